"""Reading TOML: the one parser that reports a syntax error as a :class:`Problem` with its
line (:func:`parse_toml`), and line numbers of TOML tables and keys, for messages that
point into a file.

:mod:`tomllib` returns plain data without positions, so the readers (model files,
track files) scan the text once more with :func:`line_index` and look a key path up
with :func:`find_line` when they report a problem. The scan is best effort (it reads
headers and ``key =`` lines, not full TOML), so a missing line is never an error.

Example
-------
>>> index = line_index('[bodies.B1]\\nmass = "m"\\n')
>>> index[("bodies", "B1", "mass")]
2
>>> find_line(index, ("bodies", "B1", "inertia"))
1
"""

from __future__ import annotations

import re
import sys
from collections.abc import Mapping, Sequence
from typing import Any

from express.base.diagnostics import ModelError, Problem

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = ["KeyPath", "find_line", "line_index", "parse_toml"]

#: A key path: table names and keys, and with ``number_arrays`` the 1-based position
#: (an int) of an entry of an array of tables, e.g. ``("segment", 2, "length")``.
KeyPath = tuple[str | int, ...]

_HEADER = re.compile(r"\s*(\[\[?)\s*([^\]]+?)\s*\]\]?\s*(?:#.*)?$")
_KEY = re.compile(r"\s*([A-Za-z0-9_\-\"'.]+)\s*=")


def _parts(dotted: str) -> tuple[str, ...]:
    return tuple(part.strip().strip("\"'") for part in dotted.split("."))


def line_index(text: str, *, number_arrays: bool = False) -> dict[KeyPath, int]:
    """Map TOML key paths to the line defining them (headers and ``key =`` lines).

    Parameters
    ----------
    text : str
        The TOML text.
    number_arrays : bool
        If true, the n-th ``[[name]]`` header of an array of tables opens the path
        ``(name, n)`` (n from 1), so that its keys are ``(name, n, key)``; otherwise
        every entry shares the path ``(name,)`` and the first line wins.

    Returns
    -------
    dict
        Key path -> 1-based line number of its first definition. A header also defines
        every prefix of its path.
    """
    index: dict[KeyPath, int] = {}
    table: KeyPath = ()
    counts: dict[tuple[str, ...], int] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        header = _HEADER.match(line)
        if header:
            names = _parts(header.group(2))
            table = names
            if number_arrays and header.group(1) == "[[":
                counts[names] = counts.get(names, 0) + 1
                table = (*names, counts[names])
            for end in range(1, len(table) + 1):
                index.setdefault(table[:end], number)
            continue
        key = _KEY.match(line)
        if key:
            index.setdefault(table + _parts(key.group(1)), number)
    return index


def find_line(index: Mapping[KeyPath, int], path: Sequence[str | int]) -> int | None:
    """Line of ``path``, or of its longest prefix that has one; None if none has."""
    for end in range(len(path), 0, -1):
        found = index.get(tuple(path[:end]))
        if found is not None:
            return found
    return None


def parse_toml(text: str, source: str) -> dict[str, Any]:
    """The data of a TOML text; a syntax error is a :class:`ModelError` whose one problem
    gives the file, the line and what is wrong.

    Parameters
    ----------
    text : str
        The TOML text.
    source : str
        The file's name as the user gave it (shown in the message).

    Returns
    -------
    dict
        The parsed tables.

    Raises
    ------
    ModelError
        ``<source>:<line>: TOML: not valid TOML: <reason>``, or arrays or tables nested
        too deeply to read.

    Examples
    --------
    >>> parse_toml("[study\\n", "s.toml")
    Traceback (most recent call last):
    ...
    express.base.diagnostics.ModelError: s.toml:1: TOML: not valid TOML: Expected ']' at the end of a table declaration
    """
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        match = re.search(r"line (\d+)", str(error))
        line = int(match.group(1)) if match else None
        message = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(error))
        raise ModelError([Problem(source, line, "TOML", f"not valid TOML: {message}")]) from None
    except RecursionError:
        raise ModelError([Problem(source, None, "TOML", "arrays or tables nested too deeply to read")]) from None
