"""``express critical-speed`` (``express.cli.critical_speed``): the hunting speed, the
conicity sweep as CSV and figure, speeds with units, bounded work."""

from __future__ import annotations

import argparse
import csv

import pytest

from cli_support import CONVENTIONAL, LEVER, STEERED, assert_input_error, run, run_json, valued_lever
from express.cli.critical_speed import parse_range


def test_critical_speed_json(capsys):
    data = run_json(capsys, "critical-speed", CONVENTIONAL)
    assert set(data) >= {"critical_speed_kmh", "critical_speed", "mode"}
    assert data["critical_speed"] == pytest.approx(data["critical_speed_kmh"] / 3.6)
    # the library's value (the CLI is a thin layer over it); the speed itself is this code's
    # own (421 km/h, a regression guard in tests/test_stability.py)
    from express.analysis.stability.stability import critical_speed
    from express.numeric.statespace import load_vehicle

    library = critical_speed(load_vehicle(CONVENTIONAL), v_max=540 / 3.6)
    assert data["critical_speed_kmh"] == pytest.approx(library.speed_kmh, abs=1e-9)
    assert "hunting" in data["mode"]


def test_tolerance_in_km_h_or_with_a_unit(capsys):
    """A bare ``--tolerance`` is km/h as before; ``0.5 m/s`` is 1.8 km/h: the result
    moves by less than the two brackets."""
    fine = run_json(capsys, "critical-speed", CONVENTIONAL, "--tolerance", "0.01")["critical_speed_kmh"]
    coarse = run_json(capsys, "critical-speed", CONVENTIONAL, "--tolerance", "0.5 m/s")["critical_speed_kmh"]
    assert abs(fine - coarse) <= 0.5 * (0.01 + 1.8) + 1e-9


def test_critical_speed_depends_on_conicity(capsys):
    base = run_json(capsys, "critical-speed", STEERED)["critical_speed_kmh"]
    low = run_json(capsys, "critical-speed", STEERED, "--set", "Gamma=0.05")["critical_speed_kmh"]
    assert low < 0.5 * base  # the steered car's sharp fall at small conicity (paper Fig. 11)


@pytest.mark.parametrize("vmax", ["100", "100 km/h", "27.7777777778 m/s"])
def test_critical_speed_stable_over_the_range(capsys, vmax):
    data = run_json(capsys, "critical-speed", CONVENTIONAL, "--vmax", vmax)
    assert data["critical_speed_kmh"] is None and data["mode"] is None
    status, out, _ = run(capsys, "critical-speed", CONVENTIONAL, "--vmax", vmax)
    assert status == 0 and "stable up to 100" in out


def test_critical_speed_conicity_sweep_files(capsys, tmp_path):
    table, figure = tmp_path / "vcr.csv", tmp_path / "vcr.png"
    data = run_json(capsys, "critical-speed", CONVENTIONAL, "--conicities", "0.05:0.25:3", "-o", table, "--plot", figure)
    sweep = data["sweep"]
    assert sweep["values"] == pytest.approx([0.05, 0.15, 0.25])
    speeds = sweep["critical_speeds_kmh"]
    assert speeds[0] > speeds[1] > speeds[2]  # conventional: V_cr falls with Gamma
    assert sweep["critical_speeds"] == pytest.approx([v / 3.6 for v in speeds])
    rows = list(csv.reader(table.open(encoding="utf-8")))
    assert rows[0] == ["Gamma", "critical_speed_m_s", "critical_speed_kmh", "unstable_at_min"] and len(rows) == 4
    assert float(rows[1][2]) == pytest.approx(speeds[0], rel=1e-8)
    assert figure.read_bytes()[:4] == b"\x89PNG"


def test_critical_speed_root_locus_plot(capsys, tmp_path):
    figure = tmp_path / "locus.svg"
    status, out, err = run(capsys, "critical-speed", CONVENTIONAL, "--plot", figure)
    assert status == 0, err
    assert "critical speed" in out and figure.is_file()


@pytest.mark.parametrize(
    "text, values",
    [("0.1:0.3:3", [0.1, 0.2, 0.3]), ("0.2:0.2:1", [0.2]), ("0.05,0.1", [0.05, 0.1]), ("0.4", [0.4])],
)
def test_parse_range(text, values):
    assert parse_range(text) == pytest.approx(values)


@pytest.mark.parametrize("text", ["abc", "0.1:0.2", "0.1:0.2:0", "0.1:0.2:10001", "-0.1:0.2:3", "0,0.1", "nan", ""])
def test_parse_range_refuses(text):
    with pytest.raises(argparse.ArgumentTypeError):
        parse_range(text)


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["critical-speed", CONVENTIONAL, "--conicities", "abc"], "START:STOP:COUNT"),
        (["critical-speed", CONVENTIONAL, "--conicities", "0.1:0.2"], "START:STOP:COUNT"),
        (["critical-speed", CONVENTIONAL, "--conicities=-0.1:0.2:3"], "positive"),
        (["critical-speed", CONVENTIONAL, "--conicities", "0.01:0.5:100000000"], "COUNT <= 10000"),
        (["critical-speed", CONVENTIONAL, "--vmax", "2"], "--vmax"),
        (["critical-speed", CONVENTIONAL, "--vmax", "2000"], "--vmax <= 1000 km/h"),
        (["critical-speed", CONVENTIONAL, "--tolerance", "1e-14"], "0.001 <= --tolerance"),
        (["critical-speed", CONVENTIONAL, "--tolerance", "0"], "--tolerance"),
        (["critical-speed", CONVENTIONAL, "-o", "x.csv"], "--conicities"),
        (["critical-speed", CONVENTIONAL, "--conicities", "0.1", "--parameter", "nope"], "nope"),
        (["critical-speed", CONVENTIONAL, "--conicities", "0.1", "-o", "-", "--json"], "standard output"),
        (["critical-speed", LEVER], "undefined name"),  # no values: nothing to evaluate
    ],
)
def test_critical_speed_bad_input_exits_2(capsys, argv, mentions):
    assert_input_error(capsys, *argv, mentions=mentions)


def test_critical_speed_needs_rail_data(capsys, tmp_path):
    """A model with values but no rail data: status 2 and a message saying what applies."""
    assert_input_error(capsys, "critical-speed", valued_lever(tmp_path), mentions="no rail data")


@pytest.mark.parametrize(("argv", "law"), [((), "table"), (("--creep-law", "fastsim"), "fastsim")])
def test_the_creep_law_reaches_the_nonlinear_search(capsys, monkeypatch, argv, law):
    """``--creep-law`` (the option ``simulate`` and ``curving`` share) is handed to the
    nonlinear search, the default law without it; the search itself is tested in
    ``tests/test_contact_critical_speed.py``."""
    import express.cli.critical_speed as command

    seen = []
    monkeypatch.setattr(command, "_run_nonlinear", lambda *args: seen.append(args[9]) or 0)
    status, _, err = run(capsys, "critical-speed", "examples/manchester-s1002.toml", "--nonlinear", *argv)
    assert status == 0, err
    assert seen == [law]


def test_a_creep_law_without_nonlinear_is_refused(capsys):
    assert_input_error(capsys, "critical-speed", CONVENTIONAL, "--creep-law", "fastsim", mentions="--nonlinear")
