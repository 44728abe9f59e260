"""The acrobot's problem-file table ``[robot]``, its ``[limits]``, and what ``acroplan reach`` proves.

``[robot]`` holds either the physical body (``torso_mass``, ``leg_mass``, ``torso_inertia``,
``leg_inertia``, ``torso_length``, ``leg_length``, ``angular_momentum``; ``torso_com_to_joint``
and ``leg_com_to_joint`` are clearer names of the two lengths) or the lumped parameters of text eq.
(3), ``M1, A1, M2, A2, P0``. Its ``[limits]`` (``phi_min``, ``phi_max``, ``u_max``) are
:func:`acroplan.plan` keywords.
"""

from __future__ import annotations

import math

from ...core.errors import InvalidInputError
from ...core.validate import BODY_VALUES, MAX_ANGLE, MAX_BODY, MAX_TIME, MIN_BODY, check_keys, number, numbers, short
from .family import ALIASES, LUMPED_KEYS, PHYSICAL_KEYS  # the keys, named by the family's descriptor
from .model import Acrobot
from .reach import reachable_set

__all__ = ["reachable_set", "parse_robot", "parse_nilpotent", "read", "read_limits", "reach_report", "PHYSICAL_KEYS", "LUMPED_KEYS", "LIMIT_KEYS"]

#: the acrobot's [limits]: plan() keywords
LIMIT_KEYS = ("phi_min", "phi_max", "u_max")


def parse_robot(data: dict) -> Acrobot:
    """An :class:`Acrobot` from a ``[robot]`` table (physical or lumped keys)."""
    if isinstance(data, dict):
        for alias, key in ALIASES.items():
            if alias in data:
                if key in data:
                    raise InvalidInputError(f"robot.{alias}", f"is the same distance as robot.{key}; give one of them",
                                            f"keep {alias} (the clearer name) and drop {key}")
                data = {**{k: v for k, v in data.items() if k != alias}, key: data[alias]}
    check_keys("robot", data, PHYSICAL_KEYS + LUMPED_KEYS + tuple(ALIASES))
    phys = [k for k in PHYSICAL_KEYS if k in data]
    lump = [k for k in LUMPED_KEYS if k in data]
    if phys and lump:
        raise InvalidInputError("robot", f"mixes physical keys {phys} with lumped keys {lump}",
                                "give either the physical body or the lumped parameters")
    if phys:
        missing = [k for k in PHYSICAL_KEYS if k not in data]
        if missing:
            raise InvalidInputError(f"robot.{missing[0]}", "is missing", f"the physical body needs {list(PHYSICAL_KEYS)}")
        vals = {k: number(f"robot.{k}", data[k], MAX_BODY, BODY_VALUES) for k in PHYSICAL_KEYS}
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
    vals = {k: number(f"robot.{k}", data[k], MAX_BODY, BODY_VALUES) for k in LUMPED_KEYS}
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


def read_limits(limits: dict | None, defaults: dict | None = None, *, degrees: bool = False) -> dict:
    """The :func:`acroplan.plan` keywords of an acrobot's ``[limits]`` (``phi_min``, ``phi_max``,
    ``u_max``), over ``defaults`` (a human body's position, in radians: written in the file's
    angles); ``"none"`` drops a default."""
    lim = {} if limits is None else limits
    check_keys("limits", lim, LIMIT_KEYS)
    defaults = defaults or {}
    options = {}
    for key in LIMIT_KEYS:
        if key in lim:
            v = lim[key]
            if defaults and isinstance(v, str) and v.strip().lower() == "none":
                continue  # a human body's position limit dropped
            options[key] = number(f"limits.{key}", v, *((MAX_BODY, "rates") if key == "u_max"
                                                       else (MAX_ANGLE, "angles")))
        elif key in defaults:  # a human body's position (radians; the file's angles may be degrees)
            options[key] = math.degrees(defaults[key]) if degrees else defaults[key]
    return options


def reads(table: str, data) -> bool:
    """The acrobot reads ``[robot]``."""
    return table == "robot"


def read(table: str, data: dict, limits: dict | None, context) -> tuple[Acrobot, dict]:
    """The acrobot of ``[robot]`` and the plan keywords of its ``[limits]``."""
    return parse_robot(data), read_limits(limits, degrees=context.degrees)


def reach_report(problem) -> list[dict]:
    """Per segment, the exact reachable interval of :math:`\\theta(T)` without and with the limits."""
    out = []
    limits = problem.limits
    theta, phi = problem.state("theta"), problem.state("phi")
    for k in range(len(problem.times) - 1):
        T = problem.times[k + 1] - problem.times[k]
        kw = dict(theta0=theta[k], phi0=phi[k], phiT=phi[k + 1], T=T)
        free = reachable_set(problem.system, **kw)
        lim = reachable_set(problem.system, **kw, limits=limits) if limits.active else free
        target = theta[k + 1]
        out.append({
            "index": k, "t0": problem.times[k], "t1": problem.times[k + 1], "theta0": theta[k],
            "phi0": phi[k], "phiT": phi[k + 1], "target_theta": target,
            "interval": [free.low, free.high], "interval_closed": free.closed,
            "interval_with_limits": None if not lim.success else [lim.low, lim.high],
            "with_limits_closed": lim.closed, "empty_reason": lim.message or None,
            "reachable": lim.contains(target),
        })
    return out


def two_link(problem):
    """The acrobot itself, no offsets: ``(robot, 0, 0, "phi", limits or None)``."""
    limits = problem.limits
    return problem.system, 0.0, 0.0, "phi", (limits if limits.active else None)


def parse_nilpotent(data: dict, name: str = ""):
    """A :class:`~acroplan.families.acrobot.nilpotent.NilpotentProblem` and its method from a TOML document with
    ``[robot]`` and ``[nilpotent]`` (``P``, ``Q`` as (phi, t, theta), ``degree``, ``method``)."""
    from .nilpotent import NilpotentProblem

    if isinstance(data, dict) and "plan" in data and "nilpotent" not in data:
        raise InvalidInputError("[nilpotent]", "is missing: this is a plan file ([plan] table), and `acroplan "
                                "nilpotent` needs a [nilpotent] table with P, Q and degree",
                                "start one with: acroplan init NAME --example chapter4, or plan this file with "
                                "acroplan plan")
    check_keys("<file>", data, ("robot", "nilpotent"))
    for table in ("robot", "nilpotent"):
        if table not in data:
            raise InvalidInputError(table, "table is missing", f"add a [{table}] table (see docs/chapter4.md)")
    robot = parse_robot(data["robot"])
    nil = data["nilpotent"]
    check_keys("nilpotent", nil, ("P", "Q", "degree", "method"))
    pts = {}
    for key in ("P", "Q"):
        if key not in nil:
            raise InvalidInputError(f"nilpotent.{key}", "is missing", "give [phi, t, theta]")
        vals = numbers(f"nilpotent.{key}", nil[key],
                        most_of=lambda i: (MAX_TIME, "times") if i == 1 else (MAX_ANGLE, "angles"))
        if len(vals) != 3:
            raise InvalidInputError(f"nilpotent.{key}", f"needs 3 values (phi, t, theta), got {len(vals)}",
                                    "give [phi, t, theta]")
        pts[key] = vals
    degree = nil.get("degree", 3)
    if isinstance(degree, bool) or not isinstance(degree, int) or not 1 <= degree <= 12:
        raise InvalidInputError("nilpotent.degree", "must be a whole number from 1 to 12, got "
                                f"{short(degree) if not isinstance(degree, int) or abs(degree) < 10**30 else 'a huge integer'}",
                                "write degree = 3")
    method = nil.get("method", "nilpotent")
    if not isinstance(method, str) or method not in ("nilpotent", "flat-y"):
        raise InvalidInputError("nilpotent.method", f"must be \"nilpotent\" or \"flat-y\", got {short(method)}",
                                "write method = \"nilpotent\"")
    try:
        prob = NilpotentProblem(robot, pts["P"], pts["Q"], degree)
    except InvalidInputError as e:
        field = e.field if e.field.startswith(("robot.", "nilpotent.")) else f"nilpotent.{e.field}"
        raise InvalidInputError(field, e.problem, e.fix) from None
    return prob, method
