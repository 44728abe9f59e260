"""The spatial collocation's panel tolerance (``collocation_parts.TAIL_TOL``): endpoint error and
panels against the tolerance, on random segments.

Segments: ``--n`` random bodies of 3, 4 and 5 links (acroplan.families.spatial.zoo.random_segment,
seeds ``[k, 99]``), L = 0 and L != 0 alternately, 10 Legendre coefficients per joint (the zoo's
motion, 0.5 rad/s noise on the higher coefficients, scaled by a random factor in [1, 3]). Each is
integrated by the collocation at every tolerance (``SOLUTION_TAIL_TOL`` ten times it, as in the
package) and compared with the long-double Taylor reference (backend.reference_endpoint, tol
1e-19): the largest of the attitude's angle and the joints' error. Also the panels per segment and
the endpoint's time (with its Jacobian; median of 20 calls per segment, summed over the segments).

Run:  python benchmarks/collocation_tail.py [--n 150] [--tails 1e-8 1e-7 1e-6]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from acroplan.core import backend
from acroplan.core.basis import Legendre
from acroplan.families.spatial import collocation, collocation_parts
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.zoo import random_segment


def segments(n):
    out = []
    for k in range(n):
        rng = np.random.default_rng([k, 99])
        p = random_segment(rng, 3 + k % 3, momentum=bool(k % 2))
        c = np.zeros((p.body.n_inputs, 10))
        c[:, :p.coefficients.shape[1]] = p.coefficients
        c[:, 6:] = 0.5 * rng.normal(size=(p.body.n_inputs, 4))
        c *= 1.0 + 2.0 * rng.random()
        out.append((p.body, p.x0, p.T, c))
    return out


def set_tail(tol):
    collocation_parts.TAIL_TOL = collocation.TAIL_TOL = tol
    collocation_parts.SOLUTION_TAIL_TOL = collocation.SOLUTION_TAIL_TOL = 10.0 * tol


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=150)
    ap.add_argument("--tails", type=float, nargs="+", default=[1e-8, 1e-7, 1e-6])
    args = ap.parse_args()
    basis = Legendre(10)
    cases = segments(args.n)
    print(f"{len(cases)} segments: their long-double references first (about a second each for a new topology)",
          flush=True)
    refs = [backend.reference_endpoint(b, basis, x0, T, c) for b, x0, T, c in cases]
    for tol in args.tails:
        set_tail(tol)
        errs, panels, secs = [], [], 0.0
        for (body, x0, T, c), ref in zip(cases, refs):
            y, _ = collocation.endpoint(body, basis, x0, T, c)
            errs.append(max(rot.angle_between(y[:4] / np.linalg.norm(y[:4]), ref[:4] / np.linalg.norm(ref[:4])),
                            float(np.abs(y[4:] - ref[4:]).max())))
            panels.append(collocation._solve(collocation._Segment(body, basis, x0, T, c))[1].size)
            ts = []
            for _ in range(20):
                t = time.perf_counter()
                collocation.endpoint(body, basis, x0, T, c)
                ts.append(time.perf_counter() - t)
            secs += float(np.median(ts))
        e = np.array(errs)
        print(f"TAIL_TOL = {tol:g}: {e.size} segments, error median {np.median(e):.1e}, p99 "
              f"{np.quantile(e, 0.99):.1e}, max {e.max():.1e}; panels mean {np.mean(panels):.1f}, max "
              f"{max(panels)}; endpoint + Jacobian {1e3 * secs / e.size:.3f} ms a segment (median of 20)")


if __name__ == "__main__":
    main()
