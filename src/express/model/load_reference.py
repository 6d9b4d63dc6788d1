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
    characteristic; not a friction, series, clearance or velocity element)."""
    if not element.friction_of:
        return []
    item = f"TSD {element.id}"
    found = {e.id: e for e in model.elements}.get(element.friction_of)
    if found is None:
        return [Problem(model.source, element.line, item, f'friction "of" names no element: '
                        f'"{element.friction_of}"{did_you_mean(element.friction_of, [e.id for e in model.elements])}')]
    characteristic = found.characteristic
    wrong = ("a rotational element" if found.rotational else "a friction element" if found.sliding
             else "a series element" if found.series else "a clearance element" if found.clearance
             else "a velocity characteristic (a damper)" if characteristic is not None and characteristic.velocity
             else "an element without stiffness" if characteristic is None and sp.sympify(found.stiffness) == 0
             else "")
    if wrong:
        return [Problem(model.source, element.line, item, f'friction "of" = "{found.id}" is {wrong}: the load '
                        "must be carried by a translational spring or a force-deflection characteristic")]
    return []
