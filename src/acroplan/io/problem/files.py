"""Problem files on disk: reading TOML safely, writing command-line options over a file's."""

from __future__ import annotations

import tomllib
from pathlib import Path

from ...core.errors import InvalidInputError
from ...core.validate import MAX_FILE_BYTES, short
from .model import Problem, Simulation
from .reader import parse_problem, parse_simulation

__all__ = ["load_toml", "with_options", "load_problem", "load_simulation"]


def load_toml(path) -> dict:
    """Read a TOML file, with errors as :class:`InvalidInputError` naming the file (and the line
    when the parser gives up on a number or a nesting): at most :data:`MAX_FILE_BYTES` bytes,
    regular files only."""
    path = Path(path)
    fix = "give a readable UTF-8 .toml file"
    try:
        if not path.exists():
            raise InvalidInputError(str(path), "no such file", "give the path of a problem .toml file")
        if not path.is_file():
            raise InvalidInputError(str(path), "is not a regular file", fix)
        with open(path, "rb") as f:
            raw = f.read(MAX_FILE_BYTES + 1)
        if len(raw) > MAX_FILE_BYTES:
            raise InvalidInputError(str(path), f"is larger than {MAX_FILE_BYTES // 1_000_000} MB",
                                    "a problem file is a few lines")
        text = raw.decode("utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise InvalidInputError(str(path), f"cannot be read ({e.__class__.__name__})", fix) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InvalidInputError(str(path), f"is not valid TOML ({_one_line(e)})", "fix the syntax (see the README)") \
            from None
    except (RecursionError, MemoryError):
        raise InvalidInputError(str(path), "is nested too deeply to read (arrays or tables within each other)",
                                "write the values flat, as in the README") from None
    except ValueError as e:  # an integer literal beyond Python's digit limit
        where = _line_of_long_number(text)
        raise InvalidInputError(f"{path}{where}", f"holds a number too long to read ({short(str(e), 60)})",
                                "write numbers of sensible size") from None


def _one_line(e) -> str:
    text = str(e).replace("\n", " ")
    return text if len(text) <= 200 else text[:197] + "..."


def _line_of_long_number(text: str) -> str:
    import re

    for i, line in enumerate(text.splitlines(), 1):
        if re.search(r"[0-9_]{1000,}", line):
            key = re.match(r"\s*([A-Za-z0-9_.\-\"' ]{1,60}?)\s*=", line)
            return f" (line {i}{', key ' + key.group(1).strip() if key else ''})"
    return ""


def with_options(data: dict, options: dict | None) -> dict:
    """The TOML document ``data`` with ``options`` written over its ``[options]`` table (what the
    command line's ``--objective`` and ``--tau-max`` do); ``data`` itself is not changed. A document
    whose ``[options]`` is not a table is returned as it is (its reader refuses it, naming the field)."""
    if not options or not isinstance(data, dict):
        return data
    opts = data.get("options", {})
    if not isinstance(opts, dict):
        return data
    return {**data, "options": {**opts, **options}}


def load_problem(path, *, allowed=()) -> Problem:
    """Read and validate a problem file (a URDF or a yeadon measurement file it names is read
    relative to its folder, and only from inside it or from the folders ``allowed``, relative to the
    current folder, and its ``[files] allow`` name)."""
    return parse_problem(load_toml(path), name=Path(path).stem, base=Path(path).parent, allowed=allowed)


def load_simulation(path, *, allowed=()) -> Simulation:
    """Read and validate a problem file's ``[simulate]`` table (with its ``[robot]`` or ``[body]``);
    files it names are confined as by :func:`load_problem`."""
    return parse_simulation(load_toml(path), name=Path(path).stem, base=Path(path).parent, allowed=allowed)
