"""Free-flying planar bodies with any number of links (chains and branched trees).

* :mod:`~.links`: :class:`Link`, :class:`LinkTable`, the conventions (with a figure);
* :mod:`~.model`: :class:`PlanarBody`, the momentum map (text eq. 1) and the state equation;
* :mod:`~.urdf`: :func:`read_urdf`, :func:`read_link_table` (through Pinocchio), :func:`to_urdf`;
* :mod:`~.pin`: the Pinocchio model of a link table (Pinocchio is optional: ``pip install
  acroplan[bodies]``; it is imported only when one of these is called);
* :mod:`~.check`: the independent check by Pinocchio (centroidal momentum, forward simulation);
* :mod:`~.effort`: the joint torques of a motion, by Pinocchio's inverse dynamics of the free body
  (:class:`PlanarTorque`, :func:`inverse_dynamics`) and the optimal strategies' starts
  (:func:`~.effort.optimal_starts`, registered here);
* :mod:`~.zoo`: :func:`three_rods`, :func:`diver_with_arms`, :func:`planar_space_robot`,
  :func:`random_body`.
"""

from ...core.optimal import register_starts
from .effort import PlanarTorque, inverse_dynamics, optimal_starts
from .links import Link, LinkTable
from .model import PlanarBody, momentum_from_definition
from .urdf import read_link_table, read_urdf, to_urdf
from .zoo import diver_with_arms, planar_space_robot, random_body, three_rods

register_starts(PlanarBody, optimal_starts)  # the optimal strategies' starts (effort.optimal_starts)

__all__ = ["Link", "LinkTable", "PlanarBody", "momentum_from_definition", "read_link_table", "read_urdf", "to_urdf",
           "three_rods", "diver_with_arms", "planar_space_robot", "random_body", "PlanarTorque", "inverse_dynamics"]
