"""Many independent problems at once: :func:`plan_many`.

Problems are planned on an executor: worker processes (``"process"``, the default: the planner is
mostly Python, so threads share one interpreter lock), threads (``"thread"``), one after another
(``"serial"``), or any :class:`concurrent.futures.Executor` the caller passes (``loky``'s, Dask's
``Client.get_executor()``, a pool of their own). Work goes out in chunks; each worker compiles the
integrators it needs on first use and keeps them for its later chunks (with ``"process"`` on a
``fork`` platform the parent compiles first and the workers inherit them, which saves the first
chunk's compilation but is not needed for correctness).

Results come back in input order and are bit-for-bit those of :func:`acroplan.plan` called one by
one (same code, same deterministic arithmetic). Every problem is validated before any work
starts, so bad input fails fast and names the problem; once planning has started, one problem's
failure (infeasible, not converged, an unexpected error, or its worker dying) never stops the
others: it is reported as ``not_converged`` with the reason.
"""

from __future__ import annotations

import concurrent.futures as cf
import multiprocessing
import os
import traceback
from typing import Any, Iterable

import numpy as np

from .core.basis import make_basis
from .core.errors import InvalidInputError
from .core.progress import Progress
from .core.progress import current as current_progress
from .core.progress import resolve as resolve_progress
from .core.result import PlanResult, Status
from .planning import PlanRequest, plan, warm_up

__all__ = ["plan_many", "EXECUTORS"]

#: Executor names :func:`plan_many` accepts (besides any ``concurrent.futures.Executor``).
EXECUTORS = ("process", "thread", "serial")


def _as_kwargs(i: int, p) -> dict[str, Any]:
    if hasattr(p, "plan_kwargs") and callable(p.plan_kwargs) and hasattr(p, "robot"):
        return {"system": p.robot, **p.plan_kwargs()}
    if isinstance(p, dict):
        if "system" not in p:
            raise InvalidInputError(f"problems[{i}].system", "is missing",
                                    "give each problem as a dict with 'system' and the plan() keywords, or a Problem")
        return dict(p)
    raise InvalidInputError(f"problems[{i}]", f"must be a dict or a Problem, got {type(p).__name__}",
                            "give dicts of plan() keywords with 'system', or acroplan.Problem objects")


def _failed(kwargs: dict[str, Any], why: str) -> PlanResult:
    """A ``not_converged`` result for a problem that could not be planned at all."""
    system = kwargs["system"]
    times = np.asarray(kwargs["times"], dtype=float)
    X = np.stack([np.asarray(kwargs[name], dtype=float) for name in system.state_names], axis=1)
    return PlanResult(status=Status.NOT_CONVERGED, message=f"not converged: {why}", system=system, times=times,
                      waypoints=X, conditions=kwargs.get("conditions") or ("free" if kwargs.get("objective")
                                                                           or kwargs.get("tau_max") is not None
                                                                           else "spline"),
                      basis=make_basis(kwargs.get("basis", "legendre"), kwargs.get("n_coefficients") or 6))


def _run(kwargs: dict[str, Any]) -> PlanResult:
    kwargs = dict(kwargs)
    system = kwargs.pop("system")
    kwargs["progress"] = False  # one problem of many shows nothing (the batch shows "problems")
    try:
        with Progress(enabled=False).active():  # nor does what it computes (effort, samples)
            return plan(system, **kwargs)
    except InvalidInputError:
        raise
    except Exception as e:  # one problem's bug must not stop the batch; it is reported, not hidden
        return _failed({"system": system, **kwargs},
                       f"unexpected {type(e).__name__}: {e}\n{traceback.format_exc()}")


def _run_chunk(jobs: list[dict[str, Any]]) -> list[PlanResult]:
    """Plan a chunk of problems in one task (a worker of any executor)."""
    return [_run(kw) for kw in jobs]


def _executor(executor, workers: int):
    """``(pool, owned)``: the executor to submit to, and whether this call must shut it down."""
    if isinstance(executor, cf.Executor):
        return executor, False
    if executor == "thread":
        return cf.ThreadPoolExecutor(max_workers=workers), True
    return cf.ProcessPoolExecutor(max_workers=workers), True


def plan_many(problems: Iterable, *, executor="process", workers: int | None = None, chunksize: int | None = None,
              progress=None, **options) -> list[PlanResult]:
    """Plan many independent problems.

    Parameters
    ----------
    problems : iterable of dict or Problem
        Each a dict of :func:`acroplan.plan` keywords with the system under ``"system"``, or a
        :class:`~acroplan.io.problem.Problem`.
    executor : {"process", "thread", "serial"} or concurrent.futures.Executor
        Where the work runs (module docstring). An executor passed in is used, not shut down.
    workers : int, optional
        Number of workers for ``"process"`` and ``"thread"`` (default: the number of cores).
    chunksize : int, optional
        Problems per task (default: about four tasks per worker, at most 64 problems each).
    progress : bool, Progress or callable, optional
        The stage ``"problems"`` (:mod:`acroplan.core.progress`): ``None`` (default) shown in a
        notebook and on a terminal, ``True``/``False``, a ``Progress``, or a callable called as
        ``progress(done, total)`` as problems finish. The problems themselves report nothing.
    **options
        :func:`acroplan.plan` keywords applied to every problem (a problem's own win), for example
        ``objective="energy"`` or ``tau_max=50.0`` for optimal plans of every problem (each
        validated, with the problem's system, before any work starts).

    Returns
    -------
    list of PlanResult
        In input order.

    Raises
    ------
    InvalidInputError
        Before any planning, naming the first invalid problem (``problems[i]...``) or option.
    """
    jobs = _jobs(problems, options, executor, workers, chunksize)
    n = len(jobs)
    outer = current_progress()
    prog = resolve_progress(progress, stage="problems")
    try:
        with prog.active(), prog.scope("problems", n, unit="problem") as bar:
            return _plan_jobs(jobs, executor, workers, chunksize, bar.set)
    finally:
        if prog is not outer and not isinstance(progress, Progress):
            prog.close()


def _plan_jobs(jobs, executor, workers, chunksize, progress) -> list[PlanResult]:
    """Plan validated ``jobs`` on ``executor``, calling ``progress(done)`` as they finish."""
    n = len(jobs)
    workers = int(workers or os.cpu_count() or 1)
    results: list[PlanResult | None] = [None] * n
    if executor == "serial" or n == 0 or (not isinstance(executor, cf.Executor) and (n <= 1 or workers == 1)):
        for i, kw in enumerate(jobs):
            results[i] = _run(kw)
            progress(i + 1)
        return results  # type: ignore[return-value]
    if executor == "process" and multiprocessing.get_start_method(allow_none=True) in (None, "fork"):
        # forked workers inherit what the parent compiled (an optimisation: workers compile on
        # first use anyway)
        for system, basis, size in {(kw["system"], kw.get("basis", "legendre"), kw.get("n_coefficients"))
                                    for kw in jobs}:
            if isinstance(basis, str):
                warm_up(system, basis=basis, sizes=(6, 10, 14) if size is None else (size,))
    size = int(chunksize or max(1, min(64, n // (4 * workers))))
    chunks = [list(range(i, min(n, i + size))) for i in range(0, n, size)]
    _on_executor(jobs, chunks, results, executor, workers, progress)
    return results  # type: ignore[return-value]


def _jobs(problems, options, executor, workers, chunksize) -> list[dict]:
    """The options checked and every problem validated (with its system), before any work."""
    if not (isinstance(executor, cf.Executor) or executor in EXECUTORS):
        raise InvalidInputError("executor", f"must be one of {list(EXECUTORS)} or a concurrent.futures.Executor, "
                                f"got {executor!r}", "use \"process\" (default), \"thread\", \"serial\" or an executor")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, (int, np.integer)) or workers < 1):
        raise InvalidInputError("workers", f"must be a whole number >= 1, got {workers!r}",
                                "leave it out for one worker per core")
    if chunksize is not None and (isinstance(chunksize, bool) or not isinstance(chunksize, (int, np.integer))
                                  or chunksize < 1):
        raise InvalidInputError("chunksize", f"must be a whole number >= 1, got {chunksize!r}", "give for example 16")
    jobs = []
    for i, p in enumerate(problems):
        kw = {**options, **_as_kwargs(i, p)}
        try:
            PlanRequest.build(**{k: v for k, v in kw.items() if k != "progress"})
        except InvalidInputError as e:
            raise InvalidInputError(f"problems[{i}].{e.field}", e.problem, e.fix) from None
        jobs.append(kw)
    return jobs


def _on_executor(jobs, chunks, results, executor, workers, progress) -> None:
    """Plan the chunks on the executor into ``results``; a task that fails because its worker died
    or exited is planned again one problem at a time (on a fresh pool when the pool broke), so that
    only the culprit is marked."""
    pool, owned = _executor(executor, workers)
    done = [0]

    def record(idx, out):
        for i, res in zip(idx, out):
            results[i] = res
        done[0] += len(idx)
        progress(done[0])

    def fail(i, e, what="the worker planning this problem failed"):
        record([i], [_failed(jobs[i], f"{what} ({type(e).__name__}: {e})")])

    try:
        suspects, broken = [], None
        futures = {pool.submit(_run_chunk, [jobs[i] for i in idx]): idx for idx in chunks}
        for fut in cf.as_completed(futures):
            idx = futures[fut]
            try:
                record(idx, fut.result())
            except InvalidInputError:
                raise
            except (Exception, SystemExit) as e:  # the task failed: a worker died, or exited
                if isinstance(e, cf.BrokenExecutor):
                    broken = e  # every task still running or pending fails with it, innocent or not
                if len(idx) == 1 and broken is None:
                    fail(idx[0], e)
                else:
                    suspects += idx
        # which problem was it? the suspects one at a time, each alone on the executor
        for i in sorted(suspects):
            if broken is not None:
                if not owned:  # the caller's executor is broken: say so, never lose a problem silently
                    fail(i, broken, "a worker of the executor died while this problem was pending or running")
                    continue
                pool.shutdown(wait=True, cancel_futures=True)
                pool, owned, broken = *_executor(executor, workers), None
            try:
                record([i], pool.submit(_run_chunk, [jobs[i]]).result())
            except InvalidInputError:
                raise
            except (Exception, SystemExit) as e:
                if isinstance(e, cf.BrokenExecutor):
                    broken = e
                fail(i, e)
    finally:
        if owned:
            pool.shutdown(wait=True, cancel_futures=True)
