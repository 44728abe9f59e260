"""Limits enforced in plans, the flat-output planner, and the success rate (robustness issue)."""

import numpy as np
import pytest

import acroplan
from acroplan.zoo import random_segment

from test_planner import resimulate

PI = np.pi


def test_pike_dive_within_joint_limits():
    problem = acroplan.examples.load("pike-dive-limited")
    r = problem.solve()
    assert r.success, r.message
    assert np.max(np.abs(resimulate(r)[-1] - r.waypoints[-1])) < 1e-9
    # compliance, exactly per segment and on a dense grid of the whole motion
    for s in r.segments:
        lo, hi = s.state_range
        assert lo >= -2 * PI - 1e-9 and hi <= -PI + 1e-9
    ev = r.sample(400)
    assert ev.phi.min() >= -2 * PI - 1e-9 and ev.phi.max() <= -PI + 1e-9
    # the input stays continuous across every junction
    for a, b in zip(r.segments[:-1], r.segments[1:]):
        assert a.input([a.t1])[0, 0] == pytest.approx(b.input([b.t0])[0, 0], abs=1e-8)
    # every waypoint is reached
    for k, group in enumerate(r.intervals):
        assert np.allclose(group[-1].target, r.waypoints[k + 1], atol=0)
        assert group[-1].verified_error <= 1e-9


def test_rate_limit_is_kept(physical_robot):
    lo, hi = acroplan.reachable_set(physical_robot, theta0=0.0, phi0=-2.0, phiT=-0.5, T=1.5, u_max=4.0).interval
    target = lo + 0.7 * (hi - lo)
    r = acroplan.plan(physical_robot, times=[0, 1.5], theta=[0.0, target], phi=[-2.0, -0.5], conditions="free",
                      u_max=4.0)
    assert r.success, r.message
    assert max(s.max_abs_u for s in r.segments) <= 4.0 + 1e-9
    ev = r.sample(2000)
    assert np.max(np.abs(ev.u)) <= 4.0 + 1e-9
    assert np.max(np.abs(resimulate(r)[-1] - r.waypoints[-1])) < 1e-9


def test_limits_that_make_it_impossible_are_proven(physical_robot):
    lo, hi = acroplan.reachable_set(physical_robot, theta0=0.0, phi0=-2.0, phiT=-0.5, T=1.5, u_max=4.0).interval
    free_lo, free_hi = acroplan.reachable_set(physical_robot, theta0=0.0, phi0=-2.0, phiT=-0.5, T=1.5).interval
    target = 0.5 * (hi + free_hi)  # reachable without the rate limit, not with it
    assert hi < target < free_hi
    r = acroplan.plan(physical_robot, times=[0, 1.5], theta=[0.0, target], phi=[-2.0, -0.5], u_max=4.0)
    assert r.status == "infeasible"
    assert "under the rate limits" in r.message and f"{hi:.12g}" in r.message
    r = acroplan.plan(physical_robot, times=[0, 0.2], theta=[0.0, 0.5], phi=[-2.0, -0.5], u_max=4.0)
    assert r.status == "infeasible" and "allows only 0.8 rad" in r.message


def test_spline_conditions_against_limits_are_refused():
    problem = acroplan.examples.load("pike-dive")
    r = acroplan.plan(problem.robot, times=problem.times, theta=problem.theta, phi=problem.phi,
                      conditions="spline", phi_min=-2 * PI, phi_max=-PI)
    assert r.status == "infeasible" and "on its joint limit" in r.message


def test_waypoint_outside_the_joint_limits_is_invalid(pike_robot):
    with pytest.raises(acroplan.InvalidInputError, match=r"phi: waypoint 1 \(t = 1\) has phi = -7"):
        acroplan.plan(pike_robot, times=[0, 1], theta=[0, 1], phi=[-4, -7], phi_min=-2 * PI, phi_max=-PI)


@pytest.mark.parametrize("w", [0.02, 0.3, 0.5, 0.9, 0.98])
def test_flat_method_is_exact(pike_robot, w):
    kw = dict(theta0=0.3, phi0=-2.8, phiT=-1.1, T=1.7)
    lo, hi = acroplan.reachable_set(pike_robot, **kw).interval
    r = acroplan.plan(pike_robot, times=[0, 1.7], theta=[0.3, lo + w * (hi - lo)], phi=[-2.8, -1.1],
                      conditions="free", method="flat")
    assert r.success, r.message
    assert {s.method for s in r.segments} == {"flat"} and len(r.segments) in (2, 3)
    assert r.segments[-1].final_error < 1e-12
    assert np.max(np.abs(resimulate(r)[-1] - r.waypoints[-1])) < 1e-9


def test_flat_method_honours_spline_conditions(pike_robot):
    problem = acroplan.examples.load("pike-dive")
    r = acroplan.plan(problem.robot, times=problem.times, theta=problem.theta, phi=problem.phi,
                      conditions="spline", method="flat")
    assert r.success, r.message
    from scipy.interpolate import CubicSpline

    S = CubicSpline(problem.times, problem.phi, bc_type="clamped")
    for group, t0 in zip(r.intervals, problem.times):
        first = group[0]
        p = np.polynomial.Polynomial(first.coefficients[0])
        assert p(0.0) == pytest.approx(S(t0, 1), abs=1e-8)
        assert p.deriv()(0.0) == pytest.approx(S(t0, 2), abs=1e-6)


def test_flat_method_needs_a_flat_output():
    with pytest.raises(acroplan.InvalidInputError, match="method: \"flat\" needs a flat output"):
        acroplan.plan(acroplan.Unicycle(), times=[0, 1], x=[0, 1], y=[0, 0], psi=[0, 0], conditions="free",
                      method="flat")


def test_auto_succeeds_on_a_fixed_seed_sample_and_refuses_outside():
    """Targets in the middle 96%: all planned and re-verified; targets outside: all refused."""
    rng = np.random.default_rng(99)
    for _ in range(30):
        p = random_segment(rng)
        r = acroplan.plan(p.robot, conditions="free", **p.plan_kwargs())
        assert r.success, r.message
        assert np.max(np.abs(resimulate(r)[-1] - [p.thetaT, p.phiT])) < 1e-9
        lo, hi = p.interval
        for theta_T in (hi + 0.01 * (hi - lo), lo - 0.3 * (hi - lo)):
            bad = acroplan.plan(p.robot, conditions="free", times=[0, p.T], theta=[p.theta0, theta_T],
                                phi=[p.phi0, p.phiT])
            assert bad.status == "infeasible" and bad.infeasible[0]["interval"] == [lo, hi]
