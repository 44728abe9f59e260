"""Free-flying planar bodies with any number of links (acroplan.families.planar).

The model is checked three ways: against the acrobot (two links, symbolically and numerically),
against eq. (1) built literally in sympy, and against Pinocchio (centroidal momentum map, and a
forward simulation driven by Pinocchio alone).
"""

import math
import pickle
import sys

import numpy as np
import pytest
import sympy as sp

import acroplan
from acroplan.core import backend
from acroplan.core.basis import Legendre
from acroplan.core.errors import InvalidInputError
from acroplan.core.limits import Limits
from acroplan.families.planar import (Link, LinkTable, PlanarBody, diver_with_arms, momentum_from_definition,
                                      planar_space_robot, random_body, read_link_table, read_urdf, three_rods,
                                      to_urdf)
from acroplan.families.planar.check import centroidal_momentum, simulate_with_pinocchio
from acroplan.families.planar.pin import build_model

# one worker runs this module (pyproject.toml's loadgroup): its bodies' integrators are compiled once,
# not on both workers at once (the branched body's, 10 s, was)
pytestmark = pytest.mark.xdist_group("test_planar")

pin = pytest.importorskip("pinocchio")

ACRO = dict(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2, torso_length=0.35, leg_length=0.45,
            angular_momentum=10.0)


def branched(P0=0.0):
    """A branched body with centres of mass and joints off the links' axes (every term of the model)."""
    return PlanarBody([
        Link("body", None, 12.0, 0.9, com=(0.05, -0.02)),
        Link("a1", "body", 3.0, 0.08, com=(0.2, 0.03), joint=(0.4, 0.1), joint_name="ja1"),
        Link("a2", "a1", 2.0, 0.05, com=(0.15, -0.01), joint=(0.35, 0.0), joint_name="ja2"),
        Link("b1", "body", 4.0, 0.1, com=(0.25, 0.0), joint=(-0.3, 0.15), joint_name="jb1"),
        Link("c1", "body", 1.5, 0.02, com=(0.1, 0.05), joint=(0.0, -0.2), joint_name="jc1"),
    ], P0=P0)


# ---------------------------------------------------------------------- the link table
def rods(n=3):
    return [Link(f"r{k}", None if k == 0 else f"r{k - 1}", 1.0, 0.1, com=(0.5, 0.0),
                 joint=(0.0, 0.0) if k == 0 else (1.0, 0.0)) for k in range(n)]


@pytest.mark.parametrize("change, field, words", [
    (lambda L: L.__setitem__(2, Link("r2", "r1", -1.0, 0.1)), "links[2].mass", "must be > 0"),
    (lambda L: L.__setitem__(1, Link("r1", "r0", 1.0, 0.0)), "links[1].inertia", "must be > 0"),
    (lambda L: L.__setitem__(1, Link("r1", "nobody", 1.0, 0.1)), "links[1].parent", "'nobody' is not the name"),
    (lambda L: L.__setitem__(2, Link("r1", "r1", 1.0, 0.1)), "links[2].name", "already the name of links[1]"),
    (lambda L: L.__setitem__(1, Link("r1", None, 1.0, 0.1)), "links[1].parent", "is the root already"),
    (lambda L: L.__setitem__(0, Link("r0", "r2", 1.0, 0.1)), "links", "has no root"),
    (lambda L: L.extend([Link("x", "y", 1.0, 0.1), Link("y", "x", 1.0, 0.1)]), "links[3].parent", "loop (x -> y -> x)"),
    (lambda L: L.__setitem__(1, Link("r1", "r0", 1.0, 0.1, joint_name="theta")), "links[1].joint_name", "cannot name"),
    (lambda L: L.__setitem__(1, Link("r1", "r0", 1.0, 0.1, joint_name="times")), "links[1].joint_name", "cannot name"),
    (lambda L: L.__setitem__(2, Link("r2", "r1", 1.0, 0.1, joint_name="r1")), "links[2].joint_name", "used twice"),
    (lambda L: L.__setitem__(1, Link("arm-1", "r0", 1.0, 0.1)), "links[1].name", "Python identifier"),
    (lambda L: L.__setitem__(1, Link("r1", "r0", 1.0, 0.1, com=(1.0,))), "links[1].com", "pair"),
    (lambda L: L.__setitem__(1, Link("r1", "r0", 1.0, 0.1, joint=(1.0, math.nan))), "links[1].joint[1]", "finite"),
    (lambda L: L.__setitem__(1, Link("r1", "r0", "heavy", 0.1)), "links[1].mass", "real number"),
    (lambda L: L.__setitem__(1, Link("r1", "r0", 1.0, 0.1, lower=1.0, upper=0.5)), "links[1].lower", "< upper"),
    (lambda L: L.__setitem__(1, Link("r1", "r0", 1.0, 0.1, velocity=0.0)), "links[1].velocity", "> 0"),
    (lambda L: L.__setitem__(0, Link("r0", None, 1.0, 0.1, joint=(0.2, 0.0))), "links[0].joint", "the root has no"),
    (lambda L: L.__setitem__(0, Link("r0", None, 1.0, 0.1, upper=1.0)), "links[0].upper", "the root has no"),
])
def test_link_table_refuses_bad_tables_naming_the_field_and_the_fix(change, field, words):
    links = rods(3)
    change(links)
    with pytest.raises(InvalidInputError) as e:
        LinkTable(links)
    assert e.value.field == field
    assert words in str(e.value)
    assert e.value.fix  # every refusal says what to do


def test_link_table_topology_and_body_names():
    body = diver_with_arms()
    t = body.links
    assert t.parents == (-1, 0, 1, 0) and t.root == 0
    assert t.joint_names == ("hip", "knee", "shoulder")
    assert t.subtree(1) == (1, 2) and t.path(2) == (1, 2) and t.children(0) == (1, 3)
    assert body.state_names == ("theta", "hip", "knee", "shoulder")
    assert body.input_names == ("u_hip", "u_knee", "u_shoulder")
    assert body.rate_inputs == {"u_hip": "hip", "u_knee": "knee", "u_shoulder": "shoulder"}
    assert body.structure_key == ("planar", (-1, 0, 1, 0))
    assert len(body.params) == len(body.param_names) == 2 + 3 + 2 * 6
    # links in any order: the root need not come first
    shuffled = PlanarBody([t[2], t[0], t[3], t[1]])
    assert shuffled.links.parents == (3, -1, 1, 1) and shuffled.links.root == 1
    x = np.array([0.3, 2.5, 0.4, 1.0])
    y = np.array([0.3, 0.4, 1.0, 2.5])  # the same pose, joints in the shuffled table's order (knee, shoulder, hip)
    assert shuffled.locked_inertia(y[1:]) == pytest.approx(body.locked_inertia(x[1:]), rel=1e-13)
    with pytest.raises(InvalidInputError, match="at least two links"):
        PlanarBody([Link("only", None, 1.0, 0.1)])
    with pytest.raises(InvalidInputError, match="P0"):
        PlanarBody(rods(2), P0=math.inf)


def test_link_tables_from_dicts_records_and_pickling():
    body = branched(P0=1.25)
    d = body.to_dict()
    assert d["type"] == "PlanarBody" and d["P0"] == 1.25 and d["parents"] == [-1, 0, 1, 0, 0]
    assert set(d["params"]) == set(body.param_names)
    again = PlanarBody.from_dict(d)
    assert again == body and hash(again) == hash(body)
    assert pickle.loads(pickle.dumps(body)) == body
    with pytest.raises(InvalidInputError, match=r"links\[1\]\.colour: is not a link field"):
        LinkTable([{"name": "a", "mass": 1.0, "inertia": 0.1}, {"name": "b", "parent": "a", "mass": 1.0,
                                                                "inertia": 0.1, "colour": "red"}])


# ---------------------------------------------------------------------- two links: the acrobot
def test_two_link_fields_equal_the_acrobots_symbolically():
    body = PlanarBody.from_acrobot_physical(**ACRO)
    acro = acroplan.Acrobot.from_physical(**ACRO)
    assert body.state_names == ("theta", "phi") and body.input_names == ("u_phi",)
    M, m, J, j, L, l, P0 = sp.symbols("M m J j L l P0", positive=True)
    # the compiled (lumped) fields, written back in physical symbols, then in the acrobot's geometry
    f, G = body.symbolic()
    lumped = body.lumped_expressions()
    _, phys = body.physical_symbols()
    geometry = dict(zip(phys, (P0, m, j, l, 0, M, J, L, 0, 0, 0)))
    x, _ = body.symbols()
    phi = sp.Symbol("phi", real=True)

    def physical(e):
        return e.xreplace(lumped).xreplace(geometry).xreplace({x[1]: phi})

    mu = m * M / (m + M)
    a_sym = sp.symbols("theta phi", real=True)
    fa, Ga = acro.symbolic_fields(a_sym, (j + J + mu * (L**2 + l**2), -2 * mu * L * l, J + mu * L**2, -mu * L * l, P0))
    assert sp.simplify(physical(f[0]) - fa[0]) == 0
    assert sp.simplify(physical(G[0, 0]) - Ga[0]) == 0
    assert (f[1], G[1, 0]) == (0, 1)
    # eq. (1) built literally gives the same momentum map, and theta drops out
    Ldef, td, u = momentum_from_definition(body)
    Ip, ap = body.symbolic_momentum_map(physical=True)
    # (trigonometric terms as exponentials: a rational function of exp(i angle), zero exactly when
    # cancel() gives 0; simplify() takes some 20 s on this one)
    assert sp.cancel(sp.expand((Ldef - Ip * td - ap[0] * u[0]).rewrite(sp.exp))) == 0
    assert sp.simplify(Ldef.diff(x[0])) == 0
    assert sp.simplify(Ip.xreplace(geometry).xreplace({x[1]: phi}) - (j + J + mu * (L**2 + l**2 - 2 * L * l * sp.cos(phi)))) == 0


@pytest.mark.parametrize("phys", [ACRO, dict(ACRO, torso_length=0.0, angular_momentum=-3.0),
                                  dict(torso_mass=5.0, leg_mass=30.0, torso_inertia=0.2, leg_inertia=2.0,
                                       torso_length=0.9, leg_length=0.1, angular_momentum=0.5)])
def test_two_link_fields_equal_the_acrobots_numerically(phys):
    body = PlanarBody.from_acrobot_physical(**phys)
    acro = acroplan.Acrobot.from_physical(**phys)
    rng = np.random.default_rng(7)
    for _ in range(20):
        x, u = rng.uniform(-4, 4, 2), rng.normal(size=1) * 3
        assert np.allclose(body.rhs(x, u), acro.rhs(x, u), rtol=1e-13, atol=1e-13)
        assert body.locked_inertia(x[1:]) == pytest.approx(acro.h(x[1]), rel=1e-13)
        assert body.momentum_map(x[1:])[1][0] == pytest.approx(acro.k(x[1]), rel=1e-13, abs=1e-14)
    # the geometry of the acrobot: torso CoM - leg CoM = L e(theta + phi) - l e(theta)
    th, ph = 0.4, -1.1
    F = body.link_frames([th, ph])
    d = F[1, :2] - F[0, :2]
    L, l = phys["torso_length"], phys["leg_length"]
    assert np.allclose(d, [L * math.cos(th + ph) - l * math.cos(th), L * math.sin(th + ph) - l * math.sin(th)],
                       atol=1e-14)
    assert np.allclose(F[:, 2], [th, th + ph])


def test_any_two_link_body_is_an_acrobot_and_is_checked_exactly():
    body = PlanarBody([Link("a", None, 3.0, 0.2, com=(0.1, 0.3)),
                       Link("b", "a", 2.0, 0.1, com=(0.2, -0.4), joint=(0.7, -0.2), joint_name="q")], P0=0.8)
    acro, psi0, delta = body.as_acrobot()
    rng = np.random.default_rng(3)
    for _ in range(10):
        x, u = rng.uniform(-4, 4, 2), rng.normal(size=1)
        xa = np.array([x[0] + psi0, x[1] + delta])
        assert body.rhs(x, u)[0] == pytest.approx(acro.rhs(xa, u)[0], rel=1e-12, abs=1e-13)
    # P0 = 0: holonomic; the exact test refuses an unreachable theta and lets the reachable one through
    still = PlanarBody(body.links, P0=0.0)
    sim = acroplan.simulate(still, times=[0, 1], inputs=[[[0.8, 0.3, -0.2]]], theta=0.1, q=0.5)
    xT = sim.waypoints[-1]
    assert still.check_segment(sim.waypoints[0], xT, 1.0) is None
    proof = still.check_segment(sim.waypoints[0], xT + [0.1, 0.0], 1.0)
    assert proof is not None and proof.field == "theta" and proof.interval[0] == pytest.approx(xT[0], abs=1e-12)
    res = acroplan.plan(still, times=[0, 1], theta=[0.1, xT[0] + 0.1], q=[0.5, xT[1]])
    assert res.status == "infeasible" and "holonomic" in res.message
    # with P0 != 0 the interval is the acrobot's, shifted back; limits are translated by name
    lo, hi = body.check_segment([0.0, 0.5], [100.0, 1.0], 1.0).interval
    alo, ahi = acro.reachable_interval(theta0=psi0, phi0=0.5 + delta, phiT=1.0 + delta, T=1.0)
    assert (lo, hi) == pytest.approx((alo - psi0, ahi - psi0), abs=1e-12)
    lim = Limits({"q": (0.0, 2.0)}, {"u_q": 0.6})
    proof = body.check_segment([0.0, 0.5], [0.0, 1.3], 1.0, lim)
    assert proof is not None and proof.field == "q" and "u_q" in proof.reason


# ---------------------------------------------------------------------- against eq. (1) and Pinocchio
BODIES = {
    "3-chain": lambda: random_body(11, 3, P0=1.3),
    "4-chain": lambda: random_body(12, 4, P0=-0.7),
    "branched": lambda: branched(P0=2.1),
    "diver": lambda: diver_with_arms(P0=40.0),
}


@pytest.mark.parametrize("name", list(BODIES))
def test_momentum_map_equals_pinocchios_centroidal_map(name):
    body = BODIES[name]()
    rng = np.random.default_rng(list(BODIES).index(name))
    for k in range(20):
        x = rng.uniform(-math.pi, math.pi, body.n_states)
        td, u = rng.normal() * 2, rng.normal(size=body.n_inputs) * 2
        L = body.momentum(x, td, u)
        Lp = centroidal_momentum(body, x, td, u, root="freeflyer" if k % 2 else "planar")
        scale = body.locked_inertia(x[1:]) * abs(td) + np.abs(body.momentum_map(x[1:])[1]) @ np.abs(u)
        assert abs(L - Lp) <= 1e-12 * scale, (k, L, Lp)
        # the compiled fields (lambdified sympy) give the theta rate that makes Pinocchio's momentum P0
        xdot = body.rhs(x, u)
        assert centroidal_momentum(body, x, xdot[0], u) == pytest.approx(body.P0, abs=1e-12 * scale)
        assert np.allclose(xdot[1:], u, rtol=0, atol=0)
        # the locked inertia is Pinocchio's momentum at theta_dot = 1, u = 0
        I_p = centroidal_momentum(body, x, 1.0, np.zeros(body.n_inputs))
        assert body.locked_inertia(x[1:]) == pytest.approx(I_p, rel=1e-12)


@pytest.mark.parametrize("name", ["3-chain", "branched"])
def test_compact_momentum_map_equals_eq_1_built_literally(name):
    body = BODIES[name]()
    Ldef, td, u = momentum_from_definition(body)
    x, p = body.physical_symbols()
    fn = sp.lambdify((x, p, td, u), Ldef, "numpy")
    Ip, ap = body.symbolic_momentum_map(physical=True)
    fn_c = sp.lambdify((x, p), [Ip, *ap], "numpy")
    Il, al = body.symbolic_momentum_map()
    xl, pl = body.symbols()
    fn_l = sp.lambdify((xl, pl), [Il, *al], "numpy")
    vals = list(body.physical_values().values())
    rng = np.random.default_rng(5)
    for _ in range(10):
        s = rng.uniform(-math.pi, math.pi, body.n_states)
        thd, uu = rng.normal(), rng.normal(size=body.n_inputs)
        L = fn(s, vals, thd, uu)
        for I, *a in (fn_c(s, vals), fn_l(s, body.params)):  # noqa: E741
            assert I * thd + np.dot(a, uu) == pytest.approx(L, rel=1e-12, abs=1e-12)
        s2 = s.copy()
        s2[0] += 1.0  # theta drops out
        assert fn(s2, vals, thd, uu) == pytest.approx(L, rel=1e-12, abs=1e-12)


def test_link_frames_are_about_the_centre_of_mass():
    body = branched()
    x = np.array([0.3, 0.5, -1.0, 2.0, 0.7])
    F = body.link_frames(x)
    m = np.array([k.mass for k in body.links])
    assert np.allclose(m @ F[:, :2], 0.0, atol=1e-14)
    assert np.allclose(F[:, 2], [0.3, 0.8, -0.2, 2.3, 1.0])
    J = body.joint_positions(x)
    # link a2's joint is a1's joint plus R(alpha_a1) (0.35, 0)
    assert np.allclose(J[2] - J[1], 0.35 * np.array([math.cos(0.8), math.sin(0.8)]), atol=1e-14)
    # Pinocchio agrees on the centres of mass, relative to the whole body's
    pb = build_model(body)
    data = pb.model.createData()
    q = pb.configuration(x)
    pin.centerOfMass(pb.model, data, q)
    pin.forwardKinematics(pb.model, data, q)
    for i, jid in enumerate(pb.joint_ids):
        com = data.oMi[jid].act(pb.model.inertias[jid].lever)[:2] - data.com[0][:2]
        assert np.allclose(com, F[i, :2], atol=1e-14)


# ---------------------------------------------------------------------- motions
def smooth_input(rng, m, n=6):
    c = np.zeros((m, n))
    c[:, :4] = rng.normal(scale=[1.0, 1.0, 0.6, 0.3], size=(m, 4))
    return c


@pytest.mark.parametrize("name", ["3-chain", "4-chain", "branched"])
def test_momentum_is_conserved_along_a_simulated_motion(name):
    body = BODIES[name]()
    rng = np.random.default_rng(2)
    c = smooth_input(rng, body.n_inputs)
    x0 = dict(zip(body.state_names, rng.uniform(-1, 1, body.n_states)))
    res = acroplan.simulate(body, times=[0, 1], inputs=[c], **x0)
    assert res.status == "success"
    t = np.linspace(0, 1, 21)
    S = res.evaluate(t)
    for k in range(t.size):
        x, u = S.states[:, k], S.inputs[:, k]
        scale = body.locked_inertia(x[1:]) + np.abs(body.momentum_map(x[1:])[1]) @ np.abs(u)
        assert abs(centroidal_momentum(body, x, body.rhs(x, u)[0], u) - body.P0) <= 1e-10 * max(scale, abs(body.P0))
    # theta's rate along the motion (differentiated, 4th-order central differences) is what the model says
    h = 1e-3
    tm = np.array([0.3, 0.6])
    D = (-res.evaluate(tm + 2 * h).states + 8 * res.evaluate(tm + h).states - 8 * res.evaluate(tm - h).states
         + res.evaluate(tm - 2 * h).states) / (12 * h)
    S = res.evaluate(tm)
    for k in range(tm.size):
        assert centroidal_momentum(body, S.states[:, k], D[0, k], S.inputs[:, k]) == pytest.approx(body.P0, abs=1e-8)


@pytest.mark.parametrize("name", ["3-chain", "4-chain", "branched"])
def test_pinocchio_driven_simulation_reproduces_simulate(name):
    body = BODIES[name]()
    rng = np.random.default_rng(4)
    c = smooth_input(rng, body.n_inputs)
    x0 = dict(zip(body.state_names, rng.uniform(-1, 1, body.n_states)))
    res = acroplan.simulate(body, times=[0.5, 2.0], inputs=[c], **x0)
    seg = res.segments[0]
    sol = simulate_with_pinocchio(body, res.waypoints[0], 0.5, 2.0, seg.input)
    assert np.max(np.abs(sol.y[:, -1] - res.waypoints[-1])) < 1e-9
    assert abs(res.waypoints[-1][0] - res.waypoints[0][0]) > 1e-2  # theta did move


def _loop_inputs(x_poly, y_poly, n=6):
    """Legendre coefficients (2, n) of the rates of a shape loop (q1, q2) = (x(s), y(s)), s in [0, 1]."""
    b = Legendre(n)
    rows = []
    for p in (x_poly.deriv(), y_poly.deriv()):
        q = np.zeros(n)
        q[:p.coef.size] = p.coef
        rows.append(b.from_power_s(q))
    return np.array(rows)


def test_a_symmetric_shape_loop_gives_no_net_turn_at_zero_momentum():
    body = three_rods(P0=0.0)
    P = np.polynomial.Polynomial
    s_ = P([0, 1])
    x = 0.3 + 2.0 * s_ * (1 - s_) + 3.0 * s_**2 * (1 - s_)
    # mirror-symmetric about the line q1 = -q2: (q1, q2) -> (-q2, -q1) maps the loop onto itself, reversed.
    # Reversing the chain of equal rods is that map on shapes and keeps the sense of rotation, so the turn
    # equals the reversed loop's, its own negative: zero.
    y = -x(1 - s_)
    assert abs(x(0) - x(1)) < 1e-15 and abs(y(0) - y(1)) < 1e-15
    area = (x * y.deriv()).integ()
    assert abs(area(1) - area(0)) > 0.1  # a real loop, not a back-and-forth
    res = acroplan.simulate(body, times=[0, 1], inputs=[_loop_inputs(x, y)], theta=0.2, q1=x(0), q2=y(0))
    end = res.waypoints[-1]
    assert np.allclose(end[1:], [x(0), y(0)], atol=1e-13)
    assert abs(end[0] - 0.2) < 1e-10
    sol = simulate_with_pinocchio(body, res.waypoints[0], 0, 1, res.segments[0].input)
    assert abs(sol.y[0, -1] - 0.2) < 1e-10
    # the same loop mirrored about q1 = q2 instead: no symmetry of the body maps it onto itself, and it turns
    res2 = acroplan.simulate(body, times=[0, 1], inputs=[_loop_inputs(x, x(1 - s_))], theta=0.2, q1=x(0), q2=x(1))
    assert np.allclose(res2.waypoints[-1][1:], [x(0), x(1)], atol=1e-13)
    assert abs(res2.waypoints[-1][0] - 0.2) > 1e-3


@pytest.mark.parametrize("body", [three_rods(P0=0.0), diver_with_arms(P0=0.0)], ids=["rods", "diver"])
def test_a_point_symmetric_loop_gives_no_net_turn_for_a_body_symmetric_in_its_axis(body):
    # every centre of mass and joint on its link's x axis: the mirror in the axis maps shape q to -q and
    # theta to -theta, so a loop with q(t + 1/2) = -q(t) (two segments, the second the first negated) turns 0
    rng = np.random.default_rng(8)
    c = smooth_input(rng, body.n_inputs)
    start = rng.uniform(-0.5, 0.5, body.n_inputs)
    mid = acroplan.simulate(body, times=[0, 1], inputs=[c], theta=0.0,
                            **dict(zip(body.links.joint_names, start)))
    shift = (-start - mid.waypoints[-1][1:]) / 1.0  # a constant rate that ends the first half at -start
    c1 = c.copy()
    c1[:, 0] += shift
    res = acroplan.simulate(body, times=[0, 1, 2], inputs=[c1, -c1], theta=0.0,
                            **dict(zip(body.links.joint_names, start)))
    W = res.waypoints
    assert np.allclose(W[1][1:], -start, atol=1e-13) and np.allclose(W[2][1:], start, atol=1e-13)
    assert abs(W[1][0]) > 1e-3  # half way it has turned
    assert abs(W[2][0]) < 1e-10  # and turned back


@pytest.mark.parametrize("name", ["3-chain", "branched"])
def test_endpoint_jacobian_matches_finite_differences(name):
    body = BODIES[name]()
    rng = np.random.default_rng(9)
    basis = Legendre(6)
    c = smooth_input(rng, body.n_inputs)
    x0 = rng.uniform(-1, 1, body.n_states)
    T = 1.3
    xT, J = backend.endpoint(body, basis, x0, T, c)
    assert J.shape == (body.n_states, body.n_inputs * 6)
    h = 1e-6
    flat = c.ravel()
    for k in range(flat.size):
        e = np.zeros_like(flat)
        e[k] = h
        xp, _ = backend.endpoint(body, basis, x0, T, (flat + e).reshape(c.shape))
        xm, _ = backend.endpoint(body, basis, x0, T, (flat - e).reshape(c.shape))
        assert np.allclose((xp - xm) / (2 * h), J[:, k], rtol=1e-7, atol=1e-8), k


def test_plan_a_three_link_body_and_check_it_with_pinocchio():
    body = random_body(21, 3, P0=2.0)
    rng = np.random.default_rng(10)
    start = dict(theta=0.0, q1=0.4, q2=-0.6)
    target = acroplan.simulate(body, times=[0, 1.5], inputs=[smooth_input(rng, 2)], **start).waypoints[-1]
    res = acroplan.plan(body, times=[0, 1.5], theta=[0, target[0]], q1=[0.4, target[1]], q2=[-0.6, target[2]],
                        conditions="free")
    assert res.status == "success", res.message
    x = res.waypoints[0]
    for seg in res.segments:
        x = simulate_with_pinocchio(body, x, seg.t0, seg.t1, seg.input).y[:, -1]
    assert np.max(np.abs(x - target)) < 1e-9


def test_bodies_of_one_topology_share_one_compiled_integrator():
    a = random_body(31, 3, P0=1.0)
    b = three_rods(P0=-2.0)  # other names, other values, same parents
    assert a.structure_key == b.structure_key
    acroplan.warm_up(a, sizes=(6,))
    n = backend.compiled_count()
    acroplan.warm_up(b, sizes=(6,))
    assert backend.compiled_count() == n
    rng = np.random.default_rng(12)
    c = smooth_input(rng, 2)
    res = acroplan.simulate(b, times=[0, 1], inputs=[c], theta=0.0, q1=0.2, q2=0.1)
    sol = simulate_with_pinocchio(b, res.waypoints[0], 0, 1, res.segments[0].input)
    assert np.max(np.abs(sol.y[:, -1] - res.waypoints[-1])) < 1e-9


# ---------------------------------------------------------------------- URDF
PLANAR_URDF = """<?xml version="1.0"?>
<robot name="arm">
  <link name="base">
    <inertial><origin xyz="0.1 0.2 0.05"/><mass value="2"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial>
  </link>
  <link name="upper-arm">
    <inertial><origin xyz="0.5 0 0"/><mass value="1"/>
      <inertia ixx="0.03" ixy="0" ixz="0" iyy="0.04" iyz="0" izz="0.05"/></inertial>
  </link>
  <link name="hand">
    <inertial><origin xyz="0.1 0 0"/><mass value="0.5"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
  </link>
  <link name="tool">
    <inertial><origin xyz="0 0 0"/><mass value="0.5"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.02"/></inertial>
  </link>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper-arm"/>
    <origin xyz="1 0 0.1" rpy="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="2" velocity="3" effort="1"/></joint>
  <joint name="wrist" type="revolute"><parent link="upper-arm"/><child link="hand"/>
    <origin xyz="1 0 0"/><axis xyz="0 0 -1"/><limit lower="-0.5" upper="1.5" velocity="4" effort="1"/></joint>
  <joint name="fix" type="fixed"><parent link="hand"/><child link="tool"/><origin xyz="0.3 0 0"/></joint>
</robot>
"""


def test_urdf_round_trip(tmp_path):
    for body in (diver_with_arms(), planar_space_robot(), branched(), random_body(3, 4)):
        path = tmp_path / "body.urdf"
        path.write_text(to_urdf(body))
        table = read_link_table(path)
        assert table.names == body.links.names and table.parents == body.links.parents
        assert table.joint_names == body.links.joint_names
        for a, b in zip(table, body.links):
            assert (a.mass, a.inertia) == pytest.approx((b.mass, b.inertia), rel=1e-14)
            assert a.com == pytest.approx(b.com, abs=1e-14) and a.joint == pytest.approx(b.joint, abs=1e-14)
            assert (a.lower, a.upper, a.velocity) == (b.lower, b.upper, b.velocity)
    body = read_urdf(path, P0=0.5, limits=False)
    assert body.P0 == 0.5 and body.joint_limits() is None


def test_urdf_projection_conventions_match_pinocchios_own_model(tmp_path):
    path = tmp_path / "arm.urdf"
    path.write_text(PLANAR_URDF)
    table = read_link_table(path)
    assert table.names == ("base", "upper_arm", "hand") and table.joint_names == ("shoulder", "wrist")
    base, arm, hand = table
    assert base.com == pytest.approx((0.1, 0.2)) and base.inertia == pytest.approx(0.3)
    c3, s3 = math.cos(0.3), math.sin(0.3)
    assert arm.joint == pytest.approx((1.0, 0.0)) and arm.com == pytest.approx((0.5 * c3, 0.5 * s3))
    assert (arm.lower, arm.upper, arm.velocity) == (-1.0, 2.0, 3.0)
    # wrist: axis -z, so its angle and limits flip; the tool (fixed joint) is merged into the hand
    assert (hand.lower, hand.upper, hand.velocity) == (-1.5, 0.5, 4.0)
    assert hand.mass == pytest.approx(1.0)
    assert hand.com == pytest.approx((0.2 * c3, 0.2 * s3))
    assert hand.inertia == pytest.approx(0.01 + 0.02 + 2 * 0.5 * 0.1**2)
    # the momentum of the table's body equals Pinocchio's model of the URDF itself, at random poses
    body = PlanarBody(table, P0=0.0)
    model = pin.buildModelFromUrdf(str(path), pin.JointModelPlanar())
    data = model.createData()
    rng = np.random.default_rng(13)
    for _ in range(10):
        x, td, u = rng.uniform(-3, 3, 3), rng.normal(), rng.normal(size=2)
        q = np.array([0.0, 0.0, math.cos(x[0]), math.sin(x[0]), x[1], -x[2]])
        v = np.array([0.0, 0.0, td, u[0], -u[1]])
        h = pin.computeCentroidalMap(model, data, q) @ v
        assert body.momentum(x, td, u) == pytest.approx(h[5], rel=1e-12)
    # limits honoured unless overridden
    over = read_link_table(path, overrides={"wrist": {"upper": 0.25, "velocity": None}})
    assert (over[2].lower, over[2].upper, over[2].velocity) == (-1.5, 0.25, None)
    assert read_urdf(path).joint_limits() == Limits({"shoulder": (-1.0, 2.0), "wrist": (-1.5, 0.5)},
                                                    {"u_shoulder": 3.0, "u_wrist": 4.0})
    with pytest.raises(InvalidInputError, match=r"overrides\.elbow: is not a joint"):
        read_link_table(path, overrides={"elbow": {"upper": 1.0}})
    with pytest.raises(InvalidInputError, match=r"overrides\.wrist\.effort: is not a joint limit"):
        read_link_table(path, overrides={"wrist": {"effort": 1.0}})


@pytest.mark.parametrize("edit, words", [
    (('<axis xyz="0 0 -1"/>', '<axis xyz="0 1 0"/>'), "urdf joint 'wrist': turns about (-0.29552, 0.955336, 0)"),
    (('<origin xyz="1 0 0.1" rpy="0 0 0.3"/>', '<origin xyz="1 0 0.1" rpy="0.2 0 0.3"/>'),
     "urdf joint 'shoulder': turns about"),
    (('name="wrist" type="revolute"', 'name="wrist" type="prismatic"'), "urdf joint 'wrist': is not a revolute joint"),
    (('name="wrist" type="revolute"', 'name="wrist" type="floating"'), "urdf joint 'wrist': is a"),
])
def test_non_planar_urdfs_are_refused_naming_the_joint(tmp_path, edit, words):
    text = PLANAR_URDF.replace(*edit)
    assert text != PLANAR_URDF
    path = tmp_path / "bad.urdf"
    path.write_text(text)
    with pytest.raises(InvalidInputError) as e:
        read_link_table(path)
    assert words in str(e.value), str(e.value)
    assert e.value.fix


def test_urdf_errors(tmp_path):
    with pytest.raises(InvalidInputError, match="no such file"):
        read_link_table(tmp_path / "missing.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'/>")
    with pytest.raises(InvalidInputError, match=r"urdf: bad\.urdf is not well-formed XML \(no element found at line 1"):
        read_link_table(bad)
    # what urdfdom prints is captured and becomes the message (issue #25: its lines came before acroplan's)
    bad.write_text("<robot name='x'><link name='a'/><joint name='j' type='revolute'><parent link='a'/>"
                   "<child link='b'/><axis xyz='0 0 1'/></joint></robot>")
    with pytest.raises(InvalidInputError, match=r"urdf: Pinocchio could not read bad\.urdf: Joint \[j\] is of type "
                       "REVOLUTE but it does not specify limits"):
        read_link_table(bad)
    massless = tmp_path / "massless.urdf"
    massless.write_text(PLANAR_URDF.replace('<mass value="1"/>', '<mass value="0"/>').replace(
        '<inertia ixx="0.03" ixy="0" ixz="0" iyy="0.04" iyz="0" izz="0.05"/>',
        '<inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/>'))
    with pytest.raises(InvalidInputError, match="urdf link 'upper-arm': has no mass"):
        read_link_table(massless)
    # issue #25: a massless link with an inertia is no body (it was read with the inertia dropped)
    massless.write_text(PLANAR_URDF.replace('<mass value="1"/>', '<mass value="0"/>'))
    with pytest.raises(InvalidInputError, match="urdf link 'upper-arm': has mass 0 and an inertia that is not zero"):
        read_link_table(massless)


def test_pinocchio_is_optional(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "pinocchio", None)  # import pinocchio now raises ImportError
    with pytest.raises(InvalidInputError, match=r"acroplan\[bodies\]"):
        build_model(three_rods())
    path = tmp_path / "rods.urdf"
    path.write_text(to_urdf(three_rods()))
    with pytest.raises(InvalidInputError, match=r"pinocchio: is needed"):
        read_urdf(path)
    assert three_rods().momentum([0, 0.1, 0.2], 1.0, [0.0, 0.0]) > 0  # the model itself does not need it


# ---------------------------------------------------------------------- the zoo
def test_zoo_bodies():
    rods3 = three_rods()
    assert rods3.locked_inertia([0.0, 0.0]) == pytest.approx(27 / 12)  # one rod of length 3 and mass 3: 3 * 3^2 / 12
    a, b = random_body(5, 4), random_body(5, 4)
    assert a == b and random_body(6, 4) != a
    for body in (random_body(np.random.default_rng(1), 6), a):
        for link in body.links:
            assert 1.0 <= link.mass <= 30.0
            assert 0.3 * 0.2 <= link.com[0] <= 0.7 * 0.8 and abs(link.com[1]) <= 0.05 * 0.8
            assert link.inertia > 0
    with pytest.raises(InvalidInputError, match="n_links"):
        random_body(1, 1)
    diver = diver_with_arms()
    assert 70 < diver.links.total_mass < 80
    lim = diver.joint_limits()
    lim.check_for(diver)
    assert lim.bounds("hip") == (0.35, 3.5) and lim.input_bound("u_knee") == 14.0
    robot = planar_space_robot(P0=0.0)
    assert robot.state_names == ("theta", "shoulder", "elbow")


def test_simulate_checks_a_body_by_pinocchio_by_default():
    """acroplan.simulate(verify=True) uses the family's own check (Pinocchio for bodies), "ode" the
    DOP853 re-simulation; both agree with the motion to 1e-9."""
    import acroplan
    from acroplan.families.planar import three_rods

    body = three_rods()
    kw = dict(times=[0.0, 1.0], inputs=[np.array([[0.3, 0.2, -0.1], [-0.2, 0.1, 0.05]])], theta=0.0, q1=0.1, q2=-0.2)
    fam = acroplan.simulate(body, **kw)
    ode = acroplan.simulate(body, verify="ode", **kw)
    assert fam.verification == "family" and "Pinocchio" in fam.message and fam.success
    assert ode.verification == "ode" and ode.success
    assert max(s.verified_error for s in fam.segments) < 1e-9 and max(s.verified_error for s in ode.segments) < 1e-9
    np.testing.assert_array_equal(fam.waypoints, ode.waypoints)


def test_pinocchio_model_of_a_branched_tree_has_the_right_mass_matrix():
    """Pinocchio's crba needs each joint's subtree numbered consecutively (depth first); with a
    breadth-first numbering of a branched tree it returned a mass matrix off by 0.95."""
    import pinocchio as pin

    from acroplan.families.planar import diver_with_arms
    from acroplan.families.planar.pin import build_model

    body = diver_with_arms()
    table = body.links
    assert any(len(table.children(i)) > 1 for i in range(len(table)))  # branched
    pb = build_model(table)
    model, data = pb.model, pb.model.createData()
    model.gravity = pin.Motion.Zero()
    q = pin.randomConfiguration(model, -np.ones(model.nq), np.ones(model.nq))
    M = pin.crba(model, data, q)
    M = np.triu(M) + np.triu(M, 1).T
    cols = np.column_stack([pin.rnea(model, model.createData(), q, np.zeros(model.nv), e)
                            for e in np.eye(model.nv)])
    assert np.max(np.abs(M - cols)) < 1e-12
    order = table.topological_order()
    for i in order:  # every subtree is a run of consecutive positions
        pos = sorted(order.index(j) for j in table.subtree(i))
        assert pos == list(range(pos[0], pos[0] + len(pos)))


def test_degrees_apply_to_every_angle_of_a_body():
    import acroplan
    from acroplan.families.planar import three_rods

    body = three_rods()
    rad = acroplan.plan(body, times=[0, 2], theta=[0, 0.3], q1=[0.2, 0.2], q2=[-0.1, -0.1], conditions="free")
    deg = acroplan.plan(body, times=[0, 2], theta=[0, np.degrees(0.3)], q1=[np.degrees(0.2)] * 2,
                        q2=[np.degrees(-0.1)] * 2, conditions="free", degrees=True)
    assert rad.success and deg.success
    np.testing.assert_allclose(deg.waypoints, rad.waypoints, rtol=0, atol=1e-12)


def test_tree_errors_name_the_field_in_both_families():
    """One tree check (families/tree.py) for planar and spatial link tables."""
    from acroplan.core.errors import InvalidInputError
    from acroplan.families.planar import Link, LinkTable
    from acroplan.families.spatial import SpatialLink, SpatialLinkTable

    loop = [Link("a", None, 1, 0.1), Link("b", "c", 1, 0.1, joint=(1, 0)), Link("c", "b", 1, 0.1, joint=(1, 0))]
    with pytest.raises(InvalidInputError, match=r"links\[1\]\.parent: the parents form a loop \(b -> c -> b\)"):
        LinkTable(loop)
    spatial = [SpatialLink("a", None, 1, (0.1, 0.1, 0.1)), SpatialLink("b", "b", 1, (0.1, 0.1, 0.1))]
    with pytest.raises(InvalidInputError, match=r"links\[1\]\.parent: link 'b' is its own parent"):
        SpatialLinkTable(spatial)
    with pytest.raises(InvalidInputError, match=r"links: has no root.*attitude is the state"):
        SpatialLinkTable([SpatialLink("a", "b", 1, (0.1, 0.1, 0.1)), SpatialLink("b", "a", 1, (0.1, 0.1, 0.1))])
