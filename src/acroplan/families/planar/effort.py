"""Joint torques of a planned motion of a free-flying planar body, by Pinocchio's inverse dynamics.

The planner works in kinematics (the inputs are the joint rates :math:`u = \\dot q`); the joint
torques :math:`\\tau` that produce a planned motion follow from the multibody dynamics of the free
body: :class:`PlanarTorque` (the torque model of :meth:`PlanarBody.torque_model
<acroplan.families.planar.model.PlanarBody.torque_model>`) and :func:`inverse_dynamics`.

The root's motion
-----------------
The Pinocchio model of the link table (:mod:`~acroplan.families.planar.pin`: a planar root joint,
velocity :math:`\\nu = (v_x, v_y, \\omega)` in the root's frame, or a free flyer restricted to the
plane; one revolute-:math:`z` joint per other link, numbered depth-first; no gravity) has the
generalised velocity :math:`v = (\\nu, u)` and acceleration :math:`a = (\\dot\\nu, \\dot u)`. The
planned motion fixes the joints only; the root's twist and its rate follow from the momentum, with Pinocchio's
centroidal momentum map :math:`A_G(q)` (``computeCentroidalMap``) and its time variation
:math:`\\dot A_G(q, v)` (``computeCentroidalMapTimeVariation``), restricted to the three rows of
planar motion (linear :math:`x, y`, angular :math:`z`; :math:`A_{G,r}`, :math:`A_{G,j}` their
root and joint columns):

* no external force, so the centre of mass is at rest (its frame) and the angular momentum about it
  is :math:`P_0`:

  .. math::  h_G = A_G(q)\\,v = (0, 0, P_0)
             \\quad\\Longrightarrow\\quad
             \\nu = A_{G,r}^{-1}\\big((0, 0, P_0) - A_{G,j}\\,u\\big) ,           \\qquad (1)

  so :math:`\\dot\\theta = \\omega` (text eq. 1: :math:`(P_0 - a(s)\\cdot u)/I(s)`);
* the momentum is constant:

  .. math::  \\dot h_G = A_G(q)\\,a + \\dot A_G(q, v)\\,v = 0
             \\quad\\Longrightarrow\\quad
             \\dot\\nu = -A_{G,r}^{-1}\\big(A_{G,j}\\,\\dot u + (\\dot A_G v)_{xy\\omega}\\big) ,   \\qquad (2)

  so :math:`\\ddot\\theta = \\dot\\omega`.

The torques
-----------
Pinocchio's recursive Newton-Euler algorithm (``rnea``) on the free-floating model gives the
generalised forces :math:`F = M(q)\\,a + C(q, v)\\,v` that produce :math:`(q, v, a)`:

.. math::  F = \\mathrm{RNEA}(q, v, a) = (F_{root}, \\tau) .

:math:`\\tau` (shape ``(m,)``) are the joint torques: :math:`\\tau_j` is the torque the motor of
joint :math:`j` applies to its child link (its parent receives :math:`-\\tau_j`), positive in the
sense of increasing :math:`q_j`. :math:`F_{root}` is the wrench the root would need from outside; a
free body gets none, and since (1)-(2) make the momentum constant, it vanishes:
:math:`F_{root} = 0` (3 rows for the planar root, 6 for the free flyer) is a check of the whole
computation, reported as :attr:`InverseDynamics.root_residual` (rounding level, tested to 1e-9).
The torques do not depend on :math:`\\theta` (turning the whole body changes no torque) nor on the
root's position; they are computed at :math:`\\theta = 0` with the root at the origin.

Along a segment with input coefficients :math:`c` (shape ``(m, n)``) in a basis :math:`b_i(s)`
on :math:`s = (t - t_0)/T \\in [0, 1]` (:class:`~acroplan.core.basis.InputBasis`):

.. math::  q(s) = q_0 + T\\,c\\,I(s) ,\\qquad u(s) = c\\,V(s) ,\\qquad \\dot u(s) = c\\,V'(s)/T ,

:math:`V = (b_i(s))`, :math:`V' = (b_i'(s))` and :math:`I = (\\int_0^s b_i)`.

The Jacobian in the coefficients is exact: per node, the partial derivatives of :math:`\\tau` in
:math:`(q, u, \\dot u)` by the implicit-function theorem on (1) and (2) with Pinocchio's analytic
derivatives (``computeCentroidalDynamicsDerivatives``: :math:`\\partial h_G/\\partial q`,
:math:`\\partial\\dot h_G/\\partial(q, v, a)`; ``computeRNEADerivatives``:
:math:`\\partial F/\\partial(q, v, a)`):

.. math::  d\\nu = -A_{G,r}^{-1}\\big(\\partial_q h_G\\,dq + A_{G,j}\\,du\\big) ,\\qquad
           d\\dot\\nu = -A_{G,r}^{-1}\\big(\\partial_q\\dot h_G\\,dq + \\partial_v\\dot h_G\\,dv
           + A_{G,j}\\,d\\dot u\\big) ,

.. math::  d\\tau = \\partial_q\\tau\\,dq + \\partial_v\\tau\\,dv + M_{j\\cdot}\\,da ,

then :math:`\\partial\\tau/\\partial c_{ji} = \\partial_{q_j}\\tau\\,T I_i(s) + \\partial_{u_j}\\tau\\,
V_i(s) + \\partial_{\\dot u_j}\\tau\\,V'_i(s)/T`. ``tests/test_planar_effort.py`` checks it against
central finite differences, the torques against the acrobot's closed form
(:func:`acroplan.families.acrobot.effort.joint_torque`) on the two-link body, and a forward
simulation of the full equations of motion (root free, Pinocchio's ``aba``) driven by these torques
alone against planned motions.

For the optimal strategies (:mod:`acroplan.core.optimal`) this module also gives the planar
bodies' starts, :func:`optimal_starts` (the shape guesses of :mod:`~acroplan.families.planar.guess`,
registered for :class:`~acroplan.families.planar.model.PlanarBody` by the package on import).

Units: those of the link table (kg, m, s give N m). Pinocchio is optional (``pip install
acroplan[bodies]``) and imported on first use.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np

from ...core.errors import InvalidInputError
from ..tree.motion import TreeInverseDynamics, TreeTorque, basis_tables, coefficient_jacobian, joint_motion, joint_rows, segment_arrays
from ..tree.pin import without_gravity
from .guess import shape_guesses
from .links import LinkTable
from .pin import PinocchioBody, build_model, require_pinocchio, thread_data

__all__ = ["InverseDynamics", "inverse_dynamics", "PlanarTorque", "ROOTS", "optimal_starts"]

#: The root joints of the Pinocchio model: ``"planar"`` (3 degrees of freedom) or
#: ``"freeflyer"`` (6, held in the plane).
ROOTS = ("planar", "freeflyer")
_ROWS = [0, 1, 5]  # the planar rows of the centroidal momentum: linear x, y, angular z


@functools.lru_cache(maxsize=64)
def _model(table: LinkTable, root: str) -> PinocchioBody:
    """The Pinocchio model of ``table`` (:func:`~acroplan.families.planar.pin.build_model`, its joints
    in depth-first order) without gravity; cached per table and root, read only."""
    return without_gravity(build_model(table, root))


@dataclasses.dataclass(frozen=True)
class InverseDynamics(TreeInverseDynamics):
    """What :func:`inverse_dynamics` gives: ``tau``, ``root_residual`` as in
    :class:`~acroplan.families.tree.motion.TreeInverseDynamics` (``r`` = 3 for the planar root, 6
    for the free flyer), and the root's motion.

    Attributes
    ----------
    theta_dot, theta_ddot : numpy.ndarray, shape (K,)
        :math:`\\dot\\theta = \\omega` and :math:`\\ddot\\theta = \\dot\\omega` from (1) and (2).
    root_velocity, root_acceleration : numpy.ndarray, shape (3, K)
        :math:`\\nu = (v_x, v_y, \\omega)` and :math:`\\dot\\nu` of the root frame, in the root
        frame (at :math:`\\theta = 0`, the root frame at the origin).
    partials : numpy.ndarray, shape (m, K, 3 m) or None
        :math:`\\partial\\tau/\\partial(q, u, \\dot u)` per node (columns: the joint angles, the
        rates, the accelerations), when asked for.
    """

    theta_dot: np.ndarray
    theta_ddot: np.ndarray
    root_velocity: np.ndarray
    root_acceleration: np.ndarray
    partials: np.ndarray | None = None


def _is_planar(system) -> bool:
    """A planar body: a system with a link table and a momentum (no import of ``.model``, which
    imports this module for :meth:`PlanarBody.torque_model`)."""
    return isinstance(getattr(system, "links", None), LinkTable) and hasattr(system, "P0")


def _table(body) -> LinkTable:
    if not _is_planar(body):
        raise InvalidInputError("body", f"must be a PlanarBody, got {type(body).__name__}",
                                "build one with acroplan.PlanarBody(links, P0=...)")
    return body.links


def inverse_dynamics(body, q, u, du, *, root: str = "planar", derivatives: bool = False) -> InverseDynamics:
    """Joint torques of a free-flying planar body from its joint motion (module docstring).

    Parameters
    ----------
    body : PlanarBody
        Its link table and :math:`P_0`.
    q, u, du : array_like, shape (m,) or (m, K)
        Joint angles, rates :math:`\\dot q` and accelerations :math:`\\ddot q` at ``K`` instants,
        one row per joint in state order (``body.links.joint_names``).
    root : {"planar", "freeflyer"}
        The root joint of the Pinocchio model; both give the same torques (tested), the free
        flyer's residual has 6 rows.
    derivatives : bool
        Also compute :attr:`InverseDynamics.partials`, exactly (Pinocchio's analytic derivatives).

    Returns
    -------
    InverseDynamics

    Raises
    ------
    InvalidInputError
        ``body`` is not a :class:`PlanarBody`, the shapes disagree, or Pinocchio is missing.
    """
    table = _table(body)
    if root not in ROOTS:
        raise InvalidInputError("root", f"must be one of {list(ROOTS)}, got {root!r}", "give root=\"planar\"")
    pin = require_pinocchio()
    m = len(table) - 1
    Q, U, DU = joint_rows("q", q, m), joint_rows("u", u, m), joint_rows("du", du, m)
    K = Q.shape[1]
    if U.shape[1] != K or DU.shape[1] != K:
        raise InvalidInputError("u", f"q, u and du must have the same number of instants, got {Q.shape[1]}, "
                                f"{U.shape[1]}, {DU.shape[1]}", "give one column per instant in each")
    pb = _model(table, root)
    model, data = pb.model, thread_data(pb)
    rc, jc = pb.root_columns, pb.joint_columns
    nv = model.nv
    root_rows = [i for i in range(nv) if i not in set(jc)]
    cfg = np.repeat(pb.configuration(np.zeros(m + 1))[None, :], K, axis=0)
    cfg[:, pb.idx_q] = Q.T
    Ut, DUt = U.T, DU.T  # (K, m)
    # (1): the root's twist from the momentum, Pinocchio's centroidal map at every node
    A = np.empty((K, 3, nv))
    for k in range(K):
        A[k] = pin.computeCentroidalMap(model, data, cfg[k])[_ROWS]
    Arr, Arj = A[:, :, rc], A[:, :, jc]  # (K, 3, 3), (K, 3, m)
    h0 = np.array([0.0, 0.0, float(body.P0)])
    V = np.zeros((K, nv))
    V[:, jc] = Ut
    V[:, rc] = np.linalg.solve(Arr, (h0[None, :] - np.einsum("kij,kj->ki", Arj, Ut))[:, :, None])[:, :, 0]
    # (2): the root's acceleration from the time variation of the map
    bias = np.empty((K, 3))
    for k in range(K):
        bias[k] = pin.computeCentroidalMapTimeVariation(model, data, cfg[k], V[k])[_ROWS] @ V[k]
    Acc = np.zeros((K, nv))
    Acc[:, jc] = DUt
    Acc[:, rc] = -np.linalg.solve(Arr, (np.einsum("kij,kj->ki", Arj, DUt) + bias)[:, :, None])[:, :, 0]
    # the generalised forces, joints and root
    F = np.empty((K, nv))
    for k in range(K):
        F[k] = pin.rnea(model, data, cfg[k], V[k], Acc[k])
    partials = None
    if derivatives:
        Hq = np.empty((K, 3, nv))  # d h_G / dq (planar rows)
        Dq, Dv = np.empty((K, 3, nv)), np.empty((K, 3, nv))  # d hdot_G / dq, dv
        Fq, Fv, M = np.empty((K, nv, nv)), np.empty((K, nv, nv)), np.empty((K, nv, nv))
        for k in range(K):
            dh_dq, dhd_dq, dhd_dv, _ = pin.computeCentroidalDynamicsDerivatives(model, data, cfg[k], V[k], Acc[k])
            Hq[k], Dq[k], Dv[k] = dh_dq[_ROWS], dhd_dq[_ROWS], dhd_dv[_ROWS]
            dF_dq, dF_dv, dF_da = pin.computeRNEADerivatives(model, data, cfg[k], V[k], Acc[k])
            Fq[k], Fv[k], M[k] = dF_dq, dF_dv, dF_da
        M = np.triu(M) + np.swapaxes(np.triu(M, 1), 1, 2)  # Pinocchio fills the upper triangle
        # d(q, v, a) / d(q_joints, u, du), columns (q, u, du) of m each
        eye = np.eye(m)
        dq = np.zeros((nv, 3 * m))
        dq[jc, :m] = eye
        dv = np.zeros((K, nv, 3 * m))
        dv[:, jc, m:2 * m] = eye
        dv[:, rc, :m] = -np.linalg.solve(Arr, Hq[:, :, jc])
        dv[:, rc, m:2 * m] = -np.linalg.solve(Arr, Arj)
        da = np.zeros((K, nv, 3 * m))
        da[:, jc, 2 * m:] = eye
        da[:, rc, :] = -np.linalg.solve(Arr, Dq @ dq + Dv @ dv + Arj @ da[:, jc, :])
        J = Fq[:, jc, :] @ dq + Fv[:, jc, :] @ dv + M[:, jc, :] @ da  # (K, m, 3m)
        partials = np.ascontiguousarray(np.swapaxes(J, 0, 1))
    nu, dnu = V[:, rc].T.copy(), Acc[:, rc].T.copy()  # (vx, vy, omega) and its rate
    return InverseDynamics(F[:, jc].T.copy(), F[:, root_rows].T.copy(), nu[2].copy(), dnu[2].copy(), nu, dnu,
                           partials)


@dataclasses.dataclass(frozen=True)
class PlanarTorque(TreeTorque):
    """The torque model of a :class:`~acroplan.families.planar.model.PlanarBody`: its joint
    torques along a segment and their exact Jacobian in the input coefficients (module docstring),
    for :class:`acroplan.core.optimal.TorqueOptimal`, torque limits (``tau_max``) and the torques of
    a plan.

    Parameters
    ----------
    joint_names : tuple of str, optional
        One per torque row (the body's joints, in state order); :meth:`PlanarBody.torque_model
        <acroplan.families.planar.model.PlanarBody.torque_model>` fills them in. ``None``: a model
        for any planar body.
    root : {"planar", "freeflyer"}
        The root joint of the Pinocchio model.

    Notes
    -----
    Call signature: ``model(system, basis, x0, T, c, s) -> (tau, jacobian)`` with ``c`` of shape
    ``(m, basis.n)``, ``s`` of shape ``(K,)`` (normalised times in [0, 1]), ``x0`` the segment's
    start state :math:`(\\theta_0, q_0)`; ``tau`` of shape ``(m, K)`` and ``jacobian`` of shape
    ``(m, K, m * basis.n)``, :math:`\\partial\\tau/\\partial c` with ``c`` flattened row by row.
    """

    root: str = "planar"
    KIND = "planar"
    BODY = "PlanarBody"

    def __post_init__(self):
        super().__post_init__()
        if self.root not in ROOTS:
            raise InvalidInputError("root", f"must be one of {list(ROOTS)}, got {self.root!r}",
                                    "give root=\"planar\"")

    def _models(self, system) -> bool:
        return _is_planar(system)

    def motion(self, system, basis, x0, T, c, s):
        """The joint motion of the segment at ``s``: :math:`q, u, \\dot u`, each shape (m, K)."""
        T, c, s = segment_arrays(system, basis, T, c, s)
        return joint_motion(np.asarray(x0, dtype=float).reshape(-1)[1:], T, c, basis_tables(basis, s))

    def torques(self, system, basis, x0, T, c, s):
        """:math:`\\tau(s)` alone, shape (m, K) (no Jacobian: for results and sweeps)."""
        self._require(system)
        q, u, du = self.motion(system, basis, x0, T, c, s)
        return inverse_dynamics(system, q, u, du, root=self.root).tau

    def __call__(self, system, basis, x0, T, c, s):
        self._require(system)
        q, u, du = self.motion(system, basis, x0, T, c, s)
        out = inverse_dynamics(system, q, u, du, root=self.root, derivatives=True)
        m, P = system.n_inputs, out.partials  # (m, K, 3m): d tau / d(q, u, du)
        return out.tau, coefficient_jacobian(P[:, :, :m], P[:, :, m:2 * m], P[:, :, 2 * m:], float(T),
                                             basis_tables(basis, s))

    def __repr__(self):
        return self._repr("" if self.root == "planar" else f"root={self.root!r}")


def optimal_starts(interval, basis) -> list:
    """Starts for the optimal strategies (:class:`~acroplan.core.optimal.EnergyOptimal`,
    :class:`~acroplan.core.optimal.TorqueOptimal`) on a planar body: the shape guesses
    (:func:`~acroplan.families.planar.guess.shape_guesses`: the base joint motion plus a bump, a
    tuck or a shape loop whose amplitude solves the turn equation), which meet the target up to a
    quadrature's error, no ODE solved (about 2 ms). Registered for
    :class:`~acroplan.families.planar.model.PlanarBody` with
    :func:`acroplan.core.optimal.register_starts` when the package is imported; the strategy falls
    back on the body's ``method="auto"`` plan when none is found.

    Against the generic starts (``starts=("auto", "deform")``: the body's ``method="auto"`` plan,
    then path deformation from the minimum-norm input) on the same problems:
    ``python benchmarks/optimal_planar.py --starts`` (numbers in ``benchmarks/RESULTS.md``).

    Parameters
    ----------
    interval : Interval
        Its system (a planar body), ``x0``, ``x1``, ``T``, input conditions (``ends``) and limits.
    basis : InputBasis

    Returns
    -------
    list of (str, numpy.ndarray of shape (m, basis.n))
        ``(kind, coefficients)``, best first (compliant with the limits, then the smallest motion);
        empty when no family brackets the target.
    """
    guesses = shape_guesses(interval.system, basis, interval.x0, interval.x1, float(interval.T), interval.ends,
                            interval.limits)
    return [(g.kind, g.coefficients) for g in guesses]
