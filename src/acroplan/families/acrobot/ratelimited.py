"""The rate-limited flat-output planner: smoothed bang-dwell-bang joint motions.

With a rate bound :math:`|u| \\le U` the exact reachable set of :math:`\\theta(T)` is a closed
interval whose ends are attained by *bang-dwell-bang* joint motions (:mod:`.reach`): full speed
from :math:`\\varphi_0` to a point :math:`p`, a dwell at :math:`p`, full speed to
:math:`\\varphi_T`. The quintic three-piece family of :func:`.flat.flat_pieces` approaches them
only with transitions whose peak rate grows like :math:`|p - \\varphi_0|/\\delta T`, so under a
binding rate bound it stops short of the ends of the interval. This module smooths the extremals
themselves, so that the family fills the exact interval while every member keeps
:math:`|u| < U` and the joint limits.

The joint motion
----------------
A sequence of polynomial pieces (durations in brackets):

1. a *ramp* of the rate :math:`u` from the start rate to a cruise rate :math:`V_1` [r],
2. a *cruise* at :math:`V_1` [c_1],
3. a ramp from :math:`V_1` down to 0, arriving at :math:`p` [r],
4. a *dwell* at :math:`p` [w],
5. the mirror move to :math:`\\varphi_T`: ramp from 0 to :math:`V_2` [r], cruise [c_2], ramp from
   :math:`V_2` to the end rate [r].

Each ramp is the cubic Hermite interpolant of :math:`u` on :math:`s \\in [0, 1]` (local time
:math:`\\tau = r s`),

.. math::  u(s) = h_{00}(s)\\,u_a + h_{10}(s)\\,r\\,m_a + h_{01}(s)\\,u_b + h_{11}(s)\\,r\\,m_b ,

with :math:`(u_a, m_a)` the rate and its slope at the start and :math:`(u_b, m_b)` at the end: the
interval's ``u0``, ``du0`` at the start of piece 1 and ``uT``, ``duT`` at the end of piece 7 when
given (0 otherwise), and slope 0 wherever pieces join. Its travel is
:math:`\\int_0^r u\\,d\\tau = r(u_a + u_b)/2 + r^2(m_a - m_b)/12`. The cruise rate is
:math:`V = \\pm U'`, :math:`U' = (1-\\epsilon)U`, or less when the distance is short: with
:math:`a_1 = \\varphi_0 + r u_0/2 + r^2 \\dot u_0/12` and
:math:`a_2 = \\varphi_T - r u_T/2 + r^2 \\dot u_T/12`,

.. math::  V_1 = \\operatorname{clip}\\Big(\\frac{p - a_1}{r}, -U', U'\\Big),\\quad
           c_1 = \\frac{(|p - a_1| - rU')^+}{U'},\\qquad
           V_2 = \\operatorname{clip}\\Big(\\frac{a_2 - p}{r}, -U', U'\\Big),\\quad
           c_2 = \\frac{(|a_2 - p| - rU')^+}{U'},

and the dwell lasts :math:`w = T - 4r - c_1 - c_2 \\ge 0`. All of this is continuous in
:math:`p`, and so is

.. math::  J(p) = \\int_0^T \\frac{dt}{h(\\varphi(t))}
           = \\sum_{\\text{ramps}} r\\int_0^1 \\frac{ds}{h(\\varphi(s))}
           + \\sum_{\\text{cruises}} \\frac{G(\\varphi_{end}) - G(\\varphi_{start})}{V}
           + \\frac{w}{h(p)},

with :math:`G` the antiderivative of :math:`1/h` (:func:`.reach._G`): the ramps by composite
Gauss-Legendre (32 nodes per panel of at most one radian of joint travel), the cruises and the
dwell exactly. Planning is the scalar flat-output equation :math:`J(p) = I^* = (\\theta_T - \\theta_0
+ F(\\varphi_T) - F(\\varphi_0))/P_0`, solved by Brent's method on a bracket found on a grid of
:math:`p` (97 points and the candidate extremal points of :mod:`.reach`: the multiples of
:math:`\\pi`, the joint limits, the ends of the dwell-feasible range, :math:`\\varphi_0`,
:math:`\\varphi_T`) within the joint limits, the root nearest :math:`(\\varphi_0 + \\varphi_T)/2`
first.

The ladder
----------
:data:`RAMPS` gives :math:`(r, \\epsilon)` relative to the *free time*
:math:`T_f = T - |\\varphi_T - \\varphi_0|/U` (the time an extremal does not need for travel),
gentlest first: :math:`r = \\rho T_f`, :math:`\\epsilon = e\\,T_f/T`. The member at
:math:`p` differs from the bang-dwell-bang motion through :math:`p` by :math:`O(r + \\epsilon T)`
in time, so the family's range of :math:`J` tends to the exact interval as the ladder descends
(relative shortfall about :math:`2\\rho + e`; 1e-5 and 5e-6 on the last rung) and every target
strictly inside it is bracketed on some rung. When :math:`T_f` is tiny (the joint must travel
nearly :math:`UT`) the interval itself is tiny, and the message says so if no rung reaches it.

Every piece is checked exactly before it is returned: :math:`|u| \\le U` at the ends and the roots
of :math:`u'`, :math:`\\varphi` within the joint limits at the ends and the roots of :math:`u`; the
dwell point stays :data:`LIMIT_MARGIN` inside the joint limits.

Not used without a rate bound (joint limits alone: the quintic family reaches every interior
target), nor at :math:`P_0 = 0` (holonomic).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ...core import backend
from ...core.limits import COMPLIANCE_TOL, Limits
from ...core.strategies import Interval, IntervalOutcome, compliant, limit_check, make_segment
from .reach import _G, _pi_multiples


__all__ = ["RAMPS", "LIMIT_MARGIN", "rate_limited_pieces", "rate_limited_attempt", "family_range",
           "RateLimitedFamily"]

#: ``(rho, e)`` per rung, gentlest first: ramps of ``rho * T_f``, cruise at ``(1 - e * T_f / T) U``
RAMPS = ((0.2, 0.1), (0.1, 0.05), (0.05, 0.02), (0.02, 0.01), (0.008, 0.004), (0.003, 0.0015), (0.001, 5e-4),
         (3e-4, 1.5e-4), (1e-4, 5e-5), (3e-5, 1.5e-5), (1e-5, 5e-6))
#: the dwell point keeps this distance (rad) from the joint limits
LIMIT_MARGIN = 1e-10
_GRID = 97
_XG, _WG = np.polynomial.legendre.leggauss(32)


@functools.lru_cache(maxsize=32)
def _nodes(panels: int):
    """Composite Gauss-Legendre on [0, 1] (``panels`` panels of 32 nodes) and the integrals of the
    cubic Hermite basis at the nodes: ``(w, H)`` with ``H`` of shape (4, N) holding
    :math:`\\int_0^s h_{00}, h_{10}, h_{01}, h_{11}`."""
    s = ((np.arange(panels)[:, None] + (_XG[None, :] + 1.0) / 2.0) / panels).ravel()
    w = np.tile(_WG / (2.0 * panels), panels)
    s2, s3, s4 = s * s, s**3, s**4
    H = np.array([s4 / 2 - s3 + s, s4 / 4 - 2 * s3 / 3 + s2 / 2, -s4 / 2 + s3, s4 / 4 - s3 / 3])
    for a in (w, H):
        a.flags.writeable = False
    return w, H


def _ramp(ua: float, ma: float, ub: float, mb: float, r: float) -> np.ndarray:
    """Power coefficients in :math:`s = \\tau/r` of the cubic Hermite ramp of :math:`u` from
    :math:`(u_a, m_a)` to :math:`(u_b, m_b)` in time ``r`` (slopes per unit time)."""
    return np.array([ua, ma * r, 3.0 * (ub - ua) - (2.0 * ma + mb) * r, 2.0 * (ua - ub) + (ma + mb) * r])


def _piece_extremes(phi_a: float, D: float, q: np.ndarray):
    """Exact extremes on one piece with :math:`u(s) = \\sum q_i s^i` (s in [0, 1], duration ``D``):
    ``(max |u|, min phi, max phi, phi at the end)``; extremes of u at the ends and the roots of
    u', of phi at the ends and the roots of u."""
    P = np.polynomial.Polynomial(q)
    Phi = P.integ()

    def at(poly, crit):
        pts = [0.0, 1.0] + [x.real for x in crit.roots() if abs(x.imag) < 1e-12 and 0.0 <= x.real <= 1.0] \
            if crit.degree() >= 1 else [0.0, 1.0]
        return poly(np.array(pts))

    umax = float(np.max(np.abs(at(P, P.deriv()))))
    ph = phi_a + D * at(Phi, P)
    return umax, float(ph.min()), float(ph.max()), phi_a + D * float(Phi(1.0))


class RateLimitedFamily:
    """The smoothed bang-dwell-bang motions of one segment (module docstring).

    Parameters
    ----------
    robot : Acrobot
    phi0, phiT, T : float
    limits : Limits
        Must carry a rate bound on ``u``; joint limits on ``phi`` are optional.
    ends : dict, optional
        ``u0``, ``du0``, ``uT``, ``duT`` as floats (missing ones are 0).
    """

    def __init__(self, robot, phi0: float, phiT: float, T: float, limits: Limits, ends: dict | None = None):
        ends = dict(ends or {})
        self.robot, self.phi0, self.phiT, self.T = robot, float(phi0), float(phiT), float(T)
        self.u0, self.du0 = float(ends.get("u0", 0.0)), float(ends.get("du0", 0.0))
        self.uT, self.duT = float(ends.get("uT", 0.0)), float(ends.get("duT", 0.0))
        self.U = limits.input_bound("u")
        if self.U is None:
            raise ValueError("the rate-limited family needs a rate bound on u")
        self.lim_lo, self.lim_hi = limits.bounds("phi")
        self.T_free = self.T - abs(self.phiT - self.phi0) / self.U
        # the dwell point: within the joint limits (by LIMIT_MARGIN) and within pi of the motion's
        # ends (further never helps: 1/h has period 2 pi)
        self.p_lo = max(self.lim_lo + LIMIT_MARGIN, min(self.phi0, self.phiT) - math.pi)
        self.p_hi = min(self.lim_hi - LIMIT_MARGIN, max(self.phi0, self.phiT) + math.pi)
        self.cap = max(self.U, abs(self.u0), abs(self.uT))  # the given end rates are the caller's
        # phi is accumulated piece by piece: a waypoint on a joint limit is met up to rounding
        self.rounding = 64 * np.finfo(float).eps * (1.0 + max(abs(self.phi0), abs(self.phiT)))

    # ------------------------------------------------------------------ one rung
    def rung(self, rho: float, e: float) -> dict | None:
        """Ramp duration, cruise rate and the dwell-feasible range of ``p`` for rung ``(rho, e)``
        (``None`` when no ``p`` fits: the travel needs more than the time left)."""
        if not self.T_free > 0.0:
            return None
        r = rho * self.T_free
        Uc = self.U * (1.0 - e * self.T_free / self.T)
        a1 = self.phi0 + r * self.u0 / 2 + r * r * self.du0 / 12
        a2 = self.phiT - r * self.uT / 2 + r * r * self.duT / 12
        budget_ = Uc * (self.T - 4.0 * r)
        if budget_ < 0.0:
            return None
        R = r * Uc

        def S(p):  # Uc * (c1 + c2): convex, piecewise linear in p
            return max(0.0, abs(p - a1) - R) + max(0.0, abs(a2 - p) - R)

        # the range {p : S(p) <= budget_} around the minimiser, walking the breakpoints
        pm = 0.5 * (a1 + a2)
        if S(pm) > budget_:
            return None
        brk = sorted({a1 - R, a1 + R, a2 - R, a2 + R})

        def edge(direction):
            prev, sprev = pm, S(pm)
            pts = [b for b in brk if (b - pm) * direction > 0]
            pts.sort(key=lambda b: abs(b - pm))
            for b in pts:
                sb = S(b)
                if sb > budget_:
                    return prev + (b - prev) * (budget_ - sprev) / (sb - sprev)
                prev, sprev = b, sb
            return prev + direction * (budget_ - sprev) / 2.0  # slope 2 beyond every breakpoint

        lo, hi = max(self.p_lo, edge(-1.0)), min(self.p_hi, edge(1.0))
        if not lo <= hi:
            return None
        # Gauss-Legendre panels of at most one radian of joint travel within a ramp
        travel = min(r * Uc, self.p_hi - self.p_lo) + r * max(abs(self.u0), abs(self.uT)) \
            + r * r * max(abs(self.du0), abs(self.duT)) / 4
        panels = int(min(64, max(1, math.ceil(travel))))
        return dict(rho=rho, e=e, r=r, Uc=Uc, a1=a1, a2=a2, lo=lo, hi=hi, panels=panels)

    def shape(self, rung: dict, p):
        """Cruise rates, cruise and dwell durations for the dwell points ``p`` (arrays)."""
        r, Uc = rung["r"], rung["Uc"]
        d1, d2 = p - rung["a1"], rung["a2"] - p
        V1, V2 = np.clip(d1 / r, -Uc, Uc), np.clip(d2 / r, -Uc, Uc)
        c1 = np.maximum(0.0, np.abs(d1) - r * Uc) / Uc
        c2 = np.maximum(0.0, np.abs(d2) - r * Uc) / Uc
        w = np.maximum(0.0, self.T - 4.0 * r - c1 - c2)
        return V1, V2, c1, c2, w

    def J(self, rung: dict, p) -> np.ndarray:
        """:math:`\\int_0^T dt/h(\\varphi)` of the members with dwell points ``p`` (array)."""
        robot, r = self.robot, rung["r"]
        p = np.atleast_1d(np.asarray(p, dtype=float))
        V1, V2, c1, c2, w = self.shape(rung, p)
        wq, H = _nodes(rung["panels"])
        u0, du0, uT, duT, phi0, phiT = self.u0, self.du0, self.uT, self.duT, self.phi0, self.phiT
        g = lambda phi: 1.0 / robot.h(phi)  # noqa: E731
        col = lambda a: np.asarray(a)[:, None]  # noqa: E731
        # ramp 1: (u0, du0) -> (V1, 0); ramp 2: (V1, 0) -> (0, 0) ending at p; ramp 3: (0, 0) ->
        # (V2, 0) from p; ramp 4: (V2, 0) -> (uT, duT) ending at phiT
        e1 = phi0 + r * (u0 + V1) / 2 + r * r * du0 / 12  # end of ramp 1
        b1 = p - r * V1 / 2  # start of ramp 2
        e3 = p + r * V2 / 2  # end of ramp 3
        b4 = phiT - (r * (V2 + uT) / 2 - r * r * duT / 12)  # start of ramp 4
        R1 = phi0 + r * (H[0] * u0 + H[1] * r * du0)[None, :] + r * col(V1) * H[2][None, :]
        R2 = col(b1) + r * col(V1) * H[0][None, :]
        R3 = col(p) + r * col(V2) * H[2][None, :]
        R4 = col(b4) + r * col(V2) * H[0][None, :] + r * (H[2] * uT + H[3] * r * duT)[None, :]
        ramps = r * ((g(R1) + g(R2) + g(R3) + g(R4)) @ wq)
        with np.errstate(divide="ignore", invalid="ignore"):
            C1 = np.where(c1 > 0, (_G(robot, b1) - _G(robot, e1)) / np.where(c1 > 0, V1, 1.0), 0.0)
            C2 = np.where(c2 > 0, (_G(robot, b4) - _G(robot, e3)) / np.where(c2 > 0, V2, 1.0), 0.0)
        return ramps + C1 + C2 + w * g(p)

    def grid(self, rung: dict) -> np.ndarray:
        """The dwell points scanned for a bracket: 97 equally spaced and the candidate extremal
        points of :mod:`.reach` (multiples of pi, the ends of the range, phi0, phiT, a1, a2)."""
        lo, hi = rung["lo"], rung["hi"]
        pts = [np.linspace(lo, hi, _GRID)]
        a_, b_ = sorted((self.phi0, self.phiT))
        k0, k1 = math.ceil(lo / math.pi), math.floor(hi / math.pi)
        if k1 - k0 <= 256:
            pts.append(np.pi * np.arange(k0, k1 + 1))
        else:
            for lo_r, hi_r in ((lo, a_), (a_, b_), (b_, hi)):
                pts.append(np.array(sorted(_pi_multiples(max(lo, lo_r), min(hi, hi_r)))))
        pts.append(np.array([self.phi0, self.phiT, rung["a1"], rung["a2"]]))
        p = np.unique(np.concatenate(pts))
        return p[(p >= lo) & (p <= hi)]

    def pieces(self, rung: dict, p: float) -> list:
        """The member with dwell point ``p``: ``[(duration, q)]`` with :math:`u = \\sum q_i s^i` on
        each piece's :math:`s \\in [0, 1]`; identically-zero neighbours are merged (one dwell)."""
        r = rung["r"]
        V1, V2, c1, c2, w = (float(a[0]) for a in self.shape(rung, np.array([p])))
        raw = [(r, _ramp(self.u0, self.du0, V1, 0.0, r)), (c1, np.array([V1])), (r, _ramp(V1, 0.0, 0.0, 0.0, r)),
               (w, np.zeros(1)), (r, _ramp(0.0, 0.0, V2, 0.0, r)), (c2, np.array([V2])),
               (r, _ramp(V2, 0.0, self.uT, self.duT, r))]
        out = []
        for D, q in raw:
            if D <= 0.0:
                continue
            if not np.any(q) and out and not np.any(out[-1][1]):
                out[-1] = (out[-1][0] + D, np.zeros(1))
            else:
                out.append((D, np.zeros(1) if not np.any(q) else q))
        return out

    def check(self, pieces: list) -> str | None:
        """Why the pieces break the rate or joint limits (exactly), or ``None``."""
        phi = self.phi0
        for D, q in pieces:
            umax, lo, hi, phi = _piece_extremes(phi, D, q)
            if umax > self.cap:
                return f"|u| reaches {umax:.12g} > {self.U:.12g}"
            if lo < self.lim_lo - self.rounding or hi > self.lim_hi + self.rounding:
                return f"phi reaches [{lo:.12g}, {hi:.12g}], beyond the joint limits"
        return None


def _target(robot, x0, x1) -> float:
    """:math:`I^*`: the value of :math:`\\int dt/h` the motion must have (see :mod:`.flat`)."""
    return (float(x1[0]) - float(x0[0]) + float(robot.F(float(x1[1]))) - float(robot.F(float(x0[1])))) / robot.P0


def family_range(robot, *, theta0: float, phi0: float, phiT: float, T: float, limits: Limits,
                 ends: dict | None = None, rungs=RAMPS) -> list:
    """The :math:`\\theta(T)` the family reaches on each rung: ``[(rho, e, low, high)]`` (``None`` for
    ``low, high`` when no member fits), the extremes of :math:`\\theta(0) - \\Delta F + P_0 J(p)`
    over the scan grid and the candidate points. As the ladder descends they approach the exact
    interval of :func:`.reach.reachable_set` from inside."""
    fam = RateLimitedFamily(robot, phi0, phiT, T, limits, ends)
    base = theta0 - (float(robot.F(float(phiT))) - float(robot.F(float(phi0))))
    out = []
    for rho, e in rungs:
        rung = fam.rung(rho, e)
        if rung is None:
            out.append((rho, e, None, None))
            continue
        th = base + robot.P0 * fam.J(rung, fam.grid(rung))
        out.append((rho, e, float(th.min()), float(th.max())))
    return out


def rate_limited_pieces(robot, x0, x1, T: float, *, limits: Limits, ends: dict | None = None,
                        rungs=RAMPS):
    """Plan one segment as a smoothed bang-dwell-bang joint motion (module docstring).

    Parameters
    ----------
    robot : Acrobot
    x0, x1 : array_like
        ``(theta, phi)`` at both ends.
    T : float
    limits : Limits
        With a rate bound on ``u`` (else ``None`` is returned with the reason).
    ends : dict, optional
        ``u0``, ``du0``, ``uT``, ``duT`` as floats.
    rungs : sequence of (rho, e)
        The ladder, gentlest first (:data:`RAMPS`).

    Returns
    -------
    (pieces, message)
        ``pieces``: ``[(duration, q)]``, ``u = sum q_i s^i`` on each piece's normalised time, or
        ``None`` and the reason.
    """
    if robot.P0 == 0.0:
        return None, "P0 = 0: the flat output is constant (holonomic)"
    if limits is None or limits.input_bound("u") is None:
        return None, "no rate bound: the rate-limited family is not needed"
    phi0, phiT = float(x0[1]), float(x1[1])
    fam = RateLimitedFamily(robot, phi0, phiT, T, limits, ends)
    target = _target(robot, x0, x1)
    base = float(x0[0]) - (float(robot.F(phiT)) - float(robot.F(phi0)))
    mid = 0.5 * (phi0 + phiT)
    U = fam.U
    reached, last = None, "no rung fitted the travel in the time"
    for rho, e in rungs:
        rung = fam.rung(rho, e)
        if rung is None:
            last = f"with ramps of {rho:g} T_f no dwell point fits the travel in T"
            continue
        grid = fam.grid(rung)
        vals = fam.J(rung, grid) - target
        reached = (rho, float(vals.min() + target), float(vals.max() + target))
        idx = np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)[0]
        if idx.size == 0:
            last = f"with ramps of {rho:g} T_f the family does not reach the target"
            continue
        f = lambda p: float(fam.J(rung, np.array([p]))[0]) - target  # noqa: E731
        for k in idx[np.argsort(np.abs(grid[idx] - mid), kind="stable")]:
            if vals[k] == 0.0:
                p = float(grid[k])
            elif vals[k + 1] == 0.0:
                p = float(grid[k + 1])
            else:
                from scipy.optimize import brentq  # here: scipy.optimize takes 0.4 s to import

                p = brentq(f, grid[k], grid[k + 1], xtol=1e-15, rtol=1e-15, maxiter=200)
            pieces = fam.pieces(rung, p)
            why = fam.check(pieces)
            if why is not None:
                last = f"with ramps of {rho:g} T_f the motion breaks the limits ({why})"
                continue
            V1, V2 = (float(v[0]) for v in fam.shape(rung, np.array([p]))[:2])
            return pieces, (f"rate-limited flat output, {len(pieces)} pieces: dwell p = {p:.6g}, ramps of "
                            f"{rung['r']:.3g} s ({rho:g} T_f), cruise rates {V1:.6g} and {V2:.6g} "
                            f"(u_max = {U:g})")
    msg = f"the rate-limited flat family found no solution: {last}"
    if reached is not None:
        lo_, hi_ = sorted((base + robot.P0 * reached[1], base + robot.P0 * reached[2]))
        msg += f" (finest ramps {reached[0]:g} T_f reach theta(T) in [{lo_:.12g}, {hi_:.12g}])"
    travel = abs(phiT - phi0)
    if fam.T_free <= 1e-3 * T:
        msg += (f"; the joint must travel {travel:.12g} rad of the {U * T:.12g} rad u_max T allows, so the "
                f"reachable interval is tiny (free time {fam.T_free:.3g} s)")
    return None, msg


def rate_limited_attempt(interval: Interval) -> IntervalOutcome:
    """The smoothed bang-dwell-bang plan of ``interval`` as segments (method ``"flat-rate"``), each
    checked against the limits exactly in its basis (:func:`acroplan.core.limits.violation`)."""
    system, x0, x1, T, limits = interval.system, interval.x0, interval.x1, interval.T, interval.limits
    ends = {key: float(v[0]) for key, v in interval.ends.items()}
    pieces, msg = rate_limited_pieces(system, x0, x1, T, limits=limits, ends=ends)
    if pieces is None:
        return IntervalOutcome(False, (), msg)
    out, x, t0 = [], np.array(x0, dtype=float), 0.0
    family = type(interval.basis)
    for i, (D, q) in enumerate(pieces):
        nb = family(len(q))
        c = nb.from_power_s(q)[None, :]
        y, _ = backend.endpoint(system, nb, x, D, c)
        end = np.array(x1, dtype=float) if i == len(pieces) - 1 else y
        checked = limit_check(system, nb, x, D, c, limits)
        if not compliant(checked):
            return IntervalOutcome(False, (), f"rate-limited flat output: piece {i} breaks the limits in its basis "
                                   f"by {max(checked['u'], checked['state']):.2e} > {COMPLIANCE_TOL:g}")
        out.append(make_segment(system, nb, x, end, D, c, t0=t0, final_error=system.error(y, end), message=msg,
                                method="flat-rate", limits=limits, checked=checked))
        x, t0 = end, t0 + D
    if out[-1].final_error <= interval.tol:
        return IntervalOutcome(True, tuple(out))
    return IntervalOutcome(False, (out[-1],), f"rate-limited flat output: endpoint error "
                           f"{out[-1].final_error:.2e} > tol")
