"""The library's arguments (issue 35, items 1 and 5): a number is SI (never the command
line's km/h shorthand), a quantity carries its unit (text or a pint quantity), and a
wrong type or unit is an ArgumentError naming the argument."""

from __future__ import annotations

import numpy as np
import pint
import pytest

import express
from express.analysis.curving.steady import SteadyCurve
from express.base.arguments import si_argument
from express.base.diagnostics import ArgumentError

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


def _conventional():
    return express.load_vehicle("examples/conventional.toml")


def _spectra():
    from express.analysis.ride.vehicle import track_class_spectra

    return track_class_spectra("ERRI-low")


def _lever():
    values = {"J1": 2.0, "J2": 0.5, "b": 0.4, "c": 300.0, "kLL": 5.5e6, "kLU": 5e5, "lLL": 0.06, "lLU": 0.3, "m": 20.0}
    return express.vehicle_model(express.with_values(express.load_model("examples/lever.exp"), values))


def _track_frf(car, frequencies, speed):
    from express.analysis.frequency.track_response import track_frequency_response

    return track_frequency_response(car, frequencies, components=["alignment"], speed=speed).speed


#: (case, call(car, value) -> a number that shows the SI value used, dimension, SI value,
#: the same as a pint quantity, as text, and a value of the wrong dimension with its unit)
ANALYSES = [
    ("eigen speed", lambda car, v: express.eigen(car, v).speed, 120 / 3.6, 120 * UNITS.km / UNITS.hour,
     "120 km/h", "120 kg", "kg is a mass"),
    ("root_locus speeds", lambda car, v: express.root_locus(car, v)[0, 0].real,
     [30.0], 108 * UNITS.km / UNITS.hour, ["108 km/h"], ["30 s"], "s is a time"),
    ("critical_speed v_max", lambda car, v: express.critical_speed(car, v_max=v).v_max, 150.0,
     540 * UNITS.km / UNITS.hour, "540 km/h", "540 m", "m is a length"),
    ("frequency_response speed", lambda car, v: express.frequency_response(car, [1.0], speed=v).speed, 30.0,
     30 * UNITS.m / UNITS.s, "108 km/h", "30 Hz", "Hz is a frequency"),
    ("frequency_response frequencies", lambda car, v: express.frequency_response(car, v, speed=30.0).frequencies[-1],
     [1.0, 2.0], np.array([1.0, 2.0]) * UNITS.Hz, ["1 Hz", "2 Hz"], ["1 m"], "m is a length"),
    ("ground_response frequencies", lambda car, v: express.ground_response(_lever(), v).frequencies[0],
     [2 / (2 * np.pi)], 2 * UNITS.rad / UNITS.s, ["2 rad/s"], ["2 km/h"], "is a speed"),
    ("ride_response speed", lambda car, v: express.ride_response(car, _spectra(), v, [1.0, 2.0]).speed,
     120 / 3.6, 120 * UNITS.km / UNITS.hour, "120 km/h", "120 N", "N is a force"),
    ("ride_response frequencies", lambda car, v: express.ride_response(car, _spectra(), 30.0, v).frequencies[0],
     [0.5, 1.0], [0.5 * UNITS.Hz, 1 * UNITS.Hz], ["0.5 Hz", "1 Hz"], ["0.5 s", "1 s"], "s is a time"),
    ("track_frequency_response speed", lambda car, v: _track_frf(car, [1.0], v), 30.0,
     108 * UNITS.km / UNITS.hour, "108 km/h", "108 m", "m is a length"),
]


@pytest.fixture(scope="module")
def conventional():
    return _conventional()


@pytest.mark.parametrize("case, call, si, quantity, text, wrong, message", ANALYSES, ids=[a[0] for a in ANALYSES])
def test_every_analysis_takes_si_numbers_and_quantities(conventional, case, call, si, quantity, text, wrong, message):
    """Each public analysis's speed / frequency argument: a bare number is SI (30 is 30 m/s,
    never km/h), a pint quantity and a text quantity give the same number, to round-off
    (rel 1e-12, the km/h and rad/s conversions), and a unit of another dimension is an
    InputError (ArgumentError) naming the argument and the unit's dimension."""
    expected = call(conventional, si)
    assert call(conventional, quantity) == pytest.approx(expected, rel=1e-12)
    assert call(conventional, text) == pytest.approx(expected, rel=1e-12)
    with pytest.raises(express.InputError, match=message):
        call(conventional, wrong)


def test_a_bare_speed_is_never_km_h(conventional):
    """30 is 30 m/s (108 km/h): the command line's km/h shorthand stays on the command line."""
    assert express.eigen(conventional, 30).speed == 30.0
    assert express.eigen(conventional, "30").speed == 30.0


def test_nonlinear_critical_speed_refuses_a_wrong_unit_before_running(conventional):
    with pytest.raises(express.InputError, match="v_start: unit s is a time"):
        express.nonlinear_critical_speed(conventional, v_start="4 s")
    with pytest.raises(express.InputError, match="dt: unit km/h is a speed"):
        express.nonlinear_critical_speed(conventional, v_start="400 km/h", dt="5 km/h")


def test_bare_generate_says_it_leaves_out_the_rail_terms():
    """``express.generate`` of a model with rail data has no wheel/rail terms
    (K[W1.rz, W1.y] = 0: no gravitational stiffness, no creep) and says so on its result;
    ``express.generate_vehicle`` (what ``express generate`` runs) has them and omits nothing."""
    model = express.load_model("examples/conventional.toml")
    bare, full = express.generate(model), express.generate_vehicle(model)
    i, j = bare.equations.dofs.index("W1.rz"), bare.equations.dofs.index("W1.y")
    assert bare.equations.K[i, j] == 0 and full.equations.K[i, j] != 0
    assert bare.omitted and "wheel/rail" in bare.omitted[0] and "generate_vehicle" in bare.omitted[0]
    assert "without the wheel/rail" in repr(bare).splitlines()[0]
    assert full.omitted == () and "without" not in repr(full).splitlines()[0]
    assert express.generate(express.load_model("examples/lever.exp")).omitted == ()  # no rail data: nothing left out
    assert "generate_vehicle" in express.generate.__doc__
