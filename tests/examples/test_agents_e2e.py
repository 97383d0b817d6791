"""examples/agents/aggregation.py over `robot_agent --exec` in a real multi-process swarm (scripts/swarm run
--exec): six Python behaviours gather, a killed agent takes its child with it, and a child that writes NaN makes
its robot dead with a message naming the robot, while the rest of the swarm runs on; a child slower than the
liveliness lease (but within its deadline) is not taken for dead. The behaviour is described by
aggregation.json (docs/agent-protocol.md, "The descriptor file"): its states are named in world.json, the
summary and events.jsonl, its telemetry column is recorded, nothing it reports is dropped, and a parameter out of
its bounds is refused with the scenario's file:line before anything starts; `swarm sweep --exec` runs it over a
grid and judges it on its own states. Every process this test
starts is found by its command line (the run's own temporary folder) and must be gone at the end. DDS test
domains 52 and 53 (53 reused in turn; the sweep's runs pick either through SWARM_DOMAINS)."""

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
DESCRIPTOR = os.path.join(ROOT, "examples", "agents", "aggregation.json")
STATES = {0: "alone", 1: "gathering", 2: "spaced", 3: "avoiding"}
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
        shutil.copy(DESCRIPTOR, self.dir)  # beside the program: it reads its parameters' defaults there

    def tearDown(self):
        for pid in processes_mentioning(self.dir):  # only if an assertion failed first
            os.kill(pid, 9)
        shutil.rmtree(self.dir)

    def swarm(self, *args, domain, scenario=SCENARIO, code=0):
        r = helpers.swarm("run", "--scenario", scenario, "--no-pictures", "--domain", str(domain), "--out", self.out,
                          *args, build_dir=BUILD_DIR, timeout=300)
        self.assertEqual(r.returncode, code, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        if code != 0:
            self.assertFalse(os.path.exists(self.out), "a refused run started")
            return r, None
        self.assertEqual(processes_mentioning(self.dir), [], "a process of this run (an agent or a child) is left")
        with open(os.path.join(self.out, "summary.json")) as f:
            return r, json.load(f)

    def positions(self, tick, alive_only=True):
        with open(os.path.join(self.out, "robots.csv")) as f:
            return [(float(r["x"]), float(r["y"])) for r in csv.DictReader(f)
                    if int(r["tick"]) == tick and (r["alive"] == "1" or not alive_only)]

    def test_six_python_agents_gather_and_a_killed_agent_takes_its_child_along(self):
        # --expect names the descriptor's states and telemetry, checked against the file before the run.
        r, s = self.swarm("--exec", f"python3 {self.agent}", "--kill", "2@150", "--max-ticks", "500",
                          "--expect", "telemetry_mean_at_end.neighbours > 0", "--expect", "states_at_end.alone >= 0",
                          domain=helpers.test_domain(52))
        self.assertEqual(s["robots"], 6)
        self.assertEqual([d["id"] for d in s["deaths"]], [2])
        self.assertEqual(s["alive_at_end"], 5)
        self.assertEqual(s.get("command_verdicts", 0), 0, "no clamped or dropped command")
        start, end = spread(self.positions(0)), spread(self.positions(500))
        self.assertLess(end, 0.5 * start, f"the five survivors gather: spread {start:.2f} m -> {end:.2f} m")
        self.assertNotIn("WARNING", r.stderr)  # a SIGKILL is not the agent's error
        self.assert_the_descriptor_is_the_worlds(r, s)

    def assert_the_descriptor_is_the_worlds(self, r, s):
        """aggregation.json's states and telemetry are the run's: named, recorded, never dropped."""
        with open(os.path.join(self.out, "world.json")) as f:
            desc = json.load(f)["behaviour_descriptor"]
        self.assertEqual(desc["name"], "aggregation_py")
        self.assertEqual(desc["descriptor"], os.path.realpath(DESCRIPTOR))
        self.assertEqual({st["value"]: st["name"] for st in desc["states"]}, STATES)
        self.assertEqual({p["name"]: p["value"] for p in desc["params"]},
                         {"spacing": 0.45, "gain": 1.5, "obstacle": 0.35})
        self.assertEqual([t["name"] for t in desc["telemetry"]], ["neighbours"])
        self.assertEqual(set(s["states_at_end"]), set(STATES.values()))
        self.assertEqual(sum(s["states_at_end"].values()), s["alive_at_end"])
        self.assertIn("neighbours", s["telemetry_mean_at_end"])
        with open(os.path.join(self.out, "robots.csv")) as f:
            rows = list(csv.DictReader(f))
        reported = {int(row["state"]) for row in rows}
        self.assertLessEqual(reported, set(STATES))
        self.assertGreaterEqual(len(reported), 2, f"the robots report their states: {reported}")
        self.assertTrue(any(row["neighbours"] and float(row["neighbours"]) > 0 for row in rows),
                        "the telemetry column is recorded")
        with open(os.path.join(self.out, "events.jsonl")) as f:
            changes = [e for e in map(json.loads, f) if e.get("kind") == "state"]
        self.assertTrue(changes, "no state change in events.jsonl")
        for e in changes:
            self.assertEqual((e["from_name"], e["to_name"]), (STATES[e["from"]], STATES[e["to"]]))
        # Nothing the agents reported was dropped: no input_dropped count, no "out of range" anywhere.
        self.assertEqual({k: v for k, v in (s.get("input_dropped") or {}).items() if v}, {})
        logs = os.path.join(self.out, "logs")
        for name in os.listdir(logs):
            with open(os.path.join(logs, name), errors="replace") as f:
                self.assertNotIn("out of range", f.read(), name)
        self.assertNotIn("out of range", r.stderr)

    def test_a_parameter_out_of_the_descriptors_bounds_is_refused_with_file_and_line(self):
        bad = os.path.join(self.dir, "bad.yaml")
        with open(SCENARIO) as f:
            text = f.read()
        self.assertIn("params: {spacing: 0.45, gain: 1.5}", text)
        with open(bad, "w") as f:
            f.write(text.replace("params: {spacing: 0.45, gain: 1.5}", "params: {spacing: 5, gain: 1.5}"))
        line = next(i for i, t in enumerate(text.splitlines(), 1) if "params:" in t)
        r, _ = self.swarm("--exec", f"python3 {self.agent}", domain=helpers.test_domain(53), scenario=bad, code=2)
        self.assertIn(f"{bad}:{line}: behaviour.params.spacing: must be in [0.15, 3]", r.stderr)
        # A key the descriptor does not declare is refused before the run, naming those it does.
        r, _ = self.swarm("--exec", f"python3 {self.agent}", "--expect", "states_at_end.dancing >= 0",
                          domain=helpers.test_domain(53), code=2)
        self.assertIn("summary.json will have no key 'states_at_end.dancing' (under 'states_at_end': ", r.stderr)
        for name in STATES.values():
            self.assertIn(f"states_at_end.{name}", r.stderr)
        # Without --exec, or in-process, the behaviour has no controller: refused before anything starts.
        says = ("behaviour 'aggregation_py' is described by aggregation.json and has no controller: its agents run "
                "it with robot_agent --exec / swarm run --exec")
        r, _ = self.swarm(domain=helpers.test_domain(53), code=2)
        self.assertIn(says, r.stderr)
        r, _ = self.swarm("--in-process", domain=helpers.test_domain(53), code=2)
        self.assertIn(says, r.stderr)

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

    def test_a_sweep_runs_the_python_behaviour_judged_on_its_own_states(self):
        # `swarm sweep --exec`: each run as `swarm run --exec` in a free domain of this test's two (SWARM_DOMAINS).
        sweep_dir = os.path.join(self.dir, "sweep")
        domains = {"SWARM_DOMAINS": f"{helpers.test_domain(52)}-{helpers.test_domain(53)}"}
        r = helpers.swarm("sweep", "--scenario", SCENARIO, "--exec", f"python3 {self.agent}", "--seeds", "4",
                          "--kills", "none", "2@150", "--max-ticks", "300", "--expect", "states_at_end.alone <= 2",
                          "--quiet", "--out", sweep_dir, env=domains, build_dir=BUILD_DIR, timeout=300)
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        self.assertEqual(processes_mentioning(self.dir), [], "a process of the sweep (an agent or a child) is left")
        with open(os.path.join(sweep_dir, "sweep.csv")) as f:
            rows = list(csv.DictReader(f))
        self.assertEqual([(row["kills"], row["success"]) for row in rows], [("none", "1"), ("2@150", "1")])
        for row in rows:  # the behaviour's own states and telemetry are columns; the commands say how to rerun
            self.assertEqual(sum(int(row[f"states_at_end.{name}"]) for name in STATES.values()),
                             int(row["alive_at_end"]))
            self.assertNotEqual(row["telemetry_mean_at_end.neighbours"], "")
            self.assertTrue(row["command"].startswith("scripts/swarm run --scenario "), row["command"])
            self.assertIn(f"--exec 'python3 {self.agent}'", row["command"])
        self.assertEqual([row["alive_at_end"] for row in rows], ["6", "5"])  # the kill took
        # A key the descriptor does not declare: refused by the probe, before any run; a field axis: refused.
        r = helpers.swarm("sweep", "--scenario", SCENARIO, "--exec", f"python3 {self.agent}", "--seeds", "4",
                          "--expect", "states_at_end.dancing >= 0", "--out", sweep_dir + "2", env=domains,
                          build_dir=BUILD_DIR, timeout=300)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("summary.json will have no key 'states_at_end.dancing'", r.stderr)
        self.assertIn("nothing was run", r.stderr)
        r = helpers.swarm("sweep", "--scenario", SCENARIO, "--exec", f"python3 {self.agent}", "--loss", "0.1",
                          "--out", sweep_dir + "3", build_dir=BUILD_DIR, timeout=60)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--loss with --exec", r.stderr)


if __name__ == "__main__":
    unittest.main()
