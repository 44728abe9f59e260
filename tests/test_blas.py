"""One BLAS thread while acroplan plans (acroplan.core.blas): the same bits whatever the caller's
BLAS threads, and the caller's count given back."""

import threading

import numpy as np
import scipy.linalg  # noqa: F401 - its BLAS loaded before the counts are set
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

import acroplan
from acroplan.core.blas import one_blas_thread


def _counts():
    return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]


def test_the_hold_sets_one_thread_and_gives_back_the_callers_count_when_the_last_holder_leaves():
    with threadpool_limits(limits=2, user_api="blas"):
        assert set(_counts()) == {2}
        with one_blas_thread():
            assert set(_counts()) == {1}
            with one_blas_thread():  # nested: still one, and the outer one gives the count back
                assert set(_counts()) == {1}
            assert set(_counts()) == {1}
        assert set(_counts()) == {2}
        # holders in two threads: the count comes back when the later one leaves
        inside, leave = threading.Event(), threading.Event()

        def hold():
            with one_blas_thread():
                inside.set()
                leave.wait(10)

        t = threading.Thread(target=hold)
        t.start()
        assert inside.wait(10)
        with one_blas_thread():
            pass
        assert set(_counts()) == {1}  # the other thread still holds
        leave.set()
        t.join(10)
        assert set(_counts()) == {2}
        with pytest.raises(ZeroDivisionError):  # an exception inside gives the count back too
            with one_blas_thread():
                1 / 0
        assert set(_counts()) == {2}


def test_a_plan_gives_the_same_bits_under_one_or_two_blas_threads_of_the_caller():
    """The space robot's zero-momentum turn (378 endpoint evaluations, SQP steps on 40 x 40
    matrices): before the hold, planned under two BLAS threads it took 371 evaluations and ended
    at other coefficients (OpenBLAS splits a product's sums by thread)."""
    prob = acroplan.examples.load("space-robot-turn")
    out = {}
    for n in (1, 2):
        with threadpool_limits(limits=n, user_api="blas"):
            res = acroplan.plan(prob.system, **prob.plan_kwargs(), verify=False)
            assert set(_counts()) == {n}  # given back
        assert res.status == "success"
        out[n] = (np.concatenate([s.basis_coefficients.ravel() for s in res.segments]),
                  sum(s.evaluations for s in res.segments))
    assert out[1][1] == out[2][1]
    assert np.array_equal(out[1][0], out[2][0])  # bit for bit: one machine, one thread both times


@pytest.mark.parametrize("given", [None, "2"])
def test_the_command_line_starts_with_one_blas_thread_unless_the_environment_says(given):
    """acroplan.io.cli.app.run sets OPENBLAS_NUM_THREADS (and MKL's) to 1 before numpy loads its
    BLAS in the command's process (so the effort summaries written beside a plan are held too),
    and keeps a value the environment gives: numpy's BLAS then runs that many threads there (a
    process of its own, since the command line sets process-wide state)."""
    import os
    import subprocess
    import sys

    env = {k: v for k, v in os.environ.items() if k not in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                                                            "OMP_NUM_THREADS")}
    if given is not None:
        env["OPENBLAS_NUM_THREADS"] = given
    code = ("import os, sys; sys.argv = ['acroplan', '--help']\n"
            "from acroplan.io.cli.app import run\n"
            "run()\n"
            "import numpy, threadpoolctl\n"
            "print('threads', os.environ['OPENBLAS_NUM_THREADS'], "
            "max(i['num_threads'] for i in threadpoolctl.threadpool_info() if i['user_api'] == 'blas'))\n")
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=120)
    assert res.returncode == 0, res.stderr
    want = "1" if given is None else given
    assert res.stdout.strip().splitlines()[-1] == f"threads {want} {want}", res.stdout[-300:]


def test_libraries_other_than_openblas_and_ones_that_fail_are_held_or_left_without_stopping_a_plan(monkeypatch):
    """A library reached through its threadpoolctl controller (MKL, BLIS, FlexiBLAS: controllers
    without OpenBLAS's controlling thread) is set to one thread and given its count back; one whose
    calls fail is left as it is, and the hold, and so the plan, goes on."""
    from acroplan.core import blas

    class FakeMKL:  # threadpoolctl's MKLController has no clear_controlling_thread
        user_api, internal_api = "blas", "mkl"

        def __init__(self):
            self.n, self.calls = 4, []

        def get_num_threads(self):
            return self.n

        def set_num_threads(self, n):
            self.calls.append(n)
            self.n = n

    class Broken(FakeMKL):
        def get_num_threads(self):
            raise OSError("symbol not found")

    mkl, broken = FakeMKL(), Broken()
    monkeypatch.setattr(blas, "_libraries", [blas._functions(mkl), blas._functions(broken)])
    with blas.one_blas_thread():
        assert mkl.n == 1
    assert mkl.n == 4 and mkl.calls == [1, 4] and broken.calls == []
