"""Steady harmonic response: the stacked, banded and Schur routes agree with a plain
per-frequency solve on the same matrices and with a 30-digit solve; the route follows the cost."""

from __future__ import annotations

import numpy as np
import pytest

from express.analysis.frequency.banded import band_layout, choose_route
from express.analysis.frequency.frequency import (
    dynamic_stiffness,
    frequency_response,
    ground_response,
    irregularity_delays,
    steady_response,
)
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


@pytest.mark.parametrize("route", ["stacked", "schur"])
def test_both_dense_routes_equal_a_plain_solve(car, route):
    """Either dense route against one ``numpy.linalg.solve`` per frequency: the stacked
    solve is the same LAPACK solve (1e-12 asked; equal to the last bit achieved); the
    Schur form of the state matrix loses more to the steered cars' stiff lever and yaw-bush
    modes (3e-8 asked; 1.0e-9, 2.8e-11 and 1.1e-8 of the largest amplitude achieved on the
    forced-steering, conventional and yaw-bush cars at 400 frequencies)."""
    count = 400
    frequencies = np.geomspace(0.05, 30.0, count)
    columns = [car.inputs.index(name) for name in car.layout.irregularity]
    rng = np.random.default_rng(count)
    amplitudes = rng.normal(size=(count, len(columns), 2)) + 1j * rng.normal(size=(count, len(columns), 2))
    got = steady_response(car, frequencies, 25.0, columns, amplitudes, route=route)
    expected = _plain(car, frequencies, 25.0, columns, amplitudes)
    scale = np.abs(expected).max(axis=1, keepdims=True)
    assert np.all(np.abs(got - expected) <= (3e-8 if route == "schur" else 1e-12) * scale)


def test_dynamic_stiffness_is_built_exactly():
    car = vehicle_model(load_model("examples/conventional.toml"))
    w = np.array([0.0, 3.0, 70.0])
    z = dynamic_stiffness(car, w, 30.0)
    for k, wk in enumerate(w):
        assert np.array_equal(z[k].real, car.stiffness - wk**2 * car.mass)
        assert np.array_equal(z[k].imag, wk * car.damping(30.0))


def test_frequency_response_on_a_dense_grid_matches_a_sparse_one():
    """The FRF at a frequency does not depend on the grid around it: the points of a
    30-frequency grid inside a 3000-frequency grid have the same amplitudes (both grids
    take the stacked solve, one LAPACK solve per frequency: equal to the last bit)."""
    car = vehicle_model(load_model("examples/forced-steering.toml"))
    dense = np.linspace(0.2, 20.0, 3001)
    sparse = dense[::100]
    a = frequency_response(car, dense)
    b = frequency_response(car, sparse)
    for name in ("floor_front", "W1.y", "CB.y"):
        assert np.array_equal(a.amplitude_of(name)[::100], b.amplitude_of(name))


@pytest.mark.parametrize("count", [2, 50])
def test_ground_response_routes_agree_with_the_closed_form_of_the_lever(count):
    """The lever's transfer functions against a plain solve."""
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
def test_a_singular_dynamic_stiffness_is_an_analysis_error(count):
    """A free lateral DOF: at 0 Hz nothing holds it."""
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
    assert np.all(np.abs(got - expected) <= (5e-9 if route == "schur" else 1e-12) * scale)


def test_a_train_takes_the_route_its_size_calls_for(train):
    """The 5-car train's band (26 + 26 + 1 of 120 DOFs) makes a banded LU about 3.5x
    cheaper than a dense one, but at 200 frequencies the dense solves (~0.08 s) cost
    less than importing SciPy's LAPACK (0.25 s): the stacked solve; from ~1000
    frequencies on the banded LU.  20 cars (480 DOFs, the same band): banded from a
    few dozen frequencies on (20: 0.26 s against 0.5 s of dense solves); a 24-DOF car: stacked up to the 100 000 frequencies ``frf``
    allows."""
    from express.analysis.frequency.banded import BandLayout

    layout = band_layout(train.mass, train.damping(30.0), train.stiffness)
    assert (layout.lower, layout.upper) == (26, 26)
    assert choose_route(train.n, train.form.size, 200, layout) == "stacked"
    assert choose_route(train.n, train.form.size, 1000, layout) == "banded"
    assert choose_route(480, 960, 2, BandLayout(np.arange(480), 26, 26)) == "stacked"
    assert choose_route(480, 960, 20, BandLayout(np.arange(480), 26, 26)) == "banded"
    assert choose_route(24, 48, 100_000, band_layout(np.ones((24, 24)))) == "stacked"


@pytest.mark.parametrize("route", ["stacked", "banded", "schur"])
def test_a_singular_dynamic_stiffness_is_an_analysis_error_on_every_route(route):
    """A free lateral DOF: at 0 Hz nothing holds it."""
    vehicle = vehicle_model(parse_toml_model(SPRING, source="free.toml"))
    with pytest.raises(AnalysisError, match="singular"):
        steady_response(vehicle, np.array([0.0, 1.0]), 1.0, [], np.zeros((2, 0, 1)), route=route)


def test_an_unknown_route_is_refused(train):
    with pytest.raises(ValueError, match="route must be"):
        steady_response(train, np.array([1.0]), 1.0, [0], np.ones((1, 1, 1)), route="qr")


def _exact(vehicle, frequencies, columns, amplitudes):
    """The response solved in 30-digit arithmetic (mpmath) from the same float matrices:
    what every route approximates."""
    import mpmath

    with mpmath.workdps(30):
        m, c, k = (mpmath.matrix(a.tolist()) for a in (vehicle.mass, vehicle.damping(vehicle.speed), vehicle.stiffness))
        p = mpmath.matrix(vehicle.forcing(vehicle.speed)[:, columns].tolist())
        pd = mpmath.matrix(vehicle.forcing_rate(vehicle.speed)[:, columns].tolist())
        out = []
        for f, u in zip(frequencies, amplitudes, strict=True):
            w = 2 * mpmath.pi * mpmath.mpf(float(f))
            u = mpmath.matrix([complex(x) for x in u])
            x = mpmath.lu_solve(-w * w * m + 1j * w * c + k, (p + 1j * w * pd) * u)
            out.append([complex(x[i]) for i in range(vehicle.n)])
    return np.array(out)


@pytest.mark.parametrize("model", ["examples/forced-steering.toml", "examples/manchester.toml",
                                   "tests/data/coach-series-dampers.toml"])
def test_the_stacked_route_of_small_models_is_exact_to_rounding(model):
    """``frf --points 200`` on these three models took the Schur route (forced-steering,
    coach) or the banded LU (Manchester) before the route counted the SciPy import; it
    takes the stacked solve now.  Against a 30-digit solve of the same equations at 6 of
    its frequencies: the stacked and banded LUs to 5e-14 of the largest amplitude
    (1.3e-14 and 1.5e-14 achieved), the Schur form of the state matrix to 3e-9
    (1.1e-9 achieved): the old and new routes agree to the Schur route's error."""
    from express.numeric.statespace import load_vehicle

    vehicle = load_vehicle(model)
    frequencies = np.geomspace(0.1, 20.0, 200)[::40]
    columns = [vehicle.inputs.index(name) for name in vehicle.layout.irregularity]
    delays = irregularity_delays(vehicle, vehicle.speed)
    amplitudes = 1e-3 * np.exp(-2j * np.pi * frequencies[:, None] * delays[None, :])
    exact = _exact(vehicle, frequencies, columns, amplitudes)
    scale = np.abs(exact).max(axis=1)
    assert choose_route(vehicle.n, vehicle.form.size, 200, band_layout(vehicle.mass, vehicle.damping(vehicle.speed),
                                                                       vehicle.stiffness)) == "stacked"
    for route, tolerance in (("stacked", 5e-14), ("banded", 5e-14), ("schur", 3e-9)):
        got = steady_response(vehicle, frequencies, vehicle.speed, columns, amplitudes[:, :, None], route=route)[..., 0]
        assert np.all(np.abs(got - exact).max(axis=1) <= tolerance * scale), route


@pytest.mark.parametrize("name", ["conventional.toml", "manchester.toml", "forced-steering.toml"])
def test_the_stability_check_by_blocks_is_the_dense_verdict(name):
    """``require_stable`` takes the eigenvalues block by diagonal block (the conventional
    car 34 + 6 states, Manchester 42 + 20, forced-steering one block): at speeds on
    both sides of the critical speed it refuses exactly where a dense ``eigvals`` of
    ``A`` finds an unstable eigenvalue."""
    from express.analysis.frequency.frequency import require_stable
    from express.analysis.modes.modes import stability_threshold

    vehicle = vehicle_model(load_model(f"examples/{name}"))
    verdicts = []
    for speed in np.geomspace(20.0, 250.0, 12):
        dense = np.linalg.eigvals(vehicle.state_matrix(speed))
        unstable = bool(dense.real.max() > stability_threshold(dense))
        try:
            require_stable(vehicle, speed)
            refused = False
        except AnalysisError:
            refused = True
        verdicts.append(unstable)
        assert refused == unstable, speed
    assert verdicts[0] is False and verdicts[-1] is True  # both sides


@pytest.mark.parametrize("name, largest", [("manchester.toml", 42), ("forced-steering.toml", 48)])
def test_the_stability_check_asks_for_the_threads_of_its_largest_block(monkeypatch, name, largest):
    """``require_stable`` runs its eigenvalues inside ``large_problem_threads`` of the
    largest diagonal block (the Manchester car's 42 of 62 states): threads may rise
    (``EXPRESS_BLAS_THREADS_LARGE``) only for a block of 1000 states or more (a long
    train), never for a car."""
    import contextlib

    from express.analysis.frequency import frequency

    asked = []

    @contextlib.contextmanager
    def recording(states):
        asked.append(states)
        yield

    monkeypatch.setattr(frequency, "large_problem_threads", recording)
    frequency.require_stable(vehicle_model(load_model(f"examples/{name}")), 30.0)
    assert asked == [largest]
