"""One BLAS thread while acroplan plans: the same bits whatever the machine's thread settings, and
no threads spinning over the planners' small matrices.

OpenBLAS (numpy's and scipy's) starts one thread per core, and its threaded products split their
sums by thread, so the last bits of a product depend on how many threads ran it, and a planner's
path with them: planned under one and under two BLAS threads on one machine, the bundled space
robot's turn took 378 against 371 endpoint evaluations, the falling cat and the twisting dives
ended at other coefficients (the dives at the same optima, their costs equal to 6e-13 relative;
the forward 1 1/2 somersault with two twists in 426 against 428 evaluations:
``benchmarks/RESULTS.md``, fifteenth session). The planners' matrices are
small (at most a few hundred rows), where the threads' start-up and spinning cost more than they
share: the twisting dives took 10-70% longer with two threads on two cores.

:func:`acroplan.plan` holds :func:`one_blas_thread` while it plans: every BLAS library loaded in
the process runs one thread, and each gets back the count it had when the last holder leaves
(holders may nest and may be threads of one process, as :func:`acroplan.plan_many`'s thread
executor; the count is per process). A caller's ``OPENBLAS_NUM_THREADS`` or ``threadpoolctl``
limit holds outside plans. The hold costs about 3 us (three calls into each library); the
libraries (numpy's and scipy's, imported first) are found once, the first time, by
``threadpoolctl`` (the maintained way to reach them). Without ``threadpoolctl`` it does nothing,
and a library whose count cannot be read or set is left as it is: a plan is never refused for it.
"""

from __future__ import annotations

import itertools
import threading

__all__ = ["one_blas_thread"]

_lock = threading.Lock()
_holders = 0
_saved: list[tuple[object, int]] = []
_libraries: list | None = None


def _blas_libraries() -> list:
    """``[(get_num_threads, set_num_threads)]`` of each BLAS library of this process, found once
    (threadpoolctl's controllers; OpenBLAS with its own threads through its two C functions
    directly, a third of the controller's cost). Empty when they cannot be found: a plan is then
    computed with the threads it finds, never refused for it."""
    global _libraries
    if _libraries is None:
        # numpy's and scipy's libraries loaded first (dependencies, imported by any plan anyway), so
        # that the first holder holds the same libraries as every later one
        import numpy  # noqa: F401
        import scipy.linalg  # noqa: F401

        try:
            from threadpoolctl import ThreadpoolController

            _libraries = [_functions(lib) for lib in ThreadpoolController().lib_controllers
                          if lib.user_api == "blas"]
        except Exception:  # noqa: BLE001 - no threadpoolctl, or one that cannot read this process
            _libraries = []
    return _libraries


def _functions(lib) -> tuple:
    """``(get, set)`` of one of threadpoolctl's library controllers."""
    dynlib = getattr(lib, "dynlib", None)
    if lib.internal_api == "openblas" and getattr(lib, "threading_layer", None) != "openmp" and dynlib is not None:
        # OpenBLAS's exported names carry its build's affixes (scipy's wheels: scipy_..._64_)
        for prefix, suffix in itertools.product(("", "scipy_"), ("", "64_", "_64")):
            get = getattr(dynlib, f"{prefix}openblas_get_num_threads{suffix}", None)
            put = getattr(dynlib, f"{prefix}openblas_set_num_threads{suffix}", None)
            if get is not None and put is not None:
                return get, put
    # any other library (MKL, BLIS, FlexiBLAS, OpenBLAS on OpenMP) through its controller; only
    # threadpoolctl's OpenBLAS controller keeps a controlling thread (in its recent versions),
    # which its own limits clear when they end
    clear = getattr(type(lib), "clear_controlling_thread", None)

    def put(n):
        lib.set_num_threads(n)
        if clear is not None:
            clear()

    return lib.get_num_threads, put


class _OneThread:
    """The context of :func:`one_blas_thread`."""

    __slots__ = ()

    def __enter__(self):
        global _holders
        with _lock:
            if _holders == 0:
                _saved.clear()
                for get, put in _blas_libraries():
                    try:
                        n = get()
                        if n is not None and n != 1:
                            put(1)
                            _saved.append((put, n))
                    except Exception:  # noqa: BLE001 - a library that cannot be set is left as it is
                        pass
            _holders += 1
        return self

    def __exit__(self, *exc):
        global _holders
        with _lock:
            _holders -= 1
            if _holders == 0:
                for put, n in _saved:
                    try:
                        put(n)
                    except Exception:  # noqa: BLE001 - as above
                        pass
                _saved.clear()
        return False


_ONE = _OneThread()


def one_blas_thread() -> _OneThread:
    """A context in which the BLAS libraries of the process run one thread (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from acroplan.core.blas import one_blas_thread
    >>> with one_blas_thread():
    ...     x = np.linalg.solve(np.eye(3), np.ones(3))
    >>> x.tolist()
    [1.0, 1.0, 1.0]
    """
    return _ONE
