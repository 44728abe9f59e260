"""``method="auto"`` for spatial bodies: :class:`SpatialAuto`.

Path deformation needs a non-singular start; at :math:`L = 0` the minimum-norm input :math:`u = 0`
is singular (the attitude moves at second order in :math:`u`), and with :math:`L \\ne 0` a start far
from the target makes deformation wander into large inputs. The start is a real shape motion that
already turns the body toward the target (:func:`~acroplan.families.spatial.guess.loop_guesses`: the
base joint motion plus a shape loop sized by the curvature of the momentum connection), and path
deformation (in the tangent space of SO(3) x R^m) polishes it.

Stages, the first success wins (:func:`~acroplan.core.strategies.run_stages`):

1. for each basis size of :data:`AUTO_SIZES` (6, 10, 14; loops need :math:`\\alpha + \\beta + 1`
   coefficients: 10 under spline conditions), deformation from each loop guess, then from the base
   motion;
2. generic path deformation from the minimum-norm input (perturbed starts) at each size.

Every stage's deformation has a budget of :data:`AUTO_BUDGET` endpoint evaluations; a result that
breaks the limits goes to the constrained solve (:func:`~acroplan.core.strategies.deform_attempt`).
"""

from __future__ import annotations

from ...core.strategies import Interval, IntervalOutcome, Strategy, deform_attempt, run_stages
from .guess import Connection, loop_guesses

__all__ = ["SpatialAuto", "AUTO_SIZES", "AUTO_BUDGET"]

#: basis sizes tried when ``n_coefficients`` is not given
AUTO_SIZES = (6, 10, 14)
#: evaluation budget of each deformation stage
AUTO_BUDGET = 60


class SpatialAuto(Strategy):
    """The spatial bodies' ``method="auto"`` (module docstring)."""

    name = "spatial-auto"

    def unsupported(self, system):
        if not hasattr(system, "links") or not hasattr(system, "L") or system.n_states != system.ndx + 1:
            return f"\"spatial-auto\" plans spatial bodies, not {type(system).__name__}"
        return None

    def solve(self, interval: Interval) -> IntervalOutcome:
        system = interval.system
        sizes = interval.sizes or AUTO_SIZES
        conn = Connection(system)
        cache = {}

        def attempt(n, k):
            key = n
            if key not in cache:
                cache[key] = loop_guesses(system, interval.sized(n), interval.x0, interval.x1, interval.T,
                                          interval.ends, interval.limits, conn=conn)
            g = cache[key]
            if len(g) <= k:
                return None
            out = deform_attempt(interval, n, initial=g[k].coefficients, budget=AUTO_BUDGET)
            if out.success:
                return out
            return IntervalOutcome(False, out.pieces, f"from the {g[k].describe()}: {out.reason}", out.evaluations)

        stages = [lambda n=n, k=k: attempt(n, k) for n in sizes for k in range(4)]
        stages += [lambda n=n: deform_attempt(interval, n, budget=AUTO_BUDGET) for n in sizes]
        return run_stages(stages)
