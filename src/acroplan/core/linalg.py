"""Small dense linear algebra shared by the solvers: null spaces, damped minimum-norm steps, and
the least-norm step under linear inequalities."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["null_space", "damped_step", "norm", "least_norm_step", "least_squares_step"]


def null_space(B: np.ndarray, N: int) -> np.ndarray:
    """An orthonormal basis of :math:`\\ker B`, shape ``(N, N - rank B)`` (SVD, relative rank
    tolerance 1e-12); the identity when ``B`` has no rows."""
    if B.shape[0] == 0:
        return np.eye(N)
    _, s, Vt = np.linalg.svd(B)
    rank = int(np.sum(s > 1e-12 * max(1.0, s[0])))
    return Vt[rank:].T


def norm(v: np.ndarray) -> float:
    """Euclidean norm of a short vector (cheaper than numpy.linalg.norm for the planner's sizes)."""
    return math.sqrt(float(v @ v))


def damped_step(A: np.ndarray, r: np.ndarray, lam_rel: float):
    """The Tikhonov-damped minimum-norm solution of :math:`A\\,dz = r`,
    :math:`dz = V \\operatorname{diag}(s/(s^2 + \\lambda^2)) U^\\top r` with
    :math:`\\lambda = \\lambda_{rel}\\, s_{max}`. Returns ``(dz, singular values)``."""
    U, s, Vt = np.linalg.svd(A, full_matrices=False)
    lam = lam_rel * (s[0] if s.size else 1.0)
    filt = s / (s * s + lam * lam)
    return Vt.T @ (filt * (U.T @ r)), s


def least_norm_step(J: np.ndarray, r: np.ndarray, G: np.ndarray, h: np.ndarray):
    """The shortest step :math:`d` with :math:`J d = r` and :math:`G d \\le h` (a least-distance
    program, for the planners' small problems: a few equations, a few dozen unknowns, hundreds of
    inequalities of which a handful are active).

    .. math::  \\min_d\\ \\|d\\| \\quad\\text{s.t.}\\quad J d = r,\\quad G d \\le h .

    The equations are eliminated, :math:`d = d_0 + N y` (:math:`d_0 = J^+ r`, :math:`N` an
    orthonormal basis of :math:`\\ker J`, so :math:`\\|d\\|^2 = \\|d_0\\|^2 + \\|y\\|^2`), and the
    least-distance program :math:`\\min \\|y\\|` s.t. :math:`E y \\ge e` (:math:`E = -G N`,
    :math:`e = G d_0 - h`) is solved by non-negative least squares (Lawson and Hanson, *Solving
    Least Squares Problems*, 1974, ch. 23): with :math:`u \\ge 0` minimising
    :math:`\\|[E^\\top; e^\\top] u - (0, \\dots, 0, 1)\\|` and :math:`\\rho` that residual,
    :math:`y = -\\rho_{1..}/\\rho_{last}`; :math:`\\rho = 0` means no step satisfies the
    inequalities.

    Parameters
    ----------
    J : numpy.ndarray, shape (k, p)
    r : numpy.ndarray, shape (k,)
    G : numpy.ndarray, shape (q, p)
    h : numpy.ndarray, shape (q,)

    Returns
    -------
    (d, feasible) : (numpy.ndarray of shape (p,), bool)
        ``feasible`` false: no step meets the inequalities and :math:`J d = r`; ``d`` is then the
        minimum-norm solution of :math:`J d = r` alone.
    """
    p = J.shape[1]
    d0 = np.linalg.lstsq(J, r, rcond=1e-12)[0] if J.shape[0] else np.zeros(p)
    if G.shape[0] == 0 or np.all(G @ d0 <= h):
        return d0, True
    from scipy.optimize import nnls  # here: scipy.optimize takes 0.2-0.3 s to import, and most steps need none
    N = null_space(J, p) if J.shape[0] else None  # None: no equations, y = d
    if N is not None and N.shape[1] == 0:
        return d0, False
    E = -G if N is None else -G @ N
    e = G @ d0 - h
    A = np.vstack([E.T, e[None, :]])
    f = np.zeros(A.shape[0])
    f[-1] = 1.0
    try:
        u, _ = nnls(A, f, maxiter=50 * A.shape[1])
    except RuntimeError:
        return d0, False
    rho = A @ u - f
    if abs(rho[-1]) <= 1e-12:
        return d0, False
    y = -rho[:-1] / rho[-1]
    d = d0 + (y if N is None else N @ y)
    scale = 1.0 + float(np.abs(h).max())
    return d, bool(np.max(G @ d - h) <= 1e-9 * scale)


def least_squares_step(J: np.ndarray, r: np.ndarray, G: np.ndarray, h: np.ndarray, damping: float = 1e-3):
    """The step that comes closest to :math:`J d = r` under :math:`G d \\le h`, damped:

    .. math::  \\min_d\\ \\|J d - r\\|^2 + \\mu^2 \\|d\\|^2 \\quad\\text{s.t.}\\quad G d \\le h ,

    :math:`\\mu = ` ``damping`` times the largest singular value of :math:`J`. With the QR
    factorisation :math:`[J; \\mu 1] = Q R` and :math:`y = R d - Q^\\top (r, 0)` it is the
    least-distance program :math:`\\min\\|y\\|` s.t. :math:`G R^{-1} y \\le h - G R^{-1} Q^\\top (r, 0)`
    (:func:`least_norm_step` with no equations; Lawson and Hanson's reduction of LSI to LDP).

    Returns
    -------
    (d, feasible) : (numpy.ndarray of shape (p,), bool)
    """
    p = J.shape[1]
    mu = damping * (float(np.linalg.norm(J, 2)) if J.size else 1.0)
    E = np.vstack([J, mu * np.eye(p)])
    f = np.concatenate([r, np.zeros(p)])
    Q, R = np.linalg.qr(E)
    g = Q.T @ f
    Ri = np.linalg.inv(R)
    y, ok = least_norm_step(np.zeros((0, p)), np.zeros(0), G @ Ri, h - G @ (Ri @ g))
    return Ri @ (y + g), ok
