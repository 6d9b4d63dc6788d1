"""``M^-1`` of a large mass matrix, block by block.

A vehicle's mass matrix couples only the coordinates of one body (and of the bodies a
pinned joint eliminates into it): after grouping the coordinates that ``M`` couples,
it is block diagonal with small blocks.  For a 100-car train (2400 coordinates) the
dense Cholesky test, inverse and products ``M^-1 K``, ``M^-1 C``, ``M^-1 P`` of the
state-space form took 15 s; block by block they take a fraction of a second.

:func:`mass_inverse` returns an inverse that multiplies (:meth:`MassInverse.times`):
dense below :data:`BLOCK_SIZE` coordinates (the operations used before, so the numbers
of the vehicles and small trains stay the same bits), by blocks above it.

Examples
--------
>>> import numpy as np
>>> inverse = mass_inverse(np.diag([2.0, 4.0]))
>>> inverse.times(np.ones((2, 1))).ravel().tolist()
[0.5, 0.25]
"""

from __future__ import annotations

import numpy as np

__all__ = ["BLOCK_SIZE", "MassInverse", "mass_inverse"]

#: Number of massive coordinates from which ``M^-1`` is formed block by block.
BLOCK_SIZE = 400


class MassInverse:
    """``M^-1`` of a symmetric positive definite ``M``, kept dense or as diagonal blocks.

    Parameters
    ----------
    blocks : list of (numpy.ndarray of int, numpy.ndarray)
        The coordinates of every block and its inverse.
    n : int
        Size of ``M``.
    """

    def __init__(self, blocks: list[tuple[np.ndarray, np.ndarray]], n: int):
        self.blocks, self.n = blocks, n

    def dense(self) -> np.ndarray:
        """``M^-1``, shape (n, n)."""
        if len(self.blocks) == 1 and self.blocks[0][0].size == self.n:
            return self.blocks[0][1]
        inverse = np.zeros((self.n, self.n))
        for index, block in self.blocks:
            inverse[np.ix_(index, index)] = block
        return inverse

    def times(self, matrix: np.ndarray) -> np.ndarray:
        """``M^-1 @ matrix`` (``matrix`` of shape (n, k))."""
        if len(self.blocks) == 1 and self.blocks[0][0].size == self.n:
            return self.blocks[0][1] @ matrix
        result = np.zeros((self.n, matrix.shape[1]))
        for index, block in self.blocks:
            result[index] = block @ matrix[index]
        return result


def mass_inverse(mass: np.ndarray) -> MassInverse:
    """``M^-1`` of a symmetric ``mass`` (n, n): dense below :data:`BLOCK_SIZE`, else by the
    diagonal blocks of its coupled coordinates.

    Raises
    ------
    numpy.linalg.LinAlgError
        When ``mass`` (a block of it) is not positive definite.
    """
    n = mass.shape[0]
    if n < BLOCK_SIZE:
        np.linalg.cholesky(mass)
        return MassInverse([(np.arange(n), np.linalg.inv(mass))], n)
    blocks = []
    for index in coupled_groups(mass != 0.0):
        block = mass[np.ix_(index, index)]
        np.linalg.cholesky(block)
        blocks.append((index, np.linalg.inv(block)))
    return MassInverse(blocks, n)


def coupled_groups(pattern: np.ndarray) -> list[np.ndarray]:
    """The groups of indices that a (symmetric) non-zero ``pattern`` couples, each
    ascending, ordered by their first index (connected components, union-find)."""
    n = pattern.shape[0]
    parent = list(range(n))

    def root(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    rows, columns = np.nonzero(pattern | pattern.T)
    for i, j in zip(rows.tolist(), columns.tolist(), strict=True):
        a, b = root(i), root(j)
        if a != b:
            parent[max(a, b)] = min(a, b)
    groups: dict[int, list[int]] = {}
    for i in range(n):
        groups.setdefault(root(i), []).append(i)
    return [np.array(members, dtype=np.intp) for members in groups.values()]
