"""The small kinematic systems' registration as a family (:mod:`acroplan.core.family`): the
smallest worked example of the contract, a name and the classes; they have no problem-file table,
examples or drawings (plan them from Python)."""

from __future__ import annotations

from ...core.family import Family
from .chained import ChainedForm
from .unicycle import Unicycle

__all__ = ["FAMILY"]

FAMILY = Family(name="small", system_types=(Unicycle, ChainedForm))
