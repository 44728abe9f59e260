"""Optimal 3-D plans: acroplan's ``objective="energy"`` and ``"torque"`` against CasADi + IPOPT, in
the same run (issue #22).

Problems:
  trunk    bioptim's free-floating example body, one somersault and a half twist in 1.5 s at
           L = (36.3075, 0, 0) kg m^2/s, the arms from (2.9, -2.9) rad down to (0, 0), rates zero at
           both ends (acroplan.families.spatial.examples.trunk_twist; no joint limits);
  cat      the bundled falling cat, 180 degrees at L = 0 in 0.5 s within its joint ranges
           (examples.falling_cat_turn);
  dive     the bundled back full (acroplan.examples.load("back-full-twist"), issue #23): Yeadon's
           male1 with moving shoulders, one backward somersault and one twist in 1.5 s through its
           three waypoints (take-off, the right arm down half way, the landing), within the data's
           joint ranges and rate limits (15 rad/s).

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
            the joint ranges as bounds on the nodes (the cat); the dive (CasadiDive) the same
            with each waypoint on its node (the attitude as at the end), the joint ranges on the
            nodes and the rate limits on the rates (the inputs for energy, the rate states for
            torque), its guess the file's Yeadon angles and joints linear between waypoints;
            initial guess: the trunk as
            bioptim's example gives it (somersault 0 -> 2 pi, twist 0 -> pi, tilt 0, joints
            linear; Yeadon angles), the cat's attitude on the geodesic (slerp); rates zero.
            A success: IPOPT's, and its input re-simulated (scipy DOP853, rtol = atol = 1e-12,
            interval by interval) misses the end state by at most 1e-6.

Run:  python benchmarks/peers_optimal_spatial.py [--problems trunk cat dive] [--objectives energy torque]
      [--intervals 100] [--repeat 1] [--acroplan-only] [--max-coefficients 48]
      (needs casadi and pinocchio: pip install ".[bench]")
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


def torque_field(body):
    """CasADi functions of the torque problem's state ``x = (q, s, u)`` (4 + 2m) and the joint
    accelerations ``a`` (m): ``F(x, a) -> (x', |tau|^2)`` and ``tau(x, a)``, with tau from the
    Newton-Euler recursion acroplan compiles (acroplan.families.spatial.dynamics.newton_euler,
    written over CasADi expressions) at lambda = R(q)^T L."""
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
    F = ca.Function("F", [xs, acc], [ca.vertcat(f(xs[:4 + m], u), acc), sum(t * t for t in tau)])
    return F, ca.Function("tau", [xs, acc], [ca.vertcat(*tau)])


def rk4_shooting(opti, F, X, V, dt):
    """The multiple-shooting equations of one RK4 step per interval, ``X[:, i + 1]`` from
    ``X[:, i]`` under the interval's control ``V[:, i]`` (``F(x, v) -> (x', cost rate)``); returns
    each interval's cost, the rate integrated by the same RK4 weights."""
    terms = []
    for i in range(V.shape[1]):
        xk, vk = X[:, i], V[:, i]
        k1, c1 = F(xk, vk)
        k2, c2 = F(xk + dt / 2 * k1, vk)
        k3, c3 = F(xk + dt / 2 * k2, vk)
        k4, c4 = F(xk + dt * k3, vk)
        opti.subject_to(X[:, i + 1] == xk + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4))
        terms.append(dt / 6 * (c1 + 2 * c2 + 2 * c3 + c4))
    return terms


class CasadiTorque:
    """Minimum integral of |tau|^2 by direct multiple shooting (module docstring), built once."""

    def __init__(self, body, N=100):
        import casadi as ca

        m = body.n_inputs
        F, self.tau = torque_field(body)
        opti = ca.Opti()
        X = opti.variable(4 + 2 * m, N + 1)
        A = opti.variable(m, N)
        T = opti.parameter()
        x0, x1 = opti.parameter(4 + m), opti.parameter(4 + m)
        cost = sum(rk4_shooting(opti, F, X, A, T / N))
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


class CasadiDive:
    """Minimum energy or torque through waypoints by direct multiple shooting (module docstring):
    each waypoint's attitude (vector part, and the sign of the guess) and joints on its node, the
    joint ranges on the nodes, the rate limits on the rates, built once for ``times``."""

    def __init__(self, body, times, objective, N=100):
        import casadi as ca

        m = body.n_inputs
        times = np.asarray(times, dtype=float)
        T = float(times[-1] - times[0])
        nodes = [int(round((t - times[0]) / T * N)) for t in times]
        if any(abs(k - (t - times[0]) / T * N) > 1e-9 for k, t in zip(nodes, times)):
            raise ValueError(f"the waypoint times {list(times)} are not on the nodes of {N} intervals")
        torque = objective == "torque"
        n_x = 4 + (2 * m if torque else m)
        opti = ca.Opti()
        X = opti.variable(n_x, N + 1)
        V = opti.variable(m, N)        # the rates (energy) or their rates (torque)
        W = opti.parameter(4 + m, len(times))
        if torque:
            F = torque_field(body)[0]
        else:
            f = casadi_field(body)
            xs, us = ca.SX.sym("x", n_x), ca.SX.sym("u", m)
            F = ca.Function("F", [xs, us], [f(xs, us), ca.sumsqr(us)])
        terms = rk4_shooting(opti, F, X, V, T / N)
        cost = sum(terms[1:], terms[0])
        # the cost of each waypoint interval (compared with acroplan's per segment)
        self.interval_costs = [sum(terms[a + 1:b], terms[a]) for a, b in zip(nodes[:-1], nodes[1:])]
        opti.subject_to(X[:4 + m, 0] == W[:, 0])
        for j, k in enumerate(nodes[1:], start=1):
            opti.subject_to(X[1:4, k] == W[1:4, j])
            opti.subject_to(ca.dot(X[:4, k], W[:4, j]) >= 0)
            opti.subject_to(X[4:4 + m, k] == W[4:, j])
        if torque:   # the rates zero at both ends, as the file's start_rate and end_rate
            opti.subject_to(X[4 + m:, 0] == 0)
            opti.subject_to(X[4 + m:, N] == 0)
        _joint_bounds(opti, body, X)
        lim = body.default_limits()
        rates = dict(lim.input_bounds) if lim is not None else {}
        for j, name in enumerate(body.links.joint_names):
            r = rates.get(f"u_{name}", math.inf)
            if math.isfinite(r):
                row = X[4 + m + j, :] if torque else V[j, :]
                opti.subject_to(opti.bounded(-r, row, r))
        opti.minimize(cost)
        opti.solver("ipopt", {"print_time": False}, {"print_level": 0, "sb": "yes", "tol": 1e-10,
                                                      "constr_viol_tol": 1e-12, "max_iter": 1000})
        self.opti, self.X, self.V, self.W, self.cost = opti, X, V, W, cost
        self.N, self.m, self.T, self.nodes, self.torque = N, m, T, nodes, torque

    def solve(self, waypoints, guess):
        """IPOPT from ``guess`` (attitude and joints at the nodes, (4 + m, N + 1)), the rates their
        differences (torque) or zero inputs. ``waypoints`` (4 + m, K + 1), each attitude's sign that
        of the guess at its node. Returns ``(success, seconds, cost, v (m, N))``; the cost of each
        waypoint interval in ``self.last_interval_costs``."""
        opti, N, m = self.opti, self.N, self.m
        opti.set_value(self.W, waypoints)
        Xg = np.zeros((self.X.shape[0], N + 1))
        Xg[:4 + m] = guess
        if self.torque:
            Xg[4 + m:, 1:-1] = np.gradient(guess[4:], self.T / N, axis=1)[:, 1:-1]
            opti.set_initial(self.V, np.zeros((m, N)))
        else:
            opti.set_initial(self.V, np.diff(guess[4:], axis=1) / (self.T / N))
        opti.set_initial(self.X, Xg)
        opti.set_initial(opti.lam_g, 0)
        t0 = time.perf_counter()
        try:
            sol = opti.solve()
            ok, v, cost = True, np.atleast_2d(sol.value(self.V)), float(sol.value(self.cost))
            self.last_interval_costs = [float(sol.value(c)) for c in self.interval_costs]
        except RuntimeError:
            ok, v, cost = False, np.atleast_2d(opti.debug.value(self.V)), float("nan")
            self.last_interval_costs = [float("nan")] * len(self.interval_costs)
        return ok, time.perf_counter() - t0, cost, v.reshape(m, N)

    def resimulate(self, body, x0, v):
        """The model's own right-hand side (scipy DOP853, rtol = atol = 1e-12) under the solution's
        input ``v``, interval by interval: the states at the nodes (4 + m, N + 1), and for torque the
        rates at the end."""
        x, h = np.asarray(x0, dtype=float), self.T / self.N
        u = np.zeros(self.m)
        out = [x]
        for i in range(self.N):
            ui, vi = u.copy(), v[:, i]
            rhs = (lambda t, y: body.rhs(y, ui + vi * t)) if self.torque else (lambda t, y: body.rhs(y, vi))
            x = solve_ivp(rhs, (0.0, h), x, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]
            out.append(x)
            if self.torque:
                u = ui + vi * h
        return np.stack(out, axis=1), u


def dive_problem():
    """The bundled back full: ``(body, plan keywords, Yeadon angles of the waypoints (K + 1, 3),
    degrees, unwrapped, as the file gives them)``."""
    import tomllib

    from acroplan.io import examples

    prob = examples.load("back-full-twist")
    kw = dict(prob.plan_kwargs())
    for k in ("objective", "tau_max"):  # the file's own optimum (within the strength) is not this problem
        kw.pop(k, None)
    if kw.get("conditions") is None:
        kw.pop("conditions", None)
    angles = np.asarray(tomllib.loads(examples.text("back-full-twist"))["plan"]["attitude_euler_deg"], dtype=float)
    return prob.system, kw, angles


def dive_guess(body, kw, angles, N):
    """CasADi's initial states at the nodes: the file's Yeadon angles and the joints linear between
    the waypoints, one continuous quaternion sign."""
    times = np.asarray(kw["times"], dtype=float)
    t = np.linspace(times[0], times[-1], N + 1)
    G = np.zeros((body.n_states, N + 1))
    for j, name in enumerate(body.state_names[4:], start=4):
        G[j] = np.interp(t, times, np.asarray(kw[name], dtype=float))
    eul = np.stack([np.interp(t, times, angles[:, i]) for i in range(3)], axis=1)
    G[:4] = np.stack([rot.from_euler(e) for e in eul], axis=1)
    for k in range(1, N + 1):
        G[:4, k] *= np.sign(G[:4, k] @ G[:4, k - 1])
    return G


#: the optimum's largest basis size (``--max-coefficients``, plan()'s ``max_coefficients``; None: the default, 30)
MAX_COEFFICIENTS = None


def optimal_plan(body, objective, kw):
    """``acroplan.plan`` with ``objective`` (no independent check), and ``max_coefficients`` when given."""
    extra = {} if MAX_COEFFICIENTS is None else {"max_coefficients": MAX_COEFFICIENTS}
    return acroplan.plan(body, verify=False, objective=objective, **kw, **extra)


def timed_plan(body, objective, kw, walls, cpus):
    """:func:`optimal_plan` of the problem, its wall and CPU seconds appended to ``walls`` and
    ``cpus``."""
    t, c = time.perf_counter(), time.process_time()
    r = optimal_plan(body, objective, kw)
    walls.append(time.perf_counter() - t)
    cpus.append(time.process_time() - c)
    return r


def run_dive(objective, args):
    """The dive (module docstring): acroplan and CasADi back to back, ``--repeat`` times."""
    body, kw, angles = dive_problem()
    if objective == "energy":  # the rates free at the ends, for both (module docstring)
        kw = {k: v for k, v in kw.items() if k not in ("start_rate", "end_rate")}
    names = body.state_names
    Wp = np.array([[kw[k][j] for k in names] for j in range(len(kw["times"]))]).T
    t0 = time.perf_counter()
    peer = None if args.acroplan_only else CasadiDive(body, kw["times"], objective, args.intervals)
    print(f"[dive, {objective}: CasADi problem built in {time.perf_counter() - t0:.1f} s, once]")
    optimal_plan(body, objective, kw)  # warm: compiled functions
    guess = dive_guess(body, kw, angles, args.intervals)
    if peer is not None:
        for j, k in enumerate(peer.nodes):   # each waypoint's sign the guess's at its node
            Wp[:4, j] *= np.sign(guess[:4, k] @ Wp[:4, j])
    ta, ca_, tc = [], [], []
    for _ in range(args.repeat):
        r = timed_plan(body, objective, kw, ta, ca_)
        if peer is not None:
            c = time.process_time()
            ok_c, dt_c, cost_c, v = peer.solve(Wp, guess)
            tc.append((dt_c, time.process_time() - c))
    x0 = Wp[:, 0]
    err_a = float(pinocchio_errors(body, x0, r.segments).max()) if r.success else float("nan")
    opts = [s.optimality for s in r.segments] if r.success else []
    cost_a = sum(o.get("cost", float("nan")) for o in opts) if opts else float("nan")
    conv = bool(opts) and all(o.get("converged") for o in opts)
    sa = "yes" if r.success and err_a <= ACROPLAN_TOL and conv else "no"
    line = (f"\ndive, {objective}: acroplan solved {sa} in {min(ta):.3f} s wall, {min(ca_):.3f} s CPU (check "
            f"{err_a:.1e}, cost {cost_a:.6g}, per segment: "
            + "; ".join(f"cost {o.get('cost', float('nan')):.6g}, basis {o.get('basis_size')}, ladder {[n for n, _ in o.get('ladder', [])]}, KKT "
                        f"{o.get('kkt', float('nan')):.1e}, {o.get('evaluations')} evaluations" for o in opts) + ")")
    if peer is None:
        print(line)
        return
    if ok_c:
        nodes_x, u_end = peer.resimulate(body, x0, v)
        err_c = max(state_error(nodes_x[:, k], Wp[:, j]) for j, k in enumerate(peer.nodes))
        if peer.torque:
            err_c = max(err_c, float(np.abs(u_end).max()))
    else:
        err_c = float("nan")
    sc = "yes" if ok_c and err_c <= CASADI_TOL else "no"
    best_c = min(tc)
    print(line + f"\n    casadi solved {sc} in {best_c[0]:.3f} s wall, {best_c[1]:.3f} s CPU (re-simulation "
          f"{err_c:.1e}, cost {cost_c:.6g}, per interval {', '.join(f'{c:.6g}' for c in peer.last_interval_costs)})\n    ratio (CasADi / acroplan, wall) {best_c[0] / min(ta):.1f}x, CPU "
          f"{best_c[1] / min(ca_):.1f}x; cost acroplan / CasADi {cost_a / cost_c:.4f}")


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
    optimal_plan(body, objective, kw)  # warm: compiled functions
    guess = guess_nodes(name, body, x0, x1, args.intervals)
    # the end attitude's sign the guess ends on: CasADi's end condition (vector part, q_N . q_1 >= 0)
    # then asks for the same rotation as acroplan's (whose residual, log(q_1^-1 q), has no sign)
    x1c = x1.copy()
    x1c[:4] *= np.sign(guess[:4, -1] @ x1[:4])
    ta, ca_, tc = [], [], []
    for _ in range(args.repeat):
        r = timed_plan(body, objective, kw, ta, ca_)
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
    ap.add_argument("--problems", nargs="+", default=["trunk", "cat"], choices=["trunk", "cat", "dive"])
    ap.add_argument("--objectives", nargs="+", default=["energy", "torque"], choices=["energy", "torque"])
    ap.add_argument("--intervals", type=int, default=100)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--acroplan-only", action="store_true", help="time acroplan alone (no CasADi)")
    ap.add_argument("--max-coefficients", type=int, default=None,
                    help="plan()'s max_coefficients: the last basis size of acroplan's ladder (default 30)")
    args = ap.parse_args()
    global MAX_COEFFICIENTS
    MAX_COEFFICIENTS = args.max_coefficients
    import casadi

    print(f"machine: {platform.processor() or platform.machine()}, python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, casadi {casadi.__version__}; {args.intervals} RK4 intervals, repeat "
          f"{args.repeat}; acroplan's max_coefficients {MAX_COEFFICIENTS or 'default (30)'}")
    if "dive" in args.problems:
        for objective in args.objectives:
            run_dive(objective, args)
    for name, body, kw in problems([p for p in args.problems if p != "dive"]):
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
