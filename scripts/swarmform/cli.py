"""The command line of `scripts/swarm`: run, demo, kill, replay, report, sweep. Bad flags: a clear message, exit 2.

matplotlib is imported only by the commands that draw, so `--help`, `kill` and `report` answer at once.
"""

import argparse
import os
import sys

from . import faults, launcher

DEFAULT_SCENARIO = os.path.join("scenarios", "paper.yaml")

MAIN_HELP = """\
swarmform: a robot swarm emulator. Every robot is its own process (robot_agent) talking over DDS to one
world server (world_server) that steps the physics and delivers messages in range.

commands:
  run      start the world and N robot agent processes, show progress, write a run directory, draw the pictures
  demo     `run` with the paper's scenario; prints where the pictures are
  kill     SIGKILL one agent of the running swarm (the swarm carries on)
  replay   draw the pictures again from a run directory's recording
  report   print a run's summary.json as a readable table
  sweep    a grid of in-process runs (scenarios x shapes x seeds x kill schedules) on every core:
           sweep.csv, sweep.json (success rates, worst cases with the command that reproduces each)

A run directory (default runs/<UTC time>/, runs/latest points to the newest) holds the recording (world.json,
robots.csv, events.jsonl; docs/recording-format.md), summary.json, logs/ and pictures/.

examples:
  scripts/swarm demo
  scripts/swarm run --scenario scenarios/paper.yaml --kill 0@900 --kill 5@1200
  scripts/swarm run --fault stall:3@200+30 --fault kill:2@300 --fault restart:2@400 --fault loss:all@500+20
  scripts/swarm run --shape shapes/v.txt --robots 12 --seed 7 --mode realtime
  scripts/swarm kill 3                      # while a swarm runs (agents.json of runs/latest)
  scripts/swarm replay runs/latest --ticks 500 1000
  scripts/swarm report runs/latest
  scripts/swarm sweep --kills none random:2 --seeds 1-20

`scripts/swarm <command> --help` tells more. Exit codes: 0 ok, 1 failed, 2 bad input, 130 interrupted.
Environment: BUILD_DIR (default build/) holds the executables; SWARM_NO_BUILD=1 skips the build step;
SWARM_RUNS_DIR (default runs/) is where default run directories go.
"""


class Parser(argparse.ArgumentParser):
    def error(self, message):
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {message}\n(`{self.prog} --help` for help)\n")


def _int_at_least(lo):
    def parse(text):
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got '{text}'") from None
        if v < lo:
            raise argparse.ArgumentTypeError(f"must be >= {lo}, got {v}")
        return v
    return parse


def _domain(text):
    v = _int_at_least(0)(text)
    if v > 232:
        raise argparse.ArgumentTypeError(f"DDS domain ids go up to 232, got {v}")
    return v


def _kill_spec(text):
    rid, sep, tick = text.partition("@")
    if not sep or not rid.isdigit() or not tick.isdigit():
        raise argparse.ArgumentTypeError(f"expected ID@TICK (e.g. 3@500), got '{text}'")
    return f"{int(rid)}@{int(tick)}"


def _existing_file():
    def parse(text):
        if not os.path.isfile(text):
            raise argparse.ArgumentTypeError(f"no such file '{text}'")
        return text
    return parse


def _add_run_flags(p, demo=False):
    if not demo:
        p.add_argument("--scenario", type=_existing_file(), default=None, metavar="FILE",
                       help=f"scenario file (YAML; scenarios/README.md). Default: {DEFAULT_SCENARIO}")
    p.add_argument("--shape", metavar="FILE",  # the world resolves it (also against shapes/) and checks it
                   help="shape matrix file, instead of the scenario's (shapes/README.md); a bare name is "
                        "looked up in shapes/")
    p.add_argument("--robots", type=_int_at_least(1), metavar="N",
                   help="number of robots (default: the scenario's, or the shape's label count)")
    p.add_argument("--seed", type=_int_at_least(0), metavar="S", help="random seed (placement, noise)")
    p.add_argument("--mode", choices=("lockstep", "realtime"),
                   help="lockstep: the world waits for every live agent each tick (reproducible); "
                        "realtime: fixed tick rate, latest command")
    p.add_argument("--max-ticks", type=_int_at_least(1), metavar="T", help="stop after T ticks")
    p.add_argument("--plugin-dir", action="append", default=[], metavar="DIR",
                   help="a folder behaviour plug-ins may be loaded from, besides the scenario's own "
                        "(docs/behaviour-api.md); repeatable")
    p.add_argument("--out", metavar="DIR", help="run directory (default runs/<UTC time>/, and runs/latest)")
    p.add_argument("--kill", type=_kill_spec, action="append", default=[], metavar="ID@TICK",
                   help="SIGKILL agent ID at tick TICK (repeatable)")
    p.add_argument("--fault", action="append", default=[], metavar="FAULT", help=faults.FAULT_HELP)
    p.add_argument("--domain", type=_domain, metavar="D",
                   help="DDS domain id (default: a free one on this host, picked and said; SWARM_DOMAINS=LO-HI "
                        "bounds the pick, 0-99 by default)")
    p.add_argument("--no-pictures", action="store_true", help="do not draw the pictures at the end")
    p.add_argument("--ticks", type=_int_at_least(0), nargs="+", default=[], metavar="T",
                   help="also draw snapshots at these ticks")
    p.add_argument("--labels", action="store_true",
                   help="write each robot's id beside it and draw its heading on the snapshots")
    p.add_argument("--in-process", action="store_true",
                   help="run every robot's controller inside one process (swarm_inprocess; no DDS, "
                        "deterministic, fast); same run directory")


def make_parser():
    top = Parser(prog="swarm", description=MAIN_HELP, formatter_class=argparse.RawDescriptionHelpFormatter,
                 usage="swarm {run,demo,kill,replay,report,sweep} [options]   (swarm <command> --help)")
    sub = top.add_subparsers(dest="command", metavar="command", parser_class=Parser, prog="swarm")

    run = sub.add_parser("run", help="run a swarm", formatter_class=argparse.RawDescriptionHelpFormatter,
                         description="Starts the world_server, then N robot_agent processes, shows progress (tick, "
                                     "robots alive, ticks/s),\nSIGKILLs the --kill agents at their ticks, executes "
                                     "the --fault faults, writes the run directory\nand draws the pictures. Ctrl-C "
                                     "stops everything (the recording so far is kept) and exits 130.",
                         epilog=launcher.EXIT_CODES[0].upper() + launcher.EXIT_CODES[1:])
    _add_run_flags(run)

    demo = sub.add_parser("demo", help="run the paper's scenario",
                          description=f"`swarm run --scenario {DEFAULT_SCENARIO}`, then prints where the "
                                      "pictures are.")
    _add_run_flags(demo, demo=True)

    kill = sub.add_parser("kill", help="SIGKILL one agent of the running swarm",
                          description="SIGKILLs agent ID of the running swarm (its pid from the run "
                                      "directory's agents.json, checked to be that robot_agent).")
    kill.add_argument("id", type=_int_at_least(0), metavar="ID", help="robot id")
    kill.add_argument("--run", metavar="DIR", help="run directory of the swarm (default runs/latest)")

    replay = sub.add_parser("replay", help="draw the pictures again from a recording",
                            description="Draws RUN_DIR/pictures/ from the recording: snapshots (start, formation, "
                                        "motion start, through the motion, end, and --ticks), trajectories, "
                                        "residual force and shape error (a behaviour with a shape and a goal), "
                                        "states, telemetry (a behaviour with columns of its own), animation.mp4 "
                                        "and animation.gif.")
    replay.add_argument("run_dir", metavar="RUN_DIR")
    replay.add_argument("--ticks", type=_int_at_least(0), nargs="+", default=[], metavar="T",
                        help="also draw snapshots at these ticks")
    replay.add_argument("--out", metavar="DIR", help="write the pictures here instead of RUN_DIR/pictures")
    replay.add_argument("--no-animation", action="store_true", help="skip animation.mp4 and animation.gif")
    replay.add_argument("--labels", action="store_true",
                        help="write each robot's id beside it and draw its heading on the snapshots")

    report = sub.add_parser("report", help="print a run's summary as a table",
                            description="Prints RUN_DIR/summary.json as a readable table.")
    report.add_argument("run_dir", metavar="RUN_DIR")

    _add_sweep_parser(sub)
    return top


def _float_at_least(lo):
    def parse(text):
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got '{text}'") from None
        if not v >= lo or v == float("inf"):
            raise argparse.ArgumentTypeError(f"must be a finite number >= {lo:g}, got {text}")
        return v
    return parse


def _checked(fn):
    def parse(text):
        try:
            return fn(text)
        except ValueError as e:
            raise argparse.ArgumentTypeError(str(e)) from None
    return parse


def _add_sweep_parser(sub):
    from . import sweep  # no matplotlib
    p = sub.add_parser("sweep", help="a grid of in-process runs, judged; sweep.csv and sweep.json",
                       formatter_class=argparse.RawDescriptionHelpFormatter, description=sweep.HELP,
                       epilog=sweep.EXAMPLES)
    g = p.add_argument_group("the grid (each flag takes several values, and may be repeated)")
    g.add_argument("--scenario", nargs="+", action="extend", metavar="FILE",
                   help=f"scenario files or globs (default {DEFAULT_SCENARIO})")
    g.add_argument("--shape", nargs="+", action="extend", metavar="FILE",
                   help="shape files or globs, instead of each scenario's own (a bare name is looked up in "
                        "shapes/)")
    g.add_argument("--shapes-dir", metavar="DIR", help="add every DIR/*.txt to the shapes")
    g.add_argument("--robots", nargs="+", action="extend", type=_int_at_least(1), metavar="N",
                   help="robot counts (default: the scenario's, or the shape's label count)")
    g.add_argument("--seeds", nargs="+", action="extend", type=_checked(sweep.parse_seeds), metavar="SEEDS",
                   help="seeds: 7, 1-20, 1-5,9 (default 1-10)")
    g.add_argument("--kills", nargs="+", action="extend", type=_checked(sweep.parse_kill_schedule),
                   metavar="SCHEDULE", help="kill schedules: none, ID@TICK[,ID@TICK...], random:K (default none)")
    g.add_argument("--max-ticks", type=_int_at_least(1), metavar="T",
                   help="cut every run at tick T (default: each scenario's max_ticks)")
    g.add_argument("--kill-window", type=_int_at_least(1), default=sweep.DEFAULT_KILL_WINDOW, metavar="T",
                   help="random:K kills fall at ticks 1..min(T, max_ticks) (default %(default)s)")
    j = p.add_argument_group("judging")
    j.add_argument("--expect", choices=sweep.EXPECT, default="arrived",
                   help="the outcome a run must end with (default %(default)s; formed: arrived or "
                        "formed_not_arrived; any: a clean exit)")
    j.add_argument("--max-shape-error", type=_float_at_least(0), metavar="E",
                   help="fail a run whose shape error (at the goal for --expect arrived, at formation "
                        "otherwise) is above E grid units")
    j.add_argument("--max-contacts", type=_int_at_least(0), metavar="C",
                   help="fail a run with more than C contacts (robot-robot + robot-obstacle)")
    j.add_argument("--max-robot-contacts", type=_int_at_least(0), metavar="C",
                   help="fail a run with more than C robot-robot contacts")
    r = p.add_argument_group("running")
    r.add_argument("--jobs", "-j", type=_int_at_least(1), metavar="J",
                   help=f"runs at a time (default: the cores, {os.cpu_count()})")
    r.add_argument("--timeout", type=_float_at_least(0), default=sweep.DEFAULT_TIMEOUT_S, metavar="S",
                   help="SIGKILL a run after S wall seconds and count it failed (default %(default)g; 0: never)")
    r.add_argument("--out", metavar="DIR", help="output folder (default runs/sweep-<UTC time>/)")
    r.add_argument("--worst", type=_int_at_least(0), default=20, metavar="K",
                   help="worst runs listed in sweep.json (default %(default)s)")
    r.add_argument("--quiet", action="store_true", help="no progress line")


def render_pictures(run_dir, ticks=(), out_dir=None, animate=True, labels=False):
    """Loads the recording and draws every picture; 0, or 1 with a file:line message."""
    from . import animation, pictures, recording  # matplotlib: only when drawing
    try:
        rec = recording.load(run_dir)
        for w in rec.warnings:
            print(f"swarm: warning: {w}", file=sys.stderr)
        written = pictures.render_all(rec, out_dir, ticks, animate, log=lambda m: print(m, file=sys.stderr),
                                      labels=labels)
    except recording.RecordingError as e:
        print(f"swarm: {e}", file=sys.stderr)
        return 1
    except (pictures.PictureError, animation.AnimationError) as e:
        print(f"swarm: {e}", file=sys.stderr)
        return 2 if isinstance(e, pictures.PictureError) else 1
    folder = os.path.dirname(written[0]) if written else out_dir
    print(f"pictures: {len(written)} files in {folder}/")
    return 0


def main(argv=None):
    parser = make_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    if args.command in ("run", "demo"):
        if args.command == "demo" or args.scenario is None:
            args.scenario = DEFAULT_SCENARIO
            if not os.path.isfile(args.scenario):
                args.scenario = os.path.join(launcher.ROOT, DEFAULT_SCENARIO)
            if not os.path.isfile(args.scenario):
                parser.error(f"the default scenario {DEFAULT_SCENARIO} is missing")
        if os.environ.get("SWARM_PARSE_ONLY") == "1":  # scripts/swarm checks the flags before it builds
            return 0
        code = launcher.run(args, lambda run_dir: render_pictures(run_dir, args.ticks, labels=args.labels))
        if args.command == "demo" and code == 0:
            where = os.path.relpath(args.run_dir)
            where = args.run_dir if where.startswith("..") else where
            print(f"demo done. Pictures: {where}/pictures/ (snapshot_t*.png, trajectories.png, residual_force.png,"
                  f" shape_error.png, animation.mp4, animation.gif)")
            print(f"The numbers: scripts/swarm report {where}")
        return code
    if args.command == "kill":
        run_dir = args.run or os.path.join(os.environ.get("SWARM_RUNS_DIR") or
                                           os.path.join(launcher.ROOT, "runs"), "latest")
        try:
            pid = launcher.kill(args.id, run_dir)
        except launcher.LaunchError as e:
            print(f"swarm kill: {e}", file=sys.stderr)
            return e.code
        print(f"killed agent {args.id} (pid {pid})")
        return 0
    if args.command == "replay":
        return render_pictures(args.run_dir, args.ticks, args.out, not args.no_animation, args.labels)
    if args.command == "sweep":
        if os.environ.get("SWARM_PARSE_ONLY") == "1":
            return 0
        from . import sweep
        args.seeds = [s for chunk in (args.seeds or []) for s in chunk] or None
        return sweep.sweep(args)
    if args.command == "report":
        from . import report, recording
        try:
            report.report(args.run_dir)
        except recording.RecordingError as e:
            print(f"swarm report: {e}", file=sys.stderr)
            return 1
        return 0
    parser.error(f"unknown command {args.command}")
    return 2
