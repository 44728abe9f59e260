"""acroplan: motion planning for nonholonomic control systems with drift.

The public API, grouped:

Models
    :class:`Acrobot`, :class:`PhysicalParameters`, :class:`Unicycle`,
    :class:`ControlAffineSystem` (the interface for your own systems).
Planning
    :func:`plan` (path deformation through waypoints), :class:`PlanResult`,
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
from .planner import plan
from .problem import Problem, load_problem
from .result import PlanResult, Samples, SegmentResult
from .systems import Acrobot, ControlAffineSystem, Infeasibility, PhysicalParameters, Unicycle

__version__ = "0.1.0"

__all__ = [
    "Acrobot", "ControlAffineSystem", "Infeasibility", "InputBasis", "InvalidInputError", "Legendre",
    "Monomial", "PhysicalParameters", "PlanResult", "Problem", "Samples", "SegmentResult", "Unicycle",
    "examples", "load_problem", "plan", "reachable_interval",
]


def reachable_interval(robot: Acrobot, *, theta0: float, phi0: float, phiT: float, T: float):
    """The exact open interval of :math:`\\theta(T)` reachable by the acrobot (unbounded input).

    See :meth:`Acrobot.reachable_interval`.
    """
    return robot.reachable_interval(theta0=theta0, phi0=phi0, phiT=phiT, T=T)
