"""The sparse route of the time march (``express.analysis.time.sparse_march``).

* The route choice: small or dense models keep the dense route; a 9-car train takes the
  sparse one.
* Its pieces: the balancing is an exact similarity of powers of two; the Taylor degree
  follows Al-Mohy and Higham's table; one step equals the closed-form step (Van Loan's
  block exponential) for a random matrix with a linearly varying forcing.
* Whole runs: the sparse and the dense route agree to rounding on the bundled cars
  (linear and with flange contact and creep saturation, the dead band and the contact
  tables of the S1002 car), on the coach with series dampers (first-order coordinates)
  and on the train; the time step is the same.

Accuracy achieved against the dense route (Fig. 9 curve, 120 km/h, dt = 5 ms):
coordinates q within 2.3e-13 of their largest value (tolerance 1e-12); rates q' within
1.7e-11 (tolerance 5e-11) -- the steering levers' rates are the worst, and the dense
route's own two exact formulas (integration by parts vs Van Loan's block exponential)
differ by 1.3e-11 there; derived outputs within 1.7e-12 of the largest value of their
unit (tolerance 1e-11).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from scipy.linalg import expm

from express.analysis.time.integrator import discretize
from express.analysis.time.simulate import output_unit, simulate
from express.analysis.time.sparse_march import (
    SPARSE_MIN_STATES,
    choose_route,
    sparse_steps,
    taylor_degree,
    taylor_step,
)
from express.base.diagnostics import ArgumentError
from express.io import load_model
from express.numeric.statespace import vehicle_model
from express.rail.track import paper_curve

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def train(tmp_path_factory):
    """A 9-car train of the steered car: 432 states, the smallest train on the sparse route."""
    spec = importlib.util.spec_from_file_location("make_vehicles", ROOT / "examples" / "make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = tmp_path_factory.mktemp("train") / "train9.toml"
    path.write_text(module.vehicle_toml(True, cars=9), encoding="utf-8")
    return vehicle_model(load_model(path))


def _banded(size: int, density_band: int = 3) -> np.ndarray:
    rng = np.random.default_rng(3)
    a = np.zeros((size, size))
    for offset in range(-density_band, density_band + 1):
        a += np.diag(rng.normal(size=size - abs(offset)), offset)
    return a


@pytest.mark.parametrize(("size", "band", "route", "expected"), [
    (60, 3, "auto", "dense"),                      # a car: dense whatever its pattern
    (SPARSE_MIN_STATES - 1, 3, "auto", "dense"),
    (SPARSE_MIN_STATES, 3, "auto", "sparse"),      # 7 of 400 per row: 1.7 %
    (SPARSE_MIN_STATES, 10, "auto", "dense"),      # 21 of 400 per row: too dense
    (60, 3, "sparse", "sparse"),                   # forced
    (SPARSE_MIN_STATES, 3, "dense", "dense"),
])
def test_route_choice(size, band, route, expected):
    assert choose_route(_banded(size, band), route) == expected


def test_unknown_route_is_refused():
    with pytest.raises(ArgumentError, match="route must be"):
        choose_route(np.eye(3), "banded")


@pytest.mark.parametrize(("norm", "expected"), [
    (0.0, (3, 1)),        # the forcing's hold needs three terms even for A = 0
    (1e-6, (3, 1)),
    (5.74, (40, 1)),      # the balanced 20-car train
    (8.05, (50, 1)),
    (20.0, (45, 3)),      # beyond theta_55 = 9.9: three sub-steps (20 / 3 <= theta_45 = 7.2)
])
def test_taylor_degree(norm, expected):
    assert taylor_degree(norm) == expected


def test_balancing_is_an_exact_similarity_that_lowers_the_norm():
    a = _banded(50)
    grading = 2.0 ** (3 * np.arange(50))  # neighbours scaled by up to 2^9 against each other
    a = a * grading[:, None] / grading[None, :]
    steps = sparse_steps(a, 0.01, np.zeros((2, 50)), np.zeros((50, 1)))
    balanced = np.zeros_like(a)
    rows = np.repeat(np.arange(50), np.diff(steps.indptr))
    balanced[rows, steps.indices] = steps.data
    assert np.all(np.log2(steps.scale) == np.round(np.log2(steps.scale)))  # powers of two
    np.testing.assert_array_equal(balanced, (a * 0.01) / steps.scale[:, None] * steps.scale[None, :])
    assert np.abs(balanced).sum(axis=0).max() < 0.1 * np.abs(a * 0.01).sum(axis=0).max()  # achieved 0.049


@pytest.mark.parametrize("dt", [1e-3, 0.05])
def test_one_step_equals_the_closed_form(dt):
    size = 40
    rng = np.random.default_rng(11)
    a = _banded(size) * 40.0 - 30.0 * np.eye(size)  # stiff: |lambda dt| up to ~15 at dt = 0.05
    x, w0, w1 = rng.normal(size=(3, size))
    steps = sparse_steps(a, dt, np.zeros((2, size)), np.zeros((size, 1)))
    out, work = np.zeros(size), np.zeros((4, size))
    taylor_step(steps, x, w0, w1, out, *work)
    phi, gamma0, gamma1 = discretize(a, dt)
    expected = phi @ x + gamma0 @ w0 + gamma1 @ w1
    assert np.abs(out - expected).max() <= 1e-13 * np.abs(expected).max()
    block = np.zeros((size + 2, size + 2))  # the augmented matrix, for the record
    block[:size, :size], block[:size, size], block[:size, size + 1] = a * dt, w1 * dt, w0 * dt
    block[size, size + 1] = 1.0
    assert np.abs(expm(block)[:size] @ np.r_[x, 0.0, 1.0] - out).max() <= 1e-13 * np.abs(expected).max()


def _agreement(dense, sparse):
    """The largest differences of q, q' and the outputs, relative to the largest value of
    their kind (the outputs of one unit together: a wheelset not yet in the curve has
    forces of a few mN beside the leading one's kN)."""
    q = np.abs(sparse.q - dense.q).max() / np.abs(dense.q).max()
    rates = np.abs(sparse.q_dot - dense.q_dot).max() / np.abs(dense.q_dot).max()
    scale: dict[str, float] = {}
    for name, values in dense.outputs.items():
        scale[output_unit(name)] = max(scale.get(output_unit(name), 0.0), float(np.abs(values).max()))
    outputs = max(np.abs(sparse.outputs[name] - values).max() / max(scale[output_unit(name)], 1e-300)
                  for name, values in dense.outputs.items())
    return q, rates, outputs


@pytest.mark.parametrize(("model", "nonlinear", "speed"), [
    ("examples/forced-steering.toml", True, None),
    ("examples/forced-steering.toml", False, None),
    ("examples/conventional.toml", True, None),
    ("tests/data/coach-series-dampers.toml", True, None),
    ("examples/manchester-s1002.toml", True, 80 / 3.6),  # the contact from the profiles' tables
])
def test_sparse_route_agrees_with_the_dense_route(model, nonlinear, speed):
    vehicle = vehicle_model(load_model(ROOT / model))
    runs = [simulate(vehicle, paper_curve(), speed=speed, flange=nonlinear, saturation=nonlinear, progress=False,
                     route=route) for route in ("dense", "sparse")]
    assert runs[0].options["dt"] == runs[1].options["dt"] == 0.005 and "route" not in runs[0].options
    assert runs[1].options == {**runs[0].options, "route": "sparse"}
    np.testing.assert_array_equal(runs[0].time, runs[1].time)  # the same steps
    q, rates, outputs = _agreement(*runs)
    # on the S1002 car with the table law q within 2.6e-12, the rates 4.8e-10 and the
    # outputs 3e-7 of the largest (1e-12, 5e-11, 1e-11 with FASTSIM): the routes' rounding
    # moves a nearly pure-spin contact of the straight track across the table's spin axis,
    # where its nodes agree to 0.3 % of the spin's force (docs/contact.md, the limits of the
    # table law)
    assert q <= 5e-12 and rates <= 1e-9 and outputs <= 1e-6, (q, rates, outputs)


def test_a_train_takes_the_sparse_route_and_agrees(train):
    assert train.form.size >= SPARSE_MIN_STATES
    auto = simulate(train, paper_curve(), end=120.0, progress=False)
    assert auto.options["route"] == "sparse"
    dense = simulate(train, paper_curve(), end=120.0, progress=False, route="dense")
    assert "route" not in dense.options
    q, rates, outputs = _agreement(dense, auto)
    # on the S1002 car with the table law q within 2.6e-12, the rates 4.8e-10 and the
    # outputs 3e-7 of the largest (1e-12, 5e-11, 1e-11 with FASTSIM): the routes' rounding
    # moves a nearly pure-spin contact of the straight track across the table's spin axis,
    # where its nodes agree to 0.3 % of the spin's force (docs/contact.md, the limits of the
    # table law)
    assert q <= 5e-12 and rates <= 1e-9 and outputs <= 1e-6, (q, rates, outputs)
    assert np.abs(auto.outputs["Y1"]).max() > 1e3  # a real run: the leading wheelset is steered by the curve


def test_sparse_route_is_deterministic(train):
    first, second = (simulate(train, paper_curve(), end=60.0, progress=False) for _ in range(2))
    np.testing.assert_array_equal(first.q, second.q)
    np.testing.assert_array_equal(first.q_dot, second.q_dot)


@pytest.mark.parametrize("which", ["forced-steering", pytest.param("train9", marks=pytest.mark.slow)])
def test_cold_warm_and_no_cache_runs_write_the_same_file(which, tmp_path, monkeypatch):
    """``express simulate`` with a cold cache, a warm one (a vehicle read back without its
    model: the body roles from its facts) and --no-cache: the same bytes, on the dense
    route (a car) and on the sparse one (the 9-car train)."""
    from express.cli import main
    from express.numeric import statespace

    if which == "train9":
        spec = importlib.util.spec_from_file_location("make_vehicles", ROOT / "examples" / "make_vehicles.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        model = tmp_path / "train9.toml"
        model.write_text(module.vehicle_toml(True, cars=9), encoding="utf-8")
    else:
        model = ROOT / "examples" / f"{which}.toml"
    monkeypatch.setenv("EXPRESS_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.delenv("EXPRESS_NO_CACHE", raising=False)
    written = []
    for number, extra in enumerate(([], [], ["--no-cache"])):
        statespace._GENERATED.clear()
        out = tmp_path / f"run{number}.csv"
        assert main(["simulate", str(model), "--linear", "-o", str(out), "--json", *extra]) == 0
        written.append(out.read_bytes())
    assert written[0] == written[1] == written[2]


def test_the_taylor_bounds_are_scipys_table():
    """The θ_m table of the sparse march is a copy (issue 35 item 7: SciPy keeps it in a
    private module, ``scipy.sparse.linalg._expm_multiply._theta``, not an API to build on):
    it must stay SciPy's, value for value, and the SciPy this project pins gives it."""
    from scipy.sparse.linalg import _expm_multiply

    from express.analysis.time import sparse_march

    assert sparse_march._THETA == _expm_multiply._theta
