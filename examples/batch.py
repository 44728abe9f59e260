"""Many problems at once with plan_many: results in input order, failures reported, not raised.

Run:  python examples/batch.py
"""

import numpy as np

import acroplan
from acroplan.zoo import random_segment

rng = np.random.default_rng(1)
problems = []
for _ in range(20):
    p = random_segment(rng)
    problems.append(dict(system=p.robot, conditions="free", **p.plan_kwargs()))
lo, hi = problems[0]["system"].reachable_interval(theta0=problems[0]["theta"][0], phi0=problems[0]["phi"][0],
                                                  phiT=problems[0]["phi"][1], T=problems[0]["times"][1])
problems.append({**problems[0], "theta": [problems[0]["theta"][0], hi + 1.0]})  # one impossible request

results = acroplan.plan_many(problems, executor="thread", workers=2)
print([r.status for r in results])
assert [r.status for r in results[:-1]] == ["success"] * 20 and results[-1].status == "infeasible"
