"""Problem files (TOML) and their validation.

A problem file has three tables::

    [robot]            # either the physical body ...
    torso_mass = 40.0          # M  (> 0)
    leg_mass = 20.0            # m  (> 0)
    torso_inertia = 2.5        # J  (> 0), about the torso's centre of mass
    leg_inertia = 1.2          # j  (> 0), about the leg's centre of mass
    torso_length = 0.35        # L  (>= 0), torso centre of mass to joint
    leg_length = 0.45          # l  (>= 0), leg centre of mass to joint
    angular_momentum = 10.0    # P0
    # ... or the lumped parameters M1, A1, M2, A2, P0 of text eq. (3)

    [plan]
    times = [0, 2]
    theta = ["-0.5*pi", "0.9*pi"]   # numbers, or strings of arithmetic with pi
    phi = ["-pi", "-2*pi"]
    conditions = "spline"           # or "free"

    [limits]           # optional
    phi_min = "-2*pi"               # joint limits on phi
    phi_max = "-pi"
    u_max = 20.0                    # |u| <= u_max (rad/s)

    [options]          # optional
    method = "auto"                 # or "deform" (the text's), "flat"
    basis = "legendre"              # or "monomial"
    n_coefficients = 6
    tol = 1e-10
    max_evaluations = 2000

Unknown tables and keys are rejected, so a typo never passes silently.
"""

from __future__ import annotations

import ast
import dataclasses
import math
import operator
import tomllib
from pathlib import Path
from typing import Any

from ..core.errors import InvalidInputError
from ..core.limits import Limits
from ..families.acrobot.model import Acrobot
from ..families.acrobot.reach import reachable_set
from ..planning import PlanRequest

__all__ = ["Problem", "load_problem", "parse_problem", "system_to_dict"]

PHYSICAL_KEYS = ("torso_mass", "leg_mass", "torso_inertia", "leg_inertia", "torso_length", "leg_length",
                 "angular_momentum")
LUMPED_KEYS = ("M1", "A1", "M2", "A2", "P0")
PLAN_KEYS = ("times", "theta", "phi", "conditions")
OPTION_KEYS = ("method", "basis", "n_coefficients", "tol", "max_evaluations")
LIMIT_KEYS = ("phi_min", "phi_max", "u_max")


@dataclasses.dataclass(frozen=True)
class Problem:
    """A validated planning problem: a robot, waypoints and options."""

    robot: Acrobot
    times: tuple[float, ...]
    theta: tuple[float, ...]
    phi: tuple[float, ...]
    conditions: str = "spline"
    options: dict[str, Any] = dataclasses.field(default_factory=dict)
    name: str = ""

    def plan_kwargs(self) -> dict[str, Any]:
        """The keywords of :func:`acroplan.plan` for this problem (all but the system)."""
        return dict(times=self.times, theta=self.theta, phi=self.phi, conditions=self.conditions, **self.options)

    def solve(self, *, verify: bool = True, progress=None):
        """Plan it with :func:`acroplan.plan`."""
        from ..planning import plan

        return plan(self.robot, verify=verify, progress=progress, **self.plan_kwargs())

    @property
    def limits(self):
        """The problem's :class:`~acroplan.reach.Limits`."""
        return Limits(**{k: self.options[k] for k in ("phi_min", "phi_max", "u_max") if k in self.options})

    def reach(self) -> list[dict]:
        """The exact reachable interval of every segment, without and with the limits."""
        out = []
        for k in range(len(self.times) - 1):
            T = self.times[k + 1] - self.times[k]
            kw = dict(theta0=self.theta[k], phi0=self.phi[k], phiT=self.phi[k + 1], T=T)
            free = reachable_set(self.robot, **kw)
            lim = reachable_set(self.robot, **kw, limits=self.limits) if self.limits.active else free
            target = self.theta[k + 1]
            out.append({
                "index": k, "t0": self.times[k], "t1": self.times[k + 1], "theta0": self.theta[k],
                "phi0": self.phi[k], "phiT": self.phi[k + 1], "target_theta": target,
                "interval": [free.low, free.high], "interval_closed": free.closed,
                "interval_with_limits": None if lim.empty else [lim.low, lim.high],
                "with_limits_closed": lim.closed, "empty_reason": lim.reason or None,
                "reachable": lim.contains(target),
            })
        return out


_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.USub: operator.neg, ast.UAdd: operator.pos, ast.Pow: operator.pow}


def _arith(field: str, text: str) -> float:
    """Evaluate arithmetic on numbers and ``pi`` (no names, no calls)."""

    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return float(node.value)
        if isinstance(node, ast.Name) and node.id == "pi":
            return math.pi
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](ev(node.left), ev(node.right))
        if isinstance(node, ast.UnaryOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](ev(node.operand))
        raise ValueError

    try:
        return float(ev(ast.parse(text, mode="eval")))
    except (SyntaxError, ValueError, ZeroDivisionError, OverflowError, RecursionError):
        raise InvalidInputError(field, f"cannot read {text!r} as a number",
                                "write a number or arithmetic with pi, such as \"-0.5*pi\"") from None


def _number(field: str, value) -> float:
    if isinstance(value, bool):
        raise InvalidInputError(field, f"must be a number, got {value!r}", "write a number")
    if isinstance(value, str):
        v = _arith(field, value)
    elif isinstance(value, (int, float)):
        v = float(value)
    else:
        raise InvalidInputError(field, f"must be a number, got {value!r}", "write a number")
    if not math.isfinite(v):
        raise InvalidInputError(field, f"must be finite, got {v}", "write a finite number")
    return v


def _numbers(field: str, value) -> tuple[float, ...]:
    if not isinstance(value, list):
        raise InvalidInputError(field, f"must be a list, got {value!r}", "write for example [0, 2, 4]")
    return tuple(_number(f"{field}[{i}]", v) for i, v in enumerate(value))


def _check_keys(table: str, data: dict, allowed) -> None:
    if not isinstance(data, dict):
        raise InvalidInputError(table, "must be a table", f"write [{table}] with its keys")
    for key in data:
        if key not in allowed:
            raise InvalidInputError(f"{table}.{key}", "is not a known key", f"known keys are {list(allowed)}")


def parse_robot(data: dict) -> Acrobot:
    """An :class:`Acrobot` from a ``[robot]`` table (physical or lumped keys)."""
    _check_keys("robot", data, PHYSICAL_KEYS + LUMPED_KEYS)
    phys = [k for k in PHYSICAL_KEYS if k in data]
    lump = [k for k in LUMPED_KEYS if k in data]
    if phys and lump:
        raise InvalidInputError("robot", f"mixes physical keys {phys} with lumped keys {lump}",
                                "give either the physical body or the lumped parameters")
    if phys:
        missing = [k for k in PHYSICAL_KEYS if k not in data]
        if missing:
            raise InvalidInputError(f"robot.{missing[0]}", "is missing", f"the physical body needs {list(PHYSICAL_KEYS)}")
        vals = {k: _number(f"robot.{k}", data[k]) for k in PHYSICAL_KEYS}
        try:
            return Acrobot.from_physical(**vals)
        except InvalidInputError as e:
            raise InvalidInputError(f"robot.{e.field}", e.problem, e.fix) from None
    missing = [k for k in LUMPED_KEYS if k not in data]
    if missing:
        raise InvalidInputError(f"robot.{missing[0]}", "is missing",
                                f"give the physical body {list(PHYSICAL_KEYS)} or all of {list(LUMPED_KEYS)}")
    vals = {k: _number(f"robot.{k}", data[k]) for k in LUMPED_KEYS}
    try:
        return Acrobot(**vals)
    except InvalidInputError as e:
        raise InvalidInputError(f"robot.{e.field}", e.problem, e.fix) from None


def parse_problem(data: dict, name: str = "") -> Problem:
    """A :class:`Problem` from the parsed TOML document."""
    _check_keys("<file>", data, ("robot", "plan", "limits", "options"))
    for table in ("robot", "plan"):
        if table not in data:
            raise InvalidInputError(table, "table is missing", f"add a [{table}] table (see the README)")
    robot = parse_robot(data["robot"])
    p = data["plan"]
    _check_keys("plan", p, PLAN_KEYS)
    for key in ("times", "theta", "phi"):
        if key not in p:
            raise InvalidInputError(f"plan.{key}", "is missing", "give one value per waypoint")
    times, theta, phi = (_numbers(f"plan.{k}", p[k]) for k in ("times", "theta", "phi"))
    conditions = p.get("conditions", "spline")
    if conditions not in ("spline", "free"):
        raise InvalidInputError("plan.conditions", f"must be \"spline\" or \"free\", got {conditions!r}",
                                "write conditions = \"spline\"")
    opts = data.get("options", {})
    _check_keys("options", opts, OPTION_KEYS)
    options: dict[str, Any] = {}
    lim = data.get("limits", {})
    _check_keys("limits", lim, LIMIT_KEYS)
    for key in LIMIT_KEYS:
        if key in lim:
            options[key] = _number(f"limits.{key}", lim[key])
    for key, names in (("method", ("auto", "deform", "flat")), ("basis", ("legendre", "monomial"))):
        if key in opts:
            if opts[key] not in names:
                raise InvalidInputError(f"options.{key}", f"must be one of {list(names)}, got {opts[key]!r}",
                                        f"write {key} = \"{names[0]}\"")
            options[key] = opts[key]
    for key in ("n_coefficients", "max_evaluations"):
        if key in opts:
            v = opts[key]
            if isinstance(v, bool) or not isinstance(v, int):
                raise InvalidInputError(f"options.{key}", f"must be a whole number >= 1, got {v!r}",
                                        "write for example 6")
            options[key] = v
    if "tol" in opts:
        options["tol"] = _number("options.tol", opts["tol"])
    problem = Problem(robot, times, theta, phi, conditions, options, name)
    # the meaning (lengths, order, ranges, limits against waypoints) is checked by plan()'s own
    # validation, once, with the fields named as the file names them
    try:
        PlanRequest.build(robot, **problem.plan_kwargs())
    except InvalidInputError as e:
        raise InvalidInputError(_FILE_FIELDS.get(e.field, e.field), _file_words(e.problem), _file_words(e.fix)) \
            from None
    return problem


#: plan()'s keywords as a problem file names them
_FILE_FIELDS = {**{k: f"plan.{k}" for k in PLAN_KEYS}, **{k: f"limits.{k}" for k in LIMIT_KEYS},
                **{k: f"options.{k}" for k in OPTION_KEYS}}


def _file_words(text: str) -> str:
    """plan()'s option names in a message, as the file names them (``u_max`` -> ``limits.u_max``)."""
    import re

    keys = [k for k in LIMIT_KEYS + OPTION_KEYS if "_" in k]
    return re.sub(r"(?<![\w.])(" + "|".join(keys) + r")(?!\w)", lambda m: _FILE_FIELDS[m.group(1)], text)


def parse_nilpotent(data: dict, name: str = ""):
    """A :class:`~acroplan.nilpotent.NilpotentProblem` and its method from a TOML document with
    ``[robot]`` and ``[nilpotent]`` (``P``, ``Q`` as (phi, t, theta), ``degree``, ``method``)."""
    from ..families.acrobot.nilpotent import NilpotentProblem

    _check_keys("<file>", data, ("robot", "nilpotent"))
    for table in ("robot", "nilpotent"):
        if table not in data:
            raise InvalidInputError(table, "table is missing", f"add a [{table}] table (see docs/chapter4.md)")
    robot = parse_robot(data["robot"])
    nil = data["nilpotent"]
    _check_keys("nilpotent", nil, ("P", "Q", "degree", "method"))
    pts = {}
    for key in ("P", "Q"):
        if key not in nil:
            raise InvalidInputError(f"nilpotent.{key}", "is missing", "give [phi, t, theta]")
        vals = _numbers(f"nilpotent.{key}", nil[key])
        if len(vals) != 3:
            raise InvalidInputError(f"nilpotent.{key}", f"needs 3 values (phi, t, theta), got {len(vals)}",
                                    "give [phi, t, theta]")
        pts[key] = vals
    degree = nil.get("degree", 3)
    if isinstance(degree, bool) or not isinstance(degree, int):
        raise InvalidInputError("nilpotent.degree", f"must be a whole number, got {degree!r}", "write degree = 3")
    method = nil.get("method", "nilpotent")
    if method not in ("nilpotent", "flat-y"):
        raise InvalidInputError("nilpotent.method", f"must be \"nilpotent\" or \"flat-y\", got {method!r}",
                                "write method = \"nilpotent\"")
    try:
        prob = NilpotentProblem(robot, pts["P"], pts["Q"], degree)
    except InvalidInputError as e:
        raise InvalidInputError(f"nilpotent.{e.field}", e.problem, e.fix) from None
    return prob, method


def load_toml(path) -> dict:
    """Read a TOML file, with errors as :class:`InvalidInputError`."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InvalidInputError(str(path), "no such file", "give the path of a problem .toml file") from None
    except (IsADirectoryError, PermissionError, UnicodeDecodeError) as e:
        raise InvalidInputError(str(path), f"cannot be read ({e.__class__.__name__})",
                                "give a readable UTF-8 .toml file") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InvalidInputError(str(path), f"is not valid TOML ({e})", "fix the syntax (see the README)") from None


def load_problem(path) -> Problem:
    """Read and validate a problem file."""
    return parse_problem(load_toml(path), name=Path(path).stem)


def system_to_dict(system) -> dict[str, Any]:
    """The system's own record (:meth:`ControlAffineSystem.to_dict`)."""
    return system.to_dict()
