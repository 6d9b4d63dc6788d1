"""``express frf`` (``express.cli.frf``): accelerations of the output points in SI,
CSV with units in the header, deterministic figures, ranges of the options."""

from __future__ import annotations

import csv
import io

import numpy as np
import pytest

from cli_support import CONVENTIONAL, LEVER, STEERED, assert_input_error, run, run_json, valued_lever


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


@pytest.mark.parametrize("amplitude", ["2", "2 mm", "0.2 cm", "0.002 m"])
def test_frf_amplitude_scales_and_takes_units(capsys, amplitude):
    one = run_json(capsys, "frf", CONVENTIONAL, "--points", "10")
    two = run_json(capsys, "frf", CONVENTIONAL, "--points", "10", "--amplitude", amplitude)
    assert two["amplitude"] == pytest.approx(0.002)
    assert np.allclose(np.array(two["outputs"]["floor_front"]["amplitude"]),
                       2 * np.array(one["outputs"]["floor_front"]["amplitude"]))


def test_frf_set_changes_the_response(capsys):
    one = run_json(capsys, "frf", CONVENTIONAL, "--points", "10")
    changed = run_json(capsys, "frf", CONVENTIONAL, "--points", "10", "--set", "Gamma=0.05")
    assert not np.allclose(changed["outputs"]["floor_front"]["amplitude"], one["outputs"]["floor_front"]["amplitude"])


def test_frf_frequencies_with_units(capsys):
    data = run_json(capsys, "frf", CONVENTIONAL, "--points", "3", "--fmin", "0.5 Hz", "--fmax", "2")
    assert data["frequencies"] == pytest.approx([0.5, 1.0, 2.0])


def test_frf_writes_csv_with_units_and_deterministic_svg(capsys, tmp_path):
    table, first, second = tmp_path / "frf.csv", tmp_path / "a.svg", tmp_path / "b.svg"
    status, out, err = run(capsys, "frf", CONVENTIONAL, "--points", "12", "-o", table, "--plot", first)
    assert status == 0, err
    assert "floor_front" in out
    status, _, err = run(capsys, "frf", CONVENTIONAL, "--points", "12", "--plot", second)
    assert status == 0, err
    rows = list(csv.reader(table.open(encoding="utf-8")))
    assert rows[0][0] == "frequency_hz"
    assert "floor_front_acc_amplitude_m_s2" in rows[0] and "floor_front_acc_phase_deg" in rows[0]
    assert len(rows) == 13
    assert first.read_bytes() == second.read_bytes()  # no date, fixed hash salt
    assert b"<svg" in first.read_bytes()


def test_frf_csv_on_standard_output(capsys):
    status, out, err = run(capsys, "frf", CONVENTIONAL, "--points", "4", "-o", "-")
    assert status == 0, err
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0][0] == "frequency_hz" and len(rows) == 5
    assert "peak amplitude" in err


@pytest.mark.parametrize(
    "argv, mentions",
    [
        (["frf", CONVENTIONAL, "--fmin", "0"], "--fmin"),
        (["frf", CONVENTIONAL, "--fmin", "5", "--fmax", "2"], "--fmax"),
        (["frf", CONVENTIONAL, "--fmax", "1e300"], "--fmax <= 1000 Hz"),
        (["frf", CONVENTIONAL, "--points", "1"], "--points"),
        (["frf", CONVENTIONAL, "--points", "100001"], "2 <= --points <= 100000"),
        (["frf", CONVENTIONAL, "--amplitude", "-1"], "--amplitude"),
        (["frf", CONVENTIONAL, "--amplitude", "3 kg"], "--amplitude"),
        (["frf", CONVENTIONAL, "--dof", "W9.y"], "W9.y"),
        (["frf", CONVENTIONAL, "-o", "-", "--json"], "standard output"),
        (["frf", CONVENTIONAL, "--plot", "x.gif"], ".png"),
        (["frf", LEVER], "undefined name"),  # no values: nothing to evaluate
    ],
)
def test_frf_bad_input_exits_2(capsys, argv, mentions):
    assert_input_error(capsys, *argv, mentions=mentions)


def test_frf_without_rail_data(capsys, tmp_path):
    """A model with values but no rail data (issue 11): the DOFs' response to each ground input."""
    status, out, _ = run(capsys, "frf", str(valued_lever(tmp_path)), "--points", "3")
    assert status == 0 and "B2.ry/G1.x" in out


@pytest.mark.slow
@pytest.mark.parametrize("model", ["examples/forced-steering.toml", "examples/manchester.toml",
                                   "tests/data/coach-series-dampers.toml"])
def test_a_warm_frf_of_a_small_model_does_not_import_scipy(tmp_path, model):
    """Issue 24: a warm ``frf --points 200`` of a car takes NumPy's stacked solve; neither
    the response nor the stability check imports ``scipy.linalg`` (0.2-0.25 s of the
    command).  The first (cold) start derives the model and may; the second reads the
    cache back."""
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    env = {k: v for k, v in os.environ.items() if k != "EXPRESS_NO_CACHE"}
    env.update(PYTHONPATH=str(root / "src"), EXPRESS_CACHE_DIR=str(tmp_path))
    code = ("import sys, contextlib, io\nfrom express.cli import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            f"    status = main(['frf', {str(root / model)!r}, '--points', '200'])\n"
            "print(status, 'scipy.linalg' in sys.modules)\n")
    loaded = []
    for _ in range(2):
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600)
        assert done.returncode == 0, done.stderr
        loaded.append(done.stdout.split()[-2:])
    assert loaded[1] == ["0", "False"]
