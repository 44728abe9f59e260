"""Bundled example problems (the model zoo's problems), shared by the CLI, tests and docs.

Each example is a problem file in ``acroplan/io/data/`` (``acroplan examples --show NAME`` prints
it); a file may name another file beside it (the diver's URDF), which :func:`files` lists and
``acroplan init --example NAME`` copies too. :func:`command` says which command runs an example
(``plan``, ``simulate`` or ``nilpotent``).

:func:`names` lists them with one line each: the text's two-link body (``pike-dive``,
``pike-dive-limited``, ``chapter4``), planar bodies (``diver-somersault``, ``space-robot-turn``,
``three-rods-turn``, ``space-robot-arm-loop``) and a human body, ``platform-dive``: the 10 m
platform dive, 3.5 forward somersaults in pike, of Yeadon's bundled ``male1`` split at the hips,
energy-optimal within a diver's hip range and rate (the problem of
:func:`acroplan.families.human.examples.platform_dive_pike`; needs ``pip install
"acroplan[human]"``)::

    acroplan plan --example platform-dive --out platform-dive-out --animate
"""

from __future__ import annotations

import re
import tomllib
from importlib import resources
from pathlib import Path

from ..core.errors import InvalidInputError
from .problem import Problem, Simulation, parse_problem, parse_simulation, with_options

__all__ = ["names", "load", "load_simulation", "robot", "text", "files", "command"]

_DESCRIPTIONS = {
    "pike-dive": "Chapter 3: straight -> pike -> 3.5 somersaults -> straight, 5 segments, spline conditions",
    "pike-dive-limited": "the pike dive with phi kept in [-2 pi, -pi] (never folding past flat), free conditions",
    "chapter4": "Chapter 4: nilpotentization from (pi/4, 0, 0) to (pi/4, 2, 1.4 pi), cubic v1, v2 "
                "(acroplan nilpotent)",
    "diver-somersault": "planar body (URDF): a diver with arms turns one somersault in pike with an arm sweep, "
                        "P0 = 36, 4 segments, spline conditions",
    "space-robot-turn": "planar body (link tables): a space robot turns its base 90 deg at zero momentum by arm "
                        "loops, within its joint and rate limits",
    "three-rods-turn": "planar body (link tables): three equal rods at zero momentum turn 0.4 rad by one shape "
                       "loop, |u| <= 2 rad/s",
    "space-robot-arm-loop": "planar body: the turn of the space robot's base under a given arm loop "
                            "(acroplan simulate)",
    "falling-cat": "spatial body (link tables): Kane and Scher's cat turns over, 180 deg about its long axis at "
                   "zero angular momentum in 0.5 s, from a shape back to the same shape, within its joint ranges",
    "platform-dive": "human body (Yeadon's male1, split at the hips): 10 m platform, 3.5 forward somersaults in "
                     "pike, energy-optimal within a diver's hip range and rate (needs pip install \"acroplan[human]\")",
}


def names() -> dict[str, str]:
    """Example names and one-line descriptions."""
    return dict(_DESCRIPTIONS)


def _check(name: str) -> None:
    if name not in _DESCRIPTIONS:
        raise InvalidInputError("example", f"unknown example {name!r}", f"choose one of {sorted(_DESCRIPTIONS)}")


def _folder() -> Path:
    return Path(str(resources.files("acroplan.io").joinpath("data")))


def text(name: str) -> str:
    """The example's TOML source."""
    _check(name)
    return resources.files("acroplan.io").joinpath("data", f"{name}.toml").read_text(encoding="utf-8")


def files(name: str) -> dict[str, str]:
    """The other files the example's problem file names (a URDF, a yeadon measurement file), by file
    name: their text. A bundled yeadon sample named by its name (``yeadon = "male1"``) is no file
    of the example: every installation has it."""
    _check(name)
    data = tomllib.loads(text(name))
    out = {}
    body = data.get("body") if isinstance(data.get("body"), dict) else {}
    for key in ("urdf", "yeadon"):
        fname = body.get(key)
        if isinstance(fname, str) and re.fullmatch(r"[\w.-]+", fname):
            path = resources.files("acroplan.io").joinpath("data", fname)
            if path.is_file():
                out[fname] = path.read_text(encoding="utf-8")
    return out


def command(name: str) -> str:
    """The command that runs the example: ``"plan"``, ``"simulate"`` or ``"nilpotent"``."""
    data = tomllib.loads(text(name))
    return "nilpotent" if "nilpotent" in data else "plan" if "plan" in data else "simulate"


def load(name: str, *, options: dict | None = None) -> Problem:
    """The example as a validated :class:`~acroplan.io.problem.Problem`; ``options`` are written over
    its ``[options]`` table first (``{"objective": "energy"}``: the command line's ``--objective``)."""
    data = with_options(tomllib.loads(text(name)), options)
    if "nilpotent" in data:
        raise InvalidInputError("example", f"{name!r} is a nilpotentization problem",
                                f"use: acroplan nilpotent --example {name}")
    if "plan" not in data and "simulate" in data:
        raise InvalidInputError("example", f"{name!r} is a simulation (a [simulate] table, no [plan])",
                                f"use: acroplan simulate --example {name}")
    return parse_problem(data, name=name, base=_folder())


def load_simulation(name: str) -> Simulation:
    """The example's ``[simulate]`` table as a validated :class:`~acroplan.io.problem.Simulation`."""
    data = tomllib.loads(text(name))
    if "simulate" not in data:
        raise InvalidInputError("example", f"{name!r} has no [simulate] table",
                                f"use: acroplan {command(name)} --example {name}")
    return parse_simulation(data, name=name, base=_folder())


def load_nilpotent(name: str):
    """A nilpotentization example: ``(NilpotentProblem, method)``."""
    from .problem import parse_nilpotent

    return parse_nilpotent(tomllib.loads(text(name)), name=name)


def robot(name: str):
    """The example's system (an ``Acrobot``, a ``PlanarBody`` or a ``SpatialBody``)."""
    if command(name) == "simulate":
        return load_simulation(name).system
    return load(name).robot
