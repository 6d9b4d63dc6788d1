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
from pathlib import Path
from typing import Any

import sympy as sp

from express.base.diagnostics import ModelError, Problem
from express.base.expressions import ExpressionError, is_valid_name, parse_expression
from express.base.limits import exceeded
from express.base.units import UnitError, parse_quantity, unit_factor
from express.io.classic import model_name_from_path, read_model_text
from express.io.toml_contact import conicity_value
from express.io.toml_items import TomlReader, check_id, cut_text, read_items, show_value, value_kind
from express.io.toml_lines import parse_toml
from express.model.checks import check_model
from express.model.parameters import parameter_problems, resolve
from express.model.records import (
    Derivation,
    Model,
    OutputPoint,
    Parameter,
    RailSpec,
    Wheelset,
)

__all__ = ["WHEELSET_KEYS", "parse_toml_model", "read_toml_model"]

_TOP_KEYS = (
    "model", "parameters", "bodies", "grounds", "points", "elements", "pins", "rail", "gravity",
    "substructures", "instances", "flexible",
)
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


def _parameters(reader: TomlReader, table: dict) -> dict[str, Parameter]:
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
            reader.problem(path, item, "a parameter name is ASCII: a letter A-Z or a-z, then letters, digits and _"
                           + ("" if name.isascii() else f" ({name!r} holds a character outside ASCII; e.g. mu for μ)"))
            continue
        unit = ""
        if isinstance(raw, dict):
            extra = set(raw) - {"value", "unit", "source", "note"}
            if extra:
                reader.problem(path, item, f"unknown keys {sorted(extra)} (allowed: value, unit, source, note)")
            spec, raw = raw, raw.get("value")
            unit = spec.get("unit", "")
            if not isinstance(unit, str):
                reader.problem(path, item, f"unit must be a text such as \"kN/m\", got {show_value(unit)}")
                continue
            if isinstance(raw, bool) or not isinstance(raw, (int, float)):
                reader.problem(path, item, f"value must be a number, got {show_value(raw)}")
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
            reader.problem(path, item, f"value must be a number, got {value_kind(raw)}")
    return parameters


def _text_parameter(reader: TomlReader, name: str, raw: str, line: int | None) -> Parameter | None:
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
            reader.problem(path, item, f'"{cut_text(raw)}" is neither a number with a unit nor an expression ({reason})')
            return None
        if expression.is_number:
            return Parameter(name, float(expression), "", line)
        return Parameter(name, math.nan, "", line, expression=expression)
    if not math.isfinite(value):
        reader.problem(path, item, f'"{cut_text(raw)}" is not a finite number')
        return None
    return Parameter(name, value, unit, line)


def _rail(reader: TomlReader, table: dict, parameters: dict[str, Parameter]) -> tuple[RailSpec, tuple[Derivation, ...]]:
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
        check_id(reader, name, path, f"output {name}")  # names become CSV columns and TOML keys
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


def _creep(reader: TomlReader, raw: Any) -> Derivation:
    """``[rail.creep]``: f1, f2 from the contact, a derivation node of the graph."""
    path = ("rail", "creep")
    spec = reader.table(raw, path, "rail.creep")
    reader.unknown_keys(spec, _CREEP_KEYS, path, "rail.creep")
    if spec.get("from", "kalker") != "kalker":
        reader.problem(path + ("from",), "rail.creep", f'from must be "kalker", got {show_value(spec.get("from"))}')
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


def _add_outputs(reader: TomlReader, parameters: dict[str, Parameter], derivations: tuple[Derivation, ...]) -> None:
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
    data = parse_toml(text, source)
    size = _size_problems(data, source)
    if size:
        raise ModelError(size)
    reader = TomlReader(text, source)
    reader.unknown_keys(data, _TOP_KEYS, (), "file")

    info = reader.table(data.get("model", {}), ("model",), "model")
    reader.unknown_keys(info, ("name", "title"), ("model",), "model")
    name = info.get("name", model_name_from_path(source))
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name):
        reader.problem(("model", "name"), "model", f"name must be an identifier, got {show_value(name)}")
        name = model_name_from_path(source)
    title = info.get("title", "")

    parameters = _parameters(reader, reader.table(data.get("parameters", {}), ("parameters",), "parameters"))

    bodies, grounds, points, elements, pins = read_items(reader, data)
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
    if not bodies and not reader.problems:  # an empty or cut-short file is not a model
        problems.append(Problem(source, None, "bodies", "the model has no bodies: give [bodies.NAME] tables or "
                                "[instances] of substructures (an empty or truncated file?)"))
    if problems:
        raise ModelError(problems)
    model = resolve(model)
    if "flexible" in data:  # flexible (modal) bodies: express.io.toml_modal
        model = _flexible(reader, data["flexible"], model)
    return model


def _flexible(reader: TomlReader, table: Any, model: Model) -> Model:
    """The model with its ``[flexible]`` bodies and their parameters (values needed)."""
    from dataclasses import replace

    from express.io.toml_modal import read_flexible

    flexible, added, nodes = read_flexible(reader, table, model)
    model = replace(model, flexible=flexible, parameters={**model.parameters, **added},
                    derivations=model.derivations + nodes)
    problems = reader.problems + check_model(model)
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


def _gravity(reader: TomlReader, data: dict) -> sp.Expr | None:
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
