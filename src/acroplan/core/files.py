"""Files a problem file names, confined to its folder.

A problem file may name other files (a URDF, a yeadon measurement file). They are read only from
inside the problem file's own folder unless the user allows more: a path that leads out of it (an
absolute path elsewhere, ``..``, a symbolic link pointing out) is refused unless it is inside a
folder the user allowed (``--allow-outside PATH`` on the command line, ``[files] allow = [...]`` in
the file; :attr:`acroplan.core.family.ReadContext.allowed`). A refusal reads the same whether the
path outside exists or not, and no message quotes a file's content.

Only regular files are read (not FIFOs or devices), of at most :data:`MAX_FILE_BYTES` bytes (or
less, as the caller says).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from .errors import InvalidInputError
from .validate import MAX_FILE_BYTES, short

__all__ = ["confined_file", "allowed_folders", "ALLOW_FIX", "MAX_PATH_CHARS", "MAX_ALLOWED"]

#: The longest path a problem file may give (Linux's PATH_MAX is 4096; longer names are typing
#: errors, and the operating system refuses them with an error that is no message).
MAX_PATH_CHARS = 1024
#: The most folders one ``[files] allow`` table or command line may allow.
MAX_ALLOWED = 64

#: How to read a file outside the problem file's folder (the fix of a refusal).
ALLOW_FIX = ("move the file into the problem file's folder, or allow its folder: --allow-outside FOLDER on the "
             "command line, or [files] allow = [\"FOLDER\"] in the problem file")


def _checked_text(field: str, value, example: str) -> str:
    if not isinstance(value, str) or not value.strip():
        raise InvalidInputError(field, f"must be the path of a file in quotes, got {short(value)}",
                                f"write for example {example}")
    if len(value) > MAX_PATH_CHARS:
        raise InvalidInputError(field, f"is a path of {len(value)} characters, more than {MAX_PATH_CHARS}",
                                f"give a shorter path, for example {example}")
    if any(ord(c) < 32 or ord(c) == 127 for c in value):
        raise InvalidInputError(field, "holds a control character (a NUL byte, a newline, ...)",
                                f"give a plain path, for example {example}")
    return value


def _real(path: Path) -> Path:
    """``path`` with every symbolic link resolved (the part that exists), absolute."""
    try:
        return Path(os.path.realpath(path))
    except (OSError, ValueError):  # pragma: no cover - realpath is not strict
        return Path(os.path.abspath(path))


def _inside(real: Path, roots) -> bool:
    return any(real == r or real.is_relative_to(r) for r in roots)


def allowed_folders(field: str, values, base) -> tuple[Path, ...]:
    """The folders (or files) of ``[files] allow`` or ``--allow-outside``, absolute and resolved;
    relative paths are taken from ``base`` (the problem file's folder; the current folder when
    ``None``)."""
    if isinstance(values, (str, os.PathLike)):
        values = [values]
    if not isinstance(values, (list, tuple)):
        raise InvalidInputError(field, f"must be a list of folders in quotes, got {short(values)}",
                                "write for example allow = [\"../shared\"]")
    if len(values) > MAX_ALLOWED:
        raise InvalidInputError(field, f"allows {len(values)} paths, more than {MAX_ALLOWED}",
                                "allow the folders that hold the files, not each file")
    root = Path(base) if base is not None else Path.cwd()
    out = []
    for i, v in enumerate(values):
        text = _checked_text(f"{field}[{i}]", os.fspath(v) if isinstance(v, os.PathLike) else v, "\"../shared\"")
        p = Path(text)
        out.append(_real(p if p.is_absolute() else root / p))
    return tuple(out)


def confined_file(field: str, value, base=None, allowed=(), *, example: str, what: str,
                  most_bytes: int = MAX_FILE_BYTES) -> Path:
    """The file ``value`` names (relative to ``base``, the problem file's folder; the current folder
    when ``None``), checked: inside ``base`` or an ``allowed`` folder once symbolic links are
    resolved, existing, a regular file of at most ``most_bytes`` bytes.

    Parameters
    ----------
    field : str
        The field that names the file (``"body.urdf"``), for messages.
    value : str
        The path as the file gives it.
    base : path, optional
    allowed : sequence of Path
        Folders (or files) outside ``base`` that may be read, absolute and resolved
        (:func:`allowed_folders`).
    example : str
        A path to show in a fix (``"\\"diver.urdf\\""``).
    what : str
        What the file is, for messages (``"a .urdf file"``).
    most_bytes : int

    Returns
    -------
    pathlib.Path
        The file's resolved path (what is opened: a link swapped later is not followed).

    Raises
    ------
    InvalidInputError
        Naming ``field``: not a path, outside (the same words whether it exists or not), missing,
        not a regular file, too large.
    """
    text = _checked_text(field, value, example)
    root = Path(base) if base is not None else Path.cwd()
    given = Path(text)
    real = _real(given if given.is_absolute() else root / given)
    roots = (_real(root),) + tuple(Path(a) for a in allowed)
    shown = short(text, 120)
    if not _inside(real, roots):
        raise InvalidInputError(field, f"{shown} is outside the problem file's folder: files are read only from "
                                "inside it", ALLOW_FIX)
    try:
        st = os.stat(real)
    except FileNotFoundError:
        raise InvalidInputError(field, f"no such file: {shown}", f"give the path of {what} (a relative path is read "
                                "from the problem file's folder)") from None
    except OSError as e:
        raise InvalidInputError(field, f"{shown} cannot be read ({type(e).__name__})", f"give the path of {what}") \
            from None
    if not stat.S_ISREG(st.st_mode):
        raise InvalidInputError(field, f"{shown} is not a regular file", f"give the path of {what}")
    if st.st_size > most_bytes:
        size = f"{most_bytes // 1_000_000} MB" if most_bytes >= 1_000_000 else f"{most_bytes // 1000} kB"
        raise InvalidInputError(field, f"{given.name} is larger than {size}", f"give {what}")
    return real
