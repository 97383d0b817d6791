"""The whole run as a video: animation.mp4 (H.264, for watching) and animation.gif (small, for a README).

Speed is the design: one Scene (scene.py) is drawn once, its background kept, and each frame only restores
that background and redraws the few dynamic artists (blitting on the Agg canvas); the raw RGBA frames are piped
straight into two ffmpeg processes at once. Frames are subsampled so the video has at most MAX_FRAMES frames
(about ten seconds) and the GIF at most MAX_GIF_FRAMES, 640 px wide, with a 128-colour palette.
"""

import math
import os
import subprocess
import tempfile
from typing import IO, Any, Callable, Optional

from .recording import Recording
from .scene import Scene

MP4_SIZE = (960, 540)  # even sizes: H.264 with yuv420p needs them
GIF_WIDTH = 640
MAX_FRAMES = 300
MAX_GIF_FRAMES = 150
GIF_LIMIT_BYTES = 3 * 1024 * 1024
TARGET_SECONDS = 10.0


class AnimationError(Exception):
    pass


def frame_plan(tick_count: int, max_frames: int = MAX_FRAMES,
               max_gif_frames: int = MAX_GIF_FRAMES) -> tuple[list[int], int, int]:
    """(indices of the recorded ticks that become MP4 frames, every how many MP4 frames a GIF frame, mp4 fps).

    The last tick is always a frame, so the video ends on the final state."""
    step = max(1, math.ceil(tick_count / max_frames))
    frames = list(range(0, tick_count, step))
    if frames[-1] != tick_count - 1:
        if len(frames) >= max_frames:
            frames[-1] = tick_count - 1
        else:
            frames.append(tick_count - 1)
    gif_every = max(1, math.ceil(len(frames) / max_gif_frames))
    fps = int(min(30, max(5, round(len(frames) / TARGET_SECONDS))))
    return frames, gif_every, fps


def gif_frame_count(frame_count: int, gif_every: int) -> int:
    return len(range(0, frame_count, gif_every))


def _ffmpeg(args: list[str], stderr: IO[Any]) -> "subprocess.Popen[bytes]":
    try:
        return subprocess.Popen(["ffmpeg", "-hide_banner", "-loglevel", "error", "-y"] + args,
                                stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=stderr)
    except FileNotFoundError:
        raise AnimationError("ffmpeg not found: install it (scripts/setup does, as root)") from None


def _raw_input(size: tuple[int, int], fps: int) -> list[str]:
    return ["-f", "rawvideo", "-pix_fmt", "rgba", "-s", f"{size[0]}x{size[1]}", "-r", str(fps), "-i", "-"]


def _gif_filter(width: int, colours: int) -> str:
    return (f"scale={width}:-2:flags=lanczos,split[a][b];[a]palettegen=max_colors={colours}:stats_mode=full[p];"
            f"[b][p]paletteuse=dither=bayer:bayer_scale=4:diff_mode=rectangle")


def render(rec: Recording, out_dir: str, log: Callable[[str], None] = print, max_frames: int = MAX_FRAMES,
           progress: Optional[Callable[[str], None]] = None) -> list[str]:
    """Writes animation.mp4 and animation.gif into out_dir; returns their paths. `progress(text)`, when given, is
    told how far the frames are (the slow part of the pictures)."""
    mp4 = os.path.join(out_dir, "animation.mp4")
    gif = os.path.join(out_dir, "animation.gif")
    frames, gif_every, fps = frame_plan(len(rec.track.ticks), max_frames)
    gif_fps = max(1, round(fps / gif_every))
    scene = Scene(rec, MP4_SIZE, 100)
    canvas = scene.fig.canvas
    with tempfile.TemporaryFile() as err_mp4, tempfile.TemporaryFile() as err_gif:
        p_mp4 = _ffmpeg(_raw_input(MP4_SIZE, fps) + ["-c:v", "libx264", "-preset", "veryfast", "-crf", "26",
                                                     "-pix_fmt", "yuv420p", "-movflags", "+faststart", mp4],
                        err_mp4)
        p_gif = _ffmpeg(_raw_input(MP4_SIZE, gif_fps) + ["-vf", _gif_filter(GIF_WIDTH, 128), gif], err_gif)
        assert p_mp4.stdin is not None and p_gif.stdin is not None  # stdin=PIPE (_ffmpeg)
        try:
            # Background: everything but the dynamic artists, drawn once.
            for a in scene.dynamic:
                a.set_visible(False)
            canvas.draw()
            background = canvas.copy_from_bbox(scene.fig.bbox)
            for a in scene.dynamic:
                a.set_visible(True)
            for n, i in enumerate(frames):
                if progress and n % 25 == 0:
                    progress(f"animation frame {n + 1}/{len(frames)}")
                scene.show(i)
                canvas.restore_region(background)
                for a in scene.dynamic:
                    scene.ax.draw_artist(a)
                frame = bytes(canvas.buffer_rgba())
                p_mp4.stdin.write(frame)
                if n % gif_every == 0:
                    p_gif.stdin.write(frame)
        except BrokenPipeError:
            pass  # ffmpeg failed; its message is read below
        finally:
            scene.close()
            for p in (p_mp4, p_gif):
                try:
                    if p.stdin is not None:
                        p.stdin.close()
                except BrokenPipeError:
                    pass
            codes = [p.wait(timeout=300) for p in (p_mp4, p_gif)]
        for code, err, name in ((codes[0], err_mp4, mp4), (codes[1], err_gif, gif)):
            if code != 0:
                err.seek(0)
                raise AnimationError(f"ffmpeg failed writing {name}: {err.read().decode(errors='replace')[-500:]}")
    if os.path.getsize(gif) > GIF_LIMIT_BYTES:
        _shrink_gif(mp4, gif, gif_every, gif_fps, log)
    return [mp4, gif]


def _shrink_gif(mp4: str, gif: str, gif_every: int, gif_fps: int, log: Callable[[str], None]) -> None:
    """A GIF over the limit is made again from the MP4, smaller and with fewer colours (same frame count)."""
    size = os.path.getsize(gif)
    vf = f"select='not(mod(n\\,{gif_every}))',setpts=N/({gif_fps}*TB)," + _gif_filter(360, 32)
    code = subprocess.call(["ffmpeg", "-hide_banner", "-loglevel", "error", "-y", "-i", mp4, "-vf", vf, "-r",
                            str(gif_fps), gif], stdout=subprocess.DEVNULL)
    if code != 0:
        raise AnimationError(f"ffmpeg failed shrinking {gif}")
    log(f"pictures: {gif} was {size / 1e6:.1f} MB; made again at 360 px, 32 colours: "
        f"{os.path.getsize(gif) / 1e6:.1f} MB")
