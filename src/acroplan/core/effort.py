"""The effort of a plan's joints: :class:`JointEffort` and :func:`effort_summary` (what
:meth:`PlanResult.effort <acroplan.core.result.PlanResult.effort>` returns), by the rules of
:data:`EFFORT_RULE`. Knows no body: the torques come from the system's torque model."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from . import budget
from .errors import InvalidInputError
from .progress import stage

__all__ = ["JointEffort", "EFFORT_RULE", "PEAK_CANDIDATES", "ROOT_XTOL", "ROOT_POINTS", "effort_summary", "peak",
           "peaks"]


#: How :meth:`PlanResult.effort` integrates and takes maxima (also written in ``to_dict()["effort"]``).
EFFORT_RULE = ("integrals of tau^2 and tau u: composite 32-point Gauss-Legendre on each segment, on at least 8 "
               "panels and one per radian of max|u| T (at most 4096); positive work: the same rule on each panel, "
               "split at the sign changes of tau u (found between the nodes and panel edges, refined by 32-fold "
               "bracketing, then windows about the secant's zero, to 1e-14 s and a secant step); peaks: the local "
               "maxima on those points within 1% of the largest, each refined by a bounded scalar search; integral "
               "of u^2: exact (the basis Gram matrix)")


@dataclasses.dataclass(frozen=True)
class JointEffort:
    """The effort of one joint over a plan (:meth:`PlanResult.effort`, rules in :data:`EFFORT_RULE`).

    Attributes
    ----------
    joint : str
        The joint (a torque row of the system's torque model).
    input : str
        The input that drives it (its rate).
    duration : float
        The planned span :math:`t_K - t_0`.
    peak_torque : float
        :math:`\\max_t |\\tau|` (N m with SI parameters).
    peak_power : float
        :math:`\\max_t |\\tau u|` (W).
    positive_work : float
        :math:`\\int \\max(\\tau u, 0)\\,dt` (J): what a motor that cannot recover energy spends.
    net_work : float
        :math:`\\int \\tau u\\,dt` (J), the change of the kinetic energy this joint causes.
    torque_squared : float
        :math:`\\int \\tau^2 dt` (N^2 m^2 s).
    input_squared : float
        :math:`\\int u^2 dt` of the joint's input, exact.
    """

    joint: str
    input: str
    duration: float
    peak_torque: float
    peak_power: float
    positive_work: float
    net_work: float
    torque_squared: float
    input_squared: float

    def to_dict(self) -> dict:
        """``{joint: {"input": ..., "peak_torque": ..., ...}}`` in plain JSON types."""
        d = dataclasses.asdict(self)
        return {d.pop("joint"): d}


def peak(f, grid, values) -> float:
    """:math:`\\max |f|` on ``[grid[0], grid[-1]]``: the (at most :data:`PEAK_CANDIDATES`) largest
    local maxima of ``|values|`` on ``grid`` within 1% of the largest, each refined by zooming: ``f``
    (vectorised: ``f(xs)`` for an array of times) on 33 points across the two grid intervals around
    it, then 33 across the two intervals around the best of those, four times (the bracket shrinks
    16-fold each time, to :math:`16^{-4}` of the grid's spacing: for a smooth :math:`f` the maximum
    to about :math:`10^{-11}` relative). One call of ``f`` a zoom: a torque model that integrates
    (a spatial body's attitude) is called a few times, not hundreds."""
    v = np.abs(values)
    top = float(v.max())
    best = top
    left = np.concatenate([[-np.inf], v[:-1]])
    right = np.concatenate([v[1:], [-np.inf]])
    cands = np.flatnonzero((v >= left) & (v >= right) & (v >= 0.99 * top))
    for i in cands[np.argsort(-v[cands], kind="stable")][:PEAK_CANDIDATES]:
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        for _ in range(4):
            if not b > a:
                break
            xs = np.linspace(a, b, 33)
            fx = np.abs(np.asarray(f(xs), dtype=float))
            k = int(np.argmax(fx))
            best = max(best, float(fx[k]))
            a, b = xs[max(k - 1, 0)], xs[min(k + 1, xs.size - 1)]
    return best


#: How many local maxima of a sampled torque or power :func:`_peak` refines.
PEAK_CANDIDATES = 4


def effort_summary(result) -> dict[str, JointEffort]:
    """The effort of each joint of ``result`` (a :class:`~acroplan.core.result.PlanResult` of a
    system with a torque model), by :data:`EFFORT_RULE`; reports the stage ``"effort summary"``
    (one step a segment: :mod:`acroplan.core.progress`).

    Raises
    ------
    InvalidInputError
        The system has no torque model, or the result has no segments.
    """
    model, names, inputs = result._torque_setup()
    if not result.segments:
        raise InvalidInputError("result", "has no planned segments", "plan a motion first")
    p = len(names)
    xg, wg = np.polynomial.legendre.leggauss(32)
    xg, wg = (xg + 1.0) / 2.0, wg / 2.0  # on [0, 1]
    acc = {k: np.zeros(p) for k in ("peak_tau", "peak_pow", "pos", "net", "tau2", "u2")}
    with stage("effort summary", len(result.segments), unit="segment") as st:
        for seg in result.segments:
            _segment_effort(result, seg, model, inputs, xg, wg, acc)
            st.update()
    duration = float(result.segments[-1].t1 - result.segments[0].t0)
    return {name: JointEffort(joint=name, input=result.system.input_names[inputs[j]], duration=duration,
                              peak_torque=float(acc["peak_tau"][j]), peak_power=float(acc["peak_pow"][j]),
                              positive_work=float(acc["pos"][j]), net_work=float(acc["net"][j]),
                              torque_squared=float(acc["tau2"][j]), input_squared=float(acc["u2"][j]))
            for j, name in enumerate(names)}


def _segment_effort(result, seg, model, inputs, xg, wg, acc) -> None:
    """Add one segment's integrals and peaks into the accumulators ``acc`` (by joint). The torque
    model is called on batches of times (about six calls a segment: the grid, the rounds of the
    roots with the zooms of the peaks, the split panels), never point by point: a model that integrates (a
    spatial body's momentum) costs as much for one time as for hundreds."""
    T = seg.t1 - seg.t0
    basis = result.basis_for(seg)
    G = basis.gram()
    c = np.asarray(seg.basis_coefficients, dtype=float)
    acc["u2"] += T * np.array([c[i] @ G @ c[i] for i in inputs])
    P = int(min(4096, max(8, math.ceil(seg.max_abs_u * T))))

    def motion(tt):
        budget.check()  # a plan's effort summary is inside its time budget (the command line's)
        return result._segment_torques(model, seg, np.atleast_1d(np.asarray(tt, dtype=float)), inputs)

    # one evaluation: the Gauss nodes of every panel and the panel edges, in time order
    edges = np.linspace(seg.t0, seg.t1, P + 1)
    h = T / P
    nodes = edges[:-1, None] + h * xg[None, :]  # (P, 32)
    grid = np.concatenate([np.column_stack([edges[:-1], nodes]).ravel(), edges[-1:]])
    tau_g, pow_g = motion(grid)
    p = tau_g.shape[0]
    inner = np.ones(grid.size, dtype=bool)
    inner[::33] = False  # the panel edges
    tau_q, pow_q = tau_g[:, inner].reshape(p, P, 32), pow_g[:, inner].reshape(p, P, 32)
    panel_w = h * wg
    acc["tau2"] += np.einsum("jpk,k->j", tau_q**2, panel_w)
    panel_pow = np.einsum("jpk,k->jp", pow_q, panel_w)  # (p, P): the power's integral per panel
    acc["net"] += panel_pow.sum(axis=1)
    # the roots of the powers and the zooms of the peaks in lockstep: one call a round for both
    rows, panels, lo, hi = _brackets(grid, pow_g, P)
    found, top = _lockstep(motion, [(_root_rounds(rows, lo, hi), lambda tp: tp[1]),
                                    (_peak_rounds(grid, np.vstack([tau_g, pow_g])), np.vstack)])
    roots: dict[tuple, list] = {}
    for n, r in found:
        roots.setdefault((int(rows[n]), int(panels[n])), []).append(float(r))
    _positive_work(motion, edges, roots, panel_pow, xg, wg, acc["pos"])
    acc["peak_tau"] = np.maximum(acc["peak_tau"], top[:p])
    acc["peak_pow"] = np.maximum(acc["peak_pow"], top[p:])


def _lockstep(motion, searches):
    """Run the searches ``[(generator, pick)]`` side by side: each round, every live generator
    yields the times it needs, ``motion`` is called once on all of them, and each gets
    ``pick((tau, power))`` at its own times. Returns the generators' results."""
    out = [None] * len(searches)
    live = {}
    for k, (gen, _) in enumerate(searches):
        try:
            live[k] = next(gen)
        except StopIteration as stop:
            out[k] = stop.value
    while live:
        keys = list(live)
        sizes = [live[k].size for k in keys]
        tau, pw = motion(np.concatenate([live[k] for k in keys]))
        at = 0
        for k, n in zip(keys, sizes):
            gen, pick = searches[k]
            vals = pick((tau[:, at:at + n], None if pw is None else pw[:, at:at + n]))
            at += n
            try:
                live[k] = gen.send(vals)
            except StopIteration as stop:
                out[k] = stop.value
                del live[k]
    return out


def _drive(f, gen):
    """Run one search generator alone, ``f(xs)`` giving what it needs."""
    return _lockstep(lambda xs: (f(xs), None), [(gen, lambda tp: tp[0])])[0]


def peaks(f, grid, values) -> np.ndarray:
    """:func:`peak` of every row of ``values`` (r, K) at once: ``f(xs)`` gives all rows (r, len(xs)),
    and each of the four zooms evaluates the brackets of every row's candidates in one call (the
    same points as :func:`peak` row by row)."""
    return _drive(f, _peak_rounds(grid, values))


def _peak_rounds(grid, values):
    """:func:`peaks` as a search generator (:func:`_lockstep`): yields the times of a zoom, receives
    the rows' values there, returns the peaks (r,)."""
    v = np.abs(values)
    best = v.max(axis=1)
    rows, lo, hi = [], [], []
    for j in range(v.shape[0]):
        left = np.concatenate([[-np.inf], v[j, :-1]])
        right = np.concatenate([v[j, 1:], [-np.inf]])
        cands = np.flatnonzero((v[j] >= left) & (v[j] >= right) & (v[j] >= 0.99 * best[j]))
        for i in cands[np.argsort(-v[j, cands], kind="stable")][:PEAK_CANDIDATES]:
            rows.append(j)
            lo.append(grid[max(i - 1, 0)])
            hi.append(grid[min(i + 1, grid.size - 1)])
    rows, lo, hi = np.array(rows, dtype=int), np.array(lo, dtype=float), np.array(hi, dtype=float)
    frac = np.linspace(0.0, 1.0, 33)
    for _ in range(4):
        keep = hi > lo
        rows, lo, hi = rows[keep], lo[keep], hi[keep]
        if not rows.size:
            break
        xs = lo[:, None] + (hi - lo)[:, None] * frac[None, :]
        xs[:, -1] = hi
        got = yield xs.ravel()
        fx = np.abs(np.asarray(got, dtype=float)).reshape(-1, rows.size, 33)[rows, np.arange(rows.size)]
        i = np.argmax(fx, axis=1)
        np.maximum.at(best, rows, fx[np.arange(rows.size), i])
        lo, hi = xs[np.arange(rows.size), np.maximum(i - 1, 0)], xs[np.arange(rows.size), np.minimum(i + 1, 32)]
    return best


#: Bracket width (seconds) at which the roots of the power are taken (:func:`_roots`).
ROOT_XTOL = 1e-14
#: Points in each bracket in a round of :func:`_roots` (the first round: a 32-fold shrink).
ROOT_POINTS = 33
#: A later round's window about the secant's zero is this many times narrower than the bracket.
ROOT_WINDOW = 512


def _brackets(grid, pow_g, P):
    """The grid intervals where a joint's power changes sign: ``(rows, panels, lo, hi)`` arrays."""
    rows, panels, lo, hi = [], [], [], []
    for j in range(pow_g.shape[0]):
        for i in np.flatnonzero(np.sign(pow_g[j, :-1]) * np.sign(pow_g[j, 1:]) < 0):
            rows.append(j)
            panels.append(min(int(i // 33), P - 1))
            lo.append(grid[i])
            hi.append(grid[i + 1])
    return (np.array(rows, dtype=int), np.array(panels, dtype=int), np.array(lo, dtype=float),
            np.array(hi, dtype=float))


def _roots(motion, rows, lo, hi):
    """The roots of the powers ``motion(t)[1][rows]`` in the brackets ``[lo, hi]``
    (:func:`_root_rounds`, run alone): ``[(index into the brackets, root)]``."""
    return _drive(lambda xs: motion(xs)[1], _root_rounds(rows, lo, hi))


def _root_rounds(rows, lo, hi):
    """The roots of the powers of ``rows`` in the brackets ``[lo, hi]`` (a sign change each on the
    grid), as a search generator (:func:`_lockstep`: yields times, receives every joint's power
    there). Each round takes :data:`ROOT_POINTS` points in every bracket and keeps the interval of
    the first sign change among them and the bracket's ends, until the brackets are
    :data:`ROOT_XTOL` wide; the root is then the secant's zero in the last bracket. The first round
    spreads its points across the bracket (a 32-fold shrink); later rounds put them across a window
    :data:`ROOT_WINDOW` times narrower than the bracket about the secant's zero, where a smooth
    power's root is (the secant's error is of the order of the square of the bracket's width): a
    shrink of some 15,000-fold a round when the root is in the window, and when it is not, the
    next round spreads its points again. A bracket whose ends, evaluated again, show no sign change
    (the power within rounding of zero at an end: a batch need not round as the grid's did) has
    that end, the smaller in magnitude, as its root. Returns ``[(index into the brackets, root)]``."""
    out = []
    lo, hi = lo.copy(), hi.copy()
    live = np.arange(rows.size)
    frac = np.linspace(0.0, 1.0, ROOT_POINTS)
    inner = np.linspace(-1.0, 1.0, ROOT_POINTS - 2)
    fa = fb = None
    spread = np.ones(rows.size, dtype=bool)  # the next round spreads its points across the bracket
    while live.size:
        a, b = lo[live], hi[live]
        xs = a[:, None] + (b - a)[:, None] * frac[None, :]
        was_spread = spread[live]
        if fa is not None:  # a window about the secant's zero, inside the bracket, the ends kept
            with np.errstate(divide="ignore", invalid="ignore"):
                r = np.where(fb != fa, a - fa * (b - a) / (fb - fa), 0.5 * (a + b))
            d = (b - a) / ROOT_WINDOW
            win = np.clip(r[:, None] + d[:, None] * inner[None, :], a[:, None], b[:, None])
            xs = np.where(was_spread[:, None], xs, np.column_stack([a, win, b]))
        xs[:, 0], xs[:, -1] = a, b
        k = np.arange(live.size)
        got = yield xs.ravel()
        vals = np.asarray(got, dtype=float).reshape(-1, live.size, ROOT_POINTS)[rows[live], k]
        if fa is None:  # the first round: the ends as this batch gives them
            ends = np.sign(vals[:, 0]) * np.sign(vals[:, -1]) >= 0
            for n in np.flatnonzero(ends):
                out.append((int(live[n]), a[n] if abs(vals[n, 0]) <= abs(vals[n, -1]) else b[n]))
            keep = ~ends
            live, xs, vals, k, a, b = live[keep], xs[keep], vals[keep], np.arange(int(keep.sum())), a[keep], b[keep]
            was_spread = was_spread[keep]
        else:
            vals[:, 0], vals[:, -1] = fa, fb
        if not live.size:
            break
        i = np.argmax(np.sign(vals[:, :-1]) * np.sign(vals[:, 1:]) <= 0, axis=1)
        width = b - a
        a, b, fa, fb = xs[k, i], xs[k, i + 1], vals[k, i], vals[k, i + 1]
        # after a spread round a window next; after a window that missed the root (the bracket left
        # is a piece beside it), a spread round
        spread[live] = ~was_spread & ((b - a) > 2.0 * width / ROOT_WINDOW)
        lo[live], hi[live] = a, b
        done = (b - a <= ROOT_XTOL) | ~((a < 0.5 * (a + b)) & (0.5 * (a + b) < b))
        for n in np.flatnonzero(done):
            out.append((int(live[n]), a[n] if fa[n] == fb[n] else a[n] - fa[n] * (b[n] - a[n]) / (fb[n] - fa[n])))
        live, fa, fb = live[~done], fa[~done], fb[~done]
    return out


def _positive_work(motion, edges, roots, panel_pow, xg, wg, pos) -> None:
    """Add each joint's positive work on one segment to ``pos``: a panel where the power keeps its
    sign gives max(its integral, 0); a panel where it changes sign is split at its ``roots``
    (``{(joint, panel): [times]}``) and integrated piece by piece (one call for all)."""
    p, P = panel_pow.shape
    pieces = []  # (joint, lengths, times)
    for j in range(p):
        for k in range(P):
            if (j, k) not in roots:
                pos[j] += max(float(panel_pow[j, k]), 0.0)
                continue
            cuts = np.concatenate([[edges[k]], sorted(roots[(j, k)]), [edges[k + 1]]])
            lens = np.diff(cuts)
            keep = lens > 0
            pieces.append((j, lens[keep], (cuts[:-1][keep, None] + lens[keep, None] * xg[None, :]).ravel()))
    if pieces:
        vals = motion(np.concatenate([ts for _, _, ts in pieces]))[1]
        at = 0
        for j, lens, ts in pieces:
            v = vals[j, at:at + ts.size].reshape(-1, 32) @ wg * lens
            pos[j] += float(np.sum(np.maximum(v, 0.0)))
            at += ts.size
