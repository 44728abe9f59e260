"""Figures of any plan, kept apart from the numerics. Headless (Agg) unless a backend is already chosen.

* :func:`plot_input`: the text's Fig. 1, :math:`u(t)`, with the waypoint times marked;
* :func:`plot_states`: the text's Fig. 2, :math:`\\theta(t)` above :math:`\\varphi(t)`, waypoints marked;
* :func:`plot_continuation`: path-deformation diagnostics.
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_input", "plot_states", "plot_result", "plot_continuation"]


def _plt():
    import matplotlib

    if matplotlib.get_backend().lower() not in ("agg", "pdf", "svg") and not _interactive():
        matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _interactive() -> bool:
    import os

    return bool(os.environ.get("DISPLAY") or os.environ.get("MPLBACKEND"))


def plot_input(result, samples=None):
    """Fig. 1 style: the input over time, waypoint times as dashed lines. Returns the figure."""
    plt = _plt()
    samples = samples if samples is not None else result.sample()
    fig, ax = plt.subplots(figsize=(7, 3.6), constrained_layout=True)
    for j, name in enumerate(samples.input_names):
        ax.plot(samples.t, samples.inputs[j], lw=1.6, label=f"{name}(t)")
    for tk in result.times:
        ax.axvline(tk, color="0.75", lw=0.8, ls="--", zorder=0)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("u = dφ/dt [rad/s]" if samples.input_names == ("u",) else "input")
    ax.set_title("Input u(t)" if samples.input_names == ("u",) else "Inputs")
    ax.grid(alpha=0.3)
    if len(samples.input_names) > 1:
        ax.legend()
    return fig


def plot_states(result, samples=None):
    """Fig. 2 style: one panel per state (θ above φ for the acrobot), waypoints marked."""
    plt = _plt()
    samples = samples if samples is not None else result.sample()
    n = len(samples.state_names)
    fig, axes = plt.subplots(n, 1, figsize=(7, 2.6 * n), sharex=True, constrained_layout=True)
    axes = np.atleast_1d(axes)
    labels = {"theta": "θ [rad]", "phi": "φ [rad]"}
    for i, (ax, name) in enumerate(zip(axes, samples.state_names)):
        ax.plot(samples.t, samples.states[i], lw=1.6, color=f"C{i}")
        ax.plot(result.times, result.waypoints[:, i], "o", mfc="white", color="k", ms=5, label="waypoints")
        ax.set_ylabel(labels.get(name, name))
        ax.grid(alpha=0.3)
    axes[0].legend(loc="best")
    axes[0].set_title("States" + (": θ (upper), φ (lower)" if samples.state_names == ("theta", "phi") else ""))
    axes[-1].set_xlabel("t [s]")
    return fig


def plot_result(result, *, per_segment: int = 200):
    """The figures of a plan: ``{"input": Fig. 1, "states": Fig. 2, "continuation": diagnostics}``
    (the last only when a segment was planned by path deformation)."""
    samples = result.sample(per_segment)
    figs = {"input": plot_input(result, samples), "states": plot_states(result, samples)}
    if any(s.history for s in result.segments):
        figs["continuation"] = plot_continuation(result)
    return figs


def plot_continuation(result):
    """Continuation diagnostics of every path-deformation segment of a plan.

    Left: each state's target path :math:`\\pi(\\tau)` (lines) against the endpoint reached at each
    accepted step (dots). Right: the smallest singular value of the reduced endpoint Jacobian over
    :math:`\\tau` (log scale): where it approaches 0 the continuation nears a singularity.
    """
    plt = _plt()
    segs = [s for s in result.segments if s.history]
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), constrained_layout=True)
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
    axes[0].set_xlabel("τ (path parameter)")
    axes[0].set_ylabel("π(τ) − π(0): target (line), reached (dots)")
    axes[0].set_title("Target path against what was reached")
    axes[1].set_xlabel("τ")
    axes[1].set_ylabel("smallest singular value")
    axes[1].set_title("Distance from singularity")
    for ax in axes:
        ax.grid(alpha=0.3)
        if len(segs) <= 6 and segs:
            ax.legend(fontsize=7)
    return fig
