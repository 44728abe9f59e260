"""A small zoo of spatial bodies, for tests, examples and benchmarks.

* :func:`random_body`: random physical chains (or trees) of 3-D links with revolute joints of random
  axes;
* :func:`random_segment`: a random single-segment problem reachable by construction (the end of a
  simulated random smooth joint motion);
* :func:`falling_cat`, :func:`astronaut`, :func:`diver`: the bodies of the bundled examples
  (:mod:`~acroplan.families.spatial.examples`).

All lengths in metres, masses in kilograms, inertias in kg m^2.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ...core.errors import InvalidInputError
from . import rotations as rot
from .links import SpatialLink
from .model import SpatialBody

__all__ = ["random_body", "random_segment", "SpatialSegment", "box_inertia", "cylinder_inertia"]


def box_inertia(mass: float, a: float, b: float, c: float) -> tuple[float, float, float]:
    """Principal moments of a uniform box of sides ``a, b, c`` (along x, y, z) about its centre:
    :math:`\\tfrac{m}{12}(b^2 + c^2,\\ a^2 + c^2,\\ a^2 + b^2)`."""
    return (mass * (b * b + c * c) / 12.0, mass * (a * a + c * c) / 12.0, mass * (a * a + b * b) / 12.0)


def cylinder_inertia(mass: float, length: float, radius: float, axis: int = 0) -> tuple[float, float, float]:
    """Principal moments of a uniform solid cylinder about its centre, its axis along ``axis``
    (0, 1, 2 for x, y, z): :math:`m r^2/2` about the axis, :math:`m(3r^2 + \\ell^2)/12` across."""
    out = [mass * (3 * radius**2 + length**2) / 12.0] * 3
    out[axis] = mass * radius**2 / 2.0
    return tuple(out)


def random_body(rng, n_links: int, L=(0.0, 0.0, 0.0), *, tree: bool = False) -> SpatialBody:
    """A random physical body of ``n_links`` boxes with revolute joints of random axes.

    Link ``k`` (``link0`` the root, joints ``q1 ... q{n-1}``) is a uniform box of length
    :math:`\\ell_k \\in [0.2, 0.8]` along its :math:`x` axis and cross-section sides in
    :math:`[0.05, 0.2]`, mass :math:`m_k \\in [1, 30]`, its centre of mass at
    :math:`(f\\ell_k, e_1, e_2)` with :math:`f \\in [0.3, 0.7]`, :math:`|e| \\le 0.02`, inertia the
    box's turned by a random small rotation (up to 0.3 rad) of its principal axes; its joint at the
    parent's far end :math:`(\\ell_p, 0, 0)` (chain) or, with ``tree``, at a random point of a random
    earlier link's axis; the joint axis a random unit vector.

    Parameters
    ----------
    rng : numpy.random.Generator or int
    n_links : int
        >= 2.
    L : (float, float, float)
    tree : bool
        Random parents (a branched tree) instead of a chain.

    Returns
    -------
    SpatialBody
    """
    if isinstance(n_links, bool) or not isinstance(n_links, (int, np.integer)) or n_links < 2:
        raise InvalidInputError("n_links", f"must be a whole number >= 2, got {n_links!r}", "give for example 3")
    rng = np.random.default_rng(rng)
    links, lengths = [], []
    for k in range(int(n_links)):
        length = float(rng.uniform(0.2, 0.8))
        b, c = rng.uniform(0.05, 0.2, 2)
        mass = float(rng.uniform(1.0, 30.0))
        P = np.diag(box_inertia(mass, length, b, c))
        Q = rot.to_matrix(rot.exp(rng.normal(size=3) * 0.3 / np.sqrt(3)))
        inertia = Q @ P @ Q.T
        com = (float(rng.uniform(0.3, 0.7)) * length, *(float(v) for v in rng.uniform(-0.02, 0.02, 2)))
        if k == 0:
            links.append(SpatialLink("link0", None, mass, inertia, com=com))
        else:
            parent = int(rng.integers(0, k)) if tree else k - 1
            at = lengths[parent] * (float(rng.uniform(0.2, 1.0)) if tree else 1.0)
            axis = rng.normal(size=3)
            links.append(SpatialLink(f"link{k}", f"link{parent}", mass, inertia, com=com, joint=(at, 0.0, 0.0),
                                     axis=tuple(axis / np.linalg.norm(axis)), joint_name=f"q{k}"))
        lengths.append(length)
    return SpatialBody(links, L=L)


@dataclasses.dataclass(frozen=True)
class SpatialSegment:
    """One random single-segment problem of a spatial body (:func:`random_segment`).

    Attributes
    ----------
    body : SpatialBody
    T : float
    x0, x1 : numpy.ndarray, shape (4 + m,)
        Start and target; ``x1`` is where ``coefficients`` take ``x0`` in time ``T``.
    coefficients : numpy.ndarray, shape (m, 6)
        The joint rates that reach ``x1`` (Legendre basis on ``s = t / T``): the proof of
        reachability.
    """

    body: SpatialBody
    T: float
    x0: np.ndarray
    x1: np.ndarray
    coefficients: np.ndarray

    def plan_kwargs(self) -> dict:
        """Keywords of :func:`acroplan.plan` for this problem (no limits)."""
        from ...core.limits import Limits

        names = self.body.state_names
        kw = {name: [float(a), float(b)] for name, a, b in zip(names, self.x0, self.x1)}
        return dict(times=[0.0, self.T], limits=Limits(), **kw)


def random_segment(rng, n_links: int = 3, *, momentum: bool = False, tree: bool = False) -> SpatialSegment:
    """A random single segment of a random body (:func:`random_body`), reachable by construction.

    The body: :func:`random_body` with :math:`L = 0`, or (``momentum``) :math:`L = R(q_0)\\,
    \\mathbb{I}(s_0)\\,\\omega_0` with :math:`\\omega_0` a random direction of size in :math:`[0.3, 2]`
    rad/s (the drift at the start). The motion: :math:`T \\in [1, 3]` s, a random attitude
    :math:`q_0`, joints :math:`s_0 \\in [-1.5, 1.5]`, joint rates a random smooth polynomial (6
    Legendre coefficients, standard deviations 1, 1, 0.6, 0.3 rad/s for the first four); the target
    is the end of the simulated motion (compiled integrator).

    Returns
    -------
    SpatialSegment
    """
    from ...core import backend
    from ...core.basis import Legendre

    rng = np.random.default_rng(rng)
    body = random_body(rng, n_links, tree=tree)
    m = body.n_inputs
    s0 = rng.uniform(-1.5, 1.5, m)
    q0 = rot.normalize(rng.normal(size=4))
    if momentum:
        w = rng.normal(size=3)
        w *= rng.uniform(0.3, 2.0) / np.linalg.norm(w)
        L = rot.to_matrix(q0) @ body.locked_inertia(s0) @ w
        body = SpatialBody(body.links, L=tuple(L))
    T = float(rng.uniform(1.0, 3.0))
    c = np.zeros((m, 6))
    c[:, :4] = rng.normal(scale=[1.0, 1.0, 0.6, 0.3], size=(m, 4))
    x0 = np.concatenate([q0, s0])
    x1, _ = backend.endpoint(body, Legendre(6), x0, T, c)
    x1 = np.asarray(x1, dtype=float)
    x1[:4] /= np.linalg.norm(x1[:4])
    return SpatialSegment(body, T, x0, x1, c)
