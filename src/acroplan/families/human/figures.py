"""Figures of the human family's dive (docs/human.md).

Regenerate the images of docs/human.md with::

    python -c "import acroplan; from acroplan.families.human.figures import write_figures; write_figures('docs/images', acroplan.plan)"


* :func:`plot_dive`: hip flexion, hip rate and somersaults against time, with the diver's limits
  and the literature's peak hip rates, for one or more plans of the same dive;
* :func:`plot_dive_effort`: the hip torque and power of each plan;
* ``human-platform-dive.png``, ``human-platform-dive-strobe.png`` and, when the plans have joint
  torques, ``human-platform-dive-effort.png`` are written by :func:`write_figures`.
"""

from __future__ import annotations

import math
import pathlib

import numpy as np

from .examples import PlatformDive, platform_dive
from .limits import hip_rate_literature, position

__all__ = ["plot_dive", "plot_dive_effort", "write_figures", "dive_table"]


def plot_dive(dive: PlatformDive, results: dict, *, samples: int = 2001):
    """Hip flexion :math:`\\psi` (deg), hip rate :math:`\\dot\\psi` (rad/s) and somersaults
    :math:`\\theta/2\\pi` against time, one line per plan in ``results`` (label to
    :class:`~acroplan.PlanResult`) and the reference motion (dashed); the pike's range and the
    rate limit dotted, the literature's peak hip flexion rates of elite divers (11.0 to 12.8 rad/s)
    shaded.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    t = np.linspace(0.0, dive.flight_time, samples)
    fig, axes = plt.subplots(3, 1, figsize=(7.2, 7.4), sharex=True, constrained_layout=True)
    ref = dive.reference
    axes[0].plot(t, np.degrees(ref.hip_flexion(t)), color="k", ls="--", lw=1, label="reference (sets P0)")
    axes[1].plot(t, np.gradient(ref.hip_flexion(t), t), color="k", ls="--", lw=1)
    for k, (label, res) in enumerate(results.items()):
        s = res.evaluate(t)
        psi = dive.body.hip_flexion(s.states[1])
        axes[0].plot(t, np.degrees(psi), color=f"C{k}", label=label)
        axes[1].plot(t, s.inputs[0], color=f"C{k}", label=label)
        axes[2].plot(t, s.states[0] / (2 * math.pi), color=f"C{k}", label=label)
    lo, hi = position("pike").hip
    for v in (lo, hi):
        axes[0].axhline(math.degrees(v), color="0.3", ls=":", lw=1)
    axes[0].text(0.0, math.degrees(hi), " pike limit (150°, an estimate)", va="bottom", fontsize=8, color="0.3")
    u_max = dive.limits.input_bound("u")
    a, b = hip_rate_literature()
    for sign in (1, -1):
        axes[1].axhline(sign * u_max, color="0.3", ls=":", lw=1)
        axes[1].axhspan(sign * a, sign * b, color="0.85", zorder=0)
    axes[1].text(0.0, b, " elite divers' peak hip flexion rates, 11.0-12.8 rad/s (Murtaugh 2000)", va="bottom",
                 fontsize=8, color="0.3")
    for tk in dive.kw["times"]:
        for ax in axes:
            ax.axvline(tk, color="0.7", ls="--", lw=0.8, zorder=0)
    axes[2].axhline(dive.kw["theta"][-1] / (2 * math.pi), color="0.3", ls=":", lw=1)
    axes[0].set_ylabel("hip flexion ψ [deg]")
    axes[1].set_ylabel("hip rate dψ/dt [rad/s]")
    axes[2].set_ylabel("somersaults θ/2π")
    axes[2].set_xlabel("t [s]")
    axes[0].legend(fontsize=8, loc="center right")
    axes[0].set_title(f"10 m platform, {dive.kw['theta'][-1] / (2 * math.pi):g} somersaults in pike, "
                      f"T = {dive.flight_time:.3f} s, P0 = {dive.P0:.1f} kg m²/s "
                      f"({1 + dive.margin:.3f} × least {dive.least.P0:.1f})", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
    return fig


def plot_dive_effort(dive: PlatformDive, results: dict, *, per_segment: int = 4000, scale_from=None):
    """Hip torque (both hips together, N m) and mechanical power (W) of each plan, the vertical
    range set by the plans named in ``scale_from`` (default all); a plan whose peaks leave that range
    is named with its peak torque.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 1, figsize=(7.2, 5.6), sharex=True, constrained_layout=True)
    peaks, lim = {}, [0.0, 0.0]
    for k, (label, res) in enumerate(results.items()):
        s = res.sample(per_segment)
        tau, power = s.torques[0], s.power[0]
        peaks[label] = float(np.abs(tau).max())
        axes[0].plot(s.t, tau, color=f"C{k}", label=f"{label}: peak {peaks[label]:.0f} N m")
        axes[1].plot(s.t, power, color=f"C{k}")
        if scale_from is None or label in scale_from:
            lim = [max(lim[0], float(np.abs(tau).max())), max(lim[1], float(np.abs(power).max()))]
    for ax, m in zip(axes, lim):
        ax.set_ylim(-1.2 * m, 1.2 * m)
        ax.grid(alpha=0.3)
        for tk in dive.kw["times"]:
            ax.axvline(tk, color="0.7", ls="--", lw=0.8, zorder=0)
    off = [f"{label} (peak {p:.0f} N m)" for label, p in peaks.items() if p > 1.2 * lim[0]]
    title = "Hip torque (both hips) and mechanical power"
    if off:
        title += "\noff the scale: " + ", ".join(off)
    axes[0].set_title(title, fontsize=9)
    axes[0].set_ylabel("hip torque τ [N m]")
    axes[1].set_ylabel("power τ·u [W]")
    axes[1].set_xlabel("t [s]")
    axes[0].legend(fontsize=8)
    return fig


def write_figures(outdir, plan) -> list[pathlib.Path]:
    """Plan the dive (feasible, and energy- and torque-optimal when ``plan`` has ``objective=``)
    and write the figures into ``outdir`` (module docstring).

    Parameters
    ----------
    outdir : str or pathlib.Path
    plan : callable
        :func:`acroplan.plan` (passed in: a family does not import the front doors).

    Returns
    -------
    list of pathlib.Path
    """
    import inspect

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..acrobot.drawing import Geometry, strobe

    out = pathlib.Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    dive = platform_dive(objective=None)
    results = {"feasible (objective=None)": plan(dive.robot, **dive.kw)}
    if "objective" in inspect.signature(plan).parameters:
        for objective in ("energy", "torque"):
            d = platform_dive(objective=objective)
            results[f'objective="{objective}"'] = plan(d.robot, **d.kw)
    written = [out / "human-platform-dive.png", out / "human-platform-dive-strobe.png"]
    fig = plot_dive(dive, results)
    fig.savefig(written[0], dpi=130)
    plt.close(fig)
    drawn = list(results.values())[-1]  # the most human-like plan available
    t = np.linspace(0.0, dive.flight_time, 2001)
    s = drawn.evaluate(t)
    p = dive.robot.physical
    fig = strobe(t, s.states[0], s.states[1], Geometry(p.torso_mass, p.leg_mass, p.torso_length, p.leg_length),
                 poses=11)
    fig.suptitle(f"{list(results)[-1]}, drawn every 1/10 of the flight", fontsize=9)
    fig.savefig(written[1], dpi=130)
    plt.close(fig)
    if drawn.segments and getattr(drawn, "sample", None) and drawn.sample(3).torques is not None:
        fig = plot_dive_effort(dive, results, scale_from=[k for k in results if "energy" not in k])
        written.append(out / "human-platform-dive-effort.png")
        fig.savefig(written[-1], dpi=130)
        plt.close(fig)
    return written


def dive_table(plan, body=None) -> str:
    """The dive planned without an objective and with each objective ``plan`` accepts, measured:
    wall time, peak hip rate, :math:`\\int u^2`, peak hip torque, :math:`\\int \\tau^2` (trapezoid
    on 20 000 points a segment), the hip flexion range, and the turn's error
    :math:`\\Delta\\theta - 2\\pi n`; one markdown row each (docs/human.md).

    Parameters
    ----------
    plan : callable
        :func:`acroplan.plan`.
    body : SagittalBody, optional
        Default: the bundled male1.
    """
    import inspect
    import time

    from scipy.integrate import trapezoid

    objectives = [None] + (["energy", "torque"] if "objective" in inspect.signature(plan).parameters else [])
    rows = ["| plan | time | peak hip rate | ∫u² | peak hip torque (both hips) | ∫τ² | hip flexion range | "
            "Δθ − 7π |", "|---|---|---|---|---|---|---|---|"]
    for objective in objectives:
        d = platform_dive(body, objective=objective)
        t0 = time.perf_counter()
        r = plan(d.robot, **d.kw)
        dt = time.perf_counter() - t0
        s = r.sample(20000)
        u = s.inputs[0]
        psi = d.body.hip_flexion(s.states[1])
        turn = s.states[0, -1] - s.states[0, 0] - (d.kw["theta"][-1] - d.kw["theta"][0])
        tau = (f"{np.abs(s.torques[0]).max():.0f} N m", f"{trapezoid(s.torques[0] ** 2, s.t):.0f}") \
            if s.torques is not None else ("-", "-")
        rows.append(f"| `objective={objective!r}` | {dt:.2f} s | {np.abs(u).max():.2f} rad/s | "
                    f"{trapezoid(u ** 2, s.t):.2f} | {tau[0]} | {tau[1]} | {psi.min():.3f} to {psi.max():.3f} rad | "
                    f"{turn:.1e} |")
    d = platform_dive(body, objective=None)
    rows.append("")
    rows.append(f"T = {d.flight_time:.4f} s, least P0 = {d.least.P0:.4f}, P0 = {d.P0:.4f} kg m²/s "
                f"({100 * d.margin:.1f} % above), ramp {d.reference.ramp:.4f} s")
    return "\n".join(rows)
