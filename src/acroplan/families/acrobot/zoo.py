"""Random problem generators shared by tests and benchmarks.

:func:`random_body` draws a physical acrobot: masses 5-60, joint-to-centre-of-mass distances
0.2-0.6, inertias within 20% of a uniform rod's (a rod of length 2L about its middle:
:math:`M L^2/3`), :math:`|P_0|` in 0.5-30 of either sign.
:func:`random_segment` adds a single segment: duration 0.5-3, any :math:`\\varphi(0)`,
:math:`\\varphi(T)` within :math:`\\pi` of it, and a target :math:`\\theta(T)` drawn uniformly in the
middle ``band`` fraction of the exact reachable interval.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .model import Acrobot

__all__ = ["random_body", "random_segment", "SegmentProblem"]


def random_body(rng: np.random.Generator) -> Acrobot:
    """A random physical acrobot (see module docstring)."""
    M, m = rng.uniform(5, 60, size=2)
    L, l = rng.uniform(0.2, 0.6, size=2)
    J = M * L**2 / 3 * rng.uniform(0.8, 1.2)
    j = m * l**2 / 3 * rng.uniform(0.8, 1.2)
    P0 = rng.uniform(0.5, 30) * rng.choice([-1.0, 1.0])
    return Acrobot.from_physical(torso_mass=M, leg_mass=m, torso_inertia=J, leg_inertia=j, torso_length=L,
                                 leg_length=l, angular_momentum=P0)


@dataclasses.dataclass(frozen=True)
class SegmentProblem:
    """One random single-segment problem."""

    robot: Acrobot
    T: float
    theta0: float
    phi0: float
    thetaT: float
    phiT: float
    interval: tuple[float, float]

    def plan_kwargs(self) -> dict:
        return dict(times=[0.0, self.T], theta=[self.theta0, self.thetaT], phi=[self.phi0, self.phiT])


def random_segment(rng: np.random.Generator, band: float = 0.96, draw_w=None) -> SegmentProblem:
    """A random single-segment problem (see module docstring).

    ``draw_w(rng)``, if given, draws the target's relative position in the interval instead of the
    middle ``band`` (values outside [0, 1] make an infeasible problem).
    """
    robot = random_body(rng)
    T = rng.uniform(0.5, 3.0)
    phi0 = rng.uniform(-np.pi, np.pi)
    phiT = phi0 + rng.uniform(-np.pi, np.pi)
    theta0 = rng.uniform(-np.pi, np.pi)
    lo, hi = robot.reachable_interval(theta0=theta0, phi0=phi0, phiT=phiT, T=T)
    w = draw_w(rng) if draw_w is not None else rng.uniform(0.5 - band / 2, 0.5 + band / 2)
    return SegmentProblem(robot, T, theta0, phi0, lo + w * (hi - lo), phiT, (lo, hi))
