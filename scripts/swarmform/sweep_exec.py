"""`swarm sweep --exec CMD`: each run of the grid as `swarm run --exec CMD`, real processes (the world and one agent
per robot, each running CMD behind the line protocol: docs/agent-protocol.md), for a behaviour no in-process run
can drive: a program described by a descriptor file, in any language.

A run's command is written as the user would type it (`scripts/swarm run ... --exec CMD --no-pictures`, `swarm
run` from an installed prefix): that is sweep.csv's `command` and what `--resume` compares. What runs is the same
on Debian's python3 and the swarmform package (as the launcher script runs it), with `--out` a folder of the
sweep's own, read back for summary.json and removed. Each run takes a free DDS domain of its own (domains.py),
so `--jobs` runs go side by side.
"""

import json
import os
import shutil
import subprocess
import sys
import tempfile
from typing import Any, Optional, Sequence

from . import places

# What `swarm sweep` takes from the scenario-field axes and the cluster, which `swarm run` has no flag for.
REFUSED = ("--loss", "--burst", "--noise", "--set", "--cluster")


def launcher_word() -> str:
    return "swarm" if places.installed() else "scripts/swarm"


def as_run(cmd: Sequence[str], program: str, exec_timeout: Optional[float]) -> list[str]:
    """The in-process command `cmd` (sweep.base_command's: the harness, then its flags) as `swarm run --exec`: the
    same flags, which `swarm run` takes alike, after the launcher's words."""
    out = [launcher_word(), "run", *cmd[1:], "--exec", program]
    if exec_timeout is not None:
        out += ["--exec-timeout", f"{exec_timeout:g}"]
    return out + ["--no-pictures"]


def argv(cmd: Sequence[str], out_dir: str) -> list[str]:
    """What runs for `cmd` (as_run's, with the run's flags): the launcher's package, writing into out_dir."""
    return [sys.executable, "-m", "swarmform", *cmd[1:], "--out", out_dir]


def read_summary(out_dir: str) -> Optional[dict[str, Any]]:
    """The run directory's summary.json; None when there is none or it is not a JSON object."""
    try:
        with open(os.path.join(out_dir, "summary.json"), encoding="utf-8") as f:
            value = json.load(f)
    except (OSError, ValueError):
        return None
    return value if isinstance(value, dict) else None


def take_summary(out_dir: str) -> Optional[dict[str, Any]]:
    """read_summary, then the run directory is removed (a sweep keeps the summaries, not the recordings)."""
    summary = read_summary(out_dir)
    shutil.rmtree(out_dir, ignore_errors=True)
    return summary


def probe(cmd: Sequence[str], timeout: float) -> tuple[Optional[dict[str, Any]], str]:
    """One tick of `cmd` (an as_run command with --max-ticks 1) as real processes: (its summary, or None, and the
    last line it wrote on stderr). The scenario, the shape, the parameters and the descriptor file are checked as
    in any run; a program that does not start or answer fails it."""
    tmp = tempfile.mkdtemp(prefix="swarm-sweep-probe-")
    try:
        p = subprocess.run(argv(cmd, os.path.join(tmp, "run")), stdin=subprocess.DEVNULL, capture_output=True,
                           timeout=timeout, encoding="utf-8", errors="backslashreplace")
        last = next((ln for ln in reversed(p.stderr.strip().splitlines()) if ln.strip()), f"exit {p.returncode}")
        return (read_summary(os.path.join(tmp, "run")) if p.returncode == 0 else None), last
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
