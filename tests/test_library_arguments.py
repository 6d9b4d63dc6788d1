"""The library's arguments (issue 35, items 1 and 5): a number is SI (never the command
line's km/h shorthand), a quantity carries its unit (text or a pint quantity), and a
wrong type or unit is an ArgumentError naming the argument."""

from __future__ import annotations

import numpy as np
import pint
import pytest

import express
from express.analysis.curving.steady import SteadyCurve
from express.base.diagnostics import ArgumentError
from express.base.units import si_argument

UNITS = pint.UnitRegistry()


@pytest.fixture(scope="module")
def car():
    return express.load_vehicle("examples/forced-steering.toml")


@pytest.mark.parametrize("value, dimension, expected", [
    (30, "speed", 30.0), ("95 km/h", "speed", 95 / 3.6), (95 * UNITS.km / UNITS.hour, "speed", 95 / 3.6),
    ("5 ms", "time", 0.005), (600 * UNITS.m, "length", 600.0), ("30", "speed", 30.0),
])
def test_a_number_is_si_and_a_quantity_carries_its_unit(value, dimension, expected):
    assert si_argument(value, dimension, "x") == pytest.approx(expected, rel=1e-15)


@pytest.mark.parametrize("value, message", [
    ("95 kg", "x: unit kg is a mass"), (95 * UNITS.kg, "x: unit kg is a mass"), ([1.0], "x must be a number"),
    (None, "x must be a number"), (float("nan"), "x must be finite"), (True, "x must be a number"),
])
def test_a_wrong_argument_is_named(value, message):
    with pytest.raises(ArgumentError, match=message):
        si_argument(value, "speed", "x")


def test_simulate_takes_quantities_and_names_a_wrong_argument(car):
    track = express.load_track("R400")
    si = express.simulate(car, track, speed=95 / 3.6, dt=0.005, end=60.0, progress=False)
    with_units = express.simulate(car, track, speed="95 km/h", dt=5 * UNITS.ms, end="60 m", progress=False)
    np.testing.assert_array_equal(with_units.q, si.q)
    with pytest.raises(ArgumentError, match="track must be a Track"):
        express.simulate(car, "R400", progress=False)
    with pytest.raises(ArgumentError, match="dt: unit m is a length"):
        express.simulate(car, track, dt="5 m", progress=False)


def test_steady_curving_names_a_radius_given_for_a_curve(car):
    with pytest.raises(ArgumentError, match="curves must be a SteadyCurve .* got float 600.0"):
        express.steady_curving(car, 600.0)
    curve = SteadyCurve(600.0, 0.1)
    first = express.steady_curving(car, curve, speeds=80 * UNITS.km / UNITS.hour)[0]
    second = express.steady_curving(car, [curve], speeds=["80 km/h"])[0]
    assert first.speed == second.speed == pytest.approx(80 / 3.6)
    with pytest.raises(ArgumentError, match="speeds: unit s is a time"):
        express.steady_curving(car, curve, speeds="80 s")
