"""The small kinematic systems' registration as a family (:mod:`acroplan.core.family`): the
smallest worked example of the contract, a name and the classes; they have no problem-file table,
examples or drawings (plan them from Python)."""

from __future__ import annotations

from ...core.family import Family

__all__ = ["FAMILY"]

# the classes by name ("module:Class"): the descriptor imports nothing (core.family.Family)
FAMILY = Family(name="small", system_types=(f"{__package__}.unicycle:Unicycle", f"{__package__}.chained:ChainedForm"))
