#!/usr/bin/env python3
"""The §4 campaign (examples/knit-campaign) identified from Python, its fit plotted with matplotlib.

    PYTHONPATH=build/python python3 examples/python/identify_knit_campaign.py [OUT]

Synthesises the campaign's experiment when examples/knit-campaign/experiment is missing (as
`tricot synth examples/knit-campaign/experiment.toml -o examples/knit-campaign/experiment`), runs
the paper14 identification of project-110.toml into OUT (default out/python-knit-110, the files of
`tricot identify`), then draws OUT/python_fit.png: per rig test the grip force per width measured and
identified against the grip displacement, the LM history, and the identified law's membrane force
along wale and course in uniaxial stretch. Ctrl-C stops the identification and keeps its checkpoint;
run the script again with --resume to go on from it.
"""
import os
import sys
import time

import numpy as np

import tricot

HERE = os.path.dirname(os.path.abspath(__file__))
CAMPAIGN = os.path.join(HERE, "..", "knit-campaign")


def progress(stage, done, total, detail):
    print(f"\r{stage}: iteration {done} {detail}"[:110].ljust(110), end="", file=sys.stderr, flush=True)


def main():
    args = [a for a in sys.argv[1:] if a != "--resume"]
    out = args[0] if args else os.path.join("out", "python-knit-110")
    experiment = os.path.join(CAMPAIGN, "experiment")
    t0 = time.perf_counter()
    if not os.path.isdir(experiment):
        print("synth: the campaign's experiment ->", experiment)
        tricot.synth(os.path.join(CAMPAIGN, "experiment.toml"), experiment, log=True)
    t1 = time.perf_counter()
    r = tricot.identify(os.path.join(CAMPAIGN, "project-110.toml"), out, resume="--resume" in sys.argv,
                        progress=progress, check=False)
    t2 = time.perf_counter()
    print(file=sys.stderr)
    print(r.brief_report())
    print(f"{'':8}{'identified':>14}{'std error':>12}")
    for name, value, se in zip(r.names, r.parameters, r.std_error):
        print(f"{name:8}{value:14.6g}{se:12.3g}")
    print(f"synth {t1 - t0:.1f} s, identify {t2 - t1:.1f} s")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tests = sorted(r.fits)
    cols = 4
    rows = (len(tests) + cols - 1) // cols + 1
    fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 3.2 * rows), squeeze=False)
    for ax, name in zip(axes.flat, tests):
        fit = r.fits[name]
        x = fit["model_edge_displacement"]
        ax.plot(x, fit["edge_force"], "o", ms=3, label="measured")
        ax.plot(x, fit["model_edge_force"], "-", label="identified")
        ax.set_title(name, fontsize=9)
        ax.set_xlabel("grip displacement (quarter), mm", fontsize=8)
        ax.set_ylabel("grip force, N", fontsize=8)
        ax.grid(True, alpha=0.3)
    axes.flat[0].legend(fontsize=8)
    for ax in list(axes.flat)[len(tests):]:
        ax.axis("off")
    # the LM history and the identified law
    h = axes[-1][0]
    h.axis("on")
    h.semilogy(r.history["iteration"], r.history["objective"], "o-", ms=3)
    h.set_xlabel("LM iteration", fontsize=8)
    h.set_ylabel("f", fontsize=8)
    h.set_title("objective", fontsize=9)
    law = tricot.Law(os.path.join(CAMPAIGN, "project-110.toml"))
    law.coefficients = dict(zip(r.names, r.parameters))
    stretch = np.linspace(1.0, 1.8, 41)
    for ax_i, (label, axis) in enumerate((("course (x)", 0), ("wale (y)", 1))):
        F = np.tile(np.eye(2), (len(stretch), 1, 1))
        F[:, axis, axis] = stretch
        P, _, _ = law.evaluate(F, tangent="none")
        a = axes[-1][1]
        a.axis("on")
        a.plot(stretch, P[:, axis, axis], label=label)
    a.set_xlabel("stretch (other side held at 1)", fontsize=8)
    a.set_ylabel("P, N/mm", fontsize=8)
    a.set_title("identified law", fontsize=9)
    a.legend(fontsize=8)
    fig.tight_layout()
    png = os.path.join(out, "python_fit.png")
    fig.savefig(png, dpi=110)
    print("->", png)


if __name__ == "__main__":
    main()
