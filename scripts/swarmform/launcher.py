"""`swarm run`: the world server and N robot agent processes, progress on the terminal, nothing left behind.

Order of a run:
  1. `world_server --check` validates the scenario with the overrides and tells N (file:line errors pass through);
  2. the run directory (runs/<UTC time>/ and runs/latest, or --out) with logs/;
  3. the DDS domain: --domain, or a free one picked and locked for the run (domains.py says how), and the run's
     nonce; the world first (`--run-nonce`, `--agent-pids agents.json`), and once its status says `ready` (its
     mission is out) N `robot_agent --id K --run-nonce X` processes, all in one process group of their own, so
     an agent can only join this run's world (docs/wire.md); agents.json (id -> pid) lets the world SIGKILL the
     --kill ones at their exact ticks and `swarm kill` find them; an agent that exits with an error during the
     run (a refused claim, a lost id) is a loud warning with the last line of its log; every agent must connect
     within --connect-timeout (passed to the world, which ends the run naming the missing ids; the launcher
     stops a world that does not, naming the ids it never saw claimed and what became of their agents);
  4. what the world does comes from its status channel (--status-fd: a pipe, one JSON object a line;
     docs/status-channel.md, world_status.py): `ready` starts the agents, `progress` becomes one status line,
     `claimed`/`connected`/`gave_up` follow the start-up, `restart` starts an agent, `run_ended`/`done` end it;
     every line the world prints is logged and shown, but for those its status says it printed for a moment
     shown here (`line`);
  5. when the world exits, the agents get a deadline to exit, then SIGKILL.
With --hosts K the world and each agent start inside their emulated host's network namespace (hosts.py),
and the namespaces are removed in the same `finally` that kills the processes.
A `restart` event of the world (a scheduled restart fault) starts a new agent K (faults.py).
Ctrl-C, SIGTERM and SIGHUP only set a flag that the loop (which polls, never blocks) acts on: the world gets
SIGTERM (it closes the recording and writes summary.json), then every process we started is killed by pid and
by group, and the launcher exits 130. Every child also has PR_SET_PDEATHSIG = SIGKILL, so even a SIGKILLed
launcher leaves no process behind (its --hosts namespaces are removed by the next --hosts run).
"""

import argparse
import datetime
import errno
import functools
import json
import os
import re
import secrets
import select
import shlex
import shutil
import signal
import subprocess
import sys
import time
from typing import IO, Any, Callable, Optional, Union

from . import agent_start
from . import claims
from .child_death import die_with_parent
from . import domains
from . import exit_codes
from . import faults
from . import hosts as hosts_mod
from . import jsonfile
from . import places
from . import security
from . import world_status
from .world_status import Event

# The connect deadline (--connect-timeout), when not given: world_server's default_connect_timeout
# (world_server/server.hpp), which the launcher passes on so that both wait the same time.
CONNECT_TIMEOUT_BASE_S = 30.0
CONNECT_TIMEOUT_PER_AGENT_S = 0.025
# The launcher's own deadline is the world's plus this: the world ends the wait itself and names the missing ids;
# the launcher steps in only if the world does not (a hung world), naming the ids it never saw claimed.
CONNECT_GRACE_S = (2.0, 10.0)  # 20% of the timeout, within these bounds
MISSING_DETAILS_SHOWN = 10
AGENT_WATCH_PERIOD_S = 0.5
CHECK_TIMEOUT_S = 60
AGENT_EXIT_DEADLINE_S = 5.0
WORLD_STOP_DEADLINE_S = 10.0
VIEWER_START_S = 5.0  # --view 0: how long to wait for the viewer to say its port
# `swarm run`'s exit codes: common/exit_codes.json (exit_codes.py reads it; cli.py's --help prints it).
EXIT_INTERRUPTED = exit_codes.INTERRUPTED
EXIT_WORLD_FAILED = exit_codes.FAILED
EXIT_BAD_INPUT = exit_codes.BAD_INPUT
EXIT_AGENTS_MISSING = exit_codes.AGENTS_MISSING
EXIT_AGENTS_STALLED = exit_codes.AGENTS_STALLED
EXIT_RECORDING_FAILED = exit_codes.RECORDING_FAILED
REPEATS_SHOWN = 3


class LaunchError(Exception):
    def __init__(self, message: str, code: int = exit_codes.FAILED) -> None:
        super().__init__(message)
        self.code = code


def executable(kind: str) -> str:
    name = {"world": "world_server", "agent": "robot_agent", "inprocess": "swarm_inprocess",
            "viewer": "swarm_viewer"}[kind]
    path = places.program(name)
    if not os.access(path, os.X_OK):
        raise LaunchError(f"{path} not found: {places.missing_program_hint()}")
    return path



def overrides(args: argparse.Namespace) -> list[str]:
    """The flags the world takes from `swarm run`, in its own spelling."""
    out = ["--scenario", args.scenario]
    for flag, value in (("--shape", args.shape), ("--robots", args.robots), ("--seed", args.seed),
                        ("--mode", args.mode), ("--max-ticks", args.max_ticks)):
        if value is not None:
            out += [flag, str(value)]
    if getattr(args, "record_every", None) is not None:
        out += ["--record-every", str(args.record_every)]
    for kill in args.kill:
        out += ["--kill", kill]
    for fault in getattr(args, "fault", None) or []:
        out += ["--fault", fault]
    for folder in getattr(args, "plugin_dir", None) or []:
        out += ["--plugin-dir", os.path.abspath(folder)]
    for param in getattr(args, "param", None) or []:
        out += ["--param", param]
    return out


def check_expectations(args: argparse.Namespace, status: "Status", info: dict[str, Any]) -> None:
    """--expect: every key checked against what the run's summary will hold, before the run starts: the
    summary_template `world_server --check` printed (`info`), summary.json's keys as the code that writes it will
    write them for this scenario (summary_keys.py): the generic keys, the behaviour's parameters, states,
    telemetry, metrics and declared summary keys. An unknown key: LaunchError, exit 2, nothing run. Under --exec
    with a behaviour that is not described by a file, the behaviour is the program's, not the scenario's: its
    parameters, states and telemetry are checked after the run."""
    from . import expect, summary_keys
    exps = getattr(args, "expect", None) or []
    if not exps:
        return
    template = info.get("summary_template")
    if not isinstance(template, dict):
        raise LaunchError("--expect: world_server --check printed no summary_template (a world_server older than "
                          "this launcher: rebuild it)", EXIT_WORLD_FAILED)
    series = [f["key"] for f in summary_keys.declared_summary(info) if f.get("kind") == "series"]
    declared = summary_keys.declared_keys(template, series)
    program_owned = bool(getattr(args, "exec", None)) and described_by(info) is None
    skip = summary_keys.behaviour_owned if program_owned else (lambda key: False)
    bad = expect.check_declared(exps, declared, skip)
    if bad:
        raise LaunchError("--expect " + "\nswarm: --expect ".join(bad) + "\n(nothing was run)", EXIT_BAD_INPUT)
    if program_owned and any(skip(e.key) for e in exps):
        status.line("swarm: --expect: the --exec program's parameters, states and telemetry are checked after "
                    "the run")


def agent_plugin_flags(args: argparse.Namespace) -> list[str]:
    """The folders an agent may load behaviour plug-ins from: the scenario's own and each --plugin-dir (the
    world and swarm_inprocess add the scenario's folder themselves; docs/behaviour-api.md)."""
    out = ["--plugin-dir", os.path.dirname(os.path.abspath(args.scenario))]
    for folder in getattr(args, "plugin_dir", None) or []:
        out += ["--plugin-dir", os.path.abspath(folder)]
    return out


def exec_args(args: argparse.Namespace) -> list[str]:
    """The flags every robot_agent gets for `swarm run --exec CMD` (a behaviour as a child process per robot,
    docs/agent-protocol.md): the command line is passed through as one argument, run by /bin/sh in the agent."""
    cmd = getattr(args, "exec", None)
    if not cmd:
        return []
    out = ["--exec", cmd]
    timeout = getattr(args, "exec_timeout", None)
    return out + (["--exec-timeout", f"{timeout:g}"] if timeout is not None else [])


def check_exec(cmd: Optional[str]) -> None:
    """Refuses an --exec command whose program cannot be found, before any process starts (each robot's agent would
    otherwise die of it, one WARNING each). Only a plain command line is checked: one with shell syntax (pipes,
    variables, redirections) is left to the shell."""
    if not cmd:
        return
    try:
        words = shlex.split(cmd)
    except ValueError as e:
        raise LaunchError(f"--exec {cmd!r}: not a command line ({e})", EXIT_BAD_INPUT) from None
    if not words:
        raise LaunchError("--exec: the command is empty", EXIT_BAD_INPUT)
    if any(c in cmd for c in "|&;<>()$`*?[") or "=" in words[0]:
        return
    program = words[0]
    found = os.access(program, os.X_OK) and os.path.isfile(program) if os.sep in program else shutil.which(program)
    if not found:
        where = "no such executable file" if os.sep in program else "not found on PATH"
        raise LaunchError(f"--exec {cmd!r}: {program}: {where}", EXIT_BAD_INPUT)


def described_by(info: dict[str, Any]) -> Optional[str]:
    """The descriptor file of the scenario's behaviour when a JSON file describes it (it then has no controller:
    its agents run an --exec program; docs/agent-protocol.md), from `world_server --check`'s JSON; else None."""
    d = info.get("behaviour_descriptor")
    path = d.get("descriptor") if isinstance(d, dict) else None
    return path if isinstance(path, str) and path else None


def refuse_without_exec(args: argparse.Namespace, info: dict[str, Any], in_process: bool = False) -> None:
    """A behaviour described by a file runs only as `--exec` programs under robot agents: refused before
    anything starts in an in-process run, or without --exec. A mixed swarm (robot groups) with --exec is refused:
    one program would run every group's robots (docs/scenario-format.md "Groups")."""
    groups = info.get("groups")
    if groups and getattr(args, "exec", None):
        names = ", ".join(str(g.get("name")) for g in groups)
        raise LaunchError(f"{args.scenario}: --exec runs one program for every robot, and this scenario's robots are "
                          f"groups of different behaviours ({names}); a mixed swarm runs built-in and plug-in "
                          "behaviours only", EXIT_BAD_INPUT)
    path = described_by(info)
    if path is None or (getattr(args, "exec", None) and not in_process):
        return
    name = info["behaviour_descriptor"].get("name", "?")
    raise LaunchError(f"{args.scenario}: behaviour '{name}' is described by {os.path.basename(path)} and has no "
                      "controller: its agents run it with robot_agent --exec / swarm run --exec"
                      + ("; leave out --in-process" if in_process else ""), EXIT_BAD_INPUT)


def check_scenario(world_exe: str, args: argparse.Namespace) -> dict[str, Any]:
    """Runs `world_server --check`; returns its JSON ({robots, labels, mode, max_ticks, seed,
    behaviour_descriptor, groups, summary_template}: world_server/run/recording_format.hpp check_info)."""
    cmd = [world_exe] + overrides(args) + ["--check"]
    try:
        p = subprocess.run(cmd, capture_output=True, timeout=CHECK_TIMEOUT_S, encoding="utf-8",
                           errors="backslashreplace")
    except subprocess.TimeoutExpired:
        raise LaunchError(f"{' '.join(cmd)} did not answer within {CHECK_TIMEOUT_S} s") from None
    if p.returncode != 0:
        raise LaunchError(p.stderr.strip() or f"world_server --check failed (exit {p.returncode})", EXIT_BAD_INPUT)
    for line in reversed(p.stdout.strip().splitlines()):
        try:
            info = json.loads(line)
        except json.JSONDecodeError:
            continue
        if isinstance(info, dict) and isinstance(info.get("robots"), int):
            return info
    raise LaunchError(f"world_server --check printed no JSON line with 'robots': {p.stdout.strip()[:200]!r}")


def make_run_dir(out: Optional[str]) -> str:
    """--out, or runs/<UTC time>/ with runs/latest pointing at it."""
    if out:
        os.makedirs(out, exist_ok=True)
        return os.path.abspath(out)
    runs = places.runs_root()
    os.makedirs(runs, exist_ok=True)
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%d-%H%M%S")
    name, n = stamp, 1
    while True:
        try:
            os.mkdir(os.path.join(runs, name))
            break
        except FileExistsError:
            n += 1
            name = f"{stamp}-{n}"
    tmp = os.path.join(runs, f".latest-{os.getpid()}")
    if os.path.lexists(tmp):
        os.unlink(tmp)
    os.symlink(name, tmp)
    os.replace(tmp, os.path.join(runs, "latest"))
    return os.path.join(runs, name)


class Processes:
    """Every process the launcher started, so that all of them can be stopped by pid and by group."""

    def __init__(self) -> None:
        self.agents: dict[int, subprocess.Popen[bytes]] = {}  # id -> Popen
        # given to every agent, restarted ones too (--exec CMD, plug-in folders, --security-dir)
        self.agent_args: list[str] = []
        self.groups: set[int] = set()
        self.world: Optional[subprocess.Popen[bytes]] = None
        self.viewer: Optional[subprocess.Popen[bytes]] = None
        self._files: list[IO[bytes]] = []
        # rid -> (command prefix, extra flags): where agent rid runs (hosts.Hosts.agent_wrap under --hosts)
        self.placement: Optional[Callable[[int], tuple[list[str], list[str]]]] = None
        # the run's secret (claims.py): the world's, and each agent's token is derived from it
        self.run_secret: bytes = claims.run_secret()

    def _log(self, path: str) -> IO[bytes]:
        f = open(path, "ab")
        self._files.append(f)
        return f

    def start_agent(self, exe: str, rid: int, domain: Optional[int], log_path: str,
                    run_nonce: Optional[str] = None) -> "subprocess.Popen[bytes]":
        wrap, extra = self.placement(rid) if self.placement else ([], [])
        cmd = wrap + [exe, "--id", str(rid)] + (["--domain", str(domain)] if domain is not None else [])
        cmd += (["--run-nonce", run_nonce] if run_nonce else []) + extra
        cmd += self.agent_args
        # Its own id's token only when it knows the run (the token is the run's and the id's).
        env = claims.agent_env(self.run_secret, run_nonce, rid) if run_nonce else None
        log = self._log(log_path)
        group = next(iter(self.groups), 0)
        try:
            p = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                                 process_group=group, preexec_fn=die_with_parent, env=env)
        except (subprocess.SubprocessError, OSError):  # the group is gone (its members all died): a new one
            p = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                                 process_group=0, preexec_fn=die_with_parent, env=env)
        self.groups.add(os.getpgid(p.pid) if p.poll() is None else p.pid)
        self.agents[rid] = p
        return p

    def start_world(self, cmd: list[str], status_fd: int) -> "subprocess.Popen[bytes]":
        """The world, with `status_fd` (a pipe's write end, in `cmd` as --status-fd) its only inherited extra."""
        self.world = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                      stderr=subprocess.STDOUT, process_group=0, preexec_fn=die_with_parent,
                                      env=claims.world_env(self.run_secret), pass_fds=(status_fd,))
        return self.world

    def start_viewer(self, cmd: list[str], log_path: str) -> "subprocess.Popen[bytes]":
        """The viewer (--view): its own process group, its output to its log. Its death is said, never fatal."""
        self.viewer = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=self._log(log_path),
                                       stderr=subprocess.STDOUT, process_group=0, preexec_fn=die_with_parent)
        return self.viewer

    def stop_viewer(self, deadline_s: float = 3.0) -> None:
        v = self.viewer
        if v is None or v.poll() is not None:
            return
        v.send_signal(signal.SIGTERM)
        try:
            v.wait(timeout=deadline_s)
        except subprocess.TimeoutExpired:
            _kill_quietly(v.kill)
            v.wait(timeout=5)

    def stop_world(self, deadline_s: float) -> Optional[int]:
        """SIGTERM (the world closes its recording), then SIGKILL after the deadline. Returns its exit code."""
        w = self.world
        if w is None:
            return None
        if w.poll() is None:
            w.send_signal(signal.SIGTERM)
            try:
                w.wait(timeout=deadline_s)
            except subprocess.TimeoutExpired:
                pid = w.pid
                _kill_quietly(lambda: os.killpg(pid, signal.SIGKILL))
                w.wait(timeout=5)
        return w.returncode

    def wait_agents(self, deadline_s: float, before_kill: Optional[Callable[[], None]] = None) -> int:
        """Gives the agents until the deadline to exit, calls `before_kill` (what became of each can still be told
        apart: exited on its own, or still running), then SIGKILLs the stragglers. Returns how many were."""
        end = time.monotonic() + deadline_s
        for p in self.agents.values():
            try:
                p.wait(timeout=max(0.0, end - time.monotonic()))
            except subprocess.TimeoutExpired:
                pass
        stragglers = [p for p in self.agents.values() if p.poll() is None]
        if before_kill:
            before_kill()
        self.kill_agents()
        return len(stragglers)

    def kill_agents(self) -> None:
        for g in self.groups:
            _kill_quietly(functools.partial(os.killpg, g, signal.SIGKILL))
        for p in self.agents.values():
            if p.poll() is None:
                _kill_quietly(p.kill)
        for p in self.agents.values():
            try:
                p.wait(timeout=5)
            except subprocess.TimeoutExpired:
                pass

    def close(self) -> None:
        for f in self._files:
            f.close()


class CopyLog:
    """The world's console log: a copy of what the launcher reads from the world. A write to it that fails (a full
    disk) is said once, naming the file, and the copying stops; the run goes on, because its outcome is the world's
    to record (in the room it reserved for summary.json) and the world's lines still reach the terminal."""

    def __init__(self, path: str, status: "Status") -> None:
        self.name = path
        self.failed: Optional[OSError] = None
        self._status = status
        self._f = open(path, "ab")

    def _fail(self, e: OSError) -> None:
        if self.failed is None:
            self.failed = e
            self._status.line(f"swarm: {self.name}: {e.strerror or e}{_full_disk(e)}; the world's lines are no "
                              "longer copied there (they are still shown here)")

    def write(self, data: bytes) -> None:
        if self.failed is None:
            try:
                self._f.write(data)
            except OSError as e:
                self._fail(e)

    def flush(self) -> None:
        if self.failed is None:
            try:
                self._f.flush()
            except OSError as e:
                self._fail(e)

    def close(self) -> None:
        try:
            self._f.close()
        except OSError as e:  # its last buffer
            self._fail(e)

    def __enter__(self) -> "CopyLog":
        return self

    def __exit__(self, *_: object) -> None:
        self.close()


def _full_disk(e: OSError) -> str:
    return " (the disk is full)" if e.errno in (errno.ENOSPC, errno.EDQUOT) else ""


def _kill_quietly(fn: Callable[[], object]) -> None:
    try:
        fn()
    except (ProcessLookupError, PermissionError):
        pass


class StopFlag:
    """SIGINT/SIGTERM/SIGHUP set it; the launcher's loop polls it (no exception at an arbitrary point)."""

    def __init__(self) -> None:
        self.signal: Optional[int] = None
        self._old: dict[signal.Signals, Any] = {}
        for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            self._old[s] = signal.signal(s, self._handle)

    def _handle(self, signum: int, _frame: Any) -> None:
        self.signal = self.signal or signum

    def __bool__(self) -> bool:
        return self.signal is not None

    def restore(self) -> None:
        for s, h in self._old.items():
            signal.signal(s, h)


class Status:
    """One status line on a terminal (rewritten in place); plain lines, at most every few seconds, otherwise."""

    def __init__(self, stream: IO[str] = sys.stderr) -> None:
        self.stream, self.tty = stream, stream.isatty()
        self.last_plain, self.dirty = 0.0, False

    def progress(self, tick: int, alive: int, n: int, tps: float, max_ticks: Optional[int]) -> None:
        of = f"/{max_ticks}" if max_ticks else ""
        text = f"tick {tick}{of}   robots alive {alive}/{n}   {tps:.1f} ticks/s"
        if self.tty:
            self.stream.write("\r\033[K" + text)
            self.dirty = True
        elif time.monotonic() - self.last_plain >= 5.0:
            self.stream.write(text + "\n")
            self.last_plain = time.monotonic()
        self.stream.flush()

    def line(self, text: str) -> None:
        if self.dirty:
            self.stream.write("\r\033[K")
            self.dirty = False
        self.stream.write(text + "\n")
        self.stream.flush()

    def end(self) -> None:
        if self.dirty:
            self.stream.write("\n")
            self.dirty = False


class AgentWatch:
    """Says, once per agent, when an agent exited with an error during the run (faults.md: a refused claim or a lost
    id is a loud warning, not a silent death), with the last line of its log. A SIGKILLed agent (--kill, the end)
    is not an error of its own."""

    def __init__(self, procs: Processes, logs: str, status: Status) -> None:
        self.procs, self.logs, self.status = procs, logs, status
        self.said: set[int] = set()
        self.last = 0.0

    def check(self, force: bool = False) -> None:
        if not force and time.monotonic() - self.last < AGENT_WATCH_PERIOD_S:
            return
        self.last = time.monotonic()
        for rid, p in list(self.procs.agents.items()):
            if rid in self.said:
                continue
            code = _exit_code_unreaped(p)
            if code is None or code <= 0:
                continue
            self.said.add(rid)
            self.status.line(f"swarm: WARNING: agent {rid} exited with code {code}: {_last_line(self.logs, rid)}")


def connect_timeout(robots: int, given: Optional[float] = None) -> float:
    """--connect-timeout, or the default that grows with the number of agents (30 s + 25 ms an agent)."""
    return given if given is not None else CONNECT_TIMEOUT_BASE_S + CONNECT_TIMEOUT_PER_AGENT_S * robots


class ConnectWatch:
    """The start-up deadline (a run must never wait for ever at "connecting 1023/1024"). It follows the
    world's `claimed`, `connecting` and `connected` events from `ready` on; as the world's own, its deadline counts
    from the last step of the start-up (a claim, or more claimed or matched in a `connecting` event): slowness is
    not a missing agent. When the world has not said `connected` by then plus a grace (CONNECT_GRACE_S), `check`
    raises a LaunchError (exit 3) naming the ids never claimed and what became of their agents. `missing_text`
    says the same when the world timed out itself (its exit 3)."""

    def __init__(self, procs: Processes, logs: str, robots: int, timeout_s: float) -> None:
        self.procs, self.logs, self.robots, self.timeout_s = procs, logs, robots, timeout_s
        self.claimed: set[int] = set()
        self.connected = False
        self.since: Optional[float] = None  # the start, then the last step of the start-up
        self.steps = 0  # claimed + matched in the latest `connecting` event
        self.world_gave_up: Optional[float] = None  # when the world said it ended the wait (its exit follows)

    def start(self) -> None:
        if self.since is None:
            self.since = time.monotonic()

    def event(self, ev: Event) -> None:
        if ev.name == "claimed":
            self.claimed.add(ev["id"])
            self.moved()
        elif ev.name == "connecting" and ev["claimed"] + ev["matched"] > self.steps:
            self.steps = ev["claimed"] + ev["matched"]
            self.moved()
        elif ev.name == "connected":
            self.connected = True
        elif ev.name == "gave_up" and self.world_gave_up is None:  # the world ended the wait itself
            self.world_gave_up = time.monotonic()

    def moved(self) -> None:
        if self.since is not None:
            self.since = time.monotonic()

    def missing(self) -> list[int]:
        return [rid for rid in range(self.robots) if rid not in self.claimed]

    def missing_text(self) -> str:
        """'1 (agent exited with code 3: <its last line>), 7 (agent running; logs/agent-7.log)' for the first few."""
        ids = self.missing()
        parts: list[str] = []
        for rid in ids[:MISSING_DETAILS_SHOWN]:
            p = self.procs.agents.get(rid)
            if p is None:
                what = "no agent was started"
            else:
                code = _exit_code_unreaped(p)
                if code is None:
                    what = f"agent pid {p.pid} still running; logs/agent-{rid}.log"
                elif code < 0:
                    what = f"agent killed by signal {-code}"
                else:
                    what = f"agent exited with code {code}: {_last_line(self.logs, rid)}"
            parts.append(f"{rid} ({what})")
        more = f" and {len(ids) - MISSING_DETAILS_SHOWN} more" if len(ids) > MISSING_DETAILS_SHOWN else ""
        return ", ".join(parts) + more

    def check(self) -> None:
        if self.connected or self.since is None:
            return
        grace = min(CONNECT_GRACE_S[1], max(CONNECT_GRACE_S[0], 0.2 * self.timeout_s))
        # A world that has said it gave up is exiting: its own exit names the missing ids; it gets the grace
        # again from its word (a loaded host may take seconds to end a process), not from the deadline.
        if self.world_gave_up is not None:
            if time.monotonic() - self.world_gave_up < grace:
                return
        elif time.monotonic() - self.since < self.timeout_s + grace:
            return
        missing = self.missing()
        raise LaunchError(f"{len(missing)} of {self.robots} agents did not connect, none for {self.timeout_s:g} s "
                          f"(--connect-timeout), and the world did not end the wait; stopped it. Missing ids: "
                          f"{self.missing_text() or 'none claimed missing: the world hangs'}", EXIT_AGENTS_MISSING)


def _exit_code_unreaped(p: "subprocess.Popen[bytes]") -> Optional[int]:
    """An agent's exit code (negative: killed by that signal), or None while it runs. Looked at without reaping it:
    an exited agent stays a zombie until the end of the run, so its pid cannot be reused by another process that
    the world's --kill or `swarm kill` would then hit."""
    if p.returncode is not None:
        return p.returncode
    try:
        r = os.waitid(os.P_PID, p.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT)
    except ChildProcessError:
        return None
    if r is None or r.si_pid == 0:
        return None
    return r.si_status if r.si_code == os.CLD_EXITED else -r.si_status


def _last_line(logs: str, rid: int) -> str:
    path = os.path.join(logs, f"agent-{rid}.log")
    try:
        with open(path, "rb") as f:
            f.seek(0, os.SEEK_END)
            f.seek(max(0, f.tell() - 4096))
            lines = [x.strip() for x in f.read().decode(errors="replace").splitlines() if x.strip()]
    except OSError:
        return f"(no log at {path})"
    said = [x for x in lines if not x.startswith("agent id=")]  # the summary line says nothing of why
    return (said or lines or ["(empty log)"])[-1]


def _follow(proc: "subprocess.Popen[bytes]", stop: StopFlag, status: Status, console_log: Union[IO[bytes], CopyLog],
            max_ticks: Optional[int], prefix: str = "world", on_idle: Optional[Callable[[], Optional[bool]]] = None,
            status_fd: Optional[int] = None, on_event: Optional[Callable[[Event], None]] = None,
            bad: Optional[world_status.BadLines] = None) -> Optional[Event]:
    """Reads the world's output (and its status channel, `status_fd`) until both close, the world exits, or a stop
    is asked; returns the `done` event or None. Every output line is logged; it is shown unless a status event
    said it printed it (`line`). `on_event(ev)` sees every other event (`progress` becomes the status line);
    `on_idle()` runs every time round the loop (at least every 0.2 s; at once again when it returned True, busy).
    A status line that is not an event is counted in `bad`, the first said."""
    assert proc.stdout is not None  # stdout=PIPE
    out = proc.stdout.fileno()
    bufs = {out: b""}
    if status_fd is not None:
        bufs[status_fd] = b""
    for fd in bufs:
        os.set_blocking(fd, False)
    bad_lines = bad if bad is not None else world_status.BadLines()
    done: Optional[Event] = None
    said: dict[str, int] = {}  # human lines a status event said the world printed -> how many are still due
    # a line's pattern (numbers and participant GUIDs blanked) -> times shown: "id 7 claimed by pid 123
    # (participant 0110...)" x 256 shows 3
    seen: dict[str, int] = {}

    def on_status(raw: bytes) -> None:
        nonlocal done
        if not raw.strip():
            return
        ev = world_status.parse(raw)
        if isinstance(ev, str):
            message = bad_lines.add(raw, ev)
            if message:
                status.line(message)
            return
        line = ev.fields.get("line")
        if isinstance(line, str) and len(said) < 1000:
            said[line] = said.get(line, 0) + 1
        if ev.name == "progress":
            tps = ev["tps"] if ev["tps"] is not None else float("nan")
            status.progress(ev["tick"], ev["alive"], ev["robots"], float(tps), max_ticks)
        elif ev.name == "done":
            done = ev
        if on_event is not None:
            on_event(ev)

    def on_output(raw: bytes) -> None:
        console_log.write(raw + b"\n")
        line = raw.decode(errors="replace").rstrip("\r")
        if said.get(line):
            said[line] -= 1
            if not said[line]:
                del said[line]
            return
        if line.strip():
            pattern = re.sub(r"\b[0-9a-f]{32}\b|\d+", "#", line)
            seen[pattern] = seen.get(pattern, 0) + 1
            if seen[pattern] <= REPEATS_SHOWN:
                status.line(f"{prefix}: {line}")
            elif seen[pattern] == REPEATS_SHOWN + 1:
                status.line(f"{prefix}: ... (more lines like this in {os.path.basename(console_log.name)})")

    handlers = {out: on_output, status_fd: on_status}
    while bufs and not stop:
        busy = bool(on_idle()) if on_idle else False
        ready, _, _ = select.select(list(bufs), [], [], 0.0 if busy else 0.2)
        if not ready:
            if proc.poll() is not None:
                break
            continue
        # The world writes a moment's status line before its stdout line. So stdout is read first and the status
        # channel after it, whether select saw it ready or not: every status line of the stdout lines read is
        # then in hand before they are handled (reading the status first let a stdout line written after that
        # read, its status line unread, through: a moment shown that the world said it printed).
        taken: dict[int, bytes] = {}
        for fd in sorted(bufs if out in ready else ready, key=lambda f: f == status_fd):
            try:
                taken[fd] = os.read(fd, 65536)
            except BlockingIOError:
                continue
        for fd in sorted(taken, key=lambda f: f != status_fd):
            chunk = taken[fd]
            if not chunk:  # closed: the world exited (or closed it); a last line without its newline counts
                rest = bufs.pop(fd)
                if rest:
                    handlers[fd](rest)
                continue
            bufs[fd] += chunk
            *lines, bufs[fd] = bufs[fd].split(b"\n")
            for raw in lines:
                handlers[fd](raw)
    if not stop:
        for fd in sorted(bufs, key=lambda f: f != status_fd):
            if bufs[fd]:
                handlers[fd](bufs[fd])
    console_log.flush()
    return done


def run(args: argparse.Namespace, render_pictures: Callable[[str], int]) -> int:
    """`swarm run`. Returns the exit code; `render_pictures(run_dir)` draws the figures afterwards."""
    stop = StopFlag()
    procs = Processes()
    status = Status()
    lease: Optional[domains.DomainLease] = None
    hosts: Optional[hosts_mod.Hosts] = None
    status_pipe: list[int] = []  # the read end of the world's status channel, once made
    try:
        if getattr(args, "check", False):
            return _check_only(args, status)
        if args.in_process:
            return _run_in_process(args, stop, status, render_pictures)
        if getattr(args, "hosts", None):
            try:
                hosts_mod.check_can_make_hosts()
            except hosts_mod.HostsError as e:
                raise LaunchError(str(e), EXIT_BAD_INPUT) from None
        world_exe, agent_exe = executable("world"), executable("agent")
        check_exec(getattr(args, "exec", None))
        procs.agent_args = exec_args(args) + agent_plugin_flags(args)
        info = check_scenario(world_exe, args)
        refuse_without_exec(args, info)
        check_expectations(args, status, info)
        if stop:
            return EXIT_INTERRUPTED
        n = info["robots"]
        max_ticks = info.get("max_ticks")
        run_dir = args.run_dir = make_run_dir(args.out)
        logs = os.path.join(run_dir, "logs")
        os.makedirs(logs, exist_ok=True)
        status.line(f"swarm: {n} robot agents, {info.get('mode', '?')} mode, up to {max_ticks} ticks, "
                    f"seed {info.get('seed')}; run directory {run_dir}")
        domain = args.domain
        if getattr(args, "hosts", None):
            hosts = _make_hosts(args, status, run_dir, n)
            domain = 0 if domain is None else domain  # the run's own namespaces: no other run to avoid
        elif domain is not None and not domains.ports_free(domain):
            ports = " and ".join(str(p) for p in domains.world_ports(domain))
            raise LaunchError(f"DDS domain {domain} is in use on this host (UDP port {ports} held: another run's "
                              "world?); choose another --domain, or leave it out to pick a free one")
        if domain is None and hosts is None:
            try:
                lease = domains.pick_free_domain()
            except (domains.DomainError, OSError) as e:
                raise LaunchError(str(e)) from None
            domain = lease.domain
            status.line(f"swarm: DDS domain {domain} (free on this host; --domain D chooses one)")
        secure_args: list[str] = []
        if getattr(args, "secure", False):
            made = time.monotonic()
            try:
                sec_dir = security.make_security_dir(run_dir, n, domain)
            except (security.SecurityError, OSError) as e:
                raise LaunchError(f"--secure: {e}") from None
            secure_args = ["--security-dir", sec_dir]
            procs.agent_args += secure_args
            status.line(f"swarm: DDS Security: a certificate authority and {n + 2} identities made in "
                        f"{time.monotonic() - made:.1f} s in {sec_dir} (keys 0600; docs/security.md)")
        nonce = domains.run_nonce()
        agents_json = os.path.join(run_dir, "agents.json")
        wait_s = connect_timeout(n, getattr(args, "connect_timeout", None))
        cmd = [world_exe] + overrides(args) + ["--out", run_dir, "--domain", str(domain), "--run-nonce", nonce,
                                               "--agent-pids", agents_json, "--connect-timeout", f"{wait_s:g}"]
        cmd += secure_args
        if getattr(args, "open_rejoin", False):
            cmd.append("--open-rejoin")
        view = _ViewerStart(args, info, run_dir, domain, nonce, logs, procs, status)
        view.extra = list(secure_args)
        cmd += view.world_flags()
        if hosts is not None:
            wrap, extra = hosts.world_wrap()
            cmd = wrap + cmd + extra
            view.extra += hosts.viewer_flags()
            procs.placement = hosts.agent_wrap

        def start_agent(rid: int) -> None:
            if not stop and rid not in procs.agents:
                procs.start_agent(agent_exe, rid, domain, os.path.join(logs, f"agent-{rid}.log"), nonce)

        starter = agent_start.AgentStarter(n, start_agent, lambda: write_agents())

        def start_agents() -> None:  # at the world's `ready` event: its mission is out
            connecting.start()
            view.start()
            starter.begin()
            starter.step()

        def write_agents() -> None:  # the world reads it when a kill or a stall is due: replaced whole
            jsonfile.write_atomically(agents_json, {str(k): p.pid for k, p in procs.agents.items()})

        watch = AgentWatch(procs, logs, status)
        connecting = ConnectWatch(procs, logs, n, wait_s)
        started = time.monotonic()
        ended: list[Event] = []  # the world's `run_ended`, if it ended the run on a failure
        bad = world_status.BadLines()
        with CopyLog(os.path.join(logs, "world_console.log"), status) as console_log:
            # The status channel: the world writes, the launcher reads. The launcher keeps no write end, so the
            # read end sees end-of-file when the world exits; it stays open until the world has exited (the outer
            # `finally`): a world still writing its last status while it stops must find a reader.
            status_r, status_w = os.pipe()
            status_pipe.append(status_r)
            try:
                world = procs.start_world(cmd + ["--status-fd", str(status_w)], status_w)
            finally:
                os.close(status_w)
            # The agents look at the world's process while it is silent: gone is gone at once, there is slow
            # (a world starved or stopped past their --world-timeout is waited out: docs/faults.md).
            procs.agent_args += ["--world-pid", str(world.pid)]
            restarter = faults.Restarter(procs, agent_exe, domain, nonce, logs, write_agents, n)

            def idle() -> bool:
                if stop:
                    starter.cancel()
                starter.step()
                watch.check()
                view.check()
                connecting.check()
                return starter.pending  # busy: _follow does not sleep

            def on_event(ev: Event) -> None:
                if ev.name == "ready":
                    start_agents()
                elif ev.name == "run_ended":
                    ended.append(ev)  # its human line is shown as it is
                elif ev.name == "restart":
                    restarter.restart(ev["id"], ev["tick"], status)
                connecting.event(ev)

            done = _follow(world, stop, status, console_log, max_ticks, on_idle=idle, status_fd=status_r,
                           on_event=on_event, bad=bad)
            # Its output closed: it should be exiting. One that does not is stopped (the `finally` below).
            deadline = time.monotonic() + WORLD_STOP_DEADLINE_S
            while world.poll() is None and not stop and time.monotonic() < deadline:
                time.sleep(0.1)
            if world.poll() is None and not stop:
                status.line(f"swarm: the world closed its output but had not exited {WORLD_STOP_DEADLINE_S:g} s "
                            "later; stopping it")
                procs.stop_world(WORLD_STOP_DEADLINE_S)
        status.end()
        if bad.summary():
            status.line(bad.summary() or "")
        procs.stop_viewer()
        if stop:
            return _interrupted(procs, stop, status, run_dir)
        code = world.returncode
        # What became of the agents that never connected: told once they have had their time to exit (one that
        # gives up on its own as the world does says why), before the stragglers are killed.
        missing: Optional[str] = None

        def note_missing() -> None:
            nonlocal missing
            if code == EXIT_AGENTS_MISSING and not connecting.connected:
                missing = connecting.missing_text()

        stragglers = procs.wait_agents(AGENT_EXIT_DEADLINE_S, before_kill=note_missing)
        watch.check(force=True)
        if stragglers:
            status.line(f"swarm: {stragglers} agent(s) still running {AGENT_EXIT_DEADLINE_S:.0f} s after the world "
                        "ended were killed")
        if code != 0:
            details = (f"details in {console_log.name}" if console_log.failed is None
                       else f"{console_log.name} could not be written")
            status.line(f"swarm: {_world_failure(code, run_dir, ended[-1] if ended else None)}; {details}")
            if missing is not None:
                status.line(f"swarm: {len(connecting.missing())} of {n} agents did not connect, none for {wait_s:g} s "
                            f"(--connect-timeout): {missing}")
            passed_on = (EXIT_BAD_INPUT, EXIT_AGENTS_MISSING, EXIT_AGENTS_STALLED, EXIT_RECORDING_FAILED)
            return code if code in passed_on else EXIT_WORLD_FAILED
        ticks = done["ticks"] if done else "?"
        status.line(f"swarm: {ticks} ticks in {time.monotonic() - started:.1f} s; run directory {run_dir}")
        stop.restore()  # Ctrl-C while drawing just stops the drawing
        code = 0 if args.no_pictures else render_pictures(run_dir)
        _say_if_not_arrived(status, run_dir)
        return code
    except LaunchError as e:
        status.end()
        print(f"swarm: {e}", file=sys.stderr)
        return e.code
    except OSError as e:  # the launcher's own files (run directory, logs, agents.json): one line, no traceback
        status.end()
        print(f"swarm: {_os_error_line(e)}", file=sys.stderr)
        return _os_error_code(e)
    finally:
        procs.stop_world(WORLD_STOP_DEADLINE_S)
        for fd in status_pipe:
            os.close(fd)
        procs.stop_viewer()
        procs.kill_agents()
        _close_quietly(procs)
        if hosts is not None:
            hosts.remove()
        if lease:
            lease.release()
        stop.restore()


def _make_hosts(args: argparse.Namespace, status: Status, run_dir: str, robots: int) -> hosts_mod.Hosts:
    """--hosts: the namespaces of this run (after removing a crashed run's), described in hosts.json."""
    try:
        for prefix in hosts_mod.remove_leftovers():
            status.line(f"swarm: removed the namespaces left by a --hosts run that did not end cleanly ({prefix}-*)")
        hosts = hosts_mod.Hosts(args.hosts, args.link)
    except hosts_mod.HostsError as e:
        raise LaunchError(str(e), EXIT_BAD_INPUT) from None
    if args.hosts > robots:
        raise LaunchError(f"--hosts {args.hosts}: more agent hosts than the run's {robots} robots", EXIT_BAD_INPUT)
    try:
        hosts.create()
    except hosts_mod.HostsError as e:
        raise LaunchError(str(e), EXIT_BAD_INPUT if "--link" in str(e) else EXIT_WORLD_FAILED) from None
    try:
        hosts_mod.write_description(hosts, run_dir, robots)
    except BaseException:
        hosts.remove()
        raise
    link = " ".join(f"{k} {v:g}%" if k == "loss" else f"{k} {v}" for k, v in hosts.link.items())
    status.line(f"swarm: {args.hosts} agent hosts and the world's, as network namespaces {hosts.prefix}-*"
                f"{'; links: ' + link if link else ''} (hosts.json)")
    return hosts


class _ViewerStart:
    """--view: the world gets a viewer token (and --start-paused for --view-paused); at the world's `ready` the viewer
    starts with the same token, and its URL is printed. A viewer that fails or dies is said once; the run goes on
    (the world forgets a viewer that went away: viewer_control.hpp)."""

    def __init__(self, args: argparse.Namespace, info: dict[str, Any], run_dir: str, domain: int, nonce: str,
                 logs: str, procs: Processes, status: Status) -> None:
        self.port = getattr(args, "view", None)
        self.host = getattr(args, "view_host", "127.0.0.1")
        self.paused = bool(getattr(args, "view_paused", False))
        self.grace: Optional[float] = getattr(args, "view_grace", None)
        self.control_origins: list[str] = list(getattr(args, "view_control_origin", None) or [])
        self.run_dir, self.domain, self.nonce, self.logs = run_dir, domain, nonce, logs
        self.procs, self.status, self.said = procs, status, False
        self.token = secrets.token_hex(8) if self.port is not None else None
        if self.paused and info.get("mode") != "lockstep":
            raise LaunchError("--view-paused needs a lockstep run (a realtime run ticks on the clock and cannot "
                              "be held); leave out --view-paused, or use --mode lockstep", EXIT_BAD_INPUT)
        self.exe = executable("viewer") if self.port is not None else None
        # --security-dir under --secure (the viewer takes the run's observer identity); under --hosts, the world's
        # host for its DDS side (its page stays on this host, where the browser is)
        self.extra: list[str] = []

    def world_flags(self) -> list[str]:
        if self.token is None:
            return []
        return ["--viewer-token", self.token] + (["--start-paused"] if self.paused else [])

    def start(self) -> None:
        if self.token is None or self.procs.viewer is not None or self.exe is None:
            return
        cmd = [self.exe, "--domain", str(self.domain), "--run-nonce", self.nonce, "--token", self.token,
               "--run-dir", self.run_dir, "--port", str(self.port), "--host", self.host] + self.extra
        if self.grace is not None:
            cmd += ["--page-grace", str(self.grace)]
        for origin in self.control_origins:
            cmd += ["--control-origin", origin]
        log = os.path.join(self.logs, "viewer.log")
        viewer = self.procs.start_viewer(cmd, log)
        port = self.port
        if port == 0:  # any free port: the viewer says which once it listens (`viewer http://HOST:PORT/`)
            deadline = time.monotonic() + VIEWER_START_S
            while port == 0 and time.monotonic() < deadline and viewer.poll() is None:
                m = re.search(r"^viewer http://[^\s/]+:(\d+)/", _read_text(log), re.M)
                port = int(m[1]) if m else 0
                time.sleep(0.05)
        shown = "127.0.0.1" if self.host in ("0.0.0.0", "::") else self.host
        where = f"http://{shown}:{port}/" if port else f"(port not known yet: see {log})"
        self.status.line(f"swarm: viewer at {where}" +
                         (" (the run waits at tick 0 until the page says go)" if self.paused else ""))

    def check(self) -> None:
        v = self.procs.viewer
        if v is None or self.said or v.poll() is None:
            return
        self.said = True
        if v.returncode != 0:
            self.status.line(f"swarm: WARNING: the viewer exited with code {v.returncode}: "
                             f"{_last_log_line(os.path.join(self.logs, 'viewer.log'))}; the run goes on")


def _read_text(path: str) -> str:
    try:
        with open(path, "rb") as f:
            return f.read().decode(errors="replace")
    except OSError:
        return ""


def _last_log_line(path: str) -> str:
    try:
        with open(path, "rb") as f:
            lines = [x.strip() for x in f.read().decode(errors="replace").splitlines() if x.strip()]
    except OSError:
        return f"(no log at {path})"
    return lines[-1] if lines else "(empty log)"


def view(run_dir: str, port: int, host: str, control_origins: Optional[list[str]] = None) -> int:
    """`swarm view RUN_DIR`: the viewer over a recording, until Ctrl-C."""
    if not os.path.isfile(os.path.join(run_dir, "world.json")):
        print(f"swarm view: {run_dir}/world.json: no such file (is {run_dir} a run directory?)", file=sys.stderr)
        return EXIT_BAD_INPUT
    try:
        exe = executable("viewer")
    except LaunchError as e:
        print(f"swarm view: {e}", file=sys.stderr)
        return e.code
    origins = [a for o in control_origins or [] for a in ("--control-origin", o)]
    p = subprocess.Popen([exe, "--replay", os.path.abspath(run_dir), "--port", str(port), "--host", host] + origins,
                         stdin=subprocess.DEVNULL, preexec_fn=die_with_parent)

    def stop(*_: object) -> None:
        raise KeyboardInterrupt  # SIGTERM as Ctrl-C: the viewer is stopped and says what it skipped

    signal.signal(signal.SIGTERM, stop)
    try:
        return p.wait()
    except KeyboardInterrupt:
        p.send_signal(signal.SIGTERM)
        p.wait(timeout=5)
        return EXIT_INTERRUPTED


def _os_error_line(e: OSError) -> str:
    where = f"{e.filename}: " if e.filename else ""
    return f"{where}{e.strerror or e}{_full_disk(e)}; stopped the world and the agents"


def _os_error_code(e: OSError) -> int:
    return EXIT_RECORDING_FAILED if e.errno in (errno.ENOSPC, errno.EDQUOT) else EXIT_WORLD_FAILED


def _close_quietly(procs: Processes) -> None:
    try:
        procs.close()
    except OSError:  # a log file whose last buffer cannot be written (a full disk): already reported
        pass


def _end_reason(run_dir: str) -> Optional[str]:
    try:
        with open(os.path.join(run_dir, "summary.json"), encoding="utf-8") as f:
            return json.load(f).get("end_reason")
    except (OSError, ValueError, AttributeError):
        return None


def _world_failure(code: int, run_dir: str, ended: Optional[Event] = None) -> str:
    """One line for a world that exited non-zero: why (summary.json's end_reason, else the world's own `run_ended`
    event, else the exit code or the signal that killed it), the file that failed and where the outcome is, and
    whether a recording is there to draw."""
    reason = _end_reason(run_dir) or (ended["end_reason"] if ended else None)
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = f"signal {-code}"
        what = f"world_server died of {name} (world_failed; no summary.json)"
    elif reason:
        what = f"the run ended ({reason}): world_server exit {code}"
        if ended:  # the tick, the file and its error, in the world's words
            what += f" at tick {ended['tick']}: {ended['what']}"
            summary = os.path.join(run_dir, "summary.json")
            if os.path.exists(summary):
                cut = ", cut to the run's outcome" if ended.fields.get("summary_cut") is True else ""
                what += f"; the outcome is in {summary}{cut}"
            else:
                what += f"; no summary.json could be written ({ended['summary_note']})"
    else:
        what = f"world_server failed (exit {code})"
    if os.path.exists(os.path.join(run_dir, "robots.csv")):
        what += f"; what it recorded can be drawn: scripts/swarm replay {run_dir}"
    return what


def _interrupted(procs: Processes, stop: StopFlag, status: Status, run_dir: str) -> int:
    status.end()
    assert stop.signal is not None  # called when a stop was asked
    name = signal.Signals(stop.signal).name
    status.line(f"swarm: {name}: stopping the world (it closes the recording), then the agents")
    procs.stop_world(WORLD_STOP_DEADLINE_S)
    procs.kill_agents()
    status.line(f"swarm: stopped; what was recorded is in {run_dir} (`swarm replay {run_dir}` draws it)")
    return EXIT_INTERRUPTED


def _check_only(args: argparse.Namespace, status: Status) -> int:
    """--check: the checks a run makes before it starts anything (the scenario loader's through world_server
    --check, the same library the in-process runner loads with; the --exec command; the --expect keys), then
    one line of what would run."""
    check_exec(getattr(args, "exec", None))
    info = check_scenario(executable("world"), args)
    refuse_without_exec(args, info, in_process=bool(getattr(args, "in_process", False)))
    check_expectations(args, status, info)
    status.line(f"swarm: would run {info['robots']} robots, {info.get('mode', '?')} mode, up to "
                f"{info.get('max_ticks')} ticks, seed {info.get('seed')} (--check: nothing started)")
    return 0


def _run_in_process(args: argparse.Namespace, stop: StopFlag, status: Status,
                    render_pictures: Callable[[str], int]) -> int:
    """--in-process: the same scenario in one process (no DDS), the same run directory. Its stdout (the
    summary) goes to the log; its stderr carries the progress lines and messages."""
    if getattr(args, "exec", None):
        raise LaunchError("--exec runs each robot's behaviour as a child process of its robot_agent; an in-process "
                          "run has no agents: leave out --in-process", 2)
    info = check_scenario(executable("world"), args)
    refuse_without_exec(args, info, in_process=True)
    exe = executable("inprocess")
    help_text = subprocess.run([exe, "--help"], capture_output=True, timeout=30, encoding="utf-8",
                               errors="backslashreplace").stdout
    cmd, flags = [exe], overrides(args)
    dropped: list[str] = []
    for i in range(0, len(flags), 2):  # pass only the flags this runner documents
        if flags[i] == "--scenario" or flags[i] in help_text:
            cmd += flags[i:i + 2]
        else:
            dropped.append(flags[i])
    if args.domain is not None:
        dropped.append("--domain")
    if getattr(args, "view", None) is not None:
        dropped.append("--view")
    if dropped:
        status.line(f"swarm: {', '.join(sorted(set(dropped)))} do(es) not apply to an in-process run; ignored")
    check_expectations(args, status, info)
    run_dir = args.run_dir = make_run_dir(args.out)
    cmd += ["--out", run_dir]
    procs = Processes()
    with open(os.path.join(run_dir, "inprocess_console.log"), "ab") as console_log:
        world = procs.world = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=console_log,
                                               stderr=subprocess.PIPE, process_group=0, preexec_fn=die_with_parent)
        assert world.stderr is not None  # stderr=PIPE
        world.stdout = world.stderr  # _follow reads .stdout
        try:
            _follow(world, stop, status, console_log, args.max_ticks, prefix="in-process")
            while world.poll() is None and not stop:
                time.sleep(0.1)
        finally:
            status.end()
            if stop:
                procs.stop_world(WORLD_STOP_DEADLINE_S)
            code = world.wait()
            world.stderr.close()
    if stop:
        status.line(f"swarm: stopped; what was recorded is in {run_dir}")
        return EXIT_INTERRUPTED
    if code != 0:
        status.line(f"swarm: {_world_failure(code, run_dir).replace('world_server', 'swarm_inprocess')}")
        # The same mistake, the same code as a multi-process run (a bad scenario, plug-in or flag: 2).
        return code if code in (EXIT_BAD_INPUT, EXIT_RECORDING_FAILED) else EXIT_WORLD_FAILED
    status.line(f"swarm: run directory {run_dir}")
    stop.restore()
    code = 0 if args.no_pictures else render_pictures(run_dir)
    _say_if_not_arrived(status, run_dir)
    return code


def _say_if_not_arrived(status: Status, run_dir: str) -> None:
    """The run's last line says when it ended without the behaviour's success (no silent end), from
    summary.json: the outcome its experiment gave and, for a behaviour that goes somewhere, the stuck robots.
    Nothing for a behaviour without a judge of its own (`success` null)."""
    try:
        with open(os.path.join(run_dir, "summary.json"), encoding="utf-8") as f:
            summary = json.load(f)
    except (OSError, ValueError):
        return
    if summary.get("success") is not False:
        return
    stuck = " ".join(str(i) for i in summary.get("stuck_robots") or [])
    status.line(f"swarm: ended at tick {summary.get('ticks')} without success: outcome {summary.get('outcome')}"
                + (f", stuck robots {stuck}" if stuck else ""))


def kill(rid: int, run_dir: str) -> int:
    """`swarm kill ID`: SIGKILL one agent of the running swarm, after checking the pid is that agent."""
    path = os.path.join(run_dir, "agents.json")
    try:
        with open(path, encoding="utf-8", errors="backslashreplace") as f:
            agents = json.load(f)
    except FileNotFoundError:
        raise LaunchError(f"{path}: missing (no swarm was started with this run directory)") from None
    except (OSError, json.JSONDecodeError) as e:
        raise LaunchError(f"{path}: cannot read: {e}") from None
    pid = agents.get(str(rid)) if isinstance(agents, dict) else None
    if not isinstance(pid, int):
        raise LaunchError(f"{path}: no agent with id {rid} (ids 0..{len(agents) - 1})")
    try:
        with open(f"/proc/{pid}/stat") as f:
            zombie = f.read().rsplit(")", 1)[1].split()[0] == "Z"
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            argv = f.read().split(b"\0")
    except OSError:
        zombie = True
    if zombie:
        raise LaunchError(f"agent {rid} (pid {pid}) of {run_dir} is not running (it has exited; "
                          "another run: --run DIR)")
    names = [os.path.basename(a.decode(errors="replace")) for a in argv[:2]]  # [interpreter,] program
    if not any(n.startswith("robot_agent") for n in names) or str(rid).encode() not in argv:
        raise LaunchError(f"pid {pid} is not robot_agent --id {rid} (the swarm has ended; the pid is reused)")
    os.kill(pid, signal.SIGKILL)
    return pid
