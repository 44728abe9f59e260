"""``method="auto"`` for spatial bodies: :class:`SpatialAuto`.

Path deformation needs a non-singular start; at :math:`L = 0` the minimum-norm input :math:`u = 0`
is singular (the attitude moves at second order in :math:`u`), and with :math:`L \\ne 0` a start far
from the target makes deformation wander into large inputs. The start is a real shape motion that
already turns the body toward the target (:func:`~acroplan.families.spatial.guess.loop_guesses`: the
base joint motion plus a shape loop sized by the curvature of the momentum connection), and path
deformation (in the tangent space of SO(3) x R^m) polishes it.

Stages, the first success wins (:func:`~acroplan.core.strategies.run_stages`):

1. for each basis size of :data:`AUTO_SIZES` (6, 10, 14; loops need :math:`\\alpha + \\beta + 1`
   coefficients: 10 under spline conditions), each loop guess is first refined by Gauss-Newton on
   its own offset and turn vectors (:func:`~acroplan.families.spatial.guess.refine`, at most
   :data:`REFINE_BUDGET` evaluations), then polished by deformation (from the refined loop when it
   meets the target to 1e-8 rad, else from the guess); then deformation from the base motion;
2. generic path deformation from the minimum-norm input (perturbed starts) at each size.

Every stage's deformation has a budget of :data:`AUTO_BUDGET` endpoint evaluations; a result that
breaks the limits goes to the constrained solve (:func:`~acroplan.core.strategies.deform_attempt`).
"""

from __future__ import annotations

import dataclasses

from ...core.strategies import Interval, IntervalOutcome, Strategy, deform_attempt, run_stages
from .guess import Connection, loop_guesses, refine

__all__ = ["SpatialAuto", "AUTO_SIZES", "AUTO_BUDGET"]

#: basis sizes tried when ``n_coefficients`` is not given
AUTO_SIZES = (6, 10, 14)
#: evaluation budget of each deformation stage
AUTO_BUDGET = 60
#: evaluation budget of the Gauss-Newton refinement of a loop (:func:`~acroplan.families.spatial.guess.refine`)
REFINE_BUDGET = 30


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
            c, err, spent = refine(system, interval.sized(n), interval.x0, interval.x1, interval.T, g[k],
                                   budget=REFINE_BUDGET)
            start = c if err <= 1e-8 else g[k].coefficients
            out = deform_attempt(interval, n, initial=start, budget=AUTO_BUDGET)
            if out.success:
                if spent:
                    p0 = out.pieces[0]
                    out = IntervalOutcome(True, (dataclasses.replace(p0, evaluations=p0.evaluations + spent),)
                                          + out.pieces[1:], "", out.evaluations)
                return out
            return IntervalOutcome(False, out.pieces, f"from the {g[k].describe()}: {out.reason}",
                                   out.evaluations + spent)

        stages = [lambda n=n, k=k: attempt(n, k) for n in sizes for k in range(4)]
        stages += [lambda n=n: deform_attempt(interval, n, budget=AUTO_BUDGET) for n in sizes]
        return run_stages(stages)
