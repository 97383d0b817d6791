#!/usr/bin/env python3
"""P4 (BENCHMARKS.md): the paper controller with a shape as large as the swarm, in-process.

Square blocks of 100, 400 and 1024 labels (scenarios/scale/block_*.txt) with as many robots, in the open
arena of scenarios/scale/open_arena.yaml, from the random start of its seed, for a fixed window of --ticks
ticks (3000) from tick 0: every robot holds a label (or is looking for one) the whole time. Each case runs
bench_inprocess once (--warmup 0 --samples 1 --no-split) and reports microseconds per robot-tick: wall time
of the timed ticks (bench_inprocess's own clock) and the process's CPU time (user + system, from
getrusage: steadier on a shared machine, since it does not count the time other processes hold the cores).

--baseline BINARY runs another build's bench_inprocess on the same inputs, alternating with this one (base,
new, base, new... over --rounds rounds) for the sizes in --baseline-sizes (a build from before the
incremental controller takes minutes for 100 labels and hours for 1024): the speed-up is base / new.
Each block's scenario is a copy of open_arena.yaml naming the block by absolute path, so any build that
reads that scenario format can run it.

Prints one JSON line on stdout:
  {"ticks":T, "load_average":[1, 5, 15 min before, after], "cases":[{"labels":L, "robots":L,
   "us_per_robot_tick":..., "cpu_us_per_robot_tick":..., ("baseline_us_per_robot_tick", ...,
   "speedup_wall", "speedup_cpu")}], "ratio_largest_to_smallest": {"wall":..., "cpu":...}}
(the figures are medians over the rounds). --quick: the 100- and 400-label blocks for 20 ticks, one round
(a smoke test of the machinery; its figures mean nothing).
"""
import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
SCALE = os.path.join(ROOT, "scenarios", "scale")
BLOCKS = {100: "block_10x10.txt", 144: "block_12x12.txt", 400: "block_20x20.txt", 1024: "block_32x32.txt"}


def die(message):
    print(f"bench_big_shapes: {message}", file=sys.stderr)
    sys.exit(2)


def block_scenario(labels, folder):
    """A copy of open_arena.yaml whose shape is the block of `labels` labels, by absolute path."""
    source = os.path.join(SCALE, "open_arena.yaml")
    with open(source, encoding="utf-8") as f:
        lines = f.read().splitlines()
    shape = os.path.join(SCALE, BLOCKS[labels])
    out, replaced = [], False
    for line in lines:
        if line.startswith("shape:"):
            line, replaced = f"shape: {shape}", True
        out.append(line)
    if not replaced:
        die(f"{source}: no 'shape:' line to replace")
    path = os.path.join(folder, f"block_{labels}.yaml")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")
    return path


def run_once(binary, scenario, robots, ticks, seed):
    """One bench_inprocess run: (wall us per robot-tick, cpu us per robot-tick)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    cmd = [binary, "--scenario", scenario, "--robots", str(robots), "--ticks", str(ticks), "--warmup", "0",
           "--samples", "1", "--no-split", "--seed", str(seed)]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode != 0:
        die(f"{' '.join(cmd)} exited {proc.returncode}: {proc.stderr.strip()[-500:]}")
    try:
        rate = json.loads(proc.stdout.strip().splitlines()[-1])["best"]
    except (ValueError, KeyError, IndexError) as e:
        die(f"{binary}: no JSON figure on stdout ({e}): {proc.stdout[-300:]!r}")
    robot_ticks = robots * ticks
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return 1e6 / rate, cpu * 1e6 / robot_ticks


def main():
    default_binary = os.path.join(os.environ.get("BUILD_DIR", os.path.join(ROOT, "build")), "bench", "inprocess",
                                  "bench_inprocess")
    ap = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0] + " Prints one JSON line (see the file's header).")
    ap.add_argument("--binary", default=default_binary, help="bench_inprocess to measure (default: %(default)s)")
    ap.add_argument("--baseline", help="another build's bench_inprocess, run alternately on the same inputs")
    ap.add_argument("--sizes", default="100,400,1024",
                    help="label counts, comma-separated, of: " + ", ".join(map(str, BLOCKS)) + " (default: %(default)s)")
    ap.add_argument("--baseline-sizes", default="100", help="the sizes the baseline runs (default: %(default)s)")
    ap.add_argument("--ticks", type=int, default=3000, help="ticks from the random start (default: %(default)s)")
    ap.add_argument("--rounds", type=int, default=1, help="runs of each case (default: %(default)s)")
    ap.add_argument("--seed", type=int, default=1, help="placement seed (default: %(default)s)")
    ap.add_argument("--quick", action="store_true", help="100 and 400 labels, 20 ticks, one round (smoke test)")
    args = ap.parse_args()

    def sizes_of(text, flag):
        try:
            sizes = [int(x) for x in text.split(",") if x.strip()]
        except ValueError:
            die(f"{flag} {text!r}: not a comma-separated list of integers")
        for s in sizes:
            if s not in BLOCKS:
                die(f"{flag}: no block of {s} labels (have {', '.join(map(str, BLOCKS))})")
        return sizes

    sizes = sizes_of(args.sizes, "--sizes")
    baseline_sizes = sizes_of(args.baseline_sizes, "--baseline-sizes") if args.baseline else []
    if args.quick:
        sizes, args.ticks, args.rounds = [100, 400], 20, 1
        baseline_sizes = [s for s in baseline_sizes if s in sizes]
    if args.ticks < 1 or args.rounds < 1:
        die("--ticks and --rounds must be at least 1")
    for b in [args.binary] + ([args.baseline] if args.baseline else []):
        if not os.access(b, os.X_OK):
            die(f"{b}: not an executable (build the bench_inprocess target)")

    load_before = list(os.getloadavg())
    cases = []
    with tempfile.TemporaryDirectory(prefix="bench-big-shapes-") as folder:
        for labels in sizes:
            scenario = block_scenario(labels, folder)
            new, base = [], []
            for r in range(args.rounds):
                if labels in baseline_sizes:
                    base.append(run_once(args.baseline, scenario, labels, args.ticks, args.seed))
                new.append(run_once(args.binary, scenario, labels, args.ticks, args.seed))
                print(f"bench_big_shapes: {labels} labels round {r + 1}: new {new[-1][0]:.2f} us wall "
                      f"{new[-1][1]:.2f} us cpu" + (f"; baseline {base[-1][0]:.2f} / {base[-1][1]:.2f}" if base else ""),
                      file=sys.stderr, flush=True)
            case = {"labels": labels, "robots": labels,
                    "us_per_robot_tick": statistics.median(w for w, _ in new),
                    "cpu_us_per_robot_tick": statistics.median(c for _, c in new)}
            if base:
                case["baseline_us_per_robot_tick"] = statistics.median(w for w, _ in base)
                case["baseline_cpu_us_per_robot_tick"] = statistics.median(c for _, c in base)
                case["speedup_wall"] = case["baseline_us_per_robot_tick"] / case["us_per_robot_tick"]
                case["speedup_cpu"] = case["baseline_cpu_us_per_robot_tick"] / case["cpu_us_per_robot_tick"]
            cases.append(case)
    out = {"ticks": args.ticks, "rounds": args.rounds, "seed": args.seed, "binary": args.binary,
           "baseline": args.baseline, "load_average": [load_before, list(os.getloadavg())], "cases": cases}
    if len(cases) > 1:
        out["ratio_largest_to_smallest"] = {
            "wall": cases[-1]["us_per_robot_tick"] / cases[0]["us_per_robot_tick"],
            "cpu": cases[-1]["cpu_us_per_robot_tick"] / cases[0]["cpu_us_per_robot_tick"]}
    print(json.dumps(out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
