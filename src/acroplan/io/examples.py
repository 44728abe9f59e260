"""Bundled example problems (the model zoo's problems), shared by the CLI, tests and docs.

Each family bundles its own (:attr:`acroplan.core.family.Family.examples`): a problem file in the
family's ``data/`` folder (``acroplan examples --show NAME`` prints it), and the files it names
beside it (the diver's URDF), which :func:`files` lists and ``acroplan init --example NAME`` copies
too. :func:`command` says which command runs an example (``plan``, ``simulate`` or ``nilpotent``).

:func:`names` lists them with one line each: the text's two-link body (``pike-dive``,
``pike-dive-limited``, ``chapter4``), planar bodies (``diver-somersault``, ``space-robot-turn``,
``three-rods-turn``, ``space-robot-arm-loop``), a spatial body (``falling-cat``) and a human body,
``platform-dive``: the 10 m platform dive, 3.5 forward somersaults in pike, of Yeadon's bundled
``male1`` split at the hips, energy-optimal within a diver's hip range and rate (the problem of
:func:`acroplan.families.human.examples.platform_dive_pike`; needs ``pip install
"acroplan[human]"``), and three twisting dives of the 3-D human (``back-full-twist``,
``forward-double-twist``, ``back-double-full-out``: :mod:`acroplan.families.human.dives`)::

    acroplan plan --example platform-dive --out platform-dive-out --animate
    acroplan plan --example back-full-twist --out back-full-out
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

from typing import TYPE_CHECKING

from ..core.errors import InvalidInputError
from ..core.family import Example, families

if TYPE_CHECKING:  # the problem readers import the families' numerics: imported where an example is read
    from .problem import Problem, Simulation

__all__ = ["names", "load", "load_simulation", "robot", "text", "files", "command", "example"]


def _all() -> dict[str, Example]:
    out = {}
    for fam in families():
        out.update(fam.examples)
    return out


def names() -> dict[str, str]:
    """Example names and one-line descriptions (with the extra an example needs, if any)."""
    return {name: ex.description + (f" (needs pip install \"acroplan[{ex.extra}]\")" if ex.extra else "")
            for name, ex in _all().items()}


def example(name: str) -> Example:
    """The bundled example ``name``."""
    found = _all()
    if name not in found:
        raise InvalidInputError("example", f"unknown example {name!r}", f"choose one of {sorted(found)}")
    return found[name]


def _resource(ex: Example, relative: str):
    return resources.files(ex.package).joinpath(*relative.split("/"))


def _folder(name: str) -> Path:
    ex = example(name)
    return Path(str(_resource(ex, ex.resource))).parent


def text(name: str) -> str:
    """The example's TOML source."""
    ex = example(name)
    return _resource(ex, ex.resource).read_text(encoding="utf-8")


def files(name: str) -> dict[str, str]:
    """The other files the example's problem file names (a URDF), by file name: their text. A
    bundled yeadon sample named by its name (``yeadon = "male1"``) is no file of the example: every
    installation has it."""
    ex = example(name)
    return {rel.rsplit("/", 1)[-1]: _resource(ex, rel).read_text(encoding="utf-8") for rel in ex.companions}


def command(name: str) -> str:
    """The command that runs the example: ``"plan"``, ``"simulate"`` or ``"nilpotent"``."""
    return example(name).command


def load(name: str, *, options: dict | None = None) -> Problem:
    """The example as a validated :class:`~acroplan.io.problem.Problem`; ``options`` are written over
    its ``[options]`` table first (``{"objective": "energy"}``: the command line's ``--objective``)."""
    from .problem import parse_problem, with_options

    data = with_options(tomllib.loads(text(name)), options)
    if command(name) == "nilpotent":
        raise InvalidInputError("example", f"{name!r} is a nilpotentization problem",
                                f"use: acroplan nilpotent --example {name}")
    if "plan" not in data and "simulate" in data:
        raise InvalidInputError("example", f"{name!r} is a simulation (a [simulate] table, no [plan])",
                                f"use: acroplan simulate --example {name}")
    return parse_problem(data, name=name, base=_folder(name))


def load_simulation(name: str) -> Simulation:
    """The example's ``[simulate]`` table as a validated :class:`~acroplan.io.problem.Simulation`."""
    from .problem import parse_simulation

    data = tomllib.loads(text(name))
    if "simulate" not in data:
        raise InvalidInputError("example", f"{name!r} has no [simulate] table",
                                f"use: acroplan {command(name)} --example {name}")
    return parse_simulation(data, name=name, base=_folder(name))


def robot(name: str):
    """The example's system (an ``Acrobot``, a ``PlanarBody``, a ``SpatialBody``, ...)."""
    if command(name) == "simulate":
        return load_simulation(name).system
    return load(name).robot
