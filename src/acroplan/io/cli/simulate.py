"""``acroplan simulate``: the motion a given joint motion produces."""

from __future__ import annotations

from pathlib import Path

import click

from .. import examples as _examples
from ...core.errors import EXIT_NOT_CONVERGED, EXIT_SUCCESS, InvalidInputError
from ..output import OutputFolder
from .animate import write_animation
from .common import (allow_outside_option, allowed_paths, check_outputs, common, fail, report, save, solution_doc,
                     verify_method, write_json)
from .plan import write_csv


@click.command("simulate")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Simulate a bundled example instead of a PROBLEM file.")
@common
@click.option("--no-plots", is_flag=True, help="Skip the figures.")
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
@click.option("--animate", "do_animate", is_flag=True, help="Also write motion.gif and strobe.png.")
@click.option("--degrees", is_flag=True, help="Figures with angles in degrees (states.png in [deg], input.png's joint "
              "rates in [deg/s]); default radians. solution.json and trajectory.csv stay in radians.")
@allow_outside_option
def simulate_cmd(problem, example, out, force, quiet, as_json, no_plots, fmt, do_animate, degrees, allow_outside):
    """The motion that the joint motions of PROBLEM's [simulate] table produce.

    \b
    [simulate] gives times, the initial theta, and per joint either its angles at the times (a
    clamped cubic spline through them: at rest at both ends) or its initial angle with its
    rate's Legendre coefficients per segment (u_<joint> = [[...], ...]; the acrobot's is u).
    The motion is computed by the compiled integrator (as acroplan.simulate) and checked
    independently: a planar body by Pinocchio, the acrobot by a DOP853 re-simulation.

    \b
    Writes to OUT the same files as acroplan plan: solution.json (with the joint each input
    drives, how each was given, and the effort when the body gives torques), trajectory.csv
    (t, the states, the rates), input.png, states.png; for a body in 3-D also angles.csv
    (t, Yeadon's somersault and twist in turns, tilt in degrees). Exit code 0, or
    4 when the independent check disagrees (only solution.json is written then).

    \b
    Examples:
      acroplan simulate --example space-robot-arm-loop --out loop --animate
      acroplan simulate my-arm-circle.toml --out circle --no-plots
    """
    angles = None
    try:
        if (problem is None) == (example is None):
            raise InvalidInputError("PROBLEM", "give either a problem file or --example NAME, not both or neither",
                                    "for example: --example space-robot-arm-loop")
        from ..problem import load_simulation

        sim = _examples.load_simulation(example) if example is not None else \
            load_simulation(problem, allowed=allowed_paths(allow_outside))
        fmts = check_outputs(out, force, fmt, "sim-out", [problem])
        with OutputFolder(out, force) as folder:
            try:
                result = sim.run(verify=verify_method(sim.system))
            except InvalidInputError as e:
                if e.field.startswith("inputs["):  # simulate()'s field: name the file's
                    raise InvalidInputError(f"simulate (segment {e.field[7:].split(']')[0]})", e.problem, e.fix) \
                        from None
                raise
            with folder.write() as tmp:
                write_json(tmp / "solution.json", solution_doc(result, simulation=sim))
                if result.success:
                    write_csv(result, tmp / "trajectory.csv", effort=False)
                    angles = write_angles(result, tmp / "angles.csv")
                    if not no_plots:
                        save(result.plot(degrees=degrees), tmp, fmts)
                    if do_animate:
                        write_animation(tmp)
    except InvalidInputError as e:
        fail(str(e))
    code = EXIT_SUCCESS if result.success else EXIT_NOT_CONVERGED
    end = {n: float(v) for n, v in zip(result.system.state_names, result.waypoints[-1])}
    summary = {"command": "simulate", "status": result.status.value, "message": result.message, "out": str(out),
               "segments": len(result.segments), "end": end,
               "max_verified_error": max((s.verified_error for s in result.segments
                                          if s.verified_error is not None), default=None)}
    if angles:
        summary["end_angles"] = {k: float(v[-1]) for k, v in angles.items() if k != "t"}
    ends = ", ".join(f"{n} = {v:.9g}" for n, v in end.items())
    lines = [result.message, f"at t = {result.times[-1]:g}: {ends}", f"wrote {out}/"] if code == EXIT_SUCCESS \
        else [result.message, f"diagnostics written to {out / 'solution.json'}"]
    if angles:
        lines.insert(2, "at the end: " + ", ".join(f"{k} = {v:.9g}" for k, v in summary["end_angles"].items()))
    report(summary, as_json, quiet, lines, code)


def write_angles(result, path: Path):
    """The angles the system's family names for its attitude over the motion (a body in 3-D:
    Yeadon's somersault and twist in turns, tilt in degrees; :attr:`Family.attitude_angles
    <acroplan.core.family.Family.attitude_angles>`) as ``angles.csv``; ``None`` (nothing written)
    when the family names none."""
    import csv

    import numpy as np

    from ...core.family import family_of

    fam = family_of(result.system)
    if fam is None or fam.attitude_angles is None:
        return None
    t = np.linspace(result.times[0], result.times[-1], 1001)
    angles = {"t": t, **fam.attitude_angles(result, t)}
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(list(angles))
        for row in zip(*angles.values()):
            w.writerow([repr(float(v)) for v in row])
    return angles
