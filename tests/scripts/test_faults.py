"""scripts/swarmform/faults.py without real processes: on the world's `restart` event the launcher refuses ids
outside the run, starts the new agent and rewrites agents.json."""

import json
import os
import shutil
import tempfile
import unittest

import helpers  # noqa: F401  (puts scripts/ on sys.path)
from swarmform import faults


class FakePopen:
    def __init__(self, pid):
        self.pid = pid
        self.killed = False

    def poll(self):
        return 0 if self.killed else None

    def kill(self):
        self.killed = True

    def wait(self, timeout=None):
        return 0


class FakeProcs:
    def __init__(self):
        self.agents = {0: FakePopen(100), 1: FakePopen(101)}
        self.started = []

    def start_agent(self, exe, rid, domain, log_path, run_nonce=None):
        p = FakePopen(200 + rid)
        self.started.append((exe, rid, domain, os.path.basename(log_path), run_nonce))
        self.agents[rid] = p
        return p


class Lines:
    def __init__(self):
        self.lines = []

    def line(self, text):
        self.lines.append(text)


class RestarterTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-faults-")
        self.procs, self.status = FakeProcs(), Lines()
        self.r = faults.Restarter(self.procs, "/bin/agent", 7, "00000000000000ab", self.dir, self.write_agents, robots=2)

    def write_agents(self):  # as the launcher's writer does
        with open(os.path.join(self.dir, "agents.json"), "w") as f:
            json.dump({str(k): q.pid for k, q in self.procs.agents.items()}, f, indent=1)

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_a_restart_line_starts_the_agent_and_updates_agents_json(self):
        old = self.procs.agents[1]
        self.r.restart(1, 40, self.status)
        self.assertTrue(old.killed, "the old agent is made sure of")
        self.assertEqual(self.procs.started, [("/bin/agent", 1, 7, "agent-1.log", "00000000000000ab")])
        with open(os.path.join(self.dir, "agents.json")) as f:
            self.assertEqual(json.load(f), {"0": 100, "1": 201})
        self.assertEqual(self.status.lines, ["swarm: restarted agent 1 at tick 40 (pid 201)"])

    def test_an_id_outside_the_run_is_refused_with_a_message(self):
        self.r.restart(5, 40, self.status)
        self.assertEqual(self.procs.started, [])
        self.assertIn("has 2; ignored", self.status.lines[0])


if __name__ == "__main__":
    unittest.main()
