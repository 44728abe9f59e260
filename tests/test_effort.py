"""Effort: joint torques of the two-link body, and energy- and torque-optimal plans.

* the torque's derivation (Routh, cyclic theta) against the Euler-Lagrange equations of the full
  free body (centre of mass and theta free);
* a forward simulation of the full equations of motion, driven by the computed torques alone,
  reproduces a planned motion, conserves the momentum and keeps the centre of mass still;
* power, work and the effort summary against brute force;
* optimal plans: closed-form optima (double integrator; the chained form's isoperimetric optimum),
  KKT residuals, improvement on the feasible plan, limits and torque limits respected.
"""

from __future__ import annotations

import dataclasses
import json
import math
from fractions import Fraction
import re

import mpmath
import numpy as np
import pytest
import sympy as sp
from scipy.integrate import solve_ivp

import acroplan
from acroplan.core.basis import Legendre
from acroplan.core.errors import InvalidInputError
from acroplan.core.optimal import EnergyOptimal, TorqueOptimal, energy, objective_strategy, optimize_segment
from acroplan.core.strategies import STRATEGIES
from acroplan.core.system import ControlAffineSystem
from acroplan.families.acrobot.effort import (AcrobotTorque, effort_summary, joint_torque, kinetic_energy,
                                              torque_coefficients, torque_expression, torque_optimal, torques)
from acroplan.zoo import random_segment

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml)
pytestmark = pytest.mark.xdist_group("test_effort")


# ----------------------------------------------------------------------------------------- helpers
def kkt_of(message: str) -> float:
    return float(re.search(r"relative KKT residual ([0-9.eE+-]+)", message).group(1))


def segment_energy(seg) -> float:
    return energy(seg.basis, seg.t1 - seg.t0, seg.basis_coefficients)


def plan_energy(result) -> float:
    return sum(segment_energy(s) for s in result.segments)


def theta_at(robot, theta0, phi0, phiT, T, w):
    lo, hi = robot.reachable_interval(theta0=theta0, phi0=phi0, phiT=phiT, T=T)
    return lo + w * (hi - lo)


@pytest.fixture(scope="module")
def body():
    return acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                          torso_length=0.35, leg_length=0.45, angular_momentum=10.0)


@pytest.fixture(scope="module")
def two_segment_plan(body):
    """A two-segment plan (free conditions: u continuous, u' jumps at the waypoint)."""
    t = [0.0, 1.2, 2.5]
    phi = [-1.0, -2.4, -0.6]
    th1 = theta_at(body, -0.3, phi[0], phi[1], t[1] - t[0], 0.35)
    th2 = theta_at(body, th1, phi[1], phi[2], t[2] - t[1], 0.6)
    r = acroplan.plan(body, times=t, theta=[-0.3, th1, th2], phi=phi, conditions="free")
    assert r.success, r.message
    return r


# ----------------------------------------------------------------------------------------- the full body
def full_body():
    """Lagrangian of the planar two-body system with the joint position (x, y), theta and phi all
    free: q = (x, y, theta, phi); no reduction, no centre-of-mass frame."""
    t = sp.Symbol("t", real=True)
    M, m, J, j, L, l = sp.symbols("M m J j L l", positive=True)
    x, y, th, ph = (sp.Function(n, real=True)(t) for n in ("x", "y", "theta", "phi"))

    def e(a):
        return sp.Matrix([sp.cos(a), sp.sin(a)])

    joint = sp.Matrix([x, y])
    torso, leg = joint + L * e(th + ph), joint + l * e(th)
    vt, vl = torso.diff(t), leg.diff(t)
    kin = (M * vt.dot(vt) + m * vl.dot(vl) + J * (th.diff(t) + ph.diff(t)) ** 2 + j * th.diff(t) ** 2) / 2
    q = [x, y, th, ph]
    EL = [sp.diff(sp.diff(kin, qi.diff(t)), t) - sp.diff(kin, qi) for qi in q]
    return dict(t=t, q=q, EL=EL, kin=kin, params=(M, m, J, j, L, l), torso=torso, leg=leg)


def test_torque_matches_euler_lagrange_of_the_full_free_body():
    """tau from the Routhian (cyclic theta, centre-of-mass frame) equals the joint's generalised
    force in the Euler-Lagrange equations of the full body, whose other three equations (x, y,
    theta) have zero force; theta' eliminated by P0 = h theta' + k phi'."""
    fb = full_body()
    t, (x, y, th, ph), EL = fb["t"], fb["q"], fb["EL"]
    d = torque_expression()
    S = d.symbols
    acc = [sp.Symbol(f"{n}_dd") for n in ("x", "y", "th", "ph")]
    vel = [sp.Symbol(f"{n}_d") for n in ("x", "y", "th", "ph")]
    subs = {}
    for qi, a, v in zip((x, y, th, ph), acc, vel):
        subs[qi.diff(t, 2)] = a
        subs[qi.diff(t)] = v
    EL = [sp.expand(E.subs(subs)) for E in EL]
    # free joint position and theta: their equations have no force; solve them for x'', y'', theta''
    # (linear in them: by LU, unsimplified, where sp.solve simplified for seconds; the comparison
    # below is at exact points)
    A, rhs = sp.linear_eq_to_matrix(EL[:3], acc[:3])
    sol = dict(zip(acc[:3], A.LUsolve(rhs)))
    tau_full = EL[3].subs(sol)
    # in the reduced variables: phi, u = phi', du = phi'', theta' from the momentum
    tau_full = tau_full.subs({ph: S["phi"], vel[3]: S["u"], acc[3]: S["du"]})
    M, m, J, j, L, l = fb["params"]
    ren = dict(zip((M, m, J, j, L, l), (S["M"], S["m"], S["J"], S["j"], S["L"], S["l"])))
    tau_full = tau_full.subs(ren)
    lumped = {S[k]: v for k, v in d.lumped.items()}
    h = (S["M1"] + S["A1"] * sp.cos(S["phi"])).subs(lumped)
    k = (S["M2"] + S["A2"] * sp.cos(S["phi"])).subs(lumped)
    tau_full = tau_full.subs(vel[2], (S["P0"] - k * S["u"]) / h)
    # exact comparison: the difference vanishes identically, whatever theta (checked at random
    # rational points with 60 significant digits: a non-zero expression would not vanish there);
    # the expression is evaluated by mpmath at 60 digits (lambdify), as sympy's N would, 10x faster
    diff = tau_full - d.tau
    rng = np.random.default_rng(3)
    names = ["M", "m", "J", "j", "L", "l", "P0", "phi", "u", "du"]
    f = sp.lambdify([S[n] for n in names] + [th], diff, "mpmath")
    g = sp.lambdify([S[n] for n in names], d.tau, "mpmath")
    with mpmath.workdps(60):
        for _ in range(6):
            point = [sp.Rational(int(rng.integers(1, 400)), int(rng.integers(1, 97))) * (-1 if n in ("P0", "u",
                     "du", "phi") and rng.random() < 0.5 else 1) for n in names]
            point.append(sp.Rational(int(rng.integers(-700, 700)), 100))
            exact = [mpmath.mpf(r.p) / r.q for r in point]
            value, scale = f(*exact), abs(g(*exact[:-1])) + 1
            assert abs(value) < 1e-45 * scale
    # and with the lumped coefficients: a du + b u^2 + c P0^2 - tau is zero as a rational function of
    # the parameters, the rates and cos(phi), sin(phi) taken as independent variables (stronger than
    # a trigonometric identity): exactly zero, in rational arithmetic, at 8 random rational points
    # (a non-zero numerator of degree d vanishes at a random point of numerators and denominators up
    # to 1e9 with probability about d / 1e9, Schwartz-Zippel; sp.simplify(...) == 0 took 10 s here,
    # sp.cancel 3-11 s)
    a, b, c = d.a.subs(lumped), d.b.subs(lumped), d.c.subs(lumped)
    e = a * S["du"] + b * S["u"] ** 2 + c * S["P0"] ** 2 - d.tau
    assert e.atoms(sp.Function) <= {sp.cos(S["phi"]), sp.sin(S["phi"])}
    cs = sp.symbols("cos_phi sin_phi")
    e = e.subs({sp.cos(S["phi"]): cs[0], sp.sin(S["phi"]): cs[1]})
    args = sorted(e.free_symbols, key=str)
    assert S["phi"] not in args and all(r.is_Integer for r in e.atoms(sp.Number))  # no float on the way
    exact = sp.lambdify(args, e, "math")  # only + - * / and powers: exact on Fractions
    for _ in range(8):
        point = [Fraction(int(rng.integers(1, 10**9)), int(rng.integers(1, 10**9))) for _ in args]
        assert exact(*point) == 0


def test_momentum_and_energy_of_the_derivation():
    """dT/d(theta') is the text's P0 = h theta' + k phi' (eq. 2), and the kinetic energy in the
    reduced variables is P0^2/(2h) + a u^2/2."""
    d = torque_expression()
    S = d.symbols
    lumped = {S[k]: v for k, v in d.lumped.items()}
    h = (S["M1"] + S["A1"] * sp.cos(S["phi"])).subs(lumped)
    k = (S["M2"] + S["A2"] * sp.cos(S["phi"])).subs(lumped)
    assert sp.simplify(d.momentum - (h * S["theta_dot"] + k * S["u"])) == 0
    E = d.kinetic.subs(S["theta_dot"], (S["P0"] - k * S["u"]) / h)
    assert sp.simplify(E - (S["P0"] ** 2 / (2 * h) + d.a.subs(lumped) * S["u"] ** 2 / 2)) == 0


def test_numeric_torque_and_its_derivatives_match_the_derivation(body):
    d = torque_expression()
    S = d.symbols
    P = body.physical
    phys = {S["M"]: P.torso_mass, S["m"]: P.leg_mass, S["J"]: P.torso_inertia, S["j"]: P.leg_inertia,
            S["L"]: P.torso_length, S["l"]: P.leg_length, S["P0"]: P.angular_momentum}
    f_tau = sp.lambdify((S["phi"], S["u"], S["du"]), d.tau.subs(phys), "numpy")
    lum = {S["M1"]: body.M1, S["A1"]: body.A1, S["M2"]: body.M2, S["A2"]: body.A2}
    fns = [sp.lambdify(S["phi"], e.subs(lum), "numpy") for e in
           (d.a, d.b, d.c, sp.diff(d.a, S["phi"]), sp.diff(d.b, S["phi"]), sp.diff(d.c, S["phi"]))]
    rng = np.random.default_rng(0)
    phi, u, du = rng.uniform(-7, 7, 50), rng.uniform(-6, 6, 50), rng.uniform(-30, 30, 50)
    np.testing.assert_allclose(joint_torque(body, phi, u, du), f_tau(phi, u, du), rtol=1e-12, atol=1e-12)
    for got, fn in zip(torque_coefficients(body, phi, derivatives=True), fns):
        np.testing.assert_allclose(got, fn(phi), rtol=1e-11, atol=1e-13)


def test_lumped_only_acrobot_has_no_torque(body, two_segment_plan):
    lumped = acroplan.Acrobot(**body.lumped())
    with pytest.raises(InvalidInputError) as e:
        joint_torque(lumped, 0.3, 1.0, 0.0)
    assert e.value.field == "robot.physical"
    r = acroplan.plan(lumped, times=[0, 1], theta=[0.0, theta_at(lumped, 0.0, -1.0, -2.0, 1.0, 0.5)],
                      phi=[-1.0, -2.0], conditions="free")
    for fn in (lambda: torques(r, 0.5), lambda: effort_summary(r), lambda: kinetic_energy(lumped, 0.1, 0.2)):
        with pytest.raises(InvalidInputError) as e:
            fn()
        assert e.value.field == "robot.physical"
    with pytest.raises(InvalidInputError, match="robot.physical"):
        acroplan.plan(lumped, times=[0, 1], theta=[0.0, 0.1], phi=[-1.0, -2.0], conditions="free",
                      method=torque_optimal())


def test_forward_simulation_of_the_full_body_reproduces_the_plan(body, two_segment_plan):
    """The full equations of motion (joint position, theta, phi all free; no momentum, no centre of
    mass used), driven by the computed joint torque alone, integrated by DOP853 at rtol = atol =
    1e-12 segment by segment, reproduce the planned theta(t) and phi(t) to 1e-8; the angular
    momentum stays P0 and the centre of mass stays at rest."""
    r = two_segment_plan
    fb = full_body()
    t, q, EL = fb["t"], fb["q"], fb["EL"]
    P = body.physical
    M, m, J, j, L, l = fb["params"]
    vals = {M: P.torso_mass, m: P.leg_mass, J: P.torso_inertia, j: P.leg_inertia, L: P.torso_length,
            l: P.leg_length}
    qs = sp.symbols("x y th ph")
    vs = sp.symbols("xd yd thd phd")
    acc = sp.symbols("xdd ydd thdd phdd")
    subs = {}
    for qi, a, v, s in zip(q, acc, vs, qs):
        subs[qi.diff(t, 2)] = a
        subs[qi.diff(t)] = v
    EL = [E.subs(subs).subs(dict(zip(q, qs))).subs(vals) for E in EL]
    Mq = sp.Matrix([[sp.diff(E, a) for a in acc] for E in EL])
    bias = sp.Matrix([E.subs({a: 0 for a in acc}) for E in EL])
    f_M = sp.lambdify((qs, vs), Mq, "numpy")
    f_b = sp.lambdify((qs, vs), bias, "numpy")
    torso = fb["torso"].subs(subs).subs(dict(zip(q, qs))).subs(vals)
    leg = fb["leg"].subs(subs).subs(dict(zip(q, qs))).subs(vals)
    vtorso = sp.Matrix([sum(sp.diff(c, s) * v for s, v in zip(qs, vs)) for c in torso])
    vleg = sp.Matrix([sum(sp.diff(c, s) * v for s, v in zip(qs, vs)) for c in leg])
    Mt, ml = P.torso_mass, P.leg_mass
    com = (Mt * torso + ml * leg) / (Mt + ml)
    vcom = (Mt * vtorso + ml * vleg) / (Mt + ml)
    ang = (Mt * (torso[0] * vtorso[1] - torso[1] * vtorso[0]) + ml * (leg[0] * vleg[1] - leg[1] * vleg[0])
           + P.torso_inertia * (vs[2] + vs[3]) + P.leg_inertia * vs[2])
    f_com = sp.lambdify((qs, vs), list(com) + list(vcom), "numpy")
    f_ang = sp.lambdify((qs, vs), ang, "numpy")

    def rhs(time, s):
        qq, vv = s[:4], s[4:]
        tau, _ = torques(r, time)
        Q = np.array([0.0, 0.0, 0.0, tau]) - np.array(f_b(qq, vv), dtype=float).ravel()
        return np.concatenate([vv, np.linalg.solve(np.array(f_M(qq, vv), dtype=float), Q)])

    # initial state: the plan's theta, phi, u(0); theta' from the momentum; the centre of mass at rest at 0
    th0, ph0 = r.waypoints[0]
    u0 = float(r.segments[0].input(0.0)[0])
    thd0 = (body.P0 - body.k(ph0) * u0) / body.h(ph0)
    et, el = np.array([math.cos(th0 + ph0), math.sin(th0 + ph0)]), np.array([math.cos(th0), math.sin(th0)])
    nt, nl = np.array([-et[1], et[0]]), np.array([-el[1], el[0]])
    joint = -(Mt * P.torso_length * et + ml * P.leg_length * el) / (Mt + ml)
    jointd = -(Mt * P.torso_length * nt * (thd0 + u0) + ml * P.leg_length * nl * thd0) / (Mt + ml)
    s = np.concatenate([joint, [th0, ph0], jointd, [thd0, u0]])
    worst = 0.0
    for seg in r.segments:
        te = np.linspace(seg.t0, seg.t1, 41)
        # the torque is evaluated at the segment's own coefficients: integrate inside each segment
        sol = solve_ivp(lambda tt, ss, seg=seg: rhs(min(max(tt, seg.t0 + 1e-15), seg.t1), ss), (seg.t0, seg.t1), s,
                        method="DOP853", rtol=1e-12, atol=1e-12, t_eval=te)
        assert sol.success
        planned = r.evaluate(te)
        worst = max(worst, float(np.max(np.abs(sol.y[2] - planned.theta))), float(np.max(np.abs(sol.y[3] -
                                                                                                   planned.phi))))
        for k in range(te.size):
            qq, vv = sol.y[:4, k], sol.y[4:, k]
            assert abs(f_ang(qq, vv) - body.P0) < 1e-9
            assert np.max(np.abs(np.array(f_com(qq, vv), dtype=float))) < 1e-9
        s = sol.y[:, -1]
    assert worst < 1e-8


def test_power_integrates_to_the_change_of_kinetic_energy(body, two_segment_plan):
    r = two_segment_plan
    es = effort_summary(r)
    first, last = r.segments[0], r.segments[-1]
    E0 = kinetic_energy(body, r.waypoints[0, 1], first.input(first.t0)[0])
    E1 = kinetic_energy(body, r.waypoints[-1, 1], last.input(last.t1)[0])
    assert es.net_work == pytest.approx(float(E1 - E0), rel=1e-10, abs=1e-10)


def _motion(seg, t):
    """phi, u, u' of a segment at times t, straight from its Legendre coefficients."""
    T = seg.t1 - seg.t0
    s = (t - seg.t0) / T
    c = seg.basis_coefficients[0]
    leg = np.polynomial.legendre.Legendre(c, domain=[0, 1])
    return seg.start[1] + T * (leg.integ(lbnd=0)(s)), leg(s), leg.deriv()(s) / T



def test_the_positive_work_of_split_panels_from_their_interpolants():
    """The same split panels with the motion given as the panels' interpolants (PanelInterpolants,
    from the values at each panel's 32 Gauss nodes): the pieces up to each root are the
    interpolants' Legendre series integrated (PanelInterpolants.integrals), with no call of the
    model; the closed form to 1e-14 again. On a panel that is not resolved the model is called for
    its pieces, and the value is the same."""
    from acroplan.core.effort import _GAUSS32, PanelInterpolants, _positive_work

    xg, wg = _GAUSS32
    P = 8
    edges = np.linspace(0.0, 1.0, P + 1)
    h = 1.0 / P
    f = lambda t: np.sin(20.0 * t) + 0.3  # noqa: E731
    F = lambda t: -np.cos(20.0 * t) / 20.0 + 0.3 * t  # noqa: E731
    a0, a1 = np.arcsin(-0.3), np.pi - np.arcsin(-0.3)
    roots = np.sort([(a0 + 2 * np.pi * k) / 20 for k in range(1, 4)] + [(a1 + 2 * np.pi * k) / 20 for k in range(4)])
    roots = roots[(roots > 0) & (roots < 1)]
    panels = np.minimum((roots * P).astype(int), P - 1)
    nodes = edges[:-1, None] + h * xg[None, :]  # (P, 32)
    panel_pow = (f(nodes) @ wg * h)[None, :]
    calls = []

    def model(t):
        calls.append(np.size(t))
        return np.cos(t)[None, :], f(t)[None, :]

    values = np.stack([np.cos(nodes), f(nodes)])  # (2, P, 32): a torque row, then the power's
    cuts = np.concatenate([[0.0], roots, [1.0]])
    exact = sum(max(F(b) - F(a), 0.0) for a, b in zip(cuts[:-1], cuts[1:]))
    for unresolved in (None, panels[0]):
        motion = PanelInterpolants(edges, values, model, 1)
        assert motion.resolved.all()
        if unresolved is not None:
            motion.resolved[unresolved] = False
        calls.clear()
        pos = np.zeros(1)
        _positive_work(motion, edges, np.zeros(roots.size, dtype=int), panels, roots, panel_pow, xg, wg, pos)
        assert abs(pos[0] - exact) < 1e-14
        assert calls == ([] if unresolved is None else [32 * int(np.sum(panels == unresolved))])

def test_effort_summary_against_brute_force(body, two_segment_plan):
    r = two_segment_plan
    es = effort_summary(r)
    tau2 = u2 = pos = net = peak = peak_pow = 0.0
    for seg in r.segments:  # 200,001 points per segment, trapezoid, each segment with its own values
        t = np.linspace(seg.t0, seg.t1, 200_001)
        phi, u, du = _motion(seg, t)
        tau = joint_torque(body, phi, u, du)
        pw = tau * u
        trap = lambda y: float(np.sum((y[1:] + y[:-1]) * np.diff(t)) / 2)  # noqa: E731
        tau2 += trap(tau**2)
        u2 += trap(u**2)
        pos += trap(np.maximum(pw, 0.0))
        net += trap(pw)
        peak = max(peak, float(np.max(np.abs(tau))))
        peak_pow = max(peak_pow, float(np.max(np.abs(pw))))
        inner = t[1:-1]
        np.testing.assert_allclose(torques(r, inner)[0], tau[1:-1], rtol=1e-12, atol=1e-9)
    assert es.torque_squared == pytest.approx(tau2, rel=1e-8)
    assert es.input_squared == pytest.approx(u2, rel=1e-8)
    assert es.positive_work == pytest.approx(pos, rel=1e-6)
    assert es.net_work == pytest.approx(net, rel=1e-8, abs=1e-9)
    assert peak <= es.peak_torque <= peak * (1 + 1e-8)
    assert peak_pow <= es.peak_power <= peak_pow * (1 + 1e-8)
    assert es.positive_work >= max(es.net_work, 0.0)
    assert set(es.to_dict()) == {"phi"}


def test_acrobot_torque_model_jacobian_matches_finite_differences(body):
    model = AcrobotTorque()
    basis = Legendre(8)
    rng = np.random.default_rng(4)
    c = rng.standard_normal((1, 8))
    s = np.linspace(0, 1, 33)
    x0 = np.array([0.2, -1.3])
    tau, jac = model(body, basis, x0, 1.7, c, s)
    fd = np.empty_like(jac)
    for k in range(8):
        e = np.zeros((1, 8))
        e[0, k] = 1e-6
        fd[:, :, k] = (model(body, basis, x0, 1.7, c + e, s)[0] - model(body, basis, x0, 1.7, c - e, s)[0]) / 2e-6
    np.testing.assert_allclose(jac, fd, rtol=1e-6, atol=1e-6 * np.abs(jac).max())
    # and tau itself is joint_torque of the motion the coefficients make
    phi = x0[1] + 1.7 * basis.integral(s) @ c[0]
    np.testing.assert_allclose(tau[0], joint_torque(body, phi, basis.matrix(s) @ c[0],
                                                    basis.matrix(s, 1) @ c[0] / 1.7), rtol=1e-13)


# ----------------------------------------------------------------------------------------- optimal plans
@dataclasses.dataclass(frozen=True)
class EffortTestDoubleIntegrator(ControlAffineSystem):
    """q' = v, v' = a: the minimum-energy input between two states is linear in time."""

    state_names = ("q", "v")
    input_names = ("a",)
    param_names = ()

    @classmethod
    def symbolic_fields(cls, x, p):
        return sp.Matrix([x[1], 0]), sp.Matrix([0, 1])


def test_energy_optimal_reaches_the_closed_form_optimum_of_the_double_integrator():
    """min int a^2 from (q0, v0) to (q1, v1) in T: a(t) = alpha + beta t with the controllability
    Gramian: E = d^T W^-1 d, d = (q1 - q0 - v0 T, v1 - v0), W = [[T^3/3, T^2/2], [T^2/2, T]]."""
    T, (q0, v0), (q1, v1) = 1.7, (0.3, -0.4), (1.9, 0.8)
    r = acroplan.plan(EffortTestDoubleIntegrator(), times=[0, T], q=[q0, q1], v=[v0, v1], conditions="free",
                      method=EnergyOptimal())
    assert r.success, r.message
    d = np.array([q1 - q0 - v0 * T, v1 - v0])
    W = np.array([[T**3 / 3, T**2 / 2], [T**2 / 2, T]])
    E = float(d @ np.linalg.solve(W, d))
    seg = r.segments[0]
    assert segment_energy(seg) == pytest.approx(E, rel=1e-12)
    lam = np.linalg.solve(W, d)  # a(t) = lam_1 (T - t) + lam_2
    t = np.linspace(0, T, 11)
    np.testing.assert_allclose(seg.input(t)[0], lam[0] * (T - t) + lam[1], atol=1e-10)
    assert kkt_of(seg.message) < 1e-8
    assert seg.method == "energy-optimal"


def test_energy_optimal_reaches_the_isoperimetric_optimum_of_the_chained_form():
    """x1' = u1, x2' = u2, x3' = x2 u1 from 0 to (0, 0, a): x3 is the area the closed curve (x1, x2)
    encloses, so the least length^2/T, hence the least energy, is the circle's: 4 pi |a| / T,
    with u a sinusoid of period T (the polynomial basis converges to it)."""
    a, T = 0.3, 1.5
    strategy = EnergyOptimal(rtol=1e-10)
    r = acroplan.plan(acroplan.ChainedForm(3), times=[0, T], x1=[0, 0], x2=[0, 0], x3=[0, a], conditions="free",
                      method=strategy)
    assert r.success, r.message
    seg = r.segments[0]
    assert segment_energy(seg) == pytest.approx(4 * math.pi * a / T, rel=1e-10)
    assert "converged in the basis" in seg.message and "NOT" not in seg.message
    assert kkt_of(seg.message) < 1e-6
    # constant speed on the circle
    t = np.linspace(0, T, 50)
    speed = np.hypot(*seg.input(t))
    np.testing.assert_allclose(speed, speed.mean(), rtol=1e-5)


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_energy_optimal_improves_on_the_feasible_plan(seed):
    p = random_segment(np.random.default_rng(seed))
    auto = acroplan.plan(p.robot, conditions="free", **p.plan_kwargs())
    opt = acroplan.plan(p.robot, conditions="free", method="energy-optimal", **p.plan_kwargs())
    assert auto.success and opt.success, opt.message
    assert opt.verified
    assert plan_energy(opt) <= plan_energy(auto) * (1 + 1e-12)
    assert kkt_of(opt.segments[0].message) < 1e-6
    assert "converged in the basis" in opt.segments[0].message


def test_the_family_starts_meet_the_target_and_find_the_better_basin():
    """The acrobot's starts (the bump family of the flat output, one bulge each way) reach theta(T)
    without an ODE; on a problem where the auto plan's basin is 21% above the better one, the
    default strategy (the family's starts) finds the better optimum, as path deformation does."""
    from acroplan.core import backend
    from acroplan.families.acrobot.effort import optimal_starts

    rng = np.random.default_rng(5)
    p = [random_segment(rng) for _ in range(10)][9]
    x0, x1 = np.array([p.theta0, p.phi0]), np.array([p.thetaT, p.phiT])
    interval = acroplan.core.Interval(p.robot, Legendre(6), None, x0, x1, p.T, {}, None, 1e-10, 2000)
    starts = optimal_starts(interval, Legendre(6))
    assert [label for label, _ in starts] == ["bump-", "bump+"]
    for _, c in starts:
        y, _ = backend.endpoint(p.robot, Legendre(6), x0, p.T, c)
        assert abs(y[0] - p.thetaT) < 1e-6 and abs(y[1] - p.phiT) < 1e-12
    kw = dict(conditions="free", **p.plan_kwargs())
    best = plan_energy(acroplan.plan(p.robot, method=EnergyOptimal(), **kw))
    auto_only = plan_energy(acroplan.plan(p.robot, method=EnergyOptimal(starts=("auto",)), **kw))
    deform = plan_energy(acroplan.plan(p.robot, method=EnergyOptimal(starts=("auto", "deform")), **kw))
    assert best < 0.8 * auto_only
    assert best == pytest.approx(deform, rel=2e-4)  # the same optimum, within the ladder's rtol


def test_the_predicted_change_of_the_ladder_matches_the_solved_one():
    """The ladder stops when one Newton step at the next size predicts a change < rtol: the
    prediction agrees with the optimum solved at that size."""
    checked = 0
    for seed in range(5, 30):
        p = random_segment(np.random.default_rng(seed))
        x0, x1 = np.array([p.theta0, p.phi0]), np.array([p.thetaT, p.phiT])
        interval = acroplan.core.Interval(p.robot, Legendre(6), None, x0, x1, p.T, {}, None, 1e-10, 2000)
        res, _ = EnergyOptimal().optimize(interval)
        assert res.success and res.converged_in_basis
        assert json.loads(json.dumps(res.to_dict()))["ladder"][-1][0] == res.sizes[-1][0]
        if "predicted by one Newton step" not in res.message:
            continue
        (n1, e1), (n2, e2_pred) = res.sizes[-2], res.sizes[-1]
        assert res.basis.n == n1
        solved = optimize_segment(p.robot, Legendre(n2), x0, x1, p.T,
                                  np.pad(res.coefficients, ((0, 0), (0, n2 - n1))))
        change_pred, change = (e1 - e2_pred) / e1, (e1 - solved.objective) / e1
        assert change < 1e-4
        assert change_pred == pytest.approx(change, rel=0.3, abs=1e-9)
        checked += 1
        if checked == 4:
            break
    assert checked == 4


def test_energy_optimal_respects_rate_and_joint_limits():
    p = random_segment(np.random.default_rng(8))
    free = acroplan.plan(p.robot, conditions="free", method="energy-optimal", **p.plan_kwargs())
    assert free.success
    u_max = 0.9 * free.max_abs_u
    lo, hi = min(p.phi0, p.phiT) - 0.05, max(p.phi0, p.phiT) + 0.4
    kw = dict(conditions="free", u_max=u_max, phi_min=lo, phi_max=hi, **p.plan_kwargs())
    auto = acroplan.plan(p.robot, **kw)
    opt = acroplan.plan(p.robot, method="energy-optimal", **kw)
    assert auto.success, auto.message
    assert opt.success, opt.message
    seg = opt.segments[0]
    assert seg.max_abs_u <= u_max + 1e-9
    a, b = seg.state_range
    assert lo - 1e-9 <= a and b <= hi + 1e-9
    assert plan_energy(free) <= plan_energy(opt) <= plan_energy(auto) * (1 + 1e-12)
    assert kkt_of(seg.message) < 1e-5


def test_a_multi_segment_plan_is_optimal_interval_by_interval(body, two_segment_plan):
    r0 = two_segment_plan
    kw = dict(times=list(r0.times), theta=list(r0.waypoints[:, 0]), phi=list(r0.waypoints[:, 1]),
              conditions="free")
    r = acroplan.plan(body, method=EnergyOptimal(), **kw)
    assert r.success and r.verified, r.message
    # u continuous at the waypoint (the free conditions)
    assert r.segments[0].input(r.segments[0].t1)[0] == pytest.approx(r.segments[1].input(r.segments[1].t0)[0],
                                                                        abs=1e-9)
    assert plan_energy(r) <= plan_energy(r0) * (1 + 1e-9)


def test_torque_optimal_minimises_the_torque(body):
    T, phi0, phiT = 1.4, -1.2, -2.6
    th = theta_at(body, 0.1, phi0, phiT, T, 0.7)
    kw = dict(times=[0, T], theta=[0.1, th], phi=[phi0, phiT], conditions="free")
    auto = acroplan.plan(body, **kw)
    e_opt = acroplan.plan(body, method=EnergyOptimal(), **kw)
    t_opt = acroplan.plan(body, method=torque_optimal(), **kw)
    assert auto.success and e_opt.success and t_opt.success, t_opt.message
    assert t_opt.segments[0].method == "torque-optimal"
    tau2 = {k: effort_summary(r).torque_squared for k, r in (("auto", auto), ("energy", e_opt), ("torque", t_opt))}
    assert tau2["torque"] <= tau2["energy"] * (1 + 1e-6)
    assert tau2["torque"] <= tau2["auto"] * (1 + 1e-6)
    assert plan_energy(e_opt) <= plan_energy(t_opt) * (1 + 1e-9)
    assert kkt_of(t_opt.segments[0].message) < 1e-5


def test_torque_limits_are_respected(body):
    T, phi0, phiT = 1.4, -1.2, -2.6
    th = theta_at(body, 0.1, phi0, phiT, T, 0.7)
    kw = dict(times=[0, T], theta=[0.1, th], phi=[phi0, phiT], conditions="free")
    for free_strategy, make in ((EnergyOptimal(), lambda tm: EnergyOptimal(torque=AcrobotTorque(), tau_max=tm)),
                                (torque_optimal(), lambda tm: torque_optimal(tau_max={"phi": tm}))):
        free = acroplan.plan(body, method=free_strategy, **kw)
        tau_max = 0.85 * effort_summary(free).peak_torque  # binding: 15% below the unlimited optimum's peak
        r = acroplan.plan(body, method=make(tau_max), **kw)
        assert r.success, r.message
        assert effort_summary(r).peak_torque <= tau_max * (1 + 1e-9)
        assert kkt_of(r.segments[0].message) < 1e-5
        if isinstance(free_strategy, TorqueOptimal):
            assert effort_summary(r).torque_squared >= effort_summary(free).torque_squared * (1 - 1e-9)
        else:
            assert plan_energy(r) >= plan_energy(free) * (1 - 1e-9)  # the limit costs something
    with pytest.raises(InvalidInputError, match="tau_max"):
        acroplan.plan(acroplan.ChainedForm(3), times=[0, 1], x1=[0, 0], x2=[0, 0], x3=[0, 0.1], conditions="free",
                      method=EnergyOptimal(tau_max=1.0))


def test_strategies_are_registered_and_validate_their_arguments():
    assert isinstance(STRATEGIES["energy-optimal"], EnergyOptimal)
    assert isinstance(STRATEGIES["torque-optimal"], TorqueOptimal)
    for bad in (dict(sizes=()), dict(sizes=(10, 6)), dict(rtol=0), dict(starts=("nope",)), dict(kkt_tol=-1),
                dict(tau_max=-3.0), dict(torque=3)):
        with pytest.raises(InvalidInputError):
            EnergyOptimal(**bad)
    assert type(objective_strategy("energy")) is EnergyOptimal
    assert objective_strategy("torque", tau_max=5.0).tau_max == 5.0
    with pytest.raises(InvalidInputError, match="objective"):
        objective_strategy("time")


def test_one_basis_size_when_n_coefficients_is_given():
    p = random_segment(np.random.default_rng(9))
    r = acroplan.plan(p.robot, conditions="free", method="energy-optimal", n_coefficients=10, **p.plan_kwargs())
    assert r.success, r.message
    assert r.segments[0].basis_coefficients.shape == (1, 10)
    assert "one basis size" in r.segments[0].message


def test_torques_without_the_jacobian_equal_the_full_call():
    """Results and sweeps ask the torque model for tau alone (model.torques); it must be the tau of
    the full call (with the Jacobian) the optimiser uses, for the acrobot and a planar body."""
    from acroplan.core.basis import make_basis
    from acroplan.core.system import model_torques
    from acroplan.families.planar import three_rods

    rng = np.random.default_rng(11)
    s = np.linspace(0.0, 1.0, 33)
    robot = acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                           torso_length=0.35, leg_length=0.45, angular_momentum=10.0)
    for system, x0 in ((robot, np.array([0.2, -2.5])), (three_rods(P0=0.7), np.array([0.1, 0.3, -0.4]))):
        model = system.torque_model()
        basis = make_basis("legendre", 8)
        c = rng.normal(size=(system.n_inputs, 8))
        full = model(system, basis, x0, 1.3, c, s)[0]
        fast = model_torques(model, system, basis, x0, 1.3, c, s)
        assert fast.shape == full.shape
        np.testing.assert_allclose(fast, full, rtol=1e-12, atol=1e-12 * np.max(np.abs(full)))


def test_the_roots_of_the_power_in_few_rounds():
    """effort._root_rounds on brackets of known roots (sin(20 t) + 0.3): every root to 1e-14 s, in at most 5 calls (the first round's 32-fold shrink, then the
    windows about the secant's zero; 32-fold rounds alone need 9 from brackets 1/60 wide), one call
    of all the brackets' points a round. And effort.peaks on the same function: 1.3."""
    from acroplan.core.effort import _drive, _root_rounds, peaks

    f = lambda t: np.sin(20.0 * t) + 0.3  # noqa: E731
    grid = np.linspace(0.0, 1.0, 61)
    v = f(grid)
    i = np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)
    lo, hi = grid[i], grid[i + 1]
    exact = np.sort(np.concatenate([(np.pi + np.arcsin(0.3)) / 20 + 2 * np.pi * np.arange(4) / 20,
                                    (2 * np.pi - np.arcsin(0.3)) / 20 + 2 * np.pi * np.arange(4) / 20]))
    exact = exact[exact < 1.0]
    calls = []

    def g(xs):
        calls.append(xs.size)
        return f(xs)[None, :]

    found = _drive(g, _root_rounds(np.zeros(lo.size, dtype=int), lo, hi))
    roots = np.sort([r for _, r in found])
    assert roots.size == exact.size == lo.size
    assert np.max(np.abs(roots - exact)) < 1e-14
    assert len(calls) <= 5 and all(n % lo.size == 0 for n in calls)
    assert peaks(lambda xs: f(xs)[None, :], grid, v[None, :])[0] == pytest.approx(1.3, abs=1e-12)


def test_a_refinement_that_breaks_the_limits_is_refused(monkeypatch):
    """The ladder's reported optimum is refined to the KKT target at the end; when that refinement
    leaves the limits (between the grid's points, as the falling cat's torque optimum did by 1.4e-4
    rad/s), the point the ladder accepted is reported, within its limits, the refused refinement
    named in the message (a refinement made to break the rate limit here)."""
    import acroplan.core.optimum as optimum

    p = random_segment(np.random.default_rng(8))
    free = acroplan.plan(p.robot, conditions="free", method="energy-optimal", **p.plan_kwargs())
    u_max = 0.9 * free.max_abs_u
    kw = dict(conditions="free", u_max=u_max, **p.plan_kwargs())
    plain = acroplan.plan(p.robot, method="energy-optimal", **kw)
    assert plain.success, plain.message
    refine = optimum.OptimalRun.refine

    def breaking(self, kkt_tol):
        refine(self, kkt_tol)
        self.z = self.z * 1.5  # the rate limit broken
        return self

    monkeypatch.setattr(optimum.OptimalRun, "refine", breaking)
    res = acroplan.plan(p.robot, method="energy-optimal", **kw)
    assert res.success, res.message
    assert "its refinement was refused" in res.segments[0].message
    assert res.segments[0].max_abs_u <= u_max * (1 + 1e-9)


def test_a_peak_by_two_zooms_and_the_parabola_and_ends_that_need_none():
    """effort.peaks: a peak between the samples to 1e-14 in two calls (two 32-fold zooms, then the
    vertex of the parabola through the best point and its neighbours: the best point alone is off
    by about |f''| h^2 / 8, 1e-9 here); a maximum at an end where the function falls inward with no
    call at all; and one a hair inside the end, which the end's sample alone would miss, found."""
    from acroplan.core.effort import peaks

    grid = np.linspace(0.0, 1.0, 101)
    calls = []

    def counted(f):
        def g(xs):
            calls.append(xs.size)
            return f(xs)[None, :]
        return g

    f = lambda t: 1.0 + 0.5 * np.cos(30.0 * (t - 0.41137))  # noqa: E731  peaks of 1.5 at 0.41137 + k 2 pi / 30
    got = peaks(counted(f), grid, f(grid)[None, :])[0]
    assert abs(got - 1.5) < 1e-14 and len(calls) == 2
    calls.clear()
    g = np.exp
    assert peaks(counted(g), grid, g(grid)[None, :])[0] == np.e and not calls
    calls.clear()
    h = lambda t: 1.0 + np.exp(-400.0 * (t - 0.9965) ** 2)  # noqa: E731  max 2 at 0.9965, between the last samples
    assert h(grid).max() < 2.0 - 1e-4
    assert abs(peaks(counted(h), grid, h(grid)[None, :])[0] - 2.0) < 1e-14 and len(calls) == 2


def test_peak_times_give_each_peak_with_its_time():
    """effort.peak_times: the peaks of effort.peaks (the same numbers) and where they are: the
    cosine's peak and the narrow bump's between the samples to 1e-9 of the interval (two zooms and
    the parabola's vertex), a maximum at an end at the end."""
    from acroplan.core.effort import peak_times, peaks

    grid = np.linspace(0.0, 1.0, 101)
    rows = lambda t: np.vstack([1.0 + 0.5 * np.cos(30.0 * (t - 0.41137)),  # noqa: E731
                                1.0 + np.exp(-400.0 * (t - 0.9965) ** 2), np.exp(t)])
    got, when = peak_times(rows, grid, rows(grid))
    assert np.array_equal(got, peaks(rows, grid, rows(grid)))
    assert np.allclose(got, [1.5, 2.0, np.e], rtol=1e-14, atol=0)
    on = 0.41137 + 2.0 * np.pi / 30.0 * np.round((when[0] - 0.41137) * 30.0 / (2.0 * np.pi))
    assert abs(when[0] - on) < 1e-9 and abs(when[1] - 0.9965) < 1e-9 and when[2] == 1.0


def test_the_positive_work_of_split_panels():
    """effort._positive_work on P(t) = sin(20 t) + 0.3 over [0, 1] on 8 panels, split at its exact
    roots (the pieces up to each panel's last root by the panel's rule, the rest as the panel's
    integral less them): the closed form of the integral of max(P, 0) to 1e-14."""
    from acroplan.core.effort import _GAUSS32, _positive_work

    xg, wg = _GAUSS32
    P = 8
    edges = np.linspace(0.0, 1.0, P + 1)
    f = lambda t: np.sin(20.0 * t) + 0.3  # noqa: E731
    F = lambda t: -np.cos(20.0 * t) / 20.0 + 0.3 * t  # noqa: E731
    a0, a1 = np.arcsin(-0.3), np.pi - np.arcsin(-0.3)  # sin x = -0.3
    roots = np.sort([(a0 + 2 * np.pi * k) / 20 for k in range(1, 4)] + [(a1 + 2 * np.pi * k) / 20 for k in range(4)])
    roots = roots[(roots > 0) & (roots < 1)]
    panels = np.minimum((roots * P).astype(int), P - 1)
    h = 1.0 / P
    panel_pow = np.array([[np.sum(f(e + h * xg) * wg) * h for e in edges[:-1]]])
    pos = np.zeros(1)
    _positive_work(lambda t: (None, f(t)[None, :]), edges, np.zeros(roots.size, dtype=int), panels, roots, panel_pow,
                   xg, wg, pos)
    cuts = np.concatenate([[0.0], roots, [1.0]])
    exact = sum(max(F(b) - F(a), 0.0) for a, b in zip(cuts[:-1], cuts[1:]))
    assert np.unique(panels).size >= 5 and abs(pos[0] - exact) < 1e-14


def test_the_spatial_effort_summary_in_one_call_a_segment(monkeypatch):
    """The falling cat's effort summary calls its torque model once a joint motion (the grid): every
    panel's interpolant resolves its torques and powers (PanelInterpolants), and the later rounds
    read them. Its two segments are two loops of one joint motion at L = 0 (effort_summary works out
    their effort once: test_repeated_joint_motions_are_summed_from_one_summary). With the
    interpolants off (INTERPOLANT_TAIL = -inf) the model is called four times a motion (the grid,
    two rounds of the roots with the peaks' two zooms, the split panels): the same work, peaks and
    integrals to 1e-13 (measured 1.2e-15); and there the roots' brackets of 1e-7 of a segment
    (ROOT_RTOL) give the same numbers as brackets of 1e-14 s to 1e-13."""
    from acroplan.core import effort as E
    from acroplan.core import result as R
    from acroplan.families.spatial.examples import falling_cat_turn

    body, kw = falling_cat_turn()
    r = acroplan.plan(body, verify=False, **kw)
    calls = []
    inner = R.PlanResult._segment_torques

    def counted(self, *a):
        calls.append(1)
        return inner(self, *a)

    monkeypatch.setattr(R.PlanResult, "_segment_torques", counted)
    fast = E.effort_summary(r)
    assert len(r.segments) == 2 and len(calls) == 1
    calls.clear()
    monkeypatch.setattr(E, "INTERPOLANT_TAIL", -math.inf)
    model = E.effort_summary(r)
    assert len(calls) == 4
    monkeypatch.setattr(E, "ROOT_RTOL", 1e-14 / max(s.t1 - s.t0 for s in r.segments))
    tight = E.effort_summary(r)
    for name, e in fast.items():
        for field in ("positive_work", "peak_torque", "peak_power", "torque_squared", "net_work"):
            assert getattr(e, field) == pytest.approx(getattr(model[name], field), rel=1e-13, abs=1e-15)
            assert getattr(model[name], field) == pytest.approx(getattr(tight[name], field), rel=1e-13, abs=1e-15)


def test_repeated_joint_motions_are_summed_from_one_summary(monkeypatch):
    """Segments with the same joint motion and the same start, up to what the torque model says the
    torques do not depend on (SpatialTorque.start_key: the attitude at L = 0), have one effort,
    worked out once and summed: the falling cat's two loops (L = 0, two attitudes) are one motion,
    the twisting somersault's two segments (L != 0) two; the summary is the one of every segment
    worked out on its own, to 1e-13 (the same numbers but for the segments' own times, rounded
    from their starts), and the integrals are twice a loop's."""
    from acroplan.core import effort as E
    from acroplan.families.spatial.examples import falling_cat_turn, twisting_somersault

    body, kw = falling_cat_turn()
    cat = acroplan.plan(body, verify=False, **kw)
    model = cat._torque_setup()[0]
    a, b = cat.segments
    assert not np.allclose(a.start[:4], b.start[:4])  # two attitudes
    assert E._motion_key(cat, a, model) == E._motion_key(cat, b, model)
    body, kw = twisting_somersault()
    twist = acroplan.plan(body, verify=False, **kw)
    m2 = twist._torque_setup()[0]
    assert len({E._motion_key(twist, s, m2) for s in twist.segments}) == len(twist.segments) == 2
    once = E.effort_summary(cat)
    keys = iter(range(10))
    monkeypatch.setattr(E, "_motion_key", lambda *args: next(keys))  # every segment on its own
    each = E.effort_summary(cat)
    for name, e in once.items():
        for field in ("positive_work", "net_work", "torque_squared", "input_squared", "peak_torque",
                      "peak_power"):
            v, w = getattr(e, field), getattr(each[name], field)
            assert abs(v - w) <= 1e-13 * max(abs(w), 1.0), (name, field, v, w)
        # the integrals of the two loops: twice one loop's
        loop = E._segment_effort(cat, a, model, cat._torque_setup()[2], *E._GAUSS32)
        j = list(once).index(name)
        assert e.torque_squared == pytest.approx(2 * loop["tau2"][j], rel=1e-15, abs=0)
        assert e.peak_torque == loop["peak_tau"][j]


def test_panel_interpolants_serve_where_they_resolve_and_call_the_model_elsewhere():
    """PanelInterpolants on 8 panels of [0, 1] from the values at each panel's 32 Gauss nodes:
    sin(20 t) + 0.3 (analytic: every panel resolved) to 1e-14 at 1000 random times, nodes and edges
    included, without a call of the model; |t - 0.55| + t (a kink inside panel 4): that panel alone
    goes to the model, in one call for all its times, and its times get the model's values."""
    from acroplan.core.effort import _GAUSS32, PanelInterpolants

    xg = _GAUSS32[0]
    edges = np.linspace(0.0, 1.0, 9)
    nodes = (edges[:-1, None] + (1.0 / 8) * xg[None, :])
    t = np.concatenate([np.random.default_rng(3).uniform(0.0, 1.0, 1000), nodes[2], edges])
    for f, bad in ((lambda x: np.sin(20 * x) + 0.3, []), (lambda x: np.abs(x - 0.55) + x, [4])):
        asked = []

        def model(x, f=f):
            asked.append(np.array(x))
            return f(x)[None, :], 2.0 * f(x)[None, :]

        vals = np.stack([f(nodes), 2.0 * f(nodes)])
        pi = PanelInterpolants(edges, vals, model, 1)
        assert np.flatnonzero(~pi.resolved).tolist() == bad
        tau, pw = pi(t)
        assert np.abs(tau[0] - f(t)).max() < 1e-14 and np.abs(pw[0] - 2.0 * f(t)).max() < 2e-14
        assert pi.calls == len(asked) == (1 if bad else 0)
        if bad:
            inside = (t >= edges[4]) & (t < edges[5])
            assert np.array_equal(np.sort(asked[0]), np.sort(t[inside]))


def test_gauss_legendre_is_numpys_rule_computed_once_and_read_only():
    """core.basis.gauss_legendre: numpy's leggauss to the bit, the same arrays on a second call,
    not writable, and exact for polynomials of degree 2n - 1 (the rule's order) on [-1, 1]."""
    from acroplan.core.basis import gauss_legendre

    for n in (1, 7, 32, 64):
        x, w = gauss_legendre(n)
        xr, wr = np.polynomial.legendre.leggauss(n)
        assert np.array_equal(x, xr) and np.array_equal(w, wr)
        assert gauss_legendre(n)[0] is x and not x.flags.writeable and not w.flags.writeable
        k = 2 * n - 2  # an even degree below 2n: the integral of x^k is 2 / (k + 1)
        assert abs(w @ x**k - 2.0 / (k + 1)) < 1e-14


def _former_first_candidates(grid, values, count):
    """The peaks' first-round candidates as _peak_rounds chose them before the fifteenth session
    (padded rows, a full stable argsort, the finite ones kept): ``(rows, idx)``."""
    v = np.abs(values)
    best = v.max(axis=1)
    pad = np.full((v.shape[0], 1), -np.inf)
    left, right = np.hstack([pad, v[:, :-1]]), np.hstack([v[:, 1:], pad])
    cand = np.where((v >= left) & (v >= right) & (v >= 0.99 * best[:, None]), v, -np.inf)
    top = np.argsort(-cand, axis=1, kind="stable")[:, :count]
    rows = np.repeat(np.arange(v.shape[0]), top.shape[1])
    idx = top.ravel()
    ok = np.isfinite(cand[rows, idx])
    return rows[ok], idx[ok]


def test_the_peaks_first_round_takes_the_candidates_it_took_before(monkeypatch):
    """effort._peak_rounds' first round (local maxima by shifted slices, the few found ordered by
    lexsort, the grid read in place) asks for the same zoom times as the former one (padded copies,
    a full argsort; kept here as the reference) on rows with plateaus, ties, equal neighbours, an
    infinite sample, maxima at the ends and single samples: the effort summaries' peaks stay the
    same to the bit (checked on 41 plans when it was changed)."""
    from acroplan.core import effort

    rng = np.random.default_rng(3)
    for trial in range(200):
        K = int(rng.integers(1, 40))
        r = int(rng.integers(1, 5))
        grid = np.sort(rng.uniform(0.0, 1.0, K))
        grid[0] = 0.0
        values = np.round(rng.normal(size=(r, K)), 1)  # coarse values: ties and plateaus
        if K > 2 and trial % 3 == 0:
            values[0, -1] = values[0].max() + 1.0  # a maximum at the end
        if trial % 7 == 0:
            values[-1, int(rng.integers(K))] = np.inf
        if trial % 5 == 0:
            values[0, :] = 1.0  # a plateau: every sample a local maximum
        rows, idx = _former_first_candidates(grid, values, effort.PEAK_CANDIDATES)
        # the former round's candidates, through the same test of whether they can still rise
        v = np.abs(values)
        best = v.max(axis=1)
        keep = effort._hopeful(np.broadcast_to(grid, (rows.size, K)), v[rows], idx, best[rows], ends=True)
        rows, idx = rows[keep], idx[keep]
        lo, hi = grid[np.maximum(idx - 1, 0)], grid[np.minimum(idx + 1, K - 1)]
        keep = hi > lo
        lo, hi = lo[keep], hi[keep]
        frac = np.linspace(0.0, 1.0, effort.PEAK_POINTS)
        want = lo[:, None] + (hi - lo)[:, None] * frac[None, :]
        if want.size:
            want[:, -1] = hi
        gen = effort._peak_rounds(grid, values)
        try:
            got = next(gen)
        except StopIteration:
            got = np.zeros(0)
        assert np.array_equal(got, want.ravel()), trial
