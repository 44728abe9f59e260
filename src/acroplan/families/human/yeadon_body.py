"""Bodies from Yeadon's inertia model (95 measurements), through the ``yeadon`` package.

Yeadon's model (M. R. Yeadon 1990, J. Biomech. 23:67-74) builds the body from 40 solids (stadia
and a semi-ellipsoid) of measured lengths, perimeters, widths and depths, with segment densities;
the ``yeadon`` package (Dembia, Moore and Hubbard 2014) implements it and gives every segment's
mass, centre of mass and inertia tensor in any of its 21-angle configurations. It is optional
(``pip install acroplan[human]``) and imported only here, when a body is built.

yeadon's frames
---------------
yeadon's global frame has its origin at the centre of the bottom of the pelvis (the level of the
hip joint centres), :math:`x` to the body's left, :math:`y` backwards (posterior), :math:`z` up.
The somersault axis is :math:`x`; the sagittal plane is :math:`(y, z)`. A point :math:`(y, z)`
is, in the trunk frame of :mod:`~acroplan.families.human.body` (:math:`x` up, :math:`y` forwards,
normal to the left),

.. math::  (X, Y) = (z, -y) ,

and each part's moment of inertia about the somersault axis is the :math:`xx` entry of yeadon's
inertia tensor of the combined segments about their combined centre of mass
(``Human.combine_inertia``). yeadon's joint angles (checked numerically, tests/test_human.py):
``PJ1extension = PK1extension = -psi`` (hip flexion), ``CA1extension = CB1extension = -sigma``
(shoulder flexion), ``J1J2flexion = K1K2flexion = kappa`` (knee flexion); all others 0.

The parts
---------
``trunk``: segments P, T, C (pelvis, thorax, chest-head); ``arms``: A1, A2, B1, B2 (upper arms,
forearms with hands); ``legs``: J1, J2, K1, K2 (thighs, shanks with feet). They are computed in
yeadon's configuration with the hips at 0, the arms at the sides (:math:`\\sigma = 0`, arms along
:math:`-X`) and the knees at :math:`\\kappa`, and moved into their own frames: the shoulder joint
centre is yeadon's origin of segment A1 (its :math:`(y, z)`), the hip joint centre the origin of
J1 (at :math:`(0, 0)`), and a part hanging along :math:`-X` is turned by :math:`\\pi`:
:math:`c_{own} = R(-\\pi)(c - j) = (j - c)`.
"""

from __future__ import annotations

import contextlib
import difflib
import io
import math
import os
import re
import warnings
from importlib import resources

import numpy as np

from ...core.errors import InvalidInputError, finite_number
from .body import Part, SagittalBody

__all__ = ["from_yeadon", "load_human", "read_measurements", "sample_measurements", "SAMPLES", "TRUNK", "ARMS",
           "LEGS", "MAX_MEASUREMENT_BYTES", "MAX_MEASUREMENT_LINES", "MEASUREMENT_RANGE", "TOTALMASS_RANGE"]

#: The bundled measurement files, by name (``data/README.md``: source, licence, citation).
SAMPLES = {"male1": "yeadon_male1.txt"}

#: yeadon's segments of each part.
TRUNK = ("P", "T", "C")
ARMS = ("A1", "A2", "B1", "B2")
LEGS = ("J1", "J2", "K1", "K2")

_INSTALL = "pip install acroplan[human]  (or: pip install yeadon)"


def _yeadon():
    try:
        import yeadon
    except ImportError:
        raise ImportError(f"bodies from Yeadon's measurements need the yeadon package: {_INSTALL}") from None
    return yeadon


def sample_measurements(name: str = "male1") -> str:
    """The path of a bundled measurement file (``"male1"``: data/README.md)."""
    if name not in SAMPLES:
        raise InvalidInputError("sample", f"{name!r} is not a bundled sample", f"bundled samples: {sorted(SAMPLES)}")
    return str(resources.files(__package__).joinpath("data", SAMPLES[name]))


#: The largest measurement file read: yeadon's template with its comments is 4.6 kB; a file ten
#: times larger than any of its kind is refused before it is read (a YAML reader took 79 s and
#: 1.25 GB on an 8.9 MB file).
MAX_MEASUREMENT_BYTES = 100_000
#: The most lines a measurement file may have (the template has 221, 96 of them values).
MAX_MEASUREMENT_LINES = 2_000
#: The range of a measurement in metres (after ``measurementconversionfactor``): far beyond any
#: human, within what the model's volumes and inertias (fifth powers) carry.
MEASUREMENT_RANGE = (1e-6, 1e3)
#: The range of ``totalmass`` (kg).
TOTALMASS_RANGE = (1e-6, 1e6)

_NUMBER = re.compile(r"[-+]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][-+]?[0-9]+)?")
_LINE = re.compile(r"([A-Za-z][A-Za-z0-9_]*)[ \t]*:[ \t]*([^#\s]+)[ \t]*(?:#.*)?")


def read_measurements(path, names) -> tuple[dict, float | None]:
    """Yeadon's measurements from a measurement file, read and checked in bounded time and memory,
    never by a general YAML reader: at most :data:`MAX_MEASUREMENT_BYTES` bytes and
    :data:`MAX_MEASUREMENT_LINES` lines, each line blank, a ``#`` comment, or ``name: number``
    (``names``: yeadon's 95 measurements, ``measurementconversionfactor``, optional ``totalmass``).
    Every value must be finite and > 0, each name given once, every measurement given, and the
    measurements in metres within :data:`MEASUREMENT_RANGE`, ``totalmass`` within
    :data:`TOTALMASS_RANGE`. Messages give line numbers and yeadon's names, never a line of the file.

    Returns
    -------
    (dict, float or None)
        The measurements in metres by name, and ``totalmass`` (kg) when the file gives it.

    Raises
    ------
    InvalidInputError
        Naming ``measurements``.
    """
    fix = "give the 95 measurements in yeadon's format (its misc/meastemplate.txt): one 'name: number' per line"
    field = "measurements"
    label = os.path.basename(os.fspath(path))
    try:
        with open(path, "rb") as f:
            raw = f.read(MAX_MEASUREMENT_BYTES + 1)
    except OSError as e:
        raise InvalidInputError(field, f"cannot read {label!r} ({type(e).__name__})", fix) from None
    if len(raw) > MAX_MEASUREMENT_BYTES:
        raise InvalidInputError(field, f"{label!r} is larger than {MAX_MEASUREMENT_BYTES // 1000} kB: not a yeadon "
                                "measurement file (a few kB)", fix)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise InvalidInputError(field, f"yeadon cannot read {label!r}: it is not UTF-8 text", fix) from None
    lines = text.splitlines()
    if len(lines) > MAX_MEASUREMENT_LINES:
        raise InvalidInputError(field, f"{label!r} has {len(lines)} lines, more than {MAX_MEASUREMENT_LINES}: not a "
                                "yeadon measurement file", fix)
    known = set(names) | {"measurementconversionfactor", "totalmass"}
    values: dict[str, float] = {}
    where: dict[str, int] = {}
    for i, line in enumerate(lines, 1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        m = _LINE.fullmatch(stripped)
        if m is None:
            raise InvalidInputError(field, f"yeadon cannot read {label!r}: line {i} is not 'name: number'", fix)
        key, value = m.groups()
        if key not in known:
            close = difflib.get_close_matches(key, sorted(known), n=1, cutoff=0.8)
            raise InvalidInputError(field, f"yeadon cannot read {label!r}: line {i} names no measurement of yeadon's"
                                    + (f" (did you mean {close[0]!r}?)" if close else ""), fix)
        if key in values:
            raise InvalidInputError(field, f"yeadon cannot read {label!r}: line {i} gives {key} again (line "
                                    f"{where[key]} gave it)", "give each measurement once")
        if _NUMBER.fullmatch(value) is None:
            raise InvalidInputError(field, f"yeadon cannot read {label!r}: line {i} ({key}) is not a finite number", fix)
        v = float(value)
        if not (math.isfinite(v) and v > 0):
            raise InvalidInputError(field, f"yeadon cannot read {label!r}: line {i} ({key}) must be a finite number "
                                    f"> 0, got {v:g}", "give every measurement, the conversion factor and totalmass "
                                    "as positive numbers")
        values[key], where[key] = v, i
    missing = [n for n in names if n not in values]
    if missing or "measurementconversionfactor" not in values:
        what = (f"{len(missing)} of yeadon's {len(names)} measurements are missing (the first: {missing[0]})"
                if missing else "measurementconversionfactor is missing (1 for metres, 0.01 for cm, 0.001 for mm)")
        raise InvalidInputError(field, f"yeadon cannot read {label!r}: {what}", fix)
    factor = values.pop("measurementconversionfactor")
    total = values.pop("totalmass", None)
    lo, hi = MEASUREMENT_RANGE
    out = {}
    for key in names:
        v = values[key] * factor
        if not lo <= v <= hi:
            raise InvalidInputError(field, f"{label!r} line {where[key]}: {key} is {v:.3g} m, outside [{lo:g}, {hi:g}] "
                                    "m", "check the measurement and measurementconversionfactor (1 for metres, 0.01 "
                                    "for cm, 0.001 for mm)")
        out[key] = v
    if total is not None and not TOTALMASS_RANGE[0] <= total <= TOTALMASS_RANGE[1]:
        raise InvalidInputError(field, f"{label!r} line {where['totalmass']}: totalmass is {total:.3g} kg, outside "
                                f"[{TOTALMASS_RANGE[0]:g}, {TOTALMASS_RANGE[1]:g}] kg",
                                "give the body's measured mass in kg, or leave totalmass out")
    return out, total


def load_human(measurements=None, *, density_set: str = "Dempster", quiet: bool = True):
    """A ``yeadon.Human`` from a measurement file (or a bundled sample's name, default ``"male1"``).

    The file is read by :func:`read_measurements` (bounded, every value checked), and yeadon builds
    the human from the checked measurements, scaled to ``totalmass`` when the file gives it (as
    yeadon does when it reads a file itself).

    Parameters
    ----------
    measurements : str or os.PathLike, optional
        A yeadon measurement file (95 measurements, ``name: number`` per line), or the name of a
        bundled sample.
    density_set : {"Dempster", "Chandler", "Clauser"}
        yeadon's segment densities.
    quiet : bool
        Silence yeadon's printed notes and warnings about ill-defined stadia.

    Returns
    -------
    yeadon.Human

    Raises
    ------
    InvalidInputError
        The file is missing, not a measurement file, or yeadon cannot build a human of it (naming
        ``measurements``).
    ImportError
        yeadon is not installed (``pip install acroplan[human]``).
    """
    yeadon = _yeadon()
    if measurements is None:
        measurements = "male1"
    path = os.fspath(measurements)
    if path in SAMPLES:
        path = sample_measurements(path)
    if not isinstance(path, str) or len(path) > 4096 or "\0" in path or not os.path.isfile(path):
        shown = path if isinstance(path, str) and len(path) <= 200 else "(a long path)"
        raise InvalidInputError("measurements", f"no file {shown!r}",
                                f"give a yeadon measurement file or a bundled sample ({sorted(SAMPLES)})")
    if density_set not in ("Dempster", "Chandler", "Clauser"):
        raise InvalidInputError("density_set", f"must be 'Dempster', 'Chandler' or 'Clauser', got {density_set!r}",
                                "leave it at 'Dempster' (yeadon's default)")
    meas, total = read_measurements(path, yeadon.Human.measnames)
    label = os.path.basename(path)
    try:
        with warnings.catch_warnings(), contextlib.redirect_stdout(io.StringIO()), \
                np.errstate(all="ignore"):
            if quiet:
                warnings.simplefilter("ignore")
            human = yeadon.Human(dict(meas), density_set=density_set)
            if total is not None:
                human.meas_mass = total
                human.scale_human_by_mass(total)
    except Exception as e:  # yeadon raises bare Exceptions and ValueErrors for bad measurements
        raise InvalidInputError("measurements", f"yeadon cannot build a human of {label!r}: "
                                f"{str(e)[:200]}", "check the measurements (yeadon's misc/meastemplate.txt)") from None
    if not (math.isfinite(float(human.mass)) and float(human.mass) > 0):
        raise InvalidInputError("measurements", f"{label!r} makes a body of mass {float(human.mass)!r}",
                                "check the measurements and measurementconversionfactor")
    return human


def _configured(human, psi: float = 0.0, sigma: float = 0.0, kappa: float = 0.0):
    """Set the sagittal joint angles of ``human`` (all others 0)."""
    cfg = {name: 0.0 for name in human.CFGnames}
    cfg.update(PJ1extension=-psi, PK1extension=-psi, CA1extension=-sigma, CB1extension=-sigma,
               J1J2flexion=kappa, K1K2flexion=kappa)
    with contextlib.redirect_stdout(io.StringIO()):  # yeadon prints when an angle is out of its bounds
        human.set_CFG_dict(cfg)


def whole_body(human, hip_flexion: float = 0.0, shoulder_flexion: float = 0.0, knee_flexion: float = 0.0):
    """yeadon's own whole-body mass and moment of inertia about the somersault axis through the
    centre of mass, at the given sagittal angles (the human's configuration is restored after).

    Returns
    -------
    (float, float)
        Mass (kg) and :math:`I_{xx}` (kg m²).
    """
    saved = dict(human.CFG)
    try:
        _configured(human, hip_flexion, shoulder_flexion, knee_flexion)
        return float(human.mass), float(human.inertia[0, 0])
    finally:
        with contextlib.redirect_stdout(io.StringIO()):
            human.set_CFG_dict(saved)


def _part(human, segments, joint_yz):
    m, com, inertia = human.combine_inertia(segments)
    y, z = float(com[1, 0]), float(com[2, 0])
    X, Y = z, -y
    jX, jY = joint_yz[1], -joint_yz[0]
    return m, (X, Y), float(inertia[0, 0]), (jX, jY)


def human_of(human, density_set: str, needs) -> tuple:
    """``(yeadon.Human, label)`` of ``human``: ``None`` (the bundled male1) or a measurement file
    read by :func:`load_human`, or a ``yeadon.Human`` (an object with the attributes ``needs``)
    as given; the label names it in messages."""
    if human is None or isinstance(human, (str, os.PathLike)):
        return load_human(human, density_set=density_set), ("male1" if human is None else os.fspath(human))
    if not all(hasattr(human, a) for a in needs):
        raise InvalidInputError("human", f"must be a yeadon.Human or a measurement file, got {type(human).__name__}",
                                "give yeadon.Human(...) or the path of a measurement file")
    return human, "a yeadon.Human"


def from_yeadon(human=None, *, knee_flexion: float = 0.0, density_set: str = "Dempster") -> SagittalBody:
    """The :class:`~acroplan.families.human.body.SagittalBody` of a yeadon human (module docstring).

    Parameters
    ----------
    human : yeadon.Human, str or os.PathLike, optional
        A ``yeadon.Human`` (its configuration is restored afterwards), a measurement file, or a
        bundled sample's name; default the bundled ``"male1"``.
    knee_flexion : float
        :math:`\\kappa` (rad, 0 to :math:`\\pi`): the knees' fixed flexion (0 for a pike or a
        straight position; :data:`~acroplan.families.human.limits.POSITIONS` gives a tuck's).
    density_set : str
        yeadon's densities when ``human`` is a file.

    Returns
    -------
    SagittalBody

    Examples
    --------
    >>> from acroplan.families.human import from_yeadon
    >>> body = from_yeadon()                      # the bundled male1: 58.2 kg
    >>> round(body.mass, 3)
    58.2
    """
    kappa = finite_number("knee_flexion", knee_flexion)
    if not 0.0 <= kappa <= math.pi:
        raise InvalidInputError("knee_flexion", f"must be in [0, pi] (yeadon's range), got {kappa:g}",
                                "give the knee flexion in radians, 0 for straight knees")
    human, label = human_of(human, density_set, ("combine_inertia", "set_CFG_dict", "CFGnames"))
    saved = dict(human.CFG)
    try:
        _configured(human, 0.0, 0.0, kappa)
        hip = (float(human.J1.pos[1, 0]), float(human.J1.pos[2, 0]))
        shoulder = (float(human.A1.pos[1, 0]), float(human.A1.pos[2, 0]))
        if max(abs(hip[0]), abs(hip[1])) > 1e-12:  # pragma: no cover - yeadon puts the hips at its origin
            raise InvalidInputError("human", f"yeadon's hip joint centre is at (y, z) = {hip}, not at the origin",
                                    "report this: the yeadon version is not supported")
        mT, cT, IT, _ = _part(human, TRUNK, hip)
        mA, cA, IA, jS = _part(human, ARMS, shoulder)
        mL, cL, IL, _ = _part(human, LEGS, hip)
    finally:
        with contextlib.redirect_stdout(io.StringIO()):
            human.set_CFG_dict(saved)
    # the arms and the legs hang along -X (angle pi) in this configuration: c_own = R(-pi)(c - j) = j - c
    arms = Part(mA, (jS[0] - cA[0], jS[1] - cA[1]), IA)
    legs = Part(mL, (-cL[0], -cL[1]), IL)
    return SagittalBody(trunk=Part(mT, cT, IT), arms=arms, legs=legs, shoulder=jS, knee_flexion=kappa,
                        source=f"yeadon ({label})")


def yeadon_check(human, body: SagittalBody, angles) -> np.ndarray:
    """Relative differences between yeadon's whole-body moment of inertia and the body's, at each
    ``(hip_flexion, shoulder_flexion)`` of ``angles`` (with the body's knee flexion): the check
    that the parts, their frames and the angle conventions are right.

    Returns
    -------
    numpy.ndarray, shape (len(angles),)
    """
    out = []
    for psi, sigma in angles:
        _, ref = whole_body(human, psi, sigma, body.knee_flexion)
        out.append(abs(body.inertia(psi, sigma) - ref) / ref)
    return np.array(out)
