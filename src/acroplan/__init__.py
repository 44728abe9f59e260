"""acroplan: motion planning for free-flying articulated bodies and other nonholonomic systems
with drift.

The package is layered, imports pointing one way (``docs/design.md``)::

    acroplan.core       systems, bases, the compiled back end, conditions, limits, path deformation,
                        strategies, verification, results; knows no body
    acroplan.families   acrobot (the dissertation's body), planar (bodies of any number of links),
                        small (unicycle, chained form)
    acroplan.planning, .batch, .simulation, .sweeps  the front doors: plan, plan_many, simulate, sweep
    acroplan.io         problem files, examples, output folders, sweep stores, the command line

The public API, grouped (names load on first use, so ``import acroplan.core`` loads the core alone):

Models
    :class:`Acrobot`, :class:`PhysicalParameters`, :class:`PlanarBody`, :class:`Link`,
    :class:`Unicycle`, :class:`ChainedForm`,
    :class:`ControlAffineSystem` (the interface for your own systems).
Planning
    :func:`plan`, :func:`plan_many`, :func:`simulate`, :func:`warm_up`, :class:`Limits`,
    :class:`PlanResult`, :class:`SegmentResult`, :class:`Samples`, :class:`Status`,
    :class:`Strategy`, :func:`register_strategy`.
Effort and optimal plans
    ``plan(objective="energy" | "torque", tau_max=...)``, :class:`EnergyOptimal`,
    :class:`TorqueOptimal`, :class:`JointEffort` (``PlanResult.effort()``),
    :func:`register_torque_model`.
Feasibility
    :func:`reachable_set` (a :class:`Reach`), :func:`reachable_interval` (deprecated: ``reachable_set(...).interval``).
Input bases
    :class:`Legendre`, :class:`Monomial`.
Problems and results
    :func:`load_problem`, :class:`Problem`, :mod:`acroplan.examples`, :func:`load_result`.
Sweeps
    :func:`sweep` (``acroplan.sweep(...)``, a function: the package is :mod:`acroplan.sweeps`),
    :class:`Sweep`, :class:`SweepPoint`, :func:`run_sweep`, :func:`open_sweep`, :func:`load_sweep`,
    :func:`draw_map`, :class:`SweepSummary` (the store: :mod:`acroplan.io.sweeps`).
Errors
    :class:`InvalidInputError`.
"""

from __future__ import annotations

import importlib

__version__ = "0.2.0"

_PUBLIC = {
    "Acrobot": "acroplan.families.acrobot", "PhysicalParameters": "acroplan.families.acrobot",
    "reachable_interval": "acroplan.families.acrobot", "reachable_set": "acroplan.families.acrobot",
    "Reach": "acroplan.families.acrobot",
    "Unicycle": "acroplan.families.small", "ChainedForm": "acroplan.families.small",
    "PlanarBody": "acroplan.families.planar", "Link": "acroplan.families.planar",
    "ControlAffineSystem": "acroplan.core.system", "Infeasibility": "acroplan.core.system",
    "InputBasis": "acroplan.core.basis", "Legendre": "acroplan.core.basis", "Monomial": "acroplan.core.basis",
    "Limits": "acroplan.core.limits", "InvalidInputError": "acroplan.core.errors",
    "PlanResult": "acroplan.core.result", "SegmentResult": "acroplan.core.result", "Samples": "acroplan.core.result",
    "Status": "acroplan.core.result",
    "Strategy": "acroplan.core.strategies", "register_strategy": "acroplan.core.strategies",
    "EnergyOptimal": "acroplan.core.optimal", "TorqueOptimal": "acroplan.core.optimal",
    "JointEffort": "acroplan.core.result", "register_torque_model": "acroplan.core.system",
    "plan": "acroplan.planning", "warm_up": "acroplan.planning",
    "plan_many": "acroplan.batch", "simulate": "acroplan.simulation",
    "Problem": "acroplan.io.problem", "load_problem": "acroplan.io.problem", "load_result": "acroplan.io.results",
    "sweep": "acroplan.sweeps", "Sweep": "acroplan.sweeps", "SweepPoint": "acroplan.sweeps",
    "run_sweep": "acroplan.io.sweeps", "open_sweep": "acroplan.io.sweeps", "load_sweep": "acroplan.io.sweeps",
    "draw_map": "acroplan.io.sweeps", "SweepSummary": "acroplan.io.sweeps",
}
_MODULES = {"examples": "acroplan.io.examples", "zoo": "acroplan.zoo"}
#: Modules that moved (issues #10, #21): still found under their old name for one release, with a
#: DeprecationWarning naming the new place.
_MOVED = {"nilpotent": "acroplan.families.acrobot.nilpotent", "reach": "acroplan.families.acrobot.reach",
          "flat": "acroplan.families.acrobot.flat", "animation": "acroplan.families.acrobot.drawing",
          "cli": "acroplan.io.cli", "problem": "acroplan.io.problem", "planner": "acroplan.planning"}

__all__ = sorted(_PUBLIC) + sorted(_MODULES)


def __getattr__(name: str):
    if name in _PUBLIC:
        value = getattr(importlib.import_module(_PUBLIC[name]), name)
    elif name in _MODULES:
        value = importlib.import_module(_MODULES[name])
    elif name in _MOVED:
        import warnings

        warnings.warn(f"acroplan.{name} moved to {_MOVED[name]}; import it from there", DeprecationWarning,
                      stacklevel=2)
        return importlib.import_module(_MOVED[name])
    else:
        raise AttributeError(f"module 'acroplan' has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
