"""`swarm sweep` against the real swarm_inprocess (BUILD_DIR): a tiny sweep of the paper's scenario, 2 seeds x
2 kill schedules (none, random:1), 300 ticks. Checks the rows of sweep.csv, that the kills drawn reached the runs
(the summary's deaths are the --kill flags), that the random draw is reproducible and within its window, that
sweep.json's rates agree with the rows, and that a worst case's command reproduces its run bit for bit (the
trajectory hash). Also: a bad scenario is refused by the probe, exit 2, before any run; a plug-in behaviour is swept
with --plugin-dir (and refused without it); a --param shape_heading that turns the shape into a wall is refused;
--loss, --burst and --noise reach the runs (each combination its own trajectory) and a bad --set value is refused by
the loader, naming the flag."""

import csv
import json
import os
import shlex
import shutil
import subprocess
import tempfile
import unittest

import helpers

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")
EXE = os.path.join(BUILD_DIR, "harness", "swarm_inprocess")
# The aggregation example's plug-in, built in the build tree (examples/behaviours): not in its scenario's folder.
AGGREGATION_DIR = os.environ.get("AGGREGATION_DIR") or os.path.join(BUILD_DIR, "examples", "behaviours", "aggregation")
AGGREGATION = os.path.join(helpers.ROOT, "examples", "behaviours", "aggregation", "aggregation.yaml")
PAPER = os.path.join(helpers.ROOT, "scenarios", "paper.yaml")


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@unittest.skipUnless(os.access(EXE, os.X_OK), f"swarm_inprocess is not built in {BUILD_DIR}")
class SweepSmokeTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-sweep-smoke-")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def sweep(self, out, *extra):
        return helpers.swarm("sweep", "--scenario", PAPER, "--seeds", "1-2", "--kills", "none", "random:1",
                             "--max-ticks", "300", "--kill-window", "250", "--jobs", "2", "--expect", "any",
                             "--out", out, *extra, build_dir=BUILD_DIR, timeout=240)

    def test_tiny_sweep(self):
        out = os.path.join(self.dir, "a")
        r = self.sweep(out)
        self.assertNotIn("Traceback", r.stderr)
        self.assertIn("sweep: 4/4 done", r.stderr, "the progress line")
        rows = read_csv(os.path.join(out, "sweep.csv"))
        self.assertEqual([(row["seed"], row["kills"]) for row in rows],
                         [("1", "none"), ("2", "none"), ("1", "random:1"), ("2", "random:1")])
        for row in rows:
            self.assertEqual(row["exit_code"], "0", row["reason"])
            self.assertEqual(row["ticks"], "300", "cut at --max-ticks")
            self.assertEqual(row["robots"], "9")
            self.assertEqual(row["summary_seed"], row["seed"])
            self.assertRegex(row["trajectory_sha256"], "^[0-9a-f]{64}$")
            self.assertIn(f"--max-ticks 300", row["command"])
            if row["kills"] == "none":
                self.assertEqual(row["kill_flags"], "")
                self.assertEqual(row["deaths"], "")
                continue
            rid, tick = (int(v) for v in row["kill_flags"].split("@"))
            self.assertTrue(0 <= rid < 9 and 1 <= tick <= 250, row["kill_flags"])
            self.assertIn(f"--kill {rid}@{tick}", row["command"])
            self.assertEqual(row["deaths"], row["kill_flags"], "the world killed the robot drawn, at its tick")
            self.assertEqual(row["alive_at_end"], "8")
        self.assertEqual(r.returncode, 0 if all(row["success"] == "1" for row in rows) else 1)

        with open(os.path.join(out, "sweep.json")) as f:
            res = json.load(f)
        ok = sum(row["success"] == "1" for row in rows)
        self.assertEqual(res["overall"]["runs"], 4)
        self.assertEqual(res["overall"]["succeeded"], ok)
        self.assertEqual(res["overall"]["success_rate"], round(ok / 4, 4))
        self.assertEqual(sorted(res["by_kills"]), ["none", "random:1"])
        self.assertEqual(res["by_kills"]["random:1"]["runs"], 2)
        self.assertEqual(res["by_shape"]["triangle.txt"]["runs"], 4)
        self.assertEqual(len(res["worst"]), 4)

        # The worst case's command gives the same run, bit for bit.
        worst = res["worst"][0]
        row = rows[worst["index"]]
        self.assertEqual(worst["command"], row["command"])
        again = subprocess.run(worst["command"], shell=True, cwd=os.getcwd(), capture_output=True, text=True,
                               timeout=120)
        self.assertEqual(again.returncode, 0, again.stderr)
        self.assertEqual(json.loads(again.stdout)["trajectory_sha256"], row["trajectory_sha256"])

        # The same sweep again draws the same kills and gives the same runs.
        out2 = os.path.join(self.dir, "b")
        self.sweep(out2)
        rows2 = read_csv(os.path.join(out2, "sweep.csv"))
        self.assertEqual([r["kill_flags"] for r in rows2], [r["kill_flags"] for r in rows])
        self.assertEqual([r["trajectory_sha256"] for r in rows2], [r["trajectory_sha256"] for r in rows])

    def test_a_param_reaches_the_behaviour_and_a_bad_one_is_refused_naming_it(self):
        out = os.path.join(self.dir, "p")
        r = helpers.swarm("sweep", "--scenario", PAPER, "--seeds", "1", "--param", "k_move=0.5,1", "--max-ticks",
                          "150", "--jobs", "2", "--expect", "any", "--out", out, build_dir=BUILD_DIR, timeout=240)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = read_csv(os.path.join(out, "sweep.csv"))
        self.assertEqual([row["param_k_move"] for row in rows], ["0.5", "1"])
        self.assertNotEqual(rows[0]["trajectory_sha256"], rows[1]["trajectory_sha256"],
                            "k_move changes how the robots move to their places")
        for args, says in ((["--param", "k_wobble=1"], "--param k_wobble=1: behaviour 'paper' parameter 'k_wobble'"),
                           (["--param", "k_move=0.5,500"], "--param k_move=500: behaviour 'paper' parameter 'k_move'")):
            r = helpers.swarm("sweep", "--scenario", PAPER, "--out", os.path.join(self.dir, "q"), *args,
                              build_dir=BUILD_DIR, timeout=60)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(says, r.stderr)
            self.assertFalse(os.path.exists(os.path.join(self.dir, "q", "sweep.csv")))

    def test_loss_bursts_and_noise_reach_the_runs_and_a_bad_set_is_refused_by_the_loader(self):
        out = os.path.join(self.dir, "m")
        r = helpers.swarm("sweep", "--scenario", PAPER, "--seeds", "1", "--loss", "0.3", "--burst", "1,5", "--noise",
                          "off,on", "--max-ticks", "300", "--jobs", "2", "--expect", "any", "--out", out,
                          build_dir=BUILD_DIR, timeout=240)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = read_csv(os.path.join(out, "sweep.csv"))
        self.assertEqual([(row["burst"], row["noise"]) for row in rows],
                         [("1", "off"), ("1", "on"), ("5", "off"), ("5", "on")])
        # Each value changes the run (the messages lost, the readings perceived): four different trajectories.
        self.assertEqual(len({row["trajectory_sha256"] for row in rows}), 4)
        # A row's command reproduces it bit for bit.
        again = subprocess.run(shlex.split(rows[2]["command"]), capture_output=True, text=True, timeout=120,
                               cwd=os.getcwd())
        self.assertEqual(json.loads(again.stdout)["trajectory_sha256"], rows[2]["trajectory_sha256"])
        for args, says in ((["--set", "comm_range=2,-1"], "command line: --set 'comm_range=-1': comm_range: must be > 0"),
                           (["--set", "packet_loss=0.1,{rate: 0.5, mean_burst: 1.5}"],
                            "--set 'packet_loss={rate: 0.5, mean_burst: 1.5}': packet_loss.mean_burst: must be in [2,")):
            r = helpers.swarm("sweep", "--scenario", PAPER, "--out", os.path.join(self.dir, "n"), *args,
                              build_dir=BUILD_DIR, timeout=60)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(says, r.stderr)
            self.assertFalse(os.path.exists(os.path.join(self.dir, "n", "sweep.csv")))

    @unittest.skipUnless(os.path.exists(os.path.join(AGGREGATION_DIR, "libaggregation.so")),
                         f"the aggregation example is not built in {AGGREGATION_DIR}")
    def test_a_plugin_behaviour_is_swept_with_plugin_dir(self):
        out = os.path.join(self.dir, "agg")
        common = ("sweep", "--scenario", AGGREGATION, "--seeds", "1-2", "--max-ticks", "60", "--jobs", "2",
                  "--expect", "any", "--out", out)
        # The plug-in is not in the scenario's folder: without --plugin-dir the probe is refused naming it.
        r = helpers.swarm(*common, build_dir=BUILD_DIR, timeout=120)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("libaggregation.so", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(out, "sweep.csv")))
        r = helpers.swarm(*common, "--plugin-dir", AGGREGATION_DIR, "--param", "stop_distance=0.3,0.6",
                          build_dir=BUILD_DIR, timeout=240)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = read_csv(os.path.join(out, "sweep.csv"))
        self.assertEqual(len(rows), 4)
        for row in rows:
            # Judged by a clean exit (any); the outcome is the plug-in's own experiment's.
            self.assertEqual((row["success"], row["behaviour"]), ("1", "aggregation"))
            self.assertIn(row["outcome"], ("gathered", "scattered"))
            self.assertIn(f"--plugin-dir {AGGREGATION_DIR}", row["command"])
        with open(os.path.join(out, "sweep.json")) as f:
            res = json.load(f)
        self.assertEqual(res["grid"]["plugin_dirs"], [AGGREGATION_DIR])
        # A run's command reproduces it (the plug-in found the same way): the same trajectory.
        again = subprocess.run(shlex.split(rows[3]["command"]) + ["--out", os.path.join(self.dir, "agg-again")],
                               capture_output=True, text=True, timeout=120, cwd=res["cwd"])
        self.assertEqual(again.returncode, 0, again.stderr)
        self.assertEqual(json.loads(again.stdout)["trajectory_sha256"], rows[3]["trajectory_sha256"])
        r = helpers.swarm(*common, "--plugin-dir", os.path.join(self.dir, "nowhere"), build_dir=BUILD_DIR, timeout=60)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--plugin-dir", r.stderr)

    def test_a_shape_heading_that_turns_the_shape_into_a_wall_is_refused(self):
        # A 1 x 12 bar (11 m) from paper.yaml's robots about the origin, in its 20 x 12 m arena (x in [-6, 14]):
        # turned along +x (heading pi/2) it fits; along -x (-pi/2) or -y (0, the file's own heading) it does not.
        # The fit is checked with the --param value, which the file's would not give (the file's refuses it).
        bar = os.path.join(self.dir, "bar.txt")
        with open(bar, "w") as f:
            f.write(" ".join(str(i) for i in range(12)) + "\n")
        out = os.path.join(self.dir, "h")
        base = ("sweep", "--scenario", PAPER, "--shape", bar, "--seeds", "1", "--max-ticks", "5", "--expect", "any",
                "--out", out)
        r = helpers.swarm(*base, build_dir=BUILD_DIR, timeout=120)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("shape_heading 0) cannot fit inside the walls", r.stderr)
        r = helpers.swarm(*base, "--param", "shape_heading=1.5707963", build_dir=BUILD_DIR, timeout=120)
        self.assertEqual(r.returncode, 0, r.stderr)
        r = helpers.swarm(*base, "--param", "shape_heading=1.5707963,-1.5707963", build_dir=BUILD_DIR, timeout=120)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("shape_heading -1.5708) cannot fit inside the walls", r.stderr)

    def test_a_bad_scenario_is_refused_before_any_run(self):
        bad = os.path.join(self.dir, "bad.yaml")
        with open(bad, "w") as f:
            f.write("shape: triangle.txt\ncomm_rang: 3.0\n")
        out = os.path.join(self.dir, "c")
        r = helpers.swarm("sweep", "--scenario", bad, "--out", out, build_dir=BUILD_DIR, timeout=60)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn(f"{bad}:2: comm_rang: unknown key", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(out, "sweep.csv")))
        r = helpers.swarm("sweep", "--scenario", PAPER, "--kills", "9@5", "--out", out, build_dir=BUILD_DIR,
                          timeout=60)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--kills 9@5: robot 9 does not exist (ids 0..8)", r.stderr)


if __name__ == "__main__":
    unittest.main()
