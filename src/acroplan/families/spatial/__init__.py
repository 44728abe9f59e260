"""Free-floating bodies in 3-D: a tree of rigid links and revolute joints of any axes.

* :mod:`~.links`: :class:`SpatialLink`, :class:`SpatialLinkTable`, the conventions;
* :mod:`~.rotations`: quaternions, rotation vectors, Euler angles (Yeadon's somersault, tilt,
  twist), :func:`~.rotations.attitude_states` (waypoint keywords from attitudes in any form);
* :mod:`~.model`: :class:`SpatialBody`, the momentum map and the state equation on SO(3) x R^m;
* :mod:`~.urdf`: :func:`read_urdf`, :func:`read_link_table` (through Pinocchio), :func:`to_urdf`;
* :mod:`~.biomod`: :func:`read_biomod` (.bioMod files of biorbd and bioptim, read by biorbd:
  ``pip install acroplan[biomod]``);
* :mod:`~.pin`, :mod:`~.check`: the Pinocchio model, and the independent check of every plan
  (Pinocchio is optional: ``pip install acroplan[bodies]``);
* :mod:`~.guess`, :mod:`~.strategy`: shape loops from the curvature of the momentum connection,
  :class:`~.strategy.SpatialAuto` (``method="auto"``);
* :mod:`~.zoo`: :func:`falling_cat`, :func:`astronaut`, :func:`twisting_diver`, :func:`random_body`;
* :mod:`~.examples`: the falling cat, the astronaut, a twisting somersault;
* :mod:`~.drawing`: 3-D animation, strobe figure, Euler angles over time;
* :mod:`~.effort`: joint torques by Pinocchio's inverse dynamics of the free body
  (:class:`~.effort.SpatialTorque`, registered as the torque model of :class:`SpatialBody`).
"""

from __future__ import annotations

from ...core.family import lazy_package

#: The public names and their modules, loaded on first use (PEP 562): the family's descriptor
#: (``family.py``) is imported without the numerics; the first name used also imports what the
#: family registers (its ``setup``: strategies, torque models, ...).
_NAMES = {"SpatialLink": "links", "SpatialLinkTable": "links", "SpatialBody": "model", "SpatialTorque": "effort",
          "attitude_states": "rotations", "read_link_table": "urdf", "read_urdf": "urdf", "to_urdf": "urdf",
          "read_biomod": "biomod", "astronaut": "zoo", "falling_cat": "zoo", "random_body": "zoo",
          "twisting_diver": "zoo"}

__all__ = list(_NAMES)
__getattr__, __dir__ = lazy_package(__name__, _NAMES)
