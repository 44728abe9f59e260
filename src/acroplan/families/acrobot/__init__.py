"""The free-flying two-link acrobot (the dissertation's body).

* :mod:`~.model`: :class:`Acrobot`, :class:`PhysicalParameters`;
* :mod:`~.reach`: exact reachable sets with joint and rate limits;
* :mod:`~.flat`: the flat output: guesses, the three-piece planner, the strategies ``"flat"`` and
  the acrobot's ``"auto"`` (registered on import);
* :mod:`~.effort`: the joint torque (registered as the physical robot's torque model), the starts
  of the optimal strategies (registered on import);
* :mod:`~.nilpotent`: Chapter 4's nilpotentization;
* :mod:`~.verify`: exact checks with no ODE integrator;
* :mod:`~.zoo`: random bodies and problems for tests and benchmarks;
* :mod:`~.plots`, :mod:`~.drawing`: its figures and animation.
"""

from . import effort  # noqa: F401  (registers the torque model and the optimal strategies' starts)
from . import flat  # noqa: F401  (registers the "flat" strategy)
from .model import Acrobot, PhysicalParameters
from .reach import Reach, reachable_set

__all__ = ["Acrobot", "PhysicalParameters", "Reach", "reachable_set", "reachable_interval"]


def reachable_interval(robot: Acrobot, *, theta0: float, phi0: float, phiT: float, T: float,
                       u_max: float | None = None, phi_min: float | None = None, phi_max: float | None = None):
    """Deprecated: ``reachable_set(...).interval`` (the same keywords), which also says whether the
    ends are attained and, for an impossible request, why.

    Returns
    -------
    (low, high) : tuple of float

    Raises
    ------
    InvalidInputError
        For invalid limits, or when no joint motion satisfies them (the message says why).
    """
    import warnings

    from ...core.errors import InvalidInputError

    warnings.warn("acroplan.reachable_interval is deprecated; use acroplan.reachable_set(...).interval "
                  "(a Reach: success, status, message, closed)", DeprecationWarning, stacklevel=2)
    R = reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T, u_max=u_max, phi_min=phi_min,
                      phi_max=phi_max)
    if not R.success:
        raise InvalidInputError("phi", R.message, "relax the limits or move the waypoints")
    return R.interval
