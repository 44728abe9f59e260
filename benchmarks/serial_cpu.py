"""The CPU time of ``batch.py``'s random two-link problems planned one after another in one process:
``acroplan.plan_many(..., executor="serial")`` or a loop of ``acroplan.plan`` (``--loop``), the
fastest of ``--repeat`` passes after a warm-up on the first 200. It weighs every plan as it comes,
so the plans the plausibility check flags (one in nine) count by their share; the medians of
``plan_overhead.py`` do not see them.

Problems: ``batch.py``'s (the first ``--n`` of ``acroplan.zoo.random_segment`` from
``np.random.default_rng(SEED)``, ``conditions="free"``), ``verify=False``, no progress shown; the
results' warnings are not read (a flagged plan's exact peak rate, torque and power are worked out
when they are: ``batch.py`` prints what that costs).

For another source tree (an older commit), put its ``src`` first on ``PYTHONPATH``, and alternate
the two in separate processes (this machine's speed moves by a fifth within minutes). CPU time
counts every thread of the process: compare with a tree from before ``plan()`` held BLAS at one
thread (``acroplan.core.blas``) under ``OPENBLAS_NUM_THREADS=1``.

``--parts`` also gives each plan's mean CPU time in its parts (the fastest pass's), by wrappers
that add about a microsecond each: the request's validation (``PlanRequest.build``), the exact
feasibility test (the family's ``check_segment``; in a tree with ``acroplan.planning``, the
front's ``_infeasible`` around it), the strategy that plans the interval (the two-link family's
``AcrobotAuto.solve``), the plausibility check (``_plausible``, since issue #24), and the rest
(the front door's own work). It finds each part by name in the tree it runs, so it compares a
tree from before the front door's package (639160b: ``acroplan/planning.py``) with one after.

Run:  python benchmarks/serial_cpu.py [--n 2000] [--seed 5] [--repeat 3] [--loop] [--parts]
"""

from __future__ import annotations

import argparse
import collections
import functools
import importlib.util
import time

import acroplan
from batch import problems as batch_problems  # batch.py's population (this folder is on sys.path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--loop", action="store_true", help="a loop of acroplan.plan instead of plan_many")
    ap.add_argument("--parts", action="store_true", help="each plan's mean CPU time in its parts too")
    args = ap.parse_args()
    spent = timed_parts() if args.parts else None
    problems = batch_problems(args.n, args.seed)
    # no progress shown, on a terminal or not: its updates are not what is timed (a tree from
    # before acroplan.core.progress, 4439547, shows none and takes a callable there)
    quiet = {"progress": False} if importlib.util.find_spec("acroplan.core.progress") else {}

    def run(probs):
        if args.loop:
            return [acroplan.plan(**p, verify=False, **quiet) for p in probs]
        return acroplan.plan_many(probs, executor="serial", verify=False, **quiet)

    run(problems[:200])
    best, parts = None, None
    for _ in range(args.repeat):
        if spent is not None:
            spent.clear()
        c0, t0 = time.process_time(), time.perf_counter()
        out = run(problems)
        c, t = time.process_time() - c0, time.perf_counter() - t0
        if best is None or c < best[0]:
            best, parts = (c, t), dict(spent or {})
    ok = sum(r.success for r in out)
    what = "a loop of plan()" if args.loop else "plan_many(executor='serial')"
    print(f"acroplan {acroplan.__version__}, {what}: {args.n} problems (seed {args.seed}, {ok} planned), fastest of "
          f"{args.repeat}: CPU {best[0]:.3f} s ({best[0] / args.n * 1e3:.3f} ms a plan), wall {best[1]:.3f} s")
    if parts is not None:
        us = {k: v / args.n * 1e6 for k, v in parts.items()}
        inner = us.get("check_segment", 0.0) if "_infeasible" in us else 0.0
        rest = best[0] / args.n * 1e6 - sum(us.values()) + inner
        print("  parts, mean us a plan: " + ", ".join(f"{k} {v:.1f}" for k, v in us.items()) + f", the rest {rest:.1f}"
              + (" (check_segment is inside _infeasible)" if "_infeasible" in us else ""))


def cpu_timed(spent, owner, name: str, label: str | None = None, clock=time.process_time) -> None:
    """Replace ``owner.name`` by a wrapper that adds its CPU time (or the time of ``clock``) to
    ``spent[label or name]`` (also used by ``plan_overhead.py --parts`` and ``dives.py --stages``)."""
    f = getattr(owner, name)

    @functools.wraps(f)
    def g(*a, **k):
        t = clock()
        try:
            return f(*a, **k)
        finally:
            spent[label or name] += clock() - t
    setattr(owner, name, g)


def timed_parts() -> collections.Counter:
    """Wrap the parts of a plan (module docstring) found in this tree with CPU-time counters."""
    import acroplan.planning
    from acroplan.families.acrobot import flat
    from acroplan.families.acrobot.model import Acrobot

    spent: collections.Counter = collections.Counter()

    if hasattr(acroplan.planning, "__path__"):  # the front door's package
        import acroplan.planning.front as front
        import acroplan.planning.request as request

        cpu_timed(spent, request.PlanRequest, "build", "PlanRequest.build")
        cpu_timed(spent, front, "_infeasible", "_infeasible")
        cpu_timed(spent, front, "_plausible", "_plausible")
    else:  # 639160b's single module
        import acroplan.planning as front

        cpu_timed(spent, front.PlanRequest, "build", "PlanRequest.build")
    cpu_timed(spent, Acrobot, "check_segment", "check_segment")
    cpu_timed(spent, flat.AcrobotAuto, "solve", "AcrobotAuto.solve")
    return spent


if __name__ == "__main__":
    main()
