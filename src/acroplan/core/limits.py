"""Limits by name, as linear constraints, a constrained solve, and exact compliance.

:class:`Limits` bounds any state whose rate is an input (``state_bounds={"phi": (lo, hi)}``) and
any input (``input_bounds={"u": 15.0}``, or ``u_max`` for every input). For an input :math:`u_j`
that is the rate of a state :math:`q`,

.. math::  u_j(s) = b(s)^\\top c_j ,\\qquad q(s) = q_0 + T\\, \\Big(\\int_0^s b\\Big)^\\top c_j ,

are both **linear** in the coefficients, so :math:`|u_j| \\le \\bar u_j` and
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

import dataclasses
import functools
import math
from typing import Mapping

import numpy as np

from . import backend
from .basis import InputBasis, check_points
from .errors import InvalidInputError
from .linalg import null_space
from .system import ControlAffineSystem

__all__ = ["Limits", "linear_limits", "violation", "solve_with_limits", "input_extremes", "sampled_input_peak",
           "COMPLIANCE_TOL"]

#: Largest limit violation a compliant result may have.
COMPLIANCE_TOL = 1e-9


def _real(field: str, v) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.floating, np.integer)) or not math.isfinite(v):
        raise InvalidInputError(field, f"must be a finite number, got {v!r}", "give a finite number or leave it out")
    return float(v)


@dataclasses.dataclass(frozen=True, init=False)
class Limits:
    """Bounds on states and inputs, by name.

    Parameters
    ----------
    state_bounds : mapping of str to (lo, hi), optional
        :math:`lo \\le q \\le hi` for a state ``q`` whose rate is an input (a joint angle); either
        end may be ``None`` (unbounded).
    input_bounds : mapping of str to float, optional
        :math:`|u_j| \\le \\bar u_j` (> 0) for the named inputs.
    u_max : float, optional
        :math:`|u_j| \\le u_{max}` for every input (a named bound, if smaller, wins).
    **shorthand
        ``NAME_min=lo``, ``NAME_max=hi``: a bound on state ``NAME`` (``phi_min``, ``phi_max`` for the
        acrobot's joint).

    Examples
    --------
    >>> Limits(phi_min=-3.0, phi_max=0.0, u_max=15.0) == Limits({"phi": (-3.0, 0.0)}, u_max=15.0)
    True
    """

    state_bounds: tuple[tuple[str, float | None, float | None], ...]
    input_bounds: tuple[tuple[str, float], ...]
    u_max: float | None

    def __init__(self, state_bounds: Mapping | None = None, input_bounds: Mapping | None = None, *,
                 u_max: float | None = None, **shorthand):
        bounds: dict[str, list] = {}
        for name, pair in dict(state_bounds or {}).items():
            try:
                lo, hi = pair
            except (TypeError, ValueError):
                raise InvalidInputError(f"state_bounds.{name}", f"must be a pair (lo, hi), got {pair!r}",
                                        "give for example (-3.14, 0.0); None for an open end") from None
            bounds[name] = [lo, hi]
        for key, v in shorthand.items():
            if key.endswith("_min") or key.endswith("_max"):
                name, side = key[:-4], 0 if key.endswith("_min") else 1
                if v is not None:
                    bounds.setdefault(name, [None, None])[side] = v
            else:
                raise InvalidInputError(key, "is not a limit", "give NAME_min / NAME_max for a state, u_max, "
                                        "state_bounds or input_bounds")
        clean = []
        for name, (lo, hi) in sorted(bounds.items()):
            lo = None if lo is None else _real(f"{name}_min", lo)
            hi = None if hi is None else _real(f"{name}_max", hi)
            if lo is not None and hi is not None and not lo < hi:
                raise InvalidInputError(f"{name}_min", f"must be < {name}_max, got {name}_min = {lo}, "
                                        f"{name}_max = {hi}", "swap or widen the joint limits")
            if lo is not None or hi is not None:
                clean.append((name, lo, hi))
        ins = []
        for name, v in sorted(dict(input_bounds or {}).items()):
            v = _real(f"input_bounds.{name}", v)
            if v <= 0:
                raise InvalidInputError(f"input_bounds.{name}", f"must be > 0, got {v}", "give the input's top speed")
            ins.append((name, v))
        if u_max is not None:
            u_max = _real("u_max", u_max)
            if u_max <= 0:
                raise InvalidInputError("u_max", f"must be > 0, got {u_max}", "give the joint's top speed in rad/s")
        object.__setattr__(self, "state_bounds", tuple(clean))
        object.__setattr__(self, "input_bounds", tuple(ins))
        object.__setattr__(self, "u_max", u_max)

    def __getattr__(self, key):  # NAME_min / NAME_max, as given (None when unbounded)
        if key.endswith("_min") or key.endswith("_max"):
            name = key[:-4]
            for n, lo, hi in object.__getattribute__(self, "state_bounds"):
                if n == name:
                    return lo if key.endswith("_min") else hi
            return None
        raise AttributeError(key)

    def __reduce__(self):
        return (_limits_from, (self.state_bounds, self.input_bounds, self.u_max))

    @property
    def active(self) -> bool:
        return bool(self.state_bounds or self.input_bounds) or self.u_max is not None

    @property
    def bounded_states(self) -> tuple[str, ...]:
        return tuple(name for name, _, _ in self.state_bounds)

    def bounds(self, state: str) -> tuple[float, float]:
        """``(lo, hi)`` of ``state``, with infinities where it is unbounded."""
        for name, lo, hi in self.state_bounds:
            if name == state:
                return (-math.inf if lo is None else lo), (math.inf if hi is None else hi)
        return -math.inf, math.inf

    def input_bound(self, name: str) -> float | None:
        """The bound on :math:`|u|` for input ``name`` (the smaller of its own and ``u_max``)."""
        own = dict(self.input_bounds).get(name)
        vals = [v for v in (own, self.u_max) if v is not None]
        return min(vals) if vals else None

    def check_for(self, system: ControlAffineSystem) -> None:
        """Raise :class:`InvalidInputError` when a bound names what ``system`` does not have."""
        rates = set(system.rate_inputs.values())
        for name in self.bounded_states:
            if name not in system.state_names:
                raise InvalidInputError(f"{name}_min", f"{name!r} is not a state of {type(system).__name__}",
                                        f"states are {list(system.state_names)}")
            if name not in rates:
                raise InvalidInputError(f"{name}_min", f"bounds need a state whose rate is an input, and "
                                        f"{name!r} of {type(system).__name__} is not one",
                                        "leave the bound out")
        for name, _ in self.input_bounds:
            if name not in system.input_names:
                raise InvalidInputError(f"input_bounds.{name}", f"{name!r} is not an input of "
                                        f"{type(system).__name__}", f"inputs are {list(system.input_names)}")

    def at_bound(self, state: str, q: float, tol: float = 1e-12) -> bool:
        """Whether ``q`` lies on a bound of ``state`` (relative tolerance ``tol``)."""
        lo, hi = self.bounds(state)
        return abs(q - lo) <= tol * max(1.0, abs(q)) or abs(q - hi) <= tol * max(1.0, abs(q))

    def describe(self) -> str:
        """The limits in words, for messages: ``"the joint and rate limits"``, ``"the joint limits"``
        or ``"the rate limits"``."""
        joint, rate = bool(self.state_bounds), self.u_max is not None or bool(self.input_bounds)
        return {(True, True): "the joint and rate limits", (True, False): "the joint limits",
                (False, True): "the rate limits", (False, False): "no limits"}[joint, rate]

    def to_dict(self) -> dict:
        """Plain JSON types: ``{"state_bounds": {name: [lo, hi]}, "input_bounds": {...}, "u_max": ...}``."""
        return {"state_bounds": {n: [lo, hi] for n, lo, hi in self.state_bounds},
                "input_bounds": dict(self.input_bounds), "u_max": self.u_max}


def _limits_from(state_bounds, input_bounds, u_max) -> Limits:
    return Limits({n: (lo, hi) for n, lo, hi in state_bounds}, dict(input_bounds), u_max=u_max)


def _bounded(system: ControlAffineSystem, limits: Limits):
    """(input index, state index, lo, hi) of every bounded state (a state whose rate is an input)."""
    out = []
    for state in limits.bounded_states:
        inputs = [name for name, st in system.rate_inputs.items() if st == state]
        lo, hi = limits.bounds(state)
        out.append((system.input_names.index(inputs[0]), system.state_names.index(state), lo, hi))
    return out


def linear_limits(system, basis: InputBasis, x0, T: float, limits: Limits, grid: int = 64, margin: float = 0.0,
                  ends: int = 0):
    """Rows ``A`` and bounds ``b`` with ``A c <= b`` on a grid (flattened input-major ``c``): ``grid``
    uniform points, and with ``ends`` > 1 also that many Chebyshev-Lobatto points, which crowd
    towards the ends (:func:`~acroplan.core.basis.check_points`).

    Returns
    -------
    A : numpy.ndarray, shape (q, m * n)
    b : numpy.ndarray, shape (q,)
    """
    m, n = system.n_inputs, basis.n
    s = check_points(grid, ends)
    rows, rhs = [], []

    def add(j, M, upper, sign):  # the rows of input j's block, one block of rows at once
        block = np.zeros((M.shape[0], m * n))
        block[:, j * n:(j + 1) * n] = sign * M
        rows.append(block)
        rhs.append(np.asarray(upper, dtype=float))

    V = None
    for j, name in enumerate(system.input_names):
        U = limits.input_bound(name)
        if U is None:
            continue
        V = basis.matrix(s) if V is None else V
        U = U * (1.0 - margin)
        add(j, V, np.full(s.size, U), 1.0)
        add(j, V, np.full(s.size, U), -1.0)
    for j, i, lo, hi in _bounded(system, limits):
        W = T * basis.integral(s[1:-1])  # the ends are the waypoints themselves
        q0 = float(x0[i])
        width = (hi - lo) if np.isfinite(hi - lo) else 1.0
        if np.isfinite(hi):
            add(j, W, np.full(s.size - 2, hi - q0 - margin * width), 1.0)
        if np.isfinite(lo):
            add(j, W, np.full(s.size - 2, q0 - lo - margin * width), -1.0)
    if not rows:
        return np.zeros((0, m * n)), np.zeros(0)
    return np.vstack(rows), np.concatenate(rhs)


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


def sampled_input_peak(basis: InputBasis, c) -> float:
    """:math:`\\max_j \\max_k |u_j(s_k)|` of the series ``c`` (rows ``(r, n)``, or one ``(n,)``) on
    the 257 points :math:`s_k` of the check grid: a lower bound of the exact peak
    (:func:`input_extremes`), without its root finding (a matrix product: 8 us for one series of 10
    coefficients in a ``timeit`` loop, against 0.1-0.15 ms for the exact peak of a two-link plan's
    segment)."""
    c = np.asarray(c, dtype=float)
    return float(np.abs(_grid_matrix(basis, "u") @ c.T).max())


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
    a bounded state at the roots of its rate :math:`u` and the ends (roots from the power series,
    values from the basis); a grid of 257 points is checked too.

    Returns
    -------
    dict
        ``u``: largest :math:`\\max(0, \\max|u_j| - \\bar u_j)`; ``state``: largest excursion past a
        state bound; ``max_abs_u``: :math:`\\max_j \\max |u_j|`; ``state_ranges``: ``{state: (lo, hi)}``
        of the bounded states.
    """
    c = np.asarray(c, dtype=float).reshape(system.n_inputs, basis.n)
    out = {"u": 0.0, "state": 0.0, "max_abs_u": 0.0, "state_ranges": {}}
    for j, name in enumerate(system.input_names):
        lo, hi = input_extremes(basis, c[j])
        top = max(abs(lo), abs(hi))
        out["max_abs_u"] = max(out["max_abs_u"], top)
        U = limits.input_bound(name)
        if U is not None:
            out["u"] = max(out["u"], top - U)
    for j, i, qlo, qhi in _bounded(system, limits):
        q0, cj = float(x0[i]), c[j]
        lo, hi = _extremes(basis.to_power_s(cj), lambda s: q0 + T * (basis.integral(s) @ cj),
                           q0 + T * (_grid_matrix(basis, "int") @ cj))
        out["state_ranges"][system.state_names[i]] = (lo, hi)
        out["state"] = max(out["state"], qlo - lo, hi - qhi)
    return out


def solve_with_limits(system, basis: InputBasis, x0, x1, T: float, limits: Limits, c_start, *, B=None, d=None,
                      tol: float = 1e-10, max_evaluations: int = 400):
    """Constrained solve from ``c_start`` (module docstring).

    Returns
    -------
    SegmentSolve
        ``method="deform+limits"``; ``success`` when the endpoint is within ``tol`` and the limits
        hold to :data:`COMPLIANCE_TOL`.
    """
    from .continuation import SegmentSolve

    x0 = np.asarray(x0, dtype=float)
    x1 = np.asarray(x1, dtype=float)
    m, n = system.n_inputs, basis.n
    N = m * n
    if B is None:
        B, d = np.zeros((0, N)), np.zeros(0)
    c_p = np.linalg.lstsq(B, d, rcond=None)[0] if B.shape[0] else np.zeros(N)
    Z = null_space(B, N)
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
            cache[key] = backend.endpoint(system, basis, x0, T, c_p + Z @ z)
        return cache[key]

    z0 = Z.T @ (np.asarray(c_start, dtype=float).reshape(-1) - c_p)
    unit = 1.0 + float(z0 @ Q @ z0)
    cons = [{"type": "eq", "fun": lambda z: -system.diff(ev(z)[0], x1) / scale,
             "jac": lambda z: system.tangent_jacobian(ev(z)[0], ev(z)[1]) @ Z / scale}]
    if AZ.shape[0]:
        cons.append({"type": "ineq", "fun": lambda z: bz - AZ @ z, "jac": lambda z: -AZ})
    from scipy.optimize import minimize  # here: scipy.optimize takes 0.4 s to import

    try:
        res = minimize(lambda z: (z @ Q @ z + 2 * q @ z) / unit, z0, jac=lambda z: 2 * (Q @ z + q) / unit,
                       constraints=cons, method="SLSQP", options={"maxiter": max_evaluations, "ftol": 1e-14})
        z = res.x
    except backend.IntegrationError as e:
        return SegmentSolve(success=False, message=f"the integrator failed during the constrained solve ({e})",
                            coefficients=np.asarray(c_start, dtype=float).reshape(m, n), final_error=float("inf"),
                            evaluations=evals[0], method="deform+limits")
    # polish the endpoint with minimum-norm Newton steps
    y, J = ev(z)
    for _ in range(8):
        r = system.diff(y, x1)
        if np.linalg.norm(r) <= tol * 1e-2:
            break
        z = z + np.linalg.lstsq(system.tangent_jacobian(y, J) @ Z, r, rcond=None)[0]
        y, J = ev(z)
    c = c_p + Z @ z
    err = system.error(y, x1)
    v = violation(system, basis, x0, T, c, limits)
    ok = err <= tol and v["u"] <= COMPLIANCE_TOL and v["state"] <= COMPLIANCE_TOL
    msg = (f"constrained solve (SLSQP): endpoint error {err:.2e}, limit violation "
           f"{max(v['u'], v['state']):.2e}, {res.message}")
    return SegmentSolve(success=ok, message=msg, coefficients=c.reshape(m, n), final_error=err, evaluations=evals[0],
                        method="deform+limits")
