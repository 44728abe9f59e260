"""The 3-D human's strength as data: the largest torque of each joint (``data/strength_3d.toml``),
each value with its source or marked an estimate, as ``data/limits_3d.toml`` gives the ranges and
rates.

A joint's strength is one number for both directions, the weaker direction's largest torque (N m,
one joint): the planner's limit is :math:`|\\tau_j| \\le \\tau_{max,j}`
(``acroplan.plan(..., tau_max={joint: value})``). Values given per kilogram of body mass (the
knee's, the elbow's) are scaled by the body's mass.

=====================  ==========  ================================================  ==========
joint kind             N m         source                                            estimate
=====================  ==========  ================================================  ==========
shoulder flexion       89.9        mean of young men, static at 0 deg (flexion the    no
                                   weaker way: Ivey et al. 1985)
shoulder abduction     56.2        from the static flexion by Ivey et al.'s ratios    yes
                                   (extension 5:4 flexion, adduction 2:1 abduction,
                                   adduction above extension)
shoulder rotation      37.5        two thirds of that (Ivey: internal 3:2 external)   yes
elbow flexion          0.67 / kg   Lategan & Kruger 2003 (extension, the weaker)      no
hip flexion            157.3       Jackson 2010 via Millard et al. 2019               no
                                   (``limits.toml``)
hip abduction          100.0       none found                                         yes
knee flexion           1.385 / kg  Sarabon et al. 2021 (flexion, the weaker)          no
spine                  150 / 60    none found (torsion 60)                            yes
=====================  ==========  ================================================  ==========

These are isometric peaks (or concentric ones, below them) of ordinary young men, and the hip's of
one elite gymnast: a plausibility bound, not a model of strength over angle and rate.
"""

from __future__ import annotations

import functools
import tomllib
from importlib import resources

from ...core.errors import InvalidInputError, finite_number
from .limits import human_data
from .spatial_body import JOINTS

__all__ = ["strength_data", "joint_strength", "torque_limits", "strength_report", "capacity"]


@functools.lru_cache(maxsize=1)
def _raw() -> dict:
    text = resources.files(__package__).joinpath("data", "strength_3d.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


@functools.lru_cache(maxsize=1)
def strength_data() -> dict:
    """``data/strength_3d.toml`` with ``same_as`` resolved: ``data["torques"]["hip_flexion"]`` is
    ``{"value": 157.3, "source": "Jackson2010", "estimate": False, "note": ..., "same_as": ...}``;
    ``data["sources"]`` merges ``limits.toml``'s."""
    raw = _raw()
    out = {"sources": {**human_data()["sources"], **raw["sources"]}, "torques": {}}
    for kind, entry in raw["torques"].items():
        if "same_as" in entry:
            ref = human_data()
            for key in entry["same_as"].split("."):
                ref = ref[key]
            e = {k: ref[k] for k in ("value", "source", "estimate", "note") if k in ref}
            e["same_as"] = entry["same_as"]
        else:
            e = dict(entry)
        out["torques"][kind] = e
    return out


def joint_strength(kind: str, mass: float) -> float:
    """The strength (N m) of one joint of kind ``kind`` (``"shoulder_flexion"``, ...; the
    ``kind`` of :data:`~acroplan.families.human.spatial_body.JOINTS`) of a body of ``mass`` kg."""
    t = strength_data()["torques"]
    if kind not in t:
        raise InvalidInputError("kind", f"{kind!r} is not a joint kind of the strength data", f"kinds: {sorted(t)}")
    e = t[kind]
    if "per_kg" in e:
        return float(e["per_kg"]) * finite_number("mass", mass)
    return float(e["value"])


def torque_limits(body) -> dict[str, float]:
    """``{joint name: tau_max}`` (N m) of every joint of a 3-D human (built by
    :func:`~acroplan.families.human.spatial_body.spatial_from_yeadon` or
    :func:`~acroplan.families.human.spatial_body.spatial_from_height_mass`): what
    ``acroplan.plan(..., tau_max=...)`` takes.

    Examples
    --------
    >>> from acroplan.families.human.spatial_body import spatial_from_yeadon
    >>> from acroplan.families.human.strength import torque_limits
    >>> torque_limits(spatial_from_yeadon(joints="arms"))["right_shoulder_abduction"]
    56.2
    """
    mass = float(sum(link.mass for link in body.links))
    out = {}
    for name in body.links.joint_names:
        if name not in JOINTS:
            raise InvalidInputError("body", f"joint {name!r} is not a joint of the 3-D human",
                                    "give a body built by spatial_from_yeadon")
        out[name] = joint_strength(JOINTS[name].kind, mass)
    return out


def capacity(body) -> dict:
    """What a 3-D human can do, as ``acroplan.plan``'s ``capacity=`` (a yardstick, not a limit: a
    success whose peak torque at a joint is above that joint's strength carries a warning saying
    so): ``{"torques": {joint: (strength N m, source)}}``, the source the strength data's key and
    "estimate" when the value is one. The rates need no yardstick: the 3-D human's rate limits
    (``data/limits_3d.toml``) are limits of every plan. A problem file's 3-D human brings it.

    Examples
    --------
    >>> from acroplan.families.human.spatial_body import spatial_from_yeadon
    >>> from acroplan.families.human.strength import capacity
    >>> capacity(spatial_from_yeadon(joints="arms"))["torques"]["left_shoulder_abduction"]
    (56.2, 'strength_3d.toml: Ivey1985, an estimate')
    """
    data = strength_data()["torques"]
    out = {}
    for name, top in torque_limits(body).items():
        e = data[JOINTS[name].kind]
        source = e.get("source") or "no source"
        out[name] = (top, f"strength_3d.toml: {source}" + (", an estimate" if e["estimate"] else ""))
    return {"torques": out}


def strength_report(result) -> dict[str, dict]:
    """Each joint's peak planned torque against its strength: ``{joint: {"peak": N m, "limit":
    N m, "ratio": peak / limit, "estimate": bool}}``, the peaks those of
    :func:`acroplan.core.effort.effort_summary` (sampled, and refined between the samples: what
    ``acroplan plan`` reports)."""
    from ...core.effort import effort_summary

    body = result.system
    lim = torque_limits(body)
    effort = effort_summary(result)
    data = strength_data()["torques"]
    out = {}
    for name in body.links.joint_names:
        peak = float(effort[name].peak_torque)
        out[name] = {"peak": peak, "limit": lim[name], "ratio": peak / lim[name],
                     "estimate": bool(data[JOINTS[name].kind]["estimate"])}
    return out
