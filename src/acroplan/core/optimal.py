"""Optimal plans: the minimum-energy and the minimum-torque input on each waypoint interval.

The front doors reach them by ``objective="energy"`` or ``"torque"`` (and ``tau_max=``) of
:func:`acroplan.plan` and :func:`acroplan.plan_many` (:func:`objective_strategy`); they are also
registered strategies, ``method="energy-optimal"`` and ``"torque-optimal"``. Each segment of an
optimal plan carries its diagnostics (:meth:`EnergyOptimal.diagnostics`) as
:attr:`SegmentResult.optimality <acroplan.core.result.SegmentResult.optimality>`.

Through interior waypoints the front door then optimises the intervals together
(:meth:`EnergyOptimal.joint`, :mod:`~acroplan.core.chain`): one interval at a time gives the best
plan of each interval given the ones before, not the least cost of the whole plan. The intervals'
optima are then only the joint optimum's start, reported as their ladders left them
(:data:`PROVISIONAL_STARTS`); the front door plans them in full when the joint optimum is not kept.

Where path deformation (:mod:`~acroplan.core.continuation`) finds *an* input that reaches the
target, the strategies here find the best one within the input basis, for one of two costs:

* :class:`EnergyOptimal` (``"energy-optimal"``): the control energy

  .. math::  E(c) = \\int_0^T \\|u(t)\\|^2\\,dt = T \\int_0^1 \\|u(s)\\|^2\\,ds
             = T\\, c^\\top (I_m \\otimes G)\\, c ,\\qquad G_{ik} = \\int_0^1 b_i b_k\\,ds ,

  exactly, with :math:`G` the basis Gram matrix (:meth:`InputBasis.gram`, diagonal
  :math:`1/(2i+1)` for the Legendre basis).
* :class:`TorqueOptimal` (``"torque-optimal"``): :math:`\\int_0^T \\|\\tau(t)\\|^2 dt` for joint
  torques :math:`\\tau` that a *torque model* computes from the planned motion (the core knows no
  body: the model is a callable, :data:`TorqueModel`; the acrobot's is
  :class:`acroplan.families.acrobot.effort.AcrobotTorque`), by composite Gauss-Legendre
  quadrature (:data:`TORQUE_QUADRATURE`).

The problem on one interval, in the reduced coordinates :math:`c = c_p + Z z` that carry the
input conditions :math:`Bc = d` exactly (as :func:`~acroplan.core.limits.solve_with_limits`),

.. math::  \\min_z f(c(z)) \\quad\\text{s.t.}\\quad
           h(z) = -\\mathrm{diff}(\\Phi(c(z)), x_1) = 0 ,\\qquad
           A\\,c(z) \\le b ,\\qquad |\\tau_j(s_k)| \\le \\bar\\tau_j ,

with :math:`\\Phi` the endpoint map of the compiled integrator, :math:`\\partial h/\\partial z` from
its variational equations through :meth:`~ControlAffineSystem.tangent_jacobian`, :math:`A c \\le b`
the rate and joint limits on a grid of 64 points (:func:`~acroplan.core.limits.linear_limits`,
margin 2e-3) and the torque limits on a grid of :data:`TORQUE_LIMIT_GRID` points (margin 2e-3).

Solvers
-------
* **An SQP of our own.** The model Hessian is the cost's (exact for the energy,
  :math:`2T(I_m\\otimes G)`; Gauss-Newton for the torque cost) plus the constraints' curvature
  :math:`\\sum_i \\lambda_i \\nabla^2 h_i`, whose Hessians are taken by forward differences of the
  endpoint Jacobian at the first basis size (``len(z)`` evaluations; again, at most
  :data:`MAX_REFRESH` times, after :data:`~acroplan.core.sqp.POOR_STEPS` steps in a row the model
  predicted poorly), carried over padded with
  zeros to the next sizes, and corrected by symmetric rank-one updates from the secant of the
  Lagrangian's gradient. Without inequalities a step solves the KKT system
  :math:`Wp + A^\\top\\lambda = -\\nabla f,\\ Ap = -h`; when :math:`W` is not positive definite
  on :math:`\\ker A` the reduced Hessian's eigenvalues are replaced by their magnitudes (at least
  1e-6 of the largest). Steps are accepted on the :math:`\\ell_1` merit function
  :math:`f + \\rho(\\|h\\|_1 + \\sum_i \\max(0, r_i))` (:math:`\\rho` twice the largest multiplier),
  with a second-order correction back onto the constraints at every trial (the Maratos effect),
  and a cap on the step length in the cost's metric that follows the steps taken (so no trial
  input is wild: the integrator's cost grows with the input). From a warm start it takes two to
  five iterations per basis size (measured on random acrobot segments).
* **With rate, joint or torque limits** the same SQP takes the limits :math:`r(z) \\le 0` as the
  inequalities of its quadratic programs (:func:`acroplan.core.sqp.qp_step`: the equations
  eliminated, the reduced Hessian made positive definite as above, then a least-distance program
  solved by non-negative least squares), the active limits' multipliers in the merit function, the
  KKT residual and the curvature updates; the optimum is then brought onto the endpoint by
  minimum-norm Newton steps as :func:`~acroplan.core.limits.solve_with_limits`, and success needs
  the limits to hold exactly (:func:`~acroplan.core.limits.violation`) and the torque limits at
  their peaks (sampled on :func:`~acroplan.core.objectives.torque_check_grid`, the peaks within 1%
  of a limit refined between the points as the plan's effort summary refines them:
  :meth:`~acroplan.core.optimum.OptimalProblem.torque_check`). The ladder's sizes are compared
  with their limits met on their grids (:data:`LADDER_ON_GRID`: each size is the next one's warm
  start); the reported optimum, when it breaks a limit between the grid's 64 points, is solved
  again from it with the limits it broke (the rate and joint limits, or the torque limits, or both)
  on :data:`DENSE_LIMIT_GRID` points (:meth:`_Search.denser`), then, while it still breaks a torque
  limit, with the times of the largest excesses, and a time on either side of each
  (:data:`~acroplan.core.optimum.EXCHANGE_SPREAD`), added to the torque limits' grid
  (:data:`EXCHANGE_ROUNDS`); and so is the first size's optimum, where the starts are compared,
  and the intervals' joint optimum (:data:`JOINT_LIMIT_GRIDS`, the first grid with
  :data:`JOINT_LIMIT_ENDS` Chebyshev points at the ends too, and every grid's torque limits also
  on points crowded at the intervals' ends, :data:`JOINT_TORQUE_ENDS`). (Before issue #22 the limits went to
  scipy's SLSQP, where the falling cat's energy optimum took 160 s; ``benchmarks/RESULTS.md`` has
  the figure now.) A size whose linearised limits no step can keep (a start far outside them)
  fails, and the next size is tried. The second-order correction of a trial step keeps the limits
  near their bound and holds the quadratic program's active rows at it
  (:func:`acroplan.core.sqp._corrected`), as the endpoint's final polish holds the active rows
  (:func:`acroplan.core.sqp.polish_endpoint`).

First-order optimality is reported as the relative KKT residual

.. math::  \\kappa = \\frac{\\|\\nabla_z f + (\\partial h/\\partial z)^\\top\\lambda
           + C_{\\mathcal A}^\\top \\mu\\|_2}{\\|\\nabla_z f\\|_2}

in the reduced coordinates :math:`z`, with least-squares multipliers :math:`\\lambda` of the
endpoint equations and :math:`\\mu \\ge 0` of the inequalities active within 1e-7 of their bound
(non-negative least squares): the part of the cost's gradient the constraints do not explain.
The sizes of the ladder are solved to :data:`FIRST_KKT_TOL` / :data:`STAGE_KKT_TOL` (1e-3); the
reported optimum, and any size the ladder would stop on, is refined to :data:`KKT_TOL` (1e-8).

Basis size
----------
The optimum over polynomials of degree :math:`n - 1` approaches the optimum over all inputs as
:math:`n` grows (geometrically, for smooth optima, in the Legendre basis). The strategies go up the
ladder :data:`SIZES` (6, 10, 14, 20, 26, 30), from the size of the feasible plan, and stop when the
optimal cost changes by less than ``rtol`` (:data:`RTOL`, 1e-4) relative from one size to the
next. The change to the next size is first *predicted* by one Newton step of the SQP there, from
the current optimum padded with zero coefficients (the same input): one endpoint evaluation,
:math:`\\Delta = -(\\nabla f^\\top p + \\tfrac12 p^\\top W p)/f`. When :math:`\\Delta` < ``rtol``
the current size is converged and is the one reported; otherwise the next size is solved
(warm-started there) and the solved change decides. The prediction is accurate to ~10% and
slightly above the solved change (measured on 40 random acrobot segments, and tested), so it stops
no earlier than solving would; a model that is not convex there (a symmetric optimum) gives no
prediction and the size is solved. Under limits every size is solved. With
``n_coefficients`` given, that one size is used. A system's class may set its own ladder for
an objective, ``optimal_sizes = {"torque": (...)}``, and for an interval whose optimum starts the
joint optimum of several intervals (key ``"joint"``: :attr:`Interval.joint
<acroplan.core.strategies.Interval>`), used when the strategy is given no sizes (the spatial
bodies climb 6, 14, 30 for the least :math:`\\int u^2`, 6, 30 before a joint optimum, and step their least
:math:`\\int\\tau^2` by 4 from 14 coefficients: :attr:`acroplan.families.spatial.model.SpatialBody.optimal_sizes`).

Starts
------
The optimum found is local, so the first size is optimised from more than one start, the better
optimum going up the ladder:

* **a family's starts** when the system's family provides them (:func:`register_starts`), feasible
  by construction and cheap: the acrobot's are the two joint motions of the flat output's bump
  family that meet the target, one bulging each way
  (:func:`acroplan.families.acrobot.effort.optimal_starts`, about 0.1 ms and no ODE). The cheaper
  is optimised; the other only when it is *distinct* (its input more than :data:`DISTINCT` = 0.5
  from that optimum, relative, in :math:`L^2`) and *promising* (its cost below
  :data:`FAMILY_PROMISING` = 2 times that optimum's).
* otherwise, or when those fail, **the plan of the system's own** ``method="auto"`` (projected on
  the basis when it has several pieces; a size whose projection misses the plan's input by more
  than :data:`START_PROJECTION_ERROR` is not tried with it) and, as the second start, **path
  deformation from the minimum-norm input** (the text's method, :func:`~acroplan.core.continuation.solve_segment`, at
  most :data:`DEFORM_BUDGET` evaluations), optimised when distinct and promising (cost below
  :data:`PROMISING` = 8 times); a system whose class sets ``optimal_deform_start = False`` (the
  spatial bodies) has no second start unless ``starts`` names it.

Measured on 800 random acrobot segments (:func:`acroplan.zoo.random_segment`, seeds 5, 11, 21
and 31): with ``starts=("auto", "deform")``, 11 problems end at a better optimum from the second
start (by 5-24%), none of those closer than 0.5 to the first optimum (400 checked) and all with a
cost below 4.3 times it; with the family's starts (the default for the acrobot) the optimum is never
worse than with ``("auto", "deform")``, better on 6 problems, below the auto plan's cost on all
400 checked, and found 30% faster (median). ``starts`` selects them explicitly: any of
``"auto"``, ``"family"``, ``"deform"``.

Scope: each waypoint interval is optimised on its own, with its input conditions; under
``conditions="free"`` interval :math:`k` starts with the input interval :math:`k-1` ended with,
so a plan of several intervals is optimal interval by interval, not jointly.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Callable, Sequence

import numpy as np

from .basis import InputBasis
from .continuation import solve_segment
from .errors import InvalidInputError
from .linalg import null_space
from .objectives import (TORQUE_LIMIT_GRID, TORQUE_MARGIN, TORQUE_QUADRATURE, TorqueModel, cost_for, energy, gauss,
                         tau_vector)
from .optimum import FIRST_KKT_TOL, KKT_TOL, STAGE_KKT_TOL, OptimalRun, OptimalSolve, optimize_segment
from .progress import note as progress_note
from .sqp import MAX_REFRESH, kkt_step
from .strategies import AUTO_DEFAULT, Interval, IntervalOutcome, Strategy, make_segment, register_strategy
from .system import ControlAffineSystem, torque_model_of

__all__ = ["EnergyOptimal", "TorqueOptimal", "OptimalSolve", "optimize_segment", "energy", "TorqueModel",
           "OBJECTIVES", "objective_strategy", "FAMILY_STARTS", "register_starts", "family_starts", "SIZES",
           "MAX_LADDER_SIZE", "RTOL", "own_ladder",
           "KKT_TOL", "STAGE_KKT_TOL", "FIRST_KKT_TOL", "DEFORM_BUDGET", "DEFORM_TOL", "DISTINCT", "PROMISING",
           "FAMILY_PROMISING", "MAX_REFRESH", "TORQUE_QUADRATURE", "TORQUE_LIMIT_GRID", "TORQUE_MARGIN", "tau_vector"]

#: the SQP step (:func:`acroplan.core.sqp.kkt_step`), under its former name
_step = kkt_step

#: Basis sizes of the ladder (:class:`EnergyOptimal`), smallest first.
SIZES = (6, 10, 14, 20, 26, 30)
#: The largest basis size a ladder may climb to (:func:`acroplan.plan`'s ``max_coefficients``)
MAX_LADDER_SIZE = 60
#: The ladder stops when the optimum's cost changes by less than this, relative, between sizes.
RTOL = 1e-4
#: Endpoint evaluations allowed to path deformation from the minimum-norm input (the second start).
DEFORM_BUDGET = 10
#: Endpoint tolerance of that path deformation (a nearly feasible start is enough for the SQP).
DEFORM_TOL = 1e-6
#: The second start is optimised only when its input differs from the first optimum by more than
#: this, relative, in :math:`L^2` (module docstring, Starts).
DISTINCT = 0.5
#: ... and when its cost is less than this multiple of the first optimum's (path deformation) ...
PROMISING = 8.0
#: ... or of a family's start (:func:`register_starts`).
FAMILY_PROMISING = 2.0


# ------------------------------------------------------------------------------------ the ladder
def _pad_curvature(Hc, m, n, n2):
    """Constraint Hessians (q, m n, m n) in flattened ``c``, padded with zeros to size ``n2`` (the new
    coefficients' curvature is left to the quasi-Newton updates)."""
    q = Hc.shape[0]
    out = np.zeros((q, m * n2, m * n2))
    for a in range(m):
        for b in range(m):
            out[:, a * n2:a * n2 + n, b * n2:b * n2 + n] = Hc[:, a * n:(a + 1) * n, b * n:(b + 1) * n]
    return out


def _resize(c, n2):
    """Coefficients (m, n) as (m, n2): padded with zeros (the same input) or truncated."""
    c = np.atleast_2d(np.asarray(c, dtype=float))
    out = np.zeros((c.shape[0], n2))
    k = min(n2, c.shape[1])
    out[:, :k] = c[:, :k]
    return out


def _projection(pieces, interval: Interval, basis: InputBasis):
    """``(coefficients, error)``: the coefficients in ``basis`` on the whole interval closest (least
    squares on 256 Gauss nodes) to the input of ``pieces``, under the interval's input conditions,
    and their relative L2 error against that input, :math:`\\|u_n - u\\|_2 / \\|u\\|_2`. A single
    piece in the same basis family is taken as it is (padded or truncated; error 0)."""
    if len(pieces) == 1 and pieces[0].basis is not None and type(pieces[0].basis) is type(basis):
        return _resize(pieces[0].basis_coefficients, basis.n), 0.0
    T = interval.T
    s, w = gauss(8, 32)
    t = s * T
    u = np.empty((interval.system.n_inputs, s.size))
    bounds = np.array([p.t1 for p in pieces])
    which = np.minimum(np.searchsorted(bounds, t, side="right"), len(pieces) - 1)
    for k, p in enumerate(pieces):
        idx = np.nonzero(which == k)[0]
        if idx.size:
            u[:, idx] = p.input(np.clip(t[idx], p.t0, p.t1))
    sw = np.sqrt(w)
    V = basis.matrix(s) * sw[:, None]
    B, d = interval.conditions(basis)
    m, n = interval.system.n_inputs, basis.n
    out = np.zeros((m, n))
    for j in range(m):
        rows = np.zeros(0, dtype=int) if B is None else np.flatnonzero(np.any(B[:, j * n:(j + 1) * n] != 0, axis=1))
        if rows.size == 0:
            out[j] = np.linalg.lstsq(V, u[j] * sw, rcond=None)[0]
        else:
            Bj, dj = B[rows][:, j * n:(j + 1) * n], d[rows]
            cp = np.linalg.lstsq(Bj, dj, rcond=None)[0]
            Zj = null_space(Bj, n)
            out[j] = cp + Zj @ np.linalg.lstsq(V @ Zj, u[j] * sw - V @ cp, rcond=None)[0]
    size = float(np.linalg.norm(u * sw))
    return out, (float(np.linalg.norm(out @ V.T - u * sw)) / size if size > 0.0 else 0.0)


def _distance(basis, T, c, ref) -> float:
    """:math:`\\|u_c - u_{ref}\\|_{L^2} / \\|u_{ref}\\|_{L^2}` on the segment (exact)."""
    c, ref = np.atleast_2d(c), np.atleast_2d(ref)
    return math.sqrt(energy(basis, T, c - ref) / max(energy(basis, T, ref), 1e-300))


#: Starts a family provides for the optimal strategies: system class -> ``starts(interval, basis)``
#: returning a list of ``(label, coefficients of shape (m, basis.n))`` (:func:`register_starts`).
FAMILY_STARTS: dict[type, Callable] = {}


def register_starts(system_type: type, starts: Callable) -> None:
    """Make ``starts(interval, basis) -> [(label, coefficients), ...]`` the family starts of the
    optimal strategies for systems of ``system_type`` (and its subclasses); a family registers its
    own when imported (the acrobot's: :func:`acroplan.families.acrobot.effort.optimal_starts`). A
    system may instead define a method ``optimal_starts(interval, basis)``."""
    if not (isinstance(system_type, type) and issubclass(system_type, ControlAffineSystem)):
        raise InvalidInputError("system_type", f"must be a ControlAffineSystem subclass, got {system_type!r}",
                                "pass the system's class")
    if not callable(starts):
        raise InvalidInputError("starts", f"must be callable, got {starts!r}", "give starts(interval, basis)")
    FAMILY_STARTS[system_type] = starts


def family_starts(system, interval: Interval, basis: InputBasis):
    """The family's starts for ``interval`` in ``basis`` (:func:`register_starts`), or ``None`` when
    the family provides none."""
    for cls in type(system).__mro__:
        if cls in FAMILY_STARTS:
            return list(FAMILY_STARTS[cls](interval, basis))
    hook = getattr(system, "optimal_starts", None)
    return list(hook(interval, basis)) if callable(hook) else None


class _Search:
    """One interval's optimisation (:meth:`EnergyOptimal.optimize`): the runs at each basis size, the
    evaluations they spent and the reasons of what failed (module docstring: Starts, Basis size)."""

    def __init__(self, strategy: "EnergyOptimal", interval: Interval, model):
        self.strategy, self.interval, self.model = strategy, interval, model
        self.system = interval.system
        self.cost = model if strategy._cost_kind == "torque" else "energy"
        self.tmax = tau_vector(strategy.tau_max, model)
        lim = interval.limits
        self.limits = lim if lim is not None and lim.active else None
        self.sizes = interval.sizes or strategy.ladder(self.system, joint=interval.joint)
        self.evaluations = 0
        self.reasons, self.notes = [], []
        #: why the ladder stopped at a size that failed (that size's reason), or None
        self.ladder_stop = None
        self.feasible_pieces = ()
        self.first = self.sizes[0]
        self._conditions = {}

    @staticmethod
    def failure(interval: Interval, message: str, pieces=(), evaluations: int = 0):
        """``(OptimalSolve, pieces)`` of a failure, with ``message``."""
        system, nan = interval.system, float("nan")
        c = np.zeros((system.n_inputs, interval.basis.n))
        return OptimalSolve(False, message, c, interval.basis, nan, nan, nan, np.zeros(system.ndx), float("inf"),
                            evaluations), tuple(pieces)

    def sized(self, n):
        """``(basis, B, d)`` at size ``n`` (cached)."""
        if n not in self._conditions:
            bn = self.interval.sized(n)
            self._conditions[n] = (bn,) + tuple(self.interval.conditions(bn))
        return self._conditions[n]

    def new_run(self, n, limit_grid: int | None = None, torque_grid: int | None = None,
                limit_ends: int = 0, torque_ends: bool = False) -> OptimalRun:
        """A run at size ``n`` with the rate and joint limits on ``limit_grid`` points (default
        :data:`LIMIT_GRID`; and ``limit_ends`` Chebyshev points, :func:`~acroplan.core.limits.linear_limits`)
        and the torque limits on ``torque_grid`` (default as
        :class:`~acroplan.core.optimum.OptimalProblem`; with ``torque_ends``, also on
        :func:`~acroplan.core.optimum.end_cluster`)."""
        limit_grid = LIMIT_GRID if limit_grid is None else limit_grid
        bn, B, d = self.sized(n)
        iv = self.interval
        return OptimalRun(self.system, bn, iv.x0, iv.x1, iv.T, self.cost, self.model, self.limits, self.tmax, B, d,
                          iv.tol, iv.max_evaluations, limit_grid, torque_grid, limit_ends, torque_ends)

    def first_stage(self, n, candidates):
        """Optimise the candidates ``(label, coefficients, promising)`` at size ``n``: the first one
        unconditionally, each later one only when it is distinct from the best optimum so far and its
        cost below ``promising`` times that optimum's. Returns ``(value, label, run)`` of the best or
        ``None``."""
        done = []
        iv, m = self.interval, self.system.n_inputs
        bn = self.sized(n)[0]
        fn = cost_for(self.cost, self.system, bn, iv.x0, iv.T)
        for label, c, promising in candidates:
            c = np.asarray(c, dtype=float).reshape(m, bn.n)
            curvature = None
            if done:
                best_value, _, best_run = min(done, key=lambda item: item[0])
                near = _distance(bn, iv.T, c, best_run.prob.c(best_run.z).reshape(m, -1))
                ratio = fn(c.reshape(-1))[0] / max(best_value, 1e-300)
                if not (near > DISTINCT and ratio < promising):
                    self.notes.append(f"the {label} start ({near:.2f} from the optimum, {ratio:.3g} times its cost) "
                                      "was not optimised")
                    continue
                curvature = best_run.Hc  # start from the best optimum's curvature
            run = self.new_run(n).solve(c.reshape(-1), curvature=curvature, kkt_tol=FIRST_KKT_TOL, polish=False)
            self.evaluations += run.prob.evaluations
            run, ok, value, full = self.denser(run, n, FIRST_KKT_TOL)
            if ok:
                done.append((value, label, run))
            else:
                self.reasons.append(f"{n} coefficients from the {label} start: {full.message if full else ''}")
        return min(done, key=lambda item: item[0]) if done else None

    def denser(self, run, n, kkt_tol):
        """``(run, success, cost, full result or None)`` of ``run`` at size ``n``, or of the same size
        solved again from its optimum with the limits it broke between its grid's points on
        :data:`DENSE_LIMIT_GRID` points (the rate and joint limits, the torque limits, or both:
        :func:`_denser_grids`), when it broke some (its endpoint met, the dense check of
        :meth:`OptimalRun.result` failed) and the denser grid's optimum does not; while that one
        still breaks only a torque limit, up to :data:`EXCHANGE_ROUNDS` exchange rounds (the times
        of the largest excesses join its torque grid, :meth:`OptimalProblem.torque_excess_times`,
        and its SQP goes on). The bundled forward dive's least integral of u^2 within the strength
        broke a torque limit by 0.23 to 414 N m between 65 points at every size, and ended not
        converged; without the exchange rounds the double full-out's ladders stopped at 14 of 30
        coefficients on two intervals, their 20 coefficients' optima breaking a torque limit
        between 257 points (the least integral of u^2 then 0.14% higher). (Starting the next sizes,
        or the joint optimum, on the denser grid was slower: each evaluation of the torque limits
        costs four times as much.)"""
        ok, value, full = run.brief()
        if ok or run.failed or not run.inequalities or full is None or not full.final_error <= run.tol:
            return run, ok, value, full
        grids = _denser_grids([run], DENSE_LIMIT_GRID)
        if grids is None:
            return run, ok, value, full
        again = self.new_run(n, *grids).solve(run.prob.c(run.z), curvature=run.Hc, kkt_tol=kkt_tol, polish=False)
        self.evaluations += again.prob.evaluations
        ok2, value2, full2 = again.brief()
        for _ in range(EXCHANGE_ROUNDS):
            if ok2 or again.failed or full2 is None or not again.broken["torque"] or again.broken["limits"]:
                break
            # the denser grid's optimum still breaks a torque limit between its points: the times of
            # the largest excesses join the grid and the SQP goes on from there (as the joint
            # optimum's exchange rounds; the 3-D human's arms-and-hips back full, least integral of
            # u^2 within the strength, broke a hip's by 0.4 to 0.6 N m between 257 points at 14
            # coefficients, and its ladder had stopped at 10)
            before = again.prob.evaluations
            if not again.prob.add_torque_times(again.prob.torque_excess_times(again.z)):
                break
            again.solve(again.prob.c(again.z), curvature=again.Hc, kkt_tol=kkt_tol, polish=False)
            self.evaluations += again.prob.evaluations - before
            ok2, value2, full2 = again.brief()
        if ok2:
            return again, ok2, value2, full2
        return run, ok, value, full

    def deform_start(self, n):
        """Path deformation from the minimum-norm input at size ``n``, as a candidate (or none)."""
        bn, B, d = self.sized(n)
        iv = self.interval
        out = solve_segment(self.system, bn, iv.x0, iv.x1, iv.T, B=B, d=d, tol=DEFORM_TOL,
                            max_evaluations=min(DEFORM_BUDGET, iv.max_evaluations), starts=1)
        self.evaluations += out.evaluations
        return [("deform", out.coefficients, PROMISING)] if out.success else []

    def starts(self):
        """Step 1: the family's starts (feasible by construction) when it has them, else (or when they
        fail) the plan of the system's ``method="auto"``, with the family's starts or path
        deformation. Returns ``(best, None)`` or ``(None, failure)``."""
        st, iv = self.strategy, self.interval
        explicit = st.starts is not None
        fam = family_starts(self.system, iv, iv.sized(self.first)) if not explicit or "family" in st.starts else None
        best = None
        if fam and not explicit:
            fn = cost_for(self.cost, self.system, iv.sized(self.first), iv.x0, iv.T)
            ranked = sorted(fam, key=lambda item: fn(np.ravel(item[1]))[0])
            best = self.first_stage(self.first, [(label, c, FAMILY_PROMISING) for label, c in ranked])
        if best is None:
            if explicit and "auto" not in st.starts:
                candidates = [(label, c, FAMILY_PROMISING) for label, c in (fam or ())]
                best = self.first_stage(self.first, candidates + (self.deform_start(self.first)
                                                                  if "deform" in st.starts else []))
            else:
                best, failed = self.auto_start(fam)
                if failed is not None:
                    return None, failed
        if best is None:
            return None, self.failure(iv, f"{st.name}: no start reached an optimum: " + "; ".join(self.reasons),
                                      self.feasible_pieces, self.evaluations)
        return best, None

    def auto_start(self, fam):
        """The plan of the system's ``method="auto"`` as the start (with the family's starts or path
        deformation as the second), from the feasible plan's own basis size up. Returns ``(best,
        None)`` or ``(None, failure)``."""
        st, iv, sizes = self.strategy, self.interval, self.sizes
        explicit = st.starts is not None
        feasible = (st.feasible or self.system.auto_strategy() or AUTO_DEFAULT).solve(iv)
        self.evaluations += (sum(p.evaluations for p in feasible.pieces) if feasible.success
                             else feasible.evaluations)
        if not feasible.success:
            return None, self.failure(iv, f"no feasible plan to start from: {feasible.reason}", feasible.pieces,
                                      self.evaluations)
        self.feasible_pieces = tuple(feasible.pieces)
        if iv.sizes is None and len(feasible.pieces) == 1 and feasible.pieces[0].basis is not None:
            n0 = feasible.pieces[0].basis.n  # start at the feasible plan's own size, where it is exact
            self.first = next((n for n in sizes if n >= n0), sizes[-1])
        use_family = explicit and "family" in st.starts
        # a system may leave the second start out by default (``optimal_deform_start = False``)
        use_deform = "deform" in st.starts if explicit else getattr(self.system, "optimal_deform_start", True)

        def candidates_at(n, bn, c):  # lazily: path deformation only once the auto start is done
            if c is not None:
                yield ("auto", c, math.inf)
            if use_family:
                more = fam if n == sizes[0] and fam else (family_starts(self.system, iv, bn) or [])
                for label, c in more:
                    yield (label, c, FAMILY_PROMISING)
            if use_deform:
                yield from self.deform_start(n)

        for n in (n for n in sizes if n >= self.first):
            bn = iv.sized(n)
            c, error = _projection(feasible.pieces, iv, bn)
            if error > START_PROJECTION_ERROR and n < sizes[-1]:
                # the feasible plan (several pieces) is not in this basis: its projection is no start
                why = (f"{n} coefficients not tried: the auto start's projection misses its input by {error:.2f} "
                       "(relative)")
                self.reasons.append(why)
                self.notes.append(why)
                if not (use_family or use_deform):
                    continue
                c = None
            best = self.first_stage(n, candidates_at(n, bn, c))
            if best is not None:
                self.first = n
                return best, None
        return None, None

    def ladder(self, best):
        """Step 2, the ladder of basis sizes from the first size's optimum ``best``. Returns ``(run,
        history, predicted_stop)``: the run of the reported size, ``[(n, cost), ...]`` and the
        predicted change when the ladder stopped on a prediction (else ``None``)."""
        rtol, m = self.strategy.rtol, self.system.n_inputs
        value, _, current = best
        history, previous, predicted_stop = [(self.first, value)], value, None
        for n in (n for n in self.sizes if n > self.first):
            progress_note("optimal: basis sizes", self.sizes.index(n), len(self.sizes), f"{n} coefficients")
            prev = current
            Hc = None if prev.Hc is None else _pad_curvature(prev.Hc, m, prev.prob.n, n)
            c0 = _resize(prev.prob.c(prev.z).reshape(m, -1), n).ravel()
            run = self.new_run(n)
            before = 0
            if not run.inequalities:  # the change to this size, predicted by one Newton step
                predicted = run.predicted_decrease(c0, Hc)
                self.evaluations += run.prob.evaluations
                before = run.prob.evaluations
                if predicted < rtol:
                    history.append((n, previous * (1.0 - predicted)))
                    predicted_stop = predicted
                    break
            run.solve(c0, curvature=Hc, kkt_tol=STAGE_KKT_TOL, polish=False)
            self.evaluations += run.prob.evaluations - before
            ok = False
            if LADDER_ON_GRID:
                # the sizes compared on their grids alone; the reported one is checked between the
                # points (and solved on the denser grid where it breaks a limit there) by report
                ok, value, full = run.brief(on_grid=True)
                run.checked = not (ok and run.inequalities)
            if not ok:
                run, ok, value, full = self.denser(run, n, STAGE_KKT_TOL)
            before = run.prob.evaluations  # counted so far (a denser grid's run, by denser)
            if ok and abs(previous - value) < rtol * abs(value):
                # a stop on a loosely solved size: decide on the refined optimum (lower, so the change
                # can only grow)
                run.refine(self.strategy.kkt_tol)
                ok, value, full = run.brief(on_grid=not run.checked)
            self.evaluations += run.prob.evaluations - before
            if not ok or value > previous * (1.0 + 1e-9):
                self.ladder_stop = f"{n} coefficients: " + (full.message if full is not None else
                                                            f"cost {value:.10g}, no better than the smaller basis")
                self.reasons.append(self.ladder_stop)
                break
            current = run
            history.append((n, value))
            change = abs(previous - value) / max(abs(value), 1e-300)
            previous = value
            if change < rtol:
                break
        return current, history, predicted_stop

    def _refined(self, current):
        """The reported size's optimum refined to the KKT target and checked between its grid's
        points (solved again on the denser grid where it breaks a limit there): its
        ``(result, run)``, the run the result is of (a denser grid's, when one was solved)."""
        st = self.strategy
        if not current.checked:
            # a size taken on its grid alone (LADDER_ON_GRID): checked between the points first, and
            # solved on the denser grid where it breaks a limit there, at the ladder's tolerance, so
            # that the refinement below is done once, on the grid it ends on
            current = self.denser(current, current.prob.n, STAGE_KKT_TOL)[0]
            current.checked = True
        before = current.prob.evaluations
        unrefined = current.z
        current.refine(st.kkt_tol)
        res = current.result()
        self.evaluations += current.prob.evaluations - before
        if not res.success and current.z is not unrefined:
            # the refinement left the limits between the grid's points: solved again from it with
            # those limits on the denser grid (the falling cat's least integral of tau^2, refined to
            # a KKT residual of 7e-9, broke a joint range between the 64 points, and the ladder's
            # point, at a residual of 0.48, had been reported instead; on 256 points 6.4e-5)
            again, ok, _, full = self.denser(current, current.prob.n, st.kkt_tol)
            if ok and again is not current:
                current, res = again, full
        if not res.success and current.z is not unrefined:
            # still refused (or the endpoint): the point the ladder accepted is reported instead,
            # with its own KKT residual
            before = current.prob.evaluations
            refined, current.z = current.z, unrefined
            kept = current.result()
            if kept.success:
                res = dataclasses.replace(kept, message=kept.message + f" (its refinement was refused: {res.message})")
            else:
                current.z = refined
            self.evaluations += current.prob.evaluations - before
        return res, current

    def _provisional(self, current):
        """``(result, "within" or "broken")``: the ladder's last size as the ladder left it, a start of
        the joint optimum (:data:`PROVISIONAL_STARTS`): not refined, its limits met on their grid
        (the ladder's own test) and checked between the points only to say whether they hold there;
        a success when its endpoint is met, so that the next interval starts from it."""
        before = current.prob.evaluations
        res = current.result()
        self.evaluations += current.prob.evaluations - before
        provisional = "within" if res.success else "broken"
        if not res.success and res.final_error <= current.tol:  # its endpoint met: a limit broke between the points
            res = dataclasses.replace(res, success=True)
        return res, provisional

    def report(self, current, history, predicted_stop, start_label):
        """The reported optimum: ``current`` refined to ``kkt_tol`` (or, for a start of the joint
        optimum, as the ladder left it: :meth:`_provisional`), with the ladder and its notes."""
        st, iv = self.strategy, self.interval
        if iv.provisional and PROVISIONAL_STARTS:
            res, provisional = self._provisional(current)
        else:
            (res, current), provisional = self._refined(current), None
        i = next(k for k, (n, _) in enumerate(history) if n == res.basis.n)
        history[i] = (history[i][0], res.objective)
        if predicted_stop is not None:
            history[-1] = (history[-1][0], res.objective * (1.0 - predicted_stop))
        last = history[-2:] if len(history) >= 2 else None
        converged = last is not None and abs(last[1][1] - last[0][1]) < st.rtol * abs(last[0][1])
        if converged:
            change = abs(last[1][1] - last[0][1]) / max(abs(last[0][1]), 1e-300)
            how = "predicted by one Newton step" if predicted_stop is not None else "solved"
            note = (f"converged in the basis: {last[1][0]} coefficients ({how}) change the cost by {change:.1e} "
                    f"< {st.rtol:g} (relative)")
        elif iv.sizes is not None:
            note = "one basis size (n_coefficients given)"
        elif self.ladder_stop is not None:  # a size failed (a start's failure is not the ladder's stop)
            note = f"NOT converged in the basis at the largest size tried: {self.ladder_stop}"
        else:  # the ladder's sizes ran out with the cost still changing
            top = history[-1][0]
            note = (f"NOT converged in the basis at the largest size tried ({top} coefficients"
                    + (f"; max_coefficients takes the ladder further, up to {MAX_LADDER_SIZE})" if top < MAX_LADDER_SIZE
                       else ")"))
        ladder = ", ".join(f"{n}: {v:.10g}" for n, v in history)
        msg = (f"{st.name}: {res.message}; sizes (n: cost) {ladder}; {note}; start: {start_label}"
               + (f" ({self.notes[0]})" if self.notes else "") + f"; integral of |u|^2 = {res.energy:.10g}"
               + ("" if provisional is None else "; the joint optimum's start: not refined" + (
                   "" if provisional == "within" else ", its limits broken between the grid's points")))
        grids = dict(limit_grid=int(current.prob.limit_grid),
                     torque_grid=0 if current.prob.grid is None else int(current.prob.grid.size))
        return dataclasses.replace(res, message=msg, evaluations=self.evaluations, sizes=tuple(history),
                                   converged_in_basis=converged, start=start_label, curvature=current.Hc,
                                   provisional=provisional, **grids), self.feasible_pieces


def own_ladder(system, objective: str, joint: bool = False) -> tuple[int, ...] | None:
    """The system's own ladder of basis sizes (its class's ``optimal_sizes``: module docstring,
    Basis size) for an interval whose optimum starts the joint optimum (``joint``, key
    ``"joint"``) or for ``objective`` (``"energy"``, ``"torque"``); ``None`` when it has none."""
    own = getattr(system, "optimal_sizes", None) or {}
    mine = (own.get("joint") if joint else None) or own.get(objective)
    return tuple(mine) if mine else None


class EnergyOptimal(Strategy):
    """The minimum-energy plan of each waypoint interval: :math:`\\min\\int_0^T\\|u\\|^2 dt` over
    the input coefficients, the endpoint as equality constraints, the rate and joint limits as
    inequalities (module docstring: solvers, starts, the ladder of basis sizes).

    Parameters
    ----------
    sizes : sequence of int
        The ladder of basis sizes (default: the system's own for the objective when its class has
        one, ``optimal_sizes``, else :data:`SIZES`); ``n_coefficients`` in :func:`plan` replaces it
        by one size.
    rtol : float
        The ladder stops when the optimal cost changes by less than this, relative (default
        :data:`RTOL`).
    starts : sequence of str, optional
        Any of ``"auto"`` (the plan of the system's ``method="auto"``), ``"family"`` (the family's
        starts, :func:`register_starts`) and ``"deform"`` (path deformation from the minimum-norm
        input); the best optimum at the first size is kept. Default (``None``): the family's starts
        when it has them, else (or when they fail) ``"auto"`` then ``"deform"`` (module docstring).
    torque : TorqueModel, optional
        The joint torques of a motion (needed for ``tau_max``, and by :class:`TorqueOptimal`);
        default: the system's ``torque_model()`` hook, when it has one.
    tau_max : float, sequence or dict, optional
        Torque limits :math:`|\\tau_j| \\le \\bar\\tau_j` per joint (one number for all, one per
        joint, or a dict by the model's ``joint_names``), imposed on a grid of
        :data:`TORQUE_LIMIT_GRID` points with a margin of :data:`TORQUE_MARGIN` and checked at their
        peaks (module docstring); together with the rate and joint limits of :func:`plan` they are the SQP's
        inequalities (module docstring).
    kkt_tol : float
        Target relative KKT residual of the reported optimum (default :data:`KKT_TOL`).
    feasible : Strategy, optional
        The strategy whose plan is the ``"auto"`` start (default: the system's ``method="auto"``);
        :func:`acroplan.plan` passes its ``method`` here when ``objective`` is given with a method
        other than ``"auto"`` (then with ``starts=("auto",)``: the optimum starts from that plan).

    Notes
    -----
    The segment's ``method`` is the strategy's name; its message gives the cost, the basis size,
    the ladder, the relative KKT residual and the start used, and its ``optimality`` the same as data
    (:meth:`diagnostics`). The evaluations of the feasible plan and of every start are charged to it.
    """

    name = "energy-optimal"
    _cost_kind = "energy"

    def __init__(self, sizes: Sequence[int] | None = None, rtol: float = RTOL, starts: Sequence[str] | None = None,
                 torque: TorqueModel | None = None, tau_max=None, kkt_tol: float = KKT_TOL,
                 feasible: Strategy | None = None):
        #: whether the ladder was given (else the system's own for this objective, or :data:`SIZES`)
        self.sizes_given = sizes is not None
        sizes = SIZES if sizes is None else sizes
        try:
            self.sizes = tuple(int(n) for n in sizes)
        except (TypeError, ValueError):
            raise InvalidInputError("sizes", f"must be basis sizes, got {sizes!r}", "give e.g. (6, 10, 14)") from None
        if not self.sizes or any(n < 1 for n in self.sizes) or list(self.sizes) != sorted(set(self.sizes)):
            raise InvalidInputError("sizes", f"must be increasing basis sizes >= 1, got {sizes!r}",
                                    "give e.g. (6, 10, 14)")
        if isinstance(rtol, bool) or not (isinstance(rtol, (int, float)) and 0 < rtol < 1):
            raise InvalidInputError("rtol", f"must be a number in (0, 1), got {rtol!r}", "give e.g. 1e-4")
        self.rtol = float(rtol)
        if starts is not None:
            starts = (starts,) if isinstance(starts, str) else tuple(starts)
            if not starts or any(s not in ("auto", "family", "deform") for s in starts):
                raise InvalidInputError("starts", f"must be some of \"auto\", \"family\", \"deform\", got "
                                        f"{starts!r}", "leave it out (the family's starts, else auto then deform)")
        self.starts = starts
        if torque is not None and not callable(torque):
            raise InvalidInputError("torque", f"must be a callable torque model, got {torque!r}",
                                    "give torque(system, basis, x0, T, c, s) -> tau or (tau, jacobian)")
        self.torque = torque
        tau_vector(tau_max, torque)  # validates what it can without the system
        self.tau_max = tau_max
        if isinstance(kkt_tol, bool) or not (isinstance(kkt_tol, (int, float)) and kkt_tol > 0):
            raise InvalidInputError("kkt_tol", f"must be a positive number, got {kkt_tol!r}", "give e.g. 1e-8")
        self.kkt_tol = float(kkt_tol)
        if feasible is not None and not isinstance(feasible, Strategy):
            raise InvalidInputError("feasible", f"must be a Strategy, got {feasible!r}",
                                    "give the strategy whose plan starts the optimisation, or leave it out")
        if isinstance(feasible, EnergyOptimal):
            raise InvalidInputError("feasible", "is itself an optimal strategy",
                                    "give a strategy that finds a feasible plan (\"deform\", \"flat\", ...)")
        self.feasible = feasible

    def _model(self, system):
        if self.torque is not None:
            return self.torque
        return torque_model_of(system)[0]

    def unsupported(self, system):
        if self._cost_kind == "energy" and self.tau_max is None:
            return None
        what = "torque-optimal plans" if self._cost_kind == "torque" else "tau_max"
        if self.torque is None:
            model, why = torque_model_of(system)
            return None if model is not None else f"{what} need joint torques: {why}"
        check = getattr(self.torque, "unsupported", None)
        return check(system) if callable(check) else None

    def __repr__(self):
        # sizes=None: the system's own ladder or SIZES (ladder)
        return (f"{type(self).__name__}(sizes={self.sizes if self.sizes_given else None}, rtol={self.rtol:g}, "
                f"starts={self.starts}"
                + (f", tau_max={self.tau_max!r}" if self.tau_max is not None else "")
                + (f", feasible={self.feasible!r}" if self.feasible is not None else "") + ")")

    def ladder(self, system, joint: bool = False) -> tuple[int, ...]:
        """The ladder of basis sizes for ``system``: the one given, else the system's own
        (:func:`own_ladder`), else :data:`SIZES`."""
        if self.sizes_given:
            return self.sizes
        return own_ladder(system, self._cost_kind, joint) or self.sizes

    def optimize(self, interval: Interval) -> tuple[OptimalSolve, tuple]:
        """The optimum on ``interval`` with its diagnostics (what :meth:`solve` reports).

        Returns
        -------
        solve : OptimalSolve
            The optimum (``success`` False, with the reason in ``message``, when none was found);
            ``evaluations`` counts every endpoint evaluation, the feasible plan's included.
        feasible : tuple of SegmentResult
            The plan of the system's ``method="auto"`` when it was used (empty when the family's
            starts sufficed).
        """
        model = self._model(interval.system)
        if self._cost_kind == "torque" and model is None:
            return _Search.failure(interval, f"{self.name} needs a torque model for {type(interval.system).__name__}")
        search = _Search(self, interval, model)
        best, failed = search.starts()
        if failed is not None:
            return failed
        current, history, predicted_stop = search.ladder(best)
        return search.report(current, history, predicted_stop, best[1])

    def solve(self, interval: Interval) -> IntervalOutcome:
        res, feasible = self.optimize(interval)
        if not res.success:
            return IntervalOutcome(False, feasible, res.message, res.evaluations)
        seg = make_segment(interval.system, res.basis, interval.x0, interval.x1, interval.T, res.coefficients, t0=0.0,
                           final_error=res.final_error, limits=interval.limits, message=res.message, method=self.name,
                           evaluations=res.evaluations, iterations=res.iterations,
                           optimality=self.diagnostics(res, one_size=interval.sizes is not None))
        return IntervalOutcome(True, (seg,), "", 0, curvature=res.curvature)

    def joint(self, intervals, segments, curvatures=None):
        """The whole plan's optimum through the interior waypoints (:mod:`acroplan.core.chain`) from
        the sequential one: ``intervals`` with only their own input conditions (no continuity from
        the interval before), ``segments`` the sequential optimum (one per interval), ``curvatures``
        the endpoint Hessians each interval's optimum ended with (:attr:`IntervalOutcome.curvature
        <acroplan.core.strategies.IntervalOutcome>`; the first SQP starts from them where they fit
        instead of forward differences, and the first retry on a denser grid, which starts from
        the first optimum, differences afresh there). Returns
        ``(segments, message)``: the new segments when the joint optimum succeeded and costs less,
        else the given ones, and what was done (also in each segment's ``optimality["joint"]``:
        ``kept``, ``message``, and when kept ``cost``, ``sequential_cost``, ``sequential_checked``
        (whether that is a plan's cost: the intervals' provisional optima within their limits between
        the grid's points, :data:`PROVISIONAL_STARTS`), ``evaluations``, ``iterations``)."""
        from .chain import joint_optimum

        if len(intervals) < 2 or len(segments) != len(intervals) or any(not s.optimality for s in segments):
            return tuple(segments), ""
        system = intervals[0].system
        model = self._model(system)
        msgs = []
        start, sequential, curvature = [s.basis_coefficients for s in segments], None, None
        tol = min(iv.tol for iv in intervals)
        given = list(curvatures) if curvatures is not None and len(curvatures) == len(segments) else None
        # a start whose limits break between their grid's points is no plan: its cost, which can be
        # lower than the joint optimum's, is not one to beat (PROVISIONAL_STARTS)
        beat = not any((s.optimality or {}).get("provisional") == "broken" for s in segments)
        # whether the last SQP started from the intervals' Hessians: its retry then differences afresh
        # (from the intervals' Hessians, which it may never have refreshed, the double full-out's four
        # retries took 11, 8, 6, 6 iterations instead of 6, 5, 4, 4; it has needed no retry since its
        # torque limits are also on the intervals' ends, JOINT_TORQUE_ENDS)
        borrowed = False

        def attempt(runs, start, curvature):
            """The intervals' joint optimum from ``start``, each interval's dense check of it, and the
            intervals it fails (``None`` for both when the SQP failed)."""
            nonlocal given, borrowed
            fits = curvature is None and given is not None and all(
                h is not None and np.shape(h) == (r.prob.system.ndx, r.prob.N, r.prob.N) for h, r in zip(given, runs))
            out = joint_optimum(runs, start, tol=tol, kkt_tol=self.kkt_tol, reference_cost=sequential,
                                curvature=curvature, interval_curvature=given if fits else None, beat=beat)
            given, borrowed = None, fits
            if not out.success:
                return out, None, None
            checks = []
            for run, c in zip(runs, out.coefficients):   # each interval's endpoint and limits (the dense check)
                run.z = run.prob.z(c.ravel())
                checks.append(run.result())
            return out, checks, [(k, r.message) for k, r in enumerate(checks) if not r.success]

        def refused():
            """The sequential segments, each saying why the joint optimum was not kept, and why."""
            why = "; ".join(msgs)
            return _not_joint(segments, why), why

        runs = None
        for grid in JOINT_LIMIT_GRIDS:
            # the first grid for every limit; a denser one for the limits the last optimum broke
            # between the points (the rate and joint limits, the torque limits, or both)
            first = runs is None
            grids = (grid, None) if first else _denser_grids(runs, grid)
            if grids is None:
                continue
            ends = JOINT_LIMIT_ENDS if first else 0
            where = (f"{grid} points" if grids[1] is None or grids[1] > grid else
                     f"{grids[0]} points (the torque limits on {grids[1]})") + (
                         f" and {ends} Chebyshev points" if ends else "")
            runs = [_Search(self, iv, model).new_run(seg.basis.n, *grids, limit_ends=ends, torque_ends=JOINT_TORQUE_ENDS)
                    for iv, seg in zip(intervals, segments)]
            if sequential is None:
                sequential = sum(float(r.prob.f(r.prob.z(np.ravel(c)))[0]) for r, c in zip(runs, start))
            out, checks, bad = attempt(runs, start, curvature)
            if checks is None:
                msgs.append(out.message)
                return refused()
            if not bad:
                break
            msgs.append(f"{out.message}; not kept with the limits on {where}: interval {bad[0][0]}: {bad[0][1]}")
            # the denser grid starts from this optimum, which breaks the limits only between the
            # coarser grid's points (the SQP's merit function takes the rows it breaks): some ten
            # times fewer iterations than from the sequential optimum again
            start, curvature = out.coefficients, None if borrowed else out.curvature
        else:
            # the densest grid's optimum breaks a torque limit between its points: the times of the
            # largest excesses join the torque limits' grid, and the SQP goes on from there
            # (exchange rounds; the rate and joint limits are linear and were kept on the grid)
            for _ in range(EXCHANGE_ROUNDS):
                added = sum(run.prob.add_torque_times(run.prob.torque_excess_times(run.prob.z(np.ravel(c))))
                            for run, c in zip(runs, start))
                if not added:
                    break
                out, checks, bad = attempt(runs, start, curvature)
                if checks is None:
                    msgs.append(out.message)
                    return refused()
                if not bad:
                    where = f"{grid} points and the torque limits at {added} more time(s) where they were broken"
                    break
                msgs.append(f"{out.message}; not kept with the torque limits also at {added} time(s): interval "
                            f"{bad[0][0]}: {bad[0][1]}")
                start, curvature = out.coefficients, None if borrowed else out.curvature
            else:
                return refused()
            if bad:
                return refused()
        if msgs:
            out = dataclasses.replace(out, message="; ".join(msgs) + f"; then with the limits on {where}: " + out.message)
        new = []
        kkt_ok = bool(math.isfinite(out.kkt) and out.kkt <= self.kkt_tol)
        for iv, seg, run, c, cost, chk in zip(intervals, segments, runs, out.coefficients, out.costs, checks):
            err = float(chk.final_error)
            opt = dict(seg.optimality)
            opt.pop("provisional", None)
            opt.update(cost=cost, integral_u2=float(energy(seg.basis, iv.T, c)), kkt=out.kkt, kkt_converged=kkt_ok,
                       final_error=err, converged=bool(kkt_ok and (opt.get("one_size") or opt.get("converged_in_basis"))),
                       joint={"kept": True, "cost": out.cost, "sequential_cost": out.start_cost,
                              "sequential_checked": beat,
                              "evaluations": out.evaluations, "iterations": out.iterations, "message": out.message})
            piece = make_segment(iv.system, seg.basis, iv.x0, iv.x1, iv.T, c, t0=seg.t0, final_error=err,
                                 limits=iv.limits, message=f"{seg.message}; then {out.message}", method=self.name,
                                 evaluations=seg.evaluations, iterations=seg.iterations, optimality=opt)
            new.append(dataclasses.replace(piece, index=seg.index, interval=seg.interval, t0=seg.t0, t1=seg.t1))
        return tuple(new), out.message

    def diagnostics(self, res: OptimalSolve, one_size: bool = False) -> dict:
        """The optimality diagnostics of a segment (:attr:`SegmentResult.optimality`): those of
        :meth:`OptimalSolve.to_dict` and ``kkt_tol`` (the target), ``kkt_converged`` (the relative
        KKT residual at most ``kkt_tol``), ``rtol`` (the ladder's), ``one_size`` (``n_coefficients``
        given: no ladder) and ``converged`` (the KKT residual within its target and, unless one
        size was given, the cost converged in the basis)."""
        d = res.to_dict(self._cost_kind)
        kkt_ok = bool(math.isfinite(res.kkt) and res.kkt <= self.kkt_tol)
        d.update(kkt_tol=self.kkt_tol, kkt_converged=kkt_ok, rtol=self.rtol, one_size=bool(one_size),
                 converged=bool(kkt_ok and (one_size or res.converged_in_basis)))
        return d


#: A basis size whose least-squares projection of the feasible plan (several pieces: the spatial
#: family's repeated loops) misses that plan's input by more than this (relative L2) is skipped as
#: the first size of an optimum from the auto start (:meth:`_Search.auto_start`): the projection is
#: no start there. The falling cat's feasible plan (two pieces) is missed by 0.80 at 6 coefficients
#: and 0.20 at 10: at 6 its first stage spent 8 endpoint evaluations (60-90 ms, 13-20% of its least
#: integral of u^2) to no optimum, and 10 started it.
START_PROJECTION_ERROR = 0.5
#: The joint optimum's grids of the limits (points per interval, as
#: :func:`~acroplan.core.limits.linear_limits`; the torque limits' first grid as dense, with at least
#: :data:`TORQUE_LIMIT_GRID` points): the one-interval grid first, then a denser one for the limits
#: the result broke between the first grid's points (the rate and joint limits, the torque limits,
#: or both: :func:`_denser_grids`; the dense check of :meth:`OptimalRun.result`;
#: the bundled forward dive's joint optimum broke a rate limit by 6.0e-3 between 64 points, the
#: double full-out's least integral of u^2 within the strength a torque limit by 150 N m between 65).
JOINT_LIMIT_GRIDS = (64, 256)
#: Chebyshev-Lobatto points the joint optimum's first grid of the rate and joint limits also has
#: (:func:`~acroplan.core.limits.linear_limits`), which crowd towards the intervals' ends, where
#: the inputs of 30 coefficients have their narrowest features: the bundled forward dive's joint
#: optimum on 64 uniform points broke a rate limit by 1.1e-2 rad/s between them and was solved
#: again on 256 (46 + 12 SQP iterations); with the 64 Chebyshev points too it is kept at once (27),
#: 13.5-16.7 s -> 7.8-11.3 s warm over several runs, its least integral of tau^2 1314.234 against
#: 1314.315 (benchmarks/RESULTS.md, "2026-12-06 (fifth session)"). Only the joint optimum's: in the
#: one-interval ladders the same points made the falling cat's least integral of u^2 twice as slow.
JOINT_LIMIT_ENDS = 64
#: Whether the joint optimum's torque limits are also imposed on points crowded at each interval's
#: ends (:func:`~acroplan.core.optimum.end_cluster`: 37 an end, :math:`1/(2n^2)` apart), on every
#: grid: its torques peak in boundary layers there. The bundled double full-out's joint optimum
#: then held its torque limits on the first grid (11 SQP iterations) where it had taken four grids
#: (10, 6, 5, 4): 57 endpoint evaluations against 172, the plan 3.8 s warm against 5.9; the forward
#: dive's 20 iterations against 25 (``benchmarks/RESULTS.md``, eighteenth session, item 13).
JOINT_TORQUE_ENDS = True
#: Exchange rounds of the joint optimum after its densest grid (:meth:`EnergyOptimal.joint`): the
#: times where its torques broke a limit between the grid's points are added to the torque limits'
#: grid, with a time on either side of each (:data:`acroplan.core.optimum.EXCHANGE_SPREAD`), and the
#: SQP goes on. The double full-out's least integral of u^2 within the strength broke one by 0.2 N m
#: between 257 points; one round brought it within then, three later (each optimum's peak moved
#: beside the time added), two with the neighbours (benchmarks/RESULTS.md, twelfth session).
EXCHANGE_ROUNDS = 3
#: Whether an interval whose optimum only starts the joint optimum
#: (:attr:`~acroplan.core.strategies.Interval.provisional`) reports its ladder's last size as the
#: ladder left it: not refined to the KKT target, not solved again on a denser grid where it breaks a
#: limit between its grid's points. The joint optimum refines and checks the whole plan; when it is
#: not kept, :func:`acroplan.plan` plans the intervals again in full (and the joint optimum from
#: them). The bundled dives' refinements were 0.26, 0.83 and 0.85 s of 1.9, 5.1 and 3.8 s warm
#: (back full, forward, double full-out), spent on optima the joint optimum replaces
#: (``benchmarks/RESULTS.md``, nineteenth session).
PROVISIONAL_STARTS = True
#: Whether the ladder's sizes are compared with their limits met on their grids alone
#: (:meth:`_Search.ladder`): each size is a warm start of the next, and only the reported one is
#: checked between its grid's points (and solved again on the denser grid where it breaks a limit
#: there, :meth:`_Search.denser`, by :meth:`_Search.report`). Checking every size (``False``) cost
#: the bundled dives 16 / 25 / 56 dense checks and 319 / 642 / 734 endpoint evaluations (back full,
#: forward, double full-out) against 8 / 18 / 30 and 319 / 606 / 675 when it was introduced, for the
#: same optima to 1e-13 (benchmarks/RESULTS.md, 2026-12-06, sixth session; the counts move with the
#: code's last bits, so compare them only between adjacent versions).
LADDER_ON_GRID = True
#: Points per interval of the grid of one interval's rate, joint and torque limits (the torque
#: limits' at least :data:`TORQUE_LIMIT_GRID`).
LIMIT_GRID = 64
#: The denser grid of one interval's limits (points), when its optimum on :data:`LIMIT_GRID` breaks
#: a limit between them (:meth:`_Search.denser`; the torque limits' ``DENSE_LIMIT_GRID + 1``).
DENSE_LIMIT_GRID = 256


def _denser_grids(runs, grid):
    """``(limit_grid, torque_grid)`` of a retry on ``grid`` points after ``runs`` (their last dense
    check, :attr:`OptimalRun.broken`): the rate and joint limits on ``grid`` points when a run broke
    them between its grid's points, the torque limits on ``grid + 1`` when a run broke those (each
    kind otherwise on its grid as before; both denser when neither kind was found broken); ``None``
    when that grid is no denser. The forward dive's torque optimum broke a rate limit between the
    64 points, its torques 12.6 N m within the strength: its retries on 256 points had evaluated
    the torques on 257 points an interval for nothing (benchmarks/RESULTS.md)."""
    lin = max(r.prob.limit_grid for r in runs)
    tq = max((r.prob.grid_points for r in runs if r.prob.grid is not None), default=None)
    broke_lin = any(r.broken["limits"] for r in runs)
    broke_tq = any(r.broken["torque"] for r in runs)
    if not (broke_lin or broke_tq):
        broke_lin = broke_tq = True
    new_lin = max(lin, grid) if broke_lin else lin
    new_tq = None if tq is None else (max(tq, grid + 1) if broke_tq else tq)
    if new_lin == lin and new_tq == tq:
        return None
    return new_lin, new_tq


def _not_joint(segments, message):
    """``segments`` with ``optimality["joint"]`` saying why the joint optimum was not kept."""
    return tuple(dataclasses.replace(s, optimality={**s.optimality, "joint": {"kept": False, "message": message}})
                 for s in segments)


class TorqueOptimal(EnergyOptimal):
    """The minimum-torque plan of each waypoint interval: :math:`\\min\\int_0^T\\|\\tau\\|^2 dt`,
    with :math:`\\tau` from a torque model (:data:`TorqueModel`), by composite Gauss-Legendre
    quadrature (:data:`TORQUE_QUADRATURE`: 96 nodes), with the Gauss-Newton Hessian of the cost
    in the SQP; otherwise as :class:`EnergyOptimal` (same parameters; ``torque`` defaults to the
    system's ``torque_model()`` hook when it has one).

    Slower than :class:`EnergyOptimal`: the torque model and its Jacobian are evaluated at every
    trial point, the cost's curvature beyond Gauss-Newton is learnt by the quasi-Newton updates,
    and the optimum's torque (which involves :math:`\\ddot\\varphi`) needs more coefficients.
    Measured on 20 random acrobot segments (``python benchmarks/optimal.py --torque 20``): median
    10.9 ms against 2.6 ms (3.5 times slower per problem); the optimum's :math:`\\int\\tau^2` is a
    median 0.37 of the energy-optimal plan's and its peak torque 0.57, for 1.11 times its
    :math:`\\int u^2`.
    """

    name = "torque-optimal"
    _cost_kind = "torque"


register_strategy(EnergyOptimal())
register_strategy(TorqueOptimal())

#: The costs a plan can minimise, by name (``objective=`` of a front door).
OBJECTIVES = {"energy": EnergyOptimal, "torque": TorqueOptimal}


def objective_strategy(objective: str, **kwargs) -> EnergyOptimal:
    """The optimal strategy for ``objective`` (``"energy"``: :class:`EnergyOptimal`, ``"torque"``:
    :class:`TorqueOptimal`), built with ``kwargs`` (``tau_max``, ``torque``, ``sizes``, ``rtol``,
    ``starts``, ``kkt_tol``, ``feasible``).

    Raises
    ------
    InvalidInputError
        ``objective`` is not one of :data:`OBJECTIVES`.
    """
    if not isinstance(objective, str) or objective not in OBJECTIVES:
        raise InvalidInputError("objective", f"must be one of {sorted(OBJECTIVES)}, got {objective!r}",
                                "give \"energy\" (integral of |u|^2) or \"torque\" (integral of |tau|^2)")
    return OBJECTIVES[objective](**kwargs)
