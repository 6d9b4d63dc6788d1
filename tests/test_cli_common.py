"""Shared options (``express.cli.common``): quantities with units, the unit of a bare
number, valid ranges checked before any work, ``--set`` syntax."""

from __future__ import annotations

import argparse
import time

import pytest

from cli_support import CONVENTIONAL, assert_input_error, run
from express.cli import common

KMH = 1 / 3.6


@pytest.mark.parametrize(
    "quantity, text, expected",
    [
        (common.SPEED, "120", 120 * KMH),  # a bare speed is km/h (rail usage)
        (common.SPEED, "120 km/h", 120 * KMH),
        (common.SPEED, "30 m/s", 30.0),
        (common.SPEED, "30m/s", 30.0),
        (common.VMIN, "3.6", 1.0),
        (common.VMAX, "150 m/s", 150.0),
        (common.TOLERANCE, "0.1", 0.1 * KMH),  # km/h for bare numbers, as before
        (common.TOLERANCE, "0.01 m/s", 0.01),
        (common.FMIN, "0.1", 0.1),  # Hz
        (common.FMAX, "20 Hz", 20.0),
        (common.AMPLITUDE, "2", 0.002),  # mm for bare numbers, as documented
        (common.AMPLITUDE, "2 mm", 0.002),
        (common.AMPLITUDE, "0.002 m", 0.002),
        (common.AMPLITUDE, "0.5 cm", 0.005),
        (common.DT, "0.01", 0.01),  # s
        (common.DT, "5 ms", 0.005),
    ],
)
def test_quantities_accept_units_and_bare_numbers(quantity, text, expected):
    assert quantity(text) == pytest.approx(expected, rel=1e-12)


@pytest.mark.parametrize(
    "quantity, text, mentions",
    [
        (common.SPEED, "3 kg", "speed"),  # wrong dimension
        (common.SPEED, "fast", "fast"),
        (common.SPEED, "", "number"),
        (common.SPEED, "0", "0 < --speed <= 1000 km/h"),
        (common.SPEED, "-5", "0 < --speed <= 1000 km/h"),
        (common.SPEED, "1001", "0 < --speed <= 1000 km/h"),
        (common.SPEED, "300 m/s", "0 < --speed <= 1000 km/h"),
        (common.SPEED, "1e300", "0 < --speed <= 1000 km/h"),
        (common.SPEED, "1 km^400/h", "km^400"),
        (common.SPEED, "nan", "nan"),
        (common.TOLERANCE, "1e-14", "0.001 <= --tolerance <= 100 km/h"),
        (common.TOLERANCE, "1e-6 m/s", "0.001 <= --tolerance"),
        (common.FMAX, "1e300", "--fmax <= 1000 Hz"),
        (common.FMAX, "2000 Hz", "--fmax <= 1000 Hz"),
        (common.FMIN, "0", "0.0001 <= --fmin"),
        (common.FMIN, "2 s", "frequency"),
        (common.AMPLITUDE, "0", "0 < --amplitude <= 100 mm"),
        (common.AMPLITUDE, "1 m", "0 < --amplitude <= 100 mm"),
        (common.AMPLITUDE, "2 s", "length"),
        (common.DT, "1e-9", "1e-05 <= --dt <= 0.1 s"),
        (common.DT, "1 s", "1e-05 <= --dt <= 0.1 s"),
        (common.DT, "5 Hz", "time"),
    ],
)
def test_bad_quantities_name_the_option_and_the_range(quantity, text, mentions):
    with pytest.raises(argparse.ArgumentTypeError) as info:
        quantity(text)
    assert mentions in str(info.value)


@pytest.mark.parametrize(
    "text, value",
    [("2", 2), ("100000", 100000)],
)
def test_counts_in_range(text, value):
    assert common.count("--points", 2, 100000)(text) == value


@pytest.mark.parametrize("text", ["1", "100001", "1e9", "two", "-3"])
def test_counts_out_of_range(text):
    with pytest.raises(argparse.ArgumentTypeError, match=r"2 <= --points <= 100000|whole number"):
        common.count("--points", 2, 100000)(text)


@pytest.mark.parametrize(
    "command, option, unit",
    [
        ("simulate", "--speed", "bare number: km/h"),
        ("simulate", "--dt", "bare number: s"),
        ("frf", "--fmax", "bare number: Hz"),
        ("frf", "--amplitude", "bare number: mm"),
        ("eigen", "--speed", "bare number: km/h"),
        ("critical-speed", "--tolerance", "bare number: km/h"),
        ("critical-speed", "--vmax", "bare number: km/h"),
    ],
)
def test_help_prints_the_unit_of_bare_numbers(capsys, command, option, unit):
    status, out, _ = run(capsys, command, "--help")
    assert status == 0
    text = " ".join(out.split())
    start = text.index(f"{option} ", text.index("options:"))
    assert unit in text[start:start + 200]


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["critical-speed", CONVENTIONAL, "--tolerance", "1e-14"], "--tolerance"),
        (["critical-speed", CONVENTIONAL, "--conicities", "0.01:0.5:100000000"], "COUNT <= 10000"),
        (["frf", CONVENTIONAL, "--fmax", "1e300"], "--fmax <= 1000 Hz"),
        (["frf", CONVENTIONAL, "--points", "100000000"], "--points <= 100000"),
        (["simulate", CONVENTIONAL, "--speed", "1e300"], "--speed <= 1000 km/h"),
        (["simulate", CONVENTIONAL, "--dt", "1e-12"], "--dt"),
        (["eigen", CONVENTIONAL, "--speed", "3 kg"], "--speed"),
    ],
)
def test_limits_are_checked_before_any_work(capsys, argv, mentions):
    """Hangs of old (a tolerance of 1e-14, 1e8 conicities, 1e300 Hz) end at once with
    status 2 and one line naming the option and its range."""
    start = time.perf_counter()
    err = assert_input_error(capsys, *argv, mentions=mentions)
    assert len(err.splitlines()) == 1
    assert time.perf_counter() - start < 2.0  # refused while parsing: no model loaded


def test_set_keeps_the_text_for_the_library():
    """``--set NAME=TEXT`` passes the text as written (the library applies the
    parameter's dimension); the last assignment of a name wins."""
    parser = argparse.ArgumentParser()
    common.add_model_arguments(parser)
    args = parser.parse_args(["m.toml", "--set", "v=100", "--set", "mc = 35 t", "--set", "v=27.8 m/s"])
    assert args.overrides == {"v": "27.8 m/s", "mc": "35 t"}
