"""Curve module: cant deficiency and the curvature terms in the connections (eq. 12).

Every body has a station, the first component of its position.  Its coordinates are
measured in the track frame at that station, and those frames turn along a curve.
A CP at offset ``(lx, ly, lz)`` on a body whose centre sits ``Y`` from the track
centreline, seen in the track frame at the CP's own station, is displaced by
(first order in the curvature ``rho`` at the body's station, ``rail.md``)::

    longitudinal  + rho lx (Y + ly)
    lateral       - rho lx**2 / 2

so an element whose ends lie on bodies at different stations deflects in a curve
even when every coordinate is zero: that is how a bogie turns relative to the car
body and how the steering lever is driven.  Inside a transition the curvature is
taken at the body's station; the error this makes is measured in
``docs/rail.md`` against an exact integration of the track geometry.

The cant-deficiency force on every body with a lateral DOF is
``F_y = -m (v**2 rho - g S / G)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from ..model import Model

__all__ = ["Station", "stations", "curvature_point_inputs", "cant_deficiency_forces"]


@dataclass(frozen=True)
class Station:
    """A station along the vehicle where curvature and cant are sampled.

    Attributes
    ----------
    name : str
        The first body at this station; inputs are ``<name>.rho`` and ``<name>.S``.
    position : sympy.Expr
        Distance ahead of the vehicle origin [m].
    bodies : tuple of str
        Every body at this station.
    """

    name: str
    position: sp.Expr
    bodies: tuple[str, ...]

    @property
    def curvature_input(self) -> str:
        return f"{self.name}.rho"

    @property
    def cant_input(self) -> str:
        return f"{self.name}.S"


def stations(model: Model) -> list[Station]:
    """Group the bodies by station (equal position x), in file order."""
    groups: list[tuple[sp.Expr, list[str]]] = []
    for body in model.bodies:
        position = sp.sympify(body.position[0])
        for existing, members in groups:
            if sp.expand(existing - position) == 0:
                members.append(body.id)
                break
        else:
            groups.append((position, [body.id]))
    return [Station(members[0], position, tuple(members)) for position, members in groups]


def station_of(model: Model) -> dict[str, Station]:
    """Body id -> its station."""
    return {body: station for station in stations(model) for body in station.bodies}


def curvature_point_inputs(model: Model) -> dict[tuple[str, int], dict[str, sp.Expr]]:
    """Curvature terms of every CP on a body: ``(cp, axis) -> {rho input: coefficient}``."""
    by_body = station_of(model)
    bodies = {body.id: body for body in model.bodies}
    terms: dict[tuple[str, int], dict[str, sp.Expr]] = {}
    for point in model.points:
        body = bodies.get(point.host)
        if body is None:
            continue  # grounds do not move with the track
        lx = point.offset[0]
        if lx == 0:
            continue
        lateral_position = body.position[1] + point.offset[1]
        rho = by_body[body.id].curvature_input
        longitudinal = sp.expand(lx * lateral_position)
        if longitudinal != 0:
            terms[(point.id, 0)] = {rho: longitudinal}
        terms[(point.id, 1)] = {rho: -(lx**2) / 2}
    return terms


def cant_deficiency_forces(model: Model, speed: sp.Expr, gravity: sp.Expr, cant_base: sp.Expr):
    """``(DOF, input, coefficient)`` of the cant-deficiency force on every lateral DOF."""
    by_body = station_of(model)
    forces = []
    for body in model.bodies:
        if "y" not in body.dofs or body.mass == 0:
            continue
        station = by_body[body.id]
        dof = f"{body.id}.y"
        forces.append((dof, station.curvature_input, -body.mass * speed**2))
        forces.append((dof, station.cant_input, body.mass * gravity / cant_base))
    return forces
