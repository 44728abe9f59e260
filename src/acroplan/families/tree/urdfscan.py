"""A URDF file checked before Pinocchio reads it: one streaming XML pass (expat, bounded memory) that
counts the links and joints, bounds the nesting, refuses entity declarations, and checks every
number of the links' ``<inertial>`` and of the joints' geometry, naming the link or joint.

Why before: Pinocchio's URDF reader (urdfdom, then Pinocchio's own tree walk) recurses once per link
of a chain and overflows the stack on long chains (a 3,831-link chain killed the process with
SIGSEGV, no message), and urdfdom reads a ``<mass value="nan">`` by printing an error and dropping
the link's inertia, so that the body silently changes. Both are refused here, with one line; what
urdfdom still prints while Pinocchio reads the file is captured (:func:`captured_stderr`) and turned
into the same kind of message.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
import sys
import tempfile
import threading
import xml.parsers.expat

import numpy as np

from ...core.errors import InvalidInputError
from ...core.validate import MAX_ANGLE, MAX_BODY, MAX_FILE_BYTES, MAX_LINKS, MIN_BODY

__all__ = ["UrdfScan", "scan_urdf", "captured_stderr", "inertia_problem", "MAX_URDF_LINKS", "MAX_XML_DEPTH"]

#: The most ``<link>`` elements a URDF may have (moving or fixed): Pinocchio's reader overflowed an
#: 8 MB stack on chains of about 3,500 links; fixed links are merged into their parents, and a body
#: has at most MAX_LINKS moving links, so a thousand is far beyond any body acroplan plans.
MAX_URDF_LINKS = 1000
#: The deepest nesting of XML elements (a URDF nests five or six deep).
MAX_XML_DEPTH = 64

_FIX = "check the URDF"
_INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


@dataclasses.dataclass
class UrdfScan:
    """What the streaming pass saw: the number of ``<link>`` and ``<joint>`` elements, and of joints
    that move (any type but ``fixed``)."""

    links: int = 0
    joints: int = 0
    moving: int = 0


class _Stop(Exception):
    def __init__(self, error: InvalidInputError):
        self.error = error


def _number(where: str, what: str, text, most: float | None = None, kind: str = "the body's numbers") -> float:
    """A number of the URDF (``where``: the link or joint; ``what``: the attribute, a noun), never
    quoting the file's text."""
    try:
        v = float(str(text).strip())
    except (TypeError, ValueError):
        raise InvalidInputError(where, f"has a {what} that is not a number", "write a decimal number (for example "
                                "0.5)") from None
    if not math.isfinite(v):
        raise InvalidInputError(where, f"has {what} = {v}, not a finite number", "write a finite number")
    if most is not None and abs(v) > most:
        raise InvalidInputError(where, f"has {what} = {v:.3g}: {kind} beyond {most:g} in size are more than the "
                                "arithmetic carries", "change the units so that the numbers come nearer to 1")
    return v


def _triple(where: str, what: str, text, most: float, kind: str) -> tuple[float, float, float]:
    parts = str(text).split()
    if len(parts) != 3:
        raise InvalidInputError(where, f"has a {what} of {len(parts)} numbers, not 3", "write for example "
                                "\"0 0 1\"")
    return tuple(_number(where, f"{what}[{i}]", p, most, kind) for i, p in enumerate(parts))


def inertia_problem(I: np.ndarray) -> str | None:  # noqa: E741
    """Why the symmetric 3 x 3 ``I`` is no rigid body's inertia about its centre of mass (what it has:
    a negative principal moment, or principal moments breaking :math:`I_1 + I_2 \\ge I_3`), or ``None``."""
    scale = max(float(np.max(np.abs(I))), 1e-300)
    ev = np.linalg.eigvalsh(0.5 * (I + I.T))
    if ev[0] < -1e-12 * scale:
        return f"a negative principal moment ({ev[0]:.6g}), and an inertia is positive semi-definite"
    if ev[0] + ev[1] < ev[2] * (1 - 1e-9) - 1e-12 * scale:
        return (f"principal moments {[float(f'{v:.6g}') for v in ev]} that break I1 + I2 >= I3, which every rigid "
                "body satisfies")
    return None


class _Scanner:
    def __init__(self, name: str):
        self.name = name
        self.scan = UrdfScan()
        self.stack: list[str] = []
        self.link: str | None = None  # the link being read
        self.inertial: dict | None = None
        self.joint: str | None = None

    def fail(self, where: str, problem: str, fix: str = _FIX):
        raise _Stop(InvalidInputError(where, problem, fix))

    # expat handlers -------------------------------------------------------------------------
    def start(self, tag, attrs):
        self.stack.append(tag)
        depth = len(self.stack)
        if depth > MAX_XML_DEPTH:
            self.fail("urdf", f"{self.name} nests XML elements more than {MAX_XML_DEPTH} deep", "give a URDF file")
        if depth == 1:
            if tag != "robot":
                self.fail("urdf", f"{self.name} is not a URDF: its top element is not <robot>", "give a URDF file")
            return
        parent = self.stack[-2]
        try:
            if depth == 2 and tag == "link":
                self.scan.links += 1
                self.link = str(attrs.get("name", f"#{self.scan.links}"))
            elif depth == 2 and tag == "joint":
                self.scan.joints += 1
                self.joint = str(attrs.get("name", f"#{self.scan.joints}"))
                if attrs.get("type", "").strip() != "fixed":
                    self.scan.moving += 1
            elif tag == "inertial" and parent == "link" and depth == 3:
                self.inertial = {}
            elif self.inertial is not None and parent == "inertial" and depth == 4:
                self.inertial_element(tag, attrs)
            elif self.joint is not None and parent == "joint" and depth == 3:
                self.joint_element(tag, attrs)
        except InvalidInputError as e:
            raise _Stop(e) from None

    def end(self, tag):
        depth = len(self.stack)
        self.stack.pop()
        if depth == 3 and tag == "inertial" and self.inertial is not None:
            try:
                self.check_inertial(self.inertial)
            except InvalidInputError as e:
                raise _Stop(e) from None
            self.inertial = None
        elif depth == 2:
            self.link = self.joint = None

    def entity(self, *args):
        self.fail("urdf", f"{self.name} declares XML entities, which a URDF does not need (and which can expand a "
                  "small file into gigabytes)", "remove the <!ENTITY ...> declarations")

    # checks ---------------------------------------------------------------------------------
    def where_link(self) -> str:
        return f"urdf link {self.link!r}"

    def inertial_element(self, tag, attrs):
        where = self.where_link()
        if tag == "mass":
            if "value" not in attrs:
                self.fail(where, "has a <mass> without a value", "write <mass value=\"1.0\"/>")
            self.inertial["mass"] = _number(where, "mass", attrs["value"])
        elif tag == "inertia":
            missing = [k for k in _INERTIA if k not in attrs]
            if missing:
                self.fail(where, f"has an <inertia> without {missing[0]}", "give ixx, ixy, ixz, iyy, iyz and izz")
            self.inertial["inertia"] = [_number(where, f"inertia {k}", attrs[k], MAX_BODY) for k in _INERTIA]
        elif tag == "origin":
            if "xyz" in attrs:
                _triple(where, "centre of mass (inertial origin xyz)", attrs["xyz"], MAX_BODY, "the body's numbers")
            if "rpy" in attrs:
                _triple(where, "inertial origin rpy", attrs["rpy"], MAX_ANGLE, "angles")

    def check_inertial(self, d: dict):
        where = self.where_link()
        if "mass" not in d:
            self.fail(where, "has an <inertial> without <mass>", "give <mass value=\"...\"/> in its <inertial>")
        m = d["mass"]
        if m < 0:
            self.fail(where, f"has mass {m:g} < 0", "give the link's mass in kg (> 0; 0 for a massless link)")
        if m > MAX_BODY:
            self.fail(where, f"has mass {m:.3g}: masses beyond {MAX_BODY:g} are more than the arithmetic carries",
                      "change the units so that the numbers come nearer to 1")
        if 0 < m < MIN_BODY:
            self.fail(where, f"has mass {m:.3g}: masses below {MIN_BODY:g} are less than the arithmetic carries",
                      "change the units so that the numbers come nearer to 1, or give mass 0 (a massless link)")
        I = d.get("inertia")  # noqa: E741
        if I is None:
            self.fail(where, "has an <inertial> without <inertia>", "give <inertia ixx=... izz=.../> in its <inertial>")
        ixx, ixy, ixz, iyy, iyz, izz = I
        M = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
        nonzero = [abs(v) for v in I if v != 0.0]
        if nonzero and max(nonzero) < MIN_BODY:
            self.fail(where, f"has an inertia of {max(nonzero):.3g}: inertias below {MIN_BODY:g} are less than the "
                      "arithmetic carries", "change the units so that the numbers come nearer to 1")
        if m == 0.0 and nonzero:
            self.fail(where, "has mass 0 and an inertia that is not zero: a massless link has no inertia",
                      "give the link its mass, or an inertia of 0 (massless links join revolute joints into a "
                      "multi-axis joint)")
        why = inertia_problem(M)
        if why:
            self.fail(where, f"has an inertia with {why}", "check the inertia tensor (about the link's own centre of mass)")

    def joint_element(self, tag, attrs):
        where = f"urdf joint {self.joint!r}"
        if tag == "origin":
            if "xyz" in attrs:
                _triple(where, "origin xyz", attrs["xyz"], MAX_BODY, "the body's numbers")
            if "rpy" in attrs:
                _triple(where, "origin rpy", attrs["rpy"], MAX_ANGLE, "angles")
        elif tag == "axis" and "xyz" in attrs:
            a = _triple(where, "axis", attrs["xyz"], MAX_BODY, "the body's numbers")
            if math.sqrt(sum(v * v for v in a)) < 1e-12:
                self.fail(where, "has the axis 0 0 0", "give the joint's axis, for example xyz=\"0 0 1\"")
        elif tag == "limit":
            for key in ("lower", "upper", "velocity", "effort"):
                if key in attrs:
                    try:
                        v = float(str(attrs[key]).strip())
                    except ValueError:
                        self.fail(where, f"has a limit {key} that is not a number", "write a decimal number")
                    if math.isnan(v):
                        self.fail(where, f"has a limit {key} of nan", "write a number (1e300 or more for no limit)")


def scan_urdf(path, name: str | None = None) -> UrdfScan:
    """Check the URDF file ``path`` in one streaming pass (module docstring), at most
    :data:`~acroplan.core.validate.MAX_FILE_BYTES` bytes; ``name`` names it in messages (default its
    file name).

    Returns
    -------
    UrdfScan

    Raises
    ------
    InvalidInputError
        Naming ``urdf``, or the URDF's link or joint (``urdf link 'arm'``): not XML, not a URDF,
        too large, too many links (:data:`MAX_URDF_LINKS`) or moving joints (more than
        :data:`~acroplan.core.validate.MAX_LINKS` links), nested too deep, an entity declared, a
        number that is not finite or beyond the ranges of link tables, a negative mass, a massless
        link with inertia, an inertia that is no rigid body's.
    """
    name = name or os.path.basename(os.fspath(path))
    try:
        size = os.path.getsize(path)
    except OSError as e:
        raise InvalidInputError("urdf", f"{name} cannot be read ({type(e).__name__})", "give a .urdf file") from None
    if size > MAX_FILE_BYTES:
        raise InvalidInputError("urdf", f"{name} is larger than {MAX_FILE_BYTES // 1_000_000} MB",
                                "give the URDF of a body")
    s = _Scanner(name)
    parser = xml.parsers.expat.ParserCreate()
    parser.StartElementHandler = s.start
    parser.EndElementHandler = s.end
    parser.EntityDeclHandler = s.entity
    try:
        with open(path, "rb") as f:
            parser.ParseFile(f)
    except _Stop as e:
        raise e.error from None
    except xml.parsers.expat.ExpatError as e:
        raise InvalidInputError("urdf", f"{name} is not well-formed XML ({xml.parsers.expat.ErrorString(e.code)} at "
                                f"line {e.lineno}, column {e.offset})", "give a URDF file") from None
    except OSError as e:
        raise InvalidInputError("urdf", f"{name} cannot be read ({type(e).__name__})", "give a .urdf file") from None
    scan = s.scan
    if scan.moving + 1 > MAX_LINKS:
        raise InvalidInputError("urdf", f"{name} has {scan.moving} moving joints ({scan.moving + 1} moving links), "
                                f"more than {MAX_LINKS} links: the compiled integrator of such a body takes hours to "
                                f"build", f"give at most {MAX_LINKS} links (join links that move together with fixed "
                                "joints)")
    if max(scan.links, scan.joints) > MAX_URDF_LINKS:
        raise InvalidInputError("urdf", f"{name} has {scan.links} links and {scan.joints} joints, more than "
                                f"{MAX_URDF_LINKS}: Pinocchio's URDF reader recurses once per link and would overflow "
                                "the stack", "join the fixed links into their parents")
    if scan.links == 0:
        raise InvalidInputError("urdf", f"{name} has no <link>", "give a URDF file with links")
    return scan


_STDERR_LOCK = threading.Lock()


@contextlib.contextmanager
def captured_stderr(lines: list):
    """Redirect the process's stderr (file descriptor 2, where C++ libraries print) into a temporary
    file while the body runs; ``lines`` gets what was printed, one entry per line (at most 64 kB).
    Other threads' writes to stderr in that window are captured too (the body is short: reading one
    URDF)."""
    with _STDERR_LOCK:
        try:
            sys.stderr.flush()
        except (AttributeError, ValueError, OSError):  # pragma: no cover - a closed or replaced stderr
            pass
        try:
            saved = os.dup(2)
        except OSError:  # pragma: no cover - no file descriptor 2: nothing to capture
            yield lines
            return
        with tempfile.TemporaryFile() as tmp:
            os.dup2(tmp.fileno(), 2)
            try:
                yield lines
            finally:
                os.dup2(saved, 2)
                os.close(saved)
                tmp.seek(0)
                text = tmp.read(65536).decode("utf-8", "replace")
                lines.extend(line.strip() for line in text.splitlines() if line.strip())
