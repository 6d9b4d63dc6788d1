"""Hand-off of the numerical linear model: python-control, scipy.signal, .mat/.npz, FMU."""

from __future__ import annotations

import io
import zipfile

import numpy as np
import pytest
import scipy.io

from express.export.linear_system import linear_system, numeric_matrices, to_control, to_scipy
from express.io.output import mat_bytes as to_mat_bytes
from express.io.output import npz_bytes as to_npz_bytes
from express.numeric.statespace import load_vehicle

MODELS = ["examples/conventional.toml", "examples/forced-steering.toml"]


@pytest.fixture(scope="module", params=MODELS)
def vehicle(request):
    return load_vehicle(request.param)


def _sorted(values):
    return np.sort_complex(np.asarray(values, dtype=complex))


def test_poles_of_control_and_scipy_equal_the_vehicle_eigenvalues(vehicle):
    import control

    speed = 30.0
    reference = _sorted(vehicle.eigenvalues(speed))
    scale = np.abs(reference).max()
    np.testing.assert_allclose(_sorted(control.poles(to_control(vehicle, speed))), reference, atol=1e-9 * scale)
    scipy_system = to_scipy(vehicle, speed)  # MIMO: scipy's .poles goes through zpk, which is SISO-only
    np.testing.assert_allclose(_sorted(np.linalg.eigvals(scipy_system.A)), reference, atol=1e-9 * scale)
    assert scipy_system.B.shape == (2 * vehicle.n, len(vehicle.inputs))


def test_removing_the_input_rates_keeps_the_frequency_response(vehicle):
    """x' = A x + B u + Bd u' and (A, B + A Bd, I, Bd) have the same response to
    u = U e^{iwt}: (iw - A)^-1 (B + iw Bd) U."""
    speed = 25.0
    system = linear_system(vehicle, speed)
    a, b, bd = vehicle.state_matrix(speed), vehicle.input_matrix(speed), vehicle.input_rate_matrix(speed)
    eye = np.eye(a.shape[0])
    for omega in (0.7, 6.0, 40.0):
        direct = np.linalg.solve(1j * omega * eye - a, b + 1j * omega * bd)
        standard = system.C @ np.linalg.solve(1j * omega * eye - system.A, system.B) + system.D
        np.testing.assert_allclose(standard, direct, rtol=1e-9, atol=1e-12 * np.abs(direct).max())


def test_control_names_have_no_dots(vehicle):
    system = to_control(vehicle, 30.0)
    assert system.input_labels[0] == vehicle.inputs[0].replace(".", "_")
    assert system.output_labels[: len(vehicle.dofs)] == [d.replace(".", "_") for d in vehicle.dofs]


@pytest.mark.parametrize("speed", [0.0, -1.0, float("nan"), float("inf")])
def test_a_speed_that_is_not_positive_is_refused(vehicle, speed):
    with pytest.raises(ValueError, match="positive"):
        linear_system(vehicle, speed)
    with pytest.raises(ValueError, match="positive"):
        numeric_matrices(vehicle, speed)


def test_a_speed_with_a_unit_is_the_same_system(vehicle):
    """``"108 km/h"`` is 30 m/s (issue 35: quantities accepted, never the command line's
    km/h for bare numbers)."""
    system, si = linear_system(vehicle, "108 km/h"), linear_system(vehicle, 30.0)
    assert system.speed == 30.0 and np.array_equal(system.A, si.A) and np.array_equal(system.B, si.B)
    with pytest.raises(ValueError, match="speed"):
        linear_system(vehicle, "30 m")


def test_the_files_matrices_are_the_linear_systems(vehicle):
    """The file's A is linear_system's, its B and Bd the vehicle's input matrices (the
    system's B + A Bd is not stored: it is not built for the file)."""
    system, matrices = linear_system(vehicle, 30.0), numeric_matrices(vehicle, 30.0)
    assert np.array_equal(matrices["A"], system.A) and np.array_equal(matrices["Bd"], system.D)
    np.testing.assert_array_equal(system.B, matrices["B"] + matrices["A"] @ matrices["Bd"])


def test_mat_file_reads_back_with_names_and_is_deterministic(vehicle):
    matrices = numeric_matrices(vehicle, 30.0)
    data = to_mat_bytes(matrices)
    assert data == to_mat_bytes(numeric_matrices(vehicle, 30.0))
    loaded = scipy.io.loadmat(io.BytesIO(data))
    for key in ("M", "C", "K", "P", "Pd", "A", "B", "Bd"):
        np.testing.assert_array_equal(loaded[key], matrices[key])
    assert [name.strip() for name in loaded["dofs"]] == list(vehicle.dofs)
    assert loaded["speed"].item() == 30.0


def test_npz_reads_back_without_pickles_and_is_deterministic(vehicle):
    matrices = numeric_matrices(vehicle, 30.0)
    data = to_npz_bytes(matrices)
    assert data == to_npz_bytes(numeric_matrices(vehicle, 30.0))
    with np.load(io.BytesIO(data), allow_pickle=False) as loaded:
        np.testing.assert_array_equal(loaded["A"], matrices["A"])
        assert tuple(loaded["inputs"]) == tuple(vehicle.inputs)
    with zipfile.ZipFile(io.BytesIO(data)) as archive:
        assert {info.date_time for info in archive.infolist()} == {(1980, 1, 1, 0, 0, 0)}


@pytest.mark.slow
def test_fmu_simulated_by_fmpy_matches_lsim():
    pytest.importorskip("pythonfmu", reason="pythonfmu is a test dependency")
    from fmpy import simulate_fmu
    from scipy import signal

    from express.export.fmu import to_fmu_bytes

    vehicle = load_vehicle("examples/conventional.toml")
    system = linear_system(vehicle, 30.0)
    archive = to_fmu_bytes(system, "conventional")
    assert archive == to_fmu_bytes(system, "conventional")
    path = io.BytesIO(archive)
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as folder:
        fmu = Path(folder) / "conventional.fmu"
        fmu.write_bytes(path.getvalue())
        drive = np.array([(0.0, 1e-3), (2.0, 1e-3)], dtype=[("time", float), ("W1.yR", float)])
        result = simulate_fmu(str(fmu), stop_time=2.0, step_size=1e-3, output_interval=0.01,
                              input=drive, output=["W1.y", "CB.y"])
    time = np.arange(0.0, 2.0 + 1e-9, 1e-3)
    u = np.zeros((time.size, system.B.shape[1]))
    u[:, system.inputs.index("W1.yR")] = 1e-3
    _, y, _ = signal.lsim(signal.StateSpace(system.A, system.B, system.C, system.D), u, time)
    for name in ("W1.y", "CB.y"):
        expected = y[-1, system.outputs.index(name)]
        assert abs(result[name][-1] - expected) <= 1e-9 * abs(expected) + 1e-15
        assert abs(expected) > 1e-5  # the step really moved the vehicle
