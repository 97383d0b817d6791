"""The arena at one tick, as the paper's Figs. 4-9 show it: walls, obstacles, the goal, robots coloured by state,
parent links, the leader marked, dead robots as grey crosses; and what the Khepera IV's optional sensors and
actuators meet: the floor under everything (its image, its regions), the light sources, each live robot's lit
LEDs as three small dots on it.

One Scene is built per figure: the static parts (arena, obstacles, goal, legend) are drawn once, and the few
dynamic artists (robots, links, leader, title) are updated in place by `show(index)`. The animation reuses the
same Scene with blitting, so a frame costs only the dynamic artists.
"""

import math
import os
import warnings
from typing import Any, Optional, Sequence

import matplotlib

matplotlib.use("Agg")  # headless: no display, ever
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.patches import Circle, Polygon, Rectangle  # noqa: E402

from .geometry import view_bounds  # noqa: E402
from .recording import STATE_COLOURS  # noqa: E402,F401  (the paper's; a recording carries its behaviour's)
from .recording import Floor, FloorRegion, Obstacle, Recording, World, goal_at, obstacles_at  # noqa: E402

Bounds = tuple[float, float, float, float]  # xmin, xmax, ymin, ymax (m)
States = dict[int, tuple[str, str]]  # a behaviour's states: value -> (name, colour)
UNKNOWN_COLOUR = "#000000"
OBSTACLE_COLOUR = "#6d4c41"
WALL_COLOUR = "#424242"
LIGHT_COLOUR = "#ffd600"
LIGHT_EDGE = "#e65100"
REGION_EDGE = "#9e9e9e"  # so that a region the floor's own colour still shows where it is
# Below everything else, in painting order (the grid lines are at 0.5, the other patches at 1).
Z_FLOOR, Z_FLOOR_IMAGE, Z_REGIONS = 0.1, 0.2, 0.3
Z_LIGHTS, Z_LEDS = 4.6, 4.5  # over the robots (4), under the leader's star (5)
# Each LED is drawn at this fraction of the drawn robot's radius from its centre, 120 degrees apart, LED 0
# ahead: the three tell the heading too.
LED_OFFSET = 0.55


# Arena figures (snapshots, trajectories) are 900 px wide and as tall as the view needs at equal scales
# (clamped), so a wide arena does not leave half the picture blank. Margins in pixels: axis labels, caption.
ARENA_WIDTH_PX = 900
MARGIN_BOTTOM_PX, MARGIN_TOP_PX = 55, 45
LEGEND_AXES = (0.07, 0.74)  # left, width (fractions): room for the legend on the right
PLAIN_AXES = (0.08, 0.88)


def arena_figure_size(bounds: Bounds, axes: tuple[float, float] = LEGEND_AXES, width_px: int = ARENA_WIDTH_PX,
                      min_h: int = 360, max_h: int = 900) -> tuple[int, int]:
    """(width, height) px of a figure whose axes (left, width fractions) show `bounds` at equal scales."""
    x0, x1, y0, y1 = bounds
    h = width_px * axes[1] * (y1 - y0) / (x1 - x0) + MARGIN_BOTTOM_PX + MARGIN_TOP_PX
    h = int(round(min(max(h, min_h), max_h)))
    return width_px, h + h % 2


def arena_axes_rect(size_px: tuple[int, int], axes: tuple[float, float] = LEGEND_AXES) -> list[float]:
    h = size_px[1]
    return [axes[0], MARGIN_BOTTOM_PX / h, axes[1], (h - MARGIN_BOTTOM_PX - MARGIN_TOP_PX) / h]


def state_colours(states: Sequence[Any], world_states: States) -> list[str]:
    """The colour of each state value, from the behaviour's states {value: (name, colour)}."""
    return [world_states.get(int(s), ("", UNKNOWN_COLOUR))[1] for s in states]


# A mixed swarm's robots are edged in their group's colour (the page's outlines: viewer/web/viewer.js).
GROUP_EDGES = ["#263238", "#d81b60", "#ff6f00", "#00897b", "#5e35b1", "#6d4c41"]


def robot_colours(world: Any, ids: Any, states: Sequence[Any]) -> list[str]:
    """Each robot's fill by its own behaviour's states (its group's in a mixed swarm)."""
    if not world.groups:
        return state_colours(states, world.states)
    return [world.states_of(int(k)).get(int(s), ("", UNKNOWN_COLOUR))[1] for k, s in zip(ids, states)]


def robot_edges(world: Any, ids: Any) -> Any:
    """Each robot's edge colour: its group's (black without groups)."""
    if not world.groups:
        return "black"
    out = []
    for k in ids:
        g = next((j for j, grp in enumerate(world.groups) if grp.first_id <= int(k) < grp.first_id + grp.count), 0)
        out.append(GROUP_EDGES[g % len(GROUP_EDGES)])
    return out


def group_handles(world: Any, states_present: dict[int, set[int]]) -> list[Any]:
    """A mixed swarm's legend: per group, a ring in its edge colour with its name, then its states shown."""
    handles = []
    for j, g in enumerate(world.groups):
        handles.append(Line2D([], [], marker="o", linestyle="", markerfacecolor="none", markeredgewidth=2,
                              markeredgecolor=GROUP_EDGES[j % len(GROUP_EDGES)], markersize=8,
                              label=f"{g.name}:"))
        for s in sorted(states_present.get(j, set())):
            if s in g.states:
                handles.append(Line2D([], [], marker="o", linestyle="", markerfacecolor=g.states[s][1],
                                      markeredgecolor="black", markersize=7, label=f"  {g.states[s][0]}"))
    return handles


def _region_patch(r: FloorRegion) -> Any:
    if r.kind == "circle":
        return Circle(r.centre, r.radius)
    hx, hy = r.half_extents
    c, s = math.cos(r.yaw), math.sin(r.yaw)
    return Polygon([(r.centre[0] + c * dx - s * dy, r.centre[1] + s * dx + c * dy)
                    for dx, dy in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))], closed=True)


def draw_floor(ax: Any, world: World) -> None:
    """The floor as the ground sensors read it (recording.Floor), under everything: its base colour over the arena,
    its image stretched over the arena's rectangle, its regions in painting order. A plain white floor draws
    nothing; an image that cannot be read is left out with a warning."""
    floor: Floor = world.floor
    if floor.plain():
        return
    cx, cy = world.arena_centre
    x0, y0 = cx - world.arena_width / 2, cy - world.arena_height / 2
    if floor.grey < 1.0 or floor.colour is not None:
        ax.add_patch(Rectangle((x0, y0), world.arena_width, world.arena_height, facecolor=floor.face(),
                               edgecolor="none", zorder=Z_FLOOR))
    if floor.image:
        try:
            pixels = plt.imread(floor.image) if os.path.isfile(floor.image) else None
        except (OSError, ValueError, SyntaxError) as e:
            warnings.warn(f"{floor.image}: the floor's image cannot be read ({e}); drawn without it")
            pixels = None
        if pixels is None and not os.path.isfile(floor.image):
            warnings.warn(f"{floor.image}: the floor's image is missing; drawn without it")
        if pixels is not None:
            # The image's top row is the arena's +y edge (world_server/world/floor.hpp).
            ax.imshow(pixels, extent=(x0, x0 + world.arena_width, y0, y0 + world.arena_height), origin="upper",
                      cmap="gray" if pixels.ndim == 2 else None, vmin=0.0, vmax=1.0, interpolation="nearest",
                      zorder=Z_FLOOR_IMAGE, aspect="auto")
    for r in floor.regions:
        patch = _region_patch(r)
        patch.set_facecolor(r.face())
        patch.set_edgecolor(REGION_EDGE)
        patch.set_linewidth(0.5)
        patch.set_zorder(Z_REGIONS)
        ax.add_patch(patch)


def draw_lights(ax: Any, world: World) -> None:
    """Each light source as a sun marker at its position, with its intensity (and height) beside it."""
    for light in world.lights:
        x, y = light.position
        ax.plot([x], [y], marker="*", markersize=16, markerfacecolor=LIGHT_COLOUR, markeredgecolor=LIGHT_EDGE,
                markeredgewidth=1.0, linestyle="", zorder=Z_LIGHTS)
        ax.annotate(f"light I={light.intensity:g}, h={light.height:g} m", (x, y), textcoords="offset points",
                    xytext=(0, 9), ha="center", fontsize=7, color=LIGHT_EDGE, zorder=Z_LIGHTS)


def led_positions(x: np.ndarray, y: np.ndarray, theta: np.ndarray, radius: float) -> np.ndarray:
    """[N, 3, 2]: where each robot's three LEDs are drawn, `radius` the robot's drawn radius (m)."""
    angles = theta[:, None] + np.array([0.0, 2 * math.pi / 3, -2 * math.pi / 3])[None, :]
    r = LED_OFFSET * radius
    return np.stack([x[:, None] + r * np.cos(angles), y[:, None] + r * np.sin(angles)], axis=-1)


def box_corners(ob: Obstacle) -> list[tuple[float, float]]:
    hx, hy = ob.half_extents
    c, s = math.cos(ob.yaw), math.sin(ob.yaw)
    return [(ob.centre[0] + c * dx - s * dy, ob.centre[1] + s * dx + c * dy)
            for dx, dy in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))]


def obstacle_patch(ob: Obstacle, filled: bool = True) -> Any:
    """An obstacle as drawn: filled where it stands; an outline, dashed, where it stood or will stand."""
    style: dict[str, Any] = ({"facecolor": OBSTACLE_COLOUR, "edgecolor": "black", "alpha": 0.8} if filled else
                             {"fill": False, "edgecolor": OBSTACLE_COLOUR, "linestyle": "--", "alpha": 0.8})
    if ob.kind == "cylinder":
        return Circle(ob.centre, ob.radius, **style)
    return Polygon(box_corners(ob), closed=True, **style)


def draw_obstacles(ax: Any, world: World) -> None:
    """The obstacles of a whole run: each where it stands at the end, filled; with world events, every other place
    it held (or its place while absent) as a dashed outline."""
    end = obstacles_at(world, world.world_events[-1].tick) if world.world_events else world.obstacles
    for k, ob in enumerate(end):
        if ob.present:
            ax.add_patch(obstacle_patch(ob))
        held = [world.obstacles[k]] + [obstacles_at(world, e.tick)[k] for e in world.world_events if e.obstacle == k]
        for past in held:
            if (past.centre, past.yaw, past.present) != (ob.centre, ob.yaw, ob.present) or not ob.present:
                ax.add_patch(obstacle_patch(past, filled=False))


def draw_static(ax: Any, world: World, bounds: Bounds, obstacles: bool = True, goal: bool = True) -> None:
    """The floor, walls, obstacles and the goal (unless the caller draws them as they stand: Scene) and the
    lights; the axes set to `bounds` with equal scales, in metres."""
    x0, x1, y0, y1 = bounds
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(True, color="#e0e0e0", linewidth=0.5)
    ax.set_axisbelow(True)
    draw_floor(ax, world)
    cx, cy = world.arena_centre
    ax.add_patch(Rectangle((cx - world.arena_width / 2, cy - world.arena_height / 2), world.arena_width,
                           world.arena_height, fill=False, edgecolor=WALL_COLOUR,
                           linewidth=3.0 if world.walls else 0.8, linestyle="-" if world.walls else "--"))
    if obstacles:
        draw_obstacles(ax, world)
    if goal and world.goal:
        # Where world events moved it: each goal it had, the last filled, the earlier ones hollow with the tick
        # they stood until.
        goals = [(None, *world.goal)] + list(world.goal_moves)
        for k, (_, gx, gy, gr) in enumerate(goals):
            last = k == len(goals) - 1
            ax.add_patch(Circle((gx, gy), gr, facecolor="#c8e6c9" if last else "none", edgecolor="#2e7d32",
                                linestyle="--", alpha=0.7))
            ax.plot([gx], [gy], marker="x", color="#2e7d32", markersize=8)
            label = "goal" if last else f"goal until tick {goals[k + 1][0]}"
            ax.annotate(label, (gx, gy + gr), textcoords="offset points", xytext=(0, 3), ha="center",
                        color="#2e7d32", fontsize=8)
    draw_lights(ax, world)


def legend_handles(states_present: set[int], world_states: States, leaders: bool = True,
                   links: bool = True, lights: bool = False, leds: bool = False) -> list[Any]:
    """The legend: the behaviour's states shown in this run, then leader and parent link only when the run's
    telemetry has any (the paper's), the dead, and the lights and LEDs when the run has any."""
    handles = [Line2D([], [], marker="o", linestyle="", markerfacecolor=world_states[s][1], markeredgecolor="black",
                      markersize=7, label=world_states[s][0]) for s in sorted(states_present) if s in world_states]
    if leaders:
        handles.append(Line2D([], [], marker="*", linestyle="", markerfacecolor="none", markeredgecolor="red",
                              markersize=12, label="leader"))
    handles.append(Line2D([], [], marker="x", linestyle="", color="#757575", markersize=7, label="dead"))
    if links:
        handles.append(Line2D([], [], color="#455a64", linewidth=0.8, label="parent link"))
    if lights:
        handles.append(Line2D([], [], marker="*", linestyle="", markerfacecolor=LIGHT_COLOUR,
                              markeredgecolor=LIGHT_EDGE, markersize=12, label="light"))
    if leds:
        handles.append(Line2D([], [], marker=".", linestyle="", color="#43a047", markersize=7,
                              label="LEDs (lit)"))
    return handles


class Scene:
    """A figure of the arena whose robots can be shown at any recorded tick."""

    def __init__(self, rec: Recording, size_px: Optional[tuple[int, int]] = None, dpi: int = 100,
                 legend: bool = True, labels: bool = False) -> None:
        """size_px None: 900 px wide and as tall as the view needs (arena_figure_size). labels: each live robot's
        id beside it and a line along its heading (snapshots' --labels)."""
        self.rec = rec
        self.labels = labels
        self.label_texts: list[Any] = []
        self.world_states = rec.world.states  # the behaviour's {value: (name, colour)}
        self.bounds = view_bounds(rec)
        axes = LEGEND_AXES if legend else PLAIN_AXES
        self.size_px = size_px or arena_figure_size(self.bounds, axes)
        self.fig = plt.figure(figsize=(self.size_px[0] / dpi, self.size_px[1] / dpi), dpi=dpi)
        self.ax = self.fig.add_axes(arena_axes_rect(self.size_px, axes))
        # Obstacles that world events move, add or remove are drawn as they stand at the shown tick.
        moving = bool(rec.world.world_events)
        first_goal = rec.world.goal if rec.world.goal_moves else None  # so is a goal that world events move
        draw_static(self.ax, rec.world, self.bounds, obstacles=not moving, goal=first_goal is None)
        self.obstacles = [self.ax.add_patch(obstacle_patch(ob)) for ob in rec.world.obstacles] if moving else []
        self.goal: list[Any] = []
        if first_goal is not None:
            gx, gy, gr = first_goal
            self.goal = [self.ax.add_patch(Circle((gx, gy), gr, facecolor="#c8e6c9", edgecolor="#2e7d32",
                                                  linestyle="--", alpha=0.7)),
                         self.ax.plot([gx], [gy], marker="x", color="#2e7d32", markersize=8)[0]]
        if legend:
            present = set(int(s) for s in np.unique(rec.track.state))  # only the states this run shows
            by_group = {j: set(int(s) for s in np.unique(rec.track.state[:, g.first_id:g.first_id + g.count]))
                        for j, g in enumerate(rec.world.groups)}
            handles = legend_handles(set() if rec.world.groups else present, rec.world.states,
                                     bool(rec.track.leader.any()), bool((rec.track.parent >= 0).any()),
                                     bool(rec.world.lights), rec.track.leds is not None and bool(rec.track.leds.any()))
            handles = group_handles(rec.world, by_group) + handles
            self.fig.legend(handles=handles, loc="center left",
                            bbox_to_anchor=(0.82, 0.5), fontsize=8, frameon=False)
        # Robots at true size, but never smaller than a few pixels (the arena is large, the robots small).
        ppm = self.ax.get_window_extent().width / (self.bounds[1] - self.bounds[0]) * 72.0 / dpi  # points/m
        diameter_pt = max(2 * rec.world.robot_radius * ppm, 5.0)
        self.links = LineCollection([], colors="#455a64", linewidths=0.8, zorder=3)
        self.ax.add_collection(self.links)
        self.robots = self.ax.scatter([], [], s=diameter_pt ** 2, edgecolors="black", linewidths=0.4, zorder=4)
        self.dead = self.ax.scatter([], [], s=diameter_pt ** 2, marker="x", c="#757575", linewidths=1.2,
                                    zorder=4)
        self.leader = self.ax.scatter([], [], s=(diameter_pt * 2.6) ** 2, marker="*", facecolors="none",
                                      edgecolors="red", linewidths=1.2, zorder=5)
        # The LEDs: dots a third of the drawn robot wide (never under 2.5 points), placed by the drawn radius.
        self.drawn_radius = diameter_pt / 2 / ppm  # m
        led_pt = max(diameter_pt * 0.34, 2.5)
        self.leds = self.ax.scatter([], [], s=led_pt ** 2, edgecolors="black", linewidths=0.25, zorder=Z_LEDS)
        # The caption is a figure text just above the axes as drawn (after the equal-aspect shrink): an axes
        # title would be moved by matplotlib only during a full draw, which blitted frames never do.
        self.ax.apply_aspect()
        box = self.ax.get_position()
        self.title = self.fig.text((box.x0 + box.x1) / 2, box.y1 + 0.015, "", ha="center", va="bottom",
                                   fontsize=11)
        self.dynamic = [*self.obstacles, *self.goal, self.links, self.robots, self.dead, self.leds, self.leader, self.title]

    def show(self, i: int, caption: Optional[str] = None) -> None:
        """Updates the dynamic artists to recorded tick index `i`."""
        t = self.rec.track
        x, y, alive = t.x[i], t.y[i], t.alive[i]
        live = np.nonzero(alive)[0]
        self.robots.set_offsets(np.column_stack([x[live], y[live]]) if live.size else np.empty((0, 2)))
        self.robots.set_facecolors(robot_colours(self.rec.world, live, t.state[i][live]))
        if self.rec.world.groups:
            self.robots.set_edgecolors(robot_edges(self.rec.world, live))
            self.robots.set_linewidths(1.2)
        deadi = np.nonzero(~alive)[0]
        self.dead.set_offsets(np.column_stack([x[deadi], y[deadi]]) if deadi.size else np.empty((0, 2)))
        lead = np.nonzero(alive & t.leader[i])[0]
        self.leader.set_offsets(np.column_stack([x[lead], y[lead]]) if lead.size else np.empty((0, 2)))
        segments = []
        n = t.robots
        for k in live:
            p = int(t.parent[i][k])
            if 0 <= p < n and p != k:
                segments.append([(x[k], y[k]), (x[p], y[p])])
        self.links.set_segments(segments)
        self._show_leds(i, live)
        self._show_obstacles(int(t.ticks[i]))
        self._show_goal(int(t.ticks[i]))
        if self.labels:
            self._label(live, x, y, t.theta[i])
        tick = int(t.ticks[i])
        seconds = tick / self.rec.world.tick_rate if self.rec.world.tick_rate > 0 else 0.0
        text = f"t = {tick} ({seconds:.1f} s)   alive {len(live)}/{n}"
        self.title.set_text(f"{text}: {caption}" if caption else text)

    def _show_leds(self, i: int, live: np.ndarray) -> None:
        """The lit LEDs of the live robots at tick index `i` (an LED that is off is not drawn)."""
        t = self.rec.track
        if t.leds is None or not live.size:
            self.leds.set_offsets(np.empty((0, 2)))
            return
        colours = t.leds[i][live]  # [n, 3, 3]
        lit = colours.any(axis=2)  # [n, 3]
        if not lit.any():
            self.leds.set_offsets(np.empty((0, 2)))
            return
        at = led_positions(t.x[i][live], t.y[i][live], t.theta[i][live], self.drawn_radius)
        self.leds.set_offsets(at[lit])
        self.leds.set_facecolors(colours[lit] / 255.0)

    def _show_obstacles(self, tick: int) -> None:
        """The obstacles world events move, add and remove, as they stand at `tick`."""
        if not self.obstacles:
            return
        for patch, ob in zip(self.obstacles, obstacles_at(self.rec.world, tick)):
            patch.set_visible(ob.present)
            if isinstance(patch, Circle):
                patch.set_center(ob.centre)
            else:
                patch.set_xy(box_corners(ob))

    def _show_goal(self, tick: int) -> None:
        """A goal that world events move, where it stands at `tick`."""
        goal = goal_at(self.rec.world, tick)
        if not self.goal or goal is None:
            return
        gx, gy, gr = goal
        disc, mark = self.goal
        disc.set_center((gx, gy))
        disc.set_radius(gr)
        mark.set_data([gx], [gy])

    def _label(self, live: np.ndarray, x: np.ndarray, y: np.ndarray, theta: np.ndarray) -> None:
        """Ids and headings of the live robots (replacing the previous tick's)."""
        for a in self.label_texts:
            a.remove()
        self.label_texts = []
        r = 2.5 * self.rec.world.robot_radius
        for k in live:
            self.label_texts.append(self.ax.annotate(str(k), (x[k], y[k]), textcoords="offset points",
                                                     xytext=(4, 4), fontsize=6, color="#212121", zorder=6))
            self.label_texts += self.ax.plot([x[k], x[k] + r * np.cos(theta[k])], [y[k], y[k] + r * np.sin(theta[k])],
                                             color="#212121", linewidth=0.8, zorder=6)

    def close(self) -> None:
        plt.close(self.fig)
