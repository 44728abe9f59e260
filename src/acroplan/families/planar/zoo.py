"""A small zoo of planar bodies, for tests, examples and benchmarks.

* :func:`three_rods`: three equal rods in a chain (the classic three-link swimmer);
* :func:`diver_with_arms`: a human diver, legs in two links and arms, a branched tree;
* :func:`planar_space_robot`: a spacecraft base with a two-joint arm;
* :func:`random_body`: random physical chains;
* :func:`random_segment`: a random single-segment problem reachable by construction (the end of a
  simulated random smooth joint motion), with or without limits that motion keeps.

All lengths in metres, masses in kilograms, inertias in kg m^2 (any consistent units work).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..tree.segment import TreeSegment, link_count, random_rates
from .links import Link
from .model import PlanarBody

__all__ = ["three_rods", "diver_with_arms", "planar_space_robot", "random_body", "random_segment", "PlanarSegment"]


def three_rods(P0: float = 0.0, *, mass: float = 1.0, length: float = 1.0) -> PlanarBody:
    """Three equal uniform rods in a chain: ``rod1`` (the root), ``rod2``, ``rod3``.

    Each rod's frame has its origin at the rod's first end and its x axis along the rod, so the
    centre of mass is at :math:`(\\ell/2, 0)`, the next joint at :math:`(\\ell, 0)` and the inertia
    :math:`m\\ell^2/12`. The joints are ``q1`` (rod2 relative to rod1) and ``q2`` (rod3 relative to
    rod2); :math:`q = 0` is straight. The body is symmetric under reversing the chain (shape
    :math:`(q_1, q_2) \\mapsto (-q_2, -q_1)`) and under the mirror in its axis
    (:math:`q \\mapsto -q`, :math:`\\theta \\mapsto -\\theta`).

    Parameters
    ----------
    P0 : float
        Angular momentum.
    mass, length : float
        Of each rod.

    Returns
    -------
    PlanarBody
    """
    rod = dict(mass=mass, inertia=mass * length**2 / 12.0, com=(length / 2.0, 0.0))
    return PlanarBody([
        Link("rod1", None, **rod),
        Link("rod2", "rod1", **rod, joint=(length, 0.0), joint_name="q1"),
        Link("rod3", "rod2", **rod, joint=(length, 0.0), joint_name="q2"),
    ], P0=P0)


def diver_with_arms(P0: float = 0.0) -> PlanarBody:
    """A diver in the sagittal plane: trunk (with head), thighs, shanks (with feet), arms.

    Both legs move together and both arms move together (one link each), from de Leva's (1996)
    segment proportions for a 75 kg adult. A branched tree: the trunk (root, frame at the hip, x
    axis towards the shoulders) carries the thighs at the hip (joint ``hip``) and the arms at the
    shoulder (joint ``shoulder``); the shanks hang on the thighs at the knee (joint ``knee``).

    Angles (every link's x axis runs from its joint along the segment):

    * ``hip``: :math:`\\pi` straight, smaller values pike (legs to the front, the trunk's +y side);
    * ``knee``: 0 straight, positive flexed;
    * ``shoulder``: 0 arms overhead, :math:`\\pi/2` arms forward, :math:`\\pi` arms at the sides.

    Joint limits and rate limits are in the table (:meth:`PlanarBody.joint_limits`).

    Returns
    -------
    PlanarBody
    """
    return PlanarBody([
        Link("trunk", None, 40.5, 1.9, com=(0.30, 0.0)),
        Link("thighs", "trunk", 19.8, 0.35, com=(0.17, 0.0), joint=(0.0, 0.0), joint_name="hip",
             lower=0.35, upper=3.5, velocity=12.0),
        Link("shanks", "thighs", 8.0, 0.20, com=(0.25, 0.0), joint=(0.42, 0.0), joint_name="knee",
             lower=0.0, upper=2.4, velocity=14.0),
        Link("arms", "trunk", 6.9, 0.25, com=(0.30, 0.0), joint=(0.52, 0.0), joint_name="shoulder",
             lower=-0.6, upper=3.4, velocity=15.0),
    ], P0=P0)


def planar_space_robot(P0: float = 0.0) -> PlanarBody:
    """A free-floating spacecraft (150 kg, 1.5 m wide) with a two-link arm (1.2 m and 1.0 m).

    The base is the root (frame at its centre); the arm's shoulder is on the base's edge at
    :math:`(0.6, 0)` (joint ``shoulder``), the elbow at the end of the upper arm (joint ``elbow``);
    both joints :math:`|q| \\le 2.6`/:math:`2.8` rad at :math:`|\\dot q| \\le 0.5` rad/s.

    Returns
    -------
    PlanarBody
    """
    return PlanarBody([
        Link("base", None, 150.0, 25.0, com=(0.0, 0.0)),
        Link("upper_arm", "base", 12.0, 12.0 * 1.2**2 / 12.0, com=(0.6, 0.0), joint=(0.6, 0.0), joint_name="shoulder",
             lower=-2.6, upper=2.6, velocity=0.5),
        Link("forearm", "upper_arm", 8.0, 8.0 * 1.0**2 / 12.0, com=(0.5, 0.0), joint=(1.2, 0.0), joint_name="elbow",
             lower=-2.8, upper=2.8, velocity=0.5),
    ], P0=P0)


def random_body(rng, n_links: int, P0: float = 0.0) -> PlanarBody:
    """A random physical chain of ``n_links`` links.

    Link ``k`` (``link0`` the root, joints ``q1 ... q{n-1}``) has length :math:`\\ell_k \\in
    [0.2, 0.8]`, mass :math:`m_k \\in [1, 30]`, centre of mass at :math:`(f \\ell_k, e \\ell_k)`
    with :math:`f \\in [0.3, 0.7]`, :math:`e \\in [-0.05, 0.05]` (slightly off the axis), inertia a
    rod's :math:`m_k \\ell_k^2/12` times a factor in :math:`[0.8, 1.25]`; the next joint sits at
    :math:`(\\ell_k, 0)`.

    Parameters
    ----------
    rng : numpy.random.Generator or int
    n_links : int
        >= 2.
    P0 : float

    Returns
    -------
    PlanarBody
    """
    n_links = link_count(n_links)
    rng = np.random.default_rng(rng)
    links, prev_len = [], None
    for k in range(n_links):
        length = float(rng.uniform(0.2, 0.8))
        mass = float(rng.uniform(1.0, 30.0))
        com = (float(rng.uniform(0.3, 0.7)) * length, float(rng.uniform(-0.05, 0.05)) * length)
        inertia = mass * length**2 / 12.0 * float(rng.uniform(0.8, 1.25))
        if k == 0:
            links.append(Link("link0", None, mass, inertia, com=com))
        else:
            links.append(Link(f"link{k}", f"link{k - 1}", mass, inertia, com=com, joint=(prev_len, 0.0),
                              joint_name=f"q{k}"))
        prev_len = length
    return PlanarBody(links, P0=P0)


@dataclasses.dataclass(frozen=True)
class PlanarSegment(TreeSegment):
    """One random single-segment problem of a planar body (:func:`random_segment`): a
    :class:`~acroplan.families.tree.segment.TreeSegment` (its attributes and
    :meth:`~acroplan.families.tree.segment.TreeSegment.plan_kwargs`) whose ``body`` is a
    :class:`PlanarBody` and ``x0``, ``x1`` its states :math:`(\\theta, q)`.
    """


def random_segment(rng, n_links: int = 3, *, momentum: bool = False, limited: bool = False) -> PlanarSegment:
    """A random single segment of a random body (:func:`random_body`), reachable by construction.

    The body: :func:`random_body` with :math:`P_0 = 0`, or (``momentum``) :math:`P_0 = \\pm I(s_0)\\,
    \\omega_0` with :math:`\\omega_0 \\in [0.3, 2]` rad/s (a drift of that size at the start).
    The motion: :math:`T \\in [1, 3]` s, :math:`\\theta_0 \\in [-\\pi, \\pi]`, joints
    :math:`q_0 \\in [-1.5, 1.5]`, joint rates a random smooth polynomial (6 Legendre coefficients,
    standard deviations 1, 1, 0.6, 0.3 rad/s for the first four); the target is the end of the
    simulated motion (compiled integrator). With ``limited`` the problem carries joint limits 0.25
    rad outside the range the motion sweeps and rate limits 25% above its largest rates (so the
    motion that proves reachability keeps them).

    Returns
    -------
    PlanarSegment
    """
    from ...core import backend
    from ...core.basis import Legendre
    from ...core.limits import Limits, violation

    rng = np.random.default_rng(rng)
    body = random_body(rng, n_links)
    m = body.n_inputs
    q0 = rng.uniform(-1.5, 1.5, m)
    if momentum:
        w0 = rng.uniform(0.3, 2.0) * rng.choice([-1.0, 1.0])
        body = PlanarBody(body.links, P0=float(body.locked_inertia(q0) * w0))
    T, c = random_rates(rng, m)
    x0 = np.concatenate([[rng.uniform(-np.pi, np.pi)], q0])
    basis = Legendre(6)
    x1, _ = backend.endpoint(body, basis, x0, T, c)
    limits = None
    if limited:
        names = body.links.joint_names
        probe = Limits({n: (-1e6, 1e6) for n in names}, {f"u_{n}": 1e6 for n in names})
        v = violation(body, basis, x0, T, c, probe)
        ranges = v["state_ranges"]
        tops = [max(abs(x) for x in _extremes(basis, c[j])) for j in range(m)]
        limits = Limits({n: (ranges[n][0] - 0.25, ranges[n][1] + 0.25) for n in names},
                        {f"u_{n}": 1.25 * t for n, t in zip(names, tops)})
    return PlanarSegment(body, T, x0, np.asarray(x1, dtype=float), c, limits)


def _extremes(basis, c):
    from ...core.limits import input_extremes

    return input_extremes(basis, c)
