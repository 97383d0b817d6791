"""scripts/swarm against the real world_server and robot_agent (BUILD_DIR): a short random-walk run writes a
run directory the reader and the pictures take back, a scheduled --kill is recorded as a death, and no process
is left behind. Each test has its own DDS domain and every wait a deadline."""

import json
import os
import shutil
import tempfile
import unittest

import helpers
from swarmform import recording

SCENARIO = os.path.join(helpers.HERE, "data", "walk4.yaml")
BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")


def processes_mentioning(text):
    """pids of live processes whose command line contains `text` (our run directory: nobody else's)."""
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/cmdline", "rb") as f:
                    if text.encode() in f.read() and helpers.pid_alive(int(entry)):
                        found.append(int(entry))
            except OSError:
                pass
    return found


@unittest.skipUnless(os.access(os.path.join(BUILD_DIR, "world_server", "world_server"), os.X_OK),
                     f"world_server is not built in {BUILD_DIR}")
class LauncherEndToEndTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-e2e-")
        self.out = os.path.join(self.dir, "run")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def run_swarm(self, *extra, domain):
        r = helpers.swarm("run", "--scenario", SCENARIO, "--robots", "4", "--max-ticks", "100", "--no-pictures",
                          "--domain", str(domain), "--out", self.out, *extra, build_dir=BUILD_DIR, timeout=180)
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        self.assertNotIn("Traceback", r.stderr)
        with open(os.path.join(self.out, "agents.json")) as f:
            pids = {int(k): v for k, v in json.load(f).items()}
        self.assertEqual(sorted(pids), [0, 1, 2, 3])
        self.assertEqual([p for p in pids.values() if helpers.pid_alive(p)], [], "agents left running")
        self.assertEqual(processes_mentioning(self.out), [], "a process of this run is left running")
        return r

    def test_run_writes_a_run_directory_that_reads_back_and_draws(self):
        r = self.run_swarm(domain=150)
        self.assertIn("4 robot agents", r.stderr)
        rec = recording.load(self.out)
        self.assertEqual(rec.warnings, [])
        self.assertEqual(rec.track.robots, 4)
        self.assertEqual(int(rec.track.ticks[0]), 0)
        self.assertEqual(int(rec.track.ticks[-1]), 100)
        self.assertEqual(rec.summary["robots"], 4)
        self.assertEqual(rec.summary["ticks"], 100)
        self.assertEqual(rec.summary["alive_at_end"], 4)
        self.assertTrue(rec.track.alive.all())
        moved = abs(rec.track.x[-1] - rec.track.x[0]) + abs(rec.track.y[-1] - rec.track.y[0])
        self.assertTrue((moved > 0.01).all(), "every random walker moves")
        replay = helpers.swarm("replay", self.out, "--no-animation")
        self.assertEqual(replay.returncode, 0, replay.stderr)
        self.assertTrue(os.path.exists(os.path.join(self.out, "pictures", "trajectories.png")))
        report = helpers.swarm("report", self.out)
        self.assertEqual(report.returncode, 0, report.stderr)
        self.assertIn("alive at end               4 / 4", report.stdout)

    def test_scheduled_kill_is_recorded_as_a_death(self):
        self.run_swarm("--kill", "1@50", domain=151)
        rec = recording.load(self.out)
        self.assertEqual([d["id"] for d in rec.summary["deaths"]], [1])
        tick = rec.summary["deaths"][0]["tick"]
        self.assertTrue(50 <= tick <= 65, f"death recorded at tick {tick}: within the 1 s lease of tick 50")
        self.assertIn(1, [e.get("id") for e in rec.events if e["kind"] == "death"])
        self.assertFalse(rec.track.alive[-1, 1])
        self.assertTrue(rec.track.alive[-1, [0, 2, 3]].all())
        self.assertEqual(rec.summary["alive_at_end"], 3)


if __name__ == "__main__":
    unittest.main()
