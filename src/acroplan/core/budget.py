"""A wall-clock budget for one plan.

:func:`acroplan.plan` opens a budget (``time_limit`` seconds) around its work; the solvers call
:func:`check` at every endpoint evaluation and the checking integrator at every right-hand side
call (every 256th), and a compilation is waited for until the deadline (:func:`wait`), so a plan
that would run too long ends, between two evaluations or at its deadline while it compiles, with
:class:`BudgetExceeded`, which the front door turns into ``not_converged`` with the diagnostics
gathered so far. The budget is a context variable: each thread (and each worker process) has its
own, and code run outside a plan has none.
"""

from __future__ import annotations

import contextvars
import time

__all__ = ["BudgetExceeded", "budget", "check", "now", "remaining", "wait"]

#: The clock of every budget (monotonic seconds). A module attribute, so that tests can replace it
#: with a virtual clock and assert on counts of checks instead of wall-clock times.
_clock = time.monotonic

_DEADLINE: contextvars.ContextVar[tuple[float, float] | None] = contextvars.ContextVar("acroplan_deadline",
                                                                                      default=None)


class BudgetExceeded(RuntimeError):
    """The plan's time budget is spent."""

    def __init__(self, limit: float):
        self.limit = limit
        super().__init__(f"the time budget of {limit:g} s was spent (time_limit)")


def budget(seconds: float | None, *, start: float | None = None) -> "_Budget":
    """Run the body with a deadline ``seconds`` from now, or from ``start`` (a reading of
    :func:`now`, taken when the work began) (``None``: no deadline of its own). Budgets nest:
    inside another budget the earlier deadline holds (the command line opens one around a plan and
    its effort summary, and the plan opens its own). A context manager: ``with budget(60): ...``."""
    return _Budget(seconds, start)


class _Budget:
    """:func:`budget`'s context manager (a class, not a generator: it wraps every plan, and a
    generator's context manager costs several calls more)."""

    __slots__ = ("seconds", "start", "token")

    def __init__(self, seconds, start):
        self.seconds, self.start, self.token = seconds, start, None

    def __enter__(self) -> None:
        outer = _DEADLINE.get()
        seconds, start = self.seconds, self.start
        inner = None if seconds is None else ((_clock() if start is None else float(start)) + float(seconds),
                                              float(seconds))
        if outer is not None and (inner is None or outer[0] < inner[0]):
            inner = outer
        self.token = _DEADLINE.set(inner)

    def __exit__(self, *exc) -> None:
        _DEADLINE.reset(self.token)


def now() -> float:
    """The budget's clock (monotonic seconds): where a budget opened later starts (``start=``)."""
    return _clock()


def check() -> None:
    """Raise :class:`BudgetExceeded` when the current budget is spent."""
    d = _DEADLINE.get()
    if d is not None and _clock() > d[0]:
        raise BudgetExceeded(d[1])


def wait(event) -> None:
    """Wait for ``event`` (a :class:`threading.Event`) within the current budget: raise
    :class:`BudgetExceeded` at the deadline if it is not set by then (no budget: wait for it)."""
    d = _DEADLINE.get()
    if d is None:
        event.wait()
        return
    if event.is_set():
        return
    left = d[0] - _clock()
    if left <= 0 or not event.wait(left):
        raise BudgetExceeded(d[1])


def remaining() -> float | None:
    """Seconds left in the current budget (``None`` without one)."""
    d = _DEADLINE.get()
    return None if d is None else d[0] - _clock()
