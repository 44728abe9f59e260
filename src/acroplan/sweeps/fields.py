"""A sweep's fields: places in the base problem, named as in problem files, and what each sets.

=========================  =====================================================================
``robot.NAME``             a parameter of the body (its :meth:`robot_parameters
                           <acroplan.core.system.ControlAffineSystem.robot_parameters>`: the
                           acrobot's physical keys ``torso_mass``, ..., ``angular_momentum`` when
                           given physically, else ``M1``, ``A1``, ``M2``, ``A2``, ``P0``;
                           ``P0`` and ``angular_momentum`` name each other); with a system
                           factory, its keywords
``robot.scale``            body size ``s`` (:meth:`scaled
                           <acroplan.core.system.ControlAffineSystem.scaled>`), applied after the
                           other ``robot`` fields
``plan.times[k]``          waypoint time ``k`` (``k < 0`` counts from the end)
``plan.NAME[k]``           state ``NAME`` at waypoint ``k`` (``plan.theta[-1]``)
``plan.T``                 the flight time: waypoint times stretched from the first so that the
                           last is ``T``
``plan.somersaults``       ``n``: the last value of the first angle state is the first plus
                           ``2 pi n``
``plan.reach``             ``w`` in [0, 1]: the last value of the state the family bounds exactly
                           (:func:`acroplan.core.sweep_hooks.register_reach`; the acrobot's theta)
                           at ``lo + w (hi - lo)`` in its interval over the last segment
``plan.conditions``        ``"spline"`` or ``"free"``
``limits.u_max``,          rate and joint limits (as ``plan()``'s keywords)
``limits.NAME_min/_max``
``options.KEY``            any other keyword of :func:`acroplan.plan`
=========================  =====================================================================

A bare name (``P0``, ``T``, ``scale``, ``u_max``, ``method``, ``theta[-1]``) is resolved to the one
field it can mean; the definition records the full name.
"""

from __future__ import annotations

import difflib
import math

import numpy as np

from ..core.errors import InvalidInputError
from ..core.sweep_hooks import reach_hook_of
from .keywords import ALIASES, INDEXED, PLAN_SPECIALS, limit_keys, option_keys
from .vocabulary import plain, short

__all__ = ["field_kind", "check_value", "resolve", "target", "first_angle", "reach_state"]


def field_kind(name: str) -> str:
    """``"number"``, ``"string"`` or ``"any"`` (options: checked by plan()'s validation)."""
    if name.startswith(("robot.", "limits.")):
        return "number"
    if name.startswith("plan."):
        return "string" if name == "plan.conditions" else "number"
    return "any"


def check_value(full: str, v, where: str):
    """One value of field ``full``: a finite number (as a float), a string, or a plain value."""
    kind = field_kind(full)
    if kind == "number":
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise InvalidInputError(where, f"must be a number, got {short(v)}", "give numbers")
        if not math.isfinite(float(v)):
            raise InvalidInputError(where, f"must be finite, got {v}", "give finite numbers")
        return float(v)
    if kind == "string" and not isinstance(v, str):
        raise InvalidInputError(where, f"must be a string, got {short(v)}", "give for example \"free\"")
    return plain(v, where)


def first_angle(system) -> str:
    """The first angle state (what ``plan.somersaults`` turns)."""
    angles = [s for s in system.state_names if s in system.angle_states]
    if not angles:
        raise InvalidInputError("plan.somersaults", f"{type(system).__name__} has no angle state",
                                "sweep the waypoint itself (plan.NAME[-1])")
    return angles[0]


def reach_state(system) -> str:
    """The state ``plan.reach`` sets: the one the system's family bounds exactly."""
    hook = reach_hook_of(system)
    if hook is None:
        raise InvalidInputError("plan.reach", f"{type(system).__name__} registers no exact reachable interval",
                                "sweep the waypoint itself (plan.NAME[-1])")
    return hook.state


class _Names:
    """The field names a base problem has, by table."""

    def __init__(self, n_times: int, system, robot_keys, has_factory: bool):
        self.n, self.states, self.has_factory = n_times, tuple(system.state_names), has_factory
        self.robot = set(robot_keys) | {"scale"}
        for a, b in ALIASES.items():
            if a in robot_keys and b not in robot_keys:
                self.robot.add(b)
        self.limits = limit_keys(system)
        self.options = option_keys(system)

    def plan_ok(self, rest: str) -> bool:
        if rest in PLAN_SPECIALS:
            return True
        m = INDEXED.match(rest)
        if m and (m.group(1) == "times" or m.group(1) in self.states):
            return -self.n <= int(m.group(2)) < self.n
        return False

    def ok(self, table: str, rest: str) -> bool:
        if table == "robot":
            return rest in self.robot or self.has_factory and rest.isidentifier()
        if table == "plan":
            return self.plan_ok(rest)
        return rest in (self.limits if table == "limits" else self.options)

    def known(self, table: str) -> list[str]:
        return {"robot": sorted(self.robot),
                "plan": ["times[k]"] + [f"{s}[k]" for s in self.states] + list(PLAN_SPECIALS),
                "limits": sorted(self.limits), "options": sorted(self.options)}[table]


def _dotted(name: str, names: _Names) -> str:
    table, rest = name.split(".", 1)
    if table not in ("robot", "plan", "limits", "options"):
        raise InvalidInputError(name, f"is not a field: {table!r} is not a table",
                                "fields are robot.NAME, plan.NAME, limits.NAME or options.NAME")
    if names.ok(table, rest):
        return name
    m = INDEXED.match(rest)
    if table == "plan" and m and (m.group(1) == "times" or m.group(1) in names.states):
        raise InvalidInputError(name, f"waypoint {m.group(2)} does not exist (the base problem has {names.n})",
                                "index the waypoints from 0, or from -1 back")
    known = names.known(table)
    close = difflib.get_close_matches(rest, known, n=1, cutoff=0.6)
    raise InvalidInputError(name, "is not a field of the base problem",
                            (f"did you mean {table}.{close[0]}? " if close else "") + f"{table} fields are {known}")


def _bare(name: str, names: _Names) -> str:
    cands = [f"{table}.{name}" for table, hit in (("robot", name in names.robot), ("plan", names.plan_ok(name)),
                                                   ("limits", name in names.limits), ("options", name in names.options))
             if hit]
    if not cands:
        known = sorted(names.robot) + list(PLAN_SPECIALS) + sorted(names.limits) + sorted(names.options) + \
            [f"{s}[k]" for s in ("times",) + names.states]
        close = difflib.get_close_matches(name, known, n=1, cutoff=0.5)
        raise InvalidInputError(name, "is not a field of the base problem",
                                (f"did you mean {close[0]!r}? " if close else "") +
                                "fields are robot.NAME, plan.NAME, limits.NAME, options.NAME (docs/sweeps.md)")
    if len(cands) > 1:
        raise InvalidInputError(name, f"may mean {cands}", "give the full name")
    return cands[0]


def resolve(name, n_times: int, system, robot_keys, has_factory: bool) -> str:
    """The full name of field ``name`` (``"P0"`` -> ``"robot.angular_momentum"`` for a body given
    physically), or :class:`InvalidInputError` naming it.

    Parameters
    ----------
    name : str
    n_times : int
        The base problem's number of waypoints.
    system : ControlAffineSystem
        The base system (a factory's system built with its default keywords).
    robot_keys : iterable of str
        The ``robot.*`` names: the system's :meth:`robot_parameters`, or a factory's keywords.
    has_factory : bool
        Any identifier is then a ``robot.*`` field (a keyword of the factory).
    """
    if not isinstance(name, str) or not name:
        raise InvalidInputError("sweep", f"a field must be a name, got {short(name)}", "see docs/sweeps.md (fields)")
    robot_keys = tuple(robot_keys)
    names = _Names(n_times, system, robot_keys, has_factory)
    full = _dotted(name, names) if "." in name else _bare(name, names)
    if full.startswith("robot."):
        key = full[6:]
        if key in ALIASES and key not in robot_keys and ALIASES[key] in robot_keys:
            full = "robot." + ALIASES[key]
    return full


def target(full: str, n_times: int, system) -> str:
    """What a field sets, to find two fields setting the same thing."""
    if full.startswith("plan."):
        rest = full[5:]
        m = INDEXED.match(rest)
        if m:
            return f"plan.{m.group(1)}[{int(m.group(2)) % n_times}]"
        if rest == "somersaults":
            return f"plan.{first_angle(system)}[{n_times - 1}]"
        if rest == "reach":
            return f"plan.{reach_state(system)}[{n_times - 1}]"
        if rest == "T":
            return f"plan.times[{n_times - 1}]"
    return full
