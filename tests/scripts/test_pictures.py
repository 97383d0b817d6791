"""The pictures: every file, each a complete PNG of the documented size, the animation with the planned frame
count, a GIF small enough for a README, and a long run rendered fast."""

import json
import os
import resource
import shutil
import tempfile
import time
import unittest

import numpy as np

import helpers
import fixture
from swarmform import animation, pictures, recording, scene


class PicturesTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="swarm-pics-")
        fixture.make_run(cls.dir, ticks=80, robots=7)
        cls.result = helpers.swarm("replay", cls.dir, "--ticks", "33")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir)

    def test_replay_writes_every_picture_at_its_size(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        self.assertNotIn("Traceback", self.result.stderr)
        out = os.path.join(self.dir, "pictures")
        rec = recording.load(self.dir)
        expected = [f"snapshot_t{t:05d}.png" for t, _ in pictures.snapshot_ticks(rec, [33])]
        self.assertIn("snapshot_t00000.png", expected)
        self.assertIn("snapshot_t00033.png", expected)
        self.assertIn("snapshot_t00079.png", expected)
        self.assertGreaterEqual(len(expected), 7)  # start, formation, motion, 3 during, end (+ 33)
        for name in expected:
            self.assertEqual(helpers.png_size(os.path.join(out, name)), pictures.picture_size(rec, "snapshot"), name)
        for kind in ("trajectories", "residual_force", "shape_error"):
            self.assertEqual(helpers.png_size(os.path.join(out, kind + ".png")), pictures.picture_size(rec, kind))
        w, h = pictures.picture_size(rec, "snapshot")
        self.assertEqual(w, 900)
        self.assertTrue(360 <= h <= 900 and h % 2 == 0, h)
        names = sorted(os.listdir(out))
        self.assertEqual(names, sorted(expected + ["trajectories.png", "residual_force.png", "shape_error.png",
                                                   "animation.mp4", "animation.gif"]))
        self.assertIn(f"pictures: {len(names)} files", self.result.stdout)

    def test_animation_has_the_planned_frames(self):
        out = os.path.join(self.dir, "pictures")
        frames, gif_every, _ = animation.frame_plan(80)
        self.assertEqual(len(frames), 80)  # a short run: every tick is a frame
        w, h, n = helpers.video_frames(os.path.join(out, "animation.mp4"))
        self.assertEqual((w, h, n), (*animation.MP4_SIZE, 80))
        w, h, n = helpers.video_frames(os.path.join(out, "animation.gif"))
        self.assertEqual((w, n), (animation.GIF_WIDTH, animation.gif_frame_count(80, gif_every)))
        self.assertLessEqual(os.path.getsize(os.path.join(out, "animation.gif")), animation.GIF_LIMIT_BYTES)

    def test_animation_frames_show_the_run_moving_with_a_caption(self):
        mp4 = os.path.join(self.dir, "pictures", "animation.mp4")
        w, h = animation.MP4_SIZE
        first, last = helpers.video_frame(mp4, 0, w, h), helpers.video_frame(mp4, 79, w, h)
        self.assertGreater(int(np.abs(first.astype(int) - last.astype(int)).sum()), 1000, "the robots moved")
        top = first[: h // 10, w // 4: w // 2]  # the caption ("t = 0 ...") sits above the arena
        self.assertLess(int(top.min()), 100, "a blitted frame lost its caption")

    def test_frame_plan_subsamples_long_runs_and_ends_on_the_last_tick(self):
        frames, gif_every, fps = animation.frame_plan(3001)
        self.assertLessEqual(len(frames), animation.MAX_FRAMES)
        self.assertEqual(frames[0], 0)
        self.assertEqual(frames[-1], 3000)
        self.assertLessEqual(animation.gif_frame_count(len(frames), gif_every), animation.MAX_GIF_FRAMES)
        self.assertTrue(5 <= fps <= 30)

    def test_a_second_drawing_replaces_the_snapshots_of_the_first(self):
        out = os.path.join(self.dir, "again")
        rec = recording.load(self.dir)
        pictures.render_all(rec, out, [5, 6], animate=False, log=lambda m: None)
        self.assertTrue(os.path.exists(os.path.join(out, "snapshot_t00005.png")))
        pictures.render_all(rec, out, [], animate=False, log=lambda m: None)
        self.assertFalse(os.path.exists(os.path.join(out, "snapshot_t00005.png")))
        self.assertTrue(os.path.exists(os.path.join(out, "snapshot_t00000.png")))

    def test_tick_outside_the_recording_is_a_clear_error(self):
        r = helpers.swarm("replay", self.dir, "--ticks", "5000", "--no-animation", "--out",
                          os.path.join(self.dir, "other"))
        self.assertEqual(r.returncode, 2)
        self.assertIn("--ticks 5000: the recording holds ticks 0..79", r.stderr)

    def test_random_walk_without_labels_still_draws_everything(self):
        d = tempfile.mkdtemp(prefix="swarm-walk-")
        try:
            fixture.make_run(d, ticks=30, robots=4, death=None)
            path = os.path.join(d, "robots.csv")
            with open(path) as f:
                lines = f.read().splitlines()
            rows = [lines[0]] + [",".join(p[:6] + ["0", "-1", "-1", "0", "0"])
                                 for p in (line.split(",") for line in lines[1:])]
            with open(path, "w") as f:
                f.write("\n".join(rows) + "\n")
            os.remove(os.path.join(d, "summary.json"))  # a random walk forms nothing: no formation tick
            written = pictures.render_all(recording.load(d), animate=False, log=lambda m: None)
            self.assertEqual(len(written), 5 + 3)  # five snapshots through the run + three figures
            for p in written:
                helpers.png_size(p)
        finally:
            shutil.rmtree(d)


def rgb_at(scene, x, y):
    """The drawn (r, g, b) of a Scene's figure at arena point (x, y)."""
    scene.fig.canvas.draw()
    image = np.asarray(scene.fig.canvas.buffer_rgba())
    px, py = scene.ax.transData.transform((x, y))
    return tuple(int(v) for v in image[image.shape[0] - 1 - int(round(py)), int(round(px)), :3])


def png_rgb_at(path, scene, x, y):
    """The (r, g, b) of a saved PNG at arena point (x, y), placed by a Scene of the same size (the same layout)."""
    import matplotlib.pyplot as plt
    image = plt.imread(path)
    px, py = scene.ax.transData.transform((x, y))
    return tuple(int(round(255 * v)) for v in image[image.shape[0] - 1 - int(round(py)), int(round(px)), :3])


class KheperaPicturesTest(unittest.TestCase):
    """The floor under everything (its regions and image), the light sources and each live robot's lit LEDs are
    drawn in the snapshots, the trajectories and the animation's frames."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-pics-khepera-")

    def tearDown(self):
        shutil.rmtree(self.dir)

    def scene(self, rec, tick=0):
        view = scene.Scene(rec, pictures.picture_size(rec, "snapshot"), pictures.DPI)
        self.addCleanup(view.close)
        view.show(rec.track.index_of(tick))
        return view

    def assertColour(self, got, want, what, tolerance=12):
        self.assertTrue(all(abs(g - w) <= tolerance for g, w in zip(got, want)), f"{what}: {got}, expected {want}")

    def test_floor_regions_the_light_and_the_floor_are_drawn_in_their_colours(self):
        fixture.make_khepera_run(self.dir)
        rec = recording.load(self.dir)
        view = self.scene(rec)
        self.assertColour(rgb_at(view, -1.5, 1.8), (0, 0, 255), "the blue disc's centre")
        self.assertColour(rgb_at(view, 2.3, -0.9), (77, 77, 77), "the grey band (grey 0.3)")
        self.assertColour(rgb_at(view, 3.0, 1.8), (255, 214, 0), "the light")
        self.assertColour(rgb_at(view, 3.5, 0.5), (230, 230, 230), "the floor's own grey 0.9")
        legend = [t.get_text() for t in view.fig.legends[0].get_texts()]
        self.assertIn("light", legend)
        self.assertIn("LEDs (lit)", legend)
        # The light's intensity is written beside it.
        self.assertIn("light I=2.5, h=0.3 m", [t.get_text() for t in view.ax.texts])
        # The same in the files the launcher writes: a snapshot and the trajectories.
        written = pictures.render_all(rec, animate=False, log=lambda m: None)
        snapshot = [p for p in written if p.endswith("snapshot_t00000.png")][0]
        self.assertColour(png_rgb_at(snapshot, view, -1.5, 1.8), (0, 0, 255), "the blue disc in the snapshot")
        self.assertColour(png_rgb_at(snapshot, view, 3.0, 1.8), (255, 214, 0), "the light in the snapshot")

    def test_each_live_robots_lit_leds_are_three_dots_on_it(self):
        fixture.make_khepera_run(self.dir)
        rec = recording.load(self.dir)
        view = self.scene(rec, 7)
        t, i = rec.track, rec.track.index_of(7)

        def dots():
            return [tuple(int(round(255 * v)) for v in c[:3]) for c in view.leds.get_facecolors()]

        # Tick 7: robot 0 three green, robot 1 red and blue (its middle LED is off), robot 3 one green.
        self.assertEqual(len(view.leds.get_offsets()), 6)
        self.assertEqual(sorted(dots()), sorted([(0, 255, 0)] * 4 + [(255, 0, 0), (0, 0, 255)]))
        at = scene.led_positions(t.x[i], t.y[i], t.theta[i], view.drawn_radius)
        self.assertIn(tuple(at[1, 0]), [tuple(o) for o in view.leds.get_offsets()])  # robot 1's LED 0 is drawn
        self.assertNotIn(tuple(at[1, 1]), [tuple(o) for o in view.leds.get_offsets()])  # its LED 1 is off
        for k in range(t.robots):  # on the robot's body as drawn
            self.assertLess(float(np.hypot(*(at[k] - [t.x[i, k], t.y[i, k]]).T).max()), view.drawn_radius)
        self.assertColour(rgb_at(view, *at[0, 0]), (0, 255, 0), "robot 0's LED 0")
        self.assertColour(rgb_at(view, *at[1, 2]), (0, 0, 255), "robot 1's LED 2")
        # Tick 2: robot 0 not lit yet. Tick 15: robot 3 is dead, its LEDs not drawn.
        view.show(t.index_of(2))
        self.assertEqual(len(view.leds.get_offsets()), 3)
        view.show(t.index_of(15))
        self.assertEqual(sorted(dots()), sorted([(0, 255, 0)] * 3 + [(255, 0, 0), (0, 0, 255)]))

    def test_a_recording_without_leds_draws_no_dots(self):
        fixture.make_khepera_run(self.dir, leds=False)
        rec = recording.load(self.dir)
        view = self.scene(rec, 7)
        self.assertEqual(len(view.leds.get_offsets()), 0)
        self.assertNotIn("LEDs (lit)", [t.get_text() for t in view.fig.legends[0].get_texts()])

    def test_an_image_floor_is_drawn_stretched_over_the_arena(self):
        import matplotlib.pyplot as plt
        png = os.path.join(self.dir, "floor.png")
        pixels = np.ones((6, 8, 3))
        pixels[:, :4] = (1.0, 0.0, 0.0)  # the arena's west half red (x < 0), the east half white
        plt.imsave(png, pixels)
        # world.json names the run folder's copy, relative to the folder: a copy of the folder elsewhere keeps it.
        fixture.make_khepera_run(self.dir, floor_image="floor.png")
        moved = self.dir + "-copied"
        shutil.copytree(self.dir, moved)
        self.addCleanup(shutil.rmtree, moved)
        os.remove(png)
        view = self.scene(recording.load(moved))
        self.assertColour(rgb_at(view, -1.7, -1.3), (255, 0, 0), "the image's west half")
        self.assertColour(rgb_at(view, 3.5, 0.5), (255, 255, 255), "the image's east half, over the floor's grey")
        self.assertColour(rgb_at(view, -1.5, 1.8), (0, 0, 255), "a region over the image")

    def test_a_missing_floor_image_is_a_warning_and_the_rest_is_drawn(self):
        fixture.make_khepera_run(self.dir, floor_image=os.path.join(self.dir, "gone.png"))
        rec = recording.load(self.dir)
        with self.assertWarnsRegex(UserWarning, "gone.png: the floor's image is missing"):
            view = self.scene(rec)
        self.assertColour(rgb_at(view, -1.5, 1.8), (0, 0, 255), "the blue disc")

    def test_the_animation_frames_show_the_floor_and_the_leds(self):
        fixture.make_khepera_run(self.dir)
        rec = recording.load(self.dir)
        out = os.path.join(self.dir, "pictures")
        os.makedirs(out)
        animation.render(rec, out, log=lambda m: None)
        w, h = animation.MP4_SIZE
        view = scene.Scene(rec, animation.MP4_SIZE, 100)  # the animation's own layout
        self.addCleanup(view.close)
        frame = helpers.video_frame(os.path.join(out, "animation.mp4"), 7, w, h)
        px, py = view.ax.transData.transform((-1.5, 1.8))
        self.assertColour(tuple(int(v) for v in frame[h - 1 - int(round(py)), int(round(px)), :3]), (0, 0, 255),
                          "the blue disc in frame 7", tolerance=40)
        t = rec.track
        at = scene.led_positions(t.x[7], t.y[7], t.theta[7], view.drawn_radius)
        gx, gy = view.ax.transData.transform(at[0, 0])
        g = frame[h - 1 - int(round(gy)), int(round(gx)), :3].astype(int)
        self.assertTrue(g[1] > 150 and g[0] < 110 and g[2] < 110, f"robot 0's green LED in frame 7: {g}")


class GifLimitTest(unittest.TestCase):
    def test_a_gif_over_the_limit_is_made_again_smaller_with_the_same_frames(self):
        d = tempfile.mkdtemp(prefix="swarm-gif-")
        limit = animation.GIF_LIMIT_BYTES
        try:
            fixture.make_run(d, ticks=40, robots=5, death=None)
            animation.GIF_LIMIT_BYTES = 1000  # every GIF is over it
            messages = []
            mp4, gif = animation.render(recording.load(d), d, log=messages.append)
            w, _, n = helpers.video_frames(gif)
            frames, gif_every, _ = animation.frame_plan(40)
            self.assertEqual((w, n), (360, animation.gif_frame_count(len(frames), gif_every)))
            self.assertTrue(messages and "made again at 360 px" in messages[0], messages)
        finally:
            animation.GIF_LIMIT_BYTES = limit
            shutil.rmtree(d)


def cpu_seconds():
    me, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + children.ru_utime + children.ru_stime


class SpeedTest(unittest.TestCase):
    def test_3000_ticks_of_30_robots_render_well_under_a_minute(self):
        d = tempfile.mkdtemp(prefix="swarm-speed-")
        try:
            fixture.make_run(d, ticks=3000, robots=30, death=(4, 1500))
            # CPU time (ours and ffmpeg's), not wall time: the test must not fail because the machine is busy.
            start, cpu0 = time.monotonic(), cpu_seconds()
            written = pictures.render_all(recording.load(d), log=lambda m: None)
            cpu, seconds = cpu_seconds() - cpu0, time.monotonic() - start
            print(f"\n3000 ticks x 30 robots: every picture and the animation in {seconds:.1f} s "
                  f"({cpu:.1f} s of CPU)")
            self.assertLess(cpu, 40.0)
            _, _, n = helpers.video_frames(os.path.join(d, "pictures", "animation.mp4"))
            self.assertEqual(n, animation.MAX_FRAMES)
            self.assertEqual(len(written), 12)
        finally:
            shutil.rmtree(d)


class GroupsPicturesTest(unittest.TestCase):
    """A mixed swarm (world.json `groups`): each robot filled by its own group's state colours and edged in its
    group's colour, and the legend has a line per group."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-pics-groups-")
        fixture.make_run(self.dir, robots=7, death=(0, 1000))
        path = os.path.join(self.dir, "world.json")
        with open(path) as f:
            doc = json.load(f)
        states = [{"value": v, "name": f"paper{v}", "colour": "#00ff00"} for v in range(7)]
        walking = [{"value": v, "name": f"walk{v}", "colour": "#0000ff"} for v in range(7)]
        doc["groups"] = [{"name": "shapers", "first_id": 0, "count": 4, "behaviour_descriptor": {"name": "paper",
                                                                                                "states": states}},
                         {"name": "movers", "first_id": 4, "count": 3,
                          "behaviour_descriptor": {"name": "random_walk", "states": walking}}]
        with open(path, "w") as f:
            json.dump(doc, f)

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_each_robot_has_its_groups_colours_and_the_legend_a_line_per_group(self):
        rec = recording.load(self.dir)
        self.assertEqual([(g.name, g.first_id, g.count) for g in rec.world.groups], [("shapers", 0, 4), ("movers", 4, 3)])
        view = scene.Scene(rec, pictures.picture_size(rec, "snapshot"), pictures.DPI)
        self.addCleanup(view.close)
        view.show(rec.track.index_of(10))
        fills = [tuple(np.round(c[:3], 3)) for c in view.robots.get_facecolors()]
        self.assertEqual(fills, [(0.0, 1.0, 0.0)] * 4 + [(0.0, 0.0, 1.0)] * 3)
        edges = [tuple(np.round(c[:3], 3)) for c in view.robots.get_edgecolors()]
        self.assertEqual(len(set(edges[:4])), 1)
        self.assertEqual(len(set(edges[4:])), 1)
        self.assertNotEqual(edges[0], edges[4])
        labels = [t.get_text() for t in view.fig.legends[0].get_texts()]
        self.assertIn("shapers:", labels)
        self.assertIn("movers:", labels)


class WorldEventsPicturesTest(unittest.TestCase):
    """Obstacles that world events add, move and remove are drawn as they stand at the tick shown; the trajectories
    show where each stood as a dashed outline."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-pics-events-")
        fixture.make_run(self.dir)
        path = os.path.join(self.dir, "world.json")
        with open(path) as f:
            doc = json.load(f)
        doc["obstacles"].append({"kind": "box", "name": "gate", "centre": [0.0, 4.0], "half_extents": [0.4, 0.4],
                                 "yaw": 0.0, "present": False})
        doc["world_events"] = [{"tick": 40, "obstacle": 2, "name": "gate", "do": "move", "centre": [2.0, 4.0],
                                "yaw": None},
                               {"tick": 20, "obstacle": 2, "name": "gate", "do": "appear"}]
        with open(path, "w") as f:
            json.dump(doc, f)

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_an_obstacle_is_drawn_from_its_appearance_where_it_stands(self):
        rec = recording.load(self.dir)
        self.assertEqual([e.tick for e in rec.world.world_events], [20, 40])  # read in tick order
        view = scene.Scene(rec, pictures.picture_size(rec, "snapshot"), pictures.DPI)
        self.addCleanup(view.close)
        # Points off the grid's lines: inside the gate where it first stands, and where it moves to.
        first, moved = (0.3, 4.3), (2.3, 4.3)
        view.show(rec.track.index_of(10))
        box = rgb_at(view, 4.7, 1.3)  # inside the obstacle that is always there
        background = rgb_at(view, -2.3, 4.3)
        self.assertNotEqual(box, background)
        self.assertEqual(rgb_at(view, *first), background, "absent before its appearance")
        view.show(rec.track.index_of(30))
        self.assertEqual(rgb_at(view, *first), box, "there from tick 20")
        self.assertEqual(rgb_at(view, *moved), background)
        view.show(rec.track.index_of(50))
        self.assertEqual(rgb_at(view, *first), background, "moved away at tick 40")
        self.assertEqual(rgb_at(view, *moved), box, "moved to (2, 4)")

    def test_a_world_event_of_an_unknown_obstacle_is_named_in_the_recording(self):
        path = os.path.join(self.dir, "world.json")
        with open(path) as f:
            doc = json.load(f)
        doc["world_events"][0]["obstacle"] = 7
        with open(path, "w") as f:
            json.dump(doc, f)
        with self.assertRaisesRegex(recording.RecordingError, r"world_events\[0\]\.obstacle: expected an index of "
                                                              r"obstacles \(0\.\.2\), got 7"):
            recording.load(self.dir)


class GoalMovesPicturesTest(unittest.TestCase):
    """A goal that world events move (world.json's goal_moves) is drawn where it stands at the tick shown."""

    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="swarm-pics-goal-")
        fixture.make_run(self.dir)
        path = os.path.join(self.dir, "world.json")
        with open(path) as f:
            doc = json.load(f)
        self.first = (doc["goal"]["x"], doc["goal"]["y"])
        doc["goal_moves"] = [{"tick": 30, "x": 11.0, "y": -4.0, "radius": 0.5}]
        with open(path, "w") as f:
            json.dump(doc, f)

    def tearDown(self):
        shutil.rmtree(self.dir)

    def test_the_goal_is_drawn_where_it_stands_at_the_tick_shown(self):
        rec = recording.load(self.dir)
        self.assertEqual(recording.goal_at(rec.world, 29)[:2], self.first)
        self.assertEqual(recording.goal_at(rec.world, 30), (11.0, -4.0, 0.5))
        view = scene.Scene(rec, pictures.picture_size(rec, "snapshot"), pictures.DPI)
        self.addCleanup(view.close)
        # Points off the grid's lines, off the goals' marks: inside the first goal, inside the moved one.
        first, moved = (self.first[0] + 0.27, self.first[1] - 0.23), (11.0 + 0.27, -4.0 + 0.13)
        background = rgb_at(view, -3.3, 3.3)
        view.show(rec.track.index_of(10))
        self.assertNotEqual(rgb_at(view, *first), background, "the goal at first")
        self.assertEqual(rgb_at(view, *moved), background)
        view.show(rec.track.index_of(50))
        self.assertEqual(rgb_at(view, *first), background, "moved away at tick 30")
        self.assertNotEqual(rgb_at(view, *moved), background, "where it moved")


if __name__ == "__main__":
    unittest.main()
