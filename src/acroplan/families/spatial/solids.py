"""The solids a spatial body is drawn with, as triangle meshes in each link's frame: what the GIF,
the strobe and the browser view (:mod:`~acroplan.families.spatial.view`) all draw.

A link that carries its own shapes (:attr:`SpatialLink.shapes
<acroplan.families.spatial.links.SpatialLink.shapes>`: the 3-D human's Yeadon solids, stadia and
semi-ellipsoids) is drawn with them; any other link with mass as its **equivalent box**, the
uniform box with the link's mass and principal moments, :math:`a_i = \\sqrt{6 (I_j + I_k - I_i)/m}`,
centred at its centre of mass along its principal axes. Massless links (the inner links of joints
of several axes) are not drawn.

Shapes (each ``(kind, params, origin, rotation)``, placed in the link's frame at ``origin`` turned
by ``rotation``; the solid's own x is its stadia's long axis, its z its height):

* ``("stadium_solid", (r0, t0, r1, t1, height), ...)``: Yeadon's stadium solid, the loft from a
  stadium (radius ``r0``, half straight length ``t0``) at its base to another (``r1``, ``t1``) at
  ``height`` along its z;
* ``("semiellipsoid", (r, t, height), ...)``: Yeadon's semi-ellipsoid (the top of the head), a
  dome of ``height`` on a stadium (``r``, ``t``) base.
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["Solid", "solids_of", "posed", "equivalent_boxes", "stadium_solid", "semiellipsoid", "box", "COLORS"]

#: Link colours (a muted palette; the red, green and blue of the root's axes are not among them).
COLORS = ["#4c72b0", "#dd8452", "#8172b3", "#937860", "#da8bc3", "#8c8c8c", "#ccb974", "#64b5cd"]
#: Points around a stadium's outline.
OUTLINE = 20


@dataclasses.dataclass(frozen=True)
class Solid:
    """One solid of a body: ``vertices`` (V, 3) in its link's frame, ``faces`` (F, 3) vertex indices
    (triangles, outward), its link's index, colour and name."""

    link: int
    vertices: np.ndarray
    faces: np.ndarray
    color: str
    name: str


def equivalent_boxes(body):
    """Per link with mass: the equivalent box's half sides and principal axes (module docstring).

    Returns
    -------
    list of (link index, half sides (3,), axes (3, 3) in the link frame, columns)
    """
    out = []
    for i, link in enumerate(body.links):
        if link.mass <= 0:
            continue
        ev, V = np.linalg.eigh(link.inertia_matrix)
        s = ev.sum()
        sides = np.sqrt(np.maximum(6.0 * (s - 2.0 * ev) / link.mass, 0.0))
        sides = np.maximum(sides, 0.02 * max(sides.max(), 1e-3))
        out.append((i, sides / 2.0, V))
    return out


_BOX_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                       [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)


def box(center, axes, half) -> tuple[np.ndarray, np.ndarray]:
    """A box's mesh: ``(vertices (8, 3), faces (12, 3))``, centred at ``center`` with the columns of
    ``axes`` along its sides and half sides ``half``."""
    V = np.asarray(center, dtype=float) + (_CORNERS * np.asarray(half, dtype=float)) @ np.asarray(axes).T
    return V, _outward(V, _BOX_FACES.copy())


def _outward(V, F):
    """``F`` with every triangle turned to face away from the mesh's centroid."""
    c = V.mean(axis=0)
    a, b, d = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    n = np.cross(b - a, d - a)
    flip = np.einsum("ij,ij->i", n, (a + b + d) / 3 - c) < 0
    F[flip] = F[flip][:, [0, 2, 1]]
    return F


def _stadium(r: float, t: float, n: int = OUTLINE) -> np.ndarray:
    """A stadium's outline, ``n`` points counter-clockwise in its plane: two half circles of radius
    ``r`` centred at ``x = +-t``, joined by straight sides."""
    half = n // 2
    a = np.linspace(-np.pi / 2, np.pi / 2, half)
    right = np.column_stack([t + r * np.cos(a), r * np.sin(a)])
    left = np.column_stack([-t - r * np.cos(a), -r * np.sin(a)])
    return np.vstack([right, left])


def _loft(rings: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """A closed mesh through rings of equal size (each (n, 3)), capped at both ends."""
    n = rings[0].shape[0]
    V = np.vstack(rings + [rings[0].mean(axis=0, keepdims=True), rings[-1].mean(axis=0, keepdims=True)])
    F = []
    for k in range(len(rings) - 1):
        a, b = k * n, (k + 1) * n
        for i in range(n):
            j = (i + 1) % n
            F += [[a + i, a + j, b + j], [a + i, b + j, b + i]]
    bottom, top = len(rings) * n, len(rings) * n + 1
    last = (len(rings) - 1) * n
    for i in range(n):
        j = (i + 1) % n
        F += [[bottom, j, i], [top, last + i, last + j]]
    return V, _outward(V, np.array(F))


def _posed(V, pose):
    origin, R = pose
    return np.asarray(V) @ np.asarray(R, dtype=float).T + np.asarray(origin, dtype=float)


def stadium_solid(r0, t0, r1, t1, height, pose=((0.0, 0.0, 0.0), np.eye(3))) -> tuple[np.ndarray, np.ndarray]:
    """Yeadon's stadium solid's mesh (module docstring), in the frame ``pose`` is given in."""
    rings = [np.column_stack([_stadium(r0, t0), np.zeros(OUTLINE)]),
             np.column_stack([_stadium(r1, t1), np.full(OUTLINE, float(height))])]
    V, F = _loft(rings)
    return _posed(V, pose), F


def semiellipsoid(r, t, height, pose=((0.0, 0.0, 0.0), np.eye(3)), levels: int = 5) -> tuple[np.ndarray, np.ndarray]:
    """Yeadon's semi-ellipsoid's mesh (a dome of ``height`` on a stadium (``r``, ``t``) base)."""
    rings = []
    for k in range(levels):
        a = 0.5 * np.pi * k / levels
        s = np.cos(a)
        rings.append(np.column_stack([_stadium(r * s, t * s), np.full(OUTLINE, float(height) * np.sin(a))]))
    rings.append(np.column_stack([_stadium(1e-3 * r, 1e-3 * t), np.full(OUTLINE, float(height))]))
    V, F = _loft(rings)
    return _posed(V, pose), F


def _shape_mesh(shape) -> tuple[np.ndarray, np.ndarray]:
    kind, params, origin, rotation = shape
    pose = (np.asarray(origin, dtype=float), np.asarray(rotation, dtype=float))
    if kind == "stadium_solid":
        return stadium_solid(*params, pose)
    if kind == "semiellipsoid":
        return semiellipsoid(*params, pose)
    raise ValueError(f"unknown shape kind {kind!r}")


def solids_of(body) -> list[Solid]:
    """The solids ``body`` is drawn with (module docstring), in link frames."""
    out = []
    boxes = {i: (half, V) for i, half, V in equivalent_boxes(body)}
    colour = {i: COLORS[k % len(COLORS)] for k, i in enumerate(sorted(boxes))}
    for i, link in enumerate(body.links):
        shapes = getattr(link, "shapes", None) or ()
        if shapes:
            for k, shape in enumerate(shapes):
                V, F = _shape_mesh(shape)
                out.append(Solid(i, V, F, colour.get(i, COLORS[i % len(COLORS)]), f"{link.name}[{k}]"))
        elif i in boxes:
            half, axes = boxes[i]
            V, F = box(np.asarray(link.com, dtype=float), axes, half)
            out.append(Solid(i, V, F, colour[i], link.name))
    return out


def posed(body, state, solids) -> list[np.ndarray]:
    """Each solid's vertices in the centre-of-mass frame at ``state`` (one (V, 3) array each).

    ``body.link_poses`` gives each link frame's orientation and origin; a link's vertices are
    turned by its orientation about its frame's origin (the joint)."""
    Rs, org, _ = body.link_poses(state)
    return [s.vertices @ Rs[s.link].T + org[s.link] for s in solids]


def shade(color, vertices, faces, light=(0.4, -0.5, 0.77)) -> np.ndarray:
    """Lambert shading of each triangle: RGB rows in [0, 1], ``0.35 + 0.65 max(0, n . l)``."""
    from matplotlib.colors import to_rgb

    ell = np.asarray(light, dtype=float) / np.linalg.norm(light)
    a, b, c = vertices[faces[:, 0]], vertices[faces[:, 1]], vertices[faces[:, 2]]
    n = np.cross(b - a, c - a)
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    k = 0.35 + 0.65 * np.maximum(0.0, n @ ell)
    return np.clip(np.outer(k, to_rgb(color)), 0.0, 1.0)
