"""Exact reachable sets with rate and joint limits (robustness issue)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import minimize

import acroplan
from acroplan.families.acrobot.reach import Limits, reachable_set

PI = np.pi


def simulate_pieces(robot, theta0, phi0, pieces):
    x = np.array([theta0, phi0], dtype=float)
    for d, u in pieces:
        x = solve_ivp(lambda t, x: robot.rhs(x, [u]), (0, d), x, method="DOP853", rtol=1e-13, atol=1e-13).y[:, -1]
    return x


@pytest.mark.parametrize("u_max", [1.6, 3.0, 10.0, 60.0])
@pytest.mark.parametrize("phis", [(-PI, -2 * PI), (0.3, 1.2), (-2.0, -2.0)])
def test_extremal_controls_reach_the_interval_ends(pike_robot, u_max, phis):
    phi0, phiT = phis
    R = reachable_set(pike_robot, theta0=0.1, phi0=phi0, phiT=phiT, T=2.0, limits=Limits(u_max=u_max))
    assert R.closed and R.success and R.status == "success" and R.low < R.high
    for end in ("low", "high"):
        pieces = R.extremal[end]
        assert all(abs(u) <= u_max * (1 + 1e-15) for _, u in pieces)
        assert sum(d for d, _ in pieces) == pytest.approx(2.0, abs=1e-13)
        x = simulate_pieces(pike_robot, 0.1, phi0, pieces)
        assert x[1] == pytest.approx(phiT, abs=1e-11)
        assert x[0] == pytest.approx(getattr(R, end), abs=1e-10)


def test_no_admissible_motion_beats_the_extremals(pike_robot):
    """A direct numerical optimisation over 40-knot piecewise-linear joint motions stays inside."""
    T, phi0, phiT, U = 2.0, -2.5, -1.0, 4.0
    lim = Limits(u_max=U, phi_min=-3.0, phi_max=-0.5)
    R = reachable_set(pike_robot, theta0=0.0, phi0=phi0, phiT=phiT, T=T, limits=lim)
    K = 40
    dt = T / K
    base = -(float(pike_robot.F(phiT)) - float(pike_robot.F(phi0)))

    def theta_T(inner):
        phi = np.concatenate([[phi0], inner, [phiT]])
        # exact for piecewise-linear phi up to quadrature: Gauss-Legendre on each piece
        x, w = np.polynomial.legendre.leggauss(8)
        a, b = phi[:-1, None], phi[1:, None]
        vals = 1.0 / pike_robot.h(a + (b - a) * (x + 1) / 2)
        return base + pike_robot.P0 * dt * float(np.sum(vals @ (w / 2)))

    D = np.diff(np.eye(K + 1), axis=0)[:, 1:-1]  # rows: phi_{i+1} - phi_i in terms of inner knots
    off = np.zeros(K)
    off[0], off[-1] = -phi0, phiT
    cons = [{"type": "ineq", "fun": lambda z: U * dt - (D @ z + off)},
            {"type": "ineq", "fun": lambda z: U * dt + (D @ z + off)}]
    bounds = [(lim.phi_min, lim.phi_max)] * (K - 1)
    rng = np.random.default_rng(0)
    best_hi, best_lo = -np.inf, np.inf
    for _ in range(4):
        z0 = np.linspace(phi0, phiT, K + 1)[1:-1] + 0.05 * rng.standard_normal(K - 1)
        hi = minimize(lambda z: -theta_T(z), z0, constraints=cons, bounds=bounds, method="SLSQP",
                      options={"maxiter": 300})
        lo = minimize(theta_T, z0, constraints=cons, bounds=bounds, method="SLSQP", options={"maxiter": 300})
        best_hi, best_lo = max(best_hi, -hi.fun), min(best_lo, lo.fun)
    assert best_hi <= R.high + 1e-6 and best_lo >= R.low - 1e-6
    # and the discretised optimum comes close to the exact extremes
    assert best_hi >= R.high - 2e-2 and best_lo <= R.low + 2e-2


def test_rate_bound_narrows_and_converges_to_the_open_interval(pike_robot):
    kw = dict(theta0=0.0, phi0=-PI, phiT=-2 * PI, T=2.0)
    lo, hi = acroplan.reachable_set(pike_robot, **kw).interval
    prev = None
    for U in (2.0, 5.0, 50.0, 5000.0):
        a, b = acroplan.reachable_set(pike_robot, **kw, u_max=U).interval
        assert lo < a < b < hi
        if prev:
            assert a <= prev[0] and b >= prev[1]
        prev = (a, b)
    assert prev[0] == pytest.approx(lo, abs=2e-3) and prev[1] == pytest.approx(hi, abs=2e-3)


def test_joint_limits_narrow_the_interval(pike_robot):
    kw = dict(theta0=0.0, phi0=-2.0, phiT=-2.5, T=1.5)
    lo, hi = acroplan.reachable_set(pike_robot, **kw).interval
    a, b = acroplan.reachable_set(pike_robot, **kw, phi_min=-3.0, phi_max=-1.5).interval
    # 1/h on [-3, -1.5]: largest at -1.5 (nearest the fold at 0), smallest at -3 (nearest straight)
    base = 0.0 - float(pike_robot.F(-2.5) - pike_robot.F(-2.0))
    assert a == pytest.approx(base + pike_robot.P0 * 1.5 / pike_robot.h(-3.0), rel=1e-13)
    assert b == pytest.approx(base + pike_robot.P0 * 1.5 / pike_robot.h(-1.5), rel=1e-13)
    assert lo < a < b < hi


def test_impossible_joint_motion_is_said(pike_robot):
    R = reachable_set(pike_robot, theta0=0, phi0=0.0, phiT=3.0, T=1.0, limits=Limits(u_max=2.0))
    assert not R.success and R.status == acroplan.Status.INFEASIBLE and "allows only 2 rad" in R.message
    # the names of before the one vocabulary (issue #21) still work, with a warning naming the new ones
    with pytest.warns(DeprecationWarning, match="not reach.success"):
        assert R.empty
    with pytest.warns(DeprecationWarning, match="Reach.message"):
        assert "allows only 2 rad" in R.reason
    with pytest.raises(acroplan.InvalidInputError, match="allows only 2 rad"):
        acroplan.reachable_interval(pike_robot, theta0=0, phi0=0.0, phiT=3.0, T=1.0, u_max=2.0)


@pytest.mark.parametrize("kwargs, match", [
    (dict(u_max=-1.0), "u_max: must be > 0"),
    (dict(u_max=float("nan")), "u_max: must be a finite number"),
    (dict(phi_min=1.0, phi_max=0.0), "phi_min: must be < phi_max"),
    (dict(phi_min=0.0, phi_max=0.0), "phi_min: must be < phi_max"),
])
def test_bad_limits_name_the_field(pike_robot, kwargs, match):
    with pytest.raises(acroplan.InvalidInputError, match=match):
        acroplan.plan(pike_robot, times=[0, 1], theta=[0, 1], phi=[0.1, 0.2], **kwargs)
