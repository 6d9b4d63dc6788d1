"""A model's cross references checked: every problem at once.

This module owns :func:`check_model`: duplicate ids, connection points on unknown bodies
or grounds, elements on unknown connection points, pinned joints and their elements,
the ends and values of rotational, series, friction and clearance elements, and the
bodies the rail data name. The records it checks are :mod:`express.model.records`.
"""

from __future__ import annotations

import math

import sympy as sp

from express.base.diagnostics import Problem
from express.base.expressions import expression_value
from express.model.load_reference import load_reference_problems
from express.model.modal_body import check_flexible
from express.model.records import AXES, Body, Element, ElementKind, Model, Parameter

__all__ = ["check_model"]


def _duplicates(records, kind: str, source: str, problems: list[Problem]) -> None:
    seen: dict[str, int | None] = {}
    for record in records:
        if record.id in seen:
            first = seen[record.id]
            where = f" (first defined on line {first})" if first is not None else ""
            problems.append(Problem(source, record.line, f"{kind} {record.id}", f"duplicate id{where}"))
        else:
            seen[record.id] = record.line


def check_model(model: Model) -> list[Problem]:
    """Every error in the cross references of ``model`` (empty list if none).

    Checks duplicate ids, CPs on unknown bodies or grounds, elements on unknown CPs,
    pins naming unknown CPs or lacking their element, virtual CPs whose body lacks the
    translation along the pin direction, and rail data naming unknown bodies.
    """
    source = model.source
    problems: list[Problem] = []
    _duplicates(model.bodies, "body", source, problems)
    _duplicates(model.grounds, "ground", source, problems)
    _duplicates(model.points, "CP", source, problems)
    _duplicates(model.elements, "TSD", source, problems)
    _duplicates(model.pins, "pin", source, problems)
    body_ids = {body.id for body in model.bodies}
    ground_ids = {ground.id for ground in model.grounds}
    for clash in sorted(body_ids & ground_ids):
        problems.append(Problem(source, None, f"ground {clash}", "id is also used by a body"))
    hosts = {point.id: point.host for point in model.points}
    for point in model.points:
        if point.host not in body_ids and point.host not in ground_ids:
            problems.append(
                Problem(source, point.line, f"CP {point.id}", f'unknown body or ground "{point.host}"')
            )
    for element in model.elements:
        for end_name, end in (("S_End", element.s_end), ("T_End", element.t_end)):
            if end not in hosts:
                problems.append(
                    Problem(source, element.line, f"TSD {element.id}", f'{end_name} "{end}" is not a CP')
                )
        if element.s_end == element.t_end:
            problems.append(
                Problem(source, element.line, f"TSD {element.id}", "S_End and T_End are the same CP")
            )
    bodies = {body.id: body for body in model.bodies}
    _check_element_kinds(model, hosts, bodies, problems)
    _check_pins(model, hosts, bodies, ground_ids, problems)
    _check_rail_references(model, bodies, problems)
    if model.flexible:
        problems.extend(check_flexible(model))
    return problems


def _check_pins(model: Model, hosts: dict[str, str], bodies: dict[str, Body], ground_ids: set[str],
                problems: list[Problem]) -> None:
    """Pins: known CPs, exactly one joining element, a virtual CP on a body with the
    translation along the pin direction."""
    source = model.source
    by_ends: dict[frozenset, list[Element]] = {}
    for element in model.elements:
        by_ends.setdefault(frozenset((element.s_end, element.t_end)), []).append(element)
    for pin in model.pins:
        item = f"pin {pin.id}"
        known = True
        for role, cp in (("virtual", pin.virtual), ("non-virtual", pin.non_virtual)):
            if cp not in hosts:
                problems.append(Problem(source, pin.line, item, f'{role} CP "{cp}" is not a CP'))
                known = False
        if not known:
            continue
        joining = by_ends.get(frozenset((pin.virtual, pin.non_virtual)), [])
        if not joining:
            problems.append(
                Problem(
                    source,
                    pin.line,
                    item,
                    f"no element joins its CPs {pin.virtual} and {pin.non_virtual} "
                    "(the element gives the pin direction)",
                )
            )
            continue
        if len(joining) > 1:
            ids = ", ".join(element.id for element in joining)
            problems.append(Problem(source, pin.line, item, f"several elements join its CPs: {ids}"))
            continue
        virtual_host = hosts[pin.virtual]
        if virtual_host not in bodies and virtual_host not in ground_ids:
            continue  # the CP's unknown host is reported with the CP
        if virtual_host not in bodies:
            problems.append(
                Problem(source, pin.line, item, f"virtual CP {pin.virtual} is on ground {virtual_host}")
            )
            continue
        axis = AXES[joining[0].direction]
        if axis not in bodies[virtual_host].dofs:
            problems.append(
                Problem(
                    source,
                    pin.line,
                    item,
                    f"virtual CP {pin.virtual} is on body {virtual_host}, which has no "
                    f"{axis} translation DOF (the pin direction of element {joining[0].id})",
                )
            )


def _check_rail_references(model: Model, bodies: dict[str, Body], problems: list[Problem]) -> None:
    """Wheelsets and output points name known bodies; a wheelset has the y and rz DOFs
    and is listed once (its weight against its wheel load: :mod:`express.model.parameter_ranges`)."""
    source = model.source
    if model.rail is not None:
        listed: set[str] = set()
        for wheelset in model.rail.wheelsets:
            if wheelset.body in listed:
                problems.append(Problem(source, wheelset.line, f"wheelset {wheelset.body}", "listed twice"))
                continue
            listed.add(wheelset.body)
            if wheelset.body not in bodies:
                problems.append(
                    Problem(source, wheelset.line, f"wheelset {wheelset.body}", "unknown body")
                )
            elif not {"y", "rz"} <= set(bodies[wheelset.body].dofs):
                problems.append(
                    Problem(
                        source,
                        wheelset.line,
                        f"wheelset {wheelset.body}",
                        "a wheelset body needs the y and rz DOFs",
                    )
                )
        for output in model.rail.outputs:
            if output.body not in bodies:
                problems.append(
                    Problem(source, output.line, f"output {output.name}", f'unknown body "{output.body}"')
                )


def _numeric_value(expression, parameters: dict[str, Parameter]) -> float | None:
    """Value of a parameter expression, or None when a name has no value (yet)."""
    try:
        value = expression_value(expression, {name: p.value for name, p in parameters.items()})
    except (KeyError, ValueError):
        return None
    return value if math.isfinite(value) else None


def _check_element_kinds(model: Model, hosts: dict[str, str], bodies: dict[str, Body], problems: list[Problem]) -> None:
    """Rotational, series and clearance elements: ends, values, and no pins on them."""
    pinned = {frozenset((pin.virtual, pin.non_virtual)) for pin in model.pins}
    for element in model.elements:
        item = f"TSD {element.id}"
        if element.rotational:
            axes = [element.axis_name] if element.vector is None else [
                "r" + "xyz"[a] for a, c in enumerate(element.vector) if sp.sympify(c) != 0]
            for end_name, end in (("S_End", element.s_end), ("T_End", element.t_end)):
                body = bodies.get(hosts.get(end, ""))
                if body is None:
                    continue
                for axis in axes:
                    if axis not in body.dofs:
                        problems.append(Problem(
                            model.source, element.line, item,
                            f"rotational element about {axis}: its {end_name} {end} is on body "
                            f"{body.id}, which has no {axis} DOF",
                        ))
        if element.series:
            for what, value in (("stiffness", element.stiffness), ("damping", element.damping)):
                if sp.sympify(value) == 0:
                    problems.append(Problem(
                        model.source, element.line, item,
                        f"a series (Maxwell) element needs a nonzero {what}",
                    ))
        if element.sliding:
            problems += load_reference_problems(model, element)
            for what, value in (("pre-slip stiffness (stiffness)", element.stiffness),
                                ("friction coefficient mu" if element.friction_of else "friction limit", element.friction)):
                number = _numeric_value(value, model.parameters)
                if number is not None and not number > 0:
                    problems.append(Problem(model.source, element.line, item,
                                            f"a friction element needs a positive {what}, got {number:g}"))
        for what, value, _, positive in element.checked:
            number = _numeric_value(value, model.parameters)
            if positive and number is not None and not number > 0:
                problems.append(Problem(model.source, element.line, item, f"{what} must be positive, got {number:g}"))
        if element.clearance:
            gap = _numeric_value(element.gap, model.parameters)
            if gap is not None and not gap >= 0:
                problems.append(Problem(model.source, element.line, item, f"gap must be >= 0, got {gap:g}"))
        elif sp.sympify(element.progressive) != 0:
            problems.append(Problem(
                model.source, element.line, item, "progressive stiffness needs a gap (a clearance element)"
            ))
        if frozenset((element.s_end, element.t_end)) in pinned and (
            element.rotational or element.kind is not ElementKind.PARALLEL or element.vector is not None
        ):
            problems.append(Problem(
                model.source, element.line, item,
                "the element of a pinned joint must be a plain translational element along an axis",
            ))
