"""New systems by subclassing only, planned through every front door (issue #10).

* A car with one trailer (Euclidean states, no drift, two inputs), defined here and nowhere else;
* the chained form of any length (one class, a structure per length);
* a rigid body's attitude as a unit quaternion: a state space that is not Euclidean, planned through
  the system's own ``diff``/``retract``;
* strategies passed as objects, and executors passed in.
"""

from __future__ import annotations

import concurrent.futures as cf
import dataclasses
import math
import multiprocessing
import threading

import numpy as np
import pytest
import sympy as sp

import acroplan
from acroplan.core import backend
from acroplan.core.strategies import Deform, Interval, IntervalOutcome, Strategy, deform_attempt


# ------------------------------------------------------------------------------------ the systems
@dataclasses.dataclass(frozen=True)
class CarWithTrailer(acroplan.ControlAffineSystem):
    """Kinematic car pulling one trailer hitched at distance ``d`` behind the rear axle.

    x' = v cos(th0), y' = v sin(th0), th0' = w, th1' = (v / d) sin(th0 - th1).
    """

    d: float = 1.0

    #: heyoka's compact mode compiles these fields with their variational equations in about a
    #: second where full mode takes 14 s per basis size (measured cold); what the tests check is the
    #: plan, which the mode does not change
    compact_mode = True

    state_names = ("x", "y", "th0", "th1")
    input_names = ("v", "w")
    param_names = ("d",)

    @classmethod
    def symbolic_fields(cls, x, p):
        _, _, th0, th1 = x
        (d,) = p
        f = sp.zeros(4, 1)
        G = sp.Matrix([[sp.cos(th0), 0], [sp.sin(th0), 0], [0, 1], [sp.sin(th0 - th1) / d, 0]])
        return f, G


def _qmul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw])


def _qconj(q):
    return np.array([q[0], -q[1], -q[2], -q[3]])


def _exp(v):
    a = float(np.linalg.norm(v))
    if a < 1e-12:
        return np.concatenate([[1.0], 0.5 * np.asarray(v)])
    return np.concatenate([[math.cos(a / 2)], math.sin(a / 2) * np.asarray(v) / a])


def _log(q):
    q = q if q[0] >= 0 else -q
    s = float(np.linalg.norm(q[1:]))
    if s < 1e-12:
        return 2.0 * q[1:]
    return 2.0 * math.atan2(s, q[0]) * q[1:] / s


@dataclasses.dataclass(frozen=True)
class Attitude(acroplan.ControlAffineSystem):
    """A rigid body's attitude q (a unit quaternion [w, x, y, z]) steered by its body rates:
    q' = q (0, omega) / 2. Tangent vectors are rotation vectors in the body frame."""

    state_names = ("qw", "qx", "qy", "qz")
    input_names = ("wx", "wy", "wz")
    #: compact mode: 1.2 s to compile instead of 22 s in full mode (measured cold); the planning on
    #: the manifold is what the tests check
    compact_mode = True

    @classmethod
    def symbolic_fields(cls, x, p):
        qw, qx, qy, qz = x
        G = sp.Rational(1, 2) * sp.Matrix([[-qx, -qy, -qz], [qw, -qz, qy], [qz, qw, -qx], [-qy, qx, qw]])
        return sp.zeros(4, 1), G

    @property
    def ndx(self):
        return 3

    def diff(self, x0, x1):
        return _log(_qmul(_qconj(np.asarray(x0, float)), np.asarray(x1, float)))

    def retract(self, x, dx):
        return _qmul(np.asarray(x, float), _exp(dx))

    def tangent_jacobian(self, x, J):
        # delta(rotation vector) = 2 vec(q^-1 delta q) for a unit q
        w, a, b, c = np.asarray(x, float)
        L = np.array([[-a, w, c, -b], [-b, -c, w, a], [-c, b, -a, w]])
        return 2.0 * L @ J


# ------------------------------------------------------------------------------------ the car
CAR_KW = dict(times=[0.0, 2.0], x=[0.0, 1.2], y=[0.0, 0.3], th0=[0.0, 0.25], th1=[0.0, 0.1], conditions="free")


def _reaches(res, target, tol=1e-9):
    end = res.evaluate([res.times[-1]]).states[:, 0]
    return np.max(np.abs(end - np.asarray(target))) < tol


def test_car_with_trailer_is_planned_and_verified():
    car = CarWithTrailer(d=0.8)
    res = acroplan.plan(car, **CAR_KW)
    assert res.success, res.message
    assert res.verified and max(s.verified_error for s in res.segments) < 1e-9
    assert _reaches(res, [1.2, 0.3, 0.25, 0.1])


def test_car_with_trailer_through_plan_many_and_simulate():
    car = CarWithTrailer(d=0.8)
    one = acroplan.plan(car, **CAR_KW)
    many = acroplan.plan_many([dict(system=car, **CAR_KW), dict(system=CarWithTrailer(d=1.3), **CAR_KW)],
                              executor="thread", workers=2)
    assert many[0].to_json() == one.to_json() and many[1].success
    # simulate the planned input: the same motion, independently of the planner
    seg = one.segments[0]
    sim = acroplan.simulate(car, times=[seg.t0, seg.t1], inputs=[seg.basis_coefficients],
                            **dict(zip(car.state_names, seg.start)))
    assert sim.success and np.max(np.abs(sim.waypoints[-1] - seg.target)) < 1e-9


def test_simulate_matches_the_trailer_closed_form():
    """v constant, w = 0: th1 relaxes as tan(th1/2) = tan(th1(0)/2) exp(-v t / d)."""
    car, v, T, th1_0 = CarWithTrailer(d=0.7), 1.5, 2.0, 0.9
    sim = acroplan.simulate(car, times=[0.0, T], inputs=[[[v], [0.0]]], x=0.0, y=0.0, th0=0.0, th1=th1_0)
    x, y, th0, th1 = sim.waypoints[-1]
    assert x == pytest.approx(v * T, abs=1e-13) and y == pytest.approx(0.0, abs=1e-13) and th0 == 0.0
    assert th1 == pytest.approx(2 * math.atan(math.tan(th1_0 / 2) * math.exp(-v * T / 0.7)), abs=1e-12)
    # a function of time gives the same (its projection on the basis is exact for a constant)
    sim2 = acroplan.simulate(car, times=[0.0, T], inputs=lambda t: [v, 0.0], x=0.0, y=0.0, th0=0.0, th1=th1_0)
    assert np.max(np.abs(sim2.waypoints[-1] - sim.waypoints[-1])) < 1e-12


def test_simulate_validates_its_input():
    car = CarWithTrailer()
    with pytest.raises(acroplan.InvalidInputError, match="th1: is missing"):
        acroplan.simulate(car, times=[0, 1], inputs=[[[1.0], [0.0]]], x=0.0, y=0.0, th0=0.0)
    with pytest.raises(acroplan.InvalidInputError, match=r"inputs\[0\]: must have shape \(m, n\) = \(2, n\)"):
        acroplan.simulate(car, times=[0, 1], inputs=[[1.0, 2.0, 3.0]], x=0.0, y=0.0, th0=0.0, th1=0.0)
    with pytest.raises(acroplan.InvalidInputError, match="inputs: has 1 segment"):
        acroplan.simulate(car, times=[0, 1, 2], inputs=[[[1.0], [0.0]]], x=0.0, y=0.0, th0=0.0, th1=0.0)


# ------------------------------------------------------------------------------------ chained form
def test_one_class_many_structures_compiles_once_per_structure():
    before = backend.compiled_count()
    for n in (3, 4):
        sys_ = acroplan.ChainedForm(n=n)
        x1 = [1.0, 0.5] + [0.2] * (n - 2)
        res = acroplan.plan(sys_, times=[0, 1], conditions="free",
                            **{name: [0.0, v] for name, v in zip(sys_.state_names, x1)})
        assert res.success, res.message
    again = acroplan.plan(acroplan.ChainedForm(n=4), times=[0, 1], conditions="free",
                          **{f"x{i}": [0.0, 0.1] for i in range(1, 5)})
    assert again.success
    assert acroplan.ChainedForm(3).structure_key != acroplan.ChainedForm(4).structure_key
    # sizes 6 (and maybe 10, 14) per structure, never per instance or per plan
    assert backend.compiled_count() - before <= 6


# ------------------------------------------------------------------------------------ a quaternion
def test_quaternion_attitude_is_planned_on_the_manifold():
    att = Attitude()
    q1 = _exp(np.array([0.3, -0.8, 1.2]))  # a turn of 1.47 rad
    res = acroplan.plan(att, times=[0, 1.0], conditions="free", qw=[1.0, q1[0]], qx=[0.0, q1[1]],
                        qy=[0.0, q1[2]], qz=[0.0, q1[3]])
    assert res.success, res.message
    seg = res.segments[0]
    assert seg.final_error < 1e-10 and seg.verified_error < 1e-9
    ev = res.evaluate(np.linspace(0, 1, 41))
    assert np.max(np.abs(np.linalg.norm(ev.states, axis=0) - 1.0)) < 1e-13  # the norm is kept
    end = ev.states[:, -1]
    assert np.linalg.norm(att.diff(end, q1)) < 1e-10
    # the Jacobian the planner uses is that of the tangent coordinates (finite differences)
    c = seg.basis_coefficients.ravel()
    y, J = backend.endpoint(att, seg.basis, [1, 0, 0, 0], 1.0, c)
    Jt = att.tangent_jacobian(y, J)
    h = 1e-6
    for k in (0, 4, 9):
        e = np.zeros_like(c)
        e[k] = h
        yp, _ = backend.endpoint(att, seg.basis, [1, 0, 0, 0], 1.0, c + e)
        ym, _ = backend.endpoint(att, seg.basis, [1, 0, 0, 0], 1.0, c - e)
        fd = (att.diff(y, yp) - att.diff(y, ym)) / (2 * h)
        assert np.max(np.abs(fd - Jt[:, k])) < 1e-7


def test_diff_and_retract_are_inverse():
    att = Attitude()
    rng = np.random.default_rng(3)
    for _ in range(20):
        q0 = _exp(rng.normal(size=3))
        dx = rng.normal(size=3) * 0.9
        assert np.allclose(att.diff(q0, att.retract(q0, dx)), dx, atol=1e-12)


# ------------------------------------------------------------------------------------ strategies
class OnlyTen(Strategy):
    """A user's strategy: path deformation with 10 coefficients, nothing else."""

    name = "only-ten"

    def solve(self, interval: Interval) -> IntervalOutcome:
        return deform_attempt(interval, 10)


def test_a_strategy_object_or_class_is_accepted():
    robot = acroplan.examples.robot("pike-dive")
    kw = dict(times=[0, 2], theta=[-0.5 * np.pi, 0.9 * np.pi], phi=[-np.pi, -2 * np.pi])
    for method in (OnlyTen, OnlyTen()):
        res = acroplan.plan(robot, method=method, **kw)
        assert res.success and res.segments[0].basis_coefficients.shape == (1, 10)
    res = acroplan.plan(robot, method=Deform(sizes=(14,)), **kw)
    assert res.success and res.segments[0].basis_coefficients.shape == (1, 14)
    with pytest.raises(acroplan.InvalidInputError, match="method: must be one of"):
        acroplan.plan(robot, method="newton", **kw)


def test_status_carries_its_meaning_and_fix():
    S = acroplan.Status
    assert S.SUCCESS == "success" and S("not_converged") is S.NOT_CONVERGED
    assert "n_coefficients" in S.NOT_CONVERGED.fix and "reachable" in S.INFEASIBLE.fix
    assert all(s.meaning for s in S)


# ------------------------------------------------------------------------------------ executors
def _pike_problems(n=4):
    from acroplan.zoo import random_segment

    rng = np.random.default_rng(21)
    return [dict(system=p.robot, conditions="free", **p.plan_kwargs()) for p in (random_segment(rng) for _ in range(n))]


def test_any_executor_is_accepted_and_spawned_workers_compile_for_themselves():
    probs = _pike_problems()
    ref = acroplan.plan_many(probs, executor="serial")
    with cf.ThreadPoolExecutor(2) as pool:
        threaded = acroplan.plan_many(probs, executor=pool, chunksize=1)
    # spawned processes inherit nothing: each compiles on first use
    with cf.ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        spawned = acroplan.plan_many(probs, executor=pool, chunksize=2)
    for a, b, c in zip(ref, threaded, spawned):
        assert a.to_json() == b.to_json() == c.to_json()


def test_threads_share_no_integrator_state():
    """Threads planning at once give the answers one thread gives (no lock, no shared state)."""
    probs = _pike_problems(6)
    ref = [acroplan.plan(p["system"], verify=False, **{k: v for k, v in p.items() if k != "system"}) for p in probs]
    out = [None] * len(probs)
    barrier = threading.Barrier(3)

    def work(i):
        barrier.wait() if i < 3 else None
        p = probs[i]
        out[i] = acroplan.plan(p["system"], verify=False, **{k: v for k, v in p.items() if k != "system"})

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(probs))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert [r.to_json() for r in out] == [r.to_json() for r in ref]


def _dies(*a, **k):
    import os

    os._exit(3)


def test_a_dead_worker_marks_its_problem_and_keeps_the_others():
    probs = _pike_problems(5)
    r = probs[1]["system"]
    probs[1] = dict(probs[1], system=Dying(M1=r.M1, A1=r.A1, M2=r.M2, A2=r.A2, P0=r.P0))
    ref = acroplan.plan_many([p for i, p in enumerate(probs) if i != 1], executor="serial")
    out = acroplan.plan_many(probs, executor="process", workers=2, chunksize=2)
    assert len(out) == 5 and out[1].status == "not_converged" and "worker" in out[1].message
    assert [r.to_json() for i, r in enumerate(out) if i != 1] == [r.to_json() for r in ref]
    # a caller's executor that breaks is not replaced: its problems are marked, none lost
    with cf.ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as pool:
        out = acroplan.plan_many(probs, executor=pool, chunksize=1)
    assert len(out) == 5 and out[1].status == "not_converged" and "worker" in out[1].message
    assert all(r.status in ("success", "not_converged") for r in out)


def _exits(*a, **k):
    raise SystemExit(2)


def test_sys_exit_inside_a_problem_is_reported_not_raised():
    probs = _pike_problems(3)
    r = probs[2]["system"]
    probs[2] = dict(probs[2], system=Exiting(M1=r.M1, A1=r.A1, M2=r.M2, A2=r.A2, P0=r.P0))
    out = acroplan.plan_many(probs, executor="process", workers=2, chunksize=3)
    assert [x.status for x in out[:2]] == ["success", "success"]
    assert out[2].status == "not_converged" and "SystemExit" in out[2].message


@dataclasses.dataclass(frozen=True)
class Exiting(acroplan.Acrobot):
    """An acrobot whose feasibility test calls sys.exit."""

    def check_segment(self, *a, **k):
        _exits()


@dataclasses.dataclass(frozen=True)
class Dying(acroplan.Acrobot):
    """An acrobot whose feasibility test kills its process (as the out-of-memory killer would)."""

    def check_segment(self, *a, **k):
        _dies()
