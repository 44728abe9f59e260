"""Drawings of planar bodies: a strobe of a planned motion (:func:`strobe`, saved by :func:`save_strobe`),
an animation (:func:`animate`: an animated GIF, blitted by :mod:`acroplan.core.animation`, headless), and the
link table's conventions (:func:`conventions_figure`).

Every link is drawn as in :func:`link_segments` (from its joint to each child's joint; a leaf on
through its centre of mass to as far again), the root thicker with its frame origin marked by a
square, the other joints by circles, and :math:`\\theta` by a short red arrow along the root frame's
:math:`x` axis; the picture is in the centre-of-mass frame (the centre of mass at the origin,
marked +).

The figures in ``docs/images/planar-*.png`` are made by ``python tests/test_planar_planning.py
docs/images`` (it plans the bundled examples; a family module may not call the front door).

Figures are built on an explicit :class:`matplotlib.figure.Figure` with the Agg canvas, so no global
backend or pyplot state is touched.
"""

from __future__ import annotations

import numpy as np

from ...core.animation import auto_speed, states_at, states_evenly, write_frames

__all__ = ["strobe", "save_strobe", "animate", "link_segments", "head_of", "scale_bar", "conventions_figure",
           "MAX_FRAMES"]

#: Link colours (no red: red is theta's arrow); the root is C0.
PALETTE = ("C1", "C2", "C4", "C5", "C6", "C8", "C9")
#: A link named so carries the head, drawn beyond its far end (module docstring).
_TRUNKS = ("trunk", "torso")

#: Frame cap: a longer motion is played faster, with a warning, rather than filling the disk.
MAX_FRAMES = 1500


def link_segments(body, state) -> list[tuple[np.ndarray, np.ndarray, int]]:
    """The line segments that draw each link at ``state`` (centre-of-mass frame).

    A link is drawn from its joint (the root: its frame origin) to each child's joint, and to its
    centre of mass and on as far again when it is a leaf (a uniform rod's far end).

    Returns
    -------
    list of (start, end, link index)
    """
    L = body.links
    J = body.joint_positions(state)
    F = body.link_frames(state)
    out = []
    for i in range(len(L)):
        kids = L.children(i)
        for k in kids:
            out.append((J[i], J[k], i))
        if not kids or i == L.root:
            out.append((J[i], J[i] + 2.0 * (F[i, :2] - J[i]), i))
    return out


def head_of(body, state):
    """The head of a human-like body at ``state``: ``(centre (2,), radius)``, or ``None``.

    A link whose name contains ``trunk`` or ``torso`` carries the head: a disc of radius 0.2 d
    (d: the distance from the link's joint to its farthest child joint, the shoulders; a diver's
    0.52 m trunk gets a 0.10 m head) touching the far end, along the same line."""
    L = body.links
    trunk = next((i for i in range(len(L)) if any(w in L[i].name.lower() for w in _TRUNKS)), None)
    if trunk is None:
        return None
    J = body.joint_positions(state)
    kids = L.children(trunk)
    if not kids:
        return None
    far = max(kids, key=lambda k: float(np.hypot(*(J[k] - J[trunk]))))
    v = J[far] - J[trunk]
    d = float(np.hypot(*v))
    if d == 0:
        return None
    r = 0.2 * d
    return J[far] + (r / d) * v, r


def link_colour(body, i: int) -> str:
    """Link ``i``'s colour in the drawings (the root C0)."""
    return "C0" if i == body.links.root else PALETTE[i % len(PALETTE)]


def scale_bar(ax, ext: float, *, at=(0.03, 0.05)) -> float:
    """A scale bar in the lower left of ``ax`` (data in metres): a round length near 0.4 ``ext``,
    labelled; returns its length."""
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

    raw = 0.4 * ext
    k = 10.0 ** np.floor(np.log10(raw))
    length = max(m * k for m in (1, 2, 5) if m * k <= raw)
    label = f"{length * 100:g} cm" if length < 1 else f"{length:g} m"
    ax.add_artist(AnchoredSizeBar(ax.transData, length, label, "lower left", pad=0.3, borderpad=0.5, sep=3,
                                  frameon=False, size_vertical=0.01 * ext, fontproperties={"size": 8}))
    return length


def strobe(result, *, poses: int = 7, ax=None, spacing: float | None = None, title: str | None = None,
           samples=None):
    """A strobe of a planned motion: the body at ``poses`` equally spaced times, side by side.

    The root link is drawn thicker, its frame origin marked with a square; joints are circles; a
    short arrow on the root shows :math:`\\theta` (the root frame's x axis). Poses are shifted to the
    right in time order and darken with time.

    Parameters
    ----------
    result : PlanResult
        A plan of a :class:`~acroplan.families.planar.model.PlanarBody`.
    poses : int
    ax : matplotlib.axes.Axes, optional
        Drawn into when given; otherwise a new figure (Agg canvas) is made.
    spacing : float, optional
        Horizontal shift between poses (default: 1.1 times the body's largest extent).
    title : str, optional
    samples : (t, X), optional
        Sampled states to draw from (:func:`~acroplan.core.animation.states_at`).

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Circle

    body = result.system
    t, S = states_evenly(result, poses, samples)
    segs = [link_segments(body, S[:, k]) for k in range(poses)]
    ext = max(float(np.max(np.abs(np.array([p for s in sg for p in s[:2]])))) for sg in segs)
    spacing = 2.3 * ext if spacing is None else spacing
    if ax is None:
        fig = Figure(figsize=(min(2.0 + 1.6 * poses, 16), 3.4), dpi=110)
        FigureCanvasAgg(fig)
        ax = fig.add_subplot(1, 1, 1)
    else:
        fig = ax.figure
    root = body.links.root
    for k in range(poses):
        shade = 0.75 - 0.65 * k / max(poses - 1, 1)
        colour = (shade, shade, min(1.0, shade + 0.25))
        dx = np.array([k * spacing, 0.0])
        alpha = 0.35 + 0.65 * k / max(poses - 1, 1)
        for a, b, i in segs[k]:
            ax.plot([a[0] + dx[0], b[0] + dx[0]], [a[1], b[1]], "-", color=link_colour(body, i), alpha=alpha,
                    lw=5 if i == root else 3, solid_capstyle="round", label=body.links[i].name if k == 0 else None)
        head = head_of(body, S[:, k])
        if head is not None:
            ax.add_patch(Circle(tuple(head[0] + dx), head[1], color=link_colour(body, root), alpha=alpha))
        J = body.joint_positions(S[:, k]) + dx
        joints = [i for i in range(len(body.links)) if i != root]
        ax.plot(J[joints, 0], J[joints, 1], "o", ms=5, mfc="white", mec=colour, mew=1.5)
        ax.plot(J[root, 0], J[root, 1], "s", ms=6, color=colour)
        th = S[0, k]
        ax.annotate("", xy=(J[root, 0] + 0.35 * ext * np.cos(th), J[root, 1] + 0.35 * ext * np.sin(th)),
                    xytext=(J[root, 0], J[root, 1]), arrowprops=dict(arrowstyle="->", color="tab:red", lw=1.2))
        ax.text(k * spacing, -1.1 * ext, f"t = {t[k]:.3g} s\nθ = {th:.2f} rad", ha="center", va="top", fontsize=8)
    ax.set_aspect("equal")
    ax.set_xlim(-1.2 * ext, (poses - 1) * spacing + 1.2 * ext)
    ax.set_ylim(-1.55 * ext, 1.35 * ext)
    ax.set_xticks([])
    ax.set_yticks([])
    for side in ax.spines.values():
        side.set_visible(False)
    scale_bar(ax, ext)
    handles, labels = ax.get_legend_handles_labels()
    uniq = dict(zip(labels, handles))  # (each link once)
    key = ax.legend(uniq.values(), uniq.keys(), loc="upper left", fontsize=7, ncols=min(len(uniq), 6),
                    frameon=False, bbox_to_anchor=(0.0, 1.02))
    for handle in key.legend_handles:
        handle.set_alpha(1.0)  # (the key in full colour; the first pose is drawn faded)
    if title:
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    return fig


def save_strobe(result, path, **kwargs) -> None:
    """:func:`strobe` saved as an image (format from the file name)."""
    fig = strobe(result, **kwargs)
    fig.savefig(str(path))


def _frame_times(t0: float, t1: float, speed: float, fps: int, max_frames: int) -> np.ndarray:
    import warnings

    n = max(2, int(round((t1 - t0) / speed * fps)) + 1)
    if n > max_frames:
        warnings.warn(f"a {t1 - t0:g} s motion at speed {speed:g} needs {n} frames; capped at {max_frames} "
                      f"(played {n / max_frames:.3g} times faster)", stacklevel=3)
        n = max_frames
    return np.linspace(t0, t1, n)


def animate(result, path, *, speed: float | None = None, fps: int = 25, max_frames: int = MAX_FRAMES,
            mp4_path=None, samples=None) -> int:
    """Write an animated GIF (and an MP4 when ffmpeg is on the PATH) of a planar body's motion.

    The states at the frame times come from the result itself (:meth:`PlanResult.evaluate
    <acroplan.core.result.PlanResult.evaluate>`: exact, not interpolated between samples). Every
    link is drawn (:func:`link_segments`), the root thicker with a square at its frame origin,
    the joints as circles, :math:`\\theta` as a red arrow on the root; the time, :math:`\\theta` and the
    joint angles are written in a corner.

    Parameters
    ----------
    result : PlanResult
        A plan or simulation of a :class:`~acroplan.families.planar.model.PlanarBody`.
    path : path of the GIF
    speed : float, optional
        Playback speed (1 = real time), > 0; default: real time, or slower for a motion shorter than
        3 s (:func:`~acroplan.core.animation.auto_speed`).
    fps : int
        Frames per second.
    max_frames : int
        A motion needing more frames is played faster (a warning says so).
    mp4_path : path, optional
    samples : (t, X), optional
        Sampled states to draw from (:func:`~acroplan.core.animation.states_at`).

    Returns
    -------
    int
        The number of frames.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    body = result.system
    L = body.links
    speed = auto_speed(float(result.times[-1] - result.times[0]), speed)
    tf = _frame_times(float(result.times[0]), float(result.times[-1]), speed, fps, max_frames)
    S = states_at(result, tf, samples)
    frames = [link_segments(body, S[:, k]) for k in range(tf.size)]
    joints_at = [body.joint_positions(S[:, k]) for k in range(tf.size)]
    ext = 1.1 * max(float(np.max(np.abs(np.array([p for sg in frames for s in sg for p in s[:2]])))), 1e-9)
    ext *= 1.12 if any(w in link.name.lower() for link in L for w in _TRUNKS) else 1.0  # (room for the head)
    fig = Figure(figsize=(5.0, 5.0), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_xlim(-ext, ext)
    ax.set_ylim(-ext, ext)
    ax.set_aspect("equal")
    ax.grid(alpha=0.25)
    ax.tick_params(labelsize=9)
    ax.set_xlabel("x [m], centre-of-mass frame", fontsize=10)
    ax.set_ylabel("y [m]", fontsize=10)
    root = L.root
    seen = set()
    lines = []
    for _, _, i in frames[0]:
        lines.append(ax.plot([], [], "-", lw=7 if i == root else 4, solid_capstyle="round", color=link_colour(body, i),
                             label=None if i in seen else L[i].name)[0])
        seen.add(i)
    heads = [head_of(body, S[:, k]) for k in range(tf.size)]
    from matplotlib.patches import Circle

    head = Circle((0.0, 0.0), heads[0][1] if heads[0] else 0.0, color=link_colour(body, root),
                  visible=heads[0] is not None)
    ax.add_patch(head)
    others = [i for i in range(len(L)) if i != root]
    joint_dots, = ax.plot([], [], "o", ms=6, mfc="white", mec="k", mew=1.5, label="joints")
    root_dot, = ax.plot([], [], "s", ms=7, color="k", label=f"root ({L[root].name})")
    arrow, = ax.plot([], [], "-", color="tab:red", lw=1.5, label="theta (root's x axis)", zorder=4)
    ax.plot([0], [0], "+", color="0.4", ms=10)
    names = body.state_names
    ax.legend(loc="lower right", fontsize=8)

    def draw(k):
        for line, (a, b, _) in zip(lines, frames[k]):
            line.set_data([a[0], b[0]], [a[1], b[1]])
        J = joints_at[k]
        joint_dots.set_data(J[others, 0], J[others, 1])
        root_dot.set_data([J[root, 0]], [J[root, 1]])
        th = S[0, k]
        arrow.set_data([J[root, 0], J[root, 0] + 0.3 * ext * np.cos(th)],
                       [J[root, 1], J[root, 1] + 0.3 * ext * np.sin(th)])
        if heads[k] is not None:
            head.center = tuple(heads[k][0])
        return (*lines, head, joint_dots, root_dot, arrow)

    width = max(map(len, names))
    rate = "" if speed == 1 else f"\n(x{speed:.3g} speed)"

    def caption(k):
        return f"t = {tf[k]:8.3f} s\n" + "\n".join(f"{n:>{width}} = {S[i, k]:7.3f} rad" for i, n in enumerate(names)) + rate

    return write_frames(fig, (*lines, head, joint_dots, root_dot, arrow), draw, int(tf.size), path, fps=fps,
                        mp4_path=mp4_path, caption=caption, caption_at=(0.15, 0.045), caption_size=9)


def conventions_figure():
    """The link table's conventions: a parent and a child link, their frames, the child's joint
    position in the parent's frame, the centres of mass in each link's own frame, the joint angle.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.2), dpi=110)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    arrow = dict(arrowstyle="->", lw=1.3)
    # the parent: frame at O, x_p along the link
    O = np.array([0.0, 0.0])
    J = np.array([3.0, 0.6])  # the child's joint, (jx, jy) in the parent's frame (parent frame = world here)
    ax.plot([O[0], J[0] + 0.3], [O[1], 0.0], "-", color="0.6", lw=9, solid_capstyle="round", alpha=0.5)
    ax.annotate("", xy=(4.2, 0), xytext=O, arrowprops=dict(arrow, color="k"))
    ax.annotate("", xy=(0, 2.2), xytext=O, arrowprops=dict(arrow, color="k"))
    ax.text(4.25, -0.05, "$x_p$", va="center")
    ax.text(0.05, 2.25, "$y_p$")
    ax.plot(*O, "s", color="k", ms=7)
    ax.text(-0.15, -0.35, "O: the parent's frame origin\n(its own joint; the root: any point)", fontsize=8,
            va="top")
    cp = np.array([1.3, 0.15])
    ax.plot(*cp, "o", color="tab:blue", ms=6)
    ax.text(cp[0], cp[1] + 0.2, "com = (cx, cy)\nin the parent's frame", fontsize=8, color="tab:blue", ha="center")
    ax.annotate("", xy=J, xytext=O, arrowprops=dict(arrow, color="tab:green", ls="--"))
    ax.text(1.7, 0.65, "joint = (jx, jy): J in the\nparent's frame", fontsize=8, color="tab:green", rotation=11)
    # the child: frame at J turned by q
    q = 0.75
    e = np.array([np.cos(q), np.sin(q)])
    f = np.array([-np.sin(q), np.cos(q)])
    tip = J + 2.6 * e
    ax.plot([J[0], tip[0]], [J[1], tip[1]], "-", color="0.3", lw=9, solid_capstyle="round", alpha=0.5)
    ax.annotate("", xy=J + 3.0 * e, xytext=J, arrowprops=dict(arrow, color="k"))
    ax.annotate("", xy=J + 1.3 * f, xytext=J, arrowprops=dict(arrow, color="k"))
    ax.text(*(J + 3.05 * e), "$x_c$")
    ax.text(*(J + 1.35 * f), "$y_c$")
    ax.plot(*J, "o", ms=8, mfc="white", mec="k", mew=1.5)
    ax.plot([J[0], J[0] + 1.6], [J[1], J[1]], ":", color="k", lw=1)
    th = np.linspace(0, q, 30)
    ax.plot(J[0] + 1.0 * np.cos(th), J[1] + 1.0 * np.sin(th), "-", color="tab:red")
    ax.text(J[0] + 1.1, J[1] + 0.3, "q (joint angle,\ncounter-clockwise)", color="tab:red", fontsize=8)
    cc = J + 1.2 * e + 0.12 * f
    ax.plot(*cc, "o", color="tab:blue", ms=6)
    ax.text(cc[0] - 0.2, cc[1] + 0.15, "com = (cx, cy)\nin the child's frame", fontsize=8, color="tab:blue",
            ha="right")
    ax.text(J[0] + 0.15, J[1] - 0.45, "J: the child's frame origin", fontsize=8)
    ax.text(-0.2, 3.3, "absolute angle of link i:  alpha_i = theta + sum of the joint angles from the root to i;\n"
            "theta = the root's angle to the inertial x axis; u_<joint> = d(joint angle)/dt", fontsize=8)
    ax.set_aspect("equal")
    ax.set_xlim(-0.6, 6.2)
    ax.set_ylim(-1.2, 3.9)
    ax.axis("off")
    fig.tight_layout()
    return fig

