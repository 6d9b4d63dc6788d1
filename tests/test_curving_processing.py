"""EN 14363's processing of a run's forces (express.analysis.curving.processing): the
20 Hz low-pass filter against the closed-form gain of a Butterworth filter applied
forwards and backwards, the percentiles against their definition, and the assessment
built from the filtered forces."""

from __future__ import annotations

import numpy as np
import pytest

from express.analysis.curving.assessment import assess
from express.analysis.curving.outputs import WheelRailOutputs
from express.analysis.curving.processing import CUTOFF, ORDER, PERCENTILES, filtered, percentiles

SPEED, STEP = 25.0, 0.002  # m/s, s: 500 Hz
Q0 = 60e3


def _outputs(load: np.ndarray, lateral: np.ndarray) -> WheelRailOutputs:
    """One wheelset, both wheels given the same Q and opposite Y (N instants)."""
    n = load.size
    q = np.stack([load, load], axis=1)[:, None, :]
    y = np.stack([lateral, -lateral], axis=1)[:, None, :]
    zeros = np.zeros((n, 1, 2))
    return WheelRailOutputs(q, y, zeros, zeros, zeros, np.zeros((n, 1)), np.array([Q0]), loads="dynamic")


def _gain(frequency: float) -> float:
    """The forwards-backwards digital Butterworth's gain at ``1 / STEP`` samples a second,
    ``1 / (1 + (tan(pi f T) / tan(pi fc T))^(2N))`` (the bilinear transform's warped
    frequency)."""
    ratio = np.tan(np.pi * frequency * STEP) / np.tan(np.pi * CUTOFF * STEP)
    return 1.0 / (1.0 + ratio ** (2 * ORDER))


@pytest.mark.parametrize("frequency", [2.0, 12.0, 20.0, 28.0, 60.0])
def test_the_filter_has_the_butterworths_gain(frequency):
    """A sine of Q through the filter, away from the run's ends: its amplitude is the
    closed-form gain of the squared digital Butterworth magnitude to 1e-9 of the input
    amplitude (achieved 5e-15)."""
    t = np.arange(0.0, 4.0, STEP)
    amplitude = 5e3
    outputs = _outputs(Q0 + amplitude * np.sin(2 * np.pi * frequency * t), np.zeros_like(t))
    result, filtering = filtered(outputs, SPEED * t, SPEED)
    assert filtering.applied and filtering.rate == pytest.approx(1 / STEP)
    middle = slice(t.size // 4, 3 * t.size // 4)
    signal = result.vertical_load[middle, 0, 0] - Q0
    reference = np.sin(2 * np.pi * frequency * t[middle])
    found = 2 * np.mean(signal * reference)  # the sine's amplitude (whole periods)
    assert found / amplitude == pytest.approx(_gain(frequency), abs=1e-9)


def test_the_filter_keeps_the_phase_and_the_mean():
    """Zero phase: a 5 Hz sine stays in phase (its cosine part within 1e-4 of the
    amplitude, achieved 2e-7), and a constant passes unchanged (1e-9 relative)."""
    t = np.arange(0.0, 4.0, STEP)
    outputs = _outputs(Q0 + 1e3 * np.sin(2 * np.pi * 5.0 * t), np.full_like(t, 8e3))
    result, _ = filtered(outputs, SPEED * t, SPEED)
    middle = slice(t.size // 4, 3 * t.size // 4)
    cosine = 2 * np.mean((result.vertical_load[middle, 0, 0] - Q0) * np.cos(2 * np.pi * 5.0 * t[middle]))
    assert abs(cosine) < 1e-4 * 1e3
    np.testing.assert_allclose(result.lateral_force[:, 0, 0], 8e3, rtol=1e-9)


def test_a_run_sampled_too_coarsely_is_not_filtered_and_says_so():
    t = np.arange(0.0, 4.0, 0.025)  # 40 Hz
    outputs = _outputs(np.full_like(t, Q0), np.zeros_like(t))
    result, filtering = filtered(outputs, SPEED * t, SPEED)
    assert not filtering.applied and result is outputs
    assert "40 Hz" in filtering.note and "not filtered" in filtering.note


def test_the_percentiles_are_the_quantities_own():
    """Of a ramp of Q from 50 to 70 kN the p-th percentile is ``50 + 20 p / 100`` kN
    (linear interpolation between samples; to rounding); ΣY of opposite lateral forces
    is zero at every percentile."""
    load = np.linspace(50e3, 70e3, 2001)
    found = percentiles(_outputs(load, np.linspace(0.0, 4e3, 2001)))
    assert found.names[:2] == ("Q1L", "Q1R") and "SY1" in found.names
    row = found.values[found.names.index("Q1L")]
    np.testing.assert_allclose(row, [50e3 + 20e3 * p / 100 for p in PERCENTILES], rtol=1e-12)
    np.testing.assert_allclose(found.values[found.names.index("SY1")], 0.0, atol=1e-9)
    frame = found.to_pandas()
    assert frame.shape == (len(found.names), 3) and frame.attrs["units"]["Q1L"] == "N"


def test_the_assessment_takes_the_filtered_forces():
    """A 60 Hz load oscillation of 30 kN on a 60 kN wheel (whole periods, so the odd
    reflection at the ends continues it): unfiltered the wheel unloads by 0.5; filtered
    by 0.5 times the gain (1.1e-4), within 1e-6 (achieved 1.5e-7, the sampled peak).  The lift-off check
    stays on the unfiltered loads."""
    t = np.arange(0.0, 8.0 + STEP / 2, STEP)
    outputs = _outputs(Q0 + 30e3 * np.sin(2 * np.pi * 60.0 * t), np.zeros_like(t))
    found = assess(outputs, SPEED * t, radius=np.inf, friction=0.3, flange_angle=1.2, speed=SPEED)
    unloading = {c.name: c.value for c in found.criteria}["dQQ0"]
    assert unloading == pytest.approx(0.5 * _gain(60.0), abs=1e-6)
    assert found.filtering is not None and found.filtering.applied
    assert found.percentiles is not None and "percentiles" in found.as_dict()
    unfiltered = assess(outputs, SPEED * t, radius=np.inf, friction=0.3, flange_angle=1.2)
    assert {c.name: c.value for c in unfiltered.criteria}["dQQ0"] == pytest.approx(0.5, rel=3e-3)  # sampled peaks: 0.499
