"""Cost against the number of segments (1 to 100) and of coefficients (4 to 20).

Waypoints are states of a simulated smooth motion of a fixed physical body (so every segment is
feasible), 1 time unit apart; plans use conditions="free", method="deform" with a fixed number of
coefficients, verify=False (the planner's own cost), warm (compiled before timing). Writes
benchmarks/scaling.png and prints a table: milliseconds per plan, and per segment.

Run:  python benchmarks/scaling.py
"""

from __future__ import annotations

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

import acroplan  # noqa: E402

SEGMENTS = (1, 2, 5, 10, 20, 50, 100)
COEFFICIENTS = (4, 6, 10, 14, 20)


def waypoints(robot, K):
    t = np.arange(K + 1, dtype=float)
    u = lambda s: 1.2 * np.sin(0.9 * s) + 0.6 * np.cos(2.3 * s)  # noqa: E731
    sol = solve_ivp(lambda s, x: robot.rhs(x, [u(s)]), (0, K), [0.0, -2.0], t_eval=t, rtol=1e-12, atol=1e-12)
    return t, sol.y[0], sol.y[1]


def main():
    robot = acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                           torso_length=0.35, leg_length=0.45, angular_momentum=10.0)
    rows = {}
    for n in COEFFICIENTS:
        t, th, ph = waypoints(robot, 2)
        acroplan.plan(robot, times=t, theta=th, phi=ph, conditions="free", method="deform", n_coefficients=n,
                      verify=False)  # compile
        for K in SEGMENTS:
            t, th, ph = waypoints(robot, K)
            reps = max(1, 20 // K)
            t0 = time.perf_counter()
            for _ in range(reps):
                r = acroplan.plan(robot, times=t, theta=th, phi=ph, conditions="free", method="deform",
                                  n_coefficients=n, verify=False)
            dt = (time.perf_counter() - t0) / reps
            rows[(n, K)] = (dt, r.success, r.evaluations)
    print(f"{'n':>3s} " + " ".join(f"{K:>9d}" for K in SEGMENTS) + "   (ms per plan; * = not converged)")
    for n in COEFFICIENTS:
        print(f"{n:3d} " + " ".join(f"{1e3 * rows[(n, K)][0]:8.1f}{' ' if rows[(n, K)][1] else '*'}"
                                    for K in SEGMENTS))
    print("ms per segment at K = 100:", {n: round(1e3 * rows[(n, 100)][0] / 100, 2) for n in COEFFICIENTS})
    fig, ax = plt.subplots(figsize=(6, 4), constrained_layout=True)
    for n in COEFFICIENTS:
        ax.loglog(SEGMENTS, [1e3 * rows[(n, K)][0] for K in SEGMENTS], "o-", label=f"{n} coefficients")
    ax.loglog(SEGMENTS, [1e3 * rows[(6, 1)][0] * K for K in SEGMENTS], "k:", label="linear")
    ax.set_xlabel("segments")
    ax.set_ylabel("time per plan [ms]")
    ax.set_title("Planning cost against segments (warm, verify=False)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    out = Path(__file__).with_name("scaling.png")
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
