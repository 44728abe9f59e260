"""What a sweep's point records, and the words for it: the statuses (those of
:class:`acroplan.Status` and one more, ``invalid``), the message codes, the canonical JSON of a
definition, and :class:`SweepPoint`, one point's ``success``, ``status`` and ``message``.

Statuses
--------
A point's status is one of :class:`PointStatus`, stored as an ``int8`` code:

=====  ==================  ==================================================================
code   status              meaning
=====  ==================  ==================================================================
0      ``success``         :attr:`acroplan.Status.SUCCESS`: planned (or, with ``plan=False``,
                           every derived quantity found)
1      ``infeasible``      :attr:`acroplan.Status.INFEASIBLE`: proven impossible, the proof in
                           the message
2      ``not_converged``   :attr:`acroplan.Status.NOT_CONVERGED`: the planner found no motion,
                           *or the point's computation crashed* (an unexpected error anywhere,
                           or its worker died), as :func:`acroplan.plan_many` reports a crash
3      ``invalid``         refused before planning: :func:`acroplan.plan` raised
                           :class:`~acroplan.InvalidInputError` for the point's values (a
                           negative flight time, a waypoint outside the joint limits); the
                           message names the field. Where plan() and plan_many raise (exit code
                           2 on the command line), a sweep records the point and goes on.
-1                         not computed (yet)
=====  ==================  ==================================================================

The first three are :class:`acroplan.Status`'s members and equal to them
(``PointStatus.SUCCESS == acroplan.Status.SUCCESS == "success"``); stores written before this
vocabulary (store format 1) use the same codes, and read the same (there a crash while building
a point was recorded as ``invalid``).
"""

from __future__ import annotations

import dataclasses
import enum
import json
import math
import re
import zlib
from typing import Any, Mapping

import numpy as np

from ..core.basis import InputBasis
from ..core.errors import InvalidInputError
from ..core.result import Status

__all__ = ["FORMAT", "READABLE_FORMATS", "PointStatus", "STATUS_CODES", "MISSING", "SweepPoint", "message_template",
           "message_code", "canonical_json", "plain", "short"]

#: Version of the definition's canonical form and of the store's layout written now (2: grids by
#: their description, chunk checksums).
FORMAT = 2
#: Store formats this version reads (format 1: grids by their values, no checksums; read, not resumed).
READABLE_FORMATS = (1, 2)
#: ``status`` code of a point not computed (yet).
MISSING = -1


class PointStatus(enum.StrEnum):
    """How a sweep's point ended: :class:`acroplan.Status`'s three members and ``invalid`` (module
    docstring). A member is its own string and carries its stored :attr:`code`, :attr:`meaning` and
    :attr:`fix`."""

    SUCCESS = "success"
    INFEASIBLE = "infeasible"
    NOT_CONVERGED = "not_converged"
    INVALID = "invalid"

    @property
    def code(self) -> int:
        """The ``int8`` stored for it."""
        return _CODES[self]

    @property
    def success(self) -> bool:
        return self is PointStatus.SUCCESS

    @property
    def plan_status(self) -> Status | None:
        """The :class:`acroplan.Status` it is (``None`` for ``invalid``: nothing was planned)."""
        return None if self is PointStatus.INVALID else Status(self.value)

    @property
    def meaning(self) -> str:
        if self is PointStatus.INVALID:
            return ("refused before planning: plan() raised InvalidInputError for the point's values; the message "
                    "names the field")
        if self is PointStatus.NOT_CONVERGED:
            return Status.NOT_CONVERGED.meaning + "; or the point's computation crashed (the message says how)"
        return Status(self.value).meaning

    @property
    def fix(self) -> str:
        if self is PointStatus.INVALID:
            return "keep the swept values inside what plan() accepts (the message names the field)"
        return Status(self.value).fix

    @classmethod
    def from_code(cls, code: int) -> "PointStatus | None":
        """The status stored as ``code`` (``None`` for -1, not computed)."""
        return _BY_CODE.get(int(code))


_CODES = {PointStatus.SUCCESS: 0, PointStatus.INFEASIBLE: 1, PointStatus.NOT_CONVERGED: 2, PointStatus.INVALID: 3}
_BY_CODE = {v: k for k, v in _CODES.items()}
#: ``status`` codes of a point by name (what the store's attributes record).
STATUS_CODES = {s.value: s.code for s in PointStatus}


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


@dataclasses.dataclass(frozen=True)
class SweepPoint:
    """One point of a sweep: its ``success``, ``status`` and ``message``, as every result type.

    Attributes
    ----------
    index : int
        The flat point index (C order over the grid; the sample's point).
    values : dict
        The swept fields' values there, by full name.
    status : PointStatus
        Equal to the :class:`acroplan.Status` of the same name for the first three.
    message : str
        The full message when computed here (:meth:`acroplan.sweeps.Sweep.evaluate`), the template
        (numbers as ``#``) when read from a store (:meth:`from_dataset`).
    data : dict
        The recorded quantities (``effort``, ``peak_rate``, ..., the derived ones).
    """

    index: int
    values: dict
    status: PointStatus
    message: str
    data: dict = dataclasses.field(default_factory=dict)

    @property
    def success(self) -> bool:
        return self.status.success

    @classmethod
    def from_dataset(cls, ds, index: int) -> "SweepPoint | None":
        """Point ``index`` of a store's Dataset (:func:`acroplan.open_sweep`), or ``None`` when it is
        not computed."""
        shape = tuple(ds["status"].shape)
        where = np.unravel_index(int(index), shape)
        code = int(np.asarray(ds["status"].values[where]))
        status = PointStatus.from_code(code)
        if status is None:
            return None
        table = json.loads(ds.attrs.get("messages", "{}"))
        message = table.get(str(int(np.asarray(ds["message"].values[where]))), "")
        data = {name: np.asarray(ds[name].values[where]).item() for name in ds.data_vars
                if name not in ("status", "message") and ds[name].shape == shape}
        values = {}
        for name in ds.coords:
            full = ds[name].attrs.get("field")
            if full:
                dims = ds[name].dims
                sub = tuple(where[ds["status"].dims.index(d)] for d in dims)
                values[full] = np.asarray(ds[name].values[sub]).item()
        return cls(int(index), values, status, message, data)


# ---------------------------------------------------------------------------------------------- JSON
def short(value, most: int = 80) -> str:
    """``repr(value)``, cut to ``most`` characters."""
    r = repr(value)
    return r if len(r) <= most else r[:most - 3] + "..."


def canonical_json(obj) -> str:
    """The one JSON text of ``obj`` (sorted keys, no spaces, no NaN): what the hash is taken of."""
    return json.dumps(obj, sort_keys=True, separators=(",", ":"), allow_nan=False, ensure_ascii=True)


def plain(value, field: str) -> Any:
    """``value`` as a plain JSON type (numbers, strings, booleans, None, lists, dicts).

    Raises
    ------
    InvalidInputError
        Naming ``field`` for a value a definition cannot record (a non-finite number, an object).
    """
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
        return [plain(v, field) for v in value.tolist()]
    if isinstance(value, (list, tuple)):
        return [plain(v, f"{field}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, Mapping):
        return {str(k): plain(v, f"{field}.{k}") for k, v in value.items()}
    if isinstance(value, InputBasis):
        return value.name
    raise InvalidInputError(field, f"cannot be recorded in a sweep's definition: {type(value).__name__}",
                            "give numbers, strings, booleans or lists of them (a strategy by its registered name)")
