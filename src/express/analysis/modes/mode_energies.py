"""The energy and displacement of many modes at once, summed by body and direction.

:func:`express.analysis.modes.modes.modes_of` describes every mode of a vehicle, thousands for
a long train (100 cars: 2400 DOFs, 2600 modes).  Here the per-DOF quantities of all
modes are arrays over DOFs x modes, and their sums by body, direction or role are
grouped sums over index arrays built once per vehicle (:class:`DofGroups`): a few
array operations instead of Python loops per mode and DOF.

Every grouped sum adds its rows one after the other in DOF order
(:func:`group_sums`), as a running sum over one mode's DOFs would: the shares do not
depend on how many modes are computed together.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from express.assembly.equations import STROKE  # a series element's stroke: <element>.stroke

__all__ = [
    "STROKE",
    "DofGroups",
    "RowProduct",
    "group_sums",
    "kinetic_shares",
    "participation",
    "roll_centres",
    "running_sum",
    "series_ranking",
    "series_shares",
    "top_columns",
]

@dataclass(frozen=True)
class DofGroups:
    """The DOFs of a vehicle as index arrays, for the energies and names of its modes.

    Attributes
    ----------
    dofs : tuple of str
        ``body.direction`` (``element.stroke`` for a series element), length n.
    rows : numpy.ndarray of int, shape (k,)
        The DOFs with mass (all but the strokes), in DOF order.
    bodies : tuple of str
        The bodies of ``rows``, in the order of their first DOF.
    body_of : numpy.ndarray of int, shape (k,)
        Index into :attr:`bodies` of every row's body.
    directions : tuple of str
        Every row's direction (``"y"``, ``"rz"``, ...), length k.
    strokes : numpy.ndarray of int, shape (s,)
        The series elements' strokes.
    elements : tuple of str
        Their elements, length s.
    roll : numpy.ndarray of int, shape (3, r)
        Bodies with a lateral and a roll DOF, in body order: index into :attr:`bodies`,
        DOF index of the roll and of the lateral displacement.

    Examples
    --------
    >>> groups = DofGroups.of(["CB.y", "CB.rx", "W1.y", "damper.stroke"])
    >>> groups.bodies, groups.body_of.tolist(), groups.elements
    (('CB', 'W1'), [0, 0, 1], ('damper',))
    >>> groups.roll.tolist()
    [[0], [1], [0]]
    """

    dofs: tuple[str, ...]
    rows: np.ndarray
    bodies: tuple[str, ...]
    body_of: np.ndarray
    directions: tuple[str, ...]
    strokes: np.ndarray
    elements: tuple[str, ...]
    roll: np.ndarray

    @classmethod
    def of(cls, dofs: Sequence[str]) -> DofGroups:
        """Group the DOF names ``body.direction`` (module docstring)."""
        parts = [dof.partition(".") for dof in dofs]
        rows = [i for i, (_, _, direction) in enumerate(parts) if direction != STROKE]
        strokes = [i for i, (_, _, direction) in enumerate(parts) if direction == STROKE]
        bodies: dict[str, int] = {}
        for i in rows:
            bodies.setdefault(parts[i][0], len(bodies))
        index = {dof: i for i, dof in enumerate(dofs)}
        roll = sorted((bodies[body], i, index[f"{body}.y"]) for i, (body, _, direction) in enumerate(parts)
                      if direction == "rx" and f"{body}.y" in index)
        return cls(
            dofs=tuple(dofs),
            rows=np.array(rows, dtype=np.intp),
            bodies=tuple(bodies),
            body_of=np.array([bodies[parts[i][0]] for i in rows], dtype=np.intp),
            directions=tuple(parts[i][2] for i in rows),
            strokes=np.array(strokes, dtype=np.intp),
            elements=tuple(parts[i][0] for i in strokes),
            roll=np.array(roll, dtype=np.intp).reshape(-1, 3).T,
        )


def running_sum(values: np.ndarray) -> np.ndarray:
    """Column sums of ``values`` (k, m), the rows added one after the other.

    ``np.add.reduce`` over the first axis adds a row at a time to the sums of all
    columns, but a single column pairwise: that one is accumulated
    (``tests/test_mode_energies.py`` checks both against Python's running sums).

    Examples
    --------
    >>> running_sum(np.array([[1e16], [1.0], [-1e16]])).tolist()
    [0.0]
    """
    if values.shape[1] == 1 and values.shape[0]:
        return np.add.accumulate(values, axis=0)[-1]
    return np.add.reduce(values, axis=0)


def group_sums(values: np.ndarray, labels: np.ndarray, count: int) -> np.ndarray:
    """Sums of the rows of ``values`` that share a label, each added in row order.

    Parameters
    ----------
    values : numpy.ndarray, shape (k, m)
    labels : numpy.ndarray of int, shape (k,)
        Group of every row, in ``[0, count)``.
    count : int
        Number of groups.

    Returns
    -------
    numpy.ndarray, shape (count, m)
        Row ``g``: the sum of the rows labelled ``g``, ``((v_a + v_b) + v_c) + ...`` in
        row order (0 for a group without rows).

    Examples
    --------
    >>> group_sums(np.array([[1.0], [2.0], [4.0]]), np.array([1, 0, 1]), 3).ravel().tolist()
    [2.0, 5.0, 0.0]
    """
    out = np.zeros((count, values.shape[1]))
    if labels.size == 0:
        return out
    order = np.argsort(labels, kind="stable")
    ordered = labels[order]
    starts = np.flatnonzero(np.r_[True, ordered[1:] != ordered[:-1]])
    sizes = np.diff(np.r_[starts, labels.size])
    if starts.size <= sizes.max():  # a few large groups: one running sum each
        for start, size in zip(starts.tolist(), sizes.tolist(), strict=True):
            out[ordered[start]] = running_sum(values[order[start : start + size]])
        return out
    position = np.arange(labels.size) - np.repeat(starts, sizes)  # many small ones: the p-th rows together
    for p in range(int(sizes.max())):
        at = position == p
        out[ordered[at]] += values[order[at]]
    return out


def top_columns(values: np.ndarray, count: int) -> np.ndarray:
    """The columns of the ``count`` largest values of every row, largest first, ties in
    column order: the first columns of ``np.argsort(-values, axis=1, kind="stable")``,
    without sorting whole rows.

    Parameters
    ----------
    values : numpy.ndarray, shape (m, k)
    count : int

    Returns
    -------
    numpy.ndarray of int, shape (m, min(count, k))

    Examples
    --------
    >>> top_columns(np.array([[0.1, 0.4, 0.4], [0.5, 0.2, 0.3]]), 2).tolist()
    [[1, 2], [0, 2]]
    """
    m, k = values.shape
    count = min(count, k)
    if k <= 4 * count:
        return np.argsort(-values, axis=1, kind="stable")[:, :count]
    threshold = -np.partition(-values, count - 1, axis=1)[:, count - 1 : count]  # each row's count-th largest
    chosen = values >= threshold
    plain = np.flatnonzero(chosen.sum(axis=1) == count)  # no tie at the threshold (nor nan)
    out = np.empty((m, count), dtype=np.intp)
    if plain.size:
        columns = np.nonzero(chosen[plain])[1].reshape(plain.size, count)  # ascending in each row
        picked = np.take_along_axis(values[plain], columns, axis=1)
        out[plain] = np.take_along_axis(columns, np.argsort(-picked, axis=1, kind="stable"), axis=1)
    for row in np.setdiff1d(np.arange(m), plain):
        out[row] = np.argsort(-values[row], kind="stable")[:count]
    return out


def participation(vectors: np.ndarray, groups: DofGroups, lengths: np.ndarray) -> np.ndarray:
    """Every DOF's share of the displacement of every mode (:attr:`express.analysis.modes.modes.Mode.dominant`).

    ``share_i = |l_i phi_i|^2 / sum_j |l_j phi_j|^2`` over the DOFs with mass (a stroke's
    share is 0).

    Parameters
    ----------
    vectors : numpy.ndarray, shape (n, m)
        Displacement parts ``phi`` of the eigenvectors (columns), complex.
    groups : DofGroups
    lengths : numpy.ndarray, shape (n,)
        ``l_i`` [m]: 1 for a translation, the radius of gyration for a rotation.

    Returns
    -------
    numpy.ndarray, shape (m, n)
        One row per mode (each summed over its row as a whole, NumPy's pairwise sum);
        a row of zeros for a mode without displacement.
    """
    massive = np.zeros(len(groups.dofs), dtype=bool)
    massive[groups.rows] = True
    weight = np.abs(np.where(massive, vectors.T, 0.0) * lengths) ** 2
    total = weight.sum(axis=1, keepdims=True)
    return np.divide(weight, total, out=weight, where=total > 0)


def kinetic_shares(vectors: np.ndarray, groups: DofGroups, mass: np.ndarray | RowProduct) -> np.ndarray:
    """Every DOF's share of the kinetic energy of every mode
    (:mod:`express.analysis.modes.mode_names`): ``T_i = Re(conj(phi_i) (M phi)_i)``, negative
    parts taken as 0, divided by their sum.

    Parameters
    ----------
    vectors : numpy.ndarray, shape (n, m)
        ``phi`` of the modes (columns), complex.
    groups : DofGroups
    mass : numpy.ndarray, shape (n, n), or RowProduct
        ``M`` (prepared once for many calls).

    Returns
    -------
    numpy.ndarray, shape (k, m)
        Over :attr:`DofGroups.rows`; a column of zeros where nothing with mass moves.
    """
    parts = np.maximum(np.real(np.conj(vectors) * _product(mass)(vectors))[groups.rows], 0.0)
    total = running_sum(parts)
    return np.divide(parts, total, out=parts, where=total > 0)


def series_shares(vectors: np.ndarray, groups: DofGroups, damping: np.ndarray | RowProduct) -> np.ndarray:
    """Every series element's share of the power dissipated in every mode: its damper's
    ``c |phi_s|^2`` over ``Re(phi^H C phi)``.

    Parameters
    ----------
    vectors : numpy.ndarray, shape (n, m)
    groups : DofGroups
    damping : numpy.ndarray, shape (n, n), or RowProduct
        ``C(v)``.

    Returns
    -------
    numpy.ndarray, shape (s, m)
        Over :attr:`DofGroups.strokes`; nan in a column whose mode dissipates nothing.
    """
    if groups.strokes.size == 0:
        return np.zeros((0, vectors.shape[1]))
    product = _product(damping)
    dissipated = running_sum(np.real(np.conj(vectors) * product(vectors)))
    stroke = groups.strokes
    power = product.diagonal[stroke, None] * np.abs(vectors[stroke]) ** 2
    return np.divide(power, dissipated, out=np.full_like(power, np.nan), where=dissipated > 0)


def series_ranking(shares: np.ndarray, elements: Sequence[str]) -> tuple[tuple[str, float], ...]:
    """One mode's series elements with their share of the dissipated power
    (a column of :func:`series_shares`), largest first, ties in DOF order; empty when the
    mode dissipates nothing.

    Examples
    --------
    >>> series_ranking(np.array([0.2, 0.7]), ["yaw", "lateral"])
    (('lateral', 0.7), ('yaw', 0.2))
    """
    if shares.size == 0 or np.isnan(shares).all():
        return ()
    return tuple((elements[i], float(shares[i])) for i in np.argsort(-shares, kind="stable"))


def roll_centres(vectors: np.ndarray, groups: DofGroups) -> np.ndarray:
    """Height [m] above its reference point of the line every body of
    :attr:`DofGroups.roll` rolls about, ``Re(phi_y / phi_rx)``.

    Returns
    -------
    numpy.ndarray, shape (r, m)
        nan where the body does not roll (``phi_rx = 0``).
    """
    rx, y = vectors[groups.roll[1]], vectors[groups.roll[2]]
    rolls = np.abs(rx) > 0
    return np.real(np.divide(y, rx, out=np.full_like(y, np.nan), where=rolls))


#: From this size up a non-diagonal matrix is multiplied by SciPy's sparse product (its
#: import is then a small part of the work); below, by the same sums in NumPy.
SCIPY_FROM = 400


class RowProduct:
    """``matrix @ vectors`` row by row, each row's products added in column order: by
    the diagonal when ``matrix`` is diagonal (a mass matrix), else as a sparse product
    (a long train's damping has a few entries per row).  Unlike a BLAS product, every
    column comes out the same however many are multiplied together.

    Parameters
    ----------
    matrix : numpy.ndarray, shape (n, n)

    Examples
    --------
    >>> RowProduct(np.array([[2.0, 0.0], [0.0, 3.0]]))(np.array([[1j], [1.0]])).ravel().tolist()
    [2j, (3+0j)]
    """

    def __init__(self, matrix: np.ndarray) -> None:
        self.diagonal = np.diag(matrix).copy()
        self._sparse = None
        self._entries: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        if np.count_nonzero(matrix) != np.count_nonzero(self.diagonal):
            if matrix.shape[0] >= SCIPY_FROM:
                from scipy.sparse import csr_array

                self._sparse = csr_array(matrix)
            else:  # the same sums in the same order, without importing SciPy (0.15 s of a warm command)
                rows, columns = np.nonzero(matrix)
                self._entries = (rows, columns, matrix[rows, columns])

    def __call__(self, vectors: np.ndarray) -> np.ndarray:
        """The product with ``vectors`` (n, m)."""
        if self._sparse is not None:
            return np.asarray(self._sparse @ vectors)
        if self._entries is None:
            return self.diagonal[:, None] * vectors
        rows, columns, values = self._entries
        product = np.zeros((self.diagonal.size, vectors.shape[1]), dtype=np.result_type(values, vectors))
        np.add.at(product, rows, values[:, None] * vectors[columns])  # entry by entry, row-major: SciPy's order
        return product


def _product(matrix: np.ndarray | RowProduct) -> RowProduct:
    return matrix if isinstance(matrix, RowProduct) else RowProduct(matrix)
