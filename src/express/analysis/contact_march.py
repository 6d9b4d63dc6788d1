"""Time march with the wheel/rail contact from profile tables (issue 12, item 5).

When a model's conicity comes from profiles (:mod:`express.rail.profile_contact`), the
simulation replaces the dead-band flange spring and the creep saturation by the contact
forces of :func:`express.rail.contact_forces.wheelset_forces`: normal forces from the
geometry, Hertz ellipses, creep forces by FASTSIM (or Polach), elastic rails.  As for the
other nonlinear forces, the linear part of the motion stays in the exactly discretised
``A`` (:mod:`express.analysis.integrator`), and the difference between the contact forces
and the linear wheel/rail terms of the model (:func:`express.rail.wheelrail.
wheelset_terms`, evaluated at the run's speed) is fed back on each wheelset's lateral and
yaw coordinates::

    z_y   = Y(y - yR, psi, y', psi', rho) - Y_lin,   Y_lin = -(K_yy y + K_ypsi psi + C_yy y' + C_ypsi psi') + P_yR yR + P_rho rho
    z_psi = M(...) - M_lin                            (likewise)

so that a small motion runs exactly as the linear model, which is the contact's
linearisation at the node's amplitude (``tests/test_contact_tables.py``).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import sympy as sp
from numba import njit

from express.analysis.integrator import bump_stops
from express.analysis.track_inputs import track_inputs
from express.base.diagnostics import ArgumentError
from express.model.parameters import expression_value
from express.rail.contact_forces import LAWS, OUTPUTS, WORK_COLUMNS, WheelsetContact, wheelset_forces
from express.rail.curve import station_of
from express.rail.profile_contact import contact_terms, profile_nodes
from express.rail.wheelrail import irregularity_input, wheelset_terms

__all__ = [
    "contact_arrays", "contact_force_history", "contact_outputs", "contact_rhs", "linear_coefficients", "march_contact",
]

def _linear_terms(model) -> list[list[tuple[int, object]]]:
    """``(slot, expression)`` of every wheelset's linear wheel/rail terms (cached by model)."""
    cached = _TERMS.get(id(model))
    if cached is not None and cached[0] is model:
        return cached[1]
    rail = model.rail
    nodes = profile_nodes(model)
    by_body = station_of(model)
    terms_of = []
    for wheelset in rail.wheelsets:
        node = nodes.get(wheelset.body)
        curvature = by_body[wheelset.body].curvature_input
        stiffness, damping, forces = wheelset_terms(wheelset, rail.speed, curvature,
                                                    contact_terms(node) if node is not None else None)
        y, psi = f"{wheelset.body}.y", f"{wheelset.body}.rz"
        slot = {(y, y, "K"): 0, (y, psi, "K"): 1, (y, y, "C"): 2, (y, psi, "C"): 3,
                (y, irregularity_input(wheelset), "P"): 4, (y, curvature, "P"): 5,
                (psi, y, "K"): 6, (psi, psi, "K"): 7, (psi, y, "C"): 8, (psi, psi, "C"): 9,
                (psi, irregularity_input(wheelset), "P"): 10, (psi, curvature, "P"): 11}
        terms_of.append([(slot[(row, column, kind)], value)
                         for kind, terms in (("K", stiffness), ("C", damping), ("P", forces))
                         for row, column, value in terms if (row, column, kind) in slot])
    if len(_TERMS) >= 16:
        _TERMS.pop(next(iter(_TERMS)))
    _TERMS[id(model)] = (model, terms_of)
    return terms_of


_TERMS: dict[int, tuple] = {}


def linear_coefficients(vehicle, speed: float) -> np.ndarray:
    """The model's linear wheel/rail terms of every wheelset at ``speed`` [m/s], shape
    (n_wheelsets, 12): ``K_y., K_psi.`` entries on (y, psi), ``C`` on (y', psi'), ``P`` on
    (yR, rho), lateral row then yaw row (see the module docstring)."""
    model = vehicle.model
    rail = model.rail
    if not isinstance(rail.speed, sp.Symbol):
        raise ArgumentError("the contact simulation needs the model's speed as a parameter (rail.speed = \"v\")")
    values = {**vehicle.values, rail.speed.name: float(speed)}
    terms_of = _linear_terms(model)
    out = np.zeros((len(terms_of), 12))
    for j, terms in enumerate(terms_of):
        for index, value in terms:
            out[j, index] += expression_value(value, values)
    return out


def contact_arrays(contacts: list[WheelsetContact], law: str = "fastsim") -> dict:
    """The tables and rail maps of the wheelsets stacked for the compiled march (cached
    for the same contacts)."""
    if law not in LAWS:
        raise ArgumentError(f"creep law {law!r}: use one of {', '.join(LAWS)}")
    key = tuple((id(c.tables), id(c.rail_map), c.wheel_load, c.friction, c.rail_stiffness) for c in contacts)
    held = tuple(item for c in contacts for item in (c.tables, c.rail_map))
    cached = _ARRAYS.get(key)
    if cached is not None and all(a is b for a, b in zip(cached[0], held, strict=True)):
        return {**cached[1], "law": LAWS[law]}
    arrays = _stack(contacts)
    if len(_ARRAYS) >= 16:
        _ARRAYS.pop(next(iter(_ARRAYS)))
    _ARRAYS[key] = (held, arrays)
    return {**arrays, "law": LAWS[law]}


_ARRAYS: dict[tuple, tuple] = {}


def _stack(contacts: list[WheelsetContact]) -> dict:
    count = len(contacts)
    t_len = max(c.tables.data.shape[2] for c in contacts)
    m_len = max(c.rail_map.contact.shape[1] for c in contacts)
    fields = contacts[0].tables.data.shape[0]
    tables = np.zeros((count, 2, t_len, fields))
    maps = np.zeros((count, 2, m_len))
    arrays: dict[str, Any] = {key: np.zeros(count) for key in ("t_start", "t_step", "m_start", "m_step", "load", "friction",
                                                 "shear", "wall")}
    arrays.update(t_count=np.zeros(count, dtype=np.int64), m_count=np.zeros(count, dtype=np.int64))
    for j, contact in enumerate(contacts):
        data, rail_map = contact.tables.data, contact.rail_map.contact
        tables[j, :, : data.shape[2]] = contact.tables.kernel
        maps[j, :, : rail_map.shape[1]] = rail_map
        arrays["t_start"][j], arrays["t_step"][j] = contact.tables.start, contact.tables.step
        arrays["m_start"][j], arrays["m_step"][j] = contact.rail_map.start, contact.rail_map.step
        arrays["t_count"][j], arrays["m_count"][j] = data.shape[2], rail_map.shape[1]
        arrays["load"][j], arrays["friction"][j] = contact.wheel_load, contact.friction
        arrays["shear"][j], arrays["wall"][j] = contact.tables.shear_modulus, contact.wall
    arrays.update(tables=tables, maps=maps)
    return arrays


@njit(cache=True)
def _feedback(x, k, iy, ipsi, ivy, ivpsi, y_rail, rho, speed, tables, t_start, t_step, t_count, maps, m_start,
              m_step, m_count, load, friction, shear, wall, law, linear, work, record, z):
    count = iy.size
    for j in range(count):
        out = record[j]
        y = x[iy[j]]
        psi = x[ipsi[j]]
        y_dot = x[ivy[j]]
        psi_dot = x[ivpsi[j]]
        y_r = y_rail[k, j]
        curvature = rho[k, j]
        wheelset_forces(tables[j], t_start[j], t_step[j], t_count[j], maps[j], m_start[j], m_step[j], m_count[j],
                        load[j], friction[j], shear[j], wall[j], law, y - y_r, psi, y_dot, psi_dot, curvature,
                        speed, work, out)
        c = linear[j]
        lateral = -(c[0] * y + c[1] * psi + c[2] * y_dot + c[3] * psi_dot) + c[4] * y_r + c[5] * curvature
        yaw = -(c[6] * y + c[7] * psi + c[8] * y_dot + c[9] * psi_dot) + c[10] * y_r + c[11] * curvature
        z[j] = out[0] - lateral
        z[count + j] = out[1] - yaw


@njit(cache=True)
def _march(phi, drive, g0, g1, x0, first, last, states, history, iy, ipsi, ivy, ivpsi, y_rail, rho, speed, tables,
           t_start, t_step, t_count, maps, m_start, m_step, m_count, load, friction, shear, wall, law, linear,
           stop_index, stop_coefficient, stop_offset, stop_gap, stop_k, stop_k3):
    """Heun's scheme on the feedback over the exact discretisation, as
    :func:`express.analysis.integrator.march`, with the contact feedback; the contact
    forces of every state go to ``history`` (steps + 1, n_wheelsets, len(OUTPUTS))."""
    size = x0.size
    nz = g0.shape[1]
    stops = stop_gap.size > 0
    wheel = 2 * iy.size
    x = x0.copy()
    z = np.zeros(nz)
    z_next = np.zeros(nz)
    base = np.zeros(size)
    trial = np.zeros(size)
    work = np.zeros((2, WORK_COLUMNS))
    scratch = np.zeros((iy.size, history.shape[2]))
    _feedback(x, first, iy, ipsi, ivy, ivpsi, y_rail, rho, speed, tables, t_start, t_step, t_count, maps, m_start,
              m_step, m_count, load, friction, shear, wall, law, linear, work, history[first], z)
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
        _feedback(trial, k + 1, iy, ipsi, ivy, ivpsi, y_rail, rho, speed, tables, t_start, t_step, t_count, maps,
                  m_start, m_step, m_count, load, friction, shear, wall, law, linear, work, scratch, z_next)
        if stops:
            bump_stops(trial, k + 1, stop_index, stop_coefficient, stop_offset, stop_gap, stop_k, stop_k3, wheel,
                        z_next)
        for i in range(size):
            total = base[i]
            for j in range(nz):
                total += g0[i, j] * z[j] + g1[i, j] * (z_next[j] - z[j])
            x[i] = total
        _feedback(x, k + 1, iy, ipsi, ivy, ivpsi, y_rail, rho, speed, tables, t_start, t_step, t_count, maps,
                  m_start, m_step, m_count, load, friction, shear, wall, law, linear, work, history[k + 1], z)
        if stops:
            bump_stops(x, k + 1, stop_index, stop_coefficient, stop_offset, stop_gap, stop_k, stop_k3, wheel, z)
        for i in range(size):
            states[k + 1, i] = x[i]
    return x


def _stop_arrays(wheel_rail: dict, size: int, steps: int) -> tuple:
    rows = np.asarray(wheel_rail.get("stop_rows", np.zeros((0, size))), dtype=float)
    width = max([1] + [int(np.count_nonzero(row)) for row in rows])
    index = np.zeros((rows.shape[0], width), dtype=np.int64)
    coefficient = np.zeros((rows.shape[0], width))
    for s, row in enumerate(rows):  # the few nonzero terms of each deflection
        nonzero = np.flatnonzero(row)
        index[s, : nonzero.size], coefficient[s, : nonzero.size] = nonzero, row[nonzero]
    return (index, coefficient,
            np.ascontiguousarray(wheel_rail.get("stop_offset", np.zeros((steps + 1, 0))), dtype=float),
            *(np.ascontiguousarray(wheel_rail.get(key, np.zeros(0)), dtype=float)
              for key in ("stop_gap", "stop_k", "stop_k3")))


def march_contact(phi, drive, g0, g1, x0, wheel_rail: dict, contact: dict, linear: np.ndarray, *, progress=None):
    """March with the contact feedback (arguments as :func:`express.analysis.integrator.
    march`; ``contact`` from :func:`contact_arrays`, ``linear`` from
    :func:`linear_coefficients`); returns the states, shape (steps + 1, N), and the
    contact forces of each state (:func:`contact_force_history`)."""
    steps = drive.shape[0]
    states = np.empty((steps + 1, x0.size))
    states[0] = x0
    w, c = wheel_rail, contact
    history = np.zeros((steps + 1, len(w["iy"]), len(OUTPUTS)))
    stops = _stop_arrays(w, x0.size, steps)
    chunk = steps if progress is None else max(1, steps // 50)
    x = np.ascontiguousarray(x0, dtype=float)
    for first in range(0, steps, chunk):
        last = min(steps, first + chunk)
        x = _march(phi, drive, g0, g1, x, first, last, states, history, w["iy"], w["ipsi"], w["ivy"], w["ivpsi"],
                   w["y_rail"], w["rho"], float(w["speed"]), c["tables"], c["t_start"], c["t_step"], c["t_count"],
                   c["maps"], c["m_start"], c["m_step"], c["m_count"], c["load"], c["friction"], c["shear"],
                   c["wall"], int(c["law"]), np.ascontiguousarray(linear), *stops)
        if progress is not None:
            progress(last / steps)
    return states, history


@njit(cache=True)
def _history(y, psi, y_dot, psi_dot, y_rail, rho, speed, tables, t_start, t_step, t_count, maps, m_start, m_step,
             m_count, load, friction, shear, wall, law, result):
    work = np.zeros((2, WORK_COLUMNS))
    for k in range(y.shape[0]):
        for j in range(y.shape[1]):
            wheelset_forces(tables[j], t_start[j], t_step[j], t_count[j], maps[j], m_start[j], m_step[j],
                            m_count[j], load[j], friction[j], shear[j], wall[j], law, y[k, j] - y_rail[k, j],
                            psi[k, j], y_dot[k, j], psi_dot[k, j], rho[k, j], speed, work, result[k, j])


def contact_force_history(q, q_dot, iy, ipsi, y_rail, rho, speed, contact: dict) -> np.ndarray:
    """:data:`~express.rail.contact_forces.OUTPUTS` of every wheelset at every step,
    shape (steps, n_wheelsets, len(OUTPUTS))."""
    c = contact
    y, psi = np.ascontiguousarray(q[:, iy]), np.ascontiguousarray(q[:, ipsi])
    y_dot, psi_dot = np.ascontiguousarray(q_dot[:, iy]), np.ascontiguousarray(q_dot[:, ipsi])
    result = np.zeros((q.shape[0], len(iy), len(OUTPUTS)))
    _history(y, psi, y_dot, psi_dot, np.ascontiguousarray(y_rail), np.ascontiguousarray(rho), float(speed),
             c["tables"], c["t_start"], c["t_step"], c["t_count"], c["maps"], c["m_start"], c["m_step"], c["m_count"],
             c["load"], c["friction"], c["shear"], c["wall"], int(c["law"]), result)
    return result


def contact_outputs(history: np.ndarray, wheel_loads, y_relative: np.ndarray) -> dict[str, np.ndarray]:
    """The simulation's wheelset outputs from :func:`contact_force_history`: ``Q{n}`` the
    lateral force from the rail on the flanging wheel (the one with the larger contact
    angle), ``QP{n}`` over its static load, ``Qtot{n}`` on the wheelset, ``flange{n}``
    the lateral component of the flanging wheel's normal force, ``dy{n}`` how far its
    rail gives way (``y_relative``, the wheelset's displacement from the track, less the
    contact's position), ``NL{n}``, ``NR{n}`` the normal forces [N]."""
    index = {name: i for i, name in enumerate(OUTPUTS)}
    outputs = {}
    for j in range(history.shape[1]):
        h = history[:, j]
        left = h[:, index["angle_left"]] >= h[:, index["angle_right"]]
        wheel = np.where(left, h[:, index["Y_left"]], h[:, index["Y_right"]])
        normal = np.where(left, h[:, index["N_left"]], h[:, index["N_right"]])
        angle = np.where(left, h[:, index["angle_left"]], h[:, index["angle_right"]])
        side = np.where(left, 1.0, -1.0)
        u = np.where(left, h[:, index["u_left"]], h[:, index["u_right"]])
        n = j + 1
        outputs[f"Q{n}"] = wheel
        outputs[f"QP{n}"] = wheel / wheel_loads[j]
        outputs[f"Qtot{n}"] = h[:, index["Y"]]
        outputs[f"flange{n}"] = -side * normal * np.sin(angle)
        outputs[f"NL{n}"] = h[:, index["N_left"]]
        outputs[f"NR{n}"] = h[:, index["N_right"]]
        outputs[f"dy{n}"] = y_relative[:, j] - u
    return outputs


def contact_rhs(vehicle, track, contacts: list[WheelsetContact], *, speed: float | None = None, start: float = 0.0,
                law: str = "fastsim"):
    """The contact simulation's equations as ``f(t, x)`` for reference integrations
    (``scipy.integrate.solve_ivp``); bump stops are not included."""
    v = float(vehicle.speed if speed is None else speed)
    a, b, bd = vehicle.state_matrix(v), vehicle.input_matrix(v), vehicle.input_rate_matrix(v)
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
        y_r, rho = inputs.y_rail[0], inputs.rho_wheelsets[0]
        c = linear
        q = x[:n]
        lateral = -(c[:, 0] * q[iy] + c[:, 1] * q[ipsi] + c[:, 2] * q_dot[iy] + c[:, 3] * q_dot[ipsi]) + c[:, 4] * y_r + c[:, 5] * rho
        yaw = -(c[:, 6] * q[iy] + c[:, 7] * q[ipsi] + c[:, 8] * q_dot[iy] + c[:, 9] * q_dot[ipsi]) + c[:, 10] * y_r + c[:, 11] * rho
        z = np.concatenate([history[:, 0] - lateral, history[:, 1] - yaw])
        return a @ x + b @ inputs.u[0] + bd @ inputs.u_rate[0] + selector @ z

    return rhs

