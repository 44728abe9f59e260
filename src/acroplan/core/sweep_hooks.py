"""What a body family offers sweeps, registered by the family itself.

The sweep front door (:mod:`acroplan.sweeps`) and the store (:mod:`acroplan.io.sweeps`) name no
body family: what only a family knows reaches them through three registries, filled by the
family when it is imported (as strategies and torque models are):

* **derived quantities** (:func:`register_derived`): a number computed at a sweep's point without
  planning, from the point's validated request (the acrobot's ``least_P0``, the least angular
  momentum for the turn, exact by its reachable set);
* **the reachable interval** behind the ``plan.reach`` field (:func:`register_reach`): for a
  system type, the state whose last value the family bounds exactly and the function giving the
  interval over the last segment;
* **system factories by name** (:func:`register_factory`): the only factories a stored sweep
  definition can name and have resolved. A store is data: it never names a module to import
  (issue #25); a factory that is not registered is resolved only from the callables its user
  passes explicitly.

A body's own parameters (what a sweep's ``robot.NAME`` and ``robot.scale`` fields change) are
methods of the system: :meth:`~acroplan.core.system.ControlAffineSystem.robot_parameters`,
:meth:`~acroplan.core.system.ControlAffineSystem.with_robot_parameters` and
:meth:`~acroplan.core.system.ControlAffineSystem.scaled`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Callable, Mapping

from .errors import InvalidInputError
from .family import prepare, prepare_all

__all__ = ["Derived", "DERIVED", "register_derived", "derived_value", "ReachHook", "register_reach", "reach_hook_of",
           "FACTORIES", "register_factory", "factory_name", "resolve_factory"]


# ---------------------------------------------------------------------------------------------- derived
@dataclasses.dataclass(frozen=True)
class Derived:
    """A quantity computed at a sweep's point without planning.

    Attributes
    ----------
    name : str
        The name a sweep asks for (``derived=["least_P0"]``) and the store's variable.
    description : str
        Recorded as the variable's attribute.
    units : str or callable
        Recorded as the variable's attribute: a string, or ``units(system)`` of the sweep's base
        system (``None`` for a factory's sweep) giving one (:meth:`units_for`).
    fn : callable
        ``fn(request) -> (value, proof)``: ``request`` is the point's validated plan request
        (``system``, ``times``, ``waypoints``, ``limits``); ``proof`` is ``None``, or the reason
        (a sentence) when no value exists, ``value`` then NaN.
    applies_to : tuple of type
        The system types it is defined for; at a point of another system the value is NaN with
        that reason.
    """

    name: str
    description: str
    units: str | Callable
    fn: Callable = dataclasses.field(repr=False)
    applies_to: tuple = ()

    def units_for(self, system) -> str:
        """The units of the quantity for sweeps of ``system`` (``None``: not known)."""
        return str(self.units(system)) if callable(self.units) else self.units


#: Derived quantities by name (:func:`register_derived`).
DERIVED: dict[str, Derived] = {}


def register_derived(name: str, fn: Callable, *, description: str, units: str | Callable = "",
                     applies_to=()) -> Derived:
    """Make ``fn`` the derived quantity ``name`` of sweeps.

    Parameters
    ----------
    name : str
        An identifier (the store's variable name).
    fn : callable
        ``fn(request) -> (value, proof)`` (:class:`Derived`).
    description : str
    units : str or callable
        A string, or ``units(system)`` giving one (:class:`Derived`).
    applies_to : type or tuple of type, optional
        The system types it is defined for (default: every system).

    Returns
    -------
    Derived
    """
    if not isinstance(name, str) or not name.isidentifier():
        raise InvalidInputError("name", f"must be an identifier, got {name!r}", "give for example 'least_P0'")
    types = applies_to if isinstance(applies_to, tuple) else (applies_to,)
    entry = Derived(name, description, units, fn, types)
    DERIVED[name] = entry
    return entry


def derived_value(name: str, request) -> tuple[float, str | None]:
    """``(value, proof)`` of the derived quantity ``name`` at a point's request: NaN and the reason
    for a system it does not apply to. An unexpected error propagates (the caller records it)."""
    entry = DERIVED[name]
    system = request.system
    if entry.applies_to and not isinstance(system, entry.applies_to):
        kinds = " or ".join(t.__name__ for t in entry.applies_to)
        return math.nan, f"{name} applies to {kinds}, not to {type(system).__name__}"
    value, proof = entry.fn(request)
    return float(value), proof


# ---------------------------------------------------------------------------------------------- reach
@dataclasses.dataclass(frozen=True)
class ReachHook:
    """The exact interval of one state's last value over the last segment.

    Attributes
    ----------
    state : str
        The state whose last waypoint ``plan.reach`` sets.
    fn : callable
        ``fn(system, start, end, duration, limits) -> (low, high)``: ``start`` and ``end`` map each
        state to its value at the last segment's first and last waypoint (``end[state]`` is the one
        being set, not to be used), ``limits`` an :class:`~acroplan.core.limits.Limits`; raises
        :class:`InvalidInputError` when the interval is empty (the reason).
    """

    state: str
    fn: Callable = dataclasses.field(repr=False)


#: Reachable-interval hooks by system type (:func:`register_reach`).
REACH: dict[type, ReachHook] = {}


def register_reach(system_type: type, state: str, fn: Callable) -> None:
    """Make ``fn`` the exact reachable interval of ``state`` for systems of ``system_type`` (and its
    subclasses): what a sweep's ``plan.reach`` field needs (:class:`ReachHook`)."""
    REACH[system_type] = ReachHook(state, fn)


def reach_hook_of(system) -> ReachHook | None:
    """The :class:`ReachHook` registered for the system's type (or a base of it), or ``None``."""
    prepare(system)
    for cls in type(system).__mro__:
        hook = REACH.get(cls)
        if hook is not None:
            return hook
    return None


# ---------------------------------------------------------------------------------------------- factories
#: System factories by registered name (:func:`register_factory`).
FACTORIES: dict[str, Callable] = {}


def register_factory(name: str, fn: Callable) -> None:
    """Register ``fn(**parameters) -> ControlAffineSystem`` under ``name``: a sweep built on it
    records the name, and a stored definition naming it is resolved to ``fn`` (a store never
    imports code: only registered names and the callables a caller passes are resolved).

    Parameters
    ----------
    name : str
        For example ``"Acrobot.from_physical"``; no ``":"`` (that form is a module path, which is
        recorded for unregistered factories and never resolved).
    fn : callable
    """
    if not isinstance(name, str) or not name or ":" in name:
        raise InvalidInputError("name", f"must be a non-empty name without ':', got {name!r}",
                                "give for example 'MyBody.from_measurements'")
    if not callable(fn):
        raise InvalidInputError("fn", f"must be callable, got {type(fn).__name__}", "give the factory function")
    FACTORIES[name] = fn


def factory_name(fn: Callable) -> str:
    """The name a definition records for ``fn``: its registered name, else ``module:qualname`` (a
    label that is never imported)."""
    for name, known in FACTORIES.items():
        if known is fn or known == fn:
            return name
    mod, qual = getattr(fn, "__module__", None), getattr(fn, "__qualname__", None)
    if not mod or not qual or "<" in qual:
        raise InvalidInputError("system", f"a system factory must be a named function, got {fn!r}"[:160],
                                "define the factory with def at module level (or register it: "
                                "acroplan.sweeps.register_factory)")
    return f"{mod}:{qual}"


def resolve_factory(name: str, given: Mapping[str, Callable] | None = None) -> Callable:
    """The factory a definition names: one the caller passes in ``given`` (by the recorded name),
    else a registered one. Never imports anything.

    Raises
    ------
    InvalidInputError
        Naming ``base.factory`` when neither knows the name.
    """
    given = dict(given or {})
    if name not in given and name not in FACTORIES:
        prepare_all()  # the families register their factories (core.family.Family.setup)
    fn: Any = given.get(name, FACTORIES.get(name))
    if fn is None:
        raise InvalidInputError("base.factory", f"names {name!r}, which is neither a registered factory "
                                f"({sorted(FACTORIES) or 'none registered'}) nor one passed in; a store's definition "
                                "is never imported", f"pass it explicitly: factories={{{name!r}: your_function}}")
    if not callable(fn):
        raise InvalidInputError("factories", f"{name!r} must map to a callable, got {type(fn).__name__}",
                                "give the factory function")
    return fn
