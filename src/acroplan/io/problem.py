"""Problem files (TOML) and their validation.

A problem file describes a body and what to do with it. The body is either the two-link acrobot of
the text (a ``[robot]`` table) or a planar body of any number of links (a ``[body]`` table, from
a URDF file or from link tables); then a ``[plan]`` table (``acroplan plan``, ``acroplan
reach``) and/or a ``[simulate]`` table (``acroplan simulate``)::

    [robot]            # the acrobot: either the physical body ...
    torso_mass = 40.0          # M  (> 0)
    leg_mass = 20.0            # m  (> 0)
    torso_inertia = 2.5        # J  (> 0), about the torso's centre of mass
    leg_inertia = 1.2          # j  (> 0), about the leg's centre of mass
    torso_length = 0.35        # L  (>= 0), torso centre of mass to joint
    leg_length = 0.45          # l  (>= 0), leg centre of mass to joint
    angular_momentum = 10.0    # P0
    # ... or the lumped parameters M1, A1, M2, A2, P0 of text eq. (3)

    [plan]
    times = [0, 2]
    theta = ["-0.5*pi", "0.9*pi"]   # numbers, or strings of arithmetic with pi
    phi = ["-pi", "-2*pi"]
    conditions = "spline"           # or "free"

    [limits]           # optional
    phi_min = "-2*pi"               # joint limits on phi
    phi_max = "-pi"
    u_max = 20.0                    # |u| <= u_max (rad/s)

    [options]          # optional
    method = "auto"                 # or "deform" (the text's), "flat"
    basis = "legendre"              # or "monomial"
    n_coefficients = 6
    tol = 1e-10
    max_evaluations = 2000
    objective = "energy"            # or "torque": an optimal plan (least integral of u^2 or tau^2)
    tau_max = 50.0                  # |tau| <= 50 N m at every joint (needs the physical body) ...
    # [options.tau_max]             # ... or per joint (joints not named have no torque limit)
    # phi = 50.0                    # the acrobot's joint; a body's joints by name

With ``objective`` or ``tau_max`` and no ``plan.conditions``, the conditions are :func:`acroplan.plan`'s
default for optimal plans (``"free"``: the end inputs are left to the optimiser); otherwise
``"spline"`` as always. Torques (``objective = "torque"``, ``tau_max``) need a body with its masses
and inertias: the acrobot's physical keys, or any ``[body]``.

A planar body (:class:`~acroplan.families.planar.model.PlanarBody`; state :math:`(\\theta, q_1,
\\dots, q_{n-1})`, :math:`\\theta` the root link's angle, :math:`q_j` the joint angles named by
their joints; inputs :math:`u_j = \\dot q_j` named ``u_<joint>``; the angular momentum :math:`P_0`
about the axis normal to the plane is conserved)::

    [body]
    urdf = "diver.urdf"             # relative to the problem file (read by Pinocchio) ...
    angular_momentum = 36.0         # P0
    # ... or, instead of urdf, one [[body.link]] table per link:
    # [[body.link]]
    # name = "base"                 # the root: no parent
    # mass = 150.0
    # inertia = 25.0                # about the link's centre of mass
    # com = [0.0, 0.0]              # centre of mass in the link's own frame
    # [[body.link]]
    # name = "upper_arm"
    # parent = "base"
    # joint = [0.6, 0.0]            # its joint, in the parent's frame
    # joint_name = "shoulder"       # default: the link's name
    # mass = 12.0
    # inertia = 1.44
    # com = [0.6, 0.0]
    # lower = -2.6                  # optional joint limits (rad) and rate limit (rad/s)
    # upper = 2.6
    # velocity = 0.5

    [plan]
    times = [0.0, 1.5]
    theta = [0.0, 1.2]              # the root link's angle
    shoulder = [0.3, 0.3]           # one array per joint, named as in the URDF / link table
    conditions = "free"

    [limits]           # optional: overrides the URDF's / table's limits, joint by joint
    shoulder_min = -1.0             # joint limits; "none" drops the URDF's
    shoulder_max = 3.0
    u_shoulder = 5.0                # the joint's rate limit |u_shoulder| <= 5 rad/s
    u_max = 8.0                     # every joint's rate limit (a joint's own u_<joint> wins)

The file's ``[limits]`` are written into the body's link table, so the limits a plan honours are the
URDF's (or the table's) unless the file overrides them, and ``solution.json`` records them with the
body. The link table is always in radians; ``options.degrees = true`` applies to ``[plan]`` and
``[limits]``.

A human body (:mod:`acroplan.families.human`, docs/human.md) from Yeadon's measurements or from
height and mass, split at the hips (the two-link body: an :class:`Acrobot`, state ``theta``,
``phi``) or at the hips and shoulders (a :class:`PlanarBody`, joints ``hip`` and ``shoulder``)::

    [body]
    yeadon = "male1"                # a yeadon measurement file (relative to the problem file),
                                    # or a bundled sample by name; needs pip install "acroplan[human]"
    # height = 1.74                 # ... or, instead of yeadon, de Leva's (1996) tables:
    # mass = 70.0                   # stature (m) and mass (kg),
    # sex = "male"                  # "male" (default) or "female"
    split = "hips"                  # default; or "hips+shoulders"
    angular_momentum = 65.7         # P0 (kg m^2/s; > 0 for a forward somersault)
    position = "pike"               # optional: "pike", "tuck", "straight": the default [limits]
    # knee_flexion = 0.0            # rad; default the position's (a tuck's 125 degrees), else 0
    # shoulder_flexion = 0.0        # rad; split = "hips" only: the arms' fixed angle

``position`` gives the joint ranges and rates of :func:`~acroplan.families.human.limits.human_limits`
(``phi_min``, ``phi_max``, ``u_max`` for ``split = "hips"``; ``hip_min``, ..., ``u_shoulder`` in the
link table for ``"hips+shoulders"``); each key of the file's ``[limits]`` overrides one of them
(``"none"`` drops it). The body's angles are in radians whatever ``options.degrees`` says.

A simulation (``acroplan simulate``): the motion a given joint motion produces::

    [simulate]
    times = [0.0, 10.0, 20.0]
    theta = 0.0                     # the initial root angle
    shoulder = [0.0, 1.5, 0.0]      # a joint's angle at each time: a clamped cubic spline
                                    # through them (at rest at both ends, u continuous) ...
    elbow = 0.0                     # ... or its initial angle and
    u_elbow = [[0.0, 0.3], [0.0, -0.3]]   # its rate's Legendre coefficients per segment

Per joint either form; a joint given neither way is refused. The spline's rate is a quadratic per
segment, so its three Legendre coefficients are exact. For the acrobot the joint is ``phi`` and its
rate ``u``.

Unknown tables and keys are rejected with the nearest known name, so a typo never passes silently;
every message names the file's field (``body.link[2].mass``, ``plan.shoulder``,
``limits.u_shoulder``, ``simulate.u_elbow[1]``) and the fix.
"""

from __future__ import annotations

import dataclasses
import math
import tomllib
from pathlib import Path
from typing import Any, Callable

import numpy as np

from ..core.errors import InvalidInputError
from ..core.limits import Limits
from ..core.system import ControlAffineSystem
from ..core.validate import (BODY_VALUES as _BODY, MAX_ANGLE, MAX_BODY, MAX_EVALUATIONS, MAX_FILE_BYTES, MAX_LINKS,
                             MAX_TIME, MIN_BODY, TOL_RANGE)
from ..core.validate import check_keys as _check_keys
from ..core.validate import choice_field as _choice_field
from ..core.validate import did_you_mean as _close
from ..core.validate import matrix3 as _matrix3
from ..core.validate import name_field as _name_field
from ..core.validate import number as _number
from ..core.validate import numbers as _numbers
from ..core.validate import pair_field as _pair_field
from ..core.validate import short as _short
from ..core.validate import states as _states
from ..core.validate import vector3 as _vector3
from ..families.acrobot.model import Acrobot
from ..families.acrobot.reach import reachable_set
from ..planning import PlanRequest

__all__ = ["Problem", "Simulation", "load_problem", "load_simulation", "parse_problem", "parse_simulation",
           "parse_body", "system_to_dict", "with_options", "torque_joints"]

PHYSICAL_KEYS = ("torso_mass", "leg_mass", "torso_inertia", "leg_inertia", "torso_length", "leg_length",
                 "angular_momentum")
LUMPED_KEYS = ("M1", "A1", "M2", "A2", "P0")
PLAN_KEYS = ("times", "theta", "phi", "conditions")
#: the physical keys' clearer names (what they are: centre of mass to the joint)
ALIASES = {"torso_com_to_joint": "torso_length", "leg_com_to_joint": "leg_length"}
LIMIT_KEYS = ("phi_min", "phi_max", "u_max")
#: the tables a problem file may hold
TABLES = ("robot", "body", "plan", "limits", "options", "simulate")
#: the keys of [body], and of each [[body.link]] (the fields of :class:`~acroplan.families.planar.links.Link`)
#: the keys of a human body in [body] (acroplan.families.human)
HUMAN_KEYS = ("yeadon", "height", "mass", "sex", "split", "position", "knee_flexion", "shoulder_flexion")
BODY_KEYS = ("urdf", "link", "angular_momentum") + HUMAN_KEYS
#: how a human body is split: at the hips (the two-link body), at the hips and the shoulders
SPLITS = ("hips", "hips+shoulders")
LINK_KEYS = ("name", "parent", "mass", "inertia", "com", "joint", "joint_name", "lower", "upper", "velocity")
#: the keys of each [[body.link]] of a spatial body (the fields of
#: :class:`~acroplan.families.spatial.links.SpatialLink`)
SPATIAL_LINK_KEYS = ("name", "parent", "mass", "inertia", "com", "joint", "axis", "rotation", "joint_name", "lower",
                     "upper", "velocity")
#: a spatial body's attitude keys in [plan] (one attitude per waypoint) and [simulate] (the initial
#: one), and the form of :func:`~acroplan.families.spatial.rotations.as_quaternion` each names
#: (``attitude``: a quaternion [w, x, y, z] or an inline table of any form); ``attitude_seq``
#: names another Euler sequence than Yeadon's
ATTITUDE_KEYS = {"attitude": None, "attitude_euler_deg": "euler_deg", "attitude_euler": "euler",
                 "attitude_rotvec_deg": "rotvec_deg", "attitude_rotvec": "rotvec"}
ATTITUDE_FORMS = ("quaternion", "rotvec", "rotvec_deg", "euler", "euler_deg")


@dataclasses.dataclass(frozen=True)
class Problem:
    """A validated planning problem: a system, waypoints by state name, conditions and options.

    Parameters
    ----------
    system : ControlAffineSystem
        An :class:`~acroplan.families.acrobot.model.Acrobot` (a ``[robot]`` table, or a human
        ``[body]`` split at the hips) or a :class:`~acroplan.families.planar.model.PlanarBody` (a
        ``[body]`` table; the file's ``[limits]`` are in its link table).
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
        from ..planning import plan

        return plan(self.system, verify=verify, progress=progress, **self.plan_kwargs())

    @property
    def limits(self) -> Limits:
        """The limits a plan of this problem honours: the acrobot's ``[limits]``; a body's link-table
        limits (the URDF's, overridden by the file's ``[limits]``)."""
        if isinstance(self.system, Acrobot):
            return Limits(**{k: self.options[k] for k in ("phi_min", "phi_max", "u_max") if k in self.options})
        return self.system.default_limits() or Limits()

    def reach(self) -> list[dict]:
        """What can be proven about every segment's reachable :math:`\\theta(T)`.

        The acrobot (and any two-link body, which is one): the exact reachable interval, without
        and with the limits. A body of three or more links: the bound of :meth:`PlanarBody.turn_bound
        <acroplan.families.planar.model.PlanarBody.turn_bound>`, :math:`|\\theta(T) - \\theta(0)| \\le B`,
        when every joint has a rate limit (a target outside it is proven unreachable; one inside
        is not proven reachable: ``reachable`` is then ``None``).

        Returns
        -------
        list of dict, one per segment

        Raises
        ------
        InvalidInputError
            For a body of three or more links with a joint without a rate limit (no bound is known).
        """
        if isinstance(self.system, Acrobot):
            return self._reach_acrobot()
        if getattr(self.system, "n_links", 0) == 2:
            return self._reach_two_links()
        return self._reach_bound()

    def _reach_acrobot(self) -> list[dict]:
        out = []
        for k in range(len(self.times) - 1):
            T = self.times[k + 1] - self.times[k]
            kw = dict(theta0=self.theta[k], phi0=self.phi[k], phiT=self.phi[k + 1], T=T)
            free = reachable_set(self.robot, **kw)
            lim = reachable_set(self.robot, **kw, limits=self.limits) if self.limits.active else free
            target = self.theta[k + 1]
            out.append({
                "index": k, "t0": self.times[k], "t1": self.times[k + 1], "theta0": self.theta[k],
                "phi0": self.phi[k], "phiT": self.phi[k + 1], "target_theta": target,
                "interval": [free.low, free.high], "interval_closed": free.closed,
                "interval_with_limits": None if lim.empty else [lim.low, lim.high],
                "with_limits_closed": lim.closed, "empty_reason": lim.reason or None,
                "reachable": lim.contains(target),
            })
        return out

    def _segments(self):
        names = self.system.state_names
        for k in range(len(self.times) - 1):
            x0 = [self.waypoints[n][k] for n in names]
            x1 = [self.waypoints[n][k + 1] for n in names]
            if any(v is None for v in x0 + x1):
                raise InvalidInputError(f"plan.{names[[v is None for v in x0 + x1].index(True) % len(names)]}",
                                        "has a free waypoint: what is reachable is asked from given states",
                                        "give every state at every waypoint for acroplan reach")
            yield k, np.array(x0, dtype=float), np.array(x1, dtype=float), self.times[k + 1] - self.times[k]

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
            For a body that has not exactly two links (``body``).
        """
        if isinstance(self.system, Acrobot):
            return self.system, 0.0, 0.0, "phi", (self.limits if self.limits.active else None)
        body = self.system
        n = getattr(body, "n_links", None)
        if n != 2:
            raise InvalidInputError("body", f"has {n} links: the exact answer exists for the two-link body only "
                                    "(it is an acrobot, whose reachable set is exact)",
                                    "give a two-link body ([robot], or a [body] with two links); for more links "
                                    "plan at several momenta (acroplan sweep, docs/sweeps.md)")
        acro, psi0, delta = body.as_acrobot()
        joint = body.links.joint_names[0]
        lim = self.limits
        alim = None
        if lim.active:
            lo, hi = lim.bounds(joint)
            U = lim.input_bound(f"u_{joint}")
            sb = {"phi": (None if lo == -math.inf else lo + delta, None if hi == math.inf else hi + delta)} \
                if (lo > -math.inf or hi < math.inf) else {}
            alim = Limits(sb, {"u": U} if U is not None else None)
        return acro, psi0, delta, joint, alim

    def _reach_two_links(self) -> list[dict]:
        """The exact interval of a two-link body: it is an acrobot (``PlanarBody.as_acrobot``)."""
        acro, psi0, delta, joint, alim = self.two_link()
        out = []
        for k, x0, x1, T in self._segments():
            kw = dict(theta0=float(x0[0]) + psi0, phi0=float(x0[1]) + delta, phiT=float(x1[1]) + delta, T=T)
            free = reachable_set(acro, **kw)
            R = reachable_set(acro, **kw, limits=alim) if alim is not None else free
            shift = lambda r: None if r.empty else [r.low - psi0, r.high - psi0]  # noqa: E731
            target = float(x1[0])
            inside = R.contains(target + psi0)
            out.append({
                "index": k, "t0": self.times[k], "t1": self.times[k + 1], "theta0": float(x0[0]),
                "joint": joint, "joint0": float(x0[1]), "jointT": float(x1[1]), "target_theta": target,
                "kind": "exact (a two-link body is an acrobot)",
                "interval": shift(free), "interval_closed": free.closed,
                "interval_with_limits": shift(R), "with_limits_closed": R.closed,
                "empty_reason": R.reason or None, "reachable": bool(inside),
            })
        return out

    def _reach_bound(self) -> list[dict]:
        body = self.system
        lim = self.limits
        unlimited = [j for j in body.links.joint_names if lim.input_bound(f"u_{j}") is None]
        if unlimited:
            raise InvalidInputError(
                "reach", f"exact reachable sets exist for the two-link body only, and this body has "
                f"{body.n_links} links; joint {unlimited[0]!r} has no rate limit, so no bound on theta(T) is known "
                "either", f"give every joint a rate limit (limits.u_{unlimited[0]} or limits.u_max) to get a proven "
                "bound, or plan the file with acroplan plan")
        out = []
        for k, x0, x1, T in self._segments():
            B = float(body.turn_bound(x0, x1, T, lim))
            proof = body.check_segment(x0, x1, T, lim)
            target = float(x1[0])
            out.append({
                "index": k, "t0": self.times[k], "t1": self.times[k + 1], "theta0": float(x0[0]),
                "start": dict(zip(body.state_names, map(float, x0))),
                "end": dict(zip(body.state_names[1:], map(float, x1[1:]))), "target_theta": target,
                "kind": "bound (rate limits): |theta(T) - theta(0)| <= B; inside it is not proven reachable",
                "bound": B, "interval": None, "interval_closed": True,
                "interval_with_limits": [float(x0[0]) - B, float(x0[0]) + B], "with_limits_closed": True,
                "empty_reason": None if proof is None else proof.reason,
                "reachable": False if proof is not None else None,
            })
        return out


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
        from ..simulation import simulate

        if verify != "family":
            # "ode" by name: simulate(verify=True) is the family's own check when the family has one
            res = simulate(self.system, verify="ode" if verify in (True, "ode") else False, **self.simulate_kwargs())
            return dataclasses.replace(res, verification="ode") if res.verified and res.verification is None else res
        from ..core.result import PlanResult, Status
        from ..core.verify import verify_plan

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


def parse_robot(data: dict) -> Acrobot:
    """An :class:`Acrobot` from a ``[robot]`` table (physical or lumped keys)."""
    if isinstance(data, dict):
        for alias, key in ALIASES.items():
            if alias in data:
                if key in data:
                    raise InvalidInputError(f"robot.{alias}", f"is the same distance as robot.{key}; give one of them",
                                            f"keep {alias} (the clearer name) and drop {key}")
                data = {**{k: v for k, v in data.items() if k != alias}, key: data[alias]}
    _check_keys("robot", data, PHYSICAL_KEYS + LUMPED_KEYS + tuple(ALIASES))
    phys = [k for k in PHYSICAL_KEYS if k in data]
    lump = [k for k in LUMPED_KEYS if k in data]
    if phys and lump:
        raise InvalidInputError("robot", f"mixes physical keys {phys} with lumped keys {lump}",
                                "give either the physical body or the lumped parameters")
    if phys:
        missing = [k for k in PHYSICAL_KEYS if k not in data]
        if missing:
            raise InvalidInputError(f"robot.{missing[0]}", "is missing", f"the physical body needs {list(PHYSICAL_KEYS)}")
        vals = {k: _number(f"robot.{k}", data[k], MAX_BODY, _BODY) for k in PHYSICAL_KEYS}
        for k in ("torso_mass", "leg_mass", "torso_inertia", "leg_inertia"):
            if 0 < vals[k] < MIN_BODY:
                raise InvalidInputError(f"robot.{k}", f"is {vals[k]:.3g}: masses and inertias below {MIN_BODY:g} "
                                        "are less than the arithmetic carries",
                                        "change the units so that the numbers come nearer to 1")
        try:
            robot = Acrobot.from_physical(**vals)
        except InvalidInputError as e:
            field = e.field if e.field.startswith("robot.") else f"robot.{e.field}"
            raise InvalidInputError(field, e.problem, e.fix) from None
        _check_lumped(robot, vals)
        return robot
    missing = [k for k in LUMPED_KEYS if k not in data]
    if missing:
        raise InvalidInputError(f"robot.{missing[0]}", "is missing",
                                f"give the physical body {list(PHYSICAL_KEYS)} or all of {list(LUMPED_KEYS)}")
    vals = {k: _number(f"robot.{k}", data[k], MAX_BODY, _BODY) for k in LUMPED_KEYS}
    try:
        robot = Acrobot(**vals)
    except InvalidInputError as e:
        field = e.field if e.field.startswith("robot.") else f"robot.{e.field}"
        raise InvalidInputError(field, e.problem, e.fix) from None
    _check_lumped(robot, None)
    return robot


def _check_lumped(robot: Acrobot, physical: dict | None) -> None:
    """Refuse lumped parameters the arithmetic cannot carry: |value| > MAX_BODY, or M1 < MIN_BODY
    (its square vanishes). For a physical body the field named is the key behind it (the largest
    length, mass or inertia; the momentum for P0; the smaller inertia for a tiny M1)."""
    fix = "change the units so that the numbers come nearer to 1"
    for k in LUMPED_KEYS:
        v = float(getattr(robot, k))
        if not (math.isfinite(v) and abs(v) <= MAX_BODY):
            why = f"{k} = {v:.3g}, beyond {MAX_BODY:g} in size, more than the arithmetic carries"
            if physical is None:
                raise InvalidInputError(f"robot.{k}", f"is {v:.3g}, beyond {MAX_BODY:g} in size: more than the "
                                        "arithmetic carries", fix)
            big = "angular_momentum" if k == "P0" else max(PHYSICAL_KEYS[:6], key=lambda q: abs(physical[q]))
            raise InvalidInputError(f"robot.{big}", f"is {physical[big]:.3g}, which makes {why}", fix)
    if not robot.M1 >= MIN_BODY:
        if physical is None:
            raise InvalidInputError("robot.M1", f"is {robot.M1:.3g}, below {MIN_BODY:g}: less than the arithmetic "
                                    "carries", fix)
        small = min(("torso_inertia", "leg_inertia"), key=lambda q: physical[q])
        raise InvalidInputError(f"robot.{small}", f"is {physical[small]:.3g}, which makes M1 = {robot.M1:.3g}, below "
                                f"{MIN_BODY:g}, less than the arithmetic carries", fix)




# ------------------------------------------------------------------------------- [body]
def _renamed(e: InvalidInputError, old: str, new: str) -> InvalidInputError:
    """``e`` with its field's prefix ``old`` (``links``) written as the file's ``new`` (``body.link``)."""
    field = e.field
    if field == old or field.startswith((old + "[", old + ".")):
        field = new + field[len(old):]
    return InvalidInputError(field, e.problem, e.fix)


def _link_records(tables, allowed, joint_keys: str):
    """``(field, table, names)`` for each ``[[body.link]]`` table: the array checked (not empty, at
    most :data:`MAX_LINKS`), each table's keys checked against ``allowed``, its name fields read; the
    families' readers add the numbers."""
    if not isinstance(tables, list) or not tables or not all(isinstance(t, dict) for t in tables):
        raise InvalidInputError("body.link", f"must be an array of tables ([[body.link]]), got {_short(tables)}",
                                "write one [[body.link]] table per link (docs/problem-files.md)")
    if len(tables) > MAX_LINKS:
        raise InvalidInputError("body.link", f"has {len(tables)} links, more than {MAX_LINKS}: the compiled "
                                "integrator of such a body takes hours to build", f"give at most {MAX_LINKS} links "
                                "(join links that move together)")
    for i, d in enumerate(tables):
        f = f"body.link[{i}]"
        _check_keys(f, d, allowed)
        for key in ("name", "mass", "inertia"):
            if key not in d:
                raise InvalidInputError(f"{f}.{key}", "is missing", "give every link a name, mass and inertia (and "
                                        f"every link but the root its {joint_keys})")
        yield f, d, {k: _name_field(f"{f}.{k}", d[k]) for k in ("name", "parent", "joint_name") if k in d}


def _links_from_tables(tables) -> list:
    """:class:`~acroplan.families.planar.links.Link` records from ``[[body.link]]`` tables (numbers
    checked and arithmetic read here; the tree is checked by ``LinkTable``)."""
    from ..families.planar.links import Link

    links = []
    for f, d, kw in _link_records(tables, LINK_KEYS, "parent and joint"):
        for key in ("mass", "inertia"):
            v = _number(f"{f}.{key}", d[key], MAX_BODY, _BODY)
            if 0 < v < MIN_BODY:
                raise InvalidInputError(f"{f}.{key}", f"is {v:.3g}: masses and inertias below {MIN_BODY:g} are less "
                                        "than the arithmetic carries",
                                        "change the units so that the numbers come nearer to 1")
            kw[key] = v
        for key in ("com", "joint"):
            if key in d:
                kw[key] = _pair_field(f"{f}.{key}", d[key])
        for key in ("lower", "upper"):
            if key in d:
                kw[key] = _number(f"{f}.{key}", d[key], MAX_ANGLE, "angles")
        if "velocity" in d:
            kw["velocity"] = _number(f"{f}.velocity", d["velocity"], MAX_BODY, "rates")
        kw.setdefault("parent", None)
        links.append(Link(**kw))
    return links


def _urdf_table(value, base, spatial: bool = False):
    """The link table of the URDF file ``value`` (relative to ``base``), read by Pinocchio (a
    spatial body's with :func:`acroplan.families.spatial.urdf.read_link_table`)."""
    if spatial:
        from ..families.spatial.urdf import read_link_table
    else:
        from ..families.planar.urdf import read_link_table

    if not isinstance(value, str) or not value.strip():
        raise InvalidInputError("body.urdf", f"must be the path of a URDF file in quotes, got {_short(value)}",
                                "write for example urdf = \"diver.urdf\"")
    path = Path(value)
    if not path.is_absolute() and base is not None:
        path = Path(base) / path
    if not path.is_file():
        raise InvalidInputError("body.urdf", f"no such file: {_short(str(path), 200)}",
                                "give the path of a .urdf file (a relative path is read from the problem file's "
                                "folder)")
    if path.stat().st_size > MAX_FILE_BYTES:
        raise InvalidInputError("body.urdf", f"{path.name} is larger than {MAX_FILE_BYTES // 1_000_000} MB",
                                "give the URDF of a " + ("spatial" if spatial else "planar") + " body")
    try:
        table = read_link_table(path)
    except InvalidInputError as e:
        what = e.problem if e.field == "urdf" else f"{e.field} {e.problem}"
        raise InvalidInputError("body.urdf", f"{path.name}: {what}", e.fix) from None
    if len(table) > MAX_LINKS:
        raise InvalidInputError("body.urdf", f"{path.name} has {len(table)} moving links, more than {MAX_LINKS}: "
                                "the compiled integrator of such a body takes hours to build",
                                f"give at most {MAX_LINKS} links (join links that move together with fixed joints)")
    return table


_UNSET = object()


def _apply_limits(table, lim, degrees: bool):
    """The link table with the file's ``[limits]`` written into it (per joint ``NAME_min``,
    ``NAME_max``, ``u_NAME``; ``u_max`` for every joint; ``"none"`` drops a limit)."""
    names = table.joint_names
    allowed = ("u_max",) + tuple(k for j in names for k in (f"{j}_min", f"{j}_max", f"u_{j}"))
    _check_keys("limits", lim, allowed)
    if not lim:
        return table

    def value(key, angle: bool):
        v = lim[key]
        if isinstance(v, str) and v.strip().lower() == "none":
            return None
        x = _number(f"limits.{key}", v, *((MAX_ANGLE, "angles") if angle else (MAX_BODY, "rates")))
        return math.radians(x) if degrees else x

    u_all = value("u_max", False) if "u_max" in lim else _UNSET
    links = list(table.links)
    for j, i in zip(names, table.joints):
        link = links[i]
        lo = value(f"{j}_min", True) if f"{j}_min" in lim else link.lower
        hi = value(f"{j}_max", True) if f"{j}_max" in lim else link.upper
        key = f"u_{j}" if f"u_{j}" in lim else "u_max"
        vel = value(key, False) if f"u_{j}" in lim else (link.velocity if u_all is _UNSET else u_all)
        if vel is not None and not vel > 0:
            raise InvalidInputError(f"limits.{key}", f"must be > 0, got {vel:g}",
                                    "give the joint's top speed in rad/s, or \"none\" for no rate limit")
        if lo is not None and hi is not None and not lo < hi:
            field, other = (f"{j}_min", f"{j}_max") if f"{j}_min" in lim else (f"{j}_max", f"{j}_min")
            whose = "" if other in lim else " (the body's own)"
            raise InvalidInputError(f"limits.{field}", f"must be {'<' if field.endswith('min') else '>'} "
                                    f"limits.{other}{whose}, got {j}_min = {lo:.12g}, {j}_max = {hi:.12g}",
                                    "swap or widen the joint limits")
        links[i] = dataclasses.replace(link, lower=lo, upper=hi, velocity=vel)
    return type(table)(links)  # a planar LinkTable or a SpatialLinkTable


def parse_body(data: dict, limits: dict | None = None, *, base=None, degrees: bool = False):
    """A :class:`~acroplan.families.planar.model.PlanarBody` from a ``[body]`` table (or, for a human
    body split at the hips, an :class:`Acrobot`).

    Parameters
    ----------
    data : dict
        The ``[body]`` table: ``angular_momentum`` and either ``urdf`` (a path, relative to
        ``base``) or ``link`` (the ``[[body.link]]`` tables, :class:`~acroplan.families.planar.links.Link`'s
        fields), or a human body (:data:`HUMAN_KEYS`: ``yeadon``, a measurement file relative to
        ``base`` or a bundled sample's name, or ``height``, ``mass``, ``sex``; ``split``,
        ``position``, ``knee_flexion``, ``shoulder_flexion``; module docstring).
    limits : dict, optional
        The file's ``[limits]``: ``NAME_min``, ``NAME_max`` (joint angles), ``u_NAME`` (rate),
        ``u_max`` (every joint's rate); ``"none"`` drops the URDF's, the table's or the human
        position's limit. Written into the link table (an acrobot's limits are plan options, read
        by :func:`parse_problem` with the position's as defaults: not used here).
    base : path, optional
        The problem file's folder (default: the current folder).
    degrees : bool
        ``limits`` in degrees and degrees per second.

    Returns
    -------
    PlanarBody or Acrobot

    Raises
    ------
    InvalidInputError
        Naming the file's field (``body.link[2].mass``, ``body.urdf``, ``body.yeadon``,
        ``limits.u_hip``); ``body.yeadon`` with ``pip install "acroplan[human]"`` when yeadon is
        not installed.
    """
    return _parse_body(data, limits, base=base, degrees=degrees)[0]


def _parse_body(data: dict, limits: dict | None = None, *, base=None, degrees: bool = False):
    """:func:`parse_body`, and the default ``[limits]`` of a human body split at the hips (an acrobot,
    whose limits are plan options): ``(system, {"phi_min": ..., "phi_max": ..., "u_max": ...})``,
    in radians; ``{}`` for any other body."""
    from ..families.planar.links import LinkTable
    from ..families.planar.model import PlanarBody

    _check_keys("body", data, BODY_KEYS)
    if isinstance(data.get("angular_momentum"), list):  # [Lx, Ly, Lz]: a spatial body
        return _spatial_body(data, limits, base=base, degrees=degrees), {}
    human = [k for k in HUMAN_KEYS if k in data]
    if human:
        return _human_body(data, human, limits, base=base, degrees=degrees)
    if "urdf" in data and "link" in data:
        raise InvalidInputError("body", "gives both urdf and [[body.link]] tables",
                                "describe the body one way: a URDF file or link tables")
    if "urdf" not in data and "link" not in data:
        raise InvalidInputError("body.urdf", "is missing, and there are no [[body.link]] tables",
                                "give urdf = \"body.urdf\" or one [[body.link]] table per link; for a human body "
                                "yeadon = \"male1\" (a measurement file or a bundled sample) or height and mass")
    if "angular_momentum" not in data:
        raise InvalidInputError("body.angular_momentum", "is missing", "give P0, the angular momentum about the "
                                "axis normal to the plane (0 for a body that starts at rest)")
    P0 = _number("body.angular_momentum", data["angular_momentum"], MAX_BODY, _BODY)
    where = "body.urdf" if "urdf" in data else "body.link"
    if "urdf" in data:
        table = _urdf_table(data["urdf"], base)
    else:
        try:
            table = LinkTable(_links_from_tables(data["link"]))
        except InvalidInputError as e:
            e = _renamed(e, "links", "body.link")
            if e.field.startswith("body.link[") and _looks_spatial(data["link"]):
                raise InvalidInputError(e.field, e.problem, e.fix + "; for a body in 3-D give angular_momentum = "
                                        "[Lx, Ly, Lz] (a list of three numbers makes the body spatial)") from None
            raise e from None
    table = _apply_limits(table, {} if limits is None else limits, degrees)
    try:
        body = PlanarBody(table, P0=P0)
    except InvalidInputError as e:
        raise _renamed(_renamed(e, "links", where), "P0", "body.angular_momentum") from None
    for k, v in body.lumped().items():
        if not (math.isfinite(v) and abs(v) <= MAX_BODY):
            raise InvalidInputError(where, f"makes the lumped parameter {k} = {v:.3g}, beyond {MAX_BODY:g} in size: "
                                    "more than the arithmetic carries",
                                    "change the units so that the numbers come nearer to 1")
    return body, {}


# ---------------------------------------------------------------------- a spatial [body]
def _looks_spatial(tables) -> bool:
    """Whether ``[[body.link]]`` tables look like a spatial body's (an axis, a rotation, or a
    3-vector ``com`` or ``joint``): the hint of a planar reader's error."""
    if not isinstance(tables, list):
        return False
    for d in tables:
        if isinstance(d, dict) and ("axis" in d or "rotation" in d or any(
                isinstance(d.get(k), list) and len(d[k]) == 3 for k in ("com", "joint"))):
            return True
    return False


def _spatial_links_from_tables(tables) -> list:
    """:class:`~acroplan.families.spatial.links.SpatialLink` records from ``[[body.link]]`` tables
    (numbers checked and arithmetic read here; the tree and the inertias by ``SpatialLinkTable``)."""
    from ..families.spatial.links import SpatialLink

    links = []
    for f, d, kw in _link_records(tables, SPATIAL_LINK_KEYS, "parent, joint and axis"):
        kw["mass"] = _number(f"{f}.mass", d["mass"], MAX_BODY, _BODY)
        inertia = d["inertia"]
        if isinstance(inertia, list) and inertia and all(isinstance(r, list) for r in inertia):
            kw["inertia"] = _matrix3(f"{f}.inertia", inertia, "[[0.1, 0, 0], [0, 0.2, 0], [0, 0, 0.2]]")
        else:
            kw["inertia"] = list(_vector3(f"{f}.inertia", inertia))
        for key in ("com", "joint", "axis"):
            if key in d:
                kw[key] = _vector3(f"{f}.{key}", d[key])
        if "rotation" in d:
            kw["rotation"] = _matrix3(f"{f}.rotation", d["rotation"], "[[1, 0, 0], [0, 0, -1], [0, 1, 0]]")
        for key in ("lower", "upper"):
            if key in d:
                kw[key] = _number(f"{f}.{key}", d[key], MAX_ANGLE, "angles")
        if "velocity" in d:
            kw["velocity"] = _number(f"{f}.velocity", d["velocity"], MAX_BODY, "rates")
        kw.setdefault("parent", None)
        links.append(SpatialLink(**kw))
    return links


def _spatial_body(data: dict, limits: dict | None, *, base, degrees: bool):
    """A :class:`~acroplan.families.spatial.model.SpatialBody` from ``[body]`` with
    ``angular_momentum = [Lx, Ly, Lz]`` (module docstring)."""
    from ..families.spatial.links import SpatialLinkTable
    from ..families.spatial.model import SpatialBody

    human = [k for k in HUMAN_KEYS if k in data]
    if human:
        raise InvalidInputError(f"body.{human[0]}", "is a key of a human (planar) body, and angular_momentum is a "
                                "vector [Lx, Ly, Lz], which makes the body spatial",
                                "give a spatial body by urdf or [[body.link]] tables, or a human body with "
                                "angular_momentum a number")
    if "urdf" in data and "link" in data:
        raise InvalidInputError("body", "gives both urdf and [[body.link]] tables",
                                "describe the body one way: a URDF file or link tables")
    if "urdf" not in data and "link" not in data:
        raise InvalidInputError("body.urdf", "is missing, and there are no [[body.link]] tables",
                                "give urdf = \"body.urdf\" or one [[body.link]] table per link (name, parent, mass, "
                                "inertia, com, joint, axis)")
    L = _vector3("body.angular_momentum", data["angular_momentum"])
    where = "body.urdf" if "urdf" in data else "body.link"
    if "urdf" in data:
        table = _urdf_table(data["urdf"], base, spatial=True)
    else:
        try:
            table = SpatialLinkTable(_spatial_links_from_tables(data["link"]))
        except InvalidInputError as e:
            raise _renamed(e, "links", "body.link") from None
    table = _apply_limits(table, {} if limits is None else limits, degrees)
    try:
        return SpatialBody(table, L=L)
    except InvalidInputError as e:
        raise _renamed(_renamed(e, "links", where), "L", "body.angular_momentum") from None


def _is_spatial(system) -> bool:
    return type(system).__name__ == "SpatialBody" and type(system).__module__.startswith("acroplan.families.spatial")


def _attitude_entry(field: str, value, single: str | None):
    """One attitude as :func:`~acroplan.families.spatial.rotations.as_quaternion` takes it, its
    numbers read here (arithmetic with pi allowed): a quaternion ``[w, x, y, z]``, an inline table
    ``{euler_deg = [...]}`` (``quaternion``, ``rotvec``, ``rotvec_deg``, ``euler``, ``euler_deg``,
    optional ``seq``), or, under ``single`` (a form's own key), that form's three numbers."""
    if single is not None:
        return {single: list(_vector3(field, value, MAX_ANGLE, "angles"))}
    if isinstance(value, list):
        return list(_numbers(field, value, MAX_ANGLE, "angles"))
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if k == "seq":
                if not isinstance(v, str):
                    raise InvalidInputError(f"{field}.seq", f"must be a name in quotes, got {_short(v)}",
                                            "write seq = \"yeadon\" or for example \"ZYX\"")
                out[k] = v
            elif k in ATTITUDE_FORMS:
                out[k] = list(_numbers(f"{field}.{k}", v, MAX_ANGLE, "angles"))
            else:
                raise InvalidInputError(f"{field}.{k}", "is not a form of attitude",
                                        f"give one of {list(ATTITUDE_FORMS)} (and optionally seq)")
        return out
    raise InvalidInputError(field, f"must be a quaternion [w, x, y, z] or a table such as {{euler_deg = [0, 0, 90]}}, "
                            f"got {_short(value)}", "write for example [1, 0, 0, 0]")


def _attitude_key(table: str, d: dict) -> str:
    """The one attitude key of ``d`` (``[plan]`` or ``[simulate]``), refusing none or several."""
    given = [k for k in ATTITUDE_KEYS if k in d]
    if not given:
        raise InvalidInputError(f"{table}.attitude", "is missing: a spatial body's state starts with the root's "
                                "attitude", "give attitude = [[w, x, y, z], ...] (one per waypoint; or "
                                "attitude_euler_deg = [[somersault, tilt, twist], ...], attitude_rotvec_deg, ...)"
                                if table == "plan" else "give attitude = [w, x, y, z] (the initial attitude; or "
                                "attitude_euler_deg = [somersault, tilt, twist], ...)")
    if len(given) > 1:
        raise InvalidInputError(f"{table}.{given[1]}", f"is given together with {table}.{given[0]}",
                                "give the attitude in one form")
    return given[0]


def _euler_seq(table: str, d: dict, key: str):
    seq = d.get("attitude_seq")
    if seq is None:
        return None
    if key not in ("attitude_euler", "attitude_euler_deg"):
        raise InvalidInputError(f"{table}.attitude_seq", f"is the sequence of Euler angles, and the attitude is "
                                f"given by {table}.{key}", f"drop {table}.attitude_seq, or give the attitude in Euler "
                                "angles")
    if not isinstance(seq, str):
        raise InvalidInputError(f"{table}.attitude_seq", f"must be a name in quotes, got {_short(seq)}",
                                "write attitude_seq = \"yeadon\" or for example \"ZYX\"")
    return seq


def _attitudes(table: str, d: dict, count: int | None) -> dict[str, tuple]:
    """The waypoints ``qw, qx, qy, qz`` from the attitude keys of ``d`` (``count`` waypoints; ``None``:
    one initial attitude)."""
    from ..families.spatial.rotations import attitude_states

    key = _attitude_key(table, d)
    field = f"{table}.{key}"
    seq = _euler_seq(table, d, key)
    single = ATTITUDE_KEYS[key]
    values = d[key] if count is not None else [d[key]]
    if count is not None:
        if not isinstance(values, list):
            raise InvalidInputError(field, f"must be a list of attitudes, one per waypoint, got {_short(values)}",
                                    "write for example [[1, 0, 0, 0], [0, 0, 0, 1]]" if key == "attitude" else
                                    "write for example [[0, 0, 0], [0, 0, 90]]")
        if len(values) != count:
            raise InvalidInputError(field, f"has {len(values)} attitude(s) but {table}.times has {count}",
                                    "give one attitude per waypoint")
    entries = []
    for i, v in enumerate(values):
        e = _attitude_entry(f"{field}[{i}]" if count is not None else field, v, single)
        if seq is not None:
            e["seq"] = seq
        entries.append(e)
    try:
        kw = attitude_states(entries, field=field)
    except InvalidInputError as e:
        f = e.field if e.field.startswith(field) else f"{field}.{e.field}"
        if count is None:
            f = f.replace(f"{field}[0]", field)
        raise InvalidInputError(f, e.problem, e.fix) from None
    return {k: tuple(v) for k, v in kw.items()}


_INSTALL_HUMAN = 'pip install "acroplan[human]"'


def _yeadon_path(value, base) -> str:
    """The measurement file ``body.yeadon`` names: a bundled sample by name, or a path relative to the
    problem file's folder."""
    from ..families.human.yeadon_body import SAMPLES, sample_measurements

    if not isinstance(value, str) or not value.strip():
        raise InvalidInputError("body.yeadon", "must be a measurement file or a bundled sample's name in quotes, "
                                f"got {_short(value)}", "write for example yeadon = \"male1\" (bundled: "
                                f"{sorted(SAMPLES)}) or yeadon = \"measurements.txt\"")
    if value in SAMPLES:
        return sample_measurements(value)
    path = Path(value)
    if not path.is_absolute() and base is not None:
        path = Path(base) / path
    if not path.is_file():
        raise InvalidInputError("body.yeadon", f"no such file: {_short(str(path), 200)}",
                                "give a yeadon measurement file (95 measurements in yeadon's format; a relative path "
                                "is read from the problem file's folder) or a bundled sample's name "
                                f"({sorted(SAMPLES)})")
    if path.stat().st_size > MAX_FILE_BYTES:
        raise InvalidInputError("body.yeadon", f"{path.name} is larger than {MAX_FILE_BYTES // 1_000_000} MB",
                                "give a yeadon measurement file (95 measurements, a few kB)")
    return str(path)


#: the human family's argument names as the file names them
_HUMAN_FIELDS = {"height": "body.height", "mass": "body.mass", "sex": "body.sex", "knee_flexion": "body.knee_flexion",
                 "measurements": "body.yeadon", "shoulder_flexion": "body.shoulder_flexion",
                 "angular_momentum": "body.angular_momentum"}


def _human_error(e: InvalidInputError, source: str) -> InvalidInputError:
    """The human family's error with its field as the file names it (a part's mass or inertia that a
    measurement file makes non-physical: the file's field ``source``)."""
    head = e.field.split(".", 1)[0].split("[", 1)[0]
    if head in _HUMAN_FIELDS and not (head == "mass" and source == "body.yeadon"):
        return InvalidInputError(_HUMAN_FIELDS[head] + e.field[len(head):], e.problem, e.fix)
    return InvalidInputError(source, f"makes {e.field} {e.problem}", e.fix)


def _human_body(data: dict, given: list, limits: dict | None, *, base, degrees: bool):
    """A human body from ``[body]`` (``yeadon`` or ``height``/``mass``; module docstring), and the
    default limits of an acrobot (:func:`_parse_body`)."""
    other = [k for k in ("urdf", "link") if k in data]
    if other:
        what = "urdf" if other[0] == "urdf" else "[[body.link]] tables"
        raise InvalidInputError(f"body.{given[0]}", f"is a key of a human body, and this [body] gives {what}",
                                f"describe the body one way: a URDF, link tables, or a human body (yeadon, or height "
                                f"and mass); drop body.{given[0]} or body.{other[0]}")
    deleva = [k for k in ("height", "mass", "sex") if k in data]
    if "yeadon" in data and deleva:
        raise InvalidInputError(f"body.{deleva[0]}", "is given together with body.yeadon: the measurement file gives "
                                "the whole body", "give yeadon = \"...\" (Yeadon's 95 measurements) or height and "
                                "mass (de Leva's tables), not both")
    if "yeadon" not in data:
        for key in ("height", "mass"):
            if key not in data:
                raise InvalidInputError(f"body.{key}", "is missing" + ("" if deleva else
                                        ": a human body needs yeadon = \"...\" or height and mass"),
                                        "give height (m) and mass (kg) for de Leva's tables, or yeadon = \"male1\" "
                                        "(a measurement file or a bundled sample)")
    if "angular_momentum" not in data:
        raise InvalidInputError("body.angular_momentum", "is missing", "give P0, the angular momentum about the "
                                "somersault axis in kg m^2/s (> 0 for a forward somersault; acroplan least-momentum "
                                "gives the least one for the file's turn)")
    P0 = _number("body.angular_momentum", data["angular_momentum"], MAX_BODY, _BODY)
    split = _choice_field("body.split", data.get("split", "hips"), SPLITS, "hips")
    from ..families.human.limits import POSITIONS, human_limits, position

    pos = data.get("position")
    if pos is not None:
        pos = _choice_field("body.position", pos, tuple(POSITIONS), "pike")
    kappa = (_number("body.knee_flexion", data["knee_flexion"], MAX_ANGLE, "angles") if "knee_flexion" in data
             else position(pos).knee_flexion if pos is not None else 0.0)
    sigma = 0.0
    if "shoulder_flexion" in data:
        if split != "hips":
            raise InvalidInputError("body.shoulder_flexion", f"is the arms' fixed angle of split = \"hips\", and this "
                                    f"body is split = \"{split}\": its arms move (the joint shoulder)",
                                    "give the shoulder's angles in [plan].shoulder, and drop body.shoulder_flexion")
        sigma = _number("body.shoulder_flexion", data["shoulder_flexion"], MAX_ANGLE, "angles")
        if not -math.pi <= sigma <= math.pi:
            raise InvalidInputError("body.shoulder_flexion", f"must be an angle in radians in [-pi, pi], got {sigma:g}",
                                    "write for example shoulder_flexion = \"pi/2\" (arms forward; 0: at the sides, "
                                    "pi: overhead)")
    source = "body.yeadon" if "yeadon" in data else "body.height"
    try:
        if "yeadon" in data:
            path = _yeadon_path(data["yeadon"], base)
            from ..families.human.yeadon_body import from_yeadon

            try:
                body = from_yeadon(path, knee_flexion=kappa)
            except ImportError:
                raise InvalidInputError("body.yeadon", "needs the yeadon package (Yeadon's inertia model), which is "
                                        "not installed", f"{_INSTALL_HUMAN}; or give height and mass instead of "
                                        "yeadon (de Leva's tables need nothing more)") from None
        else:
            from ..families.human.deleva import from_height_mass

            height = _number("body.height", data["height"], MAX_BODY, _BODY)
            mass = _number("body.mass", data["mass"], MAX_BODY, _BODY)
            sex = data.get("sex", "male")
            if not isinstance(sex, str):
                raise InvalidInputError("body.sex", f"must be \"male\" or \"female\" in quotes, got {_short(sex)}",
                                        "write sex = \"female\" or leave it out (male)")
            body = from_height_mass(height, mass, sex=sex, knee_flexion=kappa)
    except InvalidInputError as e:
        raise (e if e.field.startswith("body.") else _human_error(e, source)) from None
    lim = None
    if pos is not None:
        try:
            lim = human_limits(body, pos, links=2 if split == "hips" else 3, shoulder_flexion=sigma)
        except InvalidInputError as e:
            if e.field != "position":  # pragma: no cover - the arguments were checked above
                raise _human_error(e, "body.position") from None
            raise InvalidInputError("body.knee_flexion", f"is {kappa:.6g} rad, and position = \"{pos}\" holds the "
                                    f"knees at {position(pos).knee_flexion:.6g} rad", "leave body.knee_flexion out "
                                    "(the position's knees), or drop body.position and give the [limits]") from None
    try:
        if split == "hips":
            robot = body.two_link(angular_momentum=P0, shoulder_flexion=sigma)
            defaults = {} if lim is None else {**{f"phi_{e}": v for e, v in zip(("min", "max"), lim.bounds("phi"))},
                                               "u_max": lim.u_max}
            return robot, defaults
        planar = body.three_part(angular_momentum=P0, limits=lim)
    except InvalidInputError as e:  # pragma: no cover - a human body's parts are physical
        raise _human_error(e, source) from None
    from ..families.planar.model import PlanarBody

    table = _apply_limits(planar.links, {} if limits is None else limits, degrees)
    return (planar if table is planar.links else PlanarBody(table, P0=P0)), {}


def _system_table(data: dict) -> str:
    """``"robot"`` or ``"body"``: which table describes the system (refusing both and neither)."""
    if "robot" in data and "body" in data:
        raise InvalidInputError("[body]", "is given together with [robot]", "give [robot] for the two-link acrobot "
                                "or [body] for a planar body of any number of links, not both")
    if "robot" not in data and "body" not in data:
        raise InvalidInputError("robot", "table is missing", "add a [robot] table (the two-link acrobot) or a "
                                "[body] table (a planar body, or a human body; see docs/problem-files.md)")
    return "robot" if "robot" in data else "body"


def _degrees(data: dict) -> bool:
    opts = data.get("options")
    return isinstance(opts, dict) and opts.get("degrees") is True


def _parse_system(data: dict, base) -> tuple[ControlAffineSystem, dict]:
    """The system, and the default limits of a human body split at the hips (:func:`_parse_body`)."""
    if _system_table(data) == "robot":
        return parse_robot(data["robot"]), {}
    lim = data.get("limits", {})
    return _parse_body(data["body"], lim, base=base, degrees=_degrees(data))


# ----------------------------------------------------------------------------- [options]
def _choice(names: tuple[str, ...]):
    def parse(field, v, system):
        if not isinstance(v, str) or v not in names:
            raise InvalidInputError(field, f"must be one of {list(names)}, got {_short(v)}",
                                    f"write {field.rsplit('.', 1)[-1]} = \"{names[0]}\"")
        return v
    return parse


def _whole_option(most: int, example: str):
    def parse(field, v, system):
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= most:
            raise InvalidInputError(field, f"must be a whole number from 1 to {most}, got "
                                    f"{_short(v) if not isinstance(v, int) or abs(v) < 10**30 else 'a huge integer'}",
                                    f"write for example {example}")
        return v
    return parse


def _time_limit(field, v, system):
    return _number(field, v, 1e7, "seconds")


def _bool_option(field, v, system):
    if not isinstance(v, bool):
        raise InvalidInputError(field, f"must be true or false, got {_short(v)}",
                                f"write {field.rsplit('.', 1)[-1]} = true")
    return v


def _rate_option(field, v, system):
    """A number (every input), or for several inputs a table by input name."""
    if isinstance(v, dict):
        out = {}
        for k, x in v.items():
            if k not in system.input_names:
                shown = k if len(k) <= 60 and k.isprintable() else _short(k, 60)
                raise InvalidInputError(f"{field}.{shown}", "is not an input",
                                        f"inputs are {list(system.input_names)}")
            out[k] = _number(f"{field}.{k}", x, MAX_BODY, "rates")
        return out
    return _number(field, v, MAX_BODY, "rates")


def _tol(field, v, system):
    tol = _number(field, v)
    if not TOL_RANGE[0] <= tol <= TOL_RANGE[1]:
        raise InvalidInputError(field, f"is {tol:.3g}; tolerances outside [{TOL_RANGE[0]:g}, {TOL_RANGE[1]:g}] are "
                                "beyond what double precision can meet or mean", "write for example 1e-10")
    return tol


OBJECTIVES = ("energy", "torque")


def torque_joints(field: str, system) -> tuple[str, ...]:
    """The joints of ``system``'s torque model (the acrobot's ``("phi",)``, a body's joint names), or
    :class:`InvalidInputError` naming ``field`` when the system gives no torques."""
    from ..core.system import torque_model_of

    model, why = torque_model_of(system)
    if model is None:
        if isinstance(system, Acrobot):
            raise InvalidInputError(field, "needs the joint torque, and this [robot] is given by its lumped "
                                    "parameters M1, A1, M2, A2, P0, which fix the motion but not the torque's scale",
                                    "give the physical body in [robot] (torso_mass, leg_mass, torso_inertia, "
                                    f"leg_inertia, torso_length, leg_length, angular_momentum), or leave {field} out")
        raise InvalidInputError(field, f"needs the joint torques, and {why}", f"leave {field} out")
    return tuple(str(n) for n in model.joint_names)


def _objective_option(field, v, system):
    """``"energy"`` (least integral of u^2) or ``"torque"`` (least integral of tau^2, needs torques)."""
    if not isinstance(v, str) or v not in OBJECTIVES:
        raise InvalidInputError(field, f"must be \"energy\" or \"torque\", got {_short(v)}",
                                _close(v, OBJECTIVES) + "write objective = \"energy\" (least integral of u^2) or "
                                "\"torque\" (least integral of tau^2), or leave it out for the fast feasible plan")
    if v == "torque":
        try:
            torque_joints(field, system)
        except InvalidInputError as e:
            raise InvalidInputError(e.field, e.problem, e.fix.replace(f"leave {field} out",
                                                                      "write objective = \"energy\"")) from None
    return v


def _torque_value(field, v):
    x = _number(field, v, MAX_BODY, "torques")
    if not x > 0:
        raise InvalidInputError(field, f"must be > 0 (the joint's largest torque |tau|), got {x:g}",
                                "give the joint's peak torque, for example 50.0 (N m with SI units)")
    return x


def _tau_max_option(field, v, system):
    """A number (every joint's torque limit), or a table by joint name (joints left out: no limit)."""
    joints = torque_joints(field, system)
    if isinstance(v, dict):
        if not v:
            raise InvalidInputError(field, "is an empty table", f"give one entry per limited joint of {list(joints)}, "
                                    f"for example {joints[0]} = 50.0")
        out = {}
        for k, x in v.items():
            if k not in joints:
                shown = k if len(k) <= 60 and k.isprintable() else _short(k, 60)
                raise InvalidInputError(f"{field}.{shown}", "is not a joint of the body",
                                        _close(k, joints) + f"joints are {list(joints)}")
            out[k] = _torque_value(f"{field}.{k}", x)
        return out
    if isinstance(v, list):
        raise InvalidInputError(field, f"must be a number or a table by joint, got {_short(v)}",
                                f"write tau_max = 50.0 (every joint), or a table [{field}] with "
                                f"{joints[0]} = 50.0")
    return _torque_value(field, v)


#: The ``[options]`` keys and their readers ``(field, value, system) -> value`` (validated in this
#: order). To add an option, add its reader here: the key becomes known to files, to their error
#: messages and to the plan() keywords a :class:`Problem` passes on.
OPTION_PARSERS: dict[str, Callable[[str, Any, ControlAffineSystem], Any]] = {
    "method": _choice(("auto", "deform", "flat")),
    "basis": _choice(("legendre", "monomial")),
    "n_coefficients": _whole_option(1000, "6"),
    "max_evaluations": _whole_option(MAX_EVALUATIONS, "2000"),
    "time_limit": _time_limit,
    "degrees": _bool_option,
    "start_rate": _rate_option,
    "end_rate": _rate_option,
    "tol": _tol,
    "objective": _objective_option,
    "tau_max": _tau_max_option,
}
OPTION_KEYS = tuple(OPTION_PARSERS)


# -------------------------------------------------------------------------------- [plan]
def parse_problem(data: dict, name: str = "", base=None) -> Problem:
    """A :class:`Problem` from the parsed TOML document (``[robot]`` or ``[body]``, ``[plan]``,
    optional ``[limits]``, ``[options]``; a ``[simulate]`` table is left to :func:`parse_simulation`).

    ``base`` is the problem file's folder: a URDF path in ``[body]`` is read relative to it
    (default: the current folder).
    """
    _check_keys("<file>", data, TABLES)
    _system_table(data)
    if "plan" not in data:
        raise InvalidInputError("plan", "table is missing", "add a [plan] table (see docs/problem-files.md)" +
                                ("; a file with only [simulate] is run by acroplan simulate" if "simulate" in data
                                 else ""))
    system, defaults = _parse_system(data, base)
    acrobot = isinstance(system, Acrobot)
    spatial = _is_spatial(system)
    states = system.state_names
    # a spatial body's attitude (qw, qx, qy, qz) is given by one of ATTITUDE_KEYS, its joints by name
    given = tuple(n for n in states if n not in ("qw", "qx", "qy", "qz")) if spatial else tuple(states)
    p = data["plan"]
    _check_keys("plan", p, ("times",) + given + (tuple(ATTITUDE_KEYS) + ("attitude_seq",) if spatial else ())
                + ("conditions",))
    for key in ("times",) + given:
        if key not in p:
            raise InvalidInputError(f"plan.{key}", "is missing", "give one value per waypoint" +
                                    ("" if acrobot or key == "times" else
                                     f" (every joint of {list(given)})" if spatial else
                                     f" (every state: theta and the joints {list(states[1:])})"))
    times = _numbers("plan.times", p["times"], MAX_TIME, "times")
    waypoints = {k: _states(f"plan.{k}", p[k]) for k in given}
    attitude = _attitudes("plan", p, len(times)) if spatial else {}
    conditions = p.get("conditions", "spline")
    if "conditions" in p and (not isinstance(conditions, str) or conditions not in ("spline", "free")):
        raise InvalidInputError("plan.conditions", f"must be \"spline\" or \"free\", got {_short(conditions)}",
                                "write conditions = \"spline\"")
    opts = data.get("options", {})
    _check_keys("options", opts, tuple(OPTION_PARSERS))
    options: dict[str, Any] = {}
    if acrobot:  # a body's limits are in its link table (parse_body)
        lim = data.get("limits", {})
        _check_keys("limits", lim, LIMIT_KEYS)
        for key in LIMIT_KEYS:
            if key in lim:
                v = lim[key]
                if defaults and isinstance(v, str) and v.strip().lower() == "none":
                    continue  # a human body's position limit dropped
                options[key] = _number(f"limits.{key}", v, *((MAX_BODY, "rates") if key == "u_max"
                                                             else (MAX_ANGLE, "angles")))
            elif key in defaults:  # a human body's position (radians; the file's angles may be degrees)
                options[key] = math.degrees(defaults[key]) if _degrees(data) else defaults[key]
    for key, parse in OPTION_PARSERS.items():
        if key in opts:
            options[key] = parse(f"options.{key}", opts[key], system)
    if not acrobot and options.pop("degrees", False):
        # a body's angles and rates are turned into radians here (its limits were, in parse_body),
        # so that the Problem and the plan hold radians whatever the system declares as angles
        waypoints = {k: tuple(None if v is None else math.radians(v) for v in vals) for k, vals in waypoints.items()}
        for key in ("start_rate", "end_rate"):
            if key in options:
                v = options[key]
                options[key] = {k: math.radians(x) for k, x in v.items()} if isinstance(v, dict) else math.radians(v)
    if spatial:  # the attitude in state order (its forms carry their own units)
        waypoints = {k: attitude[k] if k in attitude else waypoints[k] for k in states}
    if "conditions" not in p and ("objective" in options or "tau_max" in options):
        conditions = None  # plan()'s default for an optimal plan ("free": the end inputs left to the optimiser)
    problem = Problem(system, times, waypoints, conditions, options, name)
    # the meaning (lengths, order, ranges, limits against waypoints) is checked by plan()'s own
    # validation, once, with the fields named as the file names them
    try:
        PlanRequest.build(system, **problem.plan_kwargs())
    except InvalidInputError as e:
        raise InvalidInputError(_file_field(e.field, system), _file_words(e.problem), _file_words(e.fix)) from None
    return problem


def _file_field(field: str, system) -> str:
    """plan()'s field as the problem file names it (``times`` -> ``plan.times``, ``u_max`` ->
    ``limits.u_max``, ``start_rate.u_hip`` -> ``options.start_rate.u_hip``)."""
    head = field.split(".", 1)[0].split("[", 1)[0]
    if _is_spatial(system) and head in ("attitude", "qw", "qx", "qy", "qz"):
        return "plan.attitude" if head in ("qw", "qx", "qy", "qz") else f"plan.{field}"
    if head in ("times", "conditions") or head in system.state_names:
        return f"plan.{field}"
    if head in LIMIT_KEYS and isinstance(system, Acrobot):
        return f"limits.{field}"
    if head in OPTION_PARSERS:
        return f"options.{field}"
    return field


def _file_words(text: str) -> str:
    """plan()'s option names in a message, as the file names them (``u_max`` -> ``limits.u_max``)."""
    import re

    names = {**{k: f"limits.{k}" for k in LIMIT_KEYS}, **{k: f"options.{k}" for k in OPTION_PARSERS}}
    keys = [k for k in names if "_" in k]
    return re.sub(r"(?<![\w.])(" + "|".join(keys) + r")(?!\w)", lambda m: names[m.group(1)], text)


# ---------------------------------------------------------------------------- [simulate]
def _spline_rates(times, angles) -> list[np.ndarray]:
    """Per segment, the Legendre coefficients (3) of the rate of the clamped cubic spline through
    ``(times, angles)``: on :math:`[t_k, t_{k+1}]`, :math:`q = c_3\\tau^3 + c_2\\tau^2 + c_1\\tau + c_0`,
    so :math:`u(s) = c_1 + 2c_2 T s + 3c_3 T^2 s^2` with :math:`\\tau = Ts` (exact)."""
    from scipy.interpolate import CubicSpline

    from ..core.basis import Legendre

    cs = CubicSpline(np.asarray(times, dtype=float), np.asarray(angles, dtype=float), bc_type="clamped")
    basis = Legendre(3)
    out = []
    for k in range(len(times) - 1):
        T = times[k + 1] - times[k]
        c3, c2, c1, _ = cs.c[:, k]
        out.append(basis.from_power_s([c1, 2.0 * c2 * T, 3.0 * c3 * T * T]))
    return out


def _coefficient_rows(field: str, value, K: int) -> list[np.ndarray]:
    from ..planning import MAX_COEFFICIENTS

    fix = f"give {K} list(s) of Legendre coefficients, one per segment, for example " + \
          ("[[0.0, 0.5]]" if K == 1 else "[[0.0, 0.5], [0.0, -0.5]]")
    if not isinstance(value, list) or not all(isinstance(r, list) for r in value):
        raise InvalidInputError(field, f"must be a list of lists (one per segment), got {_short(value)}", fix)
    if len(value) != K:
        raise InvalidInputError(field, f"has {len(value)} segment(s) but simulate.times has {K}", fix)
    out = []
    for k, row in enumerate(value):
        if not 1 <= len(row) <= MAX_COEFFICIENTS:
            raise InvalidInputError(f"{field}[{k}]", f"has {len(row)} coefficients; give 1 to {MAX_COEFFICIENTS}", fix)
        out.append(np.array(_numbers(f"{field}[{k}]", row, MAX_BODY, "rates")))
    return out


def parse_simulation(data: dict, name: str = "", base=None) -> Simulation:
    """A :class:`Simulation` from the parsed TOML document (``[robot]`` or ``[body]`` and
    ``[simulate]``; the module docstring shows the form). ``[plan]`` and ``[options]`` are not
    read; ``[limits]`` of a body go into its link table (recorded, not imposed on the motion)."""
    from ..planning import MAX_DURATION, MIN_DURATION

    _check_keys("<file>", data, TABLES)
    _system_table(data)
    if "simulate" not in data:
        raise InvalidInputError("simulate", "table is missing", "add a [simulate] table with times, the initial "
                                "state and each joint's motion (docs/problem-files.md); a file with only [plan] is "
                                "run by acroplan plan")
    system, _ = _parse_system(data, base)
    if isinstance(system, Acrobot):
        _check_keys("limits", data.get("limits", {}), LIMIT_KEYS)
    sim = data["simulate"]
    states, inputs = tuple(system.state_names), tuple(system.input_names)
    input_of = {s: u for u, s in system.rate_inputs.items()}
    if _is_spatial(system):  # the initial attitude by one of ATTITUDE_KEYS, as qw, qx, qy, qz below
        joints = tuple(n for n in states if n not in ("qw", "qx", "qy", "qz"))
        _check_keys("simulate", sim, ("times",) + tuple(ATTITUDE_KEYS) + ("attitude_seq",) + joints + inputs)
        q0 = _attitudes("simulate", sim, None)
        sim = {**{k: v for k, v in sim.items() if k not in ATTITUDE_KEYS and k != "attitude_seq"},
               **{k: v[0] for k, v in q0.items()}}
    _check_keys("simulate", sim, ("times",) + states + inputs)
    if "times" not in sim:
        raise InvalidInputError("simulate.times", "is missing", "give the segment boundaries, for example [0, 1, 2]")
    times = _numbers("simulate.times", sim["times"], MAX_TIME, "times")
    if len(times) < 2 or any(b <= a for a, b in zip(times, times[1:])):
        raise InvalidInputError("simulate.times", "must hold at least 2 strictly increasing values",
                                "give for example [0, 1, 2]")
    for k, (a, b) in enumerate(zip(times, times[1:])):
        if not MIN_DURATION <= b - a <= MAX_DURATION:
            raise InvalidInputError("simulate.times", f"segment {k} lasts {b - a:.3g}; durations must lie in "
                                    f"[{MIN_DURATION:g}, {MAX_DURATION:g}]", "rescale the units of time")
    K = len(times) - 1
    initial, rates, motion = {}, {}, {}
    for state in states:
        field = f"simulate.{state}"
        u = input_of.get(state)
        if state not in sim:
            raise InvalidInputError(field, "is missing", "give the initial value of every state" +
                                    ("" if u is None else f"; for a joint, its angles at the times (a spline) or its "
                                     f"initial angle with simulate.{u}"))
        v = sim[state]
        if u is None:
            if isinstance(v, list):
                raise InvalidInputError(field, "is what the simulation computes: give its initial value only",
                                        f"write for example {state} = 0.0")
            initial[state] = _number(field, v, MAX_ANGLE, "angles")
        elif isinstance(v, list):
            if u in sim:
                raise InvalidInputError(f"simulate.{u}", f"is given together with the angles of {state}",
                                        f"give {state} = [angles at the times] (a spline through them), or "
                                        f"{state} = its initial angle with {u} = [[coefficients], ...]")
            angles = _numbers(field, v, MAX_ANGLE, "angles")
            if len(angles) != len(times):
                raise InvalidInputError(field, f"has {len(angles)} value(s) but simulate.times has {len(times)}",
                                        "give one angle per time (a spline through them), or one number (the "
                                        f"initial angle) with simulate.{u}")
            initial[state] = angles[0]
            rates[u] = _spline_rates(times, angles)
            motion[u] = "spline"
        else:
            initial[state] = _number(field, v, MAX_ANGLE, "angles")
            if u not in sim:
                raise InvalidInputError(f"simulate.{u}", "is missing", f"give the Legendre coefficients of {u} per "
                                        f"segment ([[c0, c1, ...], ...]), or {state} as a list of angles, one per time")
            rates[u] = _coefficient_rows(f"simulate.{u}", sim[u], K)
            motion[u] = "coefficients"
    missing = [u for u in inputs if u not in rates]
    if missing:  # an input that is the rate of no state (no such system is read from files today)
        raise InvalidInputError(f"simulate.{missing[0]}", "is missing", "give its Legendre coefficients per segment")
    n = max(len(c) for u in inputs for c in rates[u])
    segs = tuple(np.array([np.pad(rates[u][k], (0, n - len(rates[u][k]))) for u in inputs]) for k in range(K))
    return Simulation(system, times, initial, segs, motion, name)


def parse_nilpotent(data: dict, name: str = ""):
    """A :class:`~acroplan.nilpotent.NilpotentProblem` and its method from a TOML document with
    ``[robot]`` and ``[nilpotent]`` (``P``, ``Q`` as (phi, t, theta), ``degree``, ``method``)."""
    from ..families.acrobot.nilpotent import NilpotentProblem

    if isinstance(data, dict) and "plan" in data and "nilpotent" not in data:
        raise InvalidInputError("[nilpotent]", "is missing: this is a plan file ([plan] table), and `acroplan "
                                "nilpotent` needs a [nilpotent] table with P, Q and degree",
                                "start one with: acroplan init NAME --example chapter4, or plan this file with "
                                "acroplan plan")
    _check_keys("<file>", data, ("robot", "nilpotent"))
    for table in ("robot", "nilpotent"):
        if table not in data:
            raise InvalidInputError(table, "table is missing", f"add a [{table}] table (see docs/chapter4.md)")
    robot = parse_robot(data["robot"])
    nil = data["nilpotent"]
    _check_keys("nilpotent", nil, ("P", "Q", "degree", "method"))
    pts = {}
    for key in ("P", "Q"):
        if key not in nil:
            raise InvalidInputError(f"nilpotent.{key}", "is missing", "give [phi, t, theta]")
        vals = _numbers(f"nilpotent.{key}", nil[key],
                        most_of=lambda i: (MAX_TIME, "times") if i == 1 else (MAX_ANGLE, "angles"))
        if len(vals) != 3:
            raise InvalidInputError(f"nilpotent.{key}", f"needs 3 values (phi, t, theta), got {len(vals)}",
                                    "give [phi, t, theta]")
        pts[key] = vals
    degree = nil.get("degree", 3)
    if isinstance(degree, bool) or not isinstance(degree, int) or not 1 <= degree <= 12:
        raise InvalidInputError("nilpotent.degree", "must be a whole number from 1 to 12, got "
                                f"{_short(degree) if not isinstance(degree, int) or abs(degree) < 10**30 else 'a huge integer'}",
                                "write degree = 3")
    method = nil.get("method", "nilpotent")
    if not isinstance(method, str) or method not in ("nilpotent", "flat-y"):
        raise InvalidInputError("nilpotent.method", f"must be \"nilpotent\" or \"flat-y\", got {_short(method)}",
                                "write method = \"nilpotent\"")
    try:
        prob = NilpotentProblem(robot, pts["P"], pts["Q"], degree)
    except InvalidInputError as e:
        field = e.field if e.field.startswith(("robot.", "nilpotent.")) else f"nilpotent.{e.field}"
        raise InvalidInputError(field, e.problem, e.fix) from None
    return prob, method


def load_toml(path) -> dict:
    """Read a TOML file, with errors as :class:`InvalidInputError` naming the file (and the line
    when the parser gives up on a number or a nesting): at most :data:`MAX_FILE_BYTES` bytes,
    regular files only."""
    path = Path(path)
    fix = "give a readable UTF-8 .toml file"
    try:
        if not path.exists():
            raise InvalidInputError(str(path), "no such file", "give the path of a problem .toml file")
        if not path.is_file():
            raise InvalidInputError(str(path), "is not a regular file", fix)
        with open(path, "rb") as f:
            raw = f.read(MAX_FILE_BYTES + 1)
        if len(raw) > MAX_FILE_BYTES:
            raise InvalidInputError(str(path), f"is larger than {MAX_FILE_BYTES // 1_000_000} MB",
                                    "a problem file is a few lines")
        text = raw.decode("utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise InvalidInputError(str(path), f"cannot be read ({e.__class__.__name__})", fix) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise InvalidInputError(str(path), f"is not valid TOML ({_one_line(e)})", "fix the syntax (see the README)") \
            from None
    except (RecursionError, MemoryError):
        raise InvalidInputError(str(path), "is nested too deeply to read (arrays or tables within each other)",
                                "write the values flat, as in the README") from None
    except ValueError as e:  # an integer literal beyond Python's digit limit
        where = _line_of_long_number(text)
        raise InvalidInputError(f"{path}{where}", f"holds a number too long to read ({_short(str(e), 60)})",
                                "write numbers of sensible size") from None


def _one_line(e) -> str:
    text = str(e).replace("\n", " ")
    return text if len(text) <= 200 else text[:197] + "..."


def _line_of_long_number(text: str) -> str:
    import re

    for i, line in enumerate(text.splitlines(), 1):
        if re.search(r"[0-9_]{1000,}", line):
            key = re.match(r"\s*([A-Za-z0-9_.\-\"' ]{1,60}?)\s*=", line)
            return f" (line {i}{', key ' + key.group(1).strip() if key else ''})"
    return ""


def with_options(data: dict, options: dict | None) -> dict:
    """The TOML document ``data`` with ``options`` written over its ``[options]`` table (what the
    command line's ``--objective`` and ``--tau-max`` do); ``data`` itself is not changed. A document
    whose ``[options]`` is not a table is returned as it is (its reader refuses it, naming the field)."""
    if not options or not isinstance(data, dict):
        return data
    opts = data.get("options", {})
    if not isinstance(opts, dict):
        return data
    return {**data, "options": {**opts, **options}}


def load_problem(path) -> Problem:
    """Read and validate a problem file (a URDF or a yeadon measurement file it names is read
    relative to its folder)."""
    return parse_problem(load_toml(path), name=Path(path).stem, base=Path(path).parent)


def load_simulation(path) -> Simulation:
    """Read and validate a problem file's ``[simulate]`` table (with its ``[robot]`` or ``[body]``)."""
    return parse_simulation(load_toml(path), name=Path(path).stem, base=Path(path).parent)


def system_to_dict(system) -> dict[str, Any]:
    """The system's own record (:meth:`ControlAffineSystem.to_dict`)."""
    return system.to_dict()
