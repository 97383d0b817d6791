"""The keys of a run's summary.json as judging names them: nested objects flattened with dots
(`states_at_end.settled`, `params.radius`), and which of them a behaviour declares before its run.

One reading for `swarm run --expect`, `swarm sweep --expect`, sweep.csv / sweep.json and the sweep's table, so
that a key `--expect` accepts is a column of sweep.csv with the same name.

What a run's summary will hold is known before the run from `world_server --check` (or `swarm_inprocess
--check`): its `summary_template` is summary.json as the run will write it, made by the code that writes the
run's own summary (world_server/run/recording_format.hpp summary_template), before any tick: the generic keys,
the behaviour's parameters (`params.NAME`), its states (`states_at_end.NAME`, every declared state), its
telemetry columns (`telemetry_mean_at_end.NAME`), its experiment's metrics (`behaviour_metrics.NAME`) and the
summary keys its experiment declares (`goal_tick`, ...: every one is in every summary, null when not reached).
"""

from typing import Any, Iterable, Optional

# Per-tick series: not a key to judge on, not a column.
SERIES_KEYS = {"distortion"}
# Objects of every run that say how it ran, not what the behaviour did: flattened into sweep.csv like the rest,
# but never a column of the sweep's table.
GENERIC_OBJECTS = {"provenance", "params", "input_dropped", "summary_cut"}
# Summary keys with the behaviour's own numbers (the table's columns for a behaviour that is not judged by the
# paper's formation and goal): its states and telemetry at the end, and any other object of numbers the
# summary holds (an experiment's metrics).
BEHAVIOUR_PREFIXES = ("states_at_end.", "telemetry_mean_at_end.")


def flatten(summary: dict[str, Any], prefix: str = "") -> dict[str, Any]:
    """{'a': {'b': 1}, 'c': [..]} -> {'a.b': 1, 'c': [..]}: every nested object's keys joined with dots (lists
    and scalars are values); an empty object stays as the value {}. The series (distortion) is left out."""
    out: dict[str, Any] = {}
    for k, v in summary.items():
        if not prefix and k in SERIES_KEYS:
            continue
        key = f"{prefix}{k}"
        if isinstance(v, dict) and v:
            out.update(flatten(v, key + "."))
        else:
            out[key] = v
    return out


def declared_summary(info: dict[str, Any]) -> list[dict[str, Any]]:
    """The summary keys the scenario's behaviour's experiment declares, [{key, kind, doc}] in its order, from
    `world_server --check`'s JSON (`behaviour_descriptor.experiment.summary`); [] without an experiment."""
    d = info.get("behaviour_descriptor") or {}
    e = d.get("experiment") if isinstance(d, dict) else None
    fields = e.get("summary") if isinstance(e, dict) else None
    return [f for f in fields or [] if isinstance(f, dict) and isinstance(f.get("key"), str)]


def declared_keys(template: dict[str, Any], series: Iterable[str] = ()) -> set[str]:
    """Every key `--expect` may name for a run whose summary will have the keys of `template` (`world_server
    --check`'s summary_template, or a summary of the same scenario); `series`: the keys of per-tick series, which
    are not keys to judge on (the experiment's declared series; the paper's distortion)."""
    keys = set(flatten(template)) - set(series)
    # An object's own name is a key as well (`states_at_end == ...` is refused by type, not as unknown).
    for k in list(keys):
        parts = k.split(".")
        keys.update(".".join(parts[:i]) for i in range(1, len(parts)))
    return keys


def number_keys(info: dict[str, Any]) -> list[str]:
    """The declared summary keys whose values are numbers (ticks, counts, numbers), in the declared order: the
    behaviour's own top-level columns of a sweep's table."""
    return [f["key"] for f in declared_summary(info) if f.get("kind") in ("tick", "count", "number")]


def behaviour_owned(key: str) -> bool:
    """A key the run's behaviour declares (its parameters, states and telemetry), as opposed to a generic one."""
    return key.startswith(BEHAVIOUR_PREFIXES) or key.startswith("params.")


def behaviour_columns(summaries: Iterable[Optional[dict[str, Any]]], declared: Iterable[str] = ()) -> list[str]:
    """The behaviour's own numeric keys: first `declared` (the numeric summary keys its experiment declares,
    number_keys), then across these summaries (flattened, first-seen order) its states and telemetry at the end,
    and the numbers of any other nested object but the generic ones (GENERIC_OBJECTS)."""
    cols: list[str] = list(dict.fromkeys(declared))
    for s in summaries:
        for k, v in flatten(s or {}).items():
            if "." not in k or k in cols or k.split(".", 1)[0] in GENERIC_OBJECTS:
                continue
            if isinstance(v, (int, float)) and not isinstance(v, bool) or v is None:
                cols.append(k)
    return cols


def unknown_text(key: str, known: Iterable[str], limit: int = 40) -> str:
    """'summary.json will have no key 'x' (close: a, b; its keys: ...)': for a refused key."""
    names = sorted(k for k in known if k not in ("format", "version"))
    stem = key.split(".", 1)[0]
    close = [k for k in names if k.startswith(stem + ".") or k == stem]
    shown = close if close else names
    more = f" and {len(shown) - limit} more" if len(shown) > limit else ""
    what = f"under '{stem}': " if close else "its keys: "
    return f"no key '{key}' ({what}{', '.join(shown[:limit])}{more})"
