"""Interrupts: what Ctrl-C, SIGTERM and SIGHUP do to a command, and the temporary files
that must not outlive it.

A command runs inside :func:`handling_signals` (the command line does it for every
command):

- the **first** SIGINT, SIGTERM or SIGHUP raises :class:`Interrupted` (a
  :class:`KeyboardInterrupt`) in the main thread: the command stops as it does on any
  error, its workers are stopped (``express.analysis.study.runner``), its temporary files
  removed, nothing half-written replaces an output, and the exit status is
  ``128 + signal`` (130 for Ctrl-C).  Inside a callback from compiled code, where an
  exception would be printed and lost (llvmlite's object-cache notifications while
  Numba compiles a kernel on a first run), it waits until the callback has returned
  (:data:`DEFER_S`, a SIGALRM timer) and raises there;
- a **second** one ends the process at once, wherever it is (even inside a long
  numerical call that the first one could not interrupt): a watcher thread woken by the
  signal (:func:`signal.set_wakeup_fd`) kills every child process, removes every
  registered temporary file and calls :func:`os._exit`. A study's checkpoint stays
  valid (a line cut short is dropped on ``--resume``).

Child processes forked while the handlers are installed (a study's workers) ignore
SIGINT and SIGHUP (the terminal sends Ctrl-C to the whole process group; the parent
decides and stops them) and die on SIGTERM.

Temporary files are created and registered in one step (:func:`temporary_file`): the
name is registered before the file exists, so that no interrupt can fall between the
two, and :func:`release` forgets it once it is renamed or removed.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import signal
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

__all__ = [
    "SIGNALS",
    "Interrupted",
    "active",
    "handling_signals",
    "release",
    "remove_temporaries",
    "stop_children",
    "temporary_file",
]

#: The signals that stop a command: Ctrl-C, ``kill``, the terminal closing.
SIGNALS = tuple(s for s in (getattr(signal, n, None) for n in ("SIGINT", "SIGTERM", "SIGHUP")) if s is not None)

_TEMPORARIES: set[str] = set()
_LOCK = threading.Lock()
_STOPPING = threading.Lock()


class Interrupted(KeyboardInterrupt):
    """The command was stopped by a signal; :attr:`status` is ``128 + signal``."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum

    @property
    def status(self) -> int:
        return 128 + self.signum


# --------------------------------------------------------------------------- temporary files


def temporary_file(directory: str | os.PathLike, prefix: str, suffix: str) -> tuple[int, Path]:
    """Create a new file ``directory/prefix<random>suffix`` (mode 0600, like
    :func:`tempfile.mkstemp`) registered for removal in the same step.

    Returns
    -------
    (int, Path)
        An open file descriptor and the path.
    """
    flags = os.O_RDWR | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0)
    while True:
        name = os.path.join(os.fspath(directory), f"{prefix}{secrets.token_hex(8)}{suffix}")
        with _LOCK:
            _TEMPORARIES.add(name)  # registered before it exists: no window
        try:
            return os.open(name, flags, 0o600), Path(name)
        except FileExistsError:
            release(name)
        except BaseException:
            release(name)
            raise


def release(path: str | os.PathLike) -> None:
    """Forget a temporary file (renamed over its target, or removed)."""
    with _LOCK:
        _TEMPORARIES.discard(os.fspath(path))


def remove_temporaries() -> None:
    """Remove every registered temporary file (a stopped command's leftovers)."""
    with _LOCK:
        names = list(_TEMPORARIES)
        _TEMPORARIES.clear()
    for name in names:
        with contextlib.suppress(OSError):
            os.unlink(name)


# --------------------------------------------------------------------------- child processes


def _child_pids() -> set[int]:
    """This process's children: multiprocessing's own, and any other listed by /proc."""
    pids: set[int] = set()
    with contextlib.suppress(Exception):
        import multiprocessing.process as mp_process

        pids.update(p.pid for p in list(mp_process._children) if p.pid)  # type: ignore[attr-defined]
    me = os.getpid()
    with contextlib.suppress(OSError):
        for entry in os.listdir("/proc"):
            if entry.isdigit():
                with contextlib.suppress(OSError, ValueError, IndexError):
                    with open(f"/proc/{entry}/stat", "rb") as stat:
                        fields = stat.read().rsplit(b")", 1)[1].split()
                    if int(fields[1]) == me:
                        pids.add(int(entry))
    return pids


def stop_children() -> None:
    """Kill every child process of this one and reap it (SIGKILL: workers hold nothing
    that needs cleaning up; their unfinished points are recomputed on ``--resume``)."""
    pids = _child_pids()
    for pid in pids:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
    for pid in pids:
        with contextlib.suppress(OSError):
            os.waitpid(pid, 0)


# --------------------------------------------------------------------------- signals


@dataclass
class _Session:
    """One installation of the handlers: its signal count and wakeup pipe."""

    read_end: int
    write_end: int
    received: int = 0
    raised: bool = False
    lock: threading.Lock = field(default_factory=threading.Lock)

    def count(self) -> bool:
        """Count a signal; True when it is the second (or a later) one."""
        with self.lock:
            self.received += 1
            return self.received >= 2


_CURRENT: list[_Session] = []  # the installed session, if any


def active() -> bool:
    """Whether a command is running under :func:`handling_signals`."""
    return bool(_CURRENT)


def _stop_now(signum: int) -> None:
    """The second signal: kill the children, remove the temporary files, exit at once."""
    if not _STOPPING.acquire(blocking=False):
        return
    with contextlib.suppress(OSError):
        os.write(2, f"error: interrupted again ({signal.Signals(signum).name}): stopped at once\n".encode())
    stop_children()
    remove_temporaries()
    os._exit(128 + signum)


#: How long a deferred first signal waits before it looks again whether it can raise [s].
DEFER_S = 0.02

#: Modules whose Python functions compiled code calls back (ctypes callbacks): an
#: exception raised there is printed as "Exception ignored" and lost, not propagated.
_CALLBACK_MODULES = ("llvmlite.",)


def _in_callback(frame) -> bool:
    """Whether the main thread is inside a callback from compiled code (llvmlite's object
    cache notifications while Numba compiles a kernel), where an exception would be lost."""
    while frame is not None:
        if str(frame.f_globals.get("__name__", "")).startswith(_CALLBACK_MODULES):
            return True
        frame = frame.f_back
    return False


def _handler(signum: int, frame) -> None:
    """Python-level handler (main thread): the first signal raises :class:`Interrupted`,
    at once or, inside a callback from compiled code, as soon as the callback has returned."""
    session = _CURRENT[0] if _CURRENT else None
    if session is None:
        return
    if session.received >= 2:
        _stop_now(signum)
    if not session.raised:
        if _in_callback(frame) and _defer(signum):
            return
        session.raised = True
        raise Interrupted(signum)


def _defer(signum: int) -> bool:
    """Look again in :data:`DEFER_S` (a SIGALRM timer, whose handler is restored when it
    fires); False where there is no interval timer, and the signal raises at once."""
    if not hasattr(signal, "setitimer"):
        return False
    previous = signal.getsignal(signal.SIGALRM)

    def again(_alarm: int, frame) -> None:
        signal.signal(signal.SIGALRM, previous if previous is not None else signal.SIG_DFL)
        _handler(signum, frame)

    signal.signal(signal.SIGALRM, again)
    signal.setitimer(signal.ITIMER_REAL, DEFER_S)
    return True


def _late_handler(signum: int, frame) -> None:
    """After the command (``keep``): a signal while the process exits raises nothing;
    the watcher still ends the process at the second one."""
    if _CURRENT and _CURRENT[0].received >= 2:
        _stop_now(signum)


def _watch(session: _Session) -> None:
    """Watcher thread: counts the signals as the C-level handler reports them, so that a
    second one acts even while the main thread is inside a long call."""
    wanted = {int(s) for s in SIGNALS}
    try:
        while True:
            data = os.read(session.read_end, 64)
            if not data:  # the command ended: the write end was closed
                return
            for byte in data:
                if byte in wanted and _CURRENT and _CURRENT[0] is session and session.count():
                    _stop_now(byte)
    except OSError:
        return
    finally:
        with contextlib.suppress(OSError):
            os.close(session.read_end)


def _after_fork_in_child() -> None:
    """A forked child (a study's worker): no handlers of ours, no wakeup pipe; SIGINT and
    SIGHUP ignored (the parent decides), SIGTERM ends it."""
    if not _CURRENT:
        return
    session = _CURRENT.pop()
    with contextlib.suppress(ValueError, OSError):
        signal.set_wakeup_fd(-1)
    for end in (session.read_end, session.write_end):  # the parent's watcher must see its pipe close
        with contextlib.suppress(OSError):
            os.close(end)
    with contextlib.suppress(ValueError, OSError):
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        if hasattr(signal, "SIGHUP"):
            signal.signal(signal.SIGHUP, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_after_fork_in_child)


@contextlib.contextmanager
def handling_signals(keep: bool = False) -> Iterator[None]:
    """Install the handlers of the module docstring for the duration of a command
    (only in the main thread; elsewhere it does nothing).

    Parameters
    ----------
    keep : bool
        The process ends after the command (the command line): leave the watcher
        running and a handler that raises nothing. Otherwise (a command run in-process,
        as the tests do) the previous handlers and wakeup descriptor are restored.
    """
    if threading.current_thread() is not threading.main_thread() or active():
        yield
        return
    read_end, write_end = os.pipe()
    os.set_blocking(write_end, False)
    previous = {s: signal.getsignal(s) for s in SIGNALS}
    try:
        old_fd = signal.set_wakeup_fd(write_end, warn_on_full_buffer=False)
    except ValueError:  # pragma: no cover - not the main thread of the main interpreter
        os.close(read_end)
        os.close(write_end)
        yield
        return
    session = _Session(read_end, write_end)
    _CURRENT.append(session)
    for s in SIGNALS:
        signal.signal(s, _handler)
    threading.Thread(target=_watch, args=(session,), name="express-signals", daemon=True).start()
    try:
        yield
    finally:
        if keep:
            for s in SIGNALS:
                signal.signal(s, _late_handler)
        else:
            for s, handler in previous.items():
                signal.signal(s, handler if handler is not None else signal.SIG_DFL)
            signal.set_wakeup_fd(old_fd)
            _CURRENT.clear()
            os.close(write_end)  # the watcher reads end-of-file, closes its end and returns
