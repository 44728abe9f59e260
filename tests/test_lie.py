"""acroplan.lie: brackets, Hall basis, growth vectors, nilpotency, one-forms."""

import numpy as np
import pytest
import sympy as sp

from acroplan.core import lie
from acroplan import Acrobot


def random_field(rng, x):
    """A random polynomial vector field (polynomials keep the identities checkable by expansion)."""
    terms = [sp.Integer(1), *x, x[0] * x[1], x[2] ** 3, x[1] ** 2]
    return sp.Matrix([sum(sp.Rational(int(rng.integers(-3, 4)), 1) * t for t in terms) for _ in x])


def test_bracket_antisymmetry_and_jacobi():
    rng = np.random.default_rng(0)
    x = sp.symbols("x0 x1 x2")
    f, g, h = (random_field(rng, x) for _ in range(3))
    assert sp.expand(lie.bracket(f, g, x) + lie.bracket(g, f, x)).is_zero_matrix
    jac = (lie.bracket(f, lie.bracket(g, h, x), x) + lie.bracket(g, lie.bracket(h, f, x), x)
           + lie.bracket(h, lie.bracket(f, g, x), x))
    assert sp.expand(jac).is_zero_matrix
    assert not lie.bracket(f, g, x).is_zero_matrix  # the test is not vacuous


@pytest.mark.parametrize("k", [2, 3])
def test_hall_basis_sizes_follow_witt(k):
    basis = lie.hall_basis(k, 6 if k == 2 else 4)
    for r in range(1, (6 if k == 2 else 4) + 1):
        assert sum(1 for w in basis if lie._length(w) == r) == lie.hall_count(k, r)
    assert [lie.hall_count(2, r) for r in range(1, 8)] == [2, 1, 2, 3, 6, 9, 18]
    assert lie.hall_basis(2, 3) == (0, 1, (0, 1), (0, (0, 1)), (1, (0, 1)))


def test_growth_vectors_of_known_systems():
    x, y, z = sp.symbols("x y z")
    brockett = [[1, 0, -y], [0, 1, x]]
    assert lie.growth_vector(brockett, (x, y, z), {x: 0.3, y: -0.2, z: 0.0}) == (2, 3)
    x1, x2, x3, x4 = sp.symbols("x1:5")
    chained = [[1, 0, x2, x3], [0, 1, 0, 0]]
    assert lie.growth_vector(chained, (x1, x2, x3, x4), {x1: 0.1, x2: 0.2, x3: 0.3, x4: 0.4}) == (2, 3, 4)
    # car with one trailer (Murray & Sastry): x, y, steering phi, car heading th0, trailer heading th1
    X, Y, ph, t0, t1 = sp.symbols("X Y phi th0 th1")
    drive = [sp.cos(t0), sp.sin(t0), 0, sp.tan(ph), sp.sin(t0 - t1)]
    steer = [0, 0, 1, 0, 0]
    pt = {X: 0.0, Y: 0.0, ph: 0.2, t0: 0.3, t1: -0.1}
    assert lie.growth_vector([drive, steer], (X, Y, ph, t0, t1), pt) == (2, 3, 4, 5)
    assert lie.larc([drive, steer], (X, Y, ph, t0, t1), pt)


def test_momentum_one_form_is_not_exact():
    """Chapter 2: h dtheta + k dphi - P0 dt is not exact, and not integrable where P0 A1 sin(phi) != 0."""
    (theta, phi), (M1, A1, M2, A2, P0) = Acrobot.example().symbols()
    t = sp.Symbol("t")
    omega = [M1 + A1 * sp.cos(phi), M2 + A2 * sp.cos(phi), -P0]
    coords = (theta, phi, t)
    assert not lie.is_exact(omega, coords)
    w = lie.frobenius(omega, coords)
    assert sp.simplify(w - P0 * A1 * sp.sin(phi)) == 0 or sp.simplify(w + P0 * A1 * sp.sin(phi)) == 0
    assert lie.is_exact([1, 0, 0], coords)  # d theta is exact: the check can say yes


def test_acrobot_bracket_vanishes_at_folded_and_straight_and_when_holonomic():
    (theta, phi), (M1, A1, M2, A2, P0) = Acrobot.example().symbols()
    f, G = Acrobot.example().symbolic()
    br = lie.bracket(f, G, (theta, phi))
    assert sp.simplify(br[0] + P0 * A1 * sp.sin(phi) / (M1 + A1 * sp.cos(phi)) ** 2) == 0 and br[1] == 0
    for where in (0, sp.pi, -sp.pi):
        assert sp.simplify(br.subs(phi, where)).is_zero_matrix
    assert sp.simplify(br.subs(P0, 0)).is_zero_matrix
    assert not sp.simplify(br.subs(phi, sp.Rational(1, 2))).is_zero_matrix


def test_nilpotency_check():
    x1, x2, x3 = sp.symbols("x1:4")
    assert lie.is_nilpotent([[1, 0, 0], [0, 1, x1]], (x1, x2, x3), step=2)
    assert not lie.is_nilpotent([[1, 0, 0], [0, 1, sp.sin(x1)]], (x1, x2, x3), step=3)
