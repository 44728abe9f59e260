"""Independent re-simulation with scipy's DOP853 (never the compiled integrator).

Used to check every planned result before it is reported (rtol = atol = 3e-14, at least 16 steps
per segment): it integrates the system's own right-hand side (``sympy.lambdify`` of the same
symbolic fields) with the input evaluated in plain Python from the segment's basis coefficients
(Clenshaw's recurrence for Legendre; not the compiled expression), so a wrong compiled field or
basis shows up as an endpoint error. Families may add exact checks of their own (the acrobot's
:func:`acroplan.families.acrobot.verify.flat_output_errors`, with no ODE integrator at all).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from . import budget
from .progress import note
from .system import ControlAffineSystem

__all__ = ["simulate_segment", "verify_plan", "resolve_verify", "check_name", "RTOL", "ATOL", "VERIFY_TOL", "VERIFY_RTOL", "VERIFY_METHODS"]

RTOL = 3e-14
ATOL = 3e-14
#: Largest endpoint error of the independent re-simulation that a successful plan may have ...
VERIFY_TOL = 1e-9
#: ... plus this much of the summed magnitudes of the states along the chain (:func:`verify_plan`).
VERIFY_RTOL = 2e-12


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
    T = float(t1) - float(t0)
    if callable(power_coefficients):
        inputs = power_coefficients

        def u_local(tau):
            return np.asarray(inputs(t0 + tau), dtype=float).reshape(-1)
    else:
        P = np.atleast_2d(np.asarray(power_coefficients, dtype=float))
        polys = [np.polynomial.Polynomial(row) for row in P]

        def u_local(tau):
            return np.array([p(tau) for p in polys])

    sol = _dop853(system, x0, T, u_local, None if t_eval is None else np.asarray(t_eval, dtype=float) - t0,
                  rtol, atol)
    sol.t = sol.t + t0
    return sol


def _dop853(system, x0, T: float, u_local, t_eval, rtol: float, atol: float):
    """DOP853 on ``[0, T]`` in local time (so absolute times of any size lose no digits), the input
    a function of local time; the plan's time budget is checked every 256 right-hand sides."""
    calls = [0]

    def fun(tau, x):
        calls[0] += 1
        if not calls[0] & 255:
            budget.check()
        return system.rhs(x, u_local(tau))

    # max_step: an input that starts flat (u ~ 0, u' ~ 0) tempts DOP853 into a first step across the
    # whole motion whose error estimate is blind to it (measured: 2.6e-9 endpoint errors at
    # rtol 3e-14); 16 steps per segment at least keep its error control honest.
    from scipy.integrate import solve_ivp  # here: scipy.integrate takes 0.5 s to import

    return solve_ivp(fun, (0.0, T), np.asarray(x0, dtype=float), method="DOP853", rtol=rtol, atol=atol,
                     max_step=T / 16, t_eval=t_eval if t_eval is not None else [T])


#: How plans are checked: ``"family"`` (the family's own independent check,
#: :meth:`ControlAffineSystem.family_errors`) or ``"ode"`` (the DOP853 re-simulation); ``True``
#: means the family's check when it has one.
VERIFY_METHODS = ("family", "ode")


def verify_plan(system: ControlAffineSystem, x0, segments, method: str = "ode"):
    """Check a plan's segments in a chain from ``x0`` (not segment by segment from each waypoint,
    so accumulated drift shows too) and record each segment's ``verified_error``: with
    ``method="ode"`` the DOP853 re-simulation's :math:`\\|\\mathrm{diff}(x(t_1), x_{target})\\|_2`,
    with ``method="family"`` the family's own check (:meth:`ControlAffineSystem.family_errors`).

    A segment may miss its target by :data:`VERIFY_TOL` plus :data:`VERIFY_RTOL` times the sum,
    over the chain up to it, of the largest magnitude of each segment's end states: DOP853 at
    rtol 3e-14 resolves a state to a few 1e-13 of its size per segment, and a chained
    re-simulation accumulates that (measured: a 200-waypoint pike chain with theta reaching 231
    missed by 2.4e-9 after 97 segments, where the exact flat-output identity agreed to 1e-11;
    ``tests/test_reliability.py``). For one segment with states of size 20 that is 1e-9 + 4e-11.

    Returns
    -------
    (segments, bad, allowed) : tuple of SegmentResult, the first segment whose error exceeds its
        allowance (``None`` when every segment is within it), and that allowance (the last one
        when none exceeds it)
    """
    checked, bad, allowed, scale = [], None, VERIFY_TOL, 0.0
    x = np.asarray(x0, dtype=float).copy()
    exact = system.family_errors(x, segments) if method == "family" else None
    if method == "family" and exact is None:
        raise ValueError(f"{type(system).__name__} has no check of its own; use the ODE re-simulation")
    for k, seg in enumerate(segments):
        if exact is not None:
            err = float(exact[k])
        else:
            T = seg.t1 - seg.t0
            sol = _dop853(system, x, T, lambda tau, seg=seg, T=T: seg._input_s(tau / T), None, RTOL, ATOL)
            if sol.success:
                x = sol.y[:, -1]
                err = system.error(x, seg.target)
            else:
                err = float("inf")
        seg = dataclasses.replace(seg, verified_error=err if np.isfinite(err) else float("inf"))
        checked.append(seg)
        note("independent check", k + 1, len(segments))  # (core.progress: nothing unless shown)
        scale += max(float(np.max(np.abs(seg.start))), float(np.max(np.abs(seg.target))), 1.0)
        if bad is None:
            allowed = VERIFY_TOL + VERIFY_RTOL * scale
            if not err <= allowed:
                bad = seg
    return tuple(checked), bad, allowed


def resolve_verify(system: ControlAffineSystem, verify) -> str | None:
    """The check ``verify`` asks for on ``system``: ``True`` is the family's own independent check
    when the family has one (:meth:`ControlAffineSystem.family_errors`: Pinocchio for bodies, the
    flat-output identity for the acrobot), else the DOP853 re-simulation; ``False`` is none.

    Returns
    -------
    {"family", "ode"} or None

    Raises
    ------
    InvalidInputError
        ``verify`` is not one of True, False, "family", "ode", or "family" for a system without a
        check of its own.
    """
    from .errors import InvalidInputError

    # the family's own check, when it has one and can run it here (a body's Pinocchio check without
    # Pinocchio installed is the DOP853 re-simulation, and is labelled so: "ode")
    has_own = type(system).family_errors is not ControlAffineSystem.family_errors and bool(system.family_check)
    if verify is True:
        return "family" if has_own else "ode"
    if verify is False:
        return None
    if not isinstance(verify, str) or verify not in VERIFY_METHODS:
        raise InvalidInputError("verify", f"must be True or False, or \"family\" or \"ode\", got {verify!r:.80}",
                                "give True (the family's own independent check), \"ode\" or False")
    if verify == "family" and not has_own and type(system).family_errors is not ControlAffineSystem.family_errors:
        return "ode"  # the family's check falls back on the re-simulation: say so
    if verify == "family" and not has_own:
        raise InvalidInputError("verify", f"\"family\" needs a check of the family's own, which "
                                f"{type(system).__name__} does not provide", "use True or \"ode\" (the DOP853 "
                                "re-simulation)")
    return verify


def check_name(system: ControlAffineSystem, method: str) -> str:
    """How a result message names the check ``method`` (:func:`resolve_verify`)."""
    return (system.family_check or "the family's own check") if method == "family" else "scipy DOP853 re-simulation"
