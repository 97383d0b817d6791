"""`swarm sweep`: a grid of in-process runs (scenarios x shapes x robot counts x seeds x kill schedules x behaviour
parameter values x scenario-field values: loss, bursts, noise, --set), run on
every core with `swarm_inprocess --no-record --quiet`, judged, and written as sweep.csv and sweep.json.

Order of a sweep:
  1. the grid is checked: every flag, every kill schedule's text (`none`, `ID@TICK[+D][,...]`, `random:K[+D]`);
  2. a probe per (scenario, shape, robots), with the grid's first --param values: `swarm_inprocess ... --max-ticks 1
     --no-record --quiet` validates the files (a bad one: its `file:line: what`, exit 2, before anything long
     starts) and says N and the shape; then `swarm_inprocess ... --check` says every key the runs' summaries will
     have (the --expect keys are checked against them) and the summary keys the behaviour's experiment declares;
     and one per scenario and --param value, which the behaviour checks against its own parameter table, and one
     per scenario and scenario-field value (--loss, --burst, --noise, --set: sweep_fields.py), which the loader
     checks like the file's own fields;
  3. the kill schedules become `--kill ID@TICK` flags per run (a random one from an RNG seeded by the run's seed
     and the schedule's text: the same run gets the same kills every time);
  4. the runs, `--jobs` at a time, each with a wall-time cap; a progress line on stderr;
  5. sweep.csv, sweep.json and a short table on stdout.
Ctrl-C / SIGTERM: every run still going gets SIGTERM (the harness prints the summary of what it did), then SIGKILL
after 10 s (by process group); what finished, and what the interrupted runs reported, is written; exit 130.
"""

import argparse
import csv
import datetime
import glob
import io
import itertools
import json
import math
import os
import random
import re
import shlex
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from typing import IO, Any, Callable, Iterable, Optional, Sequence, Union

from .child_death import die_with_parent
from . import expect, launcher, places, summary_keys, sweep_cluster, sweep_exec, sweep_fields, sweep_journal

ParamValues = list[tuple[str, float]]  # a --param's values: (as written, as a number)
Combo = dict[str, tuple[str, float]]  # one run's parameters: NAME -> (text, value)

EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130
DEFAULT_KILL_WINDOW = 3000
DEFAULT_TIMEOUT_S = 1800.0
INTERRUPT_GRACE_S = 10.0
PROBE_TIMEOUT_S = 120.0
EXPECT = ("success", "arrived", "formed", "not_formed", "none", "any")
PAPER_OUTCOMES = ("arrived", "formed_not_arrived", "not_formed")
SERIES_KEYS = summary_keys.SERIES_KEYS  # per-tick series: not a column
WORST_SHOWN = 5
BEHAVIOUR_COLUMNS_SHOWN = 6  # the table's columns of a behaviour's own numbers (every one is in sweep.csv)
Judging = Union[str, expect.Expectation]  # an --expect: an outcome word, or 'KEY OP VALUE'

HELP = """\
Runs a grid of in-process runs (build/harness/swarm_inprocess --no-record --quiet; with --exec CMD, real
processes: `swarm run --exec CMD`, for a behaviour only a program drives):
every --scenario x every --shape x every --robots x every seed of --seeds x every --kills schedule x every
combination of the --param values x every combination of the scenario-field values (--loss, --burst, --noise,
--set), --jobs at a time, and writes into --out:

  sweep.csv   one row per run: the grid coordinates (scenario, shape, robots, seed, kills and the --kill
              flags they gave, a param_NAME column per --param, and a loss, burst, noise or set_KEY column per
              scenario-field axis), the exact command, its exit code, wall seconds, success and the reason of a
              failure, then every key of the run's summary.json, a nested one flattened with dots
              (states_at_end.NAME, telemetry_mean_at_end.NAME, params.NAME, an experiment's metrics; lists of
              ids or {id, tick} are written as "3 7" / "3@120 7@900"; the per-tick distortion series is left
              out). A summary key named like one of the sweep's own columns is written as summary_<key>.
  sweep.json  the grid, the commit, the success rates (overall, per scenario, per shape, per kill schedule,
              per parameter combination, per field combination (by_fields), per scenario x shape x schedule x
              parameters x fields, with median formation/goal ticks and the largest shape
              errors, and the medians of the behaviour's own numbers), and the worst runs: failed ones first,
              then the largest shape error, then the latest goal, each with its flattened summary and the
              command that reproduces it (and the same command writing a run directory).
              Commands are relative to the folder the sweep ran in (sweep.json's cwd).

  runs.jsonl  written as the sweep goes: one line per finished run (its sweep.json record), to read a long
              sweep before it ends.

A progress line on stderr (done/total, failures so far, running, ETA); a short table on stdout at the end.

Kill schedules (--kills, repeatable; each is one value of the grid's kill axis):
  none                 no kills (the default)
  5@10,2@300           robot 5 at tick 10 and robot 2 at tick 300 (ids < the run's robot count)
  random:K             K kills of distinct robots, ids drawn among ALL robots (the seed robot and the leader
                       included) and ticks uniformly in [1, min(--kill-window, max_ticks)]; the draw is seeded
                       by the run's seed and the schedule's text, so it is the same on every sweep and machine
                       (K must leave one robot alive)
  5@400+10, random:2+150
                       +D after a kill: the robot is restarted D ticks after its death with a fresh controller
                       (`--fault restart:ID@TICK`; a stalled agent taken for dead comes back the same way)

Behaviour parameters (--param NAME=V1,V2,..., repeatable; each NAME one axis of the grid):
  NAME is a parameter of the scenario's behaviour (a `controller:` key: robot_agent/README.md lists the paper's),
  each run gets `--param NAME=V` over the scenario's value. Every value is checked by the behaviour before any
  run starts: an unknown NAME or a value out of its bounds is refused naming it (exit 2). A plug-in behaviour
  (`behaviour: {plugin: ...}`) loads from its scenario's folder; --plugin-dir DIR (repeatable) adds a folder,
  passed to every run.

""" + sweep_fields.HELP + """
Success (--expect, repeatable): by default (`success`) the behaviour's own outcome: a run succeeds when its
summary's `outcome` is its behaviour's success (the paper's: arrived; a summary's boolean `success`, when it has
one, says it for any behaviour); a behaviour with no judge of its own (outcome none) succeeds by a clean exit
with a summary. An outcome word instead: arrived, formed (arrived or formed_not_arrived), not_formed, none, any
(a clean exit with a summary). Or 'KEY OP VALUE', the grammar of `swarm run --expect` (a summary key, dotted for
a nested one: 'states_at_end.settled >= 10', 'outcome == settled'): every one must hold; given alone, they
judge the run with a clean exit (no outcome word asked). Every KEY is checked before any run against the keys
the runs' summaries will have (each scenario's `swarm_inprocess --check`; an unknown one: exit 2). A summary
without `outcome` (older builds) is judged from its ticks: arrived iff goal_tick is set, formed iff
formation_tick is set. Then the
optional thresholds: --max-shape-error on shape_error_at_goal (success, arrived) or shape_error_at_formation
(otherwise), --max-contacts on robot-robot + robot-obstacle contacts, --max-robot-contacts on robot-robot ones.
A run that never ends is cut at max_ticks by the harness and fails by its outcome; a run that crashes, exits
non-zero, prints no summary or outlives --timeout (SIGKILLed) fails with that reason.

Slices and resuming (docs/sweeps.md): --shard K/N runs every N-th run of the grid from the K-th (a batch system's
job array); --merge DIR... joins all N slice folders of one grid into the sweep they were cut from (into --out;
nothing is run again); --resume DIR goes on with a stopped sweep, running only what DIR/runs.jsonl lacks. Each
sweep folder keeps sweep_args.json (its grid's flags) for them.

With no grid flag: scenarios/paper.yaml x seeds 1-10, no kills, --expect success.

Exit codes: 0 every run succeeded; 1 at least one run failed (or could not start); 2 bad input (a flag, a
schedule, a scenario or shape the probe refused: nothing was run); 130 interrupted (the runs in flight get
SIGTERM and report what they did, as failed "interrupted" rows; what finished is written).
Environment: BUILD_DIR (default build/), SWARM_NO_BUILD=1 (skip the build), SWARM_RUNS_DIR (default runs/).
"""

EXAMPLES = """\
examples:
  scripts/swarm sweep                                              # paper.yaml x seeds 1-10
  scripts/swarm sweep --shape shapes/*.txt --seeds 1-20 --expect formed --max-shape-error 0.1 \\
      --max-robot-contacts 0 --out runs/sweep-shapes
  scripts/swarm sweep --scenario scenarios/*.yaml --seeds 1-10 --max-shape-error 0.1
  scripts/swarm sweep --kills random:1 random:2 random:3 --seeds 1-30
  scripts/swarm sweep --kills none 5@10 2@10,7@1500 --seeds 1-5 --max-ticks 8000 --jobs 2
  scripts/swarm sweep --param k_goal=0.5,1,2 --param m_obstacle=0.5,1 --seeds 1-10   # 3 x 2 x 10 runs
  scripts/swarm sweep --loss 0,0.1,0.2,0.3 --burst 1,5 --noise off,on --kills none random:2 --seeds 1-10
  scripts/swarm sweep --set comm_range=2,3 --set occlusion=false,true --seeds 1-5
  scripts/swarm sweep --scenario examples/behaviours/aggregation/aggregation.yaml --param stop_distance=0.3,0.5 \\
      --expect 'states_at_end.gathered >= 6' --seeds 1-10
  scripts/swarm sweep --seeds 1-30 --shard 3/8 --out runs/study/slice-3         # slice 3 of 8 (a job array's task)
  scripts/swarm sweep --merge runs/study/slice-* --out runs/study/all             # the 8 slices as one sweep
  scripts/swarm sweep --resume runs/study/slice-3                                # after a stop: only what is missing
"""


class SweepError(Exception):
    """Bad input found before any run started (exit 2)."""


# ----------------------------------------------------------------------------------------------- the grid's text

class KillSchedule:
    """One value of the kill axis: `none`, explicit kills, or `random:K`; each kill may be followed by a restart."""

    def __init__(self, text: str, kills: Iterable[tuple[int, int]] = (), random_count: int = 0,
                 restart_after: Optional[dict[int, int]] = None, random_restart_after: int = 0) -> None:
        self.text = text            # canonical: "none", "5@10,2@300+50", "random:2", "random:2+150"
        self.kills = list(kills)    # [(id, tick)] for an explicit list
        self.random_count = random_count
        self.restart_after = restart_after or {}  # explicit: id -> ticks from its kill to its restart
        self.random_restart_after = random_restart_after  # random:K+D: D (0: no restarts)

    def __repr__(self) -> str:
        return f"KillSchedule({self.text!r})"

    def flags(self, seed: int, robots: int, window: int) -> list[str]:
        """The `ID@TICK` kills of one run with `robots` robots whose ticks may go up to `window`."""
        if self.random_count:
            if self.random_count >= robots:
                raise SweepError(f"--kills {self.text}: {self.random_count} kills of {robots} robots leave none "
                                 f"alive (K must be < the robot count)")
            rng = random.Random(f"swarm-sweep:{seed}:{self.text}")  # str seeds are hashed (sha512): stable
            ids = rng.sample(range(robots), self.random_count)
            ticks = [rng.randint(1, max(1, window)) for _ in ids]
            return [f"{i}@{t}" for t, i in sorted(zip(ticks, ids))]
        for rid, _ in self.kills:
            if rid >= robots:
                raise SweepError(f"--kills {self.text}: robot {rid} does not exist (ids 0..{robots - 1})")
        return [f"{rid}@{tick}" for rid, tick in self.kills]

    def restart_flags(self, kill_flags: list[str], last_tick: Optional[int] = None) -> list[str]:
        """The `restart:ID@TICK` faults that follow the kills `kill_flags` (this schedule's `flags`), but for those
        after `last_tick` (the run's max_ticks: they would never happen)."""
        out = []
        for k in kill_flags:
            rid, tick = (int(v) for v in k.split("@"))
            after = self.random_restart_after if self.random_count else self.restart_after.get(rid, 0)
            if after and (last_tick is None or tick + after <= last_tick):
                out.append(f"restart:{rid}@{tick + after}")
        return out


_KILL = re.compile(r"^(\d+)@(\d+)(?:\+(\d+))?$")
_RANDOM = re.compile(r"^random:(\d+)(?:\+(\d+))?$")


def parse_kill_schedule(text: str) -> KillSchedule:
    """`none` | `ID@TICK[+D][,ID@TICK[+D]...]` | `random:K[+D]` -> KillSchedule (+D: the killed robot restarted D
    ticks later); ValueError with a message naming the text."""
    t = text.strip()
    usage = ("expected none, ID@TICK[+D][,ID@TICK[+D]...] (e.g. 5@10,2@300+50) or random:K[+D] (e.g. random:2, "
             "random:1+150); +D restarts the killed robot D ticks later")
    if t == "none":
        return KillSchedule("none")
    if t.startswith("random"):
        m = _RANDOM.match(t)
        if not m:
            raise ValueError(f"'{text}': {usage}")
        k = int(m[1])
        if k < 1:
            raise ValueError(f"'{text}': random:K needs K >= 1 (no kills is 'none')")
        after = _restart_delay(text, m[2])
        return KillSchedule(f"random:{k}" + (f"+{after}" if after else ""), random_count=k,
                            random_restart_after=after)
    if not t:
        raise ValueError(f"'{text}' is empty: {usage}")
    kills: list[tuple[int, int]] = []
    restarts: dict[int, int] = {}
    seen: set[int] = set()
    for part in t.split(","):
        m = _KILL.match(part.strip())
        if not m:
            where = f"'{text}': '{part}'" if part.strip() != t else f"'{text}'"
            raise ValueError(f"{where} is not ID@TICK[+D]; {usage}")
        rid, tick = int(m[1]), int(m[2])
        if rid in seen:
            raise ValueError(f"'{text}': robot {rid} is killed twice")
        if tick > 1_000_000_000:
            raise ValueError(f"'{text}': tick {tick} is beyond 1e9")
        seen.add(rid)
        kills.append((rid, tick))
        if m[3] is not None:
            restarts[rid] = _restart_delay(text, m[3])
    canonical = ",".join(f"{r}@{k}" + (f"+{restarts[r]}" if r in restarts else "") for r, k in kills)
    return KillSchedule(canonical, kills=kills, restart_after=restarts)


def _restart_delay(text: str, digits: Optional[str]) -> int:
    if digits is None:
        return 0
    after = int(digits)
    if not 1 <= after <= 1_000_000_000:
        raise ValueError(f"'{text}': +D (ticks from the kill to the restart) must be in [1, 1e9], got {digits}")
    return after


_PARAM_NAME = re.compile(r"^(?:[a-z][a-z0-9_]*\.)?[A-Za-z_][A-Za-z0-9_]*$")  # GROUP.NAME: a robot group's


def parse_param(text: str) -> tuple[str, ParamValues]:
    """`NAME=V1,V2,...` -> (NAME, [(text, value)]); ValueError naming the text. The values' own spelling is kept for
    the command line (no precision lost); whether NAME exists and the values are in bounds is the behaviour's to
    say (the probe)."""
    name, sep, values = text.partition("=")
    name = name.strip()
    usage = "expected NAME=V1,V2,... (e.g. k_goal=0.5,1,2)"
    if not sep or not _PARAM_NAME.match(name):
        raise ValueError(f"'{text}': {usage}")
    return name, sweep_fields.number_list(values, text, usage)


def param_combinations(params: Sequence[tuple[str, ParamValues]]) -> list[Combo]:
    """[(NAME, [(text, value)])] -> every combination as a dict NAME -> (text, value), in the flags' order."""
    if not params:
        return [{}]
    names = [n for n, _ in params]
    return [dict(zip(names, combo)) for combo in itertools.product(*(values for _, values in params))]


def param_flags(combo: Combo) -> list[str]:
    return [a for name, (text, _) in combo.items() for a in ("--param", f"{name}={text}")]


def param_label(combo: Combo) -> str:
    """'k_goal=0.5 m_obstacle=1' (the key of sweep.json's by_params), or 'defaults'."""
    return " ".join(f"{n}={t}" for n, (t, _) in combo.items()) or "defaults"


def parse_seeds(text: str) -> list[int]:
    """`7`, `1-20`, `1-5,9,12-13` -> list of seeds; ValueError naming the text."""
    seeds: list[int] = []
    for part in text.split(","):
        part = part.strip()
        m = re.match(r"^(\d+)(?:-(\d+))?$", part)
        if not m:
            raise ValueError(f"'{text}': '{part}' is not a seed or a range like 1-20")
        lo = int(m[1])
        hi = int(m[2]) if m[2] is not None else lo
        if hi < lo:
            raise ValueError(f"'{text}': the range {part} is empty (write LOW-HIGH)")
        if hi - lo >= 100000:
            raise ValueError(f"'{text}': the range {part} has more than 100000 seeds")
        seeds.extend(range(lo, hi + 1))
    return seeds


def expand_files(patterns: Sequence[str], what: str) -> list[str]:
    """Paths and glob patterns -> existing files, in the order given (a pattern's matches sorted)."""
    out: list[str] = []
    for p in patterns:
        if any(c in p for c in "*?["):
            matches = sorted(f for f in glob.glob(p) if os.path.isfile(f))
            if not matches:
                raise SweepError(f"--{what} '{p}': no file matches")
            out.extend(matches)
        elif what == "shape" and not os.path.isfile(p) and os.sep not in p:
            out.append(p)  # a bare name: the world looks it up in shapes/ (the probe checks it)
        elif not os.path.isfile(p):
            raise SweepError(f"--{what} '{p}': no such file")
        else:
            out.append(p)
    return list(dict.fromkeys(out))


def scenario_max_ticks(path: str) -> int:
    """The scenario's top-level `max_ticks:` (the loader's default, 3000, when it has none)."""
    try:
        with open(path, encoding="utf-8", errors="backslashreplace") as f:
            for line in f:
                m = re.match(r"^max_ticks:\s*(\d+)", line)
                if m:
                    return int(m[1])
    except OSError:
        pass
    return 3000


# ------------------------------------------------------------------------------------------------- the runs

class Run:
    def __init__(self, index: int, scenario: str, shape: Optional[str], shape_name: str,
                 robots_asked: Optional[int], robots: int, seed: int, schedule: KillSchedule, kill_flags: list[str],
                 max_ticks_asked: Optional[int], cmd: list[str], params: Optional[Combo] = None,
                 fields: Optional[dict[str, str]] = None) -> None:
        self.index, self.scenario, self.shape, self.shape_name = index, scenario, shape, shape_name
        self.robots_asked, self.robots, self.seed, self.schedule = robots_asked, robots, seed, schedule
        self.kill_flags, self.max_ticks_asked, self.cmd = kill_flags, max_ticks_asked, cmd
        self.params: Combo = params or {}  # NAME -> (text, value)
        self.fields: dict[str, str] = fields or {}  # scenario-field axis column -> value as written
        self.exit_code: Optional[int] = None
        self.wall: Optional[float] = None
        self.summary: Optional[dict[str, Any]] = None
        self.success = False
        self.reason = "not run"
        self.severity = 9  # for the worst-case order: 0 ok .. 4 crash/timeout
        self.retries = 0  # --cluster: how many times a dying worker made the scheduler start it again
        self.real_processes = False  # --exec: `swarm run` (sweep_exec.py), its summary read from its run directory
        # The numeric summary keys its scenario's behaviour's experiment declares (summary_keys.number_keys): the
        # table's own columns before the rest.
        self.declared: list[str] = []


def command_text(cmd: Sequence[str]) -> str:
    return shlex.join(cmd)


def record_command(cmd: Sequence[str], index: int) -> str:
    """The same run, writing a run directory (for `swarm replay` / `swarm report`)."""
    out = [a for a in cmd if a not in ("--no-record", "--quiet")]
    return command_text(out + ["--out", f"runs/sweep-repro-{index}"])


def base_command(exe: str, scenario: str, shape: Optional[str], robots: Optional[int], seed: Optional[int],
                 max_ticks: Optional[int], plugin_dirs: Sequence[str] = ()) -> list[str]:
    cmd = [exe, "--scenario", scenario]
    for d in plugin_dirs:  # a plug-in behaviour loads only from the scenario's folder and these
        cmd += ["--plugin-dir", d]
    if shape:
        cmd += ["--shape", shape]
    if robots is not None:
        cmd += ["--robots", str(robots)]
    if seed is not None:
        cmd += ["--seed", str(seed)]
    if max_ticks is not None:
        cmd += ["--max-ticks", str(max_ticks)]
    return cmd


def parse_summary(text: str) -> Optional[dict[str, Any]]:
    """summary.json from the harness's stdout (the whole of it, or its last {...} block); None if there is none."""
    text = text.strip()
    if not text:
        return None
    try:
        value = json.loads(text)
        return value if isinstance(value, dict) else None
    except json.JSONDecodeError:
        pass
    start = text.find("{")
    while start != -1:
        try:
            value = json.loads(text[start:])
            return value if isinstance(value, dict) else None
        except json.JSONDecodeError:
            start = text.find("{", start + 1)
    return None


def _json_of(cmd: list[str], what: str, usable: Callable[[dict[str, Any]], bool]) -> dict[str, Any]:
    """The JSON object `cmd` prints, when it exits 0 and `usable` takes it; else SweepError with its message and
    the command (`what`: "probe", "check")."""
    try:
        p = subprocess.run(cmd, capture_output=True, timeout=PROBE_TIMEOUT_S, encoding="utf-8",
                           errors="backslashreplace", preexec_fn=die_with_parent)
    except subprocess.TimeoutExpired:
        raise SweepError(f"{command_text(cmd)}: no answer within {PROBE_TIMEOUT_S:.0f} s") from None
    out = parse_summary(p.stdout)
    if p.returncode != 0 or out is None or not usable(out):
        msg = p.stderr.strip() or p.stdout.strip()[:300] or f"exit {p.returncode}"
        raise SweepError(f"{msg}\n(the {what}: {command_text(cmd)})")
    return out


def probe(exe: str, scenario: str, shape: Optional[str], robots: Optional[int], params: Optional[Combo] = None,
          plugin_dirs: Sequence[str] = (), field_flags: Sequence[str] = ()) -> dict[str, Any]:
    """Runs one tick: validates the files (and the --param values, and the scenario fields' --set flags) and returns
    the summary (robots, labels, shape_file)."""
    cmd = (base_command(exe, scenario, shape, robots, None, 1, plugin_dirs) + param_flags(params or {}) +
           list(field_flags) + ["--no-record", "--quiet"])
    return _json_of(cmd, "probe", lambda s: isinstance(s.get("robots"), int))


def check_info(exe: str, scenario: str, shape: Optional[str], robots: Optional[int], params: Optional[Combo] = None,
               plugin_dirs: Sequence[str] = (), field_flags: Sequence[str] = ()) -> dict[str, Any]:
    """`swarm_inprocess --check`: world_server --check's JSON (the behaviour's descriptor, the summary_template:
    every key the run's summary will have), for the --expect keys and the declared columns."""
    cmd = (base_command(exe, scenario, shape, robots, None, None, plugin_dirs) + param_flags(params or {}) +
           list(field_flags) + ["--check"])
    return _json_of(cmd, "check", lambda s: isinstance(s.get("summary_template"), dict))


def probe_exec(opts: argparse.Namespace, scenario: str, shape: Optional[str], robots: Optional[int],
               params: Optional[Combo] = None, plugin_dirs: Sequence[str] = ()) -> dict[str, Any]:
    """probe() for --exec: one tick as real processes (sweep_exec.probe)."""
    cmd = (sweep_exec.as_run(base_command("", scenario, shape, robots, None, 1, plugin_dirs), opts.exec,
                             opts.exec_timeout) + param_flags(params or {}))
    try:
        summary, last = sweep_exec.probe(cmd, PROBE_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        raise SweepError(f"{command_text(cmd)}: no answer within {PROBE_TIMEOUT_S:.0f} s") from None
    if summary is None or not isinstance(summary.get("robots"), int):
        raise SweepError(f"{last}\n(the probe: {command_text(cmd)})")
    return summary


def contacts(summary: dict[str, Any]) -> tuple[int, int]:
    rr = summary.get("collisions_robot_robot")
    ro = summary.get("collisions_robot_obstacle")
    return (rr if isinstance(rr, int) else 0), (ro if isinstance(ro, int) else 0)


def outcome_of(summary: dict[str, Any]) -> str:
    """The summary's outcome, or the fallback for summaries without one (from the ticks)."""
    o = summary.get("outcome")
    if isinstance(o, str):
        return o
    if summary.get("goal_tick") is not None:
        return "arrived"
    if summary.get("formation_tick") is not None:
        return "formed_not_arrived"
    if summary.get("behaviour") not in (None, "paper"):
        return "none"
    return "not_formed"


def parse_expect(text: str) -> Judging:
    """An --expect value: an outcome word (EXPECT) or 'KEY OP VALUE' (expect.py); ValueError naming the text."""
    t = text.strip()
    if t in EXPECT:
        return t
    if any(op in t for op in expect.OPS):
        try:
            return expect.parse(t)
        except expect.ExpectationError as e:
            raise ValueError(str(e)) from None
    raise ValueError(f"'{text}': expected an outcome word ({', '.join(EXPECT)}) or 'KEY OP VALUE' (e.g. "
                     "'states_at_end.settled >= 10')")


def outcome_word(opts: argparse.Namespace) -> str:
    """The one outcome word of the --expect values: the one given, `any` when only expressions were given, else
    `success`."""
    given: Sequence[Judging] = getattr(opts, "expect", None) or []
    words = [e for e in given if isinstance(e, str)]
    if words:
        return words[0]
    return "any" if given else "success"


def expressions(opts: argparse.Namespace) -> list[expect.Expectation]:
    return [e for e in (getattr(opts, "expect", None) or []) if isinstance(e, expect.Expectation)]


def check_judging(opts: argparse.Namespace) -> None:
    """SweepError for --expect values that cannot judge together (two outcome words)."""
    words = [e for e in (getattr(opts, "expect", None) or []) if isinstance(e, str)]
    if len(set(words)) > 1:
        raise SweepError(f"--expect {' and '.join(words)}: one outcome word at most (add 'KEY OP VALUE' "
                         "expressions beside it)")


def behaviour_success(summary: dict[str, Any]) -> tuple[Optional[bool], str]:
    """Whether the run ended in its behaviour's own success, and what that success is (for the reason of a
    failure). The one place that reads a behaviour's verdict from its summary: a boolean `success` when the
    summary has one (a behaviour with its own judge says it); else the paper's outcomes (success: arrived); a
    behaviour with no judge of its own (outcome none): None, judged by a clean exit; any other outcome without
    a `success` key cannot be judged: (False, why)."""
    outcome = outcome_of(summary)
    verdict = summary.get("success")
    if isinstance(verdict, bool):
        return verdict, "the behaviour's success"
    if outcome in PAPER_OUTCOMES:
        return outcome == "arrived", "arrived"
    if outcome == "none":
        return None, "none"
    return False, "a verdict: the summary has no boolean `success` to say whether it is the behaviour's " \
                  "success; judge it with --expect 'outcome == WORD'"


def judge(run: Run, opts: argparse.Namespace) -> None:
    """Sets run.success, run.reason and run.severity from its exit and summary."""
    s = run.summary
    if s is None:
        run.success, run.severity = False, 4
        return
    outcome = outcome_of(s)
    expect_word = outcome_word(opts)
    reasons: list[str] = []
    severity = 0
    ticks = s.get("ticks")
    cut = f" (ended at tick {ticks})" if isinstance(ticks, int) else ""
    if expect_word == "success":
        ok, what = behaviour_success(s)
        if ok is False:
            reasons.append(f"outcome {outcome}, expected {what}{cut}")
            severity = {"formed_not_arrived": 2}.get(outcome, 3)
    else:
        wanted = {"arrived": ("arrived",), "formed": ("arrived", "formed_not_arrived"),
                  "not_formed": ("not_formed",), "none": ("none",)}.get(expect_word)
        if wanted is not None and outcome not in wanted:
            reasons.append(f"outcome {outcome}, expected {expect_word}{cut}")
            severity = {"not_formed": 3, "none": 3, "formed_not_arrived": 2}.get(outcome, 3)
    for exp in expressions(opts):
        try:
            met, actual = expect.check(exp, s)
        except expect.ExpectationError as e:
            reasons.append(str(e))
            severity = max(severity, 3)
            continue
        if not met:
            reasons.append(f"{exp.text} failed ({exp.key} is {actual})")
            severity = max(severity, 1)
    if opts.max_shape_error is not None and expect_word != "any":
        key = "shape_error_at_goal" if expect_word in ("arrived", "success") else "shape_error_at_formation"
        value = s.get(key)
        if not isinstance(value, (int, float)):
            if not reasons:
                reasons.append(f"{key} missing")
                severity = max(severity, 1)
        elif value > opts.max_shape_error:
            reasons.append(f"{key} {value:.3f} > {opts.max_shape_error:g}")
            severity = max(severity, 1)
    rr, ro = contacts(s)
    if opts.max_contacts is not None and rr + ro > opts.max_contacts:
        reasons.append(f"contacts {rr + ro} (robot-robot {rr}, robot-obstacle {ro}) > {opts.max_contacts}")
        severity = max(severity, 1)
    if opts.max_robot_contacts is not None and rr > opts.max_robot_contacts:
        reasons.append(f"robot-robot contacts {rr} > {opts.max_robot_contacts}")
        severity = max(severity, 1)
    run.success = not reasons
    run.reason = "; ".join(reasons)
    run.severity = severity


def _signal_name(code: int) -> str:
    try:
        return signal.Signals(-code).name
    except ValueError:
        return f"signal {-code}"


class Progress:
    """One line on stderr: rewritten in place on a terminal, a plain line every few seconds otherwise."""

    def __init__(self, total: int, stream: IO[str] = sys.stderr, quiet: bool = False) -> None:
        self.total, self.stream, self.quiet = total, stream, quiet
        self.tty = stream.isatty()
        self.start = time.monotonic()
        self.last = 0.0

    def text(self, done: int, failed: int, running: int) -> str:
        elapsed = time.monotonic() - self.start
        eta = "?"
        if done:
            eta = _duration(elapsed / done * (self.total - done))
        return (f"sweep: {done}/{self.total} done, {failed} failed, {running} running, "
                f"{_duration(elapsed)} elapsed, ETA {eta}")

    def show(self, done: int, failed: int, running: int, force: bool = False) -> None:
        if self.quiet:
            return
        now = time.monotonic()
        if self.tty:
            if not force and now - self.last < 0.5:
                return
            self.last = now
            self.stream.write("\r\033[K" + self.text(done, failed, running))
        elif force or now - self.last >= 10.0:
            self.stream.write(self.text(done, failed, running) + "\n")
            self.last = now
        else:
            return
        self.stream.flush()

    def line(self, text: str) -> None:
        if self.tty and not self.quiet:
            self.stream.write("\r\033[K")
        self.stream.write(text + "\n")
        self.stream.flush()

    def end(self) -> None:
        if self.tty and not self.quiet:
            self.stream.write("\n")
            self.stream.flush()


def _duration(seconds_f: float) -> str:
    seconds = int(round(seconds_f))
    if seconds < 60:
        return f"{seconds}s"
    if seconds < 3600:
        return f"{seconds // 60}m{seconds % 60:02d}s"
    return f"{seconds // 3600}h{seconds // 60 % 60:02d}m"


def execute(runs: Sequence[Run], jobs: int, timeout: float, progress: Progress, stop: launcher.StopFlag,
            opts: argparse.Namespace, journal: Optional[IO[str]] = None) -> tuple[int, int]:
    """Runs them `jobs` at a time; each one's stdout and stderr go to temporary files (no pipe to fill).
    `journal` (a file) gets one JSON line per finished run as it finishes (a long sweep can be read early)."""
    pending = list(runs)
    pending.reverse()
    active: dict[subprocess.Popen[bytes], tuple[Run, float, IO[str], IO[str]]] = {}  # run, start, out file, err file
    done = failed = 0
    tmp = tempfile.mkdtemp(prefix="swarm-sweep-")
    try:
        while (pending or active) and not stop:
            while pending and len(active) < jobs and not stop:
                run = pending.pop()
                # Read back as text whatever bytes the run printed (a bad file's byte quoted in an error).
                out: IO[str] = open(os.path.join(tmp, f"{run.index}.out"), "w+", encoding="utf-8",
                                    errors="backslashreplace")
                err: IO[str] = open(os.path.join(tmp, f"{run.index}.err"), "w+", encoding="utf-8",
                                    errors="backslashreplace")
                try:
                    argv = sweep_exec.argv(run.cmd, _run_dir(tmp, run)) if run.real_processes else run.cmd
                    p = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                                         process_group=0, preexec_fn=die_with_parent)
                except OSError as e:
                    run.reason, run.severity, run.exit_code = f"could not start: {e}", 4, None
                    out.close()
                    err.close()
                    done += 1
                    failed += 1
                    continue
                active[p] = (run, time.monotonic(), out, err)
            time.sleep(0.05)
            for p, (run, started, out, err) in list(active.items()):
                over = False
                if p.poll() is None:
                    if not timeout or time.monotonic() - started <= timeout:
                        continue
                    over = True  # over its wall-time cap
                    _killpg(p)
                    p.wait()
                    run.reason = f"timeout: still running after {timeout:g} s (SIGKILLed)"
                run.wall = time.monotonic() - started
                run.exit_code = p.returncode
                _finish(run, out, err, over, opts, _run_dir(tmp, run))
                if journal is not None:
                    journal.write(json.dumps(journal_record(run)) + "\n")
                    journal.flush()
                del active[p]
                done += 1
                failed += 0 if run.success else 1
                progress.show(done, failed, len(active), force=done == len(runs) or progress.tty)
            progress.show(done, failed, len(active))
    finally:
        # Interrupted: SIGTERM the runs in flight (the harness then prints the summary of what it did, exit 130),
        # SIGKILL what is left after the grace period. A run that answered is kept, judged as interrupted.
        for p in active:
            _killpg(p, signal.SIGTERM)
        end = time.monotonic() + INTERRUPT_GRACE_S
        for p, (run, started, out, err) in active.items():
            try:
                p.wait(timeout=max(0.0, end - time.monotonic()))
            except subprocess.TimeoutExpired:
                _killpg(p)
                p.wait()
            run.wall = time.monotonic() - started
            run.exit_code = p.returncode
            _finish(run, out, err, False, opts, _run_dir(tmp, run))
            if run.summary is None:
                run.reason, run.severity = "interrupted", 9
            elif journal is not None:
                journal.write(json.dumps(journal_record(run)) + "\n")
        shutil.rmtree(tmp, ignore_errors=True)
    return done, failed


def execute_on_cluster(client: Any, runs: Sequence[Run], opts: argparse.Namespace, progress: Progress,
                       stop: launcher.StopFlag, journal: IO[str]) -> dict[str, Any]:
    """execute()'s work on a Dask cluster's workers (sweep_cluster.py), judged and journalled here alike."""
    def done(run: Run, result: dict[str, Any]) -> None:
        if "lost" in result:
            run.reason, run.severity, run.success = f"lost its workers: {result['lost']}", 4, False
        else:
            run.wall, run.exit_code = result["wall"], result["exit_code"]
            if result["timed_out"]:
                run.reason = f"timeout: still running after {opts.timeout:g} s (SIGKILLed)"
            _finish(run, io.StringIO(result["stdout"]), io.StringIO(result["stderr"]), result["timed_out"], opts)
        journal.write(json.dumps(journal_record(run)) + "\n")
        journal.flush()
    return sweep_cluster.execute(client, runs, opts.timeout, done, stop, progress)


def _killpg(p: "subprocess.Popen[bytes]", sig: int = signal.SIGKILL) -> None:
    try:
        os.killpg(p.pid, sig)
    except (ProcessLookupError, PermissionError):
        try:
            p.kill()
        except ProcessLookupError:
            pass


def _run_dir(tmp: str, run: Run) -> str:
    """An --exec run's run directory (sweep_exec.argv's --out), in the sweep's temporary folder."""
    return os.path.join(tmp, f"{run.index}.run")


def _finish(run: Run, out: IO[str], err: IO[str], timed_out: bool, opts: argparse.Namespace,
            run_dir: Optional[str] = None) -> None:
    out.seek(0)
    err.seek(0)
    stdout, stderr = out.read(), err.read()
    out.close()
    err.close()
    if run.real_processes and run_dir is not None:
        summary = sweep_exec.take_summary(run_dir)
        run.summary = None if timed_out else summary
    else:
        run.summary = None if timed_out else parse_summary(stdout)
    if timed_out:
        run.success, run.severity = False, 4
        return
    code = run.exit_code if run.exit_code is not None else 0  # set before _finish
    if code == EXIT_INTERRUPTED and run.summary is not None:  # SIGINT/SIGTERM: the summary of what it did
        ticks = run.summary.get("ticks")
        run.reason = f"interrupted (exit 130) at tick {ticks}, before its end"
        run.success, run.severity = False, 4
        return
    if code != 0:
        last = next((ln for ln in reversed(stderr.strip().splitlines()) if ln.strip()), "")
        what = f"crashed ({_signal_name(code)})" if code < 0 else f"exit {code}"
        run.reason = f"{what}: {last}" if last else what
        run.success, run.severity, run.summary = False, 4, None
        return
    if run.summary is None:
        run.reason = "no summary.json on stdout"
        run.success, run.severity = False, 4
        return
    judge(run, opts)


# ----------------------------------------------------------------------------------------------- the results

FIXED_COLUMNS = ["index", "scenario", "shape", "robots_asked", "seed", "kills", "kill_flags", "max_ticks_asked",
                 "success", "reason", "exit_code", "run_wall_seconds", "command"]


def _cell(value: Any) -> Optional[str]:
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else str(value)
    if isinstance(value, list):
        items: list[str] = []
        for v in value:
            if isinstance(v, dict) and "id" in v and "tick" in v:
                items.append(f"{v['id']}@{v['tick']}")
            elif isinstance(v, (dict, list)):
                return None
            else:
                items.append(_cell(v) or "")
        return " ".join(items)
    if isinstance(value, dict):
        return None
    return str(value)


def summary_columns(runs: Sequence[Run]) -> list[str]:
    """Every key of the runs' summaries, nested ones flattened with dots (summary_keys.flatten), first-seen order;
    not the series, nor lists of objects that have no cell."""
    keys: list[str] = []
    seen: set[str] = set()
    for r in runs:
        for k, v in summary_keys.flatten(r.summary or {}).items():
            if k in seen or k in SERIES_KEYS or _cell(v) is None:
                continue
            seen.add(k)
            keys.append(k)
    return keys


def write_csv(path: str, runs: Sequence[Run], param_names: Sequence[str] = (),
              field_columns: Sequence[str] = ()) -> None:
    """param_names: the --param axes, a `param_NAME` column each, after the fixed columns; field_columns: the
    scenario-field axes' columns (loss, burst, noise, set_KEY) after those."""
    keys = summary_columns(runs)
    fixed = FIXED_COLUMNS + [f"param_{n}" for n in param_names] + list(field_columns)
    names = [f"summary_{k}" if k in fixed else k for k in keys]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(fixed + names)
        for r in runs:
            row: list[Any] = [
                r.index, r.scenario, r.shape or "", "" if r.robots_asked is None else r.robots_asked, r.seed,
                r.schedule.text, " ".join(r.kill_flags), "" if r.max_ticks_asked is None else r.max_ticks_asked,
                1 if r.success else 0, r.reason, "" if r.exit_code is None else r.exit_code,
                "" if r.wall is None else f"{r.wall:.3f}", command_text(r.cmd)]
            row += [r.params[n][0] if n in r.params else "" for n in param_names]
            row += [r.fields.get(c, "") for c in field_columns]
            s = summary_keys.flatten(r.summary or {})
            row += [_cell(s.get(k)) or "" for k in keys]
            w.writerow(row)


def _num(s: Optional[dict[str, Any]], key: str) -> Optional[float]:
    v = (s or {}).get(key)
    return v if isinstance(v, (int, float)) and not isinstance(v, bool) else None


def group_stats(runs: Sequence[Run], behaviour_keys: Sequence[str] = ()) -> dict[str, Any]:
    """Success rates, outcomes, the paper's medians and maxima, contacts; `behaviour_keys` (flattened summary keys
    of the behaviour's own numbers): their medians over the runs that have them, in `medians`."""
    n = len(runs)
    ok = sum(1 for r in runs if r.success)
    out: dict[str, Any] = {"runs": n, "succeeded": ok, "failed": n - ok,
                           "success_rate": round(ok / n, 4) if n else None}
    outcomes: dict[str, int] = {}
    for r in runs:
        key = outcome_of(r.summary) if r.summary else "error"
        outcomes[key] = outcomes.get(key, 0) + 1
    out["outcomes"] = dict(sorted(outcomes.items()))
    for key, agg in (("formation_tick", "median"), ("goal_tick", "median"), ("shape_error_at_formation", "max"),
                     ("shape_error_at_goal", "max"), ("peak_distortion", "max")):
        vals = [v for v in (_num(r.summary, key) for r in runs) if v is not None]
        name = f"{agg}_{key}"
        if not vals:
            out[name] = None
        elif agg == "median":
            out[name] = statistics.median(vals)
        else:
            out[name] = round(max(vals), 4)
    rr = sum(contacts(r.summary)[0] for r in runs if r.summary)
    ro = sum(contacts(r.summary)[1] for r in runs if r.summary)
    out["contacts_robot_robot"], out["contacts_robot_obstacle"] = rr, ro
    walls = [r.wall for r in runs if r.wall is not None]
    out["median_wall_seconds"] = round(statistics.median(walls), 3) if walls else None
    if behaviour_keys:
        flat = [summary_keys.flatten(r.summary) for r in runs if r.summary]
        medians: dict[str, Optional[float]] = {}
        for key in behaviour_keys:
            vals = [v for v in (f.get(key) for f in flat) if isinstance(v, (int, float)) and not isinstance(v, bool)]
            medians[key] = statistics.median(vals) if vals else None
        out["medians"] = medians
    return out


def worst_key(opts: argparse.Namespace) -> Callable[[Run], tuple[Any, ...]]:
    err_key = "shape_error_at_goal" if outcome_word(opts) in ("arrived", "success") else "shape_error_at_formation"

    def key(r: Run) -> tuple[Any, ...]:
        err = _num(r.summary, err_key)
        goal = _num(r.summary, "goal_tick")
        return (r.success, -r.severity, -(err if err is not None else math.inf),
                -(goal if goal is not None else math.inf), r.index)
    return key


def run_record(r: Run) -> dict[str, Any]:
    s = r.summary or {}
    rec: dict[str, Any] = {"index": r.index, "success": r.success, "reason": r.reason, "scenario": r.scenario,
           "shape": r.shape_name, "robots": r.robots, "seed": r.seed, "kills": r.schedule.text,
           "kill_flags": r.kill_flags, "params": {n: v for n, (_, v) in r.params.items()},
           "fields": dict(r.fields),
           "exit_code": r.exit_code, "retries": r.retries,
           "wall_seconds": None if r.wall is None else round(r.wall, 3)}
    for k in ("outcome", "ticks", "formation_tick", "motion_start_tick", "goal_tick", "shape_error_at_formation",
              "shape_error_at_goal", "peak_distortion", "collisions_robot_robot", "collisions_robot_obstacle",
              "alive_at_end", "stuck_robots"):
        if k in s:
            rec[k] = s[k]
    # Every key of the summary, flattened as sweep.csv's columns (the behaviour's own numbers among them).
    rec["summary"] = {k: v for k, v in summary_keys.flatten(s).items() if _cell(v) is not None}
    rec["command"] = command_text(r.cmd)
    rec["record_command"] = record_command(r.cmd, r.index)
    return rec


def journal_record(r: Run) -> dict[str, Any]:
    """runs.jsonl's line: the run's record, and what it takes to count it again unrun (sweep_journal.py)."""
    return {**run_record(r), "severity": r.severity, "full_summary": r.summary}


def restore(run: Run, rec: dict[str, Any]) -> None:
    """A run of the plan, as its journal record says it ended. Raises SweepError if the record is of another
    command (the grid, the build's path or a file name changed since)."""
    if rec["command"] != command_text(run.cmd):
        raise SweepError(f"run {run.index} of the grid is now `{command_text(run.cmd)}` but the journal has "
                         f"`{rec['command']}`: not the same grid (or not run from the same folder)")
    run.success, run.reason, run.exit_code = bool(rec.get("success")), str(rec.get("reason", "")), rec.get("exit_code")
    run.wall, run.severity, run.retries = rec.get("wall_seconds"), int(rec.get("severity", 9)), int(rec.get("retries", 0))
    run.summary = rec["full_summary"] if isinstance(rec["full_summary"], dict) else None


def results(runs: Sequence[Run], opts: argparse.Namespace, grid: dict[str, Any], started: str, wall: float,
            interrupted: bool, worst_n: int) -> dict[str, Any]:
    finished = [r for r in runs if r.reason != "not run" and r.reason != "interrupted"]
    # The behaviour's own numbers (its states and telemetry at the end, an experiment's metrics) and the keys the
    # --expect expressions name: their medians per group, and the table's columns.
    own = summary_keys.behaviour_columns((r.summary for r in finished), (k for r in finished for k in r.declared))
    behaviour_keys = list(dict.fromkeys([e.key for e in expressions(opts)] + own))
    by: dict[str, Any] = {}
    keys: tuple[tuple[str, Callable[[Run], str]], ...] = (
        ("by_scenario", lambda r: r.scenario), ("by_shape", lambda r: r.shape_name),
        ("by_kills", lambda r: r.schedule.text), ("by_robots", lambda r: str(r.robots)),
        ("by_params", lambda r: param_label(r.params)), ("by_fields", lambda r: sweep_fields.label(r.fields)))
    for name, key in keys:
        groups: dict[str, list[Run]] = {}
        for r in finished:
            groups.setdefault(key(r), []).append(r)
        by[name] = {k: group_stats(v, behaviour_keys) for k, v in groups.items()}
    cells: dict[tuple[str, str, int, str, str, str], list[Run]] = {}
    for r in finished:
        cells.setdefault((r.scenario, r.shape_name, r.robots, r.schedule.text, param_label(r.params),
                          sweep_fields.label(r.fields)), []).append(r)
    by["by_cell"] = [dict(scenario=k[0], shape=k[1], robots=k[2], kills=k[3], params=k[4], fields=k[5],
                          **group_stats(v, behaviour_keys))
                     for k, v in cells.items()]
    ordered = sorted(finished, key=worst_key(opts))
    overall = group_stats(finished, behaviour_keys)
    return {
        "format": "swarmform-sweep", "version": 1,
        "commit": places.commit(), "cwd": os.getcwd(), "started_utc": started, "wall_seconds": round(wall, 1),
        "interrupted": interrupted, "planned_runs": len(runs),
        "grid": grid,
        "judging": {"expect": outcome_word(opts), "expressions": [e.text for e in expressions(opts)],
                    "behaviour_keys": behaviour_keys, "max_shape_error": opts.max_shape_error,
                    "max_contacts": opts.max_contacts, "max_robot_contacts": opts.max_robot_contacts,
                    "timeout_seconds": opts.timeout},
        "overall": overall,
        **by,
        "worst": [run_record(r) for r in ordered[:worst_n]],
    }


def _opt(value: Optional[float]) -> str:
    return "-" if value is None else f"{value:g}"


PAPER_COLUMNS = (("formed@", "median_formation_tick", ".0f"), ("goal@", "median_goal_tick", ".0f"),
                 ("err@form", "max_shape_error_at_formation", ".3f"), ("err@goal", "max_shape_error_at_goal", ".3f"))
PAPER_KEYS = {"formation_tick", "goal_tick", "shape_error_at_formation", "shape_error_at_goal"}


def print_table(res: dict[str, Any], out: Callable[[str], None] = print) -> None:
    """One row per cell: its grid coordinates, successes, then the paper's formation and goal columns when a run
    had them, and the medians of the behaviour's own numbers (and of the --expect keys), the first few of them."""
    cells = res["by_cell"]

    def f(v: Any, fmt: str) -> str:
        return "-" if not isinstance(v, (int, float)) or isinstance(v, bool) else format(v, fmt)

    paper = [c for c in PAPER_COLUMNS if any(cell.get(c[1]) is not None for cell in cells)]
    own = list(res["judging"].get("behaviour_keys") or [])
    # The keys the paper's columns show already are not shown twice.
    shown_own = [k for k in own if not paper or k not in PAPER_KEYS][:BEHAVIOUR_COLUMNS_SHOWN]
    with_params = any(c.get("params", "defaults") != "defaults" for c in cells)
    with_fields = any(c.get("fields", "scenario") != "scenario" for c in cells)
    head = ["scenario", "shape", "N", "kills"] + (["params"] if with_params else []) + \
        (["fields"] if with_fields else []) + ["ok", "rate"] + [h for h, _, _ in paper] + shown_own + ["contacts"]
    rows: list[list[str]] = []
    for c in cells:
        row = [os.path.basename(c["scenario"]), c["shape"], str(c["robots"]), c["kills"]]
        row += ([c["params"]] if with_params else []) + ([c["fields"]] if with_fields else [])
        row += [f"{c['succeeded']}/{c['runs']}", f"{100 * c['success_rate']:.0f}%" if c["runs"] else "-"]
        row += [f(c.get(key), fmt) for _, key, fmt in paper]
        row += [f((c.get("medians") or {}).get(key), ".4g") for key in shown_own]
        row.append(f"{c['contacts_robot_robot']}+{c['contacts_robot_obstacle']}")
        rows.append(row)
    widths = [max(len(h), *(len(r[i]) for r in rows)) if rows else len(h) for i, h in enumerate(head)]
    out("  ".join(h.ljust(w) for h, w in zip(head, widths)))
    for r in rows:
        out("  ".join(v.ljust(w) for v, w in zip(r, widths)))
    o = res["overall"]
    rate = "-" if o["success_rate"] is None else f"{100 * o['success_rate']:.1f}%"
    judged = res["judging"]["expect"]
    if res["judging"].get("expressions"):
        judged += " and " + " and ".join(f"'{e}'" for e in res["judging"]["expressions"])
    medians = (f"; medians formed@ {_opt(o['median_formation_tick'])} goal@ {_opt(o['median_goal_tick'])}"
               if paper else "")
    out(f"overall: {o['succeeded']}/{o['runs']} succeeded ({rate}); expect {judged}{medians}; commit {res['commit']}")
    notes = []
    if paper:
        notes.append("formed@/goal@: median ticks; err@: largest shape error, grid units")
    if shown_own:
        more = f"; {len(own) - len(shown_own)} more in sweep.json" if len(own) > len(shown_own) else ""
        notes.append(f"{', '.join(shown_own)}: medians{more}")
    notes.append("contacts: robot-robot+robot-obstacle")
    out(f"({'; '.join(notes)})")
    bad = [w for w in res["worst"] if not w["success"]][:WORST_SHOWN]
    if bad:
        out("worst failures (every one in sweep.json's worst / sweep.csv):")
        for w in bad:
            out(f"  #{w['index']} {w['reason']}")
            out(f"     {w['command']}")


# ------------------------------------------------------------------------------------------------- the sweep

def default_out_dir() -> str:
    runs = places.runs_root()
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%d-%H%M%S")
    path, n = os.path.join(runs, f"sweep-{stamp}"), 1
    while os.path.exists(path):
        n += 1
        path = os.path.join(runs, f"sweep-{stamp}-{n}")
    return path


def plan(opts: argparse.Namespace, exe: str) -> tuple[list[Run], dict[str, Any]]:
    """The runs of the grid, after probing every (scenario, shape, robots) once. Raises SweepError."""
    scenarios = expand_files(opts.scenario or [places.default_scenario()], "scenario")
    shapes: list[Optional[str]] = list(expand_files(opts.shape, "shape")) if opts.shape else []
    if opts.shapes_dir:
        if not os.path.isdir(opts.shapes_dir):
            raise SweepError(f"--shapes-dir '{opts.shapes_dir}': no such folder")
        found = sorted(glob.glob(os.path.join(opts.shapes_dir, "*.txt")))
        if not found:
            raise SweepError(f"--shapes-dir '{opts.shapes_dir}': no *.txt shape in it")
        shapes += [s for s in found if s not in shapes]
    shapes = shapes or [None]
    robots_list = opts.robots or [None]
    seeds = list(dict.fromkeys(opts.seeds or list(range(1, 11))))
    schedules = list({s.text: s for s in (opts.kills or [parse_kill_schedule("none")])}.values())
    params: list[tuple[str, ParamValues]] = list(getattr(opts, "param", None) or [])
    seen: set[str] = set()
    for name, _ in params:
        if name in seen:
            raise SweepError(f"--param {name} is given twice (one flag per parameter: NAME=V1,V2,...)")
        seen.add(name)
    combos = param_combinations(params)
    check_judging(opts)
    try:
        fields = sweep_fields.FieldGrid(sweep_fields.once(getattr(opts, "loss", None), "--loss"),
                                        sweep_fields.once(getattr(opts, "burst", None), "--burst"),
                                        sweep_fields.once(getattr(opts, "noise", None), "--noise"),
                                        getattr(opts, "set", None) or [])
        fields.check()
    except ValueError as e:
        raise SweepError(str(e)) from None
    field_combos = fields.combinations()
    plugin_dirs = list(getattr(opts, "plugin_dir", None) or [])
    for d in plugin_dirs:
        if not os.path.isdir(d):
            raise SweepError(f"--plugin-dir '{d}': no such folder")
    program: Optional[str] = getattr(opts, "exec", None)
    if program is not None:
        given = [f for f in sweep_exec.REFUSED if getattr(opts, f[2:], None)]
        if given:
            raise SweepError(f"{', '.join(given)} with --exec: `swarm run` has no such flag (sweep_exec.py); give "
                             "each radio as a scenario file instead")

    def check(scenario: str, shape: Optional[str], robots: Optional[int], params: Optional[Combo] = None,
              field_flags: Sequence[str] = ()) -> dict[str, Any]:
        if program is not None:
            return probe_exec(opts, scenario, shape, robots, params, plugin_dirs)
        return probe(exe, scenario, shape, robots, params, plugin_dirs, field_flags)

    runs: list[Run] = []
    for scenario in scenarios:
        # Each value once per scenario (its behaviour decides): an unknown name or a value out of bounds is said
        # before anything long starts. The first shape and robot count stand for the rest.
        for name, values in params:
            for text, value in values:
                check(scenario, shapes[0], robots_list[0], {name: (text, value)})
        # Each scenario-field value once per scenario (the loader checks it as it checks the file's fields).
        singles = {(f[i], f[i + 1]) for _, f in field_combos for i in range(0, len(f), 2)}
        for flag in sorted(singles):
            check(scenario, shapes[0], robots_list[0], combos[0], flag)
        window_cap = opts.max_ticks or scenario_max_ticks(scenario)
        window = min(opts.kill_window, window_cap)
        for schedule in schedules:
            late = [f"{rid}@{tick}" for rid, tick in schedule.kills if tick > window_cap]
            if late:
                raise SweepError(f"--kills {schedule.text}: {', '.join(late)} after the run's last tick (max_ticks "
                                 f"{window_cap} of {scenario}): it would never happen")
        for shape in shapes:
            for robots in robots_list:
                # With the grid's first parameters: they may decide whether the scenario loads (shape_heading
                # turns the shape, and the loader checks that it fits).
                info = check(scenario, shape, robots, combos[0], field_combos[0][1])
                # Every --expect key against what this scenario's runs' summaries will hold, before any run: the
                # summary_template of `swarm_inprocess --check` (summary_keys.py); with --exec, the probe's summary.
                declared: list[str] = []
                if program is None:
                    described = check_info(exe, scenario, shape, robots, combos[0], plugin_dirs, field_combos[0][1])
                    series = [f["key"] for f in summary_keys.declared_summary(described) if f.get("kind") == "series"]
                    keys = summary_keys.declared_keys(described["summary_template"], series)
                    declared = summary_keys.number_keys(described)
                else:
                    keys = summary_keys.declared_keys(info, summary_keys.SERIES_KEYS)
                bad = expect.check_declared(expressions(opts), keys)
                if bad:
                    raise SweepError("--expect " + "\n--expect ".join(bad) + f"\n(the probe of {scenario}; "
                                     "nothing was run)")
                n = info["robots"]
                shape_name = os.path.basename(str(info.get("shape_file") or shape or "")) or "-"
                for combo, (field_labels, field_flags) in itertools.product(combos, field_combos):
                    for schedule in schedules:
                        for seed in seeds:
                            flags = schedule.flags(seed, n, window)
                            cmd = base_command(exe, scenario, shape, robots, seed, opts.max_ticks, plugin_dirs)
                            if program is not None:
                                cmd = sweep_exec.as_run(cmd, program, opts.exec_timeout)
                            for k in flags:
                                cmd += ["--kill", k]
                            # A restart after the run's last tick would never happen (and is refused): left out.
                            for f in schedule.restart_flags(flags, window_cap):
                                cmd += ["--fault", f]
                            cmd += param_flags(combo) + field_flags
                            if program is None:
                                cmd += ["--no-record", "--quiet"]
                            runs.append(Run(len(runs), scenario, shape, shape_name, robots, n, seed, schedule,
                                            flags, opts.max_ticks, cmd, combo, field_labels))
                            runs[-1].real_processes = program is not None
                            runs[-1].declared = declared
    grid = {"scenarios": scenarios, "shapes": [s or "(the scenario's)" for s in shapes],
            "robots": [r or "(the scenario's)" for r in robots_list], "seeds": _ranges(seeds),
            "seed_count": len(seeds), "kills": [s.text for s in schedules], "kill_window": opts.kill_window,
            "max_ticks": opts.max_ticks, "plugin_dirs": plugin_dirs, "exec": program,
            "params": {name: [v for _, v in values] for name, values in params},
            "param_combinations": len(combos), "fields": fields.grid(), "field_combinations": len(field_combos),
            "field_columns": fields.columns()}
    return runs, grid


def _ranges(seeds: Sequence[int]) -> str:
    """[1,2,3,7] -> '1-3,7'."""
    parts: list[str] = []
    i = 0
    while i < len(seeds):
        j = i
        while j + 1 < len(seeds) and seeds[j + 1] == seeds[j] + 1:
            j += 1
        parts.append(str(seeds[i]) if i == j else f"{seeds[i]}-{seeds[j]}")
        i = j + 1
    return ",".join(parts)


def _relative_exe() -> str:
    exe = launcher.executable("inprocess")
    rel = os.path.relpath(exe)
    return rel if not rel.startswith("..") else exe


def _grid_flags_given(opts: argparse.Namespace) -> list[str]:
    """The grid's flags set on this command line (--resume and --merge take the grid from the folders)."""
    from . import cli  # the parser's defaults; cli imports this module lazily
    defaults = cli.parse_sweep_args([])
    return sorted(f"--{k.replace('_', '-')}" for k, v in vars(opts).items()
                  if k not in ("resume", "merge", "jobs", "quiet", "out", "argv", "command", "cluster", "plot",
                               "plot_metric")
                  and v != getattr(defaults, k, None))


def _saved_opts(sweep_dir: str) -> tuple[argparse.Namespace, dict[str, Any]]:
    """The options a sweep folder was started with. Raises SweepError."""
    from . import cli
    try:
        saved = sweep_journal.load_args(sweep_dir)
    except sweep_journal.JournalError as e:
        raise SweepError(str(e)) from None
    try:
        return cli.parse_sweep_args(saved["argv"]), saved
    except SystemExit:
        raise SweepError(f"{sweep_dir}/{sweep_journal.ARGS_FILE}: its command line no longer parses "
                         "(written by another version of swarm?)") from None


def _restored(runs: Sequence[Run], sweep_dir: str) -> int:
    """Fills the runs that sweep_dir's journal finished; returns how many. Raises SweepError."""
    try:
        records = sweep_journal.finished_runs(sweep_dir)
    except sweep_journal.JournalError as e:
        raise SweepError(str(e)) from None
    n = 0
    for run in runs:
        if run.index in records:
            restore(run, records[run.index])
            n += 1
    return n


def _write(out_dir: str, runs: Sequence[Run], res: dict[str, Any], grid: dict[str, Any]) -> int:
    write_csv(os.path.join(out_dir, "sweep.csv"), [r for r in runs if r.reason not in ("not run", "interrupted")],
              list(grid["params"]), grid["field_columns"])
    with open(os.path.join(out_dir, "sweep.json"), "w") as f:
        json.dump(res, f, indent=1)
        f.write("\n")
    print_table(res)
    print(f"sweep.csv and sweep.json in {out_dir}")
    return EXIT_OK if res["overall"]["failed"] == 0 else EXIT_FAILED


def _slice_wall(sweep_dir: str) -> float:
    try:
        with open(os.path.join(sweep_dir, "sweep.json"), "rb") as f:
            return float(json.loads(f.read().decode("utf-8")).get("wall_seconds") or 0.0)
    except (OSError, UnicodeDecodeError, ValueError, TypeError, AttributeError):
        return 0.0  # a slice that never finished writing: its runs are in its journal all the same


def merge(opts: argparse.Namespace, exe: str) -> int:
    """`swarm sweep --merge DIR...`: the slices of one grid (--shard K/N, all N of them) as the one sweep."""
    dirs: list[str] = opts.merge
    given = _grid_flags_given(opts)
    if given:
        raise SweepError(f"--merge takes the grid from the slices' {sweep_journal.ARGS_FILE}: give no "
                         f"{', '.join(given)}")
    first, saved0 = _saved_opts(dirs[0])
    n = saved0["shard"][1] if saved0["shard"] else 0
    seen: dict[int, str] = {}
    for d in dirs:
        o, saved = _saved_opts(d)
        if saved["argv"] != saved0["argv"] or saved["commit"] != saved0["commit"]:
            raise SweepError(f"{d} is a slice of another sweep than {dirs[0]} (grid {shlex.join(saved['argv'])} "
                             f"at commit {saved['commit']}, against {shlex.join(saved0['argv'])} at "
                             f"{saved0['commit']})")
        if not saved["shard"] or saved["shard"][1] != n:
            raise SweepError(f"{d}: not a slice K/{n} (--shard {saved['shard'] or 'none'})")
        k = saved["shard"][0]
        if k in seen:
            raise SweepError(f"{d} and {seen[k]} are both slice {k}/{n}")
        seen[k] = d
    missing = [str(k) for k in range(1, n + 1) if k not in seen]
    if missing:
        raise SweepError(f"slice(s) {', '.join(missing)} of {n} not given: every slice is needed")
    first.jobs, first.quiet = opts.jobs, opts.quiet
    runs, grid = plan(first, exe)
    for k, d in seen.items():
        _restored([r for r in runs if sweep_journal.in_shard(r.index, (k, n))], d)
    unfinished = [r.index for r in runs if r.reason == "not run"]
    if unfinished:
        raise SweepError(f"{len(unfinished)} run(s) of the grid are in no slice's journal (first: index "
                         f"{unfinished[0]}): finish their slices with --resume first")
    out_dir = opts.out or default_out_dir()
    os.makedirs(out_dir, exist_ok=True)
    opts.written_to = out_dir  # for --plot
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    res = results(runs, first, grid, started, 0.0, False, first.worst)
    res["wall_seconds"] = max((_slice_wall(d) for d in dirs), default=None)  # the slowest slice's
    res["merged_from"] = [os.path.abspath(seen[k]) for k in sorted(seen)]
    res["commit"] = saved0["commit"]
    return _write(out_dir, runs, res, grid)


def sweep(opts: argparse.Namespace) -> int:
    """`swarm sweep`. Returns the exit code."""
    try:
        exe = _relative_exe()
    except launcher.LaunchError as e:
        print(f"swarm sweep: {e}", file=sys.stderr)
        return EXIT_FAILED
    try:
        if opts.merge:
            return merge(opts, exe)
        shard: Optional[tuple[int, int]] = opts.shard
        if opts.resume:
            given = _grid_flags_given(opts)
            if given:
                raise SweepError(f"--resume takes the grid from {opts.resume}/{sweep_journal.ARGS_FILE}: give no "
                                 f"{', '.join(given)}")
            resumed, saved = _saved_opts(opts.resume)
            for how in ("jobs", "quiet", "cluster", "resume"):  # how it runs now, not which runs
                setattr(resumed, how, getattr(opts, how))
            resumed.out = opts.resume
            shard = tuple(saved["shard"]) if saved["shard"] else None  # type: ignore[assignment]
            opts = resumed
        runs, grid = plan(opts, exe)
        planned = len(runs)
        runs = [r for r in runs if sweep_journal.in_shard(r.index, shard)]
        out_dir = opts.out or default_out_dir()
        os.makedirs(out_dir, exist_ok=True)
        opts.written_to = out_dir  # for --plot
        finished = _restored(runs, out_dir) if opts.resume else 0
    except SweepError as e:
        print(f"swarm sweep: {e}", file=sys.stderr)
        return EXIT_BAD_INPUT
    client = None
    if getattr(opts, "cluster", None):
        try:
            sweep_cluster.relative_cwd()
            client = sweep_cluster.connect(opts.cluster)
        except sweep_cluster.ClusterError as e:
            print(f"swarm sweep: {e}", file=sys.stderr)
            return EXIT_FAILED
    if not opts.resume:
        sweep_journal.save_args(out_dir, getattr(opts, "argv", []), shard, places.commit(), planned)
    todo = [r for r in runs if r.reason == "not run"]
    jobs = opts.jobs or os.cpu_count() or 1
    progress = Progress(len(todo), quiet=opts.quiet)
    progress.line(f"sweep: {len(runs)} runs ({len(grid['scenarios'])} scenario(s) x {len(grid['shapes'])} shape(s)"
                  f" x {len(grid['robots'])} robot count(s) x {grid['seed_count']} seed(s) x "
                  f"{len(grid['kills'])} kill schedule(s)"
                  + (f" x {grid['param_combinations']} parameter combination(s)" if grid["params"] else "")
                  + (f" x {grid['field_combinations']} field combination(s)" if grid["fields"] else "")
                  + (f"; slice {shard[0]}/{shard[1]} of {planned}" if shard else "")
                  + (f"; {finished} finished before, {len(todo)} to run" if opts.resume else "")
                  + (f"), on the workers of {opts.cluster}" if client is not None else f"), {jobs} at a time")
                  + f"; results in {out_dir}")
    stop = launcher.StopFlag()
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    t0 = time.monotonic()
    cluster: Optional[dict[str, Any]] = None
    try:
        with open(os.path.join(out_dir, sweep_journal.JOURNAL_FILE), "a" if opts.resume else "w") as journal:
            if client is not None:
                cluster = execute_on_cluster(client, todo, opts, progress, stop, journal)
            else:
                execute(todo, jobs, opts.timeout, progress, stop, opts, journal)
    finally:
        stop.restore()
        if client is not None:
            client.close()
    progress.end()
    interrupted = bool(stop)
    res = results(runs, opts, grid, started, time.monotonic() - t0, interrupted, opts.worst)
    if cluster is not None:
        res["cluster"] = cluster
    if shard:
        res["shard"] = {"k": shard[0], "n": shard[1], "grid_runs": planned}
    code = _write(out_dir, runs, res, grid)
    if interrupted:
        print(f"swarm sweep: interrupted after {res['overall']['runs']} of {len(runs)} runs; go on with "
              f"`swarm sweep --resume {out_dir}`", file=sys.stderr)
        return EXIT_INTERRUPTED
    return code
