"""plan()'s limit keywords change a body's own limits name by name; ``limits=`` replaces them whole.

Before, a keyword such as ``u_max=`` replaced the body's own limits (its link table's or URDF's joint
ranges) with the keyword's alone: a rate limit given to the astronaut dropped its shoulders'
abduction range, and a plan 1.43 rad outside it reported success.
"""

import math

import pytest

from acroplan.core.errors import InvalidInputError
from acroplan.core.limits import Limits
from acroplan.families.planar import Link, PlanarBody
from acroplan.planning.request import PlanRequest


def _body():
    """Three rods whose joints have ranges (q1 in [0, 2], q2 in [-1, 1.5]) and q1 a rate limit 3."""
    rod = dict(mass=1.0, inertia=1.0 / 12.0, com=(0.5, 0.0))
    return PlanarBody([
        Link("rod1", None, **rod),
        Link("rod2", "rod1", **rod, joint=(1.0, 0.0), joint_name="q1", lower=0.0, upper=2.0, velocity=3.0),
        Link("rod3", "rod2", **rod, joint=(1.0, 0.0), joint_name="q2", lower=-1.0, upper=1.5),
    ], P0=0.0)


def _limits(**kw):
    body = _body()
    states = dict(theta=[0.0, 0.1], q1=[1.0, 1.0], q2=[0.0, 0.0])
    states.update({k: kw.pop(k) for k in list(kw) if k in states})
    return PlanRequest.build(body, times=[0.0, 1.0], verify=False, **states, **kw).limits


def test_without_keywords_the_bodys_own_limits_hold():
    own = _body().default_limits()
    assert own == Limits({"q1": (0.0, 2.0), "q2": (-1.0, 1.5)}, {"u_q1": 3.0})
    assert _limits() == own


def test_a_rate_limit_alone_keeps_the_joint_ranges():
    lim = _limits(u_max=10.0)
    assert lim.bounds("q1") == (0.0, 2.0) and lim.bounds("q2") == (-1.0, 1.5)
    # u_max takes the place of the body's rate limits on every input: it may loosen them
    assert lim.input_bound("u_q1") == 10.0 and lim.input_bound("u_q2") == 10.0
    lim = _limits(input_bounds={"u_q2": 4.0})
    assert lim.bounds("q1") == (0.0, 2.0) and lim.input_bound("u_q1") == 3.0 and lim.input_bound("u_q2") == 4.0


def test_one_end_replaces_that_end_and_none_drops_it():
    lim = _limits(q1_max=1.2)
    assert lim.bounds("q1") == (0.0, 1.2) and lim.bounds("q2") == (-1.0, 1.5)
    assert lim.input_bound("u_q1") == 3.0
    lim = _limits(q2_min=None)
    assert lim.bounds("q2") == (-math.inf, 1.5)
    lim = _limits(state_bounds={"q1": (None, 1.8)})  # a pair replaces the joint's whole range
    assert lim.bounds("q1") == (-math.inf, 1.8)


def test_degrees_convert_the_keywords_and_keep_the_bodys_radians():
    lim = _limits(q1_max=90.0, degrees=True, q1=[57.29577951308232] * 2, q2=[0.0, 0.0], theta=[0.0, 5.0])
    assert lim.bounds("q1") == (0.0, pytest.approx(math.pi / 2, abs=1e-15))
    assert lim.bounds("q2") == (-1.0, 1.5)


def test_limits_replaces_the_bodys_own_whole():
    assert _limits(limits=Limits()) == Limits()
    assert _limits(limits=Limits(u_max=5.0)) == Limits(u_max=5.0)


def test_an_end_crossing_the_bodys_other_end_is_refused_naming_it():
    with pytest.raises(InvalidInputError) as e:
        _limits(q1_min=2.5, q1=[2.6, 2.6])
    assert e.value.field == "q1_min" and "system's own other end" in str(e.value)


def test_a_waypoint_outside_the_kept_range_is_refused():
    with pytest.raises(InvalidInputError) as e:
        PlanRequest.build(_body(), times=[0.0, 1.0], theta=[0.0, 0.1], q1=[1.0, 1.0], q2=[0.0, 1.7], u_max=10.0)
    assert e.value.field == "q2" and "outside the joint limits" in str(e.value)


def test_the_astronauts_yaw_keeps_its_abduction_range_under_its_rate_limit():
    from acroplan.families.spatial.examples import SHOULDER_RATE, astronaut_yaw

    body, kw = astronaut_yaw()
    lim = PlanRequest.build(body, **kw).limits
    assert lim.bounds("left_abd") == body.default_limits().bounds("left_abd") == (-math.radians(20), math.pi)
    assert all(lim.input_bound(u) == SHOULDER_RATE for u in body.input_names)
