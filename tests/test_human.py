"""Human bodies (issue #13): Yeadon's model and de Leva's tables split into two and three parts,
human limits as data, and the 10 m platform dive in pike.

Every number asserted is either yeadon's own (computed independently by yeadon in 3-D from its
solids), a value printed in de Leva (1996), an identity of the paper's table, a closed form, or a
limit from the bundled data with its source.
"""

import doctest
import inspect
import math
import sys

import numpy as np
import pytest

import acroplan
from acroplan.core.errors import InvalidInputError
from acroplan.families.acrobot.reach import reachable_set
from acroplan.families.human import (POSITIONS, SagittalBody, de_leva_table, flight_time, from_height_mass,
                                     from_yeadon, hip_rate_literature, hip_torque_literature, human_data,
                                     human_limits, least_momentum_table, position)
from acroplan.families.human import body as body_module
from acroplan.families.human import deleva as deleva_module
from acroplan.families.human import examples as examples_module
from acroplan.families.human import limits as limits_module
from acroplan.families.human import momentum as momentum_module
from acroplan.families.human import yeadon_body as yeadon_module
from acroplan.families.human.examples import platform_dive
from acroplan.families.human.yeadon_body import load_human, whole_body

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml), together with the other module that plans the platform dive
# (tests/test_human.py and tests/test_cli_human.py, one group): the energy ladder's integrators,
# compiled by whichever runs first, serve the other (two workers compiled them side by side)
pytestmark = pytest.mark.xdist_group("platform-dive")

yeadon = pytest.importorskip("yeadon")

# (hip flexion, shoulder flexion) in rad: straight, pike, arms forward, piked with arms overhead,
# hyperextended with arms back
CONFIGS = [(0.0, 0.0), (2.5, 0.0), (0.0, 1.2), (1.3, 0.6), (2.4, math.pi), (-0.4, -0.8)]


@pytest.fixture(scope="module")
def human():
    return load_human()  # the bundled male1


@pytest.fixture(scope="module")
def male1(human):
    return from_yeadon(human)


def _yeadon_com(human, psi, sigma, kappa):
    """yeadon's whole-body centre of mass at these angles, in the trunk frame (X, Y) = (z, -y)."""
    saved = dict(human.CFG)
    cfg = {k: 0.0 for k in human.CFGnames}
    cfg.update(PJ1extension=-psi, PK1extension=-psi, CA1extension=-sigma, CB1extension=-sigma, J1J2flexion=kappa,
               K1K2flexion=kappa)
    human.set_CFG_dict(cfg)
    c = human.center_of_mass
    out = (float(c[2, 0]), -float(c[1, 0]))
    human.set_CFG_dict(saved)
    return out


# ------------------------------------------------------------------------------------------- yeadon
def test_bundled_sample_is_yeadons_male1(human, male1):
    # yeadon's own whole-body mass; the three parts add up to it
    mass, inertia = whole_body(human)
    assert mass == pytest.approx(58.200488588422544, rel=1e-12)
    assert abs(male1.mass - mass) <= 1e-12 * mass
    assert inertia == pytest.approx(9.630938502211407, rel=1e-12)


def test_two_link_straight_matches_yeadon_whole_body(human, male1):
    """Total mass and the moment of inertia about the somersault axis of the body split at the hips,
    straight with the arms at the sides, equal yeadon's own whole-body values (1e-9 relative)."""
    mass, inertia = whole_body(human, 0.0, 0.0, 0.0)
    robot = male1.two_link(angular_momentum=50.0)
    phys = robot.physical
    assert abs(phys.torso_mass + phys.leg_mass - mass) <= 1e-9 * mass
    assert male1.phi(0.0) == pytest.approx(-math.pi, abs=1e-15)  # straight: phi = -pi
    assert abs(robot.h(male1.phi(0.0)) - inertia) <= 1e-9 * inertia
    # the text's eq. (3) formulas: h(pi) = j + J + mu (L + l)^2
    mu = phys.reduced_mass
    assert robot.M1 - robot.A1 == pytest.approx(phys.leg_inertia + phys.torso_inertia
                                                + mu * (phys.torso_length + phys.leg_length) ** 2, rel=1e-14)


@pytest.mark.parametrize("psi,sigma", CONFIGS)
def test_three_part_matches_yeadon_in_any_sagittal_configuration(human, male1, psi, sigma):
    """The planar body's locked inertia and centre of mass at the joint angles of a yeadon
    configuration equal yeadon's (which rotates its 3-D solids itself): checks the parts, their
    frames and every sign convention (a wrong sign of the hip or shoulder angle moves the centre of
    mass to the other side)."""
    _, inertia = whole_body(human, psi, sigma, 0.0)
    body = male1.three_part(angular_momentum=0.0)
    q = male1.shape(psi, sigma)
    assert abs(body.locked_inertia(list(q)) - inertia) <= 1e-9 * inertia
    assert abs(male1.inertia(psi, sigma) - inertia) <= 1e-9 * inertia
    com = _yeadon_com(human, psi, sigma, 0.0)
    assert np.allclose(male1.center_of_mass(psi, sigma), com, rtol=0, atol=1e-12)
    if sigma == 0.0:  # the two-link body (arms along the trunk) at the same hip flexion
        robot = male1.two_link()
        assert abs(robot.h(male1.phi(psi)) - inertia) <= 1e-9 * inertia


def test_tuck_body_with_flexed_knees_matches_yeadon(human):
    kappa = position("tuck").knee_flexion
    body = from_yeadon(human, knee_flexion=kappa)
    assert body.phi_offset() != 0.0  # the legs' centre of mass leaves the thigh's line
    for psi, sigma in [(0.0, 0.0), (2.3, 0.0), (2.3, 1.0)]:
        _, inertia = whole_body(human, psi, sigma, kappa)
        assert abs(body.inertia(psi, sigma) - inertia) <= 1e-9 * inertia
        assert np.allclose(body.center_of_mass(psi, sigma), _yeadon_com(human, psi, sigma, kappa), atol=1e-12)
        if sigma == 0.0:
            assert abs(body.two_link().h(body.phi(psi)) - inertia) <= 1e-9 * inertia
    # the human's own configuration is left as it was
    assert all(v == 0.0 for v in human.CFG.values())


def test_yeadon_is_optional(monkeypatch):
    monkeypatch.setitem(sys.modules, "yeadon", None)  # "import yeadon" now raises ImportError
    with pytest.raises(ImportError, match=r"pip install acroplan\[human\]"):
        from_yeadon()


def test_bad_measurement_file_is_named(tmp_path):
    bad = tmp_path / "meas.txt"
    bad.write_text("measurementconversionfactor: 0.01\nLs1L: 4.9\n")
    with pytest.raises(InvalidInputError, match="measurements"):
        from_yeadon(str(bad))
    with pytest.raises(InvalidInputError, match="measurements"):
        from_yeadon(str(tmp_path / "missing.txt"))
    with pytest.raises(InvalidInputError, match="knee_flexion"):
        from_yeadon(knee_flexion=4.0)


# ------------------------------------------------------------------------------------------- de Leva
def test_de_leva_table_values_and_identities():
    seg = de_leva_table()["segments"]
    # values printed in de Leva (1996), Table 4 (male, female)
    assert (seg["thigh"]["male"]["mass"], seg["thigh"]["female"]["mass"]) == (14.16, 14.78)
    assert (seg["thigh"]["male"]["com"], seg["thigh"]["female"]["com"]) == (40.95, 36.12)
    assert (seg["trunk"]["male"]["mass"], seg["head"]["male"]["com"]) == (43.46, 59.76)
    assert (seg["upper_arm"]["male"]["r_trans"], seg["shank"]["female"]["r_trans"]) == (26.9, 26.7)
    assert de_leva_table()["reference"]["stature_mm"] == {"male": 1741.0, "female": 1735.0}
    for sex in ("male", "female"):
        parts = [seg[s][sex] for s in ("upper_trunk", "middle_trunk", "lower_trunk")]
        # the trunk is the upper, middle and lower trunk: masses and lengths add up
        assert sum(p["mass"] for p in parts) == pytest.approx(seg["trunk"][sex]["mass"], abs=1e-9)
        assert sum(p["length_mm"] for p in parts) == pytest.approx(seg["trunk"][sex]["length_mm"], abs=1e-9)
        # alternative endpoints: the same masses
        assert seg["head_to_c7"][sex]["mass"] == seg["head"][sex]["mass"]
        assert seg["trunk_from_c7"][sex]["mass"] == seg["trunk_from_shoulders"][sex]["mass"] == seg["trunk"][sex]["mass"]
    total = {sex: seg["head"][sex]["mass"] + seg["trunk"][sex]["mass"] + 2 * sum(
        seg[s][sex]["mass"] for s in ("upper_arm", "forearm", "hand", "thigh", "shank", "foot")) for sex in ("male", "female")}
    assert total["male"] == pytest.approx(100.00, abs=1e-9)
    assert total["female"] == pytest.approx(99.99, abs=1e-9)  # as transcribed (data file's note)


def _de_leva_by_hand(H, M, sex, sigma):
    """The straight body's moment of inertia about the somersault axis, segment by segment (9
    segment kinds, 15 segments), from the table alone: an independent sum of m (r l)^2 + m x^2."""
    seg, ref = de_leva_table()["segments"], de_leva_table()["reference"]["stature_mm"][sex] / 1000
    s = H / ref

    def row(name):
        r = seg[name][sex]
        return r["mass"] / 100, r["length_mm"] / 1000 * s, r["com"] / 100, r["r_trans"] / 100

    names = ("head_to_c7", "trunk_from_shoulders", "upper_arm", "forearm", "hand", "thigh", "shank", "foot")
    tot = row("head_to_c7")[0] + row("trunk_from_shoulders")[0] + 2 * sum(row(n)[0] for n in names[2:])
    pts = []  # (mass, position along the body's axis from the mid-hip, own inertia)
    fm, lt, ct, rt = row("trunk_from_shoulders")
    pts.append((fm, lt * (1 - ct), rt * lt))
    fm, lh, ch, rh = row("head_to_c7")
    pts.append((fm, row("trunk_from_c7")[1] + lh * (1 - ch), rh * lh))
    direction = -1.0 if sigma == 0.0 else 1.0  # arms along the trunk (down) or overhead (up)
    x = lt
    for n in ("upper_arm", "forearm", "hand"):
        fm, length, c, r = row(n)
        pts.append((2 * fm, x + direction * c * length, r * length))
        x += direction * length
    x = 0.0
    for n in ("thigh", "shank", "foot"):
        fm, length, c, r = row(n)
        pts.append((2 * fm, x - c * length, r * length))
        x -= length
    masses = np.array([p[0] for p in pts]) * M / tot
    xs = np.array([p[1] for p in pts])
    ks = np.array([p[2] for p in pts])
    xc = masses @ xs / masses.sum()
    return masses.sum(), float(masses @ ks**2 + masses @ (xs - xc) ** 2)


@pytest.mark.parametrize("sex,H,M", [("male", 1.741, 73.0), ("female", 1.64, 55.0), ("male", 1.90, 92.5)])
def test_de_leva_body_sums_and_inertia(sex, H, M):
    body = from_height_mass(H, M, sex=sex)
    assert abs(body.mass - M) <= 1e-12 * M  # the segments sum to the total mass
    for sigma in (0.0, math.pi):  # arms at the sides, arms overhead
        m_hand, inertia = _de_leva_by_hand(H, M, sex, sigma)
        assert m_hand == pytest.approx(M, rel=1e-12)
        assert abs(body.inertia(0.0, sigma) - inertia) <= 1e-12 * inertia
        assert abs(body.three_part().locked_inertia(list(body.shape(0.0, sigma))) - inertia) <= 1e-9 * inertia
        assert abs(body.two_link(shoulder_flexion=sigma).h(body.phi(0.0, sigma)) - inertia) <= 1e-9 * inertia
    # segment masses are the paper's fractions (rescaled by their sum)
    frac = de_leva_table()["segments"]["thigh"][sex]["mass"] / 100
    legs = 2 * sum(de_leva_table()["segments"][s][sex]["mass"] for s in ("thigh", "shank", "foot")) / 100
    total = 1.0 if sex == "male" else 0.9999
    assert body.legs.mass == pytest.approx(M * legs / total, rel=1e-12)
    assert frac > 0


def test_de_leva_and_yeadon_are_close_for_a_similar_body(male1):
    """Two independent models of an adult man: de Leva's at male1's mass and a stature of 1.74 m
    (an assumption: yeadon does not give stature) within 20 % of yeadon's straight inertia (a
    plausibility check of the units and placements, not a validation)."""
    d = from_height_mass(1.74, male1.mass, sex="male")
    assert abs(d.inertia() / male1.inertia() - 1) < 0.20


def test_de_leva_knees_flex_backwards():
    body = from_height_mass(1.75, 70.0, knee_flexion=2.0)
    assert body.legs.com[1] > 0  # towards +y of the legs' frame: backwards when they hang down
    assert body.inertia(0.0, 0.0) < from_height_mass(1.75, 70.0).inertia(0.0, 0.0)


@pytest.mark.parametrize("kw,field", [({"height": 175.0, "mass": 70.0}, "height"),
                                      ({"height": 1.75, "mass": 7.0}, "mass"),
                                      ({"height": 1.75, "mass": 70.0, "sex": "x"}, "sex"),
                                      ({"height": float("nan"), "mass": 70.0}, "height")])
def test_de_leva_bad_input_names_the_field(kw, field):
    with pytest.raises(InvalidInputError) as e:
        from_height_mass(**kw)
    assert e.value.field == field


# ------------------------------------------------------------------------------------------- limits
def test_limits_data_have_sources_or_are_marked_estimates():
    data = human_data()
    sources = data["sources"]
    n = 0
    for group in ("hip", "knee", "shoulder", "rates", "torques"):
        for name, entry in data[group].items():
            n += 1
            assert entry["estimate"] or entry["source"] in sources, (group, name)
            assert entry["source"] == "" or entry["source"] in sources, (group, name)
            assert entry["note"], (group, name)
    assert n >= 10
    assert hip_rate_literature() == (11.0, 12.8)  # Murtaugh (2000); Murtaugh & Miller (2001)
    assert data["rates"]["hip"]["source"] == "Murtaugh2000"
    assert data["hip"]["extension"]["value"] == 30.0 and not data["hip"]["extension"]["estimate"]  # AAOS
    # an elite gymnast's largest isometric hip torques, one hip (Jackson 2010, tabulated by Millard et al. 2019)
    assert (data["torques"]["hip_flexion"]["value"], data["torques"]["hip_extension"]["value"]) == (157.3, 175.7)
    assert hip_torque_literature() == (314.6, 351.4) and hip_torque_literature(both=False) == (157.3, 175.7)


def test_positions_map_to_two_and_three_part_limits(male1):
    pike = position("pike")
    assert pike.hip == pytest.approx((-math.radians(30), math.radians(150)))
    two = human_limits(male1, "pike")
    lo, hi = two.bounds("phi")
    assert (lo, hi) == pytest.approx((male1.phi(pike.hip[0]), male1.phi(pike.hip[1])), abs=1e-15)
    assert two.input_bound("u") == pike.hip_rate == 12.0
    three = human_limits(male1, "pike", links=3)
    assert three.bounds("hip") == pytest.approx((math.pi - pike.hip[1], math.pi - pike.hip[0]))
    assert three.bounds("shoulder") == pytest.approx((0.0, math.pi + math.radians(60)))
    assert three.input_bound("u_hip") == 12.0 and three.input_bound("u_shoulder") == 15.0
    body = male1.three_part(angular_momentum=30.0, limits=three)
    assert body.default_limits() == three
    straight = human_limits(male1, "straight")
    assert straight.bounds("phi") == pytest.approx((-math.pi - math.radians(15), -math.pi + math.radians(15)))
    with pytest.raises(InvalidInputError) as e:
        human_limits(male1, "tuck")  # male1 was built with straight knees
    assert e.value.field == "position"
    with pytest.raises(InvalidInputError) as e:
        human_limits(male1, "layout")
    assert e.value.field == "position"
    assert set(POSITIONS) == {"pike", "tuck", "straight"}


def test_tuck_limits_carry_the_offset(human):
    body = from_yeadon(human, knee_flexion=position("tuck").knee_flexion)
    lo, hi = human_limits(body, "tuck").bounds("phi")
    d = body.phi_offset()
    assert (lo, hi) == pytest.approx((position("tuck").hip[0] - math.pi + d, position("tuck").hip[1] - math.pi + d))
    assert body.hip_flexion(body.phi(1.7)) == pytest.approx(1.7, abs=1e-15)


# ------------------------------------------------------------------------------------------- the dive
def test_flight_time_is_the_fall_from_the_rise():
    H, r, g = 10.0, 0.2, 9.81
    T = flight_time(H, r, g)
    v0 = math.sqrt(2 * g * r)  # take-off vertical speed for a rise r
    assert v0 * T - 0.5 * g * T**2 == pytest.approx(-H, abs=1e-12)  # the centre of mass falls H at T
    assert T == pytest.approx(1.644, abs=5e-4)
    with pytest.raises(InvalidInputError):
        flight_time(-1.0)


ENERGY = "objective" in inspect.signature(acroplan.plan).parameters  # plan(objective=) is issue #13's

# (objective, through_pike): the default problem energy-optimal (the default) and feasible, and the
# four-waypoint reference problem's feasible plan (its energy-optimal plan is the boundary layers of
# docs/human.md, not a human motion)
DIVES = [("energy", False), (None, False), (None, True)]


@pytest.fixture(scope="module")
def planned(male1):
    """The dives planned once each, on first use: ``planned(objective, through_pike)``."""
    cache = {}

    def get(objective, through):
        if objective is not None and not ENERGY:
            pytest.skip("acroplan.plan has no objective= yet")
        if (objective, through) not in cache:
            d = platform_dive(male1, objective=objective, through_pike=through)
            # no time budget: the first plan compiles the energy ladder's integrators (23 s cold here,
            # over the default 60 s on a machine 2.6x slower or as loaded); what is tested is the plan
            cache[objective, through] = d, acroplan.plan(d.robot, **{**d.kw, "time_limit": None})
        return cache[objective, through]

    return get


@pytest.fixture(params=DIVES, ids=["default", "default-feasible", "through-pike-feasible"])
def dive(request, planned):
    return planned(*request.param)


@pytest.fixture
def default_dive(planned):
    return planned("energy", False)


@pytest.fixture
def reference_dive(planned):
    return planned(None, True)


def test_platform_dive_default_problem(male1):
    """What a user gets without options: two waypoints (take-off and entry straight at the hips), the
    hip rates free at both, the pike's limits, energy-optimal; through_pike=True is the reference
    problem with the hips at rest at take-off and entry."""
    d = platform_dive(male1)
    assert d.kw["times"] == [0.0, d.flight_time] and not d.through_pike
    assert d.kw["theta"] == [-0.5 * math.pi, -0.5 * math.pi + 7 * math.pi]
    assert d.kw["phi"] == [male1.phi(0.0)] * 2
    assert d.kw["conditions"] == "free" and d.kw["objective"] == "energy"
    assert "start_rate" not in d.kw and "end_rate" not in d.kw
    assert d.kw["limits"] == human_limits(male1, "pike")
    ref = platform_dive(male1, through_pike=True)
    assert len(ref.kw["times"]) == 4 and ref.kw["start_rate"] == ref.kw["end_rate"] == 0.0
    assert ref.P0 == d.P0  # the same momentum, set by the same reference motion
    with pytest.raises(InvalidInputError) as e:
        platform_dive(male1, through_pike="yes")
    assert e.value.field == "through_pike"


def test_platform_dive_momentum_is_the_exact_least_with_a_margin(dive):
    d, _ = dive
    assert d.flight_time == pytest.approx(flight_time(10.0, 0.2), rel=1e-15)
    assert d.least.attained and d.least.success
    # at the least momentum the far end of the exact reachable set is exactly 3.5 somersaults, reached
    # only by piking at the full hip rate, holding the deepest pike and opening at the full rate
    least_robot = d.body.two_link(angular_momentum=d.least.P0)
    theta0 = d.kw["theta"][0]
    assert theta0 == -0.5 * math.pi  # upright at take-off
    reach = reachable_set(least_robot, theta0=theta0, phi0=d.kw["phi"][0], phiT=d.kw["phi"][-1], T=d.flight_time,
                          limits=d.limits)
    assert reach.high - theta0 == pytest.approx(7 * math.pi, abs=1e-9)
    assert [u for _, u in reach.extremal["high"]] == [12.0, 0.0, -12.0]
    # the chosen momentum: the reference motion (minimum-jerk ramps at 11 rad/s) turns 3.5 somersaults;
    # checked by simulating the reference's hip rate (exactly a quartic on each ramp) with the
    # compiled integrator, independently of the quadrature that chose P0
    ref = d.reference
    assert ref.peak_rate == pytest.approx(11.0, rel=1e-14) and ref.peak_rate <= d.limits.input_bound("u")

    def u(t):
        s_in, s_out = t / ref.ramp, (d.flight_time - t) / ref.ramp
        du = lambda s: 30 * s**2 - 60 * s**3 + 30 * s**4  # noqa: E731
        if s_in < 1:
            return np.array([ref.pike / ref.ramp * du(s_in)])
        if s_out < 1:
            return np.array([-ref.pike / ref.ramp * du(s_out)])
        return np.array([0.0])

    times = [0.0, ref.ramp, d.flight_time - ref.ramp, d.flight_time]
    sim = acroplan.simulate(d.robot, times=times, inputs=u, n_coefficients=6, theta=theta0, phi=d.kw["phi"][0])
    assert sim.waypoints[-1, 0] - theta0 == pytest.approx(7 * math.pi, abs=1e-9)
    if d.through_pike:  # the pike waypoints' theta are the reference's
        assert np.allclose(sim.waypoints[:, 0], d.kw["theta"], rtol=0, atol=1e-9)
    assert sim.waypoints[-1, 1] == pytest.approx(d.kw["phi"][-1], abs=1e-12)
    assert d.P0 > d.least.P0 and d.margin == pytest.approx(0.149, abs=1e-3)


def test_platform_dive_with_a_given_margin(male1):
    d = platform_dive(male1, margin=0.10, objective=None)
    assert d.P0 == pytest.approx(1.10 * d.least.P0, rel=1e-14)
    assert d.reference.ramp == pytest.approx(0.3485, abs=1e-3)  # faster ramps: less momentum
    assert d.reference.turn_integral(male1, d.flight_time) * d.P0 == pytest.approx(7 * math.pi, abs=1e-9)
    with pytest.raises(InvalidInputError) as e:
        platform_dive(male1, margin=-0.1)
    assert e.value.field == "margin"


def test_platform_dive_stays_inside_the_divers_limits(dive):
    d, res = dive
    assert res.status == "success", res.message
    assert res.verified
    assert getattr(res, "objective", None) == d.kw.get("objective")
    t = np.linspace(0.0, d.flight_time, 40001)
    s = res.evaluate(t)
    theta, phi, u = s.states[0], s.states[1], s.inputs[0]
    # 3.5 somersaults
    assert theta[-1] - theta[0] == pytest.approx(7 * math.pi, abs=1e-9)
    # the hip range of a pike
    lo, hi = d.limits.bounds("phi")
    assert phi.min() >= lo - 1e-9 and phi.max() <= hi + 1e-9
    psi = d.body.hip_flexion(phi)
    assert psi.min() >= math.radians(-30) - 1e-9 and psi.max() <= math.radians(150) + 1e-9
    assert psi.max() > 2.4  # it does pike
    # the rate limit, and the literature's peak hip flexion rate of elite platform divers
    assert np.abs(u).max() <= 12.0 + 1e-9
    assert np.abs(u).max() < hip_rate_literature()[1]
    # take-off and entry straight
    assert psi[0] == pytest.approx(0.0, abs=1e-12) and psi[-1] == pytest.approx(0.0, abs=1e-12)
    if d.through_pike:  # the hips at rest at take-off and entry
        assert u[0] == pytest.approx(0.0, abs=1e-9) and u[-1] == pytest.approx(0.0, abs=1e-9)
    else:  # the rates free: the diver leaves the platform piking and enters opening
        assert u[0] > 3.0 and u[-1] < -3.0


def test_default_dive_is_energy_optimal_and_humanly_possible(default_dive):
    """The default plan (the energy-optimal plan of the two-waypoint problem): converged, peak hip rate
    below the lower literature value (11.0 rad/s), peak hip torques (both hips) below an elite
    gymnast's largest isometric hip flexion and extension torques (Jackson 2010), and
    PlanResult.effort() agreeing with the sampled torques."""
    d, res = default_dive
    assert res.status == "success" and res.verified, res.message
    opt = [seg.optimality for seg in res.segments]
    assert len(opt) == 1 and opt[0]["objective"] == "energy"
    assert opt[0]["kkt"] <= opt[0]["kkt_tol"] == 1e-8 and opt[0]["kkt_converged"] and opt[0]["converged"]
    t = np.linspace(0.0, d.flight_time, 40001)
    s = res.evaluate(t)
    u, tau = s.inputs[0], s.torques[0]
    assert np.abs(u).max() < hip_rate_literature()[0]  # 11.0 rad/s
    flexion, extension = hip_torque_literature()
    assert tau.max() < flexion and -tau.min() < extension
    assert np.abs(tau).max() < 300.0  # measured 235.5 N m (docs/human.md); thousands with through_pike
    psi = d.body.hip_flexion(s.states[1])
    assert psi.max() > math.radians(145)  # a deep pike
    effort = res.effort()
    assert set(effort) == {"phi"}
    e = effort["phi"]
    assert e.peak_torque >= np.abs(tau).max() - 1e-9 and e.peak_torque == pytest.approx(np.abs(tau).max(), rel=1e-6)
    assert e.torque_squared == pytest.approx(np.trapezoid(tau**2, t), rel=1e-6)
    assert e.input_squared == pytest.approx(opt[0]["integral_u2"], rel=1e-10)
    assert e.net_work == pytest.approx(np.trapezoid(tau * u, t), abs=1e-3)


def test_effort_of_the_reference_problem(reference_dive):
    """PlanResult.effort() on the plan with four waypoints (three segments), against sampled torques."""
    d, res = reference_dive
    e = res.effort()["phi"]
    t = np.linspace(0.0, d.flight_time, 60001)
    s = res.evaluate(t)
    tau, u = s.torques[0], s.inputs[0]
    assert len(res.segments) == 3
    assert e.peak_torque == pytest.approx(np.abs(tau).max(), rel=1e-6)
    assert e.torque_squared == pytest.approx(np.trapezoid(tau**2, t), rel=1e-5)
    assert e.input_squared == pytest.approx(np.trapezoid(u**2, t), rel=1e-6)


# ------------------------------------------------------------------------------------------- least momentum
@pytest.fixture(scope="module")
def coach():
    """The coach's table for male1 with the 10 m platform's flight among the flight times."""
    return least_momentum_table(flight_times=(1.2, 1.4, flight_time(10.0, 0.2), 1.8))


def test_least_momentum_table_is_monotone_and_ordered(coach):
    P = coach.P0
    assert coach.positions == ("pike", "tuck", "straight") and P.shape == (3, 4, 4)
    assert np.all(np.isfinite(P)) and np.all(P > 0)
    assert np.all(np.diff(P, axis=1) > 0)  # more somersaults need more momentum
    assert np.all(np.diff(P, axis=2) < 0)  # longer flights less
    pike, tuck, straight = P
    assert np.all(straight > pike) and np.all(pike > tuck)
    # take-off and entry at the same hip angle: the least momentum is 2 pi n / J+(T), proportional to n
    per = P / coach.somersaults[None, :, None]
    assert np.allclose(per, per[:, :1, :], rtol=1e-9, atol=0)
    # the headline dive's least momentum: the same number from the table
    assert coach.least("pike", 3.5, flight_time(10.0, 0.2)) == pytest.approx(57.2125, abs=1e-4)
    assert coach.least("pike", 3.5, flight_time(10.0, 0.2)) == pytest.approx(platform_dive(
        coach.bodies["pike"], objective=None).least.P0, rel=1e-12)
    # tuck: the legs built with the knees at the position's angle, the limits carry the offset
    assert coach.bodies["tuck"].knee_flexion == position("tuck").knee_flexion
    assert coach.limits["tuck"] == human_limits(coach.bodies["tuck"], "tuck")
    md = coach.to_markdown()
    assert md.count("\n") == 1 + 12 and "| straight | 4.5 |" in md


@pytest.mark.parametrize("name,n,T", [("tuck", 2.5, 1.4), ("straight", 1.5, 1.8)])
def test_least_momentum_is_where_plans_start_to_exist(coach, name, n, T):
    """1.01 times the least momentum: the planner finds a motion within the position's limits;
    0.99 times: refused as infeasible, with the exact reachable interval as the proof."""
    robot, kw = coach.problem(name, n, T, factor=1.01)
    res = acroplan.plan(robot, **kw)
    assert res.status == "success", res.message
    s = res.evaluate(np.linspace(0.0, T, 20001))
    assert s.states[0, -1] - s.states[0, 0] == pytest.approx(2 * math.pi * n, abs=1e-9)
    lo, hi = coach.limits[name].bounds("phi")
    assert s.states[1].min() >= lo - 1e-9 and s.states[1].max() <= hi + 1e-9
    assert np.abs(s.inputs[0]).max() <= 12.0 + 1e-9
    robot, kw = coach.problem(name, n, T, factor=0.99)
    res = acroplan.plan(robot, **kw)
    assert res.status == "infeasible", res.message
    assert "outside the reachable" in res.message


def test_least_momentum_table_inputs(male1):
    with pytest.raises(InvalidInputError) as e:
        least_momentum_table(male1, positions=("tuck",), somersaults=[1.5], flight_times=[1.5])  # straight knees
    assert e.value.field == "position"
    t = least_momentum_table(male1, positions=("pike", "straight"), somersaults=[2.5], flight_times=[1.5])
    assert t.P0.shape == (2, 1, 1) and t.table("straight").P0[0, 0] == t.P0[1, 0, 0]
    for kw, field in (({"somersaults": [-1.0]}, "somersaults"), ({"flight_times": [0.0]}, "flight_times"),
                      ({"positions": ("pike", "pike")}, "positions"), ({"positions": ("layout",)}, "position")):
        with pytest.raises(InvalidInputError) as e:
            least_momentum_table(male1, **kw)
        assert e.value.field == field
    with pytest.raises(InvalidInputError) as e:
        t.least("tuck", 2.5, 1.5)
    assert e.value.field == "position"


def test_least_momentum_figure(coach):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = coach.plot()
    axes = [ax for ax in fig.axes if ax.get_lines()]
    assert len(axes) == 3
    assert len(axes[0].get_lines()) == 4 + 2  # a line per somersault count, the two boards' flights
    plt.close(fig)


# ------------------------------------------------------------------------------------------- docs
@pytest.mark.parametrize("module", [body_module, deleva_module, limits_module, examples_module, yeadon_module,
                                    momentum_module])
def test_docstring_examples(module):
    failures, _ = doctest.testmod(module, verbose=False)
    assert failures == 0


def test_sagittal_body_is_public():
    assert SagittalBody.__doc__ and "sagittal" in SagittalBody.__doc__
