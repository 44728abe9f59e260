"""Interval strategies: how one waypoint interval is planned, and their registry.

A strategy is an object with a :attr:`~Strategy.name` and a :meth:`~Strategy.solve` that takes an
:class:`Interval` (the system, the end states, the duration, the input conditions and limits) and
returns an :class:`IntervalOutcome`. :func:`acroplan.plan` accepts ``method=`` as a registered name
(:data:`STRATEGIES`), a :class:`Strategy` instance or subclass (as scipy's ``solve_ivp(method=)``
takes a name or an ``OdeSolver`` class), or ``"auto"``: the system's own choice
(:meth:`ControlAffineSystem.auto_strategy`). Families register their strategies when imported
(the acrobot registers ``"flat"``).

Contract for implementers
-------------------------
1. Subclass :class:`Strategy`, set :attr:`name`, implement :meth:`solve`; return pieces whose
   ``t0`` is relative to the interval start (0) and which chain from ``x0`` to ``x1``.
2. Override :meth:`unsupported` to refuse systems you cannot plan, with the reason.
3. Keep it stateless: one instance may serve many threads.
4. ``register_strategy(MyStrategy())`` makes it available by name.

Building blocks: :func:`deform_attempt` (path deformation at one basis size, then the constrained
solve when limits are broken), :func:`run_stages` (try stages in order, charging the evaluations of
failed stages to the result), :func:`make_segment`.
"""

from __future__ import annotations

import abc
import dataclasses
from typing import Callable, ClassVar, Iterable

import numpy as np

from .basis import InputBasis
from .conditions import linear_conditions
from .continuation import solve_segment
from .errors import InvalidInputError
from .family import prepare
from .progress import note
from .limits import COMPLIANCE_TOL, Limits, solve_with_limits, violation
from .result import SegmentResult
from .status import Status
from .system import ControlAffineSystem

__all__ = ["Strategy", "Interval", "IntervalOutcome", "Deform", "STRATEGIES", "register_strategy",
           "resolve_strategy", "AUTO_DEFAULT", "deform_attempt", "run_stages", "make_segment"]


@dataclasses.dataclass(frozen=True)
class Interval:
    """One waypoint interval to plan.

    Attributes
    ----------
    system : ControlAffineSystem
    basis : InputBasis
        The basis family and the default size (``basis.n``).
    sizes : tuple of int or None
        Basis sizes to use: the user's ``n_coefficients`` when given, else ``None`` (the strategy's own).
    x0, x1 : numpy.ndarray, shape (n,)
    T : float
        Duration.
    ends : dict
        Input conditions as values (:meth:`acroplan.core.conditions.Conditions.ends`).
    limits : Limits or None
    tol : float
        Required endpoint error.
    max_evaluations : int
        Endpoint-evaluation budget per basis size.
    joint : bool
        Whether the interval's optimum is a start of the whole plan's joint optimum
        (:meth:`acroplan.core.optimal.EnergyOptimal.joint`, which :func:`acroplan.plan` runs after
        the intervals when there are several and the conditions are free): an optimal strategy may
        then climb its ladder in larger steps (:meth:`~acroplan.core.optimal.EnergyOptimal.ladder`).
    provisional : bool
        Whether the interval's optimum is only the joint optimum's start: an optimal strategy then
        reports its ladder's last size as the ladder left it, neither refined to its KKT target nor
        checked between its limits' grid points (:data:`acroplan.core.optimal.PROVISIONAL_STARTS`);
        the joint optimum refines and checks the whole plan, and :func:`acroplan.plan` plans the
        intervals again in full when it is not kept.
    """

    system: ControlAffineSystem
    basis: InputBasis
    sizes: tuple[int, ...] | None
    x0: np.ndarray
    x1: np.ndarray
    T: float
    ends: dict
    limits: Limits | None
    tol: float
    max_evaluations: int
    joint: bool = False
    provisional: bool = False

    def sized(self, n: int) -> InputBasis:
        """The basis of the interval's family with ``n`` coefficients."""
        return type(self.basis)(n)

    def conditions(self, basis: InputBasis):
        """``(B, d)`` of the input conditions in ``basis`` (:func:`linear_conditions`)."""
        return linear_conditions(basis, self.system.n_inputs, self.T, self.ends)


@dataclasses.dataclass(frozen=True)
class IntervalOutcome:
    """What a strategy returns.

    Attributes
    ----------
    success : bool
    pieces : tuple of SegmentResult
        On success the segments from ``x0`` to ``x1`` (``t0`` relative to the interval start); on
        failure the last failed attempt, for its diagnostics (may be empty).
    reason : str
        Why it failed (empty on success).
    evaluations : int
        Endpoint evaluations spent (charged to the result when a later stage succeeds).
    curvature : numpy.ndarray or None
        An optimal strategy's endpoint Hessians at its optimum (:attr:`OptimalSolve.curvature
        <acroplan.core.optimum.OptimalSolve>`), for the joint optimum that may follow; else ``None``.
    status : Status
        ``"success"``, else ``"not_converged"`` (a strategy that gives up proves nothing; what is
        proven impossible is refused before any strategy runs, by the family's ``check_segment``).
    message : str
        ``reason``, the vocabulary every result type shares.
    """

    success: bool
    pieces: tuple[SegmentResult, ...] = ()
    reason: str = ""
    evaluations: int = 0
    curvature: object = dataclasses.field(default=None, repr=False, compare=False)

    @property
    def status(self) -> Status:
        return Status.SUCCESS if self.success else Status.NOT_CONVERGED

    @property
    def message(self) -> str:
        return self.reason


class Strategy(abc.ABC):
    """How to plan one waypoint interval (module docstring)."""

    name: ClassVar[str] = "abstract"

    def unsupported(self, system: ControlAffineSystem) -> str | None:
        """Why this strategy cannot plan ``system`` (a sentence), or ``None`` when it can."""
        return None

    @abc.abstractmethod
    def solve(self, interval: Interval) -> IntervalOutcome:
        """Plan ``interval``."""

    def __repr__(self):
        return f"{type(self).__name__}()"


#: Registered strategies by name (``method=`` of :func:`acroplan.plan`).
STRATEGIES: dict[str, Strategy] = {}


def register_strategy(strategy: Strategy, *, replace: bool = False) -> Strategy:
    """Make ``strategy`` available to :func:`acroplan.plan` as ``method=strategy.name``."""
    if not isinstance(strategy, Strategy):
        raise InvalidInputError("strategy", f"must be a Strategy instance, got {strategy!r}",
                                "subclass acroplan.core.strategies.Strategy")
    if strategy.name in STRATEGIES and not replace and type(STRATEGIES[strategy.name]) is not type(strategy):
        raise InvalidInputError("strategy", f"the name {strategy.name!r} is taken by {STRATEGIES[strategy.name]!r}",
                                "choose another name or pass replace=True")
    STRATEGIES[strategy.name] = strategy
    return strategy


def resolve_strategy(method, system: ControlAffineSystem) -> Strategy:
    """The strategy ``method`` names for ``system`` (a name, ``"auto"``, an instance or a subclass)."""
    prepare(system)  # the system's family registers its strategies (core.family.Family.setup)
    if isinstance(method, Strategy):
        strategy = method
    elif isinstance(method, type) and issubclass(method, Strategy):
        strategy = method()
    elif method == "auto":
        strategy = system.auto_strategy() or AUTO_DEFAULT
    elif isinstance(method, str) and method in STRATEGIES:
        strategy = STRATEGIES[method]
    else:
        names = ["auto"] + sorted(STRATEGIES)
        raise InvalidInputError("method", f"must be one of {names}, or a Strategy, got {method!r}",
                                "use \"auto\", \"deform\" (the text's)" + (", \"flat\"" if "flat" in STRATEGIES else ""))
    why = strategy.unsupported(system)
    if why:
        raise InvalidInputError("method", why, "use method=\"auto\" or \"deform\"")
    return strategy


# ---------------------------------------------------------------------------------- building blocks
def limit_check(system, basis, x0, T, c, limits):
    """:func:`acroplan.core.limits.violation` when limits are given, else ``None``."""
    return violation(system, basis, x0, T, c, limits) if limits is not None and limits.active else None


def compliant(checked) -> bool:
    return checked is None or (checked["u"] <= COMPLIANCE_TOL and checked["state"] <= COMPLIANCE_TOL)


def make_segment(system, basis: InputBasis, x0, x1, T: float, c, *, t0: float, final_error: float,
                 limits=None, checked=None, **diagnostics) -> SegmentResult:
    """A :class:`SegmentResult` for coefficients ``c`` (shape ``(m, basis.n)``) on ``[t0, t0 + T]``.

    ``checked``: :func:`limit_check` of ``c`` when already computed. ``diagnostics``: any other
    :class:`SegmentResult` field (``iterations``, ``evaluations``, ``message``, ``method``, ...).
    """
    if checked is None:
        checked = limit_check(system, basis, x0, T, c, limits)
    ext = None if checked is None else {"max_abs_u": checked["max_abs_u"], "state_ranges": checked["state_ranges"]}
    fields = dict(verified_error=None, iterations=0, evaluations=0, restarts=0, sigma_min=float("nan"),
                  success=True, message="", history=(), method="deform")
    fields.update(diagnostics)
    return SegmentResult(index=0, t0=float(t0), t1=float(t0 + T), coefficients=basis.to_power(c, T),
                         basis_coefficients=c, start=x0, target=x1, final_error=final_error, extremes=ext,
                         basis=basis, **fields)


def deform_attempt(interval: Interval, n: int, *, initial=None, budget: int | None = None,
                   initial_endpoint=None) -> IntervalOutcome:
    """Path deformation with ``n`` coefficients per input (from ``initial`` when given; with
    ``initial_endpoint``, the endpoint map and its Jacobian there: :func:`solve_segment`), then,
    when the result breaks the limits, the constrained solve from it."""
    system, x0, x1, T, limits = interval.system, interval.x0, interval.x1, interval.T, interval.limits
    bn = interval.sized(n)
    B, d = interval.conditions(bn)
    budget = interval.max_evaluations if budget is None else min(interval.max_evaluations, budget)
    out = solve_segment(system, bn, x0, x1, T, B=B, d=d, tol=interval.tol, max_evaluations=budget, initial=initial,
                        initial_endpoint=initial_endpoint)
    info = dict(iterations=out.iterations, evaluations=out.evaluations, restarts=out.restarts,
                sigma_min=out.sigma_min, history=out.history)
    checked = limit_check(system, bn, x0, T, out.coefficients, limits) if out.success else None
    if out.success and compliant(checked):
        return IntervalOutcome(True, (make_segment(system, bn, x0, x1, T, out.coefficients, t0=0.0,
                                                   final_error=out.final_error, message=out.message, limits=limits,
                                                   checked=checked, **info),))
    if out.success:
        con = solve_with_limits(system, bn, x0, x1, T, limits, out.coefficients, B=B, d=d, tol=interval.tol)
        info["evaluations"] += con.evaluations
        piece = make_segment(system, bn, x0, x1, T, con.coefficients, t0=0.0, final_error=con.final_error,
                             success=con.success, message=con.message, method=con.method, limits=limits, **info)
        if con.success:
            return IntervalOutcome(True, (piece,))
        return IntervalOutcome(False, (piece,), f"{n} coefficients: path deformation converged but broke the "
                               f"limits, and {con.message}", info["evaluations"])
    piece = make_segment(system, bn, x0, x1, T, out.coefficients, t0=0.0, final_error=out.final_error,
                         success=False, message=out.message, limits=limits, **info)
    return IntervalOutcome(False, (piece,), f"{n} coefficients: {out.message}", info["evaluations"])


def run_stages(stages: Iterable[Callable[[], IntervalOutcome | None]]) -> IntervalOutcome:
    """Try ``stages`` in order; the first success wins, and the evaluations the failed stages spent
    are charged to its first piece. A stage may return ``None`` (skipped)."""
    spent, reasons, last = 0, [], None
    for k, stage in enumerate(stages):
        note("guesses", k + 1, detail="tried")  # (core.progress: nothing unless shown)
        out = stage()
        if out is None:
            continue
        if out.success:
            pieces = out.pieces
            if spent and pieces:
                pieces = (dataclasses.replace(pieces[0], evaluations=pieces[0].evaluations + spent),) + pieces[1:]
            return IntervalOutcome(True, pieces, "", out.evaluations + spent)
        spent += out.evaluations
        reasons.append(out.reason)
        if out.pieces:
            last = out.pieces[-1]
    return IntervalOutcome(False, (last,) if last is not None else (), "; ".join(reasons), spent)


class Deform(Strategy):
    """The text's path deformation (:func:`acroplan.core.continuation.solve_segment`), basis size by
    basis size, with the constrained solve when limits are broken.

    Parameters
    ----------
    sizes : tuple of int
        Basis sizes tried in order when the user gives no ``n_coefficients`` (default: 6).
    budget : int, optional
        Evaluation budget per size (at most the user's ``max_evaluations``).
    """

    name = "deform"

    def __init__(self, sizes: tuple[int, ...] = (6,), budget: int | None = None):
        self.sizes = tuple(int(n) for n in sizes)
        self.budget = budget

    def solve(self, interval: Interval) -> IntervalOutcome:
        sizes = interval.sizes or self.sizes
        return run_stages(lambda n=n: deform_attempt(interval, n, budget=self.budget) for n in sizes)

    def __repr__(self):
        return f"Deform(sizes={self.sizes}, budget={self.budget})"


register_strategy(Deform())

#: ``method="auto"`` for systems that do not choose their own (:meth:`ControlAffineSystem.auto_strategy`).
AUTO_DEFAULT = Deform(sizes=(6, 10, 14), budget=100)
