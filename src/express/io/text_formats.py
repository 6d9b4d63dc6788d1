"""The text formats of results: CSV with units in the header, JSON.

This module owns the text of a result before it is written: a column's header with its
unit (:func:`column_name`), CSV of equally long columns (:func:`csv_text`) and JSON
without nan or inf (:func:`json_safe`, :func:`json_text`). Both are deterministic: the
same data give the same text. The writer is :mod:`express.io.output`; a nan or inf is
refused by :mod:`express.io.finite`.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Iterable, Mapping
from typing import Any

from express.io.finite import non_finite_error, require_finite, require_finite_columns

__all__ = ["column_name", "csv_text", "json_safe", "json_text"]


# --------------------------------------------------------------------------------------
# CSV with units in the header
# --------------------------------------------------------------------------------------

_UNIT_TOKENS = {"Hz": "hz", "km/h": "kmh", "m/s": "m_s", "m/s^2": "m_s2", "rad/s": "rad_s", "1/m": "1_m", "1/s": "1_s"}


def column_name(name: str, unit: str | None) -> str:
    """A CSV header with its unit: ``("Q1", "N") -> "Q1_N"``, ``("frequency", "Hz") ->
    "frequency_hz"``, ``("d1", "m") -> "d1_m"``; dimensionless (``""``, ``"1"``,
    ``None``) keeps the bare name.

    Examples
    --------
    >>> column_name("acc", "m/s^2"), column_name("QP1", "")
    ('acc_m_s2', 'QP1')
    """
    if not unit or unit in ("1", "-"):
        return name
    token = _UNIT_TOKENS.get(unit)
    if token is None:
        token = unit.replace("^", "").replace("*", "").replace("/", "_").replace(" ", "")
    return f"{name}_{token}"


def csv_text(columns: Mapping[str, Any], units: Mapping[str, str | None] | None = None, *,
             markers: Iterable[str] = ()) -> str:
    """CSV text of equally long ``columns`` (name -> values, SI); the header carries each
    column's unit (:func:`column_name`).  Numbers are written with 9 significant digits;
    text values as they are; None as an empty cell.

    A nan or inf is no result: :class:`AnalysisError` (:func:`~express.io.finite.require_finite_columns`)
    unless it is the nan of a column in ``markers``, a documented "no value": an empty cell.

    Examples
    --------
    >>> print(csv_text({"t": [0.0, 0.5], "v": [1.0, float("nan")]}, {"t": "s"}, markers=["v"]), end="")
    t_s,v
    0,1
    0.5,
    """
    units = units or {}
    names = list(columns)
    headers = [column_name(name, units.get(name)) for name in names]
    cells = [_cells(columns[name]) for name in names]
    require_finite_columns([columns[name] for name in names], headers, [name in set(markers) for name in names],
                           cells[0] if cells else [])
    lengths = {len(column) for column in cells}
    if len(lengths) > 1:
        raise ValueError(f"columns of different lengths: {dict(zip(names, map(len, cells), strict=True))}")
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(headers)
    writer.writerows(zip(*cells, strict=True))
    return buffer.getvalue()


def _cells(values: Any) -> list[str]:
    import numpy as np

    array = np.asarray(values)
    if array.dtype.kind in "biuf":
        return [f"{float(value):.9g}" if math.isfinite(value) else "" for value in array.astype(float).ravel()]
    return ["" if value is None else str(value) for value in array.ravel()]


# --------------------------------------------------------------------------------------
# JSON
# --------------------------------------------------------------------------------------


def json_safe(value: Any, where: str = "result") -> Any:
    """A copy of ``value`` that :func:`json.dumps` accepts with ``allow_nan=False``:
    NumPy arrays and scalars become lists and Python numbers; None stays ``null`` (the
    documented "no value").

    Raises
    ------
    AnalysisError
        A nan or inf (:mod:`express.io.finite`), named by its path in ``value``
        (``where``, keys and indices: ``result.sweep[2].critical_speed``).
    """
    import numpy as np

    if isinstance(value, dict):
        return {str(k): json_safe(v, f"{where}.{k}") for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [json_safe(v, f"{where}[{i}]") for i, v in enumerate(value)]
    if isinstance(value, np.ndarray):
        require_finite(where, value)
        return json_safe(value.tolist(), where)
    if isinstance(value, (float, np.floating)):
        number = float(value)
        if not math.isfinite(number):
            raise non_finite_error(where, number, "", 1, 1)
        return number
    if isinstance(value, np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    return value


def json_text(value: Any) -> str:
    """Indented JSON of :func:`json_safe` ``(value)``, ending in a newline."""
    import json

    return json.dumps(json_safe(value), indent=2, allow_nan=False) + "\n"
