"""The long fuzz run (the reliability issue): thousands of random API calls and mutated problem files,
with the same generators and checks as the bounded fuzz tests in the suite, counted by outcome.

    python benchmarks/fuzz.py --api 3000 --files 600

A case fails when: the API raises anything but InvalidInputError (or one whose message does not
start with its field), or returns a status outside the three, or JSON with NaN/infinity, or runs past
its budget by more than 2 s; the CLI exits with a code outside 0, 2, 3, 4, prints an exit-2
message that names no field, writes NaN/infinity into JSON, or writes outside OUT.
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

from hypothesis import HealthCheck, given, settings
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


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--api", type=int, default=3000)
    ap.add_argument("--files", type=int, default=600)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    for name, fn in (("API calls", lambda: fuzz_api(args.api, args.seed)), ("problem files", lambda: fuzz_files(args.files))):
        t = time.perf_counter()
        counts = fn()
        total = sum(counts.values())
        fails = sum(v for k, v in counts.items() if k.startswith("FAIL"))
        print(f"{name}: {total} cases in {time.perf_counter() - t:.0f} s, {fails} failures")
        for k, v in sorted(counts.items()):
            print(f"  {k:32s} {v}")


if __name__ == "__main__":
    main()
