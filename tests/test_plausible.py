"""Plausible, or it says why not (issue #24): a success whose peak joint rate is far beyond what its
waypoints imply carries ``result.warnings`` with the peak numbers and the message says so; an
infeasible file of thousands of segments gives a message of a few hundred characters.

The problem files are the issue's reproducers, generated here (not committed): 5,001 waypoints
0.02 s apart sampled from a gentle motion of a human body split at the hips (de Leva's tables,
1.74 m, 70 kg, P0 = 20 kg m^2/s), the hips within 0.2 rad of straight (|u| <= 0.2 rad/s),
``conditions = "free"``; and its unreachable version (the turn 0.1 rad/s slower than the straight
body's, below every segment's reachable interval).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

import acroplan
from acroplan.families.human.deleva import from_height_mass
from acroplan.io.cli import main as cli
from acroplan.io.results import result_from_dict
from acroplan.planning import EXACT_EFFORT_SEGMENTS, PLAUSIBLE_FACTOR, plausibility, waypoint_rate

P0, AMPLITUDE = 20.0, 0.2  # kg m^2/s; rad, at 1 rad/s: |u| <= 0.2 rad/s


def gentle_motion(n: int = 5001, dt: float = 0.02):
    """``(times, theta, phi)``: the gentle motion phi = -pi + 0.2 sin t and the turn it makes,
    theta = theta0 - [F(phi) - F(phi0)] + P0 int dt / h(phi) (docs/mathematics.md), the integral by
    composite Simpson on 40 panels a waypoint interval (error below 1e-13 rad)."""
    body = from_height_mass(1.74, 70.0).two_link(angular_momentum=P0)
    t = np.arange(n) * dt
    phi = -np.pi + AMPLITUDE * np.sin(t)
    fine = np.linspace(0.0, t[-1], 40 * (n - 1) + 1)
    f = 1.0 / body.h(-np.pi + AMPLITUDE * np.sin(fine))
    h = fine[1] - fine[0]
    pairs = (f[:-2:2] + 4 * f[1:-1:2] + f[2::2]) * h / 3  # Simpson on each pair of panels
    integral = np.concatenate([[0.0], np.cumsum(pairs)])[::20]
    theta = -0.5 * np.pi - (body.F(phi) - body.F(phi[0])) + P0 * integral
    return t, theta, phi


def problem_file(path, times, theta, phi, conditions="free"):
    """A problem file of the planar human split at the hips (no position: no limits)."""
    row = lambda v: "[" + ", ".join(repr(float(x)) for x in v) + "]"  # noqa: E731
    path.write_text(f'[body]\nheight = 1.74\nmass = 70.0\nangular_momentum = {P0!r}\n\n[plan]\n'
                    f'times = {row(times)}\ntheta = {row(theta)}\nphi = {row(phi)}\nconditions = "{conditions}"\n')
    return path


@pytest.fixture(scope="module")
def motion():
    return gentle_motion()


def test_the_sampled_motion_is_the_bodys(motion):
    """The waypoints are the body's own motion: the flat-output identity holds between them, so
    the gentle motion itself (|u| <= 0.2 rad/s) passes through every one."""
    t, theta, phi = motion
    body = from_height_mass(1.74, 70.0).two_link(angular_momentum=P0)
    assert np.max(np.abs(np.diff(phi) / np.diff(t))) <= AMPLITUDE
    implied, _ = waypoint_rate(body, t, np.column_stack([theta, phi]))
    assert 1.7 < implied < 1.9  # the turn P0 / h(straight) = 1.73 rad/s is the fastest rate


def test_the_waypoint_rate_on_floats_is_numpys_bit_for_bit():
    """Up to 32 waypoints the waypoints' rate is worked out on Python floats (plain loops: it runs
    after every plan): the same differences, maxima and quotients as the numpy path, so the same
    bits; a waypoint or time that is not finite, or times that do not increase, go to the numpy
    path (which then says NaN or inf as numpy does)."""
    from acroplan.planning.plausible import _FEW, _few_rate

    rng = np.random.default_rng(17)
    for K in (1, 2, 5, 31):
        for n, idx in ((2, (0, 1)), (4, (1, 3)), (5, (0, 2, 3, 4))):
            X = rng.normal(scale=3.0, size=(K + 1, n)) * 10.0 ** rng.integers(-3, 3, size=(K + 1, n))
            t = np.cumsum(rng.uniform(0.01, 2.0, size=K + 1))
            rate = np.max(np.abs(np.diff(X[:, list(idx)], axis=0)), axis=1) / np.diff(t)
            assert K + 1 <= _FEW
            assert _few_rate(X.tolist(), t.tolist(), idx) == (float(rate.max()), int(np.argmax(rate)))
    assert _few_rate([[0.0, 1.0], [float("nan"), 2.0]], [0.0, 1.0], (0, 1)) is None
    assert _few_rate([[0.0, 1.0], [1.0, 2.0]], [0.0, float("inf")], (0, 1)) is None
    assert _few_rate([[0.0, 1.0], [1.0, 2.0], [2.0, 3.0]], [0.0, 1.0, 1.0], (0, 1)) is None
    body = from_height_mass(1.74, 70.0).two_link(angular_momentum=P0)
    implied, k = waypoint_rate(body, [0.0, 0.5, 1.5], [[0.0, 1.0], [0.2, 3.0], [0.3, 2.0]])
    assert (implied, k) == (abs(3.0 - 1.0) / 0.5, 0)


@pytest.mark.xdist_group("plausible-5001")
def test_5001_dense_waypoints_free_give_a_warning_with_the_peaks(tmp_path, motion):
    """The issue's feasible file: "success" with a peak joint rate of some hundred rad/s. It now
    carries warnings with the peak rate (more than PLAUSIBLE_FACTOR times the waypoints'), the
    peak torque and power, and the suggestion; the message says so and stays short."""
    prob = acroplan.load_problem(problem_file(tmp_path / "dense.toml", *motion))
    assert len(prob.times) == 5001 and prob.conditions == "free"
    r = acroplan.plan(prob.system, verify=False, progress=False, time_limit=None, **prob.plan_kwargs())
    assert r.success
    implied, _ = waypoint_rate(r.system, r.times, r.waypoints)
    assert r.max_abs_u > PLAUSIBLE_FACTOR * implied  # not a gentle motion: so it must warn
    assert len(r.warnings) == 5
    rate, effort, hint, human_rate, human_torque = r.warnings
    assert human_rate == (f"peak joint rate {r.max_abs_u:.4g} rad/s (u) is beyond what the body can do, 12.8 rad/s "
                          "(the highest mean peak hip rate of elite platform divers, Murtaugh 2000)")
    assert human_torque.startswith("peak torque at least ") and "is beyond the body's strength, 351.4 N m" in human_torque
    assert f"peak joint rate {r.max_abs_u:.4g} rad/s" in rate and f"{implied:.4g} rad/s" in rate
    assert "peak torque at least" in effort and "N m" in effort and "W" in effort
    tau = float(effort.split("at least ")[1].split(" N m")[0])
    assert tau > 1e4  # the hips of a 70 kg man give some 300 N m: far beyond
    assert hint.startswith("try fewer waypoints") and "5000 segments of 0.02 s" in hint
    assert hint.endswith(" or conditions = \"spline\"")
    assert "IMPLAUSIBLE" in r.message and "result.warnings" in r.message and len(r.message) <= 300


@pytest.mark.xdist_group("plausible-5001")
def test_5001_unreachable_waypoints_give_a_short_message(tmp_path, motion):
    """The issue's unreachable file printed one 651,057-character line: now one refused segment
    with its proof and how many more, all of them in solution.json; no degrees hint (radians)."""
    t, theta, phi = motion
    path = problem_file(tmp_path / "unreachable.toml", t, theta - 0.1 * t, phi)
    out = tmp_path / "out"
    run = CliRunner().invoke(cli, ["plan", str(path), "--out", str(out)])
    assert run.exit_code == 3, run.output
    doc = json.loads((out / "solution.json").read_text())
    assert doc["status"] == "infeasible" and len(doc["infeasible"]) == 5000
    msg = doc["message"]
    assert len(msg) <= 320, msg
    assert msg.startswith("infeasible: 5000 of 5000 segments") and "segment 0 [0, 0.02]" in msg
    assert "degrees" not in msg
    first, second = run.output.splitlines()  # the message, and where the diagnostics are
    assert first == "acroplan: " + msg and second.startswith("acroplan: diagnostics written to")


def test_the_same_motion_with_fewer_waypoints_is_gentle(motion):
    """What the warning suggests works: every 250th waypoint (21, 5 s apart) with spline
    conditions plans a motion as gentle as the one sampled, and no warning."""
    t, theta, phi = (v[::250] for v in motion)
    body = from_height_mass(1.74, 70.0).two_link(angular_momentum=P0)
    r = acroplan.plan(body, times=t, theta=theta, phi=phi, conditions="spline", progress=False)
    assert r.success and r.warnings == ()
    assert r.max_abs_u <= 1.5 * AMPLITUDE
    assert "IMPLAUSIBLE" not in r.message


def test_60_dense_waypoints_warn_with_exact_peaks_through_the_cli(tmp_path, motion):
    """60 segments of the dense file (t = 2.8 to 4 s): flagged under both conditions, with the exact
    peak torque and power (the effort summary: at most EXACT_EFFORT_SEGMENTS segments); the command
    line prints the warnings and writes them to solution.json, which reads back with them."""
    t, theta, phi = (v[140:201] for v in motion)
    assert len(t) - 1 <= EXACT_EFFORT_SEGMENTS
    body = from_height_mass(1.74, 70.0).two_link(angular_momentum=P0)
    for conditions in ("free", "spline"):
        r = acroplan.plan(body, times=t, theta=theta, phi=phi, conditions=conditions, progress=False)
        assert r.success and len(r.warnings) == 3, (conditions, r.max_abs_u)  # no capacity given: no more
        assert r.max_abs_u > PLAUSIBLE_FACTOR * waypoint_rate(body, t, r.waypoints)[0]
        e = r.effort()["phi"]
        assert r.warnings[1] == f"peak torque {e.peak_torque:.4g} N m (joint phi), peak power {e.peak_power:.4g} W"
        assert e.peak_torque > 1e4
        assert r._repr_html_().count("warning: ") == 3  # shown in a notebook too
    path = problem_file(tmp_path / "dense60.toml", t, theta, phi)
    out = tmp_path / "out"
    run = CliRunner().invoke(cli, ["plan", str(path), "--out", str(out), "--no-plots"])
    assert run.exit_code == 0, run.output
    doc = json.loads((out / "solution.json").read_text())
    assert len(doc["warnings"]) == 5  # the file's human body brings its capacity: rate and strength beyond
    assert "is beyond the body's strength, 351.4 N m" in doc["warnings"][4]
    for w in doc["warnings"]:
        assert f"warning: {w}" in run.output
    assert "IMPLAUSIBLE" in doc["message"] and doc["message"] in run.output
    assert result_from_dict(doc).warnings == tuple(doc["warnings"])  # solution.json read back


def test_exact_peaks_on_few_segments_and_bounded_inputs_are_not_checked():
    """The bundled three rods turn 0.4 rad at zero momentum by a shape loop within |u| <= 2 rad/s:
    no warning (a bounded input is within what the body can do). The same plan without its rate
    limit is flagged (the loop's rate is 14 times the turn's), with the exact peak torque and power
    of the effort summary (one segment)."""
    prob = acroplan.examples.load("three-rods-turn")
    r = prob.solve(progress=False)
    assert r.success and r.warnings == () and r.max_abs_u <= 2.0
    w = plausibility(r)
    assert w == ()
    unbounded = r.__class__(**{**{f: getattr(r, f) for f in ("status", "message", "system", "times", "waypoints",
                                                              "conditions", "basis", "segments", "verified",
                                                              "verification")}, "limits": None})
    w = plausibility(unbounded)
    implied, _ = waypoint_rate(r.system, r.times, r.waypoints)
    assert r.max_abs_u / implied > PLAUSIBLE_FACTOR and len(w) == 3
    e = r.effort()
    j = max(e, key=lambda n: e[n].peak_torque)
    assert w[1] == (f"peak torque {e[j].peak_torque:.4g} N m (joint {j}), peak power "
                    f"{max(x.peak_power for x in e.values()):.4g} W")


def test_gentle_bundled_examples_carry_no_warning():
    """The bundled two-link examples: peak rates 1.9 and 6.4 times their waypoints' fastest."""
    for name in ("pike-dive", "pike-dive-limited"):
        r = acroplan.examples.load(name).solve(progress=False)
        implied, _ = waypoint_rate(r.system, r.times, r.waypoints)
        assert r.success and r.warnings == () and r.max_abs_u < PLAUSIBLE_FACTOR * implied, name
        assert "IMPLAUSIBLE" not in r.message


def test_the_degrees_hint_only_for_values_that_look_like_degrees():
    """Whole degrees beyond 2 pi get the hint; the same turn in radians, refused, does not."""
    robot = acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                           torso_length=0.35, leg_length=0.45, angular_momentum=10.0)
    r = acroplan.plan(robot, times=[0, 1], theta=[0, 90], phi=[-180, -90], progress=False)
    assert r.status == "infeasible" and "if these are degrees, pass degrees=True" in r.message
    assert len(r.message) <= 400
    r = acroplan.plan(robot, times=[0, 1], theta=[0, 90.123456], phi=[-np.pi, -np.pi / 2], progress=False)
    assert r.status == "infeasible" and "degrees" not in r.message
    r = acroplan.plan(robot, times=[0, 1], theta=[0, 45], phi=[-180, -90], degrees=True, progress=False)
    assert r.success and r.warnings == () and r.max_abs_u < 10 * np.pi / 2


def test_a_target_near_the_edge_of_the_reachable_set_is_flagged():
    """One segment of 1 s, theta to 2.0 rad of the reachable (0.119, 2.443): the plan swings the
    hips at some 45 rad/s, 22 times the waypoints' fastest rate (the turn's, 2 rad/s); the warning says so,
    with the exact peak torque, and (one segment, spline) points at the waypoints and rate limits."""
    robot = acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                           torso_length=0.35, leg_length=0.45, angular_momentum=10.0)
    lo, hi = acroplan.reachable_set(robot, theta0=0.0, phi0=-np.pi, phiT=-np.pi / 2, T=1.0).interval
    assert lo < 2.0 < hi
    r = acroplan.plan(robot, times=[0, 1], theta=[0, 2.0], phi=[-np.pi, -np.pi / 2], progress=False)
    assert r.success and r.max_abs_u > PLAUSIBLE_FACTOR * 2.0
    assert waypoint_rate(robot, r.times, r.waypoints) == (2.0, 0)
    rate, effort, hint = r.warnings
    assert f"is {r.max_abs_u / 2.0:.0f} times" in rate and "imply, 2 rad/s" in rate
    assert effort == f"peak torque {r.effort()['phi'].peak_torque:.4g} N m (joint phi), peak power " \
                     f"{r.effort()['phi'].peak_power:.4g} W"
    assert hint.startswith("check the waypoints") and "u_max" in hint
    ok = acroplan.plan(robot, times=[0, 1], theta=[0, 1.0], phi=[-np.pi, -np.pi / 2], progress=False)
    assert ok.success and ok.warnings == ()  # the README's example: 5.4 times


def test_a_human_body_brings_its_capacity_from_the_data(tmp_path):
    """A human file carries plan()'s capacity= from families/human/data/limits.toml (the hip rate
    12.8 rad/s, the hip strength 351.4 N m for both hips); the bundled platform dive is within it."""
    from acroplan.families.human.limits import hip_rate_literature, hip_torque_literature

    t, theta, phi = gentle_motion(3, 0.5)
    prob = acroplan.load_problem(problem_file(tmp_path / "short.toml", t, theta, phi))
    cap = prob.options["capacity"]
    assert cap["rates"]["u"][0] == hip_rate_literature()[1] == 12.8
    assert cap["torques"]["phi"][0] == max(hip_torque_literature()) == 351.4
    r = prob.solve(progress=False)
    assert r.success and r.warnings == () and r.max_abs_u < 1.0


def test_capacity_is_a_yardstick_not_a_limit():
    """The same plan with and without capacity=: the same motion; with it, two more warnings naming
    the yardstick's numbers and sources. A capacity naming no input is refused, naming the field."""
    robot = acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                           torso_length=0.35, leg_length=0.45, angular_momentum=10.0)
    kw = dict(times=[0, 1], theta=[0, 2.0], phi=[-np.pi, -np.pi / 2], progress=False)
    cap = {"rates": {"u": (12.0, "source A")}, "torques": {"phi": (351.4, "source B")}}
    a, b = acroplan.plan(robot, **kw), acroplan.plan(robot, capacity=cap, **kw)
    assert np.array_equal(a.segments[0].basis_coefficients, b.segments[0].basis_coefficients)
    assert b.warnings[:3] == a.warnings and len(b.warnings) == 5
    assert b.warnings[3] == f"peak joint rate {b.max_abs_u:.4g} rad/s (u) is beyond what the body can do, 12 rad/s (source A)"
    assert b.warnings[4] == (f"peak torque {b.effort()['phi'].peak_torque:.4g} N m (joint phi) is beyond the body's "
                             "strength, 351.4 N m (source B)")
    ok = acroplan.plan(robot, times=[0, 1], theta=[0, 1.0], phi=[-np.pi, -np.pi / 2], progress=False, capacity=cap)
    assert ok.warnings == () and ok.max_abs_u < 12.0
    with pytest.raises(acroplan.InvalidInputError, match=r"capacity\.rates\.v: is not an input of Acrobot"):
        acroplan.plan(robot, capacity={"rates": {"v": (1.0, "x")}}, **kw)


@pytest.mark.parametrize("family", ["legendre", "monomial"])
def test_the_sup_bound_bounds_the_exact_peak_and_is_attained_at_one_end(family):
    """``InputBasis.sup_bound`` (the sum of the coefficients' magnitudes, what ``plausibility``
    asks before any root finding) is at least the exact peak, and the check grid's sample
    (``sampled_input_peak``) at most it; the exact peak :math:`\\max_{[0,1]} |u|`
    (``input_extremes``) for random series, and equals it when every coefficient is non-negative
    (then :math:`u(1) = \\sum_i c_i`, every basis function being 1 at s = 1); a basis that knows no
    bound says so (``None``)."""
    from acroplan.core.basis import InputBasis, make_basis
    from acroplan.core.limits import input_extremes, sampled_input_peak

    rng = np.random.default_rng(8)
    for n in (1, 2, 6, 14, 30):
        basis = make_basis(family, n)
        for _ in range(20):
            c = rng.normal(size=n) * rng.uniform(0.1, 10.0)
            lo, hi = input_extremes(basis, c)
            assert max(abs(lo), abs(hi)) <= basis.sup_bound(c) * (1 + 1e-12)
            # the check grid's sample (what plan() flags with before any root finding) is below it
            low = sampled_input_peak(basis, c)
            assert low <= max(abs(lo), abs(hi)) * (1 + 1e-12)
            # the largest row's (a matrix product instead of a matrix-vector one: the last bit may differ)
            assert sampled_input_peak(basis, np.vstack([0.5 * c, c])) == pytest.approx(low, rel=1e-14)
        c = np.abs(rng.normal(size=n))
        lo, hi = input_extremes(basis, c)
        assert hi == pytest.approx(basis.sup_bound(c), rel=1e-12)
    assert InputBasis.sup_bound(make_basis(family, 3), [1.0, 2.0, 3.0]) is None


def test_the_waypoint_rate_of_few_waypoints_is_numpys_to_the_bit():
    """Up to 32 waypoints :func:`waypoint_rate` works on Python floats; the same operations in the
    same order give the same bits as the numpy expression, the first of equal rates, and NaN
    (a free waypoint) as numpy gives it."""
    robot = acroplan.examples.robot("pike-dive")
    rng = np.random.default_rng(5)
    for n in (2, 3, 17, 32, 33, 200):
        for scale in (1e-3, 1.0, 1e3):
            X = rng.normal(size=(n, 2)) * scale
            t = np.cumsum(rng.uniform(0.01, 3.0, size=n))
            r = np.max(np.abs(np.diff(X, axis=0)), axis=1) / np.diff(t)
            assert waypoint_rate(robot, t, X) == (float(r[np.argmax(r)]), int(np.argmax(r)))
    X = np.array([[0.0, 0.0], [1.0, 1.0], [3.0, 1.0]])
    assert waypoint_rate(robot, [0.0, 1.0, 2.0], X) == (2.0, 1)  # ties and order: the larger second
    assert waypoint_rate(robot, [0.0, 1.0, 2.0], [[0.0, 0.0], [1.0, 1.0], [2.0, 1.0]]) == (1.0, 0)  # a tie: the first
    X[1, 0] = np.nan
    rate, k = waypoint_rate(robot, [0.0, 1.0, 2.0], X)
    assert np.isnan(rate) and k == 0


def test_the_warnings_peaks_are_the_effort_summarys_without_its_integrals():
    """:func:`peak_efforts` (what a warning gives) against :meth:`PlanResult.effort`: the acrobot's
    flagged random segments bit for bit (its model's value at a time does not depend on the other
    times asked with it), the three rods' flagged loop (a planar body) to 1e-12 relative."""
    from acroplan.core.effort import peak_efforts
    from acroplan.zoo import random_segment

    rng = np.random.default_rng(5)
    flagged = []
    while len(flagged) < 5:
        p = random_segment(rng)
        r = acroplan.plan(p.robot, conditions="free", **p.plan_kwargs(), verify=False, progress=False)
        if r.warnings:
            flagged.append(r)
    for r in flagged:
        assert r._effort is None  # the warning did not compute the whole summary
        peaks, e = peak_efforts(r), r.effort()
        assert peaks == {n: (v.peak_torque, v.peak_power) for n, v in e.items()}
    from acroplan.families.planar.examples import three_rods_turn

    body, kw = three_rods_turn()
    del kw["u_max"]
    r = acroplan.plan(body, **kw, progress=False)
    assert r.warnings  # its loop without the rate limit is flagged (above)
    peaks, e = peak_efforts(r), r.effort()
    for n, v in e.items():
        assert peaks[n] == pytest.approx((v.peak_torque, v.peak_power), rel=1e-12)


def test_a_flagged_plans_exact_numbers_are_worked_out_when_its_warnings_are_first_read():
    """A plan whose sampled peak rate (the limits' check grid, a lower bound) is already beyond the
    factor is flagged at once, its message giving that bound ("at least"); its exact peak rate (the
    roots of u') and peak torque and power stay :class:`PendingWarning` s until the warnings are
    read (``plan_many`` of plans nobody reads the warnings of does not pay for them: 0.15 + 1.2 ms a
    flagged two-link plan), then give what :func:`plausibility` works out at once: the same strings
    read here or after a pickle (a process pool's result), kept once worked out."""
    import pickle
    import re

    from acroplan.core.result import PendingWarning
    from acroplan.planning.plausible import _effort_warning
    from acroplan.zoo import random_segment

    rng = np.random.default_rng(5)
    flagged = []
    while len(flagged) < 3:
        p = random_segment(rng)
        r = acroplan.plan(p.robot, conditions="free", **p.plan_kwargs(), verify=False, progress=False)
        if r.__dict__["_warnings_held"]:
            flagged.append(r)
    for r in flagged:
        held = r.__dict__["_warnings_held"]
        assert [type(w) for w in held] == [PendingWarning, PendingWarning, str]
        assert r._effort is None and r.segments[0].extremes is None  # neither worked out yet
        head = re.search(r"IMPLAUSIBLE: peak joint rate at least ([0-9.]+) rad/s, at least ([0-9]+)x what the "
                         r"waypoints imply \(3 warnings: result.warnings\)$", r.message)
        assert head is not None, r.message
        shipped = pickle.loads(pickle.dumps(r))
        assert type(shipped.__dict__["_warnings_held"][1]) is PendingWarning
        eager = plausibility(r)
        first = r.warnings
        assert first == eager and first[2] == held[2]
        assert first[0].startswith("peak joint rate ") and " times the fastest rate the waypoints imply" in first[0]
        assert first[1].startswith("peak torque ") and " N m (joint phi), peak power " in first[1]
        assert all(type(w) is str for w in first)
        assert r.warnings is first and r.__dict__["_warnings_held"] is first  # worked out once, kept
        # the message's sampled bound is below the exact peak, and within the grid's resolution of it
        peak = r.segments[0].max_abs_u
        assert float(head.group(1)) <= float(f"{peak:.4g}") and float(head.group(1)) >= 0.999 * peak
        assert r._effort is None  # the peaks alone, not the whole summary
        assert shipped.warnings == eager
        assert r.to_dict()["warnings"] == list(eager)
    # a result pickled before this descriptor kept its warnings under their own name
    r = flagged[0]
    older = pickle.loads(pickle.dumps(r))
    older.__dict__["warnings"] = older.__dict__.pop("_warnings_held")
    assert older.warnings == r.warnings
    # with the summary computed before the warnings are read, the line comes from it, the same
    again = pickle.loads(pickle.dumps(r))
    peaks = np.array([s.max_abs_u for s in r.segments])
    object.__setattr__(again, "warnings", (r.warnings[0], PendingWarning(_effort_warning, (peaks,)), r.warnings[2]))
    again.effort()
    assert again.warnings == r.warnings
