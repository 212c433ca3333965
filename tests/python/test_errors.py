"""Bad input raises the exception class of the CLI's exit code, carrying the CLI's one-line message."""
import os
import unittest

import common
import tricot

PREFIX = "tricot: error: "


class ErrorsAreTheClis(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = common.scratch("errors")

    def cli_line(self, *args):
        code, _, stderr = common.cli(*args, check=False)
        lines = stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, stderr)
        self.assertTrue(lines[0].startswith(PREFIX), stderr)
        return code, lines[0][len(PREFIX):]

    def test_a_value_out_of_range_in_a_file(self):
        spec = common.project(os.path.join(self.dir, "experiment"))
        spec["identify"]["epsilon"] = -1.0
        toml = os.path.join(self.dir, "bad-epsilon.toml")
        with open(toml, "w") as f:
            f.write(tricot.to_toml(spec))
        code, line = self.cli_line("identify", toml, "-o", os.path.join(self.dir, "out-cli"))
        with self.assertRaises(tricot.ConfigError) as e:
            tricot.identify(toml, os.path.join(self.dir, "out-py"))
        self.assertEqual(str(e.exception), line)
        self.assertEqual(e.exception.exit_code, code)
        self.assertEqual(code, 2)
        self.assertEqual(e.exception.key, "identify.epsilon")
        self.assertEqual(e.exception.file, toml)
        self.assertIn("identify.epsilon", line)
        self.assertIsInstance(e.exception, tricot.Error)

    def test_a_missing_file(self):
        missing = os.path.join(self.dir, "no-such-project.toml")
        code, line = self.cli_line("identify", missing, "-o", os.path.join(self.dir, "out-cli"))
        with self.assertRaises(tricot.InputFileError) as e:
            tricot.identify(missing, os.path.join(self.dir, "out-py"))
        self.assertEqual((str(e.exception), e.exception.exit_code, code), (line, 3, 3))

    def test_a_missing_experiment_folder(self):
        spec = common.project(os.path.join(self.dir, "no-such-experiment"))
        toml = os.path.join(self.dir, "no-experiment.toml")
        with open(toml, "w") as f:
            f.write(tricot.to_toml(spec))
        code, line = self.cli_line("identify", toml, "-o", os.path.join(self.dir, "out-cli"))
        with self.assertRaises(tricot.InputFileError) as e:
            tricot.identify(toml, os.path.join(self.dir, "out-py"))
        self.assertEqual((str(e.exception), e.exception.exit_code), (line, code))

    def test_an_unknown_key_in_a_dict(self):
        spec = common.project(os.path.join(self.dir, "experiment"))
        spec["identify"]["epsilom"] = 1e-12
        with self.assertRaises(tricot.ConfigError) as e:
            tricot.identify(spec, os.path.join(self.dir, "out-dict"))
        msg = str(e.exception)
        self.assertTrue(msg.startswith("<dict>:"), msg)
        self.assertIn("epsilom", msg)
        self.assertIn("epsilon", msg)  # the reader's "did you mean"
        self.assertEqual(e.exception.exit_code, 2)
        self.assertNotIn("\n", msg)

    def test_a_value_toml_cannot_hold(self):
        with self.assertRaises(tricot.ConfigError) as e:
            tricot.to_toml({"mesh": {"nx": object()}})
        self.assertIn("mesh.nx", str(e.exception))

    def test_an_output_folder_that_is_a_file(self):
        f = os.path.join(self.dir, "a-file")
        open(f, "w").close()
        code, line = self.cli_line("simulate", os.path.join(common.SOURCE, "examples/uniaxial-mooney/case.toml"), "-o", f)
        with self.assertRaises(tricot.InputFileError) as e:
            tricot.simulate(os.path.join(common.SOURCE, "examples/uniaxial-mooney/case.toml"), f)
        self.assertEqual((str(e.exception), e.exception.exit_code), (line, code))

    def test_not_converged_is_exit_code_4_with_the_result(self):
        experiment = os.path.join(self.dir, "experiment")
        tricot.synth(common.EXPERIMENT, experiment)
        spec = common.project(experiment)
        spec["identify"]["max_iterations"] = 1
        toml = os.path.join(self.dir, "one-iteration.toml")
        with open(toml, "w") as f:
            f.write(tricot.to_toml(spec))
        code, _, _ = common.cli("identify", toml, "-o", os.path.join(self.dir, "one-cli"), "-q", "--no-plots", check=False)
        with self.assertRaises(tricot.NotConvergedError) as e:
            tricot.identify(toml, os.path.join(self.dir, "one-py"), plots=False)
        self.assertEqual((e.exception.exit_code, code), (4, 4))
        self.assertEqual(e.exception.result.termination, "max_iterations")
        self.assertFalse(e.exception.result.converged)
        r = tricot.identify(toml, os.path.join(self.dir, "one-py"), plots=False, check=False)
        self.assertEqual(list(r.parameters), list(e.exception.result.parameters))


if __name__ == "__main__":
    unittest.main(verbosity=2)
