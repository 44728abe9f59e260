"""First guesses for planar bodies that already meet the target: a joint motion plus a shape loop.

Planning a segment of a planar body means finding joint motions :math:`s(\\sigma)`,
:math:`\\sigma = t/T \\in [0, 1]`, with the given ends (and input conditions) whose turn

.. math::  \\Delta\\theta[s] = \\int_0^1 \\frac{T P_0 - a(s)\\cdot s'}{I(s)}\\,d\\sigma   \\qquad (1)

(:mod:`~acroplan.families.planar.connection`) equals :math:`\\theta_T - \\theta_0`. The joint ends
alone fix nothing of :math:`\\theta`: what turns the body is the *area* the shape path sweeps, by
Stokes' theorem (:math:`F_{ij}` the curvature of the connection :math:`\\mathcal{A} = a/I`)

.. math::  -\\oint_\\gamma \\mathcal{A}\\cdot ds = -\\iint_\\Omega F_{ij}\\,dq_i\\,dq_j ,   \\qquad (2)

and, with :math:`P_0 \\ne 0`, the drift :math:`T P_0 \\int d\\sigma / I(s)`. The guess:

1. **base motion** :math:`s_h(\\sigma)`: per joint the lowest-degree polynomial meeting the end
   values and the given input conditions (:math:`u = s'/T`, :math:`u' = s''/T^2` at the ends);
2. **a family of one parameter** :math:`s = s_h + \\lambda D(\\sigma)`, :math:`\\lambda \\ge 0`, with
   :math:`D` vanishing at the ends with every derivative the conditions fix
   (:math:`w = \\sigma^\\alpha (1 - \\sigma)^\\beta`, :math:`\\alpha, \\beta` one more than the
   conditions at each end):

   * a **shape loop** in the plane of joints :math:`(q_i, q_j)`:
     :math:`D = w\\,(d + \\kappa\\,(2\\sigma - 1)\\,d^\\perp)/w_{max}`, :math:`d = (\\cos\\phi, \\sin\\phi)`,
     :math:`\\kappa = \\pm 1`: a teardrop leaving the base motion towards :math:`d` and coming back,
     enclosing the signed area :math:`\\kappa\\lambda^2 \\int_0^1 w^2 d\\sigma / w_{max}^2` (so by (2) it
     turns the body by about :math:`-\\kappa\\lambda^2 F_{ij}\\int w^2/w_{max}^2`); its placement
     (the direction :math:`\\phi`, one of 8) and the pair are ranked by :math:`|F_{ij}|`
     (:func:`~acroplan.families.planar.connection.curvature`) at :math:`s_h(1/2) + 0.5\\,d`, and
     :math:`\\kappa` takes the sign (2) asks for, so loops stay small;
   * a **bump** of one joint, :math:`D = \\pm w\\,e_i/w_{max}`: no loop of its own, but with
     :math:`P_0 \\ne 0` it changes the drift, and it bends the base motion's own sweep;
   * a **tuck**, every joint at once along :math:`\\pm\\nabla I` at the middle shape (normalised to
     a largest component of 1): the motion that changes the drift :math:`T P_0\\int d\\sigma/I`
     most, as a diver tucks;

3. :math:`\\lambda` solves the scalar equation :math:`\\Delta\\theta[s_h + \\lambda D] = \\theta_T - \\theta_0`
   (1): a scan of :math:`\\lambda \\in (0, 3]` (the largest joint excursion, in radians) with a
   24-node Gauss-Legendre rule, then Brent's method on the first sign change with 64 nodes, as the
   acrobot's flat-output guess does. Among the families that bracket the target the one with the
   smallest motion :math:`\\int_0^1 |s'|^2 d\\sigma` that keeps the joint and rate limits wins.

The input :math:`u = s'/T` is a polynomial of degree :math:`\\alpha + \\beta` (loops) or
:math:`\\alpha + \\beta - 1` (bumps): it is evaluated at the nodes and projected on the basis (exact
when the basis has more coefficients than that degree). Path deformation then only polishes
(:func:`acroplan.core.continuation.solve_segment` with ``initial=``).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np
from scipy.optimize import brentq

from ...core.limits import Limits
from ..tree.loops import END_KEYS, GAUSS_S, GAUSS_W, base_motion, projector
from .connection import Connection, curvature

__all__ = ["ShapeGuess", "shape_guesses", "base_motion", "LAMBDA_MAX"]

_SG, _WSG = GAUSS_S, GAUSS_W
_XC, _WC = np.polynomial.legendre.leggauss(24)
_SC, _WSC = (_XC + 1) / 2, _WC / 2
#: the largest joint excursion a guess's loop or bump may add, in radians
LAMBDA_MAX = 3.0
_LAMS = np.linspace(0.0, LAMBDA_MAX, 31)[1:]
_PHIS = np.arange(8) * (np.pi / 4)
_KEYS = END_KEYS


@dataclasses.dataclass(frozen=True)
class ShapeGuess:
    """A start for path deformation (module docstring).

    Attributes
    ----------
    coefficients : numpy.ndarray, shape (m, n)
        The input in the basis it was made for.
    kind : str
        ``"base"``, ``"bump"``, ``"tuck"`` or ``"loop"``.
    joints : tuple of int
        The joint (bump) or the pair (loop), 0-based among the joints.
    amplitude : float
        :math:`\\lambda` (radians of the largest added excursion).
    predicted_error : float
        :math:`|\\Delta\\theta - (\\theta_T - \\theta_0)|` by the 64-node rule.
    energy : float
        :math:`\\int_0^1 |s'|^2 d\\sigma`.
    compliant : bool
        The joint limits hold at the 64 nodes, and the rate limits with a margin of 1%.
    curvature : float
        :math:`F_{ij}` at the loop's placement (loops only; ``nan`` otherwise).
    """

    coefficients: np.ndarray
    kind: str
    joints: tuple
    amplitude: float
    predicted_error: float
    energy: float
    compliant: bool
    curvature: float = float("nan")

    def describe(self) -> str:
        if self.kind == "loop":
            return (f"shape loop in joints {self.joints} (amplitude {self.amplitude:.3g} rad, curvature "
                    f"{self.curvature:.3g})")
        if self.kind == "tuck":
            return f"tuck along the gradient of the locked inertia (amplitude {self.amplitude:.3g} rad)"
        if self.kind == "bump":
            return f"bump of joint {self.joints[0]} (amplitude {self.amplitude:.3g} rad)"
        return "base motion"


@functools.lru_cache(maxsize=32)
def _weight(alpha: int, beta: int):
    """:math:`w/w_{max}` and its derivative at the 64 and the 24 nodes, and :math:`\\int w^2/w_{max}^2`."""
    sm = alpha / (alpha + beta)
    wmax = sm**alpha * (1 - sm) ** beta
    out = []
    for s in (_SG, _SC):
        w = s**alpha * (1 - s) ** beta / wmax
        dw = (alpha * s ** (alpha - 1) * (1 - s) ** beta - beta * s**alpha * (1 - s) ** (beta - 1)) / wmax
        w.flags.writeable = False
        dw.flags.writeable = False
        out += [w, dw]
    return tuple(out) + (float(_WSG @ (out[0] ** 2)),)


_projector = projector


def _directions(m: int, pair, phi: float, kappa: float, w, dw, s):
    """D and D' (shape (m, N)) of a loop (``pair``) or a bump (``pair`` of length 1, ``kappa`` its sign)."""
    D = np.zeros((m, s.size))
    dD = np.zeros((m, s.size))
    if kappa == 0.0:  # a direction in shape space (the tuck)
        v = np.asarray(pair, dtype=float)
        return v[:, None] * w[None, :], v[:, None] * dw[None, :]
    if len(pair) == 1:
        D[pair[0]] = kappa * w
        dD[pair[0]] = kappa * dw
        return D, dD
    i, j = pair
    x = 2 * s - 1
    d = np.array([math.cos(phi), math.sin(phi)])
    dp = np.array([-d[1], d[0]])
    for k, idx in enumerate((i, j)):
        D[idx] = w * (d[k] + kappa * x * dp[k])
        dD[idx] = dw * (d[k] + kappa * x * dp[k]) + w * 2 * kappa * dp[k]
    return D, dD


def _turn(conn: Connection, T: float, S, dS, weights):
    """:math:`\\Delta\\theta` by (1) for shapes ``S``, rates ``dS`` of shape (m, ..., N) (nodes last)."""
    I, a = conn(S)  # noqa: E741
    return ((T * conn.P0 - np.sum(a * dS, axis=0)) / I) @ weights


def shape_guesses(body, basis, x0, x1, T: float, ends: dict | None = None, limits: Limits | None = None, *,
                  conn: Connection | None = None, loops: int = 4, everything: bool = False,
                  keep: int = 2) -> list[ShapeGuess]:
    """Guesses that meet the target, best first (module docstring).

    Parameters
    ----------
    body : PlanarBody
    basis : InputBasis
        The basis (family and size) the coefficients are made for.
    x0, x1 : array_like, shape (n,)
    T : float
    ends : dict, optional
        Input conditions (``u0``, ``du0``, ``uT``, ``duT``: arrays of shape (m,)).
    limits : Limits, optional
    conn : Connection, optional
        The body's :class:`Connection` (built when not given).
    loops : int
        How many loop placements to try, best curvature first (every bump is tried).
    everything : bool
        Try every placement of every pair (done anyway when none of the best ``loops`` brackets).
    keep : int
        How many of the families that bracket the target are solved accurately (the best by the
        coarse scan's motion at the bracket: compliant first, then smallest energy).

    Returns
    -------
    list of ShapeGuess
        Those whose equation (1) was solved (``predicted_error`` small), compliant ones first, then by
        energy; empty when nothing brackets the target (or the families do not fit in the basis).
    """
    ends = {k: v for k, v in (ends or {}).items() if k in _KEYS}
    conn = conn or Connection(body)
    m = conn.m
    n = basis.n
    x0 = np.asarray(x0, dtype=float)
    x1 = np.asarray(x1, dtype=float)
    target = float(x1[0] - x0[0])
    left = sum(k in ends for k in ("u0", "du0"))
    alpha, beta = 1 + left, 1 + len(ends) - left
    if n < alpha + beta - 1:
        return []
    qh = base_motion(x0[1:], x1[1:], T, ends)  # (m, deg + 1)
    dqh = qh[:, 1:] * np.arange(1, qh.shape[1])
    SH = [np.polynomial.polynomial.polyval(s, qh.T) for s in (_SG, _SC)]  # (m, N)
    dSH = [np.polynomial.polynomial.polyval(s, dqh.T) if dqh.size else np.zeros((m, s.size)) for s in (_SG, _SC)]
    wG, dwG, wC, dwC, _ = _weight(alpha, beta)

    lo, hi, U = body.joint_bounds(limits)
    f0 = float(_turn(conn, T, SH[0], dSH[0], _WSG)) - target
    cands, loop_c = _candidates(conn, qh, m, n, alpha, beta, f0, loops, everything)
    out = []
    if abs(f0) <= 1e-12 * (1 + abs(target)):
        out.append(_make(basis, T, SH[0], dSH[0], np.zeros((m, _SG.size)), np.zeros((m, _SG.size)), 0.0, f0,
                         "base", (), float("nan"), lo, hi, U, x0[1:]))
    if not cands:
        return out
    ranked, Dc, lams = _coarse_brackets(conn, T, SH, dSH, cands, target, wC, dwC, lo, hi, U, m)
    if not ranked and not everything and len(loop_c) < 32 * m * (m - 1) // 2 and n >= alpha + beta + 1:
        # nothing brackets among the best placements: try every placement and orientation
        return out + shape_guesses(body, basis, x0, x1, T, ends, limits, conn=conn, everything=True, keep=keep)
    ranked.sort()
    for _, _, k, i0 in ranked[:keep]:
        guess = _solved(conn, basis, T, SH, dSH, cands[k], lams[i0], lams[i0 + 1], target, wG, dwG, lo, hi, U, x0, m)
        if guess is not None:
            out.append(guess)
    out.sort(key=lambda gs: (not gs.compliant, gs.energy))
    return out


def _candidates(conn, qh, m, n, alpha, beta, f0, loops, everything):
    """The families to try, ``(pair, phi, kappa, F)``: bumps of each joint and the tuck (when the
    basis holds them), then loops in each pair of joints, the strongest curvature first."""
    cands = []
    if n >= alpha + beta:
        cands += [((i,), 0.0, sgn, float("nan")) for i in range(m) for sgn in (1.0, -1.0)]
        if m >= 2:  # the tuck: every joint along the gradient of the locked inertia (changes the drift most)
            mid = np.polynomial.polynomial.polyval(0.5, qh.T)
            E = 1e-5 * np.eye(m)
            grad = (conn(mid[:, None] + E)[0] - conn(mid[:, None] - E)[0]) / 2e-5
            if np.max(np.abs(grad)) > 0:
                gdir = grad / np.max(np.abs(grad))
                cands += [(tuple(gdir * sgn), 0.0, 0.0, float("nan")) for sgn in (1.0, -1.0)]
    loop_c = []
    if n >= alpha + beta + 1 and m >= 2:
        mid = np.polynomial.polynomial.polyval(0.5, qh.T)
        for i in range(m):
            for j in range(i + 1, m):
                pts = np.repeat(mid[:, None], _PHIS.size, axis=1)
                pts[i] += 0.5 * np.cos(_PHIS)
                pts[j] += 0.5 * np.sin(_PHIS)
                F = curvature(conn, pts, i, j)
                for phi, Fk in zip(_PHIS, F):
                    # (2): a loop of signed area kappa * A turns by about -kappa * A * F; ask for -f0
                    kappa = 1.0 if Fk * f0 > 0 else -1.0
                    loop_c.append((abs(Fk), (i, j), float(phi), kappa, float(Fk)))
                    if everything:
                        loop_c.append((abs(Fk), (i, j), float(phi), -kappa, float(Fk)))
        loop_c.sort(key=lambda c: -c[0])
        if not everything:
            loop_c = loop_c[:loops]
        cands += [(c[1], c[2], c[3], c[4]) for c in loop_c]
    return cands, loop_c


def _coarse_brackets(conn, T, SH, dSH, cands, target, wC, dwC, lo, hi, U, m):
    """Every candidate's amplitude scanned at once on the coarse rule: per candidate its first
    bracket of the target and its motion there (interpolated; energy and limits on the coarse
    nodes), so that only the best few are solved accurately. Returns (ranked, directions, amplitudes)."""
    Dc = np.array([_directions(m, c[0], c[1], c[2], wC, dwC, _SC) for c in cands])  # (K, 2, m, N)
    S = SH[1][None, :, None, :] + _LAMS[None, None, :, None] * Dc[:, 0, :, None, :]  # (K, m, L, N)
    dS = dSH[1][None, :, None, :] + _LAMS[None, None, :, None] * Dc[:, 1, :, None, :]
    vals = _turn(conn, T, np.moveaxis(S, 1, 0), np.moveaxis(dS, 1, 0), _WSC) - target  # (K, L)
    fc0 = float(_turn(conn, T, SH[1], dSH[1], _WSC)) - target
    vals = np.concatenate([np.full((len(cands), 1), fc0), vals], axis=1)
    lams = np.concatenate([[0.0], _LAMS])
    ranked = []
    for k in range(len(cands)):
        row = vals[k]
        idx = np.flatnonzero(np.sign(row[:-1]) * np.sign(row[1:]) <= 0)
        if not idx.size:
            continue
        i0 = idx[0]
        f_a, f_b = row[i0], row[i0 + 1]
        lam = lams[i0] + (lams[i0 + 1] - lams[i0]) * (f_a / (f_a - f_b) if f_a != f_b else 0.5)
        Sx = SH[1] + lam * Dc[k, 0]
        dSx = dSH[1] + lam * Dc[k, 1]
        ok = bool(np.all(Sx.min(axis=1) >= lo) and np.all(Sx.max(axis=1) <= hi)
                  and np.all(np.abs(dSx).max(axis=1) <= 0.99 * U * T))
        ranked.append((not ok, float(np.sum((dSx**2) @ _WSC)), k, i0))
    return ranked, Dc, lams


def _solved(conn, basis, T, SH, dSH, c, a, b, target, wG, dwG, lo, hi, U, x0, m):
    """The candidate ``c``'s amplitude that meets the target on the fine rule (bracketed in
    ``[a, b]``), as a guess; ``None`` when the rules disagree even on a wider bracket."""
    D, dD = _directions(m, c[0], c[1], c[2], wG, dwG, _SG)

    def g(lam, D=D, dD=dD):
        return float(_turn(conn, T, SH[0] + lam * D, dSH[0] + lam * dD, _WSG)) - target

    ga, gb = g(a), g(b)
    if ga * gb > 0:  # the rules disagree on this bracket (a large motion): look one step wider
        a, b = max(0.0, a - (b - a)), min(LAMBDA_MAX, b + (b - a))
        ga, gb = g(a), g(b)
        if ga * gb > 0:
            return None
    lam = a if ga == 0 else b if gb == 0 else brentq(g, a, b, xtol=1e-15, rtol=1e-15, maxiter=100)
    kind = "tuck" if c[2] == 0.0 else "bump" if len(c[0]) == 1 else "loop"
    return _make(basis, T, SH[0], dSH[0], D, dD, lam, g(lam), kind, () if kind == "tuck" else c[0], c[3],
                 lo, hi, U, x0[1:])


def _make(basis, T, SH, dSH, D, dD, lam, err, kind, joints, F, lo, hi, U, q0) -> ShapeGuess:
    S = SH + lam * D
    dS = dSH + lam * dD
    u = dS / T  # (m, 64)
    c = u @ _projector(type(basis), basis.n).T
    energy = float(np.sum((dS**2) @ _WSG))
    ok = bool(np.all(S.min(axis=1) >= lo) and np.all(S.max(axis=1) <= hi)
              and np.all(np.abs(u).max(axis=1) <= 0.99 * U))
    return ShapeGuess(coefficients=c, kind=kind, joints=tuple(joints), amplitude=float(lam),
                      predicted_error=abs(float(err)), energy=energy, compliant=ok, curvature=float(F))
