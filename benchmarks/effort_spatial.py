"""The effort summary of 3-D plans against the plans' own time (issue #22: at most 10%).

For each case the plan (``verify=False``) and its effort summary (``result.effort()``: peaks,
positive and net work, the integrals of tau^2, on a fresh result so nothing is cached) are timed
back to back, ``--repeat`` times, after one warm run (compiled maps and torque functions built);
the fastest of each counts, in wall and in CPU time (``time.process_time``: on a shared machine the
CPU time is the steadier), and the summary's calls of the torque model are counted.

Cases: the falling cat (examples.falling_cat_turn, method "auto"), bioptim's trunk twist
(examples.trunk_twist) torque-optimal, and the twisting somersault (examples.twisting_somersault,
two segments, method "auto").

Run:  python benchmarks/effort_spatial.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import time

import acroplan
from acroplan.core import result as result_module
from acroplan.families.spatial.examples import falling_cat_turn, trunk_twist, twisting_somersault

CASES = {"falling cat (auto)": (falling_cat_turn, {}), "trunk twist (torque-optimal)": (trunk_twist,
                                                                                         {"objective": "torque"}),
         "twisting somersault (auto)": (twisting_somersault, {})}


def _timed(fn):
    t, c = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - t, time.process_time() - c


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    calls = [0]
    inner = result_module.PlanResult._segment_torques

    def counted(self, *a, **k):
        calls[0] += 1
        return inner(self, *a, **k)

    result_module.PlanResult._segment_torques = counted
    for name, (make, extra) in CASES.items():
        body, kw = make()
        acroplan.plan(body, verify=False, **extra, **kw).effort()  # warm
        plans, efforts = [], []
        for _ in range(args.repeat):
            r, w, c = _timed(lambda: acroplan.plan(body, verify=False, **extra, **kw))
            plans.append((w, c))
            calls[0] = 0
            _, w, c = _timed(r.effort)
            efforts.append((w, c))
        pw, pc = min(p[0] for p in plans), min(p[1] for p in plans)
        ew, ec = min(e[0] for e in efforts), min(e[1] for e in efforts)
        print(f"{name}: {r.status}, {len(r.segments)} segment(s); plan {pw:.3f} s wall, {pc:.3f} s CPU; effort "
              f"summary {1e3 * ew:.2f} ms wall, {1e3 * ec:.2f} ms CPU ({calls[0]} torque-model calls): {100 * ew / pw:.1f}% of "
              f"the plan's wall time, {100 * ec / pc:.1f}% of its CPU time")


if __name__ == "__main__":
    main()
