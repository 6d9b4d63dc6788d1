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
body and how the steering lever is driven.  Inside a transition, a CP that sits at
another station uses the curvature at both stations (see
:func:`curvature_point_inputs`); the error is measured in ``docs/rail.md`` against
an exact integration of the track geometry.

The cant-deficiency force on every body with a lateral DOF is
``F_y = -m (v**2 rho - g S / G)``.
"""

from __future__ import annotations

import sympy as sp

from express.model.records import Model
from express.rail.layout import Station

__all__ = ["ROTATION", "Station", "cant_deficiency_forces", "curvature_point_inputs", "stations"]


def stations(model: Model) -> list[Station]:
    """Group the bodies by station (equal position x), in file order.

    Grouped through a dictionary keyed by the canonical form of the position
    (:func:`_position_key`): linear in the number of bodies, where comparing every pair
    of positions made a 100-car train cost minutes."""
    groups: dict[frozenset, tuple[sp.Expr, list[str]]] = {}
    for body in model.bodies:
        position = sp.sympify(body.position[0])
        groups.setdefault(_position_key(position), (position, []))[1].append(body.id)
    return [Station(members[0], position, tuple(members)) for position, members in groups.values()]


def _position_key(position: sp.Expr) -> frozenset:
    """Canonical form of a position: its expanded terms with their numerical
    coefficients as floats, so that two positions share a key when ``expand(a - b)``
    vanishes (``lT - a - Lc`` and ``-(Lc + a) + lT``; ``1.5`` and ``3/2``; ``lT`` and
    ``1.0*lT``)."""
    coefficients: dict[sp.Expr, float] = {}
    for term in sp.Add.make_args(sp.expand(position)):
        coefficient, rest = term.as_coeff_Mul()
        coefficients[rest] = coefficients.get(rest, 0.0) + float(coefficient)
    return frozenset((rest, value) for rest, value in coefficients.items() if value != 0.0)


def station_of(model: Model) -> dict[str, Station]:
    """Body id -> its station."""
    return {body: station for station in stations(model) for body in station.bodies}


#: Key offset of a CP's rotations in :func:`curvature_point_inputs`: ``(cp, ROTATION + k)``
#: is its rotation about axis ``k`` (0 x, 1 y, 2 z), ``(cp, k)`` its displacement.
ROTATION = 3


def curvature_point_inputs(model: Model) -> dict[tuple[str, int], dict[str, sp.Expr]]:
    """Curvature terms of every CP on a body: ``(cp, axis) -> {rho input: coefficient}``,
    ``axis`` 0, 1 for the displacements and ``ROTATION + 2`` for the yaw.

    When the CP sits at another station (``s_m + lx`` equals a station ``s_n``, as
    for a car-body CP above a bogie centre), the curvature is taken at both ends, which
    is exact to first order for a linear ramp of curvature (a clothoid)::

        longitudinal  + Y lx (rho_m + rho_n) / 2
        lateral       - lx**2 (rho_m / 3 + rho_n / 6)

    Otherwise the body's own curvature is used (``rail.md``): ``+ rho_m lx Y`` and
    ``- rho_m lx**2 / 2``.  In a steady curve both forms are the same; inside a
    transition the two-station form is the more accurate (``docs/rail.md``).

    The CP's yaw, seen in the track frame at its own station, is the body's less the
    track's turn between the two stations: ``- lx (rho_m + rho_n) / 2`` (exact for a
    clothoid), ``- rho_m lx`` on one station.  So a rotational ``rz`` element between a
    car body's seat above a bogie and the bogie turns in a curve as the pair of
    longitudinal springs it stands for (issue 31: it put no moment into a curve).
    """
    all_stations = stations(model)
    by_body = {body: station for station in all_stations for body in station.bodies}
    by_key = {_position_key(station.position): station for station in all_stations}
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
        own = by_body[body.id]
        there = by_key.get(_position_key(sp.sympify(own.position) + lx))
        longitudinal = sp.expand(lx * lateral_position)
        if there is None or there is own:
            weights = {own.curvature_input: (1, sp.Rational(1, 2))}
        else:
            weights = {
                own.curvature_input: (sp.Rational(1, 2), sp.Rational(1, 3)),
                there.curvature_input: (sp.Rational(1, 2), sp.Rational(1, 6)),
            }
        if longitudinal != 0:
            terms[(point.id, 0)] = {rho: w_long * longitudinal for rho, (w_long, _) in weights.items()}
        terms[(point.id, 1)] = {rho: -w_lat * lx**2 for rho, (_, w_lat) in weights.items()}
        terms[(point.id, ROTATION + 2)] = {rho: -w_long * lx for rho, (w_long, _) in weights.items()}
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
