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
    n = animate(t, 0.5 * t, -np.pi + t, np.ones_like(t), g, tmp_path / "m.gif", fps=10)
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

    assert Image.open(out / "motion.gif").n_frames == 26  # 1 s in real time at 25 fps, ends included
    assert (out / "strobe.png").exists()
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
