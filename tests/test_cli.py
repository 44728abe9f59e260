"""The command line: outputs, exit codes, messages, atomic writes."""

import json
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner

from acroplan.io.cli import main

import texts  # the shared problem texts (tests/texts.py)

GOOD = texts.problem(theta="{theta}", conditions="spline")


def run(args):
    return CliRunner().invoke(main, args)


def write(tmp_path, text, name="p.toml"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_example_pike_dive_writes_everything(tmp_path):
    out = tmp_path / "out"
    res = run(["plan", "--example", "pike-dive", "--out", str(out)])
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in out.iterdir()) == ["continuation.png", "input.png", "solution.json", "states.png",
                                                     "trajectory.csv"]
    sol = json.loads((out / "solution.json").read_text())
    assert sol["status"] == "success" and sol["verified"] is True
    assert sol["system"]["params"]["M1"] == pytest.approx(4021 / 4920, rel=1e-15)
    assert sol["inputs"] == [{"name": "u", "joint": "phi"}]  # the joint the input drives
    assert len(sol["segments"]) == 5 and len(sol["segments"][0]["coefficients"]["u"]) == 6
    assert max(s["verified_error"] for s in sol["segments"]) < 1e-9
    with open(out / "trajectory.csv") as f:
        assert f.readline().strip() == "t,theta,phi,u"
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    assert data.shape[0] >= 5 * 199 and data[0, 0] == 0.0 and data[-1, 0] == 10.0
    assert data[-1, 1] == pytest.approx(6.5 * np.pi, abs=1e-9)
    assert (out / "input.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_physical_problem_file_and_force(tmp_path):
    out = tmp_path / "out"
    prob = write(tmp_path, GOOD.format(theta=1.0))
    assert run(["plan", prob, "--out", str(out), "--no-plots"]).exit_code == 0
    sol = json.loads((out / "solution.json").read_text())
    assert sol["system"]["physical"]["torso_mass"] == 40.0
    assert not (out / "input.png").exists()
    res = run(["plan", prob, "--out", str(out)])
    assert res.exit_code == 2 and "--out" in res.output and "add --force" in res.output
    assert run(["plan", prob, "--out", str(out), "--force"]).exit_code == 0
    assert (out / "input.png").exists()


def test_infeasible_exit_3_with_interval_and_nothing_half_written(tmp_path):
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, GOOD.format(theta=50.0)), "--out", str(out)])
    assert res.exit_code == 3
    assert "outside the reachable open interval (" in res.output
    assert sorted(p.name for p in out.iterdir()) == ["solution.json"]
    sol = json.loads((out / "solution.json").read_text())
    assert sol["status"] == "infeasible" and len(sol["infeasible"][0]["interval"]) == 2
    assert not list(tmp_path.glob(".out.*"))


def test_not_converged_exit_4_keeps_diagnostics(tmp_path):
    text = GOOD.format(theta=1.0) + "\n[options]\nmethod = \"deform\"\nn_coefficients = 2\n"
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, text), "--out", str(out)])
    assert res.exit_code == 4
    assert "segment 0" in res.output and "use more coefficients" in res.output
    sol = json.loads((out / "solution.json").read_text())
    assert sol["status"] == "not_converged" and sol["segments"][0]["success"] is False
    assert not (out / "trajectory.csv").exists()


@pytest.mark.parametrize("text, match", [
    ("[robot\n", "is not valid TOML"),
    ("[plan]\ntimes=[0,1]\ntheta=[0,1]\nphi=[0,1]\n", "robot: table is missing"),
    (GOOD.format(theta=1.0).replace("leg_mass = 20.0", "leg_mass = -20.0"), "robot.leg_mass: must be > 0"),
    (GOOD.format(theta=1.0).replace("leg_mass = 20.0", ""), "robot.leg_mass: is missing"),
    (GOOD.format(theta=1.0).replace("leg_mass = 20.0", "leg_mas = 20.0"), "robot.leg_mas: is not a known key"),
    (GOOD.format(theta=1.0).replace("leg_mass = 20.0", "leg_mass = nan"), "robot.leg_mass: must be finite"),
    (GOOD.format(theta=1.0).replace("times = [0, 1]", "times = [0, 1, 2]"), "plan.theta: has 2 value"),
    (GOOD.format(theta=1.0).replace("times = [0, 1]", "times = [1, 0]"), "plan.times: must be strictly"),
    (GOOD.format(theta=1.0).replace('"-pi/2"', '"-pi/"'), r"plan.phi\[1\]: cannot read"),
    (GOOD.format(theta=1.0).replace('"-pi/2"', '"__import__(1)"'), r"plan.phi\[1\]: cannot read"),
    (GOOD.format(theta=1.0).replace('"spline"', '"smooth"'), "plan.conditions: must be"),
    (GOOD.format(theta=1.0) + "\n[options]\nbasis = \"fourier\"\n", "options.basis: must be"),
    (GOOD.format(theta=1.0) + "\n[options]\nn_coefficients = 2.5\n", "options.n_coefficients: must be a whole"),
    ("[robot]\nM1 = 0.3\nA1 = -0.5\nM2 = 0.2\nA2 = -0.25\nP0 = 1\n[plan]\ntimes=[0,1]\ntheta=[0,1]\nphi=[0,1]\n",
     r"robot.M1: must exceed \|A1\|"),
])
def test_invalid_problem_exit_2_one_line(tmp_path, text, match):
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, text), "--out", str(out)])
    assert res.exit_code == 2
    assert res.output.startswith("acroplan: error: ")
    assert len(res.output.strip().splitlines()) == 1
    import re

    assert re.search(match, res.output), res.output
    assert not out.exists()


def test_usage_errors_exit_2(tmp_path):
    assert run(["plan", "--out", str(tmp_path / "o")]).exit_code == 2
    res = run(["plan", "--example", "nope", "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "example: unknown example 'nope'" in res.output
    res = run(["plan", str(tmp_path / "missing.toml"), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2 and "no such file" in res.output
    (tmp_path / "afile").write_text("x")
    res = run(["plan", "--example", "pike-dive", "--out", str(tmp_path / "afile")])
    assert res.exit_code == 2


def test_examples_lists_the_pike_dive():
    res = run(["examples"])
    assert res.exit_code == 0 and "pike-dive" in res.output


def test_console_script_runs():
    res = subprocess.run([sys.executable, "-m", "acroplan", "--help"], capture_output=True, text=True)
    assert res.returncode == 0 and "plan" in res.stdout


def test_a_failure_while_writing_leaves_nothing(tmp_path, monkeypatch):
    import acroplan.io.cli.plan as cli  # the plan command's figures

    def boom(figs, folder, fmts):
        (folder / "input.png").write_bytes(b"partial")
        raise RuntimeError("disk full")

    monkeypatch.setattr(cli, "save", boom)
    out = tmp_path / "out"
    res = run(["plan", "--example", "pike-dive", "--out", str(out)])
    assert res.exit_code != 0 and isinstance(res.exception, RuntimeError)
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_readme_problem_file_is_valid_and_feasible(tmp_path):
    import pathlib
    import re

    readme = (pathlib.Path(__file__).parents[1] / "README.md").read_text()
    block = re.search(r"## Problem file.*?```toml\n(.*?)```", readme, re.S).group(1)
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, block), "--out", str(out), "--no-plots"])
    assert res.exit_code == 0, res.output


def test_reach_command(tmp_path):
    out = tmp_path / "r"
    res = run(["reach", "--example", "pike-dive-limited", "--out", str(out)])
    assert res.exit_code == 0, res.output
    data = json.loads((out / "reach.json").read_text())
    assert len(data["segments"]) == 5 and all(s["reachable"] for s in data["segments"])
    assert (out / "reach.png").read_bytes()[:4] == b"\x89PNG"
    res = run(["reach", write(tmp_path, GOOD.format(theta=50.0)), "--out", str(tmp_path / "r2")])
    assert res.exit_code == 3 and "NOT reachable" in res.output
    assert (tmp_path / "r2" / "reach.json").exists()


def test_limits_in_the_problem_file(tmp_path):
    text = GOOD.format(theta=1.0).replace('conditions = "spline"', 'conditions = "free"')
    text += "\n[limits]\nphi_min = \"-pi\"\nphi_max = 0.0\nu_max = 20.0\n"
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, text), "--out", str(out), "--no-plots"])
    assert res.exit_code == 0, res.output
    sol = json.loads((out / "solution.json").read_text())
    assert sol["limits"]["u_max"] == 20.0
    assert all(s["max_abs_u"] <= 20.0 + 1e-9 for s in sol["segments"])
    assert all(-np.pi - 1e-9 <= v <= 1e-9 for s in sol["segments"] for v in s["state_range"])


@pytest.mark.parametrize("limits, match", [
    ("u_max = -1.0", "limits.u_max: must be > 0"),
    ("u_max = nan", "limits.u_max: must be finite"),
    ("phi_min = 1.0\nphi_max = 0.0", "limits.phi_min: must be < limits.phi_max"),
    ("phi_min = -1.0", r"plan.phi: waypoint 0 \(t = 0\) has phi = -3.14159265359, outside the joint limits"),
    ("phi_mx = 1.0", "limits.phi_mx: is not a known key"),
])
def test_bad_limits_exit_2(tmp_path, limits, match):
    text = GOOD.format(theta=1.0) + f"\n[limits]\n{limits}\n"
    res = run(["plan", write(tmp_path, text), "--out", str(tmp_path / "o")])
    assert res.exit_code == 2
    import re

    assert re.search(match, res.output), res.output


def test_limits_that_make_it_impossible_exit_3(tmp_path):
    text = GOOD.format(theta=2.0) + "\n[limits]\nu_max = 2.0\n"
    res = run(["plan", write(tmp_path, text), "--out", str(tmp_path / "o")])
    assert res.exit_code == 3 and "under the rate limits" in res.output


NIL = """
[robot]
M1 = "4021/4920"
A1 = "-39/82"
M2 = 0.28
A2 = "-39/164"
P0 = 1.25

[nilpotent]
P = ["pi/4", 0, 0]
Q = {Q}
degree = 3
"""


def test_nilpotent_equations_and_example(tmp_path):
    res = run(["nilpotent", "--example", "chapter4", "--equations"])
    assert res.exit_code == 0 and "m10 + m11/2 + m12/3 + m13/4 - 0.9086469918797" in res.output
    out = tmp_path / "n"
    res = run(["nilpotent", "--example", "chapter4", "--out", str(out)])
    assert res.exit_code == 0, res.output
    names = sorted(p.name for p in out.iterdir())
    assert names == ["failure_mode.png", "input.png", "solution.json", "states.png", "trajectory.csv", "u1.png"]
    sol = json.loads((out / "solution.json").read_text())
    assert sol["status"] == "success" and sol["u1_margin"] > 0 and sol["verified_error"] <= 1e-8
    assert sol["counterexample"]["u1_margin"] < 0
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    assert np.all(np.diff(data[:, 0]) > 0) and data[-1, 0] == pytest.approx(2.0, abs=1e-12)
    assert data[-1, 1] == pytest.approx(1.4 * np.pi, abs=1e-8)


def test_nilpotent_exit_codes(tmp_path):
    res = run(["nilpotent", write(tmp_path, NIL.format(Q='["pi/4", 2, 40]')), "--out", str(tmp_path / "a")])
    assert res.exit_code == 3 and "outside the reachable interval" in res.output
    res = run(["nilpotent", write(tmp_path, NIL.format(Q='["pi", 2, 4]')), "--out", str(tmp_path / "b")])
    assert res.exit_code == 2 and "nilpotent.Q.phi: must satisfy |phi| < pi" in res.output
    res = run(["nilpotent", write(tmp_path, NIL.format(Q='["pi/4", 2]')), "--out", str(tmp_path / "c")])
    assert res.exit_code == 2 and "nilpotent.Q: needs 3 values" in res.output
    res = run(["plan", "--example", "chapter4", "--out", str(tmp_path / "d")])
    assert res.exit_code == 2 and "acroplan nilpotent --example chapter4" in res.output


def test_batch_folder_and_file_of_many(tmp_path):
    folder = tmp_path / "many"
    folder.mkdir()
    (folder / "a.toml").write_text(GOOD.format(theta=1.0))
    (folder / "b.toml").write_text(GOOD.format(theta=50.0))  # infeasible
    out = tmp_path / "out"
    res = run(["plan", str(folder), "--out", str(out), "--no-plots"])
    assert res.exit_code == 3, res.output
    import csv

    rows = list(csv.DictReader(open(out / "summary.csv")))
    assert [(r["name"], r["status"]) for r in rows] == [("a", "success"), ("b", "infeasible")]
    assert (out / "a" / "trajectory.csv").exists() and not (out / "b" / "trajectory.csv").exists()
    many = "".join("[[problem]]\n" + f'name = "p{i}"\n' + GOOD.format(theta=0.5 + 0.2 * i)
                   .replace("[robot]", "[problem.robot]").replace("[plan]", "[problem.plan]") for i in range(3))
    res = run(["plan", write(tmp_path, many, "many.toml"), "--out", str(tmp_path / "o2"), "--no-plots", "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.output)["counts"] == {"success": 3}


def test_degrees_switch_draws_the_figures_in_degrees_and_changes_nothing_else(tmp_path, monkeypatch):
    """``acroplan plan --degrees``: states.png's angles and input.png's joint rate in degrees (the
    axis labels say [deg], [deg/s]; the curves, waypoints and limit lines are the radian figure's
    times 180/pi), while solution.json and trajectory.csv are the same bytes as without it."""
    import acroplan.io.cli.plan as plan_cli

    text = GOOD.format(theta=1.0).replace('conditions = "spline"', 'conditions = "free"')
    text += "\n[limits]\nphi_min = \"-pi\"\nphi_max = 0.0\nu_max = 20.0\n"
    prob = write(tmp_path, text)
    saved = []
    real_save = plan_cli.save

    def keep(figs, folder, fmts):
        saved.append(dict(figs))
        real_save(figs, folder, fmts)

    monkeypatch.setattr(plan_cli, "save", keep)
    outs = {}
    for name, extra in (("rad", []), ("deg", ["--degrees"])):
        outs[name] = tmp_path / name
        res = run(["plan", prob, "--out", str(outs[name]), *extra])
        assert res.exit_code == 0, res.output
    assert len(saved) == 2
    rad, deg = saved  # in the order run
    for a in ("solution.json", "trajectory.csv"):
        assert (outs["rad"] / a).read_bytes() == (outs["deg"] / a).read_bytes(), a
    r_axes, d_axes = rad["states"].axes, deg["states"].axes
    assert [ax.get_ylabel() for ax in r_axes] == ["θ [rad]", "φ [rad]"]
    assert [ax.get_ylabel() for ax in d_axes] == ["θ [deg]", "φ [deg]"]
    for ra, da in zip(r_axes, d_axes):
        for rl, dl in zip(ra.lines, da.lines):  # the curve, the waypoints, the limit and reference lines
            (rt, ry), (dt, dy) = rl.get_data(), dl.get_data()
            assert np.array_equal(np.asarray(rt, float), np.asarray(dt, float))
            assert np.allclose(np.asarray(dy, float), np.degrees(np.asarray(ry, float)), rtol=1e-14, atol=0)
    (ri,), (di,) = rad["input"].axes, deg["input"].axes
    assert ri.get_ylabel() == "u = dφ/dt [rad/s]" and di.get_ylabel() == "u = dφ/dt [deg/s]"
    assert np.allclose(di.lines[0].get_ydata(), np.degrees(ri.lines[0].get_ydata()), rtol=1e-14, atol=0)
    limit = [ln.get_ydata()[0] for ln in di.lines if ln.get_linestyle() == ":"]
    assert limit and np.allclose(sorted(limit), [-np.degrees(20.0), np.degrees(20.0)])
    assert "--degrees" in run(["plan", "--help"]).output and "--degrees" in run(["simulate", "--help"]).output
