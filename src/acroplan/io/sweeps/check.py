"""Checking a store: its metadata against the layout (:func:`check_store`) and each done chunk's
data against its checksum (:func:`verify_chunks`).

A store is refused (:class:`InvalidInputError`, exit code 2 on the command line), naming what is
wrong, when it is not a zarr store, not an acroplan sweep store, corrupt (unreadable metadata or
record, a definition that does not match the SHA-256 beside it, arrays missing or of the wrong
shape), written by another acroplan version, or written for another definition (the first
differing field is named). The SHA-256 only detects accidental damage: anyone can write a store
whose definition matches it, so it authenticates nothing; nothing a store names is ever imported.
"""

from __future__ import annotations

import collections
import dataclasses
import hashlib
import json
import sys
from pathlib import Path

import numpy as np

from ...core.errors import InvalidInputError
from ...sweeps.definition import Sweep, from_definition
from ...sweeps.vocabulary import FORMAT, READABLE_FORMATS, PointStatus
from .layout import (ATTR_DEF, ATTR_FORMAT, ATTR_HASH, ATTR_VERSION, FIX_NEW, RECORD, corrupt, diff, dim_names,
                     read_json)
from .record import Checksums, Record, chunk_digest

#: The largest zarr.json read (a definition records each grid axis as given: a list of values given
#: in full is the only part that grows, by about 20 bytes a value).
MAX_METADATA = 256 * 2**20

__all__ = ["MAX_METADATA", "check_store", "verify_chunks", "Verification", "block_names", "describe_chunks",
           "acroplan_version"]


def acroplan_version() -> str:
    """This acroplan's version (the package is imported whenever this module is)."""
    return sys.modules["acroplan"].__version__


def _metadata(store: Path) -> dict:
    if not store.exists():
        raise InvalidInputError(str(store), "no such store", "run the sweep first: acroplan sweep SWEEP.toml --out "
                                f"{store}")
    if not store.is_dir():
        raise InvalidInputError(str(store), "is not a sweep store (it is a file)", FIX_NEW)
    meta_path = store / "zarr.json"
    if not meta_path.exists():
        raise InvalidInputError(str(store), "is not an acroplan sweep store (no zarr.json: not a zarr store)", FIX_NEW)
    if meta_path.stat().st_size > MAX_METADATA:
        raise corrupt(store, f"its zarr.json has {meta_path.stat().st_size} bytes (a sweep's has at most "
                      f"{MAX_METADATA})")
    try:
        meta = json.loads(meta_path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise corrupt(store, f"zarr.json cannot be read ({type(e).__name__})") from None
    attrs = meta.get("attributes") if isinstance(meta, dict) else None
    if not isinstance(attrs, dict) or ATTR_DEF not in attrs:
        raise InvalidInputError(str(store), "is a zarr store, but not one acroplan sweep wrote (its attributes hold "
                                f"no {ATTR_DEF})", FIX_NEW)
    return meta


def _definition(store: Path, attrs: dict, sweep_: Sweep | None) -> dict:
    fmt = attrs.get(ATTR_FORMAT)
    if fmt not in READABLE_FORMATS:
        raise InvalidInputError(str(store), f"has store format {fmt!r}; this acroplan reads formats "
                                f"{list(READABLE_FORMATS)}", "use the acroplan version that wrote it, or a new store")
    text, stored_hash = attrs.get(ATTR_DEF), attrs.get(ATTR_HASH)
    try:
        definition = json.loads(text)
        ok = isinstance(definition, dict) and hashlib.sha256(text.encode("ascii")).hexdigest() == stored_hash
    except (TypeError, ValueError, UnicodeEncodeError):
        ok = False
    if not ok:
        raise corrupt(store, f"the definition in its attributes does not match its hash ({ATTR_HASH}: a check "
                      "against accidental damage, not a signature)")
    if sweep_ is not None and fmt != FORMAT:
        raise InvalidInputError(str(store), f"was written in store format {fmt} (no chunk checksums): it can be read "
                                "(open_sweep, acroplan map), not resumed", "start the sweep in a new store")
    if sweep_ is not None and sweep_.hash != stored_hash:
        where = diff(definition, sweep_.definition) or "the definition"
        raise InvalidInputError(str(store), f"holds another sweep: {where} differs",
                                "resume it with the definition that wrote it, or give a new store for this one")
    version = attrs.get(ATTR_VERSION)
    if sweep_ is not None and version != acroplan_version():
        raise InvalidInputError(str(store), f"was written by acroplan {version}, this is {acroplan_version()} (a "
                                "result may differ between versions)", f"finish it with acroplan {version}, or start "
                                "a new store")
    return definition


def _expected(sw: Sweep) -> dict:
    expect = {name: (dtype, sw.shape, sw.chunks) for name, dtype, _, _ in sw.variables()}
    names = dim_names(sw)
    for f in sw.fields:
        if sw.is_grid:
            expect[names[f]] = (None, (sw.shape[sw.fields.index(f)],), None)
        else:
            expect[names[f]] = (None, sw.shape, sw.chunks)
    return expect


def _check_arrays(store: Path, meta: dict, sw: Sweep) -> None:
    consolidated = (meta.get("consolidated_metadata") or {}).get("metadata") or {}
    for name, (dtype, shape, chunks) in _expected(sw).items():
        m = consolidated.get(name)
        if not (store / name / "zarr.json").exists() or not isinstance(m, dict):
            raise corrupt(store, f"its array {name!r} is missing")
        got_shape = tuple(m.get("shape") or ())
        got_chunks = tuple(((m.get("chunk_grid") or {}).get("configuration") or {}).get("chunk_shape") or ())
        if got_shape != tuple(shape) or (chunks is not None and got_chunks != tuple(chunks)) or \
                (dtype is not None and str(m.get("data_type")) != dtype):
            raise corrupt(store, f"its array {name!r} has shape {got_shape}, chunks {got_chunks}, type "
                          f"{m.get('data_type')}; the sweep needs {tuple(shape)}, {chunks}, {dtype}")


def _record(store: Path, sw: Sweep, stored_hash: str) -> Record:
    rec = read_json(store / RECORD, store, "completion record")
    try:
        done = [[int(a), int(b)] for a, b in rec["done"]]
        record = Record(done, {str(k): str(v) for k, v in dict(rec["messages"]).items()},
                        {str(k): int(v) for k, v in dict(rec["counts"]).items()}, str(rec["hash"]),
                        int(rec.get("format", 1)))
        valid = record.hash == stored_hash and all(0 <= a < b <= sw.n_chunks for a, b in done) and \
            all(done[i][1] < done[i + 1][0] for i in range(len(done) - 1))
    except (KeyError, TypeError, ValueError):
        valid = False
    if not valid:
        raise corrupt(store, f"its completion record ({RECORD}) does not describe this store")
    return record


def check_store(path, sweep_: Sweep | None = None) -> tuple[Sweep, Record, int]:
    """Validate an existing store's metadata (against ``sweep_`` when given: a resume) and return
    its sweep, its completion record and its store format. The chunks' data is checked by
    :func:`verify_chunks`. Nothing the store names is imported (:func:`acroplan.sweeps.from_definition`).

    Raises
    ------
    InvalidInputError
        Naming the store and what is wrong (module docstring).
    """
    store = Path(path)
    meta = _metadata(store)
    attrs = meta["attributes"]
    definition = _definition(store, attrs, sweep_)
    try:
        sw = sweep_ if sweep_ is not None else from_definition(definition)
        _check_arrays(store, meta, sw)
    except InvalidInputError as e:
        if e.field == str(store):
            raise
        raise corrupt(store, f"its definition cannot be read ({e})") from None
    except (KeyError, TypeError, ValueError, AttributeError, IndexError) as e:
        raise corrupt(store, f"its definition cannot be read ({type(e).__name__}: {e})") from None
    return sw, _record(store, sw, attrs[ATTR_HASH]), int(attrs[ATTR_FORMAT])


# ---------------------------------------------------------------------------------------------- the chunks
def block_names(sw: Sweep) -> dict[str, str]:
    """The arrays a chunk's checksum covers, by key: the variables, and a sample's coordinates
    (key ``("coord", field)``, array name the field's name in the store)."""
    out = {name: name for name, *_ in sw.variables()}
    if not sw.is_grid:
        names = dim_names(sw)
        out.update({("coord", f): names[f] for f in sw.fields})
    return out


@dataclasses.dataclass
class Verification:
    """What :func:`verify_chunks` found: ``good`` (one flag per chunk: done and matching its
    checksum), ``bad`` (``[(chunk, why), ...]`` of chunks the record names that do not),
    ``counts`` (points by status over the good chunks) and ``codes`` (per status, message code
    -> points)."""

    good: np.ndarray
    bad: list
    counts: dict
    codes: dict
    checked: bool

    def n_good(self) -> int:
        return int(self.good.sum())


def _read_blocks(arrays: dict, names: dict, region) -> dict:
    return {names[key]: np.asarray(arrays[key][region]) for key in names}


def _tally(ver: Verification, blocks: dict) -> None:
    status, message = np.ravel(blocks["status"]), np.ravel(blocks["message"])
    for code in np.unique(status):
        st = PointStatus.from_code(int(code))
        key = st.value if st is not None else str(int(code))
        ver.counts[key] = ver.counts.get(key, 0) + int((status == code).sum())
        if st is not None and not st.success:
            ver.codes.setdefault(key, collections.Counter()).update(message[status == code].tolist())


def verify_chunks(path, sw: Sweep, record: Record, fmt: int) -> Verification:
    """Read every chunk the record names, one at a time, and compare it with its checksum; count
    the good chunks' points by status (the record's counts, re-derived). A store of format 1 has
    no checksums: its chunks are counted, not checked (``checked`` False).
    """
    import zarr

    store = Path(path)
    ver = Verification(np.zeros(sw.n_chunks, dtype=bool), [], {}, {}, fmt >= 2)
    g = zarr.open_group(str(store), mode="r", zarr_format=3, use_consolidated=True)
    names = block_names(sw)
    arrays = {key: g[name] for key, name in names.items()}
    sums = Checksums(store)
    try:
        for c in record.chunks():
            stored = sums.get(c) if ver.checked else b""
            if ver.checked and stored is None:
                ver.bad.append((c, "has no checksum (it was never written whole)"))
                continue
            try:
                blocks = _read_blocks(arrays, names, sw.chunk_region(c))
            except Exception as e:  # noqa: BLE001 - a damaged chunk file, whatever the codec says
                ver.bad.append((c, f"cannot be read ({type(e).__name__})"))
                continue
            if ver.checked and chunk_digest(sw.hash, c, blocks) != stored:
                ver.bad.append((c, "does not match its checksum"))
                continue
            ver.good[c] = True
            _tally(ver, blocks)
    finally:
        sums.close()
    return ver


def describe_chunks(sw: Sweep, bad: list, most: int = 5) -> str:
    """``chunk 3 (P0[3:4], T[0:5]) does not match its checksum; ...`` for the first ``most``."""
    names = dim_names(sw)
    dims = [names[f] for f in sw.fields] if sw.is_grid else ["point"]
    parts = []
    for c, why in bad[:most]:
        where = ", ".join(f"{d}[{s.start}:{s.stop}]" for d, s in zip(dims, sw.chunk_region(c)))
        parts.append(f"chunk {c} ({where}) {why}")
    more = f"; and {len(bad) - most} more" if len(bad) > most else ""
    return "; ".join(parts) + more
