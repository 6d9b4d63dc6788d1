"""``[substructures.NAME]`` and ``[instances.ID]`` of the modern model format.

A substructure is written like a small model (its own ``bodies``, ``points``,
``elements``, ``pins``, ``grounds`` tables under ``[substructures.NAME]``) plus the
lists ``parameters`` (formal parameters) and ``connectors`` (points outside it that its
elements attach to).  An instance names the substructure, a ``prefix`` for the ids, a
``station`` (x shift), and the tables ``parameters``, ``connect`` and ``rename``::

    [substructures.bogie]
    parameters = ["arm"]
    connectors = ["seat_L", "seat_R"]

    [substructures.bogie.bodies.T]
    mass = "mt"
    ...

    [instances.front]
    substructure = "bogie"
    prefix = "T1_"
    station = "lT"
    parameters = { arm = "-lLL" }
    connect = { seat_L = "CB_T1L", seat_R = "CB_T1R" }
    rename = { T = "T1" }

The expansion itself is :mod:`express.model.substructures`.  A problem found while
reading a substructure's own item is reported once, naming the item by its full name in
every instance and by its local name: ``TSD T1_FL_pz, T2_FL_pz (FL_pz of substructure
bogie)``, as the expansion's problems name it.
"""

from __future__ import annotations

import re
from dataclasses import replace
from typing import Any

from express.base.diagnostics import Problem
from express.io.toml_items import check_id, read_items
from express.model.substructures import Instance, Items, Substructure, expand, full_name

__all__ = ["read_substructures"]

_SUBSTRUCTURE_KEYS = ("label", "parameters", "connectors", "bodies", "grounds", "points", "elements", "pins")
_INSTANCE_KEYS = ("substructure", "prefix", "station", "parameters", "connect", "rename")


def _names(reader, value: Any, path: tuple[str, ...], item: str, what: str) -> tuple[str, ...]:
    if not isinstance(value, list):
        reader.problem(path, item, f"{what} must be a list of names, got {type(value).__name__}")
        return ()
    return tuple(reader.name(v, path, item, what) for v in value)


def _string_table(reader, value: Any, path: tuple[str, ...], item: str, what: str) -> dict[str, str]:
    table = reader.table(value, path, item)
    return {key: reader.name(v, (*path, key), item, f"{what}.{key}") for key, v in table.items()}


def _named_in_the_model(problems: list[Problem], spans: dict[str, tuple[int, int]], instances: list[Instance]) -> None:
    """Rename, in place, the item (``"TSD FL_pz"``) of each problem found in a
    substructure's own items (``spans``: substructure -> its range of ``problems``) to
    ``"TSD T1_FL_pz, T2_FL_pz (FL_pz of substructure bogie)"``."""
    for name, (start, stop) in spans.items():
        users = [instance for instance in instances if instance.substructure == name]
        for index in range(start, stop):
            kind, _, local = problems[index].item.partition(" ")
            if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", local):
                continue
            names = ", ".join(dict.fromkeys(full_name(instance, {local}, local) for instance in users))
            item = f"{kind} {names} ({local} of substructure {name})" if names else f"{kind} {local} of substructure {name}"
            problems[index] = replace(problems[index], item=item)


def read_substructures(reader, data: dict) -> tuple[Items, list]:
    """Read every substructure and instance of a parsed TOML file and expand them.

    Parameters
    ----------
    reader : express.io.toml_items.TomlReader
        Collects problems with lines.
    data : dict
        The parsed file.

    Returns
    -------
    Items
        The instances' items, in instance order.
    list of Problem
        Problems of the expansion (missing parameters, connectors, ...); problems of
        the file's syntax go to ``reader``.
    """
    substructures: dict[str, Substructure] = {}
    spans: dict[str, tuple[int, int]] = {}  # substructure -> its items' problems in reader.problems
    table = reader.table(data.get("substructures", {}), ("substructures",), "substructures")
    for name, raw in table.items():
        path = ("substructures", name)
        item = f"substructure {name}"
        check_id(reader, name, path, item)
        spec = reader.table(raw, path, item)
        reader.unknown_keys(spec, _SUBSTRUCTURE_KEYS, path, item)
        start = len(reader.problems)
        bodies, grounds, points, elements, pins = read_items(reader, spec, path)
        spans[name] = (start, len(reader.problems))
        substructures[name] = Substructure(
            name,
            parameters=_names(reader, spec.get("parameters", []), (*path, "parameters"), item, "parameters"),
            connectors=_names(reader, spec.get("connectors", []), (*path, "connectors"), item, "connectors"),
            bodies=tuple(bodies), grounds=tuple(grounds), points=tuple(points),
            elements=tuple(elements), pins=tuple(pins),
            label=str(spec.get("label", "")),
            line=reader.line(*path),
        )
    instances = []
    table = reader.table(data.get("instances", {}), ("instances",), "instances")
    for identifier, raw in table.items():
        path = ("instances", identifier)
        item = f"instance {identifier}"
        check_id(reader, identifier, path, item)
        spec = reader.table(raw, path, item)
        reader.unknown_keys(spec, _INSTANCE_KEYS, path, item)
        if "substructure" not in spec:
            reader.problem(path, item, 'missing "substructure"')
        prefix = spec.get("prefix", "")
        if not isinstance(prefix, str) or (prefix and not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", prefix)):
            reader.problem((*path, "prefix"), item, f"prefix must be letters, digits and _, got {prefix!r}")
            prefix = ""
        parameters = reader.table(spec.get("parameters", {}), (*path, "parameters"), item)
        instances.append(Instance(
            identifier,
            reader.name(spec.get("substructure", "?"), (*path, "substructure"), item, "substructure"),
            prefix=prefix,
            station=reader.expression(spec.get("station", 0), (*path, "station"), item, "station"),
            parameters={k: reader.expression(v, (*path, "parameters", k), item, f"parameters.{k}") for k, v in parameters.items()},
            connect=_string_table(reader, spec.get("connect", {}), (*path, "connect"), item, "connect"),
            rename=_string_table(reader, spec.get("rename", {}), (*path, "rename"), item, "rename"),
            line=reader.line(*path),
        ))
    _named_in_the_model(reader.problems, spans, instances)
    return expand(substructures, instances, reader.source)
