"""Sweep stores: a sweep (:mod:`acroplan.sweeps`) computed chunk by chunk into a zarr store, read
back as an xarray Dataset, resumed after any kill, and drawn as a map.

One job per module:

* :mod:`~.layout`: the store's files, attributes and names; flushed and atomic writes;
* :mod:`~.record`: the completion record and the chunks' checksums;
* :mod:`~.check`: a store's metadata checked (:func:`check_store`), its chunks verified;
* :mod:`~.writer`: creating a store (whole or not at all) and writing chunks into it;
* :mod:`~.executors`: local processes that watch their driver, Dask, any executor; retries;
* :mod:`~.runner`: :func:`run_sweep` and :class:`SweepSummary`;
* :mod:`~.reading`: :func:`open_sweep`;
* :mod:`~.maps`: :func:`draw_map`;
* :mod:`~.files`: sweep files (:func:`load_sweep`, :func:`parse_sweep`);
* :mod:`~.commands`: ``acroplan sweep`` and ``acroplan map``.

A store is data: opening, mapping or resuming one never imports or runs code it names (a system
factory is resolved from the registered names, :func:`acroplan.sweeps.register_factory`, and from
callables passed to :func:`run_sweep`). Its SHA-256 is a check against accidental damage, not a
signature.
"""

from __future__ import annotations

import importlib

#: The public names and their modules, loaded on first use (PEP 562): ``acroplan sweep --help``
#: imports the commands alone, not xarray, zarr or dask.
_NAMES = {"run_sweep": "runner", "SweepSummary": "runner", "open_sweep": "reading", "load_sweep": "files",
          "parse_sweep": "files", "draw_map": "maps", "check_store": "check", "sweep_cmd": "commands",
          "map_cmd": "commands", "RECORD": "layout", "LOCK": "layout", "CHECKSUMS": "layout"}

__all__ = ["run_sweep", "open_sweep", "load_sweep", "parse_sweep", "draw_map", "SweepSummary", "check_store",
           "sweep_cmd", "map_cmd", "RECORD", "LOCK", "CHECKSUMS"]


def __getattr__(name: str):
    if name not in _NAMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{_NAMES[name]}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))
