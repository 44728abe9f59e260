"""Frames per second of ``acroplan animate`` (issue #24), before and after.

Plans the bundled examples once (``--plans``, with the installed acroplan), then times ``acroplan
animate DIR`` on copies of those folders, in a fresh interpreter each (``--src``: the sources to run,
for the "before" of benchmarks/RESULTS.md: ``git archive 639160b src | tar -x -C /tmp/before``).
Frames are counted in the GIF written; "frames/s" is frames over the whole command's wall time
(reading the folder and the strobe figure included)::

    python benchmarks/animation_fps.py --plans /tmp/anim
    python benchmarks/animation_fps.py --plans /tmp/anim --src /tmp/before/src
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

EXAMPLES = ("pike-dive", "space-robot-turn", "falling-cat", "platform-dive")


def frames_of(gif: Path) -> tuple[int, tuple[int, int]]:
    from PIL import Image

    with Image.open(gif) as im:
        return im.n_frames, im.size


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--plans", type=Path, required=True, help="folder of planned examples (made if missing)")
    ap.add_argument("--src", help="the sources to run (PYTHONPATH); default: the installed acroplan")
    ap.add_argument("--examples", default=",".join(EXAMPLES))
    args = ap.parse_args(argv)
    env = dict(os.environ)
    if args.src:
        env["PYTHONPATH"] = args.src
    for name in args.examples.split(","):
        folder = args.plans / name
        if not (folder / "solution.json").exists():
            subprocess.run([sys.executable, "-m", "acroplan", "plan", "--example", name, "--out", str(folder),
                            "--no-plots", "--quiet"], check=True)
        with tempfile.TemporaryDirectory() as tmp:
            work = Path(tmp) / name
            shutil.copytree(folder, work)
            t = time.perf_counter()
            done = subprocess.run([sys.executable, "-m", "acroplan", "animate", str(work)], env=env,
                                  capture_output=True, text=True)
            wall = time.perf_counter() - t
            if done.returncode != 0:
                print(f"{name:18s} exit {done.returncode}: {done.stderr.strip()[-200:]}")
                continue
            n, size = frames_of(work / "motion.gif")
            kb = (work / "motion.gif").stat().st_size / 1024
            print(f"{name:18s} {n:5d} frames of {size[0]}x{size[1]} px in {wall:6.1f} s: {n / wall:6.1f} frames/s "
                  f"(GIF {kb:,.0f} KB)")


if __name__ == "__main__":
    main()
