"""Small control-affine systems that show the core is general: :class:`Unicycle` (driftless, two
inputs) and :class:`ChainedForm` (the canonical nonholonomic normal form)."""

from __future__ import annotations

from ...core.family import lazy_package

#: The public names and their modules, loaded on first use (PEP 562): the family's descriptor
#: (``family.py``) is imported without the numerics; the first name used also imports what the
#: family registers (its ``setup``: strategies, torque models, ...).
_NAMES = {"ChainedForm": "chained", "Unicycle": "unicycle"}

__all__ = list(_NAMES)
__getattr__, __dir__ = lazy_package(__name__, _NAMES)
