"""The effort of a plan's joints: :class:`JointEffort` and :func:`effort_summary` (what
:meth:`PlanResult.effort <acroplan.core.result.PlanResult.effort>` returns), by the rules of
:data:`EFFORT_RULE`. Knows no body: the torques come from the system's torque model."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from . import budget
from .errors import InvalidInputError
from .objectives import gram
from .progress import stage

__all__ = ["JointEffort", "EFFORT_RULE", "peak_times", "PEAK_CANDIDATES", "PEAK_ZOOMS", "PEAK_POINTS", "ROOT_XTOL",
           "ROOT_RTOL", "ROOT_POINTS", "INTERPOLANT_TAIL", "effort_summary", "peak_efforts", "peak", "peaks"]


#: How :meth:`PlanResult.effort` integrates and takes maxima (also written in ``to_dict()["effort"]``).
EFFORT_RULE = ("integrals of tau^2 and tau u: composite 32-point Gauss-Legendre on each segment, on at least 8 "
               "panels and one per radian of max|u| T (at most 4096); between the nodes, on a panel where the last "
               "three Legendre coefficients of every row's values at its nodes are within 1e-12 of the row's largest "
               "value, the degree-31 interpolant of those values, elsewhere the torque model; positive work: the same "
               "rule on each panel, "
               "split at the sign changes of tau u (found between the nodes and panel edges, refined by 32-fold "
               "bracketing, then windows about the secant's zero, to brackets 1e-7 of the segment's duration and a "
               "secant step); peaks: the local maxima on those points within 1% of the largest, each refined by two "
               "32-fold zooms and the vertex of the parabola through the best point and its neighbours; integral "
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
    """:math:`\\max |f|` on ``[grid[0], grid[-1]]`` (:func:`peaks` of one row): the (at most
    :data:`PEAK_CANDIDATES`) largest local maxima of ``|values|`` on ``grid`` within 1% of the
    largest, each refined by :data:`PEAK_ZOOMS` zooms of :data:`PEAK_POINTS` points and the vertex
    of the parabola through the best point and its neighbours. ``f`` is vectorised (``f(xs)`` for
    an array of times), called once a zoom: a torque model that integrates (a spatial body's
    attitude) is called twice, not hundreds of times."""
    return float(peaks(lambda xs: np.atleast_2d(np.asarray(f(xs), dtype=float)), np.asarray(grid, dtype=float),
                       np.atleast_2d(np.asarray(values, dtype=float)))[0])


#: How many local maxima of a sampled torque or power :func:`peaks` refines.
PEAK_CANDIDATES = 4
#: Zooms of a peak's bracket (:func:`peaks`), each on :data:`PEAK_POINTS` points across the two
#: intervals about the best point of the last: a 32-fold shrink a zoom.
PEAK_ZOOMS = 2
#: Points across a peak's bracket in a zoom.
PEAK_POINTS = 65


def effort_summary(result) -> dict[str, JointEffort]:
    """The effort of each joint of ``result`` (a :class:`~acroplan.core.result.PlanResult` of a
    system with a torque model), by :data:`EFFORT_RULE`; reports the stage ``"effort summary"``
    (one step a segment: :mod:`acroplan.core.progress`).

    Raises
    ------
    InvalidInputError
        The system has no torque model, or the result has no segments.
    """
    names, inputs, efforts = _segment_efforts(result, peaks_only=False)
    p = len(names)
    acc = {k: np.zeros(p) for k in ("peak_tau", "peak_pow", "pos", "net", "tau2", "u2")}
    with stage("effort summary", len(result.segments), unit="segment") as st:
        for own in efforts:
            for k in ("pos", "net", "tau2", "u2"):
                acc[k] += own[k]
            for k in ("peak_tau", "peak_pow"):
                np.maximum(acc[k], own[k], out=acc[k])
            st.update()
    duration = float(result.segments[-1].t1 - result.segments[0].t0)
    return {name: JointEffort(joint=name, input=result.system.input_names[inputs[j]], duration=duration,
                              peak_torque=float(acc["peak_tau"][j]), peak_power=float(acc["peak_pow"][j]),
                              positive_work=float(acc["pos"][j]), net_work=float(acc["net"][j]),
                              torque_squared=float(acc["tau2"][j]), input_squared=float(acc["u2"][j]))
            for j, name in enumerate(names)}


def peak_efforts(result) -> dict[str, tuple[float, float]]:
    """Each joint's peak :math:`|\\tau|` and peak :math:`|\\tau u|` of ``result``, ``{joint:
    (peak_torque, peak_power)}``: :func:`effort_summary`'s peaks, found the same way (the model on
    every panel's Gauss nodes and edges, then the zooms of the largest), without its integrals and
    the roots of the powers for the positive work, in less than half its time (0.9 against 2.0 ms
    on the two-link plans the plausibility check flags: ``benchmarks/RESULTS.md``, fourteenth
    session). What :func:`acroplan.planning.plausibility`'s warning gives.

    Raises
    ------
    InvalidInputError
        The system has no torque model, or the result has no segments.
    """
    names, inputs, efforts = _segment_efforts(result, peaks_only=True)
    top_tau, top_pow = np.zeros(len(names)), np.zeros(len(names))
    for own in efforts:
        np.maximum(top_tau, own["peak_tau"], out=top_tau)
        np.maximum(top_pow, own["peak_pow"], out=top_pow)
    return {name: (float(top_tau[j]), float(top_pow[j])) for j, name in enumerate(names)}


def _segment_efforts(result, *, peaks_only: bool):
    """``(names, inputs, efforts)`` of ``result``: its torque model's joints and their inputs, and
    an iterator over its segments' own efforts (:func:`_segment_effort`), a joint motion worked out
    once and its repeats given the same (:func:`_motion_key`). Raises as :func:`effort_summary`."""
    model, names, inputs = result._torque_setup()
    if not result.segments:
        raise InvalidInputError("result", "has no planned segments", "plan a motion first")
    xg, wg = _GAUSS32

    def efforts():
        done = {}  # each joint motion's own effort, by its key (_motion_key)
        for seg in result.segments:
            key = _motion_key(result, seg, model)
            if key not in done:
                done[key] = _segment_effort(result, seg, model, inputs, xg, wg, peaks_only=peaks_only)
            yield done[key]

    return names, inputs, efforts()


def _gauss32():
    xg, wg = np.polynomial.legendre.leggauss(32)
    xg, wg = (xg + 1.0) / 2.0, wg / 2.0  # on [0, 1]
    xg.setflags(write=False)
    wg.setflags(write=False)
    return xg, wg


_GAUSS32 = _gauss32()


def _to_legendre():
    """The matrix (32, 32) from values at the 32 Gauss nodes to the Legendre coefficients of the
    polynomial of degree 31 through them (on the panel mapped to [-1, 1]): :math:`a_k =
    \\tfrac{2k + 1}{2} \\sum_j w_j P_k(x_j) f_j`, exact (the Gauss rule integrates degree 63)."""
    x, w = np.polynomial.legendre.leggauss(32)
    M = (np.polynomial.legendre.legvander(x, 31) * w[:, None]).T * ((2 * np.arange(32) + 1) / 2.0)[:, None]
    M.setflags(write=False)
    return M


_TO_LEGENDRE = _to_legendre()


def _barycentric():
    """The 32 Gauss nodes on [0, 1] and their barycentric weights :math:`1 / \\prod_{k \\ne j} (x_j -
    x_k)` (scaled to at most 1: the formula's quotient does not see a common factor)."""
    x = _GAUSS32[0]
    d = x[:, None] - x[None, :]
    np.fill_diagonal(d, 1.0)
    w = 1.0 / np.prod(d, axis=1)
    w /= np.abs(w).max()
    for a in (x, w):
        a.setflags(write=False)
    return x, w


_NODES, _BARY = _barycentric()


def _motion_key(result, seg, model) -> tuple:
    """What one segment's effort depends on: its basis, duration and input coefficients, and its
    start state, or the part of it the torque model names (its ``start_key(system, x0)``, when it
    has one: a spatial body's joint angles at zero angular momentum, where the attitude does not
    enter). Two segments with equal keys have the same torques at the same times into them, so
    :func:`effort_summary` works out their effort once: the repeated loops of a large turn at
    L = 0 (:mod:`acroplan.families.spatial.strategy`) are segments of one joint motion, and the
    falling cat's summary took as long again for its second loop."""
    basis = result.basis_for(seg)
    start = np.asarray(seg.start, dtype=float)
    own = getattr(model, "start_key", None)
    part = np.asarray(own(result.system, start) if callable(own) else start, dtype=float)
    return (type(basis).__name__, int(basis.n), float(seg.t1 - seg.t0),
            np.asarray(seg.basis_coefficients, dtype=float).tobytes(), part.tobytes())


def _segment_effort(result, seg, model, inputs, xg, wg, *, peaks_only: bool = False) -> dict:
    """One segment's integrals and peaks, by joint: ``{"u2", "tau2", "net", "pos", "peak_tau",
    "peak_pow"}``, each (p,) (the sums and maxima :func:`effort_summary` takes over the segments). The torque
    model is called on the grid (every panel's Gauss nodes and edges); the later rounds (two of the
    roots with the two zooms of the peaks, the split panels) read the panels' interpolants
    (:class:`PanelInterpolants`) and call the model, once a round, only for times in panels the
    interpolants do not resolve: never point by point, since a model that integrates (a spatial
    body's momentum) costs as much for one time as for hundreds. One call a segment when every panel
    is resolved, at most four. ``peaks_only``: ``{"peak_tau", "peak_pow"}`` alone, by the same
    rounds of the peaks' zooms run without the roots' (the same numbers where the model's value at
    a time does not depend on the other times asked with it, as the acrobot's and a planar body's;
    a spatial body's integrating model may differ in the last bits)."""
    T = seg.t1 - seg.t0
    P = int(min(4096, max(8, math.ceil(seg.max_abs_u * T))))

    def model_motion(tt):
        budget.check()  # a plan's effort summary is inside its time budget (the command line's)
        return result._segment_torques(model, seg, np.atleast_1d(np.asarray(tt, dtype=float)), inputs)

    # one evaluation: the Gauss nodes of every panel and the panel edges, in time order
    edges = np.linspace(seg.t0, seg.t1, P + 1)
    h = T / P
    nodes = edges[:-1, None] + h * xg[None, :]  # (P, 32)
    grid = np.concatenate([np.column_stack([edges[:-1], nodes]).ravel(), edges[-1:]])
    tau_g, pow_g = model_motion(grid)
    p = tau_g.shape[0]
    inner = np.ones(grid.size, dtype=bool)
    inner[::33] = False  # the panel edges
    tau_q, pow_q = tau_g[:, inner].reshape(p, P, 32), pow_g[:, inner].reshape(p, P, 32)
    # the later rounds read the panels' interpolants where they are resolved, the model elsewhere
    motion = PanelInterpolants(edges, np.concatenate([tau_q, pow_q]), model_motion, p)
    if peaks_only:
        (top, _), = _lockstep(motion, [(_peak_rounds(grid, np.vstack([tau_g, pow_g])), np.vstack)])
        return {"peak_tau": top[:p], "peak_pow": top[p:]}
    G = gram(result.basis_for(seg))
    c = np.asarray(seg.basis_coefficients, dtype=float)
    acc = {"u2": T * np.array([c[i] @ G @ c[i] for i in inputs])}
    panel_w = h * wg
    acc["tau2"] = np.einsum("jpk,k->j", tau_q**2, panel_w)
    panel_pow = np.einsum("jpk,k->jp", pow_q, panel_w)  # (p, P): the power's integral per panel
    acc["net"] = panel_pow.sum(axis=1)
    # the roots of the powers and the zooms of the peaks in lockstep: one call a round for both
    rows, panels, lo, hi = _brackets(grid, pow_g, P)
    found, (top, _) = _lockstep(motion, [(_root_rounds(rows, lo, hi, ROOT_RTOL * T), lambda tp: tp[1]),
                                         (_peak_rounds(grid, np.vstack([tau_g, pow_g])), np.vstack)])
    at = np.array([n for n, _ in found], dtype=int)
    acc["pos"] = np.zeros(p)
    _positive_work(motion, edges, rows[at], panels[at], np.array([r for _, r in found], dtype=float), panel_pow,
                   xg, wg, acc["pos"])
    acc["peak_tau"], acc["peak_pow"] = top[:p], top[p:]
    return acc


#: A panel's interpolant stands for the torque model (:class:`PanelInterpolants`) when the last three
#: Legendre coefficients of every row's values at the panel's 32 Gauss nodes are within this of the
#: row's largest value on the segment's grid. Measured (the bundled falling cat, twisting
#: somersault and trunk twist): those coefficients are 2e-15 to 6e-14 of the rows' largest values
#: (rounding), the interpolants off by at most 1e-13 of them at the panels' edges (the model's own
#: values there); the back full twist's torques have panels with 2e-11 and 4e-10 (the model on
#: those).
INTERPOLANT_TAIL = 1e-12


class PanelInterpolants:
    """The torques and powers of one segment between the grid's points, from the values the model
    gave at the 32 Gauss nodes of every panel: on each panel the polynomial of degree 31 through
    them, where it resolves every row (:data:`INTERPOLANT_TAIL`: its Legendre coefficients by the
    Gauss rule, exact for it), evaluated by the barycentric formula (its weights for the Gauss
    nodes, :math:`1 / \\prod_{k \\ne j} (x_j - x_k)`); the times in the other panels go to the
    model, in one call. Called like the model: ``(tau, power)`` at times ``tt``.

    Parameters
    ----------
    edges : numpy.ndarray, shape (P + 1,)
        The panels' edges (times).
    values : numpy.ndarray, shape (r, P, 32)
        Each row's values at each panel's nodes ``edges[k] + h * x_j`` (``x_j`` the 32 Gauss nodes
        on [0, 1], ``h = (edges[-1] - edges[0]) / P``): the torque rows first, then the powers.
    model : callable
        ``model(tt) -> (tau, power)``, each (p, len(tt)).
    p : int
        The torque rows (the first ``p`` of ``values``).
    """

    def __init__(self, edges, values, model, p: int):
        self.edges, self.model, self.p = np.asarray(edges, dtype=float), model, int(p)
        self.values = np.asarray(values, dtype=float)
        #: each row's Legendre coefficients on each panel (r, P, 32), the panel mapped to [-1, 1]
        self.coef = coef = self.values @ _TO_LEGENDRE.T
        scale = np.abs(self.values).max(axis=(1, 2))
        tail = np.abs(coef[:, :, -3:]).max(axis=2)  # (r, P)
        #: the panels whose interpolants serve (every row's tail within INTERPOLANT_TAIL of its scale)
        self.resolved = (tail <= INTERPOLANT_TAIL * scale[:, None]).all(axis=0)
        #: calls of the model since construction
        self.calls = 0

    def integrals(self, rows, panels, a, b) -> np.ndarray:
        """:math:`\\int_{a_i}^{b_i}` of row ``rows[i]`` of the values (the torques' rows first, then
        the powers') over a piece ``[a[i], b[i]]`` of panel ``panels[i]``: its interpolant's Legendre
        series integrated term by term (``numpy.polynomial.legendre.legint``) and evaluated at the
        piece's ends by Clenshaw's recurrence, exact for the polynomial (as the panel's Gauss rule
        on the piece is); NaN on a panel that is not resolved (:attr:`resolved`: the model's
        values are needed there)."""
        e = self.edges
        lo, width = e[panels], e[panels + 1] - e[panels]
        A = np.polynomial.legendre.legint(self.coef[rows, panels].T, lbnd=-1.0, axis=0)  # (33, pieces)
        ends = [np.polynomial.legendre.legval(2.0 * (x - lo) / width - 1.0, A, tensor=False) for x in (a, b)]
        return np.where(self.resolved[panels], 0.5 * width * (ends[1] - ends[0]), np.nan)

    def __call__(self, tt):
        t = np.atleast_1d(np.asarray(tt, dtype=float))
        e = self.edges
        k = np.searchsorted(e, t, side="right")
        k -= 1
        np.minimum(k, e.size - 2, out=k)
        np.maximum(k, 0, out=k)
        ok = self.resolved[k]
        r = self.values.shape[0]
        out = np.empty((r, t.size))
        if ok.any():
            at = np.flatnonzero(ok)
            at = at[np.argsort(k[at], kind="stable")]  # by panel, each panel's times together
            kk = k[at]
            x = t[at] - e[kk]
            x /= e[kk + 1] - e[kk]
            np.minimum(x, 1.0, out=x)
            np.maximum(x, 0.0, out=x)
            D = np.subtract.outer(x, _NODES)  # (M, 32), then the weights w_j / (x - x_j) in place
            hit = D == 0.0
            if hit.any():  # a time on a node: that node's value
                D[hit] = 1.0
                np.divide(_BARY, D, out=D)
                rows = hit.any(axis=1)
                D[rows] = hit[rows]
            else:
                np.divide(_BARY, D, out=D)
            den = D.sum(axis=1)
            cuts = np.flatnonzero(kk[1:] != kk[:-1]) + 1
            res = np.empty((r, at.size))
            for a, b in zip([0] + cuts.tolist(), cuts.tolist() + [at.size]):
                np.matmul(self.values[:, kk[a], :], D[a:b].T, out=res[:, a:b])
            res /= den  # the formula's quotient, after the products
            out[:, at] = res
        if not ok.all():
            self.calls += 1
            tau, pw = self.model(t[~ok])
            out[:self.p, ~ok], out[self.p:, ~ok] = tau, pw
        return out[:self.p], out[self.p:]


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
    """:math:`\\max_t |f_j(t)|` of every row ``j`` of ``values`` (r, K), sampled on ``grid`` (K,);
    ``f(xs)`` gives all rows (r, len(xs)).

    Each row's (at most :data:`PEAK_CANDIDATES`) largest local maxima on the grid within 1% of its
    largest are refined by :data:`PEAK_ZOOMS` zooms: :data:`PEAK_POINTS` points across the two
    intervals about the best point so far, every row's candidates in one call of ``f`` a zoom. The
    peak is then the largest value seen, or, where the last zoom's best point :math:`f_0` has two
    smaller neighbours :math:`f_\\pm`, the vertex of the parabola through the three,
    :math:`f_0 + (f_+ - f_-)^2 / (8 (2 f_0 - f_+ - f_-))`: exact for a quadratic, and for a smooth
    :math:`f` off by :math:`O(|f^{(3)}| h^3)` at the last spacing :math:`h` (the best point alone
    by up to :math:`|f''| h^2 / 8`). On the bundled falling cat and twisting somersault (grid
    spacing about 1e-3 s, :math:`h` about 1e-6 s) the peaks agree with three zooms of 129 points to
    2e-13 relative (one zoom: 2e-9)."""
    return _drive(f, _peak_rounds(grid, values))[0]


def _hopeful(x, f, i, best, *, ends: bool = False):
    """Whether the maximum near sample ``i`` of each row of ``f`` (K samples at times ``x``, both
    (r, K)) can reach ``best`` (r,), with four times the margin of a parabola's: inside, when
    :math:`f_i + 2|f''|h^2` does (:math:`f''` the second difference there, :math:`h` the wider
    neighbouring spacing: within :math:`h` of a sample the maximum is at most :math:`|f''|h^2/2`
    above it). At an end, always, or with ``ends`` (the ends of the whole span) unless the slope of
    the parabola through the three end samples falls away from the end by more than
    :math:`2|f''|h`: then the end's own value, already known, is the maximum there."""
    r = np.arange(f.shape[0])
    return _hopeful_at(lambda j: x[r, j], lambda j: f[r, j], f.shape[1], i, best, ends=ends)


def _hopeful_at(x_at, f_at, K: int, i, best, *, ends: bool = False):
    """:func:`_hopeful` with the samples read by ``x_at(j)`` and ``f_at(j)`` (the time and the value
    of each candidate's sample ``j``, an array of indices or one index): the first round's
    candidates read the whole grid's row without copying it (:func:`_peak_rounds`), the zooms
    their own samples. The same arithmetic in the same order either way."""
    inside = (i > 0) & (i < K - 1)
    a, c = np.maximum(i - 1, 0), np.minimum(i + 1, K - 1)
    xi, fi = x_at(i), f_at(i)
    hm, hp = xi - x_at(a), x_at(c) - xi
    with np.errstate(divide="ignore", invalid="ignore"):
        d2 = 2.0 * ((f_at(c) - fi) / hp - (fi - f_at(a)) / hm) / (hp + hm)
        reach = fi + 2.0 * np.abs(d2) * np.maximum(hm, hp) ** 2
        keep = ~inside | ~np.isfinite(reach) | (reach >= best)
        if ends and K >= 3:
            for at, j0, j1, j2, sign in ((i == 0, 0, 1, 2, 1.0), (i == K - 1, K - 1, K - 2, K - 3, -1.0)):
                if not at.any():
                    continue
                h1, h2 = x_at(j1) - x_at(j0), x_at(j2) - x_at(j1)  # inward, signed
                f0, f1 = f_at(j0), f_at(j1)
                s1, s2 = (f1 - f0) / h1, (f_at(j2) - f1) / h2
                curv = 2.0 * (s2 - s1) / (h1 + h2)
                slope = s1 - 0.5 * curv * h1  # f' at the end
                falls = sign * slope < -2.0 * np.abs(curv) * np.abs(h1)  # falling inward
                keep = np.where(at & np.isfinite(slope) & falls, False, keep)
    return keep


def peak_times(f, grid, values) -> tuple[np.ndarray, np.ndarray]:
    """``(peaks, times)``: :func:`peaks` of every row of ``values`` and the time of each (the
    refined point that gave it, or the vertex of the last zoom's parabola)."""
    return _drive(f, _peak_rounds(grid, values))


def _raise(best, when, rows, vals, times) -> None:
    """``best[r] = max(best[r], v)`` over the candidates ``(r, v, t)``, with ``when[r] = t`` where
    it rose (each row's largest candidate)."""
    before = best[rows]
    np.maximum.at(best, rows, vals)
    rose = (vals > before) & (vals == best[rows])
    when[rows[rose]] = times[rose]


def _peak_rounds(grid, values):
    """:func:`peak_times` as a search generator (:func:`_lockstep`): yields the times of a zoom,
    receives the rows' values there, returns the peaks (r,) and their times. A candidate goes on to
    the next zoom only while it can still reach its row's best (:func:`_hopeful`)."""
    v = np.abs(values)
    best = v.max(axis=1)
    when = grid[np.argmax(v, axis=1)]
    # each row's local maxima within 1% of its largest (a sample not below its neighbours, an end
    # not below its one neighbour), the largest first, ties in time order, at most PEAK_CANDIDATES
    local = v >= 0.99 * best[:, None]
    if v.shape[1] > 1:
        local[:, :-1] &= v[:, :-1] >= v[:, 1:]
        local[:, 1:] &= v[:, 1:] >= v[:, :-1]
    rows, idx = np.nonzero(local)
    vals = v[rows, idx]
    order = np.lexsort((idx, -vals, rows))  # by row, then value down, then time
    rows, idx = rows[order], idx[order]
    first = np.searchsorted(rows, rows, side="left")
    take = np.arange(rows.size) - first < PEAK_CANDIDATES
    take[take] = np.isfinite(vals[order][take])  # an infinite sample takes its place and is dropped
    rows, idx = rows[take], idx[take]
    keep = _hopeful_at(lambda j: grid[j], lambda j: v[rows, j], grid.size, idx, best[rows], ends=True)
    rows, idx = rows[keep], idx[keep]
    lo, hi = grid[np.maximum(idx - 1, 0)], grid[np.minimum(idx + 1, grid.size - 1)]
    n = PEAK_POINTS
    frac = np.linspace(0.0, 1.0, n)
    for zoom in range(PEAK_ZOOMS):
        keep = hi > lo
        rows, lo, hi = rows[keep], lo[keep], hi[keep]
        if not rows.size:
            break
        xs = lo[:, None] + (hi - lo)[:, None] * frac[None, :]
        xs[:, -1] = hi
        got = yield xs.ravel()
        k = np.arange(rows.size)
        fx = np.abs(np.asarray(got, dtype=float)).reshape(-1, rows.size, n)[rows, k]
        i = np.argmax(fx, axis=1)
        _raise(best, when, rows, fx[k, i], xs[k, i])
        if zoom == PEAK_ZOOMS - 1:  # the parabola's vertex, where the best point has two smaller neighbours
            r = k[(i > 0) & (i < n - 1)]
            c = i[r]
            f0, fm, fp = fx[r, c], fx[r, c - 1], fx[r, c + 1]
            d = 2.0 * f0 - fm - fp
            pos = d > 0.0
            dd = np.where(pos, d, 1.0)
            vertex = np.where(pos, f0 + (fp - fm) ** 2 / (8.0 * dd), f0)
            h = (hi[r] - lo[r]) / (n - 1)
            _raise(best, when, rows[r], vertex, xs[r, c] + np.where(pos, h * (fp - fm) / (2.0 * dd), 0.0))
            break
        live = _hopeful(xs, fx, i, best[rows])
        rows, lo, hi = rows[live], xs[k, np.maximum(i - 1, 0)][live], xs[k, np.minimum(i + 1, n - 1)][live]
    return best, when


#: Bracket width (seconds) at which :func:`_roots` takes a root, unless told another.
ROOT_XTOL = 1e-14
#: The effort summary's roots: a bracket this fraction of the segment's duration :math:`T` wide is
#: narrow enough. A root off by :math:`\delta` moves the positive work by at most
#: :math:`|P'|\delta^2/2`: at :math:`\delta = 10^{-7} T`, :math:`10^{-14}` of :math:`|P'| T^2/2`,
#: the size of a joint's work over the segment. The root itself is the secant's zero in the last
#: bracket, off by at most :math:`|P''/P'|\delta^2/8` (some 1e-16 s on the bundled plans).
ROOT_RTOL = 1e-7
#: Points in each bracket in a round of :func:`_roots` (the first round: a 32-fold shrink).
ROOT_POINTS = 33
#: A later round's window about the secant's zero is this many times narrower than the bracket.
ROOT_WINDOW = 512


def _brackets(grid, pow_g, P):
    """The grid intervals where a joint's power changes sign: ``(rows, panels, lo, hi)`` arrays, by
    joint and then in time."""
    rows, i = np.nonzero(np.sign(pow_g[:, :-1]) * np.sign(pow_g[:, 1:]) < 0)
    return rows, np.minimum(i // 33, P - 1), grid[i], grid[i + 1]


def _roots(motion, rows, lo, hi, xtol=ROOT_XTOL):
    """The roots of the powers ``motion(t)[1][rows]`` in the brackets ``[lo, hi]``
    (:func:`_root_rounds`, run alone): ``[(index into the brackets, root)]``."""
    return _drive(lambda xs: motion(xs)[1], _root_rounds(rows, lo, hi, xtol))


def _root_rounds(rows, lo, hi, xtol=ROOT_XTOL):
    """The roots of the powers of ``rows`` in the brackets ``[lo, hi]`` (a sign change each on the
    grid), as a search generator (:func:`_lockstep`: yields times, receives every joint's power
    there). Each round takes :data:`ROOT_POINTS` points in every bracket and keeps the interval of
    the first sign change among them and the bracket's ends, until the brackets are
    ``xtol`` wide (:data:`ROOT_XTOL`; the effort summary's: :data:`ROOT_RTOL` of the segment's
    duration); the root is then the secant's zero in the last bracket. The first round
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
            out.extend(zip(live[ends].tolist(), np.where(np.abs(vals[ends, 0]) <= np.abs(vals[ends, -1]), a[ends],
                                                         b[ends]).tolist()))
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
        done = (b - a <= xtol) | ~((a < 0.5 * (a + b)) & (0.5 * (a + b) < b))
        if done.any():
            ad, bd, fad, fbd = a[done], b[done], fa[done], fb[done]
            with np.errstate(divide="ignore", invalid="ignore"):
                r = np.where(fad == fbd, ad, ad - fad * (bd - ad) / (fbd - fad))
            out.extend(zip(live[done].tolist(), r.tolist()))
        live, fa, fb = live[~done], fa[~done], fb[~done]
    return out


def _positive_work(motion, edges, J, K, R, panel_pow, xg, wg, pos) -> None:
    """Add each joint's positive work on one segment to ``pos``: a panel where the power keeps its
    sign gives max(its integral, 0); a panel where it changes sign is split at its roots (joint
    ``J[i]``'s power in panel ``K[i]`` at time ``R[i]``), each piece up to the last root integrated
    exactly from the panel's interpolant where it is resolved (:meth:`PanelInterpolants.integrals`),
    elsewhere by the panel's rule on the model's values (one call for all), the piece after it as
    the panel's integral less the others."""
    p, P = panel_pow.shape
    split = np.zeros((p, P), dtype=bool)
    split[J, K] = True
    pos += np.maximum(np.where(split, 0.0, panel_pow), 0.0).sum(axis=1)
    if not R.size:
        return
    order = np.lexsort((R, K, J))
    J, K, R = J[order], K[order], R[order]
    group = J * P + K
    first = np.concatenate([[True], group[1:] != group[:-1]])
    last = np.concatenate([group[1:] != group[:-1], [True]])
    # the pieces from the previous root of the panel (or its left edge) to each root: integrated
    # from the panel's interpolant where it is resolved (PanelInterpolants.integrals), else by the
    # panel's rule on the model's values (one call for all of those)
    starts = np.where(first, edges[K], np.roll(R, 1))
    lens = R - starts
    v = motion.integrals(motion.p + J, K, starts, R) if hasattr(motion, "integrals") else np.full(J.size, np.nan)
    rest = np.flatnonzero(np.isnan(v))
    if rest.size:
        pts = (starts[rest, None] + np.maximum(lens[rest], 0.0)[:, None] * xg[None, :]).ravel()
        vals = motion(pts)[1]  # (p, pieces * 32)
        v[rest] = vals[J[rest, None], np.arange(rest.size * 32).reshape(-1, 32)] @ wg * lens[rest]
    v = np.where(lens > 0, v, 0.0)
    np.add.at(pos, J, np.maximum(v, 0.0))
    # and the piece after each panel's last root: the panel's integral less its pieces before
    before = np.add.reduceat(v, np.flatnonzero(first))
    rest = panel_pow[J[last], K[last]] - before
    np.add.at(pos, J[last], np.where(edges[K[last] + 1] > R[last], np.maximum(rest, 0.0), 0.0))
