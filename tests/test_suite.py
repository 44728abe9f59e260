"""The suite itself: what it relies on to run in minutes holds."""

import pytest

pytestmark = pytest.mark.xdist_group("test_suite")


def test_xdist_groups_reach_the_scheduler(request):
    """Under pytest-xdist's ``--dist loadgroup`` (pyproject.toml), a test marked with an
    ``xdist_group`` carries its group in its node id, which is how the scheduler keeps a group on one
    worker, so that a module's expensive fixtures are built once. pytest 9 with pytest-xdist 3.8 drops
    the group silently (every worker then rebuilds them): this fails instead."""
    if not getattr(request.config.option, "loadgroup", False):
        pytest.skip("not run by pytest-xdist with --dist loadgroup")
    assert request.node.nodeid.endswith("@test_suite"), request.node.nodeid


def test_every_test_process_runs_one_blas_thread():
    """tests/conftest.py holds BLAS at one thread (unless the environment names a number), here and
    in the processes the tests start: with a thread per core in each of pytest-xdist's workers,
    OpenBLAS's spinning threads made the warm suite 23% slower on 2 cores (223 s against 181 s)."""
    import os
    import subprocess
    import sys

    from threadpoolctl import threadpool_info

    want = int(os.environ["OPENBLAS_NUM_THREADS"])  # 1 unless the environment already said
    blas = [i for i in threadpool_info() if i["user_api"] == "blas"]
    assert blas and all(i["num_threads"] == want for i in blas), blas
    child = subprocess.run([sys.executable, "-c", "import numpy, threadpoolctl; print(max(i['num_threads'] for i in "
                            "threadpoolctl.threadpool_info() if i['user_api'] == 'blas'))"],
                           capture_output=True, text=True, check=True, env=dict(os.environ))
    assert child.stdout.strip() == str(want)
