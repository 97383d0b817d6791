#!/usr/bin/env python3
"""The motion engineer's sweep: runs swarm_inprocess over a grid and judges each run with judge_run.py.

  motion_sweep.py NAME -- ARGS...   one run per line of stdin: extra swarm_inprocess arguments
  e.g.  for s in 1 2 3; do echo "--scenario scenarios/paper.yaml --seed $s"; done | motion_sweep.py paper

Writes /tmp/motion_sweep/NAME/<n>/ and prints one judged line per run, then the count that arrived.
(scripts/swarm sweep is the project's tool; this one exists because it judges by issue 17's arrival rule
before the world does.)
"""
import os
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(__file__))
import judge_run  # noqa: E402

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "../../.."))
BIN = os.environ.get("SWARM_INPROCESS", os.path.join(ROOT, "build/world_server/harness/swarm_inprocess"))


def one(args):
    n, line = args
    out = f"/tmp/motion_sweep/{sys.argv[1]}/{n}"
    cmd = [BIN] + line.split() + ["--out", out, "--quiet"]
    subprocess.run(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, check=False)
    try:
        return line, judge_run.judge(out)
    except Exception as e:  # noqa: BLE001
        return line, {"error": str(e)}


def main():
    lines = [l.strip() for l in sys.stdin if l.strip()]
    jobs = int(os.environ.get("JOBS", "2"))
    ok = 0
    with ThreadPoolExecutor(jobs) as pool:
        for line, r in pool.map(one, enumerate(lines)):
            arrived = r.get("goal") is not None and (r.get("contacts_obs") or 0) == 0
            ok += arrived
            keys = ["motion_start", "goal", "motion_ticks", "minimum", "ratio", "peak", "err_at_goal",
                    "end_err", "end_dist", "contacts_obs", "contacts_rr"]
            print(("OK  " if arrived else "BAD ") + line + " | " + " ".join(f"{k}={r.get(k)}" for k in keys),
                  flush=True)
    print(f"{ok}/{len(lines)} arrived with 0 obstacle contacts")


if __name__ == "__main__":
    main()
