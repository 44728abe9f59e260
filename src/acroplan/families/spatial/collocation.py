"""The endpoint map of a spatial body and its Jacobian, by Gauss collocation of the attitude alone.

Why not the Taylor integrator
-----------------------------
On a segment (normalised time :math:`\\sigma \\in [0, 1]`, duration :math:`T`) the joint rates are
the basis series :math:`u(\\sigma) = \\sum_i c_{\\cdot i} b_i(\\sigma)` and the shape is their exact
integral, a polynomial of time:

.. math::  s(\\sigma) = s_0 + T \\sum_i c_{\\cdot i} B_i(\\sigma) ,\\qquad B_i(\\sigma) = \\int_0^\\sigma b_i .

So everything that is expensive in (2) of :mod:`~acroplan.families.spatial.model` (the rotations of
the links, the locked inertia :math:`\\mathbb{I}(s)`, the coupling :math:`A(s)`, the solve) is a
known function of time, and only the attitude :math:`q` needs integrating:

.. math::  \\frac{dq}{d\\sigma} = \\tfrac12\\, q \\otimes (0, \\Omega) ,\\qquad
           \\Omega(\\sigma, q) = \\omega(\\sigma) + W(\\sigma)\\, R(q)^\\top L ,\\qquad
           \\omega = -T\\,\\mathbb{I}^{-1} A\\, u ,\\quad W = T\\,\\mathbb{I}^{-1} .        \\qquad (1)

The compiled Taylor integrator (:mod:`acroplan.core.backend`) instead carries the whole field in
Taylor arithmetic, where each product costs :math:`O(p^2)` at order :math:`p = 19`, over some
50 steps for the bundled cat, plus 7 x 42 variational equations: 30-80 ms per evaluation. Here the
momentum map is evaluated at points only (a compiled function, :func:`heyoka.cfunc`, of the
shape and the rates: :math:`\\mathbb{I}^{-1}`, :math:`\\mathbb{I}^{-1}Au`, :math:`\\mathcal{A} =
\\mathbb{I}^{-1}A` and the shape derivatives :math:`X_k = \\mathbb{I}^{-1}\\partial_k\\mathbb{I}`,
:math:`y_k = \\mathbb{I}^{-1}\\partial_k A\\, u`), at some 100 points per segment
(``benchmarks/spatial_endpoint.py`` measures both).

The scheme
----------
:math:`[0, 1]` is cut into panels; on a panel :math:`[a, a + H]` the attitude is the Gauss
collocation polynomial at the :data:`NODES` Gauss-Legendre nodes :math:`a + H\\gamma_i` (the
implicit Runge-Kutta method of order :math:`2N`):

.. math::  Y_i = y_0 + H \\sum_j \\alpha_{ij} F_j ,\\qquad y_1 = y_0 + H \\sum_j \\beta_j F_j ,\\qquad
           F_j = \\tfrac12\\, Y_j \\otimes (0, \\Omega(\\sigma_j, Y_j)),

At :math:`L = 0`, (1) is linear in :math:`q`: every panel is solved at once from the identity (one
dense 4N x 4N real system each, solved as the 2N x 2N complex system it is: :func:`_attitude`) and
the panels are chained by quaternion products. With :math:`L \\ne 0`
the body-frame momentum :math:`\\lambda = R(q)^\\top L` carries the nonlinearity alone,

.. math::  \\lambda' = \\lambda \\times \\Omega ,\\qquad \\Omega = \\omega + W \\lambda ,

and its Gauss collocation is solved first, panel after panel, by Newton's method (3N x 3N systems,
from the momentum carried node to node by Heun's method on rotations; one compiled kernel per
node count gives the residual and the Jacobian's blocks), then the attitude as at
:math:`L = 0` with :math:`\\Omega` at the nodes. Collocating :math:`\\lambda` and then :math:`q` at the
same nodes is exactly the Gauss collocation of the coupled system :math:`(\\lambda, q)`, so the
endpoint keeps order :math:`2N`. Gauss methods keep quadratic invariants exactly: :math:`|q|^2` and
:math:`|\\lambda|^2 = |L|^2` hold to rounding.

*Panels.* Bisection from two halves: a panel is kept when the last two Legendre coefficients of
:math:`H\\omega` and :math:`H |L| W` on it (the interpolants at its nodes) are below
:data:`TAIL_TOL` and the shape turns the root by at most :data:`MAX_TURN` on it; after the solve,
the same test on :math:`H q'` and :math:`H \\lambda'/|L|` (the solution's own resolution) with
:data:`SOLUTION_TAIL_TOL`. The endpoint error of Gauss collocation is of the order of the square of
that tail (the quadrature is exact to degree :math:`2N - 1`): ``tests/test_spatial_endpoint.py``
checks it against a tight independent integration. The layout depends on the inputs alone, so the
same call always gives the same numbers. :func:`sample` cuts the panels at the requested times.

The Jacobian
------------
It is the exact derivative of the discrete map (to rounding), by implicit differentiation of the
collocation equations. With :math:`S = \\mathbb{1} - H (\\alpha \\otimes \\mathbb{1}_4)\\,
\\mathrm{diag}_j(\\partial F_j / \\partial q)` at the solution and
:math:`M = (\\beta^\\top \\otimes \\mathbb{1}_4)\\, \\mathrm{diag}_j(\\partial F_j/\\partial q)\\, S^{-1}`
(its first row by one transposed solve: :math:`S` and the :math:`\\partial F_j/\\partial q` are
quaternion right multiplications, which commute with every left multiplication, so each 4 x 4
block :math:`M_i` is a right multiplication too, fixed by its first row), a panel maps
perturbations as

.. math::  \\delta y_1 = \\Phi\\, \\delta y_0 + H \\sum_j Z_j\\, \\tfrac12 \\Xi(Y_j)\\, \\delta\\Omega_j ,\\qquad
           \\Phi = \\mathbb{1} + H \\sum_i M_i ,\\qquad Z_j = \\beta_j \\mathbb{1} + H \\sum_i M_i \\alpha_{ij} ,

:math:`\\Xi(q) v = q \\otimes (0, v)`, and the coefficients enter through :math:`\\Omega` at fixed
:math:`q` (with :math:`L \\ne 0` also through the momentum: an adjoint sweep over the momentum's
panels, :func:`_momentum_adjoint`, adds its part to :math:`\\partial q(1)/\\partial \\Omega_j`):

.. math::  \\frac{\\partial \\Omega}{\\partial c_{li}} = -T \\mathcal{A}_l\\, b_i(\\sigma)
           + \\big(-X_l \\Omega - T y_l\\big)\\, T B_i(\\sigma) .

The joint rows are exact: :math:`\\partial s_l(1)/\\partial c_{li} = T B_i(1)`.
"""

from __future__ import annotations

import copy
import functools
import threading

import numpy as np
from scipy.linalg import lapack

from ...core.backend import IntegrationError, evaluate_columns
from .collocation_parts import (_FULL, _SYM, MAX_PANELS, MAX_TURN, MIN_PANEL, NEWTON_ITERATIONS, NEWTON_TOL,  # noqa: F401
                                NODES, SOLUTION_TAIL_TOL, TAIL_TOL, _basis_at, _cat, _diag, _gauss,
                                _layout, _left, _quad, _right, _rightq, _skew, _split,
                                _take, _xi)

__all__ = ["endpoint", "sample", "compile_map", "evaluate_map", "NODES", "TAIL_TOL", "MAX_PANELS"]


# ---------------------------------------------------------------------- the compiled momentum map
_MAPS: dict = {}
_LOCAL = threading.local()
#: The momentum solves (and their panel sweeps) remembered per thread (:func:`_first_momentum`,
#: :func:`_momentum_panels`): the intervals of a joint optimum ask for each interval's endpoint,
#: torque cost and torque limits at the same coefficients, one interval after the other, so the
#: memo holds two per interval of a plan of up to four intervals (some 0.5 MB an entry for a 5-link
#: body at 30 coefficients)
MOMENTUM_MEMO = 8


def _remembered(name, seg, compute, usable=lambda v: True):
    """``compute()`` for ``seg``'s inputs (basis, duration, start, coefficients), remembered in this
    thread's memo ``name`` (the last :data:`MOMENTUM_MEMO` of them), its arrays made read-only; an
    entry serves when ``usable(entry)``. It depends on the inputs alone, so the memo changes no
    number."""
    key = (seg.basis, seg.T, seg.x0.tobytes(), seg.c.tobytes())
    memo = getattr(_LOCAL, name, None)
    if memo is None:
        memo = []
        setattr(_LOCAL, name, memo)
    for body, k, v in memo:
        if body is seg.body and k == key and usable(v):
            return v
    v = compute()
    for a in v:
        for arr in (a.values() if isinstance(a, dict) else (a,)):
            if arr is not None:
                arr.setflags(write=False)
    memo.insert(0, (seg.body, key, v))
    del memo[MOMENTUM_MEMO:]
    return v


def _build(body, light=False):
    """The compiled function of a topology: inputs ``(s, u)``, parameters the lumped parameters;
    outputs :math:`\\mathbb{I}^{-1}` (6 entries), :math:`\\mathbb{I}^{-1} A u` (3), :math:`\\mathcal{A}`
    (3 m, column by column), then per joint :math:`k` the 9 entries of :math:`X_k` (row by row) and
    the 3 of :math:`y_k`."""
    import heyoka as hy

    from ...core.heyoka_import import from_sympy

    x, p = body.symbols()
    I, A = body.symbolic_momentum_map()  # noqa: E741
    m = len(A)
    sv = list(hy.make_vars(*[f"s{j}" for j in range(m)])) if m > 1 else [hy.make_vars("s0")]
    uv = list(hy.make_vars(*[f"u{j}" for j in range(m)])) if m > 1 else [hy.make_vars("u0")]
    sub = {sym: v for sym, v in zip(x[4:], sv)}
    sub.update({sym: hy.par[i] for i, sym in enumerate(p)})
    Ie = [from_sympy(I[i, j], sub) for i, j in _SYM]
    Ae = [[from_sympy(A[j][i], sub) for i in range(3)] for j in range(m)]
    a = [[Ie[_FULL[i, j]] for j in range(3)] for i in range(3)]
    c00 = a[1][1] * a[2][2] - a[1][2] * a[1][2]
    c01 = a[0][2] * a[1][2] - a[0][1] * a[2][2]
    c02 = a[0][1] * a[1][2] - a[0][2] * a[1][1]
    c11 = a[0][0] * a[2][2] - a[0][2] * a[0][2]
    c12 = a[0][2] * a[0][1] - a[0][0] * a[1][2]
    c22 = a[0][0] * a[1][1] - a[0][1] * a[0][1]
    inv_det = 1.0 / (a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02)
    Wl = [c00 * inv_det, c01 * inv_det, c02 * inv_det, c11 * inv_det, c12 * inv_det, c22 * inv_det]
    W = [[Wl[_FULL[i, j]] for j in range(3)] for i in range(3)]

    def mv(M, v):
        return [M[i][0] * v[0] + M[i][1] * v[1] + M[i][2] * v[2] for i in range(3)]

    out = list(Wl)
    out += mv(W, [sum(Ae[j][i] * uv[j] for j in range(m)) for i in range(3)])
    if light:  # and the momentum map itself: I (6 entries), A (3 m, column by column)
        return hy.cfunc(out + Ie + [e for col in Ae for e in col], sv + uv)
    jac = hy.diff_tensors(Ie + [e for col in Ae for e in col], sv, diff_order=1).jacobian
    for j in range(m):
        out += mv(W, Ae[j])
    for k in range(m):
        dI = [[jac[_FULL[i, j], k] for j in range(3)] for i in range(3)]
        out += [sum(W[i][r] * dI[r][j] for r in range(3)) for i in range(3) for j in range(3)]
        out += mv(W, [sum(jac[6 + 3 * j + i, k] * uv[j] for j in range(m)) for i in range(3)])
    return hy.cfunc(out, sv + uv)


def map_key(body, light: bool = False) -> tuple:
    """The key of a topology's compiled momentum map (:func:`acroplan.core.backend.compile_once`)."""
    return ("spatial-momentum-map", tuple(body.links.parents), bool(light))


def compile_map(body, light: bool = False):
    """The compiled momentum map of a body's topology (:func:`_build`), built once per process, and
    this thread's own copy of it. ``light``: the first 9 outputs alone (:math:`\\mathbb{I}^{-1}`
    and :math:`\\mathbb{I}^{-1} A u`, for the guesses' fast integration), then :math:`\\mathbb{I}`
    (6 entries) and :math:`A` (3 m, column by column) themselves
    (:meth:`SpatialBody.momentum_map <acroplan.families.spatial.model.SpatialBody.momentum_map>`)."""
    key = (body.links.parents, bool(light))
    fn = _MAPS.get(key)
    if fn is None:  # compiled in a thread of its own, waited for within the plan's time budget
        from ...core import backend

        fn = _MAPS[key] = backend.compile_once(map_key(body, light), lambda: _build(body, light=bool(light)))
    mine = getattr(_LOCAL, "maps", None)
    if mine is None:
        mine = _LOCAL.maps = {}
    own = mine.get(key)
    if own is None:
        own = mine[key] = copy.copy(fn)
    return own


#: points per call of a compiled map (:func:`evaluate_map`)
CHUNK = 4096


def evaluate_map(body, fn, inputs) -> np.ndarray:
    """A compiled map ``fn`` (:func:`compile_map`) at the points ``inputs`` (columns: the shape and
    the rates), in chunks of :data:`CHUNK` points with the body's parameters repeated once per size.

    Returns
    -------
    numpy.ndarray, shape (outputs, points)
    """
    return evaluate_columns(fn, np.ascontiguousarray(inputs, dtype=float), body._param_tuple, CHUNK)


# ---------------------------------------------------------------------- the segment
class _Segment:
    """One segment's data: the body, the basis, the inputs; node data of panels on demand."""

    def __init__(self, body, basis, x0, T, c):
        self.m, self.n = body.n_inputs, basis.n
        self.basis = basis
        self.T = float(T)
        self.c = np.asarray(c, dtype=float).reshape(self.m, self.n)
        self.x0 = np.asarray(x0, dtype=float)
        self.L = np.asarray(body.L, dtype=float)
        self.drift = bool(np.any(self.L != 0.0))
        self.Lnorm = float(np.linalg.norm(self.L))
        self.Q = _quad(self.L)
        self.body = body
        self.fn = compile_map(body)
        self.N = NODES
        self.g, self.b, self.a, self.Vi = _gauss(NODES)

    def data(self, starts, widths, tables=None):
        """Node data of panels ``[starts[k], starts[k] + widths[k]]``: a dict of arrays whose first
        two axes are (panel, node). ``tables``: the basis and its integrals at the nodes, (P N, n)
        each, when known (else :func:`_basis_at`)."""
        P, N, m, T = len(starts), self.N, self.m, self.T
        sig = (starts[:, None] + widths[:, None] * self.g[None, :]).ravel()
        Bm, Bi = _basis_at(self.basis, N, starts, widths) if tables is None else tables
        u = self.c @ Bm.T
        s = self.x0[4:, None] + T * (self.c @ Bi.T)
        out = evaluate_map(self.body, self.fn, np.concatenate([s, u]))
        if not np.isfinite(out).all():
            raise IntegrationError("the locked inertia is singular or the input is not finite on this segment")
        out = out.T  # (PN, outputs)
        W = T * out[:, _FULL]  # (PN, 3, 3)
        w = -T * out[:, 6:9]
        cA = out[:, 9:9 + 3 * m].reshape(-1, m, 3).transpose(0, 2, 1)  # (PN, 3, m): column l is A_l
        rest = out[:, 9 + 3 * m:].reshape(-1, m, 12)
        X = rest[:, :, :9].reshape(-1, m, 3, 3)  # X_l
        y = rest[:, :, 9:]  # (PN, m, 3)
        shp = (P, N)
        return dict(sig=sig.reshape(shp), Bm=Bm.reshape(shp + (-1,)), Bi=Bi.reshape(shp + (-1,)),
                    W=W.reshape(shp + (3, 3)), w=w.reshape(shp + (3,)), cA=cA.reshape(shp + (3, m)),
                    X=X.reshape(shp + (m, 3, 3)), y=y.reshape(shp + (m, 3)))

    def tails(self, vals, widths):
        """``H`` times the largest of the last two Legendre coefficients of nodal values ``vals``
        (panel, node, channels...) on each panel."""
        P, N = vals.shape[:2]
        co = self.Vi[N - 2:] @ vals.reshape(P, N, -1)
        return widths * np.abs(co).max(axis=(1, 2))


@functools.cache
def _momentum_kernel(N: int):
    """:func:`_build_momentum_kernel`, compiled once per process (in a thread of its own, waited for
    within the plan's time budget: :func:`acroplan.core.backend.compile_once`)."""
    from ...core import backend

    return backend.compile_once(("spatial-momentum-kernel", 2, int(N)), lambda: _build_momentum_kernel(N))


def _build_momentum_kernel(N: int):
    """One Newton iteration's numbers for a panel's momentum collocation, compiled (independent of
    the body: one per node count). Inputs, flat: :math:`\\Lambda` (N x 3), :math:`\\lambda_0` (3),
    :math:`\\omega` (N x 3), :math:`W` (N x 9); parameter :math:`H`. Outputs, flat: the residual
    :math:`\\Lambda_i - \\lambda_0 - H\\sum_j \\alpha_{ij} F_j` (3N), :math:`F_j = \\Lambda_j \\times
    \\Omega_j` (3N), :math:`J_j = [\\Lambda_j]_\\times W_j - [\\Omega_j]_\\times` (9N) and the
    Jacobian :math:`S = 1 - H(\\alpha \\otimes 1) \\mathrm{diag}(J_j)` (3N x 3N) column by column, so
    that its array read row by row and transposed is ``S`` in Fortran order, which LAPACK factors in
    place (:func:`_momentum_panel`)."""
    import heyoka as hy

    a = _gauss(N)[2]
    v = hy.make_vars(*[f"v{i}" for i in range(15 * N + 3)])
    Lam = [v[3 * j:3 * j + 3] for j in range(N)]
    lam0 = v[3 * N:3 * N + 3]
    w = [v[3 * N + 3 + 3 * j:3 * N + 6 + 3 * j] for j in range(N)]
    W = [[v[6 * N + 3 + 9 * j + 3 * r:6 * N + 6 + 9 * j + 3 * r] for r in range(3)] for j in range(N)]
    H = hy.par[0]

    def cross(x, y):
        return [x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]]

    def skew(x):
        return [[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]]

    F, Jb = [], []
    for j in range(N):
        Om = [w[j][r] + W[j][r][0] * Lam[j][0] + W[j][r][1] * Lam[j][1] + W[j][r][2] * Lam[j][2] for r in range(3)]
        F.append(cross(Lam[j], Om))
        C, O = skew(Lam[j]), skew(Om)
        Jb.append([[sum(C[r][k] * W[j][k][c] for k in range(3) if not isinstance(C[r][k], float)) - O[r][c]
                    for c in range(3)] for r in range(3)])
    res = [Lam[i][c] - lam0[c] - H * sum(float(a[i, j]) * F[j][c] for j in range(N)) for i in range(N) for c in range(3)]
    mH = -H
    cols = []
    for j in range(N):          # column (j, c) of S: the block column of node j
        for c in range(3):
            for i in range(N):
                hij = mH * float(a[i, j])
                for r in range(3):
                    e = hij * Jb[j][r][c]
                    cols.append(e + 1.0 if (i == j and r == c) else e)
    out = res + [x for f in F for x in f] + [x for blk in Jb for row in blk for x in row] + cols
    return hy.cfunc(out, list(v))


@functools.cache
def _guess_kernel(N: int):
    """:func:`_build_guess_kernel`, compiled once per process as :func:`_momentum_kernel`."""
    from ...core import backend

    return backend.compile_once(("spatial-momentum-guess", int(N)), lambda: _build_guess_kernel(N))


def _build_guess_kernel(N: int):
    """The start of a panel's Newton iteration (:func:`_momentum_panel`), compiled: inputs, flat,
    :math:`\\lambda_0` (3), :math:`\\omega` (N x 3), :math:`W` (N x 9); parameter :math:`H`; outputs
    :math:`\\Lambda_j` (N x 3), :math:`\\lambda' = \\lambda \\times \\Omega`, :math:`\\Omega = \\omega + W
    \\lambda`, integrated from the panel's start to its nodes one node after the other by Heun's
    method on rotations: from node :math:`j - 1` to node :math:`j` (:math:`\\delta = H(\\gamma_j -
    \\gamma_{j-1})`, the first step from the start with node 0's fields), a predictor
    :math:`\\lambda^* = \\exp(-\\delta [\\Omega_{j-1}]_\\times)\\, \\lambda_{j-1}` and
    :math:`\\lambda_j = \\exp(-\\tfrac{\\delta}{2} [\\Omega_{j-1} + \\Omega_j(\\lambda^*)]_\\times)\\,
    \\lambda_{j-1}`, each rotation by Rodrigues' formula with :math:`(1 - \\cos t)/t^2 = \\tfrac12
    (\\sin(t/2) / (t/2))^2` and :math:`\\sin t / t` at :math:`t^2 + 10^{-300}` (a guess: its last
    digits change only where Newton's method starts). On the bundled forward dive's second interval
    (11 panels, 1/16 and 1/8 of it wide, L = 75 kg m^2/s) it is 25 to 200 times closer to the
    solution than the start's momentum turned back by the body's turn at the frozen momentum (the
    former start: off by 15-24 kg m^2/s on the widest panels), and Newton's method takes 30
    iterations there instead of 38 (benchmarks/RESULTS.md, 2026-12-06, sixth session)."""
    import heyoka as hy

    gam = _gauss(N)[0]
    v = hy.make_vars(*[f"v{i}" for i in range(12 * N + 3)])
    w = [v[3 + 3 * j:6 + 3 * j] for j in range(N)]
    W = [[v[3 * N + 3 + 9 * j + 3 * r:3 * N + 6 + 9 * j + 3 * r] for r in range(3)] for j in range(N)]
    H = hy.par[0]

    def omega(j, lam):
        return [w[j][r] + W[j][r][0] * lam[0] + W[j][r][1] * lam[1] + W[j][r][2] * lam[2] for r in range(3)]

    def turned(th, lam):  # exp([th]x) lam
        t = hy.sqrt(th[0] * th[0] + th[1] * th[1] + th[2] * th[2] + 1e-300)
        s1 = hy.sin(t) / t
        h = hy.sin(0.5 * t) / (0.5 * t)
        s2 = 0.5 * h * h
        tv = [th[1] * lam[2] - th[2] * lam[1], th[2] * lam[0] - th[0] * lam[2], th[0] * lam[1] - th[1] * lam[0]]
        ttv = [th[1] * tv[2] - th[2] * tv[1], th[2] * tv[0] - th[0] * tv[2], th[0] * tv[1] - th[1] * tv[0]]
        return [lam[r] + s1 * tv[r] + s2 * ttv[r] for r in range(3)]

    out, lam, before, om = [], list(v[:3]), 0.0, None
    for j in range(N):
        dt = float(gam[j] - before)
        start = omega(j, lam) if om is None else om  # the first step with node 0's fields
        pred = turned([-H * dt * start[r] for r in range(3)], lam)
        end = omega(j, pred)
        lam = turned([-H * (0.5 * dt) * (start[r] + end[r]) for r in range(3)], lam)
        om, before = omega(j, lam), float(gam[j])
        out += lam
    return hy.cfunc(out, list(v))


def _momentum_panel(seg, lam, H, d, start=None):
    """Newton's method on one panel's collocation equations of :math:`\\lambda' = \\lambda \\times
    \\Omega`, :math:`\\Omega = \\omega + W \\lambda`, from the guess of :func:`_build_guess_kernel` (the
    momentum carried from the panel's start to its nodes by Heun's method on rotations). Each
    iteration is one call of the compiled kernel
    (:func:`_build_momentum_kernel`: the residual and ``S``) and one LAPACK solve in place. Returns
    ``(lam1, Lam, J, Si, tail)`` (``J`` the blocks :math:`\\partial(\\lambda \\times \\Omega)/\\partial
    \\lambda` at the nodes, ``Si`` the inverse of the panel's ``S`` at the solution: the derivatives
    apply it to dozens of right-hand sides at once, a matrix product, where OpenBLAS's threaded
    triangular solves with several right-hand sides took milliseconds next to another process doing
    the same), or ``None`` when Newton's method does not converge. ``start``: Newton's
    start :math:`\\Lambda` (N, 3) instead of that guess (the same panel's solution at a nearby input)."""
    W, w, N = d["W"], d["w"], seg.N
    tol = NEWTON_TOL * seg.Lnorm
    kern, guess = _momentum_kernel_copy(N)
    n3 = 3 * N
    inp = np.empty(15 * N + 3)
    inp[n3:n3 + 3] = lam
    inp[n3 + 3:6 * N + 3] = w.ravel()
    inp[6 * N + 3:] = W.ravel()
    par = np.array([H])
    if start is None:
        guess(inp[n3:], pars=par, outputs=inp[:n3])
    else:
        inp[:n3] = np.asarray(start, dtype=float).ravel()
    out = np.empty(kern.nouts)
    res, o_s = out[:n3], 15 * N
    for _ in range(NEWTON_ITERATIONS):
        kern(inp, pars=par, outputs=out)
        step = lapack.dgesv(out[o_s:].reshape(n3, n3).T, res, overwrite_a=1, overwrite_b=1)[2]
        inp[:n3] -= step
        if not np.abs(step).max() > tol:
            break
    else:
        return None
    kern(inp, pars=par, outputs=out)
    F = out[n3:2 * n3].reshape(N, 3)
    J = out[2 * n3:o_s].reshape(N, 3, 3)
    tail = H * np.abs(seg.Vi[-2:] @ F).max() / seg.Lnorm
    Lam = inp[:n3].reshape(N, 3)
    if not (np.isfinite(tail) and np.isfinite(Lam).all()):
        return None
    lu, piv, info = lapack.dgetrf(out[o_s:].reshape(n3, n3).T, overwrite_a=1)
    if info != 0:
        return None
    Si, info = lapack.dgetri(lu, piv, overwrite_lu=1)
    if info != 0:
        return None
    return lam + H * (seg.b @ F), Lam, J, Si, tail


def _momentum_kernel_copy(N):
    """This thread's copies of :func:`_momentum_kernel` and :func:`_guess_kernel`."""
    mine = getattr(_LOCAL, "kernels", None)
    if mine is None:
        mine = _LOCAL.kernels = {}
    own = mine.get(N)
    if own is None:
        own = mine[N] = (copy.copy(_momentum_kernel(N)), copy.copy(_guess_kernel(N)))
    return own


def _momentum(seg, starts, widths, d):
    """The body-frame momentum :math:`\\lambda = R(q)^\\top L` panel after panel
    (:func:`_momentum_panel`), halving a panel whose Newton iteration fails or whose momentum is
    not resolved. Returns the (possibly refined) ``starts, widths, d`` and ``Lam`` (P, N, 3),
    ``J`` (P, N, 3, 3) and the inverses of the panels' ``S`` (P, 3N, 3N)."""
    lam = np.einsum("a,iab,b->i", seg.x0[:4], seg.Q, seg.x0[:4])
    # a panel of the layout as given is its index into ``d`` (its node data taken only when a panel
    # splits: copying every array of every panel was 16 us a panel, the forward dive's 0.13 s)
    queue = [(starts[k], widths[k], k) for k in range(widths.size)][::-1]
    out = []
    split = False
    dW, dw = d["W"], d["w"]
    while queue:
        a0, H, dk = queue.pop()
        r = _momentum_panel(seg, lam, H, dk if isinstance(dk, dict) else {"W": dW[dk], "w": dw[dk]})
        if r is None or r[4] > SOLUTION_TAIL_TOL:
            split = True
            h = H / 2.0
            if h < MIN_PANEL or len(out) + len(queue) + 2 > MAX_PANELS:
                raise IntegrationError(f"the input is too large to integrate: more than {MAX_PANELS} panels on "
                                       f"one segment")
            dd = seg.data(np.array([a0, a0 + h]), np.array([h, h]))
            queue += [(a0 + h, h, _take(dd, 1)), (a0, h, _take(dd, 0))]
            continue
        lam = r[0]
        out.append((a0, H, dk) + r[1:4])
    more = (np.stack([o[3] for o in out]), np.stack([o[4] for o in out]), np.stack([o[5] for o in out]))
    if not split:  # the layout as given (its node data restacked panel by panel were the same arrays)
        return (starts, widths, d) + more
    st = np.array([o[0] for o in out])
    wd = np.array([o[1] for o in out])
    dd = {k: np.stack([o[2][k] if isinstance(o[2], dict) else v[o[2]] for o in out]) for k, v in d.items()}
    return (st, wd, dd) + more


_CONJ = np.array([1.0, -1.0, -1.0, -1.0])


def _complex_blocks(seg, widths, Om):
    """:math:`S` of every panel's attitude equations in the complex form of :func:`_attitude`, shape
    (P, 2N, 2N), from :math:`\\Omega` at the nodes (P, N, 3): :math:`S = \\mathbb{1} - H (\\alpha
    \\otimes \\mathbb{1}_2)\\, \\mathrm{diag}_j(C_j)`, :math:`C_j` the matrix of :math:`q \\mapsto \\tfrac12
    q \\otimes (0, \\Omega_j)` (as :func:`~acroplan.families.spatial.collocation_parts._blocks` builds the
    real one)."""
    P, N = widths.size, seg.N
    h = 0.5 * Om
    C = np.empty((P, N, 2, 2), dtype=complex)  # w1 = i h_x, w2 = h_y + i h_z
    C[..., 0, 0] = 1j * h[..., 0]
    C[..., 1, 1] = -1j * h[..., 0]
    C[..., 1, 0] = h[..., 1] + 1j * h[..., 2]
    C[..., 0, 1] = -h[..., 1] + 1j * h[..., 2]
    S = (seg.a[None, :, None, :, None] * (-widths[:, None, None, None, None] * np.swapaxes(C, 1, 2)[:, None]))
    S = S.reshape(P, 2 * N, 2 * N)
    S[:, _diag(2 * N), _diag(2 * N)] += 1.0
    return S


@functools.cache
def _complex_unit(N):
    """The identity quaternion at every node in the complex form of :func:`_attitude`, (2N,), read-only."""
    e = np.zeros(2 * N, dtype=complex)
    e[0::2] = 1.0
    e.setflags(write=False)
    return e


def _chain(q0, Pk):
    """The quaternions :math:`y_0 = q_0`, :math:`y_{k+1} = y_k \\otimes P_k` (P + 1, 4), in floats: a
    dozen products, where numpy's calls cost more than the arithmetic."""
    aw, ax, ay, az = q0.tolist()
    out = [(aw, ax, ay, az)]
    for bw, bx, by, bz in Pk.tolist():
        aw, ax, ay, az = (aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                          aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw)
        out.append((aw, ax, ay, az))
    return np.array(out)


def _attitude(seg, widths, Om):
    """The attitude on every panel at once, given :math:`\\Omega` at the nodes (P, N, 3): the linear
    collocation equations of each panel solved from the identity, the panels chained by quaternion
    products, and the panels' maps of perturbations (module docstring).

    The equations are quaternion right multiplications, which are complex-linear when a quaternion
    :math:`q = z_1 + z_2 j` (:math:`z_1 = q_0 + i q_1`, :math:`z_2 = q_2 + i q_3`) is the pair
    :math:`(z_1, z_2)`: :math:`q \\mapsto q \\otimes (w_1 + w_2 j)` is the 2 x 2 complex matrix
    :math:`\\begin{pmatrix} w_1 & -\\bar w_2 \\\\ w_2 & \\bar w_1 \\end{pmatrix}`, so each panel's
    4N x 4N real system is a 2N x 2N complex one (:func:`_complex_blocks`; the real system's
    transpose is the complex one's conjugate transpose): half the LU's work and a quarter of the
    matrix to build (the falling cat's endpoint 1.2 times faster on its plan's calls,
    ``benchmarks/RESULTS.md``, 2026-12-06, ninth session).

    Returns
    -------
    q1 : (4,); Y : (P, N, 4) stage values; Phi : (P, 4, 4); Z : (P, N, 4, 4); tails : (P,) of
    :math:`H q'`.
    """
    P, N = widths.size, seg.N
    Fq = _right(Om)  # (P, N, 4, 4): F_j = Fq_j Y_j
    S = _complex_blocks(seg, widths, Om)
    e = _complex_unit(N)
    # the first row of M (module docstring): its other rows follow from it (below); the complex
    # pairs of a quaternion are its components' memory, so the real arrays are views
    rhs = (seg.b[:, None] * np.swapaxes(Fq, -1, -2)[:, :, :, 0]).reshape(P, 4 * N).view(complex)
    Yl = np.empty((P, 2 * N), dtype=complex)
    x = np.empty((P, 2 * N), dtype=complex)
    for k in range(P):
        # the LU of S^T (S[k].T is Fortran-ordered: LAPACK factors it in place, no copy): S y = e
        # is its transposed solve, S^H x = rhs its plain one, conjugated
        lu, piv, info = lapack.zgetrf(S[k].T, overwrite_a=1)
        if info != 0:
            raise IntegrationError("a panel's collocation equations are singular (the input is too large)")
        Yl[k] = lapack.zgetrs(lu, piv, e, trans=1)[0]
        x[k] = lapack.zgetrs(lu, piv, rhs[k].conj())[0].conj()
    Yl = Yl.view(float)
    x = x.view(float)
    Yl = Yl.reshape(P, N, 4)
    Fl = (Fq @ Yl[..., None])[..., 0]
    Pk = widths[:, None] * (seg.b @ Fl)
    Pk[:, 0] += 1.0
    ys = _chain(seg.x0[:4], Pk)
    Y = (_left(ys[:-1])[:, None] @ Yl[..., None])[..., 0]
    # S and the F_j are made of right multiplications, so they commute with every left
    # multiplication, and so does M: its block M_i is the right multiplication by the quaternion
    # mu_i whose first row it has, (mu_0, -mu_1, -mu_2, -mu_3)
    Mb = _rightq(x.reshape(P, N, 4) * _CONJ)  # M_i, (P, N, 4, 4)
    Phi = np.eye(4) + widths[:, None, None] * Mb.sum(axis=1)
    Z = seg.b[None, :, None, None] * np.eye(4) + widths[:, None, None, None] * (
        seg.a.T @ Mb.reshape(P, N, 16)).reshape(P, N, 4, 4)
    tails = seg.tails((Fq @ Y[..., None])[..., 0], widths)
    return ys, Y, Phi, Z, tails


def _cut(seg, starts, widths, d, points):
    """The layout cut at ``points`` (normalised times): every panel holding points strictly inside
    is replaced by its pieces between them (node data evaluated anew). Points within 1e-12 of a
    boundary are taken as that boundary."""
    keep, new_st, new_wd = [], [], []
    for k in range(widths.size):
        a0, b0 = starts[k], starts[k] + widths[k]
        inside = points[(points > a0 + 1e-12) & (points < b0 - 1e-12)]
        if inside.size == 0:
            keep.append(k)
            continue
        edges = np.concatenate([[a0], inside, [b0]])
        new_st.append(edges[:-1])
        new_wd.append(np.diff(edges))
    if not new_st:
        return starts, widths, d
    st, wd = np.concatenate(new_st), np.concatenate(new_wd)
    if widths.size - len(keep) + st.size > MAX_PANELS:
        raise IntegrationError(f"the input is too large to integrate: more than {MAX_PANELS} panels on one segment")
    keep = np.array(keep, dtype=int)
    dn = seg.data(st, wd)
    all_st = np.concatenate([starts[keep], st])
    order = np.argsort(all_st, kind="stable")
    dd = _cat([_take(d, keep), dn])
    return all_st[order], np.concatenate([widths[keep], wd])[order], _take(dd, order)


def _first_momentum(seg):
    """:func:`_momentum` on the first layout (:func:`_layout`) of ``seg``, remembered for the last
    few inputs of this thread: an optimiser asks for the endpoint (:func:`endpoint`) and for the
    torques (:func:`momentum_samples`) at the same coefficients, and both start from this solve.
    It depends on the inputs alone, so the cache changes no number. The arrays are shared: read
    them, never write them."""
    return _remembered("momentum", seg, lambda: _momentum(seg, *_layout(seg)))


def _solve(seg, points=None, starts_out=None):
    """Layout and solution, splitting panels until the attitude is resolved too, and cut at
    ``points`` when given (:func:`_cut`). Returns ``(ys, widths, data, Omega, Y, Phi, Z,
    momentum)``: ``ys`` (P + 1, 4) the attitude at the panels' boundaries, ``momentum`` is
    ``(Lam, J, Si)`` (:func:`_momentum`) or ``None`` at :math:`L = 0`."""
    first = points is None and seg.drift
    if not first:
        starts, widths, d = _layout(seg)
    if points is not None:
        starts, widths, d = _cut(seg, starts, widths, d, points)
    while True:
        mom = None
        if seg.drift:
            if first:  # the first pass's momentum, shared with momentum_samples
                starts, widths, d, *mom = _first_momentum(seg)
                first = False
            else:
                starts, widths, d, *mom = _momentum(seg, starts, widths, d)
            Om = d["w"] + (d["W"] @ mom[0][..., None])[..., 0]
        else:
            Om = d["w"]
        ys, Y, Phi, Z, tq = _attitude(seg, widths, Om)
        bad = tq > SOLUTION_TAIL_TOL
        if not bad.any():
            if starts_out is not None:
                starts_out.append(starts)
            return ys, widths, d, Om, Y, Phi, Z, mom
        ok = ~bad
        st, wd = _split(starts, widths, d, bad, seg, int(ok.sum()))
        starts, widths, d = _layout(seg, st, wd, [(starts[ok], widths[ok], _take(d, ok))])


#: An input within this much of the point of :class:`acroplan.core.backend.perturbations_of`
#: (relative to its largest coefficient) is integrated on that point's panels (:func:`_solve_near`)
NEAR_TOL = 1e-5


def _solve_near(seg):
    """:func:`_solve` on the panels of the point of the enclosing
    :class:`~acroplan.core.backend.perturbations_of` (the forward differences of the optimiser's
    constraint Hessians), the momentum's Newton iterations started from that point's solution
    panel by panel, no panel split: the differences are those of one discrete map, and cheaper.
    ``None`` when there is no such point, ``seg`` is not a small perturbation of it, or a panel's
    Newton iteration fails (then :func:`_solve` integrates as always)."""
    from ...core import backend

    near = backend.near_point()
    if near is None:
        return None
    body, basis, x0b, T, c0, memo = near
    if body is not seg.body or basis != seg.basis or T != seg.T or x0b != seg.x0.tobytes():
        return None
    if not np.abs(seg.c.reshape(-1) - c0).max() <= NEAR_TOL * max(1.0, float(np.abs(c0).max())):
        return None
    base = memo.get("spatial collocation")
    if base is None:
        starts = []
        sol = _solve(_Segment(body, basis, seg.x0, T, c0), starts_out=starts)
        base = memo["spatial collocation"] = (starts[0], sol[1], None if sol[7] is None else sol[7][0])
    starts, widths, Lam0 = base
    d = seg.data(starts, widths)
    mom = None
    if seg.drift:
        lam = np.einsum("a,iab,b->i", seg.x0[:4], seg.Q, seg.x0[:4])
        out = []
        for k in range(widths.size):
            r = _momentum_panel(seg, lam, widths[k], {"W": d["W"][k], "w": d["w"][k]}, start=Lam0[k])
            if r is None:
                return None
            lam = r[0]
            out.append(r[1:4])
        mom = (np.stack([o[0] for o in out]), np.stack([o[1] for o in out]), np.stack([o[2] for o in out]))
        Om = d["w"] + (d["W"] @ mom[0][..., None])[..., 0]
    else:
        Om = d["w"]
    ys, Y, Phi, Z, _ = _attitude(seg, widths, Om)
    return ys, widths, d, Om, Y, Phi, Z, mom


@functools.lru_cache(maxsize=64)
def _end_integrals(basis):
    """:math:`B_i(1) = \\int_0^1 b_i`, shape (n,), read-only (cached: a basis is immutable)."""
    out = np.array(basis.integral([1.0])[0], dtype=float)
    out.setflags(write=False)
    return out


def endpoint(body, basis, x0, T, c, *, jacobian: bool = True):
    """The endpoint map of a spatial body on one segment and its Jacobian in the coefficients
    (module docstring), as :func:`acroplan.core.backend.endpoint` returns them.

    Parameters
    ----------
    body : SpatialBody
    basis : InputBasis
    x0 : array_like, shape (4 + m,)
    T : float
    c : array_like, shape (m, basis.n) or (m * basis.n,)
    jacobian : bool
        Compute the Jacobian (else ``None``).

    Returns
    -------
    xT : numpy.ndarray, shape (4 + m,)
    J : numpy.ndarray, shape (4 + m, m * basis.n), or None
    """
    seg = _Segment(body, basis, x0, T, c)
    ys, widths, d, Om, Y, Phi, Z, mom = _solve_near(seg) or _solve(seg)
    q1 = ys[-1]
    m, n, Tn = seg.m, seg.n, seg.T
    B1 = _end_integrals(basis)
    xT = np.concatenate([q1, seg.x0[4:] + Tn * (seg.c @ B1)])
    if not np.isfinite(xT).all():
        raise IntegrationError("integration gave a non-finite state")
    if not jacobian:
        return xT, None
    P, N = widths.size, seg.N
    suf = np.empty((P, 4, 4))
    acc = np.eye(4)
    for k in range(P - 1, -1, -1):
        suf[k] = acc
        acc = acc @ Phi[k]
    # g_j = dq(1)/dOmega_j = (Phi_K ... Phi_{k+1}) H Z_j Xi(Y_j) / 2, (P, N, 4, 3)
    g = ((widths[:, None, None, None] * (suf[:, None] @ Z)) @ _xi(Y))
    if mom is not None:
        g = g + _momentum_adjoint(seg, widths, d, g, *mom)
    PN = P * N
    g = g.reshape(PN, 4, 3)
    dOm_du = (-Tn) * d["cA"].reshape(PN, 3, m)
    dOm_ds = -np.swapaxes((d["X"].reshape(PN, m, 3, 3) @ Om.reshape(PN, 1, 3, 1))[..., 0]
                          + Tn * d["y"].reshape(PN, m, 3), 1, 2)  # (PN, 3, m)
    Gu = (g @ dOm_du).reshape(PN, 4 * m)
    Gs = (g @ dOm_ds).reshape(PN, 4 * m)
    Jq = Gu.T @ d["Bm"].reshape(PN, n) + Tn * (Gs.T @ d["Bi"].reshape(PN, n))
    J = np.zeros((4 + m, m * n))
    J[:4] = Jq.reshape(4, m * n)
    for l in range(m):  # noqa: E741
        J[4 + l, l * n:(l + 1) * n] = Tn * B1
    return xT, J


#: :func:`sample` cuts the panels at this many times at most at once (more are taken in chunks).
SAMPLE_CHUNK = 1024


def sample(body, basis, x0, T, c, s) -> np.ndarray:
    """States at normalised times ``s`` (sorted, in [0, 1]) on one segment, as
    :func:`acroplan.core.backend.sample` returns them: the collocation's panels cut at ``s``, so
    that every sample is a panel's end, where the collocation is as exact as at the segment's end
    (order :math:`2N`); the joints from their polynomials.

    Returns
    -------
    numpy.ndarray, shape (4 + m, len(s))
    """
    s = np.asarray(s, dtype=float).reshape(-1)
    pts = np.unique(np.clip(s, 0.0, 1.0))
    if pts.size > SAMPLE_CHUNK:
        # a chunk of the times at a time (each cut of the layout is exact on its own): the layout
        # cut at every one of 5000 times would pass the panels' bound (MAX_PANELS), which is there
        # for inputs too large to integrate, not for long outputs
        vals = np.concatenate([sample(body, basis, x0, T, c, part)
                               for part in np.array_split(pts, -(-pts.size // SAMPLE_CHUNK))], axis=1)
        return vals[:, np.searchsorted(pts, np.clip(s, 0.0, 1.0))]
    seg = _Segment(body, basis, x0, T, c)
    ys, widths, d = _solve(seg, points=pts)[:3]
    bounds = np.concatenate([[0.0], np.cumsum(widths)])
    bounds[-1] = 1.0
    idx = np.clip(np.searchsorted(bounds, s - 1e-12), 0, bounds.size - 1)
    out = np.empty((4 + seg.m, s.size))
    out[:4] = ys[idx].T
    out[4:] = seg.x0[4:, None] + seg.T * (seg.c @ basis.integral(s).T)
    out[4:, s == 0.0] = seg.x0[4:, None]  # the integrals vanish there (the basis series leaves ~1e-17)
    if not np.isfinite(out).all():
        raise IntegrationError("integration gave a non-finite state")
    return out


def _momentum_adjoint(seg, widths, d, g, Lam, J, Si):
    """:math:`\\kappa_j`, what the momentum's dependence on :math:`\\Omega_j` adds to
    :math:`\\partial q(1)/\\partial \\Omega_j` (module docstring), shape (P, N, 4, 3)."""
    P, N = widths.size, seg.N
    Gk = g @ d["W"]  # g_j W_j, (P, N, 4, 3)
    rhs = np.concatenate([np.swapaxes(Gk, -1, -2).reshape(P, 3 * N, 4),
                          ((widths[:, None] * seg.b[None, :])[:, :, None, None]
                           * np.swapaxes(J, -1, -2)).reshape(P, 3 * N, 3)], axis=2)
    R = (np.swapaxes(Si, -1, -2) @ rhs).reshape(P, N, 3, 7)  # S^-T rhs, panel by panel
    R1, R2 = np.swapaxes(R[..., :4], -1, -2), np.swapaxes(R[..., 4:], -1, -2)  # (P, N, 4, 3), (P, N, 3, 3)
    mu = np.zeros((P + 1, 4, 3))
    for k in range(P - 1, 0, -1):
        rho = R1[k] + mu[k + 1] @ R2[k]
        mu[k] = mu[k + 1] + rho.sum(axis=0)
    rho = R1 + mu[1:, None] @ R2  # (P, N, 4, 3)
    kappa = widths[:, None, None, None] * ((seg.a.T @ rho.reshape(P, N, 12)).reshape(P, N, 4, 3)
                                           + seg.b[None, :, None, None] * mu[1:, None])
    return kappa @ _skew(Lam)


# ---------------------------------------------------------------------- the momentum at sample times
@functools.lru_cache(maxsize=64)
def _dense_weights(N: int, theta_bytes: bytes) -> np.ndarray:
    """:math:`\\beta_j(\\theta) = \\int_0^\\theta \\ell_j` (the Lagrange basis on the Gauss nodes) at the
    points ``theta`` of [0, 1], shape (K, N), read-only."""
    theta = np.frombuffer(theta_bytes)
    Vi = _gauss(N)[3]
    Q = np.polynomial.legendre.legint(np.eye(N), lbnd=-1.0, scl=0.5, axis=0)
    out = (np.polynomial.legendre.legvander(2.0 * theta - 1.0, N) @ Q) @ Vi
    out.setflags(write=False)
    return out


def momentum_samples(body, basis, x0, T, c, s, *, jacobian: bool = False):
    """The angular momentum in the root's frame, :math:`\\lambda(\\sigma) = R(q(\\sigma))^\\top L`, at
    normalised times ``s`` of one segment, and with ``jacobian`` its derivatives in the coefficients,
    from the momentum's Gauss collocation (module docstring) and its continuous extension.

    On a panel :math:`[a, a + H]` the collocation polynomial is
    :math:`\\lambda(a + H\\theta) = \\lambda_a + H \\sum_j \\beta_j(\\theta) F_j`,
    :math:`\\beta_j(\\theta) = \\int_0^\\theta \\ell_j`, :math:`F_j = \\Lambda_j \\times \\Omega_j` (order
    :math:`N + 1` inside a panel, :math:`2N` at its ends). Its derivatives come forward, panel after
    panel, from the collocation equations differentiated at fixed layout: with the derivative of
    :math:`\\Omega_j` at fixed :math:`\\Lambda_j`, :math:`\\delta\\Omega^c_j` (module docstring, the
    Jacobian), and :math:`S` the panel's Newton matrix,

    .. math::  S\\,\\delta\\Lambda = \\mathbb{1} \\otimes \\delta\\lambda_a
               + H (\\alpha \\otimes \\mathbb{1})\\, [\\Lambda]_\\times \\delta\\Omega^c ,\\qquad
               \\delta F_j = J_j\\, \\delta\\Lambda_j + [\\Lambda_j]_\\times \\delta\\Omega^c_j ,\\qquad
               \\delta\\lambda(a + H\\theta) = \\delta\\lambda_a + H \\sum_j \\beta_j(\\theta)\\, \\delta F_j .

    Parameters
    ----------
    body : SpatialBody
    basis : InputBasis
    x0 : array_like, shape (4 + m,)
    T : float
    c : array_like, shape (m, basis.n)
    s : array_like, shape (K,)
        Normalised times in [0, 1], any order.
    jacobian : bool

    Returns
    -------
    lam : numpy.ndarray, shape (3, K)
    dlam : numpy.ndarray, shape (K, 3, m * basis.n), only with ``jacobian``
        Columns in flattened ``c`` order. At :math:`L = 0` both are zero.
    """
    s = np.clip(np.asarray(s, dtype=float).reshape(-1), 0.0, 1.0)
    if not np.any(np.asarray(body.L, dtype=float) != 0.0):
        lam = np.zeros((3, s.size))
        return (lam, np.zeros((s.size, 3, body.n_inputs * basis.n))) if jacobian else lam
    seg = _Segment(body, basis, x0, T, c)
    starts, widths, lam_a, F, dlam_a, dF = _momentum_panels(seg, jacobian)
    P, N = widths.size, seg.N
    bounds = np.concatenate([starts, [1.0]])
    idx = np.clip(np.searchsorted(bounds, s, side="right") - 1, 0, P - 1)
    theta = np.clip((s - starts[idx]) / widths[idx], 0.0, 1.0)
    beta = _dense_weights(N, np.ascontiguousarray(theta).tobytes())  # (K, N)
    lam = lam_a[idx] + widths[idx][:, None] * np.einsum("kj,kjc->kc", beta, F[idx])
    if not np.isfinite(lam).all():
        raise IntegrationError("integration gave a non-finite state")
    if not jacobian:
        return lam.T.copy()
    # panel by panel, one matrix product each (indexing dF by the samples' panels copied it per sample)
    mn = dF.shape[-1]
    dlam = np.empty((s.size, 3, mn))
    for p in np.unique(idx):
        at = idx == p
        dlam[at] = dlam_a[p] + widths[p] * (beta[at] @ dF[p].reshape(N, 3 * mn)).reshape(-1, 3, mn)
    return lam.T.copy(), dlam


def _momentum_panels(seg, jacobian):
    """The momentum's collocation panel by panel for :func:`momentum_samples`: ``(starts, widths,
    lam_a, F, dlam_a, dF)``, the momentum at the panels' starts (P + 1, 3), :math:`F_j` at the
    nodes (P, N, 3) and, with ``jacobian``, their derivatives in the coefficients (P + 1, 3, m n)
    and (P, N, 3, m n) (else ``None``). Remembered for the last few inputs of this thread, as
    :func:`_first_momentum`: an optimiser asks for the torques at the same coefficients on two
    grids (its cost's quadrature nodes and its torque limits' grid), and the forward sweep of the
    derivatives is most of the cost. It depends on the inputs alone, so the cache changes no
    number; the arrays are shared, read-only."""
    return _remembered("panels", seg, lambda: _sweep(seg, jacobian), lambda v: v[4] is not None or not jacobian)


def _sweep(seg, jacobian):
    """:func:`_momentum_panels`' numbers, computed."""
    m, n = seg.m, seg.n
    starts, widths, d, Lam, Jb, Si = _first_momentum(seg)
    P, N = widths.size, seg.N
    Om = d["w"] + (d["W"] @ Lam[..., None])[..., 0]  # (P, N, 3)
    F = np.cross(Lam, Om)
    lam_a = np.empty((P + 1, 3))
    lam_a[0] = np.einsum("a,iab,b->i", seg.x0[:4], seg.Q, seg.x0[:4])
    for k in range(P):
        lam_a[k + 1] = lam_a[k] + widths[k] * (seg.b @ F[k])
    dlam_a = dF = None
    if jacobian:
        # the derivative of Omega at fixed Lambda, per node: (P, N, 3, m n)
        Tn = seg.T
        dOm_du = (-Tn) * d["cA"]  # (P, N, 3, m)
        dOm_ds = -np.swapaxes((d["X"] @ Om[:, :, None, :, None])[..., 0] + Tn * d["y"], -1, -2)  # (P, N, 3, m)
        dOc = (dOm_du[..., :, None] * d["Bm"][:, :, None, None, :]
               + Tn * dOm_ds[..., :, None] * d["Bi"][:, :, None, None, :]).reshape(P, N, 3, m * n)
        rhsF = _skew(Lam) @ dOc  # [Lambda]x dOmega^c, (P, N, 3, m n)
        a, b, mn = seg.a, seg.b, m * n
        dlam_a = np.zeros((P + 1, 3, mn))
        dF = np.empty((P, N, 3, mn))
        # the sums over the nodes as matrix products (einsum's were a third of this sweep)
        aF = (a @ rhsF.reshape(P, N, 3 * mn)).reshape(P, N, 3, mn)  # (alpha (x) 1) [Lambda]x dOmega^c
        for k in range(P):
            H = widths[k]
            R = H * aF[k] + dlam_a[k]  # (N, 3, mn)
            dL = (Si[k] @ R.reshape(3 * N, mn)).reshape(N, 3, mn)
            dF[k] = Jb[k] @ dL + rhsF[k]
            dlam_a[k + 1] = dlam_a[k] + H * (b @ dF[k].reshape(N, 3 * mn)).reshape(3, mn)
    return starts, widths, lam_a, F, dlam_a, dF
