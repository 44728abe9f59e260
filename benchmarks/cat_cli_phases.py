"""Where the processor time of ``acroplan plan --example falling-cat`` goes (issue #22: <= 3 s warm
with every output), phase by phase, in one process that makes the command line's own calls in its
order: the imports, reading the example, the plan and its Pinocchio check, the effort summary of
solution.json, trajectory.csv, importing pyplot, drawing the figures, writing the PNGs (as the
command line does: in two shares, one written by a forked copy where the machine allows it).

Run it after one ``acroplan plan --example falling-cat`` (warm: heyoka's disk cache and the stored
compiled functions filled); ``time.process_time()`` around each phase, so the figures are CPU
seconds, steadier than wall time on a shared machine. The outputs go to a temporary folder.

    python benchmarks/cat_cli_phases.py
"""

from __future__ import annotations

import os
import time

T = [("start", time.process_time())]


def mark(name: str) -> None:
    T.append((name, time.process_time()))


def main() -> None:
    import tempfile
    from pathlib import Path

    os.environ["MPLBACKEND"] = "Agg"  # as the command line does
    import acroplan.io.cli.app  # noqa: F401
    from acroplan.io.cli.common import scipy_docs_as_written

    scipy_docs_as_written()  # as acroplan.io.cli.app.run does first
    import acroplan.io.problem  # noqa: F401

    mark("imports: the command line, the problem reader")
    from acroplan.io import examples

    prob = examples.load("falling-cat")
    mark("reading the example")
    from acroplan.core import backend
    from acroplan.families.spatial import check

    checks, loads = [], []
    real_check, real_load = check.pinocchio_errors, backend._stored_or_built

    def timed_check(*a, **k):
        t = time.process_time()
        out = real_check(*a, **k)
        checks.append(time.process_time() - t)
        return out

    def timed_load(*a):
        t = time.process_time()
        out = real_load(*a)
        loads.append(time.process_time() - t)
        return out

    check.pinocchio_errors, backend._stored_or_built = timed_check, timed_load
    result = prob.solve()
    mark("plan + check")
    result.to_dict()
    mark("effort summary (solution.json)")
    from acroplan.core.plotting import plot_result
    from acroplan.io.cli.common import import_pyplot, save
    from acroplan.io.cli.plan import write_csv

    with tempfile.TemporaryDirectory() as tmp:
        samples = write_csv(result, Path(tmp) / "trajectory.csv")
        mark("trajectory.csv (600 samples)")
        import_pyplot()
        mark("import pyplot")
        figs = plot_result(result, effort=result.has_torques, samples=samples)
        mark("drawing the figures")
        wall = time.perf_counter()
        save(figs, Path(tmp), ["png"])  # the command line's own call: two shares, one in a forked copy
        wall = time.perf_counter() - wall
        mark("writing the PNGs")
    for (name, c), (_, c0) in zip(T[1:], T[:-1]):
        if name == "plan + check":
            print(f"{c - c0 - sum(checks):.3f}\tplanning (of which {sum(loads):.3f} reading "
                  f"{len(loads)} compiled functions)")
            print(f"{sum(checks):.3f}\tPinocchio check")
        elif name == "writing the PNGs":
            print(f"{c - c0:.3f}\t{name} (this process's share; {wall:.3f} s of wall time for both)")
        else:
            print(f"{c - c0:.3f}\t{name}")
    print(f"{T[-1][1] - T[0][1]:.3f}\ttotal")


if __name__ == "__main__":
    main()
