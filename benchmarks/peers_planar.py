"""Planar bodies: acroplan against CasADi + IPOPT on the same problems, in the same run.

Problems: random physical three-link chains, single segments reachable by construction
(acroplan.families.planar.zoo.random_segment), P0 = 0 and P0 != 0, no limits (``--n`` each).

Systems:
  acroplan  plan(..., conditions="free", verify=False), method="auto"; a success must also pass the
            Pinocchio check (acroplan.families.planar.check.pinocchio_errors) to 1e-9.
  casadi    CasADi + IPOPT, direct multiple shooting, 100 RK4 intervals, piecewise-constant joint
            rates, minimum integral of |u|^2, straight-line initial guess (states interpolated, the
            joint rates constant), the same dynamics theta' = (P0 - a(s).u)/I(s) written in casadi
            symbols in the lumped form acroplan compiles (I = Ic + 2 sum R cos(d + psi), a = Ac + W H);
            the Opti object built once per topology (body parameters, T, x0, x1 are Opti
            parameters), timed per solve. A success: IPOPT reports success and the re-simulation of its
            piecewise-constant input (scipy DOP853, rtol = atol = 1e-12, interval by interval, the
            model's own right-hand side) misses the target by at most 1e-6 (as benchmarks/peers.py).

Each problem is solved back to back by each system (``--repeat`` times, the fastest counts); the
checks are made afterwards, untimed.

Run:  python benchmarks/peers_planar.py [--n 50] [--seed 7] [--repeat 1]   (needs casadi: pip install ".[bench]")
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np
from scipy.integrate import solve_ivp

import acroplan
from acroplan.families.planar.check import pinocchio_errors
from acroplan.families.planar.connection import Connection
from acroplan.families.planar.zoo import random_segment

CASADI_TOL = 1e-6
ACROPLAN_TOL = 1e-9


class CasadiMS:
    """Direct multiple shooting with N RK4 intervals for one topology, built once."""

    def __init__(self, body, N=100):
        import casadi as ca

        conn = Connection(body)
        m, npairs = conn.m, conn.R.size
        self.ca, self.N, self.m = ca, N, m
        opti = ca.Opti()
        X = opti.variable(m + 1, N + 1)
        U = opti.variable(m, N)
        P0, Ic = opti.parameter(), opti.parameter()
        Ac, R, psi = opti.parameter(m), opti.parameter(npairs), opti.parameter(npairs)
        T = opti.parameter()
        x0, x1 = opti.parameter(m + 1), opti.parameter(m + 1)
        Dq, W = ca.DM(conn.Dq), ca.DM(conn.W)  # the topology (fixed per structure)
        dt = T / N

        def f(x, u):
            H = R * ca.cos(ca.mtimes(Dq, x[1:]) + psi)
            I = Ic + 2 * ca.sum1(H)  # noqa: E741
            a = Ac + ca.mtimes(W, H)
            return ca.vertcat((P0 - ca.dot(a, u)) / I, u)

        for i in range(N):
            xk, uk = X[:, i], U[:, i]
            k1 = f(xk, uk)
            k2 = f(xk + dt / 2 * k1, uk)
            k3 = f(xk + dt / 2 * k2, uk)
            k4 = f(xk + dt * k3, uk)
            opti.subject_to(X[:, i + 1] == xk + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4))
        opti.subject_to(X[:, 0] == x0)
        opti.subject_to(X[:, N] == x1)
        opti.minimize(ca.sumsqr(U) * dt)
        opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": 1e-10,
                                                      "constr_viol_tol": 1e-12, "max_iter": 500})
        self.opti, self.X, self.U = opti, X, U
        self.par = dict(P0=P0, Ic=Ic, Ac=Ac, R=R, psi=psi, T=T, x0=x0, x1=x1)

    def solve(self, body, T, x0, x1):
        opti, N, p = self.opti, self.N, self.par
        conn = Connection(body)
        for name, v in (("P0", conn.P0), ("Ic", conn.Ic), ("Ac", conn.Ac), ("R", conn.R), ("psi", conn.psi),
                        ("T", T), ("x0", x0), ("x1", x1)):
            opti.set_value(p[name], v)
        s = np.linspace(0, 1, N + 1)
        opti.set_initial(self.X, np.asarray(x0)[:, None] + s[None, :] * (np.asarray(x1) - np.asarray(x0))[:, None])
        opti.set_initial(self.U, np.repeat(((np.asarray(x1) - np.asarray(x0))[1:] / T)[:, None], N, axis=1))
        opti.set_initial(opti.lam_g, 0)  # no dual warm start from the previous solve
        t0 = time.perf_counter()
        try:
            sol = opti.solve()
            ok, u = True, np.atleast_2d(sol.value(self.U))
        except RuntimeError:
            ok, u = False, np.atleast_2d(opti.debug.value(self.U))
        return ok, time.perf_counter() - t0, u.reshape(self.m, N)


def resimulate_piecewise(body, x0, T, u):
    """The model's own right-hand side under a piecewise-constant input, interval by interval."""
    x = np.asarray(x0, dtype=float)
    N = u.shape[1]
    h = T / N
    for i in range(N):
        ui = u[:, i]
        x = solve_ivp(lambda t, y: body.rhs(y, ui), (0.0, h), x, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]
    return x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=50)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    import casadi

    print(f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, casadi {casadi.__version__}; n = {args.n} per population, seed {args.seed}")
    ms = None
    for momentum in (False, True):
        rng = np.random.default_rng([args.seed, int(momentum)])
        problems = [random_segment(rng, 3, momentum=momentum) for _ in range(args.n)]
        if ms is None:
            ms = CasadiMS(problems[0].body)
            acroplan.warm_up(problems[0].body)
            for p in problems[:2]:  # first calls out of the timing
                ms.solve(p.body, p.T, p.x0, p.x1)
                acroplan.plan(p.body, conditions="free", verify=False, **p.plan_kwargs())
        rows = {"acroplan": [], "casadi": []}
        for p in problems:
            best, res = np.inf, None
            for _ in range(args.repeat):
                t0 = time.perf_counter()
                r = acroplan.plan(p.body, conditions="free", verify=False, **p.plan_kwargs())
                best = min(best, time.perf_counter() - t0)
                res = r
            rows["acroplan"].append((res, best))
            best, out = np.inf, None
            for _ in range(args.repeat):
                ok, dt, u = ms.solve(p.body, p.T, p.x0, p.x1)
                best, out = min(best, dt), (ok, u)
            rows["casadi"].append((out, best))
        # checks, untimed
        a_ok, a_t, a_err, c_ok, c_t, c_err, c_ipopt = [], [], [], [], [], [], 0
        for p, (res, dt) in zip(problems, rows["acroplan"]):
            err = float(pinocchio_errors(p.body, p.x0, res.segments).max()) if res.success else np.inf
            a_ok.append(res.success and err <= ACROPLAN_TOL)
            a_t.append(dt)
            a_err.append(err)
        for p, ((ok, u), dt) in zip(problems, rows["casadi"]):
            err = float(np.max(np.abs(resimulate_piecewise(p.body, p.x0, p.T, u) - p.x1))) if np.all(np.isfinite(u)) \
                else np.inf
            c_ipopt += ok
            c_ok.append(ok and err <= CASADI_TOL)
            c_t.append(dt)
            c_err.append(err)
        ma, mc = float(np.median(a_t)), float(np.median(c_t))
        ea = np.array([e for e, k in zip(a_err, a_ok) if k])
        ec = np.array([e for e, k in zip(c_err, c_ok) if k])
        print(f"\n3 links, P0 {'!= 0' if momentum else '= 0'}, {args.n} problems")
        print(f"  acroplan  success {sum(a_ok)}/{args.n} (Pinocchio check <= 1e-9; errors median "
              f"{np.median(ea) if ea.size else np.nan:.1e} max {ea.max() if ea.size else np.nan:.1e})  time median "
              f"{ma * 1e3:.2f} ms p90 {np.percentile(a_t, 90) * 1e3:.2f} ms")
        print(f"  casadi    success {sum(c_ok)}/{args.n} (IPOPT success {c_ipopt}/{args.n}; re-simulated error "
              f"median {np.median(ec) if ec.size else np.nan:.1e} max {ec.max() if ec.size else np.nan:.1e})  "
              f"time median {mc * 1e3:.2f} ms p90 {np.percentile(c_t, 90) * 1e3:.2f} ms")
        print(f"  ratio of medians casadi / acroplan: {mc / ma:.0f}x")


if __name__ == "__main__":
    main()
