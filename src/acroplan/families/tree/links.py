"""What the link tables of tree bodies share: the checks of a table (a list of links, one root, a
tree, unique joint names that clash with no keyword) and of the fields every link has (its name,
parent, joint name and limits). Each family's table adds the physics of its links (a planar
link's scalar inertia and 2-D vectors; a spatial link's inertia tensor, axis and rotation).
"""

from __future__ import annotations

import dataclasses
from typing import Any, ClassVar, Iterable, Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ...core.keywords import RESERVED_NAMES
from ...core.validate import identifier, real
from .topology import LinkTree, tree_of

__all__ = ["LinkRecord", "TreeLinkTable", "check_joint_fields", "combine_rigid", "RESERVED_NAMES"]


def combine_rigid(pieces) -> tuple[float, np.ndarray, np.ndarray]:
    """One rigid body of ``pieces`` ``(mass, centre of mass (3,), inertia about it (3, 3))`` in one
    frame: the total mass, the centre of mass, and the inertia about it (the parallel-axis theorem,
    :math:`J = \\sum_k J_k + m_k (|d_k|^2 I - d_k d_k^\\top)`, symmetrised); no pieces: a massless
    link (zeros)."""
    if not pieces:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    m = float(sum(p[0] for p in pieces))
    c = sum(p[0] * p[1] for p in pieces) / m
    J = sum(p[2] + p[0] * (float((p[1] - c) @ (p[1] - c)) * np.eye(3) - np.outer(p[1] - c, p[1] - c)) for p in pieces)
    return m, c, 0.5 * (J + J.T)


class LinkRecord:
    """Mixin of a family's link dataclass: building it from plain data, naming the field.

    Attributes
    ----------
    name : str
        A Python identifier, unique in the table.
    parent : str or None
        The parent link's name; ``None`` for the root (exactly one).
    joint_name : str, optional
        Name of the joint to the parent (default: ``name``); a Python identifier.
    lower, upper : float, optional
        Joint-angle limits (rad).
    velocity : float, optional
        Joint-rate limit :math:`|\\dot q| \\le` ``velocity`` (rad/s, > 0).

    Notes
    -----
    These are the fields every family's link has (each family adds its link's physics); they are
    checked by :func:`check_joint_fields` when a table is built.
    """

    __slots__ = ()
    #: the fields every link needs
    REQUIRED: ClassVar[tuple[str, ...]] = ("name", "mass", "inertia")
    #: the fields a message suggests
    HINT: ClassVar[str] = "give name, parent, mass and inertia"

    def to_dict(self) -> dict[str, Any]:
        """The link as plain data (what a result file records): tuples become lists."""
        out = dataclasses.asdict(self)
        return {k: (_listed(v) if isinstance(v, tuple) else v) for k, v in out.items()}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], field: str = "link"):
        """Build from :meth:`to_dict`'s output (unknown keys are refused, naming ``field``)."""
        if not isinstance(d, Mapping):
            raise InvalidInputError(field, f"must be a table of link fields, got {type(d).__name__}", cls.HINT)
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(d) - names)
        if unknown:
            raise InvalidInputError(f"{field}.{unknown[0]}", "is not a link field", f"link fields are {sorted(names)}")
        missing = [n for n in cls.REQUIRED if n not in d]
        if missing:
            raise InvalidInputError(f"{field}.{missing[0]}", "is missing", cls.HINT)
        d = dict(d)
        d.setdefault("parent", None)
        return cls(**d)


def _listed(v):
    return [_listed(x) if isinstance(x, tuple) else x for x in v]


def check_joint_fields(field: str, link) -> dict[str, Any]:
    """The checked fields every link has: ``name`` (an identifier), ``parent`` (a name or None),
    ``joint_name``, the joint limits ``lower < upper`` and the rate limit ``velocity > 0``."""
    name = identifier(f"{field}.name", link.name, "link")
    parent = link.parent
    if parent is not None and not isinstance(parent, str):
        raise InvalidInputError(f"{field}.parent", f"must be a link name or None, got {parent!r}",
                                "give the parent link's name, or None for the root")
    jn = link.joint_name
    if jn is not None:
        jn = identifier(f"{field}.joint_name", jn, "joint")
    lower = real(f"{field}.lower", link.lower, optional=True)
    upper = real(f"{field}.upper", link.upper, optional=True)
    if lower is not None and upper is not None and not lower < upper:
        raise InvalidInputError(f"{field}.lower", f"must be < upper, got lower = {lower:g}, upper = {upper:g}",
                                "swap or widen the joint limits")
    velocity = link.velocity
    if velocity is not None:
        velocity = real(f"{field}.velocity", velocity)
        if not velocity > 0:
            raise InvalidInputError(f"{field}.velocity", f"must be > 0, got {velocity:g}",
                                    "give the joint's top speed in rad/s, or None")
    return dict(name=name, parent=parent, joint_name=jn, lower=lower, upper=upper, velocity=velocity)


class TreeLinkTable(LinkTree):
    """A checked, immutable link table: the base of the families' tables.

    A subclass is a frozen dataclass with a field ``links`` and sets

    * ``LINK``: its link record class; ``EXAMPLE``: a call that builds a table, for messages;
    * ``ROOT_STATE``: what the root's motion is (``"angle is the state theta"``), for messages;
    * ``ROOT_FREE``: the fields a root may not have (it has no joint to a parent);
    * ``RESERVED`` and ``RESERVED_WHY``: the names a joint may not take, and why;
    * ``MIN_LINKS``: the fewest links a body has;
    * ``_check(field, link) -> link``: the checked link (its numbers);
    * optionally ``_check_links(links)``: a check of the whole table (a body with mass).
    """

    __slots__ = ()
    LINK: ClassVar[type]
    EXAMPLE: ClassVar[str] = ""
    ROOT_STATE: ClassVar[str] = "motion is the root's"
    ROOT_FREE: ClassVar[tuple[str, ...]] = ("joint_name", "lower", "upper", "velocity")
    RESERVED: ClassVar[frozenset] = RESERVED_NAMES
    RESERVED_WHY: ClassVar[str] = "it is a state of the root or a keyword of plan() or simulate()"
    MIN_LINKS: ClassVar[str] = "at least one link (the root)"

    def __init__(self, links: Iterable):
        if isinstance(links, type(self)):
            links = links.links
        name = self.LINK.__name__
        if isinstance(links, (str, bytes, Mapping)) or not isinstance(links, Iterable):
            raise InvalidInputError("links", f"must be a list of {name}, got {type(links).__name__}",
                                    f"give for example {self.EXAMPLE}")
        raw = list(links)
        if not raw:
            raise InvalidInputError("links", "is empty", f"give {self.MIN_LINKS}")
        checked = []
        for i, link in enumerate(raw):
            field = f"links[{i}]"
            if isinstance(link, Mapping):
                link = self.LINK.from_dict(link, field)
            if not isinstance(link, self.LINK):
                raise InvalidInputError(field, f"must be a {name}, got {type(link).__name__}",
                                        f"build it with {self.LINK.__module__.rsplit('.', 1)[0]}.{name}(...)")
            checked.append(self._check(field, link))
        links = tuple(checked)
        root, parents = tree_of(links, self.ROOT_STATE)
        r = links[root]
        zero = type(r.joint)(0.0 for _ in r.joint)
        if r.joint != zero:
            raise InvalidInputError(f"links[{root}].joint", f"the root has no joint to a parent, got {r.joint}",
                                    "leave it out (the root's frame is any frame fixed in it; put an offset in com)")
        for f in self.ROOT_FREE:
            if getattr(r, f) is not None:
                raise InvalidInputError(f"links[{root}].{f}", "the root has no joint to a parent",
                                        "leave it out: the root moves freely")
        self._check_links(links)
        joints = tuple(i for i in range(len(links)) if i != root)
        jnames = []
        for i in joints:
            jn = links[i].joint_name or links[i].name
            field = f"links[{i}].joint_name" if links[i].joint_name else f"links[{i}].name"
            if jn in self.RESERVED:
                raise InvalidInputError(field, f"{jn!r} cannot name a joint ({self.RESERVED_WHY})",
                                        "give the joint another name with joint_name=")
            if jn in jnames:
                raise InvalidInputError(field, f"joint name {jn!r} is used twice", "give every joint its own name "
                                        "(joint_name= defaults to the child link's name)")
            jnames.append(jn)
        object.__setattr__(self, "links", links)
        object.__setattr__(self, "_derived", {"root": root, "parents": tuple(parents), "joints": joints,
                                              "joint_names": tuple(jnames)})

    @classmethod
    def of(cls, links):
        """The table of ``links``: a table of this type as it is, else the table of a body (its
        ``links``) or built from a sequence of links (or of mappings of their fields)."""
        if isinstance(links, cls):
            return links
        table = getattr(links, "links", links)
        return table if isinstance(table, cls) else cls(table)

    def _check_links(self, links) -> None:
        """A check of the whole table (none by default)."""

    def __repr__(self) -> str:
        return f"{type(self).__name__}({list(self.links)!r})"
