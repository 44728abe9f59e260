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
  ``max_step`` a sixteenth of the interval, as :mod:`acroplan.core.verify` does.

Pinocchio is optional (``pip install acroplan[bodies]``) and imported on first use.
"""

from __future__ import annotations

import functools

import numpy as np
from scipy.integrate import solve_ivp

from ...core.errors import InvalidInputError
from .links import LinkTable
from .pin import PinocchioBody, build_model, require_pinocchio

__all__ = ["centroidal_momentum", "centroidal_rows", "simulate_with_pinocchio", "pinocchio_body"]


@functools.lru_cache(maxsize=64)
def _cached(table: LinkTable, root: str) -> PinocchioBody:
    return build_model(table, root)


def pinocchio_body(body, root: str = "planar") -> PinocchioBody:
    """The Pinocchio model of ``body``'s link table (cached per table and root joint)."""
    table = getattr(body, "links", body)
    return _cached(table if isinstance(table, LinkTable) else LinkTable(table), root)


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
    t0, t1 = float(t0), float(t1)
    if not t1 > t0:
        raise InvalidInputError("t1", f"must be > t0, got t0 = {t0}, t1 = {t1}", "give an interval forward in time")

    def fun(tau, x):
        u = np.asarray(u_of_t(t0 + tau), dtype=float).reshape(m)
        Ag = pin.computeCentroidalMap(pb.model, data, pb.configuration(x))[rows]
        nu = np.linalg.solve(Ag[:, rc], target - Ag[:, jc] @ u)
        return np.concatenate([[nu[2]], u])

    T = t1 - t0
    te = None if t_eval is None else np.asarray(t_eval, dtype=float) - t0
    sol = solve_ivp(fun, (0.0, T), np.asarray(x0, dtype=float), method="DOP853", rtol=rtol, atol=atol,
                    max_step=T / 16, t_eval=te if te is not None else [T])
    if not sol.success:
        raise RuntimeError(f"the Pinocchio-driven simulation failed: {sol.message}")
    sol.t = sol.t + t0
    return sol
