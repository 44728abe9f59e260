"""Exact checks of acrobot plans, with no ODE integrator: :func:`flat_output_errors`."""

from __future__ import annotations

import functools
import math

import numpy as np

from ...core.basis import Legendre, gauss_legendre

__all__ = ["flat_output_errors", "chained_errors"]

#: Panels of the composite rule at most (64 nodes each).
MAX_PANELS = 200_000


@functools.lru_cache(maxsize=16)
def _nodes(panels: int):
    """Composite Gauss-Legendre nodes and weights on [0, 1]: ``panels`` panels of 64 nodes."""
    xg, wg = gauss_legendre(64)
    s = ((np.arange(panels)[:, None] + (xg[None, :] + 1.0) / 2.0) / panels).ravel()
    w = np.tile(wg / (2.0 * panels), panels)
    s.flags.writeable = False
    w.flags.writeable = False
    return s, w


def flat_output_errors(result) -> np.ndarray:
    """Endpoint errors of an acrobot plan by the flat-output identity, with no ODE integrator.

    .. math::  \\theta(t_1) = \\theta(t_0) - [F(\\varphi(t_1)) - F(\\varphi(t_0))]
               + P_0 \\int_{t_0}^{t_1} \\frac{dt}{h(\\varphi(t))},

    with :math:`\\varphi(t) = \\varphi(t_0) + \\int u` integrated exactly in the segment's basis
    (:meth:`InputBasis.integral`) and the time integral by composite Gauss-Legendre with 64 nodes
    per panel and as many panels as the joint needs: at least 32, and one per radian of its
    largest travel :math:`\\max|u|\\,T` (so a joint that turns 1000 rad is resolved as well as one
    that turns 1), chained through the segments from the first waypoint like
    :func:`acroplan.plan`'s own check. Every step is exact up to rounding, so this resolves
    errors far below the floor of an adaptive integrator at rtol ~ 3e-14, whose own error on
    :math:`\\theta` grows with :math:`|\\theta|` (measured in ``benchmarks/RESULTS.md``).

    Parameters
    ----------
    result : PlanResult
        A plan of an :class:`~acroplan.Acrobot` whose segments carry their basis.

    Returns
    -------
    numpy.ndarray, shape (number of segments,)
        :math:`\\max(|\\theta - \\theta_{target}|, |\\varphi - \\varphi_{target}|)` at each
        segment's end.
    """
    robot = result.system
    if not all(hasattr(robot, name) for name in ("F", "h", "P0")):
        raise TypeError("flat_output_errors needs an acrobot (a system with a flat output F, h, P0)")
    return chained_errors(robot, result.waypoints[0], result.segments)


def chained_errors(robot, x0, segments) -> np.ndarray:
    """:func:`flat_output_errors` of ``segments`` chained from the state ``x0`` (each segment
    carries its basis)."""
    theta, phi = (float(v) for v in x0)
    errors = []
    for seg in segments:
        T = seg.t1 - seg.t0
        panels = int(min(MAX_PANELS, max(32, math.ceil(seg.max_abs_u * T))))
        _, w = _nodes(panels)
        basis = seg.basis if seg.basis is not None else Legendre(seg.basis_coefficients.shape[1])
        c = np.asarray(seg.basis_coefficients[0], dtype=float)
        total = T * float(w @ (1.0 / robot.h(phi + T * (_integral(basis, panels) @ c))))
        phi_end = phi + T * float(basis.integral([1.0])[0] @ c)
        theta = theta - (float(robot.F(phi_end)) - float(robot.F(phi))) + robot.P0 * total
        phi = phi_end
        errors.append(max(abs(theta - float(seg.target[0])), abs(phi - float(seg.target[1]))))
    return np.array(errors)


@functools.lru_cache(maxsize=64)
def _integral(basis, panels: int):
    """The basis integrals at the nodes of :func:`_nodes` (``panels``), cached, read-only."""
    M = basis.integral(_nodes(panels)[0])
    M.flags.writeable = False
    return M
