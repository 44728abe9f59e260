"""The SQP of the optimal strategies (:mod:`~acroplan.core.optimal`), on a problem in reduced
coordinates :math:`z`:

.. math::  \\min_z f(z) \\quad\\text{s.t.}\\quad h(z) = 0 ,\\qquad r(z) \\le 0 .

A problem gives ``f(z) -> (f, gradient, model Hessian)`` and ``h(z) -> (h, Jacobian, ...)``, and
the inequalities ``r(z) -> (r, Jacobian)`` when it has any; the module docstring of
:mod:`~acroplan.core.optimal` describes the method (steps of the KKT system with the Lagrangian's
modelled curvature, the :math:`\\ell_1` merit function, second-order corrections, the step cap).
:func:`kkt_multipliers` gives the least-squares multipliers and the relative KKT residual the
strategies report. The second-order correction of a trial step goes back onto the equations
without leaving the inequalities near their bound, and holds the quadratic program's active rows
at their bound (:func:`_corrected`); so does the final polish of the endpoint
(:func:`polish_endpoint`) with the rows active at its start. For a few iterations after a full
step the merit function refused, the line search is nonmonotone (:data:`NONMONOTONE`); its trial
points evaluate the cost alone until accepted (:data:`LAZY_GRADIENT`).

The step with inequalities (:func:`qp_step`) solves the quadratic program

.. math::  \\min_p\\ g^\\top p + \\tfrac12 p^\\top W p \\quad\\text{s.t.}\\quad A p = -h ,\\quad
           R p \\le -r :

the equations are eliminated (:math:`p = Y p_Y + Z y`, :math:`A^\\top = [Y\\ Z] [R_A; 0]`,
:math:`p_Y = -R_A^{-\\top} h`), the reduced Hessian :math:`Z^\\top W Z = V \\mathrm{diag}(e) V^\\top` made
positive definite by the magnitudes of its eigenvalues (at least 1e-6 of the largest), and with
:math:`y = y^* + V \\mathrm{diag}(e)^{-1/2} w` (:math:`y^*` the unconstrained minimiser) the program is
the least-distance program :math:`\\min \\|w\\|` s.t. :math:`E w \\le f`, solved by non-negative least
squares (:func:`acroplan.core.linalg.least_norm_step`). When the reduced Hessian is positive
definite and well-conditioned (no eigenvalue near the floor: :func:`_well_conditioned_cholesky`),
its Cholesky factor :math:`L` serves instead, :math:`y = y^* + L^{-\\top} w`: the same program with
:math:`w` rotated, for a tenth of the cost. The inequalities' multipliers are those of
that program, :math:`w + E^\\top\\mu = 0`, :math:`\\mu \\ge 0` (non-negative least squares on the rows
active at :math:`w`); the equations' by least squares from :math:`Wp + g + A^\\top\\lambda + R^\\top\\mu = 0`.
Rows far from their bound (the free step :math:`w = 0` uses less than three quarters of their slack)
are left out, and of the others at most :data:`QP_ROWS` enter the least-distance program at a time,
those whose half-space lies farthest from the step (in :math:`w`, which has no units); rows the step
then breaks join, :data:`QP_ROWS` at a time, at most :data:`QP_ROUNDS` rounds. A least-distance
program on a subset of the rows whose solution keeps them all is the whole program's solution, so
the step is exact; the programs stay small (the forward dive's joint optimum on 257 points an
interval put 1,600-2,700 rows in play, and each non-negative least squares took up to 50 ms).
The working set starts with the last step's binding rows too (from one iteration to the next the
active set changes little: 1-2 rounds instead of 10-13 on that joint optimum). A row counts as
broken beyond rounding by its own magnitude, as active by its distance in :math:`w`; the step is
refined once onto the equations and the binding rows (a least-squares correction), so that a full
step keeps the active rows to rounding and the merit function's penalty (thousands) does not
refuse it at the end. When the reduced Hessian had negative eigenvalues, the step of the model with
their magnitudes is not the program's; the step is then Newton's on the binding rows taken as
equations with the model as it is (:func:`_active_newton`: a few rounds of a primal active-set
method), when the model is positive definite on their null space there and the step keeps every
row with multipliers not negative: a local solution of the program itself, so that the SQP
converges quadratically where the Lagrangian bends down along a direction the active limits block.
"""

from __future__ import annotations

import collections
import math

import numpy as np
from scipy.linalg import lapack

from . import backend
from .linalg import least_norm_step, norm

__all__ = ["solve_small", "kkt_multipliers", "kkt_step", "qp_step", "sqp", "polish_endpoint", "MAX_REFRESH", "POOR_STEPS",
           "MERIT_RESOLUTION", "INEQ_TOL", "SOC_NEAR"]

#: New forward-difference constraint Hessians after :data:`POOR_STEPS` steps in a row that the
#: model predicted poorly (the line search backtracked), at most this many times per solve.
MAX_REFRESH = 3
#: Backtracked steps in a row before the constraint Hessians are refreshed. A refresh costs one
#: endpoint evaluation per coordinate (120 at 30 coefficients of 4 inputs), more than the few
#: iterations the symmetric rank-one corrections take to repair the model in between: refreshing
#: after every backtracked step made the bundled twisting dives' torque optima 2-3x slower, with
#: the same optima (benchmarks/RESULTS.md, 2026-12-03, "The SQP's curvature refreshes").
POOR_STEPS = 3
#: Relative resolution of the merit function: a step whose predicted decrease is below this times
#: :math:`|f| + \\rho \\|h\\|_1` cannot be told from rounding by the line search (the endpoint's
#: rounding, some 1e-15, times a penalty of thousands), so it is taken whole when it lowers the
#: relative KKT residual instead (:func:`_below_resolution`). Without it the trunk's torque optimum
#: stopped at a residual of 5.9e-8, a predicted decrease of 1.9e-12 on a cost of 55.
MERIT_RESOLUTION = 1e-12
#: An inequality :math:`r_i(z) \\le 0` holds for the stop (and :func:`_below_resolution`) when
#: :math:`r_i \\le` this, in the limit's own units (rad/s, rad, N m): an active row evaluates to
#: rounding (measured up to 1.6e-13 on the forward dive's rate limits), and at exactly 0 the SQP ran
#: on at a KKT residual of 1e-10 until no step decreased the merit function (hundreds of
#: evaluations a size). The rows lie 2e-3 inside the limits, and a result must comply to
#: :data:`acroplan.core.limits.COMPLIANCE_TOL` (1e-9) besides.
INEQ_TOL = 1e-11


def solve_small(M, b):
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


def kkt_multipliers(g, A, C=None):
    """Least-squares multipliers and the relative KKT residual (module docstring).

    ``g``: cost gradient (N,); ``A``: equality Jacobian (q, N); ``C``: active inequality rows
    (r, N) of constraints ``C z <= ...`` (multipliers >= 0, by non-negative least squares)."""
    gn = math.sqrt(float(g @ g))
    if C is None or C.shape[0] == 0:
        try:
            lam = -solve_small(A @ A.T, A @ g)
        except np.linalg.LinAlgError:
            lam = -np.linalg.lstsq(A.T, g, rcond=None)[0]
        res = g + A.T @ lam
        return lam, (math.sqrt(float(res @ res)) / gn if gn > 0 else 0.0)
    Q, _ = np.linalg.qr(A.T, mode="complete")
    P = Q[:, A.shape[0]:]  # orthonormal basis of the null space of A: eliminates the free multipliers
    from scipy.optimize import nnls  # here: scipy.optimize takes 0.4 s to import

    mu, _ = nnls(P.T @ C.T, -P.T @ g)
    lam = -np.linalg.lstsq(A.T, g + C.T @ mu, rcond=None)[0]
    res = g + A.T @ lam + C.T @ mu
    return lam, (math.sqrt(float(res @ res)) / gn if gn > 0 else 0.0)


def _null_space(M):
    """``(Y, Z, R)`` of the complete QR factorisation :math:`M^\\top = [Y\\ Z] [R; 0]` of rows ``M``
    (k, N): :math:`Y` spans their range, :math:`Z` their null space; ``None`` when ``M`` is
    rank-deficient (a diagonal entry of :math:`R` below 1e-12 of the largest)."""
    k = M.shape[0]
    Q, R = np.linalg.qr(M.T, mode="complete")
    dR = np.abs(np.diag(R[:k, :k]))
    if dR.min() <= 1e-12 * max(1.0, dR.max()):
        return None
    return Q[:, :k], Q[:, k:], R[:k, :k]


def kkt_step(W, g, h, A, H, convex_only=False):
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
    qr = _null_space(A)
    if qr is None:
        return None
    Y, Zr, R = qr
    pY = -np.linalg.solve(R.T, h)
    Wr = Zr.T @ W @ Zr
    e, V = np.linalg.eigh(0.5 * (Wr + Wr.T))
    e = np.maximum(np.abs(e), 1e-6 * max(float(np.abs(e).max()), 1e-300))
    p = Y @ pY + Zr @ (V @ ((V.T @ (-Zr.T @ (g + W @ (Y @ pY)))) / e))
    return p, -np.linalg.solve(R, Y.T @ (W @ p + g))


#: Rounds of :func:`qp_step`'s working set (the rows broken by a round's step join the next).
QP_ROUNDS = 64
#: Rows that join :func:`qp_step`'s working set at most, at the start and in each round (those
#: farthest from the step).
QP_ROWS = 32
#: :func:`qp_step` starts from the rows whose slack the free step leaves below this fraction.
QP_NEAR = 0.25


def _farthest(rows, over, R, T):
    """The at most :data:`QP_ROWS` of ``rows`` whose half-space :math:`E_i w \\le f_i` lies farthest
    from the step, :math:`(E_i w - f_i)/\\|E_i\\|` (``over`` is :math:`E w - f` for every row)."""
    if rows.size <= QP_ROWS:
        return rows
    dist = over[rows] / np.maximum(np.linalg.norm(R[rows] @ T, axis=1), 1e-300)
    return np.sort(rows[np.argsort(-dist, kind="stable")[:QP_ROWS]])


def qp_step(W, g, h, A, R, r, hint=None):
    """The step of the quadratic program with inequalities (module docstring): ``(p, lambda, mu)``,
    or ``None`` when ``A`` is rank-deficient or no step keeps the linearised inequalities.
    ``hint``: rows to start the working set with besides (the last step's active rows: from one
    SQP iteration to the next the active set changes little)."""
    N, q = W.shape[0], A.shape[0]
    if q >= N:
        return None
    qr = _null_space(A)
    if qr is None:
        return None
    Y, Zr, RA = qr
    pY = Y @ -np.linalg.solve(RA.T, h)
    Wr = Zr.T @ W @ Zr
    Wr = 0.5 * (Wr + Wr.T)
    gr = Zr.T @ (g + W @ pY)
    L = _well_conditioned_cholesky(Wr) if CHOLESKY_QP else None
    if L is not None:
        # the same program in the same coordinates up to a rotation (w = L^T (y - y*)), the
        # eigenvalues' floor not reached (module docstring)
        e_model = None
        ystar = -lapack.dpotrs(L, gr, lower=1)[0]
        T = lapack.dtrtrs(L, Zr.T, lower=1)[0].T  # Zr L^-T: w to the step
    else:
        e, V = np.linalg.eigh(Wr)
        e_model = e  # as the model has them: when negative, its step is not the program's (ACTIVE_NEWTON)
        e = np.maximum(np.abs(e), 1e-6 * max(float(np.abs(e).max()), 1e-300))
        ystar = -(V @ ((V.T @ gr) / e))
        # the rows E = R Zr V e^(-1/2) of the inequalities in the scaled coordinates w are formed for
        # the rows in play only; the others are checked through matrix-vector products (the joint
        # optimum's limit grids give thousands of rows, of which a few dozen are near their bounds)
        T = Zr @ (V / np.sqrt(e)[None, :])  # (N, N - q): w to the step
    p_free = pY + Zr @ ystar
    f = -r - R @ p_free
    # in play: the rows the free step breaks or uses three quarters of the slack of, each in its own
    # units (rows of angles, rates and torques differ by orders), at most QP_ROWS of them, the
    # farthest from the step first (distance in w, which has no units); the others are added
    # back when a step breaks them, QP_ROWS at a time
    rows = _farthest(np.flatnonzero(f < QP_NEAR * np.maximum(-r, 0.0)), -f, R, T)
    if hint is not None and len(hint):
        hint = np.asarray(hint, dtype=int)
        rows = np.union1d(rows, hint[(hint >= 0) & (hint < R.shape[0])])
    w = np.zeros(T.shape[1])
    E = R[rows] @ T
    for _ in range(QP_ROUNDS):
        if rows.size:
            w, ok = least_norm_step(np.zeros((0, w.size)), np.zeros(0), E, f[rows])
            if not ok:
                return None
        over = R @ (T @ w) - f
        # broken beyond rounding, row by row: a tolerance of 1e-9 of the largest row let steps break
        # active rows by 4e-8 (rate limits beside 100 N m torque rows), which the merit function's
        # penalty of 3e4 then refused (the forward dive's joint optimum stopped at a KKT residual of
        # 1.3e-6: "no step decreased the merit function")
        broken = np.flatnonzero(over > 1e-12 * (1.0 + np.abs(r) + np.abs(f)))
        new = _farthest(np.setdiff1d(broken, rows), over, R, T)
        if new.size == 0:
            break
        rows = np.union1d(rows, new)
        E = R[rows] @ T
    else:
        return None
    y = ystar + (lapack.dtrtrs(L, w, lower=1, trans=1)[0] if L is not None else V @ (w / np.sqrt(e)))
    p = pY + Zr @ y
    mu = np.zeros(R.shape[0])
    # active at w: within 1e-9 of the bound in w, which has no units (a tolerance in the rows' own
    # units, 1e-9 of the largest, counted rows 1e-3 away in w as active where units differ by 1e6)
    on = (f[rows] - E @ w <= 1e-9 * np.linalg.norm(E, axis=1) * (1.0 + norm(w)) if rows.size
          else np.zeros(0, dtype=bool))
    act = rows[on]
    if act.size:
        from scipy.optimize import nnls

        mu[act] = nnls(E[on].T, -w)[0]
        # one step of refinement onto the equations and the binding rows: the least-distance
        # program holds them to its own accuracy, which the scaling by the reduced Hessian's
        # smallest eigenvalues loosens (the forward dive's joint optimum: a rate-limit row 4.7e-11
        # beyond its bound after a full step, so the step below the merit function's resolution
        # was refused and the SQP stopped at a KKT residual of 2e-8)
        bind = act[mu[act] > 0.0]  # the rows that bind (within the tolerance above, some need not)
        M = np.vstack([A, R[bind]])
        p = p + np.linalg.lstsq(M, np.concatenate([-h - A @ p, -r[bind] - R[bind] @ p]), rcond=1e-12)[0]
    if e_model is not None and e_model[0] < 0.0 and ACTIVE_NEWTON:
        start = np.flatnonzero(mu > 0.0)
        at = np.flatnonzero(np.abs(r) <= 1e-7)  # the rows at their bound now (within 1e-7 either side)
        work = np.union1d(np.union1d(start, at), hint if hint is not None and len(hint) else np.zeros(0, dtype=int))
        exact = _active_newton(R, r, work, pY, Zr, V, e_model, V.T @ gr)
        if exact is not None:
            p, mu = exact
    lam = -np.linalg.solve(RA, Y.T @ (W @ p + g + R.T @ mu))
    return p, lam, mu


#: Whether :func:`qp_step` factors a well-conditioned reduced Hessian by Cholesky instead of its
#: eigenvalues (:func:`_well_conditioned_cholesky`).
CHOLESKY_QP = True
#: :func:`_well_conditioned_cholesky` takes a factor whose estimated reciprocal condition number
#: (1-norm, LAPACK's ``dpocon``) is above this: 100 times the eigenvalues' floor (1e-6 of the
#: largest), so that the floor, which the eigenvalue route applies, is far from reached.
CHOLESKY_RCOND = 1e-4


def _well_conditioned_cholesky(Wr):
    """The lower Cholesky factor of the reduced Hessian ``Wr`` when it is positive definite and its
    estimated reciprocal condition number is above :data:`CHOLESKY_RCOND`, else ``None``. With it
    the least-distance program's coordinates :math:`w = L^\\top (y - y^*)` differ from the
    eigenvalues' :math:`w = \\mathrm{diag}(e)^{1/2} V^\\top (y - y^*)` by a rotation
    (:math:`L^\\top V \\mathrm{diag}(e)^{-1/2}` is orthogonal when no eigenvalue is floored), so
    the program, its rows' distances and its multipliers are the same; a factorisation costs a
    tenth of the eigenvalues (226 x 226: 0.7 ms against 6.6 ms)."""
    L, info = lapack.dpotrf(Wr, lower=1, clean=1)
    if info != 0:
        return None
    rcond, info = lapack.dpocon(L, float(np.abs(Wr).sum(axis=0).max()), uplo="L")
    if info != 0 or not rcond > CHOLESKY_RCOND:
        return None
    return L


#: Whether :func:`qp_step` takes the Newton step of the binding rows (:func:`_active_newton`) when
#: it had changed the model's negative curvature. Without it, where the Lagrangian's curvature is
#: negative along a direction that the binding rows block, the flipped model's step pointed the
#: right way but fell short by a constant fraction, and the SQP converged linearly: the falling
#: cat's least integral of u^2 at 30 coefficients, from the ladder's KKT residual of 9e-4 to 1e-8,
#: took 36 full steps, each 18% of the Newton step (the reduced Hessian's least eigenvalue -0.084
#: off the binding joint-range rows); with it, 16 steps from the ladder's padded curvature, 3 from
#: fresh constraint Hessians, and that optimum's endpoint evaluations 265 -> 225. The twisting dives'
#: counts move by a few percent either way, the falling cat's least integral of tau^2 (whose SQP
#: creeps on the torque cost's Gauss-Newton model either way) 522 -> 605 with the step found by
#: QR factorisations of size N, 639 with the Schur complement (:func:`_active_newton`), which costs
#: the dives 0.03-0.09 s where those took 0.18-0.54 s (``benchmarks/RESULTS.md``, 2026-12-06,
#: seventh session).
ACTIVE_NEWTON = True
#: Rounds of :func:`_active_newton`'s working set.
ACTIVE_ROUNDS = 8
#: Whether :func:`_active_newton` drops a row of its working set that is nearly dependent on the
#: others (:func:`_dependent_row`) instead of giving up. The joint optimum's grids of the rate limits
#: (64 uniform and 64 Chebyshev points an interval, which crowd at its ends) put neighbouring points
#: of one peak in the set, one at its bound and one within 1e-7 of it: their rows (unit length)
#: differ by about 4e-5 on the null space, the Schur complement had an eigenvalue 1e-11 of its
#: largest, and every Newton step of the bundled forward dive's joint torque optimum was refused;
#: the flipped model's steps then converged linearly (KKT residual x0.6 an iteration, 31
#: iterations). Dropping the row: 25 (``benchmarks/RESULTS.md``, eighteenth session).
DROP_DEPENDENT = True
#: :func:`_dependent_row`: rows count as nearly dependent when a unit combination of them (the
#: near-null eigenvector of the Schur complement) is at most this long on the null space.
DEPENDENT_ROWS = 1e-3


def _active_newton(R, r, work, pY, Zr, V, e, Vg):
    """The Newton step of the quadratic program with the model as it is, by a few rounds of a primal
    active-set method from the working set ``work`` (rows taken as equations, :math:`R_w p = -r_w`,
    beside :math:`A p = -h`): a row whose multiplier is negative leaves the set, a row the step
    breaks joins it (the only move where the model is not positive definite on the set's null
    space: its step is a saddle's), a row nearly dependent on the others leaves it
    (:func:`_dependent_row`), at most :data:`ACTIVE_ROUNDS` times. ``(p, mu)`` when a round's
    step keeps every row with multipliers not negative and the model is positive definite on the
    null space of its equations (so that ``p`` is a local solution of the program); ``None`` when
    no round gets there, or when the model is singular on the equations' null space.

    It works in :func:`qp_step`'s coordinates: :math:`p = p_Y + Z y`, the model's reduced Hessian
    :math:`W_r = Z^\\top W Z = V \\mathrm{diag}(e) V^\\top` with its own eigenvalues ``e`` (some
    negative), ``Vg`` :math:`= V^\\top Z^\\top (g + W p_Y)`. With :math:`B = R_w Z V`, the working
    set's equations are :math:`B V^\\top y = -t`, :math:`t = r_w + R_w p_Y`, and the step and the
    multipliers follow from the Schur complement :math:`S = B\\,\\mathrm{diag}(e)^{-1} B^\\top`
    (k x k): :math:`S\\mu = t - B\\,\\mathrm{diag}(e)^{-1} V^\\top g_r`, :math:`y = -V
    \\mathrm{diag}(e)^{-1}(V^\\top g_r + B^\\top\\mu)`. The model is positive definite on the
    set's null space exactly when the KKT matrix :math:`[W_r, R_r^\\top; R_r, 0]` has k negative
    eigenvalues, and by Haynsworth's inertia additivity it has as many as :math:`W_r` (the
    negative ``e``) plus the positive eigenvalues of :math:`S`: no factorisation of size N."""
    top = float(np.abs(e).max(initial=0.0))
    if not np.abs(e).min(initial=np.inf) > 1e-10 * top:
        return None
    negative = int(np.count_nonzero(e < 0.0))
    work = np.asarray(work, dtype=int)
    ZV = Zr @ V
    for _ in range(ACTIVE_ROUNDS):
        k = work.size
        if k >= e.size:
            return None
        B = R[work] @ ZV  # (k, N - q)
        norms = np.linalg.norm(B, axis=1)  # each row scaled to unit length on the null space
        if k and not norms.min() > 0.0:
            return None
        B = B / norms[:, None]
        Be = B / e
        S = Be @ B.T
        es = np.linalg.eigvalsh(0.5 * (S + S.T)) if k else np.zeros(0)
        # an eigenvalue of S (of the rows scaled to unit length) near zero: the KKT matrix is nearly
        # singular. When rows of the set are nearly dependent on the null space (two neighbouring
        # points of one limit's grid at a peak, one at its bound and one within 1e-7 of it), the row
        # of the near-null combination farthest inside its bound leaves the set (it joins again if
        # the step breaks it); else the model is nearly flat on the set's null space, its Newton step
        # long and unreliable, and the step with the magnitudes is kept
        if k and not np.abs(es).min() > 1e-8 * max(float(np.abs(es).max()), 1e-300):
            dropped = _dependent_row(B, S, r[work]) if DROP_DEPENDENT else None
            if dropped is None:
                return None
            work = np.delete(work, dropped)
            continue
        convex = negative + int(np.count_nonzero(es > 0.0)) == k
        mu_w = np.linalg.solve(S, (r[work] + R[work] @ pY) / norms - Be @ Vg) if k else np.zeros(0)
        p = pY - ZV @ ((Vg + B.T @ mu_w) / e)
        mu_w = mu_w / norms if k else mu_w  # the rows' own multipliers
        over = r + R @ p
        over[work] = 0.0
        broken = np.flatnonzero(over > 1e-12 * (1.0 + np.abs(r)))
        if not convex:  # a saddle of the model on this face: only the rows its step breaks can help
            if not broken.size:
                return None
            work = np.union1d(work, broken[np.argsort(-over[broken], kind="stable")[:QP_ROWS]])
            continue
        if k and mu_w.min() < -1e-10 * max(1.0, float(np.abs(mu_w).max())):
            work = np.delete(work, int(np.argmin(mu_w)))
            continue
        if broken.size:
            work = np.union1d(work, broken[np.argsort(-over[broken], kind="stable")[:QP_ROWS]])
            continue
        mu = np.zeros(r.size)
        mu[work] = np.maximum(mu_w, 0.0)
        return p, mu
    return None


def _dependent_row(B, S, r_work):
    """The position in the working set of the row to drop when the Schur complement ``S`` of
    :func:`_active_newton` is nearly singular because rows of ``B`` (unit length) are nearly
    dependent, or ``None`` when they are not: of the rows that weigh (at least a tenth of the
    largest) in the eigenvector of ``S``'s eigenvalue nearest zero, the one farthest inside its
    bound (``r_work``, the rows' values :math:`r_i \\le 0`). Nearly dependent means that the same
    combination nearly cancels in ``B`` itself (:math:`\\|B^\\top v\\| \\le 10^{-3}`); otherwise
    ``S`` is singular through the model's curvature, and dropping a row would not mend it."""
    ev, vecs = np.linalg.eigh(0.5 * (S + S.T))
    v = vecs[:, int(np.argmin(np.abs(ev)))]
    if not float(np.linalg.norm(B.T @ v)) <= DEPENDENT_ROWS:
        return None
    weigh = np.flatnonzero(np.abs(v) >= 0.1 * np.abs(v).max())
    return int(weigh[int(np.argmin(r_work[weigh]))])


def _at_bound(r, tol=1e-7):
    """The rows of :math:`r \\le 0` within ``tol`` of their bound (relative to its scale): those of the
    KKT residual (:meth:`_Point.active`) and of the endpoint's polish (:func:`polish_endpoint`)."""
    return r >= -tol * (1.0 + np.abs(r))


def _violation(h, r) -> float:
    """:math:`\\|h\\|_1 + \\sum_i \\max(0, r_i)`, the constraint violation of the merit function."""
    out = sum(map(abs, h.tolist()))
    if r is not None and r.size:
        out += float(np.maximum(r, 0.0).sum())
    return out


#: A trial point of the line search evaluates the cost alone, its gradient and model Hessian only
#: once it is accepted (:meth:`_Point.accepted`): a torque cost's derivatives are most of its
#: evaluation, and the second-order correction needs the endpoint's and the limits' Jacobians at
#: the trial point, never the cost's (with the Jacobians at the iterate instead, the textbook form,
#: the bundled dives took 1.0 to 3 times the evaluations and ended at other optima:
#: ``benchmarks/RESULTS.md``, 2026-12-06, eighth session).
LAZY_GRADIENT = True


class _Point:
    """The SQP's functions at one point: cost, gradient, model Hessian, constraints and their Jacobians."""

    __slots__ = ("z", "f", "g", "H", "h", "A", "r", "R")

    def __init__(self, prob, z, ineq, trial=False):
        self.z = z
        if trial and LAZY_GRADIENT and hasattr(prob, "f_value"):
            self.f, self.g, self.H = prob.f_value(z), None, None
        else:
            self.f, self.g, self.H = prob.f(z)
        self.h, self.A = prob.h(z)[:2]
        self.r, self.R = ineq(z) if ineq is not None else (None, None)

    def accepted(self, prob):
        """This trial point, with the cost's gradient and model Hessian (a trial point has its cost
        alone until it is accepted: :data:`LAZY_GRADIENT`)."""
        if self.g is None:
            self.f, self.g, self.H = prob.f(self.z)
        return self

    def merit(self, rho) -> float:
        return self.f + rho * _violation(self.h, self.r)

    def active(self, tol=1e-7):
        """The inequality rows active within ``tol`` (relative to the bound's scale), for the KKT residual."""
        if self.r is None:
            return None
        return self.R[_at_bound(self.r, tol)]


#: The second-order correction keeps the inequality rows whose slack at the trial point is below
#: this, relative (:func:`_corrected`).
SOC_NEAR = 1e-2
#: The second-order correction holds the quadratic program's active rows at their bound (:func:`_corrected`),
#: and the endpoint's polish the rows active at its start (:func:`polish_endpoint`).
WORKING_SOC = True


def _corrected(xt, work=None):
    """The second-order correction from the trial point ``xt``: the shortest step back onto the
    linearised equations, :math:`A d = -h`, that keeps the linearised inequalities near their bound,
    :math:`R_i d \\le -r_i` for the rows with :math:`r_i > -` :data:`SOC_NEAR` :math:`(1 + |r_i|)`
    (:func:`acroplan.core.linalg.least_norm_step`; the plain minimum-norm step when there are no
    inequalities, or when no step keeps them). The plain step alone broke the active torque and
    rate limits it had just been kept on, by some 1e-3: on the bundled double full-out's joint
    torque optimum, whose penalty is some 1e4, every correction then raised the merit function
    by tens, and the SQP crawled at steps of 1% until its 150 iterations were spent, at a KKT
    residual of 1.3e-2 (``benchmarks/RESULTS.md``, 2026-12-06).

    ``work``: the rows the quadratic program held at their bound (its positive multipliers), held
    there by the correction too, as equations :math:`R_i d = -r_i` (the correction of an
    active-set SQP is taken with its working set: Nocedal and Wright, *Numerical Optimization*,
    2006, section 18.3); as inequalities alone they let the shortest step leave them inwards, and
    the next step came back: on the falling cat's least :math:`\\int u^2` at 10 coefficients every
    other iterate left its 3-4 active joint-range rows by 1e-6 to 6e-4, where the KKT residual (of
    the rows within 1e-7 of their bound) read 0.36, the one between 0.02, and the stage took 34
    iterations (``benchmarks/RESULTS.md``, 2026-12-06, eighth session). When no step holds them
    (dependent rows), the correction without them."""
    plain = xt.z - xt.A.T @ solve_small(xt.A @ xt.A.T, xt.h)
    if xt.r is None:
        return plain
    near = xt.r > -SOC_NEAR * (1.0 + np.abs(xt.r))
    if not near.any():
        return plain
    if WORKING_SOC and work is not None and work.size:
        held = np.zeros(near.size, dtype=bool)
        held[work] = True
        held &= near
        if held.any():
            rest = near & ~held
            d, ok = least_norm_step(np.vstack([xt.A, xt.R[held]]), np.concatenate([-xt.h, -xt.r[held]]),
                                    xt.R[rest], -xt.r[rest])
            if ok and np.allclose(xt.R[held] @ d, -xt.r[held], rtol=0.0, atol=1e-9 * (1.0 + np.abs(xt.r[held]).max())):
                return xt.z + d
    d, ok = least_norm_step(xt.A, -xt.h, xt.R[near], -xt.r[near])
    return xt.z + d if ok else plain


#: Nonmonotone acceptance (Grippo, Lampariello and Lucidi, *SIAM J. Numer. Anal.* 23, 1986): a
#: trial point is compared with the largest merit of the last this-many iterates instead of the
#: current one's (0: the current one alone), for :data:`NONMONOTONE` iterations after a full step
#: was refused and its second-order correction taken (the Maratos effect: the merit function
#: refuses full SQP steps near a curved constraint manifold, and each such step then costs two
#: evaluations; :data:`MARATOS_ONLY`). Measured (whole-plan endpoint evaluations, one BLAS thread,
#: ``benchmarks/RESULTS.md``, 2026-12-06, eighth session): forward dive 547 -> 437, double
#: full-out 643 -> 600, back full 316 -> 305, trunk's least integral of tau^2 104 -> 83, falling cat's
#: least integral of u^2 149 -> 138, the same optima; the acrobot's and planar bodies' optima over
#: 62 random segments 2105 -> 2112 in all (without the Maratos condition, 22 torque optima among
#: them took 1187 -> 1273).
NONMONOTONE = 4
#: ... only after a refused full step (:data:`NONMONOTONE`); else after every step
MARATOS_ONLY = True


def _line_search(prob, x, p, rho, slope, alpha, ineq, work=None, ref=None):
    """Backtracking on the merit function from ``x`` along ``p``, with a second-order correction back
    onto the equations at every trial (the Maratos effect; ``work`` the quadratic program's active
    rows, :func:`_corrected`; ``ref`` a merit to compare with instead of ``x``'s when larger,
    :data:`NONMONOTONE`). Returns ``(point, alpha, trial, refused)`` (``refused``: the full step
    was refused and its correction taken) or ``None``."""
    merit0 = x.merit(rho) if ref is None else max(x.merit(rho), ref)
    for trial in range(14):
        try:
            xt = _Point(prob, x.z + alpha * p, ineq, trial=True)
        except backend.IntegrationError:
            alpha *= 0.25
            continue
        if xt.merit(rho) <= merit0 + 1e-4 * alpha * slope:
            return xt.accepted(prob), alpha, trial, False
        try:
            xc = _Point(prob, _corrected(xt, work), ineq, trial=True)
            if xc.merit(rho) <= merit0 + 1e-4 * alpha * slope:
                return xc.accepted(prob), alpha, trial, trial == 0
        except (backend.IntegrationError, np.linalg.LinAlgError):
            pass
        alpha *= 0.5
    return None


def _below_resolution(prob, x, p, kkt, ineq):
    """The full step from ``x`` along ``p`` when the decrease it predicts is below the merit
    function's resolution (:data:`MERIT_RESOLUTION`), accepted when it lowers the relative KKT
    residual and keeps the limits; ``(point, 1.0, 0)`` or ``None``."""
    try:
        xt = _Point(prob, x.z + p, ineq)
    except backend.IntegrationError:
        return None
    if xt.r is not None and xt.r.max(initial=-1.0) > INEQ_TOL:
        return None
    if kkt_multipliers(xt.g, xt.A, xt.active())[1] >= kkt:
        return None
    return xt, 1.0, 0


def sqp(prob, z, Hz, *, tol, kkt_tol, max_iter=40, refresh=None, max_refresh=None, ineq=None):
    """The SQP (module docstring) from ``z`` with constraint Hessians ``Hz`` (q, Nz, Nz);
    ``refresh(z)`` gives new ones (forward differences) after :data:`POOR_STEPS` steps in a row the
    model predicted poorly;
    ``ineq(z) -> (r, R)`` the inequalities :math:`r(z) \\le 0` and their Jacobian, when there are any.
    Returns ``(z, info)``: ``info`` has the multipliers ``lam``, the relative KKT residual ``kkt``,
    the iterations ``its``, why it stopped early (``why``, empty when converged) and the constraint
    Hessians last computed (``curvature``, shape (q, N, N), without the rank-one corrections)."""
    x = _Point(prob, z, ineq)
    lam, kkt = kkt_multipliers(x.g, x.A, x.active())
    N, q = z.size, x.A.shape[0]
    Hz2 = Hz.reshape(q, N * N)
    D = np.zeros((N, N))
    rho = 0.0
    radius = 2.0 * max(math.sqrt(max(float(z @ x.H @ z), 0.0)), 1e-3)
    its, why, refreshed, poor = 0, "", 0, 0  # poor: backtracked steps in a row
    hint = None  # the last quadratic program's active rows
    history = collections.deque([(x.f, _violation(x.h, x.r))], maxlen=max(int(NONMONOTONE), 1))
    since = 10 ** 9  # iterations since a full step was refused and its correction taken
    max_refresh = MAX_REFRESH if max_refresh is None else max_refresh
    while its < max_iter:
        if kkt <= kkt_tol and max(map(abs, x.h.tolist())) <= tol and (x.r is None or x.r.max(initial=-1.0) <= INEQ_TOL):
            break
        its += 1
        W = (lam @ Hz2).reshape(N, N)
        W += x.H
        W += D
        if ineq is None:
            out = kkt_step(W, x.g, x.h, x.A, x.H)
            mu = None
        else:
            out = qp_step(W, x.g, x.h, x.A, x.R, x.r, hint)
            mu = None if out is None else out[2]
            hint = None if mu is None else np.flatnonzero(mu > 0.0)
        if out is None:
            why = "the endpoint Jacobian is singular" if ineq is None else "no step keeps the linearised limits"
            break
        p, lam_qp = out[0], out[1]
        rho = max(rho, 2.0 * max(map(abs, lam_qp.tolist())) + 1e-12,
                  2.0 * float(mu.max(initial=0.0)) + 1e-12 if mu is not None else 0.0)
        v = _violation(x.h, x.r)
        slope = float(x.g @ p) - rho * v
        if slope > -1e-15 * (abs(x.f) + rho * v):  # nothing left to gain at this precision
            break
        step = math.sqrt(max(float(p @ x.H @ p), 0.0))
        # a decrease below the merit function's resolution: the full step on the KKT residual first
        # (a backtracking search there compares rounding, and took 20-30 evaluations a step)
        below = -slope <= MERIT_RESOLUTION * (abs(x.f) + rho * v)
        found = _below_resolution(prob, x, p, kkt, ineq) if below else None
        if found is None:
            relax = NONMONOTONE and (not MARATOS_ONLY or since < NONMONOTONE)
            ref = max(fv + rho * vv for fv, vv in history) if relax else None
            found = _line_search(prob, x, p, rho, slope, min(1.0, radius / step) if step > 0 else 1.0, ineq, hint, ref)
            since = 0 if found is not None and found[3] else since + 1
        if found is None:
            why = "no step decreased the merit function"
            break
        xt, alpha, trial = found[:3]
        s = xt.z - x.z
        # the cap on the step (in the cost's metric) follows the steps taken
        radius = max(radius, 2.0 * alpha * step) if trial == 0 else max(alpha * step, 0.25 * radius, 1e-12)
        poor = poor + 1 if trial > 0 else 0
        if refresh is not None and poor >= POOR_STEPS and refreshed < max_refresh:  # a poor model: new Hessians
            poor = 0
            refreshed += 1
            Hz2 = refresh(xt.z).reshape(q, N * N)
            D[:] = 0.0
        else:  # symmetric rank-one correction of the modelled curvature, from the Lagrangian's secant
            y = (xt.g - x.g) + (xt.A - x.A).T @ lam_qp - (xt.H + (lam_qp @ Hz2).reshape(N, N) + D) @ s
            if mu is not None:
                y += (xt.R - x.R).T @ mu
            den = float(y @ s)
            if abs(den) > 1e-8 * math.sqrt(float(y @ y) * float(s @ s)) > 0:
                D += np.outer(y, y) / den
        x = xt
        history.append((x.f, _violation(x.h, x.r)))
        lam, kkt = kkt_multipliers(x.g, x.A, x.active())
        if float(s @ s) <= 1e-30 * (1.0 + float(x.z @ x.z)):
            break
    return x.z, dict(lam=lam, kkt=kkt, its=its, why=why, curvature=Hz2.reshape(q, N, N))


def polish_endpoint(prob, z, tol, ineq=None):
    """Minimum-norm Newton steps on the endpoint alone (as :func:`solve_with_limits`). ``ineq``: the
    inequalities (as :func:`sqp`'s); the rows active at ``z`` (within 1e-7 of their bound, those of
    the KKT residual) are then held at their bound by the same steps, :math:`[A; R_a]\\,d =
    -(h, r_a)`, as the second-order correction holds them (:func:`_corrected`): the plain steps
    left them inwards by as much as the endpoint moved, and the KKT residual, which counts the rows
    within 1e-7 of their bound, then read the optimum's gradient unexplained (0.46 where the last
    iterate had 2.6e-4: the falling cat's least :math:`\\int\\tau^2`, ``benchmarks/RESULTS.md``,
    2026-12-06, eighth session). When the held steps do not bring the endpoint within ``tol``, the
    plain ones from ``z``."""
    h, A, _, _ = prob.h(z)
    if WORKING_SOC and ineq is not None and float(np.abs(h).max()) > tol * 1e-2:
        r, R = ineq(z)
        held = _at_bound(r)
        if held.any():
            out = _polish(prob, z, h, A, tol, ineq, held, (r, R))
            if out is not None:
                return out
    return _polish(prob, z, h, A, tol)


def _polish(prob, z, h, A, tol, ineq=None, held=None, rows=None):
    """:func:`polish_endpoint`'s steps from ``z`` (``h``, ``A`` its endpoint residual and Jacobian),
    the rows ``held`` of ``ineq`` held at their bound when given (``rows``: ``ineq(z)``); ``None``
    when those do not bring the endpoint within ``tol``."""

    def stacked(h, A, rows):  # the residual and Jacobian the steps solve: the endpoint's, and the held rows'
        return (h, A) if rows is None else (np.concatenate([h, rows[0][held]]), np.vstack([A, rows[1][held]]))

    res, J = stacked(h, A, rows)
    for _ in range(6):
        if float(np.abs(h).max()) <= tol * 1e-2:
            break
        zt = z - np.linalg.lstsq(J, res, rcond=None)[0]
        try:
            ht, At, _, _ = prob.h(zt)
            rest, Jt = stacked(ht, At, None if ineq is None else ineq(zt))
        except backend.IntegrationError:
            break
        if np.linalg.norm(rest) >= np.linalg.norm(res):
            break
        z, h, res, J = zt, ht, rest, Jt
    if ineq is not None and float(np.abs(h).max()) > tol:
        return None
    return z

