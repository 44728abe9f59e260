"""The free-flying two-link acrobot (the dissertation's body).

* :mod:`~.model`: :class:`Acrobot`, :class:`PhysicalParameters`;
* :mod:`~.reach`: exact reachable sets with joint and rate limits; :mod:`~.interval`: the
  reachable interval of theta(T) (:func:`reachable_interval`);
* :mod:`~.flat`: the flat output: guesses, the three-piece planner, the strategies ``"flat"`` and
  the acrobot's ``"auto"`` (registered on import);
* :mod:`~.effort`: the joint torque (registered as the physical robot's torque model), the starts
  of the optimal strategies (registered on import);
* :mod:`~.momentum`: the least angular momentum for a turn; :mod:`~.sweeping`: what the acrobot
  offers sweeps (the derived quantities ``least_P0``, ``most_P0``, the ``plan.reach`` interval, the
  factory ``"Acrobot.from_physical"``; registered on import);
* :mod:`~.nilpotent`: Chapter 4's nilpotentization;
* :mod:`~.verify`: exact checks with no ODE integrator;
* :mod:`~.zoo`: random bodies and problems for tests and benchmarks;
* :mod:`~.plots`, :mod:`~.drawing`: its figures and animation.
"""

from . import effort  # noqa: F401  (registers the torque model and the optimal strategies' starts)
from . import flat  # noqa: F401  (registers the "flat" strategy)
from . import sweeping  # noqa: F401  (registers least_P0, most_P0, plan.reach and a factory for sweeps)
from .interval import reachable_interval
from .model import Acrobot, PhysicalParameters
from .reach import Reach, reachable_set

__all__ = ["Acrobot", "PhysicalParameters", "Reach", "reachable_set", "reachable_interval"]
