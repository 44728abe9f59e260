"""The ``acroplan`` command line.

Exit codes: 0 success, 2 invalid input, 3 infeasible (with proof), 4 not converged. Errors are one
line naming the field and the fix (``--debug`` shows the traceback); colours only on a terminal;
progress bars only on a terminal; ``--json`` prints a machine-readable summary on stdout.

Output folders are checked and reserved (:class:`~acroplan.io.output.OutputFolder`: lock, repair
of what a killed run left) before any planning, and written atomically. No JSON written or printed
holds a non-finite number: such a value is written as ``null`` and named in the document's
``warnings`` list.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import click
import numpy as np

from ..core.errors import EXIT_INFEASIBLE, EXIT_INVALID, EXIT_NOT_CONVERGED, EXIT_SUCCESS, InvalidInputError
from . import examples as _examples
from .output import OutputFolder, check_entry_name, check_out_dir
from .problem import load_problem, load_simulation

EXIT_BY_STATUS = {"success": EXIT_SUCCESS, "infeasible": EXIT_INFEASIBLE, "not_converged": EXIT_NOT_CONVERGED}
FORMATS = ("png", "pdf")


def _one_line(message: str, most: int = 2000) -> str:
    message = str(message).replace("\r", "\\r").replace("\n", "\\n")
    return message if len(message) <= most else message[:most - 3] + "..."


def _fail(message: str, code: int = EXIT_INVALID):
    click.echo(click.style("acroplan: error: ", fg="red", bold=True) + _one_line(message), err=True)
    sys.exit(code)


def _json_safe(value, where: str = "", warnings: list | None = None):
    """``value`` with every non-finite float replaced by None; each replacement is named in
    ``warnings`` (``"segments[0].final_error: was nan, written as null"``)."""
    if warnings is None:
        warnings = []
    if isinstance(value, dict):
        return {k: _json_safe(v, f"{where}.{k}" if where else str(k), warnings) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_json_safe(v, f"{where}[{i}]", warnings) for i, v in enumerate(value)]
    if isinstance(value, np.ndarray):
        return _json_safe(value.tolist(), where, warnings)
    if isinstance(value, (float, np.floating)) and not isinstance(value, bool):
        if not math.isfinite(value):
            warnings.append(f"{where or 'value'}: was {float(value)}, written as null")
            return None
        return float(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.bool_):
        return bool(value)
    return value


def _json_text(doc: dict, **kwargs) -> str:
    """``doc`` as JSON with no NaN or infinity: those become null, listed under ``warnings``."""
    warnings: list[str] = []
    clean = _json_safe(doc, "", warnings)
    if warnings:
        clean["warnings"] = list(clean.get("warnings") or []) + warnings
    return json.dumps(clean, allow_nan=False, **kwargs)


def _write_json(path: Path, doc: dict) -> None:
    path.write_text(_json_text(doc, indent=2) + "\n", encoding="utf-8")


def _solution_doc(result, simulation=None) -> dict:
    """``result.to_dict()`` with, after ``system``, the list ``inputs``: each input's name and the
    joint (state) whose rate it is, ``[{"name": "u_shoulder", "joint": "shoulder"}, ...]`` (a body's
    link table is in ``system.links``); for a simulation, how each input was given."""
    d = result.to_dict()
    system = result.system
    rates = dict(getattr(system, "rate_inputs", {}) or {})
    inputs = [{"name": n, "joint": rates.get(n)} for n in system.input_names]
    out = {}
    for k, v in d.items():
        out[k] = v
        if k == "system":
            out["inputs"] = inputs
    out.setdefault("inputs", inputs)
    if simulation is not None:
        out["simulate"] = {"motion": dict(simulation.motion),
                           "note": "spline: the clamped cubic spline through the file's joint angles (its rate is "
                                   "exact in 3 Legendre coefficients); coefficients: the file's Legendre "
                                   "coefficients of the rate"}
    return out


def _verify_method(system) -> str:
    """How the command line checks a motion independently: the acrobot by the DOP853 re-simulation
    (``"ode"``; 10 ms do not matter here), any other system by its family's own check where it has
    one (Pinocchio's centroidal momentum for planar and spatial bodies), else by DOP853."""
    from ..core.verify import resolve_verify
    from ..families.acrobot.model import Acrobot

    return "ode" if isinstance(system, Acrobot) else resolve_verify(system, True)


def _formats(text: str) -> tuple[str, ...]:
    fmts = tuple(f.strip().lower() for f in text.split(",") if f.strip())
    bad = [f for f in fmts if f not in FORMATS]
    if bad or not fmts:
        raise InvalidInputError("--format", f"unknown figure format {bad[0] if bad else text!r}",
                                "use png, pdf or png,pdf")
    return fmts


def _check_outputs(out, force: bool, fmt: str, hint: str, inputs=()) -> tuple[str, ...]:
    """Validate --out, --force and --format before any work; returns the figure formats.

    ``inputs``: the problem files or folders read; --force must not replace a folder holding them.
    """
    if out is None:
        raise InvalidInputError("--out", "is required", f"give an output folder, for example --out {hint}")
    fmts = _formats(fmt)
    check_out_dir(out, force)
    target = Path(out).absolute().resolve()
    for p in inputs:
        if p is not None and Path(p).absolute().resolve().is_relative_to(target):
            raise InvalidInputError("--out", f"{out} holds the problem {p}, which replacing it would delete",
                                    "give another output folder")
    return fmts


def _save(figs: dict, folder: Path, fmts) -> None:
    import matplotlib.pyplot as plt

    try:
        for name, fig in figs.items():
            for f in fmts:
                fig.savefig(folder / f"{name}.{f}", dpi=120)
    finally:
        for fig in figs.values():
            plt.close(fig)


def _progress(total: int, desc: str):
    """A tqdm bar on a terminal, nothing otherwise; returns (callback, close)."""
    from tqdm import tqdm

    bar = tqdm(total=total, desc=desc, leave=False, disable=not sys.stderr.isatty(), file=sys.stderr)

    def update(done, _total):
        bar.update(done - bar.n)

    return update, bar.close


def _report(summary: dict, as_json: bool, quiet: bool, lines: list[str], code: int) -> None:
    if as_json:
        click.echo(_json_text(summary))
    elif code != EXIT_SUCCESS:
        for line in lines:
            click.echo(click.style("acroplan: ", fg="yellow", bold=True) + line, err=True)
    elif not quiet:
        for line in lines:
            click.echo(line)
    sys.exit(code)


_COMMON = [
    click.option("--out", "out", type=click.Path(file_okay=False, path_type=Path),
                 help="Output folder (created; written atomically)."),
    click.option("--force", is_flag=True, help="Replace a non-empty output folder."),
    click.option("--quiet", "-q", is_flag=True, help="Print nothing on success."),
    click.option("--json", "as_json", is_flag=True, help="Print a machine-readable summary on stdout."),
]


def common(f):
    for opt in reversed(_COMMON):
        f = opt(f)
    return f


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="acroplan")
@click.option("--debug", is_flag=True, help="Show the traceback of an unexpected error.")
def main(debug):
    """Motion planning for free-flying bodies: the two-link acrobot, planar bodies, and other
    control-affine systems.

    \b
    Examples:
      acroplan examples                                  # the bundled problems
      acroplan plan --example pike-dive --out pike       # Chapter 3
      acroplan nilpotent --example chapter4 --out ch4    # Chapter 4
      acroplan plan --example diver-somersault --out diver --animate    # a planar body
      acroplan simulate --example space-robot-arm-loop --out loop       # what an arm loop does
      acroplan plan my-dive.toml --out opt --objective energy --tau-max 40   # optimal, torque-limited
      acroplan least-momentum --example pike-dive-limited --somersaults 1.5,2.5 --out mom
                                                   # the exact least momentum (two-link body)
      acroplan init my-dive && acroplan plan my-dive.toml --out my-dive-out --animate

    Exit codes: 0 success, 2 invalid input, 3 infeasible (with proof), 4 not converged.
    """


def run():
    """Console entry point: one readable line for an unexpected error, unless --debug."""
    import matplotlib

    matplotlib.use("Agg")  # the command line draws to files; library code never chooses a backend
    try:
        main(standalone_mode=False)
    except click.exceptions.Exit as e:
        sys.exit(e.exit_code)
    except click.ClickException as e:
        e.show()
        sys.exit(EXIT_INVALID)
    except click.exceptions.Abort:
        sys.exit(130)
    except SystemExit:
        raise
    except InvalidInputError as e:
        _fail(str(e))
    except Exception as e:  # noqa: BLE001
        if "--debug" in sys.argv[1:]:
            raise
        _fail(f"unexpected {type(e).__name__}: {e} (run with --debug for the traceback)", 1)


@main.command("examples")
@click.option("--show", metavar="NAME", help="Print the example's problem file.")
def examples_cmd(show):
    """List the bundled example problems, or print one's problem file.

    \b
    Examples:
      acroplan examples
      acroplan examples --show pike-dive > my-dive.toml
    """
    if show is not None:
        try:
            click.echo(_examples.text(show), nl=False)
        except InvalidInputError as e:
            _fail(str(e))
        return
    for name, desc in _examples.names().items():
        click.echo(f"{click.style(f'{name:18s}', bold=True)} {desc}")


STARTER = '''# acroplan problem file: plan a motion of the free-flying acrobot through waypoints.
# Run it with:  acroplan plan {name}.toml --out {name}-out --animate
# Reference: docs/problem-files.md. For a planar body of any number of links (a [body] table:
# a URDF file or link tables) start from an example: acroplan init NAME --example three-rods-turn

[robot]                        # the body (SI units, or any consistent set) ...
torso_mass = 40.0              # M  (> 0)
leg_mass = 20.0                # m  (> 0)
torso_inertia = 1.8            # J  (> 0), about the torso's centre of mass
leg_inertia = 1.2              # j  (> 0), about the leg's centre of mass
torso_length = 0.35            # L  (>= 0), torso centre of mass to the joint
leg_length = 0.45              # l  (>= 0), leg centre of mass to the joint
angular_momentum = 10.0        # P0, constant in flight
# ... or instead the lumped parameters of the text's eq. (3): M1, A1, M2, A2, P0 (M1 > |A1|)

[plan]
times = [0, 1]                 # waypoint times, strictly increasing
theta = [0, 1.0]               # leg angle at each time (numbers or text like "0.5*pi")
phi = ["-pi", "-pi/2"]         # joint angle: -pi straight, 0 folded
conditions = "free"            # "free" (u continuous) or "spline" (the text's scheme)

# [limits]                     # optional
# phi_min = "-pi"              # joint limits; waypoints must lie inside
# phi_max = 0.0
# u_max = 20.0                 # |u| <= u_max (rad/s)

# [options]                    # optional
# method = "auto"              # "auto", "deform" (the text's path deformation), "flat"
# basis = "legendre"           # or "monomial"
# n_coefficients = 6           # per segment (auto raises it when needed if left out)
# objective = "energy"         # an optimal plan: least integral of u^2 ("torque": of tau^2)
# tau_max = 31.0               # joint torque limit |tau| <= 31 N m (an energy-optimal plan)
'''


@main.command("init")
@click.argument("name")
@click.option("--example", metavar="EXAMPLE", help="Start from a bundled example (acroplan examples lists them).")
@click.option("--force", is_flag=True, help="Overwrite an existing file.")
def init_cmd(name, example, force):
    """Write a commented starter problem file NAME.toml (or a copy of a bundled example, with the
    files it names: the diver's URDF beside it).

    \b
    Examples:
      acroplan init my-dive && acroplan plan my-dive.toml --out my-dive-out
      acroplan init my-diver --example diver-somersault     # also writes diver.urdf
      acroplan init my-ch4 --example chapter4 && acroplan nilpotent my-ch4.toml --out ch4
    """
    path = Path(name if name.endswith(".toml") else f"{name}.toml")
    if path.exists() and not force:
        _fail(f"{path}: exists; choose another name or add --force")
    try:
        text = STARTER.format(name=path.stem) if example is None else _examples.text(example)
        extra = {} if example is None else _examples.files(example)
        cmd = "plan" if example is None else _examples.command(example)
    except InvalidInputError as e:
        _fail(str(e))
    for fname in extra:
        if (path.parent / fname).exists() and not force:
            _fail(f"{path.parent / fname}: exists (the example's {fname}, which {path.name} names); choose another "
                  "folder or add --force")
    for fname, body in extra.items():
        (path.parent / fname).write_text(body, encoding="utf-8")
    path.write_text(text, encoding="utf-8")
    also = "".join(f" and {path.parent / f}" for f in extra)
    click.echo(f"wrote {path}{also}; run: acroplan {cmd} {path} --out {path.stem}-out")


@main.command("plan")
@click.argument("problem", required=False, type=click.Path(path_type=Path))
@click.option("--example", metavar="NAME", help="Plan a bundled example instead of a PROBLEM file.")
@common
@click.option("--no-plots", is_flag=True, help="Skip the figures.")
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
@click.option("--animate", "do_animate", is_flag=True, help="Also write motion.gif and strobe.png.")
@click.option("--time-limit", type=click.FloatRange(min=0, min_open=True), default=None,
              help="Wall-clock budget of each plan in seconds (default: the file's [options] time_limit, else 60).")
@click.option("--objective", type=click.Choice(["energy", "torque"]), default=None,
              help="An optimal plan: least integral of u^2 (energy) or of tau^2 (torque; needs the physical "
                   "body). Overrides the file's [options] objective.")
@click.option("--tau-max", "tau_max", multiple=True, metavar="VALUE",
              help="Torque limit |tau| <= VALUE: a number for every joint, or JOINT=VALUE (repeatable; joints "
                   "not named have none). Overrides the file's [options] tau_max; implies an optimal plan.")
def plan_cmd(problem, example, out, force, quiet, as_json, no_plots, fmt, do_animate, time_limit, objective,
             tau_max):
    """Plan a motion through the waypoints of PROBLEM (a TOML file) and write the results.

    \b
    Writes to OUT:
      solution.json      system (a body's link table), inputs (the joint each input drives),
                         waypoints, segments (Legendre and power-basis coefficients per input;
                         an optimal plan's optimality diagnostics), objective, torque_limits,
                         effort (per joint: peak |tau|, peak |power|, positive and net work,
                         integrals of tau^2 and u^2), status, diagnostics
      trajectory.csv     t, theta, every joint angle, every rate (t,theta,phi,u for the
                         acrobot), and tau_<joint>, power_<joint> per joint when the body
                         gives torques (its masses and inertias: the acrobot's physical
                         keys, any [body]), 200 samples per segment
      input.png          the joint rates u(t), the text's Fig. 1
      states.png         theta(t) and each joint angle, waypoints marked, the text's Fig. 2
      continuation.png   target path against what was reached, smallest singular value
      effort.png         joint torques (limits dotted) and power, when the body gives torques
    On exit code 3 (infeasible) or 4 (not converged) only solution.json is written. A planar
    body ([body] table) is checked independently by Pinocchio, the acrobot by a DOP853
    re-simulation.

    \b
    --objective energy|torque plans the least integral of u^2 or of tau^2 instead of the fast
    feasible plan; --tau-max adds torque limits (and an energy-optimal plan unless an objective
    is given). Both override the file's [options]; without plan.conditions in the file, an
    optimal plan leaves the end rates free (conditions "free").

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
      acroplan plan my-dive.toml --out optimal --objective energy --tau-max phi=40
      acroplan plan many-dives/ --out results --no-plots
    """
    try:
        overrides = _overrides(objective, tau_max)
    except InvalidInputError as e:
        _fail(str(e))
    if problem is not None and example is None and _is_batch(problem):
        return _plan_batch(problem, out, force, quiet, as_json, no_plots, fmt, overrides)
    try:
        prob = _load(problem, example, overrides)
        if time_limit is not None:
            import dataclasses

            prob = dataclasses.replace(prob, options={**prob.options, "time_limit": time_limit})
        fmts = _check_outputs(out, force, fmt, "plan-out", [problem])
        with OutputFolder(out, force) as folder:
            update, close = _progress(len(prob.times) - 1, "segments")
            try:
                # the command line re-simulates with DOP853 (verify="ode"): 10 ms do not matter here;
                # a planar body is checked by Pinocchio (its independent check)
                result = prob.solve(verify=_verify_method(prob.system), progress=update)
            finally:
                close()
            with folder.write() as tmp:
                _write_json(tmp / "solution.json", _solution_doc(result))
                if result.success:
                    _write_plan_files(result, tmp, fmts, no_plots)
                    if do_animate:
                        _write_animation(tmp)
    except InvalidInputError as e:
        _fail(str(e))
    code = EXIT_BY_STATUS[result.status]
    d = result.to_dict()
    summary = {"command": "plan", "status": result.status.value, "message": result.message, "out": str(out),
               "segments": len(result.segments), **d["diagnostics"], "infeasible": d["infeasible"],
               "objective": result.objective, "torque_limits": result.torque_limits,
               "effort": (d.get("effort") or {}).get("joints")}
    lines = [result.message] + _effort_lines(d) + [f"wrote {out}/"] if code == EXIT_SUCCESS else [
        result.message, f"diagnostics written to {out / 'solution.json'}"]
    _report(summary, as_json, quiet, lines, code)


def _effort_lines(doc: dict) -> list[str]:
    """One line per joint of a plan's effort block (peak torque and power, positive work)."""
    joints = (doc.get("effort") or {}).get("joints") or {}
    limits = doc.get("torque_limits") or {}
    return [f"joint {j}: peak |tau| {e['peak_torque']:.6g}" + (f" (limit {limits[j]:g})" if j in limits else "") +
            f", peak |power| {e['peak_power']:.6g}, positive work {e['positive_work']:.6g}, integral of tau^2 "
            f"{e['torque_squared']:.6g}" for j, e in joints.items()]


def _overrides(objective, tau_max) -> dict:
    """The ``[options]`` that --objective and --tau-max write over the problem file's."""
    out = {}
    if objective is not None:
        out["objective"] = objective
    if tau_max:
        number, table = None, {}
        fix = "write --tau-max 50 (every joint), or --tau-max JOINT=50 once per limited joint"
        for text in tau_max:
            joint, sep, value = text.rpartition("=")
            joint, value = joint.strip(), value.strip()
            field = f"--tau-max {joint}" if sep else "--tau-max"
            if sep and not joint:
                raise InvalidInputError("--tau-max", f"{_one_line(text, 80)!r} names no joint", fix)
            try:
                v = float(value)
            except ValueError:
                raise InvalidInputError(field, f"{_one_line(value, 80)!r} is not a number", fix) from None
            if sep:
                if joint in table:
                    raise InvalidInputError(field, "is given twice", "give each joint once")
                table[joint] = v
            elif number is not None:
                raise InvalidInputError("--tau-max", "gives two numbers for every joint", "give one")
            else:
                number = v
        if number is not None and table:
            raise InvalidInputError("--tau-max", "mixes a number for every joint with JOINT=VALUE",
                                    "give one number for every joint, or JOINT=VALUE for each limited joint")
        out["tau_max"] = number if number is not None else table
    return out


def _override_error(e: InvalidInputError, overrides: dict) -> InvalidInputError:
    """``e`` naming the command line's option when it is about a value the option gave."""
    for key, flag in (("tau_max", "--tau-max"), ("objective", "--objective")):
        head = f"options.{key}"
        if key in overrides and (e.field == head or e.field.startswith(head + ".")):
            rest = e.field[len(head) + 1:]
            fix = e.fix.replace(f"leave {head} out", f"leave {flag} out").replace(
                f"write {key} = ", f"give {flag} ")
            return InvalidInputError(f"{flag} {rest}".strip(), e.problem, fix)
    return e


def _write_csv(result, path: Path, per_segment: int = 200, *, effort: bool = True) -> None:
    """``per_segment`` samples per segment: the columns of :meth:`Samples.columns` (``t``, the states,
    the inputs, and with ``effort`` when the system has a torque model ``tau_<joint>``,
    ``power_<joint>``)."""
    cols = result.sample(per_segment, effort=effort).columns()
    np.savetxt(path, np.column_stack(list(cols.values())), delimiter=",", header=",".join(cols), comments="",
               fmt="%.17g")


def _write_plan_files(result, folder: Path, fmts, no_plots: bool) -> None:
    """trajectory.csv and, unless ``no_plots``, the figures (effort.png when the plan gives torques)."""
    _write_csv(result, folder / "trajectory.csv")
    if no_plots:
        return
    import matplotlib.pyplot as plt

    figs = result.plot()
    try:
        if result.has_torques:
            figs["effort"] = result.plot("effort")
    except BaseException:
        for fig in figs.values():
            plt.close(fig)
        raise
    _save(figs, folder, fmts)


def _is_batch(path: Path) -> bool:
    if path.is_dir():
        return True
    try:
        from .problem import load_toml

        return "problem" in load_toml(path)
    except InvalidInputError:
        return False


#: exit code of each status in a batch; the batch exits with the largest code present
EXIT_BY_BATCH_STATUS = {**EXIT_BY_STATUS, "invalid": EXIT_INVALID}


def _batch_entries(path: Path, overrides: dict | None = None):
    """[(name, Problem or None, message or None)] of a folder or a file of many problems.

    A folder: every ``*.toml`` file not hidden, named by its stem; a file that cannot be read or
    validated is kept with its message (naming the file), so that the others are planned. A file
    of many problems: any invalid entry, name or duplicate name refuses the whole file.
    """
    from .problem import load_toml, parse_problem, with_options

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
                    prob = parse_problem(with_options(load_toml(f), overrides), name=f.stem, base=f.parent) \
                        if overrides else load_problem(f)
                except InvalidInputError as e:
                    raise _override_error(e, overrides) from None
                entries.append((name, prob, None))
            except InvalidInputError as e:
                msg = str(e) if e.field.startswith(str(f)) else f"{f}: {e}"
                entries.append((f.stem, None, _one_line(msg, 500)))
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
            entries.append((name, parse_problem(with_options(entry, overrides), name=name, base=path.parent), None))
        except InvalidInputError as e:
            e = _override_error(e, overrides)
            raise InvalidInputError(e.field if e.field.startswith("--") else f"problem[{i}].{e.field}", e.problem,
                                    e.fix) from None
    return entries


def _short_key(key) -> str:
    r = str(key)
    return r if len(r) <= 60 and r.isprintable() else repr(r)[:57] + "..."


def _plan_batch(path, out, force, quiet, as_json, no_plots, fmt, overrides=None):
    import csv

    from ..batch import plan_many

    try:
        entries = _batch_entries(path, overrides)
        fmts = _check_outputs(out, force, fmt, "results", [path])
        valid = [(n, p) for n, p, _ in entries if p is not None]
        with OutputFolder(out, force) as folder:
            results = {}
            if valid:
                update, close = _progress(len(valid), "problems")
                try:
                    results = dict(zip([n for n, _ in valid], plan_many([p for _, p in valid], progress=update)))
                finally:
                    close()
            with folder.write() as tmp:
                rows = []
                for name, _, message in entries:
                    if name not in results:
                        rows.append({"name": name, "status": "invalid", "message": message, "segments": "",
                                     "evaluations": "", "max_final_error": "", "max_verified_error": ""})
                        continue
                    r = results[name]
                    sub = tmp / name
                    sub.mkdir()
                    _write_json(sub / "solution.json", _solution_doc(r))
                    if r.success:
                        _write_plan_files(r, sub, fmts, no_plots)
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
        _fail(str(e))
    statuses = [row["status"] for row in rows]
    code = max(EXIT_BY_BATCH_STATUS[s] for s in statuses)
    counts = {s: statuses.count(s) for s in sorted(set(statuses))}
    lines = [row["message"] for row in rows if row["status"] == "invalid"]
    lines += [f"{len(rows)} problems: " + ", ".join(f"{v} {k}" for k, v in counts.items()),
              f"wrote {out}/summary.csv"]
    _report({"command": "plan", "batch": True, "counts": counts, "out": str(out),
             "invalid": [row["message"] for row in rows if row["status"] == "invalid"],
             "problems": rows}, as_json, quiet, lines, code)


@main.command("simulate")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Simulate a bundled example instead of a PROBLEM file.")
@common
@click.option("--no-plots", is_flag=True, help="Skip the figures.")
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
@click.option("--animate", "do_animate", is_flag=True, help="Also write motion.gif and strobe.png.")
def simulate_cmd(problem, example, out, force, quiet, as_json, no_plots, fmt, do_animate):
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
    (t, the states, the rates), input.png, states.png. Exit code 0, or
    4 when the independent check disagrees (only solution.json is written then).

    \b
    Examples:
      acroplan simulate --example space-robot-arm-loop --out loop --animate
      acroplan simulate my-arm-circle.toml --out circle --no-plots
    """
    try:
        if (problem is None) == (example is None):
            raise InvalidInputError("PROBLEM", "give either a problem file or --example NAME, not both or neither",
                                    "for example: --example space-robot-arm-loop")
        sim = _examples.load_simulation(example) if example is not None else load_simulation(problem)
        fmts = _check_outputs(out, force, fmt, "sim-out", [problem])
        with OutputFolder(out, force) as folder:
            try:
                result = sim.run(verify=_verify_method(sim.system))
            except InvalidInputError as e:
                if e.field.startswith("inputs["):  # simulate()'s field: name the file's
                    raise InvalidInputError(f"simulate (segment {e.field[7:].split(']')[0]})", e.problem, e.fix) \
                        from None
                raise
            with folder.write() as tmp:
                _write_json(tmp / "solution.json", _solution_doc(result, simulation=sim))
                if result.success:
                    _write_csv(result, tmp / "trajectory.csv", effort=False)
                    if not no_plots:
                        _save(result.plot(), tmp, fmts)
                    if do_animate:
                        _write_animation(tmp)
    except InvalidInputError as e:
        _fail(str(e))
    code = EXIT_SUCCESS if result.success else EXIT_NOT_CONVERGED
    end = {n: float(v) for n, v in zip(result.system.state_names, result.waypoints[-1])}
    summary = {"command": "simulate", "status": result.status.value, "message": result.message, "out": str(out),
               "segments": len(result.segments), "end": end,
               "max_verified_error": max((s.verified_error for s in result.segments
                                          if s.verified_error is not None), default=None)}
    ends = ", ".join(f"{n} = {v:.9g}" for n, v in end.items())
    lines = [result.message, f"at t = {result.times[-1]:g}: {ends}", f"wrote {out}/"] if code == EXIT_SUCCESS \
        else [result.message, f"diagnostics written to {out / 'solution.json'}"]
    _report(summary, as_json, quiet, lines, code)


@main.command("reach")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Use a bundled example instead of a PROBLEM file.")
@common
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
def reach_cmd(problem, example, out, force, quiet, as_json, fmt):
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
    from ..families.acrobot.model import Acrobot
    from ..families.acrobot.plots import plot_reach

    try:
        prob = _load(problem, example)
        fmts = _check_outputs(out, force, fmt, "reach-out", [problem])
        rows = prob.reach()  # refuses a body it can say nothing about, before the folder is taken
        with OutputFolder(out, force) as folder:
            with folder.write() as tmp:
                _write_json(tmp / "reach.json", {"segments": rows})
                fig = plot_reach(prob) if isinstance(prob.system, Acrobot) else _plot_intervals(prob, rows)
                _save({"reach": fig}, tmp, fmts)
    except InvalidInputError as e:
        _fail(str(e))
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
    _report({"command": "reach", "reachable": ok, "segments": rows, "out": str(out)}, as_json, quiet,
            lines, EXIT_SUCCESS if ok else EXIT_INFEASIBLE)


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
            raise InvalidInputError(flag, f"{_one_line(x, 40)!r} is not a number", fix) from None
        if not (math.isfinite(v) and v > 0):
            raise InvalidInputError(flag, f"{_one_line(x, 40)} is not a positive finite number", fix)
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


@main.command("least-momentum")
@click.argument("problem", required=False, type=click.Path(dir_okay=False, path_type=Path))
@click.option("--example", metavar="NAME", help="Use a bundled example instead of a PROBLEM file.")
@common
@click.option("--somersaults", metavar="N1,N2,...", help="Also the table: least momentum for these numbers of "
              "somersaults (default with --flight-times: the file's turn).")
@click.option("--flight-times", "flight_times", metavar="T1,T2,...", help="Also the table: for these flight times "
              "in seconds (default with --somersaults: the file's).")
@click.option("--no-plots", is_flag=True, help="Skip the figure.")
@click.option("--format", "fmt", default="png", show_default=True, help="Figure formats: png, pdf or png,pdf.")
def least_momentum_cmd(problem, example, out, force, quiet, as_json, somersaults, flight_times, no_plots, fmt):
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
    from ..families.acrobot.momentum import least_momentum, somersault_table

    try:
        prob = _load(problem, example)
        S = _numbers_option("--somersaults", somersaults, "1.5,2.5,3.5")
        F = _numbers_option("--flight-times", flight_times, "1.4,1.5,1.6")
        fmts = _check_outputs(out, force, fmt, "momentum-out", [problem]) if out is not None else _formats(fmt)
        acro, psi0, delta, joint, limits = prob.two_link()
        times = prob.times
        theta, q = prob.theta, prob.state(joint)
        T = float(times[-1] - times[0])
        turn = dict(theta0=float(theta[0]) + psi0, thetaT=float(theta[-1]) + psi0, phi0=float(q[0]) + delta,
                    phiT=float(q[-1]) + delta, T=T)
        least = least_momentum(acro, **turn, limits=limits, end="least")
        most = least_momentum(acro, **turn, limits=limits, end="most")
        table = None
        if S is not None or F is not None:
            from ..planning import MAX_DURATION, MIN_DURATION
            from .problem import MAX_ANGLE

            turned = abs(turn["thetaT"] - turn["theta0"])
            if S is None and turned == 0.0:
                raise InvalidInputError("--somersaults", "is needed: the file's turn is zero",
                                        "give for example --somersaults 1.5,2.5,3.5")
            S = S if S is not None else [turned / (2.0 * math.pi)]
            F = F if F is not None else [T]
            for n in S:
                if 2.0 * math.pi * n > MAX_ANGLE:
                    raise InvalidInputError("--somersaults", f"{n:g} somersaults turn beyond {MAX_ANGLE:g} rad, more "
                                            "than the arithmetic carries", "give fewer somersaults")
            for t in F:
                if not MIN_DURATION <= t <= MAX_DURATION:
                    raise InvalidInputError("--flight-times", f"{t:g} s is outside [{MIN_DURATION:g}, "
                                            f"{MAX_DURATION:g}]", "rescale the units of time")
            table = somersault_table(acro, somersaults=S, flight_times=F, phi0=turn["phi0"], phiT=turn["phiT"],
                                     limits=limits, backward=turn["thetaT"] > turn["theta0"])
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
                    _write_json(tmp / "momentum.json", doc)
                    if table is not None:
                        _write_momentum_table(table, tmp)
                        if not no_plots:
                            fig = table.plot()
                            fig.axes[0].set_title(f"{prob.name or 'problem'}: least angular momentum "
                                                  f"({_limits_text(limits, joint, delta, 4)})", fontsize=9)
                            _save({"momentum": fig}, tmp, fmts)
    except InvalidInputError as e:
        _fail(str(e))
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
    _report({**doc, "out": None if out is None else str(out)}, as_json, quiet, lines,
            EXIT_SUCCESS if least.success else EXIT_INFEASIBLE)


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


@main.command("nilpotent")
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
    from ..core.limits import Limits
    from ..families.acrobot import nilpotent as nil
    from ..families.acrobot.reach import reachable_set
    from .problem import system_to_dict

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
        fmts = _check_outputs(out, force, fmt, "ch4-out (or use --equations)", [problem])
        with OutputFolder(out, force) as folder:
            R = reachable_set(prob.robot, theta0=prob.P[2], phi0=prob.P[0], phiT=prob.Q[0], T=prob.Q[1] - prob.P[1],
                              limits=Limits(phi_min=-np.pi, phi_max=np.pi))
            if not R.contains(prob.Q[2]):
                payload = {"status": "infeasible", "success": False, "interval": [R.low, R.high],
                           "message": f"theta(Q) = {prob.Q[2]:.12g} is outside the reachable interval "
                                      f"({R.low:.12g}, {R.high:.12g}) for |phi| < pi",
                           "system": system_to_dict(prob.robot)}
                with folder.write() as tmp:
                    _write_json(tmp / "solution.json", payload)
                infeasible = payload
            else:
                infeasible = None
                update, close = _progress(1, "solving")
                try:
                    result = nil.solve_nilpotent(prob) if method == "nilpotent" else nil.solve_flat_y(prob)
                    counter = nil.counterexample(prob, result.m) if (result.success and method == "nilpotent") \
                        else None
                    update(1, 1)
                finally:
                    close()
                with folder.write() as tmp:
                    doc = {**result.to_dict(), "system": system_to_dict(prob.robot)}
                    if counter is not None:
                        doc["counterexample"] = counter.to_dict()
                    _write_json(tmp / "solution.json", doc)
                    if result.success:
                        eps = np.linspace(0.0, 1.0, 2001)
                        t, theta, phi, _ = result.curve(eps)
                        u = result.u_of_eps(eps)
                        np.savetxt(tmp / "trajectory.csv", np.column_stack([t, theta, phi, u]), delimiter=",",
                                   header="t,theta,phi,u", comments="", fmt="%.17g")
                        if not no_plots:
                            from ..families.acrobot.plots import plot_nilpotent

                            _save(plot_nilpotent(result, counter), tmp, fmts)
                        if do_animate:
                            _write_animation(tmp)
    except InvalidInputError as e:
        _fail(str(e))
    if infeasible is not None:
        _report({"command": "nilpotent", **infeasible, "out": str(out)}, as_json, quiet,
                [f"infeasible: {infeasible['message']}"], EXIT_INFEASIBLE)
    code = EXIT_SUCCESS if result.success else EXIT_NOT_CONVERGED
    summary = {"command": "nilpotent", "status": result.status, "message": result.message, "out": str(out),
               "u1_margin": result.margin, "verified_error": result.verified_error}
    lines = [result.message, f"wrote {out}/"] if result.success else [f"{result.status}: {result.message}"]
    _report(summary, as_json, quiet, lines, code)


def _write_animation(folder: Path, *, speed: float = 1.0, fps: int = 25) -> int:
    """motion.gif (+ motion.mp4 with ffmpeg) and strobe.png from folder/solution.json and trajectory.csv.

    Each file is written under a temporary name and renamed, so none appears half-written.
    """
    import os

    import matplotlib.pyplot as plt

    from ..families.acrobot.drawing import animate, geometry_of, strobe

    sol_path = folder / "solution.json"
    if not sol_path.is_file():
        raise InvalidInputError(str(folder), "holds no solution.json", "give a folder written by acroplan plan, "
                                "simulate or nilpotent")
    try:
        sol = json.loads(sol_path.read_text(encoding="utf-8"))
        kind = sol["system"].get("type") if isinstance(sol["system"], dict) else None
        body = kind in ("PlanarBody", "SpatialBody")
        geom = None if body else geometry_of(sol["system"])
    except (json.JSONDecodeError, UnicodeDecodeError, KeyError, TypeError, ValueError) as e:
        raise InvalidInputError(str(sol_path), f"is corrupt ({type(e).__name__}: {e})",
                                "plan again to rewrite it") from None
    if sol.get("status") != "success" or not (folder / "trajectory.csv").is_file():
        raise InvalidInputError(str(folder), f"holds no successful motion (status {sol.get('status')!r})",
                                "animate a folder whose plan succeeded")
    if not (speed > 0 and np.isfinite(speed)):
        raise InvalidInputError("--speed", f"must be a positive number, got {speed}", "give for example 1 or 0.5")
    if kind == "SpatialBody":
        return _write_spatial_animation(folder, sol_path, speed=speed, fps=fps)
    if body:
        return _write_body_animation(folder, sol_path, speed=speed, fps=fps)
    try:
        data = np.loadtxt(folder / "trajectory.csv", delimiter=",", skiprows=1, ndmin=2)
        t, theta, phi, u = data[:, 0], data[:, 1], data[:, 2], data[:, 3]
    except (ValueError, IndexError) as e:
        raise InvalidInputError(str(folder / "trajectory.csv"), f"is corrupt ({e})", "plan again to rewrite it") \
            from None
    tmp_gif, tmp_mp4, tmp_png = folder / ".motion.tmp.gif", folder / ".motion.tmp.mp4", folder / ".strobe.tmp.png"
    try:
        n = animate(t, theta, phi, u, geom, tmp_gif, speed=speed, fps=fps, mp4_path=tmp_mp4)
        fig = strobe(t, theta, phi, geom)
        try:
            fig.savefig(tmp_png, dpi=120)
        finally:
            plt.close(fig)
        os.replace(tmp_gif, folder / "motion.gif")
        os.replace(tmp_png, folder / "strobe.png")
        if tmp_mp4.exists():
            os.replace(tmp_mp4, folder / "motion.mp4")
    finally:
        for f in (tmp_gif, tmp_mp4, tmp_png):
            f.unlink(missing_ok=True)
    return n


def _write_body_animation(folder: Path, sol_path: Path, *, speed: float, fps: int) -> int:
    """A planar body's motion.gif (+ motion.mp4 with ffmpeg) and strobe.png, from the exact result
    that solution.json records (:func:`~acroplan.io.results.load_result`)."""
    import os

    from ..families.planar.drawing import animate, strobe
    from .results import load_result

    result = load_result(sol_path)
    tmp_gif, tmp_mp4, tmp_png = folder / ".motion.tmp.gif", folder / ".motion.tmp.mp4", folder / ".strobe.tmp.png"
    try:
        n = animate(result, tmp_gif, speed=speed, fps=fps, mp4_path=tmp_mp4)
        fig = strobe(result, poses=9, title=f"{result.system.n_links} links: theta {result.waypoints[0][0]:.3g} -> "
                     f"{result.waypoints[-1][0]:.3g} rad in {result.times[-1] - result.times[0]:.3g} s")
        fig.savefig(tmp_png, dpi=120)
        os.replace(tmp_gif, folder / "motion.gif")
        os.replace(tmp_png, folder / "strobe.png")
        if tmp_mp4.exists():
            os.replace(tmp_mp4, folder / "motion.mp4")
    finally:
        for f in (tmp_gif, tmp_mp4, tmp_png):
            f.unlink(missing_ok=True)
    return n


def _write_spatial_animation(folder: Path, sol_path: Path, *, speed: float, fps: int) -> int:
    """A spatial body's motion.gif and strobe.png (:mod:`acroplan.families.spatial.drawing`: the links
    as shaded equivalent boxes, the root's axes, the angular momentum vector), from the exact result
    that solution.json records."""
    import os

    from ..families.spatial.drawing import animate, save_strobe
    from .results import load_result

    result = load_result(sol_path)
    tmp_gif, tmp_png = folder / ".motion.tmp.gif", folder / ".strobe.tmp.png"
    try:
        n = animate(result, tmp_gif, speed=speed, fps=fps)
        save_strobe(result, tmp_png, poses=6)
        os.replace(tmp_gif, folder / "motion.gif")
        os.replace(tmp_png, folder / "strobe.png")
    finally:
        for f in (tmp_gif, tmp_png):
            f.unlink(missing_ok=True)
    return n


@main.command("animate")
@click.argument("folder", type=click.Path(file_okay=False, path_type=Path))
@click.option("--speed", type=float, default=1.0, show_default=True, help="Playback speed (1 = real time).")
@click.option("--fps", type=click.IntRange(1, 100), default=25, show_default=True, help="Frames per second.")
@click.option("--quiet", "-q", is_flag=True, help="Print nothing on success.")
def animate_cmd(folder, speed, fps, quiet):
    """Animate the motion saved in FOLDER (by acroplan plan, simulate or nilpotent).

    \b
    Writes FOLDER/motion.gif (and motion.mp4 when ffmpeg is installed) and FOLDER/strobe.png.
    The body is drawn to scale in its centre-of-mass frame (an acrobot given only by lumped
    parameters gets a representative geometry: equal masses, L = l = sqrt|A1|); a planar body
    with every link drawn, the root thicker with a square at its frame origin, the joints as
    circles, theta as a red arrow. A motion longer than 1500 frames is played faster, with a
    warning.

    \b
    Example:
      acroplan plan --example pike-dive --out pike && acroplan animate pike --speed 0.5
    """
    import warnings

    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            n = _write_animation(folder, speed=speed, fps=fps)
        for w in caught:
            if "frames" in str(w.message):
                click.echo(click.style("acroplan: warning: ", fg="yellow") + str(w.message), err=True)
    except InvalidInputError as e:
        _fail(str(e))
    if not quiet:
        click.echo(f"wrote {folder}/motion.gif ({n} frames) and {folder}/strobe.png")


def _load(problem, example, overrides: dict | None = None):
    if (problem is None) == (example is None):
        raise InvalidInputError("PROBLEM", "give either a problem file or --example NAME, not both or neither",
                                "for example: --example pike-dive")
    if not overrides:
        return _examples.load(example) if example is not None else load_problem(problem)
    from .problem import load_toml, parse_problem, with_options

    try:
        if example is not None:
            return _examples.load(example, options=overrides)
        return parse_problem(with_options(load_toml(problem), overrides), name=Path(problem).stem,
                             base=Path(problem).parent)
    except InvalidInputError as e:
        raise _override_error(e, overrides) from None


from .sweeps.commands import map_cmd, sweep_cmd  # noqa: E402  (the sweep commands live with their store)

main.add_command(sweep_cmd)
main.add_command(map_cmd)


if __name__ == "__main__":  # pragma: no cover
    run()
