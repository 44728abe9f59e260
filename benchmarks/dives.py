"""The 3-D human's bundled twisting dives (issue #23): each planned (``acroplan.plan`` of
``acroplan.examples.load(name)``, the Pinocchio check included), its time, its counts
in Yeadon's angles, its peak rate and torque against the data's limits.

Each line gives the plan's time, its cost (the sum of its segments' optimal costs; 0 for a
feasible plan) and its endpoint evaluations (the intervals' own, the feasible start's included,
and the joint optimum's), then the counts in Yeadon's angles. The first plan in
the process includes compiling the 5-link body; ``--repeat 2`` plans each dive
again (warm). By default each file's own options (each asks for an optimal plan within the
strength data); ``--objective energy``, ``torque`` or ``none`` (the feasible plan) replaces the
file's objective, and ``--tau-max strength`` or ``none`` its torque limits (``strength``: the
strength data's, ``strength.torque_limits``).

``--stages`` also gives each plan's wall time by stage (wrappers that add microseconds): the
feasible plan each interval starts from (the family's ``method="auto"`` strategy), the first size's
optimum from it (``_Search.first_stage``), the ladder of basis sizes, the reported size's
refinement and dense check (``_Search.report``; for an interval whose optimum only starts the
joint optimum, its dense check alone: ``optimal.PROVISIONAL_STARTS``), the intervals' joint
optimum, the independent check (the front's ``_verified``) and the rest.

Run:  python benchmarks/dives.py [--dives back-full-twist ...] [--repeat 2] [--objective energy|torque|none]
      [--tau-max strength|none] [--stages]
"""

from __future__ import annotations

import argparse
import collections
import platform
import time

import acroplan
from acroplan.families.human.dives import DIVES, dive_report
from acroplan.io import examples
from acroplan.families.human.strength import torque_limits


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dives", nargs="*", default=list(DIVES))
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--objective", choices=("energy", "torque", "none"), default=None,
                    help="replaces the file's objective (none: the feasible plan)")
    ap.add_argument("--tau-max", choices=("strength", "none"), default=None,
                    help="replaces the file's torque limits")
    ap.add_argument("--stages", action="store_true", help="each plan's wall time by stage too")
    args = ap.parse_args()
    spent = timed_stages() if args.stages else None
    print(f"# {platform.processor() or platform.machine()}, python {platform.python_version()}")
    for name in args.dives:
        prob = examples.load(name)
        body, kw = prob.system, prob.plan_kwargs()
        extra = {}
        if args.objective is not None:
            kw.pop("objective", None)
            if args.objective != "none":
                extra["objective"] = args.objective
        if args.tau_max is not None:
            kw.pop("tau_max", None)
            if args.tau_max == "strength":
                extra["tau_max"] = torque_limits(body)
        for k in range(args.repeat):
            if spent is not None:
                spent.clear()
            t0 = time.perf_counter()
            res = acroplan.plan(body, **{**kw, **extra})  # the options given here replace the file's
            dt = time.perf_counter() - t0
            # the cost and the endpoint evaluations: on a noisy machine the count, not the time,
            # tells whether a change moved the optimiser's path
            cost = sum((s.optimality or {}).get("cost") or 0.0 for s in res.segments)
            joint = ((res.segments[0].optimality or {}).get("joint") or {}) if res.segments else {}
            own = sum(s.evaluations for s in res.segments)
            line = (f"{name} [{'cold' if k == 0 else 'warm'}] {res.status} in {dt:.1f} s, cost {cost!r}, "
                    f"{own + (joint.get('evaluations') or 0)} endpoint evaluations (the intervals' {own}, the "
                    f"joint optimum's {joint.get('evaluations') or 0})")
            if res.status == "success":
                line += ": " + dive_report(res).summary()
            print(line, flush=True)
            if spent is not None:
                parts = ", ".join(f"{label} {spent[label]:.2f}" for label in STAGES if label in spent)
                print(f"    stages (s): {parts}, the rest {dt - sum(spent.values()):.2f}", flush=True)


#: The labels of the stages :func:`timed_stages` times, in the order printed
STAGES = ("feasible", "first stage", "ladder", "report", "joint", "check")


def timed_stages() -> collections.Counter:
    """Wrap each stage's function (no stage calls another) so that its wall time adds up, by
    label, in the returned counter."""
    from acroplan.core import optimal
    from acroplan.families.spatial import strategy
    from acroplan.planning import front

    from serial_cpu import cpu_timed  # this folder is on sys.path

    spent = collections.Counter()
    for owner, name, label in ((strategy.SpatialAuto, "solve", "feasible"), (optimal._Search, "first_stage", "first stage"),
                               (optimal._Search, "ladder", "ladder"), (optimal._Search, "report", "report"),
                               (optimal.EnergyOptimal, "joint", "joint"), (front, "_verified", "check")):
        cpu_timed(spent, owner, name, label, clock=time.perf_counter)  # wall time
    return spent


if __name__ == "__main__":
    main()
