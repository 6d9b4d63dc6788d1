"""Nonlinear characteristics of a TOML model's elements (issue 31, item 2):
``characteristic = {...}`` on an element, read into a
:class:`~express.model.characteristics.Characteristic` (its meaning and linearisation are
described there).

```toml
characteristic = { shape = "table", of = "deflection", deflection = [-20, 0, 10, 30], force = [-8, 0, 2, 10], units = ["mm", "kN"] }
characteristic = { shape = "table", of = "velocity", file = "damper.csv" }   # header "velocity [m/s], force [kN]"
characteristic = { shape = "bilinear", stiffness = "k1", knee = "d1", beyond = "k2" }
characteristic = { shape = "blow-off", damping = "c", velocity = "vb" }      # or force = "Fb"; beyond = c2
characteristic = { shape = "contact", stiffness = "k", preload = "P" }       # or gap = "g"; side = "extension"
```

A table's values are numbers (in its ``units``, SI by default); a CSV file (relative to
the model file) has a header naming each column and its unit in brackets, ``#`` comment
lines and blank lines, then one breakpoint a line.  Checked on reading, every problem at
once with its file and line: at least two points, the same number of each, finite
numbers, the abscissae strictly increasing, the units' dimensions, a velocity table
through zero (to 1e-9 of its largest force), a keyword shape's parameters positive (their
dimensions with the parameters' units).  Nothing is evaluated: the values are data.
"""

from __future__ import annotations

import itertools
import math
import re
from pathlib import Path
from typing import Any

import sympy as sp

from express.base.diagnostics import ModelError, Problem
from express.base.units import DIMENSIONS, UnitError, unit_dimension, unit_factor
from express.model.characteristics import Characteristic, bilinear, blow_off, contact, table_tangent

__all__ = ["CHARACTERISTIC_KEYS", "read_characteristic"]

CHARACTERISTIC_KEYS = ("shape", "of", "deflection", "velocity", "force", "units", "file", "stiffness", "knee",
                       "compression_knee", "beyond", "damping", "preload", "gap", "side", "compression_velocity",
                       "compression_force")
SHAPES = {
    "table": ("of", "deflection", "velocity", "force", "units", "file"),
    "bilinear": ("stiffness", "knee", "compression_knee", "beyond"),
    "blow-off": ("damping", "velocity", "force", "beyond", "compression_velocity", "compression_force"),
    "contact": ("stiffness", "preload", "gap", "side"),
}
#: Through zero: a velocity table's F(0) within this fraction of its largest force.
THROUGH_ZERO = 1e-9


def _dimensions(rotational: bool) -> dict[str, Any]:
    length = DIMENSIONS["angle"] if rotational else DIMENSIONS["length"]
    force = DIMENSIONS["force"] * DIMENSIONS["length"] if rotational else DIMENSIONS["force"]
    time = DIMENSIONS["time"]
    return {"deflection": length, "velocity": length / time, "force": force, "stiffness": force / length,
            "damping": force / length * time}


def read_characteristic(reader: Any, path: tuple[str, ...], item: str, spec: dict, rotational: bool
                        ) -> tuple[Characteristic | None, list[tuple[str, sp.Expr, Any, bool]]]:
    """The characteristic ``spec["characteristic"]`` of an element, and the values to be
    checked positive with their dimensions (a keyword shape's parameters); problems go to
    ``reader`` with their lines, None when it cannot be read."""
    where = path + ("characteristic",)
    table = reader.table(spec["characteristic"], where, item)
    shape = table.get("shape")
    if shape not in SHAPES:
        reader.problem(where + ("shape",), item, f"characteristic shape must be one of {', '.join(SHAPES)}, "
                       f"got {shape!r}")
        return None, []
    reader.unknown_keys(table, ("shape", *SHAPES[shape]), where, item)
    dims = _dimensions(rotational)
    checked: list[tuple[str, sp.Expr, Any, bool]] = []

    keys: list[tuple[str, sp.Expr | str]] = []

    def value(key: str, dimension: str, positive: bool = True) -> sp.Expr:
        expression = reader.expression(table[key], where + (key,), item, f"characteristic {key}")
        checked.append((f"characteristic {key}", expression, dims[dimension], positive))
        keys.append((key, expression))
        return expression

    def need(*keys: str) -> bool:
        missing = [key for key in keys if key not in table]
        if missing:
            reader.problem(where, item, f"a {shape} characteristic needs {', '.join(missing)}")
        return not missing

    if shape == "table":
        return _table(reader, where, item, table, rotational), []
    if shape == "bilinear":
        if not need("stiffness", "knee", "beyond"):
            return None, []
        low = value("compression_knee", "deflection") if "compression_knee" in table else None
        points, tangent = bilinear(value("stiffness", "stiffness"), value("knee", "deflection"),
                                   value("beyond", "stiffness", positive=False), low)
        return Characteristic("deflection", shape, points, tangent, reader.source, tuple(keys)), checked
    if shape == "blow-off":
        if not need("damping"):
            return None, []
        c = value("damping", "damping")
        given = [key for key in ("velocity", "force") if key in table]
        if len(given) != 1:
            reader.problem(where, item, "a blow-off damper needs its blow-off velocity or its blow-off force "
                           "(one of velocity = ..., force = ...)")
            return None, []
        v_blow = value("velocity", "velocity") if given == ["velocity"] else value("force", "force") / c
        c2 = value("beyond", "damping", positive=False) if "beyond" in table else sp.S.Zero
        low = [key for key in ("compression_velocity", "compression_force") if key in table]
        if len(low) > 1:
            reader.problem(where, item, "give compression_velocity or compression_force, not both")
        compression = (None if not low else value(low[0], "velocity") if low[0] == "compression_velocity"
                       else value(low[0], "force") / c)
        points, tangent = blow_off(c, v_blow, c2, compression)
        return Characteristic("velocity", shape, points, tangent, reader.source, tuple(keys)), checked
    if not need("stiffness"):
        return None, []
    if "preload" in table and "gap" in table:
        reader.problem(where, item, "a contact is closed with a preload or open by a gap, not both")
    side = table.get("side", "compression")
    if side not in ("compression", "extension"):
        reader.problem(where + ("side",), item, f'side must be "compression" or "extension", got {side!r}')
    k = value("stiffness", "stiffness")
    preload = value("preload", "force") if "preload" in table else None
    gap = value("gap", "deflection") if "gap" in table else None
    points, tangent = contact(k, preload, gap, side == "extension")
    if side == "extension":
        keys.append(("side", "extension"))
    return Characteristic("deflection", shape, points, tangent, reader.source, tuple(keys)), checked


def _table(reader: Any, where: tuple[str, ...], item: str, table: dict, rotational: bool) -> Characteristic | None:
    of = table.get("of")
    if of not in ("deflection", "velocity"):
        reader.problem(where + ("of",), item, f'a table is of "deflection" or "velocity", got {of!r}')
        return None
    dims = _dimensions(rotational)
    problems: list[Problem] = []
    if "file" in table:
        for key in (of, "force", "units"):
            if key in table:
                reader.problem(where + (key,), item, f'a table from a file has no "{key}" (its header names '
                               "the columns and their units)")
        points, source = _csv(reader, where, item, table["file"], of, dims, problems)
    else:
        line = reader.line(*where)
        if of not in table or "force" not in table:
            reader.problem(where, item, f"a table needs {of} = [...] and force = [...] (or file = ...)")
            return None
        units = table.get("units", ["", ""])
        if not (isinstance(units, list) and len(units) == 2 and all(isinstance(u, str) for u in units)):
            reader.problem(where + ("units",), item, f'units must be two unit strings ["<{of} unit>", "<force unit>"]')
            units = ["", ""]
        factors = [_factor(reader.source, line, item, unit, dims[name], name, problems)
                   for unit, name in zip(units, (of, "force"), strict=True)]
        columns = []
        for key in (of, "force"):
            raw = table[key]
            if not isinstance(raw, list) or any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in raw):
                problems.append(Problem(reader.source, line, item, f"{key} must be a list of numbers"))
                raw = []
            columns.append([float(v) for v in raw])
        if len(columns[0]) != len(columns[1]):
            problems.append(Problem(reader.source, line, item, f"{of} has {len(columns[0])} values, force "
                                    f"{len(columns[1])}"))
        points = [(x * (factors[0] or 1.0), f * (factors[1] or 1.0), line, x) for x, f in zip(*columns, strict=False)]
        source = reader.source
    _check_points(points, of, item, source, problems)
    reader.problems.extend(problems)
    if problems or len(points) < 2:
        return None
    x, f = [p[0] for p in points], [p[1] for p in points]
    _, tangent = table_tangent(x, f)
    return Characteristic(of, "table", tuple((sp.Float(a), sp.Float(b)) for a, b in zip(x, f, strict=True)),
                          sp.Float(tangent), source)


def _factor(source: str, line: int | None, item: str, unit: str, wanted: Any, name: str,
            problems: list[Problem]) -> float | None:
    """The SI factor of ``unit`` for the column ``name`` (of dimension ``wanted``; none: SI)."""
    if not unit.strip():
        return 1.0
    try:
        factor, found = unit_factor(unit), unit_dimension(unit)
    except UnitError as error:
        problems.append(Problem(source, line, item, f'{name} unit "{unit}": {error}'))
        return None
    if found != wanted:
        problems.append(Problem(source, line, item, f'{name} unit "{unit}" is not a {name} (wanted {wanted.si()})'))
        return None
    return factor


def _check_points(points: list, of: str, item: str, source: str, problems: list[Problem]) -> None:
    if len(points) < 2:
        problems.append(Problem(source, points[0][2] if points else None, item, f"a table needs at least two points, "
                                f"got {len(points)}"))
        return
    for x, f, line, _ in points:
        if not (math.isfinite(x) and math.isfinite(f)):
            problems.append(Problem(source, line, item, f"a table's values must be finite, got {x:g}, {f:g}"))
    for (x0, _, _, given0), (x1, _, line, given1) in itertools.pairwise(points):
        if not x1 > x0:  # the values as given (in the table's unit)
            problems.append(Problem(source, line, item, f"the {of} values must increase: {given1:g} after {given0:g}"))
    if of == "velocity" and not problems:
        at_zero, _ = table_tangent([p[0] for p in points], [p[1] for p in points])
        largest = max(abs(p[1]) for p in points)
        if abs(at_zero) > THROUGH_ZERO * largest:
            near = min(points, key=lambda point: abs(point[0]))  # the row nearest zero velocity
            problems.append(Problem(source, near[2], item, f"a damper's table must pass through zero force at "
                                    f"zero velocity, got {at_zero:g} N there"))


def _csv(reader: Any, where: tuple[str, ...], item: str, name: Any, of: str, dims: dict,
         problems: list[Problem]) -> tuple[list, str]:
    """The points of a CSV table ``name`` (relative to the model file), SI, and its path."""
    from express.base.limits import read_input_text

    if not isinstance(name, str) or not name.strip():
        reader.problem(where + ("file",), item, "file must name a CSV file")
        return [], reader.source
    path = Path(name)
    if not path.is_absolute():
        path = Path(reader.source).parent / path
    try:
        text = read_input_text(path, what="the characteristic's table")  # bounded, UTF-8, noted for the cache
    except ModelError as error:
        problems.extend(Problem(reader.source, reader.line(*where, "file"), item, f"{path}: {p.message}")
                        for p in error.problems)
        return [], reader.source
    source = str(path)
    factors: list[float | None] | None = None
    points = []
    for number, raw in enumerate(text.split("\n"), 1):
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        cells = [cell.strip() for cell in line.split(",")]
        if factors is None:  # the header: "velocity [m/s], force [kN]"
            heads = [re.fullmatch(r"([A-Za-z_ ]+?)\s*\[([^\]]*)\]", cell) for cell in cells]
            names = [h.group(1).strip() if h else cell for h, cell in zip(heads, cells, strict=True)]
            if len(cells) != 2 or not all(heads) or names != [of, "force"]:
                problems.append(Problem(source, number, item, f'the header must name the columns and their units, '
                                        f'"{of} [unit], force [unit]", got "{line[:60]}"'))
                return [], source
            factors = [_factor(source, number, item, h.group(2).strip(), dims[n], n, problems)  # type: ignore[union-attr]
                       for h, n in zip(heads, (of, "force"), strict=True)]
            continue
        try:
            values = [float(cell) for cell in cells]
        except ValueError:
            values = []
        if len(values) != 2:
            problems.append(Problem(source, number, item, f'a row must be two numbers, got "{line[:60]}"'))
            continue
        points.append((values[0] * (factors[0] or 1.0), values[1] * (factors[1] or 1.0), number, values[0]))
    if factors is None:
        problems.append(Problem(source, None, item, "the table file has no header and no rows"))
    return points, source
