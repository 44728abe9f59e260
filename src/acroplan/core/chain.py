"""The optimum of a whole plan through interior waypoints: every interval's input at once.

The optimal strategies (:mod:`~acroplan.core.optimal`) optimise the waypoint intervals one after
the other; with ``conditions="free"`` interval :math:`k + 1` starts with the input interval
:math:`k` ended with, so the plan is the best of each interval *given the ones before*. Interval
:math:`k` takes its own optimum with its end input free, which can cost the next interval more
than it saves (measured on the bundled back full's torque optimum: 10.8% above the whole flight's
optimum, ``benchmarks/RESULTS.md``). Here the intervals' reduced coordinates are stacked,
:math:`z = (z_1, \\dots, z_K)` (each :math:`c_k = c_{p,k} + Z_k z_k` carrying only the
interval's own conditions: the first input at the start, the last at the end, rest at an interior
waypoint on a joint limit), and one SQP (:func:`acroplan.core.sqp.sqp`) solves

.. math::  \\min_z \\sum_k f_k(z_k) \\quad\\text{s.t.}\\quad h_k(z_k) = 0 ,\\quad
           u_k(1) - u_{k+1}(0) = 0 ,\\quad r_k(z_k) \\le 0 ,

the continuity of the input at each interior waypoint as linear equations (the rows
:math:`(e_j \\otimes b(1))^\\top c_k - (e_j \\otimes b(0))^\\top c_{k+1}`, :math:`b` the basis
values), from the sequential optimum (feasible: every endpoint reached, the input continuous), at
each interval's basis size from its ladder. The Jacobians are block-diagonal, the continuity
rows constant; the constraints' Hessians are block-diagonal too: at the start, those each
interval's own optimum ended with (the same maps at, or near, the same points), else each
interval's forward differences along its inputs' first :data:`CURVATURE_LEADING` coefficients
(refreshed as the one-interval SQP does; a retry on a denser grid differences afresh at the
first optimum, then carries each retry's Hessians to the next).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from . import backend
from .optimum import KKT_TOL, OutOfEvaluations
from .progress import note as progress_note
from .sqp import kkt_multipliers, polish_endpoint, sqp

__all__ = ["ChainProblem", "ChainOutcome", "joint_optimum", "MAX_ITER", "STAGE", "CURVATURE_LEADING"]

#: The progress stage of the joint optimum (the front door opens it; each endpoint evaluation of
#: the intervals together updates it)
STAGE = "optimal: the intervals together"


class ChainProblem:
    """The stacked problem (module docstring) over the intervals' :class:`OptimalProblem` s, in the
    interface :func:`acroplan.core.sqp.sqp` takes: ``f(z)``, ``h(z)``, ``ineq(z)``."""

    def __init__(self, probs, leading: int | None = None):
        self.probs = list(probs)
        #: the constraint Hessians are differenced along each input's first ``leading`` coefficients
        #: (all when ``None``): :meth:`OptimalProblem.curvature`
        self.leading = leading
        sizes = [p.Z.shape[1] if not p.free else p.N for p in self.probs]
        self.offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        self.N = int(self.offsets[-1])
        # the continuity rows E z + e0 = 0
        rows, e0 = [], []
        for k in range(len(self.probs) - 1):
            a, b = self.probs[k], self.probs[k + 1]
            v1 = a.basis.matrix([1.0])[0]
            v0 = b.basis.matrix([0.0])[0]
            for j in range(a.m):
                ra = np.zeros(a.N)
                ra[j * a.n:(j + 1) * a.n] = v1
                rb = np.zeros(b.N)
                rb[j * b.n:(j + 1) * b.n] = v0
                row = np.zeros(self.N)
                row[self.offsets[k]:self.offsets[k + 1]] = a.zmat(ra[None, :])[0]
                row[self.offsets[k + 1]:self.offsets[k + 2]] = -b.zmat(rb[None, :])[0]
                rows.append(row)
                e0.append(float(ra @ a.c_p) - float(rb @ b.c_p))
        self.E = np.array(rows).reshape(-1, self.N)
        self.e0 = np.array(e0)
        self.q = sum(p.system.ndx for p in self.probs) + self.E.shape[0]
        self.inequalities = any(p.lin is not None or p.tmax is not None for p in self.probs)

    @property
    def evaluations(self) -> int:
        return sum(p.evaluations for p in self.probs)

    def split(self, z):
        return [z[self.offsets[k]:self.offsets[k + 1]] for k in range(len(self.probs))]

    def join(self, parts):
        return np.concatenate([np.asarray(p, dtype=float) for p in parts])

    def f(self, z):
        fs, gs, Hs = zip(*(p.f(zk) for p, zk in zip(self.probs, self.split(z))))
        H = np.zeros((self.N, self.N))
        for k, Hk in enumerate(Hs):
            a, b = self.offsets[k], self.offsets[k + 1]
            H[a:b, a:b] = Hk
        return float(sum(fs)), np.concatenate(gs), H

    def f_value(self, z):
        """The cost alone (:meth:`OptimalProblem.f_value` of every interval)."""
        return float(sum(p.f_value(zk) for p, zk in zip(self.probs, self.split(z))))

    def h(self, z):
        """``(h, A_z, ys, None)``: the intervals' endpoint residuals, then the continuity rows."""
        hs, As, ys = [], [], []
        for p, zk in zip(self.probs, self.split(z)):
            h, A, y, _ = p.h(zk)
            hs.append(h)
            As.append(A)
            ys.append(y)
        A = np.zeros((self.q, self.N))
        r = 0
        for k, Ak in enumerate(As):
            A[r:r + Ak.shape[0], self.offsets[k]:self.offsets[k + 1]] = Ak
            r += Ak.shape[0]
        A[r:] = self.E
        progress_note(STAGE, self.evaluations, None, f"{self.evaluations} endpoint evaluations")
        return np.concatenate(hs + [self.E @ z + self.e0]), A, ys, None

    def ineq(self, z):
        """Every interval's inequalities (:meth:`OptimalProblem.ineq`), their Jacobian block-diagonal."""
        parts = [(k, *p.ineq(zk)) for k, (p, zk) in enumerate(zip(self.probs, self.split(z)))
                 if p.lin is not None or p.tmax is not None]
        r = np.concatenate([rk for _, rk, _ in parts])
        R = np.zeros((r.size, self.N))
        i = 0
        for k, rk, Rk in parts:
            R[i:i + rk.size, self.offsets[k]:self.offsets[k + 1]] = Rk
            i += rk.size
        return r, R

    def curvature(self, z):
        """The constraints' Hessians in ``z``, shape (q, N, N): each interval's forward differences
        (:meth:`OptimalProblem.curvature`, along each input's first :attr:`leading` coefficients:
        ``m * leading`` evaluations an interval), block-diagonal; none for the linear continuity
        rows."""
        hessians = []
        for p, zk in zip(self.probs, self.split(z)):
            Ac = p.h(zk)[3]
            progress_note(STAGE, self.evaluations, None, f"{self.evaluations} endpoint evaluations (curvature)")
            hessians.append(p.curvature(p.c(zk), Ac, self.leading))
        return self.stacked(hessians)

    def stacked(self, hessians):
        """Each interval's endpoint Hessians in its coefficients (``hessians[k]`` of shape (ndx,
        m n, m n), as :meth:`OptimalProblem.curvature` gives them) in the stacked coordinates, shape
        (q, N, N), as :meth:`curvature` lays them out."""
        Hz = np.zeros((self.q, self.N, self.N))
        r = 0
        for k, (p, H) in enumerate(zip(self.probs, hessians)):
            a, b = self.offsets[k], self.offsets[k + 1]
            for M in H:
                Hz[r, a:b, a:b] = p.zhess(M)
                r += 1
        return Hz


@dataclasses.dataclass(frozen=True)
class ChainOutcome:
    """What :func:`joint_optimum` found: ``success`` (every endpoint within its tolerance, the limits
    complied with, the input continuous to 1e-9, the cost below the sequential one), the
    coefficients of each interval (shape ``(m, n_k)``), the costs, the relative KKT residual of the
    stacked problem, the evaluations, the SQP's iterations and its stop."""

    success: bool
    message: str
    coefficients: tuple
    costs: tuple
    cost: float
    start_cost: float
    kkt: float
    evaluations: int
    iterations: int
    #: the SQP's constraint Hessians last computed (stacked coordinates), for a retry; ``None`` when
    #: it stopped before the SQP
    curvature: np.ndarray | None = dataclasses.field(default=None, repr=False, compare=False)


#: The joint optimum's constraint Hessians are forward differences along each input's first this
#: many coefficients (the higher ones' blocks with each other zero, as the ladder pads a smaller
#: size's; :meth:`OptimalProblem.curvature`): on the bundled dives 250 / 124 / 230 evaluations in
#: the joint optimum instead of 372 / 290 / 354 (forward, back full, double full-out), the same
#: optima to 1e-6 and KKT residuals below 1e-8 (benchmarks/RESULTS.md, 2026-12-06 second session).
#: Six were fewer still on the back full but more on the double full-out (curvature refreshes).
CURVATURE_LEADING = 10

#: SQP iterations at most (the one-interval SQP's 40 at a size, times a few: one solve at the
#: ladder's last sizes instead of a ladder)
MAX_ITER = 150


def joint_optimum(runs, starts, *, tol: float, kkt_tol: float = KKT_TOL, max_iter: int = MAX_ITER,
                  reference_cost: float | None = None, curvature=None, interval_curvature=None,
                  beat: bool = True) -> ChainOutcome:
    """The whole plan's optimum (module docstring) from the sequential one.

    Parameters
    ----------
    runs : sequence of OptimalRun
        One per interval, at the interval's basis size, with only its own conditions.
    starts : sequence of numpy.ndarray
        The sequential optimum's coefficients of each interval, shape ``(m, n_k)``.
    tol : float
        The endpoint tolerance.
    kkt_tol : float
        The target relative KKT residual.
    max_iter : int
        SQP iterations at most.
    reference_cost : float, optional
        The sequential optimum's cost, which the result must beat, when ``starts`` are not that
        optimum (a retry on a denser limit grid starts from the coarser grid's joint optimum);
        default: the cost of ``starts``.
    beat : bool
        Whether the result must cost less than the reference (default); ``False`` for starts that
        are no plan (the intervals' provisional optima with their limits broken between the grid's
        points, :attr:`acroplan.core.strategies.Interval.provisional`), whose cost can be lower.
    curvature : numpy.ndarray, shape (q, N, N), optional
        The constraints' Hessians in the stacked coordinates to start from (a retry's: its
        :attr:`ChainOutcome.curvature`; they do not depend on the limits), instead of forward
        differences at ``starts`` (some ``N`` evaluations).
    interval_curvature : sequence of numpy.ndarray, optional
        Each interval's endpoint Hessians in its coefficients, shape (ndx, m n, m n) (those its own
        optimum ended with, :attr:`OptimalSolve.curvature <acroplan.core.optimum.OptimalSolve>`),
        stacked (:meth:`ChainProblem.stacked`) when ``curvature`` is not given, instead of forward
        differences: the intervals' optima are the start, so their Hessians are those of the same
        maps at (or near: their last refresh) the same points. On the bundled back full the joint
        SQP then took 12 iterations instead of 15, and the whole plan 182 endpoint evaluations
        instead of 268 (``benchmarks/RESULTS.md``, 2026-12-06, tenth session).
    """
    probs = [r.prob for r in runs]
    chain = ChainProblem(probs, CURVATURE_LEADING)
    z0 = chain.join([p.z(np.asarray(c, dtype=float).ravel()) for p, c in zip(probs, starts)])
    nan = math.nan
    try:
        f0 = chain.f(z0)[0] if reference_cost is None else float(reference_cost)
        if curvature is not None:
            Hz = np.asarray(curvature, dtype=float)
        elif interval_curvature is not None:
            Hz = chain.stacked(interval_curvature)
        else:
            Hz = chain.curvature(z0)
        ineq = chain.ineq if chain.inequalities else None
        z, info = sqp(chain, z0, Hz, tol=tol, kkt_tol=kkt_tol, max_iter=max_iter, refresh=chain.curvature, ineq=ineq)
        z = polish_endpoint(chain, z, tol, ineq)
        f, g, _ = chain.f(z)
        h, A, ys, _ = chain.h(z)
    except (OutOfEvaluations, backend.IntegrationError) as e:
        return ChainOutcome(False, f"the joint optimum stopped: {e or type(e).__name__}", (), (), nan, nan, nan,
                            chain.evaluations, 0)
    C = None
    if chain.inequalities:
        r, R = chain.ineq(z)
        C = R[r >= -1e-7 * (1.0 + np.abs(r))]
    _, kkt = kkt_multipliers(g, A, C)
    parts = chain.split(z)
    coeffs = tuple(p.c(zk).reshape(p.m, p.n) for p, zk in zip(probs, parts))
    costs = tuple(float(p.f(zk)[0]) for p, zk in zip(probs, parts))
    errs = [p.system.error(y, p.x1) for p, y in zip(probs, ys)]
    jump = float(np.abs(chain.E @ z + chain.e0).max(initial=0.0))
    why = []
    if max(errs) > tol:
        why.append(f"an endpoint missed by {max(errs):.2e} > {tol:g}")
    if jump > 1e-9:
        why.append(f"the input jumps by {jump:.1e} at an interior waypoint")
    broken = float(chain.ineq(z)[0].max(initial=-1.0)) if chain.inequalities else -1.0
    # the rows lie 2e-3 inside the limits, in their own units (rad, rad/s, N m): within rounding of
    # the largest limit they hold (the endpoint's polish moves them by ~1e-9 N m on a 90 N m limit);
    # the dense check against the limits themselves comes after (EnergyOptimal.joint)
    tops = [float(np.max(p.tmax[np.isfinite(p.tmax)], initial=1.0)) for p in probs if p.tmax is not None]
    if broken > 1e-9 * max([1.0] + tops):
        why.append(f"a limit row is broken by {broken:.1e}")
    if beat and not f < f0:
        why.append(f"the cost {f:.10g} is not below the sequential one {f0:.10g}")
    ok = not why
    msg = (f"jointly optimised across the {len(probs)} intervals (the input continuous at the interior waypoints): "
           f"cost {f:.10g} from the sequential {f0:.10g}, {info['its']} SQP iteration(s), relative KKT residual "
           f"{kkt:.1e}" + (f" ({info['why']})" if info["why"] else "")
           + ("" if ok else "; not kept: " + ", ".join(why)))
    return ChainOutcome(ok, msg, coeffs, costs, float(f), float(f0), float(kkt), chain.evaluations, int(info["its"]),
                        info["curvature"])
