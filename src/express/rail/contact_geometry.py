"""Rigid wheelset on track: contact points, rolling radii, contact angles, roll and
curvatures against the lateral displacement y, from wheel and rail profiles.

The wheelset is shifted by ``y`` (positive to the left, the project's convention),
yawed by ``psi`` (a fixed angle of attack, positive turning the left wheel back) and
rolled by ``phi`` (positive lifts the left wheel) until both wheels touch their rails: the minimum vertical gap is zero on both sides.  For each ``y`` a
safeguarded Newton iteration on ``phi`` solves ``gap_left(phi) = gap_right(phi)``; the
gap minimum over the wheel's points is refined by a parabola through its neighbours.
A yawed wheel is replaced by its effective profile, the contact locus seen in the
track's cross-section (:mod:`express.rail.wheel_locus`), and each contact gets its lead
(longitudinal position).
The result is a :class:`ContactTable` of arrays over ``y``, built to be interpolated
cheaply (a later dynamic model reads ``y -> delta_r, contact angles, radii, curvatures``).
A jump of the contact point along the wheel between neighbouring ``y`` (flange contact,
a hollow tread) is reported in :attr:`ContactTable.jumps`; a second local gap minimum
closer than ``two_point_tolerance`` marks two-point contact.

Frames and signs are in ``docs/contact.md``.  All quantities are SI (m, rad, 1/m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from express.base.diagnostics import ArgumentError
from express.rail.contact_kernels import CONTACT_RESULTS, SIDES, WHEELSET_RESULTS, SurfaceTable, solve_all
from express.rail.profiles import Profile
from express.rail.wheel_locus import effective_profile

__all__ = ["ContactJump", "ContactSetup", "ContactTable", "contact_geometry", "prepare_surfaces"]

#: Steeper parts of a profile than this never carry the wheelset in the vertical-gap
#: formulation; they are cut off (S1002's steepest flange face is at 70 degrees).
_MAX_SLOPE_ANGLE = math.radians(85.0)


@dataclass(frozen=True)
class ContactSetup:
    """Where the profiles sit: track and wheelset dimensions [m].

    Attributes
    ----------
    gauge : float
        Track gauge, measured ``gauge_depth`` below the top of the (inclined) rails.
    flange_back : float
        Distance between the flange backs (inner faces) of the two wheels.
    inclination : float
        Rail inclination as a tangent toward the track centre (1:40 -> 0.025; 0 = upright);
        see :func:`express.rail.profiles.parse_inclination`.
    wheel_radius : float
        Nominal rolling radius r0 at the taping line.
    tapeline_offset : float
        Flange back to taping line (70 mm for S1002).
    gauge_depth : float
        Depth of the gauge measuring point below the rail top (14 mm, EN 13848-1).
    """

    gauge: float = 1.435
    flange_back: float = 1.360
    inclination: float = 1.0 / 40.0
    wheel_radius: float = 0.46
    tapeline_offset: float = 0.070
    gauge_depth: float = 0.014

    def __post_init__(self) -> None:
        for name in ("gauge", "flange_back", "wheel_radius", "tapeline_offset", "gauge_depth"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ArgumentError(f"{name} must be a positive length, not {value!r}")
        if not (math.isfinite(self.inclination) and 0.0 <= self.inclination <= 0.2):
            raise ArgumentError(f"inclination must be a tangent in 0..0.2, not {self.inclination!r}")
        if self.flange_back >= self.gauge:
            raise ArgumentError("flange_back must be smaller than the gauge")

    @property
    def tapeline_half_distance(self) -> float:
        """Lateral distance of each taping line from the wheelset centre [m]."""
        return 0.5 * self.flange_back + self.tapeline_offset




@dataclass(frozen=True, eq=False)
class Surface:
    """A profile tabulated on a uniform lateral grid for the contact search.

    ``z``, ``dz``, ``ddz`` are the height, slope and second derivative at
    ``start + step * k``; for a rail the abscissa is the track-side outward coordinate
    ``u`` (gauge and inclination applied), for a wheel the profile's own ``y``.
    """

    start: float
    step: float
    z: np.ndarray
    dz: np.ndarray
    ddz: np.ndarray
    offset: float = 0.0
    top: float = 0.0
    alpha: float = 0.0

    @property
    def table(self) -> SurfaceTable:
        """The arrays for the compiled kernels."""
        return SurfaceTable(float(self.start), float(self.step), *(np.ascontiguousarray(a, dtype=float)
                                                                   for a in (self.z, self.dz, self.ddz)))


@dataclass(frozen=True)
class ContactJump:
    """The contact point on one wheel jumps between two neighbouring displacements.

    ``side`` is ``"left"`` or ``"right"``; positions are lateral coordinates on the wheel
    profile (side frame, m) before and after the jump.
    """

    side: str
    y_before: float
    y_after: float
    position_before: float
    position_after: float


@dataclass(frozen=True, eq=False)
class ContactTable:
    """Contact geometry against the lateral displacement ``y``; every array has shape
    (n,) over ``y`` and per-side arrays have shape (2, n) with row 0 left, row 1 right.

    Attributes
    ----------
    y : wheelset lateral displacement [m], positive to the left.
    roll : wheelset roll angle phi [rad], positive lifting the left wheel.
    height : vertical displacement of the wheelset centre from its nominal height r0
        above the rail tops [m].
    delta_r : rolling radius difference r_left - r_right [m].
    radius : rolling radius [m].
    wheel_position : contact point on the wheel profile, side frame y [m].
    rail_position : contact point on the rail profile, side frame y (upright rail) [m].
    track_position : contact point, outward distance from the track centre [m].
    contact_angle : angle of the contact tangent to the track plane in the side frame
        [rad], positive when the wheel surface rises toward the field side (tread
        conicity, flange).
    wheel_curvature_lateral, rail_curvature_lateral : profile curvatures at the contact,
        positive convex [1/m].
    wheel_curvature_rolling : cos(angle to the axle) / radius [1/m].
    secondary_gap : smallest gap outside the contact's own valley [m] (inf if none).
    secondary_position : where on the wheel profile that gap is [m].
    two_point : secondary_gap <= the two-point tolerance.
    jumps : contact jumps found between neighbouring ``y``.
    setup : the :class:`ContactSetup` used.
    yaw : the wheelset's yaw psi [rad] (0: the contact points lie under the axle).
    lead : longitudinal position of the contact ahead of the wheelset centre, track
        frame [m] (zero without yaw).
    lead_rate : ``lead / yaw``, at ``yaw = 0`` its limit ``sigma (r tan(theta) - Y)``
        (``theta`` the contact's angle to the axle, ``Y`` its axial distance) [m/rad].
    """

    y: np.ndarray
    roll: np.ndarray
    height: np.ndarray
    delta_r: np.ndarray
    radius: np.ndarray
    wheel_position: np.ndarray
    rail_position: np.ndarray
    track_position: np.ndarray
    contact_angle: np.ndarray
    wheel_curvature_lateral: np.ndarray
    rail_curvature_lateral: np.ndarray
    wheel_curvature_rolling: np.ndarray
    secondary_gap: np.ndarray
    secondary_position: np.ndarray
    two_point: np.ndarray
    jumps: tuple[ContactJump, ...]
    setup: ContactSetup
    yaw: float = 0.0
    lead: np.ndarray = field(default_factory=lambda: np.zeros((2, 0)))
    lead_rate: np.ndarray = field(default_factory=lambda: np.zeros((2, 0)))

    def at(self, y: float | np.ndarray) -> dict[str, np.ndarray]:
        """Every quantity linearly interpolated at ``y`` (inside the table's range).

        Returns a dict name -> array of shape ``np.shape(y)`` (per-side quantities get a
        leading axis of 2).
        """
        y = np.asarray(y, dtype=float)
        if np.any((y < self.y[0]) | (y > self.y[-1])):
            raise ArgumentError(f"y outside the table ({self.y[0]:g} .. {self.y[-1]:g} m)")
        out: dict[str, np.ndarray] = {}
        for name in _TABLE_FIELDS:
            values = getattr(self, name)
            if values.ndim == 1:
                out[name] = np.interp(y, self.y, values)
            else:
                out[name] = np.stack([np.interp(y, self.y, row) for row in values])
        return out


_TABLE_FIELDS = (
    "roll", "height", "delta_r", "radius", "wheel_position", "rail_position", "track_position",
    "contact_angle", "wheel_curvature_lateral", "rail_curvature_lateral", "wheel_curvature_rolling", "lead",
    "lead_rate",
)


# ------------------------------------------------------------------------ preparation


def _spline(profile: Profile):
    from scipy.interpolate import CubicSpline

    return CubicSpline(profile.y, profile.z, bc_type="not-a-knot")


def _steep_cut(slope: np.ndarray, origin_index: int) -> tuple[int, int]:
    """The widest index range around ``origin_index`` where |slope| stays below the limit."""
    ok = np.abs(slope) <= math.tan(_MAX_SLOPE_ANGLE)
    if not ok[origin_index]:
        raise ArgumentError("the profile is steeper than 85 degrees at its origin")
    lo = origin_index
    while lo > 0 and ok[lo - 1]:
        lo -= 1
    hi = origin_index
    while hi < len(ok) - 1 and ok[hi + 1]:
        hi += 1
    return lo, hi


def wheel_surface(profile: Profile, step: float = 0.1e-3) -> Surface:
    """The wheel profile on a uniform grid of ``step`` [m], steep parts cut off."""
    spline = _spline(profile)
    count = math.floor((profile.y[-1] - profile.y[0]) / step) + 1
    s = profile.y[0] + step * np.arange(count)
    slope = spline(s, 1)
    lo, hi = _steep_cut(slope, int(np.argmin(np.abs(s))))
    s = s[lo : hi + 1]
    return Surface(float(s[0]), step, spline(s), spline(s, 1), spline(s, 2))


def rail_surface(profile: Profile, setup: ContactSetup, step: float = 0.02e-3) -> Surface:
    """The rail profile inclined, placed at the gauge and tabulated over the outward
    track coordinate ``u`` on a uniform grid of ``step`` [m]."""
    spline = _spline(profile)
    alpha = math.atan(setup.inclination)
    ca, sa = math.cos(alpha), math.sin(alpha)
    t = np.linspace(profile.y[0], profile.y[-1], int((profile.y[-1] - profile.y[0]) / 2e-6) + 1)
    z, dz = spline(t), spline(t, 1)
    # rotate about the crown toward the track centre (counter-clockwise in the side frame)
    u, h = ca * t - sa * z, sa * t + ca * z
    slope = (sa + ca * dz) / (ca - sa * dz)
    lo, hi = _steep_cut(np.where(ca - sa * dz > 0, slope, np.inf), int(np.argmax(h)))
    top = h[lo : hi + 1].max()
    gauge_point = _gauge_point(u, h - top, setup.gauge_depth)
    offset = 0.5 * setup.gauge - gauge_point
    u, t = u[lo : hi + 1], t[lo : hi + 1]
    grid = np.arange(math.ceil(u[0] / step) * step, u[-1], step)
    tt = np.interp(grid, u, t)
    for _ in range(2):  # Newton on u(t) = grid
        zt, dzt = spline(tt), spline(tt, 1)
        tt -= (ca * tt - sa * zt - grid) / (ca - sa * dzt)
    zt, dzt, ddzt = spline(tt), spline(tt, 1), spline(tt, 2)
    slope = (sa + ca * dzt) / (ca - sa * dzt)
    curvature = ddzt / (1.0 + dzt**2) ** 1.5
    height = sa * tt + ca * zt - top
    return Surface(float(grid[0] + offset), step, height, slope, curvature * (1.0 + slope**2) ** 1.5,
                   offset=offset, top=float(top), alpha=alpha)


def _gauge_point(u: np.ndarray, z: np.ndarray, depth: float) -> float:
    """Innermost u where the rail surface reaches ``depth`` below its top."""
    inside = np.flatnonzero(z >= -depth)
    if not len(inside) or inside[0] == 0:
        raise ArgumentError(f"the rail profile does not reach {depth * 1e3:g} mm below its top on the gauge side")
    i = inside[0]
    return float(np.interp(-depth, [z[i - 1], z[i]], [u[i - 1], u[i]]))


def prepare_surfaces(
    wheel: Profile,
    rail: Profile,
    setup: ContactSetup,
    *,
    wheel_right: Profile | None = None,
    rail_right: Profile | None = None,
    wheel_step: float = 0.1e-3,
    rail_step: float = 0.02e-3,
) -> tuple[Surface, Surface, Surface, Surface]:
    """Wheel and rail surfaces (left wheel, left rail, right wheel, right rail).

    The right profiles default to the left ones (a symmetric wheelset and track).
    """
    if wheel.kind != "wheel" or rail.kind != "rail":
        raise ArgumentError("contact geometry needs a wheel profile and a rail profile")
    wl = wheel_surface(wheel, wheel_step)
    rl = rail_surface(rail, setup, rail_step)
    wr = wl if wheel_right is None else wheel_surface(wheel_right, wheel_step)
    rr = rl if rail_right is None else rail_surface(rail_right, setup, rail_step)
    return wl, rl, wr, rr


# ----------------------------------------------------------------------------- solving


def contact_geometry(
    wheel: Profile,
    rail: Profile,
    y: np.ndarray,
    setup: ContactSetup | None = None,
    *,
    wheel_right: Profile | None = None,
    rail_right: Profile | None = None,
    two_point_tolerance: float = 10e-6,
    jump_threshold: float = 2e-3,
    wheel_step: float = 0.1e-3,
    rail_step: float = 0.02e-3,
    yaw: float = 0.0,
) -> ContactTable:
    """Contact geometry of a rigid wheelset at the lateral displacements ``y``, yawed by ``yaw``.

    Parameters
    ----------
    wheel, rail : Profile
        Profiles in their side frames (``docs/contact.md``); used on both sides unless
        ``wheel_right`` / ``rail_right`` are given.
    y : array_like, shape (n,)
        Lateral displacements [m], strictly increasing (e.g. ``np.arange(-10, 10.001, 0.01) * 1e-3``).
    setup : ContactSetup, optional
        Gauge, flange-back distance, rail inclination, wheel radius (defaults: 1435 mm,
        1360 mm, 1:40, 460 mm).
    two_point_tolerance : float
        A second gap minimum within this [m] of contact counts as two-point contact.
    jump_threshold : float
        A move of the contact point along the wheel by more than this [m] between
        neighbouring ``y`` is reported as a jump.
    yaw : float
        The wheelset's yaw angle psi [rad] (positive: the left wheel turned back, the
        project's yaw); the contacts are those of the contact locus
        (:mod:`express.rail.wheel_locus`), ``lead`` their longitudinal positions.

    Returns
    -------
    ContactTable
    """
    setup = setup or ContactSetup()
    y = np.asarray(y, dtype=float)
    if y.ndim != 1 or len(y) < 1 or not np.all(np.isfinite(y)) or np.any(np.diff(y) <= 0):
        raise ArgumentError("y must be a 1-D array of finite, strictly increasing displacements")
    if not (math.isfinite(yaw) and abs(yaw) < 0.2):
        raise ArgumentError(f"yaw must be an angle below 0.2 rad, not {yaw!r}")
    surfaces = prepare_surfaces(wheel, rail, setup, wheel_right=wheel_right, rail_right=rail_right,
                                wheel_step=wheel_step, rail_step=rail_step)
    return solve_contact(surfaces, y, setup, two_point_tolerance, jump_threshold, yaw=yaw)


def solve_contact(surfaces, y: np.ndarray, setup: ContactSetup, two_point_tolerance: float = 10e-6,
                  jump_threshold: float = 2e-3, *, yaw: float = 0.0) -> ContactTable:
    """:func:`contact_geometry` on surfaces from :func:`prepare_surfaces` (reuse them
    when the same profiles are solved many times).  A yawed wheel is replaced by its
    effective profile (:func:`express.rail.wheel_locus.effective_profile`); the contact
    positions are mapped back onto the wheel profiles and the leads added."""
    wl, rl, wr, rr = surfaces
    half = setup.tapeline_half_distance
    if yaw == 0.0:
        table = _solve_plain(surfaces, y, setup, two_point_tolerance, jump_threshold)
        sides = np.array([[1.0], [-1.0]])
        axle = np.tan(table.contact_angle - sides * table.roll)
        rate = sides * (table.radius * axle - (half + table.wheel_position))
        return replace(table, lead=np.zeros_like(rate), lead_rate=rate)
    profiles = [effective_profile(w.start, w.step, w.z, w.dz, setup.wheel_radius, half, abs(yaw)) for w in (wl, wr)]
    yawed = [Surface(p.start, p.step, p.z, p.dz, p.ddz) for p in profiles]
    table = _solve_plain((yawed[0], rl, yawed[1], rr), y, setup, two_point_tolerance, jump_threshold)
    grid = [p.start + p.step * np.arange(len(p.z)) for p in profiles]
    sign = math.copysign(1.0, yaw)
    lead = np.array([sigma * sign * np.interp(table.wheel_position[row], grid[row], profiles[row].lead)
                     for row, sigma in enumerate(SIDES)])
    position = np.array([np.interp(table.wheel_position[row], grid[row], profiles[row].position) for row in (0, 1)])
    secondary = np.array([np.interp(table.secondary_position[row], grid[row], profiles[row].position) for row in (0, 1)])
    jumps = tuple(replace(jump, position_before=float(np.interp(jump.position_before, grid[row], profiles[row].position)),
                          position_after=float(np.interp(jump.position_after, grid[row], profiles[row].position)))
                  for jump in table.jumps for row in (0 if jump.side == "left" else 1,))
    return replace(table, wheel_position=position, secondary_position=secondary, jumps=jumps, yaw=float(yaw),
                   lead=lead, lead_rate=lead / yaw)


def _solve_plain(surfaces, y: np.ndarray, setup: ContactSetup, two_point_tolerance: float,
                 jump_threshold: float) -> ContactTable:
    """The contact of the wheelset without yaw whose wheels are ``surfaces`` (lead not set)."""
    wl, rl, wr, rr = surfaces
    wheelset = np.zeros((len(WHEELSET_RESULTS), len(y)))
    contacts = np.zeros((len(CONTACT_RESULTS), 2, len(y)))
    status = solve_all(y, setup.wheel_radius, setup.tapeline_half_distance, (wl.table, wr.table),
                        (rl.table, rr.table), wheelset, contacts)
    if status >= 0:
        raise ArgumentError(
            f"no contact on both wheels at y = {y[status] * 1e3:g} mm: the wheels do not reach the rails "
            "(check gauge, flange-back distance and the profiles' lateral origins)"
        )
    return _table(y, wheelset, contacts, setup, (rl, rr), two_point_tolerance, jump_threshold)


def _table(y, wheelset, contacts, setup, rails, two_point_tolerance, jump_threshold) -> ContactTable:
    roll, height = (wheelset[WHEELSET_RESULTS.index(name)] for name in ("roll", "height"))
    position, track, rail_height, radius, angle = (contacts[CONTACT_RESULTS.index(name)] for name in (
        "wheel_position", "track_position", "rail_height", "radius", "contact_angle"))
    kw, kr, gap2, position2 = (contacts[CONTACT_RESULTS.index(name)] for name in (
        "wheel_curvature", "rail_curvature", "secondary_gap", "secondary_position"))
    # the rail contact in the upright rail's side frame: undo placement and inclination
    rail_position = np.empty_like(track)
    for row, rail in enumerate(rails):
        ca, sa = math.cos(rail.alpha), math.sin(rail.alpha)
        rail_position[row] = ca * (track[row] - rail.offset) + sa * (rail_height[row] + rail.top)
    jumps = []
    for row, side in enumerate(("left", "right")):
        moves = np.flatnonzero(np.abs(np.diff(position[row])) > jump_threshold)
        jumps += [ContactJump(side, float(y[i]), float(y[i + 1]), float(position[row, i]), float(position[row, i + 1]))
                  for i in moves]
    jumps.sort(key=lambda jump: (jump.y_before, jump.side))
    # angle to the axle = track-frame angle minus the side's share of the roll
    rolling = np.cos(angle - np.array([[1.0], [-1.0]]) * roll) / radius
    return ContactTable(
        y=y.copy(), roll=roll, height=height, delta_r=radius[0] - radius[1], radius=radius,
        wheel_position=position, rail_position=rail_position, track_position=track, contact_angle=angle,
        wheel_curvature_lateral=kw, rail_curvature_lateral=kr, wheel_curvature_rolling=rolling,
        secondary_gap=gap2, secondary_position=position2, two_point=gap2 <= two_point_tolerance,
        jumps=tuple(jumps), setup=setup,
    )
