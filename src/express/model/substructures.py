"""Substructures: a reusable sub-model (a bogie with its wheelsets, primary suspension
and points) instantiated several times with a name prefix, a station and a parameter
mapping (``docs/model-format.md``, section Substructures).

A :class:`Substructure` holds bodies, grounds, points, elements and pins with local ids,
the names of its formal parameters and of its *connectors* (points outside it that its
elements attach to, e.g. the car body's air-spring seats).  An :class:`Instance` places
it: every local id ``X`` becomes ``prefix + X`` (or ``rename[X]``), the bodies and the
ground points move by ``station`` along x, every formal parameter is replaced by the
instance's expression and every connector by the model point the instance names.

Examples
--------
>>> import sympy as sp
>>> from express.model.records import Body, ConnectionPoint, Element, Ground
>>> wheelset = Substructure(
...     "axle", parameters=("k",), connectors=("seat",),
...     bodies=(Body("W", sp.Symbol("m"), (0, 0, 0), ("y",)),),
...     points=(ConnectionPoint("box", "W", (0, 0, 0)),),
...     elements=(Element("spring", sp.Symbol("k"), 0, "seat", "box", 1),),
... )
>>> items, problems = instantiate(wheelset, Instance("front", "axle", prefix="F_", station=sp.Symbol("a"),
...                                                  parameters={"k": sp.Symbol("ky1")}, connect={"seat": "S1"}))
>>> [b.id for b in items.bodies], items.bodies[0].position[0], items.elements[0].stiffness, problems
(['F_W'], a, ky1, [])
>>> items.elements[0].s_end, items.elements[0].t_end
('S1', 'F_box')
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import sympy as sp

from express.base.diagnostics import Problem
from express.model.records import Body, ConnectionPoint, Element, Ground, Model, PinnedJoint

__all__ = ["Instance", "Items", "Substructure", "expand", "full_name", "instantiate", "with_instances"]


@dataclass(frozen=True)
class Substructure:
    """A reusable sub-model with local ids.

    Attributes
    ----------
    name : str
    parameters : tuple of str
        Formal parameters: every instance maps each to an expression of the model's
        parameters.  Other names in its values are the model's own parameters.
    connectors : tuple of str
        Point names its elements use that are not its own points: every instance names
        a model point for each.
    bodies, grounds, points, elements, pins : tuples of records
        Its items; a point must be on one of its own bodies or grounds.
    label : str
    line : int or None
    """

    name: str
    parameters: tuple[str, ...] = ()
    connectors: tuple[str, ...] = ()
    bodies: tuple[Body, ...] = ()
    grounds: tuple[Ground, ...] = ()
    points: tuple[ConnectionPoint, ...] = ()
    elements: tuple[Element, ...] = ()
    pins: tuple[PinnedJoint, ...] = ()
    label: str = ""
    line: int | None = None


@dataclass(frozen=True)
class Instance:
    """One placement of a substructure.

    Attributes
    ----------
    id : str
        Instance name (for messages).
    substructure : str
        Name of the substructure.
    prefix : str
        Put before every local id (default ``""``).
    station : sympy.Expr
        Shift along x [m] of its bodies and ground points.
    parameters : dict of str to sympy.Expr
        Formal parameter -> expression of the model's parameters.
    connect : dict of str to str
        Connector -> model point id.
    rename : dict of str to str
        Local id -> id in the model, instead of ``prefix + id``.
    line : int or None
    """

    id: str
    substructure: str
    prefix: str = ""
    station: sp.Expr = sp.S.Zero
    parameters: dict[str, sp.Expr] = field(default_factory=dict)
    connect: dict[str, str] = field(default_factory=dict)
    rename: dict[str, str] = field(default_factory=dict)
    line: int | None = None


@dataclass(frozen=True)
class Items:
    """Model items produced by instances."""

    bodies: tuple[Body, ...] = ()
    grounds: tuple[Ground, ...] = ()
    points: tuple[ConnectionPoint, ...] = ()
    elements: tuple[Element, ...] = ()
    pins: tuple[PinnedJoint, ...] = ()

    def __add__(self, other: Items) -> Items:
        return Items(*(getattr(self, f) + getattr(other, f) for f in ("bodies", "grounds", "points", "elements", "pins")))


def _local_ids(sub: Substructure) -> set[str]:
    return {item.id for group in (sub.bodies, sub.grounds, sub.points, sub.elements, sub.pins) for item in group}


def full_name(instance: Instance, local: set[str], identifier: str) -> str:
    """The model's name for ``identifier`` of the substructure ``instance`` expands: the
    model point a connector connects to, ``rename``'s name or ``prefix + identifier`` for
    the substructure's own items (``local``), else ``identifier`` unchanged."""
    if identifier in instance.connect:
        return instance.connect[identifier]
    if identifier in local:
        return instance.rename.get(identifier, instance.prefix + identifier)
    return identifier


def _check(sub: Substructure, instance: Instance, source: str) -> list[Problem]:
    """Everything wrong with an instance of ``sub`` (and with ``sub`` itself)."""
    item = f"instance {instance.id}"
    problems = []

    def problem(message: str, line: int | None = instance.line, what: str = item) -> None:
        problems.append(Problem(source, line, what, message))

    for name in sub.parameters:
        if name not in instance.parameters:
            problem(f'substructure {sub.name} needs parameter "{name}" (give it in parameters = {{ ... }})')
    for name in instance.parameters:
        if name not in sub.parameters:
            known = ", ".join(sub.parameters) or "none"
            problem(f'substructure {sub.name} has no parameter "{name}" (its parameters: {known})')
    for name in sub.connectors:
        if name not in instance.connect:
            problem(f'substructure {sub.name} needs a model point for connector "{name}" (connect = {{ ... }})')
    for name in instance.connect:
        if name not in sub.connectors:
            known = ", ".join(sub.connectors) or "none"
            problem(f'substructure {sub.name} has no connector "{name}" (its connectors: {known})')
    local = _local_ids(sub)
    for name in instance.rename:
        if name not in local:
            problem(f'rename: substructure {sub.name} has no item "{name}"')
    hosts = {b.id for b in sub.bodies} | {g.id for g in sub.grounds}
    points = {p.id for p in sub.points}

    def named(kind: str, identifier: str) -> str:  # the one full name, and where it comes from
        return f"{kind} {full_name(instance, local, identifier)} ({identifier} of substructure {sub.name})"

    for point in sub.points:
        if point.host not in hosts:
            problem(f'is on "{point.host}", not on one of its substructure\'s own bodies or grounds',
                    point.line, named("CP", point.id))
    for element in sub.elements:
        for end_name, end in (("S_End", element.s_end), ("T_End", element.t_end)):
            if end not in points and end not in sub.connectors:
                problem(f'{end_name} "{end}" is neither one of its substructure\'s points nor a connector',
                        element.line, named("TSD", element.id))
    return problems


def instantiate(sub: Substructure, instance: Instance, source: str = "<substructure>") -> tuple[Items, list[Problem]]:
    """The model items of one instance, and every problem with it.

    Parameters
    ----------
    sub : Substructure
    instance : Instance
    source : str
        File name for the problems.

    Returns
    -------
    items : Items
    problems : list of Problem
        Missing or unknown parameters and connectors, bad renames, points not on the
        substructure's own bodies, element ends that are neither points nor connectors.
    """
    problems = _check(sub, instance, source)
    local = _local_ids(sub)
    substitution = {sp.Symbol(name): sp.sympify(value) for name, value in instance.parameters.items()}
    station = sp.sympify(instance.station)

    def rename(identifier: str) -> str:
        return full_name(instance, local, identifier)

    def value(expression):
        return sp.sympify(expression).xreplace(substitution) if substitution else sp.sympify(expression)

    def vector(values, shift=sp.S.Zero):
        first, *rest = (value(v) for v in values)
        return (first + shift, *rest)

    grounds = {g.id for g in sub.grounds}
    bodies = tuple(
        replace(b, id=rename(b.id), mass=value(b.mass), inertia=vector(b.inertia), position=vector(b.position, station),
                outline=vector(b.outline) if b.outline is not None else None)
        for b in sub.bodies
    )
    points = tuple(
        replace(p, id=rename(p.id), host=rename(p.host), offset=vector(p.offset, station if p.host in grounds else sp.S.Zero))
        for p in sub.points
    )
    def characteristic(found):  # its breakpoints and tangent are expressions of the parameters too
        if found is None:
            return None
        return replace(found, points=tuple((value(x), value(f)) for x, f in found.points), tangent=value(found.tangent),
                       keys=tuple((key, v if isinstance(v, str) else value(v)) for key, v in found.keys))

    elements = tuple(
        replace(
            e, id=rename(e.id), s_end=rename(e.s_end), t_end=rename(e.t_end), stiffness=value(e.stiffness),
            damping=value(e.damping), gap=value(e.gap), progressive=value(e.progressive),
            friction=value(e.friction), friction_of=rename(e.friction_of) if e.friction_of else "",
            friction_plane=rename(e.friction_plane) if e.friction_plane else "", characteristic=characteristic(e.characteristic),
            checked=tuple((what, value(v), dim, positive) for what, v, dim, positive in e.checked),
            vector=tuple(value(c) for c in e.vector) if e.vector is not None else None,
            preload=value(e.preload),
        )
        for e in sub.elements
    )
    pins = tuple(replace(p, id=rename(p.id), virtual=rename(p.virtual), non_virtual=rename(p.non_virtual)) for p in sub.pins)
    ground_items = tuple(replace(g, id=rename(g.id)) for g in sub.grounds)
    return Items(bodies, ground_items, points, elements, pins), problems


def expand(substructures: dict[str, Substructure], instances: list[Instance], source: str = "<model>") -> tuple[Items, list[Problem]]:
    """Items of every instance, in order, and every problem (unknown substructures too)."""
    items, problems = Items(), []
    owners: dict[tuple[str, str], Instance] = {}  # (kind, id) -> the instance that made it
    for instance in instances:
        sub = substructures.get(instance.substructure)
        if sub is None:
            known = ", ".join(sorted(substructures)) or "none"
            problems.append(Problem(source, instance.line, f"instance {instance.id}",
                                    f'unknown substructure "{instance.substructure}" (defined: {known})'))
            continue
        more, found = instantiate(sub, instance, source)
        more, collision = _without_collisions(more, instance, owners, source)
        items, problems = items + more, problems + found + collision
    return items, problems


_KINDS = ("bodies", "grounds", "points", "elements", "pins")


def _without_collisions(items: Items, instance: Instance, owners: dict, source: str) -> tuple[Items, list[Problem]]:
    """The items of ``instance`` whose ids no earlier instance made, and one problem per
    earlier instance it collides with (naming both, the count and a few ids) instead of
    one "duplicate id" per item."""
    clashes: dict[str, list[str]] = {}
    others: dict[str, Instance] = {}
    kept = {}
    for kind in _KINDS:
        mine = []
        for record in getattr(items, kind):
            other = owners.get((kind, record.id))
            if other is not None and other is not instance:
                clashes.setdefault(other.id, []).append(record.id)
                others[other.id] = other
                continue
            owners[(kind, record.id)] = instance
            mine.append(record)
        kept[kind] = tuple(mine)
    problems = []
    for other, ids in clashes.items():
        shown = ", ".join(ids[:3]) + (", ..." if len(ids) > 3 else "")
        same = f" (both have {instance.prefix!r})" if others[other].prefix == instance.prefix else ""
        problems.append(Problem(source, instance.line, f"instance {instance.id}",
                                f"its ids collide with those of instance {other} ({len(ids)} ids: {shown}); "
                                f"give each instance its own prefix{same} or rename"))
    return Items(**kept), problems


def with_instances(model: Model, substructures: dict[str, Substructure] | list[Substructure], instances: list[Instance]) -> Model:
    """``model`` with the items of ``instances`` appended (Python API).

    Raises
    ------
    ModelError
        With every problem of the instances and of the resulting model.
    """
    from express.base.diagnostics import ModelError
    from express.model.checks import check_model

    if not isinstance(substructures, dict):
        substructures = {sub.name: sub for sub in substructures}
    items, problems = expand(substructures, instances, model.source)
    result = replace(
        model,
        bodies=model.bodies + items.bodies,
        grounds=model.grounds + items.grounds,
        points=model.points + items.points,
        elements=model.elements + items.elements,
        pins=model.pins + items.pins,
    )
    problems += check_model(result)
    if problems:
        raise ModelError(problems)
    return result
