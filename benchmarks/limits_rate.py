"""How limits are enforced, measured: random single-segment problems with joint and rate limits.

Each problem from acroplan.zoo gets a rate limit u_max = f * |phi(T) - phi(0)| / T with f uniform in
[1.5, 5] (at least 0.5 rad/s) and joint limits 0.5 rad beyond the motion's ends, and a target drawn
uniformly in the middle 96% of the exact reachable interval *under those limits*.

For each method it reports the success rate (every success re-verified by plan() and checked for
compliance exactly), and for "auto" which stage solved the problem:
  deform         path deformation alone already kept the limits
  deform+limits  path deformation, then the constrained solve (SLSQP on the polytope of limits)
  flat           the flat-output planner (three pieces)

Run:  python benchmarks/limits_rate.py [--n 300] [--seed 5]
"""

from __future__ import annotations

import argparse
import collections
import time

import numpy as np

import acroplan
from acroplan.families.acrobot.reach import Limits, reachable_set
from acroplan.zoo import random_body


def draw(rng):
    robot = random_body(rng)
    T = rng.uniform(0.5, 3.0)
    phi0 = rng.uniform(-np.pi, np.pi)
    phiT = phi0 + rng.uniform(-np.pi, np.pi)
    theta0 = rng.uniform(-np.pi, np.pi)
    u_max = max(0.5, rng.uniform(1.5, 5.0) * abs(phiT - phi0) / T)
    lim = Limits(phi_min=min(phi0, phiT) - 0.5, phi_max=max(phi0, phiT) + 0.5, u_max=u_max)
    R = reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T, limits=lim)
    w = rng.uniform(0.02, 0.98)
    kw = dict(times=[0.0, T], theta=[theta0, R.low + w * (R.high - R.low)], phi=[phi0, phiT],
              u_max=lim.u_max, phi_min=lim.phi_min, phi_max=lim.phi_max)
    return robot, kw


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    problems = [draw(rng) for _ in range(args.n)]
    print(f"{args.n} problems with joint and rate limits, seed {args.seed}, conditions='free'")
    for method in ("auto", "deform", "flat"):
        ok, stages, t0 = 0, collections.Counter(), time.perf_counter()
        for robot, kw in problems:
            r = acroplan.plan(robot, conditions="free", method=method, **kw)
            if r.success:
                ok += 1
                stages[r.segments[0].method] += 1
                assert all(s.max_abs_u <= kw["u_max"] + 1e-9 for s in r.segments)
        ms = 1e3 * (time.perf_counter() - t0) / args.n
        split = ", ".join(f"{k}: {v}" for k, v in sorted(stages.items()))
        print(f"{method:7s} success {ok / args.n:7.2%}   {ms:7.1f} ms/plan   solved by: {split}")


if __name__ == "__main__":
    main()
