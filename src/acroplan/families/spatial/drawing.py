"""Drawings of spatial bodies (matplotlib 3-D, headless): an animation (:func:`animate`, an animated
GIF blitted by :mod:`acroplan.core.animation`), a strobe (:func:`strobe`), and the attitude as Euler angles
over time (:func:`attitude_figure`).

Every link is drawn with its solids (:mod:`~acroplan.families.spatial.solids`): a 3-D human's
Yeadon solids (stadium solids and semi-ellipsoids), any other link with mass as its **equivalent
box**, the uniform box with the link's mass and principal moments, :math:`a_i = \\sqrt{6 (I_j + I_k
- I_i)/m}`, centred at its centre of mass along its principal axes (a rod is a long thin box, a
trunk a tall one); faces shaded by a fixed light (Lambert: :math:`0.35 + 0.65 \\max(0, n \\cdot
\\ell)`), one colour per link, named in the key; joints are dots; axes in metres. The root's frame is drawn as
three arrows (:math:`x` red, :math:`y` green, :math:`z` blue) and the angular momentum vector
:math:`L` as a black arrow from the centre of mass (scaled to the body's size; the title gives
:math:`|L|`). The picture is in the centre-of-mass frame (the centre of mass at the origin).

Figures are built on an explicit :class:`matplotlib.figure.Figure` with the Agg canvas: no global
backend or pyplot state is touched.
"""

from __future__ import annotations

import math

import numpy as np

from ...core.animation import auto_speed, states_evenly, write_frames
from . import rotations as rot
from .solids import equivalent_boxes, posed, shade, solids_of

__all__ = ["equivalent_boxes", "key_handles", "draw_body", "strobe", "save_strobe", "attitude_figure", "animate", "MAX_FRAMES"]

#: Frame cap of an animation.
MAX_FRAMES = 600
_AXES = ("#d62728", "#2ca02c", "#1f77b4")


def _triangles(body, state, solids, offset=(0.0, 0.0, 0.0)):
    """Every solid's triangles at ``state`` (shape (F, 3, 3), centre-of-mass frame plus ``offset``)
    and their shaded colours (F, 3)."""
    tris, cols = [], []
    off = np.asarray(offset, dtype=float)
    for sol, V in zip(solids, posed(body, state, solids)):
        V = V + off
        tris.append(V[sol.faces])
        cols.append(shade(sol.color, V, sol.faces))
    if not tris:
        return np.zeros((0, 3, 3)), np.zeros((0, 3))
    return np.concatenate(tris), np.concatenate(cols)


def _size(body, states, solids=None) -> float:
    """The half width of a cube about the centre of mass that holds every solid in every state."""
    solids = solids_of(body) if solids is None else solids
    pts = []
    for x in states:
        _, org, coms = body.link_poses(x)
        pts += [org, coms] + posed(body, x, solids)
    return float(np.abs(np.concatenate(pts)).max())


def key_handles(body, solids=None, *, arrows: bool = True):
    """The key of a drawing: one patch per drawn link (its colour and name), the root's axes and
    the angular momentum (matplotlib handles, for ``legend(handles=...)``)."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    solids = solids_of(body) if solids is None else solids
    seen, out = set(), []
    for sol in solids:
        if sol.link not in seen:
            seen.add(sol.link)
            out.append(Patch(facecolor=sol.color, edgecolor="0.3", label=body.links.links[sol.link].name))
    if arrows:
        out += [Line2D([], [], color=c, lw=1.8, label=f"root {a}") for c, a in zip(_AXES, "xyz")]
        if float(np.linalg.norm(body.angular_momentum)) > 0:
            out.append(Line2D([], [], color="k", lw=2.2, label="angular momentum L"))
    return out


def draw_body(ax, body, state, *, scale: float, offset=(0.0, 0.0, 0.0), alpha: float = 1.0, arrows: bool = True,
              solids=None):
    """Draw ``body`` at ``state`` on a 3-D axes (module docstring).

    Parameters
    ----------
    ax : mpl_toolkits.mplot3d.Axes3D
    state : array_like, shape (4 + m,)
    scale : float
        The body's size (arrow lengths).
    offset : (3,)
        Where the centre of mass is drawn.
    solids : list of Solid, optional
        :func:`~acroplan.families.spatial.solids.solids_of` (computed when not given).
    """
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    solids = solids_of(body) if solids is None else solids
    off = np.asarray(offset, dtype=float)
    Rs, org, _ = body.link_poses(state)
    tris, colors = _triangles(body, state, solids, off)
    pc = Poly3DCollection(tris, facecolors=colors, edgecolors="none", alpha=alpha)
    ax.add_collection3d(pc)
    J = org[[i for i in range(len(body.links)) if body.links.parents[i] != -1 and body.links.links[i].mass > 0]] + off
    if len(J):
        ax.scatter(J[:, 0], J[:, 1], J[:, 2], s=6, color="k", alpha=alpha, depthshade=False)
    if arrows:
        r = body.links.root
        o = org[r] + off
        for axis, c in zip(Rs[r].T, _AXES):
            ax.quiver(*o, *(0.6 * scale * axis), color=c, linewidth=1.5, arrow_length_ratio=0.2)
        L = body.angular_momentum
        nL = float(np.linalg.norm(L))
        if nL > 0:
            ax.quiver(*off, *(0.9 * scale * L / nL), color="k", linewidth=2.0, arrow_length_ratio=0.15)
    return ax


def _setup(ax, scale, center=(0.0, 0.0, 0.0), *, small: bool = False):
    """Limits (a cube of half width ``scale``), at most 3 ticks a side, labels in metres; ``small``
    panels (a strobe's) get smaller tick labels, set off from the axes so that none is clipped."""
    from matplotlib.ticker import MaxNLocator

    c = np.asarray(center, dtype=float)
    for setter, v in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), c):
        setter(v - scale, v + scale)
    ax.set_box_aspect((1, 1, 1), zoom=0.82 if small else 0.92)
    size = 6 if small else 8
    for axis, name in ((ax.xaxis, "x"), (ax.yaxis, "y"), (ax.zaxis, "z")):
        axis.set_major_locator(MaxNLocator(3, symmetric=True))
        axis.set_label_text(f"{name} [m]", fontsize=size + 1)
        axis.labelpad = -4 if small else 0
    ax.tick_params(labelsize=size, pad=-2 if small else 0)
    ax.view_init(elev=18, azim=-60)


def _states(result, n: int, samples=None):
    """``n`` equally spaced times of the plan and the states at them, one row a time
    (:func:`~acroplan.core.animation.states_evenly`, the attitude renormalised)."""
    t, X = states_evenly(result, n, samples, unit_rows=4)
    return t, X.T


def _title(body, t=None):
    nL = float(np.linalg.norm(body.angular_momentum))
    head = f"t = {t:.2f} s, " if t is not None else ""
    return head + ("L = 0" if nL == 0 else f"|L| = {nL:.3g} kg m²/s")


def strobe(result, *, poses: int = 6, fig=None, title: str | None = None, samples=None):
    """The body at ``poses`` equally spaced times of a plan, one 3-D panel each.

    Parameters
    ----------
    result : PlanResult
        A plan of a :class:`~acroplan.families.spatial.model.SpatialBody`.
    poses : int
    fig : matplotlib.figure.Figure, optional
        Drawn into when given; otherwise a new figure is made.
    title : str, optional
        Default: the angular momentum.
    samples : (t, X), optional
        Sampled states to draw from (:func:`~acroplan.core.animation.states_at`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    body = result.system
    t, X = _states(result, poses, samples)
    solids = solids_of(body)
    scale = _size(body, X, solids)
    fig = fig or Figure(figsize=(2.6 * poses, 3.5))
    for k in range(poses):
        ax = fig.add_subplot(1, poses, k + 1, projection="3d")
        draw_body(ax, body, X[k], scale=scale, solids=solids)
        _setup(ax, scale, small=True)
        ax.set_title(f"t = {t[k]:.2f} s", fontsize=9)
    fig.suptitle(title or _title(body), fontsize=10)
    handles = key_handles(body, solids)
    fig.legend(handles=handles, loc="lower center", ncols=min(len(handles), 8), fontsize=7, frameon=False)
    fig.subplots_adjust(left=0.01, right=0.99, bottom=0.14, top=0.86, wspace=0.12)
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
    t, X = states_evenly(result, samples)
    E = np.degrees(np.unwrap(np.radians(rot.to_euler(X[:4], seq)), axis=1))
    names = rot.EULER_NAMES if seq.lower() == "yeadon" else tuple(seq)
    fig = fig or Figure(figsize=(8.0, 5.2))
    a1 = fig.add_subplot(2, 1, 1)
    for k in range(3):
        a1.plot(t, E[k], label=names[k])
    a1.set_ylabel("attitude [deg]")
    a1.legend(loc="best", fontsize=8)
    a1.grid(alpha=0.3)
    a2 = fig.add_subplot(2, 1, 2, sharex=a1)
    for j, name in enumerate(body.links.joint_names):
        a2.plot(t, np.degrees(X[4 + j]), label=name)
    for tk in result.times:
        a1.axvline(tk, color="0.8", lw=0.6)
        a2.axvline(tk, color="0.8", lw=0.6)
    a2.set_ylabel("joint angle [deg]")
    a2.set_xlabel("t [s]")
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
        Sampled states to draw from (:func:`~acroplan.core.animation.states_at`).

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
    t, X = _states(result, frames, samples)
    solids = solids_of(body)
    scale = _size(body, X, solids)
    fig = Figure(figsize=(5.6, 5.6), dpi=dpi)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1, projection="3d")
    _setup(ax, scale)
    # the still parts (axes, the angular momentum's arrow, the key) drawn once; the body's solids,
    # joints, the root's axes and the caption move (acroplan.core.animation)
    tris, colors = _triangles(body, X[0], solids)
    pc = Poly3DCollection(tris, facecolors=colors, edgecolors="none")
    ax.add_collection3d(pc)
    joints = [i for i in range(len(body.links)) if body.links.parents[i] != -1 and body.links.links[i].mass > 0]
    dots, = ax.plot([], [], [], "o", ms=3, color="k", linestyle="none")
    root_axes = [ax.plot([], [], [], color=c, lw=1.5)[0] for c in _AXES]
    L = body.angular_momentum
    nL = float(np.linalg.norm(L))
    if nL > 0:
        ax.quiver(0, 0, 0, *(0.9 * scale * L / nL), color="k", linewidth=2.0, arrow_length_ratio=0.15)
    handles = key_handles(body, solids)
    ax.legend(handles=handles, loc="upper left", fontsize=7, frameon=False, ncols=1 if len(handles) < 9 else 2)
    if title:
        ax.set_title(title, fontsize=10)
    rate = "" if speed == 1 else f" (x{speed:.3g} speed)"

    def update(k):
        Rs, org, _ = body.link_poses(X[k])
        tris, colors = _triangles(body, X[k], solids)
        pc.set_verts(tris)
        pc.set_facecolor(colors)
        if joints:
            dots.set_data_3d(org[joints, 0], org[joints, 1], org[joints, 2])
        r = body.links.root
        for line, axis in zip(root_axes, Rs[r].T):
            end = org[r] + 0.6 * scale * axis
            line.set_data_3d([org[r][0], end[0]], [org[r][1], end[1]], [org[r][2], end[2]])

    update(0)
    return write_frames(fig, (pc, dots, *root_axes), update, frames, path, fps=fps, mp4_path=mp4_path,
                        caption=lambda k: _title(body, t[k]) + rate, caption_at=(0.03, 0.03), caption_size=9)
