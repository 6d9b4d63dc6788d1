"""Constant curves as the steady-curving solver takes them (:class:`SteadyCurve`: radius,
cant, direction, the unbalanced acceleration and its limit) and the checks of a curve or a
track against the vehicle (:func:`track_problems`); :class:`CurveError` for one that
cannot be run."""

from __future__ import annotations

import math
from dataclasses import dataclass

from express.base.diagnostics import InputError
from express.model.parameters import expression_value
from express.numeric.statespace import VehicleModel
from express.rail.track.geometry import turn_sign

__all__ = ["MAX_UNBALANCED_ACCELERATION", "CurveError", "SteadyCurve", "curves_of_track", "track_problems"]

#: Largest unbalanced lateral acceleration in the track plane a steady curve may ask for
#: [m/s^2], cant deficiency or excess: 2.0 m/s^2 is about 300 mm of cant deficiency on
#: standard gauge, beyond what the line standards allow even tilting trains
#: (``docs/curving.md``).
MAX_UNBALANCED_ACCELERATION = 2.0


class CurveError(InputError):
    """A curve the vehicle cannot run (bad geometry, too much unbalanced acceleration,
    no steady state): bad input, exit status 2 on the command line; one line per problem."""


@dataclass(frozen=True)
class SteadyCurve:
    """A constant curve.

    Attributes
    ----------
    radius : float
        [m], > 0.
    cant : float
        Rail height difference S [m], toward the centre of the curve (negative: adverse).
    direction : {"left", "right"}
        Seen in the direction of travel.
    """

    radius: float
    cant: float = 0.0
    direction: str = "right"

    @property
    def curvature(self) -> float:
        """Signed curvature rho [1/m] (positive to the left)."""
        return turn_sign(self.direction) / self.radius

    @property
    def signed_cant(self) -> float:
        """Signed cant S [m] (``docs/track.md``)."""
        return turn_sign(self.direction) * self.cant

    def unbalanced_acceleration(self, speed: float, cant_base: float, gravity: float) -> float:
        """Cant deficiency as an acceleration in the track plane toward the outside of
        the curve [m/s^2] (negative: cant excess): ``v^2 cos(phi) / R - g sin(phi)``."""
        sin_phi = self.cant / cant_base
        return speed**2 * math.sqrt(1.0 - sin_phi**2) / self.radius - gravity * sin_phi

    def speed_for(self, deficiency: float, cant_base: float, gravity: float) -> float:
        """The speed [m/s] at which the cant deficiency is ``deficiency`` [m/s^2]
        (negative: cant excess), inverting :meth:`unbalanced_acceleration`.

        Raises
        ------
        CurveError
            When no positive speed gives it (or the cant reaches the cant base).
        """
        sin_phi = self.cant / cant_base
        square = (deficiency + gravity * sin_phi) * self.radius / math.sqrt(1.0 - sin_phi**2) if abs(sin_phi) < 1 else -1.0
        if not square > 0:
            raise CurveError(f"no speed gives a cant deficiency of {deficiency:g} m/s^2 in R = {self.radius:g} m "
                             f"with {self.cant * 1e3:g} mm cant (cant base {cant_base:g} m)")
        return math.sqrt(square)

    def problems(self, speed: float, cant_base: float, gravity: float) -> list[str]:
        """Every reason the curve cannot be run at ``speed`` (empty if none)."""
        out = []
        if not (isinstance(self.radius, (int, float)) and math.isfinite(self.radius) and self.radius > 0):
            out.append(f"radius must be a positive number of metres, got {self.radius!r}")
        if not (isinstance(self.cant, (int, float)) and math.isfinite(self.cant)) or abs(self.cant) >= cant_base:
            out.append(f"cant {self.cant!r} m must be smaller than the cant base {cant_base:g} m")
        if self.direction not in ("left", "right"):
            out.append(f"direction must be 'left' or 'right', got {self.direction!r}")
        if not (math.isfinite(speed) and speed > 0):
            out.append(f"speed must be positive, got {speed!r} m/s")
        if not out:
            a = self.unbalanced_acceleration(speed, cant_base, gravity)
            if abs(a) > MAX_UNBALANCED_ACCELERATION:
                kind = "cant deficiency" if a > 0 else "cant excess"
                out.append(f"{speed * 3.6:.1f} km/h in R = {self.radius:g} m with {self.cant * 1e3:g} mm cant needs "
                           f"{abs(a):.2f} m/s^2 of unbalanced acceleration ({kind}), more than the limit "
                           f"{MAX_UNBALANCED_ACCELERATION:g} m/s^2")
        return out


def curves_of_track(track) -> list[SteadyCurve]:
    """The circular curves of a :class:`~express.rail.track.Track`, in order."""
    return [SteadyCurve(float(segment.radius), float(segment.cant), str(segment.direction))
            for segment in track.segments if hasattr(segment, "radius")]


def track_problems(vehicle: VehicleModel, track, speed: float) -> list[str]:
    """Why ``vehicle`` cannot run ``track`` at ``speed`` [m/s]: every circular curve
    checked as :meth:`SteadyCurve.problems` (cant against the cant base, unbalanced
    acceleration against :data:`MAX_UNBALANCED_ACCELERATION`); empty if none."""
    if vehicle.model is None or vehicle.model.rail is None:
        return []
    base = expression_value(vehicle.model.rail.cant_base, vehicle.values)
    gravity = expression_value(vehicle.model.rail.gravity, vehicle.values)
    return [f"curve {k + 1} of the track (R = {curve.radius:g} m): {problem}"
            for k, curve in enumerate(curves_of_track(track)) for problem in curve.problems(speed, base, gravity)]
