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
from ..families.acrobot.model import MAX_MAGNITUDE, Acrobot
from ..families.acrobot.reach import reachable_set
from ..planning import PlanRequest

__all__ = ["Problem", "load_problem", "parse_problem", "system_to_dict"]

PHYSICAL_KEYS = ("torso_mass", "leg_mass", "torso_inertia", "leg_inertia", "torso_length", "leg_length",
                 "angular_momentum")
LUMPED_KEYS = ("M1", "A1", "M2", "A2", "P0")
PLAN_KEYS = ("times", "theta", "phi", "conditions")
OPTION_KEYS = ("method", "basis", "n_coefficients", "tol", "max_evaluations", "time_limit", "degrees", "start_rate",
               "end_rate")
#: the physical keys' clearer names (what they are: centre of mass to the joint)
ALIASES = {"torso_com_to_joint": "torso_length", "leg_com_to_joint": "leg_length"}
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

#: Bounds of the arithmetic in problem files: text of at most MAX_TEXT characters, expressions at
#: most MAX_DEPTH deep, exponents at most MAX_EXPONENT in size, every intermediate result real and
#: finite.
MAX_TEXT, MAX_DEPTH, MAX_EXPONENT = 200, 32, 1024

#: Magnitudes the arithmetic carries (values beyond are refused, naming the field and the limit):
#: the body's masses, inertias, lengths and momentum, its lumped parameters M1, A1, M2, A2, P0
#: and u_max (their squares and products must stay finite in double precision); times; angles
#: (beyond 1e6 rad a double no longer resolves the 1e-9 rad that verification asks for).
MAX_BODY, MAX_TIME, MAX_ANGLE = MAX_MAGNITUDE, 1e12, 1e6  # one limit for body values: the model's
#: the smallest M1 (and physical mass or inertia) the arithmetic carries: its square must not vanish
MIN_BODY = 1e-150
#: tolerances the planner can meet; evaluation budgets it can spend
TOL_RANGE, MAX_EVALUATIONS = (1e-15, 1.0), 10_000_000
#: the largest problem file read
MAX_FILE_BYTES = 10_000_000

_TEXT_FIX = "write a number or arithmetic with pi, such as \"-0.5*pi\""


def _short(value, most: int = 80) -> str:
    """A repr of ``value`` cut to ``most`` characters, safe for any nesting and size."""
    import reprlib

    r = reprlib.Repr()
    r.maxlevel, r.maxstring, r.maxother, r.maxlong = 3, most, most, most
    r.maxlist = r.maxtuple = r.maxdict = r.maxset = 6
    try:
        text = r.repr(value)
    except Exception:  # noqa: BLE001 - a repr must never fail a message
        text = f"<{type(value).__name__}>"
    return text if len(text) <= most else text[:most - 3] + "..."


class _Refused(Exception):
    def __init__(self, why: str):
        self.why = why


def _arith(field: str, text: str) -> float:
    """Evaluate arithmetic on numbers and ``pi`` (no names, no calls), bounded: at most
    :data:`MAX_TEXT` characters, :data:`MAX_DEPTH` levels, exponents of at most
    :data:`MAX_EXPONENT`, every intermediate result a finite real number."""
    if len(text) > MAX_TEXT:
        raise InvalidInputError(field, f"is a text of {len(text)} characters, more than {MAX_TEXT}", _TEXT_FIX)

    def real(v):
        if isinstance(v, complex) or not isinstance(v, (int, float)):
            raise _Refused("is not a real number")
        v = float(v)
        if not math.isfinite(v):
            raise _Refused("is not finite (it overflows)")
        return v

    def ev(node, depth):
        if depth > MAX_DEPTH:
            raise _Refused(f"is nested more than {MAX_DEPTH} levels deep")
        if isinstance(node, ast.Expression):
            return ev(node.body, depth + 1)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return real(node.value)
        if isinstance(node, ast.Name) and node.id == "pi":
            return math.pi
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            left, right = ev(node.left, depth + 1), ev(node.right, depth + 1)
            if isinstance(node.op, ast.Pow) and abs(right) > MAX_EXPONENT:
                raise _Refused(f"has an exponent of {right:.6g}, beyond {MAX_EXPONENT}")
            if isinstance(node.op, ast.Pow) and left < 0 and right != int(right):
                raise _Refused("is not a real number (a fractional power of a negative number)")
            try:
                return real(_OPS[type(node.op)](left, right))
            except OverflowError:
                raise _Refused("is not finite (it overflows)") from None
            except ZeroDivisionError:
                raise _Refused("divides by zero") from None
        if isinstance(node, ast.UnaryOp) and type(node.op) in _OPS:
            return real(_OPS[type(node.op)](ev(node.operand, depth + 1)))
        raise ValueError

    try:
        return ev(ast.parse(text.strip(), mode="eval"), 0)
    except _Refused as e:
        raise InvalidInputError(field, f"{_short(text)} {e.why}", _TEXT_FIX) from None
    except (SyntaxError, ValueError, TypeError, ZeroDivisionError, OverflowError, RecursionError, MemoryError):
        raise InvalidInputError(field, f"cannot read {_short(text)} as a number", _TEXT_FIX) from None


def _number(field: str, value, most: float | None = None, what: str = "") -> float:
    """A finite float from a TOML number or arithmetic text; ``|value| <= most`` when given
    (``what`` names the kind of value in the message)."""
    if isinstance(value, bool):
        raise InvalidInputError(field, f"must be a number, got {_short(value)}", "write a number")
    if isinstance(value, str):
        v = _arith(field, value)
    elif isinstance(value, (int, float)):
        try:
            v = float(value)
        except OverflowError:
            digits = int(abs(value).bit_length() * math.log10(2)) + 1
            beyond = f": {what or 'values'} beyond {most:g} in size" if most is not None else ", which"
            raise InvalidInputError(field, f"is an integer of about {digits} digits{beyond} are more than the "
                                    "arithmetic carries", "write a number of sensible size") from None
    else:
        raise InvalidInputError(field, f"must be a number, got {_short(value)}", "write a number")
    if not math.isfinite(v):
        raise InvalidInputError(field, f"must be finite, got {v}", "write a finite number")
    if most is not None and abs(v) > most:
        raise InvalidInputError(field, f"is {v:.3g}: {what or 'values'} beyond {most:g} in size are more than the "
                                "arithmetic carries", "change the units so that the numbers come nearer to 1")
    return v


def _numbers(field: str, value, most: float | None = None, what: str = "",
             most_of=None) -> tuple[float, ...]:
    """A list of numbers; ``most_of(i)`` gives (most, what) per element when the kinds differ."""
    if not isinstance(value, list):
        raise InvalidInputError(field, f"must be a list, got {_short(value)}", "write for example [0, 2, 4]")
    out = []
    for i, v in enumerate(value):
        lim, kind = most_of(i) if most_of is not None else (most, what)
        out.append(_number(f"{field}[{i}]", v, lim, kind))
    return tuple(out)


def _states(field: str, value) -> tuple:
    """Waypoint values of a state: numbers, or ``"free"`` at interior waypoints (``None``)."""
    if isinstance(value, list) and any(v == "free" for v in value):
        kept = _numbers(field, [0.0 if v == "free" else v for v in value], MAX_ANGLE, "angles")
        return tuple(None if v == "free" else k for v, k in zip(value, kept))
    return _numbers(field, value, MAX_ANGLE, "angles")


def _check_keys(table: str, data: dict, allowed) -> None:
    import difflib

    if not isinstance(data, dict):
        raise InvalidInputError(table, f"must be a table, got {_short(data)}", f"write [{table}] with its keys")
    for key in data:
        if key not in allowed:
            name = key if (isinstance(key, str) and len(key) <= 60 and key.isprintable()) else _short(key, 60)
            close = difflib.get_close_matches(name, list(allowed), n=1, cutoff=0.6) if isinstance(key, str) else []
            if table == "<file>":  # a table name at the top of the file
                raise InvalidInputError(f"[{name}]", "is not a known table",
                                        (f"did you mean [{close[0]}]? " if close else "") +
                                        f"known tables are {['[' + a + ']' for a in allowed]}")
            raise InvalidInputError(f"{table}.{name}", "is not a known key",
                                    (f"did you mean {close[0]!r}? " if close else "") + f"known keys are {list(allowed)}")


_BODY = "the body's numbers"


def parse_robot(data: dict) -> Acrobot:
    """An :class:`Acrobot` from a ``[robot]`` table (physical or lumped keys)."""
    if isinstance(data, dict):
        for alias, key in ALIASES.items():
            if alias in data:
                if key in data:
                    raise InvalidInputError(f"robot.{alias}", f"is the same distance as robot.{key}; give one of them",
                                            f"keep {alias} (the clearer name) and drop {key}")
                data = {**{k: v for k, v in data.items() if k != alias}, key: data[alias]}
    _check_keys("robot", data, PHYSICAL_KEYS + LUMPED_KEYS + tuple(ALIASES))
    phys = [k for k in PHYSICAL_KEYS if k in data]
    lump = [k for k in LUMPED_KEYS if k in data]
    if phys and lump:
        raise InvalidInputError("robot", f"mixes physical keys {phys} with lumped keys {lump}",
                                "give either the physical body or the lumped parameters")
    if phys:
        missing = [k for k in PHYSICAL_KEYS if k not in data]
        if missing:
            raise InvalidInputError(f"robot.{missing[0]}", "is missing", f"the physical body needs {list(PHYSICAL_KEYS)}")
        vals = {k: _number(f"robot.{k}", data[k], MAX_BODY, _BODY) for k in PHYSICAL_KEYS}
        for k in ("torso_mass", "leg_mass", "torso_inertia", "leg_inertia"):
            if 0 < vals[k] < MIN_BODY:
                raise InvalidInputError(f"robot.{k}", f"is {vals[k]:.3g}: masses and inertias below {MIN_BODY:g} "
                                        "are less than the arithmetic carries",
                                        "change the units so that the numbers come nearer to 1")
        try:
            robot = Acrobot.from_physical(**vals)
        except InvalidInputError as e:
            field = e.field if e.field.startswith("robot.") else f"robot.{e.field}"
            raise InvalidInputError(field, e.problem, e.fix) from None
        _check_lumped(robot, vals)
        return robot
    missing = [k for k in LUMPED_KEYS if k not in data]
    if missing:
        raise InvalidInputError(f"robot.{missing[0]}", "is missing",
                                f"give the physical body {list(PHYSICAL_KEYS)} or all of {list(LUMPED_KEYS)}")
    vals = {k: _number(f"robot.{k}", data[k], MAX_BODY, _BODY) for k in LUMPED_KEYS}
    try:
        robot = Acrobot(**vals)
    except InvalidInputError as e:
        field = e.field if e.field.startswith("robot.") else f"robot.{e.field}"
        raise InvalidInputError(field, e.problem, e.fix) from None
    _check_lumped(robot, None)
    return robot


def _check_lumped(robot: Acrobot, physical: dict | None) -> None:
    """Refuse lumped parameters the arithmetic cannot carry: |value| > MAX_BODY, or M1 < MIN_BODY
    (its square vanishes). For a physical body the field named is the key behind it (the largest
    length, mass or inertia; the momentum for P0; the smaller inertia for a tiny M1)."""
    fix = "change the units so that the numbers come nearer to 1"
    for k in LUMPED_KEYS:
        v = float(getattr(robot, k))
        if not (math.isfinite(v) and abs(v) <= MAX_BODY):
            why = f"{k} = {v:.3g}, beyond {MAX_BODY:g} in size, more than the arithmetic carries"
            if physical is None:
                raise InvalidInputError(f"robot.{k}", f"is {v:.3g}, beyond {MAX_BODY:g} in size: more than the "
                                        "arithmetic carries", fix)
            big = "angular_momentum" if k == "P0" else max(PHYSICAL_KEYS[:6], key=lambda q: abs(physical[q]))
            raise InvalidInputError(f"robot.{big}", f"is {physical[big]:.3g}, which makes {why}", fix)
    if not robot.M1 >= MIN_BODY:
        if physical is None:
            raise InvalidInputError("robot.M1", f"is {robot.M1:.3g}, below {MIN_BODY:g}: less than the arithmetic "
                                    "carries", fix)
        small = min(("torso_inertia", "leg_inertia"), key=lambda q: physical[q])
        raise InvalidInputError(f"robot.{small}", f"is {physical[small]:.3g}, which makes M1 = {robot.M1:.3g}, below "
                                f"{MIN_BODY:g}, less than the arithmetic carries", fix)


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
    times = _numbers("plan.times", p["times"], MAX_TIME, "times")
    theta, phi = (_states(f"plan.{k}", p[k]) for k in ("theta", "phi"))
    conditions = p.get("conditions", "spline")
    if not isinstance(conditions, str) or conditions not in ("spline", "free"):
        raise InvalidInputError("plan.conditions", f"must be \"spline\" or \"free\", got {_short(conditions)}",
                                "write conditions = \"spline\"")
    opts = data.get("options", {})
    _check_keys("options", opts, OPTION_KEYS)
    options: dict[str, Any] = {}
    lim = data.get("limits", {})
    _check_keys("limits", lim, LIMIT_KEYS)
    for key in LIMIT_KEYS:
        if key in lim:
            options[key] = _number(f"limits.{key}", lim[key], *((MAX_BODY, "rates") if key == "u_max"
                                                                else (MAX_ANGLE, "angles")))
    for key, names in (("method", ("auto", "deform", "flat")), ("basis", ("legendre", "monomial"))):
        if key in opts:
            if not isinstance(opts[key], str) or opts[key] not in names:
                raise InvalidInputError(f"options.{key}", f"must be one of {list(names)}, got {_short(opts[key])}",
                                        f"write {key} = \"{names[0]}\"")
            options[key] = opts[key]
    for key in ("n_coefficients", "max_evaluations"):
        if key in opts:
            v = opts[key]
            most = MAX_EVALUATIONS if key == "max_evaluations" else 1000
            if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= most:
                raise InvalidInputError(f"options.{key}", f"must be a whole number from 1 to {most}, got "
                                        f"{_short(v) if not isinstance(v, int) or abs(v) < 10**30 else 'a huge integer'}",
                                        "write for example 6" if key == "n_coefficients" else "write for example 2000")
            options[key] = v
    if "time_limit" in opts:
        options["time_limit"] = _number("options.time_limit", opts["time_limit"], 1e7, "seconds")
    if "degrees" in opts:
        if not isinstance(opts["degrees"], bool):
            raise InvalidInputError("options.degrees", f"must be true or false, got {_short(opts['degrees'])}",
                                    "write degrees = true")
        options["degrees"] = opts["degrees"]
    for key in ("start_rate", "end_rate"):
        if key in opts:
            options[key] = _number(f"options.{key}", opts[key], MAX_BODY, "rates")
    if "tol" in opts:
        tol = _number("options.tol", opts["tol"])
        if not TOL_RANGE[0] <= tol <= TOL_RANGE[1]:
            raise InvalidInputError("options.tol", f"is {tol:.3g}; tolerances outside [{TOL_RANGE[0]:g}, "
                                    f"{TOL_RANGE[1]:g}] are beyond what double precision can meet or mean",
                                    "write for example 1e-10")
        options["tol"] = tol
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

    if isinstance(data, dict) and "plan" in data and "nilpotent" not in data:
        raise InvalidInputError("[nilpotent]", "is missing: this is a plan file ([plan] table), and `acroplan "
                                "nilpotent` needs a [nilpotent] table with P, Q and degree",
                                "start one with: acroplan init NAME --example chapter4, or plan this file with "
                                "acroplan plan")
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
        vals = _numbers(f"nilpotent.{key}", nil[key],
                        most_of=lambda i: (MAX_TIME, "times") if i == 1 else (MAX_ANGLE, "angles"))
        if len(vals) != 3:
            raise InvalidInputError(f"nilpotent.{key}", f"needs 3 values (phi, t, theta), got {len(vals)}",
                                    "give [phi, t, theta]")
        pts[key] = vals
    degree = nil.get("degree", 3)
    if isinstance(degree, bool) or not isinstance(degree, int) or not 1 <= degree <= 12:
        raise InvalidInputError("nilpotent.degree", "must be a whole number from 1 to 12, got "
                                f"{_short(degree) if not isinstance(degree, int) or abs(degree) < 10**30 else 'a huge integer'}",
                                "write degree = 3")
    method = nil.get("method", "nilpotent")
    if not isinstance(method, str) or method not in ("nilpotent", "flat-y"):
        raise InvalidInputError("nilpotent.method", f"must be \"nilpotent\" or \"flat-y\", got {_short(method)}",
                                "write method = \"nilpotent\"")
    try:
        prob = NilpotentProblem(robot, pts["P"], pts["Q"], degree)
    except InvalidInputError as e:
        field = e.field if e.field.startswith(("robot.", "nilpotent.")) else f"nilpotent.{e.field}"
        raise InvalidInputError(field, e.problem, e.fix) from None
    return prob, method


def load_toml(path) -> dict:
    """Read a TOML file, with errors as :class:`InvalidInputError` naming the file (and the line
    when the parser gives up on a number or a nesting): at most :data:`MAX_FILE_BYTES` bytes,
    regular files only."""
    path = Path(path)
    fix = "give a readable UTF-8 .toml file"
    try:
        if not path.exists():
            raise InvalidInputError(str(path), "no such file", "give the path of a problem .toml file")
        if not path.is_file():
            raise InvalidInputError(str(path), "is not a regular file", fix)
        with open(path, "rb") as f:
            raw = f.read(MAX_FILE_BYTES + 1)
        if len(raw) > MAX_FILE_BYTES:
            raise InvalidInputError(str(path), f"is larger than {MAX_FILE_BYTES // 1_000_000} MB",
                                    "a problem file is a few lines")
        text = raw.decode("utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise InvalidInputError(str(path), f"cannot be read ({e.__class__.__name__})", fix) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InvalidInputError(str(path), f"is not valid TOML ({_one_line(e)})", "fix the syntax (see the README)") \
            from None
    except (RecursionError, MemoryError):
        raise InvalidInputError(str(path), "is nested too deeply to read (arrays or tables within each other)",
                                "write the values flat, as in the README") from None
    except ValueError as e:  # an integer literal beyond Python's digit limit
        where = _line_of_long_number(text)
        raise InvalidInputError(f"{path}{where}", f"holds a number too long to read ({_short(str(e), 60)})",
                                "write numbers of sensible size") from None


def _one_line(e) -> str:
    text = str(e).replace("\n", " ")
    return text if len(text) <= 200 else text[:197] + "..."


def _line_of_long_number(text: str) -> str:
    import re

    for i, line in enumerate(text.splitlines(), 1):
        if re.search(r"[0-9_]{1000,}", line):
            key = re.match(r"\s*([A-Za-z0-9_.\-\"' ]{1,60}?)\s*=", line)
            return f" (line {i}{', key ' + key.group(1).strip() if key else ''})"
    return ""


def load_problem(path) -> Problem:
    """Read and validate a problem file."""
    return parse_problem(load_toml(path), name=Path(path).stem)


def system_to_dict(system) -> dict[str, Any]:
    """The system's own record (:meth:`ControlAffineSystem.to_dict`)."""
    return system.to_dict()
