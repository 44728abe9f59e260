"""The nilpotentization's problem and its exact endpoint equations: :class:`NilpotentProblem`,
:func:`equations` and their Jacobian, :func:`format_equations` (the text's style), and
:math:`u_1(\\varepsilon)`."""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
import sympy as sp
from numpy.polynomial import polynomial as P
from numpy.polynomial.polyutils import trimseq

from ....core.errors import InvalidInputError
from ..model import Acrobot


# ================================================================================ numerics
def _s(phi):
    """phi / sin(phi) and its first two derivatives, stable at 0."""
    phi = np.asarray(phi, dtype=float)
    small = np.abs(phi) < 1e-3
    ps = np.where(small, 1.0, phi)
    sn, cs = np.sin(ps), np.cos(ps)
    s0 = np.where(small, 1 + phi**2 / 6 + 7 * phi**4 / 360, ps / sn)
    s1 = np.where(small, phi / 3 + 7 * phi**3 / 90, (sn - ps * cs) / sn**2)
    s2 = np.where(small, 1 / 3 + 7 * phi**2 / 30,
                  (ps * sn**2 - 2 * sn * cs + 2 * ps * cs**2) / sn**3)
    return s0, s1, s2


def alpha_derivs(robot: Acrobot, phi):
    """:math:`\\alpha, \\alpha', \\alpha''` at ``phi`` (|phi| < pi)."""
    M1, A1 = robot.M1, robot.A1
    s0, s1, s2 = _s(phi)
    h = M1 + A1 * np.cos(phi)
    h1 = -A1 * np.sin(phi)
    h2 = -A1 * np.cos(phi)
    n = (M1 + A1) ** 2
    return (s0 * h * h / n, (s1 * h * h + 2 * s0 * h * h1) / n,
            (s2 * h * h + 4 * s1 * h * h1 + 2 * s0 * (h1 * h1 + h * h2)) / n)


@dataclasses.dataclass(frozen=True)
class NilpotentProblem:
    """Steer the acrobot from ``P`` to ``Q``, each ``(phi, t, theta)``, with ``|phi| < pi``."""

    robot: Acrobot
    P: tuple
    Q: tuple
    degree: int = 3

    def __post_init__(self):
        for name in ("P", "Q"):
            v = tuple(float(a) for a in getattr(self, name))
            if len(v) != 3 or not all(math.isfinite(a) for a in v):
                raise InvalidInputError(name, f"must be three finite numbers (phi, t, theta), got {getattr(self, name)!r}",
                                        "give for example [0.785, 0, 0]")
            if not abs(v[0]) < math.pi:
                raise InvalidInputError(f"{name}.phi", f"must satisfy |phi| < pi (the chart of the transformation), "
                                        f"got {v[0]}", "choose a joint angle strictly between -pi and pi")
            object.__setattr__(self, name, v)
        if not self.Q[1] > self.P[1]:
            raise InvalidInputError("Q.t", f"must be later than P.t ({self.P[1]}), got {self.Q[1]}",
                                    "time moves forward: give Q.t > P.t")
        if isinstance(self.degree, bool) or not isinstance(self.degree, int) or not 1 <= self.degree <= 12:
            raise InvalidInputError("degree", f"must be a whole number from 1 to 12, got {self.degree!r}",
                                    "give for example 3 (the text's cubic inputs)")
        if self.robot.P0 == 0:
            raise InvalidInputError("robot.P0", "is 0: the system is holonomic and not nilpotentizable this way",
                                    "give a nonzero angular momentum")

    # The acrobot is autonomous: the clock is started at P (t - t_P), which keeps the feedback's
    # t alpha'/alpha v2 term small; results are shifted back by t_P.
    @property
    def x2P(self) -> float:
        return 0.0

    # x2Q and rhs_theta are constants of the problem, asked for at every evaluation of the endpoint
    # equations (thousands per solve): computed once (functools.cached_property stores them in the
    # instance's __dict__, which a frozen dataclass allows; equality and hashing see the fields only)
    @functools.cached_property
    def x2Q(self) -> float:
        return (self.Q[1] - self.P[1]) / float(alpha_derivs(self.robot, self.Q[0])[0])

    @property
    def kappa(self) -> float:
        r = self.robot
        return r.P0 * r.A1 / (r.M1 + r.A1) ** 2

    def a_fn(self, phi):
        return alpha_derivs(self.robot, phi)[0] * self.robot.P0 / self.robot.h(phi)

    def rhs_theta(self) -> float:
        """The right-hand side of the third endpoint equation (module docstring)."""
        return self._rhs_theta

    @functools.cached_property
    def _rhs_theta(self) -> float:
        r = self
        phP, phQ = self.P[0], self.Q[0]
        h1 = self.x2Q - self.x2P
        C = lambda p: float(self.a_fn(p)) - self.kappa * p * p / 2  # noqa: E731
        return (self.Q[2] - self.P[2] - float(r.a_fn(phP)) * h1 + float(self.robot.F(phQ) - self.robot.F(phP))
                - (self.x2P + h1) * (C(phQ) - C(phP)))


def _split(m, d):
    m = np.asarray(m, dtype=float)
    return m[: d + 1], m[d + 1:]


def _int(c):
    """:math:`\\int_0^\\varepsilon` of the polynomial ``c`` (ascending), the numbers of
    ``numpy.polynomial.polynomial.polyint`` (``c[j] / (j + 1)`` after a zero) without its argument
    handling, which cost more than the arithmetic at these sizes (the endpoint equations are
    evaluated thousands of times a solve)."""
    c = trimseq(c)
    out = np.zeros(c.size + 1)
    out[1:] = c / np.arange(1, c.size + 1)
    return out


def _mul(a, b):
    """The product of two polynomials, as ``polymul``: its arguments trimmed of trailing zeros as it
    trims them, so that ``np.convolve`` sums the terms in numpy's order, bit for bit."""
    return trimseq(np.convolve(trimseq(a), trimseq(b)))


def _at1(c) -> float:
    """The polynomial ``c`` at 1 by Horner's rule from the top, as ``polyval(1.0, c)`` sums it."""
    v = 0.0 + c[-1]
    for a in c[-2::-1]:
        v = a + v
    return float(v)


def _integrals(m, d):
    v1, v2 = _split(m, d)
    V1, V2 = _int(v1), _int(v2)
    I = _at1(_int(_mul(V2, v1)))
    J = _at1(_int(_mul(_mul(V2, V2), v1)))
    return v1, v2, V1, V2, I, J


def equations(prob: NilpotentProblem, m) -> np.ndarray:
    """Residuals of the three endpoint equations at coefficients ``m`` (v1 then v2, ascending)."""
    d = prob.degree
    v1, v2, V1, V2, I, J = _integrals(m, d)
    return np.array([_at1(V1) - (prob.x2Q - prob.x2P), _at1(V2) - (prob.Q[0] - prob.P[0]),
                     prob.kappa * (prob.P[0] * I + J / 2) - prob.rhs_theta()])


def iterated_integrals(degree: int):
    """The iterated integrals of the endpoint equations as exact sympy polynomials.

    Returns ``(m1, m2, h1, h2, I, J)``: the coefficient symbols of :math:`v_1, v_2` and
    :math:`h_1 = V_1(1)`, :math:`h_2 = V_2(1)`, :math:`I = \\int_0^1 V_2 v_1`,
    :math:`J = \\int_0^1 V_2^2 v_1`, all with rational coefficients.
    """
    e = sp.Symbol("epsilon")
    m1 = [sp.Symbol(f"m1{i}") for i in range(degree + 1)]
    m2 = [sp.Symbol(f"m2{i}") for i in range(degree + 1)]
    v1 = sum(m1[i] * e**i for i in range(degree + 1))
    v2 = sum(m2[i] * e**i for i in range(degree + 1))
    V1 = sp.integrate(v1, (e, 0, e))
    V2 = sp.integrate(v2, (e, 0, e))
    I = sp.expand(sp.integrate(sp.expand(V2 * v1), (e, 0, 1)))
    J = sp.expand(sp.integrate(sp.expand(V2**2 * v1), (e, 0, 1)))
    return m1, m2, sp.expand(V1.subs(e, 1)), sp.expand(V2.subs(e, 1)), I, J


def endpoint_equations(prob: NilpotentProblem) -> list[sp.Eq]:
    """The three endpoint equations as sympy equations in the coefficients ``m10.., m20..``."""
    m1, m2, h1, h2, I, J = iterated_integrals(prob.degree)
    k = sp.Float(prob.kappa, 17)
    return [sp.Eq(h1, sp.Float(prob.x2Q - prob.x2P, 17)), sp.Eq(h2, sp.Float(prob.Q[0] - prob.P[0], 17)),
            sp.Eq(sp.expand(k * (sp.Float(prob.P[0], 17) * I + J / 2)), sp.Float(prob.rhs_theta(), 17))]


def format_equations(prob: NilpotentProblem) -> str:
    """The endpoint equations and the inequality, printed in the text's style."""
    m1, m2, h1, h2, I, J = iterated_integrals(prob.degree)
    st = lambda e: sp.sstr(e, order="grlex").replace("**", "^")  # noqa: E731
    r = prob.robot
    lines = [
        f"# endpoint equations: P = (phi, t, theta) = {tuple(round(v, 12) for v in prob.P)}, "
        f"Q = {tuple(round(v, 12) for v in prob.Q)}",
        f"# v1 = sum m1i eps^i, v2 = sum m2i eps^i, degree {prob.degree}; kappa = P0*A1/(M1+A1)^2 = {prob.kappa:.17g}",
        f"{st(h1)} - {prob.x2Q - prob.x2P:.17g} = 0",
        f"{st(h2)} - ({prob.Q[0] - prob.P[0]:.17g}) = 0",
        f"I = {st(I)}",
        f"J = {st(J)}",
        f"{prob.kappa:.17g}*({prob.P[0]:.17g}*I + J/2) - ({prob.rhs_theta():.17g}) = 0",
        "# and for all eps in [0, 1]:",
        f"#   u1(eps) = alpha(phi) v1 + x2 alpha'(phi) v2 > 0,  phi = {prob.P[0]:.17g} + int v2,  "
        f"x2 = {prob.x2P:.17g} + int v1,",
        f"#   alpha(phi) = phi/sin(phi) * ({r.M1:.17g} + ({r.A1:.17g})*cos(phi))^2 / {(r.M1 + r.A1) ** 2:.17g},"
        "  |phi| < pi",
    ]
    return "\n".join(lines)


def u1_values(prob: NilpotentProblem, m, eps):
    """:math:`u_1(\\varepsilon) = \\alpha(x_1) v_1 + x_2 \\alpha'(x_1) v_2` and the joint angle."""
    v1, v2 = _split(m, prob.degree)
    x1 = prob.P[0] + P.polyval(eps, P.polyint(v2))
    x2 = prob.x2P + P.polyval(eps, P.polyint(v1))
    a0, a1, _ = alpha_derivs(prob.robot, x1)
    return a0 * P.polyval(eps, v1) + x2 * a1 * P.polyval(eps, v2), x1


def _u1_jac(prob, m, eps):
    d = prob.degree
    v1, v2 = _split(m, d)
    x1 = prob.P[0] + P.polyval(eps, P.polyint(v2))
    x2 = prob.x2P + P.polyval(eps, P.polyint(v1))
    a0, a1, a2 = alpha_derivs(prob.robot, x1)
    pv1, pv2 = P.polyval(eps, v1), P.polyval(eps, v2)
    E = np.vander(eps, d + 1, increasing=True)
    Ei = np.vander(eps, d + 2, increasing=True)[:, 1:] / np.arange(1, d + 2)
    j1 = a0[:, None] * E + (Ei * (a1 * pv2)[:, None])
    j2 = Ei * (a1 * pv1 + x2 * a2 * pv2)[:, None] + E * (x2 * a1)[:, None]
    return np.hstack([j1, j2])


def _phi_jac(prob, m, eps):
    """Jacobian of the joint angle :math:`\\varphi(\\varepsilon) = \\varphi_P + \\int_0^\\varepsilon v_2` in the
    coefficients (v1 then v2): zero in v1, :math:`\\varepsilon^{i+1}/(i+1)` in v2; shape (eps.size, 2 (d + 1))."""
    d = prob.degree
    Ei = np.vander(eps, d + 2, increasing=True)[:, 1:] / np.arange(1, d + 2)
    return np.hstack([np.zeros_like(Ei), Ei])


@functools.lru_cache(maxsize=16)
def _tensors(d: int):
    i = np.arange(d + 1)
    C = 1.0 / ((i[:, None] + 1) * (i[:, None] + i[None, :] + 2))  # I = m2 C m1
    D = 1.0 / ((i[:, None, None] + 1) * (i[None, :, None] + 1) * (i[:, None, None] + i[None, :, None]
                                                                   + i[None, None, :] + 3))  # J = D[i,k,j] m2i m2k m1j
    return C, D


def _eq_jac(prob, m):
    """Exact Jacobian of :func:`equations` (the iterated integrals are bilinear and trilinear)."""
    d = prob.degree
    m1, m2 = _split(m, d)
    C, D = _tensors(d)
    w = 1.0 / np.arange(1, d + 2)
    z = np.zeros(d + 1)
    dI1, dI2 = C.T @ m2, C @ m1
    dJ1 = np.einsum("ikj,i,k->j", D, m2, m2)
    dJ2 = 2 * np.einsum("ikj,k,j->i", D, m2, m1)
    k, p = prob.kappa, prob.P[0]
    return np.array([np.concatenate([w, z]), np.concatenate([z, w]),
                     k * np.concatenate([p * dI1 + dJ1 / 2, p * dI2 + dJ2 / 2])])
