"""Steady harmonic response: the stacked solve and the Schur route agree, and with a
plain per-frequency solve on the same matrices."""

from __future__ import annotations

import numpy as np
import pytest

from express.analysis.frequency import dynamic_stiffness, frequency_response, ground_response, steady_response
from express.base.diagnostics import AnalysisError
from express.io import load_model, parse_toml_model
from express.model.parameters import with_values
from express.numeric.statespace import vehicle_model

LEVER_VALUES = {"J1": 2.0, "J2": 0.5, "b": 0.4, "c": 300.0, "kLL": 5.5e6, "kLU": 5e5, "lLL": 0.06, "lLU": 0.3, "m": 20.0}


@pytest.fixture(scope="module", params=["forced-steering.toml", "conventional.toml", "forced-steering-yaw-bush.toml"])
def car(request):
    return vehicle_model(load_model(f"examples/{request.param}"))


def _plain(vehicle, frequencies, speed, columns, amplitudes):
    """One ``numpy.linalg.solve`` per frequency of the second-order equations."""
    out = []
    for f, u in zip(frequencies, amplitudes, strict=True):
        w = 2 * np.pi * f
        z = -w * w * vehicle.mass + 1j * w * vehicle.damping(speed) + vehicle.stiffness
        rhs = (vehicle.forcing(speed)[:, columns] + 1j * w * vehicle.forcing_rate(speed)[:, columns]) @ u
        out.append(np.linalg.solve(z, rhs))
    return np.array(out)


@pytest.mark.parametrize("count", [20, 400])  # below and above the Schur threshold (2 x states)
def test_both_routes_equal_a_plain_solve(car, count):
    frequencies = np.geomspace(0.05, 30.0, count)
    columns = [car.inputs.index(name) for name in car.layout.irregularity]
    rng = np.random.default_rng(count)
    amplitudes = rng.normal(size=(count, len(columns), 2)) + 1j * rng.normal(size=(count, len(columns), 2))
    schur = count >= 2 * car.form.size
    assert schur == (count == 400)
    got = steady_response(car, frequencies, 25.0, columns, amplitudes)
    expected = _plain(car, frequencies, 25.0, columns, amplitudes)
    scale = np.abs(expected).max(axis=1, keepdims=True)
    assert np.all(np.abs(got - expected) <= (1e-7 if schur else 1e-12) * scale)


def test_dynamic_stiffness_is_built_exactly():
    car = vehicle_model(load_model("examples/conventional.toml"))
    w = np.array([0.0, 3.0, 70.0])
    z = dynamic_stiffness(car, w, 30.0)
    for k, wk in enumerate(w):
        assert np.array_equal(z[k].real, car.stiffness - wk**2 * car.mass)
        assert np.array_equal(z[k].imag, wk * car.damping(30.0))


def test_frequency_response_on_a_dense_grid_matches_a_sparse_one():
    """The FRF's outputs do not depend on the route: the points of a 30-frequency grid
    inside a 3000-frequency grid (Schur route) have the same amplitudes."""
    car = vehicle_model(load_model("examples/forced-steering.toml"))
    dense = np.linspace(0.2, 20.0, 3001)
    sparse = dense[::100]
    a = frequency_response(car, dense)
    b = frequency_response(car, sparse)
    for name in ("floor_front", "W1.y", "CB.y"):
        peak = np.abs(b.amplitude_of(name)).max()
        assert np.abs(a.amplitude_of(name)[::100] - b.amplitude_of(name)).max() <= 1e-7 * peak


@pytest.mark.parametrize("count", [2, 50])
def test_ground_response_routes_agree_with_the_closed_form_of_the_lever(count):
    """The lever's transfer functions by either route against a plain solve."""
    lever = vehicle_model(with_values(load_model("examples/lever.exp"), LEVER_VALUES))
    frequencies = np.linspace(0.0, 200.0, count)
    tf = ground_response(lever, frequencies)
    columns = [lever.inputs.index(name) for name in tf.inputs]
    identity = np.broadcast_to(np.eye(len(columns)), (count, len(columns), len(columns)))
    expected = _plain(lever, frequencies, 1.0, columns, identity)
    assert np.allclose(tf.H, expected, rtol=1e-9, atol=1e-12 * np.abs(expected).max())


SPRING = """
[model]
name = "free"
[parameters]
m = 100
k = 1e4
[bodies.B]
mass = "m"
dofs = ["x", "y"]
[grounds.G]
[points.a]
body = "B"
[points.g]
body = "G"
[elements.s]
from = "a"
to = "g"
direction = "x"
stiffness = "k"
"""


@pytest.mark.parametrize("count", [3, 30])
def test_a_singular_dynamic_stiffness_is_an_analysis_error_on_both_routes(count):
    """A free lateral DOF: at 0 Hz nothing holds it, whatever the route."""
    vehicle = vehicle_model(parse_toml_model(SPRING, source="free.toml"))
    with pytest.raises(AnalysisError, match="singular"):
        ground_response(vehicle, np.linspace(0.0, 5.0, count))


@pytest.fixture(scope="module")
def train(tmp_path_factory):
    """A 5-car train of the steered car: its DOFs couple within a narrow band."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("make_vehicles", "examples/make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = tmp_path_factory.mktemp("train") / "train5.toml"
    path.write_text(module.vehicle_toml(True, cars=5), encoding="utf-8")
    return vehicle_model(load_model(path))


@pytest.mark.parametrize("route", ["stacked", "banded", "schur"])
@pytest.mark.parametrize("which", ["train", "manchester", "conventional"])
def test_every_route_equals_a_plain_solve(route, which, train):
    vehicle = train if which == "train" else vehicle_model(load_model(f"examples/{which}.toml"))
    frequencies = np.geomspace(0.05, 30.0, 12)
    columns = list(range(min(3, len(vehicle.inputs))))
    rng = np.random.default_rng(7)
    amplitudes = rng.normal(size=(12, len(columns), 2)) + 1j * rng.normal(size=(12, len(columns), 2))
    got = steady_response(vehicle, frequencies, 25.0, columns, amplitudes, route=route)
    expected = _plain(vehicle, frequencies, 25.0, columns, amplitudes)
    scale = np.abs(expected).max(axis=1, keepdims=True)
    assert np.all(np.abs(got - expected) <= (1e-7 if route == "schur" else 1e-12) * scale)


def test_a_train_takes_the_banded_route(train):
    """Its band (26 + 26 + 1 of 120 DOFs) halves a dense LU's work, and at 200
    frequencies the Schur form of 240 states costs more than 200 banded solves."""
    from express.analysis.banded import band_layout, choose_route

    layout = band_layout(train.mass, train.damping(30.0), train.stiffness)
    assert (layout.lower, layout.upper) == (26, 26)
    assert choose_route(train.n, train.form.size, 200, layout) == "banded"
    assert choose_route(24, 48, 200, band_layout(np.ones((24, 24)))) == "schur"
    assert choose_route(24, 48, 20, band_layout(np.ones((24, 24)))) == "stacked"


def test_a_singular_dynamic_stiffness_is_an_analysis_error_on_the_banded_route():
    vehicle = vehicle_model(parse_toml_model(SPRING, source="free.toml"))
    with pytest.raises(AnalysisError, match="singular"):
        steady_response(vehicle, np.array([0.0, 1.0]), 1.0, [], np.zeros((2, 0, 1)), route="banded")


def test_an_unknown_route_is_refused(train):
    with pytest.raises(ValueError, match="route must be"):
        steady_response(train, np.array([1.0]), 1.0, [0], np.ones((1, 1, 1)), route="qr")
