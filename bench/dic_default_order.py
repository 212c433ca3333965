#!/usr/bin/python3
# The `tricot dic` figures of docs/validation.md that depend on [dic] order, measured for each order given
# (issue 16: `order = "auto"` became the default; docs/validation.md §3 and §7). For each ORDER it runs, at step 10 with everything else at its default:
#   - Sample 15: reference.tif -> p200_k{50,100,200,400}_n2.tif, reference mode: points ok, mean ZNCC, RMS v
#     error against command.csv read at the deformed row (../shared/data/README.md), RMS u, CPU per frame;
#   - Sample 14: sample14_reference -> l1, l3, l5, reference mode: ok, mean ZNCC, RMS v, mean |u| at x < 100;
#   - the star pair, incremental: ok, mean ZNCC, max |v|, RMS u;
#   - the tension series utn_00 -> 30, 35, 40, 45 %: one step each (reference mode) and incremental: ok of
#     the textured points (frame 0's ok), median exx against the nominal ½((1 + s)² − 1), its spread (IQR).
# CPU is user + sys of the `tricot dic` processes (2 threads unless OMP_NUM_THREADS says otherwise).
# Usage: dic_default_order.py TRICOT OUT_DIR ORDER...    e.g. dic_default_order.py build/tricot /tmp/ord first auto
import numpy as np, os, subprocess, sys

tricot, out = sys.argv[1], sys.argv[2]
data = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'shared', 'data')
if not os.path.isdir(data): data = '/work/shared/data'
os.makedirs(out, exist_ok=True)
rms = lambda a: float(np.sqrt(np.mean(a * a)))


def run(tag, order, mode, images):
    d = os.path.join(out, '%s_%s_%s' % (tag, order, mode))
    cfg = d + '.toml'
    open(cfg, 'w').write('[dic]\nmode = "%s"\norder = "%s"\nstep = 10\n[output]\noverlays = false\nfields = false\n'
                         % (mode, order))
    t0 = os.times()
    subprocess.run([tricot, 'dic', cfg, '-q', '-o', d] + images, check=True, stdout=subprocess.DEVNULL)
    t1 = os.times()
    cpu = (t1.children_user - t0.children_user) + (t1.children_system - t0.children_system)
    rows = [l.split(',') for l in open(os.path.join(d, 'points.csv')).read().splitlines()[1:]]
    frames = [l.split(',') for l in open(os.path.join(d, 'frames.csv')).read().splitlines()[1:]]
    return rows, frames, cpu


def frame(rows, k):
    """x0, y0, u, v, exx of the ok points of frame k, and the count of its rows."""
    sel = [r for r in rows if r[0] == str(k)]
    ok = [r for r in sel if r[9] == 'ok']
    a = np.array([[float(r[2]), float(r[3]), float(r[6]), float(r[7]), float(r[10]) if r[10] else np.nan] for r in ok])
    return a, len(sel)


for order in sys.argv[3:]:
    s15 = os.path.join(data, 'dic-challenge-15')
    table = np.loadtxt(os.path.join(s15, 'command.csv'), delimiter=',')
    ks = ['50', '100', '200', '400']
    rows, frames, cpu = run('s15', order, 'reference', [os.path.join(s15, 'reference.tif')] +
                            [os.path.join(s15, 'p200_k%s_n2.tif' % k) for k in ks])
    for i, k in enumerate(ks):
        a, n = frame(rows, i + 1)
        col = [50, 100, 150, 200, 250, 300, 350, 400].index(int(k)) + 1
        e = a[:, 3] - np.interp(a[:, 1] + a[:, 3], table[:, 0], table[:, col])
        tz = (a[:, 1] >= 300) & (a[:, 1] <= 600)
        print('%-5s sample15 K%-3s ok %5d/%d  mean ZNCC %s  RMS v %.4f (300-600 px %.4f, outside %.4f)  RMS u %.4f'
              % (order, k, len(a), n, frames[i + 1][5], rms(e), rms(e[tz]), rms(e[~tz]), rms(a[:, 2])))
    print('%-5s sample15 CPU %.2f s for 4 frames (%.2f s per frame, decode and writing included)' % (order, cpu, cpu / 4))
    s14 = os.path.join(data, 'dic-challenge-14')
    rows, frames, cpu = run('s14', order, 'reference', [os.path.join(s14, 'sample14_%s.tif' % n)
                                                        for n in ['reference', 'l1', 'l3', 'l5']])
    for i, n in enumerate(['l1', 'l3', 'l5']):
        a, m = frame(rows, i + 1)
        print('%-5s sample14 %s ok %5d/%d  mean ZNCC %s  RMS v %.4f  mean |u| x<100 %.4f  max |u| %.4f'
              % (order, n, len(a), m, frames[i + 1][5], rms(a[:, 3]), np.abs(a[a[:, 0] < 100, 2]).mean(),
                 np.abs(a[:, 2]).max()))
    st = os.path.join(data, 'dic-challenge-star')
    rows, frames, cpu = run('star', order, 'incremental', [os.path.join(st, 'star_%s_noisy.tif' % n)
                                                           for n in ['reference', 'deformed']])
    a, m = frame(rows, 1)
    print('%-5s star ok %5d/%d  mean ZNCC %s  max |v| %.4f  RMS u %.4f' % (order, len(a), m, frames[1][5],
                                                                          np.abs(a[:, 3]).max(), rms(a[:, 2])))
    te = os.path.join(data, 'synthetic-tension')
    imgs = [os.path.join(te, 'utn_%s.png' % n) for n in ['00', '30', '35', '40', '45']]
    for mode in ['reference', 'incremental']:
        rows, frames, cpu = run('tension', order, mode, imgs)
        textured = int(frames[0][3])
        for i, s in enumerate([30, 35, 40, 45]):
            a, m = frame(rows, i + 1)
            exx = a[:, 4][np.isfinite(a[:, 4])]
            q1, med, q3 = np.percentile(exx, [25, 50, 75])
            print('%-5s tension %-11s %d %%: ok %d of %d textured (%.2f %%)  median exx %.5f (nominal %.5f)  IQR %.5f'
                  % (order, mode, s, len(a), textured, 100.0 * len(a) / textured, med, 0.5 * ((1 + s / 100) ** 2 - 1),
                     q3 - q1))
        print('%-5s tension %-11s CPU %.2f s for 4 frames' % (order, mode, cpu))
    sys.stdout.flush()
