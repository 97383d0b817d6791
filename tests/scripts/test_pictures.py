"""The pictures: every file, each a complete PNG of the documented size, the animation with the planned frame
count, a GIF small enough for a README, and a long run rendered fast."""

import os
import resource
import shutil
import tempfile
import time
import unittest

import numpy as np

import helpers
import fixture
from swarmform import animation, pictures, recording


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


if __name__ == "__main__":
    unittest.main()
