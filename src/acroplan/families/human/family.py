"""Human bodies' registration as a family (:mod:`acroplan.core.family`): the ``[body]`` table of
a human body (Yeadon's measurements or de Leva's tables), the bundled platform dive and the 3-D twisting dives (``dives.py``). A human body is
an :class:`~acroplan.Acrobot` or a :class:`~acroplan.PlanarBody` once built, so its plans,
reachable sets and drawings are those families'."""

from __future__ import annotations

from ...core.family import Example, Family, hook

__all__ = ["FAMILY", "HUMAN_KEYS", "reads"]

#: the keys of a human body in [body]
HUMAN_KEYS = ("yeadon", "height", "mass", "sex", "split", "position", "knee_flexion", "shoulder_flexion", "model",
              "joints", "posture")


def reads(table: str, data) -> bool:
    """A ``[body]`` with any of :data:`HUMAN_KEYS` (here, not in ``problem.py``: asking must not
    import the human reader, whose planar model imports sympy, for every other family's body)."""
    return table == "body" and isinstance(data, dict) and any(k in data for k in HUMAN_KEYS)


FAMILY = Family(
    name="human",
    system_types=(),
    priority=20,
    tables=("body",),
    reads=reads,
    read=hook(f"{__package__}.problem:read"),
    table_keys=HUMAN_KEYS,
    examples={
        "platform-dive": Example(__package__, "data/platform-dive.toml", "human body (Yeadon's male1, split at the "
                                 "hips): 10 m platform, 3.5 forward somersaults in pike, energy-optimal within a "
                                 "diver's hip range and rate", extra="human"),
        "back-full-twist": Example(__package__, "data/back-full-twist.toml", "3-D human (Yeadon's male1, moving "
                                   "shoulders): trampoline, a back straight somersault with one twist in 1.5 s, the "
                                   "twist made in the air by the arms", extra="human"),
        "forward-double-twist": Example(__package__, "data/forward-double-twist.toml", "3-D human (Yeadon's male1, "
                                        "moving shoulders): 3 m springboard, a forward 1 1/2 somersault with two "
                                        "twists in 1.4 s, the twist made in the air by the arms", extra="human"),
        "back-double-full-out": Example(__package__, "data/back-double-full-out.toml", "3-D human (Yeadon's male1, "
                                        "moving shoulders): trampoline, a back double somersault with one twist in "
                                        "the second somersault in 2.0 s", extra="human"),
    },
)
