"""Exact checks of acrobot plans, with no ODE integrator: :func:`flat_output_errors`."""

from __future__ import annotations

import numpy as np

__all__ = ["flat_output_errors"]


def flat_output_errors(result) -> np.ndarray:
    """Endpoint errors of an acrobot plan by the flat-output identity, with no ODE integrator.

    .. math::  \\theta(t_1) = \\theta(t_0) - [F(\\varphi(t_1)) - F(\\varphi(t_0))]
               + P_0 \\int_{t_0}^{t_1} \\frac{dt}{h(\\varphi(t))},

    with :math:`\\varphi(t) = \\varphi(t_0) + \\int u` integrated exactly in the segment's basis
    (:meth:`InputBasis.integral`) and the time integral by composite Gauss-Legendre
    (32 panels of 64 nodes), chained through the segments from the first waypoint like
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
    xg, wg = np.polynomial.legendre.leggauss(64)
    panels = 32
    s = ((np.arange(panels)[:, None] + (xg[None, :] + 1.0) / 2.0) / panels).ravel()  # nodes on [0, 1]
    w = np.tile(wg / (2.0 * panels), panels)
    theta, phi = (float(v) for v in result.waypoints[0])
    errors = []
    for seg in result.segments:
        T = seg.t1 - seg.t0
        basis = result.basis_for(seg)
        c = np.asarray(seg.basis_coefficients[0], dtype=float)
        total = T * float(w @ (1.0 / robot.h(phi + T * (basis.integral(s) @ c))))
        phi_end = phi + T * float(basis.integral([1.0])[0] @ c)
        theta = theta - (float(robot.F(phi_end)) - float(robot.F(phi))) + robot.P0 * total
        phi = phi_end
        errors.append(max(abs(theta - float(seg.target[0])), abs(phi - float(seg.target[1]))))
    return np.array(errors)
