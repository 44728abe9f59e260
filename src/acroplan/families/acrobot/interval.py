"""The reachable interval of the acrobot's theta(T), deprecated: the view
``reachable_set(...).interval`` of :func:`~acroplan.families.acrobot.reach.reachable_set`, whose
:class:`~acroplan.families.acrobot.reach.Reach` also says whether the ends are attained and, for an
impossible request, why (``status``, ``message``)."""

from __future__ import annotations

import warnings

from ...core.errors import InvalidInputError
from .reach import reachable_set

__all__ = ["reachable_interval"]


def reachable_interval(robot, *, theta0: float, phi0: float, phiT: float, T: float, u_max: float | None = None,
                       phi_min: float | None = None, phi_max: float | None = None):
    """Deprecated: ``reachable_set(...).interval`` (the same keywords).

    Returns
    -------
    (low, high) : tuple of float

    Raises
    ------
    InvalidInputError
        For invalid limits, or when no joint motion satisfies them (the message says why).
    """
    warnings.warn("acroplan.reachable_interval is deprecated; use acroplan.reachable_set(...).interval "
                  "(a Reach: success, status, message, closed)", DeprecationWarning, stacklevel=2)
    R = reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T, u_max=u_max, phi_min=phi_min,
                      phi_max=phi_max)
    if not R.success:
        raise InvalidInputError("phi", R.message, "relax the limits or move the waypoints")
    return R.interval
