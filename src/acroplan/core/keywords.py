"""The keywords of the front doors, in one table: :func:`acroplan.plan` and
:func:`acroplan.simulate` validate against it, the body families refuse joint names that would
clash with it (a joint's name is a keyword of both), and the sweeps and problem files know which
fields are options. ``tests/test_layering.py`` checks it against the functions' signatures, so it
cannot drift."""

from __future__ import annotations

__all__ = ["PLAN_KEYWORDS", "SIMULATE_KEYWORDS", "RESERVED_NAMES"]

#: :func:`acroplan.plan`'s keywords (besides ``system`` and one keyword per state)
PLAN_KEYWORDS = ("times", "conditions", "method", "basis", "n_coefficients", "max_coefficients", "limits", "u_max",
                 "state_bounds", "input_bounds", "verify", "tol", "max_evaluations", "time_limit", "start_rate",
                 "end_rate", "degrees", "objective", "tau_max", "capacity", "progress")
#: :func:`acroplan.simulate`'s keywords (besides ``system`` and one keyword per state)
SIMULATE_KEYWORDS = ("times", "inputs", "basis", "n_coefficients", "verify")
#: names no state of a system may take: every keyword above, ``system``, and ``theta`` (the root
#: angle of every planar body)
RESERVED_NAMES = frozenset(PLAN_KEYWORDS + SIMULATE_KEYWORDS + ("system", "theta"))
