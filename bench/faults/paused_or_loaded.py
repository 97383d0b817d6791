#!/usr/bin/env python3
"""bench/faults/paused_or_loaded.py BUILD_DIR DOMAIN OUT_DIR [CASE ...]: the paper's lockstep run
(scenarios/paper.yaml, world_server plus 9 robot_agent processes, the world given every agent's pid as the
launcher gives it) undisturbed, on a loaded host, or with every agent SIGSTOPped at once mid-formation; prints
one row per case: its trajectory_sha256, whether it is tests/golden's paper hash, end_reason, deaths, rejoins,
stragglers (agent_stalled events) and alive_at_end (docs/faults.md "Paused or loaded").

CASE: `none`; `load` or `load:K` (K CPU-spinning processes per core, default 4, each in a session of its own,
for the run's whole length); `pause:S` (every agent stopped for S seconds, 0.1 s after every agent connected: the run lasts about a second on an idle host).
Default: none load pause:0.7 pause:1 pause:2. REPEAT (environment, default 1): runs of each case. Every
process it starts is killed by pid at the end; every wait has a deadline.
"""

import json
import os
import signal
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ROBOTS = 9
RUN_DEADLINE_S = 180
HOGS_PER_CORE = 4


def kill_all(procs):
    for p in procs:
        if p.poll() is None:
            try:
                os.kill(p.pid, signal.SIGCONT)
                os.kill(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
    for p in procs:
        try:
            p.wait(timeout=30)
        except subprocess.TimeoutExpired:
            pass


def run_case(build, domain, out, case, n):
    run_dir = os.path.join(out, f"{case.replace(':', '-')}-{n}")
    os.makedirs(run_dir, exist_ok=True)
    hogs, agents, world = [], [], None
    try:
        if case == "load" or case.startswith("load:"):
            per_core = int(case.split(":", 1)[1]) if ":" in case else HOGS_PER_CORE
            for _ in range(per_core * (os.cpu_count() or 1)):
                hogs.append(subprocess.Popen(["sh", "-c", "while :; do :; done"], start_new_session=True))
        for i in range(ROBOTS):
            agents.append(subprocess.Popen([os.path.join(build, "robot_agent", "robot_agent"), "--id", str(i),
                                            "--domain", str(domain), "--timeout", "30"],
                                           stdout=subprocess.DEVNULL,
                                           stderr=open(os.path.join(run_dir, f"agent{i}.err"), "w")))
        argv = [os.path.join(build, "world_server", "world_server"), "--scenario",
                os.path.join(ROOT, "scenarios", "paper.yaml"), "--out", os.path.join(run_dir, "run"),
                "--domain", str(domain), "--connect-timeout", "30"]
        for i, a in enumerate(agents):
            argv += ["--agent-pid", f"{i}={a.pid}"]
        world_out = os.path.join(run_dir, "world.out")
        world = subprocess.Popen(argv, stdout=open(world_out, "w"),
                                 stderr=open(os.path.join(run_dir, "world.err"), "w"))
        if case.startswith("pause:"):
            seconds = float(case.split(":", 1)[1])
            end = time.monotonic() + 60
            while time.monotonic() < end and world.poll() is None:
                with open(world_out) as f:
                    if "connected agents=" in f.read():
                        break
                time.sleep(0.05)
            time.sleep(0.1)
            for a in agents:
                os.kill(a.pid, signal.SIGSTOP)
            time.sleep(seconds)
            for a in agents:
                os.kill(a.pid, signal.SIGCONT)
        try:
            world.wait(timeout=RUN_DEADLINE_S)
        except subprocess.TimeoutExpired:
            pass
        for a in agents:  # they hear the end, or are killed below
            try:
                a.wait(timeout=10)
            except subprocess.TimeoutExpired:
                pass
    finally:
        kill_all(hogs + agents + ([world] if world else []))
    try:
        with open(os.path.join(run_dir, "run", "summary.json")) as f:
            summary = json.load(f)
        with open(os.path.join(run_dir, "run", "events.jsonl"), encoding="utf-8", errors="replace") as f:
            summary["stalled"] = sum(1 for line in f if '"kind":"agent_stalled"' in line.replace(" ", ""))
        return summary
    except (OSError, ValueError) as e:
        return {"error": str(e)}


def main():
    if len(sys.argv) < 4 or sys.argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(sys.argv) > 1 else 2
    build, domain, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    cases = sys.argv[4:] or ["none", "load", "pause:0.7", "pause:1", "pause:2"]
    with open(os.path.join(ROOT, "tests", "golden", "golden.json")) as f:
        golden = json.load(f)["paper"]["sha256"]
    os.makedirs(out, exist_ok=True)
    print("| case | trajectory_sha256 | = golden | end_reason | deaths | rejoins | stragglers | alive_at_end | wall s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for n, case in enumerate([c for c in cases for _ in range(int(os.environ.get("REPEAT", "1")))]):
        s = run_case(build, domain, out, case, n)
        if "error" in s:
            print(f"| {case} | no summary: {s['error']} | | | | | | | |", flush=True)
            continue
        sha = s.get("trajectory_sha256", "")
        print(f"| {case} | `{sha[:12]}` | {'yes' if sha == golden else 'no'} | {s.get('end_reason')} | "
              f"{len(s.get('deaths', []))} | {len(s.get('rejoins', []))} | {s['stalled']} | {s.get('alive_at_end')}/{ROBOTS} | "
              f"{s.get('wall_seconds', 0):.1f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
