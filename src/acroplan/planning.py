"""The front door for planning: :func:`plan`.

A plan passes through waypoints :math:`x_0, \\dots, x_K` at times :math:`t_0 < \\dots < t_K`. The
work is shared out as follows, and this module names no body:

1. validation (:class:`PlanRequest`): every argument checked at the boundary, messages naming the
   field and the fix;
2. exact feasibility: the system's own test (:meth:`ControlAffineSystem.check_segment`, with the
   limits) refuses an impossible request with its proof; spline conditions that break the limits
   are refused too (:class:`~acroplan.core.conditions.Conditions`);
3. each waypoint interval is planned by a strategy (:mod:`acroplan.core.strategies`): a registered
   name, an object, or ``"auto"``, the system's own choice; with ``objective=`` (or ``tau_max=``)
   by an optimal strategy (:mod:`acroplan.core.optimal`) that starts from ``method``'s plan;
4. every result is checked for compliance with the limits exactly (torque limits on the refined
   peak of each joint's torque), and every successful plan is re-simulated independently
   (:mod:`acroplan.core.verify`) unless ``verify=False``.
"""

from __future__ import annotations

import dataclasses
import difflib
import math

import numpy as np

from .core import backend
from .core.basis import InputBasis, make_basis
from .core.conditions import CONDITIONS, Conditions, check_conditions
from .core.errors import InvalidInputError
from .core.family import family_of
from .core.keywords import PLAN_KEYWORDS
from .core.limits import Limits
from .core import progress as progress_mod
from .core.family import prepare
from .core.optimal import OBJECTIVES, EnergyOptimal, tau_vector, objective_strategy
from .core.result import PlanResult, SegmentResult, Status
from .core.budget import BudgetExceeded, budget
from .core.strategies import STRATEGIES, Interval, IntervalOutcome, Strategy, resolve_strategy
from .core.system import ControlAffineSystem, torque_model_of
from .core.verify import VERIFY_TOL, check_name, resolve_verify, verify_plan

__all__ = ["plan", "warm_up", "PlanRequest", "CONDITIONS", "VERIFY_TOL", "DEFAULT_SIZE", "MAX_COEFFICIENTS",
           "TIME_LIMIT"]

#: Coefficients per input per segment when neither ``n_coefficients`` nor the strategy says.
DEFAULT_SIZE = 6
#: The largest ``n_coefficients``: more costs compile time and memory for no accuracy (the
#: Legendre basis at 14 already reaches every target the planner meets).
MAX_COEFFICIENTS = 30
#: The default wall-clock budget of one plan, in seconds.
TIME_LIMIT = 60.0
#: Segment durations and times the arithmetic carries (the power-basis export takes T**(n-1)).
MIN_DURATION, MAX_DURATION, MAX_TIME = 1e-6, 1e6, 1e12


#: plan()'s own keywords, for suggestions when one is mistyped (the one table, acroplan.core.keywords)
_OPTIONS = PLAN_KEYWORDS


def _waypoints(field, value, length) -> np.ndarray:
    """A state's waypoint values; ``None`` (free: any value will do) allowed at interior waypoints,
    returned as NaN."""
    if isinstance(value, (list, tuple)) and any(v is None for v in value):
        if len(value) != length:
            raise InvalidInputError(field, f"has {len(value)} value(s) but times has {length}",
                                    "give one value per waypoint time")
        if value[0] is None or value[-1] is None:
            raise InvalidInputError(field, "is free (None) at the first or the last waypoint",
                                    "give the start and the end; only interior waypoints may be free")
        given = _vector(field, [v for v in value if v is not None])
        out = np.full(length, np.nan)
        out[[i for i, v in enumerate(value) if v is not None]] = given
        return out
    return _vector(field, value, length)


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


def _whole(field, value, example, most: int | None = None) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InvalidInputError(field, f"must be a whole number >= 1, got {_short(value)}", f"give for example {example}")
    if most is not None and value > most:
        raise InvalidInputError(field, f"must be at most {most}, got {value}", f"give for example {example}")
    return int(value)


def _deg(field, value, is_angle: bool) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InvalidInputError(field, f"must be a number, got {_short(value)}", "give a number") from None
    return math.radians(v) if is_angle else v


def _short(value) -> str:
    r = repr(value) if not isinstance(value, (int, np.integer)) or abs(int(value)) < 10**30 else "a huge integer"
    return r if len(r) <= 80 else r[:77] + "..."


@dataclasses.dataclass(frozen=True)
class PlanRequest:
    """A validated call of :func:`plan`: build it with :meth:`build`, which checks every argument.

    Attributes
    ----------
    system : ControlAffineSystem
    times : numpy.ndarray, shape (K+1,)
    waypoints : numpy.ndarray, shape (K+1, n)
        NaN where a state is free.
    free : numpy.ndarray of bool, shape (K+1, n)
        Which waypoint states are free (``None`` in the call).
    conditions : str
    strategy : Strategy
    basis : InputBasis
        The basis family, at the first size used.
    sizes : tuple of int or None
        The user's ``n_coefficients``, or ``None`` (the strategy chooses).
    limits : Limits
    verify : {"family", "ode"} or None
        How the plan is checked (``None``: not checked).
    tol : float
    max_evaluations : int
    time_limit : float or None
    start_rate, end_rate : numpy.ndarray, shape (m,), or None
    degrees : bool
        Whether the caller gave angles in degrees (already converted: every array here is in radians).
    objective : {"energy", "torque"} or None
        What the plan minimises (``None``: a feasible plan). Also set when ``method`` is itself an
        optimal strategy (``"energy-optimal"``).
    torque_limits : dict or None
        ``{joint: tau_max}`` for every limited joint (``tau_max=``, validated against the torque
        model's joints).
    """

    system: ControlAffineSystem
    times: np.ndarray
    waypoints: np.ndarray
    free: np.ndarray
    conditions: str
    strategy: Strategy
    basis: InputBasis
    sizes: tuple[int, ...] | None
    limits: Limits
    verify: str | None
    tol: float
    max_evaluations: int
    time_limit: float | None = TIME_LIMIT
    start_rate: np.ndarray | None = None
    end_rate: np.ndarray | None = None
    degrees: bool = False
    objective: str | None = None
    torque_limits: dict | None = None

    @classmethod
    def build(cls, system, *, times, conditions: str | None = None, method="auto", basis="legendre",
              n_coefficients: int | None = None, limits: Limits | None = None, u_max: float | None = None,
              state_bounds=None, input_bounds=None, verify: bool | str = True, tol: float = 1e-10,
              max_evaluations: int = 2000, time_limit: float | None = TIME_LIMIT, start_rate=None,
              end_rate=None, degrees: bool = False, objective: str | None = None, tau_max=None,
              **named) -> "PlanRequest":
        """Validate :func:`plan`'s arguments (same keywords). Raises :class:`InvalidInputError`."""
        if not isinstance(system, ControlAffineSystem):
            raise InvalidInputError("system", f"must be a ControlAffineSystem, got {type(system).__name__}",
                                    "use for example acroplan.Acrobot(...)")
        waypoints, shorthand = _split_named(system, named)
        t = _times(times)
        if not isinstance(degrees, bool):
            raise InvalidInputError("degrees", f"must be True or False, got {_short(degrees)}", "give a boolean")
        X, free = _waypoint_matrix(system, t, waypoints)
        if degrees:  # every angle given in degrees: waypoints, bounds and rate limits
            X, shorthand, u_max, state_bounds, input_bounds = _from_degrees(system, X, shorthand, u_max, state_bounds,
                                                                            input_bounds)
        asked = objective is not None or tau_max is not None
        strategy, objective, torque_limits = _optimal_strategy(system, method, objective, tau_max)
        if conditions is None:  # optimal plans leave the end inputs free: pinned, the optimum is not attained
            conditions = "free" if asked else "spline"
        check_conditions(conditions, system)
        sizes = None if n_coefficients is None else (_whole("n_coefficients", n_coefficients, 6, MAX_COEFFICIENTS),)
        b = make_basis(basis, sizes[0] if sizes else DEFAULT_SIZE)
        tol, max_evaluations, time_limit = _solver_options(tol, max_evaluations, time_limit)
        verify = resolve_verify(system, verify)
        limits = _limits_of(system, limits, u_max, state_bounds, input_bounds, shorthand, X, t)
        rates = _end_rates(system, conditions, degrees, start_rate=start_rate, end_rate=end_rate)
        req = cls(system=system, times=t, waypoints=X, free=free, conditions=conditions, strategy=strategy, basis=b,
                  sizes=sizes, limits=limits, verify=verify, tol=tol, max_evaluations=max_evaluations,
                  time_limit=time_limit, start_rate=rates.get("start_rate"), end_rate=rates.get("end_rate"),
                  degrees=degrees, objective=objective, torque_limits=torque_limits)
        fam = family_of(system)
        if fam is not None and fam.check_request is not None:
            fam.check_request(req)  # what the family's planners cannot take, refused at the boundary
        _check_compile_time(req)
        return req


def _split_named(system, named: dict) -> tuple[dict, dict]:
    """plan()'s other keywords: ``(waypoints, shorthand)``, the states' waypoint values by name and
    the bound keywords ``NAME_min`` / ``NAME_max``; anything else is refused with the closest name."""
    states = system.state_names
    waypoints, shorthand = {}, {}
    for key, value in named.items():
        if key in states:
            waypoints[key] = value
        elif (key.endswith("_min") or key.endswith("_max")) and key[:-4] in states:
            shorthand[key] = value
        else:
            known = list(_OPTIONS) + list(states) + [f"{n}_{e}" for n in states for e in ("min", "max")]
            close = difflib.get_close_matches(key, known, n=1, cutoff=0.6)
            raise InvalidInputError(key, f"is not an option of plan() nor a state of {type(system).__name__}",
                                    (f"did you mean {close[0]!r}? " if close else "") +
                                    f"states are {list(states)}; bounds are NAME_min / NAME_max")
    return waypoints, shorthand


def _times(times) -> np.ndarray:
    """The waypoint times checked: at least two, strictly increasing, within the range the
    arithmetic carries, each segment's duration in [MIN_DURATION, MAX_DURATION]."""
    t = _vector("times", times)
    if t.size < 2:
        raise InvalidInputError("times", f"needs at least 2 values, got {t.size}", "give start and end times")
    tl = t.tolist()
    if any(b <= a for a, b in zip(tl, tl[1:])):
        raise InvalidInputError("times", "must be strictly increasing", "sort the waypoints by time")
    if np.max(np.abs(t)) > MAX_TIME:
        raise InvalidInputError("times", f"reach {np.max(np.abs(t)):.3g}; times beyond {MAX_TIME:g} are more than "
                                "the arithmetic carries", "count time from the start of the motion")
    for k, T in enumerate(np.diff(t)):
        if not MIN_DURATION <= T <= MAX_DURATION:
            raise InvalidInputError("times", f"segment {k} lasts {T:.3g}; durations must lie in "
                                    f"[{MIN_DURATION:g}, {MAX_DURATION:g}] (powers of T up to the 29th enter "
                                    "the exported coefficients)", "rescale the units of time")
    return t


def _waypoint_matrix(system, t, waypoints: dict) -> tuple[np.ndarray, np.ndarray]:
    """The waypoints as a matrix, shape (len(t), n_states), and where they are free (NaN)."""
    states = system.state_names
    missing = [name for name in states if name not in waypoints]
    if missing:
        raise InvalidInputError(missing[0], "is missing", f"give one value per waypoint for every state "
                                f"{list(states)}")
    X = np.stack([_waypoints(name, waypoints[name], t.size) for name in states], axis=1)
    free = np.isnan(X)
    if free.any() and system.ndx != system.n_states:
        raise InvalidInputError(states[int(np.argwhere(free)[0][1])], "free waypoint states need a Euclidean "
                                f"state space, which {type(system).__name__} does not have",
                                "give every state at every waypoint")
    return X, free


def _from_degrees(system, X, shorthand, u_max, state_bounds, input_bounds):
    """``degrees=True``: every angle (waypoints, bounds, rate limits) converted to radians."""
    angles = [i for i, name in enumerate(system.state_names) if name in system.angle_states]
    X = X.copy()
    X[:, angles] = np.radians(X[:, angles])
    shorthand = {k: (None if v is None else _deg(k, v, k[:-4] in system.angle_states)) for k, v in shorthand.items()}
    u_max = None if u_max is None else _deg("u_max", u_max, True)
    state_bounds = None if not state_bounds else {
        k: tuple(None if v is None else _deg(f"state_bounds.{k}", v, k in system.angle_states) for v in pair)
        for k, pair in dict(state_bounds).items()}
    input_bounds = None if not input_bounds else {
        k: _deg(f"input_bounds.{k}", v, system.rate_inputs.get(k) in system.angle_states)
        for k, v in dict(input_bounds).items()}
    return X, shorthand, u_max, state_bounds, input_bounds


def _solver_options(tol, max_evaluations, time_limit) -> tuple[float, int, float | None]:
    """``tol``, ``max_evaluations`` and ``time_limit`` checked."""
    if not (isinstance(tol, (int, float)) and not isinstance(tol, bool) and math.isfinite(tol) and tol > 0):
        raise InvalidInputError("tol", f"must be a positive number, got {tol!r}", "give for example 1e-10")
    max_evaluations = _whole("max_evaluations", max_evaluations, 2000)
    if time_limit is not None and not (isinstance(time_limit, (int, float, np.floating, np.integer))
                                       and not isinstance(time_limit, bool) and 0 < time_limit < math.inf):
        raise InvalidInputError("time_limit", f"must be a positive number of seconds or None, got "
                                f"{_short(time_limit)}", "give for example 60")
    return float(tol), max_evaluations, None if time_limit is None else float(time_limit)


def _limits_of(system, limits, u_max, state_bounds, input_bounds, shorthand, X, t) -> Limits:
    """The plan's :class:`Limits`: ``limits=`` or the limit keywords (not both), else the system's
    own (a URDF's joint ranges and rates); every waypoint checked to lie inside them."""
    if limits is not None and not isinstance(limits, Limits):
        raise InvalidInputError("limits", f"must be an acroplan.Limits, got {type(limits).__name__}",
                                "give Limits(...) or the keywords u_max, NAME_min, NAME_max")
    if limits is not None and (u_max is not None or state_bounds or input_bounds or shorthand):
        raise InvalidInputError("limits", "is given together with limit keywords",
                                "give either limits=Limits(...) or the keywords")
    if limits is None:
        given = Limits(state_bounds, input_bounds, u_max=u_max, **shorthand)
        # the system's own limits (a URDF's joint ranges and rates) hold unless the call gives
        # limits of its own; limits=Limits() (empty) switches them off
        limits = given if given.active else (system.default_limits() or given)
    limits.check_for(system)
    states = system.state_names
    for state in limits.bounded_states:
        i = states.index(state)
        lo, hi = limits.bounds(state)
        for k, v in enumerate(X[:, i]):
            if not np.isnan(v) and not lo <= v <= hi:
                raise InvalidInputError(state, f"waypoint {k} (t = {t[k]:g}) has {state} = {v:.12g}, outside "
                                        f"the joint limits [{lo:.12g}, {hi:.12g}]",
                                        "move the waypoint inside the limits or widen them")
    return limits


def _end_rates(system, conditions: str, degrees: bool, **given) -> dict[str, np.ndarray]:
    """``start_rate`` and ``end_rate`` (``conditions="free"`` only) as vectors of the inputs, in rad/s."""
    rates = {}
    for field, value in given.items():
        if value is None:
            continue
        if conditions == "spline":
            raise InvalidInputError(field, "applies to conditions=\"free\" only (the spline already starts and "
                                    "ends at rest)", "leave it out, or use conditions=\"free\"")
        if isinstance(value, dict):
            unknown = sorted(set(value) - set(system.input_names))
            if unknown:
                raise InvalidInputError(f"{field}.{unknown[0]}", f"is not an input of {type(system).__name__}",
                                        f"inputs are {list(system.input_names)}")
            value = [value.get(name, 0.0) for name in system.input_names]
        v = _vector(field, np.broadcast_to(np.asarray(value, dtype=float), (system.n_inputs,))
                    if np.ndim(value) == 0 and not isinstance(value, (str, bool)) else value, system.n_inputs)
        if degrees:
            v = np.array([np.radians(x) if system.rate_inputs.get(n) in system.angle_states else x
                          for n, x in zip(system.input_names, v)])
        rates[field] = v
    return rates


def _check_compile_time(req: PlanRequest) -> None:
    """Refuse a plan whose first compilation would take longer than its time limit
    (:func:`acroplan.core.backend.compile_estimate`: a lower bound from the family's measured
    growth, none when that integrator was compiled before on this machine)."""
    if req.time_limit is None:
        return
    n = req.sizes[0] if req.sizes else req.basis.n
    est = backend.compile_estimate(req.system, type(req.basis), n)
    if est is None or est.seconds <= req.time_limit:
        return
    raise InvalidInputError("time_limit", f"is {req.time_limit:g} s, and compiling the integrator of {est.what} with "
                            f"{n} coefficients takes at least {est.seconds:.3g} s on a first run ({est.growth}; "
                            "benchmarks/RESULTS.md), which the time limit covers",
                            f"give time_limit = {math.ceil(est.seconds / 0.8):g} or more, or fewer links (the "
                            "compiled integrator is then kept on disk: a second run compiles in seconds)")


def _optimal_strategy(system, method, objective, tau_max):
    """``(strategy, objective, torque_limits)`` for ``method``, ``objective`` and ``tau_max``
    (validated: :func:`plan`'s Parameters)."""
    if objective is not None and (not isinstance(objective, str) or objective not in OBJECTIVES):
        raise InvalidInputError("objective", f"must be None, \"energy\" or \"torque\", got {_short(objective)}",
                                "give \"energy\" (least integral of |u|^2), \"torque\" (least integral of "
                                "|tau|^2), or leave it out for the fast feasible plan")
    if objective is None and tau_max is None:
        strategy = resolve_strategy(method, system)
        if not isinstance(strategy, EnergyOptimal):
            return strategy, None, None
        # method is itself an optimal strategy: record what it minimises and its torque limits
        model = strategy._model(system)
        vec = tau_vector(strategy.tau_max, model) if strategy.tau_max is not None else None
        return strategy, strategy._cost_kind, _limits_by_joint(model, vec)
    objective = objective or "energy"  # torque limits need the optimiser; it minimises the energy by default
    model = None
    for field, wanted in (("objective", objective == "torque"), ("tau_max", tau_max is not None)):
        if wanted:
            model, why = torque_model_of(system)
            if model is None:
                raise InvalidInputError(field, f"needs the joint torques, and {why}",
                                        "leave it out, or give a body with its masses and inertias (for example "
                                        "Acrobot.from_physical)" if field == "tau_max" else
                                        "use objective=\"energy\" or leave it out, or give a body with its masses "
                                        "and inertias (for example Acrobot.from_physical)")
    vec = None if tau_max is None else tau_vector(tau_max, model)
    optimal = (method if isinstance(method, str) and isinstance(STRATEGIES.get(method), EnergyOptimal)
               else method if isinstance(method, EnergyOptimal)
               or (isinstance(method, type) and issubclass(method, EnergyOptimal)) else None)
    if optimal is not None:
        raise InvalidInputError("method", f"is an optimal strategy ({_short(optimal)}) and objective="
                                f"{objective!r}{' (set by tau_max)' if tau_max is not None else ''} is given too",
                                "give objective= (and tau_max=) alone, with method naming the feasible plan to "
                                "start from, or method= alone")
    if isinstance(method, str) and method == "auto":
        strategy = objective_strategy(objective, tau_max=tau_max)
    else:  # the optimum starts from the plan of the method asked for
        strategy = objective_strategy(objective, tau_max=tau_max, feasible=resolve_strategy(method, system),
                                      starts=("auto",))
    why = strategy.unsupported(system)
    if why:
        raise InvalidInputError("objective", why, "leave objective and tau_max out")
    return strategy, objective, _limits_by_joint(model if tau_max is not None else None, vec)


def _limits_by_joint(model, vec):
    if vec is None:
        return None
    names = getattr(model, "joint_names", None) or tuple(f"joint{j}" for j in range(len(vec)))
    return {str(n): float(v) for n, v in zip(names, vec) if math.isfinite(v)}


def plan(system: ControlAffineSystem, *, times, conditions: str | None = None, method="auto", basis="legendre",
         n_coefficients: int | None = None, limits: Limits | None = None, u_max: float | None = None,
         state_bounds=None, input_bounds=None, verify: bool | str = True, tol: float = 1e-10,
         max_evaluations: int = 2000, time_limit: float | None = TIME_LIMIT, start_rate=None, end_rate=None,
         degrees: bool = False, objective: str | None = None, tau_max=None, progress=None,
         **waypoints) -> PlanResult:
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
    limits : Limits, optional
        All bounds at once (``Limits()`` for none at all); without it and without limit keywords,
        the system's own (:meth:`ControlAffineSystem.default_limits`: a URDF's joint ranges and
        rates) hold. Or the keywords ``u_max`` (:math:`|u_j| \le u_{max}` for every input),
        ``state_bounds`` (``{"phi": (lo, hi)}``), ``input_bounds`` (``{"u": 15.0}``), ``NAME_min``,
        ``NAME_max``.
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
        next (``n_coefficients`` fixes one size), and each segment reports its relative KKT
        residual (target 1e-8) in :attr:`SegmentResult.optimality`
        (:mod:`acroplan.core.optimal`). Each interval is optimised on its own, with its input
        conditions. Slower than the feasible plan (a few ms to tens of ms per interval). The
        strategies are :class:`acroplan.EnergyOptimal` and :class:`acroplan.TorqueOptimal`.
    tau_max : float, sequence, or dict by joint name, optional
        Torque limits :math:`|\tau_j(t)| \le \bar\tau_j` (one number for every joint, one per
        joint, or ``{joint: limit}``; joints not named are free), with the rate and joint limits;
        needs a torque model. Torque limits need the optimiser, so ``objective`` defaults to
        ``"energy"`` with them. The result's peak torque of each joint (refined between grid points)
        is checked: above :math:`\bar\tau_j(1 + 10^{-9})` the plan is ``not_converged``.
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
    prepare(system)  # its family's strategies, torque model and starts (core.family.prepare)
    req = PlanRequest.build(system, times=times, conditions=conditions, method=method, basis=basis,
                            n_coefficients=n_coefficients, limits=limits, u_max=u_max, state_bounds=state_bounds,
                            input_bounds=input_bounds, verify=verify, tol=tol, max_evaluations=max_evaluations,
                            time_limit=time_limit, start_rate=start_rate, end_rate=end_rate, degrees=degrees,
                            objective=objective, tau_max=tau_max, **waypoints)
    return solve(req, progress=progress)


def solve(req: PlanRequest, *, progress=None) -> PlanResult:
    """Plan a validated :class:`PlanRequest` (what :func:`plan` does after validation), within its
    time budget, reporting to ``progress`` (:func:`acroplan.core.progress.resolve`)."""
    outer = progress_mod.current()
    prog = progress_mod.resolve(progress)
    owned = prog is not outer and not isinstance(progress, progress_mod.Progress)
    with prog.active(), budget(req.time_limit):
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
        return _check_torque_limits(PlanResult(
            status=Status.SUCCESS, message=f"success: {K} segment(s), max endpoint error {worst_final:.2e} (not "
            f"independently verified)" + _optimality_note(segments, req), segments=segments, verified=False,
            **common), req)
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


#: How many refused segments a message names (every one is in ``result.infeasible``).
MESSAGE_SEGMENTS = 3


def infeasible_message(req: PlanRequest, X, infeasible: list[dict]) -> str:
    """The message of an infeasible plan: the first :data:`MESSAGE_SEGMENTS` refused segments with
    their proofs, how many more there are (all in ``result.infeasible`` and ``solution.json``), and
    the degrees hint when the angles look like degrees (every waypoint angle within 360 in size,
    some beyond 2 pi, and whole numbers or halves: what a file in degrees holds)."""
    system = req.system
    shown = [f"segment {d['index']} [{d['t0']:g}, {d['t1']:g}]: {d['reason']}" for d in infeasible[:MESSAGE_SEGMENTS]]
    msg = "infeasible: " + "; ".join(shown)
    if len(infeasible) > MESSAGE_SEGMENTS:
        msg += (f"; and {len(infeasible) - MESSAGE_SEGMENTS} more of {req.times.size - 1} segments (every one in "
                "result.infeasible, solution.json)")
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
    an interval, its strategy reports its own stages)."""
    system, t = req.system, req.times
    K = t.size - 1
    segments: list[SegmentResult] = []
    prev_end_input = None
    with prog.scope("segments", K, unit="segment") as bar:
        for k in range(K):
            interval = Interval(system=system, basis=req.basis, sizes=req.sizes, x0=X[k], x1=X[k + 1],
                                T=float(t[k + 1] - t[k]), ends=conditions.ends(k, prev_end_input), limits=limits,
                                tol=req.tol, max_evaluations=req.max_evaluations)
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
            if not out.success:
                return tuple(segments), (f"not converged: segment {k} [{t[k]:g}, {t[k + 1]:g}] from "
                                         f"{_fmt(X[k], system)} to {_fmt(X[k + 1], system)}: {out.reason}")
            bar.update()
            if k + 1 < K:  # the input value the next interval starts with (free conditions)
                last = segments[-1]
                prev_end_input = last.input([last.t1])[:, 0]
    return tuple(segments), None


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
    return _check_torque_limits(result, req)


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
    return (f"; {req.objective}-optimal: {what} = {cost:.10g}, largest relative KKT residual {kkt:.1e} (target "
            f"{opt[0]['kkt_tol']:g}), " + ("converged on every interval" if not bad else
                                            f"NOT converged on interval(s) {bad} (see each segment's optimality)"))


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
