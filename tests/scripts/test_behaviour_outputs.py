"""Outputs that fit the behaviour: a recording of a behaviour with no shape and no goal, with its own
states, colours and a telemetry column (world.json's behaviour_descriptor, docs/recording-format.md), read and
drawn with those, and none of the paper's pictures or metrics."""

import json
import math
import os
import shutil
import tempfile
import unittest

import numpy as np

import helpers  # noqa: F401  (puts scripts/ on the path)
from swarmform import pictures, recording, report

ROBOTS, TICKS = 5, 30
DESCRIPTOR = {
    "name": "gather", "plugin": "/x/libgather.so", "summary": "test", "needs_shape": False, "needs_goal": False,
    "params": [],
    "states": [{"value": 0, "name": "alone", "colour": "#9e9e9e"},
               {"value": 7, "name": "gathered", "colour": "#2e7d32"}],
    "telemetry": [{"name": "neighbours", "doc": "neighbours heard"}],
}


def make_run(d):
    world = {"arena": {"centre": [0, 0], "width": 8, "height": 8, "walls": True}, "obstacles": [],
             "goal": {"x": 10.0, "y": 0.0, "radius": 0.5}, "grid_spacing": 1.0, "comm_range": 3.0,
             "shape": {"rows": 0, "cols": 0, "cells": []}, "robots": ROBOTS, "seed": 1, "mode": "in-process",
             "tick_rate": 10.0, "robot_radius": 0.0704, "behaviour": "gather", "behaviour_descriptor": DESCRIPTOR}
    with open(os.path.join(d, "world.json"), "w") as f:
        json.dump(world, f)
    with open(os.path.join(d, "robots.csv"), "w") as f:
        f.write("tick,id,x,y,theta,alive,state,label,parent,leader,net_force,neighbours\n")
        for t in range(TICKS + 1):
            for k in range(ROBOTS):
                a = 2 * math.pi * k / ROBOTS
                r = 2.0 - 1.5 * t / TICKS
                state = 7 if t > TICKS // 2 else 0
                extra = "" if t == 0 else str(min(t, ROBOTS - 1))  # nobody has reported at tick 0
                f.write(f"{t},{k},{r * math.cos(a)},{r * math.sin(a)},{a},1,{state},-1,-1,0,0,{extra}\n")
    with open(os.path.join(d, "events.jsonl"), "w") as f:
        f.write("")
    summary = {"format": "swarmform-summary", "version": 1, "behaviour": "gather", "robots": ROBOTS,
               "ticks": TICKS, "outcome": "none", "formation_tick": None, "goal_tick": None,
               "shape_error_at_goal": None, "path_length": 0.0, "arrived": 0, "labels": 0,
               "states_at_end": {"alone": 0, "gathered": ROBOTS},
               "telemetry_mean_at_end": {"neighbours": 4.0}, "trajectory_sha256": "ab" * 32}
    with open(os.path.join(d, "summary.json"), "w") as f:
        json.dump(summary, f)


class BehaviourOutputsTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-behaviour-")
        make_run(self.dir)

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_the_recording_carries_the_behaviours_states_columns_and_needs(self):
        rec = recording.load(self.dir)
        w = rec.world
        self.assertEqual(w.behaviour, "gather")
        self.assertEqual(w.states, {0: ("alone", "#9e9e9e"), 7: ("gathered", "#2e7d32")})
        self.assertIsNone(w.shape)  # no shape to draw
        self.assertIsNone(w.goal)   # no goal to draw
        self.assertEqual(list(rec.track.extra), ["neighbours"])
        col = rec.track.extra["neighbours"]
        self.assertEqual(col.shape, (TICKS + 1, ROBOTS))
        self.assertTrue(np.isnan(col[0]).all())  # empty fields: not reported yet
        self.assertEqual(col[-1, 0], ROBOTS - 1)

    def test_pictures_are_the_behaviours_not_the_papers(self):
        rec = recording.load(self.dir)
        out = os.path.join(self.dir, "pictures")
        written = {os.path.basename(p) for p in pictures.render_all(rec, out, animate=False, log=lambda m: None,
                                                                     labels=True)}
        self.assertIn("states.png", written)
        self.assertIn("telemetry.png", written)
        self.assertNotIn("shape_error.png", written)  # no empty placeholder
        self.assertNotIn("residual_force.png", written)
        self.assertTrue(any(n.startswith("snapshot_t") for n in written))

    def test_no_paper_phases_from_a_behaviours_own_state_values(self):
        # Its robots report labels and the values the paper uses for ready (4) and motion (5): they mean other
        # things to this behaviour, so no snapshot is captioned with the paper's phases.
        from swarmform import geometry
        rec = recording.load(self.dir)
        rec.track.state[:] = 5
        rec.track.label[:] = np.arange(ROBOTS)
        self.assertEqual(geometry.phases(rec), {"formation": None, "motion": None, "goal": None})
        captions = [c for _, c in pictures.snapshot_ticks(rec)]
        self.assertNotIn("shape formed", captions)
        self.assertNotIn("motion towards the goal starts", captions)

    def test_the_legend_names_the_behaviours_states(self):
        from swarmform import scene
        handles = scene.legend_handles({0, 7}, recording.load(self.dir).world.states, leaders=False, links=False)
        self.assertEqual([h.get_label() for h in handles], ["alone", "gathered", "dead"])
        self.assertEqual(handles[1].get_markerfacecolor(), "#2e7d32")

    def test_the_report_has_no_paper_metrics(self):
        lines = []
        report.report(self.dir, out=lines.append)
        text = "\n".join(lines)
        self.assertNotIn("not reached", text)
        self.assertNotIn("path length", text)
        self.assertNotIn("shape formed", text)
        self.assertIn("gathered 5", text)
        self.assertIn("neighbours 4", text)
        self.assertIn("outcome", text)


if __name__ == "__main__":
    unittest.main()
