"""`swarm sweep --shard K/N`, `--merge DIR...` and `--resume DIR` over the stand-in harness (fake_sweep_build/,
whose ending is chosen by the seed): the slices merged are the unsliced sweep, a sweep killed mid-way goes on
without running a finished run again, and every mistake (a missing slice, slices of two grids, a grid flag with
--resume, a bad K/N, a journal line cut short) gets its clear answer."""

import csv
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import helpers
from swarmform import sweep_journal

FAKE = os.path.join(helpers.HERE, "fake_sweep_build")
SCENARIO = os.path.join(helpers.HERE, "data", "walk4.yaml")
GRID = ["--scenario", SCENARIO, "--seeds", "1-3,7,8", "--kills", "none", "random:1", "--expect", "any"]
TIMING = {"run_wall_seconds", "wall_seconds"}  # the only columns two runs of one grid may differ in


def rows_of(sweep_dir):
    with open(os.path.join(sweep_dir, "sweep.csv"), newline="") as f:
        return [{k: v for k, v in row.items() if k not in TIMING} for row in csv.DictReader(f)]


def without_timing(value):
    if isinstance(value, dict):
        return {k: without_timing(v) for k, v in value.items() if "wall" not in k}
    if isinstance(value, list):
        return [without_timing(v) for v in value]
    return value


def judged(sweep_dir):
    """sweep.json but for where and when it ran (cwd, started_utc, wall times, the merge's own note)."""
    with open(os.path.join(sweep_dir, "sweep.json")) as f:
        res = json.load(f)
    return without_timing({k: v for k, v in res.items() if k not in ("cwd", "started_utc", "merged_from")})


class ShardParserTest(unittest.TestCase):
    def test_k_of_n(self):
        self.assertEqual(sweep_journal.parse_shard("2/8"), (2, 8))
        for text in ("0/3", "4/3", "3", "a/b", "1/0", "-1/3", ""):
            with self.assertRaises(ValueError, msg=text):
                sweep_journal.parse_shard(text)

    def test_the_slices_cover_the_grid_once(self):
        for n in (1, 2, 5):
            owners = [[k for k in range(1, n + 1) if sweep_journal.in_shard(i, (k, n))] for i in range(23)]
            self.assertTrue(all(len(o) == 1 for o in owners), owners)

    def test_the_saved_grid_leaves_out_where_and_how_it_ran(self):
        self.assertEqual(sweep_journal.grid_argv(["--seeds", "1-3", "--out", "x", "--jobs=2", "-j", "3", "--quiet",
                                                  "--shard", "1/2", "--kills", "none"]),
                         ["--seeds", "1-3", "--kills", "none"])


class JournalTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-sweep-journal-")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def sweep(self, *args):
        return helpers.swarm("sweep", "--quiet", *args, build_dir=FAKE, timeout=120)

    def test_the_merged_slices_are_the_unsliced_sweep(self):
        full = os.path.join(self.dir, "full")
        self.assertEqual(self.sweep(*GRID, "--out", full).returncode, 0)
        slices = []
        for k in (1, 2, 3):
            out = os.path.join(self.dir, f"slice{k}")
            r = self.sweep(*GRID, "--shard", f"{k}/3", "--out", out, "--jobs", "1")
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            self.assertIn(len(rows_of(out)), (3, 4), "every third of the 10 runs")
            slices.append(out)
        merged = os.path.join(self.dir, "merged")
        r = self.sweep("--merge", *reversed(slices), "--out", merged)
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertEqual(rows_of(merged), rows_of(full))
        self.assertEqual(judged(merged), judged(full))
        self.assertIn("overall: 10/10 succeeded", r.stdout)

    def test_merging_refuses_a_missing_slice_two_grids_and_a_slice_twice(self):
        outs = {}
        for name, grid, shard in (("a1", GRID, "1/2"), ("a2", GRID, "2/2"), ("b2", GRID[:-2], "2/2")):
            outs[name] = os.path.join(self.dir, name)
            self.sweep(*grid, "--shard", shard, "--out", outs[name])
        for dirs, words in (([outs["a1"]], "slice(s) 2 of 2 not given"),
                            ([outs["a1"], outs["b2"]], "is a slice of another sweep"),
                            ([outs["a1"], outs["a1"]], "are both slice 1/2"),
                            ([outs["a1"], os.path.join(self.dir, "nowhere")], "sweep_args.json: no such file")):
            r = self.sweep("--merge", *dirs, "--out", os.path.join(self.dir, "m"))
            self.assertEqual(r.returncode, 2, r.stdout + r.stderr)
            self.assertIn(words, r.stderr)
        r = self.sweep("--merge", outs["a1"], outs["a2"], "--seeds", "4")
        self.assertEqual(r.returncode, 2)
        self.assertIn("give no --seeds", r.stderr)

    def test_a_sweep_killed_mid_way_resumes_without_running_a_finished_run_again(self):
        # Seeds 1-3 end at once; seed 9 runs until it is told to stop, and is cut by --timeout 3 otherwise.
        out = os.path.join(self.dir, "killed")
        cmd = [helpers.SWARM, "sweep", "--scenario", SCENARIO, "--seeds", "1-3,9", "--expect", "any", "--timeout",
               "3", "--jobs", "1", "--quiet", "--out", out]
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=FAKE)
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                             start_new_session=True)
        journal = os.path.join(out, "runs.jsonl")
        deadline = time.monotonic() + 30
        try:
            while time.monotonic() < deadline and p.poll() is None:
                if os.path.exists(journal):
                    with open(journal) as f:
                        if f.read().count("\n") >= 3:
                            break
                time.sleep(0.05)
        finally:
            os.killpg(p.pid, signal.SIGKILL)  # the machine is lost: nothing is written after this
            p.wait(timeout=10)
        with open(journal) as f:
            before = f.read()
        self.assertEqual(before.count("\n"), 3, "seeds 1-3 finished, seed 9 was cut")
        with open(journal, "a") as f:
            f.write('{"index": 3, "success": tr')  # a record cut short by the loss
        r = self.sweep("--resume", out, "--jobs", "2")
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)  # seed 9 fails by its timeout
        self.assertIn("3 finished before, 1 to run", r.stderr + r.stdout)
        rows = {int(row["seed"]): row for row in rows_of(out)}
        self.assertEqual(sorted(rows), [1, 2, 3, 9])
        self.assertTrue(rows[9]["reason"].startswith("timeout"), rows[9])
        with open(journal) as f:
            self.assertTrue(f.read().startswith(before), "the finished runs' records kept, not run again")

    def test_resume_refuses_a_grid_flag_and_a_folder_that_is_no_sweep(self):
        out = os.path.join(self.dir, "s")
        self.sweep(*GRID, "--out", out)
        r = self.sweep("--resume", out, "--seeds", "4")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--resume takes the grid from", r.stderr)
        r = self.sweep("--resume", self.dir)
        self.assertEqual(r.returncode, 2)
        self.assertIn("sweep_args.json: no such file", r.stderr)
        with open(os.path.join(out, "runs.jsonl"), "a") as f:
            f.write("not json\n")
        r = self.sweep("--resume", out)
        self.assertEqual(r.returncode, 2)
        self.assertIn("runs.jsonl:11: not a JSON record", r.stderr)

    def test_a_bad_shard_is_refused_before_anything_runs(self):
        r = self.sweep(*GRID, "--shard", "4/3", "--out", os.path.join(self.dir, "x"))
        self.assertEqual(r.returncode, 2)
        self.assertIn("--shard '4/3': want K/N with 1 <= K <= N", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "x")))


if __name__ == "__main__":
    unittest.main()
