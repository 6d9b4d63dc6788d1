"""``express curving`` (``express.cli.curving``): one curve, sweeps, tracks, bad curves."""

from __future__ import annotations

import csv
import io

import pytest

from cli_support import CONVENTIONAL, STEERED, assert_input_error, run, run_json


def test_one_curve_json(capsys):
    data = run_json(capsys, "curving", CONVENTIONAL, "--radius", "400", "--cant", "105", "--speed", "120")
    (row,) = data["results"]
    assert row["R"] == 400.0 and row["cant"] == pytest.approx(0.105) and row["speed"] == pytest.approx(120 / 3.6)
    assert data["units"]["Q1L"] == "N" and data["units"]["aoa1"] == "rad"
    assert data["loads"] == "quasi-static estimate"
    assert row["flanging1L"] == 1.0  # right curve: the outer wheel of the leading wheelset flanges
    assert row["a_q"] == pytest.approx(1.80, abs=0.01)
    (assessment,) = data["assessments"]
    by_name = {c["name"]: c for c in assessment["criteria"]}
    assert by_name["YQ1L"]["value"] == pytest.approx(row["YQ1L"]) and by_name["YQ1L"]["limit"] == 0.8


def test_sweep_writes_csv_and_figure(capsys, tmp_path):
    table, figure = tmp_path / "c.csv", tmp_path / "c.png"
    status, out, err = run(capsys, "curving", STEERED, "--radius", "250:2000:250", "--cant", "105", "--speed", "80",
                           "-o", table, "--plot", figure)
    assert status == 0, err
    rows = list(csv.DictReader(io.StringIO(table.read_text())))
    assert [float(r["R_m"]) for r in rows] == [250.0 * k for k in range(1, 9)]
    assert {"YQ1L", "SY1_N", "aoa1_rad", "dQQ0", "Q1L_N", "gamma1L_rad", "flanging1L"} <= set(rows[0])
    assert figure.stat().st_size > 10_000
    assert "steady curving" in out and "wrote" in err


def test_sweep_over_cant_deficiency(capsys):
    data = run_json(capsys, "curving", CONVENTIONAL, "--radius", "600", "--cant", "100", "--cant-deficiency", "-0.5,0,0.5,1")
    assert [round(r["a_q"], 9) for r in data["results"]] == [-0.5, 0.0, 0.5, 1.0]


def test_bundled_track_gives_curve_and_speed(capsys):
    data = run_json(capsys, "curving", CONVENTIONAL, "--track", "R1000")
    (row,) = data["results"]
    assert (row["R"], row["cant"], row["speed"]) == pytest.approx((1000.0, 0.150, 150 / 3.6))
    assert "R1000" in data["curves"] and "track's speed" in data["curves"]


def test_model_speed_is_said(capsys):
    status, out, _ = run(capsys, "curving", CONVENTIONAL, "--radius", "800", "--cant", "50")
    assert status == 0 and "model's speed 120 km/h" in out


@pytest.mark.parametrize(("argv", "mentions"), [
    (["--radius", "0", "--speed", "80"], "--radius"),
    (["--radius", "400", "--cant", "1100", "--speed", "80"], "--cant"),
    (["--radius", "400", "--cant", "450", "--speed", "80", "--set", "G=0.4"], "cant base"),
    (["--radius", "300", "--cant", "0", "--speed", "160"], "unbalanced acceleration"),
    (["--track", "R123"], "bundled"),
    (["--speed", "80"], "--radius"),
])
def test_bad_curves_exit_2_and_write_nothing(capsys, tmp_path, argv, mentions):
    table = tmp_path / "c.csv"
    assert_input_error(capsys, "curving", CONVENTIONAL, *argv, "-o", table, mentions=mentions)
    assert not table.exists()


def test_simulate_assess_on_a_bundled_track(capsys, tmp_path):
    table = tmp_path / "run.csv"
    status, out, err = run(capsys, "simulate", CONVENTIONAL, "--track", "R600", "--assess", "--dt", "0.01", "-o", table,
                           "--json")
    assert status == 0, err
    import json

    data = json.loads(out)
    assert "bundled track R600" in data["track_used"] and "track's speed 115 km/h" in data["track_used"]
    assert data["speed"] == pytest.approx(115 / 3.6)
    names = {c["name"] for c in data["assessment"]["criteria"]}
    assert {"YQ1L", "YQ1L_nadal", "SY4", "dQQ0"} <= names
    assert all(c["limit"] is not None for c in data["assessment"]["criteria"])
    header = table.read_text().splitlines()[0].split(",")
    assert {"YQ1L", "SY1_N", "Q1L_N", "aoa1_rad", "gamma1R_rad", "flanging1L"} <= set(header)


def test_simulate_says_which_track_and_speed(capsys, tmp_path):
    status, out, _ = run(capsys, "simulate", CONVENTIONAL, "--dt", "0.02")
    assert status == 0 and "no --track given" in out and "model's speed 120 km/h" in out
    status, out, _ = run(capsys, "simulate", CONVENTIONAL, "--track", "R1000", "--speed", "100", "--dt", "0.02")
    assert status == 0 and "overridden" in out


def test_simulate_derailment_exits_3_and_keeps_history(capsys, tmp_path):
    """A derailment is a result judged, not the absence of one: status 3 (issue 32 item 6)."""
    table = tmp_path / "run.csv"
    # mu = 1: Nadal's limit at 70 degrees falls to 0.47, below the leading wheel's flanging Y/Q
    status, out, err = run(capsys, "simulate", CONVENTIONAL, "--track", "R250", "--speed", "90", "--assess",
                           "--dt", "0.01", "--set", "mu=1.0", "-o", table)
    assert status == 3, err
    assert "derails" in err and table.exists() and "FAIL" in out
    assert "the assessment fails: " in err and "_nadal" in err.split("the assessment fails: ")[1]


def test_report_takes_a_track_and_assesses(capsys, tmp_path):
    target = tmp_path / "report.html"
    status, _, err = run(capsys, "report", CONVENTIONAL, "--track", "R1000", "-o", target)
    assert status == 0, err
    page = target.read_text()
    assert "bundled track R1000" in page and "at 150 km/h" in page
    assert "YQ1L_nadal" in page and "Prud" in page


TIGHT = """
[[segment]]
type = "transition"
length = 50.0
[[segment]]
type = "curve"
length = 100.0
radius = 250.0
direction = "right"
cant = "150 mm"
"""


@pytest.mark.parametrize("command", ["simulate", "report"])
def test_a_curve_too_fast_for_the_track_exits_2(capsys, tmp_path, command):
    # R = 250 m with 150 mm cant at 160 km/h: 6.5 m/s^2 of cant deficiency on the narrow gauge
    track = tmp_path / "tight.toml"
    track.write_text(TIGHT, encoding="utf-8")
    target = tmp_path / ("out.csv" if command == "simulate" else "out.html")
    err = assert_input_error(capsys, command, CONVENTIONAL, "--track", track, "--set", "v=160", "-o", target,
                             mentions="unbalanced acceleration")
    assert "curve 1 of the track" in err and not target.exists()


def test_simulate_assess_gives_the_instability_criterion_of_every_wheelset(capsys):
    """EN 14363's ΣY rms over 100 m against (ΣY)lim / 2 (issue 32 item 4), beside (ΣY)2m."""
    data = run_json(capsys, "simulate", CONVENTIONAL, "--track", "R1000", "--speed", "100", "--assess", "--dt", "0.01")
    criteria = {c["name"]: c for c in data["assessment"]["criteria"]}
    for j in range(1, 5):
        rms, peak = criteria[f"SY{j}_rms"], criteria[f"SY{j}"]
        assert rms["limit"] == pytest.approx(peak["limit"] / 2, rel=1e-12) and rms["unit"] == "N"
        assert 0 <= rms["value"] < peak["value"] and rms["passed"] is True
        assert "over 100 m" in rms["quantity"]
