"""The sweep driver's memory against the number of grid points (issue #25: it grew with them).

For each size, twice, each time in a fresh process with the packages already imported: define a
sweep of a two-axis grid (flight time x momentum, both ``{start, stop, num}``; docs/sweeps.md's
dive, the derived least momentum only, ``plan = false``), create its store, run it until
``--chunks`` chunks are done (the progress callback stops it), resume it for as many more, and open
it (every chunk done is read back and checked against its checksum, in the resume and the open):

* ``rss``: on local worker processes; the driver's peak resident memory (``ru_maxrss``) and its
  growth over the resident memory after the imports;
* ``traced``: in the driver alone (``executor="serial"``: the same store, record and checks), the
  peak of its traced Python and numpy allocations (tracemalloc, started after the imports; tracing
  forked workers would slow them).

The driver's numbers (definition, creation, the two runs) are reported apart from the open's: a
reader holds the grid's coordinates (an index per axis, as any xarray Dataset) and the lazy
arrays' graph (one block per 2**20 points), which do grow with the grid.

Also the size of the store's zarr.json and of its completion record. A size over the limit
(``acroplan.sweeps.MAX_POINTS``) is refused before anything is allocated: the row shows the
refusal, and ``acroplan sweep`` exits 2 naming the number.

Run:  python benchmarks/sweep_memory.py                          (1e3, 1e6, 1e8 and 1e9 points)
      python benchmarks/sweep_memory.py --sizes 1e3,1e6,1e9 --chunks 8 --chunk-size 250 --workers 2
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time
import tracemalloc


class _Enough(Exception):
    """Raised by the progress callback to stop a run after its chunks."""


def _grid(n: int) -> dict:
    """About ``n`` points: T x P0 with P0 ten values, T the rest."""
    n_p0 = 10 if n >= 100 else 1
    return {"T": {"start": 1.0, "stop": 2.0, "num": max(1, n // n_p0)}, "P0": {"start": 60.0, "stop": 120.0,
                                                                              "num": n_p0}}


def _stop_after(points: int):
    def progress(done, total):
        if done >= points:
            raise _Enough()
    return progress


def _rss_mb() -> float:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def run_size(n: int, chunks: int, workers: int, chunk_size: int, mode: str) -> dict:
    import acroplan
    import dask.array  # noqa: F401  (imported before the baseline: what open_sweep and run_sweep use)
    import xarray  # noqa: F401
    import zarr  # noqa: F401
    from acroplan.core.errors import InvalidInputError

    # docs/sweeps.md's dive: 3.5 somersaults in pike, the least momentum over flight times and momenta
    robot = acroplan.Acrobot.from_physical(torso_mass=45.0, leg_mass=25.0, torso_inertia=2.1, leg_inertia=1.7,
                                           torso_length=0.35, leg_length=0.45, angular_momentum=60.0)
    base = dict(system=robot, times=[0, 1.5], theta=[0, 7 * math.pi], phi=[-math.pi, -math.pi], conditions="free",
                phi_min=-2 * math.pi + 0.6, phi_max=-math.pi, u_max=12.0)
    out = {"points": n, "mode": mode, "baseline_mb": _rss_mb()}
    tmp = tempfile.mkdtemp(prefix="acroplan-sweep-memory-")
    run = dict(executor="serial") if mode == "traced" else dict(workers=workers)
    if mode == "traced":
        tracemalloc.start()
    try:
        try:
            sw = acroplan.sweep(base, grid=_grid(n), plan=False, derived=["least_P0"], chunk_size=chunk_size)
        except InvalidInputError as e:
            out.update(refused=str(e))
            return out
        store = os.path.join(tmp, "s.zarr")
        step = min(sw.size, chunks * sw.chunk_size)
        for k in (1, 2):
            try:
                acroplan.run_sweep(sw, store, progress=_stop_after(min(sw.size, k * step)), **run)
            except _Enough:
                pass
        out["driver_maxrss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        if mode == "traced":
            out["driver_traced_mb"] = tracemalloc.get_traced_memory()[1] / 2**20
            tracemalloc.reset_peak()
        ds = acroplan.open_sweep(store)
        out.update(size=sw.size, chunks=sw.n_chunks, chunks_done=int(ds.attrs["chunks_done"]),
                   zarr_json=os.path.getsize(os.path.join(store, "zarr.json")),
                   record=os.path.getsize(os.path.join(store, "acroplan-sweep.json")))
    finally:
        if mode == "traced":
            out["traced_peak_mb"] = tracemalloc.get_traced_memory()[1] / 2**20  # the open's, or the refusal's
            tracemalloc.stop()
        shutil.rmtree(tmp, ignore_errors=True)
        out["maxrss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return out


def _cli_refusal(n: int) -> tuple[int, str]:
    """``acroplan sweep`` on a file asking for ``n`` points: its exit code and message."""
    tmp = tempfile.mkdtemp(prefix="acroplan-sweep-memory-")
    try:
        path = os.path.join(tmp, "big.toml")
        g = _grid(n)
        with open(path, "w") as f:
            f.write('[robot]\ntorso_mass = 45.0\nleg_mass = 25.0\ntorso_inertia = 2.1\nleg_inertia = 1.7\n'
                    'torso_length = 0.35\nleg_length = 0.45\nangular_momentum = 60.0\n\n[plan]\ntimes = [0, 1.5]\n'
                    'theta = [0, "7*pi"]\nphi = ["-pi", "-pi"]\nconditions = "free"\n\n[sweep]\nplan = false\n'
                    'derived = ["least_P0"]\n\n[sweep.grid]\n'
                    f'T = {{start = 1.0, stop = 2.0, num = {g["T"]["num"]}}}\n'
                    f'P0 = {{start = 60.0, stop = 120.0, num = {g["P0"]["num"]}}}\n')
        run = subprocess.run([sys.executable, "-m", "acroplan", "sweep", path, "--out", os.path.join(tmp, "s.zarr")],
                             capture_output=True, text=True)
        return run.returncode, run.stderr.strip()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _measure(n: int, args, mode: str) -> dict:
    cmd = [sys.executable, __file__, "--one", str(n), "--mode", mode, "--chunks", str(args.chunks), "--workers",
           str(args.workers), "--chunk-size", str(args.chunk_size)]
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.strip().splitlines()[-1])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", default="1e3,1e6,1e8,1e9")
    ap.add_argument("--chunks", type=int, default=8, help="chunks per run (two runs: the second resumes)")
    ap.add_argument("--chunk-size", type=int, default=250)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--one", type=float, help="measure this size in this process and print its JSON line")
    ap.add_argument("--mode", choices=["rss", "traced"], default="rss")
    args = ap.parse_args()
    if args.one:
        print(json.dumps(run_size(int(args.one), args.chunks, args.workers, args.chunk_size, args.mode)), flush=True)
        return
    import acroplan

    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, acroplan "
          f"{acroplan.__version__}; {args.workers} workers, chunks of {args.chunk_size}, {args.chunks} chunks per "
          "run, two runs (the second resumes), then open_sweep", flush=True)
    for size in args.sizes.split(","):
        n = int(float(size))
        t0 = time.perf_counter()
        r, t = _measure(n, args, "rss"), _measure(n, args, "traced")
        wall = time.perf_counter() - t0
        if "refused" in r:
            code, message = _cli_refusal(n)
            print(f"{n:>13,d} points: refused before any allocation; driver peak RSS {r['maxrss_mb']:.0f} MB "
                  f"(+{r['maxrss_mb'] - r['baseline_mb']:.0f} MB over the imports), traced peak "
                  f"{t['traced_peak_mb']:.2f} MB; acroplan sweep: exit {code}", flush=True)
            print(f"{'':>22}{message}", flush=True)
            continue
        print(f"{r['size']:>13,d} points ({r['chunks']:,d} chunks, {r['chunks_done']} done): driver (define, "
              f"create, run, resume) peak RSS {r['driver_maxrss_mb']:.0f} MB (+"
              f"{r['driver_maxrss_mb'] - r['baseline_mb']:.0f} MB over the imports), traced peak "
              f"{t['driver_traced_mb']:.1f} MB; open_sweep after it: peak RSS {r['maxrss_mb']:.0f} MB, traced peak "
              f"{t['traced_peak_mb']:.1f} MB; zarr.json {r['zarr_json'] / 1024:.1f} KB, record {r['record']} B; "
              f"{wall:.0f} s", flush=True)


if __name__ == "__main__":
    main()
