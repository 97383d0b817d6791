"""A mixed swarm through the launcher (scenarios/mixed_swarm.yaml, docs/scenario-format.md "Groups"), in-process
on the real build (BUILD_DIR): `--expect` on a group's keys (`groups.shapers.outcome`) is checked before the run
and judged after it, an unknown group key is refused before anything runs, and `--robots` / `--exec` are refused
naming why. The multi-process run of the same scenario is a golden run (tests/golden: `mixed_swarm`); kills in
it, one robot of each group, run with real agent processes (DDS test domain 30)."""

import json
import os
import shutil
import tempfile
import unittest

import helpers

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")
SCENARIO = os.path.join(helpers.ROOT, "scenarios", "mixed_swarm.yaml")


@unittest.skipUnless(os.access(os.path.join(BUILD_DIR, "harness", "swarm_inprocess"), os.X_OK)
                     and os.access(os.path.join(BUILD_DIR, "world_server", "world_server"), os.X_OK),
                     f"swarm_inprocess and world_server are not built in {BUILD_DIR}")
class MixedSwarmLauncherTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-groups-")
        self.out = os.path.join(self.dir, "run")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def swarm(self, *extra, timeout=300):
        return helpers.swarm("run", "--scenario", SCENARIO, "--in-process", "--no-pictures", "--out", self.out,
                             *extra, build_dir=BUILD_DIR, timeout=timeout)

    def test_group_keys_are_expected_and_judged(self):
        # The grammar reads a bare none as null: the outcome's word is quoted (expect.py).
        r = self.swarm("--expect", "groups.movers.outcome == 'none'", "--expect", "groups.movers.success == null",
                       "--expect", "groups.movers.count == 4",
                       "--expect", "groups.movers.states_at_end.walking == 4",
                       "--expect", "groups.shapers.first_id == 0",
                       "--expect", "groups.shapers.formation_tick >= 1",
                       "--expect", "groups.shapers.outcome != none")
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        for text in ("groups.movers.outcome == 'none'", "groups.shapers.formation_tick >= 1"):
            self.assertIn(f"expectation met: {text}", r.stderr)
        with open(os.path.join(self.out, "summary.json")) as f:
            summary = json.load(f)
        self.assertEqual(sorted(summary["groups"]), ["movers", "shapers"])
        with open(os.path.join(self.out, "world.json")) as f:
            world = json.load(f)
        self.assertEqual([(g["name"], g["first_id"], g["count"]) for g in world["groups"]],
                         [("shapers", 0, 8), ("movers", 8, 4)])

    def test_kills_in_a_multi_process_mixed_run_take_the_robot_of_the_global_id(self):
        # Ids are global and contiguous in group order (shapers 0-7, movers 8-11): --kill 9 is the second mover's
        # agent process, --kill 3 a shaper's. Each is killed at its tick by the pid the launcher started for that
        # id, its own group loses it, and the shape arrives with the seven left.
        r = helpers.swarm("run", "--scenario", SCENARIO, "--no-pictures", "--out", self.out,
                          "--domain", str(helpers.test_domain(30)), "--kill", "9@300", "--kill", "3@400",
                          build_dir=BUILD_DIR, timeout=300)
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        with open(os.path.join(self.out, "summary.json")) as f:
            summary = json.load(f)
        self.assertEqual(summary["deaths"], [{"id": 9, "tick": 300}, {"id": 3, "tick": 400}])
        with open(os.path.join(self.out, "agents.json")) as f:
            pids = json.load(f)
        with open(os.path.join(self.out, "events.jsonl")) as f:
            events = [json.loads(line) for line in f if line.strip()]
        kills = {(e["id"], e["tick"]): e["detail"] for e in events if e["kind"] == "kill_sent"}
        self.assertEqual(kills, {(9, 300): f"SIGKILL pid {pids['9']}", (3, 400): f"SIGKILL pid {pids['3']}"})
        movers, shapers = summary["groups"]["movers"], summary["groups"]["shapers"]
        self.assertEqual(movers["states_at_end"], {"walking": 3})
        self.assertEqual(shapers["outcome"], "arrived")
        self.assertEqual(shapers["arrived"], 7)

    def test_an_unknown_group_key_is_refused_before_the_run(self):
        r = self.swarm("--expect", "groups.dancers.outcome == none", "--expect", "groups.movers.states_at_end.x > 1",
                       timeout=120)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--expect 'groups.dancers.outcome == none': summary.json will have no key "
                      "'groups.dancers.outcome'", r.stderr)
        self.assertIn("'groups.movers.states_at_end.x > 1'", r.stderr)
        self.assertIn("(nothing was run)", r.stderr)
        self.assertFalse(os.path.exists(self.out))

    def test_a_param_names_its_group(self):
        r = self.swarm("--max-ticks", "5", "--param", "shapers.k_o=1.2", timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(self.out, "summary.json")) as f:
            self.assertEqual(json.load(f)["groups"]["shapers"]["params"]["k_o"], 1.2)
        shutil.rmtree(self.out)
        r = self.swarm("--max-ticks", "5", "--param", "movers.k_o=1.2", timeout=120)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--param movers.k_o=1.2: behaviour 'random_walk' parameter 'k_o'", r.stderr)
        r = self.swarm("--max-ticks", "5", "--param", "dancers.k_o=1.2", timeout=120)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("no robot group 'dancers' (groups: shapers, movers)", r.stderr)

    def test_robots_and_exec_are_refused_naming_the_groups(self):
        r = self.swarm("--robots", "20", timeout=120)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--robots: the scenario has groups:", r.stderr)
        r = helpers.swarm("run", "--scenario", SCENARIO, "--exec", "true", "--no-pictures", "--out", self.out,
                          build_dir=BUILD_DIR, timeout=120)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("this scenario's robots are groups of different behaviours (shapers, movers)", r.stderr)
        self.assertFalse(os.path.exists(self.out))

    def test_a_group_described_by_a_file_is_refused_naming_the_group(self):
        scenario = os.path.join(self.dir, "described.yaml")
        descriptor = os.path.join(helpers.ROOT, "examples", "agents", "aggregation.json")
        with open(scenario, "w") as f:
            f.write("groups:\n"
                    "  - {name: walkers, behaviour: random_walk, robots: {count: 3}}\n"
                    f"  - name: talkers\n    behaviour: {{descriptor: {descriptor}}}\n"
                    "    robots: {count: 3, region: {centre: [6.0, 0.0], width: 2.0, height: 2.0}}\n")
        for mode in ([], ["--in-process"]):
            r = helpers.swarm("run", "--scenario", scenario, "--no-pictures", "--out", self.out, *mode,
                              build_dir=BUILD_DIR, timeout=120)
            self.assertEqual(r.returncode, 2, f"{mode}: {r.stderr}")
            self.assertIn("group 'talkers'", r.stderr)
            self.assertFalse(os.path.exists(self.out))


if __name__ == "__main__":
    unittest.main()
