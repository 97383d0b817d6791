#!/usr/bin/env python3
"""Judges a run directory (robots.csv, world.json, summary.json) by issue 17's arrival rule, from the truth.

Until the world's own judgement lands (world_server/run/metrics_tracker: best assignment over a rigid fit, at
rest, centroid within goal.radius), this approximates it for the motion engineer's sweeps: the assignment is
the robots' own labels (an upper bound of the best assignment's error), the fit a proper rigid one (Kabsch),
"at rest" = every live labelled robot within 5 mm of one point for the last 10 ticks.

  judge_run.py RUN_DIR [RUN_DIR...]   prints one line of key=value per run
"""
import csv
import json
import math
import sys

REST_RADIUS = 0.005
REST_TICKS = 10
FORMED_ERROR = 0.1


def places_of(world):
    shape = world["shape"]
    rows, cols, cells = shape["rows"], shape["cols"], shape["cells"]
    g = world["grid_spacing"]
    places = {}
    for r in range(rows):
        for c in range(cols):
            label = cells[r * cols + c]
            if label >= 0:
                places[label] = (c * g, -r * g)
    return places


def rigid_error(pairs, spacing):
    """RMS distance after the best proper rigid fit of places onto robots, in grid units."""
    n = len(pairs)
    if n < 2:
        return 0.0
    px = sum(p[0][0] for p in pairs) / n
    py = sum(p[0][1] for p in pairs) / n
    rx = sum(p[1][0] for p in pairs) / n
    ry = sum(p[1][1] for p in pairs) / n
    dot = cross = 0.0
    for (a, b) in pairs:
        ax, ay = a[0] - px, a[1] - py
        bx, by = b[0] - rx, b[1] - ry
        dot += ax * bx + ay * by
        cross += ax * by - ay * bx
    th = math.atan2(cross, dot)
    c, s = math.cos(th), math.sin(th)
    err = 0.0
    for (a, b) in pairs:
        ax, ay = a[0] - px, a[1] - py
        fx, fy = c * ax - s * ay + rx, s * ax + c * ay + ry
        err += (fx - b[0]) ** 2 + (fy - b[1]) ** 2
    return math.sqrt(err / n) / spacing


def judge(run_dir):
    world = json.load(open(f"{run_dir}/world.json"))
    summary = json.load(open(f"{run_dir}/summary.json"))
    places = places_of(world)
    gx, gy, gr = world["goal"]["x"], world["goal"]["y"], world["goal"]["radius"]
    spacing = world["grid_spacing"]
    step = world["max_speed"] / world["tick_rate"]
    anchor = {}  # id -> (x, y, since)
    motion_start = None
    minimum = None
    peak = 0.0
    goal_tick = None
    at_goal = None
    last = None
    with open(f"{run_dir}/robots.csv") as f:
        rd = csv.reader(f)
        next(rd)
        rows = []
        tick = None

        def finish(t, rows):
            nonlocal motion_start, minimum, peak, goal_tick, at_goal, last
            pairs = []
            at_rest = True
            in_motion = False
            for (rid, x, y, alive, state, label) in rows:
                if not alive:
                    anchor.pop(rid, None)
                    continue
                a = anchor.get(rid)
                if a is None or math.hypot(x - a[0], y - a[1]) > REST_RADIUS:
                    anchor[rid] = a = (x, y, t)
                if state == 5:
                    in_motion = True
                if label in places:
                    pairs.append((places[label], (x, y)))
                    if t < a[2] + REST_TICKS:
                        at_rest = False
            if not pairs:
                return
            cx = sum(p[1][0] for p in pairs) / len(pairs)
            cy = sum(p[1][1] for p in pairs) / len(pairs)
            dist = math.hypot(cx - gx, cy - gy)
            err = rigid_error(pairs, spacing)
            if motion_start is None and in_motion:
                motion_start = t
                minimum = max(0.0, dist - gr) / step
            if motion_start is not None and goal_tick is None:
                peak = max(peak, err)
            if goal_tick is None and motion_start is not None and at_rest and err <= FORMED_ERROR and dist <= gr:
                goal_tick = t
                at_goal = (err, dist)
            last = (t, err, dist, at_rest)

        for row in rd:
            t = int(row[0])
            if t != tick:
                if tick is not None:
                    finish(tick, rows)
                rows = []
                tick = t
            rows.append((int(row[1]), float(row[2]), float(row[3]), row[5] == "1", int(row[6]), int(row[7])))
        if rows:
            finish(tick, rows)
    out = {
        "run": run_dir,
        "motion_start": motion_start,
        "goal": goal_tick,
        "motion_ticks": (goal_tick - motion_start) if goal_tick is not None and motion_start is not None else None,
        "minimum": round(minimum) if minimum is not None else None,
        "ratio": round((goal_tick - motion_start) / minimum, 3) if goal_tick and minimum else None,
        "peak": round(peak, 3),
        "err_at_goal": round(at_goal[0], 3) if at_goal else None,
        "end_err": round(last[1], 3) if last else None,
        "end_dist": round(last[2], 2) if last else None,
        "contacts_obs": summary.get("collisions_robot_obstacle"),
        "contacts_rr": summary.get("collisions_robot_robot"),
        "ticks": summary.get("ticks"),
    }
    return out


def main():
    for d in sys.argv[1:]:
        r = judge(d)
        print(" ".join(f"{k}={v}" for k, v in r.items()))


if __name__ == "__main__":
    main()
