"""Bushings of a TOML model (issue 31, item 3): ``bushing = {...}`` on an element.

A bushing joins two CPs with a stiffness and a damping per axis of its own frame, three
translations and three rotations::

    [elements.T1_traction]
    from = "CB_rod"
    to = "T1_rod"

    [elements.T1_traction.bushing]
    stiffness = ["kx", "ky", "kz", "krx", "kry", "krz"]
    damping = [0, 0, 0, 0, 0, "crz"]       # optional, zeros by default
    x = [4, 3, 0]                           # its axes (default the bodies')
    y = [-3, 4, 0]

``x`` and ``y`` (vectors of any length, orthogonal for every value of the parameters)
give the frame; ``z = x × y``. Each axis ``e_i`` with a nonzero stiffness or damping
becomes one element: ``<id>_x``, ``<id>_y``, ``<id>_z`` along ``e_i``
(:mod:`express.assembly.lines`, deflection ``e_i . (u_S - u_T)`` at the CPs) and
``<id>_rx``, ``<id>_ry``, ``<id>_rz`` about ``e_i`` (``direction = { about = e_i }``,
deflection ``e_i . (theta_S - theta_T)``). Their sum is the bushing's energy
``1/2 d^T R^T diag(k) R d`` over the relative motion ``d`` of its ends, ``R`` the rows
``e_i / |e_i|``: the usual six-component bushing of multibody codes (SIMPACK's force
element 43, ADAMS' BUSHING, with the rotations small). The bushing is linear; a preload,
a characteristic or friction goes on an element of its own.
"""

from __future__ import annotations

from typing import Any

import sympy as sp

from express.model.records import Axis, Element, Motion

__all__ = ["BUSHING_KEYS", "read_bushing"]

BUSHING_KEYS = ("stiffness", "damping", "x", "y")
#: Keys an element with a bushing cannot have (the bushing says them).
_CLASHES = ("direction", "stiffness", "damping", "series", "gap", "progressive", "friction", "air_spring",
            "characteristic", "preload")
_NAMES = ("x", "y", "z", "rx", "ry", "rz")


def _cross(a, b) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    return (sp.expand(a[1] * b[2] - a[2] * b[1]), sp.expand(a[2] * b[0] - a[0] * b[2]),
            sp.expand(a[0] * b[1] - a[1] * b[0]))


def _six(reader: Any, table: dict, key: str, where: tuple[str, ...], item: str) -> list[sp.Expr]:
    value = table.get(key, [0] * 6)
    if not isinstance(value, list) or len(value) != 6:
        reader.problem(where + (key,), item, f"bushing {key} must be a list of 6 values (along x, y, z, about x, y, z "
                       f"of the bushing's frame), got {value!r}"[:200])
        return [sp.S.Zero] * 6
    return [reader.expression(v, where + (key,), item, f"bushing {key}[{i}]") for i, v in enumerate(value)]


def _axes(reader: Any, table: dict, where: tuple[str, ...], item: str):
    """The frame's three axes (unnormalised), or None for the bodies' own axes."""
    if "x" not in table and "y" not in table:
        return None
    if "x" not in table or "y" not in table:
        reader.problem(where, item, "a bushing's frame needs both its x and y axes (z = x × y)")
        return None
    x = reader.vector(table["x"], where + ("x",), item, "bushing x")
    y = reader.vector(table["y"], where + ("y",), item, "bushing y")
    for name, axis in (("x", x), ("y", y)):
        if all(sp.sympify(c) == 0 for c in axis):
            reader.problem(where + (name,), item, f"the bushing's {name} axis is the zero vector")
            return None
    if sp.simplify(sum((a * b for a, b in zip(x, y, strict=True)), sp.S.Zero)) != 0:
        reader.problem(where, item, f"the bushing's axes x = {list(x)} and y = {list(y)} are not orthogonal "
                       "(for every value of the parameters)")
        return None
    return x, y, _cross(x, y)


def read_bushing(reader: Any, element_id: str, path: tuple[str, ...], item: str, spec: dict) -> list[Element]:
    """The elements of the bushing ``spec["bushing"]`` of element ``element_id`` (module
    docstring); problems go to ``reader`` with the bushing's line."""
    where = path + ("bushing",)
    table = reader.table(spec["bushing"], where, item)
    reader.unknown_keys(table, BUSHING_KEYS, where, item)
    for clash in _CLASHES:
        if clash in spec:
            reader.problem(path + (clash,), item, f'an element with a bushing has no "{clash}": the bushing gives '
                           "its stiffness and damping per axis of its frame (bushing = {stiffness = [...], ...})")
    if "stiffness" not in table and "damping" not in table:
        reader.problem(where, item, "a bushing needs its stiffness or damping (6 values each)")
    stiffness = _six(reader, table, "stiffness", where, item)
    damping = _six(reader, table, "damping", where, item)
    axes = _axes(reader, table, where, item)
    s_end = reader.name(spec.get("from"), path + ("from",), item, "from")
    t_end = reader.name(spec.get("to"), path + ("to",), item, "to")
    label = str(spec.get("label", "")) or f"bushing {element_id}"
    line = reader.line(*where)
    elements = []
    for i, name in enumerate(_NAMES):
        k, c = stiffness[i], damping[i]
        if k == 0 and c == 0:
            continue
        axis = i % 3
        vector = None if axes is None else axes[axis]
        first = axis if vector is None else next(a for a, v in enumerate(vector) if sp.sympify(v) != 0)
        elements.append(Element(f"{element_id}_{name}", k, c, s_end, t_end, Axis(first), f"{label}: {name}", line,
                                motion=Motion.ROTATION if i >= 3 else Motion.TRANSLATION, vector=vector))
    return elements
