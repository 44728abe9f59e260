"""Sweeps bounded and safe (issue #25, items 3, 4, 6, 7 and the sweep parts of 9 and 10) and the
sweep packages of one job (issue #21): each defect's regression test names the issue."""

import ast
import hashlib
import inspect
import json
import math
import os
import pathlib
import shutil
import signal
import subprocess
import sys
import threading
import time
import tracemalloc
import types

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as hs

import acroplan
from acroplan.core.errors import InvalidInputError
from acroplan.io import sweeps as st
from acroplan.io.sweeps import writer
from acroplan.io.sweeps.writer import open_or_create
from acroplan.sweeps import PointStatus, from_definition, sweep

import texts

ROOT = pathlib.Path(__file__).parents[1]
BODY = dict(torso_mass=40.0, leg_mass=20.0, torso_inertia=1.8, leg_inertia=1.2, torso_length=0.35, leg_length=0.45,
            angular_momentum=10.0)
DERIVED_ONLY = texts.problem(theta="2.0", phi='"-pi"', conditions="free") + """

[sweep]
plan = false
derived = ["least_P0", "most_P0"]
chunk_size = 5

[sweep.grid]
P0 = {start = 2, stop = 20, num = 16}
T = [0.5, 0.75, 1.0, 1.5, 2.0]
"""
COMPARED = ("status", "message", "least_P0", "most_P0")


def _base(**kw):
    return dict(system=acroplan.Acrobot.from_physical(**BODY), times=[0, 1], theta=[0, 2.0],
                phi=[-math.pi, -math.pi], conditions="free", **kw)


def _derived(chunk=5, **grid):
    return sweep(_base(), grid=grid or {"P0": {"start": 2, "stop": 20, "num": 16}, "T": [0.5, 0.75, 1.0, 1.5, 2.0]},
                 plan=False, derived=["least_P0", "most_P0"], chunk_size=chunk)


def _file(tmp_path, text=DERIVED_ONLY, name="s.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def _cli(cmd, args):
    return CliRunner().invoke(cmd, [str(a) for a in args])


@pytest.fixture(scope="module")
def complete(tmp_path_factory):
    """A complete derived-only store (16 chunks of 5 points), computed in this process."""
    path = tmp_path_factory.mktemp("complete") / "c.zarr"
    assert st.run_sweep(_derived(), path, executor="serial").complete
    return path


def _copy(src, tmp_path, name="d.zarr"):
    dst = tmp_path / name
    shutil.copytree(src, dst)
    return dst


def _values(path):
    ds = st.open_sweep(path).load()
    return {k: ds[k].values.copy() for k in COMPARED}


# ---------------------------------------------------------------------------------------------- item 3: bounded
def test_the_definition_records_the_grid_description_not_its_values(tmp_path):
    """Issue #25 (3): the stored definition held every grid value (zarr.json was 18.8 MB at 1e6
    points); it holds the description, whatever the number of points."""
    small = _derived(T={"start": 0.5, "stop": 2.0, "num": 1000}, P0=[5.0, 10.0])
    large = _derived(T={"start": 0.5, "stop": 2.0, "num": 1_000_000}, P0=[5.0, 10.0])
    assert large.size == 2_000_000 and len(large.json) - len(small.json) == 3  # "1000" -> "1000000"
    assert dict(large.definition["grid"])["plan.T"] == {"start": 0.5, "stop": 2.0, "num": 1_000_000}
    store = open_or_create(tmp_path / "big.zarr", large)
    store.close()
    assert (tmp_path / "big.zarr" / "zarr.json").stat().st_size < 30_000
    # the values are numpy's, generated where they are needed
    assert np.array_equal(large.axes["plan.T"].slice(0, 1_000_000), np.linspace(0.5, 2.0, 1_000_000))
    last = large.values(large.chunk_points(large.n_chunks - 1))["plan.T"]
    assert np.array_equal(last, np.repeat(np.linspace(0.5, 2.0, 1_000_000), 2)[-last.size:])  # T x P0, C order


@pytest.mark.parametrize("spec, numpy_values", [
    ({"start": 2.0, "stop": 20.0, "num": 16}, np.linspace(2.0, 20.0, 16)),
    ({"start": -1.3, "stop": 7.1, "num": 1}, np.linspace(-1.3, 7.1, 1)),
    ({"start": 3.0, "stop": -1e-3, "num": 977}, np.linspace(3.0, -1e-3, 977)),
    ({"start": 1e-3, "stop": 40.0, "num": 301, "log": True}, np.geomspace(1e-3, 40.0, 301)),
    ({"start": 0.5, "stop": 2.0, "step": 0.25}, 0.5 + 0.25 * np.arange(7)),
])
def test_a_range_axis_gives_numpys_values_bit_for_bit(spec, numpy_values):
    sw = _derived(P0=spec, chunk=7)
    assert np.array_equal(sw.axes["robot.angular_momentum"].slice(0, sw.shape[0]), numpy_values)
    got = np.concatenate([sw.values(sw.chunk_points(c))["robot.angular_momentum"] for c in range(sw.n_chunks)])
    assert np.array_equal(got, numpy_values)


def test_defining_and_creating_a_large_sweep_keeps_memory_flat(tmp_path):
    """Issue #25 (3): a grid of 1e7 points reached 2.3 GB before its first chunk; defining an
    8e6-point sweep, creating its store and computing a chunk stay within a few chunks' memory
    (traced allocations)."""
    tracemalloc.start()
    try:
        sw = _derived(T={"start": 0.5, "stop": 2.0, "num": 4_000_000}, P0=[5.0, 10.0], chunk=1000)
        store = open_or_create(tmp_path / "m.zarr", sw)
        try:
            store.write(sw.compute(sw.n_chunks - 1))
        finally:
            store.close()
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert sw.size == 8_000_000 and peak < 48e6, peak


@pytest.mark.parametrize("grid, number", [
    ("T = {start = 1.0, stop = 2.0, num = 1000000000}", "1000000000"),
    ("T = {start = 1.0, stop = 2.0, num = 100000}\nP0 = {start = 1.0, stop = 2.0, num = 10000}",
     "100000 x 10000 = 1000000000"),
    ("T = {start = 1.0, stop = 2.0, step = 1e-12}", "points"),
])
def test_impossible_grids_are_refused_with_exit_2_naming_the_number(tmp_path, grid, number):
    """Issue #25 (3): ``num = 1e9`` exited 1 with MemoryError; now exit 2, the number named, no store."""
    text = DERIVED_ONLY.split("[sweep.grid]")[0] + "[sweep.grid]\n" + grid + "\n"
    res = _cli(st.sweep_cmd, [_file(tmp_path, text), "--out", tmp_path / "o.zarr"])
    assert res.exit_code == 2, res.output
    assert "sweep.grid" in res.output and number in res.output and "at most 100000000" in res.output
    assert not (tmp_path / "o.zarr").exists()


def test_an_impossible_sample_is_refused_with_exit_2_and_no_store(tmp_path):
    """Issue #25 (3): ``[sweep.sample] n = 1e12`` took 4.9 GB and exited 1 leaving a store."""
    text = DERIVED_ONLY.split("[sweep.grid]")[0] + "[sweep.sample]\nn = 1000000000000\nT = [0.5, 2.0]\n"
    res = _cli(st.sweep_cmd, [_file(tmp_path, text), "--out", tmp_path / "o.zarr"])
    assert res.exit_code == 2 and "sweep.sample.n" in res.output and "1000000000000" in res.output, res.output
    assert not list(tmp_path.glob("*o.zarr*"))
    with pytest.raises(InvalidInputError, match="chunk_size: .* make 100000000 chunks; a store has at most 1000000"):
        sweep(_base(), sample={"n": 100_000_000, "T": [0.5, 2.0]}, plan=False, derived=["least_P0"], chunk_size=1)


# ---------------------------------------------------------------------------------------------- item 4: orphans
_DRIVER = "import sys; from acroplan.io.sweeps import sweep_cmd; sweep_cmd.main(args=sys.argv[1:])"
SLOW = texts.problem(theta="2.0", phi='"-pi"', conditions="free") + """

[sweep]
derived = ["least_P0"]
chunk_size = 5

[sweep.options]
verify = "ode"

[sweep.grid]
P0 = {start = 2, stop = 20, num = 16}
T = [0.5, 0.75, 1.0, 1.5, 2.0]
"""


def _done(store) -> int:
    try:
        return sum(b - a for a, b in json.loads((store / st.RECORD).read_text())["done"])
    except (OSError, ValueError, KeyError):
        return 0


def test_a_killed_driver_leaves_no_worker_behind(tmp_path):
    """Issue #25 (4): after ``kill -9`` of the driver its workers lived on (7 seen, 600-740 s later),
    holding the driver's stdout and stderr open; they watch the driver and end themselves."""
    import psutil

    out = tmp_path / "k.zarr"
    proc = subprocess.Popen([sys.executable, "-c", _DRIVER, str(_file(tmp_path, SLOW)), "--out", str(out),
                             "--workers", "2", "-q"], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    kids = []
    try:
        deadline = time.monotonic() + 180
        while time.monotonic() < deadline and proc.poll() is None and not (_done(out) >= 1 and len(kids) >= 2):
            kids = [k for k in psutil.Process(proc.pid).children(recursive=True)] or kids
            time.sleep(0.02)
        assert proc.poll() is None and len(kids) >= 2, proc.communicate()
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        # the pipes close once every worker has gone: a caller reading them does not hang
        stdout, stderr = proc.communicate(timeout=120)
        gone, alive = psutil.wait_procs(kids, timeout=60)
        assert not alive, [p.pid for p in alive]
        assert 1 <= _done(out) < 16
    finally:
        for k in kids:
            try:
                k.kill()
            except psutil.NoSuchProcess:
                pass
    # and the store resumes as ever
    assert st.run_sweep(st.load_sweep(tmp_path / "s.toml"), out, executor="serial").complete


def test_workers_watch_their_driver():
    from acroplan.io.sweeps import executors

    pool = executors.new_pool(1)
    try:
        assert pool._initializer is executors.watch_parent and pool._initargs == (os.getpid(),)
    finally:
        pool.shutdown()


# ---------------------------------------------------------------------------------------------- item 6: corruption
def _chunk_file(store, name, chunk):
    return store / name / "c" / str(chunk) / "0"


def _flip(path):
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x40
    path.write_bytes(bytes(data))


def _swap(a, b):
    da, db = a.read_bytes(), b.read_bytes()
    a.write_bytes(db)
    b.write_bytes(da)


DAMAGE = {
    "a flipped byte": (lambda s: _flip(_chunk_file(s, "least_P0", 3)), [3]),
    "swapped chunks": (lambda s: _swap(_chunk_file(s, "seconds", 2), _chunk_file(s, "seconds", 5)), [2, 5]),
    "a deleted chunk": (lambda s: _chunk_file(s, "most_P0", 7).unlink(), [7]),
    "an emptied chunk": (lambda s: _chunk_file(s, "status", 9).write_bytes(b""), [9]),
    "a chunk copied over another": (lambda s: shutil.copy(_chunk_file(s, "seconds", 11),
                                                                _chunk_file(s, "seconds", 12)), [12]),
}


@pytest.mark.parametrize("damage", list(DAMAGE))
def test_a_damaged_chunk_is_named_on_open_and_recomputed_on_resume(tmp_path, complete, damage):
    """Issue #25 (6): a flipped byte, swapped, deleted or emptied chunks were read as correct (the
    resume said "complete", exit 0, the data wrong; an emptied chunk made ``acroplan map`` exit 1).
    Every chunk carries a checksum: a bad one is named on open (exit 2) and recomputed on resume."""
    ref = _values(complete)
    store = _copy(complete, tmp_path)
    hurt, chunks = DAMAGE[damage]
    hurt(store)
    with pytest.raises(InvalidInputError, match=rf"is damaged: chunk {chunks[0]} \(P0\[{chunks[0]}:"):
        st.open_sweep(store)
    res = _cli(st.map_cmd, [store, "--x", "T", "--y", "P0", "--value", "least_P0", "--out", tmp_path / "m.png"])
    assert res.exit_code == 2 and f"chunk {chunks[0]} (" in res.output, res.output
    masked = st.open_sweep(store, damaged="mask").load()
    assert masked.attrs["damaged"] == chunks and masked.attrs["chunks_done"] == 16 - len(chunks)
    assert all((masked.status.values[c] == -1).all() and np.isnan(masked.least_P0.values[c]).all() for c in chunks)
    # the command line resumes it: exactly the damaged chunks are computed again
    res = _cli(st.sweep_cmd, [_file(tmp_path), "--out", store, "--json"])
    assert res.exit_code == 0, res.output
    summary = json.loads(res.output)
    assert [c for c, _ in summary["recomputed"]] == chunks and summary["computed"] == 5 * len(chunks)
    assert summary["complete"] and sum(summary["counts"].values()) == 80
    for name, values in _values(store).items():
        assert np.array_equal(values, ref[name], equal_nan=True), name


def test_a_record_naming_uncomputed_chunks_is_not_believed(tmp_path):
    """Issue #25 (6): a record naming chunks never computed made the resume say "complete"."""
    sw = _derived()
    store_path = tmp_path / "u.zarr"
    store = open_or_create(store_path, sw)
    try:
        for c in (0, 1, 2):
            store.write(sw.compute(c))
    finally:
        store.close()
    rec = json.loads((store_path / st.RECORD).read_text())
    rec["done"] = [[0, 16]]
    (store_path / st.RECORD).write_text(json.dumps(rec))
    with pytest.raises(InvalidInputError, match=r"chunk 3 \(P0\[3:4\], T\[0:5\]\) has no checksum"):
        st.open_sweep(store_path)
    summary = st.run_sweep(sw, store_path, executor="serial")
    assert summary.done_before == 15 and summary.computed == 65 and len(summary.recomputed) == 13
    assert summary.complete and st.open_sweep(store_path).attrs["checksums"] == "verified"


def test_the_record_counts_are_rederived_from_the_chunks(tmp_path, complete):
    """Issue #25 (10): the record's counts were trusted (2,000 "success" in a 1,600-point store)."""
    store = _copy(complete, tmp_path)
    rec = json.loads((store / st.RECORD).read_text())
    truth = dict(rec["counts"])
    rec["counts"] = {"success": 2000}
    (store / st.RECORD).write_text(json.dumps(rec))
    assert json.loads(st.open_sweep(store).attrs["counts"]) == truth and sum(truth.values()) == 80
    summary = st.run_sweep(_derived(), store, executor="serial")
    assert summary.counts == truth and summary.computed == 0
    assert json.loads((store / st.RECORD).read_text())["counts"] == truth


def test_a_store_written_before_checksums_is_read_not_resumed(tmp_path, complete):
    """Stores of format 1 (no checksums) stay readable; resuming one is refused, said why."""
    store = _copy(complete, tmp_path)
    meta = json.loads((store / "zarr.json").read_text())
    definition = json.loads(meta["attributes"]["acroplan_sweep"])
    definition["format"] = 1
    text = acroplan.sweeps.canonical_json(definition)
    meta["attributes"].update(acroplan_sweep=text, acroplan_sweep_hash=hashlib.sha256(text.encode()).hexdigest(),
                              acroplan_store_format=1)
    (store / "zarr.json").write_text(json.dumps(meta))
    rec = json.loads((store / st.RECORD).read_text())
    rec.update(hash=meta["attributes"]["acroplan_sweep_hash"], format=1)
    (store / st.RECORD).write_text(json.dumps(rec))
    (store / st.CHECKSUMS).unlink()
    ds = st.open_sweep(store)
    assert ds.attrs["checksums"] == "none (store format 1)" and ds.attrs["complete"]
    assert np.array_equal(ds.least_P0.values, _values(complete)["least_P0"], equal_nan=True)
    with pytest.raises(InvalidInputError, match="store format 1 .* not resumed"):
        st.run_sweep(from_definition(definition), store, executor="serial")


# ---------------------------------------------------------------------------------------------- item 7: no code
def body(kill: float = 0.0, boom: float = 0.0, **physical):
    """A system factory for the tests: ``kill >= 1`` ends the process computing it, ``boom`` raises."""
    if kill >= 1:
        os._exit(3)
    if boom:
        raise RuntimeError("the factory broke")
    return acroplan.Acrobot.from_physical(**{**BODY, **physical})


def _factory_sweep(**grid):
    return sweep(body, robot={"torso_mass": 40.0, "kill": 0.0, "boom": 0.0}, times=[0, 1], theta=[0, 2.0],
                 phi=[-math.pi, -math.pi], conditions="free", grid=grid or {"torso_mass": [40.0, 45.0], "T": [1.0, 1.5]},
                 plan=False, derived=["least_P0"], chunk_size=2)


def test_a_store_never_imports_the_code_it_names(tmp_path):
    """Issue #25 (7): opening a store imported the module its zarr.json named (``this:s`` printed the
    Zen of Python on ``acroplan map``); a factory is resolved from registered names and callables
    passed explicitly, never from a module path read from a store."""
    sw = _factory_sweep()
    assert sw.definition["base"]["factory"] == f"{__name__}:body"
    # a store whose definition names this:s (anyone can write one: the hash is no signature)
    definition = json.loads(sw.json)
    definition["base"]["factory"] = "this:s"
    with pytest.raises(InvalidInputError, match=r"base.factory: names 'this:s', which is neither a registered"):
        st.run_sweep(from_definition(definition), tmp_path / "f.zarr", executor="serial")
    store = tmp_path / "f.zarr"
    assert not store.exists()
    assert st.run_sweep(from_definition(definition, factories={"this:s": body}), store, executor="serial").complete
    code = ("import sys; from acroplan.io.sweeps import map_cmd, open_sweep; "
            "map_cmd.main(args=sys.argv[1:], standalone_mode=False); open_sweep(sys.argv[1]).load(); "
            "print('this' in sys.modules)")
    run = subprocess.run([sys.executable, "-c", code, str(store), "--x", "T", "--y", "torso_mass", "--value",
                          "least_P0", "--out", str(tmp_path / "m.png")], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "Zen of Python" not in run.stdout + run.stderr and run.stdout.split()[-1] == "False"
    # resuming it needs the factory given explicitly
    with pytest.raises(InvalidInputError, match=r"base.factory: names 'this:s'.*factories=\{'this:s'"):
        st.run_sweep(from_definition(definition), store, executor="serial")
    assert "this" not in sys.modules
    summary = st.run_sweep(from_definition(definition), store, executor="serial", factories={"this:s": body})
    assert summary.complete and summary.computed == 0


def test_registered_factories_are_resolved_by_name():
    sw = sweep(acroplan.Acrobot.from_physical, robot=BODY, times=[0, 1], theta=[0, 2.0], phi=[-math.pi, -math.pi],
               conditions="free", grid={"leg_mass": [20.0, 25.0]}, plan=False, derived=["least_P0"])
    assert sw.definition["base"]["factory"] == "Acrobot.from_physical"
    again = from_definition(sw.definition)
    assert again.factory == acroplan.Acrobot.from_physical
    assert again.evaluate(1).data["least_P0"] == sw.evaluate(1).data["least_P0"]


def test_the_hash_is_not_presented_as_authentication():
    """Issue #25 (7): the stored SHA-256 can be recomputed by anyone; the docs and messages say it
    detects accidents and authenticates nothing."""
    page = (ROOT / "docs" / "sweeps.md").read_text()
    assert "not a signature" in page and "never imports" in page
    from acroplan.io.sweeps import check

    assert "not a signature" in inspect.getsource(check)


# ---------------------------------------------------------------------------------------------- items 9 and 10
@pytest.mark.parametrize("key, value, field", [
    ("derived", "-3.14", "sweep.derived: must be a list of names"),
    ("derived", "[-3.14]", "sweep.derived: unknown derived quantity"),
    ("derived", '"least_PO"', "sweep.derived: unknown derived quantity 'least_PO'"),
    ("chunk_size", "1e9", "sweep.chunk_size: must be a whole number"),
    ("chunk_size", "1000000", "sweep.chunk_size: must be a whole number from 1 to 100000"),
    ("plan", "3", "sweep.plan: must be True or False"),
])
def test_bad_sweep_keys_are_exit_2_naming_the_field(tmp_path, key, value, field):
    """Issue #25 (9): a sweep ``derived = -3.14`` exited 1 with a TypeError."""
    keys = {"plan": "false", "derived": '["least_P0", "most_P0"]', "chunk_size": "5", key: value}
    head, grid = DERIVED_ONLY.split("[sweep]")[0], DERIVED_ONLY.split("[sweep.grid]")[1]
    text = head + "[sweep]\n" + "".join(f"{k} = {v}\n" for k, v in keys.items()) + "\n[sweep.grid]" + grid
    res = _cli(st.sweep_cmd, [_file(tmp_path, text), "--out", tmp_path / "o.zarr"])
    assert res.exit_code == 2 and field in res.output, res.output


_VALUES = hs.one_of(hs.integers(-10**13, 10**13), hs.floats(allow_nan=True, allow_infinity=True), hs.booleans(),
                    hs.text(max_size=6), hs.lists(hs.floats(-5, 5), max_size=3),
                    hs.fixed_dictionaries({"start": hs.floats(-3, 3), "stop": hs.floats(-3, 3),
                                           "num": hs.integers(-2, 10**10)}),
                    hs.fixed_dictionaries({"start": hs.floats(-3, 3), "stop": hs.floats(-3, 3),
                                           "step": hs.floats(-1, 1)}))
_KEYS = hs.sampled_from(["T", "P0", "scale", "u_max", "theta[-1]", "times[0]", "somersaults", "reach", "method",
                         "n", "seed", "derived", "plan", "chunk_size", "robot.nothing", "x"])


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kind=hs.sampled_from(["grid", "sample"]), table=hs.dictionaries(_KEYS, _VALUES, max_size=3),
       top=hs.dictionaries(hs.sampled_from(["derived", "plan", "chunk_size"]), _VALUES, max_size=2))
def test_fuzzed_sweep_tables_are_read_or_refused_never_crash(kind, table, top):
    """Issue #25: a bounded fuzz of sweep files: each is a sweep or an InvalidInputError (exit 2),
    never another error, and never more than the limits allow."""
    data = {"robot": dict(BODY), "plan": {"times": [0, 1], "theta": [0, 2.0], "phi": ["-pi", "-pi"],
                                          "conditions": "free"},
            "sweep": {**top, kind: table}}
    try:
        sw = st.parse_sweep(data)
    except InvalidInputError:
        return
    assert sw.size <= acroplan.sweeps.MAX_POINTS and sw.n_chunks <= acroplan.sweeps.MAX_CHUNKS
    sw.values(sw.chunk_points(sw.n_chunks - 1))


def test_stale_creation_markers_of_dead_runs_are_removed(tmp_path):
    """Issue #25 (10): a ``.STORE.creating-PID`` left by a killed run was never removed; it is once
    its process is gone (a live run's is kept)."""
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    live = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(120)"])
    try:
        stale, kept = tmp_path / f".s.zarr.creating-{dead.pid}", tmp_path / f".s.zarr.creating-{live.pid}"
        for marker in (stale, kept):
            (marker / "status").mkdir(parents=True)
            (marker / "zarr.json").write_text("{}")
        assert st.run_sweep(_derived(), tmp_path / "s.zarr", executor="serial").complete
        assert not stale.exists() and kept.exists()
    finally:
        live.kill()
        live.wait()


def test_two_runs_starting_together_on_a_new_store(tmp_path, monkeypatch):
    """Issue #25 (10): of two runs starting together on a new store, the loser said the store "exists
    and is not empty, and is not a sweep store"; it now says another run created it and writes it."""
    sw, out = _derived(), tmp_path / "t.zarr"
    building, created = threading.Event(), threading.Event()
    build = writer._build

    def slow_build(tmp, sweep_):
        build(tmp, sweep_)
        if threading.current_thread().name == "loser":
            building.set()
            created.wait(60)

    monkeypatch.setattr(writer, "_build", slow_build)
    errors = []

    def loser():
        try:
            open_or_create(out, sw).close()
        except InvalidInputError as e:
            errors.append(str(e))

    t = threading.Thread(target=loser, name="loser")
    t.start()
    assert building.wait(60)
    winner = open_or_create(out, sw)  # created while the loser was building
    try:
        created.set()
        t.join(60)
    finally:
        winner.close()
    assert len(errors) == 1 and "is not a sweep store" not in errors[0], errors
    assert f"was created by another run (pid {os.getpid()}) that started at the same time" in errors[0]
    assert not list(tmp_path.glob(".t.zarr.creating-*"))
    assert st.run_sweep(sw, out, executor="serial").complete


def test_a_point_that_kills_its_worker_is_marked_and_workers_are_counted_once(tmp_path):
    """Issue #25 (10): the summary counted replaced workers as extra workers (here "on 2 worker(s)"
    for one); a point that kills its worker is recorded as not converged, the others computed. One
    worker and one chunk in flight make the run's course fixed: chunk 0 is computed by the first
    process, chunk 1 kills it and its replacement, chunk 2 is computed by a third process, chunk 3
    kills it; the killing points are then computed alone, and marked."""
    sw = _factory_sweep(T=[1.0, 1.5], kill=[0.0, 0.5, 1.0])
    assert sw.n_chunks == 4
    summary = st.run_sweep(sw, tmp_path / "w.zarr", workers=1, window=1)
    assert summary.complete and summary.n_workers == 1 and len(summary.workers) == 2 and summary.replaced == 1
    assert any(" on 1 worker(s) (1 replaced)," in line for line in summary.lines()), summary.lines()
    ds = st.open_sweep(tmp_path / "w.zarr").load()
    assert (ds.status.values[:, 2] == PointStatus.NOT_CONVERGED.code).all()
    assert (ds.status.values[:, :2] == PointStatus.SUCCESS.code).all()
    table = json.loads(ds.attrs["messages"])
    assert "the worker computing this point died" in table[str(int(ds.message.values[0, 2]))]


# ---------------------------------------------------------------------------------------------- issue 21
def test_a_crashed_point_is_not_converged_as_in_plan_many():
    """Issue #21: a crash while building a point was ``invalid`` in sweeps, ``not_converged`` in
    batch.py: one vocabulary now, every point's status an acroplan.Status (or ``invalid``: refused
    by plan()'s validation)."""
    sw = _factory_sweep(T=[1.0, -1.0], boom=[0.0, 1.0])
    points = [sw.evaluate(i) for i in range(4)]
    assert [p.status for p in points] == ["success", "not_converged", "invalid", "not_converged"]
    assert points[1].message.startswith("not converged: unexpected RuntimeError building the point: the factory broke")
    assert points[1].status.plan_status is acroplan.Status.NOT_CONVERGED and not points[1].success
    assert points[0].success and points[0].status == acroplan.Status.SUCCESS
    assert points[2].status.plan_status is None and "plan.T: must be > 0" in points[2].message
    assert [s.code for s in PointStatus] == [0, 1, 2, 3]


def test_a_stored_point_reads_back_with_its_vocabulary(complete):
    ds = st.open_sweep(complete)
    p = acroplan.SweepPoint.from_dataset(ds, 7)
    assert p.success and p.status is PointStatus.SUCCESS and p.message == "success: derived"
    assert p.values == {"robot.angular_momentum": float(np.linspace(2, 20, 16)[1]), "plan.T": 1.0}
    assert p.data["least_P0"] == float(ds.least_P0.values[1, 2])


def test_sweep_is_a_function_and_moved_names_warn():
    assert inspect.isfunction(acroplan.sweep) and acroplan.sweep is acroplan.sweeps.sweep
    assert type(sys.modules["acroplan.sweeps"]) is types.ModuleType
    with pytest.raises(ModuleNotFoundError):
        __import__("acroplan.sweep")
    with pytest.warns(DeprecationWarning, match=r"acroplan.io.store.run_sweep moved to acroplan.io.sweeps"):
        from acroplan.io.store import run_sweep
    assert run_sweep is acroplan.run_sweep


SWEEP_PACKAGES = [ROOT / "src" / "acroplan" / "sweeps", ROOT / "src" / "acroplan" / "io" / "sweeps"]
FAMILY_CLASSES = {"Acrobot", "PhysicalParameters", "PlanarBody", "SpatialBody", "SagittalBody", "Unicycle",
                  "ChainedForm"}


@pytest.mark.parametrize("path", sorted(p for d in SWEEP_PACKAGES for p in d.glob("*.py")),
                         ids=lambda p: f"{p.parent.name}/{p.name}")
def test_the_sweep_modules_name_no_family_and_do_one_job(path):
    """Issue #21: outside families/, no family is imported, no family class named (as a name or a
    type-name string); no module over 800 lines, no function over 80; no sys.modules patching."""
    text = path.read_text()
    tree = ast.parse(text)
    used = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)} | \
        {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)} | \
        {n.value for n in ast.walk(tree) if isinstance(n, ast.Constant) and isinstance(n.value, str)}
    assert not used & FAMILY_CLASSES, used & FAMILY_CLASSES
    imported = {n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)} | \
        {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
    assert not [m for m in imported if "families" in m.split(".")], imported
    assert text.count("\n") <= 800 and "sys.modules[" not in text.replace('sys.modules["acroplan"].__version__', "")
    long = [f.name for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.end_lineno - f.lineno >= 80]
    assert not long, long


def test_family_fields_come_from_the_family_not_the_front_door():
    """Issue #21: ``plan.reach``, ``robot.scale`` and the derived quantities reach the front door
    through the family (its registered hooks and its system's methods): a system without them is
    told so when the sweep is defined."""
    sw = sweep(_base(u_max=12.0), grid={"reach": [0.0, 0.5, 1.0], "T": [1.0]}, chunk_size=3, plan=False,
               derived=["least_P0"])
    R = acroplan.reachable_interval(acroplan.Acrobot.from_physical(**BODY), theta0=0.0, phi0=-math.pi,
                                    phiT=-math.pi, T=1.0, u_max=12.0)
    assert [sw.problem(i)["theta"][-1] for i in range(3)] == [R[0], R[0] + 0.5 * (R[1] - R[0]), R[1]]
    unicycle = dict(system=acroplan.Unicycle(), times=[0, 1], x=[0, 1], y=[0, 0], psi=[0, 0], conditions="free")
    for kwargs, match in [(dict(grid={"reach": [0.5]}), "plan.reach: Unicycle registers no exact reachable interval"),
                          (dict(grid={"scale": [1.1]}), "grid.scale: Unicycle does not say how its parameters scale"),
                          (dict(grid={"T": [1.0]}, derived=["least_P0"]), "derived: least_P0 applies to Acrobot, "
                                                                          "not to Unicycle")]:
        with pytest.raises(InvalidInputError, match=match):
            sweep(unicycle, **kwargs)
    scaled = _derived(scale=[1.1]).problem(0)["system"]
    assert scaled.physical.torso_mass == 40.0 * 1.1 ** 3 and scaled.physical.leg_length == 0.45 * 1.1
