"""The bundled twisting dives of the 3-D human, and what a planned dive did, in Yeadon's angles.

Each dive is a problem file in ``data/`` (registered as an example of the human family):

* ``back-full-twist``: a back straight somersault with one twist, trampoline, 1.5 s;
* ``forward-double-twist``: a forward 1 1/2 somersault with two twists, 3 m springboard, 1.4 s;
* ``back-double-full-out``: a back double somersault with one twist in the second somersault,
  trampoline, 2.0 s.

The body is Yeadon's male1 with moving shoulders (``joints = "arms"``, straight); the twist is made
in the air by the arms (Yeadon 1993, *The biomechanics of twisting somersaults. Part III: aerial
twist*): one arm comes down from overhead first, which tilts the body, and the other follows,
which takes the tilt out. The waypoints give Yeadon's somersault, tilt and twist (take-off, the
half-way or phase points, the landing) and the arms there; the angular momentum is :math:`L = I
\\omega` of the somersault rate (each file says how). :func:`dive_report` reads the counts from the
planned motion's attitude (unwrapped Yeadon angles), its tilt, its peak joint rates against the
rate limits and its peak torques against the strength data (:mod:`~.strength`).

``acroplan.examples.load(name)`` reads a dive's problem file (the I/O layer; a family does not
import it): ``prob = acroplan.examples.load("back-full-twist")``, then
``acroplan.plan(prob.system, **prob.plan_kwargs())``.
"""

from __future__ import annotations

import dataclasses
import math
from importlib import resources

import numpy as np

from ..spatial import rotations as rot

__all__ = ["DIVES", "dive_path", "DiveReport", "dive_report"]

#: the bundled dives: name -> (file in data/, what it is)
DIVES = {
    "back-full-twist": ("data/back-full-twist.toml", "a back straight somersault with one twist (trampoline, 1.5 s)"),
    "forward-double-twist": ("data/forward-double-twist.toml", "a forward 1 1/2 somersault with two twists (3 m "
                             "springboard, 1.4 s)"),
    "back-double-full-out": ("data/back-double-full-out.toml", "a back double somersault with one twist in the "
                             "second somersault (trampoline, 2.0 s)"),
}


def dive_path(name: str):
    """The bundled problem file of dive ``name`` (a traversable of the package)."""
    if name not in DIVES:
        from ...core.errors import InvalidInputError

        raise InvalidInputError("dive", f"{name!r} is not a bundled dive", f"dives: {sorted(DIVES)}")
    return resources.files(__package__).joinpath(DIVES[name][0])


@dataclasses.dataclass(frozen=True)
class DiveReport:
    """What a planned dive did (:func:`dive_report`).

    Attributes
    ----------
    somersaults, twists : float
        Turns, from the unwrapped Yeadon angles of the pelvis along the motion (signed: a backward
        somersault and a twist of the front to the right are negative).
    tilt_end, peak_tilt : float
        Degrees.
    rates : dict
        ``{joint: (peak |rate|, limit)}`` rad/s.
    torques : dict
        ``{joint: {"peak", "limit", "ratio", "estimate"}}`` (:func:`~.strength.strength_report`).
    t, somersault, tilt, twist : numpy.ndarray
        The Yeadon angles over the flight (turns, degrees, turns).
    """

    somersaults: float
    twists: float
    tilt_end: float
    peak_tilt: float
    rates: dict
    torques: dict
    t: np.ndarray
    somersault: np.ndarray
    tilt: np.ndarray
    twist: np.ndarray

    def summary(self) -> str:
        worst = max(self.torques.items(), key=lambda kv: kv[1]["ratio"])
        rate = max(self.rates.items(), key=lambda kv: kv[1][0] / kv[1][1])
        return (f"{self.somersaults:+.6f} somersaults, {self.twists:+.6f} twists, tilt {self.tilt_end:+.2e} deg at "
                f"the end (peak {self.peak_tilt:.2f} deg); peak rate {rate[1][0]:.2f} of {rate[1][1]:g} rad/s "
                f"({rate[0]}); peak torque {worst[1]['peak']:.1f} of {worst[1]['limit']:g} N m ({worst[0]})")


def dive_report(result, samples: int = 2001, torques: bool = True) -> DiveReport:
    """The counts, tilt, rates and torques of a planned (or simulated) motion of a 3-D human."""
    from .strength import strength_report

    from ..spatial.potential import sampled_states

    t = np.linspace(result.times[0], result.times[-1], int(samples))
    X = sampled_states(result, t)
    ang = np.radians(rot.to_euler(X[:4]))
    som = np.unwrap(ang[0])
    tw = np.unwrap(ang[2])
    som, tw = (som - som[0]) / (2 * math.pi), (tw - tw[0]) / (2 * math.pi)
    tilt = np.degrees(ang[1])
    body = result.system
    U = np.concatenate([np.asarray(result.evaluate(c, effort=False).inputs, dtype=float)
                        for c in np.array_split(t, max(1, -(-len(t) // 500)))], axis=1)
    rates = {}
    for i, link in enumerate(link for link in body.links if link.parent is not None):
        rates[link.joint_name] = (float(np.max(np.abs(U[i]))), math.inf if link.velocity is None else
                                  float(link.velocity))
    tq = strength_report(result) if torques else {}
    return DiveReport(float(som[-1]), float(tw[-1]), float(tilt[-1]), float(np.max(np.abs(tilt))), rates, tq, t, som,
                      tilt, tw)
