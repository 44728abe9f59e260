"""Symbolic Lie algebra tools for control-affine systems (sympy).

Vector fields are ``sympy.Matrix`` columns in the coordinates ``x`` (a tuple of symbols). The Lie
bracket is

.. math::  [f, g] = \\frac{\\partial g}{\\partial x} f - \\frac{\\partial f}{\\partial x} g ,

the convention of Murray and Sastry, under which the acrobot's time-extended fields give the
brackets of erratum 4 (docs/chapter4.md).

* :func:`bracket`, :func:`derived_distributions` and :func:`growth_vector`, :func:`larc`;
* :func:`hall_basis` (the P. Hall basis as words, nested tuples of generator indices) and
  :func:`evaluate` (a word as a vector field);
* :func:`is_nilpotent` (every Hall bracket of the given orders vanishes identically);
* :func:`exterior_derivative_1form`, :func:`is_exact`, :func:`frobenius` for one-forms.
"""

from __future__ import annotations

import functools
import itertools
from typing import Sequence

import sympy as sp

__all__ = ["bracket", "evaluate", "hall_basis", "hall_count", "derived_distributions", "growth_vector", "larc",
           "is_nilpotent", "is_exact", "frobenius"]


def _col(f) -> sp.Matrix:
    return sp.Matrix(f).reshape(len(f), 1)


def bracket(f, g, x: Sequence[sp.Symbol]) -> sp.Matrix:
    """:math:`[f, g] = Dg\\,f - Df\\,g`, simplified: expanded when every entry is a polynomial
    in ``x`` (the canonical form; ``simplify`` takes seconds on such fields for the same zeros),
    by ``sympy.simplify`` otherwise."""
    f, g = _col(f), _col(g)
    X = sp.Matrix(x)
    out = g.jacobian(X) * f - f.jacobian(X) * g
    if all(e.is_polynomial(*x) for e in out):
        return out.applyfunc(sp.expand)
    return sp.simplify(out)


# ------------------------------------------------------------------------------ P. Hall basis
def _length(w) -> int:
    return 1 if isinstance(w, int) else _length(w[0]) + _length(w[1])


@functools.lru_cache(maxsize=None)
def hall_basis(generators: int, order: int) -> tuple:
    """The P. Hall basis of the free Lie algebra on ``generators`` letters, up to ``order``.

    Words are generator indices ``0, 1, ...`` or pairs ``(u, v)`` meaning :math:`[u, v]`. The
    basis (Murray and Sastry's definition) is ordered, by length first, and built so:

    1. the generators are in the basis, :math:`g_0 < g_1 < \\dots`;
    2. :math:`[B_i, B_j]` is in the basis when :math:`B_i, B_j` are, :math:`B_i < B_j`, and either
       :math:`B_j` is a generator or :math:`B_j = [B_l, B_r]` with :math:`B_l \\le B_i`.

    The number of elements of length :math:`r` is Witt's :math:`\\frac1r\\sum_{d|r}\\mu(d)k^{r/d}`.
    """
    basis = list(range(generators))
    index = {w: i for i, w in enumerate(basis)}
    for r in range(2, order + 1):
        new = []
        for bi, bj in itertools.product(basis, basis):
            if _length(bi) + _length(bj) != r or not index[bi] < index[bj]:
                continue
            if isinstance(bj, int) or index[bj[0]] <= index[bi]:
                new.append((bi, bj))
        for w in new:
            index[w] = len(basis)
            basis.append(w)
    return tuple(basis)


def hall_count(generators: int, r: int) -> int:
    """Witt's formula for the number of basis elements of length ``r``."""
    return sum(sp.mobius(d) * generators ** (r // d) for d in sp.divisors(r)) // r


def evaluate(word, fields: Sequence, x: Sequence[sp.Symbol], _cache=None) -> sp.Matrix:
    """The vector field of a Hall word (generator ``i`` is ``fields[i]``)."""
    cache = {} if _cache is None else _cache
    if word in cache:
        return cache[word]
    if isinstance(word, int):
        out = _col(fields[word])
    else:
        out = bracket(evaluate(word[0], fields, x, cache), evaluate(word[1], fields, x, cache), x)
    cache[word] = out
    return out


# ------------------------------------------------------------------------------ distributions
def derived_distributions(fields: Sequence, x: Sequence[sp.Symbol], point: dict, depth: int) -> list[int]:
    """Dimensions of :math:`D^0 \\subset D^1 \\subset \\dots \\subset D^{depth}` at ``point``.

    :math:`D^0 = \\mathrm{span}\\{f_i\\}`, :math:`D^{i+1} = D^i + [D^0, D^i]`, spanned by the Hall
    words of length at most :math:`i + 1`, evaluated at ``point`` (a dict symbol -> value).
    """
    words = hall_basis(len(fields), depth + 1)
    cache: dict = {}
    dims = []
    for level in range(depth + 1):
        cols = [evaluate(w, fields, x, cache).subs(point) for w in words if _length(w) <= level + 1]
        M = sp.Matrix.hstack(*cols)
        dims.append(int(M.rank(simplify=True)))
    return dims


def growth_vector(fields: Sequence, x: Sequence[sp.Symbol], point: dict, max_depth: int = 6) -> tuple[int, ...]:
    """The growth vector :math:`(\\dim D^0, \\dim D^1, \\dots)` at ``point``, until it stops growing."""
    dims = []
    for depth in range(max_depth + 1):
        dims = derived_distributions(fields, x, point, depth)
        if len(dims) >= 2 and dims[-1] == dims[-2]:
            return tuple(dims[:-1])
        if dims[-1] == len(x):
            return tuple(dims)
    return tuple(dims)


def larc(fields: Sequence, x: Sequence[sp.Symbol], point: dict, max_depth: int = 6) -> bool:
    """The Lie algebra rank condition at ``point``: the brackets span the tangent space."""
    return growth_vector(fields, x, point, max_depth)[-1] == len(x)


def is_nilpotent(fields: Sequence, x: Sequence[sp.Symbol], step: int, check_to: int | None = None) -> bool:
    """Whether every Hall bracket of length ``step + 1`` to ``check_to`` (default ``step + 2``)
    vanishes identically, i.e. the algebra is nilpotent of step at most ``step`` (as far as checked:
    brackets of length ``step + 1`` vanishing already implies all longer ones do)."""
    check_to = check_to or step + 2
    cache: dict = {}
    for w in hall_basis(len(fields), check_to):
        if _length(w) > step and any(sp.simplify(e) != 0 for e in evaluate(w, fields, x, cache)):
            return False
    return True


# ------------------------------------------------------------------------------ one-forms
def exterior_derivative_1form(omega: Sequence, x: Sequence[sp.Symbol]) -> sp.Matrix:
    """:math:`d\\omega` of :math:`\\omega = \\sum_i \\omega_i dx_i` as the antisymmetric matrix
    :math:`(d\\omega)_{ij} = \\partial_i \\omega_j - \\partial_j \\omega_i`."""
    n = len(x)
    return sp.Matrix(n, n, lambda i, j: sp.simplify(sp.diff(omega[j], x[i]) - sp.diff(omega[i], x[j])))


def is_exact(omega: Sequence, x: Sequence[sp.Symbol]) -> bool:
    """Whether :math:`d\\omega = 0` (closed; exact on a simply connected domain)."""
    return exterior_derivative_1form(omega, x).is_zero_matrix


def frobenius(omega: Sequence, x: Sequence[sp.Symbol]) -> sp.Expr:
    """:math:`\\omega \\wedge d\\omega` in three dimensions (its single component); zero iff the
    constraint :math:`\\omega = 0` is integrable (holonomic)."""
    if len(x) != 3:
        raise ValueError("frobenius: needs three coordinates")
    d = exterior_derivative_1form(omega, x)
    # (w ^ dw)_{012} = w0 dw12 - w1 dw02 + w2 dw01
    return sp.simplify(omega[0] * d[1, 2] - omega[1] * d[0, 2] + omega[2] * d[0, 1])
