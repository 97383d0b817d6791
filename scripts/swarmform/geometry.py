"""Quantities the figures need that the recording does not hold directly: the formation's centre, the phases'
ticks and the shape error (docs/recording-format.md) when summary.json has no `distortion` series.

The shape error is the RMS distance of each live labelled robot from its label's place after the best rigid fit
(rotation and translation, no scaling) of the label grid onto the robots, in grid units -- the same definition
as world_server/run/metrics.hpp, so a figure drawn from a crashed run's recording matches what the world would
have reported.
"""

import math
from typing import Any, Optional, Sequence

import numpy as np

from .recording import MOTION, READY, Recording, Track


def shape_error(places: dict[int, tuple[float, float]], labels: Sequence[Any], xs: Sequence[float],
                ys: Sequence[float], spacing: float) -> Optional[float]:
    """RMS fit error in grid units for robots with these labels at (xs, ys); None for fewer than 2 robots.

    places: label -> (x, y) of the label's grid cell. The 2-D Kabsch fit has a closed form: the rotation angle
    is atan2(sum of cross products, sum of dot products) of the centred point sets.
    """
    seen: set[int] = set()
    p: list[tuple[float, float]] = []
    q: list[tuple[float, float]] = []
    for raw_label, x, y in zip(labels, xs, ys):
        label = int(raw_label)
        if label in places and label not in seen:  # a label held twice (a transient conflict) counts once
            seen.add(label)
            p.append(places[label])
            q.append((x, y))
    if len(p) < 2:
        return None
    pa, qa = np.asarray(p, dtype=float), np.asarray(q, dtype=float)
    pc, qc = pa - pa.mean(axis=0), qa - qa.mean(axis=0)
    dot = float((pc * qc).sum())
    cross = float((pc[:, 0] * qc[:, 1] - pc[:, 1] * qc[:, 0]).sum())
    a = math.atan2(cross, dot)
    rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    residual = qc - pc @ rot.T
    return float(np.sqrt((residual ** 2).sum(axis=1).mean())) / spacing


def shape_members(track: Track) -> np.ndarray:
    """[T, N] bool: live robots that hold a label (the formation); all live robots if nobody ever has one."""
    members = track.alive & (track.label >= 0)
    if not members.any():
        members = track.alive.copy()
    return members


def formation_centre(track: Track) -> np.ndarray:
    """[T, 2] centre of the formation's members at every tick (NaN where there are none)."""
    m = shape_members(track)
    count = m.sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        cx = np.where(count > 0, (track.x * m).sum(axis=1) / count, np.nan)
        cy = np.where(count > 0, (track.y * m).sum(axis=1) / count, np.nan)
    return np.stack([cx, cy], axis=1)


def _summary_tick(summary: Optional[dict[str, Any]], key: str) -> Optional[int]:
    v = (summary or {}).get(key)
    return int(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else None


def phases(rec: Recording) -> dict[str, Optional[int]]:
    """Ticks of the run's phases: formation (all shape robots ready), motion start, goal; None when not reached.

    summary.json's values win (the world computed them from the truth); otherwise derived from the states, for
    the paper's kind of behaviour only (one that forms a shape and goes to a goal): another behaviour's state
    values mean other things, and it has no such phases.
    """
    track, summary = rec.track, rec.summary
    out = {"formation": _summary_tick(summary, "formation_tick"),
           "motion": _summary_tick(summary, "motion_start_tick"),
           "goal": _summary_tick(summary, "goal_tick")}
    if not (rec.world.needs_shape and rec.world.needs_goal):
        return out
    labelled = track.alive & (track.label >= 0)
    if out["formation"] is None:
        n = rec.world.shape.label_count() if rec.world.shape else None
        ready = ((track.state >= READY) | ~labelled).all(axis=1) & (labelled.sum(axis=1) > 0)
        if n:
            ready &= labelled.sum(axis=1) >= n
        hit = np.nonzero(ready)[0]
        out["formation"] = int(track.ticks[hit[0]]) if hit.size else None
    if out["motion"] is None:
        hit = np.nonzero((track.alive & (track.state == MOTION)).any(axis=1))[0]
        out["motion"] = int(track.ticks[hit[0]]) if hit.size else None
    return out


def distortion_series(rec: Recording) -> tuple[np.ndarray, np.ndarray]:
    """(ticks, shape error) arrays: summary.json's `distortion` if present, else computed from the recording
    for every tick from formation on (from the first tick with two labelled robots when formation never came).
    """
    series = (rec.summary or {}).get("distortion")
    if isinstance(series, list) and series:
        ticks: list[float] = []
        errors: list[float] = []
        for item in series:
            if isinstance(item, dict):
                t, e = item.get("tick"), item.get("shape_error", item.get("error", item.get("value")))
            elif isinstance(item, (list, tuple)) and len(item) == 2:
                t, e = item
            else:
                t, e = None, None
            if isinstance(t, (int, float)) and isinstance(e, (int, float)):
                ticks.append(t)
                errors.append(e)
        if ticks:
            return np.asarray(ticks, dtype=float), np.asarray(errors, dtype=float)
    shape = rec.world.shape
    track = rec.track
    if shape is None:
        return np.array([]), np.array([])
    places = shape.places(rec.world.grid_spacing)
    start_tick = phases(rec)["formation"]
    start = track.index_of(start_tick) if start_tick is not None else 0
    ticks, errors = [], []
    for i in range(start, len(track.ticks)):
        m = track.alive[i] & (track.label[i] >= 0)
        if m.sum() < 2:
            continue
        e = shape_error(places, track.label[i][m], track.x[i][m], track.y[i][m], rec.world.grid_spacing)
        if e is not None:
            ticks.append(track.ticks[i])
            errors.append(e)
    return np.asarray(ticks, dtype=float), np.asarray(errors, dtype=float)


def view_bounds(rec: Recording, pad: float = 1.0) -> tuple[float, float, float, float]:
    """(xmin, xmax, ymin, ymax) of what the pictures show: every robot's path, the goal, the lights and the obstacles,
    padded and kept inside the arena -- the swarm is small in a large arena, and the paper's figures zoom."""
    w, t = rec.world, rec.track
    xs = [np.nanmin(t.x), np.nanmax(t.x)]
    ys = [np.nanmin(t.y), np.nanmax(t.y)]
    for gx, gy, gr in ([w.goal] if w.goal else []) + [m[1:] for m in w.goal_moves]:  # every goal it has had
        xs += [gx - gr, gx + gr]
        ys += [gy - gr, gy + gr]
    for light in w.lights:  # what a phototaxis heads for
        xs.append(light.position[0])
        ys.append(light.position[1])
    places = [(ob, ob.centre) for ob in w.obstacles]
    places += [(w.obstacles[ev.obstacle], ev.centre) for ev in w.world_events if ev.centre is not None]  # moved to
    for ob, centre in places:
        r = ob.radius if ob.kind == "cylinder" else math.hypot(*ob.half_extents)
        xs += [centre[0] - r, centre[0] + r]
        ys += [centre[1] - r, centre[1] + r]
    ax0, ay0 = w.arena_centre[0] - w.arena_width / 2, w.arena_centre[1] - w.arena_height / 2
    ax1, ay1 = ax0 + w.arena_width, ay0 + w.arena_height
    m = 0.15  # keep the walls in view when the box reaches them
    x0, x1 = max(min(xs) - pad, ax0 - m), min(max(xs) + pad, ax1 + m)
    y0, y1 = max(min(ys) - pad, ay0 - m), min(max(ys) + pad, ay1 + m)
    if x1 - x0 < 2:
        x0, x1 = (x0 + x1) / 2 - 1, (x0 + x1) / 2 + 1
    if y1 - y0 < 2:
        y0, y1 = (y0 + y1) / 2 - 1, (y0 + y1) / 2 + 1
    return x0, x1, y0, y1
