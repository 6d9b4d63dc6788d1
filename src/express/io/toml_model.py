"""Reader for the modern model format (TOML), the one people write by hand.

Named bodies, points and elements, comments, parameter values with units, body
positions and rail data.  ``docs/model-format.md`` documents every key; in short::

    [model]
    name = "lever"

    [parameters]
    b = "0.5 m"                       # number with unit, or a bare SI number,
    kLU = { value = 500, unit = "kN/m" }   # or a table, or an expression of
    lLL = "0.2*lLU"                   # other parameters

    [bodies.B2]
    mass = "m"
    inertia = [0, "J2", 0]            # Ix, Iy, Iz
    dofs = ["x", "ry"]
    position = [0, 0, 0]              # station, lateral, height (rail modules)

    [grounds.G1]

    [points.C1]
    body = "B2"                       # a body or a ground
    offset = [0, 0, "lLU"]

    [elements.T1]
    from = "C1"                       # S_End
    to = "C2"                         # T_End
    direction = "x"                   # x/y/z or 1/2/3
    stiffness = "kLU"
    damping = 0

    [pins.P1]
    virtual = "C5"
    non_virtual = "C6"

Every problem is collected and reported with the file, the line, the item and what
is wrong.  Values are parsed by :mod:`express.base.expressions`, never evaluated.
"""

from __future__ import annotations

import math
import re
import sys
from pathlib import Path
from typing import Any

import sympy as sp

from express.base.diagnostics import ModelError, Problem
from express.base.expressions import ExpressionError, is_valid_name, parse_expression
from express.base.limits import exceeded
from express.base.units import UnitError, parse_quantity, unit_factor
from express.io.classic import model_name_from_path, read_model_text
from express.io.toml_contact import conicity_value
from express.io.toml_lines import line_index as _line_index
from express.model.parameters import parameter_problems, resolve
from express.model.records import (
    DOF_NAMES,
    Body,
    ConnectionPoint,
    Derivation,
    Element,
    Ground,
    Model,
    OutputPoint,
    Parameter,
    PinnedJoint,
    RailSpec,
    Wheelset,
    check_model,
)

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on Python 3.10 only
    import tomli as tomllib

__all__ = ["WHEELSET_KEYS", "parse_toml_model", "read_toml_model"]

_TOP_KEYS = (
    "model", "parameters", "bodies", "grounds", "points", "elements", "pins", "rail", "gravity",
    "substructures", "instances",
)
_BODY_KEYS = ("mass", "inertia", "dofs", "position", "label")
_POINT_KEYS = ("body", "offset")
_ELEMENT_KEYS = ("from", "to", "direction", "stiffness", "damping", "label", "series", "gap", "progressive")
_PIN_KEYS = ("virtual", "non_virtual")
WHEELSET_KEYS = (
    "f1",
    "f2",
    "conicity",
    "r0",
    "b",
    "flange_clearance",
    "rail_stiffness",
    "friction",
    "wheel_load",
)
_RAIL_KEYS = ("speed", "cant_base", "gravity", "wheelsets", "wheel_rail", "wheelset", "outputs", "creep")
_CREEP_KEYS = (
    "from",
    "longitudinal",
    "lateral",
    "wheel_load",
    "wheel_radius",
    "rail_head_radius",
    "youngs_modulus",
    "poisson",
)
_DIRECTIONS = {"x": 0, "y": 1, "z": 2, "1": 0, "2": 1, "3": 2}
_ROTATIONS = {"rx": 0, "ry": 1, "rz": 2}


class _Reader:
    def __init__(self, text: str, source: str):
        self.source = source
        self.problems: list[Problem] = []
        self.lines = _line_index(text)

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
        self.problem(path, item, f"expected a table, got {_kind(value)}")
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
                self.problem(path, item, f'{what} "{_cut(value)}" is not a valid expression ({error})')
                return sp.S.Zero
        self.problem(path, item, f"{what} must be a number or an expression, got {_kind(value)}")
        return sp.S.Zero

    def vector(self, value: Any, path: tuple[str, ...], item: str, what: str) -> tuple[sp.Expr, ...]:
        if not isinstance(value, list) or len(value) != 3:
            self.problem(path, item, f"{what} must be a list of 3 values [x, y, z], got {_show(value)}")
            return (sp.S.Zero,) * 3
        return tuple(self.expression(v, path, item, f"{what}[{i}]") for i, v in enumerate(value))

    def name(self, value: Any, path: tuple[str, ...], item: str, what: str) -> str:
        if isinstance(value, str) and re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", value):
            return value
        self.problem(path, item, f"{what} must be an id (letters, digits, _), got {_show(value)}")
        return "?"


_ID = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def _check_id(reader: _Reader, identifier: str, path: tuple[str, ...], item: str) -> None:
    if not _ID.match(identifier):
        reader.problem(path, item, "an id must start with a letter and hold only letters, digits and _")


def _entries(reader: _Reader, table: Any, section: str, kind: str, allowed: tuple[str, ...], base: tuple[str, ...] = ()):
    """``(id, path, item, spec)`` of every entry of a named-items section, checked."""
    for identifier, raw in reader.table(table, base + (section,), section).items():
        path = base + (section, identifier)
        item = f"{kind} {identifier}"
        _check_id(reader, identifier, path, item)
        spec = reader.table(raw, path, item)
        reader.unknown_keys(spec, allowed, path, item)
        yield identifier, path, item, spec


def _kind(value: Any) -> str:
    return {dict: "a table", list: "a list", str: "a string", bool: "a boolean"}.get(
        type(value), type(value).__name__
    )


def _cut(text: str, limit: int = 60) -> str:
    """A value quoted in a message, cut to ``limit`` characters."""
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _show(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _parameters(reader: _Reader, table: dict) -> dict[str, Parameter]:
    """Parameters: numbers (SI), quantities with units, or expressions of others.

    Values are not computed here: :func:`express.model.parameters.resolve` evaluates the
    graph (in dependency order, refusing cycles) once the whole model is read.
    """
    parameters: dict[str, Parameter] = {}
    for name, raw in table.items():
        path = ("parameters", name)
        item = f"parameter {name}"
        line = reader.line(*path)
        if not is_valid_name(name):
            reader.problem(path, item, "a parameter name must start with a letter (letters, digits, _)")
            continue
        unit = ""
        if isinstance(raw, dict):
            extra = set(raw) - {"value", "unit", "source", "note"}
            if extra:
                reader.problem(path, item, f"unknown keys {sorted(extra)} (allowed: value, unit, source, note)")
            spec, raw = raw, raw.get("value")
            unit = spec.get("unit", "")
            if not isinstance(unit, str):
                reader.problem(path, item, f"unit must be a text such as \"kN/m\", got {_show(unit)}")
                continue
            if isinstance(raw, bool) or not isinstance(raw, (int, float)):
                reader.problem(path, item, f"value must be a number, got {_show(raw)}")
                continue
        if isinstance(raw, bool):
            reader.problem(path, item, "value must be a number, got a boolean")
        elif isinstance(raw, (int, float)):
            try:
                si = float(raw) * unit_factor(unit)
            except UnitError as error:
                reader.problem(path, item, str(error))
                continue
            if math.isfinite(si):
                parameters[name] = Parameter(name, si, unit.strip(), line)
            else:
                reader.problem(path, item, f"value must be finite, got {raw}")
        elif isinstance(raw, str):
            parameter = _text_parameter(reader, name, raw, line)
            if parameter is not None:
                parameters[name] = parameter
        else:
            reader.problem(path, item, f"value must be a number, got {_kind(raw)}")
    return parameters


def _text_parameter(reader: _Reader, name: str, raw: str, line: int | None) -> Parameter | None:
    """``"95 mm"`` (a quantity) or ``"0.2*lLU"`` (an expression: a derived parameter)."""
    path, item = ("parameters", name), f"parameter {name}"
    try:
        value, unit = parse_quantity(raw)
    except UnitError as unit_error:
        try:
            expression = parse_expression(raw)
        except ExpressionError as error:
            looks_like_quantity = re.match(r"\s*[-+]?[\d.]", raw) and not re.search(r"[*/^()+]", raw.strip()[1:])
            reason = unit_error if looks_like_quantity else error
            reader.problem(path, item, f'"{_cut(raw)}" is neither a number with a unit nor an expression ({reason})')
            return None
        if expression.is_number:
            return Parameter(name, float(expression), "", line)
        return Parameter(name, math.nan, "", line, expression=expression)
    if not math.isfinite(value):
        reader.problem(path, item, f'"{_cut(raw)}" is not a finite number')
        return None
    return Parameter(name, value, unit, line)


def _rail(reader: _Reader, table: dict, parameters: dict[str, Parameter]) -> tuple[RailSpec, tuple[Derivation, ...]]:
    reader.unknown_keys(table, _RAIL_KEYS, ("rail",), "rail")
    defaults = reader.table(table.get("wheel_rail", {}), ("rail", "wheel_rail"), "rail.wheel_rail")
    reader.unknown_keys(defaults, WHEELSET_KEYS, ("rail", "wheel_rail"), "rail.wheel_rail")
    overrides = reader.table(table.get("wheelset", {}), ("rail", "wheelset"), "rail.wheelset")
    names = table.get("wheelsets", [])
    if not isinstance(names, list):
        reader.problem(("rail", "wheelsets"), "rail.wheelsets", "must be a list of body ids")
        names = []
    wheelsets = []
    profile_nodes: dict[str, Derivation] = {}  # conicity from profiles (express.io.toml_contact)
    for index, name in enumerate(names):
        if name in names[:index]:
            reader.problem(("rail", "wheelsets"), f"wheelset {name}", "listed twice in rail.wheelsets")
            continue
        body = reader.name(name, ("rail", "wheelsets"), "rail.wheelsets", "wheelset")
        own = reader.table(overrides.get(body, {}), ("rail", "wheelset", body), f"wheelset {body}")
        reader.unknown_keys(own, WHEELSET_KEYS, ("rail", "wheelset", body), f"wheelset {body}")
        values = {}
        conicity = conicity_value(reader, own, defaults, body, profile_nodes)
        if conicity is not None:
            values["conicity"] = conicity
        for key in WHEELSET_KEYS:
            if key in values:
                continue
            raw = own.get(key, defaults.get(key))
            if raw is None:
                reader.problem(("rail", "wheel_rail"), f"wheelset {body}", f'missing "{key}" (give it in [rail.wheel_rail])')
                raw = 0
            values[key] = reader.expression(raw, ("rail", "wheelset", body, key), f"wheelset {body}", key)
        wheelsets.append(Wheelset(body, line=reader.line("rail", "wheelsets"), **values))
    for body in overrides:
        if body not in names:
            reader.problem(("rail", "wheelset", body), f"wheelset {body}", "not listed in rail.wheelsets")
    outputs = []
    output_table = reader.table(table.get("outputs", {}), ("rail", "outputs"), "rail.outputs")
    for name, raw in output_table.items():
        path = ("rail", "outputs", name)
        _check_id(reader, name, path, f"output {name}")  # names become CSV columns and TOML keys
        spec = reader.table(raw, path, f"output {name}")
        reader.unknown_keys(spec, ("body", "offset"), path, f"output {name}")
        outputs.append(
            OutputPoint(
                name,
                reader.name(spec.get("body"), path, f"output {name}", "body"),
                reader.vector(spec.get("offset", [0, 0, 0]), path, f"output {name}", "offset"),
                reader.line(*path),
            )
        )
    scalars = {}
    gravity = "g" if "g" in parameters else "9.81"  # standard gravity unless the model names g
    for key, default in (("speed", "v"), ("cant_base", "G"), ("gravity", gravity)):
        scalars[key] = reader.expression(table.get(key, default), ("rail", key), "rail", key)
    derivations = list(profile_nodes.values())
    if "creep" in table:
        derivations.append(_creep(reader, table["creep"]))
    rail = RailSpec(tuple(wheelsets), outputs=tuple(outputs), line=reader.line("rail"), **scalars)
    return rail, tuple(derivations)


#: ``[rail.creep]`` arguments: (key, dimension, default).
_CREEP_INPUTS = (
    ("wheel_load", "force", None),
    ("wheel_radius", "length", None),
    ("rail_head_radius", "length", None),
    ("youngs_modulus", "pressure", 206e9),
    ("poisson", "dimensionless", 0.3),
)


def _creep(reader: _Reader, raw: Any) -> Derivation:
    """``[rail.creep]``: f1, f2 from the contact, a derivation node of the graph."""
    path = ("rail", "creep")
    spec = reader.table(raw, path, "rail.creep")
    reader.unknown_keys(spec, _CREEP_KEYS, path, "rail.creep")
    if spec.get("from", "kalker") != "kalker":
        reader.problem(path + ("from",), "rail.creep", f'from must be "kalker", got {_show(spec.get("from"))}')
    inputs = []
    for key, dimension, default in _CREEP_INPUTS:
        if key not in spec and default is None:
            reader.problem(path, "rail.creep", f'missing "{key}"')
        value = reader.expression(spec.get(key, default if default is not None else 0), path + (key,), "rail.creep", key)
        inputs.append((key, value, dimension))
    outputs = (
        ("f11", reader.name(spec.get("longitudinal", "f1"), path, "rail.creep", "longitudinal"), "force"),
        ("f22", reader.name(spec.get("lateral", "f2"), path, "rail.creep", "lateral"), "force"),
    )
    return Derivation("kalker", "rail.creep", tuple(inputs), outputs, reader.line(*path))


def _add_outputs(reader: _Reader, parameters: dict[str, Parameter], derivations: tuple[Derivation, ...]) -> None:
    """Make the outputs of each derivation parameters set by it."""
    for derivation in derivations:
        for _, name, _ in derivation.outputs:
            if name in parameters:
                given = parameters[name]
                where = f"line {given.line}" if given.line is not None else "[parameters]"
                reader.problems.append(Problem(
                    reader.source, derivation.line, derivation.item,
                    f"computes {name}, which [parameters] also gives ({where}); remove one of them",
                ))
                continue
            parameters[name] = Parameter(name, math.nan, "", derivation.line, derived_by=derivation.item)


def _items(reader: _Reader, data: dict, base: tuple[str, ...] = ()):
    """Bodies, grounds, points, elements and pins of a model (or of a substructure
    at key path ``base``), as lists of records."""
    bodies = []
    for body_id, path, item, spec in _entries(reader, data.get("bodies", {}), "bodies", "body", _BODY_KEYS, base):
        dofs = spec.get("dofs", [])
        if not isinstance(dofs, list) or any(d not in DOF_NAMES for d in dofs):
            reader.problem(path + ("dofs",), item, f"dofs must be a list drawn from {list(DOF_NAMES)}, got {_show(dofs)}")
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
            )
        )
    grounds_raw = data.get("grounds", {})
    if isinstance(grounds_raw, list):  # grounds = ["G1", "G2"]
        grounds_raw = {g: {} for g in grounds_raw if isinstance(g, str)}
    grounds = []
    for ground_id, path, _, spec in _entries(reader, grounds_raw, "grounds", "ground", ("label",), base):
        grounds.append(Ground(ground_id, str(spec.get("label", "")), reader.line(*path)))
    points = []
    for point_id, path, item, spec in _entries(reader, data.get("points", {}), "points", "CP", _POINT_KEYS, base):
        points.append(
            ConnectionPoint(
                point_id,
                reader.name(spec.get("body"), path + ("body",), item, "body"),
                reader.vector(spec.get("offset", [0, 0, 0]), path + ("offset",), item, "offset"),
                reader.line(*path),
            )
        )
    elements = []
    for element_id, path, item, spec in _entries(reader, data.get("elements", {}), "elements", "TSD", _ELEMENT_KEYS, base):
        elements.append(_element(reader, element_id, path, item, spec))
    pins = []
    for pin_id, path, item, spec in _entries(reader, data.get("pins", {}), "pins", "pin", _PIN_KEYS, base):
        pins.append(
            PinnedJoint(
                pin_id,
                reader.name(spec.get("virtual"), path + ("virtual",), item, "virtual"),
                reader.name(spec.get("non_virtual"), path + ("non_virtual",), item, "non_virtual"),
                reader.line(*path),
            )
        )
    return bodies, grounds, points, elements, pins


def _element(reader: _Reader, element_id: str, path: tuple[str, ...], item: str, spec: dict) -> Element:
    """One element: translational or rotational, plain, series or clearance."""
    direction = spec.get("direction")
    name = str(direction) if not isinstance(direction, (bool, float)) else ""
    rotational = name in _ROTATIONS
    axis = _ROTATIONS.get(name, _DIRECTIONS.get(name))
    if axis is None:
        reader.problem(
            path + ("direction",), item, f"direction must be x, y, z (or 1, 2, 3), rx, ry or rz, got {_show(direction)}"
        )
        axis = 0
    series = spec.get("series", False)
    if not isinstance(series, bool):
        reader.problem(path + ("series",), item, f"series must be true or false, got {_show(series)}")
        series = False
    gap = None
    if "gap" in spec:
        gap = reader.expression(spec["gap"], path + ("gap",), item, "gap")  # >= 0: check_model
    return Element(
        element_id,
        reader.expression(spec.get("stiffness", 0), path + ("stiffness",), item, "stiffness"),
        reader.expression(spec.get("damping", 0), path + ("damping",), item, "damping"),
        reader.name(spec.get("from"), path + ("from",), item, "from"),
        reader.name(spec.get("to"), path + ("to",), item, "to"),
        axis,
        str(spec.get("label", "")),
        reader.line(*path),
        rotational=rotational,
        series=series,
        gap=gap,
        progressive=reader.expression(spec.get("progressive", 0), path + ("progressive",), item, "progressive"),
    )


def parse_toml_model(text: str, source: str = "<string>") -> Model:
    """Parse the text of a modern (TOML) model file.

    Parameters
    ----------
    text : str
        File contents.
    source : str
        File name used in messages and as the model's source.

    Returns
    -------
    Model

    Raises
    ------
    ModelError
        With every problem found, each naming the file, line and item.
    """
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as error:
        match = re.search(r"line (\d+)", str(error))
        line = int(match.group(1)) if match else None
        message = re.sub(r"\s*\(at line \d+, column \d+\)", "", str(error))
        raise ModelError([Problem(source, line, "TOML", f"not valid TOML: {message}")]) from None
    except RecursionError:
        raise ModelError([Problem(source, None, "TOML", "arrays or tables nested too deeply to read")]) from None
    size = _size_problems(data, source)
    if size:
        raise ModelError(size)
    reader = _Reader(text, source)
    reader.unknown_keys(data, _TOP_KEYS, (), "file")

    info = reader.table(data.get("model", {}), ("model",), "model")
    reader.unknown_keys(info, ("name", "title"), ("model",), "model")
    name = info.get("name", model_name_from_path(source))
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name):
        reader.problem(("model", "name"), "model", f"name must be an identifier, got {_show(name)}")
        name = model_name_from_path(source)
    title = info.get("title", "")

    parameters = _parameters(reader, reader.table(data.get("parameters", {}), ("parameters",), "parameters"))

    bodies, grounds, points, elements, pins = _items(reader, data)
    if "substructures" in data or "instances" in data:  # express.model.substructures
        from express.io.toml_substructures import read_substructures

        extra, found = read_substructures(reader, data)
        reader.problems.extend(found)
        bodies, grounds, points = bodies + list(extra.bodies), grounds + list(extra.grounds), points + list(extra.points)
        elements, pins = elements + list(extra.elements), pins + list(extra.pins)
    rail: RailSpec | None = None
    derivations: tuple[Derivation, ...] = ()
    if "rail" in data:
        rail, derivations = _rail(reader, reader.table(data["rail"], ("rail",), "rail"), parameters)
        _add_outputs(reader, parameters, derivations)
    model = Model(
        name=name,
        source=source,
        bodies=tuple(bodies),
        grounds=tuple(grounds),
        points=tuple(points),
        elements=tuple(elements),
        pins=tuple(pins),
        parameters=parameters,
        rail=rail,
        title=str(title),
        derivations=derivations,
        gravity=_gravity(reader, data),
    )
    # a name without value is allowed (symbolic generation); an analysis that needs
    # numbers names the items using it (express.model.parameters.undefined_name_problems)
    problems = reader.problems + check_model(model) + parameter_problems(model)
    if problems:
        raise ModelError(problems)
    return resolve(model)


def _size_problems(data: dict, source: str) -> list[Problem]:
    """The model's size against :mod:`express.base.limits`, counted on the parsed file
    before any item is read (instances count their substructure's items)."""

    def count(table: Any, key: str) -> int:
        entries = table.get(key) if isinstance(table, dict) else None
        return len(entries) if isinstance(entries, (dict, list)) else 0

    substructures = data.get("substructures")
    substructures = substructures if isinstance(substructures, dict) else {}
    instances = data.get("instances")
    used = [spec.get("substructure") for spec in instances.values() if isinstance(spec, dict)] if isinstance(instances, dict) else []
    problems = []
    for key, name, item in (("bodies", "bodies", "bodies"), ("elements", "elements", "elements"), ("points", "points", "points")):
        total = count(data, key) + sum(count(substructures.get(sub), key) for sub in used if isinstance(sub, str))
        message = exceeded(name, total)
        if message is not None:
            problems.append(Problem(source, None, item, message))
    message = exceeded("parameters", count(data, "parameters"))
    if message is not None:
        problems.append(Problem(source, None, "parameters", message))
    return problems


def _gravity(reader: _Reader, data: dict) -> sp.Expr | None:
    """``[gravity] acceleration = "g"``: every body's weight (None without the section)."""
    if "gravity" not in data:
        return None
    table = reader.table(data["gravity"], ("gravity",), "gravity")
    reader.unknown_keys(table, ("acceleration",), ("gravity",), "gravity")
    if "acceleration" not in table:
        reader.problem(("gravity",), "gravity", 'missing "acceleration" (e.g. acceleration = "g")')
        return None
    return reader.expression(table["acceleration"], ("gravity", "acceleration"), "gravity", "acceleration")


def read_toml_model(path: str | Path) -> Model:
    """Read a modern (TOML) model file (see :func:`parse_toml_model`)."""
    path = Path(path)
    return parse_toml_model(read_model_text(path), source=str(path))
