"""Formatting of the reference files and the comparison rule of docs/reference-benchmark.md.

Numbers are printed with a fixed count of significant digits (``1.23456789012345e+06``),
rounded half-even from 40 of the 50 computed digits; an exact zero prints as ``0``. JSON is written
with sorted keys and two-space indentation, CSV with ``\\n`` line ends: the same data
gives the same bytes.
"""

from __future__ import annotations

import csv
import io
import json
from collections.abc import Iterable, Sequence
from decimal import Decimal

import mpmath
import numpy as np

#: A value below this fraction of the largest of its group is a rounding residue of an
#: exact zero and prints as 0 (the residue is about 1e-45 of it at 50 digits, 1e-26 at
#: the 30 digits of the check; no value of the benchmark comes near it otherwise).
ZERO = mpmath.mpf("1e-20")
#: The comparison rule: ``|a - b| <= rtol * max(|b|, FLOOR * s)``, ``s`` the largest
#: magnitude of the group (a matrix, the eigenvalues at one speed, one response).
FLOOR = 1e-6


class Number(str):
    """A number already formatted: written into JSON without quotes."""


def number(value, digits: int | None = None, scale=None) -> Number:
    """``value`` as text: with ``digits`` significant digits (rounded half-even), or as
    the shortest text that reads back as the same double when ``digits`` is None (the
    inputs: parameter values, speeds, frequencies). ``scale``: see :data:`ZERO`.

    Call it inside the precision the value was computed at (:func:`mpmath.workdps`):
    the last 10 of its digits are taken as uncertain."""
    if digits is None:
        return Number(repr(float(value)))
    if mpmath.mp.dps - 10 < digits:  # mpf() below would round the value to the low precision
        raise ValueError(f"print {digits} digits inside the working precision, not at {mpmath.mp.dps} digits")
    value = mpmath.mpf(value)
    if value == 0 or (scale is not None and abs(value) < ZERO * scale):
        return Number("0")
    # rounded first to the digits the working precision makes certain (40 of 50): an
    # exact decimal tie (an entry such as 2.943043781365325e7) stays a tie and rounds
    # half-even, whatever the binary rounding residue beyond
    text = mpmath.nstr(value, min(40, mpmath.mp.dps - 10), min_fixed=1, max_fixed=0)
    mantissa, exponent = format(Decimal(text), f".{digits - 1}e").split("e")
    return Number(f"{mantissa}e{int(exponent):+03d}")


def csv_table(header: Sequence[str], rows: Iterable[Sequence[str]]) -> str:
    """CSV text of a header and rows of texts."""
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(header)
    writer.writerows(rows)
    return out.getvalue()


def json_document(value, indent: int = 0) -> str:
    """JSON text with sorted keys; :class:`Number` values unquoted; lists of scalars on
    one line."""
    pad, inner = "  " * indent, "  " * (indent + 1)
    if isinstance(value, Number):
        return str(value)
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = [f"{inner}{json.dumps(str(k))}: {json_document(v, indent + 1)}" for k, v in sorted(value.items())]
        text = "{\n" + ",\n".join(items) + f"\n{pad}}}"
        return text + ("\n" if indent == 0 else "")
    if isinstance(value, (list, tuple)):
        if all(not isinstance(v, (dict, list, tuple)) for v in value):
            return "[" + ", ".join(json_document(v, indent + 1) for v in value) + "]"
        return "[\n" + ",\n".join(inner + json_document(v, indent + 1) for v in value) + f"\n{pad}]"
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    return json.dumps(str(value))


def _complex_list(values) -> list:
    if isinstance(values, mpmath.matrix):
        return [mpmath.mpmathify(values[i, j]) for i in range(values.rows) for j in range(values.cols)]
    if isinstance(values, np.ndarray):
        return [mpmath.mpmathify(complex(x)) for x in values.ravel()]
    return [mpmath.mpmathify(x if not isinstance(x, np.generic) else complex(x)) for x in values]


def relative_errors(computed, reference, *, match: bool = False, floor: float = FLOOR) -> np.ndarray:
    """``|a - b| / max(|b|, floor * s)`` of every entry, ``s = max|b|``, computed in
    mpmath; ``|a| / s`` where ``b`` is an exact zero (below :data:`ZERO` times ``s``: a
    structural zero, whose double-precision value is rounding residue).

    Parameters
    ----------
    computed, reference : array, mpmath matrix or sequence of (complex) numbers
        The same shape (flattened row by row).
    match : bool
        Pair the entries first by least total distance (eigenvalues come in any order):
        :func:`scipy.optimize.linear_sum_assignment`.
    """
    a, b = _complex_list(computed), _complex_list(reference)
    if len(a) != len(b):
        raise ValueError(f"{len(a)} values against {len(b)} in the reference")
    if not b:
        return np.zeros(0)
    if match:
        from scipy.optimize import linear_sum_assignment

        cost = np.abs(np.subtract.outer(np.array([complex(x) for x in a]), np.array([complex(x) for x in b])))
        rows, columns = linear_sum_assignment(cost)
        order = dict(zip(columns.tolist(), rows.tolist(), strict=True))
        a = [a[order[j]] for j in range(len(b))]
    largest = max(abs(x) for x in b)
    if largest == 0:
        return np.array([float(abs(x)) for x in a])
    scale = largest * mpmath.mpf(floor)
    return np.array([float(abs(x) / largest) if abs(y) < ZERO * largest else float(abs(x - y) / max(abs(y), scale))
                     for x, y in zip(a, b, strict=True)])
