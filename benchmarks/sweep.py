"""Throughput and memory of sweeps (acroplan.run_sweep) against acroplan.plan_many, same problems,
same cores.

The sweep is a random sample of single-segment problems over the body (masses, inertias, lengths),
the angular momentum, the flight time, the start state, the joint's end and the target's relative
place in the exact reachable interval (``plan.reach``), ``conditions="free"``, ``verify=False``.
plan_many gets exactly the same problems (``Sweep.problem(i)``, built before its clock starts).

Engines, each measured in a fresh process of its own, one at a time:
  plan_many  acroplan.plan_many(problems) with worker processes: from the call to the last result
  local      acroplan.io.sweeps.run_sweep(sweep, STORE): local worker processes (the default), from
             the call to the summary: store creation, workers' start, every chunk written and
             flushed to disk, the completion record
  dask       the same through a dask.distributed LocalCluster (processes, one thread each) given as
             executor; the cluster is started before the clock, its workers compile on first use

Memory: the peak resident memory of the driver and the peak of the workers' summed resident memory,
sampled every 0.2 s (psutil).

Run:  python benchmarks/sweep.py --n 100000                  (all three engines, 2 workers)
      python benchmarks/sweep.py --n 100000 --repeat 3       (three rounds, engines in rotation)
      python benchmarks/sweep.py --n 20000 --engines local,dask   (memory at another size)
      python benchmarks/sweep.py --engine local --n 1000      (one engine, in this process)
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import shutil
import subprocess
import sys
import tempfile
import threading
import time


import acroplan

SAMPLE = {"torso_mass": [5, 60], "leg_mass": [5, 60], "torso_length": [0.2, 0.6], "leg_length": [0.2, 0.6],
          "torso_inertia": [0.07, 7.2], "leg_inertia": [0.07, 7.2], "P0": [0.5, 30], "T": [0.5, 3],
          "theta[0]": [-math.pi, math.pi], "phi[0]": [-math.pi, math.pi], "phi[-1]": [-math.pi, math.pi],
          "reach": [0.02, 0.98]}


def make_sweep(n: int, seed: int, chunk: int):
    from acroplan.sweeps import sweep

    robot = acroplan.Acrobot.from_physical(torso_mass=40, leg_mass=20, torso_inertia=1.8, leg_inertia=1.2,
                                           torso_length=0.35, leg_length=0.45, angular_momentum=10)
    base = dict(system=robot, times=[0, 1], theta=[0, 1], phi=[0, 1], conditions="free", verify=False)
    return sweep(base, sample={"n": n, "seed": seed, **SAMPLE}, chunk_size=chunk)


class Memory:
    """Peak resident memory of this process and of its descendants (summed), sampled."""

    def __init__(self, every=0.2):
        import psutil

        self.me = psutil.Process()
        self.driver = self.workers = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, args=(every,), daemon=True)

    def _run(self, every):
        import psutil

        while not self._stop.is_set():
            try:
                self.driver = max(self.driver, self.me.memory_info().rss)
                total = 0
                for p in self.me.children(recursive=True):
                    try:
                        total += p.memory_info().rss
                    except psutil.Error:
                        pass
                self.workers = max(self.workers, total)
            except psutil.Error:
                pass
            self._stop.wait(every)

    def __enter__(self):
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._stop.set()
        self._thread.join()


def run_one(engine: str, n: int, seed: int, chunk: int, workers: int) -> dict:
    from acroplan.io.sweeps import run_sweep

    sw = make_sweep(n, seed, chunk)
    out = {"engine": engine, "n": n, "chunk": chunk, "workers": workers}
    tmp = tempfile.mkdtemp(prefix="acroplan-bench-")
    try:
        if engine == "plan_many":
            problems = [sw.problem(i) for i in range(n)]
            with Memory() as mem:
                t0 = time.perf_counter()
                res = acroplan.plan_many(problems, workers=workers)
                dt = time.perf_counter() - t0
            out["success"] = sum(r.success for r in res)
        elif engine == "local":
            with Memory() as mem:
                t0 = time.perf_counter()
                s = run_sweep(sw, os.path.join(tmp, "s.zarr"), workers=workers, progress=False)
                dt = time.perf_counter() - t0
            out["success"] = s.counts.get("success", 0)
        elif engine == "dask":
            from distributed import Client, LocalCluster

            with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                              silence_logs=40) as cluster, Client(cluster) as client:
                with Memory() as mem:
                    t0 = time.perf_counter()
                    s = run_sweep(sw, os.path.join(tmp, "s.zarr"), executor=client, progress=False)
                    dt = time.perf_counter() - t0
            out["success"] = s.counts.get("success", 0)
        else:
            raise SystemExit(f"unknown engine {engine!r}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    out.update(seconds=dt, rate=n / dt, driver_mb=mem.driver / 2**20, workers_mb=mem.workers / 2**20)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--chunk", type=int, default=1000)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--engine", help="run one engine in this process and print its JSON line")
    ap.add_argument("--engines", default="plan_many,local,dask")
    ap.add_argument("--repeat", type=int, default=1,
                    help="rounds of all engines, in rotation (the machine's load drifts: compare within a round)")
    args = ap.parse_args()
    if args.engine:
        print(json.dumps(run_one(args.engine, args.n, args.seed, args.chunk, args.workers)), flush=True)
        return
    import dask
    import xarray
    import zarr

    print(f"machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; acroplan "
          f"{acroplan.__version__}, dask {dask.__version__}, xarray {xarray.__version__}, zarr {zarr.__version__}; "
          f"{args.n} points, chunks of {args.chunk}, {args.workers} workers, seed {args.seed}", flush=True)
    for round_ in range(args.repeat):
        if args.repeat > 1:
            print(f"round {round_ + 1} of {args.repeat}", flush=True)
        rows = []
        for engine in args.engines.split(","):
            cmd = [sys.executable, __file__, "--engine", engine, "--n", str(args.n), "--seed", str(args.seed),
                   "--chunk", str(args.chunk), "--workers", str(args.workers)]
            line = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.strip().splitlines()[-1]
            r = json.loads(line)
            rows.append(r)
            print(f"{engine:10s} {r['rate']:7.0f} points/s  ({r['seconds']:.1f} s, {r['success']} success)  peak "
                  f"memory: driver {r['driver_mb']:.0f} MB, workers {r['workers_mb']:.0f} MB", flush=True)
        base = next((r for r in rows if r["engine"] == "plan_many"), None)
        if base:
            for r in rows:
                if r is not base:
                    print(f"{r['engine']}: {r['rate'] / base['rate']:.0%} of plan_many's throughput", flush=True)


if __name__ == "__main__":
    main()
