"""A spatial body's problem-file tables: ``[body]`` with ``angular_momentum = [Lx, Ly, Lz]`` (a
list of three numbers makes the body spatial) and ``urdf`` or ``[[body.link]]`` tables, its
``[limits]`` written into the link table; the root's attitude in ``[plan]`` (one per waypoint) and
``[simulate]`` (the initial one) in any form of
:func:`~acroplan.families.spatial.rotations.as_quaternion`.
"""

from __future__ import annotations

from ...core.errors import InvalidInputError
from ...core.validate import MAX_ANGLE, MAX_BODY, BODY_VALUES, check_keys, matrix3, number, numbers, short, vector3
from ..tree.problem import link_records, read_tree_body
from .family import ATTITUDE_KEYS, BODY_KEYS, QUATERNION_STATES  # the keys, named by the family's descriptor
from .links import SpatialLink, SpatialLinkTable
from .model import SpatialBody
from .rotations import attitude_states
from .urdf import read_link_table

__all__ = ["reads", "read", "waypoints", "links_from_tables", "attitudes", "BODY_KEYS", "LINK_KEYS",
           "ATTITUDE_KEYS", "ATTITUDE_FORMS", "QUATERNION_STATES"]

#: the keys of each [[body.link]] (the fields of :class:`~acroplan.families.spatial.links.SpatialLink`)
LINK_KEYS = ("name", "parent", "mass", "inertia", "com", "joint", "axis", "rotation", "joint_name", "lower",
             "upper", "velocity")
#: the attitude keys in [plan] (one attitude per waypoint) and [simulate] (the initial one), and
#: the form of :func:`~acroplan.families.spatial.rotations.as_quaternion` each names
#: (``attitude``: a quaternion [w, x, y, z] or an inline table of any form); ``attitude_seq``
#: names another Euler sequence than Yeadon's
ATTITUDE_FORMS = ("quaternion", "rotvec", "rotvec_deg", "euler", "euler_deg")


def reads(table: str, data) -> bool:
    """A ``[body]`` whose ``angular_momentum`` is a list (of three numbers)."""
    return table == "body" and isinstance(data, dict) and isinstance(data.get("angular_momentum"), list)


def links_from_tables(tables) -> list:
    """:class:`~acroplan.families.spatial.links.SpatialLink` records from ``[[body.link]]`` tables
    (numbers checked and arithmetic read here; the tree and the inertias by ``SpatialLinkTable``)."""
    links = []
    for f, d, kw in link_records(tables, LINK_KEYS, "parent, joint and axis"):
        kw["mass"] = number(f"{f}.mass", d["mass"], MAX_BODY, BODY_VALUES)
        inertia = d["inertia"]
        if isinstance(inertia, list) and inertia and all(isinstance(r, list) for r in inertia):
            kw["inertia"] = matrix3(f"{f}.inertia", inertia, "[[0.1, 0, 0], [0, 0.2, 0], [0, 0, 0.2]]")
        else:
            kw["inertia"] = list(vector3(f"{f}.inertia", inertia))
        for key in ("com", "joint", "axis"):
            if key in d:
                kw[key] = vector3(f"{f}.{key}", d[key])
        if "rotation" in d:
            kw["rotation"] = matrix3(f"{f}.rotation", d["rotation"], "[[1, 0, 0], [0, 0, -1], [0, 1, 0]]")
        links.append(SpatialLink(**kw))
    return links


def read(table: str, data: dict, limits: dict | None, context) -> tuple[SpatialBody, dict]:
    """A :class:`~acroplan.families.spatial.model.SpatialBody` from ``[body]`` with
    ``angular_momentum = [Lx, Ly, Lz]`` (``urdf`` or ``[[body.link]]`` tables), the file's
    ``[limits]`` written into its link table."""
    check_keys("body", data, BODY_KEYS)
    body = read_tree_body(data, limits, context, kind="spatial", read_link_table=read_link_table,
                          table_of_links=lambda t: SpatialLinkTable(links_from_tables(t)),
                          momentum=lambda d: vector3("body.angular_momentum", d["angular_momentum"]),
                          make_body=lambda table, L: SpatialBody(table, L=L),
                          links_hint=" (name, parent, mass, inertia, com, joint, axis)")
    return body, {}


def attitude_entry(field: str, value, single: str | None):
    """One attitude as :func:`~acroplan.families.spatial.rotations.as_quaternion` takes it, its
    numbers read here (arithmetic with pi allowed): a quaternion ``[w, x, y, z]``, an inline table
    ``{euler_deg = [...]}`` (``quaternion``, ``rotvec``, ``rotvec_deg``, ``euler``, ``euler_deg``,
    optional ``seq``), or, under ``single`` (a form's own key), that form's three numbers."""
    if single is not None:
        return {single: list(vector3(field, value, MAX_ANGLE, "angles"))}
    if isinstance(value, list):
        return list(numbers(field, value, MAX_ANGLE, "angles"))
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if k == "seq":
                if not isinstance(v, str):
                    raise InvalidInputError(f"{field}.seq", f"must be a name in quotes, got {short(v)}",
                                            "write seq = \"yeadon\" or for example \"ZYX\"")
                out[k] = v
            elif k in ATTITUDE_FORMS:
                out[k] = list(numbers(f"{field}.{k}", v, MAX_ANGLE, "angles"))
            else:
                raise InvalidInputError(f"{field}.{k}", "is not a form of attitude",
                                        f"give one of {list(ATTITUDE_FORMS)} (and optionally seq)")
        return out
    raise InvalidInputError(field, f"must be a quaternion [w, x, y, z] or a table such as {{euler_deg = [0, 0, 90]}}, "
                            f"got {short(value)}", "write for example [1, 0, 0, 0]")


def attitude_key(table: str, d: dict) -> str:
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


def euler_seq(table: str, d: dict, key: str):
    seq = d.get("attitude_seq")
    if seq is None:
        return None
    if key not in ("attitude_euler", "attitude_euler_deg"):
        raise InvalidInputError(f"{table}.attitude_seq", f"is the sequence of Euler angles, and the attitude is "
                                f"given by {table}.{key}", f"drop {table}.attitude_seq, or give the attitude in Euler "
                                "angles")
    if not isinstance(seq, str):
        raise InvalidInputError(f"{table}.attitude_seq", f"must be a name in quotes, got {short(seq)}",
                                "write attitude_seq = \"yeadon\" or for example \"ZYX\"")
    return seq


def attitudes(table: str, d: dict, count: int | None) -> dict[str, tuple]:
    """The waypoints ``qw, qx, qy, qz`` from the attitude keys of ``d`` (``count`` waypoints; ``None``:
    one initial attitude)."""
    key = attitude_key(table, d)
    field = f"{table}.{key}"
    seq = euler_seq(table, d, key)
    single = ATTITUDE_KEYS[key]
    values = d[key] if count is not None else [d[key]]
    if count is not None:
        if not isinstance(values, list):
            raise InvalidInputError(field, f"must be a list of attitudes, one per waypoint, got {short(values)}",
                                    "write for example [[1, 0, 0, 0], [0, 0, 0, 1]]" if key == "attitude" else
                                    "write for example [[0, 0, 0], [0, 0, 90]]")
        if len(values) != count:
            raise InvalidInputError(field, f"has {len(values)} attitude(s) but {table}.times has {count}",
                                    "give one attitude per waypoint")
    entries = []
    for i, v in enumerate(values):
        e = attitude_entry(f"{field}[{i}]" if count is not None else field, v, single)
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


def waypoints(system, table: str, data: dict, count: int | None) -> dict[str, tuple]:
    """The attitude waypoints ``qw, qx, qy, qz`` of ``[plan]`` (``count`` of them) or the initial
    attitude of ``[simulate]`` (``count=None``)."""
    return attitudes(table, data, count)
