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

from acroplan.io import output
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

        def attempt():
            res = run(["plan", "--example", "pike-dive", "--out", ro / "out" / "deeper", "--no-plots"])
            return res.exit_code, res.output

        code, text = _in_child_as_nobody(attempt) if os.geteuid() == 0 else attempt()
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
