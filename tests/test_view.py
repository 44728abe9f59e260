"""The interactive 3-D view in the browser (issue #24): one self-contained HTML page, loaded in a
headless Chromium (Debian's package; .ci/run installs it) through the DevTools Protocol: no console
error, the body on the screenshot, and the slider and the play button change the picture. Counted
in pixels, never timed."""

import json

import numpy as np
import pytest

import acroplan

import browser  # tests/browser.py

pytest.importorskip("plotly")
#: The tests that load the page in Chromium skip without it (and without websocket-client); the
#: page's other tests run anyway
needs_chromium = pytest.mark.skipif(browser.chromium() is None,
                                    reason="no chromium on the PATH (apt-get install -y chromium)")

# one worker for the module: the cat is planned and its page written once (the module fixture)
pytestmark = pytest.mark.xdist_group("test_view")

READY = "document.querySelector('.js-plotly-plot') && document.querySelector('.js-plotly-plot')._fullLayout"
#: The frame shown (plotly records it while animating and when the slider moves)
ACTIVE = "document.querySelector('.js-plotly-plot')._fullLayout._currentFrame"
#: Two animation frames of the page: what a picture needs to be redrawn after a change
REDRAWN = "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => setTimeout(r, 300))))"


@pytest.fixture(scope="module")
def cat_view(tmp_path_factory):
    result = acroplan.examples.load("falling-cat").solve(verify=False)
    path = result.view(tmp_path_factory.mktemp("view") / "cat.html", frames=40)
    return result, path


def _coloured(img, box):
    """Pixels of ``img`` inside ``box`` (left, top, right, bottom) that are coloured (not white, grey
    or black: the background, the grid, the text): the body's shaded solids."""
    a = np.asarray(img.crop(box)).astype(int)
    return (a.max(axis=2) - a.min(axis=2)) > 60


def test_the_page_is_self_contained(cat_view):
    _, path = cat_view
    import re

    html = path.read_text(encoding="utf-8")
    assert not re.findall(r"<script[^>]*\bsrc=", html)  # every script inline: plotly's too
    assert "Plotly.newPlot" in html and len(html) > 3_000_000  # plotly.js itself is ~3.5 MB


@needs_chromium
def test_the_view_loads_shows_the_body_and_moves_with_the_slider_and_play(cat_view):
    pytest.importorskip("websocket")
    result, path = cat_view
    with browser.Browser(width=1200, height=700) as b:
        b.open(browser.file_url(path))
        b.wait_js(READY)
        b.js(REDRAWN, await_promise=True)
        assert b.errors == []
        frames = b.js("document.querySelector('.js-plotly-plot')._transitionData._frames.length")
        assert frames == 40
        scene = b.js("JSON.stringify(document.querySelector('.gl-container canvas').getBoundingClientRect())")
        r = json.loads(scene)
        box = (int(r["left"]), int(r["top"]), int(r["left"] + 0.55 * 1200), int(r["top"] + r["height"]))
        first = b.screenshot()
        body = _coloured(first, box)
        assert body.sum() > 3000  # the body's solids (measured: ~15,000 px at 1200 x 700)
        # the slider: a click three quarters along its rail moves the body
        rail = json.loads(b.js("JSON.stringify(document.querySelector('.slider-rail-rect').getBoundingClientRect())"))
        b.click(rail["left"] + 0.75 * rail["width"], rail["top"] + rail["height"] / 2)
        b.js(REDRAWN, await_promise=True)
        active = b.js(ACTIVE)
        names = [f"{t:.4f}" for t in np.linspace(result.times[0], result.times[-1], 40)]
        assert active in names and 25 <= names.index(active) <= 33
        moved = b.screenshot()
        changed = (np.abs(np.asarray(moved.crop(box)).astype(int) - np.asarray(first.crop(box)).astype(int))
                   .max(axis=2) > 40)
        assert changed.sum() > 1000  # a different picture of the body
        # play runs the frames on from there; pause stops them
        buttons = json.loads(b.js("JSON.stringify(Array.from(document.querySelectorAll('.updatemenu-button'))"
                                  ".map(e => e.getBoundingClientRect()))"))
        b.click(buttons[0]["left"] + 5, buttons[0]["top"] + 5)  # play
        b.wait_js(f"{ACTIVE} != '{active}'")
        b.click(buttons[1]["left"] + 5, buttons[1]["top"] + 5)  # pause
        b.js(REDRAWN, await_promise=True)
        stopped = b.js(ACTIVE)
        b.js(REDRAWN, await_promise=True)
        assert b.js(ACTIVE) == stopped != active
        assert b.errors == []


def test_the_command_line_writes_the_view_from_a_folder(tmp_path):
    from click.testing import CliRunner

    from acroplan.io.cli import main

    out = tmp_path / "cat"
    assert CliRunner().invoke(main, ["plan", "--example", "falling-cat", "--out", str(out), "--no-plots"]).exit_code == 0
    res = CliRunner().invoke(main, ["view", str(out), "--frames", "12"])
    assert res.exit_code == 0, res.output
    html = (out / "view.html").read_text(encoding="utf-8")
    assert html.count('"name":"0.') + html.count('"name":"0') >= 12  # the frames, named by their times
    assert '"text":"cat: a spatial body of 4 links' in html  # the title names the folder
    planar = tmp_path / "rods"
    assert CliRunner().invoke(main, ["plan", "--example", "three-rods-turn", "--out", str(planar), "--no-plots"]
                              ).exit_code == 0
    res = CliRunner().invoke(main, ["view", str(planar)])
    assert res.exit_code == 2 and "acroplan animate" in res.output
    # honest failures: exit 2 naming what is missing, and no page left behind
    (out / "view.html").unlink()
    (out / "trajectory.csv").rename(tmp_path / "kept.csv")
    res = CliRunner().invoke(main, ["view", str(out)])
    assert res.exit_code == 2 and "trajectory.csv" in res.output
    assert sorted(p.name for p in out.iterdir()) == ["solution.json"]
    res = CliRunner().invoke(main, ["view", str(tmp_path / "nowhere")])
    assert res.exit_code == 2 and "no such folder" in res.output
    res = CliRunner().invoke(main, ["view", str(tmp_path)])
    assert res.exit_code == 2 and "solution.json" in res.output


def test_the_3d_human_is_viewed_as_yeadons_solids_one_mesh_per_link():
    pytest.importorskip("yeadon")
    import plotly.graph_objects as go

    from acroplan.families.human.twist import asymmetric_arm_twist
    from acroplan.families.spatial.solids import solids_of
    from acroplan.families.spatial.view import figure

    result = asymmetric_arm_twist(acroplan.simulate, verify=False, samples=3).result
    fig = figure(result, frames=5)
    meshes = [d for d in fig.data if isinstance(d, go.Mesh3d)]
    body = result.system
    drawn = [link.name for link in body.links.links if link.mass > 0]
    assert [m.name for m in meshes] == drawn == ["pelvis", "left_upper_arm", "right_upper_arm"]
    solids = solids_of(body)
    assert sum(len(m.x) for m in meshes) == sum(s.vertices.shape[0] for s in solids)
    assert all(len(s.vertices) > 8 for s in solids)  # stadium solids and a semi-ellipsoid, not boxes
    assert len(fig.frames) == 5 and all(len(f.data) == len(f.traces) for f in fig.frames)
    # the body's height in the scene is the measured body's (yeadon's male1: about 1.8 m with the arms up)
    z = np.concatenate([m.z for m in meshes])
    assert 1.9 < z.max() - z.min() < 2.4
    # the attitude panel is rotations.py's conversion, in degrees
    from acroplan.families.spatial import rotations as rot

    som = next(d for d in fig.data if d.name == "somersault")
    X = result.evaluate(np.asarray(som.x), effort=False).states
    assert np.allclose(som.y, np.degrees(np.unwrap(np.radians(rot.to_euler(X[:4])), axis=1))[0], atol=1e-9)


def test_a_page_is_written_whole_or_not_at_all(cat_view, tmp_path, monkeypatch):
    import plotly.graph_objects as go

    result, _ = cat_view

    def broken(self, file, **kw):
        with open(file, "w", encoding="utf-8") as f:
            f.write("<html>half a page")
        raise OSError("disk full")

    monkeypatch.setattr(go.Figure, "write_html", broken)
    with pytest.raises(OSError, match="disk full"):
        result.view(tmp_path / "page.html", frames=3)
    assert list(tmp_path.iterdir()) == []


def test_in_a_notebook_the_view_is_shown_inline(tmp_path):
    """``result.view()`` as a cell's last expression: the interactive figure in the output (plotly's
    own MIME type, and its HTML), no file written."""
    nbclient = pytest.importorskip("nbclient")
    nbformat = pytest.importorskip("nbformat")
    pytest.importorskip("ipykernel")
    code = ("import acroplan\n"
            "cat = acroplan.examples.load('falling-cat').solve(verify=False, progress=False)\n"
            "cat.view(frames=4)\n")
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code)])
    nbclient.NotebookClient(nb, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    outs = [o for o in nb.cells[0].outputs if o.get("output_type") in ("execute_result", "display_data")]
    assert len(outs) == 1
    data = outs[0]["data"]
    assert "application/vnd.plotly.v1+json" in data
    fig = data["application/vnd.plotly.v1+json"]
    assert len(fig["frames"]) == 4 and any(d["type"] == "mesh3d" for d in fig["data"])
    assert list(tmp_path.iterdir()) == []
