"""The generic core: control-affine systems and their planning, knowing no body.

Imports point one way, core <- families <- front doors (:func:`acroplan.plan`, ...) <- I/O; nothing
here imports a family or the I/O layer (a test asserts it).

Modules
-------
:mod:`~acroplan.core.system`
    :class:`ControlAffineSystem`, the interface (structure per instance, a structure key, the
    state space's ``diff``/``retract``), and :class:`Infeasibility`.
:mod:`~acroplan.core.basis`
    Input bases on a segment (:class:`Legendre`, :class:`Monomial`).
:mod:`~acroplan.core.backend`
    The compiled integrator (heyoka): endpoint map, its Jacobian, dense samples.
:mod:`~acroplan.core.conditions`, :mod:`~acroplan.core.limits`
    Input conditions at the waypoints; limits by name, the constrained solve, exact compliance.
:mod:`~acroplan.core.continuation`
    Path deformation on one segment.
:mod:`~acroplan.core.strategies`
    Interval strategies and their registry.
:mod:`~acroplan.core.optimal`
    Optimal plans: the energy- and torque-optimal strategies (registered on import as
    ``"energy-optimal"`` and ``"torque-optimal"``; ``objective=`` of :func:`acroplan.plan`).
:mod:`~acroplan.core.optimum`, :mod:`~acroplan.core.sqp`, :mod:`~acroplan.core.objectives`
    One interval at one basis size; the SQP; the costs and torque limits.
:mod:`~acroplan.core.verify`
    The independent checking integrator (scipy DOP853).
:mod:`~acroplan.core.result`
    :class:`Status`, :class:`PlanResult`, :class:`SegmentResult`, :class:`Samples`.
:mod:`~acroplan.core.lie`, :mod:`~acroplan.core.plotting`
    Symbolic Lie-algebra tools; figures of any plan.
"""

from . import optimal  # noqa: F401  (registers "energy-optimal" and "torque-optimal")
from .basis import InputBasis, Legendre, Monomial, make_basis
from .errors import InvalidInputError
from .limits import Limits
from .optimal import EnergyOptimal, TorqueOptimal
from .result import JointEffort, PlanResult, Samples, SegmentResult, Status
from .strategies import STRATEGIES, Deform, Interval, IntervalOutcome, Strategy, register_strategy
from .system import ControlAffineSystem, Infeasibility, register_torque_model

__all__ = ["ControlAffineSystem", "Deform", "EnergyOptimal", "Infeasibility", "InputBasis", "Interval",
           "IntervalOutcome", "InvalidInputError", "JointEffort", "Legendre", "Limits", "Monomial", "PlanResult",
           "STRATEGIES", "Samples", "SegmentResult", "Status", "Strategy", "TorqueOptimal", "make_basis",
           "register_strategy", "register_torque_model"]
