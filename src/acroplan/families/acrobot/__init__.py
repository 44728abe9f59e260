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

from __future__ import annotations

from ...core.family import lazy_package

#: The public names and their modules, loaded on first use (PEP 562): the family's descriptor
#: (``family.py``) is imported without the numerics; the first name used also imports what the
#: family registers (its ``setup``: strategies, torque models, ...).
_NAMES = {"Acrobot": "model", "PhysicalParameters": "model", "Reach": "reach", "reachable_set": "reach",
          "reachable_interval": "interval"}

__all__ = list(_NAMES)
__getattr__, __dir__ = lazy_package(__name__, _NAMES)
