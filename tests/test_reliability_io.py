"""Reliability of the I/O layer: batch names, atomic output folders under crashes and concurrent
writers, the problem-file parser against hostile values, JSON without NaN, bad files in a batch,
and a fuzz test of the whole path from a problem file to the output folder."""

import csv
import json
import os
import random
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from acroplan.io import examples, output
from acroplan.io.cli import json_text as _json_text
from acroplan.io.cli import main

import texts  # the shared problem texts (tests/texts.py)

GOOD = texts.problem(conditions="free")

INFEASIBLE = GOOD.replace("theta = [0, 1.0]", "theta = [0, 50.0]")
ENV = {**os.environ, "PYTHONWARNINGS": "ignore"}


def run(args):
    return CliRunner().invoke(main, [str(a) for a in args])


def cli(args, **kw):
    return subprocess.Popen([sys.executable, "-m", "acroplan", *map(str, args)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=ENV, **kw)


def write(folder, text, name="p.toml"):
    p = Path(folder) / name
    p.write_text(text)
    return p


def many(*names):
    """A file of many problems with these names (None: no name key)."""
    body = GOOD.replace("[robot]", "[problem.robot]").replace("[plan]", "[problem.plan]")
    return "".join("[[problem]]\n" + ("" if n is None else f"name = {json.dumps(n)}\n") + body for n in names)


def dead_pid() -> int:
    p = subprocess.Popen([sys.executable, "-c", "pass"])
    p.wait()
    return p.pid


def litter(folder: Path) -> list[str]:
    return sorted(p.name for p in Path(folder).iterdir() if p.name.startswith("."))


def strict_json(path: Path):
    def refuse(name):
        raise AssertionError(f"{path}: non-finite number {name} in JSON")

    return json.loads(path.read_text(), parse_constant=refuse)


@pytest.fixture
def no_planning(monkeypatch):
    """Fail the command if it starts planning."""
    import acroplan.io.problem as problem

    def solve(*a, **k):
        raise AssertionError("planning started before the output folder was checked")

    monkeypatch.setattr(problem.Problem, "solve", solve)


# ------------------------------------------------------------------------------------------
# 1. batch problem names stay inside OUT
@pytest.mark.parametrize("name, why", [
    ("../ESCAPED", "is a path"),
    ("<ABSOLUTE>", "is a path"),
    ("a/b", "is a path"),
    ("a\\b", "is a path"),
    ("..", "contains '..'"),
    ("x..y", "contains '..'"),
    ("", "is empty"),
    ("   ", "is empty"),
    (".hidden", "hidden"),
    ("CON", "reserved"),
    ("nul.txt", "reserved"),
    ("summary.csv", "reserved"),
    ("tab\there", "not allowed"),
    ("x" * 101, "more than 100"),
    (5, "must be a string"),
])
def test_batch_names_that_would_escape_or_collide_are_refused(tmp_path, name, why):
    out = tmp_path / "out"
    if name == "<ABSOLUTE>":
        name = str(tmp_path / "ESCAPED-abs")
    text = many("ok", None).replace('name = "ok"', "name = " + (str(name) if isinstance(name, int)
                                                                 else json.dumps(name)), 1)
    res = run(["plan", write(tmp_path, text, "many.toml"), "--out", out, "--no-plots"])
    assert res.exit_code == 2, res.output
    assert res.output.startswith("acroplan: error: problem[0].name: ") and why in res.output, res.output
    assert len(res.output.strip().splitlines()) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["many.toml"]  # no ESCAPED anywhere


def test_batch_duplicate_names_are_refused(tmp_path):
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, many("a", "b", "A"), "many.toml"), "--out", out, "--no-plots"])
    assert res.exit_code == 2 and "problem[2].name: 'A' is also the name of problem[0]" in res.output
    res = run(["plan", write(tmp_path, many("problem-0001", None), "many.toml"), "--out", out, "--no-plots"])
    assert res.exit_code == 2 and "problem[1].name" in res.output
    assert not out.exists()


def test_batch_entry_that_is_not_a_table(tmp_path):
    res = run(["plan", write(tmp_path, "problem = [1, 2]\n", "many.toml"), "--out", tmp_path / "o"])
    assert res.exit_code == 2 and "problem: must be an array of tables" in res.output


# ------------------------------------------------------------------------------------------
# 2. output folders: whole or untouched, no litter
def test_stale_temporaries_of_dead_processes_are_removed_live_ones_kept(tmp_path):
    prob = write(tmp_path, GOOD)
    dead = dead_pid()
    stale = [tmp_path / f".out.acroplan-{dead}-abc123.tmp", tmp_path / f".other.acroplan-{dead}-x_9.tmp"]
    live = tmp_path / ".out.acroplan-1-zzz.tmp"  # pid 1 is alive
    for d in stale + [live]:
        d.mkdir()
        (d / "solution.json").write_text("{half")
    (tmp_path / ".out.acroplan.lock").write_text("")  # left by kill -9; nobody holds it
    (tmp_path / ".other.acroplan.lock").write_text("")
    # a run writing "third" holds its lock: its folder is left alone even if its PID looks dead
    # (a writer in another PID namespace)
    import fcntl

    guarded = tmp_path / f".third.acroplan-{dead}-q.tmp"
    guarded.mkdir()
    fd = os.open(tmp_path / ".third.acroplan.lock", os.O_RDWR | os.O_CREAT)
    fcntl.flock(fd, fcntl.LOCK_EX)
    try:
        res = run(["plan", prob, "--out", tmp_path / "out", "--no-plots"])
    finally:
        os.close(fd)
    assert res.exit_code == 0, res.output
    assert litter(tmp_path) == sorted([live.name, guarded.name, ".third.acroplan.lock"])
    assert (tmp_path / "out" / "solution.json").exists()


def test_dangling_symlink_as_out_is_refused_and_nothing_written(tmp_path, no_planning):
    (tmp_path / "link").symlink_to(tmp_path / "nowhere")
    res = run(["plan", write(tmp_path, GOOD), "--out", tmp_path / "link", "--no-plots"])
    assert res.exit_code == 2 and "--out: " in res.output and "is a symbolic link" in res.output, res.output
    assert "does not exist" in res.output and str(tmp_path / "nowhere") in res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["link", "p.toml"] and not (tmp_path / "nowhere").exists()


def test_symlink_to_a_folder_is_refused_not_written_through(tmp_path, no_planning):
    (tmp_path / "real").mkdir()
    (tmp_path / "real" / "keep.txt").write_text("mine")
    (tmp_path / "link").symlink_to(tmp_path / "real")
    res = run(["plan", write(tmp_path, GOOD), "--out", tmp_path / "link", "--force", "--no-plots"])
    assert res.exit_code == 2 and "is a symbolic link (to " in res.output, res.output
    assert (tmp_path / "link").is_symlink() and (tmp_path / "real" / "keep.txt").read_text() == "mine"
    assert litter(tmp_path) == []


@pytest.mark.parametrize("target, why", [(".", "is the current folder"), ("..", "is a parent of the current"),
                                         ("/", "is a filesystem root"), ("~", "is the home folder")])
def test_folders_that_cannot_be_replaced_are_refused(tmp_path, monkeypatch, no_planning, target, why):
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    write(work, GOOD)
    out = os.path.expanduser(target)
    res = run(["plan", "p.toml", "--out", out, "--force", "--no-plots"])
    assert res.exit_code == 2 and res.output.startswith("acroplan: error: --out: ") and why in res.output, res.output
    assert sorted(p.name for p in work.iterdir()) == ["p.toml"] and litter(tmp_path) == []


def test_out_holding_the_problem_is_refused(tmp_path, no_planning):
    folder = tmp_path / "dives"
    folder.mkdir()
    prob = write(folder, GOOD)
    res = run(["plan", prob, "--out", folder, "--force", "--no-plots"])
    assert res.exit_code == 2 and "holds the problem" in res.output and prob.exists()
    res = run(["plan", folder, "--out", tmp_path, "--force", "--no-plots"])
    assert res.exit_code == 2 and prob.exists()


def test_a_file_in_place_of_the_parent_is_refused_before_planning(tmp_path, no_planning):
    (tmp_path / "afile").write_text("x")
    res = run(["plan", write(tmp_path, GOOD), "--out", tmp_path / "afile" / "sub" / "out", "--no-plots"])
    assert res.exit_code == 2 and "is a file, not a folder" in res.output, res.output
    assert (tmp_path / "afile").read_text() == "x" and litter(tmp_path) == []


def _in_child_as_nobody(fn):
    """Run ``fn()`` (returning (exit code, output)) in a forked child without root's rights."""
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # pragma: no cover - the child
        try:
            os.close(r)
            os.setgid(65534)
            os.setuid(65534)
            code, text = fn()
            os.write(w, json.dumps([code, text]).encode())
        finally:
            os._exit(0)
    os.close(w)
    import select

    with os.fdopen(r) as f:
        ready, _, _ = select.select([f], [], [], 120)
        if not ready:  # a child that hangs fails the test instead of hanging it
            os.kill(pid, signal.SIGKILL)
        data = f.read() if ready else "[null, \"the child hung\"]"
    os.waitpid(pid, 0)
    return json.loads(data)


def test_a_read_only_parent_is_refused_before_planning(no_planning):
    base = Path(tempfile.mkdtemp(prefix="acroplan-ro-"))
    try:
        base.chmod(0o755)
        ro = base / "ro"
        ro.mkdir()
        ro.chmod(0o555)

        problem = base / "pike-dive.toml"  # readable by the user nobody (the package's copy may not be)
        problem.write_text(examples.text("pike-dive"))
        problem.chmod(0o644)

        def attempt():
            res = run(["plan", str(problem), "--out", ro / "out" / "deeper", "--no-plots"])
            return res.exit_code, res.output

        if os.geteuid() == 0:
            # the child has nobody's rights, under which a package installed in a folder of root's
            # alone (a venv made by mktemp -d) cannot import the modules the command loads lazily;
            # the same command into a writable folder, here, imports them (and stops at planning,
            # refused by no_planning), so the child tests the folder's rights, not the install's
            warm = run(["plan", str(problem), "--out", base / "warm", "--no-plots"])
            assert "planning started before the output folder was checked" in repr(warm.exc_info[1])
            code, text = _in_child_as_nobody(attempt)
        else:
            code, text = attempt()
        assert code == 2 and f"--out: cannot write in {ro}" in text, text
        assert list(ro.iterdir()) == []
    finally:
        (base / "ro").chmod(0o755)
        import shutil

        shutil.rmtree(base)


def test_a_crash_between_the_two_renames_is_recovered(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "solution.json").write_text('{"old": true}\n')
    script = (
        "import os, sys\n"
        "from pathlib import Path\n"
        "import acroplan.io.output as o\n"
        "o._RENAMEAT2 = None\n"  # the fallback swap: two renames
        "real, n = os.rename, [0]\n"
        "def rename(a, b):\n"
        "    n[0] += 1\n"
        "    if n[0] == 2:\n"
        "        os._exit(9)\n"  # killed between the renames
        "    real(a, b)\n"
        "os.rename = rename\n"
        "with o.atomic_dir(Path(sys.argv[1]), True) as tmp:\n"
        "    (tmp / 'solution.json').write_text('{\"new\": true}')\n")
    p = subprocess.run([sys.executable, "-c", script, str(out)], env=ENV)
    assert p.returncode == 9
    assert not out.exists() and [n for n in litter(tmp_path) if n.endswith(".old")]  # the old output is aside
    # the next run puts it back before anything else (and, without --force, refuses to replace it)
    res = run(["plan", write(tmp_path, GOOD), "--out", out, "--no-plots"])
    assert res.exit_code == 2 and "exists and is not empty" in res.output, res.output
    assert (out / "solution.json").read_text() == '{"old": true}\n'
    assert litter(tmp_path) == []


def test_the_fallback_swap_leaves_no_litter(tmp_path, monkeypatch):
    monkeypatch.setattr(output, "_RENAMEAT2", None)
    out = tmp_path / "out"
    for _ in range(2):
        with output.atomic_dir(out, True) as tmp:
            (tmp / "a.txt").write_text("x")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"] and (out / "a.txt").exists()


def test_a_folder_being_written_is_refused_at_once(tmp_path, no_planning):
    out = tmp_path / "out"
    with output.OutputFolder(out, force=True):
        # refused, not queued: the folder stays held while this runs, so a run that waited for it
        # would never return, and one that went on would plan (no_planning fails on that)
        res = run(["plan", write(tmp_path, GOOD), "--out", out, "--force", "--no-plots"])
        assert res.exit_code == 2 and f"another acroplan run is writing to {out}" in res.output, res.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.toml"]


def _whole(out: Path, animated: bool) -> bool:
    names = {p.name for p in out.iterdir()}
    want = {"solution.json", "trajectory.csv"} | ({"motion.gif", "strobe.png"} if animated else set())
    return want <= names and strict_json(out / "solution.json")["status"] == "success"


def test_concurrent_writers_on_one_folder(tmp_path):
    prob = write(tmp_path, GOOD)
    out = tmp_path / "out"
    procs = [cli(["plan", prob, "--out", out, "--force", "--no-plots", "--animate"]) for _ in range(4)]
    results = [(p.wait(timeout=300), p.communicate()[1]) for p in procs]
    codes = sorted(c for c, _ in results)
    assert codes == [0, 2, 2, 2], results
    assert all("another acroplan run is writing to" in err for c, err in results if c == 2)
    assert _whole(out, animated=True)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "p.toml"]


def test_kill_9_while_writing_then_a_second_run_leaves_a_whole_output(tmp_path):
    prob = write(tmp_path, GOOD)
    out = tmp_path / "out"
    rng = random.Random(20240607)
    for _ in range(5):
        before = set(litter(tmp_path))
        p = cli(["plan", prob, "--out", out, "--force", "--no-plots", "--animate"])
        deadline = time.monotonic() + 120
        while not any(n.endswith(".tmp") and n not in before for n in litter(tmp_path)) and p.poll() is None:
            assert time.monotonic() < deadline
            time.sleep(0.005)
        time.sleep(rng.uniform(0.0, 1.0))  # somewhere in the writing
        p.send_signal(signal.SIGKILL)
        p.wait()
        assert not out.exists() or _whole(out, animated=True)  # never half written
    p = cli(["plan", prob, "--out", out, "--force", "--no-plots"])
    assert p.wait(timeout=300) == 0, p.communicate()
    assert _whole(out, animated=False) and not (out / "motion.gif").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "p.toml"]


# ------------------------------------------------------------------------------------------
# 3. the parser: hostile values are exit 2, naming the field
@pytest.mark.parametrize("old, new, field", [
    ('"-pi/2"', '"(-1)**0.5"', r"plan\.phi\[1\]: .*not a real number"),
    ('"-pi/2"', '"10**309"', r"plan\.phi\[1\]: .*not finite"),
    ('"-pi/2"', '"' + "9" * 4301 + '"', r"plan\.phi\[1\]: is a text of 4301 characters, more than 200"),
    ("leg_mass = 20.0", "leg_mass = " + "9" * 4301, r"p\.toml \(line \d+, key leg_mass\): holds a number too long"),
    ("theta = [0, 1.0]", "theta = " + "[" * 1000 + "]" * 1000, r"p\.toml: is nested too deeply"),
    ("theta = [0, 1.0]", "theta = [0, " + "[" * 300 + "1" + "]" * 300 + "]", r"plan\.theta\[1\]: must be a number"),
    ("[plan]", "[" + ".".join(["a"] * 1000) + "]\n[plan]", r"\[a\]: is not a known table"),
    ("leg_mass = 20.0", "leg_mass = " + "{a = " * 1000 + "1" + "}" * 1000, r"p\.toml: is nested too deeply"),
    ('"-pi/2"', '"' + "-" * 100000 + '1"', r"plan\.phi\[1\]: is a text of 100001 characters"),
    ('"-pi/2"', '"' + "-" * 150 + '1"', r"plan\.phi\[1\]: .*nested more than 32 levels"),
    ('"-pi/2"', '"2**2**2**2**2"', r"plan\.phi\[1\]: .*exponent of 65536, beyond 1024"),
    ('"-pi/2"', '"9**9**9"', r"plan\.phi\[1\]: .*exponent"),
    ('"-pi/2"', '"1/0"', r"plan\.phi\[1\]: .*divides by zero"),
    ('"-pi/2"', '"1j"', r"plan\.phi\[1\]: cannot read '1j'"),
    ("torso_length = 0.35", "torso_length = 1e155", r"robot\.torso_length: is 1e\+155: .* beyond 1e\+100"),
    ("leg_length = 0.45", "leg_length = 1e150", r"robot\.leg_length: "),
    ("torso_inertia = 1.8", "torso_inertia = 1e-200", r"robot\.torso_inertia: .*below 1e-150"),
    ("angular_momentum = 10.0", "angular_momentum = -1e200", r"robot\.angular_momentum: .*beyond 1e\+100"),
    ("times = [0, 1]", "times = [-1e308, 1]", r"plan\.times\[0\]: is -1e\+308: times beyond 1e\+12"),
    ("times = [0, 1]", "times = [0, " + "1" * 400 + "]", r"plan\.times\[1\]: .*beyond 1e\+12"),
    ("theta = [0, 1.0]", "theta = [0, 1e300]", r"plan\.theta\[1\]: .*angles beyond 1e\+06"),
    ('conditions = "free"', "conditions = " + "[" * 200 + "]" * 200, r"plan\.conditions: must be"),
    ('conditions = "free"', 'conditions = "free"\n[options]\nn_coefficients = ' + "9" * 100,
     r"options\.n_coefficients: must be a whole number from 1 to 1000, got a huge integer"),
    ('conditions = "free"', 'conditions = "free"\n[options]\ntol = 1e-300', r"options\.tol: is 1e-300"),
    ('conditions = "free"', 'conditions = "free"\n[limits]\nu_max = "1e200"', r"limits\.u_max: .*beyond 1e\+100"),
    ('conditions = "free"', '"a\\nb" = 1', r"plan\.'a\\nb': is not a known key"),
])
def test_hostile_values_are_exit_2_naming_the_field(tmp_path, old, new, field):
    text = GOOD.replace(old, new, 1)
    assert text != GOOD
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, text), "--out", out, "--no-plots"])
    assert res.exit_code == 2, (res.output, res.exception)
    assert res.output.startswith("acroplan: error: ") and len(res.output.strip().splitlines()) == 1
    assert len(res.output) < 600
    assert re.search(field, res.output), res.output
    assert not out.exists()


def test_hostile_lumped_and_nilpotent_values(tmp_path):
    lumped = ("[robot]\nM1 = 1e-200\nA1 = 0\nM2 = 0.2\nA2 = 0\nP0 = 1\n"
              "[plan]\ntimes=[0,1]\ntheta=[0,1]\nphi=[0,1]\n")
    res = run(["plan", write(tmp_path, lumped), "--out", tmp_path / "o"])
    assert res.exit_code == 2 and "robot.M1: is 1e-200, below 1e-150" in res.output, res.output
    nil = ('[robot]\nM1 = "4021/4920"\nA1 = "-39/82"\nM2 = 0.28\nA2 = "-39/164"\nP0 = 1.25\n'
           '[nilpotent]\nP = ["pi/4", 0, 0]\nQ = ["pi/4", 1e300, 1]\ndegree = 3\n')
    res = run(["nilpotent", write(tmp_path, nil, "n.toml"), "--out", tmp_path / "o"])
    assert res.exit_code == 2 and "nilpotent.Q[1]: is 1e+300: times beyond 1e+12" in res.output, res.output
    nil = nil.replace("1e300", "1")
    res = run(["nilpotent", write(tmp_path, nil.replace("degree = 3", "degree = " + "9" * 50), "n.toml"),
               "--out", tmp_path / "o"])
    assert res.exit_code == 2 and "nilpotent.degree: must be a whole number from 1 to 12" in res.output


def test_not_a_regular_file(tmp_path):
    import threading

    fifo = tmp_path / "p.toml"
    os.mkfifo(fifo)

    def unblock():  # a reader waiting on the FIFO is released after 5 s, so the test fails, not hangs
        while not done.wait(5):
            with open(fifo, "w"):
                pass

    done = threading.Event()
    thread = threading.Thread(target=unblock, daemon=True)
    thread.start()
    res = run(["plan", fifo, "--out", tmp_path / "o"])
    done.set()
    os.close(os.open(fifo, os.O_RDONLY | os.O_NONBLOCK))  # releases the writer, if it waits
    thread.join(10)
    assert res.exit_code == 2 and "is not a regular file" in res.output


# ------------------------------------------------------------------------------------------
# 4. no non-finite number in any JSON
def test_json_text_turns_non_finite_numbers_into_null_with_warnings():
    import numpy as np

    text = _json_text({"a": float("nan"), "b": [1.0, np.float64("inf")], "c": {"d": -np.inf}, "e": 2})
    doc = json.loads(text, parse_constant=lambda c: pytest.fail(c))
    assert doc["a"] is None and doc["b"] == [1.0, None] and doc["c"]["d"] is None and doc["e"] == 2
    assert doc["warnings"] == ["a: was nan, written as null", "b[1]: was inf, written as null",
                               "c.d: was -inf, written as null"]


def test_solution_json_never_holds_nan(tmp_path, monkeypatch):
    from acroplan.core.result import PlanResult

    to_dict = PlanResult.to_dict

    def with_nan(self):
        d = to_dict(self)
        d["diagnostics"]["max_final_error"] = float("nan")
        return d

    monkeypatch.setattr(PlanResult, "to_dict", with_nan)
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, INFEASIBLE), "--out", out, "--json"])
    assert res.exit_code == 3
    doc = strict_json(out / "solution.json")
    assert doc["diagnostics"]["max_final_error"] is None
    assert "diagnostics.max_final_error: was nan, written as null" in doc["warnings"]
    summary = json.loads(res.stdout, parse_constant=lambda c: pytest.fail(c))
    assert summary["max_final_error"] is None and summary["warnings"]


def test_a_huge_leg_is_refused_not_written_as_nan(tmp_path):
    out = tmp_path / "out"
    res = run(["plan", write(tmp_path, GOOD.replace("leg_length = 0.45", "leg_length = 1e150")), "--out", out])
    assert res.exit_code == 2 and "robot.leg_length: " in res.output and not out.exists()


# ------------------------------------------------------------------------------------------
# 5. one bad file in a batch folder
def test_one_bad_file_in_a_batch_folder_is_named_and_the_others_planned(tmp_path):
    folder = tmp_path / "many"
    folder.mkdir()
    write(folder, GOOD, "a.toml")
    write(folder, GOOD.replace("leg_mass = 20.0", "leg_mass = -1"), "bad.toml")
    write(folder, "[robot\n", "broken.toml")
    write(folder, "garbage", ".hidden.toml")  # skipped
    out = tmp_path / "out"
    res = run(["plan", folder, "--out", out, "--no-plots", "--json"])
    assert res.exit_code == 2, res.output  # the largest code present: success 0, invalid 2
    rows = {r["name"]: r for r in csv.DictReader(open(out / "summary.csv"))}
    assert sorted(rows) == ["a", "bad", "broken"]
    assert rows["a"]["status"] == "success" and (out / "a" / "trajectory.csv").exists()
    assert rows["bad"]["status"] == "invalid"
    assert rows["bad"]["message"].startswith(f"{folder / 'bad.toml'}: robot.leg_mass: must be > 0")
    assert rows["broken"]["status"] == "invalid" and "broken.toml: is not valid TOML" in rows["broken"]["message"]
    assert not (out / "bad").exists() and not (out / "broken").exists()
    summary = json.loads(res.stdout)
    assert summary["counts"] == {"invalid": 2, "success": 1}
    assert any("bad.toml: robot.leg_mass" in m for m in summary["invalid"])
    # an infeasible problem outranks an invalid file: the exit code is the largest present
    write(folder, INFEASIBLE, "c.toml")
    res = run(["plan", folder, "--out", out, "--force", "--no-plots"])
    assert res.exit_code == 3, res.output
    assert "bad.toml: robot.leg_mass" in res.stderr and "broken.toml: is not valid TOML" in res.stderr
    assert [r["status"] for r in csv.DictReader(open(out / "summary.csv"))] == ["success", "invalid", "invalid",
                                                                                   "infeasible"]


def test_batch_folder_with_only_bad_files(tmp_path):
    folder = tmp_path / "many"
    folder.mkdir()
    write(folder, "[robot\n", "x.toml")
    res = run(["plan", folder, "--out", tmp_path / "out", "--no-plots"])
    assert res.exit_code == 2 and "x.toml: is not valid TOML" in res.output
    assert [r["status"] for r in csv.DictReader(open(tmp_path / "out" / "summary.csv"))] == ["invalid"]


# ------------------------------------------------------------------------------------------
# fuzz: problem files built from the valid example with mutated values
hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, example, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


class Raw(str):
    """TOML text written as is (numbers Python itself cannot print, nan/inf spellings)."""


BASE = {
    "robot": {"torso_mass": 40.0, "leg_mass": 20.0, "torso_inertia": 1.8, "leg_inertia": 1.2,
              "torso_length": 0.35, "leg_length": 0.45, "angular_momentum": 10.0},
    "plan": {"times": [0, 1, 2], "theta": [0, 1.5, 4.2], "phi": ["-pi", "-pi/2", "-pi"], "conditions": "free"},
}


def toml_value(v) -> str:
    if isinstance(v, Raw):
        return str(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        return "nan" if v != v else "inf" if v == float("inf") else "-inf" if v == -float("inf") else repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)  # a TOML basic string
    if isinstance(v, list):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{json.dumps(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(v)


def toml_text(doc) -> str:
    return "".join(f"[{table}]\n" + "".join(f"{json.dumps(k)} = {toml_value(v)}\n" for k, v in keys.items())
                   for table, keys in doc.items())


SPECIAL = st.sampled_from([
    Raw("nan"), Raw("+nan"), Raw("-nan"), Raw("inf"), Raw("+inf"), Raw("-inf"), Raw("9" * 4301), Raw("1e309"),
    Raw("-1e308"), Raw("1e-320"), Raw("0"), Raw("-0.0"), Raw("1_000_000"), Raw("0x7fffffff"),
    "nan", "inf", "-Infinity", "NaN", "1e309", "(-1)**0.5", "2**2**2**2**2", "-" * 300 + "1", "1/0", "pi*1e308*10",
    "__import__('os')", "0.5*pi", "-pi", "1e155", "1e-155", "(" * 40 + "1" + ")" * 40, "", " ", "pi**pi**pi",
])
SCALAR = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-5, max_value=5),
    st.integers(min_value=-10**400, max_value=10**400),
    st.text(alphabet=st.characters(blacklist_categories=("Cs",)), max_size=30),
    st.booleans(),
    SPECIAL,
)
VALUE = st.recursive(SCALAR, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                      st.dictionaries(st.sampled_from("abxy"), inner, max_size=2)),
                     max_leaves=8)
NESTED = st.integers(min_value=1, max_value=1200).map(lambda n: Raw("[" * n + "]" * n))

#: values that keep the problem meaningful, so that a good share of the examples is planned
SENSIBLE = st.one_of(st.floats(min_value=-4, max_value=4),
                     st.sampled_from(["0.3*pi", "-pi/3", "2*pi/3", "1/3", "-0.25*pi"]),
                     st.floats(min_value=0.05, max_value=3).map(lambda v: Raw(repr(v))))
#: huge and tiny magnitudes, both signs
MAGNITUDE = st.tuples(st.sampled_from([1, -1]), st.floats(min_value=-320, max_value=308)).map(
    lambda t: Raw(repr(t[0] * 10.0 ** t[1])))
MUTATION = st.tuples(
    st.sampled_from([(t, k) for t, keys in BASE.items() for k in keys] + [("plan", "extra"), ("limits", "u_max"),
                                                                        ("limits", "phi_min"), ("options", "tol")]),
    st.sampled_from(["replace", "element", "element", "delete"]),
    st.integers(min_value=0, max_value=3),
    st.one_of(SENSIBLE, SENSIBLE, MAGNITUDE, VALUE, NESTED),
)


def _mutate(mutations):
    doc = json.loads(json.dumps(BASE))
    for (table, key), action, index, value in mutations:
        keys = doc.setdefault(table, {})
        if action == "delete":
            keys.pop(key, None)
        elif action == "element" and isinstance(keys.get(key), list) and keys[key]:
            keys[key][index % len(keys[key])] = value
        else:
            keys[key] = value
    return doc


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
@given(st.lists(MUTATION, min_size=1, max_size=3))
@example([(("plan", "theta"), "element", 1, Raw("[" * 1000 + "]" * 1000))])
@example([(("plan", "phi"), "element", 1, "(-1)**0.5")])
@example([(("plan", "phi"), "element", 2, "-" * 100000 + "1")])
@example([(("robot", "torso_length"), "replace", 0, Raw("1e155"))])
@example([(("plan", "times"), "element", 0, Raw("-1e308"))])
@example([(("robot", "leg_mass"), "replace", 0, Raw("9" * 4301))])
def test_fuzz_problem_files_through_the_cli(mutations):
    doc = _mutate(mutations)
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        prob = d / "p.toml"
        prob.write_text(toml_text(doc), encoding="utf-8")
        out = d / "out"
        res = CliRunner().invoke(main, ["plan", str(prob), "--out", str(out), "--no-plots", "--json"])
        assert res.exit_code in (0, 2, 3, 4), (res.output, res.exception, prob.read_text()[:2000])
        if res.exit_code == 2:
            assert re.match(r"acroplan: error: \S.*?: \S", res.stderr), res.stderr
            assert len(res.stderr.strip().splitlines()) == 1
        else:
            json.loads(res.stdout, parse_constant=lambda c: pytest.fail(f"{c} in --json output"))
        for f in out.rglob("*.json") if out.exists() else ():
            strict_json(f)
        assert sorted(p.name for p in d.iterdir()) in (["p.toml"], ["out", "p.toml"])


def test_output_folders_follow_the_umask(tmp_path):
    """Output folders were created with mode 0700 whatever the user's umask."""
    import os
    import stat

    old = os.umask(0o022)
    try:
        res = run(["plan", "--example", "pike-dive", "--out", str(tmp_path / "o"), "--no-plots", "--quiet"])
    finally:
        os.umask(old)
    assert res.exit_code == 0
    assert stat.S_IMODE((tmp_path / "o").stat().st_mode) == 0o755


def test_batch_json_gives_every_problem(tmp_path):
    import json

    many = tmp_path / "many"
    many.mkdir()
    (many / "a.toml").write_text(GOOD)
    (many / "b.toml").write_text(INFEASIBLE)
    res = run(["plan", str(many), "--out", str(tmp_path / "o"), "--no-plots", "--json"])
    doc = json.loads(res.output)
    assert [p["name"] for p in doc["problems"]] == ["a", "b"]
    assert [p["status"] for p in doc["problems"]] == ["success", "infeasible"]


# ------------------------------------------------------------------------------------------
# issue #25: hostile bodies, files confined, no exit 1 for bad input
pin = pytest.importorskip("pinocchio")

import acroplan  # noqa: E402
from acroplan.families.planar import three_rods, to_urdf as planar_urdf  # noqa: E402
from acroplan.families.spatial.urdf import to_urdf as spatial_urdf  # noqa: E402
from acroplan.families.spatial.zoo import falling_cat  # noqa: E402

#: the falling cat's plan (docs/spatial.md) with its body given by a URDF beside the file
CAT_PLAN = """
[plan]
times = [0.0, 0.5]
attitude = [[0.0, 0.984807753012208, 0.0, 0.17364817766693036],
            [0.984807753012208, 0.0, 0.17364817766693036, 0.0]]
bend = ["40*(pi/180)", "40*(pi/180)"]
side = [0.0, 0.0]
twist = [0.0, 0.0]
conditions = "free"
"""
CAT_URDF = spatial_urdf(falling_cat())
SPATIAL_FILE = '[body]\nurdf = "body.urdf"\nangular_momentum = [0.0, 0.0, 0.0]\n' + CAT_PLAN
RODS_URDF = planar_urdf(three_rods())
PLANAR_FILE = ('[body]\nurdf = "body.urdf"\nangular_momentum = 0.0\n[plan]\ntimes = [0.0, 3.0]\ntheta = [0.0, 0.4]\n'
               'q1 = [1.0, 1.0]\nq2 = [1.0, 1.0]\nconditions = "free"\n')


def chain_urdf(n: int, fixed: bool = False) -> str:
    """A URDF chain of ``n`` links (revolute joints about z, or fixed joints after the first two)."""
    inertial = ('<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.2"/>'
                '</inertial>')
    links = [f'<link name="l{i}">{inertial}</link>' for i in range(n)]
    joints = [f'<joint name="j{i}" type="{"fixed" if fixed and i > 2 else "continuous"}"><parent link="l{i - 1}"/>'
              f'<child link="l{i}"/><origin xyz="1 0 0"/><axis xyz="0 0 1"/></joint>' for i in range(1, n)]
    return '<?xml version="1.0"?>\n<robot name="chain">\n' + "\n".join(links + joints) + "\n</robot>\n"


def one_line_error(res, *words):
    """The run exited 2 with one line naming every word."""
    assert res.exit_code == 2, (res.output, res.exception)
    assert res.output.startswith("acroplan: error: ") and len(res.output.strip().splitlines()) == 1, res.output
    for w in words:
        assert w in res.output, res.output


@pytest.mark.parametrize("links, fixed, words", [
    (3831, False, "3830 moving joints (3831 moving links), more than 16 links"),
    (20000, True, "20000 links and 19999 joints, more than 1000"),
    (17, False, "16 moving joints (17 moving links), more than 16 links"),
])
def test_issue_25_a_long_chain_urdf_is_refused_before_pinocchio_reads_it(tmp_path, capfd, links, fixed, words):
    """A 3,831-link chain (1.4 MB) killed the process with SIGSEGV and no message: Pinocchio's URDF
    reader overflowed the stack before the 16-link check ran (planar, spatial and the API readers).
    A chain of fixed links overflows it too. Both are counted by a streaming pass first."""
    from acroplan.families.planar.urdf import read_link_table as planar_table
    from acroplan.families.spatial.urdf import read_urdf as spatial_body

    (tmp_path / "body.urdf").write_text(chain_urdf(links, fixed))
    for text in (PLANAR_FILE, SPATIAL_FILE):
        res = run(["plan", write(tmp_path, text), "--out", tmp_path / "out", "--no-plots"])
        one_line_error(res, "body.urdf: body.urdf has", words)
    for read in (planar_table, spatial_body):
        with pytest.raises(acroplan.InvalidInputError, match=re.escape(f"urdf: body.urdf has {words}")):
            read(tmp_path / "body.urdf")
    assert capfd.readouterr().err == ""  # nothing printed by Pinocchio or urdfdom
    assert not (tmp_path / "out").exists()


def test_issue_25_a_long_chain_urdf_in_a_sweep_is_refused_before_pinocchio_reads_it(tmp_path, capfd):
    """``acroplan sweep`` of a body with the 3,831-link chain was killed by SIGSEGV too (exit 139 on
    639160b): exit 2, one line, no store."""
    (tmp_path / "body.urdf").write_text(chain_urdf(3831))
    text = PLANAR_FILE + "[sweep]\nchunk_size = 5\n[sweep.grid]\nT = [1.0, 2.0]\n"
    res = run(["sweep", write(tmp_path, text), "--out", tmp_path / "o.zarr"])
    one_line_error(res, "body.urdf: body.urdf has 3830 moving joints (3831 moving links), more than 16 links")
    assert capfd.readouterr().err == ""
    assert not list(tmp_path.glob("*o.zarr*"))


@pytest.mark.parametrize("value, words", [
    ("nan", "has mass = nan, not a finite number"),
    ("inf", "has mass = inf, not a finite number"),
    ("heavy", "has a mass that is not a number"),
    ("1e300", "has mass 1e+300: masses beyond 1e+100"),
    ("1e-300", "has mass 1e-300: masses below 1e-150"),
    ("-2", "has mass -2 < 0"),
    ("0", "has mass 0 and an inertia that is not zero"),
])
def test_issue_25_a_urdf_mass_that_is_no_mass_is_refused_naming_the_link(tmp_path, capfd, value, words):
    """<mass value="nan"> (also inf, heavy) in a spatial URDF became a massless link and the plan
    succeeded; mass 0 with an inertia had its inertia zeroed; 1e300 was an OverflowError (planar) or
    a LinAlgError (spatial), 1e-300 accepted: exit 2 now, naming the link, for both families."""
    from acroplan.families.spatial.urdf import read_urdf

    cat = CAT_URDF.replace('<mass value="2"/>', f'<mass value="{value}"/>', 1)
    rods = RODS_URDF.replace('<mass value="1"/>', f'<mass value="{value}"/>', 1)
    assert cat != CAT_URDF and rods != RODS_URDF
    for urdf, text, link in ((cat, SPATIAL_FILE, "front"), (rods, PLANAR_FILE, "rod1")):
        (tmp_path / "body.urdf").write_text(urdf)
        res = run(["plan", write(tmp_path, text), "--out", tmp_path / "out", "--no-plots"])
        one_line_error(res, f"body.urdf: body.urdf: urdf link '{link}' {words}")
    (tmp_path / "body.urdf").write_text(cat)
    with pytest.raises(acroplan.InvalidInputError, match=re.escape(f"urdf link 'front': {words}")):
        read_urdf(tmp_path / "body.urdf")
    assert capfd.readouterr().err == ""
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("old, new, words", [
    ('ixx="0.0036"', 'ixx="nan"', "urdf link 'front' has inertia ixx = nan"),
    ('ixx="0.0036"', 'ixx="-0.0036"', "urdf link 'front' has an inertia with a negative principal moment"),
    ('ixx="0.0036"', 'ixx="1"', "urdf link 'front' has an inertia with principal moments [0.0122167, 0.0122167, 1.0] "
     "that break I1 + I2 >= I3"),
    ('xyz="0.125 0 0"', 'xyz="nan 0 0"', "urdf link 'front' has centre of mass (inertial origin xyz)[0] = nan"),
    ('xyz="0.125 0 0"', 'xyz="1e300 0 0"', "urdf link 'front' has centre of mass (inertial origin xyz)[0] = 1e+300"),
    ('<axis xyz="0 0 1"/>', '<axis xyz="0 0 0"/>', "urdf joint 'side' has the axis 0 0 0"),
    ('<robot name="spatial_body">', '<!DOCTYPE robot [<!ENTITY a "aaaa">]>\n<robot name="spatial_body">',
     "body.urdf declares XML entities"),
    ('<robot name="spatial_body">', '<robot name="spatial_body">' + "<a>" * 100 + "</a>" * 100,
     "body.urdf nests XML elements more than 64 deep"),
    ("</robot>", "", "body.urdf is not well-formed XML (no element found"),
    ('<limit lower="-1.0471975511965976"', '<limit lower="-1.0471975511965976x"', "urdf joint 'bend' has a limit "
     "lower that is not a number"),
])
def test_issue_25_every_number_of_a_spatial_urdf_is_checked(tmp_path, capfd, old, new, words):
    text = CAT_URDF.replace(old, new, 1)
    assert text != CAT_URDF
    (tmp_path / "body.urdf").write_text(text)
    res = run(["plan", write(tmp_path, SPATIAL_FILE), "--out", tmp_path / "out", "--no-plots"])
    one_line_error(res, "body.urdf: ", words)
    assert capfd.readouterr().err == ""


def test_issue_25_urdfdom_lines_become_acroplans_one_line(tmp_path, capfd):
    """urdfdom's own lines were printed to stderr before acroplan's message, and only they said what
    was wrong: they are captured (the C-level stderr) and become the message."""
    (tmp_path / "body.urdf").write_text(RODS_URDF.replace('type="continuous"', 'type="revolute"', 1))
    res = run(["plan", write(tmp_path, PLANAR_FILE), "--out", tmp_path / "out", "--no-plots"])
    one_line_error(res, "body.urdf: Pinocchio could not read body.urdf: Joint [q1] is of type REVOLUTE but it does "
                   "not specify limits")
    assert capfd.readouterr().err == ""


@pytest.mark.parametrize("value, words", [
    ('"' + "x" * 5000 + '"', "body.urdf: is a path of 5000 characters, more than 1024"),
    ('"a\\u0000b.urdf"', "body.urdf: holds a control character"),
    ('"sub"', "body.urdf: 'sub' is not a regular file"),
])
def test_issue_25_urdf_paths_the_system_cannot_open_are_exit_2(tmp_path, value, words):
    """urdf = "x" * 5000 was an OSError (File name too long): exit 1."""
    (tmp_path / "sub").mkdir()
    text = PLANAR_FILE.replace('"body.urdf"', value)
    res = run(["plan", write(tmp_path, text), "--out", tmp_path / "out", "--no-plots"])
    one_line_error(res, words)


def _cat_file(**options) -> str:
    """The bundled falling cat's problem file, its rates at the ends left free, with these options."""
    from acroplan.io import examples as bundled

    text = re.sub(r"\n(start|end)_rate = .*", "", bundled.text("falling-cat"))
    return text.replace("[options]\n", "[options]\n" + "".join(f"{k} = {v}\n" for k, v in options.items()))


@pytest.mark.parametrize("L, words", [
    ("1e3", "plan.times: segment 0 lasts 0.5 s, and the angular momentum L = (1000, 0, 0) turns the body by itself"),
    ("1e4", "L = (10000, 0, 0) turns the body by itself at 1.085e+06 rad/s, 5.425e+05 rad in that segment"),
    ("1e6", "L = (1e+06, 0, 0) turns the body by itself at 1.085e+08 rad/s, 5.425e+07 rad in that segment"),
])
def test_issue_25_a_fast_spatial_momentum_is_exit_2_through_the_cli(tmp_path, L, words):
    """A spatial angular_momentum of 1e3-1e6 exited 1 through the command line too (LinAlgError: SVD
    did not converge, after RuntimeWarnings of overflow; reproduced on 639160b): exit 2, one line."""
    text = _cat_file().replace("angular_momentum = [0.0, 0.0, 0.0]", f"angular_momentum = [{L}, 0.0, 0.0]")
    res = run(["plan", write(tmp_path, text), "--out", tmp_path / "out", "--no-plots"])
    one_line_error(res, words, "put waypoints closer in time")
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("options", [{"objective": '"energy"'}, {"tau_max": "50.0"}, {"objective": '"torque"'}])
def test_issue_25_spatial_n_coefficients_3_is_exit_2_through_the_cli(tmp_path, options):
    """n_coefficients = 3 with objective = "energy" or tau_max on a spatial body exited 1 through the
    command line (ValueError: matmul: ... size 6 is different from 3; reproduced on 639160b)."""
    res = run(["plan", write(tmp_path, _cat_file(n_coefficients=3, **options)), "--out", tmp_path / "out",
               "--no-plots"])
    one_line_error(res, "options.n_coefficients: 3 coefficients leave the spatial planner's shape loops one "
                   "coefficient short on segment 0", "give options.n_coefficients = 4 or more")


def test_issue_25_a_spatial_urdf_path_of_5000_characters_is_exit_2(tmp_path):
    """urdf = "x" * 5000 (an OSError: File name too long, exit 1) in a spatial body's file."""
    res = run(["plan", write(tmp_path, SPATIAL_FILE.replace('"body.urdf"', '"' + "x" * 5000 + '"')), "--out",
               tmp_path / "out", "--no-plots"])
    one_line_error(res, "body.urdf: is a path of 5000 characters, more than 1024")


def _outside_cases(tmp_path):
    """(the value of body.urdf, whether the file exists) for paths leading out of the folder."""
    work, other = tmp_path / "work", tmp_path / "other"
    work.mkdir()
    other.mkdir()
    (other / "body.urdf").write_text(RODS_URDF)
    (work / "link.urdf").symlink_to(other / "body.urdf")
    (work / "dangling.urdf").symlink_to(other / "missing.urdf")
    return work, other, [("../other/body.urdf", True), ("../other/missing.urdf", False),
                         (str(other / "body.urdf"), True), (str(other / "missing.urdf"), False),
                         ("link.urdf", True), ("dangling.urdf", False), ("/etc/passwd", True),
                         ("/proc/self/environ", True)]


def test_issue_25_files_outside_the_problem_folder_are_refused_alike_whether_they_exist(tmp_path):
    """body.urdf and body.yeadon read absolute paths, .. and symbolic links out of the folder
    (/etc/passwd, /proc/self/environ opened), and the messages told whether a path existed."""
    work, other, cases = _outside_cases(tmp_path)
    seen = set()
    for value, _ in cases:
        for key, text in (("urdf", PLANAR_FILE.replace('"body.urdf"', json.dumps(value))),
                          ("yeadon", '[body]\nyeadon = ' + json.dumps(value) + '\nangular_momentum = 60.0\n'
                                     '[plan]\ntimes = [0, 1]\ntheta = [0, 1]\nphi = [-3, -3]\n')):
            res = run(["plan", write(work, text), "--out", work / "out", "--no-plots"])
            one_line_error(res, f"body.{key}: ", "is outside the problem file's folder", "--allow-outside",
                           "[files] allow")
            seen.add(res.output.replace(value, "PATH"))
    assert len(seen) == 2  # one message per key, whatever the path and whether it exists
    assert not (work / "out").exists()


def test_issue_25_allow_outside_and_the_files_table_let_a_folder_be_read(tmp_path):
    work, other, _ = _outside_cases(tmp_path)
    two = chain_urdf(2)  # a two-link body is an acrobot: reach is exact and quick
    (other / "two.urdf").write_text(two)
    text = ('[body]\nurdf = "../other/two.urdf"\nangular_momentum = 1.0\n[plan]\ntimes = [0, 1]\ntheta = [0, 0.1]\n'
            'j1 = [0.5, 0.6]\n')
    p = write(work, text)
    one_line_error(run(["reach", p, "--out", work / "r"]), "is outside the problem file's folder")
    res = run(["reach", p, "--out", work / "r1", "--allow-outside", other])
    assert res.exit_code in (0, 3), res.output
    res = run(["reach", p, "--out", work / "r2", "--allow-outside", other / "two.urdf"])  # a file may be allowed
    assert res.exit_code in (0, 3), res.output
    res = run(["reach", write(work, '[files]\nallow = ["../other"]\n' + text, "q.toml"), "--out", work / "r3"])
    assert res.exit_code in (0, 3), res.output
    # a symbolic link inside the folder to a file inside it is read; the [files] table is checked
    (work / "two.urdf").write_text(two)
    (work / "alias.urdf").symlink_to(work / "two.urdf")
    res = run(["reach", write(work, text.replace("../other/two.urdf", "alias.urdf"), "a.toml"), "--out", work / "r4"])
    assert res.exit_code in (0, 3), res.output
    one_line_error(run(["reach", write(work, '[files]\nallow = "../other"\n' + text, "b.toml"), "--out", work / "r5"]),
                   "files.allow: must be a list of folders")
    one_line_error(run(["reach", write(work, '[files]\nalow = ["../other"]\n' + text, "c.toml"), "--out", work / "r6"]),
                   "files.alow: is not a known key", "did you mean 'allow'?")


def test_issue_25_a_foreign_file_named_as_measurements_is_never_quoted(tmp_path):
    """A yeadon path to a config file printed its api_token line in the error message."""
    (tmp_path / "config.txt").write_text("# my settings\napi_token: SECRET-123\nuser = root\n")
    text = ('[body]\nyeadon = "config.txt"\nangular_momentum = 60.0\n'
            '[plan]\ntimes = [0, 1]\ntheta = [0, 1]\nphi = [-3, -3]\n')
    res = run(["plan", write(tmp_path, text), "--out", tmp_path / "out"])
    one_line_error(res, "body.yeadon: yeadon cannot read 'config.txt': line 2 names no measurement of yeadon's")
    assert "SECRET" not in res.output and "api_token" not in res.output and "root" not in res.output


def _yeadon_with(tmp_path, extra: str = "", drop: str | None = None) -> Path:
    from acroplan.families.human.yeadon_body import sample_measurements

    lines = Path(sample_measurements("male1")).read_text().splitlines()
    if drop is not None:
        lines = [ln for ln in lines if not ln.startswith(drop)]
    (tmp_path / "me.txt").write_text("\n".join(lines) + "\n" + extra)
    return write(tmp_path, '[body]\nyeadon = "me.txt"\nangular_momentum = 60.0\n[plan]\ntimes = [0, 1]\n'
                           'theta = [0, 1]\nphi = [-3, -3]\n')


@pytest.mark.parametrize("extra, drop, words", [
    ("totalmass: nan\n", None, "(totalmass) is not a finite number"),
    ("totalmass: .nan\n", None, "(totalmass) is not a finite number"),
    ("totalmass: 0\n", None, "(totalmass) must be a finite number > 0, got 0"),
    ("totalmass: -70\n", None, "(totalmass) must be a finite number > 0, got -70"),
    ("totalmass: 1e9\n", None, "totalmass is 1e+09 kg, outside [1e-06, 1e+06] kg"),
    ("Ls1L: 5.0\n", None, "gives Ls1L again"),
    ("", "Ls1L", "1 of yeadon's 95 measurements are missing (the first: Ls1L)"),
    ("", "measurementconversionfactor", "measurementconversionfactor is missing"),
    ("a: [1, 2]\n", None, "is not 'name: number'"),
])
def test_issue_25_yeadon_measurements_are_checked(tmp_path, extra, drop, words):
    """A yeadon totalmass of NaN, 0 or negative was ignored (yeadon scales only by a mass > 0)."""
    pytest.importorskip("yeadon")
    res = run(["plan", _yeadon_with(tmp_path, extra, drop), "--out", tmp_path / "out"])
    one_line_error(res, "body.yeadon: ", words)


def test_issue_25_a_large_measurement_file_is_refused_before_it_is_read(tmp_path, monkeypatch):
    """An 8.9 MB measurement file took 79 s and 1.25 GB to be refused (yeadon's YAML reader): a
    measurement file is a few kB, so one over 100 kB is refused by its size, and one under it is
    read by a line reader that never builds more than one dict of numbers."""
    pytest.importorskip("yeadon")
    import builtins

    p = _yeadon_with(tmp_path, "# " + "x" * 8_900_000 + "\n")
    opened = []
    real_open = builtins.open
    monkeypatch.setattr(builtins, "open", lambda f, *a, **k: (opened.append(str(f)), real_open(f, *a, **k))[1])
    res = run(["plan", p, "--out", tmp_path / "out"])
    monkeypatch.undo()
    one_line_error(res, "body.yeadon: me.txt is larger than 100 kB")
    assert not any(f.endswith("me.txt") for f in opened)  # refused by its size, never opened
    # under the size limit: 2,000 lines at most, read once
    p = _yeadon_with(tmp_path, "# a comment\n" * 3000)
    one_line_error(run(["plan", p, "--out", tmp_path / "out"]), "lines, more than 2000")


def test_issue_25_matplotlib_writes_nothing_under_home_on_a_first_run(tmp_path):
    """matplotlib's cache was written under the home folder on a first run: the command line points
    MPLCONFIGDIR at acroplan-matplotlib-<uid> in the temporary folder when it is not set."""
    home, tmp = tmp_path / "home", tmp_path / "tmp"
    home.mkdir()
    tmp.mkdir()
    env = {k: v for k, v in ENV.items() if not k.startswith(("MPL", "XDG_"))}
    env.update(HOME=str(home), TMPDIR=str(tmp))
    p = subprocess.run([sys.executable, "-m", "acroplan", "plan", "--example", "pike-dive", "--out",
                        str(tmp_path / "out"), "--quiet"], env=env, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    assert not any("matplotlib" in str(f.relative_to(home)) for f in home.rglob("*"))  # heyoka: ~/.cache/heyoka
    mine = tmp / f"acroplan-matplotlib-{os.getuid()}"
    assert mine.is_dir() and (mine.stat().st_mode & 0o777) == 0o700 and any(mine.iterdir())


# ------------------------------------------------------------------------------------------
# issue #25: a bounded fuzz of every body kind through the command line (mutated URDFs, link
# tables, yeadon measurement files); benchmarks/fuzz.py runs the same generators for thousands
#: values written into a URDF attribute
URDF_VALUES = st.sampled_from(["nan", "inf", "-inf", "heavy", "", " ", "1e300", "1e-300", "-1", "0", "1e400",
                               "0 0", "1 2 3 4", "0x10", "1_000", "+.5", "-0.0", "1e-160", "2", "0.5", "nan 0 0",
                               "0 0 0", "0 0 1", "1 0 0", "1e100 0 0", "&amp;", "revolute", "fixed", "prismatic"])
URDF_ATTRIBUTE = re.compile(r'(\w+)="([^"]*)"')


@st.composite
def urdf_texts(draw, base: str) -> str:
    """``base`` with a few attribute values replaced and elements dropped, doubled or cut."""
    text = base
    for _ in range(draw(st.integers(min_value=1, max_value=3))):
        kind = draw(st.sampled_from(["value", "value", "value", "drop", "double", "cut", "nest", "entity"]))
        spots = list(URDF_ATTRIBUTE.finditer(text))
        lines = text.splitlines(keepends=True)
        if kind == "value" and spots:
            m = spots[draw(st.integers(min_value=0, max_value=len(spots) - 1))]
            value = draw(st.one_of(URDF_VALUES, st.text(alphabet="0123456789.eE-+ naif", max_size=12)))
            text = text[:m.start(2)] + value + text[m.end(2):]
        elif kind == "drop" and len(lines) > 2:
            i = draw(st.integers(min_value=1, max_value=len(lines) - 2))
            text = "".join(lines[:i] + lines[i + 1:])
        elif kind == "double" and len(lines) > 2:
            i = draw(st.integers(min_value=1, max_value=len(lines) - 2))
            text = "".join(lines[:i + 1] + lines[i:])
        elif kind == "cut":
            text = text[:draw(st.integers(min_value=0, max_value=len(text)))]
        elif kind == "nest":
            n = draw(st.integers(min_value=1, max_value=200))
            text = text.replace("</robot>", "<a>" * n + "</a>" * n + "</robot>")
        elif kind == "entity":
            text = text.replace("<robot", '<!DOCTYPE robot [<!ENTITY e "x">]>\n<robot', 1)
    return text


def _table_text(doc) -> str:
    """A problem file of ``doc`` (tables, and ``[[body.link]]`` arrays of tables)."""
    out = []
    for table, keys in doc.items():
        arrays = {k: v for k, v in keys.items() if isinstance(v, list) and v and all(isinstance(x, dict) for x in v)}
        out.append(f"[{table}]\n" + "".join(f"{json.dumps(k)} = {toml_value(v)}\n" for k, v in keys.items()
                                            if k not in arrays))
        for k, items in arrays.items():
            for item in items:
                out.append(f"[[{table}.{k}]]\n" + "".join(f"{json.dumps(a)} = {toml_value(b)}\n" for a, b in item.items()))
    return "".join(out)


PLANAR_TABLE = {
    "body": {"angular_momentum": 0.0, "link": [
        {"name": "rod1", "mass": 1.0, "inertia": "1/12", "com": [0.5, 0.0]},
        {"name": "rod2", "parent": "rod1", "joint": [1.0, 0.0], "joint_name": "q1", "mass": 1.0, "inertia": "1/12",
         "com": [0.5, 0.0], "velocity": 2.0},
        {"name": "rod3", "parent": "rod2", "joint": [1.0, 0.0], "joint_name": "q2", "mass": 1.0, "inertia": "1/12",
         "com": [0.5, 0.0], "velocity": 2.0}]},
    "plan": {"times": [0.0, 3.0], "theta": [0.0, 0.4], "q1": [1.0, 1.0], "q2": [1.0, 1.0], "conditions": "free"},
}
SPATIAL_TABLE = {
    "body": {"angular_momentum": [0.0, 0.0, 0.0], "link": [
        {"name": "front", "mass": 2.0, "inertia": [0.0036, 0.0122, 0.0122], "com": [0.125, 0.0, 0.0]},
        {"name": "waist", "parent": "front", "joint_name": "bend", "axis": [0.0, -1.0, 0.0], "mass": 0.0,
         "inertia": [0.0, 0.0, 0.0], "lower": -1.0, "upper": 1.7},
        {"name": "rear", "parent": "waist", "joint_name": "twist", "axis": [1.0, 0.0, 0.0], "mass": 2.0,
         "inertia": [0.0036, 0.0122, 0.0122], "com": [-0.125, 0.0, 0.0]}]},
    "plan": {"times": [0.0, 0.5], "attitude": [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.0]], "bend": [0.7, 0.7],
             "twist": [0.0, 0.0], "conditions": "free"},
}
TABLE_VALUE = st.one_of(SPECIAL, MAGNITUDE, SENSIBLE, VALUE,
                        st.lists(st.one_of(SENSIBLE, MAGNITUDE, SPECIAL), min_size=0, max_size=4),
                        st.lists(st.lists(st.one_of(SENSIBLE, MAGNITUDE), min_size=3, max_size=3), min_size=3,
                                 max_size=3))


@st.composite
def link_table_texts(draw, base: dict) -> str:
    doc = json.loads(json.dumps(base))
    links = doc["body"]["link"]
    for _ in range(draw(st.integers(min_value=1, max_value=3))):
        what = draw(st.sampled_from(["link", "link", "link", "momentum", "drop", "double"]))
        if what == "momentum":
            doc["body"]["angular_momentum"] = draw(TABLE_VALUE)
            continue
        if not links:
            break
        i = draw(st.integers(min_value=0, max_value=len(links) - 1))
        if what == "drop":
            links.pop(i)
        elif what == "double":
            links.append(dict(links[i]))
        else:
            key = draw(st.sampled_from(sorted(set(links[i]) | {"mass", "inertia", "com", "joint", "axis", "rotation",
                                                            "lower", "upper", "velocity", "parent", "other"})))
            links[i][key] = draw(TABLE_VALUE)
    return _table_text(doc)


YEADON_VALUES = st.sampled_from(["nan", ".nan", "inf", ".inf", "-1", "0", "1e9", "1e-9", "heavy", "", "[1, 2]",
                                 "{a: 1}", "&a", "*a", "1e300", "0.01", "5", "'5'", "5 # note", "!!float 5"])


@st.composite
def yeadon_texts(draw) -> str:
    from acroplan.families.human.yeadon_body import sample_measurements

    lines = Path(sample_measurements("male1")).read_text().splitlines()
    for _ in range(draw(st.integers(min_value=1, max_value=4))):
        what = draw(st.sampled_from(["value", "value", "drop", "double", "garbage", "totalmass"]))
        i = draw(st.integers(min_value=0, max_value=len(lines) - 1))
        if what == "value" and ":" in lines[i] and not lines[i].startswith("#"):
            lines[i] = lines[i].split(":")[0] + ": " + draw(YEADON_VALUES)
        elif what == "drop":
            lines.pop(i)
        elif what == "double":
            lines.insert(i, lines[i])
        elif what == "garbage":
            lines.insert(i, draw(st.text(max_size=40)).replace("\r", "").replace("\n", ""))
        else:
            lines.append("totalmass: " + draw(YEADON_VALUES))
    return "\n".join(lines) + "\n"


YEADON_PROBLEM = ('[body]\nyeadon = "body.txt"\nangular_momentum = 60.0\nposition = "pike"\n[plan]\ntimes = [0, 1.5]\n'
                  'theta = ["-0.5*pi", "-0.5*pi + 2*pi"]\nphi = ["-pi", "-pi"]\n')
BODY_KINDS = ("planar-urdf", "spatial-urdf", "planar-table", "spatial-table", "yeadon")


@st.composite
def body_files(draw) -> tuple[str, dict]:
    """``(kind, {file name: text})``: a problem file ``p.toml`` and the file its body names."""
    kind = draw(st.sampled_from(BODY_KINDS))
    if kind == "planar-urdf":
        return kind, {"p.toml": PLANAR_FILE, "body.urdf": draw(urdf_texts(RODS_URDF))}
    if kind == "spatial-urdf":
        return kind, {"p.toml": SPATIAL_FILE, "body.urdf": draw(urdf_texts(CAT_URDF))}
    if kind == "planar-table":
        return kind, {"p.toml": draw(link_table_texts(PLANAR_TABLE))}
    if kind == "spatial-table":
        return kind, {"p.toml": draw(link_table_texts(SPATIAL_TABLE))}
    return kind, {"p.toml": YEADON_PROBLEM, "body.txt": draw(yeadon_texts())}


def check_body_run(res, folder: Path, codes=(0, 2, 3, 4)) -> None:
    """What every run of a fuzzed body file must do: a known exit code, an exit 2 of one line that
    names a field, JSON without NaN, nothing written outside OUT."""
    assert res.exit_code in codes, (res.exit_code, res.output[-2000:], res.exception)
    if res.exit_code == 2:
        assert re.match(r"acroplan: error: \S.*?: \S", res.stderr), res.stderr
        assert len(res.stderr.strip().splitlines()) == 1, res.stderr
    for f in (folder / "out").rglob("*.json") if (folder / "out").exists() else ():
        strict_json(f)


@settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
@given(body_files())
@example(("planar-urdf", {"p.toml": PLANAR_FILE, "body.urdf": chain_urdf(3831)}))
@example(("spatial-urdf", {"p.toml": SPATIAL_FILE, "body.urdf": CAT_URDF.replace('value="2"', 'value="nan"', 1)}))
def test_issue_25_fuzz_every_body_kind_through_the_cli(case):
    """Mutated URDFs (planar and spatial), link tables (planar and spatial) and yeadon measurement
    files through ``acroplan reach`` (which reads the body as ``plan`` does, and plans nothing)."""
    if case[0] == "yeadon":
        pytest.importorskip("yeadon")
    _, files = case
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        for name, text in files.items():
            (d / name).write_text(text, encoding="utf-8")
        res = CliRunner().invoke(main, ["reach", str(d / "p.toml"), "--out", str(d / "out"), "--json"])
        check_body_run(res, d, codes=(0, 2, 3))
        assert sorted(p.name for p in d.iterdir()) in (sorted(files), sorted([*files, "out"]))
