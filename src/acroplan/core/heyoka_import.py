"""heyoka, imported for the command line without sympy (issue #24: start-up).

heyoka imports sympy (0.3 s) whenever sympy is installed, for its conversions
(``heyoka.from_sympy``, ``heyoka.to_sympy``). acroplan converts only a body's sympy fields, and
the two-link acrobot gives its fields as heyoka expressions
(:meth:`~acroplan.core.system.ControlAffineSystem.taylor_fields`): the command line, whose acrobot
examples plan in about a second, imports heyoka without sympy (:data:`WITHOUT_SYMPY`, set by
:func:`acroplan.io.cli.run`), and :func:`from_sympy` makes heyoka's conversion ready when a body's
sympy fields are converted. ``heyoka.to_sympy`` is not available in such a process (acroplan never
uses it). Any other process (a script, a notebook) imports heyoka whole.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

__all__ = ["WITHOUT_SYMPY", "heyoka", "from_sympy"]

#: Import heyoka without sympy (when sympy is not imported yet): the command line's choice.
WITHOUT_SYMPY = False

# the names of heyoka's sympy conversion (heyoka/_sympy_utils.py) that from_sympy() sets up again
_UTILS_NAMES = ("_with_sympy", "_fmap", "_build_fmap")


def _conversion_known() -> bool:
    """Whether the installed heyoka's sympy conversion is the one :func:`from_sympy` can set up
    after an import without sympy (read from its source; no import)."""
    spec = importlib.util.find_spec("heyoka")
    if spec is None or spec.origin is None:
        return False
    try:
        text = (Path(spec.origin).parent / "_sympy_utils.py").read_text(encoding="utf-8")
    except OSError:
        return False
    return all(f"{name} =" in text or f"def {name}(" in text for name in _UTILS_NAMES)


def heyoka():
    """The heyoka module: imported without sympy under :data:`WITHOUT_SYMPY` (when neither is
    imported yet), whole otherwise."""
    if not WITHOUT_SYMPY or "heyoka" in sys.modules or "sympy" in sys.modules or not _conversion_known():
        import heyoka as hy

        return hy
    sys.modules["sympy"] = None  # (an import of sympy fails: heyoka leaves its conversions out)
    try:
        import heyoka as hy
    finally:
        if "sympy" in sys.modules and sys.modules["sympy"] is None:
            del sys.modules["sympy"]
    return hy


def from_sympy(ex, s_dict):
    """``heyoka.from_sympy(ex, s_dict)``, with heyoka's table of sympy's functions made first if
    heyoka was imported without sympy (:func:`heyoka`)."""
    hy = heyoka()
    utils = hy._sympy_utils
    if not utils._with_sympy:
        import sympy  # noqa: F401 - (the table is made of sympy's functions)

        utils._with_sympy = True
        utils._fmap = utils._build_fmap()
    return hy.from_sympy(ex, s_dict)
