"""Twisted track: a cross-level ramp as track geometry and the quasi-static wheel loads on it.

A twist is the gradient of the cross level ``c(s) = z_R - z_L`` along the track
(``docs/track.md``, "Track components"): :func:`twist_ramp` is a ramp of a given gradient
[m/m] over a given length, held at its end value after it (a cant run-in without
curvature), :func:`twisted_track` a straight track carrying it.

:func:`quasi_static_loads` is the static solution of the linear model with the track's
inputs at one position of the vehicle, ``K q = P(v) u`` (no inertia, no damping: a slow
passage), and each wheel's load change from the model's own wheel-on-rail springs
(:func:`express.rail.vertical_contact.vertical_contacts`)::

    dQ = -k_z (u_wheel,z - u_rail,z)        (+ more load)

``dQ / Q0`` with ``Q0`` the model's static wheel load (``[rail.wheel_rail] wheel_load``)
is the quasi-static wheel unloading of EN 14363's safety against derailment on twisted
track (the standard's twist and limits: :mod:`express.analysis.twist.standard`).

A model whose rail grounds take no cross level (one ground under both rails of a
wheelset, as the bundled wagon's) is twisted by :func:`rail_height_loads`: the rail
heights imposed at each wheel's own contact spring, ``dQ = -k_z (d q + kappa r)`` with
``kappa`` the spring's coefficient on its ground's vertical input and ``r`` the rail's
height, and ``K q = -sum k_z d kappa r`` (the same equations as a ground under each rail).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.analysis.time.track_inputs import track_inputs
from express.base.arguments import si_argument
from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel
from express.rail.track import Straight, Track
from express.rail.track.irregularity import MAX_LATERAL_IRREGULARITY, ProfileIrregularity
from express.rail.vertical_contact import vertical_contacts

__all__ = [
    "TwistLoads",
    "cross_level_heights",
    "quasi_static_loads",
    "rail_height_loads",
    "takes_cross_level",
    "twist_passage",
    "twist_ramp",
    "twisted_track",
]


def twist_ramp(twist: float, length: float, start: float = 0.0) -> ProfileIrregularity:
    """A cross-level ramp: ``c = twist (s - start)`` on ``[start, start + length]``, 0
    before, ``twist length`` after.

    Parameters
    ----------
    twist : float
        Gradient of the cross level [m/m] (3 mm/m is 0.003); + the right rail rising.
    length : float
        Length of the ramp [m], > 0.
    start : float
        Where it starts [m].

    Raises
    ------
    ArgumentError
        For a non-finite value, a length <= 0, or an end cross level beyond
        :data:`~express.rail.track.irregularity.MAX_LATERAL_IRREGULARITY` (0.1 m).
    """
    if not all(np.isfinite(x) for x in (twist, length, start)) or length <= 0:
        raise ArgumentError(f"twist ramp: twist, length and start must be finite and length > 0, got "
                            f"{twist!r}, {length!r}, {start!r}")
    if abs(twist * length) > MAX_LATERAL_IRREGULARITY:
        raise ArgumentError(f"twist ramp: {twist * 1e3:g} mm/m over {length:g} m reaches a cross level of "
                            f"{abs(twist * length) * 1e3:.4g} mm, more than {MAX_LATERAL_IRREGULARITY * 1e3:g} mm")
    return ProfileIrregularity(np.array([start, start + length]), np.array([0.0, twist * length]),
                               source=f"twist ramp {twist * 1e3:g} mm/m over {length:g} m")


def twisted_track(twist: float, length: float, lead_in: float = 50.0, lead_out: float = 50.0) -> Track:
    """A straight track of ``lead_in + length + lead_out`` [m] with :func:`twist_ramp`
    (``twist`` [m/m] over ``length`` [m]) starting at ``lead_in``."""
    return Track((Straight(lead_in + length + lead_out),), cross_level=twist_ramp(twist, length, lead_in))


@dataclass(frozen=True)
class TwistLoads:
    """Quasi-static wheel loads at one position.

    Attributes
    ----------
    distance : float
        Position of the leading wheelset [m].
    wheelsets : tuple of str
    delta_q : numpy.ndarray, shape (n_wheelsets, 2)
        Load change of the (left, right) wheel [N], + more load; NaN where the model has
        no wheel-on-rail spring.
    wheel_load : numpy.ndarray, shape (n_wheelsets,)
        Static wheel load Q0 [N].
    q : numpy.ndarray, shape (n,)
        The static displacements [m, rad] under the model's inputs (without the part of a
        cross level imposed at the contact springs, :func:`rail_height_loads`).
    """

    distance: float
    wheelsets: tuple[str, ...]
    delta_q: np.ndarray
    wheel_load: np.ndarray
    q: np.ndarray

    @property
    def ratio(self) -> np.ndarray:
        """``dQ / Q0`` of each wheel, shape (n_wheelsets, 2)."""
        return self.delta_q / self.wheel_load[:, None]

    @property
    def largest_unloading(self) -> float:
        """The largest ``-dQ / Q0`` over the wheels (0 if none unloads)."""
        return float(max(0.0, np.nanmax(-self.ratio)))


def twist_passage(vehicle: VehicleModel, track: Track, step: float = 0.5,
                  speed: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`quasi_static_loads` at every ``step`` [m] of the leading wheelset from 0 to
    the track's length plus the vehicle's wheelbase (every wheel over the whole track).

    Returns
    -------
    distance : numpy.ndarray, shape (N,)
        Positions of the leading wheelset [m].
    delta_q : numpy.ndarray, shape (N, n_wheelsets, 2)
        Load change of the (left, right) wheels [N].
    wheel_load : numpy.ndarray, shape (n_wheelsets,)
        Q0 [N].
    """
    if not (np.isfinite(step) and step > 0):
        raise ArgumentError(f"twist passage: step must be > 0 m, got {step!r}")
    stations = [w.station for w in vehicle.wheelsets]
    distance = np.arange(0.0, track.length + max(stations) - min(stations) + step / 2, step)
    v = vehicle.speed if speed is None else speed
    u = track_inputs(vehicle, track, distance, v).u
    try:
        q = np.linalg.solve(vehicle.stiffness, vehicle.forcing(v) @ u.T).T
    except np.linalg.LinAlgError:
        raise ArgumentError(f"{vehicle.name}: K is singular, no static solution on the twist") from None
    springs = _springs(vehicle)
    delta = np.full((distance.size, len(springs), 2), np.nan)
    for i, pair in enumerate(springs):
        for side, spring in enumerate(pair):
            if spring is not None:
                delta[:, i, side] = -spring.stiffness * (q @ spring.dofs + u @ spring.inputs)
    if "cross_level" in track.applied_components and not takes_cross_level(vehicle, track):
        delta += rail_height_loads(vehicle, cross_level_heights(vehicle, track, distance))
    return distance, delta, np.array([w.wheel_load for w in vehicle.wheelsets], dtype=float)


def cross_level_heights(vehicle: VehicleModel, track: Track, distance: np.ndarray) -> np.ndarray:
    """The rail heights ``(-c/2, +c/2)`` of the track's cross level ``c`` under every
    wheelset with the leading one at each ``distance`` [m], shape (N, n_wheelsets, 2)."""
    stations = np.array([w.station for w in vehicle.wheelsets], dtype=float)
    s = np.asarray(distance, dtype=float)[:, None] - (stations.max() - stations)[None, :]
    c = np.asarray(track.component("cross_level").value(s.ravel()), dtype=float).reshape(s.shape)
    return np.stack([-c / 2, c / 2], axis=2)


def _springs(vehicle: VehicleModel) -> list:
    names = [w.name for w in vehicle.wheelsets]
    springs = vertical_contacts(vehicle.model, vehicle.values, names, vehicle.dofs, vehicle.inputs)
    if not any(spring is not None for pair in springs for spring in pair):
        raise ArgumentError(f"{vehicle.name}: no wheel-on-rail vertical spring (an element along z from a wheelset "
                            "to a ground): no wheel load on the twist")
    return springs


def quasi_static_loads(vehicle: VehicleModel, track: Track, distance: float, speed: float | None = None) -> TwistLoads:
    """The static wheel loads with the leading wheelset at ``distance`` [m] (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        A rail vehicle whose wheels stand on vertical springs to rail grounds.
    track : Track
    distance : float or quantity
        Position of the leading wheelset [m] (a number is SI; ``"120 m"``, pint).
    speed : float or quantity, optional
        [m/s] for the cant-deficiency terms of ``P(v)`` on a curve; default the model's.

    Raises
    ------
    ArgumentError
        If the model has no wheel-on-rail spring (no wheel load to give) or ``K`` is singular.
    """
    v = vehicle.speed if speed is None else si_argument(speed, "speed", "speed")
    distance = si_argument(distance, "length", "distance")
    inputs = track_inputs(vehicle, track, np.array([distance]), v).u[0]
    try:
        q = np.linalg.solve(vehicle.stiffness, vehicle.forcing(v) @ inputs)
    except np.linalg.LinAlgError:
        raise ArgumentError(f"{vehicle.name}: K is singular, no static solution on the twist") from None
    names = [w.name for w in vehicle.wheelsets]
    springs = _springs(vehicle)
    delta = np.full((len(names), 2), np.nan)
    for i, pair in enumerate(springs):
        for side, spring in enumerate(pair):
            if spring is not None:
                delta[i, side] = -spring.stiffness * (spring.dofs @ q + spring.inputs @ inputs)
    if "cross_level" in track.applied_components and not takes_cross_level(vehicle, track):
        delta = delta + rail_height_loads(vehicle, cross_level_heights(vehicle, track, np.array([float(distance)])))[0]
    loads = np.array([w.wheel_load for w in vehicle.wheelsets], dtype=float)
    return TwistLoads(float(distance), tuple(names), delta, loads, q)


def takes_cross_level(vehicle: VehicleModel, track: Track) -> bool:
    """Whether the track's cross level reaches the wheels through the model's rail grounds
    (a ground under each rail); else :func:`rail_height_loads` imposes it."""
    import warnings

    from express.analysis.time.track_inputs import ground_plan

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        plan = ground_plan(vehicle, track)
    return "cross_level" not in plan.ignored and not plan.at_springs


def rail_height_loads(vehicle: VehicleModel, heights: np.ndarray) -> np.ndarray:
    """The quasi-static load change of every wheel with its rail raised by ``heights``
    (module docstring): the rail height imposed at the wheel's contact spring.

    Parameters
    ----------
    vehicle : VehicleModel
        Wheels on vertical springs to grounds with a vertical input (``<G>.z``).
    heights : numpy.ndarray, shape (N, n_wheelsets, 2)
        Height of the (left, right) rail under each wheel [m], + up.

    Returns
    -------
    numpy.ndarray, shape (N, n_wheelsets, 2)
        ``dQ`` [N], + more load; NaN where the model has no wheel-on-rail spring.

    Raises
    ------
    ArgumentError
        For a shape that does not fit, a spring whose ground has no vertical input, or a
        singular ``K``.
    """
    heights = np.asarray(heights, dtype=float)
    springs = _springs(vehicle)
    if heights.ndim != 3 or heights.shape[1:] != (len(springs), 2):
        raise ArgumentError(f"rail heights: shape (N, {len(springs)}, 2) needed, got {heights.shape}")
    vertical = np.array([name.endswith(".z") for name in vehicle.inputs])
    forcing = np.zeros((heights.shape[0], vehicle.n))
    kappa = np.zeros((len(springs), 2))
    for i, pair in enumerate(springs):
        for side, spring in enumerate(pair):
            if spring is None:
                continue
            kappa[i, side] = float(np.sum(spring.inputs[vertical]))
            if kappa[i, side] == 0.0:
                raise ArgumentError(f"{vehicle.name}: the wheel-on-rail spring {spring.element} has no ground with a "
                                    "vertical input (<G>.z): no rail height reaches it")
            forcing -= np.outer(spring.stiffness * kappa[i, side] * heights[:, i, side], spring.dofs)
    try:
        q = np.linalg.solve(vehicle.stiffness, forcing.T).T
    except np.linalg.LinAlgError:
        raise ArgumentError(f"{vehicle.name}: K is singular, no static solution on the twist") from None
    delta = np.full(heights.shape, np.nan)
    for i, pair in enumerate(springs):
        for side, spring in enumerate(pair):
            if spring is not None:
                delta[:, i, side] = -spring.stiffness * (q @ spring.dofs + kappa[i, side] * heights[:, i, side])
    return delta
