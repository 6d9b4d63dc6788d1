"""No NaN or inf as a result (issue 26): the check every writer of results makes.

A non-finite number in a result means the analysis gave none there; EXPRESS never
writes or prints it. :func:`require_finite` raises
:class:`~express.base.diagnostics.AnalysisError` (exit status 1) naming the quantity,
the first non-finite position and how many there are, before anything is written.
:func:`express.io.text_formats.csv_text`, :func:`~express.io.text_formats.json_safe`,
:func:`~express.io.output.npz_bytes` and :func:`~express.io.output.mat_bytes` call it,
so every command's CSV, JSON, NPZ and MAT results are checked in one place; the
command line checks what a command prints (:class:`FiniteText`). A documented marker of
"no value" (an empty CSV cell, a JSON ``null``) is written from ``None`` or, for a CSV
column named as a marker, from nan (``docs/reliability.md``).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

from express.base.diagnostics import AnalysisError

__all__ = [
    "FiniteText", "first_non_finite", "non_finite_error", "require_finite", "require_finite_columns",
    "require_finite_text",
]

#: A nan or inf printed as a number (``nan``, ``-inf``, ``+Inf``, ``NaN``), not part of a word
#: nor the second term of a ratio (``1:inf``, the documented upright rail: an input echoed).
_NON_FINITE = re.compile(r"(?<![\w.:])[-+]?(?:nan|inf|infinity)(?![\w(])", re.IGNORECASE)


def first_non_finite(values: Any) -> tuple[tuple[int, ...], complex | float, int] | None:
    """The index, value and count of the non-finite entries of ``values`` (numbers of
    any shape), or None when all are finite (or the values are not numbers)."""
    import numpy as np

    array = np.asarray(values)
    if array.dtype.kind not in "fc" or array.size == 0:
        return None
    bad = ~np.isfinite(array)
    if not bad.any():
        return None
    index = tuple(int(i) for i in np.argwhere(bad)[0])
    return index, array[index].item(), int(bad.sum())


def non_finite_error(quantity: str, value: complex | float, where: str, count: int, size: int) -> AnalysisError:
    """The error of a non-finite result: ``quantity``, its first bad ``value`` and ``where``
    (``""``: the quantity is one number)."""
    at = f" at {where}" if where else ""
    more = f" ({count} of {size} values)" if count > 1 else ""
    return AnalysisError(f"{quantity}: not a finite number ({value}){at}{more}: the analysis gave no "
                         "valid result there; nothing written")


def require_finite(quantity: str, values: Any) -> None:
    """Refuse a result with a nan or inf.

    Parameters
    ----------
    quantity : str
        What the values are, as the message names them (``"frequency response Q1"``).
    values : array_like
        Numbers of any shape; text and integers pass.

    Raises
    ------
    AnalysisError
        At the first non-finite entry (its index), with the count.

    Examples
    --------
    >>> require_finite("speeds", [1.0, 2.0])
    >>> require_finite("speeds", [1.0, float("nan")])
    Traceback (most recent call last):
    ...
    express.base.diagnostics.AnalysisError: speeds: not a finite number (nan) at index 1: the analysis gave no valid result there; nothing written
    """
    import numpy as np

    found = first_non_finite(values)
    if found is None:
        return
    index, value, count = found
    where = f"index {index[0]}" if len(index) == 1 else f"index {list(index)}"
    raise non_finite_error(quantity, value, where, count, int(np.size(values)))


def require_finite_text(quantity: str, text: str) -> None:
    r"""Refuse ``text`` (a printed table, a report) in which a nan or inf is printed as a
    number (``nan``, ``-inf``, ``NaN``: not part of a word).

    Raises
    ------
    AnalysisError
        Quoting the line where it is (at most 120 characters).

    Examples
    --------
    >>> require_finite_text("eigen", "mode 1: 1.2 Hz, information\n")
    >>> require_finite_text("contact-geometry", "S1002 on 60E1: inclination 1:inf\n")
    >>> require_finite_text("eigen", "mode 1: nan Hz\n")
    Traceback (most recent call last):
    ...
    express.base.diagnostics.AnalysisError: eigen: a result is not a finite number (nan) in the line 'mode 1: nan Hz': the analysis gave no valid result there
    """
    match = _NON_FINITE.search(text)
    if match is None:
        return
    line = text[:match.start()].rsplit("\n", 1)[-1] + text[match.start():].split("\n", 1)[0]
    raise AnalysisError(f"{quantity}: a result is not a finite number ({match.group(0).strip()}) in the line "
                        f"{line.strip()[:120]!r}: the analysis gave no valid result there")


def require_finite_columns(columns: Sequence[Any], headers: Sequence[str], markers: Sequence[bool],
                           labels: Sequence[str]) -> None:
    """Refuse a CSV table with a nan or inf: the column's header, the row (from 1) and
    ``labels`` (the first column's cells) there. A column marked in ``markers`` may
    hold nan, its documented "no value"; inf never is one.

    Examples
    --------
    >>> require_finite_columns([[0.0, 0.5], [1.0, float("inf")]], ["t_s", "Q1_N"], [False, False], ["0", "0.5"])
    Traceback (most recent call last):
    ...
    express.base.diagnostics.AnalysisError: Q1_N: not a finite number (inf) at row 2 (t_s = 0.5): the analysis gave no valid result there; nothing written
    """
    import numpy as np

    for k, (values, header, marker) in enumerate(zip(columns, headers, markers, strict=True)):
        array = np.asarray(values)
        if marker and array.dtype.kind == "f":
            array = np.where(np.isnan(array), 0.0, array)
        found = first_non_finite(array)
        if found is not None:
            row = found[0][0]
            first = "" if k == 0 else f" ({headers[0]} = {labels[row]})"
            raise non_finite_error(header, found[1], f"row {row + 1}{first}", found[2], array.size)


class FiniteText:
    """A text stream in front of ``stream`` that refuses to pass on a nan or inf printed
    as a number (a command's standard output, :func:`require_finite_text`). Everything
    else (``buffer``, ``isatty``, ``fileno``) is the stream's own."""

    def __init__(self, stream: Any, command: str) -> None:
        self._stream = stream
        self._command = command

    def write(self, text: str) -> int:
        require_finite_text(self._command, text)
        return self._stream.write(text)

    def flush(self) -> None:
        self._stream.flush()

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)
