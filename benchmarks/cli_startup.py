"""How long the command line takes to answer ``--help`` and ``acroplan examples`` (issue #24).

Each command runs ``--repeat`` times in a fresh interpreter (``python -m acroplan ...``); the
median, least and largest wall times are printed. ``--src`` runs another checkout's sources (the
"before" of benchmarks/RESULTS.md: ``git archive 8da7203 src | tar -x -C /tmp/before``)::

    python benchmarks/cli_startup.py --repeat 5
    python benchmarks/cli_startup.py --repeat 5 --src /tmp/before/src
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import time

COMMANDS = [["--help"], ["examples"], ["plan", "--help"], ["simulate", "--help"], ["reach", "--help"],
            ["least-momentum", "--help"], ["nilpotent", "--help"], ["animate", "--help"], ["view", "--help"],
            ["examples", "--help"], ["init", "--help"], ["sweep", "--help"], ["map", "--help"]]


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--src", help="the sources to run (PYTHONPATH); default: the installed acroplan")
    args = ap.parse_args(argv)
    env = dict(os.environ)
    if args.src:
        env["PYTHONPATH"] = args.src
    for cmd in COMMANDS:
        times = []
        for _ in range(args.repeat):
            t = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "acroplan", *cmd], env=env, capture_output=True)
            times.append(time.perf_counter() - t)
        if done.returncode != 0:
            print(f"acroplan {' '.join(cmd):22s} exit {done.returncode} (not in this version)")
            continue
        print(f"acroplan {' '.join(cmd):22s} median {statistics.median(times):.2f} s (min {min(times):.2f}, "
              f"max {max(times):.2f})")


if __name__ == "__main__":
    main()
