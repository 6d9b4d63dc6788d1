"""The fast critical speed (express.analysis.study.critical): the value the stability
code reports, and the exact crossing."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from express.analysis.stability.stability import critical_speed
from express.analysis.study.critical import CriticalOptions, StateBlocks, fast_critical_speed, hopf_point
from express.numeric.statespace import load_vehicle

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def steered():
    return load_vehicle(ROOT / "examples" / "forced-steering.toml")


@pytest.fixture(scope="module")
def conventional():
    return load_vehicle(ROOT / "examples" / "conventional.toml")


#: Variants of the steered car: low-speed hunting, a window, the usual high-speed crossing.
VARIANTS = [
    {},
    {"Gamma": 0.03, "kx1": 4e6},
    {"Gamma": 0.05, "kx1": 1e6},
    {"Gamma": 0.02, "kx1": 1e6},  # unstable at v_min
    {"Gamma": 0.4, "kx1": 8e6},
    {"Gamma": 0.2, "lLL": 0.1},
    {"Gamma": 0.1, "cyaw": 5e4},
]


@pytest.mark.parametrize("changes", VARIANTS, ids=[str(v) for v in VARIANTS])
def test_same_value_as_the_stability_code(steered, changes) -> None:
    vehicle = steered.with_values(changes) if changes else steered
    expected = critical_speed(vehicle)
    result = fast_critical_speed(vehicle)
    if not expected.found:
        assert not result.found and math.isnan(result.speed) and result.reason == "stable up to v_max"
        return
    assert result.speed == expected.speed  # bit for bit: the bisection is replayed
    assert result.unstable_at_min == expected.unstable_at_min
    assert result.frequency == pytest.approx(expected.mode.frequency_hz, rel=1e-3)
    if result.crossing is not None:
        assert expected.bracket[0] <= result.crossing.speed <= expected.bracket[1]
        assert result.evaluations < expected.evaluations


def test_same_value_with_other_options(conventional) -> None:
    for options in ({"v_min": 5.0, "v_max": 80.0, "tolerance_kmh": 0.5, "points": 12}, {"v_max": 200.0, "tolerance_kmh": 0.01}):
        expected = critical_speed(conventional, **options)
        ours = CriticalOptions(v_min=options.get("v_min", 1.0), v_max=options["v_max"],
                               tolerance=options["tolerance_kmh"] / 3.6, points=options.get("points", 40))
        got = fast_critical_speed(conventional, ours)
        assert got.found == expected.found and got.reason == expected.reason
        if expected.found:
            assert got.speed == expected.speed


def test_crossing_is_an_eigenvalue_on_the_threshold(steered) -> None:
    result = fast_critical_speed(steered, CriticalOptions(tolerance=0.0))
    crossing = result.crossing
    assert result.speed == crossing.speed
    eigenvalues = np.linalg.eigvals(steered.state_matrix(crossing.speed))
    nearest = eigenvalues[np.argmin(np.abs(eigenvalues - crossing.eigenvalue))]
    assert abs(nearest - crossing.eigenvalue) < 1e-9 * abs(crossing.eigenvalue)
    # just below the crossing every mode decays, just above one grows
    assert np.linalg.eigvals(steered.state_matrix(crossing.speed * (1 - 1e-6))).real.max() < 1e-6
    assert np.linalg.eigvals(steered.state_matrix(crossing.speed * (1 + 1e-6))).real.max() > 1e-6
    residual = steered.state_matrix(crossing.speed) @ crossing.vector - crossing.eigenvalue * crossing.vector
    assert np.linalg.norm(residual) < 1e-9 * np.linalg.norm(crossing.vector) * abs(crossing.eigenvalue)


def test_local_check_follows_a_guess(steered) -> None:
    options = CriticalOptions(check="local")
    previous = fast_critical_speed(steered).crossing
    for kx1 in np.linspace(2.1e6, 3e6, 4):
        vehicle = steered.with_values({"kx1": float(kx1)})
        result = fast_critical_speed(vehicle, options, previous)
        assert result.method == "local" and result.evaluations <= 3  # the watched speed, the cell's lower end, just below
        assert result.speed == critical_speed(vehicle).speed
        previous = result.crossing


def test_local_check_falls_back_to_the_grid(steered) -> None:
    high = fast_critical_speed(steered).crossing  # ~365 km/h
    low = steered.with_values({"Gamma": 0.05, "kx1": 1e6})  # hunts near 67 km/h
    result = fast_critical_speed(low, CriticalOptions(check="local"), high)
    assert result.speed == critical_speed(low).speed


def test_hopf_newton_refuses_a_bad_guess(steered) -> None:
    blocks = StateBlocks(steered)
    assert hopf_point(blocks, -1.0, 1.0, np.ones(blocks.size), 1e-6) is None
    assert hopf_point(blocks, 30.0, 1.0, np.zeros(blocks.size), 1e-6) is None


def test_model_without_rail_is_refused() -> None:
    values = {"J1": 2.0, "J2": 0.5, "b": 0.4, "c": 300.0, "kLL": 5.5e6, "kLU": 5e5, "lLL": 0.06, "lLU": 0.3, "m": 20.0}
    lever = load_vehicle(ROOT / "examples" / "lever.exp", values)
    with pytest.raises(ValueError, match="no rail data"):
        fast_critical_speed(lever)
