"""Time marching of ``x' = A x + e(t) + G z(x, t)`` with exact discretization.

The nonlinear forces ``z`` are the wheel/rail corrections of every wheelset and the
forces of the bump stops (clearance elements, :mod:`express.assembly.clearance`).

The linear part is discretized exactly (matrix exponential, first-order hold on the
known forcing ``e``: track curvature, cant, irregularity and their rates), so the
stiff lever and creep modes cost nothing in step size.  The nonlinear wheel/rail
forces ``z`` (flange contact, creep saturation) are fed back with a first-order hold
whose end value comes from a predictor step (Heun's scheme on the feedback only).

The inner loop is compiled with Numba; it is the reason the project depends on it
(a 460 m curving run takes milliseconds).
"""

from __future__ import annotations

import numpy as np
from numba import njit
from scipy.linalg import expm

__all__ = ["discretize", "march"]


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


@njit(cache=True, fastmath=False)
def _feedback(x, ivy, ivpsi, k, iy, ipsi, y_rail, rho, speed, f1, f2, conicity, r0, b, clearance, k_rail, limit, flange, saturation, z):
    count = iy.size
    for j in range(count):
        y = x[iy[j]]
        psi = x[ipsi[j]]
        y_dot = x[ivy[j]]
        psi_dot = x[ivpsi[j]]
        relative = y - y_rail[k, j]
        xi_x = conicity[j] * relative / r0[j] + b[j] * psi_dot / speed + b[j] * rho[k, j]
        xi_y = y_dot / speed - psi
        factor = 1.0
        if saturation:
            force = np.sqrt((f1[j] * xi_x) ** 2 + (f2[j] * xi_y) ** 2)
            ratio = force / limit[j]
            if ratio > 0.0:
                if ratio <= 3.0:
                    factor = (ratio - ratio * ratio / 3.0 + ratio * ratio * ratio / 27.0) / ratio
                else:
                    factor = 1.0 / ratio
        dy = 0.0
        if flange:
            if relative > clearance[j]:
                dy = relative - clearance[j]
            elif relative < -clearance[j]:
                dy = relative + clearance[j]
        z[j] = -k_rail[j] * dy + (factor - 1.0) * (-2.0 * f2[j] * xi_y)
        z[count + j] = (factor - 1.0) * (-2.0 * b[j] * f1[j] * xi_x)


@njit(cache=True, fastmath=False)
def bump_stops(x, k, index, coefficient, offset, gap, stiffness, progressive, first, z):
    """Bump-stop forces ``-F`` (express.assembly.clearance) into ``z[first:]``; the deflection
    of stop ``s`` is ``sum coefficient[s, :] x[index[s, :]]`` (its few nonzero terms)."""
    for s in range(gap.size):
        delta = offset[k, s]
        for i in range(index.shape[1]):
            delta += coefficient[s, i] * x[index[s, i]]
        e = 0.0
        if delta > gap[s]:
            e = delta - gap[s]
        elif delta < -gap[s]:
            e = delta + gap[s]
        z[first + s] = -(stiffness[s] * e + progressive[s] * e * e * e)


@njit(cache=True, fastmath=True)
def _march(phi, drive, g0, g1, x0, first, last, states, ivy, ivpsi, iy, ipsi, y_rail, rho, speed, f1, f2, conicity, r0, b, clearance, k_rail, limit, flange, saturation, stop_index, stop_coefficient, stop_offset, stop_gap, stop_k, stop_k3):
    size = x0.size
    nz = g0.shape[1]
    stops = stop_gap.size > 0
    wheel = 2 * iy.size
    x = x0.copy()
    z = np.zeros(nz)
    z_next = np.zeros(nz)
    base = np.zeros(size)
    trial = np.zeros(size)
    _feedback(x, ivy, ivpsi, first, iy, ipsi, y_rail, rho, speed, f1, f2, conicity, r0, b, clearance, k_rail, limit, flange, saturation, z)
    if stops:
        bump_stops(x, first, stop_index, stop_coefficient, stop_offset, stop_gap, stop_k, stop_k3, wheel, z)
    for k in range(first, last):
        for i in range(size):
            total = drive[k, i]
            for j in range(size):
                total += phi[i, j] * x[j]
            base[i] = total
            held = 0.0
            for j in range(nz):
                held += g0[i, j] * z[j]
            trial[i] = total + held
        _feedback(trial, ivy, ivpsi, k + 1, iy, ipsi, y_rail, rho, speed, f1, f2, conicity, r0, b, clearance, k_rail, limit, flange, saturation, z_next)
        if stops:
            bump_stops(trial, k + 1, stop_index, stop_coefficient, stop_offset, stop_gap, stop_k, stop_k3, wheel, z_next)
        for i in range(size):
            total = base[i]
            for j in range(nz):
                total += g0[i, j] * z[j] + g1[i, j] * (z_next[j] - z[j])
            x[i] = total
        _feedback(x, ivy, ivpsi, k + 1, iy, ipsi, y_rail, rho, speed, f1, f2, conicity, r0, b, clearance, k_rail, limit, flange, saturation, z)
        if stops:
            bump_stops(x, k + 1, stop_index, stop_coefficient, stop_offset, stop_gap, stop_k, stop_k3, wheel, z)
        for i in range(size):
            states[k + 1, i] = x[i]
    return x


def march(phi, drive, g0, g1, x0, wheel_rail, *, flange=True, saturation=True, progress=None):
    """March the discretized system over all steps.

    Parameters
    ----------
    phi : numpy.ndarray, shape (N, N)
    drive : numpy.ndarray, shape (steps, N)
        Known forcing already discretized: ``gamma0 e[k] + gamma1 (e[k+1] - e[k])``.
    g0, g1 : numpy.ndarray, shape (N, 2 * n_wheelsets + n_stops)
        Discretized input matrices of the feedback forces (wheel/rail, then bump stops).
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
    steps = drive.shape[0]
    states = np.empty((steps + 1, x0.size))
    states[0] = x0
    w = wheel_rail
    half = x0.size // 2
    ivy = np.ascontiguousarray(w.get("ivy", half + w["iy"]), dtype=np.int64)
    ivpsi = np.ascontiguousarray(w.get("ivpsi", half + w["ipsi"]), dtype=np.int64)
    rows = np.asarray(w.get("stop_rows", np.zeros((0, x0.size))), dtype=float)
    width = max([1] + [int(np.count_nonzero(row)) for row in rows])
    index = np.zeros((rows.shape[0], width), dtype=np.int64)
    coefficient = np.zeros((rows.shape[0], width))
    for s, row in enumerate(rows):  # the few nonzero terms of each deflection
        nonzero = np.flatnonzero(row)
        index[s, : nonzero.size], coefficient[s, : nonzero.size] = nonzero, row[nonzero]
    stops = (
        index, coefficient,
        np.ascontiguousarray(w.get("stop_offset", np.zeros((steps + 1, 0))), dtype=float),
        *(np.ascontiguousarray(w.get(key, np.zeros(0)), dtype=float) for key in ("stop_gap", "stop_k", "stop_k3")),
    )
    chunk = steps if progress is None else max(1, steps // 50)
    x = np.ascontiguousarray(x0, dtype=float)
    for first in range(0, steps, chunk):
        last = min(steps, first + chunk)
        x = _march(
            phi, drive, g0, g1, x, first, last, states, ivy, ivpsi, w["iy"], w["ipsi"], w["y_rail"], w["rho"],
            float(w["speed"]), w["f1"], w["f2"], w["conicity"], w["r0"], w["b"], w["clearance"],
            w["k_rail"], w["limit"], bool(flange), bool(saturation), *stops,
        )
        if progress is not None:
            progress(last / steps)
    return states
