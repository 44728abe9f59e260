"""Independent re-simulation with scipy's DOP853 (never the compiled integrator).

Used to check every planned result before it is reported (rtol = atol = 3e-14, at least 16 steps
per segment): it integrates the system's own numpy
right-hand side (``sympy.lambdify`` of the same symbolic fields) with the input evaluated by numpy
(the result's own :meth:`~acroplan.result.SegmentResult.input`, or power-basis coefficients), so a
wrong compiled field or basis shows up as an endpoint error.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from .systems.base import ControlAffineSystem

__all__ = ["simulate_segment", "RTOL", "ATOL"]

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
        :meth:`SegmentResult.input` (numpy's Legendre evaluation, not the compiled one).
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
