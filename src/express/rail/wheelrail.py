"""Wheel/rail module: linear creep forces and flange contact (paper eqs. 8-11).

For wheelset n with DOFs ``y`` and ``rz = psi`` (``rail.md``)::

    yaw moment     M = -2 b f1 (Gamma (y - yR) / r0 + b psi' / v + b rho)
    lateral force  F = -2 f2 (y' / v - psi)
    flange         F_R = -kR dy

The velocity terms go into C (proportional to 1/v), the displacement terms into K
(the ``-2 f2 psi`` coupling makes K non-symmetric), and the ``yR``, ``dy`` and
``rho`` terms into the input matrix P.  The nonlinear parts (the flange penetration
``dy`` and creep saturation) are computed by :mod:`express.rail.nonlinear` and fed
back through the inputs ``dy`` and the saturation forces.
"""

from __future__ import annotations

import sympy as sp

from express.model.records import Wheelset

__all__ = ["flange_input", "irregularity_input", "wheelset_terms"]


def irregularity_input(wheelset: Wheelset) -> str:
    """Input name of the lateral track irregularity at a wheelset (``W1.yR``)."""
    return f"{wheelset.body}.yR"


def flange_input(wheelset: Wheelset) -> str:
    """Input name of the flange penetration of a wheelset (``W1.dy``)."""
    return f"{wheelset.body}.dy"


def wheelset_terms(wheelset: Wheelset, speed: sp.Expr, curvature_input: str, contact: dict | None = None):
    """Creep and flange terms of one wheelset.

    Parameters
    ----------
    wheelset : Wheelset
        Wheel/rail data of the wheelset.
    speed : sympy.Expr
        Forward speed ``v`` [m/s].
    curvature_input : str
        Name of the curvature input at the wheelset's station.
    contact : dict of str to sympy.Symbol, optional
        The results of the wheelset's ``"profiles"`` node
        (:func:`express.rail.profile_contact.contact_terms`): adds the gravitational
        stiffness and the contact-angle (spin) terms of Wickens' linearised wheelset
        (``docs/contact.md``)::

            K[y, y] += ky,  P[y, yR] += ky,  K[psi, psi] += kpsi,
            K[y, psi] += -2 f2 (g - 1),  C[y, y] += 2 f2 (gy - 1) / v,
            C[y, psi] += 2 f23 / v,  P[y, rho] += -2 f23

    Returns
    -------
    stiffness, damping, forces : list of (str, str, sympy.Expr)
        ``(row DOF, column DOF, value)`` for K and C, ``(DOF, input, value)`` for P,
        signs such that ``M q'' + C q' + K q = P u``.
    """
    y, psi = f"{wheelset.body}.y", f"{wheelset.body}.rz"
    f1, f2, b = wheelset.f1, wheelset.f2, wheelset.b
    gamma, r0 = wheelset.conicity, wheelset.r0
    stiffness = [
        (psi, y, 2 * b * f1 * gamma / r0),
        (y, psi, -2 * f2),
    ]
    damping = [
        (psi, psi, 2 * b**2 * f1 / speed),
        (y, y, 2 * f2 / speed),
    ]
    forces = [
        (psi, irregularity_input(wheelset), 2 * b * f1 * gamma / r0),
        (y, flange_input(wheelset), -wheelset.rail_stiffness),
        (psi, curvature_input, -2 * b**2 * f1),
    ]
    if contact is not None:
        ky, f23 = contact["lateral_stiffness"], contact["f23"]
        stiffness += [(y, y, ky), (psi, psi, contact["yaw_stiffness"]), (y, psi, -2 * f2 * (contact["angle_factor"] - 1))]
        damping += [(y, y, 2 * f2 * (contact["lateral_factor"] - 1) / speed), (y, psi, 2 * f23 / speed)]
        forces += [(y, irregularity_input(wheelset), ky), (y, curvature_input, -2 * f23)]
    return stiffness, damping, forces
