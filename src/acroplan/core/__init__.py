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

from __future__ import annotations

import importlib

#: The public names, each loaded from its module on first use (PEP 562), so that importing one
#: module of the core (``acroplan.core.errors``, ``acroplan.core.family``: what the command line
#: needs to parse its arguments) does not import the numerics (heyoka, sympy, scipy).
_PUBLIC = {
    "ControlAffineSystem": "system", "Infeasibility": "system", "register_torque_model": "system",
    "InputBasis": "basis", "Legendre": "basis", "Monomial": "basis", "make_basis": "basis",
    "InvalidInputError": "errors", "Limits": "limits",
    "EnergyOptimal": "optimal", "TorqueOptimal": "optimal",
    "JointEffort": "result", "PlanResult": "result", "Samples": "result", "SegmentResult": "result", "Status": "result",
    "STRATEGIES": "strategies", "Deform": "strategies", "Interval": "strategies", "IntervalOutcome": "strategies",
    "Strategy": "strategies", "register_strategy": "strategies",
}

__all__ = sorted(_PUBLIC)


def __getattr__(name: str):
    if name not in _PUBLIC:
        raise AttributeError(f"module 'acroplan.core' has no attribute {name!r}")
    module = importlib.import_module(f"{__name__}.{_PUBLIC[name]}")
    if _PUBLIC[name] == "strategies":
        importlib.import_module(f"{__name__}.optimal")  # registers "energy-optimal" and "torque-optimal"
    value = getattr(module, name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
