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
