"""`swarm report RUN_DIR`: summary.json as a readable table (or, with --json / --csv, for programs), grouped as a reader asks about a run: what ran, did
the shape form and reach the goal, what failed, what collided. Ticks are also given in simulated seconds.
Keys the table does not know (added to summary.json later) are listed at the end, so nothing is hidden.
"""

import csv
import json
import os
from typing import IO, Any, Callable, Optional, Sequence

from .recording import RecordingError, read_json, read_world, robots_damage

# (group, [(key, label, kind)]); kind: tick, int, float, grid, m, s, tps, text, list
LAYOUT = [
    ("Run", [("scenario", "scenario", "text"), ("shape_file", "shape", "text"), ("behaviour", "behaviour", "text"),
             ("robots", "robots", "int"), ("labels", "shape labels", "int"), ("seed", "seed", "text"),
             ("mode", "mode", "text"), ("ticks", "ticks", "tick"), ("wall_seconds", "wall time", "s"),
             ("ticks_per_second", "ticks per second", "tps"),
             ("robot_ticks_per_second", "robot-ticks per second", "tps"),
             ("alive_at_end", "alive at end", "alive")]),
    ("Outcome", [("outcome", "outcome", "text"), ("stuck_robots", "stuck robots", "list")]),
    ("Formation and motion", [("formation_tick", "shape formed at", "tick"),
                              ("shape_error_at_formation", "shape error at formation", "grid"),
                              ("motion_start_tick", "motion started at", "tick"),
                              ("motion_ticks_minimum", "motion minimum (straight)", "tick"),
                              ("goal_tick", "goal reached at", "tick"),
                              ("shape_error_at_goal", "shape error at goal", "grid"),
                              ("peak_distortion", "peak distortion (motion)", "grid"),
                              ("mean_distortion", "mean distortion (motion)", "grid"),
                              ("path_length", "path length of the centre", "m"),
                              ("arrived", "robots arrived", "int")]),
    ("Faults", [("deaths", "deaths", "list"), ("rejoins", "rejoins", "list"),
                ("leader_changes", "leader changes", "int"), ("fragmentations", "fragmentations", "int"),
                ("graph_rejoins", "graph rejoins", "int"), ("max_components", "most graph components", "int"),
                ("command_verdicts", "commands clamped/dropped", "int")]),
    ("Collisions (contact onsets)", [("collisions_robot_robot", "robot-robot", "int"),
                                     ("collisions_robot_obstacle", "robot-obstacle", "int")]),
    ("Behaviour at the end", [("params", "parameters", "means"),
                              ("states_at_end", "live robots by state", "counts"),
                              ("telemetry_mean_at_end", "telemetry (live mean)", "means")]),
    ("Robot groups", [("groups", "per group", "groups")]),
    ("Reproducibility", [("trajectory_sha256", "trajectory sha256", "text")]),
]
# The paper's metrics: shown only for a behaviour that forms a shape and goes to a goal (world.json's
# behaviour_descriptor); for any other they would read "not reached" for things it never tries.
PAPER_ONLY = {"shape_file", "labels", "stuck_robots", "formation_tick", "shape_error_at_formation",
              "motion_start_tick", "motion_ticks_minimum", "goal_tick", "shape_error_at_goal", "peak_distortion",
              "mean_distortion", "path_length", "arrived", "silent_robots"}
HIDDEN = {"format", "version", "distortion",  # plumbing, or series drawn in the pictures
          "stuck_robot_count"}  # shown with the stuck robots' list


def _fmt(value: Any, kind: str, summary: dict[str, Any], tick_rate: Optional[float]) -> str:
    if value is None:
        return "not reached" if kind in ("tick", "grid") else "-"
    if kind == "tick" and isinstance(value, (int, float)):
        return f"{int(value)}  ({value / tick_rate:.1f} s)" if tick_rate else str(int(value))
    if kind == "grid" and isinstance(value, (int, float)):
        return f"{value:.3f} grid units"
    if kind == "m" and isinstance(value, (int, float)):
        return f"{value:.2f} m"
    if kind == "s" and isinstance(value, (int, float)):
        return f"{value:.2f} s"
    if kind == "tps" and isinstance(value, (int, float)):
        return f"{value:.1f}"
    if kind == "alive" and isinstance(summary.get("robots"), int):
        return f"{value} / {summary['robots']}"
    if kind == "counts" and isinstance(value, dict):
        return ", ".join(f"{name} {count}" for name, count in value.items()) or "none"
    if kind == "means" and isinstance(value, dict):
        return ", ".join(f"{name} {v:.3g}" if isinstance(v, (int, float)) else f"{name} -"
                         for name, v in value.items()) or "none"
    if kind == "groups" and isinstance(value, dict):  # a mixed swarm: a line a group (docs/recording-format.md)
        out = []
        for name, g in value.items():
            if not isinstance(g, dict):
                continue
            first, count = g.get("first_id"), g.get("count")
            ids = f"robots {first}..{first + count - 1}" if isinstance(first, int) and isinstance(count, int) \
                else "robots ?"
            states = _fmt(g.get("states_at_end"), "counts", summary, tick_rate)
            out.append(f"{name}: {g.get('behaviour', '?')}, {ids}, outcome {g.get('outcome', '?')}; "
                       f"live by state {states}")
        return "\n" + "\n".join("    " + line for line in out) if out else "none"
    if kind == "list" and isinstance(value, list):
        if not value:
            return "none"
        items = [f"robot {d.get('id')} at tick {d.get('tick')}" if isinstance(d, dict) else str(d) for d in value]
        return f"{len(value)}: " + ", ".join(items)
    return str(value)


def table(summary: dict[str, Any], tick_rate: Optional[float] = None, title: Optional[str] = None,
          paper_metrics: bool = True) -> list[str]:
    """The report as text lines. paper_metrics False: the paper's formation and motion metrics are left out
    (a behaviour without a shape or a goal)."""
    lines = [title] if title else []
    width = max(len(label) for _, rows in LAYOUT for _, label, _ in rows)
    known = set(HIDDEN) | (set() if paper_metrics else PAPER_ONLY)
    for group, rows in LAYOUT:
        present = [(k, label, kind) for k, label, kind in rows if k in summary and k not in known]
        known.update(k for k, _, _ in rows)
        if not present:
            continue
        lines.append("")
        lines.append(group)
        for key, label, kind in present:
            lines.append(f"  {label:<{width}}  {_fmt(summary[key], kind, summary, tick_rate)}")
    other = [k for k in summary if k not in known]
    if other:
        lines.append("")
        lines.append("Other")
        for key in other:
            lines.append(f"  {key:<{width}}  {_fmt(summary[key], 'text', summary, tick_rate)}")
    return lines


def load_summary(run_dir: str) -> dict[str, Any]:
    """RUN_DIR/summary.json as a dict; RecordingError when it is missing or not valid."""
    path = os.path.join(run_dir, "summary.json")
    if not os.path.isdir(run_dir):
        raise RecordingError(run_dir, None, "not a directory (expected a run directory)")
    if not os.path.exists(path):
        raise RecordingError(path, None, "missing: the run did not finish (it crashed or is still running); "
                                         "`swarm replay` still draws what was recorded")
    summary = read_json(path)
    if not isinstance(summary, dict):
        raise RecordingError(path, 1, "expected a JSON object")
    return summary


def csv_cell(value: Any) -> Optional[str]:
    """A summary value as one CSV cell (the sweep.csv convention); None for what has no cell (a series, an
    object)."""
    from .sweep import _cell  # one convention for both files
    return _cell(value)


def machine_readable(run_dirs: Sequence[str], fmt: str, stream: IO[str]) -> None:
    """--json: the summary (a list of them for several RUN_DIRs), each with run_dir; --csv: a header and one row
    per RUN_DIR, the union of the scalar keys in first-seen order. RecordingError on the first bad RUN_DIR, before
    anything is written."""
    summaries = [(d, load_summary(d)) for d in run_dirs]
    if fmt == "json":
        docs = [dict(s, run_dir=d) for d, s in summaries]
        json.dump(docs[0] if len(docs) == 1 else docs, stream, indent=1)
        stream.write("\n")
        return
    keys: list[str] = []
    for _, s in summaries:
        for k, v in s.items():
            if k not in keys and k != "run_dir" and csv_cell(v) is not None:
                keys.append(k)
    w = csv.writer(stream)
    w.writerow(["run_dir"] + keys)
    for d, s in summaries:
        w.writerow([d] + [csv_cell(s.get(k)) or "" for k in keys])


def damage_lines(run_dir: str) -> list[str]:
    """robots.csv's damage (recording.robots_damage: what `swarm view` says, at the same lines and bytes), one line
    each; none when the run directory has no robots.csv or no usable world.json to count the robots."""
    path = os.path.join(run_dir, "robots.csv")
    world_path = os.path.join(run_dir, "world.json")
    if not os.path.isfile(path):
        return []
    try:
        robots = read_world(world_path).robots if os.path.exists(world_path) else 0
        return [f"damaged recording: {d}" for d in robots_damage(path, robots)]
    except RecordingError as e:
        return [f"damaged recording: {e}"]


def report(run_dir: str, out: Callable[[str], None] = print) -> None:
    """Prints the table, then robots.csv's damage when it has any; raises RecordingError when summary.json is
    missing or not valid (after saying the damage: a killed run's recording is cut, and has no summary)."""
    damage = damage_lines(run_dir) if os.path.isdir(run_dir) else []
    try:
        summary = load_summary(run_dir)
    except RecordingError:
        for line in damage:
            out(line)
        raise
    tick_rate = None
    paper_metrics = True
    world_path = os.path.join(run_dir, "world.json")
    if os.path.exists(world_path):
        try:
            world = read_world(world_path)
            tick_rate = world.tick_rate
            paper_metrics = world.needs_shape and world.needs_goal
        except RecordingError:
            tick_rate = None  # the summary alone is still worth showing
    for line in table(summary, tick_rate, f"swarmform run {run_dir}", paper_metrics):
        out(line)
    for line in damage:
        out(line)
