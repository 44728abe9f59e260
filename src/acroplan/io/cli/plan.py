"""``acroplan plan``: one problem file, an example, or a folder (or a file) of many."""

from __future__ import annotations

from pathlib import Path

import click

from ...core.errors import EXIT_INVALID, EXIT_SUCCESS, InvalidInputError
from ..output import OutputFolder, check_entry_name
from .animate import write_animation
from .common import (EXIT_BY_STATUS, allow_outside_option, allowed_paths, check_outputs, common, documented, fail,
                     import_pyplot, load_problem_arg, one_line, option_overrides, override_error, progress, report,
                     save, solve_in_budget, time_limit_of, verify_method, write_json)


@click.command("plan")
@click.argument("problem", required=False, type=click.Path(path_type=Path))
@click.option("--example", metavar="NAME", help="Plan a bundled example instead of a PROBLEM file.")
@common
@click.option("--no-plots", is_flag=True, help="Skip the figures.")
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
@click.option("--animate", "do_animate", is_flag=True, help="Also write motion.gif and strobe.png.")
@click.option("--degrees", is_flag=True, help="Figures with angles in degrees (states.png in [deg], input.png's joint rates in "
                   "[deg/s]); default radians. Only the figures: solution.json and trajectory.csv stay in "
                   "radians, and the file's [options] degrees (how its values are written) is another thing.")
@click.option("--time-limit", type=click.FloatRange(min=0, min_open=True), default=None,
              help="Wall-clock budget of each plan in seconds, compiling the integrator, the plan, its check and "
                   "its effort summary included (default: the file's [options] time_limit, else 60).")
@click.option("--objective", type=click.Choice(["energy", "torque"]), default=None,
              help="An optimal plan: least integral of u^2 (energy) or of tau^2 (torque; needs the physical "
                   "body). Overrides the file's [options] objective.")
@click.option("--tau-max", "tau_max", multiple=True, metavar="VALUE",
              help="Torque limit |tau| <= VALUE: a number for every joint, or JOINT=VALUE (repeatable; joints "
                   "not named have none). Overrides the file's [options] tau_max; implies an optimal plan.")
@click.option("--max-coefficients", "max_coefficients", type=int, default=None, metavar="N",
              help="With an optimal plan: the last basis size of its ladder (default 30; above it 36, 42, ..., "
                   "at most 60), for an optimum whose cost still falls at 30. Overrides the file's [options] "
                   "max_coefficients.")
@allow_outside_option
def plan_cmd(problem, example, out, force, quiet, as_json, no_plots, fmt, do_animate, degrees, time_limit, objective,
             tau_max, max_coefficients, allow_outside):
    """Plan a motion through the waypoints of PROBLEM (a TOML file) and write the results.

    \b
    Writes to OUT:
      solution.json      system (a body's link table), inputs (the joint each input drives),
                         waypoints, segments (Legendre and power-basis coefficients per input;
                         an optimal plan's optimality diagnostics), objective, torque_limits,
                         effort (per joint: peak |tau|, peak |power|, positive and net work,
                         integrals of tau^2 and u^2), status, warnings, diagnostics
      trajectory.csv     t, theta, every joint angle, every rate (t,theta,phi,u for the
                         acrobot), and tau_<joint>, power_<joint> per joint when the body
                         gives torques (its masses and inertias: the acrobot's physical
                         keys, any [body]), 200 samples per segment
      input.png          the joint rates u(t), the text's Fig. 1
      states.png         theta(t) and each joint angle, waypoints marked, the text's Fig. 2
                         (a body in 3-D: Yeadon's somersault, tilt and twist); in radians,
                         in degrees with --degrees
      continuation.png   target path against what was reached, smallest singular value
      effort.png         joint torques (limits dotted) and power, when the body gives torques
    On exit code 3 (infeasible) or 4 (not converged) only solution.json is written. A planar
    body ([body] table) is checked independently by Pinocchio, the acrobot by a DOP853
    re-simulation. A success whose peak joint rate is far beyond what its waypoints imply
    (10 times their fastest finite difference) prints warnings with the peaks and what to try.

    \b
    --objective energy|torque plans the least integral of u^2 or of tau^2 instead of the fast
    feasible plan; --tau-max adds torque limits (and an energy-optimal plan unless an objective
    is given); --max-coefficients N takes the optimum's ladder of basis sizes to N. They
    override the file's [options]; without plan.conditions in the file, an optimal plan leaves
    the end rates free (conditions "free").

    PROBLEM may also be a folder of problem files, or a file of many problems ([[problem]] tables,
    each with an optional name): they are planned on all cores, each into OUT/NAME/, with
    OUT/summary.csv (name, status, message, segments, evaluations, errors). In a folder, hidden
    files are skipped and a file that is not a valid problem is listed in summary.csv with status
    "invalid" and its message (the others are planned). Names must be plain folder names (no
    path, no "..", not hidden, not reserved, all different). The exit code of a batch is the
    largest code among its problems: 4 if any did not converge, else 3 if any is infeasible,
    else 2 if any file is invalid, else 0.

    --out must be a real folder (a symbolic link is refused, not written through), and not the
    current folder, one of its parents, the home folder or a filesystem root. One run at a time
    writes to a folder (another gets exit 2).

    \b
    Examples:
      acroplan plan --example pike-dive --out pike-dive-out
      acroplan plan --example three-rods-turn --out rods --animate
      acroplan plan my-dive.toml --out my-dive-out --force --format png,pdf --animate
      acroplan plan --example falling-cat --out cat --degrees
      acroplan plan my-dive.toml --out optimal --objective energy --tau-max phi=40
      acroplan plan many-dives/ --out results --no-plots
    """
    try:
        overrides = option_overrides(objective, tau_max, max_coefficients)
        if time_limit is not None:  # validated with the file's options (a compile longer than it is refused)
            overrides["time_limit"] = float(time_limit)
        allowed = allowed_paths(allow_outside)
    except InvalidInputError as e:
        fail(str(e))
    with progress(quiet) as prog:  # (whether PROBLEM is many: a large file is parsed for it, seconds)
        prog.phase("reading the problem")
        batch = problem is not None and example is None and _is_batch(problem)
    if batch:
        return _plan_batch(problem, out, force, quiet, as_json, no_plots, fmt, overrides, allowed, degrees)
    try:
        with progress(quiet) as prog:
            with prog.scope("reading the problem", unit="file"):  # (a human body imports yeadon: seconds)
                prob = load_problem_arg(problem, example, overrides, allowed)
            prog.phase("planning")
            fmts = check_outputs(out, force, fmt, "plan-out", [problem])
            with OutputFolder(out, force) as folder:
                # the check the family asks for on the command line (verify_method: the acrobot's DOP853
                # re-simulation; a body's Pinocchio check), the same in a folder of problems; the
                # compilation, the plan, its check and the effort summary within the time limit
                result, doc = solve_in_budget(prob, verify=verify_method(prob.system), progress=prog)
                prog.phase("writing the results")
                with folder.write() as tmp:
                    write_json(tmp / "solution.json", doc)
                    if result.success:
                        _write_plan_files(result, tmp, fmts, no_plots, degrees)
                        if do_animate:
                            write_animation(tmp)
                    prog.phase(f"writing {out}")
    except InvalidInputError as e:
        fail(str(e))
    code = EXIT_BY_STATUS[result.status]
    d = doc  # (result.to_dict() and more: the summary below reads its blocks, not a second copy)
    summary = {"command": "plan", "status": result.status.value, "message": result.message, "out": str(out),
               "segments": len(result.segments), **d["diagnostics"], "infeasible": d["infeasible"],
               "objective": result.objective, "torque_limits": result.torque_limits,
               "effort": (d.get("effort") or {}).get("joints"), "warnings": list(result.warnings)}
    warned = [f"warning: {w}" for w in result.warnings]  # why a success may not be a motion to use
    lines = [result.message] + warned + _effort_lines(d) + [f"wrote {out}/"] if code == EXIT_SUCCESS else [
        result.message, *warned, f"diagnostics written to {out / 'solution.json'}"]
    report(summary, as_json, quiet, lines, code)


def _effort_lines(doc: dict) -> list[str]:
    """One line per joint of a plan's effort block (peak torque and power, positive work)."""
    joints = (doc.get("effort") or {}).get("joints") or {}
    limits = doc.get("torque_limits") or {}
    return [f"joint {j}: peak |tau| {e['peak_torque']:.6g}" + (f" (limit {limits[j]:g})" if j in limits else "") +
            f", peak |power| {e['peak_power']:.6g}, positive work {e['positive_work']:.6g}, integral of tau^2 "
            f"{e['torque_squared']:.6g}" for j, e in joints.items()]


#: Rows of trajectory.csv written between two progress updates.
CSV_BLOCK = 20_000


def write_csv(result, path: Path, per_segment: int = 200, *, effort: bool = True, samples=None):
    """``per_segment`` samples per segment: the columns of :meth:`Samples.columns` (``t``, the states,
    the inputs, and with ``effort`` when the system has a torque model ``tau_<joint>``,
    ``power_<joint>``). Written in blocks of :data:`CSV_BLOCK` rows, the stage "writing
    trajectory.csv" reporting them (a million rows take tens of seconds). Returns the samples
    (``samples``: given, they are written instead of sampling again)."""
    import numpy as np

    from ...core import progress as progress_mod

    samples = samples if samples is not None else result.sample(per_segment, effort=effort)
    cols = samples.columns()
    data = np.column_stack(list(cols.values()))
    with open(path, "w", encoding="utf-8") as f, \
            progress_mod.stage("writing trajectory.csv", len(data), unit="row") as st:
        f.write(",".join(cols) + "\n")
        for i in range(0, len(data), CSV_BLOCK):
            np.savetxt(f, data[i:i + CSV_BLOCK], delimiter=",", fmt="%.17g")
            st.update(min(CSV_BLOCK, len(data) - i))
    return samples


def _write_plan_files(result, folder: Path, fmts, no_plots: bool, degrees: bool = False) -> None:
    """trajectory.csv and, unless ``no_plots``, the figures (effort.png when the plan gives torques;
    ``degrees``: their angles in degrees)."""
    samples = write_csv(result, folder / "trajectory.csv")
    if no_plots:
        return
    from ...core.plotting import plot_result

    import_pyplot()
    # the figures drawn from trajectory.csv's own samples (the same 200 points a segment): sampled once
    save(plot_result(result, effort=result.has_torques, degrees=degrees, samples=samples), folder, fmts)


def _is_batch(path: Path) -> bool:
    if path.is_dir():
        return True
    try:
        from ..problem import load_toml

        return "problem" in load_toml(path)
    except InvalidInputError:
        return False


#: exit code of each status in a batch; the batch exits with the largest code present

EXIT_BY_BATCH_STATUS = {**EXIT_BY_STATUS, "invalid": EXIT_INVALID}


def _batch_entries(path: Path, overrides: dict | None = None, allowed=()):
    """[(name, Problem or None, message or None)] of a folder or a file of many problems.

    A folder: every ``*.toml`` file not hidden, named by its stem; a file that cannot be read or
    validated is kept with its message (naming the file), so that the others are planned. A file
    of many problems: any invalid entry, name or duplicate name refuses the whole file.
    """
    from ..problem import load_problem, load_toml, parse_problem, with_options

    overrides = overrides or {}
    entries = []
    if path.is_dir():
        files = sorted(f for f in path.glob("*.toml") if not f.name.startswith("."))
        if not files:
            raise InvalidInputError(str(path), "holds no .toml problem files", "put problem files in the folder")
        seen = {}
        for f in files:
            try:
                name = check_entry_name(f"{f}: file name", f.stem)
                if name.lower() in seen:
                    raise InvalidInputError(f"{f}: file name", f"gives the same output folder as {seen[name.lower()]}"
                                            " (names differ only in case)", "rename one of the files")
                seen[name.lower()] = f.name
                try:
                    prob = parse_problem(with_options(load_toml(f), overrides), name=f.stem, base=f.parent,
                                         allowed=allowed) if overrides else load_problem(f, allowed=allowed)
                except InvalidInputError as e:
                    raise override_error(e, overrides) from None
                entries.append((name, prob, None))
            except InvalidInputError as e:
                msg = str(e) if e.field.startswith(str(f)) else f"{f}: {e}"
                entries.append((f.stem, None, one_line(msg, 500)))
        return entries
    data = load_toml(path)
    for key in data:
        if key != "problem":
            raise InvalidInputError(_short_key(key), "is not a known key of a file of many problems",
                                    "put every problem in a [[problem]] table")
    items = data["problem"]
    if not isinstance(items, list) or not items or not all(isinstance(e, dict) for e in items):
        raise InvalidInputError("problem", "must be an array of tables ([[problem]])", "see docs/problem-files.md")
    seen = {}
    for i, entry in enumerate(items):
        entry = dict(entry)
        name = check_entry_name(f"problem[{i}].name", entry.pop("name", f"problem-{i:04d}"))
        if name.lower() in seen:
            raise InvalidInputError(f"problem[{i}].name", f"{name!r} is also the name of problem[{seen[name.lower()]}]"
                                    " (names must differ, also in case)", "rename the duplicates")
        seen[name.lower()] = i
        try:
            entries.append((name, parse_problem(with_options(entry, overrides), name=name, base=path.parent,
                                                allowed=allowed), None))
        except InvalidInputError as e:
            e = override_error(e, overrides)
            raise InvalidInputError(e.field if e.field.startswith("--") else f"problem[{i}].{e.field}", e.problem,
                                    e.fix) from None
    return entries


def _short_key(key) -> str:
    r = str(key)
    return r if len(r) <= 60 and r.isprintable() else repr(r)[:57] + "..."


def _plan_batch(path, out, force, quiet, as_json, no_plots, fmt, overrides=None, allowed=(), degrees=False):
    import csv

    from ...batch import plan_many
    from ...core.budget import budget

    try:
        with progress(quiet) as prog:  # (every file parsed and validated)
            prog.phase("reading the problems")
            entries = _batch_entries(path, overrides, allowed)
        fmts = check_outputs(out, force, fmt, "results", [path])
        valid = [(n, p) for n, p, _ in entries if p is not None]
        problems = dict(valid)
        with OutputFolder(out, force) as folder:
            results = {}
            if valid:
                with progress(quiet) as prog:
                    jobs = [{"system": p.robot, **p.plan_kwargs(), "verify": verify_method(p.robot)} for _, p in valid]
                    results = dict(zip([n for n, _ in valid], plan_many(jobs, progress=prog)))
            with progress(quiet) as prog, folder.write() as tmp:
                prog.phase("writing the results")
                rows = []
                for name, _, message in entries:
                    if name not in results:
                        rows.append({"name": name, "status": "invalid", "message": message, "segments": "",
                                     "evaluations": "", "max_final_error": "", "max_verified_error": ""})
                        continue
                    with budget(time_limit_of(problems[name])):  # its effort summary, within its time limit
                        r, doc = documented(results[name])
                    sub = tmp / name
                    sub.mkdir()
                    write_json(sub / "solution.json", doc)
                    if r.success:
                        _write_plan_files(r, sub, fmts, no_plots, degrees)
                    d = r.to_dict()["diagnostics"]
                    rows.append({"name": name, "status": str(r.status), "message": r.message.splitlines()[0],
                                 "segments": len(r.segments), "evaluations": d["evaluations"],
                                 "max_final_error": d["max_final_error"],
                                 "max_verified_error": d["max_verified_error"]})
                with open(tmp / "summary.csv", "w", newline="", encoding="utf-8") as f:
                    w = csv.DictWriter(f, fieldnames=list(rows[0]))
                    w.writeheader()
                    w.writerows(rows)
    except InvalidInputError as e:
        fail(str(e))
    statuses = [row["status"] for row in rows]
    code = max(EXIT_BY_BATCH_STATUS[s] for s in statuses)
    counts = {s: statuses.count(s) for s in sorted(set(statuses))}
    lines = [row["message"] for row in rows if row["status"] == "invalid"]
    lines += [f"{len(rows)} problems: " + ", ".join(f"{v} {k}" for k, v in counts.items()),
              f"wrote {out}/summary.csv"]
    report({"command": "plan", "batch": True, "counts": counts, "out": str(out),
             "invalid": [row["message"] for row in rows if row["status"] == "invalid"],
             "problems": rows}, as_json, quiet, lines, code)
