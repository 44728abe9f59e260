"""Atomic output folders: every path ends whole or untouched, and no litter stays behind.

An output folder ``OUT`` is written as a hidden temporary folder beside it and swapped in when
it is complete. The names used beside ``OUT`` (all in its parent, all hidden)::

    .OUT.acroplan.lock               the lock (fcntl.flock): one writer per OUT at a time
    .OUT.acroplan-PID-XXXXXXXX.tmp   the folder being written by process PID
    .OUT.acroplan-PID.old            the previous OUT, during the swap (fallback swap only)

A run goes:

1. :func:`check_out_dir` (no side effects): refuse a symbolic link, the current folder, one of
   its parents, the home folder, a filesystem root or mount point, a file, a non-empty folder
   without ``force``, a parent that is a file or cannot be written.
2. :class:`OutputFolder` (a context manager, entered BEFORE the work): creates the parent
   (removed again on failure if it was created and stays empty), takes the lock (non-blocking:
   another writer means :class:`InvalidInputError` "another acroplan run is writing to OUT"),
   repairs what a killed run left (below), then checks ``OUT`` again.
3. :meth:`OutputFolder.write` (or :func:`atomic_dir`): yields the temporary folder; on success
   it is exchanged with ``OUT`` in one step (``renameat2(RENAME_EXCHANGE)`` on Linux; elsewhere
   two renames, ``OUT`` -> ``.OUT.acroplan-PID.old`` then the temporary -> ``OUT``); on an
   exception the temporary folder is removed and ``OUT`` is untouched.

Repair after ``kill -9`` (on the next run into the same parent): a temporary folder whose
process is dead (``os.kill(pid, 0)``) is removed (a live process's never is); a ``.old`` of
a dead process whose ``OUT`` is missing (a crash between the two renames) is renamed back to
``OUT``, else removed (under that OUT's lock only); a lock file nobody holds is removed.
"""

from __future__ import annotations

import ctypes
import errno
import os
import re
import shutil
import sys
import tempfile
import threading
import time
from contextlib import contextmanager
from pathlib import Path

from ..core.errors import InvalidInputError

__all__ = ["check_out_dir", "atomic_dir", "OutputFolder", "check_entry_name", "sweep"]

_TMP_RE = re.compile(r"^\.(?P<name>.+)\.acroplan-(?P<pid>\d+)-[A-Za-z0-9_]+\.tmp$")
_OLD_RE = re.compile(r"^\.(?P<name>.+)\.acroplan-(?P<pid>\d+)\.old$")
_LOCK_RE = re.compile(r"^\.(?P<name>.+)\.acroplan\.lock$")

#: names an entry of a batch may not take (Windows devices; OUT/summary.csv is the summary)
_RESERVED = {"con", "prn", "aux", "nul", "clock$", "summary.csv",
             *(f"com{i}" for i in range(10)), *(f"lpt{i}" for i in range(10))}
_BAD_CHARS = set('<>:"|?*\\/') | {chr(c) for c in range(32)} | {"\x7f"}
MAX_NAME = 100


def _short(text) -> str:
    r = repr(str(text))
    return r if len(r) <= 80 else r[:76] + "...'"


# ----------------------------------------------------------------------------------- checks
def check_entry_name(field: str, name) -> str:
    """Refuse a batch entry's name that would not stay a plain folder inside OUT."""
    fix = "use letters, digits, '-', '_' and single dots, such as \"dive-1\""
    if not isinstance(name, str):
        raise InvalidInputError(field, f"must be a string, got {type(name).__name__}", fix)
    if not name.strip():
        raise InvalidInputError(field, "is empty", fix)
    if len(name) > MAX_NAME:
        raise InvalidInputError(field, f"is {len(name)} characters long, more than {MAX_NAME}", fix)
    if os.path.isabs(name) or any(sep and sep in name for sep in ("/", "\\", os.sep, os.altsep)):
        raise InvalidInputError(field, f"{_short(name)} is a path (absolute or with a separator), and would "
                                "be written outside --out", fix)
    if ".." in name:
        raise InvalidInputError(field, f"{_short(name)} contains '..'", fix)
    if name.startswith("."):
        raise InvalidInputError(field, f"{_short(name)} is a hidden name (starts with '.')", fix)
    if any(c in _BAD_CHARS for c in name):
        raise InvalidInputError(field, f"{_short(name)} contains a character that is not allowed in a "
                                "folder name (control characters or <>:\"|?*)", fix)
    if name != name.strip() or name.endswith("."):
        raise InvalidInputError(field, f"{_short(name)} starts or ends with a space or ends with a dot", fix)
    if name.lower() in _RESERVED or name.split(".")[0].lower() in _RESERVED:
        raise InvalidInputError(field, f"{_short(name)} is a reserved name", fix)
    return name


def _resolved(out: Path) -> Path:
    """``out`` absolute, its parents' links resolved, the last component kept as written."""
    try:
        out = Path(os.path.abspath(out))
        if out.name in ("", ".", ".."):
            return out.resolve()
        return out.parent.resolve() / out.name
    except (RuntimeError, OSError) as e:
        raise InvalidInputError("--out", f"{out} cannot be resolved ({e})", "give another folder") from None


def _unreplaceable(out: Path) -> str | None:
    """Why ``out`` can never be replaced by a rename, or None."""
    r = _resolved(out)
    if r == r.parent or r.name == "":
        return "is a filesystem root"
    try:
        cwd = Path.cwd().resolve()
    except OSError:  # the current folder was removed
        cwd = None
    if cwd is not None and r == cwd:
        return "is the current folder"
    if cwd is not None and cwd.is_relative_to(r):
        return "is a parent of the current folder"
    try:
        if r == Path.home().resolve():
            return "is the home folder"
    except (RuntimeError, KeyError, OSError):  # no home
        pass
    if r.is_dir() and os.path.ismount(r):
        return "is a mount point"
    return None


def check_out_dir(out: Path, force: bool) -> None:
    """Refuse, before any work, an output folder that cannot be written or replaced.

    No side effects. Raises :class:`InvalidInputError` (field ``--out``) with the reason.
    """
    out = Path(out)
    fix_other = "give another folder, for example --out results"
    if out.is_symlink():
        target = os.readlink(out)
        state = "" if out.exists() else ", which does not exist"
        raise InvalidInputError("--out", f"{out} is a symbolic link (to {target}{state}); acroplan replaces "
                                "the output folder and does not write through links",
                                f"give the real folder ({_resolved(out).parent / target}) or another path")
    why = _unreplaceable(out)
    if why:
        raise InvalidInputError("--out", f"{out} {why} and cannot be replaced", fix_other)
    if out.exists() and not out.is_dir():
        raise InvalidInputError("--out", f"{out} exists and is not a folder", "give a folder path")
    if out.is_dir() and not force and _non_empty(out):
        raise InvalidInputError("--out", f"{out} exists and is not empty", "choose another folder or add --force")
    parent = _resolved(out).parent
    p = parent
    while not p.exists():
        if p.is_symlink():
            raise InvalidInputError("--out", f"{p} is a dangling symbolic link, so {out} cannot be created",
                                    fix_other)
        p = p.parent
    if not p.is_dir():
        raise InvalidInputError("--out", f"{p} is a file, not a folder, so {out} cannot be created", fix_other)
    if not os.access(p, os.W_OK | os.X_OK):
        raise InvalidInputError("--out", f"cannot write in {p} (permission denied or read-only)", fix_other)


def _non_empty(folder: Path) -> bool:
    try:
        with os.scandir(folder) as it:
            return any(True for _ in it)
    except OSError:
        return True


# ------------------------------------------------------------------------------------ locks
_HELD: dict[str, "OutputFolder"] = {}
_HELD_GUARD = threading.Lock()


def _pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, another user's
        return True
    except OSError:
        return True
    return True


def _lock_path(parent: Path, name: str) -> Path:
    return parent / f".{name}.acroplan.lock"


def _try_lock(path: Path, attempts: int = 5):
    """Take the flock of ``path`` (created if missing) without waiting long; the fd, or None.

    A holder unlinks the file before closing it, so after locking, the file must still be the one
    at ``path`` (else the new file is locked instead); a brief hold by another run's
    :func:`sweep` is waited out (``attempts`` x 20 ms). Without ``fcntl`` (Windows) there is no
    lock: a dummy descriptor is returned.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover
        return os.open(path, os.O_RDWR | os.O_CREAT, 0o644)

    busy = renewed = 0
    while busy < attempts and renewed < 100:
        fd = os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            busy += 1
            if busy < attempts:
                time.sleep(0.02)
            continue
        except BaseException:
            os.close(fd)
            raise
        try:
            same = os.fstat(fd).st_ino == os.stat(path).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return fd
        os.close(fd)  # the file was removed by its previous holder: lock the one at path now
        renewed += 1
    return None


def _unlock(path: Path, fd: int) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass
    finally:
        os.close(fd)


# ------------------------------------------------------------------------------- the swap
def _exchange_fn():
    if not sys.platform.startswith("linux"):
        return None
    try:
        libc = ctypes.CDLL(None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


_RENAMEAT2 = _exchange_fn()
_AT_FDCWD, _RENAME_EXCHANGE = -100, 2


def _exchange(a: Path, b: Path) -> bool:
    """Swap two existing paths atomically; False when the system cannot (then nothing moved)."""
    if _RENAMEAT2 is None:
        return False
    rc = _RENAMEAT2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE)
    if rc == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.ENOSYS, errno.EINVAL, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EPERM):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _swap_in(tmp: Path, out: Path) -> Path | None:
    """Put ``tmp`` at ``out``; returns what to remove afterwards (the previous ``out``), or None."""
    if not os.path.lexists(out):
        os.rename(tmp, out)
        return None
    if _exchange(tmp, out):
        return tmp  # now holds the previous OUT
    old = out.parent / f".{out.name}.acroplan-{os.getpid()}.old"
    os.rename(out, old)
    try:
        os.rename(tmp, out)
    except BaseException:
        os.rename(old, out)  # put the previous OUT back
        raise
    return old


# ------------------------------------------------------------------------------- the sweep
def sweep(parent: Path, held: str | None = None) -> None:
    """Repair what killed runs left in ``parent``; ``held`` is the name whose lock we hold.

    Every repair of a name is done while holding that name's lock (taken without waiting; a name
    whose lock is held by a live run is left alone, which also protects a writer whose PID means
    nothing here, in another PID namespace):

    * ``.NAME.acroplan-PID-*.tmp`` of a dead PID: removed (a live process's never is);
    * ``.NAME.acroplan-PID.old`` of a dead PID: renamed back to NAME when NAME is missing (a
      crash between the two renames of a swap), else removed;
    * ``.NAME.acroplan.lock`` that nobody holds: removed.
    """
    parent = Path(parent)
    try:
        entries = sorted(os.listdir(parent))
    except OSError:
        return
    stale: dict[str, list[tuple[str, str]]] = {}
    for entry in entries:
        for kind, regex in (("tmp", _TMP_RE), ("old", _OLD_RE)):
            m = regex.match(entry)
            if m and not _pid_alive(int(m["pid"])):
                stale.setdefault(m["name"], []).append((kind, entry))
                break
        else:
            m = _LOCK_RE.match(entry)
            if m and m["name"] != held:
                stale.setdefault(m["name"], [])
    for name, items in stale.items():
        with _locked_or_skip(parent, name, held) as ok:
            if not ok:
                continue
            for kind, entry in items:
                if kind == "tmp":
                    shutil.rmtree(parent / entry, ignore_errors=True)
                else:
                    _restore_old(parent / entry, parent / name)


@contextmanager
def _locked_or_skip(parent: Path, name: str, held: str | None, attempts: int = 1):
    """Hold ``name``'s lock for a moment (True), or yield False when another run holds it; the
    lock file is removed on leaving."""
    if name == held:
        yield True
        return
    key = str(parent / name)
    with _HELD_GUARD:
        if key in _HELD:
            yield False
            return
    path = _lock_path(parent, name)
    try:
        fd = _try_lock(path, attempts=attempts)
    except OSError:
        fd = None
    if fd is None:
        yield False
        return
    try:
        yield True
    finally:
        _unlock(path, fd)


def _restore_old(old: Path, out: Path) -> None:
    if not os.path.lexists(out):
        try:
            os.rename(old, out)
            return
        except OSError:
            pass
    shutil.rmtree(old, ignore_errors=True)


# ------------------------------------------------------------------------- the output folder
class OutputFolder:
    """The reservation of one output folder for one run (see the module's description).

    Enter it before the work; write with :meth:`write`; leaving it releases the lock and removes
    the parent folders it created when nothing was written into them.
    """

    def __init__(self, out: Path, force: bool):
        self.out = Path(out)
        self.force = force
        self._fd = None
        self._created: list[Path] = []
        self._key = None
        self._target = _resolved(self.out)
        self._lockfile = _lock_path(self._target.parent, self._target.name)

    # -- enter / leave
    def __enter__(self) -> "OutputFolder":
        check_out_dir(self.out, self.force)
        target = _resolved(self.out)
        parent = target.parent
        missing = []
        p = parent
        while not p.exists():
            missing.append(p)
            p = p.parent
        try:
            for p in reversed(missing):
                try:
                    os.mkdir(p)
                except FileExistsError:  # made by another run meanwhile
                    if not p.is_dir():
                        raise
                    continue
                self._created.append(p)
            self._lockfile = _lock_path(parent, target.name)
            fd = _try_lock(self._lockfile)
        except OSError as e:
            self._remove_created()
            raise InvalidInputError("--out", f"cannot write in {parent} ({e.strerror or type(e).__name__})",
                                    "give a folder you can write to") from None
        if fd is None:
            self._remove_created()
            raise InvalidInputError("--out", f"another acroplan run is writing to {self.out}",
                                    "wait for it to finish, or give another folder")
        self._fd = fd
        self._key = str(target)
        self._owner = threading.get_ident()
        with _HELD_GUARD:
            _HELD[self._key] = self
        try:
            sweep(parent, held=target.name)
            check_out_dir(self.out, self.force)  # again: a run may have restored or written OUT
        except BaseException:
            self._release()
            raise
        return self

    def __exit__(self, *exc) -> None:
        self._release()

    def _release(self) -> None:
        if self._key is not None:
            with _HELD_GUARD:
                _HELD.pop(self._key, None)
            self._key = None
        if self._fd is not None:
            _unlock(self._lockfile, self._fd)
            self._fd = None
        if not os.path.lexists(self._target):
            self._remove_created()

    def _remove_created(self) -> None:
        for p in reversed(self._created):
            try:
                os.rmdir(p)
            except OSError:
                break
        self._created = []

    # -- writing
    @contextmanager
    def write(self):
        """Yield a temporary folder beside OUT; on success it becomes OUT in one step."""
        if self._fd is None:
            raise RuntimeError("OutputFolder.write() outside its with block")
        out = self._target
        tmp = Path(tempfile.mkdtemp(prefix=f".{out.name}.acroplan-{os.getpid()}-", suffix=".tmp", dir=out.parent))
        try:
            tmp.chmod(0o777 & ~_umask())  # mkdtemp makes it 0700; the output follows the user's umask
            yield tmp
            if out.exists() and not out.is_dir() or out.is_symlink():
                raise InvalidInputError("--out", f"{self.out} was replaced by a file or link while planning",
                                        "give another folder")
            leftover = _swap_in(tmp, out)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
        if leftover is not None:
            shutil.rmtree(leftover, ignore_errors=True)
        self._created = []


@contextmanager
def atomic_dir(out: Path, force: bool):
    """Yield a temporary folder beside ``out``; on success it replaces ``out`` in one step.

    On an exception the temporary folder is removed and ``out`` is left as it was. Uses the
    :class:`OutputFolder` this thread already holds for ``out``, else reserves one.
    """
    out = Path(out)
    key = str(_resolved(out)) if not out.is_symlink() else None
    with _HELD_GUARD:
        held = _HELD.get(key) if key else None
    if held is not None and held._owner == threading.get_ident():
        with held.write() as tmp:
            yield tmp
        return
    with OutputFolder(out, force) as folder, folder.write() as tmp:
        yield tmp


def _umask() -> int:
    """The process's umask (read by setting and restoring it: there is no other portable way)."""
    mask = os.umask(0o022)
    os.umask(mask)
    return mask
