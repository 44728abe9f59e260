"""Optimal plans and effort through the front doors (issue #13): ``plan(objective=, tau_max=)``,
``plan_many`` with the same keywords, and the generic torque hook of the core
(``ControlAffineSystem.torque_model``, ``PlanResult.torques``/``effort``/``evaluate``/``to_dict``).

* closed-form optima: a damped oscillator (min integral of a^2, the controllability Gramian by Van
  Loan's matrix exponential) and a flywheel with a torque model of the test's own (min integral of
  tau^2: a cubic joint rate, in closed form);
* an energy-optimal plan costs no more than the feasible plan, with its KKT residual below the
  target it reports, and is verified like any plan;
* torque limits (with rate limits) hold on a dense grid, or the plan says it did not converge;
* the result's torques equal the acrobot's formula on an independent evaluation of the motion;
* without a torque model nothing changes, and options that need one are refused by name.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest
import scipy.linalg
import sympy as sp

import acroplan
from acroplan.core.errors import InvalidInputError
from acroplan.core.optimal import KKT_TOL, RTOL, EnergyOptimal, TorqueOptimal, energy
from acroplan.core.system import ControlAffineSystem
from acroplan.families.acrobot.effort import effort_summary, joint_torque, torques
from acroplan.zoo import random_segment

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml)
pytestmark = pytest.mark.xdist_group("test_optimal")


def plan_energy(result) -> float:
    return sum(energy(s.basis, s.t1 - s.t0, s.basis_coefficients) for s in result.segments)


def theta_at(robot, theta0, phi0, phiT, T, w):
    lo, hi = robot.reachable_interval(theta0=theta0, phi0=phi0, phiT=phiT, T=T)
    return lo + w * (hi - lo)


@pytest.fixture(scope="module")
def body():
    return acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                          torso_length=0.35, leg_length=0.45, angular_momentum=10.0)


@pytest.fixture(scope="module")
def problem(body):
    T, phi0, phiT = 1.4, -1.2, -2.6
    return dict(times=[0, T], theta=[0.1, theta_at(body, 0.1, phi0, phiT, T, 0.7)], phi=[phi0, phiT],
                conditions="free")


# ----------------------------------------------------------------------------------------- closed forms
@dataclasses.dataclass(frozen=True)
class OptimalTestOscillator(ControlAffineSystem):
    """q' = v, v' = -w2 q - c v + a: linear, not nilpotent (the optimal input is not a polynomial)."""

    state_names = ("q", "v")
    input_names = ("a",)
    param_names = ("w2", "c")
    w2: float = 4.0
    c: float = 0.6

    @classmethod
    def symbolic_fields(cls, x, p):
        return sp.Matrix([x[1], -p[0] * x[0] - p[1] * x[1]]), sp.Matrix([0, 1])


def least_energy(A, B, x0, x1, T) -> float:
    """min int_0^T |u|^2 dt from x0 to x1 for x' = A x + B u: d^T W^-1 d with d = x1 - e^{AT} x0 and
    the Gramian W = int_0^T e^{As} B B^T e^{A^T s} ds (Van Loan's block exponential)."""
    n = A.shape[0]
    M = np.zeros((2 * n, 2 * n))
    M[:n, :n], M[:n, n:], M[n:, n:] = -A, B @ B.T, A.T
    E = scipy.linalg.expm(M * T)
    eAT = E[n:, n:].T
    W = eAT @ E[:n, n:]
    d = np.asarray(x1, float) - eAT @ np.asarray(x0, float)
    return float(d @ np.linalg.solve(W, d))


CASES = [(1.7, (0.3, -0.4), (1.9, 0.8)), (3.0, (0.0, 0.0), (1.0, 0.0)), (5.0, (1.0, 0.0), (-1.0, 0.5))]


@pytest.mark.parametrize("T, x0, x1", CASES)
def test_energy_objective_reaches_the_gramian_optimum_of_a_linear_system(T, x0, x1):
    """With 14 coefficients the optimum is the closed form's to 1e-8 (measured: at most 4.3e-12);
    with the ladder (no n_coefficients) within the ladder's rtol, with the change it stopped on."""
    sysm = OptimalTestOscillator()
    A, B = np.array([[0.0, 1.0], [-sysm.w2, -sysm.c]]), np.array([[0.0], [1.0]])
    E = least_energy(A, B, x0, x1, T)
    kw = dict(times=[0, T], q=[x0[0], x1[0]], v=[x0[1], x1[1]], conditions="free", objective="energy")
    r = acroplan.plan(sysm, n_coefficients=14, **kw)
    assert r.success and r.verified, r.message
    assert plan_energy(r) == pytest.approx(E, rel=1e-8)
    opt = r.segments[0].optimality
    assert opt["one_size"] and opt["converged"] and opt["kkt"] <= opt["kkt_tol"] == KKT_TOL
    assert opt["cost"] == pytest.approx(plan_energy(r), rel=1e-13)
    ladder = acroplan.plan(sysm, **kw)
    assert ladder.success, ladder.message
    lo = ladder.segments[0].optimality
    assert lo["converged"] and lo["converged_in_basis"] and len(lo["ladder"]) >= 2
    assert E <= plan_energy(ladder) <= E * (1 + RTOL)
    assert r.objective == ladder.objective == "energy" and r.to_dict()["objective"] == "energy"


@dataclasses.dataclass(frozen=True)
class OptimalTestFlywheel(ControlAffineSystem):
    """A joint q driven at rate u (q' = u), and z' = q (so the endpoint constrains the joint's mean);
    torque tau = I u' (a flywheel of inertia I): a system with a torque model of its own."""

    state_names = ("q", "z")
    input_names = ("u",)
    param_names = ("I",)
    rate_inputs = {"u": "q"}
    I: float = 2.5

    @classmethod
    def symbolic_fields(cls, x, p):
        return sp.Matrix([0, x[0]]), sp.Matrix([1, 0])


class FlywheelTorque:
    """tau = I u'(t) alone (no Jacobian: the core takes finite differences)."""

    joint_names = ("q",)

    def unsupported(self, system):
        return None if isinstance(system, OptimalTestFlywheel) else "not a flywheel"

    def __call__(self, system, basis, x0, T, c, s):
        c = np.asarray(c, dtype=float).reshape(1, -1)
        return system.I * (basis.matrix(np.asarray(s, dtype=float), 1) @ c[0])[None, :] / T


acroplan.register_torque_model(OptimalTestFlywheel, lambda system: FlywheelTorque())


def test_torque_values_of_a_model_without_a_torques_method_is_its_call():
    """A torque model that is a bare callable (no ``torques`` method, no Jacobian): ``torque_values``
    is its call, tau = I u'/T exactly."""
    from acroplan.core.basis import Legendre
    from acroplan.core.objectives import torque_values

    sysm, basis = OptimalTestFlywheel(), Legendre(5)
    c = np.array([0.3, -1.0, 0.5, 0.25, -0.125])
    s = np.linspace(0.0, 1.0, 7)
    got = torque_values(FlywheelTorque(), sysm, basis, np.zeros(2), 1.3, c, s)
    assert got.shape == (1, 7)
    assert np.array_equal(got[0], sysm.I * (basis.matrix(s, 1) @ c) / 1.3)


def flywheel_optimum(I, T, q0, q1, z0, z1):
    """min int (I u')^2 dt with q(T) = q1, z(T) = z1 and u free at the ends: the Euler-Lagrange
    equation makes u'' linear, the natural boundary conditions u'(0) = u'(T) = 0, so
    u = alpha + k (T t^2/2 - t^3/3) with int u = alpha T + k T^4/12 = q1 - q0 and
    int (T - t) u = alpha T^2/2 + k T^5/40 = z1 - z0 - q0 T; the cost is I^2 k^2 T^5/30 and the
    peak torque I |k| T^2/4 (at T/2)."""
    D1, D2 = q1 - q0, z1 - z0 - q0 * T
    k = -60.0 * (D2 - D1 * T / 2) / T**5
    alpha = (D1 - k * T**4 / 12) / T
    return alpha, k, I**2 * k**2 * T**5 / 30, I * abs(k) * T**2 / 4


def test_torque_objective_reaches_the_closed_form_optimum_through_the_generic_hook():
    sysm = OptimalTestFlywheel()
    T, (q0, q1), (z0, z1) = 1.3, (0.2, 1.1), (0.0, 1.6)
    alpha, k, cost, peak = flywheel_optimum(sysm.I, T, q0, q1, z0, z1)
    r = acroplan.plan(sysm, times=[0, T], q=[q0, q1], z=[z0, z1], conditions="free", objective="torque")
    assert r.success and r.verified, r.message
    seg = r.segments[0]
    assert seg.method == "torque-optimal" and seg.optimality["objective"] == "torque"
    assert seg.optimality["cost"] == pytest.approx(cost, rel=1e-8)
    assert seg.optimality["kkt"] <= seg.optimality["kkt_tol"] and seg.optimality["converged"]
    t = np.linspace(0, T, 101)
    np.testing.assert_allclose(seg.input(t)[0], alpha + k * (T * t**2 / 2 - t**3 / 3), atol=1e-8)
    # the generic effort and torques of a system the core knows nothing about
    tau, power = r.torques(t)
    assert tau.shape == power.shape == (101, 1)
    np.testing.assert_allclose(tau[:, 0], sysm.I * k * t * (T - t), atol=1e-8 * max(1.0, peak))
    np.testing.assert_allclose(power[:, 0], tau[:, 0] * seg.input(t)[0], rtol=1e-14)
    e = r.effort()
    assert list(e) == ["q"] and e["q"].input == "u"
    assert e["q"].torque_squared == pytest.approx(cost, rel=1e-8)
    assert e["q"].peak_torque == pytest.approx(peak, rel=1e-8)
    assert e["q"].input_squared == pytest.approx(float(np.trapezoid(seg.input(np.linspace(0, T, 200001))[0] ** 2,
                                                                    np.linspace(0, T, 200001))), rel=1e-8)


# ----------------------------------------------------------------------------------------- acrobot plans
@pytest.mark.parametrize("seed", [3, 4])
def test_an_energy_optimal_plan_costs_no_more_than_the_feasible_plan(seed):
    p = random_segment(np.random.default_rng(seed))
    kw = dict(conditions="free", **p.plan_kwargs())
    fast = acroplan.plan(p.robot, **kw)
    opt = acroplan.plan(p.robot, objective="energy", **kw)
    assert fast.success and opt.success, opt.message
    assert fast.objective is None and opt.objective == "energy"
    assert opt.verified and opt.verification == "family"
    assert max(s.verified_error for s in opt.segments) <= 1e-9
    assert plan_energy(opt) <= plan_energy(fast) * (1 + 1e-12)
    d = json.loads(opt.to_json())
    o = d["segments"][0]["optimality"]
    assert o["kkt"] <= o["kkt_tol"] == KKT_TOL and o["converged"] and o["converged_in_basis"]
    assert o["cost"] == pytest.approx(plan_energy(opt), rel=1e-12)
    assert o["basis_size"] == len(d["segments"][0]["basis_coefficients"]["u"])
    assert "optimality" not in json.loads(fast.to_json())["segments"][0]
    assert "energy-optimal" in opt.message and "converged on every interval" in opt.message


def test_torque_objective_lowers_the_integral_of_tau_squared(body, problem):
    fast = acroplan.plan(body, **problem)
    e_opt = acroplan.plan(body, objective="energy", **problem)
    t_opt = acroplan.plan(body, objective="torque", **problem)
    assert fast.success and e_opt.success and t_opt.success, t_opt.message
    tau2 = {k: r.effort()["phi"].torque_squared for k, r in (("fast", fast), ("energy", e_opt), ("torque", t_opt))}
    assert tau2["torque"] <= min(tau2["energy"], tau2["fast"]) * (1 + 1e-6)
    assert plan_energy(e_opt) <= plan_energy(t_opt) * (1 + 1e-9)
    o = t_opt.segments[0].optimality
    assert o["objective"] == "torque" and o["cost"] == pytest.approx(tau2["torque"], rel=1e-6)
    assert o["kkt"] <= o["kkt_tol"]


def dense_peak(result, n=20001):
    t = np.linspace(result.times[0], result.times[-1], n)
    return float(np.max(np.abs(result.torques(t)[0])))


def test_torque_limits_hold_together_with_rate_limits(body, problem):
    """For each objective, a torque limit 15% below that objective's unlimited peak and a rate limit
    5% above its largest rate: the limits hold on a dense grid and the torque limit binds."""
    for objective, limit in (("energy", lambda v: v), ("torque", lambda v: {"phi": v}), (None, lambda v: [v])):
        free = acroplan.plan(body, objective=objective or "energy", n_coefficients=10, **problem)
        tau_max, u_max = 0.85 * free.effort()["phi"].peak_torque, 1.05 * free.max_abs_u
        # one basis size keeps the test short (the ladder under torque limits: tests/test_effort.py)
        r = acroplan.plan(body, objective=objective, tau_max=limit(tau_max), u_max=u_max, n_coefficients=10,
                          **problem)
        assert r.success and r.verified, r.message
        assert r.objective == (objective or "energy") and r.torque_limits == {"phi": pytest.approx(tau_max)}
        assert tau_max * (1 - 5e-3) <= dense_peak(r) <= tau_max * (1 + 1e-9)  # binding, and honoured
        assert r.effort()["phi"].peak_torque <= tau_max * (1 + 1e-9)
        assert r.max_abs_u <= u_max * (1 + 1e-9)
        assert r.to_dict()["torque_limits"] == {"phi": pytest.approx(tau_max)}
        o = r.segments[0].optimality
        assert o["solver"] == "sqp"  # the limits are inequalities of the SQP itself (they went to SLSQP before)
        assert o["kkt"] <= o["kkt_tol"], o  # first-order optimal with the active limits' multipliers
        cost = r.segments[0].optimality["cost"]
        assert cost >= free.segments[0].optimality["cost"] * (1 - 1e-9)  # the limit costs something


def test_an_impossible_torque_limit_is_reported_not_hidden(body, problem):
    free = acroplan.plan(body, objective="energy", **problem)
    r = acroplan.plan(body, objective="energy", tau_max=0.02 * free.effort()["phi"].peak_torque, n_coefficients=6,
                      **problem)
    assert r.status == "not_converged" and not r.success
    assert "segment 0" in r.message and "max(|tau| - tau_max)" in r.message
    assert "effort" in r.to_dict() and r.to_dict()["effort"] is None


def test_result_torques_equal_the_acrobots_formula(body):
    """PlanResult.torques (the generic hook) against joint_torque evaluated on the motion rebuilt
    from the Legendre coefficients by numpy's Legendre class (not the basis code), on a two-segment
    plan; and the acrobot's torques() and effort_summary() are the same numbers."""
    t = [0.0, 1.2, 2.5]
    phi = [-1.0, -2.4, -0.6]
    th1 = theta_at(body, -0.3, phi[0], phi[1], 1.2, 0.35)
    th2 = theta_at(body, th1, phi[1], phi[2], 1.3, 0.6)
    r = acroplan.plan(body, times=t, theta=[-0.3, th1, th2], phi=phi, conditions="free", objective="energy")
    assert r.success, r.message
    for seg in r.segments:
        tt = np.linspace(seg.t0, seg.t1, 401)[1:]  # (a shared time belongs to the earlier segment)
        T = seg.t1 - seg.t0
        leg = np.polynomial.legendre.Legendre(seg.basis_coefficients[0], domain=[0, 1])
        s = (tt - seg.t0) / T
        ph, u, du = seg.start[1] + T * leg.integ(lbnd=0)(s), leg(s), leg.deriv()(s) / T
        want = joint_torque(body, ph, u, du)
        tau, power = r.torques(tt)
        np.testing.assert_allclose(tau[:, 0], want, rtol=1e-11, atol=1e-11 * np.max(np.abs(want)))
        np.testing.assert_allclose(power[:, 0], want * u, rtol=1e-11, atol=1e-11 * np.max(np.abs(want * u)))
        a_tau, a_pow = torques(r, tt)
        assert np.array_equal(a_tau, tau[:, 0]) and np.array_equal(a_pow, power[:, 0])
    assert effort_summary(r) == r.effort()["phi"]
    # evaluate, to_pandas and to_dict carry the same numbers
    smp = r.evaluate(np.array([0.3, 1.9]))
    assert smp.joint_names == ("phi",)
    np.testing.assert_array_equal(smp.tau_phi, r.torques([0.3, 1.9])[0][:, 0])
    np.testing.assert_array_equal(smp.power_phi, r.torques([0.3, 1.9])[1][:, 0])
    df = r.to_pandas(per_segment=50)
    assert list(df.columns) == ["t", "theta", "phi", "u", "tau_phi", "power_phi"]
    np.testing.assert_array_equal(df["tau_phi"].to_numpy(), r.torques(df["t"].to_numpy())[0][:, 0])
    block = json.loads(r.to_json())["effort"]
    e = r.effort()["phi"]
    assert block["joints"]["phi"]["peak_torque"] == e.peak_torque and "Gauss-Legendre" in block["rule"]
    assert block["joints"]["phi"]["input_squared"] == pytest.approx(plan_energy(r), rel=1e-12)


def test_nothing_changes_without_a_torque_model(body):
    lumped = acroplan.Acrobot(**body.lumped())
    assert lumped.torque_model() is None and body.torque_model() is not None
    kw = dict(times=[0, 1], theta=[0.0, theta_at(lumped, 0.0, -1.0, -2.0, 1.0, 0.5)], phi=[-1.0, -2.0],
              conditions="free")
    for system, kwargs in ((lumped, kw), (acroplan.ChainedForm(3),
                                          dict(times=[0, 1], x1=[0, 0], x2=[0, 0], x3=[0, 0.1], conditions="free"))):
        r = acroplan.plan(system, **kwargs)
        assert r.success and not r.has_torques
        d = r.to_dict()
        assert "effort" not in d and "torque_limits" not in d and d["objective"] is None
        smp = r.sample(20)
        assert smp.torques is None and smp.joint_names == ()
        assert list(r.to_pandas(20).columns) == ["t", *system.state_names, *system.input_names]
        with pytest.raises(InvalidInputError) as e:
            r.torques(0.5)
        assert e.value.field == "system"
        with pytest.raises(InvalidInputError):
            r.plot("effort")
        # energy-optimal plans need no torques
        assert acroplan.plan(system, objective="energy", **kwargs).success


def test_options_that_need_torques_are_refused_by_name(body, problem):
    lumped = acroplan.Acrobot(**body.lumped())
    chain = dict(times=[0, 1], x1=[0, 0], x2=[0, 0], x3=[0, 0.1], conditions="free")
    cases = [
        (acroplan.ChainedForm(3), dict(objective="torque", **chain), "objective"),
        (acroplan.ChainedForm(3), dict(tau_max=3.0, **chain), "tau_max"),
        (lumped, dict(objective="torque", **problem), "objective"),
        (lumped, dict(objective="energy", tau_max=3.0, **problem), "tau_max"),
        (body, dict(objective="time", **problem), "objective"),
        (body, dict(tau_max=-1.0, **problem), "tau_max"),
        (body, dict(tau_max=[1.0, 2.0], **problem), "tau_max"),
        (body, dict(tau_max={"knee": 3.0}, **problem), "tau_max.knee"),
        (body, dict(objective="energy", method="energy-optimal", **problem), "method"),
        (body, dict(tau_max=5.0, method=TorqueOptimal(), **problem), "method"),
    ]
    for system, kw, field in cases:
        with pytest.raises(InvalidInputError) as e:
            acroplan.plan(system, **kw)
        assert e.value.field == field, (kw, e.value)
    with pytest.raises(InvalidInputError, match="did you mean 'tau_max'"):
        acroplan.plan(body, tau_mx=3.0, **problem)
    with pytest.raises(InvalidInputError) as e:
        acroplan.plan_many([dict(system=body, **problem)], objective="speed", executor="serial")
    assert e.value.field == "problems[0].objective"


def test_method_with_an_objective_is_the_start_and_an_optimal_method_records_its_objective(body, problem):
    deform = acroplan.plan(body, method="deform", **problem)
    r = acroplan.plan(body, method="deform", objective="energy", **problem)
    assert deform.success and r.success, r.message
    o = r.segments[0].optimality
    assert o["start"] == "auto" and o["kkt"] <= o["kkt_tol"]
    assert plan_energy(r) <= plan_energy(deform) * (1 + 1e-12)
    by_method = acroplan.plan(body, method=EnergyOptimal(tau_max=30.0), **problem)
    assert by_method.objective == "energy" and by_method.torque_limits == {"phi": 30.0}


def test_plan_many_takes_the_same_keywords(body, problem):
    rng = np.random.default_rng(7)
    probs = [dict(system=p.robot, conditions="free", **p.plan_kwargs()) for p in
             (random_segment(rng) for _ in range(2))] + [dict(system=body, **problem)]
    many = acroplan.plan_many(probs, objective="torque", executor="serial")
    for kw, r in zip(probs, many):
        kw = dict(kw)
        one = acroplan.plan(kw.pop("system"), objective="torque", **kw)
        assert r.success and r.objective == "torque" and r.segments[0].method == "torque-optimal"
        assert np.array_equal(r.segments[0].basis_coefficients, one.segments[0].basis_coefficients)
    limited = acroplan.plan_many([dict(system=body, **problem)], tau_max=15.0, n_coefficients=10,
                                 executor="serial")[0]
    assert limited.success and dense_peak(limited) <= 15.0 * (1 + 1e-9)


def test_effort_figure(body, problem):
    r = acroplan.plan(body, objective="energy", tau_max=18.0, n_coefficients=10, **problem)
    figs = r.plot("effort", per_segment=60)
    assert list(figs) == ["effort"]
    top, bottom = figs["effort"].axes
    line = top.get_lines()[0]
    np.testing.assert_allclose(line.get_ydata(), r.torques(line.get_xdata())[0][:, 0], rtol=1e-12)
    np.testing.assert_allclose(bottom.get_lines()[0].get_ydata(), r.torques(line.get_xdata())[1][:, 0],
                               rtol=1e-12)
    limits = sorted({y for ln in top.get_lines() for y in np.atleast_1d(ln.get_ydata())
                     if ln.get_linestyle() == ":"})
    assert limits == [-18.0, 18.0]
    assert "effort" not in r.plot()  # the default figures are unchanged
    import matplotlib.pyplot as plt

    plt.close("all")
    assert math.isfinite(r.effort()["phi"].positive_work)


def test_conditions_default_to_free_with_an_objective_and_pinned_ends_are_reported_not_converged():
    """With objective the default conditions are "free" (the least integral of u^2 exists); under
    spline conditions (u, u' pinned) it is an infimum no input attains: the ladder keeps falling to
    30 coefficients, reported as not converged, with a large torque at the pinned ends."""
    rng = np.random.default_rng(2024)
    p = [random_segment(rng) for _ in range(2)][1]
    fast = acroplan.plan(p.robot, **p.plan_kwargs())
    free = acroplan.plan(p.robot, objective="energy", **p.plan_kwargs())
    pinned = acroplan.plan(p.robot, objective="energy", conditions="spline", **p.plan_kwargs())
    assert fast.conditions == "spline" and free.conditions == "free" and pinned.conditions == "spline"
    assert free.success and pinned.success, pinned.message
    assert free.segments[0].optimality["converged"]
    o = pinned.segments[0].optimality
    assert not o["converged"] and not o["converged_in_basis"] and o["ladder"][-1][0] == 30
    costs = [c for _, c in o["ladder"]]
    assert all(b < a for a, b in zip(costs, costs[1:]))  # still falling
    assert "NOT converged on interval(s) [0]" in pinned.message
    assert plan_energy(free) < plan_energy(pinned)
    assert pinned.effort()["phi"].peak_torque > 20 * free.effort()["phi"].peak_torque


def test_the_sqp_step_with_no_freedom_left_on_the_constraints():
    """As many independent constraints as unknowns (spline conditions at 6 coefficients leave 2 for
    the 2 endpoint equations) and a Hessian not positive definite: the step is the constraints'
    (this raised on an empty reduced Hessian before)."""
    from acroplan.core.optimal import _step

    W, g = -np.eye(2), np.array([1.0, 1.0])
    A, h = np.array([[2.0, 1.0], [0.0, 1.0]]), np.array([0.1, -0.2])
    p, lam = _step(W, g, h, A, np.eye(2))
    np.testing.assert_allclose(A @ p, -h, rtol=1e-14)
    np.testing.assert_allclose(W @ p + A.T @ lam, -g, rtol=1e-13)


def _known_qp(seed, N, q, M, active, units=3.0, slack_low=0.01, mu_scale=1.0):
    """A quadratic program of known step, multipliers and active rows for qp_step: ``N`` unknowns,
    ``q`` equations, ``M`` inequality rows in units from 10^-units to 10^units (angles, rates and
    torques side by side), the rows ``active`` (indices, or how many to draw) active with known
    multipliers, the step small beside the other rows' slack (a step near an optimum). Returns
    ``(W, g, h, A, R, r, p_star, lam_star, mu_star, active)``."""
    rng = np.random.default_rng(seed)
    Q = np.linalg.qr(rng.normal(size=(N, N)))[0]
    W = Q @ np.diag(rng.uniform(0.5, 5.0, N)) @ Q.T
    A = rng.normal(size=(q, N))
    p_star = 0.01 * rng.normal(size=N)  # a step near an optimum: small beside the rows' slack
    h = -A @ p_star
    R = rng.normal(size=(M, N)) * 10.0 ** rng.uniform(-units, units, size=(M, 1))
    slack = np.abs(R @ rng.normal(size=N)) * rng.uniform(slack_low, 1.0, size=M)  # inactive rows: slack > 0
    if np.ndim(active) == 0:
        active = np.sort(rng.choice(M, int(active), replace=False))
    slack[active] = 0.0
    r = -(R @ p_star) - slack  # R p* + r = -slack <= 0
    mu_star = np.zeros(M)
    mu_star[active] = rng.uniform(0.5, 2.0, active.size) * mu_scale / np.abs(R[active]).max(axis=1)
    lam_star = rng.normal(size=q)
    g = -(W @ p_star + A.T @ lam_star + R.T @ mu_star)
    return W, g, h, A, R, r, p_star, lam_star, mu_star, active


def _the_known_step(out, p_star, lam_star, mu_star, R, r, scale):
    """qp_step's ``(p, lambda, mu)`` against the known ones (the step to ``scale`` of its largest
    entry, the multipliers to 100 and 1000 times that), every row kept; returns ``p``."""
    p, lam, mu = out
    np.testing.assert_allclose(p, p_star, rtol=0, atol=scale * np.abs(p_star).max())
    np.testing.assert_allclose(lam, lam_star, rtol=100 * scale, atol=100 * scale)
    np.testing.assert_allclose(mu, mu_star, rtol=1000 * scale, atol=10 * scale * mu_star.max())
    assert np.all(R @ p + r <= 1e-9 * (1 + np.abs(r).max()))
    return p


def _counting(monkeypatch):
    """The rows of every least-distance program qp_step solves, as a list filled as it goes."""
    from acroplan.core import sqp

    seen, inner = [], sqp.least_norm_step

    def counted(J, rr, G, hh):
        seen.append(G.shape[0])
        return inner(J, rr, G, hh)

    monkeypatch.setattr(sqp, "least_norm_step", counted)
    return seen


def test_the_qp_step_among_thousands_of_rows_in_mixed_units(monkeypatch):
    """qp_step on a quadratic program of known solution: 20 unknowns, 2 equations, 3000 inequality
    rows in units from 1e-3 to 1e3 (angles, rates and torques side by side), 6 of them active with
    known multipliers, the step small beside most rows' slack (a step near an optimum). The step
    and the multipliers are the known ones, and the least-distance programs see the rows in play
    only (those the free step uses most of the slack of), not every row whose slack is within a
    quarter of the largest row's magnitude (which were all of them, and took the joint optimum's
    steps on the double full-out 200 ms each)."""
    from acroplan.core import sqp

    W, g, h, A, R, r, p_star, lam_star, mu_star, _ = _known_qp(5, 20, 2, 3000, np.arange(6) * 500, mu_scale=0.01)
    seen = _counting(monkeypatch)
    _the_known_step(sqp.qp_step(W, g, h, A, R, r), p_star, lam_star, mu_star, R, r, scale=1e-10)
    assert seen and max(seen) <= 100, seen


def test_the_qp_step_with_more_active_rows_than_join_at_a_time(monkeypatch):
    """qp_step on a quadratic program of known solution with 80 active rows among 4000 (a torque
    limit on a dense grid, active over stretches of it), more than the QP_ROWS that join the working
    set at a time: the rounds add the rows the step still breaks until none is, and the step and
    the multipliers are the known ones (a least-distance program on a subset of the rows whose
    solution keeps them all is the program's solution), and the programs see far fewer rows than
    the free step leaves in play (which they all saw before)."""
    from acroplan.core import sqp

    n_act, q = 80, 4
    W, g, h, A, R, r, p_star, lam_star, mu_star, _ = _known_qp(11, 120, q, 4000, n_act, units=2.0)
    seen = _counting(monkeypatch)
    _the_known_step(sqp.qp_step(W, g, h, A, R, r), p_star, lam_star, mu_star, R, r, scale=1e-9)
    assert len(seen) >= n_act // sqp.QP_ROWS  # several rounds
    # the rows in play of the free step (the unconstrained step on the equations' null space)
    Y, Z = np.linalg.qr(A.T, mode="complete")[0][:, :q], np.linalg.qr(A.T, mode="complete")[0][:, q:]
    pY = Y @ np.linalg.solve(Y.T @ A.T, -h)
    p_free = pY - Z @ np.linalg.solve(Z.T @ W @ Z, Z.T @ (g + W @ pY))
    in_play = np.count_nonzero(-r - R @ p_free < sqp.QP_NEAR * np.maximum(-r, 0.0))
    assert seen[0] == sqp.QP_ROWS and max(seen) < in_play / 2, (seen, in_play)


def test_the_qp_step_by_cholesky_is_the_eigenvalues_step(monkeypatch):
    """qp_step factors a well-conditioned reduced Hessian by Cholesky (sqp.CHOLESKY_QP), whose
    least-distance coordinates are the eigenvalues' up to a rotation: on the known program (the
    model's eigenvalues 0.5-5) the step and the multipliers are the eigenvalue route's to 1e-11 and
    the known ones; a reduced Hessian whose condition passes the floor's margin
    (CHOLESKY_RCOND), or that is indefinite, is left to the eigenvalues."""
    from acroplan.core import sqp

    W, g, h, A, R, r, p_star, lam_star, mu_star, _ = _known_qp(5, 20, 2, 3000, np.arange(6) * 500, mu_scale=0.01)
    taken = []
    inner = sqp._well_conditioned_cholesky
    monkeypatch.setattr(sqp, "_well_conditioned_cholesky", lambda Wr: taken.append(inner(Wr)) or taken[-1])
    by_cholesky = sqp.qp_step(W, g, h, A, R, r)
    assert taken and taken[-1] is not None
    monkeypatch.setattr(sqp, "CHOLESKY_QP", False)
    by_eigenvalues = sqp.qp_step(W, g, h, A, R, r)
    for a, b in zip(by_cholesky, by_eigenvalues):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-11 * max(np.abs(b).max(), 1.0))
    _the_known_step(by_cholesky, p_star, lam_star, mu_star, R, r, scale=1e-10)
    rng = np.random.default_rng(3)
    Q = np.linalg.qr(rng.normal(size=(30, 30)))[0]
    for e in (np.geomspace(1e-7, 1.0, 30), np.linspace(-1.0, 2.0, 30)):  # ill-conditioned, indefinite
        assert sqp._well_conditioned_cholesky(Q @ np.diag(e) @ Q.T) is None
    assert sqp._well_conditioned_cholesky(Q @ np.diag(np.linspace(0.5, 5.0, 30)) @ Q.T) is not None


def test_the_qp_step_keeps_every_row_to_rounding_in_its_own_units():
    """40 random quadratic programs of known solution, rows in units from 1e-3 to 1e3: the step keeps
    every row to 1e-12 of its own magnitude, R_i p + r_i <= 1e-12 (1 + |r_i|). A tolerance of 1e-9
    of the largest row (as before) let steps break rows by up to 6e-10 relative here, and on the
    forward dive's joint optimum by 4e-8 rad/s, which its merit function's penalty of 3e4 then
    refused at the end: the SQP stopped at a KKT residual of 1.3e-6. With the last step's active
    rows as the working set's start (``hint``, as the SQP gives them) the step is the same to its
    accuracy."""
    from acroplan.core import sqp

    for seed in range(40):
        W, g, h, A, R, r, p_star, _, _, active = _known_qp(seed, 60, 3, 2000, 20, slack_low=0.001)
        p, lam, mu = sqp.qp_step(W, g, h, A, R, r)
        assert np.max((R @ p + r) / (1.0 + np.abs(r))) <= 1e-12, seed
        np.testing.assert_allclose(p, p_star, rtol=0, atol=1e-9 * np.abs(p_star).max())
        np.testing.assert_array_equal(np.flatnonzero(mu > 0), active)
        p2, _, mu2 = sqp.qp_step(W, g, h, A, R, r, hint=active[::2])
        np.testing.assert_allclose(p2, p_star, rtol=0, atol=1e-9 * np.abs(p_star).max())
        np.testing.assert_allclose(mu2, mu, rtol=1e-6, atol=1e-9 * mu.max())
        assert np.max((R @ p2 + r) / (1.0 + np.abs(r))) <= 1e-12, seed


def _bent_qp(seed, bend=10.0):
    """A quadratic program of known solution (:func:`_known_qp`: 30 unknowns, 2 equations, 300 rows,
    5 active) whose model bends down across the active rows, :math:`W - b \\sum_i \\hat R_i^\\top \\hat
    R_i` over the active rows' unit normals: indefinite on the equations' null space, unchanged (so
    positive definite) on the null space of the equations and the active rows, so that the known
    step is still a local solution (the gradient made anew for it)."""
    W, g, h, A, R, r, p_star, lam_star, mu_star, active = _known_qp(seed, 30, 2, 300, 5)
    U = R[active] / np.linalg.norm(R[active], axis=1)[:, None]
    W = W - bend * U.T @ U
    g = -(W @ p_star + A.T @ lam_star + R.T @ mu_star)
    return W, g, h, A, R, r, p_star, lam_star, mu_star, active


def test_the_qp_step_is_newtons_where_the_model_bends_down_across_the_binding_rows(monkeypatch):
    """Where the model's curvature on the equations' null space is negative along a direction the
    binding rows block, the step with the eigenvalues by their magnitude (the rule that keeps
    every step a descent direction) is not the program's: on the falling cat's least integral of
    u^2 it pointed the right way but fell 82% short, and the SQP converged linearly (36 full
    steps from a KKT residual of 9e-4 to 1e-8). qp_step then takes the Newton step of the binding
    rows (sqp._active_newton): on 20 such programs of known solution the step and the multipliers
    are the known ones, to 1e-9 of the step; with that turned off they are not (off by more than 1%
    of the step). (A program this bent has other local solutions; qp_step finds the known one when
    its binding rows are near those of the step with the magnitudes: so on 30 of 30 programs at
    bends of 3 to 20, and on 9 of 10 at a bend of 50.)"""
    from acroplan.core import sqp

    for seed in range(20):
        W, g, h, A, R, r, p_star, lam_star, mu_star, active = _bent_qp(seed)
        Z = np.linalg.qr(A.T, mode="complete")[0][:, A.shape[0]:]
        assert np.linalg.eigvalsh(Z.T @ W @ Z)[0] < 0.0  # indefinite where qp_step looks first
        _the_known_step(sqp.qp_step(W, g, h, A, R, r), p_star, lam_star, mu_star, R, r, scale=1e-9)
        monkeypatch.setattr(sqp, "ACTIVE_NEWTON", False)
        p_off = sqp.qp_step(W, g, h, A, R, r)[0]
        monkeypatch.setattr(sqp, "ACTIVE_NEWTON", True)
        assert np.abs(p_off - p_star).max() > 1e-2 * np.abs(p_star).max(), seed


def test_the_newton_step_drops_a_row_nearly_dependent_on_a_binding_one(monkeypatch):
    """A limit's grid puts neighbouring points of one peak in the working set, one at its bound and
    one just inside: rows nearly parallel, which made the Schur complement of sqp._active_newton
    singular, so that its Newton step was refused and the flipped model's step taken (the forward
    dive's joint optimum converged linearly). Here each bent program of known solution (as in the
    test above) gets a row 1e-7 (relative) off an active row's normal and 5e-8 further inside its
    bound, given as a hint: the nearly dependent row leaves the set (sqp._dependent_row) and the step
    and the multipliers are the known ones, to 1e-9 of the step, on 20 programs; refused instead
    (sqp.DROP_DEPENDENT off), the step is off by more than 1%."""
    from acroplan.core import sqp

    for seed in range(20):
        W, g, h, A, R, r, p_star, lam_star, mu_star, active = _bent_qp(seed)
        rng = np.random.default_rng(100 + seed)
        a = int(active[0])
        n = rng.normal(size=R.shape[1])
        n -= (n @ p_star) / (p_star @ p_star) * p_star  # the new row's value at the known step as row a's
        twin = R[a] + 1e-7 * np.linalg.norm(R[a]) * n / np.linalg.norm(n)
        R2, r2 = np.vstack([R, twin]), np.append(r, r[a] - 5e-8)
        mu2 = np.append(mu_star, 0.0)
        hint = np.append(active, R.shape[0])
        _the_known_step(sqp.qp_step(W, g, h, A, R2, r2, hint=hint), p_star, lam_star, mu2, R2, r2, scale=1e-9)
        monkeypatch.setattr(sqp, "DROP_DEPENDENT", False)
        p_off = sqp.qp_step(W, g, h, A, R2, r2, hint=hint)[0]
        monkeypatch.setattr(sqp, "DROP_DEPENDENT", True)
        assert np.abs(p_off - p_star).max() > 1e-2 * np.abs(p_star).max(), seed


def test_the_sqp_converges_quadratically_onto_a_bound_where_the_curvature_is_negative(monkeypatch):
    """The SQP on min 0.5 z^T Q z + c^T z with Q indefinite (eigenvalues -1.30, 2.30, 2), s.t.
    z_2 = 0.1 z_0^2 and z_0 <= 1, exact Hessians, from (0.8, 3, 0.064): the optimum is on the bound,
    (1, 0.5, 0.1) (Q's block off the bound, 2, is positive). With the Newton step of the binding rows
    it takes at most 3 iterations, to a KKT residual of 1e-15; with the eigenvalues by their
    magnitude alone the residual fell tenfold a step (a linear rate), and it took 9."""
    from acroplan.core import sqp

    Q = np.array([[-1.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 2.0]])
    c = np.array([-3.0, -2.0, 0.0])

    class Toy:
        def f(self, z):
            return 0.5 * z @ Q @ z + c @ z, Q @ z + c, Q.copy()

        def h(self, z):
            return np.array([z[2] - 0.1 * z[0] ** 2]), np.array([[-0.2 * z[0], 0.0, 1.0]]), None, None

    def ineq(z):
        return np.array([z[0] - 1.0]), np.array([[1.0, 0.0, 0.0]])

    Hz = np.zeros((1, 3, 3))
    Hz[0, 0, 0] = -0.2
    its = {}
    for flag in (True, False):
        monkeypatch.setattr(sqp, "ACTIVE_NEWTON", flag)
        z, info = sqp.sqp(Toy(), np.array([0.8, 3.0, 0.064]), Hz, tol=1e-12, kkt_tol=1e-12, ineq=ineq, max_iter=100)
        np.testing.assert_allclose(z, [1.0, 0.5, 0.1], rtol=0, atol=1e-7)
        its[flag] = info["its"]
        if flag:
            assert info["kkt"] <= 1e-15 and np.abs(z - [1.0, 0.5, 0.1]).max() <= 1e-14
    assert its[True] <= 3 and its[False] >= 6, its


class _Rows:
    """A point of the SQP with one equation and inequality rows (sqp._Point's fields)."""

    def __init__(self, z, h, A, r, R):
        self.z, self.h, self.A, self.r, self.R = (np.asarray(v, dtype=float) for v in (z, h, A, r, R))


def test_the_second_order_correction_holds_the_working_rows_at_their_bound(monkeypatch):
    """The correction from a trial point back onto A d = -h (A = (1, 1), h = 0.1) with the row
    z_0 <= 0 at its bound: as an inequality alone the shortest step leaves it inwards, (-0.05,
    -0.05); held as the quadratic program's working row it is (0, -0.1), the row exactly at its
    bound; a row at its bound outside the working set stays an inequality."""
    from acroplan.core import sqp

    xt = _Rows([0.0, 1.0, 2.0], [0.1], [[1.0, 1.0, 0.0]], [0.0, 0.0], [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
    monkeypatch.setattr(sqp, "WORKING_SOC", True)
    held = sqp._corrected(xt, np.array([0]))
    np.testing.assert_allclose(held - xt.z, [0.0, -0.1, 0.0], rtol=0, atol=1e-15)
    free = sqp._corrected(xt, None)
    np.testing.assert_allclose(free - xt.z, [-0.05, -0.05, 0.0], rtol=0, atol=1e-15)
    monkeypatch.setattr(sqp, "WORKING_SOC", False)
    np.testing.assert_allclose(sqp._corrected(xt, np.array([0])), free, rtol=0, atol=0)


def test_the_endpoints_polish_holds_the_active_rows_at_their_bound(monkeypatch):
    """Newton's steps onto h(z) = z_2 - (z_0^2 + z_1^2)/2 = 0 from (1, 0.5, 0.5) with z_0 <= 1 at its
    bound: held, z_0 stays 1 and the endpoint is met (to 1e-14); plain, the minimum-norm steps move
    z_0 inwards, by some 0.05."""
    from acroplan.core import sqp

    class Toy:
        def h(self, z):
            return np.array([z[2] - 0.5 * (z[0] ** 2 + z[1] ** 2)]), np.array([[-z[0], -z[1], 1.0]]), None, None

    def ineq(z):
        return np.array([z[0] - 1.0, -z[1] - 5.0]), np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])

    z0 = np.array([1.0, 0.5, 0.5])
    monkeypatch.setattr(sqp, "WORKING_SOC", True)
    z = sqp.polish_endpoint(Toy(), z0, 1e-12, ineq)
    assert abs(Toy().h(z)[0][0]) <= 1e-14 and abs(z[0] - 1.0) <= 1e-15, z
    plain = sqp.polish_endpoint(Toy(), z0, 1e-12)
    assert abs(Toy().h(plain)[0][0]) <= 1e-14 and plain[0] < 1.0 - 0.04, plain


def _curvature_calls(monkeypatch) -> list:
    """``(size, leading, evaluations)`` of each forward-difference constraint Hessian
    (``OptimalProblem.curvature``) of the plans that follow, in order."""
    from acroplan.core import optimum

    calls = []
    full = optimum.OptimalProblem.curvature

    def recorded(self, c, Ac, leading=None):
        before = self.evaluations
        out = full(self, c, Ac, leading)
        calls.append((self.n, leading, self.evaluations - before))
        return out

    monkeypatch.setattr(optimum.OptimalProblem, "curvature", recorded)
    return calls


def test_a_refresh_of_the_constraint_hessians_differences_the_leading_coefficients(monkeypatch):
    """The SQP's refreshed constraint Hessians (after POOR_STEPS poor steps) are forward
    differences along each input's first REFRESH_LEADING coefficients: m * 10 endpoint evaluations
    at 30 coefficients, not m * 30 (the falling cat's least integral of tau^2, refreshed here after
    every poor step), and its optimum is reached as before (a converged KKT residual)."""
    from acroplan.core import optimum, sqp
    from acroplan.families.spatial.examples import falling_cat_turn

    body, problem = falling_cat_turn()
    monkeypatch.setattr(sqp, "POOR_STEPS", 1)
    calls = _curvature_calls(monkeypatch)
    r = acroplan.plan(body, objective="torque", verify=False, **problem)
    assert r.success, r.message
    lead, m = optimum.REFRESH_LEADING, body.n_inputs
    refreshes = [c for c in calls if c[0] > lead]
    assert refreshes and all(k == lead and e == m * lead for _, k, e in refreshes), calls
    assert r.segments[0].optimality["kkt"] <= 1e-8


def test_a_stage_that_ends_off_the_endpoint_is_polished_and_the_ladder_goes_on():
    """A ladder's stage is solved to a loose KKT residual and not polished (the next size starts
    from it), but one whose endpoint ended outside the tolerance is: judged as it was, it stopped
    the ladder. The acrobot zoo's second segment of seed 31, least integral of tau^2: the SQP at 20
    coefficients spent its 40 iterations and ended with the endpoint 5.6e-7 off (KKT residual
    1.3e-3), so the ladder stopped at 14 coefficients (2450.09); polished, the stage meets the
    target and the ladder climbs to 30 coefficients, 1429.83 (each size below the one before)."""
    rng = np.random.default_rng(31)
    p = [random_segment(rng) for _ in range(2)][1]
    r = acroplan.plan(p.robot, objective="torque", **p.plan_kwargs())
    assert r.success, r.message
    seg = r.segments[0]
    o = seg.optimality
    sizes, costs = zip(*o["ladder"])
    assert sizes == (6, 10, 14, 20, 26, 30), o["ladder"]
    assert all(b < a for a, b in zip(costs, costs[1:])), costs
    # the stop at 14 coefficients cost 2450.09; the first stage's optimum, unchanged, 10466.8
    assert o["cost"] < 0.6 * 2450.0 and costs[0] == pytest.approx(10466.78, rel=1e-5), o["cost"]
    assert seg.final_error <= 1e-10 and o["kkt"] <= 1e-6


def test_a_first_size_above_the_leading_coefficients_differences_the_leading_ones(monkeypatch):
    """A run's first constraint Hessians (no curvature given) are forward differences along each
    input's first REFRESH_LEADING coefficients, as its refreshes: the falling cat's least integral
    of u^2 at rest starts at 14 coefficients (its feasible plan's projection onto 6 is no start),
    3 x 10 evaluations there instead of 3 x 14, and reaches the optimum the full differences
    reach (both KKT residuals below 1e-8: the same cost to 1e-9), in fewer evaluations."""
    from acroplan.core import optimum
    from acroplan.families.spatial.examples import falling_cat_turn

    body, problem = falling_cat_turn()
    calls = _curvature_calls(monkeypatch)
    r = acroplan.plan(body, objective="energy", verify=False, **problem)
    first = calls[0]
    assert r.success and first == (14, optimum.REFRESH_LEADING, 3 * optimum.REFRESH_LEADING), calls
    calls.clear()
    monkeypatch.setattr(optimum, "REFRESH_LEADING", None)
    again = acroplan.plan(body, objective="energy", verify=False, **problem)
    assert again.success and calls[0] == (14, None, 3 * 14), calls
    new, old = r.segments[0].optimality, again.segments[0].optimality
    assert new["kkt"] <= 1e-8 and old["kkt"] <= 1e-8
    assert new["cost"] == pytest.approx(old["cost"], rel=1e-9)
    assert new["evaluations"] < old["evaluations"], (new["evaluations"], old["evaluations"])
