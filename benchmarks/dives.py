"""The 3-D human's bundled twisting dives (issue #23): each planned (``acroplan.plan`` of
``acroplan.examples.load(name)``, the Pinocchio check included), its time, its counts
in Yeadon's angles, its peak rate and torque against the data's limits.

The first plan in the process includes compiling the 5-link body; ``--repeat 2`` plans each dive
again (warm). ``--objective energy`` (or ``torque``) plans the optimal plan instead of the feasible
one; ``--tau-max`` adds the strength data's torque limits (``strength.torque_limits``).

Run:  python benchmarks/dives.py [--dives back-full-twist ...] [--repeat 2] [--objective energy] [--tau-max]
"""

from __future__ import annotations

import argparse
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
    ap.add_argument("--objective", choices=("energy", "torque"), default=None)
    ap.add_argument("--tau-max", action="store_true")
    args = ap.parse_args()
    print(f"# {platform.processor() or platform.machine()}, python {platform.python_version()}")
    for name in args.dives:
        prob = examples.load(name)
        body, kw = prob.system, prob.plan_kwargs()
        extra = {}
        if args.objective:
            extra["objective"] = args.objective
        if args.tau_max:
            extra["tau_max"] = torque_limits(body)
        for k in range(args.repeat):
            t0 = time.perf_counter()
            res = acroplan.plan(body, **{**kw, **extra})  # the options given here replace the file's
            dt = time.perf_counter() - t0
            line = f"{name} [{'cold' if k == 0 else 'warm'}] {res.status} in {dt:.1f} s"
            if res.status == "success":
                line += ": " + dive_report(res).summary()
            print(line, flush=True)


if __name__ == "__main__":
    main()
