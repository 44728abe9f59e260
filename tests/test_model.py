"""Chapter 2: the momentum formula, the lumped parameters, the state equation."""

import numpy as np
import pytest
import sympy as sp
from scipy.integrate import quad

import acroplan
from acroplan.core import backend as _integrate
from acroplan.core.basis import Legendre


def test_eq2_and_lumped_coefficients_derived_from_eq1():
    """Eq. (1) with the joint as origin gives eq. (2) and the M1, A1, M2, A2 of eq. (3)."""
    t = sp.Symbol("t")
    M, m, J, j, L, l = sp.symbols("M m J j L l", positive=True)
    th = sp.Function("theta")(t)
    ph = sp.Function("phi")(t)
    # link 1 = leg (mass m), link 2 = torso (mass M); positions of the centres of mass from the joint
    x1, y1 = l * sp.cos(th), l * sp.sin(th)
    x2, y2 = L * sp.cos(th + ph), L * sp.sin(th + ph)
    d = sp.diff
    P = (j * d(th, t) + J * d(th + ph, t)
         + m * M / (m + M) * ((x2 - x1) * (d(y2, t) - d(y1, t)) - (d(x2, t) - d(x1, t)) * (y2 - y1)))
    thd, phd = sp.symbols("thd phd")
    P = P.subs({d(th, t): thd, d(ph, t): phd})
    P = sp.simplify(sp.expand_trig(sp.expand(P)))
    mu = m * M / (m + M)
    eq2 = ((j + J + mu * (L**2 + l**2 - 2 * L * l * sp.cos(ph))) * thd + (J + mu * (L**2 - L * l * sp.cos(ph))) * phd)
    assert sp.simplify(P - eq2) == 0
    # lumped parameters: h = M1 + A1 cos, k = M2 + A2 cos
    Ms, ms, Js, js, Ls, ls = 40.0, 20.0, 1.8, 1.2, 0.35, 0.45
    robot = acroplan.Acrobot.from_physical(torso_mass=Ms, leg_mass=ms, torso_inertia=Js, leg_inertia=js,
                                           torso_length=Ls, leg_length=ls, angular_momentum=1.0)
    subs = {M: Ms, m: ms, J: Js, j: js, L: Ls, l: ls}
    h = sp.Poly(sp.expand(eq2.coeff(thd)).subs(subs), sp.cos(ph))
    k = sp.Poly(sp.expand(eq2.coeff(phd)).subs(subs), sp.cos(ph))
    assert float(h.coeff_monomial(1)) == pytest.approx(robot.M1, rel=1e-14)
    assert float(h.coeff_monomial(sp.cos(ph))) == pytest.approx(robot.A1, rel=1e-14)
    assert float(k.coeff_monomial(1)) == pytest.approx(robot.M2, rel=1e-14)
    assert float(k.coeff_monomial(sp.cos(ph))) == pytest.approx(robot.A2, rel=1e-14)
    assert robot.A2 == pytest.approx(robot.A1 / 2, rel=1e-15)


def test_state_equation_solves_eq2_for_theta_dot():
    f, G = acroplan.Acrobot.example().symbolic()
    (theta, phi), (M1, A1, M2, A2, P0) = acroplan.Acrobot.example().symbols()
    u = sp.Symbol("u")
    thd = f[0] + G[0] * u
    assert sp.simplify((M1 + A1 * sp.cos(phi)) * thd + (M2 + A2 * sp.cos(phi)) * u - P0) == 0
    assert G[1] == 1 and f[1] == 0


def _momentum_eq1(body, theta, phi, thd, phd):
    """Eq. (1) evaluated numerically from the link centres of mass (origin at the joint)."""
    M, m, J, j = body.torso_mass, body.leg_mass, body.torso_inertia, body.leg_inertia
    L, l = body.torso_length, body.leg_length
    x1, y1 = l * np.cos(theta), l * np.sin(theta)
    vx1, vy1 = -l * np.sin(theta) * thd, l * np.cos(theta) * thd
    x2, y2 = L * np.cos(theta + phi), L * np.sin(theta + phi)
    vx2, vy2 = -L * np.sin(theta + phi) * (thd + phd), L * np.cos(theta + phi) * (thd + phd)
    return (j * thd + J * (thd + phd) + m * M / (m + M) * ((x2 - x1) * (vy2 - vy1) - (vx2 - vx1) * (y2 - y1)))


def test_momentum_is_conserved_along_simulated_motion(physical_robot):
    rng = np.random.default_rng(3)
    basis = Legendre(6)
    c = rng.normal(size=(1, 6)) * 3
    T = 2.0
    s = np.linspace(0, 1, 101)
    X = _integrate.sample(physical_robot, basis, [0.3, -2.0], T, c, s)
    u = basis.matrix(s) @ c[0]
    thd = physical_robot.rhs(X, u[None, :])[0]
    P = _momentum_eq1(physical_robot.physical, X[0], X[1], thd, u)
    assert np.max(np.abs(P - physical_robot.P0)) < 1e-10 * max(1.0, abs(physical_robot.P0))
    # and the same through the lumped eq. (2)
    assert np.max(np.abs(physical_robot.momentum(thd, u, X[1]) - physical_robot.P0)) < 1e-10


def test_folded_body_rotates_fastest(physical_robot):
    """NOTES.md geometry: A1 < 0, so h is smallest at phi = 0 (folded)."""
    assert physical_robot.A1 < 0
    assert physical_robot.h(0.0) < physical_robot.h(np.pi)


@pytest.mark.parametrize("phi", [-7.0, -3.2, -np.pi, -1.0, 0.0, 0.5, np.pi, 4.0, 9.5])
def test_F_is_a_continuous_antiderivative_of_k_over_h(pike_robot, phi):
    r = pike_robot
    val, _ = quad(lambda p: r.k(p) / r.h(p), 0.0, phi, epsabs=1e-13, epsrel=1e-13, limit=200)
    assert float(r.F(phi) - r.F(0.0)) == pytest.approx(val, abs=1e-11)


def test_physical_validation_names_the_field():
    kw = dict(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2, torso_length=0.35,
              leg_length=0.45, angular_momentum=10.0)
    for field, bad, match in [("torso_mass", 0.0, "torso_mass: must be > 0"),
                              ("leg_inertia", -1.0, "leg_inertia: must be > 0"),
                              ("leg_length", -0.1, "leg_length: must be >= 0"),
                              ("angular_momentum", float("nan"), "angular_momentum: must be finite"),
                              ("torso_length", "abc", "torso_length: must be a real number")]:
        with pytest.raises(acroplan.InvalidInputError, match=match):
            acroplan.Acrobot.from_physical(**{**kw, field: bad})
    with pytest.raises(ValueError, match=r"M1: must exceed \|A1\|"):
        acroplan.Acrobot(M1=0.4, A1=-0.5, M2=0.2, A2=-0.25, P0=1.0)
    with pytest.raises(acroplan.InvalidInputError, match="P0: must be finite"):
        acroplan.Acrobot(M1=1.0, A1=-0.5, M2=0.2, A2=-0.25, P0=float("inf"))


def test_robot_is_immutable(pike_robot):
    with pytest.raises(Exception):
        pike_robot.P0 = 3.0


def test_the_acrobots_direct_fields_are_those_of_its_sympy_fields():
    """Issue #24 (start-up): the acrobot's integrator fields written as heyoka expressions and its
    checking right-hand side written out are what heyoka's from_sympy and sympy.lambdify make of its
    sympy fields: equal expressions (the same compiled code and cache entry), the same bits."""
    import heyoka as hy

    from acroplan.core.heyoka_import import from_sympy
    from acroplan.core.system import ControlAffineSystem

    robot = acroplan.Acrobot(M1=2.0, A1=-0.5, M2=0.5, A2=-0.25, P0=1.0)
    hx = hy.make_vars(*robot.state_names)
    hp = tuple(hy.par[i] for i in range(len(robot.param_names)))
    fe, Ge = robot.taylor_fields(tuple(hx), hp)
    x, p = robot.symbols()
    f, G = robot.symbolic()
    s_dict = {**dict(zip(x, hx)), **dict(zip(p, hp))}
    for r in range(2):
        assert (fe[r] is None) == (f[r] == 0) and (fe[r] is None or fe[r] == from_sympy(f[r], s_dict))
        assert (Ge[r][0] is None) == (G[r, 0] == 0)
        assert Ge[r][0] is None or Ge[r][0] == from_sympy(G[r, 0], s_dict)
    u = (sp.Symbol("_u0", real=True),)
    ref = sp.lambdify((x, u, p), list(f + G * sp.Matrix(u)), modules="numpy")
    assert ControlAffineSystem._numeric(robot) is not robot._numeric()  # (the written-out one)
    rng = np.random.default_rng(24)
    for _ in range(200):
        xs, us = tuple(rng.normal(0, 4, 2).tolist()), tuple(rng.normal(0, 10, 1).tolist())
        ps = tuple(rng.uniform(0.1, 3, 5).tolist())
        assert [float(v) for v in robot._numeric()(xs, us, ps)] == [float(v) for v in ref(xs, us, ps)]
    X, U = rng.normal(0, 4, (2, 50)), rng.normal(0, 10, (1, 50))
    for a, b in zip(robot._numeric()(tuple(X), tuple(U), robot._param_tuple),
                    ref(tuple(X), tuple(U), robot._param_tuple)):
        assert np.array_equal(a, b)
