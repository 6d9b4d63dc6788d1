"""A model's drawing geometry as data, kept in the derivation cache.

``express draw`` needs only numbers (:class:`~express.drawing.geometry.ModelGeometry`),
but making them reads the model file into its SymPy records: 6 s of a 100-car train's
drawing.  :func:`cached_geometry` stores the geometry of a model file read without
overrides (:func:`express.numeric.products.cached_product`, ``docs/cache.md``), so a
second drawing of unchanged files reads no model; :func:`geometry_data` and
:func:`geometry_from_data` turn it into JSON-able data and back, checking every field.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from express.drawing.geometry import DrawnBody, DrawnElement, DrawnMode, ModelGeometry, Vector
from express.numeric.program import ProgramError, checked_list

__all__ = ["cached_geometry", "geometry_data", "geometry_from_data"]


def cached_geometry(path: str | Path, make: Callable[[], ModelGeometry]) -> ModelGeometry:
    """The drawing geometry of the model file ``path`` (no overrides): from the cache, or
    ``make()`` (which reads the model) stored."""
    from express.numeric.products import cached_product

    return cached_product(path, "drawing geometry", {}, make, lambda g: (f"{g.name} (drawing)", geometry_data(g)),
                          geometry_from_data)


def geometry_data(geometry: ModelGeometry) -> dict[str, Any]:
    """``geometry`` as JSON-able data (floats kept exactly: JSON writes their ``repr``);
    :class:`ProgramError` for a geometry with a number that is not finite (not stored)."""
    numbers = [x for b in geometry.bodies for v in (b.centre, b.low, b.high, b.outline or (), b.turn) for x in v]
    numbers += [x for b in geometry.bodies for x in (b.radius, b.gauge_half) if x is not None]
    numbers += [x for position in geometry.points.values() for x in position]
    numbers += [x for m in geometry.modes for x in (m.frequency_hz, *(v for _, v in m.points), *(x for c in m.curve for x in c))]
    if not all(math.isfinite(x) for x in numbers):
        raise ProgramError("a number that is not finite")
    return {
        "name": geometry.name,
        "bodies": [[b.id, b.role, list(b.centre), list(b.low), list(b.high),
                    None if b.outline is None else list(b.outline), b.radius, b.gauge_half, list(b.turn)]
                   for b in geometry.bodies],
        "points": [[name, *position] for name, position in geometry.points.items()],
        "hosts": [[point, host] for point, host in geometry.hosts.items()],
        "elements": [[e.id, e.s_point, e.t_point, e.axis, e.kind, e.description] for e in geometry.elements],
        "pins": [list(pin) for pin in geometry.pins],
        "ground_points": list(geometry.ground_points),
        "modes": [[m.coordinate, m.body, m.kind, [list(p) for p in m.points], [list(c) for c in m.curve], m.label,
                   m.frequency_hz] for m in geometry.modes],
    }


def geometry_from_data(data: Any) -> ModelGeometry:
    """The geometry of :func:`geometry_data`; :class:`ProgramError` for data that does not check."""
    if not isinstance(data, dict) or not isinstance(data.get("name"), str):
        raise ProgramError("bad drawing geometry")
    bodies = tuple(_body(item) for item in checked_list(data.get("bodies")))
    points = {_text(item[0]): _vector(item[1:]) for item in _rows(data.get("points"), 4)}
    hosts = {_text(item[0]): _text(item[1]) for item in _rows(data.get("hosts"), 2)}
    elements = tuple(_element(item) for item in _rows(data.get("elements"), 6))
    pins = tuple((_text(a), _text(b)) for a, b in _rows(data.get("pins"), 2))
    grounds = tuple(_text(name) for name in checked_list(data.get("ground_points")))
    modes = tuple(_mode(item) for item in _rows(data.get("modes", []), 7))
    if any(p not in points for m in modes for p, _ in m.points):
        raise ProgramError("a mode shape at a point that is not there")
    if not set(hosts) <= set(points) or any(p not in points for e in elements for p in (e.s_point, e.t_point)):
        raise ProgramError("an element or host of a point that is not there")
    return ModelGeometry(data["name"], bodies, points, hosts, elements, pins, grounds, modes)


def _rows(value: Any, width: int) -> list[list]:
    rows = checked_list(value)
    if not all(isinstance(row, list) and len(row) == width for row in rows):
        raise ProgramError("bad rows")
    return rows


def _text(value: Any) -> str:
    if not isinstance(value, str):
        raise ProgramError("expected a text")
    return value


def _number(value: Any) -> float:
    if type(value) not in (float, int) or not math.isfinite(value):
        raise ProgramError("expected a finite number")
    return float(value)


def _optional(value: Any) -> float | None:
    return None if value is None else _number(value)


def _vector(value: Any) -> Vector:
    if not (isinstance(value, list) and len(value) == 3):
        raise ProgramError("expected three numbers")
    return (_number(value[0]), _number(value[1]), _number(value[2]))


def _body(item: Any) -> DrawnBody:
    if not (isinstance(item, list) and len(item) == 9):
        raise ProgramError("bad body")
    identifier, role, centre, low, high, outline, radius, gauge_half, turn = item
    return DrawnBody(_text(identifier), _text(role), _vector(centre), _vector(low), _vector(high),
                     None if outline is None else _vector(outline), _optional(radius), _optional(gauge_half), _vector(turn))


def _mode(item: list) -> DrawnMode:
    coordinate, body, kind, points, curve, label, frequency = item
    if kind not in ("vertical", "lateral", "torsion"):
        raise ProgramError("bad mode kind")
    shapes = tuple((_text(p), _number(v)) for p, v in _rows(points, 2))
    samples = tuple((_number(x), _number(v)) for x, v in _rows(curve, 2))
    return DrawnMode(_text(coordinate), _text(body), kind, shapes, samples, _text(label), _number(frequency))


def _element(item: list) -> DrawnElement:
    identifier, s_point, t_point, axis, kind, description = item
    if type(axis) is not int or not 0 <= axis <= 5:
        raise ProgramError("bad axis")
    return DrawnElement(_text(identifier), _text(s_point), _text(t_point), axis, _text(kind), _text(description))
