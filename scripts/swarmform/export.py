"""`swarm export RUN_DIR --mcap FILE`: the recording as an MCAP file that Foxglove opens, with the live server's
channels and schemas (viewer/README.md "Foxglove"). swarm_viewer --export-frames makes each recorded tick's
messages with the live server's own code; scripts/mcap/write.mjs writes them with @mcap/core (npm, installed in
scripts/mcap/node_modules by scripts/setup, or here on first use)."""

import os
import shutil
import subprocess
import sys

from . import exit_codes, places, report
from .launcher import LaunchError, executable

MCAP_DIR = os.path.join(places.data_root(), "scripts", "mcap")


def _say(message: str) -> None:
    print(f"swarm export: {message}", file=sys.stderr)


def mcap_library() -> str:
    """The node executable, with @mcap/core installed in scripts/mcap (npm ci from its package-lock.json if not
    yet); LaunchError saying what is missing and how to get it."""
    node = shutil.which("node")
    if node is None:
        raise LaunchError("node not found: MCAP export needs Node.js and @mcap/core "
                          "(scripts/setup installs them; or apt-get install nodejs npm)")
    if not os.path.isdir(os.path.join(MCAP_DIR, "node_modules", "@mcap", "core")):
        npm = shutil.which("npm")
        if npm is None:
            raise LaunchError(f"@mcap/core is not installed in {MCAP_DIR} and npm is missing "
                              "(apt-get install npm; then scripts/setup)")
        _say(f"installing @mcap/core in {MCAP_DIR} (npm ci, once)")
        done = subprocess.run([npm, "ci", "--no-audit", "--no-fund", "--silent"], cwd=MCAP_DIR,
                              stdin=subprocess.DEVNULL, timeout=600)
        if done.returncode != 0:
            raise LaunchError(f"npm ci in {MCAP_DIR} failed (exit {done.returncode}): @mcap/core could not be "
                              "installed (offline? run scripts/setup where the npm registry is reachable)")
    return node


def export_mcap(run_dir: str, out: str) -> int:
    if not os.path.isdir(run_dir):
        _say(f"{run_dir}: not a directory (expected a run directory with world.json, robots.csv)")
        return exit_codes.BAD_INPUT
    for name in ("world.json", "robots.csv"):
        if not os.path.isfile(os.path.join(run_dir, name)):
            _say(f"{os.path.join(run_dir, name)}: missing (is {run_dir} a run directory?)")
            return exit_codes.BAD_INPUT
    out_dir = os.path.dirname(os.path.abspath(out))
    if not os.path.isdir(out_dir):
        _say(f"{out}: its folder {out_dir} does not exist")
        return exit_codes.BAD_INPUT
    # The damage `swarm report` and `swarm view` say, in the same words; the file holds the readable ticks.
    damage = report.damage_lines(run_dir)
    for line in damage:
        _say(line)
    if damage:
        _say("the MCAP file holds the ticks that could be read (a damaged tick shows the last readable one)")
    try:
        viewer = executable("viewer")
        node = mcap_library()
    except LaunchError as e:
        _say(str(e))
        return e.code
    frames = subprocess.Popen([viewer, "--export-frames", os.path.abspath(run_dir)], stdin=subprocess.DEVNULL,
                              stdout=subprocess.PIPE)
    assert frames.stdout is not None
    writer = subprocess.Popen([node, os.path.join(MCAP_DIR, "write.mjs"), out, "--run-dir", run_dir],
                              stdin=frames.stdout, cwd=MCAP_DIR)
    frames.stdout.close()  # the writer holds the pipe: the viewer sees it close if the writer dies
    try:
        written = writer.wait()
        made = frames.wait()
    except KeyboardInterrupt:
        for p in (frames, writer):
            p.terminate()
            p.wait(timeout=10)
        return exit_codes.INTERRUPTED
    if made != 0:
        _say(f"swarm_viewer --export-frames failed (exit {made}; its message is above); nothing written")
        return exit_codes.BAD_INPUT if made == 2 else exit_codes.FAILED
    if written != 0:
        _say(f"writing {out} failed (exit {written}); nothing written")
        return exit_codes.FAILED
    return exit_codes.OK
