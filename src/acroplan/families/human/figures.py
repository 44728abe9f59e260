"""Figures of the human family's dive (docs/human.md).

Regenerate the images of docs/human.md with::

    python -c "import acroplan; from acroplan.families.human.figures import write_figures; write_figures('docs/images', acroplan.plan)"


* :func:`plot_dive`: hip flexion, hip rate and somersaults against time, with the diver's limits
  and the literature's peak hip rates, for one or more plans of the same dive;
* :func:`plot_dive_effort`: the hip torque and power of each plan, with an elite gymnast's largest
  hip flexion and extension torques;
* ``human-platform-dive.png``, ``human-platform-dive-strobe.png`` and, when the plans have joint
  torques, ``human-platform-dive-effort.png`` are written by :func:`write_figures`: the default
  dive (two waypoints, hip rates free at take-off and entry) planned energy-optimal (the default),
  feasible and torque-optimal;
* ``human-least-momentum.png``: :func:`acroplan.families.human.momentum.plot_least_momentum`.
"""

from __future__ import annotations

import math
import pathlib

import numpy as np

from .examples import PlatformDive, platform_dive
from .limits import hip_rate_literature, hip_torque_literature, position

__all__ = ["plot_dive", "plot_dive_effort", "write_figures", "dive_table"]


def plot_dive(dive: PlatformDive, results: dict, *, samples: int = 2001):
    """Hip flexion :math:`\\psi` (deg), hip rate :math:`\\dot\\psi` (rad/s) and somersaults
    :math:`(\\theta - \\theta(0))/2\\pi` against time, one line per plan in ``results`` (label to
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
        axes[2].plot(t, (s.states[0] - dive.kw["theta"][0]) / (2 * math.pi), color=f"C{k}", label=label)
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
    axes[2].axhline((dive.kw["theta"][-1] - dive.kw["theta"][0]) / (2 * math.pi), color="0.3", ls=":", lw=1)
    axes[0].set_ylabel("hip flexion ψ [deg]")
    axes[1].set_ylabel("hip rate dψ/dt [rad/s]")
    axes[2].set_ylabel("somersaults (θ − θ(0))/2π")
    axes[2].set_xlabel("t [s]")
    axes[0].legend(fontsize=8, loc="center right")
    turns = (dive.kw["theta"][-1] - dive.kw["theta"][0]) / (2 * math.pi)
    axes[0].set_title(f"10 m platform, {turns:g} somersaults in pike, "
                      f"T = {dive.flight_time:.3f} s, P0 = {dive.P0:.1f} kg m²/s "
                      f"({1 + dive.margin:.3f} × least {dive.least.P0:.1f})", fontsize=9)
    for ax in axes:
        ax.grid(alpha=0.3)
    return fig


def plot_dive_effort(dive: PlatformDive, results: dict, *, per_segment: int = 4000, scale_from=None,
                     bounds: bool = True):
    """Hip torque (both hips together, N m; > 0 flexes the hips) and mechanical power (W) of each
    plan, the vertical range set by the plans named in ``scale_from`` (default all); a plan whose
    peaks leave that range is named with its peak torque. ``bounds``: dotted lines at an elite
    gymnast's largest isometric hip flexion and extension torques, both hips
    (:func:`~acroplan.families.human.limits.hip_torque_literature`).

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
    flex, ext = hip_torque_literature()
    lim[0] = max(lim[0], flex if bounds else 0.0)
    if bounds:
        axes[0].axhline(flex, color="0.3", ls=":", lw=1)
        axes[0].text(0.0, flex, f" elite gymnast's largest hip flexion torque, both hips ({flex:.0f} N m; "
                     "Jackson 2010)", va="bottom", fontsize=7, color="0.3")
        axes[0].axhline(-ext, color="0.3", ls=":", lw=1)
        axes[0].text(0.0, -ext, f" and extension ({ext:.0f} N m)", va="top", fontsize=7, color="0.3")
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


def _label(objective) -> str:
    return "feasible (objective=None)" if objective is None else f'objective="{objective}"'


def write_figures(outdir, plan, *, torque: bool = True) -> list[pathlib.Path]:
    """Plan the default dive (:func:`~acroplan.families.human.examples.platform_dive`: two
    waypoints, hip rates free at take-off and entry) energy-optimal (the default), feasible and,
    with ``torque``, torque-optimal (about 30 s), and write the figures into ``outdir`` (module
    docstring), with ``human-least-momentum.png``
    (:func:`~acroplan.families.human.momentum.least_momentum_table`).

    Parameters
    ----------
    outdir : str or pathlib.Path
    plan : callable
        :func:`acroplan.plan` (passed in: a family does not import the front doors).
    torque : bool
        Also plan and draw the torque-optimal plan.

    Returns
    -------
    list of pathlib.Path
    """
    import inspect

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..acrobot.drawing import Geometry, strobe
    from .momentum import least_momentum_table

    out = pathlib.Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    optimal = "objective" in inspect.signature(plan).parameters
    objectives = (["energy"] if optimal else []) + [None] + (["torque"] if optimal and torque else [])
    results = {}
    for objective in objectives:
        d = platform_dive(objective=objective)
        r = plan(d.robot, **d.kw)
        label = _label(objective) + (" (default)" if objective == "energy" else "")
        kkt = _kkt(r)
        if kkt is not None and not kkt[1]:
            size = max(sg.optimality.get("basis_size") or 0 for sg in r.segments if sg.optimality)
            label += f", not converged ({size} coefficients)"
        results[label] = r
    dive = platform_dive(objective=None)
    written = [out / "human-platform-dive.png", out / "human-platform-dive-strobe.png"]
    fig = plot_dive(dive, results)
    fig.savefig(written[0], dpi=130)
    plt.close(fig)
    label, drawn = next(iter(results.items()))  # the default plan
    t = np.linspace(0.0, dive.flight_time, 2001)
    s = drawn.evaluate(t)
    p = dive.robot.physical
    fig = strobe(t, s.states[0], s.states[1], Geometry(p.torso_mass, p.leg_mass, p.torso_length, p.leg_length),
                 poses=11)
    fig.suptitle(f"{label}, drawn every 1/10 of the flight", fontsize=9)
    fig.savefig(written[1], dpi=130)
    plt.close(fig)
    if drawn.segments and getattr(drawn, "sample", None) and drawn.sample(3).torques is not None:
        fig = plot_dive_effort(dive, results)
        written.append(out / "human-platform-dive-effort.png")
        fig.savefig(written[-1], dpi=130)
        plt.close(fig)
    table = least_momentum_table()
    fig = table.plot()
    written.append(out / "human-least-momentum.png")
    fig.savefig(written[-1], dpi=130)
    plt.close(fig)
    return written


def _kkt(result):
    """``(largest relative KKT residual, converged on every segment)`` of an optimal plan, else None
    (converged: the KKT residual below its target and the cost settled as the basis grew)."""
    opt = [s.optimality for s in result.segments if getattr(s, "optimality", None)]
    if not opt:
        return None
    kkt = max((o["kkt"] if o.get("kkt") is not None else math.inf) for o in opt)
    return kkt, all(bool(o.get("converged", o.get("kkt_converged"))) for o in opt)


def dive_table(plan, body=None, *, problems=(False, True), objectives=None, warm: bool = True) -> str:
    """The dive planned for each problem (``through_pike`` False: the default, two waypoints with
    the hip rates free; True: the four-waypoint reference problem with the hips at rest at take-off
    and entry) without an objective and with each objective ``plan`` accepts, measured: wall time,
    the largest relative KKT residual (optimal plans), peak hip rate, :math:`\\int u^2`, the peak
    hip flexion and extension torques (both hips; 20 000 samples a segment), :math:`\\int \\tau^2`
    (:meth:`acroplan.PlanResult.effort`), the hip flexion range, and the turn's error
    :math:`\\Delta\\theta - 2\\pi n`; one markdown row each (docs/human.md).

    Parameters
    ----------
    plan : callable
        :func:`acroplan.plan`.
    body : SagittalBody, optional
        Default: the bundled male1.
    problems : sequence of bool
        The ``through_pike`` values to plan.
    objectives : sequence, optional
        Default: ``None``, ``"energy"`` and ``"torque"`` (those ``plan`` accepts).
    warm : bool
        Plan every row once before timing it, so that the times leave out compiling the integrators
        (once per process and basis size: seconds).
    """
    import inspect
    import time

    if objectives is None:
        objectives = [None] + (["energy", "torque"] if "objective" in inspect.signature(plan).parameters else [])
    rows = ["| problem | plan | time | KKT, basis | peak hip rate | ∫u² | peak hip torque: flexion / extension | "
            "∫τ² | hip flexion range | Δθ − 2πn |", "|---|---|---|---|---|---|---|---|---|---|"]
    for through in problems:
        for objective in objectives:
            d = platform_dive(body, objective=objective, through_pike=through)
            if warm:
                plan(d.robot, **d.kw)
            t0 = time.perf_counter()
            r = plan(d.robot, **d.kw)
            dt = time.perf_counter() - t0
            what = "4 waypoints, hips at rest (`through_pike=True`)" if through else "default: 2 waypoints, rates free"
            if not r.segments or r.status not in ("success", "not_converged"):
                rows.append(f"| {what} | {_label(objective)} | {dt:.2f} s | {r.status} | | | | | | |")
                continue
            s = r.sample(20000)
            u = s.inputs[0]
            psi = d.body.hip_flexion(s.states[1])
            turn = s.states[0, -1] - s.states[0, 0] - (d.kw["theta"][-1] - d.kw["theta"][0])
            kkt = _kkt(r)
            if kkt is not None:
                opt = [(i, sg.optimality) for i, sg in enumerate(r.segments) if sg.optimality]
                bad = [(i, o) for i, o in opt if not o.get("converged", o.get("kkt_converged"))]
                kkt = f"{kkt[0]:.1e}, {max(o.get('basis_size') or 0 for _, o in opt)} coefficients"
                if bad:
                    i, o = bad[0]
                    kkt += (f", **not converged** (interval {i}: cost by size " + ", ".join(
                        f"{n}: {c:.6g}" for n, c in o.get("ladder", ())) + ")")
            else:
                kkt = "-"
            if s.torques is not None:
                e = next(iter(r.effort().values()))
                tau = (f"{max(s.torques[0].max(), 0.0):.1f} / {max(-s.torques[0].min(), 0.0):.1f} N m",
                       f"{e.torque_squared:.0f}")
                u2 = e.input_squared
            else:
                tau, u2 = ("-", "-"), float(np.sum(np.diff(s.t) * 0.5 * (u[1:] ** 2 + u[:-1] ** 2)))
            status = "" if r.success else f" ({r.status})"
            rows.append(f"| {what} | {_label(objective)}{status} | {dt:.2f} s | {kkt} | {np.abs(u).max():.2f} rad/s | "
                        f"{u2:.2f} | {tau[0]} | {tau[1]} | {round(np.degrees(psi.min()), 1) + 0.0:.1f}° to "
                        f"{round(np.degrees(psi.max()), 1) + 0.0:.1f}° | {turn:.1e} |")
    d = platform_dive(body, objective=None)
    rows.append("")
    rows.append(f"T = {d.flight_time:.4f} s, least P0 = {d.least.P0:.4f}, P0 = {d.P0:.4f} kg m²/s "
                f"({100 * d.margin:.1f} % above), reference ramp {d.reference.ramp:.4f} s; elite gymnast's "
                f"largest hip torques (both hips): flexion {hip_torque_literature()[0]:.1f}, extension "
                f"{hip_torque_literature()[1]:.1f} N m")
    return "\n".join(rows)
