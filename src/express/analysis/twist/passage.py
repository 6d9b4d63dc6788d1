"""The standard twist by a slow time run: for a vehicle with friction elements or
characteristics, whose suspension the linear static solution sees stuck or at its tangent.

A Y25 wagon's Lenoir-link friction is stuck in ``K`` (its pre-slip stiffness in series with
the coil springs): on a twist the static solution ``K q = P u`` of such a vehicle twists the
bogie as if it had no friction slider and the wheels lift. On the track the friction slips.
:func:`twist_run_loads` therefore drives the vehicle at walking pace over a test track built
for it, :func:`standard_twist_track`: a cross level piecewise linear through the standard
twist's value at each wheelset (:class:`~express.analysis.twist.standard.StandardTwist`),
placed so that with the leading wheelset at the track's end every wheelset stands at its
own value, reached from level track through a run-in. The wheels' load changes are read at
that end (a time run of :func:`express.analysis.time.simulate.simulate`, its nonlinear
elements and contact as in any run; the cross level at the contact springs of a model with
one ground under both rails, :mod:`express.analysis.time.rail_heights`).

The path matters for friction (hysteresis): this is the path of a vehicle running onto a
twisted test track, trailing wheelset last. At :data:`PASSAGE_SPEED` (1 m/s) the dampers'
share is first order in the speed (``tests/test_twist_passage.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.analysis.twist.standard import StandardTwist
from express.numeric.statespace import VehicleModel
from express.rail.track import Straight, Track
from express.rail.track.irregularity import ProfileIrregularity

__all__ = ["PASSAGE_SPEED", "RUN_IN", "TwistRun", "run_passage", "slips", "standard_twist_track", "twist_run_loads"]

#: Speed of the passage [m/s] and length of the run-in from level track [m].
PASSAGE_SPEED, RUN_IN = 1.0, 10.0


def standard_twist_track(vehicle: VehicleModel, twist: StandardTwist) -> tuple[Track, float]:
    """The test track of the module docstring and the leading wheelset's end position [m]."""
    stations = np.array([w.station for w in vehicle.wheelsets], dtype=float)
    end = 2.0 * RUN_IN + float(stations.max() - stations.min())
    at = end - (stations.max() - stations)
    order = np.argsort(at, kind="stable")
    s = np.concatenate([[at[order[0]] - RUN_IN], at[order]])
    c = np.concatenate([[0.0], np.asarray(twist.cross_level, dtype=float)[order]])
    keep = np.concatenate([[True], np.diff(s) > 1e-9])  # wheelsets at one station: one point
    profile = ProfileIrregularity(s[keep], c[keep], source=f"standard twist ({twist.describe()})")
    return Track((Straight(end + RUN_IN),), cross_level=profile), end


@dataclass(frozen=True)
class TwistRun:
    """The wheels' load changes at the end of the slow passage.

    Attributes
    ----------
    delta_q : numpy.ndarray, shape (n_wheelsets, 2)
        [N] of the (left, right) wheels, + more load, from the run at ``dt``.
    speed, dt : float
        Of the run [m/s, s].
    step_change : float
        The largest change of any wheel's ``dQ/Q0`` from the run at ``2 dt`` to the run at
        ``dt``: the step's error estimate.
    """

    delta_q: np.ndarray
    speed: float
    dt: float
    step_change: float

    @property
    def method(self) -> str:
        """How the loads were found, for the report."""
        return (f"slow time run at {self.speed:g} m/s, friction slipping; step {self.dt * 1e3:g} ms, "
                f"{self.step_change:.2g} in dQ/Q0 from {2 * self.dt * 1e3:g} ms")


def twist_run_loads(vehicle: VehicleModel, twist: StandardTwist, *, speed: float = PASSAGE_SPEED,
                    dt: float = 0.0025) -> TwistRun:
    """The wheel loads of ``vehicle`` at the end of the slow passage onto ``twist``, the run
    at ``dt`` checked against one at ``2 dt``.

    Parameters
    ----------
    vehicle : VehicleModel
        Wheels on vertical contact springs (their loads are read).
    twist : StandardTwist
    speed : float
        [m/s].
    dt : float
        Time step [s].
    """
    track, end = standard_twist_track(vehicle, twist)
    coarse, fine = (_end_loads(vehicle, track, end, speed, step) for step in (2 * dt, dt))
    loads = np.array([w.wheel_load for w in vehicle.wheelsets], dtype=float)[:, None]
    change = float(np.nanmax(np.abs(fine - coarse) / loads))
    return TwistRun(fine, speed, dt, change)


def run_passage(vehicle: VehicleModel, track: Track, step: float = 0.5, *, speed: float = PASSAGE_SPEED,
                dt: float = 0.0025) -> tuple[np.ndarray, np.ndarray, np.ndarray, TwistRun]:
    """:func:`~express.analysis.twist.loads.twist_passage` by a slow time run: the wheels'
    load changes every ``step`` [m] of the leading wheelset from 0 to the track's length
    plus the wheelbase, from one run at ``dt`` (checked against ``2 dt``).

    Returns
    -------
    distance : numpy.ndarray, shape (N,)
        Positions of the leading wheelset [m].
    delta_q : numpy.ndarray, shape (N, n_wheelsets, 2)
        [N] of the (left, right) wheels.
    wheel_load : numpy.ndarray, shape (n_wheelsets,)
        Q0 [N].
    run : TwistRun
        The last position's loads, with the step's change over the whole passage.
    """
    stations = [w.station for w in vehicle.wheelsets]
    end = track.length + max(stations) - min(stations)
    distance = np.arange(0.0, end + step / 2, step)
    coarse, fine = (_loads(vehicle, track, end, speed, h, distance) for h in (2 * dt, dt))
    loads = np.array([w.wheel_load for w in vehicle.wheelsets], dtype=float)
    change = float(np.nanmax(np.abs(fine - coarse) / loads[None, :, None]))
    return distance, fine, loads, TwistRun(fine[-1], speed, dt, change)


def _end_loads(vehicle: VehicleModel, track: Track, end: float, speed: float, dt: float) -> np.ndarray:
    return _loads(vehicle, track, end, speed, dt, np.array([end]))[-1]


def _loads(vehicle: VehicleModel, track: Track, end: float, speed: float, dt: float, at: np.ndarray) -> np.ndarray:
    """The wheels' load changes of a run to ``end`` at the leading wheelset's positions
    ``at`` (the nearest step), shape (len(at), n_wheelsets, 2)."""
    import warnings

    from express.analysis.time.simulate import simulate

    with warnings.catch_warnings():  # the step's resolution: checked by the caller's second run
        warnings.filterwarnings("ignore", message="the time step .* does not resolve", category=UserWarning)
        run = simulate(vehicle, track, speed=speed, dt=dt, end=end, progress=False)
    rows = np.clip(np.searchsorted(run.distance, at - 0.5 * speed * dt), 0, run.distance.size - 1)
    if run.wheel_rail is not None:
        return (run.wheel_rail.vertical_load - run.wheel_rail.static_load[None, :, None])[rows]
    return _spring_loads(vehicle, track, run, speed)[rows]


def _spring_loads(vehicle: VehicleModel, track: Track, run, speed: float) -> np.ndarray:
    """The wheels' load changes along a run without contact tables, from the model's own
    vertical contact springs as the contact march takes them
    (:func:`express.forces.contact.dynamic_wheel_loads`, the rail heights included), shape
    (steps + 1, n_wheelsets, 2)."""
    from express.analysis.time.track_inputs import track_inputs
    from express.base.diagnostics import ArgumentError
    from express.forces.contact import dynamic_wheel_loads

    loads = dynamic_wheel_loads(vehicle, track_inputs(vehicle, track, run.distance, speed),
                                np.zeros(len(vehicle.wheelsets)))
    if loads is None:
        raise ArgumentError(f"{vehicle.name}: not every wheel stands on a vertical contact spring: no wheel loads "
                            "on the twist")
    states = np.concatenate([run.q, run.q_dot[:, vehicle.form.massive]], axis=1)
    return loads.offset + np.einsum("ki,ijs->kjs", states[:, loads.places], loads.gain[0])


def slips(vehicle: VehicleModel) -> bool:
    """Whether the vehicle has friction elements or characteristics (which the linear
    static solution sees stuck or at their tangents)."""
    from express.model.records import ElementKind

    kinds = (ElementKind.FRICTION, ElementKind.CHARACTERISTIC)
    return vehicle.model is not None and any(e.kind in kinds for e in vehicle.model.elements)
