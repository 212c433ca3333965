"""Shared by the tricot module's tests: the CLI binary, a scratch folder, a small identification."""
import json
import os
import subprocess
import tempfile

import tricot

BINARY = os.environ.get("TRICOT_BINARY", "build/tricot")
SOURCE = os.environ.get("TRICOT_SOURCE_DIR", ".")


def scratch(name):
    """A fresh folder for one test (under the ctest working folder)."""
    return tempfile.mkdtemp(prefix=name + "-", dir=os.getcwd())


def cli(*args, check=True):
    """Runs build/tricot; returns (exit code, stdout, stderr)."""
    p = subprocess.run([BINARY, *args], capture_output=True, text=True)
    if check and p.returncode != 0:
        raise AssertionError(f"tricot {' '.join(args)} exited {p.returncode}: {p.stderr}")
    return p.returncode, p.stdout, p.stderr


# The paper's generated case (examples/uniaxial-mooney) made small enough for a unit test: a
# Mooney–Rivlin strip in force-controlled tension, Q8 (4 × 12), 8 steps, noise-free. The project
# identifies on the synthesis's own mesh: the truth is then f's minimum (f = 0), a check of the answer
# rather than of the discretisation (the examples' projects use a coarser mesh).
CASE = {
    "mesh": {"width": 50.0, "height": 200.0, "element": "Q8", "nx": 4, "ny": 12},
    "law": {"type": "mooney_rivlin",
            "mooney_rivlin": {"terms": ["C10", "C20", "C21", "C03"], "values": [0.1, -0.025, 0.015, 0.01]}},
    "test": [{"name": "tension", "kind": "uniaxial", "control": "force", "grip_holds_x": True,
              "load_max": 20.0, "steps": 8}],
}
EXPERIMENT = dict(CASE, synth={"noise_relative": 0.0, "seed": 20070101, "field": True,
                               "field_kind": "cumulative", "nx": 3, "ny": 8, "inset": 1.0})


def project(experiment_dir):
    """The identification of EXPERIMENT's four coefficients from half the truth."""
    return {
        "mesh": CASE["mesh"],
        "law": {"type": "mooney_rivlin",
                "mooney_rivlin": {"terms": ["C10", "C20", "C21", "C03"],
                                  "values": [0.05, -0.0125, 0.0075, 0.005]}},
        "test": CASE["test"],
        "experiment": {"dir": experiment_dir, "field_kind": "cumulative"},
        "parameter": [{"name": n} for n in ("C10", "C20", "C21", "C03")],
        "data": {"edge_displacement": 1.0, "field": 1.0},
        "identify": {"epsilon": 1e-12, "delta": 1e-5, "jacobian": "exact"},
    }


def result_numbers(path):
    """result.json's numbers that a rerun must reproduce (wall times aside)."""
    with open(path) as f:
        r = json.load(f)
    return {k: r[k] for k in ("parameters", "std_error", "correlation", "objective", "iterations",
                              "evaluations", "termination", "message", "jacobian")}
