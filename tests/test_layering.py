"""The package's layering: core <- families <- front doors <- I/O, and no import circles.

Also: the bundled examples give the numbers they gave before the layering move (issue #10), which
are recorded in tests/data/baseline/.
"""

import ast
import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

from acroplan.io.cli import main
from click.testing import CliRunner

SRC = pathlib.Path(__file__).parents[1] / "src" / "acroplan"
BASELINE = pathlib.Path(__file__).parent / "data" / "baseline"

FRONT_DOORS = {"acroplan.planning", "acroplan.batch", "acroplan.simulation", "acroplan.sweep", "acroplan.zoo"}


def _module_name(path: pathlib.Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _rank(module: str) -> int:
    if module.startswith("acroplan.core"):
        return 0
    if module.startswith("acroplan.families"):
        return 1
    if module in FRONT_DOORS:
        return 2
    if module.startswith("acroplan.io") or module == "acroplan.__main__":
        return 3
    return 4  # the package's own __init__ (lazy names only)


def _imports(path: pathlib.Path):
    """Every acroplan module ``path`` imports, anywhere in the file, with whether at top level."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    top = {id(n) for n in tree.body}
    typing_only = {id(n) for block in ast.walk(tree)  # `if TYPE_CHECKING:` imports never run
                   if isinstance(block, ast.If) and getattr(block.test, "id", None) == "TYPE_CHECKING"
                   for n in ast.walk(block)}
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            targets = [target] + [f"{target}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        else:
            continue
        for t in targets:
            if t.startswith("acroplan") and (SRC.parent / (t.replace(".", "/") + ".py")).exists() or \
                    (SRC.parent / t.replace(".", "/") / "__init__.py").exists():
                yield t, id(node) in top


MODULES = sorted(p for p in SRC.rglob("*.py"))


def test_imports_point_one_way():
    bad = []
    for path in MODULES:
        me = _module_name(path)
        for target, _ in _imports(path):
            if _rank(target) > _rank(me) and _rank(me) < 4:
                bad.append(f"{me} -> {target}")
    assert not bad, "imports against the layering: " + ", ".join(bad)


def test_no_import_circles():
    graph = {_module_name(p): {t for t, _ in _imports(p)} for p in MODULES}
    # a package imports its parents implicitly; only edges between distinct modules count
    state, stack = {}, []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt == node or node.startswith(nxt + ".") or nxt not in graph:
                continue
            if state.get(nxt) == 1:
                cycle = stack[stack.index(nxt):] + [nxt]
                pytest.fail("import circle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)


def test_the_core_imports_alone():
    code = ("import sys, acroplan.core, acroplan.core.verify, acroplan.core.plotting, acroplan.core.lie\n"
            "print('\\n'.join(m for m in sys.modules if m.startswith('acroplan')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    assert "acroplan.core.strategies" in out
    foreign = [m for m in out if _rank(m) > 0 and m != "acroplan"]
    assert not foreign, foreign


def _numbers(doc, keys=("basis_coefficients", "t0", "t1", "final_error", "max_abs_u", "state_range")):
    """The numbers a plan's solution.json records per segment."""
    out = []
    for seg in doc["segments"]:
        for key in keys:
            v = seg[key]
            if isinstance(v, dict):
                v = [x for row in v.values() for x in row]
            out.append(np.atleast_1d(np.asarray(v if v is not None else [], dtype=float)))
    return np.concatenate(out)


@pytest.mark.parametrize("name", ["pike-dive", "pike-dive-limited"])
def test_bundled_examples_give_the_recorded_numbers(tmp_path, name):
    res = CliRunner().invoke(main, ["plan", "--example", name, "--out", str(tmp_path / "o"), "--no-plots", "--quiet"])
    assert res.exit_code == 0, res.output
    new = json.loads((tmp_path / "o" / "solution.json").read_text())
    old = json.loads((BASELINE / f"{name}.json").read_text())
    assert new["status"] == old["status"] and len(new["segments"]) == len(old["segments"])
    assert new["waypoints"] == old["waypoints"] and new["system"] == old["system"]
    # the coefficients, times and extremes bit for bit; endpoint errors are ~1e-14 values
    keys = ("basis_coefficients", "t0", "t1", "max_abs_u", "state_range")
    assert np.array_equal(_numbers(new, keys), _numbers(old, keys))
    assert np.allclose(_numbers(new, ("final_error",)), _numbers(old, ("final_error",)), rtol=1e-6, atol=1e-15)
    for a, b in zip(new["segments"], old["segments"]):
        assert (a["iterations"], a["evaluations"], a["method"]) == (b["iterations"], b["evaluations"], b["method"])


def test_bundled_nilpotent_example_gives_the_recorded_numbers(tmp_path):
    res = CliRunner().invoke(main, ["nilpotent", "--example", "chapter4", "--out", str(tmp_path / "o"),
                                    "--no-plots", "--quiet"])
    assert res.exit_code == 0, res.output
    new = json.loads((tmp_path / "o" / "solution.json").read_text())
    old = json.loads((BASELINE / "chapter4.json").read_text())
    assert new["status"] == old["status"] and new["coefficients"] == old["coefficients"]
    assert new["u1_margin"] == old["u1_margin"]
