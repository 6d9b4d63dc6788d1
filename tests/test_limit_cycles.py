"""Runs at one speed that tell whether a hunting limit cycle lives there
(express.analysis.stability.limit_cycles), on the wheelset of tests/test_profile_contact.py."""

from __future__ import annotations

import pytest

from express.analysis.stability.limit_cycles import SETTLED_WINDOWS, settle_cycle, settled
from express.analysis.stability.nonlinear_stability import nonlinear_critical_speed
from express.base.units import KMH
from express.io.toml_model import parse_toml_model
from express.numeric.statespace import vehicle_model
from test_profile_contact import WHEELSET


@pytest.mark.parametrize(("amplitudes", "spread", "expected"), [
    ([1.0, 1.0, 1.0, 1.0], 1e-3, True),
    ([1.0, 1.0, 1.0], 1e-3, False),  # fewer than SETTLED_WINDOWS windows
    ([5.0, 1.0, 1.001, 0.9995, 1.0], 2e-3, True),  # only the last windows count
    ([1.0, 0.99, 0.98, 0.97], 2e-3, False),  # still decaying
    ([1.0, 0.99, 0.98, 0.97], 0.04, True),
])
def test_settled(amplitudes, spread, expected):
    assert SETTLED_WINDOWS == 4
    assert settled(amplitudes, spread) is expected


@pytest.fixture(scope="module")
def wheelset():
    vehicle = vehicle_model(parse_toml_model(WHEELSET, "wheelset.toml"))
    return vehicle, nonlinear_critical_speed(vehicle, v_max=300.0, refinements=0)


def test_a_cycle_above_its_end_survives_and_settles(wheelset):
    vehicle, result = wheelset
    check = settle_cycle(vehicle, result.speed + 1 * KMH, result.state, dt=result.dt)
    assert check.alive and check.settled and check.contact == "tables (table)"
    last = check.amplitudes[-SETTLED_WINDOWS:]
    assert max(last) - min(last) <= 2e-3 * last[-1] and last[-1] > 1e-4
    assert check.duration == 2.0 * len(check.amplitudes) < 40.0
    assert check.watched == check.amplitudes  # one wheelset: the watched one is every one
    assert check.state.shape == result.state.shape and check.flange_force > 0


def test_below_its_end_the_motion_collapses(wheelset):
    vehicle, result = wheelset
    check = settle_cycle(vehicle, result.bracket[0] - 2 * KMH, result.state, dt=result.dt)
    assert not check.alive and not check.settled
    assert check.amplitudes[-1] <= 1e-4 < check.amplitudes[0] and check.duration < 40.0


def test_a_motion_that_never_settles_is_alive_after_longest(wheelset):
    """Alive means 'survived longest'; settling only ends the run early."""
    vehicle, result = wheelset
    check = settle_cycle(vehicle, result.speed + 1 * KMH, result.state, dt=result.dt, spread=1e-15, longest=10.0)
    assert check.alive and not check.settled and check.duration == 10.0 and len(check.amplitudes) == 5


def test_bad_options(wheelset):
    vehicle, result = wheelset
    for name in ("window", "longest", "spread", "threshold"):
        with pytest.raises(ValueError, match=name):
            settle_cycle(vehicle, result.speed, result.state, dt=result.dt, **{name: 0.0})
