"""The optimisation of one waypoint interval at one basis size (:func:`optimize_segment`), and its
outcome (:class:`OptimalSolve`): the problem in reduced coordinates :math:`c = c_p + Z z` that carry
the input conditions :math:`Bc = d` exactly, the endpoint as equality constraints, the rate, joint
and torque limits as inequalities (:mod:`~acroplan.core.optimal` describes the method).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from . import backend
from .basis import InputBasis
from .errors import InvalidInputError
from .limits import COMPLIANCE_TOL, linear_limits, violation
from .linalg import least_norm_step, null_space
from .objectives import (TORQUE_LIMIT_GRID, TORQUE_MARGIN, EnergyCost, call_torque, cost_for, energy, torque_check_grid,
                         torque_values)
from .sqp import INEQ_TOL, kkt_multipliers, kkt_step, polish_endpoint, sqp
from .system import ControlAffineSystem

__all__ = ["OptimalSolve", "optimize_segment", "OptimalRun", "OptimalProblem", "OutOfEvaluations", "KKT_TOL",
           "STAGE_KKT_TOL", "FIRST_KKT_TOL"]

#: Relative KKT residual of the reported optimum (module docstring).
KKT_TOL = 1e-8
#: Relative KKT residual at the sizes of the ladder before the last; a size whose change looks
#: below ``rtol`` is refined to ``kkt_tol`` before the ladder stops on it (refining lowers its cost,
#: so the change can only grow), and the predictions at the next size include what is left.
STAGE_KKT_TOL = 1e-3
#: Relative KKT residual at the first size, where the starts are compared (an optimum not fully
#: converged there can only make the ladder's first change look larger, never stop it early).
FIRST_KKT_TOL = 1e-3
#: An exchange round (:meth:`OptimalProblem.add_torque_times`) imposes the torque limits at each
#: time of a largest excess and this fraction of the first torque grid's spacing on either side of it:
#: with the time alone, the next optimum's peak moved beside it and broke the limit again (the
#: double full-out's joint optimum took three rounds, the last one allowed; benchmarks/RESULTS.md,
#: 2026-12-07, twelfth session).
EXCHANGE_SPREAD = 0.25


@dataclasses.dataclass(frozen=True)
class OptimalSolve:
    """Outcome of :func:`optimize_segment` (one basis size) or of a strategy's ladder.

    Attributes
    ----------
    success : bool
        Endpoint within ``tol`` and the limits (and torque limits) honoured. Optimality is what
        :attr:`kkt` measures.
    message : str
    coefficients : numpy.ndarray, shape (m, n)
    basis : InputBasis
    objective : float
        The cost at :attr:`coefficients`: :math:`\\int\\|u\\|^2 dt` (exact) or
        :math:`\\int\\|\\tau\\|^2 dt` (quadrature).
    energy : float
        :math:`\\int_0^T \\|u\\|^2 dt`, exact.
    kkt : float
        Relative KKT residual :math:`\\kappa` (module docstring).
    multipliers : numpy.ndarray, shape (ndx,)
        Least-squares multipliers of the endpoint equations (in the units of the cost per unit
        of state).
    final_error : float
        Endpoint error of the compiled integrator.
    evaluations, iterations : int
    solver : str
        ``"sqp"`` (the limits, when there are any, are its inequalities).
    sizes : tuple of (int, float)
        The ladder: (basis size, optimal cost) at each size solved; when the ladder stopped on a
        prediction, the last entry is the next size with the cost one Newton step predicts there
        (one entry for :func:`optimize_segment`).
    converged_in_basis : bool
        Whether the cost changed (or is predicted to change) by less than ``rtol`` at the last
        step of the ladder.
    start : str
        The start the optimum came from (``"auto"``, ``"deform"`` or ``"given"``).
    limit_grid : int
        Points per interval of the grid the rate and joint limits were imposed on (64, or more when
        the optimum broke one between 64 points: :meth:`acroplan.core.optimal._Search.denser`).
    torque_grid : int
        Points per interval of the torque limits' grid (65, or more when the optimum broke one
        between them); 0 without torque limits.
    """

    success: bool
    message: str
    coefficients: np.ndarray
    basis: InputBasis
    objective: float
    energy: float
    kkt: float
    multipliers: np.ndarray
    final_error: float
    evaluations: int = 0
    iterations: int = 0
    solver: str = "sqp"
    sizes: tuple = ()
    converged_in_basis: bool = False
    start: str = "given"
    limit_grid: int = 64
    torque_grid: int = 0
    #: ``None`` for an optimum refined to its KKT target and checked between its limits' grid
    #: points; for a start of the joint optimum reported as the ladder left it
    #: (:attr:`acroplan.core.strategies.Interval.provisional`), ``"within"`` or ``"broken"``: whether
    #: its limits hold between the grid's points
    provisional: str | None = None
    #: the endpoint's Hessians in the coefficients, shape (ndx, m n, m n), that the SQP last used at
    #: this size (forward differences, :meth:`OptimalProblem.curvature`), or ``None``: the joint
    #: optimum of several intervals starts from them (:meth:`acroplan.core.optimal.EnergyOptimal.joint`)
    curvature: np.ndarray | None = dataclasses.field(default=None, repr=False, compare=False)

    def to_dict(self, objective: str = "energy") -> dict:
        """The diagnostics as plain JSON types (non-finite numbers as ``None``): ``objective``,
        ``cost``, ``integral_u2``, ``kkt``, ``multipliers``, ``final_error``, ``basis_size``,
        ``ladder`` (``[[n, cost], ...]``), ``converged_in_basis``, ``start``, ``solver``,
        ``evaluations``, ``iterations``, ``success``, ``limit_grid``, ``torque_grid``, and ``provisional``
        for a start of the joint optimum (:attr:`provisional`)."""
        num = (lambda v: float(v) if v is not None and math.isfinite(float(v)) else None)  # noqa: E731
        return {"objective": objective, "cost": num(self.objective), "integral_u2": num(self.energy),
                "kkt": num(self.kkt), "multipliers": [num(v) for v in np.ravel(self.multipliers)],
                "final_error": num(self.final_error), "basis_size": int(self.basis.n),
                "ladder": [[int(n), num(v)] for n, v in self.sizes],
                "converged_in_basis": bool(self.converged_in_basis), "start": self.start, "solver": self.solver,
                "evaluations": int(self.evaluations), "iterations": int(self.iterations),
                "success": bool(self.success), "limit_grid": int(self.limit_grid),
                "torque_grid": int(self.torque_grid),
                **({} if self.provisional is None else {"provisional": self.provisional})}


class OutOfEvaluations(RuntimeError):
    pass


#: :func:`end_cluster`: points an end, and the span they cover in units of :math:`1/n^2` of the
#: interval (``n`` coefficients an input), so that they lie :math:`1/(2n^2)` apart
END_CLUSTER = (37, 18.0)


def end_cluster(n: int) -> np.ndarray:
    """Normalised times crowded at both ends of an interval, for the torque limits of a joint
    optimum (:meth:`acroplan.core.optimal.EnergyOptimal.joint`): :data:`END_CLUSTER` ``[0]`` points
    an end, evenly over :math:`[0, w]` and :math:`[1 - w, 1]`, :math:`w = 18/n^2` (at most 1/4),
    so :math:`1/(2n^2)` apart. An input of ``n`` coefficients has features about :math:`1/n^2` of
    the interval wide near its ends, and with the input continuous at the interior waypoints the
    joint optimum's torques peak there, in boundary layers: the bundled double full-out's broke its
    torque limits between the 65 uniform points within 0.5% of the intervals' ends, then between
    257 within 2% (``benchmarks/RESULTS.md``, eighteenth session, item 12); points 1e-3 apart there
    still missed them, 5e-4 apart caught them."""
    count, span = END_CLUSTER
    w = min(span / float(n) ** 2, 0.25)
    e = np.linspace(0.0, w, count)
    return np.union1d(e, 1.0 - e)


class OptimalProblem:
    """One interval at one basis size, in reduced coordinates ``z`` (``c = c_p + Z z``)."""

    def __init__(self, system, basis, x0, x1, T, cost, B, d, max_evaluations, limits=None, torque_model=None,
                 tau_max=None, limit_grid: int = 64, torque_grid: int | None = None, limit_ends: int = 0,
                 torque_ends: bool = False):
        self.system, self.basis, self.T = system, basis, float(T)
        self.x0 = np.asarray(x0, dtype=float)
        self.x1 = np.asarray(x1, dtype=float)
        m, n = system.n_inputs, basis.n
        self.m, self.n, self.N = m, n, m * n
        if B is None or np.shape(B)[0] == 0:
            self.c_p, self.Z, self.free = np.zeros(self.N), None, True
        else:
            B = np.atleast_2d(np.asarray(B, dtype=float))
            self.c_p = np.linalg.lstsq(B, np.asarray(d, dtype=float), rcond=None)[0]
            self.Z, self.free = null_space(B, self.N), False
        self.cost = cost
        self.evaluations = 0
        self.max_evaluations = max_evaluations
        self._key, self._val, self._Hz = None, None, None
        self.torque_model = torque_model
        # inequalities: rate and joint limits (linear), torque limits (nonlinear)
        self.limits = limits if limits is not None and limits.active else None
        self.limit_grid = int(limit_grid)
        self.lin = None
        if self.limits is not None:
            A_c, b_c = linear_limits(system, basis, self.x0, T, self.limits, grid=limit_grid, margin=2e-3,
                                     ends=limit_ends)
            if A_c.shape[0]:
                self.lin = (self.zmat(A_c), b_c - A_c @ self.c_p)
        self.tmax = None if tau_max is None else np.atleast_1d(np.asarray(tau_max, dtype=float))
        # the torque limits' grid: TORQUE_LIMIT_GRID points, or as dense as the rate and joint
        # limits' when those are denser, unless told (a retry densifies the limits it found broken
        # between the points, the torque limits or the others)
        points = max(TORQUE_LIMIT_GRID, int(limit_grid) + 1) if torque_grid is None else max(int(torque_grid), 2)
        self.grid = None if tau_max is None else np.linspace(0.0, 1.0, points)
        if torque_ends and self.grid is not None:  # and the ends' boundary layers (end_cluster)
            self.grid = np.union1d(self.grid, end_cluster(n))
        self.grid_points = points  # the torque grid's uniform points (before end clusters and exchange rounds)

    def add_torque_times(self, s) -> int:
        """Impose the torque limits at the normalised times ``s`` too (an exchange round: where a
        result broke them between the grid's points), and at :data:`EXCHANGE_SPREAD` of the
        first grid's spacing on either side of each (the same times again add nothing); returns
        how many times were new."""
        if self.grid is None:
            return 0
        s = np.clip(np.asarray(s, dtype=float).ravel(), 0.0, 1.0)
        if EXCHANGE_SPREAD and s.size and self.grid.size > 1:
            h = EXCHANGE_SPREAD / (self.grid_points - 1)
            s = np.clip(np.concatenate([s, s - h, s + h]), 0.0, 1.0)
        grid = np.union1d(self.grid, s)
        added = grid.size - self.grid.size
        self.grid = grid
        return int(added)

    def torque_check(self, c):
        """``(s, tau, peak, when)``: the torques on the dense check's points ``s``
        (:func:`~.objectives.torque_check_grid`), shape (p, K), and each joint's peak :math:`|\\tau|`
        (p,) with its time, refined between the points (:func:`~.effort.peak_times`, as the plan's
        effort summary refines them) for the joints whose sampled peak is within 1% of their row's
        bound; the others' are the sampled peaks."""
        from .effort import peak_times

        model, system, basis, x0, T = self.torque_model, self.system, self.basis, self.x0, self.T
        s = torque_check_grid()
        tau = torque_values(model, system, basis, x0, T, c, s)
        at = np.argmax(np.abs(tau), axis=1)
        peak, when = np.abs(tau[np.arange(tau.shape[0]), at]), s[at]
        bound = np.broadcast_to(self.tmax, peak.shape) * (1.0 - TORQUE_MARGIN)
        near = np.flatnonzero(np.isfinite(bound) & (peak >= 0.99 * bound))
        if near.size:
            def f(xs):
                order = np.argsort(xs, kind="stable")
                out = np.empty((near.size, xs.size))
                out[:, order] = torque_values(model, system, basis, x0, T, c, xs[order])[near]
                return out

            peak[near], when[near] = peak_times(f, s, tau[near])
        return s, tau, peak, when

    def torque_excess_times(self, z) -> np.ndarray:
        """The normalised times of the largest excess of each stretch where a joint's
        :math:`|\\tau|` is above its row's bound (:math:`(1 - \\text{TORQUE\\_MARGIN})\\,\\bar\\tau`),
        from :meth:`torque_check`: on its points, the stretch's worst point, or the joint's refined
        peak where that lies in the stretch or between the points, above the bound; empty without
        torque limits."""
        if self.tmax is None:
            return np.zeros(0)
        s, tau, peak, when = self.torque_check(self.c(z))
        bound = np.broadcast_to(self.tmax, peak.shape) * (1.0 - TORQUE_MARGIN)
        over = np.abs(tau) - bound[:, None]
        out = []
        for j, row in enumerate(over):
            refined = bool(peak[j] > bound[j])
            bad = np.flatnonzero(row > 0.0)
            if bad.size:
                # the stretches of consecutive points above the bound, each's worst point
                for run in np.split(bad, np.flatnonzero(np.diff(bad) > 1) + 1):
                    lo, hi = s[max(run[0] - 1, 0)], s[min(run[-1] + 1, s.size - 1)]
                    if refined and lo <= when[j] <= hi:
                        out.append(when[j])
                        refined = False
                    else:
                        out.append(s[run[np.argmax(row[run])]])
            if refined:  # a peak above the bound between the points, none of them above it
                out.append(when[j])
        return np.unique(np.asarray(out, dtype=float))

    # coordinates
    def c(self, z):
        return z.copy() if self.free else self.c_p + self.Z @ z

    def z(self, c):
        c = np.asarray(c, dtype=float).reshape(-1)
        return c.copy() if self.free else self.Z.T @ (c - self.c_p)

    def zmat(self, M):
        """Rows ``M`` acting on ``c`` as rows acting on ``z``."""
        return M if self.free else M @ self.Z

    def zhess(self, H):
        return H if self.free else self.Z.T @ H @ self.Z

    def zhessians(self, Hs) -> np.ndarray:
        """Hessians ``Hs`` in ``c`` (one per constraint, each (m n, m n)) in ``z``, stacked: shape
        (len(Hs), N_z, N_z) (:meth:`zhess` of each)."""
        return np.stack([self.zhess(M) for M in Hs])

    # functions
    def f(self, z):
        """Cost, gradient and model Hessian in ``z``."""
        if self.free:
            return self.cost(z)
        f, g, H = self.cost(self.c(z))
        if isinstance(self.cost, EnergyCost):  # a constant Hessian: reduced once
            if self._Hz is None:
                self._Hz = self.Z.T @ H @ self.Z
            return f, self.Z.T @ g, self._Hz
        return f, self.Z.T @ g, self.Z.T @ H @ self.Z

    def f_value(self, z):
        """The cost alone in ``z`` (no gradient, no model Hessian: a trial point's)."""
        return self.cost.value(z if self.free else self.c(z))

    def endpoint(self, c):
        """``(y, A_c)``: the endpoint and its tangent Jacobian in flattened ``c`` (counted)."""
        if self.evaluations >= self.max_evaluations:
            raise OutOfEvaluations()
        self.evaluations += 1
        y, J = backend.endpoint(self.system, self.basis, self.x0, self.T, c)
        return y, self.system.tangent_jacobian(y, J)

    def h(self, z):
        """``(h, A_z, y, A_c)``: the endpoint residual :math:`-\\mathrm{diff}(y, x_1)`, its Jacobian
        in ``z``, the endpoint and the Jacobian in ``c``; raises :class:`backend.IntegrationError`."""
        key = z.tobytes()
        if key != self._key:
            y, Ac = self.endpoint(z if self.free else self.c_p + self.Z @ z)
            self._key, self._val = key, (-self.system.diff(y, self.x1), self.zmat(Ac), y, Ac)
        return self._val

    def _torque_limit_rows(self, z):
        """:math:`\\tau` on the torque limits' grid and its limit :math:`\\bar\\tau`, the finite
        limits only (flattened joint by joint), and the Jacobian of :math:`\\tau` in ``z``."""
        tau, J = call_torque(self.torque_model, self.system, self.basis, self.x0, self.T, self.c(z), self.grid)
        tmax = np.broadcast_to(self.tmax[:, None], tau.shape).ravel()
        fin = np.isfinite(tmax)
        return tau.ravel()[fin], tmax[fin], self.zmat(J.reshape(-1, self.N)[fin])

    def ineq(self, z):
        """The inequalities :math:`r(z) \\le 0` and their Jacobian: the rate and joint limits (linear
        rows :math:`A_z z - b_z`) and the torque limits, :math:`\\pm\\tau - (1 - m)\\bar\\tau` on
        the grid (:data:`TORQUE_MARGIN` :math:`m`), in one array."""
        n_lin = 0 if self.lin is None else self.lin[0].shape[0]
        n_tau = 0
        if self.tmax is not None:
            tau, tmax, Jt = self._torque_limit_rows(z)
            top = tmax * (1.0 - TORQUE_MARGIN)
            n_tau = tau.size
        r = np.empty(n_lin + 2 * n_tau)
        R = np.empty((r.size, self.Z.shape[1] if not self.free else self.N))
        if n_lin:
            Az, bz = self.lin
            r[:n_lin] = Az @ z - bz
            R[:n_lin] = Az
        if n_tau:
            r[n_lin:n_lin + n_tau] = tau - top
            r[n_lin + n_tau:] = -tau - top
            R[n_lin:n_lin + n_tau] = Jt
            np.negative(Jt, out=R[n_lin + n_tau:])
        return r, R

    def curvature(self, c, Ac, leading: int | None = None):
        """Constraint Hessians in ``c`` coordinates, shape (q, N, N), by forward differences of the
        endpoint Jacobian along every coordinate direction (N evaluations), symmetrised; with
        ``leading``, along each input's first ``leading`` coefficients only (``m * leading``
        evaluations): the blocks of the higher coefficients with each other are left zero (as the
        ladder pads a smaller size's Hessians: the higher Legendre coefficients move the endpoint
        least), and their blocks with the leading ones are one-sided (not averaged with a
        difference along the higher direction)."""
        q, N, n = Ac.shape[0], self.N, self.n
        cols = (np.arange(N) if leading is None or leading >= n
                else (np.arange(self.m)[:, None] * n + np.arange(leading)[None, :]).ravel())
        M = np.zeros((q, N, N))
        with backend.perturbations_of(self.system, self.basis, self.x0, self.T, c):
            for k in cols:
                eps = 1e-7 * max(1.0, abs(c[k]))
                ck = c.copy()
                ck[k] += eps
                M[:, :, k] = (self.endpoint(ck)[1] - Ac) / eps
        if cols.size == N:
            return 0.5 * (M + M.transpose(0, 2, 1))
        out = M + M.transpose(0, 2, 1)  # each difference column gives its row too
        out[np.ix_(np.arange(q), cols, cols)] *= 0.5
        return out


#: The SQP's refreshed constraint Hessians (after poor steps, :data:`acroplan.core.sqp.POOR_STEPS`)
#: are forward differences along each input's first this many coefficients, as the joint
#: optimum's (:data:`acroplan.core.chain.CURVATURE_LEADING`): the bundled double full-out's
#: second interval refreshed them at 26 coefficients, 104 of its 127 evaluations there; its plan
#: 631 -> 566 endpoint evaluations, the same optimum, the other bundled optima's counts unchanged
#: (``benchmarks/RESULTS.md``, 2026-12-06, ninth session). ``None``: every coefficient. A run's
#: first Hessians (no curvature given: the first size a start is optimised at) are differenced the
#: same way: the forward dive's second interval starts at 14 coefficients (none keeps its limits
#: at 6), 56 -> 40 evaluations there, its plan 638 -> 604, the falling cat's least integral of u^2
#: at rest (first size 14) 82 -> 75, the same optima; 62 acrobot and planar optima (whose first
#: sizes are at most 10 but one) the same to 1e-9 (``benchmarks/RESULTS.md``, tenth session).
REFRESH_LEADING = 10


class OptimalRun:
    """The optimisation at one basis size: solve from a start, refine, report."""

    def __init__(self, system, basis, x0, x1, T, cost, torque_model, limits, tau_max, B, d, tol, max_evaluations,
                 limit_grid: int = 64, torque_grid: int | None = None, limit_ends: int = 0,
                 torque_ends: bool = False):
        self.fn = cost_for(cost, system, basis, x0, T)
        self.prob = OptimalProblem(system, basis, x0, x1, T, self.fn, B, d, max_evaluations, limits, torque_model, tau_max,
                                   limit_grid, torque_grid, limit_ends, torque_ends)
        self.tol = tol
        #: whether the problem has inequalities (rate, joint or torque limits)
        self.inequalities = self.prob.lin is not None or self.prob.tmax is not None
        self.solver = "sqp"
        self.z = None
        self.Hc = None  # constraint Hessians in c coordinates (the SQP's)
        self.its, self.why, self.failed = 0, "", ""
        #: what the last :meth:`result` found broken between the grids' points (its dense check):
        #: ``{"limits": rate or joint limits, "torque": torque limits}``
        self.broken = {"limits": False, "torque": False}
        #: whether the current point's limits were checked between the grid's points (a ladder's sizes
        #: are taken on their grids alone: :data:`acroplan.core.optimal.LADDER_ON_GRID`)
        self.checked = True

    @property
    def ineq(self):
        """The problem's inequalities (:meth:`OptimalProblem.ineq`) as :func:`~acroplan.core.sqp.sqp`
        takes them: ``None`` when it has none."""
        return self.prob.ineq if self.inequalities else None

    def solve(self, c0, *, curvature=None, kkt_tol=KKT_TOL, polish=True):
        prob = self.prob
        z = prob.z(c0)
        try:
            h, Az, _, Ac = prob.h(z)
            if curvature is None and self.inequalities and not self._steps_exist(z, h, Az):
                # no step keeps the linearised limits: said before the curvature's N evaluations
                # (the falling cat's energy optimum at the feasible plan's 6 coefficients: 25
                # evaluations, a sixth of its time, to the same end)
                self.its += 1
                self.why = "no step keeps the linearised limits"
                self.z = polish_endpoint(prob, z, self.tol)
                return self
            self.Hc = prob.curvature(prob.c(z), Ac, REFRESH_LEADING) if curvature is None else curvature
            Hz = prob.zhessians(self.Hc)

            def refresh(zn):
                self.Hc = prob.curvature(prob.c(zn), prob.h(zn)[3], REFRESH_LEADING)
                return prob.zhessians(self.Hc)

            z, info = sqp(prob, z, Hz, tol=self.tol, kkt_tol=kkt_tol, refresh=refresh,
                          ineq=self.ineq)
            self.its += info["its"]
            self.why = info["why"]
            # a stage's optimum (``polish=False``: the next size starts from it) is polished too when
            # its endpoint ended outside the tolerance: judged as it was, it stopped the ladder (12
            # random segments of the spatial zoo: four ladders stopped at 10 or 20 coefficients by
            # an endpoint 1.02e-10 off, benchmarks/RESULTS.md, 2026-12-06, tenth session)
            if polish or self.inequalities or prob.system.error(prob.h(z)[2], prob.x1) > self.tol:
                z = polish_endpoint(prob, z, self.tol, self.ineq)
            self.z = z
        except OutOfEvaluations:
            self.z, self.failed = z, f"the evaluation budget ({prob.max_evaluations}) was spent"
        except backend.IntegrationError as e:
            self.z, self.failed = z, f"the integrator failed ({e})"
        return self

    def _steps_exist(self, z, h, Az) -> bool:
        """Whether some step :math:`p` meets the linearised endpoint and limits at ``z``,
        :math:`A p = -h`, :math:`R p \\le -r` (the quadratic programs of :func:`~acroplan.core.sqp.sqp`
        have a step exactly then, whatever their Hessian)."""
        r, R = self.prob.ineq(z)
        return least_norm_step(Az, -h, R, -r)[1]

    def refine(self, kkt_tol):
        """More SQP iterations at this size from the current optimum, with its curvature."""
        if self.failed or self.Hc is None:
            return self
        prob = self.prob
        try:
            Hz = prob.zhessians(self.Hc)
            z, info = sqp(prob, self.z, Hz, tol=self.tol, kkt_tol=kkt_tol, ineq=self.ineq)
            self.its += info["its"]
            self.why = info["why"]
            self.z = polish_endpoint(prob, z, self.tol, self.ineq)
        except (OutOfEvaluations, backend.IntegrationError):
            pass
        return self

    def predicted_decrease(self, c0, curvature=None):
        """The relative decrease of the cost that one Newton step of the SQP from ``c0`` (the
        previous size's optimum, padded) predicts at this size: :math:`-(g^\\top p +
        \\tfrac12 p^\\top W p)/f` with the step :math:`p` of the KKT system (one evaluation,
        reused by a :meth:`solve` from the same point). ``inf`` when the model is not convex on the
        constraints' tangent space or the evaluation fails (then the size is solved)."""
        prob = self.prob
        z = prob.z(c0)
        try:
            f, g, H = prob.f(z)
            h, A, _, _ = prob.h(z)
        except (OutOfEvaluations, backend.IntegrationError):
            return math.inf
        lam, _ = kkt_multipliers(g, A)
        W = H.copy()
        if curvature is not None:
            W += np.tensordot(lam, prob.zhessians(curvature), axes=1)
        out = kkt_step(W, g, h, A, H, convex_only=True)
        if out is None or f <= 0:
            return math.inf
        p, _ = out
        return max(-(float(g @ p) + 0.5 * float(p @ W @ p)) / f, 0.0)

    def brief(self, on_grid: bool = False):
        """``(success, cost)`` of the current point, cheaply (no KKT residual, no message); the full
        :meth:`result` when it failed. ``on_grid``: the limits checked on the grid's rows alone
        (:meth:`OptimalProblem.ineq`, to :data:`~acroplan.core.sqp.INEQ_TOL`), not between its
        points (the dense check of :meth:`result`)."""
        if self.failed or (self.inequalities and not on_grid):
            r = self.result()
            return r.success, r.objective, r
        try:
            h, _, y, _ = self.prob.h(self.z)
        except (OutOfEvaluations, backend.IntegrationError):
            r = self.result()
            return r.success, r.objective, r
        if self.prob.system.error(y, self.prob.x1) > self.tol or (
                self.inequalities and not self.prob.ineq(self.z)[0].max(initial=-1.0) <= INEQ_TOL):
            r = self.result()
            return False, r.objective, r
        return True, self.prob.f(self.z)[0], None

    def result(self, **extra) -> OptimalSolve:
        prob, z = self.prob, self.z
        self.broken = {"limits": False, "torque": False}
        system, basis = prob.system, prob.basis
        m, n = prob.m, prob.n
        c = prob.c(z)
        nan = float("nan")
        if self.failed:
            return OptimalSolve(False, self.failed, c.reshape(m, n), basis, nan, nan, nan, np.zeros(system.ndx),
                                float("inf"), prob.evaluations, self.its, self.solver, **extra)
        try:
            h, A, y, _ = prob.h(z)
        except (OutOfEvaluations, backend.IntegrationError) as e:
            return OptimalSolve(False, f"the endpoint could not be evaluated ({e})", c.reshape(m, n), basis, nan, nan,
                                nan, np.zeros(system.ndx), float("inf"), prob.evaluations, self.its, self.solver,
                                **extra)
        f, g, _ = prob.f(z)
        C = []  # active inequalities, for the KKT residual
        if prob.lin is not None:
            Az, bz = prob.lin
            C.append(Az[bz - Az @ z <= 1e-7 * (1.0 + np.abs(bz))])
        if prob.tmax is not None:
            tau, tmax, Jt = prob._torque_limit_rows(z)
            top, near = tmax * (1.0 - TORQUE_MARGIN), 1e-7 * (1.0 + tmax)
            C += [Jt[top - tau <= near], -Jt[top + tau <= near]]
        C = np.vstack(C) if C else None
        lam, kkt = kkt_multipliers(g, A, C)
        err = system.error(y, prob.x1)
        ok = err <= self.tol
        msg = (f"{self.fn.label} = {f:.10g} with {n} coefficient(s) per input ({self.solver}, {self.its} "
               f"iteration(s), {prob.evaluations} evaluations): endpoint error {err:.2e}, relative KKT residual "
               f"{kkt:.1e}")
        if prob.limits is not None:
            v = violation(system, basis, prob.x0, prob.T, c, prob.limits)
            self.broken["limits"] = not (v["u"] <= COMPLIANCE_TOL and v["state"] <= COMPLIANCE_TOL)
            ok = ok and not self.broken["limits"]
            msg += f", limit violation {max(v['u'], v['state']):.1e}"
        if prob.tmax is not None:
            peak = prob.torque_check(c.ravel())[2]
            excess = float(np.max(peak - np.broadcast_to(prob.tmax, peak.shape)))
            self.broken["torque"] = not excess <= COMPLIANCE_TOL * max(1.0, float(np.max(
                prob.tmax[np.isfinite(prob.tmax)], initial=1.0)))
            ok = ok and not self.broken["torque"]
            msg += f", max(|tau| - tau_max) = {excess:.2e}"
        if self.why:
            msg += f" ({self.why})"
        return OptimalSolve(ok, msg, c.reshape(m, n), basis, f, energy(basis, prob.T, c.reshape(m, n)), kkt, lam, err,
                            prob.evaluations, self.its, self.solver, **extra)


def optimize_segment(system: ControlAffineSystem, basis: InputBasis, x0, x1, T: float, start, *, B=None, d=None,
                     cost="energy", limits=None, tau_max=None, tol: float = 1e-10, kkt_tol: float = KKT_TOL,
                     max_evaluations: int = 2000) -> OptimalSolve:
    """Minimise the cost on one segment at one basis size, from ``start`` (no ladder).

    Parameters
    ----------
    system : ControlAffineSystem
    basis : InputBasis
    x0, x1 : array_like, shape (n,)
    T : float
    start : array_like, shape (m, basis.n)
        Starting coefficients (feasible or not; projected onto :math:`Bc = d`).
    B, d : array_like, optional
        Input conditions :math:`Bc = d` (:func:`~acroplan.core.conditions.linear_conditions`).
    cost : "energy" or TorqueModel
        :math:`\\int\\|u\\|^2 dt` or :math:`\\int\\|\\tau\\|^2 dt` with the given torque model.
    limits : Limits, optional
        Rate and joint limits (linear inequalities on a grid).
    tau_max : array_like, shape (p,), optional
        Torque limits per joint (``cost`` must then be a torque model).
    tol : float
        Endpoint tolerance.
    kkt_tol : float
        Target relative KKT residual of the SQP.
    max_evaluations : int
        Endpoint evaluations at most.

    Returns
    -------
    OptimalSolve
    """
    if isinstance(cost, str) and cost != "energy":
        raise InvalidInputError("cost", f"must be \"energy\" or a torque model, got {cost!r}",
                                "give \"energy\" or a callable torque(system, basis, x0, T, c, s)")
    if tau_max is not None and isinstance(cost, str):
        raise InvalidInputError("tau_max", "torque limits need a torque model", "pass the model as cost=")
    model = None if isinstance(cost, str) else cost
    run = OptimalRun(system, basis, x0, x1, T, cost, model, limits, tau_max, B, d, tol, max_evaluations)
    out = run.solve(np.asarray(start, dtype=float).reshape(-1), kkt_tol=kkt_tol).result()
    return dataclasses.replace(out, sizes=((basis.n, out.objective),))

