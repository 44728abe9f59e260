"""The command line's ``acroplan sweep`` and ``acroplan map`` (click), registered on the CLI's group:
``main.add_command(sweep_cmd); main.add_command(map_cmd)``."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click

from ...core.errors import EXIT_INVALID, EXIT_SUCCESS, InvalidInputError

__all__ = ["sweep_cmd", "map_cmd"]


def _fail(message: str, code: int = EXIT_INVALID):
    text = str(message).replace("\n", "\\n")
    click.echo(click.style("acroplan: error: ", fg="red", bold=True) + text, err=True)
    sys.exit(code)


def _sweep_command():
    @click.command("sweep")
    @click.argument("sweep_file", metavar="SWEEP.toml", type=click.Path(dir_okay=False, path_type=Path))
    @click.option("--out", "out", required=True, type=click.Path(path_type=Path),
                  help="The store (a zarr folder): created, or resumed when this sweep started it.")
    @click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on a Dask cluster (its scheduler's address).")
    @click.option("--workers", type=click.IntRange(1, 4096), help="Local worker processes (default: one per core).")
    @click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
    @click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON on stdout.")
    def sweep_cmd(sweep_file, out, scheduler, workers, quiet, as_json):
        """Compute the sweep SWEEP.toml (a problem file with a [sweep] table) into the store OUT.

        \b
        The store is an xarray Dataset in zarr (read it with acroplan's open_sweep, which checks
        every chunk against its checksum; xarray.open_zarr reads it unchecked): per point status,
        message code, effort, peak rate and torque, errors, evaluations, wall time and the derived
        quantities, with the definition and the acroplan version in its attributes. Killed at any
        moment, the same command resumes it: every chunk already in the store is checked against
        its checksum, and only the chunks not written (or damaged) are computed. A progress bar
        (rate, time left) on a terminal; a summary by status at the end. Exit codes: 0 complete, 2
        invalid sweep, sweep too large, or store refused.

        \b
        Examples:
          acroplan sweep least-p0.toml --out least-p0.zarr
          acroplan sweep effort.toml --out effort.zarr --scheduler tcp://10.0.0.5:8786
          acroplan map least-p0.zarr --x T --y scale --value least_P0 --out least-p0.png
        """
        from .files import load_sweep  # the store's numerics, imported when the command runs
        from .runner import run_sweep

        try:
            sw = load_sweep(sweep_file)
            summary = run_sweep(sw, out, workers=workers, scheduler=scheduler)
        except InvalidInputError as e:
            _fail(str(e))
        except KeyboardInterrupt:
            _fail(f"interrupted: what is done is in {out}; run the same command again to resume", 130)
        if as_json:
            click.echo(json.dumps(summary.to_dict(), default=str))
        elif not quiet:
            for line in summary.lines():
                click.echo(line)
        sys.exit(EXIT_SUCCESS if summary.complete else 1)

    return sweep_cmd


def _fixed(at) -> dict:
    """``--at FIELD=VALUE`` options as ``{field: number or text}``."""
    fixed = {}
    for item in at:
        name, sep, v = item.partition("=")
        if not sep or not name:
            raise InvalidInputError("--at", f"{item!r} is not FIELD=VALUE", "give for example --at P0=10")
        try:
            fixed[name] = float(v)
        except ValueError:
            fixed[name] = v
    return fixed


def _map_command():
    @click.command("map")
    @click.argument("store", type=click.Path(path_type=Path))
    @click.option("--x", "x", required=True, help="Swept field on the x axis (T, scale, P0, plan.T, ...).")
    @click.option("--y", "y", required=True, help="Swept field on the y axis.")
    @click.option("--value", "value", required=True, help="Quantity to map: least_P0, effort, peak_torque, status, ...")
    @click.option("--out", "out", required=True, type=click.Path(dir_okay=False, path_type=Path),
                  help="Figure file: .png or .pdf.")
    @click.option("--kind", type=click.Choice(["heatmap", "contour"]), default="heatmap", show_default=True)
    @click.option("--at", "at", multiple=True, metavar="FIELD=VALUE", help="Fix another grid field (repeatable).")
    @click.option("--title", help="Title of the map.")
    @click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
    def map_cmd(store, x, y, value, out, kind, at, title, quiet):
        """Draw a map of a sweep store: VALUE over the fields X and Y, as a heatmap or contours.

        \b
        Infeasible points are marked apart (grey, hatched) and failed ones (not converged,
        invalid) with red crosses; points not computed yet stay blank. Every chunk is checked
        against its checksum first: a damaged one is named (exit code 2).

        \b
        Example:
          acroplan map least-p0.zarr --x T --y scale --value least_P0 --out least-p0.png
        """
        import matplotlib

        matplotlib.use("Agg")
        from .maps import draw_map

        try:
            draw_map(store, x, y, value, out, kind=kind, at=_fixed(at), title=title)
        except InvalidInputError as e:
            _fail(str(e))
        if not quiet:
            click.echo(f"wrote {out}")

    return map_cmd


#: The ``acroplan sweep`` command (click), to register on the CLI's group.
sweep_cmd = _sweep_command()
#: The ``acroplan map`` command (click).
map_cmd = _map_command()
