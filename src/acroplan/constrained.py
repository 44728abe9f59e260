"""Joint and rate limits on one segment: linear constraints, a constrained solve, exact compliance.

For an input :math:`u_j` that is the rate of a state :math:`q` (the acrobot: :math:`u = \\dot\\varphi`),

.. math::  u_j(s) = b(s)^\\top c_j ,\\qquad q(s) = q_0 + T\\, \\Big(\\int_0^s b\\Big)^\\top c_j ,

are both **linear** in the coefficients, so :math:`|u| \\le u_{max}` and
:math:`q_{min} \\le q \\le q_{max}` on a grid are linear inequalities :math:`A c \\le b`.

:func:`solve_with_limits` starts from a path-deformation solution that breaks the limits and
solves, with scipy's SLSQP,

.. math::  \\min_z\\ \\int_0^1 \\|u\\|^2 ds \\quad\\text{s.t.}\\quad \\Phi(c(z)) = x_1,\\quad
           A c(z) \\le b - \\text{margin},

in the reduced coordinates :math:`c = c_p + Z z` that carry the input conditions, then polishes the
endpoint with minimum-norm Newton steps. :func:`violation` measures compliance exactly: the
extremes of a polynomial :math:`u` lie at the roots of :math:`u'` and of :math:`q` at the roots of
:math:`u`, and a dense grid is checked too.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy.optimize import minimize

from . import _integrate
from .basis import InputBasis
from .reach import Limits
from .systems.base import ControlAffineSystem

__all__ = ["linear_limits", "violation", "solve_with_limits", "COMPLIANCE_TOL"]

#: Largest limit violation a compliant result may have.
COMPLIANCE_TOL = 1e-9


def _bounded(system: ControlAffineSystem, limits: Limits):
    """(input index, state index) of the bounded rate state, or None."""
    if limits.phi_min is None and limits.phi_max is None:
        return None
    state = limits.state
    inputs = [name for name, st in system.rate_inputs.items() if st == state]
    j = system.input_names.index(inputs[0])
    return j, system.state_names.index(state)


def linear_limits(system, basis: InputBasis, x0, T: float, limits: Limits, grid: int = 64, margin: float = 0.0):
    """Rows ``A`` and bounds ``b`` with ``A c <= b`` on a grid (flattened input-major ``c``).

    Returns
    -------
    A : numpy.ndarray, shape (q, m * n)
    b : numpy.ndarray, shape (q,)
    """
    m, n = system.n_inputs, basis.n
    s = np.linspace(0.0, 1.0, grid)
    rows, rhs = [], []

    def add(j, M, upper, sign):
        for row, ub in zip(M, upper):
            r = np.zeros(m * n)
            r[j * n:(j + 1) * n] = sign * row
            rows.append(r)
            rhs.append(ub)

    if limits.u_max is not None:
        V = basis.matrix(s)
        U = limits.u_max * (1.0 - margin)
        for j in range(m):
            add(j, V, np.full(grid, U), 1.0)
            add(j, V, np.full(grid, U), -1.0)
    b = _bounded(system, limits)
    if b is not None:
        j, i = b
        W = T * basis.integral(s[1:-1])  # the ends are the waypoints themselves
        q0 = float(x0[i])
        width = (limits.hi - limits.lo) if np.isfinite(limits.hi - limits.lo) else 1.0
        if limits.phi_max is not None:
            add(j, W, np.full(grid - 2, limits.phi_max - q0 - margin * width), 1.0)
        if limits.phi_min is not None:
            add(j, W, np.full(grid - 2, q0 - limits.phi_min - margin * width), -1.0)
    if not rows:
        return np.zeros((0, m * n)), np.zeros(0)
    return np.array(rows), np.array(rhs)


_GRID = np.linspace(0.0, 1.0, 257)
_P = np.polynomial.polynomial


@functools.lru_cache(maxsize=64)
def _grid_matrix(basis: InputBasis, kind: str) -> np.ndarray:
    """Values (``"u"``) or integrals from 0 (``"int"``) of the basis on the check grid, read-only."""
    M = basis.matrix(_GRID) if kind == "u" else basis.integral(_GRID)
    M.flags.writeable = False
    return M


def _extremes(crit: np.ndarray, values, on_grid: np.ndarray):
    """Min and max on [0, 1] of a polynomial whose critical points are the real roots of the power
    series ``crit`` in [0, 1] (exact), given ``values(s)`` and its values on the check grid (the
    ends included, so the grid also guards the root finder)."""
    nz = np.flatnonzero(crit)
    lo, hi = float(on_grid.min()), float(on_grid.max())
    if nz.size and nz[-1] > 0:
        r = _P.polyroots(crit[: nz[-1] + 1])
        real = r.real[(np.abs(r.imag) < 1e-9) & (r.real >= 0.0) & (r.real <= 1.0)]
        if real.size:
            at = values(real)
            lo, hi = min(lo, float(at.min())), max(hi, float(at.max()))
    return lo, hi


def input_extremes(basis: InputBasis, c) -> tuple[float, float]:
    """Exact min and max of :math:`u(s) = \\sum_i c_i b_i(s)` on [0, 1]: at the ends and the roots
    of :math:`u'`, all values evaluated in the basis (stable at every size)."""
    c = np.asarray(c, dtype=float)
    Q = basis.to_power_s(c)
    crit = Q[1:] * np.arange(1, basis.n) if basis.n > 1 else np.zeros(1)
    return _extremes(crit, lambda s: basis.matrix(s) @ c, _grid_matrix(basis, "u") @ c)


def violation(system, basis: InputBasis, x0, T: float, c, limits: Limits) -> dict:
    """Exact limit violations of one segment (0 when compliant).

    The extremes of the polynomial :math:`u` lie at the roots of :math:`u'` and the ends, those of
    the joint angle at the roots of :math:`u` and the ends (roots from the power series, values
    from the basis); a grid of 257 points is checked too.

    Returns
    -------
    dict
        ``u``: :math:`\\max(0, \\max|u| - u_{max})`; ``state``: largest excursion past the joint
        limits; ``max_abs_u``, ``state_range``: the extremes found.
    """
    c = np.asarray(c, dtype=float).reshape(system.n_inputs, basis.n)
    out = {"u": 0.0, "state": 0.0, "max_abs_u": 0.0, "state_range": None}
    for j in range(system.n_inputs):
        lo, hi = input_extremes(basis, c[j])
        out["max_abs_u"] = max(out["max_abs_u"], abs(lo), abs(hi))
    if limits.u_max is not None:
        out["u"] = max(0.0, out["max_abs_u"] - limits.u_max)
    b = _bounded(system, limits)
    if b is not None:
        j, i = b
        q0, cj = float(x0[i]), c[j]
        lo, hi = _extremes(basis.to_power_s(cj), lambda s: q0 + T * (basis.integral(s) @ cj),
                           q0 + T * (_grid_matrix(basis, "int") @ cj))
        out["state_range"] = (lo, hi)
        out["state"] = max(0.0, limits.lo - lo, hi - limits.hi)
    return out


def solve_with_limits(system, basis: InputBasis, x0, x1, T: float, limits: Limits, c_start, *, B=None, d=None,
                      tol: float = 1e-10, max_evaluations: int = 400):
    """Constrained solve from ``c_start`` (module docstring).

    Returns
    -------
    (success, c, final_error, evaluations, message)
    """
    from .continuation import _null_space

    x0 = np.asarray(x0, dtype=float)
    x1 = np.asarray(x1, dtype=float)
    m, n = system.n_inputs, basis.n
    N = m * n
    if B is None:
        B, d = np.zeros((0, N)), np.zeros(0)
    c_p = np.linalg.lstsq(B, d, rcond=None)[0] if B.shape[0] else np.zeros(N)
    Z = _null_space(B, N)
    A, b = linear_limits(system, basis, x0, T, limits, margin=2e-3)
    AZ, bz = A @ Z, b - A @ c_p
    Qb = np.kron(np.eye(m), basis.gram())
    Q = Z.T @ Qb @ Z
    q = Z.T @ Qb @ c_p
    scale = 1.0 + float(np.max(np.abs(x1)))
    cache = {}
    evals = [0]

    def ev(z):
        key = z.tobytes()
        if key not in cache:
            evals[0] += 1
            cache.clear()
            cache[key] = _integrate.endpoint(system, basis, x0, T, c_p + Z @ z)
        return cache[key]

    z0 = Z.T @ (np.asarray(c_start, dtype=float).reshape(-1) - c_p)
    unit = 1.0 + float(z0 @ Q @ z0)
    cons = [{"type": "eq", "fun": lambda z: (ev(z)[0] - x1) / scale, "jac": lambda z: ev(z)[1] @ Z / scale}]
    if AZ.shape[0]:
        cons.append({"type": "ineq", "fun": lambda z: bz - AZ @ z, "jac": lambda z: -AZ})
    try:
        res = minimize(lambda z: (z @ Q @ z + 2 * q @ z) / unit, z0, jac=lambda z: 2 * (Q @ z + q) / unit,
                       constraints=cons, method="SLSQP", options={"maxiter": max_evaluations, "ftol": 1e-14})
        z = res.x
    except _integrate.IntegrationError as e:
        return False, c_start, float("inf"), evals[0], f"the integrator failed during the constrained solve ({e})"
    # polish the endpoint with minimum-norm Newton steps
    y, J = ev(z)
    for _ in range(8):
        r = x1 - y
        if np.linalg.norm(r) <= tol * 1e-2:
            break
        z = z + np.linalg.lstsq(J @ Z, r, rcond=None)[0]
        y, J = ev(z)
    c = c_p + Z @ z
    err = float(np.linalg.norm(y - x1))
    v = violation(system, basis, x0, T, c, limits)
    ok = err <= tol and v["u"] <= COMPLIANCE_TOL and v["state"] <= COMPLIANCE_TOL
    msg = (f"constrained solve (SLSQP): endpoint error {err:.2e}, limit violation "
           f"{max(v['u'], v['state']):.2e}, {res.message}")
    return ok, c.reshape(m, n), err, evals[0], msg
