"""Human bodies in problem files (issue #13): the [body] keys yeadon, height/mass/sex, split,
position, knee_flexion, shoulder_flexion; the bundled platform-dive example against the Python
example it copies; refusals naming the file's field."""

import json
import math
import shutil
import sys
import tomllib

import numpy as np
import pytest
from click.testing import CliRunner

import acroplan
from acroplan import Acrobot
from acroplan.families.human import from_height_mass, from_yeadon, human_limits, position, sample_measurements
from acroplan.families.human.examples import platform_dive, platform_dive_pike
from acroplan.io import examples as bundled
from acroplan.io.cli import main
from acroplan.io.problem import load_problem, parse_problem

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml), together with the other module that plans the platform dive
# (tests/test_human.py and tests/test_cli_human.py, one group): the energy ladder's integrators,
# compiled by whichever runs first, serve the other (two workers compiled them side by side)
pytestmark = pytest.mark.xdist_group("platform-dive")

pytest.importorskip("yeadon")


def run(args):
    return CliRunner().invoke(main, [str(a) for a in args])


def write(folder, text, name="p.toml"):
    p = folder / name
    p.write_text(text)
    return p


PLAN_HIPS = """
[plan]
times = [0, 1.6]
theta = ["-0.5*pi", "-0.5*pi + 5*pi"]
phi = ["-pi", "-pi"]
conditions = "free"
"""

PLAN_THREE = """
[plan]
times = [0, 1.6]
theta = [0.0, 1.0]
hip = ["pi", "pi"]
shoulder = ["pi", "pi"]
conditions = "free"
"""


@pytest.fixture(scope="module")
def dive():
    return platform_dive()


# ------------------------------------------------------------------------ the bundled example
def test_platform_dive_file_is_the_python_example(dive):
    prob = bundled.load("platform-dive")
    robot, kw = platform_dive_pike()
    assert isinstance(prob.robot, Acrobot)
    for k in ("M1", "A1", "M2", "A2", "P0"):
        assert getattr(prob.robot, k) == pytest.approx(getattr(robot, k), rel=1e-12, abs=1e-12), k
    for k, v in vars(robot.physical).items():
        assert getattr(prob.robot.physical, k) == pytest.approx(v, rel=1e-12, abs=1e-12), k
    # the same waypoints (exactly: the file's arithmetic gives the same doubles), limits and options
    assert prob.times == tuple(kw["times"]) and prob.theta == tuple(kw["theta"]) and prob.phi == tuple(kw["phi"])
    assert prob.theta[-1] - prob.theta[0] == pytest.approx(7.0 * math.pi, abs=1e-14)
    assert prob.limits == kw["limits"] == human_limits(dive.body, "pike")
    assert prob.conditions == kw["conditions"] == "free"
    opts = {k: v for k, v in prob.options.items() if k not in ("phi_min", "phi_max", "u_max", "capacity")}
    assert opts == {k: v for k, v in kw.items() if k not in ("times", "theta", "phi", "limits", "conditions")} == \
        {"objective": "energy"}
    # a file's human body brings its capacity (a yardstick of the plan: warnings, not limits; issue #24)
    from acroplan.families.human.problem import capacity

    assert prob.options["capacity"] == capacity(prob.robot)
    assert prob.robot.P0 == dive.P0 and dive.P0 / dive.least.P0 - 1.0 == pytest.approx(0.149, abs=5e-4)


def test_cli_plans_the_platform_dive_as_the_python_example(tmp_path):
    out = tmp_path / "out"
    res = run(["plan", "--example", "platform-dive", "--out", out, "--no-plots"])
    assert res.exit_code == 0, res.output
    sol = json.loads((out / "solution.json").read_text())
    assert sol["status"] == "success" and sol["objective"] == "energy"
    robot, kw = platform_dive_pike()
    mine = acroplan.plan(robot, **kw)
    assert mine.success and len(sol["segments"]) == len(mine.segments) == 1
    ref = json.loads(json.dumps(mine.to_dict()["segments"]))
    # the options are identical, so the coefficients are bit for bit
    for a, b in zip(sol["segments"], ref):
        assert a["basis_coefficients"] == b["basis_coefficients"] and a["coefficients"] == b["coefficients"]
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    assert data[-1, 1] - data[0, 1] == pytest.approx(7.0 * math.pi, abs=1e-9)  # 3.5 somersaults
    psi = data[:, 2] + math.pi  # hip flexion (delta = 0: arms along the trunk)
    assert psi.max() == pytest.approx(math.radians(149.6), abs=math.radians(0.1)) and psi.max() <= math.radians(150)
    assert np.abs(data[:, 3]).max() == pytest.approx(6.90, abs=0.005)
    assert sol["effort"]["joints"]["phi"]["peak_torque"] == pytest.approx(235.5, abs=0.05)


def test_init_and_least_momentum_of_the_platform_dive(tmp_path, monkeypatch, dive):
    monkeypatch.chdir(tmp_path)
    res = run(["init", "mine", "--example", "platform-dive"])
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.toml"]  # the bundled male1 is named, not copied
    assert (tmp_path / "mine.toml").read_text() == bundled.text("platform-dive")
    assert load_problem(tmp_path / "mine.toml").robot == bundled.robot("platform-dive")
    res = run(["least-momentum", "--example", "platform-dive", "--json"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert doc["least"]["P0"] == pytest.approx(dive.least.P0, rel=1e-12)
    assert doc["least"]["P0"] == pytest.approx(57.2125, abs=1e-4) and doc["file_P0_enough"] is True


def test_the_platform_dive_is_listed():
    assert "platform-dive" in bundled.names() and bundled.command("platform-dive") == "plan"
    assert bundled.files("platform-dive") == {}
    res = run(["examples"])
    assert res.exit_code == 0 and "platform-dive" in res.output and "human body" in res.output


# ------------------------------------------------------------------------ the [body] keys
def test_height_and_mass_give_de_levas_body():
    doc = tomllib.loads('[body]\nheight = 1.8\nmass = 75.0\nsex = "female"\nangular_momentum = 60.0\n' + PLAN_HIPS)
    prob = parse_problem(doc)
    assert prob.robot == from_height_mass(1.8, 75.0, sex="female").two_link(angular_momentum=60.0)
    assert prob.robot.physical.torso_mass + prob.robot.physical.leg_mass == pytest.approx(75.0, rel=1e-14)
    assert not prob.limits.active  # no position, no [limits]: no limits
    male = parse_problem(tomllib.loads('[body]\nheight = 1.8\nmass = 75.0\nangular_momentum = 60.0\n' + PLAN_HIPS))
    assert male.robot == from_height_mass(1.8, 75.0).two_link(angular_momentum=60.0) != prob.robot


def test_a_measurement_file_beside_the_problem(tmp_path):
    shutil.copy(sample_measurements("male1"), tmp_path / "me.txt")
    p = write(tmp_path, '[body]\nyeadon = "me.txt"\nangular_momentum = 60.0\nposition = "straight"\n' + PLAN_HIPS)
    prob = load_problem(p)
    body = from_yeadon()
    assert prob.robot == body.two_link(angular_momentum=60.0)
    assert prob.limits == human_limits(body, "straight")
    lo, hi = prob.limits.bounds("phi")
    assert (lo, hi) == pytest.approx((-math.pi - math.radians(15), -math.pi + math.radians(15)), abs=1e-12)


def test_position_limits_are_overridden_by_limits_key_by_key():
    base = '[body]\nyeadon = "male1"\nangular_momentum = 60.0\nposition = "pike"\n' + PLAN_HIPS
    prob = parse_problem(tomllib.loads(base + '\n[limits]\nphi_max = "-pi/2"\nu_max = "none"\n'))
    lim = prob.limits
    assert lim.bounds("phi") == (-math.pi - math.radians(30), -0.5 * math.pi)
    assert lim.u_max is None
    deg = parse_problem(tomllib.loads(base.replace('"-0.5*pi"', "-90").replace('"-0.5*pi + 5*pi"', "810")
                                      .replace('["-pi", "-pi"]', "[-180, -180]") + "\n[options]\ndegrees = true\n"))
    assert deg.options["phi_min"] == pytest.approx(-210.0, abs=1e-12)
    assert deg.options["phi_max"] == pytest.approx(-30.0, abs=1e-12)
    assert deg.options["u_max"] == pytest.approx(math.degrees(12.0), abs=1e-12)


def test_a_tuck_has_the_positions_knees_unless_told():
    base = '[body]\nheight = 1.75\nmass = 70.0\nangular_momentum = 60.0\nposition = "tuck"\n'
    prob = parse_problem(tomllib.loads(base + PLAN_HIPS))
    knees = position("tuck").knee_flexion
    body = from_height_mass(1.75, 70.0, knee_flexion=knees)
    assert knees == pytest.approx(math.radians(125), abs=1e-12)
    assert prob.robot == body.two_link(angular_momentum=60.0)
    assert prob.limits == human_limits(body, "tuck")


def test_hips_and_shoulders_give_the_three_part_body():
    doc = ('[body]\nyeadon = "male1"\nsplit = "hips+shoulders"\nangular_momentum = 60.0\nposition = "pike"\n'
           + PLAN_THREE + "\n[limits]\nu_hip = 10.0\nshoulder_min = 0.5\n")
    prob = parse_problem(tomllib.loads(doc))
    body = from_yeadon()
    lim3 = human_limits(body, "pike", links=3)
    assert type(prob.system).__name__ == "PlanarBody"
    assert prob.system.state_names == ("theta", "hip", "shoulder")
    assert prob.system.lumped() == body.three_part(angular_momentum=60.0).lumped()
    lim = prob.limits
    assert lim.bounds("hip") == lim3.bounds("hip") == (math.pi - math.radians(150), math.pi + math.radians(30))
    assert lim.bounds("shoulder") == (0.5, lim3.bounds("shoulder")[1])
    assert lim.input_bound("u_hip") == 10.0 and lim.input_bound("u_shoulder") == lim3.input_bound("u_shoulder") == 15
    bare = parse_problem(tomllib.loads(doc.replace('position = "pike"\n', "").split("[limits]")[0]))
    assert not bare.limits.active


@pytest.mark.parametrize("body, field, words", [
    ('yeadon = "male1"\nspilt = "hips"', "body.spilt", "did you mean 'split'"),
    ('yeadon = "male1"\nsplit = "hip"', "body.split", 'did you mean "hips"'),
    ('yeadon = "male1"\nposition = "pik"', "body.position", 'did you mean "pike"'),
    ('yeadon = "male1"\nheight = 1.8', "body.height", "not both"),
    ('height = 1.8', "body.mass", "is missing"),
    ('sex = "female"', "body.height", "is missing"),
    ('height = 180\nmass = 70.0', "body.height", "1.75, not 175"),
    ('height = 1.8\nmass = 70.0\nsex = "f"', "body.sex", "'male' or 'female'"),
    ('yeadon = "nobody.txt"', "body.yeadon", "no such file"),
    ('yeadon = "bad.txt"', "body.yeadon", "yeadon cannot read"),
    ('yeadon = "male1"\nurdf = "diver.urdf"', "body.yeadon", "describe the body one way"),
    ('yeadon = "male1"\nsplit = "hips+shoulders"\nshoulder_flexion = 1.0', "body.shoulder_flexion",
     "[plan].shoulder"),
    ('yeadon = "male1"\nshoulder_flexion = 90', "body.shoulder_flexion", "radians"),
    ('yeadon = "male1"\nknee_flexion = 4.0', "body.knee_flexion", "[0, pi]"),
    ('yeadon = "male1"\nposition = "tuck"\nknee_flexion = 0.0', "body.knee_flexion", "leave body.knee_flexion out"),
])
def test_bad_human_bodies_are_refused_naming_the_field(tmp_path, body, field, words):
    (tmp_path / "bad.txt").write_text("this: is not\nyeadon: 1\n")
    momentum = "" if "angular_momentum" in body else "\nangular_momentum = 60.0"
    p = write(tmp_path, f"[body]\n{body}{momentum}\n" + PLAN_HIPS)
    res = run(["plan", p, "--out", tmp_path / "o"])
    assert res.exit_code == 2, res.output
    assert f"{field}:" in res.output and words in res.output, res.output
    assert not (tmp_path / "o").exists()


def test_a_missing_momentum_and_a_bad_limit_are_refused(tmp_path):
    p = write(tmp_path, '[body]\nyeadon = "male1"\n' + PLAN_HIPS)
    res = run(["plan", p, "--out", tmp_path / "o"])
    assert res.exit_code == 2 and "body.angular_momentum: is missing" in res.output, res.output
    p = write(tmp_path, '[body]\nyeadon = "male1"\nangular_momentum = 60.0\nposition = "pike"\n' + PLAN_HIPS +
              '\n[limits]\nhip_max = 2.0\n')
    res = run(["plan", p, "--out", tmp_path / "o"])
    assert res.exit_code == 2 and "limits.hip_max: is not a known key" in res.output, res.output


def test_without_yeadon_a_file_that_needs_it_says_how_to_install_it(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "yeadon", None)  # import yeadon raises ImportError
    p = write(tmp_path, '[body]\nyeadon = "male1"\nangular_momentum = 60.0\n' + PLAN_HIPS)
    res = run(["plan", p, "--out", tmp_path / "o"])
    assert res.exit_code == 2, res.output
    assert "body.yeadon:" in res.output and 'pip install "acroplan[human]"' in res.output, res.output
    res = run(["plan", "--example", "platform-dive", "--out", tmp_path / "o"])
    assert res.exit_code == 2 and 'pip install "acroplan[human]"' in res.output, res.output
    # de Leva's tables need nothing more
    p = write(tmp_path, '[body]\nheight = 1.75\nmass = 70.0\nangular_momentum = 60.0\n' + PLAN_HIPS)
    assert isinstance(load_problem(p).robot, Acrobot)


# ------------------------------------------------------------------------ the docs
def test_the_docs_show_the_bundled_file_and_a_valid_three_part_file():
    import pathlib
    import re
    import textwrap

    root = pathlib.Path(__file__).parents[1]
    text = (root / "docs" / "problem-files.md").read_text(encoding="utf-8")
    section = text.split("## Human bodies (")[1].split("\n## ")[0]
    assert textwrap.indent(bundled.text("platform-dive"), "    ") in section  # the file as bundled
    blocks = re.findall(r"\n\n((?:    .*\n|\n)+)", section)
    three = [textwrap.dedent(b) for b in blocks if 'split = "hips+shoulders"' in b and "[plan]" in b]
    assert len(three) == 1
    prob = parse_problem(tomllib.loads(three[0]))
    body = from_height_mass(1.75, 70.0)
    assert prob.system.lumped() == body.three_part(angular_momentum=0.0).lumped()
    assert prob.limits.bounds("hip") == human_limits(body, "pike", links=3).bounds("hip")
    human = (root / "docs" / "human.md").read_text(encoding="utf-8")
    assert "acroplan plan --example platform-dive --out platform-dive-out --animate" in human
