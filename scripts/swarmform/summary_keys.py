"""The keys of a run's summary.json as judging names them: nested objects flattened with dots
(`states_at_end.settled`, `params.radius`), and which of them a behaviour declares before its run.

One reading for `swarm run --expect`, `swarm sweep --expect`, sweep.csv / sweep.json and the sweep's table, so
that a key `--expect` accepts is a column of sweep.csv with the same name.

What a run's summary will hold is learnt before the run from the summary of a one-tick probe of the same
scenario (`swarm_inprocess --max-ticks 1 --no-record --quiet`): the generic keys, the behaviour's parameters
(`params.NAME`), its states (`states_at_end.NAME`, every declared state listed, 0 included) and its telemetry
columns (`telemetry_mean_at_end.NAME`), all written by the same code that writes the run's own summary.
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


def experiment_keys(probe: dict[str, Any]) -> set[str]:
    """The keys a behaviour's experiment declares that its one-tick probe may not show yet (metrics it computes
    only at the end). The one place where declared experiment metrics join the keys checked before a run: today
    a probe's summary already lists every key its behaviour declares, so there are none more."""
    del probe
    return set()


def declared_keys(probe: dict[str, Any]) -> set[str]:
    """Every key `--expect` may name for a run of the scenario that gave this one-tick probe summary."""
    keys = set(flatten(probe))
    # An object's own name is a key as well (`states_at_end == ...` is refused by type, not as unknown).
    for k in list(keys):
        parts = k.split(".")
        keys.update(".".join(parts[:i]) for i in range(1, len(parts)))
    return keys | experiment_keys(probe)


def behaviour_owned(key: str) -> bool:
    """A key the run's behaviour declares (its parameters, states and telemetry), as opposed to a generic one."""
    return key.startswith(BEHAVIOUR_PREFIXES) or key.startswith("params.")


def behaviour_columns(summaries: Iterable[Optional[dict[str, Any]]]) -> list[str]:
    """The behaviour's own numeric keys across these summaries (flattened, first-seen order): its states and
    telemetry at the end, and the numbers of any other nested object but the generic ones (GENERIC_OBJECTS)."""
    cols: list[str] = []
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
