"""Time marching of ``x' = A x + e(t) + G z(x, t)`` with exact discretization.

The nonlinear forces ``z`` are those of the force elements (:mod:`express.forces`: the
wheel/rail forces of every wheelset, the bump stops, ...), stacked in a
:class:`~express.forces.element.ForceSet`; the march sees only the stack.

The linear part is discretized exactly (matrix exponential, first-order hold on the
known forcing ``e``: track curvature, cant, irregularity and their rates), so the
stiff lever and creep modes cost nothing in step size.  The nonlinear wheel/rail
forces ``z`` (flange contact, creep saturation) are fed back with a first-order hold
whose end value comes from a predictor step (Heun's scheme on the feedback only).

The inner loop is compiled with Numba; it is the reason the project depends on it
(a 460 m curving run takes milliseconds).  There is one march, :func:`heun_march`; what
varies is the tuple of the elements' laws, each a NamedTuple whose type picks its
compiled law (:func:`express.forces.law.force_law`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit
from scipy.linalg import expm

from express.base.kernels import kernel
from express.forces.element import ForceSet
from express.forces.law import stacked_forces

__all__ = ["DenseSteps", "discretize", "heun_march", "march", "run_march"]


def discretize(a: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact discretization with first-order hold.

    Parameters
    ----------
    a : numpy.ndarray, shape (N, N)
        State matrix.
    dt : float
        Step [s].

    Returns
    -------
    phi, gamma0, gamma1 : numpy.ndarray, shape (N, N)
        ``x[k+1] = phi x[k] + gamma0 w[k] + gamma1 (w[k+1] - w[k])`` for a forcing
        ``w`` varying linearly over the step: ``phi = exp(A dt)``,
        ``gamma0 = int_0^dt exp(A s) ds``,
        ``gamma1 = int_0^dt exp(A s) (dt - s) / dt ds`` (Van Loan's block exponential).
    """
    size = a.shape[0]
    phi = expm(a * dt)
    # Integrals in closed form when A is well conditioned (integration by parts):
    # gamma0 = A^-1 (phi - I), gamma1 = A^-1 (gamma0 - dt I) / dt.  Otherwise (rigid
    # modes make A singular) fall back to Van Loan's block exponential.
    if np.linalg.cond(a) < 1e10:
        identity = np.eye(size)
        gamma0 = np.linalg.solve(a, phi - identity)
        gamma1 = np.linalg.solve(a, gamma0 - dt * identity) / dt
        return phi, gamma0, gamma1
    block = np.zeros((3 * size, 3 * size))
    block[:size, :size] = a * dt
    block[:size, size : 2 * size] = np.eye(size) * dt
    block[size : 2 * size, 2 * size :] = np.eye(size)
    exponential = expm(block)
    phi = exponential[:size, :size]
    gamma0 = exponential[:size, size : 2 * size]
    gamma1 = exponential[:size, 2 * size :]
    return phi, gamma0, gamma1


@kernel
def _products(start, a_t, u, out):
    """``out[i] = start[i] + sum_j a[i, j] u[j]`` from the transpose ``a_t`` (C-contiguous),
    each row summed in the order ``j = 0, 1, ...``; column by column into ``out`` (not
    ``u``), so that every row's sum proceeds side by side over contiguous memory (the same
    rounding as one row after another, several times as fast)."""
    columns, rows = a_t.shape
    for i in range(rows):
        out[i] = start[i]
    for j in range(columns):
        value = u[j]
        for i in range(rows):
            out[i] += a_t[j, i] * value


@kernel
def _paired_products(start, a_t, u, b_t, w, out):
    """``out[i] = start[i] + sum_j (a[i, j] u[j] + b[i, j] w[j])``, as :func:`_products`
    (``out`` neither ``u`` nor ``w``)."""
    columns, rows = a_t.shape
    for i in range(rows):
        out[i] = start[i]
    for j in range(columns):
        value, other = u[j], w[j]
        for i in range(rows):
            out[i] += a_t[j, i] * value + b_t[j, i] * other


@njit(cache=True)
def heun_march(phi_t, drive, g0_t, g1_t, x0, first, last, states, laws, history):
    """Steps ``first .. last`` of ``x[k+1] = phi x[k] + drive[k] + g0 z[k] + g1 (z[k+1] - z[k])``
    with the end value ``z[k+1]`` of the feedback from a predictor (Heun's scheme on the
    feedback only); ``laws`` the stacked force elements' compiled laws
    (:func:`express.forces.law.stacked_forces`); ``states[k + 1]`` gets each new state, ``history[k + 1]`` what the
    recording law records of it (shape (steps + 1, ...) ; empty trailing axes for a law
    that records nothing).  ``phi_t``, ``g0_t``, ``g1_t``: the transposes, C-contiguous.
    Returns the last state."""
    size = x0.size
    nz = g0_t.shape[0]
    x = x0.copy()
    z = np.zeros(nz)
    z_next = np.zeros(nz)
    change = np.zeros(nz)
    base = np.zeros(size)
    held = np.zeros(size)
    zero = np.zeros(size)
    trial = np.zeros(size)
    scratch = np.zeros_like(history[first])
    stacked_forces(x, first, laws, z, history[first], True)
    for k in range(first, last):
        _products(drive[k], phi_t, x, base)
        _products(zero, g0_t, z, held)
        for i in range(size):
            trial[i] = base[i] + held[i]
        stacked_forces(trial, k + 1, laws, z_next, scratch, False)
        for j in range(nz):
            change[j] = z_next[j] - z[j]
        _paired_products(base, g0_t, z, g1_t, change, x)
        stacked_forces(x, k + 1, laws, z, history[k + 1], True)
        for i in range(size):
            states[k + 1, i] = x[i]
    return x


def run_march(phi, drive, g0, g1, x0, laws: tuple, history: np.ndarray, progress=None) -> np.ndarray:
    """:func:`heun_march` over every step (in 50 chunks when ``progress`` is given, called
    with the fraction done after each); returns the states, shape (steps + 1, N)."""
    steps = drive.shape[0]
    states = np.empty((steps + 1, x0.size))
    states[0] = x0
    chunk = steps if progress is None else max(1, steps // 50)
    x = np.ascontiguousarray(x0, dtype=float)
    phi_t, g0_t, g1_t = (np.ascontiguousarray(np.transpose(m), dtype=float) for m in (phi, g0, g1))
    for first in range(0, steps, chunk):
        last = min(steps, first + chunk)
        x = heun_march(phi_t, drive, g0_t, g1_t, x, first, last, states, laws, history)
        if progress is not None:
            progress(last / steps)
    return states


class DenseSteps(NamedTuple):
    """The linear part of a step as dense matrices (the route of small models):
    ``x[k+1] = phi x[k] + drive[k] + g0 z[k] + g1 (z[k+1] - z[k])``, :func:`heun_march`.

    Attributes
    ----------
    phi : numpy.ndarray, shape (N, N)
    drive : numpy.ndarray, shape (steps, N)
        Known forcing already discretized: ``gamma0 e[k] + gamma1 (e[k+1] - e[k])``.
    g0, g1 : numpy.ndarray, shape (N, n_z)
        Discretized input matrices of the feedback forces (wheel/rail, then bump stops).
    """

    phi: np.ndarray
    drive: np.ndarray
    g0: np.ndarray
    g1: np.ndarray

    @property
    def steps(self) -> int:
        """Number of steps."""
        return int(self.drive.shape[0])

    def run(self, x0, laws: tuple, history: np.ndarray, progress=None) -> np.ndarray:
        """:func:`run_march` from ``x0`` with the compiled ``laws``; returns the states,
        shape (steps + 1, N)."""
        return run_march(self.phi, self.drive, self.g0, self.g1, x0, laws, history, progress)


def march(linear, x0: np.ndarray, forces: ForceSet, progress=None) -> tuple[np.ndarray, np.ndarray]:
    """March the discretized system over all steps with the force elements ``forces``.

    Parameters
    ----------
    linear : DenseSteps or express.analysis.time.sparse_march.SparseSteps
        The linear part of the step (dense matrices, or the sparse route of large models),
        made with ``forces.selector()`` as the feedback's input matrix.
    x0 : numpy.ndarray, shape (N,)
        Initial state.
    forces : ForceSet
        The nonlinear force elements (:mod:`express.forces`).
    progress : callable, optional
        Called with the fraction done, after each chunk.

    Returns
    -------
    states : numpy.ndarray, shape (steps + 1, N)
        States at every step.
    history : numpy.ndarray, shape (steps + 1, ...)
        What the recording element recorded at every step (:meth:`ForceSet.history`).
    """
    history = forces.history(linear.steps)
    states = linear.run(np.ascontiguousarray(x0, dtype=float), forces.laws(), history, progress)
    return states, history
