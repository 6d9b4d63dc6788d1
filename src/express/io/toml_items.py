"""The items of a TOML model (bodies, grounds, points, elements, pins) and the reader that
collects problems with their lines; shared by :mod:`.toml_model` and :mod:`.toml_substructures`."""

from __future__ import annotations

import re
from typing import Any

import sympy as sp

from express.base.diagnostics import Problem
from express.base.expressions import ExpressionError, parse_expression
from express.io.toml_lines import line_index
from express.model.records import (
    DOF_NAMES,
    Axis,
    Body,
    ConnectionPoint,
    Element,
    ElementKind,
    Ground,
    Motion,
    PinnedJoint,
)

__all__ = ["TomlReader", "check_id", "cut_text", "entries", "read_items", "show_value", "value_kind"]

BODY_KEYS = ("mass", "inertia", "dofs", "position", "label", "outline")
POINT_KEYS = ("body", "offset")
ELEMENT_KEYS = ("from", "to", "direction", "stiffness", "damping", "label", "series", "gap", "progressive", "friction",
                "air_spring", "characteristic", "preload", "bushing")
PIN_KEYS = ("virtual", "non_virtual")
DIRECTIONS = {"x": 0, "y": 1, "z": 2, "1": 0, "2": 1, "3": 2}
ROTATIONS = {"rx": 0, "ry": 1, "rz": 2}


class TomlReader:
    """A parsed TOML file's problems, collected with their lines (``source`` is the file
    name shown; ``line(*path)`` the line of the nearest key of ``path`` that has one)."""

    def __init__(self, text: str, source: str):
        self.source = source
        self.problems: list[Problem] = []
        self.lines = line_index(text)

    def line(self, *path: str) -> int | None:
        for end in range(len(path), 0, -1):
            found = self.lines.get(tuple(path[:end]))
            if found is not None:
                return found
        return None

    def problem(self, path: tuple[str, ...], item: str, message: str) -> None:
        self.problems.append(Problem(self.source, self.line(*path), item, message))

    def table(self, value: Any, path: tuple[str, ...], item: str) -> dict:
        if isinstance(value, dict):
            return value
        self.problem(path, item, f"expected a table, got {value_kind(value)}")
        return {}

    def unknown_keys(self, table: dict, allowed: tuple[str, ...], path: tuple[str, ...], item: str) -> None:
        for key in table:
            if key not in allowed:
                self.problem(
                    path + (key,), item, f'unknown key "{key}" (allowed: {", ".join(allowed)})'
                )

    def expression(self, value: Any, path: tuple[str, ...], item: str, what: str) -> sp.Expr:
        if isinstance(value, bool):
            self.problem(path, item, f"{what} must be a number or an expression, got a boolean")
            return sp.S.Zero
        if isinstance(value, int):
            return sp.Integer(value)
        if isinstance(value, float):
            if value != value or value in (float("inf"), float("-inf")):
                self.problem(path, item, f"{what} must be finite, got {value}")
                return sp.S.Zero
            return parse_expression(repr(value))
        if isinstance(value, str):
            try:
                return parse_expression(value)
            except ExpressionError as error:
                self.problem(path, item, f'{what} "{cut_text(value)}" is not a valid expression ({error})')
                return sp.S.Zero
        self.problem(path, item, f"{what} must be a number or an expression, got {value_kind(value)}")
        return sp.S.Zero

    def vector(self, value: Any, path: tuple[str, ...], item: str, what: str) -> tuple[sp.Expr, ...]:
        if not isinstance(value, list) or len(value) != 3:
            self.problem(path, item, f"{what} must be a list of 3 values [x, y, z], got {show_value(value)}")
            return (sp.S.Zero,) * 3
        return tuple(self.expression(v, path, item, f"{what}[{i}]") for i, v in enumerate(value))

    def name(self, value: Any, path: tuple[str, ...], item: str, what: str) -> str:
        if isinstance(value, str) and re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", value):
            return value
        self.problem(path, item, f"{what} must be an id (letters, digits, _), got {show_value(value)}")
        return "?"


ID_PATTERN = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def check_id(reader: TomlReader, identifier: str, path: tuple[str, ...], item: str) -> None:
    if not ID_PATTERN.match(identifier):
        reader.problem(path, item, "an id is ASCII: a letter A-Z or a-z, then letters, digits and _"
                       + ("" if identifier.isascii() else f" ({identifier!r} holds a character outside ASCII)"))


def entries(reader: TomlReader, table: Any, section: str, kind: str, allowed: tuple[str, ...], base: tuple[str, ...] = ()):
    """``(id, path, item, spec)`` of every entry of a named-items section, checked."""
    for identifier, raw in reader.table(table, base + (section,), section).items():
        path = base + (section, identifier)
        item = f"{kind} {identifier}"
        check_id(reader, identifier, path, item)
        spec = reader.table(raw, path, item)
        reader.unknown_keys(spec, allowed, path, item)
        yield identifier, path, item, spec


def value_kind(value: Any) -> str:
    return {dict: "a table", list: "a list", str: "a string", bool: "a boolean"}.get(
        type(value), type(value).__name__
    )


def cut_text(text: str, limit: int = 60) -> str:
    """A value quoted in a message, cut to ``limit`` characters."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def show_value(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."



def read_items(reader: TomlReader, data: dict, base: tuple[str, ...] = ()):
    """Bodies, grounds, points, elements and pins of a model (or of a substructure
    at key path ``base``), as lists of records."""
    bodies = []
    for body_id, path, item, spec in entries(reader, data.get("bodies", {}), "bodies", "body", BODY_KEYS, base):
        dofs = spec.get("dofs", [])
        if not isinstance(dofs, list) or any(d not in DOF_NAMES for d in dofs):
            reader.problem(path + ("dofs",), item, f"dofs must be a list drawn from {list(DOF_NAMES)}, got {show_value(dofs)}")
            dofs = []
        elif len(set(dofs)) != len(dofs):
            reader.problem(path + ("dofs",), item, "a DOF is listed twice")
        inertia = reader.vector(spec.get("inertia", [0, 0, 0]), path + ("inertia",), item, "inertia")
        bodies.append(
            Body(
                body_id,
                reader.expression(spec.get("mass", 0), path + ("mass",), item, "mass"),
                inertia,
                tuple(d for d in DOF_NAMES if d in dofs),
                reader.vector(spec.get("position", [0, 0, 0]), path + ("position",), item, "position"),
                str(spec.get("label", "")),
                reader.line(*path),
                outline=(reader.vector(spec["outline"], path + ("outline",), item, "outline")
                         if "outline" in spec else None),
            )
        )
    grounds_raw = data.get("grounds", {})
    if isinstance(grounds_raw, list):  # grounds = ["G1", "G2"]
        grounds_raw = {g: {} for g in grounds_raw if isinstance(g, str)}
    grounds = []
    for ground_id, path, _, spec in entries(reader, grounds_raw, "grounds", "ground", ("label",), base):
        grounds.append(Ground(ground_id, str(spec.get("label", "")), reader.line(*path)))
    points = []
    for point_id, path, item, spec in entries(reader, data.get("points", {}), "points", "CP", POINT_KEYS, base):
        points.append(
            ConnectionPoint(
                point_id,
                reader.name(spec.get("body"), path + ("body",), item, "body"),
                reader.vector(spec.get("offset", [0, 0, 0]), path + ("offset",), item, "offset"),
                reader.line(*path),
            )
        )
    elements = []
    for element_id, path, item, spec in entries(reader, data.get("elements", {}), "elements", "TSD", ELEMENT_KEYS, base):
        if "bushing" in spec:  # one element per axis of its frame (express.io.toml_bushings)
            from express.io.toml_bushings import read_bushing

            elements.extend(read_bushing(reader, element_id, path, item, spec))
            continue
        element = read_element(reader, element_id, path, item, spec)
        if element.vector is not None or element.preload != 0:
            from express.io.toml_line_elements import check_line

            element = check_line(reader, path, item, spec, element, bodies, points)
        if "air_spring" in spec:  # the bag, the reservoir's series branch, the shear elements
            from express.io.toml_air_springs import read_air_spring

            elements.extend(read_air_spring(reader, element_id, path, item, spec, element))
        else:
            elements.append(element)
    pins = []
    for pin_id, path, item, spec in entries(reader, data.get("pins", {}), "pins", "pin", PIN_KEYS, base):
        pins.append(
            PinnedJoint(
                pin_id,
                reader.name(spec.get("virtual"), path + ("virtual",), item, "virtual"),
                reader.name(spec.get("non_virtual"), path + ("non_virtual",), item, "non_virtual"),
                reader.line(*path),
            )
        )
    return bodies, grounds, points, elements, pins


def read_element(reader: TomlReader, element_id: str, path: tuple[str, ...], item: str, spec: dict) -> Element:
    """One element: translational or rotational, plain, series, clearance or friction."""
    direction = spec.get("direction")
    name = str(direction) if not isinstance(direction, (bool, float, list)) else ""
    rotational = name in ROTATIONS or isinstance(direction, dict)
    axis = ROTATIONS.get(name, DIRECTIONS.get(name))
    vector, through_ends = None, False
    if isinstance(direction, (list, dict)) or direction == "line":  # along a line, about a vector (express.assembly.lines)
        from express.io.toml_line_elements import read_direction

        vector, through_ends, axis = read_direction(reader, path, item, direction)
    if axis is None:
        reader.problem(
            path + ("direction",), item, f"direction must be x, y, z (or 1, 2, 3), rx, ry or rz, a vector [dx, dy, dz], \"line\" or {{ about = [dx, dy, dz] }}, "
            f"got {show_value(direction)}"
        )
        axis = 0
    series = spec.get("series", False)
    if not isinstance(series, bool):
        reader.problem(path + ("series",), item, f"series must be true or false, got {show_value(series)}")
        series = False
    kind = ElementKind.SERIES if series else ElementKind.PARALLEL
    gap = sp.S.Zero
    if "gap" in spec:
        gap = reader.expression(spec["gap"], path + ("gap",), item, "gap")  # >= 0: check_model
        if series:
            reader.problem(path, item, "a clearance element cannot be a series element")
        kind = ElementKind.CLEARANCE
    friction, friction_of, plane = sp.S.Zero, "", ""
    if isinstance(spec.get("friction"), dict):  # { mu, of[, radius] } (mu r N) or { limit }; plane = partner
        friction, friction_of, plane = _friction_of(reader, path + ("friction",), item, spec["friction"], rotational)
    elif "friction" in spec:
        friction = reader.expression(spec["friction"], path + ("friction",), item, "friction")  # > 0: check_model
    if "friction" in spec:
        if kind is not ElementKind.PARALLEL:
            reader.problem(path, item, "a friction element cannot be a series or clearance element")
        if "stiffness" not in spec:
            reader.problem(path, item, "a friction element needs its pre-slip stiffness (stiffness = ...)")
        kind = ElementKind.FRICTION
    characteristic, checked = None, list[tuple]()
    if "characteristic" in spec:
        from express.io.toml_characteristics import read_characteristic

        characteristic, checked = read_characteristic(reader, path, item, spec, rotational)
        if kind is not ElementKind.PARALLEL:
            reader.problem(path, item, "a characteristic element cannot be a series, clearance or friction element")
        kind = ElementKind.CHARACTERISTIC
    stiffness = reader.expression(spec.get("stiffness", 0), path + ("stiffness",), item, "stiffness")
    damping = reader.expression(spec.get("damping", 0), path + ("damping",), item, "damping")
    if characteristic is not None:  # its tangent at the static state, beside the other (linear) part
        linear = "damping" if characteristic.velocity else "stiffness"
        if linear in spec:
            reader.problem(path + (linear,), item, f"the characteristic is the element's {linear}: give the other "
                           f"part only ({'stiffness' if characteristic.velocity else 'damping'}, in parallel)")
        if characteristic.velocity:
            damping = characteristic.tangent
        else:
            stiffness = characteristic.tangent
    return Element(
        element_id,
        stiffness,
        damping,
        reader.name(spec.get("from"), path + ("from",), item, "from"),
        reader.name(spec.get("to"), path + ("to",), item, "to"),
        Axis(axis),
        str(spec.get("label", "")),
        reader.line(*path, "characteristic") if characteristic is not None else reader.line(*path),
        motion=Motion.ROTATION if rotational else Motion.TRANSLATION,
        kind=kind,
        gap=gap,
        progressive=reader.expression(spec.get("progressive", 0), path + ("progressive",), item, "progressive"),
        friction=friction,
        friction_of=friction_of,
        friction_plane=plane,
        checked=tuple(checked),
        characteristic=characteristic,
        vector=vector,
        through_ends=through_ends,
        preload=reader.expression(spec.get("preload", 0), path + ("preload",), item, "preload"),
    )



def _friction_of(reader: TomlReader, path: tuple[str, ...], item: str, table: dict, rotational: bool
                 ) -> tuple[sp.Expr, str, str]:
    """A friction limit as a table: ``{ mu = ..., of = "id" }`` proportional to another
    element's load (rotational: ``radius = r`` too, the torque ``mu r N``) or ``{ limit =
    ... }`` constant, either with ``plane = "id"``, the partner of a friction pair in a
    plane: the factor or limit, the followed element (or ``""``), the partner (or ``""``)."""
    allowed = ("mu", "of", "radius", "limit", "plane") if rotational else ("mu", "of", "limit", "plane")
    reader.unknown_keys(table, allowed, path, item)
    plane = reader.name(table["plane"], path + ("plane",), item, "friction plane") if "plane" in table else ""
    if "limit" in table:
        if any(key in table for key in ("mu", "of", "radius")):
            reader.problem(path, item, 'a friction limit is either "limit" or "mu" and "of", not both')
        return reader.expression(table["limit"], path + ("limit",), item, "friction limit"), "", plane
    for key in (("mu", "of", "radius") if rotational else ("mu", "of")):
        if key not in table:
            reader.problem(path, item, f'a friction limit proportional to a load needs "{key}"'
                           + (" (the friction torque is mu radius N)" if key == "radius" else ""))
    mu = reader.expression(table.get("mu", 0), path + ("mu",), item, "friction mu")
    factor = mu * reader.expression(table.get("radius", 1), path + ("radius",), item, "friction radius") \
        if rotational else mu
    return factor, reader.name(table.get("of", "?"), path + ("of",), item, "friction of"), plane
