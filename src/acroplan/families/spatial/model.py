"""Free-floating bodies in 3-D with any number of links: :class:`SpatialBody`.

A body is a tree of :math:`n` rigid links (:mod:`~acroplan.families.spatial.links`) joined by
revolute joints with any axes, flying freely: no external force or torque acts, so its centre of
mass :math:`c` moves uniformly (taken at rest) and its angular momentum about :math:`c`, the vector
:math:`L` (inertial frame), is constant.

State and input
---------------
:math:`x = (q, s)`: :math:`q = [q_w, q_x, q_y, q_z]` the unit quaternion of the root's attitude
(state names ``qw, qx, qy, qz``; :mod:`~acroplan.families.spatial.rotations` for the conventions)
and :math:`s = (s_1, \\dots, s_m)` the joint angles (the *shape*), named by their joints. The
inputs are the joint rates :math:`u = \\dot s` (``u_<joint>``).

The momentum map
----------------
In the root's frame, with :math:`\\Omega` the root's angular velocity (body frame), the angular
momentum about the centre of mass is

.. math::  R(q)^\\top L = \\mathbb{I}(s)\\,\\Omega + A(s)\\,u ,                              \\qquad (1)

:math:`\\mathbb{I}(s)` (3 x 3) the *locked inertia* (the body frozen in shape :math:`s`, about its
centre of mass, in the root frame) and :math:`A(s)` (3 x m) the *coupling*. Conservation of
:math:`L` gives the state equation

.. math::  \\Omega = \\mathbb{I}(s)^{-1}\\big(R(q)^\\top L - A(s)\\,u\\big) ,\\qquad
           \\dot q = \\tfrac12\\, q \\otimes (0, \\Omega) ,\\qquad \\dot s = u .               \\qquad (2)

It is control-affine with drift: :math:`f = (\\tfrac12 \\Xi(q) \\mathbb{I}^{-1} R^\\top L, 0)`,
:math:`g_j = (-\\tfrac12 \\Xi(q) \\mathbb{I}^{-1} A_j, e_j)`. :math:`\\mathbb{I}^{-1}` is written as
:math:`\\mathrm{adj}(\\mathbb{I})/\\det \\mathbb{I}`. :math:`|q|` is a first integral of (2)
(:math:`\\tfrac{d}{dt}|q|^2 = q \\cdot \\Xi(q)\\Omega = 0`), kept by the integrator to rounding.

*Derivation (barycentric vectors, as for planar bodies).* Let :math:`R_k(s)` be link :math:`k`'s
orientation in the root frame, :math:`c_k` its centre of mass and :math:`j_h` the joint of a child
:math:`h` in its frame. The position of link :math:`i`'s centre of mass relative to :math:`c` is a
sum of rotated constant vectors, :math:`\\rho_i = \\sum_k R_k b_{ik}`, :math:`b_{ik} = e_{ik} -
g_k/M`, with :math:`e_{ik} = c_k` (:math:`i = k`), :math:`j_h` (:math:`i` below the child
:math:`h` of :math:`k`), else 0, and :math:`g_k = m_k c_k + \\sum_{h} S_h j_h` (:math:`S_h` the
mass of the subtree of :math:`h`, :math:`M` the total). With the link angular velocities
:math:`\\omega_l`, :math:`\\dot\\rho_i = \\sum_l \\omega_l \\times R_l b_{il}` and
:math:`a \\times (\\omega \\times b) = ((a\\cdot b)\\mathbb{1} - b a^\\top)\\omega`, the momentum is

.. math::  h = \\sum_i R_i J_i R_i^\\top \\omega_i + m_i \\rho_i \\times \\dot\\rho_i = \\sum_l Q_l\\, \\omega_l ,
           \\qquad Q_l = R_l J_l R_l^\\top + \\sum_k \\big(\\mathrm{tr}(M_{kl})\\,\\mathbb{1} - M_{kl}^\\top\\big) ,

:math:`M_{kl} = R_k E_{kl} R_l^\\top`, :math:`E_{kl} = \\sum_i m_i b_{ik} b_{il}^\\top` constant and,
in closed form, of rank one off the diagonal:

* :math:`E_{kk} = m_k c_k c_k^\\top + \\sum_h S_h j_h j_h^\\top - g_k g_k^\\top / M`;
* :math:`k` a proper ancestor of :math:`l`, :math:`h` the child of :math:`k` towards :math:`l`:
  :math:`E_{kl} = w_h g_l^\\top`, :math:`w_h = j_h - g_k/M`; :math:`E_{lk} = E_{kl}^\\top`;
* neither an ancestor of the other: :math:`E_{kl} = -g_k g_l^\\top / M`.

So :math:`M_{kl} = x\\,y^\\top` with root-frame vectors (:math:`x = R_k w_h`, :math:`y = R_l g_l`, ...)
and :math:`(\\mathrm{tr}(M)\\mathbb{1} - M^\\top)\\,v = (x\\cdot y)\\,v - y\\,(x \\cdot v)`. Since
:math:`\\omega_l = \\Omega + \\sum_{j \\in \\mathrm{path}(l)} a_j u_j` (:math:`a_j` joint :math:`j`'s axis
in the root frame),

.. math::  \\mathbb{I}(s) = \\sum_l Q_l ,\\qquad A_j(s) = \\Big(\\sum_{l \\in \\mathrm{subtree}(j)} Q_l\\Big)\\, a_j .

Only rotations :math:`R_k(s)` enter; positions are folded into the constants.

Parameters (runtime values of the compiled integrator)
------------------------------------------------------
Each non-root link gets a frame whose :math:`z` axis is its joint axis (a constant turn
:math:`C_k` of the link's own frame), so that :math:`R_k = R_{parent} R^0_k R_z(s_k)` with a constant
:math:`R^0_k`. The runtime parameters are ``Lx, Ly, Lz, Minv``, per link ``g<k>_{x,y,z}`` and the
six entries ``J<k>_{xx,xy,xz,yy,yz,zz}`` of :math:`J_k + \\mathrm{tr}(E_{kk})\\mathbb{1} - E_{kk}`, per
non-root link the nine entries ``R<k>_<ij>`` of :math:`R^0_k` and ``w<k>_{x,y,z}`` (table indices
:math:`k`), all in those frames (:func:`lumped_parameters`). The symbolic fields depend only on the
topology (:attr:`SpatialBody.structure_key` ``= ("spatial", parents)``): one compilation serves
every body of that topology, whatever its masses, inertias, geometry, axes, names and :math:`L`.

The endpoint map, its Jacobian and dense states are the family's own
(:meth:`SpatialBody.endpoint_map`, :meth:`SpatialBody.sample_map`: Gauss collocation of the attitude
alone, :mod:`~acroplan.families.spatial.collocation`, with the momentum map compiled once per
topology as a ``heyoka.cfunc``, which :meth:`SpatialBody.momentum_map` also evaluates). The Taylor
integrator of the whole state (``backend.taylor_endpoint``, and the torques' Jacobian at
:math:`L \\ne 0`) uses heyoka's compact mode: with the variational equations a 3-link body with 6
coefficients per input has 4,317 nodes in heyoka's decomposition, a 5-link body with 10 coefficients
12,691; full mode had not compiled an earlier form of the 3-link fields (4,889 nodes) after 15
minutes, compact mode takes seconds (:attr:`SpatialBody.compact_mode`, which the core's back end
honours). The tests check (1) against Pinocchio's centroidal map at random shapes to 1e-12.
"""

from __future__ import annotations

import dataclasses
import math
import threading
from typing import Any, Hashable, Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ...core.system import ControlAffineSystem
from ..tree.body import TreeBody
from . import rotations as rot
from .links import QUATERNION_NAMES, SpatialLink, SpatialLinkTable

__all__ = ["SpatialBody", "lumped_parameters", "generic_symbols", "axis_rotation", "kinematic_locked_inertia", "NORM_TOL"]

#: how far from 1 the norm of a waypoint's quaternion may be (larger: refused as a typing error)
NORM_TOL = 1e-9


# ---------------------------------------------------------------------- the tree
def _tree(parents: tuple[int, ...]):
    """children, ancestors (self first), subtree (self first) per link."""
    n = len(parents)
    children = [tuple(k for k in range(n) if parents[k] == i) for i in range(n)]
    ancestors = []
    for i in range(n):
        a = [i]
        while parents[a[-1]] != -1:
            a.append(parents[a[-1]])
        ancestors.append(tuple(a))
    subtree = [tuple(k for k in range(n) if i in ancestors[k]) for i in range(n)]
    return children, ancestors, subtree


def axis_rotation(axis, angle) -> np.ndarray:
    """:math:`\\mathrm{Rot}(a, \\varphi)` (Rodrigues), shape (3, 3), for a unit axis ``a``."""
    a = np.asarray(axis, dtype=float)
    c, s = math.cos(angle), math.sin(angle)
    K = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def _to_z(b) -> np.ndarray:
    """A rotation :math:`C` with :math:`C e_z = b` (unit ``b``)."""
    b = np.asarray(b, dtype=float)
    ez = np.array([0.0, 0.0, 1.0])
    v = np.cross(ez, b)
    s, c = float(np.linalg.norm(v)), float(b @ ez)
    if s < 1e-15:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    return axis_rotation(v / s, math.atan2(s, c))


_SYM = ("xx", "xy", "xz", "yy", "yz", "zz")
_SYM_IDX = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


def generic_names(parents) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The names of a topology's compiled states and parameters (module docstring): states
    ``qw, qx, qy, qz, s1, ...``; parameters ``Lx, Ly, Lz, Minv``, ``g<k>_x...``, ``J<k>_xx...``,
    ``R<k>_00...`` and ``w<k>_x...`` (non-root ``k``). Plain strings: a body's parameter names
    (:attr:`SpatialBody.param_names`, in every result file) need no sympy."""
    n = len(parents)
    states = QUATERNION_NAMES + tuple(f"s{j}" for j in range(1, n))
    names = ["Lx", "Ly", "Lz", "Minv"]
    for k in range(n):
        names += [f"g{k}_{a}" for a in "xyz"] + [f"J{k}_{e}" for e in _SYM]
    for k in range(n):
        if parents[k] != -1:
            names += [f"R{k}_{i}{j}" for i in range(3) for j in range(3)] + [f"w{k}_{a}" for a in "xyz"]
    return tuple(states), tuple(names)


def generic_symbols(parents):
    """The compiled state and parameter symbols of a topology: :func:`generic_names` as real sympy
    symbols."""
    import sympy as sp

    states, names = generic_names(parents)
    return tuple(sp.Symbol(s, real=True) for s in states), tuple(sp.Symbol(s, real=True) for s in names)


def lumped_parameters(links: SpatialLinkTable, L) -> tuple[float, ...]:
    """The compiled parameters of a link table and momentum ``L`` (module docstring), in
    :func:`generic_symbols`' order."""
    n = len(links)
    parents = links.parents
    children, ancestors, subtree = _tree(parents)
    m = np.array([k.mass for k in links])
    M = float(m.sum())
    S = [float(m[list(subtree[i])].sum()) for i in range(n)]
    # each link's constant turn C_k: its z axis along the joint axis (in the link's own frame)
    C = []
    for k, link in enumerate(links):
        if parents[k] == -1:
            C.append(np.eye(3))
        else:
            b = link.rotation_matrix.T @ np.asarray(link.axis)  # the axis in the child's own frame
            C.append(_to_z(b))
    com = [C[k].T @ np.asarray(links[k].com) for k in range(n)]
    jpos = [None] * n  # child h's joint in its parent's (primed) frame
    for h in range(n):
        if parents[h] != -1:
            jpos[h] = C[parents[h]].T @ np.asarray(links[h].joint)
    g = []
    for k in range(n):
        v = m[k] * com[k]
        for h in children[k]:
            v = v + S[h] * jpos[h]
        g.append(v)
    out = [float(v) for v in np.asarray(L, dtype=float)] + [1.0 / M]
    for k in range(n):
        E = m[k] * np.outer(com[k], com[k]) - np.outer(g[k], g[k]) / M
        for h in children[k]:
            E = E + S[h] * np.outer(jpos[h], jpos[h])
        Jk = C[k].T @ links[k].inertia_matrix @ C[k] + np.trace(E) * np.eye(3) - E
        out += [float(v) for v in g[k]] + [float(Jk[i, j]) for i, j in _SYM_IDX]
    for k in range(n):
        p = parents[k]
        if p != -1:
            R0 = C[p].T @ links[k].rotation_matrix @ C[k]
            w = jpos[k] - g[p] / M
            out += [float(v) for v in R0.ravel()] + [float(v) for v in w]
    return tuple(out)


# ---------------------------------------------------------------------- the symbolic map
_MAPS: dict[Hashable, tuple] = {}
_LOCK = threading.Lock()


def _symbolic_map(parents):
    """``(x, p, I, A, R)`` in the compiled symbols, cached per topology: ``I`` a 3 x 3 sympy Matrix,
    ``A`` a list of m column Matrices, ``R`` the links' orientations in the root frame."""
    import sympy as sp

    out = _MAPS.get(parents)
    if out is not None:
        return out
    n = len(parents)
    children, ancestors, subtree = _tree(parents)
    x, p = generic_symbols(parents)
    it = iter(p)
    for _ in range(3):  # Lx, Ly, Lz: not in the momentum map
        next(it)
    Minv = next(it)
    g, J = [], []
    for k in range(n):
        g.append(sp.Matrix([next(it) for _ in range(3)]))
        e = [next(it) for _ in range(6)]
        J.append(sp.Matrix([[e[0], e[1], e[2]], [e[1], e[3], e[4]], [e[2], e[4], e[5]]]))
    R0, w = {}, {}
    for k in range(n):
        if parents[k] != -1:
            R0[k] = sp.Matrix(3, 3, [next(it) for _ in range(9)])
            w[k] = sp.Matrix([next(it) for _ in range(3)])
    joints = [k for k in range(n) if parents[k] != -1]
    svar = {k: x[4 + j] for j, k in enumerate(joints)}
    R = [None] * n
    order = [parents.index(-1)]
    for i in order:
        order.extend(children[i])
    for k in order:
        if parents[k] == -1:
            R[k] = sp.eye(3)
            continue
        B = R0[k] if parents[parents[k]] == -1 else R[parents[k]] * R0[k]
        c, s = sp.cos(svar[k]), sp.sin(svar[k])
        R[k] = sp.Matrix.hstack(B[:, 0] * c + B[:, 1] * s, -B[:, 0] * s + B[:, 1] * c, B[:, 2])
    G = [R[k] * g[k] for k in range(n)]
    V = {h: R[parents[h]] * w[h] for h in joints}

    def pair(k, l):  # noqa: E741  M_kl = x y^T
        if k in ancestors[l]:
            return V[ancestors[l][ancestors[l].index(k) - 1]], G[l]
        if l in ancestors[k]:
            return G[k], V[ancestors[k][ancestors[k].index(l) - 1]]
        return G[k], -Minv * G[l]

    pairs = {(k, l): pair(k, l) for k in range(n) for l in range(n) if k != l}  # noqa: E741
    dots = {kl: xy[0].dot(xy[1]) for kl, xy in pairs.items()}
    RJ = [R[l] * J[l] for l in range(n)]
    I = sp.zeros(3, 3)  # noqa: E741
    for l in range(n):  # noqa: E741
        I += RJ[l] * R[l].T
    for k in range(n):
        for l in range(k + 1, n):  # noqa: E741
            xv, yv = pairs[k, l]
            I += 2 * dots[k, l] * sp.eye(3) - (yv * xv.T + xv * yv.T)
    A = []
    for j in joints:
        a = R[j][:, 2]
        col = sp.zeros(3, 1)
        for l in subtree[j]:  # noqa: E741
            col += RJ[l] * (R[l].T * a)
            for k in range(n):
                if k != l:
                    xv, yv = pairs[k, l]
                    col += dots[k, l] * a - yv * xv.dot(a)
        A.append(col)
    out = (x, p, I, A, R)
    with _LOCK:
        out = _MAPS.setdefault(parents, out)
    return out


def _matmul(A, B):
    """``A * B`` of sympy matrices, entry by entry over the nonzero products. sympy's own product
    asks, for every entry, whether zero times it is zero (to catch infinities): an assumptions
    query over the whole expression, which for a 5-link body's inertia terms took minutes."""
    import sympy as sp

    return sp.Matrix(A.rows, B.cols, lambda i, j: sp.Add(*[A[i, k] * B[k, j] for k in range(A.cols)
                                                            if A[i, k] != 0 and B[k, j] != 0]))


def _fields(parents):
    """The fields (f, G) of (2) in the compiled symbols."""
    import sympy as sp

    x, p, I, A, _ = _symbolic_map(parents)  # noqa: E741
    qw, qx, qy, qz = x[:4]
    Lv = sp.Matrix(p[:3])
    a00 = I[1, 1] * I[2, 2] - I[1, 2] ** 2
    a01 = I[0, 2] * I[1, 2] - I[0, 1] * I[2, 2]
    a02 = I[0, 1] * I[1, 2] - I[0, 2] * I[1, 1]
    a11 = I[0, 0] * I[2, 2] - I[0, 2] ** 2
    a12 = I[0, 2] * I[0, 1] - I[0, 0] * I[1, 2]
    a22 = I[0, 0] * I[1, 1] - I[0, 1] ** 2
    adj = sp.Matrix([[a00, a01, a02], [a01, a11, a12], [a02, a12, a22]])
    inv_det = 1 / (I[0, 0] * a00 + I[0, 1] * a01 + I[0, 2] * a02)
    Rq = sp.Matrix([[qw**2 + qx**2 - qy**2 - qz**2, 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)],
                    [2 * (qx * qy + qw * qz), qw**2 - qx**2 + qy**2 - qz**2, 2 * (qy * qz - qw * qx)],
                    [2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), qw**2 - qx**2 - qy**2 + qz**2]])
    Xi = sp.Matrix([[-qx, -qy, -qz], [qw, -qz, qy], [qz, qw, -qx], [-qy, qx, qw]]) / 2
    nx, m = len(x), len(A)
    f = sp.zeros(nx, 1)
    f[:4, 0] = _matmul(Xi, _matmul(adj, _matmul(Rq.T, Lv)) * inv_det)
    Gm = sp.zeros(nx, m)
    for j, Aj in enumerate(A):
        Gm[:4, j] = _matmul(Xi, _matmul(adj, Aj) * (-inv_det))
        Gm[4 + j, j] = 1
    return f, Gm


_NUMERIC_MAPS: dict[Hashable, Any] = {}


def _numeric_map(parents):
    """``fn(s, p) -> (I entries (9), A entries (3 m))``, lambdified with common subexpressions.

    The subexpressions are found first, in sympy's ``order="none"``, and lambdify is handed the
    reduced expressions: for the 15-link human (``families/human/spatial_body.py``) that takes 3 s,
    where ``lambdify(..., cse=True)`` took about 5 minutes (its walk of the whole expression tree,
    then the canonical ordering of the subexpressions)."""
    import sympy as sp

    fn = _NUMERIC_MAPS.get(parents)
    if fn is None:
        x, p, I, A, _ = _symbolic_map(parents)  # noqa: E741
        exprs = list(I) + [e for col in A for e in col]
        rep, red = sp.cse(exprs, order="none")
        fn = sp.lambdify((x[4:], p), red, modules="numpy", cse=lambda _: (rep, red))
        with _LOCK:
            fn = _NUMERIC_MAPS.setdefault(parents, fn)
    return fn


def _link_frames(links: SpatialLinkTable, shape):
    """Every link's orientation, frame origin and centre of mass in the root frame at ``shape``
    (plain kinematics of the link table): shapes (n, 3, 3), (n, 3), (n, 3)."""
    s = np.asarray(shape, dtype=float)
    n = len(links)
    Rs = np.zeros((n, 3, 3))
    org = np.zeros((n, 3))
    for i in links.topological_order():
        p = links.parents[i]
        if p == -1:
            Rs[i] = np.eye(3)
            continue
        link = links[i]
        Rs[i] = Rs[p] @ axis_rotation(link.axis, s[links.joints.index(i)]) @ link.rotation_matrix
        org[i] = org[p] + Rs[p] @ np.asarray(link.joint)
    coms = org + np.einsum("kij,kj->ki", Rs, np.array([link.com for link in links]))
    return Rs, org, coms


def kinematic_locked_inertia(links: SpatialLinkTable, shape) -> np.ndarray:
    """:math:`\\mathbb{I}(s)` by plain kinematics of the link table (no sympy): every link's
    orientation :math:`R_k` and centre of mass :math:`c_k` in the root frame, then
    :math:`\\sum_k R_k J_k R_k^\\top + m_k (|d_k|^2 \\mathbb{1} - d_k d_k^\\top)`, :math:`d_k = c_k - c`.

    Parameters
    ----------
    links : SpatialLinkTable
    shape : array_like, shape (m,)

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        About the centre of mass, in the root frame.
    """
    Rs, _, coms = _link_frames(links, shape)
    mass = np.array([link.mass for link in links])
    d = coms - mass @ coms / mass.sum()
    out = np.zeros((3, 3))
    for k, link in enumerate(links):
        out += Rs[k] @ link.inertia_matrix @ Rs[k].T + mass[k] * (float(d[k] @ d[k]) * np.eye(3) - np.outer(d[k], d[k]))
    return out


# ---------------------------------------------------------------------- the body
@dataclasses.dataclass(frozen=True, init=False)
class SpatialBody(TreeBody, ControlAffineSystem):
    """A free-floating body in 3-D (module docstring for the model).

    Parameters
    ----------
    links : SpatialLinkTable or sequence of SpatialLink
    angular_momentum : (float, float, float)
        The angular momentum :math:`L` about the centre of mass, inertial frame (kg m^2/s)
        (keyword; ``L``, the field's name, is accepted as an alias).

    Attributes
    ----------
    state_names : tuple of str
        ``("qw", "qx", "qy", "qz", <joint names>...)``.
    input_names : tuple of str
        ``("u_<joint>", ...)``.
    param_names : tuple of str
        The compiled parameters (:func:`lumped_parameters`).

    Examples
    --------
    >>> from acroplan.families.spatial import SpatialBody, SpatialLink
    >>> body = SpatialBody([SpatialLink("a", None, 1.0, (0.1, 0.1, 0.1)),
    ...                     SpatialLink("b", "a", 1.0, (0.1, 0.1, 0.1), joint=(1.0, 0.0, 0.0), axis=(0, 0, 1))])
    >>> body.state_names, body.input_names
    (('qw', 'qx', 'qy', 'qz', 'b'), ('u_b',))
    >>> I, A = body.momentum_map([0.0])   # 0.1 + 0.1, plus two unit masses 1 m apart: m d^2 / 2 = 0.5
    >>> [round(float(v), 12) for v in np.diag(I)]
    [0.2, 0.7, 0.7]
    """

    links: SpatialLinkTable
    L: tuple = (0.0, 0.0, 0.0)

    #: the states before the joints (the quaternion), the record's name of the momentum, the check's module
    n_root = 4
    momentum_field = "L"
    _check_module = "acroplan.families.spatial.check"

    def __init__(self, links, L=None, *, angular_momentum=None):
        if L is not None and angular_momentum is not None:
            raise InvalidInputError("angular_momentum", "is given together with L (its alias)", "give one of them")
        object.__setattr__(self, "links", links)
        object.__setattr__(self, "L", angular_momentum if angular_momentum is not None else
                           ((0.0, 0.0, 0.0) if L is None else L))
        self.__post_init__()

    #: compile with heyoka's compact mode (module docstring)
    compact_mode = True

    def __post_init__(self):
        object.__setattr__(self, "links", SpatialLinkTable(self.links))
        Lv = self.L
        try:
            Lt = tuple(float(v) for v in np.asarray(Lv, dtype=float).reshape(-1))
        except (TypeError, ValueError):
            raise InvalidInputError("L", f"must be three numbers (Lx, Ly, Lz), got {Lv!r}",
                                    "give the angular momentum vector, for example (0, 0, 0)") from None
        if len(Lt) != 3 or not all(math.isfinite(v) for v in Lt):
            raise InvalidInputError("L", f"must be three finite numbers (Lx, Ly, Lz), got {Lv!r}",
                                    "give the angular momentum vector, for example (0, 0, 0)")
        object.__setattr__(self, "L", Lt)
        if len(self.links) < 2:
            raise InvalidInputError("links", "has one link: a single rigid body has no joint to move",
                                    "give at least two links")
        # plain kinematics: a body is built without its symbolic map (about 10 s for 15 links)
        I0 = kinematic_locked_inertia(self.links, np.zeros(self.n_links - 1))
        ev = np.linalg.eigvalsh(I0)
        if not ev[0] > 1e-12 * max(1.0, ev[-1]):
            raise InvalidInputError("links", f"the locked inertia at the zero shape is singular (principal moments "
                                    f"{ev.tolist()})", "give the links inertia, or mass off one line")

    # ------------------------------------------------------------------ structure and names
    @property
    def structure_key(self):
        """``("spatial", parents)``: the topology. Names, axes and values are runtime."""
        return ("spatial", self.links.parents)

    @property
    def state_names(self):
        return QUATERNION_NAMES + self.links.joint_names

    @property
    def angle_states(self):
        return self.links.joint_names

    @property
    def param_names(self):
        return generic_names(self.links.parents)[1]

    @property
    def _param_tuple(self) -> tuple:
        cached = self.__dict__.get("_acroplan_params")
        if cached is None:
            cached = lumped_parameters(self.links, self.L)
            object.__setattr__(self, "_acroplan_params", cached)
        return cached

    def lumped(self) -> dict[str, float]:
        """The runtime parameters by name (they are computed from the link table, not attributes)."""
        return dict(zip(self.param_names, (float(v) for v in self._param_tuple)))

    @property
    def angular_momentum(self) -> np.ndarray:
        """:math:`L`, shape (3,)."""
        return np.array(self.L)

    def _momentum_record(self) -> list:
        return list(self.L)

    def symbols(self):
        """The compiled state and parameter symbols (:func:`generic_symbols`)."""
        return generic_symbols(self.links.parents)

    def symbolic_fields(self, x, p):
        """:math:`f`, :math:`G` of (2) in the compiled symbols; shapes (4 + m, 1), (4 + m, m)."""
        f, G = _fields(self.links.parents)
        x0, p0 = generic_symbols(self.links.parents)
        sub = {s: t for s, t in zip(x0 + p0, tuple(x) + tuple(p)) if s != t}
        if sub:
            f, G = f.xreplace(sub), G.xreplace(sub)
        return f, G

    def symbolic_momentum_map(self):
        """:math:`\\mathbb{I}(s)` (3 x 3 sympy Matrix) and :math:`A(s)` (list of m columns) in the
        compiled symbols."""
        _, _, I, A, _ = _symbolic_map(self.links.parents)  # noqa: E741
        return I, A

    def _numeric(self):
        """The right-hand side for the core's DOP853 re-simulation (``verify="ode"``): (2) evaluated
        from the lambdified symbolic :math:`\\mathbb{I}(s)`, :math:`A(s)` with a linear solve for
        :math:`\\Omega` (not the adjugate the compiled fields use, and not heyoka). Lambdifying the
        whole fields would print their deep expression as a tree; with common subexpressions it took
        about 30 s for four links."""
        parents = self.links.parents
        m = len(parents) - 1

        def fn(x, u, p):
            x = np.asarray(x, dtype=float)
            u = np.asarray(u, dtype=float)
            vals = _numeric_map(parents)(tuple(x[4:]), p)
            rest = x.shape[1:]
            arr = np.array([np.broadcast_to(np.asarray(v, dtype=float), rest) for v in vals])
            I = np.moveaxis(arr[:9].reshape((3, 3) + rest), (0, 1), (-2, -1))  # noqa: E741
            A = np.moveaxis(arr[9:].reshape((m, 3) + rest), (0, 1), (-1, -2))
            q = x[:4]
            w, a, b, c = q
            Lv = np.asarray(p[:3], dtype=float)
            RtL = np.stack([(w * w + a * a - b * b - c * c) * Lv[0] + 2 * (a * b + w * c) * Lv[1]
                            + 2 * (a * c - w * b) * Lv[2],
                            2 * (a * b - w * c) * Lv[0] + (w * w - a * a + b * b - c * c) * Lv[1]
                            + 2 * (b * c + w * a) * Lv[2],
                            2 * (a * c + w * b) * Lv[0] + 2 * (b * c - w * a) * Lv[1]
                            + (w * w - a * a - b * b + c * c) * Lv[2]], axis=-1)
            rhs = RtL - np.einsum("...ij,j...->...i", A, u)
            om = np.linalg.solve(I, rhs[..., None])[..., 0]
            o = np.moveaxis(om, -1, 0)
            qd = 0.5 * np.stack([-a * o[0] - b * o[1] - c * o[2], w * o[0] - c * o[1] + b * o[2],
                                 c * o[0] + w * o[1] - a * o[2], -b * o[0] + a * o[1] + w * o[2]])
            return list(qd) + list(np.broadcast_to(u, (m,) + rest))

        return fn

    # ------------------------------------------------------------------ the endpoint map
    def endpoint_map(self, basis, x0, T, c):
        """The endpoint map and its Jacobian by Gauss collocation of the attitude alone
        (:func:`acroplan.families.spatial.collocation.endpoint`): the joint angles are polynomials
        of time, so only :math:`q` is integrated, on panels of Gauss nodes where the compiled
        momentum map is evaluated at points; 10-30 times faster than the Taylor integrator of the
        whole state with its variational equations, and as exact (``benchmarks/RESULTS.md``)."""
        from .collocation import endpoint

        return endpoint(self, basis, x0, T, c)

    def sample_map(self, basis, x0, T, c, s):
        """States at normalised times ``s`` by the same collocation, cut at ``s``
        (:func:`acroplan.families.spatial.collocation.sample`)."""
        from .collocation import sample

        return sample(self, basis, x0, T, c, s)

    def prepare_endpoint_map(self) -> bool:
        """Compile the momentum map of this topology (:func:`~acroplan.families.spatial.collocation.compile_map`),
        and with :math:`L \\ne 0` the momentum's Newton kernel and its start (one per process)."""
        from .collocation import NODES, _guess_kernel, _momentum_kernel, compile_map

        compile_map(self)
        compile_map(self, light=True)  # the guesses' fast integration
        if any(self.L):
            _momentum_kernel(NODES)
            _guess_kernel(NODES)
        return True

    # ------------------------------------------------------------------ the state space: SO(3) x R^m
    @property
    def ndx(self) -> int:
        """3 + m: a rotation vector and the joint angles."""
        return 3 + self.n_links - 1

    def diff(self, x0, x1) -> np.ndarray:
        """:math:`(\\log(q_0^{-1} \\otimes q_1),\\ s_1 - s_0)`: the rotation vector in the frame of
        :math:`q_0` (angle in :math:`[0, \\pi]`), then the joint differences; shape (3 + m,)."""
        x0 = np.asarray(x0, dtype=float)
        x1 = np.asarray(x1, dtype=float)
        q0, q1 = x0[:4], x1[:4]
        q0 = q0 / math.sqrt(float(q0 @ q0))
        q1 = q1 / math.sqrt(float(q1 @ q1))
        return np.concatenate([rot.log(rot.qmul(rot.qconj(q0), q1)), x1[4:] - x0[4:]])

    def retract(self, x, dx) -> np.ndarray:
        """:math:`(q \\otimes \\exp(v),\\ s + \\delta s)` for ``dx = (v, \\delta s)``; shape (4 + m,)."""
        x = np.asarray(x, dtype=float)
        dx = np.asarray(dx, dtype=float)
        return np.concatenate([rot.qmul(x[:4], rot.exp(dx[:3])), x[4:] + dx[3:]])

    def tangent_jacobian(self, x, J) -> np.ndarray:
        """Rows of the rotation vector: :math:`\\delta v = 2\\,\\mathrm{vec}(q^{-1} \\otimes \\delta q)`
        for a unit :math:`q`; the joint rows unchanged. ``J`` (4 + m, k) -> (3 + m, k)."""
        w, a, b, c = (float(v) for v in np.asarray(x, dtype=float)[:4])
        Lq = 2.0 * np.array([[-a, w, c, -b], [-b, -c, w, a], [-c, b, -a, w]])
        J = np.asarray(J, dtype=float)
        return np.concatenate([Lq @ J[:4], J[4:]], axis=0)

    # ------------------------------------------------------------------ numeric helpers
    def momentum_map(self, shape) -> tuple[np.ndarray, np.ndarray]:
        """:math:`\\mathbb{I}(s)` and :math:`A(s)` of (1), at one shape or many.

        Parameters
        ----------
        shape : array_like, shape (m,) or (m, N)

        Returns
        -------
        I : numpy.ndarray, shape (3, 3) or (3, 3, N)
        A : numpy.ndarray, shape (3, m) or (3, m, N)

        Evaluated by the topology's compiled map (:func:`~acroplan.families.spatial.collocation.compile_map`,
        heyoka); the lambdified sympy map stays for the independent re-simulation (``verify="ode"``).
        """
        from .collocation import compile_map, evaluate_map

        s = self._shape(shape)
        m = self.n_links - 1
        rest = s.shape[1:]
        S = s.reshape(m, -1)
        out = evaluate_map(self, compile_map(self, light=True), np.concatenate([S, np.zeros_like(S)]))
        I = out[9:15][[0, 1, 2, 1, 3, 4, 2, 4, 5]].reshape((3, 3) + rest)  # noqa: E741
        A = out[15:15 + 3 * m].reshape((m, 3) + rest).swapaxes(0, 1)
        return I, A

    def locked_inertia(self, shape) -> np.ndarray:
        """:math:`\\mathbb{I}(s)` (root frame, about the centre of mass), shape (3, 3) or (3, 3, N)."""
        return self.momentum_map(shape)[0]

    def angular_velocity(self, state, u) -> np.ndarray:
        """:math:`\\Omega = \\mathbb{I}^{-1}(R^\\top L - A u)` (root frame), shape (3,)."""
        x = np.asarray(state, dtype=float)
        I, A = self.momentum_map(x[4:])  # noqa: E741
        R = rot.to_matrix(x[:4] / np.linalg.norm(x[:4]))
        return np.linalg.solve(I, R.T @ self.angular_momentum - A @ np.asarray(u, dtype=float))

    def momentum(self, state, omega, u) -> np.ndarray:
        """The angular momentum :math:`L = R(q)(\\mathbb{I}\\Omega + A u)` (inertial), shape (3,)."""
        x = np.asarray(state, dtype=float)
        I, A = self.momentum_map(x[4:])  # noqa: E741
        return rot.to_matrix(x[:4]) @ (I @ np.asarray(omega, dtype=float) + A @ np.asarray(u, dtype=float))

    def link_poses(self, state):
        """Every link's orientation and position in the inertial frame, the centre of mass at the
        origin (plain kinematics of the link table, for drawings and checks).

        Parameters
        ----------
        state : array_like, shape (4 + m,)

        Returns
        -------
        rotations : numpy.ndarray, shape (n_links, 3, 3)
            Link frame to inertial.
        origins : numpy.ndarray, shape (n_links, 3)
            Each link frame's origin (its joint; the root's reference point).
        coms : numpy.ndarray, shape (n_links, 3)
            Each link's centre of mass.
        """
        x = np.asarray(state, dtype=float)
        if x.shape != (self.n_states,):
            raise InvalidInputError("state", f"must have shape ({self.n_states},) {list(self.state_names)}, got "
                                    f"{x.shape}", "give the quaternion and every joint angle")
        R = rot.to_matrix(x[:4] / np.linalg.norm(x[:4]))
        Rs, org, coms = _link_frames(self.links, x[4:])
        Rs, org, coms = np.einsum("ij,kjl->kil", R, Rs), org @ R.T, coms @ R.T
        mass = np.array([link.mass for link in self.links])
        c = mass @ coms / mass.sum()
        return Rs, org - c, coms - c

    # ------------------------------------------------------------------ planning hooks
    def check_segment(self, x0, x1, duration, limits=None):
        """Checks of one segment: the waypoints' quaternions must be unit (to :data:`NORM_TOL`;
        raises :class:`InvalidInputError` otherwise, naming ``attitude``); under limits, the joint
        ends must lie in the joint limits and a rate-limited joint cannot move more than
        :math:`\\bar u_j T`. Otherwise ``None`` (the segment may be feasible)."""
        for end, x in (("start", x0), ("end", x1)):
            nq = float(np.linalg.norm(np.asarray(x, dtype=float)[:4]))
            if abs(nq - 1.0) > NORM_TOL:
                raise InvalidInputError("attitude", f"the {end} quaternion (qw, qx, qy, qz) of a segment has norm "
                                        f"{nq:.12g}, not 1", "give unit quaternions (acroplan.families.spatial."
                                        "rotations.as_quaternion normalises and converts other forms)")
        return self.joint_ends_infeasibility(x0, x1, duration, limits)

    def state_unit(self, state):
        """The quaternion's components have no unit; the joint angles are in ``"rad"``."""
        return "" if state in ("qw", "qx", "qy", "qz") else "rad"

    def display_states(self, X, *, degrees: bool = False):
        """The attitude as Yeadon's somersault, tilt and twist (:func:`~acroplan.families.spatial.
        rotations.to_euler`, unwrapped along the columns; labelled ``"attitude: somersault"``, ...),
        then the joint angles; in radians, or degrees with ``degrees``."""
        X = np.asarray(X, dtype=float)
        E = np.unwrap(np.radians(rot.to_euler(X[:4], "yeadon")), axis=1)
        unit = "deg" if degrees else "rad"
        conv = np.degrees if degrees else (lambda v: v)
        return ([(f"attitude: {name}", conv(E[k]), unit, None) for k, name in enumerate(rot.EULER_NAMES)]
                + [(name, conv(X[4 + j]), unit, name) for j, name in enumerate(self.links.joint_names)])

    #: The optimal strategies' second start, path deformation from the minimum-norm input
    #: (:mod:`acroplan.core.optimal`, Starts), is left out for spatial bodies: at L = 0 that input
    #: (u = 0) is a singular control, and at L != 0 its deformation integrates wild trial inputs
    #: (bioptim's trunk with two arms: 10 evaluations, 10 s, no feasible start; issue #22).
    optimal_deform_start = False

    #: The optimal strategies' ladders of basis sizes by objective, when they are given none
    #: (:mod:`acroplan.core.optimal`, Basis size). The least integral of u^2 climbs 6, 14, 30: on
    #: the falling cat (joint ranges binding), the trunk and 12 random 3-5 link segments of the zoo
    #: no ladder stopped before 30 (the optimum still changing by 1e-4), and 6, 14, 30 reached the
    #: same optima in fewer endpoint evaluations (cat with free end rates 150 -> 94, at rest 103
    #: -> 82, trunk 147 -> 126, the random segments 1073 -> 907, the twisting somersault 534 both;
    #: ``benchmarks/RESULTS.md``, 2026-12-06, tenth session).
    #: The least integral of tau^2 steps by 4 from 14
    #: coefficients. Its optimum moves far between sizes (the torque involves the joint
    #: accelerations): the falling cat's fell from 1.72 at 14 coefficients to 0.71 or 0.84 at 20,
    #: and from the smaller optimum padded, a start that far off, the ladder ended at one of three
    #: local optima (0.483, 0.495, 0.623) as the last bits of the arithmetic fell (over eight
    #: durations differing by 1e-10 s: two ended at KKT residuals of 1.8e-3 and 1.7e-2; with
    #: the attitude's complex systems, equal to 1.7e-15, the default duration at 0.623, above
    #: CasADi's 0.569); by steps of 4 at 0.4825-0.4830 eight times in eight, KKT residuals below
    #: 1e-8, in 1.2 s against 1.4-1.8 s; the dives' optima the same, their times within the noise.
    #: A size costs a spatial body no compilation (its endpoint map is compiled once for every
    #: size), where the Taylor-integrated families compile one integrator per size; they keep the
    #: default ladder. An interval whose optimum starts the joint optimum of several intervals (key
    #: ``"joint"``, either objective) climbs 6, 30: its sizes are the joint optimum's warm start,
    #: which re-optimises every interval at its ladder's last size. On the bundled dives the optima
    #: were the same to 1e-6 with 6, 14, 30, with 6, 30, with 6, 18, 30 and with 6, 12, 20, 30 as
    #: with the default ladder, in fewer endpoint evaluations (back full 336 -> 268, double
    #: full-out 566 -> 447, forward 729 -> 716) (``benchmarks/RESULTS.md``, 2026-12-06, ninth
    #: session), and 6, 14, 30 was taken; since the intervals' optima are only the joint optimum's
    #: provisional start (:data:`acroplan.core.optimal.PROVISIONAL_STARTS`), 6, 30 reaches the same
    #: optima in fewer (164 -> 146, 210 -> 191, 427 -> 386; 10, 30 sent the forward dive to a local
    #: optimum 4.7% higher: ``benchmarks/RESULTS.md``, nineteenth session, item 4).
    optimal_sizes = {"energy": (6, 14, 30), "torque": (6, 10, 14, 18, 22, 26, 30), "joint": (6, 30)}

    def auto_strategy(self):
        """``method="auto"``: path deformation from shape loops that meet the target
        (:class:`~acroplan.families.spatial.strategy.SpatialAuto`)."""
        from .strategy import SpatialAuto

        return SpatialAuto()

    # ------------------------------------------------------------------ records
    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "SpatialBody":
        """Rebuild from :meth:`to_dict`'s output (``links`` and ``L``)."""
        return cls(SpatialLinkTable(cls._links_of(d)), L=tuple(d.get("L", (0.0, 0.0, 0.0))))


_ = SpatialLink  # re-exported through the package
