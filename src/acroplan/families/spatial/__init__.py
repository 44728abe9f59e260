"""Free-floating bodies in 3-D: a tree of rigid links and revolute joints of any axes.

* :mod:`~.links`: :class:`SpatialLink`, :class:`SpatialLinkTable`, the conventions;
* :mod:`~.rotations`: quaternions, rotation vectors, Euler angles (Yeadon's somersault, tilt,
  twist);
* :mod:`~.model`: :class:`SpatialBody`, the momentum map and the state equation on SO(3) x R^m.
"""

from .links import SpatialLink, SpatialLinkTable
from .model import SpatialBody

__all__ = ["SpatialLink", "SpatialLinkTable", "SpatialBody"]
