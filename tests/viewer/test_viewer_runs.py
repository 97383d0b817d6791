"""The viewer against recordings and its own death (viewer/README.md; DDS test domain offset 63, one run at a time): a
viewer SIGKILLed mid-run changes nothing of a lockstep run (the same trajectory hash as a run without one), and
`swarm view RUN_DIR` serves the same page over a recording: scrubbed to a tick, a headless Chromium draws the robots
where robots.csv puts them; a Foxglove client (foxglove.websocket.v1) during the replay gets the live channels and
schemas, and the poses of the tick the timeline is at (sought and played) are robots.csv's; a broken run directory
is refused naming the file."""

import asyncio
import json
import math
import os
import shutil
import signal
import struct
import subprocess
import tempfile
import time
import unittest

import viewer_helpers as vh

import websockets  # Debian's python3-websockets (scripts/setup)

import cdp

SCENARIO = os.path.join(vh.ROOT, "scenarios", "paper.yaml")
LIVE_CHANNELS = {"/scene": "foxglove.SceneUpdate", "/robots/poses": "foxglove.PosesInFrame",
                 "/robots/telemetry": "swarmform.RobotTelemetry", "/tf": "foxglove.FrameTransforms",
                 "/metrics": "swarmform.Metrics"}
MCAP_READER = os.path.join(vh.ROOT, "scripts", "mcap", "read.mjs")


@unittest.skipUnless(vh.built("world", "agent", "viewer"), f"world_server/robot_agent/swarm_viewer not built in "
                                                          f"{vh.BUILD_DIR}")
class RecordedRunsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        # One run without a viewer: the reference trajectory and the recording the replay test views.
        cls.dir = tempfile.mkdtemp(prefix="sf-view-runs-")
        cls.plain = os.path.join(cls.dir, "plain")
        r = vh.SwarmRun("--scenario", SCENARIO, "--domain", str(vh.helpers.test_domain(63)), "--out", cls.plain,
                        "--no-pictures", "--max-ticks", "300")
        cls.plain_result = r.wait(timeout=120)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.dir)

    def setUp(self):
        self.assertEqual(self.plain_result[0], 0, self.plain_result[1])
        self.runs = []
        self.procs = []
        self.browser = None

    def tearDown(self):
        if self.browser:
            self.browser.close()
        for r in self.runs:
            r.stop()
        for p in self.procs:  # `swarm view` and its swarm_viewer: their own process group
            try:
                os.killpg(p.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            p.wait(timeout=10)
        time.sleep(0.2)
        left = [p for p in vh.processes_mentioning(self.dir) if p != os.getpid()]
        for pid in left:
            os.kill(pid, signal.SIGKILL)
        self.assertEqual(left, [], "a process of this test was left running")

    def start(self, out, *extra, domain):
        r = vh.SwarmRun("--scenario", SCENARIO, "--domain", str(domain), "--out", out, "--no-pictures", *extra)
        self.runs.append(r)
        return r

    def test_a_viewer_killed_mid_run_changes_nothing(self):
        domain = vh.helpers.test_domain(63)
        plain = self.plain
        viewed = os.path.join(self.dir, "viewed")
        port = vh.free_port()
        # Paused at tick 0, then run on under a speed cap (50 ticks/s) through the page's protocol; the viewer is
        # SIGKILLed at tick 60 or later, while it caps the run: the world sees it gone (2 s of silence) and the run
        # goes on without it.
        run = self.start(viewed, "--max-ticks", "300", "--view-paused", "--view", str(port), domain=domain)
        vh.wait_http(f"http://127.0.0.1:{port}/")
        viewers = [p for p in vh.processes_mentioning(viewed) if "swarm_viewer" in vh.cmdline(p)]
        self.assertEqual(len(viewers), 1, "the viewer process")
        killed_at = asyncio.run(self.kill_viewer_at(port, 60, viewers[0]))
        self.assertGreaterEqual(killed_at, 60)
        self.assertLess(killed_at, 150)
        code, text = run.wait(timeout=120)
        self.assertEqual(code, 0, text)
        self.assertIn("the viewer exited with code -9", text)
        with open(os.path.join(viewed, "logs", "world_console.log")) as f:
            self.assertIn("the viewer went away", f.read())
        hashes = []
        for d in (plain, viewed):
            with open(os.path.join(d, "summary.json")) as f:
                s = json.load(f)
            self.assertEqual(s["ticks"], 300)
            hashes.append(s["trajectory_sha256"])
        self.assertEqual(hashes[0], hashes[1], "a viewer that died changed the run")

    async def kill_viewer_at(self, port, tick, pid):
        async with websockets.connect(f"ws://127.0.0.1:{port}/ws") as ws:
            await ws.send(json.dumps({"cmd": "speed", "value": 50}))
            await ws.send(json.dumps({"cmd": "resume"}))
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline:
                m = json.loads(await asyncio.wait_for(ws.recv(), 30))
                if m["type"] == "frame" and m["tick"] >= tick:
                    os.kill(pid, signal.SIGKILL)
                    return m["tick"]
        raise AssertionError(f"no frame of tick {tick} within 60 s")

    @unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
    def test_replay_scrubbed_to_a_tick_draws_the_recording(self):
        port = vh.free_port()
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=vh.BUILD_DIR)
        p = subprocess.Popen([vh.SWARM, "view", self.plain, "--port", str(port)], stdin=subprocess.DEVNULL,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, start_new_session=True)
        self.procs.append(p)
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        b = self.browser = cdp.Browser()
        b.navigate(url)
        b.wait_for("window.sfViewer && sfViewer.replay && sfViewer.frame", what="the recording loaded")
        self.assertEqual(b.eval("sfViewer.replay.ticks"), 301)
        checked = 0
        for tick in (0, 137, 300):
            # Scrub: the timeline set as a user's drag sets it.
            b.eval(f"(() => {{ const t = document.getElementById('timeline'); t.value = '{tick}';"
                   f" t.dispatchEvent(new Event('input')); }})()")
            b.wait_for(f"sfViewer.frame.tick === {tick}", what=f"tick {tick}")
            self.assertEqual(b.eval("document.getElementById('tick').textContent"), str(tick))
            img, _ = b.screenshot()
            drawn = b.eval("""(() => { const c = document.getElementById('arena').getBoundingClientRect();
                return {x0: c.x, y0: c.y, w: c.width, h: c.height, view: sfViewer.view,
                        states: Array.from(sfViewer.states, ([v, s]) => [v, s.colour])}; })()""")
            colours = {int(v): c for v, c in drawn["states"]}
            for rid, r in vh.rows_at(self.plain, tick).items():
                px, py = vh.check_projection(self, b, float(r["x"]), float(r["y"]))
                want = vh.hex_rgb(colours[int(r["state"])])
                got, d = vh.drawn_near(img, px, py, want)
                self.assertLessEqual(d, 12,
                                     f"tick {tick} robot {rid} at ({px:.1f}, {py:.1f}): drawn {got}, want {want}")
                checked += 1
        self.assertEqual(checked, 27)
        # Jump to an event: the list holds the recording's deaths, rejoins, leader changes, formation and arrival.
        with open(os.path.join(self.plain, "events.jsonl")) as f:
            events = [json.loads(line) for line in f if line.strip()]
        with open(os.path.join(self.plain, "summary.json")) as f:
            summary = json.load(f)
        marks = sum(e["kind"] in ("death", "rejoin", "leader", "leader_lost") for e in events)
        marks += sum(summary.get(k) is not None for k in ("formation_tick", "goal_tick"))
        self.assertEqual(b.eval("document.getElementById('jump').options.length"), 1 + marks)

    @unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
    def test_replay_rates_take_no_jump_for_a_tick_rate_and_keys_drive_the_timeline(self):
        """ticks/s counts the timeline playing, not its jumps: seeks while playing at 1x (10 ticks/s) never show
        more than the recording's rate; paused it says so. Space plays and pauses, → moves one tick, + / − the
        speed. Ids are drawn only where they fit; the scale bar and grid are on."""
        b = self.open_replay_page()
        b.key(" ")
        b.wait_for("!sfViewer.frame.paused && sfViewer.rates.now && sfViewer.rates.now.tps !== null", timeout=30,
                   what="playing, a measured tick rate")
        highest = 0.0
        for target in (20, 250, 10, 200):
            b.eval(f"(() => {{ const t = document.getElementById('timeline'); t.value = '{target}';"
                   f" t.dispatchEvent(new Event('input')); }})()")
            deadline = time.monotonic() + 1.0
            while time.monotonic() < deadline:
                tps = b.eval("sfViewer.rates.now.tps")
                if tps is not None:
                    highest = max(highest, tps)
                time.sleep(0.05)
        self.assertLess(highest, 10 * 1.5, "a seek counted as ticks (the recording plays 10 ticks/s at 1x)")
        self.assertGreater(highest, 0)
        self.assertRegex(b.eval("document.getElementById('fps').textContent"), r"^\d+\.\d$")
        self.assertEqual(b.eval("document.getElementById('lag').textContent"), "0.0")
        b.key(" ")
        b.wait_for("sfViewer.frame.paused", what="paused by space")
        b.wait_for("document.getElementById('tps').textContent === 'paused'", what="ticks/s: paused")
        at = b.eval("sfViewer.frame.at")
        b.key("ArrowRight")
        b.wait_for(f"sfViewer.frame.at === {at + 1}", what="→: the next tick")
        # + / −: the speed list's next and previous (the server's speed shows in the next frame: a step sends one).
        b.key("+")
        self.assertEqual(b.eval("document.getElementById('replay-speed').value"), "2")
        b.key("ArrowRight")
        b.wait_for("sfViewer.frame.replay_speed === 2", what="+: 2x")
        b.key("-")
        b.key("-")
        self.assertEqual(b.eval("sfViewer.lastKey.action"), "speed 0.5")
        b.key("ArrowRight")
        b.wait_for("sfViewer.frame.replay_speed === 0.5", what="− −: 0.5x")
        # Ids where they fit: all nine at "fit" in the paper's formation, fewer when zoomed out so far that the
        # labels would print over each other.
        b.eval("sfViewer.view.scale = 400; sfViewer.view.cx = sfViewer.frame.robots[0].x;"
               " sfViewer.view.cy = sfViewer.frame.robots[0].y; sfViewer.select(null)")
        self.assertEqual(b.eval("sfViewer.drawn.ids"), 9)
        b.eval("sfViewer.view.scale = 2; sfViewer.select(null)")
        self.assertLess(b.eval("sfViewer.drawn.ids"), 9)
        self.assertGreaterEqual(b.eval("sfViewer.drawn.ids"), 1)
        bar = b.eval("sfViewer.drawn.scaleBar")
        self.assertGreaterEqual(bar["px"], 80)
        self.assertAlmostEqual(bar["px"], bar["metres"] * 2, places=6)
        self.assertGreater(b.eval("sfViewer.drawn.gridStep"), 0)

    @unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
    def test_replay_sends_a_slow_page_the_newest_frame_not_a_backlog(self):
        """A replay paces its frames as live does (viewer/page_flow.hpp): a page slower than the timeline gets
        the newest frame once it has drawn the last, never a queue of frames in its socket. The page's draw is
        slowed to 150 ms a frame while the recording plays at 5x (50 ticks/s, a frame every 20 ms): a seek is
        shown after at most the two frames in flight when it was asked (a queue would show seconds of frames
        first), and the first frame at the new place is a jump (`played` false), though the timeline playing on
        replaced the seek's own frame while the page drew: the page's ticks/s must not count the seek's
        distance as ticks played."""
        b = self.open_replay_page()
        # Every frame the page gets, in order: [at, tick, played]; and a draw that takes 150 ms.
        b.eval("""(() => { sfViewer.got = []; const show = window.show, draw = window.draw;
            window.show = function (f) {
              sfViewer.got.push([f.at, f.tick, f.played]);
              return show.apply(this, arguments);
            };
            window.draw = function () {
              const t = performance.now() + 150;
              while (performance.now() < t);
              return draw.apply(this, arguments);
            };
            send("speed", 5); send("play"); })()""")
        b.wait_for("sfViewer.got.some((g) => g[0] >= 40)", timeout=120, what="the timeline past tick 40")
        # Seek 100 ticks forward of the page's last frame, between two of its frames: every frame it had been
        # sent is before that (the timeline is ahead of the page by the frames in flight, a few ticks).
        before, target = b.eval("""(() => { const n = sfViewer.got.length, t = sfViewer.got[n - 1][0] + 100;
            send('seek', t); return [n, t]; })()""")
        self.assertLess(target, 300, "the recording's end")
        b.wait_for(f"sfViewer.got.slice({before}).some((g) => g[0] >= {target})", timeout=120,
                   what="a frame at the seek's place")
        got = b.eval(f"sfViewer.got.slice({before})")
        first = next(i for i, g in enumerate(got) if g[0] >= target)
        self.assertLessEqual(first, 2, f"frames [at, tick, played] before the seek's after it was asked (a "
                                       f"backlog): {got[:3]} ... {got[first - 1:first + 1]}")
        self.assertIs(got[first][2], False, f"the first frame at the seek's place counted as played: {got[first]}")

    def open_replay_page(self):
        """`swarm view` of the plain run and a headless Chromium page on it, the recording loaded."""
        port = vh.free_port()
        self.view(self.plain, port)
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        b = self.browser = cdp.Browser()
        b.navigate(url)
        b.wait_for("window.sfViewer && sfViewer.replay && sfViewer.frame", what="the recording loaded")
        return b

    def view(self, run_dir, port):
        """`swarm view RUN_DIR --port PORT` in the background (its own process group, killed in tearDown)."""
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=vh.BUILD_DIR)
        p = subprocess.Popen([vh.SWARM, "view", run_dir, "--port", str(port)], stdin=subprocess.DEVNULL,
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                             start_new_session=True)
        self.procs.append(p)
        return p

    def test_replay_speaks_foxglove_on_the_timeline(self):
        port = vh.free_port()
        self.view(self.plain, port)
        vh.wait_http(f"http://127.0.0.1:{port}/")
        got = asyncio.run(self.foxglove_replay(port))
        rate = 10.0  # scenarios/paper.yaml's tick rate
        # Log time: the run's wall time, world.json's (written as the run starts) plus tick / rate.
        start = os.stat(os.path.join(self.plain, "world.json")).st_mtime_ns / 1e9
        # Each seek's poses are robots.csv's at that tick, to the last bit (the reader parses the same text).
        for tick, poses in got["seeks"]:
            rows = vh.rows_at(self.plain, tick)
            self.assertEqual(len(poses), len(rows))
            for rid, p in enumerate(poses):
                r = rows[rid]
                self.assertAlmostEqual(p["position"]["x"], float(r["x"]), places=9)
                self.assertAlmostEqual(p["position"]["y"], float(r["y"]), places=9)
                yaw = 2 * math.atan2(p["orientation"]["z"], p["orientation"]["w"])
                self.assertAlmostEqual(math.remainder(yaw - float(r["theta"]), 2 * math.pi), 0.0, places=9)
        self.assertEqual([t for t, _ in got["seeks"]], [0, 137, 300])
        # Playing: Foxglove hears the ticks in order as the timeline runs, each one robots.csv's.
        played = [t for t, _ in got["played"]]
        self.assertGreaterEqual(len(played), 5)
        self.assertEqual(played, sorted(played))
        self.assertGreater(played[-1], played[0])
        for tick, poses in got["played"]:
            rows = vh.rows_at(self.plain, tick)
            self.assertAlmostEqual(poses[4]["position"]["x"], float(rows[4]["x"]), places=9)
        for stamp, tel in got["telemetry"]:
            self.assertEqual(round((stamp - start) * rate), tel["tick"])
            self.assertEqual(len(tel["robots"]), 9)
            rows = vh.rows_at(self.plain, tel["tick"])
            for r in tel["robots"]:
                self.assertEqual((r["state"], r["label"], r["alive"]),
                                 (int(rows[r["id"]]["state"]), int(rows[r["id"]]["label"]),
                                  rows[r["id"]]["alive"] == "1"))
                # The recording holds no neighbours heard or commands: left out, not sent as zeros.
                self.assertNotIn("heard", r)
                self.assertNotIn("left_speed", r)
        entities = {e["id"]: e for e in got["first_scene"]["entities"]}
        # No ultrasonic rays: robots.csv does not hold them.
        self.assertEqual(list(entities), ["arena", "obstacles", "robots", "parent_links", "leader"])
        self.assertEqual(len(entities["robots"]["cylinders"]), 9)
        self.assertEqual(len(entities["arena"]["cubes"]), 4, "four walls")
        self.assertEqual(len(entities["obstacles"]["cubes"]), 1, "paper.yaml's box")
        # Foxglove's /control took the page's replay commands: it sought to tick 250.
        self.assertEqual(got["controlled"], 250)

    async def foxglove_replay(self, port):
        got = {"seeks": [], "played": [], "telemetry": [], "first_scene": None}
        async with websockets.connect(f"ws://127.0.0.1:{port}/", subprotocols=["foxglove.websocket.v1"]) as fox, \
                websockets.connect(f"ws://127.0.0.1:{port}/ws") as page:
            self.assertEqual(fox.subprotocol, "foxglove.websocket.v1")
            self.assertEqual(json.loads(await asyncio.wait_for(fox.recv(), 10))["op"], "serverInfo")
            adv = json.loads(await asyncio.wait_for(fox.recv(), 10))
            self.assertEqual(adv["op"], "advertise")
            channels = {c["topic"]: c for c in adv["channels"]}
            self.assertEqual({t: c["schemaName"] for t, c in channels.items()}, LIVE_CHANNELS)
            for c in channels.values():
                self.assertEqual((c["encoding"], c["schemaEncoding"]), ("json", "jsonschema"))
                self.assertEqual(json.loads(c["schema"])["type"], "object")
            hello = json.loads(await asyncio.wait_for(page.recv(), 10))
            self.assertEqual((hello["mode"], hello["first_tick"], hello["last_tick"]), ("replay", 0, 300))
            subs = {20: channels["/scene"]["id"], 21: channels["/robots/poses"]["id"],
                    22: channels["/robots/telemetry"]["id"]}
            await fox.send(json.dumps({"op": "subscribe",
                                       "subscriptions": [{"id": k, "channelId": v} for k, v in subs.items()]}))

            async def poses_of(tick):
                """Foxglove's messages until the poses of `tick` (the scene and telemetry on the way kept)."""
                deadline = time.monotonic() + 30
                while time.monotonic() < deadline:
                    m = await asyncio.wait_for(fox.recv(), 30)
                    self.assertIsInstance(m, bytes, f"a status instead of data: {m}")
                    self.assertEqual(m[0], 1, "Message Data opcode")
                    sub = struct.unpack_from("<I", m, 1)[0]
                    stamp = struct.unpack_from("<Q", m, 5)[0] / 1e9
                    payload = json.loads(m[13:])
                    if sub == 21 and (tick is None or payload["tick"] == tick):
                        return payload["tick"], payload["poses"]
                    if sub == 22:
                        got["telemetry"].append((stamp, payload))
                    elif sub == 20 and got["first_scene"] is None:
                        got["first_scene"] = payload
                raise AssertionError(f"no poses of tick {tick} within 30 s")

            for tick in (0, 137, 300):
                await page.send(json.dumps({"cmd": "seek", "value": tick}))
                got["seeks"].append(await poses_of(tick))
            await page.send(json.dumps({"cmd": "seek", "value": 100}))
            await poses_of(100)
            await page.send(json.dumps({"cmd": "speed", "value": 5}))
            await page.send(json.dumps({"cmd": "play"}))
            while len(got["played"]) < 8:
                got["played"].append(await poses_of(None))
            await page.send(json.dumps({"cmd": "pause"}))
            # clientPublish: the same commands on Foxglove's /control channel.
            await fox.send(json.dumps({"op": "advertise", "channels": [
                {"id": 5, "topic": "/control", "encoding": "json"}]}))
            await fox.send(b"\x01" + struct.pack("<I", 5) + b'{"cmd": "seek", "value": 250}')
            got["controlled"] = (await poses_of(250))[0]
        return got

    @unittest.skipUnless(shutil.which("node"), "node missing (scripts/setup installs nodejs)")
    def test_mcap_export_reads_back_with_the_live_channels(self):
        out = os.path.join(self.dir, "plain.mcap")
        done = subprocess.run([vh.SWARM, "export", self.plain, "--mcap", out], capture_output=True, text=True,
                              timeout=300, env=dict(os.environ, SWARM_NO_BUILD="1"))
        self.assertEqual(done.returncode, 0, done.stderr)
        self.assertIn("messages on 5 channels, ticks 0..300", done.stderr)
        back = subprocess.run(["node", MCAP_READER, out], capture_output=True, text=True, timeout=120)
        self.assertEqual(back.returncode, 0, back.stderr)
        m = json.loads(back.stdout)
        self.assertIn("@mcap/core", m["library"])
        self.assertEqual({c["topic"]: c["schema_name"] for c in m["channels"]}, LIVE_CHANNELS)
        for c in m["channels"]:
            self.assertEqual((c["message_encoding"], c["schema_encoding"]), ("json", "jsonschema"), c["topic"])
            self.assertEqual(c["count"], 301, f"{c['topic']}: one message a recorded tick, 0..300")
        self.assertEqual(int(m["message_count"]), 5 * 301)
        # First and last log times: the run's start (world.json's time) plus tick / tick_rate.
        start = os.stat(os.path.join(self.plain, "world.json")).st_mtime_ns
        self.assertEqual(int(m["message_start_time"]), start)
        self.assertEqual(int(m["message_end_time"]), start + 30 * 10**9)
        self.assertEqual(m["metadata"]["swarmform"]["last_tick"], "300")
        # The messages are the live server's: poses of tick 300 are robots.csv's; the scene holds the arena.
        poses = m["last"]["/robots/poses"]["payload"]
        self.assertEqual(poses["tick"], 300)
        rows = vh.rows_at(self.plain, 300)
        for rid, p in enumerate(poses["poses"]):
            self.assertAlmostEqual(p["position"]["x"], float(rows[rid]["x"]), places=9)
        self.assertEqual([e["id"] for e in m["first"]["/scene"]["payload"]["entities"]][:3],
                         ["arena", "obstacles", "robots"])
        self.assertEqual(m["last"]["/tf"]["payload"]["transforms"][8]["child_frame_id"], "robot_8")
        self.assertEqual(len(m["last"]["/metrics"]["payload"]["net_force"]), 9)

    def test_mcap_export_says_what_is_wrong(self):
        swarm = [vh.SWARM, "export"]
        env = dict(os.environ, SWARM_NO_BUILD="1")
        helped = subprocess.run(swarm + ["--help"], capture_output=True, text=True, timeout=60, env=env)
        self.assertEqual(helped.returncode, 0)
        self.assertIn("--mcap", helped.stdout)
        out = os.path.join(self.dir, "x.mcap")
        not_run = subprocess.run(swarm + [self.dir + "/nothing", "--mcap", out], capture_output=True, text=True,
                                 timeout=60, env=env)
        self.assertEqual(not_run.returncode, 2)
        self.assertIn("not a directory (expected a run directory", not_run.stderr)
        self.assertFalse(os.path.exists(out))
        # A robots.csv with bytes overwritten mid-file: said as `swarm report` says it, the rest exported.
        damaged = os.path.join(self.dir, "damaged")
        shutil.copytree(self.plain, damaged)
        path = os.path.join(damaged, "robots.csv")
        size = os.path.getsize(path)
        with open(path, "r+b") as f:
            f.seek(size // 2)
            f.write(b"\xff" * 300)
        said = subprocess.run(swarm + [damaged, "--mcap", out], capture_output=True, text=True, errors="replace",
                              timeout=300, env=env)
        self.assertEqual(said.returncode, 0, said.stderr)
        self.assertIn("swarm export: damaged recording: ", said.stderr)
        self.assertIn("robots.csv", said.stderr)
        self.assertTrue(os.path.exists(out))

    def test_replay_of_a_broken_run_directory_says_what(self):
        bad = os.path.join(self.dir, "bad")
        os.makedirs(bad)
        shutil.copy(os.path.join(self.plain, "robots.csv"), bad)
        cases = [("{\"arena\": ", "world.json: not valid JSON"),
                 ("{\"robots\": 9}", "world.json: missing 'arena' object"),
                 ("{\"arena\": {\"centre\": [0, 0], \"width\": -1, \"height\": 5}}", "world.json: arena: width and "
                                                                                         "height must be positive"),
                 (None, "robots.csv: cannot open")]
        for world, message in cases:
            if world is None:
                shutil.copy(os.path.join(self.plain, "world.json"), bad)
                os.remove(os.path.join(bad, "robots.csv"))
            else:
                with open(os.path.join(bad, "world.json"), "w") as f:
                    f.write(world)
            p = self.view(bad, vh.free_port())
            out, _ = p.communicate(timeout=60)
            self.assertEqual(p.returncode, 2, out)
            self.assertIn(f"{bad}/{message}", out)


@unittest.skipUnless(vh.built("viewer"), f"swarm_viewer not built in {vh.BUILD_DIR}")
@unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
class ViewedFolderTest(unittest.TestCase):
    """A test of `swarm view` on one run folder, `self.dir` (made by setUp, removed here), with a headless page."""

    def tearDown(self):
        if self.browser:
            self.browser.close()
        if self.proc:
            try:
                os.killpg(self.proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            self.proc.wait(timeout=10)
        shutil.rmtree(self.dir)

    def open_view(self):
        """`swarm view self.dir` in its own process group and a page navigated to it; the caller waits for it."""
        port = vh.free_port()
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=vh.BUILD_DIR)
        self.proc = subprocess.Popen([vh.SWARM, "view", self.dir, "--port", str(port)], stdin=subprocess.DEVNULL,
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                                     start_new_session=True)
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        b = self.browser = cdp.Browser()
        b.navigate(url)
        return b


class KheperaReplayTest(ViewedFolderTest):
    """`swarm view` of a recording with a floor, a light, LEDs and sensors' readings (tests/scripts/fixture.py, no
    DDS): the page draws the floor's image (the run folder's copy), its regions and the light from world.json, each
    live robot's lit LEDs from the frames, and the selected robot's readings (readings.csv) in its panel."""

    def setUp(self):
        import fixture  # tests/scripts (viewer_helpers puts it on the path)
        self.fixture = fixture
        self.dir = tempfile.mkdtemp(prefix="sf-view-khepera-")
        # A floor image, the run folder's copy as world.json names it: the arena's west half red, the east half
        # the floor's own grey.
        import numpy as np
        from matplotlib import pyplot as plt
        pixels = np.full((6, 8, 3), 230 / 255)
        pixels[:, :4] = (1.0, 0.0, 0.0)
        plt.imsave(os.path.join(self.dir, "floor.png"), pixels)
        doc = fixture.make_khepera_run(self.dir, floor_image="floor.png")
        # A gate that a world event puts in place at tick 5 (docs/scenario-format.md, World events).
        doc["obstacles"] = [{"kind": "box", "name": "gate", "centre": [2.5, -2.3], "half_extents": [0.3, 0.3],
                             "yaw": 0.0, "present": False}]
        doc["world_events"] = [{"tick": 5, "obstacle": 0, "name": "gate", "do": "appear"}]
        # A goal that a world event moves at tick 6 (world.json's goal_moves).
        doc["goal"] = {"x": -2.0, "y": 2.0, "radius": 0.4}
        doc["goal_moves"] = [{"tick": 6, "x": 3.0, "y": 1.0, "radius": 0.3}]
        with open(os.path.join(self.dir, "world.json"), "w") as f:
            json.dump(doc, f)
        self.proc = None
        self.browser = None

    def test_the_floor_the_light_and_the_leds_are_drawn(self):
        b = self.open_view()
        b.wait_for("window.sfViewer && sfViewer.replay && sfViewer.frame", what="the recording loaded")

        def scrub(tick):
            b.eval(f"(() => {{ const t = document.getElementById('timeline'); t.value = '{tick}';"
                   " t.dispatchEvent(new Event('input')); })()")
            b.wait_for(f"sfViewer.frame.tick === {tick}", what=f"tick {tick}")

        b.wait_for("sfViewer.floorImage && sfViewer.floorImage.complete && sfViewer.floorImage.naturalWidth === 8",
                   what="the floor image served from the run folder")
        # The gate is drawn from the tick of its world event on, not before.
        gate, obstacle, floor = (2.6, -2.4), (109, 76, 65), (230, 230, 230)
        scrub(3)
        img, _ = b.screenshot()
        got, d = vh.drawn_near(img, *vh.check_projection(self, b, *gate), floor)
        self.assertLessEqual(d, 12, f"the gate before tick 5: drawn {got}, want the floor")
        self.assertEqual(b.eval("sfViewer.drawn.goal"), {"x": -2.0, "y": 2.0, "radius": 0.4}, "the goal at first")
        scrub(7)
        self.assertEqual(b.eval("sfViewer.drawn.goal"), {"x": 3.0, "y": 1.0, "radius": 0.3}, "moved at tick 6")
        robots = b.eval("sfViewer.frame.robots")
        leds = {r["id"]: r.get("leds") for r in robots}
        self.assertEqual(leds, {0: ["#00ff00"] * 3, 1: ["#ff0000", "#000000", "#0000ff"], 2: None,
                                3: ["#00ff00", "#000000", "#000000"]})
        img, _ = b.screenshot()
        for (x, y), want, what in (((-1.5, 1.8), (0, 0, 255), "the blue disc"),
                                   ((-1.7, -1.3), (255, 0, 0), "the image's west half"),
                                   ((2.3, -0.9), (77, 77, 77), "the grey band"),
                                   ((3.5, 0.5), (230, 230, 230), "the floor's grey 0.9"),
                                   ((3.0, 1.8), (255, 214, 0), "the light"),
                                   (gate, obstacle, "the gate, there from tick 5")):
            px, py = vh.check_projection(self, b, x, y)
            got, d = vh.drawn_near(img, px, py, want)
            self.assertLessEqual(d, 12, f"{what} at ({px:.1f}, {py:.1f}): drawn {got}, want {want}")
        # Robot 0's LED 0 ahead of its centre (heading 0), LED 1 of robot 1 is off: its body's colour there.
        scale = b.eval("sfViewer.view.scale")
        rr = b.eval("Math.max(4, sfViewer.world.robot_radius * sfViewer.view.scale)")
        r0 = [r for r in robots if r["id"] == 0][0]
        px, py = vh.check_projection(self, b, r0["x"] + 0.55 * rr / scale, r0["y"])
        got, d = vh.drawn_near(img, px, py, (0, 255, 0))
        self.assertLessEqual(d, 24, f"robot 0's LED 0 at ({px:.1f}, {py:.1f}): drawn {got}")  # a small dot: smoothed
        r1 = [r for r in robots if r["id"] == 1][0]
        angle = 2 * math.pi / 3
        px, py = vh.check_projection(self, b, r1["x"] + 0.55 * rr / scale * math.cos(angle),
                                     r1["y"] + 0.55 * rr / scale * math.sin(angle))
        got, d = vh.drawn_near(img, px, py, (158, 158, 158))  # the state's grey (#9e9e9e), no dot
        self.assertLessEqual(d, 12, f"robot 1's LED 1 is off, yet drawn {got} at ({px:.1f}, {py:.1f})")
        # readings.csv in the frames of the robot a page selects (and of no other), in the live frames' form
        # (frame_json.hpp add_readings), and in its panel drawn by the live view's code; a dead robot (3, from
        # tick 11) has none. The behaviour's telemetry column "light" (a number) is not taken for the light
        # ring's readings.
        sensed = {"proximity", "lidar", "battery"}
        self.assertFalse([r["id"] for r in robots if sensed & set(r)], "readings before any robot was selected")
        b.eval("sfViewer.select(1)")
        b.wait_for("sfViewer.frame.robots.find((r) => r.id === 1).proximity", what="robot 1's readings")
        robots = b.eval("sfViewer.frame.robots")
        r1 = [r for r in robots if r["id"] == 1][0]
        want = self.fixture.khepera_readings(7, 1)
        self.assertEqual((r1["proximity"], r1["lidar"], r1["battery"]),
                         (want[:8], {"rays": 682, "nearest_angle": 0.5236, "nearest_range": 0.57}, 0.73))
        self.assertEqual([r["id"] for r in robots if sensed & set(r)], [1])
        scrub(12)
        fields = b.eval("document.getElementById('robot-fields').textContent")
        for text in ("proximity (0..1)0.01 0.11 0.21 0.31 0.41 0.51 0.61 0.71",
                     "lidar682 rays, nearest 0.62 m at 30°", "battery68 %", "light0.120"):
            self.assertIn(text, fields)
        b.eval("sfViewer.select(3)")
        # The frame sent again for the new selection: robot 1's readings gone with it.
        b.wait_for("!sfViewer.frame.robots.find((r) => r.id === 1).proximity", what="the frame after selecting 3")
        self.assertEqual(b.eval("document.getElementById('panel-id').textContent"), "3")
        r3 = [r for r in b.eval("sfViewer.frame.robots") if r["id"] == 3][0]
        self.assertFalse(sensed & set(r3), r3)
        self.assertNotIn("proximity", b.eval("document.getElementById('robot-fields').textContent"))


@unittest.skipUnless(vh.built("viewer"), f"swarm_viewer not built in {vh.BUILD_DIR}")
@unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
class GroupsReplayTest(ViewedFolderTest):
    """`swarm view` of a mixed swarm's recording (world.json `groups`; tests/scripts/fixture.py, no DDS): each robot
    is filled by its own group's state colours and outlined in its group's colour, and the legend has a line per
    group naming its behaviour and ids."""

    def setUp(self):
        import fixture  # tests/scripts (viewer_helpers puts it on the path)
        self.dir = tempfile.mkdtemp(prefix="sf-view-groups-")
        fixture.make_run(self.dir, ticks=30, robots=7)
        path = os.path.join(self.dir, "world.json")
        with open(path) as f:
            doc = json.load(f)
        green = [{"value": v, "name": f"paper{v}", "colour": "#00ff00"} for v in range(7)]
        blue = [{"value": v, "name": f"walk{v}", "colour": "#0000ff"} for v in range(7)]
        doc["groups"] = [{"name": "shapers", "first_id": 0, "count": 4,
                          "behaviour_descriptor": {"name": "paper", "states": green}},
                         {"name": "movers", "first_id": 4, "count": 3,
                          "behaviour_descriptor": {"name": "random_walk", "states": blue}}]
        with open(path, "w") as f:
            json.dump(doc, f)
        self.proc = None
        self.browser = None

    def test_each_robot_is_drawn_in_its_groups_colours_with_a_legend_line_per_group(self):
        b = self.open_view()
        b.wait_for("window.sfViewer && sfViewer.replay && sfViewer.frame && sfViewer.drawn.groups"
                   " && sfViewer.drawn.groups.movers", what="the recording drawn")
        drawn = b.eval("sfViewer.drawn.groups")
        self.assertEqual(sorted(drawn), ["movers", "shapers"])
        shapers = {d["id"]: (d["fill"], d["outline"]) for d in drawn["shapers"]}
        movers = {d["id"]: (d["fill"], d["outline"]) for d in drawn["movers"]}
        self.assertEqual(sorted(shapers), [0, 1, 2, 3])
        self.assertEqual(sorted(movers), [4, 5, 6])
        self.assertEqual({f for f, _ in shapers.values()}, {"#00ff00"})
        self.assertEqual({f for f, _ in movers.values()}, {"#0000ff"})
        outlines = {o for _, o in shapers.values()} | {o for _, o in movers.values()}
        self.assertEqual(len(outlines), 2, "one outline colour a group")
        legend = b.eval("document.getElementById('legend').textContent")
        self.assertIn("shapers (paper, 0..3)", legend)
        self.assertIn("movers (random_walk, 4..6)", legend)
        self.assertIn("walk0", legend)
        # A selected robot's panel names its group and its state by its own behaviour's names.
        b.eval("sfViewer.select(5)")
        b.wait_for("document.getElementById('panel-id').textContent === '5 (group movers)'", what="robot 5's panel")
        self.assertIn("walk", b.eval("document.getElementById('robot-fields').textContent"))


@unittest.skipUnless(vh.built("viewer"), f"swarm_viewer not built in {vh.BUILD_DIR}")
@unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
class DamagedReplayTest(unittest.TestCase):
    """`swarm view` of a damaged recording (tests/scripts/fixture.py, 7 robots, 80 ticks, no DDS): corrupt bytes in
    the middle are a banner on the page at the ticks they touch (a seek into the lost ticks says it instead of
    showing a frozen frame) and a line on the terminal at once; a recording cut by a killed world is shown up to its
    last whole tick with a notice that it ends early. `swarm report` and `swarm replay` say the same damage
    (recording.robots_damage: the same words, line and byte)."""

    def setUp(self):
        import fixture  # tests/scripts (viewer_helpers puts it on the path)
        from swarmform import recording  # scripts/ (tests/scripts/helpers puts it on the path)
        self.recording = recording
        self.dir = tempfile.mkdtemp(prefix="sf-view-damage-")
        fixture.make_run(self.dir, ticks=80, robots=7, death=None)
        self.csv = os.path.join(self.dir, "robots.csv")
        with open(self.csv, "rb") as f:
            self.text = f.read()
        self.proc = None
        self.browser = None
        self.log = os.path.join(tempfile.mkdtemp(prefix="sf-view-damage-log-"), "view.log")

    def tearDown(self):
        if self.browser:
            self.browser.close()
        if self.proc and self.proc.poll() is None:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait(timeout=10)
        shutil.rmtree(self.dir)
        shutil.rmtree(os.path.dirname(self.log))

    def row_at(self, tick, rid):
        return self.text.index(f"\n{tick},{rid},".encode()) + 1

    def view(self):
        port = vh.free_port()
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=vh.BUILD_DIR)
        with open(self.log, "wb") as out:
            self.proc = subprocess.Popen([vh.SWARM, "view", self.dir, "--port", str(port)], stdin=subprocess.DEVNULL,
                                         stdout=out, stderr=subprocess.STDOUT, env=env, start_new_session=True)
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        self.port = port
        b = self.browser = cdp.Browser()
        b.navigate(url)
        b.wait_for("window.sfViewer && sfViewer.replay && sfViewer.frame", what="the recording loaded")
        return b

    async def foxglove_statuses(self, port):
        async with websockets.connect(f"ws://127.0.0.1:{port}/", subprotocols=["foxglove.websocket.v1"]) as fox:
            ops = [json.loads(await asyncio.wait_for(fox.recv(), 10)) for _ in range(4)]
        self.assertEqual([m["op"] for m in ops[:2]], ["serverInfo", "advertise"])
        return ops[2:]

    def terminal_says(self, text, timeout=20):
        """`swarm view`'s output holds `text` while it still runs (not only once it exits)."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            self.assertIsNone(self.proc.poll(), "swarm view exited")
            with open(self.log, errors="replace") as f:
                if text in f.read():
                    return
            time.sleep(0.1)
        with open(self.log, errors="replace") as f:
            self.fail(f"{text!r} not on the terminal within {timeout} s: {f.read()}")

    def scrub(self, b, tick):
        b.eval(f"(() => {{ const t = document.getElementById('timeline'); t.value = '{tick}';"
               " t.dispatchEvent(new Event('input')); })()")
        b.wait_for(f"sfViewer.frame.at === {tick}", what=f"the timeline at tick {tick}")

    def test_corrupt_bytes_in_the_middle_are_said_at_their_ticks(self):
        start = self.row_at(40, 3)
        cut_from, cut_to = start + 4, self.row_at(43, 1) + 5
        with open(self.csv, "wb") as f:
            f.write(self.text[:cut_from] + b"x" * (cut_to - cut_from) + self.text[cut_to:])
        python = self.recording.robots_damage(self.csv, 7)
        self.assertEqual([(d.from_tick, d.to_tick) for d in python], [(40, 42), (43, 43)])
        b = self.view()
        self.scrub(b, 10)
        self.assertTrue(b.eval("document.getElementById('banner').hidden"), "a banner before the damage")
        # Into the lost ticks: the last readable tick, and the banner that says why, naming file and byte.
        self.scrub(b, 41)
        self.assertEqual(b.eval("sfViewer.frame.tick"), 40)
        self.assertFalse(b.eval("document.getElementById('banner').hidden"))
        banner = b.eval("document.getElementById('banner').textContent")
        self.assertIn("tick 41 cannot be read: showing tick 40, the last readable one before it", banner)
        self.assertIn(f"damaged recording: robots.csv byte {start} (ticks 40..42): {python[0].what}", banner)
        self.assertEqual(b.eval("sfViewer.frame.robots.length"), 3, "tick 40's readable rows")
        self.terminal_says(f"{self.csv} byte {start} (tick 40..42): {python[0].what}")
        # The tick after the damage lost its first rows: said from that tick, and no more after it.
        self.scrub(b, 43)
        self.assertIn(python[1].what, b.eval("document.getElementById('banner').textContent"))
        self.scrub(b, 44)
        self.assertTrue(b.eval("document.getElementById('banner').hidden"))
        # A Foxglove client is told the damage found so far, as warnings (status level 1).
        statuses = asyncio.run(self.foxglove_statuses(self.port))
        self.assertEqual(statuses, [{"op": "status", "level": 1, "id": f"damage-{d.offset}",
                                     "message": f"damaged recording: {self.csv} byte {d.offset} "
                                                f"({'tick' if d.from_tick == d.to_tick else 'ticks'} {d.from_tick}"
                                                f"{'' if d.from_tick == d.to_tick else f'..{d.to_tick}'}): {d.what}"}
                                    for d in python])
        # SIGTERM on `swarm view`: the viewer is stopped and says what it skipped on the way out.
        os.killpg(self.proc.pid, signal.SIGTERM)
        self.proc.wait(timeout=20)
        with open(self.log, errors="replace") as f:
            self.assertIn("row(s) of robots.csv skipped; the first: ", f.read())

    def test_a_cut_recording_is_shown_to_its_last_whole_tick_and_says_it_ends_early(self):
        at = self.row_at(79, 3)
        with open(self.csv, "wb") as f:
            f.write(self.text[:at + 9])  # a killed world: tick 79 has robots 0..2 and half of 3's row
        os.remove(os.path.join(self.dir, "summary.json"))
        python = self.recording.robots_damage(self.csv, 7)
        self.assertEqual(len(python), 1)
        self.assertTrue(python[0].at_open)
        b = self.view()
        self.assertEqual(b.eval("[sfViewer.replay.first, sfViewer.replay.last]"), [0, 78])
        notice = b.eval("document.getElementById('notice').textContent")
        self.assertFalse(b.eval("document.getElementById('notice').hidden"))
        self.assertIn(f"recording ends early: robots.csv byte {python[0].offset} (tick 78): {python[0].what}", notice)
        self.assertIn("the run did not finish (no summary.json): the recording ends at tick 78", notice)
        self.terminal_says(f"{self.csv} byte {python[0].offset} (tick 78): {python[0].what}")
        self.scrub(b, 78)
        self.assertEqual(b.eval("sfViewer.frame.robots.length"), 7)
        self.assertEqual(b.eval("sfViewer.frame.robots.filter((r) => r.alive).length"), 7)


if __name__ == "__main__":
    unittest.main()
