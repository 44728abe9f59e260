"""Success rate of the planner on random physical single-segment problems, by band.

Problems come from acroplan.zoo (masses 5-60, joint-to-centre-of-mass distances 0.2-0.6, inertias
within 20% of uniform rods', |P0| 0.5-30 of either sign, T 0.5-3, any phi(0), phi(T) within pi of
it). The target theta(T) sits at relative position w in the exact reachable interval:

    center   w in [0.25, 0.75]
    middle   w in [0.10, 0.25) or (0.75, 0.90]
    edge     w in [0.02, 0.10) or (0.90, 0.98]
    outside  w in [-0.2, 0) or (1, 1.2]        (must be refused: status "infeasible", exit code 3)

Every success is re-verified independently (scipy DOP853) by plan() itself.

Run:  python benchmarks/success_rate.py [--n 400] [--seed 2024] [--methods auto,deform,flat]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import acroplan
from acroplan.zoo import random_segment

BANDS = {"center": [(0.25, 0.75)], "middle": [(0.10, 0.25), (0.75, 0.90)], "edge": [(0.02, 0.10), (0.90, 0.98)],
         "outside": [(-0.2, 0.0), (1.0, 1.2)]}


def draw(rng, band):
    def draw_w(rng):
        a, b = BANDS[band][rng.integers(len(BANDS[band]))]
        w = rng.uniform(a, b)
        return -0.01 if band == "outside" and w in (0.0, 1.0) else w

    p = random_segment(rng, draw_w=draw_w)
    return p.robot, p.plan_kwargs()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=400, help="problems per band")
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--methods", default="auto,deform,flat")
    args = ap.parse_args()
    methods = args.methods.split(",")
    print(f"{args.n} problems per band, seed {args.seed}, conditions='free'")
    print(f"{'band':8s} " + " ".join(f"{m + ' ok':>12s} {'ms/plan':>8s}" for m in methods))
    for band in BANDS:
        rng = np.random.default_rng([args.seed, list(BANDS).index(band)])
        problems = [draw(rng, band) for _ in range(args.n)]
        cells = []
        for method in methods:
            ok, t0 = 0, time.perf_counter()
            for robot, kw in problems:
                r = acroplan.plan(robot, conditions="free", method=method, **kw)
                if band == "outside":
                    ok += r.status == "infeasible" and r.infeasible[0]["interval"] is not None
                else:
                    ok += r.success
            ms = 1e3 * (time.perf_counter() - t0) / args.n
            label = "refused" if band == "outside" else "ok"
            cells.append(f"{ok / args.n:11.2%}{'*' if label == 'refused' else ' '} {ms:8.2f}")
        print(f"{band:8s} " + " ".join(cells))
    print("* outside: share refused as infeasible with the interval (exit code 3 in the CLI)")


if __name__ == "__main__":
    main()
