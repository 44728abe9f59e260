"""The front door for planning, :func:`plan`, and what it does after validation (:func:`solve`):
feasibility, the strategies per waypoint interval, the exact compliance and the independent
check (the package docstring's steps 2-4); :func:`warm_up`."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..core import backend
from ..core.basis import make_basis
from ..core.conditions import Conditions
from ..core.errors import InvalidInputError
from ..core.limits import Limits
from ..core import progress as progress_mod
from ..core.family import prepare
from ..core.result import PlanResult, SegmentResult, Status
from ..core.blas import one_blas_thread
from ..core.budget import BudgetExceeded, budget
from ..core.chain import STAGE as JOINT_STAGE
from ..core.budget import now as budget_clock
from ..core.strategies import Interval, IntervalOutcome
from ..core.system import ControlAffineSystem
from ..core.verify import check_name, verify_plan

from .plausible import _plausible
from .request import PlanRequest, TIME_LIMIT

__all__ = ["plan", "solve", "warm_up"]


def plan(system: ControlAffineSystem, *, times, conditions: str | None = None, method="auto", basis="legendre",
         n_coefficients: int | None = None, max_coefficients: int | None = None, limits: Limits | None = None,
         u_max: float | None = None, state_bounds=None, input_bounds=None, verify: bool | str = True,
         tol: float = 1e-10, max_evaluations: int = 2000, time_limit: float | None = TIME_LIMIT, start_rate=None,
         end_rate=None, degrees: bool = False, objective: str | None = None, tau_max=None, capacity=None,
         progress=None, **waypoints) -> PlanResult:
    r"""Plan a motion of ``system`` through waypoints.

    Parameters
    ----------
    system : ControlAffineSystem
        For example :class:`acroplan.Acrobot`.
    times : array_like, shape (K+1,)
        Strictly increasing waypoint times.
    **waypoints : array_like, shape (K+1,)
        One keyword per state, by the system's state names (``theta=..., phi=...`` for the
        acrobot). Every state must be given; ``None`` at an interior waypoint leaves that state
        free there (the system chooses it: :meth:`~ControlAffineSystem.fill_free`; the result's
        waypoints hold the values chosen). ``NAME_min=``, ``NAME_max=`` bound a state whose rate
        is an input (``phi_min``, ``phi_max`` for the acrobot's joint).
    conditions : {"spline", "free"}, optional
        Input conditions (:mod:`acroplan.core.conditions`); default ``"spline"``, or ``"free"`` with
        ``objective`` (or ``tau_max``): the least :math:`\int u^2` with the input's values pinned
        at the waypoints (the spline's u and u', or ``start_rate``/``end_rate``), and the least
        :math:`\int\tau^2` with u' pinned, are infima no input attains (the optimum in the basis
        grows boundary layers as the basis grows, and the ladder reports it not converged).
        ``"spline"`` needs every input to be
        the rate of a state (:attr:`ControlAffineSystem.rate_inputs`).
    method : str or Strategy
        ``"auto"`` (the system's own choice), a registered strategy (``"deform"``, the text's path
        deformation; ``"flat"`` for the acrobot; ``"energy-optimal"``, ``"torque-optimal"``), or a
        :class:`~acroplan.core.strategies.Strategy`. With ``objective``: the feasible plan the
        optimisation starts from (``"auto"``: the family's own starts when it has them, else the
        system's ``"auto"`` plan and path deformation; any other method: that method's plan alone);
        an optimal strategy together with ``objective`` is refused.
    basis : {"legendre", "monomial"} or InputBasis
        Internal basis of each segment's input (results are also exported in the power basis).
    n_coefficients : int, optional
        Coefficients per input per segment, at most :data:`MAX_COEFFICIENTS`. Default: the
        strategy's choice (6, the text's, for ``"deform"``; 6, 10 or 14 for ``"auto"``).
    max_coefficients : int, optional
        With ``objective`` (or ``tau_max``): the largest basis size of the optimum's ladder (below),
        from 6 to :data:`MAX_LADDER_COEFFICIENTS`; above 30 the ladder goes on in steps of 6 (36,
        42, ...) and ends at it. Default 30. For an optimum whose cost still falls at 30 (reported
        as not converged in the basis; the bundled back full's least :math:`\int\tau^2`: 181.36 at
        30, 179.87 at 48, ``benchmarks/RESULTS.md``); a smaller one stops the ladder early.
        Refused with ``n_coefficients`` (one size, no ladder).
    limits : Limits, optional
        All bounds at once, in place of the system's own (``Limits()`` for none at all). Without
        it, the system's own limits (:meth:`ControlAffineSystem.default_limits`: a URDF's or link
        table's joint ranges and rates) hold, changed name by name by the keywords ``u_max``
        (:math:`|u_j| \le u_{max}` for every input, in place of the system's rate limits),
        ``state_bounds`` (``{"phi": (lo, hi)}``: that joint's range), ``input_bounds``
        (``{"u": 15.0}``: that input's rate limit), ``NAME_min``, ``NAME_max`` (one end; ``None``
        drops the system's). What the keywords do not name keeps the system's limit: a rate limit
        alone does not drop a body's joint ranges.
    verify : bool or {"family", "ode"}
        Check the plan independently of the planner's compiled integrator, and require every
        waypoint within :data:`VERIFY_TOL` (plus what the check can resolve on long chains,
        :func:`acroplan.core.verify.verify_plan`): ``"ode"`` re-simulates it with scipy DOP853
        (rtol = atol = 3e-14, about 5-10 ms a segment); ``"family"`` uses the family's own check
        (the acrobot's flat-output identity: no ODE solver, a fraction of a millisecond;
        Pinocchio's centroidal momentum for articulated bodies); ``True`` (default) the family's
        check when it has one, else the ODE; ``False`` skips the check (only for speed in batch
        work).
    tol : float
        Required endpoint error of each segment (compiled integrator).
    max_evaluations : int
        Evaluation budget per segment and basis size.
    time_limit : float or None
        Wall-clock budget of the whole plan in seconds (default :data:`TIME_LIMIT`); when it is
        spent the plan ends ``not_converged``, with the segments done so far. ``None``: no limit.
    start_rate, end_rate : float, array_like of shape (m,), or dict by input name, optional
        With ``conditions="free"``: the inputs at the first and at the last waypoint, ``0`` to
        start or end at rest (the default leaves them free).
    degrees : bool
        Angles (the system's :attr:`~ControlAffineSystem.angle_states`) are given in degrees:
        waypoints, their bounds, and rate limits and rates of angles in degrees per second. The
        result is in radians.
    objective : {None, "energy", "torque"}
        ``None`` (default): the fast feasible plan, no cost minimised. ``"energy"``: the least
        :math:`\int_0^T\|u\|^2 dt` on each waypoint interval; ``"torque"``: the least
        :math:`\int_0^T\|\tau\|^2 dt` of the joint torques (systems with a torque model:
        :meth:`~ControlAffineSystem.torque_model`). The endpoint is an equality, the limits are
        inequalities, in the input coefficients; the basis size goes up the ladder 6, 10, 14, 20,
        26, 30 until the optimal cost changes by less than 1e-4 (relative) from one size to the
        next (``n_coefficients`` fixes one size, ``max_coefficients`` the ladder's last), and each
        segment reports its relative KKT residual (target 1e-8) in :attr:`SegmentResult.optimality`
        (:mod:`acroplan.core.optimal`). Each interval is optimised on its own, with its input
        conditions, one after the other (with ``conditions="free"`` an interval starts with the
        input the one before ended with); then, through interior waypoints with
        ``conditions="free"``, all the intervals together at the sizes their ladders reached
        (:mod:`acroplan.core.chain`: one SQP, the input continuous at the waypoints), kept when
        it succeeds and costs less; each segment's ``optimality["joint"]`` says what was done (on
        the bundled back full's torque optimum: 197.41 one after the other, 181.36 together;
        ``benchmarks/RESULTS.md``). Slower than the feasible plan (a few ms to tens of ms per
        interval). The strategies are :class:`acroplan.EnergyOptimal` and
        :class:`acroplan.TorqueOptimal`.
    tau_max : float, sequence, or dict by joint name, optional
        Torque limits :math:`|\tau_j(t)| \le \bar\tau_j` (one number for every joint, one per
        joint, or ``{joint: limit}``; joints not named are free), with the rate and joint limits;
        needs a torque model. Torque limits need the optimiser, so ``objective`` defaults to
        ``"energy"`` with them. The result's peak torque of each joint (refined between grid points)
        is checked: above :math:`\bar\tau_j(1 + 10^{-9})` the plan is ``not_converged``.
    capacity : dict, optional
        What the body can do, as a yardstick of the plan, not a limit of it: ``{"rates": {input:
        (top, source)}, "torques": {joint: (top, source)}}`` (rad/s and N m whatever ``degrees``;
        ``source`` a short citation). A success beyond it carries a warning
        (:attr:`PlanResult.warnings`, :func:`beyond_capacity`) with the peak and the yardstick. A
        human body read from a problem file brings its own (the hip rate and strength of
        ``families/human/data/limits.toml``: 12.8 rad/s, 351.4 N m for both hips; a 3-D human, each
        joint's strength, ``families/human/data/strength_3d.toml``).
    progress : bool, Progress or callable, optional
        Progress of the work, one ``tqdm.auto`` line per stage that lasts more than half a second
        (the waypoint intervals; within one, the strategy's guesses, path deformation, the optimal
        ladder's basis sizes; the independent check), refreshed at least every quarter second
        (:mod:`acroplan.core.progress`). ``None`` (default): shown in a notebook and when stderr is
        a terminal, not when the output goes to a file or a pipe (nor inside :func:`plan_many` and
        sweeps); ``True``/``False``: shown or not; a :class:`~acroplan.core.progress.Progress`
        (``Progress(record=True)`` keeps every update); a callable: called as ``progress(done,
        total)`` after each waypoint interval, nothing shown.

    Returns
    -------
    PlanResult

    Raises
    ------
    InvalidInputError
        For any invalid argument, naming it.

    Examples
    --------
    >>> import numpy as np, acroplan
    >>> robot = acroplan.examples.robot("pike-dive")
    >>> res = acroplan.plan(robot, times=[0, 2], theta=[-0.5 * np.pi, 0.9 * np.pi],
    ...                     phi=[-np.pi, -2 * np.pi])
    >>> res.status
    'success'
    """
    started = budget_clock()  # the time limit covers the family's preparation and the validation too
    outer = progress_mod.current()
    prog = progress_mod.resolve(progress)
    owned = prog is not outer and not isinstance(progress, progress_mod.Progress)
    try:
        with prog.active():
            # the stage "preparing the plan": the family's modules imported the first time (a body's
            # numerics: seconds on a cold start), the arguments validated
            with prog.scope("preparing the plan", unit="step"):
                prepare(system)  # its family's strategies, torque model and starts (core.family.prepare)
                req = PlanRequest.build(system, times=times, conditions=conditions, method=method, basis=basis,
                                        n_coefficients=n_coefficients, max_coefficients=max_coefficients,
                                        limits=limits, u_max=u_max, state_bounds=state_bounds,
                                        input_bounds=input_bounds, verify=verify, tol=tol,
                                        max_evaluations=max_evaluations, time_limit=time_limit,
                                        start_rate=start_rate, end_rate=end_rate, degrees=degrees,
                                        objective=objective, tau_max=tau_max, capacity=capacity, **waypoints)
            # what solve() does, its progress already active
            with budget(req.time_limit, start=started), one_blas_thread():
                return _solve(req, prog)
    finally:
        if owned:
            prog.close()


def solve(req: PlanRequest, *, progress=None, started: float | None = None) -> PlanResult:
    """Plan a validated :class:`PlanRequest` (what :func:`plan` does after validation), within its
    time budget, reporting to ``progress`` (:func:`acroplan.core.progress.resolve`). The budget
    runs from ``started`` (a reading of :func:`acroplan.core.budget.now`; default: now): :func:`plan`
    passes its own start, so that its time limit covers the family's preparation and the
    validation too."""
    outer = progress_mod.current()
    prog = progress_mod.resolve(progress)
    owned = prog is not outer and not isinstance(progress, progress_mod.Progress)
    with prog.active(), budget(req.time_limit, start=started), one_blas_thread():
        try:
            return _solve(req, prog)
        finally:
            if owned:
                prog.close()


def _solve(req: PlanRequest, prog) -> PlanResult:
    system, t, X = req.system, req.times, req.waypoints
    limits = req.limits if req.limits.active else None
    if req.free.any():
        X = _fill_free(system, t, X, req.free, limits)
    common = dict(system=system, times=t, waypoints=X, conditions=req.conditions, basis=req.basis, limits=limits,
                  objective=req.objective, torque_limits=req.torque_limits)
    refused = _infeasible(req, X, limits, common)
    if refused is not None:
        return refused
    conditions = Conditions(req.conditions, system, t, X, limits, req.start_rate, req.end_rate)
    proof = conditions.infeasible()
    if proof:
        return PlanResult(status=Status.INFEASIBLE, message="infeasible: " + proof["reason"], infeasible=(proof,),
                          **common)
    segments, failed = _plan_intervals(req, X, limits, conditions, prog)
    if failed is not None:
        return PlanResult(status=Status.NOT_CONVERGED, message=failed, segments=segments, **common)
    K = t.size - 1
    if not req.verify:
        worst_final = max(s.final_error for s in segments)
        return _plausible(_check_torque_limits(PlanResult(
            status=Status.SUCCESS, message=f"success: {K} segment(s), max endpoint error {worst_final:.2e} (not "
            f"independently verified)" + _optimality_note(segments, req), segments=segments, verified=False,
            **common), req), req)
    return _verified(req, X, segments, common)


def _infeasible(req: PlanRequest, X, limits, common) -> PlanResult | None:
    """The ``infeasible`` result when the system's exact test refuses a segment (every segment's
    proof in it), else ``None``."""
    system, t = req.system, req.times
    infeasible = []
    for k in range(t.size - 1):
        proof = system.check_segment(X[k], X[k + 1], t[k + 1] - t[k], limits)
        if proof is not None:
            infeasible.append({"index": k, "t0": float(t[k]), "t1": float(t[k + 1]), "field": proof.field,
                               "interval": list(proof.interval) if proof.interval else None,
                               "reason": proof.reason})
    if not infeasible:
        return None
    return PlanResult(status=Status.INFEASIBLE, message=infeasible_message(req, X, infeasible),
                      infeasible=tuple(infeasible), **common)


#: How many refused segments a message names (every one is in ``result.infeasible``): one, so
#: that the message stays a few hundred characters however many segments are refused.
MESSAGE_SEGMENTS = 1


def infeasible_message(req: PlanRequest, X, infeasible: list[dict]) -> str:
    """The message of an infeasible plan: how many segments are refused, the first
    :data:`MESSAGE_SEGMENTS` with their proofs (all in ``result.infeasible`` and ``solution.json``),
    and the degrees hint when the angles look like degrees (every waypoint angle within 360 in size,
    some beyond 2 pi, and whole numbers or halves: what a file in degrees holds)."""
    system = req.system
    shown = [f"segment {d['index']} [{d['t0']:g}, {d['t1']:g}]: {d['reason']}" for d in infeasible[:MESSAGE_SEGMENTS]]
    msg = "infeasible: " + "; ".join(shown)
    if len(infeasible) > MESSAGE_SEGMENTS:
        msg = (f"infeasible: {len(infeasible)} of {req.times.size - 1} segments (every one in result.infeasible, "
               f"solution.json); the first, " + "; ".join(shown))
    angles = [i for i, name in enumerate(system.state_names) if name in system.angle_states]
    if not req.degrees and angles and _look_like_degrees(X[:, angles]):
        msg += (f" (angles up to {np.max(np.abs(X[:, angles])):.4g} rad: if these are degrees, pass "
                "degrees=True, or degrees = true in [options])")
    return msg


def _look_like_degrees(values) -> bool:
    """Whether waypoint angles look like degrees: beyond 2 pi somewhere, none beyond 360 x 10 in
    size, and most of them whole or half degrees (radians of a real motion seldom are)."""
    v = np.abs(np.asarray(values, dtype=float)).ravel()
    v = v[np.isfinite(v)]
    if v.size == 0 or v.max() < 2 * np.pi or v.max() > 3600:
        return False
    whole = np.abs(2 * v - np.round(2 * v)) < 1e-9
    return bool(np.mean(whole) >= 0.5)


def _plan_intervals(req: PlanRequest, X, limits, conditions, prog):
    """Plan each waypoint interval by the request's strategy: ``(segments, None)``, or ``(segments
    so far, message)`` at the first interval that fails. Reports the stage ``"segments"`` (inside
    an interval, its strategy reports its own stages). With several intervals, free conditions and
    a strategy that optimises them together (its ``joint``), the intervals' optima are only that
    joint optimum's start (:attr:`~acroplan.core.strategies.Interval.provisional`: an optimal
    strategy leaves them unrefined); when the joint optimum is not kept, the intervals are planned
    again in full and the joint optimum tried from them, so that what is reported is either the
    joint optimum or the intervals' own, refined and checked."""
    system, t = req.system, req.times
    K = t.size - 1
    joint = getattr(req.strategy, "joint", None)
    joint_follows = joint is not None and K > 1 and conditions.kind == "free"
    segments, curvatures, failed = _sequential(req, X, limits, conditions, prog, joint_follows, joint_follows)
    if failed is not None or not joint_follows:
        return segments, failed
    # the whole plan's optimum through the interior waypoints, from the sequential one
    intervals = [Interval(system=system, basis=req.basis, sizes=req.sizes, x0=X[k], x1=X[k + 1],
                          T=float(t[k + 1] - t[k]), ends=conditions.ends(k, None), limits=limits, tol=req.tol,
                          max_evaluations=req.max_evaluations) for k in range(K)]
    try:
        with progress_mod.stage(JOINT_STAGE):
            out, _ = joint(intervals, segments, curvatures)
        if any((s.optimality or {}).get("provisional") for s in out):
            # not kept: the intervals' own optima, refined and checked, and the joint optimum from them
            segments, curvatures, failed = _sequential(req, X, limits, conditions, prog, True, False)
            if failed is not None:
                return segments, failed
            with progress_mod.stage(JOINT_STAGE):
                out, _ = joint(intervals, segments, curvatures)
    except BudgetExceeded as e:
        return tuple(segments), (f"not converged: every interval was optimised, but {e} while optimising them "
                                 f"together")
    return tuple(out), None


def _sequential(req: PlanRequest, X, limits, conditions, prog, joint: bool, provisional: bool):
    """The intervals planned one after the other (each from the input the one before ended with,
    under free conditions): ``(segments, curvatures, None)`` or ``(segments so far, curvatures,
    message)`` at the first that fails; ``joint``, ``provisional`` as
    :class:`~acroplan.core.strategies.Interval`'s."""
    system, t = req.system, req.times
    K = t.size - 1
    segments: list[SegmentResult] = []
    curvatures = []  # each interval's endpoint Hessians at its optimum (the joint optimum's start)
    prev_end_input = None
    with prog.scope("segments", K, unit="segment") as bar:
        for k in range(K):
            interval = Interval(system=system, basis=req.basis, sizes=req.sizes, x0=X[k], x1=X[k + 1],
                                T=float(t[k + 1] - t[k]), ends=conditions.ends(k, prev_end_input), limits=limits,
                                tol=req.tol, max_evaluations=req.max_evaluations, joint=joint,
                                provisional=provisional)
            try:
                out = req.strategy.solve(interval)
            except BudgetExceeded as e:
                out = IntervalOutcome(False, (), str(e))
            finally:
                progress_mod.close_notes(*progress_mod.INNER_STAGES)
            for i, piece in enumerate(out.pieces):
                t1 = float(t[k + 1]) if i == len(out.pieces) - 1 else piece.t1 + float(t[k])
                t0 = piece.t0 + float(t[k])
                if (piece.index, piece.interval, piece.t0, piece.t1) != (len(segments), k, t0, t1):
                    piece = dataclasses.replace(piece, index=len(segments), interval=k, t0=t0, t1=t1)
                segments.append(piece)
            curvatures.append(out.curvature)
            if not out.success:
                return tuple(segments), curvatures, (f"not converged: segment {k} [{t[k]:g}, {t[k + 1]:g}] from "
                                                     f"{_fmt(X[k], system)} to {_fmt(X[k + 1], system)}: {out.reason}")
            bar.update()
            if k + 1 < K:  # the input value the next interval starts with (free conditions)
                last = segments[-1]
                prev_end_input = last.input([last.t1])[:, 0]
    return tuple(segments), curvatures, None


def _verified(req: PlanRequest, X, segments, common) -> PlanResult:
    """The plan checked independently (:func:`~acroplan.core.verify.verify_plan`): ``success``, or
    ``not_converged`` naming the first segment the check misses."""
    system, K = req.system, req.times.size - 1
    check = check_name(system, req.verify)
    try:
        with progress_mod.stage("independent check", len(segments), unit="segment"):
            checked, bad, allowed = verify_plan(system, X[0], segments, req.verify)
    except BudgetExceeded as e:
        return PlanResult(status=Status.NOT_CONVERGED, message=f"not converged: every segment was planned, but "
                          f"{e} before the independent check ({check}) ended", segments=segments, verified=False,
                          **common)
    if bad is not None:
        return PlanResult(status=Status.NOT_CONVERGED, message=f"not converged: the independent check ({check}) "
                          f"misses the planned state at t = {bad.t1:g} by {bad.verified_error:.2e} > "
                          f"{allowed:.2g}", segments=checked, verified=True, verification=req.verify, **common)
    worst = max(s.verified_error for s in checked)
    result = PlanResult(status=Status.SUCCESS, message=f"success: {K} segment(s), max endpoint error "
                        f"{max(s.final_error for s in checked):.2e}, independently verified to {worst:.2e} "
                        f"({check})" + _optimality_note(checked, req), segments=checked, verified=True,
                        verification=req.verify, **common)
    return _plausible(_check_torque_limits(result, req), req)


def _optimality_note(segments, req) -> str:
    """What the success message says of an optimal plan: its cost, worst KKT residual, and whether
    every interval converged."""
    opt = [s.optimality for s in segments if s.optimality]
    if not req.objective or not opt:
        return ""
    cost = sum(d["cost"] or 0.0 for d in opt)
    kkt = max((d["kkt"] if d["kkt"] is not None else math.inf) for d in opt)
    bad = [s.interval for s in segments if s.optimality and not s.optimality["converged"]]
    what = "integral of |u|^2" if req.objective == "energy" else "integral of |tau|^2"
    joint = opt[0].get("joint")
    how = ""
    if joint is not None and joint.get("kept"):
        how = (f"; the intervals optimised together (from {joint['sequential_cost']:.10g} one after the other"
               + ("" if joint.get("sequential_checked", True) else ", their limits broken between the grid's points")
               + ")")
    elif joint is not None:
        how = f"; the intervals optimised one after the other (together: {joint['message']})"
    return (f"; {req.objective}-optimal: {what} = {cost:.10g}, largest relative KKT residual {kkt:.1e} (target "
            f"{opt[0]['kkt_tol']:g}), " + ("converged on every interval" if not bad else
                                            f"NOT converged on interval(s) {bad} (see each segment's optimality)")
            + how)


def _check_torque_limits(result: PlanResult, req) -> PlanResult:
    """``result``, or ``not_converged`` when a joint's peak torque (:meth:`PlanResult.effort`:
    refined between grid points) exceeds its limit by more than 1e-9 (relative)."""
    if not req.torque_limits or not result.success:
        return result
    try:
        effort = result.effort()
    except BudgetExceeded as e:
        return dataclasses.replace(result, status=Status.NOT_CONVERGED, message=f"not converged: every waypoint was "
                                   f"reached, but {e} before the peak torques were checked against tau_max")
    over = [(j, effort[j].peak_torque, top) for j, top in req.torque_limits.items()
            if effort[j].peak_torque > top * (1.0 + 1e-9)]
    if not over:
        return result
    j, peak, top = over[0]
    return dataclasses.replace(result, status=Status.NOT_CONVERGED, message=f"not converged: the peak torque of "
                               f"joint {j} is {peak:.10g} > tau_max = {top:g} (every waypoint reached)")


def _fill_free(system, t, X, free, limits):
    """Choose the free waypoint states, waypoint by waypoint (the system's
    :meth:`~ControlAffineSystem.fill_free`, from the linear interpolation of the given values)."""
    X = X.copy()
    for k in range(1, len(t) - 1):
        if not free[k].any():
            continue
        guess = X[k].copy()
        for i in np.flatnonzero(free[k]):
            nxt = next(j for j in range(k + 1, len(t)) if not free[j, i])
            w = (t[k] - t[k - 1]) / (t[nxt] - t[k - 1])
            guess[i] = X[k - 1, i] + w * (X[nxt, i] - X[k - 1, i])
        after = (X[k + 1], float(t[k + 1] - t[k])) if not free[k + 1].any() else None
        X[k] = system.fill_free(X[k - 1], X[k], guess, float(t[k] - t[k - 1]), limits, after=after)
    return X


def warm_up(system: ControlAffineSystem | type, *, basis: str = "legendre", sizes=(6, 10, 14)) -> None:
    """Compile the integrators :func:`plan` uses for ``system``, so that the first plan is warm.

    One compiled integrator serves every system of one structure (parameters, durations and
    coefficients are runtime values); this builds the ones for each basis size in ``sizes``
    (default: those ``method="auto"`` may use) in this process, or the family's own endpoint map
    when it has one (:meth:`~acroplan.core.system.ControlAffineSystem.prepare_endpoint_map`: a
    spatial body's compiled momentum map, one per topology, whatever the basis). Without it, each
    process compiles on first use.

    Parameters
    ----------
    system : ControlAffineSystem, or a class whose instances all share one structure and that can
        be built without arguments (``Unicycle``); for the acrobot pass an instance or
        ``acroplan.Acrobot`` (a representative instance is used).
    basis : {"legendre", "monomial"}
    sizes : iterable of int
    """
    if isinstance(system, type):
        if not issubclass(system, ControlAffineSystem):
            raise InvalidInputError("system", f"must be a ControlAffineSystem, got {system!r}",
                                    "use for example acroplan.Acrobot(...)")
        system = _representative(system)
    if not isinstance(system, ControlAffineSystem):
        raise InvalidInputError("system", f"must be a ControlAffineSystem, got {type(system).__name__}",
                                "use for example acroplan.Acrobot(...)")
    if system.prepare_endpoint_map():  # the family's own endpoint map (spatial bodies): no Taylor integrator
        return
    for n in sizes:
        backend.compile_for(system, type(make_basis(basis, int(n))), int(n))


def _representative(cls):
    example = getattr(cls, "example", None)
    if callable(example):
        return example()
    try:
        return cls()
    except TypeError:
        raise InvalidInputError("system", f"{cls.__name__} needs parameters to be built",
                                "pass an instance instead of the class") from None


def _fmt(x, system):
    return "(" + ", ".join(f"{n} = {v:.6g}" for n, v in zip(system.state_names, x)) + ")"
