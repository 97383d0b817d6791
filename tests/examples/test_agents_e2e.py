"""examples/agents/aggregation.py over `robot_agent --exec` in a real multi-process swarm (scripts/swarm run
--exec): six Python behaviours gather, a killed agent takes its child with it, and a child that writes NaN makes
its robot dead with a message naming the robot, while the rest of the swarm runs on; a child slower than the
liveliness lease (but within its deadline) is not taken for dead. Every process this test
starts is found by its command line (the run's own temporary folder) and must be gone at the end. DDS test
domains 52 and 53 (53 reused in turn)."""

import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
import helpers  # noqa: E402

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(ROOT, "build")
EXAMPLE = os.path.join(ROOT, "examples", "agents", "aggregation.py")
SCENARIO = os.path.join(ROOT, "examples", "agents", "aggregation.yaml")

# Robot 3 writes NaN at tick 20; every robot stands still otherwise.
FAULTY = r'''
import json, os, sys
me = int(os.environ["SWARMFORM_ROBOT_ID"])
json.loads(sys.stdin.readline())
print(json.dumps({"type": "hello", "protocol": 1}), flush=True)
for line in sys.stdin:
    t = json.loads(line)["tick"]
    left = float("nan") if me == 3 and t == 20 else 0.0
    print(json.dumps({"type": "command", "tick": t, "left": left, "right": 0.0}), flush=True)
'''

# Robot 2 takes 0.9 s over each of ticks 10-12: longer than the agents' 500 ms liveliness lease, within the
# --exec deadline and the world's lockstep deadline (2 s).
SLOW = r'''
import json, os, sys, time
me = int(os.environ["SWARMFORM_ROBOT_ID"])
json.loads(sys.stdin.readline())
print(json.dumps({"type": "hello", "protocol": 1}), flush=True)
for line in sys.stdin:
    t = json.loads(line)["tick"]
    if me == 2 and t in (10, 11, 12):
        time.sleep(0.9)
    print(json.dumps({"type": "command", "tick": t, "left": 0.05, "right": 0.05, "message": "01"}), flush=True)
'''


def processes_mentioning(text):
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit() and int(entry) != os.getpid():
            try:
                with open(f"/proc/{entry}/cmdline", "rb") as f:
                    if text.encode() in f.read() and helpers.pid_alive(int(entry)):
                        found.append(int(entry))
            except OSError:
                pass
    return found


def spread(positions):
    """Mean distance of the robots from their centroid, m."""
    cx = sum(p[0] for p in positions) / len(positions)
    cy = sum(p[1] for p in positions) / len(positions)
    return sum(math.hypot(x - cx, y - cy) for x, y in positions) / len(positions)


@unittest.skipUnless(os.access(os.path.join(BUILD_DIR, "robot_agent", "robot_agent"), os.X_OK),
                     f"robot_agent is not built in {BUILD_DIR}")
class PythonAgentEndToEndTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-exec-e2e-")
        self.out = os.path.join(self.dir, "run")
        # A copy in our folder, so that every child of this run is found by its command line.
        self.agent = os.path.join(self.dir, "aggregation.py")
        shutil.copy(EXAMPLE, self.agent)

    def tearDown(self):
        for pid in processes_mentioning(self.dir):  # only if an assertion failed first
            os.kill(pid, 9)
        shutil.rmtree(self.dir)

    def swarm(self, *args, domain):
        r = helpers.swarm("run", "--scenario", SCENARIO, "--no-pictures", "--domain", str(domain), "--out", self.out,
                          *args, build_dir=BUILD_DIR, timeout=300)
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        self.assertEqual(processes_mentioning(self.dir), [], "a process of this run (an agent or a child) is left")
        with open(os.path.join(self.out, "summary.json")) as f:
            return r, json.load(f)

    def positions(self, tick, alive_only=True):
        with open(os.path.join(self.out, "robots.csv")) as f:
            return [(float(r["x"]), float(r["y"])) for r in csv.DictReader(f)
                    if int(r["tick"]) == tick and (r["alive"] == "1" or not alive_only)]

    def test_six_python_agents_gather_and_a_killed_agent_takes_its_child_along(self):
        r, s = self.swarm("--exec", f"python3 {self.agent}", "--kill", "2@150", "--max-ticks", "500",
                          domain=helpers.test_domain(52))
        self.assertEqual(s["robots"], 6)
        self.assertEqual([d["id"] for d in s["deaths"]], [2])
        self.assertEqual(s["alive_at_end"], 5)
        self.assertEqual(s.get("command_verdicts", 0), 0, "no clamped or dropped command")
        start, end = spread(self.positions(0)), spread(self.positions(500))
        self.assertLess(end, 0.5 * start, f"the five survivors gather: spread {start:.2f} m -> {end:.2f} m")
        self.assertNotIn("WARNING", r.stderr)  # a SIGKILL is not the agent's error

    def test_a_child_that_writes_nan_is_a_dead_robot_and_the_swarm_runs_on(self):
        faulty = os.path.join(self.dir, "faulty.py")
        with open(faulty, "w") as f:
            f.write(FAULTY)
        r, s = self.swarm("--exec", f"python3 {faulty}", "--max-ticks", "100", domain=helpers.test_domain(53))
        self.assertEqual([d["id"] for d in s["deaths"]], [3])
        self.assertEqual(s["alive_at_end"], 5)
        self.assertEqual(s["ticks"], 100)
        self.assertRegex(r.stderr, r"WARNING: agent 3 exited with code 6: .*robot 3: the behaviour 'python3 "
                                   r".*faulty.py' \(pid \d+\) wrote a non-finite number \(NaN or Infinity\) as its "
                                   r"command; robot 3 is dead")

    def test_a_slow_child_within_its_deadline_is_not_a_dead_robot(self):
        slow = os.path.join(self.dir, "slow.py")
        with open(slow, "w") as f:
            f.write(SLOW)
        r, s = self.swarm("--exec", f"python3 {slow}", "--max-ticks", "40", domain=helpers.test_domain(53))
        self.assertEqual((s["deaths"], s["rejoins"], s["alive_at_end"]), ([], [], 6), r.stderr)


if __name__ == "__main__":
    unittest.main()
