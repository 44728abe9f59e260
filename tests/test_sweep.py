"""Sweeps (acroplan.sweeps, acroplan.io.sweeps): definitions, points, the derived least momentum, the
store (local processes and a real dask.distributed LocalCluster, bit for bit), kill -9 and resume,
corrupt and foreign stores refused, maps."""

import importlib.util
import json
import math
import os
import pathlib
import pickle
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest
from click.testing import CliRunner

import acroplan
from acroplan.core import backend
from acroplan.core.errors import InvalidInputError
from acroplan.families.acrobot.sweeping import least_momentum
from acroplan.io import sweeps as st
from acroplan.io.sweeps.writer import open_or_create
from acroplan.planning import PlanRequest
from acroplan.sweeps import message_code, sweep

import texts  # the shared problem texts (tests/texts.py)

ROOT = pathlib.Path(__file__).parents[1]
BODY = dict(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2, torso_length=0.35, leg_length=0.45,
            angular_momentum=10.0)
REPRODUCIBLE = ("status", "message", "effort", "peak_rate", "peak_torque", "final_error", "verified_error",
                "evaluations", "segments", "least_P0", "most_P0")

SWEEP_TOML = texts.problem(theta="2.0", phi='"-pi"', conditions="free") + """

[sweep]
derived = ["least_P0", "most_P0"]
chunk_size = {chunk}

[sweep.options]
verify = {verify}

[sweep.grid]
P0 = {{start = 2, stop = 20, num = {n_p0}}}
T = [0.5, 0.75, 1.0, 1.5, 2.0]
"""


def _robot(**kw):
    return acroplan.Acrobot.from_physical(**{**BODY, **kw})


def _base(**kw):
    return dict(system=_robot(), times=[0, 1], theta=[0, 2.0], phi=[-math.pi, -math.pi], conditions="free", **kw)


def _small(chunk=7, **kw):
    """80 points (P0 x T), a third of them infeasible (too little momentum for the turn); the sweep
    of SWEEP_TOML (P0 as the range, recorded as such)."""
    return sweep(_base(**kw), grid={"P0": {"start": 2, "stop": 20, "num": 16}, "T": [0.5, 0.75, 1.0, 1.5, 2.0]},
                 derived=["least_P0", "most_P0"], chunk_size=chunk)


def _load(path):
    return st.open_sweep(path).load()


def _assert_same(a, b):
    for name in REPRODUCIBLE:
        if name in a:
            assert a[name].dtype == b[name].dtype, name
            assert np.array_equal(a[name].values, b[name].values, equal_nan=True), name


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The small sweep computed in this process, one chunk after another."""
    path = tmp_path_factory.mktemp("ref") / "ref.zarr"
    summary = st.run_sweep(_small(), path, executor="serial")
    assert summary.complete
    return path


def test_derived_momentum_units_follow_the_body(reference):
    """A physical body's momenta are recorded in kg m^2/s (the colour bar of ``acroplan map`` said
    "units of P0" for an SI body, #24); a body given by its lumped parameters keeps their units."""
    ds = st.open_sweep(reference).load()
    assert ds.least_P0.attrs["units"] == ds.most_P0.attrs["units"] == "kg m^2/s"
    lumped = acroplan.Acrobot(M1=2.0, A1=-0.5, M2=0.5, A2=-0.25, P0=1.0)
    sw = sweep(dict(system=lumped, times=[0, 1], theta=[0, 2.0], phi=[-math.pi, -math.pi], conditions="free"),
               grid={"T": [1.0, 2.0]}, derived=["least_P0"], chunk_size=2)
    units = {name: attrs.get("units") for name, _, _, attrs in sw.variables()}
    assert units["least_P0"] == "units of P0"


# ---------------------------------------------------------------------------------------------- definitions
def test_a_definition_is_canonical_immutable_and_named_by_its_fields():
    a, b = _small(), _small()
    assert a == b and a.hash == b.hash and a.json == b.json
    assert a.fields == ("robot.angular_momentum", "plan.T")  # P0 of a physical body is its angular momentum
    assert a.shape == (16, 5) and a.size == 80 and a.chunks == (1, 5) and a.n_chunks == 16
    with pytest.raises(Exception):
        a.definition = {}
    c = sweep(_base(), grid={"T": [0.5, 0.75, 1.0, 1.5, 2.0], "P0": np.linspace(2, 20, 16)},
              derived=["least_P0", "most_P0"], chunk_size=7)
    assert c.hash != a.hash and c.fields == ("plan.T", "robot.angular_momentum")  # the axes' order matters
    assert pickle.loads(pickle.dumps(a)) == a
    # a point is plan()'s keywords
    kw = a.problem(7)
    assert kw["system"].P0 == pytest.approx(np.linspace(2, 20, 16)[1]) and kw["times"] == [0, 1.0]
    # chunks of consecutive points
    assert [list(a.chunk_points(i)) for i in (0, 15)] == [[0, 1, 2, 3, 4], [75, 76, 77, 78, 79]]
    big = sweep(_base(), grid={"P0": [1.0, 2.0, 3.0], "T": np.linspace(0.5, 2, 40)}, chunk_size=16)
    assert big.chunks == (1, 16) and big.n_chunks == 9 and list(big.chunk_points(2)) == list(range(32, 40))


def test_fields_resolve_and_mistakes_are_named():
    sw = sweep(_base(), grid={"theta[-1]": [1.0, 2.0], "scale": [0.9, 1.1], "u_max": [20.0, 30.0],
                              "options.method": ["auto", "deform"]}, chunk_size=4)
    assert sw.fields == ("plan.theta[-1]", "robot.scale", "limits.u_max", "options.method")
    kw = sw.problem(15)
    assert kw["theta"][-1] == 2.0 and kw["u_max"] == 30.0 and kw["method"] == "deform"
    assert kw["system"].physical.torso_mass == pytest.approx(40 * 1.1 ** 3)
    assert kw["system"].physical.torso_inertia == pytest.approx(1.8 * 1.1 ** 5)
    assert kw["system"].physical.leg_length == pytest.approx(0.45 * 1.1)
    cases = [
        (dict(grid={"P1": [1.0]}), r"^P1: is not a field.*did you mean 'P0'"),
        (dict(grid={"robot.torso_mas": [1.0]}), r"robot.torso_mas: is not a field.*robot.torso_mass"),
        (dict(grid={"T": [1.0], "times[-1]": [2.0]}), r"grid.times\[-1\]: sets plan.times\[1\]"),
        (dict(grid={"theta[5]": [1.0]}), r"plan.theta\[5\]|theta\[5\]"),
        (dict(grid={"T": [1.0, "x"]}), r"grid.T\[1\]: must be a number"),
        (dict(grid={"T": [1.0, 1.0]}), r"grid.T: repeats a value"),
        (dict(grid={"T": [1.0]}, sample={"n": 3, "T": [1, 2]}), r"not both"),
        (dict(), r"give either grid= or sample="),
        (dict(grid={"T": [1.0]}, derived=["least_PO"]), r"derived: unknown derived quantity.*'least_P0'"),
        (dict(sample={"n": 0, "T": [1, 2]}), r"sample.n: must be a whole number"),
        (dict(sample={"n": 5, "T": [2, 1]}), r"sample.T: needs low < high"),
        (dict(grid={"T": [1.0]}, plan=False), r"plan: is False and no derived quantity"),
    ]
    for kwargs, pattern in cases:
        with pytest.raises(InvalidInputError, match=pattern):
            sweep(_base(), **kwargs)
    with pytest.raises(InvalidInputError, match=r"base.theta: has 3 value"):
        sweep(dict(_base(), theta=[0, 1, 2]), grid={"T": [1.0]})


def test_a_sample_is_drawn_per_point_whatever_the_chunking():
    spec = {"n": 50, "seed": 3, "P0": [1, 30], "T": {"log": [0.5, 3]}, "method": {"choices": ["auto", "deform"]}}
    a, b = sweep(_base(), sample=spec, chunk_size=7), sweep(_base(), sample=spec, chunk_size=50)
    whole = b.values(np.arange(50))
    parts = [a.values(a.chunk_points(c)) for c in range(a.n_chunks)]
    for f in a.fields:
        assert np.array_equal(np.concatenate([p[f] for p in parts]), whole[f])
    assert np.all((whole["robot.angular_momentum"] >= 1) & (whole["robot.angular_momentum"] < 30))
    assert np.all((whole["plan.T"] >= 0.5) & (whole["plan.T"] < 3)) and set(whole["options.method"]) == {"auto",
                                                                                                        "deform"}
    other = sweep(_base(), sample={**spec, "seed": 4}, chunk_size=7).values(np.arange(50))
    assert not np.array_equal(other["plan.T"], whole["plan.T"])


def test_a_toml_file_gives_the_python_definition(tmp_path):
    text = SWEEP_TOML.format(chunk=7, verify="true", n_p0=16) + 'robot.scale = ["0.5*2", 1.1]\n'
    path = tmp_path / "s.toml"
    path.write_text(text)
    from_file = st.load_sweep(path)
    prob = acroplan.io.problem.parse_problem({"robot": BODY, "plan": {"times": [0, 1], "theta": [0, 2.0],
                                                                      "phi": ["-pi", "-pi"], "conditions": "free"}})
    from_python = sweep(prob, grid={"P0": {"start": 2, "stop": 20, "num": 16}, "T": [0.5, 0.75, 1.0, 1.5, 2.0],
                                    "robot.scale": [1.0, 1.1]}, derived=["least_P0", "most_P0"], chunk_size=7,
                       verify=True)
    assert from_file == from_python
    path.write_text(text.replace("chunk_size = 7", "chunk_size = 7\nspeed = 2"))
    with pytest.raises(InvalidInputError, match=r"sweep.speed: is not a known key"):
        st.load_sweep(path)
    path.write_text(text.replace("T = [", "Tee = ["))
    with pytest.raises(InvalidInputError, match=r"Tee: is not a field"):
        st.load_sweep(path)


# ---------------------------------------------------------------------------------------------- least P0
def _request(robot, T=1.0, theta=(0.0, 7 * math.pi), phi=(-math.pi, -math.pi), **limits):
    return PlanRequest.build(robot, times=[0, T], theta=list(theta), phi=list(phi), conditions="free", **limits)


@pytest.mark.parametrize("limits,theta", [
    ({}, (0.0, 7 * math.pi)),                                            # closed form: 7 pi (M1 - |A1|) / T
    ({"u_max": 8.0}, (0.0, 7 * math.pi)),                                # bang-dwell-bang extremes
    ({"phi_min": -2 * math.pi + 0.6, "phi_max": -math.pi, "u_max": 12.0}, (0.0, 7 * math.pi)),  # pike
    ({"u_max": 8.0}, (0.3, -5.0)),                                       # backwards: P0 < 0
])
def test_least_momentum_is_exact_against_a_brute_force_scan(limits, theta):
    robot = _robot()
    req = _request(robot, T=1.3, theta=theta, **limits)
    p_least, why = least_momentum(req, "least")
    p_most, _ = least_momentum(req, "most")
    assert why is None and abs(p_most) > abs(p_least) > 0 and np.sign(p_least) == np.sign(theta[1] - theta[0])
    kw = dict(theta0=theta[0], phi0=-math.pi, phiT=-math.pi, T=1.3, u_max=limits.get("u_max"),
              phi_min=limits.get("phi_min"), phi_max=limits.get("phi_max"))

    def reachable(P0):
        lo, hi = acroplan.reachable_set(acroplan.Acrobot(robot.M1, robot.A1, robot.M2, robot.A2, P0), **kw).interval
        return lo <= theta[1] <= hi

    scan = np.linspace(0, 2 * p_most, 4001)
    ok = np.array([reachable(p) for p in scan])
    step = scan[1] - scan[0]
    first, last = np.argmax(ok), len(ok) - 1 - np.argmax(ok[::-1])
    assert ok[first] and ok[last] and ok[first:last + 1].all()  # one interval of momenta
    assert abs(scan[first] - p_least) <= abs(step) and abs(scan[last] - p_most) <= abs(step)
    # to the last bits: just beyond it the target is reachable, just short of it not
    assert reachable(p_least * (1 + 1e-12)) and not reachable(p_least * (1 - 1e-12))
    assert reachable(p_most * (1 - 1e-12)) and not reachable(p_most * (1 + 1e-12))
    if not limits:
        assert p_least == pytest.approx(7 * math.pi * (robot.M1 - abs(robot.A1)) / 1.3, rel=1e-14)


def test_least_momentum_says_why_when_there_is_none():
    req = _request(_robot(), T=0.1, phi=(-math.pi, 0.0), u_max=1.0)
    # phi must move pi in 0.1 s at 1 rad/s: plan() refuses nothing here, the derived quantity says why
    value, why = least_momentum(req)
    assert math.isnan(value) and "no joint motion" in why
    unicycle = PlanRequest.build(acroplan.Unicycle(), times=[0, 1], x=[0, 1], y=[0, 0], psi=[0, 0],
                                 conditions="free")
    assert math.isnan(least_momentum(unicycle)[0])


def test_the_recorded_peak_torque_is_the_torque_model_of_the_plan():
    """peak_torque is the system's torque model (the same as PlanResult.torques) on 65 points per
    segment, and NaN for a system without one."""
    from acroplan.sweeps.metrics import TORQUE_SAMPLES
    from acroplan.sweeps.metrics import point_metrics as _metrics

    robot = _robot()
    res = acroplan.plan(robot, times=[0, 1.2], theta=[0, 2.5], phi=[-math.pi, -2.0], conditions="free")
    assert res.success
    _, _, peak = _metrics(res)
    s = np.linspace(0.0, 1.0, TORQUE_SAMPLES)
    best = 0.0
    for seg in res.segments:
        tau, _ = res.torques(seg.t0 + s * (seg.t1 - seg.t0))
        best = max(best, float(np.max(np.abs(tau))))
    assert peak == pytest.approx(best, rel=1e-12) and peak > 0
    dense, _ = res.torques(np.linspace(0, 1.2, 20001))
    assert best <= np.max(np.abs(dense)) <= best * 1.01
    lumped = acroplan.Acrobot(robot.M1, robot.A1, robot.M2, robot.A2, robot.P0)
    assert math.isnan(_metrics(acroplan.plan(lumped, times=[0, 1.2], theta=[0, 2.5], phi=[-math.pi, -2.0],
                                             conditions="free"))[2])


# ---------------------------------------------------------------------------------------------- points
def test_a_chunk_records_what_plan_gives_point_by_point():
    sw = _small()
    out = sw.compute(3)
    for j, i in enumerate(out["points"]):
        kw = sw.problem(int(i))
        res = acroplan.plan(**kw)
        d = {k: v[j] for k, v in out["data"].items()}
        assert d["status"] == {"success": 0, "infeasible": 1, "not_converged": 2}[res.status]
        assert d["message"] == message_code(res.message)[0] and out["messages"][d["message"]]
        assert d["evaluations"] == res.evaluations and d["segments"] == len(res.segments)
        if res.success:
            assert d["final_error"] == max(s.final_error for s in res.segments)
            assert d["verified_error"] == max(s.verified_error for s in res.segments)
            assert d["peak_rate"] == pytest.approx(res.max_abs_u, rel=1e-13)
            s = res.sample(4001)
            effort = np.trapezoid(s.u ** 2, s.t)
            assert d["effort"] == pytest.approx(effort, rel=1e-6)
        else:
            assert np.isnan(d["effort"])
    assert message_code("theta(T) = 1.5 is outside (0.2, 3e-4)")[0] == message_code("theta(T) = 2 is outside (1, 2)")[0]


def test_invalid_points_are_recorded_not_raised():
    sw = sweep(_base(), grid={"T": [-1.0, 1.0]}, chunk_size=2)
    out = sw.compute(0)
    assert list(out["data"]["status"]) == [3, 0]
    assert "plan.T: must be > #" in out["messages"][out["data"]["message"][0]]


# ---------------------------------------------------------------------------------------------- the store
def test_local_processes_write_a_complete_store_equal_to_one_process(tmp_path, reference):
    seen = []
    summary = st.run_sweep(_small(), tmp_path / "p.zarr", workers=2, progress=lambda d, n: seen.append((d, n)))
    assert summary.complete and summary.computed == 80 and summary.done_before == 0
    assert summary.counts["success"] + summary.counts["infeasible"] == 80 and summary.counts["infeasible"] > 10
    assert seen[-1] == (80, 80) and all(a[0] <= b[0] for a, b in zip(seen, seen[1:]))
    assert any("80 points in 16 chunks" in line for line in summary.lines())
    ds, ref = _load(tmp_path / "p.zarr"), _load(reference)
    _assert_same(ds, ref)
    assert ds.attrs["acroplan_version"] == acroplan.__version__ and ds.attrs["complete"]
    assert json.loads(ds.attrs["acroplan_sweep"]) == _small().definition
    assert ds.attrs["acroplan_sweep_hash"] == _small().hash
    assert list(ds["P0"].values) == list(np.linspace(2, 20, 16)) and ds["T"].attrs["field"] == "plan.T"
    assert set(np.unique(ds.status.values)) == {0, 1} and np.isfinite(ds.least_P0.values).all()
    # the planner succeeds exactly where the momentum lies between the derived least and most
    # momenta, and the target is proven unreachable elsewhere: the two agree
    P0 = ds["P0"].values[:, None] * np.ones(ds.status.shape)
    inside = (P0 > ds.least_P0.values) & (P0 < ds.most_P0.values)
    assert np.array_equal(inside, ds.status.values == 0)
    # running it again computes nothing
    again = st.run_sweep(_small(), tmp_path / "p.zarr", executor="serial")
    assert again.computed == 0 and again.done_before == 80 and again.complete


def test_a_sample_store_has_its_points_as_coordinates(tmp_path):
    sw = sweep(_base(), sample={"n": 23, "seed": 1, "P0": [2, 20], "T": [0.5, 2]}, chunk_size=5)
    st.run_sweep(sw, tmp_path / "s.zarr", executor="thread", workers=2)
    ds = _load(tmp_path / "s.zarr")
    assert ds.status.dims == ("point",) and ds.sizes["point"] == 23
    assert np.array_equal(ds["T"].values, sw.values(np.arange(23))["plan.T"])
    assert (ds.status.values >= 0).all()


@pytest.fixture(scope="module")
def dask_client():
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                                       silence_logs=40)
    client = distributed.Client(cluster)
    yield client
    client.close()
    cluster.close()


def test_a_dask_cluster_gives_the_local_result_bit_for_bit(tmp_path, reference, dask_client):
    summary = st.run_sweep(_small(), tmp_path / "d.zarr", executor=dask_client)
    assert summary.complete and summary.computed == 80
    _assert_same(_load(tmp_path / "d.zarr"), _load(reference))
    # the scheduler's address works too (the command line's --scheduler)
    res = CliRunner().invoke(st.sweep_cmd, [str(_toml(tmp_path)), "--out", str(tmp_path / "a.zarr"), "--scheduler",
                                            dask_client.scheduler.address, "--json"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.output)["complete"]
    _assert_same(_load(tmp_path / "a.zarr"), _load(reference))


def test_dask_workers_compile_once_not_per_chunk(tmp_path, dask_client):
    sw = sweep(_base(), grid={"P0": np.linspace(8, 20, 12), "T": np.linspace(0.6, 2.0, 5)}, chunk_size=1)
    summary = st.run_sweep(sw, tmp_path / "c.zarr", executor=dask_client)
    assert summary.complete and sw.n_chunks == 60
    counts = dask_client.run(backend.compiled_count)
    assert len(summary.workers) == 2
    for pid, w in summary.workers.items():
        assert w["chunks"] >= 10 and 1 <= w["compiled"] <= 6  # per structure and basis size, not per chunk
    assert max(counts.values()) <= 6


def _toml(tmp_path, chunk=7, verify="true", n_p0=16):
    path = tmp_path / "sweep.toml"
    path.write_text(SWEEP_TOML.format(chunk=chunk, verify=verify, n_p0=n_p0))
    return path


_DRIVER = "import sys; from acroplan.io.sweeps import sweep_cmd; sweep_cmd.main(args=sys.argv[1:])"


def _record(store):
    try:
        return json.loads((store / st.RECORD).read_text())
    except (OSError, ValueError):
        return None


def _kill_tree(proc):
    import psutil

    try:
        kids = psutil.Process(proc.pid).children(recursive=True)
    except psutil.NoSuchProcess:
        kids = []
    return kids


def test_kill_9_of_the_driver_then_resume_computes_each_point_once(tmp_path, reference):
    toml = _toml(tmp_path, chunk=5, verify='"ode"')  # the re-simulation makes a point slow enough to kill mid-way
    out = tmp_path / "k.zarr"
    proc = subprocess.Popen([sys.executable, "-c", _DRIVER, str(toml), "--out", str(out), "--workers", "2", "-q"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline, kids = time.time() + 120, []
    while time.time() < deadline:
        rec = _record(out)
        kids = _kill_tree(proc) or kids
        if rec and 2 <= sum(b - a for a, b in rec["done"]) <= 10:
            break
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.01)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    for k in kids:  # the pool's workers follow their parent; make sure
        with_kill(k.pid)
    before = {c for a, b in _record(out)["done"] for c in range(a, b)}
    assert 2 <= len(before) < 16
    ds = st.open_sweep(out).load()
    assert not ds.attrs["complete"] and (ds.status.values == -1).sum() == 80 - 5 * len(before)
    res = CliRunner().invoke(st.sweep_cmd, [str(toml), "--out", str(out), "--workers", "2", "--json"])
    assert res.exit_code == 0, res.output
    summary = json.loads(res.output)
    assert summary["done_before"] == 5 * len(before) and summary["computed"] == 80 - 5 * len(before)
    rec = _record(out)
    assert rec["done"] == [[0, 16]] and sum(rec["counts"].values()) == 80  # each point counted once
    ds = _load(out)
    assert ds.attrs["complete"]
    same = {k: v for k, v in ds.data_vars.items() if k != "verified_error"}  # verified by the ODE here
    ref = _load(reference)
    for name in REPRODUCIBLE:
        if name in same and name not in ("message",):
            assert np.array_equal(same[name].values, ref[name].values, equal_nan=True), name


def with_kill(pid):
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def test_kill_9_of_a_worker_loses_nothing(tmp_path, reference):
    toml = _toml(tmp_path, chunk=5, verify='"ode"')
    out = tmp_path / "w.zarr"
    proc = subprocess.Popen([sys.executable, "-c", _DRIVER, str(toml), "--out", str(out), "--workers", "2", "--json"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline, killed = time.time() + 120, None
    while time.time() < deadline and proc.poll() is None:
        rec = _record(out)
        if rec and sum(b - a for a, b in rec["done"]) >= 2:
            kids = _kill_tree(proc)
            if kids:
                killed = kids[0].pid
                with_kill(killed)
                break
        time.sleep(0.01)
    stdout, stderr = proc.communicate(timeout=180)
    assert killed is not None and proc.returncode == 0, stderr
    summary = json.loads(stdout)
    assert summary["complete"] and summary["computed"] == 80 and summary["counts"]["success"] > 0
    ds, ref = _load(out), _load(reference)
    for name in ("status", "effort", "peak_rate", "least_P0", "evaluations"):
        assert np.array_equal(ds[name].values, ref[name].values, equal_nan=True), name


def test_a_half_written_chunk_is_never_read_as_done(tmp_path, reference):
    sw = _small()
    out = tmp_path / "h.zarr"
    store = open_or_create(out, sw)
    try:
        store.write(sw.compute(0))
        # a run killed while writing chunk 1: its data is there, the record does not name it
        half = sw.compute(1)
        arrays = store.arrays()
        region = sw.chunk_region(1)
        arrays["status"][region] = half["data"]["status"].reshape(1, 5)
        arrays["effort"][region] = half["data"]["effort"].reshape(1, 5)
        (out / f".{st.RECORD}.tmp-999").write_text("{half")  # and the record's temporary file
    finally:
        store.close()
    ds = st.open_sweep(out).load()
    assert ds.attrs["chunks_done"] == 1 and (ds.status.values[1] == -1).all() and np.isnan(ds.effort.values[1]).all()
    assert (ds.status.values[0] >= 0).all()
    summary = st.run_sweep(sw, out, executor="serial")
    assert summary.done_before == 5 and summary.computed == 75 and summary.complete
    assert not list(out.glob(f".{st.RECORD}.tmp-*"))
    _assert_same(_load(out), _load(reference))


def _refused(tmp_path, out, match, toml=None):
    res = CliRunner().invoke(st.sweep_cmd, [str(toml or _toml(tmp_path)), "--out", str(out)])
    assert res.exit_code == 2, res.output
    assert match in res.output, res.output
    return res.output


def test_foreign_and_corrupt_stores_are_refused_with_exit_2(tmp_path, reference):
    # a folder with other files
    other = tmp_path / "other"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    _refused(tmp_path, other, "is not an acroplan sweep store (no zarr.json")
    assert (other / "notes.txt").read_text() == "mine" and len(list(other.iterdir())) == 1
    # a zarr store someone else wrote
    import xarray as xr

    foreign = tmp_path / "foreign.zarr"
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_zarr(foreign, zarr_format=3, consolidated=False)
    _refused(tmp_path, foreign, "is a zarr store, but not one acroplan sweep wrote")
    with pytest.raises(InvalidInputError, match="not one acroplan sweep wrote"):
        st.open_sweep(foreign)
    # another sweep's store: the differing field is named
    _refused(tmp_path, reference, "holds another sweep: sweep.base.options.verify", _toml(tmp_path, verify="false"))
    _refused(tmp_path, reference, "holds another sweep: sweep.grid.robot.angular_momentum",
             _toml(tmp_path, n_p0=17))
    # corrupt: the record, the metadata, an array, the definition against its hash
    for damage, match in [
        (lambda p: (p / st.RECORD).write_text("{not json"), "completion record (acroplan-sweep.json) cannot be read"),
        (lambda p: (p / st.RECORD).write_text(json.dumps({"done": [[0, 99]], "messages": {}, "counts": {},
                                                          "hash": _small().hash})), "does not describe this store"),
        (lambda p: (p / st.RECORD).unlink(), "completion record (acroplan-sweep.json) is missing"),
        (lambda p: (p / "zarr.json").write_text("\x00\x01"), "zarr.json cannot be read"),
        (lambda p: shutil.rmtree(p / "effort"), "its array 'effort' is missing"),
        (lambda p: (p / "zarr.json").write_text((p / "zarr.json").read_text().replace('\\"free\\"', '\\"spline\\"')),
         "does not match its hash"),
    ]:
        broken = tmp_path / "broken.zarr"
        shutil.rmtree(broken, ignore_errors=True)
        shutil.copytree(reference, broken)
        damage(broken)
        _refused(tmp_path, broken, match)
        with pytest.raises(InvalidInputError, match="corrupt"):
            st.open_sweep(broken)
    # a file, not a store
    f = tmp_path / "file.zarr"
    f.write_text("x")
    _refused(tmp_path, f, "is not a sweep store (it is a file)")


def test_one_run_at_a_time_writes_a_store(tmp_path):
    sw = _small()
    out = tmp_path / "l.zarr"
    store = open_or_create(out, sw)
    try:
        with pytest.raises(InvalidInputError, match=r"is being written by another run \(pid \d+\)"):
            open_or_create(out, sw)
    finally:
        store.close()
    st.run_sweep(sw, out, executor="serial")


def test_layering_with_the_sweep_as_a_front_door():
    spec = importlib.util.spec_from_file_location("layering", ROOT / "tests" / "test_layering.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    mod.FRONT_DOORS = set(mod.FRONT_DOORS) | {"acroplan.sweeps"}
    mod.test_imports_point_one_way()
    mod.test_no_import_circles()


# ---------------------------------------------------------------------------------------------- maps
def test_maps_mark_infeasible_and_failed_points_apart(tmp_path, reference):
    import matplotlib

    backend_before = matplotlib.get_backend()
    fig = st.draw_map(reference, "T", "P0", "effort", tmp_path / "m.png")
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(label.startswith("infeasible (") for label in labels)
    assert (tmp_path / "m.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert matplotlib.get_backend() == backend_before
    res = CliRunner().invoke(st.map_cmd, [str(reference), "--x", "plan.T", "--y", "P0", "--value", "least_P0",
                                          "--kind", "contour", "--out", str(tmp_path / "m.pdf")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "m.pdf").read_bytes()[:5] == b"%PDF-"
    res = CliRunner().invoke(st.map_cmd, [str(reference), "--x", "T", "--y", "P0", "--value", "status", "--out",
                                          str(tmp_path / "s.png")])
    assert res.exit_code == 0, res.output
    res = CliRunner().invoke(st.map_cmd, [str(reference), "--x", "T", "--y", "P0", "--value", "torque", "--out",
                                          str(tmp_path / "x.png")])
    assert res.exit_code == 2 and "--value: 'torque' is not in the store" in res.output
    # a failed point gets its own mark
    ds = st.open_sweep(reference).load()
    ds["status"][0, 0] = 2
    fig = st.draw_map(ds, "T", "P0", "effort")
    assert any(t.get_text().startswith("failed (1)") for t in fig.axes[0].get_legend().get_texts())


def test_a_sweep_over_the_objective_records_what_plan_gives(tmp_path):
    """objective is a plan() keyword like any other: the energy-optimal points have the least
    integral of u^2, and every point equals plan() with that objective."""
    from acroplan.io.sweeps import open_sweep, run_sweep
    from acroplan.sweeps.metrics import point_metrics as _metrics

    base = dict(system=_robot(), times=[0, 1], theta=[0, 2.0], phi=[-math.pi, -2.5], conditions="free")
    sw = sweep(base, grid={"objective": ["energy", "torque"], "T": [1.0, 1.2]}, chunk_size=2)
    run_sweep(sw, tmp_path / "o.zarr", workers=1)
    ds = open_sweep(tmp_path / "o.zarr")
    assert (ds.status.values == 0).all()
    effort = ds.effort.values
    assert np.all(effort[0] <= effort[1] * (1 + 1e-9))  # least integral of u^2 where it is minimised
    for i, objective in enumerate(["energy", "torque"]):
        for j, T in enumerate([1.0, 1.2]):
            res = acroplan.plan(**{**base, "times": [0, T]}, objective=objective)
            e, peak, tau = _metrics(res)
            assert (effort[i, j], ds.peak_rate.values[i, j], ds.peak_torque.values[i, j]) == (e, peak, tau)
