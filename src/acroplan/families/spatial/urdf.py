"""Spatial bodies from URDF files, read by Pinocchio (never by a hand-written XML parser).

:func:`read_link_table` builds the model with ``pinocchio.buildModelFromUrdf(path,
JointModelFreeFlyer())`` (the URDF's root link on a free-flyer root) and reads, per moving joint
(links joined by ``fixed`` joints are merged into their parent by Pinocchio, inertias combined):

* the link it carries (named after the URDF link), its mass, centre of mass and inertia tensor about
  the centre of mass, in the link's frame (Pinocchio's joint frame, the URDF joint's frame);
* the joint's placement in the parent's frame: its position (``joint``) and its fixed rotation
  (``rotation``, the URDF ``rpy``), and its axis, given in the table in the parent's frame
  (:math:`R_{fixed}\\,a_{urdf}`, so that the child frame at angle :math:`q` is
  :math:`\\mathrm{Rot}(a, q) R_{fixed} = R_{fixed}\\,\\mathrm{Rot}(a_{urdf}, q)`, as in the URDF);
* the joint limits: position (``lower``, ``upper``; none for a ``continuous`` joint) and rate
  (``velocity``), honoured unless overridden (``overrides=``) or dropped (``limits=False``).

Every joint must be revolute (``revolute`` or ``continuous``): a prismatic, planar or floating
joint is refused, naming it. Names become Python identifiers (other characters become ``_``; a
clash with the attitude's ``qw, qx, qy, qz`` or a keyword of ``plan()`` gets a ``_joint`` suffix).

:func:`to_urdf` writes a link table as a URDF (for tests and for other tools).
"""

from __future__ import annotations

from typing import Mapping

import numpy as np

from ..tree.urdf import (joint_limits, limit_overrides, load_model, revolute_motion,
                         robot_xml, table_names, urdf_links)
from .links import RESERVED_NAMES, SpatialLink, SpatialLinkTable

__all__ = ["read_link_table", "read_urdf", "to_urdf"]


def read_link_table(path, *, limits: bool = True, overrides: Mapping[str, Mapping] | None = None) -> SpatialLinkTable:
    """The link table of a URDF with revolute joints (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
    limits : bool
        Read the joint limits from the URDF (default) or leave them out.
    overrides : mapping of joint name to mapping, optional
        Per joint (URDF or table name), any of ``lower``, ``upper``, ``velocity`` (``None`` drops it).

    Returns
    -------
    SpatialLinkTable
        Root first, then the links in Pinocchio's (depth-first) order.

    Raises
    ------
    InvalidInputError
        Pinocchio missing, the file missing, unreadable, too large or with more than
        :data:`~acroplan.core.validate.MAX_LINKS` moving links (counted before Pinocchio reads it),
        a joint that is not revolute (named), a mass, centre of mass or inertia that is not finite,
        out of range or no rigid body's (the link named; a massless link must have no inertia), an
        unknown override.
    """
    pin, model, data = load_model(path, "freeflyer")
    link_names, joint_names = set(), set()
    rows = []
    for jid in range(1, model.njoints):
        axis = None
        if jid > 1:
            S = revolute_motion(model, data, jid, "spatial", "a spatial body has only revolute joints (revolute or "
                                "continuous); make a multi-axis joint of revolute joints through massless links")
            axis = S[3:] / np.linalg.norm(S[3:])
        rows.append((jid, *table_names(model, jid, pin, link_names, joint_names, RESERVED_NAMES), axis))
    over = limit_overrides({k: r[0] for r in rows[1:] for k in (r[3], r[4])}, [r[3] for r in rows[1:]], overrides)
    names = {r[0]: r[1] for r in rows}
    links = []
    for jid, tlink, lname, jname, tname, axis in rows:
        Y = model.inertias[jid]
        mass, com, inertia = float(Y.mass), np.asarray(Y.lever, dtype=float), np.asarray(Y.inertia, dtype=float)
        if jid == 1:
            links.append(SpatialLink(tlink, None, mass, inertia, com=tuple(com)))
            continue
        P = model.jointPlacements[jid]
        Rf = np.asarray(P.rotation, dtype=float)
        lo, up, vel = joint_limits(model, jid, over, limits)
        rotation = None if np.allclose(Rf, np.eye(3), rtol=0.0, atol=1e-15) else Rf
        links.append(SpatialLink(tlink, names[model.parents[jid]], mass, inertia, com=tuple(com),
                                 joint=tuple(np.asarray(P.translation, dtype=float)), axis=tuple(Rf @ axis),
                                 rotation=rotation, joint_name=tname, lower=lo, upper=up, velocity=vel))
    return urdf_links(SpatialLinkTable, links, [r[2] for r in rows])


def read_urdf(path, L=None, *, angular_momentum=None, limits: bool = True, overrides=None):
    """A :class:`~acroplan.families.spatial.model.SpatialBody` from a URDF (:func:`read_link_table`).

    Parameters
    ----------
    path : str or pathlib.Path
    angular_momentum : (float, float, float)
        About the centre of mass, inertial frame (default zero; ``L`` is its alias).
    """
    from .model import SpatialBody

    return SpatialBody(read_link_table(path, limits=limits, overrides=overrides), L,
                       angular_momentum=angular_momentum)


def to_urdf(links, name: str = "spatial_body", effort: float = 1000.0) -> str:
    """A URDF document of a spatial link table.

    Each joint's ``<origin>`` is the link's ``joint`` with the ``rpy`` of its ``rotation``
    (:math:`R = R_z(y) R_y(p) R_x(r)`), its ``<axis>`` the table's axis in the joint's frame
    (:math:`R_{fixed}^\\top a`); a joint with both position limits is ``revolute``, one without is
    ``continuous`` (a one-sided limit is written with the open side at :math:`\\pm 10^{300}`).
    Massless links are written without ``<inertial>``. Pinocchio reads the document back
    (:func:`read_urdf`) with the same masses, inertias, joints and limits; it numbers the joints
    depth-first in the URDF's order, so they may come back in another order.

    Parameters
    ----------
    links : SpatialLinkTable, sequence of SpatialLink, or SpatialBody
    name : str
        The robot's name.
    effort : float
        The ``effort`` attribute of each ``<limit>`` (URDF requires one; acroplan does not use it).

    Returns
    -------
    str
    """
    from scipy.spatial.transform import Rotation

    table = SpatialLinkTable.of(links)

    def frame(link):
        Rf = link.rotation_matrix
        return link.joint, Rotation.from_matrix(Rf).as_euler("xyz"), Rf.T @ np.asarray(link.axis)

    return robot_xml(table, name, effort,
                     lambda link: (link.com, link.mass, link.inertia_matrix) if link.mass > 0 else None, frame)
