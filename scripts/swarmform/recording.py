"""Reads a run directory back (format: docs/recording-format.md).

A run directory holds world.json (the static scene), robots.csv (one row per robot per tick), readings.csv (the
sensors' readings, when the behaviour declares sensors; read when asked: load(..., with_readings=True)),
events.jsonl (one JSON object per line) and summary.json (written at the end; missing when the run crashed). Everything that is
wrong with a file is reported as a RecordingError naming file:line, never as a traceback. A crashed run keeps
what it had: a half-written last line of robots.csv or events.jsonl, or a last tick with missing rows, is
dropped with a warning instead.
"""

import dataclasses
import json
import math
import os
from dataclasses import dataclass, field
from typing import Any, Optional, Sequence

import numpy as np

ROBOT_COLUMNS = ("tick", "id", "x", "y", "theta", "alive", "state", "label", "parent", "leader", "net_force")
LEDS_COLUMN = "leds"  # after the fixed columns, before the behaviour's (absent from an older recording)
LED_COUNT = 3
INT_COLUMNS = {"tick", "id", "alive", "state", "label", "parent", "leader"}
STATE_NAMES = {0: "idle", 1: "searching", 2: "moving", 3: "reached", 4: "ready", 5: "motion", 6: "arrived"}
# The paper's states' colours (robot_agent/controller/builtins.cpp), for a recording older than world.json's
# behaviour_descriptor; a newer one carries its behaviour's own states and colours.
STATE_COLOURS = {0: "#9e9e9e", 1: "#ff9800", 2: "#fdd835", 3: "#8bc34a", 4: "#2e7d32", 5: "#1e88e5",
                 6: "#8e24aa"}
READY, MOTION = 4, 5


class RecordingError(Exception):
    """A file of the run directory is missing or wrong. str() is `file:line: what` (or `file: what`)."""

    def __init__(self, path: str, line: Optional[int], what: str) -> None:
        super().__init__(what)
        self.path, self.line, self.what = path, line, what

    def __str__(self) -> str:
        where = self.path if self.line is None else f"{self.path}:{self.line}"
        return f"{where}: {self.what}"


@dataclass
class Obstacle:
    kind: str  # "box" or "cylinder"
    centre: tuple
    name: str = ""
    half_extents: tuple = (0.0, 0.0)  # boxes, m
    yaw: float = 0.0  # boxes, rad
    radius: float = 0.0  # cylinders, m
    present: bool = True  # there at tick 0; world events change it


@dataclass
class WorldEvent:
    """A scheduled world event (world.json's world_events; world_server/world/world_events.hpp): at `tick`, obstacle
    `obstacle` (an index of World.obstacles) appears, disappears or moves to `centre` (and `yaw`, if given)."""
    tick: int
    obstacle: int
    action: str  # "appear", "disappear" or "move"
    centre: Optional[tuple] = None
    yaw: Optional[float] = None


@dataclass
class Shape:
    rows: int
    cols: int
    cells: list  # row-major, -1 empty

    def label_count(self) -> int:
        return sum(1 for c in self.cells if c >= 0)

    def places(self, spacing: float) -> dict[int, tuple[float, float]]:
        """label -> (x, y) of its grid cell: column along +x, row along -y (common/shape.hpp)."""
        out: dict[int, tuple[float, float]] = {}
        for i, label in enumerate(self.cells):
            if label >= 0:
                out[label] = ((i % self.cols) * spacing, -(i // self.cols) * spacing)
        return out


@dataclass
class FloorRegion:
    kind: str  # "circle" or "rectangle"
    centre: tuple
    grey: float  # 0 black .. 1 white: what the ground sensors read
    colour: Optional[str] = None  # "#rrggbb" when the scenario gave a colour rather than a grey
    radius: float = 0.0  # circles, m
    half_extents: tuple = (0.0, 0.0)  # rectangles, m
    yaw: float = 0.0  # rectangles, rad

    def face(self) -> str:
        """The colour to draw it in: the scenario's colour, else its grey."""
        return self.colour or grey_hex(self.grey)


@dataclass
class Floor:
    """What the ground sensors read: a base, an image stretched over the arena's rectangle, regions on top."""

    grey: float = 1.0
    colour: Optional[str] = None
    image: Optional[str] = None  # the PNG's path: the run folder's copy (world.json names it relative to the folder)
    image_size: tuple = (0, 0)  # its pixels (width, height)
    regions: list = field(default_factory=list)  # FloorRegion, in painting order

    def plain(self) -> bool:
        """White and nothing on it: nothing to draw."""
        return self.image is None and not self.regions and self.grey >= 1.0 and self.colour is None

    def face(self) -> str:
        return self.colour or grey_hex(self.grey)


@dataclass
class Light:
    position: tuple  # (x, y) m
    height: float  # m above the floor
    intensity: float  # ARGoS's reference intensity (docs/scenario-format.md)


def grey_hex(grey: float) -> str:
    v = int(min(max(grey, 0.0), 1.0) * 255 + 0.5)  # half up: 0.3 is #4d4d4d
    return f"#{v:02x}{v:02x}{v:02x}"


@dataclass
class World:
    arena_centre: tuple = (0.0, 0.0)
    arena_width: float = 10.0
    arena_height: float = 10.0
    walls: bool = True
    obstacles: list = field(default_factory=list)  # as they stand at tick 0
    world_events: list = field(default_factory=list)  # WorldEvent, by tick
    goal: Optional[tuple] = None  # (x, y, radius) at tick 0
    goal_moves: list = field(default_factory=list)  # (tick, x, y, radius): where world events move it, by tick
    grid_spacing: float = 1.0
    comm_range: float = 3.0
    shape: Optional[Shape] = None
    robots: int = 0
    seed: object = None
    mode: str = ""
    tick_rate: float = 10.0
    robot_radius: float = 0.0704
    # The behaviour (world.json's behaviour_descriptor; docs/behaviour-api.md): its states {value: (name,
    # colour)}, its telemetry columns, and whether it forms a shape and goes to a goal (the paper's pictures and
    # metrics apply only then).
    behaviour: str = "paper"
    states: dict = field(default_factory=lambda: {v: (n, STATE_COLOURS[v]) for v, n in STATE_NAMES.items()})
    telemetry: list = field(default_factory=list)
    needs_shape: bool = True
    needs_goal: bool = True
    # The optional sensors' world (absent from a recording older than them: a plain floor, no lights, no battery).
    floor: Floor = field(default_factory=Floor)
    lights: list = field(default_factory=list)  # Light
    battery: Optional[dict] = None  # {capacity, idle, moving, start}
    # A mixed swarm's robot groups (world.json `groups`, docs/recording-format.md "Robot groups"), in id order;
    # empty without: every robot has `states`.
    groups: list = field(default_factory=list)  # RobotGroup

    def states_of(self, robot: int) -> dict:
        """The states {value: (name, colour)} of robot `robot`'s own behaviour (its group's)."""
        for g in self.groups:
            if g.first_id <= robot < g.first_id + g.count:
                return g.states
        return self.states


@dataclass
class RobotGroup:
    """One group of a mixed swarm: its name, its ids first_id..first_id+count-1, its behaviour and states."""

    name: str
    first_id: int
    count: int
    behaviour: str
    states: dict


@dataclass
class Track:
    """Every robot at every recorded tick: arrays of shape [T, N] (ticks [T]); row t, column = robot id."""

    ticks: np.ndarray
    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    alive: np.ndarray  # bool
    state: np.ndarray  # int
    label: np.ndarray  # int, -1 none
    parent: np.ndarray  # int, id of the parent robot, -1 none
    leader: np.ndarray  # bool
    net_force: np.ndarray
    # The behaviour's telemetry columns (robots.csv after the fixed ones): name -> [T, N] floats, nan where a
    # robot had not reported them yet.
    extra: dict = field(default_factory=dict)
    # The three LEDs: [T, N, 3 LEDs, 3 (r, g, b)] uint8, 0 (off) everywhere when robots.csv has no `leds`
    # column (a recording older than it). None only for a Track built without them.
    leds: Optional[np.ndarray] = None

    @property
    def robots(self) -> int:
        return self.x.shape[1]

    def index_of(self, tick: int) -> int:
        """Index of the last recorded tick <= `tick` (the first one if `tick` is before it)."""
        i = int(np.searchsorted(self.ticks, tick, side="right")) - 1
        return max(i, 0)


@dataclass
class Readings:
    """readings.csv (docs/recording-format.md) on the Track's ticks: values[t, id, k] is column k's reading
    (columns: the sensors' columns, e.g. proximity0..proximity7, lidar_nearest_range, battery), nan where the file
    has none (a dead robot's empty fields, or ticks after a cut-off file's last whole line)."""

    columns: list
    values: np.ndarray  # [T, N, C] float

    def column(self, name: str) -> np.ndarray:
        """[T, N] readings of one column."""
        return self.values[:, :, self.columns.index(name)]


@dataclass
class Recording:
    run_dir: str
    world: World
    track: Track
    events: list
    summary: Optional[dict]
    warnings: list
    readings: Optional[Readings] = None  # load(with_readings=True) of a run that has readings.csv


def load(run_dir: str, with_readings: bool = False) -> Recording:
    """Reads a whole run directory (readings.csv too when `with_readings` and the run has one); raises
    RecordingError on anything wrong."""
    if not os.path.isdir(run_dir):
        raise RecordingError(run_dir, None, "not a directory (expected a run directory with world.json, robots.csv)")
    warnings: list[str] = []
    world = read_world(os.path.join(run_dir, "world.json"))
    track = read_robots(os.path.join(run_dir, "robots.csv"), world.robots, warnings)
    if world.robots == 0:
        world.robots = track.robots
    events_path = os.path.join(run_dir, "events.jsonl")
    events: list[dict[str, Any]] = read_events(events_path, warnings) if os.path.exists(events_path) else []
    summary_path = os.path.join(run_dir, "summary.json")
    summary = None
    if os.path.exists(summary_path):
        summary = read_json(summary_path)
        if not isinstance(summary, dict):
            raise RecordingError(summary_path, 1, "expected a JSON object")
    else:
        warnings.append(f"{summary_path}: missing (the run did not finish); figures come from the recording alone")
    readings_path = os.path.join(run_dir, "readings.csv")
    readings = None
    if with_readings and os.path.exists(readings_path):
        readings = read_readings(readings_path, track, warnings)
    return Recording(run_dir, world, track, events, summary, warnings, readings)


# --- world.json -------------------------------------------------------------------------------------------


def _read_text(path: str) -> str:
    """The whole file as text; a missing or unreadable file is a RecordingError naming it."""
    try:
        with open(path, encoding="utf-8") as f:
            return f.read()
    except FileNotFoundError:
        raise RecordingError(path, None, "missing (is this a run directory?)") from None
    except (OSError, UnicodeDecodeError) as e:
        raise RecordingError(path, None, f"cannot read: {e}") from None


def read_json(path: str) -> Any:
    text = _read_text(path)
    try:
        return json.loads(text)
    except json.JSONDecodeError as e:
        raise RecordingError(path, e.lineno, f"not valid JSON: {e.msg} (column {e.colno})") from None


def _vec2(value: Any, path: str, what: str) -> tuple[float, float]:
    if isinstance(value, dict) and "x" in value and "y" in value:
        value = (value["x"], value["y"])
    if isinstance(value, (list, tuple)) and len(value) == 2 and all(_is_number(v) for v in value):
        return (float(value[0]), float(value[1]))
    raise RecordingError(path, None, f"{what}: expected [x, y] or {{x, y}}, got {value!r}")


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def _number(obj: dict[str, Any], key: str, path: str, what: str, default: Optional[float] = None) -> float:
    if key not in obj:
        if default is None:
            raise RecordingError(path, None, f"{what}: missing '{key}'")
        return default
    v = obj[key]
    if not _is_number(v):
        raise RecordingError(path, None, f"{what}.{key}: expected a number, got {v!r}")
    return float(v)


def read_world(path: str) -> World:
    doc = read_json(path)
    if not isinstance(doc, dict):
        raise RecordingError(path, 1, "expected a JSON object")
    w = World()
    arena = doc.get("arena")
    if not isinstance(arena, dict):
        raise RecordingError(path, None, "missing 'arena' object {centre, width, height, walls}")
    w.arena_centre = _vec2(arena.get("centre", [0, 0]), path, "arena.centre")
    w.arena_width = _number(arena, "width", path, "arena")
    w.arena_height = _number(arena, "height", path, "arena")
    w.walls = bool(arena.get("walls", True))
    for i, ob in enumerate(doc.get("obstacles") or []):
        w.obstacles.append(_read_obstacle(ob, path, f"obstacles[{i}]"))
    for i, ev in enumerate(doc.get("world_events") or []):
        w.world_events.append(_read_world_event(ev, path, f"world_events[{i}]", len(w.obstacles)))
    w.world_events.sort(key=lambda e: e.tick)  # stable: the file's order within a tick
    goal = doc.get("goal")
    if isinstance(goal, dict):
        w.goal = (_number(goal, "x", path, "goal"), _number(goal, "y", path, "goal"),
                  _number(goal, "radius", path, "goal", 0.5))
    elif goal is not None:
        raise RecordingError(path, None, f"goal: expected {{x, y, radius}}, got {goal!r}")
    moves = doc.get("goal_moves") or []
    if not isinstance(moves, list):
        raise RecordingError(path, None, f"goal_moves: expected a list of {{tick, x, y, radius}}, got {moves!r}")
    for i, m in enumerate(moves):
        where = f"goal_moves[{i}]"
        if not isinstance(m, dict):
            raise RecordingError(path, None, f"{where}: expected {{tick, x, y, radius}}, got {m!r}")
        w.goal_moves.append((int(_number(m, "tick", path, where)), _number(m, "x", path, where),
                             _number(m, "y", path, where), _number(m, "radius", path, where)))
    w.goal_moves.sort(key=lambda m: m[0])
    w.grid_spacing = _number(doc, "grid_spacing", path, "world", 1.0)
    w.comm_range = _number(doc, "comm_range", path, "world", 3.0)
    w.tick_rate = _number(doc, "tick_rate", path, "world", 10.0)
    w.robot_radius = _number(doc, "robot_radius", path, "world", 0.0704)
    robots = doc.get("robots", 0)
    if isinstance(robots, list):  # tolerated: a list of initial poses
        robots = len(robots)
    if not isinstance(robots, int) or isinstance(robots, bool) or robots < 0:
        raise RecordingError(path, None, f"robots: expected a count, got {robots!r}")
    w.robots = robots
    w.seed = doc.get("seed")
    w.mode = str(doc.get("mode", ""))
    if doc.get("shape") is not None:
        w.shape = _read_shape(doc["shape"], path)
    w.behaviour = str(doc.get("behaviour", "paper"))
    desc = doc.get("behaviour_descriptor")
    if isinstance(desc, dict):
        _read_behaviour(desc, path, w)
    w.groups = _read_groups(doc.get("groups"), path)
    if doc.get("floor") is not None:
        w.floor = _read_floor(doc["floor"], path)
    for i, light in enumerate(doc.get("lights") or []):
        if not isinstance(light, dict):
            raise RecordingError(path, None, f"lights[{i}]: expected {{position, height, intensity}}")
        w.lights.append(Light(_vec2(light.get("position"), path, f"lights[{i}].position"),
                              _number(light, "height", path, f"lights[{i}]", 0.0),
                              _number(light, "intensity", path, f"lights[{i}]")))
    battery = doc.get("battery")
    if battery is not None:
        if not isinstance(battery, dict):
            raise RecordingError(path, None, f"battery: expected {{capacity, idle, moving, start}}, got {battery!r}")
        w.battery = {k: _number(battery, k, path, "battery", d)
                     for k, d in (("capacity", None), ("idle", 0.0), ("moving", 0.0), ("start", 1.0))}
    return w


def _colour(value: Any, path: str, what: str) -> Optional[str]:
    if value is None:
        return None
    if isinstance(value, str) and len(value) == 7 and value[0] == "#":
        try:
            int(value[1:], 16)
            return value.lower()
        except ValueError:
            pass
    raise RecordingError(path, None, f"{what}: expected \"#rrggbb\" or null, got {value!r}")


def _read_floor(doc: Any, path: str) -> Floor:
    if not isinstance(doc, dict):
        raise RecordingError(path, None, "floor: expected {grey, colour, image, regions}")
    f = Floor(grey=_number(doc, "grey", path, "floor", 1.0), colour=_colour(doc.get("colour"), path, "floor.colour"))
    image = doc.get("image")
    if isinstance(image, dict) and isinstance(image.get("file"), str):
        # A name relative to the run folder (its copy of the image, so that a copied folder keeps it).
        f.image = os.path.join(os.path.dirname(os.path.abspath(path)), image["file"])
        f.image_size = (int(_number(image, "width", path, "floor.image", 0)),
                        int(_number(image, "height", path, "floor.image", 0)))
    elif image is not None:
        raise RecordingError(path, None, f"floor.image: expected {{file, width, height}} or null, got {image!r}")
    for i, r in enumerate(doc.get("regions") or []):
        what = f"floor.regions[{i}]"
        if not isinstance(r, dict):
            raise RecordingError(path, None, f"{what}: expected an object")
        kind = str(r.get("kind", ""))
        region = FloorRegion(kind, _vec2(r.get("centre"), path, f"{what}.centre"), _number(r, "grey", path, what),
                             _colour(r.get("colour"), path, f"{what}.colour"))
        if kind == "circle":
            region.radius = _number(r, "radius", path, what)
        elif kind == "rectangle":
            region.half_extents = _vec2(r.get("half_extents"), path, f"{what}.half_extents")
            region.yaw = _number(r, "yaw", path, what, 0.0)
        else:
            raise RecordingError(path, None, f"{what}.kind: expected 'circle' or 'rectangle', got {r.get('kind')!r}")
        f.regions.append(region)
    return f


def _read_groups(groups: Any, path: str) -> list[RobotGroup]:
    """world.json's `groups` (a mixed swarm): each group's ids and its own behaviour's states."""
    if groups is None:
        return []
    if not isinstance(groups, list):
        raise RecordingError(path, None, "groups: expected a list of {name, first_id, count, behaviour_descriptor}")
    out = []
    for i, g in enumerate(groups):
        ok = isinstance(g, dict) and all(isinstance(g.get(k), int) and not isinstance(g.get(k), bool) and g[k] >= 0
                                         for k in ("first_id", "count"))
        if not ok:
            raise RecordingError(path, None, f"groups[{i}]: expected {{name, first_id, count, behaviour_descriptor}}")
        desc = g.get("behaviour_descriptor") if isinstance(g.get("behaviour_descriptor"), dict) else {}
        w = World()
        _read_behaviour(desc, path, w)
        out.append(RobotGroup(str(g.get("name", i)), g["first_id"], g["count"], str(desc.get("name", "?")), w.states))
    return out


def _read_behaviour(desc: dict[str, Any], path: str, w: World) -> None:
    """world.json's behaviour_descriptor into `w`: states and colours, telemetry columns, needs_shape/goal. A
    behaviour without a shape has no shape to draw, one without a goal no goal."""
    states = {}
    for i, st in enumerate(desc.get("states") or []):
        if not isinstance(st, dict) or not isinstance(st.get("value"), int):
            raise RecordingError(path, None, f"behaviour_descriptor.states[{i}]: expected {{value, name, colour}}")
        states[st["value"]] = (str(st.get("name", st["value"])), str(st.get("colour", "#1e88e5")))
    w.states = states
    w.telemetry = [str(t.get("name")) for t in desc.get("telemetry") or [] if isinstance(t, dict)]
    w.needs_shape = bool(desc.get("needs_shape", True))
    w.needs_goal = bool(desc.get("needs_goal", True))
    if not w.needs_shape:
        w.shape = None
    if not w.needs_goal:
        w.goal = None


def _read_obstacle(ob: Any, path: str, what: str) -> Obstacle:
    if not isinstance(ob, dict):
        raise RecordingError(path, None, f"{what}: expected an object")
    kind = str(ob.get("kind", "")).lower()
    centre = _vec2(ob.get("centre"), path, f"{what}.centre")
    name = str(ob.get("name", ""))
    present = ob.get("present", True)
    if not isinstance(present, bool):
        raise RecordingError(path, None, f"{what}.present: expected true or false, got {present!r}")
    if kind == "box":
        he = _vec2(ob.get("half_extents"), path, f"{what}.half_extents")
        return Obstacle("box", centre, name, half_extents=he, yaw=_number(ob, "yaw", path, what, 0.0),
                        present=present)
    if kind == "cylinder":
        return Obstacle("cylinder", centre, name, radius=_number(ob, "radius", path, what), present=present)
    raise RecordingError(path, None, f"{what}.kind: expected 'box' or 'cylinder', got {ob.get('kind')!r}")


def _read_world_event(ev: Any, path: str, what: str, obstacles: int) -> WorldEvent:
    if not isinstance(ev, dict):
        raise RecordingError(path, None, f"{what}: expected an object {{tick, obstacle, do[, centre, yaw]}}")
    tick, index, action = ev.get("tick"), ev.get("obstacle"), ev.get("do")
    if not isinstance(tick, int) or isinstance(tick, bool) or tick < 0:
        raise RecordingError(path, None, f"{what}.tick: expected a tick, got {tick!r}")
    if not isinstance(index, int) or isinstance(index, bool) or not 0 <= index < obstacles:
        raise RecordingError(path, None, f"{what}.obstacle: expected an index of obstacles (0..{obstacles - 1}), "
                                         f"got {index!r}")
    if action not in ("appear", "disappear", "move"):
        raise RecordingError(path, None, f"{what}.do: expected appear, disappear or move, got {action!r}")
    if action != "move":
        return WorldEvent(tick, index, action)
    yaw = ev.get("yaw")
    return WorldEvent(tick, index, action, _vec2(ev.get("centre"), path, f"{what}.centre"),
                      None if yaw is None else _number(ev, "yaw", path, what))


def goal_at(world: World, tick: int) -> Optional[tuple]:
    """The goal (x, y, radius) as it stands at `tick`: world.json's, moved by its goal_moves up to and including
    `tick`; None when the run has none."""
    goal = world.goal
    for move in world.goal_moves:
        if move[0] > tick:
            break
        goal = move[1:]
    return goal


def obstacles_at(world: World, tick: int) -> list:
    """The obstacles as they stand at `tick` (every one, `present` saying whether it is there): world.json's, with
    its world events up to and including `tick` applied, as the world executed them."""
    now = [dataclasses.replace(ob) for ob in world.obstacles]
    for ev in world.world_events:
        if ev.tick > tick:
            break
        ob = now[ev.obstacle]
        if ev.action == "appear":
            ob.present = True
        elif ev.action == "disappear":
            ob.present = False
        else:
            ob.centre = ev.centre
            if ev.yaw is not None:
                ob.yaw = ev.yaw
    return now


def _read_shape(sh: Any, path: str) -> Shape:
    if not isinstance(sh, dict):
        raise RecordingError(path, None, "shape: expected {rows, cols, cells}")
    rows, cols, cells = sh.get("rows"), sh.get("cols"), sh.get("cells")
    if isinstance(cells, list) and cells and all(isinstance(r, list) for r in cells):
        cells = [c for r in cells for c in r]  # tolerated: a list of rows
    if not (isinstance(rows, int) and isinstance(cols, int) and isinstance(cells, list)):
        raise RecordingError(path, None, "shape: expected integer rows, cols and a list of cells")
    if len(cells) != rows * cols or not all(isinstance(c, int) for c in cells):
        raise RecordingError(path, None, f"shape: cells must be {rows}x{cols} integers, got {len(cells)} entries")
    return Shape(rows, cols, cells)


# --- robots.csv -------------------------------------------------------------------------------------------


def _read_lines(path: str) -> tuple[list[tuple[int, str]], bool]:
    """The file's non-blank lines as (line number, text), and whether its last line lacks a newline."""
    text = _read_text(path)
    lines = text.split("\n")
    truncated = not text.endswith("\n") and lines[-1] != ""
    numbered = [(i + 1, s.rstrip("\r")) for i, s in enumerate(lines) if s.strip()]
    return numbered, truncated


def read_robots(path: str, expected_robots: int, warnings: list[str]) -> Track:
    numbered, truncated = _read_lines(path)
    if not numbered:
        raise RecordingError(path, 1, "empty: expected the header " + ",".join(ROBOT_COLUMNS))
    header_line, header = numbered[0]
    names = [h.strip() for h in header.split(",")]
    missing = [c for c in ROBOT_COLUMNS if c not in names]
    if missing:
        raise RecordingError(path, header_line, f"header lacks column(s) {', '.join(missing)}; got '{header}'")
    col = {c: names.index(c) for c in ROBOT_COLUMNS}
    rows = numbered[1:]
    if truncated and rows:
        last_no, last = rows[-1]
        if _parse_row(last, len(names), col) is None:
            rows = rows[:-1]
            warnings.append(f"{path}:{last_no}: half-written last line dropped (the run stopped while writing)")
    if not rows:
        raise RecordingError(path, header_line + 1, "no rows after the header")
    data = _parse_fast(rows, names, col)
    if data is None:  # something is off: parse row by row to name the first bad line
        data = np.empty((len(rows), len(ROBOT_COLUMNS)), dtype=np.float64)
        for i, (no, text) in enumerate(rows):
            values = _parse_row(text, len(names), col)
            if values is None:
                raise RecordingError(path, no, _describe_bad_row(text, names, col))
            data[i] = values
    line_numbers = np.array([no for no, _ in rows])
    # The format allows nan/inf only when the physics produced them: kept as gaps (nan), with a warning.
    floats = [ROBOT_COLUMNS.index(c) for c in ROBOT_COLUMNS if c not in INT_COLUMNS]
    bad = ~np.isfinite(data[:, floats])
    if bad.any():
        first = int(np.nonzero(bad.any(axis=1))[0][0])
        warnings.append(f"{path}:{line_numbers[first]}: {int(bad.sum())} nan/inf value(s) in x, y, theta or "
                        "net_force; drawn as gaps")
        sub = data[:, floats]
        sub[bad] = np.nan
        data[:, floats] = sub
    extra_names = [n for n in names if n not in ROBOT_COLUMNS and n != LEDS_COLUMN]
    if extra_names:
        data = np.column_stack([data, _extra_columns(rows, [names.index(n) for n in extra_names])])
    leds = _leds_column(path, rows, names.index(LEDS_COLUMN)) if LEDS_COLUMN in names else None
    if leds is not None:
        data = np.column_stack([data, leds])
    return _to_track(path, data, line_numbers, expected_robots, warnings, extra_names, leds is not None)


@dataclass
class Damage:
    """Something wrong in robots.csv that a reader must say where it is, in the viewer's terms
    (viewer/robots_csv.hpp Damage, the same `what`): the timeline ticks it touches, its line and byte."""
    path: str
    line: int
    offset: int
    from_tick: int
    to_tick: int
    what: str
    at_open: bool = False  # the file's tail (the viewer finds it when it opens the file)

    def __str__(self) -> str:
        ticks = f"tick {self.from_tick}" if self.from_tick == self.to_tick else \
            f"ticks {self.from_tick}..{self.to_tick}"
        return f"{self.path}:{self.line} (byte {self.offset}, {ticks}): {self.what}"


def _fast_row(raw: bytes, width: int, ints: list[int], floats: list[int]) -> Optional[tuple[int, int]]:
    """(tick, id) of a row whose fixed columns are numbers (int() and float() strip blanks, as _cell does), without
    decoding it; None to let _parse_row decide (2.5x faster over a million rows)."""
    parts = raw.split(b",")
    if len(parts) != width:
        return None
    try:
        got = [int(parts[i]) for i in ints]
        for i in floats:
            float(parts[i])
    except ValueError:
        return None
    return got[0], got[1]  # INT_COLUMNS in ROBOT_COLUMNS order: tick, id first


@dataclass
class _Unreadable:
    """The unreadable lines after a tick's rows (before the next tick's first readable one)."""
    n: int = 0
    start: int = 0  # the first one's byte
    end: int = 0    # one past the last one's newline
    line: int = 0   # the first one's line
    first: str = ""


def robots_damage(path: str, robots: int) -> list[Damage]:
    """robots.csv's damage, read line by line (never the whole file in memory): unreadable lines (with the ticks
    lost in them), ticks short of `robots` rows (world.json's count; 0: not checked), and a tail cut by a run that
    stopped while writing. The same findings, in the same words, as `swarm view` (viewer/robots_csv.cpp), which
    finds the tail at open and the rest as it reads the ticks. An unreadable header is a RecordingError."""
    found: list[Damage] = []
    size = os.path.getsize(path)
    with open(path, "rb") as f:
        header = f.readline()
        if not header.endswith(b"\n"):
            raise RecordingError(path, 1, "no header line (expected tick,id,x,y,theta,...)")
        names = [h.strip() for h in header.decode(errors="replace").split(",")]
        missing = [c for c in ROBOT_COLUMNS if c not in names]
        if missing:
            raise RecordingError(path, 1, f"header lacks column(s) {', '.join(missing)}")
        col = {c: names.index(c) for c in ROBOT_COLUMNS}
        ints = [col[c] for c in ROBOT_COLUMNS if c in INT_COLUMNS]
        floats = [col[c] for c in ROBOT_COLUMNS if c not in INT_COLUMNS]
        offset, line_no = len(header), 1
        tick: Optional[int] = None  # the tick being read
        start = start_line = 0      # its first row
        ids: set[int] = set()
        bad = _Unreadable()
        last_whole: Optional[int] = None  # the tick before the one being read
        half_written: Optional[tuple[int, int]] = None

        def finish(next_tick: Optional[int]) -> None:
            assert tick is not None
            short = robots > 0 and len(ids) < robots
            if not bad.n and not short:
                return
            what, to_tick = "", tick
            if bad.n:
                what = f"bytes {bad.start}..{bad.end} cannot be read ({bad.n} line(s), the first '{bad.first}')"
                if next_tick is not None and next_tick > tick + 1:
                    to_tick = next_tick - 1
                    what += f"; no tick after {tick} can be read before tick {next_tick}"
            if short:
                gone = [i for i in range(robots) if i not in ids]
                listed = " ".join(str(i) for i in gone[:10]) + (" ..." if len(gone) > 10 else "")
                what += ("; " if what else "") + (f"tick {tick} has {len(ids)} of {robots} robots' rows "
                                                  f"(missing: {listed})")
            line, at = (bad.line, bad.start) if bad.n else (start_line, start)
            found.append(Damage(path, line, at, tick, to_tick, what))

        for raw in f:
            line_no += 1
            here = offset
            offset += len(raw)
            if not raw.endswith(b"\n"):
                half_written = (line_no, here)  # the run stopped while writing it: not data
                break
            key = _fast_row(raw, len(names), ints, floats)
            if key is None:  # words for booleans, or unreadable: the reader's own rules decide
                values = _parse_row(raw[:-1].decode(errors="replace"), len(names), col)
                key = (int(values[0]), int(values[1])) if values is not None else None
            if key is None:
                if bad.n == 0:
                    bad.start, bad.line = here, line_no
                    bad.first = "".join(chr(c) if 0x20 <= c <= 0x7E else "?" for c in raw[:-1][:60])  # as the viewer
                bad.n += 1
                bad.end = offset
                continue
            t, rid = key
            if tick is None or t != tick:
                if tick is not None:  # (unreadable lines before the first row are the first tick's)
                    finish(t)
                    last_whole = tick
                    bad = _Unreadable()
                tick, start, start_line, ids = t, here, line_no, set()
            ids.add(rid)
    if tick is None:
        return found
    # A last tick short of robots is left out, as the viewer leaves it (its unreadable lines with it).
    short_last = robots > 0 and len(ids) < robots and last_whole is not None
    if not short_last:
        finish(None)
    what = ""
    if half_written:
        what = f"a half-written last line at byte {half_written[1]} ({size - half_written[1]} bytes)"
    shown = tick
    if short_last and last_whole is not None:
        shown = last_whole
        what += ("; " if what else "") + (f"the last tick {tick} has {len(ids)} of {robots} robots' rows "
                                          f"(from byte {start})")
    if what:
        line, at = (start_line, start) if short_last else half_written  # type: ignore[misc]
        found.append(Damage(path, line, at, shown, shown, "ends early (the run stopped while writing): " + what +
                            f"; shown up to tick {shown}", at_open=True))
    return found


# --- readings.csv -----------------------------------------------------------------------------------------


def read_readings(path: str, track: Track, warnings: list[str]) -> Readings:
    """readings.csv on `track`'s ticks and robots. A row that cannot be read, or whose tick or id robots.csv does
    not have, is a RecordingError naming its line; a half-written last line (a run that stopped while writing) is
    dropped with a warning, and ticks the file does not reach stay nan, with a warning."""
    numbered, truncated = _read_lines(path)
    if not numbered:
        raise RecordingError(path, 1, "empty: expected the header tick,id and the sensors' columns")
    header_line, header = numbered[0]
    names = [h.strip() for h in header.split(",")]
    if names[:2] != ["tick", "id"] or len(names) < 3 or any(not n for n in names):
        raise RecordingError(path, header_line, f"header: expected tick,id then the sensors' columns; got "
                                                f"'{header[:80]}'")
    columns = names[2:]
    rows = numbered[1:]
    if truncated and rows:  # the writer ends every line: one without its newline was cut off mid-way
        warnings.append(f"{path}:{rows[-1][0]}: half-written last line dropped (the run stopped while writing)")
        rows = rows[:-1]
    robots = track.robots
    values = np.full((len(track.ticks), robots, len(columns)), np.nan)
    index = {int(t): i for i, t in enumerate(track.ticks)}
    last = -1
    for no, text in rows:
        parts = text.split(",")
        if len(parts) != len(names):
            raise RecordingError(path, no, f"expected {len(names)} comma-separated fields, got {len(parts)}: "
                                           f"'{text[:80]}'")
        try:
            tick, rid = int(parts[0]), int(parts[1])
        except ValueError:
            raise RecordingError(path, no, f"columns 'tick' and 'id': expected integers, got '{parts[0][:20]}', "
                                           f"'{parts[1][:20]}'") from None
        t = index.get(tick)
        if t is None or t < last:
            raise RecordingError(path, no, f"tick {tick}: not a tick of robots.csv, or out of order")
        if not 0 <= rid < robots:
            raise RecordingError(path, no, f"id {rid}: expected 0..{robots - 1}")
        last = t
        for k, field in enumerate(parts[2:]):
            field = field.strip()
            if not field:
                continue  # a dead robot's
            try:
                values[t, rid, k] = float(field)
            except ValueError:
                raise RecordingError(path, no, f"column '{columns[k]}': expected a number or nothing, got "
                                               f"'{field[:20]}'") from None
    if last < len(track.ticks) - 1:
        reached = int(track.ticks[last]) if last >= 0 else None
        warnings.append(f"{path}: ends at tick {reached}, robots.csv at {int(track.ticks[-1])}: the later ticks "
                        "have no readings")
    return Readings(columns, values)


def _leds_column(path: str, rows: list[tuple[int, str]], index: int) -> np.ndarray:
    """[rows, 9]: each row's three LEDs' r, g, b (docs/recording-format.md: empty when all are off, else
    `#rrggbb #rrggbb #rrggbb`). A field of another form is a RecordingError naming its line."""
    out = np.zeros((len(rows), 3 * LED_COUNT), dtype=np.float64)
    for i, (no, text) in enumerate(rows):
        if "#" not in text:  # all off (most rows of most runs): nothing else in a row has a '#'
            continue
        parts = text.split(",", index + 1)
        field = parts[index].strip() if index < len(parts) else ""
        if not field:
            continue
        colours = field.split(" ")
        try:
            if len(colours) != LED_COUNT or any(len(c) != 7 or c[0] != "#" for c in colours):
                raise ValueError(field)
            out[i] = list(bytes.fromhex("".join(c[1:] for c in colours)))
        except ValueError:
            raise RecordingError(path, no, f"column 'leds': expected empty or '#rrggbb #rrggbb #rrggbb', got "
                                 f"'{field[:40]}'") from None
    return out


def _extra_columns(rows: list[tuple[int, str]], indices: list[int]) -> np.ndarray:
    """The behaviour's telemetry columns as floats; an empty or unreadable field is nan."""
    out = np.full((len(rows), len(indices)), np.nan)
    for i, (_, text) in enumerate(rows):
        parts = text.split(",")
        for k, j in enumerate(indices):
            if j < len(parts) and parts[j].strip():
                try:
                    out[i, k] = float(parts[j])
                except ValueError:
                    pass
    return out


def _parse_fast(rows: list[tuple[int, str]], names: list[str], col: dict[str, int]) -> Optional[np.ndarray]:
    """numpy's C parser for a well-formed file (10x faster than row by row); None if anything is off. Only the
    fixed columns (the behaviour's own are read by _extra_columns)."""
    if any(t.count(",") != len(names) - 1 for _, t in rows[:1] + rows[-1:]):
        return None
    try:
        data = np.loadtxt([t for _, t in rows], delimiter=",", dtype=np.float64, ndmin=2,
                          usecols=[col[c] for c in ROBOT_COLUMNS])
    except ValueError:
        return None
    if data.shape != (len(rows), len(ROBOT_COLUMNS)):
        return None
    ints = data[:, [ROBOT_COLUMNS.index(c) for c in INT_COLUMNS]]
    if not np.isfinite(ints).all() or (ints != np.round(ints)).any():
        return None
    return data


def _cell(text: str, name: str) -> float:
    text = text.strip()
    if name in ("alive", "leader"):
        low = text.lower()
        if low in ("true", "false"):
            return 1.0 if low == "true" else 0.0
    return float(text) if name not in INT_COLUMNS else float(int(text))  # nan/inf: see read_robots


def _parse_row(text: str, width: int, col: dict[str, int]) -> Optional[list[float]]:
    parts = text.split(",")
    if len(parts) != width:
        return None
    try:
        return [_cell(parts[col[c]], c) for c in ROBOT_COLUMNS]
    except ValueError:
        return None


def _describe_bad_row(text: str, names: list[str], col: dict[str, int]) -> str:
    parts = text.split(",")
    if len(parts) != len(names):
        return f"expected {len(names)} comma-separated fields, got {len(parts)}: '{text[:80]}'"
    for c in ROBOT_COLUMNS:
        try:
            _cell(parts[col[c]], c)
        except ValueError:
            kind = "an integer" if c in INT_COLUMNS else "a number"
            return f"column '{c}': expected {kind}, got '{parts[col[c]].strip()}'"
    return f"cannot read '{text[:80]}'"


def _to_track(path: str, data: np.ndarray, line_numbers: np.ndarray, expected_robots: int, warnings: list[str],
              extra_names: Sequence[str] = (), has_leds: bool = False) -> Track:
    ticks_col = data[:, 0].astype(np.int64)
    ids = data[:, 1].astype(np.int64)
    back = np.nonzero(np.diff(ticks_col) < 0)[0]
    if back.size:
        i = back[0] + 1
        raise RecordingError(path, int(line_numbers[i]),
                             f"tick {ticks_col[i]} comes after tick {ticks_col[i - 1]}: rows must be in tick order")
    bad = np.nonzero((ids < 0) | ((ids >= expected_robots) if expected_robots else False))[0]
    if bad.size:
        i = bad[0]
        raise RecordingError(path, int(line_numbers[i]),
                             f"robot id {ids[i]} out of range (world.json says {expected_robots} robots)")
    n = expected_robots or int(ids.max()) + 1
    ticks, tick_index = np.unique(ticks_col, return_inverse=True)
    count = np.zeros((len(ticks), n), dtype=np.int64)
    np.add.at(count, (tick_index, ids), 1)
    dup = np.nonzero(count[tick_index, ids] > 1)[0]
    if dup.size:
        i = dup[-1]
        raise RecordingError(path, int(line_numbers[i]), f"robot {ids[i]} appears twice at tick {ticks_col[i]}")
    incomplete = np.nonzero((count == 0).any(axis=1))[0]
    if incomplete.size:
        t = incomplete[0]
        first_row = int(np.argmax(tick_index == t))
        have = int(count[t].sum())
        if t == len(ticks) - 1 and len(ticks) > 1:
            warnings.append(f"{path}:{line_numbers[first_row]}: last tick {ticks[t]} has {have} of {n} robots "
                            "(the run stopped while writing); dropped")
            keep = tick_index < t
            data, tick_index, ids, ticks = data[keep], tick_index[keep], ids[keep], ticks[:-1]
        else:
            raise RecordingError(path, int(line_numbers[first_row]),
                                 f"tick {ticks[t]} has rows for {have} of {n} robots")
    shape = (len(ticks), n)

    def grid(column: str, dtype: Any) -> np.ndarray:
        out = np.zeros(shape, dtype=dtype)
        out[tick_index, ids] = data[:, ROBOT_COLUMNS.index(column)].astype(dtype)
        return out

    extra = {}
    for k, name in enumerate(extra_names):
        out = np.full(shape, np.nan)
        out[tick_index, ids] = data[:, len(ROBOT_COLUMNS) + k]
        extra[name] = out
    leds = np.zeros(shape + (LED_COUNT, 3), dtype=np.uint8)
    if has_leds:
        first = len(ROBOT_COLUMNS) + len(extra_names)
        leds[tick_index, ids] = data[:, first:first + 3 * LED_COUNT].reshape(-1, LED_COUNT, 3).astype(np.uint8)
    return Track(ticks=ticks, x=grid("x", np.float64), y=grid("y", np.float64), theta=grid("theta", np.float64),
                 alive=grid("alive", np.int64) != 0, state=grid("state", np.int64), label=grid("label", np.int64),
                 parent=grid("parent", np.int64), leader=grid("leader", np.int64) != 0,
                 net_force=grid("net_force", np.float64), extra=extra, leds=leds)


# --- events.jsonl -----------------------------------------------------------------------------------------


def read_events(path: str, warnings: list[str]) -> list[dict[str, Any]]:
    numbered, truncated = _read_lines(path)
    events: list[dict[str, Any]] = []
    for k, (no, text) in enumerate(numbered):
        last = k == len(numbered) - 1
        try:
            ev = json.loads(text)
        except json.JSONDecodeError as e:
            if last and truncated:
                warnings.append(f"{path}:{no}: half-written last line dropped (the run stopped while writing)")
                break
            raise RecordingError(path, no, f"not valid JSON: {e.msg} (column {e.colno})") from None
        if not isinstance(ev, dict):
            raise RecordingError(path, no, "expected a JSON object {\"tick\", \"kind\", ...}")
        if not isinstance(ev.get("tick"), int) or isinstance(ev.get("tick"), bool):
            raise RecordingError(path, no, f"'tick' must be an integer, got {ev.get('tick')!r}")
        if not isinstance(ev.get("kind"), str):
            raise RecordingError(path, no, f"'kind' must be a string, got {ev.get('kind')!r}")
        ev["_line"] = no
        events.append(ev)
    return events
