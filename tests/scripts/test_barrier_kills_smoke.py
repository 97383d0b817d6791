"""scripts/sweep-barrier-kills against the real swarm_inprocess (BUILD_DIR): one seed, kills 20 ticks before the
barrier. Checks that every schedule kills at the barrier's tick minus 20 robots that stood at their places by then
(one or two of them), that the summary line counts the records, and that every single kill ends `arrived` (a
member killed at its place before the barrier is found dead and replaced: robot_agent/README.md, Death); bad
arguments exit 2 before any run."""

import json
import os
import subprocess
import tempfile
import unittest

import helpers

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")
EXE = os.path.join(BUILD_DIR, "harness", "swarm_inprocess")
SCRIPT = os.path.join(helpers.ROOT, "scripts", "sweep-barrier-kills")


def run(*args):
    return subprocess.run([SCRIPT, "--binary", EXE, *args], capture_output=True, text=True, timeout=240)


@unittest.skipUnless(os.access(EXE, os.X_OK), f"swarm_inprocess is not built in {BUILD_DIR}")
class BarrierKillsSmokeTest(unittest.TestCase):
    def test_one_seed(self):
        with tempfile.TemporaryDirectory(prefix="barrier-kills-") as d:
            out = os.path.join(d, "runs.json")
            r = run("--seeds", "704-704", "--before", "20", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(out) as f:
                runs = json.load(f)["runs"]
        self.assertGreaterEqual(len(runs), 6, "a schedule or two for each of the six layouts")
        for rec in runs:
            self.assertEqual(rec["before"], 20)
            self.assertIn(len(rec["kills"]), (1, 2))
            for kill in rec["kills"]:
                self.assertEqual(int(kill.split("@")[1]), rec["barrier_tick"] - 20, rec)
            if len(rec["kills"]) == 1:
                self.assertEqual(rec["outcome"], "arrived", rec)
        arrived = sum(rec["outcome"] == "arrived" for rec in runs)
        self.assertIn(f"arrived {arrived}/{len(runs)}", r.stdout)

    def test_bad_arguments(self):
        for args in (["--seeds", "9-1"], ["--before", "0"], ["--seeds", "x"]):
            r = run(*args)
            self.assertEqual(r.returncode, 2, args)
            self.assertIn("sweep-barrier-kills:", r.stderr)


if __name__ == "__main__":
    unittest.main()
