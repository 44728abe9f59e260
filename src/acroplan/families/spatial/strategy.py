"""``method="auto"`` for spatial bodies: :class:`SpatialAuto`.

Path deformation needs a non-singular start; at :math:`L = 0` the minimum-norm input :math:`u = 0`
is singular (the attitude moves at second order in :math:`u`), and with :math:`L \\ne 0` a start far
from the target makes deformation wander into large inputs. The start is a real shape motion that
already turns the body toward the target (:func:`~acroplan.families.spatial.guess.loop_guesses`: the
base joint motion plus a shape loop sized by the curvature of the momentum connection), refined by
Gauss-Newton on the loop's own vectors within the joint ranges and rate limits
(:func:`~acroplan.families.spatial.guess.refine`), and path deformation (in the tangent space of
SO(3) x R^m) polishes it.

Stages, the first success wins (:func:`~acroplan.core.strategies.run_stages`):

1. **At rest at the waypoints.** When the interval leaves the end rate free (``conditions="free"``
   between waypoints), the stages below are first tried with the joints at rest at its end too
   (a special case of the free end, so a valid answer): a free end rate carried into the next
   interval (several rad/s) starts it against its joint ranges.
2. **Repeated loops** (:math:`L = 0`, the shape back where it started, at rest at both ends): a
   turn by the rotation vector :math:`r` (body frame) that one loop within the limits cannot make
   (the best compliant guess misses by more than :data:`LOOP_SLACK` rad) is made by :math:`k` equal
   loops, each turning by :math:`r/k` in :math:`T/k`, the smallest :math:`k \\le` :data:`MAX_LOOPS`
   whose loop can. At :math:`L = 0` the attitude equation is left-invariant (:math:`q \\mapsto
   g \\otimes q` maps solutions to solutions), so one loop planned from :math:`q_0` to
   :math:`q_0 \\otimes \\exp(r/k)` serves every repetition: the interval's pieces are :math:`k` copies
   of it, from :math:`q_0 \\otimes \\exp(i r/k)` (each piece's endpoint evaluated anew).
3. at the smallest basis size of :data:`AUTO_SIZES` (6, 10, 14) the loops fit in (they need
   :math:`\\alpha + \\beta + 1` coefficients: 10 under spline conditions), each of the three best
   loop guesses is refined (at most :data:`REFINE_BUDGET` evaluations) and, when it meets the
   target to 1e-8 rad, polished by deformation; then the three best loops of each larger size the
   same way (more freedom to keep the joint ranges), a loop no further once a larger size missed by
   at least :data:`ENLARGE_GAIN` of its miss at the first size (the joint ranges, not the basis,
   hold it there);
4. generic path deformation from the minimum-norm input (perturbed starts) at that size, then the
   loops that missed polished from their guesses (that polish often ends in the constrained
   solve, seconds where a refined loop takes milliseconds). On the second interval of the bundled
   forward twisting dive, whose loops all miss by 0.24 rad within the joint ranges, the four
   polishes stalled, 1.0 s, before the generic deformation succeeded in 0.2 s; after the best
   loop's polish alone was moved behind the generic deformation too, that dive's optimal plan
   takes 100 endpoint evaluations fewer (525 -> 425), the same plan to the last bit, and 180
   random chains and 180 trees the same plans in the same evaluations
   (``benchmarks/RESULTS.md``, 2026-12-07, twelfth session);
5. each other size: the best loop guess, then generic deformation.

Every stage's deformation has a budget of :data:`AUTO_BUDGET` endpoint evaluations; a result that
breaks the limits goes to the constrained solve (:func:`~acroplan.core.strategies.deform_attempt`).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...core import backend
from ...core.strategies import Interval, IntervalOutcome, Strategy, deform_attempt, make_segment, run_stages
from . import rotations as rot
from .guess import Connection, loop_guesses, refine

__all__ = ["SpatialAuto", "AUTO_SIZES", "AUTO_BUDGET", "REFINE_BUDGET", "MAX_LOOPS", "LOOP_SLACK", "ENLARGE_GAIN"]

#: basis sizes tried when ``n_coefficients`` is not given
AUTO_SIZES = (6, 10, 14)
#: evaluation budget of each deformation stage
AUTO_BUDGET = 100
#: evaluation budget of the Gauss-Newton refinement of a loop (:func:`~acroplan.families.spatial.guess.refine`)
REFINE_BUDGET = 40
#: the most repetitions of a loop in one interval (module docstring)
MAX_LOOPS = 8
#: a loop "can" make a turn when its guess misses by at most this (rad)
LOOP_SLACK = 0.6
#: a loop's refinement is tried in the next larger basis only when the last larger one brought its
#: miss below this fraction of its miss at the first size (module docstring, stage 3): on the
#: bundled forward twisting dive's second interval the three loops missed by 0.0433, 0.0526 and
#: 0.137 rad at 6 coefficients, by 0.0433, 0.0525 and 0.127 at 10, and again at 14 (55
#: evaluations, 0.41 s, the last 40 of them one refinement's whole budget)
ENLARGE_GAIN = 0.9


class SpatialAuto(Strategy):
    """The spatial bodies' ``method="auto"`` (module docstring)."""

    name = "spatial-auto"

    def unsupported(self, system):
        if not hasattr(system, "links") or not hasattr(system, "L") or system.n_states != system.ndx + 1:
            return f"\"spatial-auto\" plans spatial bodies, not {type(system).__name__}"
        return None

    def solve(self, interval: Interval) -> IntervalOutcome:
        stages = []
        if "uT" not in interval.ends:
            rest = dataclasses.replace(interval, ends=dict(interval.ends, uT=np.zeros(interval.system.n_inputs)))
            stages.append(lambda: _stages(rest, generic=False))
        stages.append(lambda: _stages(interval, generic=True))
        return run_stages(stages)


def _stages(interval: Interval, *, generic: bool) -> IntervalOutcome:
    """The stages 2-5 of the module docstring on ``interval`` (``generic``: with the generic
    deformation stages too)."""
    system = interval.system
    sizes = interval.sizes or AUTO_SIZES
    conn = Connection(system)
    cache = {}

    def guess_list(n):
        if n not in cache:
            cache[n] = loop_guesses(system, interval.sized(n), interval.x0, interval.x1, interval.T,
                                    interval.ends, interval.limits, conn=conn)
        return cache[n]

    refined = {}

    def attempt(n, k, polish_failures=True):
        g = guess_list(n)
        if len(g) <= k:
            return None
        known = None
        if (n, k) in refined:  # refined in an earlier stage: its evaluations are counted there
            c, err = refined[n, k]
            spent = 0
            if err <= 1e-8:  # and polished there already
                return None
        else:
            c, err, spent, known = refine(system, interval.sized(n), interval.x0, interval.x1, interval.T, g[k],
                                          budget=REFINE_BUDGET, limits=interval.limits)
            refined[n, k] = c, err
        if not err <= 1e-8 and not polish_failures:
            return IntervalOutcome(False, (), f"the refined {g[k].describe()} missed by {err:.2g} rad", spent)
        # the polish ends on the refinement's last evaluation (at c exactly) when it needs no
        # correction, instead of evaluating c again (solve_segment's initial_endpoint)
        out = (deform_attempt(interval, n, initial=c, budget=AUTO_BUDGET, initial_endpoint=known) if err <= 1e-8
               else deform_attempt(interval, n, initial=g[k].coefficients, budget=AUTO_BUDGET))
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
    g = guess_list(first)
    loops = [lambda: _repeated_loops(interval, first)] if len(g) > 1 else []
    if not generic:  # one loop first when one can, else repeated loops first; no failed loop polished
        single = [lambda k=k: attempt(first, k, polish_failures=False) for k in range(4)]
        return run_stages(single[:1] + loops + single[1:] if _one_loop_can(g) else loops + single)
    # every loop's refinement first (repeated loops before or after one loop, as one loop can or
    # not); a loop that missed is polished from its guess only after (that polish often ends in
    # the constrained solve: seconds, where a refined loop takes milliseconds)
    single = [lambda k=k: attempt(first, k, polish_failures=False) for k in range(4)]
    stages = single + loops if _one_loop_can(g) else loops + single
    # the loops in the larger bases (more freedom to keep the joint ranges) before any polish
    larger = [n for n in sizes if n > first]

    def enlarged(n, k):
        """``attempt(n, k)`` in a larger basis, unless the last larger one did not lower loop ``k``'s
        miss at the first size (:data:`ENLARGE_GAIN`)."""
        before = [m for m in larger if m < n]
        if before and (first, k) in refined and (before[-1], k) in refined:
            e0, e1 = refined[first, k][1], refined[before[-1], k][1]
            if e1 >= ENLARGE_GAIN * e0:
                return None
        return attempt(n, k, polish_failures=False)

    stages += [lambda n=n, k=k: enlarged(n, k) for n in larger for k in range(3)]
    stages += [lambda: deform_attempt(interval, first, budget=AUTO_BUDGET), lambda: attempt(first, 0)]
    stages += [lambda k=k: attempt(first, k) for k in range(1, 4)]
    for n in sizes:
        if n != first:
            stages += [lambda n=n: attempt(n, 0), lambda n=n: deform_attempt(interval, n, budget=AUTO_BUDGET)]
    return run_stages(stages)


def _one_loop_can(guesses) -> bool:
    """Whether a compliant loop guess misses by at most :data:`LOOP_SLACK`."""
    return any(g.kind == "loop" and g.compliant and g.predicted_error <= LOOP_SLACK for g in guesses)


def _repeatable(interval: Interval) -> bool:
    """Repeated loops apply (module docstring): :math:`L = 0`, the same shape at both ends, at rest
    at both ends (no other condition)."""
    system = interval.system
    if np.any(np.asarray(system.L) != 0.0) or not np.allclose(interval.x0[4:], interval.x1[4:], rtol=0, atol=1e-12):
        return False
    ends = interval.ends
    return (set(ends) == {"u0", "uT"} and not np.any(ends["u0"]) and not np.any(ends["uT"]))


def _repeated_loops(interval: Interval, n: int):
    """Stage 2 of the module docstring: ``None`` when it does not apply."""
    if not _repeatable(interval):
        return None
    system, x0, x1, T = interval.system, interval.x0, interval.x1, interval.T
    q0 = x0[:4] / np.linalg.norm(x0[:4])
    r = rot.log(rot.qmul(rot.qconj(q0), x1[:4] / np.linalg.norm(x1[:4])))
    conn = Connection(system)
    spent = 0
    reasons = []
    for k in range(2, MAX_LOOPS + 1):
        Tk = T / k
        step = rot.exp(r / k)
        sub_x1 = np.concatenate([rot.qmul(q0, step), x0[4:]])
        sub = dataclasses.replace(interval, x0=np.concatenate([q0, x0[4:]]), x1=sub_x1, T=Tk)
        basis = interval.sized(n)
        g = loop_guesses(system, basis, sub.x0, sub.x1, Tk, sub.ends, sub.limits, conn=conn)
        if not _one_loop_can(g):
            continue
        for guess in [x for x in g if x.kind == "loop" and x.compliant][:2]:
            c, err, used, known = refine(system, basis, sub.x0, sub.x1, Tk, guess, budget=REFINE_BUDGET,
                                         limits=interval.limits)
            spent += used
            if not err <= 1e-8:
                reasons.append(f"{k} loops: the refined {guess.describe()} missed by {err:.2g} rad")
                continue
            out = deform_attempt(sub, n, initial=c, budget=AUTO_BUDGET, initial_endpoint=known)
            spent += out.evaluations
            if not out.success or out.pieces[0].method != "deform":
                reasons.append(f"{k} loops: {out.reason or 'the polished loop needed the constrained solve'}")
                continue
            return _copies(interval, basis, out.pieces[0], q0, step, k, spent)
    return IntervalOutcome(False, (), "; ".join(reasons) or f"no loop within the limits turns by 1/{MAX_LOOPS} "
                           f"of the turn", spent)


def _copies(interval, basis, piece, q0, step, k, spent):
    """``k`` copies of one loop's piece (module docstring), each evaluated from its own start."""
    system, x0, T = interval.system, interval.x0, interval.T
    c = piece.basis_coefficients
    Tk = T / k
    pieces = []
    start = np.concatenate([q0, x0[4:]])
    q = q0
    for i in range(k):
        q = rot.qmul(q, step)
        target = interval.x1 if i == k - 1 else np.concatenate([q, x0[4:]])
        y, _ = backend.endpoint(system, basis, start, Tk, c)
        err = system.error(y, target)
        if not err <= interval.tol:
            return IntervalOutcome(False, (), f"{k} loops: copy {i + 1} missed by {err:.2g}", spent + i + 1)
        pieces.append(make_segment(system, basis, start, target, Tk, c, t0=i * Tk, final_error=err,
                                   limits=interval.limits, iterations=piece.iterations if i == 0 else 0,
                                   evaluations=(spent if i == 0 else 0) + 1, message=f"loop {i + 1} of {k}",
                                   method="loops"))
        start = target
    return IntervalOutcome(True, tuple(pieces), "", spent + k)
