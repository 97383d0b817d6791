"""The command line: help before any build, bad flags exit 2, the report table, damaged recordings reported
as file:line by the commands (never a traceback)."""

import csv
import io
import json
import os
import shutil
import tempfile
import time
import unittest

import helpers
import fixture


class CliTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-cli-")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_help_is_fast_and_documents_every_command(self):
        start = time.monotonic()
        # No SWARM_NO_BUILD and a build dir that does not exist: --help must neither build nor need one.
        r = helpers.swarm("--help", env={"SWARM_NO_BUILD": "0"}, build_dir=os.path.join(self.dir, "nothing"))
        self.assertLess(time.monotonic() - start, 10.0)
        self.assertEqual(r.returncode, 0, r.stderr)
        for word in ("run", "demo", "kill", "replay", "view", "export", "report", "runs/latest", "--help"):
            self.assertIn(word, r.stdout)
        for cmd, flags in (("run", ["--scenario", "--shape", "--robots", "--seed", "--mode", "--max-ticks", "--out",
                                    "--kill", "--domain", "--no-pictures", "--in-process", "--secure",
                                    "--no-animation", "--view", "--view-host", "--view-paused"]),
                           ("view", ["--port", "--host", "RUN_DIR"]),
                           ("export", ["--mcap", "RUN_DIR"]),
                           ("demo", ["--robots"]), ("kill", ["--run"]), ("replay", ["--ticks"]), ("report", [])):
            r = helpers.swarm(cmd, "--help", env={"SWARM_NO_BUILD": "0"},
                              build_dir=os.path.join(self.dir, "nothing"))
            self.assertEqual(r.returncode, 0, r.stderr)
            for flag in flags:
                self.assertIn(flag, r.stdout, f"swarm {cmd} --help")
        self.assertFalse(os.path.exists(os.path.join(self.dir, "nothing")))

    def test_bad_flags_exit_2_with_a_clear_message(self):
        cases = [(["run", "--robots", "zero"], "argument --robots: expected an integer, got 'zero'"),
                 (["run", "--robots", "0"], "must be >= 1"),
                 (["run", "--kill", "3"], "argument --kill: expected ID@TICK"),
                 (["run", "--mode", "fast"], "invalid choice: 'fast'"),
                 (["run", "--scenario", "/no/such.yaml"], "argument --scenario: no such file '/no/such.yaml'"),
                 (["run", "--domain", "300"], "DDS domain ids go up to 232"),
                 (["run", "--frobnicate"], "unrecognized arguments: --frobnicate"),
                 (["run", "--secure", "--in-process"], "--secure secures DDS and --in-process runs without it"),
                 (["run", "--secure", "--domain", "231"], "--secure: DDS domain 231 is above 230"),
                 (["replay"], "the following arguments are required: RUN_DIR"),
                 (["run", "--view", "70000"], "a TCP port is 0..65535, got 70000"),
                 (["run", "--record-every", "0"], "argument --record-every: must be >= 1, got 0"),
                 (["run", "--record-every", "2.5"], "argument --record-every: expected an integer, got '2.5'"),
                 (["view"], "the following arguments are required: RUN_DIR"),
                 (["view", "runs/x", "--port", "-1"], "must be >= 0"),
                 (["kill", "x"], "argument ID"),
                 (["explode"], "invalid choice: 'explode'"),
                 ([], "usage")]
        for args, message in cases:
            r = helpers.swarm(*args, env={"SWARM_NO_BUILD": "0"}, build_dir=os.path.join(self.dir, "nothing"))
            self.assertEqual(r.returncode, 2, (args, r.stderr))
            self.assertIn(message, r.stderr, args)
            self.assertNotIn("Traceback", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "nothing")), "a bad flag must not start a build")

    def test_report_prints_the_summary_as_a_table(self):
        fixture.make_run(self.dir, ticks=40)
        r = helpers.swarm("report", self.dir)
        self.assertEqual(r.returncode, 0, r.stderr)
        lines = r.stdout.splitlines()
        self.assertIn(f"swarmform run {self.dir}", lines[0])
        self.assertIn("  robots                     7", lines)
        self.assertIn("  ticks                      40  (4.0 s)", lines)
        self.assertIn("  shape formed at            12  (1.2 s)", lines)
        self.assertIn("  goal reached at            not reached", lines)
        self.assertIn("  deaths                     1: robot 2 at tick 50", lines)
        self.assertIn("  alive at end               6 / 7", lines)
        self.assertIn("  outcome                    formed_not_arrived", lines)
        self.assertIn("  stuck robots               2: 3, 5", lines)
        self.assertNotIn("stuck_robot_count", r.stdout)
        for group in ("Run", "Outcome", "Formation and motion", "Faults", "Collisions (contact onsets)", "Reproducibility"):
            self.assertIn(group, lines)

    def test_report_gives_a_mixed_swarms_groups_a_line_each(self):
        fixture.make_run(self.dir, ticks=40)
        path = os.path.join(self.dir, "summary.json")
        with open(path) as f:
            summary = json.load(f)
        summary["groups"] = {"shapers": {"behaviour": "paper", "first_id": 0, "count": 5, "outcome": "arrived",
                                         "states_at_end": {"arrived": 5}},
                             "movers": {"behaviour": "random_walk", "first_id": 5, "count": 2, "outcome": "none",
                                        "states_at_end": {"walking": 2}}}
        with open(path, "w") as f:
            json.dump(summary, f)
        r = helpers.swarm("report", self.dir)
        self.assertEqual(r.returncode, 0, r.stderr)
        lines = r.stdout.splitlines()
        self.assertIn("Robot groups", lines)
        self.assertIn("    shapers: paper, robots 0..4, outcome arrived; live by state arrived 5", lines)
        self.assertIn("    movers: random_walk, robots 5..6, outcome none; live by state walking 2", lines)

    def test_report_json_and_csv(self):
        fixture.make_run(self.dir, ticks=40, distortion=True)
        r = helpers.swarm("report", self.dir, "--json")
        self.assertEqual(r.returncode, 0, r.stderr)
        doc = json.loads(r.stdout)
        with open(os.path.join(self.dir, "summary.json")) as f:
            summary = json.load(f)
        self.assertEqual(doc, dict(summary, run_dir=self.dir), "every key of summary.json, and run_dir")
        r = helpers.swarm("report", self.dir, self.dir, "--csv")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = list(csv.DictReader(io.StringIO(r.stdout)))
        self.assertEqual(len(rows), 2)
        self.assertEqual(rows[0]["run_dir"], self.dir)
        self.assertEqual(rows[0]["ticks"], "40")
        self.assertEqual(rows[0]["deaths"], "2@50")
        self.assertEqual(rows[0]["stuck_robots"], "3 5")
        self.assertNotIn("distortion", rows[0], "a per-tick series is no cell")
        both = helpers.swarm("report", self.dir, "--json", "--csv")
        self.assertEqual(both.returncode, 2)
        missing = helpers.swarm("report", self.dir, os.path.join(self.dir, "nope"), "--csv")
        self.assertEqual(missing.returncode, 1)
        self.assertEqual(missing.stdout, "", "nothing written before the bad RUN_DIR is found")
        self.assertIn("nope: not a directory", missing.stderr)

    def test_report_without_summary_explains(self):
        fixture.make_run(self.dir, ticks=20, summary=False)
        r = helpers.swarm("report", self.dir)
        self.assertEqual(r.returncode, 1)
        self.assertIn("summary.json: missing: the run did not finish", r.stderr)

    def test_replay_of_a_corrupt_recording_names_file_and_line(self):
        fixture.make_run(self.dir, ticks=20)
        path = os.path.join(self.dir, "robots.csv")
        with open(path) as f:
            lines = f.read().splitlines()
        lines[6] = "0,5,1.0,NOPE,0,1,1,-1,-1,0,0"
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")
        r = helpers.swarm("replay", self.dir, "--no-animation")
        self.assertEqual(r.returncode, 1)
        self.assertIn(f"{path}:7: column 'y': expected a number, got 'NOPE'", r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_replay_of_a_crashed_run_warns_and_draws(self):
        fixture.make_run(self.dir, ticks=20, summary=False)
        with open(os.path.join(self.dir, "robots.csv"), "a") as f:
            f.write("20,0,0.5,0.")  # the run died mid-line
        r = helpers.swarm("replay", self.dir, "--no-animation")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("robots.csv:142: half-written last line dropped", r.stderr)
        self.assertIn("summary.json: missing", r.stderr)
        self.assertTrue(os.path.exists(os.path.join(self.dir, "pictures", "trajectories.png")))

    def test_replay_of_a_missing_directory(self):
        r = helpers.swarm("replay", os.path.join(self.dir, "nope"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("nope: not a directory", r.stderr)


if __name__ == "__main__":
    unittest.main()
