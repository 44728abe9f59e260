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

Methods (per waypoint interval):

* ``"deform"``: the text's path deformation (:mod:`acroplan.continuation`), then, when joint or rate
  limits are given and broken, a constrained solve (:mod:`acroplan.constrained`);
* ``"flat"`` (acrobot): the flat-output planner (:mod:`acroplan.flat`): three pieces, move, dwell,
  move, exact up to a scalar root;
* ``"auto"`` (default): path deformation started from a flat-output guess that already meets the
  target (:func:`acroplan.flat.flat_guess`), at the smallest of :data:`AUTO_SIZES` whose guess
  brackets it, gentle guesses at every size before steep ones, so that deformation only polishes
  (one or two endpoint evaluations); then path deformation with the first size from the closest
  guess (budget :data:`AUTO_BUDGET` evaluations), the flat-output planner, and the remaining sizes
  (only the given size when ``n_coefficients`` is given).

Before any work, every segment is checked by the system's exact feasibility test
(:meth:`ControlAffineSystem.check_segment`, with the limits); an impossible request is refused
with the proof. Every result is checked for compliance with the limits exactly (polynomial
extremes), and every successful plan is re-simulated by scipy's DOP853 unless ``verify=False``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.interpolate import CubicSpline

from ._errors import InvalidInputError
from . import _integrate
from .basis import from_power, make_basis
from .constrained import COMPLIANCE_TOL, solve_with_limits, violation
from .continuation import solve_segment
from .reach import Limits
from .result import PlanResult, SegmentResult
from .systems.base import ControlAffineSystem
from .verify import simulate_segment

__all__ = ["plan", "warm_up", "CONDITIONS", "METHODS", "VERIFY_TOL"]

CONDITIONS = ("spline", "free")
METHODS = ("auto", "deform", "flat")
#: basis sizes tried by method="auto" when n_coefficients is not given
AUTO_SIZES = (6, 10, 14)
#: evaluation budget per basis size under method="auto"
AUTO_BUDGET = 100
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
    if not np.isfinite(a).all():
        raise InvalidInputError(field, "contains NaN or infinite values", "give finite numbers")
    return a


def plan(system: ControlAffineSystem, *, times, conditions: str = "spline", method: str = "auto",
         basis: str = "legendre", n_coefficients: int | None = None, u_max: float | None = None,
         phi_min: float | None = None, phi_max: float | None = None, verify: bool = True, tol: float = 1e-10,
         max_evaluations: int = 2000, progress=None, **waypoints) -> PlanResult:
    r"""Plan a motion of ``system`` through waypoints.

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
    method : {"auto", "deform", "flat"}
        How each waypoint interval is planned (module docstring).
    basis : {"legendre", "monomial"}
        Internal basis of each segment's input (results are exported in the power basis).
    n_coefficients : int, optional
        Coefficients per input per segment. Default: 6 (the text's choice), raised to 10 and 14 by
        ``method="auto"`` when a segment stalls.
    u_max : float, optional
        Rate limit: :math:`|u| \le u_{max}` for every input (> 0).
    phi_min, phi_max : float, optional
        Joint limits on ``phi`` (systems with a state ``phi`` whose rate is an input).
    verify : bool
        Re-simulate the plan with scipy DOP853 (rtol = atol = 3e-14) and require every waypoint
        within :data:`VERIFY_TOL`. Skip only for speed in batch work.
    tol : float
        Required endpoint error of each segment (compiled integrator).
    max_evaluations : int
        Evaluation budget per segment and basis size.
    progress : callable, optional
        Called as ``progress(done, total)`` after each waypoint interval (for a progress bar).

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
    v = _validated(system, times=times, conditions=conditions, method=method, basis=basis,
                   n_coefficients=n_coefficients, u_max=u_max, phi_min=phi_min, phi_max=phi_max, verify=verify,
                   tol=tol, max_evaluations=max_evaluations, waypoints=waypoints)
    t, X, b, sizes, limits = v["t"], v["X"], v["b"], v["sizes"], v["limits"]
    common = dict(system=system, times=t, waypoints=X, conditions=conditions, basis=b,
                  limits=limits if limits.active else None)
    K = t.size - 1

    # ---------------------------------------------------------------- exact feasibility, all segments
    infeasible = []
    for k in range(K):
        proof = system.check_segment(X[k], X[k + 1], t[k + 1] - t[k], limits if limits.active else None)
        if proof is not None:
            infeasible.append({"index": k, "t0": float(t[k]), "t1": float(t[k + 1]), "field": proof.field,
                               "interval": list(proof.interval) if proof.interval else None,
                               "reason": proof.reason})
    if infeasible:
        msg = "; ".join(f"segment {d['index']} [{d['t0']:g}, {d['t1']:g}]: {d['reason']}" for d in infeasible)
        return PlanResult("infeasible", "infeasible: " + msg, infeasible=tuple(infeasible), **common)

    # ---------------------------------------------------------------- plan each waypoint interval
    m = system.n_inputs
    splines = None
    if conditions == "spline":
        splines = [CubicSpline(t, X[:, system.state_names.index(system.rate_inputs[name])], bc_type="clamped")
                   for name in system.input_names]
        proof = _spline_against_limits(system, splines, t, X, limits)
        if proof:
            return PlanResult("infeasible", "infeasible: " + proof["reason"], infeasible=(proof,), **common)
    segments: list[SegmentResult] = []
    prev_end_input = None
    for k in range(K):
        T = float(t[k + 1] - t[k])
        ends = _end_values(m, k, conditions, splines, t, prev_end_input)
        if conditions == "free" and limits.active and _at_limit(system, X[k + 1], limits) and k + 1 < K:
            # an interior waypoint on a joint limit: the joint must arrive there at rest, else the
            # continuous input carries it out of the limits in the next interval
            ends = {**ends, "uT": np.zeros(m)}
        pieces, ok, why = _solve_interval(system, b, sizes, X[k], X[k + 1], T, ends, limits, method, tol,
                                          max_evaluations)
        for i, piece in enumerate(pieces):
            t1 = float(t[k + 1]) if i == len(pieces) - 1 else piece.t1 + float(t[k])
            t0 = piece.t0 + float(t[k])
            if (piece.index, piece.interval, piece.t0, piece.t1) != (len(segments), k, t0, t1):
                piece = dataclasses.replace(piece, index=len(segments), interval=k, t0=t0, t1=t1)
            segments.append(piece)
        if not ok:
            msg = (f"not converged: segment {k} [{t[k]:g}, {t[k + 1]:g}] from {_fmt(X[k], system)} to "
                   f"{_fmt(X[k + 1], system)}: {why}")
            return PlanResult("not_converged", msg, segments=tuple(segments), **common)
        if progress is not None:
            progress(k + 1, K)
        if k + 1 < K:  # the input value the next interval starts with (free conditions)
            last = segments[-1]
            prev_end_input = last.input([last.t1])[:, 0]
    segments = tuple(segments)

    if not verify:
        return PlanResult("success", f"success: {K} segment(s), max endpoint error "
                          f"{max(s.final_error for s in segments):.2e} (not independently verified)",
                          segments=tuple(segments), verified=False, **common)

    # ---------------------------------------------------------------- independent check
    checked = []
    x = X[0].copy()
    for seg in segments:
        sol = simulate_segment(system, x, seg.t0, seg.t1, seg._input_scalar)
        x = sol.y[:, -1]
        err = float(np.linalg.norm(x - seg.target)) if sol.success else float("inf")
        checked.append(dataclasses.replace(seg, verified_error=err))
    worst = max(s.verified_error for s in checked)
    if not worst <= VERIFY_TOL:
        bad = max(checked, key=lambda s: s.verified_error)
        return PlanResult("not_converged", f"not converged: the independent re-simulation (scipy DOP853) misses "
                          f"the planned state at t = {bad.t1:g} by {bad.verified_error:.2e} > {VERIFY_TOL:g}",
                          segments=tuple(checked), verified=True, **common)
    return PlanResult("success", f"success: {K} segment(s), max endpoint error "
                      f"{max(s.final_error for s in checked):.2e}, independently verified to {worst:.2e}",
                      segments=tuple(checked), verified=True, **common)


def warm_up(system: ControlAffineSystem | type, *, basis: str = "legendre", sizes=AUTO_SIZES) -> None:
    """Compile the integrators :func:`plan` uses for ``system``, so that the first plan is warm.

    One compiled integrator serves every instance of a system class (parameters, durations and
    coefficients are runtime values); this builds the ones for each basis size in ``sizes``
    (default: those ``method="auto"`` may use). :func:`plan_many` calls it before starting worker
    processes, which then inherit the compiled code.

    Parameters
    ----------
    system : ControlAffineSystem or its class
    basis : {"legendre", "monomial"}
    sizes : iterable of int
    """
    cls = system if isinstance(system, type) else type(system)
    if not (isinstance(cls, type) and issubclass(cls, ControlAffineSystem)):
        raise InvalidInputError("system", f"must be a ControlAffineSystem, got {cls!r}",
                                "use for example acroplan.Acrobot(...)")
    for n in sizes:
        _integrate._compiled(cls, type(make_basis(basis, int(n))), int(n))


def _at_limit(system, x, limits, tol=1e-12):
    if limits.phi_min is None and limits.phi_max is None:
        return False
    q = float(x[system.state_names.index(limits.state)])
    return abs(q - limits.lo) <= tol * max(1.0, abs(q)) or abs(q - limits.hi) <= tol * max(1.0, abs(q))


def _spline_against_limits(system, splines, t, X, limits):
    """Spline conditions fix u at every waypoint; prove when that breaks the limits."""
    if not limits.active:
        return None
    for name, sp_ in zip(system.input_names, splines):
        for k, tk in enumerate(t):
            u = float(sp_(tk, 1))
            if limits.u_max is not None and abs(u) > limits.u_max:
                return {"index": k, "t0": float(tk), "t1": float(tk), "field": name, "interval": None,
                        "reason": f"conditions=\"spline\" sets {name}(t = {tk:g}) = {u:.6g}, beyond u_max = "
                                  f"{limits.u_max:g}; use conditions=\"free\" or a larger u_max"}
            if system.rate_inputs.get(name) == limits.state and _at_limit(system, X[k], limits) and abs(u) > 1e-12:
                q = X[k, system.state_names.index(limits.state)]
                return {"index": k, "t0": float(tk), "t1": float(tk), "field": limits.state, "interval": None,
                        "reason": f"conditions=\"spline\" sets {name}(t = {tk:g}) = {u:.6g} at the waypoint where "
                                  f"{limits.state} = {q:.12g} is on its joint limit, so the joint leaves the limits "
                                  f"on one side; use conditions=\"free\""}
    return None


def _validated(system, *, times, conditions, method, basis, n_coefficients, u_max, phi_min, phi_max, verify, tol,
               max_evaluations, waypoints) -> dict:
    """All of plan()'s input checks; returns the normalised inputs. Raises InvalidInputError."""
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
    tl = t.tolist()
    if any(b <= a for a, b in zip(tl, tl[1:])):
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
    if method not in METHODS:
        raise InvalidInputError("method", f"must be one of {list(METHODS)}, got {method!r}",
                                "use \"auto\", \"deform\" (the text's) or \"flat\"")
    if method == "flat" and not hasattr(system, "F"):
        raise InvalidInputError("method", f"\"flat\" needs a flat output, which {type(system).__name__} does not "
                                "provide", "use method=\"deform\"")
    sizes = AUTO_SIZES if (n_coefficients is None and method == "auto") else None
    if n_coefficients is None:
        n_coefficients = AUTO_SIZES[0]
    if isinstance(n_coefficients, bool) or not isinstance(n_coefficients, (int, np.integer)) or n_coefficients < 1:
        raise InvalidInputError("n_coefficients", f"must be a whole number >= 1, got {n_coefficients!r}",
                                "give for example 6")
    sizes = sizes or (int(n_coefficients),)
    b = make_basis(basis, int(n_coefficients))
    if not (isinstance(tol, (int, float)) and math.isfinite(tol) and tol > 0):
        raise InvalidInputError("tol", f"must be a positive number, got {tol!r}", "give for example 1e-10")
    if isinstance(max_evaluations, bool) or not isinstance(max_evaluations, (int, np.integer)) or max_evaluations < 1:
        raise InvalidInputError("max_evaluations", f"must be a whole number >= 1, got {max_evaluations!r}",
                                "give for example 2000")
    if not isinstance(verify, bool):
        raise InvalidInputError("verify", f"must be True or False, got {verify!r}", "give a boolean")
    limits = Limits(phi_min=phi_min, phi_max=phi_max, u_max=u_max)
    if (phi_min is not None or phi_max is not None):
        if "phi" not in system.state_names or "phi" not in system.rate_inputs.values():
            raise InvalidInputError("phi_min", f"joint limits need a state phi whose rate is an input, which "
                                    f"{type(system).__name__} does not have", "leave phi_min and phi_max out")
        i = system.state_names.index("phi")
        for k, v in enumerate(X[:, i]):
            if not limits.lo <= v <= limits.hi:
                raise InvalidInputError("phi", f"waypoint {k} (t = {t[k]:g}) has phi = {v:.12g}, outside the joint "
                                        f"limits [{limits.lo:.12g}, {limits.hi:.12g}]",
                                        "move the waypoint inside the limits or widen them")
    return dict(t=t, X=X, b=b, sizes=sizes, limits=limits)


def _fmt(x, system):
    return "(" + ", ".join(f"{n} = {v:.6g}" for n, v in zip(system.state_names, x)) + ")"


def _end_values(m, k, conditions, splines, t, prev_end_input):
    """Input conditions of interval ``k`` as values: dict of arrays (m,) for u0, du0, uT, duT."""
    if conditions == "spline":
        ends = np.array([t[k], t[k + 1]])
        vals = np.array([sp_(ends, 1) for sp_ in splines])
        slopes = np.array([sp_(ends, 2) for sp_ in splines])
        return {"u0": vals[:, 0], "du0": slopes[:, 0], "uT": vals[:, 1], "duT": slopes[:, 1]}
    if prev_end_input is not None:
        return {"u0": np.asarray(prev_end_input, dtype=float)}
    return {}


def _linear_conditions(b, m, T, ends):
    """``B c = d`` for the end values (flattened input-major ``c``)."""
    if not ends:
        return None, None
    n = b.n
    rows, rhs = [], []
    V = b.matrix([0.0, 1.0], 0)
    D = b.matrix([0.0, 1.0], 1) / T
    which = {"u0": V[0], "du0": D[0], "uT": V[1], "duT": D[1]}
    for key in ("u0", "du0", "uT", "duT"):
        if key not in ends:
            continue
        for j in range(m):
            r = np.zeros(m * n)
            r[j * n:(j + 1) * n] = which[key]
            rows.append(r)
            rhs.append(float(ends[key][j]))
    if not rows:
        return None, None
    return np.array(rows), np.array(rhs)


def _segment(system, basis, x0, x1, T, c, *, t0, final_error, verified_error=None, iterations=0, evaluations=0,
             restarts=0, sigma_min=float("nan"), success=True, message="", history=(), method="deform", limits=None,
             checked=None):
    """A SegmentResult; ``checked``: :func:`_limit_check` of ``c`` when already computed."""
    if checked is None:
        checked = _limit_check(system, basis, x0, T, c, limits)
    ext = None if checked is None else {"max_abs_u": checked["max_abs_u"], "state_range": checked["state_range"]}
    return SegmentResult(
        index=0, t0=float(t0), t1=float(t0 + T), coefficients=basis.to_power(c, T), basis_coefficients=c,
        start=x0, target=x1, final_error=final_error,
        verified_error=verified_error, iterations=iterations, evaluations=evaluations, restarts=restarts,
        sigma_min=sigma_min, success=success, message=message, history=history, method=method,
        extremes=ext, basis=basis)


def _limit_check(system, basis, x0, T, c, limits):
    """:func:`acroplan.constrained.violation` when limits are given, else None."""
    return violation(system, basis, x0, T, c, limits) if limits is not None and limits.active else None


def _compliant(checked) -> bool:
    return checked is None or (checked["u"] <= COMPLIANCE_TOL and checked["state"] <= COMPLIANCE_TOL)


def _solve_interval(system, b, sizes, x0, x1, T, ends, limits, method, tol, max_evaluations):
    """Plan one waypoint interval. Returns (pieces, ok, reason); pieces have t0 relative to 0."""
    m = system.n_inputs
    scalar_ends = {key: float(v[0]) for key, v in ends.items()}  # the acrobot's one input (flat output)
    reasons = []
    last_failed = None
    spent = [0]  # evaluations of the stages that did not succeed, charged to the result

    def charge(pieces):
        if spent[0] and pieces:
            pieces = [dataclasses.replace(pieces[0], evaluations=pieces[0].evaluations + spent[0])] + pieces[1:]
        return pieces

    def deform(n):
        nonlocal last_failed
        bn = type(b)(n)
        B, d = _linear_conditions(bn, m, T, ends)
        guess = None
        if method == "auto":
            g = guess_for(n, False)
            guess = g if g is not None and g.bracketed else guess_for(n)
            guess = None if guess is None else guess.coefficients
        # auto keeps a small budget per size: a continuation that needs hundreds of steps is
        # better replaced by the next stage than finished (measured: benchmarks/RESULTS.md)
        budget = min(max_evaluations, AUTO_BUDGET) if method == "auto" else max_evaluations
        out = solve_segment(system, bn, x0, x1, T, B=B, d=d, tol=tol, max_evaluations=budget, initial=guess)
        info = dict(iterations=out.iterations, evaluations=out.evaluations, restarts=out.restarts,
                    sigma_min=out.sigma_min, history=out.history)
        checked = _limit_check(system, bn, x0, T, out.coefficients, limits) if out.success else None
        if out.success and _compliant(checked):
            return charge([_segment(system, bn, x0, x1, T, out.coefficients, t0=0.0, final_error=out.final_error,
                                    message=out.message, limits=limits, checked=checked, **info)])
        if out.success:
            ok, c, err, ev, msg = solve_with_limits(system, bn, x0, x1, T, limits, out.coefficients, B=B, d=d,
                                                    tol=tol)
            info["evaluations"] += ev
            piece = _segment(system, bn, x0, x1, T, c, t0=0.0, final_error=err, success=ok, message=msg,
                             method="deform+limits", limits=limits, **info)
            if ok:
                return charge([piece])
            spent[0] += info["evaluations"]
            reasons.append(f"{n} coefficients: path deformation converged but broke the limits, and {msg}")
            last_failed = piece
        else:
            spent[0] += info["evaluations"]
            reasons.append(f"{n} coefficients: {out.message}")
            last_failed = _segment(system, bn, x0, x1, T, out.coefficients, t0=0.0, final_error=out.final_error,
                                   success=False, message=out.message, limits=limits, **info)
        return None

    def flat():
        nonlocal last_failed
        from .flat import flat_pieces

        pieces, msg = flat_pieces(system, x0, x1, T, ends=scalar_ends, limits=limits if limits.active else None)
        if pieces is None:
            reasons.append(msg)
            return None
        out, x, t0 = [], np.array(x0, dtype=float), 0.0
        for i, (D, coef) in enumerate(pieces):
            nb = type(b)(max(len(coef), 1))
            c = from_power(type(b), np.pad(coef, (0, nb.n - len(coef))), D)[None, :]
            y, _ = _integrate.endpoint(system, nb, x, D, c)
            end = np.array(x1, dtype=float) if i == len(pieces) - 1 else y
            out.append(_segment(system, nb, x, end, D, c, t0=t0, final_error=float(np.linalg.norm(y - end)),
                                message=msg, method="flat", limits=limits))
            x, t0 = end, t0 + D
        if out[-1].final_error <= tol:
            return charge(out)
        reasons.append(f"flat output: endpoint error {out[-1].final_error:.2e} > tol")
        last_failed = out[-1]
        return None

    has_flat = hasattr(system, "F")
    guesses = {}

    def guess_for(n, steep=True):
        if not has_flat:
            return None
        if (n, steep) not in guesses:
            from .flat import flat_guess

            guesses[n, steep] = flat_guess(system, type(b)(n), x0, x1, T, scalar_ends, steep=steep)
        return guesses[n, steep]

    if method == "deform":
        stages = [lambda n=n: deform(n) for n in sizes]
    elif method == "flat":
        stages = [flat]
    else:
        # auto: the smallest size whose flat-output guess meets the target (deformation then only
        # polishes), gentle guesses at every size before steep ones; then the first size from its
        # closest guess, the flat output (exact), and the remaining sizes
        first = next((n for steep in (False, True) for n in sizes
                      if (g := guess_for(n, steep)) is not None and g.bracketed), None)
        order = ([first] if first is not None else []) + [n for n in sizes if n != first]
        stages = [lambda: deform(order[0])] + ([flat] if has_flat else []) + [lambda n=n: deform(n)
                                                                               for n in order[1:]]
    for stage in stages:
        pieces = stage()
        if pieces is not None:
            return pieces, True, ""
    return ([last_failed] if last_failed is not None else []), False, "; ".join(reasons)
