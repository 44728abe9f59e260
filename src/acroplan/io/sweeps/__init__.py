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

from .check import check_store
from .commands import map_cmd, sweep_cmd
from .files import load_sweep, parse_sweep
from .layout import CHECKSUMS, LOCK, RECORD
from .maps import draw_map
from .reading import open_sweep
from .runner import SweepSummary, run_sweep

__all__ = ["run_sweep", "open_sweep", "load_sweep", "parse_sweep", "draw_map", "SweepSummary", "check_store",
           "sweep_cmd", "map_cmd", "RECORD", "LOCK", "CHECKSUMS"]
