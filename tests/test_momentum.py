"""The least angular momentum for a turn (acroplan.families.acrobot.momentum): exact by the
reachable set, so a plan just above it succeeds and one just below it is refused with the proof."""

import math

import numpy as np
import pytest

import acroplan
from acroplan.families.acrobot import Acrobot
from acroplan.families.acrobot.momentum import least_momentum, somersault_table
from acroplan.core.errors import InvalidInputError

# one worker runs this module, so that its module-scoped fixtures are built once (pytest-xdist's
# loadgroup, pyproject.toml)
pytestmark = pytest.mark.xdist_group("test_momentum")

PIKE = acroplan.Limits(phi_min=-math.pi, phi_max=-0.4, u_max=12.0)


@pytest.fixture(scope="module")
def robot():
    return acroplan.examples.robot("pike-dive")


def _with(robot, P0):
    return Acrobot(robot.M1, robot.A1, robot.M2, robot.A2, P0)


@pytest.mark.parametrize("n", [1.5, 2.5])
def test_least_momentum_is_the_boundary_of_what_plans(robot, n):
    kw = dict(theta0=0.0, thetaT=-2 * math.pi * n, phi0=-math.pi, phiT=-math.pi, T=1.5)
    b = least_momentum(robot, **kw, limits=PIKE)
    assert b.success and b.attained and b.P0 < 0
    common = dict(times=[0.0, 1.5], theta=[0.0, kw["thetaT"]], phi=[-math.pi, -math.pi], limits=PIKE,
                  conditions="free")
    above = acroplan.plan(_with(robot, b.P0 * 1.01), **common)
    assert above.success, above.message
    below = acroplan.plan(_with(robot, b.P0 * 0.99), **common)
    assert below.status == "infeasible"
    # the most momentum: beyond it even the slowest-turning motion turns too far
    m = least_momentum(robot, **kw, limits=PIKE, end="most")
    assert m.success and abs(m.P0) > abs(b.P0)
    assert acroplan.plan(_with(robot, m.P0 * 0.99), **common).success
    assert acroplan.plan(_with(robot, m.P0 * 1.01), **common).status == "infeasible"


def test_somersault_table_is_monotone(robot):
    tab = somersault_table(robot, somersaults=[2.5, 3.5, 4.5], flight_times=[1.4, 1.5, 1.6, 1.7], phi0=-math.pi,
                           phiT=-math.pi, limits=PIKE)
    assert tab.P0.shape == (3, 4) and np.all(np.isfinite(tab.P0))
    assert np.all(np.diff(tab.P0, axis=0) > 0)   # more somersaults need more momentum
    assert np.all(np.diff(tab.P0, axis=1) < 0)   # more time needs less
    # each entry is the bound for its problem
    b = least_momentum(robot, theta0=0.0, thetaT=-7 * math.pi, phi0=-math.pi, phiT=-math.pi, T=1.6, limits=PIKE)
    assert tab.P0[1, 2] == abs(b.P0)
    assert "| 3.5 |" in tab.to_markdown()


def test_without_rate_limits_it_is_an_infimum_and_impossible_limits_say_why(robot):
    b = least_momentum(robot, theta0=0.0, thetaT=-7 * math.pi, phi0=-math.pi, phiT=-math.pi, T=1.5,
                       limits=acroplan.Limits(phi_min=-math.pi, phi_max=-0.4))
    assert b.success and not b.attained and "infimum" in b.message
    none = least_momentum(robot, theta0=0.0, thetaT=-7 * math.pi, phi0=-math.pi, phiT=-0.4, T=0.01,
                          limits=acroplan.Limits(u_max=1.0))
    assert not none.success and math.isnan(none.P0) and "no joint motion" in none.message
    with pytest.raises(InvalidInputError, match="robot"):
        least_momentum(acroplan.Unicycle(), theta0=0, thetaT=1, phi0=0, phiT=0, T=1)
