import pytest

import acroplan


@pytest.fixture(scope="session")
def pike_robot():
    return acroplan.examples.robot("pike-dive")


@pytest.fixture(scope="session")
def pike_result():
    return acroplan.examples.load("pike-dive").solve()


@pytest.fixture(scope="session")
def physical_robot():
    return acroplan.Acrobot.from_physical(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2,
                                          torso_length=0.35, leg_length=0.45, angular_momentum=10.0)


def pytest_configure(config):
    import matplotlib

    matplotlib.use("Agg")
