"""Bodies from .bioMod files (issue #23), read by biorbd: bioptim's free-floating trunk with two arms,
a body with every kind of placement, and the refusals. Skipped where biorbd is not installed
(``pip install acroplan[biomod]``), except the message that says how to install it.

The reference numbers are biorbd's own: its total mass, its centre of mass and its angular momentum
about the centre of mass (``CalcAngularMomentum``), whose columns at unit generalized velocities are
the locked inertia (root rotations) and the coupling (joints).
"""

import sys

import numpy as np
import pytest

from acroplan.core.errors import InvalidInputError
from acroplan.families.spatial import read_biomod
from acroplan.families.spatial.biomod import keeping_locale, read_biomod_table

try:
    import biorbd
except ImportError:  # pragma: no cover - the extra is not installed
    biorbd = None

needs_biorbd = pytest.mark.skipif(biorbd is None, reason="biorbd is not installed (pip install acroplan[biomod])")

# bioptim's examples/torque_driven_ocp/models/trunk_and_2arm.bioMod (pyomeca/bioptim, MIT licence): its
# segments, masses, inertias, centres of mass, RT and degrees of freedom (its meshes and markers left out)
TRUNK_AND_2ARM = """version 3

segment Pelvis
    translations xyz
    rotations xyz
    mass 58.801
    inertia
        7.85829 0.00000 0.00000
        0.00000 8.12771 0.00000
        0.00000 0.00000 0.51802
    com 0 0 0.09410
endsegment

segment RightArm
    parent Pelvis
    RT 0 0 0 xyz -0.1875 0.0205 0.4719
    rotations y
    mass 3.106
    inertia
        0.0910283 0.00000 0.00000
        0.00000 0.0909983 0.00000
        0.00000 0.00000 0.00292
    com 0 0 -0.233088
endsegment

segment LeftArm
    parent Pelvis
    RT 0 0 0 xyz 0.1875 0.0205 0.4719
    rotations y
    mass 3.106
    inertia
        0.0910283 0.00000 0.00000
        0.00000 0.0909983 0.00000
        0.00000 0.00000 0.00292
    com 0 0 -0.233088
endsegment
"""

# every placement the reader handles: a root rotating zxy with an RT, a two-rotation joint under a
# turned RT, a segment without degrees of freedom (merged), a massless frame segment, off-diagonal
# inertias
BRANCHED = """version 4
segment Root
    RT 0.1 -0.3 0.2 xyz 0.05 0.0 0.1
    translations xyz
    rotations zxy
    mass 10
    inertia
        2.0 0.1 0.0
        0.1 2.5 0.05
        0.0 0.05 3.0
    com 0.1 0.2 0.3
endsegment
segment Frame
    parent Root
    RT 0 0 0.3 xyz 0 0.1 0.5
endsegment
segment A
    parent Frame
    RT 0.3 -0.2 0.5 xyz 0.1 0.2 0.3
    rotations zx
    mass 2
    inertia
        0.1 0.01 0
        0.01 0.2 0
        0 0 0.25
    com 0 0 -0.2
endsegment
segment B
    parent A
    RT 0.1 0.4 0 yxz 0 0 -0.4
    mass 1
    inertia
        0.05 0 0
        0 0.05 0
        0 0 0.01
    com 0.05 0 -0.1
endsegment
segment C
    parent Root
    RT 0 0 1.2 xyz -0.2 0 0.4
    rotations yzx
    mass 1.5
    inertia
        0.04 0 0
        0 0.05 0
        0 0 0.02
    com 0 0.1 -0.15
endsegment
"""


def _model(path):
    """``biorbd.Model(path)``, the process's locale kept (biorbd sets it to "C")."""
    with keeping_locale():
        return biorbd.Model(str(path))


def _write(tmp_path, text, name="body.bioMod"):
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _biorbd_map(model, shape):
    """biorbd's locked inertia and coupling, in the root segment's frame, at root angles 0 (the root
    segment's frame is then its RT: its intrinsic rotations at 0 turn by nothing, and a unit rate of
    the k-th root rotation is a unit angular velocity about that axis of the root frame)."""
    nq = model.nbQ()
    root = model.segment(0)
    nroot = root.nbDof()
    q = np.zeros(nq)
    q[nroot:] = shape
    R = np.asarray(root.localJCS().to_array())[:3, :3]
    ntr = root.nbDofTrans()
    I = np.zeros((3, 3))  # noqa: E741
    for k, axis in enumerate(root.seqR().to_string()):
        qd = np.zeros(nq)
        qd[ntr + k] = 1.0
        I[:, "xyz".index(axis)] = R.T @ model.CalcAngularMomentum(q, qd, True).to_array()
    A = np.column_stack([R.T @ model.CalcAngularMomentum(q, np.eye(nq)[nroot + j], True).to_array()
                         for j in range(nq - nroot)])
    com = R.T @ (model.CoM(q).to_array() - np.asarray(root.localJCS().to_array())[:3, 3])
    return I, A, com


@needs_biorbd
def test_bioptims_trunk_and_two_arms_equal_biorbd(tmp_path):
    """bioptim's free-floating example: a 58.801 kg trunk and two 3.106 kg arms turning about y,
    with L = (36.3075, 0, 0). Total mass, locked inertia, coupling and centre of mass equal biorbd's
    to 1e-9, at the arms' rest and at three other shapes."""
    path = _write(tmp_path, TRUNK_AND_2ARM, "trunk_and_2arm.bioMod")
    body = read_biomod(path, angular_momentum=(36.3075, 0.0, 0.0))
    model = _model(path)
    assert body.links.names == ("Pelvis", "RightArm", "LeftArm")
    assert body.links.joint_names == ("RightArm_RotY", "LeftArm_RotY")
    assert body.L == (36.3075, 0.0, 0.0)
    assert abs(sum(link.mass for link in body.links) - model.mass()) < 1e-12
    assert abs(model.mass() - 65.013) < 1e-12
    for shape in ([0.0, 0.0], [0.4, -1.1], [2.5, 2.9], [-3.0, 0.2]):
        I, A = body.momentum_map(shape)
        Ib, Ab, cb = _biorbd_map(model, np.asarray(shape))
        assert np.max(np.abs(I - Ib)) < 1e-9 * np.max(np.abs(Ib))
        assert np.max(np.abs(A - Ab)) < 1e-9 * np.max(np.abs(Ib))
        _, origins, _ = body.link_poses(np.concatenate([[1.0, 0.0, 0.0, 0.0], shape]))
        assert np.max(np.abs(-origins[body.links.root] - cb)) < 1e-12


@needs_biorbd
def test_every_placement_equals_biorbd(tmp_path):
    """A root rotating zxy under an RT, a massless frame segment and a fixed segment (both merged), a
    two- and a three-rotation joint (chains through massless links), off-diagonal inertias: the
    locked inertia, coupling and centre of mass equal biorbd's to 1e-9 at random shapes."""
    pytest.importorskip("pinocchio")
    from acroplan.families.spatial.check import pinocchio_momentum_map

    path = _write(tmp_path, BRANCHED)
    table = read_biomod_table(path)
    assert table.names == ("Root", "A_rotz", "A", "C_roty", "C_rotz", "C")
    assert table.joint_names == ("A_RotZ", "A_RotX", "C_RotY", "C_RotZ", "C_RotX")
    assert table[1].mass == 0.0 and table[2].mass == 3.0   # A with the fixed B merged in
    assert table[0].mass == 10.0 + 1e-8                     # the frame segment: biorbd's 1e-8 kg point mass
    body = read_biomod(path)
    model = _model(path)
    assert abs(sum(link.mass for link in body.links) - model.mass()) < 1e-12
    rng = np.random.default_rng(4)
    for _ in range(4):
        s = rng.uniform(-2.0, 2.0, 5)
        I, A = body.momentum_map(s)
        Ib, Ab, cb = _biorbd_map(model, s)
        assert np.max(np.abs(I - Ib)) < 1e-9 * np.max(np.abs(Ib))
        assert np.max(np.abs(A - Ab)) < 1e-9 * np.max(np.abs(Ib))
        Ip, _ = pinocchio_momentum_map(body, s)
        assert np.max(np.abs(I - Ip)) < 1e-12 * np.max(np.abs(Ip))
        _, origins, _ = body.link_poses(np.concatenate([[1.0, 0.0, 0.0, 0.0], s]))
        assert np.max(np.abs(-origins[body.links.root] - cb)) < 1e-12


@needs_biorbd
def test_a_quaternion_root_under_a_world_frame_is_the_same_body(tmp_path):
    """bioptim's quaternion variant (trunk_and_2arm_quaternion.bioMod) opens with a massless
    ``Global`` frame segment fixed to the world and turns the root by a quaternion: the frame is left
    out and the body is the Cardan one's, link for link (its arms, quaternion ball joints there, are
    refused below)."""
    text = TRUNK_AND_2ARM.replace("version 3\n", "version 3\n\nsegment Global\nendsegment\n", 1)
    text = text.replace("    rotations xyz\n", "    rotations q\n", 1)
    body = read_biomod(_write(tmp_path, text, "q.bioMod"))
    ref = read_biomod(_write(tmp_path, TRUNK_AND_2ARM))
    assert body.links == ref.links


@needs_biorbd
def test_limits_are_read_when_asked(tmp_path):
    text = TRUNK_AND_2ARM.replace("    rotations y\n    mass 3.106", "    rotations y\n    rangesQ -0.5 3.0\n"
                                  "    rangesQdot -12 12\n    mass 3.106", 1)
    path = _write(tmp_path, text)
    assert read_biomod(path).default_limits() is None
    table = read_biomod_table(path, limits=True)
    right, left = table[1], table[2]
    assert (right.lower, right.upper, right.velocity) == (-0.5, 3.0, 12.0)
    assert (left.lower, left.upper) == pytest.approx((-np.pi, np.pi))   # biorbd's default range


BAD = [
    # a quaternion (ball) joint below the root, a world-fixed segment with mass
    (TRUNK_AND_2ARM.replace("    rotations y\n", "    rotations q\n", 1), "bioMod segment 'RightArm'", "quaternion"),
    (TRUNK_AND_2ARM.replace("version 3\n", "version 3\n\nsegment Global\n    mass 1.0\n    inertia\n        0.1 0 0\n"
                            "        0 0.1 0\n        0 0 0.1\nendsegment\n", 1), "bioMod segment 'Global'",
     "fixed to the world"),
    # a translation below the root: refused, naming the segment
    (TRUNK_AND_2ARM.replace("parent Pelvis\n    RT 0 0 0 xyz 0.1875", "parent Pelvis\n    translations z\n"
                            "    RT 0 0 0 xyz 0.1875"), "bioMod segment 'LeftArm'", "translates"),
    # a root that is not free to turn
    (TRUNK_AND_2ARM.replace("    rotations xyz\n", "    rotations xy\n", 1), "bioMod segment 'Pelvis'", "not free"),
    (TRUNK_AND_2ARM.replace("translations xyz", "translations xz", 1), "bioMod segment 'Pelvis'", "translates"),
    # inertia not positive semi-definite or not a rigid body's, mass negative, inertia not symmetric
    (TRUNK_AND_2ARM.replace("0.00000 8.12771 0.00000", "0.00000 -8.12771 0.00000"), "bioMod segment 'Pelvis'",
     "positive semi-definite"),
    (TRUNK_AND_2ARM.replace("0.00000 0.00000 0.51802", "0.00000 0.00000 17.51802"), "bioMod segment 'Pelvis'",
     "I1 + I2 >= I3"),
    (TRUNK_AND_2ARM.replace("mass 3.106", "mass -3.106", 1), "bioMod segment 'RightArm'", "mass"),
    (TRUNK_AND_2ARM.replace("0.0910283 0.00000 0.00000\n        0.00000 0.0909983", "0.0910283 0.00100 0.00000\n"
                            "        0.00000 0.0909983", 1), "bioMod segment 'RightArm'", "not symmetric"),
]


@needs_biorbd
@pytest.mark.parametrize("text,field,words", BAD)
def test_bad_files_are_refused_naming_the_segment(tmp_path, text, field, words):
    path = _write(tmp_path, text)
    with pytest.raises(InvalidInputError) as e:
        read_biomod(path)
    assert e.value.field == field
    assert words in str(e.value)


@needs_biorbd
def test_reading_keeps_the_locale(tmp_path):
    """biorbd sets the locale to "C" (Python's default encoding then ASCII): the reader restores it."""
    import locale

    before = locale.setlocale(locale.LC_ALL)
    read_biomod(_write(tmp_path, TRUNK_AND_2ARM))
    assert locale.setlocale(locale.LC_ALL) == before


@needs_biorbd
def test_missing_file_and_bad_momentum(tmp_path):
    with pytest.raises(InvalidInputError) as e:
        read_biomod(tmp_path / "none.bioMod")
    assert e.value.field == "biomod"
    path = _write(tmp_path, TRUNK_AND_2ARM)
    with pytest.raises(InvalidInputError) as e:
        read_biomod(path, angular_momentum=(1.0, 2.0))
    assert e.value.field == "angular_momentum"


def test_without_biorbd_the_error_says_how_to_install(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "biorbd", None)
    with pytest.raises(ImportError, match=r"acroplan\[biomod\]"):
        read_biomod(_write(tmp_path, TRUNK_AND_2ARM))
