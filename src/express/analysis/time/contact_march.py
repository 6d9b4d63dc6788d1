"""The contact from profile tables in a time run: the contact forces of every step
(recorded by the march, or computed again from states), the per-wheel record, and the
reference right-hand side for ``solve_ivp``.  The force element itself — the compiled law,
the wheel loads, the linear terms it is measured against — is
:mod:`express.forces.contact`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from express.analysis.curving.outputs import WheelRailOutputs
from express.analysis.time.track_inputs import track_inputs
from express.forces.contact import contact_arrays, linear_coefficients, linear_wheel_rail
from express.rail.contact_forces import (
    OUTPUTS,
    WORK_FIELDS,
    ContactSet,
    WheelsetContact,
    patch_area,
    profile_wheelset_forces,
)
from express.rail.options import DEFAULT_CREEP_LAW, CreepLaw

__all__ = ["contact_force_history", "contact_rhs", "contact_wheel_outputs"]


@njit(cache=True)
def _history(y, psi, y_dot, psi_dot, y_rail, rho, speed, contacts, loads, result):
    work = np.zeros((2, len(WORK_FIELDS)))
    for k in range(y.shape[0]):
        for j in range(y.shape[1]):
            profile_wheelset_forces(contacts, j, loads[k, j, 0], loads[k, j, 1], y[k, j] - y_rail[k, j], psi[k, j],
                            y_dot[k, j], psi_dot[k, j], rho[k, j], speed, work, result[k, j])


def contact_force_history(q, q_dot, iy, ipsi, y_rail, rho, speed, contact: ContactSet,
                          loads: np.ndarray | None = None) -> np.ndarray:
    """:data:`~express.rail.contact_forces.OUTPUTS` of every wheelset at every step,
    shape (steps, n_wheelsets, len(OUTPUTS)); ``loads`` the wheel loads (left, right) [N],
    shape (steps, n_wheelsets, 2), the static ones by default."""
    y, psi = np.ascontiguousarray(q[:, iy]), np.ascontiguousarray(q[:, ipsi])
    y_dot, psi_dot = np.ascontiguousarray(q_dot[:, iy]), np.ascontiguousarray(q_dot[:, ipsi])
    if loads is None:
        loads = np.broadcast_to(contact.wheel_load[None, :, None], (q.shape[0], len(iy), 2))
    result = np.zeros((q.shape[0], len(iy), len(OUTPUTS)))
    _history(y, psi, y_dot, psi_dot, np.ascontiguousarray(y_rail), np.ascontiguousarray(rho), float(speed), contact,
             np.ascontiguousarray(loads, dtype=float), result)
    return result


def contact_wheel_outputs(vehicle, history: np.ndarray, q: np.ndarray, loads: str) -> WheelRailOutputs:
    """The per-wheel record (:class:`~express.analysis.curving.outputs.WheelRailOutputs`)
    of a march from its contact forces ``history`` (recorded by :class:`express.forces.contact.ContactElement`): each wheel's
    Q, Y, Fx, contact position and angle as the contact used them, its frictional power
    Tgamma and patch area (the wear and RCF columns), its position on the wheel and the
    patch's lateral semi-axis (the wear across the profile); the angle of attack is
    each wheelset's yaw ``q[:, psi]``; ``loads`` says where Q came from."""
    column = {name: k for k, name in enumerate(OUTPUTS)}

    def pair(name: str) -> np.ndarray:
        return history[:, :, [column[f"{name}_left"], column[f"{name}_right"]]]

    return WheelRailOutputs(
        vertical_load=pair("Q"), lateral_force=pair("Y"), longitudinal_force=pair("Fx"), contact_position=pair("u"),
        contact_angle=pair("angle"), angle_of_attack=q[:, [w.psi for w in vehicle.wheelsets]],
        static_load=np.array([w.wheel_load for w in vehicle.wheelsets], dtype=float), loads=loads,
        frictional_power=pair("Tgamma"), patch_area=patch_area(pair("unit_area"), pair("N")),
        wheel_position=pair("wheel_u"), patch_semi_b=pair("unit_b") * np.cbrt(np.maximum(pair("N"), 0.0)))


def contact_rhs(vehicle, track, contacts: list[WheelsetContact], *, speed: float | None = None, start: float = 0.0,
                law: CreepLaw = DEFAULT_CREEP_LAW):
    """The contact simulation's equations as ``f(t, x)`` for reference integrations
    (``scipy.integrate.solve_ivp``); bump stops are not included, the wheel loads are
    the static ones (the march adds the load transfer of
    :func:`express.analysis.curving.measure.estimated_wheel_loads`)."""
    v = float(vehicle.speed if speed is None else speed)
    a = vehicle.state_matrix(v)
    n = vehicle.n
    ws = vehicle.wheelsets
    columns = [vehicle.form.force[:, w.y] for w in ws] + [vehicle.form.force[:, w.psi] for w in ws]
    selector = np.column_stack(columns)
    arrays = contact_arrays(contacts, law)
    linear = linear_coefficients(vehicle, v)
    iy = np.array([w.y for w in ws])
    ipsi = np.array([w.psi for w in ws])

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        inputs = track_inputs(vehicle, track, np.array([start + v * t]), v)
        q_dot = vehicle.form.velocities(x, inputs.u[0], inputs.u_rate[0])
        history = contact_force_history(x[None, :n], q_dot[None, :], iy, ipsi, inputs.y_rail, inputs.rho_wheelsets,
                                        v, arrays)[0]
        terms = np.array([linear_wheel_rail(linear, j, x[iy[j]], x[ipsi[j]], q_dot[iy[j]], q_dot[ipsi[j]],
                                            inputs.y_rail[0, j], inputs.rho_wheelsets[0, j]) for j in range(len(iy))])
        z = np.concatenate([history[:, OUTPUTS.index("Y")] - terms[:, 0], history[:, OUTPUTS.index("M")] - terms[:, 1]])
        return a @ x + inputs.drive(vehicle, v)[0] + selector @ z

    return rhs

