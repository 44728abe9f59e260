"""What a point's plan records beyond its status: the effort (the integral of the sum of squared
inputs, exact from the basis' Gram matrix), the peak rate (max |u|, exact: every local maximum
polished to rounding) and the peak joint torque of the system's torque model (on
:data:`TORQUE_SAMPLES` points per segment)."""

from __future__ import annotations

import functools
import math

import numpy as np

from ..core.system import model_torques, torque_model_of

__all__ = ["TORQUE_SAMPLES", "point_metrics"]

#: Torque samples per segment.
TORQUE_SAMPLES = 65


@functools.cache
def _grid(basis_cls, n):
    """Values, derivatives and integrals of the basis on TORQUE_SAMPLES points of [0, 1]."""
    s = np.linspace(0.0, 1.0, TORQUE_SAMPLES)
    b = basis_cls(n)
    return s, b.matrix(s), b.matrix(s, 1), b.integral(s)


@functools.cache
def _gram(basis_cls, n):
    return basis_cls(n).gram()


def _leg3(c, x):
    """A Legendre series and its first two derivatives at ``x`` in [-1, 1] (plain arithmetic)."""
    p0, p1, d0, d1, e0, e1 = 1.0, x, 0.0, 1.0, 0.0, 0.0
    u, du, ddu = c[0], 0.0, 0.0
    if len(c) > 1:
        u, du = u + c[1] * x, c[1]
    for k in range(1, len(c) - 1):
        p2 = ((2 * k + 1) * x * p1 - k * p0) / (k + 1)
        d2 = d0 + (2 * k + 1) * p1
        e2 = e0 + (2 * k + 1) * d1
        u, du, ddu = u + c[k + 1] * p2, du + c[k + 1] * d2, ddu + c[k + 1] * e2
        p0, p1, d0, d1, e0, e1 = p1, p2, d1, d2, e1, e2
    return u, du, ddu


def _peak_legendre(c, values) -> float:
    """max |u| on [0, 1] of the Legendre series ``c`` (in s), from its ``values`` on the sample grid:
    every discrete local maximum of |u| polished by Newton steps on u' = 0 (the ends are grid
    points), so the result is the exact maximum to rounding."""
    a = np.abs(values)
    best = float(a.max())
    inner = np.nonzero((a[1:-1] >= a[:-2]) & (a[1:-1] >= a[2:]))[0] + 1
    cl = c.tolist()
    h = 2.0 / (len(values) - 1)
    for i in inner:
        x = -1.0 + h * i
        for _ in range(8):
            _, du, ddu = _leg3(cl, x)
            if ddu == 0.0:
                break
            step = du / ddu
            x = min(1.0, max(-1.0, x - step))
            if abs(step) <= 1e-15:
                break
        if abs(x - (-1.0 + h * i)) <= 2 * h:  # stayed in its bump
            best = max(best, abs(_leg3(cl, x)[0]))
    return best


def point_metrics(result) -> tuple[float, float, float]:
    """``(effort, peak_rate, peak_torque)`` of a successful plan: the effort exactly (Gram matrix of
    the basis), the peak rate exactly (:func:`_peak_legendre`, or the segment's own extremes for
    another basis), the largest joint torque of the system's torque model
    (:meth:`~acroplan.core.system.ControlAffineSystem.torque_model`, the same torques as
    :meth:`PlanResult.torques <acroplan.core.result.PlanResult.torques>`) on
    :data:`TORQUE_SAMPLES` points per segment; NaN for a system without one."""
    effort, peak, torque = 0.0, 0.0, math.nan
    model, _ = torque_model_of(result.system)
    if model is not None:
        torque = 0.0
    for seg in result.segments:
        basis = result.basis_for(seg)
        T = seg.t1 - seg.t0
        C = seg.basis_coefficients
        legendre = basis.name == "legendre" and type(basis).__module__ == "acroplan.core.basis"
        if legendre:
            effort += T * float(np.sum(C * C / (2.0 * np.arange(C.shape[1]) + 1.0)))
        else:
            G = _gram(type(basis), basis.n)
            effort += T * float(np.einsum("ji,ik,jk->", C, G, C))
        s, V, _, _ = _grid(type(basis), basis.n)
        U = C @ V.T
        if legendre:
            peak = max(peak, max(_peak_legendre(C[j], U[j]) for j in range(C.shape[0])))
        else:
            peak = max(peak, seg.max_abs_u)
        if model is not None:
            tau = model_torques(model, result.system, basis, np.asarray(seg.start, dtype=float), T, C, s)
            torque = max(torque, float(np.max(np.abs(tau))))
    return effort, peak, torque
