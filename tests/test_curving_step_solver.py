"""The sparse solve of the pseudo-transient steps (express.analysis.curving.step_solver).

Against the dense solve: the same step to rounding at every step size (achieved 3e-15
relative on the random chain, bound 2e-14); a singular
system raises as the dense solve does; and a long train's steady curving, sparse,
against the same solver forced dense (achieved: the states agree to 5e-16 of the largest
coordinate, bound 1e-14)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest
from scipy import sparse

from express.analysis.curving import step_solver
from express.analysis.curving.step_solver import StepSolver

ROOT = Path(__file__).resolve().parents[1]


def _chain(n: int, rng: np.random.Generator) -> np.ndarray:
    """A random J coupling each state with its neighbours within 3, in a shuffled order."""
    j = np.zeros((n, n))
    for k in range(-3, 4):
        j += np.diag(rng.normal(size=n - abs(k)), k)
    j -= 10.0 * np.eye(n)
    order = rng.permutation(n)
    return j[np.ix_(order, order)]


@pytest.mark.parametrize("step", [1e-3, 1.0, 1e6])
def test_sparse_steps_are_the_dense_ones(step):
    rng = np.random.default_rng(7)
    j, f = _chain(60, rng), rng.normal(size=60)
    sparse_route, dense = StepSolver(60, sparse_from=10), StepSolver(60, sparse_from=1000)
    assert sparse_route.sparse and not dense.sparse
    np.testing.assert_allclose(sparse_route(step, sparse.csr_matrix(j), f), dense(step, j, f), rtol=2e-14, atol=1e-16)
    np.testing.assert_allclose(sparse_route.solve(j, f), np.linalg.solve(j, f), rtol=2e-14, atol=1e-16)


def test_a_singular_system_raises_as_the_dense_solve_does():
    with pytest.raises(np.linalg.LinAlgError):
        StepSolver(12, sparse_from=1).solve(sparse.csr_matrix((12, 12)), np.ones(12))
    with pytest.raises(np.linalg.LinAlgError):
        StepSolver(12).solve(np.zeros((12, 12)), np.ones(12))


@pytest.mark.slow
def test_a_trains_steady_curving_sparse_is_the_dense_one(tmp_path, monkeypatch):
    from express.analysis.curving.steady import SteadyCurve, steady_curving
    from express.numeric.statespace import load_vehicle

    spec = importlib.util.spec_from_file_location("make_vehicles", ROOT / "examples" / "make_vehicles.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    path = tmp_path / "train.toml"
    path.write_text(module.vehicle_toml(True, cars=10), encoding="utf-8")  # 240 DOFs, 480 states: sparse
    train = load_vehicle(path)
    curve = SteadyCurve(600.0, 0.1, "right")
    (sparse_route,) = steady_curving(train, curve)
    monkeypatch.setattr(step_solver, "SPARSE_FROM", 10**9)
    (dense,) = steady_curving(train, curve)
    scale = float(np.max(np.abs(dense.q)))
    print("sparse against dense:", float(np.max(np.abs(sparse_route.q - dense.q))) / scale)
    assert float(np.max(np.abs(sparse_route.q - dense.q))) <= 1e-14 * scale
    assert sparse_route.residual < 1e-6 and dense.residual < 1e-6
