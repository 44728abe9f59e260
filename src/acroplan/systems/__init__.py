"""The model zoo: control-affine systems shared by the planner, tests, examples and the CLI."""

from .acrobot import Acrobot, PhysicalParameters
from .base import ControlAffineSystem, Infeasibility
from .unicycle import Unicycle

__all__ = ["Acrobot", "ControlAffineSystem", "Infeasibility", "PhysicalParameters", "Unicycle"]
