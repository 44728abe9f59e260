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

from .links import SpatialLink, SpatialLinkTable
from .model import SpatialBody
from .effort import SpatialTorque, register as _register_torque
from .rotations import attitude_states
from .urdf import read_link_table, read_urdf, to_urdf
from .biomod import read_biomod
from .zoo import astronaut, falling_cat, random_body, twisting_diver

_register_torque()  # SpatialTorque is the torque model of SpatialBody

__all__ = ["SpatialLink", "SpatialLinkTable", "SpatialBody", "SpatialTorque", "attitude_states", "read_link_table", "read_urdf",
           "to_urdf", "read_biomod", "astronaut", "falling_cat", "random_body", "twisting_diver"]
