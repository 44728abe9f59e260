"""What a user sees of long work (issue #24): a command's progress lines on a terminal, or a
notebook cell's, with how often they were redrawn.

Terminal: the command runs under script(1) (a pseudo-terminal; its timing file says when each piece
of output came), and the capture is summarised: the wall time, the stages seen, how many times a
line was drawn, and the longest time without a new drawing from the first line to the end::

    python benchmarks/progress_capture.py --out /tmp/cap -- acroplan animate pike-out

Notebook: the cell runs in a Jupyter kernel through nbclient; every message the kernel sends
(widget updates of ``tqdm.auto``, or text) is timed the same way::

    python benchmarks/progress_capture.py --notebook "import acroplan; r = acroplan.examples.load('falling-cat').solve()"

The summary is printed as JSON (and written to ``OUT/summary.json`` with the raw capture).
``--silences OUT`` lists where a terminal capture showed nothing new for more than a second, and
the line on screen meanwhile::

    python benchmarks/progress_capture.py --silences /tmp/cap
"""

from __future__ import annotations

import argparse
import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
from pathlib import Path

_STAGE = re.compile(r"([A-Za-z][A-Za-z :'.-]{2,40}?): +(?:\d+%\||\d+:\d\d|\d+\.\d s)")  # "writing trajectory.csv" too


def _gaps(times: list[float]) -> float:
    return max((b - a for a, b in zip(times, times[1:])), default=0.0)


def _text_before(chunk: bytes) -> str:
    """The last line drawn in ``chunk`` (after its last carriage return), stripped of its bar."""
    line = chunk.decode("utf-8", "replace").replace("\r\n", "\n").rstrip("\r\n").split("\r")[-1].split("\n")[-1]
    return re.sub(r"[\u2580-\u259f]+", "", line).strip()[:90]


def _chunks(typescript: Path, timing: Path):
    """``(clock, bytes)`` of each piece of output script(1) recorded, after its own header line."""
    data = typescript.read_bytes()
    clock, pos = 0.0, data.index(b"\n") + 1
    for row in timing.read_text().split("\n"):
        if not row.strip():
            continue
        delay, size = row.split()
        clock += float(delay)
        yield clock, data[pos:pos + int(size)]
        pos += int(size)


def silences(out: Path, longer: float = 1.0) -> list[dict]:
    """Where a terminal capture (``OUT/typescript``, ``OUT/timing``) shows nothing new for more than
    ``longer`` seconds: the start of each silence, how long, and the line on screen meanwhile (the
    command's start and its end count as draws)."""
    draws = [(0.0, "(the command starts)")]
    for clock, chunk in _chunks(out / "typescript", out / "timing"):
        if chunk.strip():
            draws.append((clock, _text_before(chunk)))
    return [{"at_s": round(a, 2), "for_s": round(b - a, 2), "showing": text}
            for (a, text), (b, _) in zip(draws, draws[1:]) if b - a > longer]


def terminal(cmd: list[str], out: Path) -> dict:
    """Run ``cmd`` under script(1) and summarise its progress lines."""
    out.mkdir(parents=True, exist_ok=True)
    typescript, timing = out / "typescript", out / "timing"
    line = " ".join(shlex.quote(c) for c in cmd)
    t0 = time.perf_counter()
    done = subprocess.run(["script", "-q", "-e", "-c", line, str(typescript), "-T", str(timing)],
                          stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    data = typescript.read_bytes()
    start = data.index(b"\n") + 1  # after script's own header line
    draws = []
    for clock, chunk in _chunks(typescript, timing):
        draws += [clock] * chunk.count(b"\r")  # tqdm draws a line with a carriage return
    text = data[start:].decode("utf-8", "replace")
    stages = sorted(set(_STAGE.findall(text)))
    draws = sorted(set(round(t, 3) for t in draws))
    summary = {"command": line, "exit": done.returncode, "wall_s": round(wall, 2), "stages": stages,
               "draws": len(draws), "first_draw_s": draws[0] if draws else None,
               "longest_gap_s": round(_gaps(draws), 2), "last_draw_s": draws[-1] if draws else None}
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


def notebook(code: str, out: Path, timeout: int = 1800) -> dict:
    """Run ``code`` as one notebook cell (nbclient) and summarise the kernel's progress messages."""
    import nbformat
    from nbclient import NotebookClient

    out.mkdir(parents=True, exist_ok=True)
    nb = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell(code)])
    stamps: list[tuple[float, str]] = []
    shown: list[tuple[float, str]] = []  # (time, what the message drew: a widget's text, a stream's)
    t0 = time.perf_counter()

    class Timed(NotebookClient):
        def output(self, outs, msg, display_id, cell_index):
            now = time.perf_counter() - t0
            stamps.append((now, msg["msg_type"]))
            if msg["msg_type"] == "stream":
                shown.append((now, msg["content"].get("text", "").strip()[-90:]))
            elif msg["msg_type"] in ("execute_result", "display_data"):  # (the cell's result: a silence's end)
                shown.append((now, f"({msg['msg_type']})"))
            return super().output(outs, msg, display_id, cell_index)

        def handle_comm_msg(self, outs, msg, cell_index):
            now = time.perf_counter() - t0
            stamps.append((now, "comm_msg"))
            state = msg["content"].get("data", {}).get("state", {})
            text = " ".join(str(state[k]) for k in ("description", "value") if k in state)
            shown.append((now, text[:90]))
            return super().handle_comm_msg(outs, msg, cell_index)

    client = Timed(nb, timeout=timeout, kernel_name="python3", record_timing=True)
    client.execute(cwd=str(out))
    wall = time.perf_counter() - t0
    nbformat.write(nb, out / "capture.ipynb")
    updates = [t for t, kind in stamps if kind in ("comm_msg", "stream", "display_data", "update_display_data")]
    widgets = sum(1 for _, kind in stamps if kind == "comm_msg")
    text = json.dumps(nb.cells[0].get("outputs", []))
    summary = {"code": code, "wall_s": round(wall, 2), "messages": len(updates), "widget_updates": widgets,
               "stages": sorted(set(_STAGE.findall(text))) or None,
               "first_update_s": round(updates[0], 2) if updates else None,
               "longest_gap_s": round(_gaps(updates), 2), "last_update_s": round(updates[-1], 2) if updates else None,
               # from the first update to the last, the gaps of over a second and what was drawn before each
               "silences": [{"at_s": round(a, 2), "for_s": round(b - a, 2), "after": text}
                            for (a, text), (b, _) in zip(shown, shown[1:]) if b - a > 1.0]}
    (out / "shown.json").write_text(json.dumps([[round(a, 3), text] for a, text in shown], indent=0) + "\n")
    (out / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return summary


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=None, help="where the capture goes (default: a temporary folder)")
    ap.add_argument("--notebook", metavar="CODE", help="run CODE in a notebook cell instead of a command")
    ap.add_argument("--silences", type=Path, metavar="OUT", help="list the silences over 1 s of the terminal "
                    "capture in OUT (its typescript and timing), with the line on screen meanwhile")
    ap.add_argument("cmd", nargs=argparse.REMAINDER, help="the command (after --)")
    args = ap.parse_args(argv)
    if args.silences:
        print(json.dumps(silences(args.silences), indent=2, ensure_ascii=False))
        return
    out = args.out or Path(tempfile.mkdtemp(prefix="acroplan-progress-"))
    if args.notebook:
        summary = notebook(args.notebook, out)
    else:
        cmd = args.cmd[1:] if args.cmd[:1] == ["--"] else args.cmd
        if not cmd:
            ap.error("give a command after --, or --notebook CODE")
        if cmd[0] == "acroplan":
            cmd = [sys.executable, "-m", "acroplan", *cmd[1:]]
        os.environ.setdefault("COLUMNS", "100")
        summary = terminal(cmd, out)
    print(json.dumps(summary, indent=2))


if __name__ == "__main__":
    main()
