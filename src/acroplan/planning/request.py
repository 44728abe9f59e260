"""Validation of :func:`~acroplan.planning.plan`'s arguments: :class:`PlanRequest`, every
argument checked at the boundary, messages naming the field and the fix (step 1 of the package
docstring); the limits of what the arithmetic carries; the refusal of a first compilation longer
than the time limit."""

from __future__ import annotations

import dataclasses
import difflib
import math

import numpy as np

from ..core import backend
from ..core.basis import InputBasis, make_basis
from ..core.conditions import check_conditions
from ..core.errors import InvalidInputError
from ..core.family import family_of
from ..core.keywords import PLAN_KEYWORDS
from ..core.limits import Limits
from ..core.optimal import MAX_LADDER_SIZE, OBJECTIVES, EnergyOptimal, objective_strategy, own_ladder, tau_vector
from ..core.strategies import STRATEGIES, Strategy, resolve_strategy
from ..core.system import ControlAffineSystem, torque_model_of
from ..core.verify import resolve_verify


__all__ = ["PlanRequest", "checked_vector", "DEFAULT_SIZE", "MAX_COEFFICIENTS", "MAX_LADDER_COEFFICIENTS",
           "ladder_sizes", "TIME_LIMIT", "MIN_DURATION", "MAX_DURATION", "MAX_TIME"]

#: Coefficients per input per segment when neither ``n_coefficients`` nor the strategy says.
DEFAULT_SIZE = 6
#: The largest ``n_coefficients``: more costs compile time and memory for no accuracy (the
#: Legendre basis at 14 already reaches every target the planner meets).
MAX_COEFFICIENTS = 30
#: The largest ``max_coefficients``: the top of an optimum's ladder of basis sizes (an optimum's
#: cost can still fall at 30 coefficients where a limit binds: benchmarks/RESULTS.md).
MAX_LADDER_COEFFICIENTS = MAX_LADDER_SIZE
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
        given = checked_vector(field, [v for v in value if v is not None])
        out = np.full(length, np.nan)
        out[[i for i, v in enumerate(value) if v is not None]] = given
        return out
    return checked_vector(field, value, length)


def checked_vector(field, value, length=None) -> np.ndarray:
    """``value`` as a vector of finite numbers (of ``length`` when given), or the error naming
    ``field``."""
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
    if not (all(map(math.isfinite, a.tolist())) if a.size <= _FEW else np.isfinite(a).all()):
        raise InvalidInputError(field, "contains NaN or infinite values", "give finite numbers")
    return a


#: Up to this many values the checks of a plan's arguments work on Python floats (the same
#: answers; numpy's per-call overhead, some microseconds a call, was most of a two-link plan's
#: 0.1 ms of validation: ``benchmarks/plan_overhead.py --parts``)
_FEW = 64


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
    capacity: dict | None = None

    @classmethod
    def build(cls, system, *, times, conditions: str | None = None, method="auto", basis="legendre",
              n_coefficients: int | None = None, max_coefficients: int | None = None, limits: Limits | None = None,
              u_max: float | None = None, state_bounds=None, input_bounds=None, verify: bool | str = True,
              tol: float = 1e-10, max_evaluations: int = 2000, time_limit: float | None = TIME_LIMIT, start_rate=None,
              end_rate=None, degrees: bool = False, objective: str | None = None, tau_max=None,
              capacity=None, **named) -> "PlanRequest":
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
        top = _ladder_top(max_coefficients, asked, n_coefficients, method, t)
        strategy, objective, torque_limits = _optimal_strategy(system, method, objective, tau_max, top)
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
                  degrees=degrees, objective=objective, torque_limits=torque_limits,
                  capacity=_capacity(system, capacity))
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
    t = checked_vector("times", times)
    if t.size < 2:
        raise InvalidInputError("times", f"needs at least 2 values, got {t.size}", "give start and end times")
    tl = t.tolist()
    if any(b <= a for a, b in zip(tl, tl[1:])):
        raise InvalidInputError("times", "must be strictly increasing", "sort the waypoints by time")
    reach = max(abs(tl[0]), abs(tl[-1]))  # increasing: the largest magnitude is at an end
    if reach > MAX_TIME:
        raise InvalidInputError("times", f"reach {reach:.3g}; times beyond {MAX_TIME:g} are more than "
                                "the arithmetic carries", "count time from the start of the motion")
    for k, (a, b) in enumerate(zip(tl, tl[1:])):
        T = b - a
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
    X = np.empty((t.size, len(states)))
    for i, name in enumerate(states):
        X[:, i] = _waypoints(name, waypoints[name], t.size)
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
        # limits=Limits(...) is the whole set (Limits() switches the system's own off); the keywords
        # change the system's own limits (a URDF's joint ranges and rates) name by name
        limits = _merged_limits(system.default_limits(), u_max, state_bounds, input_bounds, shorthand)
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


_NO_LIMITS = Limits()  # immutable: one for every plan without limits


def _merged_limits(own: Limits | None, u_max, state_bounds, input_bounds, shorthand: dict) -> Limits:
    """The system's own limits ``own`` changed by the limit keywords, name by name.

    ``state_bounds={"q": (lo, hi)}`` replaces joint ``q``'s range (``None``: that end open);
    ``q_min=`` / ``q_max=`` replace one end (``None`` drops it); ``input_bounds={"u_q": v}``
    replaces input ``u_q``'s rate limit; ``u_max`` replaces the system's rate limits on every input
    (a named ``input_bounds`` entry, if smaller, wins, as in :class:`Limits`). What the keywords do
    not name keeps the system's own limit: a rate limit alone does not drop a body's joint ranges.
    """
    if u_max is None and not state_bounds and not input_bounds and not shorthand:
        return own if own is not None else _NO_LIMITS
    given = Limits(state_bounds, input_bounds, u_max=u_max, **shorthand)  # validated as given
    if own is None or not own.active:
        return given
    ranges = {name: [lo, hi] for name, lo, hi in own.state_bounds}
    for name, (lo, hi) in dict(state_bounds or {}).items():
        ranges[name] = [lo, hi]
    for key, v in shorthand.items():
        ranges.setdefault(key[:-4], [None, None])[0 if key.endswith("_min") else 1] = v
    for name, (lo, hi) in ranges.items():
        if lo is not None and hi is not None and not lo < hi:  # one end the call's, the other the body's
            field = f"{name}_min" if f"{name}_min" in shorthand else f"{name}_max"
            raise InvalidInputError(field, f"must keep {name}_min < {name}_max, and with the system's own other "
                                    f"end it gives {name}_min = {lo:.12g}, {name}_max = {hi:.12g}",
                                    "give both ends, or move this one inside the system's range")
    rates = {} if u_max is not None else dict(own.input_bounds)
    rates.update(dict(input_bounds or {}))
    return Limits({n: tuple(pair) for n, pair in ranges.items()}, rates,
                  u_max=u_max if u_max is not None else own.u_max)


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
        v = checked_vector(field, np.broadcast_to(np.asarray(value, dtype=float), (system.n_inputs,))
                    if np.ndim(value) == 0 and not isinstance(value, (str, bool)) else value, system.n_inputs)
        if degrees:
            v = np.array([np.radians(x) if system.rate_inputs.get(n) in system.angle_states else x
                          for n, x in zip(system.input_names, v)])
        rates[field] = v
    return rates


def _capacity(system, capacity) -> dict | None:
    """``capacity=`` validated: ``{"rates": {input: (top, source)}, "torques": {joint: (top, source)}}``."""
    if capacity is None:
        return None
    fix = 'give {"rates": {"u": (12.0, "a source")}, "torques": {"phi": (350.0, "a source")}}'
    if not isinstance(capacity, dict) or set(capacity) - {"rates", "torques"}:
        raise InvalidInputError("capacity", f"must be a dict with the keys rates and torques, got {_short(capacity)}",
                                fix)
    out = {}
    for kind, names in (("rates", system.input_names), ("torques", None)):
        table = capacity.get(kind) or {}
        if not isinstance(table, dict):
            raise InvalidInputError(f"capacity.{kind}", f"must be a dict, got {_short(table)}", fix)
        entries = {}
        for name, pair in table.items():
            if names is not None and name not in names:
                raise InvalidInputError(f"capacity.{kind}.{name}", f"is not an input of {type(system).__name__}",
                                        f"inputs are {list(names)}")
            try:
                top, source = pair
                top = float(top)
            except (TypeError, ValueError):
                raise InvalidInputError(f"capacity.{kind}.{name}", f"must be (top, source), got {_short(pair)}",
                                        fix) from None
            if not (math.isfinite(top) and top > 0):
                raise InvalidInputError(f"capacity.{kind}.{name}", f"must be a positive number, got {top!r}", fix)
            entries[str(name)] = (top, str(source))
        out[kind] = entries
    return out


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
    raise InvalidInputError("time_limit", f"is {req.time_limit:g} s, and the first compilation for {est.what} "
                            f"({n} coefficients) takes at least {est.seconds:.3g} s ({est.growth}; "
                            "benchmarks/RESULTS.md), which the time limit covers",
                            f"give time_limit = {math.ceil(est.seconds / 0.8):g} or more, or fewer links (what is "
                            "compiled is then kept on disk: a second run loads it in seconds)")


def ladder_sizes(top: int, base=None) -> tuple[int, ...]:
    """The optimum's ladder of basis sizes up to ``top`` (:func:`plan`'s ``max_coefficients``):
    ``base`` (default :data:`acroplan.core.optimal.SIZES`; a system's own ladder for its objective,
    ``optimal_sizes``) up to it, then steps of 6 from its last size, ending at ``top``."""
    from ..core.optimal import SIZES

    base = SIZES if base is None else tuple(base)
    sizes = [n for n in base if n <= top] + list(range(base[-1] + 6, top + 1, 6))
    if not sizes or sizes[-1] != top:
        sizes.append(top)
    return tuple(sizes)


def _is_optimal(method) -> bool:
    """Whether ``method`` is an optimal strategy: a registered name of one, an instance or a class."""
    return ((isinstance(method, str) and isinstance(STRATEGIES.get(method), EnergyOptimal))
            or isinstance(method, EnergyOptimal) or (isinstance(method, type) and issubclass(method, EnergyOptimal)))


def _ladder_top(max_coefficients, asked: bool, n_coefficients, method, times) -> int | None:
    """``max_coefficients``, the top of the optimum's ladder (validated against the waypoint ``times``:
    the power-basis export divides by :math:`T^{n-1}`, which must stay within 1e-300 and 1e300),
    ``None`` when it is not given."""
    if max_coefficients is None:
        return None
    top = _whole("max_coefficients", max_coefficients, 48, MAX_LADDER_COEFFICIENTS)
    if top < 6:
        raise InvalidInputError("max_coefficients", f"must be at least 6, got {top}", "give for example 48")
    if _is_optimal(method) and not asked:
        raise InvalidInputError("max_coefficients", f"is given with method={_short(method)}, an optimal strategy with "
                                "its own ladder", "give objective= with max_coefficients (and method naming the "
                                "feasible plan to start from), or the strategy its sizes: EnergyOptimal(sizes=...)")
    if not asked:
        raise InvalidInputError("max_coefficients", "is the top of an optimum's ladder of basis sizes, and no objective "
                                "is given (the feasible plan has no ladder)",
                                "give objective=\"energy\" or \"torque\" with it, or n_coefficients for the feasible "
                                "plan's basis size")
    if n_coefficients is not None:
        raise InvalidInputError("max_coefficients", "and n_coefficients are both given: n_coefficients fixes one basis "
                                "size, max_coefficients the last of the ladder", "give one of them")
    durations = np.diff(np.asarray(times, dtype=float))
    k = int(np.argmax(np.abs(np.log10(durations))))
    worst = abs(math.log10(durations[k]))
    if worst * (top - 1) > 300:
        most = max(6, 1 + int(300 // worst))
        raise InvalidInputError("max_coefficients", f"is {top}, and a segment of {durations[k]:g} s would take "
                                f"T**{top - 1} out of the arithmetic's range (the power-basis export)",
                                f"give at most {most}, or rescale the times")
    return top


def _optimal_strategy(system, method, objective, tau_max, top=None):
    """``(strategy, objective, torque_limits)`` for ``method``, ``objective`` and ``tau_max``
    (validated: :func:`plan`'s Parameters), its ladder ending at ``top`` when given (:func:`_ladder_top`:
    the system's own ladder for the objective, else the default, by :func:`ladder_sizes`)."""
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
    if _is_optimal(method):
        raise InvalidInputError("method", f"is an optimal strategy ({_short(method)}) and objective="
                                f"{objective!r}{' (set by tau_max)' if tau_max is not None else ''} is given too",
                                "give objective= (and tau_max=) alone, with method naming the feasible plan to "
                                "start from, or method= alone")
    sized = {} if top is None else {"sizes": ladder_sizes(top, own_ladder(system, objective))}
    if isinstance(method, str) and method == "auto":
        strategy = objective_strategy(objective, tau_max=tau_max, **sized)
    else:  # the optimum starts from the plan of the method asked for
        strategy = objective_strategy(objective, tau_max=tau_max, feasible=resolve_strategy(method, system),
                                      starts=("auto",), **sized)
    why = strategy.unsupported(system)
    if why:
        raise InvalidInputError("objective", why, "leave objective and tau_max out")
    return strategy, objective, _limits_by_joint(model if tau_max is not None else None, vec)


def _limits_by_joint(model, vec):
    if vec is None:
        return None
    names = getattr(model, "joint_names", None) or tuple(f"joint{j}" for j in range(len(vec)))
    return {str(n): float(v) for n, v in zip(names, vec) if math.isfinite(v)}


