"""`swarm sweep` without the C++ programs: the kill-schedule and seed parsers and their errors, the random
schedule's reproducibility and bounds, and a sweep over a stand-in swarm_inprocess (fake_sweep_build/) whose
ending is chosen by the seed: the judging, the reasons (crash, timeout, no summary), sweep.csv, sweep.json's rates
and worst-case order, and the exit codes. The scenario-field axes (--loss, --burst, --noise, --set): their parsers,
the --set flags each combination gives a run, and their columns."""

import csv
import json
import os
import shlex
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import helpers
from swarmform import sweep, sweep_fields

FAKE = os.path.join(helpers.HERE, "fake_sweep_build")
SCENARIO = os.path.join(helpers.HERE, "data", "walk4.yaml")


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


class ScheduleParserTest(unittest.TestCase):
    def test_the_three_forms(self):
        self.assertEqual(sweep.parse_kill_schedule("none").text, "none")
        self.assertEqual(sweep.parse_kill_schedule("none").flags(1, 9, 3000), [])
        s = sweep.parse_kill_schedule(" 5@10, 2@300 ")
        self.assertEqual(s.text, "5@10,2@300")
        self.assertEqual(s.flags(7, 9, 3000), ["5@10", "2@300"])
        self.assertEqual(sweep.parse_kill_schedule("random:3").random_count, 3)

    def test_a_kill_followed_by_a_restart(self):
        s = sweep.parse_kill_schedule("5@400+10, 2@300")
        self.assertEqual(s.text, "5@400+10,2@300")
        self.assertEqual(s.flags(1, 9, 3000), ["5@400", "2@300"])
        self.assertEqual(s.restart_flags(s.flags(1, 9, 3000)), ["restart:5@410"])
        r = sweep.parse_kill_schedule("random:2+150")
        self.assertEqual(r.text, "random:2+150")
        kills = r.flags(3, 9, 3000)
        self.assertEqual(r.restart_flags(kills),
                         [f"restart:{k.split('@')[0]}@{int(k.split('@')[1]) + 150}" for k in kills])
        self.assertEqual(sweep.parse_kill_schedule("random:2").restart_flags(kills), [])
        for text in ("5@10+0", "random:1+0", "5@10+x"):
            with self.assertRaises(ValueError, msg=text):
                sweep.parse_kill_schedule(text)

    def test_errors_name_the_text_and_the_forms(self):
        for text, words in (("5@", "'5@' is not ID@TICK"), ("@5", "is not ID@TICK"), ("5@10,x", "'x' is not ID@TICK"),
                            ("-1@5", "is not ID@TICK"), ("random:0", "K >= 1"), ("random:", "random:K"),
                            ("random:two", "random:K"), ("randomly", "random:K"), ("", "empty"),
                            ("5@10,5@20", "robot 5 is killed twice"), ("1@2000000000", "beyond 1e9")):
            with self.assertRaises(ValueError, msg=text) as e:
                sweep.parse_kill_schedule(text)
            self.assertIn(words, str(e.exception), text)
        with self.assertRaises(sweep.SweepError) as e:
            sweep.parse_kill_schedule("12@5").flags(1, 9, 3000)
        self.assertIn("robot 12 does not exist (ids 0..8)", str(e.exception))
        with self.assertRaises(sweep.SweepError) as e:
            sweep.parse_kill_schedule("random:9").flags(1, 9, 3000)
        self.assertIn("leave none alive", str(e.exception))

    def test_random_is_reproducible_within_bounds_and_reaches_every_id(self):
        s = sweep.parse_kill_schedule("random:3")
        ids, ticks = set(), []
        for seed in range(200):
            flags = s.flags(seed, 9, 250)
            self.assertEqual(flags, sweep.parse_kill_schedule("random:3").flags(seed, 9, 250), "reproducible")
            kills = [tuple(int(v) for v in f.split("@")) for f in flags]
            self.assertEqual(len(kills), 3)
            self.assertEqual(len({k[0] for k in kills}), 3, "distinct robots")
            ids.update(k[0] for k in kills)
            ticks += [k[1] for k in kills]
        self.assertEqual(ids, set(range(9)), "every robot, the seed (0 is often nearest the origin) included")
        self.assertGreaterEqual(min(ticks), 1)
        self.assertLessEqual(max(ticks), 250)
        self.assertGreater(max(ticks) - min(ticks), 200, "spread over the whole window")
        self.assertNotEqual(s.flags(1, 9, 250), s.flags(2, 9, 250), "the seed changes the draw")
        self.assertNotEqual(sweep.parse_kill_schedule("random:1").flags(1, 9, 250)[0], s.flags(1, 9, 250)[0],
                            "so does the schedule's text")
        # Pinned: the draw must not change between versions, or old sweep.csv commands stop matching.
        self.assertEqual(sweep.parse_kill_schedule("random:2").flags(1, 9, 3000), ["5@2010", "4@2537"])

    def test_seeds(self):
        self.assertEqual(sweep.parse_seeds("7"), [7])
        self.assertEqual(sweep.parse_seeds("1-3,9,11-12"), [1, 2, 3, 9, 11, 12])
        for bad, words in (("5-1", "empty"), ("a", "not a seed"), ("1-", "not a seed"), ("", "not a seed")):
            with self.assertRaises(ValueError) as e:
                sweep.parse_seeds(bad)
            self.assertIn(words, str(e.exception))


class FieldAxesTest(unittest.TestCase):
    def test_set_values_split_on_top_level_commas_only(self):
        self.assertEqual(sweep_fields.split_values("0.1,{rate: 0.2, mean_burst: 5},[1, 2],'a,b'"),
                         ["0.1", "{rate: 0.2, mean_burst: 5}", "[1, 2]", "'a,b'"])
        for bad, says in (("{a: 1", "unclosed bracket"), ("a]", "closes nothing"), ("'a,b", "unclosed quote")):
            with self.assertRaises(ValueError) as e:
                sweep_fields.split_values(bad)
            self.assertIn(says, str(e.exception))

    def test_bad_values_are_refused_naming_the_text(self):
        for parse, text, says in (
                (sweep_fields.parse_loss, "0.1,lots", "'0.1,lots': 'lots' is not a number"),
                (sweep_fields.parse_loss, "0.1,0.1", "the value 0.1 is given twice"),
                (sweep_fields.parse_loss, "-0.1", "the loss rate -0.1 is outside [0, 1)"),
                (sweep_fields.parse_burst, "0.5", "'0.5': the mean burst 0.5 is outside [1, 1e+06]"),
                (sweep_fields.parse_burst, "inf", "the mean burst inf is outside"),
                (sweep_fields.parse_noise, "off,loud", "'loud' is not a noise level (expected off or on"),
                (sweep_fields.parse_noise, "on,on", "on is given twice"),
                (sweep_fields.parse_set, "comm_range", "'comm_range': expected KEY=V1,V2,..."),
                (sweep_fields.parse_set, "noise..range=1", "expected KEY=V1,V2,..."),
                (sweep_fields.parse_set, "noise={range: 0.1", "an unclosed bracket or brace"),
                (sweep_fields.parse_set, "comm_range=2,2", "the value 2 is given twice"),
                (sweep_fields.parse_set, "comm_range=2,", "an empty value")):
            with self.assertRaises(ValueError, msg=text) as e:
                parse(text)
            self.assertIn(says, str(e.exception))
        for grid, says in (
                ((None, sweep_fields.parse_burst("1,5"), None, []), "--burst needs --loss"),
                ((None, None, None, [("comm_range", ["2"]), ("comm_range", ["3"])]), "--set comm_range is given twice"),
                ((sweep_fields.parse_loss("0.1"), None, None, [("packet_loss", ["0.2"])]),
                 "--set packet_loss and --loss both set packet_loss"),
                ((None, None, None, [("arena", ["{width: 5}"]), ("arena.width", ["6"])]),
                 "--set arena.width and --set arena both set arena")):
            with self.assertRaises(ValueError) as e:
                sweep_fields.FieldGrid(*grid).check()
            self.assertIn(says, str(e.exception))

    def test_each_combination_gives_its_set_flags(self):
        grid = sweep_fields.FieldGrid(sweep_fields.parse_loss("0.2"), sweep_fields.parse_burst("1,5"),
                                      sweep_fields.parse_noise("on"), [sweep_fields.parse_set("occlusion=true")])
        grid.check()
        self.assertEqual(grid.combinations(), [
            ({"loss": "0.2", "burst": "1", "noise": "on", "set_occlusion": "true"},
             ["--set", "packet_loss=0.2", "--set", "noise={range: 0.05, bearing: 0.05, ultrasonic: 0.02}",
              "--set", "occlusion=true"]),
            ({"loss": "0.2", "burst": "5", "noise": "on", "set_occlusion": "true"},
             ["--set", "packet_loss={rate: 0.2, mean_burst: 5}", "--set",
              "noise={range: 0.05, bearing: 0.05, ultrasonic: 0.02}", "--set", "occlusion=true"])])
        self.assertEqual(sweep_fields.FieldGrid(None, None, None, []).combinations(), [({}, [])])
        # The bound is the loader's: 1 / (1 - 0.2) = 1.25 is accepted, below it refused.
        sweep_fields.FieldGrid(sweep_fields.parse_loss("0.2"), sweep_fields.parse_burst("1.25"), None, []).check()
        with self.assertRaises(ValueError):
            sweep_fields.FieldGrid(sweep_fields.parse_loss("0.2"), sweep_fields.parse_burst("1.2"), None, []).check()


class SweepCliTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-sweep-")
        self.out = os.path.join(self.dir, "out")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def sweep(self, *args, timeout=120):
        return helpers.swarm("sweep", "--scenario", SCENARIO, "--out", self.out, "--quiet", *args,
                             build_dir=FAKE, timeout=timeout)

    def test_help_documents_every_flag_and_the_exit_codes(self):
        r = helpers.swarm("sweep", "--help", env={"SWARM_NO_BUILD": "0"}, build_dir=os.path.join(self.dir, "no"))
        self.assertEqual(r.returncode, 0, r.stderr)
        for word in ("--scenario", "--shape", "--shapes-dir", "--robots", "--seeds", "--kills", "--max-ticks",
                     "--kill-window", "--expect", "--max-shape-error", "--max-contacts", "--max-robot-contacts",
                     "--jobs", "--timeout", "--out", "random:K", "sweep.csv", "sweep.json", "Exit codes", "--param",
                     "param_NAME", "--loss", "--burst", "--noise", "--set", "set_KEY", "by_fields",
                     "ultrasonic 0.02",
                     "130 interrupted"):
            self.assertIn(word, r.stdout)
        top = helpers.swarm("--help", build_dir=os.path.join(self.dir, "no"))
        self.assertIn("sweep", top.stdout)

    def test_bad_input_exits_2_before_any_run(self):
        bad_scenario = os.path.join(self.dir, "bad.yaml")
        with open(bad_scenario, "w") as f:
            f.write("fake: bad\n")
        cases = [(["--kills", "5@"], "argument --kills: '5@' is not ID@TICK"),
                 (["--kills", "random:0"], "random:K needs K >= 1"),
                 (["--kills", "12@5"], "--kills 12@5: robot 12 does not exist (ids 0..8)"),
                 (["--kills", "random:9"], "leave none alive"),
                 (["--seeds", "9-2"], "argument --seeds: '9-2': the range 9-2 is empty"),
                 (["--jobs", "0"], "argument --jobs/-j: must be >= 1"),
                 (["--max-shape-error", "-1"], "argument --max-shape-error: must be a finite number >= 0"),
                 (["--expect", "maybe"], "argument --expect: 'maybe': expected an outcome word"),
                 (["--expect", "arrived", "--expect", "formed"], "one outcome word at most"),
                 (["--shape", os.path.join(self.dir, "*.nothing")], "no file matches"),
                 (["--scenario", bad_scenario], f"{bad_scenario}:1: fake: a bad scenario"),
                 (["--param", "k_goal"], "argument --param: 'k_goal': expected NAME=V1,V2,..."),
                 (["--param", "k_goal=1,fast"], "'fast' is not a number"),
                 (["--param", "k_goal=1,1"], "the value 1 is given twice"),
                 (["--param", "k_goal=nan"], "not a finite number"),
                 (["--param", "k_goal=1", "--param", "k_goal=2"], "--param k_goal is given twice"),
                 (["--param", "k_wobble=1,2"], "--param k_wobble=1: unknown controller parameter 'k_wobble'"),
                 (["--param", "k_goal=1,200"], "--param k_goal=200: controller parameter 'k_goal' = 200 is outside"),
                 (["--loss", "0,1"], "argument --loss: '0,1': the loss rate 1 is outside [0, 1)"),
                 (["--loss", "0.1", "--loss", "0.2"], "--loss is given 2 times"),
                 (["--loss", "0.3,0.6", "--burst", "1,2"],
                  "--burst 2 with --loss 0.6: a mean burst must be at least 1 / (1 - rate) = 2.5 ticks"),
                 (["--noise", "on", "--set", "noise.range=0.1"], "--set noise.range and --noise both set noise"),
                 (["--set", "comm_rang=2,3"], "command line: --set 'comm_rang=2': comm_rang: unknown key")]
        for args, message in cases:
            r = self.sweep(*args)
            self.assertEqual(r.returncode, 2, f"{args}: {r.stderr}")
            self.assertIn(message, r.stderr, args)
            self.assertNotIn("Traceback", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(self.out, "sweep.csv")), args)

    def test_sweep_judges_every_ending_and_writes_csv_and_json(self):
        # --timeout 15: the hung seed (60 s) is cut, and every other stand-in run ends well within it on a loaded
        # 2-core machine (with 3 s, a stand-in's start-up under load was sometimes cut as if it had hung).
        start = time.monotonic()
        r = self.sweep("--seeds", "1-8", "--kills", "none", "3@7", "--timeout", "15", "--jobs", "4",
                       "--expect", "formed")
        self.assertLess(time.monotonic() - start, 55, "the hung run (60 s) was cut at --timeout")
        self.assertEqual(r.returncode, 1, r.stderr)
        rows = read_csv(os.path.join(self.out, "sweep.csv"))
        self.assertEqual(len(rows), 16)
        self.assertEqual([(row["seed"], row["kills"]) for row in rows],
                         [(str(s), k) for k in ("none", "3@7") for s in range(1, 9)])
        by = {(int(row["seed"]), row["kills"]): row for row in rows}
        for seed in range(1, 9):
            self.assertEqual(by[seed, "none"]["kill_flags"], "")
            self.assertEqual(by[seed, "3@7"]["kill_flags"], "3@7")
            self.assertIn("--kill 3@7", by[seed, "3@7"]["command"])
            self.assertIn("--seed %d" % seed, by[seed, "3@7"]["command"])
            self.assertIn("--no-record --quiet", by[seed, "3@7"]["command"])
        self.assertEqual(by[1, "3@7"]["deaths"], "3@7", "the kill reached the harness")
        ok = {seed for seed in range(1, 9) if by[seed, "none"]["success"] == "1"}
        self.assertEqual(ok, {1, 2, 7, 8}, "formed: arrived or formed_not_arrived (or the fallback)")
        self.assertEqual(by[3, "none"]["reason"], "outcome not_formed, expected formed (ended at tick 5000)")
        self.assertTrue(by[4, "none"]["reason"].startswith("crashed (SIGSEGV): about to crash"),
                        by[4, "none"]["reason"])
        self.assertEqual(by[4, "none"]["exit_code"], "-11")
        self.assertTrue(by[5, "none"]["reason"].startswith("timeout: still running after 15 s"))
        self.assertEqual(by[6, "none"]["reason"], "no summary.json on stdout")
        self.assertEqual(by[2, "none"]["stuck_robots"], "3 4")
        self.assertEqual(by[1, "none"]["goal_tick"], "3000")
        self.assertEqual(by[1, "none"]["summary_scenario"], SCENARIO, "a key named like a sweep column")
        self.assertNotIn("distortion", rows[0], "no per-tick series")
        self.assertGreater(float(by[5, "none"]["run_wall_seconds"]), 14.9)

        with open(os.path.join(self.out, "sweep.json")) as f:
            res = json.load(f)
        self.assertEqual(res["overall"]["runs"], 16)
        self.assertEqual(res["overall"]["succeeded"], 8)
        self.assertEqual(res["overall"]["success_rate"], 0.5)
        self.assertEqual(res["by_kills"]["none"]["success_rate"], 0.5)
        self.assertEqual(res["by_scenario"][SCENARIO]["runs"], 16)
        self.assertEqual(res["by_shape"]["triangle.txt"]["runs"], 16)
        self.assertEqual(len(res["by_cell"]), 2)
        self.assertEqual(res["grid"]["seeds"], "1-8")
        self.assertEqual(res["judging"]["expect"], "formed")
        worst = res["worst"]
        self.assertEqual(len(worst), 16)
        self.assertEqual([w["success"] for w in worst], [False] * 8 + [True] * 8, "failed runs first")
        self.assertEqual({w["seed"] for w in worst[:6]}, {4, 5, 6}, "crashes, timeouts, no summary first")
        self.assertEqual(worst[8]["shape_error_at_formation"], 0.05, "then the largest shape error")
        for w in worst:
            self.assertIn(f"--seed {w['seed']} ", w["command"])
            self.assertTrue(w["command"].endswith("--no-record --quiet"))
            self.assertIn("--out runs/sweep-repro-", w["record_command"])
            self.assertNotIn("--no-record", w["record_command"])
        with open(os.path.join(self.out, "runs.jsonl")) as f:
            journal = [json.loads(line) for line in f]
        self.assertEqual(sorted(j["index"] for j in journal), list(range(16)), "one line per finished run")
        self.assertEqual({j["index"]: j["success"] for j in journal}, {w["index"]: w["success"] for w in worst})
        self.assertIn("overall: 8/16 succeeded (50.0%)", r.stdout)
        self.assertIn("worst failures", r.stdout)

    def test_an_expression_judges_by_a_nested_key_checked_before_any_run(self):
        r = self.sweep("--seeds", "1-3", "--expect", "states_at_end.settled >= 2")
        self.assertEqual(r.returncode, 1, r.stderr)
        rows = {int(row["seed"]): row for row in read_csv(os.path.join(self.out, "sweep.csv"))}
        self.assertEqual({s: rows[s]["success"] for s in rows}, {1: "0", 2: "1", 3: "1"},
                         "given alone, the expression judges (seed 3 is not_formed, a clean run)")
        self.assertEqual(rows[1]["reason"], "states_at_end.settled >= 2 failed (states_at_end.settled is 1)")
        self.assertEqual((rows[3]["states_at_end.settled"], rows[3]["states_at_end.moving"]), ("3", "6"))
        self.assertEqual(rows[3]["params.k_goal"], "1.0")
        self.assertIn("states_at_end.settled", r.stdout.splitlines()[0], "the table's column")
        with open(os.path.join(self.out, "sweep.json")) as f:
            res = json.load(f)
        self.assertEqual(res["overall"]["medians"]["states_at_end.settled"], 2)
        # The numeric summary keys the behaviour declares (the stand-in's --check: the paper's formation and goal
        # keys; not its stuck_robots list nor its distortion series) are its own columns, after the --expect key;
        # the table does not repeat those its formed@/goal@ columns show.
        self.assertEqual(res["judging"]["behaviour_keys"][:5], ["states_at_end.settled", "formation_tick",
                                                                "shape_error_at_formation", "goal_tick",
                                                                "shape_error_at_goal"])
        self.assertEqual(res["overall"]["medians"]["formation_tick"], 550)
        head = r.stdout.splitlines()[0].split()
        self.assertIn("formed@", head)
        self.assertNotIn("formation_tick", head)

        shutil.rmtree(self.out)
        r = self.sweep("--seeds", "1", "--expect", "states_at_end.setled >= 2")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("'states_at_end.setled >= 2': summary.json will have no key 'states_at_end.setled' (under "
                      "'states_at_end': states_at_end, states_at_end.moving, states_at_end.settled)", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.out, "sweep.csv")))

        r = self.sweep("--seeds", "1-3", "--expect", "formed", "--expect", "states_at_end.settled >= 2")
        rows = {int(row["seed"]): row for row in read_csv(os.path.join(self.out, "sweep.csv"))}
        self.assertEqual({s: rows[s]["success"] for s in rows}, {1: "0", 2: "1", 3: "0"}, "the word and the "
                         "expression both")

    def test_thresholds_and_the_exit_code_when_all_succeed(self):
        r = self.sweep("--seeds", "1,7,8")
        self.assertEqual(r.returncode, 1)
        rows = {int(row["seed"]): row for row in read_csv(os.path.join(self.out, "sweep.csv"))}
        self.assertEqual(rows[1]["success"], "1")
        self.assertEqual(rows[7]["reason"], "outcome formed_not_arrived, expected arrived (ended at tick 5000)",
                         "the summary's outcome wins over goal_tick")
        self.assertEqual(rows[8]["success"], "1", "no outcome key: arrived from goal_tick")

        r = self.sweep("--seeds", "1", "8", "--max-shape-error", "0.1", "--max-robot-contacts", "1")
        rows = {int(row["seed"]): row for row in read_csv(os.path.join(self.out, "sweep.csv"))}
        self.assertEqual(rows[1]["reason"], "shape_error_at_goal 0.300 > 0.1")
        self.assertEqual(rows[8]["reason"], "robot-robot contacts 2 > 1")
        self.assertEqual(r.returncode, 1)

        r = self.sweep("--seeds", "8", "--max-shape-error", "0.1", "--max-contacts", "2")
        self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
        self.assertIn("overall: 1/1 succeeded (100.0%)", r.stdout)

    def test_an_interrupted_sweep_writes_what_it_has_and_asks_the_runs_for_theirs(self):
        cmd = [helpers.SWARM, "sweep", "--scenario", SCENARIO, "--out", self.out, "--seeds", "1", "9", "--jobs", "2"]
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=FAKE)
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
        journal = os.path.join(self.out, "runs.jsonl")
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:  # seed 1 is done, seed 9 runs until told to stop
            if os.path.exists(journal) and os.path.getsize(journal) > 0:
                break
            time.sleep(0.1)
        time.sleep(0.5)
        p.send_signal(signal.SIGTERM)
        out, err = p.communicate(timeout=30)
        self.assertEqual(p.returncode, 130, err)
        self.assertIn("interrupted after 2 of 2 runs", err)
        rows = {int(row["seed"]): row for row in read_csv(os.path.join(self.out, "sweep.csv"))}
        self.assertEqual(rows[1]["success"], "1")
        self.assertEqual(rows[9]["success"], "0")
        self.assertEqual(rows[9]["reason"], "interrupted (exit 130) at tick 1234, before its end")
        self.assertEqual(rows[9]["ticks"], "1234", "the summary it printed when told to stop")
        with open(os.path.join(self.out, "sweep.json")) as f:
            self.assertTrue(json.load(f)["interrupted"])

    def test_params_are_a_grid_axis_recorded_in_csv_and_json(self):
        r = self.sweep("--seeds", "1", "--param", "k_goal=0.5,2", "--param", "m_obstacle=1,3.25", "--expect", "any")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = read_csv(os.path.join(self.out, "sweep.csv"))
        self.assertEqual([(row["param_k_goal"], row["param_m_obstacle"]) for row in rows],
                         [("0.5", "1"), ("0.5", "3.25"), ("2", "1"), ("2", "3.25")])
        for row in rows:
            flags = f"--param k_goal={row['param_k_goal']} --param m_obstacle={row['param_m_obstacle']}"
            self.assertIn(flags, row["command"])
            self.assertEqual(row["fake_params"], flags.replace("--param ", ""), "the values reached the run")
        with open(os.path.join(self.out, "sweep.json")) as f:
            res = json.load(f)
        self.assertEqual(res["grid"]["params"], {"k_goal": [0.5, 2.0], "m_obstacle": [1.0, 3.25]})
        self.assertEqual(sorted(res["by_params"]), ["k_goal=0.5 m_obstacle=1", "k_goal=0.5 m_obstacle=3.25",
                                                    "k_goal=2 m_obstacle=1", "k_goal=2 m_obstacle=3.25"])
        self.assertEqual({w["index"]: w["params"] for w in res["worst"]}[3], {"k_goal": 2.0, "m_obstacle": 3.25})
        self.assertEqual(len(res["by_cell"]), 4)
        self.assertIn("params", r.stdout.splitlines()[0], "the table shows the parameters")

    def test_loss_burst_noise_and_set_are_grid_axes_recorded_in_csv_and_json(self):
        r = self.sweep("--seeds", "1", "--loss", "0,0.2", "--burst", "1,5", "--noise", "off,on",
                       "--set", "comm_range=3", "--expect", "any")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = read_csv(os.path.join(self.out, "sweep.csv"))
        self.assertEqual(len(rows), 8)
        axes = [(row["loss"], row["burst"], row["noise"], row["set_comm_range"]) for row in rows]
        self.assertEqual(axes, [(lo, b, n, "3") for lo in ("0", "0.2") for b in ("1", "5") for n in ("off", "on")])
        for row in rows:
            loss = (f"packet_loss={row['loss']}" if row["burst"] == "1" else
                    f"packet_loss={{rate: {row['loss']}, mean_burst: {row['burst']}}}")
            noise = ("noise={range: 0.05, bearing: 0.05, ultrasonic: 0.02}" if row["noise"] == "on" else
                     "noise={range: 0, bearing: 0, ultrasonic: 0}")
            # The values reached the run, as --set flags in the axes' order.
            self.assertEqual(row["fake_sets"], " | ".join([loss, noise, f"comm_range={row['set_comm_range']}"]))
            argv = shlex.split(row["command"])  # the command reproduces the run
            self.assertEqual([argv[i + 1] for i, a in enumerate(argv) if a == "--set"], row["fake_sets"].split(" | "))
        with open(os.path.join(self.out, "sweep.json")) as f:
            res = json.load(f)
        self.assertEqual(res["grid"]["fields"], {"loss": ["0", "0.2"], "burst": ["1", "5"], "noise": ["off", "on"],
                                                 "set_comm_range": ["3"]})
        self.assertEqual(res["grid"]["field_combinations"], 8)
        self.assertIn("loss=0.2 burst=5 noise=on set_comm_range=3", res["by_fields"])
        self.assertEqual(len(res["by_cell"]), 8)
        self.assertEqual({w["index"]: w["fields"] for w in res["worst"]}[7],
                         {"loss": "0.2", "burst": "5", "noise": "on", "set_comm_range": "3"})
        self.assertIn("fields", r.stdout.splitlines()[0], "the table shows the fields")

    def test_a_set_value_with_commas_stays_one_value(self):
        r = self.sweep("--seeds", "1", "--set", "packet_loss=0.1,{rate: 0.2, mean_burst: 5}", "--expect", "any")
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = read_csv(os.path.join(self.out, "sweep.csv"))
        self.assertEqual([row["set_packet_loss"] for row in rows], ["0.1", "{rate: 0.2, mean_burst: 5}"])
        self.assertEqual(rows[1]["fake_sets"], "packet_loss={rate: 0.2, mean_burst: 5}")

    def test_random_schedule_flags_reach_the_runs_and_repeat(self):
        self.sweep("--seeds", "1-3,7", "--kills", "random:2", "--kill-window", "100", "--max-ticks", "80",
                   "--robots", "5")
        first = read_csv(os.path.join(self.out, "sweep.csv"))
        for row in first:
            kills = [tuple(map(int, k.split("@"))) for k in row["kill_flags"].split()]
            self.assertEqual(len(kills), 2)
            self.assertTrue(all(0 <= i < 5 and 1 <= t <= 80 for i, t in kills), row["kill_flags"])
            self.assertEqual(row["deaths"], row["kill_flags"], "every drawn kill reached the harness")
            self.assertIn("--robots 5", row["command"])
        self.sweep("--seeds", "1-3,7", "--kills", "random:2", "--kill-window", "100", "--max-ticks", "80",
                   "--robots", "5")
        again = read_csv(os.path.join(self.out, "sweep.csv"))
        self.assertEqual([r["kill_flags"] for r in first], [r["kill_flags"] for r in again])


if __name__ == "__main__":
    unittest.main()
