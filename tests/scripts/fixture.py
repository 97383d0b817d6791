"""A small synthetic run directory in the recording format (docs/recording-format.md), so the reader, the
pictures and the report are tested without the C++ programs.

The story of the synthetic run: 7 robots (6 shape labels and one spare) gather near the origin, take labels
(searching -> moving -> reached -> ready), robot 0 is elected leader, the formation moves towards the goal at
(8, 0) with a wobble that peaks near the obstacle, robot 2 dies on the way (SIGKILL) and robot 6 stays a spare.
"""

import json
import math
import os

SHAPE = [[-1, -1, 0, -1, -1],
         [-1, 1, -1, 2, -1],
         [3, -1, 4, -1, 5]]
SPACING = 1.0
GOAL = (8.0, 0.0, 0.5)
HEADER = "tick,id,x,y,theta,alive,state,label,parent,leader,net_force"


def label_place(label):
    for r, row in enumerate(SHAPE):
        for c, v in enumerate(row):
            if v == label:
                return c * SPACING, -r * SPACING
    raise KeyError(label)


def world_doc(robots):
    return {
        "arena": {"centre": [4.0, 0.0], "width": 20.0, "height": 12.0, "walls": True},
        "obstacles": [
            {"kind": "box", "name": "large", "centre": [4.5, 1.5], "half_extents": [0.6, 0.4], "yaw": 0.3},
            {"kind": "cylinder", "name": "small", "centre": [6.0, -2.0], "radius": 0.25},
        ],
        "goal": {"x": GOAL[0], "y": GOAL[1], "radius": GOAL[2]},
        "grid_spacing": SPACING,
        "comm_range": 3.0,
        "shape": {"rows": len(SHAPE), "cols": len(SHAPE[0]), "cells": [v for row in SHAPE for v in row]},
        "robots": robots,
        "seed": 7,
        "mode": "lockstep",
        "tick_rate": 10.0,
        "robot_radius": 0.0704,
    }


def robot_row(tick, k, ticks, death):
    """(x, y, theta, alive, state, label, parent, leader, force) of robot k at `tick`."""
    form_end, motion_start = ticks * 0.25, ticks * 0.35
    start = (-1.5 + 0.5 * k, -3.5 + 0.3 * (k % 3))
    label = k if k < 6 else -1
    if label < 0:  # the spare: stays searching at its start
        return start[0], start[1], 0.0, 1, 1, -1, -1, 0, 0.0
    px, py = label_place(label)
    px, py = px - 2.0, py + 1.0
    if tick < form_end:
        f = tick / form_end
        x, y = start[0] + (px - start[0]) * f, start[1] + (py - start[1]) * f
        state = 1 if f < 0.2 else 2
        lab = label if f >= 0.2 else -1
    else:
        f = min(1.0, (tick - motion_start) / (ticks - motion_start)) if tick >= motion_start else 0.0
        wobble = 0.3 * math.sin(math.pi * f) * math.sin(1.7 * k)
        x, y = px + f * 7.0, py + wobble
        state = 5 if tick >= motion_start else (3 if tick < (form_end + motion_start) / 2 else 4)
        lab = label
    parent = -1 if label == 0 or lab < 0 else {1: 0, 2: 0, 3: 1, 4: 1, 5: 2}[label]
    leader = 1 if label == 0 and state >= 4 else 0
    force = 0.0 if state != 5 else 0.05 + 0.4 * math.exp(-((x - 4.5) ** 2))
    alive = 1
    if death is not None and k == death[0] and tick >= death[1]:
        alive, force = 0, 0.0
        x, y = robot_row(death[1] - 1, k, ticks, None)[:2]
    return x, y, 0.1 * k, alive, state, lab, parent, leader, force


def summary_doc(ticks=80, robots=7, death=(2, 50)):
    """The synthetic run's summary.json (without the distortion series); the stand-in world_server --check prints
    its keys as the summary_template."""
    return {"robots": robots, "seed": 7, "mode": "lockstep", "ticks": ticks, "wall_seconds": 1.25,
            "ticks_per_second": ticks / 1.25, "alive_at_end": robots - (1 if death else 0),
            "deaths": [{"id": death[0], "tick": death[1]}] if death else [],
            "collisions_robot_robot": 1, "collisions_robot_obstacle": 0,
            "formation_tick": int(ticks * 0.3), "shape_error_at_formation": 0.0,
            "goal_tick": None, "peak_distortion": 0.21, "trajectory_sha256": "ab" * 32,
            "outcome": "formed_not_arrived", "stuck_robots": [3, 5], "stuck_robot_count": 2}


def make_run(run_dir, ticks=80, robots=7, summary=True, distortion=False, death=(2, 50)):
    """Writes a synthetic run directory; returns the list of rows written (as tuples, in file order)."""
    os.makedirs(run_dir, exist_ok=True)
    with open(os.path.join(run_dir, "world.json"), "w") as f:
        json.dump(world_doc(robots), f, indent=1)
    rows, events, prev = [], [], {}
    for t in range(ticks):
        for k in range(robots):
            x, y, th, alive, state, lab, parent, leader, force = robot_row(t, k, ticks, death)
            rows.append((t, k, round(x, 6), round(y, 6), th, alive, state, lab, parent, leader, round(force, 6)))
            if prev.get(k) != state and alive:
                events.append({"tick": t, "kind": "state", "id": k, "state": state})
            prev[k] = state
        if death and t == death[1]:
            events.append({"tick": t, "kind": "death", "id": death[0]})
    with open(os.path.join(run_dir, "robots.csv"), "w") as f:
        f.write(HEADER + "\n")
        for r in rows:
            f.write(",".join(str(v) for v in r) + "\n")
    with open(os.path.join(run_dir, "events.jsonl"), "w") as f:
        for e in events:
            f.write(json.dumps(e) + "\n")
    if summary:
        doc = summary_doc(ticks, robots, death)
        if distortion:
            doc["distortion"] = [[t, 0.01 * (t % 10)] for t in range(int(ticks * 0.3), ticks)]
        with open(os.path.join(run_dir, "summary.json"), "w") as f:
            json.dump(doc, f, indent=1)
    return rows


# --- a run of the Khepera IV's world: a floor, a light, a battery, LEDs --------------------------------------

KHEPERA_TICKS, KHEPERA_ROBOTS = 20, 4
BLUE_DISC = {"kind": "circle", "centre": [-1.5, 1.8], "radius": 0.5, "grey": 0.114, "colour": "#0000ff"}
GREY_BAND = {"kind": "rectangle", "centre": [2.0, -1.0], "half_extents": [1.0, 0.3], "yaw": 0.2, "grey": 0.3,
             "colour": None}
LIGHT = {"position": [3.0, 1.8], "height": 0.3, "intensity": 2.5}
BATTERY = {"capacity": 100.0, "idle": 0.1, "moving": 20.0, "start": 0.8}
GREEN, RED, BLUE, OFF = "#00ff00", "#ff0000", "#0000ff", "#000000"


def khepera_leds(tick, k):
    """robots.csv's leds field of robot k at `tick`: robot 0 green from tick 5, robot 1 red-off-blue always,
    robot 3 green (it dies at tick 10: a dead robot's LEDs are not drawn), robot 2 never lit."""
    if k == 0:
        return f"{GREEN} {GREEN} {GREEN}" if tick >= 5 else ""
    if k == 1:
        return f"{RED} {OFF} {BLUE}"
    if k == 3:
        return f"{GREEN} {OFF} {OFF}"
    return ""


READINGS_COLUMNS = ([f"proximity{k}" for k in range(8)] +
                    ["lidar_rays", "lidar_nearest_angle", "lidar_nearest_range", "battery"])


def khepera_readings(tick, k):
    """readings.csv's values of robot k at `tick` (READINGS_COLUMNS), None for a dead robot (robot 3 after tick 10):
    proximity sensor j reads 0.1 j + 0.01 k, the lidar's 682 rays see nearest 0.5 + 0.01 tick m at 30 degrees,
    the battery 0.8 - 0.01 tick."""
    if k == 3 and tick > 10:
        return None
    return [round(0.1 * j + 0.01 * k, 4) for j in range(8)] + [682, 0.5235987755982988, 0.5 + 0.01 * tick,
                                                              0.8 - 0.01 * tick]


def make_khepera_run(run_dir, floor_image=None, leds=True):
    """Writes a run of 4 robots crossing an 8 m x 6 m arena whose world.json has a grey floor with a blue disc
    and a grey band (and `floor_image`, a PNG path, when given), a light and batteries; robots.csv has the
    `leds` column (khepera_leds) unless `leds` is False (a recording older than it); readings.csv has the
    proximity ring, the lidar and the battery (khepera_readings). Returns world.json's document."""
    os.makedirs(run_dir, exist_ok=True)
    floor = {"grey": 0.9, "colour": None, "regions": json.loads(json.dumps([BLUE_DISC, GREY_BAND])),
             "image": None if floor_image is None else {"file": floor_image, "width": 8, "height": 6}}
    doc = {"format": "swarmform-recording", "version": 1,
           "arena": {"centre": [0.0, 0.0], "width": 8.0, "height": 6.0, "walls": True}, "obstacles": [],
           "goal": None, "grid_spacing": 1.0, "comm_range": 3.0, "robots": KHEPERA_ROBOTS, "seed": 5,
           "mode": "in-process", "tick_rate": 10.0, "robot_radius": 0.0704, "floor": floor, "lights": [LIGHT],
           "battery": BATTERY, "shape": {"rows": 0, "cols": 0, "cells": []}, "behaviour": "phototaxis",
           "behaviour_descriptor": {"name": "phototaxis", "needs_shape": False, "needs_goal": False,
                                    "states": [{"value": 0, "name": "seeking", "colour": "#9e9e9e"}],
                                    "telemetry": [{"name": "light", "doc": "strongest reading"}]}}
    with open(os.path.join(run_dir, "world.json"), "w") as f:
        json.dump(doc, f, indent=1)
    with open(os.path.join(run_dir, "robots.csv"), "w") as f:
        f.write(HEADER + (",leds" if leds else "") + ",light\n")
        for t in range(KHEPERA_TICKS + 1):
            for k in range(KHEPERA_ROBOTS):
                x, y = -1.0 + 0.05 * t, -0.6 + 0.4 * k
                alive = 0 if k == 3 and t > 10 else 1
                led = ("," + khepera_leds(t, k)) if leds else ""
                f.write(f"{t},{k},{x},{y},0.0,{alive},0,-1,-1,0,0{led},{0.01 * t}\n")
    with open(os.path.join(run_dir, "readings.csv"), "w") as f:
        f.write("tick,id," + ",".join(READINGS_COLUMNS) + "\n")
        for t in range(KHEPERA_TICKS + 1):
            for k in range(KHEPERA_ROBOTS):
                values = khepera_readings(t, k)
                cells = [""] * len(READINGS_COLUMNS) if values is None else [repr(v) for v in values]
                f.write(f"{t},{k}," + ",".join(cells) + "\n")
    with open(os.path.join(run_dir, "events.jsonl"), "w") as f:
        f.write(json.dumps({"tick": 10, "kind": "death", "id": 3}) + "\n")
    return doc
