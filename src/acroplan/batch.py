"""Many independent problems at once: :func:`plan_many`.

Problems are planned by worker processes (``executor="process"``, the default: the planner is
mostly Python, so threads share one interpreter lock), by threads, or one after another. The
parent compiles the integrators first (:func:`acroplan.warm_up`, ~0.1 s), so forked workers
inherit them (where processes are spawned instead, each worker compiles its own). Results come
back in input order and are bit-for-bit those of :func:`acroplan.plan` called one by one (same
code, same deterministic arithmetic). Every
problem is validated before any work starts, so bad input fails fast and names the problem; once
planning has started, one problem's failure (infeasible, not converged, or even an unexpected
error, reported as ``not_converged`` with the error) never stops the others.
"""

from __future__ import annotations

import concurrent.futures as cf
import functools
import os
import traceback
from typing import Any, Iterable

from ._errors import InvalidInputError
from .planner import AUTO_SIZES, plan, warm_up
from .problem import Problem
from .result import PlanResult

__all__ = ["plan_many", "EXECUTORS"]

EXECUTORS = ("process", "thread", "serial")


def _as_kwargs(i: int, p) -> dict[str, Any]:
    if isinstance(p, Problem):
        return dict(system=p.robot, times=p.times, theta=p.theta, phi=p.phi, conditions=p.conditions, **p.options)
    if isinstance(p, dict):
        if "system" not in p:
            raise InvalidInputError(f"problems[{i}].system", "is missing",
                                    "give each problem as a dict with 'system' and the plan() keywords, or a Problem")
        return dict(p)
    raise InvalidInputError(f"problems[{i}]", f"must be a dict or a Problem, got {type(p).__name__}",
                            "give dicts of plan() keywords with 'system', or acroplan.Problem objects")


def _run(kwargs: dict[str, Any]) -> PlanResult:
    kwargs = dict(kwargs)
    system = kwargs.pop("system")
    try:
        return plan(system, **kwargs)
    except InvalidInputError:
        raise
    except Exception as e:  # one problem's bug must not stop the batch; it is reported, not hidden
        import numpy as np

        from .basis import make_basis

        times = np.asarray(kwargs["times"], dtype=float)
        X = np.stack([np.asarray(kwargs[name], dtype=float) for name in system.state_names], axis=1)
        msg = f"not converged: unexpected {type(e).__name__}: {e}\n{traceback.format_exc()}"
        return PlanResult("not_converged", msg, system=system, times=times, waypoints=X,
                          conditions=kwargs.get("conditions", "spline"),
                          basis=make_basis(kwargs.get("basis", "legendre"), kwargs.get("n_coefficients") or 6))


@functools.cache
def _plan_options() -> tuple[tuple[str, Any], ...]:
    """plan()'s keyword-only options (but ``progress``) with their defaults."""
    import inspect

    params = inspect.signature(plan).parameters
    return tuple((name, p.default) for name, p in params.items()
                 if p.kind is inspect.Parameter.KEYWORD_ONLY and name != "progress")


def _validate(kwargs: dict[str, Any]) -> None:
    """plan()'s own input checks, without planning."""
    from .planner import _validated

    k = dict(kwargs)
    system = k.pop("system")
    opts = {name: k.pop(name, default) for name, default in _plan_options()}
    _validated(system, **opts, waypoints=k)


def plan_many(problems: Iterable, *, executor: str = "process", workers: int | None = None, progress=None,
              **options) -> list[PlanResult]:
    """Plan many independent problems.

    Parameters
    ----------
    problems : iterable of dict or Problem
        Each a dict of :func:`acroplan.plan` keywords with the system under ``"system"``, or a
        :class:`~acroplan.problem.Problem`.
    executor : {"process", "thread", "serial"}
        Where the work runs (module docstring).
    workers : int, optional
        Number of workers (default: the number of cores).
    progress : callable, optional
        Called as ``progress(done, total)`` after each problem (for a progress bar).
    **options
        :func:`acroplan.plan` keywords applied to every problem (a problem's own win).

    Returns
    -------
    list of PlanResult
        In input order.

    Raises
    ------
    InvalidInputError
        Before any planning, naming the first invalid problem (``problems[i]...``).
    """
    if executor not in EXECUTORS:
        raise InvalidInputError("executor", f"must be one of {list(EXECUTORS)}, got {executor!r}",
                                "use \"process\" (default), \"thread\" or \"serial\"")
    jobs = []
    for i, p in enumerate(problems):
        kw = {**options, **_as_kwargs(i, p)}
        try:
            _validate(kw)
        except InvalidInputError as e:
            raise InvalidInputError(f"problems[{i}].{e.field}", e.problem, e.fix) from None
        jobs.append(kw)
    n = len(jobs)
    workers = workers or os.cpu_count() or 1
    results: list[PlanResult | None] = [None] * n
    if executor == "serial" or n <= 1 or workers == 1:
        for i, kw in enumerate(jobs):
            results[i] = _run(kw)
            if progress:
                progress(i + 1, n)
        return results  # type: ignore[return-value]
    if executor == "process":
        # compile in the parent: forked workers inherit the compiled integrators instead of each
        # compiling its own
        for cls, basis, size in {(type(kw["system"]), kw.get("basis", "legendre"), kw.get("n_coefficients"))
                                 for kw in jobs}:
            warm_up(cls, basis=basis, sizes=AUTO_SIZES if size is None else (size,) + AUTO_SIZES)
    pool_cls = cf.ProcessPoolExecutor if executor == "process" else cf.ThreadPoolExecutor
    chunks = max(1, min(64, n // (4 * workers)))
    with pool_cls(max_workers=workers) as pool:
        if executor == "process":
            for i, res in enumerate(pool.map(_run, jobs, chunksize=chunks)):
                results[i] = res
                if progress:
                    progress(i + 1, n)
        else:
            futs = {pool.submit(_run, kw): i for i, kw in enumerate(jobs)}
            for done, fut in enumerate(cf.as_completed(futs), 1):
                results[futs[fut]] = fut.result()
                if progress:
                    progress(done, n)
    return results  # type: ignore[return-value]
