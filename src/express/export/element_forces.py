"""The elements' forces as outputs of the linear model (issue 35, item 6).

An element's deflection is ``delta = g . q + h . u`` (:func:`express.rail.build.vehicle_deflections`,
a line element's along its unit vector), and the coordinates' rates over the state ``x``
are ``q' = V x + Vu u + Vr u'`` (:attr:`express.assembly.first_order.StateForm.velocity`).
What the linear analyses see of the element's force is then ::

    F = k delta + c delta' = R x + E u + G u'
    R = k [g, 0] + c g V,     E = k h + c g Vu,     G = c (g Vr + h)

and for a series (Maxwell) element the force through it, ``F = k (delta - s)`` (its
spring; the damper carries the same force), which has no rate term.  A friction element
is its stuck pre-slip spring, a characteristic its tangent (the preload ``F(0)`` that
the static state balances is not part of the linear output), as in ``K`` and ``C``.

``G`` is not zero for a damper whose end an input moves: every damper across stations
in a curve (the curvature's rate) or to a moving ground.  A standard state space has no
input rates, so :mod:`express.export.linear_system` gives such outputs the rates as
further inputs, ``<input>_dot`` (``D`` holds ``G``); its states are unchanged.

An output is named ``force_<element>`` [N; N m for a rotational element], the name the
time runs give the same force.  Refused, with the reason: a clearance element (bump
stop: left out of the linear model), a pinned joint's element (its force is a
reaction, not a function of the state) and an unknown element.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from express.base.diagnostics import ArgumentError
from express.base.expressions import expression_value
from express.numeric.statespace import VehicleModel

__all__ = ["FORCE", "ForceRows", "element_force_rows"]

#: The prefix of an element's force among the outputs: ``force_<element>``.
FORCE = "force_"


@dataclass(frozen=True)
class ForceRows:
    """``F = state @ x + inputs @ u + rates @ u'`` of the named element forces.

    Attributes
    ----------
    names : tuple of str
        ``force_<element>``.
    state : numpy.ndarray, shape (k, N)
        Over the state ``x = [q; q_D']`` [N per m, N per m/s].
    inputs, rates : numpy.ndarray, shape (k, m)
        Over the inputs and their rates.
    """

    names: tuple[str, ...]
    state: np.ndarray
    inputs: np.ndarray
    rates: np.ndarray


def element_force_rows(vehicle: VehicleModel, names: Sequence[str]) -> ForceRows:
    """The rows of the forces ``force_<element>`` of ``vehicle`` (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        Evaluated from its model (:attr:`VehicleModel.model`).
    names : sequence of str
        ``force_<element>`` each.

    Raises
    ------
    ArgumentError
        Naming every output that is no element's force, with the reason.
    """
    from express.rail.build import vehicle_deflections

    model = vehicle.model
    elements = {element.id: element for element in model.elements}
    terms = {term.element: term for term in vehicle_deflections(model, with_rail=vehicle.layout is not None)}
    problems = []
    for name in names:
        element = name[len(FORCE):]
        if not name.startswith(FORCE) or element not in elements:
            problems.append(f"{name!r}: no such element (force_<element>, e.g. "
                            f"{', '.join(FORCE + e for e in list(terms)[:3])})")
        elif elements[element].clearance:
            problems.append(f"{name!r}: a clearance element (bump stop) is left out of the linear model")
        elif element not in terms:
            problems.append(f"{name!r}: the element of a pinned joint carries a reaction, not a force of the state")
    if problems:
        raise ArgumentError("outputs: " + "; ".join(problems))
    rows = [_force_row(vehicle, terms[name[len(FORCE):]], elements[name[len(FORCE):]].series) for name in names]
    size, m = vehicle.form.size, len(vehicle.inputs)
    return ForceRows(tuple(names), *(np.array([row[i] for row in rows]).reshape(len(rows), width)
                                     for i, width in enumerate((size, m, m))))


def _force_row(vehicle: VehicleModel, term, series: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(R, E, G)`` of one element (module docstring)."""
    form, values = vehicle.form, vehicle.values
    k, c = (expression_value(term.values[key], values) for key in ("stiffness", "damping"))
    column = {dof: i for i, dof in enumerate(vehicle.dofs)}
    g, h = np.zeros(vehicle.n), np.zeros(len(vehicle.inputs))
    for dof, value in term.gradient.items():
        if dof in column:
            g[column[dof]] = expression_value(value, values)
        elif series and (k == 0 or c == 0):  # its stroke removed at a limit: no force passes
            return np.zeros(form.size), np.zeros(h.size), np.zeros(h.size)
        # else a locked stroke (infinite damping), s = 0: the spring alone
    for name, value in term.inputs.items():
        h[vehicle.inputs.index(name)] = expression_value(value, values)
    state = np.zeros(form.size)
    state[: vehicle.n] = k * g
    if series:
        return state, k * h, np.zeros(h.size)
    state += c * (g @ form.velocity)
    return state, k * h + c * (g @ form.velocity_input), c * (g @ form.velocity_rate + h)
