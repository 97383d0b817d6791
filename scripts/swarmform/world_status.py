"""The world's status channel as the launcher reads it: world_server --status-fd N writes one JSON object a line
(docs/status-channel.md holds the events and their fields). `parse` turns a line into an Event or says why it is
not one; `BadLines` counts the lines that were not, and has them said once."""

import json
from dataclasses import dataclass
from typing import Any, Optional, Union

VERSION = 1

# event -> {field: the types it may have}; the fields every reader needs (more may come: they are ignored).
_INT = (int,)
_STR = (str,)
FIELDS: dict[str, dict[str, tuple[type, ...]]] = {
    "ready": {"domain": _INT, "run_nonce": _STR},
    "claimed": {"id": _INT, "pid": _INT},
    "connecting": {"claimed": _INT, "matched": _INT, "robots": _INT},
    "connected": {"agents": _INT},
    "gave_up": {"robots": _INT, "missing": (list,), "timeout_s": (int, float)},
    "progress": {"tick": _INT, "alive": _INT, "robots": _INT, "tps": (int, float, type(None))},
    "restart": {"id": _INT, "tick": _INT},
    "run_ended": {"end_reason": _STR, "tick": _INT, "what": _STR, "summary": (str, type(None)),
                  "summary_note": _STR},
    "done": {"ticks": _INT, "run_dir": _STR},
}


@dataclass
class Event:
    name: str
    fields: dict[str, Any]

    def __getitem__(self, key: str) -> Any:
        return self.fields[key]


def parse(raw: bytes) -> Union[Event, str]:
    """An Event, or the reason the line is not one (a short phrase)."""
    try:
        obj = json.loads(raw)
    except ValueError:  # JSONDecodeError and UnicodeDecodeError alike
        return "not JSON"
    if not isinstance(obj, dict):
        return "not a JSON object"
    if obj.get("v") != VERSION:
        return f"version {obj.get('v')!r}, not {VERSION}"
    name = obj.get("event")
    if not isinstance(name, str) or name not in FIELDS:
        return f"unknown event {name!r}"
    for field, types in FIELDS[name].items():
        value = obj.get(field)
        # bool is an int to Python; no field of the channel is a bool where a number is meant
        if field not in obj or isinstance(value, bool) or not isinstance(value, types):
            return f"{name}: field {field!r} missing or of the wrong type"
    return Event(name, obj)


class BadLines:
    """The status lines that were not events: counted, the first said (with why) at once, the count at the end."""

    def __init__(self) -> None:
        self.count = 0
        self.first: Optional[str] = None

    def add(self, raw: bytes, why: str) -> Optional[str]:
        """Counts the line; returns the one message to show for the first, else None."""
        self.count += 1
        if self.first is not None:
            return None
        self.first = raw[:120].decode(errors="backslashreplace")
        return (f"swarm: WARNING: a line of the world's status channel was not understood ({why}): "
                f"{self.first!r}; ignored (any more are counted)")

    def summary(self) -> Optional[str]:
        if self.count <= 1:
            return None
        return f"swarm: WARNING: {self.count} lines of the world's status channel were not understood and ignored"
