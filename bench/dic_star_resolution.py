#!/usr/bin/python3
# Spatial resolution against noise, DIC Challenge 2.0 style (docs/validation.md §3), on
# ../shared/data/dic-challenge-star: v is a vertical sinusoid of 0.5 px amplitude whose period p grows
# along x, u = 0. For each setting it runs `tricot dic` in reference
# mode at step 4 and, column by column, fits v(y) = a cos(2πy/p) + b sin(2πy/p) + c with the period law
# p(x) fitted first from the best-resolved columns; the measured amplitude √(a² + b²) over 0.5 is the
# transfer of the displacement. Spatial resolution: the longest period at which it is below 0.9 (smoothed
# over 9 columns). Noise: the standard deviation of v about the fitted sinusoid where p >= 130 px, and of
# u (zero) there too. Writes OUT/star_resolution.dat (+ per-setting transfer curves) and, with
# gnuplot, the PNG given. Needs numpy.
# Usage: dic_star_resolution.py TRICOT OUT_DIR PNG [SETTING...]   SETTING = order:subset:weight_sigma
import numpy as np, os, subprocess, sys
tricot, out, png = sys.argv[1], sys.argv[2], sys.argv[3]
settings = sys.argv[4:] or ['first:21:0', 'first:31:0', 'first:31:6', 'first:41:8', 'second:21:0', 'second:31:0',
                            'second:41:0', 'second:51:0', 'second:41:8', 'second:51:10', 'second:61:12', 'auto:31:0']
data = '/work/shared/data/dic-challenge-star'
here = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', 'shared', 'data', 'dic-challenge-star')
if os.path.isdir(here): data = here
os.makedirs(out, exist_ok=True)
A0 = 0.5

def run(setting):
    order, subset, sigma = setting.split(':')
    d = os.path.join(out, setting.replace(':', '_'))
    if not os.path.exists(os.path.join(d, 'points.csv')):
        cfg = d + '.toml'
        open(cfg, 'w').write('[dic]\nmode = "reference"\norder = "%s"\nsubset_size = %s\nstep = 4\nweight_sigma = %s\n'
                             '[output]\noverlays = false\nfields = false\n' % (order, subset, sigma))
        subprocess.run([tricot, 'dic', cfg, '-q', '-o', d, os.path.join(data, 'star_reference_noisy.tif'),
                        os.path.join(data, 'star_deformed_noisy.tif')], check=True, stdout=subprocess.DEVNULL)
    rows = [l.split(',') for l in open(os.path.join(d, 'points.csv')).read().splitlines()[1:]]
    return np.array([[float(r[2]), float(r[3]), float(r[6]), float(r[7])] for r in rows if r[0] == '1' and r[9] == 'ok'])

def fit(y, v, p):
    M = np.column_stack([np.cos(2 * np.pi * y / p), np.sin(2 * np.pi * y / p), np.ones_like(y)])
    c, *_ = np.linalg.lstsq(M, v, rcond=None)
    return np.hypot(c[0], c[1]), v - M @ c

# The period law, from the first setting that resolves the long periods best (second order, 41 px or the
# first second-order one given): the best period per column by a scan, then a straight line through them.
def period_law(P):
    x, y, v = P[:, 0], P[:, 1], P[:, 3]
    xs, ps = [], []
    for xc in np.unique(x):
        m = x == xc
        if m.sum() < 60: continue
        cand = np.arange(20, 200, 0.25)
        r = [np.sum(fit(y[m], v[m], p)[1] ** 2) for p in cand]
        best = cand[int(np.argmin(r))]
        if fit(y[m], v[m], best)[0] > 0.35: xs.append(xc), ps.append(best)  # only well-resolved columns
    b, a = np.polyfit(xs, ps, 1)
    return a, b, len(xs)

results = {s: run(s) for s in settings}
ref = next((s for s in settings if s.startswith('second:41')), next((s for s in settings if s.startswith('second')), settings[0]))
a, b, ncols = period_law(results[ref])
print('period law fitted on %s (%d columns with amplitude > 0.35 px): p(x) = %.3f + %.5f x px' % (ref, ncols, a, b))
law = lambda x: a + b * x
table = open(os.path.join(out, 'star_resolution.dat'), 'w')
table.write('# setting order subset weight_sigma resolution_px noise_v_px noise_u_px product\n')
print('order   subset  weight_sigma  points  resolution_px(90%)  noise_v_px(p>=130)  noise_u_px(p>=130)  resolution*noise_v')
curves = []
for s in settings:
    P = results[s]
    x, y, u, v = P.T
    cols = np.unique(x)
    amp, res = [], []
    for xc in cols:
        m = x == xc
        A, r = fit(y[m], v[m], law(xc))
        amp.append(A / A0)
        if law(xc) >= 130: res.append(r)
    amp = np.convolve(amp, np.ones(9) / 9, mode='same')
    ok = np.arange(4, len(cols) - 4)
    below = [i for i in ok if amp[i] < 0.9]
    resolution = law(cols[max(below)]) if below else float('nan')
    if below and max(below) == ok[-1]: resolution = float('inf')  # never reaches 90 %
    noise_v = np.std(np.concatenate(res)) if res else float('nan')
    noise_u = np.std(u[law(x) >= 130])
    order, subset, sigma = s.split(':')
    print('%-7s %6s  %12s  %6d  %18.1f  %18.4f  %10.4f  %18.3f' % (order, subset, sigma, len(v), resolution, noise_v,
                                                                  noise_u, resolution * noise_v))
    table.write('%s %s %s %s %.2f %.5f %.5f %.4f\n' % (s.replace(':', '_'), order, subset, sigma, resolution, noise_v,
                                                       noise_u, resolution * noise_v))
    f = os.path.join(out, 'transfer_%s.dat' % s.replace(':', '_'))
    np.savetxt(f, np.column_stack([law(cols[ok]), amp[ok]]), fmt='%.4f')
    curves.append((s, f))
    sys.stdout.flush()
table.close()
label = lambda s: (lambda o, n, w: '%s %s px%s' % (o, n, '' if float(w) == 0 else ', Gauss σ %s' % w))(*s.split(':'))
colours = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2', '#7f7f7f', '#bcbd22',
           '#17becf', '#000000', '#ff1493']
style = lambda i, s: "lw 2 lc rgb '%s' dt %d" % (colours[i % len(colours)], 1 if s.startswith('second') else 2 if s.startswith('first') else 4)
plots = ', '.join("'%s' u 1:2 w l %s t '%s'" % (f, style(i, s), label(s)) for i, (s, f) in enumerate(curves))
points = ', '.join("'%s' u 5:6 every ::%d::%d w p pt 7 ps 1.6 lc rgb '%s' t '%s'" % (
    os.path.join(out, 'star_resolution.dat'), i, i, colours[i % len(colours)], label(s)) for i, (s, f) in enumerate(curves))
script = f"""
set terminal pngcairo size 1400,600 font ',11' noenhanced
set output '{png}'
set multiplot layout 1,2
set title 'Star pair: measured / imposed amplitude of v (0.5 px), step 4'
set xlabel 'period of the sinusoid (px)'; set ylabel 'amplitude ratio'
set yrange [0:1.15]; set xrange [10:150]; set grid; set key bottom right font ',9'
set arrow from 10,0.9 to 150,0.9 nohead dt 3 lc rgb 'black'
plot {plots}
unset arrow
set title 'Spatial resolution (period at 90 %) against noise (std of v where p >= 130 px)'
set xlabel 'spatial resolution (px)'; set ylabel 'noise (px)'; set xrange [0:160]; set yrange [0:0.016]
set key top right font ',9'
set samples 400
plot {points}, 0.35/x w l dt 3 lc rgb 'gray40' t 'resolution × noise = 0.35 px²', 0.6/x w l dt 2 lc rgb 'gray60' t '0.6 px²'
unset multiplot
"""
subprocess.run(['gnuplot'], input=script.encode(), check=True)
print('wrote', png)
