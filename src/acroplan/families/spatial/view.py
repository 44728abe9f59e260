"""An interactive 3-D view of a spatial body's motion in the browser: one self-contained HTML page
(plotly, its JavaScript inline: it opens without a network), written by :func:`write_view`
(:meth:`PlanResult.view <acroplan.core.result.PlanResult.view>`, ``acroplan view DIR``).

The page: on the left the body as shaded solids (:mod:`~acroplan.families.spatial.solids`: a 3-D
human's Yeadon solids, any other link's equivalent box), the root's axes (x red, y green, z blue)
and the angular momentum vector (black, from the centre of mass; its size in the legend), which the
mouse turns and zooms; on the right the attitude as Yeadon's somersault, tilt and twist and the
joint angles over the whole motion, in degrees, with the present time marked. Play and pause
buttons and a time slider move the body and the marks together. The picture is in the
centre-of-mass frame.
"""

from __future__ import annotations

import numpy as np

from . import rotations as rot
from .solids import posed, solids_of

__all__ = ["figure", "write_view", "FRAMES"]

#: Frames of the view by default (the page holds every frame's vertices).
FRAMES = 120
_AXES = ("#d62728", "#2ca02c", "#1f77b4")
#: plotly.js rejects the promise of an animation that a newer one interrupts (the pause button, a
#: slider step while playing) with no reason, and nothing catches it: the browser logs "Uncaught (in
#: promise)". Those rejections (and only those: no reason) are marked handled.
QUIET_PAUSE = ("window.addEventListener('unhandledrejection', function (e) {"
               " if (e.reason === undefined) { e.preventDefault(); } });")


def _groups(solids):
    """The solids by link, in link order: ``[(link, [solid, ...]), ...]`` (one mesh trace each, one
    entry of the key)."""
    out: dict[int, list] = {}
    for s in solids:
        out.setdefault(s.link, []).append(s)
    return sorted(out.items())


def _meshes(body, groups, state):
    """Per link: one Mesh3d's arrays for its solids at ``state``: ``(V (n, 3), F (f, 3))``."""
    out = []
    for _, solids in groups:
        verts = posed(body, state, solids)
        offsets = np.cumsum([0] + [v.shape[0] for v in verts[:-1]])
        # float32 (0.1 mm at 1 km) and int32: the page's frames are half the size of float64's
        out.append((np.vstack(verts).astype(np.float32),
                    np.vstack([s.faces + o for s, o in zip(solids, offsets)]).astype(np.int32)))
    return out


def _root_axes(body, state, scale):
    Rs, org, _ = body.link_poses(state)
    r = body.links.root
    return [(org[r], org[r] + 0.75 * scale * Rs[r][:, k]) for k in range(3)]


def figure(result, *, frames: int = FRAMES, samples=None, title: str | None = None, name: str | None = None):
    """The view's :class:`plotly.graph_objects.Figure` (module docstring).

    Parameters
    ----------
    result : PlanResult
        Of a :class:`~acroplan.families.spatial.model.SpatialBody`.
    frames : int
        Frames of the animation (evenly spaced in time).
    samples : (t, X), optional
        Sampled states to draw from (:func:`~acroplan.core.animation.states_at`).
    title : str, optional
        Default: the body's links and :math:`|L|`, after ``name`` (an output folder's).
    name : str, optional
    """
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    from ...core.animation import states_at, states_evenly

    body = result.system
    title = title or ((f"{name}: " if name else "") + _title(body))
    t, X = states_evenly(result, max(2, int(frames)), samples, unit_rows=4)
    dense_t = np.linspace(t[0], t[-1], 400)
    D = states_at(result, dense_t, samples, unit_rows=4)
    euler = np.degrees(np.unwrap(np.radians(rot.to_euler(D[:4], "yeadon")), axis=1))
    joints = np.degrees(D[4:])
    groups = _groups(solids_of(body))
    scale = max(float(max(np.max(np.abs(V)) for k in range(0, t.size, max(1, t.size // 12))
                          for V, _ in _meshes(body, groups, X[:, k]))), 1e-6)

    fig = make_subplots(rows=2, cols=2, column_widths=[0.56, 0.44], horizontal_spacing=0.07, vertical_spacing=0.14,
                        specs=[[{"type": "scene", "rowspan": 2}, {"type": "xy"}], [None, {"type": "xy"}]],
                        subplot_titles=("", "attitude (Yeadon's angles) [deg]", "joint angles [deg]"))
    moving = []  # the meshes and the root's axes, then the time marks
    for (link, solids), (V, F) in zip(groups, _meshes(body, groups, X[:, 0])):
        moving.append(len(fig.data))
        fig.add_trace(go.Mesh3d(x=V[:, 0], y=V[:, 1], z=V[:, 2], i=F[:, 0], j=F[:, 1], k=F[:, 2],
                                color=solids[0].color, flatshading=True, name=body.links.links[link].name,
                                lighting=dict(ambient=0.45, diffuse=0.8, specular=0.15, roughness=0.6),
                                lightposition=dict(x=1000, y=-1500, z=2500), hoverinfo="name", showscale=False,
                                showlegend=True, legend="legend3"), row=1, col=1)
    for (a, b), c, name in zip(_root_axes(body, X[:, 0], scale), _AXES, ("root x", "root y", "root z")):
        moving.append(len(fig.data))
        fig.add_trace(go.Scatter3d(x=[a[0], b[0]], y=[a[1], b[1]], z=[a[2], b[2]], mode="lines", name=name,
                                   line=dict(color=c, width=6), hoverinfo="skip", legend="legend3"), row=1, col=1)
    L = np.asarray(body.angular_momentum, dtype=float)
    nL = float(np.linalg.norm(L))
    if nL > 0:
        tip = 0.9 * scale * L / nL
        fig.add_trace(go.Scatter3d(x=[0, tip[0]], y=[0, tip[1]], z=[0, tip[2]], mode="lines",
                                   name=f"angular momentum, |L| = {nL:.3g} kg m²/s", line=dict(color="black", width=7),
                                   legend="legend3"), row=1, col=1)
        fig.add_trace(go.Cone(x=[tip[0]], y=[tip[1]], z=[tip[2]], u=[tip[0]], v=[tip[1]], w=[tip[2]], sizemode="absolute",
                              sizeref=0.12 * scale, anchor="tail", showscale=False, colorscale=[[0, "black"], [1, "black"]],
                              hoverinfo="skip", name="L", showlegend=False), row=1, col=1)
    for k, name in enumerate(rot.EULER_NAMES):
        fig.add_trace(go.Scatter(x=dense_t, y=euler[k], mode="lines", name=name, legend="legend"), row=1, col=2)
    for j, name in enumerate(body.links.joint_names):
        fig.add_trace(go.Scatter(x=dense_t, y=joints[j], mode="lines", name=name, legend="legend2"), row=2, col=2)
    lo_a, hi_a = float(euler.min()), float(euler.max())
    lo_j, hi_j = (float(joints.min()), float(joints.max())) if joints.size else (-1.0, 1.0)
    for row, (lo, hi) in ((1, (lo_a, hi_a)), (2, (lo_j, hi_j))):
        moving.append(len(fig.data))
        fig.add_trace(go.Scatter(x=[t[0], t[0]], y=[lo, hi], mode="lines", line=dict(color="#444", dash="dot", width=1.5), showlegend=False, hoverinfo="skip"), row=row, col=2)

    fig.frames = [go.Frame(name=f"{t[k]:.4f}", traces=moving, data=_frame_data(body, groups, X[:, k], scale, t[k],
                                                                                (lo_a, hi_a), (lo_j, hi_j)))
                  for k in range(t.size)]
    _layout(fig, t, scale, title)
    return fig


def _frame_data(body, groups, state, scale, tk, att, jnt):
    import plotly.graph_objects as go

    data = [go.Mesh3d(x=V[:, 0], y=V[:, 1], z=V[:, 2]) for V, _ in _meshes(body, groups, state)]
    for a, b in _root_axes(body, state, scale):
        data.append(go.Scatter3d(x=[a[0], b[0]], y=[a[1], b[1]], z=[a[2], b[2]]))
    data += [go.Scatter(x=[tk, tk], y=list(att)), go.Scatter(x=[tk, tk], y=list(jnt))]
    return data


def _layout(fig, t, scale, title):
    delay = max(20, int(1000 * (t[-1] - t[0]) / max(t.size - 1, 1) / _speed(t[-1] - t[0])))
    play = dict(label="▶ play", method="animate",
                args=[None, dict(frame=dict(duration=delay, redraw=True), fromcurrent=True, transition=dict(duration=0))])
    pause = dict(label="❚❚ pause", method="animate",
                 args=[[None], dict(frame=dict(duration=0, redraw=False), mode="immediate", transition=dict(duration=0))])
    steps = [dict(method="animate", label=f"{tk:.2f}",
                  args=[[f"{tk:.4f}"], dict(mode="immediate", frame=dict(duration=0, redraw=True),
                                           transition=dict(duration=0))]) for tk in t]
    r = 1.05 * scale
    axis = dict(range=[-r, r], title=dict(text=""), showbackground=True, backgroundcolor="rgb(245,245,245)")
    fig.update_layout(
        title=dict(text=title, x=0.02, y=0.98, font=dict(size=15)), height=660, width=1180, template="plotly_white",
        margin=dict(l=10, r=150, t=60, b=10),
        legend=dict(x=1.01, y=1.0, yanchor="top", font=dict(size=11), title=dict(text="attitude")),
        legend2=dict(x=1.01, y=0.43, yanchor="top", font=dict(size=11), title=dict(text="joints")),
        legend3=dict(x=0.0, y=1.0, yanchor="top", font=dict(size=10), bgcolor="rgba(255,255,255,0.6)",
                     title=dict(text="key")),
        scene=dict(xaxis={**axis, "title": dict(text="x [m]")}, yaxis={**axis, "title": dict(text="y [m]")},
                   zaxis={**axis, "title": dict(text="z [m]")}, aspectmode="cube",
                   domain=dict(x=[0.12, 0.57], y=[0.04, 1.0]),
                   camera=dict(eye=dict(x=1.45, y=-1.45, z=0.85))),
        updatemenus=[dict(type="buttons", direction="left", x=0.0, y=0.0, xanchor="left", yanchor="top",
                          pad=dict(t=10, r=10), showactive=False, buttons=[play, pause])],
        sliders=[dict(active=0, x=0.16, y=0.0, len=0.40, xanchor="left", yanchor="top", pad=dict(t=10),
                      currentvalue=dict(prefix="t = ", suffix=" s", font=dict(size=13)), steps=steps)])
    fig.update_xaxes(title_text="t [s]", row=2, col=2)
    fig.update_xaxes(title_text="", row=1, col=2)


def _speed(duration: float) -> float:
    from ...core.animation import auto_speed

    return auto_speed(duration)


def _title(body):
    nL = float(np.linalg.norm(body.angular_momentum))
    return (f"a spatial body of {body.n_links} links, " + ("L = 0" if nL == 0 else f"|L| = {nL:.3g} kg m²/s")
            + " (drag to turn, scroll to zoom)")


def write_view(result, path, **kwargs):
    """Write the view (:func:`figure`) to ``path`` as one self-contained HTML page (plotly's
    JavaScript inline), whole or not at all (a temporary file beside it, then renamed); returns the
    path."""
    import os
    from pathlib import Path

    fig = figure(result, **kwargs)
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        fig.write_html(str(tmp), include_plotlyjs=True, full_html=True, auto_play=False, post_script=QUIET_PAUSE,
                       config=dict(displaylogo=False, responsive=True))
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)
    return path
