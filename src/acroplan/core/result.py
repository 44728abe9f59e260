"""The result types of the core: :class:`Status`, :class:`PlanResult` (one per plan),
:class:`SegmentResult` (one per segment) and :class:`Samples` (a sampled trajectory), both from
:mod:`acroplan.core.segment`, and :class:`JointEffort` (the effort of one joint over a plan).

Every result is built with keywords and frozen: its arrays are read-only copies.

Effort
------
When the system has a torque model (:meth:`ControlAffineSystem.torque_model`; the core names no
body), a plan also gives its joint torques :math:`\\tau_j(t)` and mechanical power
:math:`\\tau_j(t)\\,u_{i(j)}(t)` (torque row :math:`j` belongs to input :math:`i(j)`:
:func:`~acroplan.core.system.joint_inputs`): :meth:`PlanResult.torques`, the columns
``tau_<joint>`` and ``power_<joint>`` of :meth:`PlanResult.evaluate` and
:meth:`PlanResult.to_pandas`, and the summary :meth:`PlanResult.effort` (in
:meth:`PlanResult.to_dict` as ``effort``; computed in :mod:`acroplan.core.effort`, whose
:class:`JointEffort` and :data:`EFFORT_RULE` are re-exported here). Without a torque model nothing
of this appears.
"""

from __future__ import annotations

import dataclasses
import json
from typing import Any

import numpy as np

from . import backend
from .basis import InputBasis, basis_tables
from .effort import EFFORT_RULE, JointEffort, effort_summary
from .errors import InvalidInputError
from .progress import stage
from .segment import Samples, SegmentResult, _freeze, _json_safe, _num, _same_fields
from .status import STATUSES, Status
from .system import ControlAffineSystem, joint_inputs, model_torques, torque_model_of

__all__ = ["PlanResult", "SegmentResult", "Samples", "Status", "STATUSES", "JointEffort", "EFFORT_RULE"]


class PendingWarning:
    """A warning of :attr:`PlanResult.warnings` whose text is worked out when the warnings are first
    read: ``function(result, *args) -> str``, run with BLAS held at one thread
    (:func:`acroplan.core.blas.one_blas_thread`, so that its numbers are the same bits whoever reads
    them), then kept in the result. A plan makes one for a warning whose numbers cost more than the
    plan (the exact peak torque and power of :func:`acroplan.planning.plausibility`: 1.2 ms against
    the 1.5 ms a flagged two-link plan takes; the exact peak rate, 0.15 ms, when a sample already
    flags the plan), so that plans whose warnings nobody reads, in :func:`acroplan.plan_many`, do
    not pay for them. ``function`` is a module-level function (a
    result with a pending warning pickles, and the warning is worked out where it is read)."""

    __slots__ = ("function", "args")

    def __init__(self, function, args: tuple = ()):
        self.function, self.args = function, tuple(args)

    def __reduce__(self):
        return PendingWarning, (self.function, self.args)

    def __repr__(self):
        return f"PendingWarning({getattr(self.function, '__qualname__', self.function)})"


class _Warnings:
    """The descriptor of :attr:`PlanResult.warnings` (a dataclass field whose default is a
    descriptor): set, it keeps a tuple of str and :class:`PendingWarning`; read, it works out the
    pending ones once and gives a tuple of str."""

    def __set_name__(self, owner, name):
        self.held = f"_{name}_held"

    def __get__(self, obj, owner=None):
        if obj is None:
            return ()  # the field's default
        held = obj.__dict__.get(self.held)
        if held is None:  # a result pickled before the warnings had this descriptor kept them by name
            held = obj.__dict__[self.held] = tuple(obj.__dict__.get("warnings", ()))
        if any(isinstance(w, PendingWarning) for w in held):
            from .blas import one_blas_thread

            with one_blas_thread():
                held = tuple(w.function(obj, *w.args) if isinstance(w, PendingWarning) else w for w in held)
            obj.__dict__[self.held] = held
        return held

    def __set__(self, obj, value):
        obj.__dict__[self.held] = tuple(w if isinstance(w, PendingWarning) else str(w) for w in value)


_BASIS_NOTE = {
    "legendre": "u(t) = sum_i b_i P_i(2 s - 1), s = (t - t0) / (t1 - t0), P_i the Legendre polynomials: "
                "accurate at every size (the power basis loses digits from about 10 coefficients on)",
    "monomial": "u(t) = sum_i b_i s^i, s = (t - t0) / (t1 - t0)",
}


@dataclasses.dataclass(frozen=True)
class PlanResult:
    """Result of :func:`acroplan.plan`.

    Attributes
    ----------
    status : Status
        ``"success"``, ``"infeasible"`` (proven impossible; see :attr:`infeasible`) or
        ``"not_converged"`` (the planner failed; diagnostics in :attr:`segments`); a
        :class:`Status`, equal to its string.
    message : str
    system : ControlAffineSystem
    times : numpy.ndarray, shape (K+1,)
    waypoints : numpy.ndarray, shape (K+1, n)
    conditions : str
    basis : InputBasis
    segments : tuple of SegmentResult
        The segments planned (all K on success; on failure those done and the failed one).
    infeasible : tuple of dict
        Per infeasible segment: ``index``, ``field``, ``interval`` and ``reason``.
    verified : bool
        Whether the plan was checked independently.
    limits : Limits or None
        The limits the plan honours.
    verification : {"family", "ode"} or None
        How it was checked: the family's own independent check (the acrobot's flat-output
        identity, Pinocchio for articulated bodies), or the DOP853 re-simulation.
    objective : {"energy", "torque"} or None
        What the plan minimises (``objective=`` of :func:`acroplan.plan`; ``None``: a feasible
        plan, no cost minimised). Each segment's :attr:`SegmentResult.optimality` says how well.
    torque_limits : dict or None
        The torque limits the plan honours, ``{joint: tau_max}`` (``tau_max=`` of :func:`acroplan.plan`).
    warnings : tuple of str
        Why a successful plan may not be a motion to use, each a short sentence with its numbers
        (:func:`acroplan.planning.plausibility`: a peak joint rate far beyond what the waypoints
        imply, with the peak torque and power); empty when nothing is suspect. The message says
        how many there are; every one is in :meth:`to_dict` (``solution.json``). A warning whose
        numbers cost more than the plan (the exact peak rate, torque and power) is worked out when
        the warnings are first read, then kept (:class:`PendingWarning`).

    Methods: :meth:`evaluate` (states, inputs, and torques and power), :meth:`sample`,
    :meth:`to_dict`, :meth:`to_json`, :meth:`to_pandas`, :meth:`plot`. When the system has a torque
    model (:meth:`ControlAffineSystem.torque_model`), the plan also gives its joint torques and
    mechanical power: :meth:`torques` (``(tau, power)``, each of shape (N, p), power
    :math:`\\tau_j u_{i(j)}` with the input driving joint :math:`j`), :meth:`effort` (per joint a
    :class:`acroplan.JointEffort`: peak torque and power, positive and net work,
    :math:`\\int\\tau^2 dt`, :math:`\\int u^2 dt`), the ``tau_<joint>`` and ``power_<joint>``
    columns of :meth:`evaluate` and :meth:`to_pandas`, the ``effort`` block of :meth:`to_dict` and
    ``plot("effort")``; without one, none of these appear.

    Two results are equal (``==``) when every field is the same, bit for bit (arrays entry by entry,
    NaN equal to NaN): the same request planned twice on one machine gives equal results. So are
    two :class:`SegmentResult` and two :class:`Samples`.
    """

    status: Status
    message: str
    system: ControlAffineSystem
    times: np.ndarray
    waypoints: np.ndarray
    conditions: str
    basis: InputBasis
    segments: tuple[SegmentResult, ...] = ()
    infeasible: tuple[dict, ...] = ()
    verified: bool = False
    limits: object = None
    verification: str | None = None
    objective: str | None = None
    torque_limits: dict | None = None
    warnings: tuple[str, ...] = _Warnings()
    #: the effort summary, computed on first use (a cache of values the segments fix)
    _effort: dict | None = dataclasses.field(default=None, init=False, repr=False, compare=False)

    #: bit for bit, arrays and all (:func:`acroplan.core.segment._same`): two plans of the same
    #: request on one machine are equal; the generated ``==`` raised on the arrays
    __eq__ = _same_fields

    def __post_init__(self):
        _freeze(self, "times", "waypoints")
        object.__setattr__(self, "status", Status(self.status))

    @property
    def success(self) -> bool:
        return self.status is Status.SUCCESS

    @property
    def evaluations(self) -> int:
        """Endpoint-and-Jacobian evaluations over all segments."""
        return sum(s.evaluations for s in self.segments)

    @property
    def max_abs_u(self) -> float | None:
        """:math:`\\max |u|` over the whole plan, exact (``None`` without segments)."""
        return max((s.max_abs_u for s in self.segments), default=None)

    @property
    def state_ranges(self) -> dict:
        """Exact range ``(lo, hi)`` of every bounded state over the whole plan."""
        out: dict = {}
        for seg in self.segments:
            for name, (lo, hi) in seg.state_ranges.items():
                a, b = out.get(name, (lo, hi))
                out[name] = (min(a, lo), max(b, hi))
        return out

    def __repr__(self):
        worst = max((s.final_error for s in self.segments), default=float("nan"))
        return (f"PlanResult(status={self.status.value!r}, segments={len(self.segments)}, "
                f"t=[{self.times[0]:g}, {self.times[-1]:g}], max_final_error={worst:.2e}, "
                f"verification={self.verification!r}, system={type(self.system).__name__})")

    def _repr_html_(self) -> str:
        import html

        rows = "".join(
            f"<tr><td>{s.index}</td><td>[{s.t0:.4g}, {s.t1:.4g}]</td><td>{html.escape(s.method)}</td>"
            f"<td>{s.basis_coefficients.shape[1]}</td><td>{s.final_error:.2e}</td>"
            f"<td>{'' if s.verified_error is None else f'{s.verified_error:.2e}'}</td>"
            f"<td>{s.max_abs_u:.4g}</td><td>{s.evaluations}</td></tr>" for s in self.segments[:50])
        more = f"<p>... and {len(self.segments) - 50} more segments</p>" if len(self.segments) > 50 else ""
        colour = {"success": "#1a7f37", "infeasible": "#9a6700", "not_converged": "#cf222e"}[self.status.value]
        return (f"<div><b>PlanResult</b> of {html.escape(type(self.system).__name__)}: "
                f"<b style='color:{colour}'>{self.status.value}</b><br><small>{html.escape(self.message)}</small>"
                + "".join(f"<br><small style='color:#9a6700'>warning: {html.escape(w)}</small>" for w in self.warnings)
                + f"<table><tr><th>segment</th><th>t</th><th>method</th><th>coefficients</th><th>final error</th>"
                f"<th>verified error</th><th>max |u|</th><th>evaluations</th></tr>{rows}</table>{more}</div>")

    # ------------------------------------------------------------------ evaluation
    def evaluate(self, t, *, effort: bool = True) -> Samples:
        """States and inputs at times ``t`` (within the planned segments), and the joint torques and
        power when the system has a torque model.

        States are integrated by the compiled integrator from each segment's start waypoint; torques
        come from the torque model on each segment (:meth:`torques`). At a time two segments share,
        the earlier segment's values are given.

        Parameters
        ----------
        t : array_like, shape (N,)
        effort : bool
            Also sample torques and power (when the system has a torque model); ``False`` skips them.

        Returns
        -------
        Samples
            With ``torques``, ``power`` (shape (p, N)) and ``joint_names`` when the system has a
            torque model and ``effort`` is true.
        """
        if not self.segments:
            raise ValueError("this result has no planned segments to evaluate")
        t = np.atleast_1d(np.asarray(t, dtype=float))
        lo, hi = self.segments[0].t0, self.segments[-1].t1
        if np.any(t < lo) or np.any(t > hi) or not np.all(np.isfinite(t)):
            raise ValueError(f"t: every time must lie in the planned span [{lo}, {hi}]")
        bounds = np.array([s.t1 for s in self.segments])
        which = np.minimum(np.searchsorted(bounds, t, side="left"), len(self.segments) - 1)
        states = np.empty((self.system.n_states, t.size))
        inputs = np.empty((self.system.n_inputs, t.size))
        with stage("sampling", len(self.segments), unit="segment", show=len(self.segments) > 1) as st:
            for k, seg in enumerate(self.segments):
                idx = np.nonzero(which == k)[0]
                if idx.size:
                    T = seg.t1 - seg.t0
                    s = (t[idx] - seg.t0) / T
                    uniq, inverse = np.unique(s, return_inverse=True)
                    grid = uniq if uniq[0] == 0.0 else np.concatenate([[0.0], uniq])
                    X = backend.sample(self.system, self.basis_for(seg), seg.start, T, seg.basis_coefficients, grid)
                    states[:, idx] = X[:, grid.size - uniq.size:][:, inverse]
                    inputs[:, idx] = seg.input(t[idx])
                st.update()
        extra = {}
        if effort and self.has_torques:
            model, names, _ = self._torque_setup()
            tau, power = self._torque_values(model, t)
            extra = dict(torques=tau, power=power, joint_names=names)
        return Samples(t, states, inputs, self.system.state_names, self.system.input_names, **extra)

    # ------------------------------------------------------------------ effort
    @property
    def has_torques(self) -> bool:
        """Whether the system gives joint torques (:meth:`ControlAffineSystem.torque_model`)."""
        return torque_model_of(self.system)[0] is not None

    def _torque_setup(self):
        """``(model, joint_names, input indices)``, or :class:`InvalidInputError` saying why not."""
        model, why = torque_model_of(self.system)
        if model is None:
            raise InvalidInputError("system", why, "torques need a body with its masses and inertias (for example "
                                    "Acrobot.from_physical)")
        names = tuple(model.joint_names)
        return model, names, joint_inputs(self.system, model)

    def _segment_torques(self, model, seg, t, inputs):
        """``(tau, power)`` of ``seg`` at absolute times ``t`` inside it, each shape (p, K)."""
        T = seg.t1 - seg.t0
        s = (np.asarray(t, dtype=float) - seg.t0) / T
        basis, c = self.basis_for(seg), np.asarray(seg.basis_coefficients, dtype=float)
        tau = model_torques(model, self.system, basis, np.asarray(seg.start, dtype=float), T, c, s)
        if tau.shape[0] != len(inputs):
            raise InvalidInputError("torque_model", f"gave {tau.shape[0]} torque row(s) for {len(inputs)} joint "
                                    "name(s)", "give one joint name per torque row")
        # the inputs as seg.input(t) gives them, from the basis tables the model has just used (cached)
        u = c[list(inputs)] @ basis_tables(basis, s)[0].T
        return tau, tau * u

    def _torque_values(self, model, t):
        """``(tau, power)`` at sorted or unsorted absolute times ``t`` (shape (N,)), each (p, N)."""
        _, names, inputs = self._torque_setup()
        if not self.segments:
            raise InvalidInputError("result", "has no planned segments", "plan a motion first")
        lo, hi = self.segments[0].t0, self.segments[-1].t1
        if not np.all(np.isfinite(t)) or np.any(t < lo) or np.any(t > hi):
            raise InvalidInputError("t", f"every time must lie in the planned span [{lo}, {hi}]",
                                    "give times inside it")
        bounds = np.array([s.t1 for s in self.segments])
        which = np.minimum(np.searchsorted(bounds, t, side="left"), len(self.segments) - 1)
        tau, power = np.empty((len(names), t.size)), np.empty((len(names), t.size))
        with stage("torques", len(self.segments), unit="segment", show=len(self.segments) > 1) as st:
            for k, seg in enumerate(self.segments):
                idx = np.flatnonzero(which == k)
                if idx.size:
                    tau[:, idx], power[:, idx] = self._segment_torques(model, seg, t[idx], inputs)
                st.update()
        return tau, power

    def torques(self, t):
        """Joint torques and mechanical power at times ``t``.

        Torque row :math:`j` is the joint ``joint_names[j]`` of the system's torque model
        (:meth:`ControlAffineSystem.torque_model`), driven by input :math:`i(j)`: the input of that
        name, or the input that is the rate of the state of that name (the acrobot's joint
        ``"phi"`` by :math:`u = \\dot\\varphi`; :func:`~acroplan.core.system.joint_inputs`). Its
        power is :math:`P_j = \\tau_j\\,u_{i(j)}`. Each segment's torque comes from its own
        coefficients, exactly as the model computes it (no sampling in between); at a time two
        segments share, the earlier segment's values are given (the torque may jump there under
        ``conditions="free"``, where :math:`\\dot u` may).

        Parameters
        ----------
        t : float or array_like, shape (N,)
            Times within the planned span.

        Returns
        -------
        tau, power : numpy.ndarray, shape (N, p)
            (A scalar ``t`` gives shape (1, p).) The joints are ``samples.joint_names`` of
            :meth:`evaluate`.

        Raises
        ------
        InvalidInputError
            The system has no torque model (``system``), or a time is outside the plan (``t``).
        """
        model, _, _ = self._torque_setup()
        t = np.atleast_1d(np.asarray(t, dtype=float)).reshape(-1)
        tau, power = self._torque_values(model, t)
        return tau.T, power.T

    def effort(self) -> dict[str, JointEffort]:
        """The effort of each joint: peak torque and power, positive and net work,
        :math:`\\int\\tau^2 dt` and :math:`\\int u^2 dt` (:class:`JointEffort`).

        Rules (:data:`EFFORT_RULE`): the integrals of :math:`\\tau^2` and :math:`\\tau u` by
        composite 32-point Gauss-Legendre on each segment, on at least 8 panels and one per radian
        of :math:`\\max|u|\\,T` (at most 4096); the positive work by the same rule on each panel,
        a panel where the power changes sign split at its roots (found between consecutive nodes and
        panel edges, refined by 32-fold bracketing, then windows about the secant's zero, to brackets
        1e-7 of the segment's duration and a secant step); the peaks as the local maxima on those
        points within 1% of the largest, each refined by two 32-fold zooms and the vertex of the
        parabola through the best point and its neighbours; :math:`\\int u^2`
        exactly (:math:`T c^\\top G c` with the basis Gram matrix). One evaluation of the torque
        model on about :math:`33P` points per segment; the root and peak searches read each panel's
        polynomial of degree 31 through its nodes' values where its last three Legendre coefficients
        are within 1e-12 of each row's largest value (``effort.PanelInterpolants``), and call the
        model, once a round, only for the other panels. Checked
        against 200,001-point trapezoids (``tests/test_effort.py``: :math:`\\int\\tau^2` to 1e-8,
        positive work to 1e-6, peaks to 1e-8) and closed forms (``tests/test_optimal.py``).
        Computed once and kept.

        Returns
        -------
        dict of str to JointEffort
            By joint name, in the torque model's order.

        Raises
        ------
        InvalidInputError
            The system has no torque model, or the result has no segments.
        """
        if self._effort is not None:
            return dict(self._effort)
        out = effort_summary(self)
        object.__setattr__(self, "_effort", out)
        return dict(out)

    def _effort_block(self):
        """The ``effort`` entry of :meth:`to_dict` (``None`` unless the plan succeeded)."""
        if not self.success or not self.segments:
            return None
        joints = {}
        for e in self.effort().values():
            joints.update(e.to_dict())
        return {"joints": joints, "rule": EFFORT_RULE,
                "torque_limits": None if self.torque_limits is None else dict(self.torque_limits)}

    def basis_for(self, seg: SegmentResult) -> InputBasis:
        """The basis of ``seg``'s coefficients (results made before segments carried their basis:
        the plan's family at the segment's size)."""
        return seg.basis if seg.basis is not None else type(self.basis)(seg.basis_coefficients.shape[1])

    @property
    def intervals(self) -> tuple[tuple[SegmentResult, ...], ...]:
        """The segments grouped by waypoint interval."""
        return tuple(tuple(s for s in self.segments if s.interval == k) for k in range(len(self.times) - 1))

    def sample(self, per_segment: int = 200, *, effort: bool = True) -> Samples:
        """A dense sample: ``per_segment`` evenly spaced points on each segment, ends included
        (:meth:`evaluate`, with torques and power when the system has a torque model)."""
        ts = [np.linspace(s.t0, s.t1, per_segment) for s in self.segments]
        t = np.concatenate([ts[0]] + [x[1:] for x in ts[1:]]) if ts else np.zeros(0)
        return self.evaluate(t, effort=effort)

    # ------------------------------------------------------------------ export
    def to_dict(self) -> dict[str, Any]:
        """Everything needed to reproduce and check the plan, as plain JSON types (a number that
        is not finite is written as ``null``: JSON has no NaN or infinity).

        ``objective`` is what the plan minimises (``null``: a feasible plan), ``torque_limits`` the
        torque limits by joint (only when given); when the system has a torque model, ``effort``
        holds per joint the peak torque and power, positive and net work, the integrals of
        :math:`\\tau^2` and :math:`u^2` (:meth:`effort`, ``null`` unless the plan succeeded) and the
        rule they were computed by; a segment of an optimal plan carries its ``optimality``
        diagnostics (:attr:`SegmentResult.optimality`); ``warnings`` the list of :attr:`warnings`.
        """
        return _json_safe({
            "status": self.status.value,
            "success": self.success,
            "message": self.message,
            "warnings": list(self.warnings),
            "system": self.system.to_dict(),
            "waypoints": {
                "times": list(map(float, self.times)),
                **{name: list(map(float, self.waypoints[:, i])) for i, name in enumerate(self.system.state_names)},
            },
            "conditions": self.conditions,
            "basis": {"family": self.basis.name, "n_coefficients": self.basis.n,
                      "exact": "basis_coefficients: " + _BASIS_NOTE.get(self.basis.name, self.basis.name),
                      "export": "coefficients: the same input in the power basis of local time, u(t) = sum_i c_i "
                                "(t - t0)^i on [t0, t1], for convenience: each segment's power_form_error is its "
                                "largest departure from the exact input (it grows beyond ~10 coefficients)"},
            "verified": self.verified,
            "verification": self.verification,
            "max_abs_u": self.max_abs_u,
            "state_ranges": {k: list(v) for k, v in self.state_ranges.items()},
            "limits": None if self.limits is None else self.limits.to_dict(),
            "objective": self.objective,
            **({} if self.torque_limits is None else {"torque_limits": dict(self.torque_limits)}),
            **({"effort": self._effort_block()} if self.has_torques else {}),
            "segments": [s.to_dict(self.system.input_names, self.system.state_names) for s in self.segments],
            "infeasible": [dict(d) for d in self.infeasible],
            "diagnostics": {
                "evaluations": self.evaluations,
                "iterations": sum(s.iterations for s in self.segments),
                "max_final_error": _num(max((s.final_error for s in self.segments), default=None)),
                "max_verified_error": _num(max((s.verified_error for s in self.segments
                                                 if s.verified_error is not None), default=None)),
                "sigma_min": _num(min((s.sigma_min for s in self.segments), default=None)),
            },
        })

    def to_json(self, **kwargs) -> str:
        """:meth:`to_dict` as a JSON string (``kwargs`` go to :func:`json.dumps`)."""
        kwargs.setdefault("indent", 2)
        kwargs.setdefault("allow_nan", False)
        return json.dumps(self.to_dict(), **kwargs)

    def plot(self, which=None, *, ax=None, per_segment: int = 200, effort: bool = False, degrees: bool = False):
        """Figures in the text's styles, as one type: a :class:`~acroplan.core.plotting.Figures`
        (a dict of matplotlib figures by name, each shown once in a notebook, with ``savefig``).

        Parameters
        ----------
        which : {"input", "states", "continuation", "effort"} or sequence of them, optional
            The figures to draw; default ``"input"`` (Fig. 1), ``"states"`` (Fig. 2) and
            ``"continuation"`` (diagnostics, when path deformation was used). ``"effort"``: the
            joint torques (upper panel, torque limits dotted) and the mechanical power (lower
            panel), for a system with a torque model.
        ax : matplotlib Axes, optional
            Draw one panel there (``which`` = ``"states"``, the default with ``ax``, puts every
            state on it; ``"input"``; or ``"effort"``, the torques); the result holds that axes'
            figure under that name.
        per_segment : int
            Samples per segment.
        effort : bool
            With the default figures, also ``"effort"``.
        degrees : bool
            Angles in degrees: ``"states"`` (attitude angles, joints, their limits; axes in
            ``[deg]``) and the rates of angles in ``"input"`` (``[deg/s]``). Default radians.
            (Not the ``degrees`` of :func:`acroplan.plan`, which says how its arguments are given.)

        Returns
        -------
        Figures
            By name, in the order above.
        """
        from . import plotting

        if ax is None:
            return plotting.plot_result(self, which, per_segment=per_segment, effort=effort, degrees=degrees)
        which = which or "states"
        if which not in ("input", "states", "effort"):
            raise ValueError(f"which: with ax, must be 'input', 'states' or 'effort', got {which!r}")
        if which == "effort":
            self._torque_setup()
            plotting.plot_effort(self, self.sample(per_segment), ax=ax)
        else:
            fn = plotting.plot_input if which == "input" else plotting.plot_states
            fn(self, self.sample(per_segment, effort=False), ax=ax, degrees=degrees)
        return plotting.Figures({which: ax.figure})

    def animate(self, path=None, **kwargs):
        """The motion as an animation, drawn by the system's family (its ``animate`` hook:
        :attr:`Family.animate <acroplan.core.family.Family.animate>`): the body to scale in its
        centre-of-mass frame, the time and states written on each frame.

        Parameters
        ----------
        path : str or pathlib.Path, optional
            The GIF to write. Without it: in a notebook the animation is kept in memory and shown
            inline (a player with play, pause and a frame slider); elsewhere it is written to
            ``motion.gif`` in the current folder.
        **kwargs
            The family's options: ``speed`` (1 = real time; default: real time, or slower for a
            motion shorter than 3 s), ``fps`` (default 25), ``max_frames``, ``mp4_path`` (also an MP4
            when ffmpeg is on the PATH).

        Returns
        -------
        acroplan.core.animation.Animation
            Its ``path`` (``None`` when kept in memory), ``frames`` and ``fps``; shown inline in a
            notebook.

        Raises
        ------
        InvalidInputError
            The result has no planned segments, or the system's family draws no animation.
        """
        from .animation import animate_result

        hook = self._family_hook("animate", "has no drawing", "draw it yourself from result.sample()")
        return animate_result(self, hook, path, **kwargs)

    def view(self, path=None, **kwargs):
        """An interactive 3-D view of the motion in the browser, drawn by the system's family (its
        ``view`` hook: a spatial body's, :mod:`acroplan.families.spatial.view`): one
        self-contained HTML page (plotly, its JavaScript inline) with play, pause and a time slider,
        the body as shaded solids, the root's axes, the angular momentum vector, and the attitude
        and joint angles beside it.

        Parameters
        ----------
        path : str or pathlib.Path, optional
            The page to write. Without it: in a notebook the figure is returned (shown inline,
            interactive); elsewhere the page is written to ``view.html`` in the current folder.
        **kwargs
            The family's options (``frames``: how many, default 120; ``title``).

        Returns
        -------
        pathlib.Path, or a plotly Figure in a notebook without ``path``

        Raises
        ------
        InvalidInputError
            The result has no planned segments, or the family offers no view (planar bodies and
            the acrobot: ``animate`` them).
        """
        from pathlib import Path

        from .progress import in_notebook

        hook = self._family_hook("view", "has no 3-D view", "use result.animate() for its animation")
        if path is None and in_notebook():
            return hook(self, None, **kwargs)  # (the figure: the hook's contract)
        return Path(hook(self, Path("view.html" if path is None else path), **kwargs))

    def _family_hook(self, name: str, lacks: str, hint: str):
        """The system's family's ``name`` hook (``animate``, ``view``); :class:`InvalidInputError`
        when the result has no segments or the family offers none."""
        from .family import family_of

        if not self.segments:
            raise InvalidInputError("result", f"has no planned segments to {name}", "plan a motion first")
        fam = family_of(self.system)
        hook = None if fam is None else getattr(fam, name)
        if hook is None:
            raise InvalidInputError("system", f"{type(self.system).__name__} {lacks} (its family offers no {name} "
                                    "hook)", hint)
        return hook

    def to_pandas(self, per_segment: int = 200):
        """A dense sample as a pandas DataFrame: columns ``t``, the states and the inputs, and
        ``tau_<joint>``, ``power_<joint>`` per joint when the system has a torque model
        (:meth:`Samples.columns`; needs pandas)."""
        try:
            import pandas as pd
        except ImportError:  # pragma: no cover - pandas is there wherever the test extra is
            raise ImportError("to_pandas needs pandas: pip install pandas") from None
        return pd.DataFrame(self.sample(per_segment).columns())
