"""Building a model in Python (issue 35, item 4): bodies, grounds, points, elements and
pins added one call at a time, as :mod:`sympy.physics.mechanics` builds a system, giving
the model the same file would.

The builder writes the model file's text and reads it with the file reader
(:func:`express.io.toml_model.parse_toml_model`), so a built model is checked exactly as
a file is (every problem at once, naming the item) and is the file's model by
construction; :meth:`ModelBuilder.to_toml` gives that text. Values are what a file
takes: numbers (SI), quantities (``"10 t"`` or a :class:`pint.Quantity`), or
expressions of parameters (``"2*a"``), never evaluated here.

Examples
--------
>>> from express.io.builder import ModelBuilder
>>> car = ModelBuilder("mass_on_spring")
>>> car.parameter("m", "250 kg").parameter("k", "40 kN/m")
ModelBuilder('mass_on_spring': 0 bodies, 0 elements)
>>> _ = car.body("B", mass="m", dofs=["z"]).ground("G")
>>> _ = car.point("top", "B", [0, 0, 0]).point("base", "G", [0, 0, 0])
>>> _ = car.element("spring", "top", "base", "z", stiffness="k")
>>> car.build().elements[0].stiffness
k
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

from express.base.diagnostics import ArgumentError
from express.model.records import Model

__all__ = ["ModelBuilder"]


class _Table(dict):
    """A ``[section]`` of the file (a plain dict value is an inline table)."""


def _value(value: Any, where: str) -> str:
    """TOML text of one value."""
    from express.io.toml_writer import toml_string

    if hasattr(value, "magnitude") and hasattr(value, "units"):  # a pint quantity
        return toml_string(f"{float(value.magnitude)!r} {value.units:~}")
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ArgumentError(f"{where}: {value!r} is not a finite number")
        return repr(value)
    if isinstance(value, str):
        return toml_string(value)
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{_key(k)} = {_value(v, f'{where}.{k}')}" for k, v in value.items()) + " }"
    if isinstance(value, Sequence):
        return "[" + ", ".join(_value(v, f"{where}[{i}]") for i, v in enumerate(value)) + "]"
    if hasattr(value, "free_symbols"):  # a sympy expression
        return toml_string(str(value))
    raise ArgumentError(f"{where}: a number, a quantity, a string or a list of them, got {type(value).__name__}")


def _key(name: str) -> str:
    from express.io.toml_writer import toml_key

    return toml_key(str(name))


def _lines(table: _Table, path: tuple[str, ...]) -> list[str]:
    """The text of ``table`` at ``path``: its values, then its sub-tables."""
    lines = []
    values = [(k, v) for k, v in table.items() if not isinstance(v, _Table)]
    if path and (values or not any(isinstance(v, _Table) for v in table.values())):
        lines += ["", "[" + ".".join(_key(p) for p in path) + "]"]
    lines += [f"{_key(k)} = {_value(v, '.'.join((*path, str(k))))}" for k, v in values]
    for k, v in table.items():
        if isinstance(v, _Table):
            lines += _lines(v, (*path, str(k)))
    return lines


class ModelBuilder:
    """A model built one item at a time (module docstring); every method returns the
    builder, so calls chain.

    Parameters
    ----------
    name : str
        The model's name (an identifier).
    title : str, optional
    """

    def __init__(self, name: str, title: str = "") -> None:
        self._root = _Table()
        self._root["model"] = _Table(name=name, **({"title": title} if title else {}))
        self._root["parameters"] = _Table()

    def __repr__(self) -> str:
        counts = {key: len(self._root.get(key, ())) for key in ("bodies", "elements")}
        return f"ModelBuilder({self._root['model']['name']!r}: {counts['bodies']} bodies, {counts['elements']} elements)"

    def _item(self, section: str, item_id: str, keys: dict[str, Any]) -> ModelBuilder:
        table = self._root.setdefault(section, _Table())
        if item_id in table:
            raise ArgumentError(f"{section} {item_id!r} is added twice")
        table[item_id] = _Table({k: v for k, v in keys.items() if v is not None})
        return self

    def parameter(self, name: str, value: Any) -> ModelBuilder:
        """A parameter: a number (SI), a quantity (``"250 kg"``) or an expression."""
        self._root["parameters"][name] = value
        return self

    def body(self, body_id: str, *, mass: Any, dofs: Sequence[str], inertia: Sequence[Any] | None = None,
             position: Sequence[Any] | None = None, label: str | None = None, **keys: Any) -> ModelBuilder:
        """A rigid body (``[bodies.ID]``: ``docs/model-format.md``)."""
        return self._item("bodies", body_id, {"label": label, "mass": mass, "inertia": inertia, "dofs": list(dofs),
                                              "position": position, **keys})

    def ground(self, ground_id: str, *, label: str | None = None) -> ModelBuilder:
        """A ground (``[grounds.ID]``)."""
        return self._item("grounds", ground_id, {"label": label})

    def point(self, point_id: str, body: str, offset: Sequence[Any]) -> ModelBuilder:
        """A connection point on a body or ground (``[points.ID]``)."""
        return self._item("points", point_id, {"body": body, "offset": list(offset)})

    def element(self, element_id: str, from_: str, to: str, direction: Any, *, stiffness: Any = None,
                damping: Any = None, label: str | None = None, **keys: Any) -> ModelBuilder:
        """A spring/damper element between two points (``[elements.ID]``); further keys
        as the file takes them (``series = True``, ``gap``, ``friction``,
        ``characteristic = {...}``, ``air_spring = {...}``)."""
        return self._item("elements", element_id, {"label": label, "from": from_, "to": to, "direction": direction,
                                                   "stiffness": stiffness, "damping": damping, **keys})

    def pin(self, pin_id: str, virtual: str, non_virtual: str) -> ModelBuilder:
        """A pinned joint (``[pins.ID]``)."""
        return self._item("pins", pin_id, {"virtual": virtual, "non_virtual": non_virtual})

    def section(self, path: str, **keys: Any) -> ModelBuilder:
        """Any other section by its dotted path (``"rail"``, ``"rail.wheel_rail"``,
        ``"gravity"``), its keys as the file takes them."""
        table = self._root
        for part in path.split("."):
            table = table.setdefault(part, _Table())
            if not isinstance(table, _Table):
                raise ArgumentError(f"section {path!r}: {part!r} is a value, not a section")
        table.update({k: v for k, v in keys.items() if v is not None})
        return self

    def to_toml(self) -> str:
        """The model file's text."""
        return "\n".join(_lines(self._root, ())).lstrip("\n") + "\n"

    def build(self, source: str = "<builder>") -> Model:
        """The model, read from :meth:`to_toml` as a file is.

        Raises
        ------
        ModelError
            Every problem of the model at once, each naming its item.
        """
        from express.io.toml_model import parse_toml_model

        return parse_toml_model(self.to_toml(), source)
