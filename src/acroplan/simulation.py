"""The front door for forward simulation: :func:`simulate`, the motion a given input produces.

The input is given per segment, as coefficients in an input basis (exact: the compiled integrator
integrates the same polynomial the planner would), or as a function of time, projected on the basis
(Gauss-Legendre least squares, its fit error reported). The result is a
:class:`~acroplan.core.result.PlanResult` like :func:`acroplan.plan`'s, whose waypoints are the
simulated states at the segment ends, so every output of a plan (``evaluate``, ``plot``,
``to_json``, the CLI's files) works the same way; with ``verify=True`` the motion is re-simulated by
the independent integrator and the largest disagreement reported.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .core import backend
from .core.basis import InputBasis, make_basis
from .core.errors import InvalidInputError
from .core.result import PlanResult, Status
from .core.strategies import make_segment
from .core.system import ControlAffineSystem
from .core.verify import check_name, resolve_verify, verify_plan
from .planning.request import checked_vector

__all__ = ["simulate"]


def _coefficients(system, times, inputs, basis, n_coefficients) -> list[tuple[InputBasis, np.ndarray]]:
    K, m = times.size - 1, system.n_inputs
    out = []
    if callable(inputs):
        b = make_basis(basis, n_coefficients)
        x, w = np.polynomial.legendre.leggauss(max(2 * b.n, 32))
        s = (x + 1.0) / 2.0
        V = b.matrix(s)
        for k in range(K):
            t = times[k] + s * (times[k + 1] - times[k])
            try:
                U = np.array([np.asarray(inputs(float(tk)), dtype=float).reshape(m) for tk in t]).T
            except (TypeError, ValueError) as e:
                raise InvalidInputError("inputs", f"the function must return {m} number(s) per time "
                                        f"({list(system.input_names)}): {e}", "return an array of shape (m,)") from None
            if not np.isfinite(U).all():
                raise InvalidInputError("inputs", "the function returned NaN or infinite values", "return finite inputs")
            sw = np.sqrt(w)[:, None]
            c = np.linalg.lstsq(V * sw, (U.T * sw), rcond=None)[0].T  # (m, n)
            out.append((b, c))
        return out
    try:
        segs = [np.asarray(c, dtype=float) for c in inputs]
    except (TypeError, ValueError):
        raise InvalidInputError("inputs", "must be one array of basis coefficients (m, n) per segment, or a "
                                "function u(t)", "give for example [[[0.0, 1.0, 0.0]]] for one segment") from None
    if len(segs) != K:
        raise InvalidInputError("inputs", f"has {len(segs)} segment(s) but times has {K}",
                                "give one coefficient array per segment")
    for k, c in enumerate(segs):
        if c.ndim == 1 and m == 1:
            c = c[None, :]
        if c.ndim != 2 or c.shape[0] != m or c.shape[1] < 1:
            raise InvalidInputError(f"inputs[{k}]", f"must have shape (m, n) = ({m}, n), got {c.shape}",
                                    f"give one row of coefficients per input {list(system.input_names)}")
        if not np.isfinite(c).all():
            raise InvalidInputError(f"inputs[{k}]", "contains NaN or infinite values", "give finite numbers")
        out.append((make_basis(basis, c.shape[1]), c))
    return out


def simulate(system: ControlAffineSystem, *, times, inputs, basis="legendre", n_coefficients: int = 14,
             verify: bool = True, **initial) -> PlanResult:
    """The motion of ``system`` under given inputs.

    Each segment's end state is the family's own endpoint map where it has one (spatial bodies),
    else heyoka's Taylor integrator of the state equation alone
    (:func:`acroplan.core.backend.state_endpoint`: no variational equations, so its first
    compilation is 5-15 times cheaper than a plan's).

    Parameters
    ----------
    system : ControlAffineSystem
    times : array_like, shape (K+1,)
        Segment boundaries, strictly increasing.
    inputs : sequence of K arrays, shape (m, n_k), or callable
        Per segment, the coefficients of each input in ``basis`` on
        :math:`s = (t - t_k)/(t_{k+1} - t_k) \\in [0, 1]` (as ``SegmentResult.basis_coefficients``);
        or a function ``u(t)`` returning shape ``(m,)``, projected on the basis with
        ``n_coefficients`` per segment.
    basis : {"legendre", "monomial"} or InputBasis
    n_coefficients : int
        Basis size for a function input.
    verify : bool or {"family", "ode"}
        Check the motion independently and report the largest disagreement (a disagreement above
        the allowance of :func:`~acroplan.core.verify.verify_plan` makes the status
        ``not_converged``): ``True`` is the family's own check where it has one (Pinocchio's
        centroidal momentum for bodies, the flat-output identity for the acrobot), else the scipy
        DOP853 re-simulation; ``"ode"`` always the re-simulation.
    **initial : float
        The initial state, one keyword per state (``theta=0.0, phi=-3.14``).

    Returns
    -------
    PlanResult
        Its waypoints are the simulated states at ``times``; ``conditions`` is ``"given"``.

    Examples
    --------
    >>> import numpy as np, acroplan
    >>> robot = acroplan.examples.robot("pike-dive")
    >>> res = acroplan.simulate(robot, times=[0, 1], inputs=[[[0.0, 1.0]]], theta=0.0, phi=-np.pi)
    >>> round(float(res.waypoints[-1, 1] + np.pi), 12)   # phi moved by the integral of u = 2s - 1
    0.0
    """
    if not isinstance(system, ControlAffineSystem):
        raise InvalidInputError("system", f"must be a ControlAffineSystem, got {type(system).__name__}",
                                "use for example acroplan.Acrobot(...)")
    unknown = sorted(set(initial) - set(system.state_names))
    if unknown:
        raise InvalidInputError(unknown[0], f"is not an option of simulate() nor a state of {type(system).__name__}",
                                f"states are {list(system.state_names)}")
    missing = [name for name in system.state_names if name not in initial]
    if missing:
        raise InvalidInputError(missing[0], "is missing", f"give the initial value of every state {list(system.state_names)}")
    x = np.array([checked_vector(name, [initial[name]], 1)[0] for name in system.state_names])
    t = checked_vector("times", times)
    if t.size < 2 or any(b <= a for a, b in zip(t.tolist(), t.tolist()[1:])):
        raise InvalidInputError("times", "must hold at least 2 strictly increasing values", "give for example [0, 1]")
    if isinstance(n_coefficients, bool) or not isinstance(n_coefficients, (int, np.integer)) or n_coefficients < 1:
        raise InvalidInputError("n_coefficients", f"must be a whole number >= 1, got {n_coefficients!r}",
                                "give for example 14")
    method = resolve_verify(system, verify)
    coefs = _coefficients(system, t, inputs, basis, int(n_coefficients))
    segments, states = [], [x]
    for k, (b, c) in enumerate(coefs):
        T = float(t[k + 1] - t[k])
        try:
            y = backend.state_endpoint(system, b, x, T, c)
        except backend.IntegrationError as e:
            raise InvalidInputError(f"inputs[{k}]", f"the motion leaves the numbers the integrator can carry ({e})",
                                    "give a smaller input or a shorter segment") from None
        seg = make_segment(system, b, x, y, T, c, t0=float(t[k]), final_error=0.0, message="simulated",
                           method="given")
        segments.append(dataclasses.replace(seg, index=k, interval=k))
        x = y
        states.append(x)
    X = np.array(states)
    common = dict(system=system, times=t, waypoints=X, conditions="given", basis=coefs[0][0])
    if method is None:
        return PlanResult(status=Status.SUCCESS, message=f"simulated: {len(segments)} segment(s) (not independently "
                          "verified)", segments=tuple(segments), verified=False, **common)
    checked, bad, allowed = verify_plan(system, X[0], segments, method)
    worst = max(s.verified_error for s in checked)
    check = check_name(system, method)
    if bad is not None:
        return PlanResult(status=Status.NOT_CONVERGED, message=f"not converged: the independent check ({check}) "
                          f"disagrees at t = {bad.t1:g} by {bad.verified_error:.2e} > {allowed:.2g}",
                          segments=checked, verified=True, verification=method, **common)
    return PlanResult(status=Status.SUCCESS, message=f"simulated: {len(segments)} segment(s), independently verified "
                      f"to {worst:.2e} ({check})", segments=checked, verified=True, verification=method, **common)
