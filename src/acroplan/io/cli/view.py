"""``acroplan view``: an interactive 3-D view of a saved motion in the browser (one HTML page)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import click

from ...core.errors import InvalidInputError
from .common import fail, progress


def write_view(folder: Path, out: Path | None = None, *, frames: int = 120) -> Path:
    """Write ``folder``'s view (``out``, default ``folder/view.html``), drawn from its samples
    (``trajectory.csv``: nothing compiled) by the body's family; returns the page's path."""
    from ...core.animation import samples_from_csv
    from ...core.family import families
    from ..results import load_result

    folder = Path(folder)
    sol_path = folder / "solution.json"
    if not folder.is_dir():
        raise InvalidInputError(str(folder), "no such folder", "give a folder written by acroplan plan or simulate")
    if not sol_path.is_file():
        raise InvalidInputError(str(folder), "holds no solution.json", "give a folder written by acroplan plan or "
                                "simulate")
    try:
        kind = json.loads(sol_path.read_text(encoding="utf-8"))["system"].get("type")
    except (json.JSONDecodeError, UnicodeDecodeError, KeyError, TypeError, AttributeError) as e:
        raise InvalidInputError(str(sol_path), f"is corrupt ({type(e).__name__}: {e})", "plan again to rewrite it") \
            from None
    fam = next((f for f in families() if f.view is not None and kind in f.type_names()), None)
    if fam is None:
        raise InvalidInputError(str(sol_path), f"records a body of type {kind!r}, which has no 3-D view (bodies in "
                                "3-D have one)", f"use acroplan animate {folder}")
    if not 2 <= frames <= 1000:
        raise InvalidInputError("--frames", f"must lie in [2, 1000], got {frames}", "give for example 120")
    result = load_result(sol_path)
    if not result.success:
        raise InvalidInputError(str(folder), f"holds no successful motion (status {result.status.value!r})",
                                "view a folder whose plan succeeded")
    samples = samples_from_csv(folder / "trajectory.csv", result.system.state_names)
    out = Path(out) if out is not None else folder / "view.html"
    tmp = out.with_name(f".{out.name}.tmp")
    try:
        fam.view(result, tmp, samples=samples, frames=frames, name=folder.resolve().name)
        os.replace(tmp, out)
    finally:
        tmp.unlink(missing_ok=True)
    return out


@click.command("view")
@click.argument("folder", type=click.Path(file_okay=False, path_type=Path))
@click.option("--out", "out", type=click.Path(dir_okay=False, path_type=Path),
              help="The page to write (default: FOLDER/view.html).")
@click.option("--frames", type=int, default=120, show_default=True, help="Frames of the animation.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
def view_cmd(folder, out, frames, quiet):
    """Write an interactive 3-D view of the motion saved in FOLDER: one self-contained HTML page.

    \b
    The page (plotly, its JavaScript inline: it opens in any browser without a network) shows
    the body as shaded solids (a human's Yeadon solids, other links as equivalent boxes), the
    root's axes (x red, y green, z blue) and the angular momentum vector, which the mouse turns
    and zooms, and beside it the attitude (Yeadon's somersault, tilt and twist) and the joint
    angles over time; play, pause and a time slider move them together. Bodies in 3-D (a [body]
    with angular_momentum = [Lx, Ly, Lz], or model = "3d" for a human).

    \b
    Example:
      acroplan plan --example falling-cat --out cat && acroplan view cat   # then open cat/view.html
    """
    try:
        with progress(quiet):
            path = write_view(folder, out, frames=frames)
    except InvalidInputError as e:
        fail(str(e))
    if not quiet:
        click.echo(f"wrote {path} (open it in a browser)")
