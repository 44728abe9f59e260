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

from __future__ import annotations

from ...core.family import lazy_package

#: The public names and their modules, loaded on first use (PEP 562): the family's descriptor
#: (``family.py``) is imported without the numerics; the first name used also imports what the
#: family registers (its ``setup``: strategies, torque models, ...).
_NAMES = {"Link": "links", "LinkTable": "links", "PlanarBody": "model", "momentum_from_definition": "model",
          "read_link_table": "urdf", "read_urdf": "urdf", "to_urdf": "urdf", "three_rods": "zoo",
          "diver_with_arms": "zoo", "planar_space_robot": "zoo", "random_body": "zoo", "PlanarTorque": "effort",
          "inverse_dynamics": "effort"}

__all__ = list(_NAMES)
__getattr__, __dir__ = lazy_package(__name__, _NAMES)
