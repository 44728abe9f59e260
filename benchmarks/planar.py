"""Planar bodies: success, time and honesty of method="auto" on random reachable single segments.

Populations (``--n`` problems each, the same seeds every run): random physical three- and
four-link chains (acroplan.families.planar.zoo.random_body), P0 = 0 and P0 != 0 (a drift of 0.3-2
rad/s at the start), without and with limits; single segments whose target is reachable by
construction (random_segment: the end of a simulated random smooth joint motion; with limits, joint
limits 0.25 rad outside the range that motion sweeps and rate limits 25% above its largest rates).

Each problem is planned twice, warm (compiled integrators built before timing):
  * verify=False, timed: the planner alone;
  * verify=True, timed: the planner and the independent check (Pinocchio centroidal simulation).
Every success of the first is re-checked by acroplan.families.planar.check.pinocchio_errors (the
Pinocchio-driven motion chained from the start); a success whose check exceeds 1e-9 is counted as
a failure and reported as a false success.

Run:  python benchmarks/planar.py [--n 200] [--seed 2024] [--links 3 4] [--conditions free]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

import acroplan
from acroplan.families.planar import random_body
from acroplan.families.planar.check import pinocchio_errors
from acroplan.families.planar.zoo import random_segment

CHECK_TOL = 1e-9


def population(seed, n, links, momentum, limited):
    rng = np.random.default_rng([seed, links, int(momentum), int(limited)])
    return [random_segment(rng, links, momentum=momentum, limited=limited) for _ in range(n)]


def run(problems, conditions):
    rows = []
    for p in problems:
        kw = p.plan_kwargs()
        t0 = time.perf_counter()
        r = acroplan.plan(p.body, conditions=conditions, verify=False, **kw)
        dt = time.perf_counter() - t0
        t0 = time.perf_counter()
        rv = acroplan.plan(p.body, conditions=conditions, verify=True, **kw)
        dtv = time.perf_counter() - t0
        err = float(pinocchio_errors(p.body, p.x0, r.segments).max()) if r.success else float("nan")
        rows.append(dict(ok=r.success, dt=dt, okv=rv.success, dtv=dtv, err=err, ev=r.evaluations if r.segments else 0,
                         u=r.max_abs_u if r.success else float("nan"),
                         method=r.segments[0].method if r.success else "", msg=r.message))
    return rows


def summary(rows):
    ok = [r for r in rows if r["ok"] and r["err"] <= CHECK_TOL]
    false = [r for r in rows if r["ok"] and not r["err"] <= CHECK_TOL]
    t = np.array([r["dt"] for r in rows]) * 1e3
    tv = np.array([r["dtv"] for r in rows]) * 1e3
    errs = np.array([r["err"] for r in ok]) if ok else np.array([np.nan])
    u = np.array([r["u"] for r in ok]) if ok else np.array([np.nan])
    ev = np.array([r["ev"] for r in ok]) if ok else np.array([0])
    okv = sum(r["okv"] for r in rows)
    lim = sum(r["method"] == "deform+limits" for r in ok)
    return (f"success {len(ok)}/{len(rows)} ({len(ok) / len(rows):.1%}), false successes {len(false)}; "
            f"verify=True success {okv}/{len(rows)}\n"
            f"    time verify=False median {np.median(t):.2f} ms p90 {np.percentile(t, 90):.2f} ms max {t.max():.0f} ms; "
            f"verify=True median {np.median(tv):.2f} ms p90 {np.percentile(tv, 90):.2f} ms\n"
            f"    evaluations median {np.median(ev):.0f} max {ev.max()}; max|u| median {np.median(u):.2f} max "
            f"{np.max(u):.2f} rad/s; constrained solve (SLSQP) in {lim}\n"
            f"    Pinocchio re-check of every success: median {np.median(errs):.1e} max {np.max(errs):.1e}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--links", type=int, nargs="+", default=[3, 4])
    ap.add_argument("--conditions", default="free", choices=["free", "spline"])
    args = ap.parse_args()
    import pinocchio

    print(f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, pinocchio {pinocchio.__version__}; n = {args.n} per population, seed "
          f"{args.seed}, conditions={args.conditions!r}")
    for links in args.links:
        acroplan.warm_up(random_body(0, links))
        warm = population(args.seed + 1, 3, links, True, True)
        run(warm, args.conditions)  # first calls (Pinocchio models, caches) out of the timing
        for momentum in (False, True):
            for limited in (False, True):
                rows = run(population(args.seed, args.n, links, momentum, limited), args.conditions)
                print(f"\n{links} links, P0 {'!= 0' if momentum else '= 0'}, {'with' if limited else 'without'} "
                      f"limits: {summary(rows)}")
                for r in [r for r in rows if not (r["ok"] and r["err"] <= CHECK_TOL)][:5]:
                    print(f"    failure: {r['msg'][:300]}")


if __name__ == "__main__":
    main()
