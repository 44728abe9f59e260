"""The 3-D human's twisting dives (issue #23): the strength data, the three bundled dives planned
(success, Pinocchio's check, the somersault and twist counts as named from the attitude at the end
in Yeadon's angles, the tilt taken out, rates within the limits and torques within the strength
data), and the twist potential's bisection and command.

Every number asserted is the data's (with its source), the dive's name (its counts), or a bound.
"""

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

import acroplan
from acroplan.families.human.spatial_body import JOINTS, spatial_from_yeadon
from acroplan.families.human.strength import joint_strength, strength_data, torque_limits

# one worker runs this module, so that its plans (one compiled 5-link body) are made once
pytestmark = pytest.mark.xdist_group("test_dives")

pytest.importorskip("yeadon")


# ---------------------------------------------------------------------- strength as data
def test_strength_data_have_sources_or_are_marked_estimates():
    d = strength_data()
    kinds = {dof.kind for dof in JOINTS.values()}
    assert kinds <= set(d["torques"])
    for kind, e in d["torques"].items():
        assert ("value" in e) != ("per_kg" in e), kind
        assert e["estimate"] or e["source"] in d["sources"], kind
        assert isinstance(e["note"], str) and e["note"], kind
    t = d["torques"]
    # the sources' numbers: a static shoulder flexion of young men, Jackson's gymnast's hip flexion
    # (limits.toml, one number in one place), Sarabon et al.'s knee flexion interval's middle
    assert t["shoulder_flexion"]["value"] == 89.9 and not t["shoulder_flexion"]["estimate"]
    assert t["hip_flexion"]["value"] == 157.3 and t["hip_flexion"]["source"] == "Jackson2010"
    assert t["knee_flexion"]["per_kg"] == pytest.approx((1.15 + 1.62) / 2, abs=1e-12)
    assert t["shoulder_abduction"]["estimate"] and t["spine_torsion"]["estimate"]


def test_torque_limits_of_the_full_body_scale_with_mass():
    body = spatial_from_yeadon(joints="full")
    lim = torque_limits(body)
    mass = sum(link.mass for link in body.links)
    assert set(lim) == set(body.links.joint_names)
    assert lim["left_knee_flexion"] == pytest.approx(1.385 * mass, rel=1e-12)
    assert lim["right_elbow_flexion"] == pytest.approx(0.67 * mass, rel=1e-12)
    assert lim["left_hip_flexion"] == 157.3 and lim["right_shoulder_flexion"] == 89.9
    assert joint_strength("knee_flexion", 70.0) == pytest.approx(96.95, abs=1e-9)
    with pytest.raises(acroplan.InvalidInputError):
        joint_strength("neck", 70.0)


# ---------------------------------------------------------------------- the dives
#: name -> (somersaults, twists) as named (signed: backwards < 0; the twist's direction the file's)
NAMED = {"back-full-twist": (-1.0, -1.0), "forward-double-twist": (1.5, 2.0), "back-double-full-out": (-2.0, -1.0)}


@pytest.fixture(scope="module")
def plans():
    """Each dive planned once (the three share one compiled body: the same link table)."""
    from acroplan.io import examples as bundled

    cache = {}

    def get(name):
        if name not in cache:
            prob = bundled.load(name)
            cache[name] = acroplan.plan(prob.system, **prob.plan_kwargs())
        return cache[name]

    return get


@pytest.mark.parametrize("name", sorted(NAMED))
def test_bundled_dive_is_planned_with_its_counts_within_the_limits(plans, name):
    from acroplan.families.human.dives import dive_report

    res = plans(name)
    assert res.status == "success", res.message
    assert res.verification == "family"                       # Pinocchio's centroidal momentum
    assert max(s.verified_error for s in res.segments) < 1e-9
    rep = dive_report(res)
    somersaults, twists = NAMED[name]
    assert abs(rep.somersaults - somersaults) < 1e-6, rep.summary()
    assert abs(rep.twists - twists) < 1e-6, rep.summary()
    assert abs(rep.tilt_end) < 1e-6 and rep.peak_tilt > 3.0    # tilted in the air, not at the landing
    for joint, (peak, limit) in rep.rates.items():
        assert peak <= limit * (1 + 1e-6), (joint, peak, limit)


@pytest.mark.parametrize("name", sorted(NAMED))
def test_bundled_dive_torques_are_within_the_strength_data(plans, name):
    """Every joint's peak torque of the planned dive (its torques by Pinocchio's RNEA) within the
    strength data (data/strength_3d.toml)."""
    from acroplan.families.human.strength import strength_report

    res = plans(name)
    assert res.status == "success", res.message
    for joint, t in strength_report(res).items():
        assert t["peak"] <= t["limit"], (joint, t)


#: each dive's objective: the least integral of tau^2 or of u^2, within the strength data
OBJECTIVE = {"back-full-twist": "torque", "forward-double-twist": "torque", "back-double-full-out": "energy"}


@pytest.mark.parametrize("name", sorted(NAMED))
def test_every_dive_is_an_optimal_plan_within_the_strength_data(plans, name):
    """Each dive's file plans an optimum (the least integral of tau^2, or of u^2) with its torques
    limited to the strength data (its [options.tau_max] are the data's numbers, so they cannot drift
    apart); the plan is that optimum, every interval's SQP converged (KKT residual within its
    target)."""
    from acroplan.io import examples as bundled

    prob = bundled.load(name)
    kw = prob.plan_kwargs()
    assert kw["objective"] == OBJECTIVE[name]
    assert kw["tau_max"] == torque_limits(prob.system)
    res = plans(name)
    assert res.status == "success", res.message
    for seg in res.segments:
        opt = seg.optimality
        assert opt["objective"] == OBJECTIVE[name] and opt["kkt_converged"], seg.message
        # the ladder of basis sizes went on to its last size or converged: no size stopped it by
        # breaking a torque limit between the grid's points (the double full-out's second and
        # third intervals had stopped at 14 of 30 coefficients so)
        assert opt["converged_in_basis"] or opt["ladder"][-1][0] == 30, seg.message


def test_a_3d_human_brings_its_strength_as_the_capacity():
    """A 3-D human read from a file brings its strength as the plan's capacity (a yardstick of
    every plan)."""
    from acroplan.io import examples as bundled

    prob = bundled.load("forward-double-twist")
    kw = prob.plan_kwargs()
    cap = kw["capacity"]["torques"]
    assert {j: top for j, (top, _) in cap.items()} == torque_limits(prob.system)
    assert cap["left_shoulder_abduction"][1].endswith("an estimate")
    assert "estimate" not in cap["left_shoulder_flexion"][1]
    assert bundled.load("back-full-twist").plan_kwargs()["capacity"]["torques"] == cap


def test_a_loop_is_not_refined_in_a_larger_basis_that_did_not_help(monkeypatch):
    """The forward dive's feasible plan (no objective): on its second interval the loops' refinements
    missed by the same amounts at 6 and at 10 coefficients (0.0433, 0.0525-0.0526, 0.127-0.137 rad:
    the joint ranges hold them, not the basis), so they are not tried at 14
    (spatial.strategy.ENLARGE_GAIN): the same plan to the last bit, 55 endpoint evaluations fewer."""
    from acroplan.families.spatial import strategy
    from acroplan.io import examples as bundled

    prob = bundled.load("forward-double-twist")
    kw = {k: v for k, v in prob.plan_kwargs().items() if k not in ("objective", "tau_max")}
    refine, sizes, out = strategy.refine, [], {}
    monkeypatch.setattr(strategy, "refine", lambda *a, **k: sizes.append(a[1].n) or refine(*a, **k))
    for gain in (math.inf, strategy.ENLARGE_GAIN):
        monkeypatch.setattr(strategy, "ENLARGE_GAIN", gain)
        sizes.clear()
        r = acroplan.plan(prob.system, **dict(kw, verify=False))
        assert r.success
        out[gain] = (r, list(sizes))
    (r0, s0), (r1, s1) = out[math.inf], out[strategy.ENLARGE_GAIN]
    assert 14 in s0 and 14 not in s1 and s1 == [n for n in s0 if n != 14], (s0, s1)
    assert all(np.array_equal(a.coefficients, b.coefficients) for a, b in zip(r0.segments, r1.segments))
    assert sum(s.evaluations for s in r0.segments) - sum(s.evaluations for s in r1.segments) >= 40


def test_intervals_before_the_joint_optimum_climb_a_short_ladder(plans, monkeypatch):
    """The back full's two intervals are each optimised, then together (the joint optimum, which
    re-optimises both at their ladders' last size): each interval's ladder is the spatial bodies'
    one before a joint optimum (SpatialBody.optimal_sizes["joint"]: 6, 30), and the joint
    optimum is the one the default ladder (6, 10, 14, 18, 22, 26, 30 for the least integral of
    tau^2) reaches, in fewer endpoint evaluations (measured 268 against 336)."""
    from acroplan.families.spatial.model import SpatialBody
    from acroplan.io import examples as bundled

    res = plans("back-full-twist")
    assert res.status == "success"
    opt = [s.optimality for s in res.segments]
    assert all([n for n, _ in o["ladder"]] == [6, 30] for o in opt), [o["ladder"] for o in opt]
    assert all(o["joint"]["kept"] for o in opt)
    prob = bundled.load("back-full-twist")
    monkeypatch.setattr(SpatialBody, "optimal_sizes", {"torque": SpatialBody.optimal_sizes["torque"]})
    before = acroplan.plan(prob.system, **dict(prob.plan_kwargs(), verify=False))
    old = [s.optimality for s in before.segments]
    assert all([n for n, _ in o["ladder"]] == [6, 10, 14, 18, 22, 26, 30] for o in old)
    # the same KKT point of the joint problem (both converged to 1e-8): the same cost to 1e-7
    assert math.isclose(sum(o["cost"] for o in opt), sum(o["cost"] for o in old), rel_tol=1e-7)
    assert sum(o["evaluations"] for o in opt) < sum(o["evaluations"] for o in old)


def _joint_starts(monkeypatch) -> list:
    """What each joint optimum of the plans that follow starts from, in order: ``"given"`` Hessians
    (a retry's), the ``"intervals"``' own, or forward ``"differences"``."""
    from acroplan.core import chain

    starts = []
    original = chain.joint_optimum

    def recorded(*a, **k):
        starts.append("given" if k.get("curvature") is not None else
                      "intervals" if k.get("interval_curvature") is not None else "differences")
        return original(*a, **k)

    monkeypatch.setattr(chain, "joint_optimum", recorded)
    return starts


def test_the_joint_optimum_starts_from_the_intervals_own_hessians(plans, monkeypatch):
    """The joint optimum starts at the intervals' optima, so its first SQP takes the endpoint
    Hessians those optima ended with (IntervalOutcome.curvature) instead of differencing the
    endpoint Jacobian there again: on the back full no forward differences at its start (some 80
    evaluations), the same optimum as from the differences (both converged to 1e-8: the same cost
    to 1e-7), in fewer evaluations (measured 182 against 268). A retry on a denser grid, which
    starts from the first optimum, differences afresh (the test of the double full-out's rounds)."""
    from acroplan.core import optimal
    from acroplan.io import examples as bundled

    res = plans("back-full-twist")
    assert res.status == "success"
    opt = [s.optimality for s in res.segments]
    assert all(o["joint"]["kept"] for o in opt)
    prob = bundled.load("back-full-twist")
    kw = dict(prob.plan_kwargs(), verify=False)
    starts = _joint_starts(monkeypatch)
    again = acroplan.plan(prob.system, **kw)
    assert starts == ["intervals"], starts
    joint = optimal.EnergyOptimal.joint
    monkeypatch.setattr(optimal.EnergyOptimal, "joint", lambda self, iv, segs, curv=None: joint(self, iv, segs))
    before = acroplan.plan(prob.system, **kw)
    assert starts == ["intervals", "differences"], starts
    new, old = [s.optimality for s in again.segments], [s.optimality for s in before.segments]
    assert all(o["joint"]["kept"] and o["kkt"] <= 1e-8 for o in new + old)
    assert math.isclose(sum(o["cost"] for o in new), sum(o["cost"] for o in old), rel_tol=1e-7)
    assert math.isclose(sum(o["cost"] for o in new), sum(o["cost"] for o in opt), rel_tol=1e-7)
    assert new[0]["joint"]["evaluations"] < old[0]["joint"]["evaluations"], (new[0]["joint"], old[0]["joint"])


def test_a_joint_retry_after_the_intervals_hessians_differences_afresh(monkeypatch):
    """Without the torque limits' points crowded at the intervals' ends (``JOINT_TORQUE_ENDS``
    off), the double full-out's joint optimum is solved again on denser grids (it broke a torque
    limit between the points): its first SQP starts from the intervals' Hessians, the first retry
    from forward differences at the first optimum, each later retry from the retry before's."""
    from acroplan.core import optimal
    from acroplan.io import examples as bundled

    monkeypatch.setattr(optimal, "JOINT_TORQUE_ENDS", False)  # the retries are what is tested
    starts = _joint_starts(monkeypatch)
    prob = bundled.load("back-double-full-out")
    res = acroplan.plan(prob.system, **dict(prob.plan_kwargs(), verify=False))
    assert res.status == "success" and all(s.optimality["joint"]["kept"] for s in res.segments)
    assert len(starts) >= 3 and starts[:2] == ["intervals", "differences"], starts
    assert set(starts[2:]) == {"given"}, starts


def test_the_double_full_outs_joint_optimum_holds_its_torque_limits_on_its_first_grid(plans):
    """With the torque limits also on points crowded at the intervals' ends (``JOINT_TORQUE_ENDS``,
    ``optimum.end_cluster``: its torques peak in boundary layers there), the double full-out's joint
    optimum passes the dense check on its first grid, in one SQP (11 iterations on the machine that
    measured it; four grids and 25 iterations without): no retry in its message, at most 20
    iterations, kept, and the plan's torques within the strength (the plan's own check)."""
    res = plans("back-double-full-out")
    joint = res.segments[0].optimality["joint"]
    assert res.status == "success" and joint["kept"], res.message
    assert "not kept with" not in joint["message"] and joint["iterations"] <= 20, joint


def test_a_plan_beyond_the_strength_is_warned_of(plans):
    """The capacity names the torque model's joints: the back full's plan within its strength
    carries no warning, and against a yardstick below its peak it is warned of, with the peak."""
    from acroplan.families.human.strength import strength_report
    from acroplan.io import examples as bundled
    from acroplan.planning.plausible import beyond_capacity

    res = plans("back-full-twist")
    assert res.status == "success" and not res.warnings, res.message
    peaks = strength_report(res)
    joint = max(peaks, key=lambda j: peaks[j]["peak"])
    cap = bundled.load("back-full-twist").plan_kwargs()["capacity"]
    assert beyond_capacity(res, cap) == ()
    low = {"torques": {joint: (0.5 * peaks[joint]["peak"], "half the peak")}}
    (warning,) = beyond_capacity(res, low)
    assert f"(joint {joint}) is beyond the body's strength" in warning
    assert f"{peaks[joint]['peak']:.4g} N m" in warning


def test_the_dives_are_registered_examples():
    from acroplan.io import examples as bundled

    for name in NAMED:
        assert name in bundled.names() and bundled.command(name) == "plan"
        prob = bundled.load(name)
        assert prob.system.links.joint_names == spatial_from_yeadon(joints="arms").links.joint_names


# ---------------------------------------------------------------------- the twist potential
def test_bisection_finds_the_edge_to_the_resolution():
    from acroplan.families.spatial.potential import bisect_twist

    for edge in (0.3, 1.0, 1.6, 2.74, 7.9):
        lo, hi, tries = bisect_twist(lambda x: x <= edge, 1.0, 0.25)
        assert lo <= edge < hi and hi - lo == pytest.approx(0.25)
        assert all(ok == (x <= edge) for x, ok in tries)
    lo, hi, _ = bisect_twist(lambda x: True, 1.0, 0.25, most=4.0)
    assert lo == 4.0 and hi is None
    lo, hi, _ = bisect_twist(lambda x: False, 1.0, 0.25)
    assert lo == 0.0 and hi == 0.25


def test_technique_from_the_plan_and_scaled(plans):
    """The file's technique read from its plan (the counts between quaternion waypoints), then
    scaled: the times, the somersault, the twist and L = I w follow; the tilt and the arms are kept."""
    from acroplan.families.spatial import rotations as rot
    from acroplan.families.spatial.potential import scaled_problem, technique_of
    from acroplan.io import examples as bundled

    prob = bundled.load("back-full-twist")
    tech = technique_of(prob, plans("back-full-twist"))
    assert tech["somersaults"] == pytest.approx(-1.0, abs=1e-6) and tech["twists"] == pytest.approx(-1.0, abs=1e-6)
    # the waypoints' angles as the file gives them (-170, 8.5, -200 half way), the turns between them counted
    assert tech["somersault"][1] == pytest.approx(-170.0, abs=1e-6) and tech["twist"][1] == pytest.approx(-200.0, abs=1e-6)
    assert tech["tilt"][1] == pytest.approx(8.5, abs=1e-6)
    body, kw = scaled_problem(prob, tech, 2.0, 2.0, 1.5)
    assert kw["times"] == pytest.approx([0.0, 1.0, 2.0])
    assert body.L[0] == pytest.approx(prob.system.L[0] * 2.0 * 1.5 / 2.0, rel=1e-12)
    mid = rot.to_euler(np.array([kw[k][1] for k in ("qw", "qx", "qy", "qz")]))
    # half way: twice the somersault, 1.5 times the twist (mod 360), the tilt kept
    assert mid[1] == pytest.approx(8.5, abs=1e-6)
    assert math.remainder(mid[0] - 2 * tech["somersault"][1], 360.0) == pytest.approx(0.0, abs=1e-9)
    assert math.remainder(mid[2] - 1.5 * tech["twist"][1], 360.0) == pytest.approx(0.0, abs=1e-9)
    assert kw["right_shoulder_abduction"] == prob.waypoints["right_shoulder_abduction"]


def test_the_techniques_flight_in_the_files_own_time_is_the_files_plan(plans):
    """Flown in the file's flight time for the file's somersault, the technique's flight is the
    file's plan again: the same L (the secant starts at it), the same twist, the joints on the
    waypoints; Pinocchio checks it."""
    from acroplan.families.spatial.potential import FLIGHT_TOL, technique_flight, technique_of
    from acroplan.io import examples as bundled

    prob, res = bundled.load("back-full-twist"), plans("back-full-twist")
    tech = technique_of(prob, res)
    fl = technique_flight(prob, res, tech, 1.5, 1.0, acroplan.simulate)
    assert fl is not None and fl.result.verification == "family"
    assert max(s.verified_error for s in fl.result.segments) < 1e-9
    assert abs(fl.somersaults + 1.0) <= FLIGHT_TOL
    # the plan reaches its landing to its endpoint tolerance (1e-12 on the state), so the size of
    # L that turns exactly one somersault is the file's to about that
    assert fl.body.L == pytest.approx(prob.system.L, rel=1e-9, abs=1e-9)
    assert fl.twists == pytest.approx(-1.0, abs=1e-8) and abs(fl.landing_tilt) < 1e-6
    np.testing.assert_allclose(fl.states[:, 4:], res.waypoints[:, 4:], atol=1e-9)
    from acroplan.families.human.dives import dive_report

    top = max(peak / limit for peak, limit in dive_report(res).rates.values())
    assert fl.peak_rate == pytest.approx(top, abs=0.01)         # the plan's peak rate, of its limit


def test_two_somersaults_twist_twice_through_the_techniques_flight(plans):
    """Two somersaults in the same 1.5 s (L about doubled): the technique's flight twists more than
    twice, and a plan through its half-way state to two somersaults and two twists succeeds, the
    counts exact, where waypoints scaled from the file's angles left the planner searching."""
    from acroplan.families.spatial.potential import FLIGHT_TOL, _counts, scaled_problem, technique_flight, technique_of
    from acroplan.io import examples as bundled

    prob, res = bundled.load("back-full-twist"), plans("back-full-twist")
    tech = technique_of(prob, res)
    fl = technique_flight(prob, res, tech, 1.5, 2.0, acroplan.simulate)
    assert fl is not None and abs(fl.somersaults + 2.0) <= FLIGHT_TOL
    k = fl.body.L[0] / prob.system.L[0]
    assert fl.body.L[1:] == (0.0, 0.0) and 1.9 < k < 2.1      # along the file's L, about twice as large
    assert -2.6 < fl.twists < -2.0                               # the same arms, twice the spin
    body, kw = scaled_problem(prob, tech, 1.5, 2.0, 2.0, flight=fl)
    assert body is fl.body and kw["times"] == pytest.approx([0.0, 0.75, 1.5])
    r = acroplan.plan(body, **kw)
    assert r.status == "success", r.message
    assert max(s.verified_error for s in r.segments) < 1e-9
    som, tw = _counts(r)
    assert abs(som + 2.0) < 1e-6 and abs(tw + 2.0) < 1e-6


def test_twist_potential_refuses_a_body_without_it(tmp_path):
    from acroplan.io.cli import main

    res = CliRunner().invoke(main, ["twist-potential", "--example", "pike-dive"])
    assert res.exit_code == 2 and "offers no twist potential" in res.output


def test_twist_potential_command_writes_the_table(tmp_path, monkeypatch):
    """The command end to end on the bundled back full, with the planner replaced by one that
    reaches at most 1.6 twists (the bisection and the files, not the planning, are tested here)."""
    from acroplan import planning
    from acroplan.families.spatial import potential
    from acroplan.io.cli import main

    class Fake:
        def __init__(self, x):
            self.x = x
            self.status = "success" if x <= 1.6 else "not_converged"
            self.message = "" if x <= 1.6 else "not converged: the stages' reasons"

    real = potential.scaled_problem

    def scaled(problem, tech, T, n, x, flight=None):
        assert flight is None   # the fake plan of the file has no segments to fly
        body, kw = real(problem, tech, T, n, x)
        return body, {**kw, "_target": x}

    tech = {"times": np.array([0.0, 0.75, 1.5]), "somersault": np.array([0.0, -170.0, -360.0]),
            "tilt": np.array([0.0, 8.5, 0.0]), "twist": np.array([0.0, -200.0, -360.0]), "somersaults": -1.0,
            "twists": -1.0, "T": 1.5}
    monkeypatch.setattr(potential, "scaled_problem", scaled)
    monkeypatch.setattr(potential, "technique_of", lambda problem, result: tech)
    monkeypatch.setattr(potential, "_counts", lambda res: (-1.0, -res.x))
    monkeypatch.setattr(planning, "plan", lambda body, **kw: Fake(kw.get("_target", 1.0)))
    out = tmp_path / "tp"
    res = CliRunner().invoke(main, ["twist-potential", "--example", "back-full-twist", "--flight-times", "1.2,1.6",
                                    "--somersaults", "1", "--out", str(out), "--json"])
    assert res.exit_code == 0, res.output
    doc = json.loads((out / "twist-potential.json").read_text())
    assert [c["flight_time"] for c in doc["cells"]] == [1.2, 1.6]
    for c in doc["cells"]:
        assert c["most"] == 1.5 and c["failed"] == 1.75 and c["stopped"] == "planner stopped"
    rows = (out / "twist-potential.csv").read_text().splitlines()
    assert rows[0].startswith("somersaults,flight_time,most_twists") and len(rows) == 3
    assert (out / "twist-potential.png").stat().st_size > 1000


SIM_ARM = """[body]
yeadon = "male1"
model = "3d"
joints = "arms"
angular_momentum = [-50.0, 0.0, 0.0]

[simulate]
times = [0.0, 0.1, 0.5, 1.2]
attitude_euler_deg = [0.0, 0.0, 0.0]
left_shoulder_flexion = [0.0, 0.0, 0.0, 0.0]
left_shoulder_abduction = ["170*(pi/180)", "170*(pi/180)", "170*(pi/180)", "170*(pi/180)"]
right_shoulder_flexion = [0.0, 0.0, 0.0, 0.0]
right_shoulder_abduction = ["170*(pi/180)", "170*(pi/180)", "5*(pi/180)", "5*(pi/180)"]
"""


def test_simulate_writes_yeadons_angles_of_an_arm_motion(tmp_path):
    """``acroplan simulate`` of a given arm motion (the right arm lowered sideways in a backward
    layout somersault) writes the pelvis's Yeadon angles (angles.csv) and reports them at the end,
    equal to the unwrapped angles of the result's own states; the asymmetric arm tilts and twists
    the body (Yeadon 1993, Part III)."""
    from acroplan.families.spatial import rotations as rot
    from acroplan.io.cli import main
    from acroplan.io.problem import load_simulation

    path = tmp_path / "arm.toml"
    path.write_text(SIM_ARM)
    out = tmp_path / "sim"
    res = CliRunner().invoke(main, ["simulate", str(path), "--out", str(out), "--no-plots", "--json"])
    assert res.exit_code == 0, res.output
    summary = json.loads(res.output)
    rows = np.loadtxt(out / "angles.csv", delimiter=",", skiprows=1)
    head = (out / "angles.csv").read_text().splitlines()[0]
    assert head == "t,somersault_turns,tilt_deg,twist_turns"
    result = load_simulation(path).run(verify=False)
    t = np.linspace(0.0, 1.2, 4001)
    states = np.concatenate([result.evaluate(c, effort=False).states for c in np.array_split(t, 10)], axis=1)
    ang = np.radians(rot.to_euler(states[:4]))
    som = (np.unwrap(ang[0]) - ang[0][0]) / (2 * math.pi)
    tw = (np.unwrap(ang[2]) - ang[2][0]) / (2 * math.pi)
    end = summary["end_angles"]
    assert end["somersault_turns"] == pytest.approx(som[-1], abs=1e-9) == rows[-1, 1]
    assert end["twist_turns"] == pytest.approx(tw[-1], abs=1e-9) == rows[-1, 3]
    assert end["tilt_deg"] == pytest.approx(np.degrees(ang[1][-1]), abs=1e-9)
    assert som[-1] < -0.5 and abs(tw[-1]) > 0.5 and np.max(np.abs(rows[:, 2])) > 3.0
