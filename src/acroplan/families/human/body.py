"""A human body in the sagittal plane, in three rigid parts: :class:`SagittalBody`.

The somersault is a rotation about the medio-lateral axis through the centre of mass. When every
joint that moves turns about a medio-lateral axis (hips, shoulders, knees flexing and extending,
both sides together), every point of the body moves in a sagittal plane, its angular velocity is
along that axis, and the angular momentum about it is exactly that of a planar body whose links
carry each part's mass, its centre of mass projected on the sagittal plane and its moment of
inertia :math:`I_{xx}` about the medio-lateral axis through its own centre of mass (the lateral
offsets of the left and right limbs change neither). That is the model here; the sources of the
numbers are :mod:`~acroplan.families.human.yeadon_body` (Yeadon's 95 measurements) and
:mod:`~acroplan.families.human.deleva` (de Leva's tables from height and mass).

The three parts
---------------
* ``trunk``: pelvis, trunk, neck and head, one rigid part. Its frame has its origin at the hip
  joint centre (both hips project onto one point), its :math:`x` axis towards the shoulders
  (superior) and its :math:`y` axis forwards (anterior). The plane's normal
  :math:`z = x \\times y` points to the body's **left**, so counter-clockwise angles turn the head
  forwards: a forward somersault has :math:`\\dot\\theta > 0` and :math:`P_0 > 0`.
* ``arms``: both arms, elbows straight; frame at the shoulder joint centre, :math:`x` along the
  arms from the shoulders to the hands.
* ``legs``: both legs, with the knees at a fixed flexion :math:`\\kappa` (0 in a pike or a
  straight position, about 2.2 rad in a tuck); frame at the hip joint centre, :math:`x` along the
  thighs from the hips.

Each part is a :class:`Part`: its mass :math:`m`, the position :math:`c` of its centre of mass in
its own frame and its moment of inertia :math:`I` about that centre (the somersault axis).

Angles
------
Anatomical angles, 0 in the anatomical position (standing, arms at the sides):
:math:`\\psi` hip flexion (> 0: thighs forward; a pike is :math:`\\psi \\approx 2.5`),
:math:`\\sigma` shoulder flexion (> 0: arms forward, :math:`\\pi` overhead), :math:`\\kappa` knee
flexion. In the planar body (:meth:`SagittalBody.three_part`, the conventions of
:mod:`~acroplan.families.planar.links` and of the zoo's ``diver_with_arms``) the joint angles are

.. math::  q_{hip} = \\pi - \\psi ,\\qquad q_{shoulder} = \\pi - \\sigma

(:math:`q_{hip} = \\pi` straight, smaller in a pike; :math:`q_{shoulder} = \\pi` arms at the
sides, :math:`\\pi/2` forward, 0 overhead).

The two-link body (:meth:`SagittalBody.two_link`)
-------------------------------------------------
Split at the hips: the *torso* is the trunk with the arms held at a fixed shoulder flexion
:math:`\\sigma`, the *leg* is the legs. In the acrobot's convention (:mod:`~acroplan.families.acrobot.model`)
:math:`\\theta` is the direction of the line from the hip to the legs' centre of mass and
:math:`\\theta + \\varphi` that of the line from the hip to the torso's centre of mass; with
:math:`\\alpha_T` the direction of the torso's centre of mass in the trunk frame and
:math:`\\alpha_L` that of the legs' in the legs frame,

.. math::  \\varphi = \\psi - \\pi + \\delta ,\\qquad \\delta = \\alpha_T - \\alpha_L
           \\ (\\text{wrapped to } (-\\pi, \\pi]) ,

so a straight body with the arms along the trunk or overhead and straight knees has
:math:`\\delta = 0` and :math:`\\varphi = -\\pi`, a pike :math:`-\\pi < \\varphi < 0`
(:math:`\\varphi = 0` would be folded flat), and hyperextension :math:`\\varphi < -\\pi`. Over a
motion that starts and ends in the same shape, :math:`\\theta` turns by the same angle as the
trunk: 3.5 somersaults are :math:`\\Delta\\theta = 7\\pi`.

Combining parts
---------------
In one frame, parts :math:`(m_a, c_a, I_a)` combine into

.. math::  m = \\sum_a m_a ,\\quad c = \\frac{1}{m}\\sum_a m_a c_a ,\\quad
           I = \\sum_a \\big(I_a + m_a |c_a - c|^2\\big) ,

and a part moves into its parent's frame by :math:`c \\mapsto j + R(q)\\,c` (joint position
:math:`j`, joint angle :math:`q`); :math:`I` does not change. The whole body's moment of inertia
about the somersault axis (:meth:`SagittalBody.inertia`) is the three parts combined, and equals
the planar body's locked inertia and the acrobot's :math:`h(\\varphi)` at the same angles.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Iterable

import numpy as np

from ...core.errors import InvalidInputError, finite_number
from ..acrobot.model import Acrobot
from ..planar.links import Link
from ..planar.model import PlanarBody

__all__ = ["Part", "SagittalBody", "combine", "wrap_angle"]


def wrap_angle(a: float) -> float:
    """``a`` wrapped to :math:`(-\\pi, \\pi]`."""
    w = math.remainder(float(a), 2.0 * math.pi)
    return math.pi if w == -math.pi else w


@dataclasses.dataclass(frozen=True)
class Part:
    """A rigid part of a body in the sagittal plane.

    Attributes
    ----------
    mass : float
        kg, > 0.
    com : (float, float)
        Its centre of mass in its own frame (m).
    inertia : float
        Its moment of inertia about its own centre of mass, about the somersault (medio-lateral)
        axis (kg m², > 0).
    """

    mass: float
    com: tuple[float, float]
    inertia: float

    def __post_init__(self):
        m = finite_number("mass", self.mass)
        inertia = finite_number("inertia", self.inertia)
        if not m > 0:
            raise InvalidInputError("mass", f"must be > 0, got {m:g}", "give the part's mass in kg")
        if not inertia > 0:
            raise InvalidInputError("inertia", f"must be > 0, got {inertia:g}", "give the moment of inertia in kg m^2")
        try:
            cx, cy = self.com
        except (TypeError, ValueError):
            raise InvalidInputError("com", f"must be a pair (x, y), got {self.com!r}", "give two numbers (m)") from None
        object.__setattr__(self, "mass", m)
        object.__setattr__(self, "inertia", inertia)
        object.__setattr__(self, "com", (finite_number("com[0]", cx), finite_number("com[1]", cy)))

    def moved(self, joint=(0.0, 0.0), angle: float = 0.0) -> "Part":
        """The same part seen in its parent's frame: :math:`c \\mapsto j + R(q)\\,c`."""
        c, s = math.cos(angle), math.sin(angle)
        x, y = self.com
        return Part(self.mass, (joint[0] + c * x - s * y, joint[1] + s * x + c * y), self.inertia)

    @property
    def distance(self) -> float:
        """:math:`|c|`: the distance from the frame's origin (the joint) to the centre of mass."""
        return math.hypot(*self.com)

    @property
    def direction(self) -> float:
        """:math:`\\operatorname{atan2}(c_y, c_x)`: the direction of the centre of mass in the frame."""
        return math.atan2(self.com[1], self.com[0])


def combine(parts: Iterable[Part]) -> Part:
    """Parts given in one frame, as one rigid part (module docstring: masses add, the centre of
    mass is the mass-weighted mean, inertias add with the parallel-axis terms)."""
    parts = list(parts)
    m = sum(p.mass for p in parts)
    cx = sum(p.mass * p.com[0] for p in parts) / m
    cy = sum(p.mass * p.com[1] for p in parts) / m
    inertia = sum(p.inertia + p.mass * ((p.com[0] - cx) ** 2 + (p.com[1] - cy) ** 2) for p in parts)
    return Part(m, (cx, cy), inertia)


@dataclasses.dataclass(frozen=True)
class SagittalBody:
    """A human body in the sagittal plane: trunk (with head), arms, legs (module docstring).

    Parameters
    ----------
    trunk : Part
        Pelvis, trunk, neck and head; frame at the hip joint centre, x to the shoulders, y forwards.
    arms : Part
        Both arms, elbows straight; frame at the shoulder joint centre, x along the arms.
    legs : Part
        Both legs at knee flexion ``knee_flexion``; frame at the hip joint centre, x along the thighs.
    shoulder : (float, float)
        The shoulder joint centre in the trunk's frame (m).
    knee_flexion : float
        :math:`\\kappa` (rad) the legs were built with (0: straight knees).
    source : str
        Where the numbers come from (for reports).

    Examples
    --------
    >>> from acroplan.families.human import from_height_mass
    >>> body = from_height_mass(1.75, 70.0, sex="male")
    >>> round(body.mass, 9)
    70.0
    >>> robot = body.two_link(angular_momentum=50.0)
    >>> bool(abs(robot.h(body.phi(0.0)) - body.inertia(0.0)) < 1e-12)   # straight, arms at the sides
    True
    """

    trunk: Part
    arms: Part
    legs: Part
    shoulder: tuple[float, float]
    knee_flexion: float = 0.0
    source: str = ""

    # ------------------------------------------------------------------ totals
    @property
    def mass(self) -> float:
        """The body's mass (kg)."""
        return self.trunk.mass + self.arms.mass + self.legs.mass

    def torso(self, shoulder_flexion: float = 0.0) -> Part:
        """The trunk with the arms at shoulder flexion :math:`\\sigma`, in the trunk's frame."""
        return combine([self.trunk, self.arms.moved(self.shoulder, math.pi - shoulder_flexion)])

    def parts(self, hip_flexion: float = 0.0, shoulder_flexion: float = 0.0) -> dict[str, Part]:
        """The three parts in the trunk's frame at hip flexion :math:`\\psi` and shoulder flexion
        :math:`\\sigma`."""
        return {"trunk": self.trunk, "arms": self.arms.moved(self.shoulder, math.pi - shoulder_flexion),
                "legs": self.legs.moved((0.0, 0.0), math.pi - hip_flexion)}

    def inertia(self, hip_flexion: float = 0.0, shoulder_flexion: float = 0.0) -> float:
        """The whole body's moment of inertia about the somersault axis through its centre of mass
        (kg m²) at hip flexion :math:`\\psi` and shoulder flexion :math:`\\sigma` (rad)."""
        return combine(self.parts(hip_flexion, shoulder_flexion).values()).inertia

    def center_of_mass(self, hip_flexion: float = 0.0, shoulder_flexion: float = 0.0) -> tuple[float, float]:
        """The whole body's centre of mass in the trunk's frame (m)."""
        return combine(self.parts(hip_flexion, shoulder_flexion).values()).com

    # ------------------------------------------------------------------ the two-link body
    def phi_offset(self, shoulder_flexion: float = 0.0) -> float:
        """:math:`\\delta = \\alpha_T - \\alpha_L` wrapped to :math:`(-\\pi, \\pi]`: the acrobot's
        :math:`\\varphi` is :math:`\\psi - \\pi + \\delta` (module docstring)."""
        return wrap_angle(self.torso(shoulder_flexion).direction - self.legs.direction)

    def phi(self, hip_flexion, shoulder_flexion: float = 0.0):
        """The two-link body's joint angle :math:`\\varphi = \\psi - \\pi + \\delta` for hip flexion
        :math:`\\psi` (a number or an array, rad)."""
        d = self.phi_offset(shoulder_flexion)
        if np.ndim(hip_flexion) == 0:
            return finite_number("hip_flexion", hip_flexion) - math.pi + d
        return np.asarray(hip_flexion, dtype=float) - math.pi + d

    def hip_flexion(self, phi, shoulder_flexion: float = 0.0):
        """The hip flexion :math:`\\psi = \\varphi + \\pi - \\delta` of the two-link body's joint
        angle (a number or an array, rad)."""
        d = self.phi_offset(shoulder_flexion)
        if np.ndim(phi) == 0:
            return finite_number("phi", phi) + math.pi - d
        return np.asarray(phi, dtype=float) + math.pi - d

    def two_link(self, *, angular_momentum: float = 0.0, shoulder_flexion: float = 0.0) -> Acrobot:
        """The body split at the hips as the text's two-link body (:meth:`Acrobot.from_physical`).

        Torso: the trunk with the arms fixed at shoulder flexion :math:`\\sigma` (0: at the sides);
        leg: the legs. ``torso_com_to_joint`` and ``leg_com_to_joint`` are the distances from the
        hip joint centre to each part's centre of mass; :math:`\\varphi = \\psi - \\pi + \\delta`
        (:meth:`phi`).

        Parameters
        ----------
        angular_momentum : float
            :math:`P_0` about the somersault axis (kg m²/s; > 0 for a forward somersault).
        shoulder_flexion : float
            :math:`\\sigma` (rad).

        Returns
        -------
        Acrobot
        """
        torso = self.torso(finite_number("shoulder_flexion", shoulder_flexion))
        return Acrobot.from_physical(torso_mass=torso.mass, leg_mass=self.legs.mass, torso_inertia=torso.inertia,
                                     leg_inertia=self.legs.inertia, torso_com_to_joint=torso.distance,
                                     leg_com_to_joint=self.legs.distance,
                                     angular_momentum=finite_number("angular_momentum", angular_momentum))

    # ------------------------------------------------------------------ the three-part body
    def shape(self, hip_flexion: float, shoulder_flexion: float) -> tuple[float, float]:
        """The planar body's joint angles :math:`(q_{hip}, q_{shoulder}) = (\\pi - \\psi, \\pi - \\sigma)`."""
        return (math.pi - float(hip_flexion), math.pi - float(shoulder_flexion))

    def three_part(self, *, angular_momentum: float = 0.0, limits=None) -> PlanarBody:
        """The body split at the hips and the shoulders as a :class:`PlanarBody`.

        Links (in this order): ``trunk`` (the root), ``legs`` (joint ``hip`` at the trunk frame's
        origin), ``arms`` (joint ``shoulder`` at :attr:`shoulder`); the state is
        ``(theta, hip, shoulder)`` with :math:`q_{hip} = \\pi - \\psi` and
        :math:`q_{shoulder} = \\pi - \\sigma` (:meth:`shape`).

        Parameters
        ----------
        angular_momentum : float
            :math:`P_0` (kg m²/s).
        limits : acroplan.Limits, optional
            Joint ranges (``hip``, ``shoulder``) and rates (``u_hip``, ``u_shoulder``) to write into
            the link table (:func:`~acroplan.families.human.limits.human_limits` with
            ``links=3`` gives them for a position); they become the body's default limits.

        Returns
        -------
        PlanarBody
        """
        extra = {"legs": {}, "arms": {}}
        if limits is not None:
            for link, joint in (("legs", "hip"), ("arms", "shoulder")):
                lo, hi = limits.bounds(joint)
                rate = limits.input_bound(f"u_{joint}")
                extra[link] = {"lower": lo if math.isfinite(lo) else None, "upper": hi if math.isfinite(hi) else None,
                               "velocity": rate}
        links = [Link("trunk", None, self.trunk.mass, self.trunk.inertia, com=self.trunk.com),
                 Link("legs", "trunk", self.legs.mass, self.legs.inertia, com=self.legs.com, joint=(0.0, 0.0),
                      joint_name="hip", **extra["legs"]),
                 Link("arms", "trunk", self.arms.mass, self.arms.inertia, com=self.arms.com, joint=self.shoulder,
                      joint_name="shoulder", **extra["arms"])]
        return PlanarBody(links, P0=finite_number("angular_momentum", angular_momentum))

    def summary(self) -> str:
        """The parts in words (for reports)."""
        rows = [f"{self.source}: {self.mass:.2f} kg, knee flexion {self.knee_flexion:.3f} rad"]
        for name in ("trunk", "arms", "legs"):
            p = getattr(self, name)
            rows.append(f"  {name:5s} m = {p.mass:7.3f} kg, com = ({p.com[0]: .4f}, {p.com[1]: .4f}) m, "
                        f"I = {p.inertia:.4f} kg m^2")
        rows.append(f"  shoulder joint at ({self.shoulder[0]:.4f}, {self.shoulder[1]:.4f}) m; "
                    f"I (straight, arms at the sides) = {self.inertia(0.0, 0.0):.4f} kg m^2")
        return "\n".join(rows)
