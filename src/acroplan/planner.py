"""The front door for planning: :func:`plan`.

A plan passes through waypoints :math:`x_0, \\dots, x_K` at times :math:`t_0 < \\dots < t_K`.
Segment :math:`k` is solved by path deformation (:mod:`acroplan.continuation`), with input
conditions

* ``conditions="spline"`` (the text's scheme): for every rate input :math:`u = \\dot q`, the values
  and slopes of :math:`u` at both segment ends are those of the clamped cubic spline through
  :math:`(t_k, q_k)` (zero end slopes), so :math:`u` and :math:`u'` are continuous everywhere.
  With 6 coefficients the endpoint system is square; more coefficients are used minimum-norm.
* ``conditions="free"``: only the waypoint states are imposed; the inputs are continuous at interior
  waypoints (segment :math:`k` starts with the input value segment :math:`k-1` ended with).

Before any work, every segment is checked by the system's exact feasibility test
(:meth:`ControlAffineSystem.check_segment`); an impossible request is refused with the proof.
Every successful plan is re-simulated by scipy's DOP853 unless ``verify=False``.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.interpolate import CubicSpline

from ._errors import InvalidInputError
from .basis import make_basis
from .continuation import solve_segment
from .result import PlanResult, SegmentResult
from .systems.base import ControlAffineSystem
from .verify import simulate_segment

__all__ = ["plan", "CONDITIONS", "VERIFY_TOL"]

CONDITIONS = ("spline", "free")
#: Largest endpoint error of the independent re-simulation that a successful plan may have.
VERIFY_TOL = 1e-9


def _vector(field, value, length=None) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(field, "must be a list of numbers", "give for example [0, 2, 4]") from None
    if a.ndim != 1:
        raise InvalidInputError(field, f"must be a flat list of numbers, got shape {a.shape}",
                                "give one number per waypoint")
    if length is not None and a.size != length:
        raise InvalidInputError(field, f"has {a.size} value(s) but times has {length}",
                                "give one value per waypoint time")
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(field, "contains NaN or infinite values", "give finite numbers")
    return a


def plan(system: ControlAffineSystem, *, times, conditions: str = "spline", basis: str = "legendre",
         n_coefficients: int | None = None, verify: bool = True, tol: float = 1e-10,
         max_evaluations: int = 2000, **waypoints) -> PlanResult:
    """Plan a motion of ``system`` through waypoints.

    Parameters
    ----------
    system : ControlAffineSystem
        For example :class:`acroplan.Acrobot`.
    times : array_like, shape (K+1,)
        Strictly increasing waypoint times.
    **waypoints : array_like, shape (K+1,)
        One keyword per state, by the system's state names (``theta=..., phi=...`` for the
        acrobot). Every state must be given.
    conditions : {"spline", "free"}
        Input conditions (module docstring). ``"spline"`` needs every input to be the rate of a
        state (:attr:`ControlAffineSystem.rate_inputs`).
    basis : {"legendre", "monomial"}
        Internal basis of each segment's input (results are exported in the power basis).
    n_coefficients : int, optional
        Coefficients per input per segment; default 6 (the text's choice).
    verify : bool
        Re-simulate the plan with scipy DOP853 (rtol = atol = 1e-12) and require every waypoint
        within :data:`VERIFY_TOL`. Skip only for speed in batch work.
    tol : float
        Required endpoint error of each segment (compiled integrator).
    max_evaluations : int
        Evaluation budget per segment.

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
    if not isinstance(system, ControlAffineSystem):
        raise InvalidInputError("system", f"must be a ControlAffineSystem, got {type(system).__name__}",
                                "use for example acroplan.Acrobot(...)")
    unknown = sorted(set(waypoints) - set(system.state_names))
    if unknown:
        raise InvalidInputError(unknown[0], "is not an option of plan() nor a state of "
                                f"{type(system).__name__}",
                                f"states are {list(system.state_names)}")
    t = _vector("times", times)
    if t.size < 2:
        raise InvalidInputError("times", f"needs at least 2 values, got {t.size}", "give start and end times")
    if np.any(np.diff(t) <= 0):
        raise InvalidInputError("times", "must be strictly increasing", "sort the waypoints by time")
    missing = [name for name in system.state_names if name not in waypoints]
    if missing:
        raise InvalidInputError(missing[0], "is missing", f"give one value per waypoint for every state "
                                f"{list(system.state_names)}")
    X = np.stack([_vector(name, waypoints[name], t.size) for name in system.state_names], axis=1)
    if conditions not in CONDITIONS:
        raise InvalidInputError("conditions", f"must be one of {list(CONDITIONS)}, got {conditions!r}",
                                "use \"spline\" (the text's scheme) or \"free\"")
    if conditions == "spline" and set(system.rate_inputs) != set(system.input_names):
        raise InvalidInputError("conditions", f"\"spline\" needs every input to be the rate of a state, "
                                f"which {type(system).__name__} does not have", "use conditions=\"free\"")
    if n_coefficients is None:
        n_coefficients = 6
    if isinstance(n_coefficients, bool) or not isinstance(n_coefficients, (int, np.integer)) or n_coefficients < 1:
        raise InvalidInputError("n_coefficients", f"must be a whole number >= 1, got {n_coefficients!r}",
                                "give for example 6")
    b = make_basis(basis, int(n_coefficients))
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise InvalidInputError("tol", f"must be a positive number, got {tol!r}", "give for example 1e-10")
    if isinstance(max_evaluations, bool) or not isinstance(max_evaluations, (int, np.integer)) or max_evaluations < 1:
        raise InvalidInputError("max_evaluations", f"must be a whole number >= 1, got {max_evaluations!r}",
                                "give for example 2000")
    if not isinstance(verify, bool):
        raise InvalidInputError("verify", f"must be True or False, got {verify!r}", "give a boolean")

    common = dict(system=system, times=t, waypoints=X, conditions=conditions, basis=b)
    K = t.size - 1

    # ---------------------------------------------------------------- exact feasibility, all segments
    infeasible = []
    for k in range(K):
        proof = system.check_segment(X[k], X[k + 1], t[k + 1] - t[k])
        if proof is not None:
            infeasible.append({"index": k, "t0": float(t[k]), "t1": float(t[k + 1]), "field": proof.field,
                               "interval": list(proof.interval) if proof.interval else None,
                               "reason": proof.reason})
    if infeasible:
        msg = "; ".join(f"segment {d['index']} [{d['t0']:g}, {d['t1']:g}]: {d['reason']}" for d in infeasible)
        return PlanResult("infeasible", "infeasible: " + msg, infeasible=tuple(infeasible), **common)

    # ---------------------------------------------------------------- input conditions
    m = system.n_inputs
    cond_rows = []  # per segment: (B, d)
    if conditions == "spline":
        splines = [CubicSpline(t, X[:, system.state_names.index(system.rate_inputs[name])], bc_type="clamped")
                   for name in system.input_names]
    segments = []
    prev_end_input = None
    for k in range(K):
        T = float(t[k + 1] - t[k])
        B, d = _conditions(b, m, T, k, conditions, splines if conditions == "spline" else None, t,
                           prev_end_input)
        cond_rows.append((B, d))
        out = solve_segment(system, b, X[k], X[k + 1], T, B=B, d=d, tol=tol, max_evaluations=max_evaluations)
        seg = SegmentResult(
            index=k, t0=float(t[k]), t1=float(t[k + 1]), coefficients=b.to_power(out.coefficients, T),
            basis_coefficients=out.coefficients, start=X[k].copy(), target=X[k + 1].copy(),
            final_error=out.final_error, verified_error=None, iterations=out.iterations,
            evaluations=out.evaluations, restarts=out.restarts, sigma_min=out.sigma_min, success=out.success,
            message=out.message, history=out.history)
        segments.append(seg)
        if not out.success:
            msg = (f"not converged: segment {k} [{t[k]:g}, {t[k + 1]:g}] from {_fmt(X[k], system)} to "
                   f"{_fmt(X[k + 1], system)}: {out.message}")
            return PlanResult("not_converged", msg, segments=tuple(segments), **common)
        prev_end_input = b.matrix([1.0]) @ out.coefficients.T  # shape (1, m)

    if not verify:
        return PlanResult("success", f"success: {K} segment(s), max endpoint error "
                          f"{max(s.final_error for s in segments):.2e} (not independently verified)",
                          segments=tuple(segments), verified=False, **common)

    # ---------------------------------------------------------------- independent check
    checked = []
    x = X[0].copy()
    for seg in segments:
        sol = simulate_segment(system, x, seg.t0, seg.t1, seg.coefficients)
        x = sol.y[:, -1]
        err = float(np.linalg.norm(x - seg.target)) if sol.success else float("inf")
        checked.append(_replace(seg, verified_error=err))
    worst = max(s.verified_error for s in checked)
    if not worst <= VERIFY_TOL:
        bad = max(checked, key=lambda s: s.verified_error)
        return PlanResult("not_converged", f"not converged: the independent re-simulation (scipy DOP853) misses "
                          f"the waypoint at t = {bad.t1:g} by {bad.verified_error:.2e} > {VERIFY_TOL:g}",
                          segments=tuple(checked), verified=True, **common)
    return PlanResult("success", f"success: {K} segment(s), max endpoint error "
                      f"{max(s.final_error for s in checked):.2e}, independently verified to {worst:.2e}",
                      segments=tuple(checked), verified=True, **common)


def _replace(seg, **changes):
    import dataclasses

    return dataclasses.replace(seg, **changes)


def _fmt(x, system):
    return "(" + ", ".join(f"{n} = {v:.6g}" for n, v in zip(system.state_names, x)) + ")"


def _conditions(b, m, T, k, conditions, splines, t, prev_end_input):
    """Linear input conditions ``B c = d`` for segment ``k`` (flattened input-major ``c``)."""
    n = b.n
    rows, rhs = [], []
    if conditions == "spline":
        V = b.matrix([0.0, 1.0], 0)
        D = b.matrix([0.0, 1.0], 1) / T
        for j, sp_ in enumerate(splines):
            ends = np.array([t[k], t[k + 1]])
            vals, slopes = sp_(ends, 1), sp_(ends, 2)
            for row, val in ((V[0], vals[0]), (D[0], slopes[0]), (V[1], vals[1]), (D[1], slopes[1])):
                r = np.zeros(m * n)
                r[j * n:(j + 1) * n] = row
                rows.append(r)
                rhs.append(val)
    elif prev_end_input is not None:
        V0 = b.matrix([0.0], 0)[0]
        for j in range(m):
            r = np.zeros(m * n)
            r[j * n:(j + 1) * n] = V0
            rows.append(r)
            rhs.append(float(prev_end_input[0, j]))
    if not rows:
        return None, None
    return np.array(rows), np.array(rhs)
