"""What the first guesses of tree bodies share (planar and spatial shape loops): the 64-node
Gauss-Legendre rule on :math:`\\sigma \\in [0, 1]` the guesses are evaluated on, the projection of
values at those nodes onto an input basis, and the lowest-degree joint motion that meets the
segment's ends and its input conditions."""

from __future__ import annotations

import functools

import numpy as np

from ...core.conditions import hermite_inverse

__all__ = ["GAUSS_S", "GAUSS_W", "END_KEYS", "projector", "base_motion"]

_XG, _WG = np.polynomial.legendre.leggauss(64)
#: the 64 Gauss-Legendre nodes on [0, 1] and their weights (sum 1)
GAUSS_S, GAUSS_W = (_XG + 1) / 2, _WG / 2
GAUSS_S.flags.writeable = False
GAUSS_W.flags.writeable = False
#: the input conditions a joint motion may have to meet at the segment's ends
END_KEYS = ("u0", "du0", "uT", "duT")


@functools.lru_cache(maxsize=64)
def projector(basis_cls, n: int) -> np.ndarray:
    """Least-squares projection of values at the 64 nodes onto the basis of ``n`` (exact below degree n).

    Returns
    -------
    numpy.ndarray, shape (n, 64), read only
    """
    P = np.linalg.pinv(basis_cls(n).matrix(GAUSS_S))
    P.flags.writeable = False
    return P


def base_motion(q0, qT, T: float, ends: dict):
    """Power coefficients in :math:`\\sigma` of the lowest-degree joint motions meeting the ends and
    the conditions (``ends`` as :meth:`acroplan.core.conditions.Conditions.ends` gives them).

    Returns
    -------
    numpy.ndarray, shape (m, 2 + number of conditions)
    """
    keys = tuple(k for k in END_KEYS if k in ends)
    q0 = np.asarray(q0, dtype=float)
    qT = np.asarray(qT, dtype=float)
    if not keys:
        return np.stack([q0, qT - q0], axis=1)
    scale = {"u0": T, "du0": T * T, "uT": T, "duT": T * T}
    rhs = np.stack([q0, qT] + [scale[k] * np.asarray(ends[k], dtype=float) for k in keys], axis=1)
    return rhs @ hermite_inverse(keys, 1 + len(keys)).T
