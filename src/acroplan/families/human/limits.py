"""What a human body can do: joint ranges and peak joint rates, as data with their sources.

The values are in ``data/limits.toml``, each with its source (or ``estimate = true`` where none
was found), read by :func:`human_data`. :data:`POSITIONS` turns them into the positions of
diving (FINA's definitions: *straight*, no bend at the hips or knees; *pike*, legs straight and
bent at the hips; *tuck*, bent at the hips and knees), and :func:`human_limits` into an
:class:`acroplan.Limits` for a :class:`~acroplan.families.human.body.SagittalBody` split in two
(the acrobot's ``phi`` and ``u``) or three parts (``hip``, ``shoulder``, ``u_hip``,
``u_shoulder``), in those bodies' angle conventions:

.. math::  \\varphi = \\psi - \\pi + \\delta ,\\qquad q_{hip} = \\pi - \\psi ,\\qquad
           q_{shoulder} = \\pi - \\sigma ,

so a hip range :math:`\\psi_{min} \\le \\psi \\le \\psi_{max}` is
:math:`\\psi_{min} - \\pi + \\delta \\le \\varphi \\le \\psi_{max} - \\pi + \\delta` and
:math:`\\pi - \\psi_{max} \\le q_{hip} \\le \\pi - \\psi_{min}`.

=========  =============  ====================================  ==============================
position   knees          hip flexion :math:`\\psi` (deg)         source
=========  =============  ====================================  ==============================
pike       straight       -30 (extension) to 150 (closed pike)   AAOS 1965; 150 an estimate
tuck       125 deg flexed -30 to 140 (tight tuck)                AAOS 1965; 140, 125 estimates
straight   straight       -15 to 15                              FINA; the 15 an estimate
=========  =============  ====================================  ==============================

Rates: hip :math:`|\\dot\\psi| \\le` 12 rad/s, between the mean peak hip flexion rates of elite
10 m platform divers (11.0 and 12.8 rad/s: Murtaugh 2000; Murtaugh & Miller 2001, J. Appl.
Biomech. 17:312-325); shoulder 15 rad/s (an estimate). Shoulder range: -60 to 180 degrees
(AAOS 1965).

Torques (not limits of the plans, a yardstick for them): the largest active isometric hip flexion
and extension torques of an elite male gymnast, 157.3 and 175.7 N m a hip (Jackson 2010, as
tabulated by Millard et al. 2019): :func:`hip_torque_literature`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import tomllib
from importlib import resources

from ...core.errors import InvalidInputError, finite_number
from ...core.limits import Limits
from .body import SagittalBody

__all__ = ["human_data", "Position", "POSITIONS", "position", "human_limits", "hip_rate_literature",
           "hip_torque_literature"]


@functools.lru_cache(maxsize=1)
def human_data() -> dict:
    """``data/limits.toml`` as a dict: ``data["hip"]["extension"]`` is ``{"value": 30.0, "source":
    "AAOS1965", "estimate": False, "note": ...}`` (angles in degrees, rates in rad/s);
    ``data["sources"]`` the references by key."""
    text = resources.files(__package__).joinpath("data", "limits.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def _deg(group: str, name: str) -> float:
    return math.radians(human_data()[group][name]["value"])


def hip_rate_literature() -> tuple[float, float]:
    """The mean peak hip flexion rates of elite platform divers (rad/s): ``(11.0, 12.8)``
    (``data/limits.toml``, ``rates.hip.literature``)."""
    lo, hi = human_data()["rates"]["hip"]["literature"]
    return float(lo), float(hi)


def hip_torque_literature(both: bool = True) -> tuple[float, float]:
    """The largest active isometric hip torques of an elite male gymnast (N m): ``(flexion,
    extension)``, ``(314.6, 351.4)`` for both hips together (the two-link body's hip joint),
    ``(157.3, 175.7)`` for one (``both=False``). Jackson (2010) as tabulated by Millard et al.
    (2019) (``data/limits.toml``, ``torques``): at the strongest hip angle and at rest, so a bound
    of what a strong athlete's hips give, not a typical man's (Anderson et al. 2007's young men,
    0.113 and 0.161 body weight times height a hip: about 112 and 160 N m at 58.2 kg and 1.74 m).

    Examples
    --------
    >>> hip_torque_literature()
    (314.6, 351.4)
    """
    t = human_data()["torques"]
    k = 2.0 if both else 1.0
    return round(k * float(t["hip_flexion"]["value"]), 10), round(k * float(t["hip_extension"]["value"]), 10)


@dataclasses.dataclass(frozen=True)
class Position:
    """A diving position: the knees' fixed flexion and the hip's range (rad).

    Attributes
    ----------
    name : str
    knee_flexion : float
        :math:`\\kappa` the legs are built with.
    hip : (float, float)
        :math:`(\\psi_{min}, \\psi_{max})`, anatomical hip flexion.
    shoulder : (float, float)
        :math:`(\\sigma_{min}, \\sigma_{max})`, anatomical shoulder flexion.
    hip_rate, shoulder_rate : float
        Rate limits (rad/s).
    estimates : tuple of str
        Which of these values are estimates (no measurement found).
    """

    name: str
    knee_flexion: float
    hip: tuple[float, float]
    shoulder: tuple[float, float]
    hip_rate: float
    shoulder_rate: float
    estimates: tuple[str, ...]


def _positions() -> dict[str, Position]:
    d = human_data()
    ext = _deg("hip", "extension")
    tol = _deg("hip", "straight_tolerance")
    shoulder = (-_deg("shoulder", "extension"), _deg("shoulder", "flexion"))
    rates = (d["rates"]["hip"]["value"], d["rates"]["shoulder"]["value"])
    est = ("hip_rate", "shoulder_rate")
    return {
        "pike": Position("pike", 0.0, (-ext, _deg("hip", "flexion_pike")), shoulder, *rates, est + ("hip[1]",)),
        "tuck": Position("tuck", _deg("knee", "flexion_tuck"), (-ext, _deg("hip", "flexion_tuck")), shoulder, *rates,
                         est + ("hip[1]", "knee_flexion")),
        "straight": Position("straight", 0.0, (-tol, tol), shoulder, *rates, est + ("hip",)),
    }


#: The positions by name (module docstring's table).
POSITIONS: dict[str, Position] = _positions()


def position(name: str) -> Position:
    """The :class:`Position` called ``name`` (``"pike"``, ``"tuck"``, ``"straight"``)."""
    if not isinstance(name, str) or name not in POSITIONS:
        raise InvalidInputError("position", f"must be one of {sorted(POSITIONS)}, got {name!r}",
                                "pike: hips bent, knees straight; tuck: hips and knees bent; straight: neither")
    return POSITIONS[name]


def human_limits(body: SagittalBody, name: str = "pike", *, links: int = 2, shoulder_flexion: float = 0.0,
                 hip_rate: float | None = None, shoulder_rate: float | None = None) -> Limits:
    """The joint and rate limits of ``body`` in a position, in its two- or three-part model's names.

    Parameters
    ----------
    body : SagittalBody
        Built with the position's knee flexion (``from_yeadon(knee_flexion=position("tuck").knee_flexion)``).
    name : {"pike", "tuck", "straight"}
    links : {2, 3}
        2: the two-link body (:meth:`SagittalBody.two_link`): ``phi`` in
        :math:`[\\psi_{min} - \\pi + \\delta, \\psi_{max} - \\pi + \\delta]`, ``u_max`` the hip rate.
        3: the three-part body (:meth:`SagittalBody.three_part`): ``hip`` in
        :math:`[\\pi - \\psi_{max}, \\pi - \\psi_{min}]`, ``shoulder`` in
        :math:`[\\pi - \\sigma_{max}, \\pi - \\sigma_{min}]`, ``u_hip`` and ``u_shoulder`` bounds.
    shoulder_flexion : float
        The two-link body's fixed arm angle :math:`\\sigma` (its :math:`\\delta` depends on it).
    hip_rate, shoulder_rate : float, optional
        Other rate limits (rad/s) than the data's.

    Returns
    -------
    acroplan.Limits

    Raises
    ------
    InvalidInputError
        The body's knees are not at the position's flexion, or an argument is out of range.
    """
    pos = position(name)
    if not isinstance(body, SagittalBody):
        raise InvalidInputError("body", f"must be a SagittalBody, got {type(body).__name__}",
                                "build it with from_yeadon() or from_height_mass()")
    if abs(body.knee_flexion - pos.knee_flexion) > 1e-9:
        raise InvalidInputError(
            "position", f"{name!r} holds the knees at {pos.knee_flexion:.4g} rad, but the body was built with "
            f"knee_flexion = {body.knee_flexion:.4g} rad",
            f"build the body with knee_flexion={pos.knee_flexion!r} (position({name!r}).knee_flexion)")
    hr = pos.hip_rate if hip_rate is None else finite_number("hip_rate", hip_rate)
    sr = pos.shoulder_rate if shoulder_rate is None else finite_number("shoulder_rate", shoulder_rate)
    for field, v in (("hip_rate", hr), ("shoulder_rate", sr)):
        if not v > 0:
            raise InvalidInputError(field, f"must be > 0, got {v:g}", "give the joint's top speed in rad/s")
    lo, hi = pos.hip
    if links == 2:
        d = body.phi_offset(finite_number("shoulder_flexion", shoulder_flexion))
        return Limits({"phi": (lo - math.pi + d, hi - math.pi + d)}, u_max=hr)
    if links == 3:
        slo, shi = pos.shoulder
        return Limits({"hip": (math.pi - hi, math.pi - lo), "shoulder": (math.pi - shi, math.pi - slo)},
                      {"u_hip": hr, "u_shoulder": sr})
    raise InvalidInputError("links", f"must be 2 (split at the hips) or 3 (hips and shoulders), got {links!r}",
                            "give links=2 or links=3")
