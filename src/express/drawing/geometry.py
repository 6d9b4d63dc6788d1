"""Numerical geometry of a model for drawings: where bodies, points and elements are.

A body's centre is its ``position`` (station x, lateral y, height z, in the vehicle
frame); a connection point sits at its ``offset`` from the centre of its host; a point on
a ground is at its offset from the vehicle frame's origin.  Everything here is numbers
in metres: the caller turns parameter expressions into numbers (``value``).

:func:`displaced_geometry` moves the same geometry by a set of DOF values with the
small-motion kinematics of ``docs/conventions.md`` (``u = t + theta x r``), which is
what a mode-shape drawing needs; a flexible body's modes (:class:`DrawnMode`) move its
points by their shape values and bend its outline (:attr:`DrawnBody.bend`).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np

from express.base.diagnostics import ModelError, Problem

if TYPE_CHECKING:  # the records hold SymPy expressions: a drawing read from the cache needs neither
    from express.model.records import Model

__all__ = [
    "DrawnBody",
    "DrawnElement",
    "DrawnMode",
    "ModelGeometry",
    "displaced_geometry",
    "drawn_modes",
    "estimated_outline",
    "modal_bends",
    "modal_offsets",
    "model_geometry",
    "point_displacement",
    "points_by_host",
]

Vector = tuple[float, float, float]


@dataclass(frozen=True)
class DrawnBody:
    """A body to draw: its centre and the box spanned by its centre and points [m].

    ``outline`` (length, width, height) [m] is the box the body is drawn as, centred on
    its centre (:func:`estimated_outline`), None to draw the box of its points; a
    wheelset has its rolling ``radius`` and half distance ``gauge_half`` between the
    contact points [m] (its wheels are drawn as circles); ``turn`` its small rotation
    (rx, ry, rz) [rad] in a displaced drawing; ``bend`` a flexible body's deflection by its
    modes in a displaced drawing, ``(lx, u_y, u_z)`` [m] samples along it (``lx`` from its
    centre), its outline drawn bent through them.
    """

    id: str
    role: str
    centre: Vector
    low: Vector
    high: Vector
    outline: Vector | None = None
    radius: float | None = None
    gauge_half: float | None = None
    turn: Vector = (0.0, 0.0, 0.0)
    bend: tuple[Vector, ...] = ()


@dataclass(frozen=True)
class DrawnElement:
    """An element between the points ``s_point`` and ``t_point``; ``axis`` 0-2 for x, y,
    z (3-5 rotations); ``kind`` is ``"spring"``, ``"damper"``, ``"spring-damper"``
    (parallel), ``"series"`` or ``"stop"`` (a clearance element: a bump stop); ``description`` its label and values, for a tooltip."""

    id: str
    s_point: str
    t_point: str
    axis: int
    kind: str
    description: str = ""


@dataclass(frozen=True)
class DrawnMode:
    """A flexible body's mass-normalised mode (:mod:`express.model.modal_body`) for drawing.

    ``coordinate`` is the modal DOF (``CB.vb1``), ``kind`` ``"vertical"``, ``"lateral"`` or
    ``"torsion"``; ``points`` the shape value at each drawn point of the body and ``curve``
    ``(lx, value)`` samples along it [m; 1/sqrt(kg), or rad/(sqrt(kg) m) for torsion]: the
    beam's closed form, else the values at its points joined by straight lines;
    ``label`` (``"car body first vertical bending"``) and ``frequency_hz`` (free-free).
    """

    coordinate: str
    body: str
    kind: str
    points: tuple[tuple[str, float], ...]
    curve: tuple[tuple[float, float], ...]
    label: str = ""
    frequency_hz: float = 0.0


@dataclass(frozen=True)
class ModelGeometry:
    """Bodies, points, elements and pins of a model in metres.

    ``points`` maps a point id to its position; ``hosts`` a point id to its body or
    ground; ``pins`` lists each pinned joint with its virtual point.
    """

    name: str
    bodies: tuple[DrawnBody, ...]
    points: dict[str, Vector]
    hosts: dict[str, str]
    elements: tuple[DrawnElement, ...]
    pins: tuple[tuple[str, str], ...]
    ground_points: tuple[str, ...] = ()
    modes: tuple[DrawnMode, ...] = ()

    def ends(self, element: DrawnElement) -> tuple[Vector, Vector]:
        """Positions of an element's two points [m]."""
        return self.points[element.s_point], self.points[element.t_point]

    def span(self, axes: tuple[int, ...] = (0, 1, 2)) -> float:
        """The largest extent of the drawing along ``axes`` [m] (at least 1 mm)."""
        coordinates = np.array(list(self.points.values()) + [b.centre for b in self.bodies] or [(0.0, 0.0, 0.0)])
        return float(max(np.ptp(coordinates[:, list(axes)], axis=0).max(), 1e-3))


def estimated_outline(mass: float, inertia: tuple[float, float, float]) -> Vector | None:
    """The uniform box of the body's mass and principal inertias [m], or None.

    A box of length ``l``, width ``w`` and height ``h`` has ``Ix = m (w^2 + h^2) / 12``
    and the like, so ``l^2 = 6 (Iy + Iz - Ix) / m``, ``w^2 = 6 (Ix + Iz - Iy) / m``,
    ``h^2 = 6 (Ix + Iy - Iz) / m``. None when the mass or an inertia is not positive or
    a side comes out imaginary (the inertias of no box).

    Examples
    --------
    The Manchester coach's car body (32 t; 56.8, 1970, 1970 t m^2): 27 m long, 3.3 m
    wide and high.

    >>> [round(side, 2) for side in estimated_outline(32000.0, (56800.0, 1.97e6, 1.97e6))]
    [26.98, 3.26, 3.26]
    """
    ix, iy, iz = inertia
    if not (mass > 0 and ix > 0 and iy > 0 and iz > 0):
        return None
    squares = (6.0 * (iy + iz - ix) / mass, 6.0 * (ix + iz - iy) / mass, 6.0 * (ix + iy - iz) / mass)
    if min(squares) <= 0:
        return None
    return tuple(float(np.sqrt(x)) for x in squares)  # type: ignore[return-value]


def _body_shape(body, value, wheelset) -> tuple[Vector | None, float | None, float | None]:
    """``(outline, radius, gauge_half)`` of a body: a wheelset's wheels, else the
    estimated outline (None where the values are missing)."""
    try:
        if wheelset is not None:
            return None, float(value(wheelset.r0)), float(value(wheelset.b))
        if getattr(body, "outline", None) is not None:
            length, width, height = (float(value(side)) for side in body.outline)
            return (length, width, height), None, None
        ix, iy, iz = (float(value(i)) for i in body.inertia)
        return estimated_outline(float(value(body.mass)), (ix, iy, iz)), None, None
    except (KeyError, ValueError, TypeError, ModelError):
        return None, None, None


def _describe(element, value) -> str:
    """``"T1_yawL (yaw damper ...): stiffness kyaw = 1e+07, damping cyaw = 3e+05 (SI)"``."""
    parts = []
    for what in ("stiffness", "damping"):
        expression = getattr(element, what)
        if expression == 0:
            continue
        try:
            number = f" = {float(value(expression)):.4g}"
        except (KeyError, ValueError, TypeError, ModelError):
            number = ""
        shown = str(expression)
        parts.append(f"{what} {shown}{number if number.strip('= ') != shown else ''}")
    label = f" ({element.label})" if getattr(element, "label", "") else ""
    series = ", in series" if getattr(element, "series", False) else ""
    return f"{element.id}{label}: {', '.join(parts) or 'no stiffness nor damping'}{series} (SI)"


def _kind(stiffness_zero: bool, damping_zero: bool, series: bool) -> str:
    if series:
        return "series"
    if damping_zero:
        return "spring"
    return "damper" if stiffness_zero else "spring-damper"


def model_geometry(model: Model, value: Callable[[object], float], roles: Mapping[str, str] | None = None) -> ModelGeometry:
    """The numerical geometry of ``model``.

    Parameters
    ----------
    model : Model
    value : callable
        Turns a parameter expression into a float [SI]; raises ``ModelError`` (or
        ``KeyError``/``ValueError``) for an expression it cannot evaluate.
    roles : mapping of str to str, optional
        Body id -> role (``express.model.topology``), drawn in the body's style.

    Raises
    ------
    ModelError
        Naming every body or point whose position cannot be evaluated.
    """
    problems: list[Problem] = []

    def vector(expressions, item: str, line) -> Vector:
        try:
            x, y, z = (float(value(e)) for e in expressions)
        except KeyError as error:
            problems.append(Problem(model.source, line, item,
                                    f"cannot be drawn: no value for {error.args[0]} (give it with --set)"))
            return (0.0, 0.0, 0.0)
        except (ModelError, ValueError, TypeError) as error:
            problems.append(Problem(model.source, line, item, f"cannot be drawn: its position has no value ({error})"))
            return (0.0, 0.0, 0.0)
        if not all(np.isfinite((x, y, z))):
            problems.append(Problem(model.source, line, item, "cannot be drawn: its position is not finite"))
        return (x, y, z)

    centres = {body.id: vector(body.position, f"body {body.id}", body.line) for body in model.bodies}
    centres.update({ground.id: (0.0, 0.0, 0.0) for ground in model.grounds})
    points, hosts = {}, {}
    for point in model.points:
        offset = vector(point.offset, f"CP {point.id}", point.line)
        base = centres.get(point.host, (0.0, 0.0, 0.0))
        points[point.id] = (base[0] + offset[0], base[1] + offset[1], base[2] + offset[2])
        hosts[point.id] = point.host
    if problems:
        raise ModelError(problems)
    bodies = []
    wheelsets = {w.body: w for w in model.rail.wheelsets} if model.rail is not None else {}
    hosted = points_by_host(hosts)
    for body in model.bodies:
        own = np.array([centres[body.id]] + [points[p] for p in hosted.get(body.id, ())])
        outline, radius, gauge_half = _body_shape(body, value, wheelsets.get(body.id))
        bodies.append(DrawnBody(body.id, (roles or {}).get(body.id, "body"), centres[body.id],
                                tuple(own.min(axis=0)), tuple(own.max(axis=0)), outline, radius, gauge_half))
    from express.model.records import ElementKind

    elements = tuple(
        DrawnElement(
            element.id, element.s_end, element.t_end, int(element.direction) + (3 if element.rotational else 0),
            "stop" if element.kind == ElementKind.CLEARANCE
            else _kind(element.stiffness == 0, element.damping == 0, bool(element.series)),
            _describe(element, value),
        )
        for element in model.elements
        if element.s_end in points and element.t_end in points
    )
    pins = tuple((pin.id, pin.virtual) for pin in model.pins if pin.virtual in points)
    grounds = {ground.id for ground in model.grounds}
    _place_unplaced_ground_points(model, points, grounds)
    modes: tuple[DrawnMode, ...] = ()
    if getattr(model, "flexible", ()):
        modes = drawn_modes(model, value, centres, points)
    return ModelGeometry(model.name, tuple(bodies), points, hosts, elements, pins,
                         tuple(p for p, host in hosts.items() if host in grounds), modes)


def points_by_host(hosts: Mapping[str, str]) -> dict[str, list[str]]:
    """Host (body or ground) -> its points, each list in the order of ``hosts`` (point ->
    host): one pass instead of a search of every point for every body."""
    grouped: dict[str, list[str]] = {}
    for point, host in hosts.items():
        grouped.setdefault(host, []).append(point)
    return grouped


def _place_unplaced_ground_points(model: Model, points: dict[str, Vector], grounds: set[str]) -> None:
    """A point on a ground at the ground's origin (the classic format gives grounds no
    position) is drawn at its element's other end, moved along the element's direction by
    a quarter of the drawing's size, so that the element shows as in a textbook figure."""
    host = {point.id: point.host for point in model.points}
    zero = {point.id for point in model.points if point.host in grounds and all(o == 0 for o in point.offset)}
    coordinates = np.array(list(points.values()) or [(0.0, 0.0, 0.0)])
    length = 0.25 * max(float(np.ptp(coordinates, axis=0).max()), 1e-3)
    for element in model.elements:
        for ground_end, other in ((element.t_end, element.s_end), (element.s_end, element.t_end)):
            if ground_end in zero and other in points and host.get(other) not in grounds and element.direction < 3:
                position = list(points[other])
                position[element.direction] += length if ground_end == element.t_end else -length
                points[ground_end] = (position[0], position[1], position[2])
                zero.discard(ground_end)


def point_displacement(offset: Vector, dofs: Mapping[str, float], body: str) -> np.ndarray:
    """``u = t + theta x r`` of a point at ``offset`` from ``body``'s centre [m], from the
    body's DOF values (``<body>.<dof>`` -> m or rad; missing DOFs are zero)."""
    t = np.array([dofs.get(f"{body}.{axis}", 0.0) for axis in ("x", "y", "z")])
    theta = np.array([dofs.get(f"{body}.{axis}", 0.0) for axis in ("rx", "ry", "rz")])
    return t + np.cross(theta, np.asarray(offset, dtype=float))


def displaced_geometry(geometry: ModelGeometry, dofs: Mapping[str, float]) -> ModelGeometry:
    """``geometry`` with every body moved by its DOF values (small motion), a flexible
    body's points also by ``sum_i phi_i(P) q_i`` and its outline bent by its modes."""
    centres = {body.id: np.asarray(body.centre) for body in geometry.bodies}
    modal = modal_offsets(geometry, dofs) if geometry.modes else {}
    points = {}
    for point, position in geometry.points.items():
        host = geometry.hosts[point]
        if host in centres:
            offset = tuple(np.asarray(position) - centres[host])
            moved = np.asarray(position) + point_displacement(offset, dofs, host)
            points[point] = tuple(moved + modal[point]) if point in modal else tuple(moved)
        else:
            points[point] = position
    bodies = []
    hosted = points_by_host(geometry.hosts)
    bends = modal_bends(geometry, dofs) if geometry.modes else {}
    for body in geometry.bodies:
        moved = np.asarray(body.centre) + point_displacement((0.0, 0.0, 0.0), dofs, body.id)
        own = np.array([moved] + [points[p] for p in hosted.get(body.id, ())])
        turn: Vector = (float(dofs.get(f"{body.id}.rx", 0.0)), float(dofs.get(f"{body.id}.ry", 0.0)),
                        float(dofs.get(f"{body.id}.rz", 0.0)))
        bodies.append(replace(body, centre=tuple(moved), low=tuple(own.min(axis=0)), high=tuple(own.max(axis=0)),
                              turn=turn, bend=bends.get(body.id, ())))
    return replace(geometry, bodies=tuple(bodies), points=points)


# --- flexible bodies: their modes move their points and bend their outline -----------------
# (a vertical mode moves a point along z by phi q, a lateral one along y, a torsion mode turns
# the section: u_y = -psi lz q, u_z = psi ly q; express.model.modal_body.modal_motion)

#: Stations along a beam at which its modes are sampled for the bent outline.
SAMPLES = 41


def _beam_curves(model: Model, body: str, value: Callable[[object], float]) -> dict[str, list[tuple[float, float]]]:
    """``mode name -> [(lx, value)]`` of the beam of ``body`` at :data:`SAMPLES` stations
    (empty when the body's modes do not come from a beam)."""
    from express.model.beam_modes import BEAM_DERIVATION, STATION, free_free_beam

    node = next((d for d in model.derivations if d.kind == BEAM_DERIVATION and d.item == f"flexible {body} beam"), None)
    if node is None:
        return {}
    arguments: dict[str, Any] = {name: float(value(expression)) for name, expression, _ in node.inputs
                                 if not name.startswith(STATION)}
    length = arguments["length"]
    stations = np.linspace(-length / 2, length / 2, SAMPLES)
    arguments.update(dict(node.settings))
    arguments.update({f"{STATION}s{k}": float(x) for k, x in enumerate(stations)})
    results = free_free_beam(**arguments)
    curves: dict[str, list[tuple[float, float]]] = {}
    for key, number in results.items():
        name, _, where = key.rpartition("_")
        if where.startswith("s") and where[1:].isdigit():
            curves.setdefault(name, []).append((float(stations[int(where[1:])]), float(number)))
    return curves


def drawn_modes(model: Model, value: Callable[[object], float], centres: Mapping[str, Vector],
                points: Mapping[str, Vector]) -> tuple[DrawnMode, ...]:
    """The modes of every flexible body of ``model`` at its values (``value`` turns an
    expression into a number; ``centres`` and ``points`` are the drawing's positions [m])."""
    from express.model.modal_body import mode_words

    stations = {p.id: float(points[p.id][0] - centres[p.host][0]) for p in model.points if p.id in points and p.host in centres}
    if model.rail is not None:
        stations.update({o.name: float(value(o.offset[0])) for o in model.rail.outputs})
    labels = {body.id: body.label or body.id for body in model.bodies}
    found = []
    for flexible in model.flexible:
        curves = _beam_curves(model, flexible.body, value)
        for mode in flexible.modes:
            shapes = {point: float(value(shape)) for point, shape in mode.shapes}
            drawn = tuple((p, v) for p, v in shapes.items() if p in points)
            curve = curves.get(mode.name) or sorted({(stations[p], v) for p, v in shapes.items() if p in stations})
            found.append(DrawnMode(f"{flexible.body}.{mode.name}", flexible.body, mode.kind.value, drawn, tuple(curve),
                                   f"{labels.get(flexible.body, flexible.body)} {mode_words(mode.name)}",
                                   float(value(mode.omega)) / (2 * math.pi)))
    return tuple(found)


def modal_offsets(geometry: ModelGeometry, dofs: Mapping[str, float]) -> dict[str, np.ndarray]:
    """The displacement [m] of every point of a flexible body by its modes' coordinates
    in ``dofs`` (``<body>.<mode>`` [sqrt(kg) m]; missing ones are zero)."""
    centres = {body.id: np.asarray(body.centre) for body in geometry.bodies}
    offsets: dict[str, np.ndarray] = {}
    for mode in geometry.modes:
        q = float(dofs.get(mode.coordinate, 0.0))
        if q == 0.0:
            continue
        for point, shape in mode.points:
            if geometry.hosts.get(point) != mode.body:
                continue
            u = np.zeros(3)
            if mode.kind == "torsion":
                _, ly, lz = np.asarray(geometry.points[point]) - centres[mode.body]
                u[1], u[2] = -shape * lz * q, shape * ly * q
            else:
                u[2 if mode.kind == "vertical" else 1] = shape * q
            offsets[point] = offsets.get(point, np.zeros(3)) + u
    return offsets


def modal_bends(geometry: ModelGeometry, dofs: Mapping[str, float]) -> dict[str, tuple[Vector, ...]]:
    """``body -> ((lx, u_y, u_z), ...)``: the bending of each flexible body's centre line
    by its modes (torsion does not move the centre line), at the stations of its curves."""
    by_body: dict[str, list[DrawnMode]] = {}
    for mode in geometry.modes:
        if mode.kind != "torsion" and mode.curve and float(dofs.get(mode.coordinate, 0.0)) != 0.0:
            by_body.setdefault(mode.body, []).append(mode)
    bends = {}
    for body, modes in by_body.items():
        stations = np.unique(np.concatenate([np.array([x for x, _ in m.curve]) for m in modes]))
        if stations.size < 2:
            continue
        u = np.zeros((stations.size, 2))
        for mode in modes:
            x, shape = np.array(mode.curve).T
            u[:, 0 if mode.kind == "lateral" else 1] += np.interp(stations, x, shape) * float(dofs[mode.coordinate])
        bends[body] = tuple((float(x), float(uy), float(uz)) for x, (uy, uz) in zip(stations, u, strict=True))
    return bends
