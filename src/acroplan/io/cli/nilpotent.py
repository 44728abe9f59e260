"""``acroplan nilpotent``: Chapter 4 of the dissertation, the acrobot's nilpotentization. The one
command that is a family's own (its problem table ``[nilpotent]`` and its solver are the
acrobot's), so it imports that family's modules by name."""

from __future__ import annotations

import sys
from pathlib import Path

import click

from .. import examples as _examples
from ...core.errors import EXIT_INFEASIBLE, EXIT_NOT_CONVERGED, EXIT_SUCCESS, InvalidInputError
from ..output import OutputFolder
from .animate import write_animation
from .common import check_outputs, common, fail, progress, report, save, write_json


@click.command("nilpotent")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Use a bundled example (chapter4) instead of a PROBLEM file.")
@common
@click.option("--equations", is_flag=True, help="Print the endpoint equations (the text's style) and exit.")
@click.option("--no-plots", is_flag=True, help="Skip the figures.")
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
@click.option("--animate", "do_animate", is_flag=True, help="Also write motion.gif and strobe.png.")
def nilpotent_cmd(problem, example, out, force, quiet, as_json, equations, no_plots, fmt, do_animate):
    """Steer the acrobot by the nilpotentization of Chapter 4, with time moving forward.

    \b
    Writes to OUT:
      solution.json    coefficients of v1, v2, the u1 margin, verified_error, status
      trajectory.csv   t,theta,phi,u (dense; the acrobot's own time)
      input.png, states.png, u1.png, failure_mode.png
    Exit codes: 0 success, 2 invalid input, 3 target not reachable (proof: the interval),
    4 no solution with u1 > 0 found for this degree (the best margin is reported).

    \b
    Examples:
      acroplan nilpotent --example chapter4 --equations
      acroplan nilpotent --example chapter4 --out ch4-out --animate
    """
    import numpy as np

    from ...core.limits import Limits
    from ...families.acrobot import nilpotent as nil
    from ...families.acrobot.problem import parse_nilpotent
    from ...families.acrobot.reach import reachable_set
    from ..problem import system_to_dict

    try:
        if (problem is None) == (example is None):
            raise InvalidInputError("PROBLEM", "give either a problem file or --example NAME, not both or neither",
                                    "for example: --example chapter4")
        if example is not None:
            import tomllib

            prob, method = parse_nilpotent(tomllib.loads(_examples.text(example)), name=example)
        else:
            from ..problem import load_toml

            prob, method = parse_nilpotent(load_toml(problem), name=problem.stem)
        if equations:
            click.echo(nil.format_equations(prob))
            sys.exit(EXIT_SUCCESS)
        fmts = check_outputs(out, force, fmt, "ch4-out (or use --equations)", [problem])
        with OutputFolder(out, force) as folder:
            R = reachable_set(prob.robot, theta0=prob.P[2], phi0=prob.P[0], phiT=prob.Q[0], T=prob.Q[1] - prob.P[1],
                              limits=Limits(phi_min=-np.pi, phi_max=np.pi))
            if not R.contains(prob.Q[2]):
                payload = {"status": "infeasible", "success": False, "interval": [R.low, R.high],
                           "message": f"theta(Q) = {prob.Q[2]:.12g} is outside the reachable interval "
                                      f"({R.low:.12g}, {R.high:.12g}) for |phi| < pi",
                           "system": system_to_dict(prob.robot)}
                with folder.write() as tmp:
                    write_json(tmp / "solution.json", payload)
                infeasible = payload
            else:
                infeasible = None
                with progress(quiet) as prog, prog.scope("nilpotentization", unit="solve") as st:
                    result = nil.solve_nilpotent(prob) if method == "nilpotent" else nil.solve_flat_y(prob)
                    counter = nil.counterexample(prob, result.m) if (result.success and method == "nilpotent") \
                        else None
                    st.update()
                with folder.write() as tmp:
                    doc = {**result.to_dict(), "system": system_to_dict(prob.robot)}
                    if counter is not None:
                        doc["counterexample"] = counter.to_dict()
                    write_json(tmp / "solution.json", doc)
                    if result.success:
                        eps = np.linspace(0.0, 1.0, 2001)
                        t, theta, phi, _ = result.curve(eps)
                        u = result.u_of_eps(eps)
                        np.savetxt(tmp / "trajectory.csv", np.column_stack([t, theta, phi, u]), delimiter=",",
                                   header="t,theta,phi,u", comments="", fmt="%.17g")
                        if not no_plots:
                            from ...families.acrobot.plots import plot_nilpotent

                            save(plot_nilpotent(result, counter), tmp, fmts)
                        if do_animate:
                            write_animation(tmp)
    except InvalidInputError as e:
        fail(str(e))
    if infeasible is not None:
        report({"command": "nilpotent", **infeasible, "out": str(out)}, as_json, quiet,
                [f"infeasible: {infeasible['message']}"], EXIT_INFEASIBLE)
    code = EXIT_SUCCESS if result.success else EXIT_NOT_CONVERGED
    summary = {"command": "nilpotent", "status": result.status, "message": result.message, "out": str(out),
               "u1_margin": result.margin, "verified_error": result.verified_error}
    lines = [result.message, f"wrote {out}/"] if result.success else [f"{result.status}: {result.message}"]
    report(summary, as_json, quiet, lines, code)
