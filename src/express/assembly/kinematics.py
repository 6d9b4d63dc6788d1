"""Small-motion kinematics: generalized coordinates and connection-point motion.

A CP at offset ``r = (lx, ly, lz)`` on a body moves by ``u = t + theta x r``
(paper eq. 4 in 3-D, ``conventions.md``)::

    u_x = x + ry*lz - rz*ly
    u_y = y + rz*lx - rx*lz
    u_z = z + rx*ly - ry*lx

DOFs the body does not have are zero.  A CP on a ground moves with the ground's
translation, named as an input ``<ground>.<axis>``.

A rotational element sees the rotation of the body holding each of its CPs about its
axis (``point_rotation``): the CP's position does not matter; a ground's rotation is
the input ``<ground>.r<axis>``.
"""

from __future__ import annotations

import sympy as sp

from express.model.modal_body import modal_coordinates, modal_motion, modal_rotation
from express.model.records import AXES, Model

__all__ = ["end_motion", "generalized_coordinates", "point_motion", "point_rotation"]

# (translation, [(rotation, sign, offset component)]) per axis, from theta x r.
_ROTATION_TERMS = {
    0: (("ry", 1, 2), ("rz", -1, 1)),
    1: (("rz", 1, 0), ("rx", -1, 2)),
    2: (("rx", 1, 1), ("ry", -1, 0)),
}


def generalized_coordinates(model: Model) -> list[str]:
    """All DOF names ``<body>.<dof>``: bodies in file order, DOFs x, y, z, rx, ry, rz, then
    a flexible body's modal coordinates ``<body>.<mode>`` (:mod:`express.model.modal_body`)."""
    if not model.flexible:
        return [name for body in model.bodies for name in body.dof_names()]
    return [name for body in model.bodies for name in body.dof_names() + modal_coordinates(model, body.id)]


def point_motion(model: Model, point_id: str, axis: int) -> tuple[dict[str, sp.Expr], dict[str, sp.Expr]]:
    """Displacement of a CP along ``axis`` as linear forms.

    Parameters
    ----------
    model : Model
        The model holding the CP.
    point_id : str
        CP id.
    axis : int
        0, 1, 2 for x, y, z.

    Returns
    -------
    dofs : dict of str to sympy.Expr
        Coefficient of each generalized coordinate (zero ones omitted).
    inputs : dict of str to sympy.Expr
        Coefficient of each ground input ``<ground>.<axis>`` (for a CP on a ground).

    Examples
    --------
    The lever's upper CP (paper Fig. 5, C1 on B2 at ``(0, 0, lLU)``) moves along x by
    ``B2.x + lLU*B2.ry``:

    >>> from express.io.classic import read_classic
    >>> lever = read_classic("examples/lever.exp")
    >>> point_motion(lever, "C1", 0)
    ({'B2.x': 1, 'B2.ry': lLU}, {})
    """
    point = model.point(point_id)
    try:
        body = model.body(point.host)
    except KeyError:  # a CP on a ground
        return {}, {f"{point.host}.{AXES[axis]}": sp.S.One}
    coefficients: dict[str, sp.Expr] = {}
    if AXES[axis] in body.dofs:
        coefficients[f"{body.id}.{AXES[axis]}"] = sp.S.One
    for rotation, sign, component in _ROTATION_TERMS[axis]:
        lever_arm = point.offset[component]
        if rotation in body.dofs and lever_arm != 0:
            coefficients[f"{body.id}.{rotation}"] = sign * lever_arm
    if model.flexible:  # a flexible body's modes move its points too
        coefficients.update(modal_motion(model, body.id, point.id, point.offset, axis))
    return coefficients, {}


def point_rotation(model: Model, point_id: str, axis: int) -> tuple[dict[str, sp.Expr], dict[str, sp.Expr]]:
    """Rotation about ``axis`` of the body (or ground) holding a CP, as linear forms.

    Returns ``({"<body>.r<axis>": 1}, {})`` for a body that has that rotation DOF,
    ``({}, {})`` for one that has not, and ``({}, {"<ground>.r<axis>": 1})`` for a ground.

    Examples
    --------
    >>> from express.io.classic import read_classic
    >>> point_rotation(read_classic("examples/lever.exp"), "C1", 1)
    ({'B2.ry': 1}, {})
    """
    point = model.point(point_id)
    name = f"r{AXES[axis]}"
    body_ids = {body.id for body in model.bodies}
    if point.host not in body_ids:
        return {}, {f"{point.host}.{name}": sp.S.One}
    rotation: dict[str, sp.Expr] = {}
    if name in model.body(point.host).dofs:
        rotation[f"{point.host}.{name}"] = sp.S.One
    if model.flexible:  # the torsion of a flexible body's section at the CP
        rotation.update(modal_rotation(model, point.host, point.id, axis))
    return rotation, {}


def end_motion(model: Model, point_id: str, axis: int, rotational: bool):
    """:func:`point_rotation` for a rotational element, else :func:`point_motion`."""
    return (point_rotation if rotational else point_motion)(model, point_id, axis)
