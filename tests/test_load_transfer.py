"""Quasi-static wheel loads in a canted curve (express.rail.load_transfer) against statics."""

from __future__ import annotations

import math

import numpy as np
import pytest

from express.io import load_model
from express.model.parameters import expression_value
from express.numeric.statespace import load_vehicle
from express.rail.load_transfer import BodyLoads, body_loads, load_shares, track_plane_accelerations, wheel_loads

G = 9.81


@pytest.fixture(scope="module")
def car():
    vehicle = load_vehicle("examples/conventional.toml")
    return vehicle, body_loads(vehicle.model, vehicle.values, [w.b for w in vehicle.wheelsets])


def test_accelerations_are_the_resolved_gravity_and_centripetal_ones():
    # right curve R = 400 m, 105 mm cant over 1.067 m, 120 km/h
    v, rho, cant, base = 120 / 3.6, -1 / 400, -0.105, 1.067
    phi = math.asin(cant / base)
    a_y, a_n = track_plane_accelerations(v, rho, cant, base, G)
    # gravity (0, 0, -g) and centripetal (0, v^2 rho, 0) seen in the track frame rolled by phi
    assert a_y == pytest.approx(G * math.sin(phi) - v**2 * rho * math.cos(phi), rel=1e-15)
    assert a_n == pytest.approx(G * math.cos(phi) + v**2 * rho * math.sin(phi), rel=1e-15)
    assert math.hypot(a_y, a_n) == pytest.approx(math.hypot(G, v**2 * rho), rel=1e-14)
    with pytest.raises(ValueError, match="cant base"):
        track_plane_accelerations(v, rho, 1.1, base, G)


def test_shares_carry_each_body_and_keep_its_station(car):
    vehicle, loads = car
    stations = np.array([w.station for w in vehicle.wheelsets])
    body_station = np.array([expression_value(b.position[0], vehicle.values) for b in vehicle.model.bodies])
    np.testing.assert_allclose(loads.shares.sum(axis=1), 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(loads.shares @ stations, body_station, rtol=0, atol=1e-12)
    # the model's own static wheel load P0 = (mc + 2 mt + 4 mw) g / 8
    np.testing.assert_allclose(loads.static_loads(vehicle.values["g"]), [w.wheel_load for w in vehicle.wheelsets],
                               rtol=1e-15)


def test_offset_car_body_is_shared_by_the_lever_rule():
    model = load_model("examples/conventional.toml")
    values = {**load_vehicle("examples/conventional.toml").values}
    shares = load_shares(model, values)
    cb = [b.id for b in model.bodies].index("CB")
    assert shares[cb] == pytest.approx([0.25] * 4, abs=1e-15)


@pytest.mark.parametrize(("speed_kmh", "radius", "cant"), [(120, 400, 0.105), (160, 1000, 0.150), (40, 600, 0.150),
                                                          (100, -800, -0.080)])
def test_statics_close(car, speed_kmh, radius, cant):
    vehicle, loads = car
    v, rho = speed_kmh / 3.6, 1.0 / radius
    base = vehicle.values["G"]
    a_y, a_n = track_plane_accelerations(v, rho, cant, base, G)
    q = wheel_loads(loads, a_y, a_n)
    mass = loads.mass.sum()
    phi = math.asin(cant / base)
    # the sum: the weight's component normal to the track plane plus the centrifugal one
    assert q.total.sum() == pytest.approx(mass * (G * math.cos(phi) + v**2 * rho * math.sin(phi)), rel=1e-14)
    # the roll moment of the whole vehicle about the rail-level centreline
    b0 = loads.half_base
    assert float(q.difference @ b0) == pytest.approx(a_y * float(loads.mass @ loads.height), rel=1e-13)
    # each wheelset: its bodies' m a h / (2 b0) per wheel (a = -a_y, the cant deficiency)
    per_wheelset = -a_y * ((loads.mass * loads.height) @ loads.shares) / (2 * b0)
    np.testing.assert_allclose((q.right - q.left) / 2, per_wheelset, rtol=1e-13)


def test_cant_excess_loads_the_inner_rail(car):
    _, loads = car
    # left curve R = 600 m, 150 mm cant, 40 km/h: cant excess, the inner (left) rail gains
    a_y, a_n = track_plane_accelerations(40 / 3.6, 1 / 600, 0.150, 1.067, G)
    assert a_y > 0
    q = wheel_loads(loads, a_y, a_n)
    assert np.all(q.left > q.right)
    # cant deficiency in the same curve at 140 km/h: the outer (right) rail gains
    q = wheel_loads(loads, *track_plane_accelerations(140 / 3.6, 1 / 600, 0.150, 1.067, G))
    assert np.all(q.right > q.left)


def test_single_mass_closed_form_and_suspension_roll():
    # 10 t at 1.2 m on one wheelset with b0 = 0.75 m, 0.8 m/s^2 deficiency, body 20 mm outward
    one = BodyLoads(("B",), np.array([1e4]), np.array([1.2]), np.ones((1, 1)), np.array([0.75]))
    q = wheel_loads(one, -0.8, G)
    assert float(q.right[0] - q.left[0]) / 2 == pytest.approx(1e4 * 0.8 * 1.2 / (2 * 0.75), rel=1e-15)
    rolled = wheel_loads(one, -0.8, G, offsets=[-0.02])
    extra = float(rolled.right[0] - rolled.left[0]) / 2 - float(q.right[0] - q.left[0]) / 2
    assert extra == pytest.approx(1e4 * G * 0.02 / (2 * 0.75), rel=1e-13)


def test_time_histories_broadcast(car):
    _, loads = car
    a_y, a_n = track_plane_accelerations(np.array([10.0, 30.0, 50.0]), -1 / 500, -0.1, 1.067, G)
    q = wheel_loads(loads, a_y[:, None], a_n[:, None], offsets=np.zeros((3, loads.mass.size)))
    assert q.left.shape == (3, 4)
    np.testing.assert_allclose(q.total, np.repeat(a_n[:, None], 4, axis=1) * 2 * loads.static_loads(G) / G, rtol=1e-14)


def test_accelerations_per_body():
    # two bodies on one wheelset, each feeling its own lateral acceleration
    two = BodyLoads(("A", "B"), np.array([1e4, 2e3]), np.array([1.5, 0.5]), np.ones((2, 1)), np.array([0.75]))
    q = wheel_loads(two, np.array([-1.0, -0.5]), G)
    assert float(q.right[0] - q.left[0]) == pytest.approx((1e4 * 1.0 * 1.5 + 2e3 * 0.5 * 0.5) / 0.75, rel=1e-15)
