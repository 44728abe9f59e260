"""Planar bodies from URDF files, read by Pinocchio (never by a hand-written XML parser).

:func:`read_link_table` builds the model with ``pinocchio.buildModelFromUrdf(path,
JointModelPlanar())`` (the URDF's root link on a planar root joint) and reads, at the neutral
configuration (every joint angle 0, the root at the origin with :math:`\\theta = 0`):

* one link per moving joint (links joined by ``fixed`` joints are merged into their parent by
  Pinocchio, inertias combined), named after the URDF link the joint carries;
* its mass, and its inertia about its centre of mass about the plane's normal (the ``zz`` entry
  in the world frame, :math:`(R I R^\\top)_{zz}`);
* its centre of mass and its joint position, projected on the plane: the :math:`z` components are
  dropped, which is exact for the motion in the plane;
* the joint limits: position (``lower``, ``upper``; none for a ``continuous`` joint) and rate
  (``velocity``), honoured unless overridden (``overrides=``) or dropped (``limits=False``).

Planar means: every joint is revolute (``revolute`` or ``continuous``), and every joint axis, in
the root frame at the neutral configuration, is parallel to :math:`z`. A joint whose axis is
:math:`-z` is read with its angle's sign flipped (so that every joint angle of the table is
counter-clockwise about :math:`+z`; its limits flip too). Anything else (a prismatic, floating or
planar joint, an axis off :math:`z`) is refused, naming the joint.

Each link's frame in the table is parallel to the root's at the neutral configuration (its
origin at its joint), so a URDF ``rpy`` on a joint's origin is absorbed into the vectors, and the
joint angles mean what they mean in the URDF (up to the sign flip above).

Names become Python identifiers (other characters become ``_``; a clash with ``theta`` or a
keyword of ``plan()`` gets a ``_joint`` suffix), since joint names are state names.

:func:`to_urdf` writes a link table as a URDF (for tests and for other tools).
"""

from __future__ import annotations

import keyword
import math
import pathlib
import re
from typing import Mapping
from xml.sax.saxutils import quoteattr

import numpy as np

from ...core.errors import InvalidInputError
from .links import RESERVED_NAMES, Link, LinkTable
from .pin import require_pinocchio

__all__ = ["read_link_table", "read_urdf", "to_urdf"]

#: Axis tolerance: a joint axis counts as parallel to z when it is within this of (0, 0, +-1).
AXIS_TOL = 1e-9
_LIMIT_KEYS = ("lower", "upper", "velocity")


def _identifier(name: str, taken: set, suffix: str) -> str:
    out = re.sub(r"\W", "_", name) or "_"
    if out[0].isdigit():
        out = "_" + out
    if keyword.iskeyword(out) or out in RESERVED_NAMES:
        out = out + suffix
    base, k = out, 1
    while out in taken:
        k += 1
        out = f"{base}_{k}"
    taken.add(out)
    return out


def _limit(v: float) -> float | None:
    v = float(v)
    return v if math.isfinite(v) and abs(v) < 1e300 else None


def _frame_link_name(model, joint_id: int, pin) -> str:
    """The URDF link a joint carries: the body frame attached right after the joint's frame."""
    for f in model.frames:
        # Pinocchio 3+ names; Pinocchio 2 called them parent and previousFrame
        parent_joint = f.parentJoint if hasattr(f, "parentJoint") else f.parent
        parent_frame = f.parentFrame if hasattr(f, "parentFrame") else f.previousFrame
        if f.type == pin.FrameType.BODY and parent_joint == joint_id and \
                model.frames[parent_frame].type == pin.FrameType.JOINT:
            return f.name
    return model.names[joint_id]


def read_link_table(path, *, limits: bool = True, overrides: Mapping[str, Mapping] | None = None) -> LinkTable:
    """The link table of a planar URDF (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        A URDF file.
    limits : bool
        Read the joint limits from the URDF (default) or leave them out.
    overrides : mapping of joint name to mapping, optional
        Per joint (its URDF name or its table name), any of ``lower``, ``upper``, ``velocity``
        (a number, or ``None`` to drop it): replaces what the URDF says.

    Returns
    -------
    LinkTable
        Root first, then the links in Pinocchio's (depth-first) order.

    Raises
    ------
    InvalidInputError
        Pinocchio missing, the file missing or unreadable, a joint that is not revolute about an
        axis parallel to z (named), a link without mass or inertia (named), an unknown override.
    """
    pin = require_pinocchio()
    p = pathlib.Path(path)
    if not p.is_file():
        raise InvalidInputError("urdf", f"no such file: {str(p)!r}", "give the path of a .urdf file")
    try:
        model = pin.buildModelFromUrdf(str(p), pin.JointModelPlanar())
    except Exception as e:  # Pinocchio raises ValueError or RuntimeError on a bad file
        raise InvalidInputError("urdf", f"Pinocchio could not read {p.name}: {e}", "check the URDF") from None
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    if model.njoints < 3:
        raise InvalidInputError("urdf", f"{p.name} has no moving joint", "give a URDF with revolute joints")

    link_names, joint_names = set(), set()
    rows = []  # (pinocchio joint id, table link name, URDF link name, URDF joint name, table joint name, sign)
    for jid in range(1, model.njoints):
        jm = model.joints[jid]
        jname = model.names[jid]
        lname = _frame_link_name(model, jid, pin)
        sign = 1.0
        if jid > 1:
            kind = jm.shortname()
            if jm.nv != 1:
                raise InvalidInputError(f"urdf joint {jname!r}", f"is a {kind} with {jm.nv} degrees of freedom, "
                                        "not a revolute joint", "a planar body has only revolute joints about z")
            S = np.asarray(data.joints[jid].S).reshape(6)
            if np.linalg.norm(S[:3]) > AXIS_TOL or abs(np.linalg.norm(S[3:]) - 1.0) > AXIS_TOL:
                raise InvalidInputError(f"urdf joint {jname!r}", f"is not a revolute joint ({kind}: it translates)",
                                        "a planar body has only revolute joints (revolute or continuous) about z")
            axis = data.oMi[jid].rotation @ S[3:]
            if abs(abs(axis[2]) - 1.0) > AXIS_TOL or math.hypot(axis[0], axis[1]) > AXIS_TOL:
                raise InvalidInputError(f"urdf joint {jname!r}", f"turns about ({axis[0]:.6g}, {axis[1]:.6g}, "
                                        f"{axis[2]:.6g}) in the root frame, not about z: the body is not planar",
                                        "every joint axis must be parallel to the z axis (axis 0 0 1 in the plane "
                                        "of motion)")
            sign = 1.0 if axis[2] > 0 else -1.0
        if jid > 1 and model.parents[jid] < 1:
            raise InvalidInputError(f"urdf joint {jname!r}", "is not below the root link", "check the URDF tree")
        rows.append((jid, _identifier(lname, link_names, "_link"), lname, jname,
                     _identifier(jname, joint_names, "_joint") if jid > 1 else None, sign))

    overrides = dict(overrides or {})
    by_name = {}
    for jid, _, _, jname, tname, _ in rows[1:]:
        by_name[jname] = jid
        by_name[tname] = jid
    over: dict[int, dict] = {}
    for key, values in overrides.items():
        if key not in by_name:
            raise InvalidInputError(f"overrides.{key}", "is not a joint of the URDF",
                                    f"joints are {[r[3] for r in rows[1:]]}")
        if not isinstance(values, Mapping):
            raise InvalidInputError(f"overrides.{key}", f"must be a table of limits, got {values!r}",
                                    "give for example {'lower': -1.0, 'upper': 1.0, 'velocity': 5.0}")
        bad = sorted(set(values) - set(_LIMIT_KEYS))
        if bad:
            raise InvalidInputError(f"overrides.{key}.{bad[0]}", "is not a joint limit",
                                    f"give any of {list(_LIMIT_KEYS)}")
        over.setdefault(by_name[key], {}).update(values)

    world = {}  # joint id -> (com relative to the joint, joint relative to the parent's joint, mass, izz)
    parent_of = {}
    for jid, tname_link, lname, jname, tname, sign in rows:
        M = data.oMi[jid]
        Y = model.inertias[jid]
        if not Y.mass > 0:
            raise InvalidInputError(f"urdf link {lname!r}", f"has no mass (mass {Y.mass:g})",
                                    "give it an <inertial> element with mass > 0, or join it to its parent with a "
                                    "fixed joint")
        izz = float((M.rotation @ np.asarray(Y.inertia) @ M.rotation.T)[2, 2])
        if not izz > 0:
            raise InvalidInputError(f"urdf link {lname!r}", f"has no inertia about z (izz {izz:g})",
                                    "give its <inertia> a positive izz")
        # vectors rotated into the world frame (no subtraction of positions: exact when unrotated)
        com = (M.rotation @ np.asarray(Y.lever))[:2]
        parent = model.parents[jid]
        joint = (data.oMi[parent].rotation @ np.asarray(model.jointPlacements[jid].translation))[:2] \
            if jid > 1 else np.zeros(2)
        world[jid] = (com, joint, Y.mass, izz)
        parent_of[jid] = parent

    names = {r[0]: r[1] for r in rows}
    links = []
    for jid, tname_link, lname, jname, tname, sign in rows:
        com, joint, mass, izz = world[jid]
        rel_com = tuple(float(v) for v in com)
        if jid == 1:
            links.append(Link(tname_link, None, float(mass), izz, com=rel_com))
            continue
        parent = parent_of[jid]
        joint = tuple(float(v) for v in joint)
        lo = up = vel = None
        if limits:
            jm = model.joints[jid]
            if jm.nq == 1:  # revolute; a continuous joint (nq = 2, cos and sin) has no position limits
                lo = _limit(model.lowerPositionLimit[jm.idx_q])
                up = _limit(model.upperPositionLimit[jm.idx_q])
            vel = _limit(model.velocityLimit[jm.idx_v])
            if vel is not None and vel <= 0:
                vel = None
            if sign < 0:
                lo, up = (None if up is None else -up), (None if lo is None else -lo)
        for k, v in over.get(jid, {}).items():
            v = None if v is None else float(v)
            if k == "lower":
                lo = v
            elif k == "upper":
                up = v
            else:
                vel = v
        if lo is not None and up is not None and not lo < up:
            raise InvalidInputError(f"urdf joint {jname!r}", f"has lower = {lo:g} >= upper = {up:g}",
                                    "fix its <limit>, or override it (overrides=)")
        links.append(Link(tname_link, names[parent], float(mass), izz, com=rel_com, joint=joint,
                          joint_name=tname, lower=lo, upper=up, velocity=vel))
    return LinkTable(links)


def read_urdf(path, P0: float = 0.0, *, limits: bool = True, overrides=None):
    """A :class:`~acroplan.families.planar.model.PlanarBody` from a planar URDF.

    Parameters
    ----------
    path : str or pathlib.Path
    P0 : float
        Angular momentum about the centre of mass.
    limits, overrides
        As :func:`read_link_table`.

    Returns
    -------
    PlanarBody
        Its joint limits are in its table (:meth:`PlanarBody.joint_limits`).
    """
    from .model import PlanarBody

    return PlanarBody(read_link_table(path, limits=limits, overrides=overrides), P0=P0)


def _num(v: float) -> str:
    return repr(float(v))


def to_urdf(links, name: str = "planar_body", effort: float = 1000.0) -> str:
    """A URDF document of a link table (every joint revolute about z).

    Each link's ``<inertial>`` has its centre of mass at ``(cx, cy, 0)`` and the inertia
    ``diag(I/2, I/2, I)``; each joint's ``<origin>`` is ``(jx, jy, 0)`` with no rotation. A joint
    with both position limits is ``revolute``; one without any is ``continuous``; a one-sided limit
    is written with the open side at :math:`\\pm 10^{300}` (read back as none).

    Parameters
    ----------
    links : LinkTable, sequence of Link, or PlanarBody
    name : str
        The robot's name.
    effort : float
        The ``effort`` attribute URDF requires on ``<limit>`` (unused here).

    Returns
    -------
    str
    """
    table = getattr(links, "links", links)
    table = table if isinstance(table, LinkTable) else LinkTable(table)
    out = ['<?xml version="1.0"?>', f"<robot name={quoteattr(name)}>"]
    for link in table:
        I = link.inertia  # noqa: E741
        out += [f"  <link name={quoteattr(link.name)}>",
                "    <inertial>",
                f'      <origin xyz="{_num(link.com[0])} {_num(link.com[1])} 0" rpy="0 0 0"/>',
                f'      <mass value="{_num(link.mass)}"/>',
                f'      <inertia ixx="{_num(I / 2)}" ixy="0" ixz="0" iyy="{_num(I / 2)}" iyz="0" izz="{_num(I)}"/>',
                "    </inertial>",
                "  </link>"]
    for i in table.topological_order():
        if i == table.root:
            continue
        link = table[i]
        jname = table.joint_names[table.joints.index(i)]
        bounded = link.lower is not None or link.upper is not None
        kind = "revolute" if bounded else "continuous"
        out += [f"  <joint name={quoteattr(jname)} type=\"{kind}\">",
                f"    <parent link={quoteattr(link.parent)}/>",
                f"    <child link={quoteattr(link.name)}/>",
                f'    <origin xyz="{_num(link.joint[0])} {_num(link.joint[1])} 0" rpy="0 0 0"/>',
                '    <axis xyz="0 0 1"/>']
        attrs = []
        if bounded:
            lo = -1e300 if link.lower is None else link.lower
            up = 1e300 if link.upper is None else link.upper
            attrs += [f'lower="{_num(lo)}"', f'upper="{_num(up)}"']
        if bounded or link.velocity is not None:
            attrs += [f'effort="{_num(effort)}"', f'velocity="{_num(link.velocity or 0.0)}"']
            out.append(f"    <limit {' '.join(attrs)}/>")
        out.append("  </joint>")
    out.append("</robot>")
    return "\n".join(out) + "\n"
