"""Animation, strobe and the finished command line (init, --json, --debug, --format, animate)."""

import json
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner

from acroplan.families.acrobot.drawing import Geometry, animate, geometry_of, pose
from acroplan.io.cli import main


def run(args):
    return CliRunner().invoke(main, args)


def test_pose_geometry_matches_the_states():
    g = Geometry(torso_mass=40.0, leg_mass=20.0, torso_length=0.35, leg_length=0.45)
    theta, phi = np.array([0.3, -1.2]), np.array([-2.0, 0.7])
    P = pose(theta, phi, g)
    e_leg = np.stack([np.cos(theta), np.sin(theta)], 1)
    e_torso = np.stack([np.cos(theta + phi), np.sin(theta + phi)], 1)
    assert np.allclose(P["torso_end"] - P["joint"], 0.7 * e_torso, atol=1e-15)
    assert np.allclose(P["leg_end"] - P["joint"], 0.9 * e_leg, atol=1e-15)
    # the origin is the centre of mass
    cm = (40.0 * P["torso_cm"] + 20.0 * P["leg_cm"]) / 60.0
    assert np.allclose(cm, 0.0, atol=1e-15)
    # angle between the links is phi
    d = np.angle(np.exp(1j * (np.arctan2(*(P["torso_end"] - P["joint"]).T[::-1])
                              - np.arctan2(*(P["leg_end"] - P["joint"]).T[::-1]))))
    assert np.allclose(d, np.angle(np.exp(1j * phi)), atol=1e-12)


def test_representative_geometry_for_a_lumped_body():
    g = geometry_of({"params": {"M1": 0.82, "A1": -0.49, "M2": 0.28, "A2": -0.245, "P0": 1.0}, "physical": None})
    assert g.representative and g.torso_mass == g.leg_mass
    mu = 0.5
    assert -2 * mu * g.torso_length * g.leg_length == pytest.approx(-0.49, rel=1e-14)


def test_animation_frames_size_and_cap(tmp_path):
    from PIL import Image

    t = np.linspace(0, 2, 50)
    g = Geometry(40.0, 20.0, 0.35, 0.45)
    n = animate(t, 0.5 * t, -np.pi + t, np.ones_like(t), g, tmp_path / "m.gif", fps=10, speed=1.0)
    assert n == 21
    im = Image.open(tmp_path / "m.gif")
    assert im.n_frames == 21 and im.size == (500, 500)  # 5 in at 100 dpi: text legible (issue: "~7 px")
    with pytest.warns(UserWarning, match="capped at 30"):
        n = animate(np.linspace(0, 36000, 20), np.zeros(20), np.zeros(20), np.zeros(20), g, tmp_path / "l.gif",
                    fps=10, max_frames=30)
    assert n == 30 and Image.open(tmp_path / "l.gif").n_frames == 30


def test_animate_command(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert run(["init", "short"]).exit_code == 0  # a 1 s motion
    out = tmp_path / "p"
    assert run(["plan", "short.toml", "--out", str(out), "--no-plots", "--animate"]).exit_code == 0
    from PIL import Image

    # a motion shorter than 3 s is played slower, so that it lasts 3 s: 1 s at 1/3 speed, 25 fps
    assert Image.open(out / "motion.gif").n_frames == 76
    assert (out / "strobe.png").exists()
    res = run(["animate", str(out), "--speed", "1"])
    assert res.exit_code == 0 and "(26 frames)" in res.output  # real time asked for: 1 s at 25 fps, ends included
    res = run(["animate", str(out), "--speed", "0.25", "--fps", "5"])
    assert res.exit_code == 0 and "(21 frames)" in res.output  # 1 s at quarter speed: 4 s of film at 5 fps
    assert not list(out.glob(".*tmp*"))
    res = run(["animate", str(tmp_path)])
    assert res.exit_code == 2 and "holds no solution.json" in res.output
    bad = tmp_path / "bad"
    bad.mkdir()
    (bad / "solution.json").write_text("{not json")
    res = run(["animate", str(bad)])
    assert res.exit_code == 2 and "is corrupt" in res.output
    res = run(["animate", str(out), "--speed", "-1"])
    assert res.exit_code == 2 and "--speed: must be a positive number" in res.output


def test_init_json_format_and_debug(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    res = run(["init", "my-dive"])
    assert res.exit_code == 0 and (tmp_path / "my-dive.toml").exists()
    assert run(["init", "my-dive"]).exit_code == 2
    res = run(["plan", "my-dive.toml", "--out", "o", "--json", "--format", "png,pdf"])
    assert res.exit_code == 0, res.output
    summary = json.loads(res.output)
    assert summary["status"] == "success" and summary["max_verified_error"] < 1e-9
    assert (tmp_path / "o" / "input.pdf").read_bytes()[:4] == b"%PDF"
    res = run(["plan", "my-dive.toml", "--out", "o2", "--format", "svgz"])
    assert res.exit_code == 2 and "--format: unknown figure format" in res.output
    res = run(["plan", "my-dive.toml", "--out", "o3", "--quiet"])
    assert res.exit_code == 0 and res.output == ""


def test_unexpected_errors_are_one_line_unless_debug(tmp_path):
    # a problem file that is a folder triggers an error the CLI reports in one line
    code = ("import sys; sys.argv = ['acroplan', *sys.argv[1:]]\n"
            "import acroplan.planning as p\n"
            "def boom(*a, **k): raise RuntimeError('boom')\n"
            "p.plan = boom\nimport acroplan.io.problem as q\nq.Problem.solve = lambda self, **k: boom()\n"
            "from acroplan.io.cli import run\nrun()\n")
    args = ["plan", "--example", "pike-dive", "--out", str(tmp_path / "x")]
    res = subprocess.run([sys.executable, "-c", code, *args], capture_output=True, text=True)
    assert res.returncode == 1
    assert res.stderr.strip().splitlines()[-1].startswith("acroplan: error: unexpected RuntimeError: boom")
    assert "Traceback" not in res.stderr
    res = subprocess.run([sys.executable, "-c", code, "--debug", *args], capture_output=True, text=True)
    assert res.returncode != 0 and "Traceback" in res.stderr


@pytest.mark.parametrize("cmd", ["plan", "reach", "nilpotent", "animate", "init", "examples"])
def test_every_subcommand_has_help_with_an_example(cmd):
    res = run([cmd, "--help"])
    assert res.exit_code == 0 and "Example" in res.output


# ------------------------------------------------------------------ result.animate(), every family
@pytest.fixture(scope="module")
def three_results():
    """A plan of each family that draws: the acrobot, a planar body, a spatial body (the cat)."""
    import acroplan

    out = {"acrobot": acroplan.examples.load("pike-dive-limited").solve(verify=False),
           "planar": acroplan.examples.load("three-rods-turn").solve(verify=False),
           "spatial": acroplan.examples.load("falling-cat").solve(verify=False)}
    assert all(r.success for r in out.values())
    return out


@pytest.mark.parametrize("family", ["acrobot", "planar", "spatial"])
def test_result_animate_writes_the_file_through_the_family_hook(three_results, family, tmp_path, monkeypatch):
    from PIL import Image

    from acroplan.core.progress import Progress

    r = three_results[family]
    prog = Progress(enabled=False, record=True)
    with prog.active():
        a = r.animate(tmp_path / "m.gif", max_frames=90)
    with Image.open(a.path) as im:
        assert im.n_frames == a.frames and min(im.size) >= 500
    # one progress update a frame
    assert [d for s, d, _ in prog.events if s == "animation frames" and d] == list(range(1, a.frames + 1))
    monkeypatch.chdir(tmp_path)  # no path and no notebook: motion.gif here
    assert r.animate(max_frames=10).path.name == "motion.gif" and (tmp_path / "motion.gif").exists()


def test_a_short_motion_is_played_slower_with_enough_frames(three_results, tmp_path):
    """The falling cat turns in 0.5 s: its GIF had 14 frames of 384 px; now 3 s at 25 fps."""
    from PIL import Image

    a = three_results["spatial"].animate(tmp_path / "cat.gif")
    with Image.open(a.path) as im:
        assert a.frames == im.n_frames == 76 and im.size == (560, 560)
    assert three_results["spatial"].animate(tmp_path / "rt.gif", speed=1.0).frames == 14  # real time asked for


def test_in_a_notebook_animate_returns_an_inline_player(three_results, monkeypatch):
    import re

    import acroplan.core.progress as P

    monkeypatch.setattr(P, "in_notebook", lambda: True)
    a = three_results["planar"].animate(max_frames=12)
    assert a.path is None and a.frames == 12
    html = a._repr_html_()
    assert len(re.findall(r"data:image/png;base64,", html)) == 1 + 12  # the first frame shown, then all 12
    assert 'type="range"' in html and "play" in html and "pause" in html
    # the frames' encoding (seconds for hundreds, while the notebook shows the result) is a stage
    prog = P.Progress(enabled=False, record=True)
    with prog.active():
        a._repr_html_()
    assert ("player frames", 12, 12) in prog.events
