"""The unicycle: a driftless system with two inputs, used to show the planner is general.

.. math::  \\dot x = v\\cos\\psi ,\\quad \\dot y = v\\sin\\psi ,\\quad \\dot\\psi = \\omega .
"""

from __future__ import annotations

import dataclasses

import sympy as sp

from ...core.system import ControlAffineSystem

__all__ = ["Unicycle"]


@dataclasses.dataclass(frozen=True)
class Unicycle(ControlAffineSystem):
    """Unicycle with forward speed ``v`` and turn rate ``omega`` as inputs. No parameters."""

    state_names = ("x", "y", "psi")
    input_names = ("v", "omega")
    param_names = ()
    angle_states = ("psi",)

    @classmethod
    def symbolic_fields(cls, x, p):
        _, _, psi = x
        f = sp.Matrix([0, 0, 0])
        G = sp.Matrix([[sp.cos(psi), 0], [sp.sin(psi), 0], [0, 1]])
        return f, G
