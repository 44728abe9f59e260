"""Body families as plug-ins: the contract between a family and the layers above it.

A *family* is a kind of body (the two-link acrobot, planar bodies of any number of links, bodies in
3-D, human bodies from anthropometric data, the small kinematic systems). Its model, planners and
checks live in its own folder under ``acroplan/families``; what the problem files, the command line,
the sweeps and the result files need of it is one :class:`Family` object that the family registers.
The I/O layer and the front doors ask this registry; they never name a family, so a new family is a
new folder and one registration.

Registration
------------
A family is found through the entry point group ``acroplan.families`` (``pyproject.toml``:
``[project.entry-points."acroplan.families"]``, ``name = "package.module:FAMILY"``), so a family in
another package registers the same way as acroplan's own; or by :func:`register_family` at run time
(tests, notebooks). Entry points are loaded on first use of the registry, not at import: a command
that needs no family loads none.

The contract (for implementers)
-------------------------------
A family is a frozen :class:`Family`. Everything but ``name`` and ``system_types`` is optional; a
missing hook means the family does not offer that job, and the layer asking says so to the user.

1. ``name`` (str): unique; ``system_types`` (tuple of classes, or of ``"module:Class"`` strings,
   which are imported only when needed: :meth:`Family.classes`): the systems it owns;
   :func:`family_of` finds a system's family along its class's MRO (by name, importing nothing).
   ``setup`` (tuple of module names): the modules that register what the family's systems need
   (strategies, torque models, the optimal strategies' starts, sweep hooks); :func:`prepare`
   imports them before a system of the family is planned (the front doors and the registries'
   look-ups call it), so neither the family's descriptor nor its package imports them.
2. ``tables``: the problem-file tables it may read (``"robot"``, ``"body"``), with their keys
   ``table_keys`` (a key no family knows is refused with the nearest known one);
   ``reads(table, data) -> bool``: whether it reads this one (``data`` the table). Families are
   asked in order of ``priority`` (higher first), so a family keyed on a few distinctive keys (a
   human body's ``yeadon``) is asked before a general one (a link table).
3. ``read(table, data, limits, context) -> (system, options)``: the system, and the :func:`plan`
   keywords that the file's ``[limits]`` table gives (the acrobot's ``phi_min``, ...); a family
   that writes the limits into its body returns ``{}`` and sets ``limits_in_body`` (the reader of
   ``[plan]`` then turns the file's angles into radians when ``options.degrees`` is set; otherwise
   ``degrees`` is a plan keyword). ``context`` is a :class:`ReadContext`.
   Messages name the file's fields (``body.link[2].mass``) through
   :class:`~acroplan.core.errors.InvalidInputError`.
4. ``waypoints(system, table, data, count) -> dict`` (optional): the waypoints of the states
   ``waypoint_states`` that a ``[plan]`` (``count`` waypoints) or ``[simulate]`` (``count=None``: the
   initial state) table gives in other forms than one list per state (a spatial body's attitude
   ``qw, qx, qy, qz`` as quaternions, Euler angles or rotation vectors), through the keys
   ``waypoint_keys``.
5. ``reach(problem) -> list of dict`` (optional): what can be proven about each segment of a
   problem (``acroplan reach``), and ``reach_figure(problem, rows) -> Figure``.
6. ``two_link(problem)`` (optional): the problem's body as the acrobot of the text, the offsets
   of its angles, its joint's name and its limits, for the exact answers of the two-link body
   (``acroplan least-momentum``); ``least_momentum`` and ``somersault_table`` (the acrobot's): the
   exact least angular momentum of a turn, and its table over somersaults and flight times. (What a
   family offers sweeps, derived quantities and factories, it registers in
   :mod:`acroplan.core.sweep_hooks`.)
7. ``examples``: the bundled problems, ``{name: Example}``; ``commands``: extra command-line
   commands, ``{name: "module:function"}``.
8. ``draw(folder, solution, gif, strobe, mp4, *, speed, fps, load) -> int`` (optional): write the
   animation (``gif``, and ``mp4`` when not ``None`` and ffmpeg is there) and the strobe figure of
   the motion an output folder holds (``solution``: its ``solution.json``; ``load()``: the
   :class:`~acroplan.core.result.PlanResult` it records); returns the number of frames.
   ``animate(result, path, **kw) -> int`` (optional): the animation of a result
   (:meth:`PlanResult.animate <acroplan.core.result.PlanResult.animate>`); ``view(result, path,
   samples=None, **kw) -> path`` (optional): an interactive 3-D view in the browser, one HTML page
   (:meth:`PlanResult.view <acroplan.core.result.PlanResult.view>`, ``acroplan view``; ``samples``:
   an output folder's sampled states, ``(t, X)``); with ``path=None`` the figure itself (shown
   inline in a notebook).
9. ``cli_verify`` (str or None): the check the command line asks for (``"ode"``: the DOP853
   re-simulation, which the acrobot affords at any size); ``None``: the family's own check where
   it has one.
10. ``torque_hint`` (``(problem, fix)`` or None): what to tell a user whose body of this family
    gives no torques (the acrobot given by its lumped parameters).
11. ``describe(system) -> str`` (optional): one line saying what the body is, for the command
    line's summaries.
12. ``check_request(request)`` (optional): refuse, with an
    :class:`~acroplan.core.errors.InvalidInputError` naming the field, a valid
    :class:`~acroplan.planning.PlanRequest` that the family's planners cannot take (called at the
    end of :meth:`PlanRequest.build <acroplan.planning.PlanRequest.build>`: the boundary).
13. ``compile_seconds(system, n) -> (float, str) or None`` (optional): a lower bound of the seconds
    a first compilation of the system's integrator with ``n`` coefficients per input takes, and the
    measured growth it comes from in words (``benchmarks/RESULTS.md``); a plan whose time limit it
    exceeds is refused up front, unless that integrator was compiled before on this machine
    (:func:`acroplan.core.backend.compile_estimate`).
14. ``twist_potential(problem, plan, *, flight_times, somersaults, resolution, time_limit,
    progress, simulate) -> list`` (optional): the coach's question in 3-D, the most twist the
    problem's body can make in each flight time and number of somersaults (``acroplan
    twist-potential``); each cell has ``to_dict()`` and says where it stopped and why
    (``"proven"`` by an exact test, or ``"planner stopped"``); ``plan`` and ``simulate`` are
    :func:`acroplan.plan` and :func:`acroplan.simulate`, passed in since a family does not import
    the front doors. ``twist_potential_figure(cells) -> Figure``: its figure.
15. ``attitude_angles(result, t) -> {name: array}`` (optional): the angles a user reads the
    attitude in, at the times ``t`` (a body in 3-D: Yeadon's ``somersault_turns``, ``tilt_deg``,
    ``twist_turns``, unwrapped from 0 at the start); ``acroplan simulate`` writes them
    (``angles.csv``) and reports them at the end.

A family's descriptor module (``family.py``) should be light: the command line imports every
registered one to list the bundled examples, and ``acroplan examples`` imports no numerics (a test
counts the modules). Hooks that need the family's numerics are given as :func:`hook`
(``hook("package.problem:read")``: the module is imported on the first call), or as functions
that import inside.

Worked examples: ``acroplan/families/small/family.py`` (the unicycle and the chained form: a
name, the classes, nothing else) and ``acroplan/families/planar/family.py`` (link tables and URDF,
the reach bound, drawings, examples).
"""

from __future__ import annotations

import dataclasses
import importlib
import sys
import threading
from pathlib import Path
from typing import Any, Callable, Mapping

__all__ = ["Family", "Example", "ReadContext", "lazy_package", "register_family", "families", "family_of", "family_named",
           "reader_for", "hook", "prepare", "prepare_all", "system_classes", "ENTRY_POINT_GROUP"]

#: The entry point group a family is registered under.
ENTRY_POINT_GROUP = "acroplan.families"


@dataclasses.dataclass(frozen=True)
class Example:
    """A bundled problem: its file (inside the package: ``package`` and ``resource``), what it
    shows (one line), the command that runs it (``"plan"``, ``"simulate"``, ``"nilpotent"``) and
    files it needs beside it (a URDF)."""

    package: str
    resource: str
    description: str
    command: str = "plan"
    companions: tuple[str, ...] = ()
    extra: str | None = None  # the pip extra it needs, if any


@dataclasses.dataclass(frozen=True)
class ReadContext:
    """What a family's reader knows of the file: its folder (relative paths are read from it;
    ``None``: the current folder), whether ``options.degrees`` is set, and the folders outside it
    that the user allowed (absolute and resolved: ``--allow-outside``, ``[files] allow``). A family
    opens the files a table names through :meth:`file`, never directly."""

    base: Path | None = None
    degrees: bool = False
    allowed: tuple[Path, ...] = ()

    def file(self, field: str, value, *, example: str, what: str, most_bytes: int | None = None) -> Path:
        """The file ``value`` names, confined to :attr:`base` and :attr:`allowed`
        (:func:`acroplan.core.files.confined_file`: a path leading out is refused, naming ``field``
        and the options that allow it)."""
        from .files import confined_file
        from .validate import MAX_FILE_BYTES

        return confined_file(field, value, self.base, self.allowed, example=example, what=what,
                             most_bytes=MAX_FILE_BYTES if most_bytes is None else most_bytes)


@dataclasses.dataclass(frozen=True)
class Hook:
    """A family's hook by name (``"package.module:function"``): the module is imported on the first
    call, so a family's descriptor names its numerics without importing them (:func:`hook`)."""

    target: str

    def resolve(self) -> Callable:
        """The function named."""
        module, _, attr = self.target.partition(":")
        return getattr(importlib.import_module(module), attr)

    def __call__(self, *args, **kwargs):
        return self.resolve()(*args, **kwargs)


def hook(target: str) -> Hook:
    """A hook of a :class:`Family` given by name, ``"package.module:function"``, imported on its first
    call (:class:`Hook`)."""
    if ":" not in target:
        raise ValueError(f"a hook is named 'package.module:function', got {target!r}")
    return Hook(target)


def _type_name(cls: type) -> str:
    return f"{cls.__module__}:{cls.__qualname__}"


def _resolve_type(spec) -> type:
    if isinstance(spec, type):
        return spec
    module, _, attr = spec.partition(":")
    return getattr(importlib.import_module(module), attr)


@dataclasses.dataclass(frozen=True)
class Family:
    """A body family's contract with the I/O layer and the front doors (module docstring)."""

    name: str
    system_types: tuple[type, ...]
    priority: int = 0
    tables: tuple[str, ...] = ()
    reads: Callable[[str, Mapping], bool] | None = None
    read: Callable[..., tuple[Any, dict]] | None = None
    table_keys: tuple[str, ...] = ()
    waypoints: Callable[..., dict] | None = None
    waypoint_keys: tuple[str, ...] = ()
    waypoint_states: tuple[str, ...] = ()
    reach: Callable[[Any], list] | None = None
    reach_figure: Callable[[Any, list], Any] | None = None
    two_link: Callable[[Any], tuple] | None = None
    least_momentum: Callable[..., Any] | None = None
    somersault_table: Callable[..., Any] | None = None
    examples: Mapping[str, Example] = dataclasses.field(default_factory=dict)
    commands: Mapping[str, str] = dataclasses.field(default_factory=dict)
    draw: Callable[..., int] | None = None
    animate: Callable[..., int] | None = None
    view: Callable[..., Any] | None = None
    limits_in_body: bool = False
    cli_verify: str | None = None
    torque_hint: tuple[str, str] | None = None
    describe: Callable[[Any], str] | None = None
    check_request: Callable[[Any], None] | None = None
    compile_seconds: Callable[[Any, int], tuple[float, str] | None] | None = None
    twist_potential: Callable[..., list] | None = None
    twist_potential_figure: Callable[[list], Any] | None = None
    attitude_angles: Callable[..., dict] | None = None
    setup: tuple[str, ...] = ()

    def owns(self, system) -> bool:
        """Whether ``system`` (an instance) is of this family."""
        return any(self._owns_class(base) for base in type(system).__mro__)

    def _owns_class(self, cls: type) -> bool:
        """Whether ``cls`` itself is one of :attr:`system_types` (names compared: nothing imported)."""
        name = _type_name(cls)
        return any(t is cls if isinstance(t, type) else t == name for t in self.system_types)

    def type_names(self) -> tuple[str, ...]:
        """The class names of :attr:`system_types` (what a result file's ``system.type`` records),
        nothing imported."""
        return tuple(t.__name__ if isinstance(t, type) else t.rpartition(":")[2].rpartition(".")[2]
                     for t in self.system_types)

    def classes(self) -> tuple[type, ...]:
        """The classes of :attr:`system_types`, those given by name imported."""
        return tuple(_resolve_type(t) for t in self.system_types)


_FAMILIES: dict[str, Family] = {}
_LOADED = False
_LOCK = threading.RLock()
#: :func:`families`' order and :func:`family_of`'s answers, kept until a family is registered (every
#: plan asks both; with them kept, a two-link plan's validation took 0.106 ms at the median against
#: 0.148 before, `benchmarks/plan_overhead.py --parts`, one noisy run each: benchmarks/RESULTS.md)
_ORDER: tuple[Family, ...] | None = None
_OWNER: dict[type, Family | None] = {}
_GENERATION = 0  # (how many times they were dropped: an answer found meanwhile is not kept)


def register_family(family: Family, *, replace: bool = False) -> Family:
    """Register ``family`` (by its name). Registering the same name again needs ``replace=True``,
    unless it is the same object (a module imported twice)."""
    from .errors import InvalidInputError

    if not isinstance(family, Family):
        raise InvalidInputError("family", f"must be an acroplan.core.family.Family, got {type(family).__name__}",
                                "build one with Family(name=..., system_types=(...))")
    with _LOCK:
        old = _FAMILIES.get(family.name)
        if old is not None and old is not family and not replace and old != family:
            raise InvalidInputError("family", f"the name {family.name!r} is taken", "give another name, or "
                                    "replace=True to replace it")
        _FAMILIES[family.name] = family
        _forget()
    return family


def _forget() -> None:
    """Drop the cached order and owners (a family was registered)."""
    global _ORDER, _GENERATION
    _ORDER = None
    _OWNER.clear()
    _GENERATION += 1


def _load_entry_points() -> None:
    global _LOADED
    if _LOADED:
        return
    with _LOCK:
        if _LOADED:
            return
        from importlib.metadata import entry_points

        for ep in sorted(entry_points(group=ENTRY_POINT_GROUP), key=lambda e: e.name):
            module, _, attr = ep.value.partition(":")
            fam = getattr(importlib.import_module(module), attr or "FAMILY")
            if fam.name not in _FAMILIES:
                register_family(fam)
        _LOADED = True


def families() -> tuple[Family, ...]:
    """Every registered family, highest ``priority`` first (then by name)."""
    global _ORDER
    _load_entry_points()
    order = _ORDER
    if order is None:
        with _LOCK:
            order = _ORDER = tuple(sorted(_FAMILIES.values(), key=lambda f: (-f.priority, f.name)))
    return order


def family_named(name: str) -> Family:
    """The family registered as ``name``."""
    from .errors import InvalidInputError

    _load_entry_points()
    if name not in _FAMILIES:
        raise InvalidInputError("family", f"no family is registered as {name!r}",
                                f"registered: {sorted(_FAMILIES)}")
    return _FAMILIES[name]


def family_of(system) -> Family | None:
    """The family of ``system`` (an instance or a class): the first family owning a class along its
    MRO; ``None`` for a system of no registered family (a user's own class)."""
    _load_entry_points()
    cls = system if isinstance(system, type) else type(system)
    try:
        return _OWNER[cls]
    except KeyError:
        pass
    found, generation = None, _GENERATION
    ordered = families()
    for base in cls.__mro__:
        found = next((fam for fam in ordered if fam._owns_class(base)), None)
        if found is not None:
            break
    with _LOCK:
        if generation == _GENERATION:
            _OWNER[cls] = found
    return found


_PREPARED_FAMILIES: set[str] = set()
_PREPARED_TYPES: set[type] = set()


def _prepare_family(fam: Family) -> None:
    if fam.name in _PREPARED_FAMILIES:
        return
    for module in fam.setup:
        importlib.import_module(module)
    _PREPARED_FAMILIES.add(fam.name)


def prepare(system) -> None:
    """Import the :attr:`Family.setup` modules of ``system``'s family (an instance or a class), once:
    what registers its strategies, torque model, optimal starts and sweep hooks. Called by the
    front doors and by the registries' look-ups; about a microsecond once done."""
    cls = system if isinstance(system, type) else type(system)
    if cls in _PREPARED_TYPES:
        return
    fam = family_of(cls)
    if fam is not None:
        _prepare_family(fam)
    _PREPARED_TYPES.add(cls)


def lazy_package(package: str, names: Mapping[str, str]):
    """A family package's ``__getattr__`` and ``__dir__`` (PEP 562): each public name of ``names``
    (name -> module of the package) is imported on its first use, and with it the family's
    :attr:`Family.setup` modules (its ``family.py`` ``FAMILY``), so that importing the package, or
    its light descriptor, imports no numerics.

    Examples
    --------
    In a family's ``__init__.py``::

        _NAMES = {"PlanarBody": "model", "read_urdf": "urdf"}
        __all__ = list(_NAMES)
        __getattr__, __dir__ = lazy_package(__name__, _NAMES)
    """
    module = sys.modules[package]

    def __getattr__(name: str):
        if name not in names:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{names[name]}"), name)
        try:
            fam = importlib.import_module(f"{package}.family").FAMILY
        except ModuleNotFoundError as e:  # a package that registers no family
            if e.name != f"{package}.family":
                raise
            fam = None
        if fam is not None:
            for setup in fam.setup:  # what the family registers (prepare)
                importlib.import_module(setup)
        setattr(module, name, value)
        return value

    def __dir__():
        return sorted(set(vars(module)) | set(names))

    return __getattr__, __dir__


def prepare_all() -> None:
    """:func:`prepare` every registered family (what a look-up by name needs: a sweep's derived
    quantity or factory)."""
    for fam in families():
        _prepare_family(fam)


def registered_class(name: str) -> type | None:
    """The registered family's system class named ``name`` (imported), or ``None``: what a record's
    ``system.type`` names, before any other class of the same name (a user's, defined in a notebook
    before the family's class was first imported)."""
    for fam in families():
        if name in fam.type_names():
            for cls in fam.classes():
                if cls.__name__ == name:
                    return cls
    return None


def system_classes() -> dict[str, type]:
    """Every registered family's system classes by class name, imported (what reading a result
    file's ``system.type`` needs)."""
    out: dict[str, type] = {}
    for fam in families():
        for cls in fam.classes():
            out.setdefault(cls.__name__, cls)
    return out


def reader_for(table: str, data: Mapping) -> Family | None:
    """The family that reads the system table ``table`` (``"robot"``, ``"body"``) holding ``data``."""
    for fam in families():
        # a family that names its tables is not asked about another's (asking imports its reader)
        if fam.tables and table not in fam.tables:
            continue
        if fam.read is not None and fam.reads is not None and fam.reads(table, data):
            return fam
    return None
