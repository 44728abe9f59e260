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
import keyword
import math
from typing import Any, Iterable, Mapping

from ...core.errors import InvalidInputError
from ..tree import LinkTree, tree_of

__all__ = ["Link", "LinkTable", "RESERVED_NAMES"]

#: Names a joint may not take: the root angle, and the keywords of ``plan()`` and ``simulate()``
#: (a joint's name is a keyword argument of both).
RESERVED_NAMES = frozenset({
    "theta", "times", "conditions", "method", "basis", "n_coefficients", "limits", "u_max", "state_bounds",
    "input_bounds", "verify", "tol", "max_evaluations", "progress", "inputs", "system",
})


@dataclasses.dataclass(frozen=True)
class Link:
    """One rigid link of a planar body (see the module docstring for the conventions).

    Parameters
    ----------
    name : str
        A Python identifier, unique in the table.
    parent : str or None
        The parent link's name; ``None`` for the root (exactly one).
    mass : float
        > 0.
    inertia : float
        Moment of inertia about the link's own centre of mass, > 0.
    com : (float, float)
        Centre of mass in the link's own frame.
    joint : (float, float)
        Position of this link's joint in the **parent's** frame (``(0, 0)`` for the root).
    joint_name : str, optional
        Name of the joint to the parent (default: ``name``); a Python identifier.
    lower, upper : float, optional
        Joint-angle limits (rad).
    velocity : float, optional
        Joint-rate limit :math:`|\\dot q| \\le` ``velocity`` (rad/s, > 0).

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

    def to_dict(self) -> dict[str, Any]:
        """The link as plain data (what a result file records)."""
        out = dataclasses.asdict(self)
        out["com"], out["joint"] = list(self.com), list(self.joint)
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], field: str = "link") -> "Link":
        """Build from :meth:`to_dict`'s output (unknown keys are refused, naming ``field``)."""
        if not isinstance(d, Mapping):
            raise InvalidInputError(field, f"must be a table of link fields, got {type(d).__name__}",
                                    "give name, parent, mass, inertia, com, joint")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(d) - names)
        if unknown:
            raise InvalidInputError(f"{field}.{unknown[0]}", "is not a link field",
                                    f"link fields are {sorted(names)}")
        missing = [n for n in ("name", "mass", "inertia") if n not in d]
        if missing:
            raise InvalidInputError(f"{field}.{missing[0]}", "is missing", "give name, parent, mass and inertia")
        d = dict(d)
        d.setdefault("parent", None)
        return cls(**d)


def _real(field: str, value, *, positive: bool = False, allow_none: bool = False) -> float | None:
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)) and not hasattr(value, "__float__"):
        raise InvalidInputError(field, f"must be a real number, got {value!r}", "give a finite number")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InvalidInputError(field, f"must be a real number, got {value!r}", "give a finite number") from None
    if not math.isfinite(v):
        raise InvalidInputError(field, f"must be finite, got {v}", "give a finite number")
    if positive and not v > 0:
        raise InvalidInputError(field, f"must be > 0, got {v:g}", "give a positive value")
    return v


def _pair(field: str, value) -> tuple[float, float]:
    try:
        x, y = value
    except (TypeError, ValueError):
        raise InvalidInputError(field, f"must be a pair (x, y), got {value!r}", "give for example (0.5, 0.0)") from None
    return (_real(f"{field}[0]", x), _real(f"{field}[1]", y))


def _identifier(field: str, value, what: str) -> str:
    if not isinstance(value, str) or not value.isidentifier() or keyword.iskeyword(value):
        raise InvalidInputError(field, f"must be a Python identifier, got {value!r}",
                                f"give the {what} a name of letters, digits and underscores (for example 'arm1')")
    return value


@dataclasses.dataclass(frozen=True, init=False)
class LinkTable(LinkTree):
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

    def __init__(self, links: Iterable[Link | Mapping]):
        if isinstance(links, LinkTable):
            links = links.links
        if isinstance(links, (str, bytes, Mapping)) or not isinstance(links, Iterable):
            raise InvalidInputError("links", f"must be a list of Link, got {type(links).__name__}",
                                    "give for example [Link('a', None, 1.0, 0.1), Link('b', 'a', 1.0, 0.1, "
                                    "joint=(1.0, 0.0))]")
        raw = list(links)
        if not raw:
            raise InvalidInputError("links", "is empty", "give at least one link (the root)")
        checked = []
        for i, link in enumerate(raw):
            field = f"links[{i}]"
            if isinstance(link, Mapping):
                link = Link.from_dict(link, field)
            if not isinstance(link, Link):
                raise InvalidInputError(field, f"must be a Link, got {type(link).__name__}",
                                        "build it with acroplan.families.planar.Link(...)")
            checked.append(self._check(field, link))
        links = tuple(checked)
        root, parents = tree_of(links, "angle is the state theta")
        r = links[root]
        if r.joint != (0.0, 0.0):
            raise InvalidInputError(f"links[{root}].joint", f"the root has no joint to a parent, got {r.joint}",
                                    "leave it out (its frame is any point of the root; put that offset in com)")
        for f in ("joint_name", "lower", "upper", "velocity"):
            if getattr(r, f) is not None:
                raise InvalidInputError(f"links[{root}].{f}", "the root has no joint to a parent",
                                        "leave it out: the root's angle theta is free")
        joints = tuple(i for i in range(len(links)) if i != root)
        jnames = []
        for i in joints:
            jn = links[i].joint_name or links[i].name
            field = f"links[{i}].joint_name" if links[i].joint_name else f"links[{i}].name"
            if jn in RESERVED_NAMES:
                raise InvalidInputError(field, f"{jn!r} cannot name a joint (it is the root angle or a keyword of "
                                        "plan() or simulate())", "give the joint another name with joint_name=")
            if jn in jnames:
                raise InvalidInputError(field, f"joint name {jn!r} is used twice", "give every joint its own name "
                                        "(joint_name= defaults to the child link's name)")
            jnames.append(jn)
        object.__setattr__(self, "links", links)
        object.__setattr__(self, "_derived", {
            "root": root, "parents": tuple(parents), "joints": joints, "joint_names": tuple(jnames),
        })

    @staticmethod
    def _check(field: str, link: Link) -> Link:
        name = _identifier(f"{field}.name", link.name, "link")
        parent = link.parent
        if parent is not None and not isinstance(parent, str):
            raise InvalidInputError(f"{field}.parent", f"must be a link name or None, got {parent!r}",
                                    "give the parent link's name, or None for the root")
        mass = _real(f"{field}.mass", link.mass, positive=True)
        inertia = _real(f"{field}.inertia", link.inertia, positive=True)
        com = _pair(f"{field}.com", link.com)
        joint = _pair(f"{field}.joint", link.joint)
        jn = link.joint_name
        if jn is not None:
            jn = _identifier(f"{field}.joint_name", jn, "joint")
        lower = _real(f"{field}.lower", link.lower, allow_none=True)
        upper = _real(f"{field}.upper", link.upper, allow_none=True)
        if lower is not None and upper is not None and not lower < upper:
            raise InvalidInputError(f"{field}.lower", f"must be < upper, got lower = {lower:g}, upper = {upper:g}",
                                    "swap or widen the joint limits")
        velocity = link.velocity
        if velocity is not None:
            velocity = _real(f"{field}.velocity", velocity)
            if not velocity > 0:
                raise InvalidInputError(f"{field}.velocity", f"must be > 0, got {velocity:g}",
                                        "give the joint's top speed in rad/s, or None")
        return Link(name, parent, mass, inertia, com, joint, jn, lower, upper, velocity)

    def __repr__(self) -> str:
        return f"LinkTable({list(self.links)!r})"
