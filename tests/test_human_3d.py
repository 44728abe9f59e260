"""The 3-D human (issue #23): Yeadon's 11 segments as a SpatialBody, its joints, postures, limits as
data, its physics against yeadon's and Pinocchio's, and Yeadon's (1993) law of twisting somersaults.

Every number asserted is yeadon's own (its posed segments, its centre of mass), Pinocchio's, a
closed form, or a value of the bundled data with its source.
"""

import contextlib
import doctest
import io
import math

import numpy as np
import pytest

import acroplan
from acroplan.core.errors import InvalidInputError
from acroplan.families.human import spatial_body as sb
from acroplan.families.human.spatial_body import (
    JOINTS,
    PRESETS,
    human_link_table,
    joint_names,
    posture_angles,
    spatial_from_height_mass,
    spatial_from_yeadon,
    spatial_joint_limits,
    spatial_limits_data,
    yeadon_configuration,
    yeadon_segments,
    yeadon_whole_body,
)
from acroplan.families.spatial import SpatialBody, SpatialLink, read_urdf, to_urdf
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.model import kinematic_locked_inertia

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml)
pytestmark = pytest.mark.xdist_group("test_human_3d")

yeadon = pytest.importorskip("yeadon")


@pytest.fixture(scope="module")
def human():
    from acroplan.families.human import load_human

    return load_human()


def _set(human, cfg):
    with contextlib.redirect_stdout(io.StringIO()):
        human.set_CFG_dict(cfg)


def _whole(body, state):
    """The body's inertia (inertial frame, about the centre of mass) and its centre of mass seen
    from the pelvis's origin (inertial axes): plain kinematics of the link table."""
    x = np.asarray(state, dtype=float)
    R = rot.to_matrix(x[:4] / np.linalg.norm(x[:4]))
    _, origins, _ = body.link_poses(x)
    return R @ kinematic_locked_inertia(body.links, x[4:]) @ R.T, -origins[body.links.root]


def test_presets_name_the_joints_and_merge_the_held_segments(human):
    counts = {"arms": (4, 5), "arms+hips": (8, 9), "full": (14, 15)}
    for preset, (m, n) in counts.items():
        body = spatial_from_yeadon(human, joints=preset)
        assert body.links.joint_names == PRESETS[preset]
        assert (body.n_inputs, body.n_links) == (m, n)
        assert abs(sum(link.mass for link in body.links) - human.mass) < 1e-12
    arms = spatial_from_yeadon(human, joints="arms")
    assert arms.links.names == ("pelvis", "left_shoulder_flexion_link", "left_upper_arm",
                                "right_shoulder_flexion_link", "right_upper_arm")
    assert arms.links[1].mass == 0.0
    # the held forearms are merged into the upper arms, the trunk and legs into the pelvis
    assert abs(arms.links[2].mass - (human.A1.mass + human.A2.mass)) < 1e-12
    trunk = sum(getattr(human, s).mass for s in ("P", "T", "C", "J1", "J2", "K1", "K2"))
    assert abs(arms.links[0].mass - trunk) < 1e-12
    assert spatial_from_yeadon(human, joints=["right_knee_flexion", "left_hip_flexion"]).links.joint_names == (
        "left_hip_flexion", "right_knee_flexion")


# (preset, posture, seed): random joint angles in [-0.8, 0.8] rad and a random attitude
CASES = [(p, q, k) for p in ("arms", "arms+hips", "full") for q in ("straight", "pike", "tuck") for k in (0, 1)]


@pytest.mark.parametrize("preset,posture,seed", CASES)
def test_inertia_and_centre_of_mass_equal_yeadons(human, preset, posture, seed):
    """The whole body's inertia tensor and centre of mass equal those of yeadon's Human posed in the
    same configuration (:func:`yeadon_configuration`), to 1e-9. yeadon's centre of mass is its own
    ``Human.center_of_mass``; its tensor is assembled from its posed segments
    (:func:`yeadon_whole_body`), since yeadon 2.0.1's ``Human.inertia`` turns each segment the
    wrong way (next test)."""
    body = spatial_from_yeadon(human, joints=preset, posture=posture)
    rng = np.random.default_rng(100 * seed + len(preset))
    for _ in range(3):
        s = rng.uniform(-0.8, 0.8, body.n_inputs)
        q = rot.normalize(rng.normal(size=4))
        _set(human, yeadon_configuration(dict(zip(body.links.joint_names, s)), attitude=q, posture=posture))
        mass, com, inertia = yeadon_whole_body(human)
        J, c = _whole(body, np.concatenate([q, s]))
        assert abs(mass - human.mass) < 1e-12
        assert np.max(np.abs(com - np.asarray(human.center_of_mass).reshape(3))) < 1e-12
        assert np.max(np.abs(c - com)) < 1e-9
        assert np.max(np.abs(J - inertia)) < 1e-9 * np.max(np.abs(inertia))


def test_yeadon_human_inertia_rotates_segments_by_the_transpose(human):
    """Why the tensor above is assembled from yeadon's posed segments: turning the whole straight
    body rigidly (somersault 0.7, tilt 0.3 rad) must turn its tensor, :math:`R I_0 R^\\top`. The
    assembly does (1e-12); yeadon 2.0.1's ``Human.inertia`` is off by more than 0.5 kg m², because
    each ``Segment.inertia`` is :math:`R^\\top J R` instead of :math:`R J R^\\top`. Its
    medio-lateral entry :math:`I_{xx}` is right whenever every segment turns about x only (the
    planar human's checks), which the last assertion shows with yeadon's own number."""
    _set(human, {k: 0.0 for k in human.CFGnames})
    I0 = np.array(human.inertia, dtype=float)
    cfg = {k: 0.0 for k in human.CFGnames}
    cfg.update(somersault=0.7, tilt=0.3)
    _set(human, cfg)
    R = np.asarray(human.P.rot_mat, dtype=float)
    _, _, inertia = yeadon_whole_body(human)
    assert np.max(np.abs(inertia - R @ I0 @ R.T)) < 1e-12
    assert np.max(np.abs(np.asarray(human.inertia) - R @ I0 @ R.T)) > 0.5
    seg = human.A1
    assert np.max(np.abs(np.asarray(seg.inertia) - R.T @ seg.rel_inertia @ R)) < 1e-15
    # sagittal configurations: yeadon's own I_xx equals the 3-D body's
    body = spatial_from_yeadon(human, joints="full")
    s = np.zeros(body.n_inputs)
    angles = {"spine_flexion": 0.4, "left_shoulder_flexion": 1.1, "right_shoulder_flexion": -0.5,
              "left_hip_flexion": 1.4, "right_hip_flexion": 0.9, "left_knee_flexion": 1.2, "left_elbow_flexion": 0.7}
    for k, v in angles.items():
        s[body.links.joint_names.index(k)] = v
    q = rot.from_euler([40.0, 0.0, 0.0])
    _set(human, yeadon_configuration(angles, attitude=q))
    J, _ = _whole(body, np.concatenate([q, s]))
    assert abs(J[0, 0] - human.inertia[0, 0]) < 1e-9 * human.inertia[0, 0]


def test_attitude_is_yeadons_somersault_tilt_twist(human):
    """``from_euler([somersault, tilt, twist])`` is yeadon's pelvis orientation at those angles."""
    for angles in ([30.0, 0.0, 0.0], [0.0, 25.0, 0.0], [0.0, 0.0, 50.0], [200.0, -35.0, 120.0]):
        q = rot.from_euler(angles)
        cfg = yeadon_configuration(attitude=q)
        _set(human, cfg)
        assert np.max(np.abs(np.asarray(human.P.rot_mat) - rot.to_matrix(q))) < 1e-12
        assert np.allclose(np.degrees([cfg["somersault"], cfg["tilt"], cfg["twist"]]),
                           rot.to_euler(q), atol=1e-9)


def _coms(body, **angles):
    s = np.zeros(body.n_inputs)
    for k, v in angles.items():
        s[body.links.joint_names.index(k)] = v
    _, origins, coms = body.link_poses(np.concatenate([[1.0, 0.0, 0.0, 0.0], s]))
    names, o = body.links.names, origins[body.links.root]   # seen from the pelvis's origin
    return ({n: coms[i] - o for i, n in enumerate(names)}, {n: origins[i] - o for i, n in enumerate(names)})


def test_joint_signs_are_anatomical(human):
    """The documented signs, in yeadon's axes (x left, y backwards, z up): flexion forwards (-y),
    abduction away from the midline, knee flexion backwards, spine bending to the left, torsion
    turning the chest to the left, a twist turning the front (-y) to the left (+x)."""
    body = spatial_from_yeadon(human, joints="full")
    c0, _ = _coms(body)
    c, _ = _coms(body, left_shoulder_flexion=math.pi / 2, right_shoulder_flexion=math.pi / 2)
    assert c["left_forearm_hand"][1] - c0["left_forearm_hand"][1] < -0.3
    assert c["right_forearm_hand"][1] - c0["right_forearm_hand"][1] < -0.3
    c, o = _coms(body, left_shoulder_abduction=math.pi / 2, right_shoulder_abduction=math.pi / 2)
    assert c["left_upper_arm"][0] - o["left_upper_arm"][0] > 0.1      # the left arm out to the left
    assert c["right_upper_arm"][0] - o["right_upper_arm"][0] < -0.1   # the right arm out to the right
    c, _ = _coms(body, left_hip_flexion=1.0, right_hip_flexion=1.0)
    assert c["left_thigh"][1] - c0["left_thigh"][1] < -0.1 and c["right_thigh"][1] - c0["right_thigh"][1] < -0.1
    c, _ = _coms(body, left_hip_abduction=0.5, right_hip_abduction=0.5)
    assert c["left_thigh"][0] - c0["left_thigh"][0] > 0.05 and c["right_thigh"][0] - c0["right_thigh"][0] < -0.05
    c, _ = _coms(body, left_knee_flexion=1.5)
    assert c["left_shank_foot"][1] - c0["left_shank_foot"][1] > 0.1
    c, _ = _coms(body, left_elbow_flexion=1.5)
    assert c["left_forearm_hand"][1] - c0["left_forearm_hand"][1] < -0.1
    c, _ = _coms(body, spine_flexion=0.5)
    assert c["thorax"][1] - c0["thorax"][1] < -0.01
    c, _ = _coms(body, spine_bending=0.5)
    assert c["thorax"][0] - c0["thorax"][0] > 0.01
    torsion = spatial_from_yeadon(human, joints=["spine_torsion"])
    Rs, _, _ = torsion.link_poses(np.array([1.0, 0.0, 0.0, 0.0, 0.5]))
    front = Rs[torsion.links.index("chest_head")] @ np.array([0.0, -1.0, 0.0])
    assert front[0] == pytest.approx(math.sin(0.5), abs=1e-12)     # the chest's front turns to the left
    _set(human, yeadon_configuration({"spine_torsion": 0.5}))
    assert np.asarray(human.A1.pos)[1, 0] > 0.01                     # yeadon's left shoulder goes back
    front = rot.to_matrix(rot.from_euler([0.0, 0.0, 30.0])) @ np.array([0.0, -1.0, 0.0])
    assert front[0] == pytest.approx(0.5, abs=1e-12)                 # a twist > 0 turns the front to the left


def test_spine_torsion_and_bending_match_yeadon(human):
    """Spine torsion (the TC joint, in no preset) with bending: inertia and centre of mass equal yeadon's."""
    body = spatial_from_yeadon(human, joints=["spine_torsion", "spine_bending"])
    assert body.links.joint_names == ("spine_bending", "spine_torsion")   # the link table's order: T, then C
    s = np.array([0.3, -0.4])
    _set(human, yeadon_configuration(dict(zip(body.links.joint_names, s))))
    _, com, inertia = yeadon_whole_body(human)
    J, c = _whole(body, np.concatenate([[1.0, 0.0, 0.0, 0.0], s]))
    assert np.max(np.abs(J - inertia)) < 1e-12 * 10
    assert np.max(np.abs(c - com)) < 1e-12


@pytest.mark.parametrize("preset", ["arms", "arms+hips", "full"])
def test_pinocchio_centroidal_map_equals_the_momentum_map(human, preset):
    """Pinocchio's centroidal momentum map (its angular rows) equals the body's symbolic momentum
    map I(s), A(s) (1e-12 relative), at random shapes."""
    pytest.importorskip("pinocchio")
    from acroplan.families.spatial.check import pinocchio_momentum_map

    body = spatial_from_yeadon(human, joints=preset, posture="pike")
    rng = np.random.default_rng(7)
    for _ in range(4):
        s = rng.uniform(-1.0, 1.0, body.n_inputs)
        I, A = body.momentum_map(s)
        Ip, Ap = pinocchio_momentum_map(body, s)
        scale = np.max(np.abs(Ip))
        assert np.max(np.abs(I - Ip)) < 1e-12 * scale
        assert np.max(np.abs(A - Ap)) < 1e-12 * scale
        assert np.max(np.abs(kinematic_locked_inertia(body.links, s) - Ip)) < 1e-12 * scale


def test_pinocchio_locked_inertia_of_the_full_body(human):
    """The 15-link body in a tuck: Pinocchio's locked inertia equals yeadon's posed segments."""
    pytest.importorskip("pinocchio")
    from acroplan.families.spatial.check import pinocchio_momentum_map

    body = spatial_from_yeadon(human, joints="full", posture="tuck")
    rng = np.random.default_rng(8)
    s = rng.uniform(-1.0, 1.0, body.n_inputs)
    Ip, Ap = pinocchio_momentum_map(body, s)
    _set(human, yeadon_configuration(dict(zip(body.links.joint_names, s)), posture="tuck"))
    _, _, inertia = yeadon_whole_body(human)
    assert np.max(np.abs(Ip - inertia)) < 1e-12 * np.max(np.abs(inertia))
    assert Ap.shape == (3, 14)


def test_urdf_export_reads_back_with_the_same_inertia(human, tmp_path):
    """``to_urdf`` of the 3-D human, read back by Pinocchio (``read_urdf``): the same joints, limits,
    locked inertia and coupling (Pinocchio orders the joints depth-first, so compared by name)."""
    pytest.importorskip("pinocchio")
    from acroplan.families.spatial.check import pinocchio_momentum_map

    body = spatial_from_yeadon(human, joints="full", posture="pike")
    path = tmp_path / "human.urdf"
    path.write_text(to_urdf(body, name="yeadon_male1"), encoding="utf-8")
    back = read_urdf(path)
    assert sorted(back.links.joint_names) == sorted(body.links.joint_names)
    perm = [body.links.joint_names.index(n) for n in back.links.joint_names]
    lim = {link.joint_name: (link.lower, link.upper, link.velocity) for link in body.links if link.parent}
    lim_back = {link.joint_name: (link.lower, link.upper, link.velocity) for link in back.links if link.parent}
    assert lim == lim_back
    rng = np.random.default_rng(9)
    s = rng.uniform(-1.0, 1.0, body.n_inputs)
    I1, A1 = pinocchio_momentum_map(body, s)
    I2, A2 = pinocchio_momentum_map(back, s[perm])
    assert np.max(np.abs(I1 - I2)) < 1e-12 * np.max(np.abs(I1))
    assert np.max(np.abs(A1[:, perm] - A2)) < 1e-12 * np.max(np.abs(I1))


def test_held_postures_come_from_the_data():
    d = spatial_limits_data()
    pike, tuck = posture_angles("pike"), posture_angles("tuck")
    assert pike["left_hip_flexion"] == pike["right_hip_flexion"] == pytest.approx(math.radians(150.0))
    assert pike["left_knee_flexion"] == 0.0
    assert tuck["left_hip_flexion"] == pytest.approx(math.radians(140.0))
    assert tuck["right_knee_flexion"] == pytest.approx(math.radians(125.0))
    assert set(posture_angles("straight").values()) == {0.0}
    assert d["postures"]["tuck"]["knee_flexion"]["same_as"] == "knee.flexion_tuck"
    custom = posture_angles({"left_elbow_flexion": 1.0})
    assert custom["left_elbow_flexion"] == 1.0 and custom["right_elbow_flexion"] == 0.0


def test_limits_data_have_sources_or_are_marked_estimates():
    d = spatial_limits_data()
    sources = d["sources"]
    kinds = {dof.kind for dof in JOINTS.values()}
    for kind in kinds:
        for bound in ("lower", "upper", "rate"):
            e = d[kind][bound]
            assert isinstance(e["value"], float), (kind, bound)
            assert e["estimate"] or e["source"] in sources, (kind, bound)
    for k, e in d["geometry"].items():
        assert e["estimate"] and e["source"] in sources, k
    # values from the sources (degrees): AAOS (1965), as tabulated by Norkin & White
    assert d["shoulder_abduction"]["upper"]["value"] == 180.0 and not d["shoulder_abduction"]["upper"]["estimate"]
    assert d["elbow_flexion"]["upper"]["value"] == 150.0
    assert d["hip_abduction"]["lower"]["value"] == -30.0 and d["hip_abduction"]["upper"]["value"] == 45.0
    assert d["shoulder_flexion"]["lower"]["value"] == -60.0 and d["shoulder_flexion"]["lower"]["same_as"]
    assert d["hip_flexion"]["upper"]["value"] == 150.0 and d["hip_flexion"]["upper"]["estimate"]
    assert d["hip_flexion"]["rate"]["value"] == 12.0
    lim = spatial_joint_limits()
    assert lim["right_hip_abduction"] == pytest.approx((math.radians(-30.0), math.radians(45.0), 12.0))
    assert set(lim) == set(JOINTS)


def test_geometry_estimates_are_male1s_proportions(human):
    geo = spatial_limits_data()["geometry"]
    _set(human, {k: 0.0 for k in human.CFGnames})
    vertex = float(np.asarray(human.C.end_pos)[2, 0])
    shoulder = 2.0 * float(np.asarray(human.A1.pos)[0, 0])
    hip = 2.0 * float(np.asarray(human.J1.pos)[0, 0])
    assert geo["shoulder_width"]["value"] == pytest.approx(shoulder / vertex, abs=1e-4)
    assert geo["hip_width"]["value"] == pytest.approx(hip / vertex, abs=1e-4)


def test_limits_are_in_the_link_table_and_honoured_by_default(human):
    body = spatial_from_yeadon(human, joints="arms")
    lim = body.default_limits()
    lo, hi = lim.bounds("left_shoulder_abduction")
    assert (lo, hi) == pytest.approx((0.0, math.pi))
    assert lim.input_bound("u_right_shoulder_flexion") == 15.0
    assert spatial_from_yeadon(human, joints="arms", limits=False).default_limits() is None


def test_de_leva_body_sums_and_inertia():
    """From height and mass: the segments add up to the mass; the straight body's inertia equals an
    independent sum of de Leva's segments (1e-12); the arms and the legs hang where the table and
    the geometry put them."""
    from acroplan.families.human.deleva import de_leva_table

    H, M = 1.741, 73.0
    body = spatial_from_height_mass(H, M, joints="full")
    assert abs(sum(link.mass for link in body.links) - M) < 1e-12
    t = de_leva_table()
    rows = {k: t["segments"][k]["male"] for k in t["segments"]}
    k = H / 1.741
    L = {n: r["length_mm"] / 1000.0 * k for n, r in rows.items()}
    singles = ("lower_trunk", "middle_trunk", "upper_trunk", "head_to_c7")
    pairs = ("upper_arm", "forearm", "hand", "thigh", "shank", "foot")
    total = sum(rows[n]["mass"] for n in singles) + 2 * sum(rows[n]["mass"] for n in pairs)
    geo = spatial_limits_data()["geometry"]
    vertex = L["trunk_from_c7"] + L["head_to_c7"]
    ws, wh = geo["shoulder_width"]["value"] * vertex / 2, geo["hip_width"]["value"] * vertex / 2
    parts = []   # (mass, centre (x, y, z), principal moments (x, y, z)) in the straight posture

    def add(n, x, z_com):
        r = rows[n]
        m = M * r["mass"] / total
        parts.append((m, np.array([x, 0.0, z_com]), m * (np.array([r["r_trans"], r["r_sag"], r["r_long"]])
                                                         / 100.0 * L[n]) ** 2))

    f = {n: rows[n]["com"] / 100.0 for n in rows}
    add("lower_trunk", 0.0, (1 - f["lower_trunk"]) * L["lower_trunk"])
    z = L["lower_trunk"]
    add("middle_trunk", 0.0, z + (1 - f["middle_trunk"]) * L["middle_trunk"])
    z += L["middle_trunk"]
    add("upper_trunk", 0.0, z + (1 - f["upper_trunk"]) * L["upper_trunk"])
    add("head_to_c7", 0.0, L["trunk_from_c7"] + (1 - f["head_to_c7"]) * L["head_to_c7"])
    zs = L["trunk_from_shoulders"]
    for x in (ws, -ws):
        add("upper_arm", x, zs - f["upper_arm"] * L["upper_arm"])
        add("forearm", x, zs - L["upper_arm"] - f["forearm"] * L["forearm"])
        add("hand", x, zs - L["upper_arm"] - L["forearm"] - f["hand"] * L["hand"])
    for x in (wh, -wh):
        add("thigh", x, -f["thigh"] * L["thigh"])
        add("shank", x, -L["thigh"] - f["shank"] * L["shank"])
        add("foot", x, -L["thigh"] - L["shank"] - f["foot"] * L["foot"])
    m = sum(p[0] for p in parts)
    c = sum(p[0] * p[1] for p in parts) / m
    J = sum(np.diag(p[2]) + p[0] * ((p[1] - c) @ (p[1] - c) * np.eye(3) - np.outer(p[1] - c, p[1] - c)) for p in parts)
    J0, c0 = _whole(body, np.concatenate([[1.0, 0.0, 0.0, 0.0], np.zeros(body.n_inputs)]))
    assert abs(m - M) < 1e-12
    assert np.max(np.abs(c0 - c)) < 1e-12
    assert np.max(np.abs(J0 - J)) < 1e-12 * np.max(np.abs(J))
    # a woman of 1.735 m and 62 kg: the masses add up too, and her body is lighter to turn
    her = spatial_from_height_mass(1.735, 62.0, sex="female", joints="arms")
    assert abs(sum(link.mass for link in her.links) - 62.0) < 1e-12
    assert kinematic_locked_inertia(her.links, np.zeros(4))[0, 0] < J[0, 0]


def test_de_leva_and_yeadon_3d_are_close_for_a_similar_body(human):
    """male1 (58.2 kg) and a de Leva man of the same mass and a stature of 1.70 m (an assumption:
    yeadon's sample gives no stature) have principal moments within 25 %."""
    a = np.linalg.eigvalsh(kinematic_locked_inertia(spatial_from_yeadon(human).links, np.zeros(4)))
    b = np.linalg.eigvalsh(kinematic_locked_inertia(spatial_from_height_mass(1.70, human.mass).links, np.zeros(4)))
    assert np.all(np.abs(a - b) / a < 0.25)


@pytest.mark.parametrize("kw,field", [
    (dict(joints="legs"), "joints"), (dict(joints=["elbow"]), "joints"), (dict(posture="layout"), "posture"),
    (dict(posture={"knee": 1.0}), "posture.knee"), (dict(angular_momentum=(1.0, 2.0)), "angular_momentum"),
])
def test_bad_input_names_the_field(human, kw, field):
    with pytest.raises(InvalidInputError) as e:
        spatial_from_yeadon(human, **kw)
    assert e.value.field == field


def test_body_angles_fill_in_the_held_posture(human):
    body = spatial_from_yeadon(human, joints="arms", posture="tuck")
    x = np.array([1.0, 0.0, 0.0, 0.0, 0.1, 0.2, 0.3, 0.4])
    a = sb.body_angles(body, x, posture="tuck")
    assert [a[n] for n in body.links.joint_names] == [0.1, 0.2, 0.3, 0.4]
    assert a["left_knee_flexion"] == pytest.approx(math.radians(125.0)) and a["spine_flexion"] == 0.0
    cfg = yeadon_configuration(a)
    assert cfg["CB1abduction"] == 0.4 and cfg["CA1adduction"] == -0.2 and cfg["J1J2flexion"] == a["left_knee_flexion"]
    with pytest.raises(InvalidInputError) as e:
        sb.body_angles(body, x[:-1])
    assert e.value.field == "state"


def test_joint_names_and_link_table_without_limits(human):
    assert joint_names("arms+hips")[-1] == "right_hip_abduction"
    table = human_link_table(yeadon_segments(human), "arms", limits=False)
    assert all(link.lower is None and link.velocity is None for link in table)


# ---------------------------------------------------------------------- Yeadon's (1993) law
def _symmetric_top(A: float, C: float) -> SpatialBody:
    """A rigid body symmetric about its long axis z: two equal coaxial solid cylinders of length
    ``h`` and radius ``r`` end to end (joint about z at the junction, held still), with the
    whole body's transverse moment A and long-axis moment C about its centre of mass:
    :math:`C = m r^2 / 2`, :math:`A = m (3 r^2 + (2h)^2) / 12` for the total mass :math:`m`."""
    m = 60.0
    r = math.sqrt(2.0 * C / m)
    h = math.sqrt(12.0 * A / m - 3.0 * r * r) / 2.0
    half = m / 2.0
    Ia = half * (3 * r * r + h * h) / 12.0
    Ic = half * r * r / 2.0
    return SpatialBody([SpatialLink("lower", None, half, (Ia, Ia, Ic), com=(0.0, 0.0, -h / 2.0)),
                        SpatialLink("upper", "lower", half, (Ia, Ia, Ic), com=(0.0, 0.0, h / 2.0), axis=(0, 0, 1),
                                    joint_name="spin")], L=(0.0, 0.0, 0.0))


@pytest.mark.parametrize("A,C,tilt_deg", [(15.0, 1.0, 5.0), (12.0, 0.8, 10.0), (9.6, 0.55, 3.0)])
def test_yeadons_law_twists_per_somersault(A, C, tilt_deg):
    """Yeadon (1993, *The biomechanics of twisting somersaults. Part I: rigid body motions*, J.
    Sports Sci. 11:187-198): a rigid body symmetric about its long axis (transverse moment A,
    long-axis moment C) with its angular momentum L along the somersault axis and tilt
    :math:`\\theta` twists :math:`(A/C - 1)\\sin\\theta` times per somersault.

    Derivation (free symmetric top, Yeadon's Cardan angles :math:`R = R_x(\\phi) R_y(\\theta)
    R_z(\\psi)`, L along the inertial x). In the body frame :math:`R^\\top L = L(\\cos\\theta
    \\cos\\psi, -\\cos\\theta\\sin\\psi, \\sin\\theta)`, so the angular velocity is
    :math:`\\Omega = (L_x/A, L_y/A, L_z/C)` in body components. The Cardan rates give
    :math:`\\Omega = \\dot\\phi (\\cos\\theta\\cos\\psi, -\\cos\\theta\\sin\\psi, \\sin\\theta)
    + \\dot\\theta (\\sin\\psi, \\cos\\psi, 0) + \\dot\\psi (0, 0, 1)`. Matching: the transverse
    components give :math:`\\dot\\theta = 0` and :math:`\\dot\\phi = L/A`; the long axis gives
    :math:`\\dot\\phi\\sin\\theta + \\dot\\psi = (L/C)\\sin\\theta`, so

    .. math::  \\dot\\psi = \\frac{L}{A}\\Big(\\frac{A}{C} - 1\\Big)\\sin\\theta
               = \\Big(\\frac{A}{C} - 1\\Big)\\sin\\theta\\;\\dot\\phi ,

    all three rates constant: the tilt stays at its initial value and the Cardan twist angle grows
    in proportion to the Cardan somersault angle, exactly.

    The precise reading: "twists per somersault" is the Cardan twist :math:`\\psi` per Cardan
    somersault :math:`\\phi` (both in turns), with :math:`\\theta` the Cardan tilt. It is *not* the
    spin about the long axis: :math:`\\Omega_z = (A/C)\\sin\\theta\\,\\dot\\phi` counts :math:`A/C`
    rather than :math:`A/C - 1`, the difference being the somersault's own component along the
    tilted long axis. Checked here by simulating the locked body (joint rate 0) with acroplan's
    compiled integrator over two somersaults from tilt :math:`\\theta`, and counting, to 1e-6,
    twists per somersault from the Yeadon angles of the states, the tilt constant to 1e-9 and
    :math:`\\Omega_z/\\dot\\phi = (A/C)\\sin\\theta`.
    """
    body = _symmetric_top(A, C)
    I0 = kinematic_locked_inertia(body.links, [0.0])
    assert np.allclose(np.diag(I0), (A, A, C), rtol=1e-12) and np.max(np.abs(I0 - np.diag(np.diag(I0)))) < 1e-12
    L = 50.0
    body = SpatialBody(body.links, L=(L, 0.0, 0.0))
    theta = math.radians(tilt_deg)
    q0 = rot.from_euler([0.0, tilt_deg, 0.0])
    T = 2 * (2 * math.pi * A / L)            # two somersaults at dphi/dt = L/A
    times = np.linspace(0.0, T, 65)
    res = acroplan.simulate(body, times=times, inputs=[np.zeros((1, 2))] * 64, qw=q0[0], qx=q0[1], qy=q0[2],
                            qz=q0[3], spin=0.0, verify=False)
    assert res.status == "success"
    angles = np.radians(rot.to_euler(res.waypoints[:, :4].T))
    som, tilt, twist = np.unwrap(angles[0]), angles[1], np.unwrap(angles[2])
    assert np.max(np.abs(tilt - theta)) < 1e-9
    assert abs(som[-1] - som[0] - 4 * math.pi) < 1e-8
    per_somersault = (twist[-1] - twist[0]) / (som[-1] - som[0])
    law = (A / C - 1.0) * math.sin(theta)
    assert abs(per_somersault - law) < 1e-6 * max(1.0, law)
    # the rates are constant: the twist grows in proportion to the somersault all along
    assert np.max(np.abs((twist - twist[0]) - law * (som - som[0]))) < 1e-7
    # the spin about the long axis is (A/C) sin(theta) per somersault, not the twist
    omega = body.angular_velocity(np.concatenate([q0, [0.0]]), [0.0])
    assert omega[2] / (L / A) == pytest.approx(A / C * math.sin(theta), rel=1e-12)


def test_docstring_examples():
    assert doctest.testmod(sb, optionflags=doctest.ELLIPSIS).failed == 0


# ---------------------------------------------------------------------- aerial twist from the arms
@pytest.fixture(scope="module")
def arm_twists():
    from acroplan.families.human.twist import asymmetric_arm_twist

    return {arm: asymmetric_arm_twist(acroplan.simulate, arm=arm) for arm in ("right", "left", "both")}


def test_symmetric_arms_neither_tilt_nor_twist_and_somersault_as_the_planar_integral(arm_twists):
    """Both arms lowered together: the motion stays in the sagittal plane (tilt and twist 0 to 1e-9),
    and the somersault is the planar integral :math:`\\int (L_x - A_x(s)\\,u)/I_{xx}(s)\\,dt`
    (Pinocchio's locked inertia and coupling at Gauss nodes), to 1e-9 turns."""
    pytest.importorskip("pinocchio")
    from acroplan.families.spatial.check import pinocchio_momentum_map

    both = arm_twists["both"]
    assert both.result.status == "success"
    assert np.max(np.abs(both.tilt)) < 1e-9 and np.max(np.abs(both.twist)) < 1e-9
    res = both.result
    Lx = res.system.L[0]
    x, w = np.polynomial.legendre.leggauss(40)
    total = 0.0
    for seg in res.segments:
        T = seg.t1 - seg.t0
        for xi, wi in zip(x, w):
            t = seg.t0 + (xi + 1) / 2 * T
            u = np.asarray(seg.input(np.array([t]))).reshape(-1)
            shape = res.evaluate([t], effort=False).states[4:, 0]
            I, A = pinocchio_momentum_map(res.system, shape)
            assert abs(I[0, 1]) + abs(I[0, 2]) < 1e-12
            total += wi * T / 2 * (Lx - A[0] @ u) / I[0, 0]
    assert abs(both.somersault[-1] - total / (2 * math.pi)) < 1e-9


def test_one_arm_lowered_tilts_and_twists_the_body(arm_twists):
    """One arm lowered from overhead to the side in a backward layout somersault tilts the body
    (Yeadon 1993, Part III); the left arm's flight is the right arm's mirror image (tilt and twist
    of opposite signs, the same somersault, to 1e-9); every flight checked by Pinocchio."""
    right, left = arm_twists["right"], arm_twists["left"]
    assert right.result.status == "success" and left.result.status == "success"
    assert np.max(np.abs(right.tilt + left.tilt)) < 1e-9
    assert np.max(np.abs(right.twist + left.twist)) < 1e-9
    assert np.max(np.abs(right.somersault - left.somersault)) < 1e-9
    s, _, twist = right.final
    assert right.peak_tilt > 3.0 and abs(twist) > 1.0
    assert s < -1.0                      # backwards, about one somersault
    assert "twists" in right.summary()


# ---------------------------------------------------------------------- aerial twist from the hips
@pytest.fixture(scope="module")
def hip_twists():
    from acroplan.families.human.twist import asymmetric_hip_twist

    return {leg: asymmetric_hip_twist(acroplan.simulate, leg=leg) for leg in ("right", "left", "both")}


def test_one_leg_swung_out_tilts_and_twists_the_body(hip_twists, arm_twists):
    """One leg swung out sideways (hip abduction 0 -> 40 degrees) in a backward layout somersault,
    the arms overhead, tilts the body (Yeadon 1993, Part III: asymmetric hip movements); the left
    leg's flight is the right leg's mirror image (1e-9); the straddle (both legs) neither tilts nor
    twists (1e-9); the right leg twists the other way from the right arm lowered (it turns the other
    way in the frontal plane); every flight checked by Pinocchio (1e-9)."""
    from acroplan.families.human.twist import HIP_ANGLE

    right, left, both = hip_twists["right"], hip_twists["left"], hip_twists["both"]
    for r in (right, left, both):
        assert r.result.status == "success"
        assert max(s.verified_error for s in r.result.segments) < 1e-9
    assert np.max(np.abs(right.tilt + left.tilt)) < 1e-9
    assert np.max(np.abs(right.twist + left.twist)) < 1e-9
    assert np.max(np.abs(right.somersault - left.somersault)) < 1e-9
    assert np.max(np.abs(both.tilt)) < 1e-9 and np.max(np.abs(both.twist)) < 1e-9
    s, _, twist = right.final
    assert right.peak_tilt > 3.0 and twist > 0.1
    assert np.sign(twist) == -np.sign(arm_twists["right"].final[2])
    assert s < -1.0
    assert right.summary().startswith("right leg swung out:")
    # within the data's limits: the hip's range, and the minimum-jerk peak rate 1.875 angle / 0.3 s
    lim = right.result.system.default_limits()
    lo, hi = lim.bounds("right_hip_abduction")
    assert lo <= 0.0 and HIP_ANGLE < hi
    seg = right.result.segments[1]
    t = np.linspace(seg.t0, seg.t1, 201)
    u = np.asarray(seg.input(t))
    names = right.result.system.links.joint_names
    k = names.index("right_hip_abduction")
    assert np.max(np.abs(u[k])) == pytest.approx(1.875 * HIP_ANGLE / 0.3, rel=1e-12)
    assert np.max(np.abs(np.delete(u, k, axis=0))) == 0.0
    assert 1.875 * HIP_ANGLE / 0.3 < lim.input_bound("u_right_hip_abduction")


def test_hip_twist_problem_refuses_what_it_cannot_build():
    from acroplan.families.human.twist import hip_twist_problem

    with pytest.raises(InvalidInputError, match="leg"):
        hip_twist_problem(leg="middle")
    with pytest.raises(InvalidInputError, match="arms\\+hips"):
        hip_twist_problem(spatial_from_yeadon(joints="arms"))
    with pytest.raises(InvalidInputError, match="duration"):
        hip_twist_problem(start=1.4, duration=0.3)


# ------------------------------------------------------------------ problem files (the plug-in family)
H3 = """[body]
yeadon = "male1"
model = "3d"
joints = "arms+hips"
posture = "pike"
angular_momentum = [-60.0, 0.0, 0.0]

[plan]
times = [0, 1.0]
attitude_euler_deg = [[0, 0, 0], [-200, 0, 20]]
{joints}
conditions = "free"
"""


def _h3(tmp_path, text):
    from acroplan.io.problem import load_problem

    path = tmp_path / "h3.toml"
    path.write_text(text)
    return load_problem(path)


def test_a_problem_file_gives_the_3d_human_through_the_human_family(tmp_path):
    """[body] model = "3d" is read by the human family's own table (families/human/problem.py), with
    no change to the I/O layer (issue #21's plug-in families): the same body as the API's."""
    from acroplan.families.human.spatial_body import spatial_from_yeadon

    ref = spatial_from_yeadon(joints="arms+hips", posture="pike", angular_momentum=(-60.0, 0.0, 0.0))
    joints = "\n".join(f"{j} = [0.1, 0.1]" for j in ref.links.joint_names)
    prob = _h3(tmp_path, H3.format(joints=joints))
    assert prob.system.links == ref.links and np.array_equal(prob.system.angular_momentum, ref.angular_momentum)
    assert prob.state("qw")[0] == 1.0 and len(prob.state("qw")) == 2
    # the file's limits override the data's, joint by joint
    lim = _h3(tmp_path, H3.format(joints=joints) + "[limits]\nleft_hip_flexion_max = 1.0\n").limits
    assert lim.bounds("left_hip_flexion")[1] == 1.0


@pytest.mark.parametrize("edit, match", [
    (('model = "3d"', 'model = "4d"'), r"^body\.model: must be one of \['2d', '3d'\]"),
    (('posture = "pike"', 'posture = "pik"'), r"^body\.posture: .*did you mean \"pike\""),
    (('joints = "arms+hips"', 'joints = "legs"'), r"^body\.joints: must be one of"),
    (('angular_momentum = [-60.0, 0.0, 0.0]', 'angular_momentum = -60.0'), r"^body\.angular_momentum: must be three"),
    (('posture = "pike"', 'split = "hips"'), r"^body\.split: is a key of the planar human, and model = \"3d\""),
    (('model = "3d"\n', ''), r"^body\.joints: is a key of the 3-D human"),
])
def test_bad_3d_human_tables_name_the_field(tmp_path, edit, match):
    joints = "left_shoulder_flexion = [0, 0]"
    with pytest.raises(acroplan.InvalidInputError, match=match):
        _h3(tmp_path, H3.format(joints=joints).replace(*edit))
