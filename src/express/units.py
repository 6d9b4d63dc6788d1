"""Units of parameter values in model files, converted to SI.

A unit is a product/quotient of known symbols with optional integer powers:
``kg``, ``kN/m``, ``kN*s/m``, ``kg*m^2``, ``t*m2``, ``km/h``, ``MN*m/rad``.
Every value is stored in SI (kg, m, s, N, rad); the unit the user wrote is kept
for display.

Examples
--------
>>> to_si(120, "km/h")
33.333333333333336
>>> to_si(5, "MN/m")
5000000.0
"""

from __future__ import annotations

import re

__all__ = ["KMH", "UnitError", "unit_factor", "to_si", "parse_quantity"]

#: One km/h in m/s.
KMH = 1.0 / 3.6

_BASE = {
    "1": 1.0,
    "-": 1.0,
    "rad": 1.0,
    "mrad": 1e-3,
    "deg": 3.141592653589793 / 180.0,
    "m": 1.0,
    "mm": 1e-3,
    "cm": 1e-2,
    "km": 1e3,
    "kg": 1.0,
    "t": 1e3,
    "g": 1e-3,
    "s": 1.0,
    "h": 3600.0,
    "min": 60.0,
    "N": 1.0,
    "kN": 1e3,
    "MN": 1e6,
    "GN": 1e9,
    "Pa": 1.0,
    "kPa": 1e3,
    "MPa": 1e6,
    "GPa": 1e9,
    "Hz": 1.0,
}
_FACTOR = re.compile(r"([A-Za-z]+|1|-)(?:\^?(-?\d+))?\Z")
_QUANTITY = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*\Z")


class UnitError(ValueError):
    """A unit or quantity that cannot be understood; the message says why."""


def unit_factor(unit: str) -> float:
    """SI factor of ``unit`` (``"kN/m"`` -> 1000.0).

    Raises
    ------
    UnitError
        For an unknown symbol or a malformed unit.
    """
    text = unit.replace(" ", "")
    if not text:
        return 1.0
    factor = 1.0
    # split into factors keeping the operator that precedes each
    parts = re.split(r"([*/])", text)
    sign = 1
    for part in parts:
        if part == "*":
            sign = 1
            continue
        if part == "/":
            sign = -1
            continue
        match = _FACTOR.match(part)
        if match is None or match.group(1) not in _BASE:
            known = ", ".join(sorted(k for k in _BASE if k not in ("1", "-")))
            raise UnitError(f'unknown unit "{part}" in "{unit}" (known: {known})')
        power = int(match.group(2)) if match.group(2) else 1
        factor *= _BASE[match.group(1)] ** (sign * power)
    return factor


def to_si(value: float, unit: str) -> float:
    """Convert ``value`` given in ``unit`` to SI."""
    return float(value) * unit_factor(unit)


def parse_quantity(text: str) -> tuple[float, str]:
    """Split ``"95 mm"`` into ``(0.095, "mm")`` (value in SI, unit as written)."""
    match = _QUANTITY.match(text)
    if match is None:
        raise UnitError(f'"{text}" is not a number with a unit (e.g. "95 mm")')
    unit = match.group(2)
    return to_si(float(match.group(1)), unit), unit
