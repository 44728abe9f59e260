"""Chapter 3, eq. (4)-(12): the endpoint map and its derivative."""

import numpy as np
import pytest
from numpy.polynomial import Polynomial
from scipy.integrate import quad

from acroplan.core import backend as _integrate
from acroplan.core.basis import Legendre, Monomial
from acroplan.core.verify import simulate_segment

X0 = np.array([0.4, -2.6])
T = 1.7
C = np.array([[0.8, -1.1, 0.7, 0.3, -0.2, 0.1]])


@pytest.fixture(params=["legendre", "monomial"])
def basis(request):
    return {"legendre": Legendre, "monomial": Monomial}[request.param](6)


def test_endpoint_matches_scipy_dop853(pike_robot, basis):
    y, _ = _integrate.endpoint(pike_robot, basis, X0, T, C)
    sol = simulate_segment(pike_robot, X0, 0.0, T, basis.to_power(C, T), rtol=1e-12, atol=1e-12)
    assert np.max(np.abs(y - sol.y[:, -1])) < 1e-10


def test_phi_endpoint_is_the_integral_of_u(pike_robot, basis):
    y, _ = _integrate.endpoint(pike_robot, basis, X0, T, C)
    p = Polynomial(basis.to_power(C, T)[0]).integ()
    assert y[1] == pytest.approx(X0[1] + p(T), abs=1e-13)


def test_jacobian_matches_central_differences(pike_robot, basis):
    _, J = _integrate.endpoint(pike_robot, basis, X0, T, C)
    fd = np.empty_like(J)
    for i in range(C.size):
        h = 1e-5 * max(1.0, abs(C.flat[i]))
        e = np.zeros(C.size)
        e[i] = h
        yp, _ = _integrate.endpoint(pike_robot, basis, X0, T, C.ravel() + e)
        ym, _ = _integrate.endpoint(pike_robot, basis, X0, T, C.ravel() - e)
        fd[:, i] = (yp - ym) / (2 * h)
    assert np.allclose(J, fd, rtol=1e-6, atol=1e-8 * np.max(np.abs(J)))


def closed_form_jacobian(robot, basis, x0, T, c, *, drift_sign=+1.0, g_sign=-1.0):
    """Text eq. (11)-(12): columns are D Phi applied to zeta_i(t) = b_i(t/T).

    The corrected signs are drift_sign = +1 (erratum 2: +P0 A1 sin(phi)/h^2) and g_sign = -1
    (erratum 1: g1 = -k/h). The text's printed signs are drift_sign = -1 and g_sign = +1.
    """
    M1, A1, M2, A2, P0 = robot.params
    u0 = Polynomial(basis.to_power(c, T)[0])
    phi = u0.integ() + x0[1]
    cols = []
    for i in range(basis.n):
        e = np.zeros(basis.n)
        e[i] = 1.0
        zeta = Polynomial(basis.to_power(e, T))
        Z = zeta.integ()

        def integrand(t):
            p = phi(t)
            h = M1 + A1 * np.cos(p)
            a = (drift_sign * P0 * A1 * np.sin(p) + (A2 * M1 - A1 * M2) * np.sin(p) * u0(t)) / h**2
            return a * Z(t) + g_sign * (M2 + A2 * np.cos(p)) / h * zeta(t)

        y1 = quad(integrand, 0.0, T, epsabs=1e-14, epsrel=1e-13, limit=200)[0]
        cols.append([y1, Z(T)])
    return np.array(cols).T


def test_jacobian_matches_closed_form_eq11_12_with_errata_corrected(pike_robot, basis):
    _, J = _integrate.endpoint(pike_robot, basis, X0, T, C)
    A = closed_form_jacobian(pike_robot, basis, X0, T, C)
    assert np.allclose(J, A, rtol=1e-9, atol=1e-11)


@pytest.mark.parametrize("signs", [dict(drift_sign=-1.0), dict(g_sign=+1.0)],
                         ids=["eq9-printed-sign", "eq5-printed-sign"])
def test_printed_signs_give_a_wrong_jacobian(pike_robot, signs):
    """Errata 1 and 2 pinned: the printed signs disagree with finite differences."""
    basis = Legendre(6)
    _, J = _integrate.endpoint(pike_robot, basis, X0, T, C)
    wrong = closed_form_jacobian(pike_robot, basis, X0, T, C, **signs)
    assert np.max(np.abs(wrong[0] - J[0])) > 1e-2 * np.max(np.abs(J[0]))


def test_zero_input_from_straight_body_is_singular(pike_robot):
    """NOTES.md: u = 0 started at phi = -pi keeps sin(phi) = 0, and D Phi loses rank."""
    _, J = _integrate.endpoint(pike_robot, Legendre(6), [0.0, -np.pi], 2.0, np.zeros((1, 6)))
    s = np.linalg.svd(J, compute_uv=False)
    assert s[-1] < 1e-12 * s[0]


def test_basis_power_conversion_is_exact():
    rng = np.random.default_rng(0)
    for cls in (Legendre, Monomial):
        b = cls(7)
        c = rng.normal(size=7)
        t = np.linspace(0, 2.5, 11)
        direct = b.matrix(t / 2.5) @ c
        power = Polynomial(b.to_power(c, 2.5))(t)
        assert np.allclose(direct, power, rtol=1e-12, atol=1e-12)
        # derivative rows: d/ds of the series
        ds = b.matrix(t / 2.5, 1) @ c
        assert np.allclose(ds, Polynomial(b.to_power_s(c)).deriv()(t / 2.5), rtol=1e-12, atol=1e-12)
    # Legendre really is P_i(2s - 1)
    s = np.linspace(0, 1, 5)
    assert np.allclose(Legendre(4).matrix(s), np.polynomial.legendre.legvander(2 * s - 1, 3), atol=1e-14)
