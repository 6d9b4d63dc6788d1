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

from express.base.diagnostics import ArgumentError
from express.rail.contact_tables import (
    ANGLE,
    ARM,
    C11,
    C22,
    C23,
    COS_ANGLE,
    RADIUS,
    ROLL_SLOPE,
    SECANT_CBRT,
    SEMI_A,
    SEMI_B,
    SIN_ANGLE,
    SIN_AXLE,
    TAN_AXLE,
    ContactTables,
    RailMap,
    rail_deflection_map,
)
from express.rail.creep_law import fastsim, polach

__all__ = ["LAWS", "OUTPUTS", "WORK_COLUMNS", "WheelsetContact", "quasi_static_forces", "wheelset_contact", "wheelset_forces"]

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
        raise ArgumentError("wheel load and friction must be positive")
    key = (id(tables), float(wheel_load), float(rail_stiffness))
    cached = _MAPS.get(key)
    if cached is None or cached[0] is not tables:
        if len(_MAPS) >= 64:
            _MAPS.pop(next(iter(_MAPS)))
        cached = _MAPS[key] = (tables, rail_deflection_map(tables, wheel_load, rail_stiffness))
    return WheelsetContact(tables, cached[1], float(wheel_load), float(friction), float(rail_stiffness))


#: Rail maps already built, by (tables, wheel load, rail stiffness).
_MAPS: dict[tuple, tuple] = {}


@njit(cache=True)
def _interpolate(data, start, step, count, u, side, values):
    """Fields of ``side`` at ``u`` into ``values[:fields]`` (the first ``count`` nodes of
    ``data``, kernel layout (2, n, fields)); returns ``u`` clamped to the table."""
    last = start + step * (count - 1)
    clamped = min(max(u, start), last)
    f = (clamped - start) / step
    k = min(max(math.floor(f), 0), count - 2)
    t = f - k
    row, following = data[side, k], data[side, k + 1]
    for i in range(row.size):
        values[i] = row[i] + t * (following[i] - row[i])
    return clamped


@njit(cache=True)
def _map(contact, start, step, count, y, side):
    """``u`` of ``side`` at ``y`` from the rail map (clamped) and the overshoot."""
    last = start + step * (count - 1)
    clamped = min(max(y, start), last)
    f = (clamped - start) / step
    k = min(max(math.floor(f), 0), count - 2)
    t = f - k
    return (1.0 - t) * contact[side, k] + t * contact[side, k + 1], y - clamped


#: Columns of the work array of :func:`wheelset_forces` after the table's fields.
_NORMAL, _FX, _LATERAL, _F11, _U, _SCALE = range(16, 22)
_COS, _SIN, _SIN_AXLE, _TAN_AXLE = COS_ANGLE, SIN_ANGLE, SIN_AXLE, TAN_AXLE
WORK_COLUMNS = 22


@njit(cache=True)
def wheelset_forces(data, t_start, t_step, t_count, contact, m_start, m_step, m_count, wheel_load, friction,
                    shear_modulus, wall, law, y, psi, y_dot, psi_dot, rho, speed, work, out):
    """Forces of the rails on one wheelset (see the module docstring) into ``out``
    (:data:`OUTPUTS`): lateral force ``Y`` [N] and yaw moment ``M`` [N m] on the
    wheelset, each wheel's normal force, lateral force, longitudinal force, contact
    position ``u``, contact angle, and the overshoot beyond the tables [m].

    ``data`` is a table in the kernel layout (2, >= t_count, fields)
    (:attr:`~express.rail.contact_tables.ContactTables.kernel`), ``contact`` (2, >= m_count)
    a rail map; ``work`` is scratch space of shape (2, :data:`WORK_COLUMNS`); ``law`` 0
    Polach, 1 FASTSIM.
    """
    # size-reason: one numba kernel per wheelset and step, both wheels in one pass (no calls in the hot loop)
    extra = 0.0
    for side in range(2):
        position, over = _map(contact, m_start, m_step, m_count, y, side)
        clamped = _interpolate(data, t_start, t_step, t_count, position, side, work[side])
        work[side, _U] = clamped
        over += position - clamped
        if abs(over) > abs(extra):
            extra = over
    q = psi_dot / speed + rho
    roll_rate = 0.5 * (work[0, ROLL_SLOPE] + work[1, ROLL_SLOPE]) * y_dot
    lateral_slip = y_dot / speed - psi
    # pass 1 (Polach): normal forces Q / cos(delta), wheel rotation from the linear pitch
    # balance; pass 2 (the chosen law) at the corrected normal forces and rotation
    load_cbrt = wheel_load ** (1.0 / 3.0)
    top = 0.0
    bottom = 0.0
    for side in range(2):
        sigma = 1.0 - 2.0 * side
        normal = wheel_load / work[side, _COS]
        work[side, _NORMAL] = normal
        scale = load_cbrt * work[side, SECANT_CBRT]
        work[side, _SCALE] = scale
        f11 = shear_modulus * work[side, SEMI_A] * work[side, SEMI_B] * scale * scale * work[side, C11]
        r = work[side, RADIUS]
        top += f11 * r * (1.0 - sigma * work[side, ARM] * q)
        bottom += f11 * r * r
        work[side, _F11] = f11
    rate = top / bottom
    for attempt in range(2):
        residual = 0.0
        slope = 0.0
        for side in range(2):
            sigma = 1.0 - 2.0 * side
            r = work[side, RADIUS]
            cosine = work[side, _COS]
            normal = work[side, _NORMAL]
            scale = work[side, _SCALE]
            semi_a = work[side, SEMI_A] * scale
            semi_b = work[side, SEMI_B] * scale
            xi = 1.0 - rate * r - sigma * work[side, ARM] * q
            eta = (lateral_slip + r * roll_rate / speed) / cosine
            phi = -sigma * rate * work[side, _SIN_AXLE] + q * cosine
            if law == 1 and attempt == 1:
                fx, fy = fastsim(normal, friction, semi_a, semi_b, shear_modulus,
                                 work[side, C11], work[side, C22], work[side, C23], xi, eta, phi)
            else:
                fx, fy = polach(normal, friction, semi_a, semi_b, shear_modulus,
                                work[side, C11], work[side, C22], work[side, C23], xi, eta, phi)
            work[side, _FX] = fx
            work[side, _LATERAL] = fy
            # secant stiffness of the longitudinal force, for a Newton step of the pitch balance
            k = -fx / xi if abs(xi) > 1e-12 else work[side, _F11]
            residual += r * fx
            slope += k * r * r
        for side in range(2):
            # T is nearly proportional to N (exactly so in full slip): with kappa = T / N,
            # N cos(delta) + sigma T sin(delta) = Q gives N; the forces follow it
            sigma = 1.0 - 2.0 * side
            old = work[side, _NORMAL]
            kappa = work[side, _LATERAL] / old
            new = wheel_load / max(work[side, _COS] + sigma * kappa * work[side, _SIN], 0.05)
            work[side, _NORMAL] = new
            if attempt == 1:
                work[side, _FX] *= new / old
                work[side, _LATERAL] *= new / old
            else:
                work[side, _SCALE] = new ** (1.0 / 3.0)
        if slope > 0.0:
            rate -= residual / slope
    total_y = 0.0
    total_m = 0.0
    for side in range(2):
        sigma = 1.0 - 2.0 * side
        arm = work[side, ARM]
        normal = work[side, _NORMAL]
        force_y = -sigma * normal * work[side, _SIN] + work[side, _LATERAL] * work[side, _COS]
        lead = sigma * psi * (work[side, RADIUS] * work[side, _TAN_AXLE] - arm)
        total_y += force_y
        total_m += -sigma * arm * work[side, _FX] + lead * force_y
        out[4 + side] = force_y
        out[2 + side] = normal
        out[6 + side] = work[side, _FX]
        out[8 + side] = work[side, _U]
        out[10 + side] = work[side, ANGLE]
    out[0] = total_y - wall * extra
    out[1] = total_m
    out[12] = extra


#: Creep laws of :func:`wheelset_forces` by name.
LAWS = {"polach": 0, "fastsim": 1}


def quasi_static_forces(contact: WheelsetContact, y: float, psi: float = 0.0, y_dot: float = 0.0,
                        psi_dot: float = 0.0, rho: float = 0.0, speed: float = 1.0, law: str = "polach") -> dict[str, float]:
    """:func:`wheelset_forces` of one state, by name (:data:`OUTPUTS`); SI units; ``law``
    ``"polach"`` or ``"fastsim"``."""
    tables, rail_map = contact.tables, contact.rail_map
    out = np.zeros(len(OUTPUTS))
    wheelset_forces(tables.kernel, tables.start, tables.step, tables.data.shape[2], rail_map.contact, rail_map.start,
                    rail_map.step, rail_map.contact.shape[1], contact.wheel_load, contact.friction,
                    tables.shear_modulus, contact.wall, LAWS[law], float(y), float(psi), float(y_dot),
                    float(psi_dot), float(rho), float(speed), np.zeros((2, WORK_COLUMNS)), out)
    return dict(zip(OUTPUTS, out.tolist(), strict=True))
