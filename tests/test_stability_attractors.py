"""The attractors the ramp-down follows (express.analysis.stability.attractors): how the
ramp's points split into limit cycles, table-driven (the search itself on the bundled
S1002 car: tests/test_nonlinear_critical_speed.py)."""

from __future__ import annotations

import math

import pytest

from express.analysis.stability.attractors import Attractor, attractors
from express.analysis.stability.nonlinear_stability import BifurcationPoint

V = [60.0, 55.0, 50.0, 45.0, 40.0, 35.0]


def _points(amplitudes, flanges, alive=None):
    alive = alive or [a > 0 for a in amplitudes]
    return [BifurcationPoint(v, a, a, live, 1e3 * a, flange, 100 * a) for v, a, flange, live in
            zip(V, amplitudes, flanges, alive, strict=False)]


@pytest.mark.parametrize("amplitudes, flanges, alive, expected", [
    # one branch in flange contact, decaying slowly, then dead: gone at the dead point
    ([8e-3, 7.5e-3, 7e-3, 0.0], [True] * 4, None, [(60.0, 50.0, 45.0, 50.0)]),
    # the flange lost along one branch: one attractor, in flange contact down to 55
    ([8e-3, 7e-3, 6e-3, 5e-3, 0.0], [True, True, False, False, False], None, [(60.0, 45.0, 40.0, 55.0)]),
    # a fold onto a small tread cycle (amplitude falls 17-fold), alive to the ramp's end
    ([8e-3, 7e-3, 0.4e-3, 0.35e-3, 0.3e-3, 0.3e-3], [True, False, False, False, False, False], None,
     [(60.0, 55.0, 50.0, 60.0), (50.0, 35.0, math.nan, math.nan)]),
    # a jump up by more than JUMP is a new attractor too; 1.4 is not
    ([1e-3, 1.4e-3, 3e-3, 0.0], [False] * 4, None, [(60.0, 55.0, 50.0, math.nan), (50.0, 50.0, 45.0, math.nan)]),
    # dead at the start: no attractor
    ([5e-5], [False], [False], []),
])
def test_the_ramp_points_split_into_attractors(amplitudes, flanges, alive, expected):
    found = attractors(_points(amplitudes, flanges, alive))
    assert [(a.highest, a.lowest, a.below, a.flange_lowest) for a in found] == pytest.approx(expected, nan_ok=True)
    for attractor in found:
        assert attractor.amplitudes == tuple(a for v, a in zip(V, amplitudes, strict=False)
                                             if attractor.lowest <= v <= attractor.highest)
        assert attractor.flange_force == pytest.approx(1e3 * max(attractor.amplitudes))
        assert attractor.instability == pytest.approx(100 * max(attractor.amplitudes))
        assert attractor.flange_contact == math.isfinite(attractor.flange_lowest)


def test_an_attractor_describes_itself():
    attractor = Attractor(60.0, 50.0, 45.0, (8e-3, 7e-3), 55.0, 5.0e4)
    assert attractor.describe() == ("limit cycle from 216.0 down to 180.0 km/h, gone at 162.0: amplitude 8.00 to "
                                    "7.00 mm, flange contact down to 198.0 km/h, largest lateral force 50.0 kN")
    assert attractor.as_dict()["lowest_kmh"] == pytest.approx(180.0)
    assert "alive at the ramp's end" in Attractor(60.0, 50.0, math.nan, (1e-3,), math.nan, 1e3).describe()
    assert Attractor(60.0, 50.0, 45.0, (8e-3,), 55.0, 5e4, 1.24).describe().endswith(
        "ΣY rms up to 1.24 of (ΣY)lim/2 (FAIL)")


@pytest.mark.slow
def test_the_s1002_car_has_a_flange_contact_and_a_tread_attractor():
    """The bundled S1002 car from 1.2 times its linear critical speed with 5 mm: the ramp
    follows a flange-contact cycle, then (a fold at about 300 km/h, the amplitude halving)
    a tread cycle down to the end the refined search finds.  Each ramp point's flange
    contact (contact angle above 30 degrees in its run) agrees with its amplitude against
    the flange clearance of the car's contact tables, the centred wheelset's displacement
    where a contact angle passes 30 degrees (7.71 mm): within 0.15 mm (achieved 0.06 mm,
    the yaw's share).  The speeds of the two attractors and their instability ratios
    (1.31 and 0.90 with the table law; 1.25 and 0.51 with FASTSIM) are regression guards."""
    from express.analysis.stability.nonlinear_stability import nonlinear_critical_speed
    from express.base.units import KMH
    from express.numeric.statespace import load_vehicle
    from express.rail.contact_forces import quasi_static_forces
    from express.rail.profile_contact import wheelset_contacts

    vehicle = load_vehicle("examples/manchester-s1002.toml")
    result = nonlinear_critical_speed(vehicle, refinements=0)
    first, second = result.attractors
    assert first.flange_contact and not second.flange_contact
    assert first.highest == pytest.approx(result.options["v_start"])
    assert first.amplitudes[-1] / second.amplitudes[0] > 1.5
    assert second.below <= result.speed <= second.lowest
    assert result.flange_speed == first.flange_lowest
    # EN 14363's instability criterion: the flange-contact cycle fails it (1.31), the tread cycle passes (0.90)
    assert first.instability > 1.2 and 0.8 < second.instability < 1.0
    assert (first.flange_lowest / KMH, second.highest / KMH, second.lowest / KMH) == pytest.approx(
        (326.3, 301.3, 176.3), abs=0.1)  # regression guard (FASTSIM: 316.3, 296.3, 176.3)
    contact = wheelset_contacts(vehicle.model, vehicle.values, vehicle.wheelsets)[0]
    grid = [k * 1e-5 for k in range(600, 900)]
    clearance = next(y for y in grid if max(quasi_static_forces(contact, y, speed=50.0)[f"angle_{s}"]
                                            for s in ("left", "right")) > math.radians(30.0))
    assert clearance == pytest.approx(7.71e-3, abs=2e-5)
    ramp = result.points[: sum(len(a.amplitudes) for a in result.attractors) + 1]
    for point in ramp:
        if point.flange_contact:
            assert point.amplitude >= clearance - 0.15e-3
        elif point.alive:
            assert point.amplitude <= clearance + 0.15e-3
