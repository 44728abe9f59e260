"""Atomic output folders: everything appears whole, or nothing does."""

from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path

from ..core.errors import InvalidInputError

__all__ = ["check_out_dir", "atomic_dir"]


def check_out_dir(out: Path, force: bool) -> None:
    """Refuse a path that is a file, or a non-empty folder without ``force``."""
    if out.exists() and not out.is_dir():
        raise InvalidInputError("--out", f"{out} exists and is not a folder", "give a folder path")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise InvalidInputError("--out", f"{out} exists and is not empty", "choose another folder or add --force")


@contextmanager
def atomic_dir(out: Path, force: bool):
    """Yield a temporary folder beside ``out``; on success it replaces ``out`` in one rename.

    On an exception the temporary folder is removed and ``out`` is left as it was.
    """
    out = Path(out)
    check_out_dir(out, force)
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.", suffix=".tmp", dir=out.parent))
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    old = None
    if out.exists():
        old = out.parent / f".{out.name}.{os.getpid()}.old"
        os.replace(out, old)
    os.replace(tmp, out)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
