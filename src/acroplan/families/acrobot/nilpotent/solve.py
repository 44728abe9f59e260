"""Solving the endpoint equations with time moving forward (:func:`solve_nilpotent`), the text's
failure mode (:func:`counterexample`), the independent re-simulation (:func:`resimulate`) and the
flat-output variant (:func:`solve_flat_y`)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.polynomial import polynomial as P
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize

from .equations import NilpotentProblem, _eq_jac, _phi_jac, _u1_jac, alpha_derivs, equations, u1_values
from .results import FlatYResult, NilpotentResult, SeriesResult


# ================================================================================ solving
def _grid(n=201):
    return np.linspace(0.0, 1.0, n)


class _AtLast:
    """:func:`u1_values` on one grid, kept for the last coefficients asked: SLSQP evaluates the
    constraints on :math:`u_1` and on :math:`\\varphi` at the same point, one after the other."""

    def __init__(self, prob, eps):
        self.prob, self.eps, self.key, self.value = prob, eps, None, None

    def __call__(self, m):
        key = np.asarray(m, dtype=float).tobytes()
        if key != self.key:
            self.key, self.value = key, u1_values(self.prob, m, self.eps)
        return self.value


def _phi_bound(prob, at, lim, cut=lambda z: z):
    """The constraint :math:`\\pi_{lim}^2 - \\varphi(\\varepsilon_j)^2 \\ge 0` with its exact Jacobian;
    ``cut`` takes the coefficients out of SLSQP's vector."""
    def jac(z):
        J = -2.0 * at(cut(z))[1][:, None] * _phi_jac(prob, cut(z), at.eps)
        return np.hstack([J, np.zeros((J.shape[0], z.size - J.shape[1]))])  # (zero for the margin, if any)

    return {"type": "ineq", "fun": lambda z: lim ** 2 - at(cut(z))[1] ** 2, "jac": jac}


def _start(prob):
    d = prob.degree
    m = np.zeros(2 * (d + 1))
    m[0] = prob.x2Q - prob.x2P
    m[d + 1] = prob.Q[0] - prob.P[0]
    return m


def solve_nilpotent(prob: NilpotentProblem, *, starts: int = 8, seed: int = 0, verify: bool = True) -> SeriesResult:
    """Solve the endpoint equations with :math:`u_1 > 0` on [0, 1] (and :math:`|\\varphi| < \\pi`).

    SLSQP maximises the margin :math:`s` subject to the three equations, :math:`u_1(\\varepsilon_j) \\ge s`
    on 201 points and :math:`|\\varphi(\\varepsilon_j)| \\le \\pi - 0.05`, from several deterministic
    starts. The margin is then re-measured on 100001 points, and the motion is mapped back to the
    acrobot's time and re-simulated independently.
    """
    eps = _grid()
    d = prob.degree
    nm = 2 * (d + 1)
    rng = np.random.default_rng(seed)
    best = None
    lim = math.pi - 0.05
    first = [_start(prob)]
    guess = _flat_start(prob)
    if guess is not None:
        first.insert(0, guess)
    for k in range(starts):
        m0 = first[k] if k < len(first) else _start(prob) + rng.standard_normal(nm) * (0.5 + k / 4)
        z0 = np.concatenate([m0, [float(np.min(u1_values(prob, m0, eps)[0]))]])
        at = _AtLast(prob, eps)
        cons = [
            {"type": "eq", "fun": lambda z: equations(prob, z[:-1]),
             "jac": lambda z: np.hstack([_eq_jac(prob, z[:-1]), np.zeros((3, 1))])},
            {"type": "ineq", "fun": lambda z: at(z[:-1])[0] - z[-1],
             "jac": lambda z: np.hstack([_u1_jac(prob, z[:-1], eps), -np.ones((eps.size, 1))])},
            _phi_bound(prob, at, lim, cut=lambda z: z[:-1]),
        ]
        scale = max(1.0, prob.Q[1] - prob.P[1])
        obj = lambda z: -z[-1] / scale + 1e-6 * float(z[:-1] @ z[:-1])  # noqa: E731
        jac = lambda z: np.concatenate([2e-6 * z[:-1], [-1.0 / scale]])  # noqa: E731
        try:
            res = minimize(obj, z0, jac=jac, constraints=cons, method="SLSQP",
                           options={"maxiter": 400, "ftol": 1e-13})
        except (ValueError, FloatingPointError):
            continue
        m = res.x[:-1]
        r = float(np.max(np.abs(equations(prob, m))))
        fine = np.linspace(0.0, 1.0, 100001)
        u1, x1 = u1_values(prob, m, fine)
        margin, phimax = float(np.min(u1)), float(np.max(np.abs(x1)))
        cand = (r <= 1e-9 and phimax < math.pi, margin, m, r, phimax)
        if best is None or (cand[0], cand[1]) > (best[0], best[1]):
            best = cand
        if cand[0] and margin > 0 and k >= len(first) - 1:
            break
    ok_eq, margin, m, r, phimax = best
    if not ok_eq:
        return SeriesResult(success=False, status="not_converged",
                            message=f"no start solved the endpoint equations (residual {r:.1e})", problem=prob, m=m,
                            residual=r, margin=margin, phi_max=phimax)
    if margin <= 0:
        return SeriesResult(success=False, status="infeasible",
                            message=f"no solution with u1 > 0 found for degree {d}: the best margin min u1 = "
                                    f"{margin:.4g} (time would run backwards); try a higher degree",
                            problem=prob, m=m, residual=r, margin=margin, phi_max=phimax)
    out = SeriesResult(success=True, status="success",
                       message=f"endpoint equations solved (residual {r:.1e}) with u1 > 0: margin {margin:.4g}",
                       problem=prob, m=m, residual=r, margin=margin, phi_max=phimax)
    if verify:
        err = resimulate(out)
        out = dataclasses.replace(out, verified_error=err)
        if not err <= 1e-8:
            out = dataclasses.replace(out, success=False, status="not_converged",
                                      message=out.message + f"; but the re-simulated acrobot misses Q by {err:.1e}")
        else:
            out = dataclasses.replace(out, message=out.message + f"; re-simulated acrobot reaches Q to {err:.1e}")
    return out


def _flat_start(prob: NilpotentProblem):
    """A start that already moves time forward: the flat-output motion, read in the nilpotent
    coordinates (eps = sigma) and fitted by polynomials of the chosen degree (least squares)."""
    flat = solve_flat_y(prob, verify=False)
    if not flat.success:
        return None
    sig = np.linspace(0.0, 1.0, 257)
    t, _, phi, _ = flat.curve(sig)
    x2 = (t - prob.P[1]) / alpha_derivs(prob.robot, phi)[0]
    d = prob.degree
    # v = d/deps of (x2, phi): fit the integrals with polynomials of degree d + 1 vanishing at 0
    A = np.vander(sig, d + 2, increasing=True)[:, 1:]
    c2 = np.linalg.lstsq(A, x2 - x2[0], rcond=None)[0]
    c1 = np.linalg.lstsq(A, phi - phi[0], rcond=None)[0]
    k = np.arange(1, d + 2)
    return np.concatenate([c2 * k, c1 * k])


def counterexample(prob: NilpotentProblem, start, depth: float = 1.0) -> SeriesResult:
    """The text's failure mode: a solution of the same equations along which :math:`u_1 < 0`.

    Starting from a valid solution ``start``, SLSQP finds the nearest coefficients (least squares)
    that still solve the endpoint equations but have :math:`u_1(\\varepsilon^*) = -` ``depth`` at one
    virtual time :math:`\\varepsilon^*` (0.5, else 0.3 or 0.7). The curve is orbit-equivalent (a curve
    of the time-extended system from P to Q) but not trajectory-equivalent: its clock runs backwards.
    """
    m0 = np.asarray(start, dtype=float)
    eps = _grid()
    best = None
    for e_star in (0.5, 0.3, 0.7):
        es = np.array([e_star])
        cons = [{"type": "eq", "fun": lambda m: equations(prob, m), "jac": lambda m: _eq_jac(prob, m)},
                {"type": "eq", "fun": lambda m: u1_values(prob, m, es)[0] + depth,
                 "jac": lambda m: _u1_jac(prob, m, es)},
                _phi_bound(prob, _AtLast(prob, eps), math.pi - 0.05)]
        res = minimize(lambda m: float((m - m0) @ (m - m0)), m0, jac=lambda m: 2 * (m - m0), constraints=cons,
                       method="SLSQP", options={"maxiter": 500, "ftol": 1e-15})
        m = res.x
        r = float(np.max(np.abs(equations(prob, m))))
        if r <= 1e-9 and (best is None or r < best[1]):
            best = (m, r)
            break
    if best is None:
        return SeriesResult(success=False, status="not_converged", message="no orbit-equivalent counterexample found",
                            problem=prob, m=m0, residual=float("nan"), margin=float("nan"), phi_max=float("nan"))
    m, r = best
    fine = np.linspace(0.0, 1.0, 100001)
    u1, x1 = u1_values(prob, m, fine)
    margin = float(np.min(u1))
    return SeriesResult(success=False, status="infeasible",
                        message=f"solves the endpoint equations (residual {r:.1e}) but min u1 = {margin:.4g}: time "
                                "runs backwards, so it is no motion of the acrobot",
                        problem=prob, m=m, residual=r, margin=margin, phi_max=float(np.max(np.abs(x1))))


def resimulate(res: NilpotentResult) -> float:
    """Re-simulate the acrobot in its own time with u(t) (scipy DOP853, rtol 1e-11); error at Q."""
    prob = res.problem
    r = prob.robot
    T0, T1 = prob.P[1], prob.Q[1]
    sol = solve_ivp(lambda t, x: r.rhs(x, [res.u_of_t(t)]), (T0, T1), [prob.P[2], prob.P[0]], method="DOP853",
                    rtol=1e-11, atol=1e-11, max_step=(T1 - T0) / 32)
    th, ph = sol.y[:, -1]
    return float(np.hypot(th - prob.Q[2], ph - prob.Q[0]))


# ================================================================================ flat-output variant
def solve_flat_y(prob: NilpotentProblem, verify: bool = True) -> FlatYResult:
    """The variant with the flat output :math:`y = \\theta + F(\\varphi)` as the independent variable.

    :math:`dt/dy = h(\\varphi)/P_0` keeps one sign, so time moves forward by construction. With
    :math:`\\sigma = (y - y_P)/(y_Q - y_P)` and :math:`\\varphi = \\varphi_P + (\\varphi_Q-\\varphi_P)\\sigma +
    a\\,\\sigma(1-\\sigma)`, the single equation :math:`\\int h(\\varphi)/P_0\\,dy = t_Q - t_P` is solved for
    :math:`a` by Brent's method. ``m`` holds the coefficients of :math:`\\varphi(\\sigma)`.
    """
    r = prob.robot
    yP = prob.P[2] + float(r.F(prob.P[0]))
    yQ = prob.Q[2] + float(r.F(prob.Q[0]))
    T = prob.Q[1] - prob.P[1]
    dy = yQ - yP
    base = np.array([prob.P[0], prob.Q[0] - prob.P[0]])
    xg, wg = np.polynomial.legendre.leggauss(200)
    sg, wsg = (xg + 1) / 2, wg / 2

    def coef(a):
        return P.polyadd(base, a * np.array([0.0, 1.0, -1.0]))

    def f(a):
        return dy / r.P0 * float(r.h(P.polyval(sg, coef(a))) @ wsg) - T

    amps = np.linspace(-3 * math.pi, 3 * math.pi, 241)
    vals = np.array([f(a) for a in amps])
    idx = np.nonzero(np.sign(vals[:-1]) * np.sign(vals[1:]) <= 0)[0]
    if dy * r.P0 <= 0 or idx.size == 0:
        return FlatYResult(success=False, status="infeasible",
                           message="the flat-output family cannot meet t_Q: y must move with the sign of P0 and "
                                   f"int h/P0 dy must equal {T:.6g}",
                           problem=prob, m=coef(0.0), residual=float("nan"), margin=float("nan"), phi_max=float("nan"))
    k = idx[np.argmin(np.abs(amps[idx]))]
    a = brentq(f, amps[k], amps[k + 1], xtol=1e-15, rtol=1e-15)
    m = coef(a)
    fine = np.linspace(0.0, 1.0, 100001)
    phis = P.polyval(fine, m)
    margin = float(np.min(dy / r.P0 * r.h(phis)))  # dt/dsigma
    out = FlatYResult(success=True, status="success",
                      message=f"flat output as the clock: dt/dsigma >= {margin:.4g} > 0 by construction",
                      problem=prob, m=m, residual=abs(f(a)), margin=margin, phi_max=float(np.max(np.abs(phis))))
    if verify:
        err = resimulate(out)
        out = dataclasses.replace(out, verified_error=err, success=err <= 1e-8,
                                  status="success" if err <= 1e-8 else "not_converged",
                                  message=out.message + f"; re-simulated acrobot reaches Q to {err:.1e}")
    return out
