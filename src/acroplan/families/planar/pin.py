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
from ..tree.pin import INSTALL_HINT, build_tree, require_pinocchio, thread_data
from .links import LinkTable

__all__ = ["require_pinocchio", "PinocchioBody", "build_model", "thread_data", "INSTALL_HINT"]


@dataclasses.dataclass(frozen=True, eq=False)
class PinocchioBody:
    """A Pinocchio model of a link table, and where each link's joint sits in ``q`` and ``v``.

    Attributes
    ----------
    model : pinocchio.Model
    links : LinkTable
    root : {"planar", "freeflyer"}
    joint_ids : tuple of int, length n_links
        Pinocchio joint index of each link (table order); the root's is its root joint.
    """

    model: object
    links: LinkTable
    root: str
    joint_ids: tuple[int, ...]

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
        q = np.zeros(self.model.nq)
        th = float(x[0])
        if self.root == "planar":
            q[:4] = (0.0, 0.0, math.cos(th), math.sin(th))
        else:  # x, y, z, then the unit quaternion (qx, qy, qz, qw) of a turn th about z
            q[:7] = (0.0, 0.0, 0.0, 0.0, 0.0, math.sin(th / 2), math.cos(th / 2))
        for j, i in enumerate(self.links.joints):
            q[self.model.joints[self.joint_ids[i]].idx_q] = x[1 + j]
        return q

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
        v = np.zeros(self.model.nv)
        vx, vy, w = (float(t) for t in root_twist)
        if self.root == "planar":
            v[:3] = (vx, vy, w)
        else:
            v[:6] = (vx, vy, 0.0, 0.0, 0.0, w)
        u = np.asarray(u, dtype=float).reshape(-1)
        for j, i in enumerate(self.links.joints):
            v[self.model.joints[self.joint_ids[i]].idx_v] = u[j]
        return v

    @property
    def root_columns(self) -> list[int]:
        """Columns of ``v`` (and of the centroidal map) of the root's planar twist
        :math:`(v_x, v_y, \\omega)`."""
        return [0, 1, 2] if self.root == "planar" else [0, 1, 5]

    @property
    def joint_columns(self) -> list[int]:
        """Columns of ``v`` of the joint rates, in state order."""
        return [self.model.joints[self.joint_ids[i]].idx_v for i in self.links.joints]


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
    table = getattr(links, "links", links)
    table = table if isinstance(table, LinkTable) else LinkTable(table)
    if root not in ("planar", "freeflyer"):
        raise InvalidInputError("root", f"must be 'planar' or 'freeflyer', got {root!r}", "give root='planar'")
    def joint_of(link):
        return pin.JointModelRZ(), pin.SE3(np.eye(3), np.array([link.joint[0], link.joint[1], 0.0]))

    def inertia(link):
        return pin.Inertia(link.mass, np.array([link.com[0], link.com[1], 0.0]),
                           np.diag([link.inertia / 2.0, link.inertia / 2.0, link.inertia]))

    model, ids = build_tree(table, "planar_body", pin.JointModelPlanar() if root == "planar" else
                            pin.JointModelFreeFlyer(), joint_of, inertia)
    return PinocchioBody(model, table, root, ids)
