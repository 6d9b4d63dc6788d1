"""The vehicle as a control-design plant driven by the track (express.export.track_system):
the Padé delays against python-control's, the exact delayed response against
``frequency_response``, the Padé plant's convergence to it, chosen outputs."""

from __future__ import annotations

import numpy as np
import pytest

from express.analysis.frequency.frequency import frequency_response
from express.base.diagnostics import ArgumentError
from express.export.linear_system import to_control, to_scipy
from express.export.track_system import pade_delay, track_response, track_system
from express.numeric.statespace import load_vehicle

SPEED = 30.0
OUTPUTS = ["floor_front", "W1.y", "CB.y_dot"]
FREQUENCIES = np.array([0.2, 0.5, 1.0, 2.0, 4.0])


@pytest.fixture(scope="module")
def car():
    return load_vehicle("examples/conventional.toml")


def _response(system, frequencies):
    eye = np.eye(system.A.shape[0])
    return np.array([system.C @ np.linalg.solve(2j * np.pi * f * eye - system.A, system.B)[:, 0] + system.D[:, 0]
                     for f in frequencies])


@pytest.mark.parametrize("delay, order", [(0.3, 6), (0.557, 10), (0.05, 2)])
def test_the_pade_delay_is_python_controls(delay, order):
    """The state space of the approximant has python-control's ``pade`` transfer function
    (to 1e-12; achieved 1e-15) and is all-pass (|H| = 1 to 1e-12)."""
    import control

    a, b, c, d = pade_delay(delay, order)
    numerator, denominator = control.pade(delay, order)
    for w in (0.5, 5.0, 50.0):
        h = (c @ np.linalg.solve(1j * w * np.eye(order) - a, b) + d)[0, 0]
        assert h == pytest.approx(np.polyval(numerator, 1j * w) / np.polyval(denominator, 1j * w), rel=1e-12)
        assert abs(h) == pytest.approx(1.0, abs=1e-12)


def test_the_exact_track_response_is_the_frequency_response(car):
    """Unit alignment, each wheelset delayed exactly: the output point and the DOF equal
    ``frequency_response`` at 1 m (to 1e-12 relative; achieved 1.7e-14)."""
    exact = track_response(car, SPEED, FREQUENCIES, outputs=OUTPUTS)
    reference = frequency_response(car, FREQUENCIES, amplitude=1.0, speed=SPEED)
    floor = reference.outputs["floor_front"]
    assert np.abs(exact[:, 0] - floor).max() < 1e-12 * np.abs(floor).max()
    wheelset = reference.X[:, car.dofs.index("W1.y")]
    assert np.abs(exact[:, 1] - wheelset).max() < 1e-12 * np.abs(wheelset).max()


@pytest.mark.parametrize("order, bounds", [
    # the largest error against the exact response, relative to its size, at 0.2, 0.5, 1, 2 Hz
    # (tau_max = 0.557 s at 30 m/s, so w tau_max = 0.7, 1.7, 3.5, 7.0); achieved for order 6:
    # 4e-13, 5.6e-11, 8.4e-7, 1.6e-3; order 10: 1.4e-13, 1.1e-14, 3e-14, 7.2e-9
    (6, (1e-11, 1e-9, 2e-6, 3e-3)),
    (10, (1e-11, 1e-11, 1e-11, 2e-8)),
])
def test_the_pade_plant_converges_to_the_exact_delays(car, order, bounds):
    system = track_system(car, SPEED, outputs=OUTPUTS, pade_order=order)
    assert system.inputs == ("alignment",) and system.outputs == tuple(OUTPUTS)
    assert system.A.shape[0] == 2 * car.n + 3 * order  # three delayed wheelsets
    exact = track_response(car, SPEED, FREQUENCIES[:4], outputs=OUTPUTS)
    error = np.abs(_response(system, FREQUENCIES[:4]) - exact).max(axis=1) / np.abs(exact).max(axis=1)
    assert np.all(error < np.array(bounds)), error


def test_control_and_scipy_take_outputs_and_the_track(car):
    import control

    plant = to_control(car, SPEED, outputs=OUTPUTS, track=True, pade_order=4)
    assert plant.input_labels == ["alignment"] and plant.output_labels == ["floor_front", "W1_y", "CB_y_dot"]
    poles = np.sort_complex(control.poles(plant))
    expected = np.sort_complex(np.concatenate([car.eigenvalues(SPEED),
                                               *[np.linalg.eigvals(pade_delay(t, 4)[0]) for t in (0.0767, 0.48, 0.5567)]]))
    assert poles.shape == expected.shape
    assert np.abs(np.sort_complex(np.linalg.eigvals(to_scipy(car, SPEED, outputs=OUTPUTS).A))
                  - np.sort_complex(car.eigenvalues(SPEED))).max() < 1e-9 * np.abs(car.eigenvalues(SPEED)).max()
    with pytest.raises(ArgumentError, match="no such output 'floor_middle'"):
        to_control(car, SPEED, outputs=["floor_middle"])
    with pytest.raises(ArgumentError, match="pade_order must be 0 to 20"):
        track_system(car, SPEED, pade_order=30)
