"""`--print-dds-config` and `--dds-config FILE` of world_server and robot_agent (BUILD_DIR), docs/dds-config.md: the
listing needs none of the run's flags, follows --world-host/--interface/--domain, shows a user's file (the flag
over CYCLONEDDS_URI) after ours, and a missing or non-XML file is refused before any DDS, exit 2, naming it."""

import os
import subprocess
import tempfile
import unittest

import helpers

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")
WORLD = os.path.join(BUILD_DIR, "world_server", "world_server")
AGENT = os.path.join(BUILD_DIR, "robot_agent", "robot_agent")
TUNING = "<CycloneDDS><Domain><General><MaxMessageSize>8000B</MaxMessageSize></General></Domain></CycloneDDS>"


def run(*cmd, env=None):
    e = {k: v for k, v in os.environ.items() if k != "CYCLONEDDS_URI"}
    e.update(env or {})
    return subprocess.run(list(cmd), capture_output=True, text=True, timeout=30, env=e)


@unittest.skipUnless(os.access(WORLD, os.X_OK) and os.access(AGENT, os.X_OK), f"not built in {BUILD_DIR}")
class DdsConfigFlagsTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory(prefix="swarm-dds-config-")
        self.file = os.path.join(self.dir.name, "tuning.xml")
        with open(self.file, "w") as f:
            f.write(TUNING + "\n")

    def tearDown(self):
        self.dir.cleanup()

    def test_the_listing_follows_the_flags_and_needs_no_run(self):
        r = run(AGENT, "--print-dds-config", "--domain", "3", "--world-host", "10.9.8.7", "--interface", "10.9.8.6")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn('<Peer address="10.9.8.7:7710"/>', r.stdout)
        self.assertIn('<NetworkInterface address="10.9.8.6"/>', r.stdout)
        self.assertIn("1 of 1: swarmform's own", r.stdout)
        r = run(WORLD, "--print-dds-config", "--interface", "10.9.8.7")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("<ParticipantIndex>0</ParticipantIndex>", r.stdout)
        self.assertIn('<NetworkInterface address="10.9.8.7"/>', r.stdout)

    def test_a_users_file_comes_second_and_the_flag_wins_over_the_environment(self):
        other = os.path.join(self.dir.name, "other.xml")
        with open(other, "w") as f:
            f.write("<CycloneDDS><Domain><Tracing><Verbosity>warning</Verbosity></Tracing></Domain></CycloneDDS>")
        for exe in (WORLD, AGENT):
            r = run(exe, "--print-dds-config", env={"CYCLONEDDS_URI": f"file://{self.file}"})
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn(f"2 of 2: from CYCLONEDDS_URI {self.file}", r.stdout)
            self.assertLess(r.stdout.index("1 of 2"), r.stdout.index(TUNING))
            r = run(exe, "--print-dds-config", "--dds-config", other, env={"CYCLONEDDS_URI": self.file})
            self.assertIn(f"2 of 2: from --dds-config {other}", r.stdout)
            self.assertNotIn(TUNING, r.stdout)

    def test_a_missing_or_non_xml_file_is_refused_before_any_dds(self):
        missing = os.path.join(self.dir.name, "missing.xml")
        r = run(AGENT, "--id", "0", "--dds-config", missing, "--timeout", "1")
        self.assertEqual(r.returncode, 2)
        self.assertIn(f"robot_agent: --dds-config {missing}: no such file", r.stderr)
        text = os.path.join(self.dir.name, "text.xml")
        with open(text, "w") as f:
            f.write("MaxMessageSize = 8000\n")
        r = run(WORLD, "--scenario", os.path.join(helpers.HERE, "data", "walk4.yaml"), "--out", self.dir.name,
                env={"CYCLONEDDS_URI": text})
        self.assertEqual(r.returncode, 2)
        self.assertIn(f"CYCLONEDDS_URI {text}: is not a Cyclone DDS configuration", r.stderr)


if __name__ == "__main__":
    unittest.main()
