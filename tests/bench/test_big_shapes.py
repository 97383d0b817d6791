"""bench/inprocess/bench_big_shapes.py --quick runs and prints its JSON line with every figure positive (issue
22 point 4). Asserts no speed: only that the machinery works end to end."""
import json
import os
import subprocess
import sys
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


class BigShapesQuick(unittest.TestCase):
    def test_quick_prints_positive_figures_for_each_block(self):
        proc = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "inprocess", "bench_big_shapes.py"),
                               "--quick"], capture_output=True, text=True, timeout=120)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        out = json.loads(proc.stdout.strip().splitlines()[-1])
        self.assertEqual(out["ticks"], 20)
        self.assertEqual([c["labels"] for c in out["cases"]], [100, 400])
        for case in out["cases"]:
            self.assertEqual(case["robots"], case["labels"])
            self.assertGreater(case["us_per_robot_tick"], 0)
            self.assertGreater(case["cpu_us_per_robot_tick"], 0)
        self.assertGreater(out["ratio_largest_to_smallest"]["wall"], 0)

    def test_a_size_without_a_block_is_refused_by_name(self):
        proc = subprocess.run([sys.executable, os.path.join(ROOT, "bench", "inprocess", "bench_big_shapes.py"),
                               "--sizes", "100,7"], capture_output=True, text=True, timeout=60)
        self.assertEqual(proc.returncode, 2)
        self.assertIn("no block of 7 labels", proc.stderr)


if __name__ == "__main__":
    unittest.main()
