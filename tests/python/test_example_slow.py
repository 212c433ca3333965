"""examples/uniaxial-mooney (the paper's Table 1 case, 2218 dofs, 35 steps) identified from Python
equals `tricot identify` on the same project file, bit for bit (result.json's numbers)."""
import os
import shutil
import unittest

import common
import tricot


class ExampleEqualsCli(unittest.TestCase):
    def test_uniaxial_mooney_project(self):
        d = common.scratch("example")
        example = os.path.join(common.SOURCE, "examples", "uniaxial-mooney")
        for f in ("experiment.toml", "project.toml"):
            shutil.copy(os.path.join(example, f), d)
        project = os.path.join(d, "project.toml")
        common.cli("synth", os.path.join(d, "experiment.toml"), "-o", os.path.join(d, "experiment"), "-q")
        common.cli("identify", project, "-o", os.path.join(d, "cli"), "-q", "--no-plots")
        r = tricot.identify(project, os.path.join(d, "py"), plots=False)
        cli = common.result_numbers(os.path.join(d, "cli", "result.json"))
        self.assertEqual(common.result_numbers(os.path.join(d, "py", "result.json")), cli)
        self.assertEqual(list(r.parameters), [cli["parameters"][n] for n in r.names])
        self.assertEqual(list(r.std_error), [cli["std_error"][n] for n in r.names])
        self.assertEqual((r.objective, r.iterations), (cli["objective"], cli["iterations"]))
        with open(os.path.join(d, "cli", "history.csv")) as a, open(os.path.join(d, "py", "history.csv")) as b:
            self.assertEqual(a.read(), b.read())


if __name__ == "__main__":
    unittest.main(verbosity=2)
