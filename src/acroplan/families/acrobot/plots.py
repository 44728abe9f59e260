"""The acrobot's own figures: reachable bands (:func:`plot_reach`) and the Chapter 4
nilpotentization (:func:`plot_nilpotent`)."""

from __future__ import annotations

import numpy as np

from ...core.plotting import pyplot

__all__ = ["plot_reach", "plot_nilpotent"]


def plot_reach(problem, *, samples: int = 241):
    """The reachable band of :math:`\\theta(T)` over :math:`\\varphi(T)`, one panel per segment.

    Each panel shows, for the segment's start state and duration, the exact reachable
    :math:`\\theta(T)` as a function of the final joint angle (unbounded input, light; under the
    problem's limits, dark) and the requested target.
    """
    from .reach import reachable_set

    plt = pyplot()
    robot = problem.robot
    lim = problem.limits
    K = len(problem.times) - 1
    cols = min(K, 3)
    rows = (K + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(4.4 * cols, 3.6 * rows), squeeze=False, constrained_layout=True)
    for k in range(K):
        ax = axes[k // cols][k % cols]
        T = problem.times[k + 1] - problem.times[k]
        th0, ph0 = problem.theta[k], problem.phi[k]
        lo_p = lim.phi_min if lim.phi_min is not None else ph0 - 2 * np.pi
        hi_p = lim.phi_max if lim.phi_max is not None else ph0 + 2 * np.pi
        lo_p, hi_p = min(lo_p, problem.phi[k + 1]), max(hi_p, problem.phi[k + 1])
        phis = np.linspace(lo_p, hi_p, samples)
        free = np.array([[reachable_set(robot, theta0=th0, phi0=ph0, phiT=p, T=T).low,
                          reachable_set(robot, theta0=th0, phi0=ph0, phiT=p, T=T).high] for p in phis])
        # the band without limits: hatched, with its edges drawn, so it shows under the limited one
        ax.fill_between(phis, free[:, 0], free[:, 1], facecolor="none", edgecolor="C0", hatch="///", lw=0,
                        alpha=0.5, label="reachable (no limits)")
        ax.plot(phis, free[:, 0], color="C0", lw=1.0)
        ax.plot(phis, free[:, 1], color="C0", lw=1.0)
        ys = [free.min(), free.max(), problem.theta[k + 1]]
        if lim.active:
            R = [reachable_set(robot, theta0=th0, phi0=ph0, phiT=p, T=T, limits=lim) for p in phis]
            ok = np.array([r.success for r in R])
            band = np.array([[r.low, r.high] for r in R])
            ax.fill_between(phis, np.where(ok, band[:, 0], np.nan), np.where(ok, band[:, 1], np.nan), color="C2",
                            alpha=0.45, lw=0, label="reachable within limits")
        ax.plot([problem.phi[k + 1]], [problem.theta[k + 1]], marker="*", ms=13, color="C3", ls="none",
                label="target", clip_on=False, zorder=5)
        pad = 0.08 * (max(ys) - min(ys) + 1e-9)
        ax.set_ylim(min(ys) - pad, max(ys) + pad)
        xpad = 0.04 * (hi_p - lo_p)
        ax.set_xlim(min(lo_p, problem.phi[k + 1]) - xpad, max(hi_p, problem.phi[k + 1]) + xpad)
        ax.set_title(f"segment {k}: t ∈ [{problem.times[k]:g}, {problem.times[k + 1]:g}] s\n"
                     f"from θ(0) = {th0:.4g} rad, φ(0) = {ph0:.4g} rad", fontsize=10)
        ax.set_xlabel("φ(T) [rad]")
        ax.set_ylabel("θ(T) [rad]")
        ax.grid(alpha=0.3)
        if k == 0:
            ax.legend(fontsize=8, loc="best")
    for k in range(K, rows * cols):
        axes[k // cols][k % cols].set_visible(False)
    return fig


def plot_nilpotent(result, counter=None, *, samples: int = 801):
    """Figures of a nilpotentization result: ``{"input", "states", "u1", "failure_mode"}``.

    ``u1`` shows :math:`u_1(\\varepsilon) = dt/d\\varepsilon` (positive: time moves forward);
    ``failure_mode`` shows ``counter``, another solution of the same endpoint equations along which
    :math:`u_1 < 0` somewhere: one curve from P to Q, drawn against its own clock
    :math:`t(\\varepsilon)`, which runs backwards on part of it (red), so it is no motion of the
    acrobot; the clocks of both solutions are compared beside it.
    """
    plt = pyplot()
    eps = np.linspace(0.0, 1.0, samples)
    t, theta, phi, u1 = result.curve(eps)
    u = result.u_of_eps(eps)
    figs = {}
    fig, ax = plt.subplots(figsize=(7, 3.6), constrained_layout=True)
    ax.plot(t, u, lw=1.6)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("u = dφ/dt [rad/s]")
    ax.set_title("Input u(t) from the nilpotent solution" if result.method == "nilpotent"
                 else "Input u(t), flat output as the clock")
    ax.grid(alpha=0.3)
    figs["input"] = fig
    fig, axes = plt.subplots(2, 1, figsize=(7, 5.2), sharex=True, constrained_layout=True)
    axes[0].plot(t, theta, color="C0", lw=1.6)
    axes[1].plot(t, phi, color="C1", lw=1.6)
    for ax, (name, i) in zip(axes, (("θ [rad]", 2), ("φ [rad]", 0))):
        ax.plot([result.problem.P[1], result.problem.Q[1]], [result.problem.P[i], result.problem.Q[i]], "o",
                mfc="white", color="k", label="P, Q")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    axes[0].legend()
    axes[0].set_title("States: θ (upper), φ (lower)")
    axes[1].set_xlabel("t [s]")
    figs["states"] = fig
    fig, ax = plt.subplots(figsize=(7, 3.6), constrained_layout=True)
    ax.plot(eps, u1, lw=1.6, label="valid: min u1 = %.3g" % result.margin)
    if counter is not None:
        ax.plot(eps, counter.curve(eps)[3], lw=1.4, ls="--", color="C3",
                label="same equations, min u1 = %.3g" % counter.margin)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel("ε (virtual time)")
    ax.set_ylabel("u1 = dt/dε" if result.method == "nilpotent" else "dt/dσ")
    ax.set_title("Time moves forward where u1 > 0")
    ax.grid(alpha=0.3)
    ax.legend()
    figs["u1"] = fig
    if counter is not None:
        tc, thc, phc, u1c = counter.curve(eps)
        back = u1c < 0  # where the counterexample's clock runs backwards
        fig, axes = plt.subplots(1, 2, figsize=(10.5, 4.0), constrained_layout=True)
        axes[0].plot(eps, t, lw=1.6, color="C0", label="valid solution (u1 > 0)")
        axes[0].plot(eps, tc, lw=1.4, color="0.5", label="other solution of the same equations")
        axes[0].plot(eps, np.where(back, tc, np.nan), lw=3, color="C3", label="its clock running backwards")
        axes[0].set_xlabel("ε (virtual time, no unit)")
        axes[0].set_ylabel("t(ε) [s]")
        axes[0].set_title("The clocks: t(ε) is monotone only for the valid one", fontsize=10)
        # the other solution alone: one curve, drawn against its own clock; the red part is
        # traversed backwards in time
        axes[1].plot(tc, phc, lw=1.4, color="0.5", label="u1 > 0: forward in time")
        axes[1].plot(np.where(back, tc, np.nan), np.where(back, phc, np.nan), lw=3, color="C3",
                     label="u1 < 0: backwards in time")
        step = max(1, len(eps) // 12)
        for i in range(step, len(eps) - 1, step):
            axes[1].annotate("", xy=(tc[i + 1], phc[i + 1]), xytext=(tc[i], phc[i]),
                             arrowprops=dict(arrowstyle="->", color="C3" if back[i] else "0.4", lw=1.2))
        axes[1].plot([tc[0], tc[-1]], [phc[0], phc[-1]], "o", mfc="white", color="k", label="P, Q")
        axes[1].set_xlabel("t(ε) [s]")
        axes[1].set_ylabel("φ [rad]")
        axes[1].set_title("One curve from P to Q (arrows: ε grows), partly backwards in time", fontsize=9)
        for ax in axes:
            ax.grid(alpha=0.3)
            ax.legend(fontsize=8)
        fig.suptitle("A solution of the endpoint equations with u1 < 0 is no motion of the acrobot", fontsize=11)
        figs["failure_mode"] = fig
    return figs
