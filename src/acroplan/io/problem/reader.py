"""Reading problem files: the tables every file shares (``[plan]``, ``[options]``,
``[simulate]``), and the system table (``[robot]``, ``[body]``) handed to the family that reads it
(:mod:`acroplan.core.family`)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from ...core.errors import InvalidInputError
from ...core.family import ReadContext, families, family_of, reader_for
from ...core.files import allowed_folders
from ...core.validate import MAX_ANGLE, MAX_BODY, MAX_TIME, check_keys, number, numbers, short
from ...core.validate import states as states_field
from ...planning import PlanRequest
from .model import Problem, Simulation
from .options import OPTION_PARSERS

__all__ = ["parse_problem", "parse_simulation", "parse_body", "read_system", "system_table", "read_allowed",
           "TABLES"]

#: the tables a problem file may hold
TABLES = ("robot", "body", "plan", "limits", "options", "simulate", "files")


def read_allowed(data: dict, base=None, allowed=()) -> tuple:
    """The folders outside the problem file's own that its files may be read from: ``allowed``
    (the command line's ``--allow-outside``, already resolved) and the file's ``[files] allow``
    (relative to ``base``, the file's folder)."""
    extra = tuple(allowed or ())
    if "files" not in data:
        return extra
    files = data["files"]
    check_keys("files", files, ("allow",))
    if "allow" not in files:
        raise InvalidInputError("files.allow", "is missing", "write allow = [\"../shared\"] (the folders outside the "
                                "problem file's folder that its files may be read from), or drop [files]")
    if not isinstance(files["allow"], list):
        raise InvalidInputError("files.allow", f"must be a list of folders in quotes, got {short(files['allow'])}",
                                "write for example allow = [\"../shared\"]")
    return extra + allowed_folders("files.allow", files["allow"], base)


def system_table(data: dict) -> str:
    """``"robot"`` or ``"body"``: which table describes the system (refusing both and neither)."""
    if "robot" in data and "body" in data:
        raise InvalidInputError("[body]", "is given together with [robot]", "give [robot] for the two-link acrobot "
                                "or [body] for a planar body of any number of links, not both")
    if "robot" not in data and "body" not in data:
        raise InvalidInputError("robot", "table is missing", "add a [robot] table (the two-link acrobot) or a "
                                "[body] table (a planar body, or a human body; see docs/problem-files.md)")
    return "robot" if "robot" in data else "body"


def _degrees(data: dict) -> bool:
    opts = data.get("options")
    return isinstance(opts, dict) and opts.get("degrees") is True


def read_system(data: dict, base=None, allowed=()):
    """The system of a problem file's ``[robot]`` or ``[body]``, read by the family that claims it,
    and the plan() keywords its ``[limits]`` give (``{}`` for a body whose limits are written into
    its link table). Files it names are read from ``base`` (the problem file's folder; the current
    folder when ``None``) or the folders ``allowed`` and ``[files] allow`` name.

    Returns
    -------
    (ControlAffineSystem, dict)
    """
    table = system_table(data)
    return _read_table(table, data[table], data.get("limits", {}), base=base, degrees=_degrees(data),
                       allowed=read_allowed(data, base, allowed))


def _read_table(table: str, tdata, limits, *, base, degrees: bool, allowed=()):
    if isinstance(tdata, dict):  # a typo in a key of no family gets the nearest key of any family
        known = tuple(dict.fromkeys(k for fam in families() if table in fam.tables for k in fam.table_keys))
        if known:
            check_keys(table, tdata, known)
    fam = reader_for(table, tdata)
    if fam is None:
        raise InvalidInputError(table, "is read by no body family", "see docs/problem-files.md for the tables")
    return fam.read(table, tdata, limits, ReadContext(base=None if base is None else Path(base), degrees=degrees,
                                                      allowed=tuple(allowed)))


def parse_body(data: dict, limits: dict | None = None, *, base=None, degrees: bool = False, allowed=()):
    """The body of a ``[body]`` table, read by the family that claims it (a
    :class:`~acroplan.families.planar.model.PlanarBody` from a URDF or link tables, a spatial body
    when ``angular_momentum`` is a list, a human body from ``yeadon`` or ``height`` and ``mass``).

    Parameters
    ----------
    data : dict
        The ``[body]`` table.
    limits : dict, optional
        The file's ``[limits]``, written into a body's link table (``NAME_min``, ``NAME_max``,
        ``u_NAME``, ``u_max``; ``"none"`` drops a limit).
    base : path, optional
        The problem file's folder (default: the current folder): the files ``data`` names are read
        from inside it only.
    degrees : bool
        ``limits`` in degrees and degrees per second.
    allowed : sequence of path
        Folders outside ``base`` that files may be read from (absolute or relative to the current
        folder).

    Returns
    -------
    ControlAffineSystem
    """
    return _read_table("body", data, {} if limits is None else limits, base=base, degrees=degrees,
                       allowed=allowed_folders("allowed", list(allowed), None))[0]


def parse_problem(data: dict, name: str = "", base=None, allowed=()) -> Problem:
    """A :class:`Problem` from the parsed TOML document (``[robot]`` or ``[body]``, ``[plan]``,
    optional ``[limits]``, ``[options]``; a ``[simulate]`` table is left to :func:`parse_simulation`).

    The system table is read by the family that claims it (:func:`acroplan.core.family.reader_for`);
    ``base`` is the problem file's folder, from which the files a ``[body]`` names are read
    (default: the current folder), and only from there or the folders ``allowed`` (resolved paths,
    the command line's ``--allow-outside``) and the file's ``[files] allow`` name.
    """
    check_keys("<file>", data, TABLES)
    system_table(data)
    if "plan" not in data:
        raise InvalidInputError("plan", "table is missing", "add a [plan] table (see docs/problem-files.md)" +
                                ("; a file with only [simulate] is run by acroplan simulate" if "simulate" in data
                                 else ""))
    system, limit_options = read_system(data, base, allowed_folders("allowed", list(allowed), None))
    fam = family_of(system)
    hooked = fam.waypoint_states if fam is not None and fam.waypoints is not None else ()
    states = system.state_names
    given = tuple(n for n in states if n not in hooked)
    p = data["plan"]
    check_keys("plan", p, ("times",) + given + (fam.waypoint_keys if hooked else ()) + ("conditions",))
    for key in ("times",) + given:
        if key not in p:
            raise InvalidInputError(f"plan.{key}", "is missing", "give one value per waypoint" +
                                    ("" if key == "times" or len(states) <= 2 else
                                     f" (every joint of {list(given)})" if hooked else
                                     f" (every state: {states[0]} and the joints {list(states[1:])})"))
    times = numbers("plan.times", p["times"], MAX_TIME, "times")
    waypoints = {k: states_field(f"plan.{k}", p[k]) for k in given}
    hooked_values = fam.waypoints(system, "plan", p, len(times)) if hooked else {}
    conditions = p.get("conditions", "spline")
    if "conditions" in p and (not isinstance(conditions, str) or conditions not in ("spline", "free")):
        raise InvalidInputError("plan.conditions", f"must be \"spline\" or \"free\", got {short(conditions)}",
                                "write conditions = \"spline\"")
    opts = data.get("options", {})
    check_keys("options", opts, tuple(OPTION_PARSERS))
    options: dict[str, Any] = dict(limit_options)
    for key, parse in OPTION_PARSERS.items():
        if key in opts:
            options[key] = parse(f"options.{key}", opts[key], system)
    if _limits_in_body(system) and options.pop("degrees", False):
        # a body's angles and rates are turned into radians here (its limits were, by its reader),
        # so that the Problem and the plan hold radians whatever the system declares as angles
        waypoints = {k: tuple(None if v is None else math.radians(v) for v in vals) for k, vals in waypoints.items()}
        for key in ("start_rate", "end_rate"):
            if key in options:
                v = options[key]
                options[key] = {k: math.radians(x) for k, x in v.items()} if isinstance(v, dict) else math.radians(v)
    if hooked:  # the hooked states (a spatial attitude: its forms carry their own units), in state order
        waypoints = {k: hooked_values[k] if k in hooked_values else waypoints[k] for k in states}
    if "conditions" not in p and ("objective" in options or "tau_max" in options):
        conditions = None  # plan()'s default for an optimal plan ("free": the end inputs left to the optimiser)
    problem = Problem(system, times, waypoints, conditions, options, name)
    # the meaning (lengths, order, ranges, limits against waypoints) is checked by plan()'s own
    # validation, once, with the fields named as the file names them
    try:
        PlanRequest.build(system, **problem.plan_kwargs())
    except InvalidInputError as e:
        raise InvalidInputError(_file_field(e.field, system), _file_words(e.problem, system),
                                _file_words(e.fix, system)) from None
    return problem


def _limits_in_body(system) -> bool:
    """Whether the system's limits are in its body (a link table, radians), not plan keywords."""
    fam = family_of(system)
    return bool(fam is not None and fam.limits_in_body)


def _limit_names(system) -> tuple[str, ...]:
    """The plan() limit keywords a file gives in ``[limits]`` (none for a body whose limits are in
    its link table)."""
    if _limits_in_body(system):
        return ()
    return ("u_max",) + tuple(f"{s}_{e}" for s in system.rate_inputs.values() for e in ("min", "max"))


def _file_field(field: str, system) -> str:
    """plan()'s field as the problem file names it (``times`` -> ``plan.times``, ``u_max`` ->
    ``limits.u_max``, ``start_rate.u_hip`` -> ``options.start_rate.u_hip``, a spatial body's ``qw``
    -> ``plan.attitude``)."""
    head = field.split(".", 1)[0].split("[", 1)[0]
    fam = family_of(system)
    if fam is not None and fam.waypoints is not None and (head in fam.waypoint_states or head in fam.waypoint_keys):
        return f"plan.{fam.waypoint_keys[0]}" if head in fam.waypoint_states else f"plan.{field}"
    if head in ("times", "conditions") or head in system.state_names:
        return f"plan.{field}"
    if head in _limit_names(system):
        return f"limits.{field}"
    if head in OPTION_PARSERS:
        return f"options.{field}"
    return field


def _file_words(text: str, system) -> str:
    """plan()'s option names in a message, as the file names them (``u_max`` -> ``limits.u_max``)."""
    import re

    names = {**{k: f"limits.{k}" for k in _limit_names(system)}, **{k: f"options.{k}" for k in OPTION_PARSERS}}
    keys = [k for k in names if "_" in k]
    return re.sub(r"(?<![\w.])(" + "|".join(keys) + r")(?!\w)", lambda m: names[m.group(1)], text)


def _spline_rates(times, angles) -> list[np.ndarray]:
    """Per segment, the Legendre coefficients (3) of the rate of the clamped cubic spline through
    ``(times, angles)``: on :math:`[t_k, t_{k+1}]`, :math:`q = c_3\\tau^3 + c_2\\tau^2 + c_1\\tau + c_0`,
    so :math:`u(s) = c_1 + 2c_2 T s + 3c_3 T^2 s^2` with :math:`\\tau = Ts` (exact)."""
    from scipy.interpolate import CubicSpline

    from ...core.basis import Legendre

    cs = CubicSpline(np.asarray(times, dtype=float), np.asarray(angles, dtype=float), bc_type="clamped")
    basis = Legendre(3)
    out = []
    for k in range(len(times) - 1):
        T = times[k + 1] - times[k]
        c3, c2, c1, _ = cs.c[:, k]
        out.append(basis.from_power_s([c1, 2.0 * c2 * T, 3.0 * c3 * T * T]))
    return out


def _coefficient_rows(field: str, value, K: int) -> list[np.ndarray]:
    from ...planning import MAX_COEFFICIENTS

    fix = f"give {K} list(s) of Legendre coefficients, one per segment, for example " + \
          ("[[0.0, 0.5]]" if K == 1 else "[[0.0, 0.5], [0.0, -0.5]]")
    if not isinstance(value, list) or not all(isinstance(r, list) for r in value):
        raise InvalidInputError(field, f"must be a list of lists (one per segment), got {short(value)}", fix)
    if len(value) != K:
        raise InvalidInputError(field, f"has {len(value)} segment(s) but simulate.times has {K}", fix)
    out = []
    for k, row in enumerate(value):
        if not 1 <= len(row) <= MAX_COEFFICIENTS:
            raise InvalidInputError(f"{field}[{k}]", f"has {len(row)} coefficients; give 1 to {MAX_COEFFICIENTS}", fix)
        out.append(np.array(numbers(f"{field}[{k}]", row, MAX_BODY, "rates")))
    return out


def parse_simulation(data: dict, name: str = "", base=None, allowed=()) -> Simulation:
    """A :class:`Simulation` from the parsed TOML document (``[robot]`` or ``[body]`` and
    ``[simulate]``; the module docstring shows the form). ``[plan]`` and ``[options]`` are not
    read; ``[limits]`` of a body go into its link table (recorded, not imposed on the motion)."""
    from ...planning import MAX_DURATION, MIN_DURATION

    check_keys("<file>", data, TABLES)
    system_table(data)
    if "simulate" not in data:
        raise InvalidInputError("simulate", "table is missing", "add a [simulate] table with times, the initial "
                                "state and each joint's motion (docs/problem-files.md); a file with only [plan] is "
                                "run by acroplan plan")
    # a body's [limits] are recorded in it, not imposed on the motion
    system, _ = read_system(data, base, allowed_folders("allowed", list(allowed), None))
    sim = data["simulate"]
    states, inputs = tuple(system.state_names), tuple(system.input_names)
    input_of = {s: u for u, s in system.rate_inputs.items()}
    fam = family_of(system)
    if fam is not None and fam.waypoints is not None:  # hooked initial states (a spatial body's attitude)
        others = tuple(n for n in states if n not in fam.waypoint_states)
        check_keys("simulate", sim, ("times",) + fam.waypoint_keys + others + inputs)
        q0 = fam.waypoints(system, "simulate", sim, None)
        sim = {**{k: v for k, v in sim.items() if k not in fam.waypoint_keys}, **{k: v[0] for k, v in q0.items()}}
    check_keys("simulate", sim, ("times",) + states + inputs)
    if "times" not in sim:
        raise InvalidInputError("simulate.times", "is missing", "give the segment boundaries, for example [0, 1, 2]")
    times = numbers("simulate.times", sim["times"], MAX_TIME, "times")
    if len(times) < 2 or any(b <= a for a, b in zip(times, times[1:])):
        raise InvalidInputError("simulate.times", "must hold at least 2 strictly increasing values",
                                "give for example [0, 1, 2]")
    for k, (a, b) in enumerate(zip(times, times[1:])):
        if not MIN_DURATION <= b - a <= MAX_DURATION:
            raise InvalidInputError("simulate.times", f"segment {k} lasts {b - a:.3g}; durations must lie in "
                                    f"[{MIN_DURATION:g}, {MAX_DURATION:g}]", "rescale the units of time")
    K = len(times) - 1
    initial, rates, motion = {}, {}, {}
    for state in states:
        field = f"simulate.{state}"
        u = input_of.get(state)
        if state not in sim:
            raise InvalidInputError(field, "is missing", "give the initial value of every state" +
                                    ("" if u is None else f"; for a joint, its angles at the times (a spline) or its "
                                     f"initial angle with simulate.{u}"))
        v = sim[state]
        if u is None:
            if isinstance(v, list):
                raise InvalidInputError(field, "is what the simulation computes: give its initial value only",
                                        f"write for example {state} = 0.0")
            initial[state] = number(field, v, MAX_ANGLE, "angles")
        elif isinstance(v, list):
            if u in sim:
                raise InvalidInputError(f"simulate.{u}", f"is given together with the angles of {state}",
                                        f"give {state} = [angles at the times] (a spline through them), or "
                                        f"{state} = its initial angle with {u} = [[coefficients], ...]")
            angles = numbers(field, v, MAX_ANGLE, "angles")
            if len(angles) != len(times):
                raise InvalidInputError(field, f"has {len(angles)} value(s) but simulate.times has {len(times)}",
                                        "give one angle per time (a spline through them), or one number (the "
                                        f"initial angle) with simulate.{u}")
            initial[state] = angles[0]
            rates[u] = _spline_rates(times, angles)
            motion[u] = "spline"
        else:
            initial[state] = number(field, v, MAX_ANGLE, "angles")
            if u not in sim:
                raise InvalidInputError(f"simulate.{u}", "is missing", f"give the Legendre coefficients of {u} per "
                                        f"segment ([[c0, c1, ...], ...]), or {state} as a list of angles, one per time")
            rates[u] = _coefficient_rows(f"simulate.{u}", sim[u], K)
            motion[u] = "coefficients"
    missing = [u for u in inputs if u not in rates]
    if missing:  # an input that is the rate of no state (no such system is read from files today)
        raise InvalidInputError(f"simulate.{missing[0]}", "is missing", "give its Legendre coefficients per segment")
    n = max(len(c) for u in inputs for c in rates[u])
    segs = tuple(np.array([np.pad(rates[u][k], (0, n - len(rates[u][k]))) for u in inputs]) for k in range(K))
    return Simulation(system, times, initial, segs, motion, name)
