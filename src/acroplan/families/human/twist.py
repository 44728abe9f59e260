"""Aerial twist from an asymmetric limb movement: what one arm lowered, or one leg swung out sideways,
during a somersault does to the tilt and the twist (Yeadon 1993, *The biomechanics of twisting
somersaults. Part III: aerial twist*, J. Sports Sci. 11:209-218: tilt from asymmetric movements of
the arms, chest or hips).

The body is the 3-D human (:func:`~acroplan.families.human.spatial_body.spatial_from_yeadon`,
straight) in a layout somersault with its angular momentum :math:`L` along yeadon's lateral axis x
(:math:`L_x < 0`: a backward somersault), taking off with both arms overhead (abduction
:math:`\\pi`), the legs together. Between ``start`` and ``start + duration`` one joint angle moves by
a minimum-jerk move from :math:`a_0` to :math:`a_1`,

.. math::  a(t) = a_0 + (a_1 - a_0)\\,(10\\sigma^3 - 15\\sigma^4 + 6\\sigma^5) ,\\qquad
           \\sigma = (t - t_0)/\\tau ,\\qquad
           \\dot a = \\frac{a_1 - a_0}{\\tau}\\,(30\\sigma^2 - 60\\sigma^3 + 30\\sigma^4)

(peak rate :math:`1.875\\,|a_1 - a_0|/\\tau` at mid-move), and is held there:

* :func:`asymmetric_arm_twist` (the ``"arms"`` body): one arm is lowered sideways to the side,
  shoulder abduction :math:`\\pi \\to 0`;
* :func:`asymmetric_hip_twist` (the ``"arms+hips"`` body, the arms held overhead): one leg is
  swung out sideways, hip abduction :math:`0 \\to` ``angle`` (40 degrees by default, inside the
  data's 45: ``data/limits_3d.toml``).

The asymmetry turns the body's principal axes away from the angular momentum: the body tilts and,
tilted, twists (Yeadon 1993, Part I: a rigid body at constant tilt :math:`\\theta` twists
:math:`(A/C - 1)\\sin\\theta` times per somersault). The motion is a forward simulation
(:func:`acroplan.simulate`, passed in, since a family does not import the front doors), its inputs
exact polynomials in the monomial basis; the result reports the pelvis's Yeadon angles
(:func:`~acroplan.families.spatial.rotations.to_euler`: somersault and twist in turns, tilt in
degrees) over the flight.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...core.errors import InvalidInputError, finite_number
from ..spatial import rotations as rot
from ..spatial.model import SpatialBody, kinematic_locked_inertia
from .spatial_body import PRESETS, spatial_from_yeadon

__all__ = ["ArmTwist", "arm_twist_problem", "asymmetric_arm_twist", "hip_twist_problem", "asymmetric_hip_twist",
           "HIP_ANGLE"]

_N = 5  # monomial coefficients per segment (the minimum-jerk rate is quartic): one compilation
#: the hip abduction of :func:`hip_twist_problem` by default (rad): 40 degrees, inside the data's 45
HIP_ANGLE = math.radians(40.0)


@dataclasses.dataclass(frozen=True)
class ArmTwist:
    """The Yeadon angles of a simulated flight (:func:`asymmetric_arm_twist`,
    :func:`asymmetric_hip_twist`).

    Attributes
    ----------
    result : acroplan.PlanResult
        The simulation (Pinocchio-checked when ``verify`` was true).
    t : numpy.ndarray, shape (N,)
    somersault, twist : numpy.ndarray, shape (N,)
        Unwrapped, in turns (revolutions), from 0 at take-off.
    tilt : numpy.ndarray, shape (N,)
        Degrees.
    arm : str
        ``"left"``, ``"right"`` or ``"both"``: the side(s) moved.
    limb : str
        ``"arm"`` (lowered) or ``"leg"`` (swung out).
    """

    result: object
    t: np.ndarray
    somersault: np.ndarray
    tilt: np.ndarray
    twist: np.ndarray
    arm: str
    limb: str = "arm"

    @property
    def final(self) -> tuple[float, float, float]:
        """(somersault turns, tilt degrees, twist turns) at the end of the flight."""
        return float(self.somersault[-1]), float(self.tilt[-1]), float(self.twist[-1])

    @property
    def peak_tilt(self) -> float:
        """The largest :math:`|\\theta|` over the flight (degrees)."""
        return float(np.max(np.abs(self.tilt)))

    def summary(self) -> str:
        s, th, tw = self.final
        who = f"both {self.limb}s" if self.arm == "both" else f"{self.arm} {self.limb}"
        how = "lowered" if self.limb == "arm" else "swung out"
        return (f"{who} {how}: {s:.3f} somersaults, {tw:+.3f} twists, tilt {th:+.2f} deg at the end "
                f"(peak {self.peak_tilt:.2f} deg) in {self.t[-1]:.3g} s")


def _flight(t0, tau, T):
    t0 = finite_number("start", t0)
    tau = finite_number("duration", tau)
    T = finite_number("flight_time", T)
    if not (0.0 < t0 and 0.0 < tau and t0 + tau < T):
        raise InvalidInputError("duration", f"the move [{t0:g}, {t0 + tau:g}] s must lie inside the flight (0, {T:g}) s",
                                "give 0 < start and start + duration < flight_time")
    return t0, tau, T


def _one_move(body, preset, side, joint, a0, a1, t0, tau, T, angular_momentum):
    """The body (with :math:`L`) and :func:`acroplan.simulate`'s keywords: ``joint`` of ``side``
    (or of both sides) moved from ``a0`` to ``a1`` by the minimum-jerk move (module docstring),
    from the take-off shape (the shoulders abducted :math:`\\pi`, every other joint 0); the callers
    check ``side`` under their own parameter's name."""
    if body is None:
        body = spatial_from_yeadon(joints=preset)
    if body.links.joint_names != PRESETS[preset]:
        raise InvalidInputError("body", f"must have the {preset!r} joints {list(PRESETS[preset])}, got "
                                f"{list(body.links.joint_names)}", f"build it with spatial_from_yeadon(joints={preset!r})")
    names = body.links.joint_names
    start_shape = np.array([math.pi if n.endswith("shoulder_abduction") else 0.0 for n in names])
    moving = [i for i, n in enumerate(names) if n.endswith(joint) and (side == "both" or n.startswith(side))]
    start_shape[moving] = a0
    if angular_momentum is None:
        Lx = -2.0 * math.pi * kinematic_locked_inertia(body.links, start_shape)[0, 0] / T
    else:
        Lx = finite_number("angular_momentum", angular_momentum)
    body = SpatialBody(body.links, L=(Lx, 0.0, 0.0))
    rate = np.zeros(_N)
    rate[2:5] = np.array([30.0, -60.0, 30.0]) * ((a1 - a0) / tau)   # d/dt of the minimum-jerk move, in sigma
    still = np.zeros((len(names), _N))
    move = still.copy()
    move[moving] = rate
    kw = dict(times=[0.0, t0, t0 + tau, T], inputs=[still, move, still], basis="monomial", qw=1.0, qx=0.0, qy=0.0,
              qz=0.0, **{n: float(v) for n, v in zip(names, start_shape)})
    return body, kw


def arm_twist_problem(body: SpatialBody | None = None, *, arm: str = "right", start: float = 0.1,
                      duration: float = 0.3, flight_time: float = 1.5, angular_momentum: float | None = None):
    """The body and the keywords of :func:`acroplan.simulate` for :func:`asymmetric_arm_twist`.

    Parameters
    ----------
    body : SpatialBody, optional
        A 3-D human with the ``"arms"`` joints (default: male1, straight, the data's limits).
    arm : {"right", "left", "both"}
        The arm lowered (``"both"``: the symmetric control, which neither tilts nor twists).
    start, duration : float
        When the arm starts to move and how long it takes (s).
    flight_time : float
        s.
    angular_momentum : float, optional
        :math:`L_x` (kg m²/s, < 0 backwards). Default: one backward somersault's worth in the
        take-off shape, :math:`-2\\pi I_{xx}/T` (the arm's move changes the count a little).

    Returns
    -------
    (SpatialBody, dict)
    """
    if arm not in ("right", "left", "both"):
        raise InvalidInputError("arm", f"must be 'right', 'left' or 'both', got {arm!r}", "give the arm lowered")
    t0, tau, T = _flight(start, duration, flight_time)
    return _one_move(body, "arms", arm, "shoulder_abduction", math.pi, 0.0, t0, tau, T, angular_momentum)


def hip_twist_problem(body: SpatialBody | None = None, *, leg: str = "right", angle: float = HIP_ANGLE,
                      start: float = 0.1, duration: float = 0.3, flight_time: float = 1.5,
                      angular_momentum: float | None = None):
    """The body and the keywords of :func:`acroplan.simulate` for :func:`asymmetric_hip_twist`.

    Parameters
    ----------
    body : SpatialBody, optional
        A 3-D human with the ``"arms+hips"`` joints (default: male1, straight, the data's limits).
    leg : {"right", "left", "both"}
        The leg swung out (``"both"``: the symmetric control, a straddle, which neither tilts nor
        twists).
    angle : float
        The hip abduction it ends at (rad; default :data:`HIP_ANGLE`).
    start, duration, flight_time, angular_momentum
        As :func:`arm_twist_problem`.

    Returns
    -------
    (SpatialBody, dict)
    """
    if leg not in ("right", "left", "both"):
        raise InvalidInputError("leg", f"must be 'right', 'left' or 'both', got {leg!r}", "give the leg swung out")
    angle = finite_number("angle", angle)
    t0, tau, T = _flight(start, duration, flight_time)
    return _one_move(body, "arms+hips", leg, "hip_abduction", 0.0, angle, t0, tau, T, angular_momentum)


def _angles(simulate, body, kw, samples, verify, side, limb) -> ArmTwist:
    res = simulate(body, verify=verify, **kw)
    t = np.linspace(0.0, kw["times"][-1], int(samples))
    X = res.evaluate(t, effort=False).states
    ang = np.radians(rot.to_euler(X[:4]))
    som = np.unwrap(ang[0])
    tw = np.unwrap(ang[2])
    return ArmTwist(res, t, (som - som[0]) / (2 * math.pi), np.degrees(ang[1]), (tw - tw[0]) / (2 * math.pi), side,
                    limb)


def asymmetric_arm_twist(simulate, body: SpatialBody | None = None, *, samples: int = 301, verify=True,
                         **options) -> ArmTwist:
    """Simulate :func:`arm_twist_problem` and read the pelvis's Yeadon angles over the flight.

    Parameters
    ----------
    simulate : callable
        :func:`acroplan.simulate`.
    body : SpatialBody, optional
    samples : int
        Times at which the angles are read (evenly spaced; unwrapping needs less than half a turn
        between samples).
    verify : bool or str
        ``simulate``'s check (Pinocchio's centroidal momentum by default).
    **options
        ``arm``, ``start``, ``duration``, ``flight_time``, ``angular_momentum`` of
        :func:`arm_twist_problem`.

    Returns
    -------
    ArmTwist

    Examples
    --------
    >>> import acroplan                                                      # doctest: +SKIP
    >>> from acroplan.families.human.twist import asymmetric_arm_twist       # doctest: +SKIP
    >>> print(asymmetric_arm_twist(acroplan.simulate).summary())             # doctest: +SKIP
    """
    body, kw = arm_twist_problem(body, **options)
    return _angles(simulate, body, kw, samples, verify, options.get("arm", "right"), "arm")


def asymmetric_hip_twist(simulate, body: SpatialBody | None = None, *, samples: int = 301, verify=True,
                         **options) -> ArmTwist:
    """Simulate :func:`hip_twist_problem` (one leg swung out sideways, the arms overhead) and read
    the pelvis's Yeadon angles over the flight; parameters as :func:`asymmetric_arm_twist`, with
    ``leg``, ``angle``, ``start``, ``duration``, ``flight_time``, ``angular_momentum`` of
    :func:`hip_twist_problem` as ``options``.

    Returns
    -------
    ArmTwist
        Its ``limb`` is ``"leg"``.

    Examples
    --------
    >>> import acroplan                                                      # doctest: +SKIP
    >>> from acroplan.families.human.twist import asymmetric_hip_twist       # doctest: +SKIP
    >>> print(asymmetric_hip_twist(acroplan.simulate).summary())             # doctest: +SKIP
    """
    body, kw = hip_twist_problem(body, **options)
    return _angles(simulate, body, kw, samples, verify, options.get("leg", "right"), "leg")
