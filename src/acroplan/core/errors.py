"""Exceptions raised at acroplan's boundaries.

Every error a user can provoke with bad input is an :class:`InvalidInputError`, a subclass of
:class:`ValueError` that names the offending field and says how to fix it. Infeasible or
non-converged plans are *not* exceptions: they are a status in the result (see
:class:`acroplan.PlanResult`).
"""

from __future__ import annotations

__all__ = ["InvalidInputError", "finite_number", "EXIT_SUCCESS", "EXIT_INVALID", "EXIT_INFEASIBLE",
           "EXIT_NOT_CONVERGED"]

#: Exit codes of the command line, one per outcome.
EXIT_SUCCESS = 0
EXIT_INVALID = 2
EXIT_INFEASIBLE = 3
EXIT_NOT_CONVERGED = 4


class InvalidInputError(ValueError):
    """Invalid user input.

    Parameters
    ----------
    field : str
        The offending field, as the user wrote it (``"robot.M1"``, ``"plan.times"``, ``"times"``).
    problem : str
        What is wrong with it.
    fix : str, optional
        What to do instead.
    """

    def __init__(self, field: str, problem: str, fix: str = ""):
        self.field = field
        self.problem = problem
        self.fix = fix
        msg = f"{field}: {problem}"
        if fix:
            msg += f"; {fix}"
        super().__init__(msg)


def finite_number(field: str, value) -> float:
    """``value`` as a finite float, or :class:`InvalidInputError` naming ``field`` (booleans refused)."""
    import math

    if isinstance(value, bool):
        raise InvalidInputError(field, f"must be a real number, got {value!r}", "give a finite number")
    try:
        v = float(value)
    except (TypeError, ValueError, OverflowError):
        r = repr(value)
        raise InvalidInputError(field, f"must be a real number, got {r if len(r) <= 80 else r[:77] + '...'}",
                                "give a finite number") from None
    if not math.isfinite(v):
        raise InvalidInputError(field, f"must be finite, got {v}", "give a finite number")
    return v
