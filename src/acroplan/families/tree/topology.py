"""The tree of links that planar and spatial bodies share: its topology, not its physics.

:class:`LinkTree` is the part of a link table that knows only the tree: names, parents, the joints'
order, children, paths, subtrees, and the depth-first order Pinocchio needs. The families' tables
(:class:`~acroplan.families.planar.links.LinkTable`,
:class:`~acroplan.families.spatial.links.SpatialLinkTable`) validate their own links and set
``links`` and ``_derived`` (``root``, ``parents``, ``joints``, ``joint_names``); the rest is here.
"""

from __future__ import annotations

from typing import Any

from ...core.errors import InvalidInputError

__all__ = ["LinkTree", "tree_of", "relations"]


class LinkTree:
    """The topology of a checked link table (module docstring)."""

    __slots__ = ()

    def __len__(self) -> int:
        return len(self.links)

    def __iter__(self):
        return iter(self.links)

    def __getitem__(self, i):
        return self.links[i]

    @property
    def root(self) -> int:
        return self._derived["root"]

    @property
    def parents(self) -> tuple[int, ...]:
        return self._derived["parents"]

    @property
    def joints(self) -> tuple[int, ...]:
        return self._derived["joints"]

    @property
    def joint_names(self) -> tuple[str, ...]:
        return self._derived["joint_names"]

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(link.name for link in self.links)

    def index(self, name: str) -> int:
        """Index of the link called ``name``."""
        return self.names.index(name)

    def children(self, i: int) -> tuple[int, ...]:
        """Indices of link ``i``'s children, in table order."""
        return tuple(k for k, p in enumerate(self.parents) if p == i)

    def path(self, i: int) -> tuple[int, ...]:
        """The non-root links from the root down to link ``i`` (``i`` included unless it is the
        root): their joints are the joints whose angles add up to link ``i``'s angle."""
        out = []
        while self.parents[i] != -1:
            out.append(i)
            i = self.parents[i]
        return tuple(reversed(out))

    def ancestors(self, i: int) -> tuple[int, ...]:
        """Link ``i`` and every link above it, up to the root (``i`` first)."""
        out = [i]
        while self.parents[out[-1]] != -1:
            out.append(self.parents[out[-1]])
        return tuple(out)

    def subtree(self, i: int) -> tuple[int, ...]:
        """Link ``i`` and every link below it, in table order."""
        return tuple(k for k in range(len(self.links)) if i in self.ancestors(k))

    def topological_order(self) -> tuple[int, ...]:
        """Link indices with every parent before its children (root first), depth first: each
        link's subtree is a run of consecutive indices. Pinocchio's algorithms that work on blocks
        of the mass matrix (``crba``, ``computeRNEADerivatives``) need that numbering of the joints;
        a breadth-first one gives them wrong matrices on a branched tree."""
        order, todo = [], [self.root]
        while todo:
            i = todo.pop()
            order.append(i)
            todo.extend(reversed(self.children(i)))
        return tuple(order)

    def joint_index(self, name: str) -> int:
        """Position of joint ``name`` among the joint angles (0-based)."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise InvalidInputError("joint", f"{name!r} is not a joint of this body",
                                    f"joints are {list(self.joint_names)}") from None

    @property
    def total_mass(self) -> float:
        return sum(link.mass for link in self.links)

    def to_dicts(self) -> list[dict[str, Any]]:
        """The table as plain data, one dict per link (its ``to_dict``)."""
        return [link.to_dict() for link in self.links]


def tree_of(links, root_state: str) -> tuple[int, tuple[int, ...]]:
    """The root and the parents of checked links (each with ``name`` and ``parent``), or an
    :class:`InvalidInputError` naming the field: duplicate names, no root or two roots, an unknown
    parent, a link its own parent, a loop of parents.

    Parameters
    ----------
    links : sequence of links
    root_state : str
        What the root's state is, for the message when no root is given ("angle is the state
        theta", "attitude is the state").

    Returns
    -------
    root : int
    parents : tuple of int, -1 for the root
    """
    names = [link.name for link in links]
    for i, name in enumerate(names):
        if name in names[:i]:
            raise InvalidInputError(f"links[{i}].name", f"{name!r} is already the name of links[{names.index(name)}]",
                                    "give every link its own name")
    roots = [i for i, link in enumerate(links) if link.parent is None]
    if not roots:
        raise InvalidInputError("links", "has no root (every link has a parent)",
                                f"give exactly one link parent=None: the root, whose {root_state}")
    if len(roots) > 1:
        raise InvalidInputError(f"links[{roots[1]}].parent", f"is None, but links[{roots[0]}] "
                                f"({names[roots[0]]!r}) is the root already",
                                "give exactly one root; name the parent of every other link")
    index = {name: i for i, name in enumerate(names)}
    parents = []
    for i, link in enumerate(links):
        if link.parent is None:
            parents.append(-1)
            continue
        if link.parent not in index:
            raise InvalidInputError(f"links[{i}].parent", f"{link.parent!r} is not the name of a link",
                                    f"link names are {names}")
        if link.parent == link.name:
            raise InvalidInputError(f"links[{i}].parent", f"link {link.name!r} is its own parent",
                                    "name another link, or None for the root")
        parents.append(index[link.parent])
    for i in range(len(links)):  # every link must lead to the root
        seen, j = [i], parents[i]
        while j != -1:
            if j in seen:
                loop = " -> ".join(names[k] for k in seen[seen.index(j):] + [j])
                raise InvalidInputError(f"links[{i}].parent", f"the parents form a loop ({loop})",
                                        "a body is a tree: every chain of parents must end at the root")
            seen.append(j)
            j = parents[j]
    return roots[0], tuple(parents)


def relations(parents: tuple[int, ...]):
    """The tree of a tuple of parent indices (``-1`` for the root), per link: its children, its
    ancestors (itself first), its path (the non-root links from the root down to it) and its
    subtree (itself first).

    Returns
    -------
    (children, ancestors, path, subtree) : tuple of lists of tuples
    """
    n = len(parents)
    children = [tuple(k for k in range(n) if parents[k] == i) for i in range(n)]
    ancestors = []
    for i in range(n):
        a = [i]
        while parents[a[-1]] != -1:
            a.append(parents[a[-1]])
        ancestors.append(tuple(a))
    path = [tuple(reversed([k for k in ancestors[i] if parents[k] != -1])) for i in range(n)]
    subtree = [tuple(k for k in range(n) if i in ancestors[k]) for i in range(n)]
    return children, ancestors, path, subtree
