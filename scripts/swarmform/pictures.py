"""The paper's figures from a recording, into RUN_DIR/pictures/:

  snapshot_tNNNNN.png   the arena at chosen ticks (Figs. 4-9): the start, formation, motion start, evenly
                        through the motion, the end, plus any tick asked for
  trajectories.png      every robot's path (Fig. 10)
  residual_force.png    the net force summed over the robots against the path of the formation's centre (Fig. 3)
  shape_error.png       shape error (RMS after a rigid fit, grid units) over time
  states.png            live robots in each of the behaviour's states over time (its own names and colours)
  telemetry.png         the mean over the live robots of each of the behaviour's telemetry columns over time
  animation.mp4/.gif    the whole run (animation.py)

residual_force.png and shape_error.png are the paper's: drawn only for a behaviour that forms a shape and goes to
a goal (world.json's behaviour_descriptor), states.png for any other instead; telemetry.png only for a behaviour
that records columns of its own.

Every figure has a known pixel size (picture_size): the arena figures are 900 px wide and as tall as the view
needs at equal scales; the plots have fixed sizes (PICTURE_SIZES); the videos too (animation.py).
"""

import os
import re
from typing import Any, Callable, Iterable, Optional

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection  # noqa: E402

from . import animation, geometry, scene  # noqa: E402
from .recording import Recording  # noqa: E402
from .scene import Scene, draw_static  # noqa: E402

DPI = 100
PICTURE_SIZES = {"residual_force": (900, 800), "shape_error": (900, 450), "states": (900, 450),
                 "telemetry": (900, 450)}


def picture_size(rec: Recording, kind: str) -> tuple[int, int]:
    """(width, height) px of a picture: "snapshot", "trajectories", "residual_force" or "shape_error"."""
    if kind == "snapshot":
        return scene.arena_figure_size(geometry.view_bounds(rec), scene.LEGEND_AXES)
    if kind == "trajectories":
        return scene.arena_figure_size(geometry.view_bounds(rec), scene.PLAIN_AXES)
    return PICTURE_SIZES[kind]


class PictureError(Exception):
    """A request the recording cannot answer (e.g. a tick beyond its end)."""


def snapshot_ticks(rec: Recording, extra: Iterable[int] = ()) -> list[tuple[int, str]]:
    """[(tick, caption)] in tick order: t=0, formation, motion start, three evenly through the motion, the end
    (the paper's Figs. 4-9); without a formation (e.g. a random walk), five ticks evenly through the run."""
    t = rec.track
    first, last = int(t.ticks[0]), int(t.ticks[-1])
    ph = geometry.phases(rec)
    chosen = {first: "start"}
    if ph["formation"] is not None:
        chosen.setdefault(ph["formation"], "shape formed")
    if ph["motion"] is not None:
        end = ph["goal"] if ph["goal"] is not None else last
        chosen.setdefault(ph["motion"], "motion towards the goal starts")
        for k in (1, 2, 3):
            chosen.setdefault(int(round(ph["motion"] + (end - ph["motion"]) * k / 4)), "")
        if ph["goal"] is not None:
            chosen.setdefault(ph["goal"], "goal reached")
    else:
        for k in (1, 2, 3):
            chosen.setdefault(int(round(first + (last - first) * k / 4)), "")
    chosen.setdefault(last, "end")
    for tick in extra:
        if tick < first or tick > last:
            raise PictureError(f"--ticks {tick}: the recording holds ticks {first}..{last}")
        chosen.setdefault(int(tick), "")
    # Snap to recorded ticks (a recording may skip ticks) and keep one caption per tick.
    out: dict[int, str] = {}
    for tick, caption in sorted(chosen.items()):
        real = int(t.ticks[t.index_of(tick)])
        if real not in out or (caption and not out[real]):
            out[real] = caption
    return sorted(out.items())


def render_all(rec: Recording, out_dir: Optional[str] = None, extra_ticks: Iterable[int] = (), animate: bool = True,
               log: Callable[[str], None] = print, progress: Optional[Callable[[str], None]] = None,
               labels: bool = False) -> list[str]:
    """Writes every picture; returns the list of paths written. `progress(text)`, when given, hears what is being
    drawn (the launcher shows it: the pictures take longer than a lockstep run). labels: robot ids and headings on
    the snapshots."""
    say: Callable[[str], None] = progress or (lambda _text: None)
    out_dir = out_dir or os.path.join(rec.run_dir, "pictures")
    os.makedirs(out_dir, exist_ok=True)
    for name in os.listdir(out_dir):  # snapshots of an earlier drawing (other ticks) would mislead
        if re.fullmatch(r"snapshot_t\d+\.png", name):
            os.remove(os.path.join(out_dir, name))
    written = []
    ticks = snapshot_ticks(rec, extra_ticks)
    view = Scene(rec, picture_size(rec, "snapshot"), DPI, labels=labels)
    try:
        for k, (tick, caption) in enumerate(ticks):
            say(f"snapshot {k + 1}/{len(ticks)} (tick {tick})")
            view.show(rec.track.index_of(tick), caption)
            path = os.path.join(out_dir, f"snapshot_t{tick:05d}.png")
            view.fig.savefig(path, dpi=DPI)
            written.append(path)
    finally:
        view.close()
    say("trajectories, residual force, shape error")
    written.append(trajectories(rec, os.path.join(out_dir, "trajectories.png")))
    paper = rec.world.needs_shape and rec.world.needs_goal
    kinds = ["residual_force", "shape_error"] if paper else ["states"]
    kinds += ["telemetry"] if rec.track.extra else []
    for name in ("residual_force", "shape_error", "states", "telemetry"):  # none left from an earlier drawing
        path = os.path.join(out_dir, f"{name}.png")
        if name not in kinds and os.path.exists(path):
            os.remove(path)
    draw: dict[str, Callable[[Recording, str], str]] = {"residual_force": residual_force, "shape_error": shape_error,
                                                         "states": states, "telemetry": telemetry}
    for name in kinds:
        written.append(draw[name](rec, os.path.join(out_dir, f"{name}.png")))
    if animate:
        written += animation.render(rec, out_dir, log=log, progress=progress)
    return written


def _figure(size: tuple[int, int]) -> Any:
    return plt.figure(figsize=(size[0] / DPI, size[1] / DPI), dpi=DPI)


def _save(fig: Any, path: str) -> str:
    fig.savefig(path, dpi=DPI)
    plt.close(fig)
    return path


def trajectories(rec: Recording, path: str) -> str:
    """Fig. 10: each robot's path from start (circle) to end (square; a cross where it died)."""
    t = rec.track
    size = picture_size(rec, "trajectories")
    fig = _figure(size)
    ax = fig.add_axes(scene.arena_axes_rect(size, scene.PLAIN_AXES))
    draw_static(ax, rec.world, geometry.view_bounds(rec))
    cmap = plt.get_cmap("tab10" if t.robots <= 10 else "tab20")  # tab20 pairs look alike: only when needed
    for k in range(t.robots):
        colour = cmap(k % cmap.N)
        ever_alive = np.nonzero(t.alive[:, k])[0]
        upto = ever_alive[-1] + 1 if ever_alive.size else len(t.ticks)
        xs, ys = t.x[:upto, k], t.y[:upto, k]
        ax.plot(xs, ys, color=colour, linewidth=1.0)
        ax.plot(xs[:1], ys[:1], marker="o", color=colour, markersize=4)
        died = not t.alive[-1, k]
        ax.plot(xs[-1:], ys[-1:], marker="x" if died else "s", color=colour, markersize=6 if died else 4)
    ax.set_title(f"Trajectories of the {t.robots} robots, ticks {t.ticks[0]}-{t.ticks[-1]} "
                 "(o start, \u25a0 end, x died)", fontsize=11)
    return _save(fig, path)


def residual_force(rec: Recording, path: str) -> str:
    """Fig. 3: the net force |F_net| summed over the robots, on the path of the formation's centre (top, as
    colour) and against the distance that centre travelled (bottom). The paper reads obstacles off its peaks."""
    t = rec.track
    total = np.nansum(t.net_force * t.alive, axis=1)
    centre = geometry.formation_centre(t)
    ph = geometry.phases(rec)
    start = t.index_of(ph["motion"]) if ph["motion"] is not None else 0
    sel = np.arange(start, len(t.ticks))
    sel = sel[np.isfinite(centre[sel]).all(axis=1)]
    fig = _figure(PICTURE_SIZES["residual_force"])
    ax = fig.add_axes([0.08, 0.42, 0.80, 0.52])
    cax = fig.add_axes([0.90, 0.42, 0.02, 0.52])
    draw_static(ax, rec.world, geometry.view_bounds(rec))
    ax.apply_aspect()  # the colour bar as tall as the arena drawn at equal scales
    box = ax.get_position()
    cax.set_position([0.90, box.y0, 0.02, box.height])
    ax2 = fig.add_axes([0.08, 0.07, 0.80, 0.26])
    ax2.set_xlabel("distance travelled by the formation's centre (m)")
    ax2.set_ylabel("\u03a3 |F_net|")
    ax2.grid(True, color="#e0e0e0", linewidth=0.5)
    if sel.size >= 2:
        pts = centre[sel]
        segs = np.stack([pts[:-1], pts[1:]], axis=1)
        vmax = max(float(total[sel].max()), 1e-9)
        lc = LineCollection(segs, cmap="inferno_r", norm=plt.Normalize(0.0, vmax), linewidths=3.0, zorder=5)
        lc.set_array(total[sel][1:])
        ax.add_collection(lc)
        fig.colorbar(lc, cax=cax, label="\u03a3 |F_net| over the robots")
        dist = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
        ax2.plot(dist, total[sel], color="#bf360c", linewidth=1.2)
        ax2.set_xlim(0, max(dist[-1], 1e-6))
    else:
        cax.set_axis_off()
        ax2.text(0.5, 0.5, "no formation motion in this run", transform=ax2.transAxes, ha="center",
                 va="center")
    what = "formation motion" if ph["motion"] is not None else "the whole run"
    ax.set_title(f"Residual force along the path of the formation's centre ({what})", fontsize=11)
    return _save(fig, path)


def shape_error(rec: Recording, path: str) -> str:
    """Shape error (docs/recording-format.md) over time, with the formation, motion-start and goal ticks marked."""
    ticks, errors = geometry.distortion_series(rec)
    fig = _figure(PICTURE_SIZES["shape_error"])
    ax = fig.add_axes([0.08, 0.13, 0.88, 0.77])
    ax.set_xlabel("tick")
    ax.set_ylabel("shape error (grid units)")
    ax.grid(True, color="#e0e0e0", linewidth=0.5)
    if ticks.size:
        ax.plot(ticks, errors, color="#1e88e5", linewidth=1.2)
        peak = int(np.argmax(errors))
        ax.plot([ticks[peak]], [errors[peak]], marker="v", color="#c62828")
        ax.annotate(f"peak {errors[peak]:.3f}", (ticks[peak], errors[peak]), textcoords="offset points",
                    xytext=(5, 5), fontsize=8, color="#c62828")
        ax.set_ylim(bottom=0)
    else:
        ax.text(0.5, 0.5, "no labelled robots in this run (no shape to measure)", transform=ax.transAxes,
                ha="center", va="center")
    ax.set_xlim(float(rec.track.ticks[0]), max(float(rec.track.ticks[-1]), float(rec.track.ticks[0]) + 1))
    marks = [(tick, label, colour) for key, label, colour in (("formation", "formed", "#2e7d32"),
                                                               ("motion", "motion starts", "#1e88e5"),
                                                               ("goal", "goal", "#8e24aa"))
             if (tick := geometry.phases(rec)[key]) is not None]
    marks += [(e["tick"], f"robot {e.get('id')} dies", "#c62828") for e in rec.events if e["kind"] == "death"]
    for n, (tick, label, colour) in enumerate(sorted(marks, key=lambda m: m[0])):
        ax.axvline(tick, color=colour, linestyle=":", linewidth=1.0)
        ax.annotate(label, (tick, 1.0), xycoords=("data", "axes fraction"), textcoords="offset points",
                    xytext=(2, -10 - 11 * (n % 3)), fontsize=8, color=colour)  # staggered: ticks may be close
    source = "summary.json" if (rec.summary or {}).get("distortion") else "computed from robots.csv"
    ax.set_title(f"Shape error after the best rigid fit ({source})", fontsize=11)
    return _save(fig, path)


def states(rec: Recording, path: str) -> str:
    """Live robots in each of the behaviour's states over time, stacked, in its own colours."""
    t = rec.track
    fig = _figure(PICTURE_SIZES["states"])
    ax = fig.add_axes([0.08, 0.13, 0.70, 0.77])
    ax.set_xlabel("tick")
    ax.set_ylabel("live robots")
    ax.grid(True, color="#e0e0e0", linewidth=0.5)
    present = sorted(set(int(s) for s in np.unique(t.state[t.alive])))
    names = rec.world.states
    series = [((t.state == v) & t.alive).sum(axis=1) for v in present]
    if series:
        ax.stackplot(t.ticks, series, colors=[names.get(v, (str(v), "#000000"))[1] for v in present],
                     labels=[names.get(v, (f"state {v}", ""))[0] for v in present])
        fig.legend(loc="center left", bbox_to_anchor=(0.80, 0.5), fontsize=8, frameon=False)
    ax.set_xlim(float(t.ticks[0]), max(float(t.ticks[-1]), float(t.ticks[0]) + 1))
    ax.set_ylim(0, max(t.robots, 1))
    ax.set_title(f"Robots by state ({rec.world.behaviour})", fontsize=11)
    return _save(fig, path)


def telemetry(rec: Recording, path: str) -> str:
    """The mean over the live robots of each telemetry column the behaviour records, over time."""
    t = rec.track
    fig = _figure(PICTURE_SIZES["telemetry"])
    ax = fig.add_axes([0.08, 0.13, 0.70, 0.77])
    ax.set_xlabel("tick")
    ax.grid(True, color="#e0e0e0", linewidth=0.5)
    cmap = plt.get_cmap("tab10")
    for k, (name, values) in enumerate(t.extra.items()):
        live = np.where(t.alive, values, np.nan)
        with np.errstate(all="ignore"):
            counted = np.isfinite(live).sum(axis=1)
            mean = np.where(counted > 0, np.nansum(live, axis=1) / np.maximum(counted, 1), np.nan)
        ax.plot(t.ticks, mean, color=cmap(k % cmap.N), linewidth=1.2, label=name)
    fig.legend(loc="center left", bbox_to_anchor=(0.80, 0.5), fontsize=8, frameon=False)
    ax.set_xlim(float(t.ticks[0]), max(float(t.ticks[-1]), float(t.ticks[0]) + 1))
    ax.set_title(f"Telemetry of {rec.world.behaviour} (mean of the live robots)", fontsize=11)
    return _save(fig, path)
