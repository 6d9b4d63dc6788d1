"""Band layouts and banded solves (express.analysis.frequency.banded) against dense algebra."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.analysis.frequency.banded import (
    SCIPY_IMPORT_S,
    band_layout,
    band_storage,
    choose_route,
    route_costs,
    solve_banded_stiffness,
)

ROOT = Path(__file__).resolve().parents[1]


def _banded_random(n: int, lower: int, upper: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, n)) + n * np.eye(n)
    rows, columns = np.indices((n, n))
    a[(rows - columns > lower) | (columns - rows > upper)] = 0.0
    return a


@pytest.mark.parametrize(("n", "lower", "upper"), [(1, 0, 0), (6, 1, 2), (30, 4, 4), (30, 0, 7)])
def test_natural_order_keeps_its_band(n, lower, upper):
    layout = band_layout(_banded_random(n, lower, upper, n))
    assert np.array_equal(layout.order, np.arange(n))
    assert (layout.lower, layout.upper) == (lower, upper)


def test_reverse_cuthill_mckee_recovers_a_scrambled_band():
    """A tridiagonal matrix with its DOFs shuffled has a full band; the reordering finds
    a tridiagonal one again."""
    a = _banded_random(40, 1, 1, 3)
    shuffle = np.random.default_rng(4).permutation(40)
    layout = band_layout(a[np.ix_(shuffle, shuffle)])
    assert layout.lower + layout.upper <= 2
    assert layout.work <= 40 * 1 * 3


def test_storage_is_lapacks():
    a = _banded_random(5, 1, 2, 0)
    layout = band_layout(a)
    storage = band_storage(a, layout)
    assert storage.shape == (2 * 1 + 2 + 1, 5)
    for i in range(5):
        for j in range(5):
            if -1 <= j - i <= 2:
                assert storage[1 + 2 + i - j, j] == a[i, j]
    assert not storage[:1].any()  # the LU's room


@pytest.mark.parametrize("shuffled", [False, True])
def test_banded_solve_equals_the_dense_one(shuffled):
    n = 25
    m, c, k = (_banded_random(n, 3, 2, seed) for seed in (1, 2, 3))
    if shuffled:
        p = np.random.default_rng(5).permutation(n)
        m, c, k = (a[np.ix_(p, p)] for a in (m, c, k))
    layout = band_layout(m, c, k)
    omega = np.array([0.0, 0.7, 13.0])
    rhs = np.random.default_rng(6).normal(size=(3, n, 2)) + 0j
    got = solve_banded_stiffness(m, c, k, omega, rhs, layout)
    for index, w in enumerate(omega):
        expected = np.linalg.solve(-w * w * m + 1j * w * c + k, rhs[index])
        assert np.allclose(got[index], expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max())


def test_a_singular_band_is_a_linalg_error():
    k = np.diag([1.0, 0.0, 1.0])
    with pytest.raises(np.linalg.LinAlgError, match="singular"):
        solve_banded_stiffness(np.zeros((3, 3)), np.zeros((3, 3)), k, np.array([0.0]), np.ones((1, 3, 1)), band_layout(k))


def test_routes_follow_the_cost():
    """The SciPy import (0.25 s) is charged to the banded and Schur routes: a 24-DOF car
    takes NumPy's stacked solve at any count of frequencies ``frf`` allows; a dense
    120-DOF model the Schur form from about 1 100 frequencies on; a 480-DOF train's
    narrow band the banded LU (a Schur form of 960 states costs ~9 s)."""
    wide = band_layout(np.ones((24, 24)))
    assert choose_route(24, 48, 95, wide) == "stacked"
    assert choose_route(24, 48, 100_000, wide) == "stacked"
    dense = band_layout(np.ones((120, 120)))
    assert choose_route(120, 240, 1000, dense) == "stacked"
    assert choose_route(120, 240, 2000, dense) == "schur"
    narrow = band_layout(_banded_random(480, 26, 26, 0))
    assert choose_route(480, 960, 2000, narrow) == "banded"


def test_the_route_does_not_depend_on_what_the_process_imported():
    """The SciPy import is charged whether or not ``scipy.linalg`` is loaded: the route,
    and the last bits of a response, are the same in every process."""
    import sys

    import scipy.linalg  # noqa: F401  (loaded now, whatever ran before)

    assert "scipy.linalg" in sys.modules
    costs = route_costs(24, 48, 200, band_layout(np.ones((24, 24))))
    assert costs["banded"] > SCIPY_IMPORT_S and costs["schur"] > SCIPY_IMPORT_S > costs["stacked"]
    assert choose_route(24, 48, 200, band_layout(np.ones((24, 24)))) == "stacked"


def test_the_reverse_cuthill_mckee_order_is_scipys():
    """The order of express.analysis.frequency.banded.reverse_cuthill_mckee (written here so that a
    command does not import SciPy's sparse package) is SciPy's, step for step: random
    symmetric patterns with and without diagonals, ties included, and a car's M + C + K."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee as scipys

    from express.analysis.frequency.banded import reverse_cuthill_mckee
    from express.numeric.statespace import load_vehicle

    rng = np.random.default_rng(7)
    patterns = []
    for _ in range(400):
        n = int(rng.integers(1, 50))
        pattern = rng.random((n, n)) < rng.uniform(0.02, 0.3)
        if rng.random() < 0.5:
            np.fill_diagonal(pattern, True)
        patterns.append(pattern | pattern.T)
    car = load_vehicle(ROOT / "examples" / "manchester.toml")
    car_pattern = (car.mass != 0) | (car.damping(30.0) != 0) | (car.stiffness != 0)
    patterns.append(car_pattern | car_pattern.T)
    for pattern in patterns:
        expected = np.asarray(scipys(csr_matrix(pattern), symmetric_mode=True))
        assert np.array_equal(reverse_cuthill_mckee(pattern), expected)
