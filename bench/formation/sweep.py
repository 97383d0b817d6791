#!/usr/bin/env python3
"""Formation sweep (issue 17, formation rows): runs swarm_inprocess over shapes x seeds x robot counts and over
kill schedules on scenarios/paper.yaml, two runs at a time, and prints one line per failure and the totals.

  bench/formation/sweep.py shapes [--seeds 20] [--max-ticks 4000]
  bench/formation/sweep.py kills  [--max-ticks 3000]
  bench/formation/sweep.py paper
SWARM_INPROCESS=path runs another build's binary.

A run passes when formation_tick is set, shape_error_at_formation <= 0.1 and there is no robot-robot contact
(kills: formation_tick set, and no robot-robot contact)."""
import argparse
import concurrent.futures as cf
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BIN = os.environ.get("SWARM_INPROCESS", os.path.join(ROOT, "build/world_server/harness/swarm_inprocess"))


def labels(shape):
    n = 0
    with open(shape) as f:
        for line in f:
            if line.lstrip().startswith("#"):
                continue
            n += sum(1 for t in line.split() if t.lstrip("-").isdigit() and int(t) >= 0)
    return n


def run(args):
    cmd = [BIN, "--scenario", os.path.join(ROOT, "scenarios/paper.yaml"), "--no-record", "--quiet"] + args
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    try:
        s = json.loads(out.stdout)
    except json.JSONDecodeError:
        return " ".join(args), None
    return " ".join(args), s


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("what", choices=["shapes", "kills", "paper"])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--max-ticks", type=int, default=4000)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--shapes", nargs="*")
    a = ap.parse_args()
    jobs = []
    if a.what == "shapes":
        shapes = a.shapes or sorted(f for f in os.listdir(os.path.join(ROOT, "shapes")) if f.endswith(".txt"))
        for sh in shapes:
            n = labels(os.path.join(ROOT, "shapes", sh))
            for robots in (n, n + 3):
                for seed in range(1, a.seeds + 1):
                    jobs.append(["--shape", "shapes/" + sh, "--robots", str(robots), "--seed", str(seed),
                                 "--max-ticks", str(a.max_ticks)])
    elif a.what == "kills":
        for k in range(9):
            for t in (1, 5, 10, 25, 50, 100, 200, 400):
                jobs.append(["--kill", f"{k}@{t}", "--max-ticks", str(a.max_ticks)])
    else:
        jobs.append(["--max-ticks", str(a.max_ticks)])
    ok = 0
    ticks = []
    errs = []
    worst = []
    contacts_obstacle = 0
    per_shape = {}
    with cf.ThreadPoolExecutor(a.jobs) as ex:
        for args, s in ex.map(run, jobs):
            if s is None:
                print("CRASH", args)
                continue
            ft = s.get("formation_tick")
            err = s.get("shape_error_at_formation")
            rr = s.get("collisions_robot_robot", 0)
            contacts_obstacle += s.get("collisions_robot_obstacle", 0)
            good = ft is not None and rr == 0 and (a.what == "kills" or (err is not None and err <= 0.1))
            if good:
                ok += 1
                ticks.append(ft)
                errs.append(err)
                worst.append((ft, args))
                if a.what == "shapes":
                    per_shape.setdefault(args.split()[1], []).append(ft)
            else:
                print(f"FAIL {args}: formation_tick {ft} shape_error {err} robot_contacts {rr}", flush=True)
    print(f"{ok}/{len(jobs)} passed", end="")
    if ticks:
        ticks.sort()
        print(f"; formation_tick median {ticks[len(ticks) // 2]} max {ticks[-1]}; "
              f"shape error max {max(errs):.3f}; robot-obstacle contacts {contacts_obstacle}")
        for ft, args in sorted(worst)[-3:]:
            print(f"  slowest: {ft} ({args})")
        for shape, ts in sorted(per_shape.items()):
            ts.sort()
            print(f"  {shape}: formed {len(ts)}, formation_tick median {ts[len(ts) // 2]} max {ts[-1]}")
    else:
        print()
    return 0 if ok == len(jobs) else 1


if __name__ == "__main__":
    sys.exit(main())
