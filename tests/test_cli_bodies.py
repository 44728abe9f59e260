"""The command line and problem files for planar bodies (issue #11): [body] tables (URDF or link
tables), plan, simulate, reach, animate, solution.json and load_result."""

import json
import math
import re

import numpy as np
import pytest
from click.testing import CliRunner

import acroplan
from acroplan.families.planar import diver_with_arms, planar_space_robot, three_rods, to_urdf
from acroplan.families.planar.examples import EXAMPLES
from acroplan.io import examples as bundled
from acroplan.io.cli import main
from acroplan.io.problem import load_problem, load_simulation, parse_problem, parse_simulation
from acroplan.io.results import load_result

pytest.importorskip("pinocchio")

RODS = """
[body]
angular_momentum = {P0}

[[body.link]]
name = "rod1"
mass = 1.0
inertia = "1/12"
com = [0.5, 0.0]

[[body.link]]
name = "rod2"
parent = "rod1"
joint = [1.0, 0.0]
joint_name = "q1"
mass = 1.0
inertia = "1/12"
com = [0.5, 0.0]

[[body.link]]
name = "rod3"
parent = "rod2"
joint = [1.0, 0.0]
joint_name = "q2"
mass = 1.0
inertia = "1/12"
com = [0.5, 0.0]
"""

PLAN = """
[plan]
times = [0.0, 3.0]
theta = [0.0, 0.4]
q1 = [1.0, 1.0]
q2 = [1.0, 1.0]
conditions = "free"

[limits]
u_max = 2.0

[options]
start_rate = 0.0
end_rate = 0.0
"""


def run(args):
    return CliRunner().invoke(main, [str(a) for a in args])


def write(folder, text, name="p.toml"):
    p = folder / name
    p.write_text(text)
    return p


def links_toml(body) -> str:
    """A [body] table with [[body.link]] tables of ``body`` (numbers written exactly by repr)."""
    out = ["[body]", f"angular_momentum = {body.P0!r}", ""]
    for link in body.links:
        out.append("[[body.link]]")
        out.append(f'name = "{link.name}"')
        if link.parent is not None:
            out += [f'parent = "{link.parent}"', f"joint = [{link.joint[0]!r}, {link.joint[1]!r}]"]
        if link.joint_name is not None:
            out.append(f'joint_name = "{link.joint_name}"')
        out += [f"mass = {link.mass!r}", f"inertia = {link.inertia!r}", f"com = [{link.com[0]!r}, {link.com[1]!r}]"]
        for key in ("lower", "upper", "velocity"):
            if getattr(link, key) is not None:
                out.append(f"{key} = {getattr(link, key)!r}")
        out.append("")
    return "\n".join(out)


def plan_table(body, theta, **joints) -> str:
    wp = {"theta": theta, **joints}
    lines = ["[plan]", f"times = {[float(t) for t in np.linspace(0.0, 1.0, len(theta))]}"]
    lines += [f"{k} = {list(map(float, v))}" for k, v in wp.items()]
    return "\n".join(lines) + '\nconditions = "free"\n'


# ----------------------------------------------------------------------------- files give bodies
@pytest.mark.parametrize("make", [diver_with_arms, planar_space_robot, three_rods])
def test_a_link_table_file_and_a_urdf_file_give_the_same_body(tmp_path, make):
    body = make(P0=1.7)
    (tmp_path / "b.urdf").write_text(to_urdf(body, name="b"))
    mid = {}
    for j, i in zip(body.links.joint_names, body.links.joints):  # inside every joint's limits
        lo, hi = body.links[i].lower, body.links[i].upper
        mid[j] = [0.1, 0.1] if lo is None else [(lo + hi) / 2] * 2
    wp = plan_table(body, [0.0, 0.1], **mid)
    from_links = load_problem(write(tmp_path, links_toml(body) + wp, "links.toml")).system
    from_urdf = load_problem(write(tmp_path, '[body]\nurdf = "b.urdf"\nangular_momentum = 1.7\n' + wp,
                                   "urdf.toml")).system
    for b in (from_links, from_urdf):
        assert b.state_names == body.state_names and b.links.parents == body.links.parents
        lb, lo = body.lumped(), b.lumped()
        assert set(lb) == set(lo) and max(abs(lb[k] - lo[k]) for k in lb) <= 1e-12
        assert b.joint_limits() == body.joint_limits()
    # and the same momentum map at random shapes (the body, not only its parameters)
    S = np.random.default_rng(0).uniform(-3, 3, (body.n_links - 1, 20))
    for b in (from_links, from_urdf):
        I0, a0 = body.momentum_map(S)
        I1, a1 = b.momentum_map(S)
        assert np.allclose(I1, I0, rtol=1e-13, atol=0) and np.allclose(a1, a0, rtol=1e-12, atol=1e-13)


@pytest.mark.parametrize("name", list(EXAMPLES))
def test_bundled_files_are_the_python_examples(name):
    prob = bundled.load(name)
    body, kw = EXAMPLES[name]()
    lb, lp = body.lumped(), prob.system.lumped()
    assert max(abs(lb[k] - lp[k]) for k in lb) <= 1e-12 and prob.system.links.names == body.links.names
    assert prob.times == tuple(kw["times"]) and prob.conditions == kw["conditions"]
    for state in body.state_names:
        assert np.allclose(prob.waypoints[state], kw[state], rtol=0, atol=1e-15)
    lim = prob.limits
    want = body.joint_limits() or acroplan.Limits(u_max=kw.get("u_max"))
    for j in body.links.joint_names:  # the same limits, whether from the table or from u_max
        assert lim.bounds(j) == want.bounds(j) and lim.input_bound(f"u_{j}") == want.input_bound(f"u_{j}")


def test_urdf_limits_hold_unless_the_file_overrides_them(tmp_path):
    body = diver_with_arms(P0=0.0)
    (tmp_path / "d.urdf").write_text(to_urdf(body))
    base = '[body]\nurdf = "d.urdf"\nangular_momentum = 0.0\n' + plan_table(
        body, [0.0, 0.1], hip=[3.0, 3.0], knee=[0.1, 0.1], shoulder=[0.3, 0.3])
    lim = load_problem(write(tmp_path, base)).limits
    assert lim.bounds("hip") == (0.35, 3.5) and lim.input_bound("u_knee") == 14.0
    over = base + '[limits]\nhip_max = "pi"\nknee_min = "none"\nu_shoulder = 2.5\nu_max = 3.0\n'
    lim = load_problem(write(tmp_path, over)).limits
    assert lim.bounds("hip") == (0.35, math.pi) and lim.bounds("knee") == (-math.inf, 2.4)
    assert (lim.input_bound("u_shoulder"), lim.input_bound("u_hip"), lim.input_bound("u_knee")) == (2.5, 3.0, 3.0)
    deg = over.replace('hip_max = "pi"', "hip_max = 180.0").replace("u_max = 3.0", "u_max = 90.0") + \
        "[options]\ndegrees = true\n"
    deg = deg.replace("hip = [3.0, 3.0]", "hip = [170.0, 170.0]").replace("knee = [0.1, 0.1]", "knee = [5.0, 5.0]") \
        .replace("shoulder = [0.3, 0.3]", "shoulder = [20.0, 20.0]").replace("u_shoulder = 2.5", "u_shoulder = 45.0")
    lim = load_problem(write(tmp_path, deg)).limits
    assert lim.bounds("hip")[1] == pytest.approx(math.pi, rel=1e-15)
    assert lim.input_bound("u_hip") == pytest.approx(math.pi / 2, rel=1e-15)
    assert lim.input_bound("u_shoulder") == pytest.approx(math.pi / 4, rel=1e-15)


def test_urdf_path_is_relative_to_the_problem_file(tmp_path, monkeypatch):
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "rods.urdf").write_text(to_urdf(three_rods()))
    p = write(sub, '[body]\nurdf = "rods.urdf"\nangular_momentum = 0.0\n' + PLAN)
    monkeypatch.chdir(tmp_path)
    assert load_problem(p).system.n_links == 3
    monkeypatch.chdir(sub)  # init --example copies the URDF beside the new file
    res = run(["init", "my-diver", "--example", "diver-somersault"])
    assert res.exit_code == 0 and "diver.urdf" in res.output
    assert load_problem(sub / "my-diver.toml").system.links.joint_names == ("hip", "knee", "shoulder")
    res = run(["init", "other", "--example", "diver-somersault"])
    assert res.exit_code == 2 and "diver.urdf: exists" in res.output and not (sub / "other.toml").exists()


# ------------------------------------------------------------------------------------------ plan
@pytest.mark.parametrize("name", list(EXAMPLES))
def test_plan_through_the_cli_meets_the_targets_and_the_pinocchio_check(tmp_path, name):
    from acroplan.families.planar.check import simulate_with_pinocchio

    out = tmp_path / "out"
    res = run(["plan", "--example", name, "--out", out, "--no-plots"])
    assert res.exit_code == 0, res.output
    sol = json.loads((out / "solution.json").read_text())
    prob = bundled.load(name)
    body = prob.system
    # which joint each input drives, and the link table
    assert sol["inputs"] == [{"name": f"u_{j}", "joint": j} for j in body.links.joint_names]
    assert [d["name"] for d in sol["system"]["links"]] == list(body.links.names)
    assert sol["verification"] == "family" and sol["verified"] is True
    # every segment's end is the file's waypoint, and Pinocchio's simulation of the inputs gets there
    result = load_result(out / "solution.json")
    names = body.state_names
    x = np.array([prob.waypoints[n][0] for n in names])
    for k, seg in enumerate(result.segments):
        want = np.array([prob.waypoints[n][k + 1] for n in names])
        assert np.max(np.abs(seg.target - want)) <= 1e-9
        assert set(sol["segments"][k]["basis_coefficients"]) == {f"u_{j}" for j in body.links.joint_names}
        x = simulate_with_pinocchio(body, x, seg.t0, seg.t1, seg.input).y[:, -1]
        assert np.max(np.abs(x - want)) <= 1e-9
        assert sol["segments"][k]["verified_error"] <= 1e-9
    header = (out / "trajectory.csv").read_text().splitlines()[0]
    joints = body.links.joint_names  # every body has its torques (Pinocchio's inverse dynamics)
    assert header == ",".join(["t", *names, *body.input_names, *(f"tau_{j}" for j in joints),
                               *(f"power_{j}" for j in joints)])


def test_plan_writes_a_figure_per_state_and_the_rates(tmp_path):
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, RODS.format(P0=0.0) + PLAN), "--out", out])
    assert res.exit_code == 0, res.output
    assert {"input.png", "states.png", "solution.json", "trajectory.csv"} <= {p.name for p in out.iterdir()}
    assert (out / "states.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_load_result_round_trip(tmp_path):
    out = tmp_path / "out"
    assert run(["plan", write(tmp_path, RODS.format(P0=0.3) + PLAN.replace("0.4]", "0.9]")), "--out", out,
                "--no-plots"]).exit_code == 0
    doc = json.loads((out / "solution.json").read_text())
    result = load_result(out / "solution.json")
    assert type(result.system).__name__ == "PlanarBody" and result.system.P0 == 0.3
    again = json.loads(json.dumps(result.to_dict()))
    skip = {"inputs", "effort"}  # inputs: the command line's; effort: recomputed by quadrature
    assert {k: v for k, v in again.items() if k not in skip} == {k: v for k, v in doc.items() if k not in skip}
    # the motion itself: the CSV's samples again, from the coefficients alone
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    s = result.evaluate(data[::37, 0])
    assert np.max(np.abs(s.states.T - data[::37, 1:4])) <= 1e-12
    assert np.max(np.abs(s.inputs.T - data[::37, 4:6])) <= 1e-12


# -------------------------------------------------------------------------------------- simulate
SIM = """
[simulate]
times = [0.0, 1.0, 2.5]
theta = 0.2
q1 = [1.0, 1.8, 0.6]
q2 = 0.5
u_q2 = [[0.3, -0.4, 0.2], [0.0, 0.5]]
"""


def test_simulate_through_the_cli_is_acroplan_simulate_bit_for_bit(tmp_path):
    from scipy.interpolate import CubicSpline

    out = tmp_path / "out"
    res = run(["simulate", write(tmp_path, RODS.format(P0=0.7) + SIM), "--out", out, "--no-plots", "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.output)["max_verified_error"] <= 1e-9
    sol = json.loads((out / "solution.json").read_text())
    assert sol["verification"] == "family" and sol["simulate"]["motion"] == {"u_q1": "spline", "u_q2": "coefficients"}
    assert sol["inputs"] == [{"name": "u_q1", "joint": "q1"}, {"name": "u_q2", "joint": "q2"}]
    # the rate of q1 is the clamped spline's derivative: check the coefficients against it
    cs = CubicSpline([0.0, 1.0, 2.5], [1.0, 1.8, 0.6], bc_type="clamped").derivative()
    x = np.linspace(-1, 1, 7)
    for k, (t0, t1) in enumerate([(0.0, 1.0), (1.0, 2.5)]):
        c = np.array(sol["segments"][k]["basis_coefficients"]["u_q1"])
        assert np.max(np.abs(np.polynomial.legendre.legval(x, c) - cs(t0 + (x + 1) / 2 * (t1 - t0)))) <= 1e-12
    assert sol["segments"][0]["basis_coefficients"]["u_q2"] == [0.3, -0.4, 0.2]
    assert sol["segments"][1]["basis_coefficients"]["u_q2"] == [0.0, 0.5, 0.0]
    # the joint passes through the file's angles
    assert np.allclose(sol["waypoints"]["q1"], [1.0, 1.8, 0.6], rtol=0, atol=1e-12)
    # bit for bit: acroplan.simulate with the same coefficients
    inputs = [np.array([s["basis_coefficients"]["u_q1"], s["basis_coefficients"]["u_q2"]]) for s in sol["segments"]]
    ref = acroplan.simulate(three_rods(P0=0.7), times=[0.0, 1.0, 2.5], inputs=inputs, theta=0.2, q1=1.0, q2=0.5,
                            verify=False)
    for name in ("theta", "q1", "q2"):
        assert sol["waypoints"][name] == ref.waypoints[:, ref.system.state_names.index(name)].tolist()
    data = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    s = ref.sample(200)
    assert np.array_equal(data, np.column_stack([s.t, s.states.T, s.inputs.T]))
    # and the Pinocchio check agrees with the motion
    from acroplan.families.planar.check import simulate_with_pinocchio

    res_loaded = load_result(out / "solution.json")
    xk = res_loaded.waypoints[0]
    for seg in res_loaded.segments:
        xk = simulate_with_pinocchio(res_loaded.system, xk, seg.t0, seg.t1, seg.input).y[:, -1]
    assert np.max(np.abs(xk - ref.waypoints[-1])) <= 1e-9


def test_simulate_the_acrobot_too(tmp_path):
    text = ("[robot]\nM1 = \"4021/4920\"\nA1 = \"-39/82\"\nM2 = 0.28\nA2 = \"-39/164\"\nP0 = 1.25\n"
            "[simulate]\ntimes = [0, 2, 4]\ntheta = 0.0\nphi = [\"-pi\", \"-2*pi\", \"-pi\"]\n")
    out = tmp_path / "out"
    res = run(["simulate", write(tmp_path, text), "--out", out, "--no-plots"])
    assert res.exit_code == 0, res.output
    sol = json.loads((out / "solution.json").read_text())
    assert sol["inputs"] == [{"name": "u", "joint": "phi"}] and sol["verification"] == "ode"
    assert np.allclose(sol["waypoints"]["phi"], [-np.pi, -2 * np.pi, -np.pi], rtol=0, atol=1e-12)
    sim = load_simulation(tmp_path / "p.toml")
    ref = acroplan.simulate(sim.system, verify=False, **sim.simulate_kwargs())
    assert sol["waypoints"]["theta"] == ref.waypoints[:, 0].tolist()


def test_simulate_example_and_its_wrong_command(tmp_path):
    res = run(["simulate", "--example", "space-robot-arm-loop", "--out", tmp_path / "a", "--no-plots"])
    assert res.exit_code == 0, res.output
    sol = json.loads((tmp_path / "a" / "solution.json").read_text())
    # the loop closes in the shape and turns the base (P0 = 0: the curvature over the loop's area)
    assert abs(sol["waypoints"]["shoulder"][-1]) <= 1e-12 and abs(sol["waypoints"]["elbow"][-1]) <= 1e-12
    assert abs(sol["waypoints"]["theta"][-1]) > 0.01
    res = run(["plan", "--example", "space-robot-arm-loop", "--out", tmp_path / "b"])
    assert res.exit_code == 2 and "acroplan simulate --example space-robot-arm-loop" in res.output
    res = run(["simulate", "--example", "three-rods-turn", "--out", tmp_path / "c"])
    assert res.exit_code == 2 and "has no [simulate] table" in res.output


# ----------------------------------------------------------------------------------- bad files
NONPLANAR = to_urdf(three_rods()).replace('<axis xyz="0 0 1"/>', '<axis xyz="1 0 0"/>', 1)


@pytest.mark.parametrize("text, match", [
    (RODS.format(P0=0.0).replace("angular_momentum = 0.0", "") + PLAN, r"^body\.angular_momentum: is missing"),
    (RODS.format(P0="nan") + PLAN, r"^body\.angular_momentum: must be finite"),
    (RODS.format(P0=0.0).replace('"q1"\nmass = 1.0', '"q1"\nmass = -1.0') + PLAN,
     r"^body\.link\[1\]\.mass: must be > 0"),
    (RODS.format(P0=0.0).replace("mass = 1.0", "masss = 1.0", 1) + PLAN,
     r"^body\.link\[0\]\.masss: is not a known key; did you mean 'mass'\?"),
    (RODS.format(P0=0.0).replace('parent = "rod2"', 'parent = "rod9"') + PLAN,
     r"^body\.link\[2\]\.parent: 'rod9' is not the name of a link"),
    (RODS.format(P0=0.0).replace('com = [0.5, 0.0]', 'com = [0.5]', 1) + PLAN,
     r"^body\.link\[0\]\.com: must be a pair"),
    (RODS.format(P0=0.0).replace('inertia = "1/12"', 'inertia = "1/0"', 1) + PLAN,
     r"^body\.link\[0\]\.inertia: '1/0' divides by zero"),
    (RODS.format(P0=0.0).replace('joint_name = "q2"', 'joint_name = "q1"') + PLAN,
     r"^body\.link\[2\]\.joint_name: joint name 'q1' is used twice"),
    ('[body]\nurdf = "missing.urdf"\nangular_momentum = 0.0\n' + PLAN, r"^body\.urdf: no such file"),
    ('[body]\nurdf = "bad.urdf"\nangular_momentum = 0.0\n' + PLAN,
     r"^body\.urdf: bad\.urdf: urdf joint 'q\d' turns about .* not about z: the body is not planar"),
    ('[body]\nurdf = "bad.urdf"\nangular_momentum = 0.0\n[[body.link]]\nname = "a"\n' + PLAN,
     r"^body: gives both urdf and \[\[body.link\]\] tables"),
    ("[robot]\nM1 = 1.0\nA1 = 0.1\nM2 = 0.2\nA2 = 0.05\nP0 = 1\n" + RODS.format(P0=0.0) + PLAN,
     r"^\[body\]: is given together with \[robot\]"),
    (RODS.format(P0=0.0) + PLAN.replace("q2 = [1.0, 1.0]", "q3 = [1.0, 1.0]"),
     r"^plan\.q3: is not a known key; known keys are \['times', 'theta', 'q1', 'q2', 'conditions'\]"),
    (RODS.format(P0=0.0) + PLAN.replace("q2 = [1.0, 1.0]", ""), r"^plan\.q2: is missing"),
    (RODS.format(P0=0.0) + PLAN.replace("q2 = [1.0, 1.0]", "q2 = [1.0]"), r"^plan\.q2: has 1 value"),
    (RODS.format(P0=0.0) + PLAN.replace("u_max = 2.0", "u_q1 = -1.0"), r"^limits\.u_q1: must be > 0"),
    (RODS.format(P0=0.0) + PLAN.replace("u_max = 2.0", "q1_min = 2.0\nq1_max = 1.0"),
     r"^limits\.q1_min: must be < limits\.q1_max"),
    (RODS.format(P0=0.0) + PLAN.replace("u_max = 2.0", "q1_min = 1.5"),
     r"^plan\.q1: waypoint 0 \(t = 0\) has q1 = 1, outside the joint limits"),
    (RODS.format(P0=0.0) + PLAN.replace("u_max = 2.0", "q9_min = 1.5"), r"^limits\.q9_min: is not a known key"),
    (RODS.format(P0=0.0) + PLAN.replace("u_max = 2.0", "phi_min = 1.5"), r"^limits\.phi_min: is not a known key"),
    (RODS.format(P0=0.0) + PLAN.replace("start_rate = 0.0", 'method = "flat"'), r"^options\.method: "),
    (RODS.format(P0=0.0) + PLAN.replace("start_rate = 0.0", "start_rate = {u_q7 = 0.0}"),
     r"^options\.start_rate\.u_q7: is not an input"),
    (RODS.format(P0=0.0) + SIM, r"^plan: table is missing.*acroplan simulate"),
    ("[body]\nangular_momentum = 0.0\n" + '[[body.link]]\nname = "a0"\nmass = 1.0\ninertia = 0.1\n' +
     "".join(f'[[body.link]]\nname = "a{k}"\nparent = "a{k - 1}"\nmass = 1.0\ninertia = 0.1\n' for k in range(1, 17))
     + PLAN, r"^body\.link: has 17 links, more than 16"),
])
def test_bad_body_files_exit_2_naming_the_field(tmp_path, text, match):
    (tmp_path / "bad.urdf").write_text(NONPLANAR)
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, text), "--out", out])
    assert res.exit_code == 2, res.output
    assert res.output.startswith("acroplan: error: ") and len(res.output.strip().splitlines()) == 1
    assert re.search(match, res.output[len("acroplan: error: "):]), res.output
    assert not out.exists()


@pytest.mark.parametrize("sim, match", [
    (SIM.replace("q2 = 0.5", "q2 = [0.5, 0.6, 0.7]"), r"^simulate\.u_q2: is given together with the angles of q2"),
    (SIM.replace("u_q2 = [[0.3, -0.4, 0.2], [0.0, 0.5]]", ""), r"^simulate\.u_q2: is missing"),
    (SIM.replace("theta = 0.2", "theta = [0.2, 0.3, 0.4]"), r"^simulate\.theta: is what the simulation computes"),
    (SIM.replace("[[0.3, -0.4, 0.2], [0.0, 0.5]]", "[[0.3, -0.4, 0.2]]"),
     r"^simulate\.u_q2: has 1 segment\(s\) but simulate\.times has 2"),
    (SIM.replace("q1 = [1.0, 1.8, 0.6]", "q1 = [1.0, 1.8]"), r"^simulate\.q1: has 2 value\(s\) but simulate\.times"),
    (SIM.replace("q1 = [1.0, 1.8, 0.6]", ""), r"^simulate\.q1: is missing"),
    (SIM.replace("times = [0.0, 1.0, 2.5]", "times = [0.0, 1.0, 1.0]"), r"^simulate\.times: must hold"),
    (SIM.replace("u_q2 = ", "u_q3 = "), r"^simulate\.u_q3: is not a known key; did you mean 'u_q2'\?"),
    (SIM.replace("[0.0, 0.5]]", "[0.0, \"x\"]]"), r"^simulate\.u_q2\[1\]\[1\]: cannot read 'x'"),
    (PLAN, r"^simulate: table is missing"),
])
def test_bad_simulate_tables_exit_2_naming_the_field(tmp_path, sim, match):
    out = tmp_path / "out"
    res = run(["simulate", write(tmp_path, RODS.format(P0=0.0) + sim), "--out", out])
    assert res.exit_code == 2, res.output
    assert re.search(match, res.output[len("acroplan: error: "):]), res.output
    assert not out.exists()


# ----------------------------------------------------------------------------------------- reach
def test_reach_for_bodies(tmp_path):
    # no rate limit on a joint: nothing is known, said plainly
    res = run(["reach", write(tmp_path, RODS.format(P0=0.0) + PLAN.replace("u_max = 2.0", "")), "--out",
               tmp_path / "a"])
    assert res.exit_code == 2 and "exact reachable sets exist for the two-link body only" in res.output
    assert "limits.u_q1" in res.output and not (tmp_path / "a").exists()
    # rate limits on every joint: the bound, and a target beyond it is proven unreachable
    import tomllib

    prob = parse_problem(tomllib.loads(RODS.format(P0=0.0) + PLAN))
    B = prob.system.turn_bound(np.array([0.0, 1.0, 1.0]), np.array([0.4, 1.0, 1.0]), 3.0, prob.limits)
    res = run(["reach", write(tmp_path, RODS.format(P0=0.0) + PLAN), "--out", tmp_path / "b", "--json"])
    assert res.exit_code == 0, res.output
    row = json.loads(res.output)["segments"][0]
    assert row["bound"] == B and row["interval_with_limits"] == [-B, B] and row["reachable"] is None
    far = PLAN.replace("theta = [0.0, 0.4]", f"theta = [0.0, {B * 1.01!r}]")
    res = run(["reach", write(tmp_path, RODS.format(P0=0.0) + far, "far.toml"), "--out", tmp_path / "c"])
    assert res.exit_code == 3 and "NOT reachable" in res.output
    assert (tmp_path / "c" / "reach.png").read_bytes()[:4] == b"\x89PNG"


def test_a_two_link_body_reaches_what_its_acrobot_reaches(tmp_path):
    robot = ("[robot]\ntorso_mass = 40.0\nleg_mass = 20.0\ntorso_inertia = 1.8\nleg_inertia = 1.2\n"
             "torso_length = 0.35\nleg_length = 0.45\nangular_momentum = 10.0\n")
    body = ("[body]\nangular_momentum = 10.0\n[[body.link]]\nname = \"leg\"\nmass = 20.0\ninertia = 1.2\n"
            "com = [0.45, 0.0]\n[[body.link]]\nname = \"torso\"\nparent = \"leg\"\njoint_name = \"phi\"\n"
            "mass = 40.0\ninertia = 1.8\ncom = [0.35, 0.0]\njoint = [0.0, 0.0]\n")
    plan = "[plan]\ntimes = [0, 1, 2]\ntheta = [0, 1.0, 50.0]\nphi = [\"-pi\", \"-pi/2\", \"-pi\"]\n"
    limits = "[limits]\nphi_min = \"-pi\"\nphi_max = 0.0\nu_max = 20.0\n"
    body_limits = "[limits]\nphi_min = \"-pi\"\nphi_max = 0.0\nu_phi = 20.0\n"
    a = run(["reach", write(tmp_path, robot + plan + limits, "a.toml"), "--out", tmp_path / "a", "--json"])
    b = run(["reach", write(tmp_path, body + plan + body_limits, "b.toml"), "--out", tmp_path / "b", "--json"])
    assert a.exit_code == b.exit_code == 3, (a.output, b.output)
    ra, rb = json.loads(a.output)["segments"], json.loads(b.output)["segments"]
    for x, y in zip(ra, rb):
        for key in ("interval", "interval_with_limits"):
            assert np.allclose(x[key], y[key], rtol=0, atol=1e-12)
        assert x["reachable"] == y["reachable"]
    assert [r["reachable"] for r in rb] == [True, False]


# --------------------------------------------------------------------------------------- animate
def test_animate_draws_every_link(tmp_path):
    from PIL import Image

    out = tmp_path / "out"
    assert run(["plan", "--example", "three-rods-turn", "--out", out, "--no-plots"]).exit_code == 0
    res = run(["animate", out, "--fps", "5"])
    assert res.exit_code == 0, res.output
    assert "16 frames" in res.output  # 3 s at 5 frames per second, both ends
    with Image.open(out / "motion.gif") as im:
        assert im.n_frames == 16
    assert (out / "strobe.png").stat().st_size > 5000
    # the drawing: one line per link (the root from its frame origin), from the result's own states
    from acroplan.families.planar.drawing import link_segments

    result = load_result(out / "solution.json")
    segs = link_segments(result.system, result.waypoints[-1])
    assert sorted(i for _, _, i in segs) == [0, 0, 1, 2]  # rod1 (root) to rod2's joint and through its
    # centre of mass, rod2 to rod3's joint, rod3 (a leaf) to its end
    J = result.system.joint_positions(result.waypoints[-1])
    m = np.array([link.mass for link in result.system.links])
    com = np.array([result.system.link_frames(result.waypoints[-1])[i, :2] for i in range(3)])
    assert np.allclose(m @ com, 0.0, atol=1e-12)  # drawn in the centre-of-mass frame
    assert np.allclose(J[1] - J[0], np.linalg.norm(J[1] - J[0]) * np.array([math.cos(0.4), math.sin(0.4)]))


def test_examples_list_the_bodies():
    res = run(["examples"])
    for name in ("diver-somersault", "space-robot-turn", "three-rods-turn", "space-robot-arm-loop"):
        assert name in res.output


def test_the_body_files_in_the_docs_are_valid(tmp_path):
    import pathlib
    import tomllib

    root = pathlib.Path(__file__).parents[1]
    text = (root / "docs" / "problem-files.md").read_text(encoding="utf-8")
    blocks = [b for b in re.findall(r"```toml\n(.*?)```", text, re.S) if "[body]" in b or "[simulate]" in b]
    assert len(blocks) == 5
    full, urdf, sim, outside, allowed = blocks
    prob = parse_problem(tomllib.loads(full))
    assert prob.system.links.joint_names == ("q1", "q2") and prob.limits.input_bound("u_q1") == 2.0
    (tmp_path / "diver.urdf").write_text(bundled.files("diver-somersault")["diver.urdf"])
    assert parse_problem(tomllib.loads(urdf), base=tmp_path).system.links.joint_names == ("hip", "knee", "shoulder")
    body = bundled.text("space-robot-arm-loop").split("[simulate]")[0]
    s = parse_simulation(tomllib.loads(body + sim))
    assert s.motion == {"u_shoulder": "spline", "u_elbow": "coefficients"} and len(s.inputs) == 4
    # the files section (issue #25): plans/ reads the URDF of robots/ only when allowed
    (tmp_path / "plans").mkdir()
    (tmp_path / "robots").mkdir()
    (tmp_path / "robots" / "diver.urdf").write_text(bundled.files("diver-somersault")["diver.urdf"])
    with pytest.raises(acroplan.InvalidInputError, match="body.urdf: '../robots/diver.urdf' is outside the problem "
                       "file's folder"):
        parse_problem(tomllib.loads(outside), base=tmp_path / "plans")
    assert parse_problem(tomllib.loads(outside), base=tmp_path / "plans", allowed=[tmp_path / "robots"]).system.n_links \
        == parse_problem(tomllib.loads(allowed), base=tmp_path / "plans").system.n_links == 4


def test_batch_of_body_files_reads_urdfs_beside_them(tmp_path):
    import csv

    folder = tmp_path / "many"
    folder.mkdir()
    (folder / "rods.urdf").write_text(to_urdf(three_rods()))
    write(folder, '[body]\nurdf = "rods.urdf"\nangular_momentum = 0.0\n' + PLAN, "a.toml")
    write(folder, RODS.format(P0=0.0) + PLAN.replace("theta = [0.0, 0.4]", "theta = [0.0, 400.0]"), "b.toml")
    out = tmp_path / "out"
    res = run(["plan", folder, "--out", out, "--no-plots"])
    assert res.exit_code == 3, res.output  # b's turn is beyond the rate limits' bound: proven
    rows = list(csv.DictReader(open(out / "summary.csv")))
    assert [(r["name"], r["status"]) for r in rows] == [("a", "success"), ("b", "infeasible")]
    sol = json.loads((out / "a" / "solution.json").read_text())
    assert sol["inputs"][0] == {"name": "u_q1", "joint": "q1"} and float(rows[0]["max_verified_error"]) <= 1e-9
    many = "".join(f'[[problem]]\nname = "{n}"\n' + ('[problem.body]\nurdf = "rods.urdf"\nangular_momentum = 0.0\n'
                                                     + PLAN).replace("[plan]", "[problem.plan]")
                   .replace("[limits]", "[problem.limits]").replace("[options]", "[problem.options]")
                   for n in ("x", "y"))
    res = run(["plan", write(folder, many, "many.toml"), "--out", tmp_path / "o2", "--no-plots", "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.output)["counts"] == {"success": 2}
