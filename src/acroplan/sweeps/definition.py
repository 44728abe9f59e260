"""The sweep definition (:class:`Sweep`): its layout in chunks, its points' values and the
:func:`acroplan.plan` keywords of each point."""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import json
import math
from typing import Any, Callable, Mapping

import numpy as np

from ..core.errors import InvalidInputError
from ..core.limits import Limits
from ..core.sweep_hooks import DERIVED, reach_hook_of, resolve_factory
from ..core.system import ControlAffineSystem
from .axes import MAX_CHUNKS, axis_of, check_points, sample_values
from .base import build_factory
from .compute import compute_chunk, evaluate_point
from .fields import first_angle
from .keywords import INDEXED
from .metrics import TORQUE_SAMPLES
from .vocabulary import MISSING, READABLE_FORMATS, STATUS_CODES, canonical_json

__all__ = ["Sweep", "from_definition"]

_ORDER = {"robot": 0, "option": 1, "T": 2, "times": 3, "state": 4, "somersaults": 5, "reach": 6}


@dataclasses.dataclass(frozen=True, eq=False)
class Sweep:
    """An immutable sweep definition: build it with :func:`acroplan.sweep` (or
    :func:`acroplan.load_sweep` from a TOML file).

    Attributes
    ----------
    definition : dict
        The canonical definition (plain JSON types; each grid axis as it was given: the list of
        values or the range, never every value); :attr:`json` is its one text and :attr:`hash`
        its SHA-256, which identifies it (a store records it and a resumed run must match it).
        The hash detects accidental damage; it is no signature (anyone can compute it).
    system : ControlAffineSystem or None
        The base system (``None`` for a factory's sweep, or a definition read from a store:
        rebuilt from its record when a point needs it).
    factory : callable or None
        The system factory, for a factory's sweep.
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
    def axes(self) -> dict:
        """The grid's axes by field (:class:`~acroplan.sweeps.axes.Axis`: ``len``, ``dtype``, values on
        demand with ``take``); empty for a sample."""
        return {f: axis_of(d) for f, d in self.definition["grid"]} if self.is_grid else {}

    @functools.cached_property
    def shape(self) -> tuple[int, ...]:
        if self.is_grid:
            return tuple(len(self.axes[f]) for f in self.fields)
        return (int(self.definition["sample"]["n"]),)

    @property
    def size(self) -> int:
        return math.prod(self.shape)

    @property
    def chunk_size(self) -> int:
        return int(self.definition["chunk_size"])

    @property
    def derived(self) -> tuple[str, ...]:
        return tuple(self.definition["derived"])

    @property
    def planned(self) -> bool:
        return bool(self.definition["plan"])

    @property
    def is_factory(self) -> bool:
        return bool(self.definition["base"]["factory"])

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
        return math.prod(self.chunk_grid)

    def chunk_region(self, chunk: int) -> tuple[slice, ...]:
        """The store region (one slice per dimension) of chunk number ``chunk``."""
        if not 0 <= chunk < self.n_chunks:
            raise IndexError(f"chunk {chunk} of {self.n_chunks}")
        idx = np.unravel_index(chunk, self.chunk_grid)
        return tuple(slice(int(i) * c, min(n, (int(i) + 1) * c)) for i, c, n in zip(idx, self.chunks, self.shape))

    def chunk_len(self, chunk: int) -> int:
        """The number of points of chunk ``chunk``."""
        return math.prod(s.stop - s.start for s in self.chunk_region(chunk))

    def chunk_points(self, chunk: int) -> np.ndarray:
        """The flat indices of the chunk's points, in C order (consecutive)."""
        region = self.chunk_region(chunk)
        first = int(np.ravel_multi_index(tuple(s.start for s in region), self.shape))
        return np.arange(first, first + self.chunk_len(chunk), dtype=np.int64)

    # -------------------------------------------------------------- points
    def values(self, points) -> dict[str, np.ndarray]:
        """The swept fields' values at flat point indices ``points``, generated for those points
        only (a sample is drawn per point from a counter-based generator, so a point's values do not
        depend on how the work is chunked)."""
        points = np.asarray(points, dtype=np.int64)
        if self.is_grid:
            multi = np.unravel_index(points, self.shape)
            return {f: self.axes[f].take(i) for f, i in zip(self.fields, multi)}
        smp = self.definition["sample"]
        return sample_values(smp["fields"], int(smp["seed"]), points)

    def point(self, index: int) -> dict[str, Any]:
        """The swept fields' values at point ``index`` (flat, C order), as plain Python values."""
        v = self.values([int(index)])
        return {f: a[0].item() if hasattr(a[0], "item") else a[0] for f, a in v.items()}

    def problem(self, index: int) -> dict[str, Any]:
        """The :func:`acroplan.plan` keywords (with ``"system"``) of point ``index``: what
        :func:`acroplan.plan_many` takes. Raises :class:`InvalidInputError` for an invalid point."""
        return self.problem_of(self.point(index))

    def compute(self, chunk: int, points=None) -> dict[str, Any]:
        """Compute chunk ``chunk`` here (what a task does): every point of it, or only ``points``
        (flat indices within it); :func:`acroplan.sweeps.compute.compute_chunk`."""
        return compute_chunk(self, chunk, points)

    def evaluate(self, index: int):
        """Compute point ``index`` here: a :class:`~acroplan.sweeps.vocabulary.SweepPoint`
        (``success``, ``status``, ``message`` in full, the recorded quantities)."""
        return evaluate_point(self, int(index))

    # -------------------------------------------------------------- the problem of a point
    @functools.cached_property
    def base_system(self) -> ControlAffineSystem | None:
        """The base system: :attr:`system`, or rebuilt from the definition's record (``None`` for a
        factory's sweep)."""
        if self.system is not None or self.is_factory:
            return self.system
        return ControlAffineSystem.from_dict(self.definition["base"]["system"])

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
                m = INDEXED.match(rest)
                name, k = m.group(1), int(m.group(2)) % n
                ops.append((f, "times" if name == "times" else "state", name, k))
        return tuple(sorted(ops, key=lambda o: _ORDER[o[1]]))

    def problem_of(self, values: Mapping[str, Any], cache: dict | None = None) -> dict[str, Any]:
        """The :func:`acroplan.plan` keywords (with ``"system"``) for the swept fields' ``values``;
        ``cache`` keeps the last system built (a chunk's points often share their body)."""
        base = self.definition["base"]
        times = list(base["times"])
        wp = {k: list(v) for k, v in base["waypoints"].items()}
        opts = dict(base["options"])
        robot_vals = {key: values[f] for f, kind, key, _ in self._operations if kind == "robot"}
        ckey = tuple(robot_vals.items())
        system = cache.get(ckey) if cache is not None else None
        if system is None:
            system = self.system_of(dict(robot_vals))
            if cache is not None:
                cache.clear()
                cache[ckey] = system
        for f, kind, key, k in self._operations:
            v = values[f]
            if kind == "option":
                opts[key] = v
            elif kind == "T":
                times = _stretched(times, v)
            elif kind == "times":
                times[k] = v
            elif kind == "state":
                wp[key][k] = v
            elif kind == "somersaults":
                angle = first_angle(system)
                wp[angle][-1] = wp[angle][0] + 2.0 * math.pi * v
            elif kind == "reach":
                state, value = _reach_target(system, times, wp, opts, v)
                wp[state][-1] = value
        return {"system": system, "times": times, **wp, **opts}

    def system_of(self, robot_vals: dict) -> ControlAffineSystem:
        """The body with the swept ``robot.*`` values (by name, ``scale`` among them)."""
        scale = robot_vals.pop("scale", None)
        if self.is_factory:
            if scale is not None:
                raise InvalidInputError("robot.scale", "applies to a body the sweep builds itself, not to a factory's",
                                        "give the factory a size parameter and sweep robot.NAME")
            factory = self.factory or resolve_factory(self.definition["base"]["factory"])
            return build_factory(factory, {**self.definition["base"]["system"]["params"], **robot_vals}, "robot")
        system = self.base_system
        try:
            if robot_vals:
                system = system.with_robot_parameters(**robot_vals)
            if scale is not None:
                system = system.scaled(scale)
        except InvalidInputError as e:
            raise InvalidInputError(e.field if e.field.startswith("robot") else f"robot.{e.field}", e.problem,
                                    e.fix) from None
        except (TypeError, ValueError) as e:
            raise InvalidInputError("robot", f"cannot build the body ({type(e).__name__}: {e})",
                                    "check the robot fields") from None
        return system

    # -------------------------------------------------------------- what a point records
    def variables(self) -> list[tuple[str, str, Any, dict]]:
        """``(name, dtype, fill value, attributes)`` of every per-point variable of the store."""
        out = [("status", "int8", MISSING, {
            "description": "how the point ended: " + ", ".join(f"{v} {k}" for k, v in STATUS_CODES.items()) +
                           "; -1 not computed" + ("" if self.planned else " (the derived quantities' status)"),
            "flag_values": list(STATUS_CODES.values()), "flag_meanings": " ".join(STATUS_CODES)}),
               ("message", "uint32", 0, {"description": "CRC-32 of the message with its numbers replaced by #; "
                                                        "the table is the store's messages"})]
        if self.planned:
            out += _PLANNED
        base = self.base_system if any(callable(getattr(DERIVED.get(d), "units", None)) for d in self.derived) \
            else None
        for d in self.derived:
            entry = DERIVED.get(d)
            out.append((d, "float64", math.nan, {"description": entry.description if entry else d,
                                                  "units": entry.units_for(base) if entry else ""}))
        out.append(("seconds", "float64", math.nan, {"description": "wall time of the point (plan, metrics, "
                                                                    "derived), seconds; not reproducible"}))
        return out

    def coordinate_dtypes(self) -> dict[str, np.dtype]:
        """The dtype of each swept field's values."""
        if self.is_grid:
            return {f: self.axes[f].dtype for f in self.fields}
        return {f: a.dtype for f, a in self.values(np.zeros(1, dtype=np.int64)).items()}


_PLANNED = [
    ("effort", "float64", math.nan, {"description": "integral over the plan of the sum of squared inputs",
                                      "units": "input units^2 x time"}),
    ("peak_rate", "float64", math.nan, {"description": "max |u| over the plan (exact)", "units": "input units"}),
    ("peak_torque", "float64", math.nan, {
        "description": f"the largest |joint torque| of the system's torque model on {TORQUE_SAMPLES} points per "
                       "segment (NaN for a system without one)", "units": "the body's torque units"}),
    ("final_error", "float64", math.nan, {"description": "worst segment's endpoint error (planner)"}),
    ("verified_error", "float64", math.nan, {"description": "worst segment's independently verified error (NaN "
                                                            "when not verified)"}),
    ("evaluations", "int32", -1, {"description": "endpoint-and-Jacobian evaluations"}),
    ("segments", "int16", -1, {"description": "segments planned"}),
]


def _stretched(times: list, T) -> list:
    if not T > 0:
        raise InvalidInputError("plan.T", f"must be > 0, got {T}", "give a positive flight time")
    t0, t1 = times[0], times[-1]
    out = [t0 + (t - t0) * (T / (t1 - t0)) for t in times]
    out[-1] = t0 + T
    return out


@functools.lru_cache(maxsize=64)
def _limits(state_items: tuple, u_max, input_bounds: str) -> Limits:
    return Limits(None, json.loads(input_bounds), u_max=u_max, **dict(state_items))


def _reach_target(system, times, wp, opts, w) -> tuple[str, float]:
    """``(state, value)``: the last value of the state the family bounds, at ``lo + w (hi - lo)``."""
    hook = reach_hook_of(system)
    if hook is None:
        raise InvalidInputError("plan.reach", f"{type(system).__name__} registers no exact reachable interval",
                                "sweep the waypoint itself (plan.NAME[-1])")
    if not 0.0 <= w <= 1.0:
        raise InvalidInputError("plan.reach", f"must lie in [0, 1], got {w}", "give a relative position")
    states = system.state_names
    bounds = tuple(sorted((k, v) for k, v in opts.items() if (k.endswith("_min") or k.endswith("_max"))
                          and k[:-4] in states and v is not None))
    limits = _limits(bounds, opts.get("u_max"), json.dumps(opts.get("input_bounds"), sort_keys=True))
    start = {s: wp[s][-2] for s in states if s in wp}
    end = {s: wp[s][-1] for s in states if s in wp}
    lo, hi = hook.fn(system, start, end, float(times[-1] - times[-2]), limits)
    return hook.state, lo + w * (hi - lo)


def _check_layout(definition: dict) -> None:
    if definition.get("format") not in READABLE_FORMATS:
        raise InvalidInputError("format", f"is {definition.get('format')!r}, this acroplan reads "
                                f"{list(READABLE_FORMATS)}", "use the acroplan version that wrote the store")
    if (definition.get("grid") is None) == (definition.get("sample") is None):
        raise InvalidInputError("grid", "a definition has a grid or a sample", "start the sweep in a new store")


def from_definition(definition: Mapping, system: ControlAffineSystem | None = None,
                    factories: Mapping[str, Callable] | None = None) -> Sweep:
    """The sweep a recorded (canonical) definition describes. Nothing is imported: the base system
    is rebuilt from its record when a point needs it (``system`` gives it directly), a factory is
    resolved from the registered names and ``factories`` (:func:`acroplan.sweeps.register_factory`),
    and a factory known to neither is an error only when a point is computed.

    Raises
    ------
    InvalidInputError, KeyError, TypeError, ValueError
        For a definition that is not one (the caller names the store).
    """
    definition = json.loads(canonical_json(definition))
    _check_layout(definition)
    factory = None
    name = definition["base"].get("factory")
    if name:
        try:
            factory = resolve_factory(name, factories)
        except InvalidInputError:
            factory = None
    sw = Sweep(definition, system, factory)
    check_points(sw.size, "the definition")
    if sw.n_chunks > MAX_CHUNKS or not 1 <= sw.chunk_size:
        raise InvalidInputError("chunk_size", f"gives {sw.n_chunks} chunks; a store has at most {MAX_CHUNKS}",
                                "start the sweep in a new store")
    return sw
