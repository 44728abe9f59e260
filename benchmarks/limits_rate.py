"""How limits are enforced, measured: random single-segment problems with joint and rate limits.

Two populations, each target drawn by its relative position w in the exact reachable interval
*under the limits* (acroplan.reachable_set with u_max, phi_min, phi_max):

old    acroplan.zoo bodies; u_max = f * |phi(T) - phi(0)| / T with f uniform in [1.5, 5] (at least
       0.5 rad/s), joint limits 0.5 rad beyond the motion's ends, T in [0.5, 3], w uniform in
       [0.02, 0.98] (the generator of the first limits benchmark, same draws for the same seed).
human  human-scale bodies split at the hips: mass 50-90 kg, stature 1.55-1.95 m, de Leva (1996)
       proportions (upper body, i.e. trunk + head + arms, 58-61% of the mass; its centre of mass
       0.16-0.18 H above the hip, the legs' 0.175-0.19 H below; radii of gyration 0.122 H and
       0.156 H within 10%), |P0| in 10-80 kg m^2/s of either sign; hip range from a pike of 20-40
       degrees (phi >= -2 pi + pike; phi = -2 pi is folded) to straight plus 0-15 degrees of
       hyperextension (phi <= -pi + hyper); |u| <= 10-20 rad/s; T in 1.2-2.0 s; phi(0), phi(T)
       on the straight body (30%), on the pike limit (10%) or uniform in the range; w uniform in
       [0.001, 0.999] for half the problems and within 5% of either end ([0.001, 0.05] or
       [0.95, 0.999]) for the other half. The rate bound binds: the limited interval is narrower
       than with the joint limits alone (the median ratio is printed).

For each method it reports the success rate per population and per band of w (every success
re-verified by plan() itself, and its max |u| and joint range checked against the limits, to
1e-9), the mean, median and 90th percentile of the time per plan, and for "auto" which stage solved the problem:
  deform         path deformation alone already kept the limits
  deform+limits  path deformation, then the constrained solve (SLSQP on the polytope of limits)
  flat           the flat-output planner (three pieces: quintic, dwell, quintic)
  flat-rate      the rate-limited flat planner (smoothed bang-dwell-bang pieces)

Run:  python benchmarks/limits_rate.py [--n 300] [--seed 5] [--population both|old|human]
                                       [--methods auto,deform,flat]
"""

from __future__ import annotations

import argparse
import collections
import time

import numpy as np

import acroplan
from acroplan.families.acrobot.reach import Limits, reachable_set
from acroplan.zoo import random_body

BANDS = ((0.0, 0.05), (0.05, 0.2), (0.2, 0.5), (0.5, 0.8), (0.8, 0.95), (0.95, 1.0))
TOL = 1e-9


def draw(rng):
    """The first limits benchmark's problem (population "old")."""
    robot = random_body(rng)
    T = rng.uniform(0.5, 3.0)
    phi0 = rng.uniform(-np.pi, np.pi)
    phiT = phi0 + rng.uniform(-np.pi, np.pi)
    theta0 = rng.uniform(-np.pi, np.pi)
    u_max = max(0.5, rng.uniform(1.5, 5.0) * abs(phiT - phi0) / T)
    lim = Limits(phi_min=min(phi0, phiT) - 0.5, phi_max=max(phi0, phiT) + 0.5, u_max=u_max)
    R = reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T, limits=lim)
    w = rng.uniform(0.02, 0.98)
    kw = dict(times=[0.0, T], theta=[theta0, R.low + w * (R.high - R.low)], phi=[phi0, phiT],
              u_max=lim.u_max, phi_min=lim.phi_min, phi_max=lim.phi_max)
    return robot, kw, w, 1.0


def human_body(rng):
    """A human-scale body split at the hips (module docstring)."""
    mass, H = rng.uniform(50.0, 90.0), rng.uniform(1.55, 1.95)
    M = mass * rng.uniform(0.58, 0.61)  # trunk + head + arms
    m = mass - M  # both legs
    L, l = H * rng.uniform(0.16, 0.18), H * rng.uniform(0.175, 0.19)
    J = M * (0.122 * H * rng.uniform(0.9, 1.1)) ** 2
    j = m * (0.156 * H * rng.uniform(0.9, 1.1)) ** 2
    P0 = rng.uniform(10.0, 80.0) * rng.choice([-1.0, 1.0])
    return acroplan.Acrobot.from_physical(torso_mass=M, leg_mass=m, torso_inertia=J, leg_inertia=j,
                                          torso_com_to_joint=L, leg_com_to_joint=l, angular_momentum=P0)


def draw_human(rng):
    """A human-scale problem with binding rate and joint limits (population "human")."""
    robot = human_body(rng)
    pike, hyper = np.radians(rng.uniform(20.0, 40.0)), np.radians(rng.uniform(0.0, 15.0))
    lo, hi = -2 * np.pi + pike, -np.pi + hyper
    u_max, T = rng.uniform(10.0, 20.0), rng.uniform(1.2, 2.0)

    def joint():
        k = rng.uniform()
        return -np.pi if k < 0.3 else lo if k < 0.4 else rng.uniform(lo, hi)

    phi0, phiT = joint(), joint()
    theta0 = rng.uniform(-np.pi, np.pi)
    lim = Limits(phi_min=lo, phi_max=hi, u_max=u_max)
    R = reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T, limits=lim)
    joint_only = reachable_set(robot, theta0=theta0, phi0=phi0, phiT=phiT, T=T, limits=Limits(phi_min=lo, phi_max=hi))
    if rng.uniform() < 0.5:
        w = rng.uniform(0.001, 0.999)
    else:
        w = rng.uniform(0.001, 0.05) if rng.uniform() < 0.5 else rng.uniform(0.95, 0.999)
    kw = dict(times=[0.0, T], theta=[theta0, R.low + w * (R.high - R.low)], phi=[phi0, phiT],
              u_max=u_max, phi_min=lo, phi_max=hi)
    return robot, kw, w, (R.high - R.low) / (joint_only.high - joint_only.low)


def band(w):
    return next(i for i, (a, b) in enumerate(BANDS) if w < b or i == len(BANDS) - 1)


def compliant(r, kw):
    lo, hi = kw["phi_min"] - TOL, kw["phi_max"] + TOL
    return all(s.max_abs_u <= kw["u_max"] + TOL and lo <= s.state_range[0] and s.state_range[1] <= hi
               for s in r.segments)


def run(name, problems, methods, show_failures):
    ratio = np.median([p[3] for p in problems])
    print(f"\n== population {name}: {len(problems)} problems, conditions='free'"
          + (f", median width ratio (rate+joint / joint only) {ratio:.3f}" if name == "human" else ""))
    counts = collections.Counter(band(w) for _, _, w, _ in problems)
    header = "  ".join(f"{100 * a:g}-{100 * min(b, 0.999):g}%".rjust(11) for a, b in BANDS)
    print(f"{'':7s} {'success':>8s} {'mean ms':>8s} {'median':>7s} {'p90':>7s}   {header}")
    sizes = "  ".join(f"{counts[i]:11d}" for i in range(len(BANDS)))
    print(f"{'(n)':7s} {'':>8s} {'':>8s} {'':>7s} {'':>7s}   {sizes}")
    for method in methods:
        ok, stages, times, per_band, failures = 0, collections.Counter(), [], collections.Counter(), []
        for robot, kw, w, _ in problems:
            t0 = time.perf_counter()
            r = acroplan.plan(robot, conditions="free", method=method, **kw)
            times.append(time.perf_counter() - t0)
            if r.success and r.verified and compliant(r, kw):
                ok += 1
                per_band[band(w)] += 1
                stages[r.segments[0].method] += 1
            else:
                failures.append((w, r.status, r.message[:300]))
        ms = 1e3 * np.array(times)
        cells = "  ".join((f"{per_band[i] / counts[i]:11.2%}" if counts[i] else f"{'-':>11s}")
                          for i in range(len(BANDS)))
        print(f"{method:7s} {ok / len(problems):8.2%} {ms.mean():8.1f} {np.median(ms):7.1f} "
              f"{np.percentile(ms, 90):7.1f}   {cells}")
        print(f"{'':7s} solved by: " + ", ".join(f"{k}: {v}" for k, v in sorted(stages.items())))
        for w, status, msg in failures[:show_failures]:
            print(f"{'':7s} failed at w = {w:.4f} ({status}): {msg}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=300)
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--population", choices=("both", "old", "human"), default="both")
    ap.add_argument("--methods", default="auto,deform,flat")
    ap.add_argument("--show-failures", type=int, default=3)
    args = ap.parse_args()
    methods = [m.strip() for m in args.methods.split(",") if m.strip()]
    print(f"{args.n} problems per population with joint and rate limits, seed {args.seed}")
    if args.population in ("both", "old"):
        rng = np.random.default_rng(args.seed)
        run("old", [draw(rng) for _ in range(args.n)], methods, args.show_failures)
    if args.population in ("both", "human"):
        rng = np.random.default_rng(args.seed + 1000)
        run("human", [draw_human(rng) for _ in range(args.n)], methods, args.show_failures)


if __name__ == "__main__":
    main()
