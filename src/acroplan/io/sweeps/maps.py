"""Maps of a sweep store: :func:`draw_map`, a heatmap or contours of a recorded quantity over two
swept fields (coloured points for a sample), built without pyplot."""

from __future__ import annotations

import re

from pathlib import Path
from typing import Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ...sweeps.vocabulary import STATUS_CODES
from .reading import open_sweep

__all__ = ["draw_map"]

_STATUS_COLOURS = ["#1a7f37", "#bbbbbb", "#cf222e", "#8250df"]


def _name_in(ds, name: str, what: str, field_names: dict) -> str:
    if name in ds.variables:
        return name
    if name in field_names:
        return field_names[name]
    for short, full in field_names.items():
        if full.endswith(f".{name}") or short.endswith(f".{name}"):
            return full if full in ds.variables else short
    known = sorted(set(ds.data_vars) | set(ds.coords)) if what == "--value" else sorted(ds.coords)
    raise InvalidInputError(what, f"{name!r} is not in the store", f"known: {known}")


def _names(ds, x: str, y: str, value: str) -> tuple[str, str, str, dict]:
    field_names = {}
    for name in ds.coords:
        full = ds[name].attrs.get("field")
        if full:
            field_names[full] = name
            field_names[full.split(".", 1)[1]] = name
    xn, yn = (_name_in(ds, n, w, field_names) for n, w in ((x, "--x"), (y, "--y")))
    vn = _name_in(ds, value, "--value", field_names)
    if xn == yn:
        raise InvalidInputError("--y", "is the same field as --x", "give two different fields")
    if vn not in ds.data_vars:
        raise InvalidInputError("--value", f"{value!r} is a coordinate, not a recorded quantity",
                                f"known: {sorted(ds.data_vars)}")
    return xn, yn, vn, field_names


def _plane(ds, xn: str, yn: str, at: Mapping | None, field_names: dict):
    """The grid cut to the plane of ``xn`` and ``yn`` (other fields fixed by ``at``), as (y, x)."""
    sel = {}
    for name, v in dict(at or {}).items():
        n = _name_in(ds, name, "--at", field_names)
        if n not in ds.dims:
            raise InvalidInputError("--at", f"{name!r} is not a grid dimension", f"dimensions: {list(ds.dims)}")
        sel[n] = v
    for n in (xn, yn):
        if n not in ds.dims:
            raise InvalidInputError("--x" if n == xn else "--y", f"{n!r} is not a grid dimension",
                                    f"dimensions: {list(ds.dims)}")
    if sel:
        try:
            ds = ds.sel(sel, method="nearest")
        except (TypeError, ValueError, KeyError):
            ds = ds.sel(sel)
    rest = [d for d in ds.dims if d not in (xn, yn) and ds.sizes[d] > 1]
    if rest:
        raise InvalidInputError("--at", f"the grid has more dimensions than x and y: {rest}",
                                "fix them, for example --at " + ",".join(f"{d}={ds[d].values[0]}" for d in rest))
    ds = ds.isel({d: 0 for d in ds.dims if d not in (xn, yn)}, drop=True)
    return ds.transpose(yn, xn)


def _grid_map(ax, ds, xn, yn, kind, Z, categorical, cmap, infeasible):
    from matplotlib.colors import ListedColormap

    X, Y = np.asarray(ds[xn].values, dtype=float), np.asarray(ds[yn].values, dtype=float)
    if kind == "heatmap" or categorical or min(len(X), len(Y)) < 2:
        m = ax.pcolormesh(_edges(X), _edges(Y), np.ma.masked_invalid(Z), cmap=cmap, shading="flat",
                          **({"vmin": -0.5, "vmax": 3.5} if categorical else {}))
    else:
        m = ax.contourf(X, Y, np.ma.masked_invalid(Z), levels=12, cmap=cmap)
        lines = ax.contour(X, Y, np.ma.masked_invalid(Z), levels=m.levels, colors="k", linewidths=0.4)
        ax.clabel(lines, lines.levels[::2], fmt="%.4g", fontsize=7)
    if not categorical and infeasible.any():
        ax.pcolor(_edges(X), _edges(Y), np.ma.masked_where(~infeasible, np.ones_like(Z)),
                  cmap=ListedColormap(["#d0d0d0"]), hatch="//", edgecolor="#888888", linewidth=0.0, shading="flat")
    PX, PY = np.meshgrid(X, Y)
    return m, PX, PY


def _sample_map(ax, ds, xn, yn, kind, val, ok, categorical, cmap, infeasible):
    PX, PY = np.asarray(ds[xn].values, dtype=float), np.asarray(ds[yn].values, dtype=float)
    if kind == "contour" and not categorical and ok.sum() >= 3:
        m = ax.tricontourf(PX[ok], PY[ok], val[ok], levels=12, cmap=cmap)
    else:
        m = ax.scatter(PX[ok], PY[ok], c=val[ok], cmap=cmap, s=14, **({"vmin": -0.5, "vmax": 3.5} if categorical
                                                                       else {}))
    if not categorical and infeasible.any():
        ax.scatter(PX[infeasible], PY[infeasible], s=14, c="#bbbbbb", marker="s")
    return m, PX, PY


def _legend(ax, PX, PY, status, categorical, infeasible, failed) -> list:
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles = []
    if not categorical and infeasible.any():
        handles.append(Patch(facecolor="#d0d0d0", edgecolor="#888888", hatch="//",
                             label=f"infeasible ({int(infeasible.sum())})"))
    if not categorical and failed.any():
        ax.plot(PX[failed], PY[failed], "x", color="#cf222e", ms=6, mew=1.5)
        handles.append(Line2D([], [], marker="x", color="#cf222e", ls="", label=f"failed ({int(failed.sum())})"))
    missing = int((status < 0).sum())
    if missing:
        handles.append(Patch(facecolor="white", edgecolor="#888888", label=f"not computed ({missing})"))
    return handles


def draw_map(store, x: str, y: str, value: str, path=None, *, kind: str = "heatmap", at: Mapping | None = None,
             title: str | None = None):
    """A map of ``value`` over the fields ``x`` and ``y`` of a sweep store: a heatmap or filled
    contours on a grid, coloured points (or triangulated contours) for a sample. Infeasible points
    are marked apart (grey, hatched ``//``), and failed ones (not converged, invalid) with red
    crosses; points not computed stay blank.

    Parameters
    ----------
    store : path or xarray.Dataset
        A sweep store (read by :func:`acroplan.open_sweep`: a damaged chunk is refused, named) or
        its Dataset.
    x, y : str
        Swept fields (``"T"``, ``"scale"``, or full names ``"plan.T"``).
    value : str
        A recorded variable (``"least_P0"``, ``"effort"``, ``"peak_torque"``, ``"status"``, ...).
    path : path, optional
        Write the figure there (``.png`` or ``.pdf``).
    kind : {"heatmap", "contour"}
    at : mapping, optional
        Values of the grid's other fields (the nearest grid value is taken), e.g. ``{"P0": 10}``.
    title : str, optional

    Returns
    -------
    matplotlib.figure.Figure
        Built without pyplot: the caller's matplotlib backend is left as it is.
    """
    from matplotlib.colors import ListedColormap
    from matplotlib.figure import Figure

    if kind not in ("heatmap", "contour"):
        raise InvalidInputError("--kind", f"must be \"heatmap\" or \"contour\", got {kind!r}", "give heatmap")
    if path is not None and Path(path).suffix.lower() not in (".png", ".pdf"):
        raise InvalidInputError("--out", f"{path}: the map is written as .png or .pdf", "give for example map.png")
    ds = store if hasattr(store, "data_vars") else open_sweep(store)
    xn, yn, vn, field_names = _names(ds, x, y, value)
    grid = "point" not in ds.dims
    if grid:
        ds = _plane(ds, xn, yn, at, field_names)
    status = np.asarray(ds["status"].values)
    val = np.asarray(ds[vn].values, dtype=float)
    ok, infeasible, failed = (status == 0) & np.isfinite(val), status == 1, (status == 2) | (status == 3)
    categorical = vn == "status"
    cmap = ListedColormap(_STATUS_COLOURS) if categorical else "viridis"
    if categorical:
        val, ok = np.where(status >= 0, status, np.nan).astype(float), status >= 0
    fig = Figure(figsize=(6.4, 4.8), layout="constrained")
    ax = fig.add_subplot()
    if grid:
        m, PX, PY = _grid_map(ax, ds, xn, yn, kind, np.where(ok, val, np.nan), categorical, cmap, infeasible)
    else:
        m, PX, PY = _sample_map(ax, ds, xn, yn, kind, val, ok, categorical, cmap, infeasible)
    handles = _legend(ax, PX, PY, status, categorical, infeasible, failed)
    units = ds[vn].attrs.get("units")
    cb = fig.colorbar(m, ax=ax, label=vn + (f" [{units}]" if units else ""))
    if categorical:
        cb.set_ticks([0, 1, 2, 3], labels=list(STATUS_CODES))
    ax.set_xlabel(_axis_label(ds, xn))
    ax.set_ylabel(_axis_label(ds, yn))
    label = ds[vn].attrs.get("description", vn)
    ax.set_title(title or (label if len(label) <= 70 else vn), fontsize=10)
    if handles:
        ax.legend(handles=handles, loc="best", fontsize=8, framealpha=0.9)
    if path is not None:
        fig.savefig(path, dpi=130)
    return fig


def _edges(c: np.ndarray) -> np.ndarray:
    """Cell edges around grid values (midpoints; ends mirrored)."""
    c = np.asarray(c, dtype=float)
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


#: Units of swept fields known by their name alone (the rest are labelled without one): times in
#: seconds (``plan.T``, ``plan.times[-1]``, a ``time_limit``)
_TIME_FIELD = re.compile(r"(^|\.)(T|times(\[[^\]]*\])?|duration|time_limit)$")


def field_unit(field: str) -> str:
    """The unit of a swept field named ``field`` when its name tells it (``"s"`` for a time), else ``""``."""
    return "s" if _TIME_FIELD.search(field) else ""


def _axis_label(ds, name) -> str:
    full = ds[name].attrs.get("field", name)
    unit = ds[name].attrs.get("units") or field_unit(full)
    label = name if full == name else f"{name}  ({full})"
    return f"{label} [{unit}]" if unit else label
