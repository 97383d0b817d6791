"""One in-process run (swarm_inprocess) to its summary, for the checks that compare fixed runs' trajectory hashes
(tests/golden/test_golden.py, scripts/check-motion-hashes): one runner, one way to read the summary
(sweep.parse_summary) and one deadline, so the two checks cannot drift apart."""

import os
import signal
import subprocess
from typing import Any, Optional, Sequence

from .sweep import parse_summary


def summary_of(exe: str, args: Sequence[str], cwd: str, timeout_s: float,
               prefix: Sequence[str] = ()) -> tuple[Optional[dict[str, Any]], str]:
    """Runs `prefix exe args --no-record --quiet` in `cwd` (its own process group, killed with it at the
    deadline); returns (the summary, the command line) or (None, the command line and why there is none)."""
    cmd = [*prefix, exe, *args, "--no-record", "--quiet"]
    said = " ".join(cmd)
    p = subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, stdin=subprocess.DEVNULL,
                         encoding="utf-8", errors="backslashreplace", start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout_s)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate(timeout=30)
        return None, f"{said}: over {timeout_s:g} s"
    if p.returncode != 0:
        return None, f"{said}: exit {p.returncode}\n{err.strip()}"
    summary = parse_summary(out)
    if summary is None or "trajectory_sha256" not in summary:
        return None, f"{said}: no summary with a trajectory_sha256 on stdout"
    return summary, said
