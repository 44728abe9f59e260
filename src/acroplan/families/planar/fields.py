"""The planar body's momentum map in symbols and numbers: the structure coefficients of a topology,
the compiled (lumped) parameters, the symbolic map per topology, and the map from its definition
(the model is in :mod:`~acroplan.families.planar.model`'s docstring)."""

from __future__ import annotations

import math
import threading
from typing import Hashable

import sympy as sp

from ..tree.topology import relations

__all__ = ["structure_coefficients", "lumped_coefficients", "physical_symbols", "momentum_from_definition"]


_tree = relations


def structure_coefficients(parents, m, inertia, com, joint):
    """The constants :math:`D_{kl}`, :math:`C_{kl}` of the momentum map (module docstring).

    Plain arithmetic on the arguments, so they may be numbers (numeric helpers) or sympy symbols
    (the symbolic fields).

    Parameters
    ----------
    parents : tuple of int, length n
        Parent index per link, -1 for the root.
    m, inertia : sequence, length n
    com, joint : sequence of (x, y) pairs, length n
        ``joint[root]`` is ignored.

    Returns
    -------
    D, C : list of lists, shape (n, n)
        :math:`D` symmetric, :math:`C` antisymmetric.
    """
    n = len(parents)
    children, ancestors, path, subtree = _tree(tuple(parents))
    M = sum(m[1:], m[0])
    S = [sum((m[k] for k in subtree[i][1:]), m[subtree[i][0]]) for i in range(n)]
    g = []
    for k in range(n):
        gx, gy = m[k] * com[k][0], m[k] * com[k][1]
        for h in children[k]:
            gx, gy = gx + S[h] * joint[h][0], gy + S[h] * joint[h][1]
        g.append((gx, gy))
    D = [[0] * n for _ in range(n)]
    C = [[0] * n for _ in range(n)]
    for k in range(n):
        D[k][k] = m[k] * (com[k][0] ** 2 + com[k][1] ** 2) - (g[k][0] ** 2 + g[k][1] ** 2) / M
        for h in children[k]:
            D[k][k] = D[k][k] + S[h] * (joint[h][0] ** 2 + joint[h][1] ** 2)
    for k in range(n):
        for l in range(n):  # noqa: E741
            if k == l:
                continue
            if k in ancestors[l]:  # k a proper ancestor of l: h is the child of k towards l
                h = ancestors[l][ancestors[l].index(k) - 1]
                vx, vy = joint[h][0] - g[k][0] / M, joint[h][1] - g[k][1] / M
                D[k][l] = vx * g[l][0] + vy * g[l][1]
                C[k][l] = vx * g[l][1] - vy * g[l][0]
            elif l in ancestors[k]:
                continue  # filled from (l, k)
            else:
                D[k][l] = -(g[k][0] * g[l][0] + g[k][1] * g[l][1]) / M
                C[k][l] = -(g[k][0] * g[l][1] - g[k][1] * g[l][0]) / M
    for k in range(n):
        for l in range(n):  # noqa: E741
            if l in ancestors[k] and l != k:
                D[k][l] = D[l][k]
                C[k][l] = -C[l][k]
    return D, C


# ---------------------------------------------------------------------- symbols per topology
def _pairs(n):
    return [(k, l) for k in range(n) for l in range(k + 1, n)]  # noqa: E741


def _generic_symbols(parents):
    """The compiled state and parameter symbols; they depend on the topology alone (not on names):
    ``theta, q1, ...`` and ``P0, Ic, Ac1, ..., R_k_l, psi_k_l, ...`` (link indices)."""
    n = len(parents)
    x = (sp.Symbol("theta", real=True),) + tuple(sp.Symbol(f"q{j}", real=True) for j in range(1, n))
    p = [sp.Symbol("P0", real=True), sp.Symbol("Ic", real=True)]
    p += [sp.Symbol(f"Ac{j}", real=True) for j in range(1, n)]
    for k, l in _pairs(n):  # noqa: E741
        p += [sp.Symbol(f"R_{k}_{l}", real=True), sp.Symbol(f"psi_{k}_{l}", real=True)]
    return x, tuple(p)


def physical_symbols(parents):
    """State and *physical* parameter symbols: ``theta, q1, ...`` and ``P0``, then per link (table
    index ``i``) ``m{i}, I{i}, cx{i}, cy{i}`` and, but for the root, ``jx{i}, jy{i}``."""
    n = len(parents)
    x, _ = _generic_symbols(parents)
    p = [sp.Symbol("P0", real=True)]
    for i in range(n):
        p += [sp.Symbol(f"{k}{i}", real=True) for k in ("m", "I", "cx", "cy")]
        if parents[i] != -1:
            p += [sp.Symbol(f"{k}{i}", real=True) for k in ("jx", "jy")]
    return x, tuple(p)


def _unpack(parents, p):
    """(P0, m, I, com, joint) from the physical parameter tuple (symbols or numbers), per link."""
    it = iter(p)
    P0 = next(it)
    m, inertia, com, joint = [], [], [], []
    for i in range(len(parents)):
        m.append(next(it))
        inertia.append(next(it))
        com.append((next(it), next(it)))
        joint.append((next(it), next(it)) if parents[i] != -1 else (0, 0))
    return P0, m, inertia, com, joint


def lumped_coefficients(parents, m, inertia, com, joint, P0, *, symbolic=False):
    """The compiled parameters from the physical ones (module docstring):

    .. math::  I_c = \\sum_l (I_l + D_{ll}),\\quad A_j = \\sum_{l \\in \\mathrm{subtree}(j)} (I_l + D_{ll}),
               \\quad R_{kl} = \\sqrt{D_{kl}^2 + C_{kl}^2},\\quad \\psi_{kl} = \\operatorname{atan2}(C_{kl}, D_{kl}),

    so that :math:`H_{kl} = R_{kl}\\cos(\\beta_l - \\beta_k + \\psi_{kl})`.

    Returns
    -------
    tuple, length 2 + (n - 1) + n (n - 1)
        In :func:`_generic_symbols`' parameter order; floats, or sympy expressions when
        ``symbolic``.
    """
    n = len(parents)
    D, C = structure_coefficients(parents, m, inertia, com, joint)
    _, _, _, subtree = _tree(tuple(parents))
    diag = [inertia[l] + D[l][l] for l in range(n)]  # noqa: E741
    out = [P0, sum(diag[1:], diag[0])]
    for i in range(n):
        if parents[i] != -1:
            out.append(sum((diag[l] for l in subtree[i][1:]), diag[subtree[i][0]]))
    for k, l in _pairs(n):  # noqa: E741
        if symbolic:
            out += [sp.sqrt(D[k][l] ** 2 + C[k][l] ** 2), sp.atan2(C[k][l], D[k][l])]
        else:
            out += [math.hypot(D[k][l], C[k][l]), math.atan2(C[k][l], D[k][l])]
    return tuple(out)


_MAPS: dict[Hashable, tuple] = {}
_LOCK = threading.Lock()


def _symbolic_map(parents, physical=False):
    """(x, p, I, a) in the compiled symbols, or in the physical ones, cached per topology."""
    key = (parents, physical)
    out = _MAPS.get(key)
    if out is None:
        n = len(parents)
        children, ancestors, path, subtree = _tree(parents)
        joints = [i for i in range(n) if parents[i] != -1]
        if physical:
            x, p = physical_symbols(parents)
            _, m, inertia, com, joint = _unpack(parents, p)
            D, C = structure_coefficients(parents, m, inertia, com, joint)
            diag = [inertia[l] + D[l][l] for l in range(n)]  # noqa: E741
            Ic = sp.Add(*diag)
            Ac = [sp.Add(*[diag[l] for l in subtree[i]]) for i in joints]
        else:
            x, p = _generic_symbols(parents)
            Ic, Ac = p[1], p[2:1 + n]
        qsym = {i: x[1 + j] for j, i in enumerate(joints)}
        beta = [sp.Add(*[qsym[k] for k in path[i]]) for i in range(n)]
        H = {}
        for idx, (k, l) in enumerate(_pairs(n)):  # noqa: E741
            d = beta[l] - beta[k]
            if physical:
                H[k, l] = sp.cos(d) * D[k][l] - sp.sin(d) * C[k][l]
            else:
                R, psi = p[1 + n + 2 * idx], p[2 + n + 2 * idx]
                H[k, l] = R * sp.cos(d + psi)
        I = Ic + sp.Add(*[2 * h for h in H.values()])  # noqa: E741
        a = []
        for Aj, i in zip(Ac, joints):
            sub = set(subtree[i])
            a.append(Aj + sp.Add(*[((k in sub) + (l in sub)) * h for (k, l), h in H.items()]))  # noqa: E741
        out = (x, p, I, tuple(a))
        with _LOCK:
            out = _MAPS.setdefault(key, out)
    return out


def momentum_from_definition(body):
    """The angular momentum about the centre of mass, built literally from eq. (1) in sympy.

    Positions :math:`r_i(\\theta, s)` from the link table, :math:`c = \\sum m_i r_i / M`, velocities
    :math:`\\dot r_i = \\partial_\\theta r_i\\,\\dot\\theta + \\sum_j \\partial_{q_j} r_i\\, u_j`, and
    :math:`L = \\sum_i m_i (r_i - c) \\times \\dot r_i + I_i \\dot\\alpha_i`, nothing simplified. It is
    slow (a check, not a model): :class:`PlanarBody` uses the compact form of the module docstring.

    Returns
    -------
    L : sympy.Expr
        In the physical symbols (:func:`physical_symbols`: ``theta, q1, ...``, ``m0, I0, cx0, ...``)
        and the velocity symbols.
    theta_dot : sympy.Symbol
    u : tuple of sympy.Symbol, length n - 1
    """
    parents = body.links.parents
    x, p = physical_symbols(parents)
    _, m, inertia, com, joint = _unpack(parents, p)
    children, ancestors, path, subtree = _tree(parents)
    joints = [i for i in range(len(parents)) if parents[i] != -1]
    qsym = {i: x[1 + j] for j, i in enumerate(joints)}
    theta = x[0]
    n = len(parents)
    alpha = [theta + sum((qsym[k] for k in path[i]), sp.Integer(0)) for i in range(n)]

    def rot(a, v):
        return sp.Matrix([sp.cos(a) * v[0] - sp.sin(a) * v[1], sp.sin(a) * v[0] + sp.cos(a) * v[1]])

    origin = [None] * n
    for i in body.links.topological_order():
        pa = parents[i]
        origin[i] = sp.zeros(2, 1) if pa == -1 else origin[pa] + rot(alpha[pa], joint[i])
    r = [origin[i] + rot(alpha[i], com[i]) for i in range(n)]
    M = sum(m[1:], m[0])
    c = sum((m[i] * r[i] for i in range(1, n)), m[0] * r[0]) / M
    theta_dot = sp.Symbol("theta_dot", real=True)
    u = tuple(sp.Symbol(f"u{j}", real=True) for j in range(1, n))
    coords = [theta] + [x[1 + j] for j in range(n - 1)]
    rates = [theta_dot] + list(u)
    L = sp.Integer(0)
    for i in range(n):
        v = sum((r[i].diff(q) * w for q, w in zip(coords, rates)), sp.zeros(2, 1))
        d = r[i] - c
        adot = sum((w for q, w in zip(coords, rates) if alpha[i].has(q)), sp.Integer(0))
        L += m[i] * (d[0] * v[1] - d[1] * v[0]) + inertia[i] * adot
    return L, theta_dot, u
