"""A dict spec becomes TOML text that reads back to the same values (Python's own tomllib as the
reader), so a dict and the file written from it are the same spec."""
import pathlib
import tomllib
import unittest

import numpy as np

import common
import tricot


class DictToToml(unittest.TestCase):
    def test_values_round_trip_exactly(self):
        spec = {
            "law": {"type": "mooney_rivlin",
                    "mooney_rivlin": {"terms": ["C10", "C03"], "values": [0.1 + 0.2, 1 / 3]}},
            "mesh": {"nx": 7, "grading": 2.0 ** -40, "big": 6.02214076e23, "tiny": 5e-324},
            "experiment": {"dir": pathlib.Path("some/dir"), "flag": True, "quoted": 'a "b"\n c'},
            "test": [{"name": "a", "loads": np.array([1.5, 2.25])}, {"name": "b", "steps": np.int64(3)}],
        }
        back = tomllib.loads(tricot.to_toml(spec))
        self.assertEqual(back["law"]["mooney_rivlin"]["values"], [0.1 + 0.2, 1 / 3])
        self.assertEqual(back["mesh"], {"nx": 7, "grading": 2.0 ** -40, "big": 6.02214076e23, "tiny": 5e-324})
        self.assertEqual(back["experiment"], {"dir": "some/dir", "flag": True, "quoted": 'a "b"\n c'})
        self.assertEqual(back["test"], [{"name": "a", "loads": [1.5, 2.25]}, {"name": "b", "steps": 3}])
        self.assertIsInstance(back["mesh"]["nx"], int)

    def test_print_config_is_the_clis(self):
        text = tricot.print_config("identify")
        self.assertIn("[identify]", text)
        self.assertIn("epsilon", text)
        _, out, _ = common.cli("identify", "--print-config")
        self.assertEqual(out.strip(), text.strip())
        with self.assertRaises(tricot.ConfigError):
            tricot.print_config("nope")


if __name__ == "__main__":
    unittest.main(verbosity=2)
