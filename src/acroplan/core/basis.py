"""Input bases: each input on a segment is a finite series in normalised time.

On a segment :math:`[t_0, t_1]` with :math:`T = t_1 - t_0` and :math:`s = (t - t_0)/T \\in [0, 1]`,
input :math:`j` is

.. math::  u_j(t) = \\sum_{i=0}^{n-1} c_{j,i}\\, b_i(s) .

Whatever basis is used inside, results are exported in the power basis of local time,
:math:`u_j(t) = \\sum_i p_{j,i} (t - t_0)^i` (:meth:`InputBasis.to_power`).

Two families:

* :class:`Monomial`: :math:`b_i(s) = s^i`, the text's :math:`t^i` (eq. 7) up to scaling;
* :class:`Legendre`: :math:`b_i(s) = P_i(2s - 1)`, orthogonal on the segment and better
  conditioned (measured in ``benchmarks/RESULTS.md``).
"""

from __future__ import annotations

import abc
import dataclasses
import functools
import math

import numpy as np
from numpy.polynomial import Legendre as _Leg
from numpy.polynomial import Polynomial as _Poly

from .errors import InvalidInputError

__all__ = ["InputBasis", "Monomial", "Legendre", "make_basis", "basis_tables", "check_points", "gauss_legendre"]


@dataclasses.dataclass(frozen=True)
class InputBasis(abc.ABC):
    """A family of ``n`` functions :math:`b_0, \\dots, b_{n-1}` on :math:`s \\in [0, 1]`."""

    n: int
    name = "abstract"

    def __post_init__(self):
        if not isinstance(self.n, (int, np.integer)) or isinstance(self.n, bool) or self.n < 1:
            raise InvalidInputError("n_coefficients", f"must be a whole number >= 1, got {self.n!r}",
                                    "give for example 6")
        object.__setattr__(self, "n", int(self.n))

    @abc.abstractmethod
    def power_matrix(self) -> np.ndarray:
        """``P`` with :math:`\\sum_i c_i b_i(s) = \\sum_k (P c)_k s^k`; shape ``(n, n)``."""

    @abc.abstractmethod
    def expression(self, s, c):
        """The series :math:`\\sum_i c_i b_i(s)` built from heyoka expressions ``s`` and ``c[i]``."""

    def to_power_s(self, c) -> np.ndarray:
        """Coefficients ``q`` with :math:`\\sum_i c_i b_i(s) = \\sum_i q_i s^i`; same shape as ``c``."""
        return np.asarray(c, dtype=float) @ self.power_matrix().T

    def from_power_s(self, q) -> np.ndarray:
        """Coefficients ``c`` with :math:`\\sum_i c_i b_i(s) = \\sum_i q_i s^i`; the inverse of
        :meth:`to_power_s` (last axis of length ``n``)."""
        return np.asarray(q, dtype=float) @ _inverse_power(type(self), self.n).T

    def matrix(self, s, derivative: int = 0) -> np.ndarray:
        """Values of :math:`d^k b_i / ds^k` at ``s``.

        Parameters
        ----------
        s : array_like, shape (N,)
        derivative : int

        Returns
        -------
        numpy.ndarray, shape (N, n)
        """
        s = np.atleast_1d(np.asarray(s, dtype=float))
        P = self.power_matrix()
        if derivative:
            P = _power_derivative(self.n, derivative) @ P
        return np.vander(s, self.n, increasing=True) @ P

    def integral(self, s) -> np.ndarray:
        """Values of :math:`\\int_0^s b_i(\\sigma)\\,d\\sigma`; shape ``(N, n)``."""
        s = np.atleast_1d(np.asarray(s, dtype=float))
        k = np.arange(1, self.n + 1)
        return (np.vander(s, self.n + 1, increasing=True)[:, 1:] / k) @ self.power_matrix()

    def at(self, s: float) -> tuple[np.ndarray, np.ndarray]:
        """``(matrix(s), integral(s))`` at one point ``s``, each shape ``(1, n)``: what an ODE
        right-hand side evaluates at each of its calls (the Pinocchio check), the same numbers."""
        return self.matrix(s), self.integral(s)

    def sup_bound(self, c) -> float | None:
        """An upper bound of :math:`\\max_{s \\in [0, 1]} |\\sum_i c_i b_i(s)|` without root finding,
        or ``None`` when the family knows none (this default). :class:`Monomial` and
        :class:`Legendre`: :math:`\\sum_i |c_i|`, since :math:`|s^i| \\le 1` and :math:`|P_i(x)| \\le 1`
        on their intervals.

        Parameters
        ----------
        c : array_like, shape (n,)
        """
        return None

    def gram(self) -> np.ndarray:
        """:math:`\\int_0^1 b_i b_k\\,ds`, shape ``(n, n)`` (Gauss-Legendre, exact)."""
        x, w = gauss_legendre(self.n + 1)
        V = self.matrix((x + 1) / 2)
        return (V * (w / 2)[:, None]).T @ V

    def to_power(self, c, T: float) -> np.ndarray:
        """Power-basis coefficients in local time :math:`\\tau = t - t_0` on a segment of length ``T``.

        Parameters
        ----------
        c : array_like, shape (n,) or (m, n)
        T : float

        Returns
        -------
        numpy.ndarray, same shape as ``c``: :math:`u(\\tau) = \\sum_i p_i \\tau^i`.
        """
        return self.to_power_s(c) / float(T) ** np.arange(self.n)


@functools.lru_cache(maxsize=64)
def gauss_legendre(n: int) -> tuple[np.ndarray, np.ndarray]:
    """``numpy.polynomial.legendre.leggauss(n)``, read-only and computed once per ``n``: the same
    numbers, without the eigenvalues of an n x n matrix at each call (1.0 ms for n = 64, which the
    composite rules built per panel count paid for every new count: 0.22 s of some 2 s for 2,000
    random two-link plans, ``benchmarks/RESULTS.md``, fifteenth session).

    Returns
    -------
    x, w : numpy.ndarray, shape (n,)
        Nodes on [-1, 1] and weights.
    """
    x, w = np.polynomial.legendre.leggauss(n)
    x.setflags(write=False)
    w.setflags(write=False)
    return x, w


@functools.cache
def _inverse_power(basis_cls, n: int) -> np.ndarray:
    Q = np.linalg.inv(basis_cls(n).power_matrix())
    Q.setflags(write=False)
    return Q


@functools.cache
def _power_derivative(n: int, k: int) -> np.ndarray:
    """Matrix of d^k/ds^k acting on power coefficients (n x n)."""
    D = np.zeros((n, n))
    for i in range(1, n):
        D[i - 1, i] = i
    return np.linalg.matrix_power(D, k)


@functools.cache
def _legendre_power(n: int) -> np.ndarray:
    P = np.zeros((n, n))
    for i in range(n):
        e = np.zeros(i + 1)
        e[i] = 1.0
        q = _Leg(e, domain=[0.0, 1.0]).convert(kind=_Poly, domain=[0.0, 1.0], window=[0.0, 1.0]).coef
        P[: q.size, i] = q
    P.setflags(write=False)
    return P


@functools.cache
def _legendre_derivative(n: int, k: int) -> np.ndarray:
    """Legendre coefficients of :math:`d^k b_i/ds^k` (column i), shape (n, n)."""
    D = np.zeros((n, n))
    for i in range(n):
        d = np.polynomial.legendre.legder(np.eye(n)[i], k, scl=2.0)
        D[: d.size, i] = d
    D.setflags(write=False)
    return D


@functools.cache
def _legendre_integral(n: int) -> np.ndarray:
    """Legendre coefficients of :math:`\\int_0^s b_i` (column i), shape (n+1, n)."""
    Q = np.zeros((n + 1, n))
    for i in range(n):
        q = np.polynomial.legendre.legint(np.eye(n)[i], lbnd=-1.0, scl=0.5)
        Q[: q.size, i] = q
    Q.setflags(write=False)
    return Q


def from_power(basis_cls, p, T: float) -> np.ndarray:
    """Coefficients in ``basis_cls`` (of size ``len(p)``) of :math:`\\sum_i p_i \\tau^i` on ``[0, T]``."""
    p = np.asarray(p, dtype=float)
    q = p * float(T) ** np.arange(p.size)  # power basis in s = tau / T
    return basis_cls(p.size).from_power_s(q)


@dataclasses.dataclass(frozen=True)
class Monomial(InputBasis):
    """:math:`b_i(s) = s^i` (the text's eq. 7). Built in Horner form for the integrator."""

    name = "monomial"

    def power_matrix(self):
        return np.eye(self.n)

    def sup_bound(self, c) -> float:
        return _abs_sum(c)  # |s^i| <= 1 on [0, 1]

    def expression(self, s, c):
        # Horner form: time**i gives non-finite Taylor coefficients at s = 0 (heyoka 7.13: err_nf_state).
        u = c[self.n - 1]
        for i in range(self.n - 2, -1, -1):
            u = c[i] + s * u
        return u


def _abs_sum(c) -> float:
    """:math:`\\sum_i |c_i|`, correctly rounded (``math.fsum`` on Python floats: a fifth of numpy's
    per-call time on a dozen coefficients, and checked after every plan)."""
    return math.fsum(map(abs, np.asarray(c, dtype=float).tolist()))


@dataclasses.dataclass(frozen=True)
class Legendre(InputBasis):
    """:math:`b_i(s) = P_i(2s - 1)`, Legendre polynomials shifted to the segment.

    Built for the integrator by Bonnet's recurrence
    :math:`(i+1) P_{i+1} = (2i+1)\\,x P_i - i P_{i-1}`, :math:`x = 2s - 1`.
    """

    name = "legendre"

    def power_matrix(self):
        return _legendre_power(self.n)

    def sup_bound(self, c) -> float:
        return _abs_sum(c)  # |P_i(x)| <= 1 on [-1, 1]

    # values, derivatives and integrals through Legendre series (three-term recurrence), never
    # through power series, which lose digits from about 10 coefficients on
    def matrix(self, s, derivative: int = 0) -> np.ndarray:
        s = np.atleast_1d(np.asarray(s, dtype=float))
        V = np.polynomial.legendre.legvander(2.0 * s - 1.0, self.n - 1)
        if derivative:
            return V @ _legendre_derivative(self.n, derivative)
        return V

    def integral(self, s) -> np.ndarray:
        s = np.atleast_1d(np.asarray(s, dtype=float))
        return np.polynomial.legendre.legvander(2.0 * s - 1.0, self.n) @ _legendre_integral(self.n)

    def at(self, s: float) -> tuple[np.ndarray, np.ndarray]:
        """``(matrix(s), integral(s))`` at one point, bit for bit: numpy's ``legvander`` recurrence,
        operation for operation, on Python floats (one pass for both: the values are the first
        ``n`` columns of the integral's degree-``n`` table), then the same matrix products; a
        tenth of the time of the two array calls at one point."""
        x = float(2.0 * s - 1.0) + 0.0
        v = [x * 0 + 1, x]
        for i in range(2, self.n + 1):
            v.append((v[i - 1] * x * (2 * i - 1) - v[i - 2] * (i - 1)) / i)
        V = np.array([v])
        return V[:, :self.n], V @ _legendre_integral(self.n)

    def expression(self, s, c):
        x = 2.0 * s - 1.0
        P = [1.0 + 0.0 * s, x]
        for i in range(1, self.n - 1):
            P.append(((2 * i + 1) * x * P[i] - i * P[i - 1]) / (i + 1))
        u = c[0]
        for i in range(1, self.n):
            u = u + c[i] * P[i]
        return u


_BASES = {"monomial": Monomial, "legendre": Legendre}


def make_basis(basis, n: int) -> InputBasis:
    """A basis from its name (``"monomial"``, ``"legendre"``) or an :class:`InputBasis` instance."""
    if isinstance(basis, InputBasis):
        return basis
    if not isinstance(basis, str) or basis not in _BASES:
        r = repr(basis)
        raise InvalidInputError("basis", f"unknown basis {r if len(r) <= 80 else r[:77] + '...'}",
                                f"use one of {sorted(_BASES)} or an InputBasis")
    return _BASES[basis](n)


def check_points(uniform: int, ends: int = 0) -> np.ndarray:
    """Sorted normalised times in [0, 1]: ``uniform`` uniform points and, with ``ends`` > 1, also
    ``ends`` Chebyshev-Lobatto points :math:`(1 - \\cos(\\pi k / (\\text{ends} - 1))) / 2`, which crowd
    towards the ends, where a polynomial input of :math:`n` coefficients has its narrowest features
    (its extrema about :math:`1/n^2` of the interval apart there). The points on which the limits
    of an optimum are imposed or checked (:func:`~acroplan.core.limits.linear_limits`,
    :func:`~acroplan.core.objectives.torque_check_grid`)."""
    s = np.linspace(0.0, 1.0, uniform)
    if ends > 1:
        s = np.union1d(s, 0.5 * (1.0 - np.cos(np.pi * np.arange(ends) / (ends - 1))))
        s[0], s[-1] = 0.0, 1.0
    return s


@functools.lru_cache(maxsize=64)
def _tables(basis, s_bytes: bytes):
    s = np.frombuffer(s_bytes)
    out = (basis.matrix(s), basis.matrix(s, 1), basis.integral(s))
    for t in out:
        t.setflags(write=False)
    return out


def basis_tables(basis: InputBasis, s) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:math:`V(s)`, :math:`V'(s)` and :math:`\\int_0^s V` of ``basis`` at the normalised times ``s``,
    each shape (K, n), read only and cached per (basis, times): what a torque model evaluates a
    segment's joint motion with."""
    s = np.ascontiguousarray(np.atleast_1d(np.asarray(s, dtype=float)))
    return _tables(basis, s.tobytes())
