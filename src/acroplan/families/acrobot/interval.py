"""The exact reachable interval of the acrobot's theta(T) (:func:`reachable_interval`), the view of
:func:`~acroplan.families.acrobot.reach.reachable_set` the front doors and the least-momentum search
use."""

from __future__ import annotations

import math

from ...core.errors import InvalidInputError
from ...core.limits import Limits
from .model import Acrobot
from .reach import reachable_set

__all__ = ["reachable_interval"]


def reachable_interval(robot: Acrobot, *, theta0: float, phi0: float, phiT: float, T: float,
                       u_max: float | None = None, phi_min: float | None = None, phi_max: float | None = None):
    """The exact interval of :math:`\\theta(T)` reachable by the acrobot.

    Without limits it is open (:meth:`Acrobot.reachable_interval`); with a rate bound ``u_max`` it
    is closed, its ends attained by bang-dwell-bang joint motions; joint limits
    ``phi_min``/``phi_max`` narrow it further (:func:`acroplan.families.acrobot.reach.reachable_set`).

    Returns
    -------
    (low, high) : tuple of float

    Raises
    ------
    InvalidInputError
        For invalid limits, or when no joint motion satisfies them (the message says why).
    """
    if not isinstance(robot, Acrobot):
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
    R = reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T,
                      limits=Limits(phi_min=phi_min, phi_max=phi_max, u_max=u_max))
    if R.empty:
        raise InvalidInputError("phi", R.reason, "relax the limits or move the waypoints")
    return R.low, R.high
