"""First guesses for spatial bodies: a joint motion plus a shape loop whose net rotation points
toward the target.

The momentum connection
-----------------------
With (1)-(2) of :mod:`~acroplan.families.spatial.model`, the root turns at
:math:`\\Omega = \\mathbb{I}^{-1} R^\\top L - \\mathcal{A}(s)\\,\\dot s`, :math:`\\mathcal{A} =
\\mathbb{I}^{-1} A` (3 x m, the *momentum connection*). At :math:`L = 0` the attitude depends on the
shape path alone, and a small closed loop of signed area :math:`\\varepsilon` in the plane of joints
:math:`(s_i, s_j)` (counter-clockwise positive) turns the body, in its own frame, by the rotation
vector :math:`\\varepsilon\\,F_{ij}(s)` to leading order, with the *curvature*

.. math::  F_{ij} = -(\\partial_i \\mathcal{A}_j - \\partial_j \\mathcal{A}_i) + \\mathcal{A}_i \\times \\mathcal{A}_j

(:func:`curvature`; the sign of the bracket is that of the right-invariant kinematics
:math:`\\dot q = \\tfrac12 q \\otimes (0, \\Omega)`, and ``tests/test_spatial_planning.py`` checks it
against the holonomy of small loops). The minimum-norm input :math:`u = 0` is a singular control at
:math:`L = 0` (the attitude moves at second order in :math:`u`), so path deformation starts from a
real loop.

The guess
---------
1. **Base motion** :math:`s_h(\\sigma)`, :math:`\\sigma = t/T`: per joint the lowest-degree polynomial
   meeting the end values and the input conditions
   (:func:`acroplan.families.planar.guess.base_motion`); its endpoint (compiled integrator) misses
   the target attitude by the rotation vector :math:`r` (end frame).
2. **Where the loop goes**: at mid-time :math:`\\sigma = 1/2`; a body-frame rotation :math:`\\delta`
   there reaches the end as :math:`R(Q)^\\top \\delta` (:math:`Q = q(1/2)^{-1} q(1)`: exact at
   :math:`L = 0`, where later motion is left-invariant), so the loop must turn by
   :math:`\\delta = R(Q)\\, r`.
3. **The loop**: the teardrop :math:`\\delta s(\\sigma) = \\hat w(\\sigma)\\,(a + (2\\sigma - 1)\\, b)`,
   :math:`\\hat w = w / \\max w`, :math:`w = \\sigma^\\alpha (1 - \\sigma)^\\beta` (:math:`\\alpha,
   \\beta` one more than the conditions at each end, so the conditions still hold), whose
   projection on the plane :math:`(i, j)` encloses the area :math:`(a_i b_j - a_j b_i)
   \\int_0^1 \\hat w^2`; so it turns the body by about :math:`\\sum_{i<j} F_{ij}\\,(a \\wedge b)_{ij}
   \\int \\hat w^2`. The bivector :math:`B = a \\wedge b` is the least-squares solution of
   :math:`\\sum_{i<j} F_{ij} B_{ij} \\int \\hat w^2 = \\delta` (minimum norm), made decomposable by
   its best rank-two part (exact for up to three joints), and :math:`a, b` span that plane (a
   canonical orthonormal pair of it: :func:`_decomposable`).
4. Variants: the loop on the other side (:math:`a \\to -a`, :math:`b \\to -b`, the same area), and
   loops offset along each joint whose turn vector makes the turn best.
5. **Ranking**: every variant at every pair of amplitudes (:data:`AMPLITUDES`; 810 candidates for
   four joints) is integrated by the fast Runge-Kutta scheme (:func:`fast_attitudes`), and ranked
   by its attitude error (the joint and rate limits kept first, the smaller loop first among equal
   errors to 0.01 rad). The candidates are screened first with :data:`SCREEN_STEPS` steps, and the
   :data:`SCREENED` best of that ranking are integrated again with :data:`FAST_STEPS` and ranked on
   those: the same guesses, in the same order, as ranking every candidate with :data:`FAST_STEPS`
   on 179 of 180 random chains (``benchmarks/RESULTS.md``, 2026-12-07), for half the points of the
   compiled map, which was a quarter of a random body's plan.

Path deformation (:func:`acroplan.core.strategies.deform_attempt`) then polishes a guess to the
target; the guess only has to be non-singular and close.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import threading

import numpy as np

from ...core import backend
from ..tree.loops import END_KEYS as _KEYS
from ..tree.loops import GAUSS_S as _SG
from ..tree.loops import GAUSS_W as _WSG
from ..tree.loops import base_motion
from ..tree.loops import projector as _projector
from . import rotations as rot

__all__ = ["Connection", "curvature", "fast_attitudes", "LoopGuess", "loop_guesses", "refine", "AMPLITUDES",
           "FAST_STEPS", "SCREEN_STEPS", "SCREENED", "CORRECTOR_STALL"]


class Connection:
    """:math:`\\mathcal{A}(s) = \\mathbb{I}(s)^{-1} A(s)` of one body at many shapes.

    Parameters
    ----------
    body : SpatialBody
    """

    def __init__(self, body):
        self.body = body
        self.m = body.n_inputs

    def __call__(self, S) -> np.ndarray:
        """:math:`\\mathcal{A}` at shapes ``S`` of shape ``(m, N)``; returns shape ``(3, m, N)``."""
        from .collocation import compile_map, evaluate_map

        S = np.asarray(S, dtype=float).reshape(self.m, -1)
        m, N = S.shape
        out = evaluate_map(self.body, compile_map(self.body), np.concatenate([S, np.zeros((m, N))]))
        return out[9:9 + 3 * m].reshape(m, 3, N).swapaxes(0, 1)


def curvature(conn: Connection, S, h: float = 1e-5) -> np.ndarray:
    """:math:`F_{ij}` (module docstring) for every pair :math:`i < j` at shapes ``S`` (``(m, N)``),
    by central differences of step ``h``.

    Returns
    -------
    numpy.ndarray, shape (3, P, N)
        ``P = m (m - 1) / 2`` pairs in the order (0, 1), (0, 2), ..., (1, 2), ...
    """
    S = np.asarray(S, dtype=float).reshape(conn.m, -1)
    m, N = S.shape
    pts = [S]
    for k in range(m):
        E = np.zeros((m, 1))
        E[k] = h
        pts += [S + E, S - E]
    vals = conn(np.concatenate(pts, axis=1)).reshape(3, m, 1 + 2 * m, N)
    A0 = vals[:, :, 0]
    dA = [(vals[:, :, 1 + 2 * k] - vals[:, :, 2 + 2 * k]) / (2 * h) for k in range(m)]  # d/ds_k, (3, m, N)
    out = []
    for i in range(m):
        for j in range(i + 1, m):
            out.append(-(dA[i][:, j] - dA[j][:, i]) + np.cross(A0[:, i], A0[:, j], axis=0))
    return np.stack(out, axis=1) if out else np.zeros((3, 0, N))


#: Runge-Kutta steps per call of the compiled step kernel (:func:`_rk4_kernel`)
KERNEL_STEPS = 8


@functools.cache
def _rk4_compiled(steps: int, drift: bool):
    """:func:`_build_rk4_kernel`, compiled once per process and kept on disk
    (:func:`acroplan.core.backend.compile_once`); it knows no body."""
    return backend.compile_once(("spatial-rk4-attitude", 1, int(steps), bool(drift)),
                                lambda: _build_rk4_kernel(int(steps), bool(drift)))


_LOCAL = threading.local()


def _rk4_kernel(steps: int, drift: bool):
    """This thread's own copy of :func:`_rk4_compiled` (a compiled function is not called from two
    threads at once, as :func:`~acroplan.families.spatial.collocation.compile_map`)."""
    mine = getattr(_LOCAL, "kernels", None)
    if mine is None:
        mine = _LOCAL.kernels = {}
    own = mine.get((steps, drift))
    if own is None:
        own = mine[(steps, drift)] = copy.copy(_rk4_compiled(steps, drift))
    return own


def _build_rk4_kernel(steps: int, drift: bool):
    """``steps`` steps of the classical Runge-Kutta scheme of :func:`fast_attitudes`, compiled (a
    ``heyoka.cfunc``, one column a motion). Inputs, flat: :math:`q` (4), then at each of the
    :math:`2\\,\\text{steps} + 1` grid points the shape's rate :math:`-\\mathbb{I}^{-1} A s'` (3) and,
    with ``drift``, the upper triangle of :math:`\\mathbb{I}^{-1}` (6). Parameters: the step
    :math:`h` and, with ``drift``, :math:`T L` (3). Output: :math:`q` after the steps (4, not normalised). The
    body's rate is :math:`\\Omega = -\\mathbb{I}^{-1} A s' + \\mathbb{I}^{-1} R(q)^\\top T L`, with
    :math:`R(q)^\\top L` the quadratic form of the model's fields (:func:`collocation_parts._quad`),
    so the numbers are those of the same scheme in numpy up to the order of the operations."""
    import heyoka as hy

    from .collocation_parts import _QUAD

    per = 9 if drift else 3
    v = hy.make_vars(*[f"v{i}" for i in range(4 + (2 * steps + 1) * per)])
    h, L = hy.par[0], [hy.par[1], hy.par[2], hy.par[3]]
    pts = [v[4 + per * k:4 + per * (k + 1)] for k in range(2 * steps + 1)]

    def f(q, k):
        ox, oy, oz = pts[k][:3]
        if drift:
            lv = []  # (R(q)^T L)_i = sum_l L_l q^T Q_il q, over the pairs a <= b
            for i in range(3):
                terms = []
                for a in range(4):
                    for b in range(a, 4):
                        c = [float(_QUAD[i, l, a, b] + (_QUAD[i, l, b, a] if b != a else 0.0)) for l in range(3)]
                        if any(c):
                            terms.append((c[0] * L[0] + c[1] * L[1] + c[2] * L[2]) * (q[a] * q[b]))
                lv.append(sum(terms[1:], terms[0]))
            I0, I1, I2, I3, I4, I5 = pts[k][3:]
            ox = ox + I0 * lv[0] + I1 * lv[1] + I2 * lv[2]
            oy = oy + I1 * lv[0] + I3 * lv[1] + I4 * lv[2]
            oz = oz + I2 * lv[0] + I4 * lv[1] + I5 * lv[2]
        w, x, y, z = q
        return [0.5 * -(x * ox + y * oy + z * oz), 0.5 * (w * ox + y * oz - z * oy),
                0.5 * (w * oy - x * oz + z * ox), 0.5 * (w * oz + x * oy - y * ox)]

    q = list(v[:4])
    for step in range(steps):
        k = 2 * step
        k1 = f(q, k)
        k2 = f([q[i] + 0.5 * h * k1[i] for i in range(4)], k + 1)
        k3 = f([q[i] + 0.5 * h * k2[i] for i in range(4)], k + 1)
        k4 = f([q[i] + h * k3[i] for i in range(4)], k + 2)
        q = [q[i] + (h / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) for i in range(4)]
    return hy.cfunc(q, list(v))


def fast_attitudes(body, q0, T: float, S, dS) -> np.ndarray:
    """End attitudes of many joint motions at once, by the classical Runge-Kutta scheme (for
    guesses: error about :math:`h^4`, :math:`h` the step; not a check).

    The joint motions are sampled on the uniform grid :math:`\\sigma_k = k/(2N)`,
    :math:`k = 0, \\dots, 2N` (the steps and their midpoints), and
    :math:`dq/d\\sigma = \\tfrac12 \\Xi(q)\\,\\mathbb{I}(s)^{-1}(T R(q)^\\top L - A(s)\\, s')`.
    The steps run in a compiled kernel (:func:`_build_rk4_kernel`), :data:`KERNEL_STEPS` a call,
    every motion a column.

    Parameters
    ----------
    body : SpatialBody
    q0 : array_like, shape (4,)
    T : float
    S, dS : array_like, shape (m, K, 2N + 1)
        Shapes and their derivatives in :math:`\\sigma` of ``K`` motions.

    Returns
    -------
    numpy.ndarray, shape (4, K)
    """
    from .collocation import CHUNK, compile_map, evaluate_map

    S = np.asarray(S, dtype=float)
    dS = np.asarray(dS, dtype=float)
    m, K, M = S.shape
    fn = compile_map(body, light=True)
    Lv = T * np.asarray(body.angular_momentum, dtype=float)
    drift = bool(np.linalg.norm(Lv) > 0)
    # per grid point: the shape's rate -I^-1 A s' (3) and, with drift, I^-1's upper triangle (6);
    # (M, per, K), so that the points of a kernel call are one contiguous block. The map is
    # evaluated a few grid points a call (every motion's column at each), and each call's outputs
    # go straight to their rows of G: no array of every output at every point
    G = np.empty((M, 9 if drift else 3, K))
    X = np.concatenate([S, dS]).transpose(2, 0, 1)  # (M, 2m, K)
    at = max(1, CHUNK // K)
    for j in range(0, M, at):
        e = min(M, j + at)
        out = evaluate_map(body, fn, X[j:e].transpose(1, 0, 2).reshape(2 * m, -1)).reshape(fn.nouts, e - j, K)
        np.negative(out[6:9].transpose(1, 0, 2), out=G[j:e, :3])
        if drift:
            G[j:e, 3:] = out[:6].transpose(1, 0, 2)
    N = (M - 1) // 2
    h = 1.0 / N
    params = (h, float(Lv[0]), float(Lv[1]), float(Lv[2])) if drift else (h,)
    q = np.ascontiguousarray(np.tile(np.asarray(q0, dtype=float)[:, None], (1, K)))  # (4, K)
    step = 0
    while step < N:
        s = min(KERNEL_STEPS, N - step)
        x = np.concatenate([q, G[2 * step:2 * (step + s) + 1].reshape(-1, K)])
        q = backend.evaluate_columns(_rk4_kernel(s, drift), x, params, CHUNK)
        step += s
    with np.errstate(over="ignore", invalid="ignore"):  # wild candidates blow up: ranked last (NaN)
        return q / np.linalg.norm(q, axis=0)[None, :]


@dataclasses.dataclass(frozen=True)
class LoopGuess:
    """A start for path deformation (module docstring).

    Attributes
    ----------
    coefficients : numpy.ndarray, shape (m, n)
    kind : str
        ``"base"`` or ``"loop"``.
    a, b : numpy.ndarray, shape (m,)
        The teardrop's offset and turn vectors (zero for the base motion).
    predicted_error : float
        The attitude error (rad) of the fast integration (:func:`fast_attitudes`).
    compliant : bool
        The joint limits hold on the grid, and the rate limits with a margin of 1%.
    """

    coefficients: np.ndarray
    kind: str
    a: np.ndarray
    b: np.ndarray
    predicted_error: float
    compliant: bool = True
    #: the coefficients of unit vectors :math:`v_k` of :math:`\\hat w \\sum_k P_k(2\\sigma - 1) v_k`
    #: (:math:`v_0 = a`, :math:`v_1 = b`), shape (m n, (d + 1) m) (:func:`refine`)
    subspace: np.ndarray | None = None
    #: the base motion's coefficients, shape (m, n)
    base: np.ndarray | None = None

    def describe(self) -> str:
        if self.kind == "base":
            return "base motion"
        return (f"shape loop (offset {np.linalg.norm(self.a):.3g} rad, turn {np.linalg.norm(self.b):.3g} rad, "
                f"predicted error {self.predicted_error:.2g} rad)")


@functools.lru_cache(maxsize=16)
def _weights(alpha: int, beta: int, N: int):
    """Normalised teardrop weight and its derivative at the 64 Gauss nodes and on the uniform
    grid of 2N + 1 points, and :math:`\\int_0^1 \\hat w^2`."""
    sm = alpha / (alpha + beta)
    wmax = sm**alpha * (1 - sm) ** beta
    out = []
    for s in (_SG, np.linspace(0.0, 1.0, 2 * N + 1)):
        w = s**alpha * (1 - s) ** beta / wmax
        dw = (alpha * s ** (alpha - 1) * (1 - s) ** beta - beta * s**alpha * (1 - s) ** (beta - 1)) / wmax
        out += [w, dw]
    return tuple(out) + (float(_WSG @ (out[0] * out[0])),)


def _decomposable(Bv, m: int):
    """Unit ``a, b`` and a scale with :math:`\\text{scale}\\, a \\wedge b` the best rank-two part of
    the bivector ``Bv`` (pairs i < j).

    The plane of :math:`a, b` is that of the two largest singular values of the skew matrix of
    ``Bv`` (they come in equal pairs), but the singular value decomposition returns *any*
    orthonormal pair of a repeated singular value: which one is decided by rounding, so a change
    in the last bits of ``Bv`` (another processor, another order of the same sums) turned the
    loop's offset :math:`a` by a quarter turn in its plane and changed the plan. The pair is made
    canonical: :math:`a` is the projection on the plane of the joint axis :math:`e_k` that
    projects longest (the first within 1e-9 of the longest), :math:`b` the unit vector of the plane
    orthogonal to it, with the sign of :math:`a^\\top B\\, b`."""
    Bm = np.zeros((m, m))
    k = 0
    for i in range(m):
        for j in range(i + 1, m):
            Bm[i, j], Bm[j, i] = Bv[k], -Bv[k]
            k += 1
    U, _, _ = np.linalg.svd(Bm)
    P = U[:, :2]
    proj = P @ P.T  # the plane's projector; its columns are the axes' projections
    lengths = np.sqrt(np.einsum("ij,ij->j", proj, proj))
    axis = int(np.flatnonzero(lengths >= lengths.max() - 1e-9)[0])
    a = proj[:, axis] / lengths[axis]
    b0 = P[:, int(np.argmin(np.abs(P.T @ a)))]
    b = b0 - (b0 @ a) * a
    b /= np.linalg.norm(b)
    beta = float(a @ Bm @ b)
    return a, (1.0 if beta >= 0 else -1.0) * b, abs(beta)


#: amplitudes (rad) of the loops' offset and turn vectors tried by :func:`loop_guesses`
AMPLITUDES = (0.15, 0.3, 0.5, 0.75, 1.0, 1.3, 1.6, 2.0, 2.5)
#: Runge-Kutta steps of the fast integration
FAST_STEPS = 48
#: Runge-Kutta steps of the screening of the loop candidates (a divisor of :data:`FAST_STEPS`: the
#: same grid's every other point; module docstring, step 5)
SCREEN_STEPS = 24
#: Candidates the screening keeps for :data:`FAST_STEPS`
SCREENED = 24
#: :func:`refine` corrects its trial steps after a step that left more than this fraction of the error
CORRECTOR_STALL = 0.5


def loop_guesses(body, basis, x0, x1, T: float, ends: dict | None = None, limits=None, *,
                 conn: Connection | None = None, keep: int = 3):
    """Guesses for one segment, best first (module docstring).

    Parameters
    ----------
    body : SpatialBody
    basis : InputBasis
        The basis (family and size) the coefficients are made for.
    x0, x1 : array_like, shape (4 + m,)
    T : float
    ends : dict, optional
        Input conditions (``u0``, ``du0``, ``uT``, ``duT``).
    limits : Limits, optional
        Guesses that keep them come first.
    keep : int
        How many loops to return.

    Returns
    -------
    list of LoopGuess
        The best loops (when they fit in the basis and the body has two joints or more) by the
        fast integration's attitude error, compliant ones first, then the base motion; empty when
        not even the base motion fits.
    """
    ends = {k: v for k, v in (ends or {}).items() if k in _KEYS}
    conn = conn or Connection(body)
    m, n = body.n_inputs, basis.n
    x0 = np.asarray(x0, dtype=float)
    x1 = np.asarray(x1, dtype=float)
    left = sum(k in ends for k in ("u0", "du0"))
    alpha, beta = 1 + left, 1 + len(ends) - left
    if n < alpha + beta - 1:
        return []
    P = _projector(type(basis), n)
    N = FAST_STEPS
    grid = np.linspace(0.0, 1.0, 2 * N + 1)
    qh = base_motion(x0[4:], x1[4:], T, ends)  # power coefficients in sigma, (m, deg + 1)
    dqh = qh[:, 1:] * np.arange(1, qh.shape[1]) if qh.shape[1] > 1 else np.zeros((m, 1))
    dSH = np.polynomial.polynomial.polyval(_SG, dqh.T) if dqh.size else np.zeros((m, _SG.size))
    SHg = np.polynomial.polynomial.polyval(grid, qh.T)
    dSHg = np.polynomial.polynomial.polyval(grid, dqh.T) if dqh.size else np.zeros((m, grid.size))
    c_base = (dSH / T) @ P.T
    lo, hi, U = body.joint_bounds(limits)

    q_base = fast_attitudes(body, x0[:4], T, SHg[:, None, :], dSHg[:, None, :])[:, 0]
    err_base = rot.angle_between(q_base, x1[:4])
    base = LoopGuess(c_base, "base", np.zeros(m), np.zeros(m), err_base,
                     bool(np.all(SHg.min(axis=1) >= lo) and np.all(SHg.max(axis=1) <= hi)
                          and np.all(np.abs(dSHg).max(axis=1) <= 0.99 * U * T)))
    if m < 2 or n < alpha + beta + 1:
        return [base]
    wG, dwG, wg, dwg, W2 = _weights(alpha, beta, N)
    Ksub = _refinement_subspace(m, n, alpha, beta, T, P, wG, dwG)
    # the turn a loop at mid-time must make (module docstring), in the mid-time body frame
    # (the first half on its own normalised time: half the duration, half the rates; N is even)
    q_mid = fast_attitudes(body, x0[:4], T / 2, SHg[:, None, :N + 1], 0.5 * dSHg[:, None, :N + 1])[:, 0]
    r = rot.log(rot.qmul(rot.qconj(q_base), x1[:4]))
    delta = rot.to_matrix(rot.qmul(rot.qconj(q_mid), q_base)) @ r
    dirs = _loop_directions(conn, SHg[:, N], delta, W2, m)
    amps = np.array(AMPLITUDES)
    Ad = np.array([d[0] for d in dirs])  # (D, m)
    Bd = np.array([d[1] for d in dirs])
    # every direction at every pair of amplitudes (a's, b's)
    Av = (Ad[:, None, None, :] * amps[None, :, None, None] + 0.0 * amps[None, None, :, None]).reshape(-1, m).T
    Bv = (Bd[:, None, None, :] * amps[None, None, :, None] + 0.0 * amps[None, :, None, None]).reshape(-1, m).T
    xg = 2 * grid - 1
    size = np.sqrt(np.sum(Av**2, axis=0) + np.sum(Bv**2, axis=0))

    def shapes(which, at):  # the candidates ``which`` on the grid's points ``at``: S, dS (m, K, points)
        Y = Av[:, which, None] + xg[None, None, at] * Bv[:, which, None]  # a + (2 sigma - 1) b
        return (SHg[:, None, at] + wg[None, None, at] * Y,
                dSHg[:, None, at] + dwg[None, None, at] * Y + 2.0 * wg[None, None, at] * Bv[:, which, None])

    every = np.arange(Av.shape[1])
    full = slice(None)
    S = dS = None
    if np.all(np.isinf(lo)) and np.all(np.isinf(hi)) and np.all(np.isinf(U)):
        ok = np.ones(every.size, dtype=bool)  # no range or rate to keep: every candidate keeps them
    else:
        S, dS = shapes(every, full)
        ok = np.all(S.min(axis=2) >= lo[:, None], axis=0) & np.all(S.max(axis=2) <= hi[:, None], axis=0) \
            & np.all(np.abs(dS).max(axis=2) <= 0.99 * U[:, None] * T, axis=0)

    def errors(qe):  # the attitude error (rad) of end attitudes (4, K); NaN (a wild candidate): inf
        rel = rot.qmul(rot.qconj(x1[:4] / np.linalg.norm(x1[:4])), qe)  # (4, K), unit
        with np.errstate(invalid="ignore"):
            e = 2.0 * np.arctan2(np.linalg.norm(rel[1:], axis=0), np.abs(rel[0]))
        return np.where(np.isfinite(e), e, np.inf)

    def ranked(e, among):  # compliant first, then the error, then the size
        return among[np.lexsort((size[among], np.round(e[among], 2), ~ok[among]))]

    def attitudes(which, at):  # the fast integration of the candidates ``which`` on the points ``at``
        if S is None:  # made for these points alone (the same numbers as the full arrays' entries)
            return fast_attitudes(body, x0[:4], T, *shapes(which, at))
        if which is not every:
            return fast_attitudes(body, x0[:4], T, S[:, which][:, :, at], dS[:, which][:, :, at])
        return fast_attitudes(body, x0[:4], T, S[:, :, at], dS[:, :, at])

    if every.size > SCREENED:
        # the screening (module docstring): every candidate by SCREEN_STEPS steps, the best
        # SCREENED of that ranking again by FAST_STEPS, and ranked on those
        coarse = errors(attitudes(every, slice(None, None, N // SCREEN_STEPS)))
        among = ranked(coarse, every)[:SCREENED]
        err = np.full(every.size, np.inf)
        err[among] = errors(attitudes(among, full))
    else:
        among = every
        err = errors(attitudes(every, full))
    order = ranked(err, among)
    out, seen = [], []
    for k in order:
        a, b = Av[:, k], Bv[:, k]
        if any(_close(a, a2) and _close(b, b2) for a2, b2 in seen):
            continue
        seen.append((a, b))
        c = c_base + (Ksub[:, :2 * m] @ np.concatenate([a, b])).reshape(m, n)
        out.append(LoopGuess(c, "loop", a, b, float(err[k]), bool(ok[k]), Ksub, c_base))
        if len(out) >= keep:
            break
    return out + [base]


def _close(x, y) -> bool:
    """``numpy.allclose(x, y)`` (its default tolerances) for finite vectors, without its overhead."""
    return bool(np.all(np.abs(x - y) <= 1e-8 + 1e-5 * np.abs(y)))


def _refinement_subspace(m: int, n: int, alpha: int, beta: int, T: float, P, wG, dwG) -> np.ndarray:
    """The loop refinement's subspace in the coefficients, shape (m n, (degree + 1) m): the joint
    offsets :math:`w(x)(v_0 + x v_1 + P_2(x) v_2 + P_3(x) v_3)` (as many Legendre terms as fit in
    the basis beside the end conditions), ``c = c_base + K (v_0, v_1, ...)``; :math:`v_0 = a`,
    :math:`v_1 = b` of a loop."""
    degree = min(3, n - 1 - (alpha + beta))
    Pl, dPl = _legendre_at_nodes(degree)
    K = np.zeros((m * n, (degree + 1) * m))
    for k in range(degree + 1):
        # joint i's offset P_k has the coefficients of row i of (d / T) P^T, d that offset's rates at
        # the nodes (row i, zero elsewhere): every joint's row in one product of the same shape
        # (the same numbers as m products of one nonzero row each)
        d = np.tile(dwG * Pl[k] + wG * dPl[k], (m, 1))
        R = (d / T) @ P.T  # (m, n)
        for i in range(m):
            K[i * n:(i + 1) * n, k * m + i] = R[i]
    return K


@functools.cache
def _legendre_at_nodes(degree: int):
    """:math:`P_k(2\\sigma - 1)` and its derivative in :math:`\\sigma` at the 64 Gauss nodes, ``k = 0 ..
    degree``, each shape (degree + 1, 64), read-only."""
    xG = 2 * _SG - 1
    eye = np.eye(degree + 1)
    Pl = np.array([np.polynomial.legendre.legval(xG, eye[k]) for k in range(degree + 1)])
    dPl = np.array([2.0 * np.polynomial.legendre.legval(xG, np.polynomial.legendre.legder(eye[k]))
                    for k in range(degree + 1)])
    Pl.setflags(write=False)
    dPl.setflags(write=False)
    return Pl, dPl


def _loop_directions(conn, mid, delta, W2, m: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """Loop directions ``(a, b)`` about the mid-time shape ``mid`` (m,) for the turn ``delta`` (3,):
    the curvature's least-squares bivector (both senses; :func:`_decomposable`), and a loop offset
    along each joint, each sense, whose ``b`` makes the turn best."""
    # the curvature at the mid-time shape and half a radian off it along each joint, each sense:
    # one call of the compiled map for all 1 + 2 m shapes
    offsets = [np.zeros(m)]
    for k in range(m):
        for sgn in (1.0, -1.0):
            offsets.append(np.zeros(m))
            offsets[-1][k] = sgn
    Fall = curvature(conn, np.stack([mid + 0.5 * o for o in offsets], axis=1)) * W2  # (3, P, 1 + 2 m)
    a, b, _ = _decomposable(np.linalg.lstsq(Fall[:, :, 0], delta, rcond=1e-10)[0], m)
    dirs = [(a, b), (-a, -b)]
    pairs = [(i, j) for i in range(m) for j in range(i + 1, m)]
    for at, a in enumerate(offsets[1:], start=1):
        Fk = Fall[:, :, at]
        M = np.zeros((3, m))  # turn of a ^ b as a linear map of b
        for p, (i, j) in enumerate(pairs):
            M[:, j] += Fk[:, p] * a[i]
            M[:, i] -= Fk[:, p] * a[j]
        bv = np.linalg.lstsq(M, delta, rcond=1e-10)[0]
        nb = np.linalg.norm(bv)
        if nb > 0:
            dirs += [(a, bv / nb)]
    return dirs


def refine(body, basis, x0, x1, T: float, guess: LoopGuess, *, budget: int = 30, tol: float = 1e-12,
           limits=None):
    """Gauss-Newton on the loop's vectors :math:`z = (v_0, \\dots, v_d)` of
    :math:`\\delta s = \\hat w(\\sigma) \\sum_k P_k(2\\sigma - 1)\\, v_k` (Legendre polynomials
    :math:`P_k`, :math:`d \\le 3` as the basis allows; the teardrop is :math:`v_0 = a`,
    :math:`v_1 = b`, the rest 0): :math:`(d + 1) m` unknowns, the attitude's 3 equations (the
    joints end on target whatever :math:`z`); the shortest steps with :math:`J_z\\, \\delta z = r`,
    :math:`r` the attitude's rotation vector to the target and :math:`J_z` its Jacobian (compiled
    integrator, tangent space), with backtracking. After a step that stalled (:math:`|r|` down by
    less than the factor :data:`CORRECTOR_STALL`), a trial step that does not reduce :math:`|r|` is
    first corrected: one more step from the trial point with the trial point's own Jacobian, no
    longer than the trial step, kept when it ends below the current :math:`|r|`. With
    :math:`L \\ne 0` the Jacobian can be ill-conditioned (the twisting somersault: singular values
    2.3, 0.03 and 0.01 rad per unit of :math:`z`): the weak directions (the twist a loop makes) need
    long steps, along which the strong one (the drift's somersault) moves at second order, so the
    full step overshoots and backtracking creeps; the corrector takes that second-order part back
    for one evaluation. Only after a stall, so that a refinement that makes progress keeps the
    plain (shorter) steps.

    With ``limits``, the joint ranges and rate limits hold inside the refinement: they are linear in
    :math:`z` on a grid of 64 times (:func:`acroplan.core.limits.linear_limits`, with a margin of
    0.2%), and each step is the shortest one that also keeps them
    (:func:`acroplan.core.linalg.least_norm_step`), so a refined loop needs no constrained solve
    afterwards.

    Returns
    -------
    (coefficients, error, evaluations, endpoint)
        The best input found (shape (m, n)), its attitude error (rad), the endpoint evaluations
        spent, and the endpoint map and its Jacobian at those coefficients exactly
        (:func:`acroplan.core.backend.endpoint`; ``None`` when they were not evaluated), for the
        polish that follows (:func:`acroplan.core.strategies.deform_attempt`).
    """
    from ...core.limits import linear_limits
    from ...core.linalg import least_norm_step, least_squares_step

    if guess.subspace is None:
        return guess.coefficients, float("nan"), 0, None
    m, n = body.n_inputs, basis.n
    K, c0 = guess.subspace, guess.base.ravel()
    z = np.zeros(K.shape[1])
    z[:2 * m] = np.concatenate([guess.a, guess.b])
    evals = 0
    G = np.zeros((0, K.shape[1]))
    h = np.zeros(0)
    if limits is not None and limits.active:
        A, b = linear_limits(body, basis, x0, T, limits, margin=2e-3)
        G, h = A @ K, b - A @ c0

    seen = {}

    def evaluate(z):
        y, J = backend.endpoint(body, basis, x0, T, c0 + K @ z)
        seen[z.tobytes()] = (y, J)
        return body.diff(y, x1)[:3], body.tangent_jacobian(y, J)[:3] @ K

    def step(Jz, r, z):
        """The step, and whether the limits kept it from meeting the linearised target."""
        if not G.shape[0]:
            return np.linalg.lstsq(Jz, r, rcond=1e-12)[0], False
        d, ok = least_norm_step(Jz, r, G, h - G @ z)
        if ok:
            return d, False
        # the limits do not let one step meet the target: the step that comes closest under them
        d, ok = least_squares_step(Jz, r, G, h - G @ z)
        return (d if ok else np.linalg.lstsq(Jz, r, rcond=1e-12)[0]), True

    try:
        r, Jz = evaluate(z)
    except backend.IntegrationError:
        return guess.coefficients, float("inf"), 1, None
    evals += 1
    res = float(np.linalg.norm(r))
    slow, stalled = 0, False
    while evals < budget and res > tol and slow < 2:
        d, blocked = step(Jz, r, z)
        before = res
        alpha, moved = 1.0, False
        while alpha >= 1.0 / 64 and evals < budget:
            evals += 1
            try:
                r2, J2 = evaluate(z + alpha * d)
            except backend.IntegrationError:
                alpha /= 4.0
                continue
            if np.linalg.norm(r2) < (1.0 - 1e-4 * alpha) * res:
                z, r, Jz, res, moved = z + alpha * d, r2, J2, float(np.linalg.norm(r2)), True
                break
            if stalled and evals < budget:  # the corrector from the trial point (docstring)
                z2 = z + alpha * d
                d2, _ = step(J2, r2, z2)
                if np.linalg.norm(d2) <= alpha * np.linalg.norm(d):
                    evals += 1
                    try:
                        r3, J3 = evaluate(z2 + d2)
                    except backend.IntegrationError:
                        r3 = None
                    if r3 is not None and np.linalg.norm(r3) < (1.0 - 1e-4 * alpha) * res:
                        z, r, Jz, res, moved = z2 + d2, r3, J3, float(np.linalg.norm(r3)), True
                        break
            alpha /= 4.0
        if not moved:
            break
        stalled = res > CORRECTOR_STALL * before
        slow = slow + 1 if blocked and res > 0.7 * before else 0  # stalled against the limits
    return (c0 + K @ z).reshape(m, n), res, evals, seen.get(z.tobytes())
