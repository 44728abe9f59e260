"""The symbolic construction of Chapter 4 (sympy): the time-extended system, the nilpotent model,
the feedback transformation and its fields (package docstring)."""

from __future__ import annotations

import dataclasses
import functools

import sympy as sp

from ..model import Acrobot


# ================================================================================ symbolic construction
@dataclasses.dataclass(frozen=True)
class Construction:
    """The Chapter 4 objects, symbolic, for a general acrobot (parameters as symbols).

    Coordinates are the text's ``(phi, t, theta)``; ``x = (x1, x2, x3)`` are the model's.
    """

    phi: sp.Symbol
    t: sp.Symbol
    theta: sp.Symbol
    params: tuple
    Y1: sp.Matrix
    Y2: sp.Matrix
    x: tuple
    X1: sp.Matrix
    X2: sp.Matrix
    alpha: sp.Expr
    beta: sp.Expr
    Yp1: sp.Matrix
    Yp2: sp.Matrix
    u1: sp.Expr
    u2: sp.Expr
    v: tuple
    kappa: sp.Expr
    a: sp.Expr
    b: sp.Expr
    c: sp.Expr


@functools.cache
def construction() -> Construction:
    """Derive the whole construction with sympy (cached)."""
    (theta, phi), params = Acrobot.example().symbols()
    M1, A1, M2, A2, P0 = params
    t = sp.Symbol("t", real=True)
    f, G = Acrobot.example().symbolic()
    # 1. time-extended driftless system in (phi, t, theta): d/deps = Y1 u1 + Y2 u2
    Y1 = sp.Matrix([f[1], 1, f[0]])
    Y2 = sp.Matrix([G[1], 0, G[0]])
    coords = (phi, t, theta)
    # 2. the model: Taylor in x1 = phi to second order
    x = sp.symbols("x1 x2 x3", real=True)
    sub = {phi: x[0], t: x[1], theta: x[2]}

    def taylor(e):
        return sp.expand(sp.series(e.subs(sub), x[0], 0, 3).removeO())

    X1 = Y1.applyfunc(taylor)
    X2 = Y2.applyfunc(taylor)
    # 3. feedback Y'1 = alpha Y1, Y'2 = Y2 + t beta Y1 with alpha, beta functions of phi
    al = sp.Function("alpha")(phi)
    be = sp.Function("beta")(phi)
    from ....core.lie import bracket

    br = bracket(al * Y1, Y2 + t * be * Y1, coords)
    beta = sp.solve(sp.Eq(br[1], 0), be)[0]  # no d/dt part
    model = bracket(X1, X2, x)[2].subs(x[0], phi)  # the model's [X1, X2], a d/dx3 field
    theta_part = sp.simplify(br[2].subs(be, beta).doit())
    alpha = sp.simplify(sp.solve(sp.Eq(theta_part, model), al)[0])
    beta = sp.simplify(beta.subs(al, alpha).doit())
    Yp1 = sp.simplify(alpha * Y1)
    Yp2 = sp.simplify(Y2 + t * beta * Y1)
    v = sp.symbols("v1 v2", real=True)
    u1 = alpha * v[0] + t * beta * v[1]
    u2 = v[1]
    kappa = sp.simplify(P0 * A1 / (M1 + A1) ** 2)
    h = M1 + A1 * sp.cos(phi)
    k = M2 + A2 * sp.cos(phi)
    a = sp.simplify(alpha * P0 / h)
    b = -k / h
    c = sp.simplify(sp.diff(alpha, phi) * P0 / h)
    return Construction(phi, t, theta, params, Y1, Y2, x, X1, X2, alpha, beta, Yp1, Yp2, u1, u2, v, kappa, a, b, c)
