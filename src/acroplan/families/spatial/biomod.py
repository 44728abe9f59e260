"""Spatial bodies from .bioMod files (the model format of biorbd and bioptim), read by biorbd.

The file is read by ``biorbd.Model`` (PyPI ``biorbd``, the optional extra ``biomod``), never by a
parser of our own: per segment, its name, parent, mass, centre of mass and inertia tensor (about
the centre of mass, in the segment's frame), its ``RT`` (``localJCS``: the segment frame's
placement in its parent's frame before its own degrees of freedom) and its degrees of freedom
(``translations``, ``rotations``). biorbd places a segment at

.. math::  G_{segment} = G_{parent}\\; RT\\; T(q_{translations})\\; R_{a_1}(q_1) R_{a_2}(q_2) \\cdots ,

its rotations about the successive moving axes :math:`a_1, a_2, \\dots` in the order the file
names them (``rotations zx``: first about z, then about the turned x).

The body
--------
* **The root** (the segment whose parent is biorbd's ``root``) must rotate freely: three rotations
  (any order of x, y, z) or a quaternion; its translations, if any, must be all three: that is the
  free flight, its centre of mass moving uniformly (taken at rest). The root's free rotation becomes
  the body's **attitude** :math:`q` (the root segment's frame, so Yeadon's angles of
  :func:`~acroplan.families.spatial.rotations.to_euler` are that frame's).
* **Every other rotation** is a revolute joint named by biorbd (``RightArm_RotY``): a segment with
  two or three rotations is a chain of revolute joints through massless links
  (``<segment>_rot<axis>``), as URDF does, with the segment's mass on the last. A joint's axis is
  :math:`R_{RT} e_{a_1}` in the parent's frame for the first and the moving axes after it; so the
  joint angles are biorbd's generalized coordinates.
* **A segment without degrees of freedom** is fixed to its parent: its mass is merged into the
  link it hangs from (masses add, inertias turned into that frame with the parallel-axis terms).
  One fixed to the world (no degrees of freedom, nor any above it: bioptim's ``Global`` frames) is
  left out when it is a frame (biorbd's 1e-8 kg, no inertia) and refused when it carries mass; the
  segment with degrees of freedom that hangs from the world is the root.
* **A translation anywhere but the root** (a prismatic joint) is refused, naming the segment, as is
  a quaternion joint below the root.
* **Checks** (each naming the segment): a finite mass >= 0; a finite, symmetric, positive
  semi-definite inertia whose principal moments satisfy :math:`I_1 + I_2 \\ge I_3` (as every rigid
  body's do), zero when the segment has no mass; the whole body's mass > 0. biorbd gives a segment
  that names no mass (a frame) 1e-8 kg and no inertia: a point mass, kept, so that the body's mass
  is biorbd's to the last digit.

``limits=True`` also reads the joints' ranges (``rangesQ``) and rate ranges (``rangesQdot``):
biorbd gives every joint :math:`[-\\pi, \\pi]` and :math:`[-10\\pi, 10\\pi]` when the file names
none, so they are left out by default. A symmetric rate range :math:`[-v, v]` becomes the rate
limit :math:`v`; an asymmetric one is refused (acroplan's rate limits are symmetric).
"""

from __future__ import annotations

import contextlib
import locale
import os
import pathlib

import numpy as np

from ...core.errors import InvalidInputError
from ..tree.links import combine_rigid
from ..tree.urdf import identifier
from .links import SpatialLink, SpatialLinkTable
from .links import RESERVED_NAMES

__all__ = ["read_biomod", "read_biomod_table", "require_biorbd", "keeping_locale"]

_INSTALL = "pip install acroplan[biomod]  (or: pip install biorbd)"
#: biorbd's mass of a segment that names none (a frame)
_FRAME_MASS = 1e-8


@contextlib.contextmanager
def keeping_locale():
    """Restore the process's locale on exit: creating a ``biorbd.Model`` (biorbd 1.12.4) sets it
    to ``"C"``, which turns Python's default text encoding to ASCII for the rest of the process
    (``open()`` and ``Path.read_text()`` without ``encoding=`` then fail on UTF-8 files)."""
    saved = locale.setlocale(locale.LC_ALL)
    try:
        yield
    finally:
        locale.setlocale(locale.LC_ALL, saved)


def require_biorbd():
    """``import biorbd``, or an ImportError that says how to install it."""
    try:
        import biorbd
    except ImportError:
        raise ImportError(f"reading .bioMod files needs the biorbd package: {_INSTALL}") from None
    return biorbd


def _s(v) -> str:
    return v.to_string() if hasattr(v, "to_string") else str(v)


def _checked(name: str, mass, com, inertia):
    field = f"bioMod segment {name!r}"
    m = float(mass)
    if not np.isfinite(m) or m < 0:
        raise InvalidInputError(field, f"has mass {m!r}", "give a finite mass >= 0 (kg)")
    c = np.asarray(com, dtype=float).reshape(3)
    if not np.isfinite(c).all():
        raise InvalidInputError(field, f"has a centre of mass that is not finite: {c.tolist()}", "check its com")
    J = np.asarray(inertia, dtype=float).reshape(3, 3)
    if not np.isfinite(J).all():
        raise InvalidInputError(field, "has an inertia that is not finite", "check its inertia matrix")
    scale = max(1.0, float(np.max(np.abs(J))))
    if np.max(np.abs(J - J.T)) > 1e-12 * scale:
        raise InvalidInputError(field, "has an inertia matrix that is not symmetric", "give Ixy = Iyx, ...")
    J = 0.5 * (J + J.T)
    ev = np.linalg.eigvalsh(J)
    if m == 0.0:
        if np.max(np.abs(J)) > 0.0:
            raise InvalidInputError(field, "has no mass but an inertia", "give mass > 0, or an inertia of zeros")
    elif ev[0] < -1e-12 * scale:
        raise InvalidInputError(field, f"has an inertia that is not positive semi-definite (principal moments "
                                f"{ev.tolist()})", "give its inertia about its centre of mass, in its frame")
    elif ev[0] + ev[1] < ev[2] * (1 - 1e-9) - 1e-12 * scale:
        raise InvalidInputError(field, f"has principal moments {ev.tolist()} that break I1 + I2 >= I3, which every "
                                "rigid body satisfies", "give its inertia about its centre of mass, in its frame")
    return m, c, J


def _unit(axis: str) -> np.ndarray:
    e = np.zeros(3)
    e["xyz".index(axis)] = 1.0
    return e


def read_biomod_table(path, *, limits: bool = False) -> SpatialLinkTable:
    """The link table of a .bioMod file (module docstring).

    Parameters
    ----------
    path : str or os.PathLike
    limits : bool
        Read the joints' ``rangesQ`` and ``rangesQdot`` (default: leave them out).

    Returns
    -------
    SpatialLinkTable
        The root first, then the links in the file's order (massless links before the segment
        they carry); the joints in biorbd's order of its generalized coordinates.

    Raises
    ------
    InvalidInputError
        The file missing or unreadable by biorbd, a root that does not rotate freely, a
        translation below the root (naming the segment), a bad mass or inertia (naming the
        segment).
    ImportError
        biorbd is not installed (``pip install acroplan[biomod]``).
    """
    p = pathlib.Path(os.fspath(path))
    model = _load(p)
    segs = [model.segment(i) for i in range(model.nbSegment())]
    names = [_s(s.name()) for s in segs]
    world, root = _world_and_root(p, segs, names)
    link_names: set = set()
    joint_names: set = set()
    # host[segment index] = (link index in `out`, R, p): the segment's frame in that link's frame
    host: dict[int, tuple[int, np.ndarray, np.ndarray]] = {}
    out: list[dict] = []
    pieces: list[list] = []
    for i, s in enumerate(segs):
        if i in world:
            continue
        name = names[i]
        m, c, J = _checked(name, s.characteristics().mass(), s.characteristics().CoM().to_array(),
                           s.characteristics().inertia().to_array())
        if i == root:
            _check_root(name, s)
            out.append({"name": identifier(name, link_names, "_link", RESERVED_NAMES), "parent": None})
            pieces.append([])
            host[i] = (0, np.eye(3), np.zeros(3))
        else:
            host[i] = _joint_links(s, name, names, host, out, pieces, link_names, joint_names, limits)
        hl, R, pos = host[i]
        if m > 0:
            pieces[hl].append((m, pos + R @ c, R @ J @ R.T))
    if sum(x[0] for ps in pieces for x in ps) <= 0:
        raise InvalidInputError("biomod", f"{p.name} has no mass", "give at least one segment mass > 0")
    links = _assembled(out, pieces)
    if len(links) < 2:
        raise InvalidInputError("biomod", f"{p.name} has no joint below its root", "give a segment with rotations")
    return SpatialLinkTable(links)


def _load(p: pathlib.Path):
    """biorbd's model of the file ``p`` (the process's locale kept)."""
    biorbd = require_biorbd()
    if not p.is_file():
        raise InvalidInputError("biomod", f"no such file: {str(p)!r}", "give the path of a .bioMod file")
    try:
        with keeping_locale():
            model = biorbd.Model(str(p))
    except Exception as e:  # biorbd raises RuntimeError on a bad file
        raise InvalidInputError("biomod", f"biorbd could not read {p.name}: {e}", "check the .bioMod file") from None
    if model.nbSegment() < 1:
        raise InvalidInputError("biomod", f"{p.name} has no segment", "give a .bioMod with segments")
    return model


def _world_and_root(p, segs, names) -> tuple[set[int], int]:
    """The segments fixed to the world (no degrees of freedom, no moving ancestor: bioptim's
    "Global" frames), which must be massless and are left out, and the one segment below them
    that is the body's root."""
    world: set[int] = set()
    for i, s in enumerate(segs):
        pname = _s(s.parent())
        on_world = pname not in names or names.index(pname) in world
        if on_world and int(s.nbDof()) == 0:
            m = float(s.characteristics().mass())
            J = np.asarray(s.characteristics().inertia().to_array(), dtype=float)
            if m > _FRAME_MASS or np.max(np.abs(J)) > 0.0:
                raise InvalidInputError(f"bioMod segment {names[i]!r}", f"is fixed to the world (no degrees of "
                                        f"freedom, nor any above it) but has mass {m:g} kg or an inertia",
                                        "a free-floating body moves as a whole: give the root segment "
                                        "'translations xyz' and 'rotations xyz', or make this a massless frame")
            world.add(i)
    roots = [i for i, s in enumerate(segs) if i not in world and (_s(s.parent()) not in names
                                                                  or names.index(_s(s.parent())) in world)]
    if len(roots) != 1:
        raise InvalidInputError("biomod", f"{p.name} has {len(roots)} segments that hang from the world "
                                f"({[names[i] for i in roots]})", "a free-floating body has one root segment")
    return world, roots[0]


def _check_root(name: str, s) -> None:
    field = f"bioMod segment {name!r}"
    nt, nr = int(s.nbDofTrans()), int(s.nbDofRot())
    if not (bool(s.isRotationAQuaternion()) or (nr == 3 and sorted(_s(s.seqR())) == ["x", "y", "z"])):
        raise InvalidInputError(field, f"is the root but rotates about {nr} axis/axes "
                                f"({_s(s.seqR()) or 'none'}): it is not free to turn",
                                "give the root 'rotations xyz' (any order) for a body in free flight")
    if nt not in (0, 3):
        raise InvalidInputError(field, f"is the root but translates along {nt} axis/axes ({_s(s.seqT())})",
                                "give the root 'translations xyz' (free flight) or none")


def _joint_links(s, name, names, host, out, pieces, link_names, joint_names, limits):
    """The links of a segment below the root, one per rotation (massless links before the segment's
    own), appended to ``out``; returns the segment's host ``(link index, R, p)``."""
    field = f"bioMod segment {name!r}"
    pname = _s(s.parent())
    if pname not in names or names.index(pname) not in host:
        raise InvalidInputError(field, f"has parent {pname!r}, which is not defined before it",
                                "define every segment after its parent")
    if int(s.nbDofTrans()):
        raise InvalidInputError(field, f"translates ({_s(s.seqT())}): a spatial body has only revolute "
                                "joints below its root", "remove the segment's translations (or fix them in its RT)")
    if bool(s.isRotationAQuaternion()):
        raise InvalidInputError(field, "has a quaternion (ball) joint below the root",
                                "give its rotations as Cardan axes, for example 'rotations xyz'")
    RT = np.asarray(s.localJCS().to_array(), dtype=float)
    hl, Rp, pp = host[names.index(pname)]
    F = Rp @ RT[:3, :3]
    at = pp + Rp @ RT[:3, 3]
    cur = hl
    seq = _s(s.seqR())
    for k, axis in enumerate(seq):
        lname = name if k == len(seq) - 1 else f"{name}_rot{axis}"
        jn = f"{name}_{_s(s.nameDof(k))}"  # biorbd's name of the coordinate: RightArm_RotY
        spec = {"name": identifier(lname, link_names, "_link", RESERVED_NAMES), "parent": cur, "joint": at,
                "axis": F @ _unit(axis), "rotation": F,
                "joint_name": identifier(jn, joint_names, "_joint", RESERVED_NAMES)}
        if limits:
            spec.update(_ranges(field, s, k, jn))
        out.append(spec)
        pieces.append([])
        cur, F, at = len(out) - 1, np.eye(3), np.zeros(3)
    return (cur, F, at) if not seq else (cur, np.eye(3), np.zeros(3))


def _ranges(field: str, s, k: int, jn: str) -> dict:
    rq, rqd = s.QRanges()[k], s.QdotRanges()[k]
    lo, hi = float(rq.min()), float(rq.max())
    vlo, vhi = float(rqd.min()), float(rqd.max())
    if abs(vlo + vhi) > 1e-12 * max(1.0, abs(vhi)):
        raise InvalidInputError(field, f"has an asymmetric rate range [{vlo:g}, {vhi:g}] for {jn}",
                                "give a symmetric rangesQdot [-v, v] (or read with limits=False)")
    return dict(lower=lo, upper=hi, velocity=vhi if vhi > 0 else None)


def _assembled(out, pieces) -> list[SpatialLink]:
    """The links: each the mass, centre of mass and inertia of the segments it carries."""
    links = []
    by_index = {}
    for k, spec in enumerate(out):
        ps = pieces[k]
        m, c, J = combine_rigid(ps)
        by_index[k] = spec["name"]
        if spec["parent"] is None:
            links.append(SpatialLink(spec["name"], None, m, J, com=tuple(c)))
            continue
        R0 = spec["rotation"]
        rotation = None if np.max(np.abs(R0 - np.eye(3))) < 1e-15 else R0
        links.append(SpatialLink(spec["name"], by_index[spec["parent"]], m, J, com=tuple(c), joint=tuple(spec["joint"]),
                                 axis=tuple(spec["axis"]), rotation=rotation, joint_name=spec["joint_name"],
                                 lower=spec.get("lower"), upper=spec.get("upper"), velocity=spec.get("velocity")))
    return links


def read_biomod(path, angular_momentum=(0.0, 0.0, 0.0), *, limits: bool = False):
    """A :class:`~acroplan.families.spatial.model.SpatialBody` from a .bioMod file
    (:func:`read_biomod_table`).

    Parameters
    ----------
    path : str or os.PathLike
    angular_momentum : (float, float, float)
        :math:`L` about the centre of mass, in the inertial frame (kg m²/s).
    limits : bool
        Read the file's joint ranges and rate ranges.

    Returns
    -------
    SpatialBody

    Examples
    --------
    bioptim's free-floating trunk with two arms (``trunk_and_2arm.bioMod``) with
    :math:`L = (36.3075, 0, 0)`: ``read_biomod("trunk_and_2arm.bioMod", (36.3075, 0.0, 0.0))``, joints
    ``RightArm_RotY`` and ``LeftArm_RotY``.
    """
    from .model import SpatialBody

    try:
        L = tuple(float(v) for v in angular_momentum)
    except (TypeError, ValueError):
        L = ()
    if len(L) != 3 or not np.isfinite(L).all():
        raise InvalidInputError("angular_momentum", f"must be three finite numbers (Lx, Ly, Lz), got "
                                f"{angular_momentum!r}", "give for example (36.3075, 0.0, 0.0)")
    return SpatialBody(read_biomod_table(path, limits=limits), L=L)
