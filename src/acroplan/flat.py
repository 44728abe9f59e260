"""The flat-output planner for one acrobot segment.

:math:`y = \\theta + F(\\varphi)` with :math:`F' = k/h` is a flat output: :math:`\\dot y = P_0/h(\\varphi)`.
Any joint motion :math:`\\varphi(t)` with the right ends therefore reaches

.. math::  \\theta(T) = \\theta(0) - [F(\\varphi_T) - F(\\varphi_0)] + P_0 \\int_0^T \\frac{dt}{h(\\varphi(t))},

and planning a segment is **one scalar equation** :math:`I[\\varphi] = I^* :=
(\\theta_T - \\theta_0 + F(\\varphi_T) - F(\\varphi_0))/P_0` for the joint motion, with no ODE to solve.

Two uses:

* :func:`flat_pieces` (``method="flat"``): the joint moves along a quintic to a dwell value
  :math:`p`, dwells, and moves along a quintic to :math:`\\varphi_T` (honouring the input conditions
  at the ends); :math:`p` solves the equation (Brent's method), for transition times from 30% of
  the segment down to 0.08% until one brackets the target. As the transitions shorten this
  approaches the bang-dwell-bang extremals of :mod:`acroplan.reach`, so every target strictly
  inside the exact interval is reached.
* :func:`initial_guess`: a one-parameter polynomial joint motion that fits the path-deformation
  basis, whose amplitude solves the same equation (safeguarded Newton): a start that usually
  already meets the target.

Where it does not apply: ``P0 = 0`` (holonomic, refused before planning), and, with a rate bound,
targets whose transitions would have to be faster than :math:`u_{max}` allows (it says so).
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.polynomial import Polynomial as _Poly
from scipy.optimize import brentq

from .reach import Limits
from .systems.acrobot import Acrobot

__all__ = ["flat_pieces", "initial_guess", "TRANSITIONS"]

_X, _W = np.polynomial.legendre.leggauss(256)
_S, _WS = (_X + 1) / 2, _W / 2


# ----------------------------------------------------------------------------------------- pieces
#: relative durations of the two transitions tried, gentlest first
TRANSITIONS = (0.3, 0.15, 0.07, 0.03, 0.012, 0.005, 0.002, 0.0008)


def _quintic(q0, v0, a0, q1, v1, a1, D):
    """The quintic on [0, D] (local time) with the given value, slope and curvature at both ends."""
    # q(t) = sum_k c_k t^k; solve the 6x6 Hermite system
    A = np.array([[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 2, 0, 0, 0],
                  [1, D, D**2, D**3, D**4, D**5], [0, 1, 2 * D, 3 * D**2, 4 * D**3, 5 * D**4],
                  [0, 0, 2, 6 * D, 12 * D**2, 20 * D**3]], dtype=float)
    return _Poly(np.linalg.solve(A, [q0, v0, a0, q1, v1, a1]))


def _gl_integral(robot, q: _Poly, D: float) -> float:
    return D * float(np.sum(_WS / robot.h(q(D * _S))))


def flat_pieces(robot: Acrobot, x0, x1, T: float, *, ends: dict | None = None, limits: Limits | None = None):
    """Plan one segment as three joint-motion pieces: move, dwell, move (module docstring, below).

    The joint leaves :math:`\\varphi_0` along a quintic (honouring ``u0``, ``du0``) and reaches the
    dwell value :math:`p` with zero rate and curvature in time :math:`\\delta T`, stays at
    :math:`p`, and reaches :math:`\\varphi_T` along a quintic (honouring ``uT``, ``duT``) in the
    last :math:`\\delta T`. For each :math:`\\delta` in :data:`TRANSITIONS` (gentlest first) the dwell
    value solving the flat-output equation is found by Brent's method; the first that brackets the
    target and keeps the limits is used. As :math:`\\delta \\to 0` this approaches the
    bang-dwell-bang extremal motions of :mod:`acroplan.reach`, so every target strictly inside the
    reachable interval is reached for a small enough :math:`\\delta`.

    Returns
    -------
    (pieces, message)
        ``pieces``: list of ``(duration, u_power_coefficients)`` with ``u`` in the power basis of
        the piece's local time (4 coefficients... up to degree 4), or ``None`` with the reason.
    """
    from .constrained import COMPLIANCE_TOL

    theta0, phi0 = float(x0[0]), float(x0[1])
    thetaT, phiT = float(x1[0]), float(x1[1])
    if robot.P0 == 0.0:
        return None, "P0 = 0: the flat output is constant (holonomic)"
    ends = dict(ends or {})
    u0, du0 = ends.get("u0", 0.0), ends.get("du0", 0.0)
    uT, duT = ends.get("uT", 0.0), ends.get("duT", 0.0)
    target = (thetaT - theta0 + float(robot.F(phiT)) - float(robot.F(phi0))) / robot.P0
    limits = limits or Limits()
    mid = 0.5 * (phi0 + phiT)
    lo = max(limits.lo, min(phi0, phiT) - math.pi)
    hi = min(limits.hi, max(phi0, phiT) + math.pi)
    grid = np.linspace(lo, hi, 97)
    last = "no transition duration worked"
    for rel in TRANSITIONS:
        D = rel * T

        def build(p):
            A = _quintic(phi0, u0, du0, p, 0.0, 0.0, D)
            C = _quintic(p, 0.0, 0.0, phiT, uT, duT, D)
            return A, C

        def f(p):
            A, C = build(p)
            return _gl_integral(robot, A, D) + (T - 2 * D) / robot.h(p) + _gl_integral(robot, C, D) - target

        # the quintics are affine in p: evaluate the whole grid at once
        A0, C0 = build(0.0)
        A1, C1 = build(1.0)
        tq = D * _S
        a0, a1 = A0(tq), A1(tq) - A0(tq)
        c0, c1 = C0(tq), C1(tq) - C0(tq)
        gA = 1.0 / robot.h(a0[None, :] + grid[:, None] * a1[None, :])
        gC = 1.0 / robot.h(c0[None, :] + grid[:, None] * c1[None, :])
        vals = D * (gA @ _WS + gC @ _WS) + (T - 2 * D) / robot.h(grid) - target
        idx = np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)[0]
        if idx.size == 0:
            last = (f"with transitions of {rel:g} T the dwell reaches int dt/h in [{vals.min() + target:.6g}, "
                    f"{vals.max() + target:.6g}], not {target:.6g}")
            continue
        for k in idx[np.argsort(np.abs(grid[idx] - mid))]:
            p = brentq(f, grid[k], grid[k + 1], xtol=1e-15, rtol=1e-15, maxiter=200)
            A, C = build(p)
            pieces = [(D, A.deriv().coef), (T - 2 * D, np.zeros(1)), (D, C.deriv().coef)]
            # limits, exactly: extremes of u at roots of u', of phi at roots of u
            bad = False
            for (dur, coef), q in zip((pieces[0], pieces[2]), (A, C)):
                u = _Poly(coef)
                pts = np.concatenate([[0.0, dur], [r.real for r in u.deriv().roots() if abs(r.imag) < 1e-12
                                                   and 0 <= r.real <= dur]])
                if limits.u_max is not None and np.max(np.abs(u(pts))) > limits.u_max - COMPLIANCE_TOL:
                    bad = True
                qp = np.concatenate([[0.0, dur], [r.real for r in u.roots() if abs(r.imag) < 1e-12
                                                  and 0 <= r.real <= dur]])
                if np.min(q(qp)) < limits.lo - COMPLIANCE_TOL or np.max(q(qp)) > limits.hi + COMPLIANCE_TOL:
                    bad = True
            if bad:
                last = f"with transitions of {rel:g} T the motion breaks the joint or rate limits"
                continue
            return [pc for pc in pieces if pc[0] > 0], f"flat output, three pieces: dwell p = {p:.6g}, " \
                                                       f"transitions of {rel:g} T"
    return None, f"the three-piece flat motion found no solution: {last}"


# ----------------------------------------------------------------------------------------- guesses
_XG, _WG = np.polynomial.legendre.leggauss(40)
_SG, _WSG = (_XG + 1) / 2, _WG / 2
_AMPS = np.linspace(-4 * np.pi, 4 * np.pi, 41)


@functools.lru_cache(maxsize=64)
def _hermite(keys: tuple, deg: int) -> np.ndarray:
    """Inverse of the Hermite conditions matrix: value at 0 and 1, then the keyed derivatives."""
    k = np.arange(deg + 1)
    rows = [(k == 0).astype(float), np.ones(deg + 1)]
    for key in keys:
        s0, order = {"u0": (0.0, 1), "du0": (0.0, 2), "uT": (1.0, 1), "duT": (1.0, 2)}[key]
        fall = np.array([math.perm(int(i), order) for i in k], dtype=float)
        rows.append(fall * np.where(k >= order, s0 ** np.maximum(k - order, 0), 0.0))
    return np.linalg.inv(np.array(rows))


@functools.lru_cache(maxsize=64)
def _bump(alpha: int, beta: int) -> np.ndarray:
    """Power coefficients of s^alpha (1 - s)^beta."""
    return np.polynomial.polynomial.polymul(np.eye(alpha + 1)[alpha],
                                            np.polynomial.polynomial.polypow([1.0, -1.0], beta))


def initial_guess(robot: Acrobot, basis, x0, x1, T: float, ends: dict | None = None):
    """A start for path deformation from the flat output, or ``None``.

    The joint motion :math:`\\varphi(s) = \\varphi_h(s) + a\\,w(s)`: :math:`\\varphi_h` is the
    lowest-degree polynomial meeting the end values of :math:`\\varphi` and the given end conditions
    on :math:`u, u'`, and :math:`w = s^{\\alpha}(1-s)^{\\beta}` vanishes with them. The amplitude
    :math:`a` solving the flat-output equation (or, failing a bracket, coming closest) is found on
    a grid and by Brent's method. The guess meets :math:`\\varphi(T)` and the input conditions
    exactly, and :math:`\\theta(T)` too when bracketed, so the continuation path is short or empty.

    Returns
    -------
    numpy.ndarray, shape (1, basis.n), or None when the family does not fit in the basis.
    """
    ends = ends or {}
    theta0, phi0 = float(x0[0]), float(x0[1])
    thetaT, phiT = float(x1[0]), float(x1[1])
    if robot.P0 == 0.0:
        return None
    keys = tuple(k for k in ("u0", "du0", "uT", "duT") if k in ends)
    left = sum(k in ends for k in ("u0", "du0"))
    right = len(keys) - left
    deg = 1 + len(keys)
    alpha, beta = 1 + left, 1 + right
    if max(deg, alpha + beta) > basis.n:
        return None
    scale = {"u0": T, "du0": T * T, "uT": T, "duT": T * T}
    rhs = np.array([phi0, phiT] + [scale[k] * float(ends[k]) for k in keys])
    ph = _hermite(keys, deg) @ rhs
    w = _bump(alpha, beta)
    PH = np.polynomial.polynomial.polyval(_SG, ph)
    W = np.polynomial.polynomial.polyval(_SG, w)
    target = (thetaT - theta0 + float(robot.F(phiT)) - float(robot.F(phi0))) / robot.P0
    amps = _AMPS / float(np.max(np.abs(W)))
    M1, A1 = robot.M1, robot.A1
    vals = T * (1.0 / (M1 + A1 * np.cos(PH[None, :] + amps[:, None] * W[None, :]))) @ _WSG - target
    idx = np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)[0]
    if idx.size:
        kk = idx[np.argmin(np.abs(amps[idx]))]
        lo, hi, flo = amps[kk], amps[kk + 1], vals[kk]
        # safeguarded Newton on I(a) = target: dI/da = T sum w A1 sin(phi) W / h^2
        a = lo - flo * (hi - lo) / (vals[kk + 1] - flo) if vals[kk + 1] != flo else 0.5 * (lo + hi)
        for _ in range(20):
            ph_ = PH + a * W
            h = M1 + A1 * np.cos(ph_)
            fa = T * float((1.0 / h) @ _WSG) - target
            if fa == 0.0:
                break
            if (fa < 0) == (flo < 0):
                lo, flo = a, fa
            else:
                hi = a
            d = T * float((A1 * np.sin(ph_) * W / (h * h)) @ _WSG)
            step = a - fa / d if d != 0.0 else 0.5 * (lo + hi)
            a_new = step if lo < step < hi else 0.5 * (lo + hi)
            if abs(a_new - a) <= 1e-12 * (1.0 + abs(a)):
                a = a_new
                break
            a = a_new
    else:
        a = amps[int(np.argmin(np.abs(vals)))]
    phi = np.zeros(max(ph.size, w.size))
    phi[: ph.size] += ph
    phi[: w.size] += a * w
    q = np.zeros(basis.n)
    du = phi[1:] * np.arange(1, phi.size) / T
    q[: du.size] = du
    return np.linalg.solve(basis.power_matrix(), q)[None, :]
