"""A sweep's points, described and generated on demand.

A definition records each grid axis as it was given (issue #25: never every value): a list of
values, ``{start, stop, num}`` (``log = true`` for geometric spacing) or ``{start, stop, step}``;
a sample as ``n``, ``seed`` and one distribution per field. The values of any set of points are
generated when asked for (a chunk's, a slice of a coordinate), so no part of the package holds
every value of a large sweep. A range axis gives exactly ``numpy.linspace``'s,
``numpy.geomspace``'s or ``start + step * arange(n)``'s values.

Sizes are bounded (:data:`MAX_POINTS`, :data:`MAX_CHUNKS`, :data:`MAX_CHUNK_SIZE`) and a larger
sweep is refused up front, naming the number.
"""

from __future__ import annotations

import math
from typing import Mapping

import numpy as np

from ..core.errors import InvalidInputError
from .fields import check_value, field_kind
from .vocabulary import short

__all__ = ["MAX_POINTS", "MAX_CHUNKS", "MAX_CHUNK_SIZE", "MAX_LIST", "DEFAULT_CHUNK", "Axis", "parse_axis", "axis_of",
           "parse_sample_field", "sample_values", "check_points"]

#: The most points a sweep may have. A store's every chunk is read back and checked against its
#: checksum on each open and resume: at about 80 bytes a point, 1e8 points are 8 GB to read.
MAX_POINTS = 100_000_000
#: The most chunks: the completion record, the checksums (32 bytes a chunk) and the driver's map of
#: chunks done (one byte a chunk) stay below 40 MB.
MAX_CHUNKS = 1_000_000
#: The most points per chunk: a chunk's results (about 80 bytes a point) are held by the driver,
#: twice the workers' number of them at once.
MAX_CHUNK_SIZE = 100_000
#: The most values a list may give (an axis or a sample's choices): a definition records a list in
#: full (about 20 bytes a value); a longer axis is a range, ``{start, stop, num}``.
MAX_LIST = 1_000_000
#: Points per chunk when the definition does not say (docs/sweeps.md: chunk size advice).
DEFAULT_CHUNK = 1000
_RANGE = ({"start", "stop", "num"}, {"start", "stop", "num", "log"}, {"start", "stop", "step"})


def _count(n, where: str) -> int:
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise InvalidInputError(where, f"must be a whole number >= 1, got {short(n)}", "give for example 25")
    return check_points(int(n), where)


def check_points(n: int, where: str, product: str = "") -> int:
    """``n``, or :class:`InvalidInputError` naming ``where`` and the number (``product``: how it is
    made, ``"1000 x 1000 = "``) when it exceeds :data:`MAX_POINTS`."""
    if n > MAX_POINTS:
        raise InvalidInputError(where, f"gives {product}{n} points; a sweep has at most {MAX_POINTS} (every chunk "
                                "of its store is read back and checked on each open)",
                                "split it into several sweeps, or sample it ([sweep.sample] n = ...)")
    return n


def _distinct(step: float, scale: float, where: str) -> None:
    if not abs(step) > 4.0 * math.ulp(scale):
        raise InvalidInputError(where, "gives values that repeat: the step between them is below the floating-point "
                                "resolution of its ends", "give fewer points, or ends further apart")


class Axis:
    """A grid axis: its length, its values' type, and any of its values on demand (:meth:`take`)."""

    kind = "values"

    def __init__(self, description):
        self.description = description

    def __len__(self) -> int:
        return self.num

    @property
    def dtype(self) -> np.dtype:
        return np.dtype(np.float64)

    def take(self, idx) -> np.ndarray:
        """The values at indices ``idx`` (a numpy array of int)."""
        raise NotImplementedError

    def slice(self, a: int, b: int, step: int = 1 << 18) -> np.ndarray:
        """The values ``a`` to ``b - 1``, generated ``step`` at a time into the result."""
        out = np.empty(max(0, b - a), dtype=self.dtype)
        for i in range(a, b, step):
            j = min(b, i + step)
            out[i - a:j - a] = self.take(np.arange(i, j, dtype=np.int64))
        return out


class ListAxis(Axis):
    """The values given."""

    def __init__(self, description):
        super().__init__(description)
        self._values = np.asarray(description)
        self.num = len(description)

    @property
    def dtype(self):
        return self._values.dtype

    def take(self, idx):
        return self._values[np.asarray(idx, dtype=np.int64)]


class LinearAxis(Axis):
    """``numpy.linspace(start, stop, num)``, value by value."""

    kind = "linear"

    def __init__(self, description):
        super().__init__(description)
        self.start, self.stop, self.num = float(description["start"]), float(description["stop"]), \
            int(description["num"])

    def take(self, idx):
        i = np.asarray(idx, dtype=np.int64)
        if self.num == 1:
            return np.full(i.shape, self.start)
        div = self.num - 1
        delta = self.stop - self.start
        step = delta / div
        y = i.astype(np.float64)
        y = (y / div) * delta if step == 0 else y * step  # as numpy.linspace (its denormal case too)
        y = y + self.start
        return np.where(i == div, self.stop, y)


class GeometricAxis(LinearAxis):
    """``numpy.geomspace(start, stop, num)``, value by value (ends > 0)."""

    kind = "geometric"

    def take(self, idx):
        i = np.asarray(idx, dtype=np.int64)
        lin = LinearAxis({"start": float(np.log10(self.start)), "stop": float(np.log10(self.stop)), "num": self.num})
        y = np.power(10.0, lin.take(i))
        y = np.where(i == 0, self.start, y)
        return np.where(i == self.num - 1, self.stop, y) if self.num > 1 else y


class StepAxis(Axis):
    """``start + step * arange(n)`` up to ``stop`` (within a relative 1e-12)."""

    kind = "step"

    def __init__(self, description):
        super().__init__(description)
        self.start, self.stop, self.step = (float(description[k]) for k in ("start", "stop", "step"))
        self.num = int(math.floor((self.stop - self.start) / self.step * (1 + 1e-12))) + 1

    def take(self, idx):
        return self.start + self.step * np.asarray(idx, dtype=np.int64)


def axis_of(description) -> Axis:
    """The :class:`Axis` a canonical description gives (a list: :class:`ListAxis`)."""
    if isinstance(description, list):
        return ListAxis(description)
    if "step" in description:
        return StepAxis(description)
    return (GeometricAxis if description.get("log") else LinearAxis)(description)


def _range(spec: Mapping, where: str) -> dict:
    keys = set(spec)
    if "num" in keys:
        num = _count(spec["num"], f"{where}.num")
        a, b = (check_value("robot.x", spec[k], f"{where}.{k}") for k in ("start", "stop"))
        log = spec.get("log", False)
        if not isinstance(log, (bool, np.bool_)):
            raise InvalidInputError(f"{where}.log", f"must be true or false, got {short(log)}", "give log = true")
        if log and (a <= 0 or b <= 0):
            raise InvalidInputError(where, "a log axis needs start and stop > 0", "give positive ends")
        if num > 1:
            if log:
                la, lb = math.log(a), math.log(b)
                _distinct((lb - la) / (num - 1), 2.0 * max(abs(la), abs(lb), 1.0), where)
            else:
                _distinct((b - a) / (num - 1), max(abs(a), abs(b), abs(b - a)), where)
        return {"start": a, "stop": b, "num": num, **({"log": True} if log else {})}
    a, b, h = (check_value("robot.x", spec[k], f"{where}.{k}") for k in ("start", "stop", "step"))
    if not h > 0 or b < a:
        raise InvalidInputError(where, "needs step > 0 and stop >= start", "give for example "
                                "{start = 0.5, stop = 2, step = 0.25}")
    n = (b - a) / h * (1 + 1e-12)
    if not n < MAX_POINTS:
        check_points(MAX_POINTS + 1 if not math.isfinite(n) else int(n) + 1, where)
    _distinct(h, max(abs(a), abs(b)), where)
    return {"start": a, "stop": b, "step": h}


def _values(spec, where: str) -> list:
    if isinstance(spec, (str, bytes)) or not hasattr(spec, "__len__"):
        raise InvalidInputError(where, f"must be a list of values, got {short(spec)}", "give for example [1, 2, 3]")
    if len(spec) > MAX_LIST:
        raise InvalidInputError(where, f"lists {len(spec)} values; a list has at most {MAX_LIST} (the definition "
                                "records it in full)", "give a range: {start = ..., stop = ..., num = ...}")
    values = list(np.asarray(spec).tolist()) if isinstance(spec, np.ndarray) else list(spec)
    if not values:
        raise InvalidInputError(where, "has no values", "give at least one value")
    return values


def parse_axis(spec, full: str, where: str):
    """The canonical description of a grid axis of field ``full``: the list of values given, or the
    range (``{start, stop, num[, log]}``, ``{start, stop, step}``), checked."""
    if isinstance(spec, Mapping):
        if set(spec) in _RANGE:
            if field_kind(full) != "number":
                raise InvalidInputError(where, "a range is for a number field", "give the list of values")
            return _range(spec, where)
        raise InvalidInputError(where, f"must be a list of values or {{start, stop, num}}, got keys {sorted(spec)}",
                                "give for example [1, 2, 3] or {start = 0.5, stop = 2, num = 16}")
    vals = [check_value(full, v, f"{where}[{i}]") for i, v in enumerate(_values(spec, where))]
    kinds = {type(v) for v in vals}
    if len(kinds) > 1 and not kinds <= {int, float}:
        raise InvalidInputError(where, "mixes kinds of values", "give values of one kind")
    if len(set(map(repr, vals))) != len(vals):
        raise InvalidInputError(where, "repeats a value", "give each value once")
    return vals


# ---------------------------------------------------------------------------------------------- samples
_SAMPLE_KINDS = ("uniform", "log", "choices")


def parse_sample_field(spec, full: str, where: str) -> dict:
    """``[lo, hi]`` -> ``{"uniform": [lo, hi]}``; ``{"log": [lo, hi]}``; ``{"uniform": [lo, hi]}``;
    ``{"choices": [...]}``, checked."""
    if isinstance(spec, Mapping):
        if len(spec) != 1 or next(iter(spec)) not in _SAMPLE_KINDS:
            raise InvalidInputError(where, f"must be [low, high] or one of {{uniform, log, choices}}, got "
                                    f"{short(dict(spec))}", "give for example [0.5, 3] or {log = [1, 100]}")
        kind, val = next(iter(spec.items()))
    else:
        kind, val = "uniform", spec
    if kind == "choices":
        return {"choices": [check_value(full, v, f"{where}[{i}]") for i, v in enumerate(_values(val, where))]}
    if isinstance(val, (str, bytes)) or not hasattr(val, "__len__") or len(val) != 2:
        raise InvalidInputError(where, f"must be [low, high], got {short(val)}", "give for example [0.5, 3]")
    if field_kind(full) == "string":
        raise InvalidInputError(where, "a text field is sampled from choices", "give {choices = [...]}")
    lo, hi = (check_value("robot.x", v, where) for v in val)
    if not lo < hi:
        raise InvalidInputError(where, f"needs low < high, got [{lo}, {hi}]", "give for example [0.5, 3]")
    if kind == "log" and lo <= 0:
        raise InvalidInputError(where, "a log range needs low > 0", "give positive ends")
    return {kind: [lo, hi]}


def _uniforms(seed: int, k: int, points: np.ndarray) -> np.ndarray:
    """``(len(points), k)`` uniforms in [0, 1) for consecutive points: a counter-based generator
    (Philox) advanced to the first, so a point's draw does not depend on how the work is chunked."""
    if not points.size:
        return np.zeros((0, k))
    blocks = (k + 3) // 4
    bg = np.random.Philox(key=int(seed))
    bg.advance(int(points[0]) * blocks)
    raw = bg.random_raw(points.size * blocks * 4).reshape(points.size, blocks * 4)[:, :k]
    return (raw >> np.uint64(11)).astype(np.float64) * (1.0 / 9007199254740992.0)


def sample_values(fields, seed: int, points) -> dict[str, np.ndarray]:
    """The sampled fields' values at flat point indices ``points`` (``fields``: the definition's
    ``[[name, spec], ...]``)."""
    points = np.asarray(points, dtype=np.int64)
    if points.size > 1 and not np.array_equal(points, np.arange(points[0], points[0] + points.size)):
        parts = [sample_values(fields, seed, points[i:i + 1]) for i in range(points.size)]
        return {f: np.concatenate([p[f] for p in parts]) for f, _ in fields}
    U = _uniforms(seed, len(fields), points)
    out = {}
    for j, (f, spec) in enumerate(fields):
        (kind, val), = spec.items()
        u = U[:, j]
        if kind == "uniform":
            out[f] = val[0] + u * (val[1] - val[0])
        elif kind == "log":
            out[f] = np.exp(math.log(val[0]) + u * (math.log(val[1]) - math.log(val[0])))
        else:
            out[f] = np.asarray(val)[np.minimum((u * len(val)).astype(np.int64), len(val) - 1)]
    return out
