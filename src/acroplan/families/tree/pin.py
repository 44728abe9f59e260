"""Pinocchio for tree bodies: importing it (an optional dependency, the extra ``bodies``), building
the model of a link table (:func:`build_tree`), the model with where each joint sits in its
configuration and velocity vectors (:class:`PinocchioTree`, the base of the families' wrappers),
and one ``pinocchio.Data`` per model and thread.

Pinocchio (PyPI ``pin``, import name ``pinocchio``) is imported inside the functions that need it,
never at module import, and its absence is an :class:`~acroplan.core.errors.InvalidInputError`
that says how to install it.
"""

from __future__ import annotations

import dataclasses
import threading

import numpy as np

__all__ = ["require_pinocchio", "INSTALL_HINT", "build_tree", "PinocchioTree", "without_gravity", "thread_data"]

INSTALL_HINT = "pip install acroplan[bodies] (or pip install pin)"


def require_pinocchio():
    """The ``pinocchio`` module, or an :class:`InvalidInputError` saying how to install it."""
    from ...core.errors import InvalidInputError

    try:
        import pinocchio
    except ImportError as e:  # pragma: no cover - exercised only without the extra
        raise InvalidInputError("pinocchio", f"is needed for this and is not installed ({e})", INSTALL_HINT) from None
    return pinocchio


def build_tree(table, name: str, root_joint, joint_of, inertia_of):
    """A ``pinocchio.Model`` of the link table ``table``: the root on ``root_joint`` (a Pinocchio
    joint model), each other link on the joint ``joint_of(link) -> (joint model, placement)`` in its
    parent's joint frame, named by its table joint name, carrying ``inertia_of(link)`` (a
    ``pinocchio.Inertia``); links added in depth-first order (Pinocchio's).

    Returns
    -------
    (model, joint ids per link in table order)
    """
    pin = require_pinocchio()
    model = pin.Model()
    model.name = name
    ids = [0] * len(table)
    for i in table.topological_order():
        link = table[i]
        if i == table.root:
            jid = model.addJoint(0, root_joint, pin.SE3.Identity(), "root_joint")
        else:
            jmodel, placement = joint_of(link)
            jid = model.addJoint(ids[table.parents[i]], jmodel, placement, table.joint_names[table.joints.index(i)])
        model.appendBodyToJoint(jid, inertia_of(link), pin.SE3.Identity())
        ids[i] = jid
    return model, tuple(ids)


@dataclasses.dataclass(frozen=True, eq=False)
class PinocchioTree:
    """A Pinocchio model of a link table, and where each link's joint sits in ``q`` and ``v``: the
    base of the families' wrappers, which add the root's coordinates (``configuration``).

    Attributes
    ----------
    model : pinocchio.Model
    links : TreeLinkTable
        The family's link table (:class:`~acroplan.families.tree.links.TreeLinkTable`).
    joint_ids : tuple of int, length n_links
        Pinocchio joint index of each link (table order); the root's is its root joint.
    """

    model: object
    links: object
    joint_ids: tuple[int, ...]

    @property
    def idx_q(self) -> list[int]:
        """Positions of the joint angles (state order) in Pinocchio's ``q``."""
        return [self.model.joints[self.joint_ids[i]].idx_q for i in self.links.joints]

    @property
    def idx_v(self) -> list[int]:
        """Columns of the joint rates (state order) in ``v`` and the centroidal map."""
        return [self.model.joints[self.joint_ids[i]].idx_v for i in self.links.joints]

    def _configuration(self, root, angles) -> np.ndarray:
        """Pinocchio's ``q``: the root joint's coordinates ``root`` first, then the joint angles
        (state order) at :attr:`idx_q`."""
        return _placed(self.model.nq, root, self.idx_q, angles)

    def _velocity(self, root, rates) -> np.ndarray:
        """Pinocchio's ``v``: the root joint's velocity ``root`` first, then the joint rates (state
        order) at :attr:`idx_v`."""
        return _placed(self.model.nv, root, self.idx_v, rates)


def without_gravity(pb):
    """``pb`` (a :class:`PinocchioTree`) with its model's gravity set to zero, for the inverse
    dynamics of the free body; returned."""
    pb.model.gravity = require_pinocchio().Motion.Zero()
    return pb


def _placed(size: int, head, idx: list[int], values) -> np.ndarray:
    out = np.zeros(size)
    out[:len(head)] = head
    out[idx] = np.asarray(values, dtype=float).reshape(-1)
    return out


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
