"""Motions a diving coach would recognise: the 10 m platform dive, 3.5 somersaults in pike.

>>> import acroplan
>>> from acroplan.families.human.examples import platform_dive_pike
>>> robot, kw = platform_dive_pike(objective=None)      # the fast feasible plan of the default problem
>>> result = acroplan.plan(robot, **kw)
>>> str(result.status)
'success'

What a user gets by default
---------------------------
``platform_dive_pike()`` gives the problem of a forward 3.5-somersault pike dive from 10 m with
**two waypoints**, take-off and entry, both straight at the hips, with the hip rates at take-off
and at entry left free (``conditions="free"``, no ``start_rate``/``end_rate``), under a diver's
hip range and rate limits, and ``objective="energy"`` (minimum :math:`\\int u^2`). The diver
leaves the platform already piking (elite divers flex their hips fast during the take-off: the
11.0 to 12.8 rad/s of Murtaugh 2000) and enters at the end of the kick-out; the optimiser chooses
when and how deep to pike. Measured on the bundled ``male1``: the plan converges (largest relative
KKT residual 7.3e-10, 30 coefficients) with a peak hip rate of 6.90 rad/s (below the lower
literature value, 11.0 rad/s), the hips flexed up to 149.6 degrees (the pike's limit is 150) and
a peak hip torque (both hips) of 235.5 N m, the flexors holding the pike against the spin: below
an elite gymnast's largest isometric hip flexion torque, 314.6 N m for both hips
(:func:`~acroplan.families.human.limits.hip_torque_literature`). It took 2.2 s and 4.0 s in two
runs (2 cores shared with other work; a new process compiles the integrators first, a few seconds
more). docs/human.md gives the table, made by::

    python -c "import acroplan; from acroplan.families.human.figures import dive_table; print(dive_table(acroplan.plan))"

Why two waypoints: with the hips pinned at rest at take-off and entry and the pike imposed at
interior waypoints (``through_pike=True``, the reference problem below), the least
:math:`\\int u^2` is made of boundary layers (the rate jumps near the pinned ends and the
waypoints, which :math:`\\int u^2` does not penalise) and the hip torque that makes them reaches
6186 N m: not a motion a diver can make. ``objective="torque"`` (least :math:`\\int \\tau^2`)
on the default problem is smooth too, but stops at 10 coefficients with its cost still falling
(not converged) and peaks at 11.8 rad/s; ``objective=None`` is the fast feasible plan.

The problem (:func:`platform_dive`)
-----------------------------------
* **Body**: Yeadon's model of the bundled ``male1`` measurements (58.2 kg), split at the hips
  (:meth:`~acroplan.families.human.body.SagittalBody.two_link`), arms along the trunk.
* **Flight time** (:func:`flight_time`): the centre of mass rises :math:`r` above its take-off
  height and the flight ends at entry, when the hands reach the water with the centre of mass as
  high above the water as it was above the platform at take-off (body vertical and straight, arms
  overhead: about a metre above the hands, as at take-off above the feet). So it falls
  :math:`H + r` from the peak:

  .. math::  T = \\sqrt{2r/g} + \\sqrt{2(H + r)/g} ,

  and :math:`H = 10` m, :math:`r = 0.2` m, :math:`g = 9.81` m/s² give :math:`T = 1.644` s. The
  rise is the assumption: 0.5 m gives 1.78 s.
* **Limits** of a diver in pike (:func:`~acroplan.families.human.limits.human_limits`): hip flexion
  from -30 to 150 degrees, hip rate 12 rad/s.
* **Angular momentum**: the least :math:`P_0` for 3.5 somersaults in :math:`T` under these limits
  is exact (:func:`~acroplan.families.acrobot.momentum.least_momentum`: the end of the reachable
  set, attained only by the bang-dwell-bang motion that pikes and opens at the full 12 rad/s and
  holds the deepest pike in between): 57.2 kg m²/s for ``male1``. No diver moves like that. The
  margin above it is chosen by a motion a diver could make, the *reference*: minimum-jerk hip
  ramps (:math:`\\psi = \\psi_p (10 s^3 - 15 s^4 + 6 s^5)`, :math:`s = t/\\tau`) into a pike
  :math:`\\psi_p` 0.1 rad short of the limit, peaking at 11 rad/s (the lower of the literature's
  two mean peak hip rates), the same ramp out before entry, the pike held in between. The
  :math:`P_0` with which the reference turns exactly 3.5 somersaults, 65.7 kg m²/s for ``male1``,
  is 14.9 % above the least. (``margin=`` instead fixes :math:`P_0` as a multiple of the least and
  finds the ramp time :math:`\\tau` for which the reference turns 3.5 somersaults.) The reference
  sets :math:`P_0` only: the default plan is not asked to follow it.
* **Waypoints** (default): take-off straight at the hips (hip flexion 0) with :math:`\\theta =
  -\\pi/2` (upright: the legs below the hips, the :math:`x` axis horizontal), entry straight with
  :math:`\\theta = -\\pi/2 + 7\\pi` (head down), the hip rates at both free.
* **Waypoints** (``through_pike=True``, the reference problem): take-off straight, pike at
  :math:`\\tau`, still pike at :math:`T - \\tau`, straight at entry, the hips at rest at take-off
  and at entry (``start_rate = end_rate = 0``); :math:`\\theta` at the pike waypoints the
  reference's (its exact integral
  :math:`\\theta(t) = -(F(\\varphi(t)) - F(\\varphi_0)) + P_0\\int_0^t dt'/h(\\varphi)`). Its
  feasible plan (``objective=None``) is a smooth motion; its energy-optimal plan is the boundary
  layers above.
* **Objective**: ``objective="energy"`` by default; ``"torque"`` or ``None`` (the feasible plan)
  on request.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from scipy.integrate import quad
from scipy.optimize import brentq

from ...core.errors import InvalidInputError, finite_number
from ...core.limits import Limits
from ..acrobot.model import Acrobot
from ..acrobot.momentum import MomentumBound, least_momentum
from .body import SagittalBody
from .limits import human_limits, position

__all__ = ["flight_time", "minimum_jerk", "ReferenceMotion", "PlatformDive", "platform_dive", "platform_dive_pike",
           "GRAVITY", "THETA0"]

#: Standard gravity (m/s²).
GRAVITY = 9.81

#: The take-off's :math:`\\theta`: the line from the hips to the legs' centre of mass points down.
THETA0 = -0.5 * math.pi


def flight_time(platform: float = 10.0, rise: float = 0.2, g: float = GRAVITY) -> float:
    """The flight time of a platform dive (module docstring: the assumption on the entry):
    :math:`T = \\sqrt{2r/g} + \\sqrt{2(H + r)/g}`.

    Parameters
    ----------
    platform : float
        :math:`H` (m), the platform's height above the water.
    rise : float
        :math:`r` (m), how far the centre of mass rises above its take-off height.
    g : float
        Gravity (m/s²).

    Returns
    -------
    float
        Seconds.

    Examples
    --------
    >>> round(flight_time(10.0, 0.2), 3)
    1.644
    """
    H, r, g = finite_number("platform", platform), finite_number("rise", rise), finite_number("g", g)
    if not H > 0:
        raise InvalidInputError("platform", f"must be > 0, got {H:g}", "give the height above the water in m")
    if not r >= 0:
        raise InvalidInputError("rise", f"must be >= 0, got {r:g}", "give the rise of the centre of mass in m")
    if not g > 0:
        raise InvalidInputError("g", f"must be > 0, got {g:g}", "give 9.81")
    return math.sqrt(2.0 * r / g) + math.sqrt(2.0 * (H + r) / g)


def minimum_jerk(s):
    """:math:`10 s^3 - 15 s^4 + 6 s^5` on :math:`[0, 1]` (0 and 1 outside): a rest-to-rest ramp
    whose rate peaks at :math:`15/8` of its mean at :math:`s = 1/2`."""
    s = np.clip(np.asarray(s, dtype=float), 0.0, 1.0)
    return s**3 * (10.0 - 15.0 * s + 6.0 * s**2)


@dataclasses.dataclass(frozen=True)
class ReferenceMotion:
    """The diver's reference hip motion (module docstring): minimum-jerk ramps of duration
    :math:`\\tau` from straight to the pike :math:`\\psi_p` and back before entry.

    Attributes
    ----------
    pike : float
        :math:`\\psi_p` (rad).
    ramp : float
        :math:`\\tau` (s).
    duration : float
        :math:`T` (s).
    """

    pike: float
    ramp: float
    duration: float

    def hip_flexion(self, t):
        """:math:`\\psi(t)` (rad), array_like ``t`` in :math:`[0, T]`."""
        t = np.asarray(t, dtype=float)
        return self.pike * minimum_jerk(np.minimum(t, self.duration - t) / self.ramp)

    @property
    def peak_rate(self) -> float:
        """:math:`15\\psi_p / (8\\tau)` (rad/s)."""
        return 1.875 * self.pike / self.ramp

    def turn_integral(self, body: SagittalBody, t: float) -> float:
        """:math:`\\int_0^t dt'/h(\\varphi(t'))` of the two-link body (unit :math:`P_0`), by adaptive
        quadrature (scipy ``quad``, tolerance 1e-13) split at the ramps' ends."""
        robot = body.two_link(angular_momentum=1.0)
        f = lambda x: 1.0 / float(robot.h(body.phi(float(self.hip_flexion(x)))))  # noqa: E731
        pts = sorted(p for p in (self.ramp, self.duration - self.ramp) if 0.0 < p < t)
        total, lo = 0.0, 0.0
        for hi in pts + [t]:
            total += quad(f, lo, hi, epsabs=1e-13, epsrel=1e-13, limit=200)[0]
            lo = hi
        return total

    def theta(self, body: SagittalBody, P0: float, t: float) -> float:
        """:math:`\\theta(t) = -(F(\\varphi(t)) - F(\\varphi(0))) + P_0 \\int_0^t dt'/h` from
        :math:`\\theta(0) = 0`."""
        robot = body.two_link(angular_momentum=P0)
        phi0, phit = body.phi(float(self.hip_flexion(0.0))), body.phi(float(self.hip_flexion(t)))
        return -(float(robot.F(phit)) - float(robot.F(phi0))) + P0 * self.turn_integral(body, t)


@dataclasses.dataclass(frozen=True)
class PlatformDive:
    """A platform dive for the two-link body, with how it was found (:func:`platform_dive`).

    Attributes
    ----------
    body : SagittalBody
    robot : Acrobot
        The body split at the hips, at the chosen :math:`P_0`.
    kw : dict
        The keywords of :func:`acroplan.plan` (``acroplan.plan(robot, **kw)``).
    limits : acroplan.Limits
    flight_time : float
    least : MomentumBound
        The least :math:`P_0` for the turn under the limits (exact).
    reference : ReferenceMotion
        The hip motion that sets :math:`P_0` (and, with ``through_pike``, the pike waypoints'
        :math:`\\theta`).
    through_pike : bool
        Whether the problem is the four-waypoint reference problem (:func:`platform_dive`).
    """

    body: SagittalBody
    robot: Acrobot
    kw: dict
    limits: Limits
    flight_time: float
    least: MomentumBound
    reference: ReferenceMotion
    through_pike: bool = False

    @property
    def P0(self) -> float:
        return self.robot.P0

    @property
    def margin(self) -> float:
        """:math:`P_0` above the least, as a fraction."""
        return self.P0 / self.least.P0 - 1.0


def platform_dive(body: SagittalBody | None = None, *, somersaults: float = 3.5, platform: float = 10.0,
                  rise: float = 0.2, ramp_rate: float = 11.0, margin: float | None = None,
                  objective: str | None = "energy", through_pike: bool = False) -> PlatformDive:
    """A forward platform dive in pike for the two-link body (module docstring).

    Parameters
    ----------
    body : SagittalBody, optional
        Straight knees (a pike). Default: :func:`~acroplan.families.human.from_yeadon` of the
        bundled ``male1`` (needs yeadon).
    somersaults : float
        Forward somersaults, :math:`\\Delta\\theta = 2\\pi n`.
    platform, rise : float
        :func:`flight_time`'s :math:`H` and :math:`r` (m).
    ramp_rate : float
        The reference's peak hip rate (rad/s): its ramp time is :math:`\\tau = 15\\psi_p/(8 u)`, and
        :math:`P_0` the momentum with which it turns exactly ``somersaults``.
    margin : float, optional
        Instead: :math:`P_0 = (1 + \\text{margin})` times the least (> 0), and :math:`\\tau` the ramp
        time with which the reference turns exactly ``somersaults`` (``ramp_rate`` unused).
    objective : {"energy", "torque"} or None
        Passed to :func:`acroplan.plan` (``None``: left out, the default feasible plan).
    through_pike : bool
        ``False`` (default): two waypoints, take-off and entry straight at the hips, hip rates
        free at both. ``True``: the reference problem, four waypoints (take-off, pike at
        :math:`\\tau`, pike at :math:`T - \\tau`, entry), the hips at rest at take-off and entry
        (module docstring: its energy-optimal plan is not a human motion).

    Returns
    -------
    PlatformDive
    """
    if not isinstance(through_pike, bool):
        raise InvalidInputError("through_pike", f"must be True or False, got {through_pike!r}",
                                "leave it out for the two-waypoint dive")
    if body is None:
        from .yeadon_body import from_yeadon

        body = from_yeadon()
    n = finite_number("somersaults", somersaults)
    if not n > 0:
        raise InvalidInputError("somersaults", f"must be > 0, got {n:g}", "give for example 3.5")
    T = flight_time(platform, rise)
    limits = human_limits(body, "pike", links=2)
    u_max = limits.input_bound("u")
    psi_p = position("pike").hip[1] - 0.1
    thetaT = 2.0 * math.pi * n
    phi0 = phiT = float(body.phi(0.0))
    least = least_momentum(body.two_link(angular_momentum=1.0), theta0=0.0, thetaT=thetaT, phi0=phi0, phiT=phiT,
                           T=T, limits=limits)
    if not least.success:  # pragma: no cover - a pike always turns forwards with enough momentum
        raise InvalidInputError("somersaults", least.message, "lower the somersaults or raise the platform")
    if margin is None:
        rate = finite_number("ramp_rate", ramp_rate)
        if not 0 < rate:
            raise InvalidInputError("ramp_rate", f"must be > 0, got {rate:g}", f"give for example 11 (<= {u_max:g})")
        ref = ReferenceMotion(psi_p, 1.875 * psi_p / rate, T)
        if not 2.0 * ref.ramp < T:
            raise InvalidInputError("ramp_rate", f"ramps of {ref.ramp:.3g} s do not fit twice in the flight of "
                                    f"{T:.4g} s", "raise ramp_rate")
        P0 = thetaT / ref.turn_integral(body, T)  # F(phi(T)) = F(phi(0)): straight at both ends
    else:
        margin = finite_number("margin", margin)
        if not margin > 0:
            raise InvalidInputError("margin", f"must be > 0, got {margin:g}: at the least momentum only the "
                                    "bang-dwell-bang motion at the rate limits turns far enough, and no smooth one does",
                                    "give for example 0.15")
        P0 = (1.0 + margin) * least.P0

        def short(tau):
            return P0 * ReferenceMotion(psi_p, tau, T).turn_integral(body, T) - thetaT

        hi = 0.5 * T * (1.0 - 1e-9)
        if short(hi) > 0:
            raise InvalidInputError("margin", f"{margin:g} is so large that the reference turns more than "
                                    f"{n:g} somersaults even with the slowest ramps", "lower the margin")
        lo = 1e-3
        if short(lo) < 0:  # pragma: no cover - margin > 0 and the fastest ramp is near the extremal
            raise InvalidInputError("margin", f"{margin:g} is too small for a smooth motion", "raise the margin")
        ref = ReferenceMotion(psi_p, brentq(short, lo, hi, xtol=1e-13), T)
    robot = body.two_link(angular_momentum=P0)
    if through_pike:
        t_in, t_out = ref.ramp, T - ref.ramp
        # theta0 = -pi/2: the legs point down at take-off (the x axis is horizontal), the head up
        theta = [THETA0, THETA0 + ref.theta(body, P0, t_in), THETA0 + ref.theta(body, P0, t_out), THETA0 + thetaT]
        phi = [phi0, float(body.phi(psi_p)), float(body.phi(psi_p)), phiT]
        kw = dict(times=[0.0, t_in, t_out, T], theta=theta, phi=phi, limits=limits, conditions="free",
                  start_rate=0.0, end_rate=0.0)
    else:  # take-off and entry only, the hip rates free at both
        kw = dict(times=[0.0, T], theta=[THETA0, THETA0 + thetaT], phi=[phi0, phiT], limits=limits,
                  conditions="free")
    if objective is not None:
        kw["objective"] = objective
    return PlatformDive(body=body, robot=robot, kw=kw, limits=limits, flight_time=T, least=least, reference=ref,
                       through_pike=through_pike)


def platform_dive_pike(body: SagittalBody | None = None, **options) -> tuple[Acrobot, dict]:
    """A 10 m platform dive, 3.5 forward somersaults in pike: ``(robot, plan keywords)``.

    ``acroplan.plan(robot, **kw)`` plans it; ``options`` are :func:`platform_dive`'s (by default
    two waypoints, take-off and entry, with the hip rates free at both, and ``objective="energy"``:
    the minimum :math:`\\int u^2` plan; ``objective=None`` for the fast feasible plan;
    ``through_pike=True`` for the four-waypoint reference problem).

    Returns
    -------
    (Acrobot, dict)
    """
    dive = platform_dive(body, **options)
    return dive.robot, dive.kw
