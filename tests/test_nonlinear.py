"""Wheel/rail nonlinearities: flange contact, Shen-Hedrick-Elkins saturation, creep forces.

Physics in ``docs/rail-conventions.md`` (paper eqs. 8-11); axes x forward, y left,
yaw positive turning left.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.forces.deadband import DeadbandLaw, deadband_feedback
from express.forces.wheelsets import WheelsetCoordinates
from express.numeric.statespace import WheelsetData
from express.rail.nonlinear import flange_penetration, linear_creepages, saturation_factor, wheelset_forces

ROOT = Path(__file__).resolve().parents[1]

F1, F2 = 8.7e6, 7.8e6  # N, per wheel
GAMMA, R0, B = 0.1, 0.43, 0.56
DELTA, K_RAIL = 0.006, 2.0e7
MU, LOAD = 0.3, 50e3
V = 120 / 3.6


def wheelset(name="W1", **changes) -> WheelsetData:
    data = dict(name=name, y=0, psi=1, station=0.0, f1=F1, f2=F2, conicity=GAMMA, r0=R0, b=B,
                flange_clearance=DELTA, rail_stiffness=K_RAIL, friction=MU, wheel_load=LOAD)
    data.update(changes)
    return WheelsetData(**data)


def forces(y=0.0, psi=0.0, y_dot=0.0, psi_dot=0.0, y_rail=0.0, rho=0.0, ws=None, **flags):
    ws = ws or (wheelset(),)
    arr = lambda value: np.atleast_1d(np.asarray(value, dtype=float))  # noqa: E731
    return wheelset_forces(arr(y), arr(psi), arr(y_dot), arr(psi_dot), arr(y_rail), arr(rho), V, ws, **flags)


# ---------------------------------------------------------------- flange penetration (eq. 11)


def test_penetration_is_zero_inside_the_clearance():
    y = np.linspace(-DELTA, DELTA, 101)  # both boundaries included
    assert np.all(flange_penetration(y, 0.0, DELTA) == 0.0)


@pytest.mark.parametrize("y, expected", [(0.007, 0.001), (0.0065, 0.0005), (-0.008, -0.002), (-0.0061, -0.0001)])
def test_penetration_outside_the_clearance(y, expected):
    # dy = y - yR - delta beyond +delta, y - yR + delta beyond -delta
    assert flange_penetration(y, 0.0, DELTA) == pytest.approx(expected, abs=1e-15)


@pytest.mark.parametrize(
    "y, y_rail, expected",
    [(0.004, -0.003, 0.001), (0.007, 0.003, 0.0), (-0.002, 0.005, -0.001), (0.0, 0.0065, -0.0005), (0.01, 0.01, 0.0)],
)
def test_penetration_is_measured_from_the_displaced_rail(y, y_rail, expected):
    assert flange_penetration(y, y_rail, DELTA) == pytest.approx(expected, abs=1e-15)


def test_penetration_is_continuous_odd_and_has_slopes_zero_and_one():
    y = np.linspace(-0.02, 0.02, 4001)
    dy = flange_penetration(y, 0.0, DELTA)
    np.testing.assert_allclose(flange_penetration(-y, 0.0, DELTA), -dy, atol=1e-15)
    slope = np.diff(dy) / np.diff(y)
    inside = np.abs(y[:-1] + np.diff(y) / 2) < DELTA - 1e-9
    outside = np.abs(y[:-1] + np.diff(y) / 2) > DELTA + 1e-9
    np.testing.assert_allclose(slope[inside], 0.0, atol=1e-9)
    np.testing.assert_allclose(slope[outside], 1.0, atol=1e-6)
    assert np.max(np.abs(np.diff(dy))) <= np.max(np.diff(y)) + 1e-15  # no jump at +-delta


def test_penetration_broadcasts_over_time_and_wheelsets():
    y = np.array([[0.007, -0.007, 0.0], [0.0, 0.01, -0.02]])
    clearance = np.array([0.006, 0.005, 0.01])
    expected = np.array([[0.001, -0.002, 0.0], [0.0, 0.005, -0.01]])
    np.testing.assert_allclose(flange_penetration(y, 0.0, clearance), expected, atol=1e-15)


# ---------------------------------------------------------------- Shen-Hedrick-Elkins


def she(x):
    """F' / (mu N) for F / (mu N) = x."""
    x = np.asarray(x, dtype=float)
    return np.where(x <= 3.0, x - x**2 / 3.0 + x**3 / 27.0, 1.0)


def test_saturation_factor_is_one_at_zero_force_and_tends_to_one():
    assert float(saturation_factor(0.0, MU * LOAD)) == 1.0
    small = np.array([1e-9, 1e-6, 1e-3]) * MU * LOAD
    np.testing.assert_allclose(saturation_factor(small, MU * LOAD), 1.0 - np.array([1e-9, 1e-6, 1e-3]) / 3.0, rtol=1e-6)


def test_saturated_force_matches_the_polynomial():
    limit = MU * LOAD
    x = np.linspace(0.01, 6.0, 600)
    force = x * limit
    np.testing.assert_allclose(saturation_factor(force, limit) * force, she(x) * limit, rtol=1e-13)


def test_saturated_force_is_continuous_and_flat_at_three():
    limit = MU * LOAD
    x = np.array([3.0 - 1e-6, 3.0, 3.0 + 1e-6])
    saturated = saturation_factor(x * limit, limit) * x * limit
    np.testing.assert_allclose(saturated, limit, rtol=1e-12)  # value mu N at x = 3, no jump
    assert saturated[0] < limit  # approaches from below, and the slope 1 - 2x/3 + x^2/9 vanishes at 3


def test_saturated_force_is_monotone_bounded_and_below_the_linear_force():
    limit = np.array([MU * LOAD, 0.2 * 30e3])
    force = np.linspace(0.0, 10.0, 5001)[:, None] * limit
    saturated = saturation_factor(force, limit) * force
    assert np.all(np.diff(saturated, axis=0) >= -1e-9)
    assert np.all(saturated <= limit + 1e-9)
    assert np.all(saturated <= force + 1e-9)
    factor = saturation_factor(force, limit)
    assert np.all((factor > 0.0) & (factor <= 1.0))


# ---------------------------------------------------------------- creep forces (eqs. 8-9)


def test_creepage_formulas():
    xi_x, xi_y = linear_creepages(0.003, 0.001, 0.02, 0.004, 0.001, 1 / 400, V, GAMMA, R0, B)
    assert xi_x == pytest.approx(GAMMA * 0.002 / R0 + B * 0.004 / V + B / 400)
    assert xi_y == pytest.approx(0.02 / V - 0.001)


def test_wheelset_displaced_left_gets_a_negative_yaw_moment():
    y = 0.002  # to the left, inside the clearance, psi = 0
    out = forces(y=y, saturation=False)
    assert out["yaw_creep"][0] < 0.0
    assert out["yaw_creep"][0] == pytest.approx(-2 * B * F1 * GAMMA * y / R0)  # eq. 8
    assert out["lateral_creep"][0] == 0.0
    assert out["flange"][0] == 0.0
    # the same moment with saturation on, reduced but the same sign
    saturated = forces(y=y)
    assert -abs(out["yaw_creep"][0]) < saturated["yaw_creep"][0] < 0.0


def test_lateral_creep_force_signs():
    # yawed to the left (nose toward +y) while running straight: the rails push it left
    assert forces(psi=0.001, saturation=False)["lateral_creep"][0] == pytest.approx(2 * F2 * 0.001)
    # moving to the left: the creep force opposes the motion (damping 2 f2 / v)
    moving = forces(y_dot=0.05, saturation=False)["lateral_creep"][0]
    assert moving == pytest.approx(-2 * F2 * 0.05 / V)
    assert moving < 0.0


def test_pure_rolling_offset_in_a_curve_has_no_yaw_moment():
    rho = 1 / 400  # left curve: the pure-rolling line lies outward (to the right)
    centred = forces(rho=rho, saturation=False)["yaw_creep"][0]
    assert centred == pytest.approx(-2 * B * F1 * B * rho)  # steers outward
    offset = -R0 * B * rho / GAMMA
    assert abs(forces(y=offset, rho=rho, saturation=False)["yaw_creep"][0]) < 1e-6 * abs(centred)


def test_flange_force_pushes_back_toward_the_track_centre():
    # left curve: outer rail on the right, wheelset pressed to y < -delta
    out = forces(y=-0.008, rho=1 / 400)
    assert out["dy"][0] == pytest.approx(-0.002)
    assert out["flange"][0] == pytest.approx(K_RAIL * 0.002)
    assert forces(y=0.008)["flange"][0] == pytest.approx(-K_RAIL * 0.002)
    assert forces(y=0.008, flange=False)["flange"][0] == 0.0


def test_force_bookkeeping_and_saturated_resultant():
    rng = np.random.default_rng(1)
    count = 400
    ws = (wheelset("W1"), wheelset("W2", f1=6e6, f2=5e6, friction=0.2, wheel_load=40e3))
    shape = (count, 2)
    y = rng.uniform(-0.012, 0.012, shape)
    psi = rng.uniform(-0.01, 0.01, shape)
    y_dot = rng.uniform(-0.3, 0.3, shape)
    psi_dot = rng.uniform(-0.3, 0.3, shape)
    y_rail = rng.uniform(-0.004, 0.004, shape)
    rho = rng.uniform(-1 / 300, 1 / 300, shape)
    out = wheelset_forces(y, psi, y_dot, psi_dot, y_rail, rho, V, ws)
    linear = wheelset_forces(y, psi, y_dot, psi_dot, y_rail, rho, V, ws, saturation=False)
    np.testing.assert_allclose(linear["factor"], 1.0)
    np.testing.assert_allclose(linear["lateral_correction"], 0.0)
    np.testing.assert_allclose(out["lateral"], out["lateral_creep"] + out["flange"])
    np.testing.assert_allclose(out["lateral_correction"], out["lateral_creep"] - linear["lateral_creep"], atol=1e-6)
    np.testing.assert_allclose(out["yaw_correction"], out["yaw_creep"] - linear["yaw_creep"], atol=1e-6)
    np.testing.assert_allclose(out["flange"], -K_RAIL * flange_penetration(y, y_rail, DELTA))
    b = np.array([w.b for w in ws])
    limit = np.array([w.friction * w.wheel_load for w in ws])
    # per wheel: longitudinal M / (2 b), lateral F / 2; the resultant never exceeds mu N
    resultant = np.hypot(out["yaw_creep"] / (2 * b), out["lateral_creep"] / 2)
    assert np.all(resultant <= limit * (1 + 1e-12))
    assert np.any(resultant > 0.9 * limit)  # the sample does reach saturation
    # and it is the Shen-Hedrick-Elkins value of the linear resultant
    linear_resultant = np.hypot(linear["yaw_creep"] / (2 * b), linear["lateral_creep"] / 2)
    np.testing.assert_allclose(resultant, she(linear_resultant / limit) * limit, rtol=1e-10)


@pytest.mark.parametrize("flange, saturation", [(True, True), (True, False), (False, True), (False, False)])
def test_numba_feedback_matches_wheelset_forces(flange, saturation):
    """The compiled kernel of the time march feeds back exactly the corrections of
    ``wheelset_forces`` (flange force plus saturated-minus-linear creep)."""
    rng = np.random.default_rng(7)
    ws = (wheelset("W1", y=0, psi=1), wheelset("W2", y=2, psi=3, f1=6e6, conicity=0.2, friction=0.2))
    n = 5
    steps = 30
    y_rail = rng.uniform(-0.003, 0.003, (steps, 2))
    rho = rng.uniform(-1 / 300, 1 / 300, (steps, 2))
    arrays = [np.array([getattr(w, key) for w in ws], dtype=float)
              for key in ("f1", "f2", "conicity", "r0", "b", "flange_clearance", "rail_stiffness")]
    limit = np.array([w.friction * w.wheel_load for w in ws])
    iy, ipsi = np.array([0, 2]), np.array([1, 3])
    for k in range(steps):
        x = rng.uniform(-1, 1, 2 * n) * np.array([0.012, 0.008, 0.012, 0.008, 0.1] * 2) * np.r_[np.ones(n), 20 * np.ones(n)]
        z = np.zeros(4)
        coordinates = WheelsetCoordinates(iy, ipsi, n + iy, n + ipsi, y_rail, rho, V)
        deadband_feedback(x, k, DeadbandLaw(0, coordinates, *arrays, limit, flange, saturation), z)
        out = wheelset_forces(x[iy], x[ipsi], x[n + iy], x[n + ipsi], y_rail[k], rho[k], V, ws,
                              flange=flange, saturation=saturation)
        np.testing.assert_allclose(z[:2], out["flange"] + out["lateral_correction"], rtol=1e-9, atol=1e-6)
        np.testing.assert_allclose(z[2:], out["yaw_correction"], rtol=1e-9, atol=1e-6)


# ---------------------------------------------------------------- Q definitions


@pytest.fixture(scope="module")
def conventional():
    from express.io import load_model
    from express.numeric.statespace import vehicle_model

    return vehicle_model(load_model(ROOT / "examples" / "conventional.toml"))


def test_q_is_the_flanging_wheels_share_of_the_rail_force(conventional):
    """``Y{n}`` = flange force + half the wheelset's lateral creep force; ``Ytot{n}`` =
    creep + flange; ``YQ{n}`` = Y / Q0 (``simulate.py`` module docstring)."""
    from express.analysis.time.simulate import derived_outputs, track_inputs
    from express.rail.track import paper_curve

    vehicle = conventional
    n = vehicle.n
    distance = np.array([0.0, 250.0, 250.0, 250.0])  # straight, then in the R = 400 m curve
    q = np.zeros((4, n))
    q_dot = np.zeros((4, n))
    w1 = vehicle.wheelsets[0]
    q[1, w1.y] = -0.008  # 2 mm into the outer (right) rail of the left curve
    q[2, w1.y] = -0.003  # inside the clearance
    q[3, w1.y], q[3, w1.psi], q_dot[3, w1.y] = -0.0065, 0.002, 0.01
    inputs = track_inputs(vehicle, paper_curve(), distance, vehicle.speed)
    out = derived_outputs(vehicle, q, q_dot, inputs, vehicle.speed)
    ws = vehicle.wheelsets
    iy, ipsi = [w.y for w in ws], [w.psi for w in ws]
    ref = wheelset_forces(q[:, iy], q[:, ipsi], q_dot[:, iy], q_dot[:, ipsi], inputs.y_rail, inputs.rho_wheelsets,
                          vehicle.speed, ws)
    for j in range(len(ws)):
        np.testing.assert_allclose(out[f"Y{j + 1}"], ref["flange"][:, j] + 0.5 * ref["lateral_creep"][:, j])
        np.testing.assert_allclose(out[f"Ytot{j + 1}"], ref["lateral"][:, j])
        np.testing.assert_allclose(out[f"YQ{j + 1}"], out[f"Y{j + 1}"] / ws[j].wheel_load)
        np.testing.assert_allclose(out[f"flange{j + 1}"], ref["flange"][:, j])
    assert out["Y1"][0] == 0.0  # centred on the straight: no force
    assert out["flange1"][1] == pytest.approx(w1.rail_stiffness * 0.002)  # outer rail pushes it left
    assert out["dy1"][1] == pytest.approx(-0.002)
    assert out["flange1"][2] == 0.0
    assert out["rho1"][1] == pytest.approx(1 / 400)
    assert out["S1"][1] == pytest.approx(0.095)
