"""The paper's wheel/rail nonlinearity as a force element: the dead-band flange spring and
the Shen-Hedrick-Elkins creep saturation of every wheelset (:mod:`express.rail.nonlinear`).

It reads each wheelset's lateral and yaw coordinates and their rates, acts on them (the
flange force plus the saturated less the linear creep force on ``y``, the saturated less
the linear creep moment on ``psi``: the linear creep terms are in ``A``), has no internal
state; its compiled law is :class:`DeadbandLaw`; its linearisation is by differences
(:func:`express.forces.wheelsets.wheel_rail_slopes`): zero inside the flange clearance
below saturation, so the linear analyses see exactly the linear model there.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import types
from numba.extending import overload

from express.base.kernels import kernel
from express.forces.element import ForceElement
from express.forces.law import force_law
from express.forces.wheelsets import WheelsetCoordinates, wheel_rail_slopes
from express.rail.nonlinear import longitudinal_creepage, penetration, saturation_ratio, wheelset_forces

__all__ = ["DeadbandElement", "DeadbandLaw", "deadband_feedback"]


class DeadbandLaw(NamedTuple):
    """The dead-band flange spring and the saturation of every wheelset, compiled.

    Attributes
    ----------
    first : int
        The law's place in ``z``.
    wheelsets : WheelsetCoordinates
    f1, f2, conicity, r0, b, clearance, k_rail, limit : numpy.ndarray, shape (n_wheelsets,)
        Creep coefficients [N], conicity [-], wheel radius [m], half contact distance [m],
        flange clearance [m], rail stiffness [N/m], ``mu Q`` [N].
    flange, saturation : bool
        Include flange contact / creep saturation.
    """

    first: int
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


@kernel
def deadband_feedback(x, k, feedback, z):
    """Flange force plus saturated-minus-linear creep forces (:func:`express.rail.
    nonlinear.wheelset_forces`) of every wheelset into ``z`` from ``feedback.first``."""
    w = feedback.wheelsets
    count = w.iy.size
    first = feedback.first
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
        z[first + j] = -feedback.k_rail[j] * dy + (factor - 1.0) * (-2.0 * feedback.f2[j] * xi_y)
        z[first + count + j] = (factor - 1.0) * (-2.0 * feedback.b[j] * feedback.f1[j] * xi_x)


@overload(force_law)
def _deadband_law(x, k, law, z, record, commit):
    if isinstance(law, types.BaseNamedTuple) and law.instance_class is DeadbandLaw:
        return lambda x, k, law, z, record, commit: deadband_feedback(x, k, law, z)
    return None


class DeadbandElement(ForceElement):
    """The dead-band wheel/rail forces of a vehicle along a run (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        Its wheelsets (creep coefficients, conicity, clearances, ...) and state form.
    coordinates : WheelsetCoordinates
        Where the wheelsets are and the track under them.
    flange, saturation : bool
        Include flange contact / creep saturation.
    """

    kind = "dead-band"

    def __init__(self, vehicle, coordinates: WheelsetCoordinates, *, flange: bool, saturation: bool):
        self.wheelsets, self.coordinates = vehicle.wheelsets, coordinates
        self.force = vehicle.form.force
        self.flange, self.saturation = bool(flange), bool(saturation)

    @property
    def names(self) -> tuple[str, ...]:
        return (tuple(f"{w.name}.y wheel/rail" for w in self.wheelsets)
                + tuple(f"{w.name}.rz wheel/rail" for w in self.wheelsets))

    @property
    def reads(self) -> np.ndarray:
        c = self.coordinates
        return np.concatenate([c.iy, c.ipsi, c.ivy, c.ivpsi])

    def directions(self) -> np.ndarray:
        columns = [self.force[:, w.y] for w in self.wheelsets] + [self.force[:, w.psi] for w in self.wheelsets]
        return np.column_stack(columns) if columns else np.zeros((self.force.shape[0], 0))

    def law(self, first: int) -> DeadbandLaw:
        ws = self.wheelsets
        arrays = ([w.f1 for w in ws], [w.f2 for w in ws], [w.conicity for w in ws], [w.r0 for w in ws],
                  [w.b for w in ws], [w.flange_clearance for w in ws], [w.rail_stiffness for w in ws],
                  [w.friction * w.wheel_load for w in ws])
        f1, f2, conicity, r0, b, clearance, k_rail, limit = (np.ascontiguousarray(np.array(a), dtype=float) for a in arrays)
        return DeadbandLaw(first, self.coordinates, f1, f2, conicity, r0, b, clearance, k_rail, limit,
                           self.flange, self.saturation)

    def forces(self, x: np.ndarray, k: int) -> np.ndarray:
        c = self.coordinates
        forces = wheelset_forces(x[c.iy], x[c.ipsi], x[c.ivy], x[c.ivpsi], c.y_rail[k], c.rho[k], c.speed,
                                 self.wheelsets, flange=self.flange, saturation=self.saturation)
        return np.concatenate([forces["flange"] + forces["lateral_correction"], forces["yaw_correction"]])

    def slopes(self, x: np.ndarray, k: int, forces: np.ndarray) -> np.ndarray:
        return wheel_rail_slopes(self.forces, x, k, forces, self.coordinates)
