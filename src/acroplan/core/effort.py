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

__all__ = ["JointEffort", "EFFORT_RULE", "PEAK_CANDIDATES", "ROOT_XTOL", "effort_summary", "peak", "peaks"]


#: How :meth:`PlanResult.effort` integrates and takes maxima (also written in ``to_dict()["effort"]``).
EFFORT_RULE = ("integrals of tau^2 and tau u: composite 32-point Gauss-Legendre on each segment, on at least 8 "
               "panels and one per radian of max|u| T (at most 4096); positive work: the same rule on each panel, "
               "split at the sign changes of tau u (found between the nodes and panel edges, refined by 32-fold "
               "bracketing to 1e-14 s and a secant step); peaks: the local maxima on those points within 1% of the largest, each refined "
               "by a bounded scalar search; integral of u^2: exact (the basis Gram matrix)")


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
    model is called on batches of times (about fifteen calls a segment: the grid, the zooms of the
    roots and of the peaks, the split panels), never point by point: a model that integrates (a
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
    _positive_work(motion, grid, edges, pow_g, panel_pow, xg, wg, acc["pos"])
    acc["peak_tau"] = np.maximum(acc["peak_tau"], peaks(lambda x: motion(x)[0], grid, tau_g))
    acc["peak_pow"] = np.maximum(acc["peak_pow"], peaks(lambda x: motion(x)[1], grid, pow_g))


def peaks(f, grid, values) -> np.ndarray:
    """:func:`peak` of every row of ``values`` (p, K) at once: ``f(xs)`` gives all rows (p, len(xs)),
    and each zoom evaluates the brackets of every row's candidates in one call (the same points
    and the same numbers as :func:`peak` row by row)."""
    p = values.shape[0]
    best = np.abs(values).max(axis=1)
    brackets = []  # (row, a, b)
    for j in range(p):
        v = np.abs(values[j])
        top = float(v.max())
        left = np.concatenate([[-np.inf], v[:-1]])
        right = np.concatenate([v[1:], [-np.inf]])
        cands = np.flatnonzero((v >= left) & (v >= right) & (v >= 0.99 * top))
        for i in cands[np.argsort(-v[cands], kind="stable")][:PEAK_CANDIDATES]:
            brackets.append((j, grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]))
    for _ in range(4):
        brackets = [(j, a, b) for j, a, b in brackets if b > a]
        if not brackets:
            break
        xs = np.concatenate([np.linspace(a, b, 33) for _, a, b in brackets])
        fx = np.abs(np.asarray(f(xs), dtype=float))
        out = []
        for k, (j, a, b) in enumerate(brackets):
            pts, vals = xs[33 * k:33 * (k + 1)], fx[j, 33 * k:33 * (k + 1)]
            i = int(np.argmax(vals))
            best[j] = max(best[j], float(vals[i]))
            out.append((j, pts[max(i - 1, 0)], pts[min(i + 1, 32)]))
        brackets = out
    return best


#: Bracket width (seconds) at which the roots of the power are taken (:func:`_roots`).
ROOT_XTOL = 1e-14


def _roots(motion, brackets):
    """The roots of the powers in ``brackets`` ``[(tag, row, a, b, f(a), f(b))]`` (a sign change
    each), all at once, as ``[(tag, row, root)]``: each round evaluates 33 points across every bracket in one call and keeps
    the interval of the sign change (a 32-fold shrink), until the brackets are :data:`ROOT_XTOL`
    wide; the root is then the secant's zero in the last bracket."""
    out = []
    live = list(brackets)
    while live:
        xs = np.concatenate([np.linspace(a, b, 33) for _, _, a, b, _, _ in live])
        fx = motion(xs)[1]
        nxt = []
        for k, (tag, j, a, b, fa, fb) in enumerate(live):
            pts, vals = xs[33 * k:33 * (k + 1)], fx[j, 33 * k:33 * (k + 1)].copy()
            vals[0], vals[-1] = fa, fb
            i = int(np.flatnonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)[0])
            a, b, fa, fb = pts[i], pts[i + 1], vals[i], vals[i + 1]
            if b - a <= ROOT_XTOL or not (a < 0.5 * (a + b) < b):
                out.append((tag, j, a if fa == fb else a - fa * (b - a) / (fb - fa)))
            else:
                nxt.append((tag, j, a, b, fa, fb))
        live = nxt
    return out


def _positive_work(motion, grid, edges, pow_g, panel_pow, xg, wg, pos) -> None:
    """Add each joint's positive work on one segment to ``pos``: a panel where the power keeps its
    sign gives max(its integral, 0); a panel where it changes sign is split at the roots (found for
    every joint at once, :func:`_roots`) and integrated piece by piece (one call for all)."""
    P, p = edges.size - 1, pow_g.shape[0]
    brackets = []  # (panel, joint, a, b)
    for j in range(p):
        for i in np.flatnonzero(np.sign(pow_g[j, :-1]) * np.sign(pow_g[j, 1:]) < 0):
            brackets.append((min(int(i // 33), P - 1), j, grid[i], grid[i + 1]))
    roots: dict[tuple, list] = {}
    if brackets:
        # the ends again, as point evaluations (a point need not round as the batch did)
        ends = motion(np.array([t for _, _, a, b in brackets for t in (a, b)]))[1]
        live = []
        for k, (panel, j, a, b) in enumerate(brackets):
            fa, fb = float(ends[j, 2 * k]), float(ends[j, 2 * k + 1])
            if fa * fb < 0:
                live.append((panel, j, a, b, fa, fb))
            else:  # the power is within rounding of zero at an end: that end is the root
                roots.setdefault((j, panel), []).append(a if abs(fa) <= abs(fb) else b)
        for panel, j, r in _roots(motion, live):
            roots.setdefault((j, panel), []).append(r)
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
