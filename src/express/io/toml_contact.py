"""``conicity = { from = "profiles", ... }`` in ``[rail.wheel_rail]`` or
``[rail.wheelset.ID]``: the wheelset's conicity and contact terms from wheel and rail
profiles, a ``"profiles"`` derivation node of the parameter graph
(:mod:`express.rail.profile_contact`, ``docs/model-format.md``)::

    [rail.wheel_rail]
    conicity = { from = "profiles", wheel = "S1002", rail = "60E1", inclination = "1:40",
                 gauge = "1435 mm", flange_back = "1360 mm", amplitude = "3 mm" }

The node's arguments are quantities with units or expressions of parameters; the
profiles are standard names or files (relative to the model file).  Its results become
parameters named after ``name`` (default ``Gamma_e``; ``Gamma_e_<wheelset>`` for one
wheelset's own table).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import sympy as sp

from express.base.units import UnitError, check_dimension, parse_quantity
from express.model.records import Derivation

__all__ = ["PROFILE_INPUTS", "PROFILE_OUTPUTS", "TABLE_INPUTS", "conicity_value"]

#: Arguments of the ``"profiles"`` node: (key, dimension, default); ``None``: the
#: wheelset's own value (r0, wheel load).  The one definition: the rail layer's
#: :data:`express.rail.profile_contact.INPUTS` is this tuple.
PROFILE_INPUTS = (
    ("gauge", "length", 1.435),
    ("flange_back", "length", 1.360),
    ("inclination", "dimensionless", 1.0 / 40.0),
    ("wheel_radius", "length", None),
    ("amplitude", "length", 3e-3),
    ("wheel_load", "force", None),
    ("youngs_modulus", "pressure", 206e9),
    ("poisson", "dimensionless", 0.3),
)
#: Results: (key, parameter name suffix, dimension); :data:`express.rail.profile_contact.OUTPUTS`.
PROFILE_OUTPUTS = (
    ("conicity", "", "dimensionless"),
    ("epsilon", "epsilon", "dimensionless"),
    ("sigma", "sigma", "dimensionless"),
    ("delta0", "delta0", "angle"),
    ("half_distance", "l0", "length"),
    ("radius", "r0", "length"),
    ("f11", "f11", "force"),
    ("f22", "f22", "force"),
    ("f23", "f23", "rotational_stiffness"),
    ("lateral_stiffness", "ky", "stiffness"),
    ("yaw_stiffness", "kpsi", "rotational_stiffness"),
    ("angle_factor", "g", "dimensionless"),
    ("lateral_factor", "gy", "dimensionless"),
)
#: The profiles known by name (``express.rail.profiles.STANDARD_PROFILES`` and the
#: ``UIC60`` alias of 60E1): any other text names a file.
STANDARD_NAMES = frozenset({"S1002", "60E1", "UIC60"})
_KEYS = ("from", "wheel", "rail", "units", "name", "f11", "f22", "f23", "f33", *(key for key, _, _ in PROFILE_INPUTS))
#: Arguments of a ``from = "table"`` node (a contact table file,
#: :mod:`express.io.contact_table_file`): (key, dimension, default); Kalker's
#: coefficients are arguments only where given (else from the table's Hertz ellipse,
#: :mod:`express.rail.table_contact`); ``wheel_load`` defaults to the wheelset's.
TABLE_INPUTS = (
    ("amplitude", "length", 3e-3),
    ("wheel_load", "force", None),
    ("youngs_modulus", "pressure", 206e9),
    ("poisson", "dimensionless", 0.3),
    ("f11", "force", ""),
    ("f22", "force", ""),
    ("f23", "rotational_stiffness", ""),
    ("f33", "spin_coefficient", ""),
)
_TABLE_KEYS = ("from", "file", "name", *(key for key, _, _ in TABLE_INPUTS))
#: Kalker's coefficients a node may give directly (both kinds): the last four of :data:`TABLE_INPUTS`.
COEFFICIENT_INPUTS = TABLE_INPUTS[4:]
_RATIO = re.compile(r"\s*1\s*:\s*(\S+)\s*\Z")


def conicity_value(reader, own: dict, defaults: dict, body: str, nodes: dict[str, Derivation]) -> sp.Expr | None:
    """The conicity of wheelset ``body`` when it comes from profiles (its own table or
    the ``[rail.wheel_rail]`` one): the symbol of the node's conicity, the node added to
    ``nodes`` (one for ``[rail.wheel_rail]``, shared); ``None`` otherwise."""
    path: tuple[str, ...]
    if isinstance(own.get("conicity"), dict):
        spec, path, key, name = own["conicity"], ("rail", "wheelset", body, "conicity"), body, f"Gamma_e_{body}"
        table = {**defaults, **own}
    elif "conicity" not in own and isinstance(defaults.get("conicity"), dict):
        spec, path, key, name = defaults["conicity"], ("rail", "wheel_rail", "conicity"), "wheel_rail", "Gamma_e"
        table = defaults
    else:
        return None
    if key not in nodes:
        nodes[key] = _node(reader, spec, path, name, table)
    return sp.Symbol(nodes[key].output("conicity"))


def _node(reader, spec: dict, path: tuple[str, ...], name: str, table: dict) -> Derivation:
    item = ".".join(path)
    if spec.get("from") == "table":
        return _table_node(reader, spec, path, name, table)
    reader.unknown_keys(spec, _KEYS, path, item)
    if spec.get("from") != "profiles":
        reader.problem((*path, "from"), item, f'from must be "profiles" or "table", got {spec.get("from")!r}')
    settings = []
    for key in ("wheel", "rail"):
        value = spec.get(key)
        if not isinstance(value, str) or not value.strip():
            reader.problem((*path, key), item, f'{key} must name a profile ("S1002", "60E1") or a file')
            value = "?"
        settings.append((key, value))
    settings.append(("base", str(Path(reader.source).parent)))
    units = spec.get("units", "")
    if units not in ("", "mm", "m"):
        reader.problem((*path, "units"), item, f'units must be "mm" or "m", got {units!r}')
        units = ""
    settings.append(("units", units))
    name = reader.name(spec.get("name", name), (*path, "name"), item, "name")
    inputs = []
    for key, dimension, default in PROFILE_INPUTS:
        raw = spec.get(key, default)
        if raw is None:  # the wheelset's own r0 / wheel load
            raw = table.get({"wheel_radius": "r0", "wheel_load": "wheel_load"}[key], 0)
        inputs.append((key, _argument(reader, raw, dimension, (*path, key), item, key), dimension))
    inputs += [(key, _argument(reader, spec[key], dimension, (*path, key), item, key), dimension)
               for key, dimension, _ in COEFFICIENT_INPUTS if key in spec]
    outputs = tuple((key, f"{name}_{suffix}" if suffix else name, dimension) for key, suffix, dimension in PROFILE_OUTPUTS)
    return Derivation("profiles", item, tuple(inputs), outputs, reader.line(*path), tuple(settings))


def _table_node(reader, spec: dict, path: tuple[str, ...], name: str, table: dict) -> Derivation:
    """``conicity = { from = "table", file = "contact.csv", ... }``: a ``"profiles"``
    derivation whose ``table`` setting names the file, read now so that its problems are
    the model's (file and line each)."""
    from express.base.diagnostics import ModelError
    from express.io.contact_table_file import read_contact_table

    item = ".".join(path)
    reader.unknown_keys(spec, _TABLE_KEYS, path, item)
    file = spec.get("file")
    if not isinstance(file, str) or not file.strip():
        reader.problem((*path, "file"), item, "file must name a contact table (CSV, docs/model-format.md)")
        file = "?"
    else:
        where = Path(file) if Path(file).is_absolute() else Path(reader.source).parent / file
        try:
            read_contact_table(where)
        except ModelError as error:
            for problem in error.problems:
                at = f"{problem.file}:{problem.line}" if problem.line else problem.file
                reader.problem((*path, "file"), item, f"{at}: {problem.message}")
    settings = (("table", file), ("base", str(Path(reader.source).parent)))
    name = reader.name(spec.get("name", name), (*path, "name"), item, "name")
    inputs = []
    for key, dimension, default in TABLE_INPUTS:
        raw = spec.get(key, default)
        if raw == "":
            continue  # a coefficient not given
        if raw is None:
            raw = table.get("wheel_load", 0)
        inputs.append((key, _argument(reader, raw, dimension, (*path, key), item, key), dimension))
    outputs = tuple((key, f"{name}_{suffix}" if suffix else name, dimension) for key, suffix, dimension in PROFILE_OUTPUTS)
    return Derivation("profiles", item, tuple(inputs), outputs, reader.line(*path), settings)


def _argument(reader, raw: Any, dimension: str, path: tuple[str, ...], item: str, key: str) -> sp.Expr:
    """A quantity with a unit (``"1435 mm"``), a rail inclination ``"1:40"``, a number
    (SI) or an expression of parameters."""
    if isinstance(raw, str):
        ratio = _RATIO.match(raw)
        if key == "inclination" and ratio:
            tail = ratio.group(1).lower()
            if tail in ("inf", "infinity", "∞"):
                return sp.S.Zero
            try:
                return sp.Integer(1) / sp.nsimplify(float(tail))
            except (ValueError, ZeroDivisionError):
                reader.problem(path, item, f'{key} "{raw}": expected 1:n (1:40, 1:20, 1:inf) or a tangent')
                return sp.S.Zero
        try:
            value, unit = parse_quantity(raw)
        except UnitError:
            return reader.expression(raw, path, item, key)
        if unit:  # a bare number is SI
            try:
                check_dimension(unit, dimension)
            except UnitError as error:
                reader.problem(path, item, f'{key} "{raw}": {error}')
                return sp.S.Zero
        return sp.Float(value)
    return reader.expression(raw, path, item, key)
