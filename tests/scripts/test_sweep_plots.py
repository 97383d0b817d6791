"""`swarm plot` and `swarm sweep --plot` over a sweep of the stand-in harness (fake_sweep_build/): the three
figures in PNG and SVG, titled with the grid and the commit and labelled with the grid's axes; the median's
distribution-free confidence interval against hand-computed order statistics; failure reasons grouped by kind;
a folder that is not a sweep and an unknown metric refused with exit 2."""

import os
import shutil
import tempfile
import unittest

import helpers
from swarmform import sweep_plots

FAKE = os.path.join(helpers.HERE, "fake_sweep_build")
SCENARIO = os.path.join(helpers.HERE, "data", "walk4.yaml")


class IntervalTest(unittest.TestCase):
    def test_the_median_and_its_order_statistics(self):
        # n = 10: P(2 <= B <= 8) = 1 - 2 (1 + 10) / 1024 = 0.979 >= 0.95, P(3 <= B <= 7) = 0.891 < 0.95: x_(2), x_(9).
        self.assertEqual(sweep_plots.median_interval(list(range(10, 0, -1))), (5.5, 2, 9))
        # n = 20: j = 6 (P(6 <= B <= 14) = 0.959; P(7 <= B <= 13) = 0.885): x_(6), x_(15).
        self.assertEqual(sweep_plots.median_interval(list(range(1, 21))), (10.5, 6, 15))
        # n = 5: no symmetric pair holds 95 %: the range.
        self.assertEqual(sweep_plots.median_interval([3, 1, 2, 5, 4]), (3, 1, 5))
        with self.assertRaises(ValueError):
            sweep_plots.median_interval([])

    def test_reasons_are_grouped_by_kind(self):
        self.assertEqual(sweep_plots.reason_kind("timeout: still running after 3 s (SIGKILLed)"), "timeout")
        self.assertEqual(sweep_plots.reason_kind("exit 2: bad.yaml:3: nope"), "exit N")
        self.assertEqual(sweep_plots.reason_kind("shape_error_at_goal 0.300 > 0.1"),
                         "shape_error_at_goal N > N")


class PlotTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-plot-")
        self.out = os.path.join(self.dir, "sweep")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_a_sweep_with_plot_draws_the_three_figures_labelled_with_its_grid(self):
        r = helpers.swarm("sweep", "--scenario", SCENARIO, "--seeds", "1-4", "--param", "k_goal=0.5,2", "--loss",
                          "0,0.2", "--out", self.out, "--quiet", "--plot", "--max-shape-error", "0.1",
                          build_dir=FAKE, timeout=120)
        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)  # 2-4 fail by their ends, 1 by its shape error
        self.assertIn("figures: 6 files in", r.stdout)
        figures = os.path.join(self.out, "figures")
        self.assertEqual(sorted(os.listdir(figures)), [f"{n}.{e}" for n in ("failures", "metric", "success")
                                                       for e in ("png", "svg")])
        for name in ("failures", "metric", "success"):
            with open(os.path.join(figures, f"{name}.png"), "rb") as f:
                self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n")
        with open(os.path.join(figures, "success.svg")) as f:
            svg = f.read()
        for words in ("success rate", "seeds 1-4", "16 runs", "commit", "param_k_goal", "loss"):
            self.assertTrue(words in svg, f"{words!r} not in success.svg")
        with open(os.path.join(figures, "metric.svg")) as f:
            self.assertTrue("goal_tick (median, 95 % CI)" in f.read(), "metric.svg's axis label")
        with open(os.path.join(figures, "failures.svg")) as f:
            svg = f.read()
        self.assertTrue("failures by reason (16 of 16 runs)" in svg, "failures.svg's title")
        self.assertTrue("crashed (SIGSEGV)" in svg, "failures.svg's reasons")

    def test_plot_refuses_what_is_not_a_sweep_and_an_unknown_metric(self):
        r = helpers.swarm("plot", self.dir)
        self.assertEqual(r.returncode, 2)
        self.assertIn("sweep.json: no such file", r.stderr)
        helpers.swarm("sweep", "--scenario", SCENARIO, "--seeds", "1-2", "--out", self.out, "--quiet",
                      build_dir=FAKE, timeout=120)
        r = helpers.swarm("plot", self.out, "--metric", "no_such_key")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--metric no_such_key: no such column", r.stderr)
        r = helpers.swarm("plot", self.out, "--metric", "ticks", "--out", os.path.join(self.dir, "f"))
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(len(os.listdir(os.path.join(self.dir, "f"))), 6)


if __name__ == "__main__":
    unittest.main()
