"""The pieces of the spatial collocation (:mod:`~acroplan.families.spatial.collocation`) that know
no segment: the vectorised quaternion algebra of the attitude's kinematics, the dyadic panel
layout's tables, and the small linear algebra of its blocks (the collocation matrices, skew
matrices, rotations of vectors)."""

from __future__ import annotations

import functools
import math

import numpy as np

from ...core.backend import IntegrationError

#: Gauss-Legendre nodes per panel (the collocation method has order 2 NODES)
NODES = 16
#: the largest Legendre tail (rad) of a kept panel (module docstring). The endpoint error goes as
#: its square or below: over 150 random segments of 3-5 links (L = 0 and L != 0, 10 coefficients,
#: motions to three times the zoo's) against the long-double reference the largest error was
#: 5.6e-14 at 1e-8, 5.3e-14 at 1e-7 and at 1e-6 (the reference's own floor), with 10.7, 9.0 and 7.5
#: panels on average (``benchmarks/RESULTS.md``); 1e-7 keeps the estimate 1e-14, a hundredth of the
#: 1e-12 every endpoint must meet
TAIL_TOL = 1e-7
#: the largest tail of the solution's own rates (:math:`H\\lambda'/|L|`, :math:`H q'`) after the solve: a
#: safety net for the attitude's resolution (those rates' tails follow the data's within a factor
#: of about two)
SOLUTION_TAIL_TOL = 10 * TAIL_TOL
#: the most panels one segment may take (a wild input, as the Taylor integrator's step limit)
MAX_PANELS = 2048
#: the shortest panel (normalised time)
MIN_PANEL = 1e-7
#: the largest turn of the root by the shape's motion on one panel (rad), :math:`H \\max|\\omega|`
MAX_TURN = 3.0
#: the layout's bisection (:func:`_layout`) evaluates its first levels, the panels of 1/2 down to
#: ``2 ** -FIRST_LEVELS`` of the segment, in one call of the compiled map, and keeps the same panels
#: as level by level (a panel's node data depend on the panel alone): 30 panels where the falling
#: cat's optimum needed 26 of them evaluated in 3.7 calls, one call instead (the endpoint 1.2 times
#: faster there: ``benchmarks/RESULTS.md``, 2026-12-06, eighth session)
FIRST_LEVELS = 4
#: Newton iterations per panel before it is split
NEWTON_ITERATIONS = 12
#: Newton stops after a step this small (the next would be about its square)
NEWTON_TOL = 1e-8

_SYM = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
_FULL = np.array([[0, 1, 2], [1, 3, 4], [2, 4, 5]])


# ---------------------------------------------------------------------- Gauss tables
@functools.cache
def _gauss(N: int):
    """Nodes ``g`` on [0, 1], weights ``b``, the collocation matrix ``a`` (:math:`\\alpha_{ij} =
    \\int_0^{g_i} \\ell_j`) and ``Vi`` (nodal values to Legendre coefficients on the panel)."""
    x, w = np.polynomial.legendre.leggauss(N)
    g, b = (x + 1.0) / 2.0, w / 2.0
    V = np.polynomial.legendre.legvander(x, N - 1)
    Vi = np.linalg.inv(V)
    Q = np.polynomial.legendre.legint(np.eye(N), lbnd=-1.0, scl=0.5, axis=0)
    a = (np.polynomial.legendre.legvander(x, N) @ Q) @ Vi
    for t in (g, b, a, Vi):
        t.setflags(write=False)
    return g, b, a, Vi


# ---------------------------------------------------------------------- quaternion algebra, vectorised
def _tensors():
    """Constant tensors: ``RIGHT[k]`` the matrix of :math:`q \\mapsto \\tfrac12 q \\otimes (0, e_k)`,
    ``XI[a]`` the part of :math:`\\tfrac12 \\Xi(q)` linear in :math:`q_a`, ``LEFT[a]`` that of
    :math:`p \\mapsto q \\otimes p`, ``RIGHTQ[a]`` that of :math:`p \\mapsto p \\otimes q`, and ``QUAD[i, l]`` the symmetric matrices with
    :math:`(R(q)^\\top L)_i = \\sum_l L_l\\, q^\\top Q_{il}\\, q`."""
    E = np.eye(4)

    def qm(a, b):
        return _qmul(a, b)

    RIGHT = np.zeros((3, 4, 4))
    XI = np.zeros((4, 4, 3))
    LEFT = np.zeros((4, 4, 4))
    for k in range(3):
        v = np.zeros(4)
        v[k + 1] = 1.0
        for b in range(4):
            RIGHT[k][:, b] = 0.5 * qm(E[b], v)
            XI[b][:, k] = 0.5 * qm(E[b], v)
    for a in range(4):
        for b in range(4):
            LEFT[a][:, b] = qm(E[a], E[b])
    QUAD = np.zeros((3, 3, 4, 4))
    for a in range(4):
        for b in range(4):
            qa, qb = E[a], E[b]
            # R(q)^T L = vec(q^* (0, L) q), bilinear in (q, q): symmetrise
            for l in range(3):  # noqa: E741
                Lv = np.zeros(4)
                Lv[l + 1] = 1.0
                val = qm(qm(np.array([qa[0], -qa[1], -qa[2], -qa[3]]), Lv), qb)[1:]
                QUAD[:, l, a, b] += 0.5 * val
                QUAD[:, l, b, a] += 0.5 * val
    RIGHTQ = np.zeros((4, 4, 4))
    for a in range(4):
        for b in range(4):
            RIGHTQ[a][:, b] = qm(E[b], E[a])
    for t in (RIGHT, XI, LEFT, QUAD, RIGHTQ):
        t.setflags(write=False)
    return RIGHT, XI, LEFT, QUAD, RIGHTQ


def _qmul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw])


_RIGHT, _XI, _LEFT, _QUAD, _RIGHTQ = _tensors()


def _right(w):
    """The matrices of :math:`q \\mapsto \\tfrac12 q \\otimes (0, w)`, shape (..., 4, 4)."""
    return (w @ _RIGHT.reshape(3, 16)).reshape(w.shape[:-1] + (4, 4))


def _xi(q):
    """:math:`\\tfrac12 \\Xi(q)`, :math:`\\Xi(q) v = q \\otimes (0, v)`, shape (..., 4, 3)."""
    return (q @ _XI.reshape(4, 12)).reshape(q.shape[:-1] + (4, 3))


def _left(q):
    """The matrix of :math:`p \\mapsto q \\otimes p`, shape (..., 4, 4)."""
    return (q @ _LEFT.reshape(4, 16)).reshape(q.shape[:-1] + (4, 4))


def _rightq(q):
    """The matrix of :math:`p \\mapsto p \\otimes q`, shape (..., 4, 4)."""
    return (q @ _RIGHTQ.reshape(4, 16)).reshape(q.shape[:-1] + (4, 4))


def _quad(L):
    """:math:`Q(L) = \\sum_l L_l Q_{il}`, shape (3, 4, 4): :math:`R(q)^\\top L = (q^\\top Q_i q)_i`
    (the quadratic form of the model's fields, also off the unit sphere)."""
    return np.einsum("l,ilab->iab", np.asarray(L, dtype=float), _QUAD)


@functools.lru_cache(maxsize=64)
def _dyadic_tables(basis, N: int, depth: int):
    """The basis and its integrals at the Gauss nodes of every panel of width :math:`2^{-d}`:
    arrays (2^d, N, n), cached (the layout's panels are all dyadic)."""
    K = 2 ** depth
    g = _gauss(N)[0]
    sig = ((np.arange(K)[:, None] + g[None, :]) / K).ravel()
    out = (basis.matrix(sig).reshape(K, N, -1), basis.integral(sig).reshape(K, N, -1))
    for t in out:
        t.setflags(write=False)
    return out


@functools.lru_cache(maxsize=64)
def _level_tables(basis, N: int, depth: int):
    """:func:`_dyadic_tables` of levels 1 .. ``depth`` one after the other (the panels of
    :func:`_level_grid`), shape (P N, n) each, read-only."""
    out = tuple(np.concatenate([_dyadic_tables(basis, N, lv)[i].reshape(-1, basis.n) for lv in range(1, depth + 1)])
                for i in range(2))
    for t in out:
        t.setflags(write=False)
    return out


def _basis_at(basis, N, starts, widths):
    """``(B, Bi)`` of shape (P N, n): the basis and its integrals at the nodes of the panels, from
    the dyadic tables (:func:`_dyadic_tables`) when every panel is dyadic, depth by depth."""
    w0 = float(widths[0])
    if (widths == w0).all():  # one width: one table, when it is dyadic
        d0 = round(-math.log2(w0)) if w0 > 0.0 else 99
        if d0 <= 10 and w0 == 2.0 ** -d0:
            k = np.rint(starts * 2.0 ** d0).astype(int)
            Bm, Bi = _dyadic_tables(basis, N, d0)
            return Bm[k].reshape(k.size * N, -1), Bi[k].reshape(k.size * N, -1)
    depth = np.rint(-np.log2(widths)).astype(int)
    if depth.max() <= 10 and np.all(widths == 2.0 ** -depth):
        levels = np.unique(depth)
        Bm = np.empty((starts.size, N, basis.n))
        Bi = np.empty((starts.size, N, basis.n))
        for lv in levels:
            at = depth == lv
            k = np.rint(starts[at] * 2.0 ** lv).astype(int)
            tm, ti = _dyadic_tables(basis, N, int(lv))
            Bm[at], Bi[at] = tm[k], ti[k]
        return Bm.reshape(-1, basis.n), Bi.reshape(-1, basis.n)
    sig = (starts[:, None] + widths[:, None] * _gauss(N)[0][None, :]).ravel()
    return basis.matrix(sig), basis.integral(sig)


def _take(d, idx):
    return {k: v[idx] for k, v in d.items()}


def _cat(parts):
    return {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}


def _split(starts, widths, d, bad, seg, kept_count=0):
    """Halve the panels ``bad`` (a boolean mask): starts, widths and node data of the new panels."""
    h = widths[bad] / 2.0
    if h.size and (h.min() < MIN_PANEL or kept_count + 2 * h.size > MAX_PANELS):
        raise IntegrationError(f"the input is too large to integrate: more than {MAX_PANELS} panels on one "
                               f"segment")
    st = np.concatenate([starts[bad], starts[bad] + h])
    wd = np.concatenate([h, h])
    return st, wd


def _layout(seg, starts=None, widths=None, kept=None):
    """The panels (module docstring): starts, widths, node data, sorted by start. Bisection of
    ``starts, widths`` (default: the two halves of the segment, their first :data:`FIRST_LEVELS`
    levels evaluated at once, :func:`_first_levels`), keeping the panels ``kept``
    (``(starts, widths, data)``) as they are."""
    kept = list(kept or [])
    if starts is None:
        kept, starts, widths = _first_levels(seg)
    while starts.size:
        d = seg.data(starts, widths)
        ok = _resolved(seg, d, widths)
        if ok.any():
            kept.append((starts[ok], widths[ok], _take(d, ok)))
        if ok.all():
            break
        starts, widths = _split(starts, widths, d, ~ok, seg, sum(k[0].size for k in kept))
    st = np.concatenate([k[0] for k in kept])
    wd = np.concatenate([k[1] for k in kept])
    d = _cat([k[2] for k in kept])
    order = np.argsort(st, kind="stable")
    return st[order], wd[order], _take(d, order)


def _resolved(seg, d, widths):
    """The panels whose node data ``d`` pass the layout's tests (module docstring: the tails of
    :math:`H\\omega` and :math:`H|L|W` at most :data:`TAIL_TOL`, the turn at most :data:`MAX_TURN`)."""
    vals = d["w"]
    if seg.drift:
        vals = np.concatenate([vals, seg.Lnorm * d["W"].reshape(vals.shape[:2] + (9,))], axis=2)
    turn = widths * np.sqrt((d["w"] * d["w"]).sum(axis=2).max(axis=1))
    return (seg.tails(vals, widths) <= TAIL_TOL) & (turn <= MAX_TURN)


@functools.cache
def _level_grid(depth: int):
    """The dyadic panels of levels 1 .. ``depth`` one level after the other: ``(starts, widths,
    parent, levels)``, ``parent`` the index of each panel's parent (-1 on level 1), ``levels`` the
    slices of the levels."""
    st, wd, par, levels, off = [], [], [], [], 0
    for lv in range(1, depth + 1):
        K = 2 ** lv
        st.append(np.arange(K) / K)
        wd.append(np.full(K, 1.0 / K))
        par.append(np.full(K, -1) if lv == 1 else off - K // 2 + np.arange(K) // 2)
        levels.append(slice(off, off + K))
        off += K
    out = (np.concatenate(st), np.concatenate(wd), np.concatenate(par), tuple(levels))
    for a in out[:3]:
        a.setflags(write=False)
    return out


def _first_levels(seg):
    """The bisection's first :data:`FIRST_LEVELS` levels at once: every panel of those levels
    evaluated in one call (:meth:`_Segment.data`), a panel kept when it passes the tests
    (:func:`_resolved`) and no panel above it did, as level by level. Returns ``(kept, starts,
    widths)``: the kept panels as :func:`_layout` holds them, and the children of the last level's
    panels that fail (to bisect on)."""
    st, wd, parent, levels = _level_grid(FIRST_LEVELS)
    d = seg.data(st, wd, _level_tables(seg.basis, seg.N, FIRST_LEVELS))
    ok = _resolved(seg, d, wd)
    alive = np.zeros(st.size, dtype=bool)  # every panel above failed
    alive[levels[0]] = True
    for lv in levels[1:]:
        p = parent[lv]
        alive[lv] = alive[p] & ~ok[p]
    keep = np.flatnonzero(alive & ok)
    kept = [(st[keep], wd[keep], _take(d, keep))] if keep.size else []
    last = np.zeros(st.size, dtype=bool)
    last[levels[-1]] = True
    bad = alive & ~ok & last
    return (kept,) + (_split(st, wd, d, bad, seg, keep.size) if bad.any() else (st[:0], wd[:0]))


def _blocks(seg, widths, J):
    """``S = 1 - H (alpha (x) 1) diag_j(J_j)`` of every panel, from blocks ``J`` (P, N, k, k)."""
    P, N, k = J.shape[0], J.shape[1], J.shape[2]
    S = (seg.a[None, :, None, :, None] * (-widths[:, None, None, None, None] * np.swapaxes(J, 1, 2)[:, None]))
    S = S.reshape(P, N * k, N * k)
    S[:, _diag(N * k), _diag(N * k)] += 1.0
    return S


@functools.cache
def _diag(n):
    return np.arange(n)


def _skew(v):
    """:math:`[v]_\\times`, shape (..., 3, 3)."""
    return (v @ _E2).reshape(v.shape[:-1] + (3, 3))


_EPS = np.zeros((3, 3, 3))
for _i, _j, _k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
    _EPS[_k, _i, _j], _EPS[_k, _j, _i] = -1.0, 1.0  # [v]x[i, j] = -eps_ijk v_k
_EPS.setflags(write=False)
_E2 = _EPS.reshape(3, 9)
