"""Contact tables for the dynamics: the contact geometry of a wheel/rail pair, with the
Hertz ellipse and Kalker's coefficients of every contact, on a uniform grid of the
lateral displacement, ready for compiled look-ups; the quasi-linear contact parameters
of the linearised wheelset (Wickens' contact-angle and roll parameters).

A :class:`ContactTables` holds, for the left (row 0) and right (row 1) contact of a
rigid wheelset at every ``y`` of the grid, without yaw and, when asked
(``yaw_nodes``), at the yaw nodes ``|psi| = 5, 10, ..., 30 mrad``
(:mod:`express.rail.contact_geometry`, the yawed wheel's contact locus of
:mod:`express.rail.wheel_locus`):
the rolling radius, the contact angle in the track plane ``delta`` (positive when the
wheel surface rises toward the field side), the angle of the contact to the axle
``theta = delta -+ roll`` (what the spin sees), the lateral distance of the contact
from the wheelset centre, the Hertz semi-axes for a normal force of 1 N (they scale
with ``N^(1/3)``), Kalker's C11, C22, C23 (they depend on the ellipse's shape only),
the roll and its slope, and the contact's lead per unit yaw (``lead / psi``).  Quantities
are interpolated linearly in ``y`` between the nodes (a contact jump, tread to flange, is
a step between two nodes 10 um apart) and linearly in ``psi^2`` between the yaw nodes
(exact for the second-order changes of the geometry with yaw, which is even in ``psi``
apart from the lead's sign); beyond 30 mrad the last node's geometry holds.  With one
node (the simulation's default) the yaw enters through the lead, ``psi lead_rate``, exact
to first order.

:func:`rail_deflection_map` adds the lateral elasticity of the rails (the model's
``rail_stiffness``): each rail is pushed outward by the change of the lateral component
of its wheel's normal force, ``Q (tan delta - tan delta_0)``, so that the contact sits
at ``u`` where ``y = u + (Q / kR)(tan delta(u) - tan delta_0)``.  This is what makes the
flange contact elastic.

:func:`linear_contact_parameters` gives the quantities of Wickens' linearised wheelset at
an amplitude (``docs/contact.md``, "Linear model from the contact").

All quantities SI.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np

from express.base.diagnostics import ArgumentError
from express.rail.contact import hertz_contact
from express.rail.contact_geometry import ContactJump, ContactSetup, ContactTable, prepare_surfaces, solve_contact
from express.rail.kalker import kalker_coefficients
from express.rail.profiles import Profile

__all__ = [
    "FIELDS",
    "YAW_NODES",
    "YAW_STEP",
    "ContactTables",
    "LinearContact",
    "RailMap",
    "contact_tables",
    "describing_gain",
    "linear_contact_parameters",
    "rail_deflection_map",
]

#: Per-side fields of :attr:`ContactTables.data`, in order.
FIELDS = ("radius", "angle", "axle_angle", "arm", "semi_a", "semi_b", "c11", "c22", "c23", "roll", "roll_slope",
          "cos_angle", "sin_angle", "sin_axle_angle", "lead_rate", "secant_cbrt")
(RADIUS, ANGLE, AXLE_ANGLE, ARM, SEMI_A, SEMI_B, C11, C22, C23, ROLL, ROLL_SLOPE,
 COS_ANGLE, SIN_ANGLE, SIN_AXLE, LEAD_RATE, SECANT_CBRT) = range(len(FIELDS))
#: The yaw nodes of tables over yaw: ``|psi| = YAW_STEP k``, ``k = 0 .. YAW_NODES - 1`` [rad]
#: (``contact_tables(..., yaw_nodes=YAW_NODES)``; the simulation's default is one node).
YAW_STEP, YAW_NODES = 5e-3, 7
#: Smallest lateral relative curvature used for Hertz [1/m]: a conformal contact is
#: not Hertzian; this bounds the ellipse's width (S1002 on 60E1 never comes below 0.28).
_MIN_CURVATURE = 0.02


@dataclass(frozen=True, eq=False)
class ContactTables:
    """Contact quantities of a wheel/rail pair on a uniform grid of ``y``.

    Attributes
    ----------
    start, step : float
        ``y[k] = start + step k`` [m].
    data : numpy.ndarray, shape (len(FIELDS), 2, n)
        ``data[f, side, k]`` of the wheelset without yaw, fields :data:`FIELDS`: radius
        (the contact's depth below the axle) [m], angle [rad], axle_angle [rad], arm [m],
        semi_a and semi_b [m per N^(1/3)], c11, c22, c23 [-], roll [rad] (same on both
        rows), roll_slope [rad/m], and for the force kernel cos and sin of the angle,
        ``cos(psi) sin(axle_angle)`` (the spin's share of the rotation), the lead per unit
        yaw [m/rad] and cos(angle)^(-1/3).
    setup : ContactSetup
    youngs_modulus, poisson : float
        Material of both bodies [Pa, -].
    names : str
        ``"wheel/rail"`` for displays.
    jumps : tuple of ContactJump
        Contact jumps of the underlying geometry (without yaw).
    yawed : numpy.ndarray, shape (YAW_NODES, len(FIELDS), 2, n)
        ``data`` at each yaw node ``|psi| = YAW_STEP k`` (``yawed[0]`` is ``data``).
    """

    start: float
    step: float
    data: np.ndarray
    setup: ContactSetup
    youngs_modulus: float
    poisson: float
    names: str
    jumps: tuple = ()
    yawed: np.ndarray | None = None

    @property
    def y(self) -> np.ndarray:
        """The grid [m]."""
        return self.start + self.step * np.arange(self.data.shape[2])

    @property
    def nodes(self) -> np.ndarray:
        """:attr:`yawed`, or :attr:`data` as the one node when there is no yaw."""
        return self.data[None] if self.yawed is None else self.yawed

    @property
    def kernel(self) -> np.ndarray:
        """:attr:`nodes` in the compiled look-up's layout (yaw nodes, 2, n, fields), contiguous."""
        cached = self.__dict__.get("_kernel")
        if cached is None:
            cached = np.ascontiguousarray(self.nodes.transpose(0, 2, 3, 1))
            object.__setattr__(self, "_kernel", cached)
        return cached

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson))

    def at(self, y: float) -> dict[str, np.ndarray]:
        """Every field at ``y`` (linear interpolation, inside the grid), shape (2,) each."""
        grid = self.y
        if not grid[0] <= y <= grid[-1]:
            raise ArgumentError(f"y = {y * 1e3:g} mm outside the table ({grid[0] * 1e3:g} .. {grid[-1] * 1e3:g} mm)")
        return {name: np.array([np.interp(y, grid, self.data[f, side]) for side in (0, 1)])
                for f, name in enumerate(FIELDS)}


#: Tables already built, by the content of their arguments (a table takes seconds).
_CACHE: dict[tuple, ContactTables] = {}
_CACHE_SIZE = 16


def _profile_key(profile: Profile) -> tuple:
    digest = hashlib.sha1(np.ascontiguousarray(profile.y).tobytes() + np.ascontiguousarray(profile.z).tobytes())
    return profile.name, profile.kind, digest.hexdigest()


def _tables(wheel: Profile, rail: Profile, setup: ContactSetup, youngs_modulus: float, poisson: float,
            reach: float, step: float, yaw_nodes: int) -> ContactTables:
    count = math.ceil(reach / step - 1e-9)
    y = step * np.arange(-count, count + 1)
    surfaces = prepare_surfaces(wheel, rail, setup)
    hertz: dict[tuple[float, float], tuple[float, ...]] = {}
    yawed: list[np.ndarray] = []
    jumps: tuple[ContactJump, ...] = ()
    for node in range(yaw_nodes):
        geometry = solve_contact(surfaces, y, setup, yaw=YAW_STEP * node)
        bad = ~np.all(np.isfinite(geometry.radius) & np.isfinite(geometry.wheel_curvature_lateral), axis=0)
        if bad.any():
            raise ArgumentError(f"{wheel.name}/{rail.name}: no contact inside the profiles at y = "
                                f"{y[np.argmax(bad)] * 1e3:g} mm, yaw {YAW_STEP * node * 1e3:g} mrad "
                                f"(the contact runs off the end of a profile within +-{reach * 1e3:g} mm)")
        yawed.append(_node_data(geometry, youngs_modulus, poisson, hertz))
        jumps = jumps or geometry.jumps
    stack = np.array(yawed)
    return ContactTables(float(y[0]), step, stack[0], setup, float(youngs_modulus), float(poisson),
                         f"{wheel.name}/{rail.name}", jumps, stack)


def _node_data(geometry: ContactTable, youngs_modulus: float, poisson: float,
               hertz: dict[tuple[float, float], tuple[float, ...]]) -> np.ndarray:
    """The table's fields (:data:`FIELDS`) of one yaw node; ``hertz`` caches ellipses by
    their rounded curvatures across nodes."""
    y = geometry.y
    n = len(y)
    data = np.zeros((len(FIELDS), 2, n))
    sign = np.array([[1.0], [-1.0]])
    data[RADIUS] = geometry.radius
    data[ANGLE] = geometry.contact_angle
    data[AXLE_ANGLE] = geometry.contact_angle - sign * geometry.roll
    data[ARM] = geometry.track_position - sign * y
    data[ROLL] = geometry.roll
    data[ROLL_SLOPE] = np.gradient(geometry.roll, y)
    # the functions of the angles the force kernel needs, tabulated (no trigonometry there)
    data[COS_ANGLE], data[SIN_ANGLE] = np.cos(data[ANGLE]), np.sin(data[ANGLE])
    data[SIN_AXLE] = math.cos(geometry.yaw) * np.sin(data[AXLE_ANGLE])
    data[LEAD_RATE] = geometry.lead_rate
    data[SECANT_CBRT] = np.cos(data[ANGLE]) ** (-1.0 / 3.0)
    rolling = 0.5 * geometry.wheel_curvature_rolling
    lateral = np.maximum(0.5 * (geometry.wheel_curvature_lateral + geometry.rail_curvature_lateral), _MIN_CURVATURE)
    cache = hertz
    for side in (0, 1):
        for k in range(n):
            key = (round(float(rolling[side, k]), 9), round(float(lateral[side, k]), 6))
            if key not in cache:
                # hertz_contact takes radii: A = 1 / (2 R_rolling), B = 1 / (2 R_lateral)
                ellipse = hertz_contact(1.0, 0.5 / key[0], 0.5 / key[1], youngs_modulus, poisson)
                cache[key] = (ellipse.a, ellipse.b, *kalker_coefficients(ellipse.a, ellipse.b, poisson)[:3])
            data[SEMI_A:C23 + 1, side, k] = cache[key]
    return data


def contact_tables(
    wheel: Profile,
    rail: Profile,
    setup: ContactSetup | None = None,
    *,
    youngs_modulus: float = 206e9,
    poisson: float = 0.3,
    reach: float = 15e-3,
    step: float = 0.01e-3,
    yaw_nodes: int = 1,
) -> ContactTables:
    """Contact tables of a wheel/rail pair for ``|y| <= reach`` every ``step``.

    The geometry is :func:`express.rail.contact_geometry.contact_geometry`; the Hertz
    ellipse (:func:`express.rail.contact.hertz_contact`) uses the relative curvatures
    ``A = cos(theta) / (2 r)`` and ``B = (k_wheel + k_rail) / 2`` of each contact
    (``B`` at least 0.02 1/m).  Tables are cached by their arguments (profiles by
    identity): building one takes 0.3-0.6 s for +-15 mm every 0.01 mm, and that again
    for every further yaw node.

    ``yaw_nodes`` > 1 adds the yawed wheelset's geometry at ``|psi| = 5 k`` mrad
    (:data:`YAW_NODES` = 7 reaches 30 mrad), interpolated in ``psi^2``; with one node
    the yaw enters through the contact's lead to first order (``lead_rate`` of the
    unyawed geometry), the default of the simulation: the flange's two-point zone moves
    with yaw, and interpolating it between nodes made the march through a 250 m curve
    hunt around a yaw node instead of settling (``docs/contact.md``).

    Raises
    ------
    ArgumentError
        When the wheels do not reach the rails over the range (reduce ``reach``).
    """
    setup = setup or ContactSetup()
    if not 1 <= yaw_nodes <= 12:
        raise ArgumentError(f"yaw_nodes must be 1..12, not {yaw_nodes!r}")
    key = (_profile_key(wheel), _profile_key(rail), setup, float(youngs_modulus), float(poisson), float(reach), float(step),
           int(yaw_nodes))
    if key not in _CACHE:
        if len(_CACHE) >= _CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = _tables(wheel, rail, setup, float(youngs_modulus), float(poisson), float(reach), float(step),
                              int(yaw_nodes))
    return _CACHE[key]


# ------------------------------------------------------------------ elastic rails


@dataclass(frozen=True, eq=False)
class RailMap:
    """Where each contact sits, ``u``, for a wheelset displacement ``y`` relative to the
    undeformed track: ``contact[side, k]`` at ``y = start + step k`` [m]; beyond the
    last node the contact stays at the end value (the wheel would climb the rail)."""

    start: float
    step: float
    contact: np.ndarray
    yawed: np.ndarray | None = None

    @property
    def nodes(self) -> np.ndarray:
        """``u`` at every yaw node of the tables, shape (yaw nodes, 2, nodes) [m]
        (``contact`` is the first)."""
        return self.contact[None] if self.yawed is None else self.yawed

    def at(self, y: float) -> np.ndarray:
        """``u`` of both sides at ``y`` (clamped to the map), shape (2,)."""
        grid = self.start + self.step * np.arange(self.contact.shape[1])
        return np.array([np.interp(y, grid, row) for row in self.contact])


def rail_deflection_map(tables: ContactTables, wheel_load: float, rail_stiffness: float) -> RailMap:
    """The contact position ``u`` of each side against the wheelset displacement ``y``
    with rails of lateral stiffness ``rail_stiffness`` [N/m] each, wheel load ``Q``.

    Each rail moves outward by ``Q (tan delta(u) - tan delta(0)) / kR`` (the change of
    the lateral component of a normal force whose vertical component is ``Q``), so
    ``y = u + sign (Q / kR)(tan delta(u) - tan delta(0))`` (sign +1 left, -1 right).
    The map follows the branch through the centre; where ``y(u)`` turns back (the
    contact angle falls as the flange climbs) it stops.  ``rail_stiffness = inf``
    gives ``u = y``.  One map per yaw node of the tables, on one grid.
    """
    grid = tables.y
    centre = int(np.argmin(np.abs(grid)))
    compliance = wheel_load / rail_stiffness if math.isfinite(rail_stiffness) and rail_stiffness > 0 else 0.0
    rows = []
    for node in tables.nodes:
        tangent = np.tan(node[ANGLE])
        rows.append([grid + sign * compliance * (tangent[side] - tangent[side, centre])
                     for side, sign in ((0, 1.0), (1, -1.0))])
    step = tables.step
    # nodes on multiples of the step, so that y = 0 is one (u(y) has a kink there)
    first = math.ceil(max(float(position[: centre + 1].min()) for node in rows for position in node) / step - 1e-9)
    last = math.floor(min(float(position[centre:].max()) for node in rows for position in node) / step + 1e-9)
    start = first * step
    y = step * np.arange(first, last + 1)
    yawed = np.array([[_invert(position, grid, centre, y) for position in node] for node in rows])
    return RailMap(float(start), step, yawed[0], yawed)


def _invert(position: np.ndarray, grid: np.ndarray, centre: int, y: np.ndarray) -> np.ndarray:
    """``u(y)`` on the monotone branch of ``y = position(u)`` through the centre."""
    up = np.maximum.accumulate(position[centre:])
    keep = np.concatenate([[True], np.diff(up) > 0])
    down = np.minimum.accumulate(position[: centre + 1][::-1])
    keep_down = np.concatenate([[True], np.diff(down) < 0])
    ys = np.concatenate([down[keep_down][::-1][:-1], up[keep]])
    us = np.concatenate([grid[: centre + 1][::-1][keep_down][::-1][:-1], grid[centre:][keep]])
    return np.interp(y, ys, us)


# ------------------------------------------------------------------ linearisation


def describing_gain(function, amplitude: float, points: int = 512) -> float:
    """First-harmonic gain of an odd function at ``amplitude``:
    ``(2 / (pi A)) integral_0^pi f(A sin t) sin t dt`` (midpoint rule); the slope at 0
    for a smooth function and a small amplitude."""
    t = (np.arange(points) + 0.5) * math.pi / points
    return float(2.0 / (math.pi * amplitude) * np.sum(function(amplitude * np.sin(t)) * np.sin(t)) * math.pi / points)


@dataclass(frozen=True)
class LinearContact:
    """The contact of a centred wheelset and its quasi-linear changes at an amplitude.

    Attributes
    ----------
    delta0 : float
        Contact angle at the centred position [rad] (mean of both sides).
    half_distance : float
        Lateral distance of the contacts from the wheelset centre, centred [m] (l0).
    radius : float
        Rolling radius at the centred position [m].
    epsilon : float
        Wickens' contact-angle parameter: ``delta_L - delta_R = 2 epsilon y / l0``.
    sigma : float
        Wickens' roll parameter: ``roll = sigma y / l0``.
    lambda_ : float
        ``delta_r = 2 lambda y`` (first-harmonic gain; the EN 15302 conicity is separate).
    amplitude : float
        The amplitude of the gains [m].
    """

    delta0: float
    half_distance: float
    radius: float
    epsilon: float
    sigma: float
    lambda_: float
    amplitude: float


def linear_contact_parameters(tables: ContactTables, amplitude: float) -> LinearContact:
    """Wickens' linear contact parameters as first-harmonic gains at ``amplitude`` [m]
    (:func:`describing_gain`): for smooth profiles and a small amplitude, the slopes at
    the centred position."""
    grid = tables.y
    if not 0 < amplitude <= min(-grid[0], grid[-1]):
        raise ArgumentError(f"amplitude {amplitude * 1e3:g} mm outside the table (+-{grid[-1] * 1e3:g} mm)")
    data = tables.data
    centre = [float(np.interp(0.0, grid, data[f, side])) for f, side in ((ANGLE, 0), (ANGLE, 1))]
    l0 = 0.5 * sum(float(np.interp(0.0, grid, data[ARM, side])) for side in (0, 1))

    def odd(values):
        return lambda y: 0.5 * (np.interp(y, grid, values) - np.interp(-y, grid, values))

    angle_gain = describing_gain(odd(data[ANGLE, 0] - data[ANGLE, 1]), amplitude)
    roll_gain = describing_gain(odd(data[ROLL, 0]), amplitude)
    radius_gain = describing_gain(odd(data[RADIUS, 0] - data[RADIUS, 1]), amplitude)
    return LinearContact(
        delta0=0.5 * (centre[0] + centre[1]),
        half_distance=l0,
        radius=0.5 * sum(float(np.interp(0.0, grid, data[RADIUS, side])) for side in (0, 1)),
        epsilon=0.5 * l0 * angle_gain,
        sigma=l0 * roll_gain,
        lambda_=0.5 * radius_gain,
        amplitude=float(amplitude),
    )
