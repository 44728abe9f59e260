"""Where the seconds of one command line run go (issue #24: the pike dive's cold plan without
plots): the interpreter's start, the imports, reading the problem (the family's strategies
prepared), loading the compiled integrator (from heyoka's on-disk cache: a cold process, a warm
cache), the plan, its independent check, writing the folder. One fresh process per run; the
median of ``--repeat`` runs::

    python benchmarks/startup_phases.py --repeat 5 -- plan --example pike-dive --out OUT --force --no-plots

The imports are made first, as the command makes them (heyoka without sympy, as
``acroplan.io.cli.run`` does; numpy, scipy.interpolate and scipy.integrate, which the plan's
spline conditions and its DOP853 check import when they run), so that the other phases are
their own work; each phase is timed by wrapping the function that does it.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys

_CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
from acroplan.core.progress import process_age
started = process_age()
from acroplan.core import heyoka_import
heyoka_import.WITHOUT_SYMPY = True
import numpy, scipy.interpolate, scipy.integrate  # noqa: F401 - (what the plan imports when it runs)
import acroplan.io.cli.app as app, acroplan.io.cli.common as common, acroplan.io.problem  # noqa: F401
from acroplan.core import backend, verify
import acroplan.planning  # noqa: F401
T = {"interpreter": started, "imports": time.perf_counter() - t0}
spent = {"reading": 0.0, "solve": 0.0, "compile-load": 0.0, "check": 0.0}

def timed(owner, name, key):
    inner = getattr(owner, name)
    def wrapper(*a, **k):
        s = time.perf_counter()
        try:
            return inner(*a, **k)
        finally:
            spent[key] += time.perf_counter() - s
    setattr(owner, name, wrapper)

timed(common, "load_problem_arg", "reading")
timed(common, "solve_in_budget", "solve")
timed(backend, "_compiled", "compile-load")
timed(verify, "verify_plan", "check")
import acroplan.io.cli.plan as plan_module
plan_module.load_problem_arg = common.load_problem_arg
plan_module.solve_in_budget = common.solve_in_budget
import acroplan.planning.front as front
front.verify_plan = verify.verify_plan  # (imported by name there)
t1 = time.perf_counter()
try:
    app.main(sys.argv[1:], prog_name="acroplan", standalone_mode=False)
except SystemExit:
    pass
total = time.perf_counter() - t1
T["reading"] = spent["reading"]
T["compile-load"] = spent["compile-load"]
T["check"] = spent["check"]
T["planning"] = spent["solve"] - spent["compile-load"] - spent["check"]
T["writing and the rest"] = total - spent["reading"] - spent["solve"]
T["wall in the process"] = time.perf_counter() - t0 + started
print(json.dumps(T))
"""


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("cmd", nargs=argparse.REMAINDER, help="the command's arguments (after --)")
    args = ap.parse_args(argv)
    cmd = args.cmd[1:] if args.cmd[:1] == ["--"] else args.cmd
    runs = []
    for _ in range(args.repeat):
        out = subprocess.run([sys.executable, "-c", _CHILD, *cmd], capture_output=True, text=True, check=True)
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    for key in runs[0]:
        values = [r[key] for r in runs]
        print(f"{key:22s} median {statistics.median(values):6.3f} s   ({', '.join(f'{v:.3f}' for v in values)})")


if __name__ == "__main__":
    main()
