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
import threading

import numpy as np

from ...core.errors import InvalidInputError
from .links import LinkTable

__all__ = ["require_pinocchio", "PinocchioBody", "build_model", "thread_data"]

INSTALL_HINT = "pip install acroplan[bodies] (or pip install pin)"


def require_pinocchio():
    """The ``pinocchio`` module, or an :class:`InvalidInputError` saying how to install it."""
    try:
        import pinocchio
    except ImportError as e:  # pragma: no cover - exercised only without the extra
        raise InvalidInputError("pinocchio", f"is needed for this and is not installed ({e})", INSTALL_HINT) from None
    return pinocchio


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
    model = pin.Model()
    model.name = "planar_body"
    ids = [0] * len(table)

    def inertia(link):
        return pin.Inertia(link.mass, np.array([link.com[0], link.com[1], 0.0]),
                           np.diag([link.inertia / 2.0, link.inertia / 2.0, link.inertia]))

    for i in table.topological_order():
        link = table[i]
        if i == table.root:
            jmodel = pin.JointModelPlanar() if root == "planar" else pin.JointModelFreeFlyer()
            jid = model.addJoint(0, jmodel, pin.SE3.Identity(), "root_joint")
        else:
            placement = pin.SE3(np.eye(3), np.array([link.joint[0], link.joint[1], 0.0]))
            name = table.joint_names[table.joints.index(i)]
            jid = model.addJoint(ids[table.parents[i]], pin.JointModelRZ(), placement, name)
        model.appendBodyToJoint(jid, inertia(link), pin.SE3.Identity())
        ids[i] = jid
    return PinocchioBody(model, table, root, tuple(ids))


_LOCAL = threading.local()


def thread_data(pb):
    """One ``pinocchio.Data`` per Pinocchio model and thread (Pinocchio's algorithms write into it):
    for any body whose ``model`` is a ``pinocchio.Model`` (planar and spatial)."""
    cache = getattr(_LOCAL, "data", None)
    if cache is None:
        cache = _LOCAL.data = {}
    d = cache.get(id(pb))
    if d is None or d[0] is not pb:
        d = cache[id(pb)] = (pb, pb.model.createData())
    return d[1]
