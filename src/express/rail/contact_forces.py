"""Wheel/rail forces of a wheelset from contact tables: the normal forces from the
geometry, the Hertz ellipses, Polach's creep forces with spin, compiled.

For a wheelset at lateral displacement ``y`` (relative to the track), yaw ``psi``,
their rates, track curvature ``rho`` and forward speed ``v``, each contact ``s``
(left ``sigma = +1``, right ``sigma = -1``) sits at ``u_s`` (:class:`~express.rail.
contact_tables.RailMap`: ``u = y`` on rigid rails) and has, from the tables, the rolling
radius ``r``, the contact angle ``delta`` in the track plane and ``theta`` to the axle,
the lateral distance ``l`` from the wheelset centre, the Hertz ellipse and Kalker's
coefficients.  Then (``docs/contact.md``, "Nonlinear contact in simulation"):

* wheel rotation: quasi-static pitch balance ``sum r Fx = 0``, from the linear forces
  (``omega / v = sum f11 r (1 - sigma l q) / sum f11 r^2``, ``q = psi' / v + rho``) and
  one Newton step with the secant stiffnesses ``-Fx / xi`` of the first pass;
* creepages in each contact plane: ``xi = 1 - omega r / v - sigma l q``,
  ``eta = (y' / v - psi + r roll' / v) / cos(delta)``,
  ``phi = -sigma (omega / v) sin(theta) + q cos(delta)``;
* normal force from the vertical load ``Q`` of the wheel:
  ``N cos(delta) + sigma T sin(delta) = Q``, ``T`` the lateral creep force; the creep
  forces are nearly proportional to ``N`` (exactly in full slip), so with
  ``kappa = T / N`` of a pass, ``N = Q / (cos(delta) + sigma kappa sin(delta))`` and the
  forces are scaled with ``N``;
* tangential forces: a first pass by Polach's method (:func:`express.rail.creep_law.
  polach`) at ``N = Q / cos(delta)``, a second by the chosen law (Polach or FASTSIM,
  :func:`express.rail.creep_law.fastsim`) at the corrected ``N`` and rotation;
* on the wheelset: ``Y = sum(-sigma N sin(delta) + T cos(delta))`` and
  ``M = sum(-sigma l Fx) + sum(x_s Y_s)``, ``x_s = sigma psi (r tan(theta) - l)`` the
  lead of the contact point of the yawed wheel.

The yaw of the wheelset does not enter the table (the contact geometry is that of the
unyawed wheelset); the vertical load of each wheel is its static load (no load transfer,
as the Manchester benchmark's case A).  Beyond the table (or the rail map), a wall of
the rail's stiffness holds the wheel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from .contact_tables import (
    ANGLE,
    ARM,
    AXLE_ANGLE,
    C11,
    C22,
    C23,
    RADIUS,
    ROLL_SLOPE,
    SEMI_A,
    SEMI_B,
    ContactTables,
    RailMap,
    rail_deflection_map,
)
from .creep_law import fastsim, polach

__all__ = ["LAWS", "OUTPUTS", "WheelsetContact", "quasi_static_forces", "wheelset_contact", "wheelset_forces"]

#: Entries of the output vector of :func:`wheelset_forces`.
OUTPUTS = ("Y", "M", "N_left", "N_right", "Y_left", "Y_right", "Fx_left", "Fx_right", "u_left", "u_right",
           "angle_left", "angle_right", "beyond")
#: Wall stiffness beyond the tables when the rails are rigid [N/m].
_RIGID_WALL = 1e8


@dataclass(frozen=True, eq=False)
class WheelsetContact:
    """Everything the compiled force kernel needs for one wheelset.

    Attributes
    ----------
    tables : ContactTables
    rail_map : RailMap
        Contact positions against the wheelset displacement (elastic rails).
    wheel_load : float
        Vertical load Q of each wheel [N].
    friction : float
        mu [-].
    rail_stiffness : float
        Lateral stiffness of each rail [N/m] (``inf``: rigid).
    """

    tables: ContactTables
    rail_map: RailMap
    wheel_load: float
    friction: float
    rail_stiffness: float

    @property
    def wall(self) -> float:
        """Stiffness [N/m] holding the wheel beyond the tables."""
        return self.rail_stiffness if math.isfinite(self.rail_stiffness) else _RIGID_WALL


def wheelset_contact(tables: ContactTables, wheel_load: float, friction: float,
                     rail_stiffness: float = math.inf) -> WheelsetContact:
    """A :class:`WheelsetContact` with its rail map (:func:`rail_deflection_map`)."""
    if not wheel_load > 0 or not friction > 0:
        raise ValueError("wheel load and friction must be positive")
    return WheelsetContact(tables, rail_deflection_map(tables, wheel_load, rail_stiffness), float(wheel_load),
                           float(friction), float(rail_stiffness))


@njit(cache=True)
def _interpolate(data, start, step, u, side, values):
    """Fields of ``side`` at ``u`` into ``values``; returns u clamped to the table."""
    n = data.shape[2]
    last = start + step * (n - 1)
    clamped = min(max(u, start), last)
    f = (clamped - start) / step
    k = min(max(math.floor(f), 0), n - 2)
    t = f - k
    for i in range(data.shape[0]):
        values[i] = (1.0 - t) * data[i, side, k] + t * data[i, side, k + 1]
    return clamped


@njit(cache=True)
def _map(contact, start, step, y, side):
    """``u`` of ``side`` at ``y`` from the rail map (clamped) and the overshoot."""
    m = contact.shape[1]
    last = start + step * (m - 1)
    clamped = min(max(y, start), last)
    f = (clamped - start) / step
    k = min(max(math.floor(f), 0), m - 2)
    t = f - k
    return (1.0 - t) * contact[side, k] + t * contact[side, k + 1], y - clamped


@njit(cache=True)
def wheelset_forces(data, t_start, t_step, contact, m_start, m_step, wheel_load, friction, shear_modulus, wall,
                    law, y, psi, y_dot, psi_dot, rho, speed, out):
    """Forces of the rails on one wheelset (see the module docstring) into ``out``
    (:data:`OUTPUTS`): lateral force ``Y`` [N] and yaw moment ``M`` [N m] on the
    wheelset, each wheel's normal force, lateral force, longitudinal force, contact
    position ``u``, contact angle, and the overshoot beyond the tables [m]."""
    values = np.empty((2, data.shape[0]))
    u = np.empty(2)
    extra = 0.0
    for side in range(2):
        position, over = _map(contact, m_start, m_step, y, side)
        clamped = _interpolate(data, t_start, t_step, position, side, values[side])
        u[side] = clamped
        over += position - clamped
        if abs(over) > abs(extra):
            extra = over
    q = psi_dot / speed + rho
    roll_rate = 0.5 * (values[0, ROLL_SLOPE] + values[1, ROLL_SLOPE]) * y_dot
    normal = np.empty(2)
    fx = np.zeros(2)
    lateral = np.zeros(2)
    stiffness = np.empty(2)
    # pass 1 (Polach): normal forces Q / cos(delta), wheel rotation from the linear pitch
    # balance; pass 2 (the chosen law) at the corrected normal forces and rotation
    top = 0.0
    bottom = 0.0
    for side in range(2):
        sigma = 1.0 - 2.0 * side
        normal[side] = wheel_load / math.cos(values[side, ANGLE])
        scale = normal[side] ** (1.0 / 3.0)
        f11 = shear_modulus * values[side, SEMI_A] * values[side, SEMI_B] * scale * scale * values[side, C11]
        r = values[side, RADIUS]
        top += f11 * r * (1.0 - sigma * values[side, ARM] * q)
        bottom += f11 * r * r
        stiffness[side] = f11
    rate = top / bottom
    for attempt in range(2):
        residual = 0.0
        slope = 0.0
        for side in range(2):
            sigma = 1.0 - 2.0 * side
            r = values[side, RADIUS]
            delta = values[side, ANGLE]
            scale = normal[side] ** (1.0 / 3.0)
            semi_a = values[side, SEMI_A] * scale
            semi_b = values[side, SEMI_B] * scale
            xi = 1.0 - rate * r - sigma * values[side, ARM] * q
            eta = (y_dot / speed - psi + r * roll_rate / speed) / math.cos(delta)
            phi = -sigma * rate * math.sin(values[side, AXLE_ANGLE]) + q * math.cos(delta)
            if law == 1 and attempt == 1:
                fx[side], lateral[side] = fastsim(normal[side], friction, semi_a, semi_b, shear_modulus,
                                                  values[side, C11], values[side, C22], values[side, C23], xi, eta, phi)
            else:
                fx[side], lateral[side] = polach(normal[side], friction, semi_a, semi_b, shear_modulus,
                                                 values[side, C11], values[side, C22], values[side, C23], xi, eta, phi)
            # secant stiffness of the longitudinal force, for a Newton step of the pitch balance
            k = -fx[side] / xi if abs(xi) > 1e-12 else stiffness[side]
            residual += r * fx[side]
            slope += k * r * r
        for side in range(2):
            # T is nearly proportional to N (exactly so in full slip): with kappa = T / N,
            # N cos(delta) + sigma T sin(delta) = Q gives N; the forces follow it
            sigma = 1.0 - 2.0 * side
            delta = values[side, ANGLE]
            old = normal[side]
            kappa = lateral[side] / old
            normal[side] = wheel_load / max(math.cos(delta) + sigma * kappa * math.sin(delta), 0.05)
            if attempt == 1:
                fx[side] *= normal[side] / old
                lateral[side] *= normal[side] / old
        if slope > 0.0:
            rate -= residual / slope
    total_y = 0.0
    total_m = 0.0
    for side in range(2):
        sigma = 1.0 - 2.0 * side
        delta = values[side, ANGLE]
        arm = values[side, ARM]
        force_y = -sigma * normal[side] * math.sin(delta) + lateral[side] * math.cos(delta)
        lead = sigma * psi * (values[side, RADIUS] * math.tan(values[side, AXLE_ANGLE]) - arm)
        total_y += force_y
        total_m += -sigma * arm * fx[side] + lead * force_y
        out[4 + side] = force_y
        out[2 + side] = normal[side]
        out[6 + side] = fx[side]
        out[8 + side] = u[side]
        out[10 + side] = delta
    out[0] = total_y - wall * extra
    out[1] = total_m
    out[12] = extra
    return out


#: Creep laws of :func:`wheelset_forces` by name.
LAWS = {"polach": 0, "fastsim": 1}


def quasi_static_forces(contact: WheelsetContact, y: float, psi: float = 0.0, y_dot: float = 0.0,
                        psi_dot: float = 0.0, rho: float = 0.0, speed: float = 1.0, law: str = "polach") -> dict[str, float]:
    """:func:`wheelset_forces` of one state, by name (:data:`OUTPUTS`); SI units; ``law``
    ``"polach"`` or ``"fastsim"``."""
    tables, rail_map = contact.tables, contact.rail_map
    out = np.zeros(len(OUTPUTS))
    wheelset_forces(tables.data, tables.start, tables.step, rail_map.contact, rail_map.start, rail_map.step,
                    contact.wheel_load, contact.friction, tables.shear_modulus, contact.wall, LAWS[law],
                    float(y), float(psi), float(y_dot), float(psi_dot), float(rho), float(speed), out)
    return dict(zip(OUTPUTS, out.tolist(), strict=True))
