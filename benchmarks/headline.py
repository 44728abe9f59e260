"""The README's headline command, cold and warm (issue #24): wall times of a fresh process each.

Cold: an empty heyoka cache (``ACROPLAN_HEYOKA_CACHE`` set to a new empty folder, so every
integrator the plan needs is compiled anew) and a fresh process. Warm: the same cache, filled by the
cold run, and a fresh process. The load average is printed before each run (a shared machine)::

    python benchmarks/headline.py --repeat 3
    python benchmarks/headline.py --repeat 3 -- plan --example pike-dive --out OUT --force --no-plots

``OUT`` in the command is replaced by a temporary folder.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HEADLINE = ["plan", "--example", "platform-dive", "--out", "OUT", "--force"]


def run(cmd: list[str], cache: Path, out: Path) -> tuple[float, float, int]:
    """``(wall s, CPU s of the process: user + system, exit code)``."""
    env = {**os.environ, "ACROPLAN_HEYOKA_CACHE": str(cache)}
    args = [str(out) if c == "OUT" else c for c in cmd]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "acroplan", *args], env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if done.returncode != 0:
        print(f"exit {done.returncode}: {done.stderr.strip()[-300:]}", flush=True)
    return wall, cpu, done.returncode


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("command", nargs="*", help="acroplan's arguments (default: the README's headline)")
    args = ap.parse_args(argv)
    cmd = args.command or HEADLINE
    cold, warm = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.repeat):
            cache, out = Path(tmp) / f"cache{k}", Path(tmp) / f"out{k}"
            cache.mkdir()
            load = os.getloadavg()[0]
            cold.append(run(cmd, cache, out))
            load2 = os.getloadavg()[0]
            warm.append(run(cmd, cache, out))
            print(f"run {k}: cold {cold[-1][0]:.2f} s wall, {cold[-1][1]:.2f} s CPU, exit {cold[-1][2]} (load "
                  f"{load:.1f}); warm {warm[-1][0]:.2f} s wall, {warm[-1][1]:.2f} s CPU, exit {warm[-1][2]} (load "
                  f"{load2:.1f})", flush=True)
    print(f"acroplan {' '.join(cmd)}")
    for name, v in (("cold", cold), ("warm", warm)):
        wall, cpu = [w for w, _, _ in v], [c for _, c, _ in v]
        print(f"{name}: wall median {statistics.median(wall):.2f} s (least {min(wall):.2f}, largest {max(wall):.2f}), "
              f"CPU median {statistics.median(cpu):.2f} s, {len(v)} runs")


if __name__ == "__main__":
    main()
