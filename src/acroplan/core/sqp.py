"""The SQP of the optimal strategies (:mod:`~acroplan.core.optimal`), on a problem in reduced
coordinates :math:`z`:

.. math::  \\min_z f(z) \\quad\\text{s.t.}\\quad h(z) = 0 .

A problem gives ``f(z) -> (f, gradient, model Hessian)`` and ``h(z) -> (h, Jacobian, ...)``; the
module docstring of :mod:`~acroplan.core.optimal` describes the method (steps of the KKT system
with the Lagrangian's modelled curvature, the :math:`\\ell_1` merit function, second-order
corrections, the step cap). :func:`kkt_multipliers` gives the least-squares multipliers and the
relative KKT residual the strategies report.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import nnls

from . import backend

__all__ = ["solve_small", "kkt_multipliers", "kkt_step", "sqp", "polish_endpoint", "MAX_REFRESH"]

#: New forward-difference constraint Hessians after a step the model predicted poorly (line
#: search backtracked), at most this many times per solve.
MAX_REFRESH = 3


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
    mu, _ = nnls(P.T @ C.T, -P.T @ g)
    lam = -np.linalg.lstsq(A.T, g + C.T @ mu, rcond=None)[0]
    res = g + A.T @ lam + C.T @ mu
    return lam, (math.sqrt(float(res @ res)) / gn if gn > 0 else 0.0)



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


def sqp(prob, z, Hz, *, tol, kkt_tol, max_iter=40, refresh=None, max_refresh=None):
    """The equality-constrained SQP (module docstring) from ``z`` with constraint Hessians ``Hz``
    (q, Nz, Nz); ``refresh(z)`` gives new ones (forward differences) after a step the model
    predicted poorly. Returns ``(z, info)``."""
    f, g, H = prob.f(z)
    h, A, _, _ = prob.h(z)
    lam, kkt = kkt_multipliers(g, A)
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
        out = kkt_step(W, g, h, A, H)
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
                zc = zt - At.T @ solve_small(At @ At.T, ht)
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
        lam, kkt = kkt_multipliers(g, A)
        if float(s @ s) <= 1e-30 * (1.0 + float(z @ z)):
            break
    return z, dict(lam=lam, kkt=kkt, its=its, why=why)


def polish_endpoint(prob, z, tol):
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

