"""Nonlinear critical speed by ramp-down (express.analysis.stability.nonlinear_stability) and
``express critical-speed --nonlinear``.

The smallest rail vehicle (a wheelset on springs, tests/test_profile_contact.py) on
S1002/60E1 at 1:40: its hunting is subcritical, a limit cycle lives far below the linear
critical speed.  The result is checked against its definition with longer runs than
the ramp's: at the reported speed the cycle persists, just below the bracket it dies; and
in the time step: the search at half the reported step lands within the bracket.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json

import pytest

from cli_support import assert_input_error
from express.analysis.stability.nonlinear_stability import limit_cycle, nonlinear_critical_speed
from express.base.units import KMH
from express.cli import main
from express.io.toml_model import parse_toml_model
from express.numeric.statespace import vehicle_model
from test_profile_contact import WHEELSET


@pytest.fixture(scope="module")
def vehicle():
    return vehicle_model(parse_toml_model(WHEELSET, "wheelset.toml"))


@pytest.fixture(scope="module")
def result(vehicle):
    return nonlinear_critical_speed(vehicle, v_max=300.0)


def test_ramp_down_brackets_the_end_of_the_limit_cycle(result):
    assert result.contact == "tables (table)"
    dead, alive = result.bracket
    assert alive == result.speed and 0 < alive - dead <= 0.5 * KMH + 1e-12
    assert result.linear is not None and result.speed < 0.7 * result.linear.speed  # subcritical
    first = result.step_checks[0]
    assert first.dt == 0.005 and first.runs == len(result.points)
    ramp = [p for p in result.points if p.speed >= first.speed]
    assert ramp[0].speed == pytest.approx(1.2 * result.linear.speed)
    assert all(p.alive for p in ramp if p.speed >= first.speed)
    assert all(p.amplitude > 1e-4 for p in ramp if p.alive)
    assert not next(p for p in result.points if p.speed == first.bracket[0]).alive


def test_step_size_refined_until_halving_moves_it_less_than_the_bracket(result):
    """5 ms is too coarse here (239.25 km/h); 2.5 ms moves it down by five grid cells
    (1.5625 km/h), 1.25 ms not at all: the result is the 1.25 ms one (237.69 km/h, the
    table law; with FASTSIM 238.6 and 239.25 km/h, two cells up)."""
    dts = [check.dt for check in result.step_checks]
    assert dts == [0.005, 0.0025, 0.00125] and result.dt == 0.00125
    coarse, *_, fine = [check.speed / KMH for check in result.step_checks]
    cell = result.options["step"] / 16 / KMH  # 5 km/h halved to below the 0.5 km/h tolerance
    assert fine - coarse == pytest.approx(-5 * cell, abs=1e-9)
    assert result.converged and result.step_change <= result.options["tolerance"]
    width = result.bracket[1] - result.bracket[0]
    assert result.uncertainty == pytest.approx(width + result.step_change)
    assert "dt 1.25 ms" in result.describe() and "uncertainty" in result.describe()


def test_halving_the_reported_step_stays_within_the_bracket(vehicle, result):
    """The search once more at half the result's step, from the same anchor, without
    refinement: the end of the cycle stays within the bracket (here the same bracket)."""
    speed, state = result.anchor
    half = nonlinear_critical_speed(vehicle, v_max=300.0, v_start=speed, initial_state=state, dt=result.dt / 2,
                                    refinements=0)
    assert half.step_checks[0].dt == result.dt / 2 and len(half.step_checks) == 1
    assert abs(half.speed - result.speed) <= result.options["tolerance"] + 1e-9
    assert half.bracket == pytest.approx(result.bracket, abs=1e-9)


def test_result_meets_the_definition(vehicle, result):
    """Three times the ramp's run length at half the result's step: the cycle persists at
    the reported speed and dies 2 km/h below the bracket, both from the state on the cycle."""
    dt = result.dt / 2
    at, previous, *_ = limit_cycle(vehicle, result.speed, result.state, duration=18.0, dt=dt)
    assert at > 1e-4 and at == pytest.approx(previous, rel=0.05)
    below, *_ = limit_cycle(vehicle, result.bracket[0] - 2 * KMH, result.state, duration=18.0, dt=dt)
    assert below < 1e-4


def test_describe_and_options(result):
    text = result.describe()
    assert f"{result.speed_kmh:.1f} km/h" in text and "linear" in text
    assert result.options["duration"] == 6.0 and result.state.shape == (4,)
    assert result.options["refinements"] == 4 and result.options["longest"] == 40.0
    anchor, _ = result.anchor
    assert result.speed < anchor <= result.speed + result.options["step"]


def test_deadband_contact_without_profiles():
    text = WHEELSET.replace('f1 = "Gamma_e_f11"\nf2 = "Gamma_e_f22"', 'f1 = 9e6\nf2 = 8e6').replace(
        'conicity = { from = "profiles", wheel = "S1002", rail = "60E1", inclination = "1:40", gauge = "1435 mm", '
        'flange_back = "1360 mm", amplitude = "A" }', 'conicity = 0.2')
    vehicle = vehicle_model(parse_toml_model(text))
    result = nonlinear_critical_speed(vehicle, v_max=300.0, step=20 * KMH, tolerance=5 * KMH)
    assert result.contact == "deadband"
    assert result.speed is not None and result.speed <= 1.2 * result.linear.speed


def test_bad_options(vehicle):
    with pytest.raises(ValueError, match="v_start"):
        nonlinear_critical_speed(vehicle, v_start=10.0, v_min=20.0)
    with pytest.raises(ValueError, match="step"):
        nonlinear_critical_speed(vehicle, step=0.0)
    with pytest.raises(ValueError, match="no linear critical speed"):
        nonlinear_critical_speed(vehicle, v_max=50.0)
    with pytest.raises(ValueError, match="refinements"):
        nonlinear_critical_speed(vehicle, refinements=-1)
    with pytest.raises(ValueError, match="longest"):
        nonlinear_critical_speed(vehicle, longest=0.0)
    with pytest.raises(ValueError, match="initial_state"):
        nonlinear_critical_speed(vehicle, v_start=300 * KMH, initial_state=[0.0, 1.0])


def test_no_cycle_at_the_start(vehicle):
    result = nonlinear_critical_speed(vehicle, v_start=150 * KMH, disturbance=0.1e-3, v_max=300.0)
    assert result.speed is None and "no limit cycle" in result.describe()


@pytest.fixture(scope="module")
def cli_json(tmp_path_factory):
    folder = tmp_path_factory.mktemp("cli")
    model = folder / "wheelset.toml"
    model.write_text(WHEELSET)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        status = main(["critical-speed", str(model), "--nonlinear", "--json", "-o", str(folder / "b.csv"),
                       "--plot", str(folder / "b.png"), "--vmax", "1000", "--threshold", "0.1", "--disturbance",
                       "5 mm"])
    assert status == 0
    return json.loads(out.getvalue()), folder


@pytest.mark.regression
def test_cli_linear_critical_speed_regression_guard(cli_json):
    """Regression guard, not validation: 500.2 km/h is this code's own earlier result."""
    data, _ = cli_json
    assert data["critical_speed_kmh"] == pytest.approx(500.2, abs=0.1)  # the CLI's bracket, 0.1 km/h


def test_cli_nonlinear(cli_json, result):
    data, folder = cli_json
    nonlinear = data["nonlinear"]
    assert nonlinear["contact"] == "tables (table)"
    # the library's result (0.5 km/h bracket) and the CLI's (0.1 km/h) within their uncertainties
    assert abs(nonlinear["critical_speed"] - result.speed) <= nonlinear["uncertainty"] + result.uncertainty
    assert nonlinear["dt"] == nonlinear["step_checks"][-1]["dt"] <= 0.0025 and nonlinear["converged_in_dt"]
    assert nonlinear["uncertainty"] == pytest.approx(
        nonlinear["bracket"][1] - nonlinear["bracket"][0] + nonlinear["step_change"])
    rows = list(csv.DictReader((folder / "b.csv").read_text().splitlines()))
    assert len(rows) == len(nonlinear["speeds"]) and set(rows[0]) == {
        "speed_m_s", "speed_kmh", "amplitude_m", "limit_cycle", "flange_force_N", "flange_contact", "instability"}
    assert nonlinear["threshold"] == pytest.approx(1e-4) and nonlinear["disturbance"] == pytest.approx(5e-3)
    # the same attractors (the CLI starts from its own, finer linear critical speed)
    assert [a["flange_contact"] for a in nonlinear["attractors"]] == [a.flange_contact for a in result.attractors]
    assert [a["highest"] for a in nonlinear["attractors"]] == pytest.approx([a.highest for a in result.attractors],
                                                                           rel=1e-3)
    assert (folder / "b.png").stat().st_size > 10_000


def test_cli_nonlinear_usage(tmp_path, capsys):
    model = tmp_path / "wheelset.toml"
    model.write_text(WHEELSET)
    assert_input_error(capsys, "critical-speed", str(model), "--nonlinear", "--conicities", "0.1,0.2",
                       mentions="choose one")
    assert_input_error(capsys, "critical-speed", str(model), "--vstart", "300", mentions="--vstart")
    for option in ("--threshold", "--disturbance"):
        assert_input_error(capsys, "critical-speed", str(model), option, "1", mentions=f"{option} is used only with")
    assert_input_error(capsys, "critical-speed", str(model), "--nonlinear", "--threshold", "0", mentions="--threshold")
