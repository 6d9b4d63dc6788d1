"""The model's own vertical wheel/rail contact: the springs that carry each wheel.

A 3-D model whose wheelsets have vertical and roll coordinates carries each wheel on its
rail by a translational element along z between a connection point on the wheelset and
one on a ground (``examples/manchester-s1002.toml``: ``kH``, the linearised Hertz
contact).  The element's deflection is linear in the coordinates and the ground inputs
(:func:`express.assembly.kinematics.point_motion`, the same forms the generator
assembles), so the wheel's vertical load follows the vehicle::

    Q = Q0 - k_z (u_wheel,z - u_rail,z) - c_z (u_wheel,z - u_rail,z)'      (z up: a wheel that rises unloads)

The wheel is the element's end on the wheelset whose offset is to the left (``y > 0``)
or to the right; a wheelset with no such element on a side has none (its loads come
from elsewhere, :mod:`express.rail.load_transfer`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from express.assembly.kinematics import point_motion
from express.base.caches import IdentityCache
from express.model.parameters import expression_value
from express.model.records import ElementKind, Model

__all__ = ["VerticalContact", "vertical_contacts"]


@dataclass(frozen=True)
class VerticalContact:
    """The vertical spring under one wheel.

    Attributes
    ----------
    element : str
        The element's id.
    stiffness : float
        k_z [N/m].
    dofs : numpy.ndarray, shape (n,)
        The deflection ``u_wheel,z - u_rail,z`` over the coordinates [m per unit].
    inputs : numpy.ndarray, shape (m,)
        Its part over the inputs (a driven ground) [m per unit].
    arm : float
        Lateral distance of the wheel's end from the wheelset centre [m].
    damping : float
        c_z [N s/m], the element's damping in parallel (the track's under the wheel).
    """

    element: str
    stiffness: float
    dofs: np.ndarray
    inputs: np.ndarray
    arm: float
    damping: float = 0.0


def _side(model: Model, point_id: str, values: Mapping[str, float]) -> int:
    lateral = expression_value(model.point(point_id).offset[1], values)
    return 0 if lateral > 0 else 1


def vertical_contacts(model: Model, values: Mapping[str, float], wheelsets: Sequence[str],
                      dofs: Sequence[str], inputs: Sequence[str]) -> list[tuple[VerticalContact | None, ...]]:
    """The vertical contact spring of each wheel (left, right) of each wheelset body in
    ``wheelsets``, ``None`` where the model has none; deflections over ``dofs`` and
    ``inputs`` (the vehicle's own order).  Kept for the same model and numbers (a
    simulation asks twice per run); the arrays are read-only."""
    numbers = (tuple(sorted(values.items())), tuple(wheelsets), tuple(dofs), tuple(inputs))
    return list(_FOUND.get_or_make((model,), lambda: _vertical_contacts(model, values, wheelsets, dofs, inputs),
                                   numbers))


#: Springs already found, by model and numbers.
_FOUND: IdentityCache[list[tuple[VerticalContact | None, ...]]] = IdentityCache(16)


def _vertical_contacts(model: Model, values: Mapping[str, float], wheelsets: Sequence[str],
                       dofs: Sequence[str], inputs: Sequence[str]) -> list[tuple[VerticalContact | None, ...]]:
    grounds = {g.id for g in model.grounds}
    found: dict[tuple[str, int], VerticalContact] = {}
    for element in model.elements:
        if element.rotational or element.direction != 2 or element.vector is not None or element.kind is not ElementKind.PARALLEL:
            continue
        hosts = (model.point(element.s_end).host, model.point(element.t_end).host)
        if not (hosts[0] in wheelsets and hosts[1] in grounds) and not (hosts[1] in wheelsets and hosts[0] in grounds):
            continue
        wheel_end, sign = (element.s_end, 1.0) if hosts[0] in wheelsets else (element.t_end, -1.0)
        row, drive = np.zeros(len(dofs)), np.zeros(len(inputs))
        for end, scale in ((element.s_end, sign), (element.t_end, -sign)):
            motion, driven = point_motion(model, end, 2)
            for name, value in motion.items():
                if name in dofs:
                    row[list(dofs).index(name)] += scale * expression_value(value, values)
            for name, value in driven.items():
                if name in inputs:
                    drive[list(inputs).index(name)] += scale * expression_value(value, values)
        key = (model.point(wheel_end).host, _side(model, wheel_end, values))
        arm = abs(expression_value(model.point(wheel_end).offset[1], values))
        row.flags.writeable = drive.flags.writeable = False
        found[key] = VerticalContact(element.id, expression_value(element.stiffness, values), row, drive, arm,
                                     expression_value(element.damping, values))
    return [tuple(found.get((body, side)) for side in (0, 1)) for body in wheelsets]
