"""Optimal plans: the minimum-energy and the minimum-torque input on each waypoint interval.

The front doors reach them by ``objective="energy"`` or ``"torque"`` (and ``tau_max=``) of
:func:`acroplan.plan` and :func:`acroplan.plan_many` (:func:`objective_strategy`); they are also
registered strategies, ``method="energy-optimal"`` and ``"torque-optimal"``. Each segment of an
optimal plan carries its diagnostics (:meth:`EnergyOptimal.diagnostics`) as
:attr:`SegmentResult.optimality <acroplan.core.result.SegmentResult.optimality>`.

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
* **No inequality (the common case): an SQP of our own.** The model Hessian is the cost's (exact
  for the energy, :math:`2T(I_m\\otimes G)`; Gauss-Newton for the torque cost) plus the
  constraints' curvature :math:`\\sum_i \\lambda_i \\nabla^2 h_i`, whose Hessians are taken by forward
  differences of the endpoint Jacobian at the first basis size (``len(z)`` evaluations; again, at
  most :data:`MAX_REFRESH` times, after a step the model predicted poorly), carried over padded
  with zeros to the next sizes, and corrected by symmetric rank-one updates from the secant of the
  Lagrangian's gradient. A step solves the KKT system
  :math:`Wp + A^\\top\\lambda = -\\nabla f,\\ Ap = -h`; when :math:`W` is not positive definite
  on :math:`\\ker A` the reduced Hessian's eigenvalues are replaced by their magnitudes (at least
  1e-6 of the largest). Steps are accepted on the :math:`\\ell_1` merit function
  :math:`f + \\rho\\|h\\|_1` (:math:`\\rho = 2\\|\\lambda\\|_\\infty`), with a second-order
  correction back onto the constraints at every trial (the Maratos effect), and a cap on the step
  length in the cost's metric that follows the steps taken (so no trial input is wild: the
  integrator's cost grows with the input). From a warm start it takes two to five iterations
  per basis size (measured on random acrobot segments).
* **With rate, joint or torque limits: scipy's SLSQP** on the same problem, in coordinates where the
  cost's model Hessian is the identity (SLSQP's own first guess), then minimum-norm Newton steps
  on the endpoint as :func:`~acroplan.core.limits.solve_with_limits`; success needs the limits to
  hold exactly (:func:`~acroplan.core.limits.violation`) and the torque limits on 1025 points.

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
prediction and the size is solved. Under limits (SLSQP) every size is solved. With
``n_coefficients`` given, that one size is used.

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
  the basis when it has several pieces) and, as the second start, **path deformation from the
  minimum-norm input** (the text's method, :func:`~acroplan.core.continuation.solve_segment`, at
  most :data:`DEFORM_BUDGET` evaluations), optimised when distinct and promising (cost below
  :data:`PROMISING` = 8 times).

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
import functools
import math
from typing import Callable, Sequence

import numpy as np
from scipy.optimize import minimize, nnls

from . import backend
from .basis import InputBasis
from .continuation import solve_segment
from .errors import InvalidInputError
from .limits import COMPLIANCE_TOL, linear_limits, violation
from .linalg import null_space
from .progress import note as progress_note
from .strategies import AUTO_DEFAULT, Interval, IntervalOutcome, Strategy, make_segment, register_strategy
from .system import ControlAffineSystem, torque_model_of

__all__ = ["EnergyOptimal", "TorqueOptimal", "OptimalSolve", "optimize_segment", "energy", "TorqueModel",
           "OBJECTIVES", "objective_strategy", "FAMILY_STARTS", "register_starts", "family_starts", "SIZES", "RTOL",
           "KKT_TOL", "STAGE_KKT_TOL", "FIRST_KKT_TOL", "DEFORM_BUDGET", "DEFORM_TOL", "DISTINCT", "PROMISING",
           "FAMILY_PROMISING", "MAX_REFRESH", "TORQUE_QUADRATURE", "TORQUE_LIMIT_GRID", "TORQUE_MARGIN"]

#: Basis sizes of the ladder (:class:`EnergyOptimal`), smallest first.
SIZES = (6, 10, 14, 20, 26, 30)
#: The ladder stops when the optimum's cost changes by less than this, relative, between sizes.
RTOL = 1e-4
#: Relative KKT residual of the reported optimum (module docstring).
KKT_TOL = 1e-8
#: Relative KKT residual at the sizes of the ladder before the last; a size whose change looks
#: below ``rtol`` is refined to ``kkt_tol`` before the ladder stops on it (refining lowers its cost,
#: so the change can only grow), and the predictions at the next size include what is left.
STAGE_KKT_TOL = 1e-3
#: Relative KKT residual at the first size, where the starts are compared (an optimum not fully
#: converged there can only make the ladder's first change look larger, never stop it early).
FIRST_KKT_TOL = 1e-3
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
#: Composite Gauss-Legendre rule for the torque cost: (panels, nodes per panel) on [0, 1].
TORQUE_QUADRATURE = (4, 24)
#: Points of the uniform grid on which torque limits are imposed (the check uses 1025).
TORQUE_LIMIT_GRID = 65
#: Relative margin of the torque limits on the grid (as the rate and joint limits' 2e-3).
TORQUE_MARGIN = 2e-3
#: New forward-difference constraint Hessians after a step the model predicted poorly (line
#: search backtracked), at most this many times per solve.
MAX_REFRESH = 3

#: ``torque(system, basis, x0, T, c, s) -> tau`` or ``(tau, jacobian)``: the joint torques of the
#: motion that input coefficients ``c`` (shape ``(m, basis.n)``) produce from ``x0`` in time ``T``,
#: at normalised times ``s`` (shape ``(K,)``): ``tau`` of shape ``(p, K)`` for ``p`` joints, and
#: optionally ``jacobian`` = d tau / d c of shape ``(p, K, m * basis.n)`` (flattened ``c``; by
#: forward differences when it is not given). An object may also have ``joint_names`` (length
#: ``p``) and ``unsupported(system) -> str | None``.
TorqueModel = Callable


@functools.lru_cache(maxsize=128)
def _gram(basis: InputBasis) -> np.ndarray:
    G = basis.gram()
    G.setflags(write=False)
    return G


@functools.lru_cache(maxsize=16)
def _gauss(panels: int, per: int):
    """Composite Gauss-Legendre nodes and weights on [0, 1] (read-only)."""
    xg, wg = np.polynomial.legendre.leggauss(per)
    s = ((np.arange(panels)[:, None] + (xg[None, :] + 1.0) / 2.0) / panels).ravel()
    w = np.tile(wg / (2.0 * panels), panels)
    s.setflags(write=False)
    w.setflags(write=False)
    return s, w


def energy(basis: InputBasis, T: float, c) -> float:
    """:math:`\\int_0^T \\|u\\|^2 dt = T\\,\\sum_j c_j^\\top G c_j`, exact (basis Gram matrix).

    Parameters
    ----------
    basis : InputBasis
    T : float
        Segment duration.
    c : array_like, shape (m, basis.n) or (basis.n,)

    Returns
    -------
    float
    """
    c = np.atleast_2d(np.asarray(c, dtype=float))
    return float(T * np.einsum("ji,ik,jk->", c, _gram(basis), c))


# ------------------------------------------------------------------------------------ costs
class _EnergyCost:
    """:math:`f(c) = T c^\\top (I_m \\otimes G) c`: value, gradient and (exact, constant) Hessian."""

    label = "integral of |u|^2"

    def __init__(self, system, basis, x0, T):
        m = system.n_inputs
        self.H = 2.0 * T * (_gram(basis) if m == 1 else np.kron(np.eye(m), _gram(basis)))

    def __call__(self, c):
        g = self.H @ c
        return 0.5 * float(c @ g), g, self.H


def _call_torque(model, system, basis, x0, T, c, s):
    """The torque model at flat ``c``: ``(tau (p, K), jacobian (p, K, N))``."""
    m, n = system.n_inputs, basis.n
    c = np.asarray(c, dtype=float).reshape(-1)
    out = model(system, basis, x0, T, c.reshape(m, n), s)
    if isinstance(out, tuple):
        tau = np.atleast_2d(np.asarray(out[0], dtype=float))
        return tau, np.asarray(out[1], dtype=float).reshape(tau.shape + (m * n,))
    tau = np.atleast_2d(np.asarray(out, dtype=float))
    jac = np.empty(tau.shape + (m * n,))
    for k in range(m * n):
        eps = 1e-7 * max(1.0, abs(c[k]))
        ck = c.copy()
        ck[k] += eps
        jac[:, :, k] = (np.atleast_2d(model(system, basis, x0, T, ck.reshape(m, n), s)) - tau) / eps
    return tau, jac


class _TorqueCost:
    """:math:`f(c) = \\int_0^T \\|\\tau\\|^2 dt` by composite Gauss-Legendre, its gradient and its
    Gauss-Newton Hessian :math:`2\\sum_k T w_k\\, \\partial\\tau_k^\\top \\partial\\tau_k`."""

    label = "integral of |tau|^2"

    def __init__(self, model, system, basis, x0, T):
        self.model, self.system, self.basis, self.x0, self.T = model, system, basis, x0, T
        s, w = _gauss(*TORQUE_QUADRATURE)
        self.s, self.sw = s, np.sqrt(T * w)

    def __call__(self, c):
        tau, jac = _call_torque(self.model, self.system, self.basis, self.x0, self.T, c, self.s)
        r = (tau * self.sw).ravel()
        R = (jac * self.sw[None, :, None]).reshape(r.size, -1)
        return float(r @ r), 2.0 * R.T @ r, 2.0 * R.T @ R


def _cost_for(cost, system, basis, x0, T):
    if isinstance(cost, str):
        return _EnergyCost(system, basis, x0, T)
    return _TorqueCost(cost, system, basis, x0, T)


# ------------------------------------------------------------------------------------ result
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
        ``"sqp"`` or ``"slsqp"``.
    sizes : tuple of (int, float)
        The ladder: (basis size, optimal cost) at each size solved; when the ladder stopped on a
        prediction, the last entry is the next size with the cost one Newton step predicts there
        (one entry for :func:`optimize_segment`).
    converged_in_basis : bool
        Whether the cost changed (or is predicted to change) by less than ``rtol`` at the last
        step of the ladder.
    start : str
        The start the optimum came from (``"auto"``, ``"deform"`` or ``"given"``).
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

    def to_dict(self, objective: str = "energy") -> dict:
        """The diagnostics as plain JSON types (non-finite numbers as ``None``): ``objective``,
        ``cost``, ``integral_u2``, ``kkt``, ``multipliers``, ``final_error``, ``basis_size``,
        ``ladder`` (``[[n, cost], ...]``), ``converged_in_basis``, ``start``, ``solver``,
        ``evaluations``, ``iterations``."""
        num = (lambda v: float(v) if v is not None and math.isfinite(float(v)) else None)  # noqa: E731
        return {"objective": objective, "cost": num(self.objective), "integral_u2": num(self.energy),
                "kkt": num(self.kkt), "multipliers": [num(v) for v in np.ravel(self.multipliers)],
                "final_error": num(self.final_error), "basis_size": int(self.basis.n),
                "ladder": [[int(n), num(v)] for n, v in self.sizes],
                "converged_in_basis": bool(self.converged_in_basis), "start": self.start, "solver": self.solver,
                "evaluations": int(self.evaluations), "iterations": int(self.iterations),
                "success": bool(self.success)}


# ------------------------------------------------------------------------------------ one size
class _OutOfEvaluations(RuntimeError):
    pass


def _solve_small(M, b):
    """``M x = b`` for the small symmetric systems of the multipliers (Cramer's rule up to 2 x 2)."""
    q = M.shape[0]
    if q == 1:
        return b / M[0, 0]
    if q == 2:
        det = M[0, 0] * M[1, 1] - M[0, 1] * M[1, 0]
        if det == 0.0 or not math.isfinite(det):
            raise np.linalg.LinAlgError("singular")
        return np.array([(M[1, 1] * b[0] - M[0, 1] * b[1]) / det, (M[0, 0] * b[1] - M[1, 0] * b[0]) / det])
    return np.linalg.solve(M, b)


def _kkt(g, A, C=None):
    """Least-squares multipliers and the relative KKT residual (module docstring).

    ``g``: cost gradient (N,); ``A``: equality Jacobian (q, N); ``C``: active inequality rows
    (r, N) of constraints ``C z <= ...`` (multipliers >= 0, by non-negative least squares)."""
    gn = math.sqrt(float(g @ g))
    if C is None or C.shape[0] == 0:
        try:
            lam = -_solve_small(A @ A.T, A @ g)
        except np.linalg.LinAlgError:
            lam = -np.linalg.lstsq(A.T, g, rcond=None)[0]
        res = g + A.T @ lam
        return lam, (math.sqrt(float(res @ res)) / gn if gn > 0 else 0.0)
    Q, _ = np.linalg.qr(A.T, mode="complete")
    P = Q[:, A.shape[0]:]  # orthonormal basis of the null space of A: eliminates the free multipliers
    mu, _ = nnls(P.T @ C.T, -P.T @ g)
    lam = -np.linalg.lstsq(A.T, g + C.T @ mu, rcond=None)[0]
    res = g + A.T @ lam + C.T @ mu
    return lam, (math.sqrt(float(res @ res)) / gn if gn > 0 else 0.0)


class _Problem:
    """One interval at one basis size, in reduced coordinates ``z`` (``c = c_p + Z z``)."""

    def __init__(self, system, basis, x0, x1, T, cost, B, d, max_evaluations, limits=None, torque_model=None,
                 tau_max=None):
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
        self.lin = None
        if self.limits is not None:
            A_c, b_c = linear_limits(system, basis, self.x0, T, self.limits, margin=2e-3)
            if A_c.shape[0]:
                self.lin = (self.zmat(A_c), b_c - A_c @ self.c_p)
        self.tmax = None if tau_max is None else np.atleast_1d(np.asarray(tau_max, dtype=float))
        self.grid = None if tau_max is None else np.linspace(0.0, 1.0, TORQUE_LIMIT_GRID)

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

    # functions
    def f(self, z):
        """Cost, gradient and model Hessian in ``z``."""
        if self.free:
            return self.cost(z)
        f, g, H = self.cost(self.c(z))
        if isinstance(self.cost, _EnergyCost):  # a constant Hessian: reduced once
            if self._Hz is None:
                self._Hz = self.Z.T @ H @ self.Z
            return f, self.Z.T @ g, self._Hz
        return f, self.Z.T @ g, self.Z.T @ H @ self.Z

    def endpoint(self, c):
        """``(y, A_c)``: the endpoint and its tangent Jacobian in flattened ``c`` (counted)."""
        if self.evaluations >= self.max_evaluations:
            raise _OutOfEvaluations()
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

    def torque_rows(self, z):
        """Torque-limit inequalities ``g(z) >= 0`` on the grid, and their Jacobian in ``z``."""
        tau, J = _call_torque(self.torque_model, self.system, self.basis, self.x0, self.T, self.c(z), self.grid)
        top = self.tmax[:, None] * (1.0 - TORQUE_MARGIN)
        J = self.zmat(J.reshape(-1, self.N))
        return np.concatenate([(top - tau).ravel(), (top + tau).ravel()]), np.vstack([-J, J])

    def curvature(self, c, Ac):
        """Constraint Hessians in ``c`` coordinates, shape (q, N, N), by forward differences of the
        endpoint Jacobian along every coordinate direction (N evaluations), symmetrised."""
        q, N = Ac.shape[0], self.N
        M = np.empty((q, N, N))
        for k in range(N):
            eps = 1e-7 * max(1.0, abs(c[k]))
            ck = c.copy()
            ck[k] += eps
            M[:, :, k] = (self.endpoint(ck)[1] - Ac) / eps
        return 0.5 * (M + M.transpose(0, 2, 1))


def _step(W, g, h, A, H, convex_only=False):
    """The SQP step: the KKT system :math:`W p + A^\\top\\lambda = -g`, :math:`A p = -h`, with
    :math:`W` replaced, when it is not positive definite on :math:`\\ker A`, by the reduced
    Hessian with its eigenvalues by their magnitude (at least 1e-6 of the largest). Returns
    ``(p, lambda)`` or ``None`` when ``A`` is rank-deficient."""
    N, q = W.shape[0], A.shape[0]
    AtA = A.T @ A
    sigma = 1e2 * W.trace() / max(AtA.trace(), 1e-300) + 1.0
    try:
        np.linalg.cholesky(W + sigma * AtA)  # positive definite on ker A (for this sigma): Newton's step
        K = np.empty((N + q, N + q))
        K[:N, :N] = W
        K[:N, N:] = A.T
        K[N:, :N] = A
        K[N:, N:] = 0.0
        rhs = np.empty(N + q)
        rhs[:N] = -g
        rhs[N:] = -h
        sol = np.linalg.solve(K, rhs)
        return sol[:N], sol[N:]
    except np.linalg.LinAlgError:
        if convex_only:
            return None
    if q >= N:  # no freedom left on the constraints: the step is theirs (least squares if over-determined)
        p = -np.linalg.lstsq(A, h, rcond=None)[0]
        return p, -np.linalg.lstsq(A.T, W @ p + g, rcond=None)[0]
    Q, R = np.linalg.qr(A.T, mode="complete")
    Y, Zr, R = Q[:, :q], Q[:, q:], R[:q, :q]
    dR = np.abs(np.diag(R))
    if dR.min() <= 1e-12 * max(1.0, dR.max()):
        return None
    pY = -np.linalg.solve(R.T, h)
    Wr = Zr.T @ W @ Zr
    e, V = np.linalg.eigh(0.5 * (Wr + Wr.T))
    e = np.maximum(np.abs(e), 1e-6 * max(float(np.abs(e).max()), 1e-300))
    p = Y @ pY + Zr @ (V @ ((V.T @ (-Zr.T @ (g + W @ (Y @ pY)))) / e))
    return p, -np.linalg.solve(R, Y.T @ (W @ p + g))


def _sqp(prob: _Problem, z, Hz, *, tol, kkt_tol, max_iter=40, refresh=None, max_refresh=None):
    """The equality-constrained SQP (module docstring) from ``z`` with constraint Hessians ``Hz``
    (q, Nz, Nz); ``refresh(z)`` gives new ones (forward differences) after a step the model
    predicted poorly. Returns ``(z, info)``."""
    f, g, H = prob.f(z)
    h, A, _, _ = prob.h(z)
    lam, kkt = _kkt(g, A)
    N, q = z.size, A.shape[0]
    Hz2 = Hz.reshape(q, N * N)
    D = np.zeros((N, N))
    rho = 0.0
    radius = 2.0 * max(math.sqrt(max(float(z @ H @ z), 0.0)), 1e-3)
    its, why, refreshed = 0, "", 0
    max_refresh = MAX_REFRESH if max_refresh is None else max_refresh
    while its < max_iter:
        if kkt <= kkt_tol and max(map(abs, h.tolist())) <= tol:
            break
        its += 1
        W = (lam @ Hz2).reshape(N, N)
        W += H
        W += D
        out = _step(W, g, h, A, H)
        if out is None:
            why = "the endpoint Jacobian is singular"
            break
        p, lam_qp = out
        rho = max(rho, 2.0 * max(map(abs, lam_qp.tolist())) + 1e-12)
        h1 = sum(map(abs, h.tolist()))
        merit0 = f + rho * h1
        slope = float(g @ p) - rho * h1
        if slope > -1e-15 * (abs(f) + rho * h1):  # nothing left to gain at this precision
            break
        step = math.sqrt(max(float(p @ H @ p), 0.0))
        alpha = min(1.0, radius / step) if step > 0 else 1.0
        accepted = None
        for trial in range(14):
            zt = z + alpha * p
            try:
                ht, At, _, _ = prob.h(zt)
            except backend.IntegrationError:
                alpha *= 0.25
                continue
            ft = prob.f(zt)
            if ft[0] + rho * sum(map(abs, ht.tolist())) <= merit0 + 1e-4 * alpha * slope:
                accepted = (zt, ht, At, ft)
                break
            try:  # second-order correction: back onto the constraints (the Maratos effect)
                zc = zt - At.T @ _solve_small(At @ At.T, ht)
                hc, Ac, _, _ = prob.h(zc)
                fc = prob.f(zc)
                if fc[0] + rho * sum(map(abs, hc.tolist())) <= merit0 + 1e-4 * alpha * slope:
                    accepted = (zc, hc, Ac, fc)
                    break
            except (backend.IntegrationError, np.linalg.LinAlgError):
                pass
            alpha *= 0.5
        if accepted is None:
            why = "no step decreased the merit function"
            break
        zt, ht, At, (ft, gt, Ht) = accepted
        s = zt - z
        # the cap on the step (in the cost's metric) follows the steps taken
        radius = max(radius, 2.0 * alpha * step) if trial == 0 else max(alpha * step, 0.25 * radius, 1e-12)
        if refresh is not None and trial > 0 and refreshed < max_refresh:  # a poor model: new Hessians
            refreshed += 1
            Hz2 = refresh(zt).reshape(q, N * N)
            D[:] = 0.0
        else:  # symmetric rank-one correction of the modelled curvature, from the Lagrangian's secant
            r = (gt - g) + (At - A).T @ lam_qp - (Ht + (lam_qp @ Hz2).reshape(N, N) + D) @ s
            den = float(r @ s)
            if abs(den) > 1e-8 * math.sqrt(float(r @ r) * float(s @ s)) > 0:
                D += np.outer(r, r) / den
        z, f, g, H, h, A = zt, ft, gt, Ht, ht, At
        lam, kkt = _kkt(g, A)
        if float(s @ s) <= 1e-30 * (1.0 + float(z @ z)):
            break
    return z, dict(lam=lam, kkt=kkt, its=its, why=why)


def _polish(prob: _Problem, z, tol):
    """Minimum-norm Newton steps on the endpoint alone (as :func:`solve_with_limits`)."""
    h, A, _, _ = prob.h(z)
    for _ in range(6):
        if float(np.abs(h).max()) <= tol * 1e-2:
            break
        zt = z - np.linalg.lstsq(A, h, rcond=None)[0]
        try:
            ht, At, _, _ = prob.h(zt)
        except backend.IntegrationError:
            break
        if np.linalg.norm(ht) >= np.linalg.norm(h):
            break
        z, h, A = zt, ht, At
    return z


def _slsqp(prob: _Problem, z0, max_iter=300):
    """SLSQP with the linear and torque inequalities, in coordinates ``w = L^T z`` where the cost's
    model Hessian at the start is the identity (``L L^T``). Returns ``(z, iterations, message)``."""
    f0, _, H0 = prob.f(z0)
    ridge = 1e-12 * max(float(np.trace(H0)) / H0.shape[0], 1e-300)
    L = np.linalg.cholesky(H0 + ridge * np.eye(H0.shape[0]))
    Li = np.linalg.inv(L.T)  # z = Li w
    scale = 1.0 + float(np.max(np.abs(prob.x1)))
    bad = np.full(prob.system.ndx, 1e6)

    def eq(w):
        try:
            return prob.h(Li @ w)[0] / scale
        except backend.IntegrationError:
            return bad

    def eq_jac(w):
        try:
            return prob.h(Li @ w)[1] @ Li / scale
        except backend.IntegrationError:
            return np.zeros((prob.system.ndx, w.size))

    cons = [{"type": "eq", "fun": eq, "jac": eq_jac}]
    if prob.lin is not None:
        Az, bz = prob.lin
        AL = Az @ Li
        cons.append({"type": "ineq", "fun": lambda w: bz - AL @ w, "jac": lambda w: -AL})
    if prob.tmax is not None:
        cons.append({"type": "ineq", "fun": lambda w: prob.torque_rows(Li @ w)[0],
                     "jac": lambda w: prob.torque_rows(Li @ w)[1] @ Li})
    unit = 1.0 + abs(f0)

    def obj(w):
        f, g, _ = prob.f(Li @ w)
        return f / unit, (Li.T @ g) / unit

    res = minimize(obj, L.T @ z0, jac=True, constraints=cons, method="SLSQP",
                   options={"maxiter": max_iter, "ftol": 1e-15})
    return Li @ res.x, int(res.nit), str(res.message)


class _Run:
    """The optimisation at one basis size: solve from a start, refine, report."""

    def __init__(self, system, basis, x0, x1, T, cost, torque_model, limits, tau_max, B, d, tol, max_evaluations):
        self.fn = _cost_for(cost, system, basis, x0, T)
        self.prob = _Problem(system, basis, x0, x1, T, self.fn, B, d, max_evaluations, limits, torque_model, tau_max)
        self.tol = tol
        self.solver = "sqp" if self.prob.lin is None and self.prob.tmax is None else "slsqp"
        self.z = None
        self.Hc = None  # constraint Hessians in c coordinates (the SQP's)
        self.its, self.why, self.failed = 0, "", ""

    def solve(self, c0, *, curvature=None, kkt_tol=KKT_TOL, polish=True):
        prob = self.prob
        z = prob.z(c0)
        try:
            if self.solver == "sqp":
                _, _, _, Ac = prob.h(z)
                self.Hc = prob.curvature(prob.c(z), Ac) if curvature is None else curvature
                Hz = np.stack([prob.zhess(M) for M in self.Hc])

                def refresh(zn):
                    self.Hc = prob.curvature(prob.c(zn), prob.h(zn)[3])
                    return np.stack([prob.zhess(M) for M in self.Hc])

                z, info = _sqp(prob, z, Hz, tol=self.tol, kkt_tol=kkt_tol, refresh=refresh)
                self.its += info["its"]
                self.why = info["why"]
            else:
                z, its, msg = _slsqp(prob, z)
                self.its += its
                self.why = "" if msg.startswith("Optimization terminated successfully") else msg
            self.z = _polish(prob, z, self.tol) if polish or self.solver != "sqp" else z
        except _OutOfEvaluations:
            self.z, self.failed = z, f"the evaluation budget ({prob.max_evaluations}) was spent"
        except backend.IntegrationError as e:
            self.z, self.failed = z, f"the integrator failed ({e})"
        return self

    def refine(self, kkt_tol):
        """More SQP iterations at this size from the current optimum, with its curvature."""
        if self.solver != "sqp" or self.failed or self.Hc is None:
            return self
        prob = self.prob
        try:
            Hz = np.stack([prob.zhess(M) for M in self.Hc])
            z, info = _sqp(prob, self.z, Hz, tol=self.tol, kkt_tol=kkt_tol)
            self.its += info["its"]
            self.why = info["why"]
            self.z = _polish(prob, z, self.tol)
        except (_OutOfEvaluations, backend.IntegrationError):
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
        except (_OutOfEvaluations, backend.IntegrationError):
            return math.inf
        lam, _ = _kkt(g, A)
        W = H.copy()
        if curvature is not None:
            W += np.tensordot(lam, np.stack([prob.zhess(M) for M in curvature]), axes=1)
        out = _step(W, g, h, A, H, convex_only=True)
        if out is None or f <= 0:
            return math.inf
        p, _ = out
        return max(-(float(g @ p) + 0.5 * float(p @ W @ p)) / f, 0.0)

    def brief(self):
        """``(success, cost)`` of the current point, cheaply (no KKT residual, no message); the full
        :meth:`result` when it failed."""
        if self.failed or self.solver != "sqp":
            r = self.result()
            return r.success, r.objective, r
        try:
            h, _, y, _ = self.prob.h(self.z)
        except (_OutOfEvaluations, backend.IntegrationError):
            r = self.result()
            return r.success, r.objective, r
        if self.prob.system.error(y, self.prob.x1) > self.tol:
            r = self.result()
            return False, r.objective, r
        return True, self.prob.f(self.z)[0], None

    def result(self, **extra) -> OptimalSolve:
        prob, z = self.prob, self.z
        system, basis = prob.system, prob.basis
        m, n = prob.m, prob.n
        c = prob.c(z)
        nan = float("nan")
        if self.failed:
            return OptimalSolve(False, self.failed, c.reshape(m, n), basis, nan, nan, nan, np.zeros(system.ndx),
                                float("inf"), prob.evaluations, self.its, self.solver, **extra)
        try:
            h, A, y, _ = prob.h(z)
        except (_OutOfEvaluations, backend.IntegrationError) as e:
            return OptimalSolve(False, f"the endpoint could not be evaluated ({e})", c.reshape(m, n), basis, nan, nan,
                                nan, np.zeros(system.ndx), float("inf"), prob.evaluations, self.its, self.solver,
                                **extra)
        f, g, _ = prob.f(z)
        C = []  # active inequalities, for the KKT residual
        if prob.lin is not None:
            Az, bz = prob.lin
            C.append(Az[bz - Az @ z <= 1e-7 * (1.0 + np.abs(bz))])
        if prob.tmax is not None:
            vals, J = prob.torque_rows(z)
            top = np.tile(np.repeat(prob.tmax, TORQUE_LIMIT_GRID), 2)
            C.append(-J[vals <= 1e-7 * (1.0 + np.where(np.isfinite(top), top, 0.0))])
        C = np.vstack(C) if C else None
        lam, kkt = _kkt(g, A, C)
        err = system.error(y, prob.x1)
        ok = err <= self.tol
        msg = (f"{self.fn.label} = {f:.10g} with {n} coefficient(s) per input ({self.solver}, {self.its} "
               f"iteration(s), {prob.evaluations} evaluations): endpoint error {err:.2e}, relative KKT residual "
               f"{kkt:.1e}")
        if prob.limits is not None:
            v = violation(system, basis, prob.x0, prob.T, c, prob.limits)
            ok = ok and v["u"] <= COMPLIANCE_TOL and v["state"] <= COMPLIANCE_TOL
            msg += f", limit violation {max(v['u'], v['state']):.1e}"
        if prob.tmax is not None:
            tau, _ = _call_torque(prob.torque_model, system, basis, prob.x0, prob.T, c, np.linspace(0.0, 1.0, 1025))
            excess = float(np.max(np.abs(tau) - prob.tmax[:, None]))
            ok = ok and excess <= COMPLIANCE_TOL * max(1.0, float(np.max(prob.tmax[np.isfinite(prob.tmax)],
                                                                          initial=1.0)))
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
        Target relative KKT residual of the SQP (no inequality).
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
    run = _Run(system, basis, x0, x1, T, cost, model, limits, tau_max, B, d, tol, max_evaluations)
    out = run.solve(np.asarray(start, dtype=float).reshape(-1), kkt_tol=kkt_tol).result()
    return dataclasses.replace(out, sizes=((basis.n, out.objective),))


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


def _project(pieces, interval: Interval, basis: InputBasis):
    """Coefficients in ``basis`` on the whole interval closest (least squares on 256 Gauss nodes)
    to the input of ``pieces``, under the interval's input conditions. A single piece in the same
    basis family is taken as it is (padded or truncated)."""
    if len(pieces) == 1 and pieces[0].basis is not None and type(pieces[0].basis) is type(basis):
        return _resize(pieces[0].basis_coefficients, basis.n)
    T = interval.T
    s, w = _gauss(8, 32)
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
    return out


def _distance(basis, T, c, ref) -> float:
    """:math:`\\|u_c - u_{ref}\\|_{L^2} / \\|u_{ref}\\|_{L^2}` on the segment (exact)."""
    c, ref = np.atleast_2d(c), np.atleast_2d(ref)
    return math.sqrt(energy(basis, T, c - ref) / max(energy(basis, T, ref), 1e-300))


def tau_vector(tau_max, model):
    """``tau_max`` as an array, one bound per joint of ``model`` (``inf``: unlimited); validated."""
    if tau_max is None:
        return None
    names = getattr(model, "joint_names", None)
    fix = "give each joint's largest torque, e.g. 50.0 (one number for all joints, one per joint, or a dict)"
    if isinstance(tau_max, dict):
        unknown = sorted(set(tau_max) - set(names)) if names is not None else []
        if unknown:
            raise InvalidInputError(f"tau_max.{unknown[0]}", "is not a joint of the torque model",
                                    f"joints are {list(names)}")
        if names is None and model is not None:
            raise InvalidInputError("tau_max", "a dict needs a torque model with joint_names", fix)
        raw = [tau_max.get(nm, math.inf) for nm in names] if names is not None else list(tau_max.values())
    else:
        raw = list(np.atleast_1d(tau_max)) if not isinstance(tau_max, (str, bytes)) else [tau_max]
    vals = []
    for v in raw:
        if isinstance(v, (bool, str, bytes)):
            raise InvalidInputError("tau_max", f"must be positive numbers, got {tau_max!r}", fix)
        try:
            v = float(v)
        except (TypeError, ValueError):
            raise InvalidInputError("tau_max", f"must be positive numbers, got {tau_max!r}", fix) from None
        if math.isnan(v) or v <= 0:
            raise InvalidInputError("tau_max", f"must be positive numbers, got {tau_max!r}", fix)
        vals.append(v)
    if names is not None and not isinstance(tau_max, dict):
        if len(vals) == 1:
            vals = vals * len(names)
        elif len(vals) != len(names):
            raise InvalidInputError("tau_max", f"has {len(vals)} value(s) for {len(names)} joint(s)",
                                    f"give one per joint {list(names)}, or one for all")
    return np.array(vals, dtype=float)


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


class EnergyOptimal(Strategy):
    """The minimum-energy plan of each waypoint interval: :math:`\\min\\int_0^T\\|u\\|^2 dt` over
    the input coefficients, the endpoint as equality constraints, the rate and joint limits as
    inequalities (module docstring: solvers, starts, the ladder of basis sizes).

    Parameters
    ----------
    sizes : sequence of int
        The ladder of basis sizes (default :data:`SIZES`); ``n_coefficients`` in :func:`plan`
        replaces it by one size.
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
        :data:`TORQUE_LIMIT_GRID` points with a margin of :data:`TORQUE_MARGIN` and checked on 1025
        points; together with the rate and joint limits of :func:`plan` they make the problem one
        for SLSQP.
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

    def __init__(self, sizes: Sequence[int] = SIZES, rtol: float = RTOL, starts: Sequence[str] | None = None,
                 torque: TorqueModel | None = None, tau_max=None, kkt_tol: float = KKT_TOL,
                 feasible: Strategy | None = None):
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
        return (f"{type(self).__name__}(sizes={self.sizes}, rtol={self.rtol:g}, starts={self.starts}"
                + (f", tau_max={self.tau_max!r}" if self.tau_max is not None else "")
                + (f", feasible={self.feasible!r}" if self.feasible is not None else "") + ")")

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
        system = interval.system
        model = self._model(system)
        nan = float("nan")

        def failure(message, pieces=(), evaluations=0):
            c = np.zeros((system.n_inputs, interval.basis.n))
            return OptimalSolve(False, message, c, interval.basis, nan, nan, nan, np.zeros(system.ndx), float("inf"),
                                evaluations), tuple(pieces)

        if self._cost_kind == "torque" and model is None:
            return failure(f"{self.name} needs a torque model for {type(system).__name__}")
        cost = model if self._cost_kind == "torque" else "energy"
        tmax = tau_vector(self.tau_max, model)
        limits = interval.limits if interval.limits is not None and interval.limits.active else None
        sizes = interval.sizes or self.sizes
        conditions = {}

        def new_run(n):
            if n not in conditions:
                bn = interval.sized(n)
                conditions[n] = (bn,) + tuple(interval.conditions(bn))
            bn, B, d = conditions[n]
            return _Run(system, bn, interval.x0, interval.x1, interval.T, cost, model, limits, tmax, B, d,
                        interval.tol, interval.max_evaluations)

        evaluations = 0
        reasons, notes = [], []

        def first_stage(n, candidates):
            """Optimise the candidates ``(label, coefficients, promising)`` at size ``n``: the first one
            unconditionally, each later one only when it is distinct from the best optimum so far and
            its cost below ``promising`` times that optimum's. Returns ``(value, label, run)`` of the best
            or ``None``."""
            nonlocal evaluations
            done = []
            bn = interval.sized(n)
            fn = _cost_for(cost, system, bn, interval.x0, interval.T)
            for label, c, promising in candidates:
                c = np.asarray(c, dtype=float).reshape(system.n_inputs, bn.n)
                curvature = None
                if done:
                    best_value, _, best_run = min(done, key=lambda item: item[0])
                    near = _distance(bn, interval.T, c, best_run.prob.c(best_run.z).reshape(system.n_inputs, -1))
                    ratio = fn(c.reshape(-1))[0] / max(best_value, 1e-300)
                    if not (near > DISTINCT and ratio < promising):
                        notes.append(f"the {label} start ({near:.2f} from the optimum, {ratio:.3g} times its cost) "
                                     "was not optimised")
                        continue
                    curvature = best_run.Hc  # start from the best optimum's curvature
                run = new_run(n).solve(c.reshape(-1), curvature=curvature, kkt_tol=FIRST_KKT_TOL, polish=False)
                ok, value, full = run.brief()
                evaluations += run.prob.evaluations
                if ok:
                    done.append((value, label, run))
                else:
                    reasons.append(f"{n} coefficients from the {label} start: {full.message if full else ''}")
            return min(done, key=lambda item: item[0]) if done else None

        def deform_start(n):
            nonlocal evaluations
            new_run(n)  # (the size's basis and conditions)
            bn, B, d = conditions[n]
            out = solve_segment(system, bn, interval.x0, interval.x1, interval.T, B=B, d=d, tol=DEFORM_TOL,
                                max_evaluations=min(DEFORM_BUDGET, interval.max_evaluations), starts=1)
            evaluations += out.evaluations
            return [("deform", out.coefficients, PROMISING)] if out.success else []

        # 1. the starts: the family's (feasible by construction) when it has them, else (or when they
        #    fail) the plan of the system's method="auto", with the family's starts or path deformation
        feasible_pieces, best, first = (), None, sizes[0]
        explicit = self.starts is not None
        if not explicit or "family" in self.starts:
            fam = family_starts(system, interval, interval.sized(first))
        else:
            fam = None
        if fam and not explicit:
            fn = _cost_for(cost, system, interval.sized(first), interval.x0, interval.T)
            ranked = sorted(fam, key=lambda item: fn(np.ravel(item[1]))[0])
            best = first_stage(first, [(label, c, FAMILY_PROMISING) for label, c in ranked])
        if best is None:
            if explicit and "auto" not in self.starts:
                candidates = [(label, c, FAMILY_PROMISING) for label, c in (fam or ())]
                best = first_stage(first, candidates + (deform_start(first) if "deform" in self.starts else []))
            else:
                feasible = (self.feasible or system.auto_strategy() or AUTO_DEFAULT).solve(interval)
                evaluations += (sum(p.evaluations for p in feasible.pieces) if feasible.success
                                else feasible.evaluations)
                if not feasible.success:
                    return failure(f"no feasible plan to start from: {feasible.reason}", feasible.pieces,
                                   evaluations)
                feasible_pieces = tuple(feasible.pieces)
                if interval.sizes is None and len(feasible.pieces) == 1 and feasible.pieces[0].basis is not None:
                    n0 = feasible.pieces[0].basis.n  # start at the feasible plan's own size, where it is exact
                    first = next((n for n in sizes if n >= n0), sizes[-1])
                # by default (no family starts, or they failed): path deformation as the second start
                use_family = explicit and "family" in self.starts
                use_deform = not explicit or "deform" in self.starts

                def candidates_at(n, bn):  # lazily: path deformation only once the auto start is done
                    yield ("auto", _project(feasible.pieces, interval, bn), math.inf)
                    if use_family:
                        more = fam if n == sizes[0] and fam else (family_starts(system, interval, bn) or [])
                        for label, c in more:
                            yield (label, c, FAMILY_PROMISING)
                    if use_deform:
                        yield from deform_start(n)

                for n in (n for n in sizes if n >= first):
                    best = first_stage(n, candidates_at(n, interval.sized(n)))
                    if best is not None:
                        first = n
                        break
        if best is None:
            return failure(f"{self.name}: no start reached an optimum: " + "; ".join(reasons), feasible_pieces,
                           evaluations)
        value, start_label, current = best

        # 2. the ladder of basis sizes
        history, previous, predicted_stop = [(first, value)], value, None
        for n in (n for n in sizes if n > first):
            progress_note("optimal: basis sizes", sizes.index(n), len(sizes), f"{n} coefficients")  # (core.progress)
            prev = current
            Hc = None if prev.Hc is None else _pad_curvature(prev.Hc, system.n_inputs, prev.prob.n, n)
            c0 = _resize(prev.prob.c(prev.z).reshape(system.n_inputs, -1), n).ravel()
            run = new_run(n)
            before = 0
            if run.solver == "sqp":  # the change to this size, predicted by one Newton step
                predicted = run.predicted_decrease(c0, Hc)
                evaluations += run.prob.evaluations
                before = run.prob.evaluations
                if predicted < self.rtol:
                    history.append((n, previous * (1.0 - predicted)))
                    predicted_stop = predicted
                    break
            run.solve(c0, curvature=Hc, kkt_tol=STAGE_KKT_TOL, polish=False)
            ok, value, full = run.brief()
            if ok and abs(previous - value) < self.rtol * abs(value):
                # a stop on a loosely solved size: decide on the refined optimum (lower, so the change
                # can only grow)
                run.refine(self.kkt_tol)
                ok, value, full = run.brief()
            evaluations += run.prob.evaluations - before
            if not ok or value > previous * (1.0 + 1e-9):
                reasons.append(f"{n} coefficients: " + (full.message if full is not None else
                                                          f"cost {value:.10g}, no better than the smaller basis"))
                break
            current = run
            history.append((n, value))
            change = abs(previous - value) / max(abs(value), 1e-300)
            previous = value
            if change < self.rtol:
                break
        before = current.prob.evaluations
        current.refine(self.kkt_tol)
        res = current.result()
        evaluations += current.prob.evaluations - before
        i = next(k for k, (n, _) in enumerate(history) if n == res.basis.n)
        history[i] = (history[i][0], res.objective)
        if predicted_stop is not None:
            history[-1] = (history[-1][0], res.objective * (1.0 - predicted_stop))
        last = history[-2:] if len(history) >= 2 else None
        converged = last is not None and abs(last[1][1] - last[0][1]) < self.rtol * abs(last[0][1])
        if converged:
            change = abs(last[1][1] - last[0][1]) / max(abs(last[0][1]), 1e-300)
            how = "predicted by one Newton step" if predicted_stop is not None else "solved"
            note = (f"converged in the basis: {last[1][0]} coefficients ({how}) change the cost by {change:.1e} "
                    f"< {self.rtol:g} (relative)")
        elif interval.sizes is not None:
            note = "one basis size (n_coefficients given)"
        else:
            note = "NOT converged in the basis at the largest size tried" + (f": {reasons[-1]}" if reasons else "")
        ladder = ", ".join(f"{n}: {v:.10g}" for n, v in history)
        msg = (f"{self.name}: {res.message}; sizes (n: cost) {ladder}; {note}; start: {start_label}"
               + (f" ({notes[0]})" if notes else "") + f"; integral of |u|^2 = {res.energy:.10g}")
        return dataclasses.replace(res, message=msg, evaluations=evaluations, sizes=tuple(history),
                                   converged_in_basis=converged, start=start_label), feasible_pieces

    def solve(self, interval: Interval) -> IntervalOutcome:
        res, feasible = self.optimize(interval)
        if not res.success:
            return IntervalOutcome(False, feasible, res.message, res.evaluations)
        seg = make_segment(interval.system, res.basis, interval.x0, interval.x1, interval.T, res.coefficients, t0=0.0,
                           final_error=res.final_error, limits=interval.limits, message=res.message, method=self.name,
                           evaluations=res.evaluations, iterations=res.iterations,
                           optimality=self.diagnostics(res, one_size=interval.sizes is not None))
        return IntervalOutcome(True, (seg,), "", 0)

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
