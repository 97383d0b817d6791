#!/usr/bin/env python3
"""Aggregation with avoidance: a swarmform behaviour in Python, standard library only, run by robot_agent
--exec over the JSON line protocol (docs/agent-protocol.md).

Each tick the robot broadcasts one byte (so its neighbours hear it and get its range and bearing), steers
towards the centroid of the neighbours it heard, keeps `--spacing` metres from the nearest one, turns away
from obstacles its ultrasonic sensors see, and random-walks when it hears nobody. Parameters are its own
flags; the hello's "params" (the scenario's `controller:` values) are not used here.

    scripts/swarm run --scenario examples/agents/aggregation.yaml --exec 'python3 examples/agents/aggregation.py'

Debugging output goes to stderr (the agent's log, logs/agent-K.log); stdout carries the protocol only.
"""

import argparse
import json
import math
import random
import sys

PROTOCOL = 1
WHEEL_SPACING = 0.1054  # m, Khepera IV (common/types.hpp)


def parse_args():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--spacing", type=float, default=0.45, help="distance kept from the nearest neighbour, m")
    p.add_argument("--gain", type=float, default=1.5, help="turning gain towards the target, 1/s")
    p.add_argument("--obstacle", type=float, default=0.35, help="ultrasonic range under which to turn away, m")
    return p.parse_args()


def wheels(v, w, limit):
    """Forward speed v (m/s) and turn rate w (rad/s) to wheel speeds, scaled down to the speed limit."""
    left, right = v - w * WHEEL_SPACING / 2, v + w * WHEEL_SPACING / 2
    scale = max(1.0, abs(left) / limit, abs(right) / limit)
    # Clamped as well: the division can land one rounding step above the limit, which the world counts as a
    # clamped command.
    return (max(-limit, min(limit, left / scale)), max(-limit, min(limit, right / scale)))


class Aggregation:
    def __init__(self, hello, opts):
        self.opts = opts
        self.limit = float(hello["max_speed"])
        self.rng = random.Random(int(hello["seed"]) * 1000003 + int(hello["robot"]))
        self.wander = 0.0  # rad/s, the random walk's current turn rate

    def step(self, p):
        us = p["ultrasonic"]  # right (-90 deg), front-right, front, front-left, left (+90 deg)
        heard = [(m["range"], m["bearing"]) for m in p["messages"]]
        if min(us[1:4]) < self.opts.obstacle:  # an obstacle ahead: turn on the spot, away from the nearer side
            return wheels(0.0, 2.0 if us[1] < us[3] else -2.0, self.limit)
        if not heard:
            if self.rng.random() < 0.1:
                self.wander = self.rng.uniform(-1.0, 1.0)
            return wheels(self.limit, self.wander, self.limit)
        # Neighbours in the robot's own frame (x ahead, y to the left).
        cx = sum(r * math.cos(b) for r, b in heard) / len(heard)
        cy = sum(r * math.sin(b) for r, b in heard) / len(heard)
        nearest, bearing = min(heard)
        if nearest < self.opts.spacing:  # too close: move away from the nearest neighbour
            cx, cy = -math.cos(bearing), -math.sin(bearing)
        elif math.hypot(cx, cy) < self.opts.spacing / 2:
            return 0.0, 0.0  # at the centroid: stay
        heading = math.atan2(cy, cx)
        v = self.limit * max(0.0, math.cos(heading))
        return wheels(v, self.opts.gain * heading, self.limit)


def main():
    opts = parse_args()
    hello = json.loads(sys.stdin.readline())
    if hello.get("protocol") != PROTOCOL:
        print(f"aggregation.py: the agent speaks protocol {hello.get('protocol')}, this speaks {PROTOCOL}",
              file=sys.stderr)
        return 2
    print(json.dumps({"type": "hello", "protocol": PROTOCOL, "name": "aggregation"}), flush=True)
    behaviour = Aggregation(hello, opts)
    for line in sys.stdin:  # one perception a line, until the agent closes our stdin (the run ended)
        p = json.loads(line)
        left, right = behaviour.step(p)
        print(json.dumps({"type": "command", "tick": p["tick"], "left": left, "right": right, "message": "01"}),
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
