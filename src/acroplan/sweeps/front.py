"""The front door: :func:`sweep` defines a sweep, one base problem varied over a grid or a random
sample of its fields."""

from __future__ import annotations

import difflib
import math
from typing import Mapping

import numpy as np

from ..core.errors import InvalidInputError
from ..core.sweep_hooks import DERIVED
from ..planning import PlanRequest
from .axes import DEFAULT_CHUNK, MAX_CHUNK_SIZE, MAX_CHUNKS, check_points, parse_axis, parse_sample_field
from .base import base_from, robot_keys
from .definition import Sweep
from .fields import field_kind, first_angle, reach_state, resolve, target
from .vocabulary import FORMAT, short

__all__ = ["sweep", "resolve_field"]


def _derived_names(derived) -> list[str]:
    if isinstance(derived, str):
        derived = [derived]
    if not isinstance(derived, (list, tuple)):
        raise InvalidInputError("derived", f"must be a list of names of derived quantities, got {short(derived)}",
                                f"give for example [\"least_P0\"] (known: {sorted(DERIVED)})")
    for name in derived:
        if not isinstance(name, str) or name not in DERIVED:
            close = difflib.get_close_matches(str(name), list(DERIVED), n=1)
            raise InvalidInputError("derived", f"unknown derived quantity {short(name)}",
                                    (f"did you mean {close[0]!r}? " if close else "") + f"known: {sorted(DERIVED)}")
    return list(dict.fromkeys(derived))


def _scalable(system, where: str) -> None:
    """Refuse ``robot.scale`` for a system that does not say how it scales."""
    try:
        system.scaled(1.0)
    except InvalidInputError as e:
        raise InvalidInputError(where, e.problem, e.fix) from None


def _applicable(derived: list, system) -> None:
    """Refuse a derived quantity the base system's type is not one of (its family registered it for
    its own bodies)."""
    for name in derived:
        types = DERIVED[name].applies_to
        if types and not isinstance(system, types):
            kinds = " or ".join(t.__name__ for t in types)
            raise InvalidInputError("derived", f"{name} applies to {kinds}, not to {type(system).__name__}",
                                    f"known: {sorted(DERIVED)}")


def _check_base(base_def: dict, probe) -> None:
    """The base problem must be one plan() accepts (its refusal named ``base.FIELD``)."""
    try:
        PlanRequest.build(probe, times=base_def["times"], **base_def["options"], **base_def["waypoints"])
    except InvalidInputError as e:
        raise InvalidInputError(f"base.{e.field}", e.problem, e.fix) from None


def _chunk_size(size) -> int:
    size = DEFAULT_CHUNK if size is None else size
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or not 1 <= size <= MAX_CHUNK_SIZE:
        raise InvalidInputError("chunk_size", f"must be a whole number from 1 to {MAX_CHUNK_SIZE}, got {short(size)}",
                                f"give for example {DEFAULT_CHUNK}")
    return int(size)


def _sample_head(sample: Mapping) -> tuple[int, int]:
    n, seed = sample.get("n"), sample.get("seed", 0)
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise InvalidInputError("sample.n", f"must be a whole number >= 1, got {short(n)}", "give for example 1000")
    check_points(int(n), "sample.n")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= seed < 2**63:
        raise InvalidInputError("sample.seed", f"must be a whole number >= 0, got {short(seed)}", "give for example 0")
    return int(n), int(seed)


def _entries(src: Mapping, kind: str, base_def: dict, probe, has_factory: bool) -> list:
    """``[[full name, description], ...]`` of the grid's axes or the sample's fields, checked."""
    if not isinstance(src, Mapping) or not src:
        raise InvalidInputError(kind, "names no field", "give for example {\"P0\": [1, 2, 3]}")
    n_times = len(base_def["times"])
    keys = robot_keys(base_def, probe)
    entries, seen = [], {}
    for name, spec in src.items():
        full = resolve(name, n_times, probe, keys, has_factory)
        where = f"{kind}.{name}"
        if full == "robot.scale" and has_factory:
            raise InvalidInputError(where, "applies to a body the sweep builds itself, not to a factory's",
                                    "give the factory a size parameter and sweep robot.NAME")
        if full == "robot.scale":
            _scalable(probe, where)
        if full == "plan.somersaults":
            first_angle(probe)
        if full == "plan.reach":
            reach_state(probe)
        tgt = target(full, n_times, probe)
        if tgt in seen:
            raise InvalidInputError(where, f"sets {tgt}, which {seen[tgt]} sets too", "sweep one of them")
        seen[tgt] = name
        entries.append([full, parse_axis(spec, full, where) if kind == "grid" else parse_sample_field(spec, full,
                                                                                                      where)])
    return entries


def _check_layout(sw: Sweep, kind: str) -> None:
    check_points(sw.size, kind, " x ".join(map(str, sw.shape)) + " = " if len(sw.shape) > 1 else "")
    if sw.n_chunks > MAX_CHUNKS:
        raise InvalidInputError("chunk_size", f"{sw.size} points in chunks of at most {sw.chunk_size} make "
                                f"{sw.n_chunks} chunks; a store has at most {MAX_CHUNKS}",
                                f"give chunk_size >= {math.ceil(sw.size / MAX_CHUNKS)}")


def sweep(base, *, grid: Mapping | None = None, sample: Mapping | None = None, derived=(), plan: bool = True,
          chunk_size: int | None = None, robot: Mapping | None = None, **plan_kwargs) -> Sweep:
    """Define a sweep: one base problem varied over a grid or a random sample of its fields.

    Parameters
    ----------
    base : Problem, dict, ControlAffineSystem or callable
        The base problem: an :class:`acroplan.Problem`, a dict of :func:`acroplan.plan` keywords
        with ``"system"`` (as :func:`acroplan.plan_many` takes), a system (then give the plan
        keywords here), or a system factory ``factory(**robot) -> ControlAffineSystem`` (a function
        defined at module level, or registered with :func:`acroplan.sweeps.register_factory`) with
        its default keywords in ``robot``.
    grid : mapping of field to values, optional
        One axis per field, in order: a list of values, or ``{"start", "stop", "num"}`` (with
        ``"log": True`` for geometric spacing) or ``{"start", "stop", "step"}``, recorded as given.
        Fields are named in :mod:`acroplan.sweeps.fields` (``"P0"``, ``"T"``, ``"robot.scale"``,
        ``"theta[-1]"``, ``"options.method"``).
    sample : mapping, optional
        Instead of a grid: ``{"n": points, "seed": 0, FIELD: [low, high] | {"log": [low, high]} |
        {"choices": [...]}, ...}``, drawn independently per point.
    derived : sequence of str
        Quantities computed at each point without planning (registered by the body's family,
        :data:`acroplan.core.sweep_hooks.DERIVED`): the acrobot's ``"least_P0"``, ``"most_P0"``.
    plan : bool
        Plan every point (default); ``False`` computes the derived quantities only.
    chunk_size : int, optional
        Points per chunk (default 1000, at most 100000); a chunk is the unit of work, of writing
        and of resuming.
    robot : mapping, optional
        The factory's default keywords (with a factory only).
    **plan_kwargs
        :func:`acroplan.plan` keywords of the base problem (over the base's own).

    Returns
    -------
    Sweep
        Run it with :func:`acroplan.run_sweep`.

    Raises
    ------
    InvalidInputError
        Naming the field: unknown or ambiguous fields, bad values, a base problem that
        :func:`acroplan.plan` would refuse, more than 1e8 points or 1e6 chunks (the number said).

    Examples
    --------
    >>> import acroplan
    >>> sw = acroplan.sweep(acroplan.examples.load("pike-dive"), grid={"P0": [1.0, 1.25], "T": [9.0, 10.0]},
    ...                     verify=False)
    >>> sw.shape, sw.fields
    ((2, 2), ('robot.P0', 'plan.T'))
    """
    base_def, system, factory, probe = base_from(base, robot, plan_kwargs)
    if (grid is None) == (sample is None):
        raise InvalidInputError("sweep", "give either grid= or sample=" if grid is None else
                                "give grid= or sample=, not both", "for example grid={\"P0\": [1, 2, 3]}")
    derived = _derived_names(derived)
    _applicable(derived, probe)
    if not isinstance(plan, bool):
        raise InvalidInputError("plan", f"must be True or False, got {short(plan)}", "give a boolean")
    if not plan and not derived:
        raise InvalidInputError("plan", "is False and no derived quantity is asked for: nothing to compute",
                                "plan the points, or give derived=[\"least_P0\"]")
    size = _chunk_size(chunk_size)
    _check_base(base_def, probe)
    kind = "grid" if grid is not None else "sample"
    if sample is not None and not isinstance(sample, Mapping):
        raise InvalidInputError("sample", f"must be a table, got {short(sample)}", "give {\"n\": 100, FIELD: [lo, hi]}")
    head = _sample_head(sample) if sample is not None else None
    src = grid if grid is not None else {k: v for k, v in sample.items() if k not in ("n", "seed")}
    entries = _entries(src, kind, base_def, probe, factory is not None)
    definition = {"format": FORMAT, "base": base_def, "grid": entries if grid is not None else None,
                  "sample": None if head is None else {"n": head[0], "seed": head[1], "fields": entries},
                  "derived": derived, "plan": plan, "chunk_size": size}
    sw = Sweep(definition, system, factory)
    _check_layout(sw, kind)
    return sw


def resolve_field(base, name: str, *, robot: Mapping | None = None, **plan_kwargs) -> tuple[str, str]:
    """``(full name, kind)`` of field ``name`` of the base problem (:func:`sweep`'s ``base``), kind
    ``"number"``, ``"string"`` or ``"any"``: how a file's value for it is read."""
    base_def, _system, factory, probe = base_from(base, robot, plan_kwargs)
    full = resolve(name, len(base_def["times"]), probe, robot_keys(base_def, probe), factory is not None)
    return full, field_kind(full)
