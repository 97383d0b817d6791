"""The arena at one tick, as the paper's Figs. 4-9 show it: walls, obstacles, the goal, robots coloured by state,
parent links, the leader marked, dead robots as grey crosses.

One Scene is built per figure: the static parts (arena, obstacles, goal, legend) are drawn once, and the few
dynamic artists (robots, links, leader, title) are updated in place by `show(index)`. The animation reuses the
same Scene with blitting, so a frame costs only the dynamic artists.
"""

import math
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
from .recording import Recording, World  # noqa: E402

Bounds = tuple[float, float, float, float]  # xmin, xmax, ymin, ymax (m)
States = dict[int, tuple[str, str]]  # a behaviour's states: value -> (name, colour)
UNKNOWN_COLOUR = "#000000"
OBSTACLE_COLOUR = "#6d4c41"
WALL_COLOUR = "#424242"


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


def draw_static(ax: Any, world: World, bounds: Bounds) -> None:
    """Walls, obstacles and the goal; the axes set to `bounds` with equal scales, in metres."""
    x0, x1, y0, y1 = bounds
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.grid(True, color="#e0e0e0", linewidth=0.5)
    ax.set_axisbelow(True)
    cx, cy = world.arena_centre
    ax.add_patch(Rectangle((cx - world.arena_width / 2, cy - world.arena_height / 2), world.arena_width,
                           world.arena_height, fill=False, edgecolor=WALL_COLOUR,
                           linewidth=3.0 if world.walls else 0.8, linestyle="-" if world.walls else "--"))
    for ob in world.obstacles:
        if ob.kind == "cylinder":
            ax.add_patch(Circle(ob.centre, ob.radius, facecolor=OBSTACLE_COLOUR, edgecolor="black", alpha=0.8))
        else:
            hx, hy = ob.half_extents
            c, s = math.cos(ob.yaw), math.sin(ob.yaw)
            corners = [(ob.centre[0] + c * dx - s * dy, ob.centre[1] + s * dx + c * dy)
                       for dx, dy in ((-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy))]
            ax.add_patch(Polygon(corners, closed=True, facecolor=OBSTACLE_COLOUR, edgecolor="black", alpha=0.8))
    if world.goal:
        gx, gy, gr = world.goal
        ax.add_patch(Circle((gx, gy), gr, facecolor="#c8e6c9", edgecolor="#2e7d32", linestyle="--", alpha=0.7))
        ax.plot([gx], [gy], marker="x", color="#2e7d32", markersize=8)
        ax.annotate("goal", (gx, gy + gr), textcoords="offset points", xytext=(0, 3), ha="center",
                    color="#2e7d32", fontsize=8)


def legend_handles(states_present: set[int], world_states: States, leaders: bool = True,
                   links: bool = True) -> list[Any]:
    """The legend: the behaviour's states shown in this run, then leader and parent link only when the run's
    telemetry has any (the paper's), and the dead."""
    handles = [Line2D([], [], marker="o", linestyle="", markerfacecolor=world_states[s][1], markeredgecolor="black",
                      markersize=7, label=world_states[s][0]) for s in sorted(states_present) if s in world_states]
    if leaders:
        handles.append(Line2D([], [], marker="*", linestyle="", markerfacecolor="none", markeredgecolor="red",
                              markersize=12, label="leader"))
    handles.append(Line2D([], [], marker="x", linestyle="", color="#757575", markersize=7, label="dead"))
    if links:
        handles.append(Line2D([], [], color="#455a64", linewidth=0.8, label="parent link"))
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
        draw_static(self.ax, rec.world, self.bounds)
        if legend:
            present = set(int(s) for s in np.unique(rec.track.state))  # only the states this run shows
            handles = legend_handles(present, rec.world.states, bool(rec.track.leader.any()),
                                     bool((rec.track.parent >= 0).any()))
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
        # The caption is a figure text just above the axes as drawn (after the equal-aspect shrink): an axes
        # title would be moved by matplotlib only during a full draw, which blitted frames never do.
        self.ax.apply_aspect()
        box = self.ax.get_position()
        self.title = self.fig.text((box.x0 + box.x1) / 2, box.y1 + 0.015, "", ha="center", va="bottom",
                                   fontsize=11)
        self.dynamic = [self.links, self.robots, self.dead, self.leader, self.title]

    def show(self, i: int, caption: Optional[str] = None) -> None:
        """Updates the dynamic artists to recorded tick index `i`."""
        t = self.rec.track
        x, y, alive = t.x[i], t.y[i], t.alive[i]
        live = np.nonzero(alive)[0]
        self.robots.set_offsets(np.column_stack([x[live], y[live]]) if live.size else np.empty((0, 2)))
        self.robots.set_facecolors(state_colours(t.state[i][live], self.world_states))
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
        if self.labels:
            self._label(live, x, y, t.theta[i])
        tick = int(t.ticks[i])
        seconds = tick / self.rec.world.tick_rate if self.rec.world.tick_rate > 0 else 0.0
        text = f"t = {tick} ({seconds:.1f} s)   alive {len(live)}/{n}"
        self.title.set_text(f"{text}: {caption}" if caption else text)

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
