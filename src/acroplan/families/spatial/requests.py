"""What the spatial planner can take, checked at the boundary (:attr:`Family.check_request
<acroplan.core.family.Family.check_request>`, called by :meth:`acroplan.PlanRequest.build` once every
argument is valid), so that a request outside it is refused with a message instead of failing
inside the planner.

The spatial planner's first guesses (:func:`~acroplan.families.spatial.guess.loop_guesses`, used by
``method="auto"`` and by the optimal plans that start from it) integrate the attitude with a fixed
number of Runge-Kutta steps (:data:`~acroplan.families.spatial.guess.FAST_STEPS`). Two requests
break them:

* **a fast free rotation.** With a large angular momentum the body turns by itself, at
  :math:`\\Omega = \\mathbb{I}(s)^{-1} R^\\top L`; over a segment of duration :math:`T` it turns
  :math:`|\\Omega| T` radians. The fixed steps follow at most about 150 rad per segment (measured on
  the falling cat and the astronaut: 136 rad and 146 rad planned, 163 rad and 175 rad diverged to NaN,
  then a ``LinAlgError``; with ten times the steps the cat planned 510 rad). This is the cause of the
  ``LinAlgError`` at ``angular_momentum`` of 1e3 to 1e6, not the conditioning of the locked inertia
  (which is that of the link table, checked when the body is built). Refused here above
  :data:`MAX_FREE_TURN` (two radians per fast step: a margin under the measured limit), naming the
  segment, its turn and the longest segment that would do.
* **one coefficient too few for a loop.** A shape loop needs its offset and turn vectors, so
  :math:`\\alpha + \\beta + 2` coefficients per input with :math:`\\alpha - 1`, :math:`\\beta - 1` the
  input conditions at the two ends; with exactly :math:`\\alpha + \\beta + 1` the guesses fail with a
  ``ValueError`` (``n_coefficients = 3`` with free conditions, ``objective = "energy"`` or
  ``tau_max``). Refused here, naming ``n_coefficients`` and the sizes that work.

Both apply only to the strategies that use the loop guesses; ``method="deform"`` is not refused.
"""

from __future__ import annotations

import math

import numpy as np

from ...core.errors import InvalidInputError
from .guess import FAST_STEPS
from .strategy import SpatialAuto

__all__ = ["check_request", "uses_loop_guesses", "MAX_FREE_TURN"]

#: The largest free turn :math:`|\Omega| T` (rad) of one segment the loop guesses are asked to follow.
MAX_FREE_TURN = 2.0 * FAST_STEPS


def uses_loop_guesses(strategy) -> bool:
    """Whether ``strategy`` plans with the spatial loop guesses: :class:`SpatialAuto` itself, or an
    optimal strategy whose feasible start is ``method="auto"`` (its default)."""
    if isinstance(strategy, SpatialAuto):
        return True
    from ...core.optimal import EnergyOptimal

    if isinstance(strategy, EnergyOptimal):
        feasible = getattr(strategy, "feasible", None)
        if feasible is not None:
            return isinstance(feasible, SpatialAuto)
        starts = getattr(strategy, "starts", None)
        return starts is None or "auto" in starts
    return False


def _conditions_at_ends(req, k: int, K: int) -> tuple[int, int]:
    """How many input conditions interval ``k`` has at its start and at its end
    (:meth:`acroplan.core.conditions.Conditions.ends`)."""
    if req.conditions == "spline":
        return 2, 2
    left = 1 if (k > 0 or req.start_rate is not None) else 0
    right = 1 if (k == K - 1 and req.end_rate is not None) else 0
    limits = req.limits if req.limits.active else None
    if limits is not None and k + 1 < K:
        x = req.waypoints[k + 1]
        names = req.system.state_names
        if any(limits.at_bound(s, float(x[names.index(s)])) for s in limits.bounded_states):
            right = 1
    return left, right


def check_request(req) -> None:
    """Refuse a :class:`~acroplan.planning.PlanRequest` of a spatial body that the loop guesses cannot
    take (module docstring).

    Raises
    ------
    InvalidInputError
        Naming ``n_coefficients`` (one too few for a loop) or ``times`` (a segment in which the body
        turns by itself more than :data:`MAX_FREE_TURN`).
    """
    if not uses_loop_guesses(req.strategy):
        return
    body = req.system
    K = len(req.times) - 1
    if req.sizes and body.n_inputs >= 2:
        n = req.sizes[0]
        for k in range(K):
            left, right = _conditions_at_ends(req, k, K)
            need = 3 + left + right  # alpha + beta + 1 with alpha = 1 + left, beta = 1 + right
            if n == need:
                raise InvalidInputError("n_coefficients", f"{n} coefficients leave the spatial planner's shape loops "
                                        f"one coefficient short on segment {k} (under its input conditions a loop "
                                        f"needs {need + 1})", f"give n_coefficients = {need + 1} or more (or leave it "
                                        "out: 6, 10 and 14 are tried), or method = \"deform\"")
    if not any(abs(v) > 0 for v in body.L):
        return
    zero = np.zeros(body.n_inputs)
    rates = [float(np.linalg.norm(body.angular_velocity(x, zero))) for x in req.waypoints]
    for k in range(K):
        T = float(req.times[k + 1] - req.times[k])
        rate = max(rates[k], rates[k + 1])
        turn = rate * T
        if not math.isfinite(turn) or turn > MAX_FREE_TURN:
            longest = MAX_FREE_TURN / rate if rate > 0 and math.isfinite(rate) else 0.0
            raise InvalidInputError(
                "times", f"segment {k} lasts {T:.6g} s, and the angular momentum L = "
                f"({', '.join(f'{v:.6g}' for v in body.L)}) turns the body by itself at {rate:.4g} rad/s, "
                f"{turn:.4g} rad in that segment: the spatial planner's guesses follow at most {MAX_FREE_TURN:g} "
                "rad per segment", f"put waypoints closer in time (segments of at most {longest:.3g} s here), "
                "lower the angular momentum, or give method = \"deform\"")
