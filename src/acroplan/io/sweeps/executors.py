"""Where a sweep's chunks are computed, and how a run keeps going when workers die.

* Local worker processes (the default) watch the driver: each checks every half second that its
  parent is still the process that started it and that the driver lives, and exits at once when
  not (issue #25: a ``kill -9`` of the driver used to leave its workers running, holding the
  driver's output open).
* :func:`drive` keeps a window of chunks in flight and writes each as it finishes. A chunk whose
  task fails (its worker died: the pool broke, or Dask gave up on it) is submitted again; after two
  failures its points are computed one at a time, each alone on the executor (:func:`isolate`), so
  that only a point that kills its worker is marked ``not_converged``, with the reason.
"""

from __future__ import annotations

import collections
import concurrent.futures as cf
import os
import threading
import time
from typing import Callable

import numpy as np

from ...core.errors import InvalidInputError
from ...sweeps.compute import run_chunk
from ...sweeps.definition import Sweep
from ...sweeps.vocabulary import PointStatus, message_code

__all__ = ["executor_for", "new_pool", "watch_parent", "drive", "isolate", "Todo", "WATCH_INTERVAL"]

#: Seconds between a worker's checks that its driver lives.
WATCH_INTERVAL = 0.5


def _watch(parent: int, driver: int) -> None:
    while True:
        time.sleep(WATCH_INTERVAL)
        if os.getppid() != parent or not _alive(driver):
            os._exit(70)  # the driver is gone: nobody will read what this worker computes


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def watch_parent(driver: int) -> None:
    """A worker's initializer: a daemon thread that ends the worker when its parent (the driver,
    or a fork server) changes or the driver ``driver`` is gone."""
    threading.Thread(target=_watch, args=(os.getppid(), int(driver)), name="acroplan-watch-driver",
                     daemon=True).start()


def new_pool(n: int) -> cf.ProcessPoolExecutor:
    """``n`` local worker processes, each watching this process (:func:`watch_parent`)."""
    return cf.ProcessPoolExecutor(max_workers=n, initializer=watch_parent, initargs=(os.getpid(),))


def _dask(client):
    info = client.scheduler_info()
    n = sum(int(w.get("nthreads", 1)) for w in info.get("workers", {}).values()) or 1
    return client.get_executor(pure=False), n


def _scheduler(scheduler: str):
    try:
        from distributed import Client
    except ImportError:  # pragma: no cover - a dependency
        raise InvalidInputError("scheduler", "needs dask.distributed", "pip install \"dask[distributed]\"") from None
    try:
        client = Client(scheduler, timeout="20s")
    except (OSError, TimeoutError, ValueError) as e:
        raise InvalidInputError("--scheduler", f"cannot connect to {scheduler} ({type(e).__name__}: {e})",
                                "give the address of a running dask scheduler, tcp://HOST:PORT") from None
    pool, n = _dask(client)
    return pool, False, n, "dask", client.close


def executor_for(executor, workers: int | None, scheduler: str | None):
    """``(submit-able executor, owned, workers, kind, closer)``; the local pool (kind
    ``"process"``) is started later by the caller (:func:`new_pool`)."""
    if scheduler is not None:
        if executor is not None:
            raise InvalidInputError("scheduler", "is given together with executor", "give one of them")
        return _scheduler(scheduler)
    if executor is None or executor == "process":
        return None, True, int(workers or os.cpu_count() or 1), "process", None
    if executor == "serial":
        return None, False, 1, "serial", None
    if executor == "thread":
        n = int(workers or os.cpu_count() or 1)
        return cf.ThreadPoolExecutor(max_workers=n), True, n, "thread", None
    if type(executor).__module__.startswith("distributed") and hasattr(executor, "get_executor"):
        pool, n = _dask(executor)
        return pool, False, n, "dask", None
    if isinstance(executor, cf.Executor):
        n = int(workers or getattr(executor, "_max_workers", None) or os.cpu_count() or 1)
        return executor, False, n, "executor", None
    raise InvalidInputError("executor", "must be \"process\", \"thread\", \"serial\", a concurrent.futures.Executor "
                            f"or a dask.distributed.Client, got {type(executor).__name__}",
                            "leave it out for local processes")


class Todo:
    """The chunks left: a walk over the chunks not ``good`` (never listed whole), then retries."""

    def __init__(self, good: np.ndarray):
        self.good, self._next, self.retry = good, 0, collections.deque()

    def pop(self) -> int | None:
        if self.retry:
            return self.retry.popleft()
        n = self.good.size
        while self._next < n:
            c, self._next = self._next, self._next + 1
            if not self.good[c]:
                return c
        return None

    def again(self, chunk: int) -> None:
        self.retry.append(chunk)

    def left(self) -> int:
        return len(self.retry) + int((~self.good[self._next:]).sum())


class _Run:
    """One :func:`drive`: the executor, the chunks in flight, the failures."""

    def __init__(self, sw, ctx, owned, n_workers, todo, finished, window):
        self.sw, self.ctx, self.owned, self.n, self.todo, self.finished = sw, ctx, owned, n_workers, todo, finished
        self.window = int(window or 2 * n_workers + 2)
        self.failures: collections.Counter = collections.Counter()
        self.suspects: list[int] = []
        self.inflight: dict = {}

    def failed(self, c: int) -> None:
        self.failures[c] += 1
        if self.failures[c] >= 2:
            self.suspects.append(c)
        else:
            self.todo.again(c)

    def fill(self):
        """Submit chunks up to the window; the BrokenExecutor a submission raised, if any."""
        while len(self.inflight) < self.window:
            c = self.todo.pop()
            if c is None:
                return None
            try:
                self.inflight[self.ctx["pool"].submit(run_chunk, self.sw, c)] = c
            except cf.BrokenExecutor as e:  # the pool broke before a task of it said so
                self.todo.retry.appendleft(c)
                return e
        return None

    def collect(self, futures):
        broken = None
        for fut in futures:
            c = self.inflight.pop(fut)
            try:
                result = fut.result()
            except (Exception, SystemExit) as e:  # noqa: BLE001 - the task failed; retried
                broken = e if isinstance(e, cf.BrokenExecutor) else broken
                self.failed(c)
                continue
            self.finished(result)
        return broken

    def renew(self, broken) -> None:
        """After the pool broke: keep what finished, retry the rest on a new pool."""
        self.collect(list(self.inflight))
        if not self.owned:
            raise RuntimeError(f"the executor given broke ({type(broken).__name__}: {broken}); "
                               f"{self.todo.left() + len(self.suspects)} chunk(s) are not done: run the sweep again "
                               "to finish them (what is done is kept)")
        self.ctx["pool"].shutdown(wait=True, cancel_futures=True)
        self.ctx["pool"] = new_pool(self.n)


def drive(sw: Sweep, ctx: dict, owned: bool, n_workers: int, todo: Todo, finished: Callable,
          window: int | None) -> None:
    """Keep ``window`` chunks in flight (default twice the workers, plus two); write each as it
    finishes (``finished(result)``); retry and isolate failures (module docstring). ``ctx["pool"]``
    is the executor (a new one when an owned pool broke)."""
    run = _Run(sw, ctx, owned, n_workers, todo, finished, window)
    while True:
        broken = run.fill()
        if not run.inflight and broken is None:
            break
        if broken is None:
            ready = cf.wait(list(run.inflight), return_when=cf.FIRST_COMPLETED)[0]
            broken = run.collect(ready)
        if broken is not None:
            run.renew(broken)
    for c in sorted(run.suspects):
        isolate(sw, ctx, owned, n_workers, c, finished)


def isolate(sw: Sweep, ctx: dict, owned: bool, n_workers: int, chunk: int, finished: Callable) -> None:
    """Compute a chunk whose task failed twice point by point, each point alone on the executor."""
    parts = []
    for p in sw.chunk_points(chunk):
        try:
            parts.append(ctx["pool"].submit(run_chunk, sw, chunk, [int(p)]).result())
        except (Exception, SystemExit) as e:  # noqa: BLE001 - this point kills its worker
            parts.append(_failed_point(sw, chunk, int(p), e))
            if isinstance(e, cf.BrokenExecutor):
                if not owned:
                    raise RuntimeError(f"the executor given broke ({type(e).__name__}: {e}); run the sweep again "
                                       "to finish (what is done is kept)") from None
                ctx["pool"].shutdown(wait=True, cancel_futures=True)
                ctx["pool"] = new_pool(n_workers)
    data = {k: np.concatenate([r["data"][k] for r in parts]) for k in parts[0]["data"]}
    coords = {k: np.concatenate([r["coords"][k] for r in parts]) for k in parts[0]["coords"]}
    messages = {}
    for r in parts:
        messages.update(r["messages"])
    pids = [r["pid"] for r in parts if "pid" in r]
    finished({"chunk": chunk, "points": sw.chunk_points(chunk), "data": data, "coords": coords, "messages": messages,
              **({"pid": pids[-1], "compiled": max(r["compiled"] for r in parts if "pid" in r)} if pids else {})})


def _failed_point(sw: Sweep, chunk: int, p: int, e: BaseException) -> dict:
    data = {name: np.full(1, fill, dtype=dtype) for name, dtype, fill, _ in sw.variables()}
    msg = f"not converged: the worker computing this point died or failed ({type(e).__name__}: {e})"
    code, tpl = message_code(msg)
    data["status"][0] = PointStatus.NOT_CONVERGED.code
    data["message"][0] = code
    return {"chunk": chunk, "points": np.array([p]), "data": data, "coords": sw.values([p]), "messages": {code: tpl}}
