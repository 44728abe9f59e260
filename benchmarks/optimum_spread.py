"""How far an optimal 3-D plan depends on the last bits of the arithmetic: the same problem with its
duration moved by 0, +-1e-10, +-2e-10, 3e-10 and +-5e-10 s (far below any physical meaning, but
enough to change the last bits of every number the optimiser sees), each planned once, and the
optima it ends at side by side.

A nonconvex program (the falling cat's least integral of tau^2 has local optima at 0.483, 0.495 and
0.623) may end at different optima as the last bits fall; a change to the numerics that moves one
run's optimum is judged on this spread, not on one run (benchmarks/RESULTS.md, 2026-12-06, ninth
session).

Problems: ``cat-torque`` and ``cat-energy`` (examples.falling_cat_turn, at rest at both ends;
``cat-energy-free`` without the end rates), ``trunk-torque`` (examples.trunk_twist), or a bundled
problem file by name (``back-full-twist``, ...: its last interval's duration moved). ``--sizes``
gives the optimal strategy its ladder (default: the system's own).

Run:  python benchmarks/optimum_spread.py [--problem cat-torque] [--sizes 6 10 14 20 26 30]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

import acroplan
from acroplan.core.optimal import OBJECTIVES
from acroplan.families.spatial.examples import falling_cat_turn, trunk_twist

OFFSETS = (0.0, 1e-10, -1e-10, 2e-10, -2e-10, 3e-10, 5e-10, -5e-10)


def problem(name):
    """``(body, plan keywords)`` of ``name`` (module docstring), ``verify=False``."""
    if name.startswith("cat"):
        body, kw = falling_cat_turn()
        if name == "cat-energy-free":
            kw = {k: v for k, v in kw.items() if k not in ("start_rate", "end_rate")}
        kw["objective"] = "torque" if name == "cat-torque" else "energy"
    elif name == "trunk-torque":
        body, kw = trunk_twist()
        kw["objective"] = "torque"
    else:
        from acroplan.io import examples

        prob = examples.load(name)
        body, kw = prob.system, prob.plan_kwargs()
    return body, dict(kw, verify=False)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--problem", default="cat-torque")
    ap.add_argument("--sizes", type=int, nargs="*", default=None, help="the optimal strategy's ladder")
    args = ap.parse_args()
    print(f"# {platform.processor() or platform.machine()}, python {platform.python_version()}; "
          f"{args.problem}, ladder {tuple(args.sizes) if args.sizes else 'the system default'}")
    body, kw = problem(args.problem)
    if args.sizes:
        kw = dict(kw, method=OBJECTIVES[kw.pop("objective", "energy")](sizes=tuple(args.sizes)))
    acroplan.plan(body, **kw)  # warm: compiled functions
    costs, times = [], []
    for dt in OFFSETS:
        t = list(kw["times"])
        t[-1] += dt
        t0 = time.perf_counter()
        r = acroplan.plan(body, **dict(kw, times=tuple(t)))
        times.append(time.perf_counter() - t0)
        if not r.success:
            print(f"{dt:+.0e} s: {r.status.value}: {r.message[:160]}")
            continue
        opt = [s.optimality for s in r.segments]
        cost = sum(o["cost"] for o in opt)
        costs.append(cost)
        ladders = "; ".join(",".join(str(n) for n, _ in o["ladder"]) for o in opt)
        print(f"{dt:+.0e} s: cost {cost:.7g}, KKT {max(o['kkt'] for o in opt):.1e}, "
              f"{sum(o['evaluations'] for o in opt)} evaluations, ladder {ladders}, {times[-1]:.2f} s")
    if costs:
        low = min(costs)
        at_low = sum(c <= low * (1.0 + 1e-3) for c in costs)
        print(f"optima from {low:.7g} to {max(costs):.7g}; {at_low} of {len(OFFSETS)} within 0.1% of the lowest; "
              f"median time {float(np.median(times)):.2f} s")


if __name__ == "__main__":
    main()
