"""The costs of the optimal strategies (:mod:`~acroplan.core.optimal`): the control energy and the
integral of the squared joint torques, with their gradients and model Hessians.

* the control energy, exactly by the basis Gram matrix :math:`G_{ik} = \\int_0^1 b_i b_k\\,ds`:

  .. math::  E(c) = \\int_0^T \\|u(t)\\|^2\\,dt = T\\, c^\\top (I_m \\otimes G)\\, c ;

* the torque cost :math:`\\int_0^T \\|\\tau\\|^2 dt` for the torques a *torque model*
  (:data:`TorqueModel`) gives, by composite Gauss-Legendre quadrature (:data:`TORQUE_QUADRATURE`),
  with its Gauss-Newton Hessian :math:`2\\sum_k T w_k\\, \\partial\\tau_k^\\top \\partial\\tau_k`;
* :func:`tau_vector`: torque limits, one per joint of a model, validated.
"""

from __future__ import annotations

import functools
import math
from typing import Callable

import numpy as np

from .basis import InputBasis, check_points, gauss_legendre
from .errors import InvalidInputError

__all__ = ["energy", "TorqueModel", "EnergyCost", "TorqueCost", "cost_for", "call_torque", "tau_vector", "gram",
           "gauss", "TORQUE_QUADRATURE", "TORQUE_LIMIT_GRID", "TORQUE_MARGIN", "TORQUE_CHECK_POINTS",
           "torque_check_grid"]

#: Composite Gauss-Legendre rule for the torque cost: (panels, nodes per panel) on [0, 1].
TORQUE_QUADRATURE = (4, 24)
#: Points of the uniform grid on which torque limits are imposed (the check uses
#: :func:`torque_check_grid`).
TORQUE_LIMIT_GRID = 65
#: Relative margin of the torque limits on the grid (as the rate and joint limits' 2e-3).
TORQUE_MARGIN = 2e-3
#: ``(uniform, chebyshev)``: the points of :func:`torque_check_grid`.
TORQUE_CHECK_POINTS = (1025, 257)


def torque_check_grid() -> np.ndarray:
    """The normalised times (sorted, in [0, 1]) on which an optimum's torques are sampled for the
    check against their limits (the peaks near a limit are then refined between them:
    :meth:`~acroplan.core.optimum.OptimalProblem.torque_check`), and where the exchange rounds look
    for the largest excesses: the union of :data:`TORQUE_CHECK_POINTS` ``[0]`` uniform points and
    ``[1]`` Chebyshev-Lobatto points :math:`(1 - \\cos(\\pi k / K)) / 2`, which crowd towards the
    ends.

    A motion with :math:`n` coefficients an input has features about :math:`1/n^2` of the interval
    wide near its ends (the spacing of a degree-:math:`n` polynomial's extrema there): the peak of
    :math:`s (1 - s)\\, T_n''(2 s - 1)` near an end is missed by 1e-3 of its height from :math:`n =
    20` on the uniform points alone, 3e-3 at 30, 5e-2 at 50 (the Chebyshev points there are 1e-5
    to 1e-4 of the interval apart; the refinement then finds it to 1e-9). Checked on the uniform
    points alone, the bundled back double full-out's least :math:`\\int u^2` within the strength,
    its ladders taken to 30 coefficients, passed and was then refused by the exact peaks of the
    plan's own check (``not_converged``); a 3-D human with arms and hips passed it with four joints'
    torques above their limits within 0.3% of an interval's end (a shoulder's at 90.04 N m, its
    limit 89.9)."""
    return _CHECK_GRID


_CHECK_GRID = check_points(*TORQUE_CHECK_POINTS)
_CHECK_GRID.setflags(write=False)

#: ``torque(system, basis, x0, T, c, s) -> tau`` or ``(tau, jacobian)``: the joint torques of the
#: motion that input coefficients ``c`` (shape ``(m, basis.n)``) produce from ``x0`` in time ``T``,
#: at normalised times ``s`` (shape ``(K,)``): ``tau`` of shape ``(p, K)`` for ``p`` joints, and
#: optionally ``jacobian`` = d tau / d c of shape ``(p, K, m * basis.n)`` (flattened ``c``; by
#: forward differences when it is not given). An object may also have ``joint_names`` (length
#: ``p``) and ``unsupported(system) -> str | None``.
TorqueModel = Callable


@functools.lru_cache(maxsize=128)
def gram(basis: InputBasis) -> np.ndarray:
    """The basis Gram matrix :math:`G_{ik} = \\int_0^1 b_i b_k\\,ds` (read-only, cached)."""
    G = basis.gram()
    G.setflags(write=False)
    return G


@functools.lru_cache(maxsize=16)
def gauss(panels: int, per: int):
    """Composite Gauss-Legendre nodes and weights on [0, 1] (read-only)."""
    xg, wg = gauss_legendre(per)
    s = ((np.arange(panels)[:, None] + (xg[None, :] + 1.0) / 2.0) / panels).ravel()
    w = np.tile(wg / (2.0 * panels), panels)
    s.setflags(write=False)
    w.setflags(write=False)
    return s, w


def energy(basis: InputBasis, T: float, c) -> float:
    """:math:`\\int_0^T \\|u\\|^2 dt = T\\,\\sum_j c_j^\\top G c_j`, exact (basis Gram matrix).

    Parameters
    ----------
    basis : InputBasis
    T : float
        Segment duration.
    c : array_like, shape (m, basis.n) or (basis.n,)

    Returns
    -------
    float
    """
    c = np.atleast_2d(np.asarray(c, dtype=float))
    return float(T * np.einsum("ji,ik,jk->", c, gram(basis), c))


class EnergyCost:
    """:math:`f(c) = T c^\\top (I_m \\otimes G) c`: value, gradient and (exact, constant) Hessian."""

    label = "integral of |u|^2"

    def __init__(self, system, basis, x0, T):
        m = system.n_inputs
        self.H = 2.0 * T * (gram(basis) if m == 1 else np.kron(np.eye(m), gram(basis)))

    def __call__(self, c):
        g = self.H @ c
        return 0.5 * float(c @ g), g, self.H

    def value(self, c):
        """The cost alone."""
        return self(c)[0]


def torque_values(model, system, basis, x0, T, c, s):
    """The torque model's :math:`\\tau` alone at flat ``c``, shape (p, K): its ``torques`` method when
    it has one (no Jacobian computed), else its call with the Jacobian dropped."""
    m, n = system.n_inputs, basis.n
    c = np.asarray(c, dtype=float).reshape(m, n)
    alone = getattr(model, "torques", None)
    out = alone(system, basis, x0, T, c, s) if callable(alone) else model(system, basis, x0, T, c, s)
    return np.atleast_2d(np.asarray(out[0] if isinstance(out, tuple) else out, dtype=float))


def call_torque(model, system, basis, x0, T, c, s):
    """The torque model at flat ``c``: ``(tau (p, K), jacobian (p, K, N))``."""
    m, n = system.n_inputs, basis.n
    c = np.asarray(c, dtype=float).reshape(-1)
    out = model(system, basis, x0, T, c.reshape(m, n), s)
    if isinstance(out, tuple):
        tau = np.atleast_2d(np.asarray(out[0], dtype=float))
        return tau, np.asarray(out[1], dtype=float).reshape(tau.shape + (m * n,))
    tau = np.atleast_2d(np.asarray(out, dtype=float))
    jac = np.empty(tau.shape + (m * n,))
    for k in range(m * n):
        eps = 1e-7 * max(1.0, abs(c[k]))
        ck = c.copy()
        ck[k] += eps
        jac[:, :, k] = (np.atleast_2d(model(system, basis, x0, T, ck.reshape(m, n), s)) - tau) / eps
    return tau, jac


class TorqueCost:
    """:math:`f(c) = \\int_0^T \\|\\tau\\|^2 dt` by composite Gauss-Legendre, its gradient and its
    Gauss-Newton Hessian :math:`2\\sum_k T w_k\\, \\partial\\tau_k^\\top \\partial\\tau_k`."""

    label = "integral of |tau|^2"

    def __init__(self, model, system, basis, x0, T):
        self.model, self.system, self.basis, self.x0, self.T = model, system, basis, x0, T
        s, w = gauss(*TORQUE_QUADRATURE)
        self.s, self.sw = s, np.sqrt(T * w)

    def __call__(self, c):
        tau, jac = call_torque(self.model, self.system, self.basis, self.x0, self.T, c, self.s)
        r = (tau * self.sw).ravel()
        R = (jac * self.sw[None, :, None]).reshape(r.size, -1)
        return float(r @ r), 2.0 * R.T @ r, 2.0 * R.T @ R

    def value(self, c):
        """The cost alone, from the torques alone (:func:`torque_values`: no Jacobian)."""
        r = (torque_values(self.model, self.system, self.basis, self.x0, self.T, c, self.s) * self.sw).ravel()
        return float(r @ r)


def cost_for(cost, system, basis, x0, T):
    if isinstance(cost, str):
        return EnergyCost(system, basis, x0, T)
    return TorqueCost(cost, system, basis, x0, T)


def tau_vector(tau_max, model):
    """``tau_max`` as an array, one bound per joint of ``model`` (``inf``: unlimited); validated."""
    if tau_max is None:
        return None
    names = getattr(model, "joint_names", None)
    fix = "give each joint's largest torque, e.g. 50.0 (one number for all joints, one per joint, or a dict)"
    if isinstance(tau_max, dict):
        unknown = sorted(set(tau_max) - set(names)) if names is not None else []
        if unknown:
            raise InvalidInputError(f"tau_max.{unknown[0]}", "is not a joint of the torque model",
                                    f"joints are {list(names)}")
        if names is None and model is not None:
            raise InvalidInputError("tau_max", "a dict needs a torque model with joint_names", fix)
        raw = [tau_max.get(nm, math.inf) for nm in names] if names is not None else list(tau_max.values())
    else:
        raw = list(np.atleast_1d(tau_max)) if not isinstance(tau_max, (str, bytes)) else [tau_max]
    vals = []
    for v in raw:
        if isinstance(v, (bool, str, bytes)):
            raise InvalidInputError("tau_max", f"must be positive numbers, got {tau_max!r}", fix)
        try:
            v = float(v)
        except (TypeError, ValueError):
            raise InvalidInputError("tau_max", f"must be positive numbers, got {tau_max!r}", fix) from None
        if math.isnan(v) or v <= 0:
            raise InvalidInputError("tau_max", f"must be positive numbers, got {tau_max!r}", fix)
        vals.append(v)
    if names is not None and not isinstance(tau_max, dict):
        if len(vals) == 1:
            vals = vals * len(names)
        elif len(vals) != len(names):
            raise InvalidInputError("tau_max", f"has {len(vals)} value(s) for {len(names)} joint(s)",
                                    f"give one per joint {list(names)}, or one for all")
    return np.array(vals, dtype=float)

