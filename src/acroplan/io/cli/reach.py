"""``acroplan reach``: what can be proven about each segment, by the body's family."""

from __future__ import annotations

from pathlib import Path

import click

from ...core.errors import EXIT_INFEASIBLE, EXIT_SUCCESS, InvalidInputError
from ..output import OutputFolder
from .common import allow_outside_option, allowed_paths, check_outputs, common, fail, load_problem_arg, report, save, write_json


@click.command("reach")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Use a bundled example instead of a PROBLEM file.")
@common
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
@allow_outside_option
def reach_cmd(problem, example, out, force, quiet, as_json, fmt, allow_outside):
    """Write what can be proven about theta(T) for every segment of PROBLEM.

    \b
    The acrobot, and any two-link body (which is one): the exact reachable interval of theta(T).
    A planar body of three or more links has no exact reachable set; when every joint has a
    rate limit, the root's turn is bounded, |theta(T) - theta(0)| <= B, and a target outside the
    bound is proven unreachable (one inside is not proven reachable). Without rate limits on
    every joint nothing is known: exit 2 with that message.

    \b
    Writes to OUT:
      reach.json   per segment: the interval (or bound) without and with the problem's limits,
                   the target, and whether it is reachable (null: not known)
      reach.png    the acrobot: the reachable band of theta(T) over phi(T) per segment;
                   a body: each segment's interval, target marked
    Exit code 0 when no target is proven unreachable, 3 when one is (the outputs are written).

    \b
    Examples:
      acroplan reach --example pike-dive-limited --out reach-out
      acroplan reach --example space-robot-turn --out bound-out
    """
    try:
        prob = load_problem_arg(problem, example, None, allowed_paths(allow_outside))
        fmts = check_outputs(out, force, fmt, "reach-out", [problem])
        rows = prob.reach()  # refuses a body it can say nothing about, before the folder is taken
        with OutputFolder(out, force) as folder:
            with folder.write() as tmp:
                write_json(tmp / "reach.json", {"segments": rows})
                fam = prob.family()
                fig = (fam.reach_figure if fam.reach_figure is not None else _plot_intervals)(prob, rows)
                save({"reach": fig}, tmp, fmts)
    except InvalidInputError as e:
        fail(str(e))
    lines = []
    for r in rows:
        iv = r["interval_with_limits"]
        if r["reachable"] is None:
            state = "inside the bound (not proven reachable)"
        else:
            state = "reachable" if r["reachable"] else "NOT reachable"
        ends = "none" if iv is None else f"[{iv[0]:.9g}, {iv[1]:.9g}]"
        what = "theta(T) in" if "bound" not in r else f"|theta(T) - theta(0)| <= {r['bound']:.9g}: theta(T) in"
        lines.append(f"segment {r['index']} [{r['t0']:g}, {r['t1']:g}]: {what} {ends}; target "
                     f"{r['target_theta']:.9g} {state}" + (f" ({r['empty_reason']})" if r["reachable"] is False
                                                           and r.get("empty_reason") and "bound" in r else ""))
    ok = all(r["reachable"] is not False for r in rows)
    report({"command": "reach", "reachable": ok, "segments": rows, "out": str(out)}, as_json, quiet,
            lines, EXIT_SUCCESS if ok else EXIT_INFEASIBLE)


def _plot_intervals(prob, rows):
    """A body's reach: per segment, the interval of theta(T) (without limits, hatched; with them,
    solid) and the target (a star)."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(max(4.5, 1.3 * len(rows) + 2), 3.8), constrained_layout=True)
    for r in rows:
        k = r["index"]
        if r.get("interval"):
            lo, hi = r["interval"]
            ax.bar(k, hi - lo, bottom=lo, width=0.55, facecolor="none", edgecolor="C0", hatch="///",
                   label="reachable (no limits)" if k == 0 else None)
        if r.get("interval_with_limits"):
            lo, hi = r["interval_with_limits"]
            label = ("bound under the rate limits" if "bound" in r else "reachable within limits") if k == 0 else None
            ax.bar(k, hi - lo, bottom=lo, width=0.35, color="C2", alpha=0.5, label=label)
        ax.plot([k], [r["target_theta"]], marker="*", ms=13, ls="none",
                color="C3" if r["reachable"] is False else "k", label="target" if k == 0 else None, zorder=5)
    ax.set_xticks([r["index"] for r in rows],
                  [f"{r['index']}: [{r['t0']:g}, {r['t1']:g}] s" for r in rows], fontsize=8)
    ax.set_xlabel("segment")
    ax.set_ylabel("θ(T) [rad]")
    ax.set_title(f"{prob.name or 'problem'}: what is reachable of θ(T)", fontsize=10)
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    return fig
