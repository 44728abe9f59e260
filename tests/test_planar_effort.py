"""Joint torques of planar bodies by Pinocchio's inverse dynamics (acroplan.families.planar.effort).

* the two-link body built from the acrobot's physical parameters gives the acrobot's closed-form
  torque (Routh, cyclic theta) along planned motions, and its Jacobian;
* a forward simulation of the full equations of motion (root free, Pinocchio's ABA, DOP853 at
  rtol 1e-12), driven by the computed joint torques alone from the planned initial state and
  velocities, reproduces the planned motion to 1e-8, with the momentum conserved and the centre of
  mass at rest along it;
* the root's part of RNEA vanishes (planar root and free flyer), the root rate is the model's;
* the power integrates to the change of kinetic energy (Pinocchio's);
* the Jacobian in the input coefficients against central finite differences.
"""

from __future__ import annotations

import dataclasses
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import acroplan
from acroplan.core.basis import Legendre
from acroplan.core.errors import InvalidInputError
from acroplan.families.acrobot.effort import AcrobotTorque, joint_torque
from acroplan.families.planar import PlanarBody, three_rods
from acroplan.families.planar.effort import PlanarTorque, inverse_dynamics
from acroplan.families.planar.pin import build_model
from acroplan.families.planar.zoo import random_segment
from acroplan.zoo import random_segment as acrobot_segment

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml)
pytestmark = pytest.mark.xdist_group("test_planar_effort")

pin = pytest.importorskip("pinocchio")

NODES = np.linspace(0.0, 1.0, 41)


def planar_twin(robot) -> PlanarBody:
    """The acrobot as a two-link planar body (root: the leg; joint phi: leg to torso)."""
    return PlanarBody.from_acrobot_physical(**dataclasses.asdict(robot.physical))


@pytest.fixture(scope="module")
def acrobot_plans():
    """Three planned acrobot motions (random physical bodies, P0 of either sign)."""
    rng = np.random.default_rng(2024)
    out = []
    for _ in range(3):
        p = acrobot_segment(rng)
        r = acroplan.plan(p.robot, conditions="free", verify=False, **p.plan_kwargs())
        assert r.success, r.message
        out.append((p.robot, r))
    return out


@pytest.fixture(scope="module")
def planar_plan():
    """A planned motion of a random three-link chain with angular momentum (P0 != 0)."""
    p = random_segment(np.random.default_rng(17), 3, momentum=True)
    r = acroplan.plan(p.body, conditions="free", verify=False, **p.plan_kwargs())
    assert r.success, r.message
    assert abs(p.body.P0) > 0.5
    return p.body, r


def segment_args(result):
    seg = result.segments[0]
    return result.basis_for(seg), seg.start, seg.t1 - seg.t0, seg.basis_coefficients


# ------------------------------------------------------------------------------ (a) the acrobot
def test_two_link_body_gives_the_acrobots_closed_form_torque(acrobot_plans):
    for robot, r in acrobot_plans:
        body = planar_twin(robot)
        basis, x0, T, c = segment_args(r)
        tau_a, jac_a = AcrobotTorque()(robot, basis, x0, T, c, NODES)
        tau_p, jac_p = body.torque_model()(body, basis, x0, T, c, NODES)
        scale = max(1.0, np.abs(tau_a).max())
        assert np.abs(tau_a).max() > 1e-2  # a motion with real torques
        assert np.abs(tau_p - tau_a).max() <= 1e-10 * scale
        assert np.abs(jac_p - jac_a).max() <= 1e-10 * max(1.0, np.abs(jac_a).max())
        # and joint_torque from phi, u, du directly (the planar model's motion)
        q, u, du = body.torque_model().motion(body, basis, x0, T, c, NODES)
        assert np.abs(joint_torque(robot, q[0], u[0], du[0]) - tau_p[0]).max() <= 1e-10 * scale


def test_two_link_root_rate_is_the_acrobots(acrobot_plans):
    robot, r = acrobot_plans[0]
    body = planar_twin(robot)
    basis, x0, T, c = segment_args(r)
    q, u, du = body.torque_model().motion(body, basis, x0, T, c, NODES)
    out = inverse_dynamics(body, q, u, du)
    theta_dot = (robot.P0 - robot.k(q[0]) * u[0]) / robot.h(q[0])  # text eq. (2)
    assert np.abs(out.theta_dot - theta_dot).max() <= 1e-12 * max(1.0, np.abs(theta_dot).max())


# ------------------------------------------------------------------------------ (b) forward dynamics
def free_simulation(body, basis, x0, T, c, t_eval):
    """The full equations of motion of the free body (planar root free: x, y, theta), Pinocchio's
    ABA driven by the computed joint torques alone (open loop, as functions of time), DOP853 at
    rtol = atol = 1e-12, from the planned state and the velocities the momentum implies."""
    pb = build_model(body, "planar")
    model = pb.model
    model.gravity = pin.Motion.Zero()
    data = model.createData()
    rc, jc = pb.root_columns, pb.joint_columns
    m, nv = body.n_inputs, model.nv
    tm = body.torque_model()

    def torque(t):
        q, u, du = tm.motion(body, basis, x0, T, c, [t / T])
        return inverse_dynamics(body, q, u, du).tau[:, 0]

    def config(y):
        cfg = pb.configuration(np.concatenate([[y[2]], y[3:3 + m]]))
        cfg[:2] = y[:2]
        return cfg

    def rhs(t, y):
        th, v = y[2], y[3 + m:]
        cfg = config(y)
        f = np.zeros(nv)
        f[jc] = torque(t)
        acc = pin.aba(model, data, cfg, v, f)
        ct, st = np.cos(th), np.sin(th)
        return np.concatenate([[ct * v[0] - st * v[1], st * v[0] + ct * v[1], v[2]], v[jc], acc])

    q, u, du = tm.motion(body, basis, x0, T, c, [0.0])
    start = inverse_dynamics(body, q, u, du)
    v0 = np.zeros(nv)
    v0[rc] = start.root_velocity[:, 0]
    v0[jc] = u[:, 0]
    y0 = np.concatenate([[0.0, 0.0, x0[0]], x0[1:], v0])
    sol = solve_ivp(rhs, (0.0, T), y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=t_eval)
    assert sol.success, sol.message
    momenta = []
    for y in sol.y.T:
        h = pin.computeCentroidalMomentum(model, data, config(y), y[3 + m:])
        momenta.append([h.linear[0], h.linear[1], h.linear[2], h.angular[0], h.angular[1], h.angular[2]])
    return sol, np.array(momenta)


def check_forward(body, result):
    basis, x0, T, c = segment_args(result)
    t = np.linspace(0.0, T, 21)
    sol, momenta = free_simulation(body, basis, x0, T, c, t)
    planned = result.evaluate(t).states  # theta and the joints, (n, 21)
    m = body.n_inputs
    simulated = sol.y[2:3 + m]
    assert np.abs(simulated - planned).max() <= 1e-8
    P0 = body.P0
    assert np.abs(momenta[:, 5] - P0).max() <= 1e-9 * max(1.0, abs(P0))  # angular momentum conserved
    assert np.abs(momenta[:, :5]).max() <= 1e-9 * max(1.0, abs(P0))  # the centre of mass at rest
    return np.abs(simulated - planned).max()


def test_forward_simulation_driven_by_the_torques_reproduces_a_three_link_plan(planar_plan):
    body, r = planar_plan
    check_forward(body, r)


def test_forward_simulation_reproduces_an_acrobot_plan_on_its_twin(acrobot_plans):
    robot, r = acrobot_plans[1]
    body = planar_twin(robot)
    basis, x0, T, c = segment_args(r)
    # the acrobot's plan is a motion of its twin: same state (theta, phi), same input
    t = np.linspace(0.0, T, 21)
    sol, momenta = free_simulation(body, basis, x0, T, c, t)
    planned = r.evaluate(t).states
    assert np.abs(sol.y[2:4] - planned).max() <= 1e-8
    assert np.abs(momenta[:, 5] - robot.P0).max() <= 1e-9 * max(1.0, abs(robot.P0))


def test_a_wrong_torque_does_not_reproduce_the_plan(planar_plan):
    """The forward check can fail: 1% more torque on one joint misses the plan by far more than 1e-8."""
    body, r = planar_plan
    basis, x0, T, c = segment_args(r)
    pb = build_model(body, "planar")
    model = pb.model
    model.gravity = pin.Motion.Zero()
    data = model.createData()
    rc, jc = pb.root_columns, pb.joint_columns
    m = body.n_inputs
    tm = body.torque_model()

    def rhs(t, y):
        q, u, du = tm.motion(body, basis, x0, T, c, [t / T])
        f = np.zeros(model.nv)
        f[jc] = inverse_dynamics(body, q, u, du).tau[:, 0] * np.r_[1.01, np.ones(m - 1)]
        cfg = pb.configuration(np.concatenate([[y[2]], y[3:3 + m]]))
        v = y[3 + m:]
        ct, st = np.cos(y[2]), np.sin(y[2])
        return np.concatenate([[ct * v[0] - st * v[1], st * v[0] + ct * v[1], v[2]], v[jc],
                               pin.aba(model, data, cfg, v, f)])

    q, u, du = tm.motion(body, basis, x0, T, c, [0.0])
    v0 = np.zeros(model.nv)
    v0[rc] = inverse_dynamics(body, q, u, du).root_velocity[:, 0]
    v0[jc] = u[:, 0]
    sol = solve_ivp(rhs, (0.0, T), np.concatenate([[0.0, 0.0, x0[0]], x0[1:], v0]), method="DOP853", rtol=1e-10,
                    atol=1e-10)
    assert np.abs(sol.y[2:3 + m, -1] - r.segments[0].target).max() > 1e-5


# ------------------------------------------------------------------------------ (c) the root's part
@pytest.mark.parametrize("root, rows", [("planar", 3), ("freeflyer", 6)])
def test_root_part_of_rnea_vanishes_and_both_roots_agree(planar_plan, root, rows):
    body, r = planar_plan
    basis, x0, T, c = segment_args(r)
    q, u, du = PlanarTorque().motion(body, basis, x0, T, c, NODES)
    out = inverse_dynamics(body, q, u, du, root=root)
    ref = inverse_dynamics(body, q, u, du)
    assert out.root_residual.shape == (rows, NODES.size)
    assert np.abs(out.tau).max() > 0.1
    assert np.abs(out.root_residual).max() <= 1e-9
    assert np.abs(out.tau - ref.tau).max() <= 1e-10 * np.abs(ref.tau).max()
    # the root rate is the model's (P0 - a.u) / I, and theta'' its time derivative (central differences)
    I, a = body.momentum_map(q)
    assert np.abs(out.theta_dot - (body.P0 - np.sum(a * u, axis=0)) / I).max() <= 1e-12 * np.abs(out.theta_dot).max()
    h = 1e-5
    qp, up, _ = PlanarTorque().motion(body, basis, x0, T, c, NODES[1:-1] + h)
    qm, um, _ = PlanarTorque().motion(body, basis, x0, T, c, NODES[1:-1] - h)
    Ip, ap = body.momentum_map(qp)
    Im, am = body.momentum_map(qm)
    fd = ((body.P0 - np.sum(ap * up, axis=0)) / Ip - (body.P0 - np.sum(am * um, axis=0)) / Im) / (2 * h * T)
    assert np.abs(out.theta_ddot[1:-1] - fd).max() <= 1e-6 * np.abs(fd).max()


def test_root_part_would_not_vanish_without_the_momentum(planar_plan):
    """The residual is a real check: with the root at rest (no momentum map) it is large."""
    body, r = planar_plan
    basis, x0, T, c = segment_args(r)
    q, u, du = PlanarTorque().motion(body, basis, x0, T, c, NODES)
    pb = build_model(body, "planar")
    model = pb.model
    model.gravity = pin.Motion.Zero()
    data = model.createData()
    cfg = pb.configuration(np.r_[0.0, q[:, 20]])
    v, a = np.zeros(model.nv), np.zeros(model.nv)
    v[pb.joint_columns], a[pb.joint_columns] = u[:, 20], du[:, 20]
    assert np.abs(pin.rnea(model, data, cfg, v, a)[:3]).max() > 1e-2


def test_power_integrates_to_the_change_of_kinetic_energy(planar_plan):
    body, r = planar_plan
    basis, x0, T, c = segment_args(r)
    xg, wg = np.polynomial.legendre.leggauss(64)
    s, w = (xg + 1) / 2, wg / 2
    tm = body.torque_model()
    q, u, du = tm.motion(body, basis, x0, T, c, s)
    work = T * float(np.sum(inverse_dynamics(body, q, u, du).tau * u, axis=0) @ w)
    pb = build_model(body, "planar")
    data = pb.model.createData()
    E = []
    for end in (0.0, 1.0):
        q, u, du = tm.motion(body, basis, x0, T, c, [end])
        v = pb.velocity(inverse_dynamics(body, q, u, du).root_velocity[:, 0], u[:, 0])
        E.append(pin.computeKineticEnergy(pb.model, data, pb.configuration(np.r_[0.0, q[:, 0]]), v))
    assert abs(E[1] - E[0]) > 1e-3  # the motion changes the energy
    assert abs(work - (E[1] - E[0])) <= 1e-9 * max(1.0, abs(E[1] - E[0]))


# ------------------------------------------------------------------------------ (d) the Jacobian
def test_jacobian_against_central_finite_differences():
    p = random_segment(np.random.default_rng(5), 3, momentum=True)
    body, basis = p.body, Legendre(6)
    tm = body.torque_model()
    tau, jac = tm(body, basis, p.x0, p.T, p.coefficients, NODES)
    m, n = p.coefficients.shape
    assert tau.shape == (m, NODES.size) and jac.shape == (m, NODES.size, m * n)
    fd = np.empty_like(jac)
    h = 1e-6
    for k in range(m * n):
        e = np.zeros(m * n)
        e[k] = h
        tp, _ = tm(body, basis, p.x0, p.T, p.coefficients + e.reshape(m, n), NODES)
        tm_, _ = tm(body, basis, p.x0, p.T, p.coefficients - e.reshape(m, n), NODES)
        fd[:, :, k] = (tp - tm_) / (2 * h)
    assert np.abs(jac).max() > 1.0
    assert np.abs(jac - fd).max() <= 1e-6 * np.abs(jac).max()


def test_torques_do_not_depend_on_theta_or_the_basis():
    body = three_rods(P0=1.5)
    T, x0 = 1.3, np.array([0.4, 0.3, -0.8])
    c6 = np.array([[0.5, -0.2, 0.3, 0.0, 0.1, 0.05], [-0.4, 0.6, 0.0, -0.2, 0.0, 0.02]])
    tm = body.torque_model()
    tau, _ = tm(body, Legendre(6), x0, T, c6, NODES)
    tau2, _ = tm(body, Legendre(6), np.r_[2.0, x0[1:]], T, c6, NODES)
    assert np.array_equal(tau, tau2)
    from acroplan.core.basis import Monomial

    power = Legendre(6).to_power_s(c6)  # the same input in the monomial basis
    tau3, _ = tm(body, Monomial(6), x0, T, power, NODES)
    assert np.abs(tau3 - tau).max() <= 1e-11 * np.abs(tau).max()
    # a symmetric body at the straight shape, at rest, with momentum: no torque is needed to keep still
    out = inverse_dynamics(body, [0.0, 0.0], [0.0, 0.0], [0.0, 0.0])
    assert np.abs(out.tau).max() <= 1e-12
    assert abs(out.theta_dot[0] - 1.5 / body.locked_inertia([0.0, 0.0])) <= 1e-12


# ------------------------------------------------------------------------------ the model object
def test_torque_model_hook_and_refusals():
    body = three_rods(P0=0.5)
    tm = body.torque_model()
    assert isinstance(tm, PlanarTorque)
    assert tm.joint_names == ("q1", "q2")
    assert tm.unsupported(body) is None
    assert "planar bodies" in PlanarTorque().unsupported(acroplan.Acrobot.example())
    other = PlanarBody(body.links[:2], P0=0.0)
    assert "joints" in tm.unsupported(other)
    with pytest.raises(InvalidInputError) as e:
        PlanarTorque(root="floating")
    assert e.value.field == "root" and e.value.fix
    with pytest.raises(InvalidInputError) as e:
        inverse_dynamics(body, [0.0], [0.0, 0.0], [0.0, 0.0])
    assert e.value.field == "q" and e.value.fix
    with pytest.raises(InvalidInputError) as e:
        inverse_dynamics(body, [0.0, 0.0], np.zeros((2, 3)), np.zeros((2, 2)))
    assert e.value.field == "u"
    with pytest.raises(InvalidInputError) as e:
        inverse_dynamics(acroplan.Acrobot.example(), [0.0], [0.0], [0.0])
    assert e.value.field == "body"
    with pytest.raises(InvalidInputError) as e:
        tm(body, Legendre(6), [0.0, 0.0, 0.0], 1.0, np.zeros((2, 5)), NODES)
    assert e.value.field == "c"
    with pytest.raises(InvalidInputError) as e:
        tm(body, Legendre(6), [0.0, 0.0, 0.0], -1.0, np.zeros((2, 6)), NODES)
    assert e.value.field == "T"


# ------------------------------------------------------------------------------ optimal plans
def test_energy_optimal_starts_from_the_shape_guesses_and_finds_the_generic_optimum():
    from acroplan.core.optimal import FAMILY_STARTS, EnergyOptimal, energy
    from acroplan.families.planar.effort import optimal_starts

    assert FAMILY_STARTS[PlanarBody] is optimal_starts
    p = random_segment(np.random.default_rng(31), 3, momentum=True)
    kw = dict(conditions="free", verify=False, **p.plan_kwargs())
    fam = acroplan.plan(p.body, method=EnergyOptimal(sizes=(6, 10)), **kw)
    gen = acroplan.plan(p.body, method=EnergyOptimal(sizes=(6, 10), starts=("auto", "deform")), **kw)
    feasible = acroplan.plan(p.body, **kw)
    assert fam.success and gen.success and feasible.success
    assert re.search(r"; start: (\w+)", fam.segments[0].message).group(1) in ("bump", "tuck", "loop")

    def cost(r):
        s = r.segments[0]
        return energy(s.basis, p.T, s.basis_coefficients)

    assert abs(cost(fam) - cost(gen)) <= 1e-8 * cost(gen)
    assert cost(fam) < cost(feasible)


def test_torque_optimal_lowers_the_integral_of_tau_squared():
    from acroplan.core.optimal import EnergyOptimal, TorqueOptimal

    p = random_segment(np.random.default_rng(8), 3, momentum=True)
    kw = dict(conditions="free", verify=False, **p.plan_kwargs())
    tm = p.body.torque_model()
    xg, wg = np.polynomial.legendre.leggauss(96)
    s, w = (xg + 1) / 2, wg / 2

    def tau2(r):
        seg = r.segments[0]
        tau, _ = tm(p.body, seg.basis, seg.start, p.T, seg.basis_coefficients, s)
        return p.T * float(np.sum(tau**2, axis=0) @ w)

    e = acroplan.plan(p.body, method=EnergyOptimal(sizes=(6, 10)), **kw)
    t = acroplan.plan(p.body, method=TorqueOptimal(torque=tm, sizes=(6, 10)), **kw)
    assert e.success and t.success, t.message
    assert np.abs(t.segments[0].final_error) <= 1e-9
    assert tau2(t) < 0.9 * tau2(e)


def branched(P0=0.0):
    """A branched body with centres of mass and joints off the links' axes (as tests/test_planar.py)."""
    from acroplan.families.planar import Link

    return PlanarBody([
        Link("body", None, 12.0, 0.9, com=(0.05, -0.02)),
        Link("a1", "body", 3.0, 0.08, com=(0.2, 0.03), joint=(0.4, 0.1), joint_name="ja1"),
        Link("a2", "a1", 2.0, 0.05, com=(0.15, -0.01), joint=(0.35, 0.0), joint_name="ja2"),
        Link("b1", "body", 4.0, 0.1, com=(0.25, 0.0), joint=(-0.3, 0.15), joint_name="jb1"),
        Link("c1", "body", 1.5, 0.02, com=(0.1, 0.05), joint=(0.0, -0.2), joint_name="jc1"),
    ], P0=P0)


@pytest.mark.parametrize("root", ["planar", "freeflyer"])
def test_branched_tree_residual_root_rate_and_partials(root):
    body = branched(P0=2.5)
    rng = np.random.default_rng(4)
    q, u, du = (rng.normal(size=(4, 7)) for _ in range(3))
    out = inverse_dynamics(body, q, u, du, root=root, derivatives=True)
    assert np.abs(out.tau).max() > 0.1
    assert np.abs(out.root_residual).max() <= 1e-9
    I, a = body.momentum_map(q)
    assert np.abs(out.theta_dot - (body.P0 - np.sum(a * u, axis=0)) / I).max() <= 1e-12 * np.abs(out.theta_dot).max()
    x = np.concatenate([q, u, du])  # (12, 7)
    fd = np.empty_like(out.partials)
    h = 1e-6
    for i in range(12):
        e = np.zeros((12, 1))
        e[i] = h
        xp, xm = x + e, x - e
        fd[:, :, i] = (inverse_dynamics(body, *np.split(xp, 3), root=root).tau
                       - inverse_dynamics(body, *np.split(xm, 3), root=root).tau) / (2 * h)
    assert np.abs(out.partials - fd).max() <= 1e-6 * np.abs(out.partials).max()
