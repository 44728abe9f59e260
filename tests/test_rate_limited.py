"""The rate-limited flat planner (acroplan.families.acrobot.ratelimited): every target strictly inside
the exact rate- and joint-limited interval is planned, within the limits.

The body of the issue ("The first hour": rate- and joint-limited problems fail): a 1.75 m, 58 kg
adult split at the hips, with de Leva (1996) segment proportions (male, adjusted
Zatsiorsky-Seluyanov), arms along the trunk:

* upper body (trunk 43.46% + head and neck 6.94% + both arms 2 x 4.94% = 60.28%): M = 34.96 kg,
  centre of mass L = 0.30 m above the hip, J = 1.60 kg m^2 about it (trunk, head and arms with
  de Leva's sagittal radii of gyration, parallel axes);
* both legs (2 x (thigh 14.16% + shank 4.33% + foot 1.37%) = 39.72%): m = 23.04 kg, centre of
  mass l = 0.32 m below the hip, j = 1.72 kg m^2 about it.

Convention (as in the pike-dive examples): phi = -2 pi is folded (legs on the trunk), phi = -pi
straight. A pike limit of 30 degrees between trunk and legs is phi >= -2 pi + pi/6; the upper
limit is the straight body, phi <= -pi. |u| <= 15 rad/s, T = 1.65 s, P0 = +-40 kg m^2/s.
"""

import numpy as np
import pytest

import acroplan
from acroplan.core.limits import Limits
from acroplan.families.acrobot.ratelimited import RAMPS, family_range, rate_limited_pieces
from acroplan.families.acrobot.reach import reachable_set

from test_planner import resimulate

PI = np.pi
PHI_MIN, PHI_MAX = -2 * PI + PI / 6, -PI
U, T = 15.0, 1.65
LIMITS = Limits(phi_min=PHI_MIN, phi_max=PHI_MAX, u_max=U)
ROUNDING = 1e-12  # the joint range is integrated from the waypoint: exact up to rounding


def human(P0=40.0):
    return acroplan.Acrobot.from_physical(torso_mass=34.96, leg_mass=23.04, torso_inertia=1.60, leg_inertia=1.72,
                                          torso_com_to_joint=0.30, leg_com_to_joint=0.32, angular_momentum=P0)


def _plan(robot, phi0, phiT, w, limits=LIMITS, method="auto", T=T, **kw):
    R = reachable_set(robot, theta0=0.2, phi0=phi0, phiT=phiT, T=T, limits=limits)
    target = R.low + w * (R.high - R.low)
    r = acroplan.plan(robot, times=[0.0, T], theta=[0.2, target], phi=[phi0, phiT], conditions="free",
                      limits=limits, method=method, **kw)
    return r, R


def _assert_within_limits(r, limits):
    U_ = limits.input_bound("u")
    lo, hi = limits.bounds("phi")
    assert max(s.max_abs_u for s in r.segments) <= U_
    for s in r.segments:
        if np.isfinite(lo) or np.isfinite(hi):
            a, b = s.state_range
            assert lo - ROUNDING <= a and b <= hi + ROUNDING, (a, b)
    ev = r.sample(400)
    assert np.max(np.abs(ev.u)) <= U_
    assert ev.phi.min() >= lo - ROUNDING and ev.phi.max() <= hi + ROUNDING


@pytest.mark.parametrize("method", ["auto", "flat"])
@pytest.mark.parametrize("P0", [40.0, -40.0])
@pytest.mark.parametrize("w", [0.8, 0.9, 0.95, 0.98, 0.995])
@pytest.mark.parametrize("motion", [(-PI, -PI), (-PI, -5.2)], ids=["straight-straight", "straight-pike"])
def test_the_issue_targets_near_the_end_are_planned(method, P0, w, motion):
    """Targets at 80-99.5% of the exact limited interval: planned, verified, within the limits."""
    r, _ = _plan(human(P0), *motion, w, method=method)
    assert r.success, r.message
    assert r.verified and r.verification is not None  # plan()'s independent check
    assert max(s.verified_error for s in r.segments) <= 1e-9
    assert np.max(np.abs(resimulate(r)[-1] - r.waypoints[-1])) < 1e-9  # DOP853, independently
    _assert_within_limits(r, LIMITS)
    # the input is continuous, and so is its slope, across the pieces
    for a, b in zip(r.segments[:-1], r.segments[1:]):
        assert a.input([a.t1])[0, 0] == pytest.approx(b.input([b.t0])[0, 0], abs=1e-9)


@pytest.mark.parametrize("method", ["auto", "flat"])
@pytest.mark.parametrize("w", [0.001, 0.02, 0.5, 0.999])
def test_both_methods_reach_across_the_interval(method, w):
    r, _ = _plan(human(-40.0), -PI, -5.2, w, method=method)
    assert r.success, r.message
    _assert_within_limits(r, LIMITS)


@pytest.mark.parametrize("P0", [40.0, -40.0])
@pytest.mark.parametrize("motion", [(-PI, -PI), (-PI, -5.2), (-4.0, -3.3)])
def test_the_family_converges_to_the_exact_interval(P0, motion):
    """As the ramps shorten the family's reach tends to the exact ends, from inside: the shortfall
    on each side is at most ~2 rho + e of the interval (module docstring), never negative."""
    robot = human(P0)
    R = reachable_set(robot, theta0=0.2, phi0=motion[0], phiT=motion[1], T=T, limits=LIMITS)
    width = R.high - R.low
    rungs = family_range(robot, theta0=0.2, phi0=motion[0], phiT=motion[1], T=T, limits=LIMITS)
    assert len(rungs) == len(RAMPS) and all(lo is not None for _, _, lo, _ in rungs)
    short = np.array([((lo - R.low) / width, (R.high - hi) / width) for _, _, lo, hi in rungs])
    assert np.all(short >= -1e-12)  # inside the exact interval: nothing beats the extremals
    assert np.all(np.diff(short, axis=0) <= 1e-12)  # the gap closes as the ladder descends
    rho = np.array([rho for rho, _, _, _ in rungs])
    assert np.all(short.max(axis=1) <= 3 * rho + 1e-12)
    assert short[-1].max() <= 1e-4 and short[0].max() > 10 * short[-1].max()


def test_rate_bound_without_joint_limits_and_phi0_equal_phiT():
    limits = Limits(u_max=U)
    for P0 in (25.0, -25.0):
        for phi0, phiT in ((0.3, 0.3), (-2.0, 1.5)):
            for w in (0.001, 0.98, 0.999):
                r, _ = _plan(human(P0), phi0, phiT, w, limits=limits)
                assert r.success, r.message
                assert max(s.max_abs_u for s in r.segments) <= U


def test_spline_conditions_are_honoured():
    """u and u' of the clamped spline at every waypoint start each interval's first piece."""
    robot = human(40.0)
    limits = Limits(phi_min=PHI_MIN, phi_max=-PI + 0.1, u_max=U)
    times, phis, theta = [0.0, 1.65, 3.3, 4.5], [-PI, -5.0, -4.0, -PI], [0.0]
    for k in range(3):
        R = reachable_set(robot, theta0=theta[-1], phi0=phis[k], phiT=phis[k + 1], T=times[k + 1] - times[k],
                          limits=limits)
        theta.append(R.low + 0.97 * (R.high - R.low))
    from scipy.interpolate import CubicSpline

    S = CubicSpline(times, phis, bc_type="clamped")
    for method in ("auto", "flat"):
        r = acroplan.plan(robot, times=times, theta=theta, phi=phis, conditions="spline", limits=limits,
                          method=method)
        assert r.success, r.message
        assert "flat-rate" in {s.method for s in r.segments}
        _assert_within_limits(r, limits)
        for group, t0, t1 in zip(r.intervals, times[:-1], times[1:]):
            first, last = group[0], group[-1]
            p = np.polynomial.Polynomial(first.coefficients[0])
            assert p(0.0) == pytest.approx(S(t0, 1), abs=1e-8)
            assert p.deriv()(0.0) == pytest.approx(S(t0, 2), abs=1e-6)
            q = np.polynomial.Polynomial(last.coefficients[0])
            assert q(t1 - last.t0) == pytest.approx(S(t1, 1), abs=1e-8)


def test_free_conditions_carry_the_rate_across_waypoints():
    robot = human(-40.0)
    times, phis, theta = [0.0, 1.0, 2.2], [-PI, -4.5, -5.5], [0.0]
    for k in range(2):
        R = reachable_set(robot, theta0=theta[-1], phi0=phis[k], phiT=phis[k + 1], T=times[k + 1] - times[k],
                          limits=LIMITS)
        theta.append(R.low + 0.99 * (R.high - R.low))
    r = acroplan.plan(robot, times=times, theta=theta, phi=phis, conditions="free", limits=LIMITS, start_rate=-2.0)
    assert r.success, r.message
    _assert_within_limits(r, LIMITS)
    assert r.segments[0].input([0.0])[0, 0] == pytest.approx(-2.0, abs=1e-12)
    for a, b in zip(r.segments[:-1], r.segments[1:]):
        assert a.input([a.t1])[0, 0] == pytest.approx(b.input([b.t0])[0, 0], abs=1e-9)


@pytest.mark.parametrize("slack", [1e-2, 1e-4, 1e-6])
def test_travel_close_to_u_max_T(slack):
    """The joint must travel (1 - slack) u_max T: the interval is ~slack wide, and still filled."""
    robot = human(25.0)
    Tn = 1.2
    limits = Limits(phi_min=-2 * PI, phi_max=-PI, u_max=3.0 / ((1 - slack) * Tn))
    R = reachable_set(robot, theta0=0.3, phi0=-PI, phiT=-PI - 3.0, T=Tn, limits=limits)
    for w in (0.01, 0.5, 0.99):
        target = R.low + w * (R.high - R.low)
        pieces, msg = rate_limited_pieces(robot, [0.3, -PI], [target, -PI - 3.0], Tn, limits=limits)
        assert pieces is not None, msg
        assert sum(D for D, _ in pieces) == pytest.approx(Tn, abs=1e-12)


def test_not_used_without_a_rate_bound():
    pieces, msg = rate_limited_pieces(human(), [0.0, -PI], [1.0, -4.0], T, limits=Limits(phi_min=PHI_MIN,
                                                                                         phi_max=PHI_MAX))
    assert pieces is None and "no rate bound" in msg
