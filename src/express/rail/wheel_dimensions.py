"""The flange dimensions of a wheel profile that EN 15313 limits in service: the flange
thickness Sd, the flange height Sh and the flange slope measure qR (issue 37, item 3).

In the profile's side frame (:mod:`express.rail.profiles`: ``y`` toward the field side,
the flange at negative ``y``, ``z`` up, the taping line at ``y = 0``) with the wheel's
inner face (the back of the flange) ``tapeline_offset`` inward of the taping line
(70 mm for S1002):

* the **tread datum** is the point of the tread on the measuring circle, at the taping
  line: height ``z(0)`` (it moves with the tread's wear);
* **Sh**, the flange height: from the tread datum to the flange tip, ``z(0) - min z``;
* **Sd**, the flange thickness: from the inner face to the flange's active flank (the
  flank toward the tread), measured horizontally **10 mm above the tread datum**:
  ``y_f + tapeline_offset`` with ``z(y_f) = z(0) - 10 mm`` on that flank;
* **qR**, the flange slope measure: the horizontal distance between that flank point and
  the point of the same flank **2 mm above the flange tip**.

These are the definitions of EN 15313 (and UIC 510-2, EN 13715, whose S1002 they give as
Sd 32.5 mm, Sh 28 mm, qR 10.8 mm); the standards are not public and were not read
here: ``docs/wear.md``, "Flange dimensions", says what was checked.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from express.base.diagnostics import ArgumentError

__all__ = ["FLANGE_THICKNESS_HEIGHT", "SLOPE_HEIGHT", "FlangeDimensions", "flange_dimensions"]

#: Height of the flange thickness's measuring point above the tread datum [m].
FLANGE_THICKNESS_HEIGHT = 10e-3
#: Height of qR's upper point above the flange tip [m].
SLOPE_HEIGHT = 2e-3


@dataclass(frozen=True)
class FlangeDimensions:
    """EN 15313's flange dimensions of a wheel profile (module docstring), all [m].

    Attributes
    ----------
    thickness : float
        Sd.
    height : float
        Sh.
    slope : float
        qR.
    """

    thickness: float
    height: float
    slope: float


def _flank_point(y: np.ndarray, z: np.ndarray, level: float) -> float:
    """``y`` where the flank (increasing ``z`` from the tip toward the tread) first
    reaches ``level`` (linear between the points)."""
    above = np.flatnonzero(z >= level)
    if above.size == 0 or above[0] == 0:
        raise ArgumentError(f"the flank does not reach z = {level * 1e3:.4g} mm")
    k = int(above[0])
    return float(y[k - 1] + (level - z[k - 1]) * (y[k] - y[k - 1]) / (z[k] - z[k - 1]))


def flange_dimensions(y: ArrayLike, z: ArrayLike, tapeline_offset: float = 0.070) -> FlangeDimensions:
    """Sd, Sh and qR of the wheel profile ``(y, z)`` [m] (shape (n,), ``y`` increasing;
    side frame, module docstring); ``tapeline_offset`` the inner face's distance from
    the taping line [m].

    Raises
    ------
    ArgumentError
        When the profile has no flange tip inward of the taping line, or its flank does
        not reach the measuring heights.

    Examples
    --------
    >>> from express.rail.profiles import standard_profile
    >>> p = standard_profile("S1002")
    >>> d = flange_dimensions(p.y, p.z)
    >>> round(d.thickness * 1e3, 2), round(d.height * 1e3, 2), round(d.slope * 1e3, 2)
    (32.5, 28.0, 10.79)
    """
    y, z = np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    if y.ndim != 1 or y.shape != z.shape or y.size < 4 or not (y[0] < 0.0 < y[-1]):
        raise ArgumentError("a wheel profile of at least 4 points across its taping line (y = 0)")
    inward = y < 0.0
    tip = int(np.argmin(np.where(inward, z, np.inf)))
    datum = float(np.interp(0.0, y, z))
    height = datum - float(z[tip])
    flank_y, flank_z = y[tip:], z[tip:]
    thickness_y = _flank_point(flank_y, flank_z, datum - FLANGE_THICKNESS_HEIGHT)
    slope_y = _flank_point(flank_y, flank_z, float(z[tip]) + SLOPE_HEIGHT)
    return FlangeDimensions(thickness=thickness_y + tapeline_offset, height=height, slope=thickness_y - slope_y)
