"""The command line and problem files for spatial bodies (issue #12): [body] with angular_momentum =
[Lx, Ly, Lz] (link tables or a URDF), the root's attitude per waypoint, plan, simulate, animate,
solution.json and load_result; the bundled falling cat."""

import json
import math
import tomllib

import numpy as np
import pytest
from click.testing import CliRunner

from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.examples import falling_cat_turn
from acroplan.io import examples as bundled
from acroplan.io.cli import main
from acroplan.io.problem import load_simulation, parse_problem, parse_simulation
from acroplan.io.results import load_result

pytest.importorskip("pinocchio")

CAT = bundled.text("falling-cat")
BODY = CAT.split("[plan]")[0]

# the cat's joints move through a loop (splines at rest at both ends): the body turns at L = 0
SIMULATE = BODY + """
[simulate]
times = [0.0, 0.125, 0.25, 0.375, 0.5]
attitude_euler_deg = [0.0, 20.0, 0.0]
bend = ["40*(pi/180)", "40*(pi/180)", "40*(pi/180)", "40*(pi/180)", "40*(pi/180)"]
side = [0.0, 1.0, 0.0, -1.0, 0.0]
twist = [0.0, 0.5, 0.9, 0.5, 0.0]
"""


def _run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def _doc(text):
    return tomllib.loads(text)


def test_the_bundled_cat_is_the_python_examples_cat():
    prob = bundled.load("falling-cat")
    cat, kw = falling_cat_turn()
    body = prob.system
    assert type(body).__name__ == "SpatialBody" and body.L == (0.0, 0.0, 0.0)
    assert body.links.names == cat.links.names and body.links.joint_names == cat.links.joint_names
    assert body.links.parents == cat.links.parents
    assert np.max(np.abs(np.array(body._param_tuple) - np.array(cat._param_tuple))) < 1e-12
    for a, b in zip(body.links, cat.links):
        for f in ("com", "joint", "axis"):
            assert np.max(np.abs(np.subtract(getattr(a, f), getattr(b, f)))) < 1e-12
        assert np.max(np.abs(a.inertia_matrix - b.inertia_matrix)) < 1e-12
        for f in ("lower", "upper"):
            assert (getattr(a, f) is None) == (getattr(b, f) is None)
            if getattr(a, f) is not None:
                assert abs(getattr(a, f) - getattr(b, f)) < 1e-12
    pk = prob.plan_kwargs()
    assert tuple(pk["times"]) == tuple(kw["times"]) and pk["conditions"] == kw["conditions"]
    assert pk["start_rate"] == kw["start_rate"] and pk["end_rate"] == kw["end_rate"]
    for name in cat.state_names:
        assert np.max(np.abs(np.array(pk[name]) - np.array(kw[name]))) < 1e-12, name
    # and the same I(s), A(s) at a shape
    s = [0.3, -0.2, 0.4]
    for x, y in zip(body.momentum_map(s), cat.momentum_map(s)):
        assert np.max(np.abs(x - y)) < 1e-12


def test_attitude_forms_give_the_same_waypoints():
    base = CAT.split("attitude = [[")[0]
    rest = CAT.split("0.0]]\n", 1)[1]
    quats = parse_problem(_doc(CAT)).plan_kwargs()
    for form in ('attitude_euler_deg = [[180, 20, 0], [0, 20, 0]]',
                 'attitude_euler = [["pi", "20*(pi/180)", 0], [0, "20*(pi/180)", 0]]',
                 'attitude = [{euler_deg = [180, 20, 0]}, [0.984807753012208, 0.0, 0.17364817766693036, 0.0]]',
                 'attitude_rotvec_deg = [[0, 0, 0], [0, 20, 0]]'):
        kw = parse_problem(_doc(base + form + "\n" + rest)).plan_kwargs()
        if "rotvec" in form:  # another start attitude: identity
            assert np.allclose([kw[n][0] for n in ("qw", "qx", "qy", "qz")], [1, 0, 0, 0], atol=1e-15)
            assert abs(kw["qy"][1] - math.sin(math.radians(10))) < 1e-15
            continue
        for n in ("qw", "qx", "qy", "qz"):
            assert np.max(np.abs(np.array(kw[n]) - np.array(quats[n]))) < 1e-12, (form, n)
    # another Euler sequence: intrinsic ZYX, (20, 0, 0) is 20 degrees about z
    kw = parse_problem(_doc(base + 'attitude_euler_deg = [[0, 0, 0], [20, 0, 0]]\nattitude_seq = "ZYX"\n'
                            + rest)).plan_kwargs()
    assert abs(kw["qz"][1] - math.sin(math.radians(10))) < 1e-15 and abs(kw["qy"][1]) < 1e-15


def test_degrees_apply_to_the_joints_not_to_the_quaternion():
    text = CAT.replace('bend = ["40*(pi/180)", "40*(pi/180)"]', "bend = [40, 40]").replace(
        "[options]", "[options]\ndegrees = true")
    kw = parse_problem(_doc(text)).plan_kwargs()
    ref = parse_problem(_doc(CAT)).plan_kwargs()
    for n in ("qw", "qx", "qy", "qz", "bend", "side", "twist"):
        assert np.max(np.abs(np.array(kw[n]) - np.array(ref[n]))) < 1e-15, n


@pytest.mark.parametrize("edit, field, fix", [
    (("angular_momentum = [0.0, 0.0, 0.0]", "angular_momentum = [0.0, 0.0]"), "body.angular_momentum",
     "[0.0, 0.0, 0.5]"),
    (("axis = [0.0, -1.0, 0.0]", "axis = [0.0, 0.0]"), "body.link[1].axis", "[0.0, 0.0, 0.5]"),
    (("axis = [0.0, -1.0, 0.0]", "axes = [0.0, -1.0, 0.0]"), "body.link[1].axes", "'axis'"),
    (("axis = [0.0, -1.0, 0.0]", "axis = [0.0, 0.0, 0.0]"), "body.link[1].axis", ""),
    (("0.012216666666666667]   # principal", "0.0001]   # principal"), "body.link[0].inertia", ""),
    (("attitude = [[", "attitudes = [["), "plan.attitudes", "'attitude'"),
    (("0.984807753012208, 0.0, 0.17364817766693036, 0.0]]", "0.9, 0.0, 0.17364817766693036, 0.0]]"),
     "plan.attitude[1]", "unit quaternion"),
    (("[0.984807753012208, 0.0, 0.17364817766693036, 0.0]]", "[0.984807753012208, 0.0, 0.17364817766693036]]"),
     "plan.attitude[1]", "[1, 0, 0, 0]"),
    (("side = [0.0, 0.0]", "side = [0.0, 0.0, 0.0]"), "plan.side", ""),
    (("twist = [0.0, 0.0]", ""), "plan.twist", "every joint"),
    (("bend = [\"40*(pi/180)\", \"40*(pi/180)\"]", "bend = [2.0, 2.0]"), "plan.bend", ""),
])
def test_bad_input_exits_2_naming_the_field(tmp_path, edit, field, fix):
    old, new = edit
    assert old in CAT
    path = tmp_path / "bad.toml"
    path.write_text(CAT.replace(old, new, 1), encoding="utf-8")
    res = _run("plan", path, "--out", tmp_path / "out", "--no-plots")
    assert res.exit_code == 2, res.output
    assert field in res.output and fix in res.output, res.output


def test_no_attitude_and_two_attitudes_are_refused(tmp_path):
    lines = [ln for ln in CAT.splitlines() if not ln.startswith(("attitude", "            [0.98"))]
    path = tmp_path / "none.toml"
    path.write_text("\n".join(lines), encoding="utf-8")
    res = _run("plan", path, "--out", tmp_path / "o1")
    assert res.exit_code == 2 and "plan.attitude" in res.output and "attitude = [[w, x, y, z]" in res.output
    path.write_text(CAT.replace("[plan]", "[plan]\nattitude_euler_deg = [[180, 20, 0], [0, 20, 0]]"), encoding="utf-8")
    res = _run("plan", path, "--out", tmp_path / "o2")
    assert res.exit_code == 2 and "plan.attitude" in res.output and "one form" in res.output, res.output


def test_a_planar_momentum_with_spatial_links_says_how_to_make_the_body_spatial(tmp_path):
    path = tmp_path / "planar.toml"
    path.write_text(CAT.replace("angular_momentum = [0.0, 0.0, 0.0]", "angular_momentum = 0.0"), encoding="utf-8")
    res = _run("plan", path, "--out", tmp_path / "out")
    assert res.exit_code == 2 and "body.link[" in res.output and "[Lx, Ly, Lz]" in res.output, res.output


def test_limits_per_joint_go_into_the_link_table():
    text = CAT + "\n[limits]\nbend_max = 1.5\nside_min = \"none\"\nu_twist = 3.0\n"
    body = parse_problem(_doc(text)).system
    bend, side, twist = (body.links[body.links.joints[body.links.joint_index(j)]] for j in ("bend", "side", "twist"))
    assert bend.upper == 1.5 and abs(bend.lower + math.pi / 3) < 1e-15
    assert side.lower is None and abs(side.upper - 70 * math.pi / 180) < 1e-15
    assert twist.velocity == 3.0 and bend.velocity is None
    lim = body.default_limits()
    assert lim.bounds("bend") == (bend.lower, 1.5) and lim.input_bound("u_twist") == 3.0


def test_a_urdf_body(tmp_path):
    from acroplan.families.spatial import to_urdf

    cat, _ = falling_cat_turn()
    (tmp_path / "cat.urdf").write_text(to_urdf(cat.links, "cat"), encoding="utf-8")
    plan = CAT.split("[plan]")[1]
    text = '[body]\nurdf = "cat.urdf"\nangular_momentum = [0.0, 0.5, 0.0]\n\n[plan]' + plan
    prob = parse_problem(_doc(text), base=tmp_path)
    body = prob.system
    assert body.L == (0.0, 0.5, 0.0) and len(body.links.joint_names) == 3
    s = [0.3, -0.2, 0.4]
    for x, y in zip(body.momentum_map(s), cat.momentum_map(s)):
        assert np.max(np.abs(x - y)) < 1e-12
    missing = '[body]\nurdf = "nope.urdf"\nangular_momentum = [0.0, 0.0, 0.0]\n\n[plan]' + plan
    with pytest.raises(Exception) as e:
        parse_problem(_doc(missing), base=tmp_path)
    assert e.value.field == "body.urdf"


def test_simulate_load_back_and_animate(tmp_path):
    """The cheap spatial CLI round: simulate a joint loop of the cat (checked by Pinocchio), load
    solution.json back, animate. (Planning the cat by the CLI takes about 15 s: not in the tests.)"""
    path = tmp_path / "loop.toml"
    path.write_text(SIMULATE, encoding="utf-8")
    sim = load_simulation(path)
    assert sim.initial["qy"] == pytest.approx(math.sin(math.radians(10)), abs=1e-15)
    res = _run("simulate", path, "--out", tmp_path / "sim", "--no-plots")
    assert res.exit_code == 0, res.output
    assert "Pinocchio" in res.output
    doc = json.loads((tmp_path / "sim" / "solution.json").read_text())
    assert doc["system"]["type"] == "SpatialBody" and doc["verification"] == "family"
    assert max(s["verified_error"] for s in doc["segments"]) < 1e-9
    end = doc["waypoints"]
    q_end = np.array([end[n][-1] for n in ("qw", "qx", "qy", "qz")])
    q_start = np.array([end[n][0] for n in ("qw", "qx", "qy", "qz")])
    assert abs(np.linalg.norm(q_end) - 1) < 1e-12
    turn = rot.angle_between(q_start, q_end)
    assert turn > 0.02  # the loop turned the cat at L = 0
    assert [j["joint"] for j in doc["inputs"]] == ["bend", "side", "twist"]

    # round trip: solution.json read back is the same body, waypoints and inputs, and its motion
    # ends where the file says
    result = load_result(tmp_path / "sim" / "solution.json")
    assert result.success and result.verification == "family"
    assert result.system.to_dict() == doc["system"]
    for k, seg in enumerate(result.segments):
        for j, name in enumerate(result.system.input_names):
            assert seg.basis_coefficients[j].tolist() == doc["segments"][k]["basis_coefficients"][name]
    x_end = result.segments[-1].target
    assert rot.angle_between(np.asarray(x_end[:4]), q_end) < 1e-12
    res = _run("animate", tmp_path / "sim", "--fps", 8)
    assert res.exit_code == 0, res.output
    gif = tmp_path / "sim" / "motion.gif"
    assert gif.stat().st_size > 1000 and (tmp_path / "sim" / "strobe.png").stat().st_size > 1000
    from PIL import Image

    with Image.open(gif) as im:
        assert im.n_frames == 25  # 0.5 s played in 3 s (a short motion is slowed) at 8 frames per second, both ends


def test_simulate_attitude_forms_and_errors():
    sim = parse_simulation(_doc(SIMULATE.replace("attitude_euler_deg = [0.0, 20.0, 0.0]",
                                                 "attitude = [1, 0, 0, 0]")))
    assert [sim.initial[n] for n in ("qw", "qx", "qy", "qz")] == [1.0, 0.0, 0.0, 0.0]
    with pytest.raises(Exception) as e:
        parse_simulation(_doc(SIMULATE.replace("attitude_euler_deg = [0.0, 20.0, 0.0]\n", "")))
    assert e.value.field == "simulate.attitude" and "attitude = [w, x, y, z]" in e.value.fix
    with pytest.raises(Exception) as e:
        parse_simulation(_doc(SIMULATE.replace("attitude_euler_deg = [0.0, 20.0, 0.0]", "attitude = [2, 0, 0, 0]")))
    assert e.value.field == "simulate.attitude"


def test_plan_the_bundled_cat_through_the_cli(tmp_path):
    """acroplan plan --example falling-cat (about 11 s): the cat turns over (180 degrees) at L = 0 and
    ends in its starting shape; the end state is the file's target, re-checked by Pinocchio to 1e-9,
    and the joint ranges hold."""
    out = tmp_path / "cat"
    res = _run("plan", "--example", "falling-cat", "--out", out, "--no-plots")
    assert res.exit_code == 0, res.output
    doc = json.loads((out / "solution.json").read_text())
    assert doc["verification"] == "family" and max(s["verified_error"] for s in doc["segments"]) < 1e-9
    prob = parse_problem(tomllib.loads(CAT), name="falling-cat")
    result = load_result(out / "solution.json")
    q0 = np.array([prob.waypoints[n][0] for n in ("qw", "qx", "qy", "qz")])
    q1 = np.array([prob.waypoints[n][-1] for n in ("qw", "qx", "qy", "qz")])
    assert rot.angle_between(q0, q1) == pytest.approx(math.pi, abs=1e-9)
    end = result.segments[-1].target
    assert rot.angle_between(np.asarray(end[:4]), q1) < 1e-9
    for j, name in enumerate(result.system.links.joint_names):
        assert abs(end[4 + j] - prob.waypoints[name][-1]) < 1e-9 and prob.waypoints[name][-1] == prob.waypoints[name][0]
        lo, hi = doc["state_ranges"][name]
        link = result.system.links[result.system.links.joints[j]]
        assert link.lower - 1e-9 <= lo and hi <= link.upper + 1e-9


def _python_succeeds(code: str) -> None:
    """``python -c code`` in a fresh interpreter exits 0 (its stderr the failure's message)."""
    import subprocess
    import sys

    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert res.returncode == 0, res.stderr


def test_the_cats_command_imports_no_sympy_once_its_maps_are_compiled(tmp_path):
    """Issue #22 (the falling cat's command line): with the cat's compiled maps in the cache (a
    first run makes them, deriving the body with sympy), planning it from its problem file imports
    no sympy at all (0.3-0.6 s of the command): the human family's test of the table lives in its
    descriptor, the spatial model derives with sympy only when it compiles, and heyoka is imported
    without it."""
    import subprocess
    import sys

    code = ("import atexit, sys\n"
            "atexit.register(lambda: print('SYMPY', sys.modules.get('sympy') is not None))\n"
            "from acroplan.io.cli import run\n"
            f"sys.argv = ['acroplan', 'plan', '--example', 'falling-cat', '--out', {str(tmp_path / 'cat')!r}, "
            "'--force', '--no-plots', '--quiet']\n"
            "run()\n")
    runs = [subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=600)
            for _ in range(2)]
    for res in runs:
        assert res.returncode == 0, res.stderr
    assert "SYMPY False" in runs[1].stdout, runs[1].stdout
    assert (tmp_path / "cat" / "solution.json").is_file()


def test_a_command_imports_scipy_without_rewriting_its_docstrings():
    """Issue #22 (the falling cat's command line): after ``scipy_docs_as_written`` (what
    ``acroplan.io.cli.app.run`` calls first) scipy's array-API decorator keeps each docstring as
    written (no capabilities table appended), still records the capabilities, and nothing computed
    changes (``nnls`` against its closed form); a second call adds no second hook; a process that
    never calls it gets scipy's own docstrings."""
    api = pytest.importorskip("scipy._lib._array_api")
    if not (callable(getattr(api, "xp_capabilities", None)) and hasattr(api, "FunctionDoc")):
        pytest.skip("this scipy has no array-API capabilities decorator (the hook does nothing)")
    code = ("import sys\n"
            "from acroplan.io.cli.common import scipy_docs_as_written, _ArrayApiFinder\n"
            "scipy_docs_as_written(); scipy_docs_as_written()\n"
            "assert sum(isinstance(f, _ArrayApiFinder) for f in sys.meta_path) == 1\n"
            "import numpy as np, scipy.linalg, scipy._lib._array_api as api\n"
            "from scipy.optimize import nnls\n"
            "assert not any(isinstance(f, _ArrayApiFinder) for f in sys.meta_path)\n"
            "assert scipy.linalg.block_diag in api.xp_capabilities_table\n"
            "assert 'Array API Standard Support' not in scipy.linalg.block_diag.__doc__\n"
            "assert scipy.linalg.block_diag.__doc__.startswith('Create a block diagonal')\n"
            "x, r = nnls(np.array([[1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.array([2.0, 1.0, 1.0]))\n"
            "assert np.allclose(x, [1.5, 1.0], rtol=0, atol=1e-15) and abs(r - 0.5 ** 0.5) < 1e-15\n")
    _python_succeeds(code)
    _python_succeeds("import scipy.linalg\n"
                     "assert 'Array API Standard Support' in scipy.linalg.block_diag.__doc__\n")


def test_a_command_that_draws_imports_pyplot_without_its_docstring_tables():
    """Issue #22 (the falling cat's command line): ``import_pyplot`` imports matplotlib.pyplot with
    matplotlib's ``kwdoc`` (the property tables of the artists' docstrings) stubbed for the import
    alone (the tables are docstrings' text, nothing drawn reads them), restored afterwards; a second
    call does nothing."""
    code = ("import matplotlib; matplotlib.use('Agg'); import matplotlib.artist as a; real = a.kwdoc\n"
            "from acroplan.io.cli.common import import_pyplot; import_pyplot()\n"
            "import sys; assert 'matplotlib.pyplot' in sys.modules and a.kwdoc is real\n"
            "from matplotlib.lines import Line2D; assert 'Properties' not in (Line2D.set.__doc__ or '')\n"
            "import_pyplot()\n")
    _python_succeeds(code)
