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
