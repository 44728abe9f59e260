"""``acroplan animate``: the motion an output folder holds, drawn by the body's family."""

from __future__ import annotations

import json
from pathlib import Path

import math

import click

from ...core.errors import InvalidInputError
from .common import fail, progress


def write_animation(folder: Path, *, speed: float | None = None, fps: int = 25) -> int:
    """motion.gif (+ motion.mp4 with ffmpeg) and strobe.png from folder/solution.json (and
    trajectory.csv), drawn by the family of the body solution.json records
    (:attr:`Family.draw <acroplan.core.family.Family.draw>`).

    Each file is written under a temporary name and renamed, so none appears half-written.
    """
    import os

    from ...core.family import families
    from ..results import load_result

    sol_path = folder / "solution.json"
    if not sol_path.is_file():
        raise InvalidInputError(str(folder), "holds no solution.json", "give a folder written by acroplan plan, "
                                "simulate or nilpotent")
    try:
        sol = json.loads(sol_path.read_text(encoding="utf-8"))
        kind = sol["system"].get("type") if isinstance(sol["system"], dict) else None
    except (json.JSONDecodeError, UnicodeDecodeError, KeyError, TypeError, ValueError) as e:
        raise InvalidInputError(str(sol_path), f"is corrupt ({type(e).__name__}: {e})",
                                "plan again to rewrite it") from None
    if sol.get("status") != "success" or not (folder / "trajectory.csv").is_file():
        raise InvalidInputError(str(folder), f"holds no successful motion (status {sol.get('status')!r})",
                                "animate a folder whose plan succeeded")
    if speed is not None and not (speed > 0 and math.isfinite(speed)):
        raise InvalidInputError("--speed", f"must be a positive number, got {speed}", "give for example 1 or 0.5")
    fam = next((f for f in families() if f.draw is not None and kind in f.type_names()),
               None)
    if fam is None:
        raise InvalidInputError(str(sol_path), f"records a body of type {kind!r}, which no family draws",
                                "animate a folder written by acroplan plan, simulate or nilpotent")
    tmp_gif, tmp_mp4, tmp_png = folder / ".motion.tmp.gif", folder / ".motion.tmp.mp4", folder / ".strobe.tmp.png"
    try:
        n = fam.draw(folder, sol, tmp_gif, tmp_png, tmp_mp4, speed=speed, fps=fps, load=lambda: load_result(sol_path))
        os.replace(tmp_gif, folder / "motion.gif")
        os.replace(tmp_png, folder / "strobe.png")
        if tmp_mp4.exists():
            os.replace(tmp_mp4, folder / "motion.mp4")
    finally:
        for f in (tmp_gif, tmp_mp4, tmp_png):
            f.unlink(missing_ok=True)
    return n


@click.command("animate")
@click.argument("folder", type=click.Path(file_okay=False, path_type=Path))
@click.option("--speed", type=float, default=None,
              help="Playback speed (1 = real time; default: real time, or slower for a motion shorter than 3 s, so "
                   "that it lasts 3 s).")
@click.option("--fps", type=click.IntRange(1, 100), default=25, show_default=True, help="Frames per second.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
def animate_cmd(folder, speed, fps, quiet):
    """Animate the motion saved in FOLDER (by acroplan plan, simulate or nilpotent).

    \b
    Writes FOLDER/motion.gif (and motion.mp4 when ffmpeg is installed) and FOLDER/strobe.png.
    The body is drawn to scale in its centre-of-mass frame (an acrobot given only by lumped
    parameters gets a representative geometry: equal masses, L = l = sqrt|A1|); a planar body
    with every link drawn, the root thicker with a square at its frame origin, the joints as
    circles, theta as a red arrow; a body in 3-D as shaded solids with the root's axes and the
    angular momentum. A motion longer than 1500 frames is played faster, with a warning; one
    shorter than 3 s slower (the falling cat's 0.5 s at 1/6 speed), unless --speed is given.
    A progress line per stage (frames) on a terminal.

    \b
    Example:
      acroplan plan --example pike-dive --out pike && acroplan animate pike --speed 0.5
    """
    import warnings

    try:
        with warnings.catch_warnings(record=True) as caught, progress(quiet) as prog:
            warnings.simplefilter("always")
            prog.phase("animating")  # (loading the motion, the frames, the GIF, the strobe)
            n = write_animation(folder, speed=speed, fps=fps)
        for w in caught:
            if "frames" in str(w.message):
                click.echo(click.style("acroplan: warning: ", fg="yellow") + str(w.message), err=True)
    except InvalidInputError as e:
        fail(str(e))
    if not quiet:
        click.echo(f"wrote {folder}/motion.gif ({n} frames) and {folder}/strobe.png")
