"""The independent check of planar bodies, by Pinocchio: nothing here uses the sympy fields.

* :func:`centroidal_momentum`: the angular momentum about the centre of mass from Pinocchio's
  centroidal momentum map :math:`A_G(q)` (``computeCentroidalMap``): :math:`h_G = A_G(q)\\,v`, its
  angular :math:`z` component;
* :func:`simulate_with_pinocchio`: a forward simulation driven by Pinocchio alone. At each
  right-hand side, with the joint rates :math:`u(t)` given, the root's planar twist
  :math:`\\nu = (v_x, v_y, \\omega)` solves the three planar rows of the centroidal momentum
  (linear :math:`x, y` and angular :math:`z`),

  .. math::  A_{G,\\mathrm{root}}(q)\\,\\nu = (0, 0, P_0) - A_{G,\\mathrm{joints}}(q)\\,u ,

  (the centre of mass at rest, the angular momentum :math:`P_0`), and
  :math:`(\\dot\\theta, \\dot q) = (\\omega, u)` is integrated with scipy's DOP853 at
  ``max_step`` a sixteenth of the interval, as :mod:`acroplan.core.verify` does;
* :func:`pinocchio_errors`: the check ``plan(verify=True)`` uses for planar bodies
  (:meth:`PlanarBody.family_errors <acroplan.families.planar.model.PlanarBody.family_errors>`): the
  same Pinocchio-driven motion, chained through a plan's segments, computed as what it is. The
  joint angles are the exact integrals of the planned inputs (a polynomial, integrated in its basis),
  and :math:`\\omega` does not depend on :math:`\\theta` (turning the whole body changes no momentum
  about its centre of mass), so :math:`\\theta(t_1) = \\theta(t_0) + \\int \\omega\\,dt` is a
  quadrature: composite Gauss-Legendre, 16 nodes a panel, panels doubled until two rules agree to
  :math:`10^{-13}` (at most :data:`MAX_PANELS`), and their disagreement is added to the reported
  error, so an unresolved integral can only make the check stricter. Exact up to rounding and much
  faster than DOP853 (no step control, one centroidal map a node; measured in ``docs/planar.md``).

Pinocchio is optional (``pip install acroplan[bodies]``) and imported on first use.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ..tree.check import simulate_driven
from .links import LinkTable
from .pin import PinocchioBody, build_model, require_pinocchio

__all__ = ["centroidal_momentum", "state_error", "centroidal_rows", "simulate_with_pinocchio", "pinocchio_body", "pinocchio_errors",
           "pinocchio_turn", "MAX_PANELS"]

#: the most panels (of 16 nodes) :func:`pinocchio_turn` uses on one segment
MAX_PANELS = 4096


@functools.lru_cache(maxsize=64)
def _cached(table: LinkTable, root: str) -> PinocchioBody:
    return build_model(table, root)


def pinocchio_body(body, root: str = "planar") -> PinocchioBody:
    """The Pinocchio model of ``body``'s link table (cached per table and root joint)."""
    return _cached(LinkTable.of(body), root)


def centroidal_rows(body, state, root: str = "planar"):
    """The planar rows of Pinocchio's centroidal momentum map at ``state``.

    Parameters
    ----------
    body : PlanarBody or LinkTable
    state : array_like, shape (n,)
    root : {"planar", "freeflyer"}

    Returns
    -------
    A_root : numpy.ndarray, shape (3, 3)
        Rows (linear x, linear y, angular z), columns the root twist :math:`(v_x, v_y, \\omega)`.
    A_joints : numpy.ndarray, shape (3, n - 1)
        The same rows, columns the joint rates in state order.
    """
    pin = require_pinocchio()
    pb = pinocchio_body(body, root)
    data = pb.model.createData()
    Ag = pin.computeCentroidalMap(pb.model, data, pb.configuration(state))
    rows = [0, 1, 5]
    return Ag[np.ix_(rows, pb.root_columns)], Ag[np.ix_(rows, pb.joint_columns)]


def centroidal_momentum(body, state, theta_dot, u, *, root: str = "planar") -> float:
    """The angular momentum about the centre of mass by Pinocchio's centroidal map.

    The root frame turns at :math:`\\dot\\theta` (its translation does not change the momentum
    about the centre of mass; it is taken 0).

    Parameters
    ----------
    body : PlanarBody or LinkTable
    state : array_like, shape (n,)
        :math:`(\\theta, q_1, \\dots, q_{n-1})`.
    theta_dot : float
    u : array_like, shape (n - 1,)
        Joint rates.
    root : {"planar", "freeflyer"}
        The root joint of the Pinocchio model.

    Returns
    -------
    float
        :math:`h_G` angular :math:`z` = :math:`(A_G(q)\\,v)_5`.
    """
    pin = require_pinocchio()
    pb = pinocchio_body(body, root)
    data = pb.model.createData()
    Ag = pin.computeCentroidalMap(pb.model, data, pb.configuration(state))
    return float(Ag[5] @ pb.velocity((0.0, 0.0, float(theta_dot)), u))


def simulate_with_pinocchio(body, x0, t0: float, t1: float, u_of_t, rtol: float = 3e-14, atol: float = 3e-14,
                            t_eval=None, root: str = "planar"):
    """Forward simulation of a planar body driven by Pinocchio's centroidal map (module docstring).

    Parameters
    ----------
    body : PlanarBody
        Its link table and ``P0`` are used; its sympy fields are not.
    x0 : array_like, shape (n,)
        State at ``t0``.
    t0, t1 : float
    u_of_t : callable
        ``u_of_t(t)`` returns the joint rates at absolute time ``t``, shape ``(n - 1,)`` (or
        ``(n - 1, 1)``, as :meth:`SegmentResult.input` does).
    rtol, atol : float
        DOP853 tolerances.
    t_eval : array_like, optional
        Times to report (default: ``t1`` only).
    root : {"planar", "freeflyer"}

    Returns
    -------
    scipy.integrate.OdeResult
        ``.t`` absolute times, ``.y`` shape (n, len(t)); ``.y[:, -1]`` the state at ``t1``.
    """
    pin = require_pinocchio()
    pb = pinocchio_body(body, root)
    data = pb.model.createData()
    P0 = float(body.P0)
    rows = [0, 1, 5]
    rc, jc = pb.root_columns, pb.joint_columns
    m = len(jc)
    target = np.array([0.0, 0.0, P0])
    t0 = float(t0)

    def fun(tau, x):
        u = np.asarray(u_of_t(t0 + tau), dtype=float).reshape(m)
        Ag = pin.computeCentroidalMap(pb.model, data, pb.configuration(x))[rows]
        nu = np.linalg.solve(Ag[:, rc], target - Ag[:, jc] @ u)
        return np.concatenate([[nu[2]], u])

    return simulate_driven(fun, x0, t0, t1, rtol=rtol, atol=atol, t_eval=t_eval)


_XQ, _WQ = np.polynomial.legendre.leggauss(16)


@functools.lru_cache(maxsize=32)
def _panel_nodes(panels: int):
    s = ((np.arange(panels)[:, None] + (_XQ[None, :] + 1.0) / 2.0) / panels).ravel()
    w = np.tile(_WQ / (2.0 * panels), panels)
    s.flags.writeable = False
    w.flags.writeable = False
    return s, w


class _Omega:
    """:math:`\\omega(q, u)` at many nodes, from Pinocchio's centroidal map (module docstring)."""

    def __init__(self, body, root: str = "planar"):
        self.pin = require_pinocchio()
        self.pb = pinocchio_body(body, root)
        self.data = self.pb.model.createData()
        self.idx_q = self.pb.idx_q
        self.rc, self.jc = self.pb.root_columns, self.pb.joint_columns
        self.P0 = float(body.P0)

    def __call__(self, theta: float, Q, Udot):
        """``Q``, ``Udot``: joint angles and rates, shape (m, N); returns :math:`\\omega`, shape (N,)."""
        pin, model, data = self.pin, self.pb.model, self.data
        q = self.pb.configuration(np.concatenate([[theta], Q[:, 0]]))
        N = Q.shape[1]
        rows = np.empty((N, 3, model.nv))
        idx = self.idx_q
        Qt = Q.T.copy()
        for k in range(N):
            q[idx] = Qt[k]
            Ag = pin.computeCentroidalMap(model, data, q)
            rows[k, 0] = Ag[0]
            rows[k, 1] = Ag[1]
            rows[k, 2] = Ag[5]
        A_root = rows[:, :, self.rc]  # (N, 3, 3)
        A_joint = rows[:, :, self.jc]  # (N, 3, m)
        rhs = -np.einsum("kij,jk->ki", A_joint, Udot)
        rhs[:, 2] += self.P0
        return np.linalg.solve(A_root, rhs[:, :, None])[:, 2, 0]


def pinocchio_turn(body, theta0: float, q0, T: float, basis, coefficients, *, omega=None, tol: float = 1e-13):
    """One segment of the Pinocchio-driven motion as a quadrature (module docstring).

    Parameters
    ----------
    body : PlanarBody
    theta0 : float
    q0 : array_like, shape (m,)
    T : float
    basis : InputBasis
    coefficients : array_like, shape (m, basis.n)
        The joint rates in ``basis`` on :math:`s = (t - t_0)/T`.
    tol : float
        Agreement of two successive rules required, relative to :math:`1 + |\\Delta\\theta|`.

    Returns
    -------
    (state, uncertainty) : numpy.ndarray of shape (n,) and float
        The state at the segment's end, and the last two rules' disagreement on :math:`\\theta`.
    """
    omega = omega or _Omega(body)
    c = np.asarray(coefficients, dtype=float)
    q0 = np.asarray(q0, dtype=float)
    qT = q0 + T * (basis.integral([1.0])[0] @ c.T)
    # one panel per radian of the largest joint travel, at least 2
    from ...core.limits import input_extremes

    travel = max(max(abs(v) for v in input_extremes(basis, row)) for row in c) * T
    panels = int(min(MAX_PANELS, max(2, math.ceil(travel))))
    prev, diff = None, math.inf
    while True:
        s, w = _panel_nodes(panels)
        Q = q0[:, None] + T * (basis.integral(s) @ c.T).T
        Ud = (basis.matrix(s) @ c.T).T
        val = T * float(omega(theta0, Q, Ud) @ w)
        if prev is not None:
            diff = abs(val - prev)
            if diff <= tol * (1.0 + abs(val)) or panels >= MAX_PANELS:
                break
        prev = val
        panels = min(MAX_PANELS, 2 * panels)
    return np.concatenate([[theta0 + val], qT]), diff


def pinocchio_errors(body, x0, segments) -> np.ndarray:
    """The independent check of a planar body's plan by Pinocchio (module docstring): the segments'
    inputs chained from ``x0``, each segment's error the largest :math:`|x - x_{target}|` plus the
    quadrature's disagreement.

    Parameters
    ----------
    body : PlanarBody
    x0 : array_like, shape (n,)
    segments : sequence of SegmentResult
        Each with its ``basis`` and ``basis_coefficients``.

    Returns
    -------
    numpy.ndarray, shape (len(segments),)
    """
    from ...core.basis import Legendre

    omega = _Omega(body)
    x = np.asarray(x0, dtype=float)
    out = []
    for seg in segments:
        basis = seg.basis if seg.basis is not None else Legendre(seg.basis_coefficients.shape[1])
        x, unc = pinocchio_turn(body, float(x[0]), x[1:], seg.t1 - seg.t0, basis, seg.basis_coefficients,
                                omega=omega)
        out.append(float(np.max(np.abs(x - np.asarray(seg.target, dtype=float)))) + unc)
    return np.array(out)


def state_error(x, target) -> float:
    """:math:`\\max_i |x_i - x_{target,i}|` of two states (every state is an angle)."""
    return float(np.max(np.abs(np.asarray(x, dtype=float) - np.asarray(target, dtype=float))))
