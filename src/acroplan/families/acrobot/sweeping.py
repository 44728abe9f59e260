"""What the acrobot offers sweeps (:mod:`acroplan.sweeps`), registered on import
(:mod:`acroplan.core.sweep_hooks`):

* the derived quantities ``least_P0`` and ``most_P0``: the least and the largest angular momentum
  for which the body reaches the last waypoint's theta from the first one's over the whole flight
  (:func:`least_momentum`, exact by the reachable set, no planning);
* the interval behind the ``plan.reach`` field: the exact reachable theta of the last segment;
* the factory ``"Acrobot.from_physical"``, which a stored sweep definition may name.
"""

from __future__ import annotations

import math

from ...core.errors import InvalidInputError
from ...core.sweep_hooks import register_derived, register_factory, register_reach
from .model import Acrobot
from .momentum import least_momentum as _least
from .reach import reachable_set

__all__ = ["least_momentum"]


def least_momentum(req, end: str = "least") -> tuple[float, str | None]:
    """The least (or, ``end="most"``, the largest) angular momentum P0 for which the acrobot reaches
    the last waypoint's theta from the first one's over the whole flight, interior waypoints aside,
    under the request's limits; signed: negative when theta must decrease. Exact, by the reachable
    set, with no planning: :func:`acroplan.families.acrobot.momentum.least_momentum`.

    Parameters
    ----------
    req : PlanRequest
        A validated request (:meth:`acroplan.planning.PlanRequest.build`).
    end : {"least", "most"}

    Returns
    -------
    (P0, None), or (nan, reason)
        The reason when no momentum works (the limits allow no joint motion) or the system is not
        the acrobot.
    """
    system = req.system
    if not isinstance(system, Acrobot):
        return math.nan, f"least_P0 applies to the acrobot, not to {type(system).__name__}"
    t, X = req.times, req.waypoints
    b = _least(system, theta0=float(X[0, 0]), thetaT=float(X[-1, 0]), phi0=float(X[0, 1]), phiT=float(X[-1, 1]),
               T=float(t[-1] - t[0]), limits=req.limits, end=end)
    return (b.P0, None) if b.success else (math.nan, b.message)


def _reach(system: Acrobot, start, end, duration, limits) -> tuple[float, float]:
    R = reachable_set(system, theta0=float(start["theta"]), phi0=float(start["phi"]), phiT=float(end["phi"]),
                      T=float(duration), limits=limits)
    if not R.success:
        raise InvalidInputError("plan.reach", R.message, "relax the limits or move the waypoints")
    return R.low, R.high


def _momentum_units(system) -> str:
    """kg m^2/s for a body given by its masses, inertias and lengths (SI); otherwise the lumped
    parameters' own units."""
    return "kg m^2/s" if getattr(system, "physical", None) is not None else "units of P0"


register_derived("least_P0", lambda req: least_momentum(req, "least"), applies_to=Acrobot, units=_momentum_units,
                 description="the least angular momentum (signed) that reaches the last waypoint's theta from the "
                             "first's over the whole flight under the limits (exact, by the reachable set; an "
                             "infimum without rate limits)")
register_derived("most_P0", lambda req: least_momentum(req, "most"), applies_to=Acrobot, units=_momentum_units,
                 description="the largest angular momentum (signed) that still reaches it: more turns too fast "
                             "(exact, by the reachable set)")
register_reach(Acrobot, "theta", _reach)
register_factory("Acrobot.from_physical", Acrobot.from_physical)
