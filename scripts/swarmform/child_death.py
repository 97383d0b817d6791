"""Children that die with the process that started them: `preexec_fn=die_with_parent` (Linux PR_SET_PDEATHSIG).

The signal is armed in the child after the fork, so a parent that dies between the two (SIGKILLed while it starts
an agent) would never send it and the child would live on. The forking pid is recorded just before each fork
(`os.register_at_fork`, which also runs for a `preexec_fn` fork) and the child compares it with its parent once the
signal is armed: another parent means the one that started it is gone, and the child exits at once."""

import ctypes
import os
import signal
from typing import Optional

EXIT_ORPHANED = 125  # the child's code when its starter died before the death signal was armed (never exec'd)

_libc: Optional[ctypes.CDLL] = None
_spawner = 0


def _note_spawner() -> None:
    global _spawner
    _spawner = os.getpid()


os.register_at_fork(before=_note_spawner)


def die_with_parent() -> None:
    """In the child before exec: be SIGKILLed if the starter dies; exit now if it already has."""
    global _libc
    try:
        _libc = _libc or ctypes.CDLL(None, use_errno=True)
        _libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG
    except OSError:
        return
    if _spawner and os.getppid() != _spawner:
        os._exit(EXIT_ORPHANED)
