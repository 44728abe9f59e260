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

#: The front doors: modules, or packages (every module inside one is a front door).
FRONT_DOORS = {"acroplan.planning", "acroplan.batch", "acroplan.simulation", "acroplan.sweeps", "acroplan.zoo"}


def _module_name(path: pathlib.Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _rank(module: str) -> int:
    if module.startswith("acroplan.core"):
        return 0
    if module.startswith("acroplan.families"):
        return 1
    if module in FRONT_DOORS or any(module.startswith(door + ".") for door in FRONT_DOORS):
        return 2
    if module.startswith("acroplan.io") or module == "acroplan.__main__":
        return 3
    return 4  # the package's own __init__ (lazy names only)


def _is_module(name: str) -> bool:
    base = SRC.parent / name.replace(".", "/")
    return base.with_suffix(".py").exists() or (base / "__init__.py").exists()


def _package_of(module: str) -> str:
    return module if (SRC.parent / module.replace(".", "/") / "__init__.py").exists() else module.rsplit(".", 1)[0]


def _imports(path: pathlib.Path):
    """Every acroplan module ``path`` imports, counted strictly: anywhere in the file (function
    level and ``if TYPE_CHECKING:`` blocks too); ``from P import name`` is an edge to the module
    ``P.name`` when there is one, else to ``P`` itself (a package's ``__init__`` when ``P`` is a
    package: importing a name a package defines imports its ``__init__``). Yields ``(target,
    imported names)``."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("acroplan"):
                continue
            for a in node.names:
                sub = f"{target}.{a.name}"
                yield (sub, ()) if _is_module(sub) else (target, (a.name,))
        elif isinstance(node, ast.Import):
            for a in node.names:
                if a.name.startswith("acroplan") and _is_module(a.name):
                    yield a.name, ()


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
    """No circle of imports of any kind: function-level, under TYPE_CHECKING, or through a package's
    ``__init__`` (a module importing a name its own package defines, which that package imports)."""
    graph = {_module_name(p): {t for t, _ in _imports(p)} for p in MODULES}
    state, stack = {}, []

    def visit(node):
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt == node or nxt not in graph:
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


def test_no_private_name_is_imported_across_packages():
    bad = []
    for path in MODULES:
        me = _module_name(path)
        mine = me if path.name == "__init__.py" else me.rsplit(".", 1)[0]
        for target, names in _imports(path):
            for n in names:
                if n.startswith("_") and not n.startswith("__") and _package_of(target) != mine:
                    bad.append(f"{me} imports {target}.{n}")
    assert not bad, "private names imported across packages: " + ", ".join(bad)


def _family_classes() -> set[str]:
    from acroplan.core.family import families

    return {t.__name__ for fam in families() for t in fam.classes()} | {"SagittalBody"}


def test_outside_the_families_no_family_type_is_tested():
    """The I/O layer, the front doors and the core name no family (issue #21): no isinstance or
    issubclass of a family class, no type-name string of one."""
    names = _family_classes()
    bad = []
    for path in MODULES:
        me = _module_name(path)
        if me.startswith("acroplan.families") or me == "acroplan":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and getattr(node.func, "id", None) in ("isinstance", "issubclass"):
                for arg in ast.walk(node.args[1]) if len(node.args) > 1 else ():
                    if isinstance(arg, (ast.Name, ast.Attribute)) and getattr(arg, "id", getattr(arg, "attr", "")) in names:
                        bad.append(f"{me}:{node.lineno} {ast.unparse(node)}")
            if isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value in names:
                bad.append(f"{me}:{node.lineno} {node.value!r}")
    assert not bad, "family types named outside families/: " + "; ".join(bad)


def test_one_table_of_plan_keywords():
    """plan() and simulate() take exactly the keywords of acroplan.core.keywords (families refuse
    joint names that clash with them)."""
    import inspect

    import acroplan
    from acroplan.core.keywords import PLAN_KEYWORDS, RESERVED_NAMES, SIMULATE_KEYWORDS

    plan = [p for p in inspect.signature(acroplan.plan).parameters if p not in ("system", "waypoints")]
    sim = [p for p in inspect.signature(acroplan.simulate).parameters if p not in ("system", "initial")]
    assert tuple(plan) == PLAN_KEYWORDS and tuple(sim) == SIMULATE_KEYWORDS
    from acroplan.families.planar.links import RESERVED_NAMES as planar
    from acroplan.families.spatial.links import RESERVED_NAMES as spatial

    assert RESERVED_NAMES <= planar and RESERVED_NAMES <= spatial


def test_the_core_imports_alone():
    code = ("import sys, acroplan.core, acroplan.core.verify, acroplan.core.plotting, acroplan.core.lie, "
            "acroplan.core.strategies, acroplan.core.optimal\n"
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


#: Tolerances for numbers recorded on another machine. heyoka compiles for the host processor and BLAS
#: picks kernels per processor, so an endpoint evaluation differs between machines in its last bits
#: (a few ulps of the state). A plan's coefficients solve Phi(c) = x_T; a change dx of the endpoint
#: map moves the solution by about |dx| / sigma_min (the reduced Jacobian's smallest singular value,
#: recorded per segment). With |dx| <= ENDPOINT_ULPS (1e-13: the polish level, ~500 ulps of the
#: states) the coefficients may differ by 1e-13 (1 + max|c|) / sigma_min, here at most ~3e-11;
#: measured between two x86-64 processors (an AVX-512 EPYC and the recording machine): 3.6e-14.
#: Any change of the algorithm moves them by far more (a different Newton path: ~1e-3).
ENDPOINT_ULPS = 1e-13


def _close_segments(new, old):
    for a, b in zip(new["segments"], old["segments"]):
        assert a["basis_coefficients"].keys() == b["basis_coefficients"].keys()
        ca = np.concatenate([np.asarray(v, float) for v in a["basis_coefficients"].values()])
        cb = np.concatenate([np.asarray(v, float) for v in b["basis_coefficients"].values()])
        tol = ENDPOINT_ULPS * (1 + np.abs(cb).max()) / min(1.0, b["sigma_min"])
        assert ca.shape == cb.shape and np.abs(ca - cb).max() <= tol, (b["index"], np.abs(ca - cb).max(), tol)
        # times are data of the problem (exact); extremes are functions of the coefficients, |u| of
        # a Legendre series is Lipschitz in c with constant sum |P_i| <= n on [0, 1]
        assert (a["t0"], a["t1"]) == (b["t0"], b["t1"])
        assert abs(a["max_abs_u"] - b["max_abs_u"]) <= ca.size * tol
        if b["state_range"] is not None:  # the limited joint's range over the segment
            assert np.allclose(a["state_range"], b["state_range"], rtol=0, atol=ca.size * tol * (b["t1"] - b["t0"]))
        # endpoint errors are rounding-level numbers (~1e-14): compared as such
        assert a["final_error"] <= 1e-12 and b["final_error"] <= 1e-12
        # the solver took the same route: the method, and the counts (a last-bit difference could
        # move one convergence comparison, so one evaluation either way is allowed)
        assert a["method"] == b["method"]
        assert abs(a["iterations"] - b["iterations"]) <= 1 and abs(a["evaluations"] - b["evaluations"]) <= 1


@pytest.mark.parametrize("name", ["pike-dive", "pike-dive-limited"])
def test_bundled_examples_give_the_recorded_numbers(tmp_path, name):
    res = CliRunner().invoke(main, ["plan", "--example", name, "--out", str(tmp_path / "o"), "--no-plots", "--quiet"])
    assert res.exit_code == 0, res.output
    new = json.loads((tmp_path / "o" / "solution.json").read_text())
    old = json.loads((BASELINE / f"{name}.json").read_text())
    assert new["status"] == old["status"] and len(new["segments"]) == len(old["segments"])
    assert new["waypoints"] == old["waypoints"] and new["system"] == old["system"]
    _close_segments(new, old)


def test_bundled_examples_are_deterministic(tmp_path):
    """Bit for bit where it is promised: the same input twice on one machine, in one process."""
    runs = []
    for k in range(2):
        res = CliRunner().invoke(main, ["plan", "--example", "pike-dive-limited", "--out", str(tmp_path / f"o{k}"),
                                        "--no-plots", "--quiet"])
        assert res.exit_code == 0, res.output
        doc = json.loads((tmp_path / f"o{k}" / "solution.json").read_text())
        runs.append(_numbers(doc, ("basis_coefficients", "final_error", "max_abs_u")))
    assert np.array_equal(runs[0], runs[1])


def test_bundled_nilpotent_example_gives_the_recorded_numbers(tmp_path):
    res = CliRunner().invoke(main, ["nilpotent", "--example", "chapter4", "--out", str(tmp_path / "o"),
                                    "--no-plots", "--quiet"])
    assert res.exit_code == 0, res.output
    new = json.loads((tmp_path / "o" / "solution.json").read_text())
    old = json.loads((BASELINE / "chapter4.json").read_text())
    assert new["status"] == old["status"] and new["coefficients"].keys() == old["coefficients"].keys()
    # The coefficients are roots of the nilpotent system's endpoint equations (polynomials with
    # coefficients from the compiled integrator), polished by Newton to machine precision; their
    # Jacobian is well conditioned here, so a few ulps of difference in the integrals give a few
    # ulps here: 1e-12 relative to the largest coefficient is 100x the 1.0e-14 measured between
    # two processors (v1[0]: 0.8980524143132835 against 0.8980524143132734).
    for key, old_v in old["coefficients"].items():
        new_v, old_v = np.asarray(new["coefficients"][key]), np.asarray(old_v)
        assert np.abs(new_v - old_v).max() <= 1e-12 * np.abs(old_v).max(), key
    assert new["u1_margin"] == pytest.approx(old["u1_margin"], rel=1e-12)


def test_names_that_moved_still_work_with_a_warning():
    """Public names that moved keep working for one release, naming the new place (issue #21)."""
    import acroplan

    with pytest.warns(DeprecationWarning, match="acroplan.families.acrobot.nilpotent"):
        from acroplan import nilpotent
    assert nilpotent.__name__ == "acroplan.families.acrobot.nilpotent" and hasattr(nilpotent, "NilpotentProblem")
    robot = acroplan.examples.robot("pike-dive")
    with pytest.warns(DeprecationWarning, match=r"reachable_set\(\.\.\.\)\.interval"):
        lo, hi = acroplan.reachable_interval(robot, theta0=0.0, phi0=-3.0, phiT=-1.0, T=1.0)
    assert (lo, hi) == acroplan.reachable_set(robot, theta0=0.0, phi0=-3.0, phiT=-1.0, T=1.0).interval
