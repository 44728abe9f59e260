"""The acrobot's fixed costs, measured in one run: compiling its integrators, a thread's copy of a
compiled integrator, and the independent check of a plan.

  compile  a first compilation of the integrator at each basis size ``plan`` may use (6, 10, 14), in
           a fresh process with heyoka's on-disk cache off (``ACROPLAN_HEYOKA_CACHE=off``), then
           from the on-disk cache (a fresh process on a temporary cache filled by one run before):
           wall and CPU seconds of ``backend.compile_for`` (the first size also builds the
           symbolic fields);
  copy     ``copy.copy`` of the compiled template (what each thread of a process makes once);
  verify   warm single-segment plans (``acroplan.zoo.random_segment``, ``conditions="free"``) with
           ``verify=False``, ``True`` (the acrobot's exact flat-output identity) and ``"ode"``
           (the scipy DOP853 re-simulation): median and p90 per plan, the fastest of ``--repeat``.

Run:  python benchmarks/acrobot_costs.py [--n 100] [--seed 11] [--repeat 3]
"""

from __future__ import annotations

import argparse
import copy
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

SIZES = (6, 10, 14)

CHILD = r"""
import json, sys, time
import acroplan
from acroplan.core import backend
from acroplan.core.basis import Legendre
robot = acroplan.Acrobot.example()
out = []
for n in map(int, sys.argv[1:]):
    t, c = time.perf_counter(), time.process_time()
    backend.compile_for(robot, Legendre, n)
    out.append([n, time.perf_counter() - t, time.process_time() - c])
print(json.dumps(out))
"""


def compile_times(cache: str) -> list:
    env = {**os.environ, "ACROPLAN_HEYOKA_CACHE": cache, "PYTHONWARNINGS": "ignore"}
    p = subprocess.run([sys.executable, "-c", CHILD, *map(str, SIZES)], env=env, capture_output=True, text=True,
                       check=True)
    return json.loads(p.stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=100)
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"command: python benchmarks/acrobot_costs.py --n {args.n} --seed {args.seed} --repeat {args.repeat}; "
          f"load average {os.getloadavg()[0]:.1f} at the start")
    for label, rows in [("cache off", compile_times("off"))] + [("from the disk cache", None)]:
        if rows is None:
            with tempfile.TemporaryDirectory() as d:
                compile_times(d)
                rows = compile_times(d)
        print(f"compile ({label}): " + ", ".join(f"n = {n}: {w:.3f} s wall, {c:.3f} s CPU" for n, w, c in rows))

    import acroplan
    from acroplan.core import backend
    from acroplan.core.basis import Legendre
    from acroplan.zoo import random_segment

    template = backend.compile_for(acroplan.Acrobot.example(), Legendre, 14)
    ts = []
    for _ in range(20):
        t = time.perf_counter()
        copy.copy(template)
        ts.append(time.perf_counter() - t)
    print(f"copy of the 14-coefficient template: median {np.median(ts) * 1e3:.2f} ms, min {min(ts) * 1e3:.2f} ms")

    rng = np.random.default_rng(args.seed)
    problems = [random_segment(rng) for _ in range(args.n)]
    acroplan.warm_up(acroplan.Acrobot)
    for verify in (False, True, "ode"):
        best = []
        for p in problems:
            ts = []
            for _ in range(args.repeat):
                t = time.perf_counter()
                acroplan.plan(p.robot, conditions="free", verify=verify, **p.plan_kwargs())
                ts.append(time.perf_counter() - t)
            best.append(min(ts))
        print(f"plan(verify={verify!r}): median {np.median(best) * 1e3:.3f} ms, p90 {np.percentile(best, 90) * 1e3:.3f} ms")


if __name__ == "__main__":
    main()
