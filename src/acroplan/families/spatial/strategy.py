"""``method="auto"`` for spatial bodies: :class:`SpatialAuto`.

Path deformation needs a non-singular start; at :math:`L = 0` the minimum-norm input :math:`u = 0`
is singular (the attitude moves at second order in :math:`u`), and with :math:`L \\ne 0` a start far
from the target makes deformation wander into large inputs. The start is a real shape motion that
already turns the body toward the target (:func:`~acroplan.families.spatial.guess.loop_guesses`: the
base joint motion plus a shape loop sized by the curvature of the momentum connection), and path
deformation (in the tangent space of SO(3) x R^m) polishes it.

Stages, the first success wins (:func:`~acroplan.core.strategies.run_stages`):

1. at the smallest basis size of :data:`AUTO_SIZES` (6, 10, 14) the loops fit in (they need
   :math:`\\alpha + \\beta + 1` coefficients: 10 under spline conditions), each of the three best
   loop guesses is refined by Gauss-Newton on its own vectors
   (:func:`~acroplan.families.spatial.guess.refine`, at most :data:`REFINE_BUDGET` evaluations),
   then polished by deformation (from the refined loop when it meets the target to 1e-8 rad, else
   from the guess); then deformation from the base motion;
2. generic path deformation from the minimum-norm input (perturbed starts) at that size;
3. each other size: the best loop guess, then generic deformation.

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
AUTO_BUDGET = 100
#: evaluation budget of the Gauss-Newton refinement of a loop (:func:`~acroplan.families.spatial.guess.refine`)
REFINE_BUDGET = 40


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

        def guess_list(n):
            if n not in cache:
                cache[n] = loop_guesses(system, interval.sized(n), interval.x0, interval.x1, interval.T,
                                        interval.ends, interval.limits, conn=conn)
            return cache[n]

        def attempt(n, k):
            g = guess_list(n)
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

        # the loops are the same functions at every size they fit in: their guesses at the first
        # such size, then generic deformation there, then the other sizes
        first = next((n for n in sizes if len(guess_list(n)) > 1), sizes[0])
        stages = [lambda k=k: attempt(first, k) for k in range(4)]
        stages += [lambda: deform_attempt(interval, first, budget=AUTO_BUDGET)]
        for n in sizes:
            if n != first:
                stages += [lambda n=n: attempt(n, 0), lambda n=n: deform_attempt(interval, n, budget=AUTO_BUDGET)]
        return run_stages(stages)
