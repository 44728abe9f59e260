"""Sweep files: a problem file with a ``[sweep]`` table (docs/sweeps.md), read into a
:class:`~acroplan.sweeps.Sweep`."""

from __future__ import annotations

from pathlib import Path
from typing import Mapping

from ...core.errors import InvalidInputError
from ...core.validate import arith, check_keys
from ...sweeps.definition import Sweep
from ...sweeps.front import resolve_field, sweep
from ...sweeps.keywords import PLAN_KEYWORDS
from ..problem import load_toml, parse_problem

__all__ = ["parse_sweep", "load_sweep", "SWEEP_KEYS"]

#: The keys of a ``[sweep]`` table.
SWEEP_KEYS = ("grid", "sample", "derived", "plan", "chunk_size", "options")
_SPEC_KEYS = {"start", "stop", "num", "step", "log", "uniform", "choices"}
_TOP = ("derived", "plan", "chunk_size", "sweep", "grid", "sample")


def _flatten(table: Mapping, prefix: str = "") -> dict:
    """TOML's dotted keys (``robot.scale = [...]``) back into field names; range tables stay."""
    out = {}
    for k, v in table.items():
        name = f"{prefix}{k}"
        if isinstance(v, Mapping) and v and not (set(v) & _SPEC_KEYS):
            out.update(_flatten(v, name + "."))
        else:
            out[name] = v
    return out


class _Reader:
    """A file's field values: arithmetic with ``pi`` read for the number fields."""

    def __init__(self, problem, extra: dict):
        self.problem, self.extra = problem, extra

    def value(self, field_name, v, where):
        _full, kind = resolve_field(self.problem, field_name, **self.extra)
        if isinstance(v, str) and kind == "number":
            return arith(where, v)
        return v

    def values(self, field_name, spec, where):
        if isinstance(spec, list):
            return [self.value(field_name, v, f"{where}[{i}]") for i, v in enumerate(spec)]
        if isinstance(spec, Mapping):
            return {k: (self.values(field_name, v, f"{where}.{k}") if isinstance(v, list) else
                        self.value(field_name, v, f"{where}.{k}") if k in ("start", "stop", "step") else v)
                    for k, v in spec.items()}
        return spec

    def table(self, table, kind: str) -> dict:
        if not isinstance(table, Mapping):
            raise InvalidInputError(f"sweep.{kind}", "must be a table", f"write [sweep.{kind}] with one key per field")
        raw = _flatten(table)
        return {k: (v if kind == "sample" and k in ("n", "seed") else self.values(k, v, f"sweep.{kind}.{k}"))
                for k, v in raw.items()}


def _field(e: InvalidInputError, kind: str) -> str:
    """An error's field named as in the file (``sweep.grid.T``, ``sweep.derived``, ``robot.M1``)."""
    field = e.field
    if field.startswith(("grid.", "sample.")):
        field = f"sweep.{field}"
    elif field in _TOP:
        field = f"sweep.{field}"
    elif not field.startswith(("sweep.", "robot", "plan", "limits", "options", "base.")):
        field = f"sweep.{kind}.{field}"
    return field.replace("base.", "")


def parse_sweep(data: dict, name: str = "", base=None) -> Sweep:
    """A :class:`~acroplan.sweeps.Sweep` from a parsed TOML document: the problem file's tables
    (``[robot]`` or ``[body]``, ``[plan]``, ``[limits]``, ``[options]``) and a ``[sweep]`` table with
    ``[sweep.grid]`` or ``[sweep.sample]`` (docs/sweeps.md). ``base`` is the file's folder: a URDF
    named in ``[body]`` is read relative to it.

    Raises
    ------
    InvalidInputError
        Naming the key as the file writes it (``sweep.grid.T``, ``sweep.derived``).
    """
    if not isinstance(data, dict):
        raise InvalidInputError("<file>", "must be a TOML document", "see docs/sweeps.md")
    if "sweep" not in data:
        raise InvalidInputError("sweep", "table is missing", "add [sweep] with [sweep.grid] or [sweep.sample] "
                                "(docs/sweeps.md)")
    table = data["sweep"]
    check_keys("sweep", table, SWEEP_KEYS)
    problem = parse_problem({k: v for k, v in data.items() if k != "sweep"}, name=name, base=base)
    extra = table.get("options", {})
    check_keys("sweep.options", extra, tuple(k for k in PLAN_KEYWORDS if k not in ("times", "limits", "state_bounds")))
    kind = "grid" if "grid" in table else "sample"
    reader = _Reader(problem, extra)
    try:
        grid = reader.table(table["grid"], "grid") if "grid" in table else None
        sample = reader.table(table["sample"], "sample") if "sample" in table else None
        return sweep(problem, grid=grid, sample=sample, derived=table.get("derived", []),
                     plan=table.get("plan", True), chunk_size=table.get("chunk_size"), **extra)
    except InvalidInputError as e:
        raise InvalidInputError(_field(e, kind), e.problem, e.fix) from None


def load_sweep(path) -> Sweep:
    """Read and validate a sweep file (a problem file with a ``[sweep]`` table)."""
    return parse_sweep(load_toml(path), name=Path(path).stem, base=Path(path).parent)
