"""What the problem-file tables of tree bodies share (planar and spatial link tables, URDF files,
limits written into the link table); each family reads its own link fields."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

from ...core.errors import InvalidInputError
from ...core.validate import MAX_ANGLE, MAX_BODY, MAX_LINKS, check_keys, name_field, number, short

__all__ = ["renamed", "link_records", "urdf_table", "apply_limits", "read_tree_body"]


def renamed(e: InvalidInputError, old: str, new: str) -> InvalidInputError:
    """``e`` with its field's prefix ``old`` (``links``) written as the file's ``new`` (``body.link``)."""
    field = e.field
    if field == old or field.startswith((old + "[", old + ".")):
        field = new + field[len(old):]
    return InvalidInputError(field, e.problem, e.fix)


def link_records(tables, allowed, joint_keys: str):
    """``(field, table, names)`` for each ``[[body.link]]`` table: the array checked (not empty, at
    most :data:`MAX_LINKS`), each table's keys checked against ``allowed``, its name fields read; the
    families' readers add the numbers. The joint's limits (``lower``, ``upper``: angles;
    ``velocity``: a rate) are read here, and ``parent`` is ``None`` for the root."""
    if not isinstance(tables, list) or not tables or not all(isinstance(t, dict) for t in tables):
        raise InvalidInputError("body.link", f"must be an array of tables ([[body.link]]), got {short(tables)}",
                                "write one [[body.link]] table per link (docs/problem-files.md)")
    if len(tables) > MAX_LINKS:
        raise InvalidInputError("body.link", f"has {len(tables)} links, more than {MAX_LINKS}: the compiled "
                                "integrator of such a body takes hours to build", f"give at most {MAX_LINKS} links "
                                "(join links that move together)")
    for i, d in enumerate(tables):
        f = f"body.link[{i}]"
        check_keys(f, d, allowed)
        for key in ("name", "mass", "inertia"):
            if key not in d:
                raise InvalidInputError(f"{f}.{key}", "is missing", "give every link a name, mass and inertia (and "
                                        f"every link but the root its {joint_keys})")
        kw = {k: name_field(f"{f}.{k}", d[k]) for k in ("name", "parent", "joint_name") if k in d}
        for key in ("lower", "upper"):
            if key in d:
                kw[key] = number(f"{f}.{key}", d[key], MAX_ANGLE, "angles")
        if "velocity" in d:
            kw["velocity"] = number(f"{f}.velocity", d["velocity"], MAX_BODY, "rates")
        kw.setdefault("parent", None)
        yield f, d, kw


def urdf_table(value, context, read_link_table, what: str):
    """The link table of the URDF file ``value`` (relative to the problem file's folder, and confined
    to it and the folders the user allowed: ``context``, a :class:`~acroplan.core.family.ReadContext`),
    read by the family's ``read_link_table`` (through Pinocchio); ``what`` names the kind of body in
    messages (``"planar"``, ``"spatial"``)."""
    path = context.file("body.urdf", value, example="urdf = \"diver.urdf\"", what=f"the .urdf file of a {what} body")
    name = Path(value).name
    try:
        table = read_link_table(path)
    except InvalidInputError as e:
        problem = e.problem if e.field == "urdf" else f"{e.field} {e.problem}"
        if not problem.startswith(name):
            problem = f"{name if len(name) <= 100 else name[:97] + chr(46) * 3}: {problem}"
        raise InvalidInputError("body.urdf", problem, e.fix) from None
    if len(table) > MAX_LINKS:  # pragma: no cover - read_link_table counts the links before Pinocchio reads them
        raise InvalidInputError("body.urdf", f"{name} has {len(table)} moving links, more than "
                                f"{MAX_LINKS}: the compiled integrator of such a body takes hours to build",
                                f"give at most {MAX_LINKS} links (join links that move together with fixed joints)")
    return table


_UNSET = object()


def apply_limits(table, lim, degrees: bool):
    """The link table with the file's ``[limits]`` written into it (per joint ``NAME_min``,
    ``NAME_max``, ``u_NAME``; ``u_max`` for every joint; ``"none"`` drops a limit)."""
    names = table.joint_names
    allowed = ("u_max",) + tuple(k for j in names for k in (f"{j}_min", f"{j}_max", f"u_{j}"))
    check_keys("limits", lim, allowed)
    if not lim:
        return table

    def value(key, angle: bool):
        v = lim[key]
        if isinstance(v, str) and v.strip().lower() == "none":
            return None
        x = number(f"limits.{key}", v, *((MAX_ANGLE, "angles") if angle else (MAX_BODY, "rates")))
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


def read_tree_body(data: dict, limits, context, *, kind: str, read_link_table, table_of_links, momentum,
                   make_body, links_hint: str, link_error=None):
    """The body of a ``[body]`` table of a tree family: a URDF (``urdf``, read by the family's
    ``read_link_table``) or ``[[body.link]]`` tables (``table_of_links(tables)``: the family's link
    table), the file's ``[limits]`` written into it, and ``make_body(table, momentum(data))``.

    ``kind`` names the body in messages (``"planar"``); ``links_hint`` says what a link table
    holds; ``link_error(e, tables)``, optional, adds a hint to an error of the link tables. The
    messages name the file's fields (``body.link[2].mass``, ``body.angular_momentum``).
    """
    if "urdf" in data and "link" in data:
        raise InvalidInputError("body", "gives both urdf and [[body.link]] tables",
                                "describe the body one way: a URDF file or link tables")
    if "urdf" not in data and "link" not in data:
        raise InvalidInputError("body.urdf", "is missing, and there are no [[body.link]] tables",
                                f"give urdf = \"body.urdf\" or one [[body.link]] table per link{links_hint}")
    moment = momentum(data)
    where = "body.urdf" if "urdf" in data else "body.link"
    if "urdf" in data:
        table = urdf_table(data["urdf"], context, read_link_table, kind)
    else:
        try:
            table = table_of_links(data["link"])
        except InvalidInputError as e:
            e = renamed(e, "links", "body.link")
            raise (link_error(e, data["link"]) if link_error is not None else e) from None
    table = apply_limits(table, {} if limits is None else limits, context.degrees)
    try:
        return make_body(table, moment)
    except InvalidInputError as e:
        raise renamed(renamed(renamed(e, "links", where), "P0", "body.angular_momentum"), "L",
                      "body.angular_momentum") from None
