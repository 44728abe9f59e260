"""Independent re-simulation with scipy's DOP853 (never the compiled integrator).

Used to check every planned result before it is reported (rtol = atol = 3e-14, at least 16 steps
per segment): it integrates the system's own right-hand side (``sympy.lambdify`` of the same
symbolic fields) with the input evaluated in plain Python from the segment's basis coefficients
(Clenshaw's recurrence for Legendre; not the compiled expression), so a wrong compiled field or
basis shows up as an endpoint error. :func:`flat_output_errors` checks acrobot plans with no ODE
integrator at all, to rounding level.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from .systems.base import ControlAffineSystem

__all__ = ["simulate_segment", "flat_output_errors", "RTOL", "ATOL"]

RTOL = 3e-14
ATOL = 3e-14


def simulate_segment(system: ControlAffineSystem, x0, t0: float, t1: float, power_coefficients,
                     t_eval=None, rtol: float = RTOL, atol: float = ATOL):
    """Integrate one segment with the input :math:`u_j(t) = \\sum_i p_{j,i}(t - t_0)^i`.

    Parameters
    ----------
    system : ControlAffineSystem
    x0 : array_like, shape (n,)
    t0, t1 : float
    power_coefficients : array_like, shape (m, k), or callable
        The input's power-basis coefficients in local time, or a function ``u(t)`` returning the
        inputs at absolute time ``t`` (shape ``(m,)`` or ``(m, 1)``), for example
        :meth:`SegmentResult.input`.
    t_eval : array_like, optional
        Times at which to report the state (default: only ``t1``).

    Returns
    -------
    scipy.integrate.OdeResult
        As from :func:`scipy.integrate.solve_ivp`; ``.y[:, -1]`` is the state at ``t1``.
    """
    if callable(power_coefficients):
        inputs = power_coefficients

        def fun(t, x):
            return system.rhs(x, np.asarray(inputs(t), dtype=float).reshape(-1))
    else:
        P = np.atleast_2d(np.asarray(power_coefficients, dtype=float))
        polys = [np.polynomial.Polynomial(row) for row in P]

        def fun(t, x):
            u = np.array([p(t - t0) for p in polys])
            return system.rhs(x, u)

    # max_step: an input that starts flat (u ~ 0, u' ~ 0) tempts DOP853 into a first step across the
    # whole motion whose error estimate is blind to it (measured: 2.6e-9 endpoint errors at
    # rtol 3e-14); 16 steps per segment at least keep its error control honest.
    return solve_ivp(fun, (t0, t1), np.asarray(x0, dtype=float), method="DOP853", rtol=rtol, atol=atol,
                     max_step=(t1 - t0) / 16, t_eval=t_eval if t_eval is not None else [t1])


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
