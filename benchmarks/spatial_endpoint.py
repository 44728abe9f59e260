"""Spatial bodies: the endpoint map and its Jacobian by every route, side by side, beside its floor.

Cases: the bundled falling cat (acroplan.families.spatial.examples.falling_cat_turn, 3 joints) from
its start over its 0.5 s, with a shape loop of the size its plans make (Legendre coefficients of
standard deviations 4, 6, 3, 2, 1, 0.5 rad/s and 0.3 beyond, seed 22) at 6 and 14 coefficients per
joint; a 5-link chain (acroplan.families.spatial.zoo.random_segment, seed 3: boxes of 1-30 kg,
random joint axes, its own random motion), with L = 0 and with L != 0, at 10 coefficients.

Routes (each the endpoint x(T) and, where said, dx(T)/dc; times are min and median of ``--repeat``
calls, interleaved route by route so that the machine's load hits them alike; and "warm", the
median of the third call of a block of three calls of one route, the blocks interleaved the same
way: a call right after the other routes' integrators finds the caches cold, and the planners call
the endpoint back to back, a continuation's evaluations one after the other):

  collocation        the back end's map for spatial bodies (families/spatial/collocation.py): the
                     attitude alone by Gauss collocation on panels, the compiled momentum map at the
                     nodes, the exact derivative of the discrete map; with and without the Jacobian
  taylor             heyoka's Taylor integrator of the whole state and its variational equations in
                     the coefficients, compact mode, tol 1e-15 (backend.taylor_endpoint: the back
                     end before issue #22)
  taylor tol=1e-13   the same at a looser tolerance
  taylor, no jac     the state alone (7 or 9 equations), compact mode: below every Taylor route
  taylor, state var  the state with its transition matrix (variational equations in the state, the
                     Jacobian in c would then need a quadrature against the basis on top)
  floor (map)        the compiled momentum map (heyoka cfunc: the inertia, its inverse, the coupling
                     and their shape derivatives) at the collocation's nodes, one call: what any
                     scheme that evaluates the fields at that many points must pay
  pinocchio map      Pinocchio's centroidal map (pin.ccrba) at one configuration, times the same
                     node count: the floor of a route that drives the integration by Pinocchio

Every route's endpoint is compared with a tight reference (backend.reference_endpoint: the Taylor
integrator of the fields in long double at tolerance 1e-19): the attitude's angle (rad) and the
joints' largest error.

Run:  python benchmarks/spatial_endpoint.py [--repeat 20] [--full]
      (``--full`` adds heyoka's full (non-compact) mode for the state alone: its compilation takes
      some 100 s per case)
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import heyoka as hy
import numpy as np

import acroplan
from acroplan.core import backend
from acroplan.core.basis import Legendre
from acroplan.families.spatial import SpatialBody, collocation
from acroplan.families.spatial import rotations as rot
from acroplan.families.spatial.examples import falling_cat_turn
from acroplan.families.spatial.zoo import random_segment


def cat_case(n):
    cat, kw = falling_cat_turn()
    x0 = np.array([kw[k][0] for k in cat.state_names])
    rng = np.random.default_rng(22)
    c = np.zeros((3, n))
    c[:, :6] = rng.normal(scale=[4.0, 6.0, 3.0, 2.0, 1.0, 0.5], size=(3, 6))
    c[:, 6:] = rng.normal(scale=0.3, size=(3, n - 6))
    return cat, x0, 0.5, c


def chain_case(momentum, n=10):
    rng = np.random.default_rng(3)
    p = random_segment(rng, 5, momentum=True)
    body = p.body if momentum else SpatialBody(p.body.links)
    c = np.zeros((body.n_inputs, n))
    c[:, :6] = p.coefficients
    c[:, 6:] = 0.3 * rng.normal(size=(body.n_inputs, n - 6))
    return body, p.x0, p.T, c


def taylor_variant(body, n, *, tol=1e-15, mode="coefficients", compact=True):
    """A heyoka integrator of the body's fields: ``mode`` "coefficients" (variational equations in
    c), "state" (in the state) or "none"."""
    sys_, coeffs = backend.heyoka_fields(body, Legendre(n))
    n_x, m, n_p = len(sys_), len(coeffs), len(body.param_names)
    if mode == "coefficients":
        sys_ = hy.var_ode_sys(sys_, [c for row in coeffs for c in row], order=1)
    elif mode == "state":
        sys_ = hy.var_ode_sys(sys_, hy.var_args.vars, order=1)
    dim = len(sys_.sys) if hasattr(sys_, "sys") else n_x
    ta = hy.taylor_adaptive(sys_, [0.0] * dim, tol=tol, pars=[0.0] * (n_p + 1 + m * n), compact_mode=compact)

    def run(x0, T, c):
        ta.time = 0.0
        ta.state[:] = 0.0
        ta.state[:n_x] = x0
        if mode == "state":
            ta.state[n_x:] = np.eye(n_x).ravel()
        ta.pars[:n_p] = body._param_tuple
        ta.pars[n_p] = T
        ta.pars[n_p + 1:] = np.ravel(c)
        res = ta.propagate_until(1.0)
        return ta.state[:n_x].copy(), int(res[3])

    return run


def error(y, ref):
    return (rot.angle_between(y[:4] / np.linalg.norm(y[:4]), ref[:4] / np.linalg.norm(ref[:4])),
            float(np.abs(y[4:] - ref[4:]).max()))


def pinocchio_map(body):
    """One call of Pinocchio's centroidal map (ccrba) at a random configuration."""
    import pinocchio as pin

    from acroplan.families.spatial.pin import build_model

    pb = build_model(body)
    data = pb.model.createData()
    q = pb.configuration(np.concatenate([[1.0, 0.0, 0.0, 0.0], np.full(body.n_inputs, 0.3)]))
    v = np.zeros(pb.model.nv)
    return lambda: pin.ccrba(pb.model, data, q, v)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--full", action="store_true", help="add heyoka's full mode (slow to compile)")
    args = ap.parse_args()
    try:
        load = os.getloadavg()
        load = f"load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}"
    except OSError:
        load = "load average unknown"
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, python "
          f"{platform.python_version()}; acroplan {acroplan.__version__}, heyoka {hy.__version__}, numpy "
          f"{np.__version__}; {load}; repeat {args.repeat}; collocation: {collocation.NODES} nodes per panel, "
          f"tail tolerance {collocation.TAIL_TOL:g}")
    cases = [("bundled cat, n = 6", *cat_case(6)), ("bundled cat, n = 14", *cat_case(14)),
             ("5-link chain, L = 0, n = 10", *chain_case(False)), ("5-link chain, L != 0, n = 10", *chain_case(True))]
    for name, body, x0, T, c in cases:
        n = c.shape[1]
        basis = Legendre(n)
        t0 = time.perf_counter()
        ref = backend.reference_endpoint(body, basis, x0, T, c)
        t_ref = time.perf_counter() - t0
        seg = collocation._Segment(body, basis, x0, T, c)
        sol = collocation._solve(seg)
        widths = sol[1]
        nodes = widths.size * collocation.NODES
        sig = np.linspace(0.0, 1.0, nodes)
        s = x0[4:, None] + T * (c @ basis.integral(sig).T)
        u = c @ basis.matrix(sig).T
        inp = np.concatenate([s, u])
        fn = collocation.compile_map(body)
        pars = np.repeat(np.asarray(body._param_tuple)[:, None], nodes, axis=1)
        routes = {
            "collocation (x(T) and J)": lambda: (collocation.endpoint(body, basis, x0, T, c)[0], None),
            "collocation, no J": lambda: (collocation.endpoint(body, basis, x0, T, c, jacobian=False)[0], None),
            "taylor (x(T) and J; before #22)": lambda: (backend.taylor_endpoint(body, basis, x0, T, c)[0], None),
        }
        t0 = time.perf_counter()
        variants = {"taylor tol=1e-13 (x(T) and J)": taylor_variant(body, n, tol=1e-13),
                    "taylor, no J": taylor_variant(body, n, mode="none"),
                    "taylor, state transition matrix": taylor_variant(body, n, mode="state")}
        if args.full:
            variants["taylor full mode, no J"] = taylor_variant(body, n, mode="none", compact=False)
        t_build = time.perf_counter() - t0
        steps = {}
        for k, run in variants.items():
            routes[k] = (lambda run=run: run(x0, T, c))
            steps[k] = run(x0, T, c)[1]
        routes["floor: compiled map at the nodes"] = lambda: (fn(inp, pars=pars), "floor")
        pmap = pinocchio_map(body)
        routes["pinocchio ccrba, one call"] = lambda: (pmap(), "floor")
        for f in routes.values():  # warm
            f()
        times = {k: [] for k in routes}
        warm = {k: [] for k in routes}
        for _ in range(args.repeat):
            for k, f in routes.items():
                t = time.perf_counter()
                f()
                times[k].append(time.perf_counter() - t)
            for k, f in routes.items():  # the third call of a block of three: warm caches
                f()
                f()
                t = time.perf_counter()
                f()
                warm[k].append(time.perf_counter() - t)
        print(f"\n{name}: {body.n_inputs} joints, {n} coefficients each, L = "
              f"{'0' if not np.any(body.angular_momentum) else np.round(body.angular_momentum, 2).tolist()}; "
              f"collocation {widths.size} panels ({nodes} nodes); reference (long double, tol 1e-19) in "
              f"{t_ref:.1f} s; Taylor variants built in {t_build:.1f} s")
        base = np.min(times["collocation (x(T) and J)"])
        print(f"  {'route':40s} {'min ms':>9s} {'median ms':>10s} {'warm ms':>8s} {'/ colloc.':>9s}  endpoint error "
              "(angle, joints)")
        for k, f in routes.items():
            t = np.array(times[k]) * 1e3
            out = f()[0]
            if k == "pinocchio ccrba, one call":
                extra = f"x {nodes} nodes = {np.min(t) * nodes:.2f} ms"
            elif k.startswith("floor"):
                extra = "(no integration)"
            else:
                ea, ej = error(out, ref)
                extra = f"{ea:.1e}, {ej:.1e}" + (f"  ({steps[k]} Taylor steps)" if k in steps else "")
            print(f"  {k:40s} {np.min(t):9.3f} {np.median(t):10.3f} {1e3 * np.median(warm[k]):8.3f} "
                  f"{np.min(t) / base / 1e3:9.2f}  {extra}")


if __name__ == "__main__":
    main()
