"""One vocabulary for how every computation ended: :class:`Status` (success, infeasible with its
proof, not converged with its diagnostics) and :class:`Outcome`, the mixin that gives a result type
``success`` from its ``status`` (as scipy's ``OdeResult`` has ``success``, ``status``, ``message``).
Every result type of acroplan has ``success``, ``status`` and ``message``: plans
(:class:`~acroplan.core.result.PlanResult`), a strategy's interval
(:class:`~acroplan.core.strategies.IntervalOutcome`), reachable sets
(:class:`~acroplan.families.acrobot.reach.Reach`), the least momentum
(:class:`~acroplan.families.acrobot.momentum.MomentumBound`), Chapter 4's solutions
(:class:`~acroplan.families.acrobot.nilpotent.NilpotentResult`) and the points of a sweep.
"""

from __future__ import annotations

import enum

__all__ = ["Status", "Outcome", "STATUSES"]


class Status(enum.StrEnum):
    """How a plan ended. A member is its own string (``Status.SUCCESS == "success"``) and carries
    what it means (:attr:`meaning`) and what to do about it (:attr:`fix`), as diffrax's ``RESULTS``.
    """

    SUCCESS = "success"
    INFEASIBLE = "infeasible"
    NOT_CONVERGED = "not_converged"

    @property
    def meaning(self) -> str:
        return _MEANING[self]

    @property
    def fix(self) -> str:
        return _FIX[self]

    @property
    def success(self) -> bool:
        return self is Status.SUCCESS


_MEANING = {
    Status.SUCCESS: "every waypoint is reached, the limits hold, and (unless verify=False) an independent "
                    "re-simulation agrees",
    Status.INFEASIBLE: "proven impossible: the proof (the reachable set, or the limit that is broken) is in the "
                       "message and in `infeasible`",
    Status.NOT_CONVERGED: "the planner did not find a motion; its diagnostics are kept in `segments`",
}
_FIX = {
    Status.SUCCESS: "",
    Status.INFEASIBLE: "move the target inside the reachable set given, or relax the limits",
    Status.NOT_CONVERGED: "try more coefficients (n_coefficients), another method, a larger max_evaluations, "
                          "or waypoints closer together",
}

#: The possible values of :attr:`PlanResult.status`.
STATUSES = tuple(s.value for s in Status)


class Outcome:
    """Mixin of a result type with a ``status`` (a :class:`Status`) and a ``message``: its
    ``success`` is ``status is Status.SUCCESS``."""

    __slots__ = ()

    @property
    def success(self) -> bool:
        """Whether it succeeded (``status == "success"``)."""
        return Status(self.status) is Status.SUCCESS
