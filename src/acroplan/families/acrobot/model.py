"""The free-flying two-link acrobot of the dissertation (Chapter 2).

State :math:`x = (\\theta, \\varphi)`: :math:`\\theta` is the angle of the leg to the x axis of the
centre-of-mass frame, :math:`\\varphi` the joint angle from leg to torso. The input is the joint
rate :math:`u = \\dot\\varphi`. Conservation of the angular momentum :math:`P_0` (text eq. 2),

.. math::  P_0 = h(\\varphi)\\,\\dot\\theta + k(\\varphi)\\,\\dot\\varphi ,\\qquad
           h = M_1 + A_1\\cos\\varphi ,\\quad k = M_2 + A_2\\cos\\varphi ,

gives the state equation (text eq. 3)

.. math::  \\dot\\theta = \\frac{P_0}{h(\\varphi)} - \\frac{k(\\varphi)}{h(\\varphi)}\\,u ,\\qquad
           \\dot\\varphi = u .

Geometry (docs/mathematics.md): from the joint, the torso's centre of mass is at
:math:`L(\\cos(\\theta+\\varphi), \\sin(\\theta+\\varphi))` and the leg's at
:math:`l(\\cos\\theta, \\sin\\theta)`; :math:`\\varphi = 0` is folded, :math:`\\pm\\pi` straight.

::

        torso (M, J)          joint          leg (m, j)
    o=====================*=====o======================o
             L                        l
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...core.errors import InvalidInputError, finite_number
from ...core.system import ControlAffineSystem, Infeasibility, sp
from ...core.validate import MAX_MAGNITUDE
from .reach import _reachable_set, reachable_set

__all__ = ["Acrobot", "PhysicalParameters"]


def _finite(field: str, value) -> float:
    v = finite_number(field, value)
    if abs(v) > MAX_MAGNITUDE:
        raise InvalidInputError(field, f"is {v:.3g}, beyond {MAX_MAGNITUDE:g}: more than the arithmetic carries "
                                "(its squares overflow)", "change the units")
    return v


def _alias(name: str, value, alias: str, alias_value):
    if value is not None and alias_value is not None:
        raise InvalidInputError(alias, f"is the same distance as {name}; give one of them",
                                f"keep {alias} (the clearer name) and drop {name}")
    if value is None and alias_value is None:
        raise InvalidInputError(alias, "is missing", "give the distance from the centre of mass to the joint "
                                "(m), not the segment's length")
    return value if value is not None else alias_value


@dataclasses.dataclass(frozen=True)
class PhysicalParameters:
    """The body as the text's Fig. 4 describes it (SI units or any consistent set).

    Attributes
    ----------
    torso_mass, leg_mass : float
        M and m (> 0).
    torso_inertia, leg_inertia : float
        J and j, moments of inertia about each link's centre of mass (> 0).
    torso_length, leg_length : float
        L and l, distances from each link's centre of mass to the joint (>= 0).
    angular_momentum : float
        P0, the constant total angular momentum.
    """

    torso_mass: float
    leg_mass: float
    torso_inertia: float
    leg_inertia: float
    torso_length: float
    leg_length: float
    angular_momentum: float

    def __post_init__(self):
        for f in dataclasses.fields(self):
            object.__setattr__(self, f.name, _finite(f.name, getattr(self, f.name)))
        for name in ("torso_mass", "leg_mass", "torso_inertia", "leg_inertia"):
            if getattr(self, name) <= 0:
                raise InvalidInputError(name, f"must be > 0, got {getattr(self, name)}", "give a positive value")
        for name in ("torso_length", "leg_length"):
            if getattr(self, name) < 0:
                raise InvalidInputError(name, f"must be >= 0, got {getattr(self, name)}", "give a distance >= 0")

    @property
    def reduced_mass(self) -> float:
        """:math:`\\mu = mM/(m+M)`."""
        return self.leg_mass * self.torso_mass / (self.leg_mass + self.torso_mass)

    def lumped(self) -> dict[str, float]:
        """M1, A1, M2, A2, P0 of text eq. (3)."""
        mu = self.reduced_mass
        L, l = self.torso_length, self.leg_length
        J, j = self.torso_inertia, self.leg_inertia
        return {
            "M1": j + J + mu * (L**2 + l**2),
            "A1": -2.0 * mu * L * l,
            "M2": J + mu * L**2,
            "A2": -mu * L * l,
            "P0": self.angular_momentum,
        }


def _checking_rhs(x, u, p):
    """The right-hand side :math:`f + G u` of the checking integrator: the code ``sympy.lambdify``
    writes for :meth:`Acrobot.symbolic_fields` (``modules="numpy"``), written out so that the check
    needs no sympy (``tests/test_system.py`` checks the values are the same, bit for bit)."""
    theta, phi = x
    (u0,) = u
    M1, A1, M2, A2, P0 = p
    return [P0/(A1*np.cos(phi) + M1) + u0*(-A2*np.cos(phi) - M2)/(A1*np.cos(phi) + M1), u0]


@dataclasses.dataclass(frozen=True)
class Acrobot(ControlAffineSystem):
    """The free-flying two-link acrobot, in lumped parameters.

    Parameters
    ----------
    M1, A1, M2, A2 : float
        Coefficients of :math:`h(\\varphi) = M_1 + A_1\\cos\\varphi` and
        :math:`k(\\varphi) = M_2 + A_2\\cos\\varphi`. Requires :math:`M_1 > |A_1|` so that
        :math:`h` never vanishes.
    P0 : float
        Angular momentum. ``P0 = 0`` makes the system holonomic (see :meth:`check_segment`).
    physical : PhysicalParameters, optional
        The body these came from, kept for reports and drawing; set by :meth:`from_physical`.

    Examples
    --------
    >>> robot = Acrobot.from_physical(torso_mass=40, leg_mass=20, torso_inertia=2.5,
    ...     leg_inertia=1.2, torso_length=0.35, leg_length=0.45, angular_momentum=10)
    >>> round(robot.A2 / robot.A1, 12)
    0.5
    """

    M1: float
    A1: float
    M2: float
    A2: float
    P0: float
    physical: PhysicalParameters | None = dataclasses.field(default=None, compare=False, repr=False)

    state_names = ("theta", "phi")
    input_names = ("u",)
    param_names = ("M1", "A1", "M2", "A2", "P0")
    rate_inputs = {"u": "phi"}
    angle_states = ("theta", "phi")

    def __post_init__(self):
        for name in self.param_names:
            object.__setattr__(self, name, _finite(name, getattr(self, name)))
        if not self.M1 > abs(self.A1):
            raise InvalidInputError(
                "M1",
                f"must exceed |A1| (M1 = {self.M1}, A1 = {self.A1}), else h(phi) = M1 + A1 cos(phi) vanishes",
                "check the parameters, or give the physical body with from_physical()",
            )

    @classmethod
    def from_physical(cls, *, torso_mass, leg_mass, torso_inertia, leg_inertia, torso_length=None,
                      leg_length=None, angular_momentum, torso_com_to_joint=None,
                      leg_com_to_joint=None) -> "Acrobot":
        """Build from the body's masses, inertias and distances (text eq. 3's parameter formulas).

        .. math::  \\mu = \\frac{mM}{m+M},\\quad M_1 = j + J + \\mu(L^2 + l^2),\\quad
                   A_1 = -2\\mu L l,\\quad M_2 = J + \\mu L^2,\\quad A_2 = -\\mu L l .

        ``torso_length`` (L) and ``leg_length`` (l) are the text's names for the distances from each
        link's **centre of mass to the joint**, not the segments' lengths (for a uniform segment,
        half of it); ``torso_com_to_joint`` and ``leg_com_to_joint`` are the same with names that
        say so (give one of each pair). The figure of the body's parameters is in
        ``docs/problem-files.md``.
        """
        torso_length = _alias("torso_length", torso_length, "torso_com_to_joint", torso_com_to_joint)
        leg_length = _alias("leg_length", leg_length, "leg_com_to_joint", leg_com_to_joint)
        phys = PhysicalParameters(torso_mass, leg_mass, torso_inertia, leg_inertia, torso_length, leg_length,
                                  angular_momentum)
        lumped = phys.lumped()
        for name, v in lumped.items():
            if not (math.isfinite(v) and abs(v) <= MAX_MAGNITUDE):
                raise InvalidInputError("torso_length" if name != "P0" else "angular_momentum",
                                        f"the body's {name} = {v:.3g} is more than the arithmetic carries",
                                        "change the units (masses in kg, lengths in m)")
        return cls(**lumped, physical=phys)

    @classmethod
    def example(cls) -> "Acrobot":
        """A representative acrobot (every acrobot has the same structure: one compilation serves all)."""
        return cls(M1=2.0, A1=-0.5, M2=0.5, A2=-0.25, P0=1.0)

    # ------------------------------------------------------------------ fields
    @classmethod
    def symbolic_fields(cls, x, p):
        theta, phi = x
        M1, A1, M2, A2, P0 = p
        h = M1 + A1 * sp.cos(phi)
        k = M2 + A2 * sp.cos(phi)
        f = sp.Matrix([P0 / h, 0])
        G = sp.Matrix([-k / h, 1])
        return f, G

    @classmethod
    def taylor_fields(cls, x, p):
        """:meth:`symbolic_fields` as the heyoka expressions ``heyoka.from_sympy`` makes of them (sympy's
        terms in sympy's order; ``tests/test_system.py`` checks they are equal), so that a plan whose
        integrator heyoka has on disk never imports sympy."""
        if cls.symbolic_fields.__func__ is not Acrobot.symbolic_fields.__func__:
            return None  # (a subclass with fields of its own)
        import heyoka as hy

        theta, phi = x
        M1, A1, M2, A2, P0 = p
        minus = hy.expression(-1.0)
        c = hy.cos(phi)
        inv_h = hy.sum([M1, hy.prod([A1, c])]) ** minus
        f = [hy.prod([P0, inv_h]), None]
        G = [[hy.prod([inv_h, hy.sum([hy.prod([minus, M2]), hy.prod([minus, A2, c])])])], [hy.expression(1.0)]]
        return f, G

    def _numeric(self):
        if type(self).symbolic_fields.__func__ is not Acrobot.symbolic_fields.__func__:
            return super()._numeric()
        return _checking_rhs

    # ------------------------------------------------------------------ closed forms
    def h(self, phi):
        """:math:`h(\\varphi) = M_1 + A_1\\cos\\varphi`."""
        return self.M1 + self.A1 * np.cos(phi)

    def k(self, phi):
        """:math:`k(\\varphi) = M_2 + A_2\\cos\\varphi`."""
        return self.M2 + self.A2 * np.cos(phi)

    def momentum(self, theta_dot, phi_dot, phi):
        """Angular momentum, text eq. (2): :math:`h(\\varphi)\\dot\\theta + k(\\varphi)\\dot\\varphi`."""
        return self.h(phi) * theta_dot + self.k(phi) * phi_dot

    def F(self, phi):
        """An antiderivative of :math:`k/h`, continuous on the whole real line.

        With :math:`a = M_1`, :math:`b = A_1`, :math:`s = \\sqrt{a^2 - b^2}` and
        :math:`\\rho = (a - s)/b` (0 when :math:`b = 0`),

        .. math::  \\int \\frac{d\\varphi}{a + b\\cos\\varphi} = \\frac{1}{s}\\Big(\\varphi
                   - 2\\,\\operatorname{atan2}(\\rho\\sin\\varphi,\\, 1 + \\rho\\cos\\varphi)\\Big),

        and :math:`k/h = A_2/A_1 + (M_2 - A_2 M_1/A_1)/h` for :math:`A_1 \\ne 0`.
        """
        a, b = self.M1, self.A1
        if isinstance(phi, float):  # scalar fast path (the planner's feasibility and flat-output work)
            sin, cos, atan2 = math.sin, math.cos, math.atan2
        else:
            phi = np.asarray(phi, dtype=float)
            sin, cos, atan2 = np.sin, np.cos, np.arctan2
        if b == 0.0:
            return (self.M2 * phi + self.A2 * sin(phi)) / a
        s = math.sqrt(a * a - b * b)  # finite: |a|, |b| <= MAX_MAGNITUDE
        rho = (a - s) / b
        G = (phi - 2.0 * atan2(rho * sin(phi), 1.0 + rho * cos(phi))) / s
        return (self.A2 / b) * phi + (self.M2 - self.A2 * a / b) * G

    def reachable_interval(self, *, theta0: float, phi0: float, phiT: float, T: float) -> tuple[float, float]:
        """The exact set of :math:`\\theta(T)` reachable with unbounded :math:`u` (an open interval).

        Since :math:`k/h\\,d\\varphi = dF` is exact (docs/mathematics.md),

        .. math::  \\theta(T) = \\theta(0) - [F(\\varphi(T)) - F(\\varphi(0))]
                   + P_0 \\int_0^T \\frac{dt}{h(\\varphi(t))} ,

        and :math:`1/h` ranges over :math:`(1/(M_1+|A_1|), 1/(M_1-|A_1|))`, both ends approached
        but not attained by continuous motions with the given :math:`\\varphi(0), \\varphi(T)`.

        Returns
        -------
        (low, high) : tuple of float
            The open interval; ``low == high`` when ``P0 == 0`` or ``A1 == 0`` (a single value).
        """
        R = reachable_set(self, theta0=theta0, phi0=phi0, phiT=phiT, T=T)
        return R.low, R.high

    def continuation_path(self, y0, x1, x0, duration):
        """A target path inside the exact reachable set.

        Along the path :math:`\\varphi` moves linearly from its start to its target value, and
        :math:`\\theta` keeps a relative position :math:`w \\in (0, 1)` in the reachable interval
        :math:`(\\theta_{lo}(\\varphi), \\theta_{hi}(\\varphi))` that moves linearly too, so every
        point of the path is reachable (the straight segment can leave the set, since the interval
        moves with :math:`\\varphi` through :math:`F`).
        """
        theta0, phi0 = float(x0[0]), float(x0[1])
        ends = lambda phi: self.reachable_interval(theta0=theta0, phi0=phi0, phiT=phi, T=duration)  # noqa: E731
        cache = {}

        def weights():  # computed on first use: a first full step needs no path
            if not cache:
                lo0, hi0 = ends(float(y0[1]))
                lo1, hi1 = ends(float(x1[1]))
                if hi0 > lo0 and hi1 > lo1:
                    cache["w"] = ((float(y0[0]) - lo0) / (hi0 - lo0), (float(x1[0]) - lo1) / (hi1 - lo1))
                else:
                    cache["w"] = None
            return cache["w"]

        straight = super().continuation_path(y0, x1, x0, duration)

        def path(tau):
            w = weights()
            if w is None:
                return straight(tau)
            phi = float(y0[1]) + tau * (float(x1[1]) - float(y0[1]))
            lo, hi = ends(phi)
            return np.array([lo + (w[0] + tau * (w[1] - w[0])) * (hi - lo), phi])

        return path

    def check_segment(self, x0, x1, duration, limits=None):
        """Refuse a segment whose end :math:`\\theta` is not reachable (see :mod:`acroplan.reach`).

        Without limits the reachable set is the open interval of :meth:`reachable_interval`; with
        joint or rate limits it is :func:`acroplan.reach.reachable_set`. A target on the boundary
        is refused too: it is reached by no smooth input.
        """
        theta0, phi0 = float(x0[0]), float(x0[1])
        thetaT, phiT = float(x1[0]), float(x1[1])
        # the arguments are the planner's own, already validated: the public door's checks skipped
        R = _reachable_set(self, theta0=theta0, phi0=phi0, phiT=phiT, T=float(duration), limits=limits)
        lim = "" if limits is None or not limits.active else f" under {limits.describe()}"
        if not R.success:
            return Infeasibility(f"no joint motion is possible{lim}: {R.message}", "phi", None)
        lo, hi = R.low, R.high
        scale = max(1.0, abs(lo), abs(hi))
        if lo == hi or self.P0 == 0.0:
            if abs(thetaT - lo) <= 1e-12 * scale:
                return None
            why = ("P0 = 0 makes the acrobot holonomic (theta + F(phi) is constant)" if self.P0 == 0.0
                   else "only one theta(T) is reachable")
            return Infeasibility(f"{why}: with phi(T) = {phiT:.12g} the only reachable theta(T) is {lo:.12g}, "
                                 f"not {thetaT:.12g}", "theta", (lo, lo))
        if not (lo < thetaT < hi):
            where = (f"for theta(0) = {theta0:.12g}, phi(0) = {phi0:.12g}, phi(T) = {phiT:.12g}, "
                     f"T = {duration:.12g}")
            kind = "closed" if R.closed else "open"
            ends = f"[{lo:.12g}, {hi:.12g}]" if R.closed else f"({lo:.12g}, {hi:.12g})"
            edge = " (its ends are reached only by bang-dwell-bang joint motions, not by a smooth input)" \
                if R.closed and lo <= thetaT <= hi else ""
            return Infeasibility(f"theta(T) = {thetaT:.12g} is outside the reachable {kind} interval {ends}{lim} "
                                 f"{where}{edge}", "theta", (lo, hi))
        return None

    # ------------------------------------------------------------------ family hooks
    def auto_strategy(self):
        """``method="auto"`` for the acrobot: path deformation from a flat-output guess that already
        meets the target, then the flat-output planner (:class:`~acroplan.families.acrobot.flat.AcrobotAuto`)."""
        from .flat import AcrobotAuto

        return AcrobotAuto()

    def torque_model(self):
        """The joint torque :math:`\\tau = a(\\varphi)\\ddot\\varphi + b(\\varphi)\\dot\\varphi^2 +
        c(\\varphi)P_0^2` (:class:`~acroplan.families.acrobot.effort.AcrobotTorque`, registered by
        :mod:`~acroplan.families.acrobot.effort` on import) when the robot was built from its
        physical body (:meth:`from_physical`); ``None`` for a lumped-only robot, whose parameters fix
        the motion but not the torque's scale (any common multiple of ``M1, A1, M2, A2, P0`` gives
        the same motion)."""
        return super().torque_model() if self.physical is not None else None

    def fill_free(self, x0, x1, guess, duration, limits=None, after=None):
        """A free ``phi`` takes the interpolated value (inside the joint limits); a free ``theta``
        the middle of the values that are reachable from ``x0`` and from which the next waypoint
        is reachable (theta enters additively, so that is an intersection of two exact intervals),
        or of the first alone when they do not meet or there is no next waypoint."""
        x1 = np.array(x1, dtype=float)
        if np.isnan(x1[1]):
            lo, hi = limits.bounds("phi") if limits is not None else (-math.inf, math.inf)
            x1[1] = min(max(float(guess[1]), lo), hi)
        if np.isnan(x1[0]):
            R = reachable_set(self, theta0=float(x0[0]), phi0=float(x0[1]), phiT=float(x1[1]), T=duration,
                              limits=limits)
            lo, hi = (float(guess[0]),) * 2 if not R.success else (R.low, R.high)
            if after is not None and R.success:
                x2, T2 = after
                # theta_2 - theta_1 must lie in the reachable offsets of the next segment
                N = reachable_set(self, theta0=0.0, phi0=float(x1[1]), phiT=float(x2[1]), T=T2, limits=limits)
                if N.success and max(lo, x2[0] - N.high) < min(hi, x2[0] - N.low):
                    lo, hi = max(lo, x2[0] - N.high), min(hi, x2[0] - N.low)
            x1[0] = 0.5 * (lo + hi)
        return x1

    def state_unit(self, state):
        """theta and phi are angles: ``"rad"``."""
        return "rad"

    def reference_lines(self, state, lo, hi):
        """The straight body (phi = pi mod 2 pi) and the folded body (phi = 0 mod 2 pi) on plots of phi."""
        if state != "phi" or not (np.isfinite(lo) and np.isfinite(hi)) or hi - lo > 40 * math.pi:
            return []
        ks = range(math.floor(lo / math.pi), math.ceil(hi / math.pi) + 1)
        return [(k * math.pi, "folded" if k % 2 == 0 else "straight") for k in ks]

    family_check = "flat-output identity"

    def family_errors(self, x0, segments):
        """The flat-output identity (:func:`acroplan.families.acrobot.verify.flat_output_errors`):
        exact up to rounding, with no ODE solver and no compiled code; microseconds per segment."""
        from .verify import chained_errors

        return chained_errors(self, x0, segments)

    def to_dict(self) -> dict:
        """Type, lumped parameters and, when known, the physical body."""
        out = super().to_dict()
        out["physical"] = dataclasses.asdict(self.physical) if self.physical is not None else None
        return out

    @classmethod
    def from_dict(cls, data: dict) -> "Acrobot":
        """The acrobot :meth:`to_dict` described (from the physical body when it is recorded)."""
        if data.get("physical"):
            return cls.from_physical(**data["physical"])
        return cls(**data["params"])

    # ------------------------------------------------------------------ the body's parameters (sweeps)
    def robot_parameters(self) -> dict[str, float]:
        """The physical body's masses, inertias, lengths and ``angular_momentum`` when it is known,
        else the lumped ``M1, A1, M2, A2, P0``: what a sweep's ``robot.NAME`` fields set."""
        return dataclasses.asdict(self.physical) if self.physical is not None else self.lumped()

    def with_robot_parameters(self, **values) -> "Acrobot":
        """This body with some of :meth:`robot_parameters` changed (rebuilt from the physical body
        when there is one)."""
        if self.physical is not None:
            return type(self).from_physical(**{**dataclasses.asdict(self.physical), **values})
        return type(self)(**{**self.lumped(), **values})

    def scaled(self, s: float) -> "Acrobot":
        """The body ``s`` times its size at the same density: lengths x s, masses x s^3, inertias x
        s^5; a lumped-only body: ``M1, A1, M2, A2`` x s^5 (``P0`` is kept)."""
        if not s > 0:
            raise InvalidInputError("robot.scale", f"must be > 0, got {s}", "give a positive size factor")
        target = self.robot_parameters()
        for k in list(target):
            if k.endswith("_mass"):
                target[k] *= s ** 3
            elif k.endswith("_inertia") or (self.physical is None and k in ("M1", "A1", "M2", "A2")):
                target[k] *= s ** 5
            elif k.endswith("_length"):
                target[k] *= s
        return type(self).from_physical(**target) if self.physical is not None else type(self)(**target)
