"""Figures of any plan, kept apart from the numerics. The user's matplotlib backend is never changed
here (the command line chooses Agg for itself).

* :func:`plot_input`: the text's Fig. 1, :math:`u(t)`, with the waypoint times marked;
* :func:`plot_states`: the text's Fig. 2, :math:`\\theta(t)` above :math:`\\varphi(t)`, waypoints marked;
* :func:`plot_continuation`: path-deformation diagnostics;
* :func:`plot_effort`: joint torques and mechanical power (systems with a torque model).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Figures", "save_figure", "plot_input", "plot_states", "plot_result", "plot_continuation", "plot_effort"]


class Figures(dict):
    """Figures by name (``{"input": Figure, "states": Figure, ...}``): what
    :meth:`PlanResult.plot <acroplan.core.result.PlanResult.plot>` returns, always.

    A ``dict`` of :class:`matplotlib.figure.Figure`; as the last expression of a notebook cell it
    shows each figure once (and closes it, so the inline backend does not show it again at the end
    of the cell). :meth:`savefig` writes them all, :meth:`close` closes them.
    """

    def savefig(self, folder, formats=("png",), *, dpi: int = 120) -> list:
        """Write each figure as ``folder/NAME.FORMAT`` (``formats``: a name or a sequence, ``"png"``,
        ``"pdf"``, ``"svg"``); returns the paths written."""
        from pathlib import Path

        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        formats = (formats,) if isinstance(formats, str) else tuple(formats)
        paths = []
        for name, fig in self.items():
            for fmt in formats:
                path = folder / f"{name}.{fmt}"
                save_figure(fig, path, fmt, dpi)
                paths.append(path)
        return paths

    def close(self) -> None:
        """Close every figure (pyplot keeps them until closed)."""
        plt = pyplot()
        for fig in self.values():
            plt.close(fig)

    def _ipython_display_(self):
        from IPython.display import display

        for fig in self.values():
            display(fig)
        self.close()

    def __repr__(self):
        return f"Figures({', '.join(self)})"


def save_figure(fig, path, fmt: str, dpi: int = 120) -> None:
    """``fig.savefig(path, dpi=dpi)``, the same file, with the constrained layout computed once.

    matplotlib's ``savefig`` of a figure with a layout engine draws it twice: once without output
    to lay it out (the layout engine, then every artist again), then for the file. A PNG of an Agg
    figure (the command line's, a notebook's) is laid out here by the engine alone, at the file's
    dpi, and written with the engine set aside for that one draw: the same pixels, the same bytes
    (tests/test_figures.py), a fifth less time. Any other figure or format, or ``savefig.bbox =
    "tight"`` in the rc parameters: ``savefig`` itself."""
    import matplotlib as mpl
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    engine = fig.get_layout_engine()
    if (fmt != "png" or type(engine).__name__ != "ConstrainedLayoutEngine" or type(fig.canvas) is not FigureCanvasAgg
            or getattr(fig, "_layout_engine", None) is not engine or mpl.rcParams["savefig.bbox"] == "tight"):
        fig.savefig(path, dpi=dpi)
        return
    from matplotlib import cbook

    with cbook._setattr_cm(fig, dpi=dpi), cbook._setattr_cm(fig.canvas, _is_saving=True):
        engine.execute(fig)
    fig._layout_engine = None
    try:
        fig.savefig(path, dpi=dpi)
    finally:
        fig._layout_engine = engine


def pyplot():
    """``matplotlib.pyplot``, imported when a figure is made (never at import: the command line
    chooses its backend first)."""
    import matplotlib.pyplot as plt

    return plt


def plot_input(result, samples=None, *, ax=None, degrees: bool = False):
    """Fig. 1 style: the input over time, waypoint times as dashed lines. ``degrees``: the rates of
    angles (inputs in rad/s) in deg/s, their rate limits too. Returns the figure (or, given
    ``ax``, draws there and returns ``ax``)."""
    plt = pyplot()
    samples = samples if samples is not None else result.sample(effort=False)
    own = ax is None
    if own:
        fig, ax = plt.subplots(figsize=(7, 3.6), constrained_layout=True)
    units = {name: _input_unit(result.system, name) for name in samples.input_names}
    to_deg = {name: degrees and unit == "rad/s" for name, unit in units.items()}
    shown = {name: ("deg/s" if to_deg[name] else unit) for name, unit in units.items()}
    for j, name in enumerate(samples.input_names):
        ax.plot(samples.t, np.degrees(samples.inputs[j]) if to_deg[name] else samples.inputs[j], lw=1.6,
                label=f"{name}(t)")
    for tk in result.times:
        ax.axvline(tk, color="0.75", lw=0.8, ls="--", zorder=0)
    ax.set_xlabel("t [s]")
    kinds = set(shown.values())
    unit = kinds.pop() if len(kinds) == 1 else ""
    ax.set_ylabel(f"u = dφ/dt [{unit or 'rad/s'}]" if samples.input_names == ("u",) else
                  (f"input [{unit}]" if unit else "input"))
    ax.set_title("Input u(t)" if samples.input_names == ("u",) else "Inputs")
    ax.grid(alpha=0.3)
    limits = getattr(result, "limits", None)
    for j, name in enumerate(samples.input_names):
        U = limits.input_bound(name) if limits is not None else None
        if U is not None:
            U = math.degrees(U) if to_deg[name] else U
            for v in (-U, U):
                ax.axhline(v, color="C3", lw=0.9, ls=":", label=f"rate limit ±{U:g}" if v > 0 and j == 0 else None)
    if len(samples.input_names) > 1 or (limits is not None and limits.active):
        ax.legend(fontsize=8)
    return fig if own else ax


_SYMBOLS = {"theta": "θ", "phi": "φ"}


def _input_unit(system, name: str) -> str:
    """An input's unit: a rate of a state (``rate_inputs``) has the state's unit per second."""
    state = getattr(system, "rate_inputs", {}).get(name)
    unit = system.state_unit(state) if state is not None else ""
    return f"{unit}/s" if unit else ""


def _label(name: str, unit: str) -> str:
    """An axis label: the state's name (θ, φ for the acrobot's) and its unit in brackets."""
    return f"{_SYMBOLS.get(name, name)} [{unit}]" if unit else _SYMBOLS.get(name, name)


def _panels(result, samples, degrees: bool):
    """The panels of the states figure: ``(label, unit, values at samples.t, values at the
    waypoints, state or None)`` each, from the system's :meth:`display_states
    <acroplan.core.system.ControlAffineSystem.display_states>` (a spatial body's attitude as
    Yeadon's angles). A panel that is not a state itself (an attitude angle) has its waypoints
    moved by whole turns to the curve's branch (the unwrapped angle), so that a waypoint reached
    sits on its curve."""
    system = result.system
    shown = system.display_states(samples.states, degrees=degrees)
    wps = system.display_states(np.asarray(result.waypoints, dtype=float).T, degrees=degrees)
    out = []
    for (name, values, unit, state), (_, wp, _, _) in zip(shown, wps):
        wp = np.array(wp, dtype=float)
        if state is None and unit in ("rad", "deg"):
            turn = 360.0 if unit == "deg" else 2 * np.pi
            at = np.interp(result.times, samples.t, values)
            ok = np.isfinite(wp)
            wp[ok] += turn * np.round((at[ok] - wp[ok]) / turn)
        out.append((name, unit, np.asarray(values, dtype=float), wp, state))
    return out


def _state_panel(ax, result, samples, panel, color):
    name, unit, values, wp, state = panel
    ax.plot(samples.t, values, lw=1.6, color=color, label=name)
    ax.plot(result.times, wp, "o", mfc="white", color="k", ms=5)
    lo_v, hi_v = float(np.min(values)), float(np.max(values))
    to_unit = np.degrees if unit == "deg" else (lambda v: v)
    limits = getattr(result, "limits", None)
    if state is not None and limits is not None and state in limits.bounded_states:
        label = f"{name} limits"
        for v in limits.bounds(state):
            if np.isfinite(v):
                ax.axhline(to_unit(v), color="C3", lw=1.0, ls=":", label=label)
                label = None  # (each item once in the legend)
    if state is not None:
        raw = (np.radians(lo_v), np.radians(hi_v)) if unit == "deg" else (lo_v, hi_v)
        for v, label in result.system.reference_lines(state, *raw):
            ax.axhline(to_unit(v), color="0.6", lw=0.7, ls="--", zorder=0)
            ax.annotate(label, (1.0, to_unit(v)), xycoords=("axes fraction", "data"), xytext=(2, 0),
                        textcoords="offset points", va="center", fontsize=7, color="0.4", annotation_clip=False)


def plot_states(result, samples=None, *, ax=None, degrees: bool = False):
    """Fig. 2 style: one panel per state (θ above φ for the acrobot; a spatial body's attitude as
    Yeadon's somersault, tilt and twist, then its joints), waypoints marked (white dots), state
    limits dotted, and the family's reference values dashed (the acrobot's straight and folded
    body); every axis with its unit. ``degrees``: angles in degrees. Given ``ax``, every state is
    drawn on that one panel and ``ax`` returned."""
    plt = pyplot()
    samples = samples if samples is not None else result.sample(effort=False)
    panels = _panels(result, samples, degrees)
    if ax is not None:
        for i, panel in enumerate(panels):
            _state_panel(ax, result, samples, panel, f"C{i}")
        ax.set_xlabel("t [s]")
        units = sorted({p[1] for p in panels})
        ax.set_ylabel(f"states [{units[0]}]" if len(units) == 1 and units[0] else "states")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        return ax
    n = len(panels)
    fig, axes = plt.subplots(n, 1, figsize=(7, max(2.6 * n, 3.0) if n <= 8 else 1.7 * n), sharex=True,
                             constrained_layout=True)
    axes = np.atleast_1d(axes)
    for i, (axi, panel) in enumerate(zip(axes, panels)):
        _state_panel(axi, result, samples, panel, f"C{i}")
        axi.set_ylabel(_label(panel[0], panel[1]))
        axi.grid(alpha=0.3)
        handles, labels = axi.get_legend_handles_labels()
        if len(handles) > 1:
            axi.legend(loc="best", fontsize=8)
    names = tuple(p[0] for p in panels)
    axes[0].set_title("States (white dots: waypoints)" + (": θ (upper), φ (lower)" if names == ("theta", "phi")
                                                           else ""))
    axes[-1].set_xlabel("t [s]")
    return fig


#: The figures :func:`plot_result` can draw, in order.
FIGURES = ("input", "states", "continuation", "effort")


def plot_result(result, which=None, *, per_segment: int = 200, effort: bool = False, degrees: bool = False,
                samples=None) -> Figures:
    """The figures of a plan (a :class:`Figures`): by default ``input`` (Fig. 1), ``states`` (Fig. 2)
    and ``continuation`` (only when a segment was planned by path deformation), and ``effort``
    with ``effort=True``; ``which`` (a name or a sequence of names of :data:`FIGURES`) draws those
    alone; ``degrees``: angles in degrees in the states figure (its attitude angles, joints and
    limits: ``[deg]``) and rates of angles in deg/s in the input figure; ``samples``: the plan's
    ``result.sample(per_segment)`` when the caller has it already (the command line, which wrote
    trajectory.csv from it), with torques if ``effort``. Reports the stage ``"figures"``
    (:mod:`acroplan.core.progress`)."""
    from .progress import stage

    if which is None:
        names = ["input", "states"] + (["continuation"] if any(s.history for s in result.segments) else [])
        names += ["effort"] if effort else []
    else:
        names = [which] if isinstance(which, str) else list(which)
    bad = [n for n in names if n not in FIGURES]
    if bad:
        raise ValueError(f"which: must be one of {list(FIGURES)}, got {bad[0]!r}")
    if "effort" in names:
        result._torque_setup()  # (InvalidInputError when the system gives no torques)
    figs = Figures()
    with stage("figures", len(names) + 1, unit="figure") as st:
        if samples is None or ("effort" in names and samples.torques is None):
            samples = result.sample(per_segment, effort="effort" in names)
        st.update()
        try:
            for name in names:
                if name == "continuation":
                    figs[name] = plot_continuation(result)
                elif name == "states":
                    figs[name] = plot_states(result, samples, degrees=degrees)
                elif name == "input":
                    figs[name] = plot_input(result, samples, degrees=degrees)
                else:
                    figs[name] = plot_effort(result, samples)
                st.update(detail=name)
        except BaseException:
            figs.close()
            raise
    return figs


def plot_continuation(result):
    """Continuation diagnostics of every path-deformation segment of a plan.

    Left: each state's target path :math:`\\pi(\\tau)` (lines) against the endpoint reached at each
    accepted step (dots). Right: the smallest singular value of the reduced endpoint Jacobian over
    :math:`\\tau` (log scale): where it approaches 0 the continuation nears a singularity.
    """
    plt = pyplot()
    segs = [s for s in result.segments if s.history]
    fig, axes = plt.subplots(1, 2, figsize=(10, 5.0), constrained_layout=True)
    names = result.system.state_names
    for k, seg in enumerate(segs):
        tau = np.array([h[0] for h in seg.history])
        goal = np.array([h[3] for h in seg.history])
        reached = np.array([h[4] for h in seg.history])
        for i, name in enumerate(names):
            ls = "-" if i == 0 else "--"
            line, = axes[0].plot(tau, goal[:, i] - goal[0, i], ls, lw=1.2,
                                 label=f"seg {seg.index}: {name}" if len(segs) <= 6 else None)
            axes[0].plot(tau, reached[:, i] - goal[0, i], "o", ms=3, color=line.get_color())
        axes[1].semilogy(tau, [max(h[2], 1e-300) for h in seg.history], "o-", ms=3, lw=1,
                         label=f"segment {seg.index}" if len(segs) <= 6 else None)
    axes[0].set_xlabel("τ (path parameter, no unit)")
    axes[0].set_ylabel("change along the path [state units]")
    axes[0].set_title("Target path (lines) against what was reached (dots)")
    axes[1].set_xlabel("τ")
    axes[1].set_ylabel("smallest singular value")
    axes[1].set_title("Distance from singularity")
    for ax in axes:
        ax.grid(alpha=0.3)
        if len(segs) <= 6 and segs:
            ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=3, frameon=False)
    return fig


def _effort_panel(ax, result, samples, values, kind):
    for k, name in enumerate(samples.joint_names):
        ax.plot(samples.t, values[k], lw=1.6, color=f"C{k}", label=f"{name}")
    for tk in result.times:
        ax.axvline(tk, color="0.75", lw=0.8, ls="--", zorder=0)
    ax.axhline(0.0, color="0.5", lw=0.6, zorder=0)
    if kind == "torque":
        limits = getattr(result, "torque_limits", None) or {}
        for k, name in enumerate(samples.joint_names):
            top = limits.get(name)
            if top is not None and np.isfinite(top):
                for v in (-top, top):
                    ax.axhline(v, color=f"C{k}", lw=0.9, ls=":",
                               label=f"torque limit {name} ±{top:g}" if v > 0 else None)
        ax.set_ylabel("joint torque τ [N m]")
    else:
        ax.set_ylabel("power τ·u [W]")
    ax.grid(alpha=0.3)
    handles, _ = ax.get_legend_handles_labels()
    if len(handles) > 1:
        ax.legend(fontsize=8)


def plot_effort(result, samples=None, *, ax=None):
    """Joint torques :math:`\\tau_j(t)` (upper panel; torque limits dotted) and mechanical power
    :math:`\\tau_j u_{i(j)}` (lower panel; positive: the motor does work), waypoint times dashed,
    one line per joint of the system's torque model. Given ``ax``, draws the torques there and
    returns ``ax``; otherwise returns the figure.

    Parameters
    ----------
    result : PlanResult
        Of a system with a torque model (:meth:`PlanResult.torques`).
    samples : Samples, optional
        With torques (:meth:`PlanResult.sample`); default: 200 points per segment.
    """
    plt = pyplot()
    samples = samples if samples is not None and samples.torques is not None else result.sample()
    if ax is not None:
        _effort_panel(ax, result, samples, samples.torques, "torque")
        ax.set_xlabel("t [s]")
        return ax
    fig, axes = plt.subplots(2, 1, figsize=(7, 5.4), sharex=True, constrained_layout=True)
    _effort_panel(axes[0], result, samples, samples.torques, "torque")
    _effort_panel(axes[1], result, samples, samples.power, "power")
    axes[0].set_title("Joint torque (upper) and mechanical power (lower)")
    axes[1].set_xlabel("t [s]")
    return fig
