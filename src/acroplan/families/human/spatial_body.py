"""The 3-D human: Yeadon's 11 segments as a :class:`~acroplan.families.spatial.model.SpatialBody`.

Yeadon's simulation model (M. R. Yeadon, J. Atha and F. D. Hales 1990, *The simulation of aerial
movement - IV. A computer simulation model*, J. Biomech. 23(1):85-89) has 11 rigid segments; the
``yeadon`` package (Dembia, Moore and Hubbard 2014) computes their masses, centres of mass and
inertia tensors from Yeadon's (1990) 95 measurements, and poses them by 21 angles. Here the
segments become the links of a spatial body whose joints are the angles a user names.

The segments and the frames
---------------------------
============  ==========  ====================  =====================================
yeadon        parent      link                  joints (yeadon's angle, sign)
============  ==========  ====================  =====================================
P pelvis      (root)      ``pelvis``            the attitude: somersault, tilt, twist
T thorax      P           ``thorax``            ``spine_flexion`` (PTsagittalFlexion, +),
                                                ``spine_bending`` (PTbending, +)
C chest-head  T           ``chest_head``        ``chest_flexion`` (TCsagittalSpinalFlexion, +),
                                                ``spine_torsion`` (TCspinalTorsion, +)
A1, B1        C           ``left_upper_arm``,   ``*_shoulder_flexion`` (CA1extension -, CB1extension -),
                          ``right_upper_arm``   ``*_shoulder_abduction`` (CA1adduction -, CB1abduction +),
                                                ``*_shoulder_rotation`` (CA1rotation -, CB1rotation +)
A2, B2        A1, B1      ``*_forearm_hand``    ``*_elbow_flexion`` (A1A2extension -, B1B2extension -)
J1, K1        P           ``*_thigh``           ``*_hip_flexion`` (PJ1extension -, PK1extension -),
                                                ``*_hip_abduction`` (PJ1adduction -, PK1abduction +)
J2, K2        J1, K1      ``*_shank_foot``      ``*_knee_flexion`` (J1J2flexion +, K1K2flexion +)
============  ==========  ====================  =====================================

Every link's frame is yeadon's frame of its segment: in Yeadon's reference posture (every angle 0:
standing straight, arms at the sides) all are parallel to yeadon's global frame, **x to the body's
left, y backwards (posterior), z up (feet to head)**, the pelvis's origin at the centre of the
bottom of the pelvis (the level of the hip joint centres), each other segment's origin at its
proximal joint centre. The root is the pelvis, so the body's attitude :math:`q` is the pelvis's.

Joint angles
------------
Anatomical, 0 in the reference posture: **an angle here is the sign times yeadon's angle** (the
table above), so that flexion > 0 moves a limb forwards (or bends the trunk forwards), abduction
> 0 moves a limb away from the midline on both sides, shoulder rotation > 0 is medial (internal)
rotation on both sides, elbow and knee flexion > 0 bend them, ``spine_bending`` > 0 bends the
thorax to the left and ``spine_torsion`` > 0 turns the chest to the left. A joint's angles turn
the segment as yeadon does, in Cardan order on the moving axes: the child's frame is
:math:`R_x(a)\\,R_y(b)\\,R_z(c)` in its parent's frame (yeadon's ``euler_123``) with :math:`(a, b, c)`
yeadon's three angles of that joint, so a shoulder's abduction is about the arm's once-turned
antero-posterior axis (after its flexion). A joint with several free angles is a chain of revolute
joints through massless links (``*_link``), as URDF does.

Attitude: Yeadon's angles
-------------------------
yeadon poses the pelvis by ``somersault``, ``tilt``, ``twist``: :math:`R = R_x(\\phi) R_y(\\theta)
R_z(\\psi)` in its frame, the Cardan convention of :mod:`~acroplan.families.spatial.rotations`
(``to_euler(q)``, ``from_euler``). With yeadon's axes (x to the **left**) a positive somersault
turns the head forwards (a forward somersault), as in the planar human (``docs/human.md``); the
tilt turns about the once-turned antero-posterior axis y (backwards), the twist about the
long axis z: a twist > 0 turns the body's front (:math:`-y`) towards its left (:math:`+x`).

Joints and postures
-------------------
``joints`` names the free angles: a preset (:data:`PRESETS`) or any list of the 18 names of
:data:`JOINTS`. Presets: ``"arms"``: flexion and abduction of each shoulder (4 joints, 5 links);
``"arms+hips"``: and flexion and abduction of each hip (8 joints, 9 links); ``"full"``: and the
elbows, the knees and the spine joint between pelvis and thorax (flexion and lateral bending; 14
joints, 15 links). Every other angle is held at the ``posture`` (:data:`POSTURES`, from
``data/limits_3d.toml``): ``"straight"`` (every angle 0), ``"pike"`` (hips flexed to a diver's
closed pike), ``"tuck"`` (hips and knees flexed to a diver's tuck), or a mapping of angles by
joint name over the straight posture. Held segments are merged into the link they hang from
(masses add, inertias with the parallel-axis terms), so an ``"arms"`` body has 5 links, not 11.

Limits
------
``limits=True`` writes the data's ranges and rates (:func:`spatial_joint_limits`, each with its
source or marked an estimate, ``data/limits_3d.toml``) into the link table, so that
:func:`acroplan.plan` honours them by default.
"""

from __future__ import annotations

import contextlib
import dataclasses
import functools
import io
import math
import tomllib
from importlib import resources
from typing import Mapping

import numpy as np

from ...core.errors import InvalidInputError, finite_number
from ..spatial import rotations as rot
from ..spatial.links import SpatialLink, SpatialLinkTable
from ..spatial.model import SpatialBody
from ..tree.links import combine_rigid
from .limits import human_data

__all__ = ["Dof", "JOINTS", "SEGMENTS", "PRESETS", "POSTURES", "HumanSegments", "spatial_limits_data",
           "spatial_joint_limits", "joint_names", "posture_angles", "yeadon_segments", "de_leva_segments",
           "human_link_table", "spatial_from_yeadon", "spatial_from_height_mass", "yeadon_configuration", "yeadon_whole_body",
           "body_angles"]


@dataclasses.dataclass(frozen=True)
class Dof:
    """One joint angle of the 3-D human (module docstring's table).

    Attributes
    ----------
    name : str
        acroplan's name (the state; ``u_<name>`` its rate).
    segment : str
        The yeadon segment it turns (``"A1"``, ...).
    axis : int
        0, 1, 2: yeadon's Cardan axis x, y, z of the segment's joint.
    sign : float
        +1 or -1: the angle here is ``sign`` times yeadon's.
    yeadon : str
        yeadon's name of the angle (``Human.CFGnames``).
    kind : str
        The entry of ``data/limits_3d.toml`` (left and right share it).
    """

    name: str
    segment: str
    axis: int
    sign: float
    yeadon: str
    kind: str


#: The 18 joint angles (yeadon's order of ``Human.CFGnames``, without the attitude).
JOINTS: dict[str, Dof] = {d.name: d for d in (
    Dof("spine_flexion", "T", 0, 1.0, "PTsagittalFlexion", "spine_flexion"),
    Dof("spine_bending", "T", 1, 1.0, "PTbending", "spine_bending"),
    Dof("spine_torsion", "C", 2, 1.0, "TCspinalTorsion", "spine_torsion"),
    Dof("chest_flexion", "C", 0, 1.0, "TCsagittalSpinalFlexion", "chest_flexion"),
    Dof("left_shoulder_flexion", "A1", 0, -1.0, "CA1extension", "shoulder_flexion"),
    Dof("left_shoulder_abduction", "A1", 1, -1.0, "CA1adduction", "shoulder_abduction"),
    Dof("left_shoulder_rotation", "A1", 2, -1.0, "CA1rotation", "shoulder_rotation"),
    Dof("right_shoulder_flexion", "B1", 0, -1.0, "CB1extension", "shoulder_flexion"),
    Dof("right_shoulder_abduction", "B1", 1, 1.0, "CB1abduction", "shoulder_abduction"),
    Dof("right_shoulder_rotation", "B1", 2, 1.0, "CB1rotation", "shoulder_rotation"),
    Dof("left_elbow_flexion", "A2", 0, -1.0, "A1A2extension", "elbow_flexion"),
    Dof("right_elbow_flexion", "B2", 0, -1.0, "B1B2extension", "elbow_flexion"),
    Dof("left_hip_flexion", "J1", 0, -1.0, "PJ1extension", "hip_flexion"),
    Dof("left_hip_abduction", "J1", 1, -1.0, "PJ1adduction", "hip_abduction"),
    Dof("right_hip_flexion", "K1", 0, -1.0, "PK1extension", "hip_flexion"),
    Dof("right_hip_abduction", "K1", 1, 1.0, "PK1abduction", "hip_abduction"),
    Dof("left_knee_flexion", "J2", 0, 1.0, "J1J2flexion", "knee_flexion"),
    Dof("right_knee_flexion", "K2", 0, 1.0, "K1K2flexion", "knee_flexion"),
)}

#: yeadon's 11 segments in tree order: (segment, parent, link name).
SEGMENTS: tuple[tuple[str, str | None, str], ...] = (
    ("P", None, "pelvis"), ("T", "P", "thorax"), ("C", "T", "chest_head"),
    ("A1", "C", "left_upper_arm"), ("A2", "A1", "left_forearm_hand"),
    ("B1", "C", "right_upper_arm"), ("B2", "B1", "right_forearm_hand"),
    ("J1", "P", "left_thigh"), ("J2", "J1", "left_shank_foot"),
    ("K1", "P", "right_thigh"), ("K2", "K1", "right_shank_foot"),
)


def _tree_order(names) -> tuple[str, ...]:
    """``names`` in the link table's order: by segment (:data:`SEGMENTS`), then Cardan axis."""
    seg = [s for s, _, _ in SEGMENTS]
    return tuple(sorted(names, key=lambda n: (seg.index(JOINTS[n].segment), JOINTS[n].axis)))


_ARMS = ("left_shoulder_flexion", "left_shoulder_abduction", "right_shoulder_flexion", "right_shoulder_abduction")
_HIPS = ("left_hip_flexion", "left_hip_abduction", "right_hip_flexion", "right_hip_abduction")
#: The named joint sets, in the link table's (the state's) order.
PRESETS: dict[str, tuple[str, ...]] = {
    "arms": _tree_order(_ARMS),
    "arms+hips": _tree_order(_ARMS + _HIPS),
    "full": _tree_order(("spine_flexion", "spine_bending") + _ARMS + ("left_elbow_flexion", "right_elbow_flexion")
                        + _HIPS + ("left_knee_flexion", "right_knee_flexion")),
}


# ---------------------------------------------------------------------- data
@functools.lru_cache(maxsize=1)
def _raw() -> dict:
    text = resources.files(__package__).joinpath("data", "limits_3d.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def _resolve(entry: Mapping) -> dict:
    """An entry of ``limits_3d.toml`` with ``same_as`` replaced by limits.toml's value (and its
    source, estimate and note)."""
    if "same_as" not in entry:
        return dict(entry)
    ref = human_data()
    for key in entry["same_as"].split("."):
        ref = ref[key]
    out = {k: ref[k] for k in ("value", "source", "estimate", "note") if k in ref}
    if entry.get("negate", False):
        out["value"] = -out["value"]
    out["same_as"] = entry["same_as"]
    return out


@functools.lru_cache(maxsize=1)
def spatial_limits_data() -> dict:
    """``data/limits_3d.toml`` with every ``same_as`` resolved: ``data["hip_flexion"]["upper"]`` is
    ``{"value": 150.0, "source": "", "estimate": True, "note": ..., "same_as": "hip.flexion_pike"}``;
    also ``data["postures"]``, ``data["geometry"]`` and ``data["sources"]`` (those of
    ``limits.toml`` merged in)."""
    raw = _raw()
    out: dict = {"sources": {**human_data()["sources"], **raw["sources"]}}
    for kind, entries in raw.items():
        if kind in ("sources", "postures", "geometry"):
            continue
        out[kind] = {b: _resolve(e) for b, e in entries.items()}
    out["postures"] = {p: {k: _resolve(e) for k, e in (v or {}).items()}
                       for p, v in raw["postures"].items()}
    out["geometry"] = {k: dict(v) for k, v in raw["geometry"].items()}
    return out


def spatial_joint_limits() -> dict[str, tuple[float, float, float]]:
    """Each joint's ``(lower, upper, rate)`` in radians and rad/s, from ``data/limits_3d.toml``.

    Returns
    -------
    dict
        By joint name (all 18 of :data:`JOINTS`).
    """
    d = spatial_limits_data()
    out = {}
    for name, dof in JOINTS.items():
        e = d[dof.kind]
        out[name] = (math.radians(e["lower"]["value"]), math.radians(e["upper"]["value"]), float(e["rate"]["value"]))
    return out


def _posture_table() -> dict[str, dict[str, float]]:
    d = spatial_limits_data()["postures"]
    return {p: {k: math.radians(e["value"]) for k, e in v.items()} for p, v in d.items()}


#: The held postures by name: the angle of each joint kind that is not 0 (rad), both sides.
POSTURES: dict[str, dict[str, float]] = _posture_table()


def joint_names(joints) -> tuple[str, ...]:
    """The free joints of a preset name or a list of names, in the link table's order (the state's:
    by segment of :data:`SEGMENTS`, then Cardan axis x, y, z).

    Raises
    ------
    InvalidInputError
        An unknown preset or joint name, or a name given twice.
    """
    if isinstance(joints, str):
        if joints not in PRESETS:
            raise InvalidInputError("joints", f"{joints!r} is not a preset", f"presets: {sorted(PRESETS)}, or a list "
                                    f"of joint names from {list(JOINTS)}")
        return PRESETS[joints]
    try:
        names = list(joints)
    except TypeError:
        raise InvalidInputError("joints", f"must be a preset name or a list of joint names, got {joints!r}",
                                f"presets: {sorted(PRESETS)}") from None
    for n in names:
        if n not in JOINTS:
            raise InvalidInputError("joints", f"{n!r} is not a joint of the 3-D human", f"joints: {list(JOINTS)}")
    if len(set(names)) != len(names):
        raise InvalidInputError("joints", "names a joint twice", "give each joint once")
    return _tree_order(names)


def posture_angles(posture="straight") -> dict[str, float]:
    """Every joint's angle (rad) in a held posture.

    Parameters
    ----------
    posture : str or mapping
        A name of :data:`POSTURES`, or a mapping of joint names (of :data:`JOINTS`) to angles in
        radians over the straight posture.

    Returns
    -------
    dict
        All 18 joints.
    """
    out = {name: 0.0 for name in JOINTS}
    if isinstance(posture, str):
        if posture not in POSTURES:
            raise InvalidInputError("posture", f"{posture!r} is not a posture", f"postures: {sorted(POSTURES)}, or a "
                                    "mapping of joint angles (rad)")
        kinds = POSTURES[posture]
        for name, dof in JOINTS.items():
            out[name] = kinds.get(dof.kind, 0.0)
        return out
    if not isinstance(posture, Mapping):
        raise InvalidInputError("posture", f"must be a posture name or a mapping of joint angles, got {posture!r}",
                                f"postures: {sorted(POSTURES)}")
    for k, v in posture.items():
        if k not in JOINTS:
            raise InvalidInputError(f"posture.{k}", "is not a joint of the 3-D human", f"joints: {list(JOINTS)}")
        out[k] = finite_number(f"posture.{k}", v)
    return out


# ---------------------------------------------------------------------- the segments
@dataclasses.dataclass(frozen=True)
class HumanSegments:
    """The 11 segments' inertia and geometry, each in its own frame (module docstring).

    Attributes
    ----------
    mass : dict of str to float
        kg, by yeadon segment name.
    com : dict of str to numpy.ndarray, shape (3,)
        Centre of mass in the segment's frame, from its origin (m).
    inertia : dict of str to numpy.ndarray, shape (3, 3)
        About the segment's centre of mass, in its frame (kg m²).
    joint : dict of str to numpy.ndarray, shape (3,)
        Each non-root segment's origin (its proximal joint centre) in its parent's frame (m).
    source : str
    shapes : dict of str to tuple
        The solids each segment is drawn with, in its frame (:attr:`SpatialLink.shapes
        <acroplan.families.spatial.links.SpatialLink.shapes>`): yeadon's stadium solids and
        semi-ellipsoids; empty for de Leva's segments (drawn as boxes).
    """

    mass: dict
    com: dict
    inertia: dict
    joint: dict
    source: str = ""
    shapes: dict = dataclasses.field(default_factory=dict)

    @property
    def total_mass(self) -> float:
        return float(sum(self.mass.values()))


def _check_segments(segs: HumanSegments) -> None:
    for s, _, _ in SEGMENTS:
        m = segs.mass[s]
        if not (math.isfinite(m) and m > 0):
            raise InvalidInputError(f"segment {s}", f"has mass {m!r}", "every segment needs a finite mass > 0")
        J = np.asarray(segs.inertia[s], dtype=float)
        if J.shape != (3, 3) or not np.isfinite(J).all() or np.linalg.eigvalsh(0.5 * (J + J.T))[0] <= 0:
            raise InvalidInputError(f"segment {s}", "has an inertia that is not positive definite",
                                    "check the measurements")


def _yeadon():
    from .yeadon_body import _yeadon as y

    return y()


def yeadon_segments(human=None, *, density_set: str = "Dempster") -> HumanSegments:
    """The 11 segments of a yeadon human.

    Parameters
    ----------
    human : yeadon.Human, str or os.PathLike, optional
        A ``yeadon.Human`` (its configuration is restored afterwards), a measurement file, or a
        bundled sample's name (default ``"male1"``).
    density_set : str
        yeadon's densities when ``human`` is a file.

    Returns
    -------
    HumanSegments
        Masses, centres of mass and inertias are yeadon's (``Segment.mass``,
        ``rel_center_of_mass``, ``rel_inertia``); the joints are read in yeadon's reference posture
        (every angle 0), where every segment frame is parallel to the global one:
        ``joint[child] = child.pos - parent.pos``.
    """
    from .yeadon_body import human_of

    human, label = human_of(human, density_set, ("segments", "set_CFG_dict", "CFGnames"))
    saved = dict(human.CFG)
    try:
        with contextlib.redirect_stdout(io.StringIO()):
            human.set_CFG_dict({k: 0.0 for k in human.CFGnames})
        seg = {s: getattr(human, s) for s, _, _ in SEGMENTS}
        for s in seg.values():  # pragma: no cover - yeadon's reference posture has every frame parallel
            if np.max(np.abs(np.asarray(s.rot_mat) - np.eye(3))) > 1e-12:
                raise InvalidInputError("human", f"yeadon's segment {s.label} is turned in the reference posture",
                                        "report this: the yeadon version is not supported")
        mass = {k: float(s.mass) for k, s in seg.items()}
        com = {k: np.asarray(s.rel_center_of_mass, dtype=float).reshape(3) for k, s in seg.items()}
        inertia = {k: np.asarray(s.rel_inertia, dtype=float).reshape(3, 3) for k, s in seg.items()}
        joint = {k: (np.asarray(seg[k].pos, dtype=float) - np.asarray(seg[p].pos, dtype=float)).reshape(3)
                 for k, p, _ in SEGMENTS if p is not None}
        shapes = {k: _yeadon_shapes(s) for k, s in seg.items()}
        root = np.asarray(seg["P"].pos, dtype=float).reshape(3)
        if np.max(np.abs(root)) > 1e-12:  # pragma: no cover
            raise InvalidInputError("human", f"yeadon's pelvis origin is at {root}, not at the global origin",
                                    "report this: the yeadon version is not supported")
    finally:
        with contextlib.redirect_stdout(io.StringIO()):
            human.set_CFG_dict(saved)
    out = HumanSegments(mass, com, inertia, joint, f"yeadon ({label})", shapes)
    _check_segments(out)
    return out


_QUARTER = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # about z: a stadium along y


def _yeadon_shapes(segment) -> tuple:
    """A yeadon segment's solids in its frame (in the reference posture, where the segment's and its
    solids' frames are parallel to the global one): each solid's base stadium (``stads[0]``) at its
    ``pos``, the other ``height`` above along the solid's z, as yeadon draws them; a solid whose
    stadia lie antero-posteriorly (``alignment "AP"``, the feet) turned a quarter about z."""
    out = []
    base = np.asarray(segment.pos, dtype=float).reshape(3)
    for solid in segment.solids:
        origin = tuple(float(v) for v in np.asarray(solid.pos, dtype=float).reshape(3) - base)
        if hasattr(solid, "stads"):
            s0, s1 = solid.stads
            R = _QUARTER if getattr(solid, "alignment", "ML") == "AP" else np.eye(3)
            out.append(("stadium_solid", (float(s0.radius), float(s0.thickness), float(s1.radius),
                                          float(s1.thickness), float(solid.height)), origin,
                        tuple(map(tuple, R.tolist()))))
        else:
            out.append(("semiellipsoid", (float(solid.radius), 0.0, float(solid.height)), origin,
                        tuple(map(tuple, np.eye(3).tolist()))))
    return tuple(out)


def de_leva_segments(height: float, mass: float, *, sex: str = "male") -> HumanSegments:
    """The 11 segments from stature and mass by de Leva's (1996) Table 4 (``data/de_leva_1996.toml``).

    Yeadon's segments from de Leva's: pelvis = lower trunk (omphalion to mid-hip), thorax = middle
    trunk (xiphion to omphalion), chest-head = upper trunk (suprasternale to xiphion) and the head
    (vertex to C7, C7 at the C7-to-mid-hip length above the hips), upper arm, forearm-hand =
    forearm and hand in line, thigh, shank-foot = shank and a pointed foot in line (as
    :func:`~acroplan.families.human.deleva.from_height_mass`). Lengths scale with stature, masses
    are the table's fractions divided by their sum (so they add up to ``mass``), the principal
    moments are :math:`m (r \\ell)^2` with the transverse radius about x (medio-lateral), the
    sagittal one about y (antero-posterior) and the longitudinal one about z. Every segment lies
    on its axis; the shoulder joint centres are at the mid-shoulder's height (the MIDS-to-mid-hip
    trunk's length above the hips), the shoulder and hip joint centres ``geometry.shoulder_width``
    and ``geometry.hip_width`` times the vertex-to-mid-hip distance apart (``data/limits_3d.toml``:
    estimates, from yeadon's male1).

    Returns
    -------
    HumanSegments
    """
    from .deleva import _sex, de_leva_table, stature_and_mass

    H, M = stature_and_mass(height, mass)
    sex = _sex(sex)
    table = de_leva_table()
    scale = H / (table["reference"]["stature_mm"][sex] / 1000.0)
    rows = {k: table["segments"][k][sex] for k in ("lower_trunk", "middle_trunk", "upper_trunk", "head_to_c7",
                                                     "trunk_from_c7", "trunk_from_shoulders", "upper_arm", "forearm",
                                                     "hand", "thigh", "shank", "foot")}
    length = {k: r["length_mm"] / 1000.0 * scale for k, r in rows.items()}
    total = sum(rows[k]["mass"] for k in ("lower_trunk", "middle_trunk", "upper_trunk", "head_to_c7")) + 2.0 * sum(
        rows[k]["mass"] for k in ("upper_arm", "forearm", "hand", "thigh", "shank", "foot"))

    def piece(k, start, up):
        """(mass, com, inertia) of de Leva's segment k on the z axis from ``start``, towards +z
        (``up``) or -z, its centre of mass at the table's fraction from its first endpoint, which
        is the far one for the trunk's pieces and the head (given from above) and the near one for
        the limbs."""
        r = rows[k]
        m = M * r["mass"] / total
        lk = length[k]
        f = r["com"] / 100.0
        z = start + (1.0 - f) * lk if up else start - f * lk
        J = m * np.diag([(r["r_trans"] / 100.0 * lk) ** 2, (r["r_sag"] / 100.0 * lk) ** 2,
                         (r["r_long"] / 100.0 * lk) ** 2])
        return m, np.array([0.0, 0.0, z]), J

    def combined(pieces):
        m = sum(p[0] for p in pieces)
        c = sum(p[0] * p[1] for p in pieces) / m
        J = sum(p[2] + p[0] * (float((p[1] - c) @ (p[1] - c)) * np.eye(3) - np.outer(p[1] - c, p[1] - c))
                for p in pieces)
        return m, c, J

    lL, lM = length["lower_trunk"], length["middle_trunk"]
    parts = {
        "P": piece("lower_trunk", 0.0, True),
        "T": piece("middle_trunk", 0.0, True),
        "C": combined([piece("upper_trunk", 0.0, True), piece("head_to_c7", length["trunk_from_c7"] - lL - lM, True)]),
    }
    arm = piece("upper_arm", 0.0, False)
    hand_arm = combined([piece("forearm", 0.0, False), piece("hand", -length["forearm"], False)])
    thigh = piece("thigh", 0.0, False)
    # the foot pointed in line with the shank, its heel at the lateral malleolus (deleva.py): de Leva's foot
    # runs from the heel (first endpoint) to the toe tip, so it starts at the shank's end
    shank_foot = combined([piece("shank", 0.0, False), piece("foot", -length["shank"], False)])
    geo = spatial_limits_data()["geometry"]
    vertex = length["trunk_from_c7"] + length["head_to_c7"]
    ws = geo["shoulder_width"]["value"] * vertex / 2.0
    wh = geo["hip_width"]["value"] * vertex / 2.0
    zs = length["trunk_from_shoulders"] - lL - lM
    for s in ("A1", "B1"):
        parts[s] = arm
    for s in ("A2", "B2"):
        parts[s] = hand_arm
    for s in ("J1", "K1"):
        parts[s] = thigh
    for s in ("J2", "K2"):
        parts[s] = shank_foot
    joint = {"T": np.array([0.0, 0.0, lL]), "C": np.array([0.0, 0.0, lM]),
             "A1": np.array([ws, 0.0, zs]), "B1": np.array([-ws, 0.0, zs]),
             "A2": np.array([0.0, 0.0, -length["upper_arm"]]), "B2": np.array([0.0, 0.0, -length["upper_arm"]]),
             "J1": np.array([wh, 0.0, 0.0]), "K1": np.array([-wh, 0.0, 0.0]),
             "J2": np.array([0.0, 0.0, -length["thigh"]]), "K2": np.array([0.0, 0.0, -length["thigh"]])}
    out = HumanSegments({k: float(v[0]) for k, v in parts.items()}, {k: v[1] for k, v in parts.items()},
                        {k: v[2] for k, v in parts.items()}, joint, f"de Leva (1996), {sex}, {H:g} m, {M:g} kg")
    _check_segments(out)
    return out


# ---------------------------------------------------------------------- the link table
def _elementary(axis: int, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    if axis == 0:
        return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    if axis == 1:
        return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def human_link_table(segments: HumanSegments, joints="arms", posture="straight", *, limits: bool = True
                     ) -> SpatialLinkTable:
    """The link table of the 3-D human (module docstring).

    Each segment's joint is yeadon's three Cardan angles :math:`R_x(a) R_y(b) R_z(c)`; a free angle
    becomes a revolute joint, a held one a constant turn. With :math:`F` the constant turn
    accumulated before a free angle (in the frame of the link it hangs from) and :math:`G` the one
    after the segment's last free angle, a free angle :math:`s` about yeadon's axis :math:`e`
    (sign :math:`\\sigma`) is the link with ``axis`` :math:`F \\sigma e` and ``rotation`` :math:`F`
    (:math:`F G` for the segment's last one), since :math:`F R_e(\\sigma s) G = \\mathrm{Rot}(F\\sigma
    e, s)\\, F G`. A segment with no free angle is merged into the link it hangs from at its held
    pose: :math:`c \\mapsto j + R c`, :math:`J \\mapsto R J R^\\top`, and the parallel-axis sum.

    Parameters
    ----------
    segments : HumanSegments
    joints : str or sequence of str
        A preset of :data:`PRESETS` or joint names of :data:`JOINTS`.
    posture : str or mapping
        The held angles (:func:`posture_angles`).
    limits : bool
        Write :func:`spatial_joint_limits` into the table.

    Returns
    -------
    SpatialLinkTable
        The pelvis first, then the links in :data:`SEGMENTS`' order; the joints (states) in that
        order.
    """
    free = set(joint_names(joints))
    held = posture_angles(posture)
    lim = spatial_joint_limits() if limits else {}
    by_axis = {(d.segment, d.axis): d for d in JOINTS.values()}
    pieces: dict[str, list] = {"pelvis": []}   # per link: (mass, com, inertia) in the link's frame
    drawn: dict[str, list] = {}   # per link: the solids it is drawn with, in its frame
    order = ["pelvis"]
    specs: dict[str, dict] = {"pelvis": {"parent": None}}
    host: dict[str, tuple[str, np.ndarray, np.ndarray]] = {"P": ("pelvis", np.eye(3), np.zeros(3))}
    for seg, parent, link_name in SEGMENTS:
        if parent is not None:
            hl, Rp, pp = host[parent]
            F = Rp.copy()
            at = pp + Rp @ segments.joint[seg]
            cur, last = hl, None
            for axis in range(3):
                dof = by_axis.get((seg, axis))
                if dof is None:
                    continue
                if dof.name not in free:
                    F = F @ _elementary(axis, dof.sign * held[dof.name])
                    continue
                if last is not None:  # the previous free angle's link is massless
                    specs[last]["name"] = f"{specs[last]['joint_name']}_link"
                e = np.zeros(3)
                e[axis] = dof.sign
                key = f"_{seg}_{axis}"
                specs[key] = {"parent": cur, "joint": at, "axis": F @ e, "pre": F, "joint_name": dof.name}
                if dof.name in lim:
                    lo, hi, rate = lim[dof.name]
                    specs[key].update(lower=lo, upper=hi, velocity=rate)
                order.append(key)
                pieces[key] = []
                cur, last, F, at = key, key, np.eye(3), np.zeros(3)
            if last is None:
                host[seg] = (hl, F, at)
            else:
                specs[last]["name"] = link_name
                specs[last]["post"] = F
                host[seg] = (last, np.eye(3), np.zeros(3))
        hl, R, p = host[seg]
        pieces[hl].append((segments.mass[seg], p + R @ segments.com[seg], R @ segments.inertia[seg] @ R.T))
        drawn.setdefault(hl, []).extend((kind, params, tuple((p + R @ np.asarray(o)).tolist()),
                                         tuple(map(tuple, (R @ np.asarray(Q)).tolist())))
                                        for kind, params, o, Q in segments.shapes.get(seg, ()))
    names = {k: (specs[k].get("name", k) if k != "pelvis" else "pelvis") for k in order}
    links = []
    for k in order:
        ps = pieces[k]
        m, c, J = combine_rigid(ps)
        sp = specs[k]
        shapes = tuple(drawn[k]) if drawn.get(k) else None
        if sp["parent"] is None:
            links.append(SpatialLink(names[k], None, m, J, com=tuple(c), shapes=shapes))
            continue
        R0 = sp["pre"] @ sp.get("post", np.eye(3))
        rotation = None if np.max(np.abs(R0 - np.eye(3))) < 1e-15 else R0
        links.append(SpatialLink(names[k], names[sp["parent"]], m, J, com=tuple(c), joint=tuple(sp["joint"]),
                                 axis=tuple(sp["axis"]), rotation=rotation, joint_name=sp["joint_name"],
                                 lower=sp.get("lower"), upper=sp.get("upper"), velocity=sp.get("velocity"),
                                 shapes=shapes))
    return SpatialLinkTable(links)


def _momentum(angular_momentum) -> tuple[float, float, float]:
    try:
        L = tuple(finite_number(f"angular_momentum[{i}]", v) for i, v in enumerate(angular_momentum))
    except TypeError:
        raise InvalidInputError("angular_momentum", f"must be three numbers (Lx, Ly, Lz), got {angular_momentum!r}",
                                "give for example (60.0, 0.0, 0.0): a forward somersault about yeadon's x") from None
    if len(L) != 3:
        raise InvalidInputError("angular_momentum", f"must be three numbers (Lx, Ly, Lz), got {angular_momentum!r}",
                                "give for example (60.0, 0.0, 0.0)")
    return L


def spatial_from_yeadon(human=None, *, joints="arms", posture="straight", angular_momentum=(0.0, 0.0, 0.0),
                        limits: bool = True, density_set: str = "Dempster") -> SpatialBody:
    """The 3-D human of a yeadon human (module docstring).

    Parameters
    ----------
    human : yeadon.Human, str or os.PathLike, optional
        Default the bundled ``"male1"``; a measurement file; a ``yeadon.Human``.
    joints : str or sequence of str
        ``"arms"`` (default), ``"arms+hips"``, ``"full"``, or joint names of :data:`JOINTS`.
    posture : str or mapping
        ``"straight"`` (default), ``"pike"``, ``"tuck"``, or angles by joint name (rad).
    angular_momentum : (float, float, float)
        :math:`L` about the centre of mass, inertial frame (kg m²/s). With the body in the
        reference attitude, :math:`(L_x, 0, 0)` with :math:`L_x > 0` is a forward somersault.
    limits : bool
        The data's joint ranges and rates in the link table (default), or none.
    density_set : str
        yeadon's densities.

    Returns
    -------
    SpatialBody

    Examples
    --------
    >>> from acroplan.families.human.spatial_body import spatial_from_yeadon
    >>> body = spatial_from_yeadon(joints="arms")
    >>> body.links.joint_names
    ('left_shoulder_flexion', 'left_shoulder_abduction', 'right_shoulder_flexion', 'right_shoulder_abduction')
    >>> round(sum(link.mass for link in body.links), 4)
    58.2005
    """
    segs = yeadon_segments(human, density_set=density_set)
    return SpatialBody(human_link_table(segs, joints, posture, limits=limits), L=_momentum(angular_momentum))


def spatial_from_height_mass(height: float, mass: float, *, sex: str = "male", joints="arms", posture="straight",
                             angular_momentum=(0.0, 0.0, 0.0), limits: bool = True) -> SpatialBody:
    """The 3-D human from stature and mass by de Leva's tables (:func:`de_leva_segments`), with the
    joints, posture and limits of :func:`spatial_from_yeadon`.

    Returns
    -------
    SpatialBody
    """
    segs = de_leva_segments(height, mass, sex=sex)
    return SpatialBody(human_link_table(segs, joints, posture, limits=limits), L=_momentum(angular_momentum))


# ---------------------------------------------------------------------- conventions
def body_angles(body: SpatialBody, state, posture="straight") -> dict[str, float]:
    """Every joint's angle (rad, all 18 of :data:`JOINTS`) of a 3-D human in ``state``: the free
    ones from the state, the others from the ``posture`` it was built with.

    Parameters
    ----------
    body : SpatialBody
        Built by :func:`spatial_from_yeadon` or :func:`spatial_from_height_mass`.
    state : array_like, shape (4 + m,)
        ``(qw, qx, qy, qz, s_1, ..., s_m)``.
    posture : str or mapping
    """
    x = np.asarray(state, dtype=float)
    names = body.links.joint_names
    if x.shape != (4 + len(names),):
        raise InvalidInputError("state", f"must have shape ({4 + len(names)},), got {x.shape}",
                                "give the quaternion and every joint angle")
    out = posture_angles(posture)
    for n, v in zip(names, x[4:]):
        if n not in JOINTS:
            raise InvalidInputError("body", f"joint {n!r} is not a joint of the 3-D human",
                                    "give a body built by spatial_from_yeadon")
        out[n] = float(v)
    return out


def yeadon_whole_body(human) -> tuple[float, np.ndarray, np.ndarray]:
    """A yeadon human's mass, centre of mass and inertia tensor in its current configuration, from
    its posed segments: :math:`\\sum_i R_i J_i R_i^\\top + m_i (|d_i|^2 \\mathbb{1} - d_i d_i^\\top)`,
    :math:`R_i` the segment's ``rot_mat``, :math:`J_i` its ``rel_inertia``, :math:`d_i` its
    ``center_of_mass`` minus the body's.

    yeadon 2.0.1's own ``Human.inertia`` turns each segment's tensor the other way,
    :math:`R_i^\\top J_i R_i` (``Segment.calc_properties`` calls ``inertia.rotate_inertia(rot_mat,
    rel_inertia)``, whose convention maps a tensor *into* the turned frame), so it is wrong whenever
    a segment is turned: a pure somersault and tilt of the straight body changes its entries by up
    to 0.6 kg m² (``tests/test_human_3d.py`` shows it). Its mass, centre of mass and the segments'
    poses and ``rel_inertia`` are right; this is the whole-body tensor they make.

    Returns
    -------
    mass : float
    com : numpy.ndarray, shape (3,)
        In yeadon's global frame (m).
    inertia : numpy.ndarray, shape (3, 3)
        About the centre of mass, in yeadon's global frame (kg m²).
    """
    segs = list(human.segments)
    m = np.array([float(s.mass) for s in segs])
    c = np.array([np.asarray(s.center_of_mass, dtype=float).reshape(3) for s in segs])
    com = m @ c / m.sum()
    J = np.zeros((3, 3))
    for s, mi, ci in zip(segs, m, c):
        R = np.asarray(s.rot_mat, dtype=float)
        d = ci - com
        J += R @ np.asarray(s.rel_inertia, dtype=float) @ R.T + mi * (float(d @ d) * np.eye(3) - np.outer(d, d))
    return float(m.sum()), com, J


def yeadon_configuration(angles: Mapping[str, float] | None = None, attitude=None, posture="straight") -> dict:
    """yeadon's configuration (``Human.set_CFG_dict``) of a pose of the 3-D human.

    Parameters
    ----------
    angles : mapping of str to float, optional
        Joint angles (rad) by name, over the ``posture``'s.
    attitude : array_like, shape (4,), optional
        The pelvis's unit quaternion ``[w, x, y, z]``; yeadon's ``somersault``, ``tilt``,
        ``twist`` are its Yeadon angles (:func:`~acroplan.families.spatial.rotations.to_euler`).
        Default the identity.
    posture : str or mapping

    Returns
    -------
    dict
        All 21 of yeadon's angles (rad): yeadon's angle = sign times the angle here.
    """
    a = posture_angles(posture)
    for k, v in (angles or {}).items():
        if k not in JOINTS:
            raise InvalidInputError(f"angles.{k}", "is not a joint of the 3-D human", f"joints: {list(JOINTS)}")
        a[k] = finite_number(f"angles.{k}", v)
    cfg = {d.yeadon: d.sign * a[n] for n, d in JOINTS.items()}
    if attitude is None:
        cfg.update(somersault=0.0, tilt=0.0, twist=0.0)
    else:
        s, t, w = rot.to_euler(rot.as_quaternion(attitude), degrees=False)
        cfg.update(somersault=float(s), tilt=float(t), twist=float(w))
    return cfg

