"""`swarm plot SWEEP_DIR` (and `swarm sweep ... --plot`): the figures a paper shows, from a sweep's sweep.csv and
sweep.json, as PNG and SVG in SWEEP_DIR/figures/ (docs/sweeps.md "Figures"):

  success.{png,svg}   the success rate over the grid's two axes with the most values, as a heat map (one axis: bars)
  metric.{png,svg}    a metric (--metric KEY; default the paper's goal_tick, else the behaviour's first metric, else
                      ticks) against the grid's first numeric axis (else its first axis): the median over the runs
                      of each point with its 95 % confidence interval, one line per shape (else scenario, else
                      value of the grid's next axis)
  failures.{png,svg}  the failed runs by reason (the reason's kind: its text before ':', numbers dropped)

The grid's axes are the sweep's columns whose value varies: scenario, shape, robots_asked, kills, each param_NAME and
each scenario-field column (loss, burst, noise, set_KEY); seeds are the repetitions, never an axis. The
interval of a median is distribution-free: the order statistics whose ranks a Binomial(n, 1/2) puts 95 % between
(median_interval below); with fewer than 6 runs at a point it is the range of the runs."""

import csv
import json
import math
import os
import re
from typing import Any, Optional, Sequence

AXES = ["scenario", "shape", "robots_asked", "kills"]  # then param_* and the grid's field columns
FORMATS = ("png", "svg")


class PlotError(Exception):
    pass


def median_interval(values: Sequence[float], confidence: float = 0.95) -> tuple[float, float, float]:
    """(median, low, high): the sample median and the distribution-free interval [x_(j), x_(k)] (1-based order
    statistics) with the smallest symmetric j for which P(j <= B < k) >= confidence, B ~ Binomial(n, 1/2),
    k = n + 1 - j. Fewer than 6 values: no such j exists at 95 %, and the interval is their range."""
    xs = sorted(values)
    n = len(xs)
    if n == 0:
        raise ValueError("no values")
    mid = n // 2
    median = xs[mid] if n % 2 else (xs[mid - 1] + xs[mid]) / 2
    pmf = [math.comb(n, i) / 2 ** n for i in range(n + 1)]
    best: Optional[int] = None
    for j in range(1, n // 2 + 1):
        k = n + 1 - j
        if sum(pmf[j:k]) >= confidence:
            best = j
        else:
            break
    if best is None:
        return median, xs[0], xs[-1]
    return median, xs[best - 1], xs[n - best]


def _number(text: str) -> Optional[float]:
    try:
        v = float(text)
    except (TypeError, ValueError):
        return None
    return v if math.isfinite(v) else None


def load(sweep_dir: str) -> tuple[list[dict[str, str]], dict[str, Any]]:
    """sweep.csv's rows and sweep.json. Raises PlotError naming the file."""
    csv_path, json_path = os.path.join(sweep_dir, "sweep.csv"), os.path.join(sweep_dir, "sweep.json")
    try:
        with open(json_path, "rb") as f:
            res = json.loads(f.read().decode("utf-8"))
        with open(csv_path, "rb") as f:
            text = f.read().decode("utf-8")
    except FileNotFoundError as e:
        raise PlotError(f"{e.filename}: no such file (not a sweep's folder?)") from None
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise PlotError(f"{sweep_dir}: unreadable sweep output: {e}") from None
    if not isinstance(res, dict) or res.get("format") != "swarmform-sweep":
        raise PlotError(f"{json_path}: not a swarmform sweep")
    rows = list(csv.DictReader(text.splitlines()))
    if not rows:
        raise PlotError(f"{csv_path}: no run in it (the sweep ran nothing)")
    return rows, res


def axes(rows: Sequence[dict[str, str]], res: dict[str, Any]) -> list[str]:
    """The columns that vary over the runs, in the grid's order."""
    names = AXES + sorted(k for k in rows[0] if k.startswith("param_"))
    names += [c for c in (res.get("grid") or {}).get("field_columns") or [] if c not in names]
    return [a for a in names if a in rows[0] and len({r[a] for r in rows}) > 1]


def default_metric(rows: Sequence[dict[str, str]]) -> str:
    columns = rows[0].keys()
    if "goal_tick" in columns and any(_number(r["goal_tick"]) is not None for r in rows):
        return "goal_tick"
    own = [c for c in columns if c.startswith("behaviour_metrics.")]
    return own[0] if own else "ticks"


def reason_kind(reason: str) -> str:
    head = reason.split(":", 1)[0].strip()
    return re.sub(r"\s+", " ", re.sub(r"[-+]?\d[\d.,]*", "N", head)) or "(no reason)"


def _order(values: Sequence[str]) -> list[str]:
    """Numbers in numeric order, then the rest as text."""
    uniq = sorted(set(values))
    nums = [v for v in uniq if _number(v) is not None]
    return sorted(nums, key=lambda v: float(v)) + [v for v in uniq if _number(v) is None]


def _title(res: dict[str, Any], what: str) -> str:
    g = res.get("grid") or {}
    return (f"{what}\n{len(g.get('scenarios') or [])} scenario(s), seeds {g.get('seeds')}, "
            f"{res.get('overall', {}).get('runs', '?')} runs; commit {res.get('commit') or 'unknown'}")


def _save(fig: Any, out_dir: str, name: str) -> list[str]:
    paths = []
    for ext in FORMATS:
        path = os.path.join(out_dir, f"{name}.{ext}")
        fig.savefig(path, dpi=120, bbox_inches="tight")
        paths.append(path)
    return paths


def _success(plt: Any, rows: Sequence[dict[str, str]], res: dict[str, Any], grid_axes: list[str]) -> Any:
    by = sorted(grid_axes, key=lambda a: -len({r[a] for r in rows}))[:2]
    fig, ax = plt.subplots(figsize=(7, 5))
    if len(by) == 2:
        xs, ys = _order([r[by[0]] for r in rows]), _order([r[by[1]] for r in rows])
        rate = [[math.nan] * len(xs) for _ in ys]
        for yi, y in enumerate(ys):
            for xi, x in enumerate(xs):
                cell = [r for r in rows if r[by[0]] == x and r[by[1]] == y]
                if cell:
                    rate[yi][xi] = sum(r["success"] == "1" for r in cell) / len(cell)
                    ax.text(xi, yi, f"{100 * rate[yi][xi]:.0f}%\n({len(cell)})", ha="center", va="center",
                            fontsize=8)
        im = ax.imshow(rate, vmin=0, vmax=1, cmap="RdYlGn", origin="lower", aspect="auto")
        ax.set_xticks(range(len(xs)), [os.path.basename(x) for x in xs], rotation=30, ha="right")
        ax.set_yticks(range(len(ys)), [os.path.basename(y) for y in ys])
        ax.set_xlabel(by[0])
        ax.set_ylabel(by[1])
        fig.colorbar(im, ax=ax, label="success rate")
    else:
        axis = by[0] if by else None
        values = _order([r[axis] for r in rows]) if axis else ["all runs"]
        rates = []
        for v in values:
            cell = [r for r in rows if axis is None or r[axis] == v]
            rates.append(sum(r["success"] == "1" for r in cell) / len(cell))
        ax.bar(range(len(values)), rates, color="tab:green")
        ax.set_xticks(range(len(values)), [os.path.basename(v) for v in values], rotation=30, ha="right")
        ax.set_ylim(0, 1)
        ax.set_ylabel("success rate")
        ax.set_xlabel(axis or "")
    ax.set_title(_title(res, "success rate"), fontsize=9)
    return fig


def _metric(plt: Any, rows: Sequence[dict[str, str]], res: dict[str, Any], grid_axes: list[str],
            metric: str) -> Any:
    numeric = [a for a in grid_axes if all(_number(r[a]) is not None for r in rows)]
    x_axis = numeric[0] if numeric else (grid_axes[0] if grid_axes else None)
    # A line per shape, else per scenario, else per value of the grid's next axis.
    group = next((a for a in ["shape", "scenario", *grid_axes] if a in grid_axes and a != x_axis), None)
    fig, ax = plt.subplots(figsize=(7, 5))
    groups: list[Optional[str]] = list(_order([r[group] for r in rows])) if group else [None]
    for g in groups:
        mine = [r for r in rows if group is None or r[group] == g]
        xs = _order([r[x_axis] for r in mine]) if x_axis else ["all runs"]
        pos, med, lo, hi = [], [], [], []
        for i, x in enumerate(xs):
            vals = [v for r in mine if (x_axis is None or r[x_axis] == x)
                    for v in [_number(r.get(metric, ""))] if v is not None]
            if not vals:
                continue
            m, low, high = median_interval(vals)
            pos.append(float(x) if numeric else float(i))
            med.append(m)
            lo.append(m - low)
            hi.append(high - m)
        if pos:
            ax.errorbar(pos, med, yerr=[lo, hi], marker="o", capsize=4,
                        label=os.path.basename(g) if g is not None else None)
    if not numeric and x_axis:
        labels = _order([r[x_axis] for r in rows])
        ax.set_xticks(range(len(labels)), [os.path.basename(v) for v in labels], rotation=30, ha="right")
    ax.set_xlabel(x_axis or "")
    ax.set_ylabel(f"{metric} (median, 95 % CI)")
    if group:
        ax.legend(title=group, fontsize=8)
    ax.set_title(_title(res, f"{metric} against {x_axis or 'the runs'}"), fontsize=9)
    return fig


def _failures(plt: Any, rows: Sequence[dict[str, str]], res: dict[str, Any]) -> Any:
    counts: dict[str, int] = {}
    for r in rows:
        if r["success"] != "1":
            kind = reason_kind(r.get("reason") or "")
            counts[kind] = counts.get(kind, 0) + 1
    fig, ax = plt.subplots(figsize=(7, max(2.5, 0.4 * len(counts) + 1.5)))
    kinds = sorted(counts, key=lambda k: (-counts[k], k))
    ax.barh(range(len(kinds)), [counts[k] for k in kinds], color="tab:red")
    ax.set_yticks(range(len(kinds)), kinds)
    ax.invert_yaxis()
    ax.set_xlabel("failed runs")
    if not kinds:
        ax.text(0.5, 0.5, "no failed run", ha="center", va="center", transform=ax.transAxes)
    ax.set_title(_title(res, f"failures by reason ({sum(counts.values())} of {len(rows)} runs)"), fontsize=9)
    return fig


def plot(sweep_dir: str, metric: Optional[str] = None, out_dir: Optional[str] = None) -> list[str]:
    """Draws the three figures; returns the files written. Raises PlotError."""
    rows, res = load(sweep_dir)
    metric = metric or default_metric(rows)
    if metric not in rows[0]:
        numeric = [k for k in rows[0] if any(_number(r[k]) is not None for r in rows)]
        raise PlotError(f"--metric {metric}: no such column in {sweep_dir}/sweep.csv (numeric ones: "
                        f"{', '.join(numeric[:30])}{' ...' if len(numeric) > 30 else ''})")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    out = out_dir or os.path.join(sweep_dir, "figures")
    os.makedirs(out, exist_ok=True)
    grid_axes = axes(rows, res)
    written: list[str] = []
    for name, fig in (("success", _success(plt, rows, res, grid_axes)),
                      ("metric", _metric(plt, rows, res, grid_axes, metric)),
                      ("failures", _failures(plt, rows, res))):
        written += _save(fig, out, name)
        plt.close(fig)
    return written
