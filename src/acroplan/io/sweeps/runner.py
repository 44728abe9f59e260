"""Running a sweep into a store (:func:`run_sweep`) and what a run reports (:class:`SweepSummary`).

A run killed at any moment (the driver or a worker, ``kill -9``) leaves a record that names only
chunks written whole, each with its checksum; started again with the same definition, it checks
every chunk the record names against its checksum, recomputes those that do not match (and those
not done), and re-derives the counts from the chunks.
"""

from __future__ import annotations

import collections
import dataclasses
import multiprocessing
import time
from pathlib import Path
from typing import Callable, Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ...core.sweep_hooks import resolve_factory
from ...sweeps.compute import run_chunk, warm_worker
from ...sweeps.definition import Sweep
from ...sweeps.vocabulary import FORMAT, STATUS_CODES, PointStatus
from .check import check_store, verify_chunks
from .executors import Todo, drive, executor_for, new_pool
from .writer import open_or_create

__all__ = ["run_sweep", "SweepSummary"]


@dataclasses.dataclass(frozen=True)
class SweepSummary:
    """What :func:`run_sweep` did.

    Attributes
    ----------
    store : str
    points, chunks : int
        The sweep's size.
    done_before : int
        Points found done (and matching their checksums) in the store: a resumed sweep.
    computed : int
        Points computed by this run.
    counts : dict
        Points by status over the whole store (``success``, ``infeasible``, ``not_converged``,
        ``invalid``), counted from the chunks themselves.
    complete : bool
    seconds, rate : float
        This run's wall time and points per second.
    workers : dict
        Per worker process (process id): ``{"chunks": chunks computed there, "compiled":
        integrators compiled in that process}`` (one per structure and basis size: it does not grow
        with the chunks). A worker that died and was replaced is a process of its own here.
    messages : dict
        The most frequent message of each status other than success (template with ``#`` for the
        numbers).
    n_workers : int
        The workers the run computed on at once (local processes, threads, or the Dask cluster's
        worker threads when the run started): replaced workers are not counted again.
    replaced : int
        Worker processes beyond ``n_workers`` that computed chunks: replacements of workers that
        died (or, on a Dask cluster, workers added during the run).
    recomputed : list
        ``[chunk, why]`` of the chunks the record named as done that did not match their checksum
        (or could not be read), computed again by this run.
    """

    store: str
    points: int
    chunks: int
    done_before: int
    computed: int
    counts: dict
    complete: bool
    seconds: float
    rate: float
    workers: dict
    messages: dict
    n_workers: int = 0
    replaced: int = 0
    recomputed: list = dataclasses.field(default_factory=list)

    def lines(self) -> list[str]:
        out = [f"{self.points} points in {self.chunks} chunks: " +
               ", ".join(f"{self.counts.get(k, 0)} {k}" for k in STATUS_CODES if self.counts.get(k, 0)) +
               ("" if self.complete else f"; {self.points - sum(self.counts.values())} not computed yet")]
        if self.recomputed:
            out.append(f"recomputed {len(self.recomputed)} damaged chunk(s): chunks " +
                       ", ".join(str(c) for c, _ in self.recomputed[:10]) + (" ..." if len(self.recomputed) > 10
                                                                               else ""))
        if self.done_before:
            out.append(f"resumed: {self.done_before} points were done, {self.computed} computed now")
        workers = ""
        if self.workers:
            again = f" ({self.replaced} replaced)" if self.replaced else ""
            workers = (f" on {self.n_workers or len(self.workers)} worker(s){again}, integrators compiled per worker: "
                       f"{sorted(w['compiled'] for w in self.workers.values())}")
        out.append(f"{self.computed} points in {self.seconds:.1f} s ({self.rate:.0f} points/s)" + workers)
        for status, tpl in self.messages.items():
            out.append(f"most frequent {status} message: {tpl}")
        out.append(f"wrote {self.store}" + ("" if self.complete else " (incomplete: run again to resume)"))
        return out

    def to_dict(self) -> dict:
        return dataclasses.asdict(self)


def _progress_bar(progress, total: int, initial: int):
    """``(update(done), close())``: a tqdm bar (rate and time left) or a callback or nothing."""
    if callable(progress):
        return (lambda done: progress(done, total)), (lambda: None)
    from ...core.progress import Progress, auto

    prog = Progress(enabled=auto() if progress is None else bool(progress))
    if not prog.enabled:
        return (lambda done: None), (lambda: None)
    st = prog.stage("sweep", total, unit="pt")  # refreshed while a chunk runs (core.progress)
    st.set(initial)
    return st.set, prog.close


def _ready(sweep_, factories: Mapping[str, Callable] | None) -> Sweep:
    """The sweep, its factory resolved (registered names and ``factories``) and its base system
    rebuilt: anything missing is an error before any work."""
    if not isinstance(sweep_, Sweep):
        raise InvalidInputError("sweep", f"must be an acroplan Sweep, got {type(sweep_).__name__}",
                                "build it with acroplan.sweep(...) or load_sweep(path)")
    if sweep_.is_factory and sweep_.factory is None:
        return Sweep(sweep_.definition, None, resolve_factory(sweep_.definition["base"]["factory"], factories))
    if not sweep_.is_factory and sweep_.system is None:
        try:
            return Sweep(sweep_.definition, sweep_.base_system, None)
        except InvalidInputError as e:
            raise InvalidInputError(f"base.system.{e.field}", e.problem, e.fix) from None
    return sweep_


class _State:
    """What a run has done so far (the summary's numbers)."""

    def __init__(self, store, done: int, codes: dict, update: Callable):
        self.store, self.done, self.done_before, self.computed, self.update = store, done, done, 0, update
        self.workers: dict = {}
        self.codes = {k: collections.Counter(v) for k, v in codes.items()}

    def finished(self, result: dict) -> None:
        self.store.write(result)
        n = len(result["points"])
        self.done += n
        self.computed += n
        if "pid" in result:
            w = self.workers.setdefault(result["pid"], {"chunks": 0, "compiled": 0})
            w["chunks"] += 1
            w["compiled"] = max(w["compiled"], int(result["compiled"]))
        status, message = np.asarray(result["data"]["status"]), np.asarray(result["data"]["message"])
        for code in np.unique(status):
            st = PointStatus.from_code(int(code))
            if st is not None and not st.success:
                self.codes.setdefault(st.value, collections.Counter()).update(message[status == code].tolist())
        self.update(self.done)

    def frequent(self, messages: dict) -> dict:
        return {k: messages.get(str(v.most_common(1)[0][0]), "?") for k, v in self.codes.items() if v}


def _start_local(sweep_: Sweep, n_workers: int):
    if multiprocessing.get_start_method(allow_none=True) in (None, "fork"):
        warm_worker(sweep_)  # forked workers inherit the parent's integrators
    pool = new_pool(n_workers)
    # start the workers (and compile there) before this process opens the store
    for f in [pool.submit(warm_worker, sweep_) for _ in range(n_workers)]:
        f.result()
    return pool


def _compute(store, sweep_, ctx, kind, owned, n_workers, progress, window):
    """Verify the store's chunks, then compute the rest; ``(state, verification)``."""
    ver = verify_chunks(store.path, sweep_, store.record, FORMAT)
    store.reset(ver.good, ver.counts)
    done_before = sum(ver.counts.values())  # the points of the good chunks
    update, close_bar = _progress_bar(progress, sweep_.size, done_before)
    state = _State(store, done_before, ver.codes, update)
    todo = Todo(ver.good.copy())
    try:
        if kind == "serial":
            while (c := todo.pop()) is not None:
                state.finished(run_chunk(sweep_, c))
        else:
            drive(sweep_, ctx, owned, n_workers, todo, state.finished, window)
    finally:
        close_bar()
    return state, ver


def run_sweep(sweep_: Sweep, out, *, executor=None, workers: int | None = None, scheduler: str | None = None,
              progress=None, window: int | None = None, factories: Mapping[str, Callable] | None = None
              ) -> SweepSummary:
    """Compute a sweep into a zarr store, chunk by chunk; resume it if the store holds part of it.

    Parameters
    ----------
    sweep_ : Sweep
        From :func:`acroplan.sweep` or :func:`acroplan.load_sweep`.
    out : path
        The store: a new path (created), or a store this definition started (resumed: every chunk
        it names is checked against its checksum, and only the chunks not done, or damaged, are
        computed).
    executor : {"process", "thread", "serial"}, concurrent.futures.Executor or dask.distributed.Client
        Where the chunks are computed: local worker processes (default; they end themselves when
        this process dies), or a Dask cluster's workers through its client (each worker compiles
        the integrators once and keeps them), or any executor. An executor or client passed in is
        not shut down.
    workers : int, optional
        Local worker processes (default: one per core).
    scheduler : str, optional
        A Dask scheduler's address (``tcp://HOST:PORT``) to connect to instead of ``executor``.
    progress : bool or callable, optional
        A progress bar on stderr (default: when it is a terminal), or ``progress(done, total)``.
    window : int, optional
        Chunks in flight at once (default: twice the workers, plus two): the memory of the run is
        this many chunks' results, whatever the number of points.
    factories : mapping of str to callable, optional
        For a sweep read from a definition (:func:`acroplan.sweeps.from_definition`) whose system
        factory is not registered: the factory by the name the definition records. A store's
        definition is never imported.

    Returns
    -------
    SweepSummary

    Raises
    ------
    InvalidInputError
        For a store that is refused (:mod:`acroplan.io.sweeps.check`), or bad arguments, before
        any work.
    """
    sweep_ = _ready(sweep_, factories)
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, (int, np.integer))
                                or workers < 1):
        raise InvalidInputError("workers", f"must be a whole number >= 1, got {workers!r}", "leave it out")
    path = Path(out)
    if path.exists() and not (path.is_dir() and not any(path.iterdir())):
        check_store(path, sweep_)  # refuse a bad store before starting any worker
    pool, owned, n_workers, kind, closer = executor_for(executor, workers, scheduler)
    ctx = {"pool": pool}
    t_start = time.perf_counter()
    store = None
    try:
        if kind == "process":
            ctx["pool"] = _start_local(sweep_, n_workers)
        store = open_or_create(path, sweep_)
        state, ver = _compute(store, sweep_, ctx, kind, owned, n_workers, progress, window)
        record = store.record
        counts, complete = dict(record.counts), record.n_done() == sweep_.n_chunks
    finally:
        if store is not None:
            store.close()
        if owned and ctx["pool"] is not None:
            ctx["pool"].shutdown(wait=True, cancel_futures=True)
        if closer is not None:
            closer()
    seconds = time.perf_counter() - t_start
    return SweepSummary(str(path), sweep_.size, sweep_.n_chunks, state.done_before, state.computed, counts, complete,
                        seconds, state.computed / seconds if seconds > 0 else 0.0, dict(state.workers),
                        state.frequent(record.messages), n_workers=n_workers,
                        replaced=max(0, len(state.workers) - n_workers), recomputed=[list(b) for b in ver.bad])

