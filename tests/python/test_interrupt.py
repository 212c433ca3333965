"""Ctrl-C (SIGINT) stops tricot.identify with KeyboardInterrupt, leaving its checkpoint; identify(...,
resume=True) goes on from it to the uninterrupted run's answer. Progress reaches a Python callback
while the run holds no GIL."""
import os
import signal
import threading
import time
import unittest

import common
import tricot


class InterruptThenResume(unittest.TestCase):
    def test_interrupted_identification_resumes_to_the_same_answer(self):
        d = common.scratch("interrupt")
        experiment = os.path.join(d, "experiment")
        tricot.synth(common.EXPERIMENT, experiment)
        spec = common.project(experiment)
        whole = tricot.identify(spec, os.path.join(d, "whole"), plots=False)
        self.assertGreater(whole.iterations, 3)

        out = os.path.join(d, "interrupted")
        reports = []

        def progress(stage, done, total, detail):
            reports.append((stage, done))
            if len(reports) == 3:  # as Ctrl-C would: Python's SIGINT handler runs at the next check
                os.kill(os.getpid(), signal.SIGINT)

        with self.assertRaises(KeyboardInterrupt):
            tricot.identify(spec, out, plots=False, progress=progress)
        self.assertEqual(len(reports), 3)  # stopped at the report that saw the signal
        self.assertTrue(all(stage == "identify" for stage, _ in reports))
        # nothing published, the checkpoint kept in the staging folder
        self.assertFalse(os.path.exists(os.path.join(out, "result.json")))
        self.assertTrue(os.path.exists(os.path.join(out, ".tricot-identify", "checkpoint.json")))

        resumed = tricot.identify(spec, out, plots=False, resume=True)
        self.assertEqual(list(resumed.parameters), list(whole.parameters))
        self.assertEqual(resumed.objective, whole.objective)
        self.assertEqual(resumed.iterations, whole.iterations)
        self.assertEqual(resumed.termination, whole.termination)
        self.assertEqual(common.result_numbers(os.path.join(out, "result.json"))["parameters"],
                         common.result_numbers(os.path.join(d, "whole", "result.json"))["parameters"])

    def test_the_gil_is_released_during_a_run(self):
        # A Python thread counts while identify works in C++: it advances between the run's progress
        # reports (one per LM iteration) at a good fraction of the rate it has alone. Were the GIL held
        # by the run, it would stand still there.
        d = common.scratch("gil")
        experiment = os.path.join(d, "experiment")
        tricot.synth(common.EXPERIMENT, experiment)
        counter = [0]
        stop = threading.Event()

        def count():
            while not stop.is_set():
                counter[0] += 1

        def rate(seconds):
            c0, t0 = counter[0], time.perf_counter()
            time.sleep(seconds)
            return (counter[0] - c0) / (time.perf_counter() - t0)

        t = threading.Thread(target=count)
        t.start()
        alone = rate(0.3)
        samples = []
        tricot.identify(common.project(experiment), os.path.join(d, "out"), plots=False,
                        progress=lambda *_: samples.append((time.perf_counter(), counter[0])))
        stop.set()
        t.join()
        self.assertGreater(len(samples), 2)
        (t0, c0), (t1, c1) = samples[0], samples[-1]
        during = (c1 - c0) / (t1 - t0)
        self.assertGreater(during, 0.05 * alone, f"counted {during:.0f}/s during the run, {alone:.0f}/s alone")


if __name__ == "__main__":
    unittest.main(verbosity=2)
