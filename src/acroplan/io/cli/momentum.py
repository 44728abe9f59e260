"""``acroplan least-momentum``: the exact least angular momentum for a two-link body's turn."""

from __future__ import annotations

import math
from pathlib import Path

import click

from ...core.errors import EXIT_INFEASIBLE, EXIT_SUCCESS, InvalidInputError
from ..output import OutputFolder
from .common import allow_outside_option, allowed_paths, check_outputs, common, fail, formats, load_problem_arg, one_line, report, save, write_json


def _numbers_option(flag: str, text: str | None, example: str, most: int = 200) -> list[float] | None:
    """A comma-separated list of positive numbers from the command line (at most ``most``)."""
    if text is None:
        return None
    parts = [x.strip() for x in text.split(",") if x.strip()]
    fix = f"give positive numbers separated by commas, for example {flag} {example}"
    if not parts:
        raise InvalidInputError(flag, "is empty", fix)
    if len(parts) > most:
        raise InvalidInputError(flag, f"gives {len(parts)} values, more than {most}", "give fewer")
    out = []
    for x in parts:
        try:
            v = float(x)
        except ValueError:
            raise InvalidInputError(flag, f"{one_line(x, 40)!r} is not a number", fix) from None
        if not (math.isfinite(v) and v > 0):
            raise InvalidInputError(flag, f"{one_line(x, 40)} is not a positive finite number", fix)
        out.append(v)
    return out


def _limits_text(limits, joint: str = "phi", delta: float = 0.0, digits: int = 9) -> str:
    """The two-link limits in the file's angles (the acrobot's less the joint offset ``delta``)."""
    if limits is None or not limits.active:
        return "no limits"
    d = _two_link_limits(limits, delta)
    parts = []
    if d["joint_min"] is not None or d["joint_max"] is not None:
        lo, hi = (-math.inf if d["joint_min"] is None else d["joint_min"]), \
            (math.inf if d["joint_max"] is None else d["joint_max"])
        parts.append(f"{joint} in [{lo:.{digits}g}, {hi:.{digits}g}]")
    if d["u_max"] is not None:
        parts.append(f"|u| <= {d['u_max']:.{digits}g}")
    return ", ".join(parts) or "no limits"


@click.command("least-momentum")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Use a bundled example instead of a PROBLEM file.")
@common
@click.option("--somersaults", metavar="N1,N2,...", help="Also the table: least momentum for these numbers of "
              "somersaults (default with --flight-times: the file's turn).")
@click.option("--flight-times", "flight_times", metavar="T1,T2,...", help="Also the table: for these flight times "
              "in seconds (default with --somersaults: the file's).")
@click.option("--no-plots", is_flag=True, help="Skip the figure.")
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
@allow_outside_option
def least_momentum_cmd(problem, example, out, force, quiet, as_json, somersaults, flight_times, no_plots, fmt, allow_outside):
    """The exact least (and largest) angular momentum P0 for PROBLEM's turn, two-link body only.

    \b
    The turn is from the first to the last waypoint of [plan]: theta and the joint angle there,
    in the whole flight time (interior waypoints are not imposed), under the file's [limits]
    (the joint range, the rate limit). The reachable theta(T) is an exact interval whose ends
    are affine and monotone in P0, so the least |P0| that turns that far is exact: with a
    rate limit a plan at that P0 exists (attained); without one it is an infimum. The largest
    is where even the slowest-turning motion turns too far. The file's own momentum is not
    used. A body of three or more links is refused (exit 2): the exact answer exists for the
    two-link body only.

    \b
    --somersaults and --flight-times add the coach's table: the least |P0| for each number of
    somersaults (full turns of theta in the file's direction) in each flight time, with the
    file's joint angles at take-off and entry and its limits.

    \b
    Writes to OUT (optional):
      momentum.json        the turn, the limits, least and largest P0 (signed), whether
                           attained, the file's P0, the table when asked for
      momentum-table.md    the table (rows: somersaults, columns: flight time)
      momentum-table.csv   somersaults, flight_time, least_abs_P0, message
      momentum.png         least |P0| against flight time, one line per somersault count
    Exit code 0, or 3 when no momentum achieves the turn (with the reason).

    \b
    Examples:
      acroplan least-momentum --example pike-dive-limited
      acroplan least-momentum my-dive.toml --somersaults 1.5,2.5,3.5 --flight-times 1.4,1.5,1.6 --out table
    """
    from ...core.family import family_of

    try:
        prob = load_problem_arg(problem, example, None, allowed_paths(allow_outside))
        S = _numbers_option("--somersaults", somersaults, "1.5,2.5,3.5")
        F = _numbers_option("--flight-times", flight_times, "1.4,1.5,1.6")
        fmts = check_outputs(out, force, fmt, "momentum-out", [problem]) if out is not None else formats(fmt)
        acro, psi0, delta, joint, limits = prob.two_link()
        exact = family_of(acro)  # the acrobot's family: the exact least momentum of its turn
        least_momentum, somersault_table = exact.least_momentum, exact.somersault_table
        times = prob.times
        theta, q = prob.theta, prob.state(joint)
        T = float(times[-1] - times[0])
        turn = dict(theta0=float(theta[0]) + psi0, thetaT=float(theta[-1]) + psi0, phi0=float(q[0]) + delta,
                    phiT=float(q[-1]) + delta, T=T)
        least = least_momentum(acro, **turn, limits=limits, end="least")
        most = least_momentum(acro, **turn, limits=limits, end="most")
        table = None
        if S is not None or F is not None:
            table = _table(somersault_table, acro, turn, limits, S, F)
        file_P0 = float(acro.P0)
        doc = {
            "command": "least-momentum",
            "turn": {"theta0": float(theta[0]), "thetaT": float(theta[-1]), "joint": joint,
                     "joint0": float(q[0]), "jointT": float(q[-1]), "T": T,
                     "note": "from the first to the last waypoint in the whole flight time; interior waypoints "
                             "are not imposed"},
            "limits": None if limits is None else _two_link_limits(limits, delta),
            "least": least.to_dict(), "most": most.to_dict(), "file_P0": file_P0,
            "file_P0_enough": bool(least.success and most.success and file_P0 * least.P0 >= 0
                                   and abs(least.P0) <= abs(file_P0) <= abs(most.P0)),
            "method": "exact: the ends of the reachable interval of theta(T) are affine and monotone in P0; "
                      "safeguarded false position on P0 to the last bit (acroplan.families.acrobot.momentum)",
        }
        if table is not None:
            doc["table"] = {"somersaults": table.somersaults.tolist(), "flight_times": table.flight_times.tolist(),
                            "least_abs_P0": table.P0.tolist(), "direction": "backward" if turn["thetaT"] >
                            turn["theta0"] else "forward", "messages": [list(r) for r in table.messages]}
        if out is not None:
            with OutputFolder(out, force) as folder:
                with folder.write() as tmp:
                    write_json(tmp / "momentum.json", doc)
                    if table is not None:
                        _write_momentum_table(table, tmp)
                        if not no_plots:
                            fig = table.plot()
                            fig.axes[0].set_title(f"{prob.name or 'problem'}: least angular momentum "
                                                  f"({_limits_text(limits, joint, delta, 4)})", fontsize=9)
                            save({"momentum": fig}, tmp, fmts)
    except InvalidInputError as e:
        fail(str(e))
    lines = [f"turn: theta {doc['turn']['theta0']:.9g} -> {doc['turn']['thetaT']:.9g} rad in {T:g} s, {joint} "
             f"{doc['turn']['joint0']:.9g} -> {doc['turn']['jointT']:.9g} rad, {_limits_text(limits, joint, delta)}"]
    for name, b in (("least", least), ("largest", most)):
        lines.append(f"{name} angular momentum: P0 = {b.P0!r}" + (f" ({b.message})" if b.success else
                                                                 f": {b.message}"))
    if least.success:
        lines.append(f"the file's P0 = {file_P0!r}: " + ("enough" if doc["file_P0_enough"] else "outside that range"))
    if table is not None:
        lines += ["least |P0| by somersaults (rows) and flight time (columns):", table.to_markdown(digits=3)]
    if out is not None:
        lines.append(f"wrote {out}/")
    report({**doc, "out": None if out is None else str(out)}, as_json, quiet, lines,
            EXIT_SUCCESS if least.success else EXIT_INFEASIBLE)


def _table(somersault_table, acro, turn: dict, limits, S, F):
    """The coach's table: the least |P0| for each number of somersaults ``S`` (default the file's
    turn) in each flight time ``F`` (default the file's)."""
    from ...core.validate import MAX_ANGLE
    from ...planning import MAX_DURATION, MIN_DURATION

    turned = abs(turn["thetaT"] - turn["theta0"])
    if S is None and turned == 0.0:
        raise InvalidInputError("--somersaults", "is needed: the file's turn is zero",
                                "give for example --somersaults 1.5,2.5,3.5")
    S = S if S is not None else [turned / (2.0 * math.pi)]
    F = F if F is not None else [turn["T"]]
    for n in S:
        if 2.0 * math.pi * n > MAX_ANGLE:
            raise InvalidInputError("--somersaults", f"{n:g} somersaults turn beyond {MAX_ANGLE:g} rad, more "
                                    "than the arithmetic carries", "give fewer somersaults")
    for t in F:
        if not MIN_DURATION <= t <= MAX_DURATION:
            raise InvalidInputError("--flight-times", f"{t:g} s is outside [{MIN_DURATION:g}, {MAX_DURATION:g}]",
                                    "rescale the units of time")
    return somersault_table(acro, somersaults=S, flight_times=F, phi0=turn["phi0"], phiT=turn["phiT"],
                            limits=limits, backward=turn["thetaT"] > turn["theta0"])


def _two_link_limits(limits, delta: float) -> dict:
    """The limits in the file's angles (the acrobot's less the joint offset ``delta``)."""
    lo, hi = limits.bounds("phi")
    return {"joint_min": lo - delta if math.isfinite(lo) else None,
            "joint_max": hi - delta if math.isfinite(hi) else None, "u_max": limits.input_bound("u")}


def _write_momentum_table(table, folder: Path) -> None:
    import csv

    (folder / "momentum-table.md").write_text(table.to_markdown(digits=3) + "\n", encoding="utf-8")
    with open(folder / "momentum-table.csv", "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["somersaults", "flight_time", "least_abs_P0", "message"])
        for i, n in enumerate(table.somersaults):
            for j, t in enumerate(table.flight_times):
                p0 = float(table.P0[i, j])
                w.writerow([repr(float(n)), repr(float(t)), repr(p0) if math.isfinite(p0) else "",
                            table.messages[i][j]])
