"""Shared bits of the viewer's tests: a free TCP port, a `scripts/swarm` run in the background killed by pid and
group at the end, waiting for the viewer's page, robots.csv rows of one tick, colours."""

import csv
import os
import signal
import subprocess
import sys
import time
import urllib.request

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SWARM = os.path.join(ROOT, "scripts", "swarm")
BUILD_DIR = os.environ.get("BUILD_DIR") or os.path.join(ROOT, "build")
sys.path.insert(0, os.path.join(ROOT, "tests", "scripts"))
import helpers  # noqa: E402  (test_domain, pid_alive, free_port)


def built(*names):
    paths = {"world": "world_server/world_server", "agent": "robot_agent/robot_agent",
             "viewer": "viewer/swarm_viewer"}
    return all(os.access(os.path.join(BUILD_DIR, paths[n]), os.X_OK) for n in names)


free_port = helpers.free_port

class SwarmRun:
    """`scripts/swarm run ARGS` in the background (its own process group); stop() ends whatever is left."""

    def __init__(self, *args):
        env = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=BUILD_DIR, PYTHONDONTWRITEBYTECODE="1")
        self.proc = subprocess.Popen([SWARM, "run"] + list(args), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True, env=env, start_new_session=True)

    def wait(self, timeout):
        try:
            out, _ = self.proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.stop()
            raise AssertionError(f"scripts/swarm run did not end within {timeout} s") from None
        return self.proc.returncode, out

    def stop(self):
        if self.proc.poll() is None:
            try:
                os.killpg(self.proc.pid, signal.SIGTERM)
                self.proc.wait(timeout=20)
            except (ProcessLookupError, subprocess.TimeoutExpired):
                try:
                    os.killpg(self.proc.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                self.proc.wait(timeout=10)


def wait_http(url, timeout=60):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            with urllib.request.urlopen(url, timeout=2) as r:
                if r.status == 200:
                    return
        except OSError:
            pass
        time.sleep(0.2)
    raise AssertionError(f"{url}: no answer within {timeout} s")


def rows_at(run_dir, tick):
    """robots.csv's rows of `tick`, by id."""
    with open(os.path.join(run_dir, "robots.csv")) as f:
        return {int(r["id"]): r for r in csv.DictReader(f) if int(r["tick"]) == tick}


def hex_rgb(colour):
    return tuple(int(colour[i:i + 2], 16) for i in (1, 3, 5))


def pixel(img, x, y):
    """The 0..255 RGB of the screenshot at CSS pixel (x, y) (device scale factor 1)."""
    p = img[int(y), int(x)]  # the device pixel that holds the point
    return tuple(int(round(float(c) * 255)) for c in p[:3])


def check_projection(test, b, x, y):
    """The page's projection of arena point (x, y), checked against the arena frame's (x right, y up, the view's
    centre at the canvas's centre) within 1.5 px; returns the page's point in the screenshot's pixels."""
    c = b.eval("(() => { const r = document.getElementById('arena').getBoundingClientRect();"
               " return {x: r.x, y: r.y, w: r.width, h: r.height, v: sfViewer.view}; })()")
    px, py = b.eval(f"sfViewer.project({x!r}, {y!r})")
    ex = c["w"] / 2 + (x - c["v"]["cx"]) * c["v"]["scale"]
    ey = c["h"] / 2 - (y - c["v"]["cy"]) * c["v"]["scale"]
    test.assertLess(abs(px - ex) + abs(py - ey), 1.5, f"the page projects ({x}, {y}) to ({px}, {py}), not ({ex}, {ey})")
    return c["x"] + px, c["y"] + py


def drawn_near(img, x, y, want, tolerance=12):
    """The pixel nearest (x, y) of the 3x3 around it that is closest to colour `want`, and its distance (max over
    channels). A body is a disc of radius >= 4 px (viewer.js): its 3x3 centre is its own whatever the sub-pixel
    placement of the canvas, and no other body can reach it (bodies do not overlap)."""
    best = None
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            got = pixel(img, x + dx, y + dy)
            d = max(abs(a - b) for a, b in zip(got, want))
            if best is None or d < best[1]:
                best = (got, d)
    return best


def processes_mentioning(text):
    found = []
    for entry in os.listdir("/proc"):
        if entry.isdigit():
            try:
                with open(f"/proc/{entry}/cmdline", "rb") as f:
                    if text.encode() in f.read() and helpers.pid_alive(int(entry)):
                        found.append(int(entry))
            except OSError:
                pass
    return found


def cmdline(pid):
    try:
        with open(f"/proc/{pid}/cmdline", "rb") as f:
            return f.read().decode(errors="replace")
    except OSError:
        return ""
