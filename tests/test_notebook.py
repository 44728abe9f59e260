"""What a notebook user meets: shapes, reprs, plots that leave the backend alone, tables, files
read back."""

import json
import subprocess
import sys

import numpy as np
import pytest

import acroplan

PI = np.pi


@pytest.fixture(scope="module")
def limited():
    p = acroplan.examples.load("pike-dive-limited")
    return p.solve()


def test_scalar_time_gives_a_flat_input(pike_result):
    seg = pike_result.segments[0]
    assert seg.input(0.3).shape == (1,) and seg.input([0.3]).shape == (1, 1)
    assert seg.input(0.3)[0] == seg.input([0.3])[0, 0]
    assert seg.input(np.linspace(seg.t0, seg.t1, 7)).shape == (1, 7)


def test_reprs_are_concise_and_html_is_a_table(pike_result):
    r = repr(pike_result)
    assert len(r) < 250 and "status='success'" in r and "segments=5" in r
    assert len(repr(pike_result.segments[0])) < 200
    html = pike_result._repr_html_()
    assert html.count("<tr>") == 1 + len(pike_result.segments) and "success" in html


def test_plan_level_extremes_are_always_present(pike_result, limited):
    assert pike_result.max_abs_u == max(s.max_abs_u for s in pike_result.segments)
    lo, hi = limited.state_ranges["phi"]
    assert -2 * PI - 1e-9 <= lo < hi <= -PI + 1e-9
    d = limited.to_dict()
    assert d["max_abs_u"] == limited.max_abs_u and d["state_ranges"]["phi"] == [lo, hi]


def test_plot_into_an_axes_and_the_backend_is_left_alone(pike_result):
    import matplotlib
    import matplotlib.pyplot as plt

    before = matplotlib.get_backend()
    fig, ax = plt.subplots()
    assert pike_result.plot(ax=ax) == {"states": fig} and len(ax.lines) >= 2
    assert pike_result.plot("input", ax=ax)["input"] is fig
    figs = pike_result.plot()
    assert isinstance(figs, acroplan.core.plotting.Figures) and set(figs) >= {"input", "states"}
    assert list(pike_result.plot("states")) == ["states"]  # one figure: the same type
    assert matplotlib.get_backend() == before
    plt.close("all")


def test_library_code_never_switches_the_backend(tmp_path):
    """result.plot() switched to Agg when DISPLAY was unset; animate() always did."""
    code = ("import matplotlib; matplotlib.use('svg')\n"
            "import acroplan, numpy as np\n"
            "from acroplan.families.acrobot.drawing import animate, geometry_of\n"
            "r = acroplan.examples.load('pike-dive').solve(verify=False)\n"
            "r.plot(); s = r.sample(20)\n"
            f"animate(s.t, s.theta, s.phi, s.u, geometry_of(r.to_dict()['system']), r'{tmp_path / 'a.gif'}',"
            " max_frames=10)\n"
            "print(matplotlib.get_backend())\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "svg" and (tmp_path / "a.gif").stat().st_size > 1000


def test_to_pandas(pike_result):
    df = pike_result.to_pandas(per_segment=11)
    assert list(df.columns) == ["t", "theta", "phi", "u"] and len(df) == 5 * 10 + 1
    assert df["t"].iloc[-1] == pike_result.times[-1]


def test_a_result_file_reads_back_into_the_same_result(tmp_path, limited):
    path = tmp_path / "solution.json"
    path.write_text(limited.to_json())
    back = acroplan.load_result(path)
    assert back.status == limited.status and back.limits == limited.limits
    assert back.to_dict()["segments"] == limited.to_dict()["segments"]
    t = np.linspace(limited.times[0], limited.times[-1], 33)
    a, b = limited.evaluate(t), back.evaluate(t)
    assert np.array_equal(a.states, b.states) and np.array_equal(a.inputs, b.inputs)
    assert json.loads(back.to_json()) == json.loads(limited.to_json())
    with pytest.raises(acroplan.InvalidInputError, match="solution.json: is not a plan result"):
        path.write_text('{"status": "success"}')
        acroplan.load_result(path)


def test_systems_round_trip_through_their_dicts():
    for system in (acroplan.examples.robot("pike-dive"), acroplan.Unicycle(), acroplan.ChainedForm(5),
                   acroplan.Acrobot(M1=2.0, A1=-0.5, M2=0.5, A2=-0.25, P0=1.0)):
        again = acroplan.ControlAffineSystem.from_dict(system.to_dict())
        assert again == system and again.structure_key == system.structure_key


def test_every_export_says_how_exact_it_is(pike_robot, pike_result):
    """The power-basis export missed waypoints by up to 4e-7 at 14 coefficients, without a word."""
    d = pike_result.to_dict()
    assert d["basis"]["exact"].startswith("basis_coefficients") and "power_form_error" in d["basis"]["export"]
    for seg, sd in zip(pike_result.segments, d["segments"]):
        assert sd["power_form_error"] == seg.power_form_error < 1e-9 * max(1.0, seg.max_abs_u)
    r = acroplan.plan(pike_robot, times=[0, 2], theta=[-0.5 * PI, 0.9 * PI], phi=[-PI, -2 * PI],
                      n_coefficients=14)
    seg = r.segments[0]
    t = np.linspace(seg.t0, seg.t1, 257)
    power = np.polynomial.polynomial.polyval(t - seg.t0, seg.coefficients[0])
    assert seg.power_form_error == pytest.approx(np.max(np.abs(power - seg.input(t)[0])), rel=1e-12)


def test_a_record_names_the_family_class_before_a_users_class_of_the_same_name():
    """A notebook (or a docs page) may define its own ``Unicycle`` before the family's class is
    first imported (the family packages load lazily): a record of ``type = "Unicycle"`` is still
    the registered family's class."""
    import sympy as sp

    class Unicycle(acroplan.ControlAffineSystem):  # the user's, of the same name
        state_names = ("x", "y", "psi")
        input_names = ("v", "omega")
        param_names = ()

        @classmethod
        def symbolic_fields(cls, x, p):
            return sp.zeros(3, 1), sp.eye(3)[:, :2]

    system = acroplan.Unicycle()
    again = acroplan.ControlAffineSystem.from_dict(system.to_dict())
    assert type(again) is type(system) and again == system and type(again) is not Unicycle


def test_a_long_plan_in_a_notebook_shows_its_stages_and_keeps_them_moving(tmp_path):
    """Issue #24: in a notebook, ``plan()`` of a multi-second job (a cold ``three-rods-turn``: its
    integrators compiled into an empty cache, seconds in one step) shows its stages as ``tqdm.auto``
    widgets, and a shown line's text changes while one long step runs (a widget is redrawn only
    when its text changes: whole seconds of elapsed time left it unchanged for up to 1.25 s).
    Counted, not timed: the widget texts the kernel sent, against the seconds the plan took."""
    nbclient = pytest.importorskip("nbclient")
    nbformat = pytest.importorskip("nbformat")
    pytest.importorskip("ipykernel")
    pytest.importorskip("ipywidgets")
    code = (f"import os, time\nos.environ['ACROPLAN_HEYOKA_CACHE'] = {str(tmp_path / 'cache')!r}\n"
            "import acroplan\n"
            "p = acroplan.examples.load('three-rods-turn')\n"
            "t0 = time.monotonic()\n"
            "r = acroplan.plan(p.system, **p.plan_kwargs())\n"
            "print(r.status, time.monotonic() - t0)\n")
    texts: list[str] = []

    class Client(nbclient.NotebookClient):
        def handle_comm_msg(self, outs, msg, cell_index):
            state = msg["content"].get("data", {}).get("state", {})
            if isinstance(state.get("value"), str):
                texts.append(state["value"])
            return super().handle_comm_msg(outs, msg, cell_index)

    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code)])
    Client(nb, timeout=600, kernel_name="python3").execute(cwd=str(tmp_path))
    outs = nb.cells[0].outputs
    printed = [o["text"] for o in outs if o.get("output_type") == "stream" and o.get("name") == "stdout"]
    status, seconds = printed[-1].split()
    assert status == "success" and float(seconds) >= 1.0  # (a cold compilation: seconds everywhere)
    widgets = [o for o in outs if o.get("output_type") == "display_data"
               and "application/vnd.jupyter.widget-view+json" in o.get("data", {})]
    assert widgets, "no progress widget in the cell's outputs"
    assert any(t.startswith("compiling") for t in texts), sorted(set(texts))
    # the compilation's line moved while it ran: its texts differ (elapsed tenths, then its end)
    compiling = [t for t in texts if "compiling" in t or "integrator" in t]
    assert len(set(compiling)) >= 3, compiling
    # and the cell's lines changed at least once a second on average over the plan
    assert len(set(texts)) >= float(seconds), (len(set(texts)), seconds)
