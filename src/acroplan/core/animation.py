"""Animations of any figure, fast: the still parts drawn once, the moving artists blitted per frame.

matplotlib's ``FuncAnimation(...).save(writer=PillowWriter)`` redraws the whole figure for every
frame (axes, ticks, grid, legend: 0.14-0.18 s a frame for acroplan's drawings). Here the figure is
drawn once without its moving artists, its pixels are kept, and each frame restores them, draws the
moving artists alone (``Figure.draw_artist``) and takes the pixels: the usual blitting of
interactive matplotlib, applied to a file. Text that changes every frame (the time, the angles) is
drawn by Pillow on the finished frame (``caption``): matplotlib lays text out glyph by glyph, which
took two thirds of a frame's time. The frames are written by Pillow, as one GIF with one palette
(chosen from the first frame, so the colours do not flicker between frames); an MP4 is written too
when ffmpeg is on the PATH.

:func:`animate_result` is what :meth:`PlanResult.animate <acroplan.core.result.PlanResult.animate>`
does with a family's ``animate`` hook: the file, or in a notebook an :class:`Animation` shown inline
(a JavaScript player: play, pause, a frame slider).

Knows no body: the families' drawing modules build the figure and say which artists move.
"""

from __future__ import annotations

import shutil
import subprocess
from typing import Callable, Sequence

import numpy as np

from .progress import stage

__all__ = ["write_frames", "frame_times", "auto_speed", "Animation", "animate_result", "samples_from_csv",
           "states_at", "states_evenly", "MIN_SECONDS"]

#: A motion shorter than this many seconds is played slower by default, so that its animation lasts
#: this long (the falling cat's 0.5 s turn: 3 s at 1/6 speed), :func:`auto_speed`.
MIN_SECONDS = 3.0


def auto_speed(duration: float, speed: float | None = None) -> float:
    """The playback speed: ``speed`` when given, else real time (1), or slower for a motion shorter
    than :data:`MIN_SECONDS` (so that it lasts that long)."""
    if speed is not None:
        return float(speed)
    return min(1.0, float(duration) / MIN_SECONDS) if duration > 0 else 1.0


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


def samples_from_csv(path, names) -> tuple[np.ndarray, np.ndarray]:
    """``(t, X)`` of the states ``names`` in a ``trajectory.csv`` (``t`` shape (N,), ``X`` shape (n, N)):
    what an output folder's animation is drawn from, with no integrator compiled.

    Raises
    ------
    InvalidInputError
        The file is missing, corrupt, or lacks a state's column.
    """
    from .errors import InvalidInputError

    try:
        with open(path, encoding="utf-8") as f:
            header = f.readline().strip().split(",")
        data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
        cols = [header.index(n) for n in names]
        t = data[:, header.index("t")]
    except (OSError, ValueError, IndexError) as e:
        raise InvalidInputError(str(path), f"cannot be read ({type(e).__name__}: {e})",
                                "plan again to rewrite it") from None
    if t.size < 2 or np.any(np.diff(t) <= 0):
        raise InvalidInputError(str(path), "needs increasing times", "plan again to rewrite it")
    return t, data[:, cols].T


def states_at(result, t, samples=None, unit_rows: int = 0) -> np.ndarray:
    """The states of ``result`` at times ``t``: what the families' drawings draw.

    Parameters
    ----------
    result : PlanResult
    t : array_like, shape (K,)
    samples : (t, X), optional
        Sampled states to draw from instead of evaluating the result: times (N,) and states (n, N),
        for example an output folder's ``trajectory.csv`` (:func:`samples_from_csv`); interpolated
        linearly, row by row.
    unit_rows : int
        With ``samples``: the first ``unit_rows`` rows renormalised (a unit quaternion).

    Returns
    -------
    numpy.ndarray, shape (n, K)
        Exact (:meth:`PlanResult.evaluate <acroplan.core.result.PlanResult.evaluate>`) without
        ``samples``.
    """
    t = np.asarray(t, dtype=float)
    if samples is None:
        return np.asarray(result.evaluate(t, effort=False).states)
    ts, X = samples
    out = np.stack([np.interp(t, ts, row) for row in X])
    if unit_rows:
        out[:unit_rows] /= np.linalg.norm(out[:unit_rows], axis=0, keepdims=True)
    return out


def states_evenly(result, n: int, samples=None, unit_rows: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``n`` equally spaced times from the plan's start to its end, and the states at them
    (:func:`states_at`, whose ``samples`` and ``unit_rows`` these are): a strobe's poses, an
    animation's frames.

    Returns
    -------
    t : numpy.ndarray, shape (n,)
    states : numpy.ndarray, shape (n_states, n)
    """
    t = np.linspace(float(result.times[0]), float(result.times[-1]), int(n))
    return t, states_at(result, t, samples, unit_rows)


def _rgb(canvas) -> np.ndarray:
    return np.asarray(canvas.buffer_rgba())[..., :3].copy()


class _Caption:
    """Text drawn by Pillow on a frame: ``lines`` at ``xy`` (figure fraction from the top left), in
    DejaVu Sans Mono (matplotlib's) of ``size`` points at the figure's dpi."""

    def __init__(self, fig, xy=(0.02, 0.02), size: float = 9.0, color=(20, 20, 20)):
        from matplotlib import font_manager
        from PIL import ImageFont

        self.px = (int(xy[0] * fig.bbox.width), int(xy[1] * fig.bbox.height))
        path = font_manager.findfont(font_manager.FontProperties(family="DejaVu Sans Mono"))
        self.font = ImageFont.truetype(path, max(6, int(round(size * fig.dpi / 72.0))))
        self.color = color

    def draw(self, img, text: str) -> None:
        from PIL import ImageDraw

        ImageDraw.Draw(img).multiline_text(self.px, text, font=self.font, fill=self.color, spacing=2)


def write_frames(fig, artists: Sequence, update: Callable[[int], object], n_frames: int, path, *, fps: int,
                 mp4_path=None, progress: Callable[[int], object] | None = None,
                 full_redraw: bool = False, caption: Callable[[int], str] | None = None,
                 caption_at=(0.02, 0.02), caption_size: float = 9.0) -> int:
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
    caption : callable ``caption(k) -> str``, optional
        Text of frame ``k`` (several lines), drawn by Pillow at ``caption_at`` (figure fraction from
        the top left) in a monospace font of ``caption_size`` points.

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
    cap = _Caption(fig, caption_at, caption_size) if caption is not None else None
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
            if cap is not None:
                cap.draw(img, caption(k))
                rgb = np.asarray(img) if mp4_path is not None else rgb
            if palette is None:
                palette = img.quantize(colors=255, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
            frames.append(img.quantize(palette=palette, dither=Image.Dither.NONE))
            if mp4_path is not None:
                frames[-1].info["rgb"] = rgb
            if progress is not None:
                progress(k + 1)
            st.update()
    duration = max(1, int(round(1000 / fps)))
    with stage("writing the GIF", unit="file"):  # (the encoding of hundreds of frames: seconds)
        frames[0].save(str(path), save_all=True, append_images=frames[1:], duration=duration, loop=0,
                       optimize=False, disposal=1)
    if mp4_path is not None and shutil.which("ffmpeg"):
        with stage("writing the MP4", unit="file"):
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


class Animation:
    """An animation written by a family's drawing (:func:`animate_result`): its GIF file, its frame
    count and rate; shown inline in a notebook as a JavaScript player (play, pause, a frame slider),
    the frames embedded.

    Attributes
    ----------
    path : pathlib.Path or None
        The GIF written (``None``: kept in memory only, for a notebook).
    frames : int
    fps : int
    """

    def __init__(self, path, frames: int, fps: int, data: bytes | None = None):
        from pathlib import Path

        self.path = None if path is None else Path(path)
        self.frames, self.fps = int(frames), int(fps)
        self._data = data

    def gif(self) -> bytes:
        """The GIF's bytes."""
        return self._data if self._data is not None else self.path.read_bytes()

    def save(self, path) -> "Animation":
        """Write the GIF to ``path``; returns the animation of that file."""
        from pathlib import Path

        Path(path).write_bytes(self.gif())
        return Animation(path, self.frames, self.fps)

    def __repr__(self):
        return f"Animation({self.frames} frames at {self.fps} fps{f', {self.path}' if self.path else ''})"

    def _repr_html_(self) -> str:
        return player_html(self.gif(), self.fps)


def player_html(gif: bytes, fps: int, *, max_frames: int = 600) -> str:
    """A self-contained HTML player of a GIF's frames (each as an embedded PNG): play, pause, a
    frame slider, the frame's time. At most ``max_frames`` frames (every k-th beyond that). Under
    the progress stage "player frames" (hundreds of frames: seconds, while a notebook shows the
    result)."""
    import base64
    import io
    import json
    import uuid

    from PIL import Image, ImageSequence

    srcs = []
    with Image.open(io.BytesIO(gif)) as im:
        n = getattr(im, "n_frames", 1)
        step = max(1, -(-n // max_frames))
        with stage("player frames", -(-n // step), unit="frame") as st:
            for k, frame in enumerate(ImageSequence.Iterator(im)):
                if k % step:
                    continue
                f = frame.convert("P") if frame.mode == "P" else frame.convert("RGB")
                buf = io.BytesIO()
                f.save(buf, format="PNG", optimize=False)
                srcs.append("data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii"))
                st.update()
    uid = "acroplan" + uuid.uuid4().hex[:10]
    delay = 1000.0 * step / max(fps, 1)
    return f"""<div id="{uid}" style="font-family:sans-serif;font-size:13px">
<img id="{uid}_img" src="{srcs[0]}" style="max-width:100%"><br>
<button id="{uid}_play">&#9654; play</button> <button id="{uid}_pause">&#10074;&#10074; pause</button>
<input id="{uid}_slider" type="range" min="0" max="{len(srcs) - 1}" value="0" style="width:60%">
<span id="{uid}_label">frame 1 / {len(srcs)}</span>
<script>(function() {{
  var f = {json.dumps(srcs)}, k = 0, timer = null;
  var img = document.getElementById("{uid}_img"), s = document.getElementById("{uid}_slider"),
      lab = document.getElementById("{uid}_label");
  function show(i) {{ k = i; img.src = f[k]; s.value = k; lab.textContent = "frame " + (k + 1) + " / " + f.length; }}
  function pause() {{ if (timer) {{ clearInterval(timer); timer = null; }} }}
  document.getElementById("{uid}_play").onclick = function() {{
    pause(); timer = setInterval(function() {{ show((k + 1) % f.length); }}, {delay:.1f}); }};
  document.getElementById("{uid}_pause").onclick = pause;
  s.oninput = function() {{ pause(); show(parseInt(s.value)); }};
}})();</script></div>"""


def animate_result(result, hook, path=None, **kwargs) -> Animation:
    """Write ``result``'s animation with a family's ``animate`` hook (``hook(result, path, **kwargs)
    -> frames``): to ``path``; without one, in a notebook into memory (the returned
    :class:`Animation` is shown inline), elsewhere to ``motion.gif`` in the current folder."""
    import tempfile
    from pathlib import Path

    from .progress import in_notebook

    fps = int(kwargs.get("fps") or 25)
    if path is None and in_notebook():
        with tempfile.TemporaryDirectory() as tmp:
            gif = Path(tmp) / "motion.gif"
            n = hook(result, gif, **kwargs)
            return Animation(None, n, fps, data=gif.read_bytes())
    path = Path("motion.gif" if path is None else path)
    n = hook(result, path, **kwargs)
    return Animation(path, n, fps)
