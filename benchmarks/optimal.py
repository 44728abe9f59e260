"""Minimum-energy plans: acroplan's EnergyOptimal against CasADi + IPOPT, on the same problems.

Problems: random physical single segments of the acrobot (acroplan.zoo.random_segment, seed 11 by
default, targets in the middle 96% of the exact reachable interval), conditions="free".

Systems:
  acroplan   plan(robot, method=EnergyOptimal(), conditions="free", verify=False): minimum of the
             integral of u^2 over the input coefficients, the basis grown 6 -> 10 -> 14 -> 20 ... until
             the optimum changes by < 1e-4 relative (acroplan.core.optimal); timed per plan call.
  casadi     the peer of benchmarks/peers.py: CasADi + IPOPT, direct multiple shooting, 100 RK4
             intervals, piecewise-constant u, minimum sum u^2 dt, the Opti object built once,
             duals reset before every solve; timed per solve.

The objective is compared by the same exact integral, the integral of u(t)^2 over [0, T]:
  acroplan   T c^T G c with G the Legendre Gram matrix (exact), cross-checked by 4096-node
             Gauss-Legendre quadrature of the segment's input;
  casadi     sum_i u_i^2 dt, exact for its piecewise-constant input.
Both inputs are re-simulated from the start by one independent integrator (scipy DOP853, rtol =
atol = 3e-14, as in peers.py) and the endpoint error is reported; acroplan's plans are also checked
by the exact flat-output identity (no ODE integrator).

Timing: for each problem CasADi and acroplan are run back to back (each --repeat times, the
fastest kept), so both see the same load on a shared machine; the speed-up is the ratio of the
median times (and the median of the per-problem ratios).

With --torque K, TorqueOptimal (minimum integral of tau^2, acroplan.families.acrobot.effort) is
also timed against EnergyOptimal on the first K problems (acroplan alone; --n 0 skips CasADi), with
both plans' integral of tau^2 and peak |tau| (effort_summary).

Run:  python benchmarks/optimal.py [--n 60] [--seed 11] [--repeat 3] [--torque 20]   (casadi: ".[bench]")
"""

from __future__ import annotations

import argparse
import platform
import re
import sys
import time
from pathlib import Path

import numpy as np

import acroplan
from acroplan.core.optimal import SIZES, EnergyOptimal, energy
from acroplan.families.acrobot.effort import effort_summary, torque_optimal
from acroplan.families.acrobot.verify import flat_output_errors
from acroplan.zoo import random_segment

sys.path.insert(0, str(Path(__file__).parent))
from peers import CasadiMS, resimulate  # noqa: E402  (the same CasADi formulation and checking integrator)


def quadrature_energy(seg, nodes=4096) -> float:
    """The integral of |u|^2 over the segment by Gauss-Legendre quadrature of the segment's input."""
    x, w = np.polynomial.legendre.leggauss(nodes)
    T = seg.t1 - seg.t0
    t = seg.t0 + (x + 1.0) / 2.0 * T
    u = seg.input(t)
    return float(np.sum(u**2 * w) * T / 2.0)


def parse(message: str) -> dict:
    """Numbers of the strategy's message: basis size, relative KKT residual, start, converged."""
    out = {}
    m = re.search(r"with (\d+) coefficient", message)
    out["n"] = int(m.group(1)) if m else None
    m = re.search(r"relative KKT residual ([0-9.eE+-]+)", message)
    out["kkt"] = float(m.group(1)) if m else float("nan")
    m = re.search(r"; start: ([\w+-]+)", message)
    out["start"] = m.group(1) if m else "?"
    out["converged"] = "converged in the basis" in message and "NOT converged" not in message
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=60)
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--repeat", type=int, default=3, help="solves per problem and system; the fastest is kept")
    ap.add_argument("--torque", type=int, default=0, help="also time TorqueOptimal on this many problems")
    args = ap.parse_args()
    import casadi

    print(f"machine: {platform.processor() or platform.machine()}, Python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, casadi {casadi.__version__}")
    print(f"command: python benchmarks/optimal.py --n {args.n} --seed {args.seed} --repeat {args.repeat}"
          + (f" --torque {args.torque}" if args.torque else ""))
    rng = np.random.default_rng(args.seed)
    problems = [random_segment(rng) for _ in range(max(args.n, args.torque))]
    if args.n == 0:
        return torque_table(problems[:args.torque], args.repeat)
    strategy = EnergyOptimal()
    ms = CasadiMS(100)
    # warm up: compile every basis size of the ladder, build CasADi's solver, one solve of each
    acroplan.warm_up(acroplan.Acrobot, sizes=SIZES)
    p = problems[0]
    acroplan.plan(p.robot, method=strategy, conditions="free", verify=False, **p.plan_kwargs())
    ms.solve(p.robot, p.T, np.array([p.theta0, p.phi0]), np.array([p.thetaT, p.phiT]))

    rows = []
    for i, p in enumerate(problems):
        x0, x1 = np.array([p.theta0, p.phi0]), np.array([p.thetaT, p.phiT])
        tc, ta = [], []
        for _ in range(args.repeat):
            ok_c, dt, u = ms.solve(p.robot, p.T, x0, x1)
            tc.append(dt)
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            r = acroplan.plan(p.robot, method=strategy, conditions="free", verify=False, **p.plan_kwargs())
            ta.append(time.perf_counter() - t0)
        row = dict(i=i, t_cas=min(tc), t_acro=min(ta), ok_cas=ok_c, ok_acro=r.success)
        row["E_cas"] = float(np.sum(u**2) * p.T / ms.N)
        h = p.T / ms.N
        xc = resimulate(p.robot, x0, [(k * h, (k + 1) * h, (lambda v: (lambda t: v))(u[k])) for k in range(ms.N)])
        row["err_cas"] = float(np.max(np.abs(xc - x1)))
        if r.success:
            seg = r.segments[0]
            row["E_acro"] = energy(seg.basis, p.T, seg.basis_coefficients)
            row["E_quad"] = quadrature_energy(seg)
            xa = resimulate(p.robot, x0, [(seg.t0, seg.t1, lambda t, s=seg: float(s.input(t)[0]))])
            row["err_acro"] = float(np.max(np.abs(xa - x1)))
            row["err_exact"] = float(flat_output_errors(r).max())
            row.update(parse(seg.message))
        else:
            row.update(E_acro=float("nan"), E_quad=float("nan"), err_acro=float("nan"), err_exact=float("nan"),
                       n=None, kkt=float("nan"), start="-", converged=False)
            print(f"  problem {i}: acroplan {r.status}: {r.message[:300]}")
        rows.append(row)
        print(f"  {i:3d}  E acroplan {row['E_acro']:.8g}  casadi {row['E_cas']:.8g}  ratio "
              f"{row['E_acro'] / row['E_cas']:.5f}  n={row['n']}  kkt={row['kkt']:.1e}  start={row['start']}  "
              f"t {row['t_acro'] * 1e3:.2f} ms vs {row['t_cas'] * 1e3:.1f} ms", flush=True)

    ok = [r for r in rows if r["ok_acro"] and r["ok_cas"]]
    ratio = np.array([r["E_acro"] / r["E_cas"] for r in ok])
    ta = np.array([r["t_acro"] for r in rows])
    tc = np.array([r["t_cas"] for r in rows])
    quad = np.array([abs(r["E_quad"] - r["E_acro"]) / r["E_acro"] for r in ok])
    kkt = np.array([r["kkt"] for r in ok])
    sizes = [r["n"] for r in ok]
    print(f"\n{len(rows)} problems; solved: acroplan {sum(r['ok_acro'] for r in rows)}, casadi "
          f"{sum(r['ok_cas'] for r in rows)}; compared on {len(ok)} solved by both")
    print("\n| quantity | acroplan EnergyOptimal | CasADi + IPOPT (100 RK4) |")
    print("|---|---|---|")
    print(f"| median integral of u^2 | {np.median([r['E_acro'] for r in ok]):.6g} | "
          f"{np.median([r['E_cas'] for r in ok]):.6g} |")
    print(f"| median time per problem | {np.median(ta) * 1e3:.2f} ms (p90 {np.percentile(ta, 90) * 1e3:.2f}) | "
          f"{np.median(tc) * 1e3:.2f} ms (p90 {np.percentile(tc, 90) * 1e3:.2f}) |")
    print(f"| endpoint error, DOP853 re-simulation, max | {max(r['err_acro'] for r in ok):.1e} | "
          f"{max(r['err_cas'] for r in ok):.1e} |")
    print(f"| endpoint error, exact flat-output identity, max | {max(r['err_exact'] for r in ok):.1e} | - |")
    print("\nratio acroplan / CasADi of the integral of u^2:")
    print(f"  min {ratio.min():.5f}, p5 {np.percentile(ratio, 5):.5f}, median {np.median(ratio):.5f}, "
          f"p95 {np.percentile(ratio, 95):.5f}, max {ratio.max():.5f}")
    within = np.mean(ratio <= 1.01)
    print(f"  <= 1.01: {np.sum(ratio <= 1.01)}/{ratio.size} ({within:.1%}); <= 1.00: {np.sum(ratio <= 1.0)}; "
          f"> 1.05: {np.sum(ratio > 1.05)}")
    print(f"speed: CasADi median / acroplan median = {np.median(tc) / np.median(ta):.1f}x; median of per-problem "
          f"ratios {np.median(tc / ta):.1f}x; slowest per-problem ratio {np.min(tc / ta):.1f}x")
    print("acroplan basis sizes of the optimum: " + ", ".join(f"{n}: {sizes.count(n)}" for n in sorted(set(sizes))) +
          f"; converged in the basis (change < 1e-4): {sum(r['converged'] for r in ok)}/{len(ok)}")
    print(f"acroplan relative KKT residual: median {np.median(kkt):.1e}, max {np.max(kkt):.1e}; the energy by "
          f"4096-node quadrature agrees with the Gram form to {quad.max():.1e} (relative)")
    starts = [r["start"] for r in ok]
    print("acroplan optimum from the start: " + ", ".join(f"{s}: {starts.count(s)}" for s in sorted(set(starts))))
    verdict = (within >= 0.95 and ratio.max() <= 1.05 and np.median(tc) / np.median(ta) >= 10)
    print(f"\ntargets (<= +1% on >= 95%, never > +5%, >= 10x faster): {'met' if verdict else 'NOT met'}")
    if args.torque:
        torque_table(problems[:args.torque], args.repeat)


def torque_table(problems, repeat):
    """TorqueOptimal against EnergyOptimal (acroplan alone): time, integral of tau^2, peak |tau|."""
    acroplan.warm_up(acroplan.Acrobot, sizes=SIZES)
    energy_s, torque_s = EnergyOptimal(), torque_optimal()
    rows = []
    for p in problems:
        out = {}
        for name, strategy in (("energy", energy_s), ("torque", torque_s)):
            best, r = float("inf"), None
            for _ in range(repeat):
                t0 = time.perf_counter()
                r = acroplan.plan(p.robot, method=strategy, conditions="free", verify=False, **p.plan_kwargs())
                best = min(best, time.perf_counter() - t0)
            es = effort_summary(r) if r.success else None
            out[name] = (r.success, best, es)
        rows.append(out)
    ok = [o for o in rows if o["energy"][0] and o["torque"][0]]
    te = np.array([o["energy"][1] for o in rows])
    tt = np.array([o["torque"][1] for o in rows])
    tau2 = np.array([o["torque"][2].torque_squared / o["energy"][2].torque_squared for o in ok])
    peak = np.array([o["torque"][2].peak_torque / o["energy"][2].peak_torque for o in ok])
    u2 = np.array([o["torque"][2].input_squared / o["energy"][2].input_squared for o in ok])
    print(f"\nTorqueOptimal vs EnergyOptimal on {len(problems)} problems ({len(ok)} solved by both):")
    print(f"  median time: torque-optimal {np.median(tt) * 1e3:.2f} ms (p90 {np.percentile(tt, 90) * 1e3:.2f}), "
          f"energy-optimal {np.median(te) * 1e3:.2f} ms: {np.median(tt / te):.1f}x slower (median per problem)")
    print(f"  integral of tau^2, torque-optimal / energy-optimal: median {np.median(tau2):.3f}, max {tau2.max():.4f}")
    print(f"  peak |tau|, torque-optimal / energy-optimal: median {np.median(peak):.3f}")
    print(f"  integral of u^2, torque-optimal / energy-optimal: median {np.median(u2):.3f}, min {u2.min():.5f}")


if __name__ == "__main__":
    main()
