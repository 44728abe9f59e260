"""The joint torques of a free-flying tree in closed form: a Newton-Euler recursion in the root's
frame, written once over scalars and compiled (a ``heyoka.cfunc`` per topology), with its exact
partial derivatives.

The torques of a free body (no external force or torque, no gravity) depend on the shape
:math:`s`, the joint rates :math:`u`, their rates :math:`\\dot u` and the angular momentum in the
root's frame, :math:`\\lambda = R(q)^\\top L`, alone (:mod:`~acroplan.families.spatial.effort`): turning
the whole body changes nothing else. So :func:`joint_torques` is a function of :math:`(s, u, \\dot u,
\\lambda)` per instant, evaluated at many instants at once, and its Jacobian in those
:math:`3m + 3` arguments comes with it (heyoka's ``diff_tensors``, forward mode).

The recursion
-------------
Everything is written in the root's frame at the instant (an inertial frame that coincides with it
then), with the root's frame origin as the reference point. Links are visited parents first; link
:math:`l` hangs from :math:`p` on its joint at :math:`j_l` (parent frame) about :math:`a_l` (parent
frame), with the constant turn :math:`R^0_l`:

.. math::  R_l = R_p\\,\\mathrm{Rot}(a_l, s_l)\\,R^0_l ,\\qquad P_l = P_p + R_p j_l ,\\qquad
           \\hat a_l = R_p a_l ,\\qquad r_l = P_l + R_l c_l ,

(:math:`R_{root} = \\mathbb{1}`, :math:`P_{root} = 0`, :math:`c_l` the centre of mass in the link's
frame), :math:`\\rho_l = r_l - r_c` from the centre of mass :math:`r_c = \\sum m_l r_l / M` and
:math:`J_l = R_l J^0_l R_l^\\top`. Velocities, with the root's angular velocity :math:`\\Omega`:

.. math::  \\omega_l = \\omega_p + \\hat a_l u_l ,\\qquad \\dot P_l = \\dot P_p + \\omega_p \\times R_p j_l ,
           \\qquad \\dot r_l = \\dot P_l + \\omega_l \\times R_l c_l ,\\qquad \\dot\\rho_l = \\dot r_l - \\dot r_c ;

the momentum about the centre of mass :math:`h = \\sum_l J_l \\omega_l + m_l \\rho_l \\times \\dot\\rho_l
= \\mathbb{I}\\,\\Omega + h^0` (:math:`h^0` the same sum at :math:`\\Omega = 0`, :math:`\\mathbb{I} =
\\sum_l J_l + m_l (|\\rho_l|^2 \\mathbb{1} - \\rho_l \\rho_l^\\top)`) equals :math:`\\lambda`, so
:math:`\\Omega = \\mathbb{I}^{-1}(\\lambda - h^0)` (the adjugate over the determinant). Accelerations,
with the root's angular acceleration :math:`\\dot\\Omega`:

.. math::  \\alpha_l = \\alpha_p + \\omega_p \\times \\hat a_l u_l + \\hat a_l \\dot u_l ,\\qquad
           \\ddot P_l = \\ddot P_p + \\alpha_p \\times d + \\omega_p \\times (\\omega_p \\times d) ,\\qquad
           \\ddot r_l = \\ddot P_l + \\alpha_l \\times e + \\omega_l \\times (\\omega_l \\times e)

(:math:`d = R_p j_l`, :math:`e = R_l c_l`), :math:`\\ddot\\rho_l = \\ddot r_l - \\ddot r_c`. The momentum is
constant in the inertial frame: :math:`\\dot h = \\sum_l J_l \\alpha_l + \\omega_l \\times J_l \\omega_l +
m_l \\rho_l \\times \\ddot\\rho_l = \\mathbb{I}\\,\\dot\\Omega + \\dot h^0 = 0` (:math:`\\dot\\Omega` adds
:math:`\\dot\\Omega` to every :math:`\\alpha_l` and :math:`\\dot\\Omega \\times \\rho_l` to every
:math:`\\ddot\\rho_l`), so :math:`\\dot\\Omega = -\\mathbb{I}^{-1} \\dot h^0`. Last, the moment about joint
:math:`j` that the subtree's motion needs: the motor's torque is its component along the axis,

.. math::  \\tau_j = \\hat a_j \\cdot \\sum_{l \\in \\mathrm{subtree}(j)} \\big(J_l \\alpha_l + \\omega_l \\times
           J_l \\omega_l + m_l (\\rho_l - \\pi_j) \\times \\ddot\\rho_l\\big) ,\\qquad \\pi_j = P_j - r_c ,

(the joint's reaction force acts at :math:`P_j`, its reaction moment is normal to the axis):
the torque the motor applies to the child about :math:`\\hat a_j`, positive in the sense of increasing
:math:`s_j`, as Pinocchio's ``rnea`` gives it (``tests/test_spatial_effort.py`` checks the two
against each other). Massless links are left out of every sum (they are part of the compiled
structure).

Parameters (runtime values of the compiled function): per link with mass :math:`m_l`, :math:`c_l`
and the six entries of :math:`J^0_l`; per non-root link :math:`j_l`, :math:`a_l` and the nine of
:math:`R^0_l` (:func:`parameters`).
"""

from __future__ import annotations

import copy
import functools
import threading

import numpy as np

__all__ = ["joint_torques", "parameters", "newton_euler", "structure", "MAX_COMPILED_JOINTS"]

#: bodies with more joints than this use Pinocchio instead of the compiled recursion (its
#: compilation grows with the tree: seconds at six joints)
MAX_COMPILED_JOINTS = 8


# ---------------------------------------------------------------------- scalar vector algebra
def _zero(x) -> bool:
    return isinstance(x, float) and x == 0.0


def _one(x) -> bool:
    return isinstance(x, float) and x == 1.0


def _a(x, y):
    """``x + y``, with exact zeros folded (so the compiled expressions carry no ``0 + e``)."""
    if _zero(x):
        return y
    if _zero(y):
        return x
    return x + y


def _m(x, y):
    """``x * y``, with exact zeros and ones folded."""
    if _zero(x) or _zero(y):
        return 0.0
    if _one(x):
        return y
    if _one(y):
        return x
    return x * y


def _s(x, y):
    if _zero(y):
        return x
    if _zero(x):
        return -y
    return x - y


def _add(a, b):
    return (_a(a[0], b[0]), _a(a[1], b[1]), _a(a[2], b[2]))


def _sub(a, b):
    return (_s(a[0], b[0]), _s(a[1], b[1]), _s(a[2], b[2]))


def _scale(k, a):
    return (_m(k, a[0]), _m(k, a[1]), _m(k, a[2]))


def _dot(a, b):
    return _a(_a(_m(a[0], b[0]), _m(a[1], b[1])), _m(a[2], b[2]))


def _cross(a, b):
    return (_s(_m(a[1], b[2]), _m(a[2], b[1])), _s(_m(a[2], b[0]), _m(a[0], b[2])),
            _s(_m(a[0], b[1]), _m(a[1], b[0])))


def _mv(M, v):
    return tuple(_dot(M[i], v) for i in range(3))


def _mtv(M, v):
    return tuple(_a(_a(_m(M[0][i], v[0]), _m(M[1][i], v[1])), _m(M[2][i], v[2])) for i in range(3))


def _mm(A, B):
    return tuple(tuple(_a(_a(_m(A[i][0], B[0][j]), _m(A[i][1], B[1][j])), _m(A[i][2], B[2][j])) for j in range(3))
                 for i in range(3))


def _sum(vs, zero):
    out = zero
    for v in vs:
        out = _add(out, v)
    return out


def _rot(a, c, s):
    """:math:`\\mathrm{Rot}(a, \\varphi) = \\mathbb{1} + \\sin\\varphi K + (1 - \\cos\\varphi) K^2`
    (Rodrigues, :math:`K = [a]_\\times`, unit ``a``), from ``c, s`` = cos, sin."""
    k = 1.0 - c
    x, y, z = a
    return ((c + k * x * x, k * x * y - s * z, k * x * z + s * y),
            (k * x * y + s * z, c + k * y * y, k * y * z - s * x),
            (k * x * z - s * y, k * y * z + s * x, c + k * z * z))


def _solve3(M, b):
    """:math:`M^{-1} b` for a symmetric 3 x 3 ``M`` (adjugate over determinant)."""
    a00, a01, a02, a11, a12, a22 = M[0][0], M[0][1], M[0][2], M[1][1], M[1][2], M[2][2]
    c00 = a11 * a22 - a12 * a12
    c01 = a02 * a12 - a01 * a22
    c02 = a01 * a12 - a02 * a11
    c11 = a00 * a22 - a02 * a02
    c12 = a02 * a01 - a00 * a12
    c22 = a00 * a11 - a01 * a01
    inv = 1.0 / (a00 * c00 + a01 * c01 + a02 * c02)
    return ((c00 * b[0] + c01 * b[1] + c02 * b[2]) * inv, (c01 * b[0] + c11 * b[1] + c12 * b[2]) * inv,
            (c02 * b[0] + c12 * b[1] + c22 * b[2]) * inv)


# ---------------------------------------------------------------------- the recursion
def structure(links) -> tuple:
    """The compiled structure of a link table: ``(parents, massless)``, ``massless`` a flag per link."""
    return (tuple(links.parents), tuple(bool(link.mass == 0.0) for link in links))


def parameters(links) -> tuple:
    """The runtime parameters of a link table, in :func:`newton_euler`'s order: per link with mass
    ``m, c (3), J0 (xx, xy, xz, yy, yz, zz)``, then per non-root link ``j (3), a (3), R0 (9)``."""
    out = []
    for link in links:
        if link.mass != 0.0:
            J = link.inertia_matrix
            out += [link.mass, *link.com, J[0, 0], J[0, 1], J[0, 2], J[1, 1], J[1, 2], J[2, 2]]
    for link in links:
        if link.parent is not None:
            out += [*link.joint, *link.axis, *link.rotation_matrix.ravel()]
    return tuple(float(v) for v in out)


def newton_euler(struct, par, s, u, du, lam, sin, cos):
    """The joint torques (module docstring) over scalars of any kind: numbers, heyoka or CasADi
    expressions.

    Parameters
    ----------
    struct : tuple
        :func:`structure` of the link table.
    par : sequence
        The parameters (:func:`parameters`), as scalars.
    s, u, du : sequence, length m
        Joint angles, rates and accelerations, in state order (the non-root links in table order).
    lam : sequence, length 3
        The angular momentum in the root's frame, :math:`R(q)^\\top L`.
    sin, cos : callables
        Of the scalars' kind.

    Returns
    -------
    list, length m
        :math:`\\tau_j`.
    """
    parents, massless = struct
    mass, com, J0, jpos, axis, R0 = _unpack(struct, par)
    joints = [k for k in range(len(parents)) if parents[k] != -1]
    jidx = {k: i for i, k in enumerate(joints)}
    root = parents.index(-1)
    order = _depth_first(parents)
    zero = (0.0, 0.0, 0.0)
    heavy = [k for k in order if not massless[k]]
    M = sum(mass[k] for k in heavy) if heavy else 0.0
    P, ahat, d, e, rc, rho, Jw = _positions(parents, order, jidx, heavy, mass, com, J0, jpos, axis, R0, M, s,
                                            sin, cos)

    def velocities(Om):
        w, Pd = {root: Om}, {root: zero}
        for k in order[1:]:
            p = parents[k]
            w[k] = _add(w[p], _scale(u[jidx[k]], ahat[k]))
            Pd[k] = _add(Pd[p], _cross(w[p], d[k]))
        rd = {k: _add(Pd[k], _cross(w[k], e[k])) for k in heavy}
        vc = _scale(1.0 / M, _sum([_scale(mass[k], rd[k]) for k in heavy], zero))
        return w, {k: _sub(rd[k], vc) for k in heavy}

    # the locked inertia, and Omega from the momentum
    I = [[0.0] * 3 for _ in range(3)]  # noqa: E741
    for k in heavy:
        q2 = _dot(rho[k], rho[k])
        for a in range(3):
            for b in range(a, 3):
                I[a][b] = _a(_a(I[a][b], Jw[k][a][b]), _m(mass[k], _s(q2 if a == b else 0.0, _m(rho[k][a], rho[k][b]))))
    I = tuple(tuple(I[min(a, b)][max(a, b)] for b in range(3)) for a in range(3))  # noqa: E741
    w0, rhod0 = velocities(zero)
    h0 = _sum([_add(_mv(Jw[k], w0[k]), _scale(mass[k], _cross(rho[k], rhod0[k]))) for k in heavy], zero)
    Om = _solve3(I, _sub(tuple(lam), h0))
    w = {k: _add(w0[k], Om) for k in order}
    rhod = {k: _add(rhod0[k], _cross(Om, rho[k])) for k in heavy}
    del rhod

    # accelerations at a root at rest in rotation, then the root's angular acceleration
    al, Pdd = {root: zero}, {root: zero}
    for k in order[1:]:
        p, i = parents[k], jidx[k]
        al[k] = _add(_add(al[p], _cross(w[p], _scale(u[i], ahat[k]))), _scale(du[i], ahat[k]))
        Pdd[k] = _add(_add(Pdd[p], _cross(al[p], d[k])), _cross(w[p], _cross(w[p], d[k])))
    rdd = {k: _add(_add(Pdd[k], _cross(al[k], e[k])), _cross(w[k], _cross(w[k], e[k]))) for k in heavy}
    ac = _scale(1.0 / M, _sum([_scale(mass[k], rdd[k]) for k in heavy], zero))
    rhodd = {k: _sub(rdd[k], ac) for k in heavy}
    Jww = {k: _mv(Jw[k], w[k]) for k in heavy}
    hd0 = _sum([_add(_add(_mv(Jw[k], al[k]), _cross(w[k], Jww[k])), _scale(mass[k], _cross(rho[k], rhodd[k])))
                for k in heavy], zero)
    Omd = _scale(-1.0, _solve3(I, hd0))
    al = {k: _add(al[k], Omd) for k in order}
    rhodd = {k: _add(rhodd[k], _cross(Omd, rho[k])) for k in heavy}

    # the moments each link's motion needs about the centre of mass, and the forces
    nk = {k: _add(_add(_mv(Jw[k], al[k]), _cross(w[k], Jww[k])), _scale(mass[k], _cross(rho[k], rhodd[k])))
          for k in heavy}
    fk = {k: _scale(mass[k], rhodd[k]) for k in heavy}
    N, F = {}, {}
    for k in reversed(order):
        N[k] = _sum([N[c] for c in order if parents[c] == k] + ([nk[k]] if k in nk else []), zero)
        F[k] = _sum([F[c] for c in order if parents[c] == k] + ([fk[k]] if k in fk else []), zero)
    tau = [None] * len(joints)
    for k in joints:
        pi = _sub(P[k], rc)
        tau[jidx[k]] = _dot(ahat[k], _sub(N[k], _cross(pi, F[k])))
    return tau


def _unpack(struct, par):
    """The link table's numbers from the flat parameters (:func:`parameters`): per massive link its
    mass, centre of mass and inertia; per joint its position, axis and fixed rotation."""
    parents, massless = struct
    n = len(parents)
    it = iter(par)
    mass, com, J0 = {}, {}, {}
    for k in range(n):
        if not massless[k]:
            mass[k] = next(it)
            com[k] = (next(it), next(it), next(it))
            e = [next(it) for _ in range(6)]
            J0[k] = ((e[0], e[1], e[2]), (e[1], e[3], e[4]), (e[2], e[4], e[5]))
    jpos, axis, R0 = {}, {}, {}
    for k in range(n):
        if parents[k] != -1:
            jpos[k] = (next(it), next(it), next(it))
            axis[k] = (next(it), next(it), next(it))
            r = [next(it) for _ in range(9)]
            R0[k] = (tuple(r[0:3]), tuple(r[3:6]), tuple(r[6:9]))
    return mass, com, J0, jpos, axis, R0


def _depth_first(parents) -> list[int]:
    """The links from the root, each after its parent."""
    order = [parents.index(-1)]
    for i in order:
        order.extend(k for k in range(len(parents)) if parents[k] == i)
    return order


def _positions(parents, order, jidx, heavy, mass, com, J0, jpos, axis, R0, M, s, sin, cos):
    """The pose at the joint angles ``s``, the root's frame fixed: per link its frame's origin ``P``,
    its joint's axis ``ahat`` and offset ``d`` from the parent's origin, its centre of mass ``e``
    from its origin; the whole body's centre of mass ``rc``, each massive link's centre of mass from
    it ``rho`` and its inertia ``Jw``, all in the root's frame."""
    root = order[0]
    zero = (0.0, 0.0, 0.0)
    eye = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    R, P, ahat, d, e = {root: eye}, {root: zero}, {}, {}, {}
    for k in order[1:]:
        p, i = parents[k], jidx[k]
        d[k] = _mv(R[p], jpos[k])
        P[k] = _add(P[p], d[k])
        ahat[k] = _mv(R[p], axis[k])
        R[k] = _mm(_mm(R[p], _rot(axis[k], cos(s[i]), sin(s[i]))), R0[k])
    for k in heavy:
        e[k] = _mv(R[k], com[k])
    r = {k: _add(P[k], e[k]) for k in heavy}
    rc = _scale(1.0 / M, _sum([_scale(mass[k], r[k]) for k in heavy], zero))
    rho = {k: _sub(r[k], rc) for k in heavy}
    Jw = {k: _mm(_mm(R[k], J0[k]), tuple(zip(*R[k]))) for k in heavy}
    return P, ahat, d, e, rc, rho, Jw


# ---------------------------------------------------------------------- compiled
_FUNCS: dict = {}
_LOCAL = threading.local()


def _build(struct, derivatives: bool):
    """The compiled torques (outputs :math:`\\tau`), or with ``derivatives`` their Jacobian in
    :math:`x = (s, u, \\dot u, \\lambda)`, row by row (heyoka's ``diff_tensors``)."""
    import heyoka as hy

    parents, massless = struct
    m = sum(1 for p in parents if p != -1)
    names = [f"s{i}" for i in range(m)] + [f"u{i}" for i in range(m)] + [f"a{i}" for i in range(m)] + ["lx", "ly", "lz"]
    v = list(hy.make_vars(*names))
    npar = sum(10 for k in massless if not k) + 15 * m
    par = [hy.par[i] for i in range(npar)]
    tau = [t if not isinstance(t, float) else hy.expression(t)
           for t in newton_euler(struct, par, v[:m], v[m:2 * m], v[2 * m:3 * m], v[3 * m:], hy.sin, hy.cos)]
    if not derivatives:
        return hy.cfunc(tau, v, compact_mode=True)
    jac = hy.diff_tensors(tau, diff_args=v, diff_order=1).jacobian
    return hy.cfunc([jac[i, j] for i in range(m) for j in range(3 * m + 3)], v, compact_mode=True)


def _compiled(struct, derivatives: bool):
    key = (struct, bool(derivatives))
    fn = _FUNCS.get(key)
    if fn is None:  # compiled in a thread of its own, waited for within the plan's time budget
        from ...core import backend

        fn = _FUNCS[key] = backend.compile_once(("spatial-torques", *key), lambda: _build(struct, bool(derivatives)))
    mine = getattr(_LOCAL, "funcs", None)
    if mine is None:
        mine = _LOCAL.funcs = {}
    own = mine.get(key)
    if own is None:
        own = mine[key] = copy.copy(fn)
    return own


def joint_torques(links, s, u, du, lam, *, derivatives: bool = False):
    """The joint torques (module docstring) at ``K`` instants, by the compiled recursion (built once
    per :func:`structure`).

    Parameters
    ----------
    links : SpatialLinkTable
    s, u, du : array_like, shape (m, K)
    lam : array_like, shape (3, K)
        :math:`R(q)^\\top L` at each instant.
    derivatives : bool
        Also the partial derivatives.

    Returns
    -------
    tau : numpy.ndarray, shape (m, K)
    partials : numpy.ndarray, shape (m, K, 3 m + 3), only with ``derivatives``
        :math:`\\partial\\tau/\\partial(s, u, \\dot u, \\lambda)` at each instant.
    """
    struct = structure(links)
    fn = _compiled(struct, derivatives)
    x = np.ascontiguousarray(np.concatenate([np.atleast_2d(np.asarray(a, dtype=float)) for a in (s, u, du, lam)]))
    nx, K = x.shape
    m = (nx - 3) // 3
    params = _parameters(links)
    if not derivatives:
        return _chunked(fn, x, params)
    # the torques by the same compiled code with or without the derivatives (the same numbers)
    tau = _chunked(_compiled(struct, False), x, params)
    return tau, np.ascontiguousarray(_chunked(fn, x, params).reshape(m, nx, K).transpose(0, 2, 1))


#: Points per call of a compiled torque function (its parameters repeated once per size, cached).
CHUNK = 256


@functools.lru_cache(maxsize=64)
def _parameters(links) -> tuple:
    return parameters(links)


def _chunked(fn, x, params) -> np.ndarray:
    """``fn`` at the columns of ``x`` (C-contiguous), :data:`CHUNK` columns a call."""
    from ...core.backend import evaluate_columns

    return evaluate_columns(fn, x, params, CHUNK)
