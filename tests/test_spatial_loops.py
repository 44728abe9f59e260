"""Large reorientations of spatial bodies within their limits (issue #22): the two-joint cat of the
issue, the bundled cat by repeated loops, and the limit-aware steps of the refinement."""

import numpy as np
import pytest

import acroplan
from acroplan.core.limits import violation
from acroplan.core.linalg import least_norm_step, least_squares_step
from acroplan.families.spatial.check import pinocchio_errors
from acroplan.families.spatial.examples import falling_cat_turn
from acroplan.families.spatial.zoo import long_axis_turn, two_joint_cat

pytest.importorskip("pinocchio")


def _check(body, kw, r):
    assert r.success, r.message
    x0 = np.array([kw[n][0] for n in body.state_names])
    assert pinocchio_errors(body, x0, r.segments).max() <= 1e-9
    lim = body.default_limits()
    for seg in r.segments:
        v = violation(body, seg.basis, seg.start, seg.t1 - seg.t0, seg.basis_coefficients, lim)
        assert v["u"] <= 1e-9 and v["state"] <= 1e-9
        assert seg.method != "deform+limits"  # no constrained repair was needed


def test_the_two_joint_cat_turns_over_within_its_limits():
    cat = two_joint_cat()
    kw = long_axis_turn(cat, [0.6, 0.0], 1.0)
    r = acroplan.plan(cat, **kw)
    _check(cat, kw, r)
    assert r.evaluations <= 100


def test_the_bundled_cat_turns_by_repeated_loops():
    cat, kw = falling_cat_turn()
    r = acroplan.plan(cat, **kw)
    _check(cat, kw, r)
    assert {s.method for s in r.segments} == {"loops"} and len(r.segments) >= 2
    # the loops are copies: the same input, each from where the last one ended
    c = r.segments[0].basis_coefficients
    assert all(np.array_equal(s.basis_coefficients, c) for s in r.segments)
    assert r.evaluations <= 60


@pytest.mark.parametrize("name, most", [("astronaut_yaw", 400), ("twisting_somersault", 100)])
def test_the_astronaut_and_the_diver_need_no_constrained_repair(name, most):
    """Regressions of issue #22: the yaw's fourth segment (a loop that cannot make its turn inside the
    abduction range at 6 coefficients) was polished from its guess into SLSQP, 1644 evaluations,
    before the larger bases' loops were tried (221 evaluations in all now); the twisting somersault's
    second segment (L != 0, an ill-conditioned Jacobian) went to SLSQP before the refinement's
    corrector (37 now)."""
    from acroplan.families.spatial import examples

    body, kw = getattr(examples, name)()
    r = acroplan.plan(body, **kw)
    _check(body, kw, r)
    assert r.evaluations <= most, r.evaluations


def test_least_norm_step_is_the_shortest_feasible_step():
    rng = np.random.default_rng(0)
    for _ in range(10):
        J = rng.normal(size=(3, 10))
        feasible = rng.normal(size=10)
        r = J @ feasible
        G = rng.normal(size=(200, 10))
        h = G @ feasible + rng.uniform(0.0, 2.0, 200)
        d, ok = least_norm_step(J, r, G, h)
        assert ok and np.allclose(J @ d, r, atol=1e-12) and np.all(G @ d <= h + 1e-9)
        # the optimality conditions: d = -J^T nu - G_A^T mu with mu >= 0 on the active rows
        active = np.abs(G @ d - h) <= 1e-8
        M = np.vstack([J, G[active]])
        lam = np.linalg.lstsq(M.T, -d, rcond=None)[0]
        assert np.allclose(M.T @ lam, -d, atol=1e-9) and np.all(lam[3:] >= -1e-9)
        assert np.linalg.norm(d) <= np.linalg.norm(feasible) + 1e-12
    J = np.eye(3, 10)
    G = np.zeros((1, 10))
    G[0, 0] = 1.0
    d, ok = least_norm_step(J, np.array([1.0, 0.0, 0.0]), G, np.array([0.5]))
    assert not ok  # d_0 = 1 is needed and at most 0.5 allowed


def test_least_squares_step_comes_closest_under_the_limits():
    rng = np.random.default_rng(1)
    J = rng.normal(size=(3, 10))
    r = 5.0 * rng.normal(size=3)
    G = rng.normal(size=(100, 10))
    h = rng.uniform(0.1, 1.0, 100)
    d, ok = least_squares_step(J, r, G, h, damping=1e-3)
    assert ok and np.all(G @ d <= h + 1e-9)
    mu = 1e-3 * np.linalg.norm(J, 2)

    def cost(x):
        return float(np.sum((J @ x - r) ** 2) + mu * mu * x @ x)

    # no feasible point nearby does better (the optimum of a convex problem)
    for _ in range(200):
        e = 1e-3 * rng.normal(size=10)
        if np.all(G @ (d + e) <= h):
            assert cost(d + e) >= cost(d) - 1e-9
