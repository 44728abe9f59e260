"""The independent check of spatial bodies, by Pinocchio: nothing here uses the sympy fields.

* :func:`pinocchio_momentum_map`: :math:`\\mathbb{I}(s)` and :math:`A(s)` read from Pinocchio's
  centroidal momentum map :math:`A_G(q)` (``computeCentroidalMap``, world frame, at the centre of
  mass): at the root attitude :math:`R`, its angular rows are :math:`R\\,\\mathbb{I}(s)` in the
  root's angular-velocity columns and :math:`R\\,A(s)` in the joint columns;
* :func:`root_twist`: the root's twist :math:`\\nu = (v, \\Omega)` (root frame) that gives the
  centroidal momentum :math:`h_G = (0, L)` with the joint rates :math:`u`:

  .. math::  A_{G,\\mathrm{root}}(q)\\,\\nu = (0, L) - A_{G,\\mathrm{joints}}(q)\\,u ,

  six equations in six unknowns (the centre of mass at rest, the angular momentum :math:`L`);
* :func:`simulate_with_pinocchio`: a forward simulation driven by that twist alone,
  :math:`\\dot q = \\tfrac12 q \\otimes (0, \\Omega)`, :math:`\\dot s = u(t)`, scipy's DOP853 at
  rtol = atol = 3e-14 and at least 16 steps, as :mod:`acroplan.core.verify` does;
* :func:`pinocchio_errors`: the check ``plan(verify=True)`` uses for spatial bodies. The joint
  angles are the exact integrals of the planned inputs (integrated in their basis), so only the
  attitude is integrated (DOP853, the quaternion renormalised at the end: its norm drifts by about
  1e-14); each segment's error is :math:`\\max(\\angle(q_{target}^{-1} q_{check}),\\ \\max_j |s_j -
  s_{j,target}|)`, the segments chained from the first waypoint.

Pinocchio is optional (``pip install acroplan[bodies]``) and imported on first use.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy.integrate import solve_ivp
from scipy.linalg import lapack

from ..tree.check import simulate_driven
from ..tree.pin import require_pinocchio
from . import rotations as rot
from .links import SpatialLinkTable
from .pin import SpatialPinocchioBody, build_model

__all__ = ["pinocchio_body", "pinocchio_momentum_map", "root_twist", "simulate_with_pinocchio", "pinocchio_segment",
           "pinocchio_errors", "state_error", "norm_drift",
           "RTOL", "ATOL"]

RTOL = 3e-14
ATOL = 3e-14


@functools.lru_cache(maxsize=64)
def _cached(table: SpatialLinkTable) -> SpatialPinocchioBody:
    return build_model(table)


def pinocchio_body(body) -> SpatialPinocchioBody:
    """The Pinocchio model of ``body``'s link table (cached per table)."""
    return _cached(SpatialLinkTable.of(body))


def pinocchio_momentum_map(body, shape):
    """:math:`\\mathbb{I}(s)` and :math:`A(s)` from Pinocchio's centroidal map at the identity attitude.

    Returns
    -------
    I : numpy.ndarray, shape (3, 3)
    A : numpy.ndarray, shape (3, m)
    """
    pin = require_pinocchio()
    pb = pinocchio_body(body)
    x = np.concatenate([[1.0, 0.0, 0.0, 0.0], np.asarray(shape, dtype=float)])
    Ag = pin.computeCentroidalMap(pb.model, pb.model.createData(), pb.configuration(x))
    return Ag[3:6, 3:6].copy(), Ag[3:6, pb.idx_v].copy()


def _as_slice(index):
    """``index`` (a list of positions) as a slice when it is a run of consecutive positions (a
    slice is a view: no copy in the right-hand side), else as given."""
    idx = list(index)
    if idx and idx == list(range(idx[0], idx[0] + len(idx))):
        return slice(idx[0], idx[0] + len(idx))
    return index


class _Twist:
    """:math:`\\Omega(q, s, u)` from Pinocchio's centroidal map (module docstring)."""

    def __init__(self, body):
        self.pin = require_pinocchio()
        self.pb = pinocchio_body(body)
        self.data = self.pb.model.createData()
        self.h = np.concatenate([np.zeros(3), np.asarray(body.L, dtype=float)])
        self.iq = _as_slice(self.pb.idx_q)
        self.iv = _as_slice(self.pb.idx_v)
        self.q = np.zeros(self.pb.model.nq)

    def __call__(self, quat, s, u):
        q = self.q
        n = np.sqrt(quat @ quat)
        q[3:6] = quat[1:] / n
        q[6] = quat[0] / n
        q[self.iq] = s
        Ag = self.pin.computeCentroidalMap(self.pb.model, self.data, q)
        # LAPACK's gesv, as numpy.linalg.solve, without its array wrapping (7 of this call's 30 us:
        # 16.5 against 9.3 us a solve)
        _, _, nu, info = lapack.dgesv(Ag[:, :6], self.h - Ag[:, self.iv] @ u)
        if info != 0:
            raise RuntimeError(f"the centroidal map's root block is singular (gesv info {info})")
        return nu[3:6]


def root_twist(body, state, u) -> np.ndarray:
    """The root's angular velocity :math:`\\Omega` (root frame) by Pinocchio (module docstring), shape (3,)."""
    x = np.asarray(state, dtype=float)
    return _Twist(body)(x[:4], x[4:], np.asarray(u, dtype=float).reshape(-1))


def simulate_with_pinocchio(body, x0, t0: float, t1: float, u_of_t, rtol: float = RTOL, atol: float = ATOL,
                            t_eval=None):
    """Forward simulation of a spatial body driven by Pinocchio's centroidal map (module docstring).

    Parameters
    ----------
    body : SpatialBody
        Its link table and ``L`` are used; its sympy fields are not.
    x0 : array_like, shape (4 + m,)
    t0, t1 : float
    u_of_t : callable
        ``u_of_t(t)``: the joint rates at absolute time ``t``, shape ``(m,)`` or ``(m, 1)``.
    t_eval : array_like, optional
        Times to report (default: ``t1`` only).

    Returns
    -------
    scipy.integrate.OdeResult
        ``.t`` absolute times, ``.y`` shape (4 + m, len(t)).
    """
    twist = _Twist(body)
    m = body.n_inputs
    t0 = float(t0)

    def fun(tau, x):
        u = np.asarray(u_of_t(t0 + tau), dtype=float).reshape(m)
        w = twist(x[:4], x[4:], u)
        return np.concatenate([quaternion_rate(x[:4].tolist(), w.tolist()), u])

    return simulate_driven(fun, x0, t0, t1, rtol=rtol, atol=atol, t_eval=t_eval)


def quaternion_rate(q, omega) -> np.ndarray:
    """:math:`\\dot q = \\tfrac12 q \\otimes (0, \\Omega) = \\tfrac12 \\Xi(q)\\,\\Omega` (``rotations.xi``),
    written out: the right-hand side the check evaluates thousands of times a plan (on Python
    floats: ``q`` and ``omega`` sequences of 4 and 3 numbers)."""
    w, x, y, z = q
    a, b, c = omega
    return np.array([-x * a - y * b - z * c, w * a - z * b + y * c, z * a + w * b - x * c,
                     -y * a + x * b + w * c]) * 0.5


def pinocchio_segment(body, x0, T: float, basis, coefficients, *, twist=None):
    """One segment of the Pinocchio-driven motion (module docstring): the joints exactly, the attitude
    by DOP853.

    Parameters
    ----------
    body : SpatialBody
    x0 : array_like, shape (4 + m,)
    T : float
    basis : InputBasis
    coefficients : array_like, shape (m, basis.n)
        The joint rates in ``basis`` on :math:`\\sigma = (t - t_0)/T`.

    Returns
    -------
    numpy.ndarray, shape (4 + m,)
        The state at the segment's end (the quaternion normalised).
    """
    twist = twist or _Twist(body)
    c = np.asarray(coefficients, dtype=float)
    x0 = np.asarray(x0, dtype=float)
    s0 = x0[4:]
    ct = c.T.copy()

    def fun(tau, q):
        V, B = basis.at(tau / T)
        u = (V @ ct)[0]
        s = s0 + T * (B @ ct)[0]
        return quaternion_rate(q.tolist(), twist(q, s, u).tolist())

    sol = solve_ivp(fun, (0.0, T), x0[:4] / np.linalg.norm(x0[:4]), method="DOP853", rtol=RTOL, atol=ATOL,
                    max_step=T / 16, t_eval=[T])
    if not sol.success:
        raise RuntimeError(f"the Pinocchio-driven simulation failed: {sol.message}")
    q = sol.y[:, -1]
    sT = s0 + T * (basis.integral([1.0]) @ ct)[0]
    return np.concatenate([q / np.linalg.norm(q), sT])


def pinocchio_errors(body, x0, segments) -> np.ndarray:
    """The independent check of a spatial body's plan by Pinocchio (module docstring).

    Parameters
    ----------
    body : SpatialBody
    x0 : array_like, shape (4 + m,)
    segments : sequence of SegmentResult

    Returns
    -------
    numpy.ndarray, shape (len(segments),)
        Each segment's :math:`\\max(\\angle(q_{target}^{-1} q),\\ \\max_j |s_j - s_{j,target}|)`.
    """
    from ...core.basis import Legendre

    twist = _Twist(body)
    x = np.asarray(x0, dtype=float)
    out = []
    for seg in segments:
        basis = seg.basis if seg.basis is not None else Legendre(seg.basis_coefficients.shape[1])
        x = pinocchio_segment(body, x, seg.t1 - seg.t0, basis, seg.basis_coefficients, twist=twist)
        out.append(state_error(x, seg.target))
    return np.array(out)


def state_error(x, target) -> float:
    """:math:`\\max(\\angle(q^{-1} q_{target}),\\ \\max_j |s_j - s_{j,target}|)` of two states."""
    x = np.asarray(x, dtype=float)
    target = np.asarray(target, dtype=float)
    ang = rot.angle_between(x[:4] / np.linalg.norm(x[:4]), target[:4] / np.linalg.norm(target[:4]))
    return float(max(ang, float(np.max(np.abs(x[4:] - target[4:]))) if x.size > 4 else 0.0))


def norm_drift(result, samples: int = 401) -> float:
    """How far the planned motion's quaternion strays from unit norm: :math:`\\max_t ||q(t)| - 1|`
    over ``samples`` equally spaced times of the compiled integrator's dense output (the norm is a
    first integral of the state equation, kept to rounding: about 1e-15).

    Parameters
    ----------
    result : PlanResult
        A plan of a spatial body.

    Returns
    -------
    float
    """
    t = np.linspace(result.times[0], result.times[-1], samples)
    q = result.evaluate(t).states[:4]
    return float(np.max(np.abs(np.linalg.norm(q, axis=0) - 1.0)))
