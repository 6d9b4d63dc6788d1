"""Eigenvalues by diagonal blocks (:class:`express.numeric.compiled.EigenBlocks`, issue 16).

The splitting is exact: the strongly connected components of the state matrix's
sparsity pattern permute it into block-triangular form (checked on the pattern of every
bundled model), and the eigenvalues block by block are numpy's of the whole matrix to
rounding (matched one to one) on every bundled TOML model at speeds from 1 to 150 m/s.
A model with one block goes through exactly the former stacked call (bitwise equal).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment
from scipy.sparse import csr_array
from scipy.sparse.csgraph import connected_components

from express.analysis.stability.stability import max_real_part, root_locus
from express.numeric.compiled import EigenBlocks, diagonal_blocks, strong_components
from express.numeric.statespace import load_vehicle

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: Every bundled model with values, and the sizes of its diagonal blocks.
MODELS = {
    "conventional.toml": [34, 6],
    "conventional-yaw-bush.toml": [44],
    "forced-steering.toml": [48],
    "forced-steering-yaw-bush.toml": [52],
    "manchester.toml": [42, 20],
    "manchester-flexible.toml": [44, 24],  # torsion joins the lateral block, bending the vertical
    "manchester-s1002.toml": [42, 20],
    "manchester-rails.toml": [42, 20],
    "y25-wagon.toml": [42, 20],
    "coach-blowoff.toml": [66],  # the inclined lateral damper joins lateral and vertical; 4 reservoir strokes
}
SPEEDS = np.array([1.0, 10.0, 30.0, 83.3, 150.0])


@pytest.fixture(scope="module")
def vehicles():
    return {name: load_vehicle(EXAMPLES / name) for name in MODELS}


def test_every_bundled_model_with_values_is_listed():
    bundled = {p.name for p in EXAMPLES.glob("*.toml")} - {"vehicle_parameters.toml"}
    assert bundled == set(MODELS)


@pytest.mark.parametrize("seed", range(6))
def test_strong_components_match_scipy_and_come_in_reverse_topological_order(seed):
    rng = np.random.default_rng(seed)
    for _ in range(50):
        size = int(rng.integers(1, 80))
        pattern = rng.random((size, size)) < rng.random() * 0.08
        labels = np.array(strong_components([np.flatnonzero(row).tolist() for row in pattern]))
        count, reference = connected_components(csr_array(pattern), directed=True, connection="strong")
        assert labels.max() + 1 == count
        assert len(set(zip(labels.tolist(), reference.tolist(), strict=True))) == count  # the same partition
        rows, columns = np.nonzero(pattern)
        assert np.all(labels[rows] >= labels[columns])  # every edge runs to an earlier component


@pytest.mark.slow  # the six models are read and evaluated once (about 5-10 s)
@pytest.mark.parametrize("name", MODELS)
def test_the_blocks_make_the_state_matrix_block_triangular(vehicles, name):
    """The exactness: ordered by component, no entry of A0 or A1 lies above the blocks."""
    form = vehicles[name].form
    pattern = (form.a0 != 0) | (form.a1 != 0)
    labels = np.array(strong_components([np.flatnonzero(row).tolist() for row in pattern]))
    rows, columns = np.nonzero(pattern)
    assert np.all(labels[rows] >= labels[columns])
    assert [block.size for block in diagonal_blocks(form.a0, form.a1)] == MODELS[name]


@pytest.mark.slow  # the six models are read and evaluated once (about 5-10 s)
@pytest.mark.parametrize("name", MODELS)
def test_block_eigenvalues_are_numpys_of_the_whole_matrix(vehicles, name):
    vehicle = vehicles[name]
    values = vehicle.eigen_blocks.eigenvalues(SPEEDS)
    for row, speed in zip(values, SPEEDS, strict=True):
        reference = np.linalg.eigvals(vehicle.state_matrix(speed))
        distance = np.abs(row[:, None] - reference[None, :])
        pairs = linear_sum_assignment(distance)
        assert distance[pairs].max() <= 1e-12 * np.abs(reference).max()
        np.testing.assert_allclose(vehicle.eigenvalues(speed), row, rtol=0, atol=0)
    locus = root_locus(vehicle, SPEEDS)
    order = np.lexsort((-values.imag, -values.real), axis=-1)
    np.testing.assert_array_equal(locus, np.take_along_axis(values, order, axis=-1))
    np.testing.assert_array_equal(max_real_part(vehicle, SPEEDS), values.real.max(axis=1))


@pytest.mark.slow  # the six models are read and evaluated once (about 5-10 s)
def test_one_block_is_the_former_stacked_call_bitwise(vehicles):
    form = vehicles["forced-steering.toml"].form
    former = np.linalg.eigvals(form.a0[None] + form.a1[None] / SPEEDS[:, None, None])
    np.testing.assert_array_equal(EigenBlocks(form.a0, form.a1).eigenvalues(SPEEDS), former)


@pytest.mark.parametrize(
    "a0, expected",
    [
        (np.diag([1.0, 2.0, 3.0]), [[0], [1], [2]]),
        (np.array([[1.0, 1.0], [1.0, 1.0]]), [[0, 1]]),
        (np.array([[0.0, 1.0, 0.0], [2.0, 0.0, 7.0], [0.0, 0.0, 5.0]]), [[0, 1], [2]]),  # upper triangular coupling
        (np.zeros((1, 1)), [[0]]),
    ],
)
def test_diagonal_blocks_of_small_matrices(a0, expected):
    assert [block.tolist() for block in diagonal_blocks(a0, np.zeros_like(a0))] == expected
    values = EigenBlocks(a0, np.zeros_like(a0)).eigenvalues(np.array([2.0]))[0]
    np.testing.assert_allclose(np.sort_complex(values), np.sort_complex(np.linalg.eigvals(a0).astype(complex)))


def test_a_speed_term_joins_blocks():
    """A1 couples what A0 leaves apart: one block (the pattern is the union over speeds)."""
    a0 = np.diag([1.0, 2.0])
    a1 = np.array([[0.0, 1.0], [1.0, 0.0]])
    assert [block.tolist() for block in diagonal_blocks(a0, a1)] == [[0, 1]]
    values = EigenBlocks(a0, a1).eigenvalues(np.array([0.5]))[0]
    np.testing.assert_allclose(np.sort_complex(values), np.sort_complex(np.linalg.eigvals(a0 + a1 / 0.5).astype(complex)))
