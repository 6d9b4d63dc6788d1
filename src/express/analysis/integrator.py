"""Time marching of ``x' = A x + e(t) + G z(x, t)`` with exact discretization.

The nonlinear forces ``z`` are the wheel/rail corrections of every wheelset and the
forces of the bump stops (clearance elements, :mod:`express.assembly.clearance`).

The linear part is discretized exactly (matrix exponential, first-order hold on the
known forcing ``e``: track curvature, cant, irregularity and their rates), so the
stiff lever and creep modes cost nothing in step size.  The nonlinear wheel/rail
forces ``z`` (flange contact, creep saturation) are fed back with a first-order hold
whose end value comes from a predictor step (Heun's scheme on the feedback only).

The inner loop is compiled with Numba; it is the reason the project depends on it
(a 460 m curving run takes milliseconds).  There is one march, :func:`heun_march`; what
varies is the wheel/rail feedback, a NamedTuple whose type picks the compiled law
(:func:`wheel_rail_feedback`): the dead-band flange spring with creep saturation
(:class:`DeadbandFeedback`, here) or the contact from profile tables
(:class:`express.analysis.contact_march.ContactFeedback`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.extending import overload
from scipy.linalg import expm

from express.rail.nonlinear import longitudinal_creepage, penetration, saturation_ratio

__all__ = [
    "BumpStops", "DeadbandFeedback", "DenseSteps", "WheelsetCoordinates", "all_feedback", "bump_stop_arrays",
    "bump_stops", "discretize", "heun_march", "march", "run_march", "wheel_rail_feedback", "wheelset_coordinates",
]


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


class WheelsetCoordinates(NamedTuple):
    """Where the wheelsets are in the state and the track under them, for the compiled
    feedback laws.

    Attributes
    ----------
    iy, ipsi : numpy.ndarray of int, shape (n_wheelsets,)
        The wheelsets' lateral and yaw coordinates in the state.
    ivy, ivpsi : numpy.ndarray of int, shape (n_wheelsets,)
        Their velocities in the state.
    y_rail, rho : numpy.ndarray, shape (steps + 1, n_wheelsets)
        Lateral rail irregularity [m] and track curvature [1/m] at each wheelset.
    speed : float
        [m/s].
    """

    iy: np.ndarray
    ipsi: np.ndarray
    ivy: np.ndarray
    ivpsi: np.ndarray
    y_rail: np.ndarray
    rho: np.ndarray
    speed: float


class DeadbandFeedback(NamedTuple):
    """The dead-band flange spring and the Shen-Hedrick-Elkins saturation
    (:mod:`express.rail.nonlinear`) of every wheelset, for :func:`heun_march`.

    Attributes
    ----------
    wheelsets : WheelsetCoordinates
    f1, f2, conicity, r0, b, clearance, k_rail, limit : numpy.ndarray, shape (n_wheelsets,)
        Creep coefficients [N], conicity [-], wheel radius [m], half contact distance [m],
        flange clearance [m], rail stiffness [N/m], ``mu Q`` [N].
    flange, saturation : bool
        Include flange contact / creep saturation.
    """

    wheelsets: WheelsetCoordinates
    f1: np.ndarray
    f2: np.ndarray
    conicity: np.ndarray
    r0: np.ndarray
    b: np.ndarray
    clearance: np.ndarray
    k_rail: np.ndarray
    limit: np.ndarray
    flange: bool
    saturation: bool


class BumpStops(NamedTuple):
    """Bump stops (:mod:`express.assembly.clearance`) for the compiled march: the
    deflection of stop ``s`` is ``offset[k, s] + sum coefficient[s, :] x[places[s, :]]``
    (its few nonzero terms, at ``places[s, :]`` of the state); ``gap`` [m], ``stiffness`` [N/m], ``progressive`` [N/m^3]
    (rotational: rad, N m/rad, N m/rad^3)."""

    places: np.ndarray
    coefficient: np.ndarray
    offset: np.ndarray
    gap: np.ndarray
    stiffness: np.ndarray
    progressive: np.ndarray


def bump_stop_arrays(wheel_rail: dict, size: int, steps: int) -> BumpStops:
    """:class:`BumpStops` from the ``stop_*`` entries of ``wheel_rail`` (:func:`march`;
    none when absent)."""
    rows = np.asarray(wheel_rail.get("stop_rows", np.zeros((0, size))), dtype=float)
    width = max([1] + [int(np.count_nonzero(row)) for row in rows])
    index = np.zeros((rows.shape[0], width), dtype=np.int64)
    coefficient = np.zeros((rows.shape[0], width))
    for s, row in enumerate(rows):  # the few nonzero terms of each deflection
        nonzero = np.flatnonzero(row)
        index[s, : nonzero.size], coefficient[s, : nonzero.size] = nonzero, row[nonzero]
    return BumpStops(index, coefficient,
                     np.ascontiguousarray(wheel_rail.get("stop_offset", np.zeros((steps + 1, 0))), dtype=float),
                     *(np.ascontiguousarray(wheel_rail.get(key, np.zeros(0)), dtype=float)
                       for key in ("stop_gap", "stop_k", "stop_k3")))


def wheel_rail_feedback(x, k, feedback, z, record):
    """The wheel/rail feedback forces of state ``x`` at step ``k`` into ``z[:2 n]``
    (lateral of every wheelset, then yaw) and what the law records into ``record``.

    Compiled only: each feedback NamedTuple type registers its law with
    ``numba.extending.overload`` (:func:`_deadband_law` here,
    :mod:`express.analysis.contact_march` for the contact tables)."""
    raise NotImplementedError("wheel_rail_feedback runs inside compiled code only")


@njit(cache=True)
def deadband_feedback(x, k, feedback, z):
    """Flange force plus saturated-minus-linear creep forces (:func:`express.rail.
    nonlinear.wheelset_forces`) of every wheelset into ``z``."""
    w = feedback.wheelsets
    count = w.iy.size
    for j in range(count):
        relative = x[w.iy[j]] - w.y_rail[k, j]
        xi_x = longitudinal_creepage(relative, x[w.ivpsi[j]], w.rho[k, j], w.speed, feedback.conicity[j],
                                     feedback.r0[j], feedback.b[j])
        xi_y = x[w.ivy[j]] / w.speed - x[w.ipsi[j]]
        factor = 1.0
        if feedback.saturation:
            factor = saturation_ratio(np.sqrt((feedback.f1[j] * xi_x) ** 2 + (feedback.f2[j] * xi_y) ** 2),
                                      feedback.limit[j])
        dy = penetration(relative, feedback.clearance[j]) if feedback.flange else 0.0
        z[j] = -feedback.k_rail[j] * dy + (factor - 1.0) * (-2.0 * feedback.f2[j] * xi_y)
        z[count + j] = (factor - 1.0) * (-2.0 * feedback.b[j] * feedback.f1[j] * xi_x)


@overload(wheel_rail_feedback)
def _deadband_law(x, k, feedback, z, record):
    if isinstance(feedback, types.BaseNamedTuple) and feedback.instance_class is DeadbandFeedback:
        return lambda x, k, feedback, z, record: deadband_feedback(x, k, feedback, z)
    return None


@njit(cache=True)
def bump_stops(x, k, stops, first, z):
    """Bump-stop forces ``-F`` (express.assembly.clearance) of :class:`BumpStops` into
    ``z[first:]``."""
    for s in range(stops.gap.size):
        delta = stops.offset[k, s]
        for i in range(stops.places.shape[1]):
            delta += stops.coefficient[s, i] * x[stops.places[s, i]]
        e = 0.0
        if delta > stops.gap[s]:
            e = delta - stops.gap[s]
        elif delta < -stops.gap[s]:
            e = delta + stops.gap[s]
        z[first + s] = -(stops.stiffness[s] * e + stops.progressive[s] * e * e * e)


@njit(cache=True)
def all_feedback(x, k, feedback, stops, z, record):
    """Wheel/rail feedback, then the bump stops after it, into ``z``."""
    wheel_rail_feedback(x, k, feedback, z, record)
    if stops.gap.size > 0:
        bump_stops(x, k, stops, z.size - stops.gap.size, z)


@njit(cache=True)
def _products(start, a_t, u, out):
    """``out[i] = start[i] + sum_j a[i, j] u[j]`` from the transpose ``a_t`` (C-contiguous),
    each row summed in the order ``j = 0, 1, ...``; four rows at a time, so that their sums
    proceed side by side (the same rounding as one row after another, twice as fast)."""
    columns, rows = a_t.shape
    i = 0
    while i + 4 <= rows:
        t0, t1, t2, t3 = start[i], start[i + 1], start[i + 2], start[i + 3]
        for j in range(columns):
            value = u[j]
            t0 += a_t[j, i] * value
            t1 += a_t[j, i + 1] * value
            t2 += a_t[j, i + 2] * value
            t3 += a_t[j, i + 3] * value
        out[i], out[i + 1], out[i + 2], out[i + 3] = t0, t1, t2, t3
        i += 4
    for row in range(i, rows):
        total = start[row]
        for j in range(columns):
            total += a_t[j, row] * u[j]
        out[row] = total


@njit(cache=True)
def _paired_products(start, a_t, u, b_t, w, out):
    """``out[i] = start[i] + sum_j (a[i, j] u[j] + b[i, j] w[j])``, as :func:`_products`."""
    columns, rows = a_t.shape
    i = 0
    while i + 4 <= rows:
        t0, t1, t2, t3 = start[i], start[i + 1], start[i + 2], start[i + 3]
        for j in range(columns):
            value, other = u[j], w[j]
            t0 += a_t[j, i] * value + b_t[j, i] * other
            t1 += a_t[j, i + 1] * value + b_t[j, i + 1] * other
            t2 += a_t[j, i + 2] * value + b_t[j, i + 2] * other
            t3 += a_t[j, i + 3] * value + b_t[j, i + 3] * other
        out[i], out[i + 1], out[i + 2], out[i + 3] = t0, t1, t2, t3
        i += 4
    for row in range(i, rows):
        total = start[row]
        for j in range(columns):
            total += a_t[j, row] * u[j] + b_t[j, row] * w[j]
        out[row] = total


@njit(cache=True)
def heun_march(phi_t, drive, g0_t, g1_t, x0, first, last, states, feedback, stops, history):
    """Steps ``first .. last`` of ``x[k+1] = phi x[k] + drive[k] + g0 z[k] + g1 (z[k+1] - z[k])``
    with the end value ``z[k+1]`` of the feedback from a predictor (Heun's scheme on the
    feedback only); ``states[k + 1]`` gets each new state, ``history[k + 1]`` what the
    feedback law records of it (shape (steps + 1, ...) ; empty trailing axes for a law
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
    all_feedback(x, first, feedback, stops, z, history[first])
    for k in range(first, last):
        _products(drive[k], phi_t, x, base)
        _products(zero, g0_t, z, held)
        for i in range(size):
            trial[i] = base[i] + held[i]
        all_feedback(trial, k + 1, feedback, stops, z_next, scratch)
        for j in range(nz):
            change[j] = z_next[j] - z[j]
        _paired_products(base, g0_t, z, g1_t, change, x)
        all_feedback(x, k + 1, feedback, stops, z, history[k + 1])
        for i in range(size):
            states[k + 1, i] = x[i]
    return x


def run_march(phi, drive, g0, g1, x0, feedback, stops: BumpStops, history: np.ndarray, progress=None) -> np.ndarray:
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
        x = heun_march(phi_t, drive, g0_t, g1_t, x, first, last, states, feedback, stops, history)
        if progress is not None:
            progress(last / steps)
    return states


def wheelset_coordinates(wheel_rail: dict, size: int) -> WheelsetCoordinates:
    """:class:`WheelsetCoordinates` from ``wheel_rail`` (:func:`march`)."""
    w = wheel_rail
    half = size // 2
    return WheelsetCoordinates(
        np.ascontiguousarray(w["iy"], dtype=np.int64), np.ascontiguousarray(w["ipsi"], dtype=np.int64),
        np.ascontiguousarray(w.get("ivy", half + w["iy"]), dtype=np.int64),
        np.ascontiguousarray(w.get("ivpsi", half + w["ipsi"]), dtype=np.int64),
        np.ascontiguousarray(w["y_rail"], dtype=float), np.ascontiguousarray(w["rho"], dtype=float), float(w["speed"]))


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

    def run(self, x0, feedback, stops: BumpStops, history: np.ndarray, progress=None) -> np.ndarray:
        """:func:`run_march` from ``x0``; returns the states, shape (steps + 1, N)."""
        return run_march(self.phi, self.drive, self.g0, self.g1, x0, feedback, stops, history, progress)


def march(linear, x0, wheel_rail, *, flange=True, saturation=True, progress=None):
    """March the discretized system over all steps with the dead-band wheel/rail law.

    Parameters
    ----------
    linear : DenseSteps or express.analysis.sparse_march.SparseSteps
        The linear part of the step (dense matrices, or the sparse route of large models).
    x0 : numpy.ndarray, shape (N,)
        Initial state.
    wheel_rail : dict
        ``iy``, ``ipsi`` (int arrays: the wheelsets' lateral and yaw coordinates in the
        state), ``ivy``, ``ivpsi`` (their velocities in the state), ``y_rail`` and
        ``rho`` (steps + 1, n_wheelsets), ``speed`` and the per-wheelset arrays ``f1,
        f2, conicity, r0, b, clearance, k_rail, limit``; optionally the bump stops
        (:mod:`express.assembly.clearance`): ``stop_rows`` (n_stops, N) deflection over the
        state, ``stop_offset`` (steps + 1, n_stops) its input part, ``stop_gap``,
        ``stop_k``, ``stop_k3`` (n_stops,).
    progress : callable, optional
        Called with the fraction done, after each chunk.

    Returns
    -------
    numpy.ndarray, shape (steps + 1, N)
        States at every step.
    """
    w = wheel_rail
    feedback = DeadbandFeedback(wheelset_coordinates(w, x0.size),
                                *(np.ascontiguousarray(w[key], dtype=float) for key in
                                  ("f1", "f2", "conicity", "r0", "b", "clearance", "k_rail", "limit")),
                                bool(flange), bool(saturation))
    steps = linear.steps
    return linear.run(x0, feedback, bump_stop_arrays(w, x0.size, steps), np.zeros((steps + 1, 0, 0)), progress)
