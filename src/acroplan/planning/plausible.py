"""Whether a successful plan is a motion a body could make (:func:`plausibility`): its peak joint
rate against the rate its waypoints imply, its torques and power against the body's capacity
(:func:`beyond_capacity`); the warnings a result carries (:attr:`PlanResult.warnings`)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..core.result import PendingWarning, PlanResult
from ..core.budget import BudgetExceeded
from ..core.effort import peak_efforts

from .request import PlanRequest

__all__ = ["plausibility", "beyond_capacity", "waypoint_rate", "PLAUSIBLE_FACTOR", "EXACT_EFFORT_SEGMENTS",
           "DENSE_SEGMENTS"]

#: A success whose peak joint rate exceeds this many times the fastest rate its waypoints imply
#: (:func:`waypoint_rate`) carries warnings (:func:`plausibility`).
PLAUSIBLE_FACTOR = 10.0
#: Up to this many segments, a warning's peak torque and power are exact (the effort summary's
#: peaks, :func:`acroplan.core.effort.peak_efforts`, less than half the summary's time: 0.9 against
#: 2.0 ms for a flagged two-link segment); beyond, sampled on the fastest segments.
EXACT_EFFORT_SEGMENTS = 100
#: Segments from which a plan's waypoints count as dense (the warning then suggests fewer).
DENSE_SEGMENTS = 50


def waypoint_rate(system, times, waypoints) -> tuple[float, int]:
    """The fastest rate the waypoints imply, and the interval where: the largest finite difference
    :math:`|\\Delta q_i| / (t_{k+1} - t_k)` over the intervals :math:`k` and the angles :math:`q_i`
    (every angle state, the turn :math:`\\theta` included; a spatial body's attitude as the
    rotation vector :meth:`~ControlAffineSystem.diff` gives), in rad/s. ``(0.0, 0)`` when the
    system has no angle state or the waypoints do not move."""
    return _waypoint_rate(system, times, waypoints, _static(system)[1])


def _waypoint_rate(system, times, waypoints, idx) -> tuple[float, int]:
    """:func:`waypoint_rate` with the angle states' indices ``idx`` (:func:`_static`: ``None`` for
    an attitude on a manifold)."""
    if idx is not None:
        if not idx:
            return 0.0, 0
        if len(waypoints) <= _FEW:
            found = _few_rate(np.asarray(waypoints, dtype=float).tolist(), [float(v) for v in times], idx)
            if found is not None:
                return found
        X = np.asarray(waypoints, dtype=float)
        D = np.abs(np.diff(X[:, list(idx)], axis=0))
    else:  # an attitude on a manifold (unit quaternion): its rotation vector and the joint angles
        X = np.asarray(waypoints, dtype=float)
        D = np.abs(np.array([system.diff(X[k], X[k + 1]) for k in range(len(X) - 1)]))
    rate = np.max(D, axis=1) / np.diff(np.asarray(times, dtype=float))
    k = int(np.argmax(rate))
    return float(rate[k]), k


#: Up to this many waypoints :func:`waypoint_rate` works on Python floats: the same operations in
#: the same order (the same bits), without numpy's per-call overhead (20 of its 25 us on a
#: two-link plan, which checks it after every plan: ``benchmarks/plan_overhead.py``)
_FEW = 32


def _few_rate(rows, times, idx):
    """:func:`waypoint_rate` of a few waypoints (lists of floats), ``None`` unless every value is
    finite and the times increase (the numpy path then says what numpy says: NaN, inf). Plain
    loops: a plan checks this after its planner, where each generator expression cost a few
    microseconds more than in a loop of its own (``benchmarks/RESULTS.md``, seventeenth session)."""
    isfinite = math.isfinite
    for row in rows:
        for v in row:
            if not isfinite(v):
                return None
    before = None
    for v in times:
        if not isfinite(v) or (before is not None and v <= before):
            return None
        before = v
    best, where = -1.0, 0
    for k in range(len(times) - 1):
        a, b = rows[k], rows[k + 1]
        d = -1.0
        for i in idx:
            e = abs(b[i] - a[i])
            if e > d:
                d = e
        d /= times[k + 1] - times[k]
        if d > best:
            best, where = d, k
    return best, where


#: what :func:`_static` found, by the system's class and names (at most :data:`_STATIC_SIZE`)
_STATIC: dict = {}
_STATIC_SIZE = 256


def _static(system) -> tuple[bool, tuple | None]:
    """``(checked, idx)`` of a system, found once for its class and names: whether
    :func:`plausibility` checks its plans (every input a joint rate, of an angle state) and the
    indices of its angle states among its states (``None`` when its states are not a vector
    space: an attitude on a manifold, whose rate :func:`waypoint_rate` takes from
    :meth:`~ControlAffineSystem.diff`). The key is the class, the state, input and angle names, the
    rate inputs and the tangent dimension, all that the answer depends on (not
    :attr:`~ControlAffineSystem.structure_key`: a planar or spatial body's is its topology alone,
    its names being runtime), so two systems that differ in any of them never share an entry."""
    rates = system.rate_inputs
    key = (type(system), tuple(system.state_names), tuple(system.input_names), tuple(system.angle_states),
           tuple(rates.items()) if rates else (), system.ndx)
    found = _STATIC.get(key)
    if found is None:
        angles = system.angle_states
        checked = bool(rates) and set(rates) == set(system.input_names) and set(rates.values()) <= set(angles)
        idx = (tuple(i for i, name in enumerate(system.state_names) if name in angles)
               if system.ndx == system.n_states else None)
        found = (checked, idx)
        if len(_STATIC) >= _STATIC_SIZE:
            _STATIC.clear()
        _STATIC[key] = found
    return found


def plausibility(result: PlanResult, *, factor: float = PLAUSIBLE_FACTOR) -> tuple[str, ...]:
    """Why a successful plan may not be a motion to use: the warnings :func:`plan` puts in
    :attr:`PlanResult.warnings` (empty when nothing is suspect).

    A plan is suspect when its peak joint rate (exact, :attr:`PlanResult.max_abs_u`) exceeds
    ``factor`` times the fastest rate its waypoints imply (:func:`waypoint_rate`): the waypoints
    are met, but by a motion far wilder than theirs (dense waypoints of a body with little
    authority, free conditions that pass a growing oscillation from segment to segment). The
    warnings then say: the peak rate, where, and the ratio; the peak torque and power when the
    body gives torques (exact, the peaks of :meth:`PlanResult.effort`, up to
    :data:`EXACT_EFFORT_SEGMENTS` segments; beyond, a lower bound sampled on the 32 fastest
    segments, said so); and what to try (fewer waypoints when they are dense, from
    :data:`DENSE_SEGMENTS` segments: the issue's 5,001 waypoints 0.02 s apart give 179 rad/s free
    and 92 rad/s spline, every 250th of them 0.28 rad/s; ``conditions="spline"`` for free
    conditions). Only bodies whose inputs are all joint rates are checked,
    and only the inputs without a rate limit (``u_max``, ``input_bounds``, a link table's or URDF's
    velocity): a bounded input is within what the caller says the body can do.

    A turn at zero angular momentum made by shape loops needs joint rates many times its turn's
    (the bundled ``three-rods-turn`` 14 times, ``space-robot-turn`` 31 times): such plans pass when
    their rates are bounded, as the bundled ones are; unbounded, they are flagged.

    Here every warning is worked out. :func:`plan` leaves the peak torque and power to be worked
    out when its result's warnings are first read (:class:`~acroplan.core.result.PendingWarning`),
    with the same numbers, and the exact peak rate too when a sample of the inputs (the limits'
    257-point check grid: :func:`acroplan.core.limits.sampled_input_peak`, a lower bound) already
    shows the plan beyond ``factor``; its message then gives that bound ("at least").
    """
    return tuple(w.function(result, *w.args) if isinstance(w, PendingWarning) else w
                 for w in _rate_check(result, factor, lazy=False)[0])


def _rate_check(result: PlanResult, factor: float, lazy: bool) -> tuple[tuple, str]:
    """``(warnings, head)``: :func:`plausibility`'s warnings, the peak torque and power a
    :class:`~acroplan.core.result.PendingWarning` (when the summary was not computed already), and
    what the message says of the peak rate. ``lazy`` (what :func:`plan` asks): a plan whose sampled
    peak rate (each free input on the 257 points of the limits' check grid, a lower bound of its
    peak) is already beyond the factor is flagged without finding the exact peak (the roots of u':
    0.15 ms of a two-link plan); its rate warning is pending too, with the same words and numbers
    when read, and the head gives the sampled bound ("at least")."""
    system, segs = result.system, result.segments
    if not result.success or not segs:
        return (), ""
    checked, idx = _static(system)
    if not checked:
        return (), ""
    # an input with a rate limit is within what the caller says the body can do: not checked
    limits = result.limits
    free = (tuple(range(len(system.input_names))) if limits is None else
            tuple(j for j, name in enumerate(system.input_names) if limits.input_bound(name) is None))
    implied, k = _waypoint_rate(system, result.times, result.waypoints, idx)
    if not free or implied <= 0.0:
        return (), ""
    # an upper bound of every free input's peak first (InputBasis.sup_bound: the sum of the
    # coefficients' magnitudes): a plan it shows within the factor needs no root finding (0.1-0.2
    # ms of a two-link plan's 0.4-0.8), and the answer is the same
    if _bounds_within(result, free, factor * implied):
        return (), ""
    low = _sampled_peak(result, free) if lazy else 0.0
    if low > factor * implied:
        rate = PendingWarning(_rate_warning, (free, implied, k))
        effort = PendingWarning(_effort_of_peaks, (free,))
        head = f"peak joint rate at least {low:.4g} rad/s, at least {low / implied:.0f}x what the waypoints imply"
    else:
        peaks = _exact_peaks(result, free)
        peak = float(peaks.max())
        if not peak > factor * implied:
            return (), ""
        rate = _rate_warning(result, free, implied, k, peaks)
        effort = PendingWarning(_effort_warning, (peaks,))
        head = f"peak joint rate {peak:.4g} rad/s, {peak / implied:.0f}x what the waypoints imply"
    out = [rate]
    if result.has_torques:  # its numbers when the warnings are read: they cost more than the plan
        out.append(effort.function(result, *effort.args) if result._effort is not None else effort)
    K = len(result.times) - 1
    tries = []
    if K >= DENSE_SEGMENTS:
        dt = np.diff(result.times)
        tries.append(f"fewer waypoints, further apart (these are {K} segments of {np.median(dt):.3g} s: with so "
                     "little time a segment can need a wild motion to keep the turn on its waypoints)")
    if result.conditions == "free":
        tries.append('conditions = "spline"')
    out.append("try " + " or ".join(tries) if tries else
               "check the waypoints (a turn the body can only make with such a motion), or add rate limits "
               "(u_max, input_bounds) to plan within them")
    return tuple(out), head


def _bounds_within(result: PlanResult, free, top: float) -> bool:
    """Whether the coefficients' bound (:meth:`InputBasis.sup_bound`) of every free input on every
    segment is known and at most ``top`` (loops that stop at the first bound beyond it)."""
    for seg in result.segments:
        basis, c = result.basis_for(seg), seg.basis_coefficients
        for j in free:
            b = basis.sup_bound(c[j])
            if b is None or b > top:
                return False
    return True


def _sampled_peak(result: PlanResult, free) -> float:
    """The largest :math:`|u_j|` of the free inputs on the 257 points of the limits' check grid
    (:mod:`acroplan.core.limits`), over the segments: a lower bound of the peak rate."""
    from ..core.limits import sampled_input_peak

    rows = None if len(free) == result.system.n_inputs else list(free)  # all rows: as they are, no copy
    return max(sampled_input_peak(result.basis_for(seg), seg.basis_coefficients if rows is None else
                                  seg.basis_coefficients[rows]) for seg in result.segments)


def _row_peaks(result: PlanResult, seg, free) -> list[float]:
    """Each free input's exact peak :math:`\\max|u_j|` on ``seg`` (the roots of :math:`u_j'`)."""
    from ..core.limits import input_extremes

    basis = result.basis_for(seg)
    return [max(abs(v) for v in input_extremes(basis, seg.basis_coefficients[j])) for j in free]


def _exact_peaks(result: PlanResult, free) -> np.ndarray:
    """Each segment's exact peak rate of the free inputs, shape (K,) (every input free: the
    segments' own :attr:`~acroplan.core.segment.SegmentResult.max_abs_u`, kept in them)."""
    if len(free) == result.system.n_inputs:
        return np.array([s.max_abs_u for s in result.segments])
    return np.array([max(_row_peaks(result, s, free)) for s in result.segments])


def _rate_warning(result: PlanResult, free, implied: float, k: int, peaks=None) -> str:
    """The warning of the peak rate: the exact peak, where, and its ratio to ``implied`` (the
    waypoints' fastest rate, over interval ``k``); ``peaks`` the segments' exact peaks
    (:func:`_exact_peaks`) when already found."""
    peaks = _exact_peaks(result, free) if peaks is None else peaks
    worst = int(np.argmax(peaks))
    peak, seg = float(peaks[worst]), result.segments[worst]
    # the input at the peak (one free input: that one, without finding its extremes again)
    name = result.system.input_names[free[0] if len(free) == 1 else free[int(np.argmax(_row_peaks(result, seg, free)))]]
    return (f"peak joint rate {peak:.4g} rad/s ({name}, segment {seg.index}, t = {seg.t0:.4g} to {seg.t1:.4g} s) is "
            f"{peak / implied:.0f} times the fastest rate the waypoints imply, {implied:.4g} rad/s (finite difference "
            f"over [{result.times[k]:.4g}, {result.times[k + 1]:.4g}] s)")


def _effort_of_peaks(result: PlanResult, free) -> str:
    """:func:`_effort_warning` with the segments' exact peak rates (worked out here)."""
    return _effort_warning(result, _exact_peaks(result, free))


def _effort_warning(result: PlanResult, peaks) -> str:
    """The warning's peak torque and power (exact, or a lower bound sampled on the fastest segments)."""
    segs = result.segments
    try:
        if len(segs) <= EXACT_EFFORT_SEGMENTS:
            # the exact peaks alone (peak_efforts: the summary's without its integrals and roots, less
            # than half its time), or the summary's when it was computed already
            known = result._effort
            tops = ({n: (e.peak_torque, e.peak_power) for n, e in known.items()} if known is not None
                    else peak_efforts(result))
            j = max(tops, key=lambda n: tops[n][0])
            p = max(v[1] for v in tops.values())
            return f"peak torque {tops[j][0]:.4g} N m (joint {j}), peak power {p:.4g} W"
        fastest = np.argsort(peaks)[-32:]
        t = np.concatenate([np.linspace(segs[i].t0, segs[i].t1, 65) for i in sorted(fastest)])
        tau, power = result.torques(t)
        return (f"peak torque at least {np.max(np.abs(tau)):.4g} N m, peak power at least "
                f"{np.max(np.abs(power)):.4g} W (sampled on the 32 fastest of {len(segs)} segments; exact in "
                "result.effort())")
    except BudgetExceeded as e:
        return f"peak torque and power not computed: {e}"


def beyond_capacity(result: PlanResult, capacity: dict | None) -> tuple[str, ...]:
    """Warnings of a success beyond what the body can do (``capacity=`` of :func:`plan`): a peak
    joint rate above its input's top rate (exact), a peak torque above its joint's strength (exact
    up to :data:`EXACT_EFFORT_SEGMENTS` segments; beyond, a lower bound sampled on the 32 fastest
    segments, which is enough to show it exceeded)."""
    if not capacity or not result.success or not result.segments:
        return ()
    from ..core.limits import input_extremes

    segs, system, out = result.segments, result.system, []
    for name, (top, source) in capacity.get("rates", {}).items():
        j = system.input_names.index(name)
        if system.n_inputs == 1:
            peak = max(s.max_abs_u for s in segs)
        else:
            peak = max(max(abs(v) for v in input_extremes(result.basis_for(s), s.basis_coefficients[j])) for s in segs)
        if peak > top * (1.0 + 1e-9):
            out.append(f"peak joint rate {peak:.4g} rad/s ({name}) is beyond what the body can do, {top:g} rad/s "
                       f"({source})")
    torques = capacity.get("torques") or {}
    if torques and result.has_torques:
        try:
            if len(segs) <= EXACT_EFFORT_SEGMENTS:
                effort = result.effort()
                peaks, exact = {j: e.peak_torque for j, e in effort.items()}, True
            else:
                fastest = np.argsort([s.max_abs_u for s in segs])[-32:]
                t = np.concatenate([np.linspace(segs[i].t0, segs[i].t1, 65) for i in sorted(fastest)])
                tau, _ = result.torques(t)
                peaks, exact = {j: float(np.max(np.abs(tau[:, k]))) for k, j in enumerate(_joint_names(result))}, False
        except BudgetExceeded:
            peaks, exact = {}, True
        for joint, (top, source) in torques.items():
            peak = peaks.get(joint)
            if peak is not None and peak > top * (1.0 + 1e-9):
                out.append(f"peak torque {'at least ' if not exact else ''}{peak:.4g} N m (joint {joint}) is beyond "
                           f"the body's strength, {top:g} N m ({source})")
    return tuple(out)


def _joint_names(result: PlanResult) -> tuple[str, ...]:
    """The torque model's joint names, in the order of :meth:`PlanResult.torques`'s columns."""
    return result._torque_setup()[1]


def _plausible(result: PlanResult, req: PlanRequest) -> PlanResult:
    """``result`` with its warnings (:func:`plausibility`, :func:`beyond_capacity`), the message
    saying so (a success only)."""
    if not result.success:
        return result
    try:
        rate, head = _rate_check(result, PLAUSIBLE_FACTOR, lazy=True)
        warnings = rate + beyond_capacity(result, req.capacity)
    except BudgetExceeded:
        return result
    if not warnings:
        return result
    if not rate:
        head = warnings[0].split(" (", 1)[0] + " beyond what the body can do"
    out = dataclasses.replace(result, warnings=warnings, message=result.message + f"; IMPLAUSIBLE: {head} "
                              f"({len(warnings)} warning{'s' if len(warnings) > 1 else ''}: result.warnings)")
    object.__setattr__(out, "_effort", result._effort)  # an effort summary computed already, kept
    return out


