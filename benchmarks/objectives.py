"""The three objectives of an acrobot plan, timed on the same random segments: the feasible plan
(``objective=None``), ``"energy"`` and ``"torque"``: the table of docs/mathematics.md ("Free
waypoint states").

Problems: ``acroplan.zoo.random_segment`` (targets in the middle 96% of the exact reachable
interval), ``conditions="free"``, the default verification; each problem planned the three ways one
after the other, once (wall time, and the process's CPU time, which a loaded machine inflates less),
after one warm-up plan of each kind (so compiling is left out). The effort
integrals come from ``PlanResult.effort()["phi"]`` (``input_squared``, ``torque_squared``).

Run:  python benchmarks/objectives.py [--n 40] [--seed 2024]
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import acroplan
from acroplan.zoo import random_segment

OBJECTIVES = (None, "energy", "torque")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=40)
    ap.add_argument("--seed", type=int, default=2024)
    args = ap.parse_args()
    print(f"command: python benchmarks/objectives.py --n {args.n} --seed {args.seed}; "
          f"load average {os.getloadavg()[0]:.1f} at the start")
    rng = np.random.default_rng(args.seed)
    problems = [random_segment(rng) for _ in range(args.n)]
    for objective in OBJECTIVES:  # warm-up: compile every basis size the optimal ladders use
        acroplan.plan(problems[0].robot, conditions="free", objective=objective, **problems[0].plan_kwargs())
    times = {o: [] for o in OBJECTIVES}
    cpu = {o: [] for o in OBJECTIVES}
    u2 = {o: [] for o in OBJECTIVES}
    tau2 = {o: [] for o in OBJECTIVES}
    converged = {o: 0 for o in OBJECTIVES}
    ok = {o: 0 for o in OBJECTIVES}
    for p in problems:
        for objective in OBJECTIVES:
            t0, c0 = time.perf_counter(), time.process_time()
            r = acroplan.plan(p.robot, conditions="free", objective=objective, **p.plan_kwargs())
            times[objective].append(time.perf_counter() - t0)
            cpu[objective].append(time.process_time() - c0)
            ok[objective] += bool(r.success)
            e = r.effort()["phi"]
            u2[objective].append(e.input_squared)
            tau2[objective].append(e.torque_squared)
            opt = r.segments[0].optimality
            converged[objective] += bool(opt and opt.get("converged"))
    feasible_u2 = np.array(u2[None]) / np.array(u2["energy"])
    torque_tau2 = np.array(tau2["torque"]) / np.array(tau2["energy"])
    print(f"{args.n} random acrobot segments, seed {args.seed}, conditions='free'")
    for o in OBJECTIVES:
        print(f"  objective={o!r:9s} success {ok[o]}/{args.n}  median {np.median(times[o]) * 1e3:.1f} ms  "
              f"p90 {np.percentile(times[o], 90) * 1e3:.1f} ms  CPU median {np.median(cpu[o]) * 1e3:.1f} ms" + ("" if o is None else f"  converged {converged[o]}/{args.n}"))
    print(f"  integral u^2, feasible / energy-optimal: median {np.median(feasible_u2):.3f}, max {feasible_u2.max():.2f}")
    print(f"  integral tau^2, torque-optimal / energy-optimal: median {np.median(torque_tau2):.2f}")


if __name__ == "__main__":
    main()
