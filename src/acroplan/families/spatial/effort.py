"""Joint torques of a planned motion of a free-flying body in 3-D, by Pinocchio's inverse dynamics.

The planner works in kinematics (the inputs are the joint rates :math:`u = \\dot s`); the joint
torques :math:`\\tau` that produce a planned motion follow from the multibody dynamics of the free
body: :class:`SpatialTorque` (the torque model of a
:class:`~acroplan.families.spatial.model.SpatialBody`, registered by :func:`register`) and
:func:`inverse_dynamics`.

The root's motion
-----------------
The Pinocchio model of the link table (:mod:`~acroplan.families.spatial.pin`: a free-flyer root,
configuration :math:`(p, q)`, velocity :math:`\\nu = (v, \\Omega)` in the root's frame; one revolute
joint per other link, numbered depth first (the table's order); no gravity) has the
generalised velocity :math:`v = (\\nu, u)` and acceleration :math:`a = (\\dot\\nu, \\dot u)`. The
planned motion fixes the joints, and the attitude :math:`q(t)` through the state equation; the root's
twist and its rate follow from the momentum, with Pinocchio's centroidal momentum map
:math:`A_G(q)` (``computeCentroidalMap``: world axes, about the centre of mass; :math:`A_{G,r}`,
:math:`A_{G,j}` its six root and its joint columns) and its time variation :math:`\\dot A_G(q, v)`
(``computeCentroidalMapTimeVariation``):

* no external force or torque, so the centre of mass is at rest (its frame) and the angular momentum
  about it is the constant vector :math:`L` (inertial frame):

  .. math::  h_G = A_G(q)\\,v = (0, L)
             \\quad\\Longrightarrow\\quad
             \\nu = A_{G,r}^{-1}\\big((0, L) - A_{G,j}\\,u\\big) ,                 \\qquad (1)

  whose angular part is the model's :math:`\\Omega = \\mathbb{I}^{-1}(R^\\top L - A u)`;
* the momentum is constant:

  .. math::  \\dot h_G = A_G(q)\\,a + \\dot A_G(q, v)\\,v = 0
             \\quad\\Longrightarrow\\quad
             \\dot\\nu = -A_{G,r}^{-1}\\big(A_{G,j}\\,\\dot u + \\dot A_G\\,v\\big) .         \\qquad (2)

In 3-D the torques depend on the attitude through the momentum in the root's frame,
:math:`R(q)^\\top L`, alone (no gravity: turning the whole body changes nothing else). At
:math:`L = 0` they do not depend on it at all, and the attitude is not integrated. Otherwise it is
integrated along the segment first, by the compiled Taylor integrator of the family's state
equation with its variational equations (:math:`\\partial q(s)/\\partial c` comes with it), at
every node at once.

The torques
-----------
Pinocchio's recursive Newton-Euler algorithm (``rnea``) on the free-floating model gives the
generalised forces :math:`F = M(q)\\,a + C(q, v)\\,v = (F_{root}, \\tau)`. :math:`\\tau` (shape
``(m,)``) are the joint torques: :math:`\\tau_j` is the torque the motor of joint :math:`j` applies
to its child link about the joint axis (its parent receives :math:`-\\tau_j`), positive in the sense
of increasing :math:`s_j`. :math:`F_{root}` (6 rows: force, then moment, in the root's frame) is
the wrench the root would need from outside; since (1)-(2) make the momentum constant, it vanishes,
a check of the whole computation reported as :attr:`SpatialInverseDynamics.root_residual`
(rounding level; ``tests/test_spatial_effort.py`` asserts 1e-9). The torques do not depend on the
root's position (computed with the root at the origin).

Along a segment with input coefficients :math:`c` (shape ``(m, n)``) in a basis :math:`b_i(s)` on
:math:`s = (t - t_0)/T \\in [0, 1]`:

.. math::  s_j(s) = s_{j,0} + T\\,(c\\,I(s))_j ,\\qquad u(s) = c\\,V(s) ,\\qquad \\dot u(s) = c\\,V'(s)/T ,

and :math:`q(s)` from the integrator.

The Jacobian in the coefficients is exact (no finite differences): per node, the partial derivatives
of :math:`\\tau` in :math:`(\\delta\\theta, s, u, \\dot u)`, :math:`\\delta\\theta` the attitude's
rotation vector in the root frame (:math:`q \\to q \\otimes \\exp(\\delta\\theta)`, the tangent of
:meth:`SpatialBody.retract <acroplan.families.spatial.model.SpatialBody.retract>`), by the
implicit-function theorem on (1) and (2) with Pinocchio's analytic derivatives
(``computeCentroidalDynamicsDerivatives``, ``computeRNEADerivatives``; :math:`dq = (0, \\delta\\theta,
ds)` in Pinocchio's tangent space):

.. math::  d\\nu = -A_{G,r}^{-1}\\big(\\partial_q h_G\\,dq + A_{G,j}\\,du\\big) ,\\qquad
           d\\dot\\nu = -A_{G,r}^{-1}\\big(\\partial_q\\dot h_G\\,dq + \\partial_v\\dot h_G\\,dv
           + A_{G,j}\\,d\\dot u\\big) ,\\qquad
           d\\tau = \\partial_q\\tau\\,dq + \\partial_v\\tau\\,dv + M_{j\\cdot}\\,da ;

then :math:`\\partial\\tau/\\partial c = \\partial_{\\delta\\theta}\\tau\\,\\partial\\delta\\theta(s)/\\partial c
+ \\partial_s\\tau\\,T I(s) + \\partial_u\\tau\\,V(s) + \\partial_{\\dot u}\\tau\\,V'(s)/T`, with
:math:`\\partial\\delta\\theta(s)/\\partial c` the compiled variational equations' sensitivity of the
attitude at :math:`s`, in the tangent space
(:meth:`SpatialBody.tangent_jacobian <acroplan.families.spatial.model.SpatialBody.tangent_jacobian>`).
``computeRNEADerivatives`` and the centroidal derivatives work on blocks of consecutive joints, so
the model numbers the joints depth first whatever the link table's own order (a breadth-first
numbering gives wrong derivatives on branched trees).

``tests/test_spatial_effort.py`` checks: a planar body described in 3-D gives the planar family's
torques and Jacobian (:class:`~acroplan.families.planar.effort.PlanarTorque`); the free-flyer part
vanishes along simulated motions with :math:`L \\ne 0`; a forward simulation of the full equations
of motion (free-flyer root free, Pinocchio's ``aba``) driven by these torques alone reproduces the
motion, with :math:`L` conserved; the partials and the Jacobian against central finite differences.

Units: those of the link table (kg, m, s give N m). Pinocchio is optional (``pip install
acroplan[bodies]``) and imported on first use.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from ...core import backend
from ...core.errors import InvalidInputError
from ...core.system import register_torque_model
from ..tree.motion import TreeInverseDynamics, TreeTorque, basis_tables, coefficient_jacobian, joint_motion, joint_rows, segment_arrays
from ..tree.pin import require_pinocchio, thread_data, without_gravity
from .collocation import momentum_samples
from .dynamics import MAX_COMPILED_JOINTS, joint_torques
from .links import SpatialLinkTable
from .model import SpatialBody
from .pin import SpatialPinocchioBody, build_model

__all__ = ["SpatialInverseDynamics", "inverse_dynamics", "SpatialTorque", "attitude_samples",
           "register"]


@functools.lru_cache(maxsize=64)
def _model(table: SpatialLinkTable) -> SpatialPinocchioBody:
    """The Pinocchio model of ``table`` (joints depth first), without gravity; cached, read only."""
    return without_gravity(build_model(table))  # SpatialLinkTable.topological_order is depth first


@dataclasses.dataclass(frozen=True)
class SpatialInverseDynamics(TreeInverseDynamics):
    """What :func:`inverse_dynamics` gives: ``tau``, ``root_residual`` as in
    :class:`~acroplan.families.tree.motion.TreeInverseDynamics` (the free flyer's six rows: force,
    then moment, in the root frame), and the root's motion.

    Attributes
    ----------
    root_velocity, root_acceleration : numpy.ndarray, shape (6, K)
        :math:`\\nu = (v, \\Omega)` and :math:`\\dot\\nu` of the root frame in the root frame (the
        root at the origin), from (1) and (2).
    partials : numpy.ndarray, shape (m, K, 3 + 3 m) or None
        :math:`\\partial\\tau/\\partial(\\delta\\theta, s, u, \\dot u)` per node (columns: the attitude's
        rotation vector in the root frame, the joint angles, the rates, the accelerations), when
        asked for.
    """

    root_velocity: np.ndarray
    root_acceleration: np.ndarray
    partials: np.ndarray | None = None


def _rows(name: str, value, m: int) -> np.ndarray:
    if name == "attitude":
        return joint_rows(name, value, m, what="quaternion component", fix="give quaternions [w, x, y, z]")
    return joint_rows(name, value, m)


def inverse_dynamics(body, attitude, q, u, du, *, derivatives: bool = False) -> SpatialInverseDynamics:
    """Joint torques of a free-flying spatial body from its attitude and joint motion (module
    docstring).

    Parameters
    ----------
    body : SpatialBody
        Its link table and :math:`L`.
    attitude : array_like, shape (4,) or (4, K)
        The root's attitude quaternions ``[w, x, y, z]`` (normalised here).
    q, u, du : array_like, shape (m,) or (m, K)
        Joint angles, rates and accelerations at ``K`` instants, one row per joint in state order
        (``body.links.joint_names``).
    derivatives : bool
        Also compute :attr:`SpatialInverseDynamics.partials`, exactly (Pinocchio's analytic
        derivatives).

    Returns
    -------
    SpatialInverseDynamics

    Raises
    ------
    InvalidInputError
        ``body`` is not a :class:`SpatialBody`, the shapes disagree, or Pinocchio is missing.
    """
    if not isinstance(body, SpatialBody):
        raise InvalidInputError("body", f"must be a SpatialBody, got {type(body).__name__}",
                                "build one with acroplan.families.spatial.SpatialBody(links, L=...)")
    pin = require_pinocchio()
    m = body.n_inputs
    Qa = _rows("attitude", attitude, 4)
    Q, U, DU = _rows("q", q, m), _rows("u", u, m), _rows("du", du, m)
    K = Q.shape[1]
    if Qa.shape[1] == 1 and K > 1:
        Qa = np.repeat(Qa, K, axis=1)
    if U.shape[1] != K or DU.shape[1] != K or Qa.shape[1] != K:
        raise InvalidInputError("u", f"attitude, q, u and du must have the same number of instants, got "
                                f"{Qa.shape[1]}, {Q.shape[1]}, {U.shape[1]}, {DU.shape[1]}",
                                "give one column per instant in each")
    pb = _model(body.links)
    model, data = pb.model, thread_data(pb)
    nv = model.nv
    jc = pb.idx_v
    h0 = np.concatenate([np.zeros(3), np.asarray(body.L, dtype=float)])
    cfg = np.array([pb.configuration(np.concatenate([Qa[:, k], Q[:, k]])) for k in range(K)])
    Ar, Aj = np.empty((K, 6, 6)), np.empty((K, 6, m))
    V, Acc, F = np.zeros((K, nv)), np.zeros((K, nv)), np.empty((K, nv))
    V[:, jc], Acc[:, jc] = U.T, DU.T
    for k in range(K):
        Ag = pin.computeCentroidalMap(model, data, cfg[k])  # (1)
        Ar[k], Aj[k] = Ag[:, :6], Ag[:, jc]
        V[k, :6] = np.linalg.solve(Ar[k], h0 - Aj[k] @ U[:, k])
        bias = pin.computeCentroidalMapTimeVariation(model, data, cfg[k], V[k]) @ V[k]  # (2)
        Acc[k, :6] = -np.linalg.solve(Ar[k], Aj[k] @ DU[:, k] + bias)
        F[k] = pin.rnea(model, data, cfg[k], V[k], Acc[k])
    partials = None
    if derivatives:
        nx = 3 + 3 * m
        dq = np.zeros((nv, nx))  # Pinocchio's tangent dq: (dp, dtheta, ds)
        dq[3:6, :3] = np.eye(3)
        dq[jc, 3:3 + m] = np.eye(m)
        J = np.empty((K, m, nx))
        for k in range(K):
            dh_dq, dhd_dq, dhd_dv, _ = pin.computeCentroidalDynamicsDerivatives(model, data, cfg[k], V[k], Acc[k])
            Fq, Fv, M = pin.computeRNEADerivatives(model, data, cfg[k], V[k], Acc[k])
            M = np.triu(M) + np.triu(M, 1).T  # Pinocchio fills the upper triangle
            dv = np.zeros((nv, nx))
            dv[jc, 3 + m:3 + 2 * m] = np.eye(m)
            dv[:6] = -np.linalg.solve(Ar[k], dh_dq @ dq + Aj[k] @ dv[jc])
            da = np.zeros((nv, nx))
            da[jc, 3 + 2 * m:] = np.eye(m)
            da[:6] = -np.linalg.solve(Ar[k], dhd_dq @ dq + dhd_dv @ dv + Aj[k] @ da[jc])
            J[k] = Fq[jc] @ dq + Fv[jc] @ dv + M[jc] @ da
        partials = np.ascontiguousarray(np.swapaxes(J, 0, 1))
    return SpatialInverseDynamics(F[:, jc].T.copy(), F[:, :6].T.copy(), V[:, :6].T.copy(), Acc[:, :6].T.copy(),
                                  partials)


def attitude_samples(system, basis, x0, T, c, s, *, jacobian: bool = False):
    """The states of a segment at normalised times ``s`` (any order, in [0, 1]) by the compiled
    Taylor integrator (:func:`acroplan.core.backend.taylor_sample`'s), and with ``jacobian`` their
    sensitivities to the coefficients from its variational equations, at the same cost (one
    ``propagate_grid``): the torques with and without their Jacobian see the same attitude.

    Returns
    -------
    X : numpy.ndarray, shape (n, K)
    DX : numpy.ndarray, shape (K, n, m * basis.n), only with ``jacobian``
        :math:`\\partial x(s_k)/\\partial c`, columns in flattened ``c`` order.
    """
    s = np.asarray(s, dtype=float).reshape(-1)
    if not (np.all(np.isfinite(s)) and s.min(initial=0.0) >= -1e-12):
        raise InvalidInputError("s", "must hold normalised times in [0, 1], got one below 0 or not finite",
                                "give s = (t - t0) / T for times t inside the segment")
    grid, where = np.unique(np.concatenate([[0.0], np.maximum(s, 0.0)]), return_inverse=True)
    ta, _, n_x = backend._load(system, basis, x0, T, c)
    res = ta.propagate_grid(grid, max_steps=backend.MAX_STEPS)
    out = res[-1]
    if res[0] != backend._TIME_LIMIT or not np.isfinite(out).all():
        raise backend.IntegrationError(backend._why(res[0], ta.time))
    out = out[where[1:]]
    X = out[:, :n_x].T.copy()
    if not jacobian:
        return X
    return X, out[:, n_x:].reshape(len(s), n_x, -1)


def _checked(system, basis, x0, T, c, s):
    """``(x0, T, c, s)`` of a segment as arrays, checked (naming the field)."""
    T, c, s = segment_arrays(system, basis, T, c, s)
    x0 = np.asarray(x0, dtype=float).reshape(-1)
    if x0.shape != (system.n_states,):
        raise InvalidInputError("x0", f"must have shape ({system.n_states},) {list(system.state_names)}, got "
                                f"{x0.shape}", "give the quaternion and every joint angle")
    return x0, T, c, s


@dataclasses.dataclass(frozen=True)
class SpatialTorque(TreeTorque):
    """The torque model of a :class:`~acroplan.families.spatial.model.SpatialBody`: its joint torques
    along a segment and their exact Jacobian in the input coefficients (module docstring), for
    :class:`acroplan.core.optimal.TorqueOptimal`, torque limits (``tau_max``) and the torques of a
    plan.

    Parameters
    ----------
    joint_names : tuple of str, optional
        One per torque row (the body's joints, in state order); the registered factory
        (:func:`register`) fills them in. ``None``: a model for any spatial body.

    Notes
    -----
    Call signature: ``model(system, basis, x0, T, c, s) -> (tau, jacobian)`` with ``c`` of shape
    ``(m, basis.n)``, ``s`` of shape ``(K,)`` (normalised times in [0, 1]), ``x0`` the segment's start
    state :math:`(q_w, q_x, q_y, q_z, s_1, \\dots, s_m)`; ``tau`` of shape ``(m, K)`` and ``jacobian``
    of shape ``(m, K, m * basis.n)``, :math:`\\partial\\tau/\\partial c` with ``c`` flattened row by
    row. :meth:`evaluate` also returns the free-flyer residual and the attitude.
    """

    KIND = "spatial"
    BODY = "SpatialBody"

    def _models(self, system) -> bool:
        return isinstance(system, SpatialBody)

    def motion(self, system, basis, x0, T, c, s, *, jacobian: bool = False):
        """The motion of the segment at ``s``: the attitude (4, K) from the compiled integrator, and
        :math:`s, u, \\dot u`, each (m, K), from the basis; with ``jacobian`` also the attitude's
        tangent sensitivity :math:`\\partial\\delta\\theta(s_k)/\\partial c`, shape (K, 3, m n)."""
        m = system.n_inputs
        x0, T, c, s = _checked(system, basis, x0, T, c, s)
        joints = joint_motion(x0[4:], T, c, basis_tables(basis, s))
        if not np.any(system.angular_momentum):
            # at L = 0 the torques do not depend on the attitude (no gravity, and no momentum for the
            # body to turn in): the start's attitude serves at every node, with no sensitivity
            att = np.repeat(x0[:4, None], s.size, axis=1)
            return (att,) + joints + ((np.zeros((s.size, 3, m * basis.n)),) if jacobian else ())
        if not jacobian:
            return (attitude_samples(system, basis, x0, T, c, s)[:4],) + joints
        X, DX = attitude_samples(system, basis, x0, T, c, s, jacobian=True)
        # the attitude's rows in the tangent space, as SpatialBody.tangent_jacobian, at every node at once
        w, a, b, d = X[:4]
        Lq = 2.0 * np.array([[-a, w, d, -b], [-b, -d, w, a], [-d, b, -a, w]])  # (3, 4, K)
        dtheta = np.einsum("ijk,kjc->kic", Lq, DX[:, :4])
        return (X[:4],) + joints + (dtheta,)

    def start_key(self, system, x0) -> np.ndarray:
        """The part of a segment's start state ``x0`` its torques depend on, besides its joint
        motion (:func:`acroplan.core.effort.effort_summary` works out the effort of segments with
        the same joint motion and key once): the joint angles at L = 0, where the attitude does not
        enter (:meth:`motion`), else the whole state."""
        x0 = np.asarray(x0, dtype=float).reshape(-1)
        return x0 if np.any(system.angular_momentum) else x0[4:]

    def evaluate(self, system, basis, x0, T, c, s, *, derivatives: bool = False) -> SpatialInverseDynamics:
        """:func:`inverse_dynamics` along the segment (its ``partials`` in the coefficients, shape
        (m, K, m n), with ``derivatives``)."""
        self._require(system)
        if not derivatives:
            att, q, u, du = self.motion(system, basis, x0, T, c, s)
            return inverse_dynamics(system, att, q, u, du)
        att, q, u, du, dtheta = self.motion(system, basis, x0, T, c, s, jacobian=True)
        out = inverse_dynamics(system, att, q, u, du, derivatives=True)
        m, P = system.n_inputs, out.partials  # (m, K, 3 + 3m): d tau / d(dtheta, s, u, du)
        jac = coefficient_jacobian(P[:, :, 3:3 + m], P[:, :, 3 + m:3 + 2 * m], P[:, :, 3 + 2 * m:], float(T),
                                   basis_tables(basis, s))
        jac = jac + np.einsum("pka,kac->pkc", P[:, :, :3], dtheta)
        return dataclasses.replace(out, partials=jac)

    def torques(self, system, basis, x0, T, c, s):
        """:math:`\\tau(s)` alone, shape (m, K) (no Jacobian: for results and sweeps), by the compiled
        recursion (:meth:`compiled`) when the body has at most
        :data:`~acroplan.families.spatial.dynamics.MAX_COMPILED_JOINTS` joints, else by
        :meth:`evaluate`."""
        if self._compiled_for(system):
            return self.compiled(system, basis, x0, T, c, s)
        return self.evaluate(system, basis, x0, T, c, s).tau

    def _compiled_for(self, system) -> bool:
        self._require(system)
        return system.n_inputs <= MAX_COMPILED_JOINTS

    def compiled(self, system, basis, x0, T, c, s, *, jacobian: bool = False):
        """The torques by the compiled recursion (:func:`~acroplan.families.spatial.dynamics.joint_torques`)
        at the momentum in the root's frame that the collocation gives at ``s``
        (:func:`~acroplan.families.spatial.collocation.momentum_samples`), and with ``jacobian`` their
        exact derivatives in the coefficients:

        .. math::  \\frac{\\partial\\tau}{\\partial c} = \\partial_s\\tau\\, T I(s) + \\partial_u\\tau\\, V(s)
                   + \\partial_{\\dot u}\\tau\\, V'(s)/T + \\partial_\\lambda\\tau\\, \\frac{\\partial\\lambda(s)}{\\partial c} .

        Returns
        -------
        tau : numpy.ndarray, shape (m, K)
        jacobian : numpy.ndarray, shape (m, K, m * basis.n), only with ``jacobian``
        """
        m = system.n_inputs
        x0, T, c, s = _checked(system, basis, x0, T, c, s)
        tables = basis_tables(basis, s)
        q, u, du = joint_motion(x0[4:], T, c, tables)
        if not jacobian:
            lam = momentum_samples(system, basis, x0, T, c, s)
            return joint_torques(system.links, q, u, du, lam)
        lam, dlam = momentum_samples(system, basis, x0, T, c, s, jacobian=True)
        tau, P = joint_torques(system.links, q, u, du, lam, derivatives=True)
        jac = coefficient_jacobian(P[:, :, :m], P[:, :, m:2 * m], P[:, :, 2 * m:3 * m], T, tables)
        if np.any(system.angular_momentum):
            jac += np.einsum("pka,kac->pkc", P[:, :, 3 * m:], dlam)
        return tau, jac

    def __call__(self, system, basis, x0, T, c, s):
        if self._compiled_for(system):
            return self.compiled(system, basis, x0, T, c, s, jacobian=True)
        out = self.evaluate(system, basis, x0, T, c, s, derivatives=True)
        return out.tau, out.partials

    def __repr__(self):
        return self._repr()


def _factory(body) -> SpatialTorque:
    return SpatialTorque(body.links.joint_names)


def register() -> None:
    """Make :class:`SpatialTorque` the torque model of :class:`SpatialBody`
    (:func:`acroplan.core.system.register_torque_model`); idempotent."""
    register_torque_model(SpatialBody, _factory)

