"""Progress on long work (issue #24): what each stage reports, counted (never timed), where lines
appear (a terminal, a notebook) and where they do not (a file, a pipe, the workers of a batch)."""

import io
import json
import subprocess
import sys
import time

import numpy as np
import pytest

import acroplan
from acroplan.core import progress as P
from acroplan.core.progress import Progress


def _updates(prog, name):
    """The ``done`` values the stage ``name`` reported, in order (its opening at 0 left out)."""
    return [done for stage, done, _ in prog.events if stage == name and done]


def test_a_plan_reports_each_interval_and_each_checked_segment(pike_robot):
    problem = acroplan.examples.load("pike-dive")
    prog = Progress(enabled=False, record=True)
    res = problem.solve(progress=prog)
    assert res.success
    assert _updates(prog, "segments") == [1, 2, 3, 4, 5]
    assert _updates(prog, "independent check") == [1, 2, 3, 4, 5]
    assert _updates(prog, "path deformation")[-1] == 100  # each interval's continuation, to tau = 1
    with prog.active():
        res.effort() if res.has_torques else None
        figs = res.plot()
    assert _updates(prog, "figures") == list(range(1, len(figs) + 2))  # the samples, then each figure
    figs.close()


def test_the_old_callback_is_called_after_each_interval(pike_robot):
    calls = []
    problem = acroplan.examples.load("pike-dive-limited")
    assert problem.solve(progress=lambda done, total: calls.append((done, total))).success
    assert calls == [(k, 5) for k in range(1, 6)]


def test_a_batch_reports_its_problems_and_nothing_of_each():
    robot = acroplan.examples.robot("pike-dive")
    jobs = [dict(system=robot, times=[0, 1], theta=[0, 1.0 + 0.1 * k], phi=[-np.pi, -np.pi / 2], conditions="free")
            for k in range(6)]
    prog = Progress(enabled=False, record=True)
    out = acroplan.plan_many(jobs, executor="serial", progress=prog)
    assert all(r.success for r in out)
    assert _updates(prog, "problems") == [1, 2, 3, 4, 5, 6]
    assert {stage for stage, _, _ in prog.events} == {"problems"}


def test_the_optimal_ladder_reports_its_basis_sizes():
    robot = acroplan.examples.robot("pike-dive")
    prog = Progress(enabled=False, record=True)
    res = acroplan.plan(robot, times=[0, 1.5], theta=[0, 2.0], phi=[-np.pi, -np.pi], conditions="free",
                        objective="energy", progress=prog)
    assert res.success
    sizes = [(done, total) for stage, done, total in prog.events if stage == "optimal: basis sizes"]
    assert sizes and all(total == 6 for _, total in sizes)
    assert [d for d, _ in sizes] == sorted(d for d, _ in sizes)  # up the ladder


def test_a_one_step_stage_shows_its_time_not_a_bar_at_zero_of_one():
    prog = Progress(enabled=False)
    assert P._bar_total(prog.stage("segments", 1)) is None
    assert P._bar_total(prog.stage("frames", 40)) == 40


def test_a_shown_line_is_redrawn_while_one_long_step_runs():
    """The stage is updated once; its line is redrawn by the refreshing thread (counted, not timed:
    the test waits for three redraws, whatever the machine's load)."""
    out = io.StringIO()
    prog = Progress(enabled=True, file=out, delay=0.0)
    with prog.active(), prog.scope("compiling", unit="step") as st:
        st.update()
        deadline = time.monotonic() + 120
        while prog.draws < 4 and time.monotonic() < deadline:
            time.sleep(0.05)
    prog.close()
    assert prog.draws >= 4
    assert out.getvalue().count("\r") >= 4 and "compiling" in out.getvalue()


def test_nothing_is_printed_when_stderr_is_not_a_terminal(tmp_path):
    code = ("import acroplan\n"
            "r = acroplan.examples.load('pike-dive').solve()\n"
            "r.effort() if r.has_torques else None\n"
            "r.plot()\n"
            "print(r.status)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=tmp_path)
    assert done.stdout.strip() == "success" and done.stderr == ""


def test_the_command_line_shows_nothing_in_a_pipe(tmp_path):
    done = subprocess.run([sys.executable, "-m", "acroplan", "plan", "--example", "pike-dive-limited", "--out",
                           str(tmp_path / "o"), "--no-plots"], capture_output=True, text=True)
    assert done.returncode == 0 and done.stderr == ""


def test_auto_is_off_in_a_pipe_and_on_in_a_notebook(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert P.auto() is False
    monkeypatch.setattr(P, "in_notebook", lambda: True)
    assert P.auto() is True


def test_progress_in_a_notebook_draws_widgets():
    """In a Jupyter kernel (nbclient), a stage is a tqdm.auto widget that updates."""
    nbclient = pytest.importorskip("nbclient")
    nbformat = pytest.importorskip("nbformat")
    pytest.importorskip("ipykernel")
    pytest.importorskip("ipywidgets")
    code = ("from acroplan.core.progress import stage, auto\n"
            "import time\n"
            "print(auto())\n"
            "with stage('work', 6) as st:\n"
            "    for _ in range(6):\n"
            "        time.sleep(0.15); st.update()\n")
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code)])
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3").execute()
    outs = nb.cells[0].outputs
    assert outs[0]["text"].strip() == "True"
    widgets = [o for o in outs if o.get("output_type") == "display_data"
               and "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert len(widgets) == 1  # one line (a widget) for the stage
    text = json.dumps([o.get("data", {}).get("text/plain", "") for o in outs])
    assert "work" in text
