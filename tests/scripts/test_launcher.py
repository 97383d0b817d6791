"""The launcher's process handling, against stand-ins of world_server and robot_agent (tests/scripts/fake_build)
that keep their command-line contract: agents started and handed to the world by pid, agents.json, the run
directory and runs/latest, `swarm kill`, failures passed on, and no process left behind -- Ctrl-C included."""

import io
import json
import os
import shutil
import signal
import subprocess
import tempfile
import time
import unittest

import helpers
from swarmform import child_death, claims, exit_codes, jsonfile, launcher


def agent_pids(run_dir):
    with open(os.path.join(run_dir, "agents.json")) as f:
        return {int(k): v for k, v in json.load(f).items()}


def wait_for(predicate, seconds):
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if predicate():
            return True
        time.sleep(0.05)
    return False


class LauncherTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-launch-")
        self.scenario = os.path.join(self.dir, "s.yaml")
        with open(self.scenario, "w") as f:
            f.write("robots: 4\n")
        self.started = []

    def tearDown(self):
        for p in self.started:  # never leave a launcher behind, even when an assertion failed
            if p.poll() is None:
                p.kill()
            p.communicate(timeout=30)
        shutil.rmtree(self.dir)

    def assert_all_gone(self, pids):
        self.assertTrue(wait_for(lambda: not any(helpers.pid_alive(p) for p in pids), 5.0),
                        f"left behind: {[p for p in pids if helpers.pid_alive(p)]}")

    def test_run_hands_agent_pids_to_the_world_and_cleans_up(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "3", "--max-ticks", "40", "--kill",
                          "1@20", "--out", out, "--domain", "77", "--no-pictures",
                          env={"FAKE_AGENT_EXIT_S": "0.5"})
        self.assertEqual(r.returncode, 0, r.stderr)
        pids = agent_pids(out)
        self.assertEqual(sorted(pids), [0, 1, 2])
        with open(os.path.join(out, "world_args.json")) as f:
            world_args = json.load(f)
        # The world starts first and reads the agents' pids from agents.json (for --kill) once they run; it
        # and every agent get the run's nonce.
        nonce = world_args[world_args.index("--run-nonce") + 1]
        self.assertRegex(nonce, r"^[0-9a-f]{16}$")
        for flag in (["--kill", "1@20"], ["--domain", "77"], ["--robots", "3"], ["--out", out],
                     ["--agent-pids", os.path.join(out, "agents.json")]):
            i = world_args.index(flag[0])
            self.assertEqual(world_args[i:i + 2], flag)
        for rid in pids:
            self.assertTrue(os.path.exists(os.path.join(out, "logs", f"agent-{rid}.log")))
        self.assertIn("3 robot agents", r.stderr)
        self.assertIn("40 ticks in", r.stderr)
        self.assertNotIn("killed", r.stderr)  # the agents exited by themselves before the deadline
        self.assertFalse(os.path.exists(os.path.join(out, "pictures")))
        self.assert_all_gone(pids.values())

    def test_the_launcher_follows_the_worlds_status_channel_not_its_printed_words(self):
        # The same run with every human line of the world in other words: the agents still start at `ready`,
        # the kill is still done, the run still ends at `done`; the reworded lines are logged, and those the
        # status said the world printed for a moment shown here (ready, progress, done) are not echoed.
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "3", "--max-ticks", "40", "--kill",
                          "1@20", "--out", out, "--domain", "77", "--no-pictures",
                          env={"FAKE_AGENT_EXIT_S": "0.5", "FAKE_WORLD_HUMAN": "reworded"})
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(sorted(agent_pids(out)), [0, 1, 2])
        with open(os.path.join(out, "world_args.json")) as f:
            world_args = json.load(f)
        fd = world_args[world_args.index("--status-fd") + 1]
        self.assertRegex(fd, r"^\d+$")
        self.assertIn("40 ticks in", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertNotIn("not understood", r.stderr)
        with open(os.path.join(out, "logs", "world_console.log")) as f:
            console = f.read()
        self.assertIn("[fake world, reworded]", console)
        self.assertNotIn("world ready", console)
        for words in ("YDAER DLROW", "SSERGORP", "SKCIT ENOD"):  # said on the status channel: logged, not shown
            self.assertIn(words, console)
            self.assertNotIn(words, r.stderr)
        self.assertIn("DEMIALC", r.stderr)  # a claim's line is shown as it is
        self.assert_all_gone(agent_pids(out).values())

    def test_a_moment_printed_while_the_launcher_handles_an_earlier_one_is_not_shown(self):
        # The world writes each moment's status line, then its stdout line. Here the second moment is written while
        # the launcher handles the first (as the agents start at `ready`): its stdout line must wait for its
        # status line, however the reads fall. Reading the status channel before stdout let it through.
        status_r, status_w = os.pipe()
        out_r, out_w = os.pipe()

        def say(line: str) -> None:
            os.write(status_w, json.dumps({"v": 1, "event": "connected", "agents": 1, "line": line}).encode() + b"\n")
            os.write(out_w, line.encode() + b"\n")

        def on_event(ev) -> None:
            if len(events) == 0:
                say("the second moment")
                os.close(status_w)
                os.close(out_w)
            events.append(ev)

        class Never:
            def __bool__(self) -> bool:
                return False

        class World:  # exits (as far as _follow can tell) 10 s on, should the pipes never close
            stdout = os.fdopen(out_r, "rb", buffering=0)
            ends = time.monotonic() + 10

            def poll(self):
                return 0 if time.monotonic() > self.ends else None

        events: list = []
        say("the first moment")
        shown = io.StringIO()
        try:
            launcher._follow(World(), Never(), launcher.Status(shown), io.BytesIO(), 10, status_fd=status_r,
                             on_event=on_event, bad=None)
        finally:
            World.stdout.close()
            os.close(status_r)
        self.assertEqual(len(events), 2)
        self.assertEqual(shown.getvalue(), "")

    def test_lines_on_the_status_channel_that_are_not_events_are_said_once_and_counted(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "20", "--out", out,
                          "--no-pictures", env={"FAKE_AGENT_EXIT_S": "0.3", "FAKE_WORLD_BAD_STATUS": "1"})
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertEqual(r.stderr.count("was not understood"), 1, r.stderr)
        self.assertIn("(not JSON): 'not json at all'", r.stderr)
        self.assertIn("swarm: WARNING: 6 lines of the world's status channel were not understood and ignored",
                      r.stderr)
        self.assertIn("20 ticks in", r.stderr)

    def test_the_world_gets_the_runs_secret_and_each_agent_only_its_token(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "3", "--max-ticks", "10", "--out", out,
                          "--no-pictures", env={"FAKE_AGENT_EXIT_S": "0.3"})
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "world_env.json")) as f:
            secret = json.load(f)["SWARMFORM_RUN_SECRET"]
        self.assertRegex(secret, r"^[0-9a-f]{64}$")
        with open(os.path.join(out, "world_args.json")) as f:
            world_args = json.load(f)
        self.assertNotIn(secret, " ".join(world_args))  # never on a command line
        self.assertNotIn("--open-rejoin", world_args)
        nonce = world_args[world_args.index("--run-nonce") + 1]
        for rid in range(3):
            with open(os.path.join(out, "logs", f"agent-{rid}.log")) as f:
                log = f.read()
            self.assertIn(f"token={claims.claim_token(bytes.fromhex(secret), nonce, rid)} secret=False", log)
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "1", "--max-ticks", "10", "--out",
                          os.path.join(self.dir, "open"), "--no-pictures", "--open-rejoin",
                          env={"FAKE_AGENT_EXIT_S": "0.3"})
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(self.dir, "open", "world_args.json")) as f:
            self.assertIn("--open-rejoin", json.load(f))

    def test_repeated_world_lines_are_shown_three_times_and_logged_all(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "6", "--max-ticks", "10", "--out", out,
                          "--no-pictures", env={"FAKE_AGENT_EXIT_S": "0.3"})
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stderr.count("claimed by pid"), 3)
        self.assertIn("world: ... (more lines like this in world_console.log)", r.stderr)
        with open(os.path.join(out, "logs", "world_console.log")) as f:
            self.assertEqual(f.read().count("claimed by pid"), 6)

    def test_stragglers_are_killed_after_the_deadline(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "10", "--out", out,
                          "--no-pictures")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("2 agent(s) still running 5 s after the world ended were killed", r.stderr)
        self.assert_all_gone(agent_pids(out).values())

    def test_default_run_dir_and_latest_link_and_pictures(self):
        runs = os.path.join(self.dir, "runs")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "20", "--ticks", "3",
                          env={"SWARM_RUNS_DIR": runs, "FAKE_AGENT_EXIT_S": "0.3"})
        self.assertEqual(r.returncode, 0, r.stderr)
        latest = os.path.join(runs, "latest")
        self.assertTrue(os.path.exists(os.path.join(latest, "pictures", "snapshot_t00003.png")))
        self.assertTrue(os.path.islink(latest))
        target = os.readlink(latest)
        self.assertRegex(target, r"^\d{8}-\d{6}(-\d+)?$")
        self.assertTrue(os.path.exists(os.path.join(latest, "pictures", "animation.gif")))
        self.assertIn("pictures: 13 files", r.stdout)

    def test_demo_runs_the_paper_scenario_and_says_where_the_pictures_are(self):
        runs = os.path.join(self.dir, "runs")
        r = helpers.swarm("demo", "--robots", "2", "--max-ticks", "20",
                          env={"SWARM_RUNS_DIR": runs, "FAKE_AGENT_EXIT_S": "0.3"})
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(runs, "latest", "world_args.json")) as f:
            world_args = json.load(f)
        self.assertTrue(world_args[world_args.index("--scenario") + 1].endswith("scenarios/paper.yaml"))
        run_dir = os.path.realpath(os.path.join(runs, "latest"))  # outside the working directory: absolute
        self.assertIn(f"demo done. Pictures: {run_dir}/pictures/", r.stdout)
        self.assertIn(f"The numbers: scripts/swarm report {run_dir}", r.stdout)

    def test_in_process_passes_the_flags_the_runner_takes(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--in-process", "--scenario", self.scenario, "--robots", "3", "--mode",
                          "realtime", "--domain", "9", "--kill", "1@5", "--max-ticks", "25", "--out", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "inprocess_args.json")) as f:
            self.assertEqual(json.load(f), ["--scenario", self.scenario, "--robots", "3", "--max-ticks", "25",
                                            "--kill", "1@5", "--out", out])
        self.assertIn("--domain, --mode do(es) not apply to an in-process run", r.stderr)
        with open(os.path.join(out, "inprocess_console.log")) as f:
            self.assertIn('"robots": 3', f.read())  # its stdout (the summary) goes to the log, not the terminal
        self.assertTrue(os.path.exists(os.path.join(out, "pictures", "animation.mp4")))

    def test_failed_check_exits_2_with_the_worlds_message(self):
        with open(self.scenario, "w") as f:
            f.write("bad\n")
        r = helpers.swarm("run", "--scenario", self.scenario, "--out", os.path.join(self.dir, "run"))
        self.assertEqual(r.returncode, 2)
        self.assertIn(f"{self.scenario}:1: not a scenario", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.dir, "run")))

    def test_a_non_utf8_byte_in_the_scenario_is_quoted_not_a_traceback(self):
        with open(self.scenario, "wb") as f:
            f.write(b"bad seed: \xff\n")
        r = helpers.swarm("run", "--scenario", self.scenario, "--out", os.path.join(self.dir, "run"))
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn(f"{self.scenario}:1: not a scenario: 'bad seed: \\xff'", r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_swarm_kill_with_a_non_utf8_agents_json_says_which_file(self):
        with open(os.path.join(self.dir, "agents.json"), "wb") as f:
            f.write(b'{"0": \xff}')
        r = helpers.swarm("kill", "0", "--run", self.dir)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn(f"{os.path.join(self.dir, 'agents.json')}: cannot read", r.stderr)
        self.assertNotIn("Traceback", r.stderr)

    def test_world_failure_is_passed_on(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "40", "--out", out,
                          env={"FAKE_WORLD_FAIL": "1", "FAKE_AGENT_EXIT_S": "0.5"})
        self.assertEqual(r.returncode, 3)
        self.assertIn("world: world: something broke", r.stderr)
        self.assertIn("world_server failed (exit 3)", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assert_all_gone(agent_pids(out).values())

    def test_a_missing_agent_ends_the_run_at_the_connect_timeout_naming_its_id(self):
        # The world waits --connect-timeout (the launcher passes it), then names the missing id and
        # exits 3; the launcher says what became of that id's agent.
        out = os.path.join(self.dir, "run")
        began = time.monotonic()
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "3", "--max-ticks", "40", "--out", out,
                          "--domain", "78", "--no-pictures", "--connect-timeout", "1",
                          env={"FAKE_WORLD_UNCLAIMED": "1", "FAKE_AGENT_GONE": "1"})
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertLess(time.monotonic() - began, 30)
        with open(os.path.join(out, "world_args.json")) as f:
            world_args = json.load(f)
        self.assertEqual(world_args[world_args.index("--connect-timeout") + 1], "1")
        self.assertIn("1 of 3 agents missing, and none claimed its id in the last 1 s: 1", r.stderr)
        self.assertIn("swarm: 1 of 3 agents did not connect, none for 1 s (--connect-timeout): 1 (agent exited with "
                      f"code {exit_codes.CODES['no_world']}: robot_agent 1: no world on DDS domain 0", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assert_all_gone(agent_pids(out).values())

    def test_a_world_that_never_ends_the_wait_is_stopped_by_the_launchers_own_deadline(self):
        # A hung world (it never times out itself): the launcher stops it at --connect-timeout plus its grace
        # (2 s here), names the id it never saw claimed and exits 3, leaving nothing behind.
        out = os.path.join(self.dir, "run")
        began = time.monotonic()
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "3", "--max-ticks", "40", "--out", out,
                          "--domain", "79", "--no-pictures", "--connect-timeout", "1",
                          env={"FAKE_WORLD_UNCLAIMED": "2", "FAKE_WORLD_HANG": "1"})
        self.assertEqual(r.returncode, 3, r.stderr)
        self.assertLess(time.monotonic() - began, 30)
        self.assertIn("1 of 3 agents did not connect, none for 1 s (--connect-timeout), and the world did not end "
                      "the wait; stopped it. Missing ids: 2 (agent pid ", r.stderr)
        self.assertIn("still running; logs/agent-2.log)", r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assert_all_gone(agent_pids(out).values())

    def test_the_world_is_read_while_the_agents_start(self):
        # The agents start a slice at a time, and the launcher reads the world between slices: the world's
        # status pipe (64 KB) holds it up only for a slice. 800 agents (a shell that sleeps: quick to start) and a
        # world that writes 1 MB of status right after `ready`: it had written it when far fewer than all were
        # started. A launcher that starts them all in one go reads 1 MB only after the 800th.
        build = os.path.join(self.dir, "build")
        for name, text in (("world_server", f'#!/bin/sh\nexec {helpers.FAKE_BUILD}/world_server/world_server "$@"\n'),
                           ("robot_agent", "#!/bin/sh\nexec sleep 600\n")):
            os.makedirs(os.path.join(build, name))
            path = os.path.join(build, name, name)
            with open(path, "w") as f:
                f.write(text)
            os.chmod(path, 0o755)
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "800", "--max-ticks", "5", "--out", out,
                          "--domain", "77", "--no-pictures", build_dir=build, timeout=300,
                          env={"FAKE_WORLD_FLOOD": str(1 << 20),
                               "PYTHONPATH": os.path.join(helpers.FAKE_BUILD, "python")})
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(out, "flood.json")) as f:
            started = json.load(f)["agents_started"]
        self.assertLess(started, 800)
        self.assert_all_gone(agent_pids(out).values())

    def test_the_connect_timeout_grows_with_the_robots_when_not_given(self):
        self.assertAlmostEqual(launcher.connect_timeout(16), 30.4)
        self.assertAlmostEqual(launcher.connect_timeout(1024), 55.6)
        self.assertEqual(launcher.connect_timeout(1024, 5.0), 5.0)

    def test_an_agent_that_exits_with_an_error_is_a_loud_warning(self):
        # A refused claim is a loud warning with the agent's own words, not a silent death.
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "3", "--max-ticks", "200", "--out", out,
                          "--domain", "77", "--no-pictures",
                          env={"FAKE_AGENT_EXIT_S": "0.2", "FAKE_AGENT_REFUSED": "1", "FAKE_WORLD_SLOW": "0.01"})
        self.assertEqual(r.returncode, 0, r.stderr)
        refused = exit_codes.CODES["id_refused"]
        self.assertIn(f"swarm: WARNING: agent 1 exited with code {refused}: robot_agent 1: refused: id is already owned",
                      r.stderr)
        self.assertEqual(r.stderr.count("WARNING"), 1, r.stderr)

    def test_a_domain_in_use_on_this_host_is_refused_before_anything_starts(self):
        import socket
        from swarmform import domains
        s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            s.bind(("127.0.0.1", 0))  # an ephemeral port, standing in for a world's port of domain 77
            port = s.getsockname()[1]
            probe = os.path.join(self.dir, "sitecustomize.py")  # makes the launcher see it as domain 77's
            with open(probe, "w") as f:
                f.write("from swarmform import domains\n"
                        f"domains.world_ports = lambda d: ({port}, {port}) if d == 77 else (7400 + 100 * d + 10,) * 2\n")
            out = os.path.join(self.dir, "run")
            r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--out", out, "--domain", "77",
                              "--no-pictures", env={"PYTHONPATH": self.dir + os.pathsep + os.path.join(helpers.ROOT,
                                                                                                       "scripts")})
        finally:
            s.close()
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn("DDS domain 77 is in use on this host", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(out, "agents.json")))

    # Every end is one clear line with a documented exit code, never a traceback.
    def test_a_world_on_a_full_disk_ends_with_one_line_and_exit_5(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "40", "--out", out,
                          "--no-pictures", env={"FAKE_WORLD_FAIL": "disk_full", "FAKE_AGENT_EXIT_S": "0.5"})
        self.assertEqual(r.returncode, 5, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        # The launcher's line names the file that failed and where the outcome is.
        self.assertIn(f"swarm: the run ended (disk_full): world_server exit 5 at tick 20: {out}/robots.csv: cannot "
                      f"write: No space left on device; the outcome is in {out}/summary.json", r.stderr)
        self.assert_all_gone(agent_pids(out).values())

    def test_a_lockstep_wait_run_out_is_passed_on_with_the_worlds_words_and_exit_10(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "40", "--out", out,
                          "--no-pictures", env={"FAKE_WORLD_FAIL": "agents_stalled", "FAKE_AGENT_EXIT_S": "0.5"})
        self.assertEqual(r.returncode, exit_codes.AGENTS_STALLED, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertIn(f"swarm: the run ended (agents_stalled): world_server exit {exit_codes.AGENTS_STALLED} at tick "
                      f"20: robot 1 gave no command for tick 20 in 30 s (lockstep_deadline)", r.stderr)
        self.assertIn(f"the outcome is in {out}/summary.json", r.stderr)
        self.assert_all_gone(agent_pids(out).values())

    def test_a_world_that_could_not_write_its_summary_is_said_with_the_file(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "40", "--out", out,
                          "--no-pictures", env={"FAKE_WORLD_FAIL": "disk_full", "FAKE_WORLD_NO_SUMMARY": "1",
                                                "FAKE_AGENT_EXIT_S": "0.5"})
        self.assertEqual(r.returncode, 5, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertIn(f"swarm: the run ended (disk_full): world_server exit 5 at tick 20: {out}/robots.csv: cannot "
                      f"write: No space left on device; no summary.json could be written (summary.json not "
                      f"written: {out}/summary.json: cannot write: No space left on device)", r.stderr)

    def test_a_crashed_world_is_named_and_the_agents_end(self):
        out = os.path.join(self.dir, "run")
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "40", "--out", out,
                          "--no-pictures", env={"FAKE_WORLD_FAIL": "segv", "FAKE_AGENT_EXIT_S": "0.5"})
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        self.assertIn("swarm: world_server died of SIGSEGV (world_failed; no summary.json)", r.stderr)
        self.assert_all_gone(agent_pids(out).values())

    def test_the_launchers_copy_of_the_worlds_lines_failing_is_one_line_naming_it_and_the_run_goes_on(self):
        out = os.path.join(self.dir, "run")
        os.makedirs(os.path.join(out, "logs"))
        # The world's console log is the launcher's own file (agents.json is replaced whole, so a symlink there
        # would be replaced, not written through): every write fails with ENOSPC, as on a full disk. It is a copy:
        # the run's end is the world's to say (before, the launcher stopped the world, naming no file).
        os.symlink("/dev/full", os.path.join(out, "logs", "world_console.log"))
        r = helpers.swarm("run", "--scenario", self.scenario, "--robots", "2", "--max-ticks", "40", "--out", out,
                          "--no-pictures", env={"FAKE_AGENT_EXIT_S": "0.5"})
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("Traceback", r.stderr)
        lines = [line for line in r.stderr.splitlines() if "No space left on device" in line]
        self.assertEqual(len(lines), 1, r.stderr)
        self.assertIn(f"swarm: {out}/logs/world_console.log: No space left on device (the disk is full); the world's "
                      "lines are no longer copied there", lines[0])
        self.assertTrue(os.path.exists(os.path.join(out, "summary.json")))

    def test_the_launchers_own_agents_json_failing_names_it(self):
        # agents.json is written whole (a temporary file renamed): a full disk shows only when its buffer is
        # written, where Python's error names no file. jsonfile names it.
        path = os.path.join(self.dir, "agents.json")
        os.symlink("/dev/full", f"{path}.tmp-{os.getpid()}")
        with self.assertRaises(OSError) as caught:
            jsonfile.write_atomically(path, {"0": 1})
        self.assertEqual(caught.exception.filename, path)
        self.assertIn("No space left on device", str(caught.exception))

    def test_missing_executables_are_explained(self):
        r = helpers.swarm("run", "--scenario", self.scenario, build_dir=os.path.join(self.dir, "nothing"))
        self.assertEqual(r.returncode, 1)
        self.assertIn("world_server/world_server not found: build it first", r.stderr)

    def start_long_run(self, out, robots=3):
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=helpers.FAKE_BUILD, FAKE_WORLD_SLOW="0.05")
        p = subprocess.Popen([helpers.SWARM, "run", "--scenario", self.scenario, "--robots", str(robots),
                              "--max-ticks", "100000", "--out", out, "--no-pictures"], env=env,
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.started.append(p)
        def all_started():  # agents.json is rewritten as each slice of agents starts
            try:
                return len(agent_pids(out)) == robots
            except (OSError, ValueError):
                return False
        self.assertTrue(wait_for(all_started, 20.0))
        return p

    def test_ctrl_c_stops_everything_and_exits_130(self):
        for sig in (signal.SIGINT, signal.SIGTERM):
            out = os.path.join(self.dir, f"run-{sig}")
            p = self.start_long_run(out)
            pids = agent_pids(out)
            self.assertTrue(all(helpers.pid_alive(x) for x in pids.values()))
            p.send_signal(sig)
            _, err = p.communicate(timeout=30)
            self.assertEqual(p.returncode, 130, err)
            self.assertIn(f"{signal.Signals(sig).name}: stopping the world", err)
            self.assert_all_gone(pids.values())

    def test_even_a_sigkilled_launcher_leaves_nothing_behind(self):
        out = os.path.join(self.dir, "run")
        p = self.start_long_run(out, robots=2)
        pids = list(agent_pids(out).values())
        p.kill()
        p.communicate(timeout=30)
        self.assert_all_gone(pids)

    def test_swarm_kill_kills_one_agent_of_the_running_swarm(self):
        out = os.path.join(self.dir, "run")
        p = self.start_long_run(out)
        pids = agent_pids(out)
        r = helpers.swarm("kill", "1", "--run", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(f"killed agent 1 (pid {pids[1]})", r.stdout)
        self.assertTrue(wait_for(lambda: not helpers.pid_alive(pids[1]), 5.0))
        self.assertTrue(helpers.pid_alive(pids[0]) and helpers.pid_alive(pids[2]))
        r = helpers.swarm("kill", "1", "--run", out)
        self.assertEqual(r.returncode, 1)
        self.assertIn("is not running", r.stderr)
        r = helpers.swarm("kill", "9", "--run", out)
        self.assertEqual(r.returncode, 1)
        self.assertIn("no agent with id 9", r.stderr)
        p.send_signal(signal.SIGINT)
        p.communicate(timeout=30)
        self.assert_all_gone(pids.values())

    def test_kill_refuses_a_pid_that_is_not_that_agent(self):
        with open(os.path.join(self.dir, "agents.json"), "w") as f:
            json.dump({"0": os.getpid()}, f)  # this test process: alive, but no robot_agent
        r = helpers.swarm("kill", "0", "--run", self.dir)
        self.assertEqual(r.returncode, 1)
        self.assertIn("is not robot_agent --id 0", r.stderr)


class ExecFlagTest(unittest.TestCase):
    """`swarm run --exec`: refused before anything starts when its program cannot be found or with --in-process;
    passed to every agent otherwise (the end-to-end use: tests/examples/test_agents_e2e.py)."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-exec-flag-")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def run_swarm(self, *args):
        return helpers.swarm("run", "--robots", "2", "--max-ticks", "5", "--no-pictures",
                             "--out", os.path.join(self.dir, "run"), *args)

    def test_a_program_that_cannot_be_found_is_refused(self):
        for cmd, says in (("pyhton3 agent.py", "--exec 'pyhton3 agent.py': pyhton3: not found on PATH"),
                          ("./no/such/agent --x", "./no/such/agent: no such executable file"),
                          ("python3 'unclosed", "not a command line")):
            r = self.run_swarm("--exec", cmd)
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertIn(says, r.stderr)
            self.assertFalse(os.path.exists(os.path.join(self.dir, "run", "agents.json")), "nothing was started")

    def test_shell_syntax_is_left_to_the_shell_and_in_process_is_refused(self):
        from swarmform import launcher
        launcher.check_exec("env A=1 python3 x.py")  # env is on PATH
        launcher.check_exec("A=1 nosuch x.py")       # an assignment: the shell's to judge
        launcher.check_exec("nosuch < in.txt")       # a redirection: the same
        r = self.run_swarm("--exec", "python3 x.py", "--in-process")
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("leave out --in-process", r.stderr)


class ChildDeathTest(unittest.TestCase):
    """Every process the launcher starts dies with it (PR_SET_PDEATHSIG), even one whose starter died between the
    fork and the arming of the signal."""

    def test_a_child_whose_starter_died_before_the_signal_was_armed_exits_at_once(self):
        pid = os.fork()
        if pid == 0:  # the child: its recorded starter is not its parent, as when the starter died meanwhile
            child_death._spawner = 1
            child_death.die_with_parent()
            os._exit(0)
        _, status = os.waitpid(pid, 0)
        self.assertEqual(os.waitstatus_to_exitcode(status), child_death.EXIT_ORPHANED)

    def test_a_child_goes_on_while_its_starter_lives_and_dies_with_it(self):
        code = ("import subprocess, time\n"
                "from swarmform.child_death import die_with_parent\n"
                "p = subprocess.Popen(['sleep', '60'], preexec_fn=die_with_parent)\n"
                "print(p.pid, flush=True)\n"
                "time.sleep(60)\n")
        starter = subprocess.Popen(["/usr/bin/python3", "-c", code], stdout=subprocess.PIPE, text=True,
                                   env=dict(os.environ, PYTHONPATH=os.path.join(helpers.ROOT, "scripts")))
        try:
            child = int(starter.stdout.readline())
            time.sleep(0.5)
            self.assertTrue(helpers.pid_alive(child))
            starter.kill()
            starter.wait(timeout=30)
            self.assertTrue(wait_for(lambda: not helpers.pid_alive(child), 5.0), f"sleep {child} outlived its starter")
        finally:
            if starter.poll() is None:
                starter.kill()
                starter.wait(timeout=30)
            starter.stdout.close()


if __name__ == "__main__":
    unittest.main()
