"""Pinocchio glue: the Pinocchio model of a spatial link table (free-flyer root), and its
configuration and velocity vectors.

Pinocchio (PyPI ``pin``) is optional (the extra ``bodies``) and imported on first use
(:func:`~acroplan.families.tree.pin.require_pinocchio`).

The model: a ``JointModelFreeFlyer`` root (configuration :math:`(p, q_x, q_y, q_z, q_w)`, velocity
:math:`(v, \\omega)` in the root frame), then per non-root link a revolute joint placed at
``SE3(rotation, joint)`` in its parent's joint frame, about the axis :math:`R_{fixed}^\\top a` of
the child's frame (``JointModelRX``/``RY``/``RZ`` when it is a coordinate axis, else
``JointModelRevoluteUnaligned``), so that the child's frame is
:math:`R_{fixed}\\,\\mathrm{Rot}(R_{fixed}^\\top a, s) = \\mathrm{Rot}(a, s)\\,R_{fixed}` as in the link
table's convention; each link carries ``Inertia(mass, com, inertia)``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...core.errors import InvalidInputError
from ..tree.pin import PinocchioTree, build_tree, require_pinocchio
from .links import SpatialLinkTable

__all__ = ["SpatialPinocchioBody", "build_model"]


@dataclasses.dataclass(frozen=True, eq=False)
class SpatialPinocchioBody(PinocchioTree):
    """A Pinocchio model of a spatial link table on a free-flyer root: a
    :class:`~acroplan.families.tree.pin.PinocchioTree` (``model``, ``links``: a
    :class:`~acroplan.families.spatial.links.SpatialLinkTable`, ``joint_ids``, the root's the free
    flyer, ``idx_q``, ``idx_v``) with the attitude in its configuration.
    """

    def configuration(self, state) -> np.ndarray:
        """Pinocchio's ``q`` for the state :math:`(q_w, q_x, q_y, q_z, s)`, the root at the origin.

        Parameters
        ----------
        state : array_like, shape (4 + n_links - 1,)
            The attitude (a quaternion, normalised here) and the joint angles.

        Returns
        -------
        numpy.ndarray, shape (model.nq,)
        """
        x = np.asarray(state, dtype=float)
        w, a, b, c = x[:4] / np.linalg.norm(x[:4])
        return self._configuration((0.0, 0.0, 0.0, a, b, c, w), x[4:])


def _axis_joint(pin, axis):
    for k, name in enumerate(("RX", "RY", "RZ")):
        e = np.zeros(3)
        e[k] = 1.0
        if np.allclose(axis, e, atol=0.0, rtol=0.0):
            return getattr(pin, f"JointModel{name}")()
    return pin.JointModelRevoluteUnaligned(np.asarray(axis, dtype=float))


def build_model(links) -> SpatialPinocchioBody:
    """The Pinocchio model of a spatial link table (module docstring).

    Parameters
    ----------
    links : SpatialLinkTable, sequence of SpatialLink, or SpatialBody

    Returns
    -------
    SpatialPinocchioBody
    """
    pin = require_pinocchio()
    table = SpatialLinkTable.of(links)

    def joint_of(link):
        Rf = link.rotation_matrix
        return _axis_joint(pin, Rf.T @ np.asarray(link.axis)), pin.SE3(Rf, np.asarray(link.joint, dtype=float))

    def inertia(link):
        return pin.Inertia(link.mass, np.asarray(link.com, dtype=float), link.inertia_matrix)

    model, ids = build_tree(table, "spatial_body", pin.JointModelFreeFlyer(), joint_of, inertia)
    if model.nv != 6 + len(table.joints):
        raise InvalidInputError("links", f"the Pinocchio model has {model.nv} velocity coordinates, expected "
                                f"{6 + len(table.joints)}", "report this: every joint must be revolute")
    return SpatialPinocchioBody(model, table, ids)
