"""Limits on the work an input file may ask for, checked before the work starts.

A model file is data, and it may come from someone else: a few lines of text must
not be able to make EXPRESS run for minutes or exhaust memory.  Every limit below is
far beyond the bundled vehicles (a 20-car train has 220 bodies and 1 118 elements,
its file 0.4 MB) and is checked before the corresponding work, with a message that
names the item, the limit and, when there is one, the way to raise it
(``docs/reliability.md``).  The model-size defaults admit a train of up to 178 cars of
the forced-steering car (11 bodies, 56 elements and 112 connection points per car: a
150-car train has 1 650 bodies, 8 398 elements and 16 796 points, a 2.8 MB file), which
reads, generates and exports in well under a minute (the 100-car train of issue 16:
about 20 s, ``docs/benchmarks.md``).

=========================  =======================  ============================  ==========================
limit                      default                  override                      checked by
=========================  =======================  ============================  ==========================
input file size            16 MB                    ``EXPRESS_MAX_FILE_MB``       model and profile readers
bodies in a model          2 000                    ``EXPRESS_MAX_BODIES``        the model readers
elements in a model        10 000                   ``EXPRESS_MAX_ELEMENTS``      the model readers
connection points          20 000                   ``EXPRESS_MAX_POINTS``        the model readers
parameters                 10 000                   ``EXPRESS_MAX_PARAMETERS``    the model readers
expression length          1 000 characters         ``EXPRESS_MAX_EXPRESSION``    :mod:`express.base.expressions`
nesting depth              100 levels               none                          :mod:`express.base.expressions`
exponent                   integer, ``|n| <= 64``   none                          :mod:`express.base.expressions`
exact constants            within a double's range  none                          :mod:`express.base.expressions`
=========================  =======================  ============================  ==========================

The overrides are environment variables, read when a limit is checked, so that they
stay in the hands of the person who runs the command: a file cannot raise its own
limits.  A value must be a positive whole number (``EXPRESS_MAX_BODIES=5000``);
anything else is refused with a message naming the variable.

Examples
--------
>>> limit("bodies")
2000
>>> LIMITS["bodies"].variable
'EXPRESS_MAX_BODIES'
"""

from __future__ import annotations

import os
import stat
from dataclasses import dataclass
from pathlib import Path

from express.base.diagnostics import ModelError, Problem, UsageError
from express.base.reads import note_read

__all__ = ["LIMITS", "MAX_EXPONENT", "MAX_NESTING", "Limit", "exceeded", "input_kind_problem", "limit", "read_input_text"]

#: Deepest nesting of parentheses, signs and powers in one expression (no override:
#: no formula needs more, and Python's own recursion limit is not far beyond).
MAX_NESTING = 100
#: Largest integer exponent ``|n|`` of ``x^n`` in an expression (no override).
MAX_EXPONENT = 64


@dataclass(frozen=True)
class Limit:
    """One limit: its default, the environment variable that raises it, and the unit
    of its value in messages (``"bodies"``, ``"MB"``)."""

    name: str
    default: int
    variable: str
    unit: str
    why: str

    def value(self) -> int:
        """The limit in force (the variable's value when set).

        Raises
        ------
        UsageError
            When the variable is set to something else than a positive whole number.
        """
        text = os.environ.get(self.variable, "").strip()
        if not text:
            return self.default
        try:
            value = int(text)
        except ValueError:
            value = 0
        if value <= 0:
            raise UsageError(f"environment variable {self.variable}={text!r}: expected a positive whole number")
        return value


LIMITS = {
    limit.name: limit
    for limit in (
        Limit("file_mb", 16, "EXPRESS_MAX_FILE_MB", "MB", "input file size (models, wheel/rail profiles, delta-r)"),
        Limit("bodies", 2000, "EXPRESS_MAX_BODIES", "bodies", "bodies in a model"),
        Limit("elements", 10000, "EXPRESS_MAX_ELEMENTS", "elements", "elements in a model"),
        Limit("points", 20000, "EXPRESS_MAX_POINTS", "connection points", "connection points in a model"),
        Limit("parameters", 10000, "EXPRESS_MAX_PARAMETERS", "parameters", "parameters in a model"),
        Limit("expression", 1000, "EXPRESS_MAX_EXPRESSION", "characters", "length of one expression"),
    )
}


def limit(name: str) -> int:
    """The value in force of the limit ``name`` (a key of :data:`LIMITS`)."""
    return LIMITS[name].value()


def exceeded(name: str, found: int) -> str | None:
    """``None`` when ``found`` is within the limit ``name``, else the message to give.

    Examples
    --------
    >>> exceeded("bodies", 12) is None
    True
    >>> exceeded("bodies", 5000)
    '5000 bodies, more than the limit of 2000 bodies (raise it with the environment variable EXPRESS_MAX_BODIES)'
    """
    spec = LIMITS[name]
    allowed = spec.value()
    if found <= allowed:
        return None
    return (
        f"{found} {spec.unit}, more than the limit of {allowed} {spec.unit} "
        f"(raise it with the environment variable {spec.variable})"
    )


_KINDS = (
    (stat.S_ISDIR, "a directory"),
    (stat.S_ISCHR, "a character device (such as /dev/null, /dev/zero or a terminal)"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def input_kind_problem(path: str | Path, fifo: bool = True) -> str | None:
    """What is wrong with ``path`` as an input file, judged by its kind before it is
    opened (opening a FIFO or a device may block or never end), or None (also for a
    file that cannot be looked at: opening it says why).

    A regular file is an input; so is a FIFO (a pipe from the shell, ``<(...)``) when
    ``fifo``, and :func:`read_input_text` refuses one without a writer.

    Examples
    --------
    >>> input_kind_problem("/dev/null")
    'not a regular file but a character device (such as /dev/null, /dev/zero or a terminal)'
    """
    try:
        mode = os.stat(path).st_mode
    except OSError:  # a missing file: the reader's own message when it opens it
        return None
    if stat.S_ISREG(mode) or (fifo and stat.S_ISFIFO(mode)):
        return None
    kind = next((words for test, words in _KINDS if test(mode)), "a FIFO (named pipe)" if stat.S_ISFIFO(mode) else "")
    return f"not a regular file but {kind}" if kind else "not a regular file"


def _read_fifo(path: Path, most: int) -> bytes | None:
    """The bytes of a FIFO, or None when nobody writes into it (opened without blocking)."""
    handle = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    try:
        try:
            first = os.read(handle, most + 1)
        except BlockingIOError:  # a writer, no data yet
            first = b""
            writer = True
        else:
            writer = bool(first)
        if not writer:
            return None
        os.set_blocking(handle, True)
        chunks = [first]
        size = len(first)
        while size <= most:
            chunk = os.read(handle, most + 1 - size)
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        return b"".join(chunks)
    finally:
        os.close(handle)


def read_input_text(path: str | Path, item: str = "", what: str = "the file") -> str:
    """The text of an input file (a model, a profile), refused beyond the size limit
    before it is read whole (``EXPRESS_MAX_FILE_MB``) and when it is not UTF-8 text.

    A regular file or a pipe from the shell is accepted; a directory, a device
    (``/dev/null``, ``/dev/zero``), a socket or a FIFO that nobody writes into is refused
    by its kind before it is read (:func:`input_kind_problem`).  Newlines are made universal, as ``open()`` in text mode does; ``what``
    names the file in the message of one that cannot be read.

    Raises
    ------
    ModelError
        For a file that cannot be read, is too large or is not UTF-8 text.
    """
    path = Path(path)
    most = limit("file_mb") * 1024 * 1024

    def refuse(message: str) -> ModelError:
        return ModelError([Problem(str(path), None, item, message)])

    kind = input_kind_problem(path)
    if kind is not None:
        raise refuse(kind)
    try:
        if stat.S_ISFIFO(os.stat(path).st_mode):
            fifo = _read_fifo(path, most)
            if fifo is None:
                raise refuse("a FIFO (named pipe) that nobody writes into")
            data = fifo
        else:
            with open(path, "rb") as file:
                data = file.read(most + 1)
    except OSError as error:
        raise refuse(f"cannot read {what} ({error.strerror or error})") from None
    if len(data) > most:
        raise refuse(
            f"file larger than the limit of {most // (1024 * 1024)} MB "
            f"(raise it with the environment variable {LIMITS['file_mb'].variable})"
        )
    note_read(path, data)  # the derivation cache's key (express.base.reads)
    if b"\0" in data:
        raise refuse("not a UTF-8 text file (it holds NUL bytes)")
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as error:
        raise refuse(f"not a UTF-8 text file (byte {error.start + 1} cannot be decoded)") from None
    return text.replace("\r\n", "\n").replace("\r", "\n")
