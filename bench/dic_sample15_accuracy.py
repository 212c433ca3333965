#!/usr/bin/python3
# DIC Challenge Sample 15, K50 at step 10 (issue 16, docs/validation.md §3): runs
# `tricot dic` in reference mode on reference.tif -> p200_k50_n2.tif for each setting given, and prints the
# RMS error of v against command.csv read at the deformed row y0 + v (../shared/data/README.md), over all ok
# points, over the 300-600 px transition and outside it. Needs numpy.
# Usage: dic_sample15_accuracy.py [--rows] TRICOT OUT_DIR SETTING...   with SETTING = order:subset:weight_sigma[:prefilter]
#   e.g. dic_sample15_accuracy.py build/tricot /tmp/s15 first:31:0 second:41:10
# --rows also prints, per grid row y0 of the transition (280-620 px), the mean error (bias) / its std.
import numpy as np, os, subprocess, sys
rows_wanted = '--rows' in sys.argv
argv = [a for a in sys.argv if a != '--rows']
tricot, out = argv[1], argv[2]
data = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'shared', 'data', 'dic-challenge-15')
if not os.path.isdir(data): data = '/work/shared/data/dic-challenge-15'
table = np.loadtxt(os.path.join(data, 'command.csv'), delimiter=',')
os.makedirs(out, exist_ok=True)
print('order  subset  weight_sigma  prefilter  points  rms_v_all  rms_v_300_600  rms_v_outside  rms_u  cpu_s')
for setting in argv[3:]:
    f = setting.split(':')
    order, subset, sigma = f[0], int(f[1]), float(f[2])
    pre = float(f[3]) if len(f) > 3 else 0.0
    d = os.path.join(out, setting.replace(':', '_'))
    cfg = d + '.toml'
    open(cfg, 'w').write('[dic]\nmode = "reference"\norder = "%s"\nsubset_size = %d\nstep = 10\nweight_sigma = %g\n'
                         'prefilter_sigma = %g\n[output]\noverlays = false\nfields = false\n' % (order, subset, sigma, pre))
    t0 = os.times()
    subprocess.run([tricot, 'dic', cfg, '-q', '-o', d, os.path.join(data, 'reference.tif'),
                    os.path.join(data, 'p200_k50_n2.tif')], check=True, stdout=subprocess.DEVNULL)
    t1 = os.times()
    cpu = (t1.children_user - t0.children_user) + (t1.children_system - t0.children_system)
    rows = [l.split(',') for l in open(os.path.join(d, 'points.csv')).read().splitlines()[1:]]
    p = np.array([[float(r[3]), float(r[6]), float(r[7])] for r in rows if r[0] == '1' and r[9] == 'ok'])
    y0, u, v = p[:, 0], p[:, 1], p[:, 2]
    e = v - np.interp(y0 + v, table[:, 0], table[:, 1])  # the table is indexed by the deformed row
    tz = (y0 >= 300) & (y0 <= 600)
    rms = lambda a: np.sqrt(np.mean(a * a))
    print('%-6s %6d  %12g  %9g  %6d  %9.4f  %13.4f  %13.4f  %5.4f  %5.2f' % (
        order, subset, sigma, pre, len(v), rms(e), rms(e[tz]), rms(e[~tz]), rms(u), cpu))
    if rows_wanted:
        print('  y0:bias/std ' + ' '.join('%d:%+.3f/%.3f' % (y, e[y0 == y].mean(), e[y0 == y].std())
                                         for y in np.unique(y0) if 280 <= y <= 620))
    sys.stdout.flush()
