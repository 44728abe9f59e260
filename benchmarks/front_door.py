"""What a two-link plan spends around its planner: ``acroplan.plan(..., verify=False)`` against the
acrobot's strategy alone (``AcrobotAuto.solve`` on the same interval), on every third of the first
30 random segments of ``plan_overhead.py`` (seed 11), the fastest of 5 x 100 calls each (wall time,
``timeit``); medians over the problems. The difference is the front door: validation, the
feasibility test, the result, the plausibility check, the progress and the budget.

For another source tree (an older commit), put its ``src`` first on ``PYTHONPATH``.

Run:  python benchmarks/front_door.py
"""

from __future__ import annotations

import timeit

import numpy as np

import acroplan
from acroplan.families.acrobot import flat
from acroplan.zoo import random_segment


def main() -> None:
    rng = np.random.default_rng(11)
    problems = [random_segment(rng) for _ in range(30)]
    problems = [dict(system=p.robot, conditions="free", **p.plan_kwargs()) for p in problems]
    solve = flat.AcrobotAuto.solve
    seen = {}

    def watched(self, interval):
        seen["call"] = (self, interval)
        return solve(self, interval)

    rows = []
    for p in problems[::3]:
        flat.AcrobotAuto.solve = watched
        try:
            acroplan.plan(**p, verify=False)
        finally:
            flat.AcrobotAuto.solve = solve
        strategy, interval = seen["call"]
        whole = min(timeit.repeat(lambda: acroplan.plan(**p, verify=False), number=100, repeat=5)) / 100
        alone = min(timeit.repeat(lambda: solve(strategy, interval), number=100, repeat=5)) / 100
        rows.append((whole, alone))
    r = np.array(rows) * 1e6
    print(f"acroplan {acroplan.__version__}: plan median {np.median(r[:, 0]):.1f} us, the strategy alone "
          f"{np.median(r[:, 1]):.1f} us, the front door (the difference) median {np.median(r[:, 0] - r[:, 1]):.1f} us")


if __name__ == "__main__":
    main()
