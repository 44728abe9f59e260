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
* :func:`flat_guess`: a polynomial joint motion that fits the path-deformation basis and solves
  the same equation (a one-parameter bump first; failing a bracket, a line towards a polynomial
  imitation of a dwell at an extreme of :math:`1/h`): a start that already meets the target, so
  that path deformation only polishes.

Where it does not apply: ``P0 = 0`` (holonomic, refused before planning), and, with a rate bound,
targets whose transitions would have to be faster than :math:`u_{max}` allows (it says so). Under a
rate bound both strategies then use :mod:`.ratelimited`: smoothed bang-dwell-bang motions (cubic
ramps of the rate, cruises below :math:`u_{max}`, a dwell) that fill the exact limited interval.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
from numpy.polynomial import Polynomial as _Poly

from ...core.conditions import hermite_inverse
from ...core import backend
from ...core.basis import from_power
from ...core.limits import COMPLIANCE_TOL, Limits
from ...core.strategies import (Interval, IntervalOutcome, Strategy, deform_attempt, make_segment,
                                register_strategy, run_stages)
from .ratelimited import rate_limited_attempt


__all__ = ["flat_pieces", "flat_guess", "FlatGuess", "FlatOutput", "AcrobotAuto", "TRANSITIONS", "AUTO_SIZES",
           "AUTO_BUDGET"]


@functools.cache
def _fine_rule() -> tuple[np.ndarray, np.ndarray]:
    """The 256-node Gauss-Legendre rule on [0, 1], ``(nodes, weights)``: made on first use (an
    eigenvalue problem of order 256: milliseconds, but up to a second on a busy machine, when the
    linear algebra's threads wait for a core), not when the family's strategies are imported."""
    x, w = np.polynomial.legendre.leggauss(256)
    return (x + 1) / 2, w / 2


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
    S, WS = _fine_rule()
    return D * float(np.sum(WS / robot.h(q(D * S))))


def flat_pieces(robot, x0, x1, T: float, *, ends: dict | None = None, limits: Limits | None = None):
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
    phi0, phiT = float(x0[1]), float(x1[1])
    if robot.P0 == 0.0:
        return None, "P0 = 0: the flat output is constant (holonomic)"
    ends = dict(ends or {})
    u0, du0 = ends.get("u0", 0.0), ends.get("du0", 0.0)
    uT, duT = ends.get("uT", 0.0), ends.get("duT", 0.0)
    target = _flat_target(robot, x0, x1)
    limits = limits or Limits()
    mid = 0.5 * (phi0 + phiT)
    lim_lo, lim_hi = limits.bounds("phi")
    u_max = limits.input_bound("u")
    lo = max(lim_lo, min(phi0, phiT) - math.pi)
    hi = min(lim_hi, max(phi0, phiT) + math.pi)
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
        S, WS = _fine_rule()
        tq = D * S
        a0, a1 = A0(tq), A1(tq) - A0(tq)
        c0, c1 = C0(tq), C1(tq) - C0(tq)
        gA = 1.0 / robot.h(a0[None, :] + grid[:, None] * a1[None, :])
        gC = 1.0 / robot.h(c0[None, :] + grid[:, None] * c1[None, :])
        vals = D * (gA @ WS + gC @ WS) + (T - 2 * D) / robot.h(grid) - target
        idx = np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)[0]
        if idx.size == 0:
            last = (f"with transitions of {rel:g} T the dwell reaches int dt/h in [{vals.min() + target:.6g}, "
                    f"{vals.max() + target:.6g}], not {target:.6g}")
            continue
        for k in idx[np.argsort(np.abs(grid[idx] - mid))]:
            from scipy.optimize import brentq  # here: scipy.optimize takes 0.4 s to import

            p = brentq(f, grid[k], grid[k + 1], xtol=1e-15, rtol=1e-15, maxiter=200)
            A, C = build(p)
            pieces = [(D, A.deriv().coef), (T - 2 * D, np.zeros(1)), (D, C.deriv().coef)]
            # limits, exactly: extremes of u at roots of u', of phi at roots of u
            bad = False
            for (dur, coef), q in zip((pieces[0], pieces[2]), (A, C)):
                u = _Poly(coef)
                pts = np.concatenate([[0.0, dur], [r.real for r in u.deriv().roots() if abs(r.imag) < 1e-12
                                                   and 0 <= r.real <= dur]])
                if u_max is not None and np.max(np.abs(u(pts))) > u_max - COMPLIANCE_TOL:
                    bad = True
                qp = np.concatenate([[0.0, dur], [r.real for r in u.roots() if abs(r.imag) < 1e-12
                                                  and 0 <= r.real <= dur]])
                if np.min(q(qp)) < lim_lo - COMPLIANCE_TOL or np.max(q(qp)) > lim_hi + COMPLIANCE_TOL:
                    bad = True
            if bad:
                last = f"with transitions of {rel:g} T the motion breaks the joint or rate limits"
                continue
            return [pc for pc in pieces if pc[0] > 0], f"flat output, three pieces: dwell p = {p:.6g}, " \
                                                       f"transitions of {rel:g} T"
    return None, f"the three-piece flat motion found no solution: {last}"


# ----------------------------------------------------------------------------------------- guesses
_XG, _WG = np.polynomial.legendre.leggauss(64)
_SG, _WSG = (_XG + 1) / 2, _WG / 2
_SQW = np.sqrt(_WSG)
_VSG = np.vander(_SG, 32, increasing=True)  # power series at the nodes by one product
_VSG.flags.writeable = False
# a coarser rule only to scan the amplitude grid for sign changes (the root uses the 64 nodes)
_XC, _WC = np.polynomial.legendre.leggauss(24)
_SC, _WSC = (_XC + 1) / 2, _WC / 2
_VSC = np.vander(_SC, 32, increasing=True)
_VSC.flags.writeable = False
_AMPS = np.linspace(-4 * np.pi, 4 * np.pi, 41)


@dataclasses.dataclass(frozen=True)
class FlatGuess:
    """An input from the flat output, for path deformation to start from.

    Attributes
    ----------
    coefficients : numpy.ndarray, shape (1, n)
        Coefficients of :math:`u` in the basis it was made for.
    bracketed : bool
        True when the flat-output equation is met (up to the 64-node quadrature's error), i.e.
        the input already reaches the target; False when no member of the families came across
        the target and this is the closest one.
    family : str
        ``"amplitude"`` (the one-parameter bump), ``"dwell"`` (on the line from the closest bump
        to a polynomial imitation of a dwell at an extreme of :math:`1/h`) or ``"closest"``.
    """

    coefficients: np.ndarray
    bracketed: bool
    family: str


_hermite = hermite_inverse  # the conditions on a joint motion's power coefficients


@functools.lru_cache(maxsize=64)
def _family(alpha: int, beta: int, n: int, deg: int):
    """The joint-motion directions that keep the end conditions, for a basis of ``n`` coefficients.

    :math:`v_j(s) = s^{\\alpha}(1-s)^{\\beta}(2s-1)^j`, :math:`j = 0..n-\\alpha-\\beta`, all of degree
    <= n, so :math:`\\varphi' \\propto u` fits the basis. Returns, read-only: their values at the
    quadrature nodes ``V`` (64, d+1) and their derivatives ``Vd`` (64, d+1), both evaluated in
    product form (no power series: accurate at every degree), the weighted least-squares
    pseudo-inverse on the nodes ``pinv`` (d+1, 64), the largest :math:`|v_0|` on the nodes, and
    the dwell shape ``B`` (64,): :math:`(1 - (2s-1)^{2k})^{a}`, :math:`a = \\max(\\alpha, \\beta)`, which
    vanishes with the directions and is flat in the middle, with the largest :math:`k` that keeps
    :math:`\\deg \\varphi_h + 2ka \\le n` (``None`` when even k = 1 does not fit), and
    :math:`v_0` on the 24 coarse nodes.
    """
    d = n - alpha - beta
    x = 2.0 * _SG - 1.0
    w = _SG**alpha * (1.0 - _SG) ** beta
    dw = alpha * _SG ** (alpha - 1) * (1.0 - _SG) ** beta - beta * _SG**alpha * (1.0 - _SG) ** (beta - 1)
    j = np.arange(d + 1)
    X = x[:, None] ** j[None, :]
    Xd = np.where(j > 0, 2.0 * j * x[:, None] ** np.maximum(j - 1, 0), 0.0)
    V = w[:, None] * X
    Vd = dw[:, None] * X + w[:, None] * Xd
    pinv = np.linalg.pinv(V * _SQW[:, None]) * _SQW[None, :]
    a = max(alpha, beta)
    k = (n - deg) // (2 * a)
    B = (1.0 - x ** (2 * k)) ** a if k >= 1 else None
    Wc = _SC**alpha * (1.0 - _SC) ** beta
    for arr in (V, Vd, pinv, Wc) + ((B,) if B is not None else ()):
        arr.flags.writeable = False
    return V, Vd, pinv, float(np.max(np.abs(V[:, 0]))), B, Wc


@functools.lru_cache(maxsize=256)
def _projection(basis_cls, n: int, alpha: int, beta: int, deg: int):
    """:math:`u = \\varphi'/T` in the basis, as two matrices: ``Pd`` (n, deg) maps the power
    coefficients 1.. of :math:`\\varphi_h` (in s), ``PVd`` (n, d+1) the family coefficients ``q``;
    ``c = (Pd @ ph[1:] + PVd @ q) / T``. Both are the least-squares projection of values at the
    64 nodes (exact for polynomials of degree < n) of derivatives evaluated in product form."""
    P = np.linalg.pinv(basis_cls(n).matrix(_SG))
    k = np.arange(1, deg + 1)
    Pd = P @ (k * _SG[:, None] ** (k - 1))  # d/ds s^k at the nodes
    PVd = P @ _family(alpha, beta, n, deg)[1]
    for a in (Pd, PVd):
        a.flags.writeable = False
    return Pd, PVd


_NMID = 13  # the grid amplitudes nearest 0, scanned first
_MID0 = (_AMPS.size - _NMID) // 2


def _integral(T, M1, A1, phi, weights=_WSG):
    """:math:`T \\int_0^1 ds / h(\\varphi(s))` by the 64-node rule (or the coarse one, given its
    ``weights``); ``phi`` has the nodes last."""
    return T * ((1.0 / (M1 + A1 * np.cos(phi))) @ weights)


def _coarse(T, M1, A1, PHc, amps, Wc):
    """:func:`_integral` on the coarse rule for the bump amplitudes ``amps`` (a scan only)."""
    return _integral(T, M1, A1, PHc[None, :] + amps[:, None] * Wc[None, :], _WSC)


def _flat_target(robot, x0, x1) -> float:
    """:math:`I^* = (\\theta_T - \\theta_0 + F(\\varphi_T) - F(\\varphi_0))/P_0`, the value of
    :math:`\\int dt/h(\\varphi)` a joint motion from ``x0`` to ``x1`` must have."""
    return (float(x1[0]) - float(x0[0]) + float(robot.F(float(x1[1]))) - float(robot.F(float(x0[1])))) / robot.P0


def _root(T, M1, A1, phi0, dphi, target, f0, f1):
    """:math:`\\lambda \\in [0, 1]` with :math:`I[\\varphi_0 + \\lambda\\,\\delta\\varphi] = I^*`, given
    ``f0``, ``f1`` (the residuals at 0 and 1) of opposite signs: safeguarded Newton."""
    lo, hi, flo = 0.0, 1.0, f0
    lam = -f0 / (f1 - f0) if f1 != f0 else 0.5
    tol = 4e-16 * (1.0 + abs(target))
    for _ in range(40):
        phi = phi0 + lam * dphi
        h = M1 + A1 * np.cos(phi)
        g = 1.0 / h
        f = T * float(g @ _WSG) - target
        if abs(f) <= tol:
            break
        if (f < 0) == (flo < 0):
            lo, flo = lam, f
        else:
            hi = lam
        df = T * float((A1 * np.sin(phi) * dphi * g * g) @ _WSG)
        step = lam - f / df if df != 0.0 else 0.5 * (lo + hi)
        new = step if lo < step < hi else 0.5 * (lo + hi)
        if abs(new - lam) <= 1e-15:
            lam = new
            break
        lam = new
    return lam


def flat_guess(robot, basis, x0, x1, T: float, ends: dict | None = None, *,
               steep: bool = True) -> FlatGuess | None:
    """A start for path deformation from the flat output, or ``None``.

    Joint motions :math:`\\varphi(s) = \\varphi_h(s) + w(s)\\,q(s)`: :math:`\\varphi_h` is the
    lowest-degree polynomial meeting the end values of :math:`\\varphi` and the given end conditions
    on :math:`u, u'`; :math:`w = s^{\\alpha}(1-s)^{\\beta}` vanishes with them; :math:`q` is a
    polynomial of degree :math:`n - \\alpha - \\beta`, so that :math:`u = \\dot\\varphi` fits the
    basis of ``basis.n`` coefficients. Two families, cheapest first, each solving the scalar
    flat-output equation :math:`T\\int_0^1 ds/h(\\varphi(s)) = I^*` (64-node Gauss-Legendre,
    safeguarded Newton):

    1. *amplitude*: :math:`q = a` constant, :math:`a` on a grid of 41 values, the root nearest
       :math:`a = 0`;
    2. *dwell*: polynomial imitations of the bang-dwell-bang extremals that bound the reachable
       interval, moving the joint to an extreme of :math:`1/h` (:math:`\\varphi^* \\in \\pi\\mathbb{Z}`
       within :math:`\\pi` of the motion, nearest first) and keeping it there: first the gentle
       :math:`\\varphi_h + (\\varphi^* - \\varphi_h)B` with the flat-topped :math:`B` of
       :func:`_family`, then (``steep=True``) the weighted least-squares fit of :math:`q` to a
       dwell at :math:`\\varphi^*` on the nodes, which reaches further with much larger rates. The
       root is sought on the straight line from the closest amplitude member to the first of
       these on the other side of the target.

    ``u`` is evaluated at the nodes in product form and projected on the basis (exact for its
    degree), never through power series, so the guess stays accurate at 10 and 14 coefficients.

    The guess meets :math:`\\varphi(T)` and the input conditions exactly, and :math:`\\theta(T)` up to
    the quadrature error when ``bracketed``; path deformation then only polishes.

    Returns
    -------
    FlatGuess, or None when the family does not fit in the basis (or ``P0 = 0``).
    """
    ends = ends or {}
    phi0, phiT = float(x0[1]), float(x1[1])
    if robot.P0 == 0.0:
        return None
    keys = tuple(k for k in ("u0", "du0", "uT", "duT") if k in ends)
    left = sum(k in ends for k in ("u0", "du0"))
    deg = 1 + len(keys)
    alpha, beta = 1 + left, 1 + len(keys) - left
    n = basis.n
    if max(deg, alpha + beta) > n:
        return None
    scale = {"u0": T, "du0": T * T, "uT": T, "duT": T * T}
    if keys:
        ph = _hermite(keys, deg) @ np.array([phi0, phiT] + [scale[k] * float(ends[k]) for k in keys])
    else:  # no input conditions: the straight line
        ph = np.array([phi0, phiT - phi0])
    V, _, pinv, wmax, dwell, Wc = _family(alpha, beta, n, deg)
    PH = _VSG[:, : ph.size] @ ph
    W = V[:, 0]
    target = _flat_target(robot, x0, x1)
    M1, A1 = robot.M1, robot.A1

    # 1. amplitude family: scan the grid with the coarse rule (the 13 amplitudes nearest 0 first:
    #    a sign change among them is nearer 0 than any outside), confirm with the fine rule
    amps = _AMPS / wmax
    PHc = _VSC[:, : ph.size] @ ph
    coarse = _coarse(T, M1, A1, PHc, amps[_MID0:_MID0 + _NMID], Wc) - target
    idx = np.flatnonzero(np.sign(coarse[:-1]) * np.sign(coarse[1:]) <= 0) + _MID0
    if not idx.size:
        coarse = _coarse(T, M1, A1, PHc, amps, Wc) - target
        idx = np.flatnonzero(np.sign(coarse[:-1]) * np.sign(coarse[1:]) <= 0)
    bracketed = False
    if idx.size:
        kk = idx[np.argmin(np.abs(amps[idx]))]
        f01 = _integral(T, M1, A1, PH[None, :] + amps[kk:kk + 2, None] * W[None, :]) - target
        bracketed = f01[0] * f01[1] <= 0  # the rules agree (they differ only by quadrature error)
    q = np.zeros(V.shape[1])
    if bracketed:
        da = amps[kk + 1] - amps[kk]
        lam = _root(T, M1, A1, PH + amps[kk] * W, da * W, target, f01[0], f01[1])
        q[0] = amps[kk] + lam * da
        family = "amplitude"
    else:
        if coarse.size < amps.size:
            coarse = _coarse(T, M1, A1, PHc, amps, Wc) - target
        i = int(np.argmin(np.abs(coarse)))
        q[0] = amps[i]
        f_a = float(_integral(T, M1, A1, PH + amps[i] * W)) - target
        family = "closest"
        # 2. dwell family: phi_h + (phi* - phi_h) B, a flat-topped move to phi* in pi Z near the
        #    motion (gentle), then the least-squares fit of a dwell at phi* (steeper), nearest first
        if V.shape[1] > 1 and (steep or dwell is not None):
            lo_, hi_ = min(phi0, phiT) - math.pi, max(phi0, phiT) + math.pi
            stars = np.pi * np.arange(math.ceil(lo_ / math.pi), math.floor(hi_ / math.pi) + 1)
            stars = stars[np.argsort(np.abs(stars - 0.5 * (phi0 + phiT)), kind="stable")]
            gap = stars[:, None] - PH[None, :]
            shapes = ([gap * dwell[None, :]] if dwell is not None else []) + ([gap] if steep else [])
            Q = np.concatenate([g @ pinv.T for g in shapes])
            fq = _integral(T, M1, A1, PH[None, :] + Q @ V.T) - target
            across = np.flatnonzero(np.sign(fq) != np.sign(f_a))
            if across.size:
                j = across[0]
                dq = Q[j] - q
                lam = _root(T, M1, A1, PH + V @ q, V @ dq, target, f_a, fq[j])
                q = q + lam * dq
                family, bracketed = "dwell", True
    # u = phi'/T at the nodes, in product form, projected on the basis (exact for its degree)
    Pd, PVd = _projection(type(basis), n, alpha, beta, deg)
    c = (Pd[:, : ph.size - 1] @ ph[1:] + PVd @ q) / T
    return FlatGuess(c[None, :], bracketed, family)


# ----------------------------------------------------------------------------------------- strategies
#: basis sizes tried by the acrobot's ``method="auto"`` when ``n_coefficients`` is not given
AUTO_SIZES = (6, 10, 14)
#: evaluation budget per basis size under ``method="auto"``
AUTO_BUDGET = 100


def _scalar_ends(ends: dict) -> dict:
    """The acrobot's one input: the end conditions as floats."""
    return {key: float(v[0]) for key, v in ends.items()}


def _flat_attempt(interval: Interval) -> IntervalOutcome:
    """The three-piece flat-output plan of ``interval`` as segments (move, dwell, move)."""
    system, x0, x1, T, limits = interval.system, interval.x0, interval.x1, interval.T, interval.limits
    pieces, msg = flat_pieces(system, x0, x1, T, ends=_scalar_ends(interval.ends), limits=limits)
    if pieces is None:
        return IntervalOutcome(False, (), msg)
    out, x, t0 = [], np.array(x0, dtype=float), 0.0
    family = type(interval.basis)
    for i, (D, coef) in enumerate(pieces):
        nb = family(max(len(coef), 1))
        c = from_power(family, np.pad(coef, (0, nb.n - len(coef))), D)[None, :]
        y, _ = backend.endpoint(system, nb, x, D, c)
        end = np.array(x1, dtype=float) if i == len(pieces) - 1 else y
        out.append(make_segment(system, nb, x, end, D, c, t0=t0, final_error=system.error(y, end), message=msg,
                                method="flat", limits=limits))
        x, t0 = end, t0 + D
    if out[-1].final_error <= interval.tol:
        return IntervalOutcome(True, tuple(out))
    return IntervalOutcome(False, (out[-1],), f"flat output: endpoint error {out[-1].final_error:.2e} > tol")


def _rate_bound(interval: Interval) -> bool:
    """Whether the interval's limits bound the joint rate (the rate-limited family then applies)."""
    return interval.limits is not None and interval.limits.input_bound("u") is not None


def _holonomic_attempt(interval: Interval) -> IntervalOutcome:
    """P0 = 0: theta + F(phi) is constant, so theta(T) follows from phi(T) whatever the joint does
    (the feasibility test has already checked that the target is that value). Plan the joint
    motion directly: the lowest-degree polynomial meeting phi's end values and the input
    conditions, and let theta follow; no iteration."""
    system, x0, x1, T, limits = interval.system, interval.x0, interval.x1, interval.T, interval.limits
    ends = _scalar_ends(interval.ends)
    keys = tuple(k for k in ("u0", "du0", "uT", "duT") if k in ends)
    deg = 1 + len(keys)
    phi0, phiT = float(x0[1]), float(x1[1])
    scale = {"u0": T, "du0": T * T, "uT": T, "duT": T * T}
    ph = (_hermite(keys, deg) @ np.array([phi0, phiT] + [scale[k] * float(ends[k]) for k in keys])) if keys \
        else np.array([phi0, phiT - phi0])
    n = max(deg, (interval.sizes or AUTO_SIZES)[0])
    q = np.zeros(n)
    q[: ph.size - 1] = ph[1:] * np.arange(1, ph.size) / T  # u(s) = phi_h'(s) / T, power basis in s
    nb = interval.sized(n)
    c = nb.from_power_s(q)[None, :]
    y, _ = backend.endpoint(system, nb, x0, T, c)
    err = system.error(y, x1)
    msg = (f"P0 = 0 (holonomic): the joint motion planned directly, theta follows; endpoint error {err:.2e}")
    piece = make_segment(system, nb, x0, x1, T, c, t0=0.0, final_error=err, message=msg, method="holonomic",
                         limits=limits, evaluations=1)
    checked = piece.extremes
    broke = checked is not None and limits is not None and (
        (limits.input_bound("u") is not None and checked["max_abs_u"] > limits.input_bound("u") + COMPLIANCE_TOL)
        or any(r[0] < limits.bounds(st)[0] - COMPLIANCE_TOL or r[1] > limits.bounds(st)[1] + COMPLIANCE_TOL
               for st, r in checked["state_ranges"].items()))
    if err <= interval.tol and not broke:
        return IntervalOutcome(True, (piece,), "", 1)
    why = "the lowest-degree joint motion breaks the limits" if broke else \
        f"theta(T) is fixed by phi(T) and the joint motion ends {err:.2e} from the target"
    return IntervalOutcome(False, (dataclasses.replace(piece, success=False),), f"P0 = 0: {why}", 1)


class FlatOutput(Strategy):
    """``method="flat"``: the three-piece flat-output planner (:func:`flat_pieces`): move, dwell,
    move, exact up to a scalar root; reaches every target strictly inside the exact interval.

    Under a rate bound, when the quintic transitions cannot reach the target within it, the
    rate-limited family (:func:`.ratelimited.rate_limited_attempt`: up to seven pieces, method
    ``"flat-rate"``), which reaches every target strictly inside the exact limited interval."""

    name = "flat"

    def unsupported(self, system):
        if not all(hasattr(system, a) for a in ("F", "h", "P0")):
            return f"\"flat\" needs a flat output, which {type(system).__name__} does not provide"
        return None

    def solve(self, interval: Interval) -> IntervalOutcome:
        if interval.system.P0 == 0.0:
            return _holonomic_attempt(interval)
        out = _flat_attempt(interval)
        if out.success or not _rate_bound(interval):
            return out
        # under a rate bound: the smoothed bang-dwell-bang family (acrobot.ratelimited)
        alt = rate_limited_attempt(interval)
        if alt.success:
            return alt
        return IntervalOutcome(False, alt.pieces or out.pieces, f"{out.reason}; {alt.reason}")


class AcrobotAuto(Strategy):
    """The acrobot's ``method="auto"``.

    Path deformation started from a flat-output guess that already meets the target
    (:func:`flat_guess`), at the smallest of :data:`AUTO_SIZES` whose guess brackets it, gentle
    guesses at every size before steep ones, so that deformation only polishes (one or two
    endpoint evaluations); then path deformation with the first size from the closest guess
    (budget :data:`AUTO_BUDGET` evaluations), the flat-output planner, and the remaining sizes
    (only the given size when ``n_coefficients`` is given).

    Under a rate bound the rate-limited flat family (:func:`.ratelimited.rate_limited_attempt`)
    comes right after the first path deformation, before the quintic flat planner: it reaches every
    target strictly inside the exact limited interval, and trying it there was measured fastest
    at equal success (``benchmarks/limits_rate.py``). Without a rate bound nothing changes.
    """

    name = "acrobot-auto"

    def unsupported(self, system):
        return FlatOutput().unsupported(system)

    def solve(self, interval: Interval) -> IntervalOutcome:
        if interval.system.P0 == 0.0:
            return _holonomic_attempt(interval)
        sizes = interval.sizes or AUTO_SIZES
        guesses = {}
        scalar = _scalar_ends(interval.ends)

        def guess_for(n, steep=True):
            if (n, steep) not in guesses:
                guesses[n, steep] = flat_guess(interval.system, interval.sized(n), interval.x0, interval.x1,
                                               interval.T, scalar, steep=steep)
            return guesses[n, steep]

        def deform(n):
            g = guess_for(n, False)
            g = g if g is not None and g.bracketed else guess_for(n)
            return deform_attempt(interval, n, initial=None if g is None else g.coefficients, budget=AUTO_BUDGET)

        first = next((n for steep in (False, True) for n in sizes
                      if (g := guess_for(n, steep)) is not None and g.bracketed), None)
        order = ([first] if first is not None else []) + [n for n in sizes if n != first]
        stages = [lambda: deform(order[0]), lambda: _flat_attempt(interval)]
        stages += [lambda n=n: deform(n) for n in order[1:]]
        if _rate_bound(interval):  # before the quintic flat stage (measured: benchmarks/limits_rate.py)
            stages.insert(1, lambda: rate_limited_attempt(interval))
        return run_stages(stages)


register_strategy(FlatOutput())
