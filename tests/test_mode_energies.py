"""express.analysis.modes.mode_energies: the participation and energies of many modes at once,
and modes_of built on them (issue 24: naming the modes of long trains)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from express.analysis.modes.mode_energies import (
    DofGroups,
    group_sums,
    kinetic_shares,
    participation,
    running_sum,
    series_ranking,
    series_shares,
    top_columns,
)
from express.analysis.modes.mode_names import mode_energy
from express.analysis.modes import modes as modes_module
from express.analysis.modes.modes import modes_of
from express.io import load_model
from express.numeric.statespace import vehicle_model

ROOT = Path(__file__).resolve().parents[1]
RNG = np.random.default_rng(24)


@pytest.mark.parametrize("columns", [1, 2, 7])
@pytest.mark.parametrize("rows", [0, 1, 9, 100, 2400])
def test_running_sums_add_the_rows_one_after_the_other(rows, columns):
    """Bit for bit Python's running sum, also for a single column (NumPy would add it pairwise)."""
    values = RNG.random((rows, columns)) * 10.0 ** RNG.integers(-8, 8, size=(rows, 1))
    expected = [sum(float(v) for v in values[:, column]) for column in range(columns)]
    assert running_sum(values).tolist() == expected


@pytest.mark.parametrize("rows, groups", [(1, 1), (7, 3), (60, 11), (300, 40), (400, 2)])
def test_group_sums_add_in_row_order_as_running_sums(rows, groups):
    """Bit for bit the running sum ``((0 + a) + b) + c`` of one mode's DOFs, for every column."""
    values = RNG.random((rows, 5)) * 10.0 ** RNG.integers(-8, 8, size=(rows, 1))
    labels = RNG.integers(0, groups, size=rows)  # many small groups, or a few large ones
    expected = np.zeros((groups, 5))
    for column in range(5):
        for row in range(rows):
            expected[labels[row], column] = float(expected[labels[row], column]) + float(values[row, column])
    assert np.array_equal(group_sums(values, labels, groups), expected)


@pytest.mark.parametrize("rows", [3, 16, 17, 200])
@pytest.mark.parametrize("count", [1, 4])
def test_top_columns_are_the_stable_argsort_prefix_also_with_ties(rows, count):
    values = np.round(RNG.random((50, rows)), 1)  # many ties, also at the threshold
    values[:5] = 0.0  # whole rows tied
    values[10, rows // 2] = np.nan
    expected = np.argsort(-values, axis=1, kind="stable")[:, :count]
    assert np.array_equal(top_columns(values, count), expected)


def test_top_columns_of_distinct_values_pick_the_largest_first():
    values = RNG.permutation(1000).reshape(10, 100).astype(float)
    top = top_columns(values, 4)
    assert np.array_equal(np.take_along_axis(values, top, axis=1), -np.sort(-values, axis=1)[:, :4])


def _car(name):
    return vehicle_model(load_model(ROOT / name))


@pytest.fixture(scope="module")
def coach():
    """A vehicle with series (Maxwell) dampers: strokes without mass."""
    return _car("tests/data/coach-series-dampers.toml")


def _eig(vehicle):
    values, vectors = np.linalg.eig(vehicle.state_matrix(vehicle.speed))
    return values, vectors


def test_participation_sums_to_one_and_strokes_take_none(coach):
    _, vectors = _eig(coach)
    groups = DofGroups.of(coach.dofs)
    shares = participation(vectors[: coach.n], groups, np.ones(coach.n))
    assert groups.strokes.size > 0
    np.testing.assert_allclose(shares.sum(axis=1), 1.0, rtol=1e-14)
    assert not shares[:, groups.strokes].any()


def test_the_arrays_hold_the_single_mode_energies(coach):
    """Every column of the arrays is the :func:`mode_energy` of its mode alone."""
    values, vectors = _eig(coach)
    groups = DofGroups.of(coach.dofs)
    damping = coach.damping(coach.speed)
    phi = vectors[: coach.n]
    kinetic = kinetic_shares(phi, groups, coach.mass)
    series = series_shares(phi, groups, damping)
    for k in range(0, values.size, 7):
        single = mode_energy(phi[:, k], values[k], coach.dofs, coach.mass, damping, coach.stiffness)
        assert list(single.kinetic.values()) == kinetic[:, k].tolist()
        assert single.series == series_ranking(series[:, k], groups.elements)
        assert 0 <= sum(share for _, share in single.series) <= 1 + 1e-12  # the rest: the other dampers


@pytest.mark.parametrize("name", ["tests/data/coach-series-dampers.toml", "examples/forced-steering.toml"])
def test_modes_do_not_depend_on_how_many_are_described_together(monkeypatch, name):
    vehicle = _car(name)
    values, vectors = _eig(vehicle)
    together = modes_of(vehicle, values, vectors)
    monkeypatch.setattr(modes_module, "_CHUNK", 1)
    one_by_one = modes_of(vehicle, values, vectors)
    assert together == one_by_one
    assert [m.body_shares for m in together] == [m.body_shares for m in one_by_one]
    assert modes_of(vehicle, values, vectors, limit=3) == together[:3]


def test_body_shares_are_the_sums_of_the_dofs_shares(coach):
    values, vectors = _eig(coach)
    for mode in modes_of(coach, values, vectors):
        shares = dict(mode.body_shares)
        assert [s for _, s in mode.body_shares] == sorted(shares.values(), reverse=True)
        for dof, share in mode.dominant:
            assert shares[dof.partition(".")[0]] >= share
        assert sum(shares.values()) == pytest.approx(1.0, rel=1e-14)


@pytest.mark.parametrize("n", [5, 30, 120])
@pytest.mark.parametrize("kind", ["real", "complex"])
def test_the_numpy_row_product_is_scipys_bit_for_bit(monkeypatch, n, kind):
    """Below ``SCIPY_FROM`` a non-diagonal matrix (a damping with series elements) is
    multiplied without importing SciPy: the same sums in the same order as SciPy's sparse
    product, so a mode's shares do not depend on the model's size class."""
    from express.analysis.modes import mode_energies

    rng = np.random.default_rng(n)
    matrix = np.diag(rng.normal(size=n))
    for k in (1, 2, 3):
        matrix += np.diag(rng.normal(size=n - k) * (rng.random(n - k) < 0.5), k)
    matrix[-1, 0] = 1.5
    vectors = rng.normal(size=(n, 6)) + (1j * rng.normal(size=(n, 6)) if kind == "complex" else 0)
    monkeypatch.setattr(mode_energies, "SCIPY_FROM", 10**9)
    own = mode_energies.RowProduct(matrix)(vectors)
    monkeypatch.setattr(mode_energies, "SCIPY_FROM", 0)
    assert np.array_equal(own, mode_energies.RowProduct(matrix)(vectors))
    scale = float(np.max(np.abs(matrix @ vectors)))  # achieved 1.1e-16 of it, bound 2e-15
    assert float(np.max(np.abs(own - matrix @ vectors))) <= 2e-15 * scale
