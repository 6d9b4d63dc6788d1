"""The steps of a wear prediction in distance (``docs/wear.md``, "The steps"): the
profile ``z`` [m] per node moves as ``dz/dD = d(z)``, the route's depth rate [m/m] on the
worn profile.

* :func:`euler_step`, first order: ``z + L d(z)``, ``L`` as long as the bound on the
  change allows;
* :func:`heun_step`, second order (the explicit trapezoidal rule): the predictor
  ``z* = z + L d(z)``, then ``z + L (d(z) + d(z*)) / 2``; the difference of the two,
  ``L / 2 max|d(z*) - d(z)|``, is the local error estimate of the Euler step (an
  embedded pair, as in Runge-Kutta-Fehlberg 1(2)), and ``L`` is shrunk until it is
  within the tolerance and the change within the bound; the next step's proposed length
  grows by ``0.9 sqrt(tolerance / error)``, at most twice (the estimate is of order L^2).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from express.analysis.wear.cases import ProfileGrid

__all__ = ["MAX_EVALUATIONS", "METHODS", "WearStep", "euler_step", "heun_step"]

#: The stepping methods.
METHODS = ("heun", "euler")
#: Most evaluations of the rate in one Heun step (its length shrunk after each rejection).
MAX_EVALUATIONS = 6


@dataclass(frozen=True)
class WearStep:
    """One step of the profile.

    Attributes
    ----------
    change : numpy.ndarray, shape (nodes,)
        Depth removed at each node [m].
    length : float
        The step's distance [m].
    error : float
        Its local error estimate [m] (nan for Euler).
    evaluations : int
        Evaluations of the rate the step took (the start's included).
    proposal : float or None
        The next step's proposed length [m] (None: from the bound alone).
    """

    change: np.ndarray
    length: float
    error: float
    evaluations: int
    proposal: float | None


def euler_step(start: np.ndarray, remaining: float, bound: float) -> WearStep:
    """The rate at the start, ``start`` [m/m] per node, over the longest length that changes
    the profile by at most ``bound`` [m], at most ``remaining`` [m]."""
    peak = float(start.max())
    length = remaining if peak * remaining <= bound else bound / peak
    return WearStep(start * length, length, math.nan, 1, None)


def heun_step(rate_on: Callable[[ProfileGrid, int], np.ndarray], grid: ProfileGrid, start: np.ndarray,
              remaining: float, proposal: float | None, bound: float, tolerance: float) -> WearStep:
    """One Heun step from ``grid`` (module docstring).

    Parameters
    ----------
    rate_on : callable
        ``rate_on(profile, trial)``: the rate [m/m] per node on a predicted profile (the
        trial's number, 1, 2, ..., names it).
    grid : ProfileGrid
        The profile at the step's start.
    start : numpy.ndarray, shape (nodes,)
        The rate on ``grid`` [m/m].
    remaining : float
        Distance left to run [m].
    proposal : float or None
        The length the previous step proposed [m].
    bound : float
        Largest change of the profile [m].
    tolerance : float
        Largest local error estimate [m].
    """
    peak = float(start.max())
    length = min(remaining, math.inf if peak <= 0 else bound / peak, math.inf if proposal is None else proposal)
    evaluations = 1
    while True:
        predicted = rate_on(grid.worn(start * length), evaluations)
        evaluations += 1
        change = 0.5 * (start + predicted) * length
        error = 0.5 * length * float(np.max(np.abs(predicted - start)))
        over = float(change.max()) / bound
        if (error <= tolerance and over <= 1.0 + 1e-9) or evaluations >= MAX_EVALUATIONS:
            break
        length *= max(0.2, min(0.9 * math.sqrt(tolerance / error) if error > tolerance else 1.0,
                               0.99 / over if over > 1.0 else 1.0))
    grow = 2.0 if error <= 0 else min(2.0, 0.9 * math.sqrt(tolerance / error))
    return WearStep(change, length, error, evaluations, length * grow)
