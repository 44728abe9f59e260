"""Sweeps: one problem varied over a grid or a random sample of its fields, planned point by point.

A sweep is a definition (:class:`Sweep`, immutable, built by :func:`sweep` or read from a TOML file
by :func:`acroplan.io.store.load_sweep`) and a store it is computed into
(:func:`acroplan.io.store.run_sweep`, a zarr store read back with xarray). This module is the front
door: it knows the definition, its points, what is computed at a point and how a chunk of points
is computed by a task on any executor; it writes no file.

Fields
------
A field is a place in the base problem, named as in problem files:

=========================  =====================================================================
``robot.NAME``             a parameter of the body: the physical keys (``torso_mass``, ...,
                           ``angular_momentum``) when the body is given physically, else the
                           system's parameters (``M1``, ``A1``, ``M2``, ``A2``, ``P0``); ``P0`` is
                           also the physical body's ``angular_momentum``; with a system factory,
                           its keywords
``robot.scale``            body size ``s``: lengths x s, masses x s^3, inertias x s^5 (the same
                           density; a body given by lumped parameters: M1, A1, M2, A2 x s^5), applied
                           after the other ``robot`` fields
``plan.times[k]``          waypoint time ``k`` (``k < 0`` counts from the end)
``plan.NAME[k]``           state ``NAME`` at waypoint ``k`` (``plan.theta[-1]``)
``plan.T``                 the flight time: waypoint times stretched from the first so that the
                           last is ``T``
``plan.somersaults``       ``n``: the last value of the first angle state (the acrobot's theta) is
                           the first plus ``2 pi n``
``plan.reach``             ``w`` in [0, 1]: the acrobot's last theta at ``lo + w (hi - lo)``, the
                           exact reachable interval of the last segment under the limits
``plan.conditions``        ``"spline"`` or ``"free"``
``limits.u_max``,          rate and joint limits (as ``plan()``'s keywords)
``limits.NAME_min/_max``
``options.KEY``            any other keyword of :func:`acroplan.plan` (``method``, ``basis``,
                           ``n_coefficients``, ``tol``, ``max_evaluations``, ``verify``, ...)
=========================  =====================================================================

A bare name (``P0``, ``T``, ``scale``, ``u_max``, ``method``, ``theta[-1]``) is resolved to the one
field it can mean; the definition records the full name.

What a point records
--------------------
``status`` (0 success, 1 infeasible, 2 not converged, 3 invalid point; -1 not computed), ``message``
(a code: the CRC-32 of the message with its numbers replaced by ``#``; the store keeps the table),
``effort`` (the integral of the sum of squared inputs over the plan), ``peak_rate`` (max |u|,
exact), ``peak_torque`` (the largest joint torque of the system's torque model, max |tau| on 65 points
per segment; NaN for a system without one: kinematic systems, an acrobot given by lumped
parameters only), ``final_error`` and ``verified_error`` (the worst segment's), ``evaluations``,
``segments``, ``seconds`` (wall time of the point), and each derived quantity asked for. With
``plan=False`` only the derived quantities are computed, and ``status`` is theirs.

Every value but ``seconds`` depends only on the point: a sweep gives the same numbers, bit for bit,
on any executor, in any chunking of the work, and when resumed.
"""

from __future__ import annotations

import dataclasses
import difflib
import functools
import hashlib
import importlib
import inspect
import json
import math
import os
import re
import sys
import time
import types
import traceback
import zlib
from typing import Any, Callable, Mapping

import numpy as np

from .core import backend
from .core.basis import InputBasis
from .core.errors import InvalidInputError
from .core.limits import Limits
from .core.system import ControlAffineSystem, model_torques, torque_model_of
from .core.family import family_of
from .planning import PlanRequest
from .planning import plan as _plan

__all__ = ["Sweep", "sweep", "DERIVED", "STATUS_CODES", "FORMAT", "message_code", "message_template",
           "least_momentum", "run_chunk", "warm_worker", "resolve_field", "from_definition",
           "canonical_json"]

#: Version of the definition's canonical form and of the store's layout.
FORMAT = 1
#: ``status`` codes of a point; -1 marks a point not computed (yet).
STATUS_CODES = {"success": 0, "infeasible": 1, "not_converged": 2, "invalid": 3}
MISSING = -1
#: Points per chunk when the definition does not say (docs/sweeps.md: chunk size advice).
DEFAULT_CHUNK = 1000
#: Torque samples per segment.
TORQUE_SAMPLES = 65

_PLAN_KEYWORDS = tuple(k for k in inspect.signature(_plan).parameters
                       if k not in ("system", "progress", "waypoints"))
_PLAN_DEFAULTS = {k: p.default for k, p in inspect.signature(_plan).parameters.items()
                  if p.default is not inspect.Parameter.empty and p.default is not None}
_LIMIT_KEYWORDS = ("u_max", "state_bounds", "input_bounds", "limits")
_PLAN_SPECIALS = ("T", "somersaults", "reach", "conditions")
_ALIASES = {"angular_momentum": "P0"}  # the physical body's name of the lumped parameter
_INDEXED = re.compile(r"^([A-Za-z_]\w*)\[(-?\d+)\]$")


# ---------------------------------------------------------------------------------------------- messages
_NUMBER = re.compile(r"(?<![A-Za-z_])[-+]?(?:\d+\.\d*|\.\d+|\d+)(?:[eE][-+]?\d+)?|\b(?:nan|inf)\b")


def message_template(message: str) -> str:
    """The message's first line with every number replaced by ``#`` (at most 300 characters)."""
    first = str(message).splitlines()[0] if message else ""
    return _NUMBER.sub("#", first)[:300]


def message_code(message: str) -> tuple[int, str]:
    """``(code, template)``: the CRC-32 of :func:`message_template` (never 0, the fill value)."""
    tpl = message_template(message)
    return (zlib.crc32(tpl.encode("utf-8")) or 1), tpl


# ---------------------------------------------------------------------------------------------- helpers
def _short(value, most: int = 80) -> str:
    r = repr(value)
    return r if len(r) <= most else r[:most - 3] + "..."


def _plain(value, field: str):
    """``value`` as a plain JSON type (numbers, strings, booleans, None, lists, dicts)."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        v = float(value)
        if not math.isfinite(v):
            raise InvalidInputError(field, f"must be finite, got {v}", "give finite numbers")
        return v
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, np.ndarray):
        return [_plain(v, field) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [_plain(v, f"{field}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, Mapping):
        return {str(k): _plain(v, f"{field}.{k}") for k, v in value.items()}
    if isinstance(value, InputBasis):
        return value.name
    raise InvalidInputError(field, f"cannot be recorded in a sweep's definition: {type(value).__name__}",
                            "give numbers, strings, booleans or lists of them (a strategy by its registered name)")


def canonical_json(obj) -> str:
    """The one JSON text of ``obj`` (sorted keys, no spaces, no NaN): what the hash is taken of."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False, ensure_ascii=True)


def _callable_name(fn) -> str:
    mod, qual = getattr(fn, "__module__", None), getattr(fn, "__qualname__", None)
    if not mod or not qual:
        raise InvalidInputError("system", f"a system factory must be a named function, got {_short(fn)}",
                                "define the factory with def at module level")
    return f"{mod}:{qual}"


def _import_callable(name: str):
    mod, _, qual = name.partition(":")
    obj = importlib.import_module(mod)
    for part in qual.split("."):
        obj = getattr(obj, part)
    return obj


# ---------------------------------------------------------------------------------------------- base
def _base_from(base, robot, kwargs) -> tuple[dict, ControlAffineSystem | None, Callable | None]:
    """The canonical base problem ``{"system", "factory", "times", "waypoints", "options"}``, the base
    system (None for a factory) and the factory."""
    factory = None
    if hasattr(base, "plan_kwargs") and callable(base.plan_kwargs) and hasattr(base, "robot"):
        system, kw = base.robot, dict(base.plan_kwargs())
    elif isinstance(base, Mapping):
        kw = dict(base)
        if "system" not in kw:
            raise InvalidInputError("base.system", "is missing", "give the plan() keywords with 'system'")
        system = kw.pop("system")
    elif isinstance(base, ControlAffineSystem):
        system, kw = base, {}
    elif callable(base) and not isinstance(base, type):
        factory, system, kw = base, None, {}
    else:
        raise InvalidInputError("base", f"must be a Problem, a dict of plan() keywords with 'system', a system or a "
                                f"system factory, got {type(base).__name__}", "see docs/sweeps.md")
    kw.update(kwargs)
    if factory is None and isinstance(system, ControlAffineSystem):
        if robot:
            raise InvalidInputError("robot", "applies to a system factory only",
                                    "sweep the body's parameters as robot.NAME fields instead")
        record = _plain(system.to_dict(), "system")
    elif factory is None:
        raise InvalidInputError("system", f"must be a ControlAffineSystem, got {type(system).__name__}",
                                "use for example acroplan.Acrobot(...)")
    else:
        record = {"params": _plain(dict(robot or {}), "robot")}
        system = _build_factory(factory, record["params"], "robot")
        if not isinstance(system, ControlAffineSystem):
            raise InvalidInputError("system", f"the factory returned {type(system).__name__}, not a system",
                                    "return a ControlAffineSystem from the factory")
    bad = [k for k in kw if k not in _PLAN_KEYWORDS and k not in system.state_names
           and not ((k.endswith("_min") or k.endswith("_max")) and k[:-4] in system.state_names)]
    if bad:
        close = difflib.get_close_matches(bad[0], list(_PLAN_KEYWORDS) + list(system.state_names), n=1)
        raise InvalidInputError(bad[0], f"is not a keyword of plan() nor a state of {type(system).__name__}",
                                (f"did you mean {close[0]!r}? " if close else "") + "see acroplan.plan")
    if "progress" in kw:
        raise InvalidInputError("progress", "is the sweep's, not the points'", "give progress to run_sweep")
    method = kw.get("method")
    if method is not None and not isinstance(method, str):
        name = getattr(method, "name", None)
        from .core.strategies import resolve_strategy

        try:
            same = isinstance(name, str) and type(resolve_strategy(name, system)) is type(method)
        except InvalidInputError:
            same = False
        if not same:
            raise InvalidInputError("method", "a strategy object cannot be recorded in a sweep's definition",
                                    "register it (acroplan.register_strategy) and give its name")
        kw["method"] = name
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
    if "times" not in kw:
        raise InvalidInputError("times", "is missing", "give the waypoint times of the base problem")
    waypoints = {name: _plain(np.asarray(kw.pop(name), dtype=float), f"plan.{name}")
                 for name in system.state_names if name in kw}
    times = _plain(np.asarray(kw.pop("times"), dtype=float), "plan.times")
    # plan()'s defaults are left out, so that a definition that states one hashes as one that does not
    options = {k: _plain(v, f"options.{k}") for k, v in kw.items()
               if v is not None and not (k in _PLAN_DEFAULTS and type(v) is type(_PLAN_DEFAULTS[k])
                                         and v == _PLAN_DEFAULTS[k])}
    base_def = {"system": record, "factory": None if factory is None else _callable_name(factory),
                "times": times, "waypoints": waypoints, "options": options}
    return base_def, (None if factory is not None else system), factory


def _build_factory(factory, params, field):
    try:
        return factory(**params)
    except InvalidInputError as e:
        raise InvalidInputError(f"{field}.{e.field}", e.problem, e.fix) from None


def _robot_keys(record: dict) -> tuple[str, ...]:
    if record.get("physical"):
        return tuple(record["physical"])
    return tuple(record.get("params", {}))


# ---------------------------------------------------------------------------------------------- fields
def _field_kind(name: str) -> str:
    """``"number"``, ``"string"`` or ``"any"`` (options: checked by plan()'s validation)."""
    if name.startswith(("robot.", "limits.")):
        return "number"
    if name.startswith("plan."):
        return "string" if name == "plan.conditions" else "number"
    return "any"


def _resolve(name, base: dict, system: ControlAffineSystem, has_factory: bool) -> str:
    """The full name of field ``name`` (``"P0"`` -> ``"robot.P0"``), or InvalidInputError."""
    if not isinstance(name, str) or not name:
        raise InvalidInputError("sweep", f"a field must be a name, got {_short(name)}", "see docs/sweeps.md (fields)")
    states = system.state_names
    rkeys = _robot_keys(base["system"])
    robot = set(rkeys) | {"scale"}
    if base["system"].get("physical") and "angular_momentum" in rkeys:
        robot.add("P0")
    elif "P0" in rkeys:
        robot.add("angular_momentum")
    limit_keys = {"u_max"} | {f"{s}_{e}" for s in system.rate_inputs.values() for e in ("min", "max")}
    option_keys = {k for k in _PLAN_KEYWORDS if k not in ("times", "conditions", "limits", "state_bounds")
                   and k not in limit_keys}

    def plan_ok(rest):
        if rest in _PLAN_SPECIALS:
            return True
        m = _INDEXED.match(rest)
        if m and (m.group(1) == "times" or m.group(1) in states):
            n = len(base["times"])
            return -n <= int(m.group(2)) < n
        return False

    if "." in name:
        table, rest = name.split(".", 1)
        ok = {"robot": lambda r: r in robot or has_factory and r.isidentifier(),
              "plan": plan_ok, "limits": lambda r: r in limit_keys, "options": lambda r: r in option_keys}
        if table not in ok:
            raise InvalidInputError(name, f"is not a field: {table!r} is not a table",
                                    "fields are robot.NAME, plan.NAME, limits.NAME or options.NAME")
        if not ok[table](rest):
            m = _INDEXED.match(rest)
            if table == "plan" and m and (m.group(1) == "times" or m.group(1) in states):
                raise InvalidInputError(name, f"waypoint {m.group(2)} does not exist (the base problem has "
                                        f"{len(base['times'])})", "index the waypoints from 0, or from -1 back")
            known = {"robot": sorted(robot), "plan": ["times[k]"] + [f"{s}[k]" for s in states] + list(_PLAN_SPECIALS),
                     "limits": sorted(limit_keys), "options": sorted(option_keys)}[table]
            close = difflib.get_close_matches(rest, known, n=1, cutoff=0.6)
            raise InvalidInputError(name, "is not a field of the base problem",
                                    (f"did you mean {table}.{close[0]}? " if close else "") +
                                    f"{table} fields are {known}")
        full = name
    else:
        cands = []
        if name in robot:
            cands.append(f"robot.{name}")
        if plan_ok(name):
            cands.append(f"plan.{name}")
        if name in limit_keys:
            cands.append(f"limits.{name}")
        if name in option_keys:
            cands.append(f"options.{name}")
        if not cands:
            known = sorted(robot) + list(_PLAN_SPECIALS) + sorted(limit_keys) + sorted(option_keys) + \
                [f"{s}[k]" for s in ("times",) + tuple(states)]
            close = difflib.get_close_matches(name, known, n=1, cutoff=0.5)
            raise InvalidInputError(name, "is not a field of the base problem",
                                    (f"did you mean {close[0]!r}? " if close else "") +
                                    "fields are robot.NAME, plan.NAME, limits.NAME, options.NAME (docs/sweeps.md)")
        if len(cands) > 1:
            raise InvalidInputError(name, f"may mean {cands}", "give the full name")
        full = cands[0]
    if full == "robot.P0" and base["system"].get("physical"):
        full = "robot.angular_momentum"
    if full.startswith("robot.") and full[6:] in _ALIASES and not base["system"].get("physical"):
        full = "robot." + _ALIASES[full[6:]]
    return full


def _target(full: str, base: dict, system: ControlAffineSystem) -> str:
    """What a field sets, to find two fields setting the same thing."""
    if full.startswith("plan."):
        rest = full[5:]
        n = len(base["times"])
        m = _INDEXED.match(rest)
        if m:
            return f"plan.{m.group(1)}[{int(m.group(2)) % n}]"
        if rest in ("somersaults", "reach"):
            angle = _first_angle(system)
            return f"plan.{angle}[{n - 1}]"
        if rest == "T":
            return f"plan.times[{n - 1}]"
    return full


def _first_angle(system) -> str:
    angles = [s for s in system.state_names if s in system.angle_states]
    if not angles:
        raise InvalidInputError("plan.somersaults", f"{type(system).__name__} has no angle state",
                                "sweep the waypoint itself (plan.NAME[-1])")
    return angles[0]


def _check_value(full: str, v, where: str):
    kind = _field_kind(full)
    if kind == "number":
        if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise InvalidInputError(where, f"must be a number, got {_short(v)}", "give numbers")
        if not math.isfinite(float(v)):
            raise InvalidInputError(where, f"must be finite, got {v}", "give finite numbers")
        return float(v)
    if kind == "string" and not isinstance(v, str):
        raise InvalidInputError(where, f"must be a string, got {_short(v)}", "give for example \"free\"")
    return _plain(v, where)


def _axis_values(spec, where: str) -> list:
    """A grid axis: a list, an array, or ``{start, stop, num[, log]}`` / ``{start, stop, step}``."""
    if isinstance(spec, Mapping):
        keys = set(spec)
        if keys <= {"start", "stop", "num", "log"} and {"start", "stop", "num"} <= keys:
            num = spec["num"]
            if isinstance(num, bool) or not isinstance(num, (int, np.integer)) or num < 1:
                raise InvalidInputError(f"{where}.num", f"must be a whole number >= 1, got {_short(num)}",
                                        "give for example 25")
            a, b = (_check_value("robot.x", spec[k], f"{where}.{k}") for k in ("start", "stop"))
            if spec.get("log"):
                if a <= 0 or b <= 0:
                    raise InvalidInputError(where, "a log axis needs start and stop > 0", "give positive ends")
                return np.geomspace(a, b, int(num)).tolist()
            return np.linspace(a, b, int(num)).tolist()
        if keys == {"start", "stop", "step"}:
            a, b, h = (_check_value("robot.x", spec[k], f"{where}.{k}") for k in ("start", "stop", "step"))
            if not h > 0 or b < a:
                raise InvalidInputError(where, "needs step > 0 and stop >= start", "give for example "
                                        "{start = 0.5, stop = 2, step = 0.25}")
            n = int(math.floor((b - a) / h * (1 + 1e-12))) + 1
            return (a + h * np.arange(n)).tolist()
        raise InvalidInputError(where, f"must be a list of values or {{start, stop, num}}, got keys {sorted(keys)}",
                                "give for example [1, 2, 3] or {start = 0.5, stop = 2, num = 16}")
    if isinstance(spec, (str, bytes)) or not hasattr(spec, "__len__"):
        raise InvalidInputError(where, f"must be a list of values, got {_short(spec)}", "give for example [1, 2, 3]")
    values = list(np.asarray(spec).tolist()) if isinstance(spec, np.ndarray) else list(spec)
    if not values:
        raise InvalidInputError(where, "has no values", "give at least one value")
    return values


_SAMPLE_KINDS = ("uniform", "log", "choices")


def _sample_spec(spec, full: str, where: str) -> dict:
    """``(lo, hi)`` -> uniform; ``{"log": [lo, hi]}``; ``{"uniform": [lo, hi]}``; ``{"choices": [...]}``."""
    if isinstance(spec, Mapping):
        if len(spec) != 1 or next(iter(spec)) not in _SAMPLE_KINDS:
            raise InvalidInputError(where, f"must be [low, high] or one of {{uniform, log, choices}}, got "
                                    f"{_short(dict(spec))}", "give for example [0.5, 3] or {log = [1, 100]}")
        kind, val = next(iter(spec.items()))
    else:
        kind, val = "uniform", spec
    if kind == "choices":
        vals = _axis_values(val, where)
        return {"choices": [_check_value(full, v, f"{where}[{i}]") for i, v in enumerate(vals)]}
    if isinstance(val, (str, bytes)) or not hasattr(val, "__len__") or len(val) != 2:
        raise InvalidInputError(where, f"must be [low, high], got {_short(val)}", "give for example [0.5, 3]")
    if _field_kind(full) == "string":
        raise InvalidInputError(where, "a text field is sampled from choices", "give {choices = [...]}")
    lo, hi = (_check_value("robot.x", v, where) for v in val)
    if not lo < hi:
        raise InvalidInputError(where, f"needs low < high, got [{lo}, {hi}]", "give for example [0.5, 3]")
    if kind == "log" and lo <= 0:
        raise InvalidInputError(where, "a log range needs low > 0", "give positive ends")
    return {kind: [lo, hi]}


# ---------------------------------------------------------------------------------------------- derived
@dataclasses.dataclass(frozen=True)
class Derived:
    """A quantity computed at each point without planning: ``fn(request) -> (value, proof)`` where
    ``proof`` is a message when the value is proven impossible (``value`` NaN)."""

    name: str
    description: str
    units: str
    fn: Callable = dataclasses.field(repr=False)


def least_momentum(req: PlanRequest, end: str = "least") -> tuple[float, str | None]:
    """The least (or, ``end="most"``, the largest) angular momentum P0 for which the acrobot reaches
    the last waypoint's theta from the first one's over the whole flight, interior waypoints aside,
    under the request's limits; signed: negative when theta must decrease. Exact, by the reachable
    set, with no planning: :func:`acroplan.families.acrobot.momentum.least_momentum`.

    Returns ``(P0, None)``, or ``(nan, reason)`` when no momentum works (the limits allow no joint
    motion) or the system is not the acrobot.
    """
    system = req.system
    fam = family_of(system)
    if fam is None or fam.least_momentum is None:
        return math.nan, f"least_P0 applies to the acrobot, not to {type(system).__name__}"
    t, X = req.times, req.waypoints
    b = fam.least_momentum(system, theta0=float(X[0, 0]), thetaT=float(X[-1, 0]), phi0=float(X[0, 1]), phiT=float(X[-1, 1]),
               T=float(t[-1] - t[0]), limits=req.limits, end=end)
    return (b.P0, None) if b.success else (math.nan, b.message)


DERIVED: dict[str, Derived] = {
    "least_P0": Derived("least_P0", "the least angular momentum (signed) that reaches the last waypoint's theta from "
                        "the first's over the whole flight under the limits (exact, by the reachable set; an "
                        "infimum without rate limits)", "units of P0", lambda req: least_momentum(req, "least")),
    "most_P0": Derived("most_P0", "the largest angular momentum (signed) that still reaches it: more turns too fast "
                       "(exact, by the reachable set)", "units of P0", lambda req: least_momentum(req, "most")),
}


# ---------------------------------------------------------------------------------------------- metrics
@functools.cache
def _grid(basis_cls, n):
    """Values, derivatives and integrals of the basis on TORQUE_SAMPLES points of [0, 1]."""
    s = np.linspace(0.0, 1.0, TORQUE_SAMPLES)
    b = basis_cls(n)
    return s, b.matrix(s), b.matrix(s, 1), b.integral(s)


@functools.cache
def _gram(basis_cls, n):
    return basis_cls(n).gram()


def _leg3(c, x):
    """A Legendre series and its first two derivatives at ``x`` in [-1, 1] (plain arithmetic)."""
    p0, p1, d0, d1, e0, e1 = 1.0, x, 0.0, 1.0, 0.0, 0.0
    u, du, ddu = c[0], 0.0, 0.0
    if len(c) > 1:
        u, du = u + c[1] * x, c[1]
    for k in range(1, len(c) - 1):
        p2 = ((2 * k + 1) * x * p1 - k * p0) / (k + 1)
        d2 = d0 + (2 * k + 1) * p1
        e2 = e0 + (2 * k + 1) * d1
        u, du, ddu = u + c[k + 1] * p2, du + c[k + 1] * d2, ddu + c[k + 1] * e2
        p0, p1, d0, d1, e0, e1 = p1, p2, d1, d2, e1, e2
    return u, du, ddu


def _peak_legendre(c, values) -> float:
    """max |u| on [0, 1] of the Legendre series ``c`` (in s), from its ``values`` on the sample grid:
    every discrete local maximum of |u| polished by Newton steps on u' = 0 (the ends are grid
    points), so the result is the exact maximum to rounding."""
    a = np.abs(values)
    best = float(a.max())
    inner = np.nonzero((a[1:-1] >= a[:-2]) & (a[1:-1] >= a[2:]))[0] + 1
    cl = c.tolist()
    h = 2.0 / (len(values) - 1)
    for i in inner:
        x = -1.0 + h * i
        for _ in range(8):
            _, du, ddu = _leg3(cl, x)
            if ddu == 0.0:
                break
            step = du / ddu
            x = min(1.0, max(-1.0, x - step))
            if abs(step) <= 1e-15:
                break
        if abs(x - (-1.0 + h * i)) <= 2 * h:  # stayed in its bump
            best = max(best, abs(_leg3(cl, x)[0]))
    return best


def _metrics(result) -> tuple[float, float, float]:
    """``(effort, peak_rate, peak_torque)`` of a successful plan: the effort exactly (Gram matrix of
    the basis), the peak rate exactly (:func:`_peak_legendre`, or the segment's own extremes for
    another basis), the largest joint torque of the system's torque model
    (:meth:`~acroplan.core.system.ControlAffineSystem.torque_model`, the same torques as
    :meth:`PlanResult.torques <acroplan.core.result.PlanResult.torques>`) on
    :data:`TORQUE_SAMPLES` points per segment; NaN for a system without one."""
    effort, peak, torque = 0.0, 0.0, math.nan
    model, _ = torque_model_of(result.system)
    if model is not None:
        torque = 0.0
    for seg in result.segments:
        basis = result.basis_for(seg)
        T = seg.t1 - seg.t0
        C = seg.basis_coefficients
        legendre = basis.name == "legendre" and type(basis).__module__ == "acroplan.core.basis"
        if legendre:
            effort += T * float(np.sum(C * C / (2.0 * np.arange(C.shape[1]) + 1.0)))
        else:
            G = _gram(type(basis), basis.n)
            effort += T * float(np.einsum("ji,ik,jk->", C, G, C))
        s, V, _, _ = _grid(type(basis), basis.n)
        U = C @ V.T
        if legendre:
            peak = max(peak, max(_peak_legendre(C[j], U[j]) for j in range(C.shape[0])))
        else:
            peak = max(peak, seg.max_abs_u)
        if model is not None:
            tau = model_torques(model, result.system, basis, np.asarray(seg.start, dtype=float), T, C, s)
            torque = max(torque, float(np.max(np.abs(tau))))
    return effort, peak, torque


@functools.lru_cache(maxsize=64)
def _limits_of(phi_min, phi_max, u_max, input_bounds: str) -> Limits:
    shorthand = {k: v for k, v in (("phi_min", phi_min), ("phi_max", phi_max)) if v is not None}
    return Limits(None, json.loads(input_bounds), u_max=u_max, **shorthand)


# ---------------------------------------------------------------------------------------------- the definition
@dataclasses.dataclass(frozen=True, eq=False)
class Sweep:
    """An immutable sweep definition: build it with :func:`sweep` (or
    :func:`acroplan.io.store.load_sweep` from a TOML file).

    Attributes
    ----------
    definition : dict
        The canonical definition (plain JSON types); :attr:`json` is its one text and :attr:`hash`
        its SHA-256, which a store records and checks.
    dims : tuple of str
        The store's dimensions: the grid's fields, or ``("point",)`` for a sample.
    shape, chunks : tuple of int
        The store's shape and chunk shape (each chunk a run of consecutive points).
    """

    definition: dict
    system: ControlAffineSystem | None = dataclasses.field(repr=False)
    factory: Callable | None = dataclasses.field(default=None, repr=False)

    def __post_init__(self):
        object.__setattr__(self, "json", canonical_json(self.definition))
        object.__setattr__(self, "hash", hashlib.sha256(self.json.encode("ascii")).hexdigest())

    def __eq__(self, other):
        return isinstance(other, Sweep) and other.json == self.json

    def __hash__(self):
        return hash(self.json)

    def __repr__(self):
        kind = "grid" if self.is_grid else "sample"
        return (f"Sweep({kind} {dict(zip(self.dims, self.shape))}, {self.size} points in {self.n_chunks} chunk(s) "
                f"of {self.chunk_size}, derived={list(self.derived)}, plan={self.definition['plan']}, "
                f"hash={self.hash[:12]})")

    def __getstate__(self):
        return {"definition": self.definition, "system": self.system, "factory": self.factory}

    def __setstate__(self, state):
        for k, v in state.items():
            object.__setattr__(self, k, v)
        self.__post_init__()

    # -------------------------------------------------------------- layout
    @property
    def is_grid(self) -> bool:
        return self.definition["grid"] is not None

    @property
    def fields(self) -> tuple[str, ...]:
        """The swept fields, in order."""
        src = self.definition["grid"] if self.is_grid else self.definition["sample"]["fields"]
        return tuple(f for f, _ in src)

    @property
    def dims(self) -> tuple[str, ...]:
        return self.fields if self.is_grid else ("point",)

    @functools.cached_property
    def axes(self) -> dict[str, np.ndarray]:
        """The grid's coordinate values per field (empty for a sample)."""
        return {f: np.asarray(v) for f, v in self.definition["grid"]} if self.is_grid else {}

    @property
    def shape(self) -> tuple[int, ...]:
        if self.is_grid:
            return tuple(len(v) for _, v in self.definition["grid"])
        return (int(self.definition["sample"]["n"]),)

    @property
    def size(self) -> int:
        return int(np.prod(self.shape))

    @property
    def chunk_size(self) -> int:
        return int(self.definition["chunk_size"])

    @property
    def derived(self) -> tuple[str, ...]:
        return tuple(self.definition["derived"])

    @property
    def planned(self) -> bool:
        return bool(self.definition["plan"])

    @functools.cached_property
    def chunks(self) -> tuple[int, ...]:
        """Chunk shape: whole trailing dimensions and a slice of one more, at most ``chunk_size``
        points, so that every chunk is a run of consecutive points (C order)."""
        shape, size = self.shape, self.chunk_size
        out = [1] * len(shape)
        trailing = 1
        for d in range(len(shape) - 1, -1, -1):
            if trailing * shape[d] <= size:
                out[d] = shape[d]
                trailing *= shape[d]
            else:
                out[d] = max(1, size // trailing)
                break
        return tuple(out)

    @property
    def chunk_grid(self) -> tuple[int, ...]:
        return tuple(-(-n // c) for n, c in zip(self.shape, self.chunks))

    @property
    def n_chunks(self) -> int:
        return int(np.prod(self.chunk_grid))

    def chunk_region(self, chunk: int) -> tuple[slice, ...]:
        """The store region (one slice per dimension) of chunk number ``chunk``."""
        if not 0 <= chunk < self.n_chunks:
            raise IndexError(f"chunk {chunk} of {self.n_chunks}")
        idx = np.unravel_index(chunk, self.chunk_grid)
        return tuple(slice(i * c, min(n, (i + 1) * c)) for i, c, n in zip(idx, self.chunks, self.shape))

    def chunk_points(self, chunk: int) -> np.ndarray:
        """The flat indices of the chunk's points, in C order (consecutive)."""
        region = self.chunk_region(chunk)
        first = np.ravel_multi_index(tuple(s.start for s in region), self.shape)
        count = int(np.prod([s.stop - s.start for s in region]))
        return np.arange(first, first + count)

    # -------------------------------------------------------------- points
    def values(self, points) -> dict[str, np.ndarray]:
        """The swept fields' values at flat point indices ``points`` (a sample is drawn per point from
        a counter-based generator, so a point's values do not depend on how the work is chunked)."""
        points = np.asarray(points, dtype=np.int64)
        if self.is_grid:
            multi = np.unravel_index(points, self.shape)
            return {f: self.axes[f][i] for f, i in zip(self.fields, multi)}
        smp = self.definition["sample"]
        specs = smp["fields"]
        k = len(specs)
        blocks = (k + 3) // 4
        out = {}
        if points.size > 1 and not np.array_equal(points, np.arange(points[0], points[0] + points.size)):
            parts = [self.values(points[i:i + 1]) for i in range(points.size)]
            return {f: np.concatenate([p[f] for p in parts]) for f in self.fields}
        if points.size:
            bg = np.random.Philox(key=int(smp["seed"]))
            bg.advance(int(points[0]) * blocks)
            raw = bg.random_raw(points.size * blocks * 4).reshape(points.size, blocks * 4)[:, :k]
            U = (raw >> np.uint64(11)).astype(np.float64) * (1.0 / 9007199254740992.0)
        else:
            U = np.zeros((0, k))
        for j, (f, spec) in enumerate(specs):
            (kind, val), = spec.items()
            u = U[:, j]
            if kind == "uniform":
                out[f] = val[0] + u * (val[1] - val[0])
            elif kind == "log":
                out[f] = np.exp(math.log(val[0]) + u * (math.log(val[1]) - math.log(val[0])))
            else:
                out[f] = np.asarray(val)[np.minimum((u * len(val)).astype(np.int64), len(val) - 1)]
        return out

    def point(self, index: int) -> dict[str, Any]:
        """The swept fields' values at point ``index`` (flat, C order), as plain Python values."""
        v = self.values([int(index)])
        return {f: a[0].item() if hasattr(a[0], "item") else a[0] for f, a in v.items()}

    def problem(self, index: int) -> dict[str, Any]:
        """The :func:`acroplan.plan` keywords (with ``"system"``) of point ``index``: what
        :func:`acroplan.plan_many` takes. Raises :class:`InvalidInputError` for an invalid point."""
        return self._problem(self.point(index))

    @functools.cached_property
    def _operations(self) -> tuple:
        """How each swept field sets the point's problem, worked out once:
        ``(field, kind, key, index)`` with kind robot, option, T, times, state, somersaults, reach."""
        n = len(self.definition["base"]["times"])
        ops = []
        for f in self.fields:
            table, rest = f.split(".", 1)
            if table == "robot":
                ops.append((f, "robot", rest, None))
            elif table in ("limits", "options") or rest == "conditions":
                ops.append((f, "option", rest, None))
            elif rest in ("T", "somersaults", "reach"):
                ops.append((f, rest, None, None))
            else:
                m = _INDEXED.match(rest)
                name, k = m.group(1), int(m.group(2)) % n
                ops.append((f, "times" if name == "times" else "state", name, k))
        order = {"robot": 0, "option": 1, "T": 2, "times": 3, "state": 4, "somersaults": 5, "reach": 6}
        return tuple(sorted(ops, key=lambda o: order[o[1]]))

    def _problem(self, values: Mapping[str, Any], cache: dict | None = None) -> dict[str, Any]:
        base = self.definition["base"]
        times = list(base["times"])
        wp = {k: list(v) for k, v in base["waypoints"].items()}
        opts = dict(base["options"])
        ops = self._operations
        robot_vals = {key: values[f] for f, kind, key, _ in ops if kind == "robot"}
        ckey = tuple(robot_vals.items())
        system = cache.get(ckey) if cache is not None else None
        if system is None:
            record = dict(base["system"])
            for part in ("params", "physical"):
                if isinstance(record.get(part), dict):
                    record[part] = dict(record[part])
            system = self._system(record, dict(robot_vals))
            if cache is not None:
                cache.clear()
                cache[ckey] = system
        for f, kind, key, k in ops:
            v = values[f]
            if kind == "option":
                opts[key] = v
            elif kind == "T":
                if not v > 0:
                    raise InvalidInputError("plan.T", f"must be > 0, got {v}", "give a positive flight time")
                t0, t1 = times[0], times[-1]
                times = [t0 + (t - t0) * (v / (t1 - t0)) for t in times]
                times[-1] = t0 + v
            elif kind == "times":
                times[k] = v
            elif kind == "state":
                wp[key][k] = v
            elif kind == "somersaults":
                angle = _first_angle(system)
                wp[angle][-1] = wp[angle][0] + 2.0 * math.pi * v
            elif kind == "reach":
                wp[_first_angle(system)][-1] = self._reach_target(system, times, wp, opts, v)
        return {"system": system, "times": times, **wp, **opts}

    def _system(self, record: dict, robot_vals: dict) -> ControlAffineSystem:
        scale = robot_vals.pop("scale", None)
        if self.factory is not None or self.definition["base"]["factory"]:
            params = {**record["params"], **robot_vals}
            if scale is not None:
                raise InvalidInputError("robot.scale", "applies to a body the sweep builds itself, not to a factory's",
                                        "give the factory a size parameter and sweep robot.NAME")
            factory = self.factory or _import_callable(self.definition["base"]["factory"])
            system = _build_factory(factory, params, "robot")
            if not isinstance(system, ControlAffineSystem):
                raise InvalidInputError("system", f"the factory returned {type(system).__name__}", "return a system")
            return system
        target = record["physical"] if record.get("physical") else record["params"]
        for k, v in robot_vals.items():
            target[k] = v
        if scale is not None:
            if not scale > 0:
                raise InvalidInputError("robot.scale", f"must be > 0, got {scale}", "give a positive size factor")
            for k in list(target):
                if k.endswith("_mass"):
                    target[k] *= scale ** 3
                elif k.endswith("_inertia") or (not record.get("physical") and k in ("M1", "A1", "M2", "A2")):
                    target[k] *= scale ** 5
                elif k.endswith("_length") or k.endswith("_to_joint"):
                    target[k] *= scale
        if record.get("physical"):
            record["params"] = {}
        cls = type(self.system) if self.system is not None else ControlAffineSystem
        try:
            return cls.from_dict(record)
        except InvalidInputError as e:
            raise InvalidInputError(e.field if e.field.startswith("robot.") else f"robot.{e.field}", e.problem,
                                    e.fix) from None
        except (TypeError, ValueError) as e:
            raise InvalidInputError("robot", f"cannot build the body ({type(e).__name__}: {e})",
                                    "check the robot fields") from None

    @staticmethod
    def _reach_target(system, times, wp, opts, w) -> float:
        fam = family_of(system)
        if fam is None or fam.reachable_set is None:
            raise InvalidInputError("plan.reach", f"applies to the acrobot, not to {type(system).__name__}",
                                    "sweep the waypoint itself (plan.NAME[-1])")
        if not 0.0 <= w <= 1.0:
            raise InvalidInputError("plan.reach", f"must lie in [0, 1], got {w}", "give a relative position")
        limits = _limits_of(opts.get("phi_min"), opts.get("phi_max"), opts.get("u_max"),
                            json.dumps(opts.get("input_bounds"), sort_keys=True))
        R = fam.reachable_set(system, theta0=float(wp["theta"][-2]), phi0=float(wp["phi"][-2]), phiT=float(wp["phi"][-1]),
                          T=float(times[-1] - times[-2]), limits=limits)
        if not R.success:
            raise InvalidInputError("plan.reach", R.message, "relax the limits or move the waypoints")
        return R.low + w * (R.high - R.low)

    # -------------------------------------------------------------- what a point records
    def variables(self) -> list[tuple[str, str, Any, dict]]:
        """``(name, dtype, fill value, attributes)`` of every per-point variable of the store."""
        meanings = " ".join(STATUS_CODES)
        out = [("status", "int8", MISSING, {
            "description": "how the point ended: " + ", ".join(f"{v} {k}" for k, v in STATUS_CODES.items()) +
                           "; -1 not computed" + ("" if self.planned else " (the derived quantities' status)"),
            "flag_values": list(STATUS_CODES.values()), "flag_meanings": meanings}),
               ("message", "uint32", 0, {"description": "CRC-32 of the message with its numbers replaced by #; "
                                                        "the table is the store's messages"})]
        if self.planned:
            out += [
                ("effort", "float64", math.nan, {"description": "integral over the plan of the sum of squared inputs",
                                                  "units": "input units^2 x time"}),
                ("peak_rate", "float64", math.nan, {"description": "max |u| over the plan (exact)",
                                                     "units": "input units"}),
                ("peak_torque", "float64", math.nan, {
                    "description": f"the acrobot's max |joint torque| on {TORQUE_SAMPLES} points per segment "
                                   "(NaN for other systems)", "units": "units of M1 / time^2"}),
                ("final_error", "float64", math.nan, {"description": "worst segment's endpoint error (planner)"}),
                ("verified_error", "float64", math.nan, {"description": "worst segment's independently verified "
                                                                        "error (NaN when not verified)"}),
                ("evaluations", "int32", -1, {"description": "endpoint-and-Jacobian evaluations"}),
                ("segments", "int16", -1, {"description": "segments planned"}),
            ]
        out += [(d, "float64", math.nan, {"description": DERIVED[d].description, "units": DERIVED[d].units})
                for d in self.derived]
        out.append(("seconds", "float64", math.nan, {"description": "wall time of the point (plan, metrics, "
                                                                    "derived), seconds; not reproducible"}))
        return out

    def coordinate_dtypes(self) -> dict[str, np.dtype]:
        """The dtype of each swept field's values."""
        if self.is_grid:
            return {f: self.axes[f].dtype for f in self.fields}
        return {f: self.values(np.zeros(1, dtype=np.int64))[f].dtype for f in self.fields}

    def compute(self, chunk: int, points=None) -> dict[str, Any]:
        """Compute chunk ``chunk`` here (what a task does): every point of it, or only ``points``
        (flat indices within it). Returns ``{"chunk", "points", "data": {name: array}, "coords",
        "messages": {code: template}, "pid", "compiled", "seconds"}``."""
        t_start = time.perf_counter()
        idx = self.chunk_points(chunk) if points is None else np.asarray(points, dtype=np.int64)
        values = self.values(idx)
        columns = {f: a.tolist() for f, a in values.items()}
        specs = self.variables()
        data = {name: np.full(idx.size, fill, dtype=dtype) for name, dtype, fill, _ in specs}
        messages: dict[int, str] = {}
        cache: dict = {}
        for j in range(idx.size):
            t0 = time.perf_counter()
            vals = {f: c[j] for f, c in columns.items()}
            self._compute_point(vals, data, j, messages, cache)
            data["seconds"][j] = time.perf_counter() - t0
        return {"chunk": int(chunk), "points": idx, "data": data, "coords": values, "messages": messages,
                "pid": os.getpid(), "compiled": backend.compiled_count(), "seconds": time.perf_counter() - t_start}

    def _compute_point(self, vals, data, j, messages, cache):
        def record(status, message):
            code, tpl = message_code(message)
            messages.setdefault(code, tpl)
            data["status"][j] = STATUS_CODES[status]
            data["message"][j] = code

        try:
            kw = self._problem(vals, cache)
            system = kw.pop("system")
            req = PlanRequest.build(system, **kw) if self.derived else None  # plan() validates its own
        except InvalidInputError as e:
            record("invalid", f"invalid: {e}")
            return
        except Exception as e:  # noqa: BLE001 - one point's bug must not stop the sweep
            record("invalid", f"invalid: unexpected {type(e).__name__}: {e}")
            return
        proof = None
        for name in self.derived:
            try:
                value, why = DERIVED[name].fn(req)
            except Exception as e:  # noqa: BLE001
                value, why = math.nan, f"{name}: unexpected {type(e).__name__}: {e}"
            data[name][j] = value
            proof = proof or (f"{name}: {why}" if why else None)
        if not self.planned:
            record("infeasible" if proof else "success", f"infeasible: {proof}" if proof else "success: derived")
            return
        try:
            res = _plan(system, **kw)
        except InvalidInputError as e:
            record("invalid", f"invalid: {e}")
            return
        except Exception as e:  # noqa: BLE001
            record("not_converged", f"not converged: unexpected {type(e).__name__}: {e}\n{traceback.format_exc()}")
            return
        record(res.status.value, res.message)
        segs = res.segments
        data["segments"][j] = len(segs)
        data["evaluations"][j] = res.evaluations
        if segs:
            data["final_error"][j] = max(s.final_error for s in segs)
            ver = [s.verified_error for s in segs if s.verified_error is not None]
            if ver:
                data["verified_error"][j] = max(ver)
        if res.success:
            data["effort"][j], data["peak_rate"][j], data["peak_torque"][j] = _metrics(res)


def run_chunk(sweep_: Sweep, chunk: int, points=None) -> dict[str, Any]:
    """A task: :meth:`Sweep.compute` in a worker of any executor (the worker compiles the
    integrators on first use and keeps them for its later chunks)."""
    return sweep_.compute(chunk, points)


def warm_worker(sweep_: Sweep) -> tuple[int, int]:
    """A task run once per worker before the chunks: compiles the base system's integrators in that
    worker. Returns ``(pid, compiled_count)``."""
    if sweep_.planned and sweep_.system is not None:
        from .planning import warm_up

        try:
            warm_up(sweep_.system)
        except Exception:  # noqa: BLE001 - only an optimisation
            pass
    return os.getpid(), backend.compiled_count()


# ---------------------------------------------------------------------------------------------- the front door
def sweep(base, *, grid: Mapping | None = None, sample: Mapping | None = None, derived=(), plan: bool = True,
          chunk_size: int | None = None, robot: Mapping | None = None, **plan_kwargs) -> Sweep:
    """Define a sweep: one base problem varied over a grid or a random sample of its fields.

    Parameters
    ----------
    base : Problem, dict, ControlAffineSystem or callable
        The base problem: an :class:`acroplan.Problem`, a dict of :func:`acroplan.plan` keywords
        with ``"system"`` (as :func:`acroplan.plan_many` takes), a system (then give the plan
        keywords here), or a system factory ``factory(**robot) -> ControlAffineSystem`` (a function
        defined at module level) with its default keywords in ``robot``.
    grid : mapping of field to values, optional
        One axis per field, in order: a list of values, or ``{"start", "stop", "num"}`` (with
        ``"log": True`` for geometric spacing) or ``{"start", "stop", "step"}``. Fields are named in
        the module docstring (``"P0"``, ``"T"``, ``"robot.scale"``, ``"theta[-1]"``,
        ``"options.method"``).
    sample : mapping, optional
        Instead of a grid: ``{"n": points, "seed": 0, FIELD: [low, high] | {"log": [low, high]} |
        {"choices": [...]}, ...}``, drawn independently per point.
    derived : sequence of str
        Quantities computed at each point without planning (:data:`DERIVED`): ``"least_P0"``,
        ``"most_P0"``.
    plan : bool
        Plan every point (default); ``False`` computes the derived quantities only.
    chunk_size : int, optional
        Points per chunk (default :data:`DEFAULT_CHUNK`); a chunk is the unit of work, of writing
        and of resuming.
    robot : mapping, optional
        The factory's default keywords (with a factory only).
    **plan_kwargs
        :func:`acroplan.plan` keywords of the base problem (over the base's own).

    Returns
    -------
    Sweep
        Run it with :func:`acroplan.run_sweep` (``acroplan.io.store``).

    Raises
    ------
    InvalidInputError
        Naming the field: unknown or ambiguous fields, bad values, a base problem that
        :func:`acroplan.plan` would refuse.

    Examples
    --------
    >>> import acroplan
    >>> sw = acroplan.sweep(acroplan.examples.load("pike-dive"), grid={"P0": [1.0, 1.25], "T": [9.0, 10.0]},
    ...                     verify=False)
    >>> sw.shape, sw.fields
    ((2, 2), ('robot.P0', 'plan.T'))
    """
    base_def, system, factory = _base_from(base, robot, plan_kwargs)
    probe = system if system is not None else _build_factory(factory, base_def["system"]["params"], "robot")
    has_factory = factory is not None
    if (grid is None) == (sample is None):
        raise InvalidInputError("sweep", "give either grid= or sample=" if grid is None else
                                "give grid= or sample=, not both", "for example grid={\"P0\": [1, 2, 3]}")
    for name in derived if not isinstance(derived, str) else [derived]:
        if name not in DERIVED:
            close = difflib.get_close_matches(str(name), list(DERIVED), n=1)
            raise InvalidInputError("derived", f"unknown derived quantity {_short(name)}",
                                    (f"did you mean {close[0]!r}? " if close else "") + f"known: {sorted(DERIVED)}")
    derived = [derived] if isinstance(derived, str) else list(dict.fromkeys(derived))
    if not isinstance(plan, bool):
        raise InvalidInputError("plan", f"must be True or False, got {_short(plan)}", "give a boolean")
    if not plan and not derived:
        raise InvalidInputError("plan", "is False and no derived quantity is asked for: nothing to compute",
                                "plan the points, or give derived=[\"least_P0\"]")
    size = DEFAULT_CHUNK if chunk_size is None else chunk_size
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or not 1 <= size <= 10_000_000:
        raise InvalidInputError("chunk_size", f"must be a whole number from 1 to 10000000, got {_short(size)}",
                                f"give for example {DEFAULT_CHUNK}")
    # the base problem must be one plan() accepts
    try:
        kw = {**{k: v for k, v in base_def["options"].items()}, **base_def["waypoints"]}
        PlanRequest.build(probe, times=base_def["times"], **kw)
    except InvalidInputError as e:
        raise InvalidInputError(f"base.{e.field}", e.problem, e.fix) from None
    src = grid if grid is not None else {k: v for k, v in dict(sample).items() if k not in ("n", "seed")}
    if not isinstance(src, Mapping) or not src:
        raise InvalidInputError("grid" if grid is not None else "sample", "names no field",
                                "give for example {\"P0\": [1, 2, 3]}")
    entries, seen = [], {}
    for name, spec in src.items():
        full = _resolve(name, base_def, probe, has_factory)
        where = f"{'grid' if grid is not None else 'sample'}.{name}"
        tgt = _target(full, base_def, probe)
        if tgt in seen:
            raise InvalidInputError(where, f"sets {tgt}, which {seen[tgt]} sets too", "sweep one of them")
        seen[tgt] = name
        if full in ("plan.somersaults", "plan.reach"):
            _first_angle(probe)
        if grid is not None:
            vals = _axis_values(spec, where)
            vals = [_check_value(full, v, f"{where}[{i}]") for i, v in enumerate(vals)]
            kinds = {type(v) for v in vals}
            if len(kinds) > 1 and not kinds <= {int, float}:
                raise InvalidInputError(where, "mixes kinds of values", "give values of one kind")
            if len(set(map(repr, vals))) != len(vals):
                raise InvalidInputError(where, "repeats a value", "give each value once")
            entries.append([full, vals])
        else:
            entries.append([full, _sample_spec(spec, full, where)])
    if grid is not None:
        definition_grid, definition_sample = entries, None
    else:
        n, seed = dict(sample).get("n"), dict(sample).get("seed", 0)
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise InvalidInputError("sample.n", f"must be a whole number >= 1, got {_short(n)}", "give for example 1000")
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**63:
            raise InvalidInputError("sample.seed", f"must be a whole number >= 0, got {_short(seed)}",
                                    "give for example 0")
        definition_grid, definition_sample = None, {"n": int(n), "seed": int(seed), "fields": entries}
    definition = {"format": FORMAT, "base": base_def, "grid": definition_grid, "sample": definition_sample,
                  "derived": derived, "plan": plan, "chunk_size": int(size)}
    return Sweep(definition, system, factory)


def resolve_field(base, name: str, *, robot: Mapping | None = None, **plan_kwargs) -> tuple[str, str]:
    """``(full name, kind)`` of field ``name`` of the base problem (:func:`sweep`'s ``base``), kind
    ``"number"``, ``"string"`` or ``"any"``: how a file's value for it is read."""
    base_def, system, factory = _base_from(base, robot, plan_kwargs)
    probe = system if system is not None else _build_factory(factory, base_def["system"]["params"], "robot")
    full = _resolve(name, base_def, probe, factory is not None)
    return full, _field_kind(full)


def from_definition(definition: Mapping, system: ControlAffineSystem | None = None) -> Sweep:
    """The sweep a store's recorded (canonical) definition describes; ``system`` rebuilds the base
    system's type when it is not one the package knows (the acrobot, the small systems)."""
    definition = json.loads(canonical_json(definition))
    if definition.get("format") != FORMAT:
        raise InvalidInputError("format", f"is {definition.get('format')!r}, this acroplan reads {FORMAT}",
                                "use the acroplan version that wrote the store")
    base = definition["base"]
    factory = None
    if base.get("factory"):
        factory = _import_callable(base["factory"])
        sys_ = None
    else:
        sys_ = system or ControlAffineSystem.from_dict(base["system"])
    return Sweep(definition, sys_, factory)


# ---------------------------------------------------------------------------------------------- acroplan.sweep(...)
class _CallableModule(types.ModuleType):
    """``acroplan.sweep`` is this module once it is imported as one; calling it defines a sweep."""

    def __call__(self, *args, **kwargs):
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule
