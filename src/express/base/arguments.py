"""A library function's arguments in SI: numbers, quantities as text, pint quantities.

This module owns how the library's functions take a physical argument: a number (SI,
never the command line's shorthand), a quantity with its unit as text (``"95 km/h"``) or
a :class:`pint.Quantity` of any registry, one value (:func:`si_argument`) or an array
(:func:`si_arguments`), refused with an :class:`~express.base.diagnostics.ArgumentError`
naming the argument. The units themselves are :mod:`express.base.units`.
"""

from __future__ import annotations

import math

from express.base.units import UnitError, parse_quantity, si_unit

__all__ = ["si_argument", "si_arguments"]

#: An example quantity of each dimension, for the message of a wrong argument.
_EXAMPLE = {"speed": "95 km/h", "length": "600 m", "time": "5 ms", "frequency": "20 Hz"}


def si_argument(value: object, dimension: str, argument: str) -> float:
    """A library function's argument in SI: a number (SI, never the command line's
    shorthand), a quantity with its unit as text (``"95 km/h"``) or a
    :class:`pint.Quantity` (any registry).

    Parameters
    ----------
    value : float, str or pint.Quantity
    dimension : str
        Its dimension (a name of :data:`DIMENSIONS`: ``"speed"``, ``"length"``, ...).
    argument : str
        The argument's name, for the message.

    Raises
    ------
    ArgumentError
        Naming the argument: a wrong type, a unit of another dimension, not finite.

    Examples
    --------
    >>> si_argument("95 km/h", "speed", "speed")
    26.38888888888889
    >>> si_argument(30, "speed", "speed")
    30.0
    """
    from express.base.diagnostics import ArgumentError

    if isinstance(value, bool):
        raise ArgumentError(f"{argument} must be a number (SI) or a quantity, got {value!r}")
    if hasattr(value, "magnitude") and hasattr(value, "units"):  # a pint quantity of any registry
        value = f"{float(value.magnitude)!r} {value.units:~}"
    if isinstance(value, str):
        try:
            number, _ = parse_quantity(value, dimension)
        except UnitError as error:
            raise ArgumentError(f"{argument}: {error}") from None
        return number
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ArgumentError(f"{argument} must be a number (SI, {si_unit(dimension)}) or a quantity such as "
                            f"\"{_EXAMPLE.get(dimension, '1 m')}\", got {type(value).__name__} {value!r:.60}") from None
    if not math.isfinite(number):
        raise ArgumentError(f"{argument} must be finite, got {number!r}")
    return number


def si_arguments(values: object, dimension: str, argument: str):
    """A library function's array argument in SI (:func:`si_argument` for each value):
    numbers (SI), a sequence of quantities (text or pint), one pint quantity holding an
    array, or one quantity as text (a single value).

    Parameters
    ----------
    values : array_like, str or pint.Quantity
    dimension : str
        Their dimension (a name of :data:`DIMENSIONS`).
    argument : str
        The argument's name, for the message.

    Returns
    -------
    numpy.ndarray, float
        The values [SI], of the shape given (0-D for one value).

    Raises
    ------
    ArgumentError
        Naming the argument, as :func:`si_argument`.

    Examples
    --------
    >>> si_arguments(["36 km/h", 20.0], "speed", "speeds").tolist()
    [10.0, 20.0]
    """
    import numpy as np

    if hasattr(values, "magnitude") and hasattr(values, "units"):  # a pint quantity, maybe of an array
        magnitude = np.asarray(values.magnitude, dtype=float)
        return magnitude * si_argument(f"1 {values.units:~}", dimension, argument)
    if isinstance(values, str):
        return np.asarray(si_argument(values, dimension, argument))
    if isinstance(values, np.ndarray) and values.dtype.kind in "fiu":  # numbers: SI, as they are
        return values.astype(float)
    if not isinstance(values, (np.ndarray, list, tuple)) and hasattr(values, "__iter__"):
        values = list(values)  # a generator, a range
    array = np.asarray(values, dtype=object)
    if array.dtype == object and all(isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool)
                                     for v in array.flat):
        return np.asarray(array, dtype=float)
    return np.asarray([si_argument(v, dimension, argument) for v in array.flat], dtype=float).reshape(array.shape)
