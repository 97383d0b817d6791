"""Judging a behaviour that is not the paper, through `scripts/swarm` with the real build: the dispersion plug-in
(no judge of its own) swept and judged by its own summary keys, --expect keys checked before anything runs, `swarm
run --param`, and the same refusal (exit 2, the same reason) for the same mistake whichever way a run goes
(multi-process or --in-process); the summary keys an experiment declares (the paper's, the aggregation plug-in's)
accepted by --expect before anything runs. No test here starts a DDS process: a multi-process run that is refused
is refused before its world starts (`world_server --check`, whose summary_template has every key the run's
summary.json will have).

Run by ctest (label examples) with BUILD_DIR, DISPERSION_DIR and AGGREGATION_DIR set."""

import csv
import json
import os
import shutil
import subprocess
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(HERE)))
SWARM = os.path.join(ROOT, "scripts", "swarm")
SCENARIO = os.path.join(ROOT, "examples", "behaviours", "dispersion", "dispersion.yaml")
PLUGIN_DIR = os.environ.get("DISPERSION_DIR", "")
AGGREGATION_DIR = os.environ.get("AGGREGATION_DIR", "")
AGGREGATION = os.path.join(ROOT, "examples", "behaviours", "aggregation", "aggregation.yaml")
PAPER = os.path.join(ROOT, "scenarios", "paper.yaml")


def swarm(*args, timeout=240):
    env = dict(os.environ, SWARM_NO_BUILD="1", PYTHONDONTWRITEBYTECODE="1")
    return subprocess.run([SWARM, *args], capture_output=True, text=True, timeout=timeout, env=env, cwd=ROOT)


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@unittest.skipUnless(os.environ.get("BUILD_DIR") and PLUGIN_DIR, "needs BUILD_DIR and DISPERSION_DIR (ctest)")
class JudgingTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-judging-")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def sweep(self, out, *args):
        return swarm("sweep", "--scenario", SCENARIO, "--plugin-dir", PLUGIN_DIR, "--seeds", "1-2",
                     "--param", "spacing=0.8,1.2", "--max-ticks", "300", "--jobs", "2", "--quiet",
                     "--out", os.path.join(self.dir, out), *args)

    def test_a_sweep_judges_a_plugin_by_its_own_outcome_and_keys(self):
        # No judge of its own (outcome none): a clean run succeeds; its states, telemetry and parameters are
        # columns, and the table shows them instead of the paper's formation and goal.
        r = self.sweep("plain")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        rows = read_csv(os.path.join(self.dir, "plain", "sweep.csv"))
        self.assertEqual(len(rows), 4)
        for row in rows:
            self.assertEqual((row["success"], row["outcome"], row["reason"]), ("1", "none", ""), row)
            self.assertEqual(float(row["params.spacing"]), float(row["param_spacing"]))
            counts = sum(int(row[f"states_at_end.{s}"]) for s in ("spreading", "settled"))
            self.assertEqual(counts, 12, "every robot in one of the behaviour's states")
            self.assertEqual(row.get("stuck_robots", ""), "", "no experiment of its own: nobody is stuck")
        self.assertIn("states_at_end.settled", r.stdout)
        self.assertNotIn("formed@", r.stdout)
        self.assertNotIn("goal@", r.stdout)

        # Judged by a nested key: success exactly where the key holds, every run's value in sweep.csv.
        r = self.sweep("judged", "--expect", "states_at_end.settled >= 10")
        rows = read_csv(os.path.join(self.dir, "judged", "sweep.csv"))
        verdicts = [(int(row["states_at_end.settled"]) >= 10, row["success"] == "1") for row in rows]
        self.assertEqual([v for v, _ in verdicts], [s for _, s in verdicts], rows)
        self.assertEqual(r.returncode, 0 if all(s for _, s in verdicts) else 1, r.stderr)
        for row in rows:
            if row["success"] == "0":
                self.assertIn("states_at_end.settled >= 10 failed (states_at_end.settled is", row["reason"])
        with open(os.path.join(self.dir, "judged", "sweep.json")) as f:
            res = json.load(f)
        self.assertEqual(res["judging"]["expressions"], ["states_at_end.settled >= 10"])
        self.assertIn("states_at_end.settled", res["overall"]["medians"])
        self.assertIn("states_at_end.settled", res["worst"][0]["summary"])

    def test_an_unknown_expect_key_is_refused_before_anything_runs(self):
        r = self.sweep("unknown", "--expect", "states_at_end.gathered >= 10")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("'states_at_end.gathered >= 10': summary.json will have no key 'states_at_end.gathered' "
                      "(under 'states_at_end': states_at_end, states_at_end.settled, states_at_end.spreading)",
                      r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "unknown")), "nothing was run")
        for mode in ([], ["--in-process"]):
            out = os.path.join(self.dir, "run" + "".join(mode))
            r = swarm("run", "--scenario", SCENARIO, "--plugin-dir", PLUGIN_DIR, "--no-pictures", "--out", out,
                      "--expect", "states_at_end.gathered >= 10", *mode)
            self.assertEqual(r.returncode, 2, f"{mode}: {r.stderr}")
            self.assertIn("summary.json will have no key 'states_at_end.gathered'", r.stderr)
            self.assertFalse(os.path.exists(out), f"{mode}: nothing was run")

    @unittest.skipUnless(AGGREGATION_DIR, "needs AGGREGATION_DIR (ctest)")
    def test_a_declared_experiment_summary_key_is_known_before_the_run(self):
        # An experiment's summary keys are declared (ExperimentSpec::summary): `world_server --check` prints them
        # and a summary_template holding them, so --expect takes them before anything runs (`swarm run --check`
        # runs every check a run makes and starts nothing), whatever the run will give, and refuses a misspelt one.
        for scenario, plugin, good, bad in (
                (PAPER, [], ("goal_tick <= 3000", "stuck_robot_count == 0", "shape_error_at_goal < 0.1"),
                 "goal_tik <= 3000"),
                (AGGREGATION, ["--plugin-dir", AGGREGATION_DIR], ("stragglers == 0", "behaviour_metrics.clusters <= 2"),
                 "straglers == 0")):
            name = os.path.basename(scenario)
            world = os.path.join(os.environ["BUILD_DIR"], "world_server", "world_server")
            p = subprocess.run([world, "--scenario", scenario, *plugin, "--check"], capture_output=True, text=True,
                               timeout=60)
            self.assertEqual(p.returncode, 0, p.stderr)
            info = json.loads(p.stdout.strip().splitlines()[-1])
            declared = [f["key"] for f in info["behaviour_descriptor"]["experiment"]["summary"]]
            template = list(info["summary_template"])
            self.assertLess(template.index("max_components"), template.index(declared[0]), name)
            for key in declared:
                self.assertIsNone(info["summary_template"][key], f"{name}: {key} (null before the run)")
            for mode in ([], ["--in-process"]):
                expects = [a for text in good for a in ("--expect", text)]
                r = swarm("run", "--scenario", scenario, *plugin, "--check", *expects, *mode, timeout=60)
                self.assertEqual(r.returncode, 0, f"{name} {mode}: {r.stderr}")
                self.assertIn("nothing started", r.stderr + r.stdout)
                out = os.path.join(self.dir, "declared" + "".join(mode))
                r = swarm("run", "--scenario", scenario, *plugin, "--no-pictures", "--out", out, *expects,
                          "--expect", bad, *mode, timeout=60)
                self.assertEqual(r.returncode, 2, f"{name} {mode}: {r.stderr}")
                self.assertIn(f"--expect '{bad}': summary.json will have no key '{bad.split()[0]}'", r.stderr)
                self.assertIn("(nothing was run)", r.stderr)
                self.assertFalse(os.path.exists(out), f"{name} {mode}: nothing was run")
        self.assertIn("stragglers", declared)

    def test_run_param_reaches_the_run_and_a_bad_one_is_refused_alike(self):
        out = os.path.join(self.dir, "param")
        r = swarm("run", "--in-process", "--scenario", SCENARIO, "--plugin-dir", PLUGIN_DIR, "--no-pictures",
                  "--max-ticks", "20", "--out", out, "--param", "spacing=1.2", "--param", "k_turn=3",
                  "--expect", "params.spacing == 1.2")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("expectation met: params.spacing == 1.2", r.stderr)
        with open(os.path.join(out, "summary.json")) as f:
            self.assertEqual(json.load(f)["params"]["k_turn"], 3.0)
        with open(os.path.join(out, "world.json")) as f:
            self.assertIsNone(json.load(f)["goal"], "no goal: in the scenario, none told to a behaviour without one")
        for mode in ([], ["--in-process"]):
            r = swarm("run", "--scenario", SCENARIO, "--plugin-dir", PLUGIN_DIR, "--no-pictures",
                      "--out", os.path.join(self.dir, "bad" + "".join(mode)), "--param", "spacing=99", *mode)
            self.assertEqual(r.returncode, 2, f"{mode}: {r.stderr}")
            self.assertIn("--param spacing=99", r.stderr)

    def test_a_kill_after_max_ticks_is_refused_alike(self):
        for mode in ([], ["--in-process"]):
            r = swarm("run", "--scenario", SCENARIO, "--plugin-dir", PLUGIN_DIR, "--no-pictures", "--max-ticks",
                      "200", "--kill", "3@300", "--out", os.path.join(self.dir, "kill" + "".join(mode)), *mode)
            self.assertEqual(r.returncode, 2, f"{mode}: {r.stderr}")
            self.assertIn("--kill: kill at tick 300, after the run's last tick (max_ticks 200): it would never "
                          "happen", r.stderr)

    def test_a_plugin_not_found_names_the_folders_searched_alike(self):
        scenario = os.path.join(self.dir, "elsewhere.yaml")
        shutil.copy(SCENARIO, scenario)
        for mode in ([], ["--in-process"]):
            r = swarm("run", "--scenario", scenario, "--no-pictures",
                      "--out", os.path.join(self.dir, "plugin" + "".join(mode)), *mode)
            self.assertEqual(r.returncode, 2, f"{mode}: {r.stderr}")
            self.assertIn(f"plug-in 'libdispersion.so' not found in the folders searched ({self.dir}", r.stderr)
            self.assertIn("give the folder that holds it with --plugin-dir DIR", r.stderr)


if __name__ == "__main__":
    unittest.main()
