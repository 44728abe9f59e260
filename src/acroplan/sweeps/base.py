"""A sweep's base problem in canonical form: what a definition records of the problem every point
varies (the system's record or its factory's name, waypoint times and values, plan() options)."""

from __future__ import annotations

import difflib
from typing import Callable, Mapping

import numpy as np

from ..core.errors import InvalidInputError
from ..core.limits import Limits
from ..core.strategies import resolve_strategy
from ..core.sweep_hooks import factory_name
from ..core.system import ControlAffineSystem
from .keywords import PLAN_DEFAULTS, PLAN_KEYWORDS
from .vocabulary import plain

__all__ = ["base_from", "build_factory", "robot_keys"]


def _split(base) -> tuple[object, dict, Callable | None]:
    """``(system, plan keywords, factory)`` of any form of base."""
    if hasattr(base, "plan_kwargs") and callable(base.plan_kwargs) and hasattr(base, "robot"):
        return base.robot, dict(base.plan_kwargs()), None
    if isinstance(base, Mapping):
        kw = dict(base)
        if "system" not in kw:
            raise InvalidInputError("base.system", "is missing", "give the plan() keywords with 'system'")
        return kw.pop("system"), kw, None
    if isinstance(base, ControlAffineSystem):
        return base, {}, None
    if callable(base) and not isinstance(base, type):
        return None, {}, base
    raise InvalidInputError("base", f"must be a Problem, a dict of plan() keywords with 'system', a system or a "
                            f"system factory, got {type(base).__name__}", "see docs/sweeps.md")


def build_factory(factory: Callable, params: dict, field: str = "robot") -> ControlAffineSystem:
    """``factory(**params)``, its refusals naming ``robot.NAME``; a system, or InvalidInputError."""
    try:
        system = factory(**params)
    except InvalidInputError as e:
        raise InvalidInputError(f"{field}.{e.field}", e.problem, e.fix) from None
    if not isinstance(system, ControlAffineSystem):
        raise InvalidInputError("system", f"the factory returned {type(system).__name__}, not a system",
                                "return a ControlAffineSystem from the factory")
    return system


def robot_keys(base_def: dict, system: ControlAffineSystem) -> tuple[str, ...]:
    """The ``robot.*`` names: a factory's keywords, or the system's :meth:`robot_parameters`."""
    if base_def["factory"]:
        return tuple(base_def["system"]["params"])
    return tuple(system.robot_parameters())


def _check_keywords(kw: dict, system: ControlAffineSystem) -> None:
    states = system.state_names
    bad = [k for k in kw if k not in PLAN_KEYWORDS and k not in states
           and not ((k.endswith("_min") or k.endswith("_max")) and k[:-4] in states)]
    if bad:
        close = difflib.get_close_matches(bad[0], list(PLAN_KEYWORDS) + list(states), n=1)
        raise InvalidInputError(bad[0], f"is not a keyword of plan() nor a state of {type(system).__name__}",
                                (f"did you mean {close[0]!r}? " if close else "") + "see acroplan.plan")
    if "progress" in kw:
        raise InvalidInputError("progress", "is the sweep's, not the points'", "give progress to run_sweep")


def _method_name(method, system) -> str:
    """A strategy object recorded by its registered name (when that name gives its type)."""
    name = getattr(method, "name", None)
    try:
        same = isinstance(name, str) and type(resolve_strategy(name, system)) is type(method)
    except InvalidInputError:
        same = False
    if not same:
        raise InvalidInputError("method", "a strategy object cannot be recorded in a sweep's definition",
                                "register it (acroplan.register_strategy) and give its name")
    return name


def _flatten_limits(kw: dict) -> None:
    """``limits=Limits(...)`` and ``state_bounds=`` as the keywords NAME_min, NAME_max, u_max, input_bounds."""
    limits = kw.pop("limits", None)
    if limits is not None:
        if not isinstance(limits, Limits):
            raise InvalidInputError("limits", f"must be an acroplan.Limits, got {type(limits).__name__}",
                                    "give Limits(...) or the keywords u_max, NAME_min, NAME_max")
        d = limits.to_dict()
        for name, (lo, hi) in d["state_bounds"].items():
            kw.setdefault(f"{name}_min", lo)
            kw.setdefault(f"{name}_max", hi)
        if d["input_bounds"]:
            kw["input_bounds"] = d["input_bounds"]
        if d["u_max"] is not None:
            kw["u_max"] = d["u_max"]
    for name, pair in dict(kw.pop("state_bounds", None) or {}).items():
        lo, hi = pair
        kw.setdefault(f"{name}_min", lo)
        kw.setdefault(f"{name}_max", hi)


def _system_record(system, factory, robot) -> tuple[dict, ControlAffineSystem]:
    if factory is None and isinstance(system, ControlAffineSystem):
        if robot:
            raise InvalidInputError("robot", "applies to a system factory only",
                                    "sweep the body's parameters as robot.NAME fields instead")
        return plain(system.to_dict(), "system"), system
    if factory is None:
        raise InvalidInputError("system", f"must be a ControlAffineSystem, got {type(system).__name__}",
                                "use for example acroplan.Acrobot(...)")
    record = {"params": plain(dict(robot or {}), "robot")}
    return record, build_factory(factory, record["params"], "robot")


def base_from(base, robot, kwargs) -> tuple[dict, ControlAffineSystem | None, Callable | None, ControlAffineSystem]:
    """The canonical base problem ``{"system", "factory", "times", "waypoints", "options"}``, the base
    system (``None`` for a factory), the factory, and a system to check fields against (the
    factory's, built with its default keywords)."""
    system, kw, factory = _split(base)
    kw.update(kwargs)
    record, probe = _system_record(system, factory, robot)
    _check_keywords(kw, probe)
    method = kw.get("method")
    if method is not None and not isinstance(method, str):
        kw["method"] = _method_name(method, probe)
    _flatten_limits(kw)
    if "times" not in kw:
        raise InvalidInputError("times", "is missing", "give the waypoint times of the base problem")
    waypoints = {name: plain(np.asarray(kw.pop(name), dtype=float), f"plan.{name}")
                 for name in probe.state_names if name in kw}
    times = plain(np.asarray(kw.pop("times"), dtype=float), "plan.times")
    # plan()'s defaults are left out, so that a definition that states one hashes as one that does not
    options = {k: plain(v, f"options.{k}") for k, v in kw.items()
               if v is not None and not (k in PLAN_DEFAULTS and type(v) is type(PLAN_DEFAULTS[k])
                                         and v == PLAN_DEFAULTS[k])}
    base_def = {"system": record, "factory": None if factory is None else factory_name(factory),
                "times": times, "waypoints": waypoints, "options": options}
    return base_def, (None if factory is not None else probe), factory, probe
