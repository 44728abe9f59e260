"""A human body's problem-file table: ``[body]`` with ``yeadon`` (a measurement file, or a bundled
sample by name) or ``height``, ``mass`` and ``sex`` (de Leva's tables), ``split``, ``position``,
``knee_flexion``, ``shoulder_flexion`` and ``angular_momentum`` (docs/problem-files.md). Split at the
hips the body is an :class:`~acroplan.Acrobot`, whose ``[limits]`` are plan keywords over the
position's; split at the hips and shoulders a :class:`~acroplan.PlanarBody`, whose limits are in its
link table.
"""

from __future__ import annotations

import math

from ...core.errors import InvalidInputError
from ...core.validate import BODY_VALUES, MAX_ANGLE, MAX_BODY, check_keys, choice_field, number, short, vector3
from ..acrobot.problem import read_limits as acrobot_limits
from ..planar.model import PlanarBody
from ..tree.problem import apply_limits
from .family import HUMAN_KEYS, reads  # the keys and the test, named by the family's descriptor
from .deleva import from_height_mass
from .limits import POSITIONS, human_limits, position
from .yeadon_body import MAX_MEASUREMENT_BYTES, SAMPLES, from_yeadon, sample_measurements

__all__ = ["reads", "read", "HUMAN_KEYS", "SPLITS"]

#: the keys of the planar human only, and of the 3-D human only
PLANAR_KEYS = ("split", "position", "knee_flexion", "shoulder_flexion")
SPATIAL_KEYS = ("joints", "posture")
#: the human models: in the sagittal plane (split at the hips, or the hips and shoulders), in 3-D
MODELS = ("2d", "3d")
#: how a human body is split: at the hips (the two-link body), at the hips and the shoulders
SPLITS = ("hips", "hips+shoulders")
#: what [body] may hold beside the human keys (refused with a message naming the clash)
OTHER_KEYS = ("urdf", "link", "angular_momentum")


def read(table: str, data: dict, limits: dict | None, context):
    """The human body of ``[body]`` and, split at the hips (an acrobot), the plan keywords of the
    file's ``[limits]`` over the position's."""
    check_keys("body", data, HUMAN_KEYS + OTHER_KEYS)
    model = choice_field("body.model", data.get("model", "2d"), MODELS, "3d")
    if model == "3d":
        from .strength import capacity as spatial_capacity

        system = _spatial_human(data, limits, context)
        return system, {"capacity": spatial_capacity(system)}
    given = [k for k in HUMAN_KEYS if k in data]
    wrong = [k for k in SPATIAL_KEYS if k in data]
    if wrong:
        raise InvalidInputError(f"body.{wrong[0]}", "is a key of the 3-D human", "add model = \"3d\" (and "
                                "angular_momentum = [Lx, Ly, Lz]), or drop it for the planar human")
    if isinstance(data.get("angular_momentum"), list):
        raise InvalidInputError(f"body.{given[0]}", "is a key of a human (planar) body, and angular_momentum is a "
                                "vector [Lx, Ly, Lz], which makes the body spatial",
                                "give model = \"3d\" for the 3-D human, or angular_momentum a number for the "
                                "planar human")
    system, defaults = _human_body(data, given, limits, context=context)
    if defaults or not isinstance(system, PlanarBody):
        return system, {**acrobot_limits(limits, defaults, degrees=context.degrees), "capacity": capacity(system)}
    return system, {"capacity": capacity(system)}


def capacity(system) -> dict:
    """What a human body can do, as plan()'s ``capacity=`` (a yardstick of a plan, not a limit of
    it: a success beyond it is warned of): the hip rate, the highest mean peak hip flexion rate
    measured in elite platform divers, and the hip strength, the larger of an elite gymnast's
    largest isometric hip flexion and extension torques, both hips together (``data/limits.toml``);
    split at the shoulders too, the shoulder's rate (an estimate, said so)."""
    from .limits import hip_rate_literature, hip_torque_literature, human_data

    rate = hip_rate_literature()[1]
    strength = max(hip_torque_literature(both=True))
    rate_src = "the highest mean peak hip rate of elite platform divers, Murtaugh 2000"
    torque_src = "an elite gymnast's largest isometric hip torque, both hips, Jackson 2010"
    if not isinstance(system, PlanarBody):  # split at the hips: the acrobot's u and phi
        return {"rates": {"u": (rate, rate_src)}, "torques": {"phi": (strength, torque_src)}}
    shoulder = float(human_data()["rates"]["shoulder"]["value"])
    return {"rates": {"u_hip": (rate, rate_src), "u_shoulder": (shoulder, "an estimate, data/limits.toml")},
            "torques": {"hip": (strength, torque_src)}}


_INSTALL_HUMAN = 'pip install "acroplan[human]"'


def yeadon_path(value, context) -> str:
    """The measurement file ``body.yeadon`` names: a bundled sample by name, or a path relative to the
    problem file's folder and confined to it and the folders the user allowed (``context``, a
    :class:`~acroplan.core.family.ReadContext`)."""
    if not isinstance(value, str) or not value.strip():
        raise InvalidInputError("body.yeadon", "must be a measurement file or a bundled sample's name in quotes, "
                                f"got {short(value)}", "write for example yeadon = \"male1\" (bundled: "
                                f"{sorted(SAMPLES)}) or yeadon = \"measurements.txt\"")
    if value in SAMPLES:
        return sample_measurements(value)
    return str(context.file("body.yeadon", value, example="yeadon = \"measurements.txt\"",
                            what="a yeadon measurement file (95 measurements in yeadon's format, a few kB) or a "
                            f"bundled sample's name ({sorted(SAMPLES)})", most_bytes=MAX_MEASUREMENT_BYTES))


#: the human family's argument names as the file names them
_HUMAN_FIELDS = {"height": "body.height", "mass": "body.mass", "sex": "body.sex", "knee_flexion": "body.knee_flexion",
                 "measurements": "body.yeadon", "shoulder_flexion": "body.shoulder_flexion",
                 "angular_momentum": "body.angular_momentum"}


def human_error(e: InvalidInputError, source: str) -> InvalidInputError:
    """The human family's error with its field as the file names it (a part's mass or inertia that a
    measurement file makes non-physical: the file's field ``source``)."""
    head = e.field.split(".", 1)[0].split("[", 1)[0]
    if head in _HUMAN_FIELDS and not (head == "mass" and source == "body.yeadon"):
        return InvalidInputError(_HUMAN_FIELDS[head] + e.field[len(head):], e.problem, e.fix)
    return InvalidInputError(source, f"makes {e.field} {e.problem}", e.fix)


def _human_body(data: dict, given: list, limits: dict | None, *, context):
    """A human body from ``[body]`` (``yeadon`` or ``height``/``mass``; module docstring), and the
    default limits of an acrobot (split at the hips) in radians."""
    _check_one_description(data, given)
    if "angular_momentum" not in data:
        raise InvalidInputError("body.angular_momentum", "is missing", "give P0, the angular momentum about the "
                                "somersault axis in kg m^2/s (> 0 for a forward somersault; acroplan least-momentum "
                                "gives the least one for the file's turn)")
    P0 = number("body.angular_momentum", data["angular_momentum"], MAX_BODY, BODY_VALUES)
    split = choice_field("body.split", data.get("split", "hips"), SPLITS, "hips")
    pos = data.get("position")
    if pos is not None:
        pos = choice_field("body.position", pos, tuple(POSITIONS), "pike")
    kappa = (number("body.knee_flexion", data["knee_flexion"], MAX_ANGLE, "angles") if "knee_flexion" in data
             else position(pos).knee_flexion if pos is not None else 0.0)
    sigma = 0.0
    if "shoulder_flexion" in data:
        if split != "hips":
            raise InvalidInputError("body.shoulder_flexion", f"is the arms' fixed angle of split = \"hips\", and this "
                                    f"body is split = \"{split}\": its arms move (the joint shoulder)",
                                    "give the shoulder's angles in [plan].shoulder, and drop body.shoulder_flexion")
        sigma = number("body.shoulder_flexion", data["shoulder_flexion"], MAX_ANGLE, "angles")
        if not -math.pi <= sigma <= math.pi:
            raise InvalidInputError("body.shoulder_flexion", f"must be an angle in radians in [-pi, pi], got {sigma:g}",
                                    "write for example shoulder_flexion = \"pi/2\" (arms forward; 0: at the sides, "
                                    "pi: overhead)")
    source = "body.yeadon" if "yeadon" in data else "body.height"
    body = _sagittal_body(data, kappa, source, context)
    lim = None
    if pos is not None:
        try:
            lim = human_limits(body, pos, links=2 if split == "hips" else 3, shoulder_flexion=sigma)
        except InvalidInputError as e:
            if e.field != "position":  # pragma: no cover - the arguments were checked above
                raise human_error(e, "body.position") from None
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
        raise human_error(e, source) from None
    table = apply_limits(planar.links, {} if limits is None else limits, context.degrees)
    return (planar if table is planar.links else PlanarBody(table, P0=P0)), {}


def _check_one_description(data: dict, given: list) -> None:
    """A human ``[body]`` describes the body one way: not with a URDF or link tables, and by a
    measurement file (``yeadon``) or by ``height`` and ``mass`` (de Leva's tables), not both."""
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


def _sagittal_body(data: dict, kappa: float, source: str, context):
    """The :class:`~acroplan.families.human.body.SagittalBody` of ``[body]``: from Yeadon's
    measurements or de Leva's tables, the knees flexed by ``kappa``."""
    try:
        if "yeadon" in data:
            path = yeadon_path(data["yeadon"], context)
            try:
                return from_yeadon(path, knee_flexion=kappa)
            except ImportError:
                raise InvalidInputError("body.yeadon", "needs the yeadon package (Yeadon's inertia model), which is "
                                        "not installed", f"{_INSTALL_HUMAN}; or give height and mass instead of "
                                        "yeadon (de Leva's tables need nothing more)") from None
        else:
            height = number("body.height", data["height"], MAX_BODY, BODY_VALUES)
            mass = number("body.mass", data["mass"], MAX_BODY, BODY_VALUES)
            sex = data.get("sex", "male")
            if not isinstance(sex, str):
                raise InvalidInputError("body.sex", f"must be \"male\" or \"female\" in quotes, got {short(sex)}",
                                        "write sex = \"female\" or leave it out (male)")
            return from_height_mass(height, mass, sex=sex, knee_flexion=kappa)
    except InvalidInputError as e:
        raise (e if e.field.startswith("body.") else human_error(e, source)) from None


def _spatial_human(data: dict, limits, context):
    """The 3-D human (:func:`~acroplan.families.human.spatial_body.spatial_from_yeadon`, or from
    height and mass by de Leva's tables): ``joints`` a preset (``"arms"``, ``"arms+hips"``,
    ``"full"``) or a list of joint names, ``posture`` (``"straight"``, ``"pike"``, ``"tuck"``) for
    the joints held fixed, ``angular_momentum = [Lx, Ly, Lz]``; the file's ``[limits]`` over the
    data's ranges and rates."""
    from .spatial_body import PRESETS, POSTURES, spatial_from_height_mass, spatial_from_yeadon

    wrong = [k for k in PLANAR_KEYS if k in data]
    if wrong:
        raise InvalidInputError(f"body.{wrong[0]}", "is a key of the planar human, and model = \"3d\"",
                                "give joints = \"arms+hips\" and posture = \"pike\" for the 3-D human, or drop "
                                "model = \"3d\"")
    for key in ("urdf", "link"):
        if key in data:
            raise InvalidInputError(f"body.{key}", "is a key of a body of links, and this [body] is a human body",
                                    "describe the body one way")
    if "angular_momentum" not in data or not isinstance(data["angular_momentum"], list):
        raise InvalidInputError("body.angular_momentum", "must be three numbers [Lx, Ly, Lz] for the 3-D human"
                                + ("" if "angular_momentum" in data else " (it is missing)"),
                                "give for example angular_momentum = [-90.0, 0.0, 0.0] (a backward somersault: "
                                "Lx < 0 in Yeadon's frame, x to the left)")
    L = vector3("body.angular_momentum", data["angular_momentum"])
    joints = data.get("joints", "arms")
    if isinstance(joints, str):
        joints = choice_field("body.joints", joints, tuple(PRESETS), "arms+hips")
    elif not (isinstance(joints, list) and joints and all(isinstance(j, str) for j in joints)):
        raise InvalidInputError("body.joints", f"must be a preset or a list of joint names, got {short(joints)}",
                                f"write joints = \"arms\" (presets: {sorted(PRESETS)})")
    posture = choice_field("body.posture", data.get("posture", "straight"), tuple(POSTURES), "straight")
    try:
        if "yeadon" in data:
            path = yeadon_path(data["yeadon"], context)
            body = spatial_from_yeadon(path, joints=joints, posture=posture, angular_momentum=L)
        else:
            for key in ("height", "mass"):
                if key not in data:
                    raise InvalidInputError(f"body.{key}", "is missing", "give height (m) and mass (kg), or "
                                            "yeadon = \"male1\"")
            sex = data.get("sex", "male")
            body = spatial_from_height_mass(number("body.height", data["height"], MAX_BODY, BODY_VALUES),
                                            number("body.mass", data["mass"], MAX_BODY, BODY_VALUES),
                                            sex=sex if isinstance(sex, str) else str(sex), joints=joints,
                                            posture=posture, angular_momentum=L)
    except ImportError:
        raise InvalidInputError("body.yeadon", "needs the yeadon package (Yeadon's inertia model), which is not "
                                "installed", f"{_INSTALL_HUMAN}; or give height and mass instead of yeadon") from None
    except InvalidInputError as e:
        head = e.field.split(".", 1)[0].split("[", 1)[0]
        field = f"body.{e.field}" if head in ("joints", "posture", "angular_momentum") else e.field
        raise InvalidInputError(field if field.startswith(("body.", "limits.")) else f"body.{field}",
                                e.problem, e.fix) from None
    table = apply_limits(body.links, {} if limits is None else limits, context.degrees)
    return body if table is body.links else type(body)(table, L=L)
