"""Pinocchio glue: the Pinocchio model of a link table, and its configuration and velocity vectors.

Pinocchio (PyPI ``pin``, import name ``pinocchio``) is an optional dependency (the extra
``bodies``): it is imported inside the functions that need it, never at module import, and its
absence is reported as an :class:`~acroplan.core.errors.InvalidInputError` that says how to
install it.

The model of a link table: a root joint (``JointModelPlanar``: configuration
:math:`(x, y, \\cos\\theta, \\sin\\theta)`, velocity :math:`(v_x, v_y, \\omega)` in the root frame;
or ``JointModelFreeFlyer``), then one revolute-:math:`z` joint (``JointModelRZ``) per non-root
link, placed at ``(jx, jy, 0)`` in its parent's joint frame with no rotation, carrying the link's
inertia: mass, centre of mass ``(cx, cy, 0)`` in the link's frame, rotational inertia
``diag(I/2, I/2, I)`` about it (a flat plate; only the ``zz`` entry matters in the plane).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...core.errors import InvalidInputError
from ..tree.pin import INSTALL_HINT, PinocchioTree, build_tree, require_pinocchio, thread_data
from .links import LinkTable

__all__ = ["require_pinocchio", "PinocchioBody", "build_model", "thread_data", "INSTALL_HINT"]


@dataclasses.dataclass(frozen=True, eq=False)
class PinocchioBody(PinocchioTree):
    """A Pinocchio model of a planar link table on a planar or free-flyer root: a
    :class:`~acroplan.families.tree.pin.PinocchioTree` (``model``, ``links``: a
    :class:`~acroplan.families.planar.links.LinkTable`, ``joint_ids``, ``idx_q``, ``idx_v``) with
    the root joint's coordinates.

    Attributes
    ----------
    root : {"planar", "freeflyer"}
        The root joint.
    """

    root: str = "planar"

    def configuration(self, state) -> np.ndarray:
        """Pinocchio's ``q`` for the state :math:`(\\theta, q_1, \\dots)`, the root at the origin.

        Parameters
        ----------
        state : array_like, shape (n_links,)

        Returns
        -------
        numpy.ndarray, shape (model.nq,)
        """
        x = np.asarray(state, dtype=float)
        th = float(x[0])
        if self.root == "planar":
            root = (0.0, 0.0, math.cos(th), math.sin(th))
        else:  # x, y, z, then the unit quaternion (qx, qy, qz, qw) of a turn th about z
            root = (0.0, 0.0, 0.0, 0.0, 0.0, math.sin(th / 2), math.cos(th / 2))
        return self._configuration(root, x[1:])

    def velocity(self, root_twist, u) -> np.ndarray:
        """Pinocchio's ``v`` from the root's planar twist and the joint rates.

        Parameters
        ----------
        root_twist : array_like, shape (3,)
            :math:`(v_x, v_y, \\omega)` of the root frame, expressed in the root frame.
        u : array_like, shape (n_links - 1,)

        Returns
        -------
        numpy.ndarray, shape (model.nv,)
        """
        vx, vy, w = (float(t) for t in root_twist)
        return self._velocity((vx, vy, w) if self.root == "planar" else (vx, vy, 0.0, 0.0, 0.0, w), u)

    @property
    def root_columns(self) -> list[int]:
        """Columns of ``v`` (and of the centroidal map) of the root's planar twist
        :math:`(v_x, v_y, \\omega)`."""
        return [0, 1, 2] if self.root == "planar" else [0, 1, 5]

    @property
    def joint_columns(self) -> list[int]:
        """Columns of ``v`` of the joint rates, in state order (:attr:`idx_v`)."""
        return self.idx_v


def build_model(links, root: str = "planar") -> PinocchioBody:
    """The Pinocchio model of a link table (module docstring).

    Parameters
    ----------
    links : LinkTable, sequence of Link, or PlanarBody
    root : {"planar", "freeflyer"}
        The root joint: Pinocchio's planar joint, or a free flyer (six degrees of freedom).

    Returns
    -------
    PinocchioBody
    """
    pin = require_pinocchio()
    table = LinkTable.of(links)
    if root not in ("planar", "freeflyer"):
        raise InvalidInputError("root", f"must be 'planar' or 'freeflyer', got {root!r}", "give root='planar'")
    def joint_of(link):
        return pin.JointModelRZ(), pin.SE3(np.eye(3), np.array([link.joint[0], link.joint[1], 0.0]))

    def inertia(link):
        return pin.Inertia(link.mass, np.array([link.com[0], link.com[1], 0.0]),
                           np.diag([link.inertia / 2.0, link.inertia / 2.0, link.inertia]))

    model, ids = build_tree(table, "planar_body", pin.JointModelPlanar() if root == "planar" else
                            pin.JointModelFreeFlyer(), joint_of, inertia)
    return PinocchioBody(model, table, ids, root)
