"""The ``acroplan`` command line.

Exit codes: 0 success, 2 invalid input, 3 infeasible (with proof), 4 not converged.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import click
import numpy as np

from . import examples as _examples
from ._errors import EXIT_INFEASIBLE, EXIT_INVALID, EXIT_NOT_CONVERGED, EXIT_SUCCESS, InvalidInputError
from ._output import atomic_dir, check_out_dir
from .problem import load_problem

EXIT_BY_STATUS = {"success": EXIT_SUCCESS, "infeasible": EXIT_INFEASIBLE, "not_converged": EXIT_NOT_CONVERGED}


def _fail(message: str, code: int = EXIT_INVALID):
    click.echo(f"acroplan: error: {message}", err=True)
    sys.exit(code)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="acroplan")
def main():
    """Motion planning for the free-flying two-link acrobot (and other control-affine systems).

    \b
    Example:
      acroplan plan --example pike-dive --out pike-dive-out
    """


@main.command("examples")
def examples_cmd():
    """List the bundled example problems."""
    for name, desc in _examples.names().items():
        click.echo(f"{name:12s} {desc}")


@main.command("plan")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Plan a bundled example instead of a PROBLEM file.")
@click.option("--out", "out", required=True, type=click.Path(file_okay=False, path_type=Path),
              help="Output folder (created; written atomically).")
@click.option("--force", is_flag=True, help="Replace a non-empty output folder.")
@click.option("--no-plots", is_flag=True, help="Skip input.png and states.png.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
def plan_cmd(problem, example, out, force, no_plots, quiet):
    """Plan a motion through the waypoints of PROBLEM (a TOML file) and write the results.

    \b
    Writes to OUT:
      solution.json    robot, waypoints, segments (power-basis coefficients), status, diagnostics
      trajectory.csv   t,theta,phi,u with 200 samples per segment
      input.png        u(t), the text's Fig. 1
      states.png       theta(t) above phi(t), waypoints marked, the text's Fig. 2
    On exit code 3 (infeasible) or 4 (not converged) only solution.json is written.

    \b
    Examples:
      acroplan plan --example pike-dive --out pike-dive-out
      acroplan plan my-dive.toml --out my-dive-out --force
    """
    try:
        prob = _load(problem, example)
        check_out_dir(out, force)
        result = prob.solve(verify=True)
        with atomic_dir(out, force) as tmp:
            (tmp / "solution.json").write_text(result.to_json() + "\n", encoding="utf-8")
            if result.success:
                _write_csv(result, tmp / "trajectory.csv")
                if not no_plots:
                    _write_plots(result, tmp)
    except InvalidInputError as e:
        _fail(str(e))
    code = EXIT_BY_STATUS[result.status]
    if code != EXIT_SUCCESS:
        click.echo(f"acroplan: {result.message}", err=True)
        click.echo(f"acroplan: diagnostics written to {out / 'solution.json'}", err=True)
    elif not quiet:
        click.echo(result.message)
        click.echo(f"wrote {out}/")
    sys.exit(code)


@main.command("reach")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Use a bundled example instead of a PROBLEM file.")
@click.option("--out", "out", required=True, type=click.Path(file_okay=False, path_type=Path),
              help="Output folder (created; written atomically).")
@click.option("--force", is_flag=True, help="Replace a non-empty output folder.")
def reach_cmd(problem, example, out, force):
    """Write the exact reachable interval of theta(T) for every segment of PROBLEM.

    \b
    Writes to OUT:
      reach.json   per segment: the interval without limits and with the problem's limits,
                   the target, and whether it is reachable
      reach.png    the reachable band of theta(T) over phi(T) for each segment, target marked
    Exit code 0 when every target is reachable, 3 when one is not (the outputs are written).

    \b
    Example:
      acroplan reach --example pike-dive-limited --out reach-out
    """
    import matplotlib.pyplot as plt

    from .plotting import plot_reach

    try:
        prob = _load(problem, example)
        check_out_dir(out, force)
        rows = prob.reach()
        with atomic_dir(out, force) as tmp:
            (tmp / "reach.json").write_text(json.dumps({"segments": rows}, indent=2) + "\n", encoding="utf-8")
            fig = plot_reach(prob)
            try:
                fig.savefig(tmp / "reach.png", dpi=120)
            finally:
                plt.close(fig)
    except InvalidInputError as e:
        _fail(str(e))
    for r in rows:
        iv = r["interval_with_limits"]
        state = "reachable" if r["reachable"] else "NOT reachable"
        ends = "none" if iv is None else f"[{iv[0]:.9g}, {iv[1]:.9g}]"
        click.echo(f"segment {r['index']} [{r['t0']:g}, {r['t1']:g}]: theta(T) in {ends}; target "
                   f"{r['target_theta']:.9g} {state}")
    sys.exit(EXIT_SUCCESS if all(r["reachable"] for r in rows) else EXIT_INFEASIBLE)


@main.command("nilpotent")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Use a bundled example (chapter4) instead of a PROBLEM file.")
@click.option("--out", "out", type=click.Path(file_okay=False, path_type=Path),
              help="Output folder (created; written atomically). Required unless --equations.")
@click.option("--force", is_flag=True, help="Replace a non-empty output folder.")
@click.option("--equations", is_flag=True, help="Print the endpoint equations (the text's style) and exit.")
@click.option("--no-plots", is_flag=True, help="Skip the figures.")
def nilpotent_cmd(problem, example, out, force, equations, no_plots):
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
      acroplan nilpotent --example chapter4 --out ch4-out
    """
    from . import nilpotent as nil
    from .reach import Limits, reachable_set

    try:
        if (problem is None) == (example is None):
            raise InvalidInputError("PROBLEM", "give either a problem file or --example NAME, not both or neither",
                                    "for example: --example chapter4")
        if example is not None:
            prob, method = _examples.load_nilpotent(example)
        else:
            from .problem import load_toml, parse_nilpotent

            prob, method = parse_nilpotent(load_toml(problem), name=problem.stem)
        if equations:
            click.echo(nil.format_equations(prob))
            sys.exit(EXIT_SUCCESS)
        if out is None:
            raise InvalidInputError("--out", "is required", "give an output folder, or --equations")
        check_out_dir(out, force)
        R = reachable_set(prob.robot, theta0=prob.P[2], phi0=prob.P[0], phiT=prob.Q[0], T=prob.Q[1] - prob.P[1],
                          limits=Limits(phi_min=-np.pi, phi_max=np.pi))
        if not R.contains(prob.Q[2]):
            payload = {"status": "infeasible", "success": False, "interval": [R.low, R.high],
                       "message": f"theta(Q) = {prob.Q[2]:.12g} is outside the reachable interval ({R.low:.12g}, "
                                  f"{R.high:.12g}) for |phi| < pi"}
            with atomic_dir(out, force) as tmp:
                (tmp / "solution.json").write_text(json.dumps(payload, indent=2) + "\n", encoding="utf-8")
            click.echo(f"acroplan: infeasible: {payload['message']}", err=True)
            sys.exit(EXIT_INFEASIBLE)
        result = nil.solve_nilpotent(prob) if method == "nilpotent" else nil.solve_flat_y(prob)
        counter = nil.counterexample(prob, result.m) if (result.success and method == "nilpotent") else None
        with atomic_dir(out, force) as tmp:
            doc = result.to_dict()
            if counter is not None:
                doc["counterexample"] = counter.to_dict()
            (tmp / "solution.json").write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
            if result.success:
                eps = np.linspace(0.0, 1.0, 2001)
                t, theta, phi, _ = result.curve(eps)
                u = result.u_of_eps(eps)
                np.savetxt(tmp / "trajectory.csv", np.column_stack([t, theta, phi, u]), delimiter=",",
                           header="t,theta,phi,u", comments="", fmt="%.17g")
                if not no_plots:
                    import matplotlib.pyplot as plt

                    from .plotting import plot_nilpotent

                    figs = plot_nilpotent(result, counter)
                    try:
                        for name, fig in figs.items():
                            fig.savefig(tmp / f"{name}.png", dpi=120)
                    finally:
                        for fig in figs.values():
                            plt.close(fig)
    except InvalidInputError as e:
        _fail(str(e))
    if not result.success:
        click.echo(f"acroplan: {result.status}: {result.message}", err=True)
        sys.exit(EXIT_NOT_CONVERGED)
    click.echo(result.message)
    click.echo(f"wrote {out}/")
    sys.exit(EXIT_SUCCESS)


def _load(problem, example):
    if (problem is None) == (example is None):
        raise InvalidInputError("PROBLEM", "give either a problem file or --example NAME, not both or neither",
                                "for example: --example pike-dive")
    return _examples.load(example) if example is not None else load_problem(problem)


def _write_csv(result, path: Path, per_segment: int = 200) -> None:
    s = result.sample(per_segment)
    names = list(s.state_names) + list(s.input_names)
    data = np.column_stack([s.t, s.states.T, s.inputs.T])
    np.savetxt(path, data, delimiter=",", header="t," + ",".join(names), comments="", fmt="%.17g")


def _write_plots(result, folder: Path) -> None:
    import matplotlib.pyplot as plt

    figs = result.plot()
    try:
        figs["input"].savefig(folder / "input.png", dpi=120)
        figs["states"].savefig(folder / "states.png", dpi=120)
    finally:
        for f in figs.values():
            plt.close(f)


if __name__ == "__main__":  # pragma: no cover
    main()
