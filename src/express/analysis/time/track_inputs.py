"""The known inputs of a run along a track: curvature, cant and lateral irregularity (and
their rates) at every station of the vehicle, shared by the linear and the contact march.

The track's other components (vertical level, cross level, gauge: ``docs/track.md``,
"Track components") drive the model's *rail grounds*, found as the ride analysis finds
them (:func:`express.analysis.ride.vehicle.rail_inputs`): a ground ``<B>_rail``,
``<B>_railL``, ``<B>_railR`` or one that holds a single wheelset and nothing else. Along z
a ground takes ``z_v`` (both rails), ``z_v - c/2`` (left) or ``z_v + c/2`` (right); along y
``yR``, ``yR + g/2``, ``yR - g/2``; each read at the station of its body. A model with
one ground under both rails of a wheelset takes the cross level at its wheels' contact
springs instead (:mod:`express.analysis.time.rail_heights`). A component the track carries
but the model does not take is named in one warning per run.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

from express.analysis.time.rail_heights import RailHeights, contact_springs, rail_heights
from express.base.caches import IdentityCache
from express.base.diagnostics import ArgumentError, ModelWarning
from express.numeric.statespace import VehicleModel
from express.rail.build import RailLayout
from express.rail.track import Track

__all__ = ["GroundPlan", "TrackInputs", "ground_plan", "rail_layout", "station_index", "track_inputs"]


@dataclass(frozen=True)
class TrackInputs:
    """The known inputs along a run: ``u`` and ``u'`` at every instant, shape (N, m);
    ``rail`` the cross level's rail heights at the contact springs of a model with one
    ground under both rails of a wheelset (:mod:`express.analysis.time.rail_heights`),
    None otherwise."""

    u: np.ndarray
    u_rate: np.ndarray
    y_rail: np.ndarray  # (N, n_wheelsets)
    rho_wheelsets: np.ndarray  # (N, n_wheelsets)
    rho_stations: np.ndarray  # (N, n_stations)
    rail: RailHeights | None = None

    def drive(self, vehicle: VehicleModel, v: float) -> np.ndarray:
        """The state equations' known forcing ``e = B u + Bd u' (+ G f)`` at every instant
        at speed ``v`` [m/s], shape (N, vehicle.form.size)."""
        e = self.u @ vehicle.input_matrix(v).T + self.u_rate @ vehicle.input_rate_matrix(v).T
        if self.rail is not None:
            e = e + self.rail.forces() @ vehicle.form.force.T
        return e


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
    _rail_ground_inputs(vehicle, track, distance, speed, lead, u, u_rate)
    heights = rail_heights(vehicle, track, distance, speed) if ground_plan(vehicle, track).at_springs else None
    return TrackInputs(u, u_rate, y_rail, rho, curvature, heights)


@dataclass(frozen=True)
class GroundPlan:
    """The rail-ground inputs of a vehicle and what drives them.

    Attributes
    ----------
    columns : numpy.ndarray of int, shape (K,)
        Indices of the rail-ground inputs in ``vehicle.inputs``.
    positions : numpy.ndarray, shape (K,)
        Station x [m] of the body each ground carries.
    mixing : numpy.ndarray, shape (K, 4)
        Coefficient of each component of :data:`~express.rail.track.TRACK_COMPONENTS`.
    ignored : tuple of str
        Components the track carries that the model does not take.
    at_springs : bool
        Whether the cross level is imposed at the contact springs (module docstring).
    """

    columns: np.ndarray
    positions: np.ndarray
    mixing: np.ndarray
    ignored: tuple[str, ...]
    at_springs: bool = False


def ground_plan(vehicle: VehicleModel, track: Track) -> GroundPlan:
    """Which rail-ground inputs the track drives (module docstring); kept per vehicle and
    track, so that the warning for an ignored component comes once."""
    return _PLANS.get_or_make((vehicle, track), lambda: _ground_plan(vehicle, track))


_PLANS: IdentityCache[GroundPlan] = IdentityCache(8)


def _ground_plan(vehicle: VehicleModel, track: Track) -> GroundPlan:
    from express.rail.track import TRACK_COMPONENTS

    layout = rail_layout(vehicle)
    extra = [name for name in vehicle.inputs if name not in layout.inputs]
    columns, positions, mixing = np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros((0, len(TRACK_COMPONENTS)))
    if extra and vehicle.model is not None:  # a model with grounds: find its rail grounds
        from express.analysis.ride.vehicle import rail_inputs

        found = rail_inputs(vehicle)
        keep = [k for k, name in enumerate(found.names) if name not in layout.irregularity]
        columns, positions, mixing = found.columns[keep], found.positions[keep], found.mixing[keep]
    taken = {"alignment"} | {c for j, c in enumerate(TRACK_COMPONENTS) if np.any(mixing[:, j] != 0)}
    at_springs = "cross_level" not in taken and contact_springs(vehicle) is not None
    if at_springs:
        taken.add("cross_level")
    ignored = tuple(c for c in track.applied_components if c not in taken)
    if ignored:
        warnings.warn(f"the track's {', '.join(ignored)} {'is' if len(ignored) == 1 else 'are'} not applied: "
                      f"{vehicle.name} has no rail ground that takes {'it' if len(ignored) == 1 else 'them'} "
                      "(vertical level: a rail ground under each wheelset; cross level: one under each rail, "
                      "<W>_railL and <W>_railR or one on each side, or a vertical contact spring under each wheel; "
                      "gauge: grounds under each rail moving in y; docs/track.md)",
                      ModelWarning, stacklevel=4)
    return GroundPlan(columns, positions, mixing, ignored, at_springs)


def _rail_ground_inputs(vehicle: VehicleModel, track: Track, distance: np.ndarray, speed: float, lead: float,
                        u: np.ndarray, u_rate: np.ndarray) -> None:
    """Add the rail grounds' inputs and rates (``v d/ds``) to ``u``, ``u_rate``, in place."""
    from express.rail.track import TRACK_COMPONENTS

    plan = ground_plan(vehicle, track)
    if plan.columns.size == 0:
        return
    s = (distance[:, None] - (lead - plan.positions)[None, :]).ravel()
    shape = (distance.size, plan.positions.size)
    for j, name in enumerate(TRACK_COMPONENTS):
        weights = plan.mixing[:, j]
        component = track.component(name)
        if not np.any(weights) or name not in track.applied_components:
            continue
        value = np.asarray(component.value(s), dtype=float).reshape(shape)
        rate = np.asarray(component.rate(s), dtype=float).reshape(shape)
        u[:, plan.columns] += value * weights
        u_rate[:, plan.columns] += speed * rate * weights


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
