"""Free-floating bodies in 3-D (acroplan.families.spatial): the model and its independent check.

The momentum map is checked against Pinocchio's centroidal map at random configurations of
branched trees with off-axis centres of mass, joint axes in every direction, fixed joint rotations
and a massless link; a planar body described in 3-D against the planar family; the integrator's
Jacobian in the tangent space against finite differences; the quaternion's norm and the angular
momentum vector along integrations; the compiled integrator against the Pinocchio-driven
simulation.
"""

import math

import numpy as np
import pytest

from acroplan.core import backend
from acroplan.core.basis import Legendre
from acroplan.core.errors import InvalidInputError
from acroplan.families.planar import random_body as random_planar_body
from acroplan.families.spatial import SpatialBody, SpatialLink, SpatialLinkTable
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.zoo import box_inertia, random_body

pin = pytest.importorskip("pinocchio")


def _rotation(rng):
    return rot.to_matrix(rot.normalize(rng.normal(size=4)))


def _inertia(rng, mass):
    Q = _rotation(rng)
    return Q @ np.diag(box_inertia(mass, *rng.uniform(0.05, 0.6, 3))) @ Q.T


def general_tree(L=(0.0, 0.0, 0.0), seed=7):
    """A branched tree with every term of the model: off-axis centres of mass, joints anywhere,
    axes in every direction, fixed rotations, a two-axis joint through a massless link."""
    rng = np.random.default_rng(seed)
    links = [SpatialLink("trunk", None, 20.0, _inertia(rng, 20.0), com=tuple(rng.normal(size=3) * 0.1))]
    spec = [("arm", "trunk"), ("fore", "arm"), ("gimbal", "trunk"), ("leg", "gimbal")]
    for name, parent in spec:
        mass = 0.0 if name == "gimbal" else float(rng.uniform(1.0, 8.0))
        links.append(SpatialLink(name, parent, mass, np.zeros((3, 3)) if mass == 0 else _inertia(rng, mass),
                                 com=(0.0, 0.0, 0.0) if mass == 0 else tuple(rng.normal(size=3) * 0.2),
                                 joint=(0.0, 0.0, 0.0) if name == "leg" else tuple(rng.normal(size=3) * 0.4),
                                 axis=tuple(rng.normal(size=3)), rotation=_rotation(rng), joint_name=f"j_{name}"))
    return SpatialBody(links, L=L)


# ---------------------------------------------------------------------- the link table
def test_link_table_refuses_bad_links_by_name():
    ok = [SpatialLink("a", None, 1.0, (0.1, 0.1, 0.1)), SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.1), joint=(1, 0, 0))]
    cases = [
        (SpatialLink("b", "a", -1.0, (0.1, 0.1, 0.1)), "links[1].mass", "must be >= 0"),
        (SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.5)), "links[1].inertia", r"I1 \+ I2 >= I3"),
        (SpatialLink("b", "a", 1.0, [[0.1, 0.2, 0], [0, 0.1, 0], [0, 0, 0.1]]), "links[1].inertia", "not symmetric"),
        (SpatialLink("b", "a", 0.0, (0.1, 0.1, 0.1)), "links[1].inertia", "has no mass"),
        (SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.1), axis=(0, 0, 0)), "links[1].axis", "must not be zero"),
        (SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.1), rotation=np.diag([1.0, 1.0, -1.0])), "links[1].rotation",
         "not a rotation"),
        (SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.1), joint_name="qw"), "links[1].joint_name", "cannot name"),
    ]
    for bad, field, words in cases:
        with pytest.raises(InvalidInputError, match=rf"{field.replace('[', '.').replace(']', '.')}.*{words}"):
            SpatialLinkTable([ok[0], bad])
    with pytest.raises(InvalidInputError, match="links: has one link"):
        SpatialBody(ok[:1])
    with pytest.raises(InvalidInputError, match="L: must be three finite numbers"):
        SpatialBody(ok, L=(0.0, 1.0))
    # point masses on one line have no inertia about that line
    line = [SpatialLink("a", None, 1.0, (0, 0, 0)), SpatialLink("b", "a", 1.0, (0, 0, 0), joint=(1, 0, 0))]
    with pytest.raises(InvalidInputError, match="locked inertia at the zero shape is singular"):
        SpatialBody(line)


# ---------------------------------------------------------------------- the momentum map against Pinocchio
@pytest.mark.parametrize("make", [general_tree, lambda: random_body(3, 5, tree=True), lambda: random_body(4, 4)])
def test_momentum_map_equals_pinocchios_centroidal_map(make):
    body = make()
    from acroplan.families.spatial.pin import build_model

    pb = build_model(body)
    data = pb.model.createData()
    rng = np.random.default_rng(11)
    worst = 0.0
    for _ in range(10):
        x = np.concatenate([rot.normalize(rng.normal(size=4)), rng.uniform(-3, 3, body.n_inputs)])
        Ag = pin.computeCentroidalMap(pb.model, data, pb.configuration(x))
        I, A = body.momentum_map(x[4:])  # noqa: E741
        R = rot.to_matrix(x[:4])
        # angular rows: R I in the root's angular columns, R A in the joint columns
        worst = max(worst, np.max(np.abs(Ag[3:6, 3:6] - R @ I)), np.max(np.abs(Ag[3:6, pb.idx_v] - R @ A)))
        # the locked inertia is symmetric positive definite
        assert np.max(np.abs(I - I.T)) < 1e-13 and np.linalg.eigvalsh(I)[0] > 0
    assert worst < 1e-12
    # many shapes at once give the same
    S = rng.uniform(-3, 3, (body.n_inputs, 5))
    Iv, Av = body.momentum_map(S)
    for k in range(5):
        I1, A1 = body.momentum_map(S[:, k])
        assert np.max(np.abs(Iv[..., k] - I1)) < 1e-14 and np.max(np.abs(Av[..., k] - A1)) < 1e-14


def test_a_planar_body_in_3d_gives_the_planar_answer():
    """A planar body (joint axes along z, everything in the plane) described in 3-D: same locked
    inertia about z and coupling, and the same turn theta(T) for the same joint motion, the attitude
    staying a turn about z."""
    planar = random_planar_body(5, 4, P0=3.0)
    links = []
    for link in planar.links:
        links.append(SpatialLink(link.name, link.parent, link.mass, (link.inertia / 2, link.inertia / 2, link.inertia),
                                 com=(*link.com, 0.0), joint=(*link.joint, 0.0), axis=(0.0, 0.0, 1.0),
                                 joint_name=link.joint_name))
    body = SpatialBody(links, L=(0.0, 0.0, 3.0))
    rng = np.random.default_rng(2)
    for _ in range(5):
        s = rng.uniform(-2, 2, 3)
        I, A = body.momentum_map(s)  # noqa: E741
        Ip, ap = planar.momentum_map(s)
        assert abs(I[2, 2] - Ip) < 1e-12 and np.max(np.abs(A[2] - ap)) < 1e-12
        assert np.max(np.abs(I[2, :2])) < 1e-12 and np.max(np.abs(A[:2])) < 1e-12
    basis = Legendre(6)
    c = rng.normal(size=(3, 6))
    th0, s0, T = 0.4, rng.uniform(-1, 1, 3), 1.7
    yp, _ = backend.endpoint(planar, basis, np.concatenate([[th0], s0]), T, c)
    ys, _ = backend.endpoint(body, basis, np.concatenate([rot.exp([0, 0, th0]), s0]), T, c)
    assert rot.angle_between(ys[:4], rot.exp([0.0, 0.0, yp[0]])) < 1e-11
    assert np.max(np.abs(ys[4:] - yp[1:])) < 1e-13


# ---------------------------------------------------------------------- the state space
def test_diff_retract_and_the_tangent_jacobian():
    body = general_tree(L=(0.5, -1.0, 2.0))
    rng = np.random.default_rng(4)
    for _ in range(20):
        x = np.concatenate([rot.normalize(rng.normal(size=4)), rng.normal(size=4)])
        dx = np.concatenate([rng.normal(size=3) * 0.9, rng.normal(size=4)])
        assert np.allclose(body.diff(x, body.retract(x, dx)), dx, atol=1e-12)
        assert abs(np.linalg.norm(body.retract(x, dx)[:4]) - 1) < 1e-15
    # q and -q are the same attitude
    x = np.concatenate([rot.normalize(rng.normal(size=4)), np.zeros(4)])
    y = x.copy()
    y[:4] *= -1
    assert np.max(np.abs(body.diff(x, y))) < 1e-15
    # the endpoint Jacobian in the tangent space, against central differences of diff()
    basis = Legendre(6)
    x0 = np.concatenate([rot.normalize(rng.normal(size=4)), rng.normal(size=4)])
    c = rng.normal(size=(4, 6)) * 0.7
    y, J = backend.endpoint(body, basis, x0, 1.3, c)
    Jt = body.tangent_jacobian(y, J)
    assert Jt.shape == (7, 24)
    h = 1e-6
    cf = c.ravel()
    for k in (0, 5, 8, 13, 23):
        e = np.zeros_like(cf)
        e[k] = h
        yp, _ = backend.endpoint(body, basis, x0, 1.3, cf + e)
        ym, _ = backend.endpoint(body, basis, x0, 1.3, cf - e)
        fd = (body.diff(y, yp) - body.diff(y, ym)) / (2 * h)
        assert np.max(np.abs(fd - Jt[:, k])) < 1e-7


# ---------------------------------------------------------------------- invariants along integrations
def test_norm_and_angular_momentum_are_kept_along_integrations():
    L = np.array([1.5, -0.7, 2.2])
    body = general_tree(L=tuple(L))
    from acroplan.families.spatial.pin import build_model

    pb = build_model(body)
    data = pb.model.createData()
    rng = np.random.default_rng(9)
    basis = Legendre(6)
    x0 = np.concatenate([rot.normalize(rng.normal(size=4)), rng.normal(size=4)])
    c = rng.normal(size=(4, 6))
    T = 2.0
    sig = np.linspace(0, 1, 21)
    X = backend.sample(body, basis, x0, T, c, sig)
    U = (basis.matrix(sig) @ c.T).T
    assert np.max(np.abs(np.linalg.norm(X[:4], axis=0) - 1.0)) < 1e-13
    for k in range(sig.size):
        x, u = X[:, k], U[:, k]
        # the root's angular velocity from the model's own right-hand side ...
        qdot = body.rhs(x, u)[:4]
        omega = 2.0 * rot.qmul(rot.qconj(x[:4]), qdot)[1:]
        # ... gives Pinocchio's centroidal momentum (0, L): the linear part vanishes for the root's
        # linear velocity that keeps the centre of mass at rest
        Ag = pin.computeCentroidalMap(pb.model, data, pb.configuration(x))
        v = np.zeros(pb.model.nv)
        v[3:6] = omega
        v[pb.idx_v] = u
        lin = np.linalg.solve(Ag[:3, :3], -Ag[:3] @ v)
        v[:3] = lin
        h = Ag @ v
        assert np.max(np.abs(h[3:] - L)) < 1e-12


def test_the_pinocchio_check_reproduces_the_compiled_motion():
    from acroplan.families.spatial.check import pinocchio_segment, root_twist

    body = general_tree(L=(0.8, 0.3, -1.1))
    rng = np.random.default_rng(12)
    basis = Legendre(6)
    x0 = np.concatenate([rot.normalize(rng.normal(size=4)), rng.normal(size=4)])
    c = rng.normal(size=(4, 6))
    y, _ = backend.endpoint(body, basis, x0, 1.5, c)
    x = pinocchio_segment(body, x0, 1.5, basis, c)
    assert rot.angle_between(x[:4], y[:4]) < 1e-11 and np.max(np.abs(x[4:] - y[4:])) < 1e-13
    u = rng.normal(size=4)
    assert np.max(np.abs(root_twist(body, x0, u) - body.angular_velocity(x0, u))) < 1e-12


def test_the_checks_quaternion_rate_is_half_xi_times_omega_and_its_indices_are_views():
    """The Pinocchio check's right-hand side, written out (``quaternion_rate``), is
    :math:`\\tfrac12 \\Xi(q)\\Omega` (``rotations.xi``) to rounding, and is the quaternion product
    :math:`\\tfrac12 q \\otimes (0, \\Omega)`; a run of consecutive positions becomes a slice, any other
    index list stays as given."""
    from acroplan.families.spatial.check import _as_slice, quaternion_rate

    rng = np.random.default_rng(5)
    for _ in range(20):
        q, w = rng.normal(size=4), rng.normal(size=3)
        got = quaternion_rate(q.tolist(), w.tolist())
        assert np.max(np.abs(got - 0.5 * rot.xi(q) @ w)) < 1e-15 * (1 + np.abs(q).sum() * np.abs(w).sum())
        a, b = q, np.concatenate([[0.0], w])  # the Hamilton product q (x) (0, w), written independently
        prod = np.array([a[0] * b[0] - a[1:] @ b[1:], *(a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:]))])
        assert np.max(np.abs(got - 0.5 * prod)) < 1e-14
    assert _as_slice([6, 7, 8, 9]) == slice(6, 10) and _as_slice([3, 5]) == [3, 5] and _as_slice([]) == []


# ---------------------------------------------------------------------- URDF
def test_urdf_round_trip_and_refusals(tmp_path):
    from acroplan.families.spatial.urdf import read_link_table, to_urdf

    body = general_tree()
    path = tmp_path / "tree.urdf"
    path.write_text(to_urdf(body))
    table = read_link_table(path)
    again = SpatialBody(table)
    rng = np.random.default_rng(3)
    for _ in range(3):
        s = rng.uniform(-2, 2, 4)
        I0, A0 = body.momentum_map(s)
        I1, A1 = again.momentum_map(s)
        assert np.max(np.abs(I0 - I1)) < 1e-12 and np.max(np.abs(A0 - A1)) < 1e-12
    assert again.links.joint_names == body.links.joint_names
    bad = to_urdf(body).replace('type="continuous"', 'type="prismatic"', 1)
    path.write_text(bad.replace("<axis", '<limit lower="-1" upper="1" effort="1" velocity="1"/>\n    <axis', 1))
    with pytest.raises(InvalidInputError, match="urdf joint 'j_arm'.*not a revolute joint"):
        read_link_table(path)


# ---------------------------------------------------------------------- rotations
def test_yeadon_euler_angles():
    # somersault about x, then tilt about y', then twist about z'': R = Rx Ry Rz
    q = rot.from_euler([30.0, 20.0, 90.0])
    R = rot.to_matrix(q)
    Rx = rot.to_matrix(rot.exp([math.radians(30), 0, 0]))
    Ry = rot.to_matrix(rot.exp([0, math.radians(20), 0]))
    Rz = rot.to_matrix(rot.exp([0, 0, math.radians(90)]))
    assert np.max(np.abs(R - Rx @ Ry @ Rz)) < 1e-15
    assert np.allclose(rot.to_euler(q), [30.0, 20.0, 90.0], atol=1e-12)
    assert np.allclose(rot.as_quaternion({"euler_deg": [30, 20, 90]}), q, atol=1e-15)
    assert np.allclose(rot.as_quaternion({"rotvec_deg": [0, 0, 180]}), [0, 0, 0, 1], atol=1e-15)
    with pytest.raises(InvalidInputError, match="attitude: has norm 2, not 1"):
        rot.as_quaternion([2.0, 0, 0, 0])


def test_a_bases_values_at_one_point_are_matrix_and_integral_bit_for_bit():
    """Issue #22 (the falling cat's command line): the Pinocchio check evaluates the joint rates and
    angles at each call of its ODE's right-hand side by ``basis.at(s)``, a single pass on Python
    floats for the Legendre basis; its numbers are those of ``matrix(s)`` and ``integral(s)``
    exactly (and so their products with the coefficients), for every size and points inside and
    outside [0, 1]; the monomial basis gives its own two calls."""
    from acroplan.core.basis import Monomial

    rng = np.random.default_rng(22)
    for n in range(1, 19):
        for basis in (Legendre(n), Monomial(n)):
            c = rng.normal(size=(n, 3))
            for s in [0.0, 0.5, 1.0, *rng.uniform(-0.3, 1.3, 200)]:
                s = np.float64(s)
                V, B = basis.at(s)
                assert V.shape == B.shape == (1, n)
                assert np.array_equal(V, basis.matrix(s)) and np.array_equal(B, basis.integral(s))
                assert np.array_equal(V @ c, basis.matrix(s) @ c) and np.array_equal(B @ c, basis.integral(s) @ c)
