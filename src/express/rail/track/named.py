"""Bundled named curves: standard-gauge curves of R = 250 to 3000 m with their cant,
transitions and line speed, to run a vehicle through without writing a track file
(``docs/curving.md``, "Named tracks").

Each is a right curve: 50 m straight, a linear transition (clothoid with a linear cant
ramp), the circular curve, the same transition back, 50 m straight.  The cants and
speeds are our choice for a mixed-traffic standard-gauge line, with a cant deficiency of
about 80 to 150 mm (0.5 to 1.0 m/s^2); each transition is long enough for a cant
gradient of at most 2.25 mm/m and a rate of change of cant of at most 50 mm/s at the line
speed (design rules of thumb of European lines, our choice, not a quotation of a
standard).  ``paper`` is the curve of the paper's Fig. 9 (:func:`~express.rail.track.
geometry.paper_curve`).

=======  ======  =====  ==========  ==========  ======  ===================
name     R [m]   cant   transition  circular    speed   cant deficiency
=======  ======  =====  ==========  ==========  ======  ===================
R250     250     150    70 m        200 m       75      115 mm (0.75 m/s^2)
R400     400     150    80 m        200 m       95      116 mm (0.76 m/s^2)
R600     600     150    100 m       250 m       115     110 mm (0.72 m/s^2)
R1000    1000    150    130 m       300 m       150     115 mm (0.76 m/s^2)
R3000    3000    130    170 m       400 m       230     78 mm (0.51 m/s^2)
=======  ======  =====  ==========  ==========  ======  ===================

(cant in mm, speed in km/h; the deficiency ``11.8 V^2 / R - D`` [mm] for a 1500 mm cant
base.)
"""

from __future__ import annotations

from dataclasses import dataclass

from express.base.units import KMH
from express.rail.track.geometry import Curve, Straight, Track, Transition, paper_curve

__all__ = ["NAMED_CURVES", "NamedCurve", "named_track"]


@dataclass(frozen=True)
class NamedCurve:
    """One bundled curve: radius [m], cant [m], transition and circular lengths [m],
    line speed [m/s]."""

    radius: float
    cant: float
    transition: float
    length: float
    speed: float

    def track(self) -> Track:
        """The whole track (module docstring), its speed the line speed."""
        segments = (Straight(50.0), Transition(self.transition), Curve(self.length, self.radius, "right", self.cant),
                    Transition(self.transition), Straight(50.0))
        return Track(segments, speed=self.speed)

    def describe(self) -> str:
        """``"R = 400 m right curve, 150 mm cant, 80 m transitions, 95 km/h"``."""
        return (f"R = {self.radius:g} m right curve, {self.cant * 1e3:g} mm cant, {self.transition:g} m linear "
                f"transitions, {self.length:g} m circular, {self.speed / KMH:g} km/h")


#: The bundled curves by name (module docstring).
NAMED_CURVES = {
    "R250": NamedCurve(250.0, 0.150, 70.0, 200.0, 75 * KMH),
    "R400": NamedCurve(400.0, 0.150, 80.0, 200.0, 95 * KMH),
    "R600": NamedCurve(600.0, 0.150, 100.0, 250.0, 115 * KMH),
    "R1000": NamedCurve(1000.0, 0.150, 130.0, 300.0, 150 * KMH),
    "R3000": NamedCurve(3000.0, 0.130, 170.0, 400.0, 230 * KMH),
}


def named_track(name: str) -> tuple[Track, str]:
    """The bundled track ``name`` (:data:`NAMED_CURVES` or ``"paper"``) and a description.

    Raises
    ------
    KeyError
        For an unknown name (the message lists the known ones).
    """
    if name == "paper":
        return paper_curve(), ("the paper's Fig. 9 curve: R = 400 m left curve, 95 mm cant, 95 m sine transitions, "
                               "170 m circular, 120 km/h")
    curve = NAMED_CURVES.get(name)
    if curve is None:
        raise KeyError(f"no bundled track {name!r}; the bundled ones are {', '.join([*NAMED_CURVES, 'paper'])}")
    return curve.track(), curve.describe()
