"""What the plausibility check's warnings cost: random two-link single segments (``batch.py``'s
population, ``acroplan.zoo.random_segment``, seed 5, ``conditions="free"``, ``verify=False``),
each planned 3 times after one warm-up pass and kept at its fastest (CPU time), split into the
plans the check flags (``result.warnings``) and the others.

For another source tree (an older commit, without the check: its plans are all "clean"), put its
``src`` first on ``PYTHONPATH``; ``--flagged FILE`` then takes the indices of the plans flagged by
the newer tree (``--write-flagged FILE`` writes them) so that the same problems are compared.

CPU time counts every thread of the process: a tree from before ``plan()`` held BLAS at one thread
(``acroplan.core.blas``, fifteenth session) spends its BLAS threads' spinning too, so compare with
one under ``OPENBLAS_NUM_THREADS=1``.

Run:  python benchmarks/flagged_plans.py [--n 400] [--write-flagged F | --flagged F]
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

import acroplan
from acroplan.zoo import random_segment


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--write-flagged", metavar="FILE", help="write the indices of the flagged plans here")
    ap.add_argument("--flagged", metavar="FILE", help="take the flagged plans' indices from here")
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    problems = [random_segment(rng) for _ in range(args.n)]
    problems = [dict(system=p.robot, conditions="free", **p.plan_kwargs()) for p in problems]
    for p in problems:
        acroplan.plan(**p, verify=False)
    best, warned = [], []
    for p in problems:
        fastest = np.inf
        for _ in range(3):
            t = time.process_time()
            r = acroplan.plan(**p, verify=False)
            fastest = min(fastest, time.process_time() - t)
        best.append(fastest)
        warned.append(bool(getattr(r, "warnings", ())))
    best = np.array(best) * 1e3
    flagged = np.array(warned)
    if args.flagged:
        flagged = np.zeros(len(best), dtype=bool)
        flagged[json.loads(open(args.flagged).read())] = True
    if args.write_flagged:
        with open(args.write_flagged, "w") as f:
            json.dump([int(i) for i in np.flatnonzero(flagged)], f)
    print(f"acroplan {acroplan.__version__}: {args.n} random two-link segments (seed {args.seed}), fastest of 3, "
          f"CPU time")
    print(f"  all      mean {best.mean():.3f} ms, median {np.median(best):.3f} ms")
    for name, sel in (("flagged", flagged), ("clean", ~flagged)):
        if sel.any():
            print(f"  {name:8s} {sel.sum()} plans, mean {best[sel].mean():.3f} ms, median {np.median(best[sel]):.3f} ms")


if __name__ == "__main__":
    main()
