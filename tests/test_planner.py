"""Path deformation plans: single segments, waypoints, conditions, failure, other systems."""

import dataclasses

import numpy as np
import pytest

import acroplan
from acroplan.core.verify import simulate_segment
from acroplan.zoo import random_segment

PI = np.pi


def resimulate(result):
    """Chain every segment through scipy DOP853 from the first waypoint; states at each waypoint."""
    x = result.waypoints[0].copy()
    reached = [x]
    for seg in result.segments:
        sol = simulate_segment(result.system, x, seg.t0, seg.t1, seg.coefficients, rtol=1e-12, atol=1e-12)
        x = sol.y[:, -1]
        reached.append(x)
    return np.array(reached)


def test_pike_dive_reaches_every_waypoint(pike_result):
    r = pike_result
    assert r.success and r.status == "success" and len(r.segments) == 5
    assert all(s.coefficients.shape == (1, 6) for s in r.segments)
    reached = resimulate(r)
    assert np.max(np.abs(reached - r.waypoints)) < 1e-9
    assert all(s.final_error <= 1e-10 for s in r.segments)
    assert all(s.verified_error <= 1e-9 for s in r.segments)
    assert min(s.sigma_min for s in r.segments) > 0


def test_spline_conditions_make_u_and_du_continuous(pike_result):
    from scipy.interpolate import CubicSpline

    r = pike_result
    spline = CubicSpline(r.times, r.waypoints[:, 1], bc_type="clamped")
    for a, b in zip(r.segments[:-1], r.segments[1:]):
        pa = np.polynomial.Polynomial(a.coefficients[0])
        pb = np.polynomial.Polynomial(b.coefficients[0])
        T = a.t1 - a.t0
        assert pa(T) == pytest.approx(pb(0.0), abs=1e-9)
        assert pa.deriv()(T) == pytest.approx(pb.deriv()(0.0), abs=1e-8)
        assert pb(0.0) == pytest.approx(spline(b.t0, 1), abs=1e-9)
        assert pb.deriv()(0.0) == pytest.approx(spline(b.t0, 2), abs=1e-8)
    # clamped ends: u = 0 at the start and the end of the dive
    assert r.segments[0].coefficients[0, 0] == pytest.approx(0.0, abs=1e-9)
    last = r.segments[-1]
    assert np.polynomial.Polynomial(last.coefficients[0])(last.t1 - last.t0) == pytest.approx(0.0, abs=1e-9)


def test_evaluate_agrees_with_independent_simulation(pike_result):
    r = pike_result
    t = np.array([0.0, 0.7, 2.0, 3.3, 6.01, 9.99, 10.0])
    ev = r.evaluate(t)
    assert ev.theta.shape == ev.phi.shape == ev.u.shape == (7,)
    seg = r.segments[1]
    sol = simulate_segment(r.system, seg.start, seg.t0, seg.t1, seg.coefficients, t_eval=[3.3])
    assert ev.theta[3] == pytest.approx(sol.y[0, 0], abs=1e-9)
    assert ev.phi[3] == pytest.approx(sol.y[1, 0], abs=1e-9)
    assert np.allclose(ev.states[:, [0, 2, 6]].T, r.waypoints[[0, 1, 5]], atol=1e-9)
    with pytest.raises(ValueError, match="planned span"):
        r.evaluate([10.5])


def test_free_conditions_keep_u_continuous(pike_robot):
    r = acroplan.plan(pike_robot, times=[0, 1.5, 3.0], theta=[0.0, 2.0, 5.5], phi=[-2.0, -1.0, -2.5],
                      conditions="free")
    assert r.success, r.message
    a, b = r.segments
    assert np.polynomial.Polynomial(a.coefficients[0])(1.5) == pytest.approx(b.coefficients[0, 0], abs=1e-10)
    assert np.max(np.abs(resimulate(r) - r.waypoints)) < 1e-9


def test_more_coefficients_than_conditions_are_used(pike_robot):
    r = acroplan.plan(pike_robot, times=[0, 2], theta=[-0.5 * PI, 0.9 * PI], phi=[-PI, -2 * PI],
                      n_coefficients=9, basis="monomial")
    assert r.success, r.message
    assert r.segments[0].coefficients.shape == (1, 9)
    assert np.max(np.abs(resimulate(r) - r.waypoints)) < 1e-9


def test_segment_the_basis_cannot_do_is_named():
    """NOTES.md: with M2 = 0.25, P0 = 1.0 the text's 6-coefficient scheme cannot do the last segment."""
    problem = acroplan.examples.load("pike-dive")
    robot = dataclasses.replace(problem.robot, M2=0.25, P0=1.0)
    r = acroplan.plan(robot, times=problem.times, theta=problem.theta, phi=problem.phi, conditions="spline",
                      method="deform", n_coefficients=6)
    assert r.status == "not_converged" and not r.success
    assert len(r.segments) == 5 and all(s.success for s in r.segments[:4]) and not r.segments[4].success
    assert "segment 4 [8, 10]" in r.message and "try more coefficients" in r.message
    d = r.to_dict()
    assert d["status"] == "not_converged" and d["segments"][4]["success"] is False


def test_too_few_coefficients_for_the_conditions(pike_robot):
    r = acroplan.plan(pike_robot, times=[0, 2], theta=[-0.5 * PI, 0.9 * PI], phi=[-PI, -2 * PI], n_coefficients=5,
                      method="deform")
    assert r.status == "not_converged"
    assert "free coefficient(s) for 2 endpoint equations" in r.message
    r = acroplan.plan(pike_robot, times=[0, 2], theta=[-0.5 * PI, 0.9 * PI], phi=[-PI, -2 * PI], n_coefficients=2,
                      method="deform")
    assert "cannot all be met by 2 coefficient(s)" in r.message


def test_target_outside_the_reachable_interval_is_refused(pike_robot):
    lo, hi = acroplan.reachable_set(pike_robot, theta0=0.0, phi0=-PI, phiT=-2 * PI, T=2.0).interval
    for theta_T in (hi + 0.01, lo - 0.01, hi):
        r = acroplan.plan(pike_robot, times=[0, 2], theta=[0.0, theta_T], phi=[-PI, -2 * PI])
        assert r.status == "infeasible" and r.segments == ()
        assert r.infeasible[0]["interval"] == [lo, hi]
        assert f"({lo:.12g}, {hi:.12g})" in r.message


def test_holonomic_P0_zero_is_refused_with_the_one_theta(pike_robot):
    robot = dataclasses.replace(pike_robot, P0=0.0)
    only = float(1.0 - (robot.F(-2.0) - robot.F(-1.0)))
    r = acroplan.plan(robot, times=[0, 1], theta=[1.0, 2.0], phi=[-1.0, -2.0])
    assert r.status == "infeasible"
    assert "holonomic" in r.message and f"{only:.12g}" in r.message
    assert r.infeasible[0]["interval"] == [pytest.approx(only, abs=1e-15)] * 2


def test_reachable_interval_is_exact(pike_robot):
    """Targets just inside both ends are reached; the ends are where 1/h is extremal."""
    r = pike_robot
    lo, hi = r.reachable_interval(theta0=0.0, phi0=-2.0, phiT=-2.5, T=1.5)
    base = 0.0 - float(r.F(-2.5) - r.F(-2.0))
    assert lo == pytest.approx(base + r.P0 * 1.5 / (r.M1 - r.A1), rel=1e-14)
    assert hi == pytest.approx(base + r.P0 * 1.5 / (r.M1 + r.A1), rel=1e-14)
    for w in (0.08, 0.5, 0.92):
        res = acroplan.plan(r, times=[0, 1.5], theta=[0.0, lo + w * (hi - lo)], phi=[-2.0, -2.5],
                            conditions="free", n_coefficients=8)
        assert res.success, res.message


def test_random_physical_single_segments():
    """A fixed-seed sample of the generator in acroplan.zoo; every success is re-simulated."""
    rng = np.random.default_rng(12345)
    n, ok, ok_text = 40, 0, 0
    for _ in range(n):
        p = random_segment(rng)
        r = acroplan.plan(p.robot, conditions="free", **p.plan_kwargs())
        assert r.status in ("success", "not_converged")
        if r.success:
            ok += 1
            assert np.max(np.abs(resimulate(r)[-1] - [p.thetaT, p.phiT])) < 1e-9
        text = acroplan.plan(p.robot, conditions="free", method="deform", n_coefficients=6, **p.plan_kwargs())
        if text.success:
            ok_text += 1
            assert np.max(np.abs(resimulate(text)[-1] - [p.thetaT, p.phiT])) < 1e-9
    # measured with this seed: auto 40 of 40; the text's method alone (6 coefficients) 39 of 40
    assert ok == n and ok_text >= 38


def test_unicycle_is_planned_too():
    uni = acroplan.Unicycle()
    r = acroplan.plan(uni, times=[0, 1, 2], x=[0, 1, 1], y=[0, 0.5, 1.5], psi=[0, 0, 1.0], conditions="free")
    assert r.success, r.message
    assert r.segments[0].coefficients.shape == (2, 6)
    assert np.max(np.abs(resimulate(r) - r.waypoints)) < 1e-9
    # parallel parking: a pure sideways displacement, singular for u = 0
    r = acroplan.plan(uni, times=[0, 1], x=[0, 0], y=[0, 1], psi=[0, 0], conditions="free")
    assert r.success, r.message
    assert np.max(np.abs(resimulate(r) - r.waypoints)) < 1e-9


def test_same_input_gives_bit_identical_output(pike_robot):
    kw = dict(times=[0, 2], theta=[-0.5 * PI, 0.9 * PI], phi=[-PI, -2 * PI])
    a = acroplan.plan(pike_robot, **kw)
    b = acroplan.plan(pike_robot, **kw)
    assert a.to_json() == b.to_json()


@pytest.mark.parametrize("kwargs, match", [
    (dict(times=[0, 2], theta=[0, 1], phi=[0, 1], foo=1), r"foo: is not an option of plan\(\)"),
    (dict(times=[0, 2], theta=[0, 1]), "phi: is missing"),
    (dict(times=[0, 2], theta=[0, 1, 2], phi=[0, 1]), "theta: has 3 value"),
    (dict(times=[2, 0], theta=[0, 1], phi=[0, 1]), "times: must be strictly increasing"),
    (dict(times=[0], theta=[0], phi=[0]), "times: needs at least 2"),
    (dict(times=[0, 2], theta=[0, float("nan")], phi=[0, 1]), "theta: contains NaN"),
    (dict(times=[0, 2], theta=[0, 1], phi=[0, 1], conditions="smooth"), "conditions: must be one of"),
    (dict(times=[0, 2], theta=[0, 1], phi=[0, 1], basis="fourier"), "basis: unknown basis"),
    (dict(times=[0, 2], theta=[0, 1], phi=[0, 1], n_coefficients=0), "n_coefficients: must be a whole number"),
    (dict(times=[0, 2], theta=[0, 1], phi=[0, 1], tol=-1.0), "tol: must be a positive number"),
    (dict(times=[0, 2], theta=[0, 1], phi=[0, 1], verify="yes"), "verify: must be True or False"),
    (dict(times="abc", theta=[0, 1], phi=[0, 1]), "times: must be a list of numbers"),
])
def test_invalid_input_names_the_field(pike_robot, kwargs, match):
    with pytest.raises(acroplan.InvalidInputError, match=match):
        acroplan.plan(pike_robot, **kwargs)


def test_spline_conditions_need_rate_inputs():
    with pytest.raises(ValueError, match="conditions: \"spline\" needs every input"):
        acroplan.plan(acroplan.Unicycle(), times=[0, 1], x=[0, 1], y=[0, 0], psi=[0, 0], conditions="spline")


def test_verify_false_skips_the_check(pike_robot):
    r = acroplan.plan(pike_robot, times=[0, 2], theta=[-0.5 * PI, 0.9 * PI], phi=[-PI, -2 * PI], verify=False)
    assert r.success and not r.verified and r.segments[0].verified_error is None
    assert "not independently verified" in r.message


def test_results_are_read_only(pike_result):
    with pytest.raises(ValueError):
        pike_result.segments[0].coefficients[0, 0] = 1.0
    with pytest.raises(ValueError):
        pike_result.waypoints[0, 0] = 1.0
