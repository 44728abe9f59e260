"""Validation at the boundary: readers of the values users give, each naming its field.

One home for what every reader of user input needs (the problem-file readers of every family, the
sweep files, the front doors' keywords): finite real numbers, names, vectors and matrices, the
arithmetic of problem files (numbers or strings such as ``"-0.5*pi"``, evaluated by a whitelist
of arithmetic nodes, never ``eval``), tables whose keys are checked against the known ones with the
nearest known name suggested. Every failure is an :class:`~acroplan.core.errors.InvalidInputError`
whose field is the one the user wrote.

The bounds below are what double precision carries: body values beyond :data:`MAX_BODY` (their
squares and products must stay finite), times beyond :data:`MAX_TIME`, angles beyond
:data:`MAX_ANGLE` (beyond 1e6 rad a double no longer resolves the 1e-9 rad that verification asks
for).
"""

from __future__ import annotations

import ast
import keyword
import math
import operator

from .errors import InvalidInputError

__all__ = ["real", "identifier", "pair", "short", "arith", "number", "numbers", "states", "check_keys",
           "name_field", "pair_field", "vector3", "matrix3", "did_you_mean", "choice_field",
           "MAX_MAGNITUDE", "MAX_BODY", "MAX_TIME", "MAX_ANGLE", "MIN_BODY", "MAX_TEXT", "MAX_DEPTH", "MAX_EXPONENT",
           "TOL_RANGE", "MAX_EVALUATIONS", "MAX_FILE_BYTES", "MAX_LINKS", "BODY_VALUES"]

#: The largest magnitude of a body's numbers (masses, inertias, lengths, momentum, lumped parameters):
#: their squares and products stay finite in double precision.
MAX_MAGNITUDE = 1e100

#: what the messages call a body's numbers
BODY_VALUES = "the body's numbers"


def real(field: str, value, *, positive: bool = False, optional: bool = False) -> float | None:
    """``value`` as a finite float (booleans and non-numbers refused); ``> 0`` when ``positive``;
    ``None`` passes when ``optional``."""
    if value is None and optional:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) and not hasattr(value, "__float__"):
        raise InvalidInputError(field, f"must be a real number, got {short(value)}", "give a finite number")
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(field, f"must be a real number, got {short(value)}", "give a finite number") from None
    if not math.isfinite(v):
        raise InvalidInputError(field, f"must be finite, got {v}", "give a finite number")
    if positive and not v > 0:
        raise InvalidInputError(field, f"must be > 0, got {v:g}", "give a positive value")
    return v


def pair(field: str, value) -> tuple[float, float]:
    """Two finite numbers ``(x, y)``."""
    try:
        x, y = value
    except (TypeError, ValueError):
        raise InvalidInputError(field, f"must be a pair (x, y), got {short(value)}",
                                "give for example (0.5, 0.0)") from None
    return (real(f"{field}[0]", x), real(f"{field}[1]", y))


def identifier(field: str, value, what: str) -> str:
    """A Python identifier that is not a keyword (a joint's or a link's name)."""
    if not isinstance(value, str) or not value.isidentifier() or keyword.iskeyword(value):
        raise InvalidInputError(field, f"must be a Python identifier, got {short(value)}",
                                f"give the {what} a name of letters, digits and underscores (for example 'arm1')")
    return value


# ---------------------------------------------------------------- values in problem and sweep files
_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
        ast.USub: operator.neg, ast.UAdd: operator.pos, ast.Pow: operator.pow}

#: Bounds of the arithmetic in problem files: text of at most MAX_TEXT characters, expressions at
#: most MAX_DEPTH deep, exponents at most MAX_EXPONENT in size, every intermediate result real and
#: finite.
MAX_TEXT, MAX_DEPTH, MAX_EXPONENT = 200, 32, 1024

#: Magnitudes the arithmetic carries (values beyond are refused, naming the field and the limit):
#: the body's masses, inertias, lengths and momentum, its lumped parameters M1, A1, M2, A2, P0
#: and u_max (their squares and products must stay finite in double precision); times; angles
#: (beyond 1e6 rad a double no longer resolves the 1e-9 rad that verification asks for).
MAX_BODY, MAX_TIME, MAX_ANGLE = MAX_MAGNITUDE, 1e12, 1e6
#: the smallest M1 (and physical mass or inertia) the arithmetic carries: its square must not vanish
MIN_BODY = 1e-150
#: tolerances the planner can meet; evaluation budgets it can spend
TOL_RANGE, MAX_EVALUATIONS = (1e-15, 1.0), 10_000_000
#: the largest problem file read
MAX_FILE_BYTES = 10_000_000
#: The most links a [body] may have: compiling a body's integrator grows about as the 4th power of
#: its links (measured: the first simulation of a 6-link chain 31 s, of an 8-link chain 96 s, on a
#: 2-core machine shared with other work), so 16 links already take tens of minutes per basis size.
MAX_LINKS = 16


_TEXT_FIX = "write a number or arithmetic with pi, such as \"-0.5*pi\""


def short(value, most: int = 80) -> str:
    """A repr of ``value`` cut to ``most`` characters, safe for any nesting and size."""
    import reprlib

    r = reprlib.Repr()
    r.maxlevel, r.maxstring, r.maxother, r.maxlong = 3, most, most, most
    r.maxlist = r.maxtuple = r.maxdict = r.maxset = 6
    try:
        text = r.repr(value)
    except Exception:  # noqa: BLE001 - a repr must never fail a message
        text = f"<{type(value).__name__}>"
    return text if len(text) <= most else text[:most - 3] + "..."


class _Refused(Exception):
    def __init__(self, why: str):
        self.why = why


def arith(field: str, text: str) -> float:
    """Evaluate arithmetic on numbers and ``pi`` (no names, no calls), bounded: at most
    :data:`MAX_TEXT` characters, :data:`MAX_DEPTH` levels, exponents of at most
    :data:`MAX_EXPONENT`, every intermediate result a finite real number."""
    if len(text) > MAX_TEXT:
        raise InvalidInputError(field, f"is a text of {len(text)} characters, more than {MAX_TEXT}", _TEXT_FIX)

    def real(v):
        if isinstance(v, complex) or not isinstance(v, (int, float)):
            raise _Refused("is not a real number")
        v = float(v)
        if not math.isfinite(v):
            raise _Refused("is not finite (it overflows)")
        return v

    def ev(node, depth):
        if depth > MAX_DEPTH:
            raise _Refused(f"is nested more than {MAX_DEPTH} levels deep")
        if isinstance(node, ast.Expression):
            return ev(node.body, depth + 1)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return real(node.value)
        if isinstance(node, ast.Name) and node.id == "pi":
            return math.pi
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            left, right = ev(node.left, depth + 1), ev(node.right, depth + 1)
            if isinstance(node.op, ast.Pow) and abs(right) > MAX_EXPONENT:
                raise _Refused(f"has an exponent of {right:.6g}, beyond {MAX_EXPONENT}")
            if isinstance(node.op, ast.Pow) and left < 0 and right != int(right):
                raise _Refused("is not a real number (a fractional power of a negative number)")
            try:
                return real(_OPS[type(node.op)](left, right))
            except OverflowError:
                raise _Refused("is not finite (it overflows)") from None
            except ZeroDivisionError:
                raise _Refused("divides by zero") from None
        if isinstance(node, ast.UnaryOp) and type(node.op) in _OPS:
            return real(_OPS[type(node.op)](ev(node.operand, depth + 1)))
        raise ValueError

    try:
        return ev(ast.parse(text.strip(), mode="eval"), 0)
    except _Refused as e:
        raise InvalidInputError(field, f"{short(text)} {e.why}", _TEXT_FIX) from None
    except (SyntaxError, ValueError, TypeError, ZeroDivisionError, OverflowError, RecursionError, MemoryError):
        raise InvalidInputError(field, f"cannot read {short(text)} as a number", _TEXT_FIX) from None


def number(field: str, value, most: float | None = None, what: str = "") -> float:
    """A finite float from a TOML number or arithmetic text; ``|value| <= most`` when given
    (``what`` names the kind of value in the message)."""
    if isinstance(value, bool):
        raise InvalidInputError(field, f"must be a number, got {short(value)}", "write a number")
    if isinstance(value, str):
        v = arith(field, value)
    elif isinstance(value, (int, float)):
        try:
            v = float(value)
        except OverflowError:
            digits = int(abs(value).bit_length() * math.log10(2)) + 1
            beyond = f": {what or 'values'} beyond {most:g} in size" if most is not None else ", which"
            raise InvalidInputError(field, f"is an integer of about {digits} digits{beyond} are more than the "
                                    "arithmetic carries", "write a number of sensible size") from None
    else:
        raise InvalidInputError(field, f"must be a number, got {short(value)}", "write a number")
    if not math.isfinite(v):
        raise InvalidInputError(field, f"must be finite, got {v}", "write a finite number")
    if most is not None and abs(v) > most:
        raise InvalidInputError(field, f"is {v:.3g}: {what or 'values'} beyond {most:g} in size are more than the "
                                "arithmetic carries", "change the units so that the numbers come nearer to 1")
    return v


def numbers(field: str, value, most: float | None = None, what: str = "",
             most_of=None) -> tuple[float, ...]:
    """A list of numbers; ``most_of(i)`` gives (most, what) per element when the kinds differ."""
    if not isinstance(value, list):
        raise InvalidInputError(field, f"must be a list, got {short(value)}", "write for example [0, 2, 4]")
    out = []
    for i, v in enumerate(value):
        lim, kind = most_of(i) if most_of is not None else (most, what)
        out.append(number(f"{field}[{i}]", v, lim, kind))
    return tuple(out)


def states(field: str, value) -> tuple:
    """Waypoint values of a state: numbers, or ``"free"`` at interior waypoints (``None``)."""
    if isinstance(value, list) and any(v == "free" for v in value):
        kept = numbers(field, [0.0 if v == "free" else v for v in value], MAX_ANGLE, "angles")
        return tuple(None if v == "free" else k for v, k in zip(value, kept))
    return numbers(field, value, MAX_ANGLE, "angles")


def check_keys(table: str, data: dict, allowed) -> None:
    """Refuse a key of the table ``data`` not in ``allowed``, naming it and the nearest known key
    (``table`` is ``"<file>"`` for the tables at the top of a file)."""
    import difflib

    if not isinstance(data, dict):
        raise InvalidInputError(table, f"must be a table, got {short(data)}", f"write [{table}] with its keys")
    for key in data:
        if key not in allowed:
            name = key if (isinstance(key, str) and len(key) <= 60 and key.isprintable()) else short(key, 60)
            close = difflib.get_close_matches(name, list(allowed), n=1, cutoff=0.6) if isinstance(key, str) else []
            if table == "<file>":  # a table name at the top of the file
                raise InvalidInputError(f"[{name}]", "is not a known table",
                                        (f"did you mean [{close[0]}]? " if close else "") +
                                        f"known tables are {['[' + a + ']' for a in allowed]}")
            raise InvalidInputError(f"{table}.{name}", "is not a known key",
                                    (f"did you mean {close[0]!r}? " if close else "") + f"known keys are {list(allowed)}")


def name_field(field: str, value) -> str:
    """A name in quotes (a string)."""
    if not isinstance(value, str):
        key = field.rsplit(".", 1)[-1]
        raise InvalidInputError(field, f"must be a name in quotes, got {short(value)}", f"write for example "
                                f"{key} = \"arm\"")
    return value


def pair_field(field: str, value) -> tuple[float, float]:
    """A file's pair ``[x, y]`` of body values (arithmetic allowed)."""
    if not isinstance(value, list) or len(value) != 2:
        raise InvalidInputError(field, f"must be a pair [x, y], got {short(value)}", "write for example [0.5, 0.0]")
    return tuple(number(f"{field}[{i}]", v, MAX_BODY, BODY_VALUES) for i, v in enumerate(value))


def vector3(field: str, value, most: float = MAX_BODY, what: str = BODY_VALUES) -> tuple[float, float, float]:
    """A file's three numbers ``[x, y, z]``, each at most ``most`` in size."""
    if not isinstance(value, list) or len(value) != 3:
        raise InvalidInputError(field, f"must be three numbers [x, y, z], got {short(value)}",
                                "write for example [0.0, 0.0, 0.5]")
    return numbers(field, value, most, what)


def matrix3(field: str, value, example: str) -> list:
    """A file's 3 x 3 matrix (three rows of three numbers); ``example`` is shown in the fix."""
    if not isinstance(value, list) or len(value) != 3 or not all(isinstance(r, list) for r in value):
        raise InvalidInputError(field, f"must be a 3 x 3 matrix (three rows of three numbers), got {short(value)}",
                                f"write for example {example}")
    return [list(vector3(f"{field}[{i}]", r)) for i, r in enumerate(value)]


def did_you_mean(word, names) -> str:
    """``'did you mean "x"? '`` for the nearest of ``names`` to ``word``, or nothing."""
    import difflib

    close = difflib.get_close_matches(word, list(names), n=1, cutoff=0.5) if isinstance(word, str) else []
    return f"did you mean \"{close[0]}\"? " if close else ""


def choice_field(field: str, value, names, example: str) -> str:
    """One of ``names`` (a string), the nearest suggested otherwise."""
    if not isinstance(value, str) or value not in names:
        raise InvalidInputError(field, f"must be one of {list(names)}, got {short(value)}",
                                did_you_mean(value, names) + f"write for example {field.rsplit('.', 1)[-1]} = \"{example}\"")
    return value
