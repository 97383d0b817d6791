"""The recording reader: round trip of a synthetic run, and every kind of damage reported as file:line."""

import contextlib
import io
import json
import os
import shutil
import tempfile
import unittest

import numpy as np

import helpers  # noqa: F401  (puts scripts/ on the path)
import fixture
from swarmform import geometry, recording


class RecordingTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-rec-")
        self.rows = fixture.make_run(self.dir, ticks=40, robots=7, death=(2, 30))

    def tearDown(self):
        shutil.rmtree(self.dir)

    def path(self, name):
        return os.path.join(self.dir, name)

    def rewrite(self, name, fn):
        with open(self.path(name)) as f:
            lines = f.read().split("\n")
        with open(self.path(name), "w") as f:
            f.write(fn(lines))

    def test_round_trip_gives_back_every_row(self):
        rec = recording.load(self.dir)
        t = rec.track
        self.assertEqual(t.x.shape, (40, 7))
        self.assertEqual(list(t.ticks), list(range(40)))
        for (tick, rid, x, y, th, alive, state, label, parent, leader, force) in self.rows:
            self.assertAlmostEqual(t.x[tick, rid], x)
            self.assertAlmostEqual(t.y[tick, rid], y)
            self.assertAlmostEqual(t.theta[tick, rid], th)
            self.assertEqual(bool(t.alive[tick, rid]), bool(alive))
            self.assertEqual(t.state[tick, rid], state)
            self.assertEqual(t.label[tick, rid], label)
            self.assertEqual(t.parent[tick, rid], parent)
            self.assertEqual(bool(t.leader[tick, rid]), bool(leader))
            self.assertAlmostEqual(t.net_force[tick, rid], force)
        self.assertEqual(rec.warnings, [])
        self.assertEqual(rec.world.robots, 7)
        self.assertEqual(rec.world.goal, fixture.GOAL)
        self.assertEqual([o.kind for o in rec.world.obstacles], ["box", "cylinder"])
        self.assertEqual(rec.world.shape.label_count(), 6)
        self.assertIn({"tick": 30, "kind": "death", "id": 2}, [{k: v for k, v in e.items() if k != "_line"}
                                                                 for e in rec.events])
        self.assertEqual(rec.summary["deaths"], [{"id": 2, "tick": 30}])

    def test_shape_error_is_zero_for_the_exact_shape_and_grows_with_distortion(self):
        places = {0: (0.0, 0.0), 1: (1.0, 0.0), 2: (0.0, 1.0)}
        # The same triangle rotated by 0.7 rad and moved: a rigid fit removes both.
        import math
        c, s = math.cos(0.7), math.sin(0.7)
        xs = [5 + c * px - s * py for px, py in places.values()]
        ys = [2 + s * px + c * py for px, py in places.values()]
        self.assertAlmostEqual(geometry.shape_error(places, [0, 1, 2], xs, ys, 1.0), 0.0, places=9)
        xs[1] += 0.3
        e = geometry.shape_error(places, [0, 1, 2], xs, ys, 1.0)
        self.assertGreater(e, 0.05)
        places2 = {k: (2 * px, 2 * py) for k, (px, py) in places.items()}  # a grid of spacing 2 m
        self.assertAlmostEqual(geometry.shape_error(places2, [0, 1, 2], [2 * x for x in xs], [2 * y for y in ys],
                                                    2.0), e, places=9)  # in grid units: the same error
        self.assertIsNone(geometry.shape_error(places, [0], [0.0], [0.0], 1.0))

    def test_half_written_last_line_is_dropped_with_a_warning(self):
        with open(self.path("robots.csv"), "a") as f:
            f.write("40,0,1.2")
        rec = recording.load(self.dir)
        self.assertEqual(len(rec.track.ticks), 40)
        self.assertTrue(any("robots.csv:" in w and "half-written" in w for w in rec.warnings), rec.warnings)

    def test_incomplete_last_tick_is_dropped_with_a_warning(self):
        self.rewrite("robots.csv", lambda lines: "\n".join(lines[:-4]) + "\n")  # last tick: 4 of 7 rows
        rec = recording.load(self.dir)
        self.assertEqual(int(rec.track.ticks[-1]), 38)
        self.assertTrue(any("last tick 39 has 4 of 7" in w for w in rec.warnings), rec.warnings)

    def test_corrupt_row_in_the_middle_names_file_and_line(self):
        self.rewrite("robots.csv", lambda lines: "\n".join(lines[:9] + ["3,2,abc,0,0,1,1,2,0,0,0"] + lines[10:]))
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir)
        self.assertTrue(str(cm.exception).startswith(self.path("robots.csv") + ":10: column 'x'"), str(cm.exception))

    def test_nan_positions_are_kept_as_gaps_with_a_warning(self):
        self.rewrite("robots.csv", lambda lines: "\n".join(lines[:11] + ["1,3,nan,inf,0,1,1,3,1,0,0"] + lines[12:]))
        rec = recording.load(self.dir)
        self.assertTrue(any("robots.csv:12: 2 nan/inf value(s)" in w for w in rec.warnings), rec.warnings)
        self.assertTrue(np.isnan(rec.track.x[1, 3]) and np.isnan(rec.track.y[1, 3]))
        d = tempfile.mkdtemp(prefix="swarm-nan-")
        try:  # and the pictures still draw
            from swarmform import pictures
            self.assertEqual(len(pictures.render_all(rec, d, animate=False, log=lambda m: None)), 10)
        finally:
            shutil.rmtree(d)

    def test_row_with_missing_fields_names_the_line(self):
        self.rewrite("robots.csv", lambda lines: "\n".join(lines[:4] + ["0,3,1.0,2.0"] + lines[5:]))
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir)
        self.assertIn("robots.csv:5: expected 11 comma-separated fields, got 4", str(cm.exception))

    def test_missing_rows_in_the_middle_are_an_error(self):
        self.rewrite("robots.csv", lambda lines: "\n".join(lines[:20] + lines[21:]))
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir)
        self.assertIn("has rows for 6 of 7 robots", str(cm.exception))

    def test_ticks_going_backwards_are_an_error(self):
        self.rewrite("robots.csv", lambda lines: "\n".join(lines[:1] + lines[8:15] + lines[1:8] + lines[15:]))
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir)
        self.assertIn("robots.csv:9: tick 0 comes after tick 1", str(cm.exception))

    def test_bad_header(self):
        self.rewrite("robots.csv", lambda lines: "\n".join(["tick,id,x,y"] + lines[1:]))
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir)
        self.assertIn("robots.csv:1: header lacks column(s) theta", str(cm.exception))

    def test_corrupt_world_json_names_the_line(self):
        self.rewrite("world.json", lambda lines: "\n".join(lines[:3] + ["  oops"] + lines[3:]))
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir)
        self.assertIn("world.json:4: not valid JSON", str(cm.exception))

    def test_world_json_with_a_wrong_field(self):
        with open(self.path("world.json")) as f:
            doc = json.load(f)
        doc["obstacles"][1]["kind"] = "pyramid"
        with open(self.path("world.json"), "w") as f:
            json.dump(doc, f)
        with self.assertRaisesRegex(recording.RecordingError, "obstacles\\[1\\].kind: expected 'box' or 'cylinder'"):
            recording.load(self.dir)

    def test_corrupt_event_line_and_truncated_last_event(self):
        with open(self.path("events.jsonl"), "a") as f:
            f.write('{"tick": 39, "ki')
        rec = recording.load(self.dir)
        self.assertTrue(any("events.jsonl" in w for w in rec.warnings))
        self.rewrite("events.jsonl", lambda lines: "\n".join(lines[:2] + ["{not json}"] + lines[2:]))
        with self.assertRaisesRegex(recording.RecordingError, "events.jsonl:3: not valid JSON"):
            recording.load(self.dir)

    def test_missing_files(self):
        os.remove(self.path("summary.json"))
        rec = recording.load(self.dir)
        self.assertIsNone(rec.summary)
        self.assertTrue(any("summary.json: missing" in w for w in rec.warnings))
        os.remove(self.path("robots.csv"))
        with self.assertRaisesRegex(recording.RecordingError, "robots.csv: missing"):
            recording.load(self.dir)
        with self.assertRaisesRegex(recording.RecordingError, "not a directory"):
            recording.load(self.path("nothing-here"))

    def test_phases_come_from_the_states_without_a_summary(self):
        os.remove(self.path("summary.json"))
        ph = geometry.phases(recording.load(self.dir))
        self.assertEqual(ph["motion"], 14)  # fixture: motion from ticks * 0.35
        self.assertIsNotNone(ph["formation"])
        self.assertLessEqual(ph["formation"], ph["motion"])


if __name__ == "__main__":
    unittest.main()


class KheperaRecordingTest(unittest.TestCase):
    """world.json's floor, lights and battery, and robots.csv's LEDs, read back; an older recording without them
    still reads."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-rec-khepera-")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_world_json_gives_back_the_floor_the_lights_and_the_battery(self):
        fixture.make_khepera_run(self.dir, floor_image="/x/floor.png")
        w = recording.load(self.dir).world
        self.assertEqual(w.floor.grey, 0.9)
        self.assertIsNone(w.floor.colour)
        self.assertEqual(w.floor.image, "/x/floor.png")
        self.assertEqual(w.floor.image_size, (8, 6))
        self.assertFalse(w.floor.plain())
        # The name world.json writes now: the run folder's copy, relative to the folder.
        fixture.make_khepera_run(self.dir, floor_image="floor.png")
        self.assertEqual(recording.load(self.dir).world.floor.image, os.path.join(os.path.abspath(self.dir), "floor.png"))
        disc, band = w.floor.regions
        self.assertEqual((disc.kind, disc.centre, disc.radius, disc.colour), ("circle", (-1.5, 1.8), 0.5, "#0000ff"))
        self.assertEqual(disc.face(), "#0000ff")
        self.assertEqual((band.kind, band.centre, band.half_extents, band.yaw), ("rectangle", (2.0, -1.0),
                                                                                 (1.0, 0.3), 0.2))
        self.assertIsNone(band.colour)
        self.assertEqual(band.face(), "#4d4d4d")  # its grey, 0.3
        self.assertEqual(len(w.lights), 1)
        self.assertEqual((w.lights[0].position, w.lights[0].height, w.lights[0].intensity), ((3.0, 1.8), 0.3, 2.5))
        self.assertEqual(w.battery, fixture.BATTERY)

    def test_a_world_json_without_them_is_a_plain_floor_no_light_no_battery(self):
        fixture.make_run(self.dir, ticks=10, robots=3)
        w = recording.load(self.dir).world
        self.assertTrue(w.floor.plain())
        self.assertEqual(w.lights, [])
        self.assertIsNone(w.battery)

    def test_a_bad_floor_region_names_it(self):
        doc = fixture.make_khepera_run(self.dir)
        doc["floor"]["regions"][1]["kind"] = "hexagon"
        with open(os.path.join(self.dir, "world.json"), "w") as f:
            json.dump(doc, f)
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir)
        self.assertIn("floor.regions[1].kind: expected 'circle' or 'rectangle', got 'hexagon'", str(cm.exception))

    def test_robots_csv_gives_back_each_robots_leds_at_each_tick(self):
        fixture.make_khepera_run(self.dir)
        t = recording.load(self.dir).track
        self.assertEqual(t.leds.shape, (fixture.KHEPERA_TICKS + 1, fixture.KHEPERA_ROBOTS, 3, 3))
        for tick in range(fixture.KHEPERA_TICKS + 1):
            for k in range(fixture.KHEPERA_ROBOTS):
                text = fixture.khepera_leds(tick, k)
                want = [[0, 0, 0]] * 3 if not text else [list(bytes.fromhex(c[1:])) for c in text.split(" ")]
                self.assertEqual(t.leds[tick, k].tolist(), want, (tick, k))
        # The behaviour's own column is still its own, after the LEDs.
        self.assertEqual(list(t.extra), ["light"])
        self.assertAlmostEqual(t.extra["light"][7, 2], 0.07)

    def test_robots_csv_without_the_leds_column_reads_with_every_led_off(self):
        fixture.make_khepera_run(self.dir, leds=False)
        t = recording.load(self.dir).track
        self.assertEqual(t.leds.shape, (fixture.KHEPERA_TICKS + 1, fixture.KHEPERA_ROBOTS, 3, 3))
        self.assertFalse(t.leds.any())
        self.assertEqual(list(t.extra), ["light"])

    def test_a_bad_leds_field_names_the_line(self):
        fixture.make_khepera_run(self.dir)
        path = os.path.join(self.dir, "robots.csv")
        with open(path) as f:
            lines = f.read().split("\n")
        lines[6] = lines[6].replace("#ff0000 #000000 #0000ff", "#ff0000 #0000ff")
        with open(path, "w") as f:
            f.write("\n".join(lines))
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir)
        self.assertEqual(cm.exception.line, 7)
        self.assertIn("column 'leds': expected empty or '#rrggbb #rrggbb #rrggbb', got '#ff0000 #0000ff'",
                      str(cm.exception))

    def test_readings_csv_gives_back_each_robots_readings_at_each_tick(self):
        fixture.make_khepera_run(self.dir)
        self.assertIsNone(recording.load(self.dir).readings)  # read only when asked
        rec = recording.load(self.dir, with_readings=True)
        r = rec.readings
        self.assertEqual(r.columns, fixture.READINGS_COLUMNS)
        self.assertEqual(r.values.shape, (fixture.KHEPERA_TICKS + 1, fixture.KHEPERA_ROBOTS, 12))
        for tick in range(fixture.KHEPERA_TICKS + 1):
            for k in range(fixture.KHEPERA_ROBOTS):
                want = fixture.khepera_readings(tick, k)
                if want is None:
                    self.assertTrue(np.isnan(r.values[tick, k]).all(), (tick, k))  # dead: nothing sensed
                else:
                    self.assertEqual(r.values[tick, k].tolist(), want, (tick, k))
        self.assertEqual(r.column("battery")[7, 2], 0.8 - 0.07)
        self.assertFalse([w for w in rec.warnings if "readings.csv" in w], rec.warnings)

    def test_a_truncated_readings_csv_keeps_its_whole_lines_and_says_where_it_was_cut(self):
        fixture.make_khepera_run(self.dir)
        path = os.path.join(self.dir, "readings.csv")
        with open(path) as f:
            lines = f.read().split("\n")
        # Cut in the middle of tick 5's third row (line 1 + 5 * 4 + 3 = 24): the run stopped while writing.
        with open(path, "w") as f:
            f.write("\n".join(lines[:23]) + "\n" + lines[23][:30])
        rec = recording.load(self.dir, with_readings=True)
        self.assertTrue(any(w.startswith(f"{path}:24: half-written last line dropped") for w in rec.warnings),
                        rec.warnings)
        self.assertTrue(any(w.startswith(f"{path}: ends at tick 5, robots.csv at 20") for w in rec.warnings),
                        rec.warnings)
        self.assertEqual(rec.readings.values[5, 1].tolist(), fixture.khepera_readings(5, 1))
        self.assertTrue(np.isnan(rec.readings.values[5, 2]).all())
        self.assertTrue(np.isnan(rec.readings.values[6:]).all())

    def test_a_damaged_readings_csv_names_the_file_and_the_line(self):
        fixture.make_khepera_run(self.dir)
        path = os.path.join(self.dir, "readings.csv")
        with open(path) as f:
            lines = f.read().split("\n")
        # Line 9: tick 1, robot 3.
        cases = [(lambda l: l.replace(",", ";", 3), "expected 14 comma-separated fields, got 11"),
                 (lambda l: l.replace("0.5235987755982988", "north"),
                  "column 'lidar_nearest_angle': expected a number or nothing, got 'north'"),
                 (lambda l: "x" + l, "columns 'tick' and 'id': expected integers"),
                 (lambda l: "25" + l[1:], "tick 25: not a tick of robots.csv, or out of order"),
                 (lambda l: "0" + l[1:], "tick 0: not a tick of robots.csv, or out of order"),
                 (lambda l: l.replace(",3,", ",7,", 1), "id 7: expected 0..3")]
        for damage, what in cases:
            broken = list(lines)
            broken[8] = damage(broken[8])
            with open(path, "w") as f:
                f.write("\n".join(broken))
            with self.assertRaises(recording.RecordingError) as cm:
                recording.load(self.dir, with_readings=True)
            self.assertEqual((cm.exception.path, cm.exception.line), (path, 9), str(cm.exception))
            self.assertIn(what, str(cm.exception))
        for header in ("tick,robot,proximity0", "tick,id"):
            with open(path, "w") as f:
                f.write("\n".join([header] + lines[1:]))
            with self.assertRaises(recording.RecordingError) as cm:
                recording.load(self.dir, with_readings=True)
            self.assertEqual(str(cm.exception), f"{path}:1: header: expected tick,id then the sensors' columns; "
                                                f"got '{header}'")
        with open(path, "w") as f:
            f.write("")
        with self.assertRaises(recording.RecordingError) as cm:
            recording.load(self.dir, with_readings=True)
        self.assertEqual(str(cm.exception), f"{path}:1: empty: expected the header tick,id and the sensors' columns")


class RobotsDamageTest(unittest.TestCase):
    """robots.csv's damage as `swarm report` and `swarm replay` say it: the same places (line, byte), ticks and
    words as `swarm view` (viewer/robots_csv.cpp; tests/viewer checks the viewer's side on the same damage)."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-damage-")
        fixture.make_run(self.dir, ticks=40, robots=7, death=None)
        self.csv = os.path.join(self.dir, "robots.csv")
        with open(self.csv, "rb") as f:
            self.text = f.read()

    def tearDown(self):
        shutil.rmtree(self.dir)

    def write(self, data):
        with open(self.csv, "wb") as f:
            f.write(data)

    def row_at(self, tick, rid):
        """The byte offset and the line number (1: the header) of tick's row of robot rid."""
        at = self.text.index(f"\n{tick},{rid},".encode()) + 1
        return at, self.text[:at].count(b"\n") + 1

    def said(self, run_dir):
        """What `swarm report` prints and what `swarm replay` warns, as two lists of lines."""
        from swarmform import cli, report
        out = []
        try:
            report.report(run_dir, out.append)
        except recording.RecordingError as e:
            out.append(str(e))
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            cli.render_pictures(run_dir, animate=False, out_dir=os.path.join(self.dir, "pictures"))
        return out, err.getvalue().splitlines()

    def test_a_whole_recording_has_no_damage(self):
        self.assertEqual(recording.robots_damage(self.csv, 7), [])

    def test_corrupt_bytes_in_the_middle_name_line_byte_and_the_ticks_lost(self):
        start, line = self.row_at(20, 3)
        end_row, _ = self.row_at(23, 1)
        cut_from, cut_to = start + 4, end_row + 5
        after = self.text.index(b"\n", cut_to) + 1
        self.write(self.text[:cut_from] + b"x" * (cut_to - cut_from) + self.text[cut_to:])
        d = recording.robots_damage(self.csv, 7)
        self.assertEqual(len(d), 2, [str(x) for x in d])
        self.assertEqual((d[0].line, d[0].offset, d[0].from_tick, d[0].to_tick), (line, start, 20, 22))
        self.assertEqual(d[0].what.split(" (1 line(s)")[0], f"bytes {start}..{after} cannot be read")
        self.assertIn("; no tick after 20 can be read before tick 23; tick 20 has 3 of 7 robots' rows "
                      "(missing: 3 4 5 6)", d[0].what)
        self.assertEqual((d[1].from_tick, d[1].to_tick, d[1].offset), (23, 23, after))
        self.assertIn("tick 23 has 5 of 7 robots' rows (missing: 0 1)", d[1].what)
        self.assertEqual(str(d[0]).split(": ")[0], f"{self.csv}:{line} (byte {start}, ticks 20..22)")
        report_lines, replay_lines = self.said(self.dir)
        for x in d:
            self.assertIn(f"damaged recording: {x}", report_lines)
            self.assertIn(f"swarm: warning: damaged recording: {x}", replay_lines)

    def test_a_missing_robot_is_named_with_its_tick(self):
        at, line = self.row_at(12, 4)
        nl = self.text.index(b"\n", at) + 1
        self.write(self.text[:at] + self.text[nl:])
        d = recording.robots_damage(self.csv, 7)
        self.assertEqual([(x.line, x.from_tick, x.to_tick) for x in d], [(line - 4, 12, 12)])
        self.assertIn("tick 12 has 6 of 7 robots' rows (missing: 4)", d[0].what)

    def test_a_cut_recording_ends_at_its_last_whole_tick(self):
        at, line = self.row_at(39, 3)
        self.write(self.text[:at + 9])  # tick 39: robots 0..2 whole, robot 3 half-written
        os.remove(os.path.join(self.dir, "summary.json"))  # a killed world writes none
        d = recording.robots_damage(self.csv, 7)
        first, first_line = self.row_at(39, 0)
        self.assertEqual(len(d), 1, [str(x) for x in d])
        self.assertTrue(d[0].at_open)
        self.assertEqual((d[0].line, d[0].offset, d[0].from_tick), (first_line, first, 38))
        self.assertEqual(d[0].what, f"ends early (the run stopped while writing): a half-written last line at byte "
                                    f"{at} (9 bytes); the last tick 39 has 3 of 7 robots' rows (from byte {first}); "
                                    "shown up to tick 38")
        report_lines, replay_lines = self.said(self.dir)
        self.assertIn(f"damaged recording: {d[0]}", report_lines)
        self.assertIn("summary.json: missing", report_lines[-1])
        self.assertIn(f"swarm: warning: damaged recording: {d[0]}", replay_lines)
