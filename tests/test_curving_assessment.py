"""EN 14363 running-safety quantities (express.analysis.curving.assessment)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.analysis.curving.assessment import (
    UNLOADING_LIMIT,
    assess,
    assess_steady,
    nadal_limit,
    prudhomme_limit,
    sliding_mean,
)
from express.analysis.curving.outputs import WheelRailOutputs
from express.analysis.curving.steady import SteadyCurve, steady_curving
from express.numeric.statespace import load_vehicle


def test_nadal_closed_form():
    # tan(70 deg) = 2.7475, mu = 0.36: (2.7475 - 0.36) / (1 + 0.36 * 2.7475) = 1.2003
    assert nadal_limit(math.radians(70.0), 0.36) == pytest.approx(1.2003, abs=1e-4)
    assert nadal_limit(math.radians(60.0), 0.0) == pytest.approx(math.sqrt(3.0), rel=1e-15)


def test_prudhomme():
    # a 20 t axle (Q0 = 98.1 kN per wheel... of a 20 t axle: 2 Q0 = 196.2 kN): 10 + 2 * 98.1 / 3 = 75.4 kN
    assert prudhomme_limit(98.1e3) == pytest.approx(75.4e3)
    assert prudhomme_limit(98.1e3, alpha=0.85) == pytest.approx(0.85 * 75.4e3)


def test_sliding_mean_of_a_pulse():
    # a 1 m long pulse of height 1 seen through 2 m windows every 0.5 m: at most 0.5
    d = np.arange(0.0, 20.0001, 0.01)
    pulse = ((d >= 8.0) & (d < 9.0)).astype(float)
    means = sliding_mean(d, pulse)
    assert means.max() == pytest.approx(0.5, abs=0.01)
    assert means.shape == (37,)  # windows starting at 0, 0.5, ..., 18
    np.testing.assert_allclose(sliding_mean(d, np.full_like(d, 3.0)), 3.0, rtol=1e-12)  # cumulative sums: 4e-14


def _outputs(y_over_q: float, load: float = 50e3) -> WheelRailOutputs:
    count = 400
    shape = (count, 1, 2)
    vertical = np.full(shape, load)
    lateral = np.zeros(shape)
    lateral[:, 0, 0] = -y_over_q * load
    angle = np.full(shape, 0.1)
    angle[:, 0, 0] = math.radians(70.0)  # the left wheel flanges
    return WheelRailOutputs(vertical, lateral, np.zeros(shape), np.zeros(shape), angle, np.zeros((count, 1)),
                            np.array([50e3]))


def test_limits_and_verdicts():
    d = np.linspace(0.0, 40.0, 400)
    result = assess(_outputs(0.7), d, radius=400.0, friction=0.36, flange_angle=math.radians(70))
    by_name = {c.name: c for c in result.criteria}
    assert by_name["YQ1L"].value == pytest.approx(0.7) and by_name["YQ1L"].limit == 0.8 and by_name["YQ1L"].passed
    assert by_name["YQ1L_nadal"].limit == pytest.approx(1.2003, abs=1e-4)
    assert by_name["SY1"].value == pytest.approx(35e3) and by_name["SY1"].limit == pytest.approx(10e3 + 2 * 50e3 / 3)
    assert by_name["dQQ0"].limit == UNLOADING_LIMIT
    assert result.passed and result.derailment is None
    failing = assess(_outputs(0.9), d, radius=400.0, friction=0.36, flange_angle=math.radians(70))
    assert not {c.name: c for c in failing.criteria}["YQ1L"].passed and failing.derailment is None
    small = assess(_outputs(0.7), d, radius=200.0, friction=0.36, flange_angle=math.radians(70))
    assert {c.name: c for c in small.criteria}["YQ1L"].passed is None  # no limit for R < 250 m


def test_flange_climb_and_wheel_lift_are_derailments():
    d = np.linspace(0.0, 40.0, 400)
    climbing = assess(_outputs(1.3), d, radius=400.0, friction=0.36, flange_angle=math.radians(70))
    assert "Nadal" in climbing.derailment
    lifted = assess(_outputs(0.1, load=-1.0), d, radius=400.0, friction=0.36, flange_angle=math.radians(70))
    assert "lifts" in lifted.derailment


def test_steady_state_assessment():
    vehicle = load_vehicle("examples/conventional.toml")
    steady = steady_curving(vehicle, SteadyCurve(400.0, 0.105, "right"), speeds=120 / 3.6)[0]
    result = assess_steady(vehicle, steady)
    by_name = {c.name: c for c in result.criteria}
    assert by_name["YQ1L"].value == pytest.approx(float(steady.wheel_rail.y_over_q[0, 0, 0]), rel=1e-12)
    assert by_name["SY1"].value == pytest.approx(abs(float(steady.wheel_rail.track_shift_force[0, 0])), rel=1e-12)
    assert by_name["YQ1L_nadal"].limit == pytest.approx(nadal_limit(math.radians(70.0), 0.3))
    # the inner (right) wheel does not flange: nothing of it counts against Nadal
    assert by_name["YQ1R"].value > 0.1 and by_name["YQ1R_nadal"].value == 0.0
