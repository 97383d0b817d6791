"""The command line of `scripts/swarm`: run, demo, kill, replay, report, sweep, plot. Bad flags: a clear message, exit 2.

matplotlib is imported only by the commands that draw, so `--help`, `kill` and `report` answer at once.
"""

import argparse
import math
import os
import re
import sys
import time
from typing import IO, Any, Callable, NoReturn, Optional, Sequence

from . import exit_codes, expect, faults, hosts, launcher, places, security

DEFAULT_SCENARIO = os.path.join("scenarios", "paper.yaml")

MAIN_HELP = """\
swarmform: a robot swarm emulator. Every robot is its own process (robot_agent) talking over DDS to one
world server (world_server) that steps the physics and delivers messages in range.

commands:
  run      start the world and N robot agent processes, show progress, write a run directory, draw the pictures
  demo     `run` with the paper's scenario; prints where the pictures are
  kill     SIGKILL one agent of the running swarm (the swarm carries on)
  replay   draw the pictures again from a run directory's recording
  view     the browser view of a recording (timeline, play, jump to events); `run --view` shows a live run
  export   a recording as an MCAP file Foxglove opens (--mcap FILE), the live Foxglove server's channels
  report   print a run's summary.json as a readable table (or --json, --csv)
  sweep    a grid of in-process runs (scenarios x shapes x seeds x kill schedules x --param values x loss, bursts,
           noise and --set scenario fields) on every core:
           sweep.csv, sweep.json (success rates, worst cases with the command that reproduces each)
  plot     a sweep's figures: success over two grid axes, a metric's median and 95 % CI, failures by reason

A run directory (default runs/<UTC time>/, runs/latest points to the newest) holds the recording (world.json,
robots.csv, readings.csv when the behaviour declares sensors, events.jsonl; docs/recording-format.md),
summary.json, logs/ and pictures/.

examples:
  scripts/swarm demo
  scripts/swarm run --scenario scenarios/paper.yaml --kill 0@900 --kill 5@1200
  scripts/swarm run --fault stall:3@200+30 --fault kill:2@300 --fault restart:2@400 --fault loss:all@500+20
  scripts/swarm run --shape shapes/v.txt --robots 12 --seed 7 --mode realtime
  scripts/swarm run --hosts 3 --link "loss 5% rate 20mbit"   # as root: 3 agent hosts (network namespaces)
  scripts/swarm kill 3                      # while a swarm runs (agents.json of runs/latest)
  scripts/swarm replay runs/latest --ticks 500 1000
  scripts/swarm run --view                  # watch it live at http://127.0.0.1:8765/ (pause, step, click a robot)
  scripts/swarm run --view-paused           # ... starting paused at tick 0 until the page says go
  scripts/swarm view runs/latest            # the same page over the recording
  scripts/swarm report runs/latest
  scripts/swarm report runs/a runs/b --csv > runs.csv
  scripts/swarm run --no-pictures --expect 'outcome == arrived' --expect 'collisions_robot_robot == 0'
  scripts/swarm sweep --kills none random:2 --seeds 1-20 --plot
  scripts/swarm plot runs/sweep-20261206-120000 --metric shape_error_at_goal

`scripts/swarm <command> --help` tells more. Exit codes: {codes} (`swarm run --help` lists its own).
Environment: BUILD_DIR (default build/) holds the executables; SWARM_NO_BUILD=1 skips the build step;
SWARM_RUNS_DIR (default runs/) is where default run directories go.
"""
MAIN_HELP = MAIN_HELP.replace("{codes}", f"{exit_codes.OK} ok, {exit_codes.FAILED} failed, {exit_codes.BAD_INPUT} bad "
                                         f"input, {exit_codes.INTERRUPTED} interrupted")


class Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {message}\n(`{self.prog} --help` for help)\n")


def _int_at_least(lo: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            v = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got '{text}'") from None
        if v < lo:
            raise argparse.ArgumentTypeError(f"must be >= {lo}, got {v}")
        return v
    return parse


def _domain(text: str) -> int:
    v = _int_at_least(0)(text)
    if v > 232:
        raise argparse.ArgumentTypeError(f"DDS domain ids go up to 232, got {v}")
    return v


def _hosts_count(text: str) -> int:
    v = _int_at_least(1)(text)
    if v > hosts.MAX_HOSTS:
        raise argparse.ArgumentTypeError(f"at most {hosts.MAX_HOSTS} agent hosts, got {v}")
    return v


def _link_spec(text: str) -> hosts.Link:
    try:
        return hosts.parse_link(text)
    except hosts.HostsError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


DEFAULT_VIEW_PORT = 8765


def _port(text: str) -> int:
    v = _int_at_least(0)(text)
    if v > 65535:
        raise argparse.ArgumentTypeError(f"a TCP port is 0..65535, got {v}")
    return v


def _kill_spec(text: str) -> str:
    rid, sep, tick = text.partition("@")
    if not sep or not rid.isdigit() or not tick.isdigit():
        raise argparse.ArgumentTypeError(f"expected ID@TICK (e.g. 3@500), got '{text}'")
    return f"{int(rid)}@{int(tick)}"


def _param(text: str) -> str:
    """`NAME=VALUE` (one value; `swarm sweep --param` takes several), or `GROUP.NAME=VALUE` for a robot group's
    (docs/scenario-format.md "Groups"): the syntax here, the group, the name and the bounds by the behaviour's own
    table when the world loads the scenario (before anything starts)."""
    name, sep, value = text.partition("=")
    try:
        number = float(value)
    except ValueError:
        number = math.nan
    if not sep or not re.fullmatch(r"(?:[a-z][a-z0-9_]*\.)?[A-Za-z_][A-Za-z0-9_]*", name.strip()) \
            or not math.isfinite(number):
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE with VALUE a finite number (e.g. radius=1.5), "
                                         f"got '{text}'")
    return f"{name.strip()}={value.strip()}"


def _expectation(text: str) -> expect.Expectation:
    try:
        return expect.parse(text)
    except expect.ExpectationError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _existing_file() -> Callable[[str], str]:
    def parse(text: str) -> str:
        if not os.path.isfile(text):
            raise argparse.ArgumentTypeError(f"no such file '{text}'")
        return text
    return parse


def _add_run_flags(p: argparse.ArgumentParser, demo: bool = False) -> None:
    if not demo:
        p.add_argument("--scenario", type=_existing_file(), default=None, metavar="FILE",
                       help=f"scenario file (YAML; docs/scenario-format.md). Default: {DEFAULT_SCENARIO}")
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
    p.add_argument("--param", type=_param, action="append", default=[], metavar="NAME=VALUE",
                   help="set the behaviour's parameter NAME (a scenario `behaviour: {params:}` / `controller:` "
                        "key) over the scenario's value; repeatable. Checked against the behaviour's parameter "
                        "table before anything starts: an unknown NAME or a value out of bounds is refused "
                        "naming it (exit 2). summary.json's params holds the values the run had")
    p.add_argument("--out", metavar="DIR", help="run directory (default runs/<UTC time>/, and runs/latest)")
    p.add_argument("--record-every", type=_int_at_least(1), metavar="K",
                   help="robots.csv gets the rows of every K-th tick only (ticks 0, K, 2K...; default 1): a "
                        "long run of many robots thinned; events, metrics and trajectory_sha256 still cover "
                        "every tick (docs/recording-format.md)")
    p.add_argument("--kill", type=_kill_spec, action="append", default=[], metavar="ID@TICK",
                   help="SIGKILL agent ID at tick TICK (repeatable)")
    p.add_argument("--fault", action="append", default=[], metavar="FAULT", help=faults.FAULT_HELP)
    p.add_argument("--domain", type=_domain, metavar="D",
                   help="DDS domain id (default: a free one on this host, picked and said; SWARM_DOMAINS=LO-HI "
                        "bounds the pick, 0-99 by default)")
    p.add_argument("--connect-timeout", type=_float_at_least(0.1), metavar="S",
                   help="seconds every agent has to connect (claim its id) once the world is up; then the run "
                        "ends with exit 3 and a line naming the missing ids and what became of their agents "
                        "(default 30 + 0.025 x robots: 30.4 s for 16, 55.6 s for 1024)")
    p.add_argument("--no-pictures", action="store_true", help="do not draw the pictures at the end")
    p.add_argument("--no-animation", action="store_true",
                   help="draw the pictures but not animation.mp4 / animation.gif (the slow part)")
    p.add_argument("--view", nargs="?", type=_port, const=DEFAULT_VIEW_PORT, default=None, metavar="PORT",
                   help=f"watch the run in a browser: a viewer process serves the page at http://HOST:PORT/ "
                        f"(default port {DEFAULT_VIEW_PORT}; viewer/README.md). Pause, step, speed cap and kill "
                        "from the page in lockstep; the run never waits for the viewer or dies with it")
    p.add_argument("--view-host", default="127.0.0.1", metavar="ADDR",
                   help="the address the viewer listens on (default 127.0.0.1: this machine only; 0.0.0.0: "
                        "every interface, and anyone who reaches it can pause and kill)")
    p.add_argument("--view-paused", action="store_true",
                   help="--view, and the run (lockstep) waits at tick 0 until the page says go (resume or step)")
    p.add_argument("--view-control-origin", action="append", default=[], metavar="ORIGIN",
                   help="--view: a Foxglove client from this browser origin (e.g. https://app.foxglove.dev) may "
                        "pause, step and kill over /control too (repeatable; viewer/README.md \"Foxglove\")")
    p.add_argument("--view-grace", type=_float_at_least(0.0), default=None, metavar="S",
                   help="--view: seconds a paused run waits once its last page closed, then it resumes and says "
                        "so (default 10)")
    p.add_argument("--ticks", type=_int_at_least(0), nargs="+", default=[], metavar="T",
                   help="also draw snapshots at these ticks")
    p.add_argument("--hosts", type=_hosts_count, metavar="K",
                   help="emulate K agent hosts and the world's as network namespaces joined by a bridge (root "
                        "only): the world in its own, agent i on host i mod K, over real UDP (docs/multi-host.md)")
    p.add_argument("--link", type=_link_spec, metavar="SPEC", help=hosts.LINK_HELP)
    p.add_argument("--secure", action="store_true",
                   help="DDS Security: a certificate authority, a certificate per robot, the world and an observer, "
                        "signed governance and permissions, made fresh in RUN_DIR/security (keys 0600); traffic "
                        "is encrypted, only this run's identities take part, robot K reads only its own packets "
                        "and only robot K's identity may claim id K (docs/security.md)")
    p.add_argument("--open-rejoin", action="store_true",
                   help="let an agent started by hand take a dead robot's id (the world's --open-rejoin). Without "
                        "it only the agents this launcher starts (restarted ones too) can: each gets its id's token "
                        "from the run's secret, which only the world shares, and proves its claims with it "
                        "(docs/wire.md, Claim proofs)")
    p.add_argument("--exec", metavar="CMD",
                   help="run each robot's behaviour as the program CMD (one child process per robot_agent, any "
                        "language) speaking the JSON line protocol of docs/agent-protocol.md on stdin/stdout; "
                        "the agent keeps the DDS side. CMD is one argument, run by /bin/sh (quote it), e.g. "
                        "--exec 'python3 examples/agents/aggregation.py'. A child that exits, hangs or writes "
                        "garbage makes its robot dead, saying why. Not with --in-process")
    p.add_argument("--exec-timeout", type=_float_at_least(0.001), metavar="S",
                   help="seconds the --exec program may take to answer each perception (default 5)")
    p.add_argument("--expect", type=_expectation, action="append", default=[], metavar="'KEY OP VALUE'",
                   help="after the run, check summary.json: KEY a summary key, dotted for a nested one "
                        "(states_at_end.NAME, params.NAME, telemetry_mean_at_end.NAME), OP one of == != <= >= < >, "
                        "e.g. --expect 'outcome == arrived' --expect 'collisions_robot_robot == 0' --expect "
                        "'deaths <= 2' (a list compares by its length); repeatable. Every KEY is checked before "
                        "the run against what the behaviour declares (exit 2 for an unknown one, nothing run); "
                        "after it each is printed met or FAILED; exit 4 when one failed "
                        "(docs/testing-your-swarm.md)")
    p.add_argument("--labels", action="store_true",
                   help="write each robot's id beside it and draw its heading on the snapshots")
    p.add_argument("--in-process", action="store_true",
                   help="run every robot's controller inside one process (swarm_inprocess; no DDS, "
                        "deterministic, fast); same run directory")
    p.add_argument("--check", action="store_true",
                   help="check the scenario, the shape and every flag (--expect keys included) as a run would, "
                        "print what would run, and exit (0: it would start; 2: what is wrong, where) without "
                        "starting anything or making a run directory")


def make_parser() -> Parser:
    top = Parser(prog="swarm", description=MAIN_HELP, formatter_class=argparse.RawDescriptionHelpFormatter,
                 usage="swarm {run,demo,kill,replay,view,export,report,sweep,plot} [options]   (swarm <command> --help)")
    sub = top.add_subparsers(dest="command", metavar="command", parser_class=Parser, prog="swarm")

    run = sub.add_parser("run", help="run a swarm", formatter_class=argparse.RawDescriptionHelpFormatter,
                         description="Starts the world_server, then N robot_agent processes, shows progress (tick, "
                                     "robots alive, ticks/s),\nSIGKILLs the --kill agents at their ticks, executes "
                                     "the --fault faults, writes the run directory\nand draws the pictures. Ctrl-C "
                                     "stops everything (the recording so far is kept) and exits 130.",
                         epilog=exit_codes.help_text("swarm_run"))
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

    view = sub.add_parser("view", help="the browser view of a recording",
                          description="Serves the live view's page over RUN_DIR's recording (world.json, robots.csv, "
                                      "events.jsonl, summary.json) at http://HOST:PORT/: a timeline to scrub, "
                                      "play/pause, speed, jump to events (deaths, formation, leader changes), "
                                      "click a robot. Ctrl-C ends it.")
    view.add_argument("run_dir", metavar="RUN_DIR")
    view.add_argument("--port", type=_port, default=DEFAULT_VIEW_PORT,
                      help=f"TCP port (default {DEFAULT_VIEW_PORT}; 0: any free one, printed)")
    view.add_argument("--host", default="127.0.0.1", metavar="ADDR",
                      help="address to listen on (default 127.0.0.1: this machine only)")
    view.add_argument("--control-origin", action="append", default=[], metavar="ORIGIN",
                      help="a Foxglove client from this browser origin (e.g. https://app.foxglove.dev) may play, "
                           "pause and seek over /control too (repeatable)")

    export = sub.add_parser("export", help="a recording as an MCAP file that Foxglove opens",
                            description="Writes RUN_DIR's recording as FILE, an MCAP file (@mcap/core, npm; "
                                        "scripts/setup installs it) with the live Foxglove server's channels and "
                                        "schemas: /scene, /robots/poses, /tf, /robots/telemetry, /metrics "
                                        "(viewer/README.md \"Foxglove\"). Log times: the run's start "
                                        "(world.json's time) plus tick / tick_rate. Damage in robots.csv is said "
                                        "as `swarm report` says it; the readable ticks are exported. Progress on "
                                        "stderr every 2 s.")
    export.add_argument("run_dir", metavar="RUN_DIR")
    export.add_argument("--mcap", required=True, metavar="FILE", help="the MCAP file to write (replaced whole)")

    report = sub.add_parser("report", help="print a run's summary as a table, JSON or CSV",
                            description="Prints RUN_DIR/summary.json as a readable table; --json and --csv give it "
                                        "to programs. Several RUN_DIRs: one table each, a JSON list, or one CSV "
                                        "row each.")
    report.add_argument("run_dir", metavar="RUN_DIR", nargs="+")
    fmt = report.add_mutually_exclusive_group()
    fmt.add_argument("--json", action="store_true",
                     help="summary.json itself, every key (docs/recording-format.md), with run_dir added")
    fmt.add_argument("--csv", action="store_true",
                     help="a header and one row per RUN_DIR: run_dir, then every scalar key of the summaries (lists "
                          "of ids or {id, tick} as '3 7' / '3@120 7@900', as sweep.csv; per-tick series left out)")

    _add_sweep_parser(sub)
    plot = sub.add_parser("plot", help="a sweep's figures (PNG and SVG)",
                          description="Draws SWEEP_DIR's figures into SWEEP_DIR/figures/ (docs/sweeps.md "
                                      "\"Figures\"): success.png/.svg (the success rate over the grid's two axes with "
                                      "the most values, a heat map), metric.png/.svg (a metric's median and 95 % "
                                      "confidence interval over the runs at each value of the grid's first numeric "
                                      "axis, a line per shape), failures.png/.svg (failed runs by reason). Titled "
                                      "with the grid and the commit.")
    plot.add_argument("sweep_dir", metavar="SWEEP_DIR")
    plot.add_argument("--metric", metavar="KEY",
                      help="a sweep.csv column (default: goal_tick when runs arrived, else the behaviour's first "
                           "metric, else ticks)")
    plot.add_argument("--out", metavar="DIR", help="write the figures here instead of SWEEP_DIR/figures")
    return top


def _float_at_least(lo: float) -> Callable[[str], float]:
    def parse(text: str) -> float:
        try:
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, got '{text}'") from None
        if not v >= lo or v == float("inf"):
            raise argparse.ArgumentTypeError(f"must be a finite number >= {lo:g}, got {text}")
        return v
    return parse


def _checked(fn: Callable[[str], Any]) -> Callable[[str], Any]:
    def parse(text: str) -> Any:
        try:
            return fn(text)
        except ValueError as e:
            raise argparse.ArgumentTypeError(str(e)) from None
    return parse


def _add_sweep_parser(sub: Any) -> None:
    from . import sweep, sweep_fields, sweep_journal  # no matplotlib
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
    g.add_argument("--param", action="append", type=_checked(sweep.parse_param), metavar="NAME=V1,V2,...",
                   help="a behaviour parameter (a scenario `controller:` key) and its values: one axis of the grid; "
                        "repeatable (one flag per NAME). Checked against the behaviour's parameter table before "
                        "any run: an unknown NAME or a value out of bounds is refused naming it. sweep.csv gets a "
                        "param_NAME column, sweep.json the grid's values, each run's and by_params rates")
    g.add_argument("--max-ticks", type=_int_at_least(1), metavar="T",
                   help="cut every run at tick T (default: each scenario's max_ticks)")
    f = p.add_argument_group("scenario fields (each flag one axis of the grid; each value given to every run as "
                             "swarm_inprocess --set KEY=VALUE, checked by the loader before any run)")
    f.add_argument("--loss", action="append", type=_checked(sweep_fields.parse_loss), metavar="R1,R2,...",
                   help="packet_loss rates in [0, 1), e.g. 0,0.1,0.2,0.3 (sweep.csv column loss)")
    f.add_argument("--burst", action="append", type=_checked(sweep_fields.parse_burst), metavar="B1,B2,...",
                   help="mean loss bursts in ticks, with --loss: 1 is independent loss, B > 1 a Gilbert-Elliott "
                        "chain per directed link (packet_loss: {rate, mean_burst: B}; B >= 1/(1 - rate)), e.g. 1,5 "
                        "(column burst)")
    f.add_argument("--noise", action="append", type=_checked(sweep_fields.parse_noise), metavar="off,on",
                   help="off: no noise; on: range 0.05 m, bearing 0.05 rad, ultrasonic 0.02 m (Gaussian sds) "
                        "(column noise)")
    f.add_argument("--set", action="append", type=_checked(sweep_fields.parse_set), metavar="KEY=V1,V2,...",
                   help="any scenario field (dotted for a nested one: noise.range) and its values as YAML (a value "
                        "with commas in brackets or braces); repeatable, one flag per KEY (column set_KEY)")
    g.add_argument("--plugin-dir", action="append", default=[], metavar="DIR",
                   help="a folder behaviour plug-ins may be loaded from, besides each scenario's own "
                        "(docs/behaviour-api.md); passed to every run; repeatable")
    g.add_argument("--kill-window", type=_int_at_least(1), default=sweep.DEFAULT_KILL_WINDOW, metavar="T",
                   help="random:K kills fall at ticks 1..min(T, max_ticks) (default %(default)s)")
    j = p.add_argument_group("judging")
    j.add_argument("--expect", action="append", type=_checked(sweep.parse_expect), metavar="WORD|'KEY OP VALUE'",
                   help="how a run succeeds; repeatable. An outcome word: success (the default: the behaviour's "
                        "own outcome; one with no judge of its own, outcome none, by a clean exit), arrived, "
                        "formed (arrived or formed_not_arrived), not_formed, none, any (a clean exit). Or "
                        "'KEY OP VALUE' as `swarm run --expect` (KEY dotted for a nested one: "
                        "'states_at_end.gathered >= 6'), each checked before any run against the keys the "
                        "behaviour declares; given alone, they judge a clean run")
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
    r.add_argument("--exec", metavar="CMD",
                   help="run every run as `swarm run --exec CMD`: real processes, each robot's behaviour the program "
                        "CMD over the line protocol (docs/agent-protocol.md), for a behaviour only such a program "
                        "drives (a descriptor file's); each run in a free DDS domain of its own. Not with the "
                        "scenario-field axes or --cluster (give each radio as a scenario file)")
    r.add_argument("--exec-timeout", type=_float_at_least(0), metavar="S",
                   help="with --exec: as `swarm run --exec-timeout`")
    r.add_argument("--cluster", metavar="tcp://HOST:PORT",
                   help="run the runs on a Dask distributed scheduler's workers (each in a checkout of this commit, "
                        "built; docs/sweeps.md \"On a cluster\") instead of this machine's cores; the same results")
    r.add_argument("--plot", action="store_true",
                   help="draw the sweep's figures at the end (as `swarm plot OUT_DIR`: docs/sweeps.md \"Figures\")")
    r.add_argument("--plot-metric", metavar="KEY", help="with --plot: the metric figure's column (swarm plot --metric)")
    m = p.add_argument_group("slices, resuming and merging (sweep_args.json and runs.jsonl in the output folder)")
    m.add_argument("--shard", type=_checked(sweep_journal.parse_shard), metavar="K/N",
                   help="run only the K-th of N slices of the grid (every N-th run from the K-th): for a batch "
                        "system's job array; join the N folders with --merge")
    m.add_argument("--resume", metavar="DIR",
                   help="go on with the sweep in DIR (stopped by Ctrl-C, a crash or a lost machine): its grid "
                        "from DIR/sweep_args.json, the runs DIR/runs.jsonl lacks; no grid flag with it")
    m.add_argument("--merge", nargs="+", metavar="DIR",
                   help="join the N folders of one sweep's --shard K/N slices into one sweep (into --out), the "
                        "same sweep.csv and sweep.json as the unsliced sweep; runs nothing but the probes")


class _DrawingProgress:
    """What is being drawn, on one line rewritten in place on a terminal; a plain line every 5 s otherwise."""

    def __init__(self, stream: IO[str] = sys.stderr) -> None:
        self.stream, self.tty, self.last, self.dirty = stream, stream.isatty(), 0.0, False
        self.start = time.monotonic()

    def __call__(self, text: str) -> None:
        line = f"pictures: {text} ({time.monotonic() - self.start:.0f} s)"
        if self.tty:
            self.stream.write("\r\033[K" + line)
            self.dirty = True
        elif time.monotonic() - self.last >= 5.0:
            self.stream.write(line + "\n")
            self.last = time.monotonic()
        self.stream.flush()

    def end(self) -> None:
        if self.dirty:
            self.stream.write("\r\033[K")
            self.stream.flush()
            self.dirty = False


def render_pictures(run_dir: str, ticks: Sequence[int] = (), out_dir: Optional[str] = None, animate: bool = True,
                    labels: bool = False) -> int:
    """Loads the recording and draws every picture; 0, or 1 with a file:line message."""
    from . import animation, pictures, recording  # matplotlib: only when drawing
    progress = _DrawingProgress()
    print("swarm: drawing the pictures" + ("" if animate else " (no animation)") +
          ("; --no-animation skips the video, --no-pictures all of it" if animate else ""), file=sys.stderr)
    try:
        progress("loading the recording")
        # robots.csv's damage first, in `swarm view`'s and `swarm report`'s words (a corrupt row below stops the
        # drawing at its line; the damage says every place and the ticks it touches).
        from . import report as run_report
        for line in run_report.damage_lines(run_dir):
            print(f"swarm: warning: {line}", file=sys.stderr)
        rec = recording.load(run_dir)
        for w in rec.warnings:
            print(f"swarm: warning: {w}", file=sys.stderr)
        try:
            written = pictures.render_all(rec, out_dir, ticks, animate, log=lambda m: print(m, file=sys.stderr),
                                          progress=progress, labels=labels)
        finally:
            progress.end()
    except recording.RecordingError as e:
        print(f"swarm: {e}", file=sys.stderr)
        return exit_codes.FAILED
    except (pictures.PictureError, animation.AnimationError) as e:
        print(f"swarm: {e}", file=sys.stderr)
        return exit_codes.BAD_INPUT if isinstance(e, pictures.PictureError) else exit_codes.FAILED
    folder = os.path.dirname(written[0]) if written else out_dir
    print(f"pictures: {len(written)} files in {folder}/")
    return exit_codes.OK


def _plot(sweep_dir: str, metric: Optional[str], out: Optional[str]) -> int:
    from . import sweep_plots
    try:
        written = sweep_plots.plot(sweep_dir, metric, out)
    except sweep_plots.PlotError as e:
        print(f"swarm plot: {e}", file=sys.stderr)
        return exit_codes.BAD_INPUT
    print(f"figures: {len(written)} files in {os.path.dirname(written[0])}/")
    return exit_codes.OK


def parse_sweep_args(argv: Sequence[str]) -> argparse.Namespace:
    """`swarm sweep ARGV`'s options as main() gives them to sweep.sweep (a sweep's saved command line, read back
    by --resume and --merge). Exits 2 on a bad flag, as the parser does."""
    args = make_parser().parse_args(["sweep", *argv])
    args.seeds = [s for chunk in (args.seeds or []) for s in chunk] or None
    args.argv = list(argv)
    return args


def main(argv: Optional[Sequence[str]] = None) -> int:
    parser = make_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return exit_codes.BAD_INPUT
    if args.command in ("run", "demo"):
        if args.link and not args.hosts:
            parser.error("--link shapes the links of emulated hosts: it needs --hosts K")
        if args.hosts and args.in_process:
            parser.error("--hosts and --in-process exclude each other (an in-process run has no network)")
        if args.command == "demo" or args.scenario is None:
            args.scenario = places.default_scenario()
            if not os.path.isfile(args.scenario):
                parser.error(f"the default scenario {args.scenario} is missing")
        if args.secure and args.in_process:
            parser.error("--secure secures DDS and --in-process runs without it: choose one")
        if args.secure and args.domain is not None and args.domain > security.MAX_SECURE_DOMAIN:
            parser.error(f"--secure: DDS domain {args.domain} is above {security.MAX_SECURE_DOMAIN}, the highest "
                         "Cyclone 0.10.2's access control takes")
        if os.environ.get("SWARM_PARSE_ONLY") == "1":  # scripts/swarm checks the flags before it builds
            return exit_codes.OK
        if args.view_paused and args.view is None:
            args.view = DEFAULT_VIEW_PORT
        code = launcher.run(args, lambda run_dir: render_pictures(run_dir, args.ticks,
                                                                  animate=not args.no_animation,
                                                                  labels=args.labels))
        if args.expect and code != launcher.EXIT_INTERRUPTED and getattr(args, "run_dir", None):
            checked = expect.evaluate(args.expect, args.run_dir, lambda m: print(m, file=sys.stderr))
            code = code or checked  # a failed run keeps its own exit code
        if args.command == "demo" and code == exit_codes.OK:
            where = os.path.relpath(args.run_dir)
            where = args.run_dir if where.startswith("..") else where
            print(f"demo done. Pictures: {where}/pictures/ (snapshot_t*.png, trajectories.png, residual_force.png,"
                  f" shape_error.png, animation.mp4, animation.gif)")
            print(f"The numbers: scripts/swarm report {where}")
        return code
    if args.command == "kill":
        run_dir = args.run or os.path.join(places.runs_root(), "latest")
        try:
            pid = launcher.kill(args.id, run_dir)
        except launcher.LaunchError as e:
            print(f"swarm kill: {e}", file=sys.stderr)
            return e.code
        print(f"killed agent {args.id} (pid {pid})")
        return exit_codes.OK
    if args.command == "view":
        if os.environ.get("SWARM_PARSE_ONLY") == "1":
            return exit_codes.OK
        return launcher.view(args.run_dir, args.port, args.host, args.control_origin)
    if args.command == "replay":
        return render_pictures(args.run_dir, args.ticks, args.out, not args.no_animation, args.labels)
    if args.command == "sweep":
        if os.environ.get("SWARM_PARSE_ONLY") == "1":
            return exit_codes.OK
        from . import sweep
        args.seeds = [s for chunk in (args.seeds or []) for s in chunk] or None
        given = list(argv if argv is not None else sys.argv[1:])
        args.argv = given[given.index("sweep") + 1:]  # the sweep's own flags: sweep_args.json
        code = sweep.sweep(args)
        out_dir = args.resume or args.out or getattr(args, "written_to", None)
        if args.plot and code in (exit_codes.OK, exit_codes.FAILED) and out_dir:
            code = _plot(out_dir, args.plot_metric, None) or code
        return code
    if args.command == "export":
        from . import export
        return export.export_mcap(args.run_dir, args.mcap)
    if args.command == "report":
        from . import report, recording
        try:
            if args.json or args.csv:
                report.machine_readable(args.run_dir, "json" if args.json else "csv", sys.stdout)
            else:
                for i, run_dir in enumerate(args.run_dir):
                    if i:
                        print()
                    report.report(run_dir)
        except recording.RecordingError as e:
            print(f"swarm report: {e}", file=sys.stderr)
            return exit_codes.FAILED
        return exit_codes.OK
    if args.command == "plot":
        return _plot(args.sweep_dir, args.metric, args.out)
    parser.error(f"unknown command {args.command}")
    return exit_codes.BAD_INPUT
