"""Whether a bundled twisting dive's optimum turns on the last bits of its problem (issue #23): each
dive planned as its file says, then with every joint-angle waypoint moved by ``eps`` relative
(``value * (1 + eps * xi)``, ``xi`` standard normal from ``numpy.random.default_rng(seed)``; the
attitude waypoints as they are), as another processor's rounding would move the feasible start the
optimiser begins from. A dive whose optimum is robust gives the same cost to ``eps``-sized changes
for every seed; one that falls into another local optimum shows a cost that differs in its leading
digits.

The twelfth session (benchmarks/RESULTS.md) found the forward dive's reported least integral of
tau^2 at 1427.229 instead of 1314.234 after a change that moved its feasible start by 1e-15 rad:
this script is how that is watched now.

Run:  python benchmarks/dive_starts.py [--dives forward-double-twist ...] [--seeds 6] [--eps 1e-13]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

import acroplan
from acroplan.families.human.dives import DIVES
from acroplan.io import examples


def perturbed(kw: dict, joints, eps: float, seed: int) -> dict:
    """``kw`` with every waypoint value of ``joints`` moved by ``eps`` relative (seed 0: as given)."""
    if seed == 0:
        return kw
    rng = np.random.default_rng(seed)
    out = dict(kw)
    for name in joints:
        v = np.asarray(kw[name], dtype=float)
        out[name] = tuple(v * (1.0 + eps * rng.standard_normal(v.shape)))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dives", nargs="*", default=["forward-double-twist", "back-double-full-out"])
    ap.add_argument("--seeds", type=int, default=6, help="perturbed problems per dive (besides the file's own)")
    ap.add_argument("--eps", type=float, default=1e-13)
    args = ap.parse_args()
    print(f"# {platform.processor() or platform.machine()}, python {platform.python_version()}, eps {args.eps:g}")
    for name in args.dives:
        if name not in DIVES:
            raise SystemExit(f"unknown dive {name!r}: {sorted(DIVES)}")
        prob = examples.load(name)
        body, kw = prob.system, prob.plan_kwargs()
        joints = [j for j in body.state_names[4:] if j in kw]  # the joint angles (after the quaternion)
        if not joints:
            raise SystemExit(f"{name}: no joint-angle waypoints to move")
        costs = []
        for seed in range(args.seeds + 1):
            t0 = time.perf_counter()
            res = acroplan.plan(body, **perturbed(kw, joints, args.eps, seed))
            dt = time.perf_counter() - t0
            opt = (res.segments[0].optimality or {}) if res.segments else {}
            joint = opt.get("joint") or {}
            cost = sum((s.optimality or {}).get("cost") or 0.0 for s in res.segments)
            costs.append(cost)
            print(f"{name} seed {seed}: {res.status} in {dt:.1f} s, cost {cost:.15g}, joint optimum "
                  f"{'kept' if joint.get('kept') else 'not kept'} ({joint.get('iterations')} SQP iterations, from "
                  f"the sequential {joint.get('sequential_cost', float('nan')):.10g}), "
                  f"{sum(s.evaluations for s in res.segments)} endpoint evaluations of the intervals, "
                  f"{joint.get('evaluations')} of the joint optimum", flush=True)
        spread = (max(costs) - min(costs)) / max(abs(min(costs)), 1e-300)
        print(f"{name}: {len(costs)} problems, costs {min(costs):.15g} to {max(costs):.15g} (relative spread "
              f"{spread:.1e})", flush=True)


if __name__ == "__main__":
    main()
