"""Joint torques of spatial bodies by Pinocchio's inverse dynamics (acroplan.families.spatial.effort).

* a planar body described in 3-D (joint axes along z) gives the planar family's torques and
  Jacobian (PlanarTorque);
* the free-flyer part of RNEA vanishes along a simulated motion with L != 0, the root's angular
  velocity is the model's, and the attitude matters (the torques at a frozen attitude differ);
* a forward simulation of the full equations of motion (free-flyer root free, Pinocchio's ABA,
  DOP853 at rtol = atol = 1e-12), driven by the computed joint torques alone from the planned
  initial state and velocities, reproduces the motion (attitude and joints) to 1e-8, with L
  conserved and the centre of mass at rest; a 1% wrong torque does not;
* the power integrates to the change of kinetic energy;
* the partials (attitude, joints, rates, accelerations) on a branched tree numbered differently
  breadth first and depth first, and the Jacobian in the coefficients, against central finite
  differences.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import acroplan
from acroplan.core.basis import Legendre
from acroplan.core.errors import InvalidInputError
from acroplan.core.system import joint_inputs, torque_model_of
from acroplan.families.planar import random_body as random_planar_body
from acroplan.families.spatial import SpatialBody, SpatialLink
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.effort import (SpatialTorque, _model, attitude_samples,
                                              inverse_dynamics, register)
from acroplan.families.spatial.zoo import box_inertia, random_segment

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml)
pytestmark = pytest.mark.xdist_group("test_spatial_effort")

pin = pytest.importorskip("pinocchio")

NODES = np.linspace(0.0, 1.0, 41)

register()  # until families/spatial/__init__.py imports the module


@pytest.fixture(scope="module")
def segment():
    """A simulated motion of a random three-link chain with angular momentum L != 0."""
    p = random_segment(np.random.default_rng(3), 3, momentum=True)
    assert np.linalg.norm(p.body.L) > 1.0
    return p.body, Legendre(6), p.x0, p.T, p.coefficients


def branched(L=(1.0, -2.0, 0.5), seed=7):
    """A branched tree whose breadth-first and depth-first numberings differ, with off-axis centres
    of mass, joint axes in every direction, fixed rotations and a massless link (a two-axis joint)."""
    rng = np.random.default_rng(seed)

    def turn():
        return rot.to_matrix(rot.normalize(rng.normal(size=4)))

    def inertia(mass):
        Q = turn()
        return Q @ np.diag(box_inertia(mass, *rng.uniform(0.05, 0.6, 3))) @ Q.T

    links = [SpatialLink("trunk", None, 20.0, inertia(20.0), com=tuple(rng.normal(size=3) * 0.1))]
    for name, parent in [("arm", "trunk"), ("fore", "arm"), ("gimbal", "trunk"), ("leg", "gimbal")]:
        mass = 0.0 if name == "gimbal" else float(rng.uniform(1.0, 8.0))
        links.append(SpatialLink(name, parent, mass, np.zeros((3, 3)) if mass == 0 else inertia(mass),
                                 com=(0.0, 0.0, 0.0) if mass == 0 else tuple(rng.normal(size=3) * 0.2),
                                 joint=(0.0, 0.0, 0.0) if name == "leg" else tuple(rng.normal(size=3) * 0.4),
                                 axis=tuple(rng.normal(size=3)), rotation=turn(), joint_name=f"j_{name}"))
    return SpatialBody(links, L=L)


def spatial_twin(planar, P0):
    """A planar body described in 3-D: joint axes along z, everything in the plane, L = (0, 0, P0)."""
    links = [SpatialLink(k.name, k.parent, k.mass, (k.inertia / 2, k.inertia / 2, k.inertia), com=(*k.com, 0.0),
                         joint=(*k.joint, 0.0), axis=(0.0, 0.0, 1.0), joint_name=k.joint_name) for k in planar.links]
    return SpatialBody(links, L=(0.0, 0.0, P0))


# ------------------------------------------------------------------------------ (a) planar bodies
def test_a_planar_body_in_3d_gives_the_planar_torques_and_jacobian():
    planar = random_planar_body(5, 3, P0=3.0)  # three links: the structure of the other tests (one compilation)
    body = spatial_twin(planar, 3.0)
    rng = np.random.default_rng(2)
    basis, T = Legendre(6), 1.7
    c = rng.normal(size=(2, 6))
    th0, s0 = 0.4, rng.uniform(-1, 1, 2)
    tau_p, jac_p = planar.torque_model()(planar, basis, np.r_[th0, s0], T, c, NODES)
    tau_s, jac_s = body.torque_model()(body, basis, np.r_[rot.exp([0.0, 0.0, th0]), s0], T, c, NODES)
    assert np.abs(tau_p).max() > 1.0  # a motion with real torques
    assert np.abs(tau_s - tau_p).max() <= 1e-10 * np.abs(tau_p).max()
    assert np.abs(jac_s - jac_p).max() <= 1e-10 * np.abs(jac_p).max()


# ------------------------------------------------------------------------------ (b) the free flyer's part
def test_free_flyer_part_vanishes_and_the_root_turns_as_the_model_says(segment):
    body, basis, x0, T, c = segment
    tm = body.torque_model()
    out = tm.evaluate(body, basis, x0, T, c, NODES)
    assert out.tau.shape == (2, NODES.size) and out.root_residual.shape == (6, NODES.size)
    assert np.abs(out.tau).max() > 1.0
    assert np.abs(out.root_residual).max() <= 1e-9
    # the root's angular velocity from Pinocchio's centroidal map is the model's I^-1 (R^T L - A u)
    att, q, u, _ = tm.motion(body, basis, x0, T, c, NODES)
    omega = np.array([body.angular_velocity(np.r_[att[:, k], q[:, k]], u[:, k]) for k in range(NODES.size)]).T
    assert np.abs(out.root_velocity[3:] - omega).max() <= 1e-12 * np.abs(omega).max()
    # the torques depend on the attitude: held at its start, they are wrong
    frozen = inverse_dynamics(body, x0[:4], *tm.motion(body, basis, x0, T, c, NODES)[1:])
    assert np.abs(frozen.tau - out.tau).max() > 1e-2 * np.abs(out.tau).max()
    assert np.abs(frozen.root_residual).max() <= 1e-9  # (which the residual alone cannot see)


def test_free_flyer_part_vanishes_on_a_branched_tree():
    body = branched()
    rng = np.random.default_rng(4)
    att = rot.normalize(rng.normal(size=(4, 7)))
    q, u, du = (rng.normal(size=(4, 7)) for _ in range(3))
    out = inverse_dynamics(body, att, q, u, du)
    assert np.abs(out.tau).max() > 0.1
    assert np.abs(out.root_residual).max() <= 1e-9


def test_root_part_would_not_vanish_without_the_momentum(segment):
    """The residual is a real check: with the root at rest (no momentum map) it is large."""
    body, basis, x0, T, c = segment
    att, q, u, du = body.torque_model().motion(body, basis, x0, T, c, [0.5])
    pb = _model(body.links)
    cfg = pb.configuration(np.r_[att[:, 0], q[:, 0]])
    v, a = np.zeros(pb.model.nv), np.zeros(pb.model.nv)
    v[pb.idx_v], a[pb.idx_v] = u[:, 0], du[:, 0]
    assert np.abs(pin.rnea(pb.model, pb.model.createData(), cfg, v, a)[:6]).max() > 1e-1


# ------------------------------------------------------------------------------ (c) forward dynamics
def free_simulation(body, basis, x0, T, c, t_eval, scale=None):
    """The full equations of motion of the free body (free-flyer root free: position, attitude),
    Pinocchio's ABA driven by the computed joint torques alone, open loop, DOP853 at rtol = atol =
    1e-12, from the planned state and the velocities the momentum implies.

    The torques at time t need the planned attitude there: it is integrated alongside (its own four
    states, q' = q (0, Omega)/2 with Omega from the inverse dynamics of the planned motion), never
    from the simulated body's state."""
    pb = _model(body.links)
    model, data = pb.model, pb.model.createData()
    m, nq, nv = body.n_inputs, pb.model.nq, pb.model.nv
    jc = pb.idx_v
    scale = np.ones(m) if scale is None else scale
    s0 = np.asarray(x0, dtype=float)[4:]

    def planned(t, qp):
        sig = np.array([t / T])
        q = s0 + T * (basis.integral(sig) @ c.T)[0]
        u = (basis.matrix(sig) @ c.T)[0]
        du = (basis.matrix(sig, 1) @ c.T)[0] / T
        return inverse_dynamics(body, qp, q, u, du)

    def rhs(t, y):
        qp, cfg, v = y[:4], y[4:4 + nq].copy(), y[4 + nq:]
        ref = planned(t, qp)
        cfg[3:7] /= np.linalg.norm(cfg[3:7])
        f = np.zeros(nv)
        f[jc] = ref.tau[:, 0] * scale
        acc = pin.aba(model, data, cfg, v, f)
        x, y_, z, w = cfg[3:7]
        R = rot.to_matrix([w, x, y_, z])
        quat_dot = 0.5 * rot.xi([w, x, y_, z]) @ v[3:6]  # [w, x, y, z] order
        cfg_dot = np.zeros(nq)
        cfg_dot[:3] = R @ v[:3]
        cfg_dot[3:7] = np.r_[quat_dot[1:], quat_dot[0]]
        cfg_dot[pb.idx_q] = v[jc]
        return np.concatenate([0.5 * rot.xi(qp) @ ref.root_velocity[3:, 0], cfg_dot, acc])

    start = planned(0.0, x0[:4])
    v0 = np.zeros(nv)
    v0[:6] = start.root_velocity[:, 0]
    v0[jc] = (basis.matrix(np.array([0.0])) @ c.T)[0]
    y0 = np.concatenate([x0[:4], pb.configuration(x0), v0])
    sol = solve_ivp(rhs, (0.0, T), y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=t_eval)
    assert sol.success, sol.message
    states, momenta = [], []
    for y in sol.y.T:
        cfg = y[4:4 + nq].copy()
        cfg[3:7] /= np.linalg.norm(cfg[3:7])
        states.append(np.r_[cfg[6], cfg[3:6], cfg[pb.idx_q]])
        h = pin.computeCentroidalMomentum(model, data, cfg, y[4 + nq:])
        momenta.append(np.r_[h.linear, h.angular])
    return np.array(states).T, np.array(momenta).T


def test_forward_simulation_driven_by_the_torques_reproduces_the_motion(segment):
    body, basis, x0, T, c = segment
    t = np.linspace(0.0, T, 11)
    states, momenta = free_simulation(body, basis, x0, T, c, t)
    planned = attitude_samples(body, basis, x0, T, c, t / T)  # the compiled integrator, (4 + m, 11)
    angle = max(rot.angle_between(states[:4, k], planned[:4, k]) for k in range(t.size))
    joints = np.abs(states[4:] - planned[4:]).max()
    assert rot.angle_between(planned[:4, 0], planned[:4, -1]) > 0.5  # the body turns
    assert angle <= 1e-8 and joints <= 1e-8
    Lnorm = np.linalg.norm(body.L)
    assert np.abs(momenta[3:] - np.asarray(body.L)[:, None]).max() <= 1e-9 * Lnorm  # L conserved
    assert np.abs(momenta[:3]).max() <= 1e-9 * Lnorm  # the centre of mass at rest


def test_a_wrong_torque_does_not_reproduce_the_motion(segment):
    """The forward check can fail: 1% more torque on one joint misses by far more than 1e-8."""
    body, basis, x0, T, c = segment
    states, _ = free_simulation(body, basis, x0, T, c, [T], scale=np.r_[1.01, 1.0])
    planned = attitude_samples(body, basis, x0, T, c, [1.0])
    miss = max(rot.angle_between(states[:4, 0], planned[:4, 0]), np.abs(states[4:, 0] - planned[4:, 0]).max())
    assert miss > 1e-5


def test_power_integrates_to_the_change_of_kinetic_energy(segment):
    body, basis, x0, T, c = segment
    tm = body.torque_model()
    xg, wg = np.polynomial.legendre.leggauss(48)
    s, w = (xg + 1) / 2, wg / 2
    att, q, u, du = tm.motion(body, basis, x0, T, c, s)
    work = T * float(np.sum(inverse_dynamics(body, att, q, u, du).tau * u, axis=0) @ w)
    pb = _model(body.links)
    data = pb.model.createData()
    E = []
    for end in (0.0, 1.0):
        att, q, u, du = tm.motion(body, basis, x0, T, c, [end])
        v = np.zeros(pb.model.nv)
        v[:6] = inverse_dynamics(body, att, q, u, du).root_velocity[:, 0]
        v[pb.idx_v] = u[:, 0]
        E.append(pin.computeKineticEnergy(pb.model, data, pb.configuration(np.r_[att[:, 0], q[:, 0]]), v))
    assert abs(E[1] - E[0]) > 1e-1  # the motion changes the energy
    assert abs(work - (E[1] - E[0])) <= 1e-9 * max(1.0, abs(E[1] - E[0]))


# ------------------------------------------------------------------------------ (d) derivatives
def test_partials_on_a_branched_tree_against_central_differences():
    """Attitude, joints, rates and accelerations; the tree is numbered differently breadth first and
    depth first (Pinocchio's derivatives need the depth-first numbering)."""
    body = branched()
    assert body.links.topological_order() == (0, 1, 2, 3, 4)  # depth first (breadth first: 0, 1, 3, 2, 4)
    assert [list(_model(body.links).model.names)[j] for j in _model(body.links).joint_ids[1:]] == \
        ["j_arm", "j_fore", "j_gimbal", "j_leg"]  # Pinocchio's joints in depth-first order
    rng = np.random.default_rng(1)
    m = body.n_inputs
    att = rot.normalize(rng.normal(size=4))
    x = rng.normal(size=3 * m)
    out = inverse_dynamics(body, att, *np.split(x, 3), derivatives=True)
    h = 1e-6
    fd = np.empty((m, 3 + 3 * m))
    for i in range(3):
        e = np.zeros(3)
        e[i] = h
        fd[:, i] = (inverse_dynamics(body, rot.qmul(att, rot.exp(e)), *np.split(x, 3)).tau
                    - inverse_dynamics(body, rot.qmul(att, rot.exp(-e)), *np.split(x, 3)).tau)[:, 0] / (2 * h)
    for i in range(3 * m):
        e = np.zeros(3 * m)
        e[i] = h
        fd[:, 3 + i] = (inverse_dynamics(body, att, *np.split(x + e, 3)).tau
                        - inverse_dynamics(body, att, *np.split(x - e, 3)).tau)[:, 0] / (2 * h)
    assert np.abs(fd[:, :3]).max() > 0.1  # the attitude matters (L != 0)
    assert np.abs(out.partials[:, 0] - fd).max() <= 1e-6 * np.abs(fd).max()


def test_jacobian_against_central_finite_differences(segment):
    body, basis, x0, T, c = segment
    tm = body.torque_model()
    s = np.linspace(0.0, 1.0, 11)
    tau, jac = tm(body, basis, x0, T, c, s)
    m, n = c.shape
    assert tau.shape == (m, s.size) and jac.shape == (m, s.size, m * n)
    fd = np.empty_like(jac)
    h = 1e-6
    for k in range(m * n):
        e = np.zeros(m * n)
        e[k] = h
        fd[:, :, k] = (tm.evaluate(body, basis, x0, T, c + e.reshape(m, n), s).tau
                       - tm.evaluate(body, basis, x0, T, c - e.reshape(m, n), s).tau) / (2 * h)
    assert np.abs(jac).max() > 1.0
    assert np.abs(jac - fd).max() <= 1e-6 * np.abs(jac).max()
    assert np.array_equal(tm.torques(body, basis, x0, T, c, s), tau)  # the torques alone, without the Jacobian
    # the attitude's part is not negligible: without it the Jacobian is wrong
    att, q, u, du, dtheta = tm.motion(body, basis, x0, T, c, s, jacobian=True)
    P = inverse_dynamics(body, att, q, u, du, derivatives=True).partials
    assert np.abs(np.einsum("pka,kac->pkc", P[:, :, :3], dtheta)).max() > 1e-2 * np.abs(jac).max()


def test_samples_in_any_order_and_at_the_start():
    p = random_segment(np.random.default_rng(3), 3, momentum=True)
    basis = Legendre(6)
    s = np.array([0.7, 0.0, 0.3, 0.7, 1.0])
    X = attitude_samples(p.body, basis, p.x0, p.T, p.coefficients, s)
    ref = attitude_samples(p.body, basis, p.x0, p.T, p.coefficients, np.sort(np.unique(s)))
    for k, v in enumerate(s):
        assert np.array_equal(X[:, k], ref[:, list(np.sort(np.unique(s))).index(v)])
    assert np.array_equal(X[:, 1], p.x0)
    assert np.abs(X[:, -1] - p.x1).max() <= 1e-12
    with pytest.raises(InvalidInputError) as e:
        attitude_samples(p.body, basis, p.x0, p.T, p.coefficients, [-0.1, 0.5])
    assert e.value.field == "s"


# ------------------------------------------------------------------------------ the model object
def test_torque_model_hook_and_refusals(segment):
    body, basis, x0, T, c = segment
    tm = body.torque_model()
    assert isinstance(tm, SpatialTorque) and tm.joint_names == ("q1", "q2")
    assert torque_model_of(body) == (tm, None)
    assert joint_inputs(body, tm) == (0, 1)
    assert "spatial bodies" in SpatialTorque().unsupported(acroplan.Acrobot.example())
    other = branched()
    assert "joints" in tm.unsupported(other)
    assert SpatialTorque().unsupported(other) is None
    with pytest.raises(InvalidInputError) as e:
        tm(acroplan.Acrobot.example(), basis, x0, T, c, NODES)
    assert e.value.field == "system"
    with pytest.raises(InvalidInputError) as e:
        tm(body, basis, x0, T, np.zeros((2, 5)), NODES)
    assert e.value.field == "c" and e.value.fix
    with pytest.raises(InvalidInputError) as e:
        tm(body, basis, x0, -1.0, c, NODES)
    assert e.value.field == "T"
    with pytest.raises(InvalidInputError) as e:
        tm(body, basis, x0[1:], T, c, NODES)
    assert e.value.field == "x0"
    with pytest.raises(InvalidInputError) as e:
        inverse_dynamics(body, [1.0, 0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [0.0, 0.0])
    assert e.value.field == "attitude"
    with pytest.raises(InvalidInputError) as e:
        inverse_dynamics(body, [1.0, 0.0, 0.0, 0.0], [0.0], [0.0, 0.0], [0.0, 0.0])
    assert e.value.field == "q"
    with pytest.raises(InvalidInputError) as e:
        inverse_dynamics(body, [1.0, 0.0, 0.0, 0.0], [0.0, 0.0], np.zeros((2, 3)), np.zeros((2, 2)))
    assert e.value.field == "u"
    with pytest.raises(InvalidInputError) as e:
        inverse_dynamics(acroplan.Acrobot.example(), [1.0, 0.0, 0.0, 0.0], [0.0], [0.0], [0.0])
    assert e.value.field == "body"


# ------------------------------------------------------------------------------ the compiled recursion
def test_compiled_newton_euler_equals_pinocchio_with_its_partials():
    """families/spatial/dynamics.py's recursion, compiled, against Pinocchio's RNEA on the branched
    tree (fixed rotations, a massless gimbal, axes in every direction) and a random chain, at random
    states: the torques to 1e-12 relative; its partials in (s, u, du) equal Pinocchio's analytic
    ones, and in lambda = R^T L they give Pinocchio's attitude partials through d lambda =
    [lambda]x d theta, to 1e-9."""
    from acroplan.families.spatial.dynamics import joint_torques

    rng = np.random.default_rng(11)
    for body in (branched(), random_segment(np.random.default_rng(5), 4, momentum=True).body):
        m, K = body.n_inputs, 9
        att = rot.normalize(rng.normal(size=(4, K)))
        q, u, du = (rng.normal(size=(m, K)) for _ in range(3))
        lam = np.stack([rot.to_matrix(att[:, k]).T @ np.asarray(body.L) for k in range(K)], axis=1)
        ref = inverse_dynamics(body, att, q, u, du, derivatives=True)
        tau, P = joint_torques(body.links, q, u, du, lam, derivatives=True)
        assert np.abs(ref.tau).max() > 1.0
        assert np.abs(tau - ref.tau).max() <= 1e-12 * np.abs(ref.tau).max()
        assert np.array_equal(joint_torques(body.links, q, u, du, lam), tau)
        scale = np.abs(ref.partials).max()
        assert np.abs(P[:, :, :3 * m] - ref.partials[:, :, 3:]).max() <= 1e-9 * scale
        skew = np.stack([np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]]) for v in lam.T])
        dtheta = np.einsum("pka,kab->pkb", P[:, :, 3 * m:], skew)  # d lambda / d theta = [lambda]x
        assert np.abs(dtheta - ref.partials[:, :, :3]).max() <= 1e-9 * scale
        assert np.abs(ref.partials[:, :, :3]).max() > 1e-3 * scale  # the momentum's part is there


def test_the_torque_model_by_collocation_equals_the_taylor_route(segment):
    """The model's call (the compiled recursion at the collocation's momentum, its exact Jacobian)
    against evaluate() (the Taylor integrator's attitude and variational equations, Pinocchio's
    derivatives) on the L != 0 segment: torques to 1e-12 and the Jacobian to 1e-9, relative; and the
    collocation's momentum at the nodes against the attitude the cut collocation gives there."""
    from acroplan.core.objectives import gauss
    from acroplan.families.spatial.collocation import momentum_samples, sample

    body, basis, x0, T, c = segment
    tm = body.torque_model()
    s = gauss(4, 24)[0]
    tau, jac = tm(body, basis, x0, T, c, s)
    ref = tm.evaluate(body, basis, x0, T, c, s, derivatives=True)
    assert np.abs(tau - ref.tau).max() <= 1e-12 * np.abs(ref.tau).max()
    assert np.abs(jac - ref.partials).max() <= 1e-9 * np.abs(ref.partials).max()
    lam = momentum_samples(body, basis, x0, T, c, s)
    X = sample(body, basis, x0, T, c, s)
    want = np.stack([rot.to_matrix(X[:4, k]).T @ np.asarray(body.L) for k in range(s.size)], axis=1)
    assert np.abs(lam - want).max() <= 1e-13 * np.linalg.norm(body.L)


def test_torque_values_alone_are_the_torques_of_the_model_with_its_jacobian(segment):
    """``torque_values`` (what the optimal plans' dense checks call: the model's ``torques``, no
    Jacobian) gives the torques of ``call_torque`` (the model's call, with the Jacobian) on 1025
    points, to rounding (1e-12 of the largest): two code paths of the compiled recursion at the
    momentum's collocation, one with the derivatives' sweep."""
    from acroplan.core.objectives import call_torque, torque_values

    body, basis, x0, T, c = segment
    model = torque_model_of(body)[0]
    s = np.linspace(0.0, 1.0, 1025)
    tau, jac = call_torque(model, body, basis, x0, T, np.ravel(c), s)
    alone = torque_values(model, body, basis, x0, T, np.ravel(c), s)
    assert jac.shape == tau.shape + (np.size(c),)
    assert alone.shape == tau.shape
    assert np.max(np.abs(alone - tau)) <= 1e-12 * np.max(np.abs(tau))
