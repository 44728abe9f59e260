"""``method="auto"`` for planar bodies: :class:`PlanarAuto`.

Path deformation needs a non-singular start, and at zero momentum the minimum-norm input
:math:`u = 0` is a singular control (the endpoint map's Jacobian there has rank :math:`m`: the
joints move, the root's turn is of second order in :math:`u`, the area a shape loop encloses). So the
start is a real shape motion that already meets the target
(:func:`~acroplan.families.planar.guess.shape_guesses`: the base motion plus a loop or a bump whose
amplitude solves the scalar turn equation, placed where the curvature of the connection is
largest), and deformation only polishes it, in one to three endpoint evaluations.

Stages, the first success wins (:func:`~acroplan.core.strategies.run_stages`):

1. at the smallest basis size of :data:`AUTO_SIZES` (6, 10, 14) whose guesses meet the target
   (loops need :math:`\\alpha + \\beta + 1` coefficients: 10 under spline conditions, 6 without),
   deformation from the best guess (compliant with the limits, smallest motion), then from the
   second (another pair, placement or family);
2. the other sizes, from their best guess;
3. every loop placement at the largest size (all 8 directions, both orientations, every pair);
4. generic path deformation from the minimum-norm input (perturbed starts) at each size.

Every stage's deformation has a budget of :data:`AUTO_BUDGET` endpoint evaluations; when a result
breaks the limits the constrained solve takes over (:func:`~acroplan.core.strategies.deform_attempt`).
A failure reports every stage's reason, the guesses tried and the best endpoint error.
"""

from __future__ import annotations

import dataclasses

from ...core.strategies import Interval, IntervalOutcome, Strategy, deform_attempt, run_stages
from .connection import Connection
from .guess import LAMBDA_MAX, shape_guesses

__all__ = ["PlanarAuto", "AUTO_SIZES", "AUTO_BUDGET"]

#: basis sizes tried when ``n_coefficients`` is not given
AUTO_SIZES = (6, 10, 14)
#: evaluation budget of each deformation stage
AUTO_BUDGET = 100


class PlanarAuto(Strategy):
    """The planar bodies' ``method="auto"`` (module docstring)."""

    name = "planar-auto"

    def unsupported(self, system):
        if not hasattr(system, "links") or not hasattr(system, "P0"):
            return f"\"planar-auto\" plans planar bodies, not {type(system).__name__}"
        return None

    def solve(self, interval: Interval) -> IntervalOutcome:
        system = interval.system
        sizes = interval.sizes or AUTO_SIZES
        conn = Connection(system)
        cache = {}

        def guesses(n, everything=False):
            key = (n, everything)
            if key not in cache:
                cache[key] = shape_guesses(system, interval.sized(n), interval.x0, interval.x1, interval.T,
                                           interval.ends, interval.limits, conn=conn, everything=everything,
                                           keep=8 if everything else 2)
            return cache[key]

        def attempt(n, k, everything=False):
            g = guesses(n, everything)
            if len(g) <= k:
                return None
            out = deform_attempt(interval, n, initial=g[k].coefficients, budget=AUTO_BUDGET)
            if out.success:
                return out
            return IntervalOutcome(False, out.pieces, f"from the {g[k].describe()}: {out.reason}", out.evaluations)

        first = next((n for n in sizes if guesses(n)), None)
        order = ([first] if first is not None else []) + [n for n in sizes if n != first]
        stages = []
        if first is not None:
            stages += [lambda: attempt(first, 0), lambda: attempt(first, 1)]
        stages += [lambda n=n: attempt(n, 0) for n in order[1:]]
        last = sizes[-1]
        stages += [lambda: _more(attempt, guesses, last)]
        stages += [lambda n=n: deform_attempt(interval, n, budget=AUTO_BUDGET) for n in sizes]
        out = run_stages(stages)
        if out.success or first is not None:
            return out
        return IntervalOutcome(False, out.pieces, "no loop or bump of the joints up to "
                               f"{LAMBDA_MAX:g} rad meets the target; {out.reason}", out.evaluations)


def _more(attempt, guesses, n):
    """Every placement at size ``n``, in their order, until one succeeds (a fallback)."""
    spent, reasons, last = 0, [], None
    tried = {g.coefficients.tobytes() for k in (0, 1) for g in guesses(n)[k:k + 1]}
    for k, g in enumerate(guesses(n, True)):
        if g.coefficients.tobytes() in tried or k >= 8:
            continue
        out = attempt(n, k, True)
        if out is None:
            break
        if out.success:
            pieces = (dataclasses.replace(out.pieces[0], evaluations=out.pieces[0].evaluations + spent),) + \
                out.pieces[1:]
            return IntervalOutcome(True, pieces, "", out.evaluations + spent)
        spent += out.evaluations
        reasons.append(out.reason)
        last = out.pieces or last
    if not reasons:
        return None
    return IntervalOutcome(False, last or (), "; ".join(reasons[-2:]), spent)
