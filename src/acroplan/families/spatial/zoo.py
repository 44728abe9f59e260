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

from ..tree.segment import TreeSegment, link_count, random_rates
from . import rotations as rot
from .links import SpatialLink
from .model import SpatialBody

__all__ = ["random_body", "random_segment", "SpatialSegment", "box_inertia", "cylinder_inertia", "falling_cat",
           "cat_frame", "two_joint_cat", "long_axis_turn", "astronaut", "twisting_diver",
           "trunk_and_two_arms"]


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


def falling_cat(*, mass: float = 4.0, length: float = 0.5, radius: float = 0.06) -> SpatialBody:
    """Kane and Scher's (1969) cat: two equal solid cylinders (the front and the rear half) joined at
    the waist, where each half's axis meets it.

    Frames: the root is the front half, its frame at the waist with :math:`x` along the front
    half's axis towards the head, :math:`z` dorsal (towards the back), :math:`y` to the cat's left.
    The rear half hangs on three revolute joints at the waist (two through massless links):

    * ``bend`` about :math:`-y`: positive curls the cat forward (ventral flexion, the back arched
      up), negative bends it backward (extension); range :math:`[-60^\\circ, 100^\\circ]`;
    * ``side`` about :math:`z`: lateral flexion, range :math:`\\pm 70^\\circ`;
    * ``twist`` about the rear half's own axis, range :math:`\\pm 60^\\circ`.

    The ranges are round numbers chosen for this model (Kane and Scher's own motion bends the halves
    by 20 to 140 degrees for their inertia ratio 0.3): they are not measurements.

    Parameters
    ----------
    mass : float
        The whole cat (kg); each half has half of it.
    length : float
        The whole cat (m); each half has half of it.
    radius : float
        Of both cylinders (m). With the defaults the inertia about a half's axis over that about a
        perpendicular axis through its centre of mass is
        :math:`6 r^2 / (3 r^2 + \\ell^2) = 0.295` (Kane and Scher's ratio, 0.2 to 0.3).

    Returns
    -------
    SpatialBody
        At :math:`L = 0`.
    """
    half, lh = mass / 2.0, length / 2.0
    Ih = cylinder_inertia(half, lh, radius, axis=0)
    deg = np.pi / 180.0
    return SpatialBody([
        SpatialLink("front", None, half, Ih, com=(lh / 2.0, 0.0, 0.0)),
        SpatialLink("waist", "front", 0.0, (0.0, 0.0, 0.0), axis=(0.0, -1.0, 0.0), joint_name="bend",
                    lower=-60 * deg, upper=100 * deg),
        SpatialLink("waist2", "waist", 0.0, (0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0), joint_name="side",
                    lower=-70 * deg, upper=70 * deg),
        SpatialLink("rear", "waist2", half, Ih, com=(-lh / 2.0, 0.0, 0.0), axis=(1.0, 0.0, 0.0), joint_name="twist",
                    lower=-60 * deg, upper=60 * deg),
    ])


def cat_frame(cat: SpatialBody, shape) -> np.ndarray:
    """The cat's own frame in its root's frame at a shape: :math:`x` its long axis (from the rear
    half's centre of mass to the front half's), :math:`z` dorsal (the root's :math:`z` made
    orthogonal to :math:`x`), :math:`y = z \\times x`.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        Columns :math:`x, y, z` in the root frame: the root attitude that puts the cat upright with
        its long axis along the inertial :math:`x` is its transpose.
    """
    _, _, coms = cat.link_poses(np.concatenate([[1.0, 0.0, 0.0, 0.0], np.asarray(shape, dtype=float)]))
    front, rear = cat.links.index("front"), cat.links.index("rear")
    x = coms[front] - coms[rear]
    x /= np.linalg.norm(x)
    z = np.array([0.0, 0.0, 1.0]) - x[2] * x
    z /= np.linalg.norm(z)
    return np.column_stack([x, np.cross(z, x), z])


def two_joint_cat() -> SpatialBody:
    """A cat of two joints (issue #22): two halves of 1.5 kg (principal moments 0.0012, 0.0085,
    0.0085 kg m^2, the first about the half's axis), their centres of mass 0.12 m either side of the
    waist on the front half's :math:`x` axis; ``bend`` about :math:`y`, then ``sway`` about
    :math:`z`, both within :math:`\\pm 1.6` rad and 50 rad/s.

    Returns
    -------
    SpatialBody
        At :math:`L = 0`.
    """
    inertia = (0.0012, 0.0085, 0.0085)
    return SpatialBody([
        SpatialLink("front", None, 1.5, inertia, com=(0.12, 0.0, 0.0)),
        SpatialLink("waist", "front", 0.0, (0.0, 0.0, 0.0), axis=(0.0, 1.0, 0.0), joint_name="bend",
                    lower=-1.6, upper=1.6, velocity=50.0),
        SpatialLink("rear", "waist", 1.5, inertia, com=(-0.12, 0.0, 0.0), axis=(0.0, 0.0, 1.0), joint_name="sway",
                    lower=-1.6, upper=1.6, velocity=50.0),
    ])


def long_axis_turn(body: SpatialBody, shape, T: float, *, front: str = "front", rear: str = "rear") -> dict:
    """Plan keywords: 180 degrees about the long axis (the line through the centres of mass of the
    links ``front`` and ``rear``) at the body's :math:`L` in ``T`` seconds, from ``shape`` back to
    it, upside down to upright, the joints at rest at both ends (``conditions="free"``).

    Returns
    -------
    dict
        Keywords of :func:`acroplan.plan`.
    """
    shape = np.asarray(shape, dtype=float)
    _, _, coms = body.link_poses(np.concatenate([[1.0, 0.0, 0.0, 0.0], shape]))
    x = coms[body.links.index(front)] - coms[body.links.index(rear)]
    x /= np.linalg.norm(x)
    z = np.array([0.0, 0.0, 1.0]) - x[2] * x
    z /= np.linalg.norm(z)
    C = np.column_stack([x, np.cross(z, x), z])
    up = rot.from_matrix(C.T)
    down = rot.from_matrix(rot.to_matrix(rot.exp([np.pi, 0.0, 0.0])) @ C.T)
    joints = {name: [float(v)] * 2 for name, v in zip(body.links.joint_names, shape)}
    return dict(times=[0.0, float(T)], conditions="free", start_rate=0.0, end_rate=0.0, **joints,
                **rot.attitude_states([down, up]))


def astronaut(*, arm_mass: float = 3.6) -> SpatialBody:
    """A person in space: a rigid trunk (with head and legs) and two arms, two joints at each
    shoulder.

    The trunk (root, 67 kg; de Leva's (1996) proportions for a 75 kg adult, rounded) has its frame
    at its centre of mass with Yeadon's axes: :math:`x` lateral (left to right), :math:`y`
    antero-posterior (back to front), :math:`z` longitudinal (feet to head); principal moments
    (12.5, 12.0, 1.1) kg m². Each arm (``arm_mass`` kg, 0.7 m long, its centre of mass 0.3 m from the
    shoulder, moments (0.16, 0.16, 0.007) kg m²) hangs from a shoulder at :math:`(\\pm 0.19, 0,
    0.45)` m on two joints through a massless link:

    * ``left_flex``, ``right_flex`` (about :math:`x`): flexion, 0 the arm down, 90° forward, 180°
      overhead; range :math:`[-50^\\circ, 180^\\circ]`;
    * ``left_abd``, ``right_abd`` (about :math:`\\pm y`): abduction, the arm sideways away from the
      body; range :math:`[-20^\\circ, 180^\\circ]`.

    Returns
    -------
    SpatialBody
        At :math:`L = 0`.
    """
    deg = np.pi / 180.0
    arm = dict(inertia=(0.16, 0.16, 0.007), com=(0.0, 0.0, -0.3))
    links = [SpatialLink("trunk", None, 67.0, (12.5, 12.0, 1.1))]
    for side, sx, sy in (("left", -0.19, 1.0), ("right", 0.19, -1.0)):
        links += [
            SpatialLink(f"{side}_shoulder", "trunk", 0.0, (0.0, 0.0, 0.0), joint=(sx, 0.0, 0.45), axis=(1.0, 0.0, 0.0),
                        joint_name=f"{side}_flex"),
            SpatialLink(f"{side}_arm", f"{side}_shoulder", arm_mass, arm["inertia"], com=arm["com"],
                        axis=(0.0, sy, 0.0), joint_name=f"{side}_abd", lower=-20 * deg, upper=180 * deg),
        ]
    return SpatialBody(links)


def twisting_diver(L: float = 0.0) -> SpatialBody:
    """A diver in the layout position with arms (:func:`astronaut`'s body, arms lighter: 3.2 kg),
    with angular momentum ``L`` (kg m²/s) about the inertial :math:`x` axis (the somersault axis
    when the trunk's lateral axis is along it).

    Returns
    -------
    SpatialBody
    """
    body = astronaut(arm_mass=3.2)
    return SpatialBody(body.links, L=(float(L), 0.0, 0.0))


def trunk_and_two_arms(L=(36.3075, 0.0, 0.0)) -> SpatialBody:
    """bioptim's free-floating example body (``trunk_and_2arm.bioMod``, pyomeca/bioptim, MIT
    licence), link for link as :func:`~acroplan.families.spatial.read_biomod` reads it (so without
    biorbd; ``tests/test_optimal_spatial.py`` compares the two): a 58.801 kg trunk (principal moments
    7.85829, 8.12771, 0.51802 kg m², centre of mass 0.0941 m above its frame) and two 3.106 kg arms
    turning about their own :math:`y` axes at the shoulders :math:`(\\mp 0.1875, 0.0205, 0.4719)` m
    (``RightArm_RotY``, ``LeftArm_RotY``; each arm's centre of mass 0.233088 m down it, moments
    0.0910283, 0.0909983, 0.00292 kg m²), no joint limits; angular momentum ``L`` (kg m²/s,
    bioptim's example's about the somersault axis :math:`x` by default).

    Returns
    -------
    SpatialBody
    """
    arm = dict(mass=3.106, inertia=(0.0910283, 0.0909983, 0.00292), com=(0.0, 0.0, -0.233088), axis=(0.0, 1.0, 0.0))
    links = [SpatialLink("Pelvis", None, 58.801, (7.85829, 8.12771, 0.51802), com=(0.0, 0.0, 0.0941)),
             SpatialLink("RightArm", "Pelvis", joint=(-0.1875, 0.0205, 0.4719), joint_name="RightArm_RotY", **arm),
             SpatialLink("LeftArm", "Pelvis", joint=(0.1875, 0.0205, 0.4719), joint_name="LeftArm_RotY", **arm)]
    return SpatialBody(links, L=tuple(float(v) for v in L))


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
    n_links = link_count(n_links)
    rng = np.random.default_rng(rng)
    links, lengths = [], []
    for k in range(n_links):
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
class SpatialSegment(TreeSegment):
    """One random single-segment problem of a spatial body (:func:`random_segment`): a
    :class:`~acroplan.families.tree.segment.TreeSegment` (its attributes and
    :meth:`~acroplan.families.tree.segment.TreeSegment.plan_kwargs`) whose ``body`` is a
    :class:`SpatialBody`, ``x0``, ``x1`` its states :math:`(q_w, q_x, q_y, q_z, s)` of shape
    (4 + m,), and ``limits`` None.
    """


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
    T, c = random_rates(rng, m)
    x0 = np.concatenate([q0, s0])
    x1, _ = backend.endpoint(body, Legendre(6), x0, T, c)
    x1 = np.asarray(x1, dtype=float)
    x1[:4] /= np.linalg.norm(x1[:4])
    return SpatialSegment(body, T, x0, x1, c)
