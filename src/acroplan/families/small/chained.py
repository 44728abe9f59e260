"""The chained form with two inputs, the normal form of many nonholonomic systems (Murray & Sastry,
1993): a car with ``n - 2`` trailers converts to it.

.. math::  \\dot x_1 = u_1,\\quad \\dot x_2 = u_2,\\quad \\dot x_{i} = x_{i-1}\\, u_1 \\ (i = 3, \\dots, n).

The number of states is a property of the instance, so this one class describes chains of any
length: its :attr:`structure_key` carries ``n``, and each length is compiled once.
"""

from __future__ import annotations

import dataclasses

import sympy as sp

from ...core.errors import InvalidInputError
from ...core.system import ControlAffineSystem

__all__ = ["ChainedForm"]


@dataclasses.dataclass(frozen=True)
class ChainedForm(ControlAffineSystem):
    """The two-input chained form with ``n >= 3`` states ``x1 ... xn`` and inputs ``u1``, ``u2``
    (both rates: ``u1 = dx1/dt``, ``u2 = dx2/dt``). No parameters."""

    n: int = 3

    input_names = ("u1", "u2")
    param_names = ()

    def __post_init__(self):
        if isinstance(self.n, bool) or not isinstance(self.n, int) or self.n < 3:
            raise InvalidInputError("n", f"must be a whole number >= 3, got {self.n!r}", "give for example 4")

    @property
    def state_names(self):
        return tuple(f"x{i}" for i in range(1, self.n + 1))

    @property
    def rate_inputs(self):
        return {"u1": "x1", "u2": "x2"}

    @property
    def structure_key(self):
        return ("ChainedForm", self.n)

    def to_dict(self):
        return {**super().to_dict(), "n": self.n}

    @classmethod
    def from_dict(cls, data):
        return cls(n=int(data["n"]))

    def symbolic_fields(self, x, p):
        f = sp.zeros(self.n, 1)
        G = sp.zeros(self.n, 2)
        G[0, 0] = 1
        G[1, 1] = 1
        for i in range(2, self.n):
            G[i, 0] = x[i - 1]
        return f, G
