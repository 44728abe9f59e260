"""Minimum-energy plans of three-link bodies: acroplan's EnergyOptimal against CasADi + IPOPT.

Problems: random physical three-link chains, single segments reachable by construction
(acroplan.families.planar.zoo.random_segment: random_body, T in [1, 3] s), P0 = 0 and P0 != 0
(``--n`` each), no limits, conditions="free".

Systems:
  acroplan  plan(body, objective="energy", conditions="free", verify=False) (or, before plan() had
            ``objective``, method=acroplan.core.optimal.EnergyOptimal(): the same strategy): the
            least integral of |u|^2 over the input coefficients, the basis grown 6 -> 10 -> 14 ...
            until the optimum changes by < 1e-4 relative; starts: the planar bodies' shape guesses
            (acroplan.families.planar.effort.optimal_starts; when none is found, the body's
            method="auto" plan and path deformation). Timed per plan call.
            A success must also pass the Pinocchio check (pinocchio_errors) to 1e-9.
  casadi    the peer of benchmarks/peers_planar.py (imported from there): CasADi + IPOPT, direct
            multiple shooting, 100 RK4 intervals, piecewise-constant joint rates, minimum
            sum |u_i|^2 dt, straight-line initial guess, the Opti object built once; timed per solve.
            A success: IPOPT reports success and the DOP853 re-simulation of its input (rtol = atol =
            1e-12, the model's own right-hand side) misses the target by at most 1e-6.

Compared by the same exact integral of |u(t)|^2 over [0, T]: acroplan's T c^T (I (x) G) c (Legendre
Gram matrix), cross-checked by 4096-node Gauss-Legendre quadrature of the input
(benchmarks/optimal.py's quadrature_energy); CasADi's sum |u_i|^2 dt, exact for its piecewise-constant
input. Each problem is solved back to back by both systems (``--repeat`` times, the fastest kept).

With --starts, every problem is also planned with the generic starts of EnergyOptimal
(starts=("auto", "deform")) instead of the planar bodies' own (the shape guesses,
acroplan.families.planar.effort.optimal_starts): optimal cost and time of both (acroplan alone).

With --torque K the first K problems of each population are also planned with TorqueOptimal (the
least integral of |tau|^2 of the joint torques by Pinocchio's inverse dynamics,
acroplan.families.planar.effort.PlanarTorque): time, integral of tau^2 and peak |tau| of both
optima (acroplan alone).

Run:  python benchmarks/optimal_planar.py [--n 20] [--seed 7] [--repeat 1] [--starts] [--torque 0]   (casadi: ".[bench]")
"""

from __future__ import annotations

import argparse
import inspect
import platform
import sys
import time
from pathlib import Path

import numpy as np

import acroplan
from acroplan.core.optimal import SIZES, EnergyOptimal, TorqueOptimal, energy
from acroplan.families.planar.check import pinocchio_errors
from acroplan.families.planar.zoo import random_segment

sys.path.insert(0, str(Path(__file__).parent))
from optimal import parse, quadrature_energy  # noqa: E402  (the acrobot version's message parser and quadrature)
from peers_planar import ACROPLAN_TOL, CASADI_TOL, CasadiMS, resimulate_piecewise  # noqa: E402

HAS_OBJECTIVE = "objective" in inspect.signature(acroplan.plan).parameters
XG, WG = np.polynomial.legendre.leggauss(96)
SG, WSG = (XG + 1.0) / 2.0, WG / 2.0


def plan_energy(p):
    kw = dict(conditions="free", verify=False, **p.plan_kwargs())
    if HAS_OBJECTIVE:
        return acroplan.plan(p.body, objective="energy", **kw)
    return acroplan.plan(p.body, method=EnergyOptimal(), **kw)


def torque_stats(body, seg):
    """(integral of |tau|^2 by 96-node Gauss-Legendre, peak |tau| on those nodes and the ends)."""
    tm = body.torque_model()
    T = seg.t1 - seg.t0
    tau, _ = tm(body, seg.basis, seg.start, T, seg.basis_coefficients, SG)
    ends, _ = tm(body, seg.basis, seg.start, T, seg.basis_coefficients, [0.0, 1.0])
    return T * float(np.sum(tau**2, axis=0) @ WSG), float(max(np.abs(tau).max(), np.abs(ends).max()))


def run_population(args, momentum, ms):
    rng = np.random.default_rng([args.seed, int(momentum)])
    problems = [random_segment(rng, 3, momentum=momentum) for _ in range(args.n)]
    rows = []
    for i, p in enumerate(problems):
        tc, ta, out, r = [], [], None, None
        for _ in range(args.repeat):
            ok_c, dt, u = ms.solve(p.body, p.T, p.x0, p.x1)
            tc.append(dt)
            out = (ok_c, u)
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            r = plan_energy(p)
            ta.append(time.perf_counter() - t0)
        ok_c, u = out
        err_c = float(np.max(np.abs(resimulate_piecewise(p.body, p.x0, p.T, u) - p.x1))) \
            if np.all(np.isfinite(u)) else np.inf
        row = dict(i=i, t_cas=min(tc), t_acro=min(ta), ipopt=ok_c, ok_cas=ok_c and err_c <= CASADI_TOL, err_cas=err_c,
                   E_cas=float(np.sum(u**2) * p.T / ms.N))
        if r.success:
            seg = r.segments[0]
            err_a = float(pinocchio_errors(p.body, p.x0, r.segments).max())
            row.update(ok_acro=err_a <= ACROPLAN_TOL, err_acro=err_a, E_acro=energy(seg.basis, p.T, seg.basis_coefficients),
                       E_quad=quadrature_energy(seg), **parse(seg.message))
        else:
            row.update(ok_acro=False, err_acro=np.inf, E_acro=np.nan, E_quad=np.nan, n=None, kkt=np.nan, start="-",
                       converged=False)
            print(f"  problem {i}: acroplan {r.status}: {r.message[:300]}")
        rows.append(row)
        print(f"  {i:3d}  E acroplan {row['E_acro']:.8g}  casadi {row['E_cas']:.8g}  ratio "
              f"{row['E_acro'] / row['E_cas']:.5f}  n={row['n']}  kkt={row['kkt']:.1e}  start={row['start']}  "
              f"t {row['t_acro'] * 1e3:.1f} ms vs {row['t_cas'] * 1e3:.1f} ms", flush=True)
    return problems, rows


def report(rows, label):
    ok = [r for r in rows if r["ok_acro"] and r["ok_cas"]]
    n = len(rows)
    print(f"\n{label}: {n} problems; solved: acroplan {sum(r['ok_acro'] for r in rows)}/{n} (Pinocchio check <= "
          f"{ACROPLAN_TOL:g}), casadi {sum(r['ok_cas'] for r in rows)}/{n} (IPOPT success "
          f"{sum(r['ipopt'] for r in rows)}, re-simulated <= {CASADI_TOL:g}); compared on {len(ok)} solved by both")
    if not ok:
        return None
    ratio = np.array([r["E_acro"] / r["E_cas"] for r in ok])
    ta = np.array([r["t_acro"] for r in rows])
    tc = np.array([r["t_cas"] for r in rows])
    quad = np.array([abs(r["E_quad"] - r["E_acro"]) / r["E_acro"] for r in ok])
    kkt = np.array([r["kkt"] for r in ok])
    sizes = [r["n"] for r in ok]
    starts = [r["start"] for r in ok]
    print("| quantity | acroplan EnergyOptimal | CasADi + IPOPT (100 RK4) |")
    print("|---|---|---|")
    print(f"| median integral of u^2 | {np.median([r['E_acro'] for r in ok]):.6g} | "
          f"{np.median([r['E_cas'] for r in ok]):.6g} |")
    print(f"| median time per problem | {np.median(ta) * 1e3:.1f} ms (p90 {np.percentile(ta, 90) * 1e3:.1f}) | "
          f"{np.median(tc) * 1e3:.1f} ms (p90 {np.percentile(tc, 90) * 1e3:.1f}) |")
    print(f"| endpoint error, max (acroplan: Pinocchio check; casadi: DOP853) | "
          f"{max(r['err_acro'] for r in ok):.1e} | {max(r['err_cas'] for r in ok):.1e} |")
    print(f"ratio acroplan / CasADi of the integral of u^2: min {ratio.min():.5f}, median {np.median(ratio):.5f}, "
          f"p90 {np.percentile(ratio, 90):.5f}, max {ratio.max():.5f}")
    print(f"  <= 1.01: {np.sum(ratio <= 1.01)}/{ratio.size} ({np.mean(ratio <= 1.01):.1%}); <= 1.00: "
          f"{np.sum(ratio <= 1.0)}; > 1.05: {np.sum(ratio > 1.05)}; < 0.95 (CasADi at a worse local optimum): "
          f"{np.sum(ratio < 0.95)}")
    print(f"speed: CasADi median / acroplan median = {np.median(tc) / np.median(ta):.1f}x; median of per-problem "
          f"ratios {np.median(tc / ta):.1f}x; slowest per-problem ratio {np.min(tc / ta):.2f}x")
    print("acroplan basis sizes of the optimum: " + ", ".join(f"{k}: {sizes.count(k)}" for k in sorted(set(sizes)))
          + f"; converged in the basis (change < 1e-4): {sum(r['converged'] for r in ok)}/{len(ok)}")
    print(f"acroplan relative KKT residual: median {np.median(kkt):.1e}, max {np.max(kkt):.1e}; the energy by "
          f"4096-node quadrature agrees with the Gram form to {quad.max():.1e} (relative)")
    print("acroplan optimum from the start: " + ", ".join(f"{s}: {starts.count(s)}" for s in sorted(set(starts))))
    return ratio, ta, tc


def torque_table(problems, repeat):
    """TorqueOptimal (PlanarTorque) against EnergyOptimal: time, integral of tau^2, peak |tau|."""
    rows = []
    for p in problems:
        out = {}
        for name, strategy in (("energy", EnergyOptimal()), ("torque", TorqueOptimal(torque=p.body.torque_model()))):
            best, r = np.inf, None
            for _ in range(repeat):
                t0 = time.perf_counter()
                r = acroplan.plan(p.body, method=strategy, conditions="free", verify=False, **p.plan_kwargs())
                best = min(best, time.perf_counter() - t0)
            seg = r.segments[0] if r.success else None
            stats = torque_stats(p.body, seg) if seg is not None else (np.nan, np.nan)
            E = energy(seg.basis, p.T, seg.basis_coefficients) if seg is not None else np.nan
            out[name] = (r.success, best, stats, E, seg.basis.n if seg is not None else None)
        rows.append(out)
        print(f"  torque-optimal {out['torque'][1] * 1e3:.0f} ms (n={out['torque'][4]}), energy-optimal "
              f"{out['energy'][1] * 1e3:.0f} ms; integral tau^2 {out['torque'][2][0]:.4g} vs {out['energy'][2][0]:.4g}",
              flush=True)
    ok = [o for o in rows if o["energy"][0] and o["torque"][0]]
    te = np.array([o["energy"][1] for o in ok])
    tt = np.array([o["torque"][1] for o in ok])
    tau2 = np.array([o["torque"][2][0] / o["energy"][2][0] for o in ok])
    peak = np.array([o["torque"][2][1] / o["energy"][2][1] for o in ok])
    u2 = np.array([o["torque"][3] / o["energy"][3] for o in ok])
    print(f"\nTorqueOptimal vs EnergyOptimal on {len(problems)} problems ({len(ok)} solved by both):")
    print(f"  median time: torque-optimal {np.median(tt) * 1e3:.0f} ms (max {tt.max() * 1e3:.0f}), energy-optimal "
          f"{np.median(te) * 1e3:.1f} ms")
    print(f"  integral of tau^2, torque-optimal / energy-optimal: median {np.median(tau2):.3f}, max {tau2.max():.4f}")
    print(f"  peak |tau|, torque-optimal / energy-optimal: median {np.median(peak):.3f}")
    print(f"  integral of u^2, torque-optimal / energy-optimal: median {np.median(u2):.3f}, min {u2.min():.5f}")


def starts_table(problems, repeat):
    """The planar starts (the shape guesses, acroplan.families.planar.effort.optimal_starts, the
    default) against the generic ones (starts=("auto", "deform"): the body's method="auto" plan,
    then path deformation from the minimum-norm input): optimal cost and time."""
    rows = []
    for p in problems:
        out = []
        for strategy in (EnergyOptimal(), EnergyOptimal(starts=("auto", "deform"))):
            best, r = np.inf, None
            for _ in range(repeat):
                t0 = time.perf_counter()
                r = acroplan.plan(p.body, method=strategy, conditions="free", verify=False, **p.plan_kwargs())
                best = min(best, time.perf_counter() - t0)
            seg = r.segments[0] if r.success else None
            out.append((best, energy(seg.basis, p.T, seg.basis_coefficients) if seg is not None else np.nan))
        rows.append(out)
    t_fam = np.array([o[0][0] for o in rows])
    t_gen = np.array([o[1][0] for o in rows])
    ratio = np.array([o[0][1] / o[1][1] for o in rows])
    ok = np.isfinite(ratio)
    print(f"\nstarts: shape guesses (default) vs starts=(\"auto\", \"deform\") on {len(rows)} problems "
          f"({ok.sum()} solved by both)")
    print(f"  integral of u^2, shape-guess starts / generic starts: min {ratio[ok].min():.10f}, median "
          f"{np.median(ratio[ok]):.10f}, max {ratio[ok].max():.10f}; > 1 + 1e-6: {np.sum(ratio[ok] > 1 + 1e-6)}, "
          f"< 1 - 1e-6: {np.sum(ratio[ok] < 1 - 1e-6)}")
    print(f"  median time: shape-guess starts {np.median(t_fam) * 1e3:.1f} ms, generic starts "
          f"{np.median(t_gen) * 1e3:.1f} ms (median per-problem ratio {np.median(t_gen / t_fam):.2f}x)")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=20, help="problems per population (P0 = 0 and P0 != 0)")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--repeat", type=int, default=1, help="solves per problem and system; the fastest is kept")
    ap.add_argument("--torque", type=int, default=0, help="also TorqueOptimal on this many problems per population")
    ap.add_argument("--starts", action="store_true", help="also compare the planar starts with the generic ones")
    args = ap.parse_args()
    import casadi

    how = 'plan(objective="energy")' if HAS_OBJECTIVE else "plan(method=EnergyOptimal())"
    print(f"machine: {platform.processor() or platform.machine()}, Python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, casadi {casadi.__version__}; acroplan through {how}")
    print(f"command: python benchmarks/optimal_planar.py --n {args.n} --seed {args.seed} --repeat {args.repeat}"
          + (f" --torque {args.torque}" if args.torque else "") + (" --starts" if args.starts else ""))
    # warm up: every basis size of the ladder compiled, CasADi's solver built, one solve of each (untimed)
    first = random_segment(np.random.default_rng(0), 3, momentum=True)
    acroplan.warm_up(first.body, sizes=SIZES)
    ms = CasadiMS(first.body)
    ms.solve(first.body, first.T, first.x0, first.x1)
    plan_energy(first)
    all_rows, populations = [], []
    for momentum in (False, True):
        label = f"3 links, P0 {'!= 0' if momentum else '= 0'}"
        print(f"\n{label}")
        problems, rows = run_population(args, momentum, ms)
        populations.append((label, problems, rows))
        all_rows += rows
    for label, _, rows in populations:
        report(rows, label)
    out = report(all_rows, "both populations")
    if out is not None:
        ratio, ta, tc = out
        verdict = np.mean(ratio <= 1.01) >= 0.95 and ratio.max() <= 1.05 and np.median(tc) / np.median(ta) >= 10
        print(f"\nissue #13's targets (<= +1% on >= 95%, never > +5%, >= 10x faster): {'met' if verdict else 'NOT met'}")
    if args.starts:
        starts_table([p for _, problems, _ in populations for p in problems], args.repeat)
    if args.torque:
        for label, problems, _ in populations:
            print(f"\n{label}: TorqueOptimal")
            torque_table(problems[:args.torque], args.repeat)


if __name__ == "__main__":
    main()
