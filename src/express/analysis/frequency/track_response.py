"""Frequency response to each sinusoidal track irregularity: alignment, vertical, cross
level and gauge, at every output point and in every direction.

The track drives the vehicle as in the ride analysis (:mod:`express.analysis.ride.vehicle`,
``docs/ride.md``): the alignment through the wheelsets' ``yR`` inputs, the vertical
irregularity and the cross level through the rail grounds (a model without rail grounds
feels neither). One component at a time is the sinusoid ``Y sin(2 pi f t)`` at the
leading wheelset, delayed at the others by their distance behind it; the response of each
ride output (the output points' accelerations ``<point>.ax, .ay, .az`` [m/s^2], the
wheels' lateral forces and dynamic loads [N], the wheelsets' lateral displacement on the
track [m]) is its complex amplitude (phase convention of :mod:`express.analysis.frequency.frequency`).
The displacement of an output point is its acceleration divided by ``-w^2``.

The transfer functions are the ride analysis's own: ``G_y = sum_j |H_yj|^2 G_j`` holds
between this response and the ride spectra by construction, and the alignment response
equals :func:`express.analysis.frequency.frequency.frequency_response` (a different solution
route; ``tests/test_track_response.py``).
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from express.base.data import DataRecord, variable, xarray
from express.base.diagnostics import ArgumentError
from express.base.names import did_you_mean
from express.numeric.statespace import VehicleModel

__all__ = ["TrackFrequencyResponse", "track_frequency_response"]


class _Unit:
    """A flat spatial spectrum, 1 m^2/(rad/m): the ride analysis then returns the plain
    transfer functions."""

    @staticmethod
    def psd(omega):
        return np.ones_like(np.asarray(omega, dtype=float))


@dataclass(frozen=True, repr=False)
class TrackFrequencyResponse(DataRecord):
    """Complex amplitudes of the ride outputs for each track component alone: the
    ride analysis's ``transfer`` (:class:`express.analysis.ride.vehicle.RideResponse`,
    same ``frequencies`` [Hz], ``speed`` [m/s], ``names`` and ``units``) times the
    irregularity ``amplitude`` ``Y`` [m].

    Attributes
    ----------
    components : tuple of str
        The components computed (of :data:`express.rail.track.spectra.COMPONENTS`).
    values : numpy.ndarray, complex, shape (F, len(names), len(components))
        Response amplitudes for ``Y``.
    """

    frequencies: np.ndarray
    speed: float
    amplitude: float
    components: tuple[str, ...]
    names: tuple[str, ...]
    units: tuple[str, ...]
    values: np.ndarray

    def of(self, name: str, component: str) -> np.ndarray:
        """Complex amplitude of one output for one component, shape (F,)."""
        if name not in self.names:
            raise ArgumentError(f"unknown output {name!r}{did_you_mean(name, self.names)} (outputs: {', '.join(self.names)})")
        if component not in self.components:
            raise ArgumentError(f"component {component!r} not computed{did_you_mean(component, self.components)}")
        return self.values[:, self.names.index(name), self.components.index(component)]

    def to_xarray(self):
        """The amplitudes as an :class:`xarray.Dataset`: ``amplitude`` (frequency [Hz] x
        output x input, complex), each output's unit in the ``units`` coordinate; the speed
        [m/s] and the irregularity amplitude [m] as attributes."""
        xr = xarray()
        return xr.Dataset(
            {"amplitude": variable(self.values, ("frequency", "output", "input"), "see the units coordinate",
                                   "complex response amplitude")},
            coords={"frequency": ("frequency", self.frequencies, {"units": "Hz", "long_name": "frequency"}),
                    "output": list(self.names), "input": list(self.components), "units": ("output", list(self.units))},
            attrs={"speed": self.speed, "speed_units": "m/s", "irregularity_amplitude": self.amplitude,
                   "irregularity_amplitude_units": "m"},
        )

    def to_pandas(self):
        """The amplitudes as a :class:`pandas.DataFrame` indexed by frequency [Hz], output
        and input; one complex column ``amplitude`` and the output's unit."""
        table = self.to_xarray().to_dataframe()
        table.attrs = {"speed": self.speed, "irregularity_amplitude": self.amplitude}
        return table

    def _summary(self) -> list[str]:
        f = self.frequencies
        return [f"{len(self.names)} outputs x {len(self.components)} inputs ({', '.join(self.components)})",
                f"{f.size} frequencies {f[0]:g}-{f[-1]:g} Hz at {self.speed:.3f} m/s, Y = {self.amplitude * 1e3:g} mm"]

    def _repr_html_(self) -> str:
        """Peak amplitudes in a notebook (output x input, with units)."""
        import pandas as pd

        peaks = np.abs(self.values).max(axis=0)
        frame = pd.DataFrame(peaks, index=pd.Index([f"{n} [{u}]" for n, u in zip(self.names, self.units, strict=True)],
                                                   name="output"), columns=list(self.components))
        return (f"<p>peak amplitudes for Y = {self.amplitude * 1e3:g} mm at {self.speed * 3.6:.1f} km/h, "
                f"{self.frequencies[0]:g}-{self.frequencies[-1]:g} Hz</p>" + frame.to_html(float_format=lambda x: f"{x:.4g}"))

    def displacement_of(self, name: str, component: str) -> np.ndarray:
        """Displacement amplitude [m] of an output point's acceleration output
        (``floor_front.az`` -> the floor's vertical displacement), ``a / (-w^2)``."""
        if self.units[self.names.index(name)] != "m/s^2":
            raise ArgumentError(f"{name} is not an acceleration")
        w = 2.0 * np.pi * self.frequencies
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(w > 0, self.of(name, component) / -(w**2), np.nan)


def track_frequency_response(
    vehicle: VehicleModel,
    frequencies: Iterable[float],
    *,
    components: Iterable[str] | None = None,
    amplitude: float = 1e-3,
    speed: float | None = None,
) -> TrackFrequencyResponse:
    """Response to a sinusoid of each track component (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data.
    frequencies : sequence of float
        [Hz] > 0, increasing (numbers SI; quantities carry their unit).
    components : sequence of str, optional
        Of ``alignment``, ``vertical``, ``cross_level``, ``gauge``; default every one
        the model feels.
    amplitude : float
        ``Y`` [m], default 1 mm.
    speed : float, str or pint.Quantity, optional
        [m/s] (a number is SI; ``"120 km/h"``); the model's own by default.

    Raises
    ------
    ArgumentError
        An unknown component, or one the model has no input for.

    Examples
    --------
    >>> from express.numeric.statespace import load_vehicle
    >>> coach = load_vehicle("examples/manchester.toml")  # one rail ground per axle: cross level at the springs
    >>> frf = track_frequency_response(coach, [1.0, 2.0])
    >>> frf.components
    ('alignment', 'vertical', 'cross_level')
    >>> frf.of("floor_front.az", "vertical").shape
    (2,)
    """
    from express.analysis.ride.vehicle import felt_components, ride_response
    from express.base.arguments import si_argument, si_arguments
    from express.rail.track.spectra import COMPONENTS

    felt = felt_components(vehicle)
    chosen = tuple(felt if components is None else components)
    problems = [f"--input {c}: not a track component{did_you_mean(c, COMPONENTS)} (components: {', '.join(COMPONENTS)})"
                for c in chosen if c not in COMPONENTS]
    problems += [f"--input {c}: the model has no input it drives (rail grounds, docs/ride.md); it feels: "
                 f"{', '.join(felt) or 'none'}" for c in chosen if c in COMPONENTS and c not in felt]
    if problems:
        raise ArgumentError("; ".join(problems))
    if not chosen:
        raise ArgumentError("the model feels no track irregularity (no rail inputs)")
    f = si_arguments(frequencies, "frequency", "frequencies")
    amplitude = si_argument(amplitude, "length", "amplitude")
    ride = ride_response(vehicle, dict.fromkeys(chosen, _Unit()), speed=speed, frequencies=f)
    order = [ride.components.index(c) for c in chosen]
    return TrackFrequencyResponse(
        frequencies=ride.frequencies, speed=ride.speed, amplitude=float(amplitude), components=chosen,
        names=ride.names, units=ride.units, values=amplitude * ride.transfer[:, :, order],
    )
