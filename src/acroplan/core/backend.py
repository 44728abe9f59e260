"""The compiled integrator back end (heyoka): endpoint map, its Jacobian, dense samples.

A family may bring its own endpoint map (:meth:`ControlAffineSystem.endpoint_map`: the spatial
bodies integrate their attitude alone by Gauss collocation, some 10-30 times faster);
:func:`endpoint` uses it when there is one, and the Taylor integrator below otherwise
(:func:`taylor_endpoint` always).

One segment is integrated in normalised time :math:`s \\in [0, 1]`:

.. math::  \\frac{dx}{ds} = T\\,\\Big(f(x;p) + \\sum_j g_j(x;p)\\, u_j(s)\\Big),\\qquad
           u_j(s) = \\sum_i c_{j,i}\\, b_i(s),

together with the first-order variational equations with respect to the coefficients
(text eq. 4-6), so that one integration gives :math:`\\Phi(c) = x(1)` and
:math:`D\\Phi(c) = \\partial x(1)/\\partial c`.
A simulation and a dense sample need no Jacobian: they use a second integrator of the state
equation alone (:func:`compile_fields`), compiled once per key as the first is.

Runtime parameters, in order: the system's parameters, ``T``, then the coefficients ``c`` flattened
input-major (``c[j, i]`` at ``n_p + 1 + j*n + i``). A compiled integrator is therefore shared by
every system of one structure (:attr:`ControlAffineSystem.structure_key`), every segment length and
every coefficient value; it is compiled once per process per (structure key, basis family, basis
size) and cached.

On-disk cache: heyoka keeps compiled code in ``~/.cache/heyoka`` (its default; about 65 MB after
acroplan's test suite, capped by heyoka at 20 GB). The environment variable
``ACROPLAN_HEYOKA_CACHE`` moves it (a folder path) or turns it off (``off``: nothing is written, and
each new process compiles anew: about a second of processor time per structure and basis size for
the acrobot, benchmarks/RESULTS.md "Compile time"); it is read when this module is first imported.
The functions of :func:`compile_once` (a spatial body's momentum maps and torques) are also kept,
whole, in its folder ``acroplan-compiled`` (:func:`_stored_or_built`, at most :data:`STORE_LIMIT`).

Threads: the compiled integrator is a template; each thread works on its own copy (a copy costs
about a millisecond, a compilation a second or more), so threads never wait on each other and never
share an integrator's state. Processes compile on first use (heyoka also keeps compiled code in an
on-disk cache, ``~/.cache/heyoka`` by default), so workers of any executor work without ``fork``.
"""

from __future__ import annotations

import copy
import functools
import hashlib
import threading
from pathlib import Path
from typing import Hashable, NamedTuple

import numpy as np

from . import budget
from . import progress as progress_mod
from .basis import InputBasis
from .heyoka_import import from_sympy, heyoka as _heyoka
from .system import ControlAffineSystem

hy = _heyoka()  # (the command line's: without sympy, acroplan.core.heyoka_import)

__all__ = ["IntegrationError", "heyoka_fields", "endpoint", "state_endpoint", "taylor_endpoint", "reference_endpoint", "sample",
           "taylor_sample", "compile_for", "compile_fields", "compile_once", "compiled_before", "compiled_count", "compile_estimate", "CompileEstimate",
           "evaluate_columns"]

#: Taylor integrator tolerance: machine precision for double.
TOL = 1e-15


def _configure_disk_cache() -> None:
    import os

    where = os.environ.get("ACROPLAN_HEYOKA_CACHE", "").strip()
    if not where:
        return
    if where.lower() in ("off", "0", "false", "no"):
        hy.llvm_state.set_diskcache_enabled(False)
    else:
        os.makedirs(where, exist_ok=True)
        hy.llvm_state.set_diskcache_path(where)


_configure_disk_cache()


class IntegrationError(RuntimeError):
    """The compiled integrator did not reach the end of the segment (non-finite state)."""


_TEMPLATES: dict[tuple, hy.taylor_adaptive] = {}
_BUILD_LOCK = threading.Lock()
_LOCAL = threading.local()


def heyoka_fields(system: ControlAffineSystem, basis: InputBasis):
    """The segment's state equation as heyoka expressions, in normalised time :math:`s \\in [0, 1]`:
    :math:`x' = T\\,(f(x) + G(x)\\,u(s))`, the input :math:`u_j(s) = \\sum_i c_{ji} V_i(s)` in ``basis``.
    Runtime parameters, in order: the system's parameters, :math:`T`, then the coefficients row by
    row.

    Returns
    -------
    sys : list of (variable, expression)
        The system, one pair per state.
    coeffs : list of list
        The coefficients' parameters, shape (m, basis.n).
    """
    n_x, m, n_p, n = system.n_states, system.n_inputs, len(system.param_names), basis.n
    hx = hy.make_vars(*system.state_names)
    if n_x == 1:
        hx = [hx]
    fe, Ge = _field_expressions(system, hx)
    coeffs = [[hy.par[n_p + 1 + j * n + i] for i in range(n)] for j in range(m)]
    u = [basis.expression(hy.time, coeffs[j]) for j in range(m)]
    rhs = []
    for r in range(n_x):
        e = fe[r] if fe[r] is not None else 0.0 * hx[0]
        for j in range(m):
            if Ge[r][j] is not None:
                e = e + Ge[r][j] * u[j]
        rhs.append(hy.par[n_p] * e)
    return list(zip(hx, rhs)), coeffs


def _field_expressions(system: ControlAffineSystem, hx):
    """``(f, G)`` as heyoka expressions (``None`` where zero): the system's own
    (:meth:`~acroplan.core.system.ControlAffineSystem.taylor_fields`), else its sympy fields converted."""
    params = [hy.par[i] for i in range(len(system.param_names))]
    direct = system.taylor_fields(tuple(hx), tuple(params))
    if direct is not None:
        return direct
    x_sym, p_sym = system.symbols()
    f, G = system.symbolic()
    s_dict = {sym: var for sym, var in zip(x_sym, hx)}
    s_dict.update(zip(p_sym, params))
    fe = [from_sympy(f[r], s_dict) if f[r] != 0 else None for r in range(G.shape[0])]
    Ge = [[from_sympy(G[r, j], s_dict) if G[r, j] != 0 else None for j in range(G.shape[1])]
          for r in range(G.shape[0])]
    return fe, Ge


def _build(system: ControlAffineSystem, basis_cls: type[InputBasis], n: int, variational: bool = True):
    """The Taylor integrator of the segment's state equation, with its variational equations in the
    coefficients (``variational``) or alone: what a simulation and a dense sample need, whose
    compilation is some 5-15 times cheaper (a 4-link planar body at 14 coefficients: 1.3 s against
    18.6 s cold) and does not grow with the number of coefficients as the variational one does."""
    sys, coeffs = heyoka_fields(system, basis_cls(n))
    n_x, m, n_p = len(sys), len(coeffs), len(system.param_names)
    if variational:
        sys = hy.var_ode_sys(sys, [c for row in coeffs for c in row], order=1)
    return hy.taylor_adaptive(sys, [0.0] * n_x, tol=TOL, pars=[0.0] * (n_p + 1 + m * n),
                              compact_mode=bool(system.compact_mode))


def _key(system: ControlAffineSystem, basis_cls: type[InputBasis], n: int) -> tuple[Hashable, type, int]:
    return (system.structure_key, basis_cls, int(n))


class _Build:
    """One compilation under way (in its own thread), which any number of callers wait for."""

    def __init__(self):
        self.done = threading.Event()
        self.error: BaseException | None = None


_PENDING: dict[tuple, _Build] = {}


def _run(job: _Build, key, build, done: dict, pending: dict) -> None:
    try:
        out = build()
        with _BUILD_LOCK:
            done[key] = out
        _mark_compiled(key)
    except BaseException as e:  # noqa: BLE001 - handed to the callers waiting for it
        job.error = e
    finally:
        with _BUILD_LOCK:
            pending.pop(key, None)
        job.done.set()


def _compiled(key, build, done: dict, pending: dict, name: str, what: str = ""):
    """``done[key]``, made by ``build()`` once: in a thread of its own (``pending`` holds it while
    it runs), which every caller waits for within its time budget (``what``: the progress stage's
    detail)."""
    if key in done:
        return done[key]
    with _BUILD_LOCK:
        if key in done:
            return done[key]
        job = pending.get(key)
        if job is None:
            job = pending[key] = _Build()
            threading.Thread(target=_run, args=(job, key, build, done, pending), daemon=True,
                             name=f"acroplan-compile-{name}").start()
    # the stage "compiling" of the active progress while the caller waits (a first compilation:
    # seconds to minutes; from heyoka's disk cache, a fraction of a second, too short to be shown)
    prog = progress_mod.current()
    st = prog.stage("compiling", unit="step", leave=False) if prog is not None else None
    if st is not None:
        st.set(0, detail=what)
    try:
        budget.wait(job.done)
    finally:
        if st is not None:
            st.close()
    if job.error is not None:
        raise job.error
    return done[key]


def compile_for(system: ControlAffineSystem, basis_cls: type[InputBasis], n: int):
    """The compiled template for (structure of ``system``, basis family, size ``n``): built on first
    use in this process, then reused.

    The compilation (sympy fields, heyoka's decomposition and LLVM, which nothing can interrupt) runs
    in a thread of its own while the caller waits within its time budget
    (:func:`acroplan.core.budget.wait`): a plan whose budget is spent while it compiles ends with
    :class:`~acroplan.core.budget.BudgetExceeded` at its deadline; the compilation goes on in the
    background and its integrator is kept for the next plan. One compilation per key, however many
    threads ask."""
    return _compiled(_key(system, basis_cls, n), lambda: _build(system, basis_cls, n), _TEMPLATES, _PENDING, str(n),
                     f"integrator, {n} coefficients")


_FIELDS: dict[tuple, hy.taylor_adaptive] = {}
_FIELDS_PENDING: dict[tuple, _Build] = {}


def compile_fields(system: ControlAffineSystem, basis_cls: type[InputBasis], n: int):
    """The compiled template of the state equation alone for (structure of ``system``, basis
    family, size ``n``) (:func:`_build`), compiled and waited for as :func:`compile_for`'s."""
    return _compiled(("fields",) + _key(system, basis_cls, n), lambda: _build(system, basis_cls, n, variational=False),
                     _FIELDS, _FIELDS_PENDING, f"fields-{n}", f"integrator of the states, {n} coefficients")


_ONCE: dict[Hashable, object] = {}
_ONCE_PENDING: dict[Hashable, _Build] = {}


def compile_once(key: tuple, build):
    """``build()`` (a compilation: a ``heyoka.cfunc`` a family compiles, say) once per ``key`` in
    this process, as :func:`compile_for` compiles an integrator: in a thread of its own, waited for
    within the caller's time budget (:class:`~acroplan.core.budget.BudgetExceeded` at its deadline,
    the compilation going on in the background and kept for the next caller), one compilation
    however many threads ask; once done it is marked on this machine (:func:`compiled_before`).
    ``key``: a tuple of hashable values whose ``repr`` is the same in every process.

    A ``heyoka.cfunc`` it builds is also kept on disk (:func:`_stored`, beside heyoka's own cache) and
    read back by the next process instead of being built again: heyoka's disk cache saves the LLVM
    compilation, not the decomposition and code generation before it (0.1-0.7 s a function of the
    bundled cat, against 0.03-0.07 s to read it back)."""
    return _compiled(key, lambda: _stored_or_built(key, build), _ONCE, _ONCE_PENDING, str(key[0]), str(key[0])[:40])


_FINGERPRINT: list[str] = []


def _fingerprint() -> str:
    """What a stored compiled function depends on besides its key: heyoka's version, this machine's
    processor (compiled code is for its instruction set), and acroplan's own source (the code that
    writes the expressions), hashed once per process (some 15 ms)."""
    if not _FINGERPRINT:
        import platform

        h = hashlib.sha256(f"heyoka {hy.__version__}|{platform.machine()}".encode())
        try:
            with open("/proc/cpuinfo", "rb") as f:
                h.update(next((line for line in f if line.startswith(b"flags")), b""))
        except OSError:
            h.update(platform.processor().encode())
        root = Path(__file__).resolve().parent.parent
        for path in sorted(root.rglob("*.py")):
            h.update(path.relative_to(root).as_posix().encode())
            h.update(path.read_bytes())
        _FINGERPRINT.append(h.hexdigest())
    return _FINGERPRINT[0]


def _stored(key) -> Path | None:
    """The file holding ``key``'s compiled function (:func:`compile_once`), in the folder of the
    markers (:func:`_marker`); ``None`` without heyoka's disk cache."""
    marker = _marker(key)
    if marker is None:
        return None
    text = f"{key!r}|{_fingerprint()}"
    return marker.parent / f"{hashlib.sha256(text.encode()).hexdigest()[:32]}.cfunc"


def _stored_or_built(key, build):
    """``key``'s compiled function read from :func:`_stored`, or ``build()`` and, when it is a
    ``heyoka.cfunc``, stored there (written to a temporary file, then renamed: a reader never sees
    half a file). The folder is the user's own, as heyoka's cache beside it, whose compiled code heyoka
    loads as well; a file that cannot be read is built anew."""
    import os
    import pickle

    path = _stored(key)
    if path is not None and path.exists():
        try:
            with open(path, "rb") as f:
                out = pickle.load(f)
            try:
                os.utime(path)  # used: the last to go when the store is trimmed
            except OSError:
                pass
            return out
        except Exception:  # noqa: BLE001 - unreadable or stale: built again below
            pass
    out = build()
    if path is not None and type(out).__module__.startswith("heyoka") and type(out).__name__.startswith("cfunc"):
        tmp = path.with_name(f"{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            with open(tmp, "wb") as f:
                pickle.dump(out, f, protocol=pickle.HIGHEST_PROTOCOL)
            os.replace(tmp, path)
            _trim(path.parent)
        except Exception:  # noqa: BLE001 - a read-only or full cache: built again next time
            try:
                tmp.unlink()
            except OSError:
                pass
    return out


#: The most bytes of compiled functions :func:`_stored_or_built` keeps (0.7-4 MB a function: a
#: topology's two momentum maps and its torques some 3-7 MB); the least recently used go first.
STORE_LIMIT = 512 * 2**20


def _trim(folder: Path, limit: int | None = None) -> None:
    """Remove the least recently used stored functions of ``folder`` until they fit in ``limit``
    bytes (:data:`STORE_LIMIT`): a fuzz of thousands of random topologies, or every edit of
    acroplan's source, writes new ones."""
    limit = STORE_LIMIT if limit is None else limit
    files = []
    for f in folder.glob("*.cfunc"):
        try:
            st = f.stat()
        except OSError:
            continue
        files.append((st.st_mtime, st.st_size, f))
    total = sum(size for _, size, _ in files)
    for _, size, f in sorted(files, key=lambda e: e[0]):
        if total <= limit:
            break
        try:
            f.unlink()
            total -= size
        except OSError:
            pass


def compiled_before(key: tuple) -> bool:
    """Whether :func:`compile_once` compiled ``key`` in this process (or is compiling it), or on
    this machine before (heyoka keeps the code on disk: a second process builds it in seconds)."""
    if key in _ONCE or key in _ONCE_PENDING:
        return True
    marker = _marker(key)
    return marker is not None and marker.exists()


class CompileEstimate(NamedTuple):
    """A lower bound of a first compilation's seconds (:func:`compile_estimate`)."""

    seconds: float
    what: str  # the body, for messages ("a planar body of 12 links")
    growth: str  # the measured growth it comes from, for messages


def _marker(key) -> Path | None:
    """The file that says ``key`` was compiled on this machine (in heyoka's on-disk cache folder):
    an integrator's ``(structure key, basis class, size)``, or the key of :func:`compile_once`."""
    try:
        if not hy.llvm_state.get_diskcache_enabled():
            return None
        folder = Path(hy.llvm_state.get_diskcache_path()) / "acroplan-compiled"
    except Exception:  # noqa: BLE001 - no disk cache: no marker
        return None
    if len(key) == 3 and isinstance(key[1], type):
        structure, basis_cls, n = key
        text = f"{structure!r}|{basis_cls.__module__}.{basis_cls.__qualname__}|{n}|heyoka {hy.__version__}"
    else:
        text = f"{key!r}|heyoka {hy.__version__}"
    return folder / hashlib.sha256(text.encode()).hexdigest()[:32]


def _mark_compiled(key) -> None:
    path = _marker(key)
    if path is None:
        return
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.touch()
    except OSError:  # a read-only cache: the estimate stays the first run's
        pass


def compile_estimate(system: ControlAffineSystem, basis_cls: type[InputBasis], n: int) -> CompileEstimate | None:
    """A lower bound of the seconds compiling the integrator of ``system`` with ``n`` coefficients
    takes, from its family's measured growth (:attr:`Family.compile_seconds
    <acroplan.core.family.Family.compile_seconds>`); ``None`` when it is compiled in this process,
    under way, compiled before on this machine (heyoka keeps it on disk: seconds), or when the
    family gives no estimate."""
    key = _key(system, basis_cls, n)
    if key in _TEMPLATES or key in _PENDING:
        return None
    from .family import family_of

    fam = family_of(system)
    if fam is None or fam.compile_seconds is None:
        return None
    est = fam.compile_seconds(system, int(n))
    if est is None:
        return None
    marker = _marker(key)
    if marker is not None and marker.exists():
        return None
    seconds, growth = est
    what = fam.describe(system) if fam.describe is not None else type(system).__name__
    return CompileEstimate(float(seconds), what, growth)


@functools.lru_cache(maxsize=32)
def _repeated(params: tuple, n: int) -> np.ndarray:
    """The parameters repeated for ``n`` columns, C-contiguous (what ``heyoka.cfunc`` wants), read-only."""
    out = np.repeat(np.asarray(params, dtype=float)[:, None], n, axis=1)
    out.setflags(write=False)
    return out


def evaluate_columns(fn, x, params: tuple, chunk: int) -> np.ndarray:
    """A compiled function (a batch ``heyoka.cfunc``, :func:`compile_once`) at the columns of ``x``,
    with the same runtime parameters ``params`` for every column, ``chunk`` columns a call (the
    parameters' repeated array is cached per size).

    Parameters
    ----------
    fn : heyoka.cfunc
    x : numpy.ndarray, shape (fn's inputs, N), C-contiguous
    params : tuple of float
    chunk : int

    Returns
    -------
    numpy.ndarray, shape (fn.nouts, N)
    """
    n = x.shape[1]
    if n <= chunk:
        return fn(x, pars=_repeated(params, n))
    out = np.empty((fn.nouts, n))
    for a in range(0, n, chunk):
        b = min(n, a + chunk)
        out[:, a:b] = fn(np.ascontiguousarray(x[:, a:b]), pars=_repeated(params, b - a))
    return out


def compiled_count() -> int:
    """How many integrators this process has compiled (for tests and diagnostics)."""
    return len(_TEMPLATES)


def _integrator(system, basis, fields_only: bool = False):
    """This thread's copy of the compiled integrator (``fields_only``: of the state equation alone,
    :func:`compile_fields`), with views on its state and parameters."""
    key = _key(system, type(basis), basis.n)
    if fields_only:
        key = ("fields",) + key
    mine = getattr(_LOCAL, "integrators", None)
    if mine is None:
        mine = _LOCAL.integrators = {}
    entry = mine.get(key)
    if entry is None:
        make = compile_fields if fields_only else compile_for
        ta = copy.copy(make(system, type(basis), basis.n))
        # the state and parameter arrays are views on the integrator's memory: bound once
        entry = mine[key] = (ta, ta.state, ta.pars, len(system.param_names))
    return entry


_TIME_LIMIT = hy.taylor_outcome.time_limit
#: The most Taylor steps one segment's integration may take. A step covers roughly a quarter
#: radian of the fastest angle, so this is some 25,000 rad of travel in one segment (an input of
#: 10,000 rad/s for 2.5 s): far beyond any motion a body makes, and at most about 0.6 s of
#: integration. Solvers that stray to absurd coefficients (a line search) get an
#: :class:`IntegrationError` instead of minutes of stepping that no time limit could interrupt.
MAX_STEPS = 100_000


def _load(system, basis, x0, T, c, fields_only: bool = False):
    """This thread's integrator for (system, basis), reset to ``x0`` with the runtime parameters
    set. Returns (integrator, its state view, number of states)."""
    ta, state, pars, n_p = _integrator(system, basis, fields_only)
    n_x = system.n_states
    ta.time = 0.0
    state[:] = 0.0
    state[:n_x] = x0
    pars[:n_p] = system._param_tuple
    pars[n_p] = T
    pars[n_p + 1:] = np.ravel(c)
    return ta, state, n_x


def _why(outcome, s: float) -> str:
    if outcome == hy.taylor_outcome.step_limit:
        return (f"the input is too large to integrate: more than {MAX_STEPS} steps on one segment "
                f"(stopped at s = {s:.3g})")
    return f"integration stopped with outcome {outcome} at s = {s}"


class perturbations_of:
    """A context in which this thread's endpoint evaluations are at inputs a small perturbation away
    from ``c`` (the forward differences of :meth:`OptimalProblem.curvature
    <acroplan.core.optimum.OptimalProblem.curvature>`): a family's endpoint map may then reuse the
    discretisation it chose at ``c`` (its panels, its solution as the start of its iterations), so
    that the differences are those of one discrete map, and cheaper. A family that does not look
    (:func:`near_point`) integrates as always."""

    def __init__(self, system, basis, x0, T, c):
        self.point = (system, basis, np.asarray(x0, dtype=float).tobytes(), float(T),
                      np.asarray(c, dtype=float).reshape(-1).copy(), {})

    def __enter__(self):
        self.previous = getattr(_LOCAL, "near", None)
        _LOCAL.near = self.point
        return self

    def __exit__(self, *exc):
        _LOCAL.near = self.previous
        return False


def near_point():
    """``(system, basis, x0 bytes, T, c, memo)`` of the enclosing :class:`perturbations_of`, or
    ``None``; ``memo`` a dict the family may keep its discretisation at ``c`` in."""
    return getattr(_LOCAL, "near", None)


def endpoint(system: ControlAffineSystem, basis: InputBasis, x0, T: float, c) -> tuple[np.ndarray, np.ndarray]:
    """The endpoint map and its Jacobian on one segment: the family's own
    (:meth:`ControlAffineSystem.endpoint_map`, the spatial bodies') when it has one, else
    :func:`taylor_endpoint`.

    Parameters
    ----------
    system : ControlAffineSystem
    basis : InputBasis
    x0 : array_like, shape (n,)
        State at the segment start.
    T : float
        Segment duration (> 0).
    c : array_like, shape (m, basis.n) or (m * basis.n,)
        Input coefficients.

    Returns
    -------
    xT : numpy.ndarray, shape (n,)
    J : numpy.ndarray, shape (n, m * basis.n)
        :math:`\\partial x(T) / \\partial c`, columns in flattened ``c`` order.
    """
    budget.check()
    own = system.endpoint_map(basis, x0, T, c)
    if own is not None:
        return own
    return _taylor(system, basis, x0, T, c)


def state_endpoint(system: ControlAffineSystem, basis: InputBasis, x0, T: float, c) -> np.ndarray:
    """:math:`x(T)` alone, for a simulation (:func:`acroplan.simulate`): the family's own endpoint
    map when it has one (its state, the Jacobian dropped), else the Taylor integrator of the state
    equation alone (:func:`compile_fields`; no variational equations to compile or integrate).

    Returns
    -------
    numpy.ndarray, shape (n,)
    """
    budget.check()
    own = system.endpoint_map(basis, x0, T, c)
    if own is not None:
        return own[0]
    ta, state, _ = _load(system, basis, x0, T, c, fields_only=True)
    return _propagated(ta, state)


def taylor_endpoint(system: ControlAffineSystem, basis: InputBasis, x0, T: float, c) -> tuple[np.ndarray, np.ndarray]:
    """:func:`endpoint` by the compiled Taylor integrator whatever the system (the fields and
    their variational equations in the coefficients, one ``propagate_until``): the reference the
    families' own maps are checked against."""
    budget.check()
    return _taylor(system, basis, x0, T, c)


_REFERENCE: dict[tuple, hy.taylor_adaptive] = {}


def reference_endpoint(system: ControlAffineSystem, basis: InputBasis, x0, T: float, c, *,
                       tol: float = 1e-19) -> np.ndarray:
    """:math:`x(T)` by the Taylor integrator of the fields alone (no variational equations) in
    extended precision (``long double``, tolerance ``tol``): a tight reference for checks and
    benchmarks, some thousand times more exact than the double-precision maps. Compiled on first
    use per (structure, basis family, size), in compact mode; not thread-safe (one integrator per
    key).

    Returns
    -------
    numpy.ndarray, shape (n,)
    """
    key = (system.structure_key, type(basis), basis.n, float(tol))
    ta = _REFERENCE.get(key)
    if ta is None:
        sys, coeffs = heyoka_fields(system, basis)
        n_x, m, n_p = len(sys), len(coeffs), len(system.param_names)
        ld = np.longdouble
        ta = hy.taylor_adaptive(sys, np.zeros(n_x, dtype=ld), tol=ld(tol), compact_mode=True,
                                fp_type=ld, pars=np.zeros(n_p + 1 + m * basis.n, dtype=ld))
        _REFERENCE[key] = ta
    n_p = len(system.param_names)
    ta.time = np.longdouble(0.0)
    ta.state[:] = np.asarray(x0, dtype=np.longdouble)
    ta.pars[:n_p] = np.asarray(system._param_tuple, dtype=np.longdouble)
    ta.pars[n_p] = T
    ta.pars[n_p + 1:] = np.ravel(np.asarray(c, dtype=float))
    res = ta.propagate_until(np.longdouble(1.0), max_steps=MAX_STEPS)
    if res[0] != _TIME_LIMIT:
        raise IntegrationError(_why(res[0], float(ta.time)))
    return np.array(ta.state, dtype=float)


def _propagated(ta, state) -> np.ndarray:
    """A copy of the state of the loaded integrator ``ta`` (:func:`_load`) at :math:`s = 1`."""
    res = ta.propagate_until(1.0, max_steps=MAX_STEPS)
    out = state.copy()
    if res[0] != _TIME_LIMIT or not np.isfinite(out).all():
        raise IntegrationError(_why(res[0], ta.time))
    return out


def _taylor(system, basis, x0, T, c):
    ta, state, n_x = _load(system, basis, x0, T, c)
    out = _propagated(ta, state)
    return out[:n_x], out[n_x:].reshape(n_x, -1)


def sample(system: ControlAffineSystem, basis: InputBasis, x0, T: float, c, s) -> np.ndarray:
    """States at normalised times ``s`` (sorted, starting at 0) on one segment: the family's own
    (:meth:`ControlAffineSystem.sample_map`) when it has one, else the Taylor integrator's
    (``propagate_grid``).

    Returns
    -------
    numpy.ndarray, shape (n, len(s))
    """
    own = system.sample_map(basis, x0, T, c, s)
    if own is not None:
        return own
    return taylor_sample(system, basis, x0, T, c, s)


def taylor_sample(system: ControlAffineSystem, basis: InputBasis, x0, T: float, c, s) -> np.ndarray:
    """:func:`sample` by the compiled Taylor integrator of the state equation alone
    (:func:`compile_fields`) whatever the system."""
    s = np.asarray(s, dtype=float)
    ta, _, n_x = _load(system, basis, x0, T, c, fields_only=True)
    res = ta.propagate_grid(s, max_steps=MAX_STEPS)
    out = res[-1]
    if res[0] != _TIME_LIMIT or not np.isfinite(out).all():
        raise IntegrationError(_why(res[0], ta.time))
    return out[:, :n_x].T.copy()
