"""The joint motion of one segment of a tree body, and the chain rule from a function of it to the
input coefficients: what the planar and spatial torque models share.

On a segment of duration :math:`T` with input coefficients :math:`c` (shape (m, n)) in the basis
:math:`V(s)` (``basis.matrix``), its derivative :math:`V'(s)` and its integral :math:`I(s)`
(``basis.integral``), at normalised times :math:`s \\in [0, 1]`:

.. math::  q(s) = q_0 + T\\,c\\,I(s)^T, \\qquad u(s) = c\\,V(s)^T, \\qquad \\dot u(s) = c\\,V'(s)^T / T,

so a function :math:`\\tau(q, u, \\dot u)` of the joint motion has

.. math::  \\frac{\\partial\\tau}{\\partial c} = \\partial_q\\tau\\; T I(s) + \\partial_u\\tau\\; V(s)
           + \\partial_{\\dot u}\\tau\\; V'(s) / T .

:class:`TreeTorque` is the base of the two torque models: the joints a model is for, and whether it
can give a system's torques; :class:`TreeInverseDynamics` the base of what their inverse dynamics
return.
"""

from __future__ import annotations

import dataclasses
from typing import ClassVar

import numpy as np

from ...core.basis import basis_tables
from ...core.errors import InvalidInputError
from .pin import INSTALL_HINT, require_pinocchio

__all__ = ["joint_rows", "basis_tables", "segment_arrays", "joint_motion", "coefficient_jacobian", "TreeTorque",
           "TreeInverseDynamics"]


def joint_rows(name: str, value, m: int, *, what: str = "joint",
               fix: str = "give the joint values in state order") -> np.ndarray:
    """``value`` as an array of shape (m, K) (a vector is one column), or the error naming ``name``:
    one row per ``what``, every value finite."""
    a = np.asarray(value, dtype=float)
    if a.ndim == 1:
        a = a[:, None]
    if a.ndim != 2 or a.shape[0] != m:
        raise InvalidInputError(name, f"must have shape ({m},) or ({m}, K), one row per {what}, got shape "
                                f"{np.shape(value)}", fix)
    if not np.all(np.isfinite(a)):
        raise InvalidInputError(name, "has a value that is not finite", "give finite numbers")
    return a


def segment_arrays(system, basis, T, c, s) -> tuple[float, np.ndarray, np.ndarray]:
    """``(T, c, s)`` of a segment checked (naming the field): ``c`` of shape (m, basis.n), ``T`` a
    positive finite duration, ``s`` the times as a contiguous vector."""
    m = system.n_inputs
    c = np.asarray(c, dtype=float)
    if c.shape != (m, basis.n):
        raise InvalidInputError("c", f"must have shape ({m}, {basis.n}), got {c.shape}",
                                "give one row of basis coefficients per joint")
    T = float(T)
    if not (np.isfinite(T) and T > 0):
        raise InvalidInputError("T", f"must be a positive duration, got {T}", "give the segment's length")
    return T, c, np.ascontiguousarray(np.atleast_1d(np.asarray(s, dtype=float)))


def joint_motion(q0, T: float, c, tables) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:math:`q, u, \\dot u` at the times of ``tables`` (:func:`basis_tables`), each shape (m, K),
    from the joint angles ``q0`` (m,) at the segment's start (module docstring)."""
    V, V1, Int = tables
    return np.asarray(q0, dtype=float)[:, None] + T * (c @ Int.T), c @ V.T, (c @ V1.T) / T


def coefficient_jacobian(dq, du, ddu, T: float, tables) -> np.ndarray:
    """:math:`\\partial\\tau / \\partial c` by the chain rule of the module docstring.

    Parameters
    ----------
    dq, du, ddu : numpy.ndarray, shape (p, K, m)
        :math:`\\partial\\tau_p(s_k) / \\partial(q, u, \\dot u)_j`.
    T : float
    tables : tuple
        :func:`basis_tables` at the same times.

    Returns
    -------
    numpy.ndarray, shape (p, K, m * n)
        Columns in flattened ``c`` order.
    """
    V, V1, Int = tables
    p, K, m = dq.shape
    # one batched product over the instants, jac[p, k, j, i] = sum_a D[p, k, j, a] E[k, a, i]
    # (three outer-product einsums took ten times as long: 1.9 against 0.19 ms on 257 instants of
    # four joints at 30 coefficients)
    D = np.stack([dq, du, ddu], axis=-1)          # (p, K, m, 3)
    E = np.stack([T * Int, V, V1 / T], axis=1)    # (K, 3, n)
    return (D @ E).reshape(p, K, m * V.shape[1])


@dataclasses.dataclass(frozen=True)
class TreeInverseDynamics:
    """The joint torques of a motion and the root's motion they imply: the base of the families'
    results of inverse dynamics, which add the root's velocity and acceleration.

    Attributes
    ----------
    tau : numpy.ndarray, shape (m, K)
        Joint torques, in state order of the joints (N m with SI link tables).
    root_residual : numpy.ndarray, shape (r, K)
        RNEA's rows of the root joint (``r`` its degrees of freedom) :math:`F_{root}`: the external
        wrench the motion would need; zero up to rounding for a free body.
    """

    tau: np.ndarray
    root_residual: np.ndarray


@dataclasses.dataclass(frozen=True)
class TreeTorque:
    """The base of the torque models of tree bodies: the joints a model is for, and why it cannot
    give the torques of a system (:meth:`unsupported`).

    A subclass sets ``KIND`` (``"planar"``: the family, in messages) and ``BODY`` (the body's class
    name), and defines ``_models(system)``: whether ``system`` is a body of the family.

    Parameters
    ----------
    joint_names : tuple of str, optional
        One per torque row (the body's joints, in state order), filled in by the body's
        ``torque_model()``; ``None``: a model for any body of the family.
    """

    joint_names: tuple | None = None
    KIND: ClassVar[str] = "tree"
    BODY: ClassVar[str] = "body"

    def __post_init__(self):
        if self.joint_names is not None:
            object.__setattr__(self, "joint_names", tuple(self.joint_names))

    def _models(self, system) -> bool:  # pragma: no cover - every family defines it
        raise NotImplementedError

    def unsupported(self, system) -> str | None:
        """Why the model cannot give the torques of ``system`` (``None`` when it can)."""
        name = type(self).__name__
        if not self._models(system):
            return f"{name} models {self.KIND} bodies, not {type(system).__name__}"
        if self.joint_names is not None and self.joint_names != system.links.joint_names:
            return (f"this {name} is for the joints {list(self.joint_names)}, the body has "
                    f"{list(system.links.joint_names)}: use the body's torque_model()")
        try:
            require_pinocchio()
        except InvalidInputError:
            return f"the torques of {self.KIND} bodies need Pinocchio: {INSTALL_HINT}"
        return None

    def _require(self, system) -> None:
        """The error of :meth:`unsupported`, when there is one."""
        why = self.unsupported(system)
        if why is not None:
            raise InvalidInputError("system", why, f"plan a {self.BODY} (with Pinocchio installed)")

    def _repr(self, *extra: str) -> str:
        names = "" if self.joint_names is None else f"joint_names={self.joint_names!r}"
        return f"{type(self).__name__}({', '.join(x for x in (names, *extra) if x)})"
