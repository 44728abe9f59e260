"""Spatial bodies: success, time and honesty of method="auto" on random reachable single segments.

Populations (``--n`` problems each, the same seeds every run): random physical chains of 3, 4 and 5
links (acroplan.families.spatial.zoo.random_body: boxes of 1-30 kg, joint axes in random
directions; ``--tree``: random trees, each link on a random earlier one), L = 0 and L != 0 (a
drift of 0.3-2 rad/s at the start, in a random direction); single segments whose target is
reachable by construction (random_segment: the end of a simulated random
smooth joint motion, from a random attitude), conditions="free", no limits.

Each problem is planned warm (the compiled maps of its topology built before timing, by
acroplan.warm_up) with verify=False
(timed: the planner alone); every success is then re-checked by
acroplan.families.spatial.check.pinocchio_errors (the Pinocchio-driven motion, timed separately),
and a success whose check exceeds 1e-9 is counted as a failure and reported as a false success.

``--examples`` plans the bundled examples (acroplan.families.spatial.examples) and the issue #22
two-joint cat (zoo.two_joint_cat, zoo.long_axis_turn) once each, warm (acroplan.warm_up first),
with the default verify=True, and prints their times.

Run:  python benchmarks/spatial.py [--n 50 (0: the examples alone)] [--seed 2024] [--links 3 4 5] [--tree] [--examples]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

import acroplan
from acroplan.families.spatial.check import pinocchio_errors
from acroplan.families.spatial.zoo import random_segment

CHECK_TOL = 1e-9


def population(seed, n, links, momentum, tree=False):
    rng = np.random.default_rng([seed, links, int(momentum)] + ([1] if tree else []))
    return [random_segment(rng, links, momentum=momentum, tree=tree) for _ in range(n)]


def run(problems):
    rows = []
    for p in problems:
        kw = p.plan_kwargs()
        # the compiled maps of this body's topology built (or read from the disk cache) untimed: a
        # tree population has many topologies, and each one's first plan in the process took 0.1-0.3 s more
        acroplan.warm_up(p.body)
        t0 = time.perf_counter()
        r = acroplan.plan(p.body, conditions="free", verify=False, **kw)
        dt = time.perf_counter() - t0
        err, dtc = float("nan"), float("nan")
        if r.success:
            t0 = time.perf_counter()
            err = float(pinocchio_errors(p.body, p.x0, r.segments).max())
            dtc = time.perf_counter() - t0
        rows.append(dict(ok=r.success, dt=dt, dtc=dtc, err=err, ev=r.evaluations if r.segments else 0,
                         u=r.max_abs_u if r.success else float("nan"), msg=r.message))
    return rows


def summary(rows):
    ok = [r for r in rows if r["ok"] and r["err"] <= CHECK_TOL]
    false = [r for r in rows if r["ok"] and not r["err"] <= CHECK_TOL]
    t = np.array([r["dt"] for r in rows]) * 1e3
    tc = np.array([r["dtc"] for r in ok]) * 1e3 if ok else np.array([np.nan])
    errs = np.array([r["err"] for r in ok]) if ok else np.array([np.nan])
    u = np.array([r["u"] for r in ok]) if ok else np.array([np.nan])
    ev = np.array([r["ev"] for r in ok]) if ok else np.array([0])
    return (f"success {len(ok)}/{len(rows)} ({len(ok) / len(rows):.1%}), false successes {len(false)}\n"
            f"    time per plan (verify=False) median {np.median(t):.0f} ms p90 {np.percentile(t, 90):.0f} ms max "
            f"{t.max():.0f} ms (mean {t.mean():.0f} ms); the Pinocchio check median {np.median(tc):.0f} ms\n"
            f"    evaluations median {np.median(ev):.0f} max {ev.max()}; max|u| median {np.median(u):.2f} max "
            f"{np.max(u):.2f} rad/s\n"
            f"    Pinocchio re-check of every success: median {np.median(errs):.1e} max {np.max(errs):.1e}")


def two_joint_cat_turn():
    """The issue's two-joint cat (zoo.two_joint_cat): 180 deg about its long axis at L = 0 in 1 s, from
    bend 0.6, sway 0 back to it."""
    from acroplan.families.spatial.zoo import long_axis_turn, two_joint_cat

    cat = two_joint_cat()
    return cat, long_axis_turn(cat, [0.6, 0.0], 1.0)


def examples():
    from acroplan.families.spatial.examples import EXAMPLES

    for name, make in dict(EXAMPLES, **{"two-joint-cat (issue #22)": two_joint_cat_turn}).items():
        acroplan.warm_up(make()[0])
        body, kw = make()
        t0 = time.perf_counter()
        r = acroplan.plan(body, **kw)
        dt = time.perf_counter() - t0
        print(f"\nexample {name}: {r.status} in {dt:.2f} s ({len(r.segments)} segment(s), "
              f"{r.evaluations} evaluations); {r.message}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=50)
    ap.add_argument("--seed", type=int, default=2024)
    ap.add_argument("--links", type=int, nargs="+", default=[3, 4, 5])
    ap.add_argument("--examples", action="store_true", help="plan the bundled examples too")
    ap.add_argument("--tree", action="store_true", help="random trees (random parents) instead of chains")
    args = ap.parse_args()
    import pinocchio

    print(f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, pinocchio {pinocchio.__version__}; n = {args.n} per population, seed "
          f"{args.seed}, conditions='free'")
    total = []
    for links in args.links if args.n > 0 else ():  # --n 0: the examples alone
        run(population(args.seed + 1, 2, links, True, args.tree))  # compile, build the Pinocchio models, untimed
        for momentum in (False, True):
            rows = run(population(args.seed, args.n, links, momentum, args.tree))
            total += rows
            kind = "trees" if args.tree else "links"
            print(f"\n{links} {kind}, L {'!= 0' if momentum else '= 0'}: {summary(rows)}", flush=True)
            for r in [r for r in rows if not (r["ok"] and r["err"] <= CHECK_TOL)][:5]:
                print(f"    failure: {r['msg'][:300]}")
    if total:
        print(f"\nall populations: {summary(total)}")
    if args.examples:
        examples()


if __name__ == "__main__":
    main()
