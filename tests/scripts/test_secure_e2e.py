"""`swarm run --secure` against the real world_server and robot_agent (BUILD_DIR), on DDS test domains 60 and 61
(tests/support/test_domain.hpp). Participants outside the run are tests/integration/outsider.cpp.

- the paper's scenario, lockstep, arrives under DDS Security; every private key is 0600, the directory 0700,
  the CA's key gone;
- meanwhile a participant with no certificate and one with a certificate of another authority, on the same
  domain, receive 0 samples and match no reader with their writes, though discovery shows them the world;
- robot 3 of the run, authenticated, claims other robots' ids: the world refuses each for its identity;
- the same listener with the run's observer identity does hear (the mission, the world state): the control;
- robot 3's certificate cannot subscribe to robot 4's packets (and can to its own);
- a key readable by others is refused by the programs, naming the file.
Each wait has a deadline; every process started here is killed by pid; temporary folders are removed.
"""

import json
import os
import re
import shutil
import signal
import stat
import subprocess
import tempfile
import time
import unittest

import helpers
from swarmform import security

BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")
OUTSIDER = os.path.join(BUILD_DIR, "tests", "integration", "outsider")
AGENT = os.path.join(BUILD_DIR, "robot_agent", "robot_agent")
PAPER = os.path.join(helpers.ROOT, "scenarios", "paper.yaml")
ROBOTS = 9  # the paper scenario's
LISTEN_LIMIT_S = 600  # the outsider's own upper bound; they are stopped when the run ends


def start(argv, out_path):
    f = open(out_path, "w")
    try:
        return subprocess.Popen(argv, stdout=f, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
    finally:
        f.close()


def stop(p):
    if p.poll() is None:
        p.kill()
    p.wait(timeout=10)


def counts(text, prefix):
    m = re.search(prefix + r" (.*)$", text, re.M)
    if not m:
        raise AssertionError(f"no '{prefix}' line in:\n{text}")
    return {k: int(v) for k, v in (kv.split("=") for kv in m.group(1).split())}


@unittest.skipUnless(os.access(OUTSIDER, os.X_OK), f"outsider is not built in {BUILD_DIR}")
class SecureRunTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-secure-")
        self.procs = []

    def tearDown(self):
        for p in self.procs:
            stop(p)
        shutil.rmtree(self.dir)

    def spawn(self, argv, name):
        p = start(argv, os.path.join(self.dir, name))
        self.procs.append(p)
        return p

    def output(self, p, name, timeout):
        p.wait(timeout=timeout)
        with open(os.path.join(self.dir, name)) as f:
            return f.read()

    def test_a_secure_run_arrives_and_nobody_outside_it_hears_or_is_heard(self):
        domain = helpers.test_domain(60)
        out = os.path.join(self.dir, "run")
        # A stranger with a certificate: another run's authority (made here the same way).
        foreign = security.make_security_dir(os.path.join(self.dir), ROBOTS, domain)
        # The outsiders listen through the whole run (the launcher's certificates and the world's start take
        # their time on a loaded machine) and are stopped once it has ended: a window of the run's own length.
        listen = ["listen", "--robots", str(ROBOTS), "--seconds", str(LISTEN_LIMIT_S)]
        bare = self.spawn([OUTSIDER, "--domain", str(domain)] + listen, "bare.txt")
        stranger = self.spawn([OUTSIDER, "--domain", str(domain), "--security-dir", foreign, "--identity", "robot-3"]
                              + listen, "stranger.txt")
        run = subprocess.Popen([helpers.SWARM, "run", "--secure", "--scenario", PAPER, "--mode", "lockstep",
                                "--domain", str(domain), "--out", out, "--no-pictures"],
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               env=dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=BUILD_DIR))
        self.procs.append(run)
        # Robot 3 of this run, once its identity exists: claims the others' ids while the run goes.
        sec = os.path.join(out, "security")
        deadline = time.monotonic() + 60
        while not os.path.exists(os.path.join(sec, f"robot-{ROBOTS - 1}.permissions.p7s")):
            self.assertLess(time.monotonic(), deadline, "the launcher made no security directory in 60 s")
            self.assertIsNone(run.poll(), "the launcher ended before making its security directory")
            time.sleep(0.05)
        time.sleep(0.5)  # the last file is written (created first, then filled)
        # It claims for 4 s from the mission's arrival, so the world (up by then) meets its claims.
        impostor = self.spawn([OUTSIDER, "--domain", str(domain), "--security-dir", sec, "--identity", "robot-3",
                               "impostor", "--robots", str(ROBOTS), "--seconds", "4"], "impostor.txt")
        # The control: the same listener with this run's observer identity hears the mission and the world state.
        observer = self.spawn([OUTSIDER, "--domain", str(domain), "--security-dir", sec, "--identity", "observer"]
                              + listen, "observer.txt")
        text, _ = run.communicate(timeout=240)
        self.assertEqual(run.returncode, 0, text)
        for p in (bare, stranger, observer, impostor):
            if p.poll() is None:
                p.send_signal(signal.SIGTERM)  # each prints its counts and exits 0 on SIGTERM

        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        self.assertEqual(summary["outcome"], "arrived", text)
        self.assertEqual(summary["end_reason"], "completed")
        self.assertEqual(summary["alive_at_end"], ROBOTS)

        # Keys: 0600, in a 0700 directory; the CA's key is gone once everything is signed.
        self.assertEqual(stat.S_IMODE(os.stat(sec).st_mode), 0o700)
        keys = sorted(n for n in os.listdir(sec) if n.endswith(".key"))
        self.assertEqual(keys, sorted(["world.key", "observer.key"] + [f"robot-{k}.key" for k in range(ROBOTS)]))
        for k in keys:
            self.assertEqual(stat.S_IMODE(os.stat(os.path.join(sec, k)).st_mode), 0o600, k)
        self.assertFalse(os.path.exists(os.path.join(sec, "ca.key")))

        # The impostor's claims reached the world (matched), which refused every one for its identity.
        imp = counts(self.output(impostor, "impostor.txt", 30), "impostor")
        self.assertGreaterEqual(imp["sent"], 3)
        self.assertGreaterEqual(imp["writers_matched"], 1, "robot 3's own writer must reach the world")
        # Each refused (a claim written after the world ended is lost with it; none is accepted).
        self.assertGreaterEqual(summary["input_dropped"]["refused_claims"], 1)
        self.assertLessEqual(summary["input_dropped"]["refused_claims"], imp["sent"])
        with open(os.path.join(out, "logs", "world_console.log")) as f:
            world_log = f.read()
        self.assertIn("the claimant is authenticated as robot 3, not robot", world_log)
        self.assertNotIn("claimed by pid 1 (", world_log, "an impostor's claim was accepted")

        # The observer of this run reads (the outsiders' zeros below are not a deaf program's), and its own
        # permissions refused it every robot's packets and every command writer.
        obs = counts(self.output(observer, "observer.txt", 30), "outsider")
        self.assertGreater(obs["samples"], 0)
        self.assertEqual((obs["readers"], obs["writers"], obs["skipped"]), (2, 0, 2 * ROBOTS))

        # Outsiders: discovery shows them the world, nothing else passes either way.
        for p, name in ((bare, "bare.txt"), (stranger, "stranger.txt")):
            c = counts(self.output(p, name, 40), "outsider")
            self.assertEqual(c["samples"], 0, name)
            self.assertEqual(c["readers_matched"], 0, name)
            self.assertEqual(c["writers_matched"], 0, name)
            self.assertGreaterEqual(c["participants_seen"], 1, f"{name}: it never even saw the world: a vacuous test")
            # The stranger (robot 3 of another authority) reads the mission and robot/3, writes in robot/3.
            self.assertGreaterEqual(c["readers"], 2, name)
            self.assertGreaterEqual(c["writers"], 1, name)
        # Their claims (pid 1, id 0..8 from writers in robot/K) never reached the world: nothing refused for a
        # wrong nonce (the outsiders stamp none), only the impostor's claims counted.
        self.assertNotIn("another run", world_log)

    def test_robot_3_cannot_subscribe_to_robot_4_and_keys_must_be_private(self):
        domain = helpers.test_domain(61)
        sec = security.make_security_dir(self.dir, 5, domain)
        base = [OUTSIDER, "--domain", str(domain), "--security-dir", sec, "--identity", "robot-3", "peek"]
        own = subprocess.run(base + ["--partition-of", "3"], capture_output=True, text=True, timeout=60)
        self.assertEqual(own.returncode, 0, own.stdout + own.stderr)
        self.assertIn("subscribed robot/3", own.stdout)
        other = subprocess.run(base + ["--partition-of", "4"], capture_output=True, text=True, timeout=60)
        self.assertEqual(other.returncode, 4, other.stdout + other.stderr)
        self.assertIn("refused: dds_create_reader(sensor): Not Allowed By Security", other.stdout)

        # A key others may read is refused before DDS starts, naming the file and its mode.
        key = os.path.join(sec, "robot-2.key")
        os.chmod(key, 0o644)
        bad = subprocess.run([AGENT, "--id", "2", "--domain", str(domain), "--security-dir", sec, "--timeout", "5"],
                             capture_output=True, text=True, timeout=60)
        self.assertEqual(bad.returncode, 2, bad.stdout + bad.stderr)
        self.assertIn(f"private key '{key}' has mode 0644", bad.stderr)


if __name__ == "__main__":
    unittest.main()
