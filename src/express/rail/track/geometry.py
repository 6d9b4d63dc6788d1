"""Track layout and its exact plane geometry.

This module owns the **layout** of a track: a sequence of segments (:class:`Straight`,
:class:`Transition`, :class:`Curve`) and, in :class:`Track`, the functions of the
distance ``s`` along the track that the rail modules need: signed curvature
``rho(s)``, its rate, signed cant ``S(s)``, its rate, and the lateral irregularity the
track carries. It also gives the **exact plane geometry** of the centreline (heading,
``(X, Y)``, offset of the track ahead of a point from the tangent there), against which
the small-curvature approximations used by the vehicle model are checked, and the
paper's test curve (:func:`paper_curve`).

Conventions (``docs/track.md``, ``docs/rail.md``): x forward, y left, z up; distances
in metres from the start of the track. The signed curvature ``rho`` is positive for a
curve to the LEFT; the signed cant ``S`` (rail height difference, metres) is positive
when the track is rolled toward the centre of a left curve, so a normally canted right
curve has ``rho < 0`` and ``S < 0``. Before the start (``s < 0``) and after the end
(``s >= length``) the track is straight with no cant. Curvature, cant and their rates
are right-continuous: at a joint they take the value of the segment that starts there.

Limits: a track is at most :data:`MAX_TRACK_LENGTH` long, and ``|cant| <=``
:data:`MAX_CANT`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from express.base.diagnostics import ArgumentError
from express.rail.track._common import FieldProblem, FloatArray, as_input, as_output, is_finite_number, raise_if
from express.rail.track.irregularity import Irregularity, NoIrregularity
from express.rail.track.tables import CONSTANT, RAMP_CODES, CentrelineTable, SegmentTables, ramp

__all__ = [
    "DIRECTIONS",
    "MAX_CANT",
    "MAX_TRACK_LENGTH",
    "TRACK_COMPONENTS",
    "TRANSITION_SHAPES",
    "Curve",
    "Segment",
    "Straight",
    "Track",
    "Transition",
    "paper_curve",
    "turn_sign",
]

#: Transition shapes: ``"linear"`` (clothoid: curvature and cant linear in s) and
#: ``"sine"`` (half-wave sine ramp, ``(1 - cos(pi s / L)) / 2``).
TRANSITION_SHAPES = ("linear", "sine")
#: The track's irregularity components (EN 13848 names): alignment ``yR``, vertical level,
#: cross level, gauge (the order of :data:`express.rail.track.spectra.COMPONENTS`).
TRACK_COMPONENTS = ("alignment", "vertical", "cross_level", "gauge")
#: Curve directions.
DIRECTIONS = ("left", "right")
#: Longest track (and segment) [m]: 1000 km. The exact centreline keeps a point every
#: 10 m, so this bounds its table to 1e5 points.
MAX_TRACK_LENGTH = 1.0e6
#: Largest cant (rail height difference) [m]. Real cant stays below 0.2 m; a larger
#: value is a unit mistake (``cant = 95`` meaning millimetres).
MAX_CANT = 0.5

# ---------------------------------------------------------------------------------------
# Segments
# ---------------------------------------------------------------------------------------


def _length_problems(length: Any) -> list[FieldProblem]:
    if not is_finite_number(length):
        return [("length", f"'length' must be a finite number of metres, got {length!r}")]
    if length <= 0:
        return [("length", f"'length' must be > 0 m, got {length!r}")]
    if length > MAX_TRACK_LENGTH:
        return [("length", f"'length' must be at most {MAX_TRACK_LENGTH:g} m, got {length!r}")]
    return []


@dataclass(frozen=True)
class Straight:
    """Straight track: zero curvature, zero cant.

    Parameters
    ----------
    length : float
        Length along the track [m], 0 < length <= :data:`MAX_TRACK_LENGTH`.
    """

    length: float

    @staticmethod
    def field_problems(length: Any) -> list[FieldProblem]:
        """``(field, message)`` for every bad value (empty if none)."""
        return _length_problems(length)

    def __post_init__(self) -> None:
        raise_if(self.field_problems(self.length), "Straight")


@dataclass(frozen=True)
class Transition:
    """Transition curve: curvature and cant ramp between the neighbouring segments.

    The start values are those at the end of the previous segment and the end values
    those at the start of the next one (zero, straight track, when the transition is
    first or last). Two transitions may not follow each other.

    Parameters
    ----------
    length : float
        Length along the track [m], 0 < length <= :data:`MAX_TRACK_LENGTH`.
    shape : {"linear", "sine"}
        ``"linear"``: curvature and cant vary linearly with s (clothoid, linear cant
        ramp). ``"sine"``: they follow ``v0 + (v1 - v0) (1 - cos(pi u)) / 2`` with
        ``u = (s - s0) / length``, the half-wave sine ramp used in Japan, whose rate is
        zero at both ends.
    """

    length: float
    shape: str = "linear"

    @staticmethod
    def field_problems(length: Any, shape: Any = "linear") -> list[FieldProblem]:
        """``(field, message)`` for every bad value (empty if none)."""
        out = _length_problems(length)
        if shape not in TRANSITION_SHAPES:
            out.append(("shape", f"'shape' must be one of {', '.join(TRANSITION_SHAPES)}, got {shape!r}"))
        return out

    def __post_init__(self) -> None:
        raise_if(self.field_problems(self.length, self.shape), "Transition")


def turn_sign(direction: str) -> float:
    """``+1.0`` for a curve to the left, ``-1.0`` to the right (the sign of its curvature
    and of its cant in the track frame, ``docs/track.md``).

    >>> turn_sign("left"), turn_sign("right")
    (1.0, -1.0)
    """
    return 1.0 if direction == "left" else -1.0


@dataclass(frozen=True)
class Curve:
    """Circular curve of constant radius and cant.

    Parameters
    ----------
    length : float
        Length along the track [m], 0 < length <= :data:`MAX_TRACK_LENGTH`.
    radius : float
        Radius [m], > 0.
    direction : {"left", "right"}
        Direction the track turns, seen in the direction of travel (+x).
    cant : float
        Cant as the rail height difference S [m] (outer rail above inner rail), toward
        the centre of the curve; default 0. A negative value is adverse cant.
        ``|cant| <=`` :data:`MAX_CANT`.
    """

    length: float
    radius: float
    direction: str
    cant: float = 0.0

    @staticmethod
    def field_problems(length: Any, radius: Any, direction: Any, cant: Any = 0.0) -> list[FieldProblem]:
        """``(field, message)`` for every bad value (empty if none)."""
        out = _length_problems(length)
        if not is_finite_number(radius):
            out.append(("radius", f"'radius' must be a finite number of metres, got {radius!r}"))
        elif radius <= 0:
            out.append(("radius", f"'radius' must be > 0 m, got {radius!r}"))
        if direction not in DIRECTIONS:
            out.append(("direction", f"'direction' must be one of {', '.join(DIRECTIONS)}, got {direction!r}"))
        if not is_finite_number(cant):
            out.append(("cant", f"'cant' must be a finite number of metres, got {cant!r}"))
        elif abs(cant) > MAX_CANT:
            out.append(("cant", f"'cant' must be at most {MAX_CANT} m in size, got {cant!r} m "
                                "(millimetres written as metres?)"))
        return out

    def __post_init__(self) -> None:
        raise_if(self.field_problems(self.length, self.radius, self.direction, self.cant), "Curve")

    @property
    def curvature(self) -> float:
        """Signed curvature rho [1/m]: ``+1/radius`` to the left, ``-1/radius`` right."""
        return turn_sign(self.direction) / self.radius

    @property
    def signed_cant(self) -> float:
        """Signed cant S [m]: ``+cant`` in a left curve, ``-cant`` in a right curve."""
        return turn_sign(self.direction) * self.cant


#: Any segment of a track.
Segment = Straight | Transition | Curve


def _segment_arrays(segments: Sequence[Segment]) -> tuple[FloatArray, ...]:
    """Lengths, ramp codes and start/end curvature and cant of each segment.

    A transition ramps from the end values of the previous segment to the start values
    of the next one (straight track, 0, when there is none).
    """
    n = len(segments)
    lengths = np.array([float(sg.length) for sg in segments])
    shape = np.full(n, CONSTANT)
    rho0, rho1, cant0, cant1 = (np.zeros(n) for _ in range(4))
    for i, sg in enumerate(segments):
        if isinstance(sg, Transition):
            shape[i] = RAMP_CODES[sg.shape]
            rho0[i], cant0[i] = _end_values(segments[i - 1] if i > 0 else None)
            rho1[i], cant1[i] = _end_values(segments[i + 1] if i + 1 < n else None)
        else:
            rho0[i], cant0[i] = rho1[i], cant1[i] = _end_values(sg)
    return lengths, shape, rho0, rho1, cant0, cant1


def _end_values(segment: Segment | None) -> tuple[float, float]:
    """Curvature and cant a neighbouring transition ramps to (0, 0 for none/straight)."""
    return (segment.curvature, segment.signed_cant) if isinstance(segment, Curve) else (0.0, 0.0)


# ---------------------------------------------------------------------------------------
# Track
# ---------------------------------------------------------------------------------------


def _track_problems(segments: Any, irregularity: Any, speed: Any,
                    components: dict[str, Any] | None = None) -> list[FieldProblem]:
    if not isinstance(segments, (tuple, list)):
        return [("segments", f"segments must be a tuple of Straight, Transition, Curve, got {segments!r}")]
    out: list[FieldProblem] = []
    for i, seg in enumerate(segments, 1):
        if not isinstance(seg, (Straight, Transition, Curve)):
            out.append(("segments", f"segment {i} is not a Straight, Transition or Curve: {seg!r}"))
    for i in range(1, len(segments)):
        if isinstance(segments[i - 1], Transition) and isinstance(segments[i], Transition):
            out.append(("segments", f"segments {i} and {i + 1} are both transitions (a transition takes "
                                    "its end values from its neighbours)"))
    if not out:
        total = math.fsum(float(seg.length) for seg in segments)
        if total > MAX_TRACK_LENGTH:
            out.append(("segments", f"the segments are {total:.6g} m long, more than the limit "
                                    f"{MAX_TRACK_LENGTH:g} m"))
    if not isinstance(irregularity, Irregularity):
        out.append(("irregularity", f"irregularity is not an Irregularity: {irregularity!r}"))
    for name, component in (components or {}).items():
        if not isinstance(component, Irregularity):
            out.append((name, f"{name} is not an Irregularity: {component!r}"))
    if speed is not None and not (is_finite_number(speed) and speed > 0):
        out.append(("speed", f"speed must be > 0 m/s, got {speed!r}"))
    return out


@dataclass(frozen=True)
class Track:
    """A track: segments one after the other, plus its irregularities (alignment, vertical
    level, cross level, gauge).

    The segments start at s = 0. Methods taking ``s`` accept floats or arrays and are
    vectorized (a float in, a float out). Before s = 0 and from s = ``length`` on, the
    track is straight, without cant, continuing the tangent at the end.

    Parameters
    ----------
    segments : tuple of Straight, Transition, Curve
        The layout, in order (a list is accepted and kept). No two transitions may
        follow each other; at most :data:`MAX_TRACK_LENGTH` in all.
    irregularity : Irregularity
        Lateral irregularity yR(s); default none.
    speed : float or None
        Nominal running speed [m/s] from the track file, if any (informative; the track
        itself does not use it).
    vertical : Irregularity
        Vertical level (longitudinal level) ``z_v(s)`` [m]: the mean height of the two
        rails, + up; default none.
    cross_level : Irregularity
        Cross level ``c(s) = z_R - z_L`` [m], the sign of the cant (+ when the right
        rail is higher); default none.  A twist is its gradient ``dc/ds``.
    gauge : Irregularity
        Gauge variation ``g(s)`` [m], + wider; default none.

    The rail heights are ``z_L = z_v - c/2``, ``z_R = z_v + c/2`` and the rails' lateral
    positions ``y_L = yR + g/2``, ``y_R = yR - g/2`` (``docs/track.md``, "Track
    components").
    """

    segments: Sequence[Segment] = ()
    irregularity: Irregularity = field(default_factory=NoIrregularity)
    speed: float | None = None
    vertical: Irregularity = field(default_factory=NoIrregularity)
    cross_level: Irregularity = field(default_factory=NoIrregularity)
    gauge: Irregularity = field(default_factory=NoIrregularity)

    def __post_init__(self) -> None:
        components = {"vertical": self.vertical, "cross_level": self.cross_level, "gauge": self.gauge}
        raise_if(_track_problems(self.segments, self.irregularity, self.speed, components), "Track")

    def component(self, name: str) -> Irregularity:
        """The irregularity of one EN 13848 component: ``"alignment"`` (``yR``),
        ``"vertical"``, ``"cross_level"`` or ``"gauge"``."""
        if name == "alignment":
            return self.irregularity
        if name in TRACK_COMPONENTS:
            return getattr(self, name)
        raise ArgumentError(f"unknown track component {name!r} (known: {', '.join(TRACK_COMPONENTS)})")

    @property
    def applied_components(self) -> tuple[str, ...]:
        """The components other than none, in the order of :data:`TRACK_COMPONENTS`."""
        return tuple(name for name in TRACK_COMPONENTS if not isinstance(self.component(name), NoIrregularity))

    @classmethod
    def field_problems(cls, segments: Any, irregularity: Any = None, speed: Any = None) -> list[FieldProblem]:
        """``(field, message)`` for every problem of the layout as a whole (empty if none)."""
        return _track_problems(segments, NoIrregularity() if irregularity is None else irregularity, speed)

    # --- tables ---------------------------------------------------------------------

    @cached_property
    def tables(self) -> SegmentTables:
        """Per-segment arrays (computed on first use, then kept)."""
        return SegmentTables.build(*_segment_arrays(self.segments))

    @cached_property
    def centreline_table(self) -> CentrelineTable:
        """Centreline knots for :meth:`centreline` (computed on first use, then kept)."""
        return CentrelineTable.build(self.tables)

    # --- evaluation -----------------------------------------------------------------

    @property
    def length(self) -> float:
        """Total length of the segments [m]."""
        return self.tables.length

    @property
    def boundaries(self) -> FloatArray:
        """Distances of the segment joints [m], from 0 to ``length`` (n + 1 values)."""
        return self.tables.starts.copy()

    def _profile(self, s: ArrayLike, start: FloatArray, end: FloatArray, rate: bool) -> FloatArray | float:
        arr, scalar = as_input(s)
        tables = self.tables
        if tables.count == 0:
            return as_output(np.zeros_like(arr), scalar)
        k, u, inside = tables.locate(arr)
        f, df, _ = ramp(tables.shape[k], u)
        jump = end[k] - start[k]
        val = jump * df / tables.lengths[k] if rate else start[k] + jump * f
        return as_output(np.where(inside, val, 0.0), scalar)

    def geometry(self, s: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Curvature, its rate, cant and its rate at ``s`` in one pass (arrays).

        The same values as :meth:`curvature` [1/m], :meth:`curvature_rate` [1/m^2],
        :meth:`cant` [m] and :meth:`cant_rate` [m/m], locating each ``s`` [m] in its
        segment once (for simulations); each array has the shape of ``s``.
        """
        arr = np.asarray(s, dtype=float)
        tables = self.tables
        if tables.count == 0:
            zeros = np.zeros_like(arr)
            return zeros, zeros, zeros, zeros
        k, u, inside = tables.locate(arr)
        f, df, _ = ramp(tables.shape[k], u)
        length = tables.lengths[k]
        out = []
        for start, end in ((tables.rho0, tables.rho1), (tables.cant0, tables.cant1)):
            jump = end[k] - start[k]
            out.append(np.where(inside, start[k] + jump * f, 0.0))
            out.append(np.where(inside, jump * df / length, 0.0))
        return out[0], out[1], out[2], out[3]

    def curvature(self, s: ArrayLike) -> FloatArray | float:
        """Signed curvature rho(s) [1/m], > 0 for a curve to the left."""
        return self._profile(s, self.tables.rho0, self.tables.rho1, rate=False)

    def curvature_rate(self, s: ArrayLike) -> FloatArray | float:
        """d rho / ds [1/m^2] (zero outside the transitions)."""
        return self._profile(s, self.tables.rho0, self.tables.rho1, rate=True)

    def cant(self, s: ArrayLike) -> FloatArray | float:
        """Signed cant S(s) [m], > 0 when rolled toward the centre of a left curve."""
        return self._profile(s, self.tables.cant0, self.tables.cant1, rate=False)

    def cant_rate(self, s: ArrayLike) -> FloatArray | float:
        """d S / ds [m/m] (zero outside the transitions)."""
        return self._profile(s, self.tables.cant0, self.tables.cant1, rate=True)

    def lateral_irregularity(self, s: ArrayLike) -> FloatArray | float:
        """Lateral irregularity yR(s) [m] (y left)."""
        return self.irregularity.value(s)

    def lateral_irregularity_rate(self, s: ArrayLike) -> FloatArray | float:
        """d yR / ds [m/m]."""
        return self.irregularity.rate(s)

    def with_irregularity(self, irregularity: Irregularity) -> Track:
        """The same layout with another irregularity."""
        return replace(self, irregularity=irregularity)

    # --- exact geometry -------------------------------------------------------------

    def heading(self, s: ArrayLike) -> FloatArray | float:
        """Heading theta(s) [rad] of the centreline tangent from +X, = int_0^s rho.

        Exact (closed form per segment). 0 before the start, constant after the end.
        """
        arr, scalar = as_input(s)
        return as_output(self.tables.heading_inside(arr), scalar)

    def centreline(self, s: ArrayLike) -> tuple[FloatArray | float, FloatArray | float]:
        """Plane coordinates (X, Y) [m] of the centreline at distance s [m].

        X along the initial tangent, Y to its left; the start is the origin. The heading
        is integrated with a 16-point Gauss-Legendre rule on pieces of at most 10 m
        inside one segment (where the heading is smooth), accurate to about 1e-12 m.
        Before the start and after the end the centreline is straight.
        """
        arr, scalar = as_input(s)
        tables, table = self.tables, self.centreline_table
        length = tables.length
        sc = np.clip(arr, 0.0, length)
        j = np.clip(np.searchsorted(table.knots, sc, side="right") - 1, 0, max(table.knots.size - 2, 0))
        if table.knots.size > 1:
            dx, dy = tables.integrate_tangent(table.knots[j], sc)
        else:
            dx = dy = np.zeros_like(sc)
        x = table.x[j] + dx
        y = table.y[j] + dy
        th_end = tables.heading0[-1]
        before, after = arr < 0.0, arr > length
        x = np.where(before, arr, np.where(after, x + (arr - length) * np.cos(th_end), x))
        y = np.where(after, y + (arr - length) * np.sin(th_end), np.where(before, 0.0, y))
        return as_output(x, scalar), as_output(y, scalar)

    def lateral_offset_exact(self, s: ArrayLike, lx: ArrayLike) -> FloatArray | float:
        """Offset [m] of the centreline point at s + lx from the tangent line at s.

        Measured perpendicular to the tangent at s, positive to the left: the natural
        geometric sign, so the track ahead (or behind) in a left curve is at about
        ``+rho lx^2 / 2``. The vehicle model's lateral displacement of a connection
        point ``lx`` ahead of a body at station s, relative to the track at the point's
        own station, is MINUS this (``-rho lx^2 / 2`` to first order).

        Parameters
        ----------
        s : array_like
            Station of the tangent [m].
        lx : array_like
            Distance along the track to the point, positive ahead [m]; broadcast with s.
        """
        s_arr, lx_arr = np.broadcast_arrays(np.asarray(s, float), np.asarray(lx, float))
        x0, y0 = self.centreline(s_arr)
        x1, y1 = self.centreline(s_arr + lx_arr)
        th = self.tables.heading_inside(s_arr)
        out = -(np.asarray(x1) - x0) * np.sin(th) + (np.asarray(y1) - y0) * np.cos(th)
        return as_output(out, s_arr.ndim == 0)

    def lateral_offset_first_order(self, s: ArrayLike, lx: ArrayLike) -> FloatArray | float:
        """First-order offset ``rho(s) lx^2 / 2`` [m] (sign of :meth:`lateral_offset_exact`)."""
        s_arr, lx_arr = np.broadcast_arrays(np.asarray(s, float), np.asarray(lx, float))
        out = np.asarray(self.curvature(s_arr)) * lx_arr**2 / 2
        return as_output(out, s_arr.ndim == 0)

    def lateral_offset_second_order(self, s: ArrayLike, lx: ArrayLike) -> FloatArray | float:
        """Offset ``rho(s) lx^2 / 2 + rho'(s) lx^3 / 6`` [m], with the curvature rate."""
        s_arr, lx_arr = np.broadcast_arrays(np.asarray(s, float), np.asarray(lx, float))
        out = (np.asarray(self.curvature(s_arr)) * lx_arr**2 / 2
               + np.asarray(self.curvature_rate(s_arr)) * lx_arr**3 / 6)
        return as_output(out, s_arr.ndim == 0)

    def lateral_offset_two_station(self, s: ArrayLike, lx: ArrayLike) -> FloatArray | float:
        """Offset ``lx^2 (rho(s) / 3 + rho(s + lx) / 6)`` [m] from two curvatures.

        The offset to first order in rho is ``int_0^lx (lx - t) rho(s + t) dt``; this
        rule is exact for it when rho is linear between s and s + lx (a clothoid), needs
        no curvature rate, and uses only the curvature at the body's station and at the
        point's station.
        """
        s_arr, lx_arr = np.broadcast_arrays(np.asarray(s, float), np.asarray(lx, float))
        out = lx_arr**2 * (np.asarray(self.curvature(s_arr)) / 3
                           + np.asarray(self.curvature(s_arr + lx_arr)) / 6)
        return as_output(out, s_arr.ndim == 0)


def paper_curve(
    direction: str = "left",
    *,
    lead_in: float = 50.0,
    lead_out: float | None = None,
    shape: str = "sine",
    radius: float = 400.0,
    cant: float = 0.095,
    transition_length: float = 95.0,
    curve_length: float = 170.0,
    irregularity: Irregularity | None = None,
    speed: float | None = 120.0 / 3.6,
) -> Track:
    """The curve of the paper's Fig. 9 (Tanifuji & Suzuki 2001, section 4.3).

    Straight ``lead_in``, transition 95 m, circular curve R = 400 m of 170 m with
    95 mm cant, transition 95 m, straight ``lead_out``: 460 m with the default 50 m
    straights. The paper gives neither the lengths of the straights nor the direction
    nor the transition shape ("curvature and cant change smoothly"); the defaults here
    are 50 m, LEFT (so rho > 0, as plotted in Fig. 9) and the half-wave sine ramp.

    Parameters
    ----------
    direction : {"left", "right"}
        Direction of the curve; default ``"left"``.
    lead_in : float
        Straight before the first transition [m], >= 0 (0: none); default 50.
    lead_out : float or None
        Straight after the second transition [m]; default: same as ``lead_in``.
    shape : {"sine", "linear"}
        Transition shape; default ``"sine"``.
    radius, cant, transition_length, curve_length : float
        [m]; defaults 400, 0.095, 95, 170.
    irregularity : Irregularity or None
        Default none.
    speed : float or None
        Nominal speed [m/s]; default 120 km/h, the speed of Fig. 9.

    Returns
    -------
    Track
    """
    lead_out = lead_in if lead_out is None else lead_out
    segments: list[Segment] = []
    if lead_in > 0:
        segments.append(Straight(lead_in))
    segments += [
        Transition(transition_length, shape),
        Curve(curve_length, radius, direction, cant),
        Transition(transition_length, shape),
    ]
    if lead_out > 0:
        segments.append(Straight(lead_out))
    return Track(tuple(segments), NoIrregularity() if irregularity is None else irregularity, speed)
