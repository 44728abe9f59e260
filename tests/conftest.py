"""The suite's shared fixtures and settings.

One BLAS thread per test process. pytest-xdist already runs one worker per core (``-n auto``,
pyproject.toml); OpenBLAS would add a thread per core in each worker, and its idle threads spin, so
two workers on two cores fight over them: the warm suite took 223 s of pytest with BLAS's default
threads and 181 s with one (2026-12-03, 2 cores). Set before numpy is first imported, and inherited
by the processes the tests start (the command line, the sweeps' workers); a value already in the
environment is kept; where numpy was imported first (``-n 0``: a plugin imports it), threadpoolctl
(of the ``test`` extra) sets the same at run time.
"""

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    if not os.environ.get(_var, "").strip().isdigit():
        os.environ[_var] = "1"
try:
    from threadpoolctl import threadpool_limits

    threadpool_limits(limits=int(os.environ["OPENBLAS_NUM_THREADS"]), user_api="blas")
except ImportError:  # pragma: no cover - threadpoolctl is in the test extra
    pass

import pytest  # noqa: E402

import acroplan  # noqa: E402


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
