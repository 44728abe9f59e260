"""Compile time of the integrator against the number of links (issue #25: the compile must be inside
the time budget, and its cost known in advance).

Each measurement runs in a fresh process with heyoka's on-disk cache off
(``ACROPLAN_HEYOKA_CACHE=off``), so it is a first compilation: building the body, its symbolic fields
(sympy), and ``backend.compile_for`` (heyoka: the variational equations, the Taylor decomposition,
LLVM) for one basis size. Chains (each link on the previous one; ``--topology star``: every link on
the root): planar chains of 2..10 links, spatial chains of 2..6 links (joint axes turning through x,
y, z). With ``--warm`` each point is also compiled a second time from a fresh process with the
on-disk cache on (what a second run on the same machine costs).

    python benchmarks/compile_time.py --planar 2-10 --spatial 2-6 --sizes 6
    python benchmarks/compile_time.py --planar "" --spatial "" --spatial-map 2-16

``--spatial-map``: what a spatial plan compiles since issue #22 (Gauss collocation of the attitude):
the momentum map of the topology, full and light (``collocation.compile_map``: the sympy map, then
heyoka's ``cfunc``, whatever the basis size), and the compiled torques of the effort summary
(``dynamics._compiled``, the column "torques"). The Taylor integrator of a spatial body (the
``--spatial`` rows) is compiled only for the torques' attitude at a non-zero angular momentum.

prints one line per point and a markdown table at the end.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

CHILD = r"""
import json, sys, time
t0 = time.perf_counter()
from acroplan.core import backend
from acroplan.core.basis import Legendre
kind, n, size, topology = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
kind, _, mode = kind.partition("-")
t1 = time.perf_counter()
parent = (lambda i: f"l{i - 1}") if topology == "chain" else (lambda i: "l0")  # a chain, or a star
if kind == "planar":
    from acroplan.families.planar.links import Link
    from acroplan.families.planar.model import PlanarBody
    links = [Link("l0", None, 1.0, 0.1)] + [Link(f"l{i}", parent(i), 1.0, 0.1, com=(0.5, 0.0), joint=(1.0, 0.0))
                                             for i in range(1, n)]
    body = PlanarBody(links, P0=0.0)
else:
    from acroplan.families.spatial.links import SpatialLink
    from acroplan.families.spatial.model import SpatialBody
    axes = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)]
    links = [SpatialLink("l0", None, 1.0, (0.1, 0.2, 0.25))] + [
        SpatialLink(f"l{i}", parent(i), 1.0, (0.1, 0.2, 0.25), com=(0.3, 0.0, 0.0), joint=(0.6, 0.0, 0.0),
                    axis=axes[i % 3]) for i in range(1, n)]
    body = SpatialBody(links, L=(0.0, 0.0, 0.0))
if mode == "map":  # what a spatial plan compiles (issue #22's back end): the momentum maps, the torques
    # (and the processor seconds of the compile, threads included: what a busy machine does not inflate)
    from acroplan.families.spatial import collocation, dynamics
    body.symbolic_momentum_map()
    t2, c2 = time.perf_counter(), time.process_time()
    collocation.compile_map(body)
    collocation.compile_map(body, light=True)
    t3, c3 = time.perf_counter(), time.process_time()
    dynamics._compiled(dynamics.structure(body.links), False)
    t4 = time.perf_counter()
    print(json.dumps({"import": t1 - t0, "symbolic": t2 - t1, "compile": t3 - t2, "compile_cpu": c3 - c2,
                      "torques": t4 - t3}))
    raise SystemExit
body.symbolic()
t2 = time.perf_counter()
backend.compile_for(body, Legendre, size)
t3 = time.perf_counter()
print(json.dumps({"import": t1 - t0, "symbolic": t2 - t1, "compile": t3 - t2}))
"""


def _range(text: str) -> list[int]:
    if not text:
        return []
    lo, _, hi = text.partition("-")
    return list(range(int(lo), int(hi or lo) + 1))


def measure(kind: str, n: int, size: int, cache: str, timeout: float, topology: str = "chain") -> dict:
    env = {**os.environ, "ACROPLAN_HEYOKA_CACHE": cache, "PYTHONWARNINGS": "ignore"}
    t = time.perf_counter()
    try:
        p = subprocess.run([sys.executable, "-c", CHILD, kind, str(n), str(size), topology], env=env, capture_output=True,
                           text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"compile": None, "symbolic": None, "wall": time.perf_counter() - t, "timeout": True}
    if p.returncode != 0:
        raise RuntimeError(p.stderr[-2000:])
    out = json.loads(p.stdout.strip().splitlines()[-1])
    out["wall"] = time.perf_counter() - t
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--planar", default="2-10", help="link counts of planar chains, as LO-HI")
    ap.add_argument("--spatial", default="2-6", help="link counts of spatial chains, as LO-HI")
    ap.add_argument("--spatial-map", default="", help="link counts of spatial bodies whose momentum maps (and "
                    "torques) are compiled, as spatial plans do since issue #22, as LO-HI")
    ap.add_argument("--sizes", default="6", help="basis sizes, comma separated")
    ap.add_argument("--warm", action="store_true", help="also time a second compile from the on-disk cache")
    ap.add_argument("--timeout", type=float, default=3600.0, help="seconds per point")
    ap.add_argument("--topology", default="chain", choices=("chain", "star"),
                    help="chains (each link on the previous one) or stars (every link on the root)")
    args = ap.parse_args()
    sizes = [int(s) for s in args.sizes.split(",")]
    rows = []
    for kind, counts in (("planar", _range(args.planar)), ("spatial", _range(args.spatial)),
                         ("spatial-map", _range(args.spatial_map))):
        for n in counts:
            for size in sizes if kind != "spatial-map" else sizes[:1]:
                load = os.getloadavg()[0]
                cold = measure(kind, n, size, "off", args.timeout, args.topology)
                row = {"kind": kind, "topology": args.topology, "links": n, "size": size, "load": load, **cold}
                if args.warm and cold["compile"] is not None:
                    with tempfile.TemporaryDirectory() as d:
                        measure(kind, n, size, d, args.timeout, args.topology)
                        row["warm"] = measure(kind, n, size, d, args.timeout, args.topology)["compile"]
                rows.append(row)
                print(json.dumps(row), flush=True)
    print()
    print("| body | topology | links | size | symbolic (s) | compile (s) | compile, processor (s) | torques (s) |"
          + (" warm (s) |" if args.warm else "") + " load |")
    print("|---|---|---|---|---|---|---|---|" + ("---|" if args.warm else "") + "---|")
    for r in rows:
        c = "timeout" if r["compile"] is None else f"{r['compile']:.1f}"
        s = "" if r["symbolic"] is None else f"{r['symbolic']:.2f}"
        tq = f"{r['torques']:.1f}" if r.get("torques") is not None else ""
        cpu = f"{r['compile_cpu']:.1f}" if r.get("compile_cpu") is not None else ""
        w = f" {r['warm']:.2f} |" if args.warm and r.get("warm") is not None else (" |" if args.warm else "")
        size = "any" if r["kind"] == "spatial-map" else r["size"]
        print(f"| {r['kind']} | {r['topology']} | {r['links']} | {size} | {s} | {c} | {cpu} | {tq} |{w} {r['load']:.1f} |")


if __name__ == "__main__":
    main()
