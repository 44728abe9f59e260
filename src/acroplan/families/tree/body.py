"""What every body of links joined by revolute joints shares, whatever its dynamics (planar or
spatial): the joint names as inputs, the link table's joint limits, the ends a segment's joints
must reach under limits, the independent check by Pinocchio, the record of the link table.

:class:`TreeBody` is a mixin of a family's :class:`~acroplan.core.system.ControlAffineSystem`
(``class PlanarBody(TreeBody, ControlAffineSystem)``). The family class gives

* ``links``: its link table (a :class:`~acroplan.families.tree.links.TreeLinkTable`);
* ``n_root``: how many states come before the joints (1 in the plane, the root angle; 4 in 3-D,
  the attitude quaternion);
* ``momentum_field``: the name its record gives the angular momentum (``"P0"``, ``"L"``), and
  ``_momentum_record()``, its value as a record holds it;
* ``_check_module``: the module holding its ``pinocchio_errors(body, x0, segments)`` and
  ``state_error(x, target)`` (the distance of two states).
"""

from __future__ import annotations

import importlib
from typing import Any, Mapping

import numpy as np

from ...core.errors import InvalidInputError
from ...core.system import Infeasibility

__all__ = ["TreeBody", "joint_ends_infeasibility"]


def joint_ends_infeasibility(names, x0, x1, duration: float, limits, offset: int) -> Infeasibility | None:
    """Why no joint motion joins the joint angles of ``x0`` to those of ``x1`` in ``duration`` under
    ``limits``, or ``None``: an end outside its joint's limits, or a rate-limited joint that must
    move more than :math:`\\bar u_j T`.

    Parameters
    ----------
    names : sequence of str
        The joint names, in state order.
    x0, x1 : array_like, shape (offset + len(names),)
        The segment's end states; the joints start at index ``offset``.
    duration : float
    limits : Limits or None
        No check (``None``) unless the limits are active.
    offset : int
        The number of states before the joints.
    """
    if limits is None or not limits.active:
        return None
    x0 = np.asarray(x0, dtype=float)
    x1 = np.asarray(x1, dtype=float)
    T = float(duration)
    lim = f" under {limits.describe()}"
    for j, name in enumerate(names):
        lo, hi = limits.bounds(name)
        a, b = x0[offset + j], x1[offset + j]
        for end, v in ((f"{name}(0)", a), (f"{name}(T)", b)):
            if not lo <= v <= hi:
                return Infeasibility(f"no joint motion is possible{lim}: {end} = {v:.12g} is outside the joint "
                                     f"limits [{lo:.12g}, {hi:.12g}]", name, None)
        U = limits.input_bound(f"u_{name}")
        if U is not None and abs(b - a) > U * T * (1 + 1e-15):
            return Infeasibility(f"no joint motion is possible{lim}: {name} must move {abs(b - a):.12g} rad in "
                                 f"T = {T:.12g} s, but u_{name} is limited to {U:.12g} rad/s", name, None)
    return None


class TreeBody:
    """The planning hooks and records a body of revolute joints shares (module docstring)."""

    n_root: int = 1
    momentum_field: str = "P0"
    _check_module: str = ""

    # ------------------------------------------------------------------ names
    @property
    def input_names(self):
        """``("u_<joint>", ...)``: one rate input per joint, in the link table's joint order."""
        return tuple(f"u_{j}" for j in self.links.joint_names)

    @property
    def rate_inputs(self):
        """``{"u_<joint>": "<joint>"}``: the joint whose rate each input is."""
        return {f"u_{j}": j for j in self.links.joint_names}

    @property
    def n_links(self) -> int:
        return len(self.links)

    def _shape(self, shape) -> np.ndarray:
        """``shape`` as an array whose first axis holds one angle per joint, or the error naming it."""
        s = np.asarray(shape, dtype=float)
        if s.shape[:1] != (self.n_links - 1,):
            raise InvalidInputError("shape", f"must hold the {self.n_links - 1} joint angle(s) "
                                    f"{list(self.links.joint_names)}, got shape {s.shape}", "give one angle per joint")
        return s

    # ------------------------------------------------------------------ limits
    def joint_limits(self):
        """The table's joint limits as a :class:`~acroplan.core.limits.Limits` (position limits on
        the joint states, rate limits on their inputs), or ``None`` when the table has none."""
        from ...core.limits import Limits

        states, inputs = {}, {}
        for i, name in zip(self.links.joints, self.links.joint_names):
            link = self.links[i]
            if link.lower is not None or link.upper is not None:
                states[name] = (link.lower, link.upper)
            if link.velocity is not None:
                inputs[f"u_{name}"] = link.velocity
        if not states and not inputs:
            return None
        return Limits(states, inputs)

    def default_limits(self):
        """The table's (or the URDF's) joint limits, honoured by :func:`acroplan.plan`: its limit
        keywords change them name by name, ``limits=Limits(...)`` replaces them whole
        (``limits=Limits()`` switches them off)."""
        return self.joint_limits()

    def joint_bounds(self, limits) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Per joint (state order), under ``limits``: its range ``lo``, ``hi`` and its rate limit ``U``,
        each shape (m,), infinite where there is none (or ``limits`` is ``None`` or inactive)."""
        m = len(self.links.joint_names)
        lo, hi, U = np.full(m, -np.inf), np.full(m, np.inf), np.full(m, np.inf)
        if limits is not None and limits.active:
            for j, name in enumerate(self.links.joint_names):
                lo[j], hi[j] = limits.bounds(name)
                bound = limits.input_bound(f"u_{name}")
                U[j] = np.inf if bound is None else bound
        return lo, hi, U

    def joint_ends_infeasibility(self, x0, x1, duration, limits) -> Infeasibility | None:
        """:func:`joint_ends_infeasibility` of this body's joints."""
        return joint_ends_infeasibility(self.links.joint_names, x0, x1, duration, limits, self.n_root)

    # ------------------------------------------------------------------ the independent check
    @property
    def family_check(self) -> str:
        """The name of :meth:`family_errors`' check (``plan(verify=True)`` reports it)."""
        try:
            import pinocchio  # noqa: F401
        except ImportError:  # no check of its own here: plans are re-simulated by DOP853 ("ode")
            return ""
        return "Pinocchio centroidal simulation"

    def family_errors(self, x0, segments):
        """The independent check by Pinocchio (the family's ``check.pinocchio_errors``): the planned
        inputs chained from ``x0`` through a motion driven by Pinocchio's centroidal map alone.
        Without Pinocchio installed, the core's DOP853 re-simulation of the model's own fields.

        Returns
        -------
        numpy.ndarray, shape (len(segments),)
            Each segment's distance from its target at its end (the family's ``state_error``).
        """
        check = importlib.import_module(self._check_module)
        try:
            import pinocchio  # noqa: F401
        except ImportError:
            from ...core.verify import simulate_segment

            x, out = np.asarray(x0, dtype=float), []
            for seg in segments:
                x = simulate_segment(self, x, seg.t0, seg.t1, seg.input).y[:, -1]
                out.append(check.state_error(x, seg.target))
            return np.array(out)
        return check.pinocchio_errors(self, x0, segments)

    # ------------------------------------------------------------------ records
    def to_dict(self) -> dict[str, Any]:
        """Type, lumped parameters, the angular momentum (under :attr:`momentum_field`), the
        topology and the link table (:meth:`from_dict` reads it back)."""
        out = super().to_dict()
        out[self.momentum_field] = self._momentum_record()
        out["parents"] = list(self.links.parents)
        out["links"] = self.links.to_dicts()
        return out

    @classmethod
    def _links_of(cls, d: Mapping[str, Any]):
        """The ``links`` of a record, or the error naming it."""
        if not isinstance(d, Mapping) or "links" not in d:
            raise InvalidInputError("links", "is missing", "give the link table (a list of link tables)")
        return d["links"]
