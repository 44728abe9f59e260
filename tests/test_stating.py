"""Stating a problem: suggestions for typos, angles in degrees, rest at the ends."""

import numpy as np
import pytest

import acroplan

PI = np.pi


def test_a_mistyped_keyword_gets_a_suggestion(pike_robot):
    with pytest.raises(acroplan.InvalidInputError, match="u_mx: .*did you mean 'u_max'"):
        acroplan.plan(pike_robot, times=[0, 1], theta=[0, 1], phi=[0, 1], u_mx=3.0)
    with pytest.raises(acroplan.InvalidInputError, match="phi_mn: .*did you mean 'phi_min'"):
        acroplan.plan(pike_robot, times=[0, 1], theta=[0, 1], phi=[0, 1], phi_mn=-3.0)


def test_degrees_give_the_radian_plan(pike_robot):
    lo, hi = acroplan.reachable_set(pike_robot, theta0=0.0, phi0=-PI, phiT=-PI / 2, T=1.0).interval
    th = 0.5 * (lo + hi)
    rad = acroplan.plan(pike_robot, times=[0, 1], theta=[0, th], phi=[-PI, -PI / 2], conditions="free",
                        phi_min=-PI, phi_max=0.0, u_max=20.0)
    deg = acroplan.plan(pike_robot, times=[0, 1], theta=[0, np.degrees(th)], phi=[-180, -90], conditions="free",
                        phi_min=-180, phi_max=0.0, u_max=np.degrees(20.0), degrees=True)
    assert rad.success and deg.success
    assert np.allclose(deg.waypoints, rad.waypoints, rtol=1e-15, atol=1e-15)
    assert np.allclose(deg.segments[0].basis_coefficients, rad.segments[0].basis_coefficients, rtol=1e-9)
    assert deg.limits.bounds("phi") == pytest.approx((-PI, 0.0)) and deg.limits.u_max == pytest.approx(20.0)


def test_degrees_that_look_like_radians_get_a_hint(pike_robot):
    res = acroplan.plan(pike_robot, times=[0, 1], theta=[0, 1], phi=[-180, -90])
    assert res.status == "infeasible" and "pass degrees=True" in res.message
    small = acroplan.plan(pike_robot, times=[0, 1], theta=[0, 100.0], phi=[-PI, -PI / 2])
    assert small.status == "infeasible" and "degrees" in small.message  # theta = 100 rad looks like degrees too


def test_free_conditions_can_start_and_end_at_rest(pike_robot):
    problem = acroplan.examples.load("pike-dive")
    kw = dict(problem.plan_kwargs(), conditions="free")
    loose = acroplan.plan(problem.robot, **kw)
    rest = acroplan.plan(problem.robot, start_rate=0.0, end_rate=0.0, **kw)
    assert loose.success and rest.success, rest.message
    assert abs(rest.segments[0].input(rest.times[0])[0]) < 1e-9
    assert abs(rest.segments[-1].input(rest.times[-1])[0]) < 1e-9
    given = acroplan.plan(problem.robot, start_rate={"u": 1.5}, **kw)
    assert given.success and given.segments[0].input(0.0)[0] == pytest.approx(1.5, abs=1e-9)
    with pytest.raises(acroplan.InvalidInputError, match="start_rate: applies to conditions=\"free\" only"):
        acroplan.plan(problem.robot, start_rate=0.0, **problem.plan_kwargs())
    with pytest.raises(acroplan.InvalidInputError, match="end_rate.w: is not an input"):
        acroplan.plan(problem.robot, end_rate={"w": 0.0}, **kw)


def test_free_intermediate_states_are_chosen_and_planned(pike_robot):
    kw = dict(times=[0, 2, 4, 6], phi=[-PI, -2 * PI, -2 * PI, -PI])
    # theta free at two interior waypoints: chosen where both neighbours stay reachable
    res = acroplan.plan(pike_robot, theta=[-0.5 * PI, None, None, 3.5 * PI], **kw)
    assert res.success, res.message
    assert res.waypoints[0, 0] == -0.5 * PI and res.waypoints[-1, 0] == 3.5 * PI
    assert np.all(np.isfinite(res.waypoints))
    # phi free: the interpolation of its neighbours
    res = acroplan.plan(pike_robot, times=[0, 2, 4], theta=[-0.5 * PI, 3.0, 2.0 * PI], phi=[-PI, None, -PI],
                        conditions="free")
    assert res.success and res.waypoints[1, 1] == -PI
    with pytest.raises(acroplan.InvalidInputError, match="theta: is free .None. at the first or the last"):
        acroplan.plan(pike_robot, times=[0, 2], theta=[None, 1.0], phi=[-PI, -PI])


def test_files_state_problems_the_same_ways(tmp_path):
    """Aliases that say what the distances are, "free" waypoints, degrees, rest at the ends, a
    time budget, and suggestions for unknown tables and keys."""
    from click.testing import CliRunner

    from acroplan.io.cli import main
    from acroplan.io.problem import load_problem

    text = """[robot]
torso_mass = 40.0
leg_mass = 20.0
torso_inertia = 1.8
leg_inertia = 1.2
torso_com_to_joint = 0.35
leg_com_to_joint = 0.45
angular_momentum = 10.0
[plan]
times = [0, 1, 2]
theta = [0, "free", 120]
phi = [-180, -90, -180]
conditions = "free"
[options]
degrees = true
start_rate = 0
end_rate = 0
time_limit = 20
"""
    (tmp_path / "p.toml").write_text(text)
    prob = load_problem(tmp_path / "p.toml")
    assert prob.theta[1] is None and prob.options["degrees"] is True
    res = prob.solve()
    assert res.success, res.message
    assert res.waypoints[-1, 0] == pytest.approx(np.radians(120.0)) and abs(res.segments[0].input(0.0)[0]) < 1e-9
    runner = CliRunner()
    (tmp_path / "q.toml").write_text(text.replace("[plan]", "[plans]"))
    out = runner.invoke(main, ["plan", str(tmp_path / "q.toml"), "--out", str(tmp_path / "o")])
    assert out.exit_code == 2 and "[plans]: is not a known table; did you mean [plan]?" in out.output
    (tmp_path / "r.toml").write_text(text.replace("time_limit", "time_limt"))
    out = runner.invoke(main, ["plan", str(tmp_path / "r.toml"), "--out", str(tmp_path / "o")])
    assert out.exit_code == 2 and "did you mean 'time_limit'?" in out.output
