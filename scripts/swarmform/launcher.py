"""`swarm run`: the world server and N robot agent processes, progress on the terminal, nothing left behind.

Order of a run:
  1. `world_server --check` validates the scenario with the overrides and tells N (file:line errors pass through);
  2. the run directory (runs/<UTC time>/ and runs/latest, or --out) with logs/;
  3. N `robot_agent --id K` processes, all in one process group of their own, then `world_server` with
     `--agent-pid K=PID` for each (it SIGKILLs the --kill ones at their exact ticks); agents.json (id -> pid)
     lets `swarm kill` find them;
  4. the world's `progress` lines become one status line; every other line it prints is shown and logged;
  5. when the world exits, the agents get a deadline to exit, then SIGKILL.
A `restart id=K` line of the world (a scheduled restart fault) starts a new agent K (faults.py).
Ctrl-C, SIGTERM and SIGHUP only set a flag that the loop (which polls, never blocks) acts on: the world gets
SIGTERM (it closes the recording and writes summary.json), then every process we started is killed by pid and
by group, and the launcher exits 130. Every child also has PR_SET_PDEATHSIG = SIGKILL, so even a SIGKILLed
launcher leaves nothing behind.
"""

import ctypes
import datetime
import json
import os
import re
import select
import signal
import subprocess
import sys
import time

from . import faults

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PROGRESS = re.compile(r"^progress tick=(\d+) alive=(\d+)/(\d+) tps=([0-9.eE+-]+|nan|inf)")
DONE = re.compile(r"^done ticks=(\d+) run_dir=(.*)$")
CHECK_TIMEOUT_S = 60
AGENT_EXIT_DEADLINE_S = 5.0
WORLD_STOP_DEADLINE_S = 10.0
EXIT_INTERRUPTED = 130
REPEATS_SHOWN = 3


class LaunchError(Exception):
    def __init__(self, message, code=1):
        super().__init__(message)
        self.code = code


def build_dir():
    return os.environ.get("BUILD_DIR") or os.path.join(ROOT, "build")


def executable(kind):
    rel = {"world": "world_server/world_server", "agent": "robot_agent/robot_agent",
           "inprocess": "world_server/harness/swarm_inprocess"}[kind]
    path = os.path.join(build_dir(), rel)
    if not os.access(path, os.X_OK):
        raise LaunchError(f"{path} not found: build it first (scripts/build), or set BUILD_DIR")
    return path


_libc = None


def _die_with_parent():
    """In the child before exec: be SIGKILLed if the launcher dies (Linux prctl PR_SET_PDEATHSIG = 1)."""
    global _libc
    try:
        _libc = _libc or ctypes.CDLL(None, use_errno=True)
        _libc.prctl(1, signal.SIGKILL, 0, 0, 0)
    except OSError:
        pass


def overrides(args):
    """The flags the world takes from `swarm run`, in its own spelling."""
    out = ["--scenario", args.scenario]
    for flag, value in (("--shape", args.shape), ("--robots", args.robots), ("--seed", args.seed),
                        ("--mode", args.mode), ("--max-ticks", args.max_ticks)):
        if value is not None:
            out += [flag, str(value)]
    for kill in args.kill:
        out += ["--kill", kill]
    for fault in getattr(args, "fault", None) or []:
        out += ["--fault", fault]
    return out


def check_scenario(world_exe, args):
    """Runs `world_server --check`; returns its JSON ({robots, labels, mode, max_ticks, seed})."""
    cmd = [world_exe] + overrides(args) + ["--check"]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=CHECK_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        raise LaunchError(f"{' '.join(cmd)} did not answer within {CHECK_TIMEOUT_S} s") from None
    if p.returncode != 0:
        raise LaunchError(p.stderr.strip() or f"world_server --check failed (exit {p.returncode})", 2)
    for line in reversed(p.stdout.strip().splitlines()):
        try:
            info = json.loads(line)
        except json.JSONDecodeError:
            continue
        if isinstance(info, dict) and isinstance(info.get("robots"), int):
            return info
    raise LaunchError(f"world_server --check printed no JSON line with 'robots': {p.stdout.strip()[:200]!r}")


def make_run_dir(out):
    """--out, or runs/<UTC time>/ with runs/latest pointing at it."""
    if out:
        os.makedirs(out, exist_ok=True)
        return os.path.abspath(out)
    runs = os.environ.get("SWARM_RUNS_DIR") or os.path.join(ROOT, "runs")
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

    def __init__(self):
        self.agents = {}  # id -> Popen
        self.groups = set()
        self.world = None
        self._files = []

    def _log(self, path):
        f = open(path, "ab")
        self._files.append(f)
        return f

    def start_agent(self, exe, rid, domain, log_path):
        cmd = [exe, "--id", str(rid)] + (["--domain", str(domain)] if domain is not None else [])
        log = self._log(log_path)
        group = next(iter(self.groups), 0)
        try:
            p = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                                 process_group=group, preexec_fn=_die_with_parent)
        except (subprocess.SubprocessError, OSError):  # the group is gone (its members all died): a new one
            p = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                                 process_group=0, preexec_fn=_die_with_parent)
        self.groups.add(os.getpgid(p.pid) if p.poll() is None else p.pid)
        self.agents[rid] = p
        return p

    def start_world(self, cmd):
        self.world = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                      stderr=subprocess.STDOUT, process_group=0, preexec_fn=_die_with_parent)
        return self.world

    def stop_world(self, deadline_s):
        """SIGTERM (the world closes its recording), then SIGKILL after the deadline. Returns its exit code."""
        w = self.world
        if w is None:
            return None
        if w.poll() is None:
            w.send_signal(signal.SIGTERM)
            try:
                w.wait(timeout=deadline_s)
            except subprocess.TimeoutExpired:
                _kill_quietly(lambda: os.killpg(w.pid, signal.SIGKILL))
                w.wait(timeout=5)
        return w.returncode

    def wait_agents(self, deadline_s):
        """Gives the agents until the deadline to exit, then SIGKILLs the stragglers. Returns how many were."""
        end = time.monotonic() + deadline_s
        for p in self.agents.values():
            try:
                p.wait(timeout=max(0.0, end - time.monotonic()))
            except subprocess.TimeoutExpired:
                pass
        stragglers = [p for p in self.agents.values() if p.poll() is None]
        self.kill_agents()
        return len(stragglers)

    def kill_agents(self):
        for g in self.groups:
            _kill_quietly(lambda g=g: os.killpg(g, signal.SIGKILL))
        for p in self.agents.values():
            if p.poll() is None:
                _kill_quietly(p.kill)
        for p in self.agents.values():
            try:
                p.wait(timeout=5)
            except subprocess.TimeoutExpired:
                pass

    def close(self):
        for f in self._files:
            f.close()


def _kill_quietly(fn):
    try:
        fn()
    except (ProcessLookupError, PermissionError):
        pass


class StopFlag:
    """SIGINT/SIGTERM/SIGHUP set it; the launcher's loop polls it (no exception at an arbitrary point)."""

    def __init__(self):
        self.signal = None
        self._old = {}
        for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            self._old[s] = signal.signal(s, self._handle)

    def _handle(self, signum, _frame):
        self.signal = self.signal or signum

    def __bool__(self):
        return self.signal is not None

    def restore(self):
        for s, h in self._old.items():
            signal.signal(s, h)


class Status:
    """One status line on a terminal (rewritten in place); plain lines, at most every few seconds, otherwise."""

    def __init__(self, stream=sys.stderr):
        self.stream, self.tty = stream, stream.isatty()
        self.last_plain, self.dirty = 0.0, False

    def progress(self, tick, alive, n, tps, max_ticks):
        of = f"/{max_ticks}" if max_ticks else ""
        text = f"tick {tick}{of}   robots alive {alive}/{n}   {tps:.1f} ticks/s"
        if self.tty:
            self.stream.write("\r\033[K" + text)
            self.dirty = True
        elif time.monotonic() - self.last_plain >= 5.0:
            self.stream.write(text + "\n")
            self.last_plain = time.monotonic()
        self.stream.flush()

    def line(self, text):
        if self.dirty:
            self.stream.write("\r\033[K")
            self.dirty = False
        self.stream.write(text + "\n")
        self.stream.flush()

    def end(self):
        if self.dirty:
            self.stream.write("\n")
            self.dirty = False


def _follow(proc, stop, status, console_log, max_ticks, prefix="world", on_line=None):
    """Reads the world's output until it exits or a stop is asked; returns the `done` line's fields or None.
    `on_line(line, status)` may take a line first (True: handled)."""
    fd = proc.stdout.fileno()
    os.set_blocking(fd, False)
    buf, done = b"", None
    seen = {}  # a line's pattern (digits blanked) -> times shown: "id 7 claimed by pid 123" x 256 shows 3


    def handle(raw):
        nonlocal done
        console_log.write(raw + b"\n")
        line = raw.decode(errors="replace").rstrip("\r")
        m = PROGRESS.match(line)
        if m:
            status.progress(int(m[1]), int(m[2]), int(m[3]), float(m[4]), max_ticks)
            return
        if on_line is not None and on_line(line, status):
            return
        m = DONE.match(line)
        if m:
            done = (int(m[1]), m[2])
        elif line.strip():
            pattern = re.sub(r"\d+", "#", line)
            seen[pattern] = seen.get(pattern, 0) + 1
            if seen[pattern] <= REPEATS_SHOWN:
                status.line(f"{prefix}: {line}")
            elif seen[pattern] == REPEATS_SHOWN + 1:
                status.line(f"{prefix}: ... (more lines like this in {os.path.basename(console_log.name)})")

    while not stop:
        ready, _, _ = select.select([fd], [], [], 0.2)
        if not ready:
            if proc.poll() is not None:
                break
            continue
        try:
            chunk = os.read(fd, 65536)
        except BlockingIOError:
            continue
        if not chunk:
            break
        buf += chunk
        *lines, buf = buf.split(b"\n")
        for raw in lines:
            handle(raw)
    if buf and not stop:
        handle(buf)
    console_log.flush()
    return done


def run(args, render_pictures):
    """`swarm run`. Returns the exit code; `render_pictures(run_dir)` draws the figures afterwards."""
    stop = StopFlag()
    procs = Processes()
    status = Status()
    try:
        if args.in_process:
            return _run_in_process(args, stop, status, render_pictures)
        world_exe, agent_exe = executable("world"), executable("agent")
        info = check_scenario(world_exe, args)
        if stop:
            return EXIT_INTERRUPTED
        n = info["robots"]
        max_ticks = info.get("max_ticks")
        run_dir = args.run_dir = make_run_dir(args.out)
        logs = os.path.join(run_dir, "logs")
        os.makedirs(logs, exist_ok=True)
        status.line(f"swarm: {n} robot agents, {info.get('mode', '?')} mode, up to {max_ticks} ticks, "
                    f"seed {info.get('seed')}; run directory {run_dir}")
        for rid in range(n):
            if stop:
                break
            procs.start_agent(agent_exe, rid, args.domain, os.path.join(logs, f"agent-{rid}.log"))
        with open(os.path.join(run_dir, "agents.json"), "w") as f:
            json.dump({str(k): p.pid for k, p in procs.agents.items()}, f, indent=1)
        if stop:
            return _interrupted(procs, stop, status, run_dir)
        cmd = [world_exe] + overrides(args) + ["--out", run_dir]
        if args.domain is not None:
            cmd += ["--domain", str(args.domain)]
        for rid, p in procs.agents.items():
            cmd += ["--agent-pid", f"{rid}={p.pid}"]
        started = time.monotonic()
        with open(os.path.join(logs, "world_console.log"), "ab") as console_log:
            procs.start_world(cmd)
            restarter = faults.Restarter(procs, agent_exe, args.domain, logs, run_dir, n)
            done = _follow(procs.world, stop, status, console_log, max_ticks, on_line=restarter.handle)
            while procs.world.poll() is None and not stop:  # its output closed; it should be exiting
                time.sleep(0.1)
        status.end()
        if stop:
            return _interrupted(procs, stop, status, run_dir)
        code = procs.world.returncode
        stragglers = procs.wait_agents(AGENT_EXIT_DEADLINE_S)
        if stragglers:
            status.line(f"swarm: {stragglers} agent(s) still running {AGENT_EXIT_DEADLINE_S:.0f} s after the world "
                        "ended were killed")
        if code != 0:
            status.line(f"swarm: world_server failed (exit {code}); its output is in {logs}/world_console.log")
            if os.path.exists(os.path.join(run_dir, "robots.csv")):
                status.line(f"swarm: what it recorded can be drawn: scripts/swarm replay {run_dir}")
            return code if code > 0 else 1
        ticks = done[0] if done else "?"
        status.line(f"swarm: {ticks} ticks in {time.monotonic() - started:.1f} s; run directory {run_dir}")
        stop.restore()  # Ctrl-C while drawing just stops the drawing
        code = 0 if args.no_pictures else render_pictures(run_dir)
        _say_if_not_arrived(status, run_dir)
        return code
    except LaunchError as e:
        status.end()
        print(f"swarm: {e}", file=sys.stderr)
        return e.code
    finally:
        procs.stop_world(WORLD_STOP_DEADLINE_S)
        procs.kill_agents()
        procs.close()
        stop.restore()


def _interrupted(procs, stop, status, run_dir):
    status.end()
    name = signal.Signals(stop.signal).name
    status.line(f"swarm: {name}: stopping the world (it closes the recording), then the agents")
    procs.stop_world(WORLD_STOP_DEADLINE_S)
    procs.kill_agents()
    status.line(f"swarm: stopped; what was recorded is in {run_dir} (`swarm replay {run_dir}` draws it)")
    return EXIT_INTERRUPTED


def _run_in_process(args, stop, status, render_pictures):
    """--in-process: the same scenario in one process (no DDS), the same run directory. Its stdout (the
    summary) goes to the log; its stderr carries the progress lines and messages."""
    exe = executable("inprocess")
    help_text = subprocess.run([exe, "--help"], capture_output=True, text=True, timeout=30).stdout
    cmd, flags, dropped = [exe], overrides(args), []
    for i in range(0, len(flags), 2):  # pass only the flags this runner documents
        if flags[i] == "--scenario" or flags[i] in help_text:
            cmd += flags[i:i + 2]
        else:
            dropped.append(flags[i])
    if args.domain is not None:
        dropped.append("--domain")
    if dropped:
        status.line(f"swarm: {', '.join(sorted(set(dropped)))} do(es) not apply to an in-process run; ignored")
    run_dir = args.run_dir = make_run_dir(args.out)
    cmd += ["--out", run_dir]
    procs = Processes()
    with open(os.path.join(run_dir, "inprocess_console.log"), "ab") as console_log:
        procs.world = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=console_log, stderr=subprocess.PIPE,
                                       process_group=0, preexec_fn=_die_with_parent)
        procs.world.stdout = procs.world.stderr  # _follow reads .stdout
        try:
            _follow(procs.world, stop, status, console_log, args.max_ticks, prefix="in-process")
            while procs.world.poll() is None and not stop:
                time.sleep(0.1)
        finally:
            status.end()
            code = procs.stop_world(WORLD_STOP_DEADLINE_S) if stop else procs.world.wait()
            procs.world.stderr.close()
    if stop:
        status.line(f"swarm: stopped; what was recorded is in {run_dir}")
        return EXIT_INTERRUPTED
    if code != 0:
        status.line(f"swarm: swarm_inprocess failed (exit {code})")
        return code if code > 0 else 1
    status.line(f"swarm: run directory {run_dir}")
    stop.restore()
    code = 0 if args.no_pictures else render_pictures(run_dir)
    _say_if_not_arrived(status, run_dir)
    return code


def _say_if_not_arrived(status, run_dir):
    """The run's last line says when it used up max_ticks without arriving (issue 17: no silent end), from
    summary.json: the outcome and the stuck robots, as world_server's own line gives them."""
    try:
        with open(os.path.join(run_dir, "summary.json"), encoding="utf-8") as f:
            summary = json.load(f)
    except (OSError, ValueError):
        return
    outcome = summary.get("outcome")
    if outcome in (None, "arrived", "none"):
        return
    stuck = " ".join(str(i) for i in summary.get("stuck_robots") or []) or "none"
    status.line(f"swarm: ended at tick {summary.get('ticks')} without arriving: outcome {outcome}, "
                f"stuck robots {stuck}")


def kill(rid, run_dir):
    """`swarm kill ID`: SIGKILL one agent of the running swarm, after checking the pid is that agent."""
    path = os.path.join(run_dir, "agents.json")
    try:
        with open(path) as f:
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
