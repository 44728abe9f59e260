"""The command line's effort: optimal plans (--objective, --tau-max, [options] objective and
tau_max), torque and power columns in trajectory.csv, effort.png, the effort block read back, and
the exact least angular momentum (acroplan least-momentum)."""

import json
import math
import re
import tomllib

import numpy as np
import pytest
from click.testing import CliRunner

import acroplan
from acroplan.families.acrobot.momentum import least_momentum, somersault_table
from acroplan.io.cli import main
from acroplan.io.problem import parse_problem
from acroplan.io.results import load_result

import texts  # the shared problem texts (tests/texts.py)

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml)
pytestmark = pytest.mark.xdist_group("test_cli_effort")

#: a physical acrobot (it gives torques), one segment: energy-optimal in well under a second
BODY = texts.problem()

#: the pike-dive's body (lumped: no torques) with a pike's joint range and rate limit
PIKE = """
[robot]
M1 = "4021/4920"
A1 = "-39/82"
M2 = 0.28
A2 = "-39/164"
P0 = {P0!r}

[plan]
times = [0.0, 1.5]
theta = [0.0, "-3*pi"]
phi = ["-pi", "-pi"]
conditions = "free"

[limits]
phi_min = "-pi"
phi_max = -0.4
u_max = 12.0
"""
PIKE_LIMITS = acroplan.Limits(phi_min=-math.pi, phi_max=-0.4, u_max=12.0)
PIKE_TURN = dict(theta0=0.0, thetaT=-3 * math.pi, phi0=-math.pi, phiT=-math.pi, T=1.5)


def run(args):
    return CliRunner().invoke(main, [str(a) for a in args])


def write(tmp_path, text, name="p.toml"):
    p = tmp_path / name
    p.write_text(text)
    return p


def csv_columns(path):
    with open(path) as f:
        header = f.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, i] for i, name in enumerate(header)}


@pytest.fixture(scope="module")
def energy(tmp_path_factory):
    """``acroplan plan BODY --objective energy``: (output folder, CliRunner result)."""
    tmp = tmp_path_factory.mktemp("energy")
    out = tmp / "out"
    return out, run(["plan", write(tmp, BODY), "--out", out, "--objective", "energy", "--json"])


@pytest.fixture(scope="module")
def limited(tmp_path_factory):
    """``acroplan plan BODY --tau-max phi=31`` (the energy optimum's peak torque is above 33 N m)."""
    tmp = tmp_path_factory.mktemp("limited")
    out = tmp / "out"
    return out, run(["plan", write(tmp, BODY), "--out", out, "--tau-max", "phi=31", "--no-plots"])


# ------------------------------------------------------------------------------ optimal plans
def test_objective_energy_writes_the_torques_power_and_effort_of_the_result(energy):
    out, res = energy
    assert res.exit_code == 0, res.output
    summary = json.loads(res.output)
    assert summary["objective"] == "energy" and set(summary["effort"]) == {"phi"}
    assert {"effort.png", "input.png", "states.png", "solution.json", "trajectory.csv"} <= \
        {p.name for p in out.iterdir()}
    assert (out / "effort.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    sol = json.loads((out / "solution.json").read_text())
    # no plan.conditions in the file: the optimal plan's default, free end rates
    assert sol["objective"] == "energy" and sol["conditions"] == "free"
    opt = sol["segments"][0]["optimality"]
    assert opt["objective"] == "energy" and opt["kkt_converged"] and opt["kkt"] <= opt["kkt_tol"]
    # the CSV's columns: t, the states, the input, then the joint's torque and power
    with open(out / "trajectory.csv") as f:
        assert f.readline().strip() == "t,theta,phi,u,tau_phi,power_phi"
    cols = csv_columns(out / "trajectory.csv")
    result = load_result(out / "solution.json")
    tau, power = result.torques(cols["t"])
    assert np.max(np.abs(cols["tau_phi"] - tau[:, 0])) <= 1e-9
    assert np.max(np.abs(cols["power_phi"] - power[:, 0])) <= 1e-9
    assert np.max(np.abs(cols["power_phi"] - cols["tau_phi"] * cols["u"])) <= 1e-9
    # solution.json's effort block is PlanResult.effort() of the plan it records
    effort = result.effort()["phi"]
    block = sol["effort"]["joints"]["phi"]
    for key in ("peak_torque", "peak_power", "positive_work", "net_work", "torque_squared", "input_squared"):
        assert block[key] == pytest.approx(getattr(effort, key), rel=1e-12, abs=1e-12), key
    assert block["input"] == "u" and block["duration"] == 1.0
    # the peak is the largest |tau| at the samples, or above it (it is refined between them)
    assert np.max(np.abs(cols["tau_phi"])) <= block["peak_torque"] * (1 + 1e-12)
    assert np.max(np.abs(cols["tau_phi"])) >= block["peak_torque"] * (1 - 1e-3)
    # what makes the torque limit of the next test bind
    assert block["peak_torque"] > 31.0 * 1.05


def test_tau_max_is_honoured_or_the_exit_code_says_not_converged(limited):
    out, res = limited
    assert res.exit_code in (0, 4), res.output
    sol = json.loads((out / "solution.json").read_text())
    assert sol["torque_limits"] == {"phi": 31.0} and sol["objective"] == "energy"
    if res.exit_code == 4:
        assert sol["status"] == "not_converged"
        return
    assert "limit 31" in res.output
    cols = csv_columns(out / "trajectory.csv")
    assert np.max(np.abs(cols["tau_phi"])) <= 31.0 * (1 + 1e-9)
    assert sol["effort"]["joints"]["phi"]["peak_torque"] <= 31.0 * (1 + 1e-9)
    assert not (out / "effort.png").exists()  # --no-plots


def test_load_result_reads_the_objective_torque_limits_and_optimality(limited):
    out, res = limited
    assert res.exit_code == 0, res.output
    doc = json.loads((out / "solution.json").read_text())
    result = load_result(out / "solution.json")
    assert result.objective == "energy" and result.torque_limits == {"phi": 31.0}
    assert result.segments[0].optimality == doc["segments"][0]["optimality"]
    assert result.segments[0].optimality["basis_size"] == len(doc["segments"][0]["basis_coefficients"]["u"])
    again = json.loads(json.dumps(result.to_dict()))
    assert {k: v for k, v in again.items() if k != "inputs"} == {k: v for k, v in doc.items() if k != "inputs"}


def test_a_body_gives_a_torque_and_power_column_per_joint(tmp_path):
    out = tmp_path / "out"
    res = run(["plan", "--example", "three-rods-turn", "--out", out])
    assert res.exit_code == 0, res.output
    assert (out / "effort.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with open(out / "trajectory.csv") as f:
        assert f.readline().strip() == "t,theta,q1,q2,u_q1,u_q2,tau_q1,tau_q2,power_q1,power_q2"
    cols = csv_columns(out / "trajectory.csv")
    result = load_result(out / "solution.json")
    tau, power = result.torques(cols["t"])
    for j, joint in enumerate(("q1", "q2")):
        assert np.max(np.abs(cols[f"tau_{joint}"] - tau[:, j])) <= 1e-9
        assert np.max(np.abs(cols[f"power_{joint}"] - cols[f"tau_{joint}"] * cols[f"u_{joint}"])) <= 1e-9
    assert np.max(np.abs(cols["tau_q1"])) > 0.1  # the rods' turn takes torque


def test_the_file_options_and_their_conditions():
    base = tomllib.loads(BODY)
    read = lambda options, plan=None: parse_problem({**base, "plan": {**base["plan"], **(plan or {})},  # noqa: E731
                                                     "options": options})
    p = read({"objective": "torque", "tau_max": {"phi": 50.0}})
    assert p.options["objective"] == "torque" and p.options["tau_max"] == {"phi": 50.0}
    assert p.conditions is None and p.plan_kwargs()["conditions"] is None  # plan()'s default: "free"
    assert read({"tau_max": 50}).options["tau_max"] == 50.0 and read({"tau_max": 50}).conditions is None
    assert read({"objective": "energy"}, {"conditions": "spline"}).conditions == "spline"
    assert read({}).conditions == "spline"  # no optimal plan asked for: today's default


@pytest.mark.parametrize("options, field, words", [
    ('objective = "enrgy"', "options.objective", 'did you mean "energy"'),
    ("objective = 3", "options.objective", '"energy" or "torque"'),
    ("tau_max = -5.0", "options.tau_max", "must be > 0"),
    ("tau_max = [1.0, 2.0]", "options.tau_max", "table by joint"),
    ("[options.tau_max]\nphy = 5.0", "options.tau_max.phy", 'did you mean "phi"'),
])
def test_bad_options_exit_2_naming_the_field(tmp_path, options, field, words):
    res = run(["plan", write(tmp_path, BODY + "\n[options]\n" + options + "\n"), "--out", tmp_path / "o"])
    assert res.exit_code == 2
    assert f"{field}:" in res.output and words in res.output, res.output
    assert not (tmp_path / "o").exists()


def test_torques_of_a_lumped_robot_are_refused_saying_what_to_give(tmp_path):
    lumped = write(tmp_path, PIKE.format(P0=1.25))
    res = run(["plan", lumped, "--out", tmp_path / "o", "--tau-max", "40"])
    assert res.exit_code == 2 and "--tau-max:" in res.output and "physical body" in res.output, res.output
    res = run(["plan", write(tmp_path, PIKE.format(P0=1.25) + '[options]\nobjective = "torque"\n', "t.toml"),
               "--out", tmp_path / "o"])
    assert res.exit_code == 2 and "options.objective:" in res.output and "torso_mass" in res.output, res.output


@pytest.mark.parametrize("args, words", [
    (["--tau-max", "phii=3"], ["--tau-max phii:", 'did you mean "phi"']),
    (["--tau-max", "abc"], ["--tau-max:", "is not a number"]),
    (["--tau-max", "30", "--tau-max", "phi=20"], ["--tau-max:", "mixes"]),
    (["--objective", "enrgy"], ["--objective"]),
    (["--objective", "energy", "--max-coefficients", "61"], ["--max-coefficients:", "at most 60"]),
    (["--max-coefficients", "36"], ["--max-coefficients:", "no objective"]),
])
def test_bad_command_line_options_exit_2(tmp_path, args, words):
    res = run(["plan", write(tmp_path, BODY), "--out", tmp_path / "o", *args])
    assert res.exit_code == 2, res.output
    for w in words:
        assert w in res.output, res.output


def test_max_coefficients_on_the_command_line_stops_the_ladder(tmp_path):
    """``--objective energy --max-coefficients 6``: the ladder stops at its first size (without the
    option it goes on to 10, measured), as plan(max_coefficients=6) gives."""
    ladders = {}
    for extra in ([], ["--max-coefficients", "6"]):
        out = tmp_path / f"o{len(extra)}"
        res = run(["plan", write(tmp_path, BODY), "--out", out, "--objective", "energy", "--no-plots", *extra])
        assert res.exit_code == 0, res.output
        segs = json.loads((out / "solution.json").read_text())["segments"]
        ladders[len(extra)] = [[n for n, _ in seg["optimality"]["ladder"]] for seg in segs]
    assert all(sizes == [6] for sizes in ladders[2]), ladders
    assert any(len(sizes) > 1 for sizes in ladders[0]), ladders


# ---------------------------------------------------------------------------- least momentum
def _printed_P0(output: str, which: str = "least") -> float:
    return float(re.search(rf"^{which} angular momentum: P0 = (\S+)", output, re.M).group(1))


def test_least_momentum_is_exact_and_the_boundary_of_what_plans(tmp_path):
    robot = acroplan.examples.robot("pike-dive")
    res = run(["least-momentum", write(tmp_path, PIKE.format(P0=1.25))])
    assert res.exit_code == 0, res.output
    least = least_momentum(robot, **PIKE_TURN, limits=PIKE_LIMITS)
    most = least_momentum(robot, **PIKE_TURN, limits=PIKE_LIMITS, end="most")
    assert least.success and least.attained and least.P0 < 0
    assert _printed_P0(res.output) == least.P0            # exactly: printed with every digit
    assert _printed_P0(res.output, "largest") == most.P0
    assert "the file's P0 = 1.25: outside that range" in res.output  # 1.25 > 0 turns the wrong way
    # 1% more momentum plans; 1% less is proven impossible
    above = run(["plan", write(tmp_path, PIKE.format(P0=least.P0 * 1.01), "above.toml"), "--out",
                 tmp_path / "above", "--no-plots"])
    assert above.exit_code == 0, above.output
    below = run(["plan", write(tmp_path, PIKE.format(P0=least.P0 * 0.99), "below.toml"), "--out",
                 tmp_path / "below", "--no-plots"])
    assert below.exit_code == 3, below.output
    assert json.loads((tmp_path / "below" / "solution.json").read_text())["status"] == "infeasible"


def test_least_momentum_table_json_and_files(tmp_path):
    robot = acroplan.examples.robot("pike-dive")
    out = tmp_path / "out"
    res = run(["least-momentum", write(tmp_path, PIKE.format(P0=-3.0)), "--somersaults", "1.5,2.5,3.5",
               "--flight-times", "1.4,1.5,1.6", "--out", out, "--json"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    least = least_momentum(robot, **PIKE_TURN, limits=PIKE_LIMITS)
    assert doc["least"]["P0"] == least.P0 and doc["least"]["attained"] is True
    assert doc["file_P0"] == -3.0 and doc["file_P0_enough"] is True
    assert doc["limits"] == {"joint_min": -math.pi, "joint_max": -0.4, "u_max": 12.0}
    assert sorted(p.name for p in out.iterdir()) == ["momentum-table.csv", "momentum-table.md", "momentum.json",
                                                     "momentum.png"]
    assert json.loads((out / "momentum.json").read_text())["least"] == doc["least"]
    tab = somersault_table(robot, somersaults=[1.5, 2.5, 3.5], flight_times=[1.4, 1.5, 1.6], phi0=-math.pi,
                           phiT=-math.pi, limits=PIKE_LIMITS)
    assert doc["table"]["least_abs_P0"] == tab.P0.tolist() and doc["table"]["direction"] == "forward"
    assert (out / "momentum-table.md").read_text().strip() == tab.to_markdown(digits=3)
    rows = (out / "momentum-table.csv").read_text().splitlines()
    assert rows[0] == "somersaults,flight_time,least_abs_P0,message" and len(rows) == 10
    assert [float(r.split(",")[2]) for r in rows[1:]] == tab.P0.ravel().tolist()
    # the table's 1.5 somersaults in 1.5 s is the file's turn
    assert tab.P0[0, 1] == abs(least.P0)
    assert (out / "momentum.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_least_momentum_of_a_two_link_body_matches_its_reachable_set(tmp_path):
    two = """
[body]
angular_momentum = {P0!r}
[[body.link]]
name = "legs"
mass = 20.0
inertia = 1.2
com = [0.3, 0.1]
[[body.link]]
name = "torso"
parent = "legs"
joint = [0.8, 0.0]
joint_name = "hip"
mass = 40.0
inertia = 1.8
com = [0.35, 0.05]
[plan]
times = [0.0, 1.5]
theta = [0.0, "-3*pi"]
hip = [0.2, 0.2]
conditions = "free"
[limits]
hip_min = -0.5
hip_max = 2.5
u_hip = 12.0
"""
    from acroplan.io.problem import load_problem

    res = run(["least-momentum", write(tmp_path, two.format(P0=1.0)), "--json"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    P0 = doc["least"]["P0"]
    assert doc["least"]["attained"] and P0 < 0 and doc["turn"]["joint"] == "hip"
    assert doc["limits"] == {"joint_min": -0.5, "joint_max": 2.5, "u_max": 12.0}
    # the exact interval of acroplan reach (the same body) holds the target just above it, not just below
    for factor, inside in ((1.01, True), (0.99, False)):
        rows = load_problem(write(tmp_path, two.format(P0=P0 * factor), "b.toml")).reach()
        assert rows[0]["reachable"] is inside, (factor, rows)


def test_least_momentum_refuses_a_body_of_three_links(tmp_path):
    res = run(["least-momentum", "--example", "three-rods-turn"])
    assert res.exit_code == 2
    assert "body:" in res.output and "two-link body only" in res.output, res.output


@pytest.mark.parametrize("args, words", [
    (["--somersaults", "0,1"], "--somersaults: 0 is not a positive"),
    (["--flight-times", "1.5,x"], "--flight-times: 'x' is not a number"),
])
def test_least_momentum_bad_options(tmp_path, args, words):
    res = run(["least-momentum", write(tmp_path, PIKE.format(P0=1.25)), *args])
    assert res.exit_code == 2 and words in res.output, res.output


def test_the_optimal_plan_file_in_the_docs_is_valid():
    import pathlib

    text = (pathlib.Path(__file__).parents[1] / "docs" / "problem-files.md").read_text(encoding="utf-8")
    blocks = [b for b in re.findall(r"```toml\n(.*?)```", text, re.S) if "objective" in b]
    assert len(blocks) == 1
    p = parse_problem(tomllib.loads(blocks[0]))
    assert p.options == {"objective": "energy", "tau_max": 31.0} and p.conditions is None
    assert tomllib.loads(blocks[0])["plan"] == tomllib.loads(BODY)["plan"]  # the file the tests plan


def test_least_momentum_exits_3_when_no_momentum_turns_the_body(tmp_path):
    text = PIKE.format(P0=1.0).replace("times = [0.0, 1.5]", "times = [0.0, 0.01]") \
        .replace('phi = ["-pi", "-pi"]', 'phi = ["-pi", -0.4]').replace("u_max = 12.0", "u_max = 1.0")
    res = run(["least-momentum", write(tmp_path, text), "--json"])
    assert res.exit_code == 3
    doc = json.loads(res.output)
    assert doc["least"]["P0"] is None and doc["least"]["success"] is False  # NaN is written as null
    assert "no joint motion is possible" in doc["least"]["message"] and doc["warnings"]
