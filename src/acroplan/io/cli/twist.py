"""``acroplan twist-potential``: the most twist a body in 3-D can make in given flight times and
numbers of somersaults (the family's ``twist_potential`` hook, :mod:`acroplan.core.family`)."""

from __future__ import annotations

import csv
from pathlib import Path

import click

from ...core.errors import EXIT_SUCCESS, InvalidInputError
from ..output import OutputFolder
from .common import (allow_outside_option, allowed_paths, check_outputs, common, fail, load_problem_arg, report, save,
                     write_json)
from .momentum import _numbers_option

#: the columns of twist-potential.csv
COLUMNS = ("somersaults", "flight_time", "most_twists", "least_not_reached", "stopped", "plans", "seconds", "Lx", "Ly",
           "Lz", "technique_twists", "technique_landing_tilt_deg", "technique_peak_rate_of_limit", "reason")


@click.command("twist-potential")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Use a bundled example instead of a PROBLEM file.")
@common
@click.option("--somersaults", metavar="N1,N2,...", help="Numbers of somersaults (default: the file's).")
@click.option("--flight-times", "flight_times", metavar="T1,T2,...", help="Flight times in seconds (default: the "
              "file's).")
@click.option("--resolution", default=0.25, show_default=True, type=float, help="The bisection's resolution, in "
              "turns of twist.")
@click.option("--time-limit", "time_limit", type=float, default=None, help="Seconds for each plan (default: the "
              "file's time_limit).")
@click.option("--no-plots", is_flag=True, help="Skip the figure.")
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
@allow_outside_option
def twist_potential_cmd(problem, example, out, force, quiet, as_json, somersaults, flight_times, resolution, time_limit,
                        no_plots, fmt, allow_outside):
    """The most twist PROBLEM's body can make in given flight times and numbers of somersaults.

    \b
    The technique is the file's: its planned joint motion, played in each flight time and
    simulated, with the angular momentum sized so that the flight turns each number of
    somersaults (the technique's flight: the twist and the landing tilt it makes). A bisection on
    the twist target, from the flight's twist rounded down, plans each target through the flight's
    states at the interior waypoints to the landing (the somersaults, no tilt, the target's twist)
    under the file's joint ranges and rate limits (and its tau_max); each cell reports the most
    twist planned, the least target not reached and why it stopped there: "proven" (an exact test
    refused it) or "planner stopped" (no plan found within the budget, which proves nothing).

    \b
    Writes to OUT (optional):
      twist-potential.json   the cells, with every target tried
      twist-potential.csv    somersaults, flight_time, most_twists, least_not_reached, stopped, ...
      twist-potential.png    most twist against flight time, one line per somersault count

    \b
    Examples:
      acroplan twist-potential --example back-full-twist --flight-times 1.2,1.6,2.0 --somersaults 1,2 --out tp
    """
    from ...core.family import family_of
    from ...planning import plan
    from ...simulation import simulate

    try:
        prob = load_problem_arg(problem, example, None, allowed_paths(allow_outside))
        S = _numbers_option("--somersaults", somersaults, "1,2")
        F = _numbers_option("--flight-times", flight_times, "1.2,1.6,2.0")
        fmts = check_outputs(out, force, fmt, "twist-out", [problem]) if out is not None else ()
        fam = family_of(prob.system)
        if fam is None or fam.twist_potential is None:
            what = fam.describe(prob.system) if fam is not None and fam.describe else type(prob.system).__name__
            raise InvalidInputError("body", f"is {what}, whose family offers no twist potential",
                                    "give a problem file of a body in 3-D (the bundled back-full-twist)")
        limit = time_limit if time_limit is not None else prob.options.get("time_limit")
        cells = fam.twist_potential(prob, plan, flight_times=F, somersaults=S, resolution=resolution,
                                    time_limit=limit, simulate=simulate, progress=None if quiet or as_json else
                                    (lambda text: click.echo(f"planning {text}", err=True)))
        doc = {"command": "twist-potential", "problem": prob.name, "resolution": resolution,
               "method": "the file's planned joint motion flown in each flight time with L sized for each somersault "
                         "count (acroplan.simulate, Pinocchio-checked); a bisection on the twist target from the "
                         "flight's twist, each target planned through the flight's interior states (acroplan.plan, "
                         "Pinocchio-checked)",
               "cells": [c.to_dict() for c in cells]}
        if out is not None:
            with OutputFolder(out, force) as folder:
                with folder.write() as tmp:
                    write_json(tmp / "twist-potential.json", doc)
                    write_csv(cells, tmp / "twist-potential.csv")
                    if not no_plots and fam.twist_potential_figure is not None:
                        save({"twist-potential": fam.twist_potential_figure(cells)}, tmp, fmts)
    except InvalidInputError as e:
        fail(str(e))
    lines = ["somersaults  flight time  technique's twists  most twists  least not reached  stopped"]
    for c in cells:
        tech = "-" if c.technique_twists is None else f"{c.technique_twists:.3f}"
        lines.append(f"{c.somersaults:11g}  {c.flight_time:9g} s  {tech:>18}  {c.most:11g}  "
                     f"{'-' if c.failed is None else format(c.failed, 'g'):>17}  {c.stopped}")
    if out is not None:
        lines.append(f"wrote {out}/")
    report({**doc, "out": None if out is None else str(out)}, as_json, quiet, lines, EXIT_SUCCESS)


def write_csv(cells, path: Path) -> None:
    """The cells as ``twist-potential.csv`` (:data:`COLUMNS`)."""
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(COLUMNS)
        for c in cells:
            w.writerow([repr(c.somersaults), repr(c.flight_time), repr(c.most), "" if c.failed is None else
                        repr(c.failed), c.stopped, c.plans, f"{c.seconds:.3f}", *(repr(v) for v in c.angular_momentum),
                        *("" if v is None else repr(v) for v in (c.technique_twists, c.technique_landing_tilt,
                                                                  c.technique_peak_rate)),
                        c.reason])
