"""The control-affine system interface.

A system is

.. math::  \\dot x = f(x; p) + \\sum_{j=1}^{m} g_j(x; p)\\, u_j ,

with state :math:`x` (``n`` numbers), inputs :math:`u \\in \\mathbb{R}^m` and constant parameters
:math:`p \\in \\mathbb{R}^{n_p}`. A concrete system writes its fields **once**, in sympy
(:meth:`ControlAffineSystem.symbolic_fields`); the compiled integrator (heyoka) and the independent
checking integrator (numpy through ``sympy.lambdify``) are both generated from that one definition.
Parameter values are runtime values, so one compilation serves every system of the same
*structure* (:attr:`ControlAffineSystem.structure_key`).

Contract for implementers
-------------------------
1. Subclass, as a frozen dataclass whose fields are the parameters (or any immutable class).
2. Give :attr:`state_names`, :attr:`input_names` and :attr:`param_names`: class attributes when
   every instance has the same structure (the acrobot), or properties computed from the instance
   (a body with any number of links).
3. Implement :meth:`symbolic_fields` (a classmethod or a method).
4. When the structure depends on the instance, override :attr:`structure_key` so that two
   instances with equal keys have the same symbolic fields up to parameter values: the compiled
   back end and the symbolic cache are keyed on it.
5. Optionally:

   * :attr:`rate_inputs` (input name -> state name) for inputs that are the time derivative of a
     state, which enables spline-derived input conditions and state bounds;
   * :meth:`diff` and :meth:`retract` when the state space is not Euclidean (a unit quaternion);
   * :meth:`check_segment`, an exact feasibility test;
   * :meth:`auto_strategy`, the family's own ``method="auto"``;
   * :meth:`torque_model`, the joint torques of a planned motion (effort, torque-optimal plans,
     torque limits), directly or through :func:`register_torque_model`;
   * :meth:`to_dict`, what a result file records of the system.
"""

from __future__ import annotations

import abc
import dataclasses
import threading
from typing import Any, Callable, ClassVar, Hashable

import numpy as np

from .family import prepare, registered_class, system_classes


class _Sympy:
    """``sympy``, imported on first use (0.3 s): a family whose fields need no sympy at start-up
    (:meth:`ControlAffineSystem.taylor_fields`, its own checking right-hand side) never imports it."""

    def __getattr__(self, name):
        import sympy

        return getattr(sympy, name)


sp = _Sympy()

__all__ = ["ControlAffineSystem", "Infeasibility", "register_torque_model", "TORQUE_MODELS", "torque_model_of",
           "joint_inputs"]


@dataclasses.dataclass(frozen=True)
class Infeasibility:
    """Proof that a segment cannot be done.

    Attributes
    ----------
    reason : str
        One sentence a user can read.
    field : str
        The state that cannot be reached (for example ``"theta"``).
    interval : tuple of float or None
        The reachable values of that state at the segment end (an open interval), or a single
        value ``(v, v)`` when only one value is reachable.
    """

    reason: str
    field: str
    interval: tuple[float, float] | None = None


# symbolic fields and lambdified right-hand sides, per structure key (not per class: a class may
# describe systems of many structures, a body with any number of links)
_SYMBOLIC: dict[Hashable, tuple[sp.Matrix, sp.Matrix]] = {}
_NUMERIC: dict[Hashable, Any] = {}
_LOCK = threading.Lock()
_TYPES: dict[str, type] = {}
#: Torque models by system class: ``factory(system) -> model or None`` (:func:`register_torque_model`).
TORQUE_MODELS: dict[type, Callable] = {}


def register_torque_model(system_type: type, factory: Callable) -> None:
    """Make ``factory(system)`` the torque model of systems of ``system_type`` (and subclasses):
    what the default :meth:`ControlAffineSystem.torque_model` returns. A family registers its own
    when imported, from the module that defines the model (so the model's module may import the
    system's without an import circle); the acrobot registers
    :class:`acroplan.families.acrobot.effort.AcrobotTorque`.

    Parameters
    ----------
    system_type : type
        A :class:`ControlAffineSystem` subclass.
    factory : callable
        ``factory(system) -> model or None`` (the interface of a model:
        :meth:`ControlAffineSystem.torque_model`).
    """
    from .errors import InvalidInputError

    if not (isinstance(system_type, type) and issubclass(system_type, ControlAffineSystem)):
        raise InvalidInputError("system_type", f"must be a ControlAffineSystem subclass, got {system_type!r}",
                                "pass the system's class")
    if not callable(factory):
        raise InvalidInputError("factory", f"must be callable, got {factory!r}",
                                "give factory(system) -> torque model or None")
    TORQUE_MODELS[system_type] = factory


class ControlAffineSystem(abc.ABC):
    """Abstract control-affine system :math:`\\dot x = f(x;p) + G(x;p)\\,u`.

    Shapes: ``x`` is ``(n,)``, ``f`` is ``(n,)``, ``G`` is ``(n, m)``; tangent vectors
    (:meth:`diff`) are ``(n,)`` too (``ndx == n``) unless a subclass says otherwise.

    Family hooks, each a method with a default: :meth:`check_segment`, :meth:`continuation_path`,
    :meth:`family_errors`, :meth:`fill_free`, :meth:`endpoint_map`, :meth:`sample_map`, :meth:`default_limits`, :meth:`reference_lines`,
    :meth:`auto_strategy`, :meth:`torque_model` (the joint torques of a motion: ``None`` by
    default, or the model registered with :func:`acroplan.register_torque_model`),
    :meth:`to_dict` / :meth:`from_dict`.
    """

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        _TYPES.setdefault(cls.__name__, cls)  # for from_dict; the first class of a name keeps it

    state_names: ClassVar[tuple[str, ...]]
    input_names: ClassVar[tuple[str, ...]]
    param_names: ClassVar[tuple[str, ...]] = ()
    #: inputs that are the time derivative of a state: ``{"u": "phi"}`` means u = d(phi)/dt.
    rate_inputs: ClassVar[dict[str, str]] = {}
    #: states that are angles (in radians): ``degrees=True`` converts these.
    angle_states: ClassVar[tuple[str, ...]] = ()
    #: Compile the fields in heyoka's compact mode (functions for the Taylor coefficients instead of
    #: unrolled code): compiles deep fields (a spatial body's rotations and adjugate) in seconds
    #: where full mode takes many minutes, at some cost per step.
    compact_mode: ClassVar[bool] = False

    # ------------------------------------------------------------------ structure
    @property
    def structure_key(self) -> Hashable:
        """What the symbolic fields depend on besides parameter values.

        Default: the class and its names (every instance of a class has the same structure).
        Systems whose structure varies per instance (number of links, topology) override it.
        """
        return (type(self).__module__, type(self).__qualname__, tuple(self.state_names),
                tuple(self.input_names), tuple(self.param_names))

    # ------------------------------------------------------------------ symbolic definition
    @abc.abstractmethod
    def symbolic_fields(self, x: tuple[sp.Symbol, ...], p: tuple[sp.Symbol, ...]) -> tuple[sp.Matrix, sp.Matrix]:
        """Drift and input fields in sympy.

        Parameters
        ----------
        x : tuple of sympy.Symbol, length n
            State symbols, in :attr:`state_names` order.
        p : tuple of sympy.Symbol, length n_p
            Parameter symbols, in :attr:`param_names` order.

        Returns
        -------
        f : sympy.Matrix, shape (n, 1)
        G : sympy.Matrix, shape (n, m)
        """

    @classmethod
    def taylor_fields(cls, x, p):
        """The fields of :meth:`symbolic_fields` written directly as heyoka expressions of the
        state variables ``x`` and the parameters ``p`` (``heyoka.par[i]``), or ``None`` (the default:
        the compiled integrator converts the sympy fields). A family with small fields may give them
        to spare sympy's import at start-up; they must be the very expressions ``heyoka.from_sympy``
        makes of the sympy fields (the same compiled code, the same on-disk cache entry).

        Returns
        -------
        (f, G) : list, list of lists
            ``f[r]`` and ``G[r][j]``: a heyoka expression, or ``None`` where the field is zero.
        """
        return None

    def symbols(self) -> tuple[tuple[sp.Symbol, ...], tuple[sp.Symbol, ...]]:
        """The state and parameter symbols used by :meth:`symbolic`."""
        x = tuple(sp.Symbol(name, real=True) for name in self.state_names)
        p = tuple(sp.Symbol(name, real=True) for name in self.param_names)
        return x, p

    def symbolic(self) -> tuple[sp.Matrix, sp.Matrix]:
        """``(f, G)`` in the symbols of :meth:`symbols`, cached per :attr:`structure_key`."""
        key = self.structure_key
        out = _SYMBOLIC.get(key)
        if out is None:
            x, p = self.symbols()
            f, G = self.symbolic_fields(x, p)
            f = sp.Matrix(f).reshape(len(self.state_names), 1)
            G = sp.Matrix(G).reshape(len(self.state_names), len(self.input_names))
            with _LOCK:
                out = _SYMBOLIC.setdefault(key, (f, G))
        return out

    @property
    def symbolic_ready(self) -> bool:
        """Whether :meth:`symbolic` is already built for this structure (in this process)."""
        return self.structure_key in _SYMBOLIC

    def _numeric(self):
        key = self.structure_key
        fn = _NUMERIC.get(key)
        if fn is None:
            x, p = self.symbols()
            f, G = self.symbolic()
            # the right-hand side x' = f + G u, with u as extra symbols
            u = tuple(sp.Symbol(f"_u{j}", real=True) for j in range(len(self.input_names)))
            rhs = f + G * sp.Matrix(u)
            fn = sp.lambdify((x, u, p), list(rhs), modules="numpy")
            with _LOCK:
                fn = _NUMERIC.setdefault(key, fn)
        return fn

    # ------------------------------------------------------------------ numeric interface
    @property
    def n_states(self) -> int:
        return len(self.state_names)

    @property
    def n_inputs(self) -> int:
        return len(self.input_names)

    @property
    def ndx(self) -> int:
        """Dimension of the tangent space (of :meth:`diff`'s result); ``n_states`` by default."""
        return self.n_states

    @property
    def params(self) -> np.ndarray:
        """Parameter values, shape ``(n_p,)``, in :attr:`param_names` order."""
        return np.array(self._param_tuple, dtype=float)

    @property
    def _param_tuple(self) -> tuple:
        """:attr:`params` as a tuple of floats (systems are immutable: computed once)."""
        cached = self.__dict__.get("_acroplan_params")
        if cached is None:
            cached = tuple(float(getattr(self, name)) for name in self.param_names)
            object.__setattr__(self, "_acroplan_params", cached)
        return cached

    def rhs(self, x, u) -> np.ndarray:
        """Right-hand side :math:`f(x) + G(x) u`.

        Parameters
        ----------
        x : array_like, shape (n,) or (n, N)
        u : array_like, shape (m,) or (m, N)

        Returns
        -------
        numpy.ndarray, shape (n,) or (n, N)
        """
        x = np.asarray(x, dtype=float)
        u = np.asarray(u, dtype=float)
        if x.ndim == 1:  # one state (the checking integrator's every call): plain floats, no broadcasting
            return np.array(self._numeric()(tuple(x.tolist()), tuple(u.reshape(-1).tolist()), self._param_tuple),
                            dtype=float)
        out = self._numeric()(tuple(x), tuple(u), self._param_tuple)
        shape = x.shape
        return np.array([np.broadcast_to(np.asarray(v, dtype=float), shape[1:]) for v in out])

    # ------------------------------------------------------------------ the state space
    def diff(self, x0, x1) -> np.ndarray:
        """The tangent vector :math:`x_1 \\ominus x_0` that :meth:`retract` maps back:
        ``retract(x0, diff(x0, x1)) == x1``. Euclidean by default: ``x1 - x0``.

        Every state difference the planner takes (endpoint residuals, errors, continuation
        paths, verification) goes through it, so a system on a manifold (a unit quaternion)
        overrides this and :meth:`retract`.

        Parameters
        ----------
        x0, x1 : array_like, shape (n,)

        Returns
        -------
        numpy.ndarray, shape (ndx,)
        """
        return np.asarray(x1, dtype=float) - np.asarray(x0, dtype=float)

    def retract(self, x, dx) -> np.ndarray:
        """The state reached from ``x`` along the tangent vector ``dx`` (Euclidean: ``x + dx``).

        Parameters
        ----------
        x : array_like, shape (n,)
        dx : array_like, shape (ndx,)

        Returns
        -------
        numpy.ndarray, shape (n,)
        """
        return np.asarray(x, dtype=float) + np.asarray(dx, dtype=float)

    def tangent_jacobian(self, x, J) -> np.ndarray:
        """A Jacobian of the state with respect to anything, ``(n, k)``, as a Jacobian of the
        tangent coordinates of :meth:`diff` at ``x``, ``(ndx, k)`` (the identity by default)."""
        return J

    def error(self, x, target) -> float:
        """:math:`\\|\\mathrm{diff}(x, \\mathrm{target})\\|_2`, the distance the planner reports."""
        d = self.diff(x, target)
        return float(np.sqrt(d @ d))

    # ------------------------------------------------------------------ family hooks
    def check_segment(self, x0: np.ndarray, x1: np.ndarray, duration: float, limits=None) -> Infeasibility | None:
        """Exact feasibility test of steering ``x0`` to ``x1`` in ``duration``.

        Returns ``None`` when the segment may be feasible (or no test is known), else an
        :class:`Infeasibility` that proves it is not. ``limits`` is a
        :class:`~acroplan.core.limits.Limits` or ``None``. The default knows no test.
        """
        return None

    def continuation_path(self, y0, x1, x0, duration):
        """The target path :math:`\\pi(\\tau)`, :math:`\\tau \\in [0, 1]`, from ``y0`` (the start input's
        endpoint) to ``x1``, for path deformation. Default: the geodesic
        :math:`\\mathrm{retract}(y_0, \\tau\\,\\mathrm{diff}(y_0, x_1))` (a straight segment in a
        Euclidean state space).

        Returns
        -------
        callable
            ``pi(tau) -> numpy.ndarray, shape (n,)``.
        """
        y0 = np.asarray(y0, dtype=float)
        d = self.diff(y0, x1)
        return lambda tau: self.retract(y0, tau * d)

    #: the name of the family's own independent check (:meth:`family_errors`), for messages; empty
    #: when the family cannot run it here (a body's Pinocchio check without Pinocchio): plans are
    #: then re-simulated by DOP853 and ``verification`` says ``"ode"``
    family_check: ClassVar[str] = ""

    def family_errors(self, x0, segments):
        """The family's own independent check of planned segments, or ``None`` when it has none
        (the default: then plans are checked by the DOP853 re-simulation of the same fields). It
        must not use the compiled integrator nor the sympy fields the planner used: a closed form
        or a conserved quantity (the acrobot's flat-output identity), or another library's model
        of the body (Pinocchio's centroidal momentum for articulated bodies).

        Parameters
        ----------
        x0 : numpy.ndarray, shape (n,)
            The first waypoint; the segments are chained from it.
        segments : sequence of SegmentResult

        Returns
        -------
        numpy.ndarray, shape (len(segments),), or None
            Each segment's distance from its target state.
        """
        return None

    def fill_free(self, x0, x1, guess, duration: float, limits=None, after=None) -> np.ndarray:
        """Choose the free states (NaN) of the waypoint ``x1`` reached from ``x0`` in ``duration``.

        ``guess`` holds the linear interpolation of the neighbouring waypoints' values; the default
        takes it. ``after`` is ``(x2, duration2)``, the next waypoint when it is fully given. A
        family may choose better (the acrobot puts a free ``theta`` in the middle of the values
        that are both reachable from ``x0`` and reach ``x2``).

        Returns
        -------
        numpy.ndarray, shape (n,)
        """
        x1 = np.asarray(x1, dtype=float)
        return np.where(np.isnan(x1), guess, x1)

    def default_limits(self):
        """The limits a plan honours when the caller gives none (a URDF's joint ranges and rates):
        a :class:`~acroplan.core.limits.Limits`, or ``None`` (the default: no limits)."""
        return None

    def state_unit(self, state: str) -> str:
        """The unit of ``state`` on figures: ``"rad"`` for the :attr:`angle_states`, ``""`` for the
        others by default (abstract coordinates); a family overrides it."""
        return "rad" if state in self.angle_states else ""

    def display_states(self, X, *, degrees: bool = False) -> list[tuple[str, np.ndarray, str, str | None]]:
        """What a figure of the states draws (:func:`~acroplan.core.plotting.plot_states`): one
        ``(label, values, unit, state)`` per panel from states ``X`` (shape (n, N), columns at
        times), ``state`` the state it shows or ``None`` for a coordinate made from several (its
        limits and reference lines are the state's). By default each state as it is
        (``degrees``: angles in ``"rad"`` shown in degrees); a family with better coordinates
        overrides it (a spatial body's attitude as Yeadon's angles)."""
        X = np.asarray(X, dtype=float)
        out = []
        for i, name in enumerate(self.state_names):
            unit = self.state_unit(name)
            if degrees and unit == "rad":
                out.append((name, np.degrees(X[i]), "deg", name))
            else:
                out.append((name, X[i], unit, name))
        return out

    def reference_lines(self, state: str, lo: float, hi: float) -> list[tuple[float, str]]:
        """Values of ``state`` worth marking on plots between ``lo`` and ``hi``, with labels (the
        acrobot's straight and folded body). None by default."""
        return []

    def auto_strategy(self):
        """The strategy ``method="auto"`` uses for this system: a
        :class:`~acroplan.core.strategies.Strategy`, or ``None`` for the core's default, path
        deformation with the basis sizes 6, 10 and 14 and 100 evaluations per size
        (:data:`acroplan.core.strategies.AUTO_DEFAULT`). A family with better knowledge (a flat
        output, a good first guess) overrides it."""
        return None

    def endpoint_map(self, basis, x0, T: float, c):
        """The family's own endpoint map and its Jacobian on one segment, or ``None`` (the default):
        then :func:`acroplan.core.backend.endpoint` integrates the fields and their variational
        equations with the compiled Taylor integrator.

        A family overrides it when it knows a faster integration that is as exact (the spatial
        bodies: only the attitude is integrated, by Gauss collocation, the joint angles being
        polynomials of time). It must return what :func:`~acroplan.core.backend.endpoint` returns,
        ``(xT, J)`` with ``xT`` of shape ``(n,)`` and ``J`` of shape ``(n, m * basis.n)``
        (:math:`\\partial x(T)/\\partial c`, flattened ``c``), and raise
        :class:`~acroplan.core.backend.IntegrationError` when it cannot integrate the input.

        Parameters
        ----------
        basis : InputBasis
        x0 : array_like, shape (n,)
        T : float
        c : array_like, shape (m, basis.n) or (m * basis.n,)
        """
        return None

    def sample_map(self, basis, x0, T: float, c, s):
        """The family's own states at normalised times ``s`` of one segment (what
        :func:`acroplan.core.backend.sample` returns, shape ``(n, len(s))``), or ``None`` (the
        default: the compiled Taylor integrator's dense output)."""
        return None

    def prepare_endpoint_map(self) -> bool:
        """Compile what :meth:`endpoint_map` needs (:func:`acroplan.warm_up`); ``True`` when the
        family has its own map, ``False`` (the default) when it uses the compiled Taylor integrator."""
        return False

    def torque_model(self):
        """The joint torques of a planned motion, or ``None`` when none are known (the default, for
        kinematic systems and bodies given without their masses and inertias). Default: the model
        registered for the class (:func:`register_torque_model`), else ``None``.

        A torque model is an object with

        * ``joint_names``: tuple of str, one per torque row, each the name of an input or of a state
          whose rate is an input (:attr:`rate_inputs`): torque row :math:`j` is the torque of the
          joint that input :math:`i(j)` drives, and its mechanical power is
          :math:`\\tau_j u_{i(j)}`;
        * ``unsupported(system) -> str | None``: why it cannot give this system's torques;
        * ``__call__(system, basis, x0, T, c, s)``: the torques of the motion that input
          coefficients ``c`` (shape ``(m, basis.n)``, in ``basis``) produce from state ``x0`` in time
          ``T``, at normalised times ``s`` (shape ``(K,)``, in [0, 1]): ``tau`` of shape ``(p, K)``,
          or ``(tau, jacobian)`` with ``jacobian`` = :math:`\\partial\\tau/\\partial c`, shape
          ``(p, K, m * basis.n)`` (flattened ``c``; by forward differences when not given);
        * optionally ``torques(system, basis, x0, T, c, s)``: ``tau`` alone, shape ``(p, K)``, without
          the Jacobian (what results and sweeps ask for; :func:`model_torques` falls back on
          ``__call__``).

        Used by :meth:`PlanResult.torques <acroplan.core.result.PlanResult.torques>`,
        :meth:`PlanResult.effort <acroplan.core.result.PlanResult.effort>`, ``objective="torque"``
        and ``tau_max`` (:mod:`acroplan.core.optimal`).
        """
        prepare(self)  # the family registers its torque model (core.family.Family.setup)
        for cls in type(self).__mro__:
            factory = TORQUE_MODELS.get(cls)
            if factory is not None:
                return factory(self)
        return None

    def lumped(self) -> dict[str, float]:
        """Parameter values by name."""
        return {name: float(getattr(self, name)) for name in self.param_names}

    def to_dict(self) -> dict[str, Any]:
        """What a result file records of the system: its type and parameters (families add more)."""
        return {"type": type(self).__name__, "params": self.lumped()}

    @classmethod
    def from_dict(cls, data: dict) -> "ControlAffineSystem":
        """The system :meth:`to_dict` described. On the base class, dispatches on ``data["type"]``
        among the system classes imported so far; the default rebuilds from the parameters."""
        from .errors import InvalidInputError

        if cls is ControlAffineSystem:
            kind = data.get("type") if isinstance(data, dict) else None
            # a registered family's class of that name first, else a class defined so far
            target = registered_class(kind) if isinstance(kind, str) else None
            if target is None:
                target = _TYPES.get(kind)
            if target is None:
                system_classes()  # (every registered family imported, for the message)
                raise InvalidInputError("system.type", f"unknown system type {kind!r}",
                                        f"known types are {sorted(_TYPES)} (import the family first)")
            return target.from_dict(data)
        return cls(**dict(data.get("params", {})))

    # ------------------------------------------------------------------ the body's parameters (sweeps)
    def robot_parameters(self) -> dict[str, Any]:
        """The body's parameters by the names a sweep's ``robot.NAME`` fields give them.

        Default: the lumped parameters (:meth:`lumped`). A family whose bodies are given by other
        quantities (the acrobot's masses, inertias and lengths) returns those.
        """
        return self.lumped()

    def with_robot_parameters(self, **values) -> "ControlAffineSystem":
        """A system like this one with the parameters ``values`` (names of
        :meth:`robot_parameters`) changed.

        Default: rebuilt through :meth:`to_dict` / :meth:`from_dict` with the lumped parameters
        replaced.

        Raises
        ------
        InvalidInputError
            A value the body refuses, naming the parameter.
        """
        record = self.to_dict()
        record["params"] = {**dict(record.get("params", {})), **values}
        return type(self).from_dict(record)

    def scaled(self, s: float) -> "ControlAffineSystem":
        """This body ``s`` times its size at the same density: lengths x s, masses x s^3, inertias
        x s^5 (a sweep's ``robot.scale``). Default: refused, for a system that does not say how its
        parameters scale.

        Raises
        ------
        InvalidInputError
            Naming ``robot.scale``.
        """
        from .errors import InvalidInputError

        raise InvalidInputError("robot.scale", f"{type(self).__name__} does not say how its parameters scale with "
                                "its size", "sweep its parameters (robot.NAME) instead")


def torque_model_of(system) -> tuple[Any, str | None]:
    """``(model, None)`` with the system's torque model (:meth:`ControlAffineSystem.torque_model`),
    or ``(None, why)`` when it has none or the model cannot serve it (its ``unsupported``)."""
    hook = getattr(system, "torque_model", None)
    model = hook() if callable(hook) else None
    if model is None:
        return None, (f"{type(system).__name__} gives no joint torques (its torque_model() is None: a kinematic "
                      "model, or a body given without its masses and inertias)")
    check = getattr(model, "unsupported", None)
    why = check(system) if callable(check) else None
    return (None, why) if why else (model, None)


def model_torques(model, system, basis, x0, T, c, s) -> np.ndarray:
    """The torques of a torque model (:meth:`ControlAffineSystem.torque_model`) without its
    Jacobian: its ``torques`` method when it has one, else the first part of its call.

    Returns
    -------
    numpy.ndarray, shape (p, K)
    """
    fast = getattr(model, "torques", None)
    out = fast(system, basis, x0, T, c, s) if callable(fast) else model(system, basis, x0, T, c, s)
    tau = out[0] if isinstance(out, tuple) else out
    return np.asarray(tau, dtype=float).reshape(-1, np.size(s))


def joint_inputs(system, model) -> tuple[int, ...]:
    """The input that drives each torque row of ``model``: row :math:`j` named ``joint_names[j]``
    belongs to the input of that name, or to the input that is the rate of the state of that name
    (:attr:`ControlAffineSystem.rate_inputs`: the acrobot's joint ``"phi"`` is driven by ``u``).

    Returns
    -------
    tuple of int, one input index per torque row

    Raises
    ------
    InvalidInputError
        A joint matches no input (the model and the system disagree).
    """
    from .errors import InvalidInputError

    names = tuple(getattr(model, "joint_names", ()) or ())
    inputs = tuple(system.input_names)
    by_state = {state: inp for inp, state in system.rate_inputs.items()}
    out = []
    for name in names:
        if name in inputs:
            out.append(inputs.index(name))
        elif name in by_state and by_state[name] in inputs:
            out.append(inputs.index(by_state[name]))
        else:
            raise InvalidInputError("torque_model.joint_names", f"joint {name!r} is neither an input of "
                                    f"{type(system).__name__} {list(inputs)} nor a state whose rate is one "
                                    f"{sorted(by_state)}", "name each torque row after its input or its joint's state")
    return tuple(out)
