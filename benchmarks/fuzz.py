"""The long fuzz run (the reliability issues): thousands of random API calls and mutated problem
files, with the same generators and checks as the bounded fuzz tests in the suite, counted by
outcome.

    python benchmarks/fuzz.py --api 3000 --files 600
    python benchmarks/fuzz.py --api 0 --files 0 --bodies 2000 --time-limit 10 --margin 15

A case fails when: the API raises anything but InvalidInputError (or one whose message does not
start with its field), or returns a status outside the three, or JSON with NaN/infinity, or runs past
its budget by more than 2 s; the CLI exits with a code outside 0, 2, 3, 4, prints an exit-2
message that names no field, writes NaN/infinity into JSON, or writes outside OUT.

``--bodies N`` (issue #25): N problem files of every body kind (the acrobot's ``[robot]``, mutated
planar and spatial URDFs, planar and spatial link tables, yeadon measurement files: the generators
of ``tests/test_reliability_io.py``) through ``acroplan plan --time-limit T``, each run in a worker
process of its own (kept between cases, replaced when it is killed). Also a failure: a run still
going at T + margin seconds (it is killed), a peak resident memory of the worker over 2 GB during
the case (``VmHWM``, reset before each case), anything printed on file descriptor 2 outside the
command's own messages (urdfdom's lines), and an exit 2 of more than one line.
"""

from __future__ import annotations

import argparse
import collections
import importlib.util
import json
import pathlib
import re
import sys
import tempfile
import time

from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

import acroplan

ROOT = pathlib.Path(__file__).parents[1]


def _module(name):
    sys.path.insert(0, str(ROOT / "tests"))
    spec = importlib.util.spec_from_file_location(name, ROOT / "tests" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def fuzz_api(n: int, seed: int) -> collections.Counter:
    api = _module("test_fuzz_api")
    counts: collections.Counter = collections.Counter()

    @settings(max_examples=n, deadline=None, database=None, suppress_health_check=list(HealthCheck))
    @given(api.plan_calls(), st.random_module())
    def run(kw, _):
        t = time.perf_counter()
        try:
            res = acroplan.plan(api.ROBOT, **kw)
        except acroplan.InvalidInputError as e:
            counts["invalid (field named)" if str(e).startswith(e.field + ":") else "FAIL: invalid, no field"] += 1
            return
        except Exception as e:  # noqa: BLE001
            counts[f"FAIL: {type(e).__name__}"] += 1
            return
        elapsed = time.perf_counter() - t
        try:
            json.loads(res.to_json())
        except ValueError:
            counts["FAIL: NaN in JSON"] += 1
            return
        budget = kw.get("time_limit") if isinstance(kw.get("time_limit"), float) else api.LIMIT
        if elapsed > budget + 2.0:
            counts["FAIL: past its budget"] += 1
            return
        counts[str(res.status)] += 1

    run()
    return counts


def fuzz_files(n: int) -> collections.Counter:
    io = _module("test_reliability_io")
    from click.testing import CliRunner

    counts: collections.Counter = collections.Counter()

    @settings(max_examples=n, deadline=None, database=None, suppress_health_check=list(HealthCheck))
    @given(st.lists(io.MUTATION, min_size=1, max_size=3))
    def run(mutations):
        doc = io._mutate(mutations)
        with tempfile.TemporaryDirectory() as d:
            d = pathlib.Path(d)
            prob = d / "p.toml"
            prob.write_text(io.toml_text(doc), encoding="utf-8")
            out = d / "out"
            res = CliRunner().invoke(io.main, ["plan", str(prob), "--out", str(out), "--no-plots", "--json"])
            if res.exit_code not in (0, 2, 3, 4):
                counts[f"FAIL: exit {res.exit_code}"] += 1
                return
            if res.exit_code == 2 and not re.match(r"acroplan: error: \S.*?: \S", res.stderr):
                counts["FAIL: exit 2 without a field"] += 1
                return
            for f in out.rglob("*.json") if out.exists() else ():
                try:
                    json.loads(f.read_text(), parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
                except ValueError:
                    counts["FAIL: NaN in JSON"] += 1
                    return
            if sorted(p.name for p in d.iterdir()) not in (["p.toml"], ["out", "p.toml"]):
                counts["FAIL: wrote outside OUT"] += 1
                return
            counts[f"exit {res.exit_code}"] += 1

    run()
    return counts


def _worker(conn):
    """A worker process: runs one command line per message, with file descriptor 2 captured."""
    import os
    import tempfile as tf

    from click.testing import CliRunner

    from acroplan.io.cli import main as cli

    while True:
        msg = conn.recv()
        if msg is None:
            return
        args = msg
        with tf.TemporaryFile() as err:
            saved = os.dup(2)
            os.dup2(err.fileno(), 2)
            try:
                res = CliRunner().invoke(cli, args)
            finally:
                os.dup2(saved, 2)
                os.close(saved)
            err.seek(0)
            fd2 = err.read(4000).decode("utf-8", "replace")
        conn.send((res.exit_code, res.stdout[-4000:], res.stderr[-4000:], fd2,
                   None if res.exception is None or isinstance(res.exception, SystemExit)
                   else f"{type(res.exception).__name__}: {res.exception}"))


class Worker:
    """A worker process for the CLI runs, its peak memory read and reset per case (Linux /proc)."""

    def __init__(self):
        import multiprocessing as mp

        ctx = mp.get_context("spawn")
        self.conn, child = ctx.Pipe()
        self.proc = ctx.Process(target=_worker, args=(child,), daemon=True)
        self.proc.start()

    def _proc(self, name: str) -> pathlib.Path:
        return pathlib.Path(f"/proc/{self.proc.pid}/{name}")

    def reset_peak(self) -> None:
        try:
            self._proc("clear_refs").write_text("5")
        except OSError:  # pragma: no cover - not Linux: the peak is the process's
            pass

    def peak_bytes(self) -> int:
        for line in self._proc("status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
        return 0

    def run(self, args, timeout: float):
        self.reset_peak()
        self.conn.send(args)
        if not self.conn.poll(timeout):
            return None
        return self.conn.recv()

    def kill(self) -> None:
        self.proc.kill()
        self.proc.join(10)


def fuzz_bodies(n: int, time_limit: float, margin: float, seed_: int = 0,
                log: pathlib.Path | None = None) -> tuple[collections.Counter, dict]:
    io = _module("test_reliability_io")
    counts: collections.Counter = collections.Counter()
    stats = {"longest": 0.0, "peak_bytes": 0, "by_kind": collections.Counter()}
    worker = [Worker()]

    @st.composite
    def cases(draw):  # every kind equally often: the acrobot's mutated files and io.body_files()'s
        if draw(st.integers(min_value=0, max_value=len(io.BODY_KINDS))) == 0:
            return "acrobot", {"p.toml": io.toml_text(io._mutate(draw(st.lists(io.MUTATION, min_size=1, max_size=3))))}
        return draw(io.body_files())

    logf = open(log, "a", encoding="utf-8") if log else None  # noqa: SIM115 - closed below

    def outcome(key, kind, elapsed, peak):
        counts[key] += 1
        if logf:
            logf.write(json.dumps({"outcome": key, "kind": kind, "seconds": round(elapsed, 2),
                                   "peak_mb": round(peak / 1024**2)}) + "\n")
            logf.flush()

    @seed(seed_)
    @settings(max_examples=n, deadline=None, database=None, suppress_health_check=list(HealthCheck))
    @given(cases())
    def run(case):
        kind, files = case
        stats["by_kind"][kind] += 1
        with tempfile.TemporaryDirectory() as d:
            d = pathlib.Path(d)
            for name, text in files.items():
                (d / name).write_text(text, encoding="utf-8")
            out = d / "out"
            args = ["plan", str(d / "p.toml"), "--out", str(out), "--no-plots", "--json", "--time-limit",
                    str(time_limit)]
            t = time.perf_counter()
            got = worker[0].run(args, time_limit + margin)
            elapsed = time.perf_counter() - t
            stats["longest"] = max(stats["longest"], elapsed)
            if got is None:
                outcome(f"FAIL: past the time limit + {margin:g} s ({kind})", kind, elapsed, 0)
                worker[0].kill()
                worker[0] = Worker()
                return
            peak = worker[0].peak_bytes()
            stats["peak_bytes"] = max(stats["peak_bytes"], peak)
            code, stdout, stderr, fd2, exc = got
            if peak > 2 * 1024**3:
                outcome(f"FAIL: over 2 GB ({kind})", kind, elapsed, peak)
            elif code not in (0, 2, 3, 4):
                outcome(f"FAIL: exit {code} ({kind}: {exc})", kind, elapsed, peak)
            elif fd2.strip():
                outcome(f"FAIL: printed on fd 2 ({kind}: {fd2.strip().splitlines()[0][:80]})", kind, elapsed, peak)
            elif code == 2 and not (re.match(r"acroplan: error: \S.*?: \S", stderr)
                                    and len(stderr.strip().splitlines()) == 1):
                outcome(f"FAIL: exit 2 not one line naming a field ({kind})", kind, elapsed, peak)
            else:
                bad_json = False
                for f in out.rglob("*.json") if out.exists() else ():
                    try:
                        json.loads(f.read_text(), parse_constant=lambda c: (_ for _ in ()).throw(ValueError(c)))
                    except ValueError:
                        bad_json = True
                if bad_json:
                    outcome(f"FAIL: NaN in JSON ({kind})", kind, elapsed, peak)
                elif sorted(p.name for p in d.iterdir()) not in (sorted(files), sorted([*files, "out"])):
                    outcome(f"FAIL: wrote outside OUT ({kind})", kind, elapsed, peak)
                else:
                    outcome(f"exit {code}", kind, elapsed, peak)

    try:
        run()
    finally:
        worker[0].conn.send(None)
        worker[0].proc.join(10)
        if logf:
            logf.close()
    return counts, stats


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--api", type=int, default=3000)
    ap.add_argument("--files", type=int, default=600)
    ap.add_argument("--bodies", type=int, default=0, help="problem files of every body kind through acroplan plan")
    ap.add_argument("--time-limit", type=float, default=10.0, help="--time-limit of each plan of --bodies (s)")
    ap.add_argument("--margin", type=float, default=15.0, help="seconds past --time-limit a run may take")
    ap.add_argument("--seed", type=int, default=0, help="hypothesis seed (of --bodies; --api's random module)")
    ap.add_argument("--log", type=pathlib.Path, help="append one JSON line per --bodies case to this file")
    args = ap.parse_args()
    for name, fn in (("API calls", lambda: fuzz_api(args.api, args.seed)), ("problem files", lambda: fuzz_files(args.files))):
        if (args.api if name == "API calls" else args.files) <= 0:
            continue
        t = time.perf_counter()
        counts = fn()
        total = sum(counts.values())
        fails = sum(v for k, v in counts.items() if k.startswith("FAIL"))
        print(f"{name}: {total} cases in {time.perf_counter() - t:.0f} s, {fails} failures")
        for k, v in sorted(counts.items()):
            print(f"  {k:32s} {v}")
    if args.bodies > 0:
        t = time.perf_counter()
        counts, stats = fuzz_bodies(args.bodies, args.time_limit, args.margin, args.seed, args.log)
        total = sum(counts.values())
        fails = sum(v for k, v in counts.items() if k.startswith("FAIL"))
        print(f"body files: {total} cases in {time.perf_counter() - t:.0f} s, {fails} failures; longest run "
              f"{stats['longest']:.1f} s (time limit {args.time_limit:g} s, margin {args.margin:g} s), largest peak "
              f"memory of a case {stats['peak_bytes'] / 1024**2:.0f} MB")
        print("  by kind: " + ", ".join(f"{k} {v}" for k, v in sorted(stats["by_kind"].items())))
        for k, v in sorted(counts.items()):
            print(f"  {k:40s} {v}")


if __name__ == "__main__":
    main()
