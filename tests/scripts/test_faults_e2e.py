"""`scripts/swarm run --fault` against the real programs (BUILD_DIR): a scheduled restart after a kill makes the
launcher start a new agent with that id, which proves its claim with the id's token and rejoins, while an agent
started by hand may take a dead robot's id only with --open-rejoin (DDS test domain 47); an in-process run takes
the same faults; a bad fault is refused by the world's check with the flag named, exit 2, no traceback. The world's
status channel (--status-fd, docs/status-channel.md) is read here without the launcher: every moment a JSON line with
its fields, the restart fault's included. Every wait has a deadline and no process is left behind."""

import json
import os
import select
import shutil
import signal
import subprocess
import tempfile
import threading
import time
import unittest

import helpers

SCENARIO = os.path.join(helpers.HERE, "data", "walk4.yaml")
BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(helpers.ROOT, "build")


def wait_for(predicate, seconds):
    """Polls `predicate` every 0.1 s until it holds or `seconds` pass; returns whether it held."""
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.1)
    return predicate()


def events(run_dir):
    with open(os.path.join(run_dir, "events.jsonl"), encoding="utf-8") as f:
        return [json.loads(line) for line in f if line.strip()]


@unittest.skipUnless(os.access(os.path.join(BUILD_DIR, "world_server", "world_server"), os.X_OK),
                     f"world_server is not built in {BUILD_DIR}")
class FaultsEndToEndTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-faults-e2e-")
        self.out = os.path.join(self.dir, "run")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def swarm_run(self, *extra):
        return helpers.swarm("run", "--scenario", SCENARIO, "--robots", "4", "--no-pictures", "--out", self.out,
                             *extra, build_dir=BUILD_DIR, timeout=180)

    def test_a_restart_after_a_kill_starts_a_new_agent_that_rejoins(self):
        r = self.swarm_run("--max-ticks", "1500", "--domain", str(helpers.test_domain(47)),
                           "--fault", "kill:1@20", "--fault", "restart:1@40")
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        self.assertNotIn("Traceback", r.stderr)
        self.assertIn("swarm: restarted agent 1 at tick 40 (pid ", r.stderr)
        ev = events(self.out)
        restart = [e for e in ev if e["kind"] == "fault" and e["detail"].startswith("restart:1@40:")]
        self.assertEqual([(e["tick"], e["id"]) for e in restart], [(40, 1)])
        claims = [e for e in ev if e["kind"] == "agent_connected" and e["id"] == 1]
        self.assertEqual(len(claims), 2, claims)
        self.assertNotEqual(claims[0]["detail"], claims[1]["detail"], "the same pid claimed twice")
        rejoins = [e for e in ev if e["kind"] == "rejoin" and e["id"] == 1]
        self.assertEqual(len(rejoins), 1)
        self.assertGreaterEqual(rejoins[0]["tick"], 40)
        with open(os.path.join(self.out, "summary.json"), encoding="utf-8") as f:
            self.assertEqual(json.load(f)["alive_at_end"], 4)
        # agents.json names the new agent, and nothing of the run is left running.
        with open(os.path.join(self.out, "agents.json"), encoding="utf-8") as f:
            pids = {int(k): v for k, v in json.load(f).items()}
        # The restarted agent's claim was issued: the launcher gave it robot 1's token (docs/wire.md, Claim
        # proofs); a claim without one would say ", unissued", and a world holding the run's secret refuses it.
        self.assertRegex(claims[1]["detail"], rf"^pid {pids[1]} \(participant [0-9a-f]{{32}}\)$")
        self.assertEqual([p for p in pids.values() if helpers.pid_alive(p)], [], "agents left running")

    def test_a_restart_due_before_the_kill_is_seen_waits_for_the_death(self):
        # Realtime: the SIGKILLed agent's death is seen ~0.5 s (~5 ticks) after tick 20, so at tick 21 the old
        # owner still holds id 1; the world asks for the new agent once the death is seen, and it rejoins.
        r = self.swarm_run("--mode", "realtime", "--max-ticks", "150", "--domain", str(helpers.test_domain(47)),
                           "--fault", "kill:1@20", "--fault", "restart:1@21")
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        ev = events(self.out)
        death = [e["tick"] for e in ev if e["kind"] == "death" and e["id"] == 1]
        restart = [e for e in ev if e["kind"] == "fault" and e["detail"].startswith("restart:1@21:")]
        self.assertEqual(len(death), 1, ev)
        self.assertEqual(len(restart), 1, ev)
        self.assertGreaterEqual(restart[0]["tick"], max(21, death[0]))
        self.assertEqual([e["kind"] for e in ev if e["kind"] == "claim_refused"], [])
        self.assertEqual(len([e for e in ev if e["kind"] == "rejoin" and e["id"] == 1]), 1, ev)

    def test_an_agent_started_by_hand_cannot_take_a_dead_robots_id_and_the_launcher_says_so(self):
        # Without --secure: robot 1 is killed at tick 20; a robot_agent started by hand with the run's nonce (read
        # off an agent's command line, as any local user can, or from the mission) claims id 1. The world holds
        # the run's secret, so it refuses the claim (the agent exits 8) and the launcher shows the world's line,
        # naming the claimant's participant. With --open-rejoin the same agent takes the id (a rejoin).
        for open_rejoin in (False, True):
            with self.subTest(open_rejoin=open_rejoin):
                shutil.rmtree(self.out, ignore_errors=True)
                env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=BUILD_DIR)
                domain = helpers.test_domain(47)
                argv = [helpers.SWARM, "run", "--scenario", SCENARIO, "--robots", "4", "--max-ticks", "1000000",
                        "--no-pictures", "--domain", str(domain), "--out", self.out, "--kill", "1@20"]
                p = subprocess.Popen(argv + (["--open-rejoin"] if open_rejoin else []), env=env,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
                lines: list[str] = []  # the launcher's stderr, as it comes (its status lines are not buffered)
                reader = threading.Thread(target=lambda: lines.extend(iter(p.stderr.readline, "")), daemon=True)
                reader.start()
                stranger = None
                try:
                    self.assertTrue(wait_for(lambda: any("world: death id=1 " in x for x in lines), 60.0), lines)
                    with open(os.path.join(self.out, "agents.json"), encoding="utf-8") as f:
                        agent0 = json.load(f)["0"]
                    with open(f"/proc/{agent0}/cmdline", "rb") as f:
                        cmdline = f.read().split(b"\0")
                    nonce = cmdline[cmdline.index(b"--run-nonce") + 1].decode()
                    stranger = subprocess.Popen(
                        [os.path.join(BUILD_DIR, "robot_agent", "robot_agent"), "--id", "1", "--domain",
                         str(domain), "--run-nonce", nonce, "--timeout", "30"],
                        stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
                    if open_rejoin:
                        self.assertTrue(wait_for(lambda: any("world: rejoin id=1 " in x for x in lines), 40.0),
                                        lines)
                    else:
                        _, agent_err = stranger.communicate(timeout=40)
                        self.assertEqual(stranger.returncode, 8, agent_err)
                        self.assertIn("refused: this run's ids go only to agents its starter issued", agent_err)
                finally:
                    p.send_signal(signal.SIGINT)
                    p.wait(timeout=60)
                    reader.join(timeout=10)
                    p.stderr.close()
                    if stranger is not None and stranger.poll() is None:
                        stranger.kill()
                    if stranger is not None:
                        stranger.communicate(timeout=10)
                err = "".join(lines)
                self.assertEqual(p.returncode, 130, err)
                with open(os.path.join(self.out, "summary.json"), encoding="utf-8") as f:
                    summary = json.load(f)
                if open_rejoin:
                    self.assertRegex(err, rf"world: world_server: id 1 claimed by pid {stranger.pid} "
                                          r"\(participant [0-9a-f]{32}\), unissued")
                    self.assertEqual([r["id"] for r in summary["rejoins"]], [1])
                    self.assertEqual(summary["input_dropped"]["unproven_claims"], 0)
                else:
                    self.assertRegex(err, rf"world: world_server: refused a claim of id 1 from pid {stranger.pid} "
                                          r"\(participant [0-9a-f]{32}\)")
                    self.assertEqual(summary["rejoins"], [])
                    self.assertGreaterEqual(summary["input_dropped"]["unproven_claims"], 1)

    def test_an_in_process_run_takes_the_faults(self):
        r = self.swarm_run("--in-process", "--max-ticks", "60", "--fault", "kill:1@20", "--fault", "restart:1@40",
                           "--fault", "stall:2@5+10", "--fault", "wheel:3/right@10", "--fault", "loss:all@30+5")
        self.assertEqual(r.returncode, 0, f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
        self.assertNotIn("do(es) not apply", r.stderr)
        kinds = sorted((e["tick"], e["kind"], e["id"]) for e in events(self.out)
                       if e["kind"] in ("fault", "fault_end", "rejoin"))
        self.assertEqual(kinds, [(5, "fault", 2), (10, "fault", 3), (15, "fault_end", 2), (30, "fault", -1),
                                 (35, "fault_end", -1), (40, "fault", 1), (40, "rejoin", 1)])

    def test_a_bad_fault_is_refused_naming_the_flag(self):
        r = self.swarm_run("--max-ticks", "10", "--fault", "wheel:1@5")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("--fault 'wheel:1@5': which wheel", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        r = self.swarm_run("--max-ticks", "10", "--fault", "restart:1@5")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("robot 1 is not killed before tick 5", r.stderr)


if __name__ == "__main__":
    unittest.main()


def _read_status(fd, deadline_s, on_event):
    """The status lines on `fd` until end-of-file (or the deadline: then the test fails on what came), each as
    (raw bytes, parsed JSON or None); `on_event(obj)` sees each object as it comes."""
    lines, buf = [], b""
    end = time.monotonic() + deadline_s
    while time.monotonic() < end:
        ready, _, _ = select.select([fd], [], [], 0.2)
        if not ready:
            continue
        chunk = os.read(fd, 65536)
        if not chunk:
            return lines, True
        buf += chunk
        *whole, buf = buf.split(b"\n")
        for raw in whole:
            try:
                obj = json.loads(raw)
            except ValueError:
                obj = None
            lines.append((raw, obj))
            if isinstance(obj, dict):
                on_event(obj)
    return lines, False


@unittest.skipUnless(os.access(os.path.join(BUILD_DIR, "world_server", "world_server"), os.X_OK) and
                     os.access(os.path.join(BUILD_DIR, "robot_agent", "robot_agent"), os.X_OK),
                     f"world_server and robot_agent are not built in {BUILD_DIR}")
class StatusChannelTest(unittest.TestCase):
    """world_server --status-fd (docs/status-channel.md), without the launcher: the test is the starter. Its
    restart event is the one fault only a starter can carry out. DDS test domain 47 (this module's)."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-status-")
        self.out = os.path.join(self.dir, "run")
        os.makedirs(self.out)
        self.agents: dict[int, subprocess.Popen] = {}
        self.world = None

    def tearDown(self):
        for p in list(self.agents.values()) + ([self.world] if self.world else []):
            if p.poll() is None:
                p.kill()
            p.wait(timeout=30)
        shutil.rmtree(self.dir)

    def run_world(self, robots, start_ids, *extra):
        """Starts the world with a status pipe, and at `ready` the agents `start_ids` (their pids in agents.json);
        returns the status lines (raw, parsed), whether end-of-file came, and the world's stdout lines."""
        domain = helpers.test_domain(47)
        agents_json = os.path.join(self.out, "agents.json")
        r, w = os.pipe()
        try:
            with open(os.path.join(self.dir, "stdout"), "wb") as out, open(os.path.join(self.dir, "stderr"),
                                                                            "wb") as err:
                self.world = subprocess.Popen(
                    [os.path.join(BUILD_DIR, "world_server", "world_server"), "--scenario", SCENARIO, "--robots",
                     str(robots), "--out", self.out, "--domain", str(domain), "--agent-pids", agents_json,
                     "--status-fd", str(w), *extra], stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                    pass_fds=(w,))
        finally:
            os.close(w)  # the world's is its only write end: end-of-file when it exits

        def on_event(obj):
            if obj.get("event") != "ready":
                return
            for rid in start_ids:
                self.agents[rid] = subprocess.Popen(
                    [os.path.join(BUILD_DIR, "robot_agent", "robot_agent"), "--id", str(rid), "--domain",
                     str(domain), "--run-nonce", obj["run_nonce"], "--timeout", "60"],
                    stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            with open(agents_json + ".tmp", "w") as f:
                json.dump({str(k): p.pid for k, p in self.agents.items()}, f)
            os.replace(agents_json + ".tmp", agents_json)

        try:
            lines, eof = _read_status(r, 150.0, on_event)
        finally:
            os.close(r)
        self.world.wait(timeout=60)
        with open(os.path.join(self.dir, "stdout"), encoding="utf-8") as f:
            stdout = f.read().splitlines()
        return lines, eof, stdout

    def check_lines(self, lines, stdout):
        """Every line a JSON object of version 1 with a known event and its documented fields (world_status.py
        holds the table the launcher reads by), and every `line` printed on stdout as it says."""
        from swarmform import world_status
        evs = []
        for raw, obj in lines:
            self.assertIsInstance(obj, dict, raw)
            self.assertEqual(obj["v"], 1, raw)
            ev = world_status.parse(raw)
            self.assertNotIsInstance(ev, str, f"{raw!r}: {ev}")
            if "line" in obj:
                self.assertIn(obj["line"], stdout)
            evs.append(obj)
        return evs

    def test_a_run_says_each_moment_on_its_status_channel_as_a_json_line(self):
        lines, eof, stdout = self.run_world(2, [0, 1], "--max-ticks", "60", "--run-nonce", "00000000000000ab",
                                            "--connect-timeout", "60", "--fault", "kill:1@10", "--fault",
                                            "restart:1@12")
        self.assertTrue(eof, lines)
        self.assertEqual(self.world.returncode, 0, lines)
        evs = self.check_lines(lines, stdout)
        names = [e["event"] for e in evs]
        self.assertEqual(evs[0], {"v": 1, "event": "ready", "domain": helpers.test_domain(47),
                                  "run_nonce": "00000000000000ab", "line": evs[0]["line"]})
        self.assertEqual(sorted((e["id"], e["pid"]) for e in evs if e["event"] == "claimed"),
                         [(0, self.agents[0].pid), (1, self.agents[1].pid)])
        self.assertEqual([e["agents"] for e in evs if e["event"] == "connected"], [2])
        self.assertLess(names.index("claimed"), names.index("connected"))
        progress = [e for e in evs if e["event"] == "progress"]
        self.assertTrue(progress, names)
        self.assertEqual(progress[-1]["tick"], 60)
        self.assertEqual(progress[-1]["robots"], 2)
        self.assertEqual(progress[-1]["alive"], 1)  # robot 1 was killed; nobody started it again
        restarts = [e for e in evs if e["event"] == "restart"]
        self.assertEqual(len(restarts), 1, names)
        self.assertEqual(restarts[0]["id"], 1)
        self.assertGreaterEqual(restarts[0]["tick"], 12)
        self.assertEqual(evs[-1]["event"], "done")
        self.assertEqual((evs[-1]["ticks"], evs[-1]["run_dir"]), (60, self.out))
        self.assertTrue(os.path.isfile(evs[-1]["summary"]))
        self.assertNotIn("gave_up", names)
        self.assertNotIn("run_ended", names)

    def test_a_missing_agent_is_a_gave_up_event_naming_it(self):
        lines, eof, stdout = self.run_world(2, [0], "--max-ticks", "60", "--connect-timeout", "3")
        self.assertTrue(eof, lines)
        self.assertEqual(self.world.returncode, 3, lines)
        evs = self.check_lines(lines, stdout)
        self.assertEqual([e["event"] for e in evs if e["event"] != "connecting"], ["ready", "claimed", "gave_up"])
        gave_up = evs[-1]
        self.assertEqual((gave_up["robots"], gave_up["claimed"], gave_up["missing"], gave_up["why"]),
                         (2, 1, [1], "not_claimed"))
        self.assertEqual(gave_up["timeout_s"], 3)

    def test_an_agent_that_knows_the_worlds_pid_waits_for_its_claim_answer_while_the_world_is_held(self):
        # The world's main thread held on its status pipe (full: nobody reads it, as when the launcher was busy
        # starting 1024 agents) after its mission is out: the agent takes the mission and claims, and no answer
        # comes for 6 s, past its --timeout of 2 s. Its world's process is there, so it waits; once the pipe is
        # read the world answers and the run goes. (Before, it gave up at 2 s: "did not answer the claim".)
        domain = helpers.test_domain(47)
        r, w = os.pipe()
        os.set_blocking(w, False)
        try:
            while True:
                os.write(w, b"\n" * 4096)
        except BlockingIOError:
            pass
        os.set_blocking(w, True)
        nonce = "00000000000000cd"
        try:
            with open(os.path.join(self.dir, "stdout"), "wb") as out, open(os.path.join(self.dir, "stderr"),
                                                                            "wb") as err:
                self.world = subprocess.Popen(
                    [os.path.join(BUILD_DIR, "world_server", "world_server"), "--scenario", SCENARIO, "--robots",
                     "1", "--out", self.out, "--domain", str(domain), "--run-nonce", nonce, "--max-ticks", "30",
                     "--connect-timeout", "60", "--status-fd", str(w)], stdin=subprocess.DEVNULL, stdout=out,
                    stderr=err, pass_fds=(w,))
        finally:
            os.close(w)
        try:
            agent_err = os.path.join(self.dir, "agent.err")
            with open(agent_err, "wb") as err:
                self.agents[0] = subprocess.Popen(
                    [os.path.join(BUILD_DIR, "robot_agent", "robot_agent"), "--id", "0", "--domain", str(domain),
                     "--run-nonce", nonce, "--timeout", "2", "--world-pid", str(self.world.pid)],
                    stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err)
            time.sleep(6.0)
            with open(agent_err) as f:
                self.assertIsNone(self.agents[0].poll(), f.read())
            lines, eof = _read_status(r, 120.0, lambda obj: None)  # the filler's empty lines, then the world's
        finally:
            os.close(r)
        self.assertEqual(self.world.wait(timeout=60), 0, lines)
        with open(agent_err) as f:
            self.assertEqual(self.agents[0].wait(timeout=30), 0, f.read())
        self.assertIn("done", [obj.get("event") for _, obj in lines if isinstance(obj, dict)])

    def test_an_agent_that_knows_the_worlds_pid_waits_for_the_mission_while_the_world_is_stopped(self):
        # The world stopped as it starts, before its mission is out (a host busy starting 1024 agents is slower
        # still): an agent with --timeout 1 and the world's pid waits, takes the mission when the world runs, and
        # the run completes. (Before, it said "no world on DDS domain ... within 1 s".)
        domain = helpers.test_domain(47)
        with open(os.path.join(self.dir, "stdout"), "wb") as out, open(os.path.join(self.dir, "stderr"), "wb") as err:
            self.world = subprocess.Popen(
                [os.path.join(BUILD_DIR, "world_server", "world_server"), "--scenario", SCENARIO, "--robots", "1",
                 "--out", self.out, "--domain", str(domain), "--max-ticks", "30", "--connect-timeout", "60"],
                stdin=subprocess.DEVNULL, stdout=out, stderr=err)
        os.kill(self.world.pid, signal.SIGSTOP)
        agent_err = os.path.join(self.dir, "agent.err")
        with open(agent_err, "wb") as err:
            self.agents[0] = subprocess.Popen(
                [os.path.join(BUILD_DIR, "robot_agent", "robot_agent"), "--id", "0", "--domain", str(domain),
                 "--timeout", "1", "--world-pid", str(self.world.pid)],
                stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err)
        time.sleep(3.0)
        still = self.agents[0].poll()
        os.kill(self.world.pid, signal.SIGCONT)
        with open(agent_err) as f:
            self.assertIsNone(still, f.read())
        self.assertEqual(self.world.wait(timeout=60), 0)
        self.assertEqual(self.agents[0].wait(timeout=30), 0)

    def test_a_status_fd_that_is_not_open_for_writing_is_refused(self):
        for fd in ("1", "57"):
            with self.subTest(fd=fd):
                p = subprocess.run([os.path.join(BUILD_DIR, "world_server", "world_server"), "--scenario",
                                    SCENARIO, "--out", self.out, "--status-fd", fd], capture_output=True, text=True,
                                   timeout=60)
                self.assertEqual(p.returncode, 2, p.stderr)
                self.assertIn(f"--status-fd {fd}: not an open file descriptor", p.stderr)

    def test_a_status_reader_that_has_gone_is_said_once_and_the_world_goes_on(self):
        # The read end closed before the world writes: no SIGPIPE death; one line, then the world's own end
        # (no agents here: exit 3 at the connect timeout).
        r, w = os.pipe()
        os.close(r)
        try:
            p = subprocess.run([os.path.join(BUILD_DIR, "world_server", "world_server"), "--scenario", SCENARIO,
                                "--robots", "1", "--out", self.out, "--domain", str(helpers.test_domain(47)),
                                "--connect-timeout", "1", "--status-fd", str(w)], capture_output=True, text=True,
                               timeout=60, pass_fds=(w,))
        finally:
            os.close(w)
        self.assertEqual(p.returncode, 3, p.stderr)
        self.assertEqual(p.stderr.count(f"--status-fd {w}: cannot write (Broken pipe); no more status lines"), 1,
                         p.stderr)
        self.assertIn("world ready", p.stdout)
