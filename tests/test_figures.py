"""Figures a paper can use (issue #24): the states figure's attitude as Yeadon's angles (equal to
rotations.py's conversion of the quaternion), a unit on every axis, each legend item once; the
3-D human drawn from Yeadon's solids (their volume is yeadon's, and they survive solution.json);
the spatial strobe's tick labels clear of the next panel; the planar diver's head, key and scale
bar."""

import json

import numpy as np
import pytest

import acroplan

matplotlib = pytest.importorskip("matplotlib")
matplotlib.use("Agg")


@pytest.fixture(scope="module")
def cat():
    return acroplan.examples.load("falling-cat").solve(verify=False)


def _axes_of(fig):
    return [ax for ax in fig.axes if ax.get_visible()]


def test_the_spatial_states_figure_shows_yeadons_angles_of_the_quaternion(cat):
    from acroplan.core import plotting
    from acroplan.families.spatial import rotations as rot

    samples = cat.sample(effort=False)
    fig = plotting.plot_states(cat, samples)
    axes = _axes_of(fig)
    assert [ax.get_ylabel() for ax in axes[:3]] == [f"attitude: {n} [rad]" for n in rot.EULER_NAMES]
    assert not any("qw" in ax.get_ylabel() or "qx" in ax.get_ylabel() for ax in axes)
    E = np.unwrap(np.radians(rot.to_euler(samples.states[:4], "yeadon")), axis=1)
    for k in range(3):
        t, y = axes[k].lines[0].get_data()
        assert np.array_equal(t, samples.t)
        assert np.allclose(y, E[k], atol=1e-12)
    # the joints follow, in rad; the waypoints (white dots) sit on their curves
    assert [ax.get_ylabel() for ax in axes[3:]] == [f"{n} [rad]" for n in cat.system.links.joint_names]
    for ax in axes:
        t, y = ax.lines[0].get_data()
        tw, yw = ax.lines[1].get_data()
        assert np.allclose(np.interp(tw, t, y), yw, atol=1e-6)
    # degrees on request
    fig_deg = plotting.plot_states(cat, samples, degrees=True)
    t, y = _axes_of(fig_deg)[0].lines[0].get_data()
    assert np.allclose(y, np.degrees(E[0])) and _axes_of(fig_deg)[0].get_ylabel() == "attitude: somersault [deg]"
    plotting.pyplot().close("all")


def test_every_axis_has_a_unit_and_every_legend_lists_each_item_once(cat):
    from acroplan.core import plotting

    rods = acroplan.examples.load("three-rods-turn").solve(verify=False)
    for result in (cat, rods):
        figs = result.plot()
        for name, fig in figs.items():
            if name == "continuation":
                continue
            for ax in _axes_of(fig):
                assert "[s]" in ax.get_xlabel() or ax.get_xlabel() == "", (name, ax.get_xlabel())
                assert "[" in ax.get_ylabel() and "]" in ax.get_ylabel(), (name, ax.get_ylabel())
                legend = ax.get_legend()
                if legend is not None:
                    labels = [t.get_text() for t in legend.get_texts()]
                    assert len(labels) == len(set(labels)), (name, labels)
            assert _axes_of(fig)[-1].get_xlabel() == "t [s]"
        figs.close()
    # the cat's joints have limits: "limits" once per panel, not twice
    fig = plotting.plot_states(cat)
    labels = [t.get_text() for t in _axes_of(fig)[3].get_legend().get_texts()]
    assert labels == ["bend", "bend limits"]
    plotting.pyplot().close("all")


def test_the_spatial_strobe_has_metres_a_key_and_no_tick_label_over_the_next_panel(cat):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from acroplan.families.spatial import drawing

    fig = drawing.strobe(cat, poses=6)
    FigureCanvasAgg(fig)  # (as save_strobe draws it)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    panels = [ax for ax in fig.axes if ax.name == "3d"]
    assert len(panels) == 6
    for ax in panels:
        assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_zlabel()) == ("x [m]", "y [m]", "z [m]")
    boxes = [ax.get_tightbbox(renderer) for ax in panels]  # with the tick labels and axis labels
    W = fig.bbox.width
    for a, b in zip(boxes, boxes[1:]):
        assert a.x1 <= b.x0 + 1.0  # (pixels) panel k's labels end before panel k + 1's begin
    assert boxes[0].x0 >= -1.0 and boxes[-1].x1 <= W + 1.0
    key = [t.get_text() for t in fig.legends[0].get_texts()]
    assert key[:2] == [link.name for link in cat.system.links.links if link.mass > 0][:2]
    assert "root x" in key and len(key) == len(set(key))


def test_the_3d_human_is_drawn_with_yeadons_solids_and_keeps_them_in_its_record():
    pytest.importorskip("yeadon")
    from acroplan.families.human.spatial_body import spatial_from_yeadon
    from acroplan.families.human.yeadon_body import load_human
    from acroplan.families.spatial.model import SpatialBody
    from acroplan.families.spatial.solids import solids_of

    body = spatial_from_yeadon(joints="arms")
    solids = solids_of(body)
    human = load_human(None)
    yeadon_solids = [s for seg in human.segments for s in seg.solids]
    assert len(solids) == len(yeadon_solids) == 11 * 0 + sum(len(seg.solids) for seg in human.segments)

    def volume(V, F):
        a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
        return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)

    meshes = sum(volume(s.vertices, s.faces) for s in solids)
    theirs = sum(s.mass / s.density for s in yeadon_solids)
    assert meshes == pytest.approx(theirs, rel=0.03)  # polygons inside the stadia's arcs: a little less
    assert meshes < theirs
    # every solid's mesh is closed and outward (a positive volume each)
    assert all(volume(s.vertices, s.faces) > 0 for s in solids)
    # at the reference posture the solids stand where yeadon draws them: the head's top is the highest point
    state = np.zeros(4 + len(body.links.joint_names))
    state[0] = 1.0
    from acroplan.families.spatial.solids import posed

    top = max(float(V[:, 2].max()) for V in posed(body, state, solids))
    _, org, _ = body.link_poses(state)
    assert top - float(org[body.links.root][2]) == pytest.approx(
        float(human.C.solids[-1].pos[2, 0] + human.C.solids[-1].height), rel=1e-9)
    # through solution.json (JSON) and back: the same table, shapes and all
    again = SpatialBody.from_dict(json.loads(json.dumps(body.to_dict())))
    assert again.links == body.links and again.links[0].shapes == body.links[0].shapes


def test_a_bad_shape_is_refused_naming_the_field():
    from acroplan.core.errors import InvalidInputError
    from acroplan.families.spatial.links import SpatialLink, SpatialLinkTable

    ok = ("stadium_solid", (0.1, 0.0, 0.1, 0.0, 0.3), (0.0, 0.0, 0.0), None)
    SpatialLinkTable([SpatialLink("a", None, 1.0, (0.1, 0.1, 0.1), shapes=(ok,)),
                      SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.1))])
    bad = ("stadium_solid", (0.1, 0.0, 0.1, 0.0), (0.0, 0.0, 0.0), None)
    with pytest.raises(InvalidInputError, match=r"links\[0\]\.shapes\[0\]\.params"):
        SpatialLinkTable([SpatialLink("a", None, 1.0, (0.1, 0.1, 0.1), shapes=(bad,)),
                          SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.1))])
    with pytest.raises(InvalidInputError, match=r"links\[0\]\.shapes\[0\]"):
        SpatialLinkTable([SpatialLink("a", None, 1.0, (0.1, 0.1, 0.1), shapes=(("cone", (), (0, 0, 0), None),)),
                          SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.1))])


def test_the_planar_diver_has_a_head_a_key_and_a_scale_bar():
    from mpl_toolkits.axes_grid1.anchored_artists import AnchoredSizeBar

    from acroplan.families.planar import drawing

    diver = acroplan.examples.load("diver-somersault").solve(verify=False)
    body = diver.system
    x = diver.waypoints[0]
    centre, r = drawing.head_of(body, x)
    J = body.joint_positions(x)
    shoulder = J[[link.name for link in body.links.links].index("arms")]
    hip = J[body.links.root]
    # beyond the shoulder, on the line from the hip, touching it
    assert np.hypot(*(centre - shoulder)) == pytest.approx(r)
    assert np.hypot(*(centre - hip)) == pytest.approx(np.hypot(*(shoulder - hip)) + r)
    assert r == pytest.approx(0.2 * 0.52)
    robot = acroplan.examples.load("space-robot-turn").system
    assert drawing.head_of(robot, np.zeros(robot.n_states)) is None
    fig = drawing.strobe(diver, poses=4)
    ax = fig.axes[0]
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["trunk", "thighs", "shanks", "arms"]
    bars = [a for a in ax.artists if isinstance(a, AnchoredSizeBar)]
    assert len(bars) == 1 and bars[0].txt_label.get_text() in ("10 cm", "20 cm", "50 cm", "1 m")
    assert any(isinstance(p, matplotlib.patches.Circle) for p in ax.patches)


def test_a_map_labels_a_swept_time_in_seconds():
    pytest.importorskip("xarray")
    import xarray as xr

    from acroplan.io.sweeps.maps import _axis_label, field_unit

    assert [field_unit(f) for f in ("plan.T", "plan.times[-1]", "T", "body.angular_momentum", "plan.theta[-1]")] \
        == ["s", "s", "s", "", ""]
    ds = xr.Dataset(coords={"T": ("T", [1.0, 2.0], {"field": "plan.T"}),
                            "L": ("L", [1.0, 2.0], {"field": "body.angular_momentum", "units": "kg m^2/s"})})
    assert _axis_label(ds, "T") == "T  (plan.T) [s]"
    assert _axis_label(ds, "L") == "L  (body.angular_momentum) [kg m^2/s]"


def test_a_png_laid_out_once_is_the_same_file_as_savefigs(cat, tmp_path):
    """Issue #22 (the falling cat's command line): ``save_figure`` lays out a constrained figure once
    instead of twice; the PNG it writes is savefig's own, byte for byte, for every figure of a plan,
    and the figure keeps its layout engine; a PDF is savefig's."""
    import matplotlib.pyplot as plt

    from acroplan.core.plotting import save_figure

    for which in ("input", "states", "effort"):
        a = cat.plot(which, effort=True)[which]
        a.savefig(tmp_path / f"{which}-savefig.png", dpi=120)
        b = cat.plot(which, effort=True)[which]
        engine = b.get_layout_engine()
        save_figure(b, tmp_path / f"{which}.png", "png", 120)
        assert b.get_layout_engine() is engine
        assert (tmp_path / f"{which}.png").read_bytes() == (tmp_path / f"{which}-savefig.png").read_bytes(), which
        plt.close(a)
        plt.close(b)
    fig = cat.plot("input")["input"]
    save_figure(fig, tmp_path / "input.pdf", "pdf", 120)
    assert (tmp_path / "input.pdf").read_bytes()[:5] == b"%PDF-"
    plt.close(fig)


def _plan_figures(cat):
    from acroplan.core.plotting import plot_result

    return plot_result(cat, effort=cat.has_torques)


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="os.fork (Linux) splits the figures")
def test_figures_written_by_two_processes_are_the_same_files_as_by_one(cat, tmp_path):
    """The command line's figures in two shares, one written by a forked copy: every file is there
    and byte for byte the one a single process writes; the states figure (6 panels) is one share,
    the input and effort figures (3 panels) the other."""
    from acroplan.io.cli.common import _shares, save

    figs = _plan_figures(cat)
    mine, theirs = _shares(list(figs.items()), 2)
    assert [n for n, _ in mine] == ["states"] and sorted(n for n, _ in theirs) == ["effort", "input"]
    one, two = tmp_path / "one", tmp_path / "two"
    one.mkdir()
    two.mkdir()
    save(figs, one, ["png"], workers=1)
    save(_plan_figures(cat), two, ["png"], workers=2)
    names = sorted(p.name for p in one.iterdir())
    assert names == ["effort.png", "input.png", "states.png"] == sorted(p.name for p in two.iterdir())
    for name in names:
        assert (one / name).read_bytes() == (two / name).read_bytes(), name


@pytest.mark.skipif(not hasattr(__import__("os"), "fork"), reason="os.fork (Linux) splits the figures")
@pytest.mark.parametrize("copy", ["fails", "hangs", "no fork"])
def test_a_share_the_forked_copy_does_not_write_is_written_by_the_process_itself(cat, tmp_path, monkeypatch, copy):
    import os
    import time

    from acroplan.io.cli import common

    def failing(share, folder, fmts):
        pid = os.fork()
        if pid == 0:
            if copy == "hangs":
                time.sleep(60)
            os._exit(1)
        return pid

    monkeypatch.setattr(common, "_fork_writer", (lambda *a: None) if copy == "no fork" else failing)
    monkeypatch.setattr(common, "FORK_PATIENCE", 0.3)
    t = time.monotonic()
    common.save(_plan_figures(cat), tmp_path, ["png"], workers=2)
    assert time.monotonic() - t < 20.0  # a hanging copy is killed after FORK_PATIENCE, not waited for
    assert sorted(p.name for p in tmp_path.iterdir()) == ["effort.png", "input.png", "states.png"]
    for p in tmp_path.iterdir():
        assert p.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and p.stat().st_size > 10_000
