"""Sweep stores: a sweep (:mod:`acroplan.sweep`) computed chunk by chunk into a zarr store, read
back as an xarray Dataset, resumed after any kill, and drawn as a map.

A store is a zarr (format 3) group, written by this module only:

    STORE/zarr.json               the group: attributes (the sweep's canonical definition, its
                                  SHA-256, the acroplan version, the layout's format) and the
                                  consolidated metadata of every array
    STORE/<variable>/...          one array per recorded variable (status, message, effort, ...),
                                  chunked as the sweep's chunks; the grid's coordinates
    STORE/acroplan-sweep.json     the completion record: which chunks are done, the message table,
                                  counts by status
    STORE/acroplan.lock           held (flock) by the run writing the store

A store is created whole or not at all (built under a temporary name, then renamed). A chunk is
computed by a task, written into its own region of every array, flushed to disk (fsync), and only
then marked done in the completion record, which is replaced atomically (temporary file, fsync,
rename, fsync of the folder). A run killed at any moment (the driver or a worker, ``kill -9``)
leaves a record that names only chunks written whole; started again with the same definition,
it computes exactly the chunks the record does not name. :func:`open_sweep` masks every point of
a chunk not in the record, so a half-written chunk is never read as done.

A store is refused (:class:`InvalidInputError`, exit code 2 on the command line), naming what is
wrong, when it is not a zarr store, not an acroplan sweep store, corrupt (unreadable metadata or
record, a definition that does not match its hash, arrays missing or of the wrong shape), written
by another acroplan version, or written for another definition (the first differing field is
named).
"""

from __future__ import annotations

import collections
import concurrent.futures as cf
import dataclasses
import json
import math
import multiprocessing
import os
import shutil
import sys
import time
import warnings
from pathlib import Path
from typing import Callable, Mapping

import numpy as np

from ..core.errors import EXIT_INVALID, EXIT_SUCCESS, InvalidInputError
from ..sweep import Sweep  # noqa: F401  (the front door this module stores)
from ..core.validate import arith as _arith
from ..core.validate import check_keys as _check_keys
from .problem import load_toml, parse_problem

#: the sweep module (``acroplan.sweep`` may be the function of that name once the package exports it)
_sw = sys.modules["acroplan.sweep"]
__version__ = sys.modules["acroplan"].__version__

__all__ = ["run_sweep", "open_sweep", "load_sweep", "parse_sweep", "draw_map", "SweepSummary", "check_store",
           "sweep_cmd", "map_cmd", "RECORD", "LOCK"]

#: The completion record's file name inside a store.
RECORD = "acroplan-sweep.json"
#: The lock file's name inside a store.
LOCK = "acroplan.lock"
#: Attribute names in the store's zarr.json.
ATTR_DEF, ATTR_HASH, ATTR_VERSION, ATTR_FORMAT = ("acroplan_sweep", "acroplan_sweep_hash", "acroplan_version",
                                                   "acroplan_store_format")
STATUS_NAMES = {v: k for k, v in _sw.STATUS_CODES.items()}


# ================================================================================================ TOML
SWEEP_KEYS = ("grid", "sample", "derived", "plan", "chunk_size", "options")
_SPEC_KEYS = {"start", "stop", "num", "step", "log", "uniform", "choices"}


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


def parse_sweep(data: dict, name: str = "", base=None) -> _sw.Sweep:
    """A :class:`~acroplan.sweep.Sweep` from a parsed TOML document: the problem file's tables
    (``[robot]`` or ``[body]``, ``[plan]``, ``[limits]``, ``[options]``) and a ``[sweep]`` table with
    ``[sweep.grid]`` or ``[sweep.sample]`` (docs/sweeps.md). ``base`` is the file's folder: a URDF
    named in ``[body]`` is read relative to it."""
    if not isinstance(data, dict):
        raise InvalidInputError("<file>", "must be a TOML document", "see docs/sweeps.md")
    if "sweep" not in data:
        raise InvalidInputError("sweep", "table is missing", "add [sweep] with [sweep.grid] or [sweep.sample] "
                                "(docs/sweeps.md)")
    table = data["sweep"]
    _check_keys("sweep", table, SWEEP_KEYS)
    problem = parse_problem({k: v for k, v in data.items() if k != "sweep"}, name=name, base=base)
    extra = table.get("options", {})
    _check_keys("sweep.options", extra, tuple(k for k in _sw._PLAN_KEYWORDS
                                              if k not in ("times", "limits", "state_bounds")))

    def value(field_name, v, where):
        full, kind = _sw.resolve_field(problem, field_name, **extra)
        if isinstance(v, str) and kind == "number":
            return _arith(where, v)
        return v

    def values(field_name, spec, where):
        if isinstance(spec, list):
            return [value(field_name, v, f"{where}[{i}]") for i, v in enumerate(spec)]
        if isinstance(spec, Mapping):
            return {k: (values(field_name, v, f"{where}.{k}") if isinstance(v, list) else
                        value(field_name, v, f"{where}.{k}") if k in ("start", "stop", "step") else v)
                    for k, v in spec.items()}
        return spec

    grid = sample = None
    try:
        if "grid" in table:
            if not isinstance(table["grid"], Mapping):
                raise InvalidInputError("sweep.grid", "must be a table", "write [sweep.grid] with one key per field")
            grid = {k: values(k, v, f"sweep.grid.{k}") for k, v in _flatten(table["grid"]).items()}
        if "sample" in table:
            if not isinstance(table["sample"], Mapping):
                raise InvalidInputError("sweep.sample", "must be a table", "write [sweep.sample] with n, seed and "
                                        "one key per field")
            raw = _flatten(table["sample"])
            sample = {k: (v if k in ("n", "seed") else values(k, v, f"sweep.sample.{k}")) for k, v in raw.items()}
        derived = table.get("derived", [])
        if isinstance(derived, str):
            derived = [derived]
        return _sw.sweep(problem, grid=grid, sample=sample, derived=derived, plan=table.get("plan", True),
                         chunk_size=table.get("chunk_size"), **extra)
    except InvalidInputError as e:
        field = e.field
        if not field.startswith(("sweep.", "robot", "plan", "limits", "options", "base.")):
            field = f"sweep.{'grid' if grid is not None or 'grid' in table else 'sample'}.{field}" \
                if field not in ("derived", "plan", "chunk_size", "sweep", "grid", "sample") else f"sweep.{field}"
        raise InvalidInputError(field.replace("base.", ""), e.problem, e.fix) from None


def load_sweep(path) -> _sw.Sweep:
    """Read and validate a sweep file (a problem file with a ``[sweep]`` table)."""
    return parse_sweep(load_toml(path), name=Path(path).stem, base=Path(path).parent)


# ================================================================================================ the store
def _fsync_path(path: Path, directory: bool = False) -> None:
    try:
        fd = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if directory else 0))
    except FileNotFoundError:
        return
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically: a temporary name, fsync, rename, fsync of the folder."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)
    _fsync_path(path.parent, directory=True)


def _dim_names(sw: _sw.Sweep) -> dict[str, str]:
    """Each swept field's name in the store: its short name (``P0``, ``T``, ``scale``; the physical
    body's ``angular_momentum`` is ``P0``) when unique, else the full name."""
    short = {f: {"angular_momentum": "P0"}.get(f.split(".", 1)[1], f.split(".", 1)[1]) for f in sw.fields}
    counts = collections.Counter(short.values())
    reserved = {name for name, *_ in sw.variables()} | {"point"}
    return {f: (s if counts[s] == 1 and s not in reserved else f) for f, s in short.items()}


def _diff(a, b, path="sweep") -> str | None:
    """The first place where two canonical definitions differ, with both values."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}.{k} (stored: {_brief(a.get(k))}, given: {_brief(b.get(k))})"
            d = _diff(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    pairs = lambda v: isinstance(v, list) and all(isinstance(e, list) and len(e) == 2 and isinstance(e[0], str)
                                                  for e in v)  # noqa: E731  (a grid's or sample's fields)
    if pairs(a) and pairs(b) and [e[0] for e in a] == [e[0] for e in b]:
        for (name, x), (_, y) in zip(a, b):
            d = _diff(x, y, f"{path}.{name}")
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            d = _diff(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    return None if a == b else f"{path} (stored: {_brief(a)}, given: {_brief(b)})"


def _brief(v) -> str:
    text = json.dumps(v)
    return text if len(text) <= 80 else text[:77] + "..."


def _read_json(path: Path, store: Path, what: str) -> dict:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InvalidInputError(str(store), f"is corrupt: its {what} ({path.name}) is missing",
                                "start the sweep in a new store (or delete this one)") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise InvalidInputError(str(store), f"is corrupt: its {what} ({path.name}) cannot be read "
                                f"({type(e).__name__})", "start the sweep in a new store (or delete this one)") \
            from None
    if not isinstance(data, dict):
        raise InvalidInputError(str(store), f"is corrupt: its {what} ({path.name}) is not a JSON object",
                                "start the sweep in a new store (or delete this one)")
    return data


@dataclasses.dataclass
class _Record:
    done: list  # sorted half-open ranges [a, b) of chunk numbers
    messages: dict
    counts: dict
    hash: str

    def chunks(self) -> set[int]:
        return {c for a, b in self.done for c in range(a, b)}

    def n_done(self) -> int:
        return sum(b - a for a, b in self.done)

    def add(self, chunk: int) -> None:
        ranges = self.done + [[chunk, chunk + 1]]
        ranges.sort()
        merged = []
        for a, b in ranges:
            if merged and a <= merged[-1][1]:
                merged[-1][1] = max(merged[-1][1], b)
            else:
                merged.append([a, b])
        self.done = merged

    def to_json(self) -> str:
        return json.dumps({"format": _sw.FORMAT, "hash": self.hash, "done": self.done, "messages": self.messages,
                           "counts": self.counts}, sort_keys=True)


def check_store(path, sweep_: _sw.Sweep | None = None) -> tuple[_sw.Sweep, _Record]:
    """Validate an existing store (against ``sweep_`` when given) and return its sweep and record.

    Raises
    ------
    InvalidInputError
        Naming the store and what is wrong (module docstring).
    """
    store = Path(path)
    fix_new = "give a new store (a path that does not exist yet)"
    if not store.exists():
        raise InvalidInputError(str(store), "no such store", "run the sweep first: acroplan sweep SWEEP.toml --out "
                                f"{store}")
    if not store.is_dir():
        raise InvalidInputError(str(store), "is not a sweep store (it is a file)", fix_new)
    meta_path = store / "zarr.json"
    if not meta_path.exists():
        raise InvalidInputError(str(store), "is not an acroplan sweep store (no zarr.json: not a zarr store)", fix_new)
    try:
        meta = json.loads(meta_path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise InvalidInputError(str(store), f"is corrupt: zarr.json cannot be read ({type(e).__name__})",
                                "start the sweep in a new store (or delete this one)") from None
    attrs = meta.get("attributes") if isinstance(meta, dict) else None
    if not isinstance(attrs, dict) or ATTR_DEF not in attrs:
        raise InvalidInputError(str(store), "is a zarr store, but not one acroplan sweep wrote (its attributes hold "
                                f"no {ATTR_DEF})", fix_new)
    fmt = attrs.get(ATTR_FORMAT)
    if fmt != _sw.FORMAT:
        raise InvalidInputError(str(store), f"has store format {fmt!r}; this acroplan reads format {_sw.FORMAT}",
                                "use the acroplan version that wrote it, or a new store")
    text, stored_hash = attrs.get(ATTR_DEF), attrs.get(ATTR_HASH)
    try:
        import hashlib

        definition = json.loads(text)
        ok = isinstance(definition, dict) and hashlib.sha256(text.encode("ascii")).hexdigest() == stored_hash
    except (TypeError, ValueError, UnicodeEncodeError):
        ok = False
    if not ok:
        raise InvalidInputError(str(store), f"is corrupt: the definition in its attributes does not match its hash "
                                f"({ATTR_HASH})", "start the sweep in a new store (or delete this one)")
    if sweep_ is not None and sweep_.hash != stored_hash:
        where = _diff(definition, sweep_.definition) or "the definition"
        raise InvalidInputError(str(store), f"holds another sweep: {where} differs",
                                "resume it with the definition that wrote it, or give a new store for this one")
    version = attrs.get(ATTR_VERSION)
    if sweep_ is not None and version != __version__:
        raise InvalidInputError(str(store), f"was written by acroplan {version}, this is {__version__} (a result "
                                "may differ between versions)", f"finish it with acroplan {version}, or start a new "
                                "store")
    try:
        sw = sweep_ if sweep_ is not None else _sw.from_definition(definition)
    except (InvalidInputError, KeyError, TypeError, ValueError, ImportError, AttributeError) as e:
        raise InvalidInputError(str(store), f"is corrupt: its definition cannot be read ({type(e).__name__}: {e})",
                                "start the sweep in a new store (or delete this one)") from None
    # the arrays: present, of the sweep's shape, chunks and type
    consolidated = (meta.get("consolidated_metadata") or {}).get("metadata") or {}
    expect = {name: (dtype, sw.shape, sw.chunks) for name, dtype, _, _ in sw.variables()}
    for name, dtype in sw.coordinate_dtypes().items():
        dn = _dim_names(sw)[name]
        if sw.is_grid:
            expect[dn] = (None, (sw.shape[sw.fields.index(name)],), None)
        else:
            expect[dn] = (None, sw.shape, sw.chunks)
    for name, (dtype, shape, chunks) in expect.items():
        arr_meta = store / name / "zarr.json"
        m = consolidated.get(name)
        if not arr_meta.exists() or not isinstance(m, dict):
            raise InvalidInputError(str(store), f"is corrupt: its array {name!r} is missing",
                                    "start the sweep in a new store (or delete this one)")
        got_shape = tuple(m.get("shape") or ())
        got_chunks = tuple(((m.get("chunk_grid") or {}).get("configuration") or {}).get("chunk_shape") or ())
        if got_shape != tuple(shape) or (chunks is not None and got_chunks != tuple(chunks)) or \
                (dtype is not None and str(m.get("data_type")) != dtype):
            raise InvalidInputError(str(store), f"is corrupt: its array {name!r} has shape {got_shape}, chunks "
                                    f"{got_chunks}, type {m.get('data_type')}; the sweep needs {tuple(shape)}, "
                                    f"{chunks}, {dtype}", "start the sweep in a new store (or delete this one)")
    rec = _read_json(store / RECORD, store, "completion record")
    try:
        done = [[int(a), int(b)] for a, b in rec["done"]]
        record = _Record(done, {str(k): str(v) for k, v in dict(rec["messages"]).items()},
                         {str(k): int(v) for k, v in dict(rec["counts"]).items()}, str(rec["hash"]))
        valid = record.hash == stored_hash and all(0 <= a < b <= sw.n_chunks for a, b in done) and \
            all(done[i][1] < done[i + 1][0] for i in range(len(done) - 1))
    except (KeyError, TypeError, ValueError):
        valid = False
    if not valid:
        raise InvalidInputError(str(store), f"is corrupt: its completion record ({RECORD}) does not describe this "
                                "store", "start the sweep in a new store (or delete this one)")
    return sw, record


def _create(path: Path, sw: _sw.Sweep) -> None:
    """Create the store whole: under a temporary name, then renamed into place."""
    tmp = path.with_name(f".{path.name}.creating-{os.getpid()}")
    shutil.rmtree(tmp, ignore_errors=True)
    try:
        _create_in(tmp, path, sw)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _create_in(tmp: Path, path: Path, sw: _sw.Sweep) -> None:
    import zarr

    with warnings.catch_warnings():
        # zarr's notes on text coordinates and consolidated metadata, which this store reads itself
        warnings.filterwarnings("ignore", module=r"zarr(\.|$)")
        _build(tmp, sw, zarr)
    try:
        os.rename(tmp, path)  # onto nothing, or onto an empty folder
    except OSError:
        raise InvalidInputError(str(path), "exists and is not empty, and is not a sweep store",
                                "give a new store (a path that does not exist yet)") from None
    _fsync_path(path.parent, directory=True)


def _build(tmp: Path, sw: _sw.Sweep, zarr) -> None:
    """The store's group, arrays, coordinates, consolidated metadata and empty record, flushed."""
    attrs = {ATTR_DEF: sw.json, ATTR_HASH: sw.hash, ATTR_VERSION: __version__, ATTR_FORMAT: _sw.FORMAT,
             "title": "acroplan sweep", "dims": list(sw.dims), "fields": list(sw.fields),
             "statuses": _sw.STATUS_CODES}
    g = zarr.open_group(str(tmp), mode="w-", zarr_format=3, attributes=attrs)
    names = _dim_names(sw)
    dims = [names[f] for f in sw.fields] if sw.is_grid else ["point"]
    coords = " ".join(names[f] for f in sw.fields) if not sw.is_grid else None
    for name, dtype, fill, var_attrs in sw.variables():
        a = dict(var_attrs)
        if coords:
            a["coordinates"] = coords
        g.create_array(name, shape=sw.shape, chunks=sw.chunks, dtype=dtype, fill_value=fill,
                       dimension_names=dims, attributes=a)
    for f, dtype in sw.coordinate_dtypes().items():
        a = {"field": f, "description": f"the swept field {f}"}
        if sw.is_grid:
            vals = sw.axes[f]
            arr = g.create_array(names[f], shape=vals.shape, chunks=vals.shape, dtype=vals.dtype,
                                 dimension_names=[names[f]], attributes=a,
                                 **({} if vals.dtype.kind in "UST" else {"fill_value": 0}))
            arr[:] = vals
        else:
            g.create_array(names[f], shape=sw.shape, chunks=sw.chunks, dtype=dtype, dimension_names=["point"],
                           attributes=a, **({"fill_value": math.nan} if dtype.kind == "f" else {}))
    zarr.consolidate_metadata(str(tmp))  # read without listing the folder
    rec = _Record([], {}, {}, sw.hash)
    (tmp / RECORD).write_text(rec.to_json(), encoding="utf-8")
    (tmp / LOCK).touch()
    for root, _dirs, files in os.walk(tmp):
        for f in files:
            _fsync_path(Path(root) / f)
        _fsync_path(Path(root), directory=True)


class _Store:
    """An open store being written by this process (holds its lock)."""

    def __init__(self, path: Path, sw: _sw.Sweep, record: _Record):
        import fcntl

        self.path, self.sweep, self.record = path, sw, record
        self._lock = open(path / LOCK, "a+")
        try:
            fcntl.flock(self._lock.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            self._lock.seek(0)
            who = self._lock.read().strip()
            self._lock.close()
            raise InvalidInputError(str(path), f"is being written by another run{f' (pid {who})' if who else ''}",
                                    "wait for it to finish, or stop it; then run again to resume") from None
        self._lock.seek(0)
        self._lock.truncate()
        self._lock.write(str(os.getpid()))
        self._lock.flush()
        self._arrays = None
        # what a killed run may have left: the record's temporary file
        for leftover in path.glob(f".{RECORD}.tmp-*"):
            leftover.unlink(missing_ok=True)

    def arrays(self):
        if self._arrays is None:
            import zarr

            g = zarr.open_group(str(self.path), mode="r+", zarr_format=3, use_consolidated=True)
            names = _dim_names(self.sweep)
            self._arrays = {name: g[name] for name, *_ in self.sweep.variables()}
            if not self.sweep.is_grid:
                self._arrays.update({("coord", f): g[names[f]] for f in self.sweep.fields})
        return self._arrays

    def write(self, result: dict) -> None:
        """Write a computed chunk into its region, flush it to disk, then mark it done."""
        sw = self.sweep
        chunk = int(result["chunk"])
        region = sw.chunk_region(chunk)
        shape = tuple(s.stop - s.start for s in region)
        arrays = self.arrays()
        for name, *_ in sw.variables():
            arrays[name][region] = np.asarray(result["data"][name]).reshape(shape)
        if not sw.is_grid:
            for f in sw.fields:
                arrays[("coord", f)][region] = np.asarray(result["coords"][f])
        # flush the chunk's files before the record names it
        key = "/".join(str(s.start // c) for s, c in zip(region, sw.chunks))
        names = [name for name, *_ in sw.variables()] + ([] if sw.is_grid else
                                                          [_dim_names(sw)[f] for f in sw.fields])
        for name in names:
            _fsync_path(self.path / name / "c" / key)
            _fsync_path((self.path / name / "c" / key).parent, directory=True)
        rec = self.record
        for code, tpl in result["messages"].items():
            rec.messages.setdefault(str(int(code)), tpl)
        status = np.asarray(result["data"]["status"])
        for code, n in zip(*np.unique(status, return_counts=True)):
            key = STATUS_NAMES.get(int(code), str(int(code)))
            rec.counts[key] = rec.counts.get(key, 0) + int(n)
        rec.add(chunk)
        _write_atomic(self.path / RECORD, rec.to_json())

    def close(self):
        if self._lock is not None:
            self._lock.close()
            self._lock = None


def _open_or_create(path, sw: _sw.Sweep) -> _Store:
    path = Path(path)
    if path.is_symlink():
        raise InvalidInputError(str(path), "is a symbolic link", "give a real folder")
    if not path.exists() or (path.is_dir() and not any(path.iterdir())):
        if not path.parent.exists():
            raise InvalidInputError(str(path), f"its folder {path.parent} does not exist", "create it first")
        _create(path, sw)
    sw2, record = check_store(path, sw)
    return _Store(path, sw2, record)


# ================================================================================================ running
@dataclasses.dataclass(frozen=True)
class SweepSummary:
    """What :func:`run_sweep` did.

    Attributes
    ----------
    store : str
    points, chunks : int
        The sweep's size.
    done_before : int
        Points found done in the store (a resumed sweep).
    computed : int
        Points computed by this run.
    counts : dict
        Points by status over the whole store (``success``, ``infeasible``, ``not_converged``,
        ``invalid``).
    complete : bool
    seconds, rate : float
        This run's wall time and points per second.
    workers : dict
        Per worker (process id): ``{"chunks": chunks computed there, "compiled": integrators
        compiled in that process}`` (one per structure and basis size: it does not grow with
        the chunks).
    messages : dict
        The most frequent message of each status other than success (template with ``#`` for the
        numbers).
    """

    store: str
    points: int
    chunks: int
    done_before: int
    computed: int
    counts: dict
    complete: bool
    seconds: float
    rate: float
    workers: dict
    messages: dict

    def lines(self) -> list[str]:
        out = [f"{self.points} points in {self.chunks} chunks: " +
               ", ".join(f"{self.counts.get(k, 0)} {k}" for k in _sw.STATUS_CODES if self.counts.get(k, 0)) +
               ("" if self.complete else f"; {self.points - sum(self.counts.values())} not computed yet")]
        if self.done_before:
            out.append(f"resumed: {self.done_before} points were done, {self.computed} computed now")
        out.append(f"{self.computed} points in {self.seconds:.1f} s ({self.rate:.0f} points/s)" +
                   (f" on {len(self.workers)} worker(s), integrators compiled per worker: "
                    f"{sorted(w['compiled'] for w in self.workers.values())}" if self.workers else ""))
        for status, tpl in self.messages.items():
            out.append(f"most frequent {status} message: {tpl}")
        out.append(f"wrote {self.store}" + ("" if self.complete else " (incomplete: run again to resume)"))
        return out

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


def _executor(executor, workers: int | None, scheduler: str | None):
    """``(submit-able executor, owned, workers, kind, closer)``."""
    if scheduler is not None:
        if executor is not None:
            raise InvalidInputError("scheduler", "is given together with executor", "give one of them")
        try:
            from distributed import Client
        except ImportError:  # pragma: no cover - a dependency
            raise InvalidInputError("scheduler", "needs dask.distributed", "pip install \"dask[distributed]\"") \
                from None
        try:
            client = Client(scheduler, timeout="20s")
        except (OSError, TimeoutError, ValueError) as e:
            raise InvalidInputError("--scheduler", f"cannot connect to {scheduler} ({type(e).__name__}: {e})",
                                    "give the address of a running dask scheduler, tcp://HOST:PORT") from None
        pool, n, _ = _dask(client)
        return pool, False, n, "dask", client.close
    if executor is None or executor == "process":
        n = int(workers or os.cpu_count() or 1)
        return None, True, n, "process", None
    if executor == "serial":
        return None, False, 1, "serial", None
    if executor == "thread":
        n = int(workers or os.cpu_count() or 1)
        return cf.ThreadPoolExecutor(max_workers=n), True, n, "thread", None
    if type(executor).__module__.startswith("distributed") and hasattr(executor, "get_executor"):
        pool, n, _ = _dask(executor)
        return pool, False, n, "dask", None
    if isinstance(executor, cf.Executor):
        n = int(workers or getattr(executor, "_max_workers", None) or os.cpu_count() or 1)
        return executor, False, n, "executor", None
    raise InvalidInputError("executor", f"must be \"process\", \"thread\", \"serial\", a concurrent.futures.Executor or "
                            f"a dask.distributed.Client, got {type(executor).__name__}",
                            "leave it out for local processes")


def _dask(client):
    info = client.scheduler_info()
    n = sum(int(w.get("nthreads", 1)) for w in info.get("workers", {}).values()) or 1
    return client.get_executor(pure=False), n, info


def _new_pool(n: int):
    return cf.ProcessPoolExecutor(max_workers=n)


def _progress_bar(progress, total: int, initial: int):
    """``(update(done), close())``: a tqdm bar (rate and time left) or a callback or nothing."""
    if callable(progress):
        return (lambda done: progress(done, total)), (lambda: None)
    show = sys.stderr.isatty() if progress is None else bool(progress)
    if not show:
        return (lambda done: None), (lambda: None)
    from tqdm import tqdm

    bar = tqdm(total=total, initial=initial, unit="pt", unit_scale=True, desc="sweep", file=sys.stderr,
               dynamic_ncols=True, smoothing=0.1)

    def update(done):
        bar.update(done - bar.n)

    return update, bar.close


def run_sweep(sweep_: _sw.Sweep, out, *, executor=None, workers: int | None = None, scheduler: str | None = None,
              progress=None, window: int | None = None) -> SweepSummary:
    """Compute a sweep into a zarr store, chunk by chunk; resume it if the store holds part of it.

    Parameters
    ----------
    sweep_ : Sweep
        From :func:`acroplan.sweep` or :func:`load_sweep`.
    out : path
        The store: a new path (created), or a store this definition started (resumed: only the
        chunks not done are computed).
    executor : {"process", "thread", "serial"}, concurrent.futures.Executor or dask.distributed.Client
        Where the chunks are computed: local worker processes (default), or a Dask cluster's
        workers through its client (each worker compiles the integrators once and keeps them), or
        any executor. An executor or client passed in is not shut down.
    workers : int, optional
        Local worker processes (default: one per core).
    scheduler : str, optional
        A Dask scheduler's address (``tcp://HOST:PORT``) to connect to instead of ``executor``.
    progress : bool or callable, optional
        A progress bar on stderr (default: when it is a terminal), or ``progress(done, total)``.
    window : int, optional
        Chunks in flight at once (default: twice the workers, plus two): the memory of the run is
        this many chunks' results, whatever the number of points.

    Returns
    -------
    SweepSummary

    Raises
    ------
    InvalidInputError
        For a store that is refused (module docstring), or bad arguments, before any work.
    """
    if not isinstance(sweep_, _sw.Sweep):
        raise InvalidInputError("sweep", f"must be an acroplan Sweep, got {type(sweep_).__name__}",
                                "build it with acroplan.sweep(...) or load_sweep(path)")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, (int, np.integer))
                                or workers < 1):
        raise InvalidInputError("workers", f"must be a whole number >= 1, got {workers!r}", "leave it out")
    path = Path(out)
    # refuse a bad store before starting any worker
    if path.exists() and not (path.is_dir() and not any(path.iterdir())):
        check_store(path, sweep_)
    pool, owned, n_workers, kind, closer = _executor(executor, workers, scheduler)
    ctx = {"pool": pool}
    t_start = time.perf_counter()
    store = None
    try:
        if kind == "process":
            if multiprocessing.get_start_method(allow_none=True) in (None, "fork"):
                _sw.warm_worker(sweep_)  # forked workers inherit the parent's integrators
            pool = ctx["pool"] = _new_pool(n_workers)
            # start the workers (and compile there) before this process opens the store
            for f in [pool.submit(_sw.warm_worker, sweep_) for _ in range(n_workers)]:
                f.result()
        store = _open_or_create(path, sweep_)
        record = store.record
        done_before_chunks = record.chunks()
        done_before = sum(_chunk_len(sweep_, c) for c in done_before_chunks)
        todo = collections.deque(c for c in range(sweep_.n_chunks) if c not in done_before_chunks)
        update, close_bar = _progress_bar(progress, sweep_.size, done_before)
        state = {"done": done_before, "computed": 0, "workers": {}}

        def finished(result):
            store.write(result)
            n = len(result["points"])
            state["done"] += n
            state["computed"] += n
            if "pid" in result:
                w = state["workers"].setdefault(result["pid"], {"chunks": 0, "compiled": 0})
                w["chunks"] += 1
                w["compiled"] = max(w["compiled"], int(result["compiled"]))
            update(state["done"])

        try:
            if kind == "serial":
                for c in todo:
                    finished(_sw.run_chunk(sweep_, c))
            else:
                _drive(sweep_, ctx, owned, n_workers, todo, finished, window)
        finally:
            close_bar()
        counts = dict(record.counts)
        complete = record.n_done() == sweep_.n_chunks
    finally:
        if store is not None:
            store.close()
        if owned and ctx["pool"] is not None:
            ctx["pool"].shutdown(wait=True, cancel_futures=True)
        if closer is not None:
            closer()
    seconds = time.perf_counter() - t_start
    return SweepSummary(str(path), sweep_.size, sweep_.n_chunks, done_before, state["computed"], counts, complete,
                        seconds, state["computed"] / seconds if seconds > 0 else 0.0, dict(state["workers"]),
                        _frequent(path, sweep_, record) if state["computed"] or done_before else {})


def _chunk_len(sw, c) -> int:
    return int(np.prod([r.stop - r.start for r in sw.chunk_region(c)]))


def _frequent(path: Path, sw: _sw.Sweep, record: _Record) -> dict:
    """The most frequent message template per status other than success, from the store's chunks
    (read chunk by chunk)."""
    import zarr

    try:
        g = zarr.open_group(str(path), mode="r", zarr_format=3, use_consolidated=True)
        status, message = g["status"], g["message"]
        counts: dict = collections.defaultdict(collections.Counter)
        for c in sorted(record.chunks()):
            region = sw.chunk_region(c)
            s, m = np.ravel(status[region]), np.ravel(message[region])
            for code in np.unique(s):
                if int(code) in (0, -1):
                    continue
                counts[STATUS_NAMES.get(int(code), str(code))].update(m[s == code].tolist())
        return {k: record.messages.get(str(v.most_common(1)[0][0]), "?") for k, v in counts.items()}
    except Exception:  # noqa: BLE001 - a summary line must never fail the run
        return {}


def _dead(e: BaseException) -> bool:
    return isinstance(e, cf.BrokenExecutor) or type(e).__name__ in ("KilledWorker", "CancelledError")


def _drive(sw: _sw.Sweep, ctx: dict, owned: bool, n_workers: int, todo: collections.deque, finished: Callable,
           window: int | None) -> None:
    """Keep ``window`` chunks in flight; write each as it finishes. A chunk whose task fails (its
    worker died: the pool broke, or Dask gave up on it) is submitted again; after two failures its
    points are computed one at a time, each alone on the executor, so that only a point that kills
    its worker is marked (``not_converged``, with the reason). ``ctx["pool"]`` is the executor (a
    new one when an owned pool broke)."""
    pool = ctx["pool"]
    window = int(window or 2 * n_workers + 2)
    failures: collections.Counter = collections.Counter()
    suspects: list[int] = []
    inflight: dict = {}

    while todo or inflight:
        broken = None
        while todo and len(inflight) < window:
            c = todo.popleft()
            try:
                inflight[pool.submit(_sw.run_chunk, sw, c)] = c
            except cf.BrokenExecutor as e:  # the pool broke before a task of it said so
                todo.appendleft(c)
                broken = e
                break
        ready = cf.wait(list(inflight), return_when=cf.FIRST_COMPLETED)[0] if inflight and broken is None else ()
        for fut in ready:
            c = inflight.pop(fut)
            try:
                result = fut.result()
            except (Exception, SystemExit) as e:  # noqa: BLE001 - the task failed; decided below
                if isinstance(e, cf.BrokenExecutor):
                    broken = e
                failures[c] += 1
                (suspects if failures[c] >= 2 else todo).append(c)
                continue
            finished(result)
        if broken is not None:
            # every task in flight fails with the pool (those that finished first are kept)
            for fut, c in list(inflight.items()):
                try:
                    result = fut.result()
                except (Exception, SystemExit):  # noqa: BLE001
                    failures[c] += 1
                    (suspects if failures[c] >= 2 else todo).append(c)
                else:
                    finished(result)
                inflight.pop(fut)
            if not owned:
                raise RuntimeError(f"the executor given broke ({type(broken).__name__}: {broken}); "
                                   f"{len(todo) + len(suspects)} chunk(s) are not done: run the sweep again to finish "
                                   "them (what is done is kept)")
            pool.shutdown(wait=True, cancel_futures=True)
            pool = ctx["pool"] = _new_pool(n_workers)
            todo = collections.deque(sorted(todo))
    for c in sorted(suspects):
        _isolate(sw, ctx, owned, n_workers, c, finished)


def _isolate(sw, ctx, owned, n_workers, chunk, finished) -> None:
    """Compute a chunk whose task failed twice point by point, each point alone on the executor."""
    parts = []
    for p in sw.chunk_points(chunk):
        try:
            parts.append(ctx["pool"].submit(_sw.run_chunk, sw, chunk, [int(p)]).result())
        except (Exception, SystemExit) as e:  # noqa: BLE001 - this point kills its worker
            parts.append(_failed_point(sw, chunk, int(p), e))
            if isinstance(e, cf.BrokenExecutor):
                if not owned:
                    raise RuntimeError(f"the executor given broke ({type(e).__name__}: {e}); run the sweep again "
                                       "to finish (what is done is kept)") from None
                ctx["pool"].shutdown(wait=True, cancel_futures=True)
                ctx["pool"] = _new_pool(n_workers)
    data = {k: np.concatenate([r["data"][k] for r in parts]) for k in parts[0]["data"]}
    coords = {k: np.concatenate([r["coords"][k] for r in parts]) for k in parts[0]["coords"]}
    messages = {}
    for r in parts:
        messages.update(r["messages"])
    finished({"chunk": chunk, "points": sw.chunk_points(chunk), "data": data, "coords": coords, "messages": messages})


def _failed_point(sw, chunk, p, e) -> dict:
    data = {name: np.full(1, fill, dtype=dtype) for name, dtype, fill, _ in sw.variables()}
    msg = f"not converged: the worker computing this point died or failed ({type(e).__name__}: {e})"
    code, tpl = _sw.message_code(msg)
    data["status"][0] = _sw.STATUS_CODES["not_converged"]
    data["message"][0] = code
    return {"chunk": chunk, "points": np.array([p]), "data": data, "coords": sw.values([p]), "messages": {code: tpl}}


# ================================================================================================ reading
def open_sweep(path, *, complete: bool = False):
    """The store as an xarray Dataset (lazy, chunked as written).

    Points of chunks the completion record does not name are masked (``status`` -1, NaN, fill
    values), whatever their files hold: a chunk half written by a killed run is never read as done.
    The attributes add ``messages`` (the message table, JSON: code -> template), ``chunks_done``,
    ``complete`` and ``definition`` (the sweep's canonical JSON).

    Parameters
    ----------
    path : path of a store
    complete : bool
        Refuse a store that is not complete.

    Raises
    ------
    InvalidInputError
        For a store that is not an acroplan sweep store, or is corrupt (module docstring).
    """
    import xarray as xr

    sw, record = check_store(path)
    if complete and record.n_done() != sw.n_chunks:
        raise InvalidInputError(str(path), f"is not complete ({record.n_done()} of {sw.n_chunks} chunks)",
                                "run the sweep again to finish it")
    ds = xr.open_zarr(str(path), consolidated=True, mask_and_scale=False, decode_times=False)
    done = record.chunks()
    if len(done) != sw.n_chunks:
        mask = np.zeros(sw.shape, dtype=bool)
        for c in done:
            mask[sw.chunk_region(c)] = True
        cond = xr.DataArray(mask, dims=list(ds["status"].dims))
        for name, _dtype, fill, _ in sw.variables():
            ds[name] = ds[name].where(cond, fill)
        if not sw.is_grid:
            for f in sw.fields:
                n = _dim_names(sw)[f]
                if ds[n].dtype.kind == "f":
                    ds[n] = ds[n].where(cond)
    for name, _dtype, fill, _ in sw.variables():
        if ds[name].dtype.kind == "f":
            ds[name].attrs["_FillValue_note"] = "NaN where not computed or not applicable"
    ds.attrs.update({"messages": json.dumps(record.messages, sort_keys=True), "chunks_done": record.n_done(),
                     "chunks": sw.n_chunks, "complete": record.n_done() == sw.n_chunks, "definition": sw.json})
    return ds


# ================================================================================================ maps
def _name_in(ds, name: str, what: str, field_names: dict) -> str:
    if name in ds.variables:
        return name
    if name in field_names:
        return field_names[name]
    for short, full in field_names.items():
        if full.endswith(f".{name}") or short.endswith(f".{name}"):
            return full if full in ds.variables else short
    known = sorted(set(ds.data_vars) | set(ds.coords)) if what == "--value" else sorted(ds.coords)
    raise InvalidInputError(what, f"{name!r} is not in the store", f"known: {known}")


def draw_map(store, x: str, y: str, value: str, path=None, *, kind: str = "heatmap", at: Mapping | None = None,
             title: str | None = None):
    """A map of ``value`` over the fields ``x`` and ``y`` of a sweep store: a heatmap or filled
    contours on a grid, coloured points (or triangulated contours) for a sample. Infeasible points
    are marked apart (grey, hatched ``//``), and failed ones (not converged, invalid) with red
    crosses; points not computed stay blank.

    Parameters
    ----------
    store : path or xarray.Dataset
        A sweep store (or :func:`open_sweep`'s Dataset).
    x, y : str
        Swept fields (``"T"``, ``"scale"``, or full names ``"plan.T"``).
    value : str
        A recorded variable (``"least_P0"``, ``"effort"``, ``"peak_torque"``, ``"status"``, ...).
    path : path, optional
        Write the figure there (``.png`` or ``.pdf``).
    kind : {"heatmap", "contour"}
    at : mapping, optional
        Values of the grid's other fields (the nearest grid value is taken), e.g. ``{"P0": 10}``.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        Built without pyplot: the caller's matplotlib backend is left as it is.
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    if kind not in ("heatmap", "contour"):
        raise InvalidInputError("--kind", f"must be \"heatmap\" or \"contour\", got {kind!r}", "give heatmap")
    if path is not None and Path(path).suffix.lower() not in (".png", ".pdf"):
        raise InvalidInputError("--out", f"{path}: the map is written as .png or .pdf", "give for example map.png")
    ds = store if hasattr(store, "data_vars") else open_sweep(store)
    field_names = {}
    for name in ds.coords:
        full = ds[name].attrs.get("field")
        if full:
            field_names[full] = name
            field_names[full.split(".", 1)[1]] = name
    xn, yn = (_name_in(ds, n, w, field_names) for n, w in ((x, "--x"), (y, "--y")))
    vn = _name_in(ds, value, "--value", field_names)
    if xn == yn:
        raise InvalidInputError("--y", "is the same field as --x", "give two different fields")
    if vn not in ds.data_vars:
        raise InvalidInputError("--value", f"{value!r} is a coordinate, not a recorded quantity",
                                f"known: {sorted(ds.data_vars)}")
    grid = "point" not in ds.dims
    sel = {}
    for name, v in dict(at or {}).items():
        n = _name_in(ds, name, "--at", field_names)
        if n not in ds.dims:
            raise InvalidInputError("--at", f"{name!r} is not a grid dimension", f"dimensions: {list(ds.dims)}")
        sel[n] = v
    if grid:
        for n in (xn, yn):
            if n not in ds.dims:
                raise InvalidInputError("--x" if n == xn else "--y", f"{n!r} is not a grid dimension",
                                        f"dimensions: {list(ds.dims)}")
        if sel:
            try:
                ds = ds.sel(sel, method="nearest")
            except (TypeError, ValueError, KeyError):
                ds = ds.sel(sel)
        rest = [d for d in ds.dims if d not in (xn, yn) and ds.sizes[d] > 1]
        if rest:
            raise InvalidInputError("--at", f"the grid has more dimensions than x and y: {rest}",
                                    "fix them, for example --at " + ",".join(f"{d}={ds[d].values[0]}" for d in rest))
        ds = ds.isel({d: 0 for d in ds.dims if d not in (xn, yn)}, drop=True)
        ds = ds.transpose(yn, xn)
    status = np.asarray(ds["status"].values)
    val = np.asarray(ds[vn].values, dtype=float)
    ok = (status == 0) & np.isfinite(val)
    infeasible = status == 1
    failed = (status == 2) | (status == 3)
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    ax = fig.add_subplot()
    label = ds[vn].attrs.get("description", vn)
    units = ds[vn].attrs.get("units")
    cbar_label = vn + (f" ({units})" if units else "")
    categorical = vn == "status"
    if categorical:
        cmap = ListedColormap(["#1a7f37", "#bbbbbb", "#cf222e", "#8250df"])
        val = np.where(status >= 0, status, np.nan).astype(float)
        ok = status >= 0
    else:
        cmap = "viridis"
    handles = []
    if grid:
        X, Y = np.asarray(ds[xn].values, dtype=float), np.asarray(ds[yn].values, dtype=float)
        Z = np.where(ok, val, np.nan)
        if kind == "heatmap" or categorical or min(len(X), len(Y)) < 2:
            m = ax.pcolormesh(_edges(X), _edges(Y), np.ma.masked_invalid(Z), cmap=cmap, shading="flat",
                              **({"vmin": -0.5, "vmax": 3.5} if categorical else {}))
        else:
            m = ax.contourf(X, Y, np.ma.masked_invalid(Z), levels=12, cmap=cmap)
            lines = ax.contour(X, Y, np.ma.masked_invalid(Z), levels=m.levels, colors="k", linewidths=0.4)
            ax.clabel(lines, lines.levels[::2], fmt="%.4g", fontsize=7)
        if not categorical and infeasible.any():
            ax.pcolor(_edges(X), _edges(Y), np.ma.masked_where(~infeasible, np.ones_like(Z)), cmap=ListedColormap(
                ["#d0d0d0"]), hatch="//", edgecolor="#888888", linewidth=0.0, shading="flat")
        PX, PY = np.meshgrid(X, Y)
    else:
        PX, PY = np.asarray(ds[xn].values, dtype=float), np.asarray(ds[yn].values, dtype=float)
        if kind == "contour" and not categorical and ok.sum() >= 3:
            m = ax.tricontourf(PX[ok], PY[ok], val[ok], levels=12, cmap=cmap)
        else:
            m = ax.scatter(PX[ok], PY[ok], c=val[ok], cmap=cmap, s=14,
                           **({"vmin": -0.5, "vmax": 3.5} if categorical else {}))
        if not categorical and infeasible.any():
            ax.scatter(PX[infeasible], PY[infeasible], s=14, c="#bbbbbb", marker="s")
    if not categorical and infeasible.any():
        handles.append(Patch(facecolor="#d0d0d0", edgecolor="#888888", hatch="//",
                             label=f"infeasible ({int(infeasible.sum())})"))
    if not categorical and failed.any():
        ax.plot(PX[failed], PY[failed], "x", color="#cf222e", ms=6, mew=1.5)
        handles.append(Line2D([], [], marker="x", color="#cf222e", ls="", label=f"failed ({int(failed.sum())})"))
    missing = int((status < 0).sum())
    if missing:
        handles.append(Patch(facecolor="white", edgecolor="#888888", label=f"not computed ({missing})"))
    cb = fig.colorbar(m, ax=ax, label=cbar_label)
    if categorical:
        cb.set_ticks([0, 1, 2, 3], labels=list(_sw.STATUS_CODES))
    ax.set_xlabel(_axis_label(ds, xn))
    ax.set_ylabel(_axis_label(ds, yn))
    ax.set_title(title or (label if len(label) <= 70 else vn), fontsize=10)
    if handles:
        ax.legend(handles=handles, loc="best", fontsize=8, framealpha=0.9)
    if path is not None:
        fig.savefig(path, dpi=130)
    return fig


def _edges(c: np.ndarray) -> np.ndarray:
    """Cell edges around grid values (midpoints; ends mirrored)."""
    c = np.asarray(c, dtype=float)
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def _axis_label(ds, name) -> str:
    full = ds[name].attrs.get("field", name)
    return name if full == name else f"{name}  ({full})"


# ================================================================================================ command line
def _fail(message: str, code: int = EXIT_INVALID):
    import click

    text = str(message).replace("\n", "\\n")
    click.echo(click.style("acroplan: error: ", fg="red", bold=True) + text, err=True)
    sys.exit(code)


def _commands():
    import click

    @click.command("sweep")
    @click.argument("sweep_file", metavar="SWEEP.toml", type=click.Path(dir_okay=False, path_type=Path))
    @click.option("--out", "out", required=True, type=click.Path(path_type=Path),
                  help="The store (a zarr folder): created, or resumed when this sweep started it.")
    @click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on a Dask cluster (its scheduler's address).")
    @click.option("--workers", type=click.IntRange(1, 4096), help="Local worker processes (default: one per core).")
    @click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
    @click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON on stdout.")
    def sweep_cmd(sweep_file, out, scheduler, workers, quiet, as_json):
        """Compute the sweep SWEEP.toml (a problem file with a [sweep] table) into the store OUT.

        \b
        The store is an xarray Dataset in zarr (read it with xarray.open_zarr, or acroplan's
        open_sweep): per point status, message code, effort, peak rate and torque, errors,
        evaluations, wall time and the derived quantities, with the definition and the acroplan
        version in its attributes. Killed at any moment, the same command resumes it: only the
        chunks not written are computed. A progress bar (rate, time left) on a terminal; a summary
        by status at the end. Exit codes: 0 complete, 2 invalid sweep or store refused.

        \b
        Examples:
          acroplan sweep least-p0.toml --out least-p0.zarr
          acroplan sweep effort.toml --out effort.zarr --scheduler tcp://10.0.0.5:8786
          acroplan map least-p0.zarr --x T --y scale --value least_P0 --out least-p0.png
        """
        try:
            sw = load_sweep(sweep_file)
            summary = run_sweep(sw, out, workers=workers, scheduler=scheduler)
        except InvalidInputError as e:
            _fail(str(e))
        except KeyboardInterrupt:
            _fail(f"interrupted: what is done is in {out}; run the same command again to resume", 130)
        if as_json:
            click.echo(json.dumps(summary.to_dict(), default=str))
        elif not quiet:
            for line in summary.lines():
                click.echo(line)
        sys.exit(EXIT_SUCCESS if summary.complete else 1)

    @click.command("map")
    @click.argument("store", type=click.Path(path_type=Path))
    @click.option("--x", "x", required=True, help="Swept field on the x axis (T, scale, P0, plan.T, ...).")
    @click.option("--y", "y", required=True, help="Swept field on the y axis.")
    @click.option("--value", "value", required=True, help="Quantity to map: least_P0, effort, peak_torque, status, ...")
    @click.option("--out", "out", required=True, type=click.Path(dir_okay=False, path_type=Path),
                  help="Figure file: .png or .pdf.")
    @click.option("--kind", type=click.Choice(["heatmap", "contour"]), default="heatmap", show_default=True)
    @click.option("--at", "at", multiple=True, metavar="FIELD=VALUE", help="Fix another grid field (repeatable).")
    @click.option("--title", help="Title of the map.")
    @click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
    def map_cmd(store, x, y, value, out, kind, at, title, quiet):
        """Draw a map of a sweep store: VALUE over the fields X and Y, as a heatmap or contours.

        \b
        Infeasible points are marked apart (grey, hatched) and failed ones (not converged,
        invalid) with red crosses; points not computed yet stay blank.

        \b
        Example:
          acroplan map least-p0.zarr --x T --y scale --value least_P0 --out least-p0.png
        """
        import matplotlib

        matplotlib.use("Agg")
        try:
            fixed = {}
            for item in at:
                name, sep, v = item.partition("=")
                if not sep or not name:
                    raise InvalidInputError("--at", f"{item!r} is not FIELD=VALUE", "give for example --at P0=10")
                try:
                    fixed[name] = float(v)
                except ValueError:
                    fixed[name] = v
            draw_map(store, x, y, value, out, kind=kind, at=fixed, title=title)
        except InvalidInputError as e:
            _fail(str(e))
        if not quiet:
            click.echo(f"wrote {out}")

    return sweep_cmd, map_cmd


#: The ``acroplan sweep`` and ``acroplan map`` commands (click), to register on the CLI's group:
#: ``main.add_command(sweep_cmd); main.add_command(map_cmd)``.
sweep_cmd, map_cmd = _commands()
