"""`swarm sweep`'s scenario-field axes: the radio (--loss, --burst), the noise (--noise) and any scenario field
(--set KEY=V1,V2,...). Each becomes one axis of the grid; a run gets its values as `swarm_inprocess --set KEY=VALUE`
flags, which the scenario loader checks like the file's own fields (docs/scenario-format.md).

  --loss 0,0.1,0.2     packet_loss rates, each in [0, 1)
  --burst 1,5          mean burst lengths in ticks (Gilbert-Elliott, per directed link); 1 is independent loss (the
                       plain `packet_loss: RATE`), any other value B gives `packet_loss: {rate: RATE, mean_burst: B}`
                       and must be at least 1 / (1 - RATE) for every --loss RATE (the loader's bound). Needs --loss.
  --noise off,on       off: no noise; on: NOISE_ON (range 5 cm, bearing 0.05 rad, ultrasonic 2 cm, Gaussian sds)
  --set KEY=V1,V2      any scenario field (dotted for a nested one: noise.range, arena.width), VALUE as YAML; a
                       value holding commas is written in brackets or braces ({rate: 0.2, mean_burst: 5}).
"""

import itertools
import math
import re
from typing import Any, Optional, Sequence

# `--noise on`: the noise of a cheap real robot's range-and-bearing board and sonar (Gaussian sds).
NOISE_ON = {"range": 0.05, "bearing": 0.05, "ultrasonic": 0.02}
NOISE_LEVELS = ("off", "on")

Values = list[tuple[str, float]]  # (as written, as a number)

_KEY = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z_][A-Za-z0-9_]*)*$")


class FieldAxis:
    """One axis: its column in sweep.csv, the scenario key it sets (for conflicts) and its values' labels."""

    def __init__(self, column: str, key: str, labels: Sequence[str]) -> None:
        self.column, self.key, self.labels = column, key, list(labels)


def number_list(values: str, quoted: str, usage: str,
                bounds: Optional[tuple[float, float, bool, str]] = None) -> Values:
    """`V1,V2,...` -> [(as written, as a number)]; ValueError quoting `quoted` (the flag's text) for a part that is
    no number, is not finite or outside `bounds` (lo, hi, hi open, what the number is), or is given twice. One
    parser for every comma-separated list of numbers a sweep takes (--param's values too)."""
    out: Values = []
    for part in values.split(","):
        part = part.strip()
        try:
            v = float(part)
        except ValueError:
            raise ValueError(f"'{quoted}': '{part}' is not a number; {usage}") from None
        if bounds is None:
            if not math.isfinite(v):
                raise ValueError(f"'{quoted}': '{part}' is not a finite number")
        else:
            lo, hi, hi_open, what = bounds
            if not math.isfinite(v) or v < lo or (v >= hi if hi_open else v > hi):
                bound = f"[{lo:g}, {hi:g})" if hi_open else f"[{lo:g}, {hi:g}]"
                raise ValueError(f"'{quoted}': {what} {part} is outside {bound}")
        if v in (x for _, x in out):
            raise ValueError(f"'{quoted}': the value {part} is given twice")
        out.append((part, v))
    return out


def _numbers(text: str, what: str, lo: float, hi: float, hi_open: bool, example: str) -> Values:
    usage = f"expected a comma-separated list of numbers (e.g. {example})"
    return number_list(text, text, usage, (lo, hi, hi_open, what))


def parse_loss(text: str) -> Values:
    """`0,0.1,0.2` -> packet_loss rates, each in [0, 1); ValueError naming the text."""
    return _numbers(text, "the loss rate", 0.0, 1.0, True, "0,0.1,0.2,0.3")


def parse_burst(text: str) -> Values:
    """`1,5` -> mean burst lengths in ticks, each in [1, 1e6] (1: independent loss); ValueError naming the text."""
    return _numbers(text, "the mean burst", 1.0, 1e6, False, "1,5")


def parse_noise(text: str) -> list[str]:
    """`off,on` -> the noise levels; ValueError naming the text."""
    out: list[str] = []
    for part in text.split(","):
        part = part.strip()
        if part not in NOISE_LEVELS:
            raise ValueError(f"'{text}': '{part}' is not a noise level (expected off or on, e.g. off,on)")
        if part in out:
            raise ValueError(f"'{text}': {part} is given twice")
        out.append(part)
    return out


def split_values(text: str) -> list[str]:
    """`0.1,{rate: 0.2, mean_burst: 5},[1, 2]` -> its top-level comma-separated parts (commas inside brackets,
    braces or quotes stay in their value); ValueError on unbalanced brackets."""
    parts: list[str] = []
    depth, quote, start = 0, "", 0
    for i, c in enumerate(text):
        if quote:
            if c == quote:
                quote = ""
        elif c in "'\"":
            quote = c
        elif c in "[{":
            depth += 1
        elif c in "]}":
            depth -= 1
            if depth < 0:
                raise ValueError(f"'{text}': '{c}' closes nothing")
        elif c == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    if depth or quote:
        raise ValueError(f"'{text}': an unclosed {'quote' if quote else 'bracket or brace'}")
    parts.append(text[start:].strip())
    return parts


def parse_set(text: str) -> tuple[str, list[str]]:
    """`KEY=V1,V2,...` -> (KEY, [V1, V2, ...]); ValueError naming the text. Whether KEY is a field and each value
    fits it is the scenario loader's to say (the probe)."""
    key, sep, values = text.partition("=")
    key = key.strip()
    usage = ("expected KEY=V1,V2,... with KEY a scenario field, dotted for a nested one (e.g. comm_range=2,3 or "
             "noise.range=0,0.05)")
    if not sep or not _KEY.match(key):
        raise ValueError(f"'{text}': {usage}")
    out: list[str] = []
    for v in split_values(values):
        if not v:
            raise ValueError(f"'{text}': an empty value; {usage}")
        if v in out:
            raise ValueError(f"'{text}': the value {v} is given twice")
        out.append(v)
    return key, out


def once(given: Optional[list[Any]], flag: str) -> Any:
    """A flag's one value list (argparse appends each use), None when absent; ValueError when given twice."""
    if not given:
        return None
    if len(given) > 1:
        raise ValueError(f"{flag} is given {len(given)} times (give its values once, comma-separated)")
    return given[0]


def _noise_value(level: str) -> str:
    n = NOISE_ON if level == "on" else {k: 0 for k in NOISE_ON}
    return "{" + ", ".join(f"{k}: {v:g}" for k, v in n.items()) + "}"


def _overlap(a: str, b: str) -> bool:
    return a == b or a.startswith(b + ".") or b.startswith(a + ".")


class FieldGrid:
    """The field axes of one sweep and their combinations: each a {column: label} and its --set flags."""

    def __init__(self, loss: Optional[Values], burst: Optional[Values], noise: Optional[list[str]],
                 sets: Sequence[tuple[str, list[str]]]) -> None:
        self.loss, self.burst, self.noise, self.sets = loss, burst, noise, list(sets)
        self.axes: list[FieldAxis] = []
        if loss is not None:
            self.axes.append(FieldAxis("loss", "packet_loss", [t for t, _ in loss]))
        if burst is not None:
            self.axes.append(FieldAxis("burst", "packet_loss", [t for t, _ in burst]))
        if noise is not None:
            self.axes.append(FieldAxis("noise", "noise", noise))
        for key, values in self.sets:
            self.axes.append(FieldAxis(f"set_{key}", key, values))

    def check(self) -> None:
        """ValueError for axes that cannot make a grid: --burst without --loss, a burst below a rate's bound, two
        axes setting the same field."""
        if self.burst is not None and self.loss is None:
            raise ValueError("--burst needs --loss (the loss rates the mean bursts go with), e.g. --loss 0.2 "
                             "--burst 1,5")
        for (lt, lv), (bt, bv) in itertools.product(self.loss or [], self.burst or []):
            if bv != 1.0 and bv < 1.0 / (1.0 - lv):
                raise ValueError(f"--burst {bt} with --loss {lt}: a mean burst must be at least 1 / (1 - rate) = "
                                 f"{1.0 / (1.0 - lv):g} ticks, the mean burst of independent loss at that rate "
                                 f"(--burst 1 is independent loss)")
        seen: list[tuple[str, str]] = []  # (flag, key)
        for flag, key in ([("--loss", "packet_loss")] if self.loss is not None else []) + \
                ([("--noise", "noise")] if self.noise is not None else []) + \
                [(f"--set {k}", k) for k, _ in self.sets]:
            for other_flag, other_key in seen:
                if _overlap(key, other_key):
                    what = "is given twice" if flag == other_flag else f"and {other_flag} both set {other_key}"
                    raise ValueError(f"{flag} {what} (one axis per field)")
            seen.append((flag, key))

    def combinations(self) -> list[tuple[dict[str, str], list[str]]]:
        """Every combination, in the axes' order: ({column: label}, [--set flags])."""
        # An absent axis: one value, None, that sets nothing.
        loss: list[Optional[tuple[str, float]]] = [None] if self.loss is None else [v for v in self.loss]
        burst: list[Optional[tuple[str, float]]] = [None] if self.burst is None else [v for v in self.burst]
        noise: list[Optional[str]] = [None] if self.noise is None else [v for v in self.noise]
        set_values = [[(key, v) for v in values] for key, values in self.sets]
        out: list[tuple[dict[str, str], list[str]]] = []
        for lo, bu, no, *sets in itertools.product(loss, burst, noise, *set_values):
            labels: dict[str, str] = {}
            flags: list[str] = []
            if lo is not None:
                labels["loss"] = lo[0]
                if bu is not None:
                    labels["burst"] = bu[0]
                if bu is None or bu[1] == 1.0:
                    flags += ["--set", f"packet_loss={lo[0]}"]
                else:
                    flags += ["--set", f"packet_loss={{rate: {lo[0]}, mean_burst: {bu[0]}}}"]
            if no is not None:
                labels["noise"] = no
                flags += ["--set", f"noise={_noise_value(no)}"]
            for key, v in sets:
                labels[f"set_{key}"] = v
                flags += ["--set", f"{key}={v}"]
            out.append((labels, flags))
        return out

    def columns(self) -> list[str]:
        return [a.column for a in self.axes]

    def grid(self) -> dict[str, list[str]]:
        """sweep.json's grid entry: each axis's values as written."""
        return {a.column: a.labels for a in self.axes}


def label(fields: dict[str, str]) -> str:
    """'loss=0.2 burst=5 noise=on' (the key of sweep.json's by_fields), or 'scenario' (the files' own)."""
    return " ".join(f"{k}={v}" for k, v in fields.items()) or "scenario"


HELP = """\
Scenario fields (each flag one axis of the grid; a run gets `swarm_inprocess --set KEY=VALUE` over its scenario):
  --loss 0,0.1,0.2,0.3   packet_loss rates, [0, 1)
  --burst 1,5            mean loss bursts in ticks (needs --loss): 1 is independent loss (packet_loss: RATE), B > 1
                         bursty loss (packet_loss: {rate: RATE, mean_burst: B}, a Gilbert-Elliott chain per
                         directed link; B >= 1 / (1 - RATE), docs/scenario-format.md "Bursty loss")
  --noise off,on         off: noise {range: 0, bearing: 0, ultrasonic: 0}; on: noise {range: 0.05 m, bearing: 0.05
                         rad, ultrasonic: 0.02 m} (Gaussian sds)
  --set KEY=V1,V2,...    any scenario field, dotted for a nested one (comm_range=2,3; noise.range=0,0.05;
                         occlusion=false,true); VALUE is YAML, a value with commas in brackets or braces; repeatable
                         (one flag per KEY). Two axes may not set the same field (--loss and --set packet_loss).
  Every value is checked by the scenario loader before any run (a bad one: its message, exit 2). sweep.csv gets a
  column per axis (loss, burst, noise, set_KEY), sweep.json the grid's values and by_fields rates.
"""
