"""The live view (viewer/README.md) against a real lockstep swarm (world_server + robot_agent + swarm_viewer through
scripts/swarm, DDS test domain offset 62, one run at a time): in a headless Chromium the page draws the robots where
robots.csv puts them in their state's colour, pause holds the tick, step 1 moves it by exactly one, a click on a
robot opens its panel; a Foxglove client (foxglove.websocket.v1) gets the channels with their schemas, and poses
that are robots.csv's; the aggregation example's frames carry its gathered robots' green LEDs, and a mixed swarm's
each robot's own group's telemetry columns. Controls say what they
do: a kill while paused is shown at once, a page closed while paused resumes the run after the grace, a run's end
(max_ticks) is shown as such, and a realtime run's controls are disabled saying why."""

import asyncio
import json
import math
import os
import shutil
import signal
import struct
import tempfile
import time
import unittest

import viewer_helpers as vh

import websockets.exceptions  # noqa: F401 (websockets.exceptions below)
import websockets  # Debian's python3-websockets (scripts/setup)

import cdp
import foxglove_schemas

SCENARIO = os.path.join(vh.ROOT, "scenarios", "paper.yaml")
AGGREGATION_DIR = os.path.join(vh.BUILD_DIR, "examples", "behaviours", "aggregation")
DISPERSION_DIR = os.path.join(vh.BUILD_DIR, "examples", "behaviours", "dispersion")
# A mixed swarm of two plug-ins whose telemetry columns differ (written here, not a shipped scenario).
MIXED_SCENARIO = """description: gatherers and spreaders, each group with its own telemetry columns
arena: {centre: [0.0, 0.0], width: 9.0, height: 9.0, walls: true}
comm_range: 3.0
mode: lockstep
tick_rate: 10
seed: 4
max_ticks: 60
groups:
  - name: gatherers
    behaviour: {plugin: libaggregation.so, params: {stop_distance: 0.4}}
    robots: {count: 5, region: {centre: [-2.0, 0.0], width: 3.0, height: 3.0}}
  - name: spreaders
    behaviour: {plugin: libdispersion.so, params: {spacing: 1.0}}
    robots: {count: 4, region: {centre: [2.0, 0.0], width: 1.5, height: 1.5}}
"""


@unittest.skipUnless(vh.built("world", "agent", "viewer"), f"world_server/robot_agent/swarm_viewer not built in "
                                                          f"{vh.BUILD_DIR}")
class LiveViewTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.mkdtemp(prefix="sf-view-")
        self.runs = []
        self.browser = None

    def tearDown(self):
        if self.browser:
            self.browser.close()
        for r in self.runs:
            r.stop()
        leftovers = vh.processes_mentioning(self.dir)
        for pid in leftovers:
            os.kill(pid, signal.SIGKILL)
        shutil.rmtree(self.dir)
        self.assertEqual(leftovers, [], "a process of this test was left running")

    def start(self, out, *extra, domain):
        r = vh.SwarmRun("--scenario", SCENARIO, "--domain", str(domain), "--out", out, "--no-pictures", *extra)
        self.runs.append(r)
        return r

    @unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
    def test_page_draws_pauses_steps_and_selects(self):
        out = os.path.join(self.dir, "run")
        port = vh.free_port()
        run = self.start(out, "--view-paused", "--view", str(port), "--max-ticks", "400",
                         domain=vh.helpers.test_domain(62))
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        b = self.browser = cdp.Browser()
        b.navigate(url)
        frame = "window.sfViewer && sfViewer.frame"
        b.wait_for(f"{frame} && sfViewer.frame.paused && sfViewer.frame.tick === 0", what="a paused frame of tick 0")
        # A paused start holds tick 0 until the page says go.
        time.sleep(1.0)
        self.assertEqual(b.eval("sfViewer.frame.tick"), 0)
        self.assertEqual(b.eval("document.getElementById('run-state').textContent"), "PAUSED")
        # A speed cap, so that the run is still going when the test pauses it; then go.
        b.eval("document.getElementById('speed').value = '60'")
        b.click_element("speed-set")
        b.wait_for("sfViewer.frame.speed_cap === 60", what="the speed cap in the frames")
        b.click_element("resume")
        b.wait_for("sfViewer.frame.tick >= 50", timeout=60, what="tick 50")
        b.click_element("pause")
        b.wait_for("sfViewer.frame.paused", what="paused")
        tick = b.eval("sfViewer.frame.tick")
        self.assertGreaterEqual(tick, 50)
        # Paused: the tick does not move for 2 s.
        for _ in range(10):
            time.sleep(0.2)
            self.assertEqual(b.eval("sfViewer.frame.tick"), tick, "the tick moved while paused")
        img, png = b.screenshot()
        with open(os.path.join(self.dir, "page.png"), "wb") as f:
            f.write(png)
        # Where the page projects each robot of its frame, and the state colours it was given.
        drawn = b.eval("""(() => { const c = document.getElementById('arena').getBoundingClientRect();
            return {x0: c.x, y0: c.y, states: Array.from(sfViewer.states, ([v, s]) => [v, s.colour]),
                    view: sfViewer.view, w: c.width, h: c.height}; })()""")
        # Step once: exactly one tick further, and held there.
        b.click_element("step1")
        b.wait_for(f"sfViewer.frame.tick === {tick + 1} && sfViewer.frame.paused", what="one step")
        time.sleep(1.0)
        self.assertEqual(b.eval("sfViewer.frame.tick"), tick + 1)
        # Click a robot: its panel shows its id.
        rid = 4
        x, y = b.eval(f"(() => {{ const r = sfViewer.frame.robots.find(q => q.id === {rid});"
                      f" const c = document.getElementById('arena').getBoundingClientRect();"
                      f" const p = sfViewer.project(r.x, r.y); return [c.x + p[0], c.y + p[1]]; }})()")
        b.click(x, y)
        b.wait_for(f"document.getElementById('panel-id').textContent === '{rid}'", what="robot 4's panel")
        self.assertFalse(b.eval("document.getElementById('robot').hidden"))
        heard = b.eval("document.getElementById('robot-fields').textContent")
        self.assertIn("heard", heard)
        self.assertIn("ultrasonic", heard)
        self.assertIn("last command", heard)
        # The optional sensors' rows: the paper's behaviour declares none, so the frame's robot is given the
        # readings a frame carries for one that does (frame_json.cpp), and picked again in the same call (a
        # paused run may send its frame again).
        shown = b.eval(f"""(() => {{ const r = sfViewer.frame.robots.find(q => q.id === {rid});
            r.proximity = [1, 0, 0, 0, 0, 0, 0, 0.25]; r.light = [0.5, 0, 0, 0, 0, 0, 0, 0.125];
            r.ground = [0, 1, 1, 0.5]; r.lidar = {{rays: 682, nearest_angle: 0.5236, nearest_range: 0.42}};
            r.battery = 0.37;
            const c = document.getElementById('arena'), box = c.getBoundingClientRect();
            const p = sfViewer.project(r.x, r.y);
            for (const t of ['mousedown', 'mouseup'])
              c.dispatchEvent(new MouseEvent(t, {{clientX: box.x + p[0], clientY: box.y + p[1], bubbles: true}}));
            return document.getElementById('robot-fields').textContent; }})()""")
        for row in ("proximity (0..1)1.00 0.00 0.00 0.00 0.00 0.00 0.00 0.25", "light (0..1)0.50",
                    "ground (0..1)0.00 1.00 1.00 0.50", "lidar682 rays, nearest 0.42 m at 30°", "battery37 %"):
            self.assertIn(row, shown)
        # Kill it from its panel (the path of --kill: at the next round), then let the run end; robots.csv then
        # holds the paused tick's rows. The rows made up above move the kill button down until the next frame
        # draws the panel again: the click waits for that, and the page says it sent the kill before resuming.
        b.wait_for("!document.getElementById('robot-fields').textContent.includes('battery')",
                   what="the panel drawn again from a frame")
        b.click_element("kill")
        b.wait_for("document.getElementById('kill-state').textContent.startsWith('kill sent')",
                   what="the page's kill sent")
        b.click_element("resume")
        code, text = run.wait(timeout=120)
        self.assertEqual(code, 0, text)
        with open(os.path.join(out, "summary.json")) as f:
            deaths = json.load(f)["deaths"]
        self.assertEqual([d["id"] for d in deaths], [rid], "the robot killed from the page")
        self.assertGreater(deaths[0]["tick"], tick)
        self.assertIn(f"viewer at http://127.0.0.1:{port}/", text)
        rows = vh.rows_at(out, tick)
        self.assertEqual(len(rows), 9)
        self.assertTrue(all(r["alive"] == "1" for r in rows.values()))
        colours = {int(v): c for v, c in drawn["states"]}

        self.assertEqual(b.eval("sfViewer.view"), drawn["view"])
        wrong = []
        for rid, r in rows.items():
            # The page's projection (its view has not moved since the screenshot), checked against the arena frame.
            px, py = vh.check_projection(self, b, float(r["x"]), float(r["y"]))
            want = vh.hex_rgb(colours[int(r["state"])])
            got, d = vh.drawn_near(img, px, py, want)
            if d > 12:
                wrong.append(f"robot {rid} at ({px:.1f}, {py:.1f}): drawn {got}, its state {r['state']} is {want}")
        self.assertEqual(wrong, [], "robots not drawn where robots.csv puts them (screenshot: page.png)")


    @unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
    def test_rays_from_the_rim_layers_keys_and_rates(self):
        """A selected robot's ultrasonic rays run from its sensor on the rim to the hit point (radius + reading from
        the centre); a layer switched off is not drawn; space, → and + / − act as the buttons; the status bar
        shows frames/s and the lag, and ticks/s says "paused" while paused."""
        out = os.path.join(self.dir, "keys")
        port = vh.free_port()
        self.start(out, "--view-paused", "--view", str(port), "--max-ticks", "2000",
                   domain=vh.helpers.test_domain(62))
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        b = self.browser = cdp.Browser()
        b.navigate(url)
        b.wait_for("window.sfViewer && sfViewer.frame && sfViewer.frame.paused", what="a paused frame")
        # − from no cap: a cap below the rate (10 while nothing is measured); + from there: the next faster.
        b.key("-")
        b.wait_for("sfViewer.frame.speed_cap === 10", what="the cap the − key set")
        b.key("+")
        b.wait_for("sfViewer.frame.speed_cap === 20", what="the cap the + key set")
        # space: go; the status bar then measures ticks, frames and the lag.
        b.key(" ")
        # Running until the robots have parents (the paper's first at tick 32), so the links layer has lines.
        b.wait_for("!sfViewer.frame.paused && sfViewer.frame.tick >= 30 && "
                   "sfViewer.frame.robots.some(r => r.alive && r.parent >= 0)", timeout=60,
                   what="running after space, with parent links")
        b.wait_for("sfViewer.rates.now && sfViewer.rates.now.tps !== null", what="a measured tick rate")
        tps = b.eval("sfViewer.rates.now.tps")
        self.assertLess(tps, 20 * 1.5, "ticks/s over a cap of 20")
        self.assertGreater(tps, 0)
        self.assertRegex(b.eval("document.getElementById('fps').textContent"), r"^\d+\.\d$")
        self.assertGreater(b.eval("sfViewer.rates.now.fps"), 0)
        self.assertRegex(b.eval("document.getElementById('lag').textContent"), r"^\d+(\.\d)? \(\d+ ms\)$")
        # space again: paused, and ticks/s says so (not a rate measured from frames of a held tick).
        b.key(" ")
        b.wait_for("sfViewer.frame.paused", what="paused by space")
        b.wait_for("document.getElementById('tps').textContent === 'paused'", what="ticks/s: paused")
        tick = b.eval("sfViewer.frame.tick")
        b.key("ArrowRight")
        b.wait_for(f"sfViewer.frame.tick === {tick + 1} && sfViewer.frame.paused", what="→: one step")
        self.assertEqual(b.eval("sfViewer.lastKey.action"), "step1")
        # Rays of robot 4, from the rim to the hit point.
        b.eval("sfViewer.select(4)")
        got = b.eval("""(() => { const r = sfViewer.frame.robots.find(q => q.id === 4);
            return {x: r.x, y: r.y, theta: r.theta, us: r.ultrasonic, rays: sfViewer.drawn.rays,
                    heard: sfViewer.drawn.heard, nheard: r.heard.length, radius: sfViewer.world.robot_radius}; })()""")
        self.assertEqual(len(got["rays"]), 5)
        angles = [-math.pi / 2, -math.pi / 4, 0, math.pi / 4, math.pi / 2]
        for (x0, y0, x1, y1), d, a in zip(got["rays"], got["us"], angles):
            self.assertAlmostEqual(math.hypot(x0 - got["x"], y0 - got["y"]), got["radius"], places=6,
                                   msg="a ray starts on the rim")
            self.assertAlmostEqual(math.hypot(x1 - got["x"], y1 - got["y"]), got["radius"] + d, places=6,
                                   msg="a ray ends at radius + reading")
            self.assertAlmostEqual(math.atan2(y0 - got["y"], x0 - got["x"]),
                                   math.atan2(math.sin(got["theta"] + a), math.cos(got["theta"] + a)), places=6)
        self.assertEqual(got["heard"], got["nheard"])
        # Each layer off: not drawn; on again: drawn.
        for layer, count in (("rays", "sfViewer.drawn.rays.length"), ("heard", "sfViewer.drawn.heard"),
                             ("links", "sfViewer.drawn.links"), ("ids", "sfViewer.drawn.ids"),
                             ("trails", "sfViewer.drawn.trails")):
            before = b.eval(count)
            if layer != "heard" or got["nheard"] > 0:
                self.assertGreater(before, 0, f"{layer} drawn while on")
            b.click_element(f"layer-{layer}")
            self.assertEqual(b.eval(count), 0, f"{layer} drawn while off")
            b.click_element(f"layer-{layer}")
            self.assertEqual(b.eval(count), before, f"{layer} back on")

    @unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
    def test_a_kill_while_paused_is_shown_at_once_and_a_closed_page_resumes_the_run(self):
        """Paused at tick 25, a kill from the page kills the agent now: the page shows it dead at tick 25 without a
        step, its button disabled saying why, and the world records the death at tick 25. The page closed while
        paused: after the grace (1 s here, --view-grace) the run resumes and both the viewer and the world say so."""
        out = os.path.join(self.dir, "kill")
        port = vh.free_port()
        run = self.start(out, "--view-paused", "--view", str(port), "--view-grace", "1", "--max-ticks", "60",
                         domain=vh.helpers.test_domain(62))
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        b = self.browser = cdp.Browser()
        b.navigate(url)
        b.wait_for("window.sfViewer && sfViewer.frame && sfViewer.frame.paused && sfViewer.frame.tick === 0",
                   what="a paused frame of tick 0")
        b.eval("document.getElementById('stepn-count').value = '25'")
        b.click_element("stepn")
        b.wait_for("sfViewer.frame.tick === 25 && sfViewer.frame.paused", what="paused at tick 25")
        b.eval("sfViewer.select(4)")
        b.wait_for("!document.getElementById('kill').disabled", what="robot 4's kill button")
        b.click_element("kill")
        b.wait_for("sfViewer.frame.robots.find((r) => r.id === 4).alive === false", timeout=20,
                   what="robot 4 dead while paused")
        self.assertEqual(b.eval("[sfViewer.frame.tick, sfViewer.frame.paused]"), [25, True])
        self.assertTrue(b.eval("document.getElementById('kill').disabled"))
        self.assertIn("robot 4 is dead", b.eval("document.getElementById('kill').title"))
        self.assertEqual(b.eval("document.getElementById('pause').title"), "disabled: the run is paused already")
        # The last page goes: the run waits the grace, then runs to its end.
        b.navigate("about:blank")
        code, text = run.wait(timeout=120)
        self.assertEqual(code, 0, text)
        self.assertIn("world_server: the viewer's last page closed while paused; running on after 1 s", text)
        with open(os.path.join(out, "logs", "viewer.log")) as f:
            log = f.read()
        self.assertIn("swarm_viewer: the last page closed while the run is paused at tick 25; it resumes in 1 s", log)
        with open(os.path.join(out, "summary.json")) as f:
            summary = json.load(f)
        self.assertEqual(summary["end_reason"], "max_ticks")
        self.assertEqual([(d["id"], d["tick"]) for d in summary["deaths"]], [(4, 25)])
        # As a kill between ticks: tick 25's rows were written before the pause, the death shows from tick 26's.
        self.assertEqual(vh.rows_at(out, 25)[4]["alive"], "1")
        self.assertEqual(vh.rows_at(out, 26)[4]["alive"], "0")

    @unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
    def test_a_run_that_reaches_max_ticks_is_shown_as_ended_so(self):
        out = os.path.join(self.dir, "end")
        port = vh.free_port()
        run = self.start(out, "--view-paused", "--view", str(port), "--max-ticks", "40",
                         domain=vh.helpers.test_domain(62))
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        b = self.browser = cdp.Browser()
        b.navigate(url)
        b.wait_for("window.sfViewer && sfViewer.frame && sfViewer.frame.paused", what="a paused frame")
        b.click_element("resume")
        b.wait_for("sfViewer.end !== null", timeout=60, what="the run's end")
        self.assertEqual(b.eval("document.getElementById('run-state').textContent"),
                         "run ended: max_ticks reached at tick 40")
        self.assertEqual(b.eval("document.getElementById('run-state').className"), "ended")
        self.assertEqual(b.eval("document.getElementById('tps').textContent"), "ended", "ticks/s after the end")
        for control in ("pause", "resume", "step1", "kill"):
            self.assertTrue(b.eval(f"document.getElementById('{control}').disabled"), control)
        self.assertEqual(b.eval("document.getElementById('step1').title"), "disabled: the run has ended")
        code, text = run.wait(timeout=60)
        self.assertEqual(code, 0, text)
        b.wait_for("sfViewer.closed", what="the viewer gone")
        self.assertEqual(b.eval("document.getElementById('run-state').textContent"),
                         "run ended: max_ticks reached at tick 40", "not 'disconnected' once the viewer is gone")

    @unittest.skipIf(not os.path.exists(cdp.CHROMIUM), "chromium missing (scripts/setup installs it)")
    def test_a_realtime_runs_controls_are_disabled_saying_why(self):
        """A realtime run ticks on the clock: pause, resume, step and the speed cap cannot act, so they are disabled
        with the reason in their tooltip; kill still acts."""
        out = os.path.join(self.dir, "realtime")
        port = vh.free_port()
        run = self.start(out, "--mode", "realtime", "--view", str(port), "--max-ticks", "100",
                         domain=vh.helpers.test_domain(62))
        url = f"http://127.0.0.1:{port}/"
        vh.wait_http(url)
        b = self.browser = cdp.Browser()
        b.navigate(url)
        b.wait_for("window.sfViewer && sfViewer.frame && !sfViewer.frame.finished", what="a realtime frame")
        self.assertFalse(b.eval("sfViewer.frame.controllable"))
        for control in ("pause", "resume", "step1", "stepn", "speed-set"):
            self.assertTrue(b.eval(f"document.getElementById('{control}').disabled"), control)
            self.assertIn("disabled: a realtime run: its ticks follow the clock",
                          b.eval(f"document.getElementById('{control}').title"))
        b.eval("sfViewer.select(2)")
        self.assertFalse(b.eval("document.getElementById('kill').disabled"), "kill acts in a realtime run")
        code, text = run.wait(timeout=120)
        self.assertEqual(code, 0, text)

    @unittest.skipUnless(os.path.exists(os.path.join(AGGREGATION_DIR, "libaggregation.so")),
                         f"the aggregation example is not built in {AGGREGATION_DIR}")
    def test_live_frames_carry_the_robots_lit_leds(self):
        """The aggregation example lights its LEDs green when gathered: every live frame's robot has `leds` all
        green exactly when its state is gathered (both from its last command), and some are."""
        out = os.path.join(self.dir, "leds")
        port = vh.free_port()
        scenario = os.path.join(vh.ROOT, "examples", "behaviours", "aggregation", "aggregation.yaml")
        run = vh.SwarmRun("--scenario", scenario, "--plugin-dir", AGGREGATION_DIR, "--domain",
                          str(vh.helpers.test_domain(62)), "--out", out, "--no-pictures", "--view-paused", "--view",
                          str(port))
        self.runs.append(run)
        vh.wait_http(f"http://127.0.0.1:{port}/")
        frames = asyncio.run(self.live_frames(port))
        code, text = run.wait(timeout=120)
        self.assertEqual(code, 0, text)
        gathered = 2  # aggregation.cpp's kGathered
        lit = 0
        for f in frames:
            for r in f["robots"]:
                if not r["alive"]:
                    continue
                want = ["#00ff00"] * 3 if r["state"] == gathered else None
                self.assertEqual(r.get("leds"), want, f"tick {f['tick']} robot {r['id']} state {r['state']}")
                lit += want is not None
        self.assertGreater(lit, 0, f"no gathered robot in {len(frames)} frames")

    @unittest.skipUnless(all(os.path.exists(os.path.join(d, f"lib{n}.so")) for d, n in
                             ((AGGREGATION_DIR, "aggregation"), (DISPERSION_DIR, "dispersion"))),
                         "the aggregation and dispersion examples are not built")
    def test_live_frames_carry_each_robots_own_groups_telemetry_columns(self):
        """A mixed swarm's live frames: each robot carries its own group's telemetry columns by name (the
        gatherers' neighbours and centroid_distance, the spreaders' nearest), never the other group's, with the
        values robots.csv records for that tick; the panel's field list is every group's."""
        out = os.path.join(self.dir, "mixed")
        scenario = os.path.join(self.dir, "mixed.yaml")
        with open(scenario, "w") as f:
            f.write(MIXED_SCENARIO)
        port = vh.free_port()
        run = vh.SwarmRun("--scenario", scenario, "--plugin-dir", AGGREGATION_DIR, "--plugin-dir", DISPERSION_DIR,
                          "--domain", str(vh.helpers.test_domain(62)), "--out", out, "--no-pictures",
                          "--view-paused", "--view", str(port))
        self.runs.append(run)
        vh.wait_http(f"http://127.0.0.1:{port}/")
        # 60 ticks at most 20 a second: 3 s of frames, however fast the host runs the ticks.
        frames = asyncio.run(self.live_frames(port, speed_cap=20))
        code, text = run.wait(timeout=120)
        self.assertEqual(code, 0, text)
        own = {"gatherers": {"neighbours", "centroid_distance"}, "spreaders": {"nearest"}}
        later = [f for f in frames if f["tick"] >= 5 and not f["finished"]]
        self.assertGreater(len(later), 0, f"no frame past tick 5 in {[(f['tick'], f['paused']) for f in frames]}; "
                                          f"the run said:\n{text}")
        for f in later:
            self.assertTrue(own["gatherers"] | own["spreaders"] <= set(f["telemetry_fields"]), f["telemetry_fields"])
            for r in f["robots"]:
                mine, theirs = (own["gatherers"], own["spreaders"]) if r["id"] < 5 else \
                    (own["spreaders"], own["gatherers"])
                self.assertTrue(mine <= set(r), f"tick {f['tick']} robot {r['id']}: {sorted(r)}")
                self.assertFalse(theirs & set(r), f"tick {f['tick']} robot {r['id']}: {sorted(r)}")
        # The values are the robot's own report, as robots.csv records it for the frame's tick.
        f = later[-1]
        rows = vh.rows_at(out, f["tick"])
        for r in f["robots"]:
            for name in own["gatherers"] if r["id"] < 5 else own["spreaders"]:
                self.assertEqual(r[name], float(rows[r["id"]][name]), f"tick {f['tick']} robot {r['id']} {name}")

    async def live_frames(self, port, speed_cap=None):
        """Every frame of the run (paused at tick 0 until resumed here, then as fast as it goes, or at most
        `speed_cap` ticks a second)."""
        frames = []
        async with websockets.connect(f"ws://127.0.0.1:{port}/ws") as page:
            await page.send(json.dumps({"cmd": "rate", "value": 60}))
            if speed_cap:
                await page.send(json.dumps({"cmd": "speed", "value": speed_cap}))
            await page.send(json.dumps({"cmd": "resume"}))
            deadline = time.monotonic() + 90
            while time.monotonic() < deadline:
                try:
                    m = json.loads(await asyncio.wait_for(page.recv(), 10))
                except (asyncio.TimeoutError, websockets.exceptions.ConnectionClosed):
                    break
                if m.get("type") == "frame":
                    frames.append(m)
                    if m["finished"]:
                        break
        return frames

    def test_foxglove_channels_schemas_and_poses(self):
        out = os.path.join(self.dir, "fox")
        port = vh.free_port()
        started = time.time()
        run = self.start(out, "--view-paused", "--view", str(port), "--max-ticks", "200",
                         "--view-control-origin", "https://app.foxglove.dev", domain=vh.helpers.test_domain(62))
        vh.wait_http(f"http://127.0.0.1:{port}/")
        got = asyncio.run(self.foxglove_session(port))
        code, text = run.wait(timeout=120)
        self.assertEqual(code, 0, text)
        checked = 0
        for stamp, tick, poses in got["poses"]:
            # Log time: the wall time of the run (not 1970), the tick in the message.
            self.assertGreaterEqual(stamp, started - 1)
            self.assertLessEqual(stamp, time.time() + 1)
            rows = vh.rows_at(out, tick)
            self.assertEqual(len(poses), len(rows))
            for rid, p in enumerate(poses):
                r = rows[rid]
                self.assertAlmostEqual(p["position"]["x"], float(r["x"]), places=9)
                self.assertAlmostEqual(p["position"]["y"], float(r["y"]), places=9)
                yaw = 2 * math.atan2(p["orientation"]["z"], p["orientation"]["w"])
                self.assertAlmostEqual(math.remainder(yaw - float(r["theta"]), 2 * math.pi), 0.0, places=9)
            checked += 1
        self.assertGreaterEqual(checked, 3, "too few pose messages to compare")
        entities = {e["id"]: e for e in got["first_scene"]["entities"]}
        self.assertEqual(list(entities), ["arena", "obstacles", "robots", "parent_links", "ultrasonic_rays", "leader"])
        robots = entities["robots"]
        self.assertEqual(len(robots["cylinders"]), 9)
        self.assertEqual(len(robots["arrows"]), 9, "a heading arrow each")
        self.assertEqual(len(entities["ultrasonic_rays"]["lines"][0]["points"]), 9 * 5 * 2, "five rays each")
        self.assertEqual(sorted(t["text"] for t in robots["texts"]), sorted(str(i) for i in range(9)))
        self.assertEqual(len(entities["arena"]["cubes"]), 4, "four walls")
        self.assertEqual(len(entities["obstacles"]["cubes"]), 1, "the large box of paper.yaml")
        self.assertGreaterEqual(len(got["telemetry"]), 3)
        self.assertEqual(len(got["telemetry"][0]["robots"]), 9)
        self.assertIn("state_name", got["telemetry"][0]["robots"][0])
        tf = got["tf"][-1]
        self.assertEqual([t["child_frame_id"] for t in tf["transforms"]], [f"robot_{i}" for i in range(9)])
        self.assertEqual({t["parent_frame_id"] for t in tf["transforms"]}, {"arena"})
        self.assertEqual(len(got["metrics"][-1]["net_force"]), 9)
        # Paused over Foxglove's /control, the run held its tick; a step moved it by exactly one.
        self.assertEqual(got["stepped"], got["paused_at"] + 1)
        self.assertGreaterEqual(got["paused_at"], 20)
        self.assertEqual(len(vh.rows_at(out, got["stepped"])), 9, "the stepped tick is recorded")

    async def foxglove_session(self, port):
        got = {"poses": [], "telemetry": [], "tf": [], "metrics": [], "first_scene": None}
        # A browser on another site may not drive the run (the page's protocol); Foxglove's may read.
        with self.assertRaises(websockets.exceptions.InvalidStatusCode) as refused:
            async with websockets.connect(f"ws://127.0.0.1:{port}/ws", origin="http://evil.example"):
                pass
        self.assertEqual(refused.exception.status_code, 403)
        async with websockets.connect(f"ws://127.0.0.1:{port}/", subprotocols=["foxglove.websocket.v1"]) as fox, \
                websockets.connect(f"ws://127.0.0.1:{port}/ws") as page:
            self.assertEqual(fox.subprotocol, "foxglove.websocket.v1")
            info = json.loads(await asyncio.wait_for(fox.recv(), 10))
            self.assertEqual(info["op"], "serverInfo")
            self.assertIn("clientPublish", info["capabilities"])
            self.assertIn("json", info["supportedEncodings"])
            adv = json.loads(await asyncio.wait_for(fox.recv(), 10))
            self.assertEqual(adv["op"], "advertise")
            channels = {c["topic"]: c for c in adv["channels"]}
            self.assertEqual({t: c["schemaName"] for t, c in channels.items()},
                             {"/scene": "foxglove.SceneUpdate", "/robots/poses": "foxglove.PosesInFrame",
                              "/robots/telemetry": "swarmform.RobotTelemetry", "/tf": "foxglove.FrameTransforms",
                              "/metrics": "swarmform.Metrics"})
            for c in channels.values():
                self.assertEqual((c["encoding"], c["schemaEncoding"]), ("json", "jsonschema"))
                schema = json.loads(c["schema"])
                self.assertEqual(schema["type"], "object")
            names = {"/scene": "scene", "/robots/poses": "poses", "/robots/telemetry": "telemetry", "/tf": "tf",
                     "/metrics": "metrics"}
            by_sub = {10 + i: names[t] for i, t in enumerate(channels)}
            await fox.send(json.dumps({"op": "subscribe", "subscriptions": [
                {"id": 10 + i, "channelId": c["id"]} for i, c in enumerate(channels.values())]}))
            # A subscription to a channel that does not exist is answered with an error status.
            await fox.send(json.dumps({"op": "subscribe", "subscriptions": [{"id": 99, "channelId": 77}]}))
            status = json.loads(await self.next_text(fox))
            self.assertEqual((status["op"], status["level"]), ("status", 2))
            # clientPublish: a /control channel, the page's commands on it.
            await fox.send(json.dumps({"op": "advertise", "channels": [
                {"id": 1, "topic": "/control", "encoding": "json", "schemaName": "swarmform.Control"}]}))

            async def control(cmd, value=None):
                m = {"cmd": cmd} if value is None else {"cmd": cmd, "value": value}
                await fox.send(b"\x01" + struct.pack("<I", 1) + json.dumps(m).encode())

            # A Foxglove client from an origin the user named (--view-control-origin) may drive: its speed cap
            # reaches the world's frames.
            async with websockets.connect(f"ws://127.0.0.1:{port}/", origin="https://app.foxglove.dev",
                                          subprotocols=["foxglove.websocket.v1"]) as app:
                await app.send(json.dumps({"op": "advertise", "channels": [
                    {"id": 1, "topic": "/control", "encoding": "json"}]}))
                await app.send(b"\x01" + struct.pack("<I", 1) + b'{"cmd": "speed", "value": 60}')
                await self.page_frame(page, lambda f: f["speed_cap"] == 60)
            # Any other origin reads but may not drive: refused, said as an error status.
            async with websockets.connect(f"ws://127.0.0.1:{port}/", origin="https://evil.example",
                                          subprotocols=["foxglove.websocket.v1"]) as other:
                self.assertEqual(json.loads(await asyncio.wait_for(other.recv(), 10))["op"], "serverInfo")
                await other.send(json.dumps({"op": "advertise", "channels": [
                    {"id": 1, "topic": "/control", "encoding": "json"}]}))
                await other.send(b"\x01" + struct.pack("<I", 1) + b'{"cmd": "resume"}')
                refusal = json.loads(await self.next_text(other))
                self.assertEqual(refusal["level"], 2)
                self.assertIn("Origin", refusal["message"])
            await control("resume")
            frame = await self.page_frame(page, lambda f: f["tick"] >= 20)
            await control("pause")
            frame = await self.page_frame(page, lambda f: f["paused"])
            got["paused_at"] = frame["tick"]
            await asyncio.sleep(1.0)  # held: the step below lands on the next tick, not further
            await control("step", 1)
            frame = await self.page_frame(page, lambda f: f["tick"] != got["paused_at"])
            got["stepped"] = frame["tick"]
            self.assertTrue(frame["paused"])
            await control("speed", 0)
            await control("resume")
            deadline = time.monotonic() + 60
            while time.monotonic() < deadline and (len(got["poses"]) < 5 or got["first_scene"] is None):
                try:
                    m = await asyncio.wait_for(fox.recv(), 10)
                except (asyncio.TimeoutError, websockets.exceptions.ConnectionClosed):
                    break
                if isinstance(m, str):
                    continue
                self.assertEqual(m[0], 1, "Message Data opcode")
                sub = struct.unpack_from("<I", m, 1)[0]
                stamp = struct.unpack_from("<Q", m, 5)[0] / 1e9
                payload = json.loads(m[13:])
                kind = by_sub[sub]
                check_schema(self, channels, kind, payload)
                if kind == "poses":
                    got["poses"].append((stamp, payload["tick"], payload["poses"]))
                elif kind == "scene":
                    if got["first_scene"] is None:
                        got["first_scene"] = payload
                else:
                    got[kind].append(payload)
        return got

    async def next_text(self, ws):
        """The next status message, past the binary Message Data and the server's other text."""
        while True:
            m = await asyncio.wait_for(ws.recv(), 30)
            if isinstance(m, str) and json.loads(m).get("op") == "status":
                return m

    async def page_frame(self, page, want):
        """The page socket's next frame that `want` accepts (30 s at most)."""
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            m = json.loads(await asyncio.wait_for(page.recv(), 30))
            if m.get("type") == "frame" and want(m):
                return m
        self.fail("no such frame within 30 s")


def check_schema(test, channels, kind, payload):
    """A message against Foxglove's published schema for its channel (foxglove_schemas.py), and against the schema
    the server advertised for it."""
    topic = {"scene": "/scene", "poses": "/robots/poses", "telemetry": "/robots/telemetry", "tf": "/tf",
             "metrics": "/metrics"}[kind]
    name = channels[topic]["schemaName"]
    if name in foxglove_schemas.SCHEMAS:
        foxglove_schemas.validate(payload, foxglove_schemas.SCHEMAS[name], f"{topic}")
    foxglove_schemas.validate(payload, json.loads(channels[topic]["schema"]), f"{topic} (advertised)")

if __name__ == "__main__":
    unittest.main()
