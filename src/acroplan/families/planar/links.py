"""The link table of a free-flying planar body: rigid links joined by revolute joints in a tree.

Conventions
-----------
Every link carries a frame that moves with it. The **root** link (exactly one, ``parent=None``)
has its frame at any point fixed in it; every other link's frame has its origin at its joint with
its parent. All vectors of a link are given in **its own** frame, except the position of its joint,
which is given in its **parent's** frame (where the joint sits on the parent)::

                                   y_c         x_c      the child: frame at its joint J,
                                     \\         /        turned by q from the parent's
                                      \\       /  . com = (cx, cy) of the child, in the
                                       \\     /           child's own frame
                                        \\   /  q
                                         \\ /   )
                                         (J) - - - - - - ->  (parallel to x_p)
            y_p                         _/
             ^                        _/     joint = (jx, jy): J in the parent's frame
             |   . com = (cx, cy)   _/
             |     of the parent  _/
             |                  _/
            (O)--------------------------------------------> x_p
            the parent's frame origin: its own joint (for the root: any point of the root)

* ``joint = (jx, jy)``: the child's joint in the parent's frame;
* ``com = (cx, cy)``: the link's centre of mass in its own frame;
* ``inertia``: the moment of inertia about the link's own centre of mass (axis normal to the
  plane), ``mass``: its mass, both > 0;
* the **joint angle** :math:`q` is the angle of the child's frame relative to the parent's,
  counter-clockwise (the joint axis is the plane's normal :math:`z`); at :math:`q = 0` the two
  frames are parallel;
* the absolute angle of link :math:`i` is :math:`\\alpha_i = \\theta + \\sum_{j \\in
  \\text{path}(i)} q_j`, where :math:`\\theta` is the root's angle to the inertial :math:`x` axis and
  the sum runs over the joints from the root to link :math:`i`.

A joint is named by ``joint_name`` (default: the child link's name); that name is the body's state
(the joint angle), and ``u_<joint name>`` its input (the joint rate). Optional limits:
``lower <= q <= upper`` and ``|dq/dt| <= velocity``.

Links may be listed in any order; chains and branched trees are both allowed, loops are not.
"""

from __future__ import annotations

import dataclasses
from typing import Iterable, Mapping

from ...core.keywords import RESERVED_NAMES
from ...core.validate import pair, real
from ..tree.links import LinkRecord, TreeLinkTable, check_joint_fields

__all__ = ["Link", "LinkTable", "RESERVED_NAMES"]


@dataclasses.dataclass(frozen=True)
class Link(LinkRecord):
    """One rigid link of a planar body (see the module docstring for the conventions).

    Parameters
    ----------
    name, parent
        The link's name and its parent's, as in :class:`~acroplan.families.tree.links.LinkRecord`.
    mass : float
        > 0.
    inertia : float
        Moment of inertia about the link's own centre of mass, > 0.
    com : (float, float)
        Centre of mass in the link's own frame.
    joint : (float, float)
        Position of this link's joint in the **parent's** frame (``(0, 0)`` for the root).
    joint_name, lower, upper, velocity
        The joint's name and limits, as in :class:`~acroplan.families.tree.links.LinkRecord`.

    Notes
    -----
    A ``Link`` is a plain record; it is checked when a :class:`LinkTable` (or a
    :class:`~acroplan.families.planar.model.PlanarBody`) is built from it, so that a message can
    name it by its position, ``links[2].mass``.
    """

    name: str
    parent: str | None
    mass: float
    inertia: float
    com: tuple[float, float] = (0.0, 0.0)
    joint: tuple[float, float] = (0.0, 0.0)
    joint_name: str | None = None
    lower: float | None = None
    upper: float | None = None
    velocity: float | None = None

    def __post_init__(self):
        for f in ("com", "joint"):  # lists from files become tuples, so that links are hashable
            v = getattr(self, f)
            if isinstance(v, list):
                object.__setattr__(self, f, tuple(v))

    @property
    def is_root(self) -> bool:
        return self.parent is None


@dataclasses.dataclass(frozen=True, init=False, repr=False)
class LinkTable(TreeLinkTable):
    """A checked, immutable link table: the links of one planar body and their tree.

    Parameters
    ----------
    links : sequence of Link (or of mappings with :class:`Link`'s fields)
        One root (``parent=None``), every other link's parent in the table, no loops.

    Attributes
    ----------
    links : tuple of Link
        The links, in the order given, with numbers as floats.
    root : int
        Index of the root link.
    parents : tuple of int, length n_links
        Index of each link's parent, ``-1`` for the root. This tuple is the body's topology (and
        its compiled structure).
    joints : tuple of int, length n_links - 1
        Indices of the non-root links, in table order: the order of the joint angles in the state.
    joint_names : tuple of str, length n_links - 1

    Raises
    ------
    InvalidInputError
        Naming the field (``links[2].mass: must be > 0``), for bad numbers, duplicate names, an
        unknown parent, no root or two roots, and loops.
    """

    links: tuple[Link, ...]
    LINK = Link
    EXAMPLE = "[Link('a', None, 1.0, 0.1), Link('b', 'a', 1.0, 0.1, joint=(1.0, 0.0))]"
    ROOT_STATE = "angle is the state theta"
    RESERVED_WHY = "it is the root angle or a keyword of plan() or simulate()"

    def __init__(self, links: Iterable[Link | Mapping]):
        super().__init__(links)

    @staticmethod
    def _check(field: str, link: Link) -> Link:
        common = check_joint_fields(field, link)
        mass = real(f"{field}.mass", link.mass, positive=True)
        inertia = real(f"{field}.inertia", link.inertia, positive=True)
        com = pair(f"{field}.com", link.com)
        joint = pair(f"{field}.joint", link.joint)
        return Link(common["name"], common["parent"], mass, inertia, com, joint, common["joint_name"],
                    common["lower"], common["upper"], common["velocity"])
