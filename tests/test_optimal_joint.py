"""The optimum of a whole plan through interior waypoints (``acroplan.core.chain``): the intervals
optimised together after the sequential pass.

On a double integrator the endpoint is linear in the input's coefficients, so the least
:math:`\\int u^2` through the waypoints with the input continuous is a quadratic program whose
KKT system numpy solves directly: the plan must give its coefficients.
"""

import dataclasses

import numpy as np
import pytest
import sympy as sp

import acroplan
from acroplan.core.system import ControlAffineSystem


@dataclasses.dataclass(frozen=True)
class DoubleIntegrator(ControlAffineSystem):
    """x' = v, v' = u."""

    input_names = ("u",)
    param_names = ()

    @property
    def state_names(self):
        return ("x", "v")

    @property
    def rate_inputs(self):
        return {"u": "v"}

    @property
    def structure_key(self):
        return ("DoubleIntegrator-test",)

    def symbolic_fields(self, x, p):
        return sp.Matrix([x[1], 0]), sp.Matrix([[0], [1]])


TIMES = [0.0, 1.0, 2.5, 3.0]
X = [0.0, 1.0, 0.2, 2.0]
V = [0.0, 1.0, -1.0, 0.0]
N = 10


def qp_optimum(continuous: bool):
    """The least sum of T_k c_k' G c_k with each interval's endpoint (x, v) reached, the input
    continuous at the interior waypoints when ``continuous``: (coefficients (K, N), cost)."""
    from acroplan.core.basis import Legendre

    basis = Legendre(N)
    s, w = np.polynomial.legendre.leggauss(40)
    s, w = 0.5 * (s + 1.0), 0.5 * w
    Bq = basis.matrix(s)                       # (40, N)
    G = basis.gram()
    int_u = w @ Bq                              # integral of b_i over [0, 1]
    int_1ms = (w * (1.0 - s)) @ Bq              # integral of (1 - s) b_i
    K = len(TIMES) - 1
    n_var = K * N
    H = np.zeros((n_var, n_var))
    rows, rhs = [], []
    for k in range(K):
        T = TIMES[k + 1] - TIMES[k]
        sl = slice(k * N, (k + 1) * N)
        H[sl, sl] = 2.0 * T * G
        r = np.zeros(n_var)                     # v(T) = v0 + T int u
        r[sl] = T * int_u
        rows.append(r)
        rhs.append(V[k + 1] - V[k])
        r = np.zeros(n_var)                     # x(T) = x0 + v0 T + T^2 int (1 - s) u
        r[sl] = T * T * int_1ms
        rows.append(r)
        rhs.append(X[k + 1] - X[k] - V[k] * T)
    if continuous:
        b0, b1 = basis.matrix([0.0])[0], basis.matrix([1.0])[0]
        for k in range(K - 1):
            r = np.zeros(n_var)
            r[k * N:(k + 1) * N] = b1
            r[(k + 1) * N:(k + 2) * N] = -b0
            rows.append(r)
            rhs.append(0.0)
    A, b = np.array(rows), np.array(rhs)
    kkt = np.block([[H, A.T], [A, np.zeros((A.shape[0], A.shape[0]))]])
    sol = np.linalg.solve(kkt, np.concatenate([np.zeros(n_var), b]))
    c = sol[:n_var]
    return c.reshape(K, N), 0.5 * float(c @ H @ c)


@pytest.fixture(scope="module")
def planned():
    return acroplan.plan(DoubleIntegrator(), times=TIMES, x=X, v=V, conditions="free", objective="energy",
                         n_coefficients=N, verify="ode")


def test_the_joint_optimum_is_the_quadratic_programs(planned):
    res = planned
    assert res.status == "success", res.message
    c_qp, cost_qp = qp_optimum(continuous=True)
    for k, seg in enumerate(res.segments):
        assert seg.optimality["joint"]["kept"]
        # the KKT system's solution, to the SQP's tolerance on a problem of cost ~10
        np.testing.assert_allclose(seg.basis_coefficients[0], c_qp[k], rtol=0, atol=1e-8)
    assert sum(s.optimality["cost"] for s in res.segments) == pytest.approx(cost_qp, rel=1e-10)
    assert "the intervals optimised together" in res.message


def test_the_joint_optimum_is_below_the_sequential_one_and_continuous(planned):
    res = planned
    joint = res.segments[0].optimality["joint"]
    _, free_cost = qp_optimum(continuous=False)   # each interval alone, the input free to jump
    # the sequential plan is feasible for the joint problem, so it costs at least the joint optimum;
    # dropping continuity can only lower the cost further
    assert joint["sequential_cost"] > joint["cost"] * (1 + 1e-6)
    assert free_cost <= joint["cost"] * (1 + 1e-12)
    for a, b in zip(res.segments[:-1], res.segments[1:]):
        assert abs(a.input([a.t1])[0, 0] - b.input([b.t0])[0, 0]) < 1e-9
    assert max(s.verified_error for s in res.segments) < 1e-9


def test_the_joint_stage_reports_its_evaluations_as_it_goes():
    """The intervals together are a stage of the plan's progress, updated at each endpoint
    evaluation (seconds on a twisting dive), never silent from its start to its end."""
    from acroplan.core.chain import STAGE
    from acroplan.core.progress import Progress

    seen = []
    prog = Progress(enabled=False, callback=lambda name, done, total: seen.append((name, done)))
    res = acroplan.plan(DoubleIntegrator(), times=TIMES, x=X, v=V, conditions="free", objective="energy",
                        n_coefficients=N, verify=False, progress=prog)
    assert res.status == "success", res.message
    counts = [done for name, done in seen if name == STAGE]
    assert len(counts) >= 3 and counts == sorted(counts) and counts[-1] > counts[0]
    assert counts[-1] <= res.segments[0].optimality["joint"]["evaluations"]


def kept_joint(res, *said):
    """The plan succeeded with its intervals' joint optimum kept, below the sequential cost, its
    message saying each of ``said``; returns the joint stage's diagnostics."""
    assert res.status == "success", res.message
    joint = res.segments[0].optimality["joint"]
    assert joint["kept"], joint["message"]
    for phrase in said:
        assert phrase in joint["message"]
    # below the sequential cost, when that is a plan's (its intervals within their limits between
    # the grid's points: optimal.PROVISIONAL_STARTS; else the caller compares with the plan in full)
    if joint["sequential_checked"]:
        assert joint["cost"] < joint["sequential_cost"]
    return joint


def test_a_joint_optimum_broken_between_the_grid_points_is_solved_again_on_a_denser_grid(monkeypatch, planned):
    """The joint stage's retry (``optimal.JOINT_LIMIT_GRIDS``): with a rate limit 5% below the
    unlimited plan's peak and a first grid of 4 points, the joint optimum breaks the limit between
    them, the dense check refuses it, and the stage is solved again on 256 points: kept, within the
    limit everywhere, continuous, below the sequential cost."""
    import acroplan.core.optimal as optimal

    top = 0.95 * max(float(np.abs(s.input(np.linspace(s.t0, s.t1, 2001))).max()) for s in planned.segments)
    monkeypatch.setattr(optimal, "JOINT_LIMIT_GRIDS", (4, 256))
    monkeypatch.setattr(optimal, "JOINT_LIMIT_ENDS", 0)  # the first grid uniform alone: the retry is tested
    res = acroplan.plan(DoubleIntegrator(), times=TIMES, x=X, v=V, conditions="free", objective="energy",
                        n_coefficients=N, verify="ode", u_max=top)
    kept_joint(res, "not kept with the limits on 4 points", "then with the limits on 256 points")
    for s in res.segments:
        assert float(np.abs(s.input(np.linspace(s.t0, s.t1, 4001))).max()) <= top * (1 + 1e-9)
    for a, b in zip(res.segments[:-1], res.segments[1:]):
        assert abs(a.input([a.t1])[0, 0] - b.input([b.t0])[0, 0]) < 1e-9
    assert max(s.verified_error for s in res.segments) < 1e-9


def test_the_joint_optimums_first_grid_has_chebyshev_points_at_the_ends(monkeypatch, planned):
    """``optimal.JOINT_LIMIT_ENDS``: the joint stage's first grid of the rate and joint limits also
    has Chebyshev-Lobatto points, which crowd towards the intervals' ends. With the first grid's
    uniform points cut to 4 (the problem of the retry's test above, which breaks the limit between
    them), the 64 Chebyshev points keep the joint optimum within the limit at the first attempt:
    one joint optimum, kept, within the limit everywhere (4001 points an interval)."""
    import acroplan.core.chain as chain
    import acroplan.core.optimal as optimal

    top = 0.95 * max(float(np.abs(s.input(np.linspace(s.t0, s.t1, 2001))).max()) for s in planned.segments)
    monkeypatch.setattr(optimal, "JOINT_LIMIT_GRIDS", (4, 256))
    assert optimal.JOINT_LIMIT_ENDS == 64
    calls = []
    inner = chain.joint_optimum
    monkeypatch.setattr(chain, "joint_optimum", lambda *a, **k: calls.append(1) or inner(*a, **k))
    res = acroplan.plan(DoubleIntegrator(), times=TIMES, x=X, v=V, conditions="free", objective="energy",
                        n_coefficients=N, verify="ode", u_max=top)
    assert res.status == "success", res.message
    assert len(calls) == 1 and res.segments[0].optimality["joint"]["kept"]
    assert "not kept" not in res.segments[0].optimality["joint"]["message"]
    for s in res.segments:
        assert float(np.abs(s.input(np.linspace(s.t0, s.t1, 4001))).max()) <= top * (1 + 1e-9)
    assert max(s.verified_error for s in res.segments) < 1e-9


def test_linear_limits_on_chebyshev_points_too():
    """core.limits.linear_limits(ends=K): the rows of a rate limit at the union of the uniform
    points and K Chebyshev-Lobatto points (each row the basis at its point); the peak near an end of
    s (1 - s) T_20''(2 s - 1), which the 64 uniform rows see 5.8% low, the union's see 2.3% low
    (the dense check then finds the extremes exactly)."""
    from numpy.polynomial import chebyshev as C

    from acroplan.core.basis import Legendre
    from acroplan.core.limits import Limits, linear_limits

    system, basis = DoubleIntegrator(), Legendre(24)
    cheb = 0.5 * (1.0 - np.cos(np.pi * np.arange(64) / 63))
    s = np.union1d(np.linspace(0.0, 1.0, 64), cheb)
    lim = Limits(u_max=1.0)
    A0, b0 = linear_limits(system, basis, np.zeros(2), 1.0, lim, grid=64)
    A, b = linear_limits(system, basis, np.zeros(2), 1.0, lim, grid=64, ends=64)
    assert A0.shape[0] == 2 * 64 and A.shape[0] == 2 * s.size and np.all(b == 1.0)
    assert np.allclose(A[:s.size], basis.matrix(s), rtol=0, atol=1e-14)
    d = np.zeros(21)
    d[20] = 1.0
    fine = np.linspace(0.0, 1.0, 400001)
    f = lambda t: t * (1 - t) * C.chebval(2 * t - 1, C.chebder(d, 2))  # noqa: E731
    c = np.linalg.lstsq(basis.matrix(fine[::100]), f(fine[::100]), rcond=None)[0]
    c /= float(np.abs(basis.matrix(fine) @ c).max())        # its peak 1, near an end
    assert 1.0 - np.max(A0 @ c) > 0.05 and 1.0 - np.max(A @ c) < 0.025


def test_a_step_below_the_merit_resolution_is_taken_whole_without_a_search(monkeypatch):
    """core.sqp: when the decrease a step predicts is below the merit function's resolution
    (MERIT_RESOLUTION, relative), the full step is tried first on the KKT residual, before any
    backtracking search (which there compares rounding: 20-30 evaluations a step on the falling
    cat's refinement). From the optimum of one interval moved by 1e-7 along the endpoint's null
    space (a decrease of about 1e-14 relative to take), the step is taken whole, no line search
    runs, and the optimum is back to 1e-12."""
    import acroplan.core.sqp as sqp_module
    from acroplan.core.basis import Legendre
    from acroplan.core.optimum import optimize_segment

    system, basis = DoubleIntegrator(), Legendre(N)
    x0, x1, T = np.array([0.0, 0.0]), np.array([1.0, 1.0]), 1.0
    best = optimize_segment(system, basis, x0, x1, T, np.zeros((1, N)), kkt_tol=1e-13)
    assert best.success and best.kkt < 1e-12
    searches = []
    search = sqp_module._line_search
    monkeypatch.setattr(sqp_module, "_line_search", lambda *a, **k: searches.append(1) or search(*a, **k))
    from acroplan.core import backend

    _, J = backend.endpoint(system, basis, x0, T, best.coefficients)
    move = np.linalg.svd(J)[2][-1]          # along the endpoint's null space: no constraint is moved
    start = best.coefficients + 1e-7 * move[None, :] / np.abs(move).max()
    again = optimize_segment(system, basis, x0, x1, T, start, kkt_tol=1e-13)
    assert again.success and again.kkt < 1e-12 and again.iterations >= 1
    assert not searches
    assert np.abs(again.coefficients - best.coefficients).max() < 1e-12


def test_the_second_order_correction_keeps_the_limits_near_their_bound():
    """core.sqp._corrected: the correction back onto the equations from a trial point is the
    shortest step with A d = -h that keeps the inequality rows near their bound. With h = 0.1 on
    the row z0 + z1, and -z1 <= 0 active, the plain minimum-norm step (-0.05, -0.05) breaks the
    row by 0.05; the correction is (-0.1, 0): on the equation, the row kept, and no longer than
    needed. A row far from its bound (slack 1) does not constrain it."""
    from types import SimpleNamespace

    from acroplan.core.sqp import _corrected

    z = np.array([0.3, 0.0])
    h, A = np.array([0.1]), np.array([[1.0, 1.0]])
    R = np.array([[0.0, -1.0], [1.0, 0.0]])     # -z1 <= 0 (active), z0 - 1.3 <= 0 (slack 1)
    r = R @ z - np.array([0.0, 1.3])
    plain = z - A.T @ np.linalg.solve(A @ A.T, h)
    assert (R @ plain - np.array([0.0, 1.3]))[0] == pytest.approx(0.05)
    zc = _corrected(SimpleNamespace(z=z, h=h, A=A, r=r, R=R))
    d = zc - z
    assert A @ d == pytest.approx(-h, abs=1e-15)
    assert R[0] @ d <= -r[0] + 1e-15
    assert d == pytest.approx([-0.1, 0.0], abs=1e-12)
    # with no inequality near its bound the plain step stands
    far = SimpleNamespace(z=z, h=h, A=A, r=r - 1.0, R=R)
    assert _corrected(far) == pytest.approx(plain, abs=1e-15)
    assert _corrected(SimpleNamespace(z=z, h=h, A=A, r=None, R=None)) == pytest.approx(plain, abs=1e-15)


def test_the_retry_on_a_denser_grid_starts_from_the_coarser_grids_optimum(monkeypatch, planned):
    """The joint stage's retry starts from the coarser grid's joint optimum, and still has to beat
    the sequential cost (not the cost of its own start). The first joint SQP started from the
    intervals' own Hessians, so the retry differences afresh at that optimum (a later retry carries
    the one before's: tests/test_dives.py, the double full-out)."""
    import acroplan.core.chain as chain
    import acroplan.core.optimal as optimal

    top = 0.95 * max(float(np.abs(s.input(np.linspace(s.t0, s.t1, 2001))).max()) for s in planned.segments)
    monkeypatch.setattr(optimal, "JOINT_LIMIT_GRIDS", (4, 256))
    monkeypatch.setattr(optimal, "JOINT_LIMIT_ENDS", 0)  # the first grid uniform alone: the retry is tested
    calls = []
    inner = chain.joint_optimum

    def spy(runs, starts, **kw):
        out = inner(runs, starts, **kw)
        calls.append((starts, kw, out))
        return out

    monkeypatch.setattr(chain, "joint_optimum", spy)
    res = acroplan.plan(DoubleIntegrator(), times=TIMES, x=X, v=V, conditions="free", objective="energy",
                        n_coefficients=N, verify=False, u_max=top)
    assert res.status == "success", res.message
    assert len(calls) == 2
    (s1, kw1, out1), (s2, kw2, out2) = calls
    for a, b in zip(s2, out1.coefficients):
        assert np.array_equal(a, b)
    assert kw1["interval_curvature"] is not None and kw1["curvature"] is None
    assert kw2["curvature"] is None and kw2["interval_curvature"] is None and out1.curvature is not None
    assert kw1["reference_cost"] == kw2["reference_cost"] == pytest.approx(out1.start_cost, rel=1e-12)
    assert out2.start_cost == kw1["reference_cost"] and out2.cost > out1.cost
    assert res.segments[0].optimality["joint"]["kept"]


def test_an_interval_whose_optimum_breaks_a_limit_between_the_grid_points_is_solved_on_a_denser_one(monkeypatch):
    """One interval (``optimal._Search.denser``): with a rate limit 5% below the unlimited optimum's
    peak and a grid of 4 points, the optima break the limit between them and the dense check
    refuses them; the first size's and the reported one are then solved again on DENSE_LIMIT_GRID
    points from that optimum: the plan succeeds, within the limit everywhere, on the denser grid
    (``limit_grid`` in its diagnostics), and at a cost no lower than the unlimited optimum's."""
    import acroplan.core.optimal as optimal

    free = acroplan.plan(DoubleIntegrator(), times=[0.0, 1.0], x=[0.0, 1.0], v=[0.0, 0.0], objective="energy",
                         verify=False)
    top = 0.95 * float(np.abs(free.segments[0].input(np.linspace(0.0, 1.0, 2001))).max())
    monkeypatch.setattr(optimal, "LIMIT_GRID", 4)
    calls = []
    denser = optimal._Search.denser
    monkeypatch.setattr(optimal._Search, "denser",
                        lambda self, run, n, kkt: calls.append(run.prob.limit_grid) or denser(self, run, n, kkt))
    res = acroplan.plan(DoubleIntegrator(), times=[0.0, 1.0], x=[0.0, 1.0], v=[0.0, 0.0], objective="energy",
                        verify="ode", u_max=top)
    assert res.status == "success", res.message
    opt = res.segments[0].optimality
    assert opt["limit_grid"] == optimal.DENSE_LIMIT_GRID
    # without the retry the ladder stopped at 6 coefficients, "NOT converged in the basis" (the 10
    # coefficients' optimum broke the limit by 1.8e-2 between the 4 points)
    assert opt["converged_in_basis"] and opt["basis_size"] > 6
    assert calls and set(calls) == {4}
    assert float(np.abs(res.segments[0].input(np.linspace(0.0, 1.0, 4001))).max()) <= top * (1 + 1e-9)
    assert opt["cost"] >= free.segments[0].optimality["cost"]
    assert res.segments[0].verified_error < 1e-9


def test_the_ladder_compares_its_sizes_on_their_grids_and_checks_the_one_it_reports(monkeypatch):
    """``optimal.LADDER_ON_GRID``: the ladder's sizes are warm starts compared with their limits met
    on their grids; only the first size (where starts are compared) and the reported one are
    checked between the points and solved on the denser grid. The same problem as above (a grid of
    4 points, a rate limit 5% below the unlimited peak), planned both ways: the same basis size and
    optimum (to 1e-9), within the limit on 4001 points, with no denser solve at the sizes between;
    the size between is entered at its grid's optimum, which the limit between the points can only
    raise."""
    import acroplan.core.optimal as optimal

    kw = dict(times=[0.0, 1.0], x=[0.0, 1.0], v=[0.0, 0.0], objective="energy")
    free = acroplan.plan(DoubleIntegrator(), verify=False, **kw)
    top = 0.95 * float(np.abs(free.segments[0].input(np.linspace(0.0, 1.0, 2001))).max())
    monkeypatch.setattr(optimal, "LIMIT_GRID", 4)
    denser = optimal._Search.denser
    out = {}
    for on in (True, False):
        calls = []
        monkeypatch.setattr(optimal, "LADDER_ON_GRID", on)
        monkeypatch.setattr(optimal._Search, "denser",
                            lambda self, run, n, kkt, calls=calls: calls.append(n) or denser(self, run, n, kkt))
        res = acroplan.plan(DoubleIntegrator(), verify=False, u_max=top, **kw)
        assert res.status == "success", res.message
        out[on] = (res, calls)
    (on, on_calls), (off, off_calls) = out[True], out[False]
    o, f = on.segments[0].optimality, off.segments[0].optimality
    sizes = [n for n, _ in o["ladder"]]
    assert o["basis_size"] == f["basis_size"] == sizes[-1] and len(sizes) >= 3, (o["ladder"], f["ladder"])
    assert abs(o["cost"] - f["cost"]) <= 1e-9 * f["cost"]
    assert on_calls == [sizes[0], sizes[-1]] and set(off_calls) == set(sizes)
    between = {n: v for n, v in o["ladder"][1:-1]}
    assert all(between[n] <= v for n, v in f["ladder"][1:-1])
    assert float(np.abs(on.segments[0].input(np.linspace(0.0, 1.0, 4001))).max()) <= top * (1 + 1e-9)


def test_the_joint_optimum_takes_the_times_where_it_broke_a_torque_limit(monkeypatch):
    """The joint stage's exchange rounds (``optimal.EXCHANGE_ROUNDS``): with the torque limits on a
    grid of 5 points only, the joint optimum breaks them between the points; the times of the
    largest excesses (``OptimalProblem.torque_excess_times`` on the dense check's 1025 points) join
    the grid and the SQP goes on, until the dense check passes: kept, the torque within its limit
    everywhere (an independent 20001-point evaluation), below the sequential cost."""
    import acroplan.core.optimal as optimal
    import acroplan.core.optimum as optimum
    from test_optimal import OptimalTestFlywheel

    sysm = OptimalTestFlywheel()
    prob = dict(times=[0, 1.0, 2.0], q=[0.2, 1.1, 0.3], z=[0.0, 1.6, 2.0], conditions="free")
    free = acroplan.plan(sysm, objective="energy", **prob)
    top = 0.5 * free.effort()["q"].peak_torque
    monkeypatch.setattr(optimal, "JOINT_LIMIT_GRIDS", (4,))
    monkeypatch.setattr(optimal, "JOINT_LIMIT_ENDS", 0)  # the first grid uniform alone: the exchange is tested
    monkeypatch.setattr(optimal, "JOINT_TORQUE_ENDS", False)
    monkeypatch.setattr(optimum, "TORQUE_LIMIT_GRID", 4)
    monkeypatch.setattr(optimal, "EXCHANGE_ROUNDS", 6)
    res = acroplan.plan(sysm, objective="energy", tau_max=top, **prob)
    joint = kept_joint(res, "not kept with the limits on 4 points", "more time(s) where they were broken")
    t = np.linspace(0.0, 2.0, 20001)
    assert float(np.abs(res.torques(t)[0]).max()) <= top * (1 + 1e-9)
    # its provisional starts broke the limits between their 4 points (their cost is no plan's): below
    # the intervals' own optima, refined and checked
    assert not joint["sequential_checked"]
    monkeypatch.setattr(optimal, "PROVISIONAL_STARTS", False)
    full = kept_joint(acroplan.plan(sysm, objective="energy", tau_max=top, **prob))
    assert full["sequential_checked"] and joint["cost"] < full["sequential_cost"]


def test_torque_excess_times_are_the_worst_point_of_each_stretch_above_the_rows():
    """OptimalProblem.torque_excess_times: on the dense check's points, one time per stretch where
    |tau| is above the rows' bound (the limit less its margin), at the stretch's largest excess, or,
    for the stretch holding the joint's peak, the peak refined between the points (here at the
    analytic maximum); add_torque_times puts them on the grid with a time a quarter of the first
    grid's spacing on either side of each (optimum.EXCHANGE_SPREAD; two more rows each), once."""
    from acroplan.core.basis import Legendre
    from acroplan.core.objectives import TORQUE_MARGIN, torque_check_grid
    from acroplan.core import optimum
    from acroplan.core.optimum import OptimalProblem
    from test_optimal import FlywheelTorque, OptimalTestFlywheel

    sysm, basis, T = OptimalTestFlywheel(), Legendre(6), 1.0
    s = torque_check_grid()
    x = 2.0 * s - 1.0                                      # u = x^2/2 - x^4/4: tau = I u' / T peaks inside,
    c = np.linalg.lstsq(basis.matrix(s), x**2 / 2 - x**4 / 4, rcond=None)[0][None, :]  # at x = -+1/sqrt(3)
    model = FlywheelTorque()
    tau = model(sysm, basis, np.zeros(2), T, c, s)[0]
    tmax = 0.6 * float(np.abs(tau).max())
    prob = OptimalProblem(sysm, basis, np.zeros(2), np.zeros(2), T, lambda z: (0.0, 0 * z, None), None, None, 100,
                          torque_model=model, tau_max=[tmax])
    times = prob.torque_excess_times(prob.z(c.ravel()))
    bound = tmax * (1 - TORQUE_MARGIN)
    over = np.abs(tau) > bound
    stretches = int(over[0]) + int(np.count_nonzero(over[1:] & ~over[:-1]))
    assert times.size == stretches >= 2
    peaks = (1.0 + np.array([-1.0, 1.0]) / np.sqrt(3.0)) / 2.0
    refined = [t for t in times if np.min(np.abs(peaks - t)) < 1e-9]
    assert len(refined) == 1                               # the joint's peak, refined (one of the two)
    for t in times:
        if t in refined:
            continue
        k = int(np.flatnonzero(s == t)[0])                 # a point of the check's grid
        assert abs(tau[k]) > bound
        run = np.arange(k, k + 1)
        while run[0] > 0 and over[run[0] - 1]:
            run = np.r_[run[0] - 1, run]
        while run[-1] < s.size - 1 and over[run[-1] + 1]:
            run = np.r_[run, run[-1] + 1]
        assert abs(tau[k]) == np.abs(tau[run]).max()
    rows, before = prob.ineq(prob.z(c.ravel()))[0].size, prob.grid.copy()
    h = optimum.EXCHANGE_SPREAD / (before.size - 1)
    assert h == 0.25 / (before.size - 1)
    wanted = np.concatenate([times, times - h, times + h])
    added = prob.add_torque_times(times)
    assert added == np.setdiff1d(wanted, before).size == 3 * times.size  # none on the grid already
    assert np.all(np.isin(wanted, prob.grid)) and np.all(np.isin(before, prob.grid))
    assert prob.add_torque_times(times) == 0
    assert prob.ineq(prob.z(c.ravel()))[0].size == rows + 2 * added


class _BumpTorque:
    """tau = I u'/T plus a narrow bump (height ``a``, 2e-4 of the interval wide) at ``s0``."""

    joint_names = ("q",)

    def __init__(self, a, s0):
        self.a, self.s0 = a, s0

    def __call__(self, system, basis, x0, T, c, s):
        s = np.asarray(s, dtype=float)
        c = np.asarray(c, dtype=float).reshape(1, -1)
        return (system.I * (basis.matrix(s, 1) @ c[0]) / T + self.a * np.exp(-((s - self.s0) / 2e-4) ** 2))[None, :]


def test_the_dense_check_refines_a_torque_peak_between_its_points():
    """A torque peak narrower than the check's points near an interval's end (where a motion with
    many coefficients has its narrowest features), on a torque within 1% of its limit: the check
    refines it (OptimalRun.result says the limit is broken, by the bump's analytic excess), and the
    exchange rounds' time is the bump's, though every point of the grid is within the rows' bound."""
    from acroplan.core.basis import Legendre
    from acroplan.core.objectives import TORQUE_MARGIN, torque_check_grid
    from acroplan.core.optimum import OptimalRun
    from test_optimal import OptimalTestFlywheel

    sysm, basis, T = OptimalTestFlywheel(), Legendre(4), 1.0
    s = torque_check_grid()
    gaps = np.diff(s)
    k = int(np.argmax(np.where(s[:-1] > 0.99, gaps, 0.0)))
    s0 = 0.5 * (s[k] + s[k + 1])                          # half-way between two of the check's points
    assert gaps[k] > 5e-4                                 # the bump (2e-4 wide) falls between them
    c = np.linalg.lstsq(basis.matrix(s), 0.99 * T * s / sysm.I, rcond=None)[0][None, :]  # tau = 0.99 + bump
    tmax = 1.0
    model = _BumpTorque(0.02, s0)
    sampled = float(np.abs(model(sysm, basis, np.zeros(2), T, c, s)).max())
    assert sampled < tmax * (1 - TORQUE_MARGIN)          # every point of the grid within the bound
    run = OptimalRun(sysm, basis, np.zeros(2), np.zeros(2), T, "energy", model, None, [tmax], None, None, 1e-10, 100)
    prob = run.prob
    _, _, peak, when = prob.torque_check(c.ravel())
    assert peak[0] == pytest.approx(1.01, rel=1e-12) and when[0] == pytest.approx(s0, abs=1e-9)
    assert np.allclose(prob.torque_excess_times(prob.z(c.ravel())), [s0], atol=1e-9, rtol=0)
    run.z = prob.z(c.ravel())
    res = run.result()
    assert run.broken["torque"] and "max(|tau| - tau_max) = 1.00e-02" in res.message


def test_the_end_cluster_is_half_a_feature_apart_at_each_end():
    """optimum.end_cluster(n): 37 points an end, evenly over [0, 18/n^2] and [1 - 18/n^2, 1] (the
    span at most 1/4), so 1/(2 n^2) apart: half the width of an n-coefficient input's narrowest
    features at the ends; sorted, in [0, 1], symmetric about 1/2."""
    from acroplan.core.optimum import end_cluster

    for n in (6, 10, 14, 20, 30, 48):
        e = end_cluster(n)
        w = min(18.0 / n**2, 0.25)
        assert e.size == 74 and np.all(np.diff(e) > 0) and e[0] == 0.0 and e[-1] == 1.0
        np.testing.assert_allclose(e, 1.0 - e[::-1], rtol=0, atol=1e-15)
        np.testing.assert_allclose(np.diff(e[:37]), w / 36, rtol=1e-12)
        assert e[36] == w and (n < 9 or abs(w / 36 - 1 / (2 * n**2)) < 1e-15), n


def test_a_retry_densifies_the_limits_that_were_broken_between_the_points():
    """optimal._denser_grids: a retry puts on the denser grid only the kind of limit its last
    optimum broke between the points (the rate and joint limits, or the torque limits); both when
    neither was found broken (another check failed); ``None`` when nothing would be denser. The
    forward dive's torque optimum broke a rate limit, its torques 12.6 N m within the strength:
    its retries had evaluated the torques on 257 points an interval for nothing. The torque grid's
    size is its uniform points' (``grid_points``), not counting the points crowded at the ends
    (``optimum.end_cluster``), which every grid of a joint optimum has besides."""
    from types import SimpleNamespace

    from acroplan.core.optimal import _denser_grids

    def run(lin, tq, limits, torque, ends=0):
        return SimpleNamespace(prob=SimpleNamespace(limit_grid=lin, grid=None if tq is None else np.zeros(tq + ends),
                                                    grid_points=tq),
                               broken={"limits": limits, "torque": torque})

    assert _denser_grids([run(64, 65, True, False), run(64, 65, False, False)], 256) == (256, 65)
    assert _denser_grids([run(64, 65, False, True), run(64, 65, False, False)], 256) == (64, 257)
    assert _denser_grids([run(64, 65, False, False)], 256) == (256, 257)
    assert _denser_grids([run(64, None, True, False)], 256) == (256, None)
    assert _denser_grids([run(256, 65, True, False)], 256) is None
    assert _denser_grids([run(256, 257, True, True)], 256) is None
    assert _denser_grids([run(64, 65, True, False, ends=72)], 256) == (256, 65)
    assert _denser_grids([run(256, 65, True, False, ends=72)], 256) is None


def test_the_curvature_along_the_leading_coefficients_is_the_full_ones_there():
    """OptimalProblem.curvature(leading=k) (the joint optimum's, chain.CURVATURE_LEADING): the
    blocks of each input's first k coefficients with each other are the full forward differences'
    (the same evaluations, averaged with their transposes as the full one is), the blocks of those
    with the higher coefficients agree with the full ones to the differences' accuracy (one-sided
    there: the higher directions are not differenced), the block of the higher coefficients with
    each other is zero, and it spends m * k evaluations, not m * n. The acrobot's endpoint is not
    linear in its coefficients, so the Hessians are not zero."""
    from acroplan.core.basis import Legendre
    from acroplan.core.optimum import OptimalProblem
    from acroplan.zoo import random_segment

    p = random_segment(np.random.default_rng(3))
    system, n, k = p.robot, 10, 4
    basis = Legendre(n)
    c = np.random.default_rng(4).normal(scale=0.5, size=system.n_inputs * n)
    x0, x1 = np.array([p.theta0, p.phi0]), np.array([p.thetaT, p.phiT])
    prob = OptimalProblem(system, basis, x0, x1, p.T, "energy", None, None, 10 ** 6)
    Ac = prob.endpoint(c)[1]
    full = prob.curvature(c, Ac)
    spent = prob.evaluations
    part = prob.curvature(c, Ac, leading=k)
    m = system.n_inputs
    assert prob.evaluations - spent == m * k and spent == m * n + 1
    lead = (np.arange(m)[:, None] * n + np.arange(k)[None, :]).ravel()
    rest = np.setdiff1d(np.arange(m * n), lead)
    big, q = np.abs(full).max(), full.shape[0]
    assert big > 1e-3
    ll, lr, rr = (np.ix_(np.arange(q), a, b) for a, b in ((lead, lead), (lead, rest), (rest, rest)))
    np.testing.assert_allclose(part[ll], full[ll], rtol=0, atol=1e-12 * big)
    np.testing.assert_allclose(part[lr], full[lr], rtol=0, atol=1e-6 * big)
    assert not np.any(part[rr]) and np.abs(full[rr]).max() > 1e-6 * big
    np.testing.assert_array_equal(part, part.transpose(0, 2, 1))


def _spy_reports(monkeypatch):
    """Count the intervals' reports by kind: ``{"provisional": n, "refined": n}`` (``optimal._Search``)."""
    import acroplan.core.optimal as optimal

    seen = {"provisional": [], "refined": 0}
    prov, ref = optimal._Search._provisional, optimal._Search._refined

    def provisional(self, current):
        out = prov(self, current)
        seen["provisional"].append(out[1])
        return out

    def refined(self, current):
        seen["refined"] += 1
        return ref(self, current)

    monkeypatch.setattr(optimal._Search, "_provisional", provisional)
    monkeypatch.setattr(optimal._Search, "_refined", refined)
    return seen


def test_the_intervals_optima_are_the_joint_optimums_provisional_start(monkeypatch, planned):
    """``optimal.PROVISIONAL_STARTS``: when the joint optimum follows, each interval reports its
    ladder's point unrefined (no refinement, no dense re-solve), and the joint optimum, kept, is the
    same optimum as from refined starts (the quadratic program's: the coefficients to the SQP's
    tolerance); no reported segment says it was provisional."""
    import acroplan.core.optimal as optimal

    seen = _spy_reports(monkeypatch)
    res = acroplan.plan(DoubleIntegrator(), times=TIMES, x=X, v=V, conditions="free", objective="energy",
                        n_coefficients=N, verify="ode")
    assert res.status == "success", res.message
    assert seen["provisional"] == ["within"] * 3 and seen["refined"] == 0
    c_qp, cost_qp = qp_optimum(continuous=True)
    for k, seg in enumerate(res.segments):
        assert seg.optimality["joint"]["kept"] and "provisional" not in seg.optimality
        np.testing.assert_allclose(seg.basis_coefficients[0], c_qp[k], rtol=0, atol=1e-8)
        np.testing.assert_allclose(seg.basis_coefficients, planned.segments[k].basis_coefficients, rtol=0, atol=1e-8)
    assert sum(s.optimality["cost"] for s in res.segments) == pytest.approx(cost_qp, rel=1e-10)
    monkeypatch.setattr(optimal, "PROVISIONAL_STARTS", False)
    seen = _spy_reports(monkeypatch)
    acroplan.plan(DoubleIntegrator(), times=TIMES, x=X, v=V, conditions="free", objective="energy",
                  n_coefficients=N, verify=False)
    assert seen == {"provisional": [], "refined": 3}


def test_a_joint_optimum_not_kept_brings_the_intervals_planned_in_full(monkeypatch):
    """When the joint optimum from the provisional starts is not kept, the intervals are planned again
    in full (refined, checked) and the joint optimum tried from them: with every joint optimum
    refused, the plan is the intervals' own optima, bit for bit those of the code without
    provisional starts, each refined to its KKT target."""
    import acroplan.core.chain as chain
    import acroplan.core.optimal as optimal

    inner = chain.joint_optimum
    tries = []

    def refused(runs, starts, **kw):
        out = inner(runs, starts, **kw)
        tries.append(kw.get("beat"))
        return dataclasses.replace(out, success=False, message=out.message + "; not kept: refused by the test")

    monkeypatch.setattr(chain, "joint_optimum", refused)
    seen = _spy_reports(monkeypatch)
    kw = dict(times=TIMES, x=X, v=V, conditions="free", objective="energy", n_coefficients=N, verify=False)
    res = acroplan.plan(DoubleIntegrator(), **kw)
    assert res.status == "success", res.message
    assert seen["provisional"] == ["within"] * 3 and seen["refined"] == 3 and tries == [True, True]
    monkeypatch.setattr(optimal, "PROVISIONAL_STARTS", False)
    old = acroplan.plan(DoubleIntegrator(), **kw)
    assert len(tries) == 3
    for a, b in zip(res.segments, old.segments):
        assert not a.optimality["joint"]["kept"] and "refused by the test" in a.optimality["joint"]["message"]
        assert "provisional" not in a.optimality and a.optimality["kkt_converged"]
        assert np.array_equal(a.basis_coefficients, b.basis_coefficients)


def test_a_provisional_start_that_breaks_a_limit_between_its_points_need_not_be_beaten(monkeypatch, planned):
    """Intervals whose limits' grid has 4 points (``optimal.LIMIT_GRID``) break a rate limit 5% below
    the unlimited plan's peak between them; as provisional starts they are not refused for it, and
    their cost (below what the limit allows) is not one the joint optimum must beat
    (``joint_optimum(beat=False)``): the joint optimum, on its own grids, is kept and holds the limit
    everywhere."""
    import acroplan.core.chain as chain
    import acroplan.core.optimal as optimal

    top = 0.95 * max(float(np.abs(s.input(np.linspace(s.t0, s.t1, 2001))).max()) for s in planned.segments)
    monkeypatch.setattr(optimal, "LIMIT_GRID", 4)
    seen = _spy_reports(monkeypatch)
    beats = []
    inner = chain.joint_optimum
    monkeypatch.setattr(chain, "joint_optimum", lambda *a, **k: beats.append(k["beat"]) or inner(*a, **k))
    # the ladder's sizes (no n_coefficients): the first size is checked between its points (the first
    # stage), the later ones on the grid alone (optimal.LADDER_ON_GRID)
    res = acroplan.plan(DoubleIntegrator(), times=TIMES, x=X, v=V, conditions="free", objective="energy",
                        verify="ode", u_max=top)
    assert res.status == "success", res.message
    assert "broken" in seen["provisional"] and seen["refined"] == 0 and beats == [False]
    joint = res.segments[0].optimality["joint"]
    assert joint["kept"] and not joint["sequential_checked"]
    for s in res.segments:
        assert float(np.abs(s.input(np.linspace(s.t0, s.t1, 4001))).max()) <= top * (1 + 1e-9)
    assert max(s.verified_error for s in res.segments) < 1e-9
