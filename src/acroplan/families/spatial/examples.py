"""Bundled examples of spatial bodies: each function returns ``(body, plan keywords)``.

>>> import acroplan
>>> from acroplan.families.spatial.examples import falling_cat_turn
>>> body, kw = falling_cat_turn()
>>> acroplan.plan(body, **kw).status   # doctest: +SKIP
'success'

* :func:`falling_cat_turn`: Kane and Scher's cat (:func:`~acroplan.families.spatial.zoo.falling_cat`)
  at zero angular momentum turns 180 degrees about its long axis in 0.5 s, from a shape (curled
  forward by 40 degrees) back to the same shape, within its joint ranges: one segment;
* :func:`astronaut_yaw`: an astronaut (:func:`~acroplan.families.spatial.zoo.astronaut`) at zero
  momentum turns 90 degrees about the vertical (longitudinal) axis by four arm cycles (the arms
  down at every waypoint, 2 s each), its shoulders within a human's rate;
* :func:`astronaut_somersault`: the same astronaut turns 90 degrees about the lateral (horizontal)
  axis by windmilling both arms, five circles of 2 s;
* :func:`twisting_somersault`: a diver (:func:`~acroplan.families.spatial.zoo.twisting_diver`) with
  :math:`L = 60` kg m²/s along the somersault axis does one and a half somersaults in 2 s, and
  asymmetric arm motions add half a twist (two quarter twists, the arms down at take-off, half
  way and at the end).

Planning times (``python benchmarks/spatial.py --examples``, in ``benchmarks/RESULTS.md``, with the
Pinocchio check): 0.3 s for the cat (two copies of one loop), 3-11 s for the others on a shared,
busy machine (issue #22; 4-90 s before).
"""

from __future__ import annotations

import math

import numpy as np

from . import rotations as rot
from .model import SpatialBody
from .zoo import astronaut, cat_frame, falling_cat, trunk_and_two_arms, twisting_diver

__all__ = ["falling_cat_turn", "astronaut_yaw", "astronaut_somersault", "twisting_somersault", "trunk_twist",
           "TRUNK_TWIST_END", "EXAMPLES", "SHOULDER_RATE"]


def falling_cat_turn() -> tuple[SpatialBody, dict]:
    """The falling cat turns over (module docstring).

    The cat's own frame (:func:`~acroplan.families.spatial.zoo.cat_frame`: :math:`x` its long axis
    through both halves' centres of mass, :math:`z` dorsal) starts upside down (back towards the
    inertial :math:`-z`) and ends upright, the long axis along the inertial :math:`x` throughout the
    waypoints: the root's attitude is :math:`R_x(\\pi)\\, C^\\top` at the start and :math:`C^\\top` at
    the end, :math:`C` the cat frame in the root's frame at the shape (bend 40°, side 0, twist 0).

    Returns
    -------
    (SpatialBody, dict)
    """
    cat = falling_cat()
    shape = [math.radians(40.0), 0.0, 0.0]
    Ct = cat_frame(cat, shape).T
    up = rot.from_matrix(Ct)
    down = rot.from_matrix(rot.to_matrix(rot.exp([math.pi, 0.0, 0.0])) @ Ct)
    kw = dict(times=[0.0, 0.5], conditions="free", start_rate=0.0, end_rate=0.0, time_limit=300.0,
              bend=[shape[0]] * 2, side=[0.0, 0.0], twist=[0.0, 0.0], **rot.attitude_states([down, up]))
    return cat, kw


#: the astronaut's shoulder rate limit in the yaw (rad/s): the human data's shoulder rate
#: (``families/human/data/limits.toml``, ``[rates.shoulder]``, an estimate said so there)
SHOULDER_RATE = 15.0


def astronaut_yaw(cycles: int = 4) -> tuple[SpatialBody, dict]:
    """The astronaut turns 90 degrees about its longitudinal axis at zero momentum (module
    docstring), its shoulders within a human's rate (:data:`SHOULDER_RATE` on every input) and its
    link table's abduction range. A turn at zero momentum by shape loops needs joint rates many
    times its own: without a rate limit the same plan (peak 5.5 rad/s, 28 times the waypoints'
    rate) was flagged implausible (:func:`acroplan.planning.plausibility`), whereas a body whose
    rates are bounded is within what it can do.

    Returns
    -------
    (SpatialBody, dict)
    """
    body = astronaut()
    att = [rot.exp([0.0, 0.0, 0.5 * math.pi * k / cycles]) for k in range(cycles + 1)]
    z = [0.0] * (cycles + 1)
    kw = dict(times=[2.0 * k for k in range(cycles + 1)], conditions="free", start_rate=0.0, end_rate=0.0,
              left_flex=z, left_abd=z, right_flex=z, right_abd=z, time_limit=300.0,
              u_max=SHOULDER_RATE, **rot.attitude_states(att))
    return body, kw


def astronaut_somersault(circles: int = 5) -> tuple[SpatialBody, dict]:
    """The astronaut turns 90 degrees backwards about its lateral axis by windmilling both arms
    forwards (flexion through a full circle per segment; module docstring).

    Returns
    -------
    (SpatialBody, dict)
    """
    body = astronaut()
    att = [rot.exp([-0.5 * math.pi * k / circles, 0.0, 0.0]) for k in range(circles + 1)]
    flex = [2.0 * math.pi * k for k in range(circles + 1)]
    z = [0.0] * (circles + 1)
    kw = dict(times=[2.0 * k for k in range(circles + 1)], conditions="free", start_rate=0.0, end_rate=0.0,
              left_flex=flex, left_abd=z, right_flex=flex, right_abd=z, time_limit=300.0, **rot.attitude_states(att))
    return body, kw


def twisting_somersault(L: float = 60.0, T: float = 2.0) -> tuple[SpatialBody, dict]:
    """One and a half somersaults with a half twist (module docstring).

    The somersault angle at the waypoints is the drift's, :math:`L T / \\mathbb{I}_{xx}` with the arms
    down (531° for the defaults), split in half; the Yeadon angles (somersault, tilt, twist) at the
    waypoints are (0, 0, 0), (265.4°, 0, 90°) and (530.9°, 0, 180°).

    Returns
    -------
    (SpatialBody, dict)
    """
    body = twisting_diver(L)
    I, _ = body.momentum_map(np.zeros(body.n_inputs))  # noqa: E741
    S = math.degrees(L / I[0, 0] * T)
    att = [[1.0, 0.0, 0.0, 0.0], {"euler_deg": [S / 2, 0.0, 90.0]}, {"euler_deg": [S, 0.0, 180.0]}]
    z = [0.0] * 3
    kw = dict(times=[0.0, T / 2, T], conditions="free", start_rate=0.0, end_rate=0.0, left_flex=z, left_abd=z,
              right_flex=z, right_abd=z, time_limit=300.0, **rot.attitude_states(att))
    return body, kw


#: the end attitude of :func:`trunk_twist`: the arm motion of its docstring integrated from the
#: identity (DOP853, rtol 1e-13, piecewise at the motion's corners; ``tests/test_optimal_spatial.py``
#: integrates it again)
TRUNK_TWIST_END = (-0.00765515498770528, -0.01601173660553089, 0.02212993316167489, -0.9995975634980555)


def trunk_twist() -> tuple[SpatialBody, dict]:
    """bioptim's free-floating example body (:func:`~acroplan.families.spatial.zoo.trunk_and_two_arms`,
    :math:`L = (36.3075, 0, 0)` kg m²/s) does one somersault and a half twist in 1.5 s, from the arms
    up (``RightArm_RotY`` 2.9, ``LeftArm_RotY`` -2.9 rad) to the arms down (0, 0), the rates zero at
    both ends: the task of bioptim's ``torque_driven_free_floating_base.py`` at its longest time.

    The end attitude (:data:`TRUNK_TWIST_END`; Yeadon angles 362.6°, 1.8°, 179.1° unwrapped along
    the motion) is reachable by construction: it is where an asymmetric drop of the arms takes the
    body, the right arm by a cubic smoothstep over the first 35% of the time and the left arm over
    10% to 45%.

    Returns
    -------
    (SpatialBody, dict)
    """
    body = trunk_and_two_arms()
    kw = dict(times=[0.0, 1.5], conditions="free", start_rate=0.0, end_rate=0.0, RightArm_RotY=[2.9, 0.0],
              LeftArm_RotY=[-2.9, 0.0], time_limit=300.0,
              **rot.attitude_states([[1.0, 0.0, 0.0, 0.0], list(TRUNK_TWIST_END)]))
    return body, kw


#: the examples by name (the figures are ``docs/images/spatial-<name>*.png`` and ``.gif``)
EXAMPLES = {"falling-cat": falling_cat_turn, "astronaut-yaw": astronaut_yaw,
            "astronaut-somersault": astronaut_somersault, "twisting-somersault": twisting_somersault}

