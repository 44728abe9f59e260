"""The least angular momentum for a turn: the question a coach asks.

How much angular momentum must a diver take off with to turn :math:`n` somersaults in a given
flight time, in a given position, under the body's joint range and rate limits? For the two-link
body this is exact, with no planning: the reachable :math:`\\theta(T)` from :math:`\\theta(0)`
with the joint going from :math:`\\varphi_0` to :math:`\\varphi_T` (module
:mod:`acroplan.families.acrobot.reach`) is an interval whose ends are

.. math::  \\theta_0 - (F(\\varphi_T) - F(\\varphi_0)) + P_0\\,J_\\pm ,
           \\qquad J_- = \\inf_\\varphi \\int_0^T \\frac{dt}{h(\\varphi(t))},\\quad
           J_+ = \\sup_\\varphi \\int_0^T \\frac{dt}{h(\\varphi(t))} ,

(the extremes over the joint motions the limits allow), affine and monotone in :math:`P_0`. The
least :math:`P_0` that reaches a target is where the far end meets it; the largest, where the near
end does (more momentum turns too far even with the slowest-turning motion). Both are found by a
safeguarded false-position search on :math:`P_0` with the exact interval
(:func:`acroplan.families.acrobot.reachable_interval`) to the last bit: the search is exact in
one step for an affine end and falls back to bisection steps whenever a step fails to halve the
bracket. Without rate limits the interval is open, so the least momentum is an infimum (any more
momentum works); with rate limits it is attained.

* :func:`least_momentum`: one turn;
* :func:`somersault_table`: least momentum for several somersault counts and flight times, the
  table and the figure (:func:`plot_somersault_table`) of the coach's question.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...core.errors import InvalidInputError
from ...core.limits import Limits
from .interval import reachable_interval
from .model import Acrobot

__all__ = ["MomentumBound", "least_momentum", "somersault_table", "SomersaultTable", "plot_somersault_table"]


@dataclasses.dataclass(frozen=True)
class MomentumBound:
    """The least (or largest) angular momentum for a turn (:func:`least_momentum`).

    Attributes
    ----------
    P0 : float
        Signed: negative when :math:`\\theta` must decrease; NaN when no momentum works.
    end : {"least", "most"}
    attained : bool
        Whether a plan at exactly ``P0`` exists (with rate limits) or ``P0`` is an infimum or a
        supremum (without: any momentum strictly beyond it works).
    success : bool
        ``P0`` is finite.
    message : str
        What was found, or why no momentum works (the proof).
    """

    P0: float
    end: str
    attained: bool
    success: bool
    message: str

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


def _ends(robot: Acrobot, P0: float, kw: dict) -> tuple[float, float]:
    return reachable_interval(Acrobot(robot.M1, robot.A1, robot.M2, robot.A2, P0), **kw)


def least_momentum(robot: Acrobot, *, theta0: float, thetaT: float, phi0: float, phiT: float, T: float,
                   limits: Limits | None = None, end: str = "least") -> MomentumBound:
    """The least (``end="least"``) or largest (``end="most"``) angular momentum with which the
    two-link body turns from ``theta0`` to ``thetaT`` in time ``T`` while its joint goes from
    ``phi0`` to ``phiT`` under ``limits`` (joint range ``phi_min``/``phi_max``, rate ``u_max``).

    Parameters
    ----------
    robot : Acrobot
        Its own ``P0`` is not used.
    theta0, thetaT, phi0, phiT : float
        Radians.
    T : float
        The flight time, seconds.
    limits : Limits, optional
    end : {"least", "most"}

    Returns
    -------
    MomentumBound

    Examples
    --------
    >>> import math, acroplan
    >>> from acroplan.families.acrobot.momentum import least_momentum
    >>> robot = acroplan.examples.robot("pike-dive")
    >>> b = least_momentum(robot, theta0=0.0, thetaT=-7 * math.pi, phi0=-math.pi, phiT=-math.pi, T=1.5,
    ...                    limits=acroplan.Limits(phi_min=-math.pi, phi_max=-0.4, u_max=12.0))
    >>> b.success, b.P0 < 0, b.attained
    (True, True, True)
    """
    if not isinstance(robot, Acrobot):
        raise InvalidInputError("robot", f"must be an acroplan.Acrobot, got {type(robot).__name__}",
                                "least_momentum is exact for the two-link body; build one with "
                                "acroplan.Acrobot.from_physical(...)")
    if end not in ("least", "most"):
        raise InvalidInputError("end", f"must be 'least' or 'most', got {end!r}", "give end='least' or end='most'")
    limits = limits if limits is not None else Limits()
    if not isinstance(limits, Limits):
        raise InvalidInputError("limits", f"must be an acroplan.Limits, got {type(limits).__name__}",
                                "give for example acroplan.Limits(phi_min=-3.1, phi_max=-0.4, u_max=12)")
    for field, v in (("thetaT", thetaT),):
        if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not math.isfinite(v):
            raise InvalidInputError(field, f"must be a finite number, got {v!r}", "give the target angle in radians")
    U = limits.input_bound("u")
    lo_l, hi_l = limits.bounds("phi")
    kw = dict(theta0=theta0, phi0=phi0, phiT=phiT, T=T, u_max=U, phi_min=lo_l if math.isfinite(lo_l) else None,
              phi_max=hi_l if math.isfinite(hi_l) else None)
    attained = U is not None
    try:
        base = _ends(robot, 0.0, kw)[0]
    except InvalidInputError as e:
        if e.field != "phi":
            raise
        return MomentumBound(math.nan, end, False, False, f"no joint motion is possible: {e.problem}")
    thetaT = float(thetaT)
    gap = thetaT - base
    if gap == 0.0:
        return MomentumBound(0.0, end, True, True, "the target is reached with no angular momentum")
    sign = 1.0 if gap > 0 else -1.0
    if end == "least":  # the interval's far end must reach the target
        def f(p):
            lo, hi = _ends(robot, sign * p, kw)
            return (hi - thetaT) if sign > 0 else (thetaT - lo)
    else:  # the near end must not pass it
        def f(p):
            lo, hi = _ends(robot, sign * p, kw)
            return (lo - thetaT) if sign > 0 else (thetaT - hi)
        if f(0.0) >= 0:  # pragma: no cover - the near end starts at the base, short of the target
            return MomentumBound(0.0, end, True, True, "the target is reached with no angular momentum")
    a, fa = 0.0, f(0.0)
    b = max(abs(gap) / max(T, 1e-300), 1e-300)
    fb = f(b)
    while fb < 0:
        a, fa = b, fb
        b *= 2.0
        if not math.isfinite(b) or b > 1e300:
            return MomentumBound(math.nan, end, False, False, "no finite angular momentum reaches the target")
        fb = f(b)
    for _ in range(400):
        if fb == 0.0 or b - a <= 2.0 * math.ulp(b):
            break
        width = b - a
        p = a - fa * (b - a) / (fb - fa)
        if not a < p < b:
            p = 0.5 * (a + b)
        fp = f(p)
        if fp >= 0:
            b, fb = p, fp
        else:
            a, fa = p, fp
        if b - a > 0.5 * width:
            m = 0.5 * (a + b)
            if a < m < b:
                fm = f(m)
                if fm >= 0:
                    b, fb = m, fm
                else:
                    a, fa = m, fm
    P0 = sign * ((b if fb == 0.0 else a) if end == "most" else b)
    what = "least" if end == "least" else "largest"
    kind = "attained (rate limits)" if attained else ("an infimum: any larger momentum works" if end == "least"
                                                      else "a supremum: any smaller momentum works")
    return MomentumBound(P0, end, attained, True, f"the {what} angular momentum is {P0:.6g}, {kind}")


@dataclasses.dataclass(frozen=True)
class SomersaultTable:
    """Least angular momentum for ``somersaults`` (rows) in ``flight_times`` (columns).

    Attributes
    ----------
    somersaults : numpy.ndarray, shape (S,)
    flight_times : numpy.ndarray, shape (F,)
    P0 : numpy.ndarray, shape (S, F)
        The least momentum (its magnitude; NaN where none works).
    messages : tuple of tuple of str, shape (S, F)
    """

    somersaults: np.ndarray
    flight_times: np.ndarray
    P0: np.ndarray
    messages: tuple

    def to_markdown(self, digits: int = 1) -> str:
        """The table as Markdown (rows: somersaults; columns: flight time)."""
        head = "| somersaults | " + " | ".join(f"T = {t:g} s" for t in self.flight_times) + " |"
        rule = "|---|" + "---|" * len(self.flight_times)
        rows = [f"| {n:g} | " + " | ".join("impossible" if not math.isfinite(p) else f"{p:.{digits}f}"
                                            for p in row) + " |" for n, row in zip(self.somersaults, self.P0)]
        return "\n".join([head, rule, *rows])

    def plot(self, ax=None):
        """The figure: least momentum against flight time, one line per somersault count."""
        return plot_somersault_table(self, ax=ax)


def somersault_table(robot: Acrobot, *, somersaults, flight_times, phi0: float, phiT: float,
                     limits: Limits | None = None, backward: bool = False) -> SomersaultTable:
    """The least angular momentum for each number of somersaults in each flight time.

    A somersault is a full turn of :math:`\\theta`: :math:`n` somersaults forward are
    :math:`\\theta_T - \\theta_0 = -2\\pi n` (the text's sign: a dive with :math:`P_0 < 0` turns
    :math:`\\theta` down), ``backward=True`` the opposite sign. The position is set by the joint's
    limits (a pike: the hip's flexion range) and the joint's start and end angles.

    Parameters
    ----------
    robot : Acrobot
    somersaults : array_like, shape (S,)
    flight_times : array_like, shape (F,)
        Seconds.
    phi0, phiT : float
        The joint angle at take-off and at entry.
    limits : Limits, optional
    backward : bool

    Returns
    -------
    SomersaultTable
    """
    S = np.atleast_1d(np.asarray(somersaults, dtype=float))
    F = np.atleast_1d(np.asarray(flight_times, dtype=float))
    if S.ndim != 1 or F.ndim != 1 or not (np.all(np.isfinite(S)) and np.all(S > 0)):
        raise InvalidInputError("somersaults", f"must be a list of positive numbers, got {somersaults!r}",
                                "give for example [2.5, 3.5, 4.5]")
    if not (np.all(np.isfinite(F)) and np.all(F > 0)):
        raise InvalidInputError("flight_times", f"must be a list of positive times, got {flight_times!r}",
                                "give for example [1.4, 1.5, 1.6]")
    sign = 1.0 if backward else -1.0
    P = np.full((S.size, F.size), np.nan)
    msgs = []
    for i, n in enumerate(S):
        row = []
        for j, T in enumerate(F):
            b = least_momentum(robot, theta0=0.0, thetaT=sign * 2.0 * math.pi * n, phi0=phi0, phiT=phiT,
                               T=float(T), limits=limits)
            P[i, j] = abs(b.P0)
            row.append(b.message)
        msgs.append(tuple(row))
    return SomersaultTable(S, F, P, tuple(msgs))


def plot_somersault_table(table: SomersaultTable, ax=None):
    """Least angular momentum against flight time, one line per somersault count."""
    import matplotlib.pyplot as plt  # plotting apart from the numerics: imported here

    if ax is None:
        fig, ax = plt.subplots(figsize=(6.0, 4.0))
    else:
        fig = ax.figure
    for n, row in zip(table.somersaults, table.P0):
        ax.plot(table.flight_times, row, marker="o", label=f"{n:g} somersaults")
    ax.set_xlabel("flight time (s)")
    ax.set_ylabel("least angular momentum |P0|")
    ax.grid(True, alpha=0.3)
    ax.legend()
    return fig
