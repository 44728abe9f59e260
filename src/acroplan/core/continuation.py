"""Path deformation (text Chapter 3): continuation on the endpoint map of one segment.

We solve :math:`\\Phi(c) = x_1` for the input coefficients :math:`c \\in \\mathbb{R}^N` subject to
linear input conditions :math:`B c = d` (values and slopes of the input at the segment ends).
Writing :math:`c = c_p + Z z` with :math:`c_p = B^+ d` and :math:`Z` an orthonormal basis of
:math:`\\ker B`, the unknown is :math:`z`.

Starting from a non-singular :math:`z_0` with :math:`y_0 = \\Phi(c(z_0))`, the target path
:math:`\\pi(\\tau)` from :math:`y_0` to :math:`x_1` is the system's
(:meth:`ControlAffineSystem.continuation_path`: a straight segment by default, one that stays inside
the exact reachable set for the acrobot), and we pull it back
(text eq. 1-3) by a predictor-corrector:

* the step :math:`\\tau \\to \\tau + \\Delta\\tau` is corrected by damped minimum-norm Newton updates
  :math:`\\Delta z = (JZ)^+_\\lambda\\,(\\pi(\\tau+\\Delta\\tau) - \\Phi)` with backtracking
  (the first correction is the Euler predictor of text eq. 3);
* :math:`\\Delta\\tau` doubles after an easy step and is quartered after a failed one;
* the smallest singular value of :math:`JZ` is recorded at every accepted step;
* a stall (:math:`\\Delta\\tau` below ``min_step`` or the evaluation budget spent) restarts from
  another non-singular start, and after the last start is reported as ``not_converged`` with the
  diagnostics, never as a silent wrong answer.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from . import backend
from .basis import InputBasis
from .progress import note
from .linalg import damped_step as _damped_step
from .linalg import norm as _norm
from .linalg import null_space as _null_space
from .system import ControlAffineSystem

__all__ = ["SegmentSolve", "solve_segment"]


@dataclasses.dataclass(frozen=True)
class SegmentSolve:
    """Outcome of :func:`solve_segment`.

    Attributes
    ----------
    success : bool
    message : str
    coefficients : numpy.ndarray, shape (m, n)
        Coefficients in the basis (the last iterate when not successful).
    final_error : float
        :math:`\\|\\Phi(c) - x_1\\|_2` from the compiled integrator.
    iterations : int
        Newton corrections, all restarts included.
    evaluations : int
        Endpoint-and-Jacobian evaluations.
    sigma_min : float
        Smallest singular value of the reduced Jacobian :math:`JZ` met on accepted steps.
    tau_reached : float
        How far along the path the last attempt got (1.0 on success).
    history : tuple of (tau, residual, sigma_min, goal, reached)
        One entry per accepted continuation step: the path parameter, the residual to the path
        point, the smallest singular value, the path point :math:`\\pi(\\tau)` and the endpoint
        reached (arrays of shape (n,)).
    restarts : int
    method : str
        ``"deform"`` (path deformation) or ``"deform+limits"`` (the constrained solve).
    """

    success: bool
    message: str
    coefficients: np.ndarray
    final_error: float
    iterations: int = 0
    evaluations: int = 0
    sigma_min: float = 0.0
    tau_reached: float = 0.0
    history: tuple = ()
    restarts: int = 0
    method: str = "deform"


class _Counter:
    def __init__(self):
        self.evaluations = 0
        self.iterations = 0


def solve_segment(system: ControlAffineSystem, basis: InputBasis, x0, x1, T: float, *,
                  B=None, d=None, tol: float = 1e-10, max_evaluations: int = 2000,
                  min_step: float = 1e-5, starts: int = 4, initial=None, initial_endpoint=None) -> SegmentSolve:
    """Steer ``x0`` to ``x1`` in time ``T`` by path deformation.

    Parameters
    ----------
    system : ControlAffineSystem
    basis : InputBasis
        ``basis.n`` coefficients per input.
    x0, x1 : array_like, shape (n,)
    T : float
    B : array_like, shape (q, m * basis.n), optional
        Linear input conditions :math:`B c = d` (flattened ``c``).
    d : array_like, shape (q,), optional
    tol : float
        Required :math:`\\|\\Phi(c) - x_1\\|_2`.
    max_evaluations : int
        Budget of endpoint-and-Jacobian evaluations over all starts.
    min_step : float
        Smallest continuation step before a start is declared stalled.
    starts : int
        Non-singular starting points to try (the first is the minimum-norm input).
    initial : array_like, shape (m, basis.n), optional
        A starting input to use instead of the minimum-norm one (it is projected onto
        :math:`Bc = d`).
    initial_endpoint : tuple of numpy.ndarray, optional
        The endpoint map and its Jacobian (:func:`acroplan.core.backend.endpoint`) at ``initial``
        exactly, when the caller has them (a refinement's last evaluation): when ``initial``
        already meets the target (``tol / 1000``), the Newton polish ends there without evaluating
        it again. ``initial`` must then meet :math:`Bc = d` (to rounding), as a refinement within
        the conditions does.

    Returns
    -------
    SegmentSolve
    """
    p = _Setup.of(system, basis, x0, x1, T, B, d)
    refused = p.refusal()
    if refused is not None:
        return refused
    if initial is None:
        z_base = np.zeros(p.n_z)
    else:
        z_base = np.asarray(initial, dtype=float).reshape(-1)
        z_base = z_base.copy() if p.free else p.Z.T @ (z_base - p.c_p)
    first = None
    if initial is not None:
        # an initial input that (nearly) meets the target, as the flat-output guess does, needs
        # only Newton corrections: no path, no restarts
        first, polished = _polish(p, z_base, tol, max_evaluations, initial_endpoint)
        if polished is not None:
            return polished
    if p.Z is None:
        p.Z = np.eye(p.N)
    best, restarts = None, -1
    for z_start, y_start, A_start, s_start in _start_points(p, z_base, first, starts):
        restarts += 1
        path = system.continuation_path(y_start, p.x1, p.x0, T)
        out = _continue(p.evaluate, p.diff, p.counter, z_start, y_start, A_start, s_start, p.x1, path, tol, p.scale,
                        max_evaluations, min_step)
        if best is None or out["tau"] > best["tau"] or (out["success"] and not best["success"]):
            best = out
        if out["success"] or p.counter.evaluations >= max_evaluations or restarts + 1 >= starts:
            break
    return _outcome(p, best, restarts)


class _Setup:
    """One segment's problem in the reduced coefficients :math:`c = c_p + Z z` (the conditions
    :math:`Bc = d` eliminated), its endpoint map in ``z`` and its evaluation count."""

    @classmethod
    def of(cls, system, basis, x0, x1, T, B, d):
        self = cls()
        self.system, self.basis, self.T = system, basis, T
        self.x0, self.x1 = np.asarray(x0, dtype=float), np.asarray(x1, dtype=float)
        self.m, self.n = system.n_inputs, basis.n
        self.N = self.m * self.n
        self.B = np.zeros((0, self.N)) if B is None else np.atleast_2d(np.asarray(B, dtype=float))
        self.d = np.zeros(0) if d is None else np.asarray(d, dtype=float)
        self.free = self.B.shape[0] == 0  # no conditions: z is c itself (c_p = 0, Z = identity)
        self.c_p = np.zeros(self.N) if self.free else np.linalg.lstsq(self.B, self.d, rcond=None)[0]
        self.Z = None if self.free else _null_space(self.B, self.N)  # free: the identity, built if needed
        self.n_z = self.N if self.free else self.Z.shape[1]
        self.n_x = system.ndx  # endpoint equations: one per tangent direction of the state space
        self.counter = _Counter()
        self.scale = 1.0 + max(map(abs, self.x1.tolist()))
        self.diff = system.diff
        return self

    def evaluate(self, z):
        self.counter.evaluations += 1
        return self.reduced(*backend.endpoint(self.system, self.basis, self.x0, self.T, self.coefficients(z).ravel()))

    def reduced(self, y, J):
        """``(y, A)``: the endpoint ``y`` and its Jacobian ``J`` in the coefficients made one in ``z``
        (tangent rows)."""
        if self.free:
            return y, self.system.tangent_jacobian(y, J)
        return y, self.system.tangent_jacobian(y, J) @ self.Z

    def coefficients(self, z):
        return (z if self.free else self.c_p + self.Z @ z).reshape(self.m, self.n)

    def refusal(self) -> SegmentSolve | None:
        """A failed solve when the conditions cannot be met, or leave too few free coefficients."""
        B, d, n, n_x, n_z = self.B, self.d, self.n, self.n_x, self.n_z
        if B.shape[0] and np.linalg.norm(B @ self.c_p - d) > 1e-9 * (1.0 + np.linalg.norm(d)):
            return SegmentSolve(success=False, message=f"the {B.shape[0]} input conditions cannot all be met by {n} "
                                f"coefficient(s) per input; use more coefficients (at least {B.shape[0] + n_x})",
                                coefficients=self.c_p.reshape(self.m, n), final_error=float("nan"))
        if n_z < n_x:
            return SegmentSolve(success=False, message=f"the input conditions leave {n_z} free coefficient(s) for "
                                f"{n_x} endpoint equations; use more coefficients (at least {B.shape[0] + n_x})",
                                coefficients=self.c_p.reshape(self.m, n), final_error=float("nan"))
        return None


def _polish(p: _Setup, z_base, tol, max_evaluations, known=None):
    """Newton corrections from a good initial input: ``(first evaluation, the solve or None)``.

    ``known``: the endpoint and its Jacobian at the initial input, when given. They are the first
    evaluation when the input already meets the target to the last correction's own tolerance
    (``tol / 1000``, :func:`_correct`) and the Jacobian is non-singular, so that the polish ends
    there with no correction. Otherwise the input is evaluated at ``z_base`` as without them, so
    that what follows is the same to the last bit (``z_base`` stands for the input to rounding,
    and the corrections' path is sensitive to the last bits: benchmarks/RESULTS.md, 2026-12-07,
    twelfth session)."""
    s0 = None
    if known is not None:
        y, A = p.reduced(*known)
        s0 = np.linalg.svd(A, compute_uv=False)
        if not (s0[-1] > 1e-8 * s0[0] and _norm(p.diff(y, p.x1)) <= tol * 1e-3):
            s0 = None
    if s0 is None:
        try:
            y, A = p.evaluate(z_base)
        except backend.IntegrationError:
            return None, None
        s0 = np.linalg.svd(A, compute_uv=False)
    first = (y, A, s0)
    if not (s0[-1] > 1e-8 * s0[0] and _norm(p.diff(y, p.x1)) <= 1e-6 * p.scale):
        return first, None
    ok, z, y1, A1, _ = _correct(p.evaluate, p.diff, p.counter, z_base, y, A, p.x1, tol, max_evaluations, True)
    if not ok:
        return first, None
    err = _norm(p.diff(y1, p.x1))
    s1 = s0[-1] if A1 is A else float(np.linalg.svd(A1, compute_uv=False)[-1])
    history = ((0.0, 0.0, float(s0[-1]), y, y), (1.0, err, float(s1), p.x1.copy(), y1))
    return first, SegmentSolve(success=True, message=f"converged: endpoint error {err:.2e} after "
                               f"{p.counter.evaluations} evaluations", coefficients=p.coefficients(z),
                               final_error=err, iterations=p.counter.iterations, evaluations=p.counter.evaluations,
                               sigma_min=min(float(s0[-1]), float(s1)), tau_reached=1.0, history=history)


def _start_points(p: _Setup, z_base, first, starts):
    """The minimum-norm (or initial) start if non-singular, then the best conditioned of random
    perturbations."""
    c_scale = 1.0 + float(np.linalg.norm(p.c_p)) + _norm(p.diff(p.x0, p.x1)) / max(p.T, 1e-12)
    rng = np.random.default_rng(20240601)  # fixed: the same problem gives the same answer
    tried = []
    for k in range(1 + 2 * starts):
        z = z_base if k == 0 else z_base + 0.3 * c_scale * rng.standard_normal(p.Z.shape[1]) / np.sqrt(p.Z.shape[1])
        if k == 0 and first is not None:
            (y, A, s) = first
        else:
            try:
                y, A = p.evaluate(z)
            except backend.IntegrationError:
                continue
            s = np.linalg.svd(A, compute_uv=False)
        ratio = s[-1] / (s[0] + 1e-300)
        if k == 0 and ratio > 1e-8:
            yield z, y, A, s[-1]
        else:
            tried.append((ratio, k, z, y, A, s[-1]))
    for _, _, z, y, A, smin in sorted(tried, key=lambda item: (-item[0], item[1])):
        yield z, y, A, smin


def _outcome(p: _Setup, best, restarts) -> SegmentSolve:
    m, n, counter = p.m, p.n, p.counter
    if best is None:
        return SegmentSolve(success=False, message="the integrator failed at every starting input",
                            coefficients=p.c_p.reshape(m, n), final_error=float("nan"), iterations=counter.iterations,
                            evaluations=counter.evaluations)
    c = (p.c_p + p.Z @ best["z"]).reshape(m, n)
    sig = min((h[2] for h in best["history"]), default=0.0)
    if best["success"]:
        msg = f"converged: endpoint error {best['error']:.2e} after {counter.evaluations} evaluations"
    else:
        msg = (f"continuation stalled at tau = {best['tau']:.4g} (endpoint error {best['error']:.2e}, smallest "
               f"singular value {sig:.2e}) after {counter.evaluations} evaluations and {restarts + 1} start(s): "
               f"{best['why']}; the basis of {n} coefficient(s) per input may be unable to reach the target, "
               f"try more coefficients")
    return SegmentSolve(success=best["success"], message=msg, coefficients=c, final_error=best["error"],
                        iterations=counter.iterations, evaluations=counter.evaluations, sigma_min=sig,
                        tau_reached=best["tau"], history=tuple(best["history"]), restarts=restarts)


def _continue(evaluate, diff, counter, z, y, A, sigma0, x1, path, tol, scale, max_evaluations, min_step):
    tau, dtau = 0.0, 1.0
    history = [(0.0, 0.0, float(sigma0), y.copy(), y.copy())]
    why = "evaluation budget spent"
    mid_tol = 1e-6 * scale
    while counter.evaluations < max_evaluations:
        tau_new = min(1.0, tau + dtau)
        goal = x1 if tau_new >= 1.0 else path(tau_new)
        last = tau_new >= 1.0
        ok, z_new, y_new, A_new, its = _correct(evaluate, diff, counter, z, y, A, goal, tol if last else mid_tol,
                                                max_evaluations, last)
        if ok:
            tau, z, y, A = tau_new, z_new, y_new, A_new
            note("path deformation", round(100 * tau), 100)  # (core.progress: nothing unless shown)
            history.append((tau, _norm(diff(y, goal)), float(np.linalg.svd(A, compute_uv=False)[-1]),
                            np.array(goal, dtype=float), y.copy()))
            if last:
                return dict(success=True, z=z, tau=1.0, error=_norm(diff(y, x1)), history=history, why="")
            if its <= 2:
                dtau = min(1.0, 2.0 * dtau)
        else:
            dtau /= 4.0
            if dtau < min_step:
                why = "the step in tau fell below min_step"
                break
    return dict(success=False, z=z, tau=tau, error=_norm(diff(y, x1)), history=history, why=why)


def _correct(evaluate, diff, counter, z, y, A, goal, tol, max_evaluations, last):
    """Damped Newton corrections towards ``goal``. Returns (ok, z, y, A, iterations).

    Intermediate steps stop at ``tol``; the last step polishes on to ``tol / 1000`` (or until the
    residual stops decreasing) and succeeds when it is within ``tol``.
    """
    target = tol * 1e-3 if last else tol
    max_its = 12 if last else 6
    r = diff(y, goal)
    res = _norm(r)
    for its in range(max_its):
        if res <= target:
            return True, z, y, A, its
        step, _ = _damped_step(A, r, 1e-13)
        alpha = 1.0
        accepted = False
        while alpha >= 1.0 / 64:
            counter.iterations += 1
            if counter.evaluations >= max_evaluations:
                return res <= tol and last, z, y, A, its
            try:
                y_t, A_t = evaluate(z + alpha * step)
            except backend.IntegrationError:
                alpha /= 4.0
                continue
            r_t = diff(y_t, goal)
            res_t = _norm(r_t)
            if res_t < (1.0 - 1e-4 * alpha) * res:
                accepted = True
                break
            alpha /= 4.0
        if not accepted:
            # no decrease: at the accuracy floor this is success, otherwise a failed step
            return res <= tol, z, y, A, its
        z, y, A, r, res = z + alpha * step, y_t, A_t, r_t, res_t
    return res <= tol, z, y, A, max_its
