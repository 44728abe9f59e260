"""What is computed at a point, and how a chunk of points is computed by one task on any executor.

A point's status follows :mod:`acroplan.sweeps.vocabulary`: ``invalid`` when plan() refuses its
values (:class:`~acroplan.InvalidInputError`), ``not_converged`` for any crash (an unexpected
error while building the point, computing a derived quantity or planning), as
:func:`acroplan.plan_many` reports one; otherwise what plan() returns (or, with ``plan=False``,
the derived quantities' status).

Every point is computed with one BLAS thread (:func:`acroplan.core.blas.one_blas_thread`, which
:func:`acroplan.plan` holds itself; here it covers the derived quantities too), on every executor: Dask's
workers start with ``OPENBLAS_NUM_THREADS=1`` (its ``distributed.nanny.pre-spawn-environ``) while
the driver's serial executor has one BLAS thread per core, and OpenBLAS's threaded products split
their sums by thread, so the last bits of a result (seen: the acrobot's flat-output check,
3.774758283725532e-15 against 3.552713678800501e-15 at one point of the tests' sweep) would depend
on where a chunk ran. With one thread everywhere a sweep gives the same numbers, bit for bit, on
any executor of one machine; its matrices are small, so the threads bought nothing.
"""

from __future__ import annotations

import math
import os
import time
import traceback
from typing import Any

import numpy as np

from ..core import backend
from ..core.blas import one_blas_thread
from ..core.errors import InvalidInputError
from ..core.progress import Progress
from ..core.sweep_hooks import derived_value
from ..planning import PlanRequest, warm_up
from ..planning import plan as _plan
from .metrics import point_metrics
from .vocabulary import PointStatus, SweepPoint, message_code

__all__ = ["compute_chunk", "evaluate_point", "run_chunk", "warm_worker", "one_blas_thread"]


def _crash(e: BaseException, where: str) -> str:
    return f"not converged: unexpected {type(e).__name__} {where}: {e}\n{traceback.format_exc()}"


def _derived(sw, req, data, j) -> tuple[str | None, str | None]:
    """Each derived quantity at a point: ``(proof, crash)`` messages (the first of each)."""
    proof = crash = None
    for name in sw.derived:
        try:
            value, why = derived_value(name, req)
        except Exception as e:  # noqa: BLE001 - a crash is recorded, it stops nothing
            value, why = math.nan, None
            crash = crash or _crash(e, f"computing {name}")
        data[name][j] = value
        proof = proof or (f"{name}: {why}" if why else None)
    return proof, crash


def _planned(res, data, j) -> None:
    segs = res.segments
    data["segments"][j] = len(segs)
    data["evaluations"][j] = res.evaluations
    if segs:
        data["final_error"][j] = max(s.final_error for s in segs)
        ver = [s.verified_error for s in segs if s.verified_error is not None]
        if ver:
            data["verified_error"][j] = max(ver)
    if res.success:
        data["effort"][j], data["peak_rate"][j], data["peak_torque"][j] = point_metrics(res)


def _point(sw, vals, data, j, cache) -> tuple[PointStatus, str]:
    """Compute one point into row ``j`` of ``data``; returns its status and full message."""
    try:
        kw = sw.problem_of(vals, cache)
        system = kw.pop("system")
        req = PlanRequest.build(system, **kw) if sw.derived else None  # plan() validates its own
    except InvalidInputError as e:
        return PointStatus.INVALID, f"invalid: {e}"
    except Exception as e:  # noqa: BLE001 - one point's crash must not stop the sweep
        return PointStatus.NOT_CONVERGED, _crash(e, "building the point")
    proof, crash = _derived(sw, req, data, j) if sw.derived else (None, None)
    if not sw.planned:
        if crash:
            return PointStatus.NOT_CONVERGED, crash
        return (PointStatus.INFEASIBLE, f"infeasible: {proof}") if proof else (PointStatus.SUCCESS, "success: derived")
    quiet = Progress(enabled=False)  # a point reports nothing (the sweep shows its points)
    try:
        with quiet.active():
            res = _plan(system, **{**kw, "progress": False})
    except InvalidInputError as e:
        return PointStatus.INVALID, f"invalid: {e}"
    except Exception as e:  # noqa: BLE001
        return PointStatus.NOT_CONVERGED, _crash(e, "planning")
    with quiet.active():
        _planned(res, data, j)
    return PointStatus(res.status.value), res.message


def _empty(sw, n: int) -> dict[str, np.ndarray]:
    return {name: np.full(n, fill, dtype=dtype) for name, dtype, fill, _ in sw.variables()}


def compute_chunk(sw, chunk: int, points=None) -> dict[str, Any]:
    """Compute chunk ``chunk`` of sweep ``sw`` here: every point of it, or only ``points`` (flat
    indices within it).

    Returns
    -------
    dict
        ``{"chunk", "points", "data": {name: array}, "coords", "messages": {code: template}, "pid",
        "compiled", "seconds"}``.
    """
    t_start = time.perf_counter()
    idx = sw.chunk_points(chunk) if points is None else np.asarray(points, dtype=np.int64)
    values = sw.values(idx)
    columns = {f: a.tolist() for f, a in values.items()}
    data = _empty(sw, idx.size)
    messages: dict[int, str] = {}
    cache: dict = {}
    with one_blas_thread():
        for j in range(idx.size):
            t0 = time.perf_counter()
            status, message = _point(sw, {f: c[j] for f, c in columns.items()}, data, j, cache)
            code, tpl = message_code(message)
            messages.setdefault(code, tpl)
            data["status"][j] = status.code
            data["message"][j] = code
            data["seconds"][j] = time.perf_counter() - t0
    return {"chunk": int(chunk), "points": idx, "data": data, "coords": values, "messages": messages,
            "pid": os.getpid(), "compiled": backend.compiled_count(), "seconds": time.perf_counter() - t_start}


def evaluate_point(sw, index: int) -> SweepPoint:
    """Point ``index`` of sweep ``sw`` computed here, as a :class:`SweepPoint` (full message)."""
    data = _empty(sw, 1)
    vals = sw.point(index)
    with one_blas_thread():
        status, message = _point(sw, vals, data, 0, {})
    out = {k: v[0].item() for k, v in data.items() if k not in ("status", "message", "seconds")}
    return SweepPoint(int(index), vals, status, message, out)


def run_chunk(sweep_, chunk: int, points=None) -> dict[str, Any]:
    """A task: :func:`compute_chunk` in a worker of any executor (the worker compiles the
    integrators on first use and keeps them for its later chunks)."""
    return compute_chunk(sweep_, chunk, points)


def warm_worker(sweep_) -> tuple[int, int]:
    """A task run once per worker before the chunks: compiles the base system's integrators in that
    worker. Returns ``(pid, compiled_count)``."""
    if sweep_.planned and sweep_.system is not None:
        try:
            warm_up(sweep_.system)
        except Exception:  # noqa: BLE001 - only an optimisation
            pass
    return os.getpid(), backend.compiled_count()
