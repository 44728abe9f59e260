"""Spatial bodies: acroplan against CasADi + IPOPT on the falling cat, in the same run.

Problems: the bundled falling cat (acroplan.families.spatial.examples.falling_cat_turn: 180 degrees
about the long axis at L = 0 in 0.5 s, the shape back to bend 40 deg, within the cat's joint
ranges), and turns of ``--angles`` degrees about the same axis (the same shape, duration and
ranges).

Systems:
  acroplan  plan(**kw) as the example gives it (method="auto", conditions="free", rates zero at both
            ends, the joint limits of the link table); a success must also pass the Pinocchio check
            (acroplan.families.spatial.check.pinocchio_errors) to 1e-9.
  casadi    CasADi + IPOPT, direct multiple shooting, ``--intervals`` RK4 intervals, piecewise-constant
            joint rates (the first and the last zero, as the rates at the ends), minimum integral of
            |u|^2, the joint limits as bounds on the shooting nodes; the end attitude by its vector
            part (q_N[1:] = q_1[1:], q_N . q_1 >= 0); the same dynamics
            (q' = q (0, Omega) / 2, Omega = I(s)^-1 (R^T L - A(s) u)) with I(s), A(s) the model's
            own symbolic expressions turned into CasADi by sympy.lambdify; initial guess: the
            attitude interpolated on the geodesic (slerp), the joints constant, u = 0. A success:
            IPOPT reports success and the re-simulation of its piecewise-constant input (scipy
            DOP853, rtol = atol = 1e-12, interval by interval, the model's right-hand side) misses
            the target by at most 1e-6 (rotation angle and joints), as benchmarks/peers_planar.py.

Each problem is solved back to back by each system (``--repeat`` times, the fastest counts); the
checks are made afterwards, untimed.

Run:  python benchmarks/peers_spatial.py [--angles 45 90 180] [--intervals 100] [--repeat 1]
      (needs casadi: pip install ".[bench]")
"""

from __future__ import annotations

import argparse
import math
import platform
import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

import acroplan
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.check import pinocchio_errors, state_error
from acroplan.families.spatial.examples import falling_cat_turn
from acroplan.families.spatial.model import _symbolic_map

CASADI_TOL = 1e-6
ACROPLAN_TOL = 1e-9


def casadi_rotation(q):
    """:math:`R(q)` (3 x 3) of a CasADi quaternion ``q = (w, x, y, z)``."""
    import casadi as ca

    qw, qx, qy, qz = q[0], q[1], q[2], q[3]
    return ca.vertcat(ca.horzcat(qw**2 + qx**2 - qy**2 - qz**2, 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)),
                      ca.horzcat(2 * (qx * qy + qw * qz), qw**2 - qx**2 + qy**2 - qz**2, 2 * (qy * qz - qw * qx)),
                      ca.horzcat(2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), qw**2 - qx**2 - qy**2 + qz**2))


def casadi_field(body):
    """The body's field as a CasADi function ``f(x, u) -> x'`` of the state ``x = (q, s)`` (4 + m)
    and the joint rates ``u`` (m), with ``I(s)``, ``A(s)`` the model's own symbolic expressions
    (sympy lambdify)."""
    import casadi as ca

    m = body.n_inputs
    x, p, I, A, _ = _symbolic_map(body.links.parents)  # noqa: E741
    fn = sp.lambdify((x[4:], p), list(I) + [e for col in A for e in col],
                     modules=[{"sin": ca.sin, "cos": ca.cos}], cse=True)
    s = ca.SX.sym("s", m)
    vals = fn([s[i] for i in range(m)], body._param_tuple)
    Imat = ca.reshape(ca.vertcat(*vals[:9]), 3, 3).T
    Amat = ca.horzcat(*[ca.vertcat(*vals[9 + 3 * j:12 + 3 * j]) for j in range(m)])
    Lv = ca.DM(body.angular_momentum)
    xs, us = ca.SX.sym("x", 4 + m), ca.SX.sym("u", m)
    qw, qx, qy, qz = xs[0], xs[1], xs[2], xs[3]
    R = casadi_rotation(xs)
    Ifun = ca.Function("I", [s], [Imat, Amat])
    Ii, Ai = Ifun(xs[4:])
    om = ca.solve(Ii, ca.mtimes(R.T, Lv) - ca.mtimes(Ai, us))
    Xi = ca.vertcat(ca.horzcat(-qx, -qy, -qz), ca.horzcat(qw, -qz, qy), ca.horzcat(qz, qw, -qx),
                    ca.horzcat(-qy, qx, qw))
    f = ca.Function("f", [xs, us], [ca.vertcat(0.5 * ca.mtimes(Xi, om), us)])
    return f


class CasadiCat:
    """Direct multiple shooting with N RK4 intervals for one body, built once."""

    def __init__(self, body, N=100, rest_ends=True):
        import casadi as ca

        m = body.n_inputs
        f = casadi_field(body)
        opti = ca.Opti()
        X = opti.variable(4 + m, N + 1)
        U = opti.variable(m, N)
        T = opti.parameter()
        x0, x1 = opti.parameter(4 + m), opti.parameter(4 + m)
        dt = T / N
        for i in range(N):
            xk, uk = X[:, i], U[:, i]
            k1 = f(xk, uk)
            k2 = f(xk + dt / 2 * k1, uk)
            k3 = f(xk + dt / 2 * k2, uk)
            k4 = f(xk + dt * k3, uk)
            opti.subject_to(X[:, i + 1] == xk + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4))
        opti.subject_to(X[:, 0] == x0)
        opti.subject_to(X[1:4, N] == x1[1:4])
        opti.subject_to(ca.dot(X[:4, N], x1[:4]) >= 0)
        opti.subject_to(X[4:, N] == x1[4:])
        if rest_ends:  # the rates zero at both ends
            opti.subject_to(U[:, 0] == 0)
            opti.subject_to(U[:, N - 1] == 0)
        lim = body.default_limits()
        for j, name in enumerate(body.links.joint_names):
            lo, hi = lim.bounds(name) if lim is not None else (-math.inf, math.inf)
            if math.isfinite(lo):
                opti.subject_to(X[4 + j, :] >= lo)
            if math.isfinite(hi):
                opti.subject_to(X[4 + j, :] <= hi)
        opti.minimize(ca.sumsqr(U) * dt)
        opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": 1e-10,
                                                      "constr_viol_tol": 1e-12, "max_iter": 1000})
        self.opti, self.X, self.U, self.N, self.m = opti, X, U, N, m
        self.par = dict(T=T, x0=x0, x1=x1)

    def solve(self, T, x0, x1, guess=None):
        """IPOPT from the attitude on the geodesic (slerp) and the joints interpolated, or from
        ``guess`` (4 + m, N + 1) states at the nodes; returns ``(success, seconds, u (m, N))``."""
        opti, N = self.opti, self.N
        for name, v in (("T", T), ("x0", x0), ("x1", x1)):
            opti.set_value(self.par[name], v)
        q0, q1 = np.asarray(x0[:4]), np.asarray(x1[:4])
        r = rot.log(rot.qmul(rot.qconj(q0), q1))
        Xg = np.zeros((4 + self.m, N + 1))
        for k, s in enumerate(np.linspace(0, 1, N + 1)):
            Xg[:4, k] = rot.qmul(q0, rot.exp(s * r))
            Xg[4:, k] = x0[4:] + s * (np.asarray(x1[4:]) - np.asarray(x0[4:]))
        opti.set_initial(self.X, Xg if guess is None else guess)
        opti.set_initial(self.U, np.zeros((self.m, N)))
        opti.set_initial(opti.lam_g, 0)
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


def problems(angles):
    cat, kw = falling_cat_turn()
    out = []
    q_down = np.array([kw[k][0] for k in ("qw", "qx", "qy", "qz")])
    q_up = np.array([kw[k][1] for k in ("qw", "qx", "qy", "qz")])
    axis = rot.log(rot.qmul(rot.qconj(q_down), q_up))
    axis /= np.linalg.norm(axis)
    for a in angles:
        q1 = rot.qmul(q_down, rot.exp(math.radians(a) * axis))
        k = dict(kw, **rot.attitude_states([q_down, q1]))
        out.append((f"{a:g} deg", cat, k))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--angles", type=float, nargs="+", default=[45.0, 90.0, 180.0])
    ap.add_argument("--intervals", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=1)
    args = ap.parse_args()
    import casadi

    print(f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, casadi {casadi.__version__}; the falling cat, turns of {args.angles} deg, "
          f"{args.intervals} RK4 intervals, repeat {args.repeat}")
    probs = problems(args.angles)
    cat = probs[0][1]
    t0 = time.perf_counter()
    peer = CasadiCat(cat, args.intervals)
    print(f"CasADi problem built in {time.perf_counter() - t0:.1f} s (once)")
    acroplan.plan(cat, **probs[0][2])  # compiled integrators and Pinocchio models out of the timing
    for name, body, kw in probs:
        names = body.state_names
        x0 = np.array([kw[n][0] for n in names])
        x1 = np.array([kw[n][-1] for n in names])
        T = kw["times"][-1] - kw["times"][0]
        ta, tc = [], []
        for _ in range(args.repeat):
            t = time.perf_counter()
            r = acroplan.plan(body, verify=False, **kw)
            ta.append(time.perf_counter() - t)
            ok_c, dt_c, u = peer.solve(T, x0, x1)
            tc.append(dt_c)
        err_a = float(pinocchio_errors(body, x0, r.segments).max()) if r.success else float("nan")
        err_c = state_error(resimulate_piecewise(body, x0, T, u), x1) if ok_c else float("nan")
        dtc = T / u.shape[1]
        ic = float(np.sum(u**2) * dtc)
        sa = "yes" if r.success and err_a <= ACROPLAN_TOL else "no"
        sc = "yes" if ok_c and err_c <= CASADI_TOL else "no"
        print(f"\n{name}: acroplan solved {sa} in {min(ta) * 1e3:.0f} ms (check {err_a:.1e}, integral u^2 "
              f"{_energy(r):.4g}); casadi solved {sc} in {min(tc) * 1e3:.0f} ms (IPOPT {'success' if ok_c else 'failure'}, "
              f"re-simulation {err_c:.1e}, integral u^2 {ic:.4g})")


def _energy(r):
    """The integral of |u|^2 of a plan, by a 2000-point trapezoid of its dense input."""
    if not r.success:
        return float("nan")
    t = np.linspace(r.times[0], r.times[-1], 2001)
    u = r.evaluate(t).inputs
    return float(np.trapezoid(np.sum(u**2, axis=0), t))


if __name__ == "__main__":
    main()
