"""The validated problems a problem file describes: :class:`Problem` (``[plan]``) and
:class:`Simulation` (``[simulate]``)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ...core.errors import InvalidInputError
from ...core.family import family_of
from ...core.limits import Limits
from ...core.system import ControlAffineSystem
from ...planning import PlanRequest

__all__ = ["Problem", "Simulation"]


@dataclasses.dataclass(frozen=True)
class Problem:
    """A validated planning problem: a system, waypoints by state name, conditions and options.

    Parameters
    ----------
    system : ControlAffineSystem
        The body its family read from the file's ``[robot]`` or ``[body]`` (an
        :class:`~acroplan.families.acrobot.model.Acrobot`, a
        :class:`~acroplan.families.planar.model.PlanarBody` whose link table holds the file's
        ``[limits]``, a :class:`~acroplan.families.spatial.model.SpatialBody`, ...).
    times : tuple of float, length K + 1
    waypoints : dict of str to tuple, each of length K + 1
        One entry per state of ``system``, in state order; ``None`` marks a free interior value.
    conditions : {"spline", "free"}
    options : dict
        Further :func:`acroplan.plan` keywords (the acrobot's limits ``phi_min``, ``phi_max``,
        ``u_max`` among them).
    name : str

    Notes
    -----
    ``problem.robot`` is the system (any kind, as the front doors expect); ``problem.theta`` and,
    for the acrobot, ``problem.phi`` are the waypoints of those states.
    """

    system: ControlAffineSystem
    times: tuple[float, ...]
    waypoints: dict[str, tuple] = dataclasses.field(default_factory=dict)
    conditions: str = "spline"
    options: dict[str, Any] = dataclasses.field(default_factory=dict)
    name: str = ""

    @property
    def robot(self) -> ControlAffineSystem:
        """The system (the name the acrobot's callers know)."""
        return self.system

    @property
    def theta(self) -> tuple:
        """The waypoints of ``theta``."""
        return self.state("theta")

    @property
    def phi(self) -> tuple:
        """The waypoints of ``phi`` (the acrobot's joint angle)."""
        if "phi" not in self.waypoints:
            raise AttributeError(f"a {type(self.system).__name__} has no state phi; its states are "
                                 f"{list(self.system.state_names)}")
        return self.waypoints["phi"]

    def state(self, name: str) -> tuple:
        """The waypoints of state ``name``."""
        if name not in self.waypoints:
            raise InvalidInputError("state", f"{name!r} is not a state of this problem",
                                    f"states are {list(self.waypoints)}")
        return self.waypoints[name]

    def plan_kwargs(self) -> dict[str, Any]:
        """The keywords of :func:`acroplan.plan` for this problem (all but the system). ``conditions`` is
        ``None`` when the file asks for an optimal plan (``objective``, ``tau_max``) and gives no
        ``plan.conditions``: :func:`acroplan.plan` then applies its default (``"free"``)."""
        return dict(times=self.times, **self.waypoints, conditions=self.conditions, **self.options)

    def solve(self, *, verify: bool | str = True, progress=None):
        """Plan it with :func:`acroplan.plan`."""
        from ...planning import plan

        return plan(self.system, verify=verify, progress=progress, **self.plan_kwargs())

    @property
    def limits(self) -> Limits:
        """The limits a plan of this problem honours (:func:`acroplan.plan`'s, from the file's
        ``[limits]``: the acrobot's plan keywords, or the body's link table, the URDF's overridden by
        the file), in radians."""
        return PlanRequest.build(self.system, **self.plan_kwargs()).limits

    def family(self):
        """The :class:`~acroplan.core.family.Family` of the problem's system (``None`` for a system of
        no registered family)."""
        return family_of(self.system)

    def reach(self) -> list[dict]:
        """What can be proven about every segment's reachable :math:`\\theta(T)`, by the system's family
        (the acrobot and any two-link body: the exact reachable interval, without and with the limits;
        a planar body of three or more links: the bound of :meth:`PlanarBody.turn_bound
        <acroplan.families.planar.model.PlanarBody.turn_bound>` when every joint has a rate limit).

        Returns
        -------
        list of dict, one per segment

        Raises
        ------
        InvalidInputError
            When the family knows nothing to prove of this body (``reach``).
        """
        fam = self.family()
        if fam is None or fam.reach is None:
            what = fam.describe(self.system) if fam is not None and fam.describe else type(self.system).__name__
            raise InvalidInputError("reach", f"nothing is known of what {what} can reach: no exact reachable set or "
                                    "bound exists for it", "plan the file with acroplan plan (a target it cannot "
                                    "reach ends not_converged with the stages' reasons)")
        return fam.reach(self)

    def two_link(self):
        """The problem's body as the acrobot of text eq. (3), for the exact answers of the two-link body.

        Returns
        -------
        (Acrobot, psi0, delta, joint, limits)
            The acrobot, its angle offsets (:math:`\\theta_A = \\theta + \\psi_0`, :math:`\\varphi_A =
            \\varphi + \\delta`: zero for a ``[robot]``), the joint's state name and the problem's limits
            in the acrobot's angles (``None`` without limits).

        Raises
        ------
        InvalidInputError
            For a body that is not a two-link body (``body``).
        """
        fam = self.family()
        if fam is None or fam.two_link is None:
            raise InvalidInputError("body", "is not a two-link body: the exact answer exists for the two-link body "
                                    "only (it is an acrobot, whose reachable set is exact)",
                                    "give a two-link body ([robot], or a [body] with two links); for more links "
                                    "plan at several momenta (acroplan sweep, docs/sweeps.md)")
        return fam.two_link(self)


@dataclasses.dataclass(frozen=True)
class Simulation:
    """A validated simulation: the motion that given joint motions produce (``[simulate]``).

    Parameters
    ----------
    system : ControlAffineSystem
    times : tuple of float, length K + 1
    initial : dict of str to float
        The initial state, every state by name.
    inputs : tuple of numpy.ndarray, K arrays of shape (m, n)
        Per segment, each input's Legendre coefficients on :math:`s = (t - t_k)/(t_{k+1} - t_k)`
        (:func:`acroplan.simulate`'s ``inputs``), padded with zeros to a common ``n``.
    motion : dict of str to str
        Per input, ``"spline"`` (through the file's joint angles) or ``"coefficients"``.
    name : str
    """

    system: ControlAffineSystem
    times: tuple[float, ...]
    initial: dict[str, float]
    inputs: tuple[np.ndarray, ...]
    motion: dict[str, str] = dataclasses.field(default_factory=dict)
    name: str = ""

    def simulate_kwargs(self) -> dict[str, Any]:
        """The keywords of :func:`acroplan.simulate` (all but the system and ``verify``)."""
        return dict(times=self.times, inputs=[np.array(c) for c in self.inputs], basis="legendre", **self.initial)

    def run(self, *, verify: bool | str = True):
        """:func:`acroplan.simulate`, checked by the family's own independent check when
        ``verify="family"`` (the Pinocchio check of a planar body), by the DOP853 re-simulation when
        ``True`` or ``"ode"``, not at all when ``False``.

        Returns
        -------
        PlanResult
        """
        from ...simulation import simulate

        if verify != "family":
            # "ode" by name: simulate(verify=True) is the family's own check when the family has one
            res = simulate(self.system, verify="ode" if verify in (True, "ode") else False, **self.simulate_kwargs())
            return dataclasses.replace(res, verification="ode") if res.verified and res.verification is None else res
        from ...core.result import PlanResult, Status
        from ...core.verify import verify_plan

        res = simulate(self.system, verify=False, **self.simulate_kwargs())
        checked, bad, allowed = verify_plan(self.system, res.waypoints[0], res.segments, method="family")
        how = getattr(self.system, "family_check", "the family's own check")
        common = dict(system=res.system, times=res.times, waypoints=res.waypoints, conditions=res.conditions,
                      basis=res.basis, segments=tuple(checked), verified=True, verification="family")
        if bad is not None:
            return PlanResult(status=Status.NOT_CONVERGED, message=f"not converged: the independent check ({how}) "
                              f"disagrees at t = {bad.t1:g} by {bad.verified_error:.2e} > {allowed:.2g}", **common)
        worst = max(s.verified_error for s in checked)
        return PlanResult(status=Status.SUCCESS, message=f"simulated: {len(checked)} segment(s), independently "
                          f"verified ({how}) to {worst:.2e}", **common)
