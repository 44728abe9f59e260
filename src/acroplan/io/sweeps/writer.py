"""Creating a store and writing chunks into it.

A store is created whole or not at all: built under ``.STORE.creating-PID-TOKEN`` beside it (its lock
already held by the creating run), then renamed into place; a marker left by a killed run is
removed by the next run once its process is gone. Two runs starting together on a new store: one
rename wins; the other finds the store being written and says so. A chunk is written into its own
region of every array and flushed (fsync), its checksum recorded and flushed, and only then is it
named in the completion record, which is replaced atomically.
"""

from __future__ import annotations

import fcntl
import math
import os
import re
import secrets
import shutil
import warnings
from pathlib import Path

import numpy as np

from ...core.errors import InvalidInputError
from ...sweeps.definition import Sweep
from ...sweeps.vocabulary import FORMAT, PointStatus, STATUS_CODES
from .check import acroplan_version, block_names, check_store
from .layout import (ATTR_DEF, ATTR_FORMAT, ATTR_HASH, ATTR_VERSION, LOCK, RECORD, FIX_NEW, dim_names, fsync_path,
                     pid_alive, write_atomic)
from .record import Checksums, Record, chunk_digest, ranges_of

__all__ = ["open_or_create", "Store", "clean_stale", "COORD_CHUNK"]

#: Values per chunk of a grid's coordinate arrays (written slice by slice).
COORD_CHUNK = 1 << 18
_MARKER = re.compile(r"^\.creating-(\d+)(?:-[0-9a-f]+)?$")


def clean_stale(path: Path) -> list[Path]:
    """Remove the ``.STORE.creating-PID[-TOKEN]`` folders beside ``path`` whose process is gone;
    returns them."""
    removed = []
    for marker in path.parent.glob(f".{path.name}.creating-*"):
        m = _MARKER.match(marker.name[len(path.name) + 1:])
        if m and not pid_alive(int(m.group(1))):
            shutil.rmtree(marker, ignore_errors=True)
            removed.append(marker)
    return removed


def _coordinates(g, sw: Sweep, names: dict) -> None:
    for f, dtype in sw.coordinate_dtypes().items():
        a = {"field": f, "description": f"the swept field {f}"}
        if sw.is_grid:
            axis = sw.axes[f]
            n = len(axis)
            arr = g.create_array(names[f], shape=(n,), chunks=(min(n, COORD_CHUNK),), dtype=dtype,
                                 dimension_names=[names[f]], attributes=a,
                                 **({} if dtype.kind in "UST" else {"fill_value": 0}))
            for start in range(0, n, COORD_CHUNK):
                stop = min(n, start + COORD_CHUNK)
                arr[start:stop] = axis.slice(start, stop)
        else:
            g.create_array(names[f], shape=sw.shape, chunks=sw.chunks, dtype=dtype, dimension_names=["point"],
                           attributes=a, **({"fill_value": math.nan} if dtype.kind == "f" else {}))


def _build(tmp: Path, sw: Sweep) -> None:
    """The store's group, arrays, coordinates, consolidated metadata, empty record and checksums,
    flushed."""
    import zarr

    attrs = {ATTR_DEF: sw.json, ATTR_HASH: sw.hash, ATTR_VERSION: acroplan_version(), ATTR_FORMAT: FORMAT,
             "title": "acroplan sweep", "dims": list(sw.dims), "fields": list(sw.fields), "statuses": STATUS_CODES}
    g = zarr.open_group(str(tmp), mode="w-", zarr_format=3, attributes=attrs)
    names = dim_names(sw)
    dims = [names[f] for f in sw.fields] if sw.is_grid else ["point"]
    coords = " ".join(names[f] for f in sw.fields) if not sw.is_grid else None
    for name, dtype, fill, var_attrs in sw.variables():
        a = dict(var_attrs, **({"coordinates": coords} if coords else {}))
        g.create_array(name, shape=sw.shape, chunks=sw.chunks, dtype=dtype, fill_value=fill, dimension_names=dims,
                       attributes=a)
    _coordinates(g, sw, names)
    zarr.consolidate_metadata(str(tmp))  # read without listing the folder
    (tmp / RECORD).write_text(Record([], {}, {}, sw.hash).to_json(), encoding="utf-8")
    Checksums(tmp).create(sw.n_chunks)
    for root, _dirs, files in os.walk(tmp):
        for f in files:
            fsync_path(Path(root) / f)
        fsync_path(Path(root), directory=True)


def _lock(path: Path):
    """The store's lock file, opened and locked, or ``None`` when another run holds it."""
    fh = open(path / LOCK, "a+")
    try:
        fcntl.flock(fh.fileno(), fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        fh.close()
        return None
    fh.seek(0)
    fh.truncate()
    fh.write(str(os.getpid()))
    fh.flush()
    return fh


def _create(path: Path, sw: Sweep):
    """Create the store whole, its lock held: ``(lock, raced)``; ``lock`` is ``None`` and ``raced``
    true when another run created it first (two runs starting together)."""
    tmp = path.with_name(f".{path.name}.creating-{os.getpid()}-{secrets.token_hex(4)}")
    shutil.rmtree(tmp, ignore_errors=True)
    try:
        with warnings.catch_warnings():
            # zarr's notes on text coordinates and consolidated metadata, which this store reads itself
            warnings.filterwarnings("ignore", module=r"zarr(\.|$)")
            _build(tmp, sw)
        lock = _lock(tmp)
        try:
            os.rename(tmp, path)  # onto nothing, or onto an empty folder
        except OSError:
            lock.close()
            if (path / "zarr.json").exists():
                return None, True
            raise InvalidInputError(str(path), "exists and is not empty, and is not a sweep store", FIX_NEW) from None
        fsync_path(path.parent, directory=True)
        return lock, False
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


class Store:
    """An open store being written by this process (holds its lock)."""

    def __init__(self, path: Path, sw: Sweep, record: Record, lock=None, raced: bool = False):
        self.path, self.sweep, self.record = path, sw, record
        self._lock = lock or _lock(path)
        if self._lock is None:
            try:
                who = (path / LOCK).read_text().strip()
            except OSError:
                who = ""
            pid = f" (pid {who})" if who else ""
            if raced:
                raise InvalidInputError(str(path), f"was created by another run{pid} that started at the same time "
                                        "as this one, and is being written by it", "wait for it to finish; running "
                                        "this command again then resumes it (nothing is computed twice)")
            raise InvalidInputError(str(path), f"is being written by another run{pid}",
                                    "wait for it to finish, or stop it; then run again to resume")
        self._arrays = None
        self._sums = Checksums(path, writable=True)
        # what a killed run may have left: the record's temporary file
        for leftover in path.glob(f".{RECORD}.tmp-*"):
            leftover.unlink(missing_ok=True)

    def arrays(self) -> dict:
        """The zarr arrays a chunk is written into, by key (:func:`~.check.block_names`)."""
        if self._arrays is None:
            import zarr

            g = zarr.open_group(str(self.path), mode="r+", zarr_format=3, use_consolidated=True)
            self._arrays = {key: g[name] for key, name in block_names(self.sweep).items()}
        return self._arrays

    def reset(self, good: np.ndarray, counts: dict) -> None:
        """Make the record name exactly the ``good`` chunks, with ``counts`` (re-derived from them)."""
        self.record.done = ranges_of(good)
        self.record.counts = dict(counts)
        self.record.format = FORMAT
        write_atomic(self.path / RECORD, self.record.to_json())

    def write(self, result: dict) -> None:
        """Write a computed chunk into its region, flush it, record its checksum, then mark it done."""
        sw = self.sweep
        chunk = int(result["chunk"])
        region = sw.chunk_region(chunk)
        shape = tuple(s.stop - s.start for s in region)
        blocks = {}
        for key, arr in self.arrays().items():
            src = result["coords"][key[1]] if isinstance(key, tuple) else result["data"][key]
            block = np.ascontiguousarray(np.asarray(src).astype(arr.dtype, copy=False).reshape(shape))
            arr[region] = block
            blocks[key if isinstance(key, str) else dim_names(sw)[key[1]]] = block
        # flush the chunk's files before the checksum and the record name it
        key = "/".join(str(s.start // c) for s, c in zip(region, sw.chunks))
        for name in blocks:
            fsync_path(self.path / name / "c" / key)
            fsync_path((self.path / name / "c" / key).parent, directory=True)
        self._sums.put(chunk, chunk_digest(sw.hash, chunk, blocks))
        rec = self.record
        for code, tpl in result["messages"].items():
            rec.messages.setdefault(str(int(code)), tpl)
        status = blocks["status"]
        for code, n in zip(*np.unique(status, return_counts=True)):
            st = PointStatus.from_code(int(code))
            name = st.value if st is not None else str(int(code))
            rec.counts[name] = rec.counts.get(name, 0) + int(n)
        rec.add(chunk)
        write_atomic(self.path / RECORD, rec.to_json())

    def close(self):
        self._sums.close()
        if self._lock is not None:
            self._lock.close()
            self._lock = None


def open_or_create(path, sw: Sweep) -> Store:
    """The store at ``path``, created for ``sw`` when the path does not exist (or is an empty folder),
    checked against ``sw`` otherwise; its lock held."""
    path = Path(path)
    if path.is_symlink():
        raise InvalidInputError(str(path), "is a symbolic link", "give a real folder")
    if not path.parent.exists():
        raise InvalidInputError(str(path), f"its folder {path.parent} does not exist", "create it first")
    clean_stale(path)
    lock, raced = None, False
    if not path.exists() or (path.is_dir() and not any(path.iterdir())):
        lock, raced = _create(path, sw)
    try:
        sw2, record, _fmt = check_store(path, sw)
        return Store(path, sw2, record, lock=lock, raced=raced)
    except BaseException:
        if lock is not None:
            lock.close()
        raise
