"""Wheel wear and rolling-contact-fatigue damage from the frictional power of a contact:
the Sheffield (USFD) wear function of ``Tgamma / A`` and Burstow's Tgamma damage function.

Both are pure functions of the contact's frictional power per unit rolling distance
``Tgamma`` [N] (:func:`express.rail.contact_forces.profile_wheelset_forces`) and, for wear,
of the Hertz patch's area ``A`` [m^2]; they work on NumPy arrays of any shape.
Their coefficients, sources and limits are in ``docs/wear.md``:

* :func:`usfd_wear_rate`: the wear rate of R8T wheel steel against UIC60 900A rail
  measured by twin-disc tests at the University of Sheffield (Lewis & Dwyer-Joyce 2004;
  the three regimes as Braghin, Lewis, Dwyer-Joyce & Bruni 2006 fit them), mass lost per
  metre rolled and per mm^2 of contact [ug/(m mm^2)];
* :func:`burstow_damage`: the RCF damage index of Burstow's whole-life rail model (no
  damage below a threshold, rising linearly to a peak, falling as wear removes the
  cracks' beginnings, none beyond), damage per wheel passage [-] (crack initiation
  expected when the sum reaches 1).

:func:`wear_rate_of_contact` joins the two steps, ``Tgamma`` and the area in SI to the
wear rate.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["BURSTOW", "USFD_R8T", "BurstowFunction", "UsfdFunction", "burstow_damage", "usfd_wear_rate",
           "wear_rate_of_contact"]

FloatArray = NDArray[np.float64]


class UsfdFunction(NamedTuple):
    """The three regimes of the USFD wear function of ``x = Tgamma / A`` [N/mm^2]:
    ``mild_slope x`` for ``x < mild_end``; ``severe`` for ``mild_end <= x <= severe_end``;
    ``catastrophic_slope x - catastrophic_offset`` beyond [ug/(m mm^2)]."""

    mild_slope: float
    mild_end: float
    severe: float
    severe_end: float
    catastrophic_slope: float
    catastrophic_offset: float


#: R8T wheel steel on UIC60 900A rail (Braghin et al. 2006, Table 1, from Lewis &
#: Dwyer-Joyce 2004): K1 = 5.3 x, K2 = 55.0, K3 = 61.9 x - 4778.7 with the boundaries
#: 10.4 and 77.2 N/mm^2.  As published the third branch starts near zero at 77.2 (not at
#: the plateau's 55.0, which it passes at 78.09); ``docs/wear.md``, "Limits".
USFD_R8T = UsfdFunction(5.3, 10.4, 55.0, 77.2, 61.9, 4778.7)


class BurstowFunction(NamedTuple):
    """Burstow's RCF damage function of ``Tgamma`` [N]: zero below ``threshold``,
    rising linearly to ``peak_damage`` [-] at ``peak``, falling linearly to zero at
    ``end``, zero beyond."""

    threshold: float
    peak: float
    end: float
    peak_damage: float


#: Burstow's whole-life rail model (Burstow 2003/2004, as the brief and the secondary
#: sources of ``docs/wear.md`` give it): 15 N, 65 N, 175 N, a peak of 1e-5 per passage.
BURSTOW = BurstowFunction(15.0, 65.0, 175.0, 1.0e-5)


def usfd_wear_rate(specific_power: ArrayLike, function: UsfdFunction = USFD_R8T) -> FloatArray:
    """Wear rate [ug/(m mm^2)] at ``Tgamma / A`` = ``specific_power`` [N/mm^2] (any
    shape; negative values count as zero).  The published third branch is negative just
    beyond 77.2 N/mm^2 (by 0.02 at most, up to 77.2003): it is clamped at zero.

    Examples
    --------
    >>> usfd_wear_rate([5.0, 50.0]).tolist()
    [26.5, 55.0]
    """
    x = np.maximum(np.asarray(specific_power, dtype=float), 0.0)
    f = function
    catastrophic = np.maximum(f.catastrophic_slope * x - f.catastrophic_offset, 0.0)
    return np.where(x < f.mild_end, f.mild_slope * x, np.where(x <= f.severe_end, f.severe, catastrophic))


def burstow_damage(tgamma: ArrayLike, function: BurstowFunction = BURSTOW) -> FloatArray:
    """RCF damage index per wheel passage [-] at ``Tgamma`` [N] (any shape).

    Examples
    --------
    >>> burstow_damage([10.0, 65.0, 175.0]).tolist()
    [0.0, 1e-05, 0.0]
    """
    f = function
    # piecewise linear through the corners, zero outside: one pass
    return np.interp(np.asarray(tgamma, dtype=float), (f.threshold, f.peak, f.end), (0.0, f.peak_damage, 0.0),
                     left=0.0, right=0.0)


def wear_rate_of_contact(tgamma: ArrayLike, area: ArrayLike, function: UsfdFunction = USFD_R8T) -> FloatArray:
    """Wear rate [ug/(m mm^2)] of contacts with frictional power ``tgamma`` [N] and patch
    area ``area`` [m^2] (broadcast); a contact without area (a lifted wheel) has none."""
    t, a = np.broadcast_arrays(np.asarray(tgamma, dtype=float), np.asarray(area, dtype=float))
    square_mm = a * 1e6
    specific = np.divide(t, square_mm, out=np.zeros_like(t), where=square_mm > 0.0)
    return np.where(square_mm > 0.0, usfd_wear_rate(specific, function), 0.0)
