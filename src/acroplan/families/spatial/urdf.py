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

from ..tree.urdf import read_tree, revolute_motion, robot_xml
from .links import RESERVED_NAMES, SpatialLink, SpatialLinkTable

__all__ = ["read_link_table", "read_urdf", "to_urdf"]


def read_link_table(path, *, limits: bool = True, overrides: Mapping[str, Mapping] | None = None) -> SpatialLinkTable:
    """The link table of a URDF with revolute joints (module docstring), read by
    :func:`~acroplan.families.tree.urdf.read_tree` on a free-flyer root.

    Parameters
    ----------
    path, limits, overrides
        As in :func:`~acroplan.families.tree.urdf.read_tree`: the URDF file, whether its joint
        limits are read (default) or left out, and per joint the limits that replace its own.

    Returns
    -------
    SpatialLinkTable
        Root first, then the links in Pinocchio's (depth-first) order.

    Raises
    ------
    InvalidInputError
        As :func:`~acroplan.families.tree.urdf.read_tree` (the file, a joint that is not revolute,
        the limits, an unknown override), and for a mass, centre of mass or inertia that is not
        finite, out of range or no rigid body's (the link named; a massless link must have no
        inertia).
    """
    return read_tree(path, "freeflyer", SpatialLinkTable, RESERVED_NAMES, _joint_axis, _link, limits=limits,
                     overrides=overrides)


def _joint_axis(model, data, jid: int) -> np.ndarray:
    """The unit axis of a revolute joint in its own frame (any other joint refused)."""
    S = revolute_motion(model, data, jid, "spatial", "a spatial body has only revolute joints (revolute or "
                        "continuous); make a multi-axis joint of revolute joints through massless links")
    return S[3:] / np.linalg.norm(S[3:])


def _link(model, data, row, parent, lims) -> SpatialLink:
    """The spatial link of a URDF joint's row (:func:`~acroplan.families.tree.urdf.read_tree`): its
    inertia in its frame, its joint's placement and its axis in the parent's frame."""
    jid, tlink, _, _, tname, axis = row
    Y = model.inertias[jid]
    mass, com, inertia = float(Y.mass), np.asarray(Y.lever, dtype=float), np.asarray(Y.inertia, dtype=float)
    if parent is None:
        return SpatialLink(tlink, None, mass, inertia, com=tuple(com))
    P = model.jointPlacements[jid]
    Rf = np.asarray(P.rotation, dtype=float)
    lo, up, vel = lims()
    rotation = None if np.allclose(Rf, np.eye(3), rtol=0.0, atol=1e-15) else Rf
    return SpatialLink(tlink, parent, mass, inertia, com=tuple(com), joint=tuple(np.asarray(P.translation, dtype=float)),
                       axis=tuple(Rf @ axis), rotation=rotation, joint_name=tname, lower=lo, upper=up, velocity=vel)


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
    (:math:`R_{fixed}^\\top a`), written by :func:`~acroplan.families.tree.urdf.robot_xml`.
    Massless links are written without ``<inertial>``.

    Parameters
    ----------
    links : SpatialLinkTable, sequence of SpatialLink, or SpatialBody
    name : str
        The robot's name.
    effort : float
        The ``effort`` of each ``<limit>`` (:func:`~acroplan.families.tree.urdf.robot_xml`).

    Returns
    -------
    str
        Read back by Pinocchio (:func:`read_urdf`) with the same masses, inertias, joints and
        limits; it numbers the joints depth-first in the URDF's order, so they may come back in
        another order.
    """
    from scipy.spatial.transform import Rotation

    table = SpatialLinkTable.of(links)

    def frame(link):
        Rf = link.rotation_matrix
        return link.joint, Rotation.from_matrix(Rf).as_euler("xyz"), Rf.T @ np.asarray(link.axis)

    return robot_xml(table, name, effort,
                     lambda link: (link.com, link.mass, link.inertia_matrix) if link.mass > 0 else None, frame)
