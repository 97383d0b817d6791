#!/usr/bin/env python3
"""Aggregation with avoidance: a swarmform behaviour in Python, standard library only, run by robot_agent
--exec over the JSON line protocol (docs/agent-protocol.md).

Each tick the robot broadcasts one byte (so its neighbours hear it and get its range and bearing), steers
towards the centroid of the neighbours it heard, keeps `spacing` metres from the nearest one, turns away
from obstacles its ultrasonic sensors see, and random-walks when it hears nobody.

aggregation.json beside it describes the behaviour to the world (docs/agent-protocol.md, "The descriptor
file"): its name, its parameters with their bounds (the world checks the scenario's `behaviour: {params:}`
against them before the run), its states (alone, gathering, spaced, avoiding: the command's "state", named in
robots.csv-derived reports, world.json and events.jsonl, and coloured in the pictures) and its telemetry column
(neighbours heard). The parameters arrive in the hello's "params" (only those the scenario sets); the others
take the descriptor's defaults, read here from the same file.

    scripts/swarm run --scenario examples/agents/aggregation.yaml --exec 'python3 examples/agents/aggregation.py'

Debugging output goes to stderr (the agent's log, logs/agent-K.log); stdout carries the protocol only.
"""

import json
import math
import os
import random
import sys

PROTOCOL = 1
WHEEL_SPACING = 0.1054  # m, Khepera IV (common/types.hpp)
DESCRIPTOR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "aggregation.json")
# The states of aggregation.json, as the command's "state" reports them.
ALONE, GATHERING, SPACED, AVOIDING = 0, 1, 2, 3


def parameters(hello):
    """The hello's params over the descriptor's defaults (the world has checked them against its bounds)."""
    with open(DESCRIPTOR) as f:
        values = {p["name"]: float(p["default"]) for p in json.load(f)["params"]}
    for name, value in hello.get("params", {}).items():
        if name not in values:
            raise ValueError(f"parameter {name!r} is not in {DESCRIPTOR}")
        values[name] = float(value)
    return values


def wheels(v, w, limit):
    """Forward speed v (m/s) and turn rate w (rad/s) to wheel speeds, scaled down to the speed limit."""
    left, right = v - w * WHEEL_SPACING / 2, v + w * WHEEL_SPACING / 2
    scale = max(1.0, abs(left) / limit, abs(right) / limit)
    # Clamped as well: the division can land one rounding step above the limit, which the world counts as a
    # clamped command.
    return (max(-limit, min(limit, left / scale)), max(-limit, min(limit, right / scale)))


class Aggregation:
    def __init__(self, hello):
        p = parameters(hello)
        self.spacing, self.gain, self.obstacle = p["spacing"], p["gain"], p["obstacle"]
        self.limit = float(hello["max_speed"])
        self.rng = random.Random(int(hello["seed"]) * 1000003 + int(hello["robot"]))
        self.wander = 0.0  # rad/s, the random walk's current turn rate

    def step(self, p):
        """(left, right, state) for one perception."""
        us = p["ultrasonic"]  # right (-90 deg), front-right, front, front-left, left (+90 deg)
        heard = [(m["range"], m["bearing"]) for m in p["messages"]]
        if min(us[1:4]) < self.obstacle:  # an obstacle ahead: turn on the spot, away from the nearer side
            return (*wheels(0.0, 2.0 if us[1] < us[3] else -2.0, self.limit), AVOIDING)
        if not heard:
            if self.rng.random() < 0.1:
                self.wander = self.rng.uniform(-1.0, 1.0)
            return (*wheels(self.limit, self.wander, self.limit), ALONE)
        # Neighbours in the robot's own frame (x ahead, y to the left).
        cx = sum(r * math.cos(b) for r, b in heard) / len(heard)
        cy = sum(r * math.sin(b) for r, b in heard) / len(heard)
        nearest, bearing = min(heard)
        state = GATHERING
        if nearest < self.spacing:  # too close: move away from the nearest neighbour
            cx, cy = -math.cos(bearing), -math.sin(bearing)
            state = AVOIDING
        elif math.hypot(cx, cy) < self.spacing / 2:
            return 0.0, 0.0, SPACED  # at the centroid: stay
        heading = math.atan2(cy, cx)
        v = self.limit * max(0.0, math.cos(heading))
        return (*wheels(v, self.gain * heading, self.limit), state)


def main():
    hello = json.loads(sys.stdin.readline())
    if hello.get("protocol") != PROTOCOL:
        print(f"aggregation.py: the agent speaks protocol {hello.get('protocol')}, this speaks {PROTOCOL}",
              file=sys.stderr)
        return 2
    print(json.dumps({"type": "hello", "protocol": PROTOCOL, "name": "aggregation_py"}), flush=True)
    behaviour = Aggregation(hello)
    for line in sys.stdin:  # one perception a line, until the agent closes our stdin (the run ended)
        p = json.loads(line)
        left, right, state = behaviour.step(p)
        print(json.dumps({"type": "command", "tick": p["tick"], "left": left, "right": right, "message": "01",
                          "state": state, "telemetry": [len(p["messages"])]}), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
