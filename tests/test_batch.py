"""plan_many: the same results as one by one, in input order; one failure never stops the others."""

import numpy as np
import pytest

import acroplan
from acroplan.zoo import random_segment


def _problems(n=6, seed=7):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        p = random_segment(rng)
        out.append(dict(system=p.robot, conditions="free", **p.plan_kwargs()))
    bad = dict(out[0])
    bad["theta"] = [bad["theta"][0], bad["theta"][1] + 1e3]  # far outside: infeasible
    out.insert(2, bad)
    return out


@pytest.mark.parametrize("executor", ["serial", "thread", "process"])
def test_batch_equals_one_by_one(executor):
    probs = _problems()
    one = [acroplan.plan(p["system"], **{k: v for k, v in p.items() if k != "system"}) for p in probs]
    many = acroplan.plan_many(probs, executor=executor, workers=2)
    assert [r.status for r in many] == [r.status for r in one]
    assert many[2].status == "infeasible" and all(r.success for i, r in enumerate(many) if i != 2)
    for a, b in zip(one, many):
        assert a.to_json() == b.to_json()  # bit for bit
        assert a == b  # every field, arrays and all (the system too, pickled to a process and back)


def test_results_compare_bit_for_bit():
    """``==`` of results (PlanResult, SegmentResult, Samples) compares every field, arrays entry by
    entry, NaN equal to NaN: the same request planned twice is equal; a waypoint moved by 1e-12
    rad, a message changed or a NaN made 0 is not. (The generated ``==`` raised on the arrays.)"""
    import dataclasses

    p = _problems(1)[0]
    kw = {k: v for k, v in p.items() if k != "system"}
    a, b = acroplan.plan(p["system"], **kw), acroplan.plan(p["system"], **kw)
    assert a == b and not (a != b) and a.segments[0] == b.segments[0] and a.sample(33) == b.sample(33)
    moved = acroplan.plan(p["system"], **{**kw, "phi": [kw["phi"][0], kw["phi"][1] + 1e-12]})
    assert moved.success and moved != a and moved.segments[0] != a.segments[0]
    assert dataclasses.replace(a, message=a.message + ".") != a and a != a.to_dict() and a != None  # noqa: E711
    seg = dataclasses.replace(a.segments[0], sigma_min=float("nan"))
    assert seg == dataclasses.replace(seg) and seg != dataclasses.replace(seg, sigma_min=0.0)


def test_batch_validates_before_planning():
    probs = _problems(2)
    probs.append(dict(system=probs[0]["system"], times=[0, 1], theta=[0, 1]))
    with pytest.raises(acroplan.InvalidInputError, match=r"problems\[3\].phi: is missing"):
        acroplan.plan_many(probs)
    with pytest.raises(acroplan.InvalidInputError, match="executor: must be one of"):
        acroplan.plan_many(probs[:1], executor="gpu")
    with pytest.raises(acroplan.InvalidInputError, match=r"problems\[0\]: must be a dict or a Problem"):
        acroplan.plan_many([42])


def test_batch_accepts_problems_and_reports_progress():
    prob = acroplan.examples.load("pike-dive")
    seen = []
    out = acroplan.plan_many([prob, prob], executor="serial", progress=lambda d, n: seen.append((d, n)))
    assert [r.status for r in out] == ["success", "success"] and seen == [(1, 2), (2, 2)]
