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
from ..tree.urdf import (joint_limits, limit_overrides, load_model, revolute_motion,
                         robot_xml, table_names, urdf_links)
from .links import RESERVED_NAMES, Link, LinkTable

__all__ = ["read_link_table", "read_urdf", "to_urdf"]

#: Axis tolerance: a joint axis counts as parallel to z when it is within this of (0, 0, +-1).
AXIS_TOL = 1e-9


def read_link_table(path, *, limits: bool = True, overrides: Mapping[str, Mapping] | None = None) -> LinkTable:
    """The link table of a planar URDF (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        A URDF file.
    limits : bool
        Read the joint limits from the URDF (default) or leave them out.
    overrides : mapping of joint name to mapping, optional
        Per joint (its URDF name or its table name), any of ``lower``, ``upper``, ``velocity``
        (a number, or ``None`` to drop it): replaces what the URDF says.

    Returns
    -------
    LinkTable
        Root first, then the links in Pinocchio's (depth-first) order.

    Raises
    ------
    InvalidInputError
        Pinocchio missing, the file missing, unreadable, too large or with more than
        :data:`~acroplan.core.validate.MAX_LINKS` moving links (counted before Pinocchio reads it),
        a joint that is not revolute about an axis parallel to z (named), a link without mass or
        inertia, or whose mass, centre of mass or inertia is not finite, out of range or no rigid
        body's (named), an unknown override.
    """
    pin, model, data = load_model(path, "planar")
    link_names, joint_names = set(), set()
    rows = []  # (pinocchio joint id, table link name, URDF link name, URDF joint name, table joint name, sign)
    for jid in range(1, model.njoints):
        jname = model.names[jid]
        sign = 1.0
        if jid > 1:
            S = revolute_motion(model, data, jid, "planar", "a planar body has only revolute joints about z", AXIS_TOL)
            axis = data.oMi[jid].rotation @ S[3:]
            if abs(abs(axis[2]) - 1.0) > AXIS_TOL or math.hypot(axis[0], axis[1]) > AXIS_TOL:
                raise InvalidInputError(f"urdf joint {jname!r}", f"turns about ({axis[0]:.6g}, {axis[1]:.6g}, "
                                        f"{axis[2]:.6g}) in the root frame, not about z: the body is not planar",
                                        "every joint axis must be parallel to the z axis (axis 0 0 1 in the plane "
                                        "of motion)")
            sign = 1.0 if axis[2] > 0 else -1.0
        rows.append((jid, *table_names(model, jid, pin, link_names, joint_names, RESERVED_NAMES), sign))
    names = {k: r[0] for r in rows[1:] for k in (r[3], r[4])}
    over = limit_overrides(names, [r[3] for r in rows[1:]], overrides)

    world = {}  # joint id -> (com relative to the joint, joint relative to the parent's joint, mass, izz)
    parent_of = {}
    for jid, tname_link, lname, jname, tname, sign in rows:
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
        # vectors rotated into the world frame (no subtraction of positions: exact when unrotated)
        com = (M.rotation @ np.asarray(Y.lever))[:2]
        parent = model.parents[jid]
        joint = (data.oMi[parent].rotation @ np.asarray(model.jointPlacements[jid].translation))[:2] \
            if jid > 1 else np.zeros(2)
        world[jid] = (com, joint, Y.mass, izz)
        parent_of[jid] = parent

    table_of = {r[0]: r[1] for r in rows}
    links = []
    for jid, tname_link, lname, jname, tname, sign in rows:
        com, joint, mass, izz = world[jid]
        rel_com = tuple(float(v) for v in com)
        if jid == 1:
            links.append(Link(tname_link, None, float(mass), izz, com=rel_com))
            continue
        parent = parent_of[jid]
        joint = tuple(float(v) for v in joint)
        lo, up, vel = joint_limits(model, jid, over, limits, sign)
        links.append(Link(tname_link, table_of[parent], float(mass), izz, com=rel_com, joint=joint,
                          joint_name=tname, lower=lo, upper=up, velocity=vel))
    return urdf_links(LinkTable, links, [r[2] for r in rows])


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
    """A URDF document of a link table (every joint revolute about z).

    Each link's ``<inertial>`` has its centre of mass at ``(cx, cy, 0)`` and the inertia
    ``diag(I/2, I/2, I)``; each joint's ``<origin>`` is ``(jx, jy, 0)`` with no rotation. A joint
    with both position limits is ``revolute``; one without any is ``continuous``; a one-sided limit
    is written with the open side at :math:`\\pm 10^{300}` (read back as none).

    Parameters
    ----------
    links : LinkTable, sequence of Link, or PlanarBody
    name : str
        The robot's name.
    effort : float
        The ``effort`` attribute URDF requires on ``<limit>`` (unused here).

    Returns
    -------
    str
    """
    table = LinkTable.of(links)
    return robot_xml(table, name, effort,
                     lambda link: ((link.com[0], link.com[1], 0.0), link.mass,
                                   np.diag([link.inertia / 2, link.inertia / 2, link.inertia])),
                     lambda link: ((link.joint[0], link.joint[1], 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
