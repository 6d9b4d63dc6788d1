"""The output layer: every file EXPRESS writes goes through here.

Guarantees (``docs/cli.md``, "Outputs"):

- **Whole or not at all.** A regular file is written to a unique temporary file in the
  target directory (:func:`express.base.interrupts.temporary_file`: created and registered
  for removal in one step, so that an interrupt leaves none behind), flushed to disk (``fsync``) and renamed
  over the target (:func:`os.replace`, atomic on POSIX).  Readers see the old file or the
  new one, never a part; concurrent writers of one path end with one complete file (the
  last rename wins).
- **Special files are written into, never replaced.**  A FIFO, a character device
  (``/dev/null``, a terminal) or ``/dev/stdout`` receives the bytes; it is not turned
  into a regular file; a FIFO that no process opens for reading within
  :data:`FIFO_WAIT` is an error, not a hang.  ``-`` is standard output (text formats
  only).  Block devices and sockets are refused.
- **Inputs are never overwritten** (compared by file identity, so hard and symbolic links
  count).
- **Several outputs are a transaction** (:func:`output_transaction`): every destination
  is checked before any work (:meth:`Transaction.declare`), every temporary file is
  written before any rename, and nothing is replaced unless all were written.  The one
  window left is the sequence of renames itself: if a rename fails (the directory
  vanished, the machine stopped) the outputs renamed before it are new and the rest old;
  the error names them.
- Outputs are deterministic: :func:`~express.io.text_formats.csv_text`, :func:`npz_bytes` and :func:`mat_bytes`
  give the same bytes for the same data (no dates, fixed zip timestamps).

:func:`write_bytes` / :func:`write_text` join the active transaction when there is one,
so library code (figures, the demo) takes part in a command's all-or-nothing without
knowing about it.  Errors are :class:`express.base.diagnostics.OutputError` (exit status 2).
"""

from __future__ import annotations

import contextlib
import contextvars
import errno
import os
import stat
import sys
import time
from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from express.base.diagnostics import OutputError
from express.base.interrupts import release, temporary_file
from express.io.archives import mat_bytes, npz_bytes
from express.io.text_formats import csv_text

__all__ = [
    "STDOUT",
    "Destination",
    "Transaction",
    "check_destination",
    "mat_bytes",
    "npz_bytes",
    "output_transaction",
    "write_bytes",
    "write_bytes_now",
    "write_csv",
    "write_output",
    "write_text",
]

#: The destination name meaning standard output.
STDOUT = "-"

#: The descriptive text of a MAT-file's 128-byte header (116 bytes, space padded).

_ACTIVE: contextvars.ContextVar[Transaction | None] = contextvars.ContextVar("express_output_transaction", default=None)


# --------------------------------------------------------------------------------------
# destinations
# --------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Destination:
    """A checked place to write.

    Attributes
    ----------
    given : str
        The name as the user gave it (used in messages).
    kind : str
        ``"file"`` (replaced atomically), ``"special"`` (a FIFO or character device,
        written into) or ``"stdout"``.
    path : Path or None
        The real path written (symbolic links resolved); None for ``"stdout"``.
    """

    given: str
    kind: str
    path: Path | None


def _is_stdout_alias(given: str, status: os.stat_result) -> bool:
    """``/dev/stdout``, ``/dev/fd/1``, ``/proc/self/fd/1`` when they lead to our stdout."""
    if not os.path.abspath(given).startswith(("/dev/", "/proc/")):
        return False
    try:
        return os.path.samestat(status, os.fstat(sys.stdout.fileno()))
    except (AttributeError, OSError, ValueError):  # no real stdout (e.g. under a test runner)
        return False


def check_destination(given: str | os.PathLike, *, inputs: Iterable[str | os.PathLike] = (), binary: bool = False) -> Destination:
    """Check that ``given`` can receive an output, before any work is done.

    Parameters
    ----------
    given : str or path-like
        Output name; ``"-"`` is standard output.
    inputs : iterable of path-like
        Files read by the command; none of them may be the destination.
    binary : bool
        The format is binary (refused on standard output).

    Returns
    -------
    Destination

    Raises
    ------
    OutputError
        The destination is an input, a directory, below a regular file, a block device
        or socket, or not writable; the message names it.
    """
    name = os.fspath(given)
    if name == STDOUT:
        if binary:
            raise OutputError("-: this format is binary; give a file name instead of standard output")
        return Destination(name, "stdout", None)
    if not name or name.endswith(os.sep):
        raise OutputError(f"{name or '(empty name)'}: not a file name")
    try:
        status: os.stat_result | None = os.stat(name)
    except FileNotFoundError:
        status = None
    except OSError as error:  # e.g. a path component that is a regular file
        raise OutputError(f"{name}: cannot write ({error.strerror or error})") from None
    if status is not None:
        _refuse_input(name, status, inputs)
        return _existing(name, status, binary)
    real = Path(os.path.realpath(name))
    _check_new_file_place(name, real)
    return Destination(name, "file", real)


#: Where the bundled examples and data live (the source tree's ``examples/``, the
#: package's ``data/``): their files are inputs of every command, never a destination.
BUNDLED = (Path(__file__).resolve().parents[3] / "examples", Path(__file__).resolve().parents[1] / "data")


def _bundled(status: os.stat_result) -> Path | None:
    """The bundled file that ``status`` is (also through a link), if any."""
    for folder in BUNDLED:
        if not folder.is_dir():
            continue
        for path in folder.rglob("*"):
            with contextlib.suppress(OSError):
                if path.is_file() and os.path.samestat(status, path.stat()):
                    return path
    return None


def _refuse_input(name: str, status: os.stat_result, inputs: Iterable[str | os.PathLike]) -> None:
    bundled = _bundled(status) if stat.S_ISREG(status.st_mode) else None
    if bundled is not None:
        raise OutputError(f"{name}: refusing to overwrite the bundled example {bundled.name} "
                          f"({bundled.parent}); write elsewhere")
    for source in inputs:
        try:
            if os.path.samestat(status, os.stat(source)):
                raise OutputError(f"{name}: refusing to overwrite the input file {os.fspath(source)}")
        except FileNotFoundError:
            continue


def _existing(name: str, status: os.stat_result, binary: bool) -> Destination:
    mode = status.st_mode
    if stat.S_ISDIR(mode):
        raise OutputError(f"{name}: is a directory, not a file")
    if _is_stdout_alias(name, status):
        if binary:
            raise OutputError(f"{name}: this format is binary; give a file name instead of standard output")
        return Destination(name, "stdout", None)
    if stat.S_ISFIFO(mode) or stat.S_ISCHR(mode):
        if not os.access(name, os.W_OK):
            raise OutputError(f"{name}: cannot write (permission denied)")
        return Destination(name, "special", Path(name))
    if not stat.S_ISREG(mode):
        raise OutputError(f"{name}: is a block device or socket; refusing to write to it")
    real = Path(os.path.realpath(name))
    if not os.access(real, os.W_OK):
        raise OutputError(f"{name}: cannot write (the file is read-only)")
    if not os.access(real.parent, os.W_OK | os.X_OK):
        raise OutputError(f"{name}: cannot write (no permission in {real.parent})")
    return Destination(name, "file", real)


def _check_new_file_place(name: str, real: Path) -> None:
    """The first existing ancestor of a new file must be a writable directory."""
    ancestor = real.parent
    while not ancestor.exists():
        if ancestor.is_symlink():
            raise OutputError(f"{name}: cannot write ({ancestor} is a dangling symbolic link)")
        ancestor = ancestor.parent
    if not ancestor.is_dir():
        raise OutputError(f"{name}: cannot write ({ancestor} is a file, not a directory)")
    if not os.access(ancestor, os.W_OK | os.X_OK):
        raise OutputError(f"{name}: cannot write (no permission in {ancestor})")


# --------------------------------------------------------------------------------------
# the transaction
# --------------------------------------------------------------------------------------


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@dataclass
class _Staged:
    destination: Destination
    temporary: Path | None = None  # for files
    data: bytes = b""  # for stdout and special files


@dataclass
class Transaction:
    """Outputs of one command, replaced all together or not at all.

    Use :func:`output_transaction`; :meth:`declare` every destination before computing,
    then :func:`write_bytes` / :func:`write_text` (or :meth:`stage`) stage the contents;
    leaving the ``with`` block normally commits, an exception discards everything.
    """

    inputs: tuple[str, ...] = ()
    _declared: dict[str, Destination] = field(default_factory=dict)
    _staged: dict[str, _Staged] = field(default_factory=dict)
    _created_dirs: list[Path] = field(default_factory=list)

    @staticmethod
    def _key(destination: Destination) -> str:
        return "<stdout>" if destination.kind == "stdout" else str(destination.path)

    def declare(self, given: str | os.PathLike, *, binary: bool = False) -> Destination:
        """Check a destination now (see :func:`check_destination`); the same file may not
        be declared twice."""
        destination = check_destination(given, inputs=self.inputs, binary=binary)
        key = self._key(destination)
        earlier = self._declared.get(key)
        if earlier is not None:
            raise OutputError(f"{destination.given}: given twice as an output (also as {earlier.given})")
        self._declared[key] = destination
        return destination

    def add_inputs(self, inputs: Iterable[str | os.PathLike]) -> None:
        """Files found to be read once the work started (a profile named by a track file):
        refused as destinations from now on, and checked against those declared already."""
        added = tuple(os.fspath(p) for p in inputs)
        for destination in self._declared.values():
            if destination.kind == "file" and destination.path is not None:
                with contextlib.suppress(FileNotFoundError):
                    _refuse_input(destination.given, os.stat(destination.path), added)
        self.inputs = self.inputs + added

    def _destination(self, given: str | os.PathLike) -> Destination:
        destination = check_destination(given, inputs=self.inputs)
        return self._declared.setdefault(self._key(destination), destination)

    def stage(self, given: str | os.PathLike, data: bytes) -> None:
        """Stage ``data`` for ``given``: a regular file is written to its temporary now."""
        destination = self._destination(given)
        key = self._key(destination)
        previous = self._staged.pop(key, None)
        if previous is not None and previous.temporary is not None:
            _remove(previous.temporary)
        if destination.kind != "file":
            self._staged[key] = _Staged(destination, data=bytes(data))
            return
        self._staged[key] = _Staged(destination, temporary=self._write_temporary(destination, data))

    def _write_temporary(self, destination: Destination, data: bytes) -> Path:
        assert destination.path is not None
        target = destination.path
        try:
            self._make_parents(target.parent)
            handle, temporary = temporary_file(target.parent, prefix=f".{target.name}.", suffix=".tmp")
        except OSError as error:
            raise OutputError(f"{destination.given}: cannot write ({error.strerror or error})") from None
        try:
            with os.fdopen(handle, "wb") as stream:
                stream.write(data)
                stream.flush()
                os.fsync(stream.fileno())
            try:
                mode = stat.S_IMODE(os.stat(target).st_mode)  # keep an existing file's mode
            except FileNotFoundError:
                mode = 0o666 & ~_umask()
            os.chmod(temporary, mode)
        except OSError as error:
            _remove(temporary)
            raise OutputError(f"{destination.given}: cannot write ({error.strerror or error})") from None
        except BaseException:
            _remove(temporary)
            raise
        return temporary

    def _make_parents(self, directory: Path) -> None:
        missing = []
        while not directory.exists():
            missing.append(directory)
            directory = directory.parent
        for path in reversed(missing):
            path.mkdir()
            self._created_dirs.append(path)

    def discard(self) -> None:
        """Remove every temporary file (and the directories made for them)."""
        for staged in self._staged.values():
            if staged.temporary is not None:
                _remove(staged.temporary)
        self._staged.clear()
        for directory in reversed(self._created_dirs):
            with contextlib.suppress(OSError):
                directory.rmdir()
        self._created_dirs.clear()

    def commit(self) -> list[Destination]:
        """Write standard output and special files, then rename every temporary file
        over its target.  Returns the destinations written, in declaration order."""
        order = [key for key in self._declared if key in self._staged]
        try:
            for key in order:
                staged = self._staged[key]
                if staged.destination.kind != "file":
                    _write_stream(staged.destination, staged.data)
        except BaseException:
            self.discard()
            raise
        renamed: list[str] = []
        for key in order:
            staged = self._staged[key]
            if staged.temporary is None:
                continue
            try:
                os.replace(staged.temporary, staged.destination.path)  # type: ignore[arg-type]
            except OSError as error:
                self.discard()
                done = f"; already replaced: {', '.join(renamed)}" if renamed else "; nothing was replaced"
                raise OutputError(f"{staged.destination.given}: cannot write ({error.strerror or error}){done}") from None
            release(staged.temporary)
            staged.temporary = None
            renamed.append(staged.destination.given)
        for directory in {self._staged[key].destination.path.parent for key in order  # type: ignore[union-attr]
                          if self._staged[key].destination.kind == "file"}:
            _fsync_directory(directory)
        written = [self._staged[key].destination for key in order]
        self._staged.clear()
        self._created_dirs.clear()
        return written


def _remove(temporary: Path) -> None:
    temporary.unlink(missing_ok=True)
    release(temporary)


def _write_stream(destination: Destination, data: bytes) -> None:
    if destination.kind == "stdout":
        stream = sys.stdout
        stream.flush()
        buffer = getattr(stream, "buffer", None)
        if buffer is not None:
            buffer.write(data)
            buffer.flush()
        else:
            stream.write(data.decode("utf-8"))
            stream.flush()
        return
    assert destination.path is not None
    try:
        handle = _open_special(destination.path)
        with os.fdopen(handle, "wb") as stream:
            stream.write(data)
    except OSError as error:
        if error.errno == errno.ENXIO:
            raise OutputError(f"{destination.given}: a FIFO that no process opened for reading within "
                              f"{FIFO_WAIT:g} s; nothing was written") from None
        raise OutputError(f"{destination.given}: cannot write ({error.strerror or error})") from None


#: Longest wait for a process to open an output FIFO for reading [s].
FIFO_WAIT = 10.0


def _open_special(path: Path) -> int:
    """A descriptor to write into a special file.  A FIFO is opened without blocking (with
    no reader the open fails with ENXIO), retried for :data:`FIFO_WAIT` seconds so that a
    reader started beside the command can attach; then the writes wait on the reader as
    in a pipe."""
    flags = os.O_WRONLY | getattr(os, "O_NOCTTY", 0)
    if not stat.S_ISFIFO(os.stat(path).st_mode):
        return os.open(path, flags)
    flags |= os.O_NONBLOCK
    deadline = time.monotonic() + FIFO_WAIT
    while True:
        try:
            handle = os.open(path, flags)
        except OSError as error:
            if error.errno != errno.ENXIO or time.monotonic() > deadline:
                raise
            time.sleep(0.05)
            continue
        os.set_blocking(handle, True)
        return handle


def _fsync_directory(directory: Path) -> None:
    """Make the renames durable (best effort: not every file system allows it)."""
    with contextlib.suppress(OSError):
        handle = os.open(directory, os.O_RDONLY)
        try:
            os.fsync(handle)
        finally:
            os.close(handle)


@contextlib.contextmanager
def output_transaction(inputs: Iterable[str | os.PathLike] = ()) -> Iterator[Transaction]:
    """All outputs written inside the block are replaced together, or none is.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> with output_transaction() as outputs:
    ...     _ = outputs.declare(folder / "a.csv")  # checked before the work
    ...     write_text(folder / "a.csv", "x_m\\n1\\n")
    ...     write_text(folder / "b.txt", "done\\n")
    >>> sorted(p.name for p in folder.iterdir())
    ['a.csv', 'b.txt']
    """
    transaction = Transaction(tuple(os.fspath(p) for p in inputs))
    token = _ACTIVE.set(transaction)
    try:
        yield transaction
    except BaseException:
        transaction.discard()
        raise
    finally:
        _ACTIVE.reset(token)
    transaction.commit()


# --------------------------------------------------------------------------------------
# writers
# --------------------------------------------------------------------------------------


def write_bytes(path: str | os.PathLike, data: bytes, *, inputs: Iterable[str | os.PathLike] = ()) -> None:
    """Write ``data`` to ``path`` whole or not at all (see the module docstring).

    Inside :func:`output_transaction` the data is staged and replaced with the other
    outputs when the block ends; otherwise it is written now.

    Raises
    ------
    OutputError
        If ``path`` cannot receive it (nothing was replaced).
    """
    active = _ACTIVE.get()
    if active is not None:
        if inputs:
            check_destination(path, inputs=inputs)
        active.stage(path, data)
        return
    write_bytes_now(path, data, inputs=inputs)


def write_bytes_now(path: str | os.PathLike, data: bytes, *, inputs: Iterable[str | os.PathLike] = ()) -> None:
    """Write ``data`` to ``path`` whole or not at all, now, outside any active
    :func:`output_transaction` (for files that are not a command's outputs: an entry
    of the derivation cache is kept even when the command fails later).

    Raises
    ------
    OutputError
        If ``path`` cannot receive it (nothing was replaced).
    """
    transaction = Transaction(tuple(os.fspath(p) for p in inputs))
    try:
        transaction.stage(path, data)
    except BaseException:
        transaction.discard()
        raise
    transaction.commit()


def write_text(path: str | os.PathLike, text: str, *, inputs: Iterable[str | os.PathLike] = ()) -> None:
    """Write ``text`` (UTF-8, ``\\n`` line ends) whole or not at all; see :func:`write_bytes`."""
    write_bytes(path, text.encode("utf-8"), inputs=inputs)


def write_output(path: str | os.PathLike, text: str, inputs: Sequence[str | os.PathLike] = ()) -> None:
    """Write ``text`` to ``path`` whole or not at all; refuse to overwrite an input
    (the name the project's brief uses for :func:`write_text`)."""
    write_text(path, text, inputs=inputs)


# --------------------------------------------------------------------------------------
# CSV files (the text: express.io.text_formats)
# --------------------------------------------------------------------------------------


def write_csv(
    path: str | os.PathLike,
    columns: Mapping[str, Any],
    units: Mapping[str, str | None] | None = None,
    *,
    inputs: Iterable[str | os.PathLike] = (),
    markers: Iterable[str] = (),
) -> None:
    """Write :func:`csv_text` of ``columns`` to ``path`` (``"-"``: standard output)."""
    write_text(path, csv_text(columns, units, markers=markers), inputs=inputs)
