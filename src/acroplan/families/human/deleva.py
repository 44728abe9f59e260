"""Bodies from height and mass: de Leva's (1996) segment tables.

P. de Leva (1996), Adjustments to Zatsiorsky-Seluyanov's segment inertia parameters, *J.
Biomech.* 29(9):1223-1230, Table 4 (``data/de_leva_1996.toml``): for young adult men and women,
each segment's mass as a fraction of the body's, the position of its centre of mass as a fraction
of its length from one endpoint, and its radii of gyration as fractions of its length; and the
mean segment lengths of the subjects (stature 1.741 m for the men, 1.735 m for the women).

From height :math:`H` and mass :math:`M` (:func:`from_height_mass`)
-------------------------------------------------------------------
* **lengths** are de Leva's mean lengths scaled by :math:`H/H_{ref}` (a geometric scaling: an
  assumption, since proportions vary between people);
* **masses** are :math:`M\\,f_s / \\sum f`: the table's fractions :math:`f_s`, divided by their sum
  (100.00 % for the men, 99.99 % for the women as transcribed) so that the segments always add up
  to :math:`M`;
* **moments of inertia** about the somersault axis are :math:`m_s (r_s \\ell_s)^2` with the
  *transverse* (medio-lateral) radius of gyration :math:`r_s` (the table's columns are the
  sagittal, transverse and longitudinal axes; the transverse axis is normal to the sagittal plane,
  and it gives the larger value for the head and the smaller for the trunk, as their shapes do).

The segments and where they sit (the assumptions, in the straight anatomical position)
----------------------------------------------------------------------------------------
Every segment lies on its part's axis (no antero-posterior offsets):

* **trunk** (root; frame at the mid-hip, :math:`x` up): the trunk from the mid-hip to the
  mid-shoulder (Table 4's MIDS-MIDH trunk, so the shoulder joint centres sit at its top,
  :math:`x = \\ell_{MIDS}`), and the head from the vertex to C7 with C7 at
  :math:`x = \\ell_{CERV}` (Table 4's CERV-MIDH trunk length: C7 above the shoulders);
* **arms** (frame at the shoulder, :math:`x` to the hands): upper arm, forearm and hand (to the
  third metacarpal) in line, elbows and wrists straight;
* **legs** (frame at the hip, :math:`x` along the thighs): thigh, then shank and foot turned by
  the knee flexion :math:`\\kappa` towards the back (:math:`+y` of the legs' frame when they hang
  down), the foot pointed, in line with the shank, its heel at the lateral malleolus.

A standing body built this way is about 2 % taller than :math:`H` (the head and trunk chain of
C7 to the mid-hip and the leg chain overlap in reality); the masses are exact, the inertias as
good as the table's and these placements.
"""

from __future__ import annotations

import functools
import math
import tomllib
from importlib import resources

from ...core.errors import InvalidInputError, finite_number
from .body import Part, SagittalBody, combine

__all__ = ["de_leva_table", "segment_parameters", "from_height_mass", "SEXES", "SEGMENTS"]

SEXES = ("male", "female")
#: the segments of the table (main and alternative endpoints)
SEGMENTS = ("head", "trunk", "upper_trunk", "middle_trunk", "lower_trunk", "upper_arm", "forearm", "hand", "thigh",
            "shank", "foot", "head_to_c7", "trunk_from_c7", "trunk_from_shoulders")


@functools.lru_cache(maxsize=1)
def de_leva_table() -> dict:
    """The bundled table (``data/de_leva_1996.toml``) as a dict: ``table["segments"][name][sex]``
    has ``length_mm``, ``mass`` (%), ``com`` (% from the first of ``endpoints``), ``r_sag``,
    ``r_trans``, ``r_long`` (% of the length); ``table["reference"]["stature_mm"][sex]``."""
    text = resources.files(__package__).joinpath("data", "de_leva_1996.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def _sex(sex: str) -> str:
    if not isinstance(sex, str) or sex.lower() not in SEXES:
        raise InvalidInputError("sex", f"must be 'male' or 'female', got {sex!r}",
                                "de Leva's tables are for young adult men and women")
    return sex.lower()


def segment_parameters(segment: str, sex: str, height: float) -> dict:
    """One segment's length (m), mass fraction (of 1), centre of mass (fraction of the length from
    its first endpoint) and transverse radius of gyration (fraction of the length), for a body of
    stature ``height`` (m).

    Returns
    -------
    dict
        ``length``, ``mass_fraction``, ``com``, ``r_trans``, ``endpoints``.
    """
    table = de_leva_table()
    sex = _sex(sex)
    if segment not in table["segments"]:
        raise InvalidInputError("segment", f"{segment!r} is not in the table", f"segments: {list(table['segments'])}")
    row = table["segments"][segment][sex]
    scale = height / (table["reference"]["stature_mm"][sex] / 1000.0)
    return {"length": row["length_mm"] / 1000.0 * scale, "mass_fraction": row["mass"] / 100.0,
            "com": row["com"] / 100.0, "r_trans": row["r_trans"] / 100.0,
            "endpoints": tuple(table["segments"][segment]["endpoints"])}


def _rod(mass: float, start: float, length: float, com: float, r: float) -> Part:
    """A segment on the x axis from ``start`` to ``start + length`` (its centre of mass at the
    fraction ``com`` of the length from ``start``)."""
    return Part(mass, (start + com * length, 0.0), mass * (r * length) ** 2)


def stature_and_mass(height, mass) -> tuple[float, float]:
    """``height`` (m) and ``mass`` (kg) checked against the ranges de Leva's tables scale to
    (1.0-2.5 m, 20-250 kg), naming the field."""
    H = finite_number("height", height)
    M = finite_number("mass", mass)
    if not 1.0 <= H <= 2.5:
        raise InvalidInputError("height", f"must be a stature in metres between 1.0 and 2.5, got {H:g}",
                                "give the height in metres (1.75, not 175)")
    if not 20.0 <= M <= 250.0:
        raise InvalidInputError("mass", f"must be a body mass in kg between 20 and 250, got {M:g}",
                                "give the mass in kilograms")
    return H, M


def from_height_mass(height: float, mass: float, *, sex: str = "male", knee_flexion: float = 0.0) -> SagittalBody:
    """A :class:`~acroplan.families.human.body.SagittalBody` from stature and mass by de Leva's
    (1996) tables (module docstring: the scaling and the placements assumed).

    Parameters
    ----------
    height : float
        Stature (m), 1.0 to 2.5.
    mass : float
        Body mass (kg), 20 to 250.
    sex : {"male", "female"}
    knee_flexion : float
        :math:`\\kappa` (rad, 0 to :math:`\\pi`): the knees' fixed flexion.

    Returns
    -------
    SagittalBody

    Examples
    --------
    >>> body = from_height_mass(1.741, 73.0, sex="male")
    >>> round(body.mass, 12)
    73.0
    """
    H, M = stature_and_mass(height, mass)
    kappa = finite_number("knee_flexion", knee_flexion)
    if not 0.0 <= kappa <= math.pi:
        raise InvalidInputError("knee_flexion", f"must be in [0, pi], got {kappa:g}",
                                "give the knee flexion in radians, 0 for straight knees")
    sex = _sex(sex)
    seg = {name: segment_parameters(name, sex, H) for name in
           ("head_to_c7", "trunk_from_c7", "trunk_from_shoulders", "upper_arm", "forearm", "hand", "thigh", "shank",
            "foot")}
    # one head, one trunk, two of each limb segment: the fractions' sum (to rescale them to 1)
    total = seg["head_to_c7"]["mass_fraction"] + seg["trunk_from_shoulders"]["mass_fraction"] + 2.0 * sum(
        seg[s]["mass_fraction"] for s in ("upper_arm", "forearm", "hand", "thigh", "shank", "foot"))

    def m(name, count=1):
        return M * count * seg[name]["mass_fraction"] / total

    def rod(name, start, count=1, reverse=False):
        s = seg[name]
        com = 1.0 - s["com"] if reverse else s["com"]
        return _rod(m(name, count), start, s["length"], com, s["r_trans"])

    # trunk frame: x up from the mid-hip. The MIDS-MIDH trunk's centre of mass is given from MIDS
    # (its first endpoint), so measured from the mid-hip it is at (1 - com) of its length; the head
    # runs from C7 (at the CERV-MIDH length) up to the vertex, its centre at (1 - com) from C7.
    l_shoulder = seg["trunk_from_shoulders"]["length"]
    l_c7 = seg["trunk_from_c7"]["length"]
    trunk = combine([rod("trunk_from_shoulders", 0.0, reverse=True), rod("head_to_c7", l_c7, reverse=True)])
    # arms frame: x from the shoulders to the hands
    l_ua, l_fa = seg["upper_arm"]["length"], seg["forearm"]["length"]
    arms = combine([rod("upper_arm", 0.0, 2), rod("forearm", l_ua, 2), rod("hand", l_ua + l_fa, 2)])
    # legs frame: x along the thighs; shank and foot turned by kappa about the knee
    l_th, l_sh = seg["thigh"]["length"], seg["shank"]["length"]
    below = combine([rod("shank", 0.0, 2), rod("foot", l_sh, 2)]).moved((l_th, 0.0), kappa)
    legs = combine([rod("thigh", 0.0, 2), below])
    return SagittalBody(trunk=trunk, arms=arms, legs=legs, shoulder=(l_shoulder, 0.0), knee_flexion=kappa,
                        source=f"de Leva (1996), {sex}, {H:g} m, {M:g} kg")
