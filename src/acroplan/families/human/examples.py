"""Motions a diving coach would recognise: the 10 m platform dive, 3.5 somersaults in pike.

>>> import acroplan
>>> from acroplan.families.human.examples import platform_dive_pike
>>> robot, kw = platform_dive_pike(objective=None)      # the default feasible plan
>>> result = acroplan.plan(robot, **kw)
>>> result.status
'success'

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
  is exact (:func:`~acroplan.families.acrobot.momentum.least_momentum`: the reachable set's end,
  attained only by the bang-dwell-bang motion that pikes and opens at the full 12 rad/s and holds
  the deepest pike in between). A diver takes off with more than that: the plan uses
  :math:`(1 + \\text{margin})` times it, 10 % by default, which lets the hips move below their top
  speed and open earlier for the entry.
* **Waypoints**: take-off straight (hip flexion 0), pike reached at 0.30 s and held (hip flexion
  0.1 rad inside the limit, so that the spline through the waypoints stays inside it), open from
  :math:`T - 0.35` s to straight at entry; :math:`\\theta` from 0 to :math:`7\\pi`, free at the
  pike waypoints (the planner takes the middle of what is reachable).
"""

from __future__ import annotations

import dataclasses
import math

from ...core.errors import InvalidInputError, finite_number
from ...core.limits import Limits
from ..acrobot.model import Acrobot
from ..acrobot.momentum import MomentumBound, least_momentum
from .body import SagittalBody
from .limits import human_limits, position

__all__ = ["flight_time", "PlatformDive", "platform_dive", "platform_dive_pike", "GRAVITY"]

#: Standard gravity (m/s²).
GRAVITY = 9.81


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
    margin : float
        :math:`P_0` is ``(1 + margin) * least.P0``.
    hip_flexion : tuple of float
        The waypoints' hip flexion (rad).
    """

    body: SagittalBody
    robot: Acrobot
    kw: dict
    limits: Limits
    flight_time: float
    least: MomentumBound
    margin: float
    hip_flexion: tuple[float, ...]

    @property
    def P0(self) -> float:
        return self.robot.P0


def platform_dive(body: SagittalBody | None = None, *, somersaults: float = 3.5, platform: float = 10.0,
                  rise: float = 0.2, margin: float = 0.10, pike_time: float = 0.30, open_time: float = 0.35,
                  objective: str | None = "energy") -> PlatformDive:
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
    margin : float
        :math:`P_0` above the least, as a fraction (0.10: 10 % more), > 0.
    pike_time : float
        When the pike is reached (s after take-off).
    open_time : float
        How long before entry the opening starts (s).
    objective : {"energy", "torque"} or None
        Passed to :func:`acroplan.plan` (``None``: leave it out, the default feasible plan).

    Returns
    -------
    PlatformDive
    """
    if body is None:
        from .yeadon_body import from_yeadon

        body = from_yeadon()
    n = finite_number("somersaults", somersaults)
    if not n > 0:
        raise InvalidInputError("somersaults", f"must be > 0, got {n:g}", "give for example 3.5")
    margin = finite_number("margin", margin)
    if not margin > 0:
        raise InvalidInputError("margin", f"must be > 0, got {margin:g}: at the least momentum only the "
                                "bang-dwell-bang motion at the rate limits turns far enough, and no smooth one does",
                                "give for example 0.10")
    T = flight_time(platform, rise)
    t_in, t_out = finite_number("pike_time", pike_time), T - finite_number("open_time", open_time)
    if not 0 < t_in < t_out < T:
        raise InvalidInputError("pike_time", f"the pike at {t_in:g} s and the opening at {t_out:g} s must be in order "
                                f"inside the flight of {T:.4g} s", "shorten pike_time or open_time")
    limits = human_limits(body, "pike", links=2)
    lo, hi = limits.bounds("phi")
    psi_pike = position("pike").hip[1] - 0.1
    psi = (0.0, psi_pike, psi_pike, 0.0)
    phi = [float(body.phi(p)) for p in psi]
    thetaT = 2.0 * math.pi * n
    least = least_momentum(body.two_link(angular_momentum=1.0), theta0=0.0, thetaT=thetaT, phi0=phi[0], phiT=phi[-1],
                           T=T, limits=limits)
    if not least.success:  # pragma: no cover - a pike always turns forwards with enough momentum
        raise InvalidInputError("somersaults", least.message, "lower the somersaults or raise the platform")
    robot = body.two_link(angular_momentum=(1.0 + margin) * least.P0)
    kw = dict(times=[0.0, t_in, t_out, T], theta=[0.0, None, None, thetaT], phi=phi, limits=limits,
              conditions="spline")
    if objective is not None:
        kw["objective"] = objective
    return PlatformDive(body=body, robot=robot, kw=kw, limits=limits, flight_time=T, least=least, margin=margin,
                        hip_flexion=psi)


def platform_dive_pike(body: SagittalBody | None = None, **options) -> tuple[Acrobot, dict]:
    """A 10 m platform dive, 3.5 forward somersaults in pike: ``(robot, plan keywords)``.

    ``acroplan.plan(robot, **kw)`` plans it; ``options`` are :func:`platform_dive`'s
    (``objective="energy"`` by default: the minimum :math:`\\int u^2` plan; ``objective=None`` for
    the fast feasible plan).

    Returns
    -------
    (Acrobot, dict)
    """
    dive = platform_dive(body, **options)
    return dive.robot, dive.kw
