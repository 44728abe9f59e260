"""The coach's question in 3-D: the most twist a body can make in a given flight time and number of
somersaults (``acroplan twist-potential FILE``).

The technique is the file's. A problem file of a twisting somersault (the bundled dives,
``docs/human.md``) gives waypoints in Yeadon's somersault, tilt and twist; the question for a
flight time :math:`T` and :math:`n` somersaults is asked of **the same technique scaled**: the
waypoint times by :math:`T / T_f`, every waypoint's somersault angle by :math:`n / n_f`, its twist
angle by :math:`X / X_f` (:math:`X` the twist target in turns), its tilt and the joint angles kept;
the angular momentum :math:`L = I\\,\\omega` follows the somersault rate, :math:`L = L_f\\,(n / n_f)
(T_f / T)` (the file's subscript :math:`f`). Each target is planned (``plan`` passed in, since a
family does not import the front doors) under the file's joint ranges and rate limits (and torque
limits when the file gives ``tau_max``).

The bisection on :math:`X`: from the file's own twist count (or half a turn), doubling while the
plan succeeds, then halving the bracket to ``resolution`` turns. It reports the most twist reached
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

from ...core.errors import InvalidInputError
from . import rotations as rot

__all__ = ["TwistCell", "file_technique", "scaled_problem", "twist_potential", "twist_potential_figure",
           "DEFAULT_RESOLUTION", "MOST_TWISTS"]

#: the bisection's resolution (turns of twist)
DEFAULT_RESOLUTION = 0.25
#: the doubling stops here (turns)
MOST_TWISTS = 8.0


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

    def to_dict(self) -> dict:
        d = dataclasses.asdict(self)
        d["angular_momentum"] = list(self.angular_momentum)
        d["tries"] = [list(t) for t in self.tries]
        return d


def file_technique(problem) -> dict:
    """The file's waypoints in Yeadon's angles: ``{"times", "somersault", "tilt", "twist"}`` (degrees,
    unwrapped along the waypoints), its somersault and twist counts (turns) and flight time."""
    names = problem.system.state_names
    if tuple(names[:4]) != ("qw", "qx", "qy", "qz"):
        raise InvalidInputError("body", "is not a body in 3-D (its states do not start with the attitude qw, qx, "
                                "qy, qz)", "give a problem file of a spatial body (model = \"3d\")")
    Q = np.array([problem.waypoints[k] for k in ("qw", "qx", "qy", "qz")], dtype=float)
    ang = rot.to_euler(Q)
    som = np.degrees(np.unwrap(np.radians(ang[0])))
    tw = np.degrees(np.unwrap(np.radians(ang[2])))
    times = np.asarray(problem.times, dtype=float)
    return {"times": times, "somersault": som - som[0], "tilt": ang[1], "twist": tw - tw[0],
            "somersaults": float(som[-1] - som[0]) / 360.0, "twists": float(tw[-1] - tw[0]) / 360.0,
            "T": float(times[-1] - times[0])}


def scaled_problem(problem, flight_time: float, somersaults: float, twists: float):
    """``(body, plan keywords)`` of the file's technique scaled (module docstring)."""
    from .model import SpatialBody

    tech = file_technique(problem)
    if abs(tech["somersaults"]) < 1e-9:
        raise InvalidInputError("plan.attitude", "turns no somersault from the first to the last waypoint",
                                "give a problem file of a somersault (the bundled back-full-twist)")
    ks = abs(somersaults) / abs(tech["somersaults"])
    if abs(tech["twists"]) > 1e-9:   # the file's twist profile, scaled (its direction kept)
        tw = tech["twist"] * (abs(twists) / abs(tech["twists"]))
    else:                             # no twist in the file: the twist grows with the somersault
        tw = tech["somersault"] / tech["somersault"][-1] * 360.0 * twists
    som = tech["somersault"] * ks
    times = (tech["times"] - tech["times"][0]) * (flight_time / tech["T"])
    atts = [{"euler_deg": [float(s), float(t), float(w)]} for s, t, w in zip(som, tech["tilt"], tw)]
    kw = problem.plan_kwargs()
    kw.update(times=[float(t) for t in times], **rot.attitude_states(atts))
    if kw.get("conditions") is None:
        kw.pop("conditions")
    L = np.asarray(problem.system.L, dtype=float) * ks * (tech["T"] / flight_time)
    return SpatialBody(problem.system.links, L=tuple(float(v) for v in L)), kw


def twist_potential(problem, plan, *, flight_times=None, somersaults=None, resolution: float = DEFAULT_RESOLUTION,
                    time_limit: float | None = None, progress=None) -> list[TwistCell]:
    """The table of the most twist (module docstring): one :class:`TwistCell` per flight time and
    somersault count (default the file's)."""
    tech = file_technique(problem)
    F = [tech["T"]] if flight_times is None else [float(t) for t in flight_times]
    S = [abs(tech["somersaults"])] if somersaults is None else [float(n) for n in somersaults]
    if not (resolution > 0 and math.isfinite(resolution)):
        raise InvalidInputError("resolution", f"must be a positive number of turns, got {resolution!r}",
                                "give for example 0.25")
    cells = []
    for n in S:
        for T in F:
            cells.append(_cell(problem, plan, T, n, resolution, time_limit, progress))
    return cells


def _cell(problem, plan, T, n, resolution, time_limit, progress):
    start = time.perf_counter()
    tech = file_technique(problem)
    tries: list[tuple[float, str]] = []
    reasons = {}

    def reachable(x):
        body, kw = scaled_problem(problem, T, n, x)
        if time_limit is not None:
            kw["time_limit"] = time_limit
        if progress is not None:
            progress(f"{n:g} somersaults in {T:g} s: {x:g} twists")
        res = plan(body, **kw)
        tries.append((float(x), str(res.status)))
        reasons[x] = (str(res.status), getattr(res, "message", "") or "")
        return res.status == "success", body

    x = max(resolution, round(abs(tech["twists"]) / resolution) * resolution) if abs(tech["twists"]) > 0 else 0.5
    lo, hi, L = 0.0, None, None
    ok, body = reachable(x)
    L = body.L
    if ok:
        lo = x
        while hi is None and x < MOST_TWISTS:
            x = min(2.0 * x, MOST_TWISTS)
            ok, _ = reachable(x)
            if ok:
                lo = x
            else:
                hi = x
    else:
        hi = x
    while hi is not None and hi - lo > resolution + 1e-12:
        mid = round((lo + hi) / 2.0 / resolution) * resolution
        if mid <= lo or mid >= hi:
            break
        ok, _ = reachable(mid)
        if ok:
            lo = mid
        else:
            hi = mid
    if hi is None:
        stopped, reason = "resolution", f"every target up to {MOST_TWISTS:g} twists was reached"
    else:
        status, message = reasons[hi]
        stopped = "proven" if status == "infeasible" else "planner stopped"
        reason = f"{hi:g} twists: {status}" + (f" ({message})" if message else "")
    return TwistCell(float(T), float(n), tuple(float(v) for v in L), float(lo), hi, stopped, reason, len(tries),
                     time.perf_counter() - start, tuple(tries))


def twist_potential_figure(cells):
    """The most twist against flight time, one line per somersault count (the least target not
    reached marked above each point)."""
    from ...core.plotting import pyplot

    plt = pyplot()

    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    for n in sorted({c.somersaults for c in cells}):
        row = sorted((c for c in cells if c.somersaults == n), key=lambda c: c.flight_time)
        t = [c.flight_time for c in row]
        ax.plot(t, [c.most for c in row], "o-", label=f"{n:g} somersault{'s' if n != 1 else ''}: most reached")
        ax.plot([c.flight_time for c in row if c.failed is not None], [c.failed for c in row if c.failed is not None],
                "x", color=ax.lines[-1].get_color(), label=f"{n:g}: least not reached (planner stopped)")
    ax.set_xlabel("flight time (s)")
    ax.set_ylabel("twists (turns)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    return fig
