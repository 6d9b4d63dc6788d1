"""Units: spellings, SI factors, dimensions, bounded parsing, display."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

from express.base.units import (
    DIMENSIONS,
    KMH,
    Dimension,
    UnitError,
    check_dimension,
    describe_dimension,
    dimension,
    dimension_of,
    format_quantity,
    parse_quantity,
    si_unit,
    to_si,
    unit_dimension,
    unit_factor,
)

# unit, SI factor (independent: by hand from the definitions), dimension name
SPELLINGS = [
    ("kN/mm", 1e6, "stiffness"),
    ("MN/m", 1e6, "stiffness"),
    ("N/m", 1.0, "stiffness"),
    ("MN*m/rad", 1e6, "rotational_stiffness"),
    ("kN*m/rad", 1e3, "rotational_stiffness"),
    ("N m/rad", 1.0, "rotational_stiffness"),
    ("N·m/rad", 1.0, "rotational_stiffness"),
    ("t", 1e3, "mass"),
    ("kg", 1.0, "mass"),
    ("km/h", 1 / 3.6, "speed"),
    ("kmh", 1 / 3.6, "speed"),
    ("m/s", 1.0, "speed"),
    ("mm", 1e-3, "length"),
    ("cm", 1e-2, "length"),
    ("km", 1e3, "length"),
    ("deg", math.pi / 180, "angle"),
    ("mrad", 1e-3, "angle"),
    ("rad", 1.0, "angle"),
    ("kg*m^2", 1.0, "inertia"),
    ("kg*m**2", 1.0, "inertia"),
    ("t*m2", 1e3, "inertia"),
    ("t*m^2", 1e3, "inertia"),
    ("kN*s/m", 1e3, "damping"),
    ("kN/m*s", 1e3, "damping"),  # left to right: (kN/m)*s
    ("kN*m*s/rad", 1e3, "rotational_damping"),
    ("1/m", 1.0, "curvature"),
    ("1/km", 1e-3, "curvature"),
    ("-", 1.0, "dimensionless"),
    ("1", 1.0, "dimensionless"),
    ("", 1.0, "dimensionless"),
    ("%", 0.01, "dimensionless"),
    ("kN", 1e3, "force"),
    ("GPa", 1e9, "pressure"),
    ("N/mm^2", 1e6, "pressure"),
    ("Hz", 1.0, "frequency"),
    ("1/s", 1.0, "frequency"),
    ("m/s^2", 1.0, "acceleration"),
    ("m/s2", 1.0, "acceleration"),
    ("min", 60.0, "time"),
    ("h", 3600.0, "time"),
    ("s^(-1)", 1.0, "frequency"),
    ("kg/(m*s)", 1.0, "kg/(m*s)"),
]


@pytest.mark.parametrize(("unit", "factor", "name"), SPELLINGS)
def test_spellings(unit, factor, name):
    assert unit_factor(unit) == pytest.approx(factor, rel=1e-15)
    assert dimension_of(unit) == name


BAD_UNITS = [
    ("km^400", "too large"),  # issue 17: no OverflowError
    ("m^99999999999999999999", "too large"),
    ("m^0.5", "integer"),
    ("furlongs_of_cheese", "unknown unit"),
    ("kN/", "ends too early"),
    ("2*m", "number 2"),
    ("((((m))))", "too deeply"),
    ("degC", "not mechanical"),
    ("A", "not mechanical"),
    ("m;import os", "unexpected character"),
    ("__import__('os')", "unexpected character"),
    ("m" * 100, "longer than"),
    ("(m", "ends too early"),
    ("m)", 'unexpected "\\)"'),
]


@pytest.mark.parametrize(("unit", "message"), BAD_UNITS)
def test_bad_units_are_unit_errors(unit, message):
    with pytest.raises(UnitError, match=message):
        unit_factor(unit)


QUANTITIES = [
    ("95 mm", None, 0.095, "mm"),
    ("95mm", None, 0.095, "mm"),
    ("  -3 kN/m ", "stiffness", -3000.0, "kN/m"),
    ("1e5 N/m", "stiffness", 1e5, "N/m"),
    ("1.5", "length", 1.5, ""),  # a bare number is SI and takes any dimension
    ("0.1", "angle", 0.1, ""),
    ("0.05 -", "dimensionless", 0.05, "-"),
    ("100 km/h", "speed", 100 / 3.6, "km/h"),
    ("30 t", "mass", 30000.0, "t"),
    ("3 kN*m", "rotational_stiffness", 3000.0, "kN*m"),
    ("2 deg", "angle", 2 * math.pi / 180, "deg"),
    (".5 m", None, 0.5, "m"),
]


@pytest.mark.parametrize(("text", "dim", "value", "unit"), QUANTITIES)
def test_parse_quantity(text, dim, value, unit):
    got, written = parse_quantity(text, dim)
    assert got == pytest.approx(value, rel=1e-15)
    assert written == unit


BAD_QUANTITIES = [
    ("1.8 kg", "length", "is a mass \\(kg\\), expected a length \\(m\\)"),
    ("4 s", "stiffness", "expected a stiffness"),
    ("1 kN*m/rad", "stiffness", "rotational stiffness"),
    ("1 kN/m", "rotational_stiffness", "is a stiffness"),
    ("2 deg", "dimensionless", "is an angle"),  # a conicity is not an angle
    ("27 m/s", "length", "is a speed"),
    ("1 km^400", None, "too large"),  # issue 17
    ("1e400 m", None, "out of range"),
    ("1e308 km", None, "out of range"),
    ("2*a", None, "not a number with a unit"),
    ("a + mc", None, "not a number with a unit"),
    ("1/2", None, "not a number with a unit"),
    ("", None, "not a number"),
    ("m", None, "not a number"),
]


@pytest.mark.parametrize(("text", "dim", "message"), BAD_QUANTITIES)
def test_bad_quantities(text, dim, message):
    with pytest.raises(UnitError, match=message):
        parse_quantity(text, dim)


def test_unit_error_is_value_error():
    assert issubclass(UnitError, ValueError)


@pytest.mark.parametrize(
    ("value", "unit", "text"),
    [
        (15000.0, "kN*s/m", "15 kN*s/m"),
        (100 / 3.6, "km/h", "100 km/h"),
        (0.3, "-", "0.3"),
        (0.3, "", "0.3"),
        (2.06e11, "GPa", "206 GPa"),
        (2.06e11, "N/m^2", "2.06e+11 N/m^2"),
        (1.2345678901234e4, "N", "12345.6789 N"),
        (-0.0, "m", "0 m"),
        (0.3 * 1000, "t", "0.3 t"),
    ],
)
def test_format_quantity(value, unit, text):
    assert format_quantity(value, unit) == text


@pytest.mark.parametrize("unit", [u for u, _, _ in SPELLINGS])
def test_format_round_trips(unit):
    value = 1234.5 * unit_factor(unit)
    shown = format_quantity(value, unit)
    assert parse_quantity(shown)[0] == pytest.approx(value, rel=1e-12)


def test_dimension_algebra():
    assert dimension("force") / dimension("length") == dimension("stiffness")
    assert dimension("stiffness") * dimension("length") ** 2 == dimension("rotational_stiffness")
    assert dimension("damping") * dimension("speed") == dimension("force")
    assert unit_dimension("kN/mm") == DIMENSIONS["stiffness"]
    assert Dimension().is_dimensionless
    assert (dimension("mass") * dimension("length")).si() == "kg*m"
    assert describe_dimension(dimension("stiffness")) == "stiffness (N/m)"
    assert describe_dimension("rotational_stiffness") == "rotational stiffness (N*m/rad)"


@pytest.mark.parametrize(("name", "unit"), [("stiffness", "N/m"), ("speed", "m/s"), ("dimensionless", "-")])
def test_si_unit_has_its_dimension(name, unit):
    assert si_unit(name) == unit
    check_dimension(unit, name)


def test_every_named_dimension_has_an_si_unit_of_that_dimension():
    for name in DIMENSIONS:
        check_dimension(si_unit(name), name)


def test_unknown_dimension_name():
    with pytest.raises(ValueError, match="unknown dimension"):
        dimension("flux")


def test_kmh_and_to_si():
    assert KMH == 1 / 3.6
    assert to_si(120, "km/h") == pytest.approx(120 * KMH)
    assert to_si(5, "MN/m") == 5e6


def test_importing_units_does_not_import_pint():
    code = "import sys, express.base.units; print('pint' in sys.modules, 'sympy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


def test_symbols_answered_without_pint_agree_with_pint():
    """The SI symbols (with prefixes) and the accepted units answered from the small
    table give exactly what pint gives."""
    from express.base import units

    names = [prefix + base for prefix in units._SI_PREFIXES for base in units._SI_SYMBOLS]
    names += list(units._ACCEPTED)
    registry = units._registry()
    for name in names:
        fast = units._fast_symbol(name)
        assert fast is not None, name
        quantity = registry.Quantity(1.0, registry.parse_units(name)).to_base_units()
        assert fast.factor == pytest.approx(float(quantity.magnitude), rel=1e-15), name
        dims = dict(quantity.dimensionality)
        assert (fast.dim.mass, fast.dim.length, fast.dim.time) == tuple(
            dims.get(key, 0) for key in ("[mass]", "[length]", "[time]")
        ), name
        assert fast.angle == ("radian" in str(registry.get_root_units(registry.parse_units(name))[1])), name


def test_loading_common_units_does_not_import_pint():
    code = (
        "import sys; from express.base.units import parse_quantity as q;"
        "[q(t) for t in ('1 kN*s/m', '2 kg*m^2', '3 t*m2', '120 km/h', '4 MN*m/rad', '5 deg', '6 GPa', '7 mm', '8 m/s^2')];"
        "print('pint' in sys.modules)"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"
