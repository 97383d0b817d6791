"""scripts/bench --quick: every part runs and bench.json holds well-formed, positive, finite figures.

No speed is asserted (a quick run on a shared 2-core machine measures nothing); a part that breaks (a program
that no longer starts, a changed output format, a world that stops counting missed ticks) fails here.
Its domains are test domains 27..35 (SWARMFORM_TEST_DOMAIN_BASE + 27.., tests/scripts/helpers.py test_domain).
"""
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
import helpers  # noqa: E402  (test_domain)


def positive(x):
    return isinstance(x, (int, float)) and math.isfinite(x) and x > 0


class BenchScript(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory(prefix="bench-test-")
        cls.out = os.path.join(cls.tmp.name, "bench.json")
        cls.proc = subprocess.run([os.path.join(ROOT, "scripts", "bench"), "--quick", "--out", cls.out,
                                   "--domain", str(helpers.test_domain(27))], capture_output=True, text=True, timeout=150)
        cls.doc = None
        if os.path.exists(cls.out):
            with open(cls.out) as f:
                cls.doc = json.load(f)

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_runs_and_prints_the_table(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        for heading in ("P1 lockstep", "P2 scale", "P3 in-process", "P4 big shapes", "Recording the readings",
                        "wrote "):
            self.assertIn(heading, self.proc.stdout)

    def test_machine_and_targets_recorded(self):
        self.assertIsNotNone(self.doc)
        m = self.doc["machine"]
        self.assertTrue(positive(m["nproc"]) and positive(m["ram_gib"]) and m["cpu_model"])
        self.assertEqual(self.doc["targets"]["p1_ratio_at_64"], 0.9)
        self.assertEqual(self.doc["targets"]["p1_ratio_at_256"], 0.8)
        self.assertTrue(self.doc["quick"])

    def test_p1_ratio_is_emulator_over_bare(self):
        rows = self.doc["parts"]["p1"]["results"]
        self.assertEqual([r["robots"] for r in rows], [4, 8])
        for r in rows:
            self.assertTrue(positive(r["emulator_ticks_per_second"]) and positive(r["bare_rounds_per_second"]))
            self.assertTrue(positive(r["emulator_whole_run_ticks_per_second"]))
            self.assertEqual(len(r["pair_ratios"]), 2)  # --quick runs two pairs; the median one is reported
            self.assertIn(r["ratio"], r["pair_ratios"])
            self.assertAlmostEqual(r["ratio"], r["emulator_ticks_per_second"] / r["bare_rounds_per_second"],
                                   delta=0.01 * r["ratio"] + 0.002)
            # The bare round carried the emulator's bytes (BENCHMARKS.md): the random walkers' 51-byte broadcasts
            # in its replies, and as many neighbours' messages a packet, of the same total size.
            wire, payload = r["emulator_wire"], r["bare_payload"]
            self.assertEqual(payload["reply_bytes"], round(wire["bytes_per_command_message"]))
            self.assertGreater(payload["reply_bytes"], 0)
            self.assertEqual(payload["readings"], round(wire["messages_per_packet"]))
            self.assertGreater(payload["readings"], 0)
            self.assertAlmostEqual(payload["readings"] * payload["message_bytes"],
                                   wire["messages_per_packet"] * wire["bytes_per_message"],
                                   delta=payload["readings"] / 2 + 1)

    def test_p2_figures(self):
        p2 = self.doc["parts"]["p2"]
        self.assertEqual((p2["robots"], p2["ticks"]), (8, 30))
        self.assertTrue(positive(p2["connect_seconds"]) and p2["connect_seconds"] < 60)
        self.assertIsInstance(p2["missed_ticks"], int)
        self.assertGreaterEqual(p2["missed_ticks"], 0)
        self.assertEqual(p2["rss_mib"]["agents_sampled"], 8)
        self.assertTrue(positive(p2["rss_mib"]["agents_max"]) and positive(p2["rss_mib"]["world"]))
        # PSS (forked agents share pages, so it is below RSS) and the drops split by socket owner.
        self.assertEqual(p2["pss_mib"]["agents_sampled"], 8)
        self.assertTrue(0 < p2["pss_mib"]["agents_max"] <= p2["rss_mib"]["agents_max"])
        self.assertEqual(set(p2["udp_socket_drops"]), {"world_sockets", "agent_sockets"})
        self.assertGreaterEqual(p2["cpu_percent_of_one_core"]["agents_total"], 0)
        self.assertLessEqual(p2["ticks_with_a_miss"], p2["missed_ticks"])
        self.assertLessEqual(p2["most_misses_in_one_tick"], 8)
        late = p2["late_commands"]  # None when no command came in after its tick
        if late is not None:
            self.assertLessEqual(late["sent_after_deadline"], late["count"])
            self.assertGreaterEqual(late["answered_ms"]["max"], late["answered_ms"]["median"])
        pub = p2["world_publish_per_round"]  # parsed from the world's profile line: None if it changed shape
        self.assertTrue(positive(pub["wall_ms"]) and 0 <= pub["on_cpu_ms"] <= pub["wall_ms"] * 1.05 + 0.05)
        self.assertGreaterEqual(pub["preempted"], 0)
        self.assertGreaterEqual(p2["udp_receive_buffer_errors"], 0)

    def test_p3_figures(self):
        rows = self.doc["parts"]["p3"]["results"]
        self.assertEqual([(r["robots"], r["behaviour"]) for r in rows], [(100, "paper"), (100, "random_walk")])
        for r in rows:
            self.assertTrue(all(positive(x) for x in r["samples"]))
            self.assertEqual(r["best"], max(r["samples"]))
            self.assertTrue(all(positive(v) for v in r["split_us_per_robot_tick"].values()))
            self.assertGreater(r["messages_per_robot"], 0)

    def test_p4_figures(self):
        p4 = self.doc["parts"]["p4"]
        self.assertEqual([c["labels"] for c in p4["cases"]], [100, 400])
        for c in p4["cases"]:
            self.assertEqual(c["robots"], c["labels"])
            self.assertTrue(positive(c["us_per_robot_tick"]) and positive(c["cpu_us_per_robot_tick"]))
        self.assertTrue(positive(p4["ratio_largest_to_smallest"]["cpu"]))

    def test_recording_figures(self):
        rows = self.doc["parts"]["recording"]["results"]
        self.assertEqual([(r["behaviour"], r["sensors"]) for r in rows], [("diffusion", 15), ("phototaxis", 17)])
        for r in rows:
            self.assertTrue(all(positive(v) for v in r["us_per_robot_tick"].values()))
            self.assertTrue(positive(r["ratio_recording"]) and positive(r["ratio_tick"]))
            self.assertTrue(positive(r["bytes_per_robot_tick"]["readings_csv"]))


if __name__ == "__main__":
    unittest.main()
