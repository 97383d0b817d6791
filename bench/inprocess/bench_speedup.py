#!/usr/bin/env python3
"""P3 (BENCHMARKS.md): CPU and wall time per robot-tick of two builds of bench_inprocess, alternated, and their ratios.

For each behaviour (random_walk, paper) and each N (100, 1000) on bench/inprocess/field.yaml, runs
`bench_inprocess --robots N --behaviour B --ticks T --warmup 10 --samples 1 --no-split` with --baseline and
with --binary in turn (base, new, base, new... over --rounds rounds) and takes two figures of each run:
- CPU: the process's CPU time (user + system, getrusage of the child) in microseconds per robot-tick of the
  whole process, start-up included (scenario, placement, world: ~0.01 s at N = 100, ~0.1 s at N = 1000, a few
  per cent of the defaults' runs; both builds pay it). What the run itself costs, whatever else the machine
  runs: the headline ratio.
- wall: 10^6 / the robot-ticks per second bench_inprocess prints for its timed ticks. How long a user waits
  (both cores used where the build splits the work); on a shared machine it also measures the queue for a core.
T defaults to 2000 at N <= 100 and 400 above (--ticks overrides both).

Prints per round on stderr and one JSON line on stdout:
  {"rounds":R, "load_average":[before, after], "cases":[{"behaviour":B, "robots":N, "ticks":T,
   "base_cpu_us":[...], "new_cpu_us":[...], "base_median":..., "new_median":..., "ratio":base/new,
   "base_wall_us":[...], "new_wall_us":[...], "wall_ratio":base/new}]}
A ratio is the median of the baseline's figures over the median of the new build's: > 1 means faster.
"""
import argparse
import json
import os
import resource
import statistics
import subprocess
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def die(message):
    print(f"bench_speedup: {message}", file=sys.stderr)
    sys.exit(2)


def us_per_robot_tick(binary, scenario, behaviour, robots, ticks, warmup):
    """One bench_inprocess run: (the child's user + system CPU microseconds per robot-tick, warmup included;
    the wall microseconds per robot-tick of its timed ticks, from its own robot-ticks/s)."""
    cmd = [binary, "--scenario", scenario, "--robots", str(robots), "--behaviour", behaviour, "--ticks",
           str(ticks), "--warmup", str(warmup), "--samples", "1", "--no-split"]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        die(f"{' '.join(cmd)} exited {proc.returncode}: {proc.stderr.strip()[-500:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    try:
        rate = json.loads(proc.stdout.strip().splitlines()[-1])["median"]
    except (IndexError, KeyError, ValueError):
        die(f"{' '.join(cmd)} printed no JSON line with a median: {proc.stdout.strip()[-300:]!r}")
    return cpu * 1e6 / (robots * (ticks + warmup)), 1e6 / rate


def main():
    default_binary = os.path.join(os.environ.get("BUILD_DIR", os.path.join(ROOT, "build")), "bench", "inprocess",
                                  "bench_inprocess")
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] + " Prints one JSON line (see the file's header).")
    ap.add_argument("--binary", default=default_binary, help="the new bench_inprocess (default: %(default)s)")
    ap.add_argument("--baseline", required=True, help="the other build's bench_inprocess (e.g. one of d2d9242)")
    ap.add_argument("--scenario", default=os.path.join(ROOT, "bench", "inprocess", "field.yaml"),
                    help="scenario both builds run (default: %(default)s)")
    ap.add_argument("--robots", default="100,1000", help="robot counts, comma-separated (default: %(default)s)")
    ap.add_argument("--behaviours", default="random_walk,paper", help="comma-separated (default: %(default)s)")
    ap.add_argument("--ticks", type=int, help="timed ticks of every run (default: 2000 at N <= 100, else 400)")
    ap.add_argument("--warmup", type=int, default=10, help="untimed ticks first (default: %(default)s)")
    ap.add_argument("--rounds", type=int, default=5, help="alternations of each case (default: %(default)s)")
    args = ap.parse_args()

    try:
        counts = [int(x) for x in args.robots.split(",") if x.strip()]
    except ValueError:
        die(f"--robots {args.robots!r}: not a comma-separated list of integers")
    behaviours = [b.strip() for b in args.behaviours.split(",") if b.strip()]
    if not counts or min(counts) < 1 or not behaviours:
        die("--robots needs counts >= 1 and --behaviours at least one name")
    if args.rounds < 1 or (args.ticks is not None and args.ticks < 1) or args.warmup < 0:
        die("--rounds and --ticks must be at least 1, --warmup at least 0")
    for b in (args.binary, args.baseline):
        if not os.access(b, os.X_OK):
            die(f"{b}: not an executable (build the bench_inprocess target)")
    if not os.path.isfile(args.scenario):
        die(f"--scenario {args.scenario}: no such file")

    load_before = list(os.getloadavg())
    cases = []
    for behaviour in behaviours:
        for robots in counts:
            ticks = args.ticks if args.ticks is not None else (2000 if robots <= 100 else 400)
            base, new, base_wall, new_wall = [], [], [], []
            for r in range(args.rounds):
                for binary, cpu, wall in ((args.baseline, base, base_wall), (args.binary, new, new_wall)):
                    c, w = us_per_robot_tick(binary, args.scenario, behaviour, robots, ticks, args.warmup)
                    cpu.append(c)
                    wall.append(w)
                print(f"bench_speedup: {behaviour} N={robots} round {r + 1}: base {base[-1]:.3f} new {new[-1]:.3f} "
                      f"us cpu per robot-tick (ratio {base[-1] / new[-1]:.2f}), wall {base_wall[-1]:.3f} / "
                      f"{new_wall[-1]:.3f} (ratio {base_wall[-1] / new_wall[-1]:.2f}), load "
                      f"{os.getloadavg()[0]:.1f}", file=sys.stderr, flush=True)
            case = {"behaviour": behaviour, "robots": robots, "ticks": ticks, "base_cpu_us": base, "new_cpu_us": new,
                    "base_median": statistics.median(base), "new_median": statistics.median(new),
                    "base_wall_us": base_wall, "new_wall_us": new_wall}
            case["ratio"] = case["base_median"] / case["new_median"]
            case["wall_ratio"] = statistics.median(base_wall) / statistics.median(new_wall)
            cases.append(case)
    print(json.dumps({"rounds": args.rounds, "warmup": args.warmup, "binary": args.binary, "baseline": args.baseline,
                      "load_average": [load_before, list(os.getloadavg())], "cases": cases}))
    for c in cases:
        print(f"bench_speedup: {c['behaviour']:>11} N={c['robots']:<5} base {c['base_median']:.3f} new "
              f"{c['new_median']:.3f} us cpu per robot-tick: base / new = {c['ratio']:.2f}; wall base / new = "
              f"{c['wall_ratio']:.2f}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
