"""Issue 12, item 6 end to end: for the bundled standard-gauge vehicle on S1002/60E1
(``examples/manchester-s1002.toml``) ``express critical-speed --nonlinear`` reports the
linear critical speed (at the profiles' equivalent conicity) and the nonlinear one
(ramp-down with the contact tables) side by side, the figures quoted in
``docs/contact.md`` ("Nonlinear critical speed"); the nonlinear one converged in the time
step to the CLI's 0.1 km/h bracket (issue 23 item 2)."""

from __future__ import annotations

import contextlib
import csv
import io
import json
from pathlib import Path

import pytest

from express.analysis.stability.nonlinear_stability import nonlinear_critical_speed
from express.base.units import KMH
from express.cli import main
from express.numeric.statespace import load_vehicle

MODEL = Path(__file__).resolve().parents[1] / "examples" / "manchester-s1002.toml"


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    folder = tmp_path_factory.mktemp("manchester")
    out, fig = folder / "cycles.csv", folder / "cycles.png"
    stdout = io.StringIO()
    with contextlib.redirect_stdout(stdout):
        assert main(["critical-speed", str(MODEL), "--nonlinear", "--json", "-o", str(out), "--plot", str(fig)]) == 0
    return json.loads(stdout.getvalue()), out, fig


@pytest.mark.slow
def test_linear_and_nonlinear_critical_speed_side_by_side(cli_run):
    data, out, fig = cli_run
    nonlinear = data["nonlinear"]
    assert nonlinear["contact"] == "tables (table)"
    assert nonlinear["critical_speed_kmh"] < data["critical_speed_kmh"]  # subcritical hunting bifurcation
    low, high = nonlinear["bracket"]
    assert 0 < (high - low) * 3.6 <= 0.1 + 1e-9  # the CLI's default tolerance
    # the step-size check: the uncertainty holds the bracket and the last halving's change,
    # which stays within the 0.1 km/h bracket (1.25 -> 0.625 ms moves it one grid cell, 0.078 km/h)
    assert nonlinear["uncertainty"] == pytest.approx((high - low) + nonlinear["step_change"], rel=1e-9)
    assert nonlinear["converged_in_dt"] and nonlinear["step_change"] * 3.6 <= 0.1 + 1e-9
    # converged at 0.625 ms on the machines of 2026-12-01/02, at 1.25 ms on that of 12-03
    # (174.17 km/h both; the halvings stop when one moves the end by less than the bracket:
    # the processor's rounding is a change of path, see the regression guard below)
    assert nonlinear["dt"] in (0.00125, 0.000625)
    halvings = [0.005, 0.0025, 0.00125, 0.000625]
    assert [c["dt"] for c in nonlinear["step_checks"]] == halvings[: halvings.index(nonlinear["dt"]) + 1]
    rows = list(csv.DictReader(out.read_text().splitlines()))
    alive = [float(r["amplitude_m"]) for r in rows if r["limit_cycle"] == "1"]
    assert max(alive) > 7.5e-3 and min(alive) < 2e-3  # flange-contact branch (7.9 mm), then the tread cycle
    assert fig.stat().st_size > 10_000


@pytest.fixture(scope="module")
def library_run():
    """The CLI's search through the library (its 0.1 km/h bracket), for the result's state."""
    return nonlinear_critical_speed(load_vehicle(MODEL), tolerance=0.1 * KMH)


@pytest.mark.slow
def test_the_cli_reports_the_library_result(cli_run, library_run):
    """The same search, the same numbers (the runs are deterministic)."""
    nonlinear = cli_run[0]["nonlinear"]
    assert nonlinear["critical_speed"] == library_run.speed and nonlinear["bracket"] == list(library_run.bracket)


@pytest.mark.slow
def test_halving_the_reported_step_stays_within_the_bracket(library_run):
    """The end of the cycle once more at half the reported step (0.3125 ms), from the same
    anchor: it stays within the 0.1 km/h bracket (measured: the same bracket)."""
    result = library_run
    speed, state = result.anchor
    half = nonlinear_critical_speed(load_vehicle(MODEL), tolerance=0.1 * KMH, v_start=speed, initial_state=state,
                                    dt=result.dt / 2, refinements=0)
    assert half.dt == result.dt / 2 and half.step_checks[0].dt == result.dt / 2
    assert abs(half.speed - result.speed) <= result.options["tolerance"] + 1e-9


@pytest.mark.slow
def test_another_start_reaches_a_cycle_ending_within_0_7_kmh(library_run):
    """The ramp started at 300 km/h instead of 342.5 (another anchor, another speed grid):
    converged in dt too.  Measured with the contact of issue 22 (the converged pitch
    balance, the contact's lead): 174.45 km/h (bracket 174.38-174.45) against the default
    start's 173.94 (173.86-173.94), each at 0.625 ms with an uncertainty of 0.08 km/h: the
    start moves the end of the cycle by 0.52 km/h, more than the search's own uncertainty
    (before, 174.61-174.69 against 174.64-174.72 overlapped).  Held: within 0.7 km/h; the
    start dependence is reported in docs/contact.md."""
    other = nonlinear_critical_speed(load_vehicle(MODEL), tolerance=0.1 * KMH, v_start=300 * KMH,
                                     linear=library_run.linear)
    assert other.converged and other.dt <= library_run.dt
    assert abs(other.speed - library_run.speed) <= 0.7 * KMH


@pytest.mark.slow
@pytest.mark.regression
def test_critical_speeds_regression_guard(cli_run):
    """Regression guard, not validation: both speeds are this code's own earlier results
    (docs/contact.md quotes them): linear 284.4 km/h at tan gamma_e(3 mm) = 0.177 (bracket
    0.1 km/h); nonlinear with the default table law 172.45 km/h at dt 1.25 ms, uncertainty
    0.16 km/h (2026-12-06; with FASTSIM 173.94 km/h at dt 0.625 ms, uncertainty 0.08 km/h,
    173.3 km/h at the unrefined 5 ms step), with the wheel loads of the vertical contact springs, the
    contact's roll moment, the air and primary springs along their supports' axes and the
    contact of issue 22 item 2 (174.72 km/h before it; 285.4 and 175.44 km/h with those
    axes fixed in the track frame).

    The nonlinear speed is held within 0.7 km/h, not its 0.1 km/h bracket: the end of the
    limit cycle depends on the path into it by up to 0.52 km/h
    (``test_another_start_reaches_a_cycle_ending_within_0_7_kmh``), and the rounding of
    another processor's BLAS kernels is such a change of path — on an AMD EPYC with
    OpenBLAS's Haswell kernels the same code gives 174.33 km/h (2026-12-01), 0.39 km/h
    from the 173.94 km/h of the machine the value was first measured on."""
    data, _, _ = cli_run
    assert data["critical_speed_kmh"] == pytest.approx(284.40, abs=0.1)
    nonlinear = data["nonlinear"]
    assert nonlinear["critical_speed_kmh"] == pytest.approx(172.45, abs=0.7)  # path dependence, not the bracket


def test_the_model_takes_its_conicity_from_the_profiles():
    from express.rail.conicity import conicity_from_profiles
    from express.rail.contact_geometry import ContactSetup
    from express.rail.profiles import standard_profile

    values = load_vehicle(MODEL).values
    tan_gamma, _ = conicity_from_profiles(standard_profile("S1002"), standard_profile("60E1"), 3e-3, ContactSetup())
    assert values["Gamma_e"] == pytest.approx(float(tan_gamma), abs=2e-3) and values["Gamma_e"] == pytest.approx(0.177, abs=1e-3)
