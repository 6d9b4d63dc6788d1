"""Tests of express.analysis.frequency.frequency: the frequency response to a sinusoidal alignment.

The reference is a time simulation of the same linear model (no flange contact, no
creep saturation) on a straight track with a sinusoidal irregularity of wavelength
``v / f``: after the transient, the amplitude and phase of each DOF and of the floor
output (least-squares fit of ``sin``, ``cos`` and a constant over whole periods) must
be those of :func:`frequency_response`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.analysis.frequency.frequency import FrequencyResponse, frequency_response, irregularity_delays
from express.io import load_model
from express.numeric.statespace import point_lateral_row, vehicle_model

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
SPEED = 120 / 3.6


@pytest.fixture(scope="module")
def steered():
    return vehicle_model(load_model(EXAMPLES / "forced-steering.toml"))


def test_delays_are_the_papers(steered):
    a, lt = 1.15, 7.2
    delays = irregularity_delays(steered, SPEED)
    np.testing.assert_allclose(delays, [0.0, 2 * a / SPEED, 2 * lt / SPEED, 2 * (a + lt) / SPEED], rtol=1e-12)
    frf = frequency_response(steered, [1.5], speed=SPEED)
    np.testing.assert_allclose(frf.delays, delays)
    w = 2 * np.pi * 1.5
    np.testing.assert_allclose(frf.irregularity[0], 1e-3 * np.exp(-1j * w * delays))


def test_static_limit_is_a_rigid_lateral_shift(steered):
    """At f = 0 every wheelset sees the same constant offset Y: the whole vehicle shifts
    by Y without deflecting anything (creep moments vanish when y = yR)."""
    frf = frequency_response(steered, [0.0], amplitude=2e-3)
    for i, dof in enumerate(steered.dofs):
        expected = 2e-3 if dof.endswith(".y") else 0.0
        assert frf.X[0, i] == pytest.approx(expected, abs=1e-12), dof
    assert frf.amplitude_of("floor_front")[0] == pytest.approx(2e-3, abs=1e-12)
    assert frf.acceleration_of("floor_front")[0] == 0


def test_linear_in_amplitude_and_outputs(steered):
    f = np.array([0.5, 1.0, 3.0])
    one = frequency_response(steered, f)
    three = frequency_response(steered, f, amplitude=3e-3)
    np.testing.assert_allclose(three.X, 3 * one.X, rtol=1e-10, atol=1e-12 * np.abs(one.X).max())
    assert isinstance(one, FrequencyResponse) and one.speed == pytest.approx(SPEED)
    assert set(one.outputs) == {"floor_front", "floor_rear"}
    model = steered.model
    for point in model.rail.outputs:
        row = point_lateral_row(model, steered.equations, point.body, point.offset)
        np.testing.assert_allclose(one.amplitude_of(point.name), one.X @ row)
        np.testing.assert_allclose(one.acceleration_of(point.name), -(2 * np.pi * f) ** 2 * (one.X @ row))
    # floor_front = CB.y + lT CB.rz - (hf - hc) CB.rx
    cb = [steered.dof_index(d) for d in ("CB.y", "CB.rz", "CB.rx")]
    np.testing.assert_allclose(one.amplitude_of("floor_front"), one.X[:, cb] @ [1.0, 7.2, -(1.2 - 1.6)])
    np.testing.assert_allclose(one.amplitude_of("W1.y"), one.X[:, steered.dof_index("W1.y")])
    np.testing.assert_allclose(one.velocity_of("CB.y"), 2j * np.pi * f * one.amplitude_of("CB.y"))
    rows = one.rows()
    assert len(rows) == 3 and rows[0]["f_hz"] == 0.5
    assert rows[1]["floor_rear_acc"] == pytest.approx(abs(one.acceleration_of("floor_rear")[1]))
    with pytest.raises(KeyError, match="floor_front"):
        one.amplitude_of("floor_middle")


def test_bad_arguments(steered):
    with pytest.raises(ValueError, match="positive"):
        frequency_response(steered, [1.0], speed=0.0)
    with pytest.raises(ValueError, match="frequencies"):
        frequency_response(steered, [-1.0])


def _fit(time: np.ndarray, signal: np.ndarray, f: float) -> complex:
    """Complex amplitude X with signal ~ Im(X exp(i w t)) + c = Re X sin + Im X cos + c."""
    w = 2 * np.pi * f
    basis = np.column_stack([np.sin(w * time), np.cos(w * time), np.ones_like(time)])
    coefficients = np.linalg.lstsq(basis, signal, rcond=None)[0]
    return complex(coefficients[0], coefficients[1])


@pytest.mark.parametrize("f", [0.7, 2.0, 5.0])
def test_matches_linear_simulation(steered, f):
    """Measured agreement: 2e-5 (0.7 Hz, near the car body's sway mode), 5e-5 (2 Hz),
    3e-4 (5 Hz; the first-order hold of the input over dt = 5 ms)."""
    from express.analysis.time.simulate import simulate
    from express.rail.track import SinusoidIrregularity, Straight, Track

    duration = 25.0  # the slowest modes decay as exp(-0.3 t): < 1e-2 after 17 s
    track = Track([Straight(SPEED * duration + 1.0)], irregularity=SinusoidIrregularity(1e-3, SPEED / f))
    result = simulate(steered, track, speed=SPEED, dt=0.005, end=SPEED * duration, flange=False, saturation=False)
    frf = frequency_response(steered, [f], speed=SPEED)
    window = result.time >= result.time[-1] - np.floor(8.0 * f) / f  # whole periods
    model = steered.model
    front = next(p for p in model.rail.outputs if p.name == "floor_front")
    floor = result.q @ point_lateral_row(model, steered.equations, front.body, front.offset)
    signals = {name: result.q[:, steered.dof_index(name)] for name in ("CB.y", "W1.y", "T1.rz", "W4.y")}
    signals["floor_front"] = floor
    for name, signal in signals.items():
        simulated = _fit(result.time[window], signal[window], f)
        expected = frf.amplitude_of(name)[0]
        assert abs(simulated - expected) <= 1e-2 * abs(expected), name
    # the floor acceleration from the simulated velocities as well
    floor_rate = result.q_dot @ point_lateral_row(model, steered.equations, front.body, front.offset)
    acceleration = 2j * np.pi * f * _fit(result.time[window], floor_rate[window], f)
    expected = frf.acceleration_of("floor_front")[0]
    assert abs(acceleration - expected) <= 1e-2 * abs(expected)
