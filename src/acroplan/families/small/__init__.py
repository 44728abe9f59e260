"""Small control-affine systems that show the core is general: :class:`Unicycle` (driftless, two
inputs) and :class:`ChainedForm` (the canonical nonholonomic normal form)."""

from __future__ import annotations

import importlib

#: The public names and their modules, loaded on first use (PEP 562): the family's descriptor
#: (``family.py``) is imported without the numerics; the first name used also imports what the
#: family registers (its ``setup``: strategies, torque models, ...).
_NAMES = {"ChainedForm": "chained", "Unicycle": "unicycle"}

__all__ = list(_NAMES)


def __getattr__(name: str):
    if name not in _NAMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_NAMES[name]}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
