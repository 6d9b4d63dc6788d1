"""The pinned joints eliminated exactly: ``q = T q_r``.

This module owns the pin constraints solved for their virtual DOFs
(:func:`pin_transformation`, in the generator's exact domain) and the transformation
``T`` from the reduced coordinates (:func:`reduced_coordinates`), which
:mod:`express.assembly.generator` applies to every element's deflection before assembly.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Any

import sympy as sp

from express.assembly.algebra import ExactDomain, needs_fractions
from express.base.diagnostics import ModelError, Problem
from express.model.records import AXES, Element, Model, PinnedJoint

__all__ = ["NeedsFractionsError", "pin_elements", "pin_transformation", "reduced_coordinates"]


class NeedsFractionsError(Exception):
    """Pin elimination divides by a parameter: redo in the fraction field.

    Raised by :func:`pin_transformation` in a polynomial domain; the generator catches
    it and generates again with ``fractions=True``.
    """


def pin_elements(model: Model) -> list[tuple[PinnedJoint, Element]]:
    """The element joining each pin's CPs.

    Parameters
    ----------
    model : Model
        A model validated by :func:`express.model.checks.check_model` (each pin has
        its element).

    Returns
    -------
    list of tuple
        ``(pin, element)`` in pin order.
    """
    by_ends = {frozenset((e.s_end, e.t_end)): e for e in model.elements}
    return [(pin, by_ends[frozenset((pin.virtual, pin.non_virtual))]) for pin in model.pins]


def pin_transformation(model: Model, domain: ExactDomain, gradients: dict[str, dict[str, Any]]):
    """Solve the pin constraints for the virtual DOFs.

    Parameters
    ----------
    model : Model
        Validated model.
    domain : ExactDomain
        Arithmetic domain.
    gradients : dict
        Element id -> ``{dof: coefficient}`` of its deflection.

    Returns
    -------
    virtual : list of str
        Virtual DOFs, in pin order.
    solution : dict
        Virtual DOF -> ``{independent dof: coefficient}`` so that
        ``q_virtual = sum coefficient * q_dof``.

    Raises
    ------
    ModelError
        If two pins share a virtual DOF or the constraint set is singular.
    NeedsFractionsError
        In a polynomial domain, when the elimination divides by a parameter.
    """
    problems = []
    virtual_of: dict[str, str] = {}
    rows: dict[str, dict[str, Any]] = {}
    owner: dict[str, str] = {}
    for pin, element in pin_elements(model):
        body = model.point(pin.virtual).host
        dof = f"{body}.{AXES[element.direction]}"
        if dof in owner:
            problems.append(
                Problem(
                    model.source,
                    pin.line,
                    f"pin {pin.id}",
                    f"pins {owner[dof]} and {pin.id} both take {dof} as their virtual DOF",
                )
            )
            continue
        owner[dof] = pin.id
        virtual_of[pin.id] = dof
        rows[pin.id] = gradients[element.id]
    if problems:
        raise ModelError(problems)
    virtual = list(virtual_of.values())
    virtual_set = set(virtual)

    # connected components: pin p touches the virtual DOFs in its row
    parent = {pin_id: pin_id for pin_id in rows}

    def find(item: str) -> str:
        while parent[item] != item:
            parent[item] = parent[parent[item]]
            item = parent[item]
        return item

    for pin_id, row in rows.items():
        for dof in row:
            if dof in virtual_set:
                parent[find(pin_id)] = find(owner[dof])
    components: dict[str, list[str]] = defaultdict(list)
    for pin_id in rows:
        components[find(pin_id)].append(pin_id)

    solution: dict[str, dict[str, Any]] = {}
    for pins in components.values():
        unknowns = [virtual_of[p] for p in pins]
        if len(pins) == 1:
            row = rows[pins[0]]
            pivot = row.get(unknowns[0], domain.zero)
            if not pivot:
                raise _singular(model, pins, virtual_of)
            if not domain.fractions and not _is_constant(pivot):
                raise NeedsFractionsError
            inverse = domain.one / pivot if domain.fractions else domain.domain.domain.quo(
                domain.domain.domain.one, pivot.LC
            )
            solution[unknowns[0]] = {
                dof: -value * inverse for dof, value in row.items() if dof != unknowns[0]
            }
            continue
        independents = sorted({d for p in pins for d in rows[p] if d not in virtual_set})
        a_vv = sp.Matrix(
            [[domain.to_expr(rows[p].get(u, domain.zero)) for u in unknowns] for p in pins]
        )
        a_vr = sp.Matrix(
            [[domain.to_expr(rows[p].get(d, domain.zero)) for d in independents] for p in pins]
        )
        if sp.cancel(a_vv.det(method="berkowitz")) == 0:
            raise _singular(model, pins, virtual_of)
        x = (-a_vv.LUsolve(a_vr)).applyfunc(sp.cancel)
        if not domain.fractions and needs_fractions(x):
            raise NeedsFractionsError
        for i, unknown in enumerate(unknowns):
            solution[unknown] = {
                dof: domain.from_expr(x[i, j]) for j, dof in enumerate(independents) if x[i, j] != 0
            }
    return virtual, solution


def _is_constant(element) -> bool:
    return element.is_ground


def _singular(model: Model, pins: list[str], virtual_of: dict[str, str]) -> ModelError:
    by_id = {pin.id: pin for pin in model.pins}
    bodies = sorted({dof.split(".")[0] for p in pins for dof in [virtual_of[p]]})
    names = ", ".join(pins)
    dofs = ", ".join(virtual_of[p] for p in pins)
    return ModelError(
        [
            Problem(
                model.source,
                by_id[pins[0]].line,
                f"pin{'s' if len(pins) > 1 else ''} {names}",
                f"the pin constraints do not determine the virtual DOFs {dofs} "
                f"(singular constraint set; bodies {', '.join(bodies)})",
            )
        ]
    )


def reduced_coordinates(model: Model, domain: ExactDomain, full_dofs: list[str], gradients: dict, keep_virtual: bool):
    """The reduced DOFs, the eliminated virtual DOFs and the rows of ``q = T q_r``.

    Parameters
    ----------
    model : Model
        Validated model.
    domain : ExactDomain
        Arithmetic domain.
    full_dofs : list of str
        Every generalized coordinate before the elimination.
    gradients : dict
        Element id -> ``{dof: coefficient}`` of its deflection.
    keep_virtual : bool
        Keep the virtual DOFs as coordinates, placed last (the paper's eq. 6).

    Returns
    -------
    reduced : list of str
        The coordinates ``q_r``.
    virtual : list of str
        The eliminated virtual DOFs (empty when kept).
    t_rows : dict
        DOF -> ``{index in reduced: coefficient}``: the rows of ``T``.

    Raises
    ------
    ModelError
        As :func:`pin_transformation`.
    NeedsFractionsError
        As :func:`pin_transformation`.
    """
    if not model.pins:
        virtual: list[str] = []
        solution: dict[str, dict[str, Any]] = {}
    else:
        virtual, solution = pin_transformation(model, domain, gradients)
    reduced = [dof for dof in full_dofs if dof not in solution]
    if keep_virtual:  # as the paper's eq. (6): virtual DOFs kept, placed last
        reduced += virtual
        virtual, solution = [], {}
    r_index = {dof: i for i, dof in enumerate(reduced)}
    t_rows: dict[str, dict[int, Any]] = {dof: {r_index[dof]: domain.one} for dof in reduced}
    for dof, combination in solution.items():
        t_rows[dof] = {r_index[d]: v for d, v in combination.items()}
    return reduced, virtual, t_rows
