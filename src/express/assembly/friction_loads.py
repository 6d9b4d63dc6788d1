"""The load a friction limit follows (issue 31, item 1): the record of the element whose
force sets a friction element's limit, for the time domain.

A friction element with ``friction = { mu = ..., of = "W" }`` slips at ``mu N`` (a torque
``mu r N``), ``N`` the load the element ``W`` carries: its static force ``N0`` (gravity's,
:func:`express.assembly.gravity.static_preloads`, plus its given ``preload``) and its
dynamic force from its deflection ``r = g . q + h . u`` — ``k r`` for a spring, ``F(r) -
F(0)`` for a force–deflection characteristic (:mod:`express.model.characteristics`).  The
values go into the friction element's :class:`~express.assembly.equations.ElementTerm`
under ``load_*`` keys (:func:`load_values`); :mod:`express.forces.friction` evaluates the
limit from them at every step.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any

import sympy as sp

from express.assembly.lines import line_vector, squared_length
from express.base.diagnostics import ModelError, Problem
from express.model.records import Model

__all__ = ["load_values", "static_loads"]


def static_loads(model: Model, preloads: Mapping[str, sp.Expr]) -> dict[str, sp.Expr]:
    """The static force ``N0`` [N] (tension positive) of every element a friction limit
    follows: gravity's ``preloads`` plus its given ``preload``."""
    named = {e.friction_of for e in model.elements if e.sliding and e.friction_of}
    found = {}
    for element in model.elements:
        if element.id in named:
            found[element.id] = sp.sympify(preloads.get(element.id, 0)) + sp.sympify(element.preload)
    return found


def load_values(model: Model, element, gradient: dict[str, Any], inputs: dict[str, Any],
                loads: Mapping[str, sp.Expr], form: Callable[[Any], sp.Expr]) -> dict[str, sp.Expr]:
    """The ``load_*`` values of the friction ``element`` whose limit follows the element
    ``element.friction_of`` (``{}`` for a constant limit).

    Parameters
    ----------
    gradient, inputs : dict
        The followed element's deflection ``g`` by reduced DOF name and ``h`` by input name
        (exact domain values; a line element's over ``v . du``).
    loads : mapping
        :func:`static_loads`.
    form : callable
        Domain value -> SymPy.

    Returns
    -------
    dict of str to sympy.Expr
        ``load_static`` ``N0`` [N], ``load_stiffness`` ``k`` [N/m], ``load_table`` (1 for a
        characteristic, whose breakpoints are ``load_x<i>``, ``load_f<i>``), and the
        deflection's terms ``load_g:<dof>``, ``load_h:<input>``.

    Raises
    ------
    ModelError
        When the followed element carries no static load (the sense of ``N`` unknown).
    """
    if not element.friction_of:
        return {}
    followed = next(e for e in model.elements if e.id == element.friction_of)  # checked by check_model
    static = sp.sympify(loads.get(followed.id, 0))
    if static == 0:
        raise ModelError([Problem(model.source, element.line, f"TSD {element.id}",
                                  f'friction "of" = "{followed.id}": that element carries no static load (give '
                                  "[gravity] or its preload): its load's sense is unknown")])
    factor = sp.S.One if followed.vector is None else 1 / sp.sqrt(squared_length(line_vector(model, followed)))
    values: dict[str, sp.Expr] = {"load_static": static, "load_stiffness": sp.sympify(followed.stiffness)}
    characteristic = followed.characteristic
    values["load_table"] = sp.Integer(0 if characteristic is None else 1)
    if characteristic is not None:
        for i, (x, f) in enumerate(characteristic.points):
            values[f"load_x{i}"], values[f"load_f{i}"] = sp.sympify(x), sp.sympify(f)
    for dof, value in gradient.items():
        values[f"load_g:{dof}"] = form(value) * factor
    for name, value in inputs.items():
        values[f"load_h:{name}"] = form(value) * factor
    return values
