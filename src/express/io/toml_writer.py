"""Writer of the modern (TOML) model format: ``express convert``.

Turns any :class:`~express.model.records.Model` (typically read from a classic file) into a
TOML file that reads back to the same model.  Exact values are written as TOML
numbers when they are decimals (``3/10`` -> ``0.3``) and as expression strings
otherwise.
"""

from __future__ import annotations

import json
import re

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
    """An element's ``direction``: its axis, ``"line"`` or its vector."""
    if element.vector is None:
        return _string(element.axis_name)
    return '"line"' if element.through_ends else _vector(element.vector)


def _string(text: str) -> str:
    """A TOML basic string: JSON's escapes (quotes, backslash, control characters)
    plus DEL, which TOML also forbids raw; a lone surrogate (not a character) becomes
    U+FFFD."""
    text = "".join("\ufffd" if 0xD800 <= ord(c) <= 0xDFFF else c for c in text)
    return json.dumps(text, ensure_ascii=False).replace("\x7f", "\\u007f")


def _key(name: str) -> str:
    """A TOML key: bare when it can be, else quoted."""
    return name if _BARE_KEY.match(name) else _string(name)


def _comment(text: str) -> str:
    """Text for a ``#`` comment: one line, control characters escaped."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def _parameter_line(parameter: Parameter) -> str:
    """``mc = { value = 30.0, unit = "t" }`` in the unit written, or ``P0 = "expression"``."""
    name = parameter.name
    if parameter.expression is not None:
        return f"{_key(name)} = {_string(value_text(parameter.expression))}"
    unit = parameter.unit.strip()
    if unit:
        factor = unit_factor(unit)
        shown = parameter.value / factor
        if float(shown) * factor == parameter.value:  # reads back to the same SI value
            return f"{_key(name)} = {{ value = {shown!r}, unit = {_string(unit)} }}"
        return f"{_key(name)} = {parameter.value!r}  # SI (given in {_comment(unit)})"
    return f"{_key(name)} = {parameter.value!r}"


def _friction(element) -> str:
    """A friction element's ``friction = ...`` line: a limit, or a table with its load
    (the factor mu, or mu r as mu with radius 1) or its partner in a plane."""
    plane = f", plane = {_string(element.friction_plane)}" if element.friction_plane else ""
    if element.friction_of:
        radius = ", radius = 1" if element.rotational else ""
        return (f"friction = {{ mu = {value_to_toml(element.friction)}, of = {_string(element.friction_of)}"
                f"{radius}{plane} }}")
    if plane:
        return f"friction = {{ limit = {value_to_toml(element.friction)}{plane} }}"
    return f"friction = {value_to_toml(element.friction)}"


def model_to_toml(model: Model) -> str:
    """The TOML text of ``model`` (deterministic)."""
    lines = [
        f"# EXPRESS model, converted from {_comment(model.source)}",
        "# Format: docs/model-format.md.  Values are numbers or expressions of parameters.",
        "",
        "[model]",
        f"name = {_string(model.name)}",
    ]
    if model.title:
        lines.append(f"title = {_string(model.title)}")
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
        lines += ["", f"[bodies.{_key(body.id)}]"]
        if body.label:
            lines.append(f"label = {_string(body.label)}")
        lines.append(f"mass = {value_to_toml(body.mass)}")
        lines.append(f"inertia = {_vector(body.inertia)}  # Ix, Iy, Iz")
        lines.append("dofs = [" + ", ".join(_string(d) for d in body.dofs) + "]")
        if any(v != 0 for v in body.position):
            lines.append(f"position = {_vector(body.position)}")
        if body.outline is not None:
            lines.append(f"outline = {_vector(body.outline)}  # length, width, height drawn")
    for ground in model.grounds:
        lines += ["", f"[grounds.{_key(ground.id)}]"]
        if ground.label:
            lines.append(f"label = {_string(ground.label)}")
    for point in model.points:
        lines += ["", f"[points.{_key(point.id)}]", f"body = {_string(point.host)}", f"offset = {_vector(point.offset)}"]
    for element in model.elements:
        lines += ["", f"[elements.{_key(element.id)}]"]
        if element.label:
            lines.append(f"label = {_string(element.label)}")
        lines += [
            f"from = {_string(element.s_end)}",
            f"to = {_string(element.t_end)}",
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
            f"[pins.{_key(pin.id)}]",
            f"virtual = {_string(pin.virtual)}",
            f"non_virtual = {_string(pin.non_virtual)}",
        ]
    if model.gravity is not None:
        lines += ["", "[gravity]", f"acceleration = {value_to_toml(model.gravity)}"]
    if model.rail is not None:
        lines += _rail_lines(model)
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
        items = [f"shape = {_string(characteristic.shape)}"]
        items += [f"{key} = {_string(value) if isinstance(value, str) else value_to_toml(value)}"
                  for key, value in characteristic.keys]
        return "{ " + ", ".join(items) + " }"
    x = ", ".join(repr(float(point[0])) for point in characteristic.points)
    f = ", ".join(repr(float(point[1])) for point in characteristic.points)
    return (f"{{ shape = \"table\", of = {_string(characteristic.of)}, {characteristic.of} = [{x}], force = [{f}] }}")


def _rail_lines(model: Model) -> list[str]:
    rail = model.rail
    assert rail is not None
    lines = [
        "",
        "[rail]",
        f"speed = {value_to_toml(rail.speed)}",
        f"cant_base = {value_to_toml(rail.cant_base)}",
        f"gravity = {value_to_toml(rail.gravity)}",
        "wheelsets = [" + ", ".join(_string(w.body) for w in rail.wheelsets) + "]",
    ]
    keys = ("f1", "f2", "conicity", "r0", "b", "flange_clearance", "rail_stiffness", "friction", "wheel_load")
    for wheelset in rail.wheelsets:
        lines += ["", f"[rail.wheelset.{_key(wheelset.body)}]"]
        lines += [f"{key} = {value_to_toml(getattr(wheelset, key))}" for key in keys]
    for derivation in model.derivations:
        if derivation.kind == "kalker":
            lines += [
                "",
                "[rail.creep]",
                'from = "kalker"',
                f"longitudinal = {_string(derivation.output('f11'))}",
                f"lateral = {_string(derivation.output('f22'))}",
            ]
            lines += [f"{key} = {value_to_toml(value)}" for key, value, _ in derivation.inputs]
    for output in rail.outputs:
        lines += ["", f"[rail.outputs.{_key(output.name)}]", f"body = {_string(output.body)}", f"offset = {_vector(output.offset)}"]
    return lines
