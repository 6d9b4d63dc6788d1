"""The known inputs of a run along a track: curvature, cant and lateral irregularity (and
their rates) at every station of the vehicle, shared by the linear and the contact march."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel
from express.rail.build import RailLayout
from express.rail.track import Track

__all__ = ["TrackInputs", "rail_layout", "station_index", "track_inputs"]


@dataclass(frozen=True)
class TrackInputs:
    """The known inputs along a run: ``u`` and ``u'`` at every instant, shape (N, m)."""

    u: np.ndarray
    u_rate: np.ndarray
    y_rail: np.ndarray  # (N, n_wheelsets)
    rho_wheelsets: np.ndarray  # (N, n_wheelsets)
    rho_stations: np.ndarray  # (N, n_stations)


def track_inputs(vehicle: VehicleModel, track: Track, distance: np.ndarray, speed: float) -> TrackInputs:
    """Inputs seen by the vehicle when its leading wheelset is at ``distance`` [m].

    Each station ``k`` at ``x_k`` in the vehicle is ``x_lead - x_k`` behind the leading
    wheelset; its curvature, cant and irregularity are read there.  Rates are
    ``v d/ds``.  Flange inputs are left at zero (they are fed back).
    """
    layout = vehicle.layout
    if layout is None:
        raise ArgumentError("the model has no rail data: add a [rail] section to simulate it")
    inputs = list(vehicle.inputs)
    lead = max(w.station for w in vehicle.wheelsets)
    count = distance.size
    u = np.zeros((count, len(inputs)))
    u_rate = np.zeros_like(u)
    # every station at once: one track evaluation per quantity
    behind = lead - np.asarray(vehicle.station_positions, dtype=float)
    s = (distance[:, None] - behind[None, :]).ravel()
    shape = (count, behind.size)
    curvature, curvature_rate, cant, cant_rate = (array.reshape(shape) for array in track.geometry(s))
    for k, station in enumerate(layout.stations):
        u[:, inputs.index(station.curvature_input)] = curvature[:, k]
        u_rate[:, inputs.index(station.curvature_input)] = speed * curvature_rate[:, k]
        u[:, inputs.index(station.cant_input)] = cant[:, k]
        u_rate[:, inputs.index(station.cant_input)] = speed * cant_rate[:, k]
    at_wheelset = [station_index(vehicle, w.name) for w in vehicle.wheelsets]
    rho = np.ascontiguousarray(curvature[:, at_wheelset])
    behind_w = lead - np.array([w.station for w in vehicle.wheelsets])
    s_w = (distance[:, None] - behind_w[None, :]).ravel()
    shape_w = (count, behind_w.size)
    y_rail = np.asarray(track.lateral_irregularity(s_w), dtype=float).reshape(shape_w)
    y_rail_rate = np.asarray(track.lateral_irregularity_rate(s_w), dtype=float).reshape(shape_w)
    for j, name in enumerate(layout.irregularity):
        u[:, inputs.index(name)] = y_rail[:, j]
        u_rate[:, inputs.index(name)] = speed * y_rail_rate[:, j]
    return TrackInputs(u, u_rate, y_rail, rho, curvature)


def rail_layout(vehicle: VehicleModel) -> RailLayout:
    """The vehicle's rail layout (stations, wheelsets, inputs); refused without rail data."""
    if vehicle.layout is None:
        raise ArgumentError("the vehicle has no rail data (no [rail] section with wheelsets)")
    return vehicle.layout


def station_index(vehicle: VehicleModel, body: str) -> int:
    """Index of the station (of the rail layout) that carries ``body``."""
    for index, station in enumerate(rail_layout(vehicle).stations):
        if body in station.bodies:
            return index
    raise ArgumentError(body)
