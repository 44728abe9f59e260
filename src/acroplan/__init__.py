"""acroplan: motion planning for nonholonomic control systems with drift.

The public API, grouped:

Models
    :class:`Acrobot`, :class:`PhysicalParameters`, :class:`Unicycle`,
    :class:`ControlAffineSystem` (the interface for your own systems).
Planning
    :func:`plan` (path deformation through waypoints), :func:`plan_many` (batches),
    :func:`warm_up` (compile ahead of the first plan),
    :class:`PlanResult`,
    :class:`SegmentResult`, :class:`Samples`.
Feasibility
    :func:`reachable_interval`.
Input bases
    :class:`Legendre`, :class:`Monomial`.
Problems
    :func:`load_problem`, :class:`Problem`, :mod:`acroplan.examples`.
Errors
    :class:`InvalidInputError`.
"""

from . import examples
from ._errors import InvalidInputError
from .basis import InputBasis, Legendre, Monomial
from .batch import plan_many
from .planner import plan, warm_up
from .problem import Problem, load_problem
from .reach import Limits, Reach, reachable_set
from .result import PlanResult, Samples, SegmentResult
from .systems import Acrobot, ControlAffineSystem, Infeasibility, PhysicalParameters, Unicycle

__version__ = "0.1.0"

__all__ = [
    "Acrobot", "ControlAffineSystem", "Infeasibility", "InputBasis", "InvalidInputError", "Legendre",
    "Limits", "Monomial", "PhysicalParameters", "Reach", "reachable_set", "PlanResult", "Problem", "Samples", "SegmentResult", "Unicycle",
    "examples", "load_problem", "plan", "plan_many", "reachable_interval", "warm_up",
]


def reachable_interval(robot: Acrobot, *, theta0: float, phi0: float, phiT: float, T: float,
                       u_max: float | None = None, phi_min: float | None = None, phi_max: float | None = None):
    """The exact interval of :math:`\\theta(T)` reachable by the acrobot.

    Without limits it is open (:meth:`Acrobot.reachable_interval`); with a rate bound ``u_max`` it
    is closed, its ends attained by bang-dwell-bang joint motions; joint limits
    ``phi_min``/``phi_max`` narrow it further (:func:`acroplan.reach.reachable_set`).

    Returns
    -------
    (low, high) : tuple of float

    Raises
    ------
    InvalidInputError
        For invalid limits, or when no joint motion satisfies them (the message says why).
    """
    from .reach import Limits, reachable_set

    R = reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T,
                      limits=Limits(phi_min=phi_min, phi_max=phi_max, u_max=u_max))
    if R.empty:
        raise InvalidInputError("phi", R.reason, "relax the limits or move the waypoints")
    return R.low, R.high
