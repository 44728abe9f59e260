"""Chapter 4: the derived construction against the printed formulas (with the errata), the endpoint
equations, solutions with time moving forward, the failure mode, the flat-output variant."""

import ast
import dataclasses
import inspect
import json
import math
import textwrap

import numpy as np
import pytest
import sympy as sp

import acroplan
from acroplan.core import lie
from acroplan.families.acrobot import nilpotent as nil

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml)
pytestmark = pytest.mark.xdist_group("test_nilpotent")

PI = math.pi


@pytest.fixture(scope="session")
def C():
    return nil.construction()


@pytest.fixture(scope="session")
def robot():
    return acroplan.examples.robot("pike-dive")


def test_time_extended_system_is_eq3(C):
    M1, A1, M2, A2, P0 = C.params
    h = M1 + A1 * sp.cos(C.phi)
    assert sp.simplify(C.Y1 - sp.Matrix([0, 1, P0 / h])).is_zero_matrix
    assert sp.simplify(C.Y2 - sp.Matrix([1, 0, -(M2 + A2 * sp.cos(C.phi)) / h])).is_zero_matrix


def test_model_taylor_coefficients_with_erratum_3(C):
    M1, A1, M2, A2, P0 = C.params
    x1 = C.x[0]
    right1 = P0 / (M1 + A1) + P0 * A1 / (2 * (M1 + A1) ** 2) * x1**2
    right2 = -(M2 + A2) / (M1 + A1) + (A2 * M1 - A1 * M2) / (2 * (M1 + A1) ** 2) * x1**2
    assert sp.simplify(C.X1[2] - right1) == 0 and sp.simplify(C.X2[2] - right2) == 0
    printed1 = P0 / (M1 + A1) + P0 * A1 / (M1 + A1) ** 2 * x1**2  # the text, without the 1/2
    assert sp.simplify(C.X1[2] - printed1) != 0
    assert sp.simplify(C.X1[2] - printed1 + P0 * A1 / (2 * (M1 + A1) ** 2) * x1**2) == 0  # exactly the erratum


def test_feedback_matches_the_text_with_erratum_4(C):
    M1, A1, M2, A2, P0 = C.params
    phi, t = C.phi, C.t
    h = M1 + A1 * sp.cos(phi)
    k = M2 + A2 * sp.cos(phi)
    alpha_text = phi / sp.sin(phi) * h**2 / (M1 + A1) ** 2
    assert sp.simplify(C.alpha - alpha_text) == 0
    bracket_text = 2 * A1 + sp.cos(phi) * (M1 - A1 * sp.cos(phi))  # erratum 4's reading
    beta_text = 1 / phi - bracket_text / (sp.sin(phi) * h)
    assert sp.simplify(C.beta - beta_text) == 0
    Yp1_text = sp.Matrix([0, alpha_text, P0 * phi / sp.sin(phi) * h / (M1 + A1) ** 2])
    Yp2_text = sp.Matrix([1, t * beta_text, P0 * t * (1 / (phi * h) - bracket_text / (sp.sin(phi) * h**2)) - k / h])
    assert sp.simplify(C.Yp1 - Yp1_text).is_zero_matrix
    assert sp.simplify(C.Yp2 - Yp2_text).is_zero_matrix
    v1, v2 = C.v
    assert sp.simplify(C.u1 - (alpha_text * v1 + t * beta_text * v2)) == 0 and C.u2 == v2


def test_hall_basis_of_the_feedback_fields_has_exactly_four_nonzero_elements(C):
    M1, A1, M2, A2, P0 = C.params
    coords = (C.phi, C.t, C.theta)
    fields = [C.Yp1, C.Yp2]
    cache = {}
    nonzero = [w for w in lie.hall_basis(2, 5)
               if not sp.simplify(lie.evaluate(w, fields, coords, cache)).is_zero_matrix]
    assert nonzero == [0, 1, (0, 1), (1, (0, 1))]
    b3 = sp.simplify(lie.evaluate((0, 1), fields, coords, cache))
    b4 = sp.simplify(lie.evaluate((1, (0, 1)), fields, coords, cache))
    assert sp.simplify(b3 - sp.Matrix([0, 0, -A1 * P0 * C.phi / (M1 + A1) ** 2])).is_zero_matrix
    assert sp.simplify(b4 - sp.Matrix([0, 0, -A1 * P0 / (M1 + A1) ** 2])).is_zero_matrix


@pytest.mark.parametrize("phiQ", [PI / 4, -PI / 4])
def test_text_example_solved_with_time_moving_forward(robot, phiQ):
    prob = nil.NilpotentProblem(robot, (PI / 4, 0, 0), (phiQ, 2, 1.4 * PI), 3)
    res = nil.solve_nilpotent(prob)
    assert res.success, res.message
    assert res.residual < 1e-9 and res.margin > 0.1 and res.phi_max < PI
    assert res.verified_error <= 1e-8
    # the endpoint formula agrees with an independent quadrature along the extended system
    t, theta, phi, _ = res.curve(np.array([1.0]))
    assert t[0] == pytest.approx(2.0, abs=1e-12) and phi[0] == pytest.approx(phiQ, abs=1e-12)
    assert theta[0] == pytest.approx(1.4 * PI, abs=1e-9)


@pytest.mark.parametrize("P, Q", [
    ((0.3, 0.0, 0.0), (-0.5, 1.5, 2.0)),
    ((-1.0, 0.0, 1.0), (1.2, 2.5, 5.0)),
    ((2.0, 0.0, 0.0), (2.5, 1.0, 1.2)),
    ((0.2, 1.0, -1.0), (-0.3, 3.0, 2.0)),
])
def test_other_start_and_target_pairs(robot, P, Q):
    prob = nil.NilpotentProblem(robot, P, Q, 3)
    R = acroplan.reachable_set(robot, theta0=P[2], phi0=P[0], phiT=Q[0], T=Q[1] - P[1],
                               limits=acroplan.Limits(phi_min=-PI, phi_max=PI))
    assert R.contains(Q[2])
    res = nil.solve_nilpotent(prob)
    assert res.success, res.message
    assert res.margin > 0 and res.verified_error <= 1e-8


def test_failure_mode_orbit_equivalent_not_trajectory_equivalent(robot):
    prob = nil.NilpotentProblem(robot, (PI / 4, 0, 0), (PI / 4, 2, 1.4 * PI), 3)
    good = nil.solve_nilpotent(prob, verify=False)
    bad = nil.counterexample(prob, good.m)
    assert bad.residual < 1e-9 and bad.margin < 0
    t, theta, phi, u1 = bad.curve(np.linspace(0, 1, 401))
    assert theta[-1] == pytest.approx(1.4 * PI, abs=1e-8) and t[-1] == pytest.approx(2.0, abs=1e-12)
    assert np.any(np.diff(t) < 0)  # the clock runs backwards somewhere
    assert np.all(np.diff(good.curve(np.linspace(0, 1, 401))[0]) > 0)


def test_no_solution_reports_the_best_margin(robot):
    """A target beyond the exact reachable interval: the equations alone can be met only by going back
    in time, so the solver must report the best (negative) margin, never success."""
    P, T = (0.5, 0.0, 0.0), 1.0
    R = acroplan.reachable_set(robot, theta0=0.0, phi0=0.5, phiT=0.5, T=T,
                               limits=acroplan.Limits(phi_min=-PI, phi_max=PI))
    prob = nil.NilpotentProblem(robot, P, (0.5, T, R.high + 1.0), 3)
    res = nil.solve_nilpotent(prob, starts=4)
    assert not res.success and res.status == "infeasible"
    assert res.margin <= 0 and "best margin" in res.message and f"{res.margin:.4g}" in res.message


def test_flat_output_variant_moves_time_forward_by_construction(robot):
    for phiQ in (PI / 4, -PI / 4):
        prob = nil.NilpotentProblem(robot, (PI / 4, 0, 0), (phiQ, 2, 1.4 * PI), 3)
        res = nil.solve_flat_y(prob)
        assert res.success and res.margin > 0 and res.verified_error <= 1e-8


def test_equations_printed_like_the_text(robot):
    """The text's third equation is int V1 v2 = h1 h2 - I, term for term (NOTES.md erratum 5)."""
    m1, m2, h1, h2, I, J = nil.iterated_integrals(3)
    s = dict(zip(m1 + m2, sp.symbols("m10:14") + sp.symbols("m20:24")))
    text_third = (sp.Rational(1, 32) * s[m2[3]] * s[m1[3]] + sp.Rational(1, 28) * s[m2[2]] * s[m1[3]]
                  + sp.Rational(1, 21) * s[m2[3]] * s[m1[2]] + sp.Rational(1, 24) * s[m2[1]] * s[m1[3]]
                  + sp.Rational(1, 18) * s[m2[2]] * s[m1[2]] + sp.Rational(1, 12) * s[m2[3]] * s[m1[1]]
                  + sp.Rational(1, 20) * s[m2[0]] * s[m1[3]] + sp.Rational(1, 15) * s[m2[1]] * s[m1[2]]
                  + sp.Rational(1, 10) * s[m2[2]] * s[m1[1]] + sp.Rational(1, 5) * s[m2[3]] * s[m1[0]]
                  + sp.Rational(1, 12) * s[m2[0]] * s[m1[2]] + sp.Rational(1, 8) * s[m2[1]] * s[m1[1]]
                  + sp.Rational(1, 4) * s[m2[2]] * s[m1[0]] + sp.Rational(1, 6) * s[m2[0]] * s[m1[1]]
                  + sp.Rational(1, 3) * s[m2[1]] * s[m1[0]] + sp.Rational(1, 2) * s[m2[0]] * s[m1[0]])
    assert sp.expand((h1 * h2 - I).subs(s) - text_third) == 0
    # the text's fourth equation is int V1 V2 v2 = h1 h2^2 / 2 - J / 2 (integration by parts)
    e = sp.Symbol("e")
    v1 = sum(s[m1[i]] * e**i for i in range(4))
    v2 = sum(s[m2[i]] * e**i for i in range(4))
    V1, V2 = sp.integrate(v1, (e, 0, e)), sp.integrate(v2, (e, 0, e))
    fourth = sp.integrate(sp.expand(V1 * V2 * v2), (e, 0, 1))
    assert sp.expand(fourth - (h1 * h2**2 / 2 - J / 2).subs(s)) == 0
    assert sp.expand(fourth).coeff(s[m1[0]] * s[m2[0]] * s[m2[1]]) == sp.Rational(3, 8)  # as printed
    # the first equation's constant: 2 / alpha(pi/4)
    prob = nil.NilpotentProblem(robot, (PI / 4, 0, 0), (-PI / 4, 2, 1.4 * PI), 3)
    assert prob.x2Q == pytest.approx(0.908647, abs=1e-6)
    assert prob.Q[0] - prob.P[0] == pytest.approx(-6283 / 4000, abs=1e-4)  # the text's -1.57075
    text = nil.format_equations(prob)
    assert "m10 + m11/2 + m12/3 + m13/4 - 0.9086469918797" in text


@pytest.mark.parametrize("P, Q, match", [
    ((PI, 0, 0), (0.5, 1, 1), r"P.phi: must satisfy \|phi\| < pi"),
    ((0.5, 1, 0), (0.5, 1, 1), "Q.t: must be later than P.t"),
    ((0.5, 0, 0), (0.5, 1), "Q: must be three finite numbers"),
])
def test_bad_nilpotent_input(robot, P, Q, match):
    with pytest.raises(acroplan.InvalidInputError, match=match):
        nil.NilpotentProblem(robot, P, Q, 3)


# ---------------------------------------------------------------- the result types (one per method)
@pytest.fixture(scope="session")  # (a module fixture is rebuilt when xdist interleaves another module)
def ch4(robot):
    """The text's example solved both ways, and its counterexample."""
    prob = nil.NilpotentProblem(robot, (PI / 4, 0, 0), (-PI / 4, 2, 1.4 * PI), 3)
    series = nil.solve_nilpotent(prob)
    return prob, series, nil.solve_flat_y(prob), nil.counterexample(prob, series.m)


def test_each_method_returns_its_own_result_type(ch4):
    prob, series, flat, bad = ch4
    assert type(series) is nil.SeriesResult and type(bad) is nil.SeriesResult
    assert type(flat) is nil.FlatYResult
    for res, method in ((series, "nilpotent"), (bad, "nilpotent"), (flat, "flat-y")):
        assert isinstance(res, nil.NilpotentResult) and res.method == method
        assert res.to_dict()["method"] == method
    assert series.success and flat.success
    assert set(series.to_dict()["coefficients"]) == {"v1", "v2"}
    assert set(flat.to_dict()["coefficients"]) == {"phi_of_y"}
    # replace keeps the subclass; the base is abstract
    assert type(dataclasses.replace(flat, message="x")) is nil.FlatYResult
    with pytest.raises(TypeError):
        nil.NilpotentResult(success=True, status="success", message="", problem=prob, m=series.m, residual=0.0,
                            margin=1.0, phi_max=0.0)


def test_results_are_frozen_and_hold_no_late_caches(ch4):
    _, series, flat, _ = ch4
    for res in (series, flat):
        assert not res.m.flags.writeable
        with pytest.raises(dataclasses.FrozenInstanceError):
            res.margin = 0.0
        res.eps_of_t(1.0)
        assert "_table" not in vars(res)
    assert "_pp" in vars(series)  # built at construction


def test_no_method_of_the_base_branches_on_the_method():
    src = inspect.getsource(nil.NilpotentResult)
    assert "self.method" not in src
    for cls in (nil.NilpotentResult, nil.SeriesResult, nil.FlatYResult):
        tree = ast.parse(textwrap.dedent(inspect.getsource(cls)))
        for node in ast.walk(tree):
            if isinstance(node, ast.Compare):
                names = {n.attr for n in ast.walk(node) if isinstance(n, ast.Attribute)}
                assert "method" not in names, f"{cls.__name__} compares .method: {ast.unparse(node)}"


@pytest.mark.parametrize("which", [1, 2])
def test_evaluate_meets_P_and_Q_and_gives_u_of_t(ch4, which):
    prob, res = ch4[0], ch4[which]
    t = np.linspace(prob.P[1], prob.Q[1], 9)
    S = res.evaluate(t)
    assert isinstance(S, acroplan.Samples)
    assert S.states.shape == (2, 9) and S.inputs.shape == (1, 9) and np.array_equal(S.t, t)
    assert S.state_names == ("theta", "phi") and S.input_names == ("u",)
    assert S.theta[0] == pytest.approx(prob.P[2], abs=1e-9) and S.phi[0] == pytest.approx(prob.P[0], abs=1e-9)
    assert S.theta[-1] == pytest.approx(prob.Q[2], abs=1e-9) and S.phi[-1] == pytest.approx(prob.Q[0], abs=1e-9)
    assert np.array_equal(S.u, [res.u_of_t(x) for x in t])
    # interior points lie on the curve at the mapped-back virtual time
    e = res.eps_of_t(t[4])
    tc, thc, phc, _ = res.curve(np.array([e]))
    assert tc[0] == pytest.approx(t[4], abs=1e-12)
    assert (S.theta[4], S.phi[4]) == pytest.approx((thc[0], phc[0]), abs=1e-12)
    assert res.evaluate(prob.Q[1]).states.shape == (2, 1)


def test_evaluate_refuses_times_outside_and_backward_clocks(ch4):
    prob, series, _, bad = ch4
    for t in (prob.P[1] - 0.1, prob.Q[1] + 0.1, float("nan")):
        with pytest.raises(ValueError, match=r"\[P.t, Q.t\]"):
            series.evaluate([prob.P[1], t])
    with pytest.raises(ValueError, match="does not run forward"):
        bad.evaluate([prob.P[1]])


def test_to_json_round_trips_to_to_dict(ch4):
    for res in ch4[1:3]:
        text = res.to_json()
        assert text.startswith('{\n  "status"')  # indent 2 by default
        assert json.loads(text) == res.to_dict()
        assert "\n" not in res.to_json(indent=None)


def test_plot_gives_the_figures_of_plot_nilpotent(ch4):
    import matplotlib.pyplot as plt

    _, series, flat, bad = ch4
    try:
        assert set(series.plot(samples=41)) == {"input", "states", "u1"}
        assert set(series.plot(bad, samples=41)) == {"input", "states", "u1", "failure_mode"}
        assert set(flat.plot(samples=41)) == {"input", "states", "u1"}
    finally:
        plt.close("all")


def test_the_iterated_integrals_are_numpy_polynomials_own_bit_for_bit():
    """equations.py's _integrals takes numpy.polynomial's steps without its argument handling (the
    endpoint equations are evaluated thousands of times a solve): on random coefficients of every
    degree, with zero, trailing-zero and all-zero cases, it gives polyint / polymul / polyval's
    numbers exactly, in the same run (so the solver's results did not change in a bit)."""
    from numpy.polynomial import polynomial as Pn

    from acroplan.families.acrobot.nilpotent.equations import _at1, _integrals, _split

    rng = np.random.default_rng(3)
    for trial in range(3000):
        d = int(rng.integers(1, 13))
        m = rng.normal(size=2 * (d + 1)) * 10.0 ** rng.uniform(-3, 3, size=2 * (d + 1))
        if trial % 5 == 0:
            m[d - 1:d + 1] = 0.0  # v1's top coefficients: trimmed by numpy
        if trial % 7 == 0:
            m[-1] = 0.0
        if trial % 97 == 0:
            m[:] = 0.0
        v1, v2 = _split(m, d)
        V1, V2 = Pn.polyint(v1), Pn.polyint(v2)
        want = (Pn.polyval(1.0, V1), Pn.polyval(1.0, V2), Pn.polyval(1.0, Pn.polyint(Pn.polymul(V2, v1))),
                Pn.polyval(1.0, Pn.polyint(Pn.polymul(Pn.polymul(V2, V2), v1))))
        _, _, W1, W2, I, J = _integrals(m, d)
        assert (_at1(W1), _at1(W2), I, J) == tuple(float(w) for w in want), (d, m)
