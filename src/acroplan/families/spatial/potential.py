"""The coach's question in 3-D: the most twist a body can make in a given flight time and number of
somersaults (``acroplan twist-potential FILE``).

The technique is the file's. A problem file of a twisting somersault (the bundled dives,
``docs/human.md``) gives waypoints in Yeadon's somersault, tilt and twist; they are read back as
quaternions, which do not say how many turns lie between two waypoints, so the file is planned
first and its waypoints' unwrapped Yeadon angles read from that plan (:func:`technique_of`).

**The technique's flight** (:func:`technique_flight`) comes first in each cell of a flight time
:math:`T` and :math:`n` somersaults: the file's planned joint motion played in the flight time
(its rates times :math:`T_f / T`, the file's subscript :math:`f`), simulated (``acroplan.simulate``,
Pinocchio-checked) with :math:`L` along the file's, its size found by the secant method so that
the flight turns exactly :math:`n` somersaults. Its twist at the landing and its tilt there say
what the technique itself makes, and its states at the waypoint times are the interior waypoints
of every twist target :math:`X` (turns) planned in the cell: a motion of the body is known to
pass through them, where waypoints scaled from the file's angles (below) are not, and from those
the planner searches in vain. The landing waypoint is :math:`n` somersaults, no tilt and the
target's twist, with the file's joints. Each target is planned (``plan`` passed in, since a
family does not import the front doors) under the file's joint ranges and rate limits (and torque
limits when the file gives ``tau_max``); a target is reached when the plan succeeds (checked by
Pinocchio) **and** its motion turns the target's somersaults and twists (to :data:`COUNT_TOL`
turns, unwrapped Yeadon angles): a plan that turns the other way between the waypoints is not.

Without a flight (no ``simulate`` given, or a flight that cannot be made: :func:`technique_flight`
says when), the targets are **the same technique scaled** (:func:`scaled_problem`): the waypoint
times by :math:`T / T_f`, every waypoint's somersault angle by :math:`n / n_f`, its twist angle by
:math:`X / X_f`, its tilt and the joint angles kept; the angular momentum :math:`L = I\\,\\omega`
follows the somersault rate, :math:`L = L_f\\,(n / n_f) (T_f / T)`.

The bisection on :math:`X`: from the technique flight's twist rounded down to ``resolution`` (the
file's own twist count, or half a turn, when there is no flight), doubling while the plan
succeeds, then halving the bracket to ``resolution`` turns. It reports the most twist reached
(``most``: a plan exists, Pinocchio-checked) and the least target not reached (``failed``), and
**why** it stopped there: ``"proven"`` when the family's exact test (``check_segment``) refuses the
segment before planning, else ``"planner stopped"`` (a plan not found within the budget proves
nothing: more may be reachable). Spatial bodies have no exact test of a twist yet, so every stop
here is ``"planner stopped"``.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np

from ...core.backend import IntegrationError
from ...core.errors import InvalidInputError
from . import rotations as rot

__all__ = ["TwistCell", "TechniqueFlight", "bisect_twist", "yeadon_turns", "sampled_states", "attitude_angles",
           "technique_of", "technique_flight", "scaled_problem", "twist_potential", "twist_potential_figure",
           "DEFAULT_RESOLUTION", "MOST_TWISTS", "COUNT_TOL", "FLIGHT_TOL"]

#: the bisection's resolution (turns of twist)
DEFAULT_RESOLUTION = 0.25
#: the doubling stops here (turns)
MOST_TWISTS = 8.0
#: a plan reaches a target when its somersault and twist counts are the target's to this (turns)
COUNT_TOL = 1e-6
#: the technique's flight turns the cell's somersaults to this (turns; the secant on the size of L)
FLIGHT_TOL = 1e-9


@dataclasses.dataclass(frozen=True)
class TwistCell:
    """One cell of the table: the most twist found in ``flight_time`` s and ``somersaults``."""

    flight_time: float
    somersaults: float
    angular_momentum: tuple[float, float, float]
    most: float           # turns of twist of the last success (0.0: none planned)
    failed: float | None  # the least target (turns) not reached, None when none failed
    stopped: str          # "proven", "planner stopped", or "resolution" (none failed below MOST_TWISTS)
    reason: str
    plans: int
    seconds: float
    tries: tuple[tuple[float, str], ...]   # (target turns, status) in the order planned
    technique_twists: float | None = None       # the technique's flight: twist at the landing (turns)
    technique_landing_tilt: float | None = None  # ... and its tilt there (degrees)
    technique_peak_rate: float | None = None     # ... its largest joint rate over that joint's limit (1: at it)

    def to_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["angular_momentum"] = list(self.angular_momentum)
        d["tries"] = [list(t) for t in self.tries]
        return d


@dataclasses.dataclass(frozen=True)
class TechniqueFlight:
    """The file's joint motion flown in another flight time with another angular momentum
    (:func:`technique_flight`)."""

    body: object            # the SpatialBody with the flight's L
    result: object          # acroplan.simulate's PlanResult (Pinocchio-checked)
    times: np.ndarray       # the waypoint times, scaled, shape (K+1,)
    states: np.ndarray      # the flight's states at those times, shape (K+1, n_states)
    somersaults: float      # turns at the landing (signed: the file's direction)
    twists: float           # turns at the landing (signed)
    landing_tilt: float     # degrees
    peak_rate: float        # the largest |joint rate| over its limit (joints without one left out; 0: none has)


def yeadon_turns(result, times=None, samples: int = 4001):
    """The pelvis's (root's) Yeadon angles along a planned motion, unwrapped on a dense sampling:
    ``(t, somersault, tilt, twist)``, somersault and twist in turns from 0 at the start, tilt in
    degrees; at ``times`` when given (read off the dense sampling's unwrapped angles)."""
    t = np.linspace(result.times[0], result.times[-1], int(samples))
    X = sampled_states(result, t)
    ang = np.radians(rot.to_euler(X[:4]))
    som = np.unwrap(ang[0])
    tw = np.unwrap(ang[2])
    som, tw, tilt = (som - som[0]) / (2 * math.pi), (tw - tw[0]) / (2 * math.pi), np.degrees(ang[1])
    if times is None:
        return t, som, tilt, tw
    idx = [int(np.argmin(np.abs(t - float(x)))) for x in times]
    return np.asarray(times, dtype=float), som[idx], tilt[idx], tw[idx]


def sampled_states(result, t, block: int = 500, field: str = "states") -> np.ndarray:
    """``result.evaluate(t).states`` (or another ``field`` of the samples: ``"inputs"``) in blocks
    of at most ``block`` times (the collocation cuts its panels at the times asked, and refuses
    more than 2048 on one segment)."""
    t = np.asarray(t, dtype=float)
    parts = [getattr(result.evaluate(c, effort=False), field) for c in np.array_split(t, max(1, -(-len(t) // block)))]
    return np.concatenate(parts, axis=1)


def attitude_angles(result, t) -> dict:
    """Yeadon's angles of the root at the times ``t`` (the spatial family's ``attitude_angles``
    hook, ``acroplan simulate``'s ``angles.csv``): ``somersault_turns``, ``tilt_deg``,
    ``twist_turns``, unwrapped on a dense sampling from 0 at the start."""
    tt, som, tilt, tw = yeadon_turns(result)
    t = np.asarray(t, dtype=float)
    return {"somersault_turns": np.interp(t, tt, som), "tilt_deg": np.interp(t, tt, tilt),
            "twist_turns": np.interp(t, tt, tw)}


def _counts(result) -> tuple[float, float]:
    """(somersault, twist) turns at the end of a planned motion (:func:`yeadon_turns`)."""
    _, som, _, tw = yeadon_turns(result)
    return float(som[-1]), float(tw[-1])


def technique_of(problem, result) -> dict:
    """The file's technique: its waypoints in Yeadon's angles read from a plan of the file itself
    (``result``; quaternion waypoints alone do not say how many turns lie between them):
    ``{"times", "somersault", "tilt", "twist"}`` (degrees, from 0 at the first waypoint), and its
    somersault and twist counts (turns) and flight time."""
    names = problem.system.state_names
    if tuple(names[:4]) != ("qw", "qx", "qy", "qz"):
        raise InvalidInputError("body", "is not a body in 3-D (its states do not start with the attitude qw, qx, "
                                "qy, qz)", "give a problem file of a spatial body (model = \"3d\")")
    times, som, tilt, tw = yeadon_turns(result, problem.times)
    return {"times": times, "somersault": 360.0 * som, "tilt": tilt, "twist": 360.0 * tw,
            "somersaults": float(som[-1]), "twists": float(tw[-1]), "T": float(times[-1] - times[0])}


def technique_flight(problem, result, technique: dict, flight_time: float, somersaults: float, simulate=None):
    """The technique's flight (module docstring): the joint rates of ``result`` (the file's plan,
    every segment's input coefficients) times :math:`a = T_f / T`, on the waypoint times scaled by
    :math:`1 / a`, flown from the file's first state by ``simulate`` (``acroplan.simulate``, passed
    in: a family does not import the front doors) with :math:`L = k L_f`, :math:`k` by the secant
    method on the somersault turns at the landing (from :math:`k = a\\,n / n_f`) until they are
    ``somersaults`` to :data:`FLIGHT_TOL`; the last flight verified by Pinocchio.

    Returns
    -------
    TechniqueFlight or None
        None when the flight cannot be made (no ``simulate``, a segment in another basis than
        Legendre's, a simulation that fails or whose check fails, or no convergence in 12 flights).

    Raises
    ------
    acroplan.core.backend.IntegrationError
        When the integrator refuses a flight (:func:`twist_potential` then falls back to the
        scaled waypoints).
    """
    from .model import SpatialBody

    if simulate is None:
        return None
    segs = list(getattr(result, "segments", ()) or ())
    if not segs or any(type(sg.basis).__name__ != "Legendre" for sg in segs):
        return None
    tech = technique
    a = tech["T"] / float(flight_time)
    times = [float(t - result.times[0]) / a for t in result.times]
    coeffs = [a * np.asarray(sg.basis_coefficients, dtype=float) for sg in segs]
    names = problem.system.state_names
    x0 = {k: float(v) for k, v in zip(names, result.waypoints[0])}
    L0 = np.asarray(problem.system.L, dtype=float)
    n = abs(float(somersaults))

    def fly(k, verify):
        body = SpatialBody(problem.system.links, L=tuple(float(v) for v in L0 * k))
        res = simulate(body, times=times, inputs=coeffs, basis="legendre", verify=verify, **x0)
        if str(getattr(res.status, "value", res.status)) != "success":
            return body, res, math.nan
        return body, res, abs(_counts(res)[0])

    k0 = a * n / abs(tech["somersaults"])
    _, _, s0 = fly(k0, False)
    if not math.isfinite(s0) or s0 <= 0:
        return None
    k1 = k0 * n / s0
    for _ in range(12):
        _, _, s1 = fly(k1, False)
        if not math.isfinite(s1):
            return None
        if abs(s1 - n) <= FLIGHT_TOL:
            break
        k0, s0, k1 = k1, s1, (k1 + (n - s1) * (k1 - k0) / (s1 - s0) if s1 != s0 else k1 * n / s1)
    else:
        return None
    body, res, s1 = fly(k1, True)
    if not (math.isfinite(s1) and abs(s1 - n) <= FLIGHT_TOL):
        return None
    tt, som, tilt, tw = yeadon_turns(res)
    states = sampled_states(res, np.asarray(times)).T
    lim = problem.system.default_limits()
    rates = dict(lim.input_bounds) if lim is not None else {}
    U = sampled_states(res, np.linspace(times[0], times[-1], 2001), field="inputs")
    peak = max((float(np.max(np.abs(U[i]))) / rates[nm] for i, nm in enumerate(problem.system.input_names)
                if nm in rates and rates[nm] > 0), default=0.0)
    return TechniqueFlight(body, res, np.asarray(times), states, float(som[-1]), float(tw[-1]), float(tilt[-1]), peak)


def scaled_problem(problem, technique: dict, flight_time: float, somersaults: float, twists: float, flight=None):
    """``(body, plan keywords)`` of the file's ``technique`` (:func:`technique_of`) scaled (module
    docstring): ``somersaults`` and ``twists`` in turns (their magnitudes; the directions the
    file's). With ``flight`` (a :class:`TechniqueFlight` of this flight time and somersault count):
    its body, its times, its states at the interior waypoints, and the landing at the somersaults,
    no tilt and ``twists``, the joints the file's."""
    from .model import SpatialBody

    tech = technique
    if flight is not None:
        sign_s = math.copysign(1.0, tech["somersaults"])
        sign_t = math.copysign(1.0, tech["twists"]) if abs(tech["twists"]) > 1e-9 else 1.0
        kw = problem.plan_kwargs()
        if kw.get("conditions") is None:
            kw.pop("conditions")
        names = problem.system.state_names
        X = np.array(flight.states, dtype=float)
        X[-1, :4] = rot.from_euler([sign_s * 360.0 * abs(somersaults), 0.0, sign_t * 360.0 * abs(twists)])
        X[-1, 4:] = [float(kw[k][-1]) for k in names[4:]]
        kw.update(times=[float(t) for t in flight.times], **{k: [float(v) for v in X[:, i]] for i, k in enumerate(names)})
        return flight.body, kw
    if abs(tech["somersaults"]) < 1e-9:
        raise InvalidInputError("plan.attitude", "turns no somersault from the first to the last waypoint",
                                "give a problem file of a somersault (the bundled back-full-twist)")
    ks = abs(somersaults) / abs(tech["somersaults"])
    if abs(tech["twists"]) > 1e-9:   # the file's twist profile, scaled (its direction kept)
        tw = np.asarray(tech["twist"]) * (abs(twists) / abs(tech["twists"]))
    else:                             # no twist in the file: the twist grows with the somersault
        tw = np.asarray(tech["somersault"]) / tech["somersault"][-1] * 360.0 * twists
    som = np.asarray(tech["somersault"]) * ks
    times = (np.asarray(tech["times"]) - tech["times"][0]) * (flight_time / tech["T"])
    atts = [{"euler_deg": [float(s), float(t), float(w)]} for s, t, w in zip(som, tech["tilt"], tw)]
    kw = problem.plan_kwargs()
    kw.update(times=[float(t) for t in times], **rot.attitude_states(atts))
    if kw.get("conditions") is None:
        kw.pop("conditions")
    L = np.asarray(problem.system.L, dtype=float) * ks * (tech["T"] / flight_time)
    return SpatialBody(problem.system.links, L=tuple(float(v) for v in L)), kw


def twist_potential(problem, plan, *, flight_times=None, somersaults=None, resolution: float = DEFAULT_RESOLUTION,
                    time_limit: float | None = None, progress=None, simulate=None) -> list[TwistCell]:
    """The table of the most twist (module docstring): one :class:`TwistCell` per flight time and
    somersault count (default the file's). ``plan`` and ``simulate`` are ``acroplan.plan`` and
    ``acroplan.simulate`` (without ``simulate``, no technique's flight: every target's waypoints
    are the file's scaled)."""
    kw = problem.plan_kwargs()
    if kw.get("conditions") is None:
        kw.pop("conditions")
    if time_limit is not None:
        kw["time_limit"] = time_limit
    if progress is not None:
        progress("the file's own dive (its technique)")
    res = plan(problem.system, **kw)
    if str(getattr(res.status, "value", res.status)) != "success":
        raise InvalidInputError("plan", f"the file's own dive could not be planned ({res.status}): the technique is "
                                "read from its plan", "give a problem file whose plan succeeds (acroplan plan)")
    tech = technique_of(problem, res)
    F = [tech["T"]] if flight_times is None else [float(t) for t in flight_times]
    S = [abs(tech["somersaults"])] if somersaults is None else [float(n) for n in somersaults]
    if not (resolution > 0 and math.isfinite(resolution)):
        raise InvalidInputError("resolution", f"must be a positive number of turns, got {resolution!r}",
                                "give for example 0.25")
    cells = []
    for n in S:
        for T in F:
            cells.append(_cell(problem, tech, plan, T, n, resolution, time_limit, progress, res, simulate))
    return cells


def bisect_twist(reachable, start: float, resolution: float = DEFAULT_RESOLUTION, most: float = MOST_TWISTS):
    """The bisection of the module docstring on ``reachable(x) -> bool`` (``x`` turns of twist):
    from ``start``, doubling while reachable (up to ``most``), then halving the bracket to
    ``resolution`` (targets on multiples of it). Returns ``(lo, hi, tries)``: the most twist
    reached (0.0 when none), the least target not reached (``None`` when every one up to ``most``
    was), and ``[(x, reached), ...]`` in the order tried."""
    tries = []

    def ask(x):
        ok = bool(reachable(x))
        tries.append((float(x), ok))
        return ok

    x = min(max(resolution, round(start / resolution) * resolution), most)
    lo, hi = 0.0, None
    if ask(x):
        lo = x
        while hi is None and x < most:
            x = min(2.0 * x, most)
            if ask(x):
                lo = x
            else:
                hi = x
    else:
        hi = x
    while hi is not None and hi - lo > resolution * (1 + 1e-9):
        mid = round((lo + hi) / 2.0 / resolution) * resolution
        if not lo < mid < hi:
            break
        if ask(mid):
            lo = mid
        else:
            hi = mid
    return lo, hi, tries


def _cell(problem, tech, plan, T, n, resolution, time_limit, progress, own=None, simulate=None):
    start = time.perf_counter()
    status: dict[float, tuple[str, str]] = {}
    body_L = []
    sign_s = math.copysign(1.0, tech["somersaults"])
    sign_t = math.copysign(1.0, tech["twists"]) if abs(tech["twists"]) > 1e-9 else 1.0
    if progress is not None and simulate is not None:
        progress(f"{n:g} somersaults in {T:g} s: the technique's flight")
    try:
        flight = technique_flight(problem, own, tech, T, n, simulate) if own is not None else None
    except IntegrationError:   # a flight the integrator refuses (too fast a motion): the scaled waypoints
        flight = None

    def reachable(x):
        body, kw = scaled_problem(problem, tech, T, n, x, flight=flight)
        body_L[:] = [body.L]
        if time_limit is not None:
            kw["time_limit"] = time_limit
        if progress is not None:
            progress(f"{n:g} somersaults in {T:g} s: {x:g} twists")
        res = plan(body, **kw)
        st = str(getattr(res.status, "value", res.status))
        message = getattr(res, "message", "") or ""
        if st == "success":   # the quaternion waypoints do not fix the turns between them: count them
            som, tw = _counts(res)
            if abs(som - sign_s * n) > COUNT_TOL or abs(tw - sign_t * x) > COUNT_TOL:
                st, message = "other_turns", f"planned, but {som:+.4f} somersaults and {tw:+.4f} twists"
        status[float(x)] = (st, message)
        return st == "success"

    if flight is not None:   # the technique's own twist, rounded down to the resolution
        first = max(resolution, math.floor(abs(flight.twists) / resolution + 1e-9) * resolution)
    else:
        first = abs(tech["twists"]) if abs(tech["twists"]) > 0 else 0.5
    lo, hi, tries = bisect_twist(reachable, first, resolution)
    if hi is None:
        stopped, reason = "resolution", f"every target up to {MOST_TWISTS:g} twists was reached"
    else:
        st, message = status[float(hi)]
        stopped = "proven" if st == "infeasible" else "planner stopped"
        reason = f"{hi:g} twists: {st}" + (f" ({message})" if message else "")
    L = body_L[0] if body_L else problem.system.L
    tw, tilt, peak = ((abs(flight.twists), flight.landing_tilt, flight.peak_rate) if flight is not None
                      else (None, None, None))
    return TwistCell(float(T), float(n), tuple(float(v) for v in L), float(lo), hi, stopped, reason, len(tries),
                     time.perf_counter() - start, tuple((x, status[x][0]) for x, _ in tries), tw, tilt, peak)


def twist_potential_figure(cells):
    """The most twist against flight time, one line per somersault count (the least target not
    reached marked above each point, the technique's flight dashed where the cells have one)."""
    from ...core.plotting import pyplot

    plt = pyplot()

    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    for n in sorted({c.somersaults for c in cells}):
        row = sorted((c for c in cells if c.somersaults == n), key=lambda c: c.flight_time)
        t = [c.flight_time for c in row]
        ax.plot(t, [c.most for c in row], "o-", label=f"{n:g} somersault{'s' if n != 1 else ''}: most reached")
        flown = [c for c in row if c.technique_twists is not None]
        if flown:
            ax.plot([c.flight_time for c in flown], [c.technique_twists for c in flown], "--", color=ax.lines[-1].get_color(),
                    alpha=0.7, label=f"{n:g}: the technique's flight")
        why = sorted({c.stopped for c in row if c.failed is not None})
        ax.plot([c.flight_time for c in row if c.failed is not None], [c.failed for c in row if c.failed is not None],
                "x", color=ax.lines[-1].get_color(), label=f"{n:g}: least not reached ({', '.join(why)})")
    ax.set_xlabel("flight time (s)")
    ax.set_ylabel("twists (turns)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig
