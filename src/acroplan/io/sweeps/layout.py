"""A sweep store's layout: its files' names, its attributes, the variables' names in it, and the
file operations every part of it uses (flushed writes, atomic replacement, live processes).

A store is a zarr (format 3) group, written by this package only::

    STORE/zarr.json               the group: attributes (the sweep's canonical definition, its
                                  SHA-256, the acroplan version, the layout's format) and the
                                  consolidated metadata of every array
    STORE/<variable>/...          one array per recorded variable (status, message, effort, ...),
                                  chunked as the sweep's chunks; the swept fields' coordinates
    STORE/acroplan-sweep.json     the completion record: which chunks are done, the message table,
                                  counts by status
    STORE/acroplan-chunks.sha256  each done chunk's SHA-256 (32 bytes per chunk, in chunk order)
    STORE/acroplan.lock           held (flock) by the run writing the store
"""

from __future__ import annotations

import collections
import json
import os
from pathlib import Path

from ...core.errors import InvalidInputError

__all__ = ["RECORD", "LOCK", "CHECKSUMS", "ATTR_DEF", "ATTR_HASH", "ATTR_VERSION", "ATTR_FORMAT", "dim_names",
           "fsync_path", "write_atomic", "read_json", "corrupt", "diff", "pid_alive", "FIX_NEW", "FIX_CORRUPT"]

#: The completion record's file name inside a store.
RECORD = "acroplan-sweep.json"
#: The lock file's name inside a store.
LOCK = "acroplan.lock"
#: The chunks' checksums (store format 2): 32 bytes (SHA-256) per chunk, at 32 x the chunk's number.
CHECKSUMS = "acroplan-chunks.sha256"
#: Attribute names in the store's zarr.json.
ATTR_DEF, ATTR_HASH, ATTR_VERSION, ATTR_FORMAT = ("acroplan_sweep", "acroplan_sweep_hash", "acroplan_version",
                                                   "acroplan_store_format")
FIX_NEW = "give a new store (a path that does not exist yet)"
FIX_CORRUPT = "start the sweep in a new store (or delete this one)"


def corrupt(store, what: str) -> InvalidInputError:
    """The error for a corrupt store: ``STORE: is corrupt: WHAT; start the sweep in a new store``."""
    return InvalidInputError(str(store), f"is corrupt: {what}", FIX_CORRUPT)


def dim_names(sw) -> dict[str, str]:
    """Each swept field's name in the store: its short name (``P0``, ``T``, ``scale``; the physical
    body's ``angular_momentum`` is ``P0``) when unique, else the full name."""
    short = {f: {"angular_momentum": "P0"}.get(f.split(".", 1)[1], f.split(".", 1)[1]) for f in sw.fields}
    counts = collections.Counter(short.values())
    reserved = {name for name, *_ in sw.variables()} | {"point"}
    return {f: (s if counts[s] == 1 and s not in reserved else f) for f, s in short.items()}


def fsync_path(path: Path, directory: bool = False) -> None:
    """Flush a file (or a folder's entries) to disk; nothing for a path that does not exist."""
    try:
        fd = os.open(path, os.O_RDONLY | (os.O_DIRECTORY if directory else 0))
    except FileNotFoundError:
        return
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` atomically: a temporary name, fsync, rename, fsync of the folder."""
    tmp = path.with_name(f".{path.name}.tmp-{os.getpid()}")
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)
    fsync_path(path.parent, directory=True)


def read_json(path: Path, store: Path, what: str) -> dict:
    """A JSON object read from a store's file, or :class:`InvalidInputError` naming the store."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise corrupt(store, f"its {what} ({path.name}) is missing") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise corrupt(store, f"its {what} ({path.name}) cannot be read ({type(e).__name__})") from None
    if not isinstance(data, dict):
        raise corrupt(store, f"its {what} ({path.name}) is not a JSON object")
    return data


def pid_alive(pid: int) -> bool:
    """Whether a process ``pid`` exists (one of another user counts as alive)."""
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def _brief(v) -> str:
    text = json.dumps(v)
    return text if len(text) <= 80 else text[:77] + "..."


def _pairs(v) -> bool:
    """A grid's or a sample's fields: ``[[name, spec], ...]``."""
    return isinstance(v, list) and all(isinstance(e, list) and len(e) == 2 and isinstance(e[0], str) for e in v)


def diff(a, b, path: str = "sweep") -> str | None:
    """The first place where two canonical definitions differ, with both values."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a or k not in b:
                return f"{path}.{k} (stored: {_brief(a.get(k))}, given: {_brief(b.get(k))})"
            d = diff(a[k], b[k], f"{path}.{k}")
            if d:
                return d
        return None
    if _pairs(a) and _pairs(b) and [e[0] for e in a] == [e[0] for e in b]:
        for (name, x), (_, y) in zip(a, b):
            d = diff(x, y, f"{path}.{name}")
            if d:
                return d
        return None
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            d = diff(x, y, f"{path}[{i}]")
            if d:
                return d
        return None
    return None if a == b else f"{path} (stored: {_brief(a)}, given: {_brief(b)})"
