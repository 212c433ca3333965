"""tricot.synth, tricot.simulate and tricot.identify from dict specs equal `tricot VERB` on the same
spec written as TOML (tricot.to_toml), bit for bit; the result's arrays are result.json's numbers."""
import json
import os
import unittest

import numpy as np

import common
import tricot


class PythonEqualsCli(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = common.scratch("identify")
        cls.experiment = os.path.join(cls.dir, "experiment")
        cls.synth = tricot.synth(common.EXPERIMENT, cls.experiment)

    def test_synth_writes_what_the_cli_writes(self):
        toml = os.path.join(self.dir, "experiment.toml")
        with open(toml, "w") as f:
            f.write(tricot.to_toml(common.EXPERIMENT))
        cli_dir = os.path.join(self.dir, "experiment-cli")
        common.cli("synth", toml, "-o", cli_dir, "-q")
        for name in ("forces.csv", "field.csv"):
            with open(os.path.join(cli_dir, "tension", name)) as a, \
                 open(os.path.join(self.experiment, "tension", name)) as b:
                self.assertEqual(a.read(), b.read(), name)
        self.assertEqual(self.synth.truth, {"C10": 0.1, "C20": -0.025, "C21": 0.015, "C03": 0.01})
        forces = self.synth.tests["tension"]["forces"]
        self.assertEqual(list(forces["step"]), list(range(1, 9)))
        # force control: the load of step k is k/8 of load_max (20 N on the full strip)
        np.testing.assert_array_equal(forces["load"], np.arange(1, 9) * 20.0 / 8)

    def test_simulate_equals_the_cli(self):
        toml = os.path.join(self.dir, "case.toml")
        with open(toml, "w") as f:
            f.write(tricot.to_toml(common.CASE))
        cli_dir = os.path.join(self.dir, "simulate-cli")
        common.cli("simulate", toml, "-o", cli_dir, "-q", "--no-vtu")
        r = tricot.simulate(common.CASE, os.path.join(self.dir, "simulate-py"), vtu=False)
        with open(os.path.join(cli_dir, "tension", "steps.csv")) as f:
            header = f.readline().strip().split(",")
            rows = np.array([[float(c) for c in line.strip().split(",")] for line in f if line.strip()])
        steps = r.tests["tension"]["steps"]
        for k, column in enumerate(header):
            np.testing.assert_array_equal(steps[column], rows[:, k], column)
        self.assertEqual(r.failures, [])

    def test_identify_equals_the_cli_bit_for_bit(self):
        spec = common.project(self.experiment)
        toml = os.path.join(self.dir, "project.toml")
        with open(toml, "w") as f:
            f.write(tricot.to_toml(spec))
        cli_dir = os.path.join(self.dir, "identify-cli")
        common.cli("identify", toml, "-o", cli_dir, "-q", "--no-plots")
        py_dir = os.path.join(self.dir, "identify-py")
        r = tricot.identify(spec, py_dir, plots=False)
        cli = common.result_numbers(os.path.join(cli_dir, "result.json"))
        self.assertEqual(common.result_numbers(os.path.join(py_dir, "result.json")), cli)
        # the arrays are result.json's numbers, exactly
        self.assertEqual(r.names, ["C10", "C20", "C21", "C03"])
        self.assertEqual(list(r.parameters), [cli["parameters"][n] for n in r.names])
        self.assertEqual(list(r.std_error), [cli["std_error"][n] for n in r.names])
        np.testing.assert_array_equal(r.correlation, np.array(cli["correlation"]))
        self.assertEqual((r.objective, r.iterations, r.evaluations, r.termination),
                         (cli["objective"], cli["iterations"], cli["evaluations"], cli["termination"]))
        self.assertTrue(r.converged)
        # the covariance is the std errors' square on its diagonal and the correlation off it
        np.testing.assert_allclose(np.sqrt(np.diag(r.covariance)), r.std_error, rtol=1e-12)
        np.testing.assert_allclose(r.covariance / np.outer(r.std_error, r.std_error), r.correlation, rtol=1e-9, atol=1e-12)
        # history: history.csv's rows; its last entry is the answer
        self.assertEqual(r.history["parameters"].shape, (len(r.history["objective"]), 4))
        np.testing.assert_array_equal(r.history["parameters"][-1], r.parameters)
        # f as Ceres's cost at that iteration: the same sum of squares to its last bits (another order)
        np.testing.assert_allclose(r.history["objective"][-1], r.objective, rtol=1e-12)
        # the noise-free synthetic truth on its own mesh is f's minimum. LM stops on its step (δ = 1e-5)
        # short of it: C03, the least identifiable coefficient, 1.1e-4 relative off; 1e-3 leaves room
        truth = np.array([r.truth[n] for n in r.names])
        np.testing.assert_allclose(r.parameters, truth, rtol=1e-3)
        # the fit: model and measured grip displacement per step of the test
        fit = r.fits["tension"]
        self.assertEqual(len(fit["step"]), 8)
        np.testing.assert_allclose(fit["model_edge_displacement"], fit["edge_displacement"], rtol=1e-5)


if __name__ == "__main__":
    unittest.main(verbosity=2)
