"""A planar body's problem-file table: ``[body]`` with ``urdf`` or ``[[body.link]]`` tables and
``angular_momentum`` (a number: the momentum about the axis normal to the plane), its ``[limits]``
written into the link table; and what ``acroplan reach`` proves of it (the exact interval for two
links, which are an acrobot; the rate-limit bound of the root's turn for more).
"""

from __future__ import annotations

import math

import numpy as np

from ...core.errors import InvalidInputError
from ...core.limits import Limits
from ...core.validate import BODY_VALUES, MAX_BODY, MIN_BODY, check_keys, number, pair_field
from ..acrobot.reach import reachable_set
from ..tree.problem import link_records, read_tree_body
from .family import BODY_KEYS  # the keys, named by the family's descriptor
from .links import Link, LinkTable
from .model import PlanarBody
from .urdf import read_link_table

__all__ = ["reads", "read", "links_from_tables", "reach_report", "two_link", "BODY_KEYS", "LINK_KEYS"]

#: the keys of each [[body.link]] (the fields of :class:`~acroplan.families.planar.links.Link`)
LINK_KEYS = ("name", "parent", "mass", "inertia", "com", "joint", "joint_name", "lower", "upper", "velocity")


def reads(table: str, data) -> bool:
    """Any ``[body]``: the planar family is asked last (the human and spatial families claim theirs first)."""
    return table == "body"


def links_from_tables(tables) -> list:
    """:class:`~acroplan.families.planar.links.Link` records from ``[[body.link]]`` tables (numbers
    checked and arithmetic read here; the tree is checked by ``LinkTable``)."""
    links = []
    for f, d, kw in link_records(tables, LINK_KEYS, "parent and joint"):
        for key in ("mass", "inertia"):
            v = number(f"{f}.{key}", d[key], MAX_BODY, BODY_VALUES)
            if 0 < v < MIN_BODY:
                raise InvalidInputError(f"{f}.{key}", f"is {v:.3g}: masses and inertias below {MIN_BODY:g} are less "
                                        "than the arithmetic carries",
                                        "change the units so that the numbers come nearer to 1")
            kw[key] = v
        for key in ("com", "joint"):
            if key in d:
                kw[key] = pair_field(f"{f}.{key}", d[key])
        links.append(Link(**kw))
    return links


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


def _momentum(data) -> float:
    if "angular_momentum" not in data:
        raise InvalidInputError("body.angular_momentum", "is missing", "give P0, the angular momentum about the "
                                "axis normal to the plane (0 for a body that starts at rest)")
    return number("body.angular_momentum", data["angular_momentum"], MAX_BODY, BODY_VALUES)


def _link_error(e: InvalidInputError, tables) -> InvalidInputError:
    if e.field.startswith("body.link[") and _looks_spatial(tables):
        return InvalidInputError(e.field, e.problem, e.fix + "; for a body in 3-D give angular_momentum = "
                                 "[Lx, Ly, Lz] (a list of three numbers makes the body spatial)")
    return e


def _body(table, P0) -> PlanarBody:
    body = PlanarBody(table, P0=P0)
    for k, v in body.lumped().items():
        if not (math.isfinite(v) and abs(v) <= MAX_BODY):
            raise InvalidInputError("links", f"makes the lumped parameter {k} = {v:.3g}, beyond {MAX_BODY:g} in size: "
                                    "more than the arithmetic carries",
                                    "change the units so that the numbers come nearer to 1")
    return body


def read(table: str, data: dict, limits: dict | None, context) -> tuple[PlanarBody, dict]:
    """A :class:`~acroplan.families.planar.model.PlanarBody` from ``[body]`` (``urdf`` or
    ``[[body.link]]`` tables, ``angular_momentum`` a number) with the file's ``[limits]`` written
    into its link table."""
    check_keys("body", data, BODY_KEYS)
    body = read_tree_body(data, limits, context, kind="planar", read_link_table=read_link_table,
                          table_of_links=lambda t: LinkTable(links_from_tables(t)), momentum=_momentum,
                          make_body=_body, links_hint="; for a human body yeadon = \"male1\" (a measurement file "
                          "or a bundled sample) or height and mass", link_error=_link_error)
    return body, {}


def segments(problem):
    names = problem.system.state_names
    for k in range(len(problem.times) - 1):
        x0 = [problem.waypoints[n][k] for n in names]
        x1 = [problem.waypoints[n][k + 1] for n in names]
        if any(v is None for v in x0 + x1):
            raise InvalidInputError(f"plan.{names[[v is None for v in x0 + x1].index(True) % len(names)]}",
                                    "has a free waypoint: what is reachable is asked from given states",
                                    "give every state at every waypoint for acroplan reach")
        yield k, np.array(x0, dtype=float), np.array(x1, dtype=float), problem.times[k + 1] - problem.times[k]


def two_link(problem):
    """The problem's two-link body as the acrobot of text eq. (3), for the exact answers of the
    two-link body (:meth:`PlanarBody.as_acrobot`).

    Returns
    -------
    (Acrobot, psi0, delta, joint, limits)
        The acrobot, its angle offsets (:math:`\\theta_A = \\theta + \\psi_0`, :math:`\\varphi_A =
        \\varphi + \\delta`)), the joint's state name and the problem's limits
        in the acrobot's angles (``None`` without limits).

    Raises
    ------
    InvalidInputError
        For a body that has not exactly two links (``body``).
    """
    body = problem.system
    n = getattr(body, "n_links", None)
    if n != 2:
        raise InvalidInputError("body", f"has {n} links: the exact answer exists for the two-link body only "
                                "(it is an acrobot, whose reachable set is exact)",
                                "give a two-link body ([robot], or a [body] with two links); for more links "
                                "plan at several momenta (acroplan sweep, docs/sweeps.md)")
    acro, psi0, delta = body.as_acrobot()
    joint = body.links.joint_names[0]
    lim = problem.limits
    alim = None
    if lim.active:
        lo, hi = lim.bounds(joint)
        U = lim.input_bound(f"u_{joint}")
        sb = {"phi": (None if lo == -math.inf else lo + delta, None if hi == math.inf else hi + delta)} \
            if (lo > -math.inf or hi < math.inf) else {}
        alim = Limits(sb, {"u": U} if U is not None else None)
    return acro, psi0, delta, joint, alim


def _reach_two_links(problem) -> list[dict]:
    """The exact interval of a two-link body: it is an acrobot (``PlanarBody.as_acrobot``)."""
    acro, psi0, delta, joint, alim = two_link(problem)
    out = []
    for k, x0, x1, T in segments(problem):
        kw = dict(theta0=float(x0[0]) + psi0, phi0=float(x0[1]) + delta, phiT=float(x1[1]) + delta, T=T)
        free = reachable_set(acro, **kw)
        R = reachable_set(acro, **kw, limits=alim) if alim is not None else free
        shift = lambda r: None if not r.success else [r.low - psi0, r.high - psi0]  # noqa: E731
        target = float(x1[0])
        inside = R.contains(target + psi0)
        out.append({
            "index": k, "t0": problem.times[k], "t1": problem.times[k + 1], "theta0": float(x0[0]),
            "joint": joint, "joint0": float(x0[1]), "jointT": float(x1[1]), "target_theta": target,
            "kind": "exact (a two-link body is an acrobot)",
            "interval": shift(free), "interval_closed": free.closed,
            "interval_with_limits": shift(R), "with_limits_closed": R.closed,
            "empty_reason": R.message or None, "reachable": bool(inside),
        })
    return out


def _reach_bound(problem) -> list[dict]:
    body = problem.system
    lim = problem.limits
    unlimited = [j for j in body.links.joint_names if lim.input_bound(f"u_{j}") is None]
    if unlimited:
        raise InvalidInputError(
            "reach", f"exact reachable sets exist for the two-link body only, and this body has "
            f"{body.n_links} links; joint {unlimited[0]!r} has no rate limit, so no bound on theta(T) is known "
            "either", f"give every joint a rate limit (limits.u_{unlimited[0]} or limits.u_max) to get a proven "
            "bound, or plan the file with acroplan plan")
    out = []
    for k, x0, x1, T in segments(problem):
        B = float(body.turn_bound(x0, x1, T, lim))
        proof = body.check_segment(x0, x1, T, lim)
        target = float(x1[0])
        out.append({
            "index": k, "t0": problem.times[k], "t1": problem.times[k + 1], "theta0": float(x0[0]),
            "start": dict(zip(body.state_names, map(float, x0))),
            "end": dict(zip(body.state_names[1:], map(float, x1[1:]))), "target_theta": target,
            "kind": "bound (rate limits): |theta(T) - theta(0)| <= B; inside it is not proven reachable",
            "bound": B, "interval": None, "interval_closed": True,
            "interval_with_limits": [float(x0[0]) - B, float(x0[0]) + B], "with_limits_closed": True,
            "empty_reason": None if proof is None else proof.reason,
            "reachable": False if proof is not None else None,
        })
    return out


def reach_report(problem) -> list[dict]:
    """What can be proven about every segment's reachable :math:`\\theta(T)`: two links, the exact
    interval (:func:`two_link`); more, the rate-limit bound of :meth:`PlanarBody.turn_bound
    <acroplan.families.planar.model.PlanarBody.turn_bound>`."""
    if problem.system.n_links == 2:
        return _reach_two_links(problem)
    return _reach_bound(problem)
