"""Reading elements along a line (``direction = [dx, dy, dz]`` or ``"line"``), rotational
elements about a vector (``direction = { about = [dx, dy, dz] }``) and the lines'
given ``preload`` (:mod:`express.assembly.lines`); problems go to the reader (the
:class:`express.io.toml_items.TomlReader`, which calls these) with the element's line."""

from __future__ import annotations

from dataclasses import replace
from typing import Any

import sympy as sp

from express.model.records import Axis, Body, ConnectionPoint, Element

__all__ = ["check_line", "read_direction"]


def _first_axis(vector) -> int:
    """The first axis a vector has a part along (the drawings' axis of a line element)."""
    return next((axis for axis, c in enumerate(vector) if sp.sympify(c) != 0), 2)


def read_direction(reader: Any, path: tuple[str, ...], item: str, direction: Any):
    """``(vector, through_ends, axis)`` of a line element's ``direction``: the given
    vector [-] (exact expressions, not normalised) or, for ``"line"``, None until its
    ends are known (:func:`check_line`)."""
    where = path + ("direction",)
    if isinstance(direction, dict):  # { about = [dx, dy, dz] }: a rotational element about that axis
        reader.unknown_keys(direction, ("about",), where, item)
        if "about" not in direction:
            reader.problem(where, item, "a rotational element about a vector is direction = { about = [dx, dy, dz] }")
            return (sp.S.Zero, sp.S.Zero, sp.S.One), False, 2
        vector = reader.vector(direction["about"], where + ("about",), item, "direction about")
        if all(sp.sympify(c) == 0 for c in vector):
            reader.problem(where, item, "direction about the zero vector gives no axis")
        return vector, False, _first_axis(vector)
    if direction == "line":
        return (sp.S.Zero, sp.S.Zero, sp.S.Zero), True, 2
    vector = reader.vector(direction, where, item, "direction")
    if isinstance(direction, list) and len(direction) == 3 and all(sp.sympify(c) == 0 for c in vector):
        reader.problem(where, item, f"direction {direction!r} is the zero vector: it gives no line")
    return vector, False, _first_axis(vector)


def check_line(reader: Any, path: tuple[str, ...], item: str, spec: dict, element: Element,
               bodies: list[Body], points: list[ConnectionPoint]) -> Element:
    """A line element with its ``"line"`` resolved to ``p_S - p_T`` [m] (its ends' positions
    at rest: body position plus offset, a ground CP's offset its position); a rotational
    element with a preload, or a line through coincident points, is a problem."""
    if element.preload != 0 and (element.rotational or spec.get("direction") in ("rx", "ry", "rz")):
        reader.problem(path + ("preload",), item, "a preload [N] is a translational element's tension "
                       "(a rotational element has none)")
    if element.series and element.vector is not None:
        reader.problem(path + ("direction",), item, "a series (Maxwell) element acts along an axis (x, y or z): "
                       "its damper stroke is a coordinate in metres along it")
    if not element.through_ends:
        return element
    by_point = {p.id: p for p in points}
    by_body = {b.id: b for b in bodies}
    ends = [by_point.get(end) for end in (element.s_end, element.t_end)]
    if any(end is None for end in ends):
        return element  # an unknown CP: check_model reports it
    positions = []
    for point in ends:
        assert point is not None
        body = by_body.get(point.host)
        base = body.position if body is not None else (sp.S.Zero,) * 3
        positions.append([sp.expand(sp.sympify(b) + sp.sympify(o)) for b, o in zip(base, point.offset, strict=True)])
    vector = tuple(sp.expand(a - b) for a, b in zip(positions[0], positions[1], strict=True))
    if all(c == 0 for c in vector):
        reader.problem(path + ("direction",), item, f'direction = "line": its ends {element.s_end} and '
                       f"{element.t_end} are at the same point, which gives no line (give a vector)")
    return replace(element, vector=vector, direction=Axis(_first_axis(vector)))
