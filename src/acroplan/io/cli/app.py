"""The ``acroplan`` command group and the console entry point.

The group is lazy (:class:`LazyGroup`): it knows each command by the module that defines it and
its one-line help, and imports that module only when the command runs or its own ``--help`` is
asked, so ``acroplan --help`` and ``acroplan examples`` start at once (no numerics imported: a
test counts the modules).
"""

from __future__ import annotations

import importlib
import sys

import click

from ...core.errors import EXIT_INVALID, InvalidInputError
from .common import fail

#: The commands: name -> ("module:attribute" of the click command, its one-line help, which a test
#: checks against the command's own).
COMMANDS = {
    "plan": ("acroplan.io.cli.plan:plan_cmd",
             "Plan a motion through the waypoints of PROBLEM (a TOML file) and write the results."),
    "simulate": ("acroplan.io.cli.simulate:simulate_cmd",
                 "The motion that the joint motions of PROBLEM's [simulate] table produce."),
    "reach": ("acroplan.io.cli.reach:reach_cmd",
              "Write what can be proven about theta(T) for every segment of PROBLEM."),
    "least-momentum": ("acroplan.io.cli.momentum:least_momentum_cmd",
                       "The exact least (and largest) angular momentum P0 for PROBLEM's turn, two-link body only."),
    "twist-potential": ("acroplan.io.cli.twist:twist_potential_cmd",
                        "The most twist PROBLEM's body can make in given flight times and numbers of somersaults."),
    "nilpotent": ("acroplan.io.cli.nilpotent:nilpotent_cmd",
                  "Steer the acrobot by the nilpotentization of Chapter 4, with time moving forward."),
    "animate": ("acroplan.io.cli.animate:animate_cmd",
                "Animate the motion saved in FOLDER (by acroplan plan, simulate or nilpotent)."),
    "view": ("acroplan.io.cli.view:view_cmd",
             "Write an interactive 3-D view of the motion saved in FOLDER: one self-contained HTML page."),
    "examples": ("acroplan.io.cli.examples:examples_cmd",
                 "List the bundled example problems, or print one's problem file."),
    "init": ("acroplan.io.cli.examples:init_cmd",
             "Write a commented starter problem file NAME.toml (or a copy of a bundled example, with the files it "
             "names: the diver's URDF beside it)."),
    "sweep": ("acroplan.io.sweeps.commands:sweep_cmd",
              "Compute the sweep SWEEP.toml (a problem file with a [sweep] table) into the store OUT."),
    "map": ("acroplan.io.sweeps.commands:map_cmd",
            "Draw a map of a sweep store: VALUE over the fields X and Y, as a heatmap or contours."),
}


def _load(target: str) -> click.Command:
    module, _, attr = target.partition(":")
    return getattr(importlib.import_module(module), attr)


class LazyGroup(click.Group):
    """A click group whose commands are imported when used (:data:`COMMANDS`, and the commands the
    registered families name in :attr:`Family.commands <acroplan.core.family.Family.commands>`).

    Listing the commands (``acroplan --help``) imports none of them; a command's module is imported
    when it runs or when its ``--help`` is asked.
    """

    def _lazy(self) -> dict[str, tuple[str, str]]:
        table = dict(COMMANDS)
        from ...core.family import families

        for fam in families():  # families' own commands: {name: "module:function"}
            for name, target in fam.commands.items():
                table.setdefault(name, (target, f"(the {fam.name} family's command)"))
        return table

    def list_commands(self, ctx):
        return sorted(set(super().list_commands(ctx)) | set(self._lazy()))

    def get_command(self, ctx, name):
        if name in self.commands:
            return self.commands[name]
        entry = self._lazy().get(name)
        if entry is None:
            return None
        cmd = _load(entry[0])
        self.add_command(cmd, name)
        return cmd

    def format_commands(self, ctx, formatter):
        """The commands with their one-line help, none imported."""
        table = self._lazy()
        rows = []
        for name in self.list_commands(ctx):
            if name in self.commands:
                rows.append((name, self.commands[name].get_short_help_str(formatter.width)))
            else:
                rows.append((name, table[name][1]))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)


@click.group(cls=LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="acroplan")
@click.option("--debug", is_flag=True, help="Show the traceback of an unexpected error.")
def main(debug):
    """Motion planning for free-flying bodies: the two-link acrobot of the dissertation, planar
    bodies of any number of links, bodies in 3-D (the falling cat, an astronaut, a twisting diver),
    human bodies from Yeadon's measurements or de Leva's tables (in the plane or in 3-D), and other
    control-affine systems.

    \b
    Bundled examples (acroplan examples describes them; --example NAME runs one):
      human body:    platform-dive
      3-D human:     back-full-twist, forward-double-twist, back-double-full-out
      3-D body:      falling-cat
      two-link body: pike-dive, pike-dive-limited, chapter4 (acroplan nilpotent)
      planar bodies: diver-somersault, space-robot-turn, three-rods-turn,
                     space-robot-arm-loop (acroplan simulate)

    \b
    Examples:
      acroplan examples                                  # the bundled problems
      acroplan plan --example platform-dive --out dive --animate        # a human body
      acroplan plan --example falling-cat --out cat --animate           # a body in 3-D
      acroplan view cat                                  # ... turned in the browser (cat/view.html)
      acroplan twist-potential --example back-full-twist --flight-times 1.2,1.6 --out tp   # most twist
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


def matplotlib_home() -> str:
    """Point matplotlib's configuration and cache folder (``MPLCONFIGDIR``) at a folder acroplan owns
    when the user has not set one, so that a first run writes nothing under the home folder:
    ``acroplan-matplotlib-<uid>`` in the system's temporary folder, created private (mode 0700)
    and used only when it is a real folder of this user that nobody else can write (else a fresh
    private folder, removed at exit). Returns the folder matplotlib uses."""
    import os

    if os.environ.get("MPLCONFIGDIR"):
        return os.environ["MPLCONFIGDIR"]
    import stat
    import tempfile

    uid = os.getuid() if hasattr(os, "getuid") else 0
    path = os.path.join(tempfile.gettempdir(), f"acroplan-matplotlib-{uid}")
    try:
        os.makedirs(path, mode=0o700, exist_ok=True)
        st = os.lstat(path)
        ok = stat.S_ISDIR(st.st_mode) and st.st_uid == uid and not st.st_mode & 0o022
    except OSError:
        ok = False
    if not ok:  # taken by someone else, or not a folder: a private one of this run
        import atexit
        import shutil

        path = tempfile.mkdtemp(prefix="acroplan-matplotlib-")
        atexit.register(shutil.rmtree, path, True)
    os.environ["MPLCONFIGDIR"] = path
    return path


def run():
    """Console entry point: one readable line for an unexpected error, unless --debug."""
    import os

    # one BLAS thread in the whole command (set before numpy loads its BLAS), as plan() holds while
    # it plans (acroplan.core.blas): the effort summaries and checks written beside a plan are then
    # the same bits under any machine's thread settings too; a value the environment gives is kept
    for var in ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")
    matplotlib_home()  # before matplotlib is imported
    # heyoka imported without sympy (0.3 s): an acrobot's plan needs none (acroplan.core.heyoka_import)
    from ...core import heyoka_import

    heyoka_import.WITHOUT_SYMPY = True
    # scipy's submodules imported without re-writing their docstrings (0.2 s: common.py)
    from .common import scipy_docs_as_written

    scipy_docs_as_written()

    # the command line draws to files (library code never chooses a backend); matplotlib itself is
    # imported only by the commands that draw
    os.environ["MPLBACKEND"] = "Agg"
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
        fail(str(e))
    except Exception as e:  # noqa: BLE001
        if "--debug" in sys.argv[1:]:
            raise
        fail(f"unexpected {type(e).__name__}: {e} (run with --debug for the traceback)", 1)
