"""Divergence of a time simulation: the first step at which a run leaves the model's range
of validity (a non-finite value, or a wheelset far beyond its flange clearance), the run
cut before it, and the message that names the time, the place and the least-damped mode."""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from express.analysis.stability.stability import eigen_analysis
from express.base.units import KMH

__all__ = ["DIVERGED_CLEARANCES", "Divergence", "divergence_message", "find_divergence", "truncate"]

#: A wheelset this many flange clearances from its rail has left the model's range.
DIVERGED_CLEARANCES = 10.0
_MIN_DIVERGED_DISTANCE = 0.05  # m, for models with a tiny or zero clearance


@dataclass(frozen=True)
class Divergence:
    """Where a run left the model's range of validity.

    Attributes
    ----------
    index : int
        The first time step outside the range.
    reason : str
        What left it (a non-finite value, a wheelset and its distance from the centre line).
    """

    index: int
    reason: str


def find_divergence(result: Any, vehicle: Any) -> Divergence | None:
    """The first time step at which ``result`` left the model's range of validity.

    A non-finite state or output, or a wheelset's lateral displacement beyond
    :data:`DIVERGED_CLEARANCES` times its flange clearance (the flange would have
    climbed the rail long before: the model no longer describes the vehicle).

    Parameters
    ----------
    result : SimulationResult
        The run (``q``, ``q_dot`` of shape (N, n) and its ``outputs``).
    vehicle : VehicleModel
        The vehicle it ran (its wheelsets' lateral coordinates and flange clearances [m]).

    Returns
    -------
    Divergence or None
        None for a run that stays in range.
    """
    bad = ~np.all(np.isfinite(result.q), axis=1) | ~np.all(np.isfinite(result.q_dot), axis=1)
    for values in result.outputs.values():
        bad |= ~np.isfinite(values)
    reasons = ["a state or output is not finite"] * len(bad)
    for wheelset in vehicle.wheelsets:
        limit = max(DIVERGED_CLEARANCES * wheelset.flange_clearance, _MIN_DIVERGED_DISTANCE)
        with np.errstate(invalid="ignore"):
            far = np.abs(result.q[:, wheelset.y]) > limit
        for index in np.flatnonzero(far & ~bad)[:1]:
            reasons[index] = (f"wheelset {wheelset.name} is {abs(result.q[index, wheelset.y]):.3g} m from the track "
                              f"centre line, beyond {limit:g} m ({DIVERGED_CLEARANCES:g} flange clearances)")
        bad |= far
    hits = np.flatnonzero(bad)
    return Divergence(int(hits[0]), reasons[int(hits[0])]) if hits.size else None


def divergence_message(result: Any, vehicle: Any, divergence: Divergence) -> str:
    """Where and why ``result`` diverged, with the least-damped eigenvalue at its speed.

    Parameters
    ----------
    result : SimulationResult
        The run.
    vehicle : VehicleModel
        The vehicle it ran.
    divergence : Divergence
        From :func:`find_divergence`.

    Returns
    -------
    str
        One line: time [s], track position [m], the reason and the eigenvalue [1/s].
    """
    k = divergence.index
    message = (f"the run diverged at t = {result.time[k]:.4g} s, d1 = {result.distance[k]:.1f} m: "
               f"{divergence.reason}")
    try:
        mode = eigen_analysis(vehicle, result.speed).modes[0]
        message += (f"; least-damped eigenvalue at {result.speed / KMH:.1f} km/h: "
                    f"{mode.real:.4g} {'+' if mode.imag >= 0 else '-'} {abs(mode.imag):.4g}j 1/s ({mode.describe()})")
    except (ArithmeticError, ValueError, np.linalg.LinAlgError):
        message += "; the eigenvalues at this speed could not be computed"
    return message


def truncate(result: Any, count: int) -> Any:
    """The first ``count`` time steps of a :class:`~express.analysis.time.simulate.SimulationResult`
    (marked ``options["diverged"] = True``).

    Parameters
    ----------
    result : SimulationResult
        The run.
    count : int
        Time steps kept.

    Returns
    -------
    SimulationResult
    """
    return replace(
        result, time=result.time[:count], distance=result.distance[:count], q=result.q[:count],
        q_dot=result.q_dot[:count], outputs={name: values[:count] for name, values in result.outputs.items()},
        options={**result.options, "diverged": True},
    )
