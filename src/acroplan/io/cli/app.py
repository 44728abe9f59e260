"""The ``acroplan`` command group and the console entry point."""

from __future__ import annotations

import sys

import click

from ...core.errors import EXIT_INVALID, InvalidInputError
from .common import fail


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
    matplotlib_home()  # before matplotlib is imported
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
        fail(str(e))
    except Exception as e:  # noqa: BLE001
        if "--debug" in sys.argv[1:]:
            raise
        fail(f"unexpected {type(e).__name__}: {e} (run with --debug for the traceback)", 1)
