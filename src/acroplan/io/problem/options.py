"""The ``[options]`` of a problem file: one reader per key, the plan() keyword it becomes."""

from __future__ import annotations

from typing import Any, Callable

from ...core.errors import InvalidInputError
from ...core.family import family_of
from ...core.system import ControlAffineSystem, torque_model_of
from ...core.validate import MAX_BODY, MAX_EVALUATIONS, TOL_RANGE, did_you_mean, number, short

__all__ = ["OPTION_PARSERS", "OPTION_KEYS", "OBJECTIVES", "torque_joints"]


def _choice(names: tuple[str, ...]):
    def parse(field, v, system):
        if not isinstance(v, str) or v not in names:
            raise InvalidInputError(field, f"must be one of {list(names)}, got {short(v)}",
                                    f"write {field.rsplit('.', 1)[-1]} = \"{names[0]}\"")
        return v
    return parse


def _whole_option(most: int, example: str):
    def parse(field, v, system):
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= most:
            raise InvalidInputError(field, f"must be a whole number from 1 to {most}, got "
                                    f"{short(v) if not isinstance(v, int) or abs(v) < 10**30 else 'a huge integer'}",
                                    f"write for example {example}")
        return v
    return parse


def _time_limit(field, v, system):
    return number(field, v, 1e7, "seconds")


def _bool_option(field, v, system):
    if not isinstance(v, bool):
        raise InvalidInputError(field, f"must be true or false, got {short(v)}",
                                f"write {field.rsplit('.', 1)[-1]} = true")
    return v


def _rate_option(field, v, system):
    """A number (every input), or for several inputs a table by input name."""
    if isinstance(v, dict):
        out = {}
        for k, x in v.items():
            if k not in system.input_names:
                shown = k if len(k) <= 60 and k.isprintable() else short(k, 60)
                raise InvalidInputError(f"{field}.{shown}", "is not an input",
                                        f"inputs are {list(system.input_names)}")
            out[k] = number(f"{field}.{k}", x, MAX_BODY, "rates")
        return out
    return number(field, v, MAX_BODY, "rates")


def _tol(field, v, system):
    tol = number(field, v)
    if not TOL_RANGE[0] <= tol <= TOL_RANGE[1]:
        raise InvalidInputError(field, f"is {tol:.3g}; tolerances outside [{TOL_RANGE[0]:g}, {TOL_RANGE[1]:g}] are "
                                "beyond what double precision can meet or mean", "write for example 1e-10")
    return tol


OBJECTIVES = ("energy", "torque")


def torque_joints(field: str, system) -> tuple[str, ...]:
    """The joints of ``system``'s torque model (the acrobot's ``("phi",)``, a body's joint names), or
    :class:`InvalidInputError` naming ``field`` when the system gives no torques."""
    model, why = torque_model_of(system)
    if model is None:
        fam = family_of(system)
        if fam is not None and fam.torque_hint is not None:
            problem, fix = fam.torque_hint
            raise InvalidInputError(field, problem, f"{fix}, or leave {field} out")
        raise InvalidInputError(field, f"needs the joint torques, and {why}", f"leave {field} out")
    return tuple(str(n) for n in model.joint_names)


def _objective_option(field, v, system):
    """``"energy"`` (least integral of u^2) or ``"torque"`` (least integral of tau^2, needs torques)."""
    if not isinstance(v, str) or v not in OBJECTIVES:
        raise InvalidInputError(field, f"must be \"energy\" or \"torque\", got {short(v)}",
                                did_you_mean(v, OBJECTIVES) + "write objective = \"energy\" (least integral of u^2) or "
                                "\"torque\" (least integral of tau^2), or leave it out for the fast feasible plan")
    if v == "torque":
        try:
            torque_joints(field, system)
        except InvalidInputError as e:
            raise InvalidInputError(e.field, e.problem, e.fix.replace(f"leave {field} out",
                                                                      "write objective = \"energy\"")) from None
    return v


def _torque_value(field, v):
    x = number(field, v, MAX_BODY, "torques")
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
                shown = k if len(k) <= 60 and k.isprintable() else short(k, 60)
                raise InvalidInputError(f"{field}.{shown}", "is not a joint of the body",
                                        did_you_mean(k, joints) + f"joints are {list(joints)}")
            out[k] = _torque_value(f"{field}.{k}", x)
        return out
    if isinstance(v, list):
        raise InvalidInputError(field, f"must be a number or a table by joint, got {short(v)}",
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
    "max_coefficients": _whole_option(1000, "48"),
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
