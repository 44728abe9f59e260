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

Run:  python benchmarks/serial_cpu.py [--n 2000] [--seed 5] [--repeat 3] [--loop]
"""

from __future__ import annotations

import argparse
import time

import acroplan
from batch import problems as batch_problems  # batch.py's population (this folder is on sys.path)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--loop", action="store_true", help="a loop of acroplan.plan instead of plan_many")
    args = ap.parse_args()
    problems = batch_problems(args.n, args.seed)

    def run(probs):  # no progress shown, on a terminal or not: its updates are not what is timed
        if args.loop:
            return [acroplan.plan(**p, verify=False, progress=False) for p in probs]
        return acroplan.plan_many(probs, executor="serial", verify=False, progress=False)

    run(problems[:200])
    best = None
    for _ in range(args.repeat):
        c0, t0 = time.process_time(), time.perf_counter()
        out = run(problems)
        c, t = time.process_time() - c0, time.perf_counter() - t0
        best = (c, t) if best is None or c < best[0] else best
    ok = sum(r.success for r in out)
    what = "a loop of plan()" if args.loop else "plan_many(executor='serial')"
    print(f"acroplan {acroplan.__version__}, {what}: {args.n} problems (seed {args.seed}, {ok} planned), fastest of "
          f"{args.repeat}: CPU {best[0]:.3f} s ({best[0] / args.n * 1e3:.3f} ms a plan), wall {best[1]:.3f} s")


if __name__ == "__main__":
    main()
