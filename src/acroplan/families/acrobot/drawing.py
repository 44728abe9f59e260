"""Animation and strobe figures of the acrobot, drawn to scale in the centre-of-mass frame.

Geometry (docs/mathematics.md, Model): from the joint, the torso's centre of mass is at :math:`L\\,e(\\theta+\\varphi)`
and the leg's at :math:`l\\,e(\\theta)`, :math:`e(a) = (\\cos a, \\sin a)`. Each link is drawn as a
uniform rod through its centre of mass, from the joint to twice that distance (torso end
:math:`2L\\,e(\\theta+\\varphi)`, leg end :math:`2l\\,e(\\theta)`). The picture's origin is the body's
centre of mass :math:`(m\\,l\\,e(\\theta) + M L\\,e(\\theta+\\varphi))/(m+M)` from the joint.

A body known only by its lumped parameters is drawn with a representative geometry: equal masses
(:math:`\\mu = 1/2`) and :math:`L = l = \\sqrt{|A_1|}`, so that :math:`A_1 = -2\\mu L l` holds.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from ...core.animation import auto_speed, write_frames

__all__ = ["Geometry", "geometry_of", "pose", "animate", "animate_result", "strobe", "MAX_FRAMES"]

#: Frame cap: a longer motion is played faster, with a warning, rather than filling the disk.
MAX_FRAMES = 1500


@dataclasses.dataclass(frozen=True)
class Geometry:
    """Masses and centre-of-mass distances used for drawing."""

    torso_mass: float
    leg_mass: float
    torso_length: float
    leg_length: float
    representative: bool = False


def geometry_of(system_dict: dict) -> Geometry:
    """The drawing geometry from a result's ``system`` entry (``solution.json``)."""
    phys = system_dict.get("physical")
    if phys:
        return Geometry(phys["torso_mass"], phys["leg_mass"], phys["torso_length"], phys["leg_length"])
    A1 = float(system_dict["params"]["A1"])
    L = math.sqrt(abs(A1)) if A1 != 0 else 1.0
    return Geometry(1.0, 1.0, L, L, representative=True)


def pose(theta, phi, g: Geometry):
    """Points of the body in the centre-of-mass frame.

    Parameters
    ----------
    theta, phi : array_like, shape (N,)

    Returns
    -------
    dict of numpy.ndarray, each shape (N, 2)
        ``joint``, ``torso_end``, ``leg_end``, ``torso_cm``, ``leg_cm``, ``head`` (the head's centre,
        beyond the torso's end).
    """
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    e_leg = np.stack([np.cos(theta), np.sin(theta)], axis=1)
    e_torso = np.stack([np.cos(theta + phi), np.sin(theta + phi)], axis=1)
    M, m = g.torso_mass, g.leg_mass
    cm = (m * g.leg_length * e_leg + M * g.torso_length * e_torso) / (m + M)
    joint = -cm
    head = 0.22 * g.torso_length
    return {"joint": joint, "torso_cm": joint + g.torso_length * e_torso, "leg_cm": joint + g.leg_length * e_leg,
            "torso_end": joint + 2 * g.torso_length * e_torso, "leg_end": joint + 2 * g.leg_length * e_leg,
            "head": joint + (2 * g.torso_length + head) * e_torso}


def head_radius(g: Geometry) -> float:
    """Radius of the head drawn on the torso's end (so a reader tells the torso from the legs)."""
    return 0.22 * g.torso_length


def _frames(t, speed, fps, max_frames):
    duration = (t[-1] - t[0]) / speed
    n = max(2, int(round(duration * fps)) + 1)
    if n > max_frames:
        warnings.warn(f"a {t[-1] - t[0]:g} s motion at speed {speed:g} needs {n} frames; capped at {max_frames} "
                      f"(played {n / max_frames:.3g} times faster)", stacklevel=3)
        n = max_frames
    return np.linspace(t[0], t[-1], n)


def animate(t, theta, phi, u, g: Geometry, path, *, speed: float | None = None, fps: int = 25, trail: float = 1.0,
            max_frames: int = MAX_FRAMES, mp4_path=None):
    """Write an animated GIF (and an MP4 when ffmpeg is present) of the motion.

    Parameters
    ----------
    t, theta, phi, u : array_like, shape (N,)
        The sampled motion (``trajectory.csv``), t increasing.
    g : Geometry
    path : path of the GIF
    speed : float, optional
        Playback speed (1 = real time; default: real time, or slower for a motion shorter than 3 s,
        :func:`~acroplan.core.animation.auto_speed`).
    fps : int
    trail : float
        Seconds of fading trail behind the link ends.
    mp4_path : path, optional
        Also write an MP4 there if ffmpeg is on the PATH.

    Returns
    -------
    int
        The number of frames.
    """
    import matplotlib
    import matplotlib.patches
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    t = np.asarray(t, dtype=float)
    speed = auto_speed(t[-1] - t[0], speed)
    tf = _frames(t, speed, fps, max_frames)
    th = np.interp(tf, t, theta)
    ph = np.interp(tf, t, phi)
    uf = np.interp(tf, t, u)
    P = pose(th, ph, g)
    rh = head_radius(g)
    reach = 1.12 * max(float(np.max(np.hypot(*P[k].T))) + (rh if k == "head" else 0.0)
                       for k in ("joint", "head", "leg_end"))
    # a figure of its own canvas (Agg), outside pyplot: the user's backend is never touched
    fig = Figure(figsize=(5.0, 5.0), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_xlim(-reach, reach)
    ax.set_ylim(-reach, reach)
    ax.set_aspect("equal")
    ax.grid(alpha=0.25)
    ax.tick_params(labelsize=9)
    ax.set_xlabel("x [m], centre-of-mass frame" if not g.representative else "x (representative geometry)",
                  fontsize=10)
    ax.set_ylabel("y [m]" if not g.representative else "y", fontsize=10)
    torso, = ax.plot([], [], lw=8, solid_capstyle="round", color="C0", label="torso and head")
    leg, = ax.plot([], [], lw=5, solid_capstyle="round", color="C1", label="legs")
    head = matplotlib.patches.Circle((0, 0), rh, color="C0")
    ax.add_patch(head)
    joint, = ax.plot([], [], "o", color="k", ms=6, label="hip (joint)")
    ax.plot([0], [0], "+", color="0.4", ms=10)
    tr_t = ax.scatter([], [], s=6, color="C0")
    tr_l = ax.scatter([], [], s=6, color="C1")
    ax.legend(loc="lower right", fontsize=9)
    n_trail = max(1, int(round(trail * fps / speed)))

    def draw(i):
        j = P["joint"][i]
        torso.set_data([j[0], P["torso_end"][i, 0]], [j[1], P["torso_end"][i, 1]])
        leg.set_data([j[0], P["leg_end"][i, 0]], [j[1], P["leg_end"][i, 1]])
        joint.set_data([j[0]], [j[1]])
        head.center = tuple(P["head"][i])
        lo = max(0, i - n_trail)
        alpha = np.linspace(0.05, 0.6, i + 1 - lo)
        for sc, key, c in ((tr_t, "torso_end", "C0"), (tr_l, "leg_end", "C1")):
            sc.set_offsets(P[key][lo:i + 1])
            rgba = np.tile(matplotlib.colors.to_rgba(c), (i + 1 - lo, 1))
            rgba[:, 3] = alpha
            sc.set_facecolors(rgba)
            sc.set_edgecolors("none")
        return torso, leg, joint, head, tr_t, tr_l

    rate = "" if speed == 1 else f"\n(x{speed:.3g} speed)"

    def caption(i):
        return f"t = {tf[i]:7.3f} s\nθ = {th[i]:7.3f} rad\nφ = {ph[i]:7.3f} rad\nu = {uf[i]:7.3f} rad/s" + rate

    return write_frames(fig, (torso, leg, joint, head, tr_t, tr_l), draw, len(tf), path, fps=fps,
                        mp4_path=mp4_path, caption=caption, caption_at=(0.15, 0.045), caption_size=10)


def animate_result(result, path, *, speed: float | None = None, fps: int = 25, trail: float = 1.0,
                   max_frames: int = MAX_FRAMES, mp4_path=None) -> int:
    """:func:`animate` of a plan of the acrobot (the family's ``animate`` hook, behind
    :meth:`PlanResult.animate <acroplan.core.result.PlanResult.animate>`): the states at the frame
    times exactly, from the result (:meth:`~acroplan.core.result.PlanResult.evaluate`)."""
    t0, t1 = float(result.times[0]), float(result.times[-1])
    s = auto_speed(t1 - t0, speed)
    tf = _frames(np.array([t0, t1]), s, fps, max_frames)
    ev = result.evaluate(tf, effort=False)
    return animate(tf, ev.theta, ev.phi, ev.u, geometry_of(result.system.to_dict()), path, speed=s, fps=fps,
                   trail=trail, max_frames=max_frames, mp4_path=mp4_path)


def strobe(t, theta, phi, g: Geometry, *, poses: int = 9, ax=None):
    """A single image of several poses overlaid, later poses darker, as in diving photography.

    The body drifts along x in the picture (one body length per pose) so that poses do not hide
    each other; the centre of mass moves in a straight line, as for a body in free flight seen in a
    frame moving with its horizontal speed.
    """
    import matplotlib.patches
    import matplotlib.pyplot as plt

    ts = np.linspace(t[0], t[-1], poses)
    P = pose(np.interp(ts, t, theta), np.interp(ts, t, phi), g)
    rh = head_radius(g)
    step = 2.2 * max(g.torso_length + rh, g.leg_length)
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(1.25 * poses + 1, 3.6), constrained_layout=True)
    for k in range(poses):
        dx = np.array([k * step, 0.0])
        a = 0.45 + 0.55 * k / max(poses - 1, 1)
        j = P["joint"][k] + dx
        ax.plot([j[0], P["torso_end"][k, 0] + dx[0]], [j[1], P["torso_end"][k, 1]], lw=6, color="C0", alpha=a,
                solid_capstyle="round", label="torso and head" if k == 0 else None)
        ax.add_patch(matplotlib.patches.Circle(tuple(P["head"][k] + dx), rh, color="C0", alpha=a))
        ax.plot([j[0], P["leg_end"][k, 0] + dx[0]], [j[1], P["leg_end"][k, 1]], lw=3.5, color="C1", alpha=a,
                solid_capstyle="round", label="legs" if k == 0 else None)
        ax.plot([j[0]], [j[1]], "o", color="k", ms=3.5, alpha=a)
        ax.text(dx[0], -1.15 * step, f"t = {ts[k]:.3g} s", ha="center", fontsize=9, color="0.25")
    if not g.representative:  # a scale bar instead of axes
        x0, y0 = -0.5 * step, 1.05 * step
        ax.plot([x0, x0 + 0.5], [y0, y0], color="0.3", lw=2)
        ax.text(x0 + 0.25, y0 + 0.05 * step, "0.5 m", ha="center", va="bottom", fontsize=9, color="0.3")
    ax.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), fontsize=9, frameon=False, ncols=2)
    ax.set_aspect("equal")
    ax.axis("off")
    return ax.figure if own else ax
