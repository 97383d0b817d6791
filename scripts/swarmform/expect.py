"""`swarm run --expect 'KEY OP VALUE'`: assertions on the run's summary.json, so that any CI can gate on a swarm
run (testing-your-swarm.md). KEY is a key of summary.json (docs/recording-format.md; `swarm report RUN_DIR --json`
lists them), a nested one named with dots (`states_at_end.settled`, `params.radius`: summary_keys.py), OP one of
== != <= >= < >, VALUE a number, true/false, null, or a word (compared as text).

Comparing: a number with a number numerically; a list (deaths, rejoins, stuck_robots) by its length, so
`deaths <= 2` means at most two deaths; true/false and null only with == and !=; a word only with == and !=
(`outcome == arrived`). A key whose value is null fails every ordering (`goal_tick <= 3000` fails when the goal
was never reached). Every KEY is checked before the run starts against the keys the run's summary will have
(`check_declared`: its behaviour's parameters, states and telemetry, and the generic keys); an unknown one is
refused then, exit 2. After the run the launcher prints every expectation met or failed and exits 4 when one
failed (the run itself succeeded) (common/exit_codes.json).
"""

import json
import math
import os
import re
from typing import Any, Callable, Sequence

from . import exit_codes, summary_keys

EXIT_EXPECTATION_FAILED = exit_codes.EXPECTATION_FAILED
_SYNTAX = re.compile(r"^\s*([A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z0-9_]+)*)\s*(==|!=|<=|>=|<|>)\s*(\S(?:.*\S)?)\s*$")
OPS = ("==", "!=", "<=", ">=", "<", ">")


class ExpectationError(Exception):
    """A bad expectation (syntax, an unknown key, an ordering of text): the user's input, exit 2."""


class Expectation:
    def __init__(self, text: str, key: str, op: str, value: Any) -> None:
        self.text, self.key, self.op, self.value = text, key, op, value

    def __repr__(self) -> str:
        return f"Expectation({self.text!r})"


def _value(text: str) -> Any:
    t = text.strip()
    if len(t) >= 2 and t[0] == t[-1] and t[0] in "'\"":
        return t[1:-1]
    low = t.lower()
    if low in ("true", "false"):
        return low == "true"
    if low in ("null", "none"):
        return None
    try:
        v = float(t)
    except ValueError:
        return t
    if not math.isfinite(v):
        raise ExpectationError(f"'{text}': the value must be a finite number")
    return int(v) if v.is_integer() and re.fullmatch(r"[+-]?\d+", t) else v


def parse(text: str) -> Expectation:
    """'KEY OP VALUE' -> Expectation; ExpectationError naming the text and what is wrong."""
    m = _SYNTAX.match(text)
    if not m:
        raise ExpectationError(f"'{text}': expected 'KEY OP VALUE' with OP one of {' '.join(OPS)} and KEY a "
                               f"summary key, dotted for a nested one (e.g. 'outcome == arrived', "
                               f"'collisions_robot_robot == 0', 'states_at_end.settled >= 10')")
    key, op, raw = m[1], m[2], m[3]
    value = _value(raw)
    if op not in ("==", "!=") and not _is_number(value):
        raise ExpectationError(f"'{text}': {op} needs a number on the right, got '{raw}' (only == and != compare "
                               "text, true/false or null)")
    return Expectation(text.strip(), key, op, value)


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _shown(v: Any) -> str:
    return json.dumps(v) if not isinstance(v, str) else v


def check_declared(expectations: Sequence[Expectation], declared: set[str],
                   skip: Callable[[str], bool] = lambda key: False) -> list[str]:
    """Before a run: a message for each expectation whose key the run's summary will not have (`declared`:
    summary_keys.declared_keys of `world_server --check`'s summary_template); keys for which `skip(key)` is true
    are left to after the run."""
    return [f"'{e.text}': summary.json will have {summary_keys.unknown_text(e.key, declared)}"
            for e in expectations if e.key not in declared and not skip(e.key)]


def check(exp: Expectation, summary: dict[str, Any]) -> tuple[bool, str]:
    """(met, the actual value as the message shows it). ExpectationError for a key summary.json lacks."""
    flat = summary_keys.flatten(summary)
    if exp.key in summary:
        actual = summary[exp.key]
    elif exp.key in flat:
        actual = flat[exp.key]
    else:
        raise ExpectationError(f"'{exp.text}': summary.json has {summary_keys.unknown_text(exp.key, flat)}")
    raw = actual
    shown = _shown(actual)
    if isinstance(actual, list) and _is_number(exp.value):
        actual, shown = len(actual), f"{len(actual)} ({_shown(raw)})"
    if exp.op in ("==", "!="):
        if _is_number(actual) and _is_number(exp.value):
            equal = float(actual) == float(exp.value)
        elif isinstance(exp.value, str) and not isinstance(actual, str) and actual is not None:
            equal = _shown(actual) == exp.value  # e.g. `seed == 7` parsed as a number; a text key vs a word
        else:
            equal = actual == exp.value
        return (equal if exp.op == "==" else not equal), shown
    if not _is_number(actual):
        return False, shown
    a, b = float(actual), float(exp.value)
    met = {"<=": a <= b, ">=": a >= b, "<": a < b, ">": a > b}[exp.op]
    return met, shown


def evaluate(expectations: Sequence[Expectation], run_dir: str, say: Callable[[str], None]) -> int:
    """Checks every expectation against RUN_DIR/summary.json, saying each; returns the exit code: exit_codes.OK all met,
    EXIT_EXPECTATION_FAILED when one failed, exit_codes.BAD_INPUT for an unknown key."""
    path = os.path.join(run_dir, "summary.json")
    try:
        with open(path, encoding="utf-8", errors="backslashreplace") as f:
            summary = json.load(f)
    except (OSError, ValueError) as e:
        say(f"swarm: --expect: cannot read {path} ({e}); no expectation can be checked")
        return EXIT_EXPECTATION_FAILED
    if not isinstance(summary, dict):
        say(f"swarm: --expect: {path} is not a JSON object")
        return EXIT_EXPECTATION_FAILED
    failed, bad = 0, 0
    for exp in expectations:
        try:
            met, actual = check(exp, summary)
        except ExpectationError as e:
            say(f"swarm: --expect {e}")
            bad += 1
            continue
        if met:
            say(f"swarm: expectation met: {exp.text} ({exp.key} is {actual})")
        else:
            failed += 1
            say(f"swarm: EXPECTATION FAILED: {exp.text} ({exp.key} is {actual})")
    if bad:
        return exit_codes.BAD_INPUT
    if failed:
        say(f"swarm: {failed} of {len(expectations)} expectation(s) failed")
        return EXIT_EXPECTATION_FAILED
    return exit_codes.OK
