"""The wheel/rail outputs (:class:`~express.analysis.curving.outputs.WheelRailOutputs`) of
vehicle states along a track: one function for a steady state and a time history alike.

Two contact models give the per-wheel forces:

* the **contact tables** of the profiles (:mod:`express.forces.contact`): each
  wheel's lateral and longitudinal force, contact position and angle come from the
  compiled contact of :mod:`express.rail.contact_forces`, at the wheel loads the time
  march uses (the static loads with the quasi-static load transfer,
  :func:`estimated_wheel_loads`);
* the **dead-band** model of the paper (:mod:`express.rail.nonlinear`): each wheel takes
  half of the wheelset's (saturated) lateral creep force, the flanging wheel (the left one
  when the wheelset is pressed left past the clearance) the flange force too; the
  longitudinal creep forces are ``±f1 xi_x`` (saturated); the contact position is the
  wheelset's displacement from the rail; the contact angle ``atan(Gamma)`` on the
  tread and ``flange_angle`` in flange contact.

The vertical loads of a lateral-only model are the quasi-static estimate of
:mod:`express.rail.load_transfer`, each body feeling the curvature and cant at its
station and displaced by its lateral coordinate less the track's chord under its
wheelsets (the suspension's roll).
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from express.analysis.curving.outputs import WheelRailOutputs
from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel
from express.rail.contact_forces import ContactSet
from express.rail.load_transfer import (
    BodyLoads,
    body_loads,
    support_line_offsets,
    track_plane_accelerations,
    wheel_loads,
)
from express.rail.nonlinear import linear_creepages, wheelset_forces

if TYPE_CHECKING:
    from express.forces.contact import WheelLoadModel

__all__ = ["DEFAULT_FLANGE_ANGLE", "estimated_loads", "estimated_wheel_loads", "march_wheel_loads", "vehicle_body_loads",
           "wheel_rail_outputs"]

#: Flange angle of the dead-band model's flange contact [rad] (70 degrees, the flank of
#: S1002 and of most standard profiles); used for its contact angle and Nadal's limit.
DEFAULT_FLANGE_ANGLE = math.radians(70.0)


def vehicle_body_loads(vehicle: VehicleModel) -> BodyLoads:
    """:func:`express.rail.load_transfer.body_loads` of ``vehicle``'s model."""
    if vehicle.model is None:
        raise ArgumentError("the vehicle has no model to take its masses from")
    return body_loads(vehicle.model, vehicle.values, [w.b for w in vehicle.wheelsets])


def _body_stations(vehicle: VehicleModel) -> list[int]:
    layout = vehicle.layout
    if layout is None or vehicle.model is None:
        raise ArgumentError("the vehicle has no rail data (no [rail] section with wheelsets)")
    index = {body: k for k, station in enumerate(layout.stations) for body in station.bodies}
    return [index[body.id] for body in vehicle.model.bodies]


def estimated_loads(vehicle: VehicleModel, q: np.ndarray, inputs, speed: float, loads: BodyLoads | None = None):
    """Quasi-static wheel loads (:func:`express.rail.load_transfer.wheel_loads`) at every
    instant, each body at its station's curvature and cant, displaced by its lateral
    coordinate; ``inputs`` a :class:`~express.analysis.time.simulate.TrackInputs`.

    Returns
    -------
    WheelLoads
        Left and right, shape (N, n_wheelsets).
    """
    loads = vehicle_body_loads(vehicle) if loads is None else loads
    layout = vehicle.layout
    assert layout is not None and vehicle.model is not None
    stations = _body_stations(vehicle)
    names = list(vehicle.inputs)
    cant = inputs.u[:, [names.index(layout.cant[k]) for k in stations]]
    curvature = inputs.rho_stations[:, stations]
    a_y, a_n = track_plane_accelerations(speed, curvature, cant, _value(vehicle, "cant_base"), _value(vehicle, "gravity"))
    # each body's displacement from the track centre line under its wheelsets (the chord)
    position = vehicle.station_positions[stations]
    under = position[[loads.bodies.index(w.name) for w in vehicle.wheelsets]]
    offsets = -support_line_offsets(loads.shares, position, under, curvature)
    for i, body in enumerate(vehicle.model.bodies):
        if f"{body.id}.y" in vehicle.dofs:
            offsets[:, i] += q[:, vehicle.dof_index(f"{body.id}.y")]
    return wheel_loads(loads, a_y, a_n, offsets)


def _value(vehicle: VehicleModel, field: str) -> float:
    from express.model.parameters import expression_value

    assert vehicle.model is not None and vehicle.model.rail is not None
    return expression_value(getattr(vehicle.model.rail, field), vehicle.values)


def estimated_wheel_loads(vehicle, inputs, speed: float, static: np.ndarray) -> WheelLoadModel:
    """The quasi-static wheel loads of :func:`express.analysis.curving.measure.
    estimated_loads` along ``inputs`` (a :class:`~express.analysis.time.track_inputs.
    TrackInputs`) at ``speed`` [m/s], as changes of the static loads ``static`` [N]; the
    estimate is linear in the bodies' lateral displacements (the wheelsets' own excepted:
    their contact points move with them), whose gains are taken one body at a time."""
    from express.forces.contact import WheelLoadModel, unpressed

    body = vehicle_body_loads(vehicle)
    count = inputs.u.shape[0]
    n = vehicle.n
    base = estimated_loads(vehicle, np.zeros((count, n)), inputs, speed, body)
    straight = replace(inputs, u=np.zeros_like(inputs.u), rho_stations=np.zeros_like(inputs.rho_stations))
    level = estimated_loads(vehicle, np.zeros((count, n)), straight, speed, body)
    wheelsets = {w.name for w in vehicle.wheelsets}
    # a wheelset's contact points move with them: its own displacement shifts no load
    bodies = [i for i, name in enumerate(body.bodies) if f"{name}.y" in vehicle.dofs and name not in wheelsets]
    places = np.array([vehicle.dof_index(f"{body.bodies[i]}.y") for i in bodies], dtype=np.int64)
    gain = np.zeros((count, places.size, len(vehicle.wheelsets), 2))
    for i, place in enumerate(places):
        unit = np.zeros((count, n))
        unit[:, place] = 1.0
        shifted = estimated_loads(vehicle, unit, inputs, speed, body)
        half = 0.5 * ((shifted.left - shifted.right) - (base.left - base.right))
        gain[:, i, :, 0], gain[:, i, :, 1] = half, -half
    common = 0.5 * ((base.left + base.right) - (level.left + level.right))
    half_difference = 0.5 * ((base.left - base.right) - (level.left - level.right))
    offset = np.stack([common + half_difference, common - half_difference], axis=2)
    return WheelLoadModel(np.ascontiguousarray(static, dtype=float), offset, places, gain,
                          *unpressed(len(vehicle.wheelsets)))


def march_wheel_loads(vehicle: VehicleModel, inputs, speed: float, static: np.ndarray) -> tuple[WheelLoadModel, str]:
    """The wheel loads of the contact tables and where they come from: the model's own
    vertical contact springs when every wheel has one
    (:func:`express.forces.contact.dynamic_wheel_loads`, ``"dynamic"``; plus the
    change of the load normal to the track plane, which a linear model does not carry),
    else the quasi-static estimate (:func:`estimated_wheel_loads`,
    ``"quasi-static estimate"``)."""
    from express.forces.contact import dynamic_wheel_loads

    dynamic = dynamic_wheel_loads(vehicle, inputs, static)
    if dynamic is None:
        return estimated_wheel_loads(vehicle, inputs, speed, static), "quasi-static estimate"
    # the linear model carries the weight g; the load normal to a canted track plane is
    # m a_n (cant and centrifugal force, second order in the cant angle): add its change
    body = vehicle_body_loads(vehicle)
    rest = np.zeros((inputs.u.shape[0], vehicle.n))
    level = replace(inputs, u=np.zeros_like(inputs.u), rho_stations=np.zeros_like(inputs.rho_stations))
    base, flat = estimated_loads(vehicle, rest, inputs, speed, body), estimated_loads(vehicle, rest, level, speed, body)
    common = 0.5 * ((base.left + base.right) - (flat.left + flat.right))
    return dynamic._replace(offset=dynamic.offset + common[:, :, None]), "dynamic"


def _deadband_forces(vehicle: VehicleModel, q, q_dot, inputs, speed: float, flange_angle: float):
    ws = vehicle.wheelsets
    iy, ipsi = [w.y for w in ws], [w.psi for w in ws]
    y, psi = q[:, iy], q[:, ipsi]
    forces = wheelset_forces(y, psi, q_dot[:, iy], q_dot[:, ipsi], inputs.y_rail, inputs.rho_wheelsets, speed, ws)
    half = 0.5 * forces["lateral_creep"]
    flange = forces["flange"]
    lateral = np.stack([half + np.where(forces["dy"] > 0, flange, 0.0), half + np.where(forces["dy"] < 0, flange, 0.0)],
                       axis=2)
    conicity = np.array([w.conicity for w in ws])
    r0, b = np.array([w.r0 for w in ws]), np.array([w.b for w in ws])
    xi_x, _ = linear_creepages(y, psi, q_dot[:, iy], q_dot[:, ipsi], inputs.y_rail, inputs.rho_wheelsets, speed,
                               conicity, r0, b)
    f1 = np.array([w.f1 for w in ws])
    longitudinal = np.stack([f1 * xi_x * forces["factor"], -f1 * xi_x * forces["factor"]], axis=2)
    relative = y - inputs.y_rail
    position = np.stack([relative, relative], axis=2)
    tread = np.broadcast_to(np.arctan(conicity), relative.shape)
    angle = np.stack([np.where(forces["dy"] > 0, flange_angle, tread), np.where(forces["dy"] < 0, flange_angle, tread)],
                     axis=2)
    return lateral, longitudinal, position, angle


def _table_outputs(vehicle: VehicleModel, q, q_dot, inputs, speed: float, contact: ContactSet) -> WheelRailOutputs:
    """The record of the contact tables with the wheel loads the time march uses
    (:func:`estimated_wheel_loads`)."""
    from express.analysis.time.contact_march import contact_force_history, contact_wheel_outputs
    from express.forces.contact import wheel_loads_history

    ws = vehicle.wheelsets
    model, kind = march_wheel_loads(vehicle, inputs, speed, contact.wheel_load)
    iy, ipsi = [w.y for w in ws], [w.psi for w in ws]
    # the loads read the coordinates and, under damped contact springs, their velocities
    states = np.hstack([q, q_dot[:, vehicle.form.massive]])
    loads = wheel_loads_history(model, states, contact, q[:, iy] - inputs.y_rail, q[:, ipsi])
    history = contact_force_history(q, q_dot, iy, ipsi, inputs.y_rail, inputs.rho_wheelsets, speed, contact, loads)
    return contact_wheel_outputs(vehicle, history, q, kind)


def wheel_rail_outputs(vehicle: VehicleModel, q: np.ndarray, q_dot: np.ndarray, inputs, speed: float, *,
                       contact: ContactSet | None = None, flange_angle: float = DEFAULT_FLANGE_ANGLE) -> WheelRailOutputs:
    """The wheel/rail outputs of states ``q``, ``q_dot`` (shape (N, n)) on ``inputs``.

    Parameters
    ----------
    vehicle : VehicleModel
    q, q_dot : numpy.ndarray, shape (N, n)
        Coordinates [m, rad] and their rates.
    inputs : TrackInputs
        The track seen by the vehicle at each instant
        (:func:`express.analysis.time.simulate.track_inputs`).
    speed : float
        [m/s].
    contact : ContactSet, optional
        The stacked contact tables (:func:`express.forces.contact.contact_arrays`);
        without them the dead-band model's forces are used.
    flange_angle : float
        The dead-band model's flange contact angle [rad].
    """
    q, q_dot = np.atleast_2d(q), np.atleast_2d(q_dot)
    if contact is not None:
        return _table_outputs(vehicle, q, q_dot, inputs, speed, contact)
    lateral, longitudinal, position, angle = _deadband_forces(vehicle, q, q_dot, inputs, speed, flange_angle)
    body = vehicle_body_loads(vehicle)
    loads = estimated_loads(vehicle, q, inputs, speed, body)
    return WheelRailOutputs(
        vertical_load=np.stack([loads.left, loads.right], axis=2), lateral_force=lateral,
        longitudinal_force=longitudinal, contact_position=position, contact_angle=angle,
        angle_of_attack=q[:, [w.psi for w in vehicle.wheelsets]], static_load=body.static_loads(_value(vehicle, "gravity")),
        loads="quasi-static estimate",
    )
