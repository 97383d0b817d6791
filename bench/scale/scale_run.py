#!/usr/bin/python3
"""P2 (BENCHMARKS.md): N agent processes and the world on this machine, realtime mode; prints one JSON line.

  bench/scale/scale_run.py [--agents 1024] [--ticks 600] [--scenario bench/scale/realtime.yaml]
                           [--area-per-robot 0.6] [--domain 180] [--connect-timeout S] [--build-dir build]
                           [--keep DIR] [--launch block|each]

Run it in a network namespace of its own (`ip netns exec NS ...`): the UDP drop counters are then the run's
alone (/proc/net/snmp and /proc/net/udp are per namespace), and no other DDS process is on its loopback.

The scenario's start region is sized for N (--area-per-robot m^2 a robot, a square; the arena around it 10 m
wider, at least the template's): the template's own region holds only ~300 robots. The sized copy is written
next to the run (its `shape` made absolute).

How the agents start (--launch): `block` (default) is one `robot_agent --id 0 --count N`, whose N robots are N
processes forked from it (common/dds/robot_block.hpp: the way to start many agents on one machine, without
each paying ~20 ms of CPU to load the DDS libraries); `each` is N `robot_agent --id K` executables. The
world is started before them, as `scripts/swarm run` does.

What it measures, in one run:
  cpu_seconds_until_connected  CPU (utime + stime) the agents together and the world had used when every agent
                    was connected: against 2 cores x connect_seconds, it says whether start-up is CPU-bound;
  connect_seconds   from the start of the world until it had every agent connected: the arrival of
                    its `connected agents=N` line (read from its stdout as it comes). clock_start_seconds: when
                    its realtime clock started, from its first `progress tick=T` line, which comes T periods
                    later (error ~ a few ms); the two agree within that error unless the world's first rounds stall;
  missed_ticks      the world's own count: its `missed_tick` events in events.jsonl (a live agent's command
                    for tick t not in before tick t+1; world_server/server.cpp), checked against the
                    "K missed ticks" line it prints on stderr;
  rss_mib           VmRSS of every agent (/proc/PID/status) sampled mid-run: max, median, mean; and the world's;
  pss_mib           the proportional set size of every agent (/proc/PID/smaps_rollup Pss, sampled after the
                    CPU window): a forked agent shares its pages with its siblings, so RSS counts the shared
                    libraries in full in every agent and PSS divides them: the memory the N agents really
                    take is agents_total; max, median, mean per agent;
  cpu               utime+stime (/proc/PID/stat) of the agents together and of the world over the middle of the
                    run, as % of one core. The agents are idle but for one control step and one DDS round
                    trip per 100 ms, so the agents' figure is reported as the idle CPU;
  achieved_ticks_per_second  ticks / wall time from the run's summary.json;
  agents_running_at_95_percent, alive_at_end, deaths, rejoins  agent processes still running at 95% of the
                    run (an agent that gave up on the world exited 3) against the world's count of live robots
                    at the end and its deaths and rejoins (summary.json): the two counts should agree;
  ticks_with_a_miss, most_misses_in_one_tick  how the misses fell: a few ticks with many agents each (a late
                    publish phase) or one here and there;
  late_commands     for the commands that came in after their tick (null if none): how many, how many were
                    sent after the deadline already, and median / max of when their packet was written in
                    the round, how long the agent took to answer it, and the transit (world's own line);
  world_publish_per_round  the world's own profile line: the publish phase's wall time, its main thread's CPU
                    time in it and its preemptions, per round;
  udp_receive_buffer_errors  datagrams the kernel dropped on full UDP receive buffers during the run
                    (/proc/net/snmp RcvbufErrors: the network namespace's; machine-wide without one);
  threads           where the CPU of the middle of the run went, by thread name (the main thread carries the
                    program's name; Cyclone's: recvUC user data, recv discovery, tev timed events, gc leases):
                    agents_per_agent_tick {name: {us, switches}} (CPU µs and context switches, i.e. wake-ups,
                    per agent per tick, over the agents_counted agents alive at both ends of the window),
                    world_per_tick the same per tick; window_ticks, the ticks they are divided by (from the
                    world's progress lines, within a second's worth);
  udp_socket_drops  the same per socket at 95% of the run (/proc/net/udp `drops`, while every socket is open; since
                    each socket opened), summed over the world's
                    sockets (its fixed ports) and over the agents' (the rest), to say whose buffer overflowed;
  load_average      /proc/loadavg at the start and at the end (the host is shared: read every figure with it).
Every process started here is killed by its pid at the end, a block's agents too while the block runs (the
world and the block also get PR_SET_PDEATHSIG, the block's agents get SIGTERM when it dies; executables started
with --launch each give up by themselves after --timeout without a world); every wait has a deadline.
"""
import argparse
import ctypes
import json
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CLK_TCK = os.sysconf("SC_CLK_TCK")
_libc = ctypes.CDLL("libc.so.6", use_errno=True)

children = []
forked = []  # (block process, pids of the agents it forked): killed by pid too, at the end


def read_block_pids(path, n):
    """The pids a `robot_agent --count` block printed ("robot_agent: id K pid P"), by id, once all n are there."""
    pids = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"robot_agent: id (\d+) pid (\d+)", line)
            if m:
                pids[int(m.group(1))] = int(m.group(2))
    return [pids[i] for i in range(n)] if len(pids) == n else None


def _die_with_parent():
    _libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


def spawn(argv, die_with_parent=True, nice=0, **kw):
    def before_exec():
        if die_with_parent:
            _die_with_parent()
        if nice:
            os.nice(nice)
    p = subprocess.Popen(argv, preexec_fn=before_exec if die_with_parent or nice else None, **kw)
    children.append(p)
    return p


def kill_all():
    for block, pids in forked:
        if block.poll() is not None:
            continue  # it reaped its agents before it exited: their pids may belong to others by now
        for pid in pids:
            try:
                os.kill(pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
    forked.clear()
    for p in children:
        if p.poll() is None:
            try:
                os.kill(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
    for p in children:
        try:
            p.wait(timeout=5)
        except subprocess.TimeoutExpired:
            pass
    children.clear()


def cpu_ticks(stat_path):
    """utime + stime in clock ticks from a /proc .../stat file (a process's or a thread's); None when it is gone."""
    try:
        with open(stat_path) as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return int(fields[11]) + int(fields[12])
    except (OSError, IndexError, ValueError):
        return None


def cpu_seconds(pid):
    """utime + stime of a live process, in seconds (None when it is gone)."""
    ticks = cpu_ticks(f"/proc/{pid}/stat")
    return None if ticks is None else ticks / CLK_TCK


def rss_mib(pid):
    try:
        with open(f"/proc/{pid}/status") as f:
            for line in f:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def pss_mib(pid):
    """Proportional set size of a live process (/proc/PID/smaps_rollup), MiB; None when unreadable."""
    try:
        with open(f"/proc/{pid}/smaps_rollup") as f:
            for line in f:
                if line.startswith("Pss:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        return None
    return None


def udp_socket_drops(domain):
    """Drops per UDP socket now (/proc/net/udp and udp6, this namespace), summed for the world's fixed ports
    (7400 + 100 x domain + 10..99: its faces' discovery and data ports) and for every other socket (the agents')."""
    lo, hi = 7400 + 100 * domain + 10, 7400 + 100 * domain + 99
    world = agents = 0
    for path in ("/proc/net/udp", "/proc/net/udp6"):
        try:
            with open(path) as f:
                rows = f.read().splitlines()[1:]
        except OSError:
            continue
        for row in rows:
            fields = row.split()
            try:
                port = int(fields[1].rsplit(":", 1)[1], 16)
                drops = int(fields[-1])
            except (IndexError, ValueError):
                continue
            if lo <= port <= hi:
                world += drops
            else:
                agents += drops
    return {"world_sockets": world, "agent_sockets": agents}


def load_average():
    try:
        with open("/proc/loadavg") as f:
            return [float(x) for x in f.read().split()[:3]]
    except (OSError, ValueError):
        return None


def sized_scenario(template, agents, area_per_robot, out_path):
    """The template with its start region a square of agents x area_per_robot m^2 (the arena 10 m wider, at least
    the template's), its shape made absolute; written to out_path. Only the template's own one-line `arena:` and
    `robots:` mappings and its `shape:` line are rewritten (bench/scale/realtime.yaml)."""
    side = round((agents * area_per_robot) ** 0.5, 2)
    folder = os.path.dirname(os.path.abspath(template))
    lines = []
    with open(template) as f:
        for line in f:
            m = re.match(r"arena: \{centre: \[([^]]*)\], width: ([0-9.]+), height: ([0-9.]+)(.*)$", line)
            if m:
                width = max(float(m[2]), side + 10.0)
                height = max(float(m[3]), side + 10.0)
                line = f"arena: {{centre: [{m[1]}], width: {width}, height: {height}{m[4]}\n"
            m = re.match(r"robots: \{count: (\d+), region: \{centre: \[([^]]*)\], width: [0-9.]+, height: [0-9.]+\}\}",
                         line)
            if m:
                line = f"robots: {{count: {agents}, region: {{centre: [{m[2]}], width: {side}, height: {side}}}}}\n"
            m = re.match(r"shape: (\S+)\s*$", line)
            if m and not os.path.isabs(m[1]):
                for base in (folder, os.path.join(ROOT, "shapes")):
                    if os.path.isfile(os.path.join(base, m[1])):
                        line = f"shape: {os.path.join(base, m[1])}\n"
                        break
            lines.append(line)
    with open(out_path, "w") as f:
        f.writelines(lines)
    return side


def udp_receive_buffer_errors():
    """Datagrams the kernel dropped because a UDP socket's receive buffer was full, machine-wide since boot
    (/proc/net/snmp); None where unreadable."""
    try:
        with open("/proc/net/snmp") as f:
            rows = [line.split() for line in f if line.startswith("Udp:")]
        return int(rows[1][rows[0].index("RcvbufErrors")])
    except (OSError, IndexError, ValueError):
        return None


def publish_phase(err):
    """The world's publish phase per round from its profile line on stderr (world_server/server.cpp):
    wall and main-thread CPU in ms, and its preemptions; None if the line is missing."""
    m = re.search(r"per round \(us\): publish ([0-9.]+) \(on CPU ([0-9.]+), preempted ([0-9.]+) times\)", err)
    if not m:
        return None
    return {"wall_ms": round(float(m.group(1)) / 1e3, 3), "on_cpu_ms": round(float(m.group(2)) / 1e3, 3),
            "preempted": float(m.group(3))}


def late_commands(err):
    """Where the late commands' time went, from the world's late-commands line on stderr (late_commands.hpp):
    count, how many were sent after the deadline, and median / max ms of each part; None without late ones."""
    m = re.search(r"(\d+) late commands \((\d+) sent after the deadline\): packet written ([0-9.]+) ms \(median; "
                  r"max ([0-9.]+)\) into the round, answered ([0-9.]+) ms \(median; max ([0-9.]+)\) after it, "
                  r"transit ([0-9.]+) ms \(median; max ([0-9.]+)\)", err)
    if not m:
        return None
    v = [float(x) for x in m.groups()]
    return {"count": int(v[0]), "sent_after_deadline": int(v[1]),
            "written_ms": {"median": v[2], "max": v[3]}, "answered_ms": {"median": v[4], "max": v[5]},
            "transit_ms": {"median": v[6], "max": v[7]}}


def thread_split(pids):
    """{(pid, tid): (thread name, CPU clock ticks, context switches)} of every thread of `pids`. The switches are
    voluntary + involuntary (each wake-up is one); the main thread carries the program's name, Cyclone's own are
    recvUC (user data), recv (discovery), tev (timed events), gc (leases, deletions), dq.builtins, dq.user."""
    out = {}
    for pid in pids:
        try:
            tids = os.listdir(f"/proc/{pid}/task")
        except OSError:
            continue
        for tid in tids:
            base = f"/proc/{pid}/task/{tid}"
            try:
                with open(base + "/comm") as f:
                    name = f.read().strip()
                switches = 0
                with open(base + "/status") as f:
                    for line in f:
                        if "ctxt_switches" in line:
                            switches += int(line.split()[1])
            except (OSError, ValueError):
                continue  # the thread ended meanwhile
            cpu = cpu_ticks(base + "/stat")
            if cpu is not None:
                out[(pid, tid)] = (name, cpu, switches)
    return out


def split_per_tick(before, after, ticks):
    """{thread name: {"us": CPU µs, "switches": context switches}} per process-tick over `ticks` ticks, summed
    over the threads present at both ends, divided by the processes present at both ends (an agent that died
    or left meanwhile counts in neither), the dearest first; and that process count."""
    cpu, switches, processes = {}, {}, set()
    for key, (name, cpu1, sw1) in after.items():
        if key in before:
            _, cpu0, sw0 = before[key]
            cpu[name] = cpu.get(name, 0) + cpu1 - cpu0
            switches[name] = switches.get(name, 0) + sw1 - sw0
            processes.add(key[0])
    per = ticks * len(processes)
    if per <= 0:
        return {}, 0
    rows = sorted(cpu, key=lambda name: -cpu[name])
    return ({name: {"us": round(cpu[name] / CLK_TCK * 1e6 / per, 1), "switches": round(switches[name] / per, 2)}
             for name in rows}, len(processes))


def read_world(world, lines, first_progress, connected, last_tick):
    """Reads the world's stdout as it comes; notes when the connected line and the first progress line arrived,
    and the tick of the last progress line (last_tick[0])."""
    for line in world.stdout:
        now = time.monotonic()
        lines.append(line.rstrip("\n"))
        if not connected and line.startswith("connected agents="):
            connected.append(now)
        if line.startswith("progress tick="):
            tick = int(line.split()[1].split("=")[1])
            last_tick[0] = tick
            if not first_progress:
                first_progress.append((now, tick))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    ap.add_argument("--agents", "--robots", dest="robots", type=int, default=1024, metavar="N",
                    help="agent processes (robots) in the run (default 1024)")
    ap.add_argument("--ticks", type=int, default=600)
    ap.add_argument("--scenario", default=os.path.join(ROOT, "bench", "scale", "realtime.yaml"),
                    help="the template scenario (its region is resized for N)")
    ap.add_argument("--area-per-robot", type=float, default=0.6, metavar="M2",
                    help="start region per robot, m^2 (default 0.6, as P3's workload)")
    ap.add_argument("--domain", type=int, default=180, help="DDS domain id (0..232)")
    ap.add_argument("--connect-timeout", type=float, default=None, metavar="S",
                    help="seconds the world waits for every agent (default: world_server's, 30 + 0.025 x N)")
    ap.add_argument("--keep", metavar="DIR", help="copy the world's run folder (events.jsonl, summary.json) here")
    ap.add_argument("--build-dir", default=os.environ.get("BUILD_DIR", os.path.join(ROOT, "build")))
    ap.add_argument("--agents-nice", type=int, default=0, metavar="N",
                    help="start the agents' block at this niceness (0..19; --launch block only): an experiment in "
                         "giving the world the larger CPU share")
    ap.add_argument("--launch", choices=("block", "each"), default="block",
                    help="one robot_agent --count N forking the agents (default), or N executables")
    a = ap.parse_args()
    if a.robots < 1 or a.ticks < 20 or not 0 <= a.domain <= 232 or not a.area_per_robot > 0:
        print("scale_run: --agents >= 1, --ticks >= 20, --domain 0..232, --area-per-robot > 0", file=sys.stderr)
        return 2
    if a.connect_timeout is None:
        a.connect_timeout = 30.0 + 0.025 * a.robots  # world_server's default (world_server/server.hpp)
    scratch = tempfile.mkdtemp(prefix="bench-scale-scenario-")
    template = a.scenario
    a.scenario = os.path.join(scratch, "scale.yaml")
    try:
        side = sized_scenario(template, a.robots, a.area_per_robot, a.scenario)
    except OSError as e:
        print(f"scale_run: {template}: {e}", file=sys.stderr)
        shutil.rmtree(scratch, ignore_errors=True)
        return 2
    world_exe = os.path.join(a.build_dir, "world_server", "world_server")
    agent_exe = os.path.join(a.build_dir, "robot_agent", "robot_agent")
    for exe in (world_exe, agent_exe):
        if not os.access(exe, os.X_OK):
            print(f"scale_run: {exe} is missing (build it, or pass --build-dir)", file=sys.stderr)
            return 2
    check = subprocess.run([world_exe, "--check", "--scenario", a.scenario, "--robots", str(a.robots)],
                           capture_output=True, text=True, timeout=60)
    if check.returncode != 0:
        print(check.stderr.strip(), file=sys.stderr)
        shutil.rmtree(scratch, ignore_errors=True)
        return 2
    rate = None
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    try:
        with tempfile.TemporaryDirectory(prefix="bench-scale-") as tmp:
            run_dir = os.path.join(tmp, "run")
            timeout = a.connect_timeout + 10
            drops0 = udp_receive_buffer_errors()
            load0 = load_average()
            t0 = time.monotonic()
            # The world first, as `scripts/swarm run` starts it: agents announce themselves every 2 s, so an
            # agent started before the world would wait for its next announcement.
            world_err = open(os.path.join(tmp, "world.err"), "w+")
            world = spawn([world_exe, "--scenario", a.scenario, "--robots", str(a.robots), "--mode", "realtime",
                           "--max-ticks", str(a.ticks), "--out", run_dir, "--domain", str(a.domain),
                           "--connect-timeout", str(a.connect_timeout)],
                          stdout=subprocess.PIPE, stderr=world_err, text=True)
            lines, first, connected, last_tick = [], [], [], [0]
            reader = threading.Thread(target=read_world, args=(world, lines, first, connected, last_tick),
                                      daemon=True)
            reader.start()
            # No preexec_fn for the agents: it forces Python to fork itself 256 times (11 s on a loaded 2-core
            # machine, against 1.5 s with vfork), which would be measured as the swarm's start-up. An agent
            # left behind by a SIGKILLed benchmark gives up by itself after --timeout without its world.
            if a.launch == "each":
                agents = [spawn([agent_exe, "--id", str(i), "--domain", str(a.domain), "--timeout",
                                 str(timeout), "--world-pid", str(world.pid)], die_with_parent=False,
                                stdout=subprocess.DEVNULL,
                                stderr=subprocess.DEVNULL)
                          for i in range(a.robots)]
                agent_pids = [p.pid for p in agents]
            else:
                block_out = os.path.join(tmp, "block.out")
                block_err = os.path.join(tmp, "block.err")  # why an agent gave up, if one did
                with open(block_out, "w") as out, open(block_err, "w") as err_file:
                    block = spawn([agent_exe, "--id", "0", "--count", str(a.robots), "--domain", str(a.domain),
                                   "--timeout", str(timeout), "--world-pid", str(world.pid)], nice=a.agents_nice,
                                  stdout=out, stderr=err_file)
                agent_pids = None
                deadline = time.monotonic() + max(60.0, a.connect_timeout)  # forking 2048 took > 60 s
                while agent_pids is None and block.poll() is None and time.monotonic() < deadline:
                    time.sleep(0.01)
                    agent_pids = read_block_pids(block_out, a.robots)
                if agent_pids is None:
                    raise RuntimeError(f"robot_agent --count {a.robots} did not start its agents "
                                       f"(exit {block.poll()})")
                forked.append((block, agent_pids))
            spawned = time.monotonic() - t0
            with open(a.scenario) as f:
                rate = 10.0
                for line in f:
                    if line.startswith("tick_rate:"):
                        rate = float(line.split(":", 1)[1].split("#")[0])
            # Wait for the first progress line (the run started), with a deadline.
            deadline = time.monotonic() + a.connect_timeout + 5
            cpu_at_connect = None
            while not first and world.poll() is None and time.monotonic() < deadline:
                if connected and cpu_at_connect is None:  # start-up's CPU: is connecting CPU-bound?
                    cpu_at_connect = {"agents": round(sum(c for c in (cpu_seconds(p) for p in agent_pids)
                                                          if c is not None), 2),
                                      "world": cpu_seconds(world.pid)}
                time.sleep(0.02)
            if not first:
                world_err.seek(0)
                said = [x for x in world_err.read().splitlines() if "missing after" in x or "matched no" in x]
                agents_said = []
                if a.launch == "block":
                    with open(block_err, errors="replace") as f:
                        agents_said = [x for x in f.read().splitlines() if x.strip()][-3:]
                raise RuntimeError(f"the world did not start ticking (exit {world.poll()}); its last lines: "
                                   f"{lines[-3:]}; {said[-1:] or 'no missing ids said yet'}; the agents' last "
                                   f"messages: {agents_said or 'none'}")
            clock_start_seconds = first[0][0] - first[0][1] / rate - t0
            connect_seconds = connected[0] - t0 if connected else clock_start_seconds
            # CPU over the middle of the run: from 20% to 80% of its ticks; RSS sampled at the end of it.
            run_seconds = a.ticks / rate
            started = first[0][0] - first[0][1] / rate
            time.sleep(max(0.0, started + 0.2 * run_seconds - time.monotonic()))
            pids = agent_pids
            c0 = [cpu_seconds(p) for p in pids]
            w0 = cpu_seconds(world.pid)
            m0 = time.monotonic()
            split0 = (thread_split(pids), thread_split([world.pid]), last_tick[0])
            time.sleep(max(0.0, started + 0.8 * run_seconds - time.monotonic()))
            c1 = [cpu_seconds(p) for p in pids]
            w1 = cpu_seconds(world.pid)
            window = time.monotonic() - m0
            split1 = (thread_split(pids), thread_split([world.pid]), last_tick[0])
            # The world's progress lines come once a second, so both ends lag alike: the ticks between are
            # those of the window within a second's worth.
            window_ticks = split1[2] - split0[2]
            agents_split, agents_counted = split_per_tick(split0[0], split1[0], window_ticks)
            world_split, _ = split_per_tick(split0[1], split1[1], window_ticks)
            rss = [r for r in (rss_mib(p) for p in pids) if r is not None]
            world_rss = rss_mib(world.pid)
            live = [(b - a_) for a_, b in zip(c0, c1) if a_ is not None and b is not None]
            pss = [r for r in (pss_mib(p) for p in pids) if r is not None]  # after the CPU window: it costs
            world_pss = pss_mib(world.pid)
            # Per-socket drops while every socket is still open (the world closes its own at the end).
            time.sleep(max(0.0, started + 0.95 * run_seconds - time.monotonic()))
            socket_drops = udp_socket_drops(a.domain)
            # Agents still running near the end, against the robots the world still counts alive: an agent
            # that gave up (exit 3) is gone from both, unless the world missed its going.
            agents_running = sum(1 for p in pids if cpu_seconds(p) is not None)
            try:
                world.wait(timeout=run_seconds + 60)
            except subprocess.TimeoutExpired:
                raise RuntimeError("the world did not finish in time")
            reader.join(timeout=5)
            drops1 = udp_receive_buffer_errors()
            load1 = load_average()
            world_err.seek(0)
            err = world_err.read()
            if world.returncode != 0:
                raise RuntimeError(f"world_server exited {world.returncode}: {err.strip()[-500:]}")
            with open(os.path.join(run_dir, "summary.json")) as f:
                summary = json.load(f)
            if a.keep:
                shutil.copytree(run_dir, a.keep, dirs_exist_ok=True)
                with open(os.path.join(a.keep, "world.err"), "w") as f:
                    f.write(err)
            missed_by_tick = {}
            with open(os.path.join(run_dir, "events.jsonl")) as f:
                for line in f:
                    event = json.loads(line)
                    if event.get("kind") == "missed_tick":
                        tick = int(event.get("tick", 0))
                        missed_by_tick[tick] = missed_by_tick.get(tick, 0) + 1
            missed = sum(missed_by_tick.values())
            missed_by_tenth = [0] * 10  # where in the run the misses fell (tenths of --ticks)
            for tick, n in missed_by_tick.items():
                missed_by_tenth[min(9, max(0, tick * 10 // a.ticks))] += n
            said = 0
            for line in err.splitlines():
                if line.endswith("missed ticks (see events)"):
                    said = int(line.split()[1])
            if said != missed:
                raise RuntimeError(f"the world said {said} missed ticks, its events hold {missed}")
            result = {
                "robots": a.robots, "ticks": summary["ticks"], "tick_rate": rate, "behaviour": "random_walk",
                "launch": a.launch, "agents_nice": a.agents_nice, "region_side_m": side, "connect_timeout_s": a.connect_timeout,
                "load_average": {"start": load0, "end": load1},
                "spawn_seconds": round(spawned, 3),
                "connect_seconds": round(connect_seconds, 3),
                "clock_start_seconds": round(clock_start_seconds, 3),
                "cpu_seconds_until_connected": cpu_at_connect,
                "missed_ticks": missed,
                "missed_ticks_by_tenth_of_run": missed_by_tenth,
                # Bursts: few ticks with many agents each (the world's publish phase ran late), or a spread.
                "ticks_with_a_miss": len(missed_by_tick),
                "most_misses_in_one_tick": max(missed_by_tick.values(), default=0),
                "world_publish_per_round": publish_phase(err),
                "late_commands": late_commands(err),
                # Machine-wide, start to end of the run: the world's discovery socket overflows while 256
                # agents discover it (BENCHMARKS.md, P2); other processes' drops count too.
                "udp_receive_buffer_errors": (drops1 - drops0) if drops0 is not None and drops1 is not None
                else None,
                "udp_socket_drops": socket_drops,
                "achieved_ticks_per_second": summary["ticks_per_second"],
                "agents_running_at_95_percent": agents_running,
                "alive_at_end": summary["alive_at_end"],
                "deaths": len(summary.get("deaths", [])), "rejoins": len(summary.get("rejoins", [])),
                "rss_mib": {"agents_max": round(max(rss), 2) if rss else None,
                            "agents_median": round(statistics.median(rss), 2) if rss else None,
                            "agents_mean": round(statistics.mean(rss), 2) if rss else None,
                            "agents_sampled": len(rss),
                            "world": round(world_rss, 2) if world_rss is not None else None},
                "pss_mib": {"agents_max": round(max(pss), 2) if pss else None,
                            "agents_median": round(statistics.median(pss), 2) if pss else None,
                            "agents_mean": round(statistics.mean(pss), 2) if pss else None,
                            "agents_total": round(sum(pss), 1) if pss else None,
                            "agents_sampled": len(pss),
                            "world": round(world_pss, 2) if world_pss is not None else None},
                "cpu_percent_of_one_core": {
                    "agents_total": round(100.0 * sum(live) / window, 1),
                    "agent_mean": round(100.0 * sum(live) / window / max(1, len(live)), 3),
                    "world": round(100.0 * (w1 - w0) / window, 1) if w0 is not None and w1 is not None
                    else None,
                    "window_seconds": round(window, 1)},
                # Where each agent-tick's CPU goes, by thread, and how often each thread woke.
                "threads": {"window_ticks": window_ticks, "agents_counted": agents_counted,
                            "agents_per_agent_tick": agents_split, "world_per_tick": world_split},
            }
    except KeyboardInterrupt:
        return 130
    except (RuntimeError, OSError, ValueError, KeyError) as e:
        print(f"scale_run: {e}", file=sys.stderr)
        return 1
    finally:
        kill_all()
        shutil.rmtree(scratch, ignore_errors=True)
    print(json.dumps(result), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
