"""express.assembly.mass_blocks: M^-1 block by block (a long train's state form)."""

from __future__ import annotations

import numpy as np
import pytest

from express.assembly.mass_blocks import BLOCK_SIZE, coupled_groups, mass_inverse


def _block_mass(sizes: list[int], seed: int = 1) -> np.ndarray:
    """A symmetric positive definite M of diagonal blocks of ``sizes``, its coordinates shuffled."""
    rng = np.random.default_rng(seed)
    n = sum(sizes)
    mass = np.zeros((n, n))
    start = 0
    for size in sizes:
        a = rng.normal(size=(size, size))
        mass[start:start + size, start:start + size] = a @ a.T + size * np.eye(size)
        start += size
    order = rng.permutation(n)
    return mass[np.ix_(order, order)]


def test_coupled_groups_are_the_connected_components():
    pattern = np.zeros((6, 6), dtype=bool)
    for i, j in [(0, 3), (3, 5), (1, 4)]:
        pattern[i, j] = True  # one side only: the pattern is made symmetric
    np.fill_diagonal(pattern, True)
    assert [g.tolist() for g in coupled_groups(pattern)] == [[0, 3, 5], [1, 4], [2]]


def test_by_blocks_is_the_inverse():
    """Above BLOCK_SIZE coordinates the inverse is formed block by block: it agrees with
    the dense inverse to rounding (measured 6e-17 of the largest entry, asserted 1e-15)."""
    sizes = [1, 6, 3, 1, 12] * (BLOCK_SIZE // 20) + [6]
    mass = _block_mass(sizes)
    inverse = mass_inverse(mass)
    assert len(inverse.blocks) == len(sizes)
    dense = np.linalg.inv(mass)
    rhs = np.random.default_rng(2).normal(size=(mass.shape[0], 7))
    scale = np.abs(dense).max()
    assert np.abs(inverse.dense() - dense).max() <= 1e-15 * scale
    assert np.abs(inverse.times(rhs) - dense @ rhs).max() <= 1e-15 * scale * np.abs(rhs).max()
    assert np.allclose(mass @ inverse.dense(), np.eye(mass.shape[0]), atol=1e-12)


def test_small_matrices_keep_the_dense_operations():
    """Below BLOCK_SIZE: numpy's inverse and product themselves (the same bits as before)."""
    mass = _block_mass([3, 2, 1])
    rhs = np.arange(12.0).reshape(6, 2)
    inverse = mass_inverse(mass)
    assert np.array_equal(inverse.dense(), np.linalg.inv(mass))
    assert np.array_equal(inverse.times(rhs), np.linalg.inv(mass) @ rhs)


@pytest.mark.parametrize("sizes", [[2, 1], [3] * (BLOCK_SIZE // 3 + 1)])
def test_a_block_not_positive_definite_is_refused(sizes):
    mass = _block_mass(sizes)
    mass[0, 0] = -1.0
    with pytest.raises(np.linalg.LinAlgError):
        mass_inverse(mass)
