"""Unit quaternions, rotation vectors, rotation matrices and Euler angles (numpy).

Conventions
-----------
* A quaternion is ``[w, x, y, z]`` (scalar first). The attitude :math:`q` of a body frame maps body
  coordinates to inertial ones: :math:`v_{inertial} = R(q)\\, v_{body}`.
* Products are Hamilton's, :math:`q_1 \\otimes q_2` (:func:`qmul`) is the rotation :math:`q_2` then
  :math:`q_1` applied in the *inertial* frame, or :math:`q_1` then :math:`q_2` about the *moving*
  axes: :math:`R(q_1 \\otimes q_2) = R(q_1) R(q_2)`.
* A rotation vector :math:`v` is the axis times the angle (rad); :func:`exp` gives its quaternion,
  :func:`log` the rotation vector of angle in :math:`[0, \\pi]` (``q`` and ``-q`` are the same
  attitude).
* The kinematics of a body turning at :math:`\\Omega` (body frame) is
  :math:`\\dot q = \\tfrac12 q \\otimes (0, \\Omega) = \\tfrac12 \\Xi(q)\\, \\Omega` (:func:`xi`).
* Euler angles: :func:`from_euler` and :func:`to_euler` with any scipy sequence, and the named
  convention ``"yeadon"`` (Yeadon 1990, *The simulation of aerial movement - I*, J. Biomech.
  23(1), 59-66): **somersault** :math:`\\phi` about the body's lateral axis :math:`x`, then **tilt**
  :math:`\\theta` about the once-turned antero-posterior axis :math:`y'`, then **twist** :math:`\\psi`
  about the twice-turned longitudinal axis :math:`z''`,

  .. math::  R = R_x(\\phi)\\, R_y(\\theta)\\, R_z(\\psi),

  for a body frame with :math:`x` lateral (left to right), :math:`y` antero-posterior (back to
  front) and :math:`z` longitudinal (feet to head). This is scipy's intrinsic sequence ``"XYZ"``;
  the tilt lies in :math:`[-90^\\circ, 90^\\circ]`.
"""

from __future__ import annotations

import math

import numpy as np

from ...core.errors import InvalidInputError

__all__ = ["qmul", "qconj", "exp", "log", "to_matrix", "from_matrix", "xi", "angle_between", "normalize",
           "from_euler", "to_euler", "as_quaternion", "attitude_states", "EULER_NAMES", "YEADON"]

#: The named Euler convention of biomechanics (module docstring): scipy's intrinsic ``"XYZ"``.
YEADON = "XYZ"
#: The names of the three Yeadon angles, in order.
EULER_NAMES = ("somersault", "tilt", "twist")


def qmul(a, b) -> np.ndarray:
    """Hamilton product :math:`a \\otimes b` of quaternions ``[w, x, y, z]`` (shape (4,) or (4, N))."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw])


def qconj(q) -> np.ndarray:
    """The conjugate ``[w, -x, -y, -z]`` (the inverse of a unit quaternion)."""
    q = np.asarray(q, dtype=float)
    return np.concatenate([q[:1], -q[1:]])


def normalize(q) -> np.ndarray:
    """``q / |q|``."""
    q = np.asarray(q, dtype=float)
    return q / np.linalg.norm(q, axis=0)


def exp(v) -> np.ndarray:
    """The unit quaternion of the rotation vector ``v`` (shape (3,)):
    :math:`(\\cos(|v|/2), \\sin(|v|/2)\\, v/|v|)`."""
    v = np.asarray(v, dtype=float)
    a = math.sqrt(float(v @ v))
    if a < 1e-8:  # series: sin(a/2)/a = 1/2 - a^2/48, cos(a/2) = 1 - a^2/8
        return np.concatenate([[1.0 - a * a / 8.0], (0.5 - a * a / 48.0) * v])
    return np.concatenate([[math.cos(a / 2.0)], (math.sin(a / 2.0) / a) * v])


def log(q) -> np.ndarray:
    """The rotation vector (angle in :math:`[0, \\pi]`) of the attitude ``q`` (normalised first)."""
    q = np.asarray(q, dtype=float)
    q = q / math.sqrt(float(q @ q))
    if q[0] < 0:
        q = -q
    s = math.sqrt(float(q[1:] @ q[1:]))
    if s < 1e-8:  # angle = 2 atan2(s, w) ~ 2 s / w
        return (2.0 / q[0]) * (1.0 - s * s / (3.0 * q[0] * q[0])) * q[1:]
    return (2.0 * math.atan2(s, q[0]) / s) * q[1:]


def angle_between(q0, q1) -> float:
    """The angle (rad, in :math:`[0, \\pi]`) of the rotation :math:`q_0^{-1} \\otimes q_1`."""
    return float(np.linalg.norm(log(qmul(qconj(q0), q1))))


def to_matrix(q) -> np.ndarray:
    """:math:`R(q)` (shape (3, 3)), body to inertial, for a unit ``q`` (homogeneous form: a non-unit
    ``q`` gives :math:`|q|^2 R`)."""
    w, x, y, z = (float(v) for v in q)
    return np.array([[w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z]])


def from_matrix(R) -> np.ndarray:
    """The unit quaternion (``w >= 0``) of a rotation matrix (scipy's ``Rotation.from_matrix``)."""
    from scipy.spatial.transform import Rotation

    x, y, z, w = Rotation.from_matrix(np.asarray(R, dtype=float)).as_quat()
    q = np.array([w, x, y, z])
    return -q if w < 0 else q


def xi(q) -> np.ndarray:
    """:math:`\\Xi(q)` (shape (4, 3)) with :math:`\\tfrac12 q \\otimes (0, \\Omega) = \\tfrac12 \\Xi(q)\\,\\Omega`."""
    w, x, y, z = (float(v) for v in q)
    return np.array([[-x, -y, -z], [w, -z, y], [z, w, -x], [-y, x, w]])


def from_euler(angles, seq: str = "yeadon", degrees: bool = True) -> np.ndarray:
    """The unit quaternion of Euler angles.

    Parameters
    ----------
    angles : array_like, shape (3,)
        For ``"yeadon"``: (somersault, tilt, twist).
    seq : str
        ``"yeadon"`` (module docstring) or any scipy sequence (``"XYZ"`` intrinsic, ``"xyz"``
        extrinsic, ...).
    degrees : bool

    Returns
    -------
    numpy.ndarray, shape (4,)
    """
    from scipy.spatial.transform import Rotation

    a = np.asarray(angles, dtype=float)
    if a.shape != (3,) or not np.isfinite(a).all():
        raise InvalidInputError("euler", f"must be three finite angles, got {angles!r}",
                                "give for example [180, 0, 90] (somersault, tilt, twist in degrees)")
    x, y, z, w = Rotation.from_euler(_seq(seq), a, degrees=degrees).as_quat()
    q = np.array([w, x, y, z])
    return -q if w < 0 else q


def to_euler(q, seq: str = "yeadon", degrees: bool = True) -> np.ndarray:
    """Euler angles of the attitude ``q`` (shape (4,) or (4, N)); for ``"yeadon"`` (somersault, tilt,
    twist), shape (3,) or (3, N). Angles are in :math:`(-180^\\circ, 180^\\circ]` (tilt in
    :math:`[-90^\\circ, 90^\\circ]`); unwrap them along a motion with ``numpy.unwrap``."""
    from scipy.spatial.transform import Rotation

    q = np.asarray(q, dtype=float)
    quat = np.stack([q[1], q[2], q[3], q[0]], axis=-1) if q.ndim == 1 else np.stack([q[1], q[2], q[3], q[0]], axis=1)
    out = Rotation.from_quat(quat).as_euler(_seq(seq), degrees=degrees)
    return out if q.ndim == 1 else out.T


def _seq(seq: str) -> str:
    if not isinstance(seq, str):
        raise InvalidInputError("seq", f"must be a string, got {seq!r}", "give \"yeadon\" or a scipy sequence")
    if seq.lower() == "yeadon":
        return YEADON
    if len(seq) != 3 or not (set(seq) <= set("xyz") or set(seq) <= set("XYZ")):
        raise InvalidInputError("seq", f"must be \"yeadon\" or three of x, y, z (intrinsic in capitals), got {seq!r}",
                                "give for example \"yeadon\" or \"ZYX\"")
    return seq


def as_quaternion(value, field: str = "attitude") -> np.ndarray:
    """An attitude given in any accepted form, as a unit quaternion ``[w, x, y, z]``.

    Accepted: a sequence of 4 numbers (a quaternion, normalised here; its norm must lie within
    1e-6 of 1 to catch typing errors), or a mapping with exactly one of
    ``{"quaternion": [w, x, y, z]}``, ``{"rotvec": [x, y, z]}`` (radians),
    ``{"rotvec_deg": [x, y, z]}``, ``{"euler_deg": [a, b, c]}`` (Yeadon's somersault, tilt, twist,
    or with ``"seq"`` another sequence), ``{"euler": [a, b, c]}`` (radians).

    Returns
    -------
    numpy.ndarray, shape (4,)
    """
    if isinstance(value, dict):
        kinds = [k for k in value if k != "seq"]
        if len(kinds) != 1:
            raise InvalidInputError(field, f"must have one of quaternion, rotvec, rotvec_deg, euler, euler_deg; got "
                                    f"{sorted(value)}", "give for example {\"euler_deg\": [0, 0, 180]}")
        kind = kinds[0]
        v = np.asarray(value[kind], dtype=float)
        seq = value.get("seq", "yeadon")
        if kind == "quaternion":
            return as_quaternion(v, f"{field}.quaternion")
        if kind in ("rotvec", "rotvec_deg"):
            if v.shape != (3,) or not np.isfinite(v).all():
                raise InvalidInputError(f"{field}.{kind}", f"must be three finite numbers, got {value[kind]!r}",
                                        "give the rotation axis times the angle")
            return exp(np.radians(v) if kind == "rotvec_deg" else v)
        if kind in ("euler", "euler_deg"):
            return from_euler(v, seq, degrees=kind == "euler_deg")
        raise InvalidInputError(f"{field}.{kind}", "is not a form of attitude",
                                "give quaternion, rotvec, rotvec_deg, euler or euler_deg")
    try:
        q = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(field, f"must be a quaternion [w, x, y, z], got {value!r}",
                                "give four numbers, or a table with rotvec or euler_deg") from None
    if q.shape != (4,) or not np.isfinite(q).all():
        raise InvalidInputError(field, f"must be a quaternion [w, x, y, z] (4 finite numbers), got {value!r}",
                                "give for example [1, 0, 0, 0]")
    nq = float(np.linalg.norm(q))
    if abs(nq - 1.0) > 1e-6:
        raise InvalidInputError(field, f"has norm {nq:.9g}, not 1", "give a unit quaternion [w, x, y, z] (divide by "
                                "its norm if that is what you meant)")
    return q / nq


def attitude_states(attitudes, field: str = "attitude") -> dict[str, list[float]]:
    """Waypoint keywords ``qw, qx, qy, qz`` of :func:`acroplan.plan` from attitudes in any form.

    Parameters
    ----------
    attitudes : sequence
        One attitude per waypoint, each in a form :func:`as_quaternion` accepts (a quaternion
        ``[w, x, y, z]``, or ``{"euler_deg": [somersault, tilt, twist]}``, ``{"rotvec": ...}``, ...).
        Consecutive quaternions are given the same hemisphere (``q`` and ``-q`` are one attitude).

    Returns
    -------
    dict
        ``{"qw": [...], "qx": [...], "qy": [...], "qz": [...]}``.

    Examples
    --------
    >>> kw = attitude_states([[1, 0, 0, 0], {"euler_deg": [0, 0, 180]}])
    >>> [round(v, 12) for v in kw["qz"]]
    [0.0, 1.0]
    """
    if isinstance(attitudes, (str, bytes, dict)) or not hasattr(attitudes, "__len__"):
        raise InvalidInputError(field, f"must be a list of attitudes, one per waypoint, got {attitudes!r}",
                                "give for example [[1, 0, 0, 0], {\"euler_deg\": [0, 0, 90]}]")
    qs = []
    for k, a in enumerate(attitudes):
        q = as_quaternion(a, f"{field}[{k}]")
        if qs and float(q @ qs[-1]) < 0:
            q = -q
        qs.append(q)
    return {name: [float(q[i]) for q in qs] for i, name in enumerate(("qw", "qx", "qy", "qz"))}
