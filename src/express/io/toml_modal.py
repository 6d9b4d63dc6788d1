"""``[flexible.<body>]``: the modes of a flexible body, read from the model file.

Two sources (``docs/model-format.md``, "Flexible bodies")::

    [flexible.CB]
    damping = 0.02                       # default modal damping ratio of its modes [-]

    [flexible.CB.beam]                   # (a) the analytic free-free beam
    length = "24 m"
    vertical_EI = "3.0e9 N*m^2"
    lateral_EI = "8.0e9 N*m^2"
    torsion_GJ = "1.5e9 N*m^2"
    torsional_inertia = "2500 kg*m"      # rho*Ip per length (default: Ix / length)
    vertical = 2                         # modes kept of each kind
    lateral = 1
    torsion = 1

    [flexible.CB.modes.vb1]              # (b) given modes (e.g. from a FE model)
    kind = "vertical"                    # vertical / lateral / torsion
    frequency = "9 Hz"
    damping = 0.02
    shapes = { C1 = 0.0087, C2 = -0.0041 }   # mass-normalised [1/sqrt(kg)]

    # or file = "coach-modes.csv" (express.io.modal_data)

    [flexible.CB.fe]                     # (c) a FE program's universal file (express.io.uff_modes)
    file = "carbody.unv"
    nodes = { C1 = 1001, C2 = 1002 }     # the FE node at each point the model uses
    axes = ["x", "y", "z"]               # the FE axes along body x, y, z (default)
    modes = { vb1 = 7, to1 = { mode = 9, kind = "torsion" } }   # default: all
    rigid_below = "0.5 Hz"               # without modes: those below are rigid (default)

Every mode becomes parameters (so ``--set``, studies and sensitivities see them):
``<body>_<mode>_w`` its angular frequency [rad/s], ``<body>_<mode>_zeta`` its damping
ratio (unless a parameter name is given) and ``<body>_<mode>_<point>`` its shape value
at each point (the beam: one per station, named after its first point, which keeps the
exact matrices small: ``k*(phi_L + phi_R)`` is ``2*k*phi``).  The beam is a node of the
parameter graph (:func:`express.model.beam_modes.free_free_beam`): its quantities become
parameters ``<body>_<key>`` (``CB_vertical_EI``), and its modes' frequencies and shapes
are its outputs, so ``--set`` of those, of the body's mass or of a point's offset
recomputes them.
"""

from __future__ import annotations

import math
from fractions import Fraction
from pathlib import Path
from typing import Any

import sympy as sp

from express.base.diagnostics import Problem
from express.base.expressions import ExpressionError, expression_value, parse_expression
from express.base.units import Dimension, UnitError, parse_quantity
from express.io.toml_items import TomlReader, check_id, show_value
from express.model.beam_modes import BEAM_DERIVATION, BEAM_NAMES, STATION, free_free_beam
from express.model.modal_body import FlexibleBody, FlexibleMode, ModeKind
from express.model.records import Derivation, Model, Parameter

__all__ = ["read_flexible"]

_BODY_KEYS = ("damping", "beam", "modes", "file", "fe")
_FE_KEYS = ("file", "nodes", "axes", "modes", "rigid_below")
_AXES = ("x", "y", "z", "-x", "-y", "-z")
_BEAM_KEYS = ("length", "vertical_EI", "lateral_EI", "torsion_GJ", "torsional_inertia", "vertical", "lateral", "torsion")
_MODE_KEYS = ("kind", "frequency", "damping", "shapes")
_LENGTH = Dimension(Fraction(0), Fraction(1), Fraction(0))
_BENDING = Dimension(Fraction(1), Fraction(3), Fraction(-2))  # N m^2
_MASS_MOMENT = Dimension(Fraction(1), Fraction(1), Fraction(0))  # kg m (per length)
_FREQUENCY = Dimension(Fraction(0), Fraction(0), Fraction(-1))


class _Modes:
    """The modes and parameters being built for one body."""

    def __init__(self, reader: TomlReader, model: Model, body: str):
        self.reader, self.model, self.body = reader, model, body
        self.parameters: dict[str, Parameter] = {}
        self.modes: list[FlexibleMode] = []

    def parameter(self, name: str, value: float, unit: str, line: int | None,
                  derived_by: str | None = None) -> sp.Symbol:
        """A parameter of the modes (``derived_by``: the beam's node computes it)."""
        if name in self.model.parameters or name in self.parameters:
            self.reader.problems.append(Problem(self.reader.source, line, f"flexible {self.body}",
                                                f"parameter {name} is also given in [parameters]; rename one"))
        self.parameters[name] = Parameter(name, float(value), unit, line, derived_by=derived_by)
        return sp.Symbol(name)

    def add(self, name: str, kind: ModeKind, omega: float, zeta: sp.Expr, shapes: dict[str, float],
            order: int, line: int | None, source: str | None = None, same: dict[str, str] | None = None,
            derived_by: str | None = None) -> None:
        """One mode; ``same`` maps a point to the first point at its station (the beam:
        they share one shape parameter, named after that first point); ``derived_by``:
        the frequency and shapes are outputs of that node (the beam's)."""
        prefix = f"{self.body}_{name}"
        unknown = sorted(set(shapes) - set(_point_positions(self.model, self.body)))
        if unknown:
            self.reader.problems.append(Problem(
                source or self.reader.source, line, f"flexible {self.body} mode {name}",
                f"shape at {', '.join(unknown)}: not a CP or output point of body {self.body}"))
        w = self.parameter(f"{prefix}_w", omega, "", line, derived_by)
        if zeta.is_number:
            zeta = self.parameter(f"{prefix}_zeta", float(zeta), "", line)
        same = same or {}
        symbols: dict[str, sp.Symbol] = {}
        for point in shapes:
            first = same.get(point, point)
            if first not in symbols:
                symbols[first] = self.parameter(f"{prefix}_{first}", shapes[first], "", line, derived_by)
            symbols[point] = symbols[first]
        values = tuple((point, symbols[point]) for point in shapes)
        self.modes.append(FlexibleMode(name, kind, w, zeta, values, order, line, source))


def _number(reader: TomlReader, model: Model, raw: Any, path: tuple[str, ...], item: str, what: str,
            dimension: Dimension) -> float | None:
    """A quantity (``"24 m"``, SI number) or an expression of the model's parameters."""
    if isinstance(raw, bool) or raw is None:
        reader.problem(path, item, f"{what} must be a quantity, got {show_value(raw)}")
        return None
    if isinstance(raw, (int, float)):
        return float(raw)
    if not isinstance(raw, str):
        reader.problem(path, item, f"{what} must be a quantity, got {show_value(raw)}")
        return None
    try:
        return parse_quantity(raw, dimension)[0]
    except UnitError as unit_error:
        try:
            expression = parse_expression(raw)
            return expression_value(expression, model.values())
        except (ExpressionError, KeyError, ValueError):
            reader.problem(path, item, f"{what}: {unit_error}")
            return None


def _point_positions(model: Model, body: str) -> dict[str, tuple[float, float, float]]:
    """Offset (lx, ly, lz) [m] of every CP and output point of ``body`` (values of the model)."""
    values = model.values()
    found = {p.id: p.offset for p in model.points if p.host == body}
    if model.rail is not None:
        found.update({o.name: o.offset for o in model.rail.outputs if o.body == body})
    positions: dict[str, tuple[float, float, float]] = {}
    for name, offset in found.items():
        try:
            lx, ly, lz = (expression_value(v, values) for v in offset)
        except (KeyError, ValueError):
            continue  # an undefined offset is reported with its CP
        positions[name] = (lx, ly, lz)
    return positions


#: The beam's quantities: key, dimension (each a parameter ``<body>_<key>`` when given as a
#: quantity, else the expression of the model's parameters given).
_BEAM_QUANTITIES = (("length", _LENGTH), ("vertical_EI", _BENDING), ("lateral_EI", _BENDING),
                    ("torsion_GJ", _BENDING), ("torsional_inertia", _MASS_MOMENT))
_STIFFNESS = {ModeKind.VERTICAL: "vertical_EI", ModeKind.LATERAL: "lateral_EI", ModeKind.TORSION: "torsion_GJ"}
_SHAPE_DIMENSION = {ModeKind.VERTICAL: Dimension(Fraction(-1, 2), Fraction(0), Fraction(0)),
                    ModeKind.LATERAL: Dimension(Fraction(-1, 2), Fraction(0), Fraction(0)),
                    ModeKind.TORSION: Dimension(Fraction(-1, 2), Fraction(-1), Fraction(0))}


def _beam_quantity(modes: _Modes, spec: dict, path: tuple[str, ...], key: str,
                   dimension: Dimension) -> tuple[float, sp.Expr] | None:
    """Value and expression of one of the beam's quantities: a quantity (``"3e9 N*m^2"``,
    an SI number) becomes the parameter ``<body>_<key>``; an expression of the model's
    parameters is kept as written (so ``--set`` of its names reaches the modes)."""
    reader, model = modes.reader, modes.model
    item, raw, where = f"flexible {modes.body} beam", spec.get(key), path + (key,)
    line = reader.line(*where) or reader.line(*path)
    if isinstance(raw, bool) or not isinstance(raw, (int, float, str)):
        reader.problem(where, item, f"{key} must be a quantity, got {show_value(raw)}")
        return None
    if isinstance(raw, (int, float)):
        return float(raw), modes.parameter(f"{modes.body}_{key}", float(raw), "", line)
    try:
        value, unit = parse_quantity(raw, dimension)
    except UnitError as unit_error:
        try:
            expression = parse_expression(raw)
            return expression_value(expression, model.values()), expression
        except (ExpressionError, KeyError, ValueError):
            reader.problem(where, item, f"{key}: {unit_error}")
            return None
    return value, modes.parameter(f"{modes.body}_{key}", value, unit, line)


def _beam(modes: _Modes, spec: dict, path: tuple[str, ...], zeta: sp.Expr) -> Derivation | None:
    """The beam's modes, and the node of the parameter graph that computes them
    (:func:`express.model.beam_modes.free_free_beam`)."""
    reader, model, body = modes.reader, modes.model, modes.body
    item = f"flexible {body} beam"
    reader.unknown_keys(spec, _BEAM_KEYS, path, item)
    line = reader.line(*path)
    try:
        mass = expression_value(model.body(body).mass, model.values())
        inertia_x = expression_value(model.body(body).inertia[0], model.values())
    except (KeyError, ValueError):
        reader.problem(path, item, "the body's mass and inertia need values")
        return None
    counts = {}
    for key, kind in (("vertical", ModeKind.VERTICAL), ("lateral", ModeKind.LATERAL), ("torsion", ModeKind.TORSION)):
        count = spec.get(key, 0)
        if isinstance(count, bool) or not isinstance(count, int) or not 0 <= count <= 20:
            reader.problem(path + (key,), item, f"{key} must be a number of modes 0...20, got {show_value(count)}")
        elif count:
            counts[kind] = count
    wanted = {"length"} | {_STIFFNESS[kind] for kind in counts}
    if ModeKind.TORSION in counts and "torsional_inertia" in spec:
        wanted.add("torsional_inertia")
    given: dict[str, tuple[float, sp.Expr]] = {}
    for key, dimension in _BEAM_QUANTITIES:
        if key in wanted:
            found = _beam_quantity(modes, spec, path, key, dimension)
            if found is None:
                continue
            if not found[0] > 0:
                reader.problem(path + (key,), item, f"{key} must be positive, got {found[0]:g}")
                continue
            given[key] = found
    if len(given) < len(wanted):
        return None
    length_value, length = given["length"]
    if ModeKind.TORSION in counts and "torsional_inertia" not in given:
        given["torsional_inertia"] = (inertia_x / length_value, model.body(body).inertia[0] / length)
    positions = _point_positions(model, body)
    outside = [n for n, p in positions.items() if abs(p[0]) > length_value / 2 * (1 + 1e-9)]
    if outside:
        reader.problem(path + ("length",), item, f"points {', '.join(outside)} lie beyond the beam's ends")
        return None
    # points at one station (the same expression of lx) share their shape parameters
    stations = _point_stations(model, body)
    first_at: dict[sp.Expr, str] = {}
    same = {name: first_at.setdefault(stations[name], name) for name in positions}
    settings = {kind.value: str(counts.get(kind, 0)) for kind in ModeKind}
    arguments: dict[str, Any] = {key: value for key, (value, _) in given.items()}
    arguments.update({f"{STATION}{first}": positions[first][0] for first in first_at.values()})
    arguments.update(settings)
    values = free_free_beam(mass=mass, **arguments)
    outputs: list[tuple[str, str, str | Dimension | None]] = []
    for kind, count in counts.items():
        for n in range(1, count + 1):
            name = f"{BEAM_NAMES[kind.value]}{n}"
            shapes = {point: values[f"{name}_{same[point]}"] for point in positions}
            modes.add(name, kind, values[f"{name}_w"], zeta, shapes, n, line, same=same, derived_by=item)
            outputs.append((f"{name}_w", f"{body}_{name}_w", None))  # rad/s, a bare number as given modes'
            outputs += [(f"{name}_{first}", f"{body}_{name}_{first}", _SHAPE_DIMENSION[kind]) for first in first_at.values()]
    inputs: list[tuple[str, sp.Expr, str | Dimension]] = [("mass", model.body(body).mass, "mass")]
    inputs += [(key, expression, dict(_BEAM_QUANTITIES)[key]) for key, (_, expression) in given.items()]
    inputs += [(f"{STATION}{first}", expression, "length") for expression, first in first_at.items()]
    return Derivation(BEAM_DERIVATION, item, tuple(inputs), tuple(outputs), line, tuple(settings.items()))


def _point_stations(model: Model, body: str) -> dict[str, sp.Expr]:
    """The expression of the offset ``lx`` of every CP and output point of ``body``."""
    found = {p.id: sp.sympify(p.offset[0]) for p in model.points if p.host == body}
    if model.rail is not None:
        found.update({o.name: sp.sympify(o.offset[0]) for o in model.rail.outputs if o.body == body})
    return found


def _given(modes: _Modes, table: dict, path: tuple[str, ...], zeta: sp.Expr) -> None:
    reader = modes.reader
    counts: dict[ModeKind, int] = {}
    for name, raw in table.items():
        where = path + (name,)
        item = f"flexible {modes.body} mode {name}"
        check_id(reader, name, where, item)
        spec = reader.table(raw, where, item)
        reader.unknown_keys(spec, _MODE_KEYS, where, item)
        try:
            kind = ModeKind(spec.get("kind"))
        except ValueError:
            reader.problem(where + ("kind",), item, f"kind must be vertical, lateral or torsion, got {show_value(spec.get('kind'))}")
            continue
        frequency = _number(reader, modes.model, spec.get("frequency"), where + ("frequency",), item, "frequency", _FREQUENCY)
        if frequency is None:
            continue
        if not frequency > 0:
            reader.problem(where + ("frequency",), item, f"frequency must be positive, got {frequency:g} Hz")
            continue
        damping = reader.expression(spec["damping"], where + ("damping",), item, "damping") if "damping" in spec else zeta
        shapes_raw = reader.table(spec.get("shapes", {}), where + ("shapes",), item)
        shapes = {}
        for point, value in shapes_raw.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                reader.problem(where + ("shapes", point), item, f"shape at {point} must be a number [1/sqrt(kg)], got {show_value(value)}")
                continue
            shapes[point] = float(value)
        counts[kind] = counts.get(kind, 0) + 1
        modes.add(name, kind, 2 * math.pi * frequency, damping, shapes, counts[kind], reader.line(*where))


def _fe(modes: _Modes, table: dict, path: tuple[str, ...], zeta: sp.Expr) -> None:
    """``[flexible.<body>.fe]``: the modes of a universal file (:mod:`express.io.uff_modes`)."""
    from express.io.uff_modes import FEModeChoice, read_uff_modes

    reader = modes.reader
    item = f"flexible {modes.body} fe"
    reader.unknown_keys(table, _FE_KEYS, path, item)
    if not isinstance(table.get("file"), str):
        reader.problem(path + ("file",), item, f"file must be the universal file's name, got {show_value(table.get('file'))}")
        return
    nodes: dict[str, int] = {}
    for point, node in reader.table(table.get("nodes", {}), path + ("nodes",), item).items():
        if isinstance(node, bool) or not isinstance(node, int) or node <= 0:
            reader.problem(path + ("nodes", point), item, f"node of {point} must be a positive FE node number, got {show_value(node)}")
        else:
            nodes[point] = node
    if not nodes and "nodes" not in table:
        reader.problem(path, item, "nodes = { POINT = NODE, ... } names the FE node at each point the model uses")
    axes = table.get("axes", ["x", "y", "z"])
    if not (isinstance(axes, list) and len(axes) == 3 and all(a in _AXES for a in axes)
            and sorted(a.lstrip("-") for a in axes) == ["x", "y", "z"]):
        reader.problem(path + ("axes",), item, f"axes must name the FE axis along body x, y, z, e.g. [\"z\", \"-x\", \"y\"], "
                       f"got {show_value(axes)}")
        return
    choices = None
    if "modes" in table:
        choices = []
        for name, raw in reader.table(table["modes"], path + ("modes",), item).items():
            check_id(reader, name, path + ("modes", name), item)
            spec = raw if isinstance(raw, dict) else {"mode": raw}
            reader.unknown_keys(spec, ("mode", "kind"), path + ("modes", name), item)
            number, kind = spec.get("mode"), spec.get("kind")
            if isinstance(number, bool) or not isinstance(number, int) or kind not in (None, "vertical", "lateral", "torsion"):
                reader.problem(path + ("modes", name), item, "a mode is its FE mode number, or { mode = N, kind = "
                               f"\"vertical\" | \"lateral\" | \"torsion\" }}, got {show_value(raw)}")
                continue
            choices.append(FEModeChoice(name, number, None if kind is None else ModeKind(kind)))
    rigid = _number(reader, modes.model, table.get("rigid_below", "0.5 Hz"), path + ("rigid_below",), item,
                    "rigid_below", _FREQUENCY)
    where = Path(reader.source).parent / table["file"]
    for mode in read_uff_modes(where, nodes, (axes[0], axes[1], axes[2]), choices, rigid or 0.0, reader.problems):
        damping = zeta if mode.zeta is None else parse_expression(repr(mode.zeta))
        modes.add(mode.name, mode.kind, mode.omega, damping, mode.shapes, mode.order, None, str(where))


def read_flexible(reader: TomlReader, table: Any,
                  model: Model) -> tuple[tuple[FlexibleBody, ...], dict[str, Parameter], tuple[Derivation, ...]]:
    """The flexible bodies of ``[flexible]``, the parameters they add and the beams'
    nodes of the parameter graph (problems go to ``reader.problems``).

    Parameters
    ----------
    reader : TomlReader
        The model file's reader.
    table : dict
        The ``[flexible]`` table.
    model : Model
        The model read so far, its parameters resolved (the beam needs values).
    """
    bodies = []
    parameters: dict[str, Parameter] = {}
    nodes: list[Derivation] = []
    known = {body.id for body in model.bodies}
    for body, raw in reader.table(table, ("flexible",), "flexible").items():
        path = ("flexible", body)
        item = f"flexible {body}"
        spec = reader.table(raw, path, item)
        reader.unknown_keys(spec, _BODY_KEYS, path, item)
        if body not in known:
            reader.problem(path, item, f'unknown body "{body}"')
            continue
        zeta = reader.expression(spec.get("damping", 0), path + ("damping",), item, "damping")
        modes = _Modes(reader, model, body)
        if "beam" in spec:
            node = _beam(modes, reader.table(spec["beam"], path + ("beam",), item), path + ("beam",), zeta)
            if node is not None:
                nodes.append(node)
        if "modes" in spec:
            _given(modes, reader.table(spec["modes"], path + ("modes",), item), path + ("modes",), zeta)
        if "file" in spec:
            from express.io.modal_data import read_modal_data

            where = Path(reader.source).parent / str(spec["file"])
            for mode in read_modal_data(where, reader.problems):
                damping = zeta if mode.zeta is None else parse_expression(repr(mode.zeta))
                modes.add(mode.name, mode.kind, mode.omega, damping, mode.shapes, mode.order, mode.line, str(where))
        if "fe" in spec:
            _fe(modes, reader.table(spec["fe"], path + ("fe",), item), path + ("fe",), zeta)
        if not modes.modes and "file" not in spec and "fe" not in spec:  # a file's problems are its own
            reader.problem(path, item, "no modes: give [flexible.NAME.beam], [flexible.NAME.modes.MODE], file or "
                           "[flexible.NAME.fe]")
        kind = ("beam" if "beam" in spec else str(spec["file"]) if "file" in spec
                else str(spec["fe"].get("file")) if isinstance(spec.get("fe"), dict) else "modes")
        bodies.append(FlexibleBody(body, tuple(modes.modes), kind, reader.line(*path)))
        parameters.update(modes.parameters)
    return tuple(bodies), parameters, tuple(nodes)


def flexible_lines(model: Model) -> tuple[list[str], set[str]]:
    """The ``[flexible]`` section of ``model`` for ``express convert`` (every mode written
    by value, whatever its source), and the names of the parameters the section makes
    (left out of ``[parameters]``: reading the section back makes them again)."""
    lines: list[str] = []
    made: set[str] = set()
    values = model.values()
    for flexible in model.flexible:
        for mode in flexible.modes:
            prefix = f"{flexible.body}_{mode.name}"
            made.add(f"{prefix}_w")
            zeta = sp.sympify(mode.zeta)
            if isinstance(zeta, sp.Symbol) and zeta.name == f"{prefix}_zeta":
                made.add(zeta.name)
                damping = repr(values[zeta.name])
            else:
                damping = '"' + sp.sstr(zeta) + '"'
            shapes = []
            for point, value in mode.shapes:
                made.add(str(value))
                shapes.append(f"{point} = {values[str(value)]!r}")
            frequency = values[f"{prefix}_w"] / (2 * math.pi)
            lines += ["", f"[flexible.{flexible.body}.modes.{mode.name}]", f'kind = "{mode.kind.value}"',
                      f'frequency = "{frequency!r} Hz"', f"damping = {damping}", "shapes = { " + ", ".join(shapes) + " }"]
    return lines, made
