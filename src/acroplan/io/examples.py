"""Bundled example problems (the model zoo's problems), shared by the CLI, tests and docs."""

from __future__ import annotations

from importlib import resources

from ..core.errors import InvalidInputError
from .problem import Problem, parse_problem

__all__ = ["names", "load", "robot", "text"]

_DESCRIPTIONS = {
    "pike-dive": "Chapter 3: straight -> pike -> 3.5 somersaults -> straight, 5 segments, spline conditions",
    "pike-dive-limited": "the pike dive with phi kept in [-2 pi, -pi] (never folding past flat), free conditions",
    "chapter4": "Chapter 4: nilpotentization from (pi/4, 0, 0) to (pi/4, 2, 1.4 pi), cubic v1, v2 "
                "(acroplan nilpotent)",
}


def names() -> dict[str, str]:
    """Example names and one-line descriptions."""
    return dict(_DESCRIPTIONS)


def text(name: str) -> str:
    """The example's TOML source."""
    if name not in _DESCRIPTIONS:
        raise InvalidInputError("example", f"unknown example {name!r}", f"choose one of {sorted(_DESCRIPTIONS)}")
    return resources.files("acroplan.io").joinpath("data", f"{name}.toml").read_text(encoding="utf-8")


def load(name: str) -> Problem:
    """The example as a validated :class:`~acroplan.problem.Problem`."""
    import tomllib

    data = tomllib.loads(text(name))
    if "nilpotent" in data:
        raise InvalidInputError("example", f"{name!r} is a nilpotentization problem",
                                f"use: acroplan nilpotent --example {name}")
    return parse_problem(data, name=name)


def load_nilpotent(name: str):
    """A nilpotentization example: ``(NilpotentProblem, method)``."""
    import tomllib

    from .problem import parse_nilpotent

    return parse_nilpotent(tomllib.loads(text(name)), name=name)


def robot(name: str):
    """The example's robot."""
    return load(name).robot
