"""Animations of any figure, fast: the still parts drawn once, the moving artists blitted per frame.

matplotlib's ``FuncAnimation(...).save(writer=PillowWriter)`` redraws the whole figure for every
frame (axes, ticks, grid, legend: 0.14-0.18 s a frame for acroplan's drawings). Here the figure is
drawn once without its moving artists, its pixels are kept, and each frame restores them, draws the
moving artists alone (``Figure.draw_artist``) and takes the pixels: the usual blitting of
interactive matplotlib, applied to a file. The frames are written by Pillow, as one GIF with one
palette (chosen from the first frame, so the colours do not flicker between frames); an MP4 is
written too when ffmpeg is on the PATH.

Knows no body: the families' drawing modules build the figure and say which artists move.
"""

from __future__ import annotations

import shutil
import subprocess
from typing import Callable, Sequence

import numpy as np

from .progress import stage

__all__ = ["write_frames", "frame_times"]


def frame_times(t0: float, t1: float, *, speed: float, fps: int, max_frames: int) -> tuple[np.ndarray, bool]:
    """Frame times of a motion on ``[t0, t1]`` played at ``speed`` (1 = real time) and ``fps``.

    Returns
    -------
    t : numpy.ndarray, shape (n,)
        ``n = round((t1 - t0) / speed * fps) + 1`` (at least 2), at most ``max_frames``.
    capped : bool
        Whether ``max_frames`` capped it (the motion is then played faster).
    """
    n = max(2, int(round((t1 - t0) / speed * fps)) + 1)
    capped = n > max_frames
    return np.linspace(t0, t1, min(n, max_frames)), capped


def _rgb(canvas) -> np.ndarray:
    return np.asarray(canvas.buffer_rgba())[..., :3].copy()


def write_frames(fig, artists: Sequence, update: Callable[[int], object], n_frames: int, path, *, fps: int,
                 mp4_path=None, progress: Callable[[int], object] | None = None,
                 full_redraw: bool = False) -> int:
    """Write the frames of ``fig`` to the GIF ``path``.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        With an Agg canvas (``FigureCanvasAgg(fig)``); never pyplot's.
    artists : sequence of matplotlib artists
        The artists ``update`` changes. Everything else in the figure must stay the same in every
        frame: it is drawn once.
    update : callable ``update(k)``
        Sets the artists to frame ``k`` (0 <= k < n_frames).
    n_frames : int
    path : path of the GIF
    fps : int
        Frames per second.
    mp4_path : path, optional
        Also write an MP4 there when ffmpeg is on the PATH (H.264, from the same frames).
    progress : callable, optional
        Called with the number of frames done after each frame (the frames are also the stage
        ``"animation frames"`` of :mod:`acroplan.core.progress`).
    full_redraw : bool
        Draw the whole figure for every frame (for figures whose still parts change, such as a 3-D
        view whose axes move with the body); slower.

    Returns
    -------
    int
        The number of frames written.
    """
    from PIL import Image

    canvas = fig.canvas
    if not full_redraw:
        for a in artists:
            a.set_animated(True)
        canvas.draw()
        background = canvas.copy_from_bbox(fig.bbox)
    frames, palette = [], None
    with stage("animation frames", n_frames, unit="frame") as st:
        for k in range(n_frames):
            update(k)
            if full_redraw:
                canvas.draw()
            else:
                canvas.restore_region(background)
                for a in artists:
                    if hasattr(a, "do_3d_projection"):
                        a.do_3d_projection()
                    fig.draw_artist(a)
            rgb = _rgb(canvas)
            img = Image.fromarray(rgb)
            if palette is None:
                palette = img.quantize(colors=255, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
            frames.append(img.quantize(palette=palette, dither=Image.Dither.NONE))
            if mp4_path is not None:
                frames[-1].info["rgb"] = rgb
            if progress is not None:
                progress(k + 1)
            st.update()
    duration = max(1, int(round(1000 / fps)))
    frames[0].save(str(path), save_all=True, append_images=frames[1:], duration=duration, loop=0,
                   optimize=False, disposal=1)
    if mp4_path is not None and shutil.which("ffmpeg"):
        _mp4(frames, mp4_path, fps)
    return n_frames


def _mp4(frames, path, fps: int) -> None:
    h, w = frames[0].info["rgb"].shape[:2]
    w2, h2 = w - w % 2, h - h % 2  # H.264 needs even sizes
    cmd = ["ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{w2}x{h2}",
           "-r", str(fps), "-i", "-", "-pix_fmt", "yuv420p", "-vcodec", "libx264", str(path)]
    proc = subprocess.Popen(cmd, stdin=subprocess.PIPE)
    for f in frames:
        proc.stdin.write(np.ascontiguousarray(f.info["rgb"][:h2, :w2]).tobytes())
    proc.stdin.close()
    if proc.wait() != 0:
        raise RuntimeError(f"ffmpeg failed writing {path}")
