"""One evaluation of an optimal 3-D plan, part by part: where a twisting dive's optimiser spends the
time of each of its endpoint evaluations (issues #22 and #23).

The bundled forward dive (``acroplan.io.examples.load("forward-double-twist")``, the 3-D human
with its arms, 75 kg m^2/s of angular momentum) is planned once; at its second interval's optimum
(30 Legendre coefficients per joint, 4 joints) each part of what the SQP asks at a new point is
timed on inputs moved by 1e-6 per call (so that no memo serves a call with the previous one's
numbers), in the optimiser's order: the endpoint and its Jacobian first (its momentum solve is
remembered for the torques at the same coefficients), then the torque limits' rows (torques and
their Jacobian on 65 and on 257 points: the first and the denser grid) and the torque cost (96
Gauss-Legendre nodes, the gradient and the Gauss-Newton Hessian). The momentum's parts are timed
alone too: the panels' layout, the Newton solves of the momentum on them, the derivative sweep of
the torques' momentum samples, and the torque Jacobian's chain rule on 257 instants.

Times are medians of ``--repeat`` calls, in ms, on one thread of OpenBLAS when run as below (the
planner's calls are single-threaded; a second BLAS thread only adds noise).

Run:  OPENBLAS_NUM_THREADS=1 python benchmarks/evaluation_parts.py [--repeat 40]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

import acroplan
from acroplan.core.objectives import TorqueCost, call_torque
from acroplan.families.spatial import collocation as colloc
from acroplan.families.spatial import collocation_parts as parts
from acroplan.families.spatial.dynamics import joint_torques
from acroplan.families.tree import motion
from acroplan.io import examples


def median_ms(fn, c, repeat, before=None):
    """The median time of ``fn(c + k 1e-6)`` over ``repeat`` calls (ms), ``before(c')`` untimed first."""
    out = []
    for k in range(repeat):
        ck = c + 1e-6 * (k + 1)
        if before is not None:
            before(ck)
        t = time.perf_counter()
        fn(ck)
        out.append(time.perf_counter() - t)
    return 1e3 * float(np.median(out))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=40)
    args = ap.parse_args()
    prob = examples.load("forward-double-twist")
    body, kw = prob.system, prob.plan_kwargs()
    print("# planning the forward dive once (its torque optimum: seconds, the first time with compiling)", flush=True)
    res = acroplan.plan(body, **kw)
    print(f"# planned: {res.status}; timing each part {args.repeat} times", flush=True)
    seg = res.segments[1]
    basis, c = seg.basis, seg.basis_coefficients
    x0, T = np.asarray(seg.start, dtype=float), seg.t1 - seg.t0
    model = body.torque_model()
    cost = TorqueCost(model, body, basis, x0, T)
    grids = {K: np.linspace(0.0, 1.0, K) for K in (65, 257)}
    r = args.repeat

    def endpoint(ck):
        return colloc.endpoint(body, basis, x0, T, ck)

    def one(ck):
        return colloc._Segment(body, basis, x0, T, ck)

    rows = [("endpoint and Jacobian (momentum solve included)", median_ms(endpoint, c, r)),
            ("endpoint alone, no Jacobian", median_ms(lambda ck: colloc.endpoint(body, basis, x0, T, ck,
                                                                                   jacobian=False), c, r))]
    for K, s in grids.items():
        rows.append((f"torques and Jacobian on {K} points, after the endpoint",
                     median_ms(lambda ck: call_torque(model, body, basis, x0, T, ck, s), c, r, endpoint)))
    rows.append(("torque cost, gradient, Gauss-Newton Hessian (96 nodes), after the endpoint",
                 median_ms(lambda ck: cost(ck.ravel()), c, r, endpoint)))
    layout = parts._layout(one(c))
    rows += [("the panels' layout", median_ms(lambda ck: parts._layout(one(ck)), c, r)),
             (f"the momentum's Newton solves on {layout[1].size} panels",
              median_ms(lambda ck: colloc._momentum(one(ck), *layout), c, r)),
             ("the momentum samples' derivative sweep", median_ms(lambda ck: colloc._sweep(one(ck), True), c, r,
                                                                    lambda ck: colloc._first_momentum(one(ck))))]
    s = grids[257]
    m = body.n_inputs
    tables = motion.basis_tables(basis, s)
    q, u, du = motion.joint_motion(x0[4:], T, c, tables)
    lam = colloc.momentum_samples(body, basis, x0, T, c, s)
    P = joint_torques(body.links, q, u, du, lam, derivatives=True)[1]
    rows.append(("the torque Jacobian's chain rule on 257 instants",
                 median_ms(lambda ck: motion.coefficient_jacobian(P[:, :, :m], P[:, :, m:2 * m], P[:, :, 2 * m:3 * m],
                                                                  T, tables), c, r)))
    print(f"# {platform.processor() or platform.machine()}, python {platform.python_version()}; forward dive, "
          f"interval 2: {m} joints, {basis.n} coefficients, L = {np.linalg.norm(body.angular_momentum):.1f} kg m^2/s; "
          f"median of {r} calls")
    for name, ms in rows:
        print(f"  {name:<78} {ms:7.3f} ms")


if __name__ == "__main__":
    main()
