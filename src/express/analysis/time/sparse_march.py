"""The time march of large sparse models: each step by the action of ``exp(A dt)``.

A long train's state matrix is large and very sparse (100 cars: 4800 states, 0.1 %
non-zeros) while its exponential ``phi = exp(A dt)`` and the hold integrals are dense:
forming them (:func:`express.analysis.time.integrator.discretize`) and multiplying by them at
every step costs minutes.  This route never forms them.  Each step integrates
``x' = A x + w0 + (t / dt) w1`` over ``dt`` exactly as the dense route does (the same
first-order hold of the known forcing and of the feedback forces, the same Heun
predictor on the feedback, :func:`express.analysis.time.integrator.heun_march`), by the
truncated Taylor series of the exponential of the matrix augmented with the forcing,
applied to the state (Al-Mohy and Higham, "Computing the action of the matrix
exponential", SIAM J. Sci. Comput. 33 (2011) 488-511, Algorithm 3.2 with the degree and
scaling of its Code Fragment 3.1 from the 1-norm, tolerance ``2**-53``).  ``A dt`` is
first balanced by a diagonal similarity of powers of two (Parlett and Reinsch's iteration
as in LAPACK's ``gebal``, on the sparse matrix; exact in floating point), which brings its 1-norm from about 6e4 to about 8 for the trains of
``examples/make_vehicles.py``; a step then costs about 50 sparse products.

The results agree with the dense route to rounding (about 1e-13 of the largest value,
``tests/test_sparse_march.py``), not bit for bit; :func:`choose_route` keeps the dense
route (and its results) for every model under :data:`SPARSE_MIN_STATES` states.
"""

from __future__ import annotations

from typing import Literal, NamedTuple

import numpy as np
from numba import njit

from express.base.diagnostics import ArgumentError
from express.forces.law import stacked_forces

__all__ = [
    "SPARSE_MAX_DENSITY", "SPARSE_MIN_STATES", "SparseSteps", "choose_route", "sparse_heun_march", "sparse_steps",
    "taylor_degree", "taylor_step",
]

Route = Literal["auto", "dense", "sparse"]

#: Models with fewer states keep the dense route (its matrices are cheap below this).
SPARSE_MIN_STATES = 400
#: ... and so do models whose state matrix has a larger share of non-zeros.
SPARSE_MAX_DENSITY = 0.02

#: Largest ``||A dt||_1 / s`` for which ``m`` Taylor terms reach the tolerance ``2**-53``
#: (Higham, Functions of Matrices (2008) Table A.3, and Al-Mohy and Higham (2011) Table 3.1).
_THETA = {
    1: 2.29e-16, 2: 2.58e-8, 3: 1.39e-5, 4: 3.40e-4, 5: 2.40e-3, 6: 9.07e-3, 7: 2.38e-2, 8: 5.00e-2,
    9: 8.96e-2, 10: 1.44e-1, 11: 2.14e-1, 12: 3.00e-1, 13: 4.00e-1, 14: 5.14e-1, 15: 6.41e-1, 16: 7.81e-1,
    17: 9.31e-1, 18: 1.09, 19: 1.26, 20: 1.44, 21: 1.62, 22: 1.82, 23: 2.01, 24: 2.22, 25: 2.43, 26: 2.64,
    27: 2.86, 28: 3.08, 29: 3.31, 30: 3.54, 35: 4.7, 40: 6.0, 45: 7.2, 50: 8.5, 55: 9.9,
}
_TOLERANCE = 2.0**-53


def choose_route(a: np.ndarray, route: Route = "auto") -> Literal["dense", "sparse"]:
    """``"sparse"`` for a state matrix of at least :data:`SPARSE_MIN_STATES` states with at
    most :data:`SPARSE_MAX_DENSITY` non-zeros, else ``"dense"`` (``route`` forces one)."""
    if route not in ("auto", "dense", "sparse"):
        raise ArgumentError(f'route must be "auto", "dense" or "sparse", not {route!r}')
    if route != "auto":
        return route
    size = a.shape[0]
    if size < SPARSE_MIN_STATES:
        return "dense"
    return "sparse" if np.count_nonzero(a) <= SPARSE_MAX_DENSITY * size * size else "dense"


def taylor_degree(norm: float) -> tuple[int, int]:
    """Taylor degree ``m`` and number of sub-steps ``s`` for a matrix of 1-norm ``norm``
    (the least ``m s`` with ``norm / s <= theta_m``, Al-Mohy and Higham's fragment 3.1;
    ``m >= 3``, so that the hold of the forcing is whole even for ``A = 0``)."""
    best = (0, 0)
    for degree, theta in _THETA.items():
        if degree < 3:
            continue
        substeps = max(1, int(np.ceil(norm / theta)))
        if best == (0, 0) or degree * substeps < best[0] * best[1]:
            best = (degree, substeps)
    return best


class SparseSteps(NamedTuple):
    """The linear part of the step of a large sparse model (:func:`sparse_steps`).

    Attributes
    ----------
    indptr, indices, data : numpy.ndarray
        ``B = D^-1 A dt D`` in compressed rows (``D`` = ``diag(scale)``, powers of two).
    scale : numpy.ndarray, shape (N,)
    degree, substeps : int
        Taylor terms per sub-step and sub-steps per step.
    dt : float
        [s].
    forcing : numpy.ndarray, shape (steps + 1, N)
        The known forcing ``e = B u + Bd u'`` at every step (held linearly over a step).
    g_indptr, g_indices, g_data : numpy.ndarray
        The feedback forces' input matrix ``G``, shape (N, n_z), in compressed rows.
    feedback_count : int
        ``n_z``.
    """

    indptr: np.ndarray
    indices: np.ndarray
    data: np.ndarray
    scale: np.ndarray
    degree: int
    substeps: int
    dt: float
    forcing: np.ndarray
    g_indptr: np.ndarray
    g_indices: np.ndarray
    g_data: np.ndarray
    feedback_count: int

    @property
    def steps(self) -> int:
        """Number of steps."""
        return int(self.forcing.shape[0]) - 1

    def run(self, x0, laws: tuple, history: np.ndarray, progress=None) -> np.ndarray:
        """:func:`sparse_heun_march` over every step (in 50 chunks when ``progress`` is
        given, called with the fraction done after each); returns the states, shape
        (steps + 1, N)."""
        steps = self.steps
        states = np.empty((steps + 1, x0.size))
        states[0] = x0
        chunk = max(steps, 1) if progress is None else max(1, steps // 50)
        x = np.ascontiguousarray(x0, dtype=float)
        for first in range(0, steps, chunk):
            last = min(steps, first + chunk)
            x = sparse_heun_march(self, x, first, last, states, laws, history)
            if progress is not None:
                progress(last / steps)
        return states


def sparse_steps(a: np.ndarray, dt: float, forcing: np.ndarray, selector: np.ndarray) -> SparseSteps:
    """The sparse route's step of ``x' = A x + e + G z`` (:class:`SparseSteps`).

    Parameters
    ----------
    a : numpy.ndarray, shape (N, N)
        State matrix [1/s].
    dt : float
        Time step [s].
    forcing : numpy.ndarray, shape (steps + 1, N)
        Known forcing ``e`` at every step.
    selector : numpy.ndarray, shape (N, n_z)
        ``G``: where the feedback forces enter.
    """
    from scipy.sparse import csr_matrix

    matrix = csr_matrix(a * dt)
    matrix.sort_indices()
    indptr, indices = matrix.indptr.astype(np.int64), matrix.indices.astype(np.int64)
    data = matrix.data.astype(float)
    scale = np.ones(a.shape[0])
    _balance(indptr, indices, data, scale)
    norm = float(np.max(np.bincount(indices, np.abs(data), minlength=a.shape[0]))) if data.size else 0.0
    degree, substeps = taylor_degree(norm)
    g = csr_matrix(selector)
    return SparseSteps(indptr, indices, data, scale, degree, substeps, float(dt), np.ascontiguousarray(forcing, dtype=float),
                       g.indptr.astype(np.int64), g.indices.astype(np.int64), g.data.astype(float),
                       int(selector.shape[1]))


@njit(cache=True)
def _balance(indptr, indices, data, scale):
    """Balance the matrix in compressed rows in place, ``D^-1 M D`` with ``D = diag(scale)``
    of powers of two (exact): the row and column 1-norms off the diagonal made about equal
    (Parlett and Reinsch's iteration, as LAPACK's ``gebal`` without its permutations)."""
    size = indptr.size - 1
    columns = np.zeros(size + 1, dtype=np.int64)  # where each column's entries are in ``data``
    for p in range(indices.size):
        columns[indices[p] + 1] += 1
    for i in range(size):
        columns[i + 1] += columns[i]
    filled = columns[:-1].copy()
    places = np.zeros(indices.size, dtype=np.int64)
    for i in range(size):
        for p in range(indptr[i], indptr[i + 1]):
            places[filled[indices[p]]] = p
            filled[indices[p]] += 1
    done = False
    sweeps = 0
    while not done and sweeps < 100:
        done = True
        sweeps += 1
        for i in range(size):
            row = 0.0
            for p in range(indptr[i], indptr[i + 1]):
                if indices[p] != i:
                    row += abs(data[p])
            column = 0.0
            for q in range(columns[i], columns[i + 1]):
                if places[q] < indptr[i] or places[q] >= indptr[i + 1]:  # off the diagonal
                    column += abs(data[places[q]])
            if row == 0.0 or column == 0.0:
                continue
            total = row + column
            factor = 1.0
            while column < 0.5 * row:
                column *= 4.0
                factor *= 2.0
            while column >= 2.0 * row:
                column *= 0.25
                factor *= 0.5
            if (column + row) / factor < 0.95 * total:
                done = False
                scale[i] *= factor
                for p in range(indptr[i], indptr[i + 1]):
                    data[p] /= factor
                for q in range(columns[i], columns[i + 1]):
                    data[places[q]] *= factor


@njit(cache=True)
def _multiply(indptr, indices, data, y, out):
    """``out = M y`` for ``M`` in compressed rows."""
    for i in range(indptr.size - 1):
        total = 0.0
        for p in range(indptr[i], indptr[i + 1]):
            total += data[p] * y[indices[p]]
        out[i] = total


@njit(cache=True)
def _largest(v):
    largest = 0.0
    for value in v:
        if abs(value) > largest:
            largest = abs(value)
    return largest


@njit(cache=True)
def taylor_step(steps, x, w0, w1, out, term, product, v0, v1):
    """``out = x(dt)`` of ``x' = A x + w0 + (t / dt) w1``, ``x(0) = x`` (real coordinates):
    ``exp`` of ``[[B, v1, v0], [0, 0, 1], [0, 0, 0]]`` (``v = dt D^-1 w``) on ``[x / D; 0; 1]``
    by the truncated Taylor series in ``steps.substeps`` sub-steps, each ended when two
    terms in a row fall below ``2**-53`` of the sum (never before the third, which is the
    first to hold all of the forcing).  ``term``, ``product``, ``v0``, ``v1``: work arrays."""
    size = x.size
    scale = steps.scale
    h = 1.0 / steps.substeps
    for i in range(size):
        out[i] = x[i] / scale[i]
        term[i] = out[i]
        v0[i] = steps.dt * w0[i] / scale[i]
        v1[i] = steps.dt * w1[i] / scale[i]
    for step in range(steps.substeps):
        t1, t2 = step * h, 1.0  # the hold's clock and the constant 1 of the augmented state
        c1 = _largest(term)
        for j in range(1, steps.degree + 1):
            coefficient = h / j
            _multiply(steps.indptr, steps.indices, steps.data, term, product)
            c2 = 0.0
            total = 0.0
            for i in range(size):  # the next term, the sum and their largest values in one pass
                value = coefficient * (product[i] + t1 * v1[i] + t2 * v0[i])
                term[i] = value
                out[i] += value
                c2 = max(c2, abs(value))
                total = max(total, abs(out[i]))
            t1, t2 = coefficient * t2, 0.0
            if j >= 3 and c1 + c2 <= _TOLERANCE * total:
                break
            c1 = c2
        for i in range(size):
            term[i] = out[i]
    for i in range(size):
        out[i] *= scale[i]


@njit(cache=True)
def sparse_heun_march(steps, x0, first, last, states, laws, history):
    """Steps ``first .. last`` as :func:`express.analysis.time.integrator.heun_march` does them,
    the linear part by :func:`taylor_step`: the predictor ``x~ = x(dt)`` with the feedback
    ``z[k]`` held, then ``x[k+1] = x~ +`` the response from rest to the feedback's change
    ``z[k+1] - z[k]`` over the step (nothing when it did not change).  Returns the last state."""
    size = x0.size
    nz = steps.feedback_count
    x = x0.copy()
    z = np.zeros(nz)
    z_next = np.zeros(nz)
    change = np.zeros(nz)
    w0 = np.zeros(size)
    w1 = np.zeros(size)
    pushed = np.zeros(size)
    rest = np.zeros(size)
    trial = np.zeros(size)
    correction = np.zeros(size)
    work = np.zeros((4, size))
    scratch = np.zeros_like(history[first])
    forcing = steps.forcing
    stacked_forces(x, first, laws, z, history[first], True)
    for k in range(first, last):
        _multiply(steps.g_indptr, steps.g_indices, steps.g_data, z, pushed)
        for i in range(size):
            w0[i] = forcing[k, i] + pushed[i]
            w1[i] = forcing[k + 1, i] - forcing[k, i]
        taylor_step(steps, x, w0, w1, trial, work[0], work[1], work[2], work[3])
        stacked_forces(trial, k + 1, laws, z_next, scratch, False)
        moved = False
        for j in range(nz):
            change[j] = z_next[j] - z[j]
            moved = moved or change[j] != 0.0
        if moved:
            _multiply(steps.g_indptr, steps.g_indices, steps.g_data, change, pushed)
            taylor_step(steps, rest, rest, pushed, correction, work[0], work[1], work[2], work[3])
            for i in range(size):
                x[i] = trial[i] + correction[i]
        else:
            for i in range(size):
                x[i] = trial[i]
        stacked_forces(x, k + 1, laws, z, history[k + 1], True)
        for i in range(size):
            states[k + 1, i] = x[i]
    return x
