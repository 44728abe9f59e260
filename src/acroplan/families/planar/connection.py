"""The momentum connection of a planar body, fast and in bulk; its curvature; a safe bound on the turn rate.

With the momentum map :math:`L = I(s)\\dot\\theta + a(s)\\cdot u = P_0`
(:mod:`~acroplan.families.planar.model`) the root turns at

.. math::  \\dot\\theta = \\frac{P_0}{I(s)} - \\mathcal{A}(s)\\cdot\\dot s ,\\qquad
           \\mathcal{A}(s) = \\frac{a(s)}{I(s)} ,

:math:`\\mathcal{A}` the *momentum connection* (a one-form on shape space). Along a shape path
:math:`s(\\sigma)`, :math:`\\sigma \\in [0, 1]`, traversed in time :math:`T`,

.. math::  \\theta(T) - \\theta(0) = \\int_0^1 \\frac{T P_0 - a(s)\\cdot s'}{I(s)}\\,d\\sigma .  \\qquad (1)

At :math:`P_0 = 0` only the path's geometry counts, and for a **closed** loop :math:`\\gamma` in
the plane of joints :math:`(q_i, q_j)` Stokes' theorem turns the line integral into an area integral
of the *curvature* :math:`F_{ij} = \\partial_i \\mathcal{A}_j - \\partial_j \\mathcal{A}_i`:

.. math::  \\Delta\\theta = -\\oint_\\gamma \\mathcal{A}\\cdot ds = -\\iint_{\\Omega} F_{ij}\\,dq_i\\,dq_j ,
           \\qquad (2)

:math:`\\Omega` the region the loop encloses (counter-clockwise positive). A small loop of area
:math:`|\\Omega|` at shape :math:`s^*` turns the body by about :math:`-F_{ij}(s^*)\\,|\\Omega|`:
loops go where :math:`|F|` is large (:func:`curvature`).

:class:`Connection` evaluates :math:`I` and :math:`a` at many shapes at once in the lumped form
:math:`H_{kl} = R_{kl}\\cos(\\beta_l - \\beta_k + \\psi_{kl})` (one cosine per pair of links), for the
guesses of :mod:`~acroplan.families.planar.guess`; :func:`turn_bound` bounds
:math:`|\\theta(T) - \\theta(0)|` under rate limits by interval arithmetic.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["Connection", "curvature", "turn_bound", "cos_range"]


class Connection:
    """:math:`I(s)`, :math:`a(s)` of one body at many shapes (lumped form, module docstring).

    Parameters
    ----------
    body : PlanarBody

    Attributes
    ----------
    Ic : float
        Constant part of :math:`I`.
    Ac : numpy.ndarray, shape (m,)
        Constant parts of :math:`a_j`.
    R, psi : numpy.ndarray, shape (p,)
        Per pair of links :math:`k < l`: :math:`H_{kl} = R \\cos(d_{kl} + \\psi)`.
    Dq : numpy.ndarray, shape (p, m)
        :math:`d_{kl} = \\beta_l - \\beta_k = D_q\\,s` (entries -1, 0, 1).
    W : numpy.ndarray, shape (m, p)
        :math:`a_j = A_j + \\sum_{kl} W_{j,kl} H_{kl}` (how many of :math:`k, l` joint :math:`j` moves).
    link_inertia : float
        :math:`\\sum_i I_i`, a lower bound of :math:`I(s)` at every shape.
    """

    def __init__(self, body):
        L = body.links
        n = len(L)
        m = n - 1
        vals = body._param_tuple
        self.P0 = float(vals[0])
        self.Ic = float(vals[1])
        self.Ac = np.array(vals[2:2 + m], dtype=float)
        pairs = [(k, l) for k in range(n) for l in range(k + 1, n)]  # noqa: E741
        self.R = np.array(vals[2 + m::2], dtype=float)
        self.psi = np.array(vals[3 + m::2], dtype=float)
        P = np.zeros((n, m))  # beta = P s
        for i in range(n):
            for k in L.path(i):
                P[i, L.joints.index(k)] = 1.0
        self.Dq = np.array([P[l] - P[k] for k, l in pairs]).reshape(len(pairs), m)  # noqa: E741
        self.W = np.zeros((m, len(pairs)))
        for j, i in enumerate(L.joints):
            sub = set(L.subtree(i))
            for p_, (k, l) in enumerate(pairs):  # noqa: E741
                self.W[j, p_] = (k in sub) + (l in sub)
        self.m = m
        self._psi, self._R, self._Ac = self.psi[:, None], self.R[:, None], self.Ac[:, None]
        self.link_inertia = float(sum(link.inertia for link in L))

    def __call__(self, S):
        """``(I, a)`` at shapes ``S`` of shape ``(m, ...)``: ``I`` of shape ``(...)``, ``a`` of ``(m, ...)``."""
        S = np.asarray(S, dtype=float)
        rest = S.shape[1:]
        S2 = S.reshape(self.m, -1)
        H = np.cos(self.Dq @ S2 + self._psi)
        H *= self._R
        I = self.Ic + 2.0 * H.sum(axis=0)  # noqa: E741
        a = self.W @ H
        a += self._Ac
        return I.reshape(rest), a.reshape((self.m,) + rest)

    def one_form(self, S):
        """The connection :math:`\\mathcal{A} = a/I` at shapes ``S`` (``(m, ...)``)."""
        I, a = self(S)  # noqa: E741
        return a / I


def curvature(conn: Connection, S, i: int, j: int, h: float = 1e-4):
    """:math:`F_{ij} = \\partial_i \\mathcal{A}_j - \\partial_j \\mathcal{A}_i` at shapes ``S`` (``(m, ...)``),
    by central differences of step ``h`` (relative error about :math:`h^2`; for ranking placements).

    Returns
    -------
    numpy.ndarray, shape (...)
    """
    S = np.asarray(S, dtype=float)
    ei = np.zeros(conn.m)
    ej = np.zeros(conn.m)
    ei[i] = h
    ej[j] = h
    sh = (-1,) + (1,) * (S.ndim - 1)
    dAj_di = (conn.one_form(S + ei.reshape(sh))[j] - conn.one_form(S - ei.reshape(sh))[j]) / (2 * h)
    dAi_dj = (conn.one_form(S + ej.reshape(sh))[i] - conn.one_form(S - ej.reshape(sh))[i]) / (2 * h)
    return dAj_di - dAi_dj


def cos_range(lo, hi):
    """A safe enclosure ``(cmin, cmax)`` of :math:`\\cos` on each interval :math:`[lo, hi]` (arrays).

    Exact extremes (the ends, and the multiples of :math:`\\pi` inside), widened outwards by
    :math:`4\\cdot 10^{-16}` plus 2 ulp of the argument's size for the rounding of ``cos`` and of the
    interval ends; an infinite or longer-than-:math:`2\\pi` interval gives :math:`[-1, 1]`.
    """
    lo = np.atleast_1d(np.asarray(lo, dtype=float))
    hi = np.atleast_1d(np.asarray(hi, dtype=float))
    cmin = np.full(lo.shape, -1.0)
    cmax = np.full(lo.shape, 1.0)
    fin = np.isfinite(lo) & np.isfinite(hi) & (hi - lo < 2 * math.pi)
    if fin.any():
        a, b = lo[fin], hi[fin]
        ca, cb = np.cos(a), np.cos(b)
        pad = 4e-16 + 4.5e-16 * np.maximum(np.abs(a), np.abs(b))
        lo_v = np.minimum(ca, cb) - pad
        hi_v = np.maximum(ca, cb) + pad
        # an even multiple of pi inside gives the max 1, an odd one the min -1
        k_even = np.ceil(a / (2 * math.pi) - 1e-15)
        has_max = 2 * math.pi * k_even <= b * (1 + 1e-15) + 1e-15
        k_odd = np.ceil((a - math.pi) / (2 * math.pi) - 1e-15)
        has_min = 2 * math.pi * k_odd + math.pi <= b * (1 + 1e-15) + 1e-15
        hi_v = np.where(has_max, 1.0, hi_v)
        lo_v = np.where(has_min, -1.0, lo_v)
        cmin[fin] = np.maximum(lo_v, -1.0)
        cmax[fin] = np.minimum(hi_v, 1.0)
    return cmin, cmax


def _box_bounds(conn: Connection, qlo, qhi):
    """Safe ``(I_min, a_abs_max)`` over joint boxes ``[qlo, qhi]`` (arrays ``(K, m)``, may be infinite):
    shapes ``(K,)`` and ``(K, m)``."""
    qlo = np.atleast_2d(np.asarray(qlo, dtype=float))
    qhi = np.atleast_2d(np.asarray(qhi, dtype=float))
    pos, neg = np.clip(conn.Dq, 0, None), np.clip(-conn.Dq, 0, None)  # (p, m)
    with np.errstate(invalid="ignore"):  # 0 * inf for joints a pair does not involve
        lo_p = np.where(pos[None] > 0, pos[None] * qlo[:, None, :], 0.0).sum(axis=2)
        lo_n = np.where(neg[None] > 0, neg[None] * qhi[:, None, :], 0.0).sum(axis=2)
        hi_p = np.where(pos[None] > 0, pos[None] * qhi[:, None, :], 0.0).sum(axis=2)
        hi_n = np.where(neg[None] > 0, neg[None] * qlo[:, None, :], 0.0).sum(axis=2)
    dlo, dhi = lo_p - lo_n, hi_p - hi_n  # (K, p)
    cmin, cmax = cos_range((dlo + conn.psi).ravel(), (dhi + conn.psi).ravel())
    R = conn.R
    Hlo, Hhi = R * cmin.reshape(dlo.shape), R * cmax.reshape(dlo.shape)  # R >= 0
    I_min = conn.Ic + 2.0 * Hlo.sum(axis=1)
    I_min = np.maximum(I_min * (1 - 1e-14) - 1e-14 * (conn.Ic + 2 * R.sum()), conn.link_inertia * (1 - 1e-15))
    W = conn.W
    a_lo = conn.Ac + Hlo @ W.T  # W >= 0
    a_hi = conn.Ac + Hhi @ W.T
    slack = 1e-14 * (np.abs(conn.Ac) + W @ R)
    a_max = np.maximum(np.abs(a_lo), np.abs(a_hi)) * (1 + 1e-14) + slack
    return I_min, a_max


def turn_bound(conn: Connection, q0, qT, T: float, rate, lower=None, upper=None, pieces: int = 32) -> float:
    """A proven upper bound of :math:`|\\theta(T) - \\theta(0)|` under rate limits.

    .. math::  |\\dot\\theta| \\le \\frac{|P_0| + \\sum_j \\max_s |a_j(s)|\\,\\bar u_j}{\\min_s I(s)}

    with the maximum and minimum taken over the shapes the joints can occupy: at time :math:`t`
    joint :math:`j` lies in :math:`[q_{j,0} - \\bar u_j t,\\ q_{j,0} + \\bar u_j t] \\cap
    [q_{j,T} - \\bar u_j (T - t),\\ q_{j,T} + \\bar u_j (T - t)] \\cap [lo_j, hi_j]`. The segment is
    cut into ``pieces`` equal times; on each the box is the union of those boxes, the extremes of
    :math:`I` and :math:`a_j` over it are enclosed by interval arithmetic on the cosine sums
    (:func:`cos_range`, never sampled), and the bound is their time integral. :math:`I` is never
    bounded below by less than :math:`\\sum_i I_i > 0`.

    Parameters
    ----------
    conn : Connection
    q0, qT : array_like, shape (m,)
        The joint angles at the segment's ends.
    T : float
    rate : array_like, shape (m,)
        :math:`\\bar u_j` (finite, > 0).
    lower, upper : array_like, shape (m,), optional
        Joint limits (infinite where none).
    pieces : int

    Returns
    -------
    float
        The bound (``inf`` when a rate limit is not finite).
    """
    q0 = np.asarray(q0, dtype=float)
    qT = np.asarray(qT, dtype=float)
    U = np.asarray(rate, dtype=float)
    if not np.all(np.isfinite(U)):
        return math.inf
    lo = np.full(q0.shape, -math.inf) if lower is None else np.asarray(lower, dtype=float)
    hi = np.full(q0.shape, math.inf) if upper is None else np.asarray(upper, dtype=float)
    T = float(T)
    edges = np.linspace(0.0, T, pieces + 1)
    t_a, t_b = edges[:-1, None], edges[1:, None]
    # the union over t in [t_a, t_b] of the reachable boxes (each end moves monotonically in t)
    up = np.minimum(q0 + U * t_b, qT + U * (T - t_a))
    dn = np.maximum(q0 - U * t_b, qT - U * (T - t_a))
    box_lo, box_hi = np.maximum(dn, lo), np.minimum(up, hi)
    box_lo, box_hi = np.minimum(box_lo, box_hi), np.maximum(box_lo, box_hi)
    I_min, a_max = _box_bounds(conn, box_lo, box_hi)
    rates = (abs(conn.P0) + a_max @ U) / I_min
    return float(rates.sum() * (T / pieces)) * (1 + 1e-13)
