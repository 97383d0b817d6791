"""A sweep's folder read back: the command line it was started with (sweep_args.json) and the runs it finished
(runs.jsonl, a line each as each run ends), so that `swarm sweep --resume DIR` runs only what is missing and
`swarm sweep --merge DIR...` joins the slices of `--shard K/N` into the one sweep they were cut from.

sweep_args.json: {"format": "swarmform-sweep-args", "version": 1, "argv": [...], "shard": [K, N] or null,
"commit": ..., "planned_runs": the whole grid's runs}. runs.jsonl: sweep.json's run records (`index` the run's
place in the whole grid, `command` its swarm_inprocess command), each with `severity` and `full_summary` (the
harness's summary as printed) besides, enough to judge and count it again without running it."""

import json
import os
from typing import Any, Optional

ARGS_FILE = "sweep_args.json"
JOURNAL_FILE = "runs.jsonl"
# Options of the command line that say how or where a sweep runs, not which runs it holds.
NOT_GRID = {"--out": 1, "--jobs": 1, "-j": 1, "--quiet": 0, "--shard": 1, "--resume": 1, "--cluster": 1,
            "--plot": 0, "--plot-metric": 1}


class JournalError(Exception):
    pass


def parse_shard(text: str) -> tuple[int, int]:
    """'K/N', 1 <= K <= N: the K-th of N slices of the grid."""
    k_text, sep, n_text = text.partition("/")
    if not sep or not k_text.isdigit() or not n_text.isdigit() or not 1 <= int(k_text) <= int(n_text):
        raise ValueError(f"--shard '{text}': want K/N with 1 <= K <= N, e.g. 2/8")
    return int(k_text), int(n_text)


def in_shard(index: int, shard: Optional[tuple[int, int]]) -> bool:
    """Run `index` of the grid belongs to slice K of N when index % N == K - 1: every slice gets every N-th run,
    so slices of a grid ordered by scenario and seed take about the same time."""
    return shard is None or index % shard[1] == shard[0] - 1


def grid_argv(argv: list[str]) -> list[str]:
    """argv without the options that do not change the grid (NOT_GRID), as `--opt value` or `--opt=value`."""
    out: list[str] = []
    skip = 0
    for a in argv:
        if skip:
            skip -= 1
            continue
        name = a.split("=", 1)[0]
        if name in NOT_GRID:
            skip = 0 if "=" in a else NOT_GRID[name]
            continue
        out.append(a)
    return out


def save_args(out_dir: str, argv: list[str], shard: Optional[tuple[int, int]], commit: Optional[str],
              planned: int) -> None:
    doc = {"format": "swarmform-sweep-args", "version": 1, "argv": grid_argv(argv),
           "shard": list(shard) if shard else None, "commit": commit, "planned_runs": planned}
    tmp = os.path.join(out_dir, ARGS_FILE + ".tmp")
    with open(tmp, "w", encoding="utf-8") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    os.replace(tmp, os.path.join(out_dir, ARGS_FILE))


def load_args(sweep_dir: str) -> dict[str, Any]:
    path = os.path.join(sweep_dir, ARGS_FILE)
    try:
        with open(path, "rb") as f:
            doc = json.loads(f.read().decode("utf-8"))
    except FileNotFoundError:
        raise JournalError(f"{path}: no such file (not a sweep's folder, or one written before --resume "
                           "existed)") from None
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise JournalError(f"{path}: unreadable: {e}") from None
    if not isinstance(doc, dict) or doc.get("format") != "swarmform-sweep-args" or doc.get("version") != 1 \
            or not isinstance(doc.get("argv"), list) or not all(isinstance(a, str) for a in doc["argv"]):
        raise JournalError(f"{path}: not a swarmform-sweep-args file of version 1")
    shard = doc.get("shard")
    if shard is not None and not (isinstance(shard, list) and len(shard) == 2
                                  and all(isinstance(v, int) for v in shard) and 1 <= shard[0] <= shard[1]):
        raise JournalError(f"{path}: 'shard' is not [K, N] with 1 <= K <= N")
    return doc


def finished_runs(sweep_dir: str) -> dict[int, dict[str, Any]]:
    """The runs.jsonl records of runs that ended (not those cut by an interruption), the last one of an index
    winning. A line cut short by a crash or a lost machine (the last, unterminated) is left out; any other bad
    line is an error naming its line."""
    path = os.path.join(sweep_dir, JOURNAL_FILE)
    records: dict[int, dict[str, Any]] = {}
    try:
        with open(path, "rb") as f:
            data = f.read()
    except FileNotFoundError:
        return records
    except OSError as e:
        raise JournalError(f"{path}: unreadable: {e}") from None
    lines = data.split(b"\n")
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        last = number == len(lines)  # no newline after it: written when the sweep stopped
        try:
            rec = json.loads(line.decode("utf-8"))
        except (UnicodeDecodeError, ValueError) as e:
            if last:
                continue
            raise JournalError(f"{path}:{number}: not a JSON record: {e}") from None
        if not isinstance(rec, dict) or not isinstance(rec.get("index"), int) or "full_summary" not in rec \
                or not isinstance(rec.get("command"), str):
            raise JournalError(f"{path}:{number}: not a run record of this version (no index, command or "
                               "full_summary)")
        if str(rec.get("reason", "")).startswith("interrupted"):
            continue  # cut by Ctrl-C or a lost machine: to run again
        records[rec["index"]] = rec
    return records
