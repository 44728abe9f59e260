"""A two-link plan's time, in CPU time, and the front door's parts of it: what every plan pays
around the planner (the request's validation, the plausibility check, the progress), the figure
the "nothing slower elsewhere" comparisons of benchmarks/RESULTS.md use (thirteenth session).

Problems: the first ``--n`` of ``acroplan.zoo.random_segment(np.random.default_rng(SEED))`` (random
physical single segments, targets inside the exact reachable interval), ``conditions="free"``,
``verify=False``. Each problem is planned ``--repeat`` times after one warm-up pass and keeps its
fastest plan (``time.process_time``: the machine's other load moves wall time by 25% within an
hour here); the medians are over the problems. ``--parts`` also times the front door's pieces
(``PlanRequest.build``, ``_plan_intervals``, ``_plausible``) of each problem's fastest plan; the
wrappers add a few microseconds, so the total without ``--parts`` is the figure to compare.

For another source tree (an older commit), put its ``src`` first on ``PYTHONPATH``; ``--parts``
needs the ``acroplan.planning`` package (since ca0a696).

CPU time counts every thread of the process: a tree from before ``plan()`` held BLAS at one thread
(``acroplan.core.blas``, fifteenth session) spends its BLAS threads' spinning too, so compare with
one under ``OPENBLAS_NUM_THREADS=1``.

Run:  python benchmarks/plan_overhead.py [--n 100] [--seed 11] [--repeat 4] [--parts]
"""

from __future__ import annotations

import argparse
import collections
import time

import numpy as np

import acroplan
from acroplan.zoo import random_segment


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--repeat", type=int, default=4)
    ap.add_argument("--parts", action="store_true", help="time the front door's pieces too")
    args = ap.parse_args()
    spent = collections.defaultdict(float)
    if args.parts:
        import acroplan.planning.front as front
        import acroplan.planning.request as request
        from serial_cpu import cpu_timed  # this folder is on sys.path

        cpu_timed(spent, front, "_plan_intervals")
        cpu_timed(spent, front, "_plausible")
        cpu_timed(spent, request.PlanRequest, "build")
    rng = np.random.default_rng(args.seed)
    problems = [random_segment(rng) for _ in range(args.n)]
    problems = [dict(system=p.robot, conditions="free", **p.plan_kwargs()) for p in problems]
    for p in problems:
        acroplan.plan(**p, verify=False)
    best = collections.defaultdict(lambda: [np.inf] * len(problems))
    for _ in range(args.repeat):
        for i, p in enumerate(problems):
            spent.clear()
            t = time.process_time()
            acroplan.plan(**p, verify=False)
            dt = time.process_time() - t
            if dt < best["total"][i]:
                best["total"][i] = dt
                for name, v in spent.items():
                    best[name][i] = v
    print(f"acroplan {acroplan.__version__}: {args.n} random two-link segments (seed {args.seed}), "
          f"fastest of {args.repeat} each, CPU time")
    for name, v in best.items():
        print(f"  {name:16s} median {np.median(v) * 1e3:.3f} ms, mean {np.mean(v) * 1e3:.3f} ms")


if __name__ == "__main__":
    main()
