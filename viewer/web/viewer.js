// The swarmform viewer page (viewer/README.md "The page"). Live: frames over the WebSocket from swarm_viewer,
// commands back. Replay: the same frames, read from the recording by the server, which holds the timeline (the
// page scrubs, plays and jumps by commands); events.jsonl and summary.json are fetched for the jump list. The
// behaviour's states (names, colours) come from the server: nothing here knows the paper's algorithm.
"use strict";

const $ = (id) => document.getElementById(id);
const canvas = $("arena");
const ctx = canvas.getContext("2d");
// The Khepera IV's ultrasonic sensors, in the robot frame (common/types.hpp kUltrasonicAngles).
const ULTRASONIC_ANGLES = [-Math.PI / 2, -Math.PI / 4, 0, Math.PI / 4, Math.PI / 2];
const UNKNOWN_COLOUR = "#000000";
const DEAD_COLOUR = "#bdbdbd";

const S = {
  floorImage: null,    // the floor image (world.json floor.image), once asked for
  mode: null,          // "live" | "replay"
  world: null,         // world.json
  frame: null,         // the frame drawn: {tick, robots: [...], ...}
  states: new Map(),   // state value -> {name, colour}
  groups: [],          // a mixed swarm's robot groups (world.json `groups`): {name, behaviour, first, count, states, outline}
  fields: [],          // telemetry fields a robot's panel lists
  events: [],          // every event so far (live) or of the recording (replay)
  selected: null,      // robot id
  view: null,          // {cx, cy, scale}: world point at the canvas centre, pixels per metre
  // Rates (status bar), over a sliding window of what reached the page: `frames` the arrival times of every
  // frame, `ticks` [time, tick] of frames whose tick moved on for real (live: the world's ticks; replay: the
  // timeline playing, not a seek); a jump back, a seek, a pause or the run's end empties `ticks`.
  rates: { frames: [], ticks: [], lagMs: null, lagTicks: null, maxGapMs: 0, log: [] },
  // Layers that can be toggled (the checkboxes, keys); `drawn` says what the last draw() drew (the tests
  // read it): how many ids, parent links, heard lines, trails, and the rays as world segments [x0, y0, x1, y1].
  layers: { ids: true, links: true, heard: true, rays: true, trails: true, grid: true },
  drawn: { ids: 0, links: 0, heard: 0, rays: [], trails: 0, drawMs: 0 },
  trailSeconds: 10,    // trails: the last N seconds of the run's time
  trails: new Map(),   // robot id -> [[tick, x, y], ...]
  lastKey: null,       // the last keyboard shortcut: {key, action} (action null: it could not act, and why)
  ws: null,
  replay: null,        // {first, last, ticks, playing, speed, tick, summary}
  notices: [],         // what the page says all along (a recording that ends early, a run that did not finish)
  end: null,           // live: the run's end {end_reason, tick} (the viewer's "end" message)
  closed: false,       // the viewer's WebSocket closed
  killSent: null,      // live: {id, tick} of a kill sent whose death no frame shows yet
};
window.sfViewer = S;  // for tests and the curious

// ---- the view --------------------------------------------------------------------------------------------

function fit() {
  if (!S.world) return;
  const a = S.world.arena;
  const w = canvas.clientWidth, h = canvas.clientHeight;
  const margin = 0.05;
  const scale = Math.min(w / (a.width * (1 + margin)), h / (a.height * (1 + margin)));
  S.view = { cx: a.centre[0], cy: a.centre[1], scale: scale };
}

// The canvas's size in CSS pixels as the last drawing saw it, read once a drawing (and at a resize):
// clientWidth is a layout query, 2 µs each in a software-rendered Chromium, and project() runs for every
// robot and every trail point (two reads a point cost 47-88 ms a frame for 256 robots' trails).
const size = { w: 0, h: 0 };
function measure() { size.w = canvas.clientWidth; size.h = canvas.clientHeight; }

// World (m) -> canvas CSS pixels, as drawn.
function project(x, y) {
  const v = S.view;
  if (!size.w) measure();
  return [size.w / 2 + (x - v.cx) * v.scale, size.h / 2 - (y - v.cy) * v.scale];
}
function unproject(px, py) {
  const v = S.view;
  if (!size.w) measure();
  return [v.cx + (px - size.w / 2) / v.scale, v.cy - (py - size.h / 2) / v.scale];
}
S.project = project;
S.draw = () => draw();  // the benchmark times it
S.select = select;

function resize() {
  const dpr = window.devicePixelRatio || 1;
  canvas.width = Math.round(canvas.clientWidth * dpr);
  canvas.height = Math.round(canvas.clientHeight * dpr);
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  measure();
  if (!S.view) fit();
  draw();
}
window.addEventListener("resize", resize);

canvas.addEventListener("wheel", (e) => {
  if (!S.view) return;
  e.preventDefault();
  const [wx, wy] = unproject(e.offsetX, e.offsetY);
  S.view.scale *= Math.exp(-e.deltaY * 0.0015);
  S.view.scale = Math.min(Math.max(S.view.scale, 2), 5000);
  const [nx, ny] = unproject(e.offsetX, e.offsetY);
  S.view.cx += wx - nx;
  S.view.cy += wy - ny;
  draw();
}, { passive: false });

let drag = null;
canvas.addEventListener("mousedown", (e) => { drag = { x: e.offsetX, y: e.offsetY, moved: false }; });
canvas.addEventListener("mousemove", (e) => {
  if (!drag || !S.view) return;
  const dx = e.offsetX - drag.x, dy = e.offsetY - drag.y;
  if (Math.abs(dx) + Math.abs(dy) > 3) drag.moved = true;
  if (!drag.moved) return;
  S.view.cx -= dx / S.view.scale;
  S.view.cy += dy / S.view.scale;
  drag.x = e.offsetX; drag.y = e.offsetY;
  draw();
});
canvas.addEventListener("mouseup", (e) => {
  if (drag && !drag.moved) pick(e.offsetX, e.offsetY);
  drag = null;
});
$("fit").addEventListener("click", (e) => { e.preventDefault(); fit(); draw(); });

function pick(px, py) {
  if (!S.frame || !S.view) return;
  let best = null, bestD = Infinity;
  for (const r of S.frame.robots) {
    const [x, y] = project(r.x, r.y);
    const d = Math.hypot(x - px, y - py);
    if (d < bestD) { bestD = d; best = r; }
  }
  const reach = Math.max(8, robotRadius() * S.view.scale * 1.5);
  select(best && bestD <= reach ? best.id : null);
}

// The robot whose panel is shown (null: none). A replay's frames carry the recorded readings of the selected
// robot only: the server is told, and sends the frame again with them.
function select(id) {
  S.selected = id;
  if (S.mode === "replay") send("select", id === null ? -1 : id);
  draw();
  panel();
}

function robotRadius() { return (S.world && S.world.robot_radius) || 0.0704; }
// A mixed swarm (docs/recording-format.md "Robot groups"): each robot is coloured by its own group's states and
// outlined in its group's colour; without groups every robot has the run's states and the one outline.
const GROUP_OUTLINES = ["#263238", "#d81b60", "#ff6f00", "#00897b", "#5e35b1", "#6d4c41"];
function groupOf(id) {
  for (const g of S.groups) if (id >= g.first && id < g.first + g.count) return g;
  return null;
}
function statesOf(id) { const g = groupOf(id); return g ? g.states : S.states; }
function stateColour(r) {
  if (!r.alive) return DEAD_COLOUR;
  const s = statesOf(r.id).get(r.state);
  return s ? s.colour : UNKNOWN_COLOUR;
}
function stateName(v, id) { const s = (id === undefined ? S.states : statesOf(id)).get(v); return s ? s.name : "state " + v; }
function setGroups(w) {
  const list = Array.isArray(w.groups) ? w.groups : [];
  S.groups = list.map((g, k) => {
    const d = (g && g.behaviour_descriptor) || {};
    return { name: String(g.name), behaviour: String(d.name || "?"), first: Number(g.first_id), count: Number(g.count),
             states: new Map((d.states || []).map((s) => [s.value, { name: s.name, colour: s.colour }])),
             outline: GROUP_OUTLINES[k % GROUP_OUTLINES.length] };
  });
  legend();
}

// ---- drawing ---------------------------------------------------------------------------------------------

// world.json's obstacles with its world_events up to `tick` applied (world_server/world/world_events.hpp), the
// present ones only.
function obstaclesAt(tick) {
  const now = (S.world.obstacles || []).map((o) => Object.assign({}, o));
  for (const e of S.world.world_events || []) {
    if (e.tick > tick) break;
    const o = now[e.obstacle];
    if (!o) continue;
    if (e.do === "appear") o.present = true;
    else if (e.do === "disappear") o.present = false;
    else if (e.do === "move") {
      o.centre = e.centre;
      if (typeof e.yaw === "number") o.yaw = e.yaw;
    }
  }
  return now.filter((o) => o.present !== false);
}

// world.json's goal as it stands at `tick`: moved by each of its goal_moves at or before it
// (world_server/world/goal_events.hpp); null when the run has none.
function goalAt(tick) {
  let g = S.world.goal;
  for (const m of S.world.goal_moves || []) {
    if (m.tick > tick) break;
    g = m;
  }
  return g;
}

// The grid's and the scale bar's step: 1, 2 or 5 x 10^n metres, the smallest at least `px` pixels long.
function niceStep(k, px) {
  const want = px / k;
  const p = Math.pow(10, Math.floor(Math.log10(want)));
  for (const m of [1, 2, 5, 10]) if (m * p >= want) return m * p;
  return 10 * p;
}
function metres(v) { return v >= 1 ? v + " m" : v >= 0.01 ? Math.round(v * 100) + " cm" : Math.round(v * 1000) + " mm"; }

// A light grid over the arena (a line every niceStep, at least 40 px apart), under everything but the floor.
function drawGrid(k) {
  const a = S.world.arena;
  const step = niceStep(k, 40);
  const x0 = a.centre[0] - a.width / 2, x1 = a.centre[0] + a.width / 2;
  const y0 = a.centre[1] - a.height / 2, y1 = a.centre[1] + a.height / 2;
  ctx.strokeStyle = "rgba(96,125,139,0.18)";
  ctx.lineWidth = 1;
  ctx.beginPath();
  for (let x = Math.ceil(x0 / step) * step; x <= x1 + 1e-9; x += step) {
    const [px, pa] = project(x, y0), [, pb] = project(x, y1);
    ctx.moveTo(px, pa); ctx.lineTo(px, pb);
  }
  for (let y = Math.ceil(y0 / step) * step; y <= y1 + 1e-9; y += step) {
    const [pa, py] = project(x0, y), [pb] = project(x1, y);
    ctx.moveTo(pa, py); ctx.lineTo(pb, py);
  }
  ctx.stroke();
  S.drawn.gridStep = step;
}

// The scale bar, bottom left of the canvas: niceStep's length at least 80 px, its length in words.
function drawScaleBar(k) {
  const step = niceStep(k, 80), len = step * k;
  const x = 12, y = size.h - 14;
  ctx.fillStyle = "rgba(255,255,255,0.8)";
  ctx.fillRect(x - 4, y - 16, len + 8, 24);
  ctx.strokeStyle = "#263238";
  ctx.lineWidth = 2;
  ctx.beginPath();
  ctx.moveTo(x, y - 5); ctx.lineTo(x, y); ctx.lineTo(x + len, y); ctx.lineTo(x + len, y - 5);
  ctx.stroke();
  ctx.fillStyle = "#263238";
  ctx.font = "11px system-ui, sans-serif";
  ctx.fillText(metres(step), x + 2, y - 4);
  S.drawn.scaleBar = { metres: step, px: len };
}

// The trails: each robot's positions of the last S.trailSeconds of the run's time (frames as they came; a jump
// back or a seek starts them again).
function noteTrails(f) {
  const rate = (S.world && S.world.tick_rate) || 10;
  const keep = S.trailSeconds * rate, step = Math.max(1, Math.round(rate / 4));
  const jumped = S.mode === "replay" && !f.played;
  for (const r of f.robots) {
    let t = S.trails.get(r.id);
    if (!t || jumped || (t.length && f.tick < t[t.length - 1][0])) { t = []; S.trails.set(r.id, t); }
    // A point every quarter second of run time at most (the newest replaces the last until then): a trail is a
    // few dozen segments, which a software-rendered canvas strokes for 256 robots within a frame's time.
    const last = t[t.length - 1];
    if (t.length >= 2 && f.tick - t[t.length - 2][0] < step) { last[0] = f.tick; last[1] = r.x; last[2] = r.y; }
    else if (!last || last[0] !== f.tick) t.push([f.tick, r.x, r.y]);
    while (t.length && t[0][0] < f.tick - keep) t.shift();
  }
}
function pale(hex) {
  const m = /^#([0-9a-f]{6})$/i.exec(hex);
  if (!m) return hex;
  const v = parseInt(m[1], 16);
  const mix = (c) => Math.round(c * 0.45 + 255 * 0.55);
  return "rgb(" + mix(v >> 16) + "," + mix((v >> 8) & 255) + "," + mix(v & 255) + ")";
}
function drawTrails(byId) {
  let n = 0;
  // A stroke a trail, opaque, in its robot's colour paled towards white: one translucent path of all the trails
  // (it crosses itself everywhere) cost a software-rendered canvas 100-300 ms for 256 robots (measured).
  ctx.lineWidth = 1;
  for (const [id, t] of S.trails) {
    if (t.length < 2) continue;
    const r = byId.get(id);
    ctx.strokeStyle = pale(r ? stateColour(r) : DEAD_COLOUR);
    ctx.beginPath();
    const [x0, y0] = project(t[0][1], t[0][2]);
    ctx.moveTo(x0, y0);
    for (let i = 1; i < t.length; i++) { const [x, y] = project(t[i][1], t[i][2]); ctx.lineTo(x, y); }
    ctx.stroke();
    n++;
  }
  S.drawn.trails = n;
}

function draw() {
  const t0 = performance.now();
  measure();
  ctx.clearRect(0, 0, size.w, size.h);
  S.drawn = { ids: 0, links: 0, heard: 0, rays: [], trails: 0, drawMs: S.drawn.drawMs };
  if (!S.world || !S.view) return;
  const k = S.view.scale;
  const a = S.world.arena;
  drawFloor(k);
  if (S.layers.grid) drawGrid(k);
  // Walls.
  if (a.walls) {
    const t = (a.wall_thickness || 0.1) * k;
    const [x0, y0] = project(a.centre[0] - a.width / 2, a.centre[1] + a.height / 2);
    ctx.strokeStyle = "#424242";
    ctx.lineWidth = t;
    ctx.strokeRect(x0 - t / 2, y0 - t / 2, a.width * k + t, a.height * k + t);
  }
  // Obstacles, as they stand at the tick shown (world events move, add and remove them).
  ctx.fillStyle = "#6d4c41";
  for (const o of obstaclesAt(S.frame ? S.frame.tick : 0)) {
    const [ox, oy] = project(o.centre[0], o.centre[1]);
    ctx.beginPath();
    if (o.kind === "cylinder") {
      ctx.arc(ox, oy, o.radius * k, 0, 2 * Math.PI);
    } else {
      ctx.save();
      ctx.translate(ox, oy);
      ctx.rotate(-(o.yaw || 0));
      ctx.rect(-o.half_extents[0] * k, -o.half_extents[1] * k, 2 * o.half_extents[0] * k, 2 * o.half_extents[1] * k);
      ctx.restore();
    }
    ctx.fill();
  }
  // Goal, as it stands at the tick shown.
  const g = goalAt(S.frame ? S.frame.tick : 0);
  S.drawn.goal = g ? { x: g.x, y: g.y, radius: g.radius } : null;
  if (g) {
    const [gx, gy] = project(g.x, g.y);
    ctx.setLineDash([6, 4]);
    ctx.strokeStyle = "#8e24aa";
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(gx, gy, g.radius * k, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = "#8e24aa";
    ctx.fillText("goal", gx + g.radius * k + 3, gy);
  }
  drawLights();
  const f = S.frame;
  if (!f) return;
  const byId = new Map(f.robots.map((r) => [r.id, r]));
  if (S.layers.trails) drawTrails(byId);
  // Parent links.
  if (S.layers.links) {
    ctx.strokeStyle = "rgba(38,50,56,0.45)";
    ctx.lineWidth = 1;
    for (const r of f.robots) {
      const p = r.parent >= 0 ? byId.get(r.parent) : null;
      if (!p || !r.alive) continue;
      const [x1, y1] = project(r.x, r.y), [x2, y2] = project(p.x, p.y);
      ctx.beginPath(); ctx.moveTo(x1, y1); ctx.lineTo(x2, y2); ctx.stroke();
      S.drawn.links++;
    }
  }
  // The selected robot's neighbours heard, then its ultrasonic rays over them, under the bodies.
  const sel = S.selected !== null ? byId.get(S.selected) : null;
  if (sel) {
    const [sx, sy] = project(sel.x, sel.y);
    if (S.layers.heard) {
      ctx.strokeStyle = "rgba(30,136,229,0.5)";
      ctx.lineWidth = 1;
      for (const id of sel.heard || []) {
        const n = byId.get(id);
        if (!n) continue;
        const [nx, ny] = project(n.x, n.y);
        ctx.beginPath(); ctx.moveTo(sx, sy); ctx.lineTo(nx, ny); ctx.stroke();
        S.drawn.heard++;
      }
    }
    // A reading is measured from the sensor on the body's rim (world_server/world/ultrasonic.hpp): the ray runs
    // from there to the hit point, radius + reading from the centre.
    if (S.layers.rays && sel.ultrasonic && sel.alive) {
      const R = robotRadius();
      ctx.strokeStyle = "rgba(229,57,53,0.9)";
      ctx.lineWidth = 2;
      sel.ultrasonic.forEach((d, i) => {
        const ang = sel.theta + ULTRASONIC_ANGLES[i], c = Math.cos(ang), s = Math.sin(ang);
        const seg = [sel.x + R * c, sel.y + R * s, sel.x + (R + d) * c, sel.y + (R + d) * s];
        const [bx, by] = project(seg[0], seg[1]), [ex, ey] = project(seg[2], seg[3]);
        ctx.beginPath(); ctx.moveTo(bx, by); ctx.lineTo(ex, ey); ctx.stroke();
        ctx.beginPath(); ctx.arc(ex, ey, 2.5, 0, 2 * Math.PI); ctx.fillStyle = ctx.strokeStyle; ctx.fill();
        S.drawn.rays.push(seg);
      });
    }
  }
  // Rings (leader amber, selected blue) and ids first, the bodies over them: a body's own disc is only ever its
  // state's colour and its heading notch, whatever its neighbours' rings and labels (the tests read its centre).
  const rr = Math.max(4, robotRadius() * k);
  ctx.font = "11px system-ui, sans-serif";
  // Ids only where they fit: a label is drawn when its box overlaps no label drawn before it (the selected
  // robot's first), so a crowd at "fit" shows some ids legibly rather than all of them over each other.
  const placed = [];
  const fits = (bx, by, bw, bh) => {
    for (const q of placed) if (bx < q[0] + q[2] && q[0] < bx + bw && by < q[1] + q[3] && q[1] < by + bh) return false;
    return true;
  };
  const order = sel ? [sel].concat(f.robots.filter((r) => r !== sel)) : f.robots;
  if (S.layers.ids) {
    for (const r of order) {
      const [x, y] = project(r.x, r.y);
      const label = String(r.id);
      const bw = ctx.measureText(label).width + 2, bh = 12;
      const bx = x + rr * 0.8 + 1, by = y - rr * 0.8 - 2 - 10;
      if (!fits(bx, by, bw, bh)) continue;
      placed.push([bx, by, bw, bh]);
      r._label = [bx + 1, by + 10];
    }
  }
  for (const r of f.robots) {
    const [x, y] = project(r.x, r.y);
    if (r.leader && r.alive) {
      ctx.beginPath();
      ctx.arc(x, y, rr + 3, 0, 2 * Math.PI);
      ctx.strokeStyle = "#ffb300";
      ctx.lineWidth = 2.5;
      ctx.stroke();
    }
    if (r.id === S.selected) {
      ctx.beginPath();
      ctx.arc(x, y, rr + 6, 0, 2 * Math.PI);
      ctx.strokeStyle = "#1e88e5";
      ctx.lineWidth = 2;
      ctx.stroke();
    }
    if (r._label) {
      ctx.fillStyle = "#263238";
      ctx.fillText(String(r.id), r._label[0], r._label[1]);
      r._label = null;
      S.drawn.ids++;
    }
  }
  // Bodies: a disc in the state's colour, a heading notch from mid-radius to the rim; the dead grey and crossed.
  // One path a colour, one for the outlines and one for the notches: 256 robots are a few fills and strokes,
  // not a thousand (the page keeps up with 10 frames a second in a software-rendered Chromium).
  // A mixed swarm's robots are outlined in their group's colour (GROUP_OUTLINES), one path a group.
  const discs = new Map(), outlines = new Map(), notches = new Path2D();
  S.drawn.groups = {};
  for (const r of f.robots) {
    const [x, y] = project(r.x, r.y);
    const colour = stateColour(r);
    let p = discs.get(colour);
    if (!p) { p = new Path2D(); discs.set(colour, p); }
    p.moveTo(x + rr, y); p.arc(x, y, rr, 0, 2 * Math.PI);
    const g = groupOf(r.id);
    const ring = g ? g.outline : GROUP_OUTLINES[0];
    if (g) S.drawn.groups[g.name] = (S.drawn.groups[g.name] || []).concat([{ id: r.id, fill: colour, outline: ring }]);
    let o = outlines.get(ring);
    if (!o) { o = new Path2D(); outlines.set(ring, o); }
    o.moveTo(x + rr, y); o.arc(x, y, rr, 0, 2 * Math.PI);
    const c = Math.cos(r.theta), s = Math.sin(r.theta);
    notches.moveTo(x + c * rr * 0.45, y - s * rr * 0.45);
    notches.lineTo(x + c * rr, y - s * rr);
  }
  for (const [colour, p] of discs) { ctx.fillStyle = colour; ctx.fill(p); }
  for (const [ring, o] of outlines) {
    ctx.strokeStyle = ring;
    ctx.lineWidth = ring === GROUP_OUTLINES[0] ? 1 : 2.5;
    ctx.stroke(o);
  }
  ctx.lineWidth = 2;
  ctx.stroke(notches);
  for (const r of f.robots) {
    if (r.alive && !r.leds) continue;
    const [x, y] = project(r.x, r.y);
    if (r.alive && r.leds) drawLeds(x, y, r.theta, rr, r.leds);
    if (!r.alive) {
      ctx.strokeStyle = "#b71c1c";
      ctx.lineWidth = 2;
      const d = rr * 0.7;
      ctx.beginPath();
      ctx.moveTo(x - d, y - d); ctx.lineTo(x - d * 0.3, y - d * 0.3);
      ctx.moveTo(x + d, y + d); ctx.lineTo(x + d * 0.3, y + d * 0.3);
      ctx.moveTo(x - d, y + d); ctx.lineTo(x - d * 0.3, y + d * 0.3);
      ctx.moveTo(x + d, y - d); ctx.lineTo(x + d * 0.3, y - d * 0.3);
      ctx.stroke();
    }
  }
  drawScaleBar(k);
  S.drawn.drawMs = performance.now() - t0;
}

// The floor as the ground sensors read it (world.json `floor`, docs/recording-format.md), under everything: its
// base over the arena, then its regions in painting order, each in the colour the scenario gave or its grey. A
// plain white floor draws nothing. The image (world.json floor.image: the run folder's copy, which the server
// serves as /run/floor.png) is stretched over the arena between the base and the regions, once it has loaded.
function greyHex(g) {
  const v = Math.round(Math.min(Math.max(g, 0), 1) * 255).toString(16).padStart(2, "0");
  return "#" + v + v + v;
}
function drawFloor(k) {
  const fl = S.world.floor;
  if (!fl) return;
  const a = S.world.arena;
  if (fl.colour || (typeof fl.grey === "number" && fl.grey < 1)) {
    const [x0, y0] = project(a.centre[0] - a.width / 2, a.centre[1] + a.height / 2);
    ctx.fillStyle = fl.colour || greyHex(fl.grey);
    ctx.fillRect(x0, y0, a.width * k, a.height * k);
  }
  if (fl.image && fl.image.file) {
    if (!S.floorImage) {
      S.floorImage = new Image();
      S.floorImage.onload = () => draw();
      S.floorImage.src = "/run/" + encodeURIComponent(fl.image.file);
    }
    if (S.floorImage.complete && S.floorImage.naturalWidth > 0) {
      const [x0, y0] = project(a.centre[0] - a.width / 2, a.centre[1] + a.height / 2);
      ctx.imageSmoothingEnabled = false;  // the floor's pixels, as the ground sensors read them
      ctx.drawImage(S.floorImage, x0, y0, a.width * k, a.height * k);
    }
  }
  for (const r of fl.regions || []) {
    const [rx, ry] = project(r.centre[0], r.centre[1]);
    ctx.beginPath();
    if (r.kind === "circle") {
      ctx.arc(rx, ry, r.radius * k, 0, 2 * Math.PI);
    } else {
      ctx.save();
      ctx.translate(rx, ry);
      ctx.rotate(-(r.yaw || 0));
      ctx.rect(-r.half_extents[0] * k, -r.half_extents[1] * k, 2 * r.half_extents[0] * k, 2 * r.half_extents[1] * k);
      ctx.restore();
    }
    ctx.fillStyle = r.colour || greyHex(r.grey);
    ctx.fill();
    ctx.lineWidth = 0.5;
    ctx.strokeStyle = "#9e9e9e";
    ctx.stroke();
  }
}

// Each light source (world.json `lights`): a yellow disc, its intensity and height beside it.
const LIGHT_COLOUR = "#ffd600";
function drawLights() {
  ctx.font = "11px system-ui, sans-serif";
  for (const l of S.world.lights || []) {
    const [lx, ly] = project(l.position[0], l.position[1]);
    ctx.beginPath();
    ctx.arc(lx, ly, 7, 0, 2 * Math.PI);
    ctx.fillStyle = LIGHT_COLOUR;
    ctx.fill();
    ctx.lineWidth = 1.5;
    ctx.strokeStyle = "#e65100";
    ctx.stroke();
    ctx.fillStyle = "#e65100";
    ctx.fillText("light I=" + l.intensity + ", h=" + l.height + " m", lx + 10, ly - 8);
  }
}

// A robot's lit LEDs (a frame's `leds`: three "#rrggbb", absent when all are off): dots on its body 120 degrees
// apart, LED 0 ahead; an LED that is off ("#000000") is not drawn.
function drawLeds(x, y, theta, rr, leds) {
  const d = rr * 0.55, dot = Math.max(2, rr * 0.25);
  leds.forEach((c, i) => {
    if (c === "#000000") return;
    const ang = theta + i * 2 * Math.PI / 3;
    ctx.beginPath();
    ctx.arc(x + d * Math.cos(ang), y - d * Math.sin(ang), dot, 0, 2 * Math.PI);
    ctx.fillStyle = c;
    ctx.fill();
    ctx.lineWidth = 0.5;
    ctx.strokeStyle = "#263238";
    ctx.stroke();
  });
}

// ---- status bar, legend, robot panel ---------------------------------------------------------------------

function status() {
  const f = S.frame;
  if (!f) return;
  $("tick").textContent = f.tick;
  const r = rates();
  $("tps").textContent = r.tps;
  $("fps").textContent = r.fps;
  $("lag").textContent = r.lag;
  $("alive").textContent = f.alive + "/" + f.robots.length;
  $("formation").textContent = f.formation_tick >= 0 ? "tick " + f.formation_tick : "–";
  $("shape-error").textContent = f.shape_error >= 0 ? f.shape_error.toFixed(3) : "–";
  const rs = $("run-state");
  rs.className = "";
  if (S.end) { rs.textContent = endText(S.end); rs.className = "ended"; }
  else if (f.finished) { rs.textContent = "run ended at tick " + f.tick; rs.className = "ended"; }
  else if (S.closed && S.mode === "live") { rs.textContent = "disconnected"; rs.className = "disconnected"; }
  else if (f.paused) { rs.textContent = "PAUSED"; rs.className = "paused"; }
  else rs.textContent = S.mode === "live" ? (f.speed_cap > 0 ? "running (≤ " + f.speed_cap + " ticks/s)" : "running") : "";
}

// The run's end as summary.json's end_reason says it (docs/recording-format.md), not as a lost connection.
function endText(e) {
  const at = e.tick != null ? " at tick " + e.tick : "";
  switch (e.end_reason) {
    case "completed": return "run completed" + at;
    case "max_ticks": return "run ended: max_ticks reached" + at;
    case "interrupted": return "run interrupted" + at;
    case "agents_stalled": return "run stopped" + at + ": agents stalled";
    default: return "run ended" + (e.end_reason ? " (" + e.end_reason + ")" : "") + at;
  }
}

// Damage of the recording (viewer/README.md "Replay"): the banner says what touches the tick the timeline is
// at; the notice what holds all along.
function damageText(d) {
  const ticks = d.from_tick === d.to_tick ? "tick " + d.from_tick : "ticks " + d.from_tick + ".." + d.to_tick;
  return d.file + " byte " + d.offset + " (" + ticks + "): " + d.what;
}
function banners() {
  const f = S.frame;
  const lines = [];
  for (const d of (f && f.damage) || []) if (!d.at_open) lines.push("damaged recording: " + damageText(d));
  if (lines.length && typeof f.at === "number" && f.at !== f.tick)
    lines.unshift("tick " + f.at + " cannot be read: showing tick " + f.tick + ", the last readable one before it");
  $("banner").textContent = lines.join("\n");
  $("banner").hidden = !lines.length;
  $("notice").textContent = S.notices.join("\n");
  $("notice").hidden = !S.notices.length;
}

// Every control says whether it can act, and why not in its tooltip: a disabled button is never clicked for
// nothing.
function setControl(id, why, what) {
  const e = $(id);
  e.disabled = !!why;
  e.title = why ? "disabled: " + why : what;
}
function controls() {
  const f = S.frame;
  const over = S.end || (f && f.finished) ? "the run has ended"
    : S.closed ? "the viewer is gone (the run is over, or the viewer was stopped)" : null;
  const why = S.mode !== "live" ? "a recording (its timeline is below)" : over ? over
    : !f ? "waiting for the world's first frame"
    : !f.controllable ? "a realtime run: its ticks follow the clock (pause, step and the speed cap act in lockstep runs)"
    : null;
  const paused = !!(f && f.paused);
  setControl("pause", why || (paused ? "the run is paused already" : null), "hold the tick (lockstep)");
  setControl("resume", why || (!paused ? "the run is running" : null), "run on");
  setControl("step1", why, "one tick, then paused");
  setControl("stepn", why, "N ticks, then paused");
  setControl("stepn-count", why, "N");
  setControl("speed", why, "ticks per second at most, 0 none");
  setControl("speed-set", why, "set the speed cap");
  const r = f && S.selected !== null ? f.robots.find((q) => q.id === S.selected) : null;
  const pending = S.killSent && r && S.killSent.id === r.id;
  const kwhy = S.mode !== "live" ? "a recording: nothing to kill" : over ? over
    : !r ? "no robot selected" : !r.alive ? "robot " + r.id + " is dead"
    : pending ? "kill sent: waiting for the world to see its death" : null;
  setControl("kill", kwhy, "SIGKILL its agent (as swarm kill); at once, also while paused");
  $("kill-state").textContent = pending ? "kill sent at tick " + S.killSent.tick + "; waiting for its death" : "";
}

function legend() {
  const l = $("legend");
  l.textContent = "";
  const line = (into, states) => {
    for (const [v, s] of states) {
      const span = document.createElement("span");
      const dot = document.createElement("i");
      dot.style.background = s.colour;
      span.append(dot, s.name);
      into.append(span);
    }
  };
  if (!S.groups.length) { line(l, S.states); return; }
  // One line a group: its outline, name, behaviour and ids, then its own states.
  for (const g of S.groups) {
    const div = document.createElement("div");
    div.className = "group";
    const ring = document.createElement("b");
    ring.style.borderColor = g.outline;
    div.append(ring, g.name + " (" + g.behaviour + ", " + g.first + ".." + (g.first + g.count - 1) + "): ");
    line(div, g.states);
    l.append(div);
  }
}

function fmt(v) { return typeof v === "number" && !Number.isInteger(v) ? v.toFixed(3) : String(v); }

function panel() {
  const r = S.frame && S.selected !== null ? S.frame.robots.find((q) => q.id === S.selected) : null;
  $("robot").hidden = !r;
  $("nothing-selected").hidden = !!r;
  if (!r) return;
  $("panel-id").textContent = r.id + (groupOf(r.id) ? " (group " + groupOf(r.id).name + ")" : "");
  const rows = [["alive", r.alive ? "yes" : "dead"], ["x, y", fmt(r.x) + ", " + fmt(r.y)],
                ["heading", (r.theta * 180 / Math.PI).toFixed(1) + "°"]];
  for (const f of S.fields) {
    if (!(f in r)) continue;
    rows.push([f, f === "state" ? stateName(r.state, r.id) + " (" + r.state + ")" : fmt(r[f])]);
  }
  if (r.heard) rows.push(["heard", r.heard.length ? r.heard.join(" ") : "nobody"]);
  if (r.ultrasonic) rows.push(["ultrasonic (m)", r.ultrasonic.map((d) => d.toFixed(2)).join(" ")]);
  // The optional sensors, when the robot's behaviour declares them (docs/behaviour-api.md), live or recorded
  // (readings.csv). Checked by form: a replay's robot also carries the behaviour's telemetry columns by name,
  // and a behaviour may call one "light".
  for (const [key, label] of [["proximity", "proximity (0..1)"], ["light", "light (0..1)"],
                              ["ground", "ground (0..1)"]]) {
    if (Array.isArray(r[key])) rows.push([label, r[key].map((v) => v.toFixed(2)).join(" ")]);
  }
  if (r.lidar && typeof r.lidar === "object") {
    rows.push(["lidar", r.lidar.rays + " rays, nearest " + r.lidar.nearest_range.toFixed(2) + " m at " +
                        (r.lidar.nearest_angle * 180 / Math.PI).toFixed(0) + "°"]);
  }
  if ("battery" in r) rows.push(["battery", (100 * r.battery).toFixed(0) + " %"]);
  if ("left_speed" in r) {
    rows.push(["last command", "L " + fmt(r.left_speed) + " R " + fmt(r.right_speed) + " m/s, " +
                               r.message_bytes + " B message"]);
  }
  const t = $("robot-fields");
  t.textContent = "";
  for (const [k, v] of rows) {
    const tr = document.createElement("tr");
    const a = document.createElement("td"), b = document.createElement("td");
    a.textContent = k; b.textContent = v;
    tr.append(a, b);
    t.append(tr);
  }
  controls();
  const ol = $("robot-events");
  ol.textContent = "";
  const upto = S.frame.tick;
  const mine = S.events.filter((e) => e.id === r.id && e.tick <= upto).slice(-200);
  for (const e of mine) {
    const li = document.createElement("li");
    const extra = e.detail !== undefined ? " " + e.detail : e.to_name !== undefined ? " " + e.from_name + " → " + e.to_name
                : e.to !== undefined ? " " + e.from + " → " + e.to : "";
    li.textContent = "t" + e.tick + " " + e.kind + extra;
    ol.append(li);
  }
}

function setDescription(m) {
  S.states = new Map((m.states || []).map((s) => [s.value, { name: s.name, colour: s.colour }]));
  // A mixed swarm's telemetry columns are the union of its groups' (robots.csv); each robot shows those it has.
  S.fields = m.telemetry_fields || [];
  legend();
}

// ---- rates ------------------------------------------------------------------------------------------------
// Measured over a sliding window of what reached the page (S.rates): ticks/s from real ticks only, frames/s from
// every frame, the lag as the world's tick minus the tick shown.
const RATE_WINDOW_MS = 3000;

function noteRates(f) {
  const R = S.rates, now = performance.now();
  if (R.frames.length) R.maxGapMs = Math.max(R.maxGapMs, now - R.frames[R.frames.length - 1]);
  R.frames.push(now);
  while (R.frames.length && now - R.frames[0] > RATE_WINDOW_MS) R.frames.shift();
  if (R.log.length < 100000) R.log.push([now, f.tick]);  // every frame's arrival (the benchmark reads it)
  // A tick counts when the run moved on by itself: live, any frame not paused; replay, the timeline playing
  // (the server marks those `played`), not a seek, a play from the start or a selection.
  const real = !f.paused && !f.finished && (S.mode !== "replay" || f.played === true);
  const last = R.ticks.length ? R.ticks[R.ticks.length - 1] : null;
  if (!real || (last && f.tick < last[1])) R.ticks = [];
  else if (!last || f.tick !== last[1]) R.ticks.push([now, f.tick]);
  while (R.ticks.length && now - R.ticks[0][0] > RATE_WINDOW_MS) R.ticks.shift();
  // Live: the frame's age since the world wrote it (same host's clock), and the ticks the world made meanwhile
  // at the measured rate. Replay: the timeline's tick minus the recorded tick shown (a damaged stretch).
  if (S.mode === "replay") { R.lagMs = null; R.lagTicks = typeof f.at === "number" ? f.at - f.tick : 0; }
  else if (typeof f.sent_ms === "number" && f.sent_ms > 0) {
    R.lagMs = Math.max(0, Date.now() - f.sent_ms);
    R.lagTicks = null;
  }
}

// What the status bar says: {tps, fps, lag} as text, and the numbers (S.rates.now) for the tests.
function rates() {
  const R = S.rates, now = performance.now(), f = S.frame;
  const ended = !!(S.end || (f && f.finished) || (S.closed && S.mode === "live"));
  const paused = !!(f && f.paused);
  let tps = null;
  const t = R.ticks;
  if (t.length >= 2 && now - t[t.length - 1][0] < 2000 && t[t.length - 1][0] - t[0][0] >= 300)
    tps = (t[t.length - 1][1] - t[0][1]) / ((t[t.length - 1][0] - t[0][0]) / 1000);
  let fps = 0;
  const fr = R.frames.filter((x) => now - x <= RATE_WINDOW_MS);
  if (fr.length >= 2) fps = (fr.length - 1) / (Math.max(now - fr[0], fr[fr.length - 1] - fr[0]) / 1000);
  if (ended) fps = 0;
  let lagTicks = R.lagTicks;
  if (S.mode === "live" && R.lagMs !== null) lagTicks = paused || ended ? 0 : tps !== null ? R.lagMs * tps / 1000 : null;
  S.rates.now = { tps: tps, fps: fps, lagMs: R.lagMs, lagTicks: lagTicks, ended: ended, paused: paused };
  return {
    tps: ended ? "ended" : paused ? "paused" : tps === null ? "–" : tps.toFixed(1),
    fps: fps.toFixed(1),
    lag: lagTicks === null ? "–" : lagTicks.toFixed(lagTicks < 10 ? 1 : 0) +
         (S.mode === "live" && R.lagMs !== null && !ended ? " (" + Math.round(R.lagMs) + " ms)" : ""),
  };
}
setInterval(() => { if (S.frame) status(); }, 500);  // a window that stops moving says so

function show(frame) {
  noteRates(frame);
  if (S.mode === "replay" && !frame.played && S.frame && frame.tick === S.frame.tick && S.frame.played !== undefined) {
    // the same tick again (a selection, a pause): the trails stay
  } else noteTrails(frame);
  S.frame = frame;
  if (S.killSent) {
    const k = frame.robots.find((q) => q.id === S.killSent.id);
    if (!k || !k.alive) S.killSent = null;
  }
  draw();
  status();
  panel();
  banners();
  controls();
}

// ---- live ------------------------------------------------------------------------------------------------

function send(cmd, value) {
  if (S.ws && S.ws.readyState === WebSocket.OPEN) S.ws.send(JSON.stringify({ cmd: cmd, value: value }));
}
$("pause").onclick = () => send("pause");
$("resume").onclick = () => send("resume");
$("step1").onclick = () => send("step", 1);
$("stepn").onclick = () => send("step", Math.max(1, parseInt($("stepn-count").value, 10) || 1));
$("speed-set").onclick = () => send("speed", Math.max(0, parseFloat($("speed").value) || 0));
$("kill").onclick = () => {
  if (S.selected === null) return;
  send("kill", S.selected);
  S.killSent = { id: S.selected, tick: S.frame ? S.frame.tick : null };
  controls();
};

// ---- layers and keyboard shortcuts ----------------------------------------------------------------------------

for (const name of Object.keys(S.layers)) {
  const box = $("layer-" + name);
  if (!box) continue;
  box.checked = S.layers[name];
  box.onchange = () => { S.layers[name] = box.checked; draw(); };
}

// Live speed caps the + and − keys step through (ticks/s; 0: none, the fastest).
const LIVE_SPEEDS = [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 0];
function nextLiveSpeed(dir) {
  const cap = S.frame ? S.frame.speed_cap : 0;
  if (cap <= 0) {
    if (dir > 0) return 0;
    const tps = S.rates.now && S.rates.now.tps;
    const below = LIVE_SPEEDS.filter((v) => v > 0 && (tps ? v < tps : v <= 10));
    return below.length ? below[below.length - 1] : 1;
  }
  const i = LIVE_SPEEDS.findIndex((v) => v > 0 && v >= cap - 1e-9);
  if (dir > 0) return i < 0 ? 0 : LIVE_SPEEDS[Math.min(i + (LIVE_SPEEDS[i] > cap + 1e-9 ? 0 : 1), LIVE_SPEEDS.length - 1)];
  const lower = LIVE_SPEEDS.filter((v) => v > 0 && v < cap - 1e-9);
  return lower.length ? lower[lower.length - 1] : LIVE_SPEEDS[0];
}

// A button's action if it can act; else its reason (the disabled button's tooltip).
function press(id) {
  const b = $(id);
  if (b.disabled) return { action: null, why: b.title };
  b.click();
  return { action: id };
}

// space: pause / resume (replay: play / pause); →: one tick on (live: step 1); + / −: faster / slower (live: the
// speed cap, through LIVE_SPEEDS; replay: the speed list). Not while typing in a field.
document.addEventListener("keydown", (e) => {
  const t = e.target, tag = t && t.tagName;
  const typing = (tag === "INPUT" && t.type !== "checkbox") || tag === "SELECT" || tag === "TEXTAREA";
  if (typing || e.ctrlKey || e.metaKey || e.altKey) return;
  // A focused button or checkbox would take space as a click of its own as well.
  if (tag === "BUTTON" || tag === "INPUT") t.blur();
  let done = null;
  const f = S.frame;
  if (e.key === " ") {
    if (S.mode === "replay") done = press("play");
    else done = press(f && f.paused ? "resume" : "pause");
  } else if (e.key === "ArrowRight") {
    if (S.mode === "replay") {
      const at = f ? (typeof f.at === "number" ? f.at : f.tick) : 0;
      send("seek", at + 1);
      done = { action: "seek " + (at + 1) };
    } else done = press("step1");
  } else if (e.key === "+" || e.key === "=" || e.key === "-" || e.key === "_") {
    const dir = e.key === "+" || e.key === "=" ? 1 : -1;
    if (S.mode === "replay") {
      const sel = $("replay-speed");
      const i = Math.min(Math.max(sel.selectedIndex + dir, 0), sel.options.length - 1);
      sel.selectedIndex = i;
      send("speed", parseFloat(sel.value));
      done = { action: "speed " + sel.value };
    } else if ($("speed-set").disabled) {
      done = { action: null, why: $("speed-set").title };
    } else {
      const v = nextLiveSpeed(dir);
      $("speed").value = v;
      send("speed", v);
      done = { action: "speed " + v };
    }
  } else return;
  e.preventDefault();
  S.lastKey = Object.assign({ key: e.key }, done);
});

async function loadWorld() {
  // Live, the world writes world.json as it starts: it may not be there, or not whole, for a moment.
  let why = "no world.json from the server";
  for (let i = 0; i < 100 && !S.world; i++) {
    try {
      const r = await fetch("run/world.json", { cache: "no-store" });
      if (r.ok) {
        const w = await r.json();
        if (w && w.arena && w.arena.width > 0 && w.arena.height > 0 && Array.isArray(w.arena.centre)) { S.world = w; break; }
        why = "the run's world.json has no usable arena {centre, width, height}";
      }
    } catch (e) { why = "the run's world.json is not valid JSON (" + e.message + ")"; }
    await new Promise((res) => setTimeout(res, 200));
  }
  if (!S.world) { $("mode").textContent = why; return; }
  setGroups(S.world);
  fit();
  resize();
}

function connect() {
  const ws = new WebSocket((location.protocol === "https:" ? "wss://" : "ws://") + location.host + "/ws");
  S.ws = ws;
  ws.onmessage = (ev) => {
    const m = JSON.parse(ev.data);
    if (m.type === "hello") {
      S.mode = m.mode;
      $("mode").textContent = m.mode;
      if (m.mode === "replay") {
        setDescription(m);
        S.notices = (m.damage || []).filter((d) => d.at_open).map((d) => "recording ends early: " + damageText(d));
        if (m.finished === false)
          S.notices.push("the run did not finish (no summary.json): the recording ends at tick " + m.last_tick);
        banners();
        startReplay(m);
      }
      controls();
    } else if (m.type === "frame") {
      if (m.states) setDescription(m);
      if (S.mode === "replay") replayFrame(m);
      show(m);
      // The viewer sends the next frame once this one is drawn (viewer/page_flow.hpp), live and in replay.
      send("drawn", m.tick);
    } else if (m.type === "end") {
      S.end = m;
      status();
      controls();
    } else if (m.type === "events") {
      S.events.push(...m.events);
      panel();
    }
  };
  ws.onclose = () => {
    S.closed = true;
    if (S.mode === "live") {
      const ended = S.end || (S.frame && S.frame.finished);
      $("mode").textContent = ended ? "live (the run is over)" : "live (the viewer closed before the run's end)";
      if (S.frame) status();
      else { $("run-state").textContent = "disconnected"; $("run-state").className = "disconnected"; }
    }
    controls();
  };
}

// ---- replay ----------------------------------------------------------------------------------------------
// The server holds the timeline (viewer/README.md "Replay"): the page sends seek / play / pause / speed and draws
// the frames it is sent, as live. Foxglove, connected to the same server, follows the same timeline.

async function startReplay(hello) {
  $("live-controls").hidden = true;
  $("replay-controls").hidden = false;
  const first = hello.first_tick, last = hello.last_tick;
  S.replay = { first: first, last: last, ticks: last - first + 1, playing: false, speed: 1, tick: first,
               summary: null, dragging: false };
  const tl = $("timeline");
  tl.min = first; tl.max = last; tl.value = first;
  tl.oninput = () => { send("seek", parseInt(tl.value, 10)); };
  tl.onpointerdown = () => { S.replay.dragging = true; };
  tl.onpointerup = () => { S.replay.dragging = false; };
  $("play").onclick = () => send(S.replay.playing ? "pause" : "play");
  $("replay-speed").onchange = () => send("speed", parseFloat($("replay-speed").value));
  const [ev, sum] = await Promise.all([
    fetch("run/events.jsonl").then((r) => (r.ok ? r.text() : "")).catch(() => ""),
    fetch("run/summary.json").then((r) => (r.ok ? r.json() : null)).catch(() => null),
  ]);
  S.replay.summary = sum;
  S.events = ev.split("\n").filter((l) => l).map((l) => { try { return JSON.parse(l); } catch (e) { return null; } })
    .filter((e) => e);
  const jump = $("jump");
  const marks = [];
  if (sum && sum.formation_tick != null) marks.push([sum.formation_tick, "formed"]);
  if (sum && sum.goal_tick != null) marks.push([sum.goal_tick, "at the goal"]);
  for (const e of S.events) {
    if (e.kind === "death") marks.push([e.tick, "death of " + e.id]);
    else if (e.kind === "rejoin") marks.push([e.tick, "rejoin of " + e.id]);
    else if (e.kind === "leader") marks.push([e.tick, "leader " + e.id]);
    else if (e.kind === "leader_lost") marks.push([e.tick, "leader lost (" + e.id + ")"]);
  }
  marks.sort((a, b) => a[0] - b[0]);
  for (const [t, what] of marks) {
    const o = document.createElement("option");
    o.value = t; o.textContent = "t" + t + " " + what;
    jump.append(o);
  }
  jump.onchange = () => { if (jump.value !== "") send("seek", parseInt(jump.value, 10)); jump.value = ""; };
  panel();
}

// A replay frame: the timeline and the play button follow the server's.
function replayFrame(m) {
  const R = S.replay;
  if (!R) return;
  R.tick = m.tick;
  R.playing = !m.paused;
  if (!R.dragging) $("timeline").value = typeof m.at === "number" ? m.at : m.tick;
  $("play").textContent = R.playing ? "pause" : "play";
}

loadWorld().then(connect);
