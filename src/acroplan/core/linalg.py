"""Small dense linear algebra shared by the solvers: null spaces and damped minimum-norm steps."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["null_space", "damped_step", "norm"]


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
