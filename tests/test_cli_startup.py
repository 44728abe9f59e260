"""The command line starts at once (issue #24): ``acroplan --help``, every command's ``--help`` and
``acroplan examples`` import none of the numerics. Counted, not timed: the heavy modules in
``sys.modules`` of a fresh interpreter after the command (timings: benchmarks/RESULTS.md)."""

import json
import subprocess
import sys

import click
import pytest

from acroplan.io.cli import COMMANDS, main

#: Modules whose import takes tenths of a second to seconds, none of which parsing needs.
HEAVY = ("heyoka", "sympy", "scipy", "matplotlib", "pinocchio", "numpy", "xarray", "zarr", "dask", "yeadon",
         "biorbd", "plotly")

_PROBE = """
import json, sys
from acroplan.io.cli.app import main
try:
    main(sys.argv[1:], prog_name="acroplan", standalone_mode=False)
except SystemExit:
    pass
heavy = sorted({m.split(".")[0] for m in sys.modules} & set(json.loads(sys.stdin.readline())))
print(json.dumps({"heavy": heavy, "acroplan": sorted(m for m in sys.modules if m.startswith("acroplan"))}))
"""


def _modules_after(*args):
    out = subprocess.run([sys.executable, "-c", _PROBE, *args], input=json.dumps(HEAVY) + "\n",
                         capture_output=True, text=True, check=True).stdout
    return json.loads(out.splitlines()[-1])


@pytest.mark.parametrize("args", [["--help"], ["examples"], ["examples", "--show", "falling-cat"]]
                         + [[name, "--help"] for name in COMMANDS], ids=lambda a: " ".join(a))
def test_help_and_examples_import_no_numerics(args):
    seen = _modules_after(*args)
    assert seen["heavy"] == [], seen["heavy"]
    # and no family's numerics: of the families, only the descriptors (family.py) and the packages'
    # lazy __init__
    numerics = [m for m in seen["acroplan"] if m.startswith("acroplan.families.") and m.count(".") > 2
                and not m.endswith(".family")]
    assert numerics == [], numerics


def test_the_top_level_help_imports_no_command():
    seen = _modules_after("--help")
    commands = {target.partition(":")[0] for target, _ in COMMANDS.values()}
    assert not commands & set(seen["acroplan"])


def test_the_lazy_table_says_what_each_command_says():
    for name, (target, short) in COMMANDS.items():
        cmd = main.get_command(click.Context(main), name)
        assert cmd.name == name
        assert cmd.get_short_help_str(limit=10_000) == short, name


def test_the_help_names_every_family_and_bundled_example():
    from acroplan.io import examples

    text = main.get_help(click.Context(main, info_name="acroplan"))
    for name in examples.names():
        assert name in text, name
    for words in ("two-link", "planar", "3-D", "human"):
        assert words in text, words


def test_examples_rows_are_aligned():
    from acroplan.io.cli.examples import example_rows

    rows = example_rows({"a": "one", "a-much-longer-name": "two " * 40}, width=80)
    assert rows[0].index("one") == rows[1].index("two") == len("a-much-longer-name") + 2
    assert all(len(r) <= 80 for r in rows) and len(rows) > 2
    assert all(r.startswith(" " * (len("a-much-longer-name") + 2)) for r in rows[2:])
