"""JSON files that other processes read while the run goes on (tests, tools, a user's `watch cat`): written to a
temporary name and renamed, so a reader sees the whole old file or the whole new one, never a torn one."""

import json
import os
from typing import Any


def write_atomically(path: str, data: Any) -> None:
    """A failure is an OSError that names the file: a full disk is seen only when the buffer is written, where
    Python's error names none."""
    tmp = f"{path}.tmp-{os.getpid()}"
    text = json.dumps(data, indent=1)
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    except OSError as e:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise OSError(e.errno, e.strerror, e.filename or path) from None
