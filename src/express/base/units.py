"""Units of quantities: parsing, dimensions, conversion to SI and display.

A unit is a product/quotient of unit symbols with optional integer powers, as people
write them: ``kg``, ``t`` (tonne), ``kN/mm``, ``kN*s/m``, ``kg*m^2``, ``t*m2``,
``km/h``, ``MN*m/rad``, ``deg``, ``1/m``; ``-``, ``1`` or nothing for a pure number.
The grammar is parsed here (bounded: short text, small integer exponents, shallow
parentheses) and each symbol is looked up in `pint <https://pint.readthedocs.io>`_'s
registry, imported on first use so that importing this module stays cheap.

Inside EXPRESS every value is SI (kg, m, s, N, rad); the unit the user wrote is kept
for display (:func:`format_quantity`).  A quantity's *dimension* is the exponents of
mass, length and time (:class:`Dimension`); the usual ones have names
(:data:`DIMENSIONS`: ``"stiffness"`` is N/m, ``"rotational_stiffness"`` N*m/rad, ...).
Angles are dimensionless, as in SI, but a unit keeps the power of the angle in it:
an angle unit is refused for a pure ratio (``"dimensionless"``: a conicity, a slope),
and a frequency given in ``rad/s`` or ``rpm`` is converted to Hz with its 2 pi
(:func:`parse_quantity`).

Examples
--------
>>> to_si(120, "km/h")
33.333333333333336
>>> parse_quantity("5 kN/mm", "stiffness")
(5000000.0, 'kN/mm')
>>> format_quantity(15000.0, "kN*s/m")
'15 kN*s/m'
>>> dimension_of("MN*m/rad")
'rotational_stiffness'
"""

from __future__ import annotations

import functools
import math
import re
from dataclasses import dataclass
from fractions import Fraction

__all__ = [
    "DIMENSIONS",
    "KMH",
    "Dimension",
    "UnitError",
    "check_dimension",
    "describe_dimension",
    "dimension",
    "dimension_of",
    "format_quantity",
    "is_angular_frequency",
    "parse_quantity",
    "si_unit",
    "to_si",
    "unit_dimension",
    "unit_factor",
]

#: One km/h in m/s.
KMH = 1.0 / 3.6

_MAX_UNIT_LENGTH = 60
_MAX_EXPONENT = 6
_MAX_DEPTH = 3
_MAX_DIMENSION_EXPONENT = 12


class UnitError(ValueError):
    """A unit or quantity that cannot be understood or has the wrong dimension."""


@dataclass(frozen=True)
class Dimension:
    """Exponents of mass, length and time of a quantity (angles are dimensionless).

    Examples
    --------
    >>> dimension("force") / dimension("length") == dimension("stiffness")
    True
    """

    mass: Fraction = Fraction(0)
    length: Fraction = Fraction(0)
    time: Fraction = Fraction(0)

    def __mul__(self, other: Dimension) -> Dimension:
        return Dimension(self.mass + other.mass, self.length + other.length, self.time + other.time)

    def __truediv__(self, other: Dimension) -> Dimension:
        return Dimension(self.mass - other.mass, self.length - other.length, self.time - other.time)

    def __pow__(self, power: int | Fraction) -> Dimension:
        p = Fraction(power)
        return Dimension(self.mass * p, self.length * p, self.time * p)

    def __repr__(self) -> str:
        return f"Dimension({self.si()!r})"

    @property
    def is_dimensionless(self) -> bool:
        return self.mass == 0 and self.length == 0 and self.time == 0

    def si(self) -> str:
        """The SI base-unit spelling, e.g. ``"kg*m/s^2"`` (``"1"`` if dimensionless)."""
        return _spell(((self.mass, "kg"), (self.length, "m"), (self.time, "s")))


def _dim(mass: int = 0, length: int = 0, time: int = 0) -> Dimension:
    return Dimension(Fraction(mass), Fraction(length), Fraction(time))


#: Named dimensions and their SI unit as shown to users (first name wins on a tie).
_NAMED: tuple[tuple[str, Dimension, str], ...] = (
    ("dimensionless", _dim(), "-"),
    ("angle", _dim(), "rad"),
    ("length", _dim(length=1), "m"),
    ("mass", _dim(mass=1), "kg"),
    ("time", _dim(time=1), "s"),
    ("speed", _dim(length=1, time=-1), "m/s"),
    ("acceleration", _dim(length=1, time=-2), "m/s^2"),
    ("force", _dim(mass=1, length=1, time=-2), "N"),
    ("stiffness", _dim(mass=1, time=-2), "N/m"),
    ("rotational_stiffness", _dim(mass=1, length=2, time=-2), "N*m/rad"),
    ("damping", _dim(mass=1, time=-1), "N*s/m"),
    ("rotational_damping", _dim(mass=1, length=2, time=-1), "N*m*s/rad"),
    ("inertia", _dim(mass=1, length=2), "kg*m^2"),
    ("frequency", _dim(time=-1), "Hz"),
    ("pressure", _dim(mass=1, length=-1, time=-2), "Pa"),
    ("curvature", _dim(length=-1), "1/m"),
    ("spin_coefficient", _dim(mass=1, length=3, time=-2), "N*m^2"),  # Kalker's f33
)

#: Dimension by name (``DIMENSIONS["stiffness"]`` is N/m).
DIMENSIONS: dict[str, Dimension] = {name: dim for name, dim, _ in _NAMED}
_SI_UNIT = {name: unit for name, _, unit in _NAMED}
_WORDS = {
    "rotational_stiffness": "rotational stiffness",
    "rotational_damping": "rotational damping",
    "dimensionless": "pure number",
}


def dimension(name: str) -> Dimension:
    """The :class:`Dimension` called ``name`` (one of :data:`DIMENSIONS`)."""
    try:
        return DIMENSIONS[name]
    except KeyError:
        raise ValueError(f"unknown dimension {name!r} (known: {', '.join(DIMENSIONS)})") from None


def si_unit(name: str) -> str:
    """The SI unit shown for a named dimension (``"stiffness"`` -> ``"N/m"``)."""
    dimension(name)
    return _SI_UNIT[name]


def describe_dimension(dim: Dimension | str) -> str:
    """Words for a dimension: ``"stiffness (N/m)"``, or its SI spelling if it has no name."""
    if isinstance(dim, str):
        return f"{_WORDS.get(dim, dim)} ({_SI_UNIT[dim]})" if dim in _SI_UNIT else dim
    for name, known, unit in _NAMED:
        if known == dim:
            return f"{_WORDS.get(name, name)} ({unit})"
    return dim.si()


def _spell(powers) -> str:
    up = [f"{s}^{_power(p)}" if p != 1 else s for p, s in powers if p > 0]
    down = [f"{s}^{_power(-p)}" if p != -1 else s for p, s in powers if p < 0]
    text = "*".join(up) or "1"
    if down:
        text += "/" + (down[0] if len(down) == 1 else "(" + "*".join(down) + ")")
    return text


def _power(p: Fraction) -> str:
    return str(p.numerator) if p.denominator == 1 else f"({p})"


# --------------------------------------------------------------------------- parsing

_TOKEN = re.compile(r"\s*(?:(?P<name>[A-Za-z_µ°%][A-Za-z_µ]*)|(?P<int>\d+)|(?P<op>\*\*|[*/^()·.+-]))")
_ALLOWED = re.compile(r"[A-Za-z0-9_µ°%*/^()·.+\- ]*\Z")
_ALIASES = {"kmh": "kph", "%": "percent", "°": "degree", "-": "dimensionless"}


@dataclass(frozen=True)
class _Unit:
    """A parsed unit: SI factor, dimension, and the power of the angle in it (1 for
    ``deg``, ``rad/s`` and ``rpm``, -1 for ``N*m/rad``, 0 for ``Hz``)."""

    factor: float
    dim: Dimension
    angle: Fraction = Fraction(0)

    def times(self, other: _Unit, sign: int) -> _Unit:
        factor = self.factor * other.factor if sign > 0 else self.factor / other.factor
        dim = self.dim * other.dim if sign > 0 else self.dim / other.dim
        return _Unit(factor, dim, self.angle + sign * other.angle)


@functools.lru_cache(maxsize=1)
def _registry():
    import pint

    return pint.UnitRegistry()


#: SI units and the units accepted for use with them (SI brochure, Table 8) that model
#: files mostly use: answered without importing pint (about half a second), and
#: checked against pint in the tests.
_SI_SYMBOLS = {
    "m": _Unit(1.0, _dim(length=1)),
    "g": _Unit(1e-3, _dim(mass=1)),
    "s": _Unit(1.0, _dim(time=1)),
    "N": _Unit(1.0, _dim(mass=1, length=1, time=-2)),
    "Pa": _Unit(1.0, _dim(mass=1, length=-1, time=-2)),
    "Hz": _Unit(1.0, _dim(time=-1)),
    "rad": _Unit(1.0, _dim(), angle=Fraction(1)),
}
_SI_PREFIXES = {"G": 1e9, "M": 1e6, "k": 1e3, "": 1.0, "c": 1e-2, "m": 1e-3}
_ACCEPTED = {
    "t": _Unit(1e3, _dim(mass=1)),
    "min": _Unit(60.0, _dim(time=1)),
    "h": _Unit(3600.0, _dim(time=1)),
    "deg": _Unit(math.pi / 180.0, _dim(), angle=Fraction(1)),
}


def _fast_symbol(name: str) -> _Unit | None:
    if name in _ACCEPTED:
        return _ACCEPTED[name]
    for prefix, scale in _SI_PREFIXES.items():
        base = _SI_SYMBOLS.get(name[len(prefix) :]) if name.startswith(prefix) else None
        if base is not None and (prefix or name in _SI_SYMBOLS):
            return _Unit(scale * base.factor, base.dim, base.angle)
    return None


@functools.lru_cache(maxsize=256)
def _symbol(name: str, text: str) -> _Unit:
    """One unit symbol looked up in pint's registry: SI factor, dimension, angle?"""
    fast = _fast_symbol(name)
    if fast is not None:
        return fast
    registry = _registry()
    try:
        units = registry.parse_units(_ALIASES.get(name, name))
        factor = float(registry.Quantity(1.0, units).to_base_units().magnitude)
        dimensionality = dict(units.dimensionality)
        root = registry.get_root_units(units)[1]
    except Exception:  # pint raises several kinds for an unknown or odd symbol
        raise UnitError(f'unknown unit "{name}" in "{text}"') from None
    unknown = sorted(set(dimensionality) - {"[mass]", "[length]", "[time]"})
    if unknown:
        raise UnitError(f'unit "{name}" in "{text}" is not mechanical ({", ".join(unknown)})')
    dim = Dimension(*(Fraction(dimensionality.get(key, 0)).limit_denominator(12) for key in ("[mass]", "[length]", "[time]")))
    angle = Fraction(dict(getattr(root, "_units", {})).get("radian", 0)).limit_denominator(12)
    if not math.isfinite(factor) or factor <= 0:
        raise UnitError(f'unit "{name}" in "{text}" cannot be converted')
    return _Unit(factor, dim, angle)


class _UnitParser:
    """``unit := "-" | product``; ``product := factor (("*" | "/" | " ") factor)*``;
    ``factor := atom [("^" | "**") exponent | digits]``; ``atom := NAME | "1" | "(" product ")"``."""

    def __init__(self, text: str):
        self.text = text
        self.tokens: list[tuple[str, str, bool]] = []  # kind, text, preceded by space
        position, end = 0, len(text.rstrip())
        while position < end:
            match = _TOKEN.match(text, position)
            if match is None or match.end() == position:
                raise UnitError(f'unexpected "{text[position:].strip()[:1]}" in unit "{text}"')
            kind = match.lastgroup or ""
            self.tokens.append((kind, match.group(kind), match.start(kind) > position))
            position = match.end()
        self.index = 0

    def peek(self) -> tuple[str, str, bool] | None:
        return self.tokens[self.index] if self.index < len(self.tokens) else None

    def take(self) -> tuple[str, str, bool]:
        token = self.peek()
        if token is None:
            raise UnitError(f'unit "{self.text}" ends too early')
        self.index += 1
        return token

    def parse(self) -> _Unit:
        if [t[1] for t in self.tokens] == ["-"]:
            return _Unit(1.0, Dimension())
        unit = self.product(0)
        if self.peek() is not None:
            raise UnitError(f'unexpected "{self.peek()[1]}" in unit "{self.text}"')  # type: ignore[index]
        return unit

    def product(self, depth: int) -> _Unit:
        unit = self.factor(depth)
        while True:
            token = self.peek()
            if token is not None and token[1] in ("*", "/", "·", "."):
                self.take()
                unit = unit.times(self.factor(depth), -1 if token[1] == "/" else 1)
            elif token is not None and token[2] and (token[0] == "name" or token[1] == "("):
                unit = unit.times(self.factor(depth), 1)  # "N m": a space multiplies
            else:
                return unit

    def factor(self, depth: int) -> _Unit:
        unit = self.atom(depth)
        token = self.peek()
        if token is not None and token[1] in ("^", "**"):
            self.take()
            return self.power(unit, self.exponent())
        if token is not None and token[0] == "int" and not token[2] and self.tokens[self.index - 1][0] == "name":
            self.take()  # "m2" is m^2
            return self.power(unit, int(token[1]))
        return unit

    def exponent(self) -> int:
        parenthesised = self.peek() is not None and self.peek()[1] == "("  # type: ignore[index]
        if parenthesised:
            self.take()
        sign = 1
        if self.peek() is not None and self.peek()[1] in ("-", "+"):  # type: ignore[index]
            sign = -1 if self.take()[1] == "-" else 1
        kind, digits, _ = self.take()
        after = self.peek()
        if kind != "int" or (after is not None and after[1] == "." and not after[2]):
            raise UnitError(f'the exponent in unit "{self.text}" must be an integer, got "{digits}"')
        if parenthesised and self.take()[1] != ")":
            raise UnitError(f'expected ")" in unit "{self.text}"')
        if len(digits) > 3 or int(digits) > _MAX_EXPONENT:
            raise UnitError(f'exponent {sign * int(digits)} in unit "{self.text}" is too large (at most {_MAX_EXPONENT})')
        return sign * int(digits)

    def power(self, unit: _Unit, exponent: int) -> _Unit:
        try:
            factor = unit.factor**exponent
        except (OverflowError, ZeroDivisionError):
            factor = math.inf
        if not math.isfinite(factor) or factor == 0:
            raise UnitError(f'unit "{self.text}" is out of range')
        return _Unit(factor, unit.dim**exponent, unit.angle * exponent)

    def atom(self, depth: int) -> _Unit:
        kind, text, _ = self.take()
        if kind == "name":
            return _symbol(text, self.text)
        if kind == "int":
            if text != "1":
                raise UnitError(f'a unit cannot hold the number {text} ("{self.text}")')
            return _Unit(1.0, Dimension())
        if text == "(":
            if depth >= _MAX_DEPTH:
                raise UnitError(f'unit "{self.text}" nests parentheses too deeply')
            unit = self.product(depth + 1)
            if self.take()[1] != ")":
                raise UnitError(f'expected ")" in unit "{self.text}"')
            return unit
        raise UnitError(f'unexpected "{text}" in unit "{self.text}"')


@functools.lru_cache(maxsize=1024)
def _parse_unit(unit: str) -> _Unit:
    text = unit.strip()
    if text in ("", "-", "1"):
        return _Unit(1.0, Dimension())
    if len(text) > _MAX_UNIT_LENGTH:
        raise UnitError(f"unit longer than {_MAX_UNIT_LENGTH} characters")
    if not _ALLOWED.match(text):
        bad = next(c for c in text if not _ALLOWED.match(c))
        raise UnitError(f'unexpected character "{bad}" in unit "{text}"')
    parsed = _UnitParser(text).parse()
    if not math.isfinite(parsed.factor) or parsed.factor == 0:
        raise UnitError(f'unit "{text}" is out of range')
    if max(abs(parsed.dim.mass), abs(parsed.dim.length), abs(parsed.dim.time)) > _MAX_DIMENSION_EXPONENT:
        raise UnitError(f'unit "{text}" has too large powers')
    return parsed


def unit_factor(unit: str) -> float:
    """SI factor of ``unit`` (``"kN/m"`` -> 1000.0).

    Raises
    ------
    UnitError
        For an unknown symbol or a malformed unit.
    """
    return _parse_unit(unit).factor


def is_angular_frequency(unit: str) -> bool:
    """Whether ``unit`` is an angular frequency (``rad/s``, ``deg/s``, ``rpm``): a value in
    it is converted to Hz with a 2 pi (:func:`parse_quantity`), not by its factor alone."""
    parsed = _parse_unit(unit)
    return parsed.dim == DIMENSIONS["frequency"] and parsed.angle == 1


def unit_dimension(unit: str) -> Dimension:
    """The :class:`Dimension` of ``unit`` (``"kN/mm"`` -> that of N/m)."""
    return _parse_unit(unit).dim


def dimension_of(unit: str) -> str:
    """Name of the dimension of ``unit`` (``"kN*s/m"`` -> ``"damping"``).

    ``"angle"`` for a dimensionless unit with an angle in it (``deg``, ``rad``); the
    SI spelling (``"kg*m/s"``) for a dimension without a name.
    """
    parsed = _parse_unit(unit)
    if parsed.dim.is_dimensionless:
        return "angle" if parsed.angle else "dimensionless"
    for name, known, _ in _NAMED:
        if known == parsed.dim:
            return name
    return parsed.dim.si()


def check_dimension(unit: str, expected: str | Dimension) -> None:
    """Raise :class:`UnitError` unless ``unit`` has the dimension ``expected``.

    A pure number (``""``, ``"-"``, ``"1"``) fits ``"angle"`` (radians); an angle
    unit does not fit ``"dimensionless"`` (a conicity is not an angle).
    """
    parsed = _parse_unit(unit)
    wanted = dimension(expected) if isinstance(expected, str) else expected
    if parsed.dim != wanted or (expected == "dimensionless" and parsed.angle):
        raise UnitError(f"unit {unit.strip()} is {_article(dimension_of(unit))}, expected {_article(expected)}")
    if wanted == DIMENSIONS["frequency"] and parsed.angle not in (0, 1):
        raise UnitError(f"unit {unit.strip()} is not a frequency (Hz, 1/s, rad/s or rpm)")


def _article(dim: str | Dimension) -> str:
    words = describe_dimension(dim)
    if isinstance(dim, Dimension) and words == dim.si():
        return f"a quantity in {words}"
    return ("an " if words[0] in "aeiou" else "a ") + words


def to_si(value: float, unit: str) -> float:
    """Convert ``value`` given in ``unit`` to SI."""
    return float(value) * unit_factor(unit)


_QUANTITY = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*\Z", re.DOTALL)


def parse_quantity(text: str, dimension: str | Dimension | None = None) -> tuple[float, str]:
    """Split ``"95 mm"`` into ``(0.095, "mm")`` (value in SI, unit as written).

    Parameters
    ----------
    text : str
        A number, optionally followed by a unit. A bare number is SI.
    dimension : str or Dimension, optional
        The dimension the quantity must have (a name of :data:`DIMENSIONS`).

    Raises
    ------
    UnitError
        For text that is not a number with a unit, an unknown unit, a non-finite
        value, or a unit of another dimension than ``dimension``; an angle for a pure
        number (a conicity, a ratio or a slope is not an angle).

    Notes
    -----
    Angles are tracked: a frequency given as an angular frequency (``rad/s``, ``deg/s``,
    ``rpm``) is converted to Hz with its 2 pi (``"20 rad/s"`` is 3.183 Hz, ``"600 rpm"``
    10 Hz); a unit with another power of the angle is not a frequency.

    Examples
    --------
    >>> round(parse_quantity("600 rpm", "frequency")[0], 12)
    10.0
    """
    if not isinstance(text, str) or len(text) > 200:
        raise UnitError("a quantity must be a short text such as \"95 mm\"")
    match = _QUANTITY.match(text)
    if match is None:
        raise UnitError(f'"{text}" is not a number with a unit (e.g. "95 mm")')
    number, unit = match.group(1), match.group(2)
    if unit[:1] in ("*", "/", "^", ")", "+") or (unit[:1] == "-" and unit != "-"):
        raise UnitError(f'"{text}" is not a number with a unit (e.g. "95 mm")')
    value = float(number) * unit_factor(unit)
    if not math.isfinite(value):
        raise UnitError(f'"{text}" is out of range')
    if dimension is not None and unit:  # a bare number is SI and takes any dimension
        parsed = _parse_unit(unit)
        if dimension == "dimensionless" and parsed.angle and parsed.dim.is_dimensionless:
            raise UnitError(
                f'"{text}" is an angle, expected a pure number (a ratio or a slope); for the slope '
                f"of that angle give its tangent: tan({text.strip()}) = {math.tan(value):.6g}"
            )
        check_dimension(unit, dimension)
        if (dimension == "frequency" or dimension == DIMENSIONS["frequency"]) and parsed.angle == 1:
            value /= 2.0 * math.pi  # an angular frequency (rad/s, rpm) in Hz
    return value, unit


def format_quantity(value_si: float, unit: str) -> str:
    """``value_si`` shown in ``unit``: ``format_quantity(15000.0, "kN*s/m") == "15 kN*s/m"``.

    Up to 10 significant digits, so that the conversion's rounding does not show;
    no unit for a pure number (``""``, ``"-"``, ``"1"``).
    """
    shown = float(value_si) / unit_factor(unit) if unit.strip() else float(value_si)
    number = f"{shown:.10g}"
    if number == "-0":
        number = "0"
    unit = unit.strip()
    return number if unit in ("", "-", "1") else f"{number} {unit}"
