"""express.numeric.compiled: matrices compiled once per model, against SymPy's own evaluation."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from express.assembly.equations import EquationsOfMotion
from express.io import load_model
from express.model.parameters import expression_value
from express.numeric.compiled import CompiledExpressions, compile_matrices
from express.numeric.statespace import vehicle_model
from express.rail.build import generate_vehicle

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def _train(tmp_path: Path, cars: int):
    spec = importlib.util.spec_from_file_location("make_vehicles", EXAMPLES / "make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = tmp_path / f"train{cars}.toml"
    path.write_text(module.vehicle_toml(True, cars=cars), encoding="utf-8")
    return load_model(path)


def _sympy_values(equations: EquationsOfMotion, values: dict[str, float]) -> dict[str, np.ndarray]:
    """The reference: every matrix by SymPy substitution of exact values."""
    symbols = {sp.Symbol(name): sp.Float(value, 30) for name, value in values.items()}
    return {key: np.array(matrix.xreplace(symbols).evalf(30), dtype=float) for key, matrix in equations.matrices.items()}


def _random_values(equations: EquationsOfMotion, seed: int) -> dict[str, float]:
    """Every parameter at its own value times a random factor 0.5..2."""
    rng = np.random.default_rng(seed)
    return {name: float(equations.values.get(name, 1.0) or 1.0) * rng.uniform(0.5, 2.0) for name in equations.parameters}


@pytest.mark.parametrize(
    "example", ["forced-steering.toml", "conventional.toml", "forced-steering-yaw-bush.toml", "lever.exp"]
)
def test_compiled_matrices_equal_sympy_substitution(example):
    equations = generate_vehicle(load_model(EXAMPLES / example)).equations
    compiled = compile_matrices(equations)
    for seed in (1, 2):
        values = _random_values(equations, seed)
        got = compiled(compiled.vector(values))
        expected = _sympy_values(equations, values)
        assert set(got) == set(expected)
        for key in expected:
            scale = max(1.0, np.abs(expected[key]).max(initial=0.0))
            assert got[key].shape == expected[key].shape
            assert np.abs(got[key] - expected[key]).max(initial=0.0) <= 1e-13 * scale, key
            assert np.array_equal(got[key] != 0, expected[key] != 0), key  # the same non-zeros


def test_a_train_compiles_its_shared_entries_once(tmp_path):
    """The cars of a train share their entries: the distinct entries do not grow with
    the number of cars, while the non-zeros do; the values still match SymPy."""
    counts = {}
    for cars in (1, 3):
        equations = generate_vehicle(_train(tmp_path, cars)).equations
        compiled = compile_matrices(equations, speed="v")
        nonzeros = sum(len(matrix.todok()) for matrix in equations.matrices.values())
        counts[cars] = (compiled.distinct_entries, nonzeros)
    assert counts[3][1] > 2.5 * counts[1][1]
    assert counts[3][0] < 1.3 * counts[1][0]
    values = _random_values(equations, 3)
    got = compiled(compiled.vector(values))
    expected = _sympy_values(equations, values)
    for key in expected:
        assert np.allclose(got[key], expected[key], rtol=1e-13, atol=1e-13 * np.abs(expected[key]).max(initial=1.0))


@pytest.mark.parametrize("speed", [3.7, 33.3, 140.0])
def test_speed_split_gives_the_matrices_at_any_speed(speed):
    equations = generate_vehicle(load_model(EXAMPLES / "forced-steering.toml")).equations
    compiled = compile_matrices(equations, speed="v")
    values = dict(equations.values)
    split = compiled.speed_split(compiled.vector(values))
    direct = compiled(compiled.vector({**values, "v": speed}))
    assert np.allclose(split.matrices["C"] + split.damping_creep / speed, direct["C"], rtol=1e-12, atol=1e-6)
    assert np.allclose(split.matrices["P"] + split.forcing_speed2 * speed**2, direct["P"], rtol=1e-12, atol=1e-9)
    for key in ("M", "K", "Pd"):
        assert np.array_equal(split.matrices[key], direct[key])
    assert split.damping_creep.any() and split.forcing_speed2.any()


def _equations(**matrices) -> EquationsOfMotion:
    symbols = set().union(*(sp.ImmutableMatrix(m).free_symbols for m in matrices.values()))
    return EquationsOfMotion(
        name="t", dofs=("a", "b"), eliminated=(), inputs=("u",),
        matrices={key: sp.ImmutableMatrix(value) for key, value in matrices.items()},
        parameters=tuple(sorted(s.name for s in symbols)),
    )


m, c, k, v, f = sp.symbols("m c k v f")
GOOD = {"M": [[m, 0], [0, m]], "C": [[c + f / v, 0], [0, c]], "K": [[k, -k], [-k, k]],
        "P": [[m * v**2], [f]], "Pd": [[c], [0]]}


@pytest.mark.parametrize(
    "key, entry, message",
    [
        ("K", k * v, "enters the matrices other than"),
        ("M", m * v, "enters the matrices other than"),
        ("C", c / v**2, "enters the matrices other than"),
        ("P", m * v**3, "enters the matrices other than"),
        ("Pd", c * v, "enters the matrices other than"),
        ("C", c / (v - 2), "not finite"),  # a division by zero at one of the split speeds
    ],
)
def test_a_speed_that_enters_otherwise_is_refused(key, entry, message):
    matrices = {name: [list(row) for row in rows] for name, rows in GOOD.items()}
    matrices[key][0][0] = entry
    compiled = compile_matrices(_equations(**matrices), speed="v")
    with pytest.raises(ValueError, match=message):
        compiled.speed_split(compiled.vector({"m": 2.0, "c": 3.0, "k": 5.0, "v": 1.0, "f": 7.0}))


def test_a_good_speed_structure_is_split_exactly():
    compiled = compile_matrices(_equations(**GOOD), speed="v")
    split = compiled.speed_split(compiled.vector({"m": 2.0, "c": 3.0, "k": 5.0, "v": 99.0, "f": 7.0}))
    assert split.matrices["C"].tolist() == [[3.0, 0.0], [0.0, 3.0]]
    assert split.damping_creep.tolist() == [[7.0, 0.0], [0.0, 0.0]]
    assert split.matrices["P"].tolist() == [[0.0], [7.0]]
    assert split.forcing_speed2.tolist() == [[2.0], [0.0]]


def test_missing_values_and_divisions_by_zero_are_clear_errors():
    compiled = compile_matrices(_equations(M=[[m, 0], [0, m]], C=[[c, 0], [0, 0]], K=[[k / m, 0], [0, k]]))
    with pytest.raises(ValueError, match="no value for parameters c, k"):
        compiled.vector({"m": 1.0})
    with pytest.raises(ValueError, match="not finite"):
        compiled(compiled.vector({"m": 0.0, "c": 1.0, "k": 1.0}))


def test_floats_keep_full_precision():
    """A float in an expression is not rounded to the 15 digits SymPy's printer shows."""
    x = sp.Symbol("x")
    number = 0.12345678901234567
    compiled = CompiledExpressions([sp.Float(number) * x, sp.Float(2 / 3)])
    assert compiled({"x": 1.0}).tolist() == [number, 2 / 3]


def test_rail_numbers_are_the_graph_evaluator_values():
    """Speed, wheelset data and station positions of the compiled path are exactly the
    graph evaluator's (:func:`express.model.parameters.expression_value`)."""
    model = load_model(EXAMPLES / "forced-steering.toml")
    vehicle = vehicle_model(model).with_values({"Gamma": 0.17, "mw": 1500.0})
    values = vehicle.values
    assert vehicle.speed == expression_value(model.rail.speed, values)
    for data, wheelset in zip(vehicle.wheelsets, model.rail.wheelsets, strict=True):
        assert data.station == expression_value(model.body(wheelset.body).position[0], values)
        for key in ("f1", "f2", "conicity", "r0", "b", "flange_clearance", "rail_stiffness", "friction", "wheel_load"):
            assert getattr(data, key) == expression_value(getattr(wheelset, key), values), key
    assert vehicle.wheelsets[0].conicity == 0.17
    assert vehicle.station_positions.tolist() == [expression_value(s.position, values) for s in vehicle.layout.stations]


def test_sparse_evaluation_equals_the_dense_one(tmp_path):
    """``CompiledMatrices.sparse`` holds exactly the dense arrays' non-zeros."""
    equations = generate_vehicle(_train(tmp_path, 2)).equations
    compiled = compile_matrices(equations)
    vector = compiled.vector(_random_values(equations, 5))
    dense, sparse = compiled(vector), compiled.sparse(vector)
    assert set(dense) == set(sparse)
    for key in dense:
        assert sparse[key].shape == dense[key].shape
        assert np.array_equal(sparse[key].toarray(), dense[key]), key
        assert sparse[key].nnz == np.count_nonzero(dense[key])


# every numerical path after the vehicle is built: no symbolic work per point (issue 16)
_PER_POINT = {
    "eigenvalues": lambda car: car.eigenvalues(30.0),
    "root_locus": lambda car: _stability().root_locus(car, np.linspace(5.0, 100.0, 20)),
    "eigen_analysis": lambda car: _stability().eigen_analysis(car, 30.0),
    "critical_speed": lambda car: _stability().critical_speed(car, v_max=150.0),
    "critical_speed_vs_conicity": lambda car: _stability().critical_speed_vs_conicity(car, [0.1, 0.2], v_max=150.0),
    "frequency_response": lambda car: _frequency().frequency_response(car, np.linspace(0.1, 20.0, 200)),
    "with_values": lambda car: car.with_values({"Gamma": 0.2, "mc": 30000.0}),
    "simulate": lambda car: _simulate(car),
}


def _stability():
    from express.analysis.stability import stability

    return stability


def _frequency():
    from express.analysis.frequency import frequency

    return frequency


def _simulate(car):
    from express.analysis.time.simulate import simulate
    from express.rail.track import paper_curve

    return simulate(car, paper_curve(), end=20.0)


@pytest.fixture(scope="module")
def steered_car():
    return vehicle_model(load_model(EXAMPLES / "forced-steering.toml"))


@pytest.mark.parametrize("name", list(_PER_POINT))
def test_no_symbolic_evaluation_per_point(steered_car, monkeypatch, name):
    """Deliver 2: once the vehicle is built, eigen, critical speed (over conicities too),
    frf, simulate and ``with_values`` evaluate compiled functions only: SymPy's
    ``subs``, ``xreplace``, ``evalf`` and ``lambdify`` all raise if called."""
    _PER_POINT[name](steered_car)  # imports and caches outside the watch

    def forbidden(*args, **kwargs):
        raise AssertionError(f"{name}: symbolic evaluation in a numerical path")

    for owner in (sp.Basic, sp.MatrixBase):
        for attribute in ("subs", "xreplace"):
            monkeypatch.setattr(owner, attribute, forbidden)
    for owner in (sp.core.evalf.EvalfMixin, sp.MatrixBase):
        monkeypatch.setattr(owner, "evalf", forbidden)
    monkeypatch.setattr(sp, "lambdify", forbidden)
    monkeypatch.setattr(sys.modules["sympy.utilities.lambdify"], "lambdify", forbidden)
    _PER_POINT[name](steered_car)
