"""Planar bodies from URDF files, read by Pinocchio (never by a hand-written XML parser).

:func:`read_link_table` builds the model with ``pinocchio.buildModelFromUrdf(path,
JointModelPlanar())`` (the URDF's root link on a planar root joint) and reads, at the neutral
configuration (every joint angle 0, the root at the origin with :math:`\\theta = 0`):

* one link per moving joint (links joined by ``fixed`` joints are merged into their parent by
  Pinocchio, inertias combined), named after the URDF link the joint carries;
* its mass, and its inertia about its centre of mass about the plane's normal (the ``zz`` entry
  in the world frame, :math:`(R I R^\\top)_{zz}`);
* its centre of mass and its joint position, projected on the plane: the :math:`z` components are
  dropped, which is exact for the motion in the plane;
* the joint limits: position (``lower``, ``upper``; none for a ``continuous`` joint) and rate
  (``velocity``), honoured unless overridden (``overrides=``) or dropped (``limits=False``).

Planar means: every joint is revolute (``revolute`` or ``continuous``), and every joint axis, in
the root frame at the neutral configuration, is parallel to :math:`z`. A joint whose axis is
:math:`-z` is read with its angle's sign flipped (so that every joint angle of the table is
counter-clockwise about :math:`+z`; its limits flip too). Anything else (a prismatic, floating or
planar joint, an axis off :math:`z`) is refused, naming the joint.

Each link's frame in the table is parallel to the root's at the neutral configuration (its
origin at its joint), so a URDF ``rpy`` on a joint's origin is absorbed into the vectors, and the
joint angles mean what they mean in the URDF (up to the sign flip above).

Names become Python identifiers (other characters become ``_``; a clash with ``theta`` or a
keyword of ``plan()`` gets a ``_joint`` suffix), since joint names are state names.

:func:`to_urdf` writes a link table as a URDF (for tests and for other tools).
"""

from __future__ import annotations

import math
from typing import Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ..tree.urdf import read_tree, revolute_motion, robot_xml
from .links import RESERVED_NAMES, Link, LinkTable

__all__ = ["read_link_table", "read_urdf", "to_urdf"]

#: Axis tolerance: a joint axis counts as parallel to z when it is within this of (0, 0, +-1).
AXIS_TOL = 1e-9


def read_link_table(path, *, limits: bool = True, overrides: Mapping[str, Mapping] | None = None) -> LinkTable:
    """The link table of a planar URDF (module docstring), read by
    :func:`~acroplan.families.tree.urdf.read_tree` on a planar root joint.

    Parameters
    ----------
    path, limits, overrides
        The URDF file, whether its joint limits are read, and the limits that replace its own, as
        in :func:`~acroplan.families.tree.urdf.read_tree`.

    Returns
    -------
    LinkTable
        Root first, then the links in Pinocchio's (depth-first) order.

    Raises
    ------
    InvalidInputError
        As :func:`~acroplan.families.tree.urdf.read_tree` (the file, a joint that is not revolute,
        the limits, an unknown override), and for a joint whose axis is not parallel to z (named),
        a link without mass or inertia, or whose mass, centre of mass or inertia is not finite, out
        of range or no rigid body's (named).
    """
    return read_tree(path, "planar", LinkTable, RESERVED_NAMES, _joint_sign, _link, limits=limits,
                     overrides=overrides)


def _joint_sign(model, data, jid: int) -> float:
    """+1 for a joint about +z in the root frame, -1 about -z; any other joint refused."""
    S = revolute_motion(model, data, jid, "planar", "a planar body has only revolute joints about z", AXIS_TOL)
    axis = data.oMi[jid].rotation @ S[3:]
    if abs(abs(axis[2]) - 1.0) > AXIS_TOL or math.hypot(axis[0], axis[1]) > AXIS_TOL:
        raise InvalidInputError(f"urdf joint {model.names[jid]!r}", f"turns about ({axis[0]:.6g}, {axis[1]:.6g}, "
                                f"{axis[2]:.6g}) in the root frame, not about z: the body is not planar",
                                "every joint axis must be parallel to the z axis (axis 0 0 1 in the plane "
                                "of motion)")
    return 1.0 if axis[2] > 0 else -1.0


def _link(model, data, row, parent, lims) -> Link:
    """The planar link of a URDF joint's row (:func:`~acroplan.families.tree.urdf.read_tree`): its
    vectors rotated into the world frame at the neutral configuration (no subtraction of positions:
    exact when unrotated) and projected on the plane."""
    jid, tlink, lname, _, tname, sign = row
    M = data.oMi[jid]
    Y = model.inertias[jid]
    if not Y.mass > 0:
        raise InvalidInputError(f"urdf link {lname!r}", f"has no mass (mass {Y.mass:g})",
                                "give it an <inertial> element with mass > 0, or join it to its parent with a "
                                "fixed joint")
    izz = float((M.rotation @ np.asarray(Y.inertia) @ M.rotation.T)[2, 2])
    if not izz > 0:
        raise InvalidInputError(f"urdf link {lname!r}", f"has no inertia about z (izz {izz:g})",
                                "give its <inertia> a positive izz")
    com = tuple(float(v) for v in (M.rotation @ np.asarray(Y.lever))[:2])
    if parent is None:
        return Link(tlink, None, float(Y.mass), izz, com=com)
    joint = data.oMi[model.parents[jid]].rotation @ np.asarray(model.jointPlacements[jid].translation)
    lo, up, vel = lims(sign)
    return Link(tlink, parent, float(Y.mass), izz, com=com, joint=tuple(float(v) for v in joint[:2]),
                joint_name=tname, lower=lo, upper=up, velocity=vel)


def read_urdf(path, P0: float | None = None, *, angular_momentum: float | None = None, limits: bool = True,
              overrides=None):
    """A :class:`~acroplan.families.planar.model.PlanarBody` from a planar URDF.

    Parameters
    ----------
    path : str or pathlib.Path
    angular_momentum : float
        About the centre of mass (default 0; ``P0`` is its alias).
    limits, overrides
        As :func:`read_link_table`.

    Returns
    -------
    PlanarBody
        Its joint limits are in its table (:meth:`PlanarBody.joint_limits`).
    """
    from .model import PlanarBody

    return PlanarBody(read_link_table(path, limits=limits, overrides=overrides), P0,
                      angular_momentum=angular_momentum)


def to_urdf(links, name: str = "planar_body", effort: float = 1000.0) -> str:
    """A URDF document of a link table (every joint revolute about z), written by
    :func:`~acroplan.families.tree.urdf.robot_xml`.

    Each link's ``<inertial>`` has its centre of mass at ``(cx, cy, 0)`` and the inertia
    ``diag(I/2, I/2, I)``; each joint's ``<origin>`` is ``(jx, jy, 0)`` with no rotation, its
    ``<axis>`` z.

    Parameters
    ----------
    links : LinkTable, sequence of Link, or PlanarBody
    name, effort
        The robot's name and the ``effort`` of its limits, as in
        :func:`~acroplan.families.tree.urdf.robot_xml`.

    Returns
    -------
    str
        Read back by :func:`read_link_table` with the same links, joints and limits (the one-sided
        ones too), in depth-first order.
    """
    table = LinkTable.of(links)
    return robot_xml(table, name, effort,
                     lambda link: ((link.com[0], link.com[1], 0.0), link.mass,
                                   np.diag([link.inertia / 2, link.inertia / 2, link.inertia])),
                     lambda link: ((link.joint[0], link.joint[1], 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
