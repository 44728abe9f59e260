"""Spatial bodies from URDF files, read by Pinocchio (never by a hand-written XML parser).

:func:`read_link_table` builds the model with ``pinocchio.buildModelFromUrdf(path,
JointModelFreeFlyer())`` (the URDF's root link on a free-flyer root) and reads, per moving joint
(links joined by ``fixed`` joints are merged into their parent by Pinocchio, inertias combined):

* the link it carries (named after the URDF link), its mass, centre of mass and inertia tensor about
  the centre of mass, in the link's frame (Pinocchio's joint frame, the URDF joint's frame);
* the joint's placement in the parent's frame: its position (``joint``) and its fixed rotation
  (``rotation``, the URDF ``rpy``), and its axis, given in the table in the parent's frame
  (:math:`R_{fixed}\\,a_{urdf}`, so that the child frame at angle :math:`q` is
  :math:`\\mathrm{Rot}(a, q) R_{fixed} = R_{fixed}\\,\\mathrm{Rot}(a_{urdf}, q)`, as in the URDF);
* the joint limits: position (``lower``, ``upper``; none for a ``continuous`` joint) and rate
  (``velocity``), honoured unless overridden (``overrides=``) or dropped (``limits=False``).

Every joint must be revolute (``revolute`` or ``continuous``): a prismatic, planar or floating
joint is refused, naming it. Names become Python identifiers (other characters become ``_``; a
clash with the attitude's ``qw, qx, qy, qz`` or a keyword of ``plan()`` gets a ``_joint`` suffix).

:func:`to_urdf` writes a link table as a URDF (for tests and for other tools).
"""

from __future__ import annotations

import pathlib
from typing import Mapping
from xml.sax.saxutils import quoteattr

import numpy as np

from ...core.errors import InvalidInputError
from ..planar.pin import require_pinocchio
from ..planar.urdf import _frame_link_name, _limit
from .links import RESERVED_NAMES, SpatialLink, SpatialLinkTable

__all__ = ["read_link_table", "read_urdf", "to_urdf"]

_LIMIT_KEYS = ("lower", "upper", "velocity")


def _identifier(name: str, taken: set, suffix: str) -> str:
    import keyword
    import re

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


def read_link_table(path, *, limits: bool = True, overrides: Mapping[str, Mapping] | None = None) -> SpatialLinkTable:
    """The link table of a URDF with revolute joints (module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
    limits : bool
        Read the joint limits from the URDF (default) or leave them out.
    overrides : mapping of joint name to mapping, optional
        Per joint (URDF or table name), any of ``lower``, ``upper``, ``velocity`` (``None`` drops it).

    Returns
    -------
    SpatialLinkTable
        Root first, then the links in Pinocchio's (depth-first) order.

    Raises
    ------
    InvalidInputError
        Pinocchio missing, the file missing or unreadable, a joint that is not revolute (named), an
        unknown override.
    """
    pin = require_pinocchio()
    p = pathlib.Path(path)
    if not p.is_file():
        raise InvalidInputError("urdf", f"no such file: {str(p)!r}", "give the path of a .urdf file")
    try:
        model = pin.buildModelFromUrdf(str(p), pin.JointModelFreeFlyer())
    except Exception as e:  # Pinocchio raises ValueError or RuntimeError on a bad file
        raise InvalidInputError("urdf", f"Pinocchio could not read {p.name}: {e}", "check the URDF") from None
    if model.njoints < 3:
        raise InvalidInputError("urdf", f"{p.name} has no moving joint", "give a URDF with revolute joints")
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    link_names, joint_names = set(), set()
    rows = []
    for jid in range(1, model.njoints):
        jm = model.joints[jid]
        jname = model.names[jid]
        axis = None
        if jid > 1:
            kind = jm.shortname()
            if jm.nv != 1:
                raise InvalidInputError(f"urdf joint {jname!r}", f"is a {kind} with {jm.nv} degrees of freedom, not a "
                                        "revolute joint", "a spatial body has only revolute joints (revolute or "
                                        "continuous); make a multi-axis joint of revolute joints through massless links")
            S = np.asarray(data.joints[jid].S).reshape(6)
            if np.linalg.norm(S[:3]) > 1e-9 or abs(np.linalg.norm(S[3:]) - 1.0) > 1e-9:
                raise InvalidInputError(f"urdf joint {jname!r}", f"is not a revolute joint ({kind}: it translates)",
                                        "a spatial body has only revolute joints (revolute or continuous)")
            axis = S[3:] / np.linalg.norm(S[3:])
            if model.parents[jid] < 1:
                raise InvalidInputError(f"urdf joint {jname!r}", "is not below the root link", "check the URDF tree")
        lname = _frame_link_name(model, jid, pin)
        rows.append((jid, _identifier(lname, link_names, "_link"), lname, jname,
                     _identifier(jname, joint_names, "_joint") if jid > 1 else None, axis))
    by_name = {}
    for jid, _, _, jname, tname, _ in rows[1:]:
        by_name[jname] = jid
        by_name[tname] = jid
    over: dict[int, dict] = {}
    for key, values in dict(overrides or {}).items():
        if key not in by_name:
            raise InvalidInputError(f"overrides.{key}", "is not a joint of the URDF",
                                    f"joints are {[r[3] for r in rows[1:]]}")
        if not isinstance(values, Mapping):
            raise InvalidInputError(f"overrides.{key}", f"must be a table of limits, got {values!r}",
                                    "give for example {'lower': -1.0, 'upper': 1.0, 'velocity': 5.0}")
        bad = sorted(set(values) - set(_LIMIT_KEYS))
        if bad:
            raise InvalidInputError(f"overrides.{key}.{bad[0]}", "is not a joint limit", f"give any of {list(_LIMIT_KEYS)}")
        over.setdefault(by_name[key], {}).update(values)
    names = {r[0]: r[1] for r in rows}
    links = []
    for jid, tlink, lname, jname, tname, axis in rows:
        Y = model.inertias[jid]
        mass, com, inertia = float(Y.mass), np.asarray(Y.lever, dtype=float), np.asarray(Y.inertia, dtype=float)
        if mass == 0.0:
            inertia = np.zeros((3, 3))
        if jid == 1:
            links.append(SpatialLink(tlink, None, mass, inertia, com=tuple(com)))
            continue
        P = model.jointPlacements[jid]
        Rf = np.asarray(P.rotation, dtype=float)
        lo = up = vel = None
        if limits:
            jm = model.joints[jid]
            if jm.nq == 1:  # revolute; a continuous joint (nq = 2) has no position limits
                lo = _limit(model.lowerPositionLimit[jm.idx_q])
                up = _limit(model.upperPositionLimit[jm.idx_q])
            vel = _limit(model.velocityLimit[jm.idx_v])
            if vel is not None and vel <= 0:
                vel = None
        for k, v in over.get(jid, {}).items():
            v = None if v is None else float(v)
            lo, up, vel = (v, up, vel) if k == "lower" else (lo, v, vel) if k == "upper" else (lo, up, v)
        if lo is not None and up is not None and not lo < up:
            raise InvalidInputError(f"urdf joint {jname!r}", f"has lower = {lo:g} >= upper = {up:g}",
                                    "fix its <limit>, or override it (overrides=)")
        rotation = None if np.allclose(Rf, np.eye(3), rtol=0.0, atol=1e-15) else Rf
        links.append(SpatialLink(tlink, names[model.parents[jid]], mass, inertia, com=tuple(com),
                                 joint=tuple(np.asarray(P.translation, dtype=float)), axis=tuple(Rf @ axis),
                                 rotation=rotation, joint_name=tname, lower=lo, upper=up, velocity=vel))
    return SpatialLinkTable(links)


def read_urdf(path, L=(0.0, 0.0, 0.0), *, limits: bool = True, overrides=None):
    """A :class:`~acroplan.families.spatial.model.SpatialBody` from a URDF (:func:`read_link_table`).

    Parameters
    ----------
    path : str or pathlib.Path
    L : (float, float, float)
        The angular momentum about the centre of mass (inertial frame).
    """
    from .model import SpatialBody

    return SpatialBody(read_link_table(path, limits=limits, overrides=overrides), L=L)


def _num(v: float) -> str:
    return repr(float(v))


def to_urdf(links, name: str = "spatial_body", effort: float = 1000.0) -> str:
    """A URDF document of a spatial link table.

    Each joint's ``<origin>`` is the link's ``joint`` with the ``rpy`` of its ``rotation``
    (:math:`R = R_z(y) R_y(p) R_x(r)`), its ``<axis>`` the table's axis in the joint's frame
    (:math:`R_{fixed}^\\top a`); a joint with both position limits is ``revolute``, one without is
    ``continuous`` (a one-sided limit is written with the open side at :math:`\\pm 10^{300}`).
    Massless links are written without ``<inertial>``. Pinocchio reads the document back
    (:func:`read_urdf`) with the same masses, inertias, joints and limits; it numbers the joints
    depth-first in the URDF's order, so they may come back in another order.

    Parameters
    ----------
    links : SpatialLinkTable, sequence of SpatialLink, or SpatialBody
    name : str
        The robot's name.
    effort : float
        The ``effort`` attribute of each ``<limit>`` (URDF requires one; acroplan does not use it).

    Returns
    -------
    str
    """
    from scipy.spatial.transform import Rotation

    table = getattr(links, "links", links)
    table = table if isinstance(table, SpatialLinkTable) else SpatialLinkTable(table)
    out = ['<?xml version="1.0"?>', f"<robot name={quoteattr(name)}>"]
    for link in table:
        out.append(f"  <link name={quoteattr(link.name)}>")
        if link.mass > 0:
            I = link.inertia_matrix  # noqa: E741
            c = link.com
            out += ["    <inertial>",
                    f'      <origin xyz="{_num(c[0])} {_num(c[1])} {_num(c[2])}" rpy="0 0 0"/>',
                    f'      <mass value="{_num(link.mass)}"/>',
                    f'      <inertia ixx="{_num(I[0, 0])}" ixy="{_num(I[0, 1])}" ixz="{_num(I[0, 2])}" '
                    f'iyy="{_num(I[1, 1])}" iyz="{_num(I[1, 2])}" izz="{_num(I[2, 2])}"/>',
                    "    </inertial>"]
        out.append("  </link>")
    for i in table.topological_order():
        if i == table.root:
            continue
        link = table[i]
        jname = table.joint_names[table.joints.index(i)]
        Rf = link.rotation_matrix
        r, p, y = Rotation.from_matrix(Rf).as_euler("xyz")
        a = Rf.T @ np.asarray(link.axis)
        bounded = link.lower is not None or link.upper is not None
        j = link.joint
        out += [f"  <joint name={quoteattr(jname)} type=\"{'revolute' if bounded else 'continuous'}\">",
                f"    <parent link={quoteattr(link.parent)}/>",
                f"    <child link={quoteattr(link.name)}/>",
                f'    <origin xyz="{_num(j[0])} {_num(j[1])} {_num(j[2])}" rpy="{_num(r)} {_num(p)} {_num(y)}"/>',
                f'    <axis xyz="{_num(a[0])} {_num(a[1])} {_num(a[2])}"/>']
        attrs = []
        if bounded:
            attrs += [f'lower="{_num(-1e300 if link.lower is None else link.lower)}"',
                      f'upper="{_num(1e300 if link.upper is None else link.upper)}"']
        if bounded or link.velocity is not None:
            attrs += [f'effort="{_num(effort)}"', f'velocity="{_num(link.velocity or 0.0)}"']
            out.append(f"    <limit {' '.join(attrs)}/>")
        out.append("  </joint>")
    out.append("</robot>")
    return "\n".join(out) + "\n"
