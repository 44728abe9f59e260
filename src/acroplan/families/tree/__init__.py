"""The base of every family whose bodies are trees of links joined by revolute joints (planar
and spatial bodies, and the human bodies built on them).

* :mod:`~.topology`: :class:`LinkTree` and :func:`tree_of`, the tree of a link table (names,
  parents, joints, paths, subtrees, the depth-first order Pinocchio needs);
* :mod:`~.problem`: what their problem-file tables share: the ``[[body.link]]`` array, a URDF
  named by ``body.urdf``, the ``[limits]`` written into the link table.
"""

from .topology import LinkTree, tree_of

__all__ = ["LinkTree", "tree_of"]
