"""Drawings of spatial bodies (matplotlib 3-D, headless): an animation (:func:`animate`, an animated
GIF blitted by :mod:`acroplan.core.animation`), a strobe (:func:`strobe`), and the attitude as Euler angles
over time (:func:`attitude_figure`).

Every link with mass is drawn as its **equivalent box**: the uniform box with the link's mass and
principal moments, :math:`a_i = \\sqrt{6 (I_j + I_k - I_i)/m}`, centred at its centre of mass along
its principal axes (a rod is a long thin box, a trunk a tall one), its faces shaded by a fixed light
(Lambert: :math:`0.35 + 0.65 \\max(0, n \\cdot \\ell)`); joints are dots. The root's frame is drawn as
three arrows (:math:`x` red, :math:`y` green, :math:`z` blue) and the angular momentum vector
:math:`L` as a black arrow from the centre of mass (scaled to the body's size; the title gives
:math:`|L|`). The picture is in the centre-of-mass frame (the centre of mass at the origin).

Figures are built on an explicit :class:`matplotlib.figure.Figure` with the Agg canvas: no global
backend or pyplot state is touched.
"""

from __future__ import annotations

import math

import numpy as np

from ...core.animation import auto_speed, states_at, write_frames
from . import rotations as rot

__all__ = ["equivalent_boxes", "draw_body", "strobe", "save_strobe", "attitude_figure", "animate", "MAX_FRAMES"]

#: Frame cap of an animation.
MAX_FRAMES = 600
_LIGHT = np.array([0.4, -0.5, 0.77]) / np.linalg.norm([0.4, -0.5, 0.77])
_COLORS = ["#4c72b0", "#dd8452", "#55a868", "#c44e52", "#8172b3", "#937860", "#da8bc3", "#8c8c8c"]


def equivalent_boxes(body):
    """Per link with mass: the equivalent box's half sides and principal axes (module docstring).

    Returns
    -------
    list of (link index, half sides (3,), axes (3, 3) in the link frame, columns)
    """
    out = []
    for i, link in enumerate(body.links):
        if link.mass <= 0:
            continue
        ev, V = np.linalg.eigh(link.inertia_matrix)
        s = ev.sum()
        sides = np.sqrt(np.maximum(6.0 * (s - 2.0 * ev) / link.mass, 0.0))
        sides = np.maximum(sides, 0.02 * max(sides.max(), 1e-3))
        out.append((i, sides / 2.0, V))
    return out


_FACES = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)


def _box_polys(center, R, half):
    P = center + (_CORNERS * half) @ R.T
    polys = [P[list(f)] for f in _FACES]
    normals = []
    for f in polys:
        n = np.cross(f[1] - f[0], f[3] - f[0])
        nn = np.linalg.norm(n)
        n = n / nn if nn > 0 else n
        c = f.mean(axis=0)
        if n @ (c - center) < 0:
            n = -n
        normals.append(n)
    return polys, normals


def _shade(color, normals):
    from matplotlib.colors import to_rgb

    base = np.array(to_rgb(color))
    return [tuple(np.clip(base * (0.35 + 0.65 * max(0.0, float(n @ _LIGHT))), 0, 1)) for n in normals]


def _size(body, states) -> float:
    pts = []
    for x in states:
        _, org, coms = body.link_poses(x)
        pts += [org, coms]
    P = np.concatenate(pts)
    boxes = equivalent_boxes(body)
    extra = max((2 * h.max() for _, h, _ in boxes), default=0.0)
    return float(np.abs(P).max() + extra / 2)


def draw_body(ax, body, state, *, scale: float, offset=(0.0, 0.0, 0.0), alpha: float = 1.0, arrows: bool = True):
    """Draw ``body`` at ``state`` on a 3-D axes (module docstring).

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.Axes3D
    state : array_like, shape (4 + m,)
    scale : float
        The body's size (arrow lengths).
    offset : (3,)
        Where the centre of mass is drawn.
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    off = np.asarray(offset, dtype=float)
    Rs, org, coms = body.link_poses(state)
    polys, colors = [], []
    for k, (i, half, V) in enumerate(equivalent_boxes(body)):
        p, n = _box_polys(coms[i] + off, Rs[i] @ V, half)
        polys += p
        colors += _shade(_COLORS[k % len(_COLORS)], n)
    pc = Poly3DCollection(polys, facecolors=colors, edgecolors=(0, 0, 0, 0.25 * alpha), linewidths=0.3, alpha=alpha)
    ax.add_collection3d(pc)
    J = org[[i for i in range(len(body.links)) if body.links.parents[i] != -1]] + off
    if len(J):
        ax.scatter(J[:, 0], J[:, 1], J[:, 2], s=8, color="k", alpha=alpha, depthshade=False)
    if arrows:
        r = body.links.root
        o = org[r] + off
        for axis, c in zip(Rs[r].T, ("#d62728", "#2ca02c", "#1f77b4")):
            ax.quiver(*o, *(0.45 * scale * axis), color=c, linewidth=1.5, arrow_length_ratio=0.2)
        L = body.angular_momentum
        nL = float(np.linalg.norm(L))
        if nL > 0:
            ax.quiver(*off, *(0.9 * scale * L / nL), color="k", linewidth=2.0, arrow_length_ratio=0.15)
    return ax


def _setup(ax, scale, center=(0.0, 0.0, 0.0)):
    c = np.asarray(center, dtype=float)
    for setter, v in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), c):
        setter(v - scale, v + scale)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.view_init(elev=18, azim=-60)


def _states(result, t, samples=None):
    """The states at ``t``, one row a time (exact, or from ``samples``: core.animation.states_at)."""
    return states_at(result, t, samples, unit_rows=4).T


def _title(body, t=None):
    nL = float(np.linalg.norm(body.angular_momentum))
    head = f"t = {t:.2f} s, " if t is not None else ""
    return head + ("L = 0" if nL == 0 else f"|L| = {nL:.3g} kg m²/s")


def strobe(result, *, poses: int = 6, fig=None, title: str | None = None, samples=None):
    """The body at ``poses`` equally spaced times of a plan, one 3-D panel each.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    body = result.system
    t = np.linspace(result.times[0], result.times[-1], poses)
    X = _states(result, t, samples)
    scale = _size(body, X)
    fig = fig or Figure(figsize=(2.4 * poses, 2.9))
    for k in range(poses):
        ax = fig.add_subplot(1, poses, k + 1, projection="3d")
        draw_body(ax, body, X[k], scale=scale)
        _setup(ax, scale)
        ax.set_title(f"t = {t[k]:.2f} s", fontsize=9)
        ax.tick_params(labelsize=6)
    fig.suptitle(title or _title(body), fontsize=10)
    fig.subplots_adjust(left=0.01, right=0.99, bottom=0.02, top=0.88, wspace=0.02)
    return fig


def save_strobe(result, path, **kw) -> None:
    """:func:`strobe` saved to ``path`` (PNG, 110 dpi)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = strobe(result, **kw)
    FigureCanvasAgg(fig)
    fig.savefig(path, dpi=110)


def attitude_figure(result, *, seq: str = "yeadon", samples: int = 400, fig=None, title: str | None = None):
    """The root's attitude as Euler angles over time (unwrapped, degrees) and the joint angles.

    Parameters
    ----------
    seq : str
        ``"yeadon"`` (somersault, tilt, twist; :mod:`~acroplan.families.spatial.rotations`) or a
        scipy sequence.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    body = result.system
    t = np.linspace(result.times[0], result.times[-1], samples)
    X = _states(result, t).T
    E = np.degrees(np.unwrap(np.radians(rot.to_euler(X[:4], seq)), axis=1))
    names = rot.EULER_NAMES if seq.lower() == "yeadon" else tuple(seq)
    fig = fig or Figure(figsize=(8.0, 5.2))
    a1 = fig.add_subplot(2, 1, 1)
    for k in range(3):
        a1.plot(t, E[k], label=names[k])
    a1.set_ylabel("attitude (deg)")
    a1.legend(loc="best", fontsize=8)
    a1.grid(alpha=0.3)
    a2 = fig.add_subplot(2, 1, 2, sharex=a1)
    for j, name in enumerate(body.links.joint_names):
        a2.plot(t, np.degrees(X[4 + j]), label=name)
    for tk in result.times:
        a1.axvline(tk, color="0.8", lw=0.6)
        a2.axvline(tk, color="0.8", lw=0.6)
    a2.set_ylabel("joint angle (deg)")
    a2.set_xlabel("t (s)")
    a2.legend(loc="best", fontsize=8, ncol=2)
    a2.grid(alpha=0.3)
    fig.suptitle(title or ("Yeadon angles (somersault, tilt, twist) and joints" if seq.lower() == "yeadon"
                           else f"Euler angles ({seq}) and joints"), fontsize=10)
    fig.tight_layout()
    return fig


def animate(result, path, *, fps: int = 25, speed: float | None = None, dpi: int = 100, title: str | None = None,
            max_frames: int = MAX_FRAMES, mp4_path=None, samples=None) -> int:
    """An animated GIF of a plan (module docstring), headless: 560 px square at the default dpi.

    Parameters
    ----------
    result : PlanResult
    path : str or pathlib.Path
    fps : int
    speed : float, optional
        Playback speed (2: twice as fast as real time); default: real time, or slower for a motion
        shorter than 3 s (the cat's 0.5 s turn at 1/6 speed: 76 frames;
        :func:`~acroplan.core.animation.auto_speed`).
    dpi : int
    title : str, optional
    max_frames : int
        At most this many frames (a longer motion is played faster).
    mp4_path : path, optional
        Also an MP4 when ffmpeg is on the PATH.
    samples : (t, X), optional
        Draw from these sampled states (an output folder's ``trajectory.csv``:
        :func:`~acroplan.core.animation.samples_from_csv`) instead of evaluating the result.

    Returns
    -------
    int
        The number of frames written (at most ``max_frames``).
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    body = result.system
    T = result.times[-1] - result.times[0]
    speed = auto_speed(T, speed)
    frames = int(min(max_frames, max(2, math.ceil(T / speed * fps) + 1)))
    t = np.linspace(result.times[0], result.times[-1], frames)
    X = _states(result, t, samples)
    scale = _size(body, X)
    fig = Figure(figsize=(5.6, 5.6), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1, projection="3d")
    _setup(ax, scale)
    # the still parts (axes, the angular momentum's arrow) drawn once; the body's boxes, joints,
    # the root's axes and the title move (acroplan.core.animation)
    boxes = equivalent_boxes(body)
    pc = Poly3DCollection([np.zeros((4, 3))] * (6 * len(boxes)), edgecolors=(0, 0, 0, 0.25), linewidths=0.3)
    ax.add_collection3d(pc)
    joints = [i for i in range(len(body.links)) if body.links.parents[i] != -1]
    dots, = ax.plot([], [], [], "o", ms=3, color="k", linestyle="none")
    root_axes = [ax.plot([], [], [], color=c, lw=1.5)[0] for c in ("#d62728", "#2ca02c", "#1f77b4")]
    L = body.angular_momentum
    nL = float(np.linalg.norm(L))
    if nL > 0:
        ax.quiver(0, 0, 0, *(0.9 * scale * L / nL), color="k", linewidth=2.0, arrow_length_ratio=0.15)
    if title:
        ax.set_title(title, fontsize=10)
    rate = "" if speed == 1 else f" (x{speed:.3g} speed)"

    def update(k):
        Rs, org, coms = body.link_poses(X[k])
        polys, colors = [], []
        for j, (i, half, V) in enumerate(boxes):
            p, n = _box_polys(coms[i], Rs[i] @ V, half)
            polys += p
            colors += _shade(_COLORS[j % len(_COLORS)], n)
        pc.set_verts(polys)
        pc.set_facecolor(colors)
        if joints:
            dots.set_data_3d(org[joints, 0], org[joints, 1], org[joints, 2])
        r = body.links.root
        for line, axis in zip(root_axes, Rs[r].T):
            end = org[r] + 0.45 * scale * axis
            line.set_data_3d([org[r][0], end[0]], [org[r][1], end[1]], [org[r][2], end[2]])

    update(0)
    return write_frames(fig, (pc, dots, *root_axes), update, frames, path, fps=fps, mp4_path=mp4_path,
                        caption=lambda k: _title(body, t[k]) + rate, caption_at=(0.03, 0.03), caption_size=9)
