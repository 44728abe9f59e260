"""The link table of a free-floating body in 3-D: rigid links joined by revolute joints in a tree.

Conventions
-----------
Every link carries a frame that moves with it. The **root** link (exactly one, ``parent=None``) has
its frame anywhere in it: the body's attitude :math:`q` is that frame's. Every other link's frame
has its origin at its joint with its parent. Vectors of a link are given in **its own** frame,
except the joint's position and axis, which are given in the **parent's** frame:

* ``joint = (jx, jy, jz)``: the child's joint (its frame's origin) in the parent's frame;
* ``axis = (ax, ay, az)``: the joint axis in the parent's frame (normalised here);
* ``rotation`` (optional, 3 x 3, default the identity): the child frame's orientation relative to
  the parent's at joint angle 0. At joint angle :math:`q` the child frame is turned by

  .. math::  R_{parent \\leftarrow child}(q) = \\mathrm{Rot}(a, q)\\, R_{fixed} ,

  a right-handed turn by :math:`q` about the axis :math:`a` (so with the default ``rotation`` the
  frames are parallel at :math:`q = 0`, as for planar bodies);
* ``com = (cx, cy, cz)``: the link's centre of mass in its own frame;
* ``inertia``: the link's inertia tensor about its own centre of mass in its own frame, a symmetric
  positive semi-definite 3 x 3 matrix, or its three principal moments (the frame's axes are then
  its principal axes); ``mass`` >= 0.

Massless links (``mass = 0``, zero inertia) make joints of several degrees of freedom out of
revolute joints, as URDF does (a universal joint is two revolute joints through a massless link).

A joint is named by ``joint_name`` (default: the child link's name); that name is the body's state
(the joint angle), ``u_<joint name>`` its input (the joint rate). Optional limits:
``lower <= q <= upper`` and ``|dq/dt| <= velocity``.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Iterable, Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ..tree import LinkTree, tree_of
from ..planar.links import RESERVED_NAMES as _PLANAR_RESERVED
from ..planar.links import _identifier, _real

__all__ = ["SpatialLink", "SpatialLinkTable", "RESERVED_NAMES", "QUATERNION_NAMES"]

#: The state names of the root's attitude quaternion ``[w, x, y, z]``.
QUATERNION_NAMES = ("qw", "qx", "qy", "qz")
#: Names a joint may not take: the attitude's, and the keywords of ``plan()`` and ``simulate()``.
RESERVED_NAMES = frozenset(_PLANAR_RESERVED | set(QUATERNION_NAMES) | {"attitude", "angular_momentum", "L"})


def _vec3(field: str, value, *, nonzero: bool = False) -> tuple[float, float, float]:
    try:
        a = [value[i] for i in range(3)]
        if len(value) != 3:
            raise ValueError
    except (TypeError, ValueError, IndexError, KeyError):
        raise InvalidInputError(field, f"must be three numbers (x, y, z), got {value!r}",
                                "give for example (0.0, 0.0, 0.5)") from None
    out = tuple(_real(f"{field}[{i}]", v) for i, v in enumerate(a))
    if nonzero and math.sqrt(sum(v * v for v in out)) < 1e-12:
        raise InvalidInputError(field, f"must not be zero, got {value!r}", "give the joint axis, for example (0, 0, 1)")
    return out


def _matrix3(field: str, value) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(field, f"must be a 3 x 3 matrix of numbers, got {value!r}",
                                "give three rows of three numbers") from None
    if a.shape != (3, 3) or not np.isfinite(a).all():
        raise InvalidInputError(field, f"must be a 3 x 3 matrix of finite numbers, got shape {a.shape}",
                                "give three rows of three numbers")
    return a


def _inertia(field: str, value, mass: float) -> tuple[tuple[float, ...], ...]:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(field, f"must be three principal moments or a 3 x 3 matrix, got {value!r}",
                                "give for example (0.1, 0.1, 0.02)") from None
    if a.shape == (3,):
        a = np.diag(a)
    if a.shape != (3, 3) or not np.isfinite(a).all():
        raise InvalidInputError(field, f"must be three principal moments or a 3 x 3 matrix, got shape {a.shape}",
                                "give for example (0.1, 0.1, 0.02)")
    scale = max(1.0, float(np.max(np.abs(a))))
    if np.max(np.abs(a - a.T)) > 1e-12 * scale:
        raise InvalidInputError(field, "is not symmetric", "give a symmetric matrix (Ixy = Iyx, ...)")
    a = 0.5 * (a + a.T)
    ev = np.linalg.eigvalsh(a)
    if ev[0] < -1e-12 * scale:
        raise InvalidInputError(field, f"has a negative principal moment ({ev[0]:.6g})",
                                "give a positive semi-definite inertia")
    # a rigid body's principal moments satisfy the triangle inequality I1 + I2 >= I3
    if ev[0] + ev[1] < ev[2] * (1 - 1e-9) - 1e-12 * scale:
        raise InvalidInputError(field, f"principal moments {ev.tolist()} break I1 + I2 >= I3, which every rigid body "
                                "satisfies", "check the inertia tensor (about the link's own centre of mass)")
    if mass == 0.0 and ev[-1] > 0.0:
        raise InvalidInputError(field, "is not zero but the link has no mass", "give mass > 0, or inertia 0")
    return tuple(tuple(float(v) for v in row) for row in a)


def _rotation(field: str, value) -> tuple[tuple[float, ...], ...] | None:
    if value is None:
        return None
    R = _matrix3(field, value)
    if np.max(np.abs(R.T @ R - np.eye(3))) > 1e-9 or np.linalg.det(R) < 0:
        raise InvalidInputError(field, "is not a rotation matrix (orthonormal, determinant +1)",
                                "give a proper rotation (for example from scipy's Rotation.as_matrix())")
    # re-orthonormalise to rounding (polar decomposition)
    U, _, Vt = np.linalg.svd(R)
    R = U @ Vt
    return tuple(tuple(float(v) for v in row) for row in R)


@dataclasses.dataclass(frozen=True)
class SpatialLink:
    """One rigid link of a spatial body (see the module docstring for the conventions).

    Parameters
    ----------
    name : str
        A Python identifier, unique in the table.
    parent : str or None
        The parent link's name; ``None`` for the root (exactly one).
    mass : float
        >= 0 (0 for the massless links of multi-axis joints).
    inertia : (3,) or (3, 3)
        About the link's centre of mass, in its frame.
    com : (float, float, float)
        Centre of mass in the link's own frame.
    joint : (float, float, float)
        This link's joint (its frame's origin) in the **parent's** frame.
    axis : (float, float, float)
        The joint axis in the **parent's** frame (normalised when the table is built).
    rotation : 3 x 3, optional
        The link frame's orientation relative to the parent's at joint angle 0 (default identity).
    joint_name : str, optional
    lower, upper : float, optional
        Joint-angle limits (rad).
    velocity : float, optional
        Joint-rate limit (rad/s, > 0).
    """

    name: str
    parent: str | None
    mass: float
    inertia: Any
    com: tuple = (0.0, 0.0, 0.0)
    joint: tuple = (0.0, 0.0, 0.0)
    axis: tuple = (0.0, 0.0, 1.0)
    rotation: Any = None
    joint_name: str | None = None
    lower: float | None = None
    upper: float | None = None
    velocity: float | None = None

    def __post_init__(self):
        for f in ("com", "joint", "axis"):
            v = getattr(self, f)
            if isinstance(v, (list, np.ndarray)):
                object.__setattr__(self, f, tuple(float(x) for x in v))
        for f in ("inertia", "rotation"):
            v = getattr(self, f)
            if isinstance(v, (list, np.ndarray)):
                a = np.asarray(v, dtype=float)
                object.__setattr__(self, f, tuple(a.tolist()) if a.ndim == 1 else tuple(tuple(r) for r in a.tolist()))

    @property
    def is_root(self) -> bool:
        return self.parent is None

    @property
    def inertia_matrix(self) -> np.ndarray:
        """The inertia tensor, shape (3, 3)."""
        a = np.asarray(self.inertia, dtype=float)
        return np.diag(a) if a.shape == (3,) else a

    @property
    def rotation_matrix(self) -> np.ndarray:
        """``rotation`` as a (3, 3) array (the identity when not given)."""
        return np.eye(3) if self.rotation is None else np.asarray(self.rotation, dtype=float)

    def to_dict(self) -> dict[str, Any]:
        """The link as plain data (lists)."""
        out = {}
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if isinstance(v, tuple):
                v = [list(r) if isinstance(r, tuple) else r for r in v]
            out[f.name] = v
        return out

    @classmethod
    def from_dict(cls, d: Mapping[str, Any], field: str = "link") -> "SpatialLink":
        """Build from :meth:`to_dict`'s output (unknown keys are refused, naming ``field``)."""
        if not isinstance(d, Mapping):
            raise InvalidInputError(field, f"must be a table of link fields, got {type(d).__name__}",
                                    "give name, parent, mass, inertia, com, joint, axis")
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(d) - names)
        if unknown:
            raise InvalidInputError(f"{field}.{unknown[0]}", "is not a link field", f"link fields are {sorted(names)}")
        missing = [n for n in ("name", "mass", "inertia") if n not in d]
        if missing:
            raise InvalidInputError(f"{field}.{missing[0]}", "is missing", "give name, parent, mass and inertia")
        d = dict(d)
        d.setdefault("parent", None)
        return cls(**d)


@dataclasses.dataclass(frozen=True, init=False)
class SpatialLinkTable(LinkTree):
    """A checked, immutable link table of a spatial body (a tree).

    Parameters
    ----------
    links : sequence of SpatialLink (or of mappings with its fields)

    Attributes
    ----------
    links : tuple of SpatialLink
        With numbers as floats, axes normalised, inertias as 3 x 3 tuples.
    root : int
    parents : tuple of int
        Parent index per link, -1 for the root: the body's topology (its compiled structure).
    joints : tuple of int
        The non-root links in table order: the order of the joint angles in the state.
    joint_names : tuple of str

    Raises
    ------
    InvalidInputError
        Naming the field, for bad numbers, duplicate names, an unknown parent, no root or two
        roots, loops, and a body without mass.
    """

    links: tuple[SpatialLink, ...]

    def __init__(self, links: Iterable[SpatialLink | Mapping]):
        if isinstance(links, SpatialLinkTable):
            links = links.links
        if isinstance(links, (str, bytes, Mapping)) or not isinstance(links, Iterable):
            raise InvalidInputError("links", f"must be a list of SpatialLink, got {type(links).__name__}",
                                    "give for example [SpatialLink('a', None, 1.0, (0.1, 0.1, 0.1)), ...]")
        raw = list(links)
        if not raw:
            raise InvalidInputError("links", "is empty", "give at least two links (the root and one more)")
        checked = []
        for i, link in enumerate(raw):
            field = f"links[{i}]"
            if isinstance(link, Mapping):
                link = SpatialLink.from_dict(link, field)
            if not isinstance(link, SpatialLink):
                raise InvalidInputError(field, f"must be a SpatialLink, got {type(link).__name__}",
                                        "build it with acroplan.families.spatial.SpatialLink(...)")
            checked.append(self._check(field, link))
        links = tuple(checked)
        root, parents = tree_of(links, "attitude is the state")
        r = links[root]
        if r.joint != (0.0, 0.0, 0.0):
            raise InvalidInputError(f"links[{root}].joint", f"the root has no joint to a parent, got {r.joint}",
                                    "leave it out (the root's frame is any frame fixed in it)")
        for f in ("rotation", "joint_name", "lower", "upper", "velocity"):
            if getattr(r, f) is not None:
                raise InvalidInputError(f"links[{root}].{f}", "the root has no joint to a parent",
                                        "leave it out: the root's attitude is free")
        if sum(link.mass for link in links) <= 0.0:
            raise InvalidInputError("links", "have no mass", "give at least one link mass > 0")
        joints = tuple(i for i in range(len(links)) if i != root)
        jnames = []
        for i in joints:
            jn = links[i].joint_name or links[i].name
            field = f"links[{i}].joint_name" if links[i].joint_name else f"links[{i}].name"
            if jn in RESERVED_NAMES:
                raise InvalidInputError(field, f"{jn!r} cannot name a joint (it is an attitude state or a keyword of "
                                        "plan() or simulate())", "give the joint another name with joint_name=")
            if jn in jnames:
                raise InvalidInputError(field, f"joint name {jn!r} is used twice", "give every joint its own name "
                                        "(joint_name= defaults to the child link's name)")
            jnames.append(jn)
        object.__setattr__(self, "links", links)
        object.__setattr__(self, "_derived", {"root": root, "parents": tuple(parents), "joints": joints,
                                              "joint_names": tuple(jnames)})

    @staticmethod
    def _check(field: str, link: SpatialLink) -> SpatialLink:
        name = _identifier(f"{field}.name", link.name, "link")
        parent = link.parent
        if parent is not None and not isinstance(parent, str):
            raise InvalidInputError(f"{field}.parent", f"must be a link name or None, got {parent!r}",
                                    "give the parent link's name, or None for the root")
        mass = _real(f"{field}.mass", link.mass)
        if mass < 0:
            raise InvalidInputError(f"{field}.mass", f"must be >= 0, got {mass:g}", "give the link's mass in kg")
        inertia = _inertia(f"{field}.inertia", link.inertia, mass)
        com = _vec3(f"{field}.com", link.com)
        joint = _vec3(f"{field}.joint", link.joint)
        axis = _vec3(f"{field}.axis", link.axis, nonzero=True)
        n = math.sqrt(sum(v * v for v in axis))
        axis = tuple(v / n for v in axis)
        rotation = _rotation(f"{field}.rotation", link.rotation)
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
        return SpatialLink(name, parent, mass, inertia, com, joint, axis, rotation, jn, lower, upper, velocity)

    def __repr__(self) -> str:
        return f"SpatialLinkTable({list(self.links)!r})"
