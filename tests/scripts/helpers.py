"""Shared bits of the scripts' tests: paths, running `scripts/swarm`, reading a PNG header, ffprobe, a free port."""

import json
import os
import socket
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
SWARM = os.path.join(ROOT, "scripts", "swarm")
FAKE_BUILD = os.path.join(HERE, "fake_build")
sys.path.insert(0, os.path.join(ROOT, "scripts"))


def test_domain(offset):
    """The DDS domain of a networked test: SWARMFORM_TEST_DOMAIN_BASE (default 100) + offset, the scheme and the
    offsets' table of tests/support/test_domain.hpp (a window of 64 domains per build; 38-39 are the launcher's
    free-domain picker's, in test_launcher_e2e's concurrent runs)."""
    text = os.environ.get("SWARMFORM_TEST_DOMAIN_BASE") or "100"
    if not text.isdigit() or int(text) > 232 - 64 + 1:
        raise ValueError(f"SWARMFORM_TEST_DOMAIN_BASE={text!r}: want an integer 0..169 "
                         "(each build's tests use 64 domains from it)")
    assert 0 <= offset < 64, offset
    return int(text) + offset


def swarm(*args, env=None, timeout=120, build_dir=FAKE_BUILD):
    """Runs scripts/swarm without building; returns the CompletedProcess (text)."""
    e = dict(os.environ, SWARM_NO_BUILD="1", BUILD_DIR=build_dir)
    if build_dir == FAKE_BUILD:  # the stand-in world holds no DDS port: see fake_build/python/sitecustomize.py
        e["PYTHONPATH"] = os.path.join(FAKE_BUILD, "python")
    e.update(env or {})
    return subprocess.run([SWARM] + list(args), capture_output=True, text=True, timeout=timeout, env=e)


def png_size(path):
    """(width, height) of a PNG, checking it is one: signature, IHDR first, IEND last."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR" or data[-8:-4] != b"IEND":
        raise AssertionError(f"{path} is not a complete PNG")
    return struct.unpack(">II", data[16:24])


def video_frames(path):
    """(width, height, frames counted by decoding) of the first video stream, from ffprobe."""
    out = subprocess.run(["ffprobe", "-v", "error", "-count_frames", "-select_streams", "v:0", "-show_entries",
                          "stream=width,height,nb_read_frames", "-of", "json", path],
                         capture_output=True, text=True, timeout=120, check=True).stdout
    s = json.loads(out)["streams"][0]
    return s["width"], s["height"], int(s["nb_read_frames"])


def pid_alive(pid):
    """True if `pid` is a live (not zombie) process."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def video_frame(path, index, width, height):
    """Frame `index` of a video as a numpy array [height, width, 3] (uint8 RGB), decoded by ffmpeg."""
    import numpy as np
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-vf", f"select=eq(n\\,{index})", "-frames:v", "1",
                          "-f", "rawvideo", "-pix_fmt", "rgb24", "-"], capture_output=True, timeout=120,
                         check=True).stdout
    return np.frombuffer(raw, dtype=np.uint8).reshape(height, width, 3)


def free_port():
    """A TCP port free on 127.0.0.1 now (for a viewer's --view)."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]
