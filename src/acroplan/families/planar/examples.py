"""Bundled examples of planar bodies: each function returns ``(body, plan keywords)``.

>>> import acroplan
>>> from acroplan.families.planar.examples import three_rods_turn
>>> body, kw = three_rods_turn()
>>> acroplan.plan(body, **kw).status
'success'

* :func:`diver_somersault_with_arm_sweep`: a diver (trunk, thighs, shanks, arms; the table's joint
  and rate limits) takes off straight with the arms overhead, pikes, sweeps the arms down to the
  sides and opens out, turning one full somersault (:math:`\\theta: 0 \\to 2\\pi`) in 1.45 s at
  :math:`P_0 = 36` kg m²/s, through five waypoints with spline conditions;
* :func:`space_robot_turn_90`: a free-floating spacecraft with a two-link arm at zero angular
  momentum turns its base by :math:`\\pi/2` by moving its arm around closed loops (five segments
  of 25 s, the arm straight out at every waypoint), within the arm's joint limits and its rate
  limits of 0.5 rad/s;
* :func:`three_rods_turn`: three equal rods at zero momentum turn by 0.4 rad in 3 s by one shape
  loop, starting and ending in the same shape, with :math:`|u| \\le 2` rad/s.

The same problems are bundled as problem files, under the same names (``acroplan plan --example
diver-somersault``: the diver through a URDF file, the others through link tables;
``acroplan/families/planar/data/``); ``tests/test_cli_bodies.py`` checks that the files give these bodies (lumped
parameters to 1e-12), waypoints and limits.
"""

from __future__ import annotations

import math

from .model import PlanarBody
from .zoo import diver_with_arms, planar_space_robot, three_rods

__all__ = ["diver_somersault_with_arm_sweep", "space_robot_turn_90", "three_rods_turn", "EXAMPLES"]


def diver_somersault_with_arm_sweep() -> tuple[PlanarBody, dict]:
    """One somersault in pike with an arm sweep (module docstring).

    The joint waypoints (hip :math:`\\pi` is straight, shoulder 0 is arms overhead, :math:`\\pi` arms
    at the sides; :func:`~acroplan.families.planar.zoo.diver_with_arms`):

    ====  ======  =====  ========  =========
    t     hip     knee   shoulder  theta
    ====  ======  =====  ========  =========
    0     3.1     0.1    0.3       0
    0.35  1.6     0.3    1.2       1.5
    0.75  0.9     0.3    2.2       4.0
    1.1   1.6     0.2    2.8       5.7
    1.45  3.1     0.1    3.1       2 pi
    ====  ======  =====  ========  =========

    Returns
    -------
    (PlanarBody, dict)
    """
    body = diver_with_arms(P0=36.0)
    kw = dict(times=[0.0, 0.35, 0.75, 1.1, 1.45], theta=[0.0, 1.5, 4.0, 5.7, 2 * math.pi],
              hip=[3.1, 1.6, 0.9, 1.6, 3.1], knee=[0.1, 0.3, 0.3, 0.2, 0.1], shoulder=[0.3, 1.2, 2.2, 2.8, 3.1],
              conditions="spline")
    return body, kw


def space_robot_turn_90() -> tuple[PlanarBody, dict]:
    """The base turns by :math:`\\pi/2` at zero momentum through five arm loops (module docstring).

    Returns
    -------
    (PlanarBody, dict)
    """
    body = planar_space_robot(P0=0.0)
    K = 5
    kw = dict(times=[25.0 * k for k in range(K + 1)], theta=[0.5 * math.pi * k / K for k in range(K + 1)],
              shoulder=[0.0] * (K + 1), elbow=[0.0] * (K + 1), conditions="free", start_rate=0.0, end_rate=0.0)
    return body, kw


def three_rods_turn() -> tuple[PlanarBody, dict]:
    """Three equal rods turn by 0.4 rad at zero momentum by one shape loop (module docstring).

    Returns
    -------
    (PlanarBody, dict)
    """
    body = three_rods(P0=0.0)
    kw = dict(times=[0.0, 3.0], theta=[0.0, 0.4], q1=[1.0, 1.0], q2=[1.0, 1.0], conditions="free",
              start_rate=0.0, end_rate=0.0, u_max=2.0)
    return body, kw


#: the examples by name (the figure of each is ``docs/images/planar-<name>.png``)
EXAMPLES = {"diver-somersault": diver_somersault_with_arm_sweep, "space-robot-turn": space_robot_turn_90,
            "three-rods-turn": three_rods_turn}
