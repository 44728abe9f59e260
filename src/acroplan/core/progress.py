"""Progress of long work: one ``tqdm.auto`` line per stage, on a terminal and in a notebook.

Long work (the waypoint intervals of a plan, a strategy's guesses, path deformation, the optimal
ladder, the independent check, the effort summary, figures, animation frames, sweeps) reports in
*stages*: a stage has a name, a count done and, when known, a total. A stage is shown as one
``tqdm.auto`` line (a widget in a notebook, a text line on a terminal) once it has lasted
:data:`DELAY` seconds, so quick work prints nothing; while it is shown, its line is refreshed at
least every :data:`REFRESH` seconds (its elapsed time moves even while one long step runs, so a
line is never a bar frozen at 0/1).

A *watched* progress (the command line's: ``Progress(watch=True)``) never leaves the screen silent
for more than :data:`SILENCE` seconds while its command runs: past it, a stage open but within its
delay is shown at once, and between stages the command's *phase* (:meth:`Progress.phase`:
"starting", "writing the results", ...) is shown with its elapsed time (a line erased when the
next stage appears). Its silence is counted from the process's start (:func:`process_age`), so the
interpreter's and the command's imports count too.

Where it goes: a :class:`Progress` is *active* in a ``with progress.active():`` block (``plan()``
opens one for its own work; the command line one for a whole command). Code deep in the core
reports to the active one through :func:`stage` and :func:`note`, and knows nothing of bars.
Outside any block, :func:`stage` shows progress when :func:`auto` says so: in a notebook and when
stderr is a terminal, never when the output goes to a file or a pipe.

``Progress(record=True)`` keeps every update as an event ``(stage, done, total)`` (what the tests
count); ``Progress(callback=f)`` calls ``f(stage, done, total)`` for each.
"""

from __future__ import annotations

import contextlib
import contextvars
import sys
import threading
import time
from typing import Callable, Iterator

__all__ = ["Progress", "Stage", "current", "stage", "note", "close_notes", "auto", "resolve", "silent", "in_notebook",
           "DELAY", "REFRESH", "SILENCE", "INNER_STAGES", "process_age"]

#: Seconds a stage runs before its line appears (quick work prints nothing).
DELAY = 0.5
#: Largest interval in seconds between two refreshes of a shown line.
REFRESH = 0.25
#: A watched progress's longest silence (seconds with nothing drawn) before it shows what runs:
#: the open stage before its delay, or the command's phase (the module docstring). With the
#: refreshing thread's period, the screen of a command is redrawn at least every
#: ``SILENCE + REFRESH`` = 0.75 s (while the interpreter lock is free: a C extension that holds it,
#: loading a compiled library, delays every thread).
SILENCE = 0.5

#: The stages code deep in the core reports by :func:`note` while one waypoint interval is planned
#: (closed when the interval is done): a strategy's guesses, path deformation, the optimal ladder.
INNER_STAGES = ("guesses", "path deformation", "optimal: basis sizes")

_CURRENT: contextvars.ContextVar["Progress | None"] = contextvars.ContextVar("acroplan_progress", default=None)


def process_age() -> float:
    """Seconds since this process started (Linux: ``/proc``; elsewhere 0, as if it just had)."""
    import os

    try:
        with open("/proc/self/stat", "rb") as f:
            start_ticks = float(f.read().rsplit(b")", 1)[1].split()[19])
        with open("/proc/uptime", "rb") as f:
            uptime = float(f.read().split()[0])
        return max(0.0, uptime - start_ticks / os.sysconf("SC_CLK_TCK"))
    except (OSError, ValueError, IndexError, AttributeError):
        return 0.0


def _terminal_width() -> int:
    import os

    try:
        return os.get_terminal_size(sys.stderr.fileno()).columns
    except (OSError, ValueError, AttributeError):
        return 0


def in_notebook() -> bool:
    """Whether this is a Jupyter kernel (an IPython ZMQ shell)."""
    shell = sys.modules.get("IPython")
    if shell is None:
        return False
    try:
        ip = shell.get_ipython()
    except Exception:  # noqa: BLE001
        return False
    return ip is not None and type(ip).__name__ == "ZMQInteractiveShell"


def auto() -> bool:
    """Whether progress is shown by default: in a notebook, or when stderr is a terminal."""
    if in_notebook():
        return True
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


class Stage:
    """One stage of a :class:`Progress`: ``update(n)`` adds ``n`` done, ``set(done, total)`` sets
    them; ``detail`` (a short text) is shown after the count."""

    def __init__(self, owner: "Progress", name: str, total: float | None, unit: str, leave: bool, show: bool = True):
        self.owner, self.name, self.total, self.unit, self.leave = owner, name, total, unit, leave
        self.show = show
        self.done = 0
        self.detail = ""
        self.start = time.monotonic()
        self.bar = None
        self.closed = False

    def update(self, n: float = 1, detail: str | None = None) -> None:
        self.set(self.done + n, detail=detail)

    def set(self, done: float, total: float | None = None, detail: str | None = None) -> None:
        if total is not None:
            self.total = total
        self.done = done
        if detail is not None:
            self.detail = detail
        self.owner._event(self)
        self.owner._show(self, force=False)

    def close(self) -> None:
        if self.closed:
            return
        self.closed = True
        self.owner._close(self)


class _Null:
    """The stage of no progress: every call does nothing."""

    name, done, total, detail = "", 0, None, ""

    def update(self, n=1, detail=None):
        pass

    def set(self, done, total=None, detail=None):
        pass

    def close(self):
        pass


NULL_STAGE = _Null()


class _NullScope:
    """``with``: the null stage, nothing done at the end (a silent progress's :meth:`Progress.scope`)."""

    def __enter__(self):
        return NULL_STAGE

    def __exit__(self, *exc):
        return False


_NULL_SCOPE = _NullScope()


class _Active:
    """:meth:`Progress.active`'s context manager (a class, not a generator: every plan opens one)."""

    __slots__ = ("progress", "token")

    def __init__(self, progress):
        self.progress, self.token = progress, None

    def __enter__(self):
        self.token = _CURRENT.set(self.progress)
        return self.progress

    def __exit__(self, *exc) -> None:
        _CURRENT.reset(self.token)


class Progress:
    """Where the stages of long work are shown (module docstring).

    Parameters
    ----------
    enabled : bool, optional
        Show the lines (default: :func:`auto`).
    record : bool
        Keep every update in :attr:`events` as ``(stage, done, total)``, and the
        ``time.monotonic()`` of every line drawn in :attr:`draw_times`, of every wake-up of the
        refreshing thread in :attr:`tick_times` and of every start of that thread in
        :attr:`ticker_starts` (what a test of the silences measures).
    callback : callable, optional
        Called as ``callback(stage, done, total)`` for every update.
    file : file object, optional
        Where text lines go (default: stderr); a notebook shows widgets.
    delay : float
        Seconds before a stage's line appears (:data:`DELAY`).
    watch : bool
        Never silent for more than :data:`SILENCE` seconds until :meth:`close` (the command
        line's): the open stage shown before its delay, or between stages the :meth:`phase`.
    since : float, optional
        With ``watch``: the ``time.monotonic()`` reading the silence is counted from (default: the
        process's start, :func:`process_age`).
    """

    def __init__(self, enabled: bool | None = None, *, record: bool = False,
                 callback: Callable[[str, float, float | None], object] | None = None, file=None,
                 delay: float = DELAY, watch: bool = False, since: float | None = None):
        self.enabled = auto() if enabled is None else bool(enabled)
        self.events: list[tuple[str, float, float | None]] | None = [] if record else None
        self.draw_times: list[float] | None = [] if record else None
        self.tick_times: list[float] | None = [] if record else None
        self.ticker_starts: list[float] | None = [] if record else None
        self.callback = callback
        self.file = file
        self.delay = float(delay)
        self._open: dict[str, Stage] = {}
        self._lock = threading.RLock()
        self._ticker: threading.Thread | None = None
        self._stop = threading.Event()
        #: how many times a shown line was drawn (updates and refreshes; for the record)
        self.draws = 0
        self.watch = bool(watch)
        #: ``time.monotonic()`` of the last line drawn (before any: of the process's start when
        #: watched, the only case that reads it before a draw; else now, without reading /proc,
        #: which every plan's own progress would pay for)
        if since is not None:
            self.last_draw = float(since)
        else:
            self.last_draw = time.monotonic() - (process_age() if self.watch else 0.0)
        self._phase: Stage | None = None
        self._phase_name = "starting"
        if self.watch:
            self._start_ticker()

    @property
    def silent(self) -> bool:
        """Nothing observes this progress: not shown, no callback, no record, not watched. Its
        stages are then :data:`NULL_STAGE` (every plan of a script or a sweep has such a progress:
        its bookkeeping was 0.05-0.1 ms of a two-link plan's 0.5-0.8)."""
        return not self.enabled and self.callback is None and self.events is None and not self.watch

    # ------------------------------------------------------------------ stages
    def stage(self, name: str, total: float | None = None, *, unit: str = "", leave: bool = True,
              show: bool = True) -> Stage:
        """Open the stage ``name`` (or return it if open): close it with :meth:`Stage.close`, or
        use :meth:`scope`. ``show=False``: counted (events, callback) but never drawn (a stage of one
        step whose inner stages say more)."""
        if self.silent:
            return NULL_STAGE
        with self._lock:
            st = self._open.get(name)
            if st is None or st.closed:
                st = Stage(self, name, total, unit, leave, show)
                self._open[name] = st
                self._event(st)
                self._start_ticker()
            elif total is not None:
                st.total = total
            return st

    def scope(self, name: str, total: float | None = None, *, unit: str = "", leave: bool = True,
              show: bool = True):
        """``with progress.scope("figures", 4) as st: ...``: the stage, closed at the end (a silent
        progress's: the null stage, with nothing to close)."""
        if self.silent:
            return _NULL_SCOPE
        return self._scope(name, total, unit=unit, leave=leave, show=show)

    @contextlib.contextmanager
    def _scope(self, name, total, *, unit, leave, show) -> Iterator[Stage]:
        st = self.stage(name, total, unit=unit, leave=leave, show=show)
        try:
            yield st
        finally:
            st.close()

    def active(self) -> "_Active":
        """Make this the progress that :func:`stage` and :func:`note` report to, in this block
        (``with progress.active(): ...``; the block's target is this progress)."""
        return _Active(self)

    def phase(self, name: str) -> None:
        """Name what a watched progress's command does from now on between its stages ("writing
        the results"): shown with its elapsed time when the screen has been silent
        :data:`SILENCE` seconds and no stage is open."""
        with self._lock:
            self._hide_phase()
            self._phase_name = str(name)

    def close(self) -> None:
        """Close every open stage and stop the refreshing thread (a silent progress has neither)."""
        if self.silent:
            return
        with self._lock:
            for st in list(self._open.values()):
                st.close()
            self._hide_phase()
        self._stop.set()

    # ------------------------------------------------------------------ internals
    def _event(self, st: Stage) -> None:
        if self.events is not None:
            self.events.append((st.name, st.done, st.total))
        if self.callback is not None:
            self.callback(st.name, st.done, st.total)

    def _show(self, st: Stage, force: bool) -> None:
        if not self.enabled or st.closed or not st.show:
            return
        with self._lock:
            if st.bar is None:
                if time.monotonic() - st.start < self.delay and not force:
                    return
                if st is not self._phase:
                    self._hide_phase()  # (a stage takes the phase's place)
                st.bar = self._bar(st)
            bar = st.bar
            bar.total = _bar_total(st)
            if st.detail:
                bar.set_postfix_str(st.detail, refresh=False)
            if st.done != bar.n:
                bar.update(st.done - bar.n)  # (tqdm's rate and time left follow its updates)
            bar.refresh()
            self._drawn()

    def _hide_phase(self) -> None:
        """Erase the phase's line, if shown (a stage appears, the phase changes, the end)."""
        ph, self._phase = self._phase, None
        if ph is not None and ph.bar is not None:
            ph.bar.close()  # (leave=False: the line is erased)
            ph.bar = None
            self._drawn()

    def _drawn(self) -> None:
        self.draws += 1
        self.last_draw = time.monotonic()
        if self.draw_times is not None:
            self.draw_times.append(self.last_draw)

    def _bar(self, st: Stage):
        import shutil

        from tqdm.auto import tqdm

        # a terminal that reports no width (a pty nobody sized) gets 100 columns, not an empty line
        sized = _terminal_width() > 0
        size = shutil.get_terminal_size((100, 24))
        return tqdm(total=_bar_total(st), initial=st.done, desc=st.name, unit=st.unit or "it", leave=st.leave, file=self.file,
                    dynamic_ncols=sized, ncols=None if sized else size.columns, nrows=None if sized else size.lines,
                    mininterval=0, bar_format=_bar_format(st, in_notebook()))

    def _close(self, st: Stage) -> None:
        with self._lock:
            if self._open.get(st.name) is st:
                del self._open[st.name]
            if st.bar is not None:
                st.bar.n = st.done
                if st.detail:
                    st.bar.set_postfix_str(st.detail, refresh=False)
                st.bar.refresh()
                st.bar.close()
                st.bar = None
                self._drawn()

    def _start_ticker(self) -> None:
        if not self.enabled or (self._ticker is not None and self._ticker.is_alive()):
            return
        self._stop.clear()
        if self.ticker_starts is not None:
            self.ticker_starts.append(time.monotonic())
        self._ticker = threading.Thread(target=self._tick, name="acroplan-progress", daemon=True)
        self._ticker.start()

    def _wait(self) -> float:
        """Seconds to the next wake-up: :data:`REFRESH`, or for a watched progress sooner when its
        silence reaches :data:`SILENCE` before (so that a command's first line comes at once)."""
        if not self.watch:
            return REFRESH
        return min(REFRESH, max(0.02, SILENCE - (time.monotonic() - self.last_draw)))

    def _tick(self) -> None:
        """Refresh every shown stage (and show those past the delay) every :data:`REFRESH` s, until
        no stage is open; a watched progress until :meth:`close`, showing the open stages or its
        phase once the screen has been silent :data:`SILENCE` s."""
        while not self._stop.wait(self._wait()):
            with self._lock:
                if self.tick_times is not None:
                    self.tick_times.append(time.monotonic())
                stages = [st for st in self._open.values() if not st.closed and st.show]
                if not stages and not self.watch:
                    self._ticker = None  # (a stage opened from now on starts another)
                    return
                now = time.monotonic()
                silent = self.watch and now - self.last_draw >= SILENCE
                for st in stages:
                    if st.bar is not None or now - st.start >= self.delay or silent:
                        self._show(st, force=True)
                if self.watch and not stages and (silent or self._phase is not None):
                    if self._phase is None:
                        self._phase = Stage(self, self._phase_name, None, "", leave=False)
                    self._show(self._phase, force=True)


def _bar_format(st: Stage, notebook: bool) -> str | None:
    """tqdm's format of a stage's line: its count or, for a stage of one step, its elapsed time. In a
    notebook the elapsed time is shown to a tenth of a second: a widget is redrawn only when its text
    changes, and whole seconds change once a second, which the refreshing thread's period makes up to
    ``1 + REFRESH`` seconds apart (a line that looks frozen); tenths change at every refresh."""
    if not notebook:
        return None if _bar_total(st) else "{desc}: {elapsed}{postfix}"
    if _bar_total(st):
        return "{l_bar}{bar}| {n_fmt}/{total_fmt} [{elapsed_s:.1f} s<{remaining}, {rate_fmt}{postfix}]"
    return "{desc}: {elapsed_s:.1f} s{postfix}"


def _bar_total(st: Stage):
    """What a stage's line counts to: its total, or none for a stage of one step (a bar at 0/1 says
    nothing: the line shows the elapsed time instead)."""
    return st.total if st.total is not None and st.total > 1 else None


_SILENT: Progress | None = None


def silent() -> Progress:
    """The one silent progress (:attr:`Progress.silent`: nothing shown or recorded, every stage the
    null stage), shared by every plan that nobody watches: making a progress (its lock and event)
    for each was part of a two-link plan's bookkeeping."""
    global _SILENT
    if _SILENT is None:
        _SILENT = Progress(enabled=False)
    return _SILENT


def current() -> Progress | None:
    """The active :class:`Progress` (``None`` outside any ``active()`` block)."""
    return _CURRENT.get()


def resolve(progress, stage: str = "segments") -> Progress:
    """The :class:`Progress` an argument ``progress=`` asks for: ``None`` (the active one, else
    :func:`auto`), ``True``/``False`` (shown or not), a :class:`Progress`, or a callable
    ``f(done, total)`` (called for each update of the stage ``stage``: the waypoint intervals of a
    plan, the problems of a batch; no lines shown)."""
    if isinstance(progress, Progress):
        return progress
    if progress is None:
        active = current()
        if active is not None:
            return active
        return Progress() if auto() else silent()
    if progress is False:
        return silent()
    if progress is True:
        return Progress(enabled=True)
    if callable(progress):
        fn = progress
        return Progress(enabled=False, callback=lambda name, done, total: fn(done, total) if name == stage and done
                        else None)
    raise TypeError(f"progress must be None, True, False, a Progress or a callable, got {progress!r}")


@contextlib.contextmanager
def stage(name: str, total: float | None = None, *, unit: str = "", leave: bool = True,
          show: bool = True) -> Iterator[Stage]:
    """A stage of the active progress, closed at the end of the block; outside any active one, of
    an automatic :class:`Progress` (:func:`auto`) for this block alone."""
    prog = current()
    own = prog is None
    if own:
        if not auto():  # decided before a Progress is made (its clock reads /proc: 0.1 ms a stage)
            yield NULL_STAGE
            return
        prog = Progress(True)
    st = prog.stage(name, total, unit=unit, leave=leave, show=show)
    try:
        if own:
            with prog.active():
                yield st
        else:
            yield st
    finally:
        st.close()
        if own:
            prog.close()


def note(name: str, done: float, total: float | None = None, detail: str | None = None) -> None:
    """Set the stage ``name`` of the active progress (opened on first use, closed by whoever opened
    the enclosing stage: :func:`close_notes`); nothing without an active progress. For code deep in
    the core (the optimal ladder, path deformation) that reports without holding a stage."""
    prog = _CURRENT.get()
    if prog is None:
        return
    st = prog._open.get(name)
    if st is None:
        st = prog.stage(name, total, leave=False)
    st.set(done, total, detail)


def close_notes(*names: str) -> None:
    """Close the stages ``names`` of the active progress, if open (the end of what they were about)."""
    prog = _CURRENT.get()
    if prog is None:
        return
    for name in names:
        st = prog._open.get(name)
        if st is not None:
            st.close()
