"""The front door for planning: :func:`plan` (:mod:`~.front`), its validation (:mod:`~.request`) and
the plausibility of its results (:mod:`~.plausible`).

A plan passes through waypoints :math:`x_0, \\dots, x_K` at times :math:`t_0 < \\dots < t_K`. The
work is shared out as follows, and this module names no body:

1. validation (:class:`PlanRequest`): every argument checked at the boundary, messages naming the
   field and the fix;
2. exact feasibility: the system's own test (:meth:`ControlAffineSystem.check_segment`, with the
   limits) refuses an impossible request with its proof; spline conditions that break the limits
   are refused too (:class:`~acroplan.core.conditions.Conditions`);
3. each waypoint interval is planned by a strategy (:mod:`acroplan.core.strategies`): a registered
   name, an object, or ``"auto"``, the system's own choice; with ``objective=`` (or ``tau_max=``)
   by an optimal strategy (:mod:`acroplan.core.optimal`) that starts from ``method``'s plan, and
   through interior waypoints with ``conditions="free"`` then all the intervals together
   (:mod:`acroplan.core.chain`);
4. every result is checked for compliance with the limits exactly (torque limits on the refined
   peak of each joint's torque), and every successful plan is re-simulated independently
   (:mod:`acroplan.core.verify`) unless ``verify=False``.
"""

from __future__ import annotations

from ..core.conditions import CONDITIONS
from ..core.verify import VERIFY_TOL
from .front import plan, solve, warm_up
from .plausible import (DENSE_SEGMENTS, EXACT_EFFORT_SEGMENTS, PLAUSIBLE_FACTOR, beyond_capacity, plausibility,
                        waypoint_rate)
from .request import (DEFAULT_SIZE, MAX_COEFFICIENTS, MAX_DURATION, MAX_LADDER_COEFFICIENTS, MAX_TIME, MIN_DURATION,
                      TIME_LIMIT, PlanRequest)

__all__ = ["plan", "solve", "warm_up", "PlanRequest", "CONDITIONS", "VERIFY_TOL", "DEFAULT_SIZE",
           "MAX_COEFFICIENTS", "MAX_LADDER_COEFFICIENTS", "TIME_LIMIT", "MIN_DURATION", "MAX_DURATION", "MAX_TIME",
           "plausibility", "beyond_capacity", "waypoint_rate", "PLAUSIBLE_FACTOR", "EXACT_EFFORT_SEGMENTS",
           "DENSE_SEGMENTS"]
