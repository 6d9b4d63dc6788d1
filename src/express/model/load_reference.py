"""A friction limit proportional to another element's load (issue 31, item 1): which
elements may carry that load, checked with the model (``check_model``)."""

from __future__ import annotations

from typing import Any

import sympy as sp

from express.base.diagnostics import Problem
from express.base.names import did_you_mean

__all__ = ["load_reference_problems"]


def load_reference_problems(model: Any, element: Any) -> list[Problem]:
    """A friction limit proportional to another element's load: that element exists and
    carries a load from its deflection (a translational spring or a deflection
    characteristic; not a friction, series, clearance or velocity element); a friction
    pair in a plane: its partner a translational friction element of the same pre-slip
    stiffness, in no other pair."""
    found = _plane_problems(model, element) if element.friction_plane else []
    if not element.friction_of:
        return found
    item = f"TSD {element.id}"
    followed = {e.id: e for e in model.elements}.get(element.friction_of)
    if followed is None:
        return found + [Problem(model.source, element.line, item, f'friction "of" names no element: '
                        f'"{element.friction_of}"{did_you_mean(element.friction_of, [e.id for e in model.elements])}')]
    characteristic = followed.characteristic
    wrong = ("a rotational element" if followed.rotational else "a friction element" if followed.sliding
             else "a series element" if followed.series else "a clearance element" if followed.clearance
             else "a velocity characteristic (a damper)" if characteristic is not None and characteristic.velocity
             else "an element without stiffness" if characteristic is None and sp.sympify(followed.stiffness) == 0
             else "")
    if wrong:
        return found + [Problem(model.source, element.line, item, f'friction "of" = "{followed.id}" is {wrong}: the load '
                        "must be carried by a translational spring or a force-deflection characteristic")]
    return found


def _plane_problems(model: Any, element: Any) -> list[Problem]:
    item = f"TSD {element.id}"
    partner = {e.id: e for e in model.elements}.get(element.friction_plane)
    if partner is None:
        return [Problem(model.source, element.line, item, f'friction "plane" names no element: '
                        f'"{element.friction_plane}"{did_you_mean(element.friction_plane, [e.id for e in model.elements])}')]
    paired = [e.id for e in model.elements if e.friction_plane in (partner.id, element.id) and e.id != element.id]
    wrong = ("itself" if partner.id == element.id else "not a friction element" if not partner.sliding
             else "rotational" if partner.rotational or element.rotational
             else f"in another pair ({', '.join(paired)})" if paired or partner.friction_plane
             else "of another pre-slip stiffness" if sp.simplify(sp.sympify(partner.stiffness) - element.stiffness) != 0
             else "")
    if wrong:
        return [Problem(model.source, element.line, item, f'friction "plane" = "{partner.id}" is {wrong}: a friction '
                        "pair in a plane is two translational friction elements of the same pre-slip stiffness")]
    return []
