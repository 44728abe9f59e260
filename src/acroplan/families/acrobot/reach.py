"""Exact reachable sets of the acrobot, with and without rate and joint limits.

Since :math:`k/h\\,d\\varphi = dF` is exact (docs/mathematics.md),

.. math::  \\theta(T) = \\theta(0) - [F(\\varphi(T)) - F(\\varphi(0))] + P_0\\, J[\\varphi],\\qquad
           J[\\varphi] = \\int_0^T g(\\varphi(t))\\,dt,\\quad g = 1/h ,

so the reachable :math:`\\theta(T)` is an interval whose ends are :math:`P_0` times the extremes of
:math:`J` over the admissible joint motions (:math:`\\varphi(0), \\varphi(T)` fixed,
:math:`\\varphi \\in [\\varphi_{min}, \\varphi_{max}]`, :math:`|\\dot\\varphi| \\le u_{max}`).

Without a rate bound the extremes are :math:`T \\min g` and :math:`T \\max g` over the allowed
:math:`\\varphi` range, approached but not attained (an open interval).

With a rate bound :math:`U`, the extremal motions are *bang-dwell-bang*: go at full speed from
:math:`\\varphi(0)` to a point :math:`p`, dwell there, go at full speed to :math:`\\varphi(T)`
(Pontryagin: bang arcs, and singular arcs only where :math:`g' = 0` or on a joint limit). With
:math:`G` an antiderivative of :math:`g` and :math:`d(p) = |p - \\varphi_0| + |\\varphi_T - p|`,

.. math::  V(p) = \\frac{|G(p) - G(\\varphi_0)| + |G(\\varphi_T) - G(p)|}{U}
                  + g(p)\\Big(T - \\frac{d(p)}{U}\\Big),\\qquad d(p) \\le UT ,

and :math:`dV/dp = g'(p)\\,(T - d(p)/U)` outside :math:`[\\varphi_0, \\varphi_T]`, so the extremes of
:math:`V` lie in a finite candidate set: the critical points :math:`k\\pi` of :math:`g`, the
points where the dwell vanishes, :math:`\\varphi_0`, :math:`\\varphi_T` and the joint limits. The
interval is then closed: its ends are attained, by these piecewise-constant controls only.
"""

from __future__ import annotations

import dataclasses
import math
import warnings

import numpy as np

from ...core.errors import InvalidInputError
from ...core.limits import Limits
from ...core.status import Outcome, Status

__all__ = ["Reach", "reachable_set", "Limits"]


@dataclasses.dataclass(frozen=True)
class Reach(Outcome):
    """The exact set of reachable :math:`\\theta(T)`.

    Attributes
    ----------
    low, high : float
        Its ends (``low == high`` when a single value is reachable).
    closed : bool
        Whether the ends are attained (with a rate bound) or only approached (without).
    status : Status
        ``"success"``: the set is not empty; ``"infeasible"``: no admissible joint motion exists,
        and ``message`` says why (the proof).
    message : str
    extremal : dict
        For ``"low"`` and ``"high"``: the extremal control as a list of ``(duration, u)`` pieces
        (only with a rate bound).
    success : bool
        ``status == "success"``.
    interval : (float, float)
        ``(low, high)``.
    """

    low: float
    high: float
    closed: bool
    status: Status = Status.SUCCESS
    message: str = ""
    extremal: dict = dataclasses.field(default_factory=dict)

    @property
    def interval(self) -> tuple[float, float]:
        """``(low, high)``."""
        return self.low, self.high

    @property
    def empty(self) -> bool:
        """Deprecated: ``not reach.success``."""
        warnings.warn("Reach.empty is deprecated; use `not reach.success` (Reach.status, Reach.message)",
                      DeprecationWarning, stacklevel=2)
        return not self.success

    @property
    def reason(self) -> str:
        """Deprecated: ``reach.message``."""
        warnings.warn("Reach.reason is deprecated; use Reach.message", DeprecationWarning, stacklevel=2)
        return self.message

    def contains(self, theta: float, *, strict: bool = True) -> bool:
        """Whether ``theta`` is reachable (``strict``: strictly inside, as a smooth input needs)."""
        if not self.success:
            return False
        if strict:
            return self.low < theta < self.high
        return self.low <= theta <= self.high


def _empty(value: float, why: str) -> Reach:
    return Reach(value, value, True, Status.INFEASIBLE, why)


_NO_LIMITS = Limits()


def _G(robot, phi):
    """Continuous antiderivative of g = 1/h."""
    a, b = robot.M1, robot.A1
    if b == 0.0:
        return np.asarray(phi, dtype=float) / a
    s = math.sqrt(a * a - b * b)
    rho = (a - s) / b
    phi = np.asarray(phi, dtype=float)
    return (phi - 2.0 * np.arctan2(rho * np.sin(phi), 1.0 + rho * np.cos(phi))) / s


def _pi_multiples(lo: float, hi: float) -> set[float]:
    """The candidate critical points :math:`k\\pi` of :math:`V` in ``[lo, hi]``, where ``[lo, hi]`` lies
    inside one of the three regions below, between and above :math:`\\varphi_0, \\varphi_T`.

    In such a region :math:`V(k\\pi)` is linear in :math:`k` for each parity of :math:`k`
    (:math:`g(k\\pi)` depends only on the parity, :math:`G(k\\pi) = k\\pi/s` and :math:`d` is linear),
    so its extremes over the multiples of one parity are at the smallest and the largest: four
    candidates whatever the width of the region (time and memory independent of ``u_max``)."""
    if not hi >= lo:
        return set()
    k0, k1 = math.ceil(lo / math.pi), math.floor(hi / math.pi)
    if k1 < k0:
        return set()
    ks = {k0, k1}
    if k0 + 1 <= k1:
        ks.update((k0 + 1, k1 - 1))
    return {k * math.pi for k in ks}


def _reachable_set(robot, *, theta0: float, phi0: float, phiT: float, T: float,
                  limits: Limits | None = None) -> Reach:
    """The exact reachable :math:`\\theta(T)` under optional limits (module docstring).

    Parameters
    ----------
    robot : Acrobot
    theta0, phi0, phiT, T : float
    limits : Limits, optional

    Returns
    -------
    Reach
    """
    limits = limits or _NO_LIMITS
    lo_lim, hi_lim = limits.bounds("phi")
    base = theta0 - (float(robot.F(phiT)) - float(robot.F(phi0)))
    for name, v in (("phi(0)", phi0), ("phi(T)", phiT)):
        if not lo_lim <= v <= hi_lim:
            return _empty(base, f"{name} = {v:.12g} is outside the joint limits [{lo_lim:.12g}, {hi_lim:.12g}]")
    g = lambda p: 1.0 / robot.h(p)  # noqa: E731
    U = limits.input_bound("u")
    if U is None:
        # sup / inf of g over the allowed range [lo_lim, hi_lim] (it contains phi0 and phiT)
        if hi_lim - lo_lim >= 2 * math.pi:
            gmin, gmax = 1.0 / (robot.M1 + abs(robot.A1)), 1.0 / (robot.M1 - abs(robot.A1))
        else:
            cands = [lo_lim, hi_lim] + [k * math.pi for k in range(math.ceil(lo_lim / math.pi),
                                                                    math.floor(hi_lim / math.pi) + 1)]
            vals = [float(g(p)) for p in cands]
            gmin, gmax = min(vals), max(vals)
        a, b = base + robot.P0 * T * gmin, base + robot.P0 * T * gmax
        return Reach(min(a, b), max(a, b), gmin == gmax)
    dist = abs(phiT - phi0)
    if dist > U * T * (1 + 1e-15):
        return _empty(base, f"phi must move {dist:.12g} rad in T = {T:.12g} s, but u_max = {U:.12g} rad/s "
                      f"allows only {U * T:.12g} rad")
    p_lo = max(lo_lim, (phi0 + phiT - U * T) / 2)
    p_hi = min(hi_lim, (phi0 + phiT + U * T) / 2)
    cands = {p_lo, p_hi, phi0, phiT}
    a_, b_ = min(phi0, phiT), max(phi0, phiT)
    for lo_r, hi_r in ((p_lo, a_), (a_, b_), (b_, p_hi)):
        cands.update(_pi_multiples(lo_r, hi_r))
    Gs = lambda p: float(_G(robot, p))  # noqa: E731

    def V(p):
        dwell = max(0.0, T - (abs(p - phi0) + abs(phiT - p)) / U)
        return (abs(Gs(p) - Gs(phi0)) + abs(Gs(phiT) - Gs(p))) / U + float(g(p)) * dwell, dwell

    scored = sorted((V(p)[0], p) for p in cands)
    (jmin, pmin), (jmax, pmax) = scored[0], scored[-1]

    def control(p):
        dwell = V(p)[1]
        pieces = [(abs(p - phi0) / U, math.copysign(U, p - phi0)), (dwell, 0.0), (abs(phiT - p) / U,
                                                                                     math.copysign(U, phiT - p))]
        return [(d, u) for d, u in pieces if d > 0]

    a, b = base + robot.P0 * jmin, base + robot.P0 * jmax
    ext = {"low": control(pmin), "high": control(pmax)} if robot.P0 >= 0 else {"low": control(pmax),
                                                                             "high": control(pmin)}
    return Reach(min(a, b), max(a, b), True, extremal=ext)


def reachable_set(robot, *, theta0: float, phi0: float, phiT: float, T: float, limits=None,
                  u_max: float | None = None, phi_min: float | None = None, phi_max: float | None = None) -> Reach:
    """The exact set of :math:`\\theta(T)` reachable by the acrobot (a :class:`Reach`: ``interval``,
    ``closed``, ``success``, ``status``, ``message``).

    Without limits it is open; with a rate bound ``u_max`` it is closed, its ends attained by
    bang-dwell-bang joint motions; joint limits ``phi_min``/``phi_max`` narrow it further
    (:func:`acroplan.families.acrobot.reach.reachable_set`). A request no joint motion meets
    (``phi`` cannot move that far, a waypoint outside the joint limits) is a ``Reach`` with
    ``status == "infeasible"`` and the proof in ``message``.

    Parameters
    ----------
    robot : Acrobot
    theta0, phi0, phiT : float
    T : float
        The segment's duration, in (0, 1e6].
    limits : Limits, optional
        All limits at once; or the keywords ``u_max``, ``phi_min``, ``phi_max``.

    Returns
    -------
    Reach
    """
    if not all(hasattr(robot, a) for a in ("F", "h", "M1", "A1", "P0")):  # an Acrobot (model.py imports this)
        raise InvalidInputError("robot", f"must be an acroplan.Acrobot, got {type(robot).__name__}",
                                "build one with acroplan.Acrobot.from_physical(...)")
    for field, v in (("theta0", theta0), ("phi0", phi0), ("phiT", phiT), ("T", T)):
        if isinstance(v, bool) or not isinstance(v, (int, float)) and not (hasattr(v, "dtype") and v.ndim == 0
                                                                          and v.dtype.kind in "fi"):
            raise InvalidInputError(field, f"must be a number, got {type(v).__name__}", "give a finite number")
        if not math.isfinite(float(v)):
            raise InvalidInputError(field, f"must be finite, got {v}", "give a finite number")
    if not 0 < T <= 1e6:
        raise InvalidInputError("T", f"must lie in (0, 1e6], got {T}", "give the segment's duration")
    shorthand = {k: v for k, v in (("u_max", u_max), ("phi_min", phi_min), ("phi_max", phi_max)) if v is not None}
    if limits is not None and shorthand:
        raise InvalidInputError("limits", "is given together with limit keywords",
                                "give either limits=Limits(...) or the keywords u_max, phi_min, phi_max")
    if limits is None:
        limits = Limits(**shorthand)
    elif not isinstance(limits, Limits):
        raise InvalidInputError("limits", f"must be an acroplan.Limits, got {type(limits).__name__}",
                                "give Limits(...) or the keywords u_max, phi_min, phi_max")
    return _reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T, limits=limits)
