"""Human bodies' registration as a family (:mod:`acroplan.core.family`): the ``[body]`` table of
a human body (Yeadon's measurements or de Leva's tables), the bundled platform dive. A human body is
an :class:`~acroplan.Acrobot` or a :class:`~acroplan.PlanarBody` once built, so its plans,
reachable sets and drawings are those families'."""

from __future__ import annotations

from ...core.family import Example, Family
from . import problem

__all__ = ["FAMILY"]

FAMILY = Family(
    name="human",
    system_types=(),
    priority=20,
    tables=("body",),
    reads=problem.reads,
    read=problem.read,
    table_keys=problem.HUMAN_KEYS,
    examples={
        "platform-dive": Example(__package__, "data/platform-dive.toml", "human body (Yeadon's male1, split at the "
                                 "hips): 10 m platform, 3.5 forward somersaults in pike, energy-optimal within a "
                                 "diver's hip range and rate", extra="human"),
    },
)
