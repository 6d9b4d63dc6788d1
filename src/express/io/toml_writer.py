"""Writer of the modern (TOML) model format: ``express convert``.

Turns any :class:`~express.model.records.Model` (typically read from a classic file) into a
TOML file that reads back to the same model.  Exact values are written as TOML
numbers when they are decimals (``3/10`` -> ``0.3``) and as expression strings
otherwise.
"""

from __future__ import annotations

import json
import os
import re
from pathlib import Path

import sympy as sp

from express.base.units import unit_factor
from express.model.records import Model, Parameter

__all__ = ["model_to_toml", "value_text", "value_to_toml"]


def _decimal(value: sp.Rational) -> str | None:
    """``3/10`` -> ``"0.3"`` when the rational has a finite decimal form."""
    denominator = int(value.q)
    twos = fives = 0
    while denominator % 2 == 0:
        denominator //= 2
        twos += 1
    while denominator % 5 == 0:
        denominator //= 5
        fives += 1
    if denominator != 1:
        return None
    digits = max(twos, fives)
    scaled = value * 10**digits
    text = str(abs(int(scaled))).rjust(digits + 1, "0")
    sign = "-" if value < 0 else ""
    if digits == 0:
        return f"{sign}{text}"
    return f"{sign}{text[:-digits]}.{text[-digits:]}"


def value_text(value: sp.Expr) -> str:
    """Plain text of an exact value: ``0.3`` for 3/10, ``h2 - hc`` for expressions."""
    if value.is_Integer:
        return str(int(value))
    if value.is_Rational:
        decimal = _decimal(value)
        if decimal is not None:
            return decimal
    return sp.sstr(value)


def value_to_toml(value: sp.Expr) -> str:
    """A TOML value for an exact expression: a number if possible, else a string."""
    text = value_text(value)
    is_number = value.is_Rational and "/" not in text
    return text if is_number else json.dumps(text)


def _vector(values) -> str:
    return "[" + ", ".join(value_to_toml(v) for v in values) + "]"


_BARE_KEY = re.compile(r"[A-Za-z0-9_-]+\Z")


def _direction(element) -> str:
    """An element's ``direction``: its axis, ``"line"``, its vector or the vector it turns about."""
    if element.vector is None:
        return toml_string(element.axis_name)
    if element.rotational:
        return f"{{ about = {_vector(element.vector)} }}"
    return '"line"' if element.through_ends else _vector(element.vector)


def toml_string(text: str) -> str:
    """A TOML basic string: JSON's escapes (quotes, backslash, control characters)
    plus DEL, which TOML also forbids raw; a lone surrogate (not a character) becomes
    U+FFFD."""
    text = "".join("\ufffd" if 0xD800 <= ord(c) <= 0xDFFF else c for c in text)
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def toml_key(name: str) -> str:
    """A TOML key: bare when it can be, else quoted."""
    return name if _BARE_KEY.match(name) else toml_string(name)


def _comment(text: str) -> str:
    """Text for a ``#`` comment: one line, control characters escaped."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def _parameter_line(parameter: Parameter) -> str:
    """``mc = { value = 30.0, unit = "t" }`` in the unit written, or ``P0 = "expression"``."""
    name = parameter.name
    if parameter.expression is not None:
        return f"{toml_key(name)} = {toml_string(value_text(parameter.expression))}"
    unit = parameter.unit.strip()
    if unit:
        factor = unit_factor(unit)
        shown = parameter.value / factor
        if float(shown) * factor == parameter.value:  # reads back to the same SI value
            return f"{toml_key(name)} = {{ value = {shown!r}, unit = {toml_string(unit)} }}"
        return f"{toml_key(name)} = {parameter.value!r}  # SI (given in {_comment(unit)})"
    return f"{toml_key(name)} = {parameter.value!r}"


def _friction(element) -> str:
    """A friction element's ``friction = ...`` line: a limit, or a table with its load
    (the factor mu, or mu r as mu with radius 1) or its partner in a plane."""
    plane = f", plane = {toml_string(element.friction_plane)}" if element.friction_plane else ""
    if element.friction_of:
        radius = ", radius = 1" if element.rotational else ""
        return (f"friction = {{ mu = {value_to_toml(element.friction)}, of = {toml_string(element.friction_of)}"
                f"{radius}{plane} }}")
    if plane:
        return f"friction = {{ limit = {value_to_toml(element.friction)}{plane} }}"
    return f"friction = {value_to_toml(element.friction)}"



def model_to_toml(model: Model, folder: str | Path | None = None) -> str:
    """The TOML text of ``model`` (deterministic).

    Parameters
    ----------
    model : Model
    folder : str or pathlib.Path, optional
        The folder the text will be written to: profile files the model names are
        written relative to it (absolute without it).
    """
    lines = [
        f"# EXPRESS model, converted from {_comment(model.source)}",
        "# Format: docs/model-format.md.  Values are numbers or expressions of parameters.",
        "",
        "[model]",
        f"name = {toml_string(model.name)}",
    ]
    if model.title:
        lines.append(f"title = {toml_string(model.title)}")
    lines += ["", "[parameters]"]
    flexible, made = _flexible_lines(model)
    if model.parameters:
        for parameter in model.parameters.values():
            if parameter.derived_by is None and parameter.name not in made:  # outputs of [rail.creep] and
                # the modes' parameters are made again on loading
                lines.append(_parameter_line(parameter))
    else:
        names = set()
        for body in model.bodies:
            names |= {s.name for s in (body.mass, *body.inertia, *body.position) for s in s.free_symbols}
        for point in model.points:
            names |= {s.name for v in point.offset for s in v.free_symbols}
        for element in model.elements:
            names |= {s.name for v in (element.stiffness, element.damping) for s in v.free_symbols}
        lines.append("# values for: " + ", ".join(sorted(names)))
    for body in model.bodies:
        lines += ["", f"[bodies.{toml_key(body.id)}]"]
        if body.label:
            lines.append(f"label = {toml_string(body.label)}")
        lines.append(f"mass = {value_to_toml(body.mass)}")
        lines.append(f"inertia = {_vector(body.inertia)}  # Ix, Iy, Iz")
        lines.append("dofs = [" + ", ".join(toml_string(d) for d in body.dofs) + "]")
        if any(v != 0 for v in body.position):
            lines.append(f"position = {_vector(body.position)}")
        if body.outline is not None:
            lines.append(f"outline = {_vector(body.outline)}  # length, width, height drawn")
    for ground in model.grounds:
        lines += ["", f"[grounds.{toml_key(ground.id)}]"]
        if ground.label:
            lines.append(f"label = {toml_string(ground.label)}")
    for point in model.points:
        lines += ["", f"[points.{toml_key(point.id)}]", f"body = {toml_string(point.host)}", f"offset = {_vector(point.offset)}"]
    for element in model.elements:
        lines += ["", f"[elements.{toml_key(element.id)}]"]
        if element.label:
            lines.append(f"label = {toml_string(element.label)}")
        lines += [
            f"from = {toml_string(element.s_end)}",
            f"to = {toml_string(element.t_end)}",
            f"direction = {_direction(element)}",
        ] + ([f"preload = {value_to_toml(element.preload)}"] if element.preload != 0 else [])
        characteristic = element.characteristic
        if characteristic is None or characteristic.velocity:  # a characteristic is its stiffness or damping
            lines.append(f"stiffness = {value_to_toml(element.stiffness)}")
        if characteristic is None or not characteristic.velocity:
            lines.append(f"damping = {value_to_toml(element.damping)}")
        if characteristic is not None:
            lines.append(f"characteristic = {_characteristic(characteristic)}")
        if element.sliding:
            lines.append(_friction(element))
        if element.series:
            lines.append("series = true")
        if element.clearance:
            lines.append(f"gap = {value_to_toml(element.gap)}")
        if element.progressive != 0:
            lines.append(f"progressive = {value_to_toml(element.progressive)}")
    for pin in model.pins:
        lines += [
            "",
            f"[pins.{toml_key(pin.id)}]",
            f"virtual = {toml_string(pin.virtual)}",
            f"non_virtual = {toml_string(pin.non_virtual)}",
        ]
    if model.gravity is not None:
        lines += ["", "[gravity]", f"acceleration = {value_to_toml(model.gravity)}"]
    if model.rail is not None:
        lines += _rail_lines(model, folder)
    return "\n".join(lines + flexible) + "\n"


def _flexible_lines(model: Model) -> tuple[list[str], set[str]]:
    """The ``[flexible]`` section (:func:`express.io.toml_modal.flexible_lines`), if any."""
    if not model.flexible:
        return [], set()
    from express.io.toml_modal import flexible_lines

    return flexible_lines(model)


def _characteristic(characteristic) -> str:
    """An inline table of a characteristic: a keyword shape with its values, a table
    (from a file too) with its breakpoints in SI."""
    if characteristic.shape != "table":
        items = [f"shape = {toml_string(characteristic.shape)}"]
        items += [f"{key} = {toml_string(value) if isinstance(value, str) else value_to_toml(value)}"
                  for key, value in characteristic.keys]
        return "{ " + ", ".join(items) + " }"
    x = ", ".join(repr(float(point[0])) for point in characteristic.points)
    f = ", ".join(repr(float(point[1])) for point in characteristic.points)
    return (f"{{ shape = \"table\", of = {toml_string(characteristic.of)}, {characteristic.of} = [{x}], force = [{f}] }}")


def _profile_name(text: str, base: str, folder: str | Path | None) -> str:
    """A profile as the reader takes it: a standard name as it is, a file relative to
    ``folder`` (absolute without one)."""
    from express.io.toml_contact import STANDARD_NAMES

    if text.strip().upper().replace(" ", "") in STANDARD_NAMES:
        return text
    path = Path(text)
    if not path.is_absolute():
        path = Path(base or ".") / path
    path = path.resolve()
    if folder is None:
        return path.as_posix()
    return Path(os.path.relpath(path, Path(folder).resolve())).as_posix()


def _profiles_node(derivation, folder: str | Path | None) -> str:
    """``conicity = { from = "profiles", ... }`` of a ``"profiles"`` derivation node."""
    settings = dict(derivation.settings)
    if settings.get("table"):  # a contact table file (express.io.contact_table_file)
        items = ['from = "table"', f"file = {toml_string(_profile_name(settings['table'], settings.get('base', ''), folder))}",
                 f"name = {toml_string(derivation.output('conicity'))}"]
        items += [f"{key} = {value_to_toml(value)}" for key, value, _ in derivation.inputs]
        return "{ " + ", ".join(items) + " }"
    items = ['from = "profiles"']
    items += [f"{key} = {toml_string(_profile_name(settings[key], settings.get('base', ''), folder))}"
              for key in ("wheel", "rail")]
    if settings.get("units"):
        items.append(f"units = {toml_string(settings['units'])}")
    items.append(f"name = {toml_string(derivation.output('conicity'))}")
    items += [f"{key} = {value_to_toml(value)}" for key, value, _ in derivation.inputs]
    return "{ " + ", ".join(items) + " }"


def _rail_lines(model: Model, folder: str | Path | None = None) -> list[str]:
    rail = model.rail
    assert rail is not None
    nodes = {d.item: d for d in model.derivations if d.kind == "profiles"}
    shared = nodes.get("rail.wheel_rail.conicity")
    lines = [
        "",
        "[rail]",
        f"speed = {value_to_toml(rail.speed)}",
        f"cant_base = {value_to_toml(rail.cant_base)}",
        f"gravity = {value_to_toml(rail.gravity)}",
        "wheelsets = [" + ", ".join(toml_string(w.body) for w in rail.wheelsets) + "]",
    ]
    if shared is not None:  # the wheelsets without their own conicity share this node
        lines += ["", "[rail.wheel_rail]", f"conicity = {_profiles_node(shared, folder)}"]
    keys = ("f1", "f2", "conicity", "r0", "b", "flange_clearance", "rail_stiffness", "friction", "wheel_load")
    for wheelset in rail.wheelsets:
        lines += ["", f"[rail.wheelset.{toml_key(wheelset.body)}]"]
        own = nodes.get(f"rail.wheelset.{wheelset.body}.conicity")
        for key in keys:
            value = getattr(wheelset, key)
            if key == "conicity" and own is not None:
                lines.append(f"conicity = {_profiles_node(own, folder)}")
            elif not (key == "conicity" and shared is not None and value == sp.Symbol(shared.output("conicity"))):
                lines.append(f"{key} = {value_to_toml(value)}")
    for derivation in model.derivations:
        if derivation.kind == "kalker":
            lines += [
                "",
                "[rail.creep]",
                'from = "kalker"',
                f"longitudinal = {toml_string(derivation.output('f11'))}",
                f"lateral = {toml_string(derivation.output('f22'))}",
            ]
            lines += [f"{key} = {value_to_toml(value)}" for key, value, _ in derivation.inputs]
    for output in rail.outputs:
        lines += ["", f"[rail.outputs.{toml_key(output.name)}]", f"body = {toml_string(output.body)}", f"offset = {_vector(output.offset)}"]
    return lines
