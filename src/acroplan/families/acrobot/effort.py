"""Effort of a planned motion of the free-flying two-link body: the joint torque, its power and work.

The planner works in kinematics (the input is the joint rate :math:`u = \\dot\\varphi`); the joint
torque :math:`\\tau` that produces a planned motion follows from the Lagrangian of the two links.

Derivation (:func:`torque_expression`, in sympy)
------------------------------------------------
No external force acts, so the centre of mass moves uniformly and, in its frame, the kinetic
energy of the two links (torso: mass :math:`M`, inertia :math:`J`, centre of mass at
:math:`L e(\\theta+\\varphi)` from the joint; leg: :math:`m, j`, at :math:`l e(\\theta)`;
:math:`e(\\alpha) = (\\cos\\alpha, \\sin\\alpha)`, :math:`\\mu = mM/(m+M)`) is

.. math::  T = \\tfrac12 \\mu\\,\\big|\\tfrac{d}{dt}(L e(\\theta+\\varphi) - l e(\\theta))\\big|^2
           + \\tfrac12 J(\\dot\\theta+\\dot\\varphi)^2 + \\tfrac12 j\\dot\\theta^2
           = \\tfrac12 h(\\varphi)\\dot\\theta^2 + k(\\varphi)\\dot\\theta\\dot\\varphi
           + \\tfrac12 M_2\\dot\\varphi^2 ,

with :math:`h = M_1 + A_1\\cos\\varphi`, :math:`k = M_2 + A_2\\cos\\varphi` (text eq. 2). The
angle :math:`\\theta` is cyclic: its momentum :math:`P_0 = \\partial T/\\partial\\dot\\theta =
h\\dot\\theta + k\\dot\\varphi` is conserved. Routh's procedure eliminates :math:`\\dot\\theta`:

.. math::  R(\\varphi, \\dot\\varphi) = T - P_0\\dot\\theta\\big|_{\\dot\\theta = (P_0 - k\\dot\\varphi)/h}
           = \\tfrac12 a(\\varphi)\\dot\\varphi^2 + P_0\\frac{k}{h}\\dot\\varphi - \\frac{P_0^2}{2h},
           \\qquad a = M_2 - \\frac{k^2}{h} > 0 ,

and the joint's equation :math:`\\frac{d}{dt}\\partial_{\\dot\\varphi}R - \\partial_\\varphi R = \\tau`
(the gyroscopic terms :math:`\\pm P_0 (k/h)'\\dot\\varphi` cancel) gives, exactly,

.. math::  \\tau = a(\\varphi)\\,\\ddot\\varphi + b(\\varphi)\\,\\dot\\varphi^2 + c(\\varphi)\\,P_0^2,
           \\qquad b = \\tfrac12 a'(\\varphi) = -\\frac{k k'}{h} + \\frac{k^2 h'}{2h^2},
           \\qquad c = -\\frac{h'}{2h^2} = \\frac{A_1\\sin\\varphi}{2h^2},

with :math:`h' = -A_1\\sin\\varphi`, :math:`k' = -A_2\\sin\\varphi`. :math:`\\tau` is the torque
the joint's motor applies to the torso (the leg receives :math:`-\\tau`), positive in the sense of
increasing :math:`\\varphi`; the mechanical power is :math:`\\tau\\dot\\varphi`, and it changes the
kinetic energy :math:`E = P_0^2/(2h) + a\\dot\\varphi^2/2` (:func:`kinetic_energy`):
:math:`\\dot E = \\tau\\dot\\varphi`. ``tests/test_effort.py`` checks the derivation against the
Euler-Lagrange equations of the full free body (centre of mass and :math:`\\theta` free), and a
forward simulation of those equations driven by these torques alone against planned motions.

This module also gives the acrobot's torque model, :class:`AcrobotTorque` (:math:`\\tau` and its
exact Jacobian in the input coefficients), registered on import
(:func:`~acroplan.core.system.register_torque_model`) as what :meth:`Acrobot.torque_model
<acroplan.families.acrobot.model.Acrobot.torque_model>` returns for a physical robot: through it
every plan of such a robot gives its torques, power and effort
(:meth:`~acroplan.core.result.PlanResult.torques`, :meth:`~acroplan.core.result.PlanResult.effort`;
:func:`torques` and :func:`effort_summary` here are the joint ``"phi"`` of those), and
``objective="torque"`` and ``tau_max`` of :func:`acroplan.plan` work. For the optimal strategies of
:mod:`acroplan.core.optimal` it registers the acrobot's starts, :func:`optimal_starts` (two
feasible joint motions from the flat output, one bulging each way).

Units: the lumped coefficients are those of the physical body (kg m^2 with SI inputs), so the
torque is in N m; a lumped-only :class:`~.model.Acrobot` (no ``physical``) is refused, since its
coefficients may be any common multiple of the body's (the state equation fixes only their ratios).
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from ...core.basis import basis_tables
from ...core.conditions import hermite_inverse
from ...core.errors import InvalidInputError
from ...core.optimal import register_starts
from ...core.result import JointEffort
from ...core.system import register_torque_model, sp
from .model import Acrobot

__all__ = ["TorqueDerivation", "torque_expression", "torque_coefficients", "joint_torque", "kinetic_energy",
           "torques", "effort_summary", "EffortSummary", "AcrobotTorque", "torque_optimal", "optimal_starts"]


# ------------------------------------------------------------------------------------ derivation
@dataclasses.dataclass(frozen=True)
class TorqueDerivation:
    """The symbolic derivation of the joint torque (:func:`torque_expression`).

    Attributes
    ----------
    tau : sympy.Expr
        :math:`\\tau` in ``phi``, ``u`` (:math:`\\dot\\varphi`), ``du`` (:math:`\\ddot\\varphi`),
        ``P0`` and the physical parameters ``M, m, J, j, L, l``.
    a, b, c : sympy.Expr
        :math:`\\tau = a\\,du + b\\,u^2 + c\\,P_0^2`, in ``phi`` and the lumped ``M1, A1, M2, A2``.
    kinetic : sympy.Expr
        The kinetic energy about the centre of mass in ``theta_dot``, ``u`` and ``phi``
        (physical parameters).
    momentum : sympy.Expr
        :math:`\\partial T/\\partial\\dot\\theta` (physical parameters).
    routhian : sympy.Expr
        :math:`R(\\varphi, \\dot\\varphi)` (physical parameters).
    lumped : dict of str to sympy.Expr
        ``M1, A1, M2, A2`` in the physical parameters.
    symbols : dict of str to sympy.Symbol
        Every symbol by name: ``phi, u, du, theta_dot, P0, M, m, J, j, L, l, M1, A1, M2, A2``.
    """

    tau: sp.Expr
    a: sp.Expr
    b: sp.Expr
    c: sp.Expr
    kinetic: sp.Expr
    momentum: sp.Expr
    routhian: sp.Expr
    lumped: dict
    symbols: dict


@functools.cache
def torque_expression() -> TorqueDerivation:
    """Derive the joint torque of the free-flying two-link body with sympy (module docstring).

    The kinetic energy of the two links about the centre of mass is built from their positions;
    :math:`\\theta` is cyclic and :math:`\\dot\\theta` is eliminated by the conserved momentum
    :math:`P_0` (Routh); the joint's Euler-Lagrange equation of the Routhian is the torque.

    Returns
    -------
    TorqueDerivation
        Cached: the derivation runs once per process (a few seconds).
    """
    t = sp.Symbol("t", real=True)
    M, m, J, j, L, l = sp.symbols("M m J j L l", positive=True)
    P0 = sp.Symbol("P0", real=True)
    phi, u, du, theta_dot = sp.symbols("phi u du theta_dot", real=True)
    th, ph = sp.Function("theta", real=True)(t), sp.Function("phi", real=True)(t)

    def e(angle):
        return sp.Matrix([sp.cos(angle), sp.sin(angle)])

    # positions of the two centres of mass relative to the system's centre of mass
    d = L * e(th + ph) - l * e(th)  # torso's centre of mass relative to the leg's
    torso = m / (M + m) * d
    leg = -M / (M + m) * d
    kin = (M * torso.diff(t).dot(torso.diff(t)) + m * leg.diff(t).dot(leg.diff(t))
           + J * (th.diff(t) + ph.diff(t)) ** 2 + j * th.diff(t) ** 2) / 2
    rates = {th.diff(t): theta_dot, ph.diff(t): u}
    kin = sp.factor_terms(sp.trigsimp(sp.expand(kin.subs(rates).subs(ph, phi))))
    momentum = sp.factor_terms(sp.diff(kin, theta_dot))
    # Routh: eliminate theta_dot by the conserved momentum P0 = dT/d(theta_dot) (linear in theta_dot)
    theta_dot_of = sp.solve(sp.Eq(momentum, P0), theta_dot)[0]
    routh = sp.cancel(sp.together((kin - P0 * theta_dot).subs(theta_dot, theta_dot_of)))
    # the joint's Euler-Lagrange equation: tau = d/dt dR/du - dR/dphi along phi(t)
    R_t = routh.subs({u: ph.diff(t), phi: ph})
    tau_t = sp.diff(sp.diff(R_t, ph.diff(t)), t) - sp.diff(R_t, ph)
    tau = sp.together(tau_t.subs({ph.diff(t, 2): du}).subs({ph.diff(t): u}).subs({ph: phi}))
    # the lumped form
    mu = M * m / (M + m)
    lumped = {"M1": j + J + mu * (L**2 + l**2), "A1": -2 * mu * L * l, "M2": J + mu * L**2, "A2": -mu * L * l}
    M1, A1, M2, A2 = sp.symbols("M1 A1 M2 A2", real=True)
    h = M1 + A1 * sp.cos(phi)
    k = M2 + A2 * sp.cos(phi)
    a = M2 - k**2 / h
    b = sp.diff(a, phi) / 2
    c = -sp.diff(h, phi) / (2 * h**2)
    symbols = dict(phi=phi, u=u, du=du, theta_dot=theta_dot, P0=P0, M=M, m=m, J=J, j=j, L=L, l=l, M1=M1, A1=A1,
                   M2=M2, A2=A2)
    return TorqueDerivation(tau=tau, a=a, b=b, c=c, kinetic=kin, momentum=momentum, routhian=routh, lumped=lumped,
                            symbols=symbols)


# ------------------------------------------------------------------------------------ numerics
def _require_physical(robot) -> Acrobot:
    if not isinstance(robot, Acrobot):
        raise InvalidInputError("robot", f"must be an acroplan.Acrobot, got {type(robot).__name__}",
                                "build one with acroplan.Acrobot.from_physical(...)")
    if robot.physical is None:
        raise InvalidInputError("robot.physical", "is missing: a lumped-only Acrobot has no torque (its M1, A1, M2, "
                                "A2, P0 fix the motion only up to a common factor, the torque's scale)",
                                "build the robot with Acrobot.from_physical(torso_mass=..., leg_mass=..., ...)")
    return robot


def torque_coefficients(robot: Acrobot, phi, derivatives: bool = False):
    """:math:`a, b, c` of :math:`\\tau = a\\ddot\\varphi + b\\dot\\varphi^2 + cP_0^2` at ``phi``.

    Parameters
    ----------
    robot : Acrobot
        Its lumped coefficients are used (no check of ``physical`` here).
    phi : array_like, shape (N,)
    derivatives : bool
        Also return :math:`a', b', c'` (for Jacobians).

    Returns
    -------
    tuple of numpy.ndarray, each shape (N,)
        ``(a, b, c)``, or ``(a, b, c, a', b', c')``.
    """
    phi = np.asarray(phi, dtype=float)
    M1, A1, M2, A2 = robot.M1, robot.A1, robot.M2, robot.A2
    cs, sn = np.cos(phi), np.sin(phi)
    h, k = M1 + A1 * cs, M2 + A2 * cs
    hp, kp = -A1 * sn, -A2 * sn  # h', k'
    a = M2 - k * k / h
    b = -k * kp / h + 0.5 * k * k * hp / (h * h)
    c = -0.5 * hp / (h * h)
    if not derivatives:
        return a, b, c
    hpp, kpp = -A1 * cs, -A2 * cs
    # a' = 2 b; b' = a''/2 with a'' = -2(k'^2 + k k'')/h + 4 k k' h'/h^2 + k^2 h''/h^2 - 2 k^2 h'^2/h^3
    app = -2.0 * (kp * kp + k * kpp) / h + 4.0 * k * kp * hp / h**2 + k * k * hpp / h**2 - 2.0 * k * k * hp * hp / h**3
    cp = -0.5 * hpp / (h * h) + hp * hp / h**3
    return a, b, c, 2.0 * b, 0.5 * app, cp


def joint_torque(robot: Acrobot, phi, u, du):
    """The joint torque :math:`\\tau = a(\\varphi)\\dot u + b(\\varphi)u^2 + c(\\varphi)P_0^2`.

    Parameters
    ----------
    robot : Acrobot
        Built from the physical body (:meth:`Acrobot.from_physical`); a lumped-only robot raises.
    phi, u, du : array_like, broadcastable
        Joint angle :math:`\\varphi`, rate :math:`u = \\dot\\varphi` and acceleration
        :math:`\\dot u = \\ddot\\varphi`.

    Returns
    -------
    numpy.ndarray
        :math:`\\tau` (N m with SI parameters), the broadcast shape.

    Raises
    ------
    InvalidInputError
        ``robot.physical`` is missing.
    """
    robot = _require_physical(robot)
    a, b, c = torque_coefficients(robot, phi)
    u = np.asarray(u, dtype=float)
    return a * np.asarray(du, dtype=float) + b * u * u + c * robot.P0**2


def kinetic_energy(robot: Acrobot, phi, u):
    """Kinetic energy about the centre of mass, :math:`E = P_0^2/(2h(\\varphi)) + a(\\varphi)u^2/2`
    (:math:`\\dot E = \\tau u`).

    Parameters
    ----------
    robot : Acrobot
        From the physical body.
    phi, u : array_like, broadcastable

    Returns
    -------
    numpy.ndarray
    """
    robot = _require_physical(robot)
    a, _, _ = torque_coefficients(robot, phi)
    u = np.asarray(u, dtype=float)
    return 0.5 * robot.P0**2 / robot.h(phi) + 0.5 * a * u * u


def _check_result(result):
    if not result.segments:
        raise InvalidInputError("result", "has no planned segments", "plan a motion first")
    return _require_physical(result.system)


def torques(result, t):
    """Joint torque and mechanical power of a planned acrobot motion at times ``t``: the joint
    ``"phi"`` of :meth:`PlanResult.torques <acroplan.core.result.PlanResult.torques>` (which
    evaluates :class:`AcrobotTorque` on each segment: :math:`\\varphi` the integral of the
    segment's input, exact in its basis, :math:`u` the input and :math:`\\dot u` its derivative
    in the basis). At a time shared by two segments the earlier segment's values are used
    (:math:`\\dot u`, hence :math:`\\tau`, may jump there under ``conditions="free"``).

    Parameters
    ----------
    result : PlanResult
        A plan of an :class:`Acrobot` built from the physical body.
    t : float or array_like, shape (N,)
        Times within the planned span.

    Returns
    -------
    tau, power : numpy.ndarray, shape (N,) (floats for a scalar ``t``)
        :math:`\\tau(t)` and :math:`\\tau(t)\\,u(t)`.

    Raises
    ------
    InvalidInputError
        ``robot.physical`` is missing (a lumped-only robot), or a time is outside the plan.
    """
    _check_result(result)
    scalar = np.ndim(t) == 0
    tau, power = result.torques(t)
    return (float(tau[0, 0]), float(power[0, 0])) if scalar else (tau[:, 0], power[:, 0])


#: The effort of the acrobot's joint: :class:`acroplan.core.result.JointEffort` (``joint`` is
#: ``"phi"``, ``input`` is ``"u"``).
EffortSummary = JointEffort


def effort_summary(result) -> JointEffort:
    """Peak torque and power, positive and net work, :math:`\\int\\tau^2` and :math:`\\int u^2` of a
    planned acrobot motion: the joint ``"phi"`` of :meth:`PlanResult.effort
    <acroplan.core.result.PlanResult.effort>` (its rules: :data:`acroplan.core.result.EFFORT_RULE`).

    Parameters
    ----------
    result : PlanResult
        A plan of an :class:`Acrobot` built from the physical body.

    Returns
    -------
    JointEffort

    Raises
    ------
    InvalidInputError
        ``robot.physical`` is missing.
    """
    _check_result(result)
    return result.effort()["phi"]


# ------------------------------------------------------------------------------------ torque model
class AcrobotTorque:
    """The acrobot's torque model for :class:`acroplan.core.optimal.TorqueOptimal` (and for torque
    limits, ``tau_max``): :math:`\\tau(s)` at normalised times ``s`` and its exact Jacobian in the
    input coefficients.

    With :math:`\\varphi(s) = \\varphi_0 + T\\,I(s)^\\top c`, :math:`u = V(s)^\\top c` and
    :math:`\\dot u = V'(s)^\\top c/T` (:math:`V, V', I`: the basis, its derivative and integral),

    .. math::  \\frac{\\partial\\tau}{\\partial c} = (a'\\dot u + b'u^2 + c'P_0^2)\\,T I(s)
               + 2bu\\,V(s) + a\\,V'(s)/T .

    Call signature: ``model(system, basis, x0, T, c, s) -> (tau (1, K), jacobian (1, K, n))``.
    """

    joint_names = ("phi",)

    def unsupported(self, system) -> str | None:
        """Why the model cannot give the torques of ``system`` (``None`` when it can)."""
        if not isinstance(system, Acrobot):
            return f"AcrobotTorque models the acrobot, not {type(system).__name__}"
        if system.physical is None:
            return ("robot.physical is missing: a lumped-only Acrobot has no torque; build it with "
                    "Acrobot.from_physical(...)")
        return None

    def torques(self, system, basis, x0, T, c, s):
        """:math:`\\tau(s)` alone, shape (1, K) (no Jacobian: for results and sweeps)."""
        robot = _require_physical(system)
        s = np.ascontiguousarray(s, dtype=float)
        V, V1, I = basis_tables(basis, s)
        c = np.asarray(c, dtype=float).reshape(-1)
        return joint_torque(robot, float(x0[1]) + T * (I @ c), V @ c, (V1 @ c) / T)[None, :]

    def __call__(self, system, basis, x0, T, c, s):
        robot = _require_physical(system)
        s = np.ascontiguousarray(s, dtype=float)
        V, V1, I = basis_tables(basis, s)
        c = np.asarray(c, dtype=float).reshape(-1)
        phi = float(x0[1]) + T * (I @ c)
        u = V @ c
        du = (V1 @ c) / T
        a, b, cc, ap, bp, cp = torque_coefficients(robot, phi, derivatives=True)
        P2 = robot.P0**2
        tau = a * du + b * u * u + cc * P2
        jac = ((ap * du + bp * u * u + cp * P2) * T)[:, None] * I + (2.0 * b * u)[:, None] * V + (a / T)[:, None] * V1
        return tau[None, :], jac[None, :, :]

    def __repr__(self):
        return "AcrobotTorque()"


def torque_optimal(**kwargs):
    """:class:`acroplan.core.optimal.TorqueOptimal` with the acrobot's torque model
    (:class:`AcrobotTorque`); ``kwargs`` as for it (``sizes``, ``rtol``, ``starts``, ``tau_max``,
    ``kkt_tol``)."""
    from ...core.optimal import TorqueOptimal

    return TorqueOptimal(torque=AcrobotTorque(), **kwargs)


# ------------------------------------------------------------------------------------ optimal starts
_XS, _WS = np.polynomial.legendre.leggauss(64)
_XS, _WS = (_XS + 1.0) / 2.0, _WS / 2.0
_XC, _WC = np.polynomial.legendre.leggauss(24)
_XC, _WC = (_XC + 1.0) / 2.0, _WC / 2.0
#: largest joint excursion of the bump family scanned, in radians (40 amplitudes on each side)
BUMP_RANGE = 12.0
_AMPS = np.linspace(-1.0, 1.0, 81)


@functools.lru_cache(maxsize=64)
def _projector(basis):
    """Least-squares projection of values at the 64 Gauss nodes on ``basis`` (exact for
    polynomials of degree < basis.n), read-only, shape (basis.n, 64)."""
    P = np.linalg.pinv(basis.matrix(_XS))
    P.setflags(write=False)
    return P


def optimal_starts(interval, basis) -> list:
    """Starts for the optimal strategies: the flat output's bump family, on both sides.

    Joint motions :math:`\\varphi(s) = \\varphi_h(s) + a\\,s^{\\alpha}(1-s)^{\\beta}`, with
    :math:`\\varphi_h` the lowest-degree polynomial meeting the end values of :math:`\\varphi` and the
    interval's conditions on :math:`u, u'` (:func:`~acroplan.core.conditions.hermite_inverse`) and
    :math:`\\alpha, \\beta` one more than the conditions at each end, reach :math:`\\theta(T)` when
    :math:`T\\int_0^1 ds/h(\\varphi(s)) = I^*` (the flat output, :mod:`.flat`). That scalar equation
    in the amplitude :math:`a` usually has a root of each sign: the joint bulges towards either
    neighbouring extreme of :math:`1/h`, and the two lie in the two basins of the least-energy motion
    (measured on 800 random segments: the better optimum was always reached from one of them).
    Returned: the root nearest 0 of each sign (scanned on 81 amplitudes, excursions up to
    :data:`BUMP_RANGE` rad, by 24-node Gauss-Legendre; refined by four steps of regula falsi on the
    64-node rule), as coefficients of :math:`u = \\dot\\varphi` in ``basis`` (exact: :math:`u` is a
    polynomial of degree < ``basis.n``). Registered for :class:`~.model.Acrobot` with
    :func:`acroplan.core.optimal.register_starts`; about 0.1 ms, no ODE.

    Parameters
    ----------
    interval : Interval
    basis : InputBasis

    Returns
    -------
    list of (str, numpy.ndarray of shape (1, basis.n))
        ``("bump-", c)`` and ``("bump+", c)`` (either may be missing); empty when :math:`P_0 = 0`
        or the family does not fit the basis.
    """
    robot = interval.system
    if not isinstance(robot, Acrobot) or robot.P0 == 0.0:
        return []
    x0, x1, T = interval.x0, interval.x1, float(interval.T)
    phi0, phiT = float(x0[1]), float(x1[1])
    ends = {k: float(np.ravel(v)[0]) for k, v in interval.ends.items()}
    keys = tuple(k for k in ("u0", "du0", "uT", "duT") if k in ends)
    left = sum(k in ends for k in ("u0", "du0"))
    deg, alpha, beta = 1 + len(keys), 1 + left, 1 + len(keys) - left
    n = basis.n
    if max(deg, alpha + beta) > n:
        return []
    scale = {"u0": T, "du0": T * T, "uT": T, "duT": T * T}
    ph = hermite_inverse(keys, deg) @ np.array([phi0, phiT] + [scale[k] * ends[k] for k in keys])
    polyval = np.polynomial.polynomial.polyval
    dph = ph[1:] * np.arange(1, ph.size)

    def bump(x):
        return x**alpha * (1.0 - x) ** beta

    smax = alpha / (alpha + beta)
    amps = _AMPS * (BUMP_RANGE / bump(smax))
    target = (float(x1[0]) - float(x0[0]) + float(robot.F(phiT)) - float(robot.F(phi0))) / robot.P0
    M1, A1 = robot.M1, robot.A1
    PH, W = polyval(_XS, ph), bump(_XS)

    vals = T * ((1.0 / (M1 + A1 * np.cos(polyval(_XC, ph)[None, :] + amps[:, None] * bump(_XC)[None, :]))) @ _WC) \
        - target
    cross = np.flatnonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)

    def J(a):  # the 64-node rule
        return T * float((1.0 / (M1 + A1 * np.cos(PH + a * W))) @ _WS) - target

    dW = alpha * _XS ** (alpha - 1) * (1.0 - _XS) ** beta - beta * _XS**alpha * (1.0 - _XS) ** (beta - 1)
    dPH = polyval(_XS, dph)
    P = _projector(basis)
    out = []
    for label, side in (("bump-", cross[amps[cross + 1] <= 0.0]), ("bump+", cross[amps[cross] >= 0.0])):
        if not side.size:
            continue
        k = side[np.argmin(np.minimum(np.abs(amps[side]), np.abs(amps[side + 1])))]
        # regula falsi (Illinois) on the 64-node rule from the coarse bracket: a start need not be
        # exact (the SQP restores the endpoint); four steps bring it within ~1e-5 of the target
        lo, hi = amps[k], amps[k + 1]
        flo, fhi = J(lo), J(hi)
        a = lo if abs(flo) < abs(fhi) else hi
        if flo * fhi < 0:
            for _ in range(4):
                a = hi - fhi * (hi - lo) / (fhi - flo)
                fa = J(a)
                if fa == 0.0:
                    break
                if fa * fhi < 0:
                    lo, flo = hi, fhi
                else:
                    flo *= 0.5
                hi, fhi = a, fa
        out.append((label, (P @ ((dPH + a * dW) / T))[None, :]))
    return out


register_starts(Acrobot, optimal_starts)


def _acrobot_torque(robot) -> AcrobotTorque:
    return AcrobotTorque()


register_torque_model(Acrobot, _acrobot_torque)  # Acrobot.torque_model(): this, for a physical robot
