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

A link may carry the solids it is **drawn** with (``shapes``: the 3-D human's Yeadon solids; no
part of the dynamics, :mod:`~acroplan.families.spatial.solids`); a link without them is drawn as
its equivalent box.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Iterable, Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ...core.keywords import RESERVED_NAMES as _KEYWORDS
from ...core.validate import real as _real
from ..tree.links import LinkRecord, TreeLinkTable, check_joint_fields

__all__ = ["SpatialLink", "SpatialLinkTable", "RESERVED_NAMES", "QUATERNION_NAMES"]

#: The state names of the root's attitude quaternion ``[w, x, y, z]``.
QUATERNION_NAMES = ("qw", "qx", "qy", "qz")
#: Names a joint may not take: the attitude's, and the keywords of ``plan()`` and ``simulate()``.
RESERVED_NAMES = frozenset(_KEYWORDS | set(QUATERNION_NAMES) | {"attitude", "angular_momentum", "L"})


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


def _tupled(v):
    return tuple(_tupled(x) for x in v) if isinstance(v, (list, tuple)) else v


#: The drawn solids' kinds and how many numbers each takes (SpatialLink.shapes)
SHAPE_PARAMS = {"stadium_solid": 5, "semiellipsoid": 3}


def _shapes(field: str, value):
    """``shapes`` checked: ``None`` or a tuple of ``(kind, params, origin, rotation)`` of floats."""
    if value is None:
        return None
    hint = "give (kind, params, origin, rotation) per solid, kind one of " + ", ".join(SHAPE_PARAMS)
    if isinstance(value, (str, bytes)) or not isinstance(value, (tuple, list)):
        raise InvalidInputError(field, f"must be a list of solids, got {type(value).__name__}", hint)
    out = []
    for k, shape in enumerate(value):
        f = f"{field}[{k}]"
        if not isinstance(shape, (tuple, list)) or len(shape) != 4 or shape[0] not in SHAPE_PARAMS:
            raise InvalidInputError(f, f"must be (kind, params, origin, rotation), got {shape!r}"[:200], hint)
        kind, params, origin, rotation = shape
        try:
            params = tuple(float(x) for x in params)
        except (TypeError, ValueError):
            raise InvalidInputError(f"{f}.params", "must be numbers", hint) from None
        if len(params) != SHAPE_PARAMS[kind] or not all(math.isfinite(x) and x >= 0 for x in params):
            raise InvalidInputError(f"{f}.params", f"must be {SHAPE_PARAMS[kind]} finite numbers >= 0 for a {kind}, "
                                    f"got {params}", hint)
        R = _rotation(f"{f}.rotation", rotation)
        out.append((kind, params, _vec3(f"{f}.origin", origin), R if R is not None else
                    ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))))
    return tuple(out)


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
class SpatialLink(LinkRecord):
    """One rigid link of a spatial body (see the module docstring for the conventions).

    Parameters
    ----------
    name, parent
        As in :class:`~acroplan.families.tree.links.LinkRecord`.
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
    joint_name, lower, upper, velocity
        The joint's name and limits (:class:`~acroplan.families.tree.links.LinkRecord`).
    shapes : tuple, optional
        The solids the link is drawn with (never the dynamics): each
        ``(kind, params, origin, rotation)``, ``kind`` ``"stadium_solid"`` (params ``r0, t0, r1,
        t1, height``) or ``"semiellipsoid"`` (``r, t, height``), placed in the link's frame at
        ``origin`` (3,) turned by ``rotation`` (3 x 3) (:mod:`~acroplan.families.spatial.solids`).
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
    shapes: Any = None

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
        if isinstance(self.shapes, list):  # (read from a record: lists all the way down)
            object.__setattr__(self, "shapes", _tupled(self.shapes))

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


@dataclasses.dataclass(frozen=True, init=False, repr=False)
class SpatialLinkTable(TreeLinkTable):
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
    LINK = SpatialLink
    EXAMPLE = "[SpatialLink('a', None, 1.0, (0.1, 0.1, 0.1)), ...]"
    ROOT_STATE = "attitude is the state"
    ROOT_FREE = ("rotation", "joint_name", "lower", "upper", "velocity")
    RESERVED = RESERVED_NAMES
    RESERVED_WHY = "it is an attitude state or a keyword of plan() or simulate()"
    MIN_LINKS = "at least two links (the root and one more)"

    def __init__(self, links: Iterable[SpatialLink | Mapping]):
        super().__init__(links)

    def _check_links(self, links) -> None:
        if sum(link.mass for link in links) <= 0.0:
            raise InvalidInputError("links", "have no mass", "give at least one link mass > 0")

    @staticmethod
    def _check(field: str, link: SpatialLink) -> SpatialLink:
        common = check_joint_fields(field, link)
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
        return SpatialLink(common["name"], common["parent"], mass, inertia, com, joint, axis, rotation,
                           common["joint_name"], common["lower"], common["upper"], common["velocity"],
                           _shapes(f"{field}.shapes", link.shapes))
