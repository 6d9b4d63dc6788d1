"""The analysis commands of the ``express`` CLI: simulate, frf, eigen, critical-speed.

Each command runs through ``express.cli.main`` as a user would; ``--json`` outputs are
parsed and checked for their keys and SI units; mistakes end with exit status 2 and
one ``error:`` line, never a traceback.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from express.cli import main

ROOT = Path(__file__).resolve().parents[1]
STEERED = str(ROOT / "examples" / "forced-steering.toml")
CONVENTIONAL = str(ROOT / "examples" / "conventional.toml")
LEVER = str(ROOT / "examples" / "lever.exp")
SINUSOID = str(ROOT / "examples" / "tracks" / "straight_sinusoid.toml")

SHORT_TRACK = """
name = "short test curve"
[[segment]]
type = "straight"
length = 10.0
[[segment]]
type = "transition"
length = 30.0
[[segment]]
type = "curve"
length = 40.0
radius = 400.0
direction = "left"
cant = "95 mm"
"""


def run(capsys, *argv):
    """``(status, stdout, stderr)`` of ``express argv``."""
    status = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return status, out, err


def run_json(capsys, *argv):
    status, out, err = run(capsys, *argv, "--json")
    assert status == 0, err
    return json.loads(out)


def assert_usage_error(capsys, *argv, mentions: str = ""):
    status, out, err = run(capsys, *argv)
    assert status == 2
    assert "Traceback" not in err
    assert err.startswith("error:"), err
    if mentions:
        assert mentions in err, err
    return err


@pytest.fixture
def short_track(tmp_path):
    path = tmp_path / "short.toml"
    path.write_text(SHORT_TRACK, encoding="utf-8")
    return path


# --------------------------------------------------------------------------------------
# simulate
# --------------------------------------------------------------------------------------


def test_simulate_json_on_the_paper_curve(capsys):
    data = run_json(capsys, "simulate", CONVENTIONAL, "--dt", "0.01")
    assert data["speed"] == pytest.approx(120 / 3.6)  # m/s, the model's speed
    assert data["track_length"] == pytest.approx(460.0)  # the paper's curve
    maxima = data["max_abs"]
    for key in ("Q1", "Q2", "psi_TW1", "psi_TW2"):
        assert key in maxima
    assert not any(key.startswith("theta_") for key in maxima)  # no levers on this car
    # SI: newtons and radians (tens of kN, a fraction of a milliradian)
    assert 5e3 < maxima["Q1"] < 1e5
    assert 0 < maxima["psi_TW1"] < 0.01
    assert maxima["rho1"] == pytest.approx(1 / 400)


def test_simulate_steered_reports_lever_angles_and_writes_files(capsys, short_track, tmp_path):
    outputs = [tmp_path / "run.csv", tmp_path / "run.npz", tmp_path / "out" / "run.mat"]
    figure = tmp_path / "run.png"
    args = ["simulate", STEERED, "--track", short_track, "--dt", "0.01", "--plot", figure]
    for path in outputs:
        args += ["-o", path]
    data = run_json(capsys, *args)
    assert data["track_length"] == pytest.approx(80.0)
    assert {"theta_L1", "theta_L2", "theta_L3", "theta_L4", "Q1", "Q2", "psi_TW1", "psi_TW2"} <= set(data["max_abs"])
    assert data["max_abs"]["theta_L1"] > 0.01  # the lever turns in the curve [rad]
    for path in outputs + [figure]:
        assert path.is_file() and path.stat().st_size > 0, path
    with open(outputs[0], newline="", encoding="utf-8") as stream:
        header = next(csv.reader(stream))
    assert {"time", "d1", "Q1", "theta_L1"} <= set(header)
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with np.load(outputs[1]) as npz:
        assert "Q1" in npz.files


def test_simulate_set_changes_the_result(capsys, short_track):
    base = run_json(capsys, "simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.01")
    changed = run_json(capsys, "simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.01", "--set", "Gamma=0.05")
    assert changed["max_abs"]["psi_TW1"] != pytest.approx(base["max_abs"]["psi_TW1"], rel=1e-3)


def test_simulate_track_speed_and_linear_options(capsys):
    data = run_json(capsys, "simulate", CONVENTIONAL, "--track", SINUSOID, "--speed", "80", "--linear", "--dt", "0.01")
    assert data["speed"] == pytest.approx(80 / 3.6)
    assert data["linear"] is True
    assert data["max_abs"]["flange1"] == 0.0  # no flange contact in the linear run


def test_simulate_prints_a_readable_summary(capsys, short_track):
    status, out, err = run(capsys, "simulate", CONVENTIONAL, "--track", short_track, "--dt", "0.01")
    assert status == 0, err
    assert "km/h" in out and "kN" in out and "Q1" in out


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["simulate", CONVENTIONAL, "--speed", "fast"], "--speed"),
        (["simulate", CONVENTIONAL, "--speed", "-5"], "positive"),
        (["simulate", CONVENTIONAL, "--dt", "0"], "--dt"),
        (["simulate", CONVENTIONAL, "-o", "results.txt"], ".csv"),
        (["simulate", CONVENTIONAL, "--plot", "figure.gif"], ".png"),
        (["simulate", LEVER], "rail data"),
        (["simulate", "no-such-model.toml"], "does not exist"),
        (["simulate", CONVENTIONAL, "--track", "no-such-track.toml"], "no-such-track.toml"),
        (["simulate", CONVENTIONAL, "--set", "Gamma"], "NAME=VALUE"),
    ],
)
def test_simulate_bad_input_exits_2(capsys, argv, mentions):
    assert_usage_error(capsys, *argv, mentions=mentions)


def test_simulate_bad_track_file_exits_2(capsys, tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('[[segment]]\ntype = "curve"\nlength = -3\n', encoding="utf-8")
    assert_usage_error(capsys, "simulate", CONVENTIONAL, "--track", bad, mentions="bad.toml")


def test_simulate_refuses_to_overwrite_its_model(capsys, tmp_path):
    model = tmp_path / "car.toml"
    model.write_text(Path(CONVENTIONAL).read_text(encoding="utf-8"), encoding="utf-8")
    before = model.read_bytes()
    assert_usage_error(capsys, "frf", model, "-o", model, mentions="refusing")
    assert_usage_error(capsys, "critical-speed", model, "--conicities", "0.1", "-o", model, mentions="refusing")
    assert model.read_bytes() == before


# --------------------------------------------------------------------------------------
# frf
# --------------------------------------------------------------------------------------


def test_frf_json_floor_accelerations_and_dof(capsys):
    data = run_json(capsys, "frf", STEERED, "--points", "25", "--dof", "W1.y")
    assert len(data["frequencies"]) == 25
    assert data["frequencies"][0] == pytest.approx(0.1) and data["frequencies"][-1] == pytest.approx(20.0)
    assert data["amplitude"] == pytest.approx(1e-3)  # 1 mm, in metres
    assert data["speed"] == pytest.approx(120 / 3.6)
    outputs = data["outputs"]
    assert {"floor_front", "floor_rear", "W1.y"} <= set(outputs)
    assert outputs["floor_front"]["unit"] == "m/s^2" and outputs["W1.y"]["unit"] == "m"
    front = np.array(outputs["floor_front"]["amplitude"])
    rear = np.array(outputs["floor_rear"]["amplitude"])
    assert front.shape == (25,) and np.all(front >= 0)
    assert 0.01 < front.max() < 5.0  # m/s^2 for a 1 mm irregularity
    assert not np.allclose(front, rear)  # front and rear differ (paper Fig. 10)
    assert np.array(outputs["W1.y"]["amplitude"])[0] == pytest.approx(1e-3, rel=0.05)  # follows the track at 0.1 Hz
    assert data["peaks"]["floor_front"]["frequency_hz"] > 0


def test_frf_amplitude_scales_and_set_changes(capsys):
    one = run_json(capsys, "frf", CONVENTIONAL, "--points", "10")
    two = run_json(capsys, "frf", CONVENTIONAL, "--points", "10", "--amplitude", "2")
    assert np.allclose(np.array(two["outputs"]["floor_front"]["amplitude"]),
                       2 * np.array(one["outputs"]["floor_front"]["amplitude"]))
    changed = run_json(capsys, "frf", CONVENTIONAL, "--points", "10", "--set", "Gamma=0.05")
    assert not np.allclose(changed["outputs"]["floor_front"]["amplitude"], one["outputs"]["floor_front"]["amplitude"])


def test_frf_writes_csv_and_deterministic_svg(capsys, tmp_path):
    table, first, second = tmp_path / "frf.csv", tmp_path / "a.svg", tmp_path / "b.svg"
    status, out, err = run(capsys, "frf", CONVENTIONAL, "--points", "12", "-o", table, "--plot", first)
    assert status == 0, err
    assert "floor_front" in out
    status, _, err = run(capsys, "frf", CONVENTIONAL, "--points", "12", "--plot", second)
    assert status == 0, err
    rows = list(csv.reader(table.open(encoding="utf-8")))
    assert rows[0][0] == "frequency_hz" and "floor_front_acc_amplitude" in rows[0]
    assert len(rows) == 13
    assert first.read_bytes() == second.read_bytes()  # no date, fixed hash salt
    assert b"<svg" in first.read_bytes()


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["frf", CONVENTIONAL, "--fmin", "0"], "--fmin"),
        (["frf", CONVENTIONAL, "--fmin", "5", "--fmax", "2"], "--fmax"),
        (["frf", CONVENTIONAL, "--points", "1"], "--points"),
        (["frf", CONVENTIONAL, "--amplitude", "-1"], "--amplitude"),
        (["frf", CONVENTIONAL, "--dof", "W9.y"], "W9.y"),
        (["frf", LEVER], "rail data"),
    ],
)
def test_frf_bad_input_exits_2(capsys, argv, mentions):
    assert_usage_error(capsys, *argv, mentions=mentions)


# --------------------------------------------------------------------------------------
# eigen
# --------------------------------------------------------------------------------------


def test_eigen_json(capsys):
    data = run_json(capsys, "eigen", CONVENTIONAL)
    assert data["speed_kmh"] == pytest.approx(120.0)
    assert data["speed"] == pytest.approx(120 / 3.6)
    eigenvalues = np.array(data["eigenvalues"])
    assert eigenvalues.shape == (40, 2)  # 20 DOFs -> 40 eigenvalues, [re, im]
    assert data["stable"] is True and eigenvalues[:, 0].max() < 0
    assert all({"eigenvalue", "frequency_hz", "damping_ratio", "dominant", "label"} <= set(m) for m in data["modes"])


def test_eigen_speed_and_set_change_the_eigenvalues(capsys):
    base = np.array(run_json(capsys, "eigen", CONVENTIONAL)["eigenvalues"])
    faster = run_json(capsys, "eigen", CONVENTIONAL, "--speed", "200")
    assert faster["speed_kmh"] == pytest.approx(200.0)
    assert not np.allclose(np.array(faster["eigenvalues"]), base)
    changed = np.array(run_json(capsys, "eigen", CONVENTIONAL, "--set", "Gamma=0.05")["eigenvalues"])
    assert not np.allclose(changed, base)


def test_eigen_table(capsys):
    status, out, err = run(capsys, "eigen", STEERED, "--speed", "120 km/h")
    assert status == 0, err
    assert "f [Hz]" in out and "zeta" in out and "dominant" in out
    assert "hunting" in out and "steering lever" in out and "car body" in out


def test_eigen_bad_input_exits_2(capsys):
    assert_usage_error(capsys, "eigen", CONVENTIONAL, "--speed", "0", mentions="positive")
    assert_usage_error(capsys, "eigen", CONVENTIONAL, "--speed", "3 kg", mentions="--speed")
    assert_usage_error(capsys, "eigen", LEVER, mentions="rail data")


# --------------------------------------------------------------------------------------
# critical-speed
# --------------------------------------------------------------------------------------


def test_critical_speed_json(capsys):
    data = run_json(capsys, "critical-speed", CONVENTIONAL)
    assert set(data) >= {"critical_speed_kmh", "critical_speed", "mode"}
    assert data["critical_speed"] == pytest.approx(data["critical_speed_kmh"] / 3.6)
    assert 150 < data["critical_speed_kmh"] < 540
    assert "hunting" in data["mode"]


def test_critical_speed_depends_on_conicity(capsys):
    base = run_json(capsys, "critical-speed", STEERED)["critical_speed_kmh"]
    low = run_json(capsys, "critical-speed", STEERED, "--set", "Gamma=0.05")["critical_speed_kmh"]
    assert low < 0.5 * base  # the steered car's sharp fall at small conicity (paper Fig. 11)


def test_critical_speed_stable_over_the_range(capsys):
    data = run_json(capsys, "critical-speed", CONVENTIONAL, "--vmax", "100")
    assert data["critical_speed_kmh"] is None and data["mode"] is None
    status, out, _ = run(capsys, "critical-speed", CONVENTIONAL, "--vmax", "100")
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
    assert rows[0][:3] == ["Gamma", "critical_speed_m_s", "critical_speed_kmh"] and len(rows) == 4
    assert figure.read_bytes()[:4] == b"\x89PNG"


def test_critical_speed_root_locus_plot(capsys, tmp_path):
    figure = tmp_path / "locus.svg"
    status, out, err = run(capsys, "critical-speed", CONVENTIONAL, "--plot", figure)
    assert status == 0, err
    assert "critical speed" in out and figure.is_file()


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["critical-speed", CONVENTIONAL, "--conicities", "abc"], "START:STOP:COUNT"),
        (["critical-speed", CONVENTIONAL, "--conicities", "0.1:0.2"], "START:STOP:COUNT"),
        (["critical-speed", CONVENTIONAL, "--conicities=-0.1:0.2:3"], "positive"),
        (["critical-speed", CONVENTIONAL, "--vmax", "2"], "--vmax"),
        (["critical-speed", CONVENTIONAL, "-o", "x.csv"], "--conicities"),
        (["critical-speed", CONVENTIONAL, "--conicities", "0.1", "--parameter", "nope"], "nope"),
        (["critical-speed", LEVER], "rail data"),
    ],
)
def test_critical_speed_bad_input_exits_2(capsys, argv, mentions):
    assert_usage_error(capsys, *argv, mentions=mentions)


def test_analysis_commands_are_listed_in_help(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--help"])
    assert exit_info.value.code == 0
    out = capsys.readouterr().out
    for command in ("simulate", "frf", "eigen", "critical-speed", "demo"):
        assert command in out
