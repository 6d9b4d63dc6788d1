"""Ride with the statistical (Gaussian) linearisation of the nonlinear elements, iterated
to its fixed point (issue 31, item 6; ``docs/analyses.md``, "Linearisation of the
nonlinear elements").

Each friction element and characteristic E is replaced by the linear spring and damper
that match it on average over a Gaussian motion of E's own rms deflection ``s`` and rate
``s'`` (:mod:`express.forces.linearisation`); those rms come from the ride response of the
vehicle so linearised (the outputs ``<E>.deflection`` and ``<E>.rate`` of
:func:`~express.analysis.ride.vehicle.ride_response`).  The iteration starts from the
response at the tangent (friction stuck) and updates the levels in log space with
relaxation ``1/2`` until the largest relative change is below ``tolerance``.  The rms are
over the response's frequency band, as every ride figure.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from numpy.typing import ArrayLike

from express.analysis.ride.vehicle import RideResponse, ride_response
from express.base.data import DataRecord, xarray
from express.base.diagnostics import ArgumentError
from express.forces.linearisation import Linearisation, linearised, nonlinear_rows
from express.numeric.statespace import VehicleModel

__all__ = ["StatisticalRide", "statistical_ride"]

#: Relaxation of the level update in log space (1: plain substitution).
RELAXATION = 0.5


@dataclass(frozen=True, repr=False)
class StatisticalRide(DataRecord):
    """The ride at the fixed point of the statistical linearisation (module docstring);
    like :class:`scipy.optimize.OptimizeResult` it says whether it converged and why.

    Attributes
    ----------
    response : RideResponse
        The ride response of :attr:`vehicle`.
    vehicle : VehicleModel
        The vehicle linearised at :attr:`levels` (a
        :class:`~express.forces.linearisation.LinearisedVehicle`).
    levels : dict of str to (float, float)
        Each element's rms deflection [m; rad] and rate [m/s; rad/s] at the fixed point.
    iterations : int
        Responses computed after the tangent's.
    success : bool
        Whether the largest relative change of the levels fell below the tolerance.
    message : str
        Why the iteration stopped.
    history : tuple of float
        The largest relative change of the levels at each iteration.
    """

    response: RideResponse
    vehicle: VehicleModel
    levels: dict[str, tuple[float, float]]
    iterations: int
    success: bool
    message: str
    history: tuple[float, ...]

    @property
    def linearisation(self) -> Linearisation:
        """The linearisation at the fixed point (``kind == "statistical"``)."""
        return Linearisation("statistical", levels=self.levels)

    def to_xarray(self) -> Any:
        """The response's dataset (:meth:`RideResponse.to_xarray`) with, over ``element``,
        the levels and the equivalent stiffness and damping; ``attrs`` say how it converged."""
        data = self.response.to_xarray()
        elements = getattr(self.vehicle, "elements", ())
        names = [e.element for e in elements]
        xr = xarray()
        extra = xr.Dataset(
            {"element_rms": ("element", [self.levels.get(n, (math.nan, math.nan))[0] for n in names]),
             "element_rate_rms": ("element", [self.levels.get(n, (math.nan, math.nan))[1] for n in names]),
             "equivalent_stiffness": ("element", [e.stiffness for e in elements]),
             "equivalent_damping": ("element", [e.damping for e in elements])},
            coords={"element": names})
        for name, unit in (("element_rms", "m or rad"), ("element_rate_rms", "m/s or rad/s"),
                           ("equivalent_stiffness", "N/m or N m/rad"), ("equivalent_damping", "N s/m or N m s/rad")):
            extra[name].attrs["units"] = unit
        merged = xr.merge([data, extra])
        merged.attrs.update(data.attrs, linearisation="statistical (Gaussian) at each element's rms response",
                            iterations=self.iterations, success=int(self.success), message=self.message)
        return merged

    def _summary(self) -> list[str]:
        state = "converged" if self.success else "NOT converged"
        return [f"statistical linearisation {state} in {self.iterations} iterations: {self.message}",
                *self.response._summary()]


def _levels(response: RideResponse, elements: list[str]) -> dict[str, tuple[float, float]]:
    found = {}
    for name in elements:
        level, rate = response.rms(f"{name}.deflection"), response.rms(f"{name}.rate")
        if level > 0.0:
            found[name] = (level, rate)
    return found


def _change(new: Mapping[str, tuple[float, float]], old: Mapping[str, tuple[float, float]]) -> float:
    if set(new) != set(old):
        return math.inf
    return max((abs(a / b - 1.0) for n in new for a, b in zip(new[n], old[n], strict=True) if b > 0.0), default=0.0)


def _relaxed(old: tuple[float, float], new: tuple[float, float]) -> tuple[float, float]:
    """One relaxed step of the levels (geometric mean weighted by ``RELAXATION``)."""
    def step(a: float, b: float) -> float:
        return math.exp((1 - RELAXATION) * math.log(a) + RELAXATION * math.log(b)) if a > 0 and b > 0 else b
    return step(old[0], new[0]), step(old[1], new[1])


def statistical_ride(vehicle: VehicleModel, spectra: Mapping[str, Any], speed: float | None = None,
                     frequencies: ArrayLike | None = None, tolerance: float = 1e-4,
                     max_iterations: int = 100) -> StatisticalRide:
    """The ride of ``vehicle`` with its nonlinear elements statistically linearised at
    their own rms response (module docstring).

    Parameters
    ----------
    vehicle, spectra, speed, frequencies
        As :func:`~express.analysis.ride.vehicle.ride_response`.
    tolerance : float
        Largest relative change of any element's rms deflection or rate between two
        iterations at which the fixed point counts as found.
    max_iterations : int
        Responses after the tangent's before giving up (``success`` False).

    Raises
    ------
    ArgumentError
        A tolerance not in (0, 0.1) or ``max_iterations`` below 1.
    InputError, AnalysisError
        As :func:`~express.analysis.ride.vehicle.ride_response` (an unstable vehicle at an
        iteration included).
    """
    if not 0.0 < tolerance < 0.1 or max_iterations < 1:
        raise ArgumentError(f"statistical_ride: tolerance {tolerance!r} must be in (0, 0.1) and max_iterations "
                            f"{max_iterations!r} at least 1")
    names = [row.element for row in nonlinear_rows(vehicle)]
    response = ride_response(vehicle, spectra, speed, frequencies)
    levels = _levels(response, names)
    current = vehicle
    history: list[float] = []
    for iteration in range(1, max_iterations + 1):
        current = linearised(vehicle, Linearisation("statistical", levels=levels))
        response = ride_response(current, spectra, speed, frequencies)
        found = _levels(response, names)
        history.append(_change(found, levels))
        if history[-1] < tolerance:
            return StatisticalRide(response, current, levels, iteration, True,
                                   f"the levels changed by {history[-1]:.2g} < {tolerance:g}", tuple(history))
        levels = {n: _relaxed(levels.get(n, found[n]), found[n]) for n in found}
    return StatisticalRide(response, current, levels, max_iterations, False,
                           f"no fixed point in {max_iterations} iterations (last change {history[-1]:.2g})", tuple(history))
