"""scripts/swarm against the real world_server and robot_agent (BUILD_DIR): a short random-walk run writes a
run directory the reader and the pictures take back, a scheduled --kill is recorded as a death, and no process
is left behind. Each test has its own DDS domain (the full-disk test shares the first one's: the module's tests
run one at a time) and every wait a deadline."""

import json
import os
import re
import shutil
import signal
import subprocess
import tempfile
import time
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
        r = self.run_swarm(domain=helpers.test_domain(23))
        self.assertIn("4 robot agents", r.stderr)
        self.assertNotIn("without success", r.stderr, "a random walk has no judge of its own (success null)")
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

    def test_a_run_that_uses_up_max_ticks_says_so_on_its_last_line(self):
        r = helpers.swarm("run", "--in-process", "--scenario", os.path.join(helpers.ROOT, "scenarios", "paper.yaml"),
                          "--max-ticks", "100", "--no-pictures", "--out", self.out, build_dir=BUILD_DIR,
                          timeout=180)
        self.assertEqual(r.returncode, 0, r.stderr)
        last = r.stderr.strip().splitlines()[-1]
        self.assertTrue(last.startswith("swarm: ended at tick 100 without success: outcome not_formed"), last)

    def test_scheduled_kill_is_recorded_as_a_death(self):
        self.run_swarm("--kill", "1@50", domain=helpers.test_domain(24))
        rec = recording.load(self.out)
        self.assertEqual([d["id"] for d in rec.summary["deaths"]], [1])
        tick = rec.summary["deaths"][0]["tick"]
        self.assertTrue(50 <= tick <= 65, f"death recorded at tick {tick}: within the 1 s lease of tick 50")
        self.assertIn(1, [e.get("id") for e in rec.events if e["kind"] == "death"])
        self.assertFalse(rec.track.alive[-1, 1])
        self.assertTrue(rec.track.alive[-1, [0, 2, 3]].all())
        self.assertEqual(rec.summary["alive_at_end"], 3)

    def test_a_full_disk_keeps_the_runs_outcome_and_every_message_names_its_file(self):
        # A real full disk: --out on a 2 MiB tmpfs this test mounts with ~500 KB left (removed whatever happens).
        # The run fills it (robots.csv), the world ends it with disk_full, and the outcome is kept: summary.json
        # goes into the room the world reserved for it at the start. The launcher's own copy of the world's lines
        # fails too: said once with its file, the run's end still its own. Before: no summary.json at all, and
        # the launcher's line named no file. Domain 23, as the first test (this module's tests run one at a time).
        if os.geteuid() != 0:
            self.skipTest("mounting a small tmpfs needs root")
        small = os.path.join(self.dir, "small")
        os.makedirs(small)
        subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", small], check=True, timeout=30)
        try:
            st = os.statvfs(small)
            with open(os.path.join(small, "filler"), "wb") as f:
                f.write(b"\0" * (st.f_bavail * st.f_frsize - 500 * 1024))
            out = os.path.join(small, "run")
            r = helpers.swarm("run", "--scenario", SCENARIO, "--robots", "4", "--max-ticks", "1000000",
                              "--no-pictures", "--domain", str(helpers.test_domain(23)), "--out", out,
                              build_dir=BUILD_DIR, timeout=180)
            self.assertEqual(r.returncode, 5, r.stderr)
            self.assertNotIn("Traceback", r.stderr)
            with open(os.path.join(out, "summary.json"), encoding="utf-8") as f:
                summary = json.load(f)
            self.assertEqual(summary["end_reason"], "disk_full")
            self.assertGreater(summary["ticks"], 100)
            self.assertEqual(len(summary["trajectory_sha256"]), 64)
            full = [line for line in r.stderr.splitlines() if "No space left on device" in line]
            self.assertTrue(full, r.stderr)
            for line in full:
                self.assertRegex(line, re.escape(out) + r"/[^ :]+: (cannot write: )?No space left on device", line)
            ended = [line for line in r.stderr.splitlines() if line.startswith("swarm: the run ended (disk_full)")]
            self.assertEqual(len(ended), 1, r.stderr)
            self.assertRegex(ended[0], r"world_server exit 5 at tick \d+: " + re.escape(out) +
                             r"/[a-z_.]+: cannot write: No space left on device; the outcome is in " +
                             re.escape(os.path.join(out, "summary.json")))
            with open(os.path.join(out, "agents.json")) as f:
                pids = list(json.load(f).values())
            self.assertEqual([x for x in pids if helpers.pid_alive(x)], [])
            self.assertEqual(processes_mentioning(out), [])
        finally:
            subprocess.run(["umount", "-l", small], timeout=30)

    def start_long_run(self, domain):
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=BUILD_DIR)
        p = subprocess.Popen([helpers.SWARM, "run", "--scenario", SCENARIO, "--robots", "4", "--max-ticks",
                              "1000000", "--no-pictures", "--domain", str(domain), "--out", self.out], env=env,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        # Running once the recording has rows past tick 20 (the agents connected, the world stepping).
        ok = wait_for(lambda: os.path.exists(os.path.join(self.out, "robots.csv")) and
                      os.path.getsize(os.path.join(self.out, "robots.csv")) > 4 * 20 * 40, 60.0)
        if not ok:
            p.kill()
            out, err = p.communicate(timeout=30)
            self.fail(f"the run did not start within 60 s:\n{err}")
        return p

    def test_ctrl_c_closes_the_recording_and_leaves_nothing(self):
        p = self.start_long_run(domain=helpers.test_domain(25))
        with open(os.path.join(self.out, "agents.json")) as f:
            pids = list(json.load(f).values())
        p.send_signal(signal.SIGINT)
        _, err = p.communicate(timeout=60)
        self.assertEqual(p.returncode, 130, err)
        self.assertTrue(os.path.exists(os.path.join(self.out, "summary.json")), "the world wrote its summary")
        rec = recording.load(self.out)
        self.assertGreater(len(rec.track.ticks), 20)
        self.assertEqual([x for x in pids if helpers.pid_alive(x)], [])
        self.assertEqual(processes_mentioning(self.out), [])

    def test_swarm_kill_kills_an_agent_and_the_world_records_it(self):
        p = self.start_long_run(domain=helpers.test_domain(26))
        try:
            r = helpers.swarm("kill", "2", "--run", self.out, build_dir=BUILD_DIR)
            self.assertEqual(r.returncode, 0, r.stderr)
            deaths = os.path.join(self.out, "events.jsonl")
            self.assertTrue(wait_for(lambda: '"kind":"death","id":2' in read_text(deaths).replace(" ", ""), 20.0),
                            "death of robot 2 recorded within the deadline")
        finally:
            p.send_signal(signal.SIGINT)
            p.communicate(timeout=60)
        self.assertEqual(p.returncode, 130)
        self.assertEqual(processes_mentioning(self.out), [])

    def test_two_concurrent_runs_without_domain_pick_their_own_and_both_complete(self):
        # Two `swarm run` at once on one host, no --domain. Each picks a free domain (here
        # within this build's test window, SWARM_DOMAINS), says which, and only its own agents join its world.
        lo, hi = helpers.test_domain(38), helpers.test_domain(39)
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=BUILD_DIR, SWARM_DOMAINS=f"{lo}-{hi}")
        outs = [os.path.join(self.dir, f"run{i}") for i in range(2)]
        procs = [subprocess.Popen([helpers.SWARM, "run", "--scenario", SCENARIO, "--robots", "4", "--max-ticks",
                                   "3000", "--no-pictures", "--out", out], env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.PIPE, text=True) for out in outs]
        results = []
        for p in procs:
            try:
                results.append(p.communicate(timeout=180))
            except subprocess.TimeoutExpired:
                for q in procs:
                    q.kill()
                self.fail("a concurrent run did not finish within 180 s")
        picked = []
        for p, out, (_, err) in zip(procs, outs, results):
            self.assertEqual(p.returncode, 0, err)
            self.assertNotIn("Traceback", err)
            self.assertNotIn("WARNING", err)
            m = re.search(r"swarm: DDS domain (\d+) \(free on this host", err)
            self.assertIsNotNone(m, err)
            picked.append(int(m[1]))
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            self.assertEqual(summary["alive_at_end"], 4)
            self.assertEqual(summary["ticks"], 3000)
            with open(os.path.join(out, "agents.json")) as f:
                own = {int(pid) for pid in json.load(f).values()}
            joined = {int(e["detail"].split()[1]) for e in recording.load(out).events  # "pid P (participant G)"
                      if e["kind"] == "agent_connected"}
            self.assertEqual(joined, own, "only this run's agents joined its world")
            self.assertEqual(processes_mentioning(out), [])
        self.assertEqual(sorted(picked), [lo, hi])


def read_text(path):
    with open(path) as f:
        return f.read()


def wait_for(predicate, seconds):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.1)
    return False


if __name__ == "__main__":
    unittest.main()
