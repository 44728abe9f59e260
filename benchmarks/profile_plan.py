"""Where a single-segment plan spends its time: pyinstrument over warm acroplan.plan calls.

Problems: random physical single segments from acroplan.zoo (seed 11), conditions="free",
verify=False, each planned after a warm-up pass (integrators compiled, caches filled).

Run:  python benchmarks/profile_plan.py [--n 400] [--depth 9]      (needs: pip install ".[bench]")
"""

from __future__ import annotations

import argparse

import numpy as np
from pyinstrument import Profiler

import acroplan
from acroplan.zoo import random_segment


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=400)
    ap.add_argument("--depth", type=int, default=9)
    args = ap.parse_args()
    rng = np.random.default_rng(11)
    problems = [random_segment(rng) for _ in range(args.n)]
    acroplan.warm_up(acroplan.Acrobot)
    for p in problems:
        acroplan.plan(p.robot, conditions="free", verify=False, **p.plan_kwargs())
    profiler = Profiler(interval=0.0001)
    profiler.start()
    for p in problems:
        acroplan.plan(p.robot, conditions="free", verify=False, **p.plan_kwargs())
    profiler.stop()
    text = profiler.output_text(unicode=False, color=False, show_all=False)
    lines = [ln for ln in text.splitlines() if ln.strip()]
    start = next(i for i, ln in enumerate(lines) if "plan " in ln and "acroplan/planning.py" in ln)
    indent = len(lines[start]) - len(lines[start].lstrip())
    for ln in lines[start:]:
        depth = (len(ln) - len(ln.lstrip(" |`-")) - indent) // 3
        if depth <= args.depth:
            print(ln)


if __name__ == "__main__":
    main()
