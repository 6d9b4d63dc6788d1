"""Where the wheelsets are in the state and the track under them: what the two wheel/rail
force elements (:mod:`express.forces.deadband`, :mod:`express.forces.contact`) read, and
their common linearisation by differences."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["WheelsetCoordinates", "wheel_rail_slopes", "wheelset_coordinates"]


class WheelsetCoordinates(NamedTuple):
    """Where the wheelsets are in the state and the track under them, for the compiled
    wheel/rail laws.

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


def wheelset_coordinates(vehicle, y_rail: np.ndarray, rho: np.ndarray, speed: float) -> WheelsetCoordinates:
    """:class:`WheelsetCoordinates` of ``vehicle`` (a :class:`~express.numeric.statespace.VehicleModel`)
    on the rail irregularity ``y_rail`` and curvature ``rho`` (steps + 1, n_wheelsets)."""
    ws = vehicle.wheelsets
    velocity = {int(i): vehicle.n + j for j, i in enumerate(vehicle.form.massive)}
    return WheelsetCoordinates(
        np.array([w.y for w in ws], dtype=np.int64), np.array([w.psi for w in ws], dtype=np.int64),
        np.array([velocity[w.y] for w in ws], dtype=np.int64), np.array([velocity[w.psi] for w in ws], dtype=np.int64),
        np.ascontiguousarray(y_rail, dtype=float), np.ascontiguousarray(rho, dtype=float), float(speed))


def wheel_rail_slopes(forces, x: np.ndarray, k: int, z: np.ndarray, coordinates: WheelsetCoordinates,
                      extra: tuple[np.ndarray, ...] = ()) -> np.ndarray:
    """``dz/dx`` (len(z), N) of wheel/rail forces ``forces(x, k)`` by forward differences:
    each wheelset's forces depend on its own coordinates only (lateral, yaw, their rates,
    and the ``extra`` columns: its vertical and roll coordinates where the loads follow
    them), so one difference moves one kind of coordinate of every wheelset at once."""
    step = 1e-8
    w = coordinates
    count = w.iy.size
    slopes = np.zeros((z.size, x.size))
    rows = np.arange(count)
    for columns in (w.iy, w.ipsi, w.ivy, w.ivpsi, *extra):
        moved = x.copy()
        moved[columns] += step
        change = (forces(moved, k) - z) / step
        for block in range(z.size // count):
            slopes[block * count + rows, columns] = change[block * count:(block + 1) * count]
    return slopes
