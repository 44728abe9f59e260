"""Free-flying planar bodies with any number of links: :class:`PlanarBody`.

A body is a tree of :math:`n` rigid links (:mod:`~acroplan.families.planar.links`) flying freely
in a plane, with no external force or torque: its centre of mass :math:`c` stays at rest (in its
own frame) and its angular momentum about :math:`c` is a constant :math:`P_0`.

State and input
---------------
:math:`x = (\\theta, q_1, \\dots, q_{n-1})`: :math:`\\theta` is the root link's angle to the
inertial :math:`x` axis, :math:`q_j` the joint angles (the *shape* :math:`s = (q_1, \\dots,
q_{n-1})`), named by their joints. The inputs are the joint rates :math:`u_j = \\dot q_j`, named
``u_<joint>``. Link :math:`i`'s absolute angle is :math:`\\alpha_i = \\theta + \\beta_i(s)`,
:math:`\\beta_i = \\sum_{j \\in \\mathrm{path}(i)} q_j`.

The momentum map (text eq. 1)
-----------------------------
The angular momentum about the centre of mass is

.. math::  L = \\sum_{i=1}^{n} m_i\\,(r_i - c) \\times \\dot r_i + I_i\\,\\dot\\alpha_i ,\\qquad
           c = \\frac{1}{M}\\sum_i m_i r_i ,\\quad M = \\sum_i m_i .                     \\qquad (1)

*Barycentric vectors.* With :math:`o_i` the origin of link :math:`i`'s frame (its joint),
:math:`r_i = o_i + R(\\alpha_i) c_i` and :math:`o_h = o_k + R(\\alpha_k) j_h` for a child :math:`h`
of :math:`k`, every :math:`r_i` is a sum of vectors fixed in the links:
:math:`r_i = o + \\sum_k R(\\alpha_k)\\, e_{ik}`, where :math:`e_{ik} = c_k` if :math:`i = k`,
:math:`e_{ik} = j_h` if :math:`i` lies in the subtree of the child :math:`h` of :math:`k`, else 0.
So :math:`\\rho_i = r_i - c = \\sum_k R(\\alpha_k)\\, b_{ik}` with :math:`b_{ik} = e_{ik} - g_k/M`,

.. math::  g_k = \\sum_i m_i e_{ik} = m_k c_k + \\sum_{h \\in \\mathrm{children}(k)} S_h\\, j_h ,

:math:`S_h` the mass of the subtree of :math:`h`. Since :math:`\\sum_i m_i \\rho_i = 0`, (1) is
:math:`L = \\sum_i m_i \\rho_i \\times \\dot\\rho_i + I_i \\dot\\alpha_i`, and with
:math:`\\dot\\rho_i = \\sum_l \\dot\\alpha_l\\, J R(\\alpha_l) b_{il}` (:math:`J` the quarter turn),
:math:`a \\times Jb = a \\cdot b` and :math:`a \\cdot R(\\Delta) b = \\cos\\Delta\\, a\\cdot b -
\\sin\\Delta\\, a \\times b`:

.. math::  L = \\sum_l Q_l(s)\\,\\dot\\alpha_l ,\\qquad Q_l = I_l + \\sum_k H_{kl} ,\\qquad
           H_{kl} = \\cos(\\beta_l - \\beta_k)\\, D_{kl} - \\sin(\\beta_l - \\beta_k)\\, C_{kl} ,

with the constants :math:`D_{kl} = \\sum_i m_i\\, b_{ik} \\cdot b_{il}` and
:math:`C_{kl} = \\sum_i m_i\\, b_{ik} \\times b_{il}`. Summing over :math:`i` in closed form
(:math:`e_{ik}` and :math:`e_{il}` overlap only when one link is an ancestor of the other):

* :math:`D_{kk} = m_k |c_k|^2 + \\sum_{h \\in \\mathrm{children}(k)} S_h |j_h|^2 - |g_k|^2/M`;
* :math:`k` a proper ancestor of :math:`l`, :math:`h` the child of :math:`k` towards :math:`l`:
  :math:`D_{kl} = (j_h - g_k/M) \\cdot g_l`, :math:`C_{kl} = (j_h - g_k/M) \\times g_l`;
* neither an ancestor of the other: :math:`D_{kl} = -g_k \\cdot g_l/M`,
  :math:`C_{kl} = -g_k \\times g_l/M`;
* :math:`D_{lk} = D_{kl}`, :math:`C_{lk} = -C_{kl}` (so :math:`H` is symmetric).

:math:`\\theta` drops out (only angle differences appear), and since :math:`\\dot\\alpha_l =
\\dot\\theta + \\sum_{j \\in \\mathrm{path}(l)} u_j`,

.. math::  L = I(s)\\,\\dot\\theta + a(s) \\cdot u ,\\qquad I(s) = \\sum_l Q_l(s) ,\\qquad
           a_j(s) = \\sum_{l \\in \\mathrm{subtree}(j)} Q_l(s) ,

:math:`I(s) = \\sum_l I_l + \\sum_i m_i |\\rho_i|^2 > 0` the *locked inertia* and
:math:`\\mathrm{subtree}(j)` the links moved by joint :math:`j`. Conservation
:math:`L = P_0` gives the state equation

.. math::  \\dot\\theta = \\frac{P_0 - a(s) \\cdot u}{I(s)} ,\\qquad \\dot q_j = u_j .

:func:`momentum_from_definition` builds (1) literally in sympy (positions, centre of mass,
velocities by differentiation), the tests check it against this compact form and both against
Pinocchio's centroidal map (:mod:`~acroplan.families.planar.check`). With two links this is the
acrobot of text eq. (2)-(3): :meth:`PlanarBody.from_acrobot_physical`.

Parameters (runtime values of the compiled integrator)
------------------------------------------------------
The compiled fields are written in *lumped* parameters, as the acrobot's are in
:math:`M_1, A_1, M_2, A_2`: with :math:`D_{kl} + i\\,C_{kl} = R_{kl} e^{i\\psi_{kl}}`,

.. math::  H_{kl} = R_{kl} \\cos(\\beta_l - \\beta_k + \\psi_{kl}) ,\\qquad
           I(s) = I_c + 2 \\sum_{k<l} H_{kl} ,\\qquad
           a_j(s) = A_j + \\sum_{k<l} w^j_{kl} H_{kl} ,

:math:`w^j_{kl}` the number of :math:`k, l` in the subtree of joint :math:`j`,
:math:`I_c = \\sum_l (I_l + D_{ll})`, :math:`A_j = \\sum_{l \\in \\mathrm{subtree}(j)} (I_l + D_{ll})`.
The runtime parameters are ``P0, Ic, Ac_<joint>..., R_k_l, psi_k_l...`` (pairs of table indices),
computed from the link table in Python (:func:`lumped_coefficients`). The symbolic fields depend
only on the topology (:attr:`PlanarBody.structure_key` ``= ("planar", parents)``), so one
compilation serves every body of that topology, whatever its masses, lengths, names and
:math:`P_0`.

Why lumped: heyoka recomputes every parameter-only subexpression (and its Taylor derivatives) at
every step and order, and carries it into the variational equations. Written in the raw link
parameters (mass, inertia, centre of mass, joint position) a 4-link chain's integrator with 6
coefficients has 716 nodes in its Taylor decomposition and took about 10 s to compile cold; in
the lumped ones it has 434 nodes and about 4 s (3 links: 248 nodes).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any, Mapping

import numpy as np
import sympy as sp

from ...core.errors import finite_number
from ...core.errors import InvalidInputError
from ...core.system import ControlAffineSystem, Infeasibility
from ..tree.body import TreeBody
from .links import Link, LinkTable

__all__ = ["PlanarBody", "momentum_from_definition", "structure_coefficients", "lumped_coefficients",
           "physical_symbols"]


from .fields import (_generic_symbols, _pairs, _symbolic_map, _tree, _unpack, lumped_coefficients,  # noqa: F401
                     momentum_from_definition, physical_symbols, structure_coefficients)


# ---------------------------------------------------------------------- the body
_finite = finite_number


@dataclasses.dataclass(frozen=True, init=False)
class PlanarBody(TreeBody, ControlAffineSystem):
    """A free-flying planar body of any number of links (module docstring for the model).

    Parameters
    ----------
    links : LinkTable or sequence of Link
        The link table (:mod:`~acroplan.families.planar.links`): one root, a tree.
    angular_momentum : float
        The constant angular momentum about the centre of mass, :math:`P_0` (keyword; ``P0``, the
        field's name, is accepted as an alias).

    Attributes
    ----------
    state_names : tuple of str
        ``("theta", <joint names>...)``, length n.
    input_names : tuple of str
        ``("u_<joint>", ...)``, length n - 1; ``rate_inputs`` maps each to its joint.
    param_names : tuple of str
        The compiled (lumped) parameters ``P0, Ic, Ac_<joint>..., R_k_l, psi_k_l...``; the physical
        ones are the link table's (:meth:`physical_values`, :meth:`to_dict`).

    Examples
    --------
    >>> from acroplan.families.planar import Link, PlanarBody
    >>> body = PlanarBody([Link("a", None, 1.0, 0.1, com=(0.5, 0.0)),
    ...                    Link("b", "a", 1.0, 0.1, com=(0.5, 0.0), joint=(1.0, 0.0))], P0=0.0)
    >>> body.state_names, body.input_names
    (('theta', 'b'), ('u_b',))
    >>> round(body.locked_inertia([0.0]), 12)   # two rods in line: 2 * 0.1 + (1/2) * 1^2
    0.7
    """

    links: LinkTable
    P0: float = 0.0

    #: the states before the joints (theta), the record's name of the momentum, the check's module
    n_root = 1
    momentum_field = "P0"
    _check_module = "acroplan.families.planar.check"

    def __init__(self, links, P0: float | None = None, *, angular_momentum: float | None = None):
        if P0 is not None and angular_momentum is not None:
            raise InvalidInputError("angular_momentum", "is given together with P0 (its alias)", "give one of them")
        object.__setattr__(self, "links", links)
        object.__setattr__(self, "P0", angular_momentum if angular_momentum is not None else
                           (0.0 if P0 is None else P0))
        self.__post_init__()

    def __post_init__(self):
        object.__setattr__(self, "links", LinkTable(self.links))
        object.__setattr__(self, "P0", _finite("P0", self.P0))
        if len(self.links) < 2:
            raise InvalidInputError("links", "has one link: a single rigid body has no joint to move",
                                    "give at least two links")

    # ------------------------------------------------------------------ structure and names
    @property
    def structure_key(self):
        """``("planar", parents)``: the topology, in table order. Names and values are runtime."""
        return ("planar", self.links.parents)

    @property
    def state_names(self):
        return ("theta",) + self.links.joint_names

    @property
    def angle_states(self):
        """Every state is an angle (the root's and the revolute joints'): ``degrees=True`` converts
        them all, and their rates."""
        return self.state_names

    @property
    def param_names(self):
        """The compiled parameters (lumped, as the acrobot's ``M1, A1, M2, A2``): ``P0``, ``Ic``
        (the constant part of :math:`I(s)`), ``Ac_<joint>`` (of :math:`a_j(s)`), and per pair of
        links ``k < l`` (table indices) ``R_k_l``, ``psi_k_l`` (:func:`lumped_coefficients`)."""
        n = self.n_links
        names = ["P0", "Ic"] + [f"Ac_{j}" for j in self.links.joint_names]
        for k, l in _pairs(n):  # noqa: E741
            names += [f"R_{k}_{l}", f"psi_{k}_{l}"]
        return tuple(names)

    @property
    def _param_tuple(self) -> tuple:
        cached = self.__dict__.get("_acroplan_params")
        if cached is None:
            L = self.links
            vals = lumped_coefficients(L.parents, [k.mass for k in L], [k.inertia for k in L], [k.com for k in L],
                                       [k.joint for k in L], self.P0)
            cached = tuple(float(v) for v in vals)
            object.__setattr__(self, "_acroplan_params", cached)
        return cached

    def lumped(self) -> dict[str, float]:
        """Parameter values by name (``P0``, ``m_<link>``, ...)."""
        return dict(zip(self.param_names, self._param_tuple))

    @property
    def angular_momentum(self) -> float:
        """:math:`P_0`."""
        return self.P0

    def _momentum_record(self) -> float:
        return self.P0

    def symbols(self):
        """The compiled state and parameter symbols (``theta, q1, ...``; ``P0, Ic, Ac1, ...,
        R_k_l, psi_k_l``): they depend on the topology alone, so the symbolic fields cached per
        :attr:`structure_key` serve every body of that topology, whatever its names."""
        return _generic_symbols(self.links.parents)

    def physical_symbols(self):
        """State and physical parameter symbols (``P0, m0, I0, cx0, cy0, ..., jx1, jy1, ...`` by
        link index), in which :meth:`symbolic_momentum_map` ``(physical=True)`` and
        :func:`momentum_from_definition` are written."""
        return physical_symbols(self.links.parents)

    def physical_values(self) -> dict:
        """Values of :meth:`physical_symbols`' parameters for this body, by symbol."""
        _, p = physical_symbols(self.links.parents)
        vals = [self.P0]
        for i, link in enumerate(self.links):
            vals += [link.mass, link.inertia, link.com[0], link.com[1]]
            if i != self.links.root:
                vals += [link.joint[0], link.joint[1]]
        return dict(zip(p, vals))

    def lumped_expressions(self) -> dict:
        """The compiled parameters as sympy expressions of the physical ones, by symbol
        (substitute them in :meth:`symbolic` to get the fields in physical symbols)."""
        parents = self.links.parents
        _, p = _generic_symbols(parents)
        _, q = physical_symbols(parents)
        P0, m, inertia, com, joint = _unpack(parents, q)
        return dict(zip(p, lumped_coefficients(parents, m, inertia, com, joint, P0, symbolic=True)))

    # ------------------------------------------------------------------ fields
    def symbolic_momentum_map(self, physical: bool = False):
        """The momentum map :math:`L = I(s)\\dot\\theta + a(s) \\cdot u` in sympy (compact form).

        Parameters
        ----------
        physical : bool
            ``False``: in the compiled symbols (:meth:`symbols`),
            :math:`H_{kl} = R_{kl}\\cos(\\beta_l - \\beta_k + \\psi_{kl})`; ``True``: in the physical
            symbols (:meth:`physical_symbols`), :math:`H_{kl} = \\cos(\\Delta) D_{kl} - \\sin(\\Delta) C_{kl}`.

        Returns
        -------
        I : sympy.Expr
            The locked inertia.
        a : tuple of sympy.Expr, length n - 1
        """
        _, _, I, a = _symbolic_map(self.links.parents, physical)  # noqa: E741
        return I, a

    def symbolic_fields(self, x, p):
        """:math:`f = (P_0/I(s), 0, \\dots)`, :math:`G = \\begin{pmatrix} -a(s)^\\top/I(s) \\\\
        \\mathbb{1}\\end{pmatrix}`; shapes (n, 1) and (n, n - 1), in the compiled symbols."""
        x0, p0, I, a = _symbolic_map(self.links.parents)  # noqa: E741
        sub = {s: t for s, t in zip(x0 + p0, tuple(x) + tuple(p)) if s != t}
        if sub:
            I, a = I.xreplace(sub), tuple(e.xreplace(sub) for e in a)  # noqa: E741
        n = len(x)
        f = sp.zeros(n, 1)
        f[0] = p[0] / I
        G = sp.zeros(n, n - 1)
        for j in range(n - 1):
            G[0, j] = -a[j] / I
            G[1 + j, j] = 1
        return f, G

    # ------------------------------------------------------------------ numeric helpers
    def _constants(self):
        cached = self.__dict__.get("_planar_constants")
        if cached is None:
            L = self.links
            D, C = structure_coefficients(L.parents, [k.mass for k in L], [k.inertia for k in L],
                                          [k.com for k in L], [k.joint for k in L])
            _, _, path, subtree = _tree(L.parents)
            n = len(L)
            P = np.zeros((n, n - 1))  # beta = P s
            for i in range(n):
                for k in path[i]:
                    P[i, L.joints.index(k)] = 1.0
            Sub = np.zeros((n - 1, n))  # a = Sub Q
            for j, i in enumerate(L.joints):
                Sub[j, list(subtree[i])] = 1.0
            cached = dict(D=np.array(D, dtype=float), C=np.array(C, dtype=float),
                          inertia=np.array([k.inertia for k in L]), P=P, Sub=Sub)
            object.__setattr__(self, "_planar_constants", cached)
        return cached

    def momentum_map(self, shape) -> tuple[np.ndarray, np.ndarray]:
        """:math:`I(s)` and :math:`a(s)` at one shape or many.

        Parameters
        ----------
        shape : array_like, shape (n - 1,) or (n - 1, N)
            Joint angles in state order.

        Returns
        -------
        I : float or numpy.ndarray, shape () or (N,)
        a : numpy.ndarray, shape (n - 1,) or (n - 1, N)
        """
        K = self._constants()
        s = self._shape(shape)
        beta = np.tensordot(K["P"], s, axes=1)  # (n,) or (n, N)
        d = beta[None, :] - beta[:, None]  # d[k, l] = beta_l - beta_k
        D, C = K["D"], K["C"]
        if s.ndim > 1:
            D, C = D[..., None], C[..., None]
        H = np.cos(d) * D - np.sin(d) * C
        Q = K["inertia"].reshape((-1,) + (1,) * (s.ndim - 1)) + H.sum(axis=0)
        I = Q.sum(axis=0)  # noqa: E741
        a = np.tensordot(K["Sub"], Q, axes=1)
        return (float(I) if s.ndim == 1 else I), a

    def locked_inertia(self, shape):
        """:math:`I(s) = \\sum_i I_i + m_i |r_i - c|^2`, the inertia of the body frozen in shape
        ``s`` about its centre of mass.

        Parameters
        ----------
        shape : array_like, shape (n - 1,) or (n - 1, N)

        Returns
        -------
        float or numpy.ndarray, shape (N,)
        """
        return self.momentum_map(shape)[0]

    def momentum(self, state, theta_dot, u):
        """The angular momentum :math:`L = I(s)\\dot\\theta + a(s) \\cdot u` about the centre of mass.

        Parameters
        ----------
        state : array_like, shape (n,) or (n, N)
            :math:`(\\theta, q_1, \\dots)` (:math:`\\theta` does not enter).
        theta_dot : float or array_like, shape (N,)
        u : array_like, shape (n - 1,) or (n - 1, N)
            Joint rates.

        Returns
        -------
        float or numpy.ndarray, shape (N,)
        """
        x = np.asarray(state, dtype=float)
        I, a = self.momentum_map(x[1:])  # noqa: E741
        u = np.asarray(u, dtype=float)
        return I * np.asarray(theta_dot, dtype=float) + np.sum(a * u, axis=0)

    def theta_dot(self, state, u):
        """The state equation's first row, :math:`\\dot\\theta = (P_0 - a(s) \\cdot u)/I(s)`.

        Parameters
        ----------
        state : array_like, shape (n,) or (n, N)
        u : array_like, shape (n - 1,) or (n - 1, N)

        Returns
        -------
        float or numpy.ndarray, shape (N,)
        """
        x = np.asarray(state, dtype=float)
        I, a = self.momentum_map(x[1:])  # noqa: E741
        return (self.P0 - np.sum(a * np.asarray(u, dtype=float), axis=0)) / I

    def _kinematics(self, state):
        x = np.asarray(state, dtype=float)
        if x.shape != (self.n_states,):
            raise InvalidInputError("state", f"must have shape ({self.n_states},) {list(self.state_names)}, got "
                                    f"{x.shape}", "give theta and every joint angle")
        L = self.links
        K = self._constants()
        alpha = x[0] + K["P"] @ x[1:]
        origin = np.zeros((len(L), 2))
        for i in L.topological_order():
            p = L.parents[i]
            if p != -1:
                ca, sa = math.cos(alpha[p]), math.sin(alpha[p])
                jx, jy = L[i].joint
                origin[i] = origin[p] + (ca * jx - sa * jy, sa * jx + ca * jy)
        r = np.array([origin[i] + (math.cos(alpha[i]) * L[i].com[0] - math.sin(alpha[i]) * L[i].com[1],
                                   math.sin(alpha[i]) * L[i].com[0] + math.cos(alpha[i]) * L[i].com[1])
                      for i in range(len(L))])
        m = np.array([k.mass for k in L])
        c = m @ r / m.sum()
        return alpha, origin - c, r - c

    def link_frames(self, state) -> np.ndarray:
        """Each link's centre of mass in the centre-of-mass frame, and its absolute angle.

        Parameters
        ----------
        state : array_like, shape (n,)

        Returns
        -------
        numpy.ndarray, shape (n_links, 3)
            Row ``i`` (table order): :math:`(x_i, y_i, \\alpha_i)`, with :math:`(x_i, y_i) = r_i - c`
            and :math:`\\alpha_i = \\theta + \\beta_i(s)` the angle of link ``i``'s frame.
        """
        alpha, _, rc = self._kinematics(state)
        return np.column_stack([rc, alpha])

    def joint_positions(self, state) -> np.ndarray:
        """Each link's frame origin (its joint; for the root, its reference point) in the
        centre-of-mass frame, for drawing: link ``i`` is the segment from ``joint_positions[i]``
        to its children's joints (or to its centre of mass for a leaf).

        Returns
        -------
        numpy.ndarray, shape (n_links, 2)
        """
        return self._kinematics(state)[1]

    # ------------------------------------------------------------------ two links: the acrobot
    def as_acrobot(self):
        """A two-link body as the acrobot of text eq. (3), with its angle offsets.

        Any two-link body is an acrobot: with :math:`d = j_1 - c_0` (root centre of mass to the
        joint, root frame), :math:`l = |d|`, :math:`L = |c_1|`, the acrobot's angles are
        :math:`\\theta_A = \\theta + \\psi_0`, :math:`\\varphi_A = \\varphi + \\delta`, where
        :math:`\\psi_0 = \\arg(-d)` and :math:`\\delta = \\arg(c_1) - \\psi_0`.

        Returns
        -------
        (Acrobot, psi0, delta)

        Raises
        ------
        InvalidInputError
            When the body does not have exactly two links.
        """
        if self.n_links != 2:
            raise InvalidInputError("links", f"has {self.n_links} links; only a two-link body is an acrobot",
                                    "use the PlanarBody itself")
        from ..acrobot.model import Acrobot

        root = self.links[self.links.root]
        child = self.links[self.links.joints[0]]
        dx, dy = child.joint[0] - root.com[0], child.joint[1] - root.com[1]
        leg, torso = math.hypot(dx, dy), math.hypot(*child.com)
        psi0 = math.atan2(-dy, -dx) if leg > 0 else 0.0
        delta = (math.atan2(child.com[1], child.com[0]) if torso > 0 else 0.0) - psi0
        acro = Acrobot.from_physical(torso_mass=child.mass, leg_mass=root.mass, torso_inertia=child.inertia,
                                     leg_inertia=root.inertia, torso_length=torso, leg_length=leg,
                                     angular_momentum=self.P0)
        return acro, psi0, delta

    def check_segment(self, x0, x1, duration, limits=None):
        """Feasibility test of one segment: exact for two-link bodies (the acrobot's reachable set,
        through :meth:`as_acrobot`); for three or more links what can be proven under the limits
        (:meth:`turn_bound`).

        With three or more links: the joint ends must lie inside the joint limits, a joint with a
        rate limit :math:`\\bar u_j` cannot move more than :math:`\\bar u_j T`, and when every joint
        has a rate limit the root's turn is bounded (:func:`~acroplan.families.planar.connection.turn_bound`):
        a target beyond the bound is refused with it as the proof. Otherwise ``None`` (the segment
        may be feasible; the planner says ``not_converged`` with its diagnostics when it finds no
        motion).

        Returns
        -------
        Infeasibility or None
        """
        if self.n_links != 2:
            return self._check_bounded(x0, x1, duration, limits)
        from ...core.limits import Limits
        from ..acrobot.reach import reachable_set

        acro, psi0, delta = self.as_acrobot()
        joint = self.links.joint_names[0]
        q0, qT, T = float(x0[1]), float(x1[1]), float(duration)
        alim, lim = None, ""
        if limits is not None and limits.active:
            lo, hi = limits.bounds(joint)
            U = limits.input_bound(f"u_{joint}")
            lim = f" under {limits.describe()}"
            why = self.joint_ends_infeasibility(x0, x1, duration, limits)
            if why is not None:
                return why
            sb = {}
            if lo > -math.inf or hi < math.inf:
                sb["phi"] = (None if lo == -math.inf else lo + delta, None if hi == math.inf else hi + delta)
            alim = Limits(sb, {"u": U} if U is not None else None)
        R = reachable_set(acro, theta0=float(x0[0]) + psi0, phi0=q0 + delta, phiT=qT + delta, T=T, limits=alim)
        if not R.success:  # not reached: the ends and the distance were checked above
            return Infeasibility(f"no joint motion is possible{lim}", joint, None)
        lo, hi = R.low - psi0, R.high - psi0
        target = float(x1[0])
        scale = max(1.0, abs(lo), abs(hi))
        if lo == hi or self.P0 == 0.0:
            if abs(target - lo) <= 1e-12 * scale:
                return None
            why = ("P0 = 0 makes a two-link body holonomic (theta is a function of the joint angle)"
                   if self.P0 == 0.0 else "only one theta(T) is reachable")
            return Infeasibility(f"{why}: with {joint}(T) = {float(x1[1]):.12g} the only reachable theta(T) is "
                                 f"{lo:.12g}, not {target:.12g}", "theta", (lo, lo))
        if not lo < target < hi:
            kind, ends = ("closed", f"[{lo:.12g}, {hi:.12g}]") if R.closed else ("open", f"({lo:.12g}, {hi:.12g})")
            return Infeasibility(f"theta(T) = {target:.12g} is outside the reachable {kind} interval {ends}{lim} "
                                 f"for theta(0) = {float(x0[0]):.12g}, {joint}(0) = {float(x0[1]):.12g}, "
                                 f"{joint}(T) = {float(x1[1]):.12g}, T = {float(duration):.12g} (exact: a two-link "
                                 "body is an acrobot)", "theta", (lo, hi))
        return None

    def _check_bounded(self, x0, x1, duration, limits):
        why = self.joint_ends_infeasibility(x0, x1, duration, limits)
        if why is not None or limits is None or not limits.active:
            return why
        names = self.links.joint_names
        x0 = np.asarray(x0, dtype=float)
        x1 = np.asarray(x1, dtype=float)
        T = float(duration)
        lim = f" under {limits.describe()}"
        U = np.array([limits.input_bound(f"u_{j}") or math.inf for j in names])
        if not np.all(np.isfinite(U)):
            return None
        B = self.turn_bound(x0, x1, T, limits)
        turn = float(x1[0] - x0[0])
        if abs(turn) > B:
            return Infeasibility(
                f"theta must turn by {turn:.12g} rad, but{lim} the root turns at most "
                f"{B:.12g} rad in T = {T:.12g} s (|theta'| <= (|P0| + sum_j max|a_j| u_max_j) / min I over the "
                f"shapes the joints can reach, by interval arithmetic): theta(T) lies in "
                f"[{x0[0] - B:.12g}, {x0[0] + B:.12g}]", "theta", (float(x0[0] - B), float(x0[0] + B)))
        return None

    def turn_bound(self, x0, x1, duration, limits) -> float:
        """A proven bound of :math:`|\\theta(T) - \\theta(0)|` on a segment from ``x0`` to ``x1`` under
        ``limits`` (``inf`` unless every joint has a rate limit):
        :func:`~acroplan.families.planar.connection.turn_bound`.

        .. math::  |\\theta(T) - \\theta(0)| \\le \\int_0^T \\frac{|P_0| + \\sum_j \\max |a_j|\\,\\bar u_j}{\\min I}\\,dt ,

        the extremes over the joint angles reachable at each time (rate and joint limits), enclosed
        by interval arithmetic on the cosine sums of :math:`I` and :math:`a_j`.
        """
        from .connection import Connection, turn_bound

        names = self.links.joint_names
        U = np.array([limits.input_bound(f"u_{j}") or math.inf for j in names]) if limits is not None \
            else np.full(len(names), math.inf)
        lo = np.array([limits.bounds(j)[0] for j in names]) if limits is not None else None
        hi = np.array([limits.bounds(j)[1] for j in names]) if limits is not None else None
        return turn_bound(Connection(self), np.asarray(x0, dtype=float)[1:], np.asarray(x1, dtype=float)[1:],
                          float(duration), U, lo, hi)

    def torque_model(self):
        """The joint torques of a planned motion: Pinocchio's inverse dynamics of the free body,
        the root's motion from the momentum (:class:`~acroplan.families.planar.effort.PlanarTorque`,
        with this body's joint names)."""
        from .effort import PlanarTorque

        return PlanarTorque(self.links.joint_names)

    def state_unit(self, state):
        """The root's angle and the joint angles: ``"rad"``."""
        return "rad"

    def auto_strategy(self):
        """``method="auto"``: path deformation from a shape-loop guess that already meets the target
        (:class:`~acroplan.families.planar.strategy.PlanarAuto`)."""
        from .strategy import PlanarAuto

        return PlanarAuto()

    # ------------------------------------------------------------------ construction and records
    @classmethod
    def from_acrobot_physical(cls, *, torso_mass, leg_mass, torso_inertia, leg_inertia, torso_length, leg_length,
                              angular_momentum) -> "PlanarBody":
        """The acrobot of :meth:`Acrobot.from_physical <acroplan.families.acrobot.model.Acrobot.from_physical>`
        as a two-link planar body, with the same state :math:`(\\theta, \\varphi)`.

        The root is the leg (link ``"leg"``, frame at the joint, centre of mass at
        :math:`(l, 0)`), so :math:`\\theta` is the leg's angle; the torso (``"torso"``, centre of mass
        at :math:`(L, 0)` in its frame, joint at the leg frame's origin) hangs on the joint
        ``"phi"``, so :math:`\\varphi` is the angle from leg to torso: the torso's centre of mass is
        at :math:`L(\\cos(\\theta+\\varphi), \\sin(\\theta+\\varphi))` from the joint and the leg's
        at :math:`l(\\cos\\theta, \\sin\\theta)`, as for :class:`~acroplan.families.acrobot.model.Acrobot`.
        The input is ``u_phi``.
        """
        links = [
            Link("leg", None, leg_mass, leg_inertia, com=(leg_length, 0.0)),
            Link("torso", "leg", torso_mass, torso_inertia, com=(torso_length, 0.0), joint=(0.0, 0.0),
                 joint_name="phi"),
        ]
        return cls(links, P0=angular_momentum)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "PlanarBody":
        """Rebuild from :meth:`to_dict`'s output (``links`` and ``P0``; the rest is derived)."""
        return cls(LinkTable(cls._links_of(d)), P0=d.get("P0", 0.0))
