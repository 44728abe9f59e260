"""Planning free-flying planar bodies (acroplan.families.planar: guess, strategy, check, bounds, examples)."""

import math

import numpy as np
import pytest

import acroplan
from acroplan.core import backend
from acroplan.core.basis import Legendre
from acroplan.core.limits import Limits
from acroplan.families.planar import random_body, three_rods
from acroplan.families.planar.check import pinocchio_errors, simulate_with_pinocchio
from acroplan.families.planar.connection import Connection, cos_range, curvature
from acroplan.families.planar.examples import EXAMPLES
from acroplan.families.planar.guess import shape_guesses
from acroplan.families.planar.strategy import PlanarAuto
from acroplan.families.planar.zoo import random_segment

pytest.importorskip("pinocchio")


def test_connection_equals_the_momentum_map_and_stokes_holds():
    body = random_body(3, 4, P0=0.0)
    conn = Connection(body)
    rng = np.random.default_rng(0)
    S = rng.uniform(-3, 3, (3, 40))
    I, a = conn(S)  # noqa: E741
    I2, a2 = body.momentum_map(S)
    assert np.allclose(I, I2, rtol=1e-13) and np.allclose(a, a2, rtol=1e-12, atol=1e-13)
    # Stokes: the turn of a small circle loop in (q1, q3) is -F * area (counter-clockwise positive)
    c, r = np.array([0.4, -0.3, 1.1]), 0.02
    s = np.linspace(0, 1, 4001)
    q = c[:, None] + np.zeros((3, s.size))
    q[0] += r * np.cos(2 * np.pi * s)
    q[2] += r * np.sin(2 * np.pi * s)
    dq = np.zeros_like(q)
    dq[0] = -2 * np.pi * r * np.sin(2 * np.pi * s)
    dq[2] = 2 * np.pi * r * np.cos(2 * np.pi * s)
    turn = -np.trapezoid(np.sum(conn.one_form(q) * dq, axis=0), s)
    F = curvature(conn, c, 0, 2)
    assert turn == pytest.approx(-F * np.pi * r**2, rel=1e-3)
    # and the compiled system agrees: the loop as an input (rates), at P0 = 0
    w = 2 * np.pi
    res = acroplan.simulate(body, times=[0, 1], inputs=lambda t: [-w * r * np.sin(w * t), 0.0, w * r * np.cos(w * t)],
                            n_coefficients=14, theta=0.0, q1=c[0] + r, q2=c[1], q3=c[2], verify=False)
    assert res.waypoints[-1][0] == pytest.approx(turn, rel=1e-4)


def test_cos_range_encloses_every_value():
    rng = np.random.default_rng(1)
    lo = rng.uniform(-20, 20, 400)
    hi = lo + rng.uniform(0, 7, 400)
    cmin, cmax = cos_range(lo, hi)
    for k in range(400):
        v = np.cos(np.linspace(lo[k], hi[k], 5001))
        assert cmin[k] <= v.min() and cmax[k] >= v.max()
        assert v.min() - cmin[k] < 1e-6 and cmax[k] - v.max() < 1e-6
    assert cos_range([-np.inf], [0.0]) == (-1.0, 1.0)


@pytest.mark.parametrize("momentum", [False, True])
def test_the_guess_already_meets_the_target(momentum):
    rng = np.random.default_rng(2)
    z = np.zeros(2)
    for _ in range(8):
        p = random_segment(rng, 3, momentum=momentum)
        for n, ends in ((6, {}), (10, {"u0": z, "du0": z, "uT": z, "duT": z})):
            g = shape_guesses(p.body, Legendre(n), p.x0, p.x1, p.T, ends)
            assert g, (p, n)
            y, _ = backend.endpoint(p.body, Legendre(n), p.x0, p.T, g[0].coefficients)
            assert np.max(np.abs(y - p.x1)) < 1e-9, (g[0].describe(), y - p.x1)
            assert g[0].predicted_error < 1e-12
            if ends:  # the spline conditions hold exactly: u = 0 at both ends
                assert np.max(np.abs(g[0].coefficients @ Legendre(n).matrix([0.0, 1.0]).T)) < 1e-12


def test_pure_reorientation_at_zero_momentum_is_a_plausible_motion():
    body = three_rods(P0=0.0)
    for dth in (0.2, 0.5):
        res = acroplan.plan(body, times=[0, 2], theta=[0, dth], q1=[0.3, 0.3], q2=[-0.2, -0.2], conditions="free")
        assert res.status == "success", res.message
        assert "Pinocchio" in res.message
        assert res.max_abs_u < 10.0  # path deformation from u = 0 gave 345 rad/s here
        assert res.segments[0].evaluations <= 3
    lim = dict(u_max=3.0, q1_min=-2.5, q1_max=2.5, q2_min=-2.5, q2_max=2.5)
    res = acroplan.plan(body, times=[0, 2], theta=[0, 0.2], q1=[0.3, 0.3], q2=[-0.2, -0.2], conditions="free", **lim)
    assert res.status == "success", res.message
    assert res.max_abs_u <= 3.0 + 1e-9


def test_auto_is_the_planar_strategy_and_the_check_is_pinocchio():
    body = random_body(7, 3)
    assert isinstance(body.auto_strategy(), PlanarAuto)
    assert body.family_check == "Pinocchio centroidal simulation"


def test_pinocchio_check_agrees_with_dop853_and_catches_errors():
    p = random_segment(8, 3, momentum=True)
    res = acroplan.plan(p.body, conditions="free", verify=False, **p.plan_kwargs())
    assert res.success
    seg = res.segments[0]
    err = pinocchio_errors(p.body, p.x0, res.segments)
    assert err[0] < 1e-12
    sol = simulate_with_pinocchio(p.body, p.x0, seg.t0, seg.t1, seg.input)
    assert np.max(np.abs(sol.y[:, -1] - p.x1)) < 1e-10
    # a wrong target, a wrong body, a wrong input: each is caught
    import dataclasses

    off = dataclasses.replace(seg, target=seg.target + np.array([1e-7, 0, 0]))
    assert pinocchio_errors(p.body, p.x0, [off])[0] == pytest.approx(1e-7, rel=1e-3)
    other = acroplan.families.planar.PlanarBody(p.body.links, P0=p.body.P0 * (1 + 1e-6) + 1e-6)
    assert pinocchio_errors(other, p.x0, res.segments)[0] > 1e-8
    bent = dataclasses.replace(seg, basis_coefficients=seg.basis_coefficients * (1 + 1e-6))
    assert pinocchio_errors(p.body, p.x0, [bent])[0] > 1e-8
    # verify=True uses it, and "ode" still works
    for verify in (True, "ode"):
        r = acroplan.plan(p.body, conditions="free", verify=verify, **p.plan_kwargs())
        assert r.success and r.segments[0].verified_error < 1e-9


@pytest.mark.parametrize("n_links, momentum, limited", [(3, False, False), (3, True, False), (3, False, True),
                                                        (3, True, True), (4, False, False), (4, True, True)])
def test_random_reachable_segments_succeed_and_pass_the_pinocchio_check(n_links, momentum, limited):
    rng = np.random.default_rng(40 + 2 * n_links + momentum + 4 * limited)
    for _ in range(10):
        p = random_segment(rng, n_links, momentum=momentum, limited=limited)
        res = acroplan.plan(p.body, conditions="free", **p.plan_kwargs())
        assert res.status == "success", res.message
        assert max(s.verified_error for s in res.segments) < 1e-9
        if limited:
            for name in p.body.links.joint_names:
                assert res.max_abs_u <= max(p.limits.input_bound(f"u_{j}") for j in p.body.links.joint_names) + 1e-9
                lo, hi = p.limits.bounds(name)
                r = res.state_ranges[name]
                assert lo - 1e-9 <= r[0] and r[1] <= hi + 1e-9


def test_rate_limits_bound_the_turn_and_refuse_beyond_it_with_the_proof():
    body = random_body(9, 3, P0=0.8)
    lim = Limits({"q1": (-1.0, 1.5), "q2": (-2.0, 0.5)}, {"u_q1": 1.5, "u_q2": 2.0})
    x0, T = np.array([0.3, 0.2, -0.4]), 1.5
    qT = np.array([0.7, -0.1])
    B = body.turn_bound(x0, np.concatenate([[0.0], qT]), T, lim)
    assert 0 < B < 10
    # the bound is a bound: random motions that keep the limits never turn further
    rng = np.random.default_rng(3)
    worst = 0.0
    for _ in range(60):
        c = np.zeros((2, 6))
        c[:, :4] = rng.normal(size=(2, 4))
        # fix the joint ends, then scale the wiggle into the limits
        res = acroplan.simulate(body, times=[0, T], inputs=[c], theta=x0[0], q1=x0[1], q2=x0[2], verify=False)
        v = acroplan.core.limits.violation(body, Legendre(6), x0, T, c, lim)
        if v["u"] > 0 or v["state"] > 0:
            continue
        worst = max(worst, abs(res.waypoints[-1][0] - x0[0]))
        assert abs(res.waypoints[-1][0] - x0[0]) <= body.turn_bound(x0, res.waypoints[-1], T, lim)
    assert worst > 0
    # beyond it: refused, with the interval as the proof (exit 3 in the CLI)
    res = acroplan.plan(body, times=[0, T], theta=[x0[0], x0[0] + 1.01 * B], q1=[x0[1], qT[0]], q2=[x0[2], qT[1]],
                        limits=lim, conditions="free")
    assert res.status == "infeasible"
    d = res.infeasible[0]
    assert d["field"] == "theta" and d["interval"][1] == pytest.approx(x0[0] + B, rel=1e-12)
    assert "interval arithmetic" in d["reason"]
    # a joint that cannot get there in time is named
    res = acroplan.plan(body, times=[0, T], theta=[0, 0], q1=[-0.9, 1.4], q2=[0, 0], limits=lim, conditions="free")
    assert res.status == "infeasible" and res.infeasible[0]["field"] == "q1"
    # no rate limit on some joint: no bound, no refusal on theta
    assert body.turn_bound(x0, x0, T, Limits({"q1": (-1.0, 1.5)}, {"u_q1": 1.5})) == math.inf
    assert body.check_segment(x0, x0 + [100.0, 0, 0], T, Limits(input_bounds={"u_q1": 1.5})) is None


def test_a_plan_through_six_waypoints_with_spline_conditions():
    body = random_body(13, 3, P0=0.9)
    rng = np.random.default_rng(5)
    times = np.linspace(0.0, 5.0, 7)
    inputs = [np.pad(rng.normal(scale=[0.8, 0.6, 0.3], size=(2, 3)), ((0, 0), (0, 3))) for _ in range(6)]
    sim = acroplan.simulate(body, times=times, inputs=inputs, theta=0.1, q1=0.2, q2=-0.3, verify=False)
    W = sim.waypoints
    # rounded waypoints: reachable (not the simulated motion's own), spline conditions at every waypoint
    W = np.round(W, 2)
    res = acroplan.plan(body, times=times, theta=W[:, 0], q1=W[:, 1], q2=W[:, 2], conditions="spline")
    assert res.status == "success", res.message
    assert len(res.segments) == 6
    assert max(s.verified_error for s in res.segments) < 1e-9
    # u and u' continuous at the interior waypoints
    for a, b in zip(res.segments[:-1], res.segments[1:]):
        assert np.allclose(a.input(a.t1), b.input(b.t0), atol=1e-9)


@pytest.mark.parametrize("name", list(EXAMPLES))
def test_bundled_examples_are_planned_and_pinocchio_verified(name, tmp_path):
    body, kw = EXAMPLES[name]()
    res = acroplan.plan(body, **kw)
    assert res.status == "success", res.message
    assert res.verification == "family" and max(s.verified_error for s in res.segments) < 1e-9
    # the ends as asked: same shape at both ends where the example says so
    if name != "diver-somersault":
        assert np.allclose(res.waypoints[0][1:], res.waypoints[-1][1:])
    x = res.waypoints[0]
    for seg in res.segments:  # and the DOP853 Pinocchio simulation agrees
        x = simulate_with_pinocchio(body, x, seg.t0, seg.t1, seg.input).y[:, -1]
    assert np.max(np.abs(x - res.waypoints[-1])) < 1e-9
    from acroplan.families.planar.drawing import save_strobe

    path = tmp_path / f"planar-{name}.png"
    save_strobe(res, path)
    assert path.stat().st_size > 5000


def write_figures(folder):
    """The docs' figures: each example's strobe (``planar-<name>.png``) and the link table's conventions."""
    import pathlib

    from acroplan.families.planar.drawing import conventions_figure, save_strobe

    folder = pathlib.Path(folder)
    titles = {"diver-somersault": "diver: one somersault in pike with an arm sweep (P0 = 36 kg m^2/s)",
              "space-robot-turn": "space robot at P0 = 0: the base turns pi/2 by five arm loops",
              "three-rods-turn": "three equal rods at P0 = 0: one shape loop turns them 0.4 rad"}
    for name, fn in EXAMPLES.items():
        body, kw = fn()
        res = acroplan.plan(body, **kw)
        assert res.success, res.message
        save_strobe(res, folder / f"planar-{name}.png", poses=11 if name == "space-robot-turn" else 7,
                    title=titles[name])
    conventions_figure().savefig(str(folder / "planar-link-table.png"))


if __name__ == "__main__":
    import sys

    write_figures(sys.argv[1] if len(sys.argv) > 1 else "docs/images")
