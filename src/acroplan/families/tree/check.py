"""What the independent checks of tree bodies share: a forward simulation of the state whose
derivative Pinocchio's centroidal map gives (the family writes that derivative), by scipy's DOP853,
never by the sympy fields the planner integrates."""

from __future__ import annotations

import numpy as np

from ...core.errors import InvalidInputError

__all__ = ["simulate_driven"]


def simulate_driven(fun, x0, t0: float, t1: float, *, rtol: float, atol: float, t_eval=None):
    """DOP853 on :math:`\\dot x = ` ``fun(tau, x)`` (``tau`` the time since ``t0``) from ``x0`` at
    ``t0`` to ``t1``, at least 16 steps.

    Returns
    -------
    scipy.integrate.OdeResult
        ``.t`` absolute times (``t_eval``, default ``t1`` only), ``.y`` shape (n, len(t)).
    """
    from scipy.integrate import solve_ivp

    t0, t1 = float(t0), float(t1)
    if not t1 > t0:
        raise InvalidInputError("t1", f"must be > t0, got t0 = {t0}, t1 = {t1}", "give an interval forward in time")
    T = t1 - t0
    te = None if t_eval is None else np.asarray(t_eval, dtype=float) - t0
    sol = solve_ivp(fun, (0.0, T), np.asarray(x0, dtype=float), method="DOP853", rtol=rtol, atol=atol,
                    max_step=T / 16, t_eval=te if te is not None else [T])
    if not sol.success:
        raise RuntimeError(f"the Pinocchio-driven simulation failed: {sol.message}")
    sol.t = sol.t + t0
    return sol
