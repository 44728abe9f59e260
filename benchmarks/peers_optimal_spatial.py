"""Optimal 3-D plans: acroplan's ``objective="energy"`` and ``"torque"`` against CasADi + IPOPT, in
the same run (issue #22).

Problems:
  trunk    bioptim's free-floating example body, one somersault and a half twist in 1.5 s at
           L = (36.3075, 0, 0) kg m^2/s, the arms from (2.9, -2.9) rad down to (0, 0), rates zero at
           both ends (acroplan.families.spatial.examples.trunk_twist; no joint limits);
  cat      the bundled falling cat, 180 degrees at L = 0 in 0.5 s within its joint ranges
           (examples.falling_cat_turn).

Systems (each problem solved back to back by each, ``--repeat`` times, the fastest counts; every
check afterwards, untimed):
  acroplan  plan(body, objective=..., verify=False, **kw) after one warm call (compiled maps and
            torque functions built); a success must also pass the Pinocchio check
            (acroplan.families.spatial.check.pinocchio_errors) to 1e-9.
  casadi    CasADi + IPOPT, direct multiple shooting with ``--intervals`` RK4 intervals (tol 1e-10,
            constr_viol_tol 1e-12, max_iter 1000), the same end state (the attitude by its vector
            part and q_N . q_1 >= 0, the joints, the rates zero at both ends):
            energy: the joint rates piecewise constant, minimum sum |u_k|^2 dt = the integral
                    of |u|^2 of that input (benchmarks/peers_spatial.CasadiCat), the rates free at
                    both ends, for both systems (rates held at zero make the energy's infimum the
                    free-ended one, approached but never reached: acroplan's basis ladder then
                    never converges, and CasADi's optimum depends on its grid);
            torque: the joint rates in the state, their rates piecewise constant, minimum integral
                    of |tau|^2 integrated by the same RK4 steps, tau from the same Newton-Euler
                    recursion acroplan compiles (acroplan.families.spatial.dynamics.newton_euler,
                    written over CasADi expressions), at lambda = R(q)^T L;
            the joint ranges as bounds on the nodes (the cat); initial guess: the trunk as
            bioptim's example gives it (somersault 0 -> 2 pi, twist 0 -> pi, tilt 0, joints
            linear; Yeadon angles), the cat's attitude on the geodesic (slerp); rates zero.
            A success: IPOPT's, and its input re-simulated (scipy DOP853, rtol = atol = 1e-12,
            interval by interval) misses the end state by at most 1e-6.

Run:  python benchmarks/peers_optimal_spatial.py [--problems trunk cat] [--objectives energy torque]
      [--intervals 100] [--repeat 1] [--acroplan-only]   (needs casadi and pinocchio: pip install ".[bench]")
"""

from __future__ import annotations

import argparse
import math
import platform
import time

import numpy as np
from peers_spatial import CasadiCat, casadi_field, casadi_rotation, resimulate_piecewise
from scipy.integrate import solve_ivp

import acroplan
from acroplan.families.spatial import dynamics
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.check import pinocchio_errors, state_error
from acroplan.families.spatial.examples import falling_cat_turn, trunk_twist

CASADI_TOL = 1e-6
ACROPLAN_TOL = 1e-9


class CasadiTorque:
    """Minimum integral of |tau|^2 by direct multiple shooting (module docstring), built once."""

    def __init__(self, body, N=100):
        import casadi as ca

        m = body.n_inputs
        f = casadi_field(body)
        struct, par = dynamics.structure(body.links), dynamics.parameters(body.links)
        L = ca.DM(body.angular_momentum)
        xs, acc = ca.SX.sym("x", 4 + 2 * m), ca.SX.sym("a", m)
        s, u = xs[4:4 + m], xs[4 + m:]
        lam = ca.mtimes(casadi_rotation(xs[:4]).T, L)
        tau = dynamics.newton_euler(struct, par, [s[i] for i in range(m)], [u[i] for i in range(m)],
                                    [acc[i] for i in range(m)], [lam[i] for i in range(3)], ca.sin, ca.cos)
        rate = sum(t * t for t in tau)
        F = ca.Function("F", [xs, acc], [ca.vertcat(f(xs[:4 + m], u), acc), rate])
        self.tau = ca.Function("tau", [xs, acc], [ca.vertcat(*tau)])
        opti = ca.Opti()
        X = opti.variable(4 + 2 * m, N + 1)
        A = opti.variable(m, N)
        T = opti.parameter()
        x0, x1 = opti.parameter(4 + m), opti.parameter(4 + m)
        dt = T / N
        cost = 0
        for i in range(N):
            xk, ak = X[:, i], A[:, i]
            k1, c1 = F(xk, ak)
            k2, c2 = F(xk + dt / 2 * k1, ak)
            k3, c3 = F(xk + dt / 2 * k2, ak)
            k4, c4 = F(xk + dt * k3, ak)
            opti.subject_to(X[:, i + 1] == xk + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4))
            cost = cost + dt / 6 * (c1 + 2 * c2 + 2 * c3 + c4)
        opti.subject_to(X[:4 + m, 0] == x0)
        opti.subject_to(X[4 + m:, 0] == 0)
        opti.subject_to(X[1:4, N] == x1[1:4])
        opti.subject_to(ca.dot(X[:4, N], x1[:4]) >= 0)
        opti.subject_to(X[4:4 + m, N] == x1[4:])
        opti.subject_to(X[4 + m:, N] == 0)
        _joint_bounds(opti, body, X)
        opti.minimize(cost)
        opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": 1e-10,
                                                      "constr_viol_tol": 1e-12, "max_iter": 1000})
        self.opti, self.X, self.A, self.N, self.m, self.cost = opti, X, A, N, m, cost
        self.par = dict(T=T, x0=x0, x1=x1)

    def solve(self, T, x0, x1, guess):
        """IPOPT from ``guess`` (attitude and joints at the nodes, (4 + m, N + 1)), the rates their
        differences, the accelerations zero. Returns ``(success, seconds, cost, a (m, N))``."""
        opti, N, m = self.opti, self.N, self.m
        for name, v in (("T", T), ("x0", x0), ("x1", x1)):
            opti.set_value(self.par[name], v)
        Xg = np.zeros((4 + 2 * m, N + 1))
        Xg[:4 + m] = guess
        Xg[4 + m:, 1:-1] = np.gradient(guess[4:], T / N, axis=1)[:, 1:-1]
        opti.set_initial(self.X, Xg)
        opti.set_initial(self.A, np.zeros((m, N)))
        opti.set_initial(opti.lam_g, 0)
        t0 = time.perf_counter()
        try:
            sol = opti.solve()
            ok, a, cost = True, np.atleast_2d(sol.value(self.A)), float(sol.value(self.cost))
        except RuntimeError:
            ok, a, cost = False, np.atleast_2d(opti.debug.value(self.A)), float("nan")
        return ok, time.perf_counter() - t0, cost, a.reshape(m, N)


def _joint_bounds(opti, body, X):
    lim = body.default_limits()
    for j, name in enumerate(body.links.joint_names):
        lo, hi = lim.bounds(name) if lim is not None else (-math.inf, math.inf)
        if math.isfinite(lo):
            opti.subject_to(X[4 + j, :] >= lo)
        if math.isfinite(hi):
            opti.subject_to(X[4 + j, :] <= hi)


def resimulate_accelerations(body, x0, T, a):
    """The model's own right-hand side with the joint rates ramping under piecewise-constant
    accelerations ``a`` (m, N) from rest, interval by interval."""
    x, N = np.asarray(x0, dtype=float), a.shape[1]
    h, u = T / N, np.zeros(a.shape[0])
    for i in range(N):
        ui, ai = u.copy(), a[:, i]
        x = solve_ivp(lambda t, y: body.rhs(y, ui + ai * t), (0.0, h), x, method="DOP853", rtol=1e-12,
                      atol=1e-12).y[:, -1]
        u = ui + ai * h
    return x, u


def guess_nodes(name, body, x0, x1, N):
    """CasADi's initial states at the nodes (module docstring)."""
    s = np.linspace(0.0, 1.0, N + 1)
    G = np.zeros((body.n_states, N + 1))
    G[4:] = x0[4:, None] + s[None, :] * (x1[4:] - x0[4:])[:, None]
    if name == "trunk":
        G[:4] = np.stack([rot.from_euler([360.0 * k, 0.0, 180.0 * k]) for k in s], axis=1)
        for k in range(1, N + 1):  # one continuous sign
            G[:4, k] *= np.sign(G[:4, k] @ G[:4, k - 1])
    else:
        r = rot.log(rot.qmul(rot.qconj(x0[:4]), x1[:4]))
        G[:4] = np.stack([rot.qmul(x0[:4], rot.exp(k * r)) for k in s], axis=1)
    return G


def problems(names):
    out = {"trunk": trunk_twist, "cat": falling_cat_turn}
    return [(n,) + out[n]() for n in names]


def run(name, body, kw, objective, peer, args):
    names = body.state_names
    x0 = np.array([kw[k][0] for k in names])
    x1 = np.array([kw[k][-1] for k in names])
    T = kw["times"][-1] - kw["times"][0]
    acroplan.plan(body, verify=False, objective=objective, **kw)  # warm: compiled functions
    guess = guess_nodes(name, body, x0, x1, args.intervals)
    # the end attitude's sign the guess ends on: CasADi's end condition (vector part, q_N . q_1 >= 0)
    # then asks for the same rotation as acroplan's (whose residual, log(q_1^-1 q), has no sign)
    x1c = x1.copy()
    x1c[:4] *= np.sign(guess[:4, -1] @ x1[:4])
    ta, ca_, tc = [], [], []
    for _ in range(args.repeat):
        t, c = time.perf_counter(), time.process_time()
        r = acroplan.plan(body, verify=False, objective=objective, **kw)
        ta.append(time.perf_counter() - t)
        ca_.append(time.process_time() - c)
        c = time.process_time()
        if peer is None:
            tc.append((math.nan, math.nan))
            continue
        if objective == "energy":
            ok_c, dt_c, u = peer.solve(T, x0, x1c, guess=guess)
            cost_c = float(np.sum(u**2) * T / u.shape[1])
        else:
            ok_c, dt_c, cost_c, a = peer.solve(T, x0, x1c, guess)
        tc.append((dt_c, time.process_time() - c))
    err_a = float(pinocchio_errors(body, x0, r.segments).max()) if r.success else float("nan")
    if peer is None:
        print(f"\n{name}, {objective}: acroplan {r.status} (check {err_a:.1e}); wall times "
              f"{', '.join(f'{v:.3f}' for v in ta)} s, CPU {', '.join(f'{v:.3f}' for v in ca_)} s; min {min(ta):.3f} / "
              f"{min(ca_):.3f} s, median {float(np.median(ta)):.3f} / {float(np.median(ca_)):.3f} s")
        return
    if objective == "energy":
        err_c = state_error(resimulate_piecewise(body, x0, T, u), x1) if ok_c else float("nan")
    else:
        xe, ue = resimulate_accelerations(body, x0, T, a)
        err_c = max(state_error(xe, x1), float(np.abs(ue).max())) if ok_c else float("nan")
    opt = r.segments[0].optimality if r.success else {}
    cost_a = opt.get("cost", float("nan"))
    best_c = min(tc)
    sa = "yes" if r.success and err_a <= ACROPLAN_TOL and opt.get("converged") else "no"
    sc = "yes" if ok_c and err_c <= CASADI_TOL else "no"
    print(f"\n{name}, {objective}: acroplan solved {sa} in {min(ta):.3f} s wall, {min(ca_):.3f} s CPU (check "
          f"{err_a:.1e}, cost {cost_a:.6g}, basis {opt.get('basis_size')}, ladder "
          f"{[n for n, _ in opt.get('ladder', [])]}, KKT {opt.get('kkt', float('nan')):.1e}, "
          f"{opt.get('evaluations')} evaluations)\n"
          f"    casadi solved {sc} in {best_c[0]:.3f} s wall, {best_c[1]:.3f} s CPU (re-simulation {err_c:.1e}, "
          f"cost {cost_c:.6g})\n    ratio (CasADi / acroplan, wall) {best_c[0] / min(ta):.1f}x, CPU "
          f"{best_c[1] / min(ca_):.1f}x; cost acroplan / CasADi {cost_a / cost_c:.4f}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--problems", nargs="+", default=["trunk", "cat"], choices=["trunk", "cat"])
    ap.add_argument("--objectives", nargs="+", default=["energy", "torque"], choices=["energy", "torque"])
    ap.add_argument("--intervals", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--acroplan-only", action="store_true", help="time acroplan alone (no CasADi)")
    args = ap.parse_args()
    import casadi

    print(f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, casadi {casadi.__version__}; {args.intervals} RK4 intervals, repeat "
          f"{args.repeat}")
    for name, body, kw in problems(args.problems):
        for objective in args.objectives:
            t0 = time.perf_counter()
            if objective == "energy":  # the rates free at the ends (module docstring)
                kw_o = {k: v for k, v in kw.items() if k not in ("start_rate", "end_rate")}
                peer = None if args.acroplan_only else CasadiCat(body, args.intervals, rest_ends=False)
            else:
                kw_o, peer = kw, None if args.acroplan_only else CasadiTorque(body, args.intervals)
            print(f"[{name}, {objective}: CasADi problem built in {time.perf_counter() - t0:.1f} s, once]")
            run(name, body, kw_o, objective, peer, args)


if __name__ == "__main__":
    main()
