"""What every command shares: output folders checked before any work, figures, JSON without NaN,
one-line errors with their exit code, progress bars on a terminal, the problem named by a file or
``--example``."""

from __future__ import annotations

import contextlib
import json
import math
import sys
from pathlib import Path

import click

from ...core.errors import EXIT_INFEASIBLE, EXIT_INVALID, EXIT_NOT_CONVERGED, EXIT_SUCCESS, InvalidInputError
from ..output import check_out_dir


EXIT_BY_STATUS = {"success": EXIT_SUCCESS, "infeasible": EXIT_INFEASIBLE, "not_converged": EXIT_NOT_CONVERGED}

FORMATS = ("png", "pdf")


def one_line(message: str, most: int = 2000) -> str:
    message = str(message).replace("\r", "\\r").replace("\n", "\\n")
    return message if len(message) <= most else message[:most - 3] + "..."


def fail(message: str, code: int = EXIT_INVALID):
    click.echo(click.style("acroplan: error: ", fg="red", bold=True) + one_line(message), err=True)
    sys.exit(code)


def json_safe(value, where: str = "", warnings: list | None = None):
    """``value`` with every non-finite float replaced by None; each replacement is named in
    ``warnings`` (``"segments[0].final_error: was nan, written as null"``)."""
    import numpy as np

    if warnings is None:
        warnings = []
    if isinstance(value, dict):
        return {k: json_safe(v, f"{where}.{k}" if where else str(k), warnings) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v, f"{where}[{i}]", warnings) for i, v in enumerate(value)]
    if isinstance(value, np.ndarray):
        return json_safe(value.tolist(), where, warnings)
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


def json_text(doc: dict, **kwargs) -> str:
    """``doc`` as JSON with no NaN or infinity: those become null, listed under ``warnings``."""
    warnings: list[str] = []
    clean = json_safe(doc, "", warnings)
    if warnings:
        clean["warnings"] = list(clean.get("warnings") or []) + warnings
    return json.dumps(clean, allow_nan=False, **kwargs)


def write_json(path: Path, doc: dict) -> None:
    path.write_text(json_text(doc, indent=2) + "\n", encoding="utf-8")


def solution_doc(result, simulation=None) -> dict:
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


def verify_method(system) -> str:
    """How the command line checks a motion independently: as the system's family asks
    (:attr:`Family.cli_verify <acroplan.core.family.Family.cli_verify>`: the acrobot by the DOP853
    re-simulation, ``"ode"``), else by the family's own check where it has one (Pinocchio's
    centroidal momentum for planar and spatial bodies), else by DOP853."""
    from ...core.family import family_of
    from ...core.verify import resolve_verify

    fam = family_of(system)
    return fam.cli_verify if fam is not None and fam.cli_verify else resolve_verify(system, True)


def formats(text: str) -> tuple[str, ...]:
    fmts = tuple(f.strip().lower() for f in text.split(",") if f.strip())
    bad = [f for f in fmts if f not in FORMATS]
    if bad or not fmts:
        raise InvalidInputError("--format", f"unknown figure format {bad[0] if bad else text!r}",
                                "use png, pdf or png,pdf")
    return fmts


def check_outputs(out, force: bool, fmt: str, hint: str, inputs=()) -> tuple[str, ...]:
    """Validate --out, --force and --format before any work; returns the figure formats.

    ``inputs``: the problem files or folders read; --force must not replace a folder holding them.
    """
    if out is None:
        raise InvalidInputError("--out", "is required", f"give an output folder, for example --out {hint}")
    fmts = formats(fmt)
    check_out_dir(out, force)
    target = Path(out).absolute().resolve()
    for p in inputs:
        if p is not None and Path(p).absolute().resolve().is_relative_to(target):
            raise InvalidInputError("--out", f"{out} holds the problem {p}, which replacing it would delete",
                                    "give another output folder")
    return fmts


def import_pyplot() -> None:
    """Import ``matplotlib.pyplot`` for a command that draws, without the tables of properties
    matplotlib writes into the docstrings of its artists' ``set`` methods as it defines them (their
    text alone, from every setter's docstring: 0.15-0.2 s of a command's start, a third of pyplot's
    import); nothing drawn depends on them, and no docstring is read in a command. Library code
    (a notebook's ``help()``) never comes here."""
    if "matplotlib.pyplot" in sys.modules:
        return
    import matplotlib.artist as artist

    real = getattr(artist, "kwdoc", None)
    if real is None:  # another matplotlib: imported as it is
        import matplotlib.pyplot  # noqa: F401
        return
    artist.kwdoc = lambda cls: ""
    try:
        import matplotlib.pyplot  # noqa: F401
    finally:
        artist.kwdoc = real


class _DocAsWritten:
    """Stands for scipy's ``FunctionDoc`` in its ``xp_capabilities`` decorator
    (:func:`scipy_docs_as_written`): the decorator appends its note to the ``Notes`` list and writes
    ``str(doc)`` back, minus its first line; here that is the docstring as written."""

    def __init__(self, func):
        self._doc = getattr(func, "__doc__", None) or ""

    def __getitem__(self, section):
        return []

    def __str__(self):
        return "\n" + self._doc


class _ArrayApiLoader:
    """The loader of ``scipy._lib._array_api``, which sets :class:`_DocAsWritten` in it once executed."""

    def __init__(self, loader):
        self._loader = loader

    def create_module(self, spec):
        return self._loader.create_module(spec)

    def exec_module(self, module):
        self._loader.exec_module(module)
        if callable(getattr(module, "xp_capabilities", None)) and hasattr(module, "FunctionDoc"):
            module.FunctionDoc = _DocAsWritten


class _ArrayApiFinder:
    """Finds ``scipy._lib._array_api`` (once) with :class:`_ArrayApiLoader`."""

    NAME = "scipy._lib._array_api"

    def find_spec(self, name, path=None, target=None):
        if name != self.NAME:
            return None
        import importlib.util

        with contextlib.suppress(ValueError):
            sys.meta_path.remove(self)
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.loader is not None and hasattr(spec.loader, "exec_module"):
            spec.loader = _ArrayApiLoader(spec.loader)
        return spec


def scipy_docs_as_written() -> None:
    """Let scipy's submodules import without re-writing their functions' docstrings, in a command.

    scipy (1.17) parses the docstring of each function it marks with its array-API capabilities as
    the function is defined, and writes it again with a table appended (``xp_capabilities`` in
    ``scipy._lib._array_api``): 0.2 s of the 0.5-0.8 s that ``scipy.linalg``, ``scipy.integrate`` and
    ``scipy.optimize`` take to import, in every command that plans. Nothing computed depends on
    the table; no docstring is read in a command. So the command line (:func:`~acroplan.io.cli.app.run`)
    has that module's ``FunctionDoc`` keep each docstring as written, set when the module is first
    imported (nothing is imported here). A scipy without that decorator, or one imported already,
    is left as it is; library code (a notebook's ``help()``) never comes here."""
    if "scipy._lib._array_api" in sys.modules or any(isinstance(f, _ArrayApiFinder) for f in sys.meta_path):
        return
    sys.meta_path.insert(0, _ArrayApiFinder())


def save(figs: dict, folder: Path, fmts, *, workers: int | None = None) -> None:
    """Write each figure as ``folder/NAME.FORMAT`` (120 dpi) and close it; the stage "writing
    figures" (a PNG of a figure of many panels takes a quarter of a second and more).

    With ``workers`` = 2 (the default where the machine has two processors and ``os.fork``, Linux)
    the figures are split in two shares of about equal work (their panels) and a forked copy of
    this process writes one share while this one writes the other: the same figure objects, so the
    same bytes (``tests/test_figures.py``), in about the time of the larger share (the falling
    cat's 6-panel states figure beside its input and effort figures: ``benchmarks/RESULTS.md``,
    fourteenth session). A share the copy did not write (it failed, or took
    :data:`FORK_PATIENCE` seconds more than this process's share) is written here, so the outputs
    are whole either way; ``workers=1`` writes every figure here."""
    import matplotlib.pyplot as plt

    from ...core.progress import stage

    items = list(figs.items())
    try:
        with stage("writing figures", len(items) * len(fmts), unit="file") as st:
            mine, theirs = _shares(items, _fig_workers() if workers is None else workers)
            pid = _fork_writer(theirs, folder, fmts) if theirs else None
            _write_share(mine, folder, fmts, st)
            if theirs and not _joined(pid):
                _write_share(theirs, folder, fmts, st)  # the copy failed or was too slow: written here
            elif theirs:
                st.update(len(theirs) * len(fmts), detail="written by a second process")
    finally:
        for fig in figs.values():
            plt.close(fig)


#: Seconds :func:`save` waits for its forked writer after its own share, before writing that
#: share itself (a share takes well under a second; this is for a copy that hangs).
FORK_PATIENCE = 30.0


def _fig_workers() -> int:
    """2 where a forked copy can write figures beside this process (``os.fork``, Linux, two
    processors or more), else 1."""
    import os

    return 2 if sys.platform.startswith("linux") and hasattr(os, "fork") and (os.cpu_count() or 1) >= 2 else 1


def _shares(items: list, workers: int) -> tuple[list, list]:
    """The figures split in two shares of about equal work, counted in panels (``(all, [])`` for
    one worker or one figure): the share of the figure with the most panels stays in this process."""
    if workers < 2 or len(items) < 2:
        return items, []
    order = sorted(items, key=lambda kv: -max(1, len(kv[1].axes)))
    a, b, wa, wb = [], [], 0, 0
    for name, fig in order:
        w = max(1, len(fig.axes))
        if wa <= wb:
            a.append((name, fig))
            wa += w
        else:
            b.append((name, fig))
            wb += w
    return a, b


def _fork_writer(share: list, folder: Path, fmts) -> int | None:
    """Fork a copy of this process that writes ``share``'s figures and exits (0 when every file was
    written); its process id, ``None`` when fork failed. The copy runs nothing else: no exit
    handlers, no flushing of this process's buffers (``os._exit``)."""
    import os
    import warnings

    try:
        with warnings.catch_warnings():  # Python 3.12+ warns of fork with threads (heyoka's pool):
            warnings.simplefilter("ignore", DeprecationWarning)  # the copy runs matplotlib alone
            pid = os.fork()
    except OSError:
        return None
    if pid:
        return pid
    code = 1
    try:
        _write_share(share, folder, fmts)
        code = 0
    finally:
        os._exit(code)


def _write_share(share: list, folder: Path, fmts, st=None) -> None:
    """Write the figures ``share`` (``(name, figure)`` pairs) as ``folder/NAME.FORMAT`` at 120 dpi,
    reporting each file to the stage ``st`` when given (not in a forked copy: the stage is this
    process's)."""
    from ...core.plotting import save_figure

    for name, fig in share:
        for f in fmts:
            save_figure(fig, folder / f"{name}.{f}", f, 120)
            if st is not None:
                st.update(detail=f"{name}.{f}")


def _joined(pid: int | None) -> bool:
    """Whether the forked writer ``pid`` wrote its share: waited for up to :data:`FORK_PATIENCE`
    seconds, then killed."""
    import os
    import signal
    import time

    if pid is None:
        return False
    deadline = time.monotonic() + FORK_PATIENCE
    try:
        while True:
            done, status = os.waitpid(pid, os.WNOHANG)
            if done:
                return os.waitstatus_to_exitcode(status) == 0
            if time.monotonic() > deadline:
                os.kill(pid, signal.SIGKILL)
                os.waitpid(pid, 0)
                return False
            time.sleep(0.005)
    except (ChildProcessError, ProcessLookupError):  # reaped elsewhere (SIGCHLD ignored): not known written
        return False


@contextlib.contextmanager
def progress(quiet: bool = False):
    """The command's progress (:mod:`acroplan.core.progress`), active for the whole command: one
    line on stderr per stage that lasts more than half a second (planning, the independent check,
    the effort summary, sampling, figures, animation frames), refreshed at least every quarter
    second, and watched (``Progress(watch=True)``): from the process's start to the end of the
    command the screen is never silent for more than half a second, the command's phase
    (:meth:`~acroplan.core.progress.Progress.phase`: "starting", "writing the results") shown
    between its stages; only on a terminal, and not with --quiet."""
    from ...core.progress import Progress

    prog = Progress(enabled=sys.stderr.isatty() and not quiet, file=sys.stderr, watch=True)
    try:
        with prog.active():
            yield prog
    finally:
        prog.close()


def report(summary: dict, as_json: bool, quiet: bool, lines: list[str], code: int) -> None:
    if as_json:
        click.echo(json_text(summary))
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


def option_overrides(objective, tau_max, max_coefficients=None) -> dict:
    """The ``[options]`` that --objective, --tau-max and --max-coefficients write over the problem
    file's."""
    out = {}
    if objective is not None:
        out["objective"] = objective
    if max_coefficients is not None:
        out["max_coefficients"] = int(max_coefficients)
    if tau_max:
        number, table = None, {}
        fix = "write --tau-max 50 (every joint), or --tau-max JOINT=50 once per limited joint"
        for text in tau_max:
            joint, sep, value = text.rpartition("=")
            joint, value = joint.strip(), value.strip()
            field = f"--tau-max {joint}" if sep else "--tau-max"
            if sep and not joint:
                raise InvalidInputError("--tau-max", f"{one_line(text, 80)!r} names no joint", fix)
            try:
                v = float(value)
            except ValueError:
                raise InvalidInputError(field, f"{one_line(value, 80)!r} is not a number", fix) from None
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


def override_error(e: InvalidInputError, overrides: dict) -> InvalidInputError:
    """``e`` naming the command line's option when it is about a value the option gave."""
    for key, flag in (("tau_max", "--tau-max"), ("objective", "--objective"), ("time_limit", "--time-limit"),
                      ("max_coefficients", "--max-coefficients")):
        head = f"options.{key}"
        if key in overrides and (e.field in (head, key) or e.field.startswith(head + ".")):
            rest = e.field[len(head) + 1:] if e.field.startswith(head) else ""
            fix = e.fix.replace(f"leave {head} out", f"leave {flag} out").replace(
                f"write {key} = ", f"give {flag} ").replace(f"give {key} = ", f"give {flag} ")
            return InvalidInputError(f"{flag} {rest}".strip(), e.problem, fix)
    return e


#: The command line's option that lets problem files read files outside their folder.
allow_outside_option = click.option(
    "--allow-outside", "allow_outside", multiple=True, metavar="PATH",
    type=click.Path(path_type=Path, file_okay=True, dir_okay=True),
    help="Let the problem file read files (a URDF, a yeadon file) in PATH, a folder or a file outside its own "
         "folder (repeatable). Without it, only files inside the problem file's folder are read.")


def allowed_paths(allow_outside) -> tuple:
    """The resolved paths of ``--allow-outside`` (relative to the current folder)."""
    from ...core.files import allowed_folders

    return allowed_folders("--allow-outside", [str(p) for p in allow_outside or ()], None)


def load_problem_arg(problem, example, overrides: dict | None = None, allowed=()):
    """The problem of a PROBLEM argument or ``--example NAME`` (exactly one), with ``overrides``
    (:func:`option_overrides`, ``--time-limit``) written over its ``[options]``; the files it names
    are read from its folder or the paths ``allowed`` (``--allow-outside``, resolved)."""
    from .. import examples as _examples
    from ..problem import load_problem
    if (problem is None) == (example is None):
        raise InvalidInputError("PROBLEM", "give either a problem file or --example NAME, not both or neither",
                                "for example: --example pike-dive")
    if not overrides:
        return _examples.load(example) if example is not None else load_problem(problem, allowed=allowed)
    from ..problem import load_toml, parse_problem, with_options

    try:
        if example is not None:
            return _examples.load(example, options=overrides)
        return parse_problem(with_options(load_toml(problem), overrides), name=Path(problem).stem,
                             base=Path(problem).parent, allowed=allowed)
    except InvalidInputError as e:
        raise override_error(e, overrides) from None


def documented(result):
    """``(result, solution document)``: :func:`solution_doc` within the current time budget. A budget
    spent on the effort summary makes the result ``not_converged``, with the plan's diagnostics."""
    import dataclasses

    from ...core.budget import BudgetExceeded
    from ...core.result import Status

    try:
        return result, solution_doc(result)
    except BudgetExceeded as e:
        result = dataclasses.replace(result, status=Status.NOT_CONVERGED, message=f"not converged: every segment was "
                                     f"planned and verified, but {e} before the effort summary was done (the plan: "
                                     f"{result.message})")
    return result, solution_doc(result)


def time_limit_of(prob) -> float | None:
    """The time limit of a problem's plan (its ``time_limit`` option, else plan()'s default)."""
    from ...planning import TIME_LIMIT

    return prob.options.get("time_limit", TIME_LIMIT)


def solve_in_budget(prob, **kwargs):
    """Plan ``prob`` and make its ``solution.json`` document within its time limit
    (:func:`time_limit_of`): compiling, the plan, its verification and its effort summary
    (:func:`documented`).

    Returns
    -------
    (PlanResult, dict)
        The result and its solution document (:func:`solution_doc`).
    """
    from ...core.budget import budget

    with budget(time_limit_of(prob)):
        return documented(prob.solve(**kwargs))
