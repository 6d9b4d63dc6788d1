"""Banded solves of the dynamic stiffness: the frequency-response route of long trains.

A train's ``M``, ``C(v)`` and ``K`` couple each car only with its neighbours.  Written
car by car, their non-zeros lie in a band a few dozen DOFs wide whatever the length of
the train (26 below and above the diagonal for the steered cars of
``examples/make_vehicles.py``, 5 cars or 20).  A banded LU (LAPACK ``zgbsv``, partial
pivoting, the same backward stability as the dense solve) then costs
``O(n l (l + u))`` per frequency instead of ``O(n^3)``: 2.6x less than the dense solve
for 5 cars, 30x for 20 (``docs/benchmarks.md``).

The band is found once per call from the non-zero pattern of ``M + C + K``: the DOFs'
own order or, when narrower, the reverse Cuthill-McKee order
(:func:`reverse_cuthill_mckee`, the classical bandwidth-reducing permutation, as
:func:`scipy.sparse.csgraph.reverse_cuthill_mckee` gives it).  :func:`choose_route` weighs it against the dense routes of
:func:`express.analysis.frequency.frequency.steady_response`.

Examples
--------
>>> import numpy as np
>>> k = np.diag([2.0, 2.0, 2.0]) - np.diag([1.0, 1.0], 1) - np.diag([1.0, 1.0], -1)
>>> layout = band_layout(k)
>>> (layout.lower, layout.upper)
(1, 1)
>>> x = solve_banded_stiffness(np.eye(3), np.zeros((3, 3)), k, np.array([0.0]), np.ones((1, 3, 1)), layout)
>>> np.round(x[0, :, 0].real, 12).tolist()   # k x = 1
[1.5, 2.0, 1.5]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "SCIPY_IMPORT_S", "BandLayout", "band_layout", "band_storage", "choose_route", "reverse_cuthill_mckee", "route_costs",
    "solve_banded_stiffness",
]


@dataclass(frozen=True)
class BandLayout:
    """A DOF order and the band it gives.

    Attributes
    ----------
    order : numpy.ndarray of int, shape (n,)
        Row ``k`` of the banded system is DOF ``order[k]``.
    lower, upper : int
        Diagonals below and above the main one that hold non-zeros.
    """

    order: np.ndarray
    lower: int
    upper: int

    @property
    def size(self) -> int:
        """Number of DOFs ``n``."""
        return int(self.order.size)

    @property
    def work(self) -> float:
        """Multiply-adds of one banded LU, about ``n l (l + u + 1)``."""
        return float(self.size * self.lower * (self.lower + self.upper + 1))


def _bandwidths(pattern: np.ndarray) -> tuple[int, int]:
    rows, columns = np.nonzero(pattern)
    if rows.size == 0:
        return 0, 0
    return int(max(0, (rows - columns).max())), int(max(0, (columns - rows).max()))


def band_layout(*matrices: np.ndarray) -> BandLayout:
    """The narrower of the natural and the reverse Cuthill-McKee order for the union
    of the non-zero patterns of ``matrices`` (each ``(n, n)``)."""
    n = int(np.shape(matrices[0])[0])
    pattern = np.zeros((n, n), dtype=bool)
    for matrix in matrices:
        pattern |= np.asarray(matrix) != 0
    natural = np.arange(n)
    lower, upper = _bandwidths(pattern)
    permuted = reverse_cuthill_mckee(pattern | pattern.T)
    rcm_lower, rcm_upper = _bandwidths(pattern[np.ix_(permuted, permuted)])
    if rcm_lower + rcm_upper < lower + upper:
        return BandLayout(permuted, rcm_lower, rcm_upper)
    return BandLayout(natural, lower, upper)


def reverse_cuthill_mckee(pattern: np.ndarray) -> np.ndarray:
    """The reverse Cuthill-McKee order of a symmetric non-zero ``pattern`` (n, n): the
    order of :func:`scipy.sparse.csgraph.reverse_cuthill_mckee` (``symmetric_mode=True``)
    step for step — seeds by ascending degree (a diagonal entry counted twice, ties as
    NumPy's default ``argsort`` leaves them), each new level's nodes by ascending degree
    (stable) — without importing SciPy's sparse package (0.4 s of a command's start).
    """
    n = pattern.shape[0]
    neighbours = [np.flatnonzero(row).tolist() for row in pattern]
    degree = np.array([len(row) + bool(pattern[i, i]) for i, row in enumerate(neighbours)], dtype=np.int32)
    seeds = np.argsort(degree).tolist()
    degrees = degree.tolist()
    seen = [False] * n
    order: list[int] = []
    for seed in seeds:
        if seen[seed]:
            continue
        seen[seed] = True
        order.append(seed)
        start = len(order) - 1
        while start < len(order):
            end = len(order)
            for i in order[start:end]:
                level = [j for j in neighbours[i] if not seen[j]]
                for j in level:
                    seen[j] = True
                order += sorted(level, key=degrees.__getitem__)
            start = end
        if len(order) == n:
            break
    return np.array(order[::-1], dtype=np.intp)


def band_storage(matrix: np.ndarray, layout: BandLayout) -> np.ndarray:
    """``matrix`` reordered by ``layout`` in LAPACK's ``gbsv`` storage, shape
    ``(2 l + u + 1, n)``: row ``l + u + i - j`` holds entry ``(i, j)``; the first ``l``
    rows are the room the LU's fill-in needs."""
    lower, upper, n = layout.lower, layout.upper, layout.size
    a = np.asarray(matrix, dtype=float)[np.ix_(layout.order, layout.order)]
    storage = np.zeros((2 * lower + upper + 1, n))
    for offset in range(-lower, upper + 1):
        diagonal = np.diagonal(a, offset)
        row = lower + upper - offset
        if offset >= 0:
            storage[row, offset:] = diagonal
        else:
            storage[row, : n + offset] = diagonal
    return storage


def solve_banded_stiffness(
    mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray, omega: np.ndarray, rhs: np.ndarray,
    layout: BandLayout,
) -> np.ndarray:
    """``(-w^2 M + i w C + K) X = R`` at every circular frequency by banded LU.

    Parameters
    ----------
    mass, damping, stiffness : numpy.ndarray, shape (n, n)
        Real; their non-zeros within ``layout``'s band.
    omega : numpy.ndarray, shape (F,)
        [rad/s].
    rhs : numpy.ndarray, complex, shape (F, n, J)
    layout : BandLayout

    Returns
    -------
    numpy.ndarray, complex, shape (F, n, J)

    Raises
    ------
    numpy.linalg.LinAlgError
        If the dynamic stiffness is singular at one of the frequencies.
    """
    from scipy.linalg.lapack import zgbsv

    m, c, k = (band_storage(a, layout) for a in (mass, damping, stiffness))
    order = layout.order
    out = np.empty(np.shape(rhs), dtype=complex)
    for index, w in enumerate(np.asarray(omega, dtype=float)):
        band = np.empty(m.shape, dtype=complex, order="F")
        np.multiply(-w * w, m, out=band.real)
        band.real += k
        np.multiply(w, c, out=band.imag)
        _, _, x, info = zgbsv(layout.lower, layout.upper, band, rhs[index][order], overwrite_ab=1, overwrite_b=1)
        if info != 0:
            raise np.linalg.LinAlgError(f"singular dynamic stiffness at w = {w:.6g} rad/s")
        out[index][order] = x
    return out


#: Time model of the routes [s], fitted to this project's 2-core benchmark machine
#: (``benchmarks/bench_numeric.py``, ``benchmarks/bench_frf_route.py``): per solve a call
#: overhead and a rate per multiply-add; the Schur form about ``10 N^3`` of them once.
_PER_CALL = 5e-6
_PER_OPERATION = 0.7e-9
_SCHUR_OPERATION = 1e-9
#: Wall time [s] of importing ``scipy.linalg`` (0.2-0.25 s on that machine, more when it is
#: loaded), which the banded and Schur routes need and NumPy's stacked solve does not.
#: Charged whether or not the process has imported it already, so that the route, and
#: with it the last bits of a response, depends only on the problem's size.
SCIPY_IMPORT_S = 0.25


def route_costs(n: int, states: int, frequencies: int, layout: BandLayout) -> dict[str, float]:
    """Estimated wall time [s] of each route of
    :func:`express.analysis.frequency.frequency.steady_response`, by the time model above.

    Parameters
    ----------
    n : int
        DOFs (size of the dynamic stiffness).
    states : int
        First-order states ``N`` (size of the state matrix).
    frequencies : int
        Frequencies ``F``.
    layout : BandLayout
        The band of the dynamic stiffness.

    Returns
    -------
    dict
        ``{"stacked": s, "banded": s, "schur": s}``: ``F`` dense LUs (``n^3 / 3``
        multiply-adds each); ``F`` banded LUs (:attr:`BandLayout.work`) and the SciPy
        import; one Schur form (``10 N^3``), ``F`` back substitutions (``N^2``) and the
        SciPy import.

    Examples
    --------
    >>> costs = route_costs(24, 48, 200, band_layout(np.ones((24, 24))))
    >>> min(costs, key=costs.__getitem__)   # a car at 200 frequencies: NumPy's stacked solve
    'stacked'
    """
    return {
        "stacked": frequencies * (_PER_CALL + _PER_OPERATION * n**3 / 3.0),
        "banded": SCIPY_IMPORT_S + frequencies * (_PER_CALL + _PER_OPERATION * layout.work),
        "schur": SCIPY_IMPORT_S + _SCHUR_OPERATION * 10.0 * states**3
        + frequencies * (_PER_CALL + _PER_OPERATION * states**2),
    }


def choose_route(n: int, states: int, frequencies: int, layout: BandLayout) -> str:
    """``"stacked"``, ``"banded"`` or ``"schur"``: the cheapest way to solve the response
    of ``n`` DOFs (``states`` first-order states) at ``frequencies`` points, by
    :func:`route_costs` (the first of that order on a tie).

    A small model takes NumPy's stacked dense solve unless the frequencies are many
    (for a 24-DOF car at 200 frequencies it costs about 2 ms, against the 0.25 s of
    importing SciPy's LAPACK for either other route); a train whose band is narrow takes
    the banded LU; a dense model at very many frequencies the Schur form.
    """
    costs = route_costs(n, states, frequencies, layout)
    return min(costs, key=costs.__getitem__)
