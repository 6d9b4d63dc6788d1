"""Small helpers shared by the track modules: number checks and scalar/array handling.

A function of the distance ``s`` takes a float or an array and returns the same kind;
:func:`as_input` and :func:`as_output` do the conversion once. Field checks return
``(field, message)`` pairs, so that a constructor can raise them and a file reader can
report each at the line of its key.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from express.base.diagnostics import ArgumentError

__all__ = [
    "FieldProblem",
    "FloatArray",
    "as_input",
    "as_output",
    "is_finite_number",
    "is_number",
    "raise_if",
]

FloatArray = NDArray[np.float64]
#: A problem with one field of a record: ``(field name, what is wrong)``.
FieldProblem = tuple[str, str]


def is_number(x: Any) -> bool:
    """True for an int or float (NumPy's too), False for a bool."""
    return isinstance(x, (int, float, np.integer, np.floating)) and not isinstance(x, bool)


def is_finite_number(x: Any) -> bool:
    """True for a finite int or float (not a bool); False for an int beyond float range."""
    if not is_number(x):
        return False
    try:
        return math.isfinite(float(x))
    except OverflowError:
        return False


def as_input(s: ArrayLike) -> tuple[FloatArray, bool]:
    """``s`` as a float array, and whether it was a scalar."""
    arr = np.asarray(s, dtype=float)
    return arr, arr.ndim == 0


def as_output(values: ArrayLike, scalar: bool) -> FloatArray | float:
    """``values`` as a float if the input was a scalar, else as an array."""
    arr = np.asarray(values, dtype=float)
    return float(arr) if scalar else arr


def raise_if(problems: Sequence[FieldProblem], what: str) -> None:
    """Raise ``ValueError("<what>: msg; msg")`` if there are problems."""
    if problems:
        raise ArgumentError(f"{what}: " + "; ".join(message for _, message in problems))
