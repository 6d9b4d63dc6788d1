"""A route's case on a random track: the time run whose wheels wear the profile where the
vehicle's random motion carries the contacts (``docs/wear.md``, "Random track").

A steady state on straight track is the centred wheelset, with no creepage and so no
wear; in service the track's alignment keeps the wheelsets moving, and the contacts sweep
the tread around the taping line.  A case with ``track = "<spectrum>"`` is therefore run
in time (:func:`~express.analysis.time.simulate.simulate`, the contact tables) on a random
alignment of that spectrum (:class:`~express.rail.track.irregularity.SpectrumIrregularity`,
the case's ``seed``): on straight track, :data:`LEAD` metres and then the case's
``run_length``; in a curve, the lead, the transition of the steady solver's path
(:func:`~express.analysis.curving.transition.transition_length`), :data:`SETTLE` metres
of the curve and then ``run_length``.  Only the last ``run_length`` (the leading
wheelset's distance) is read, each instant an equal share of the metre run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.analysis.curving.outputs import WheelRailOutputs
from express.analysis.wear.route import RouteCase
from express.base.diagnostics import AnalysisError
from express.numeric.statespace import VehicleModel
from express.rail.options import DEFAULT_CREEP_LAW

__all__ = ["DT", "LEAD", "SETTLE", "RandomTrackRun", "random_track_run"]

#: Straight track before the read part [m]: the start's transient (from the centred
#: vehicle at rest on the track's mean line) dies out within it.
LEAD = 100.0
#: Circular curve before the read part of a curve's case [m].
SETTLE = 200.0
#: The run's step [s] (``tests/test_wear_random_track.py`` shows the depth converged in it).
DT = 0.0025


@dataclass(frozen=True)
class RandomTrackRun:
    """The read part of a case's run on a random track.

    Attributes
    ----------
    speed : float
        [m/s].
    dt : float
        The run's step [s].
    window : tuple of float
        The leading wheelset's distance at the read part's start and end [m].
    wheel_rail : WheelRailOutputs
        The wheel/rail outputs of the read part's instants (with the contact tables'
        record: frictional power, patch and place on the wheel profile).
    lateral_rms : numpy.ndarray, shape (n,)
        Each wheelset's lateral displacement from the track's mean line, RMS over the
        read part [m] (how far the contacts are spread).
    """

    speed: float
    dt: float
    window: tuple[float, float]
    wheel_rail: WheelRailOutputs
    lateral_rms: np.ndarray


def random_track_run(vehicle: VehicleModel, case: RouteCase, speed: float, *, creep_law: str = DEFAULT_CREEP_LAW,
                     dt: float = DT) -> RandomTrackRun:
    """Run ``vehicle`` on ``case``'s random track at ``speed`` [m/s] (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        With the contact from profiles.
    case : RouteCase
        With ``track`` (the spectrum's name), ``run_length`` and ``seed``.
    speed : float
        [m/s].
    creep_law : str
        Of the contact tables.
    dt : float
        Step [s].

    Raises
    ------
    AnalysisError
        When the run leaves the model's range (it diverges).
    """
    from express.analysis.curving.assessment import assess_run
    from express.analysis.curving.transition import transition_length
    from express.analysis.time.divergence import divergence_message, find_divergence
    from express.analysis.time.simulate import simulate
    from express.rail.track import Curve, Straight, Track, Transition
    from express.rail.track.irregularity import SpectrumIrregularity

    assert case.track is not None
    alignment = SpectrumIrregularity(case.track, seed=case.seed)
    if case.straight:
        segments: tuple = (Straight(LEAD + case.run_length),)
    else:
        segments = (Straight(LEAD), Transition(transition_length(case.radius)),
                    Curve(SETTLE + case.run_length, case.radius, "right", case.cant))
    track = Track(segments, irregularity=alignment)
    run = simulate(vehicle, track, speed=speed, dt=dt, progress=False, contact="tables", creep_law=creep_law)  # type: ignore[arg-type]
    divergence = find_divergence(run, vehicle)
    if divergence is not None:
        raise AnalysisError(f"{case.name}: the run on the random track diverged: "
                            f"{divergence_message(run, vehicle, divergence)}")
    outputs, _ = assess_run(vehicle, track, run)
    end = track.length
    inside = run.distance >= end - case.run_length
    lateral = [w.y for w in vehicle.wheelsets]
    offset = alignment.value(run.distance[inside])
    rms = np.sqrt(np.mean((run.q[inside][:, lateral] - np.asarray(offset)[:, None]) ** 2, axis=0))
    return RandomTrackRun(float(speed), float(run.options["dt"]), (end - case.run_length, end), outputs.at(inside), rms)
