"""Deprecated: the sweep store moved to :mod:`acroplan.io.sweeps` (issue #21: modules of one job).

Every public name of this module still works, with a :class:`DeprecationWarning` naming its new
place; use :mod:`acroplan.io.sweeps` (or the package's ``acroplan.run_sweep``, ``acroplan.open_sweep``,
``acroplan.load_sweep``, ``acroplan.draw_map``, ``acroplan.SweepSummary``).
"""

from __future__ import annotations

import importlib
import warnings

_MOVED = {
    "run_sweep": "acroplan.io.sweeps.runner", "SweepSummary": "acroplan.io.sweeps.runner",
    "open_sweep": "acroplan.io.sweeps.reading", "load_sweep": "acroplan.io.sweeps.files",
    "parse_sweep": "acroplan.io.sweeps.files", "draw_map": "acroplan.io.sweeps.maps",
    "check_store": "acroplan.io.sweeps.check", "sweep_cmd": "acroplan.io.sweeps.commands",
    "map_cmd": "acroplan.io.sweeps.commands", "RECORD": "acroplan.io.sweeps.layout",
    "LOCK": "acroplan.io.sweeps.layout",
}

__all__ = sorted(_MOVED)


def __getattr__(name: str):
    if name not in _MOVED:
        raise AttributeError(f"module 'acroplan.io.store' has no attribute {name!r} (the sweep store moved to "
                             "acroplan.io.sweeps)")
    warnings.warn(f"acroplan.io.store.{name} moved to {_MOVED[name]}.{name} (acroplan.io.sweeps.{name}); "
                  "acroplan.io.store will be removed in the next release", DeprecationWarning, stacklevel=2)
    return getattr(importlib.import_module(_MOVED[name]), name)
