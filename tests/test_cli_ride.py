"""``express ride`` (``express.cli.ride``): comfort per output point and wheel forces in
SI, track classes and user PSD tables, quantities with units, CSV with units in the
header, deterministic figures, bad input refused with nothing written."""

from __future__ import annotations

import csv
import io
import math

import numpy as np
import pytest

from cli_support import CONVENTIONAL, assert_fails, assert_input_error, run, run_json, valued_lever
from express.cli import main
from express.rail.track.spectra import ERRI_LOW
from test_ride_vehicle import two_axle_toml


@pytest.fixture(scope="module")
def two_axle(tmp_path_factory):
    path = tmp_path_factory.mktemp("ride_cli") / "two_axle.toml"
    path.write_text(two_axle_toml(), encoding="utf-8")
    return path


def _table(folder, name, text):
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path


def test_ride_json_on_the_lateral_car(capsys):
    data = run_json(capsys, "ride", CONVENTIONAL, "--track", "ERRI-low", "--speed", "120 km/h", "--points", "400")
    assert data["speed"] == pytest.approx(120 / 3.6) and data["track"] == "ERRI-low"
    assert data["components"] == ["alignment"]
    assert data["frequency_band_hz"] == pytest.approx([0.1, 50.0]) and data["points"] == 400
    assert any("vertical" in note for note in data["notes"])
    for point in ("floor_front", "floor_rear"):
        comfort = data["output_points"][point]
        assert comfort["directions"] == ["x", "y"]  # the car body has no vertical DOF
        assert 0.02 < comfort["rms"]["y"] < 0.5  # m/s^2 on a good track
        assert comfort["rms"]["x"] < 1e-6
        assert set(comfort["wz"]) == {"y"} and 1.0 < comfort["wz"]["y"] < 3.0
        assert 0.2 < comfort["n_mv"] < 2.0
        assert comfort["weighted_rms"]["y"] < comfort["rms"]["y"]
    for name in ("W1", "W2", "W3", "W4"):
        wheelset = data["wheelsets"][name]
        assert wheelset["dynamic_q"] is False and wheelset["wheel_load"] == pytest.approx(50031.0)
        assert wheelset["yq_level"]["L"] == pytest.approx(3 * wheelset["y_rms"] / wheelset["wheel_load"])


def test_ride_json_on_a_3d_car_gives_vertical_comfort_and_wheel_loads(capsys, two_axle):
    data = run_json(capsys, "ride", two_axle, "--track", "erri_high", "--points", "300")
    assert data["speed"] == pytest.approx(100 / 3.6)  # the model's own speed
    assert data["components"] == ["alignment", "vertical", "cross_level"]
    front = data["output_points"]["front"]
    assert front["directions"] == ["x", "y", "z"] and set(front["wz"]) == {"y", "z"}
    p95 = front["a_p95"]
    assert front["n_mv"] == pytest.approx(6 * math.sqrt(p95["x"] ** 2 + p95["y"] ** 2 + p95["z"] ** 2))
    w1 = data["wheelsets"]["W1"]
    assert w1["dynamic_q"] and w1["dq_rms"]["L"] == pytest.approx(w1["dq_rms"]["R"], rel=1e-6)
    assert w1["yq_level"]["L"] > 3 * w1["y_rms"] / w1["wheel_load"]  # the dynamic load only adds


def test_a_wheel_that_unloads_at_3_sigma_is_a_result_not_an_error(capsys, tmp_path, two_axle):
    """Issue 36: the Y/Q level is unbounded where 3 s_Q >= Q0; ride printed half its table
    and exited 1 naming a JSON path.  Now the level is told as "unloads", with its figures."""
    rough = _table(tmp_path, "rough.csv", "n [1/m],alignment [m^3],vertical [m^3]\n0.01,1e-3,1e-2\n1,1e-3,1e-2\n")
    data = run_json(capsys, "ride", two_axle, "--track", rough, "--points", "200")
    w1 = data["wheelsets"]["W1"]
    assert 3 * w1["dq_rms"]["L"] >= w1["wheel_load"]
    assert w1["unloads"] == {"L": True, "R": True} and w1["yq_level"] == {"L": None, "R": None}
    assert any(note.startswith("W1 L: 3 standard deviations of the dynamic wheel load") for note in data["notes"])
    status, out, err = run(capsys, "ride", two_axle, "--track", rough, "--points", "200")
    assert status == 0, err
    (row,) = [line for line in out.splitlines() if line.strip().startswith("W1 ")]
    assert "unloads/unloads" in row
    assert "Y/Q has no 3-sigma level" in err
    gentle = run_json(capsys, "ride", two_axle, "--track", "erri_low", "--points", "200")["wheelsets"]["W1"]
    assert gentle["unloads"] == {"L": False, "R": False} and gentle["yq_level"]["L"] > 0


@pytest.mark.parametrize("speed", ["120", "120 km/h", "33.3333333333 m/s"])
def test_ride_speed_units(capsys, speed):
    data = run_json(capsys, "ride", CONVENTIONAL, "--track", "ERRI-low", "--speed", speed, "--points", "100")
    assert data["speed"] == pytest.approx(120 / 3.6)


def test_ride_track_level_scales_the_accelerations(capsys):
    """Only the alignment drives the lateral car: ERRI high / low = sqrt(6.125 / 2.119)."""
    low = run_json(capsys, "ride", CONVENTIONAL, "--track", "ERRI-low", "--points", "200")
    high = run_json(capsys, "ride", CONVENTIONAL, "--track", "ERRI-high", "--points", "200")
    ratio = high["output_points"]["floor_front"]["rms"]["y"] / low["output_points"]["floor_front"]["rms"]["y"]
    assert ratio == pytest.approx(math.sqrt(6.125 / 2.119), rel=1e-9)


@pytest.mark.parametrize("unit, scale", [("Omega [rad/m]", 1.0), ("n [1/m]", 2 * math.pi)])
def test_ride_user_table_equals_the_published_spectrum_it_tabulates(capsys, tmp_path, unit, scale):
    """ERRI low alignment written as a fine table (per rad/m or per cycle/m) gives the
    class's result within the linear interpolation error."""
    omega = np.geomspace(1e-3, 20.0, 3000)
    psd = ERRI_LOW.psd(omega)
    column = "alignment [m^2/(rad/m)]" if scale == 1.0 else "alignment [m^2/(1/m)]"
    # per cycle/m: n = Omega / 2 pi, G(n) = 2 pi S(Omega)
    rows = "\n".join(f"{w / scale:.10g},{g * scale:.10g}" for w, g in zip(omega, psd, strict=True))
    table = _table(tmp_path, "erri.csv", f"# ERRI low alignment\n{unit},{column}\n{rows}\n")
    mine = run_json(capsys, "ride", CONVENTIONAL, "--track", table, "--points", "300")
    published = run_json(capsys, "ride", CONVENTIONAL, "--track", "ERRI-low", "--points", "300")
    assert mine["components"] == ["alignment"] and mine["track"] == str(table)
    for point in ("floor_front", "floor_rear"):
        assert mine["output_points"][point]["rms"]["y"] == pytest.approx(
            published["output_points"][point]["rms"]["y"], rel=2e-3)


@pytest.mark.slow
def test_ride_writes_psd_csv_with_units_and_a_deterministic_figure(capsys, tmp_path, two_axle):
    table, first, second = tmp_path / "ride.csv", tmp_path / "a.svg", tmp_path / "b.svg"
    status, out, err = run(capsys, "ride", two_axle, "--track", "ERRI-low", "--points", "50", "-o", table, "--plot", first)
    assert status == 0, err
    assert "front" in out and "N_MV" in out and "W1" in out
    status, _, err = run(capsys, "ride", two_axle, "--track", "ERRI-low", "--points", "50", "--plot", second)
    assert status == 0, err
    rows = list(csv.reader(table.open(encoding="utf-8")))
    header = rows[0]
    assert header[0] == "frequency_hz" and len(rows) == 51
    for column in ("track_vertical_psd_m2_Hz", "front.az_psd_m2_s4_Hz", "W1.Y_psd_N2_Hz", "W1.dQL_psd_N2_Hz",
                   "W1.y_rel_psd_m2_Hz"):
        assert column in header, header
    values = np.array(rows[1:], dtype=float)
    assert np.all(values >= 0) and np.all(np.diff(values[:, 0]) > 0)
    assert first.read_bytes() == second.read_bytes() and b"<svg" in first.read_bytes()


def test_ride_csv_on_standard_output(capsys):
    status, out, err = run(capsys, "ride", CONVENTIONAL, "--track", "FRA-6", "--points", "20", "-o", "-")
    assert status == 0, err
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0][0] == "frequency_hz" and len(rows) == 21
    assert "floor_front" in err  # the table goes to standard error


_TABLES = {
    "negative.csv": ("n [1/m], vertical\n0.01, 1e-4\n0.02, -1e-5\n0.03, 1e-6\n", "PSD must be in 0 ... 1000 m^3"),
    "overflow.csv": ("n [1/m], vertical\n0.01, 1e300\n0.02, 1e-5\n", "PSD must be in 0 ... 1000 m^3"),
    "unsorted.csv": ("n [1/m], vertical\n0.01, 1e-4\n0.03, 1e-5\n0.02, 1e-6\n", "wavenumbers must increase"),
    "header.csv": ("frequency, vertical\n0.01, 1e-4\n0.02, 1e-5\n", "first column must be"),
    "component.csv": ("n [1/m], twist\n0.01, 1e-4\n0.02, 1e-5\n", "unknown component"),
    "unit.csv": ("n [1/m], vertical [m^2/(rad/m)]\n0.01, 1e-4\n0.02, 1e-5\n", "unit must be"),
    "text.csv": ("n [1/m], vertical\n0.01, abc\n0.02, 1e-5\n", "not a number"),
    "short.csv": ("n [1/m], vertical\n0.01, 1e-4\n", "at least two rows"),
    "twice.csv": ("n [1/m], alignment, alignment\n0.01, 1e-4, 2e-4\n0.02, 1e-5, 2e-5\n", "given twice"),
}


@pytest.mark.parametrize("name", sorted(_TABLES))
def test_ride_bad_psd_tables_exit_2_with_the_line_and_write_nothing(capsys, tmp_path, name):
    text, mentions = _TABLES[name]
    table = _table(tmp_path, name, text)
    output, plot = tmp_path / "out.csv", tmp_path / "out.png"
    err = assert_input_error(capsys, "ride", CONVENTIONAL, "--track", table, "-o", output, "--plot", plot, mentions=mentions)
    assert f"error: {table}:" in err  # file (and line) of the problem
    assert not output.exists() and not plot.exists()


def test_ride_table_reports_every_problem_at_once(capsys, tmp_path):
    table = _table(tmp_path, "two.csv", "n [1/m], vertical\n0.01, 1e-4\n0.005, -1e-5\n0.03, 1e-6\n")
    err = assert_input_error(capsys, "ride", CONVENTIONAL, "--track", table)
    assert f"{table}:3: column vertical: PSD must be in 0 ... 1000" in err
    assert f"{table}:3: column n: wavenumbers must increase" in err


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["--track", "ERRI-medium"], "unknown track class"),
        (["--track", "FRA-7"], "known: ERRI-low"),
        (["--track", "missing.csv"], "cannot read"),
        (["--track", "ERRI-low", "--speed", "0"], "--speed"),
        (["--track", "ERRI-low", "--speed", "-10 km/h"], "--speed"),
        (["--track", "ERRI-low", "--speed", "3 kg"], "--speed"),
        (["--track", "ERRI-low", "--set", "v=0"], "speed"),
        (["--track", "ERRI-low", "--fmin", "5", "--fmax", "2"], "--fmax"),
        (["--track", "ERRI-low", "--points", "3"], "16 <= --points"),
        (["--track", "ERRI-low", "-o", "-", "--json"], "standard output"),
        (["--track", "ERRI-low", "--plot", "x.gif"], ".png"),
        ([], "--track"),
    ],
)
def test_ride_bad_input_exits_2(capsys, tmp_path, argv, mentions):
    output = tmp_path / "never.csv"
    assert_input_error(capsys, "ride", CONVENTIONAL, *argv, *([] if "-o" in argv else ["-o", output]), mentions=mentions)
    assert not output.exists()


def test_ride_above_the_critical_speed_says_so_and_writes_no_psd(capsys, tmp_path):
    """The check of ``express frf`` (``analysis.frequency.frequency.require_stable``): the same
    least-damped mode.  Unstable is a result: exit 0 with the nonlinear run's ride
    (``tests/test_ride_nonlinear.py``), and no PSD file or figure (none exists)."""
    output, plot = tmp_path / "psd.csv", tmp_path / "psd.png"
    status = main(["ride", str(CONVENTIONAL), "--track", "ERRI-low", "--speed", "500", "-o", str(output),
                   "--plot", str(plot)])
    captured = capsys.readouterr()
    assert status == 0 and "Traceback" not in captured.err
    assert "unstable at 500.0 km/h" in captured.out and "hunting" in captured.out
    assert "no stationary PSD exists" in captured.out and "the ride of the nonlinear run" in captured.out
    assert not output.exists() and not plot.exists() and captured.err.count("not written") == 2
    frf = assert_fails(capsys, 1, "frf", CONVENTIONAL, "--speed", "500", mentions="unstable at 500.0 km/h")
    eigenvalue = frf.split("least-damped eigenvalue ")[1].split(",")[0]
    assert f"least-damped eigenvalue {eigenvalue}," in captured.out


@pytest.mark.parametrize("level", [1, 5])
def test_ride_aar_classes_are_the_us_class_spectra(capsys, level):
    aar = run_json(capsys, "ride", CONVENTIONAL, "--track", f"AAR-{level}", "--speed", "100", "--points", "200")
    fra = run_json(capsys, "ride", CONVENTIONAL, "--track", f"fra_{level}", "--speed", "100", "--points", "200")
    assert aar["track"] == f"AAR-{level}" and aar["components"] == ["alignment"]
    assert aar["output_points"] == fra["output_points"] and aar["wheelsets"] == fra["wheelsets"]


def test_ride_unknown_track_class_lists_every_valid_name(capsys, tmp_path):
    from express.analysis.ride.vehicle import TRACK_CLASSES

    output = tmp_path / "never.csv"
    err = assert_input_error(capsys, "ride", CONVENTIONAL, "--track", "AAR-7", "-o", output, mentions="unknown track class")
    assert all(name in err for name in TRACK_CLASSES) and "AAR-6" in err and len(err.strip().splitlines()) == 1
    assert not output.exists()


def test_ride_help_lists_the_library_track_classes(capsys):
    from express.analysis.ride.vehicle import TRACK_CLASSES
    from express.cli import ride

    assert ride.TRACK_CLASSES == TRACK_CLASSES
    status, out, _ = run(capsys, "ride", "--help")
    assert status == 0 and "ERRI-low" in out and "FRA-6" in out and "AAR-6" in out


def test_ride_needs_rail_data(capsys, tmp_path):
    assert_input_error(capsys, "ride", valued_lever(tmp_path), "--track", "ERRI-low", mentions="no rail data")
