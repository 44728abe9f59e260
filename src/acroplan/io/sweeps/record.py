"""A store's completion record and its chunks' checksums.

The record (``acroplan-sweep.json``) names the chunks done, as ranges, with the message table and
the counts by status; it is replaced atomically each time a chunk is done. Each chunk's SHA-256
is written, before the record names the chunk, at 32 bytes x its number in
``acroplan-chunks.sha256``: the digest of every array's block of the chunk (the variables and a
sample's coordinates, by name, with dtype and shape), prefixed by the definition's hash and the
chunk's number, so that a chunk moved, swapped, emptied, flipped or written for another sweep does
not match. The record's counts are re-derived from the chunks whenever they are verified.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import os
from pathlib import Path

import numpy as np

from .layout import CHECKSUMS, fsync_path

__all__ = ["Record", "Checksums", "chunk_digest", "ranges_of"]

_DIGEST = 32


@dataclasses.dataclass
class Record:
    """The completion record: ``done`` (sorted half-open ranges ``[a, b)`` of chunk numbers),
    ``messages`` (code -> template), ``counts`` (points by status), the definition's ``hash``."""

    done: list
    messages: dict
    counts: dict
    hash: str
    format: int = 2

    def is_done(self, chunk: int) -> bool:
        return any(a <= chunk < b for a, b in self.done)

    def chunks(self):
        """The chunks done, in order (a generator: the ranges are never expanded)."""
        for a, b in self.done:
            yield from range(a, b)

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
        return json.dumps({"format": self.format, "hash": self.hash, "done": self.done, "messages": self.messages,
                           "counts": self.counts}, sort_keys=True)


def ranges_of(flags: np.ndarray) -> list:
    """The half-open ranges ``[[a, b), ...]`` where a boolean array is true."""
    f = np.concatenate([[False], np.asarray(flags, dtype=bool), [False]])
    edges = np.flatnonzero(f[1:] != f[:-1])
    return [[int(a), int(b)] for a, b in zip(edges[::2], edges[1::2])]


def chunk_digest(sweep_hash: str, chunk: int, blocks: dict) -> bytes:
    """The SHA-256 of a chunk: the definition's hash, the chunk's number, then each block (by name,
    in sorted order) as its name, dtype, shape and bytes (C order)."""
    h = hashlib.sha256(f"acroplan sweep chunk\0{sweep_hash}\0{int(chunk)}\0".encode("ascii"))
    for name in sorted(blocks):
        a = np.ascontiguousarray(blocks[name])
        h.update(f"{name}\0{a.dtype.str}\0{a.shape}\0".encode("utf-8"))
        h.update(a.tobytes())
    return h.digest()


class Checksums:
    """The checksum file: 32 bytes per chunk at offset 32 x chunk (zeros: none recorded)."""

    def __init__(self, store: Path, writable: bool = False):
        self.path = Path(store) / CHECKSUMS
        self.writable = writable
        self._fd = None

    def _open(self):
        if self._fd is None:
            if self.writable:
                self._fd = os.open(self.path, os.O_RDWR | os.O_CREAT, 0o666)
            else:
                try:
                    self._fd = os.open(self.path, os.O_RDONLY)
                except FileNotFoundError:
                    self._fd = -1
        return self._fd

    def get(self, chunk: int) -> bytes | None:
        """The recorded digest of ``chunk``, or ``None``."""
        fd = self._open()
        if fd < 0:
            return None
        data = os.pread(fd, _DIGEST, int(chunk) * _DIGEST)
        return data if len(data) == _DIGEST and any(data) else None

    def put(self, chunk: int, digest: bytes) -> None:
        """Record ``digest`` for ``chunk`` and flush it to disk."""
        fd = self._open()
        os.pwrite(fd, digest, int(chunk) * _DIGEST)
        os.fsync(fd)

    def create(self, n_chunks: int) -> None:
        """An empty (sparse) file for ``n_chunks`` chunks, flushed."""
        with open(self.path, "wb") as f:
            f.truncate(int(n_chunks) * _DIGEST)
            f.flush()
            os.fsync(f.fileno())
        fsync_path(self.path.parent, directory=True)

    def close(self) -> None:
        if self._fd is not None and self._fd >= 0:
            os.close(self._fd)
        self._fd = None
