"""Which input basis to use inside the planner: monomial (the text's t^i) or shifted Legendre.

For each basis and size it reports, on random physical single-segment problems (acroplan.zoo,
conditions="free") and on the pike dive (conditions="spline"):
  * success rate;
  * median condition number of the full endpoint Jacobian D Phi at the solution;
  * median endpoint evaluations.

Run:  python benchmarks/basis_conditioning.py [N]
"""

import sys

import numpy as np

import acroplan
from acroplan.core import backend as _integrate
from acroplan.core.basis import make_basis
from acroplan.zoo import random_segment


def main(n_problems: int = 200):
    print(f"{'basis':10s} {'n':>3s} {'success':>9s} {'median cond(DPhi)':>18s} {'median evals':>13s}  pike-dive")
    for n in (6, 10, 14):
        for name in ("monomial", "legendre"):
            rng = np.random.default_rng(7)
            ok, conds, evals = 0, [], []
            for _ in range(n_problems):
                p = random_segment(rng)
                r = acroplan.plan(p.robot, conditions="free", basis=name, n_coefficients=n, verify=False,
                                  **p.plan_kwargs())
                if r.success:
                    ok += 1
                    seg = r.segments[0]
                    _, J = _integrate.endpoint(p.robot, make_basis(name, n), seg.start, seg.t1 - seg.t0,
                                               seg.basis_coefficients)
                    s = np.linalg.svd(J, compute_uv=False)
                    conds.append(s[0] / s[-1])
                    evals.append(seg.evaluations)
            pike = acroplan.examples.load("pike-dive")
            rp = acroplan.plan(pike.robot, times=pike.times, theta=pike.theta, phi=pike.phi, basis=name,
                               n_coefficients=n, verify=True)
            print(f"{name:10s} {n:3d} {ok / n_problems:9.1%} {np.median(conds):18.3g} {np.median(evals):13.0f}  "
                  f"{rp.status}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 200)
