"""Ride from a nonlinear time run: the comfort of a vehicle whose linear model is unstable.

Above the linear critical speed no stationary linear response exists (a free motion
grows), so :func:`express.analysis.ride.vehicle.ride_response` refuses; the vehicle
still runs, on its flange contact and saturated creep forces, and its ride is what the
nonlinear run gives.  :func:`simulated_ride` runs it (:func:`express.analysis.time.
simulate.simulate`, flange contact and saturation on) along a straight track carrying a
realisation of every spectrum given (:class:`express.rail.track.irregularity.
SpectrumIrregularity`: cosines with random phases, the band's variance exactly, one seed
per component so the components are independent, as the spectral ride assumes), and
takes the comfort at the output points from their acceleration histories after a
run-in (:func:`.summaries.comfort_from_time_histories`: EN 12299's N_MV from 5-s
windows, Sperling's Wz, RMS).

It is one realisation of a random track: the numbers carry its sampling spread (about
``1/sqrt(band x duration)`` of a RMS), and the limit cycle the run settles into (if any)
is part of the response.  The step is checked by halving (a flange-contact limit cycle
at 300 km/h needs 0.5 ms: the lateral RMS moves 4.8 % from 1 to 0.5 ms, 0.45 % from 0.5 to
0.25 ms), and the result states it with the change measured.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from express.analysis.ride.summaries import PointComfort, comfort_from_time_histories, simulation_accelerations
from express.analysis.ride.vehicle import felt_components
from express.analysis.stability.limit_cycles import flange_touched
from express.base.data import DataRecord, variable, xarray
from express.base.diagnostics import InputError
from express.numeric.statespace import VehicleModel
from express.rail.track.spectra import COMPONENTS

__all__ = ["FINEST_STEP", "FIRST_STEP", "RUN_IN", "STEP_TOLERANCE", "SimulatedRide", "simulated_ride"]

#: [m] the start of the run left out of the comfort (the response to the start settles).
RUN_IN = 200.0
#: The step check's first step [s], its finest and its tolerance (a RMS relative to the
#: point's largest, N_MV relative): a flange-contact limit cycle needs 0.5 ms or less.
FIRST_STEP, FINEST_STEP, STEP_TOLERANCE = 1e-3, 1.25e-4, 0.02
#: [Hz] the highest frequency the realisation carries (EN 12299's weightings fall off
#: above 20 Hz); the lowest is 0.4 Hz.
_BAND_HZ = (0.4, 25.0)
_FIELD = {"alignment": "irregularity", "vertical": "vertical", "cross_level": "cross_level", "gauge": "gauge"}


@dataclass(frozen=True, repr=False)
class SimulatedRide(DataRecord):
    """The comfort of a nonlinear run on a random track.

    Attributes
    ----------
    speed : float
        [m/s].
    length : float
        [m] the distance the comfort is taken over (after :data:`RUN_IN`).
    dt : float
        [s] the run's time step.
    components : tuple of str
        The track components realised.
    comfort : dict of str to PointComfort
        By output point.
    flange_contact : bool
        Whether any wheel's flange touched its rail in the run.
    step_change : float or None
        The step check's largest relative change between ``dt`` and ``2 dt`` (None: one
        run at a given step).
    notes : tuple of str
    """

    speed: float
    length: float
    dt: float
    components: tuple[str, ...]
    comfort: dict[str, PointComfort]
    flange_contact: bool
    step_change: float | None
    notes: tuple[str, ...]

    def to_xarray(self) -> Any:
        """RMS, weighted RMS and Wz over ``point`` and ``direction``, N_MV over ``point``
        (:class:`xarray.Dataset`; CF-style ``units`` and ``long_name``; nan where a point
        has no such direction)."""
        points, axes = list(self.comfort), ["x", "y", "z"]

        def table(what: str) -> np.ndarray:
            return np.array([[getattr(self.comfort[p], what).get(a, np.nan) for a in axes] for p in points], float)

        data = {
            "rms": variable(table("rms"), ("point", "direction"), "m/s^2", "acceleration rms"),
            "weighted_rms": variable(table("weighted_rms"), ("point", "direction"), "m/s^2",
                                     "frequency-weighted acceleration rms (EN 12299)"),
            "wz": variable(table("wz"), ("point", "direction"), "1", "Sperling's ride index Wz"),
            "n_mv": variable(np.array([self.comfort[p].n_mv for p in points], float), "point", "1",
                             "EN 12299 mean comfort N_MV"),
        }
        return xarray().Dataset(data, coords={"point": points, "direction": axes},
                                attrs={"speed_m_per_s": self.speed, "length_m": self.length, "dt_s": self.dt,
                                       "flange_contact": int(self.flange_contact),
                                       "step_change": np.nan if self.step_change is None else self.step_change,
                                       "components": ", ".join(self.components)})

    def _summary(self) -> list[str]:
        return [f"nonlinear ride at {self.speed:.4g} m/s over {self.length:g} m, step {self.dt * 1e3:g} ms, "
                f"flange contact {'reached' if self.flange_contact else 'not reached'}",
                ", ".join(f"{p}: N_MV {c.n_mv:.3g}" for p, c in self.comfort.items())]


def _track(spectra: Mapping[str, Any], speed: float, length: float, seed: int) -> Any:
    from express.rail.track import Straight, Track
    from express.rail.track.irregularity import SpectrumIrregularity

    wavelength_min = max(speed / _BAND_HZ[1], 0.5)
    wavelength_max = max(min(speed / _BAND_HZ[0], 0.5 * length), 2 * wavelength_min)
    irregularities: dict[str, Any] = {
        # each component's seed by its place in COMPONENTS: another component joining the
        # set leaves the others' realisations as they were
        _FIELD[name]: SpectrumIrregularity(spectrum, seed=seed + COMPONENTS.index(name), wavelength_min=wavelength_min,
                                           wavelength_max=wavelength_max, period=length)
        for name, spectrum in sorted(spectra.items())
    }
    return Track([Straight(length)], **irregularities)


def _ride_at(vehicle: VehicleModel, track: Any, speed: float, dt: float) -> tuple[dict[str, PointComfort], bool]:
    from express.analysis.time.simulate import simulate

    result = simulate(vehicle, track, speed=speed, dt=dt, flange=True, saturation=True, progress=False)
    accelerations = simulation_accelerations(vehicle, result, track)
    kept = result.distance >= RUN_IN
    comfort = {point: comfort_from_time_histories({axis: values[kept] for axis, values in by_axis.items()}, 1.0 / dt)
               for point, by_axis in accelerations.items()}
    return comfort, flange_touched(result, len(result.q))


def _change(fine: dict[str, PointComfort], coarse: dict[str, PointComfort]) -> float:
    """The largest relative change of a RMS (of the direction's largest at that point) or N_MV."""
    changes = []
    for point, c in fine.items():
        scale = max(c.rms.values()) or 1.0
        changes += [abs(c.rms[a] - coarse[point].rms[a]) / scale for a in c.rms]
        changes.append(abs(c.n_mv - coarse[point].n_mv) / max(abs(c.n_mv), 1e-12))
    return max(changes, default=0.0)


def simulated_ride(vehicle: VehicleModel, spectra: Mapping[str, Any], speed: float, length: float = 2000.0,
                   seed: int = 0, dt: float | None = None, tolerance: float = STEP_TOLERANCE) -> SimulatedRide:
    """The comfort at the output points of a nonlinear run on a random track.

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data and ``[rail.outputs]``.
    spectra : mapping of str to TrackSpectrum
        By component of :data:`express.rail.track.spectra.COMPONENTS`; those the model
        has no input for are left out, as in the spectral ride.
    speed : float
        [m/s] > 0.
    length : float
        [m] the run, :data:`RUN_IN` included; at least ``RUN_IN`` plus 5 s of running.
    seed : int
        The realisation's first seed: each component's is ``seed`` plus its index in
        :data:`~express.rail.track.spectra.COMPONENTS` (alignment 0, vertical 1, cross
        level 2, gauge 3), so one component's realisation does not depend on the others.
    dt : float, optional
        [s] one run at this step (``step_change`` None); by default the step is checked:
        runs at :data:`FIRST_STEP` and half of it, halved again while a RMS (relative to
        the point's largest) or N_MV moves by more than ``tolerance``, down to
        :data:`FINEST_STEP`; the finer run of the last pair is the result.
    tolerance : float
        The step check's tolerance [-].

    Raises
    ------
    InputError
        No output points, no driven component, too short a run.
    """
    unknown = sorted(set(spectra) - set(_FIELD))
    if unknown:
        raise InputError(f"simulated ride: unknown track components {', '.join(unknown)} (known: {', '.join(_FIELD)})")
    rail = vehicle.model.rail if vehicle.model is not None else None
    if rail is None or not rail.outputs:
        raise InputError("simulated ride: the model has no output points ([rail.outputs])")
    if not (speed > 0 and length - RUN_IN >= 5.0 * speed):
        raise InputError(f"simulated ride: a run of {length:g} m at {speed:g} m/s leaves less than 5 s after the "
                         f"{RUN_IN:g} m run-in")
    driven = felt_components(vehicle)  # the cross level at the contact springs too, as a time run takes it
    spectra = {name: spectrum for name, spectrum in spectra.items() if name in driven}  # as the spectral ride
    if not spectra:
        raise InputError("simulated ride: the model has no input any of the spectra drives (rail grounds, docs/ride.md)")
    track = _track(spectra, speed, length, seed)
    step_change: float | None = None
    if dt is not None:
        comfort, touched = _ride_at(vehicle, track, speed, dt)
    else:
        dt = FIRST_STEP
        coarse, _ = _ride_at(vehicle, track, speed, dt)
        while True:
            comfort, touched = _ride_at(vehicle, track, speed, dt / 2)
            dt, step_change = dt / 2, _change(comfort, coarse)
            if step_change <= tolerance or dt / 2 < FINEST_STEP:
                break
            coarse = comfort
    seeds = ", ".join(f"{name} {seed + COMPONENTS.index(name)}" for name in sorted(spectra))
    notes = [f"one realisation of a random track (seeds: {seeds}; "
             f"{_BAND_HZ[0]:g}-{_BAND_HZ[1]:g} Hz at this speed), {length - RUN_IN:g} m after a {RUN_IN:g} m run-in: "
             f"a RMS carries a sampling spread of about {100 / math.sqrt(_BAND_HZ[1] * (length - RUN_IN) / speed):.0f} %"]
    if step_change is not None:
        verdict = "converged" if step_change <= tolerance else "NOT converged at the finest step"
        notes.append(f"time step {dt * 1e3:g} ms, checked against {2 * dt * 1e3:g} ms: {verdict} (largest change "
                     f"{step_change:.2%}, tolerance {tolerance:.0%})")
    return SimulatedRide(speed, length - RUN_IN, dt, tuple(sorted(spectra)), comfort, touched, step_change, tuple(notes))
