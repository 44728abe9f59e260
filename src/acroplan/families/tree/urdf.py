"""What reading and writing URDF share for tree bodies (planar and spatial): the reader
(:func:`read_tree`: the model Pinocchio builds, each joint checked revolute, the links' and joints'
names made identifiers, the joint limits with their overrides), and the writer (:func:`robot_xml`:
the XML of a link's inertia and of a joint)."""

from __future__ import annotations

import keyword
import math
import os
import pathlib
import re
from typing import Mapping
from xml.sax.saxutils import quoteattr

import numpy as np

from ...core.errors import InvalidInputError
from ...core.files import MAX_PATH_CHARS
from ...core.validate import MAX_LINKS, short
from .pin import require_pinocchio
from .urdfscan import captured_stderr, scan_urdf

__all__ = ["read_tree", "identifier", "robot_xml", "limit", "frame_link_name", "load_model", "urdf_links", "revolute_motion", "table_names",
           "limit_overrides", "joint_limits", "inertial_xml", "joint_xml", "LIMIT_KEYS"]

#: the joint limits a URDF gives and an override may replace
LIMIT_KEYS = ("lower", "upper", "velocity")


def identifier(name: str, taken: set, suffix: str, reserved) -> str:
    """``name`` made a Python identifier not in ``reserved`` (``suffix`` appended) nor in ``taken``
    (``_2``, ``_3``, ... appended); added to ``taken``."""
    out = re.sub(r"\W", "_", name) or "_"
    if out[0].isdigit():
        out = "_" + out
    if keyword.iskeyword(out) or out in reserved:
        out = out + suffix
    base, k = out, 1
    while out in taken:
        k += 1
        out = f"{base}_{k}"
    taken.add(out)
    return out


def limit(v: float) -> float | None:
    """A URDF limit, ``None`` when it is infinite or beyond 1e300 (URDF's way of saying none)."""
    v = float(v)
    return v if math.isfinite(v) and abs(v) < 1e300 else None


def frame_link_name(model, joint_id: int, pin) -> str:
    """The URDF link a joint carries: the body frame attached right after the joint's frame."""
    for f in model.frames:
        # Pinocchio 3+ names; Pinocchio 2 called them parent and previousFrame
        parent_joint = f.parentJoint if hasattr(f, "parentJoint") else f.parent
        parent_frame = f.parentFrame if hasattr(f, "parentFrame") else f.previousFrame
        if f.type == pin.FrameType.BODY and parent_joint == joint_id and \
                model.frames[parent_frame].type == pin.FrameType.JOINT:
            return f.name
    return model.names[joint_id]


def load_model(path, root: str):
    """Pinocchio's model of the URDF ``path`` with the root joint ``root`` (``"planar"`` or
    ``"freeflyer"``), its data at the neutral configuration after forward kinematics.

    The file is checked first, in one streaming pass (:func:`~acroplan.families.tree.urdfscan.scan_urdf`:
    its size, its links and moving joints counted, every number of the links' inertias and of the
    joints checked), so that Pinocchio never sees a file that would crash it or that it would read
    into another body; what urdfdom prints while Pinocchio reads it is captured, and an error it
    reports refuses the file with urdfdom's own words.

    Returns
    -------
    (pinocchio, model, data)
    """
    pin = require_pinocchio()
    if not isinstance(path, (str, os.PathLike)):
        raise InvalidInputError("urdf", f"must be the path of a .urdf file, got {type(path).__name__}",
                                "give the path of a .urdf file")
    text = os.fspath(path)
    if not text or len(text) > MAX_PATH_CHARS or "\0" in text:
        raise InvalidInputError("urdf", "is not a usable path (empty, a NUL byte, or more than "
                                f"{MAX_PATH_CHARS} characters)", "give the path of a .urdf file")
    p = pathlib.Path(text)
    try:
        is_file = p.is_file()
    except OSError as e:  # a name too long for the file system, ...
        raise InvalidInputError("urdf", f"cannot be read ({type(e).__name__})", "give the path of a .urdf file") \
            from None
    if not is_file:
        raise InvalidInputError("urdf", f"no such file: {short(str(p), 200)}", "give the path of a .urdf file")
    scan_urdf(p)
    joint = pin.JointModelPlanar() if root == "planar" else pin.JointModelFreeFlyer()
    printed: list[str] = []
    try:
        with captured_stderr(printed):
            model = pin.buildModelFromUrdf(str(p), joint)
    except Exception as e:  # Pinocchio raises ValueError or RuntimeError on a bad file
        said = _urdfdom_error(printed) or short(str(e), 300)
        raise InvalidInputError("urdf", f"Pinocchio could not read {p.name}: {said}", "check the URDF") from None
    said = _urdfdom_error(printed)
    if said:  # urdfdom read the file by leaving something out (a link's inertia, ...): another body
        raise InvalidInputError("urdf", f"Pinocchio's URDF reader reported an error in {p.name}: {said}",
                                "check the URDF") from None
    if model.njoints < 3:
        raise InvalidInputError("urdf", f"{p.name} has no moving joint", "give a URDF with revolute joints")
    if model.njoints - 1 > MAX_LINKS:  # pragma: no cover - the scan counted the moving joints
        raise InvalidInputError("urdf", f"{p.name} has {model.njoints - 1} moving links, more than {MAX_LINKS}",
                                f"give at most {MAX_LINKS} links")
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    return pin, model, data


def read_tree(path, root: str, table_type, reserved, joint_of, link_of, *, limits: bool = True,
              overrides: Mapping[str, Mapping] | None = None):
    """The link table of a URDF: what the families' ``read_link_table`` share.

    Parameters
    ----------
    path : str or pathlib.Path
        A URDF file (:func:`load_model`).
    root : {"planar", "freeflyer"}
        Pinocchio's root joint.
    table_type : type
        The family's link table.
    reserved : collection of str
        Names a link or joint may not take (they get a ``_link`` or ``_joint`` suffix).
    joint_of : callable
        ``joint_of(model, data, jid)``: what the family reads of the moving joint ``jid`` (``>= 2``,
        checked revolute by :func:`revolute_motion`), or its error naming the joint.
    link_of : callable
        ``link_of(model, data, row, parent, lims)``: the family's link of
        ``row = (jid, table link name, URDF link name, URDF joint name, table joint name, what
        joint_of read)`` (for the root: no joint name, ``None`` read), ``parent`` its parent's table
        name (``None`` for the root), ``lims(sign=1.0)`` its joint's ``(lower, upper, velocity)``
        (:func:`joint_limits`).
    limits : bool
        Read the joint limits from the URDF (default) or leave them out.
    overrides : mapping of joint name to mapping, optional
        Per joint (its URDF name or its table name), any of ``lower``, ``upper``, ``velocity``
        (a number, or ``None`` to drop it): replaces what the URDF says.

    Returns
    -------
    table_type
        Root first, then the links in Pinocchio's (depth-first) order.

    Raises
    ------
    InvalidInputError
        Pinocchio missing, the file missing, unreadable, too large or with more than
        :data:`~acroplan.core.validate.MAX_LINKS` moving links (counted before Pinocchio reads it),
        a joint that is not revolute or has ``lower >= upper`` (named), a link ``table_type``
        refuses (the URDF link named), an unknown override; and the family's errors.
    """
    pin, model, data = load_model(path, root)
    link_names, joint_names = set(), set()
    rows = []
    for jid in range(1, model.njoints):
        read = joint_of(model, data, jid) if jid > 1 else None
        rows.append((jid, *table_names(model, jid, pin, link_names, joint_names, reserved), read))
    over = limit_overrides({k: r[0] for r in rows[1:] for k in (r[3], r[4])}, [r[3] for r in rows[1:]], overrides)
    names = {r[0]: r[1] for r in rows}
    links = []
    for row in rows:
        jid = row[0]
        parent = names[model.parents[jid]] if jid > 1 else None
        links.append(link_of(model, data, row, parent,
                             lambda sign=1.0, jid=jid: joint_limits(model, jid, over, limits, sign)))
    return urdf_links(table_type, links, [r[2] for r in rows])


def _urdfdom_error(lines: list[str]) -> str:
    """The first error urdfdom printed (``Error:   ...``), without its source location; "" when none."""
    for line in lines:
        if line.lower().startswith("error"):
            text = line.split(":", 1)[1].strip() if ":" in line else line
            return text if len(text) <= 200 else text[:197] + "..."
    return ""


def urdf_links(table_type, links, urdf_names):
    """``table_type(links)`` (a family's link table) with an error about ``links[i]`` naming the URDF
    link ``urdf_names[i]`` instead (``urdf link 'arm'``)."""
    try:
        return table_type(links)
    except InvalidInputError as e:
        m = re.match(r"links\[(\d+)\](\.(\w+))?(.*)$", e.field)
        if m is None or int(m.group(1)) >= len(urdf_names):
            raise
        what = (m.group(3) or "") + m.group(4)
        problem = f"{what} {e.problem}" if what else e.problem
        raise InvalidInputError(f"urdf link {urdf_names[int(m.group(1))]!r}", problem, e.fix) from None


def revolute_motion(model, data, jid: int, what: str, multi_fix: str, tol: float = 1e-9) -> np.ndarray:
    """The motion subspace (6,) of joint ``jid``, checked to be one revolute degree of freedom
    (``what`` names the body in messages, ``multi_fix`` says what to do with a joint of several)."""
    jm = model.joints[jid]
    jname = model.names[jid]
    kind = jm.shortname()
    if jm.nv != 1:
        raise InvalidInputError(f"urdf joint {jname!r}", f"is a {kind} with {jm.nv} degrees of freedom, not a "
                                "revolute joint", multi_fix)
    S = np.asarray(data.joints[jid].S).reshape(6)
    if np.linalg.norm(S[:3]) > tol or abs(np.linalg.norm(S[3:]) - 1.0) > tol:
        raise InvalidInputError(f"urdf joint {jname!r}", f"is not a revolute joint ({kind}: it translates)",
                                f"a {what} body has only revolute joints (revolute or continuous)")
    if model.parents[jid] < 1:
        raise InvalidInputError(f"urdf joint {jname!r}", "is not below the root link", "check the URDF tree")
    return S


def table_names(model, jid: int, pin, link_names: set, joint_names: set, reserved) -> tuple[str, str, str, str | None]:
    """``(table link name, URDF link name, URDF joint name, table joint name)`` of joint ``jid``
    (the root, ``jid == 1``, has no table joint name)."""
    lname = frame_link_name(model, jid, pin)
    jname = model.names[jid]
    return (identifier(lname, link_names, "_link", reserved), lname, jname,
            identifier(jname, joint_names, "_joint", reserved) if jid > 1 else None)


def limit_overrides(names: Mapping[str, int], urdf_joints: list[str], overrides) -> dict[int, dict]:
    """Per joint id, the limits ``overrides`` (by URDF or table joint name, ``names``) replace."""
    over: dict[int, dict] = {}
    for key, values in dict(overrides or {}).items():
        if key not in names:
            raise InvalidInputError(f"overrides.{key}", "is not a joint of the URDF", f"joints are {urdf_joints}")
        if not isinstance(values, Mapping):
            raise InvalidInputError(f"overrides.{key}", f"must be a table of limits, got {values!r}",
                                    "give for example {'lower': -1.0, 'upper': 1.0, 'velocity': 5.0}")
        bad = sorted(set(values) - set(LIMIT_KEYS))
        if bad:
            raise InvalidInputError(f"overrides.{key}.{bad[0]}", "is not a joint limit", f"give any of {list(LIMIT_KEYS)}")
        over.setdefault(names[key], {}).update(values)
    return over


def joint_limits(model, jid: int, over: Mapping, read: bool, sign: float = 1.0):
    """``(lower, upper, velocity)`` of joint ``jid``: the URDF's (when ``read``; with ``sign = -1``
    the joint's angle is measured the other way), then its overrides."""
    lo = up = vel = None
    if read:
        jm = model.joints[jid]
        if jm.nq == 1:  # revolute; a continuous joint (nq = 2, cos and sin) has no position limits
            lo = limit(model.lowerPositionLimit[jm.idx_q])
            up = limit(model.upperPositionLimit[jm.idx_q])
        vel = limit(model.velocityLimit[jm.idx_v])
        if vel is not None and vel <= 0:
            vel = None
        if sign < 0:
            lo, up = (None if up is None else -up), (None if lo is None else -lo)
    for k, v in over.get(jid, {}).items():
        v = None if v is None else float(v)
        lo, up, vel = (v, up, vel) if k == "lower" else (lo, v, vel) if k == "upper" else (lo, up, v)
    if lo is not None and up is not None and not lo < up:
        raise InvalidInputError(f"urdf joint {model.names[jid]!r}", f"has lower = {lo:g} >= upper = {up:g}",
                                "fix its <limit>, or override it (overrides=)")
    return lo, up, vel


def _num(v: float) -> str:
    """A number as URDF text: whole numbers as integers ("0 0 1"), others with every digit."""
    v = float(v)
    return str(int(v)) if v.is_integer() and abs(v) < 1e15 else repr(v)


def inertial_xml(com, mass: float, I) -> list[str]:  # noqa: E741
    """The ``<inertial>`` lines of a link: centre of mass ``com`` (3,), ``mass``, inertia (3, 3)."""
    return ["    <inertial>",
            f'      <origin xyz="{_num(com[0])} {_num(com[1])} {_num(com[2])}" rpy="0 0 0"/>',
            f'      <mass value="{_num(mass)}"/>',
            f'      <inertia ixx="{_num(I[0][0])}" ixy="{_num(I[0][1])}" ixz="{_num(I[0][2])}" '
            f'iyy="{_num(I[1][1])}" iyz="{_num(I[1][2])}" izz="{_num(I[2][2])}"/>',
            "    </inertial>"]


def robot_xml(table, name: str, effort: float, inertial, frame) -> str:
    """A URDF document of the link table ``table``: a ``<link>`` per link with its ``<inertial>``,
    a ``<joint>`` per joint (:func:`joint_xml`: ``revolute`` with position limits, ``continuous``
    without), in the depth-first order a URDF reader needs; what the families' ``to_urdf`` share.

    Parameters
    ----------
    table : TreeLinkTable
    name : str
        The robot's name.
    effort : float
        The ``effort`` attribute of each ``<limit>`` (URDF requires one; acroplan does not use it).
    inertial : callable
        ``inertial(link)``: ``(com, mass, I)`` of :func:`inertial_xml`, or ``None`` for a link
        without mass.
    frame : callable
        ``frame(link)``: its joint's ``(xyz, rpy, axis)`` (:func:`joint_xml`).

    Returns
    -------
    str
    """
    out = ['<?xml version="1.0"?>', f"<robot name={quoteattr(name)}>"]
    for link in table:
        out.append(f"  <link name={quoteattr(link.name)}>")
        numbers = inertial(link)
        if numbers is not None:
            out += inertial_xml(*numbers)
        out.append("  </link>")
    for i in table.topological_order():
        if i != table.root:
            link = table[i]
            out += joint_xml(table.joint_names[table.joints.index(i)], link, *frame(link), effort)
    out.append("</robot>")
    return "\n".join(out) + "\n"


def joint_xml(name: str, link, xyz, rpy, axis, effort: float) -> list[str]:
    """The ``<joint>`` lines of ``link``'s joint: ``revolute`` with both position limits (a one-sided
    limit is written with the open side at :math:`\\pm 10^{300}`, read back as none), ``continuous``
    without; ``<limit>`` when it has any limit."""
    bounded = link.lower is not None or link.upper is not None
    out = [f"  <joint name={quoteattr(name)} type=\"{'revolute' if bounded else 'continuous'}\">",
           f"    <parent link={quoteattr(link.parent)}/>",
           f"    <child link={quoteattr(link.name)}/>",
           f'    <origin xyz="{_num(xyz[0])} {_num(xyz[1])} {_num(xyz[2])}" '
           f'rpy="{_num(rpy[0])} {_num(rpy[1])} {_num(rpy[2])}"/>',
           f'    <axis xyz="{_num(axis[0])} {_num(axis[1])} {_num(axis[2])}"/>']
    attrs = []
    if bounded:
        attrs += [f'lower="{_num(-1e300 if link.lower is None else link.lower)}"',
                  f'upper="{_num(1e300 if link.upper is None else link.upper)}"']
    if bounded or link.velocity is not None:
        attrs += [f'effort="{_num(effort)}"', f'velocity="{_num(link.velocity or 0.0)}"']
        out.append(f"    <limit {' '.join(attrs)}/>")
    out.append("  </joint>")
    return out
