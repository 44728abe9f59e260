"""Input conditions at the ends of each waypoint interval.

* ``"spline"`` (the text's scheme): for every rate input :math:`u = \\dot q`, the values and slopes
  of :math:`u` at both ends of interval :math:`k` are those of the clamped cubic spline through
  :math:`(t_k, q_k)` (zero end slopes), so :math:`u` and :math:`u'` are continuous everywhere.
* ``"free"``: only the waypoint states are imposed; the inputs are continuous at interior waypoints
  (interval :math:`k` starts with the input value interval :math:`k-1` ended with), and an input
  that drives a state onto one of its bounds at an interior waypoint must arrive there at rest.

Conditions are **linear** in the input coefficients, :math:`B c = d`
(:func:`linear_conditions`), so the solvers eliminate them exactly.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .basis import InputBasis
from .errors import InvalidInputError

__all__ = ["CONDITIONS", "Conditions", "check_conditions", "linear_conditions", "hermite_inverse"]

#: The names ``conditions=`` accepts.
CONDITIONS = ("spline", "free")


def check_conditions(kind, system) -> None:
    """Raise :class:`InvalidInputError` unless ``kind`` names conditions ``system`` can have."""
    if kind not in CONDITIONS:
        raise InvalidInputError("conditions", f"must be one of {list(CONDITIONS)}, got {kind!r}",
                                "use \"spline\" (the text's scheme) or \"free\"")
    if kind == "spline" and set(system.rate_inputs) != set(system.input_names):
        raise InvalidInputError("conditions", f"\"spline\" needs every input to be the rate of a state, "
                                f"which {type(system).__name__} does not have", "use conditions=\"free\"")


class Conditions:
    """The input conditions of a whole plan.

    Parameters
    ----------
    kind : {"spline", "free"}
    system : ControlAffineSystem
    times : numpy.ndarray, shape (K+1,)
    waypoints : numpy.ndarray, shape (K+1, n)
    limits : Limits or None
    start_rate, end_rate : numpy.ndarray, shape (m,), optional
        Free conditions only: the inputs at the first and the last waypoint (zeros: start or end
        at rest).
    """

    def __init__(self, kind: str, system, times, waypoints, limits=None, start_rate=None, end_rate=None):
        check_conditions(kind, system)
        self.start_rate = None if start_rate is None else np.asarray(start_rate, dtype=float)
        self.end_rate = None if end_rate is None else np.asarray(end_rate, dtype=float)
        self.kind = kind
        self.system = system
        self.times = times
        self.waypoints = waypoints
        self.limits = limits if limits is not None and limits.active else None
        self.splines = None
        if kind == "spline":
            from scipy.interpolate import CubicSpline  # here: scipy.interpolate imports scipy.optimize

            self.splines = [CubicSpline(times, waypoints[:, system.state_names.index(system.rate_inputs[name])],
                                        bc_type="clamped") for name in system.input_names]

    def infeasible(self) -> dict | None:
        """Spline conditions fix every input at every waypoint: the proof (an ``infeasible`` entry)
        when that breaks the limits, else ``None``."""
        if self.splines is None or self.limits is None:
            return None
        system, limits, X = self.system, self.limits, self.waypoints
        for name, spl in zip(system.input_names, self.splines):
            U = limits.input_bound(name)
            state = system.rate_inputs[name]
            i = system.state_names.index(state)
            for k, tk in enumerate(self.times):
                u = float(spl(tk, 1))
                if U is not None and abs(u) > U:
                    return {"index": k, "t0": float(tk), "t1": float(tk), "field": name, "interval": None,
                            "reason": f"conditions=\"spline\" sets {name}(t = {tk:g}) = {u:.6g}, beyond its rate "
                                      f"limit {U:g}; use conditions=\"free\" or a larger limit"}
                if state in limits.bounded_states and limits.at_bound(state, X[k, i]) and abs(u) > 1e-12:
                    return {"index": k, "t0": float(tk), "t1": float(tk), "field": state, "interval": None,
                            "reason": f"conditions=\"spline\" sets {name}(t = {tk:g}) = {u:.6g} at the waypoint where "
                                      f"{state} = {X[k, i]:.12g} is on its joint limit, so the joint leaves the "
                                      f"limits on one side; use conditions=\"free\""}
        return None

    def ends(self, k: int, prev_end_input=None) -> dict:
        """The conditions of interval ``k`` as values: a dict of arrays ``(m,)`` under ``"u0"``,
        ``"du0"``, ``"uT"``, ``"duT"`` (any subset). ``prev_end_input``: the input value interval
        ``k - 1`` ended with (free conditions)."""
        if self.splines is not None:
            t = self.times
            ends = np.array([t[k], t[k + 1]])
            vals = np.array([spl(ends, 1) for spl in self.splines])
            slopes = np.array([spl(ends, 2) for spl in self.splines])
            return {"u0": vals[:, 0], "du0": slopes[:, 0], "uT": vals[:, 1], "duT": slopes[:, 1]}
        out = {}
        K = len(self.times) - 1
        if prev_end_input is not None:
            out["u0"] = np.asarray(prev_end_input, dtype=float)
        elif k == 0 and self.start_rate is not None:
            out["u0"] = self.start_rate
        if k == K - 1 and self.end_rate is not None:
            out["uT"] = self.end_rate
        if self.limits is not None and k + 1 < K:
            # an interior waypoint on a joint limit: the joint must arrive there at rest, else the
            # continuous input carries it out of the limits in the next interval
            x = self.waypoints[k + 1]
            for state in self.limits.bounded_states:
                if self.limits.at_bound(state, float(x[self.system.state_names.index(state)])):
                    out["uT"] = np.zeros(self.system.n_inputs)
        return out


def linear_conditions(basis: InputBasis, m: int, T: float, ends: dict):
    """``B c = d`` for the end values (flattened input-major ``c``).

    Parameters
    ----------
    basis : InputBasis
    m : int
        Number of inputs.
    T : float
        Interval duration.
    ends : dict
        As from :meth:`Conditions.ends`.

    Returns
    -------
    B : numpy.ndarray, shape (q, m * basis.n), or None when there is no condition
    d : numpy.ndarray, shape (q,), or None
    """
    if not ends:
        return None, None
    n = basis.n
    rows, rhs = [], []
    V = basis.matrix([0.0, 1.0], 0)
    D = basis.matrix([0.0, 1.0], 1) / T
    which = {"u0": V[0], "du0": D[0], "uT": V[1], "duT": D[1]}
    for key in ("u0", "du0", "uT", "duT"):
        if key not in ends:
            continue
        for j in range(m):
            r = np.zeros(m * n)
            r[j * n:(j + 1) * n] = which[key]
            rows.append(r)
            rhs.append(float(ends[key][j]))
    if not rows:
        return None, None
    return np.array(rows), np.array(rhs)


@functools.lru_cache(maxsize=64)
def hermite_inverse(keys: tuple, deg: int) -> np.ndarray:
    """The inverse of the conditions matrix on the power coefficients in s of a joint motion
    q(s) of degree ``deg``: rows are q(0), q(1), then the keyed derivatives (``"u0"``: q'(0),
    ``"du0"``: q''(0), ``"uT"``: q'(1), ``"duT"``: q''(1)); shape ``(deg+1, deg+1)``, read-only."""
    k = np.arange(deg + 1)
    rows = [(k == 0).astype(float), np.ones(deg + 1)]
    for key in keys:
        s0, order = {"u0": (0.0, 1), "du0": (0.0, 2), "uT": (1.0, 1), "duT": (1.0, 2)}[key]
        fall = np.array([math.perm(int(i), order) for i in k], dtype=float)
        rows.append(fall * np.where(k >= order, s0 ** np.maximum(k - order, 0), 0.0))
    out = np.linalg.inv(np.array(rows))
    out.flags.writeable = False
    return out
