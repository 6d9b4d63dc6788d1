"""EN 14363's twist: the limit twist of a base, the combined twist shape, the quasi-static
unloading on it (closed form of the roll chain), the flange-climb superposition against
Nadal, ``express twist --assess`` and its bad input (``express.analysis.twist``)."""

from __future__ import annotations

import math
import time
from types import SimpleNamespace

import numpy as np
import pytest

from cli_support import assert_input_error, run, run_json
from express.analysis.curving.assessment import nadal_limit
from express.analysis.twist import (
    assess_twist,
    cross_level_heights,
    flange_climb,
    quasi_static_loads,
    rail_height_loads,
    standard_twist,
    twist_limit,
    twisted_track,
)
from express.base.diagnostics import ArgumentError
from express.numeric.statespace import load_vehicle
from test_ride_vehicle import two_axle_toml

KH, B0, B1, KZ, A = 1.0e9, 0.75, 1.0, 1.2e6, 4.0  # the two-axle model's numbers (tests/test_ride_vehicle.py)
WHEEL_LOAD = (20000.0 + 2 * 1500.0) * 9.81 / 4


@pytest.fixture(scope="module")
def two_axle_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("twist") / "two_axle.toml"
    path.write_text(two_axle_toml(contact_damping=2.0e5), encoding="utf-8")
    return path


@pytest.fixture(scope="module")
def two_axle(two_axle_path):
    return load_vehicle(two_axle_path)


@pytest.mark.parametrize(("base", "expected"), [
    (1.8, 7e-3), (4.0, 7e-3),                       # the plateau, up to and at its break point
    (4.0 + 1e-9, 20e-3 / (4.0 + 1e-9) + 2e-3),      # just past it: the middle branch, continuous (7 mm/m)
    (14.2, 20e-3 / 14.2 + 2e-3), (10.0, 4e-3),      # mid values: 3.408 and 4 mm/m
    (20.0 - 1e-9, 20e-3 / (20.0 - 1e-9) + 2e-3), (20.0, 3e-3), (30.0, 3e-3),  # continuous at 20 m, then the floor
])
def test_the_limit_twist_is_the_closed_form_at_its_break_points(base, expected):
    """``g_lim = 7`` mm/m to 4 m, ``20/(2a) + 2`` mm/m between, 3 mm/m from 20 m
    (docs/track.md); exact to rounding, and continuous at both break points."""
    assert twist_limit(base) == pytest.approx(expected, rel=1e-12)
    for edge in (4.0, 20.0):
        assert twist_limit(edge * (1 + 1e-12)) == pytest.approx(twist_limit(edge * (1 - 1e-12)), rel=1e-9)


@pytest.mark.parametrize("base", [-1.0, 0.0, math.nan, math.inf, "4 m"])
def test_a_base_that_is_no_positive_length_is_refused(base):
    with pytest.raises(ArgumentError, match="positive length"):
        twist_limit(base)


def _vehicle(*stations):
    return SimpleNamespace(wheelsets=[SimpleNamespace(station=s) for s in stations])


def test_the_standard_twist_at_the_wheelsets_against_hand_computation():
    """The wagon's layout (bogie centres 14.2 m apart, wheelbase 1.8 m): ``g* = 20/14.2 + 3``
    mm/m, ``g+ = 7`` mm/m; by hand c(W1) = g* 14.2 + g+ 0.9, c(W2) = g* 14.2 - g+ 0.9,
    c(W3) = g* 0.9, c(W4) = -g* 0.9 [m]; the bogie centres differ by g* 2a*, the leading
    bogie's wheelsets by g+ 2a+. A two-axle vehicle: g* over its wheelbase only."""
    shape = standard_twist(_vehicle(8.0, 6.2, -6.2, -8.0))
    g_body, g_bogie = 20e-3 / 14.2 + 2e-3, 7e-3
    assert (shape.body_base, shape.bogie_base) == pytest.approx((14.2, 1.8), rel=1e-12)
    hand = [g_body * 14.2 + g_bogie * 0.9, g_body * 14.2 - g_bogie * 0.9, g_body * 0.9, -g_body * 0.9]
    np.testing.assert_allclose(shape.cross_level, hand, rtol=1e-12)
    c = shape.cross_level
    assert (c[0] + c[1]) / 2 - (c[2] + c[3]) / 2 == pytest.approx(g_body * 14.2, rel=1e-12)
    assert c[0] - c[1] == pytest.approx(g_bogie * 1.8, rel=1e-12)
    np.testing.assert_allclose(shape.heights[0], np.stack([-c / 2, c / 2], axis=1))
    two = standard_twist(_vehicle(4.0, -4.0))
    assert two.bogie_base == 0.0 and two.body_twist == pytest.approx(4.5e-3)
    np.testing.assert_allclose(two.cross_level, [4.5e-3 * 8.0, 0.0], rtol=1e-12)
    given = standard_twist(_vehicle(8.0, 6.2, -6.2, -8.0), 0.003, 0.005)
    assert given.cross_level[0] - given.cross_level[1] == pytest.approx(0.005 * 1.8)
    with pytest.raises(ArgumentError, match="3 wheelsets"):
        standard_twist(_vehicle(5.0, 0.0, -5.0))
    with pytest.raises(ArgumentError, match="more than 100 mm"):
        standard_twist(_vehicle(4.0, -4.0), 0.02)


def test_unloading_on_the_standard_twist_matches_the_roll_chain(two_axle):
    """Closed form. Each wheelset rolls with its rails, ``phi_i = -c_i / (2 b0)``; between
    it and the rigid body sit its contact springs (roll stiffness ``2 kH b0^2``) in series
    with its primary springs (``2 kz b1^2``): ``k = 1 / (1/(2 kH b0^2) + 1/(2 kz b1^2))``.
    The body's roll balance ``k (phi1 - theta) + k (phi2 - theta) = 0`` gives
    ``theta = (phi1 + phi2) / 2`` and the moment in chain 1 ``M = k (phi1 - phi2) / 2``,
    carried by the wheel pair as ``dQ = -+ M / (2 b0)``. On the standard twist
    (c1 = g 2a, c2 = 0, g = g_lim(8 m) = 4.5 mm/m): ``dQ1L = -k g 2a / (8 b0^2)``, the
    diagonal wheel W2 R alike. Asserted 1e-9 (achieved about 1e-13); the rail heights
    imposed at the contact springs (the path of a model without a ground under each rail)
    equal the per-rail grounds' inputs to 1e-9 on a ramp."""
    found = assess_twist(two_axle, climb=False)
    g = twist_limit(2 * A)
    k = 1 / (1 / (2 * KH * B0**2) + 1 / (2 * KZ * B1**2))
    dq = -k * g * 2 * A / (8 * B0**2)
    np.testing.assert_allclose(found.delta_q, [[dq, -dq], [-dq, dq]], rtol=1e-9)
    criterion = found.assessment.criteria[0]
    assert criterion.value == pytest.approx(-dq / WHEEL_LOAD, rel=1e-9) and criterion.limit == 0.6
    assert criterion.passed is (-dq / WHEEL_LOAD <= 0.6)
    track = twisted_track(0.003, 30.0)
    distance = np.array([60.0, 70.0, 83.0])
    imposed = rail_height_loads(two_axle, cross_level_heights(two_axle, track, distance))
    for k_, d in enumerate(distance):
        np.testing.assert_allclose(imposed[k_], quasi_static_loads(two_axle, track, d).delta_q, rtol=1e-9, atol=1e-6)


@pytest.mark.parametrize(("degrees", "friction"), [(70.0, 0.36), (70.0, 0.3), (60.0, 0.36), (75.0, 0.25)])
def test_nadal_is_the_closed_form(degrees, friction):
    """``(tan g - mu) / (1 + mu tan g) = tan(g - atan mu)`` (the tangent of a difference);
    70 degrees, mu 0.36: 1.2003."""
    gamma = math.radians(degrees)
    assert nadal_limit(gamma, friction) == pytest.approx(math.tan(gamma - math.atan(friction)), rel=1e-12)
    if (degrees, friction) == (70.0, 0.36):
        assert nadal_limit(gamma, friction) == pytest.approx(1.2003, abs=1e-4)


def test_the_flange_climb_adds_the_twist_unloading_to_the_curve(monkeypatch, two_axle):
    """Y kept, Q + dQ: a curve state with Y/Q 0.5 at Q 30 kN and dQ -10 kN gives
    0.5 * 30 / 20 = 0.75; dQ -30 kN lifts the wheel (inf)."""
    import express.analysis.curving.settled as settled

    wheel_rail = SimpleNamespace(y_over_q=np.full((1, 2, 2), 0.5), vertical_load=np.full((1, 2, 2), 30e3))
    monkeypatch.setattr(settled, "curving_or_settled", lambda *a, **k: [(SimpleNamespace(wheel_rail=wheel_rail), None)])
    found = flange_climb(two_axle, np.array([[-10e3, 10e3], [10e3, -10e3]]))
    assert found.wheel == "W1 left" and found.y_over_q == pytest.approx(0.75, rel=1e-12)
    assert found.limit == pytest.approx(nadal_limit(math.radians(70.0), 0.36), rel=1e-12)
    assert flange_climb(two_axle, np.array([[-30e3, 0.0], [0.0, 0.0]])).y_over_q == math.inf
    mean = {"YQ1L": 0.4, "Q1L": 25e3}
    run_in = SimpleNamespace(mean=mean, reason="no equilibrium found (the solver's words)")
    monkeypatch.setattr(settled, "curving_or_settled", lambda *a, **k: [(None, run_in)])
    found = flange_climb(two_axle, np.array([[-5e3, 5e3], [5e3, -5e3]]))
    assert found.y_over_q == pytest.approx(0.4 * 25 / 20, rel=1e-12)
    assert found.source == "settled time run: no equilibrium found"


def test_the_twist_command_on_the_standard_twist_and_its_assessment(capsys, two_axle_path):
    """The default is the standard twist (no limit applied, exit 0); ``--assess`` applies
    0.6: a passing twist exits 0, ``--body-twist 100`` (mm/m, beyond any wheel's load)
    exits 3 and says which criterion failed."""
    data = run_json(capsys, "twist", str(two_axle_path))
    assert data["twist"]["body_base"] == pytest.approx(8.0) and data["assessed"] is False
    k = 1 / (1 / (2 * KH * B0**2) + 1 / (2 * KZ * B1**2))
    assert data["criteria"][0]["value"] == pytest.approx(k * 4.5e-3 * 8 / (8 * B0**2) / WHEEL_LOAD, rel=1e-9)
    status, out, err = run(capsys, "twist", str(two_axle_path), "--assess", "--no-climb")
    assert status == (0 if data["criteria"][0]["passed"] else 3) and "dQQ0_twist" in out
    status, out, err = run(capsys, "twist", str(two_axle_path), "--assess", "--no-climb", "--body-twist", "12")
    assert status == 3 and "FAIL" in out and "dQQ0_twist" in err


@pytest.mark.parametrize(("argv", "mentions"), [
    (("--twist", "3 m"), "mm/m"),
    (("--body-twist", "0.003 m/m"), "mm/m"),
    (("--length", "-5 m"), "--length"),
    (("--assess", "--twist", "3"), "standard twist"),
    (("--radius", "-150 m"), "--radius"),
])
def test_bad_twist_input_exits_2(capsys, two_axle_path, argv, mentions):
    assert_input_error(capsys, "twist", str(two_axle_path), *argv, mentions=mentions)


@pytest.mark.slow
def test_the_wagon_twist_assessment_takes_under_2_s():
    """The bundled Y25 wagon's assessment on the standard twist (the model loaded first;
    the flange climb's curving run is not in it): its friction elements make it a slow
    time run onto the twist at 2.5 ms checked against 5 ms (``express.analysis.twist.
    passage``): asserted < 2 s, measured 0.41 s (median of 5). Regression guards on the figures of
    our own run: tare -dQ/Q0 0.712 on W1 left with the friction slipping, where the linear
    static solution (every friction element at its pre-slip stiffness) gives 2.07."""
    wagon = load_vehicle("examples/y25-wagon.toml")
    assess_twist(wagon, climb=False)  # the kernels loaded, the tables built
    start = time.perf_counter()
    found = assess_twist(wagon, climb=False)
    elapsed = time.perf_counter() - start
    print(f"wagon twist assessment {elapsed * 1e3:.1f} ms")
    assert elapsed < 2.0
    assert found.twist.describe() == "g* 3.41 mm/m over 2a* 14.2 m + g+ 7 mm/m over 2a+ 1.8 m"
    assert "friction slipping" in found.method
    assert found.assessment.criteria[0].value == pytest.approx(0.7123, rel=2e-3)  # regression guard
    static = -rail_height_loads(wagon, found.twist.heights)[0] / found.wheel_load[:, None]
    assert static.max() == pytest.approx(2.0669, rel=1e-3)  # regression guard: stuck friction


def test_the_loads_take_quantities_as_the_library_does(two_axle):
    """``distance`` and ``speed`` as text or pint quantities give the SI numbers' loads
    (issue 35: units in the library are explicit)."""
    import pint

    units = pint.UnitRegistry()
    track = twisted_track(0.003, 30.0)
    si = quasi_static_loads(two_axle, track, 70.0, 20.0)
    for distance, speed in (("70 m", "72 km/h"), (70.0 * units.meter, 20.0 * units.meter / units.second)):
        found = quasi_static_loads(two_axle, track, distance, speed)
        assert found.distance == 70.0 and np.array_equal(found.delta_q, si.delta_q)
    with pytest.raises(ArgumentError, match="distance"):
        quasi_static_loads(two_axle, track, "70 s")
