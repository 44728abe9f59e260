"""Fuzzing the API (hypothesis, bounded): every call ends in a result with a known status, whose JSON
has no NaN or infinity, within its time budget, or in an InvalidInputError that names its field."""

import json
import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import acroplan
from acroplan.core import budget

ROBOT = acroplan.Acrobot(M1=0.8172764227642276, A1=-0.47560975609756095, M2=0.28, A2=-0.23780487804878048,
                         P0=1.25)
LIMIT = 2.0  # seconds: each fuzzed plan's budget

numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True, width=64),
    st.floats(min_value=-10, max_value=10),
    st.sampled_from([0.0, -0.0, 1e-300, 1e300, 1e12, -1e12, math.pi, 1e-9, 1e9]),
    st.integers(min_value=-10**30, max_value=10**30),
)
weird = st.one_of(st.none(), st.text(max_size=5), st.booleans(), st.just([[1.0]]), st.just({"a": 1}))


@st.composite
def plan_calls(draw):
    k = draw(st.integers(min_value=1, max_value=3))
    times = np.cumsum([0.0] + [draw(st.floats(min_value=0.2, max_value=2.0)) for _ in range(k)]).tolist()
    kw = dict(times=times,
              theta=[draw(st.floats(min_value=-5, max_value=5)) for _ in range(k + 1)],
              phi=[draw(st.floats(min_value=-7, max_value=7)) for _ in range(k + 1)],
              conditions=draw(st.sampled_from(["free", "spline"])), time_limit=LIMIT)
    # then break one thing, or nothing
    which = draw(st.sampled_from(["nothing", "times", "theta", "phi", "u_max", "phi_min", "phi_max",
                                  "n_coefficients", "tol", "max_evaluations", "method", "basis", "verify",
                                  "time_limit", "unknown"]))
    if which in ("times", "theta", "phi"):
        vals = list(kw[which])
        vals[draw(st.integers(min_value=0, max_value=len(vals) - 1))] = draw(st.one_of(numbers, weird))
        kw[which] = vals
    elif which in ("u_max", "phi_min", "phi_max", "tol", "time_limit"):
        kw[which] = draw(st.one_of(numbers, weird))
        if which == "time_limit" and isinstance(kw[which], (int, float)) and not isinstance(kw[which], bool) \
                and 0 < kw[which] < math.inf:
            kw[which] = min(kw[which], LIMIT)
    elif which in ("n_coefficients", "max_evaluations"):
        kw[which] = draw(st.one_of(st.integers(min_value=-5, max_value=2**63), weird, numbers))
    elif which in ("method", "basis"):
        kw[which] = draw(st.one_of(st.sampled_from(["auto", "deform", "flat", "legendre", "monomial", "x"]), weird))
    elif which == "verify":
        kw[which] = draw(st.one_of(st.booleans(), weird))
    elif which == "unknown":
        kw["u_mx"] = 1.0
    return kw


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(plan_calls())
def test_plan_never_crashes_never_writes_nan_never_overruns(kw):
    # Overruns are counted, not timed (wall-clock times belong to benchmarks/fuzz.py): on a virtual
    # clock moving 1 ms per reading, the first budget check past the deadline must end the plan, so
    # no check is ever made after one that was past it.
    late, real_clock, real_check = [], budget._clock, budget.check
    clock = [0.0]

    def tick():
        clock[0] += 1e-3
        return clock[0]

    def check():
        d = budget._DEADLINE.get()
        if d is not None and clock[0] + 1e-3 > d[0]:
            late.append(clock[0])
        real_check()

    budget._clock, budget.check = tick, check
    try:
        res = acroplan.plan(ROBOT, **kw)
    except acroplan.InvalidInputError as e:
        assert e.field and str(e).startswith(e.field + ":")
        return
    finally:
        budget._clock, budget.check = real_clock, real_check
    assert res.status in ("success", "infeasible", "not_converged")
    json.loads(res.to_json())  # allow_nan=False inside: raises on NaN or infinity
    assert len(late) <= 1, late
    if late:
        assert res.status == "not_converged" and "time budget" in res.message
