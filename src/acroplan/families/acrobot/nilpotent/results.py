"""The results of Chapter 4's solvers: :class:`NilpotentResult`, :class:`SeriesResult` (polynomial
:math:`v_1, v_2`), :class:`FlatYResult` (the flat output as the clock)."""

from __future__ import annotations

import abc
import dataclasses
import functools
import json
import math
from typing import ClassVar, final

import numpy as np
from numpy.polynomial import polynomial as P
from scipy.optimize import brentq

from ....core.status import Status
from .equations import NilpotentProblem, _split, alpha_derivs, u1_values


@dataclasses.dataclass(frozen=True)
class NilpotentResult(abc.ABC):
    """A solution of the Chapter 4 problem, mapped back to the acrobot (the common face of the two
    methods).

    One result type per method, both built with keywords: :class:`SeriesResult` (``method =
    "nilpotent"``: polynomial :math:`v_1, v_2` in the virtual time :math:`\\varepsilon`, from
    :func:`solve_nilpotent` and :func:`counterexample`) and :class:`FlatYResult` (``method =
    "flat-y"``: the flat output as the clock, from :func:`solve_flat_y`). This base is abstract.

    Like a :class:`~acroplan.PlanResult`, a result has :meth:`evaluate` (states and input at the
    acrobot's times), :meth:`to_dict`, :meth:`to_json` and :meth:`plot`; in the virtual time it has
    :meth:`curve`, :meth:`clock` and :meth:`u_of_eps`, and :meth:`eps_of_t`, :meth:`u_of_t` map back.

    Attributes
    ----------
    success : bool
    status : Status
        ``"success"``, ``"infeasible"`` (no u1 > 0 found for this degree: see ``margin``) or
        ``"not_converged"`` (an :class:`acroplan.Status`, equal to its string).
    message : str
    problem : NilpotentProblem
    m : numpy.ndarray, shape (2 (degree+1),) or (3,)
        A read-only copy. ``"nilpotent"``: coefficients of v1 then v2, ascending powers of epsilon;
        ``"flat-y"``: coefficients of :math:`\\varphi(\\sigma)`, ascending.
    residual : float
        Largest |endpoint equation residual|.
    margin : float
        :math:`\\min u_1` on a grid of 100001 points of [0, 1] (positive: time moves forward).
    phi_max : float
        :math:`\\max |\\varphi(\\varepsilon)|` (must stay below pi).
    verified_error : float or None
        :math:`\\|(\\theta, \\varphi)(T) - Q\\|` from re-simulating the acrobot in its own time with the
        mapped-back u(t) (scipy DOP853), when time moves forward.
    method : str
        ``"nilpotent"`` or ``"flat-y"``: a class attribute, fixed by the subclass.
    """

    method: ClassVar[str]

    success: bool
    status: Status
    message: str
    problem: NilpotentProblem
    m: np.ndarray
    residual: float
    margin: float
    phi_max: float
    verified_error: float | None = None

    def __post_init__(self):
        m = np.array(self.m, dtype=float)
        m.setflags(write=False)
        object.__setattr__(self, "m", m)
        object.__setattr__(self, "status", Status(self.status))
        if self.success != self.status.success:
            raise ValueError(f"success = {self.success} contradicts status = {self.status!r}")

    # ---------------------------------------------------------------- the motion in the virtual time
    @abc.abstractmethod
    def curve(self, eps):
        """The motion at virtual times ``eps`` in [0, 1].

        Parameters
        ----------
        eps : array_like, shape (N,)

        Returns
        -------
        t, theta, phi, u1 : numpy.ndarray, each shape (N,)
            The acrobot's time, its two angles (theta by the exact flow) and
            :math:`u_1 = dt/d\\varepsilon` (for ``"flat-y"``, :math:`dt/d\\sigma`).
        """

    @abc.abstractmethod
    def u_of_eps(self, eps):
        """The acrobot's joint rate :math:`u = d\\varphi/dt` at virtual times ``eps``.

        Parameters
        ----------
        eps : array_like, shape (N,)

        Returns
        -------
        numpy.ndarray, shape (N,)
        """

    @abc.abstractmethod
    def clock(self, eps):
        """The acrobot's time :math:`t(\\varepsilon)`.

        Parameters
        ----------
        eps : float or array_like, shape (N,)

        Returns
        -------
        numpy.ndarray, shape (N,)  (shape (1,) for a scalar)
        """

    @abc.abstractmethod
    def _clock_and_rate(self, e: float):
        """Scalar t(eps) and dt/deps, in plain floats (the hot path of the re-simulation)."""

    @abc.abstractmethod
    def _u_at(self, e: float) -> float:
        """Scalar u = dphi/dt at the virtual time ``e``."""

    @abc.abstractmethod
    def _coefficients(self) -> dict:
        """The ``"coefficients"`` entry of :meth:`to_dict`."""

    # ---------------------------------------------------------------- back to the acrobot's time
    @functools.cached_property
    def _clock_table(self):
        """``(eps, t(eps))`` on 2049 points: the brackets of :meth:`eps_of_t` (built on first use)."""
        e = np.linspace(0.0, 1.0, 2049)
        return e, self.clock(e)

    def eps_of_t(self, t):
        """The virtual time at the acrobot's time ``t``: the inverse of the (increasing) clock.

        A table brackets, Newton's method (safeguarded by the bracket) and Brent's method finish.

        Parameters
        ----------
        t : float
            Times before ``P.t`` give 0, after ``Q.t`` give 1.

        Returns
        -------
        float
            :math:`\\varepsilon \\in [0, 1]`.
        """
        T0, T1 = self.problem.P[1], self.problem.Q[1]
        if t <= T0:
            return 0.0
        if t >= T1:
            return 1.0
        e, tt = self._clock_table
        i = int(np.clip(np.searchsorted(tt, t), 1, e.size - 1))
        lo, hi = e[i - 1], e[i]
        f = lambda x: float(self.clock(x)[0]) - t  # noqa: E731
        if f(lo) * f(hi) > 0:
            return brentq(f, 0.0, 1.0, xtol=1e-15, rtol=1e-15)
        # Newton on t(eps) = t with dt/deps = u1 > 0, safeguarded by the bracket
        x = 0.5 * (lo + hi)
        for _ in range(30):
            tx, d = self._clock_and_rate(x)
            if d <= 0:
                break
            x_new = x - (tx - t) / d
            if not lo <= x_new <= hi:
                break
            if abs(x_new - x) <= 4e-16:
                return x_new
            x = x_new
        return brentq(f, lo, hi, xtol=1e-15, rtol=1e-15)

    def u_of_t(self, t):
        """The input :math:`u(t) = d\\varphi/dt` at the acrobot's time ``t``.

        Parameters
        ----------
        t : float

        Returns
        -------
        float
        """
        return self._u_at(self.eps_of_t(t))

    def evaluate(self, t):
        """States and input at the acrobot's times ``t``, like :meth:`acroplan.PlanResult.evaluate`.

        Each time is mapped to its virtual time by :meth:`eps_of_t`; the angles are read off
        :meth:`curve` there and the input is :meth:`u_of_t`.

        Parameters
        ----------
        t : float or array_like, shape (N,)
            Times in ``[P.t, Q.t]`` (the problem's ``P[1]`` and ``Q[1]``).

        Returns
        -------
        acroplan.core.result.Samples
            ``t`` shape (N,), ``states`` shape (2, N) for ``("theta", "phi")``, ``inputs`` shape
            (1, N) for ``("u",)``.

        Raises
        ------
        ValueError
            If a time lies outside ``[P.t, Q.t]`` or is not finite, or if the clock does not run
            forward (``margin`` not positive: the curve is no motion of the acrobot).
        """
        from ....core.result import Samples

        t = np.atleast_1d(np.asarray(t, dtype=float))
        if t.ndim != 1:
            raise ValueError(f"t: must be a number or a 1-d array of times, got shape {t.shape}")
        if not self.margin > 0:
            raise ValueError(f"this result's clock does not run forward (margin {self.margin:.4g}): it is no "
                             "motion of the acrobot in its own time; use curve(eps) instead")
        lo, hi = self.problem.P[1], self.problem.Q[1]
        if not np.all(np.isfinite(t)) or np.any(t < lo) or np.any(t > hi):
            raise ValueError(f"t: every time must lie in [P.t, Q.t] = [{lo}, {hi}]")
        eps = np.array([self.eps_of_t(float(x)) for x in t])
        _, theta, phi, _ = self.curve(eps)
        u = np.array([self._u_at(e) for e in eps])
        return Samples(t, np.vstack([theta, phi]), u[None, :], ("theta", "phi"), ("u",))

    # ---------------------------------------------------------------- export
    def to_dict(self) -> dict:
        """The result as plain JSON types (the CLI's ``solution.json`` without ``"system"``).

        Returns
        -------
        dict
            ``status``, ``success``, ``message``, ``method``, ``P``, ``Q``, ``degree``,
            ``coefficients`` (``{"v1", "v2"}`` or ``{"phi_of_y"}``), ``equation_residual``,
            ``u1_margin``, ``max_abs_phi``, ``verified_error``.
        """
        return {"status": self.status, "success": self.success, "message": self.message,
                "method": type(self).method, "P": list(self.problem.P), "Q": list(self.problem.Q),
                "degree": self.problem.degree, "coefficients": self._coefficients(),
                "equation_residual": self.residual, "u1_margin": self.margin, "max_abs_phi": self.phi_max,
                "verified_error": self.verified_error}

    def to_json(self, **kwargs) -> str:
        """:meth:`to_dict` as a JSON string.

        Parameters
        ----------
        **kwargs
            Passed to :func:`json.dumps` (``indent`` is 2 unless given).

        Returns
        -------
        str
        """
        kwargs.setdefault("indent", 2)
        return json.dumps(self.to_dict(), **kwargs)

    def plot(self, counter=None, *, samples: int = 801):
        """Figures of the result (matplotlib), as :func:`~acroplan.families.acrobot.plots.plot_nilpotent`.

        Parameters
        ----------
        counter : NilpotentResult, optional
            A solution of the same equations along which :math:`u_1 < 0` (:func:`counterexample`),
            to add the ``"failure_mode"`` figure.
        samples : int
            Virtual times sampled on [0, 1].

        Returns
        -------
        dict of str to matplotlib.figure.Figure
            ``{"input", "states", "u1"}``, plus ``"failure_mode"`` with ``counter``.
        """
        from ..plots import plot_nilpotent

        return plot_nilpotent(self, counter, samples=samples)


@final
@dataclasses.dataclass(frozen=True)
class SeriesResult(NilpotentResult):
    """A :class:`NilpotentResult` of the nilpotent model (``method = "nilpotent"``): polynomial
    :math:`v_1, v_2` in the virtual time, ``m`` = coefficients of v1 then v2, shape (2 (degree+1),).

    The polynomials :math:`v_1, v_2, V_1, V_2` are computed once, at construction.
    """

    method: ClassVar[str] = "nilpotent"

    def __post_init__(self):
        super().__post_init__()
        v1, v2 = _split(self.m, self.problem.degree)
        object.__setattr__(self, "_pp", (v1, v2, P.polyint(v1), P.polyint(v2)))

    def curve(self, eps):
        prob = self.problem
        eps = np.asarray(eps, dtype=float)
        x1 = prob.P[0] + P.polyval(eps, self._pp[3])
        t = self.clock(eps)
        u1, _ = u1_values(prob, self.m, eps)
        theta = _theta_along(prob, self.m, eps)
        return t, theta, x1, u1

    def u_of_eps(self, eps):
        return P.polyval(eps, self._pp[1]) / u1_values(self.problem, self.m, eps)[0]

    def clock(self, eps):
        prob = self.problem
        eps = np.atleast_1d(np.asarray(eps, dtype=float))
        _, _, V1, V2 = self._pp
        x1 = prob.P[0] + P.polyval(eps, V2)
        x2 = prob.x2P + P.polyval(eps, V1)
        return prob.P[1] + alpha_derivs(prob.robot, x1)[0] * x2

    def _clock_and_rate(self, e: float):
        prob, r = self.problem, self.problem.robot
        v1, v2, V1, V2 = self._pp
        x1 = prob.P[0] + _horner(V2, e)
        x2 = prob.x2P + _horner(V1, e)
        if abs(x1) < 1e-3:
            s0, s1 = 1 + x1 * x1 / 6, x1 / 3
        else:
            sn, cs = math.sin(x1), math.cos(x1)
            s0, s1 = x1 / sn, (sn - x1 * cs) / (sn * sn)
        h = r.M1 + r.A1 * math.cos(x1)
        hp = -r.A1 * math.sin(x1)
        n = (r.M1 + r.A1) ** 2
        a0, a1 = s0 * h * h / n, (s1 * h * h + 2 * s0 * h * hp) / n
        return prob.P[1] + a0 * x2, a0 * _horner(v1, e) + x2 * a1 * _horner(v2, e)

    def _u_at(self, e: float) -> float:
        return _horner(self._pp[1], e) / self._clock_and_rate(e)[1]

    def _coefficients(self) -> dict:
        d = self.problem.degree
        return {"v1": list(map(float, self.m[: d + 1])), "v2": list(map(float, self.m[d + 1:]))}


@final
@dataclasses.dataclass(frozen=True)
class FlatYResult(NilpotentResult):
    """A :class:`NilpotentResult` of the flat-output variant (``method = "flat-y"``): the virtual time
    is :math:`\\sigma = (y - y_P)/(y_Q - y_P)`, ``m`` = coefficients of :math:`\\varphi(\\sigma)`,
    ascending, shape (3,).
    """

    method: ClassVar[str] = "flat-y"

    def _dy(self) -> float:
        prob, r = self.problem, self.problem.robot
        return prob.Q[2] + float(r.F(prob.Q[0])) - prob.P[2] - float(r.F(prob.P[0]))

    def curve(self, eps):
        sig = np.asarray(eps, dtype=float)
        prob, r = self.problem, self.problem.robot
        yP = prob.P[2] + float(r.F(prob.P[0]))
        yQ = prob.Q[2] + float(r.F(prob.Q[0]))
        dy = yQ - yP
        phi = P.polyval(sig, self.m)
        t = self.clock(sig)
        theta = yP + sig * dy - r.F(phi)
        dtds = dy / r.P0 * r.h(phi)
        return t, theta, phi, dtds

    def u_of_eps(self, eps):
        r = self.problem.robot
        dy = self._dy()
        phi = P.polyval(eps, self.m)
        return P.polyval(eps, P.polyder(self.m)) / (dy / r.P0 * r.h(phi))

    def clock(self, eps):
        sig = np.atleast_1d(np.asarray(eps, dtype=float))
        prob, r = self.problem, self.problem.robot
        dy = self._dy()
        xg, wg = _XG60, _WG60
        return np.array([prob.P[1] + s / 2 * dy / r.P0 * float(r.h(P.polyval(s * (xg + 1) / 2, self.m)) @ wg)
                         for s in sig])

    def _clock_and_rate(self, e: float):
        r = self.problem.robot
        return float(self.clock(np.array([e]))[0]), self._dy() / r.P0 * float(r.h(_horner(self.m, e)))

    def _u_at(self, e: float) -> float:
        return float(self.u_of_eps(np.array([e]))[0])

    def _coefficients(self) -> dict:
        return {"phi_of_y": list(map(float, self.m))}


# Gauss-Legendre nodes and weights on [-1, 1], 60 points: computed once (an eigenvalue problem each
# time otherwise; the clock is evaluated thousands of times in a re-simulation)
_XG60, _WG60 = np.polynomial.legendre.leggauss(60)


def _horner(c, x: float) -> float:
    out = 0.0
    for a in c[::-1]:
        out = out * x + a
    return float(out)


def _theta_along(prob, m, eps):
    """theta(eps) by quadrature of the exact field (an independent route to the endpoint formula)."""
    d = prob.degree
    v1, v2 = _split(m, d)
    out = np.empty(eps.size)
    xg, wg = _XG60, _WG60
    r = prob.robot
    for i, e in enumerate(eps):
        s = e * (xg + 1) / 2
        x1 = prob.P[0] + P.polyval(s, P.polyint(v2))
        x2 = prob.x2P + P.polyval(s, P.polyint(v1))
        a0, a1, _ = alpha_derivs(r, x1)
        h = r.h(x1)
        integrand = a0 * r.P0 / h * P.polyval(s, v1) + (-r.k(x1) / h + x2 * a1 * r.P0 / h) * P.polyval(s, v2)
        out[i] = prob.P[2] + e / 2 * float(integrand @ wg)
    return out
