"""Where the product's files are: the source tree (scripts/swarm, the programs under BUILD_DIR), or an
installed prefix (bin/swarm from `cmake --install`, which sets SWARM_BIN_DIR and SWARM_DATA_DIR; the programs
in that bin/, the data under share/swarmform/). Nothing else in the package names a path of the product."""

import os
import subprocess
from typing import Optional

# The source tree: scripts/swarmform/ is two folders below it. Meaningless when installed.
SOURCE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Where each program is under a build folder; an installed prefix has them all in bin/.
_BUILD_PATHS = {"world_server": "world_server/world_server", "robot_agent": "robot_agent/robot_agent",
                "swarm_inprocess": "harness/swarm_inprocess", "swarm_viewer": "viewer/swarm_viewer"}


def installed() -> bool:
    return bool(os.environ.get("SWARM_DATA_DIR"))


def data_root() -> str:
    """The folder holding scenarios/, shapes/ and common/exit_codes.json."""
    return os.environ.get("SWARM_DATA_DIR") or SOURCE_ROOT


def build_dir() -> str:
    return os.environ.get("BUILD_DIR") or os.path.join(SOURCE_ROOT, "build")


def program(name: str) -> str:
    """The path of one of _BUILD_PATHS's programs (whether it exists is the caller's check)."""
    bin_dir = os.environ.get("SWARM_BIN_DIR")
    if bin_dir:
        return os.path.join(bin_dir, name)
    return os.path.join(build_dir(), _BUILD_PATHS[name])


def missing_program_hint() -> str:
    if os.environ.get("SWARM_BIN_DIR"):
        return "the installed prefix is incomplete: install it again (cmake --install)"
    return "build it first (scripts/build), or set BUILD_DIR"


def runs_root() -> str:
    """SWARM_RUNS_DIR, else runs/ in the source tree, else (installed) runs/ in the current folder."""
    return os.environ.get("SWARM_RUNS_DIR") or os.path.join(os.getcwd() if installed() else SOURCE_ROOT, "runs")


def commit() -> Optional[str]:
    """The product's commit: the one an installed prefix was built from, else the source tree's (with -dirty)."""
    if installed():
        return os.environ.get("SWARM_INSTALLED_COMMIT") or None
    try:
        head = subprocess.run(["git", "-C", SOURCE_ROOT, "rev-parse", "--short=12", "HEAD"], capture_output=True,
                              text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", SOURCE_ROOT, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=10).stdout.strip()
        return (head + ("-dirty" if dirty else "")) or None
    except (OSError, subprocess.SubprocessError):
        return None


def default_scenario() -> str:
    """scenarios/paper.yaml: as written when the current folder has it (the source tree's root), else the
    product's own (the source tree's, or the installed one)."""
    rel = os.path.join("scenarios", "paper.yaml")
    return rel if os.path.isfile(rel) else os.path.join(data_root(), rel)
