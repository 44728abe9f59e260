"""Throughput of acroplan.plan_many and the single-plan time distribution, measured in one run.

Problems: random physical single segments from acroplan.zoo (targets in the middle 96% of the
exact reachable interval), conditions="free", verify=False (the planner's own cost; the
independent re-simulation is a separate, optional check).

It reports:
  single   warm acroplan.plan one by one: median, p90, mean per plan, and which basis size and how
           many endpoint evaluations the plans needed;
  batch    acroplan.plan_many with each executor ("serial", "thread", "process") on the same
           problems, wall time from the call to the last result (process: pool start, parent-side
           validation, compilation in the parent and result transfer included), plans per second;
           after the serial run, what reading every result's warnings costs (a flagged plan's exact
           peak rate, torque and power are worked out then) and the throughput with it;
  heyoka   heyoka's SIMD batch mode (taylor_adaptive_batch, the recommended batch size) against
           the same number of scalar propagations of the same variational system: the speed-up it
           could bring to the integrator's share of a plan.

Run:  python benchmarks/batch.py [--n 4000] [--seed 5]
"""

from __future__ import annotations

import argparse
import collections
import os
import platform
import time

import numpy as np

import acroplan
from acroplan.zoo import random_segment


def problems(n, seed):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        p = random_segment(rng)
        out.append(dict(system=p.robot, conditions="free", **p.plan_kwargs()))
    return out


def single(probs):
    acroplan.warm_up(acroplan.Acrobot)
    for kw in probs[:50]:
        acroplan.plan(verify=False, **kw)
    times, kinds = [], collections.Counter()
    for kw in probs:
        t0 = time.perf_counter()
        r = acroplan.plan(verify=False, **kw)
        times.append(time.perf_counter() - t0)
        s = r.segments[0]
        kinds[(r.status, s.basis_coefficients.shape[1], s.evaluations)] += 1
    t = np.array(times) * 1e3
    print(f"single plans, warm: median {np.median(t):.3f} ms, p90 {np.percentile(t, 90):.3f} ms, "
          f"mean {t.mean():.3f} ms ({1e3 / t.mean():.0f} plans/s on one core)")
    for (status, n, ev), count in sorted(kinds.items()):
        print(f"  {count:6d} x {status}, {n} coefficients, {ev} endpoint evaluation(s)")


def batch(probs):
    for executor in ("serial", "thread", "process"):
        t0 = time.perf_counter()
        out = acroplan.plan_many(probs, executor=executor, verify=False)
        dt = time.perf_counter() - t0
        ok = sum(r.success for r in out)
        print(f"plan_many executor={executor:8s} {len(probs) / dt:7.0f} plans/s  ({dt:.2f} s for {len(probs)}, "
              f"{ok} planned)")
        if executor == "serial":
            # a flagged plan's exact peak rate, torque and power are worked out when its warnings are
            # first read (acroplan.core.result.PendingWarning): what reading them all costs, beside the
            # plans' own time
            t0 = time.perf_counter()
            flagged = sum(bool(r.warnings) for r in out)
            dw = time.perf_counter() - t0
            print(f"  reading every result's warnings afterwards: {dw:.2f} s ({flagged} flagged); with it "
                  f"{len(probs) / (dt + dw):7.0f} plans/s")


def heyoka_batch_mode(reps=2000):
    """The compiled variational system of acroplan, scalar vs SIMD batch mode."""
    import copy

    import heyoka as hy

    from acroplan.core import backend as _integrate
    from acroplan.core.basis import Legendre

    robot = random_segment(np.random.default_rng(0)).robot  # any acrobot: one structure, one integrator
    ta = copy.copy(_integrate.compile_for(robot, Legendre, 6))  # this run's own copy of the template
    state, pars, n_p = ta.state, ta.pars, len(robot.param_names)
    B = hy.recommended_simd_size()
    rng = np.random.default_rng(0)
    P = np.zeros((ta.pars.size, B))
    P[:n_p] = np.array([[3.3, -1.6, 2.4, -0.8, 2.6]]).T
    P[n_p] = 1.5
    P[n_p + 1:] = 0.5 * rng.standard_normal((ta.pars.size - n_p - 1, B))
    sys = ta.sys  # the variational system the scalar integrator was built from
    tb = hy.taylor_adaptive_batch(sys, np.zeros((ta.state.size, B)), tol=_integrate.TOL, pars=P)

    def run_batch():
        tb.set_time(0.0)
        tb.state[:] = 0.0
        tb.state[:2] = 0.3
        tb.pars[:] = P
        tb.propagate_until(1.0)

    def run_scalar():
        for k in range(B):
            ta.time = 0.0
            state[:] = 0.0
            state[:2] = 0.3
            pars[:] = P[:, k]
            ta.propagate_until(1.0)

    for f in (run_batch, run_scalar):
        f()
    res = {}
    for name, f in (("batch", run_batch), ("scalar", run_scalar)):
        t0 = time.perf_counter()
        for _ in range(reps):
            f()
        res[name] = (time.perf_counter() - t0) / reps
    print(f"heyoka: {B} propagations with endpoint Jacobian: batch mode {res['batch'] * 1e6:.1f} us, "
          f"{B} scalar {res['scalar'] * 1e6:.1f} us (x{res['scalar'] / res['batch']:.2f})")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=4000)
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args()
    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"acroplan {acroplan.__version__}; {args.n} random single segments, seed {args.seed}")
    probs = problems(args.n, args.seed)
    single(probs)
    batch(probs)
    heyoka_batch_mode()


if __name__ == "__main__":
    main()
