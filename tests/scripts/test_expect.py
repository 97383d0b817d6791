"""`swarm run --expect`: the parser of 'KEY OP VALUE', the comparisons against a summary, the messages and exit
codes, and the flag on the command line (bad syntax is refused before anything runs). The launcher's end-to-end
use is in docs/testing-your-swarm.md's shell example (tests/examples/test_swarm_ci_example.sh)."""

import json
import os
import shutil
import tempfile
import unittest

import helpers
from swarmform import expect, summary_keys

SUMMARY = {"format": "swarmform-summary", "version": 1, "outcome": "arrived", "robots": 9, "alive_at_end": 8,
           "collisions_robot_robot": 0, "collisions_robot_obstacle": 3, "goal_tick": None, "shape_error_at_goal": 0.04,
           "deaths": [{"id": 3, "tick": 900}], "stuck_robots": [], "seed": 7, "leader_changes": 1}


def met(text, summary=SUMMARY):
    return expect.check(expect.parse(text), summary)[0]


class ParseTest(unittest.TestCase):
    def test_the_six_operators_and_values(self):
        e = expect.parse("collisions_robot_robot==0")
        self.assertEqual((e.key, e.op, e.value), ("collisions_robot_robot", "==", 0))
        for op in expect.OPS:
            self.assertEqual(expect.parse(f"robots {op} 9").op, op)
        self.assertEqual(expect.parse("outcome == arrived").value, "arrived")
        self.assertEqual(expect.parse("goal_tick == null").value, None)
        self.assertEqual(expect.parse("x != true").value, True)
        self.assertEqual(expect.parse("shape_error_at_goal <= 0.1").value, 0.1)
        self.assertEqual(expect.parse("outcome == 'formed_not_arrived'").value, "formed_not_arrived")

    def test_bad_syntax_is_refused_naming_the_text(self):
        for text in ("outcome arrived", "outcome = arrived", "== 3", "outcome ==", "3x == 1", "a =< 2", ""):
            with self.assertRaises(expect.ExpectationError, msg=text) as cm:
                expect.parse(text)
            self.assertIn(f"'{text}'", str(cm.exception))
            self.assertIn("KEY OP VALUE", str(cm.exception))

    def test_an_ordering_needs_a_number(self):
        with self.assertRaisesRegex(expect.ExpectationError, "<= needs a number on the right, got 'arrived'"):
            expect.parse("outcome <= arrived")
        with self.assertRaisesRegex(expect.ExpectationError, "finite"):
            expect.parse("robots < inf")


class CheckTest(unittest.TestCase):
    def test_comparisons(self):
        self.assertTrue(met("outcome == arrived"))
        self.assertFalse(met("outcome != arrived"))
        self.assertFalse(met("outcome == formed_not_arrived"))
        self.assertTrue(met("collisions_robot_robot == 0"))
        self.assertTrue(met("collisions_robot_robot == 0.0"))
        self.assertFalse(met("collisions_robot_obstacle == 0"))
        self.assertTrue(met("collisions_robot_obstacle <= 3"))
        self.assertFalse(met("collisions_robot_obstacle < 3"))
        self.assertTrue(met("alive_at_end >= 8"))
        self.assertFalse(met("alive_at_end > 8"))
        self.assertTrue(met("shape_error_at_goal < 0.05"))
        self.assertTrue(met("seed == 7"))

    def test_a_list_compares_by_its_length(self):
        self.assertTrue(met("deaths == 1"))
        self.assertTrue(met("deaths <= 2"))
        self.assertFalse(met("deaths == 0"))
        self.assertTrue(met("stuck_robots == 0"))
        self.assertEqual(expect.check(expect.parse("deaths == 0"), SUMMARY)[1], '1 ([{"id": 3, "tick": 900}])')

    def test_null_fails_every_ordering_and_equals_null(self):
        self.assertFalse(met("goal_tick <= 3000"))
        self.assertFalse(met("goal_tick > 0"))
        self.assertTrue(met("goal_tick == null"))
        self.assertFalse(met("goal_tick != null"))

    def test_an_unknown_key_names_the_key_and_lists_the_real_ones(self):
        with self.assertRaises(expect.ExpectationError) as cm:
            expect.check(expect.parse("colisions == 0"), SUMMARY)
        self.assertIn("no key 'colisions'", str(cm.exception))
        self.assertIn("collisions_robot_robot", str(cm.exception))


class NestedKeyTest(unittest.TestCase):
    NESTED = dict(SUMMARY, states_at_end={"settled": 10, "moving": 2}, params={"radius": 1.5})

    def test_a_dotted_key_names_a_nested_value(self):
        self.assertEqual(expect.parse("states_at_end.settled >= 10").key, "states_at_end.settled")
        self.assertTrue(met("states_at_end.settled >= 10", self.NESTED))
        self.assertFalse(met("states_at_end.moving == 0", self.NESTED))
        self.assertTrue(met("params.radius == 1.5", self.NESTED))
        with self.assertRaises(expect.ExpectationError) as cm:
            expect.check(expect.parse("states_at_end.setled >= 1"), self.NESTED)
        self.assertIn("no key 'states_at_end.setled' (under 'states_at_end': states_at_end.moving, "
                      "states_at_end.settled)", str(cm.exception))

    def test_keys_are_checked_against_the_declared_ones_before_a_run(self):
        declared = summary_keys.declared_keys(self.NESTED)
        exps = [expect.parse(t) for t in ("states_at_end.settled >= 10", "params.radius < 2", "outcome == x",
                                          "states_at_end.dancing > 0", "colisions == 0")]
        bad = expect.check_declared(exps, declared)
        self.assertEqual(len(bad), 2, bad)
        self.assertTrue(bad[0].startswith("'states_at_end.dancing > 0': summary.json will have no key "
                                          "'states_at_end.dancing'"), bad[0])
        self.assertIn("no key 'colisions'", bad[1])
        self.assertEqual(expect.check_declared(exps, declared, summary_keys.behaviour_owned), [bad[1]],
                         "the behaviour's own keys left to after the run (--exec)")

    def test_the_declared_summary_keys_come_from_the_check(self):
        """`world_server --check`'s JSON: its summary_template holds every key (a declared one null before the
        run), a declared series is not a key to judge on, and the numeric declared keys are the sweep's own
        columns, first and in the declared order."""
        info = {"behaviour_descriptor": {"experiment": {"summary": [
                    {"key": "goal_tick", "kind": "tick", "doc": ""}, {"key": "stragglers", "kind": "ids", "doc": ""},
                    {"key": "spread", "kind": "number", "doc": ""}, {"key": "trail", "kind": "series", "doc": ""},
                    {"key": "arrived", "kind": "count", "doc": ""}]}},
                "summary_template": {"ticks": 0, "goal_tick": None, "stragglers": None, "spread": None,
                                     "arrived": None, "states_at_end": {"settled": 0}, "trail": None}}
        series = [f["key"] for f in summary_keys.declared_summary(info) if f["kind"] == "series"]
        declared = summary_keys.declared_keys(info["summary_template"], series)
        self.assertEqual(declared, {"ticks", "goal_tick", "stragglers", "spread", "arrived", "states_at_end",
                                    "states_at_end.settled"})
        self.assertEqual(summary_keys.number_keys(info), ["goal_tick", "spread", "arrived"])
        self.assertEqual(summary_keys.declared_summary({"behaviour_descriptor": {"experiment": None}}), [])
        runs = [{"goal_tick": 40, "spread": 1.0, "states_at_end": {"settled": 3}}, None]
        self.assertEqual(summary_keys.behaviour_columns(runs, summary_keys.number_keys(info)),
                         ["goal_tick", "spread", "arrived", "states_at_end.settled"])
        self.assertEqual(summary_keys.behaviour_columns(runs), ["states_at_end.settled"],
                         "a top-level key is a column only when declared")


class EvaluateTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-expect-")
        with open(os.path.join(self.dir, "summary.json"), "w") as f:
            json.dump(SUMMARY, f)
        self.said = []

    def tearDown(self):
        shutil.rmtree(self.dir)

    def evaluate(self, *texts):
        return expect.evaluate([expect.parse(t) for t in texts], self.dir, self.said.append)

    def test_all_met_is_zero(self):
        self.assertEqual(self.evaluate("outcome == arrived", "deaths <= 1"), 0)
        self.assertEqual(len([s for s in self.said if "expectation met" in s]), 2)

    def test_each_failure_is_named_and_the_code_is_4(self):
        code = self.evaluate("outcome == arrived", "collisions_robot_obstacle == 0", "alive_at_end == 9")
        self.assertEqual(code, expect.EXIT_EXPECTATION_FAILED)
        failed = [s for s in self.said if "EXPECTATION FAILED" in s]
        self.assertEqual(failed, ["swarm: EXPECTATION FAILED: collisions_robot_obstacle == 0 "
                                  "(collisions_robot_obstacle is 3)",
                                  "swarm: EXPECTATION FAILED: alive_at_end == 9 (alive_at_end is 8)"])
        self.assertIn("swarm: 2 of 3 expectation(s) failed", self.said)

    def test_an_unknown_key_is_bad_input(self):
        self.assertEqual(self.evaluate("outcome == arrived", "colisions == 0"), 2)
        self.assertTrue(any("no key 'colisions'" in s for s in self.said))

    def test_no_summary_fails(self):
        os.remove(os.path.join(self.dir, "summary.json"))
        self.assertEqual(self.evaluate("outcome == arrived"), expect.EXIT_EXPECTATION_FAILED)
        self.assertIn("cannot read", self.said[0])


class CommandLineTest(unittest.TestCase):
    def test_an_unknown_key_is_refused_before_the_run_starts(self):
        """The stand-in world_server --check's summary_template has no `dancers` key: refused before the world
        starts, in both modes (no run directory)."""
        out = os.path.join(tempfile.mkdtemp(prefix="swarm-expect-run-"), "run")
        try:
            for mode in ([], ["--in-process"]):
                r = helpers.swarm("run", "--robots", "2", "--max-ticks", "20", "--no-pictures", "--out", out,
                                  "--expect", "ticks >= 1", "--expect", "dancers.count > 1", *mode)
                self.assertEqual(r.returncode, 2, f"{mode}: {r.stderr}")
                self.assertIn("--expect 'dancers.count > 1': summary.json will have no key 'dancers.count'",
                              r.stderr)
                self.assertIn("(nothing was run)", r.stderr)
                self.assertFalse(os.path.exists(out), f"{mode}: no run directory")
        finally:
            shutil.rmtree(os.path.dirname(out))

    def test_bad_syntax_exits_2_before_anything_runs(self):
        r = helpers.swarm("run", "--expect", "outcome = arrived", env={"SWARM_PARSE_ONLY": "1"})
        self.assertEqual(r.returncode, 2)
        self.assertIn("--expect: 'outcome = arrived': expected 'KEY OP VALUE'", r.stderr)

    def test_help_documents_it(self):
        r = helpers.swarm("run", "--help")
        self.assertEqual(r.returncode, 0)
        self.assertIn("--expect", r.stdout)
        self.assertIn("4 an --expect expectation failed", " ".join(r.stdout.split()))

    def test_a_failed_expectation_of_a_run_exits_4_naming_it(self):
        """Through the launcher with the stand-in build (fake_build/): its summary says outcome arrived."""
        out = tempfile.mkdtemp(prefix="swarm-expect-run-")
        try:
            r = helpers.swarm("run", "--robots", "2", "--max-ticks", "20", "--no-pictures", "--out", out,
                              "--expect", "ticks >= 1", "--expect", "collisions_robot_robot > 1000")
            self.assertEqual(r.returncode, 4, r.stderr)
            self.assertIn("expectation met: ticks >= 1", r.stderr)
            self.assertIn("EXPECTATION FAILED: collisions_robot_robot > 1000", r.stderr)
        finally:
            shutil.rmtree(out)


if __name__ == "__main__":
    unittest.main()
