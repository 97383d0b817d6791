"""JSON files that other processes read while the run goes on (tests, tools, a user's `watch cat`): written to a
temporary name and renamed, so a reader sees the whole old file or the whole new one, never a torn one."""

import json
import os
from typing import Any


def write_atomically(path: str, data: Any) -> None:
    tmp = f"{path}.tmp-{os.getpid()}"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1)
    os.replace(tmp, path)
