"""The records of one plan's parts: :class:`SegmentResult` (one per segment: its input, exact in
its basis, the solver's diagnostics, the independent check) and :class:`Samples` (a sampled
trajectory), with the helpers every result record shares (read-only arrays, JSON without
non-finite numbers)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from .basis import InputBasis

__all__ = ["SegmentResult", "Samples"]


def _freeze(obj, *names):
    """Store read-only copies of array fields, so a result cannot be changed after the fact."""
    for name in names:
        a = np.array(getattr(obj, name), dtype=float)
        a.setflags(write=False)
        object.__setattr__(obj, name, a)


def _same(a, b) -> bool:
    """Whether two field values are the same, bit for bit: arrays of the same shape and dtype with
    equal entries (NaN equal to NaN), floats likewise, tuples, lists and dicts entry by entry, any
    other value by ``==`` (by identity when its ``==`` gives no single truth value)."""
    if a is b:
        return True
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a, b = np.asarray(a), np.asarray(b)
        if a.shape != b.shape or a.dtype != b.dtype:
            return False
        try:
            return bool(np.array_equal(a, b, equal_nan=True))
        except TypeError:  # an array of objects: entry by entry
            return all(_same(x, y) for x, y in zip(a.ravel().tolist(), b.ravel().tolist()))
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (a != a and b != b)
    if isinstance(a, (tuple, list)) and isinstance(b, (tuple, list)):
        return type(a) is type(b) and len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b))
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    try:
        return bool(a == b)
    except (ValueError, TypeError):
        return False


def _same_fields(x, y):
    """Dataclass equality field by field with :func:`_same` (the fields with ``compare=True``):
    the ``__eq__`` of the result records, whose array fields made the generated one raise."""
    if x is y:
        return True
    if type(x) is not type(y):
        return NotImplemented
    return all(_same(getattr(x, f.name), getattr(y, f.name)) for f in dataclasses.fields(x) if f.compare)


def _json_safe(obj):
    """``obj`` with every non-finite float replaced by ``None`` (recursively)."""
    if isinstance(obj, float):
        return obj if np.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_json_safe(v) for v in obj]
    return obj


def _num(v):
    if v is None:
        return None
    v = float(v)
    return v if np.isfinite(v) else None


@dataclasses.dataclass(frozen=True)
class Samples:
    """A sampled trajectory.

    Attributes
    ----------
    t : numpy.ndarray, shape (N,)
    states : numpy.ndarray, shape (n, N)
    inputs : numpy.ndarray, shape (m, N)
    state_names, input_names : tuple of str
    torques : numpy.ndarray, shape (p, N), or None
        Joint torques :math:`\\tau_j(t)`, one row per joint of the system's torque model (``None``
        when the system has none, or when they were not asked for).
    power : numpy.ndarray, shape (p, N), or None
        Mechanical power :math:`\\tau_j(t)\\,u_{i(j)}(t)` of each joint.
    joint_names : tuple of str
        The rows of ``torques`` and ``power`` (empty without a torque model).

    States and inputs are also attributes by name: ``samples.theta``, ``samples.u``; torques and
    power as ``samples.tau_<joint>``, ``samples.power_<joint>`` (``samples.tau_phi``).
    """

    t: np.ndarray
    states: np.ndarray
    inputs: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    torques: np.ndarray | None = None
    power: np.ndarray | None = None
    joint_names: tuple[str, ...] = ()

    #: bit for bit, arrays and all (:func:`_same`); the generated ``==`` raised on the arrays
    __eq__ = _same_fields

    def __getattr__(self, name):
        names = object.__getattribute__(self, "state_names")
        if name in names:
            return self.states[names.index(name)]
        inames = object.__getattribute__(self, "input_names")
        if name in inames:
            return self.inputs[inames.index(name)]
        joints = object.__getattribute__(self, "joint_names")
        for prefix, field in (("tau_", "torques"), ("power_", "power")):
            if name.startswith(prefix) and name[len(prefix):] in joints:
                return object.__getattribute__(self, field)[joints.index(name[len(prefix):])]
        raise AttributeError(name)

    def columns(self) -> dict[str, np.ndarray]:
        """Every sampled quantity by column name: ``t``, the states, the inputs, then
        ``tau_<joint>`` and ``power_<joint>`` for each joint (when torques were sampled); each of
        shape (N,)."""
        out = {"t": self.t, **{n: self.states[i] for i, n in enumerate(self.state_names)},
               **{n: self.inputs[j] for j, n in enumerate(self.input_names)}}
        if self.torques is not None:
            out.update({f"tau_{n}": self.torques[k] for k, n in enumerate(self.joint_names)})
            out.update({f"power_{n}": self.power[k] for k, n in enumerate(self.joint_names)})
        return out


@dataclasses.dataclass(frozen=True)
class SegmentResult:
    """One segment :math:`[t_0, t_1]` of a plan.

    Attributes
    ----------
    index : int
        Position in the plan. A waypoint interval is one segment, or several pieces when a
        family's piecewise planner was used (the acrobot's flat output: move, dwell, move; up to
        seven pieces with a rate bound).
    interval : int
        The waypoint interval :math:`[t_k, t_{k+1}]` this segment belongs to.
    method : str
        How it was planned: ``"deform"`` (path deformation), ``"deform+limits"`` (then the
        constrained solve), or a family's own: the acrobot's ``"flat"`` (flat-output pieces),
        ``"flat-rate"`` (rate-limited flat-output pieces), ``"holonomic"`` (P0 = 0).
    t0, t1 : float
    coefficients : numpy.ndarray, shape (m, k)
        Power-basis coefficients in local time: :math:`u_j(t) = \\sum_i p_{j,i}(t - t_0)^i`.
    basis_coefficients : numpy.ndarray, shape (m, k)
        The same input in the planner's basis on :math:`s = (t - t_0)/(t_1 - t_0)` (for the
        Legendre basis accurate at every size; the power series loses digits from about 10
        coefficients on).
    basis : InputBasis or None
        The basis of ``basis_coefficients`` (its family and size).
    start, target : numpy.ndarray, shape (n,)
        Planned states at the segment's ends (waypoints, or interior points of a flat plan).
    max_abs_u : float
        :math:`\\max_j \\max |u_j|` on the segment, exact (roots of :math:`u'`); computed on first
        use when the plan had no limits.
    state_ranges : dict
        Exact range ``(lo, hi)`` of every bounded state on the segment (empty without bounds).
    state_range : tuple or None
        The range of the one bounded state, when exactly one state is bounded (the acrobot's
        ``phi``).
    final_error : float
        Endpoint error of the compiled integrator, :math:`\\|x(t_1) - x_{target}\\|_2`.
    verified_error : float or None
        The same from the independent scipy DOP853 re-simulation of the whole chained plan
        (``None`` when ``verify=False``).
    iterations, evaluations, restarts : int
    sigma_min : float
        Smallest singular value of the reduced endpoint Jacobian along the continuation.
    success : bool
    message : str
    history : tuple of (tau, residual, sigma_min, goal, reached)
    optimality : dict or None
        For a segment of an optimal plan (``objective=`` of :func:`acroplan.plan`,
        :mod:`acroplan.core.optimal`), its first-order optimality diagnostics: ``objective``
        (``"energy"`` or ``"torque"``), ``cost`` (the value minimised), ``integral_u2``, ``kkt``
        (the relative KKT residual) and ``kkt_tol`` (its target), ``kkt_converged``,
        ``ladder`` (``[[basis size, cost], ...]`` tried), ``converged_in_basis``, ``rtol``,
        ``converged`` (both), ``start``, ``solver``; through interior waypoints with free
        conditions, ``joint`` (whether the intervals' joint optimum was kept, and why:
        :meth:`acroplan.core.optimal.EnergyOptimal.joint`); ``None`` otherwise.
    """

    index: int
    t0: float
    t1: float
    coefficients: np.ndarray
    basis_coefficients: np.ndarray
    start: np.ndarray
    target: np.ndarray
    final_error: float
    verified_error: float | None
    iterations: int
    evaluations: int
    restarts: int
    sigma_min: float
    success: bool
    message: str
    history: tuple = ()
    interval: int = 0
    method: str = "deform"
    #: ``{"max_abs_u": float, "state_ranges": dict}`` when known at construction (the
    #: planner's limit checks); otherwise computed from the coefficients on first use
    extremes: dict | None = dataclasses.field(default=None, repr=False, compare=False)
    #: the segment's basis (family and size of ``basis_coefficients``)
    basis: InputBasis | None = dataclasses.field(default=None, repr=False)
    #: first-order optimality diagnostics of an optimal plan's segment (plain JSON types)
    optimality: dict | None = dataclasses.field(default=None, repr=False, compare=False)

    #: bit for bit, arrays and all (:func:`_same`); the generated ``==`` raised on the arrays
    __eq__ = _same_fields

    def __post_init__(self):
        _freeze(self, "coefficients", "basis_coefficients", "start", "target")

    def _extremes(self) -> dict:
        if self.extremes is None:
            from .basis import Monomial
            from .limits import input_extremes

            if self.basis is not None:
                basis, rows = self.basis, self.basis_coefficients
            else:  # power basis in local time -> in s
                k = self.coefficients.shape[1]
                basis, rows = Monomial(k), self.coefficients * (self.t1 - self.t0) ** np.arange(k)
            top = 0.0
            for row in rows:
                lo, hi = input_extremes(basis, row)
                top = max(top, abs(lo), abs(hi))
            # a lazily computed cache of values the coefficients fix (not part of equality)
            object.__setattr__(self, "extremes", {"max_abs_u": top, "state_ranges": {}})
        return self.extremes

    @property
    def max_abs_u(self) -> float:
        return self._extremes()["max_abs_u"]

    @property
    def state_ranges(self) -> dict:
        return dict(self._extremes()["state_ranges"])

    @property
    def state_range(self) -> tuple | None:
        r = self._extremes()["state_ranges"]
        return next(iter(r.values())) if len(r) == 1 else None

    def input(self, t) -> np.ndarray:
        """Inputs at times ``t`` in :math:`[t_0, t_1]`.

        Parameters
        ----------
        t : float or array_like, shape (N,)

        Returns
        -------
        numpy.ndarray, shape (m,) for a scalar ``t``, else (m, N)

        Evaluated from ``basis_coefficients`` in the segment's basis (for Legendre by the
        three-term recurrence), which stays accurate at every basis size; the power-basis
        ``coefficients`` lose digits to cancellation from about 10 coefficients on (measured:
        ``docs/design.md``).
        """
        scalar = np.ndim(t) == 0
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if self.basis is None:
            out = np.array([np.polynomial.polynomial.polyval(t - self.t0, row) for row in self.coefficients])
        else:
            out = self.basis_coefficients @ self.basis.matrix((t - self.t0) / (self.t1 - self.t0)).T
        return out[:, 0] if scalar else out

    @property
    def power_form_error(self) -> float:
        """How far the power-basis export :attr:`coefficients` strays from the exact input
        (:attr:`basis_coefficients`): :math:`\\max_t |u_{power}(t) - u(t)|` over all inputs, on 257
        points of the segment. Rounding level up to about 10 coefficients; it grows beyond."""
        if self.basis is None:
            return 0.0
        t = np.linspace(self.t0, self.t1, 257)
        power = np.array([np.polynomial.polynomial.polyval(t - self.t0, row) for row in self.coefficients])
        return float(np.max(np.abs(power - self.input(t))))

    def __repr__(self):
        return (f"SegmentResult(index={self.index}, t=[{self.t0:g}, {self.t1:g}], method={self.method!r}, "
                f"success={self.success}, final_error={self.final_error:.2e}, "
                f"n_coefficients={self.basis_coefficients.shape[1]})")

    def _input_scalar(self, t: float) -> list:
        """:meth:`input` at one absolute time, in plain Python arithmetic (:meth:`_input_s`)."""
        return self._input_s((t - self.t0) / (self.t1 - self.t0))

    def _input_s(self, s: float) -> list:
        """The inputs at normalised time ``s`` in plain Python arithmetic (Clenshaw's recurrence for
        the Legendre basis, Horner's otherwise): the independent re-simulation calls it for every
        right-hand side, where numpy's per-call overhead would dominate."""
        if self.basis is None or self.basis.name not in ("legendre", "monomial"):
            return [float(v) for v in self.input([self.t0 + s * (self.t1 - self.t0)])[:, 0]]
        out = []
        for row in self.basis_coefficients.tolist():
            if self.basis.name == "monomial":
                v = 0.0
                for ck in reversed(row):
                    v = v * s + ck
            elif len(row) == 1:
                v = row[0]
            else:  # numpy's legval, scalar
                x = 2.0 * s - 1.0
                nd = len(row)
                c0, c1 = row[-2], row[-1]
                for i in range(3, len(row) + 1):
                    tmp = c0
                    nd -= 1
                    c0 = row[-i] - (c1 * (nd - 1)) / nd
                    c1 = tmp + (c1 * x * (2 * nd - 1)) / nd
                v = c0 + c1 * x
            out.append(v)
        return out

    def to_dict(self, input_names, state_names=None) -> dict[str, Any]:
        """The segment as plain JSON types (``state_names`` adds its ``start`` and ``target``)."""
        ends = {} if state_names is None else {
            "start": {n: float(v) for n, v in zip(state_names, self.start)},
            "target": {n: float(v) for n, v in zip(state_names, self.target)}}
        return {
            "index": self.index,
            "interval": self.interval,
            "method": self.method,
            "t0": self.t0,
            "t1": self.t1,
            **ends,
            "basis_coefficients": {name: list(map(float, row))
                                   for name, row in zip(input_names, self.basis_coefficients)},
            "coefficients": {name: list(map(float, row)) for name, row in zip(input_names, self.coefficients)},
            "power_form_error": self.power_form_error,
            "success": self.success,
            "message": self.message,
            "final_error": _num(self.final_error),
            "verified_error": _num(self.verified_error),
            "iterations": self.iterations,
            "evaluations": self.evaluations,
            "restarts": self.restarts,
            "sigma_min": _num(self.sigma_min),
            "max_abs_u": _num(self.max_abs_u),
            "state_range": None if self.state_range is None else [float(v) for v in self.state_range],
            "state_ranges": {k: [float(v) for v in r] for k, r in self.state_ranges.items()},
            **({} if self.optimality is None else {"optimality": _json_safe(dict(self.optimality))}),
        }


