"""EN 14363's twist for a vehicle: the limit twist of a base and the combined twist shape.

The limit twist ``g_lim`` of a base ``2a`` [m] (:func:`twist_limit`, in m/m)::

    g_lim = 7 mm/m                    for 2a <= 4 m
    g_lim = 20 mm / (2a) + 2 mm/m     for 4 m < 2a < 20 m
    g_lim = 3 mm/m                    for 2a >= 20 m

EN 14363's limit twist as commonly cited (the standard's text is not public to us, and no
public page we could search states it; a public summary of UIC 530-2, chapter 5, names the
limit twists ``g_lim`` and the limit ``dQ/Q0 <= 0.6`` without their values).  The three
branches meet: ``20/4 + 2 = 7`` and ``20/20 + 2 = 3``.  (The issue's brief gave ``+ 3`` and
4 mm/m, which jumps from 7 to 8 mm/m at 4 m; the continuous form was chosen.)  The
constants are module values (:data:`TWIST_PLATEAU`, ...) so that a user who holds the
standard can check them.

The combined twist (:func:`standard_twist`) puts the car-body-base twist ``g*`` over the
bogie centre spacing ``2a*`` and the bogie-base twist ``g+`` over the leading bogie's
wheelbase ``2a+`` (``g* = g_lim(2a*)``, ``g+ = g_lim(2a+)``; a two-axle vehicle has
only ``g*`` over its wheelbase). The cross level ``c = z_R - z_L`` at the wheelset at
``x`` (from the rear bogie centre ``x_r``, the leading bogie centre at ``x_f``)::

    c(x) = g* (x - x_r)                          every wheelset but the leading bogie's
    c(x) = g* (x_f - x_r) + g+ (x - x_f)         the leading bogie's wheelsets

so that the bogie centres' cross levels (the means of their wheelsets') differ by
``g* 2a*`` and the leading bogie's wheelsets by ``g+ 2a+``; + twist raises the right rail
ahead and unloads the leading left wheel (the outer one in a right curve).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel
from express.rail.track.irregularity import MAX_LATERAL_IRREGULARITY

__all__ = [
    "LONG_BASE",
    "SHORT_BASE",
    "TWIST_FLOOR",
    "TWIST_PLATEAU",
    "StandardTwist",
    "standard_twist",
    "twist_limit",
]

#: ``g_lim`` up to :data:`SHORT_BASE` [m/m] and from :data:`LONG_BASE` on (module docstring).
TWIST_PLATEAU, TWIST_FLOOR = 7e-3, 3e-3
#: The bases [m] where the middle branch ``20 mm / (2a) + 2 mm/m`` starts and ends.
SHORT_BASE, LONG_BASE = 4.0, 20.0
#: The middle branch's constants: ``TWIST_SPAN / (2a) + TWIST_OFFSET`` [m, m/m].
TWIST_SPAN, TWIST_OFFSET = 20e-3, 2e-3


def twist_limit(base: float) -> float:
    """The limit twist ``g_lim`` [m/m] of a base ``2a`` [m] (module docstring).

    Examples
    --------
    >>> round(twist_limit(14.2) * 1e3, 4)
    3.4085

    Raises
    ------
    ArgumentError
        For a base that is not a positive finite number.
    """
    if not (isinstance(base, (int, float)) and np.isfinite(base) and base > 0):
        raise ArgumentError(f"twist base: a positive length in metres is needed, got {base!r}")
    if base <= SHORT_BASE:
        return TWIST_PLATEAU
    if base >= LONG_BASE:
        return TWIST_FLOOR
    return TWIST_SPAN / base + TWIST_OFFSET


@dataclass(frozen=True)
class StandardTwist:
    """The combined twist at the vehicle's wheelsets (module docstring).

    Attributes
    ----------
    body_base, bogie_base : float
        ``2a*`` and ``2a+`` [m] (``bogie_base`` 0 for a two-axle vehicle).
    body_twist, bogie_twist : float
        ``g*`` and ``g+`` [m/m].
    cross_level : numpy.ndarray, shape (n_wheelsets,)
        ``c`` at each wheelset [m], in the vehicle's wheelset order.
    """

    body_base: float
    bogie_base: float
    body_twist: float
    bogie_twist: float
    cross_level: np.ndarray

    @property
    def heights(self) -> np.ndarray:
        """The (left, right) rail heights ``(-c/2, +c/2)`` [m], shape (1, n_wheelsets, 2)."""
        return np.stack([-self.cross_level / 2, self.cross_level / 2], axis=1)[None]

    def describe(self) -> str:
        """One line: the twists and their bases."""
        text = f"g* {self.body_twist * 1e3:.3g} mm/m over 2a* {self.body_base:g} m"
        if self.bogie_base > 0:
            text += f" + g+ {self.bogie_twist * 1e3:.3g} mm/m over 2a+ {self.bogie_base:g} m"
        return text


def _bases(stations: np.ndarray) -> tuple[float, float, np.ndarray]:
    """``2a*``, ``2a+`` and which wheelsets form the leading bogie, from the stations."""
    order = np.argsort(-stations)
    count = stations.size
    if count == 2:
        return float(stations.max() - stations.min()), 0.0, np.zeros(count, dtype=bool)
    if count < 4 or count % 2:
        raise ArgumentError(f"standard twist: {count} wheelsets; it is defined for two-axle vehicles and for two "
                            "bogies of equally many wheelsets (give the twist and its length instead)")
    front, rear = order[: count // 2], order[count // 2:]
    body = float(stations[front].mean() - stations[rear].mean())
    bogie = float(stations[front].max() - stations[front].min())
    leading = np.zeros(count, dtype=bool)
    leading[front] = True
    return body, bogie, leading


def standard_twist(vehicle: VehicleModel, body_twist: float | None = None,
                   bogie_twist: float | None = None) -> StandardTwist:
    """The combined twist for ``vehicle``, its bases from its wheelsets' stations.

    Parameters
    ----------
    vehicle : VehicleModel
        A rail vehicle with two wheelsets, or two bogies of equally many (the front half
        of the wheelsets by station is the leading bogie).
    body_twist, bogie_twist : float, optional
        ``g*`` and ``g+`` [m/m]; default :func:`twist_limit` of the bases.

    Raises
    ------
    ArgumentError
        For another wheelset layout, coincident wheelsets, or a cross level beyond
        :data:`~express.rail.track.irregularity.MAX_LATERAL_IRREGULARITY`.
    """
    stations = np.array([w.station for w in vehicle.wheelsets], dtype=float)
    body, bogie, leading = _bases(stations)
    if body <= 0 or (leading.any() and bogie <= 0):
        raise ArgumentError(f"standard twist: the wheelsets' stations {stations.tolist()} give no base")
    g_body = twist_limit(body) if body_twist is None else float(body_twist)
    g_bogie = (twist_limit(bogie) if leading.any() else 0.0) if bogie_twist is None else float(bogie_twist)
    if leading.any():
        rear, front = stations[~leading].mean(), stations[leading].mean()
        c = np.where(leading, g_body * (front - rear) + g_bogie * (stations - front), g_body * (stations - rear))
    else:
        c = g_body * (stations - stations.min())
    if np.abs(c).max() > MAX_LATERAL_IRREGULARITY:
        raise ArgumentError(f"standard twist: a cross level of {np.abs(c).max() * 1e3:.4g} mm, more than "
                            f"{MAX_LATERAL_IRREGULARITY * 1e3:g} mm")
    return StandardTwist(body, bogie, g_body, g_bogie, c)
