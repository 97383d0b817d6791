"""The exit codes of every swarmform program, read from common/exit_codes.json (the one table; the C++ side gets
the same one as a header CMake generates). A name here that the table lacks fails at import, not at exit."""

import json
import os
from typing import Any, Dict, List

from . import places

TABLE_PATH = os.path.join(places.data_root(), "common", "exit_codes.json")


def _load() -> Dict[str, Any]:
    try:
        with open(TABLE_PATH, encoding="utf-8") as f:
            table: Dict[str, Any] = json.load(f)
    except (OSError, ValueError) as e:
        raise RuntimeError(f"{TABLE_PATH}: the exit-code table cannot be read: {e}") from None
    return table


TABLE = _load()
CODES: Dict[str, int] = {row["name"]: int(row["code"]) for row in TABLE["codes"]}


def _code(name: str) -> int:
    if name not in CODES:
        raise RuntimeError(f"{TABLE_PATH}: no exit code named '{name}'")
    return CODES[name]


OK = _code("ok")
FAILED = _code("failed")
BAD_INPUT = _code("bad_input")
AGENTS_MISSING = _code("agents_missing")
AGENTS_STALLED = _code("agents_stalled")
EXPECTATION_FAILED = _code("expectation_failed")
RECORDING_FAILED = _code("recording_failed")
INTERRUPTED = _code("interrupted")


def help_text(program: str) -> str:
    """`program`'s --help epilogue: the codes it uses, in the table's order (as the C++ kExitHelp_<program>)."""
    if program not in TABLE["programs"]:
        raise RuntimeError(f"{TABLE_PATH}: no program named '{program}'")
    parts: List[str] = []
    for row in TABLE["codes"]:
        if program in row["programs"]:
            shown = f"{row['code']}+N" if row.get("plus_signal") else str(row["code"])
            parts.append(f"{shown} {row['meaning']}")
    return "Exit codes: " + "; ".join(parts) + "."
