"""Reading a store back: :func:`open_sweep`, an xarray Dataset whose every chunk is either checked
against its checksum or masked, never read as data otherwise."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from ...core.errors import InvalidInputError
from .check import check_store, describe_chunks, verify_chunks
from .layout import dim_names

__all__ = ["open_sweep", "BLOCK_POINTS"]


#: Points per block of the Dataset's dask arrays: a block spans several of the store's chunks (a
#: run along the first dimension), so that the graph stays small for a large store.
BLOCK_POINTS = 1 << 20


def _lazy(arr, sw, good: np.ndarray, fill):
    """A dask array of the zarr array ``arr`` (the sweep's shape and chunks): each block reads the
    good chunks it spans from the store and fills the others with ``fill`` (their files are never
    opened)."""
    import dask.array as da

    shape, cs, grid = tuple(arr.shape), sw.chunks, sw.chunk_grid
    k = max(1, BLOCK_POINTS // math.prod(cs))  # store chunks per block along the first dimension
    rows = k * cs[0]
    chunks = (tuple(min(rows, shape[0] - i) for i in range(0, shape[0], rows)),) + \
        tuple(tuple(min(c, n - i) for i in range(0, n, c)) for n, c in zip(shape[1:], cs[1:]))
    dtype = np.dtype(arr.dtype)

    def block(block_info=None):
        info = block_info[None]
        loc, region = info["chunk-location"], tuple(slice(a, b) for a, b in info["array-location"])
        first, last = loc[0] * k, min(grid[0], loc[0] * k + k)
        flags = good[[int(np.ravel_multi_index((i,) + tuple(loc[1:]), grid)) for i in range(first, last)]]
        if flags.all():
            return np.asarray(arr[region])
        out = np.full(tuple(s.stop - s.start for s in region), fill, dtype=dtype)
        for i, ok in zip(range(first, last), flags):
            if ok:
                a, b = i * cs[0], min(shape[0], (i + 1) * cs[0])
                out[a - region[0].start:b - region[0].start] = np.asarray(arr[(slice(a, b),) + region[1:]])
        return out

    return da.map_blocks(block, chunks=chunks, dtype=dtype, meta=np.empty((0,) * len(shape), dtype=dtype))


def _variables(g, sw, good) -> dict:
    names = dim_names(sw)
    dims = [names[f] for f in sw.fields] if sw.is_grid else ["point"]
    out = {}
    for name, _dtype, fill, _ in sw.variables():
        arr = g[name]
        attrs = {k: v for k, v in dict(arr.attrs).items() if k != "coordinates"}
        if np.dtype(arr.dtype).kind == "f":
            attrs["_FillValue_note"] = "NaN where not computed or not applicable"
        out[name] = (dims, _lazy(arr, sw, good, fill), attrs)
    return out


def _coordinates(g, sw, good) -> dict:
    names = dim_names(sw)
    out = {}
    for f in sw.fields:
        attrs = {"field": f, "description": f"the swept field {f}"}
        if sw.is_grid:  # from the definition, whatever the store's copy holds
            axis = sw.axes[f]
            out[names[f]] = ([names[f]], axis.slice(0, len(axis)), attrs)
        else:
            arr = g[names[f]]
            fill = math.nan if np.dtype(arr.dtype).kind == "f" else arr.fill_value
            out[names[f]] = (["point"], _lazy(arr, sw, good, fill), attrs)
    return out


def open_sweep(path, *, complete: bool = False, damaged: str = "raise"):
    """The store as an xarray Dataset (lazy, chunked as written).

    Every chunk the completion record names is read once and compared with its checksum. Points of
    chunks the record does not name are masked (``status`` -1, NaN, fill values), whatever their
    files hold: a chunk half written by a killed run is never read as done. A chunk the record
    names that does not match its checksum (a flipped byte, a swapped, emptied or deleted file) is
    refused, named, or with ``damaged="mask"`` masked like a chunk not done. The grid's coordinates
    are the definition's. Nothing the store names is imported or run.

    The attributes add ``messages`` (the message table, JSON: code -> template), ``chunks_done``
    (chunks done and verified), ``chunks``, ``complete``, ``counts`` (JSON: points by status,
    counted from the chunks), ``checksums`` (``"verified"``, or ``"none (store format 1)"`` for a
    store written before checksums), ``damaged`` (the chunks masked as damaged) and ``definition``
    (the sweep's canonical JSON).

    Parameters
    ----------
    path : path of a store
    complete : bool
        Refuse a store that is not complete.
    damaged : {"raise", "mask"}
        What a damaged chunk does: refuse the store, naming the chunks (default), or mask them.

    Raises
    ------
    InvalidInputError
        For a store that is not an acroplan sweep store, is corrupt, or has a damaged chunk.
    """
    import xarray as xr
    import zarr

    if damaged not in ("raise", "mask"):
        raise InvalidInputError("damaged", f"must be \"raise\" or \"mask\", got {damaged!r}", "leave it out")
    sw, record, fmt = check_store(path)
    ver = verify_chunks(path, sw, record, fmt)
    if ver.bad and damaged == "raise":
        raise InvalidInputError(str(path), f"is damaged: {describe_chunks(sw, ver.bad)}",
                                "run the sweep again (the same command) to recompute them, or read the rest with "
                                "open_sweep(path, damaged=\"mask\")")
    n_good = ver.n_good()
    if complete and n_good != sw.n_chunks:
        raise InvalidInputError(str(path), f"is not complete ({n_good} of {sw.n_chunks} chunks)",
                                "run the sweep again to finish it")
    g = zarr.open_group(str(Path(path)), mode="r", zarr_format=3, use_consolidated=True)
    ds = xr.Dataset(_variables(g, sw, ver.good), coords=_coordinates(g, sw, ver.good), attrs=dict(g.attrs))
    ds.attrs.update({"messages": json.dumps(record.messages, sort_keys=True), "chunks_done": n_good,
                     "chunks": sw.n_chunks, "complete": n_good == sw.n_chunks, "definition": sw.json,
                     "counts": json.dumps(ver.counts, sort_keys=True),
                     "checksums": "verified" if ver.checked else f"none (store format {fmt})",
                     "damaged": [int(c) for c, _ in ver.bad]})
    return ds
