"""Wheel/rail forces of a wheelset from contact tables: the normal forces from the
geometry, the Hertz ellipses, Polach's creep forces with spin, compiled.

For a wheelset at lateral displacement ``y`` (relative to the track), yaw ``psi``,
their rates, track curvature ``rho`` and forward speed ``v``, each contact ``s``
(left ``sigma = +1``, right ``sigma = -1``) sits at ``u_s`` (:class:`~express.rail.
contact_tables.RailMap`: ``u = y`` on rigid rails) and has, from the tables, the rolling
radius ``r``, the contact angle ``delta`` in the track plane and ``theta`` to the axle,
the lateral distance ``l`` from the wheelset centre, the Hertz ellipse and Kalker's
coefficients, and the contact's lead ``x_s = psi lead_rate`` ahead of the wheelset
centre (tables with yaw nodes, interpolated in ``psi^2``, give all of these at the
wheelset's yaw, the contact locus of :mod:`express.rail.wheel_locus`; one node, the
simulation's default, the unyawed geometry with the lead to first order).  Then (``docs/contact.md``, "Nonlinear contact in
simulation"):

* creepages in each contact plane: ``xi = 1 - omega r / v - sigma l q``,
  ``eta = (y' / v - psi + r roll' / v + q x_s) / cos(delta)``,
  ``phi = -sigma (omega / v) cos(psi) sin(theta) + q cos(delta)``, ``q = psi' / v + rho``
  (``r`` the contact's depth below the axle);
* normal force from the vertical load ``Q`` of the wheel:
  ``N cos(delta) + sigma T sin(delta) = Q``, ``T`` the lateral creep force; the creep
  forces are nearly proportional to ``N`` (exactly in full slip), so with
  ``kappa = T / N`` of a pass, ``N = Q / (cos(delta) + sigma kappa sin(delta))`` and the
  forces are scaled with ``N``;
* wheel rotation from the quasi-static pitch balance ``sum(r Fx + m T) = 0`` (``m T`` the
  moment of the lateral creep force acting ahead of the wheel's lowest point; the normal
  force passes through the axle): the linear forces' balance
  ``omega / v = sum f11 r (1 - sigma l q) / sum f11 r^2`` starts Newton's method with
  Polach's longitudinal force and its tangent stiffness (at most 3 steps);
* tangential forces: a first pass by Polach's method (:func:`express.rail.creep_law.
  polach`) at ``N = Q / cos(delta)``, the last by the chosen law (Polach, FASTSIM,
  :func:`express.rail.creep_law.fastsim`, or the tables of the exact theory,
  :func:`express.rail.creep_table.tabulated_with_moment`) at the corrected ``N`` and balanced rotation;
* on the wheelset: ``Y = sum(-sigma N sin(delta) + T cos(delta))`` and
  ``M = sum(-sigma l Fx) + sum(x_s Y_s)``;
* per contact, the frictional power per unit rolling distance
  ``Tgamma = |Fx xi + T eta + Mz phi|`` at the balanced rotation (the table law's spin
  moment ``Mz``; FASTSIM and Polach give none) and the patch's area per ``N^(2/3)``,
  ``pi a b`` at 1 N (``docs/wear.md``).

The vertical load of each wheel is an argument: the static load
(:func:`quasi_static_forces`' default, as the Manchester benchmark's case A) or the
march's (:class:`express.forces.contact.WheelLoadModel`).  Beyond the table (or
the rail map), a wall of the rail's stiffness holds the wheel.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from express.base.caches import IdentityCache
from express.base.diagnostics import ArgumentError
from express.base.kernels import kernel
from express.rail.contact_tables import (
    ANGLE,
    ARM,
    C11,
    C22,
    C23,
    COS_ANGLE,
    FIELDS,
    LEAD_RATE,
    RADIUS,
    ROLL,
    ROLL_SLOPE,
    SECANT_CBRT,
    SEMI_A,
    SEMI_B,
    SIN_ANGLE,
    SIN_AXLE,
    ContactTables,
    RailMap,
    rail_deflection_map,
)
from express.rail.creep_law import fastsim, polach_longitudinal, polach_with_slope
from express.rail.creep_table import tabulated_with_moment
from express.rail.options import DEFAULT_CREEP_LAW, CreepLaw
from express.rail.wheel_rise import rail_position, rise_tables, yaw_node

__all__ = [
    "FASTSIM",
    "LAWS",
    "OUTPUTS",
    "POLACH",
    "TABLE",
    "WORK_FIELDS",
    "ContactSet",
    "WheelsetContact",
    "contact_set",
    "patch_area",
    "profile_wheelset_forces",
    "quasi_static_forces",
    "wheelset_contact",
]

#: Entries of the output vector of :func:`profile_wheelset_forces`.
OUTPUTS = ("Y", "M", "N_left", "N_right", "Y_left", "Y_right", "Fx_left", "Fx_right", "u_left", "u_right",
           "angle_left", "angle_right", "beyond", "Q_left", "Q_right", "Mx",
           # energy (issue 37): the creepages and the lateral creep force the law gave, Tgamma, the patch
           "xi_left", "xi_right", "eta_left", "eta_right", "phi_left", "phi_right", "T_left", "T_right",
           "Tgamma_left", "Tgamma_right", "unit_area_left", "unit_area_right", "unit_b_left", "unit_b_right",
           "wheel_u_left", "wheel_u_right")
#: Creep laws of :func:`profile_wheelset_forces`, by named constant and by name.
POLACH, FASTSIM, TABLE = 0, 1, 2
LAWS = {"polach": POLACH, "fastsim": FASTSIM, "table": TABLE}
#: Wall stiffness beyond the tables when the rails are rigid [N/m].
_RIGID_WALL = 1e8


def _sides(name: str) -> tuple[int, int]:
    """Places of ``name_left``, ``name_right`` in :data:`OUTPUTS`."""
    return OUTPUTS.index(f"{name}_left"), OUTPUTS.index(f"{name}_right")


_OUT_Y, _OUT_M, _OUT_BEYOND, _OUT_ROLL = (OUTPUTS.index(name) for name in ("Y", "M", "beyond", "Mx"))
_OUT_NORMAL, _OUT_LATERAL, _OUT_FX, _OUT_U, _OUT_ANGLE, _OUT_LOAD = (
    _sides(name) for name in ("N", "Y", "Fx", "u", "angle", "Q"))
_OUT_XI, _OUT_ETA, _OUT_PHI, _OUT_CREEP_Y, _OUT_TGAMMA, _OUT_AREA, _OUT_SEMI_B, _OUT_WHEEL_U = (
    _sides(name) for name in ("xi", "eta", "phi", "T", "Tgamma", "unit_area", "unit_b", "wheel_u"))
#: Newton iterations (at most) of the wheel's rotation on the pitch balance.
_NEWTON = 3
#: Newton on the pitch balance stops after a step below this (after one on the corrected
#: normal forces) [-]: the rotation converged to rounding.
_EXIT = 1e-12
#: Smallest wheel load the contact carries [N]: a lifted wheel (Q <= 0) transmits no
#: force; this keeps the ellipse's scale finite.
_LIFTED = 1.0

#: Columns of the work array of :func:`profile_wheelset_forces`: the table's fields, then the
#: quantities of each contact the kernel computes.
WORK_FIELDS = FIELDS + ("normal", "fx", "lateral", "stiffness", "u", "scale", "eta", "pitch_arm", "spin_moment")
_NORMAL, _FX, _LATERAL, _F11, _U, _SCALE, _ETA, _PITCH_ARM, _MZ = (WORK_FIELDS.index(name)
                                                                  for name in WORK_FIELDS[len(FIELDS):])


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
    rail_map = _MAPS.get_or_make((tables,), lambda: rail_deflection_map(tables, wheel_load, rail_stiffness),
                                 (float(wheel_load), float(rail_stiffness)))
    return WheelsetContact(tables, rail_map, float(wheel_load), float(friction), float(rail_stiffness))


#: Rail maps already built, by (tables, wheel load, rail stiffness).
_MAPS: IdentityCache[Any] = IdentityCache(64)


class ContactSet(NamedTuple):
    """The contacts of ``n`` wheelsets stacked for the compiled kernels (numba compiles
    a NamedTuple of arrays); wheelset ``j`` is row ``j`` of every array.

    Attributes
    ----------
    tables : numpy.ndarray, shape (n, yaw nodes, 2, rows, len(FIELDS))
        Contact tables in the kernel layout (:attr:`~express.rail.contact_tables.
        ContactTables.kernel`), padded to the longest.
    yaw_count : numpy.ndarray of int, shape (n,)
        Yaw nodes of each table (``|psi| = YAW_STEP k``).
    table_start, table_step : numpy.ndarray, shape (n,)
        The tables' grids [m].
    table_count : numpy.ndarray of int, shape (n,)
        Nodes of each table.
    rail_maps : numpy.ndarray, shape (n, yaw nodes, 2, nodes)
        Contact positions ``u`` over the wheelset displacement (:class:`~express.rail.
        contact_tables.RailMap`) [m], padded.
    map_start, map_step : numpy.ndarray, shape (n,)
        The maps' grids [m].
    map_count : numpy.ndarray of int, shape (n,)
    wheel_load, friction, shear_modulus, wall : numpy.ndarray, shape (n,)
        Static wheel load [N], mu [-], G [Pa], stiffness beyond the tables [N/m].
    centred_arm : numpy.ndarray, shape (n, 2)
        ``arm`` of each side of the centred wheelset without yaw [m] (the origin of the
        output ``u``).
    rise : numpy.ndarray, shape (n, yaw nodes, 2, rows)
        How far each wheel must rise to stay on its rail as it moves across it, from the
        centred wheelset, on the tables' grid [m] (:func:`express.rail.wheel_rise.contact_rise`).
    lever : numpy.ndarray, shape like ``rise``
        ``l - d tan(delta)`` (``d`` the contact's depth below the centre), where the
        contact normal meets the axle, from the wheelset centre [m]: the lever of the
        wheel's load about the centre (:func:`express.rail.wheel_rise.contact_rise`).
    law : int
        :data:`POLACH` or :data:`FASTSIM`.
    """

    tables: np.ndarray
    table_start: np.ndarray
    table_step: np.ndarray
    table_count: np.ndarray
    yaw_count: np.ndarray
    rail_maps: np.ndarray
    map_start: np.ndarray
    map_step: np.ndarray
    map_count: np.ndarray
    wheel_load: np.ndarray
    friction: np.ndarray
    shear_modulus: np.ndarray
    wall: np.ndarray
    centred_arm: np.ndarray
    rise: np.ndarray
    lever: np.ndarray
    law: int


def contact_set(contacts: list[WheelsetContact], law: CreepLaw = DEFAULT_CREEP_LAW) -> ContactSet:
    """The contacts of the wheelsets stacked for the compiled kernels."""
    if law not in LAWS:
        raise ArgumentError(f"creep law {law!r}: use one of {', '.join(LAWS)}")
    count = len(contacts)
    t_len = max(c.tables.data.shape[2] for c in contacts)
    m_len = max(c.rail_map.contact.shape[1] for c in contacts)
    yaws = max(len(c.tables.nodes) for c in contacts)
    tables = np.zeros((count, yaws, 2, t_len, len(FIELDS)))
    maps = np.zeros((count, yaws, 2, m_len))
    for j, contact in enumerate(contacts):
        nodes = len(contact.tables.nodes)
        tables[j, :nodes, :, : contact.tables.data.shape[2]] = contact.tables.kernel
        maps[j, :nodes, :, : contact.rail_map.contact.shape[1]] = contact.rail_map.nodes

    def each(value) -> np.ndarray:
        return np.array([value(c) for c in contacts], dtype=float)

    return ContactSet(
        tables, each(lambda c: c.tables.start), each(lambda c: c.tables.step),
        np.array([c.tables.data.shape[2] for c in contacts], dtype=np.int64),
        np.array([len(c.tables.nodes) for c in contacts], dtype=np.int64), maps, each(lambda c: c.rail_map.start), each(lambda c: c.rail_map.step),
        np.array([c.rail_map.contact.shape[1] for c in contacts], dtype=np.int64),
        each(lambda c: c.wheel_load), each(lambda c: c.friction), each(lambda c: c.tables.shear_modulus),
        each(lambda c: c.wall),
        np.array([[_centred_arm(tables[j], c.tables.start, c.tables.step, side) for side in range(2)]
                  for j, c in enumerate(contacts)], dtype=float),
        *rise_tables(tables, [c.tables for c in contacts]), LAWS[law],
    )


@kernel
def _interpolate(data, j, start, step, count, node, weight, u, side, work):
    """Fields of ``side`` of wheelset ``j`` at ``u`` into ``work[side, :fields]`` (the first
    ``count`` nodes of ``data``, :attr:`ContactSet.tables`), between yaw nodes ``node``
    and ``node + 1`` with ``weight``; returns ``u`` clamped to the table.  Indexed in
    place: row views handed to compiled calls cost more than the interpolation."""
    last = start + step * (count - 1)
    clamped = min(max(u, start), last)
    f = (clamped - start) / step
    k = min(max(math.floor(f), 0), count - 2)
    t = f - k
    for i in range(data.shape[4]):
        value = data[j, node, side, k, i]
        work[side, i] = value + t * (data[j, node, side, k + 1, i] - value)
    if weight > 0.0:
        for i in range(data.shape[4]):
            value = data[j, node + 1, side, k, i]
            work[side, i] += weight * (value + t * (data[j, node + 1, side, k + 1, i] - value) - work[side, i])
    return clamped


@kernel
def _centred_arm(data, start, step, side):
    """``arm`` of ``side`` of the centred wheelset without yaw (``u = 0``, kernel layout)."""
    f = -start / step
    k = math.floor(f)
    t = f - k
    return (1.0 - t) * data[0, side, k, ARM] + t * data[0, side, k + 1, ARM]


@kernel
def profile_wheelset_forces(contacts, j, load_left, load_right, y, psi, y_dot, psi_dot, rho, speed, work, out):
    """Forces of the rails on wheelset ``j`` of ``contacts`` (see the module docstring)
    into ``out`` (:data:`OUTPUTS`): lateral force ``Y`` [N] and yaw moment ``M`` [N m] on
    the wheelset, each wheel's normal force, lateral force, longitudinal force, contact
    position ``u`` on the rail (lateral, from the centred wheelset's contact point, +y left;
    the rail's own deflection not included), contact angle, the overshoot beyond the tables [m], its vertical
    load ``Q``, and the roll moment ``Mx`` [N m] of the rails' forces about the wheelset
    centre, ``sum(sigma l Q + d Y_wheel)``, ``d = r - sigma l phi_g`` the contact's depth below the
    centre in the track plane (roll positive lifting the left wheel); then
    each contact's creepages ``xi``, ``eta``, ``phi`` [-, -, 1/m] at the balanced rotation,
    its lateral creep force ``T`` in the contact plane [N], the frictional power per unit
    rolling distance ``Tgamma = |Fx xi + T eta + Mz phi|`` [N] (``Mz`` of the table law only) and the Hertz patch's area per
    ``N^(2/3)`` [m^2 / N^(2/3)] (:func:`_energy`; :func:`patch_area` gives the area), its
    lateral semi-axis per ``N^(1/3)`` [m / N^(1/3)], and the contact's position on the
    wheel profile from the centred wheelset's contact [m], positive toward the field side.

    ``contacts`` is a :class:`ContactSet`; ``load_left``, ``load_right`` [N] the vertical
    wheel loads Q (``contacts.wheel_load[j]`` each for the static ones; a wheel with
    ``Q <= 0`` is lifted and carries no force); ``y`` [m] the wheelset's displacement from the
    track, ``psi`` [rad] its yaw, ``y_dot`` [m/s], ``psi_dot`` [rad/s] their rates, ``rho``
    [1/m] the track curvature, ``speed`` [m/s]; ``work`` is scratch space of shape
    (2, len(:data:`WORK_FIELDS`)).
    """
    # size-reason: one numba kernel per wheelset and step, both wheels in one pass (no calls in the hot loop)
    t_start, t_step, t_count = contacts.table_start[j], contacts.table_step[j], contacts.table_count[j]
    friction, shear_modulus = contacts.friction[j], contacts.shear_modulus[j]
    lifted_left, lifted_right = max(load_left, _LIFTED), max(load_right, _LIFTED)
    node, weight = yaw_node(psi, contacts.yaw_count[j])
    extra = 0.0
    for side in range(2):
        position, over = rail_position(contacts.rail_maps, j, contacts.map_start[j], contacts.map_step[j],
                                       contacts.map_count[j], node, weight, y, side)
        clamped = _interpolate(contacts.tables, j, t_start, t_step, t_count, node, weight, position, side, work)
        work[side, _U] = clamped
        over += position - clamped
        if abs(over) > abs(extra):
            extra = over
    q = psi_dot / speed + rho
    roll_rate = 0.5 * (work[0, ROLL_SLOPE] + work[1, ROLL_SLOPE]) * y_dot
    lateral_slip = y_dot / speed - psi
    # pass 1 (Polach): normal forces Q / cos(delta), wheel rotation from the linear pitch
    # balance; the rotation balanced by Newton's method at the corrected normal forces;
    # pass 2 (the chosen law) at that rotation
    top = 0.0
    bottom = 0.0
    for side in range(2):
        sigma = 1.0 - 2.0 * side
        load = lifted_left if side == 0 else lifted_right
        normal = load / work[side, COS_ANGLE]
        work[side, _NORMAL] = normal
        scale = load ** (1.0 / 3.0) * work[side, SECANT_CBRT]
        work[side, _SCALE] = scale
        f11 = shear_modulus * work[side, SEMI_A] * work[side, SEMI_B] * scale * scale * work[side, C11]
        r = work[side, RADIUS]
        top += f11 * r * (1.0 - sigma * work[side, ARM] * q)
        bottom += f11 * r * r
        work[side, _F11] = f11
        # constant over the passes and Newton's steps: the lateral creepage, the pitch arm
        work[side, _ETA] = (lateral_slip + r * roll_rate / speed + q * psi * work[side, LEAD_RATE]) / work[side, COS_ANGLE]
        work[side, _PITCH_ARM] = _lateral_pitch_arm(sigma, psi, r, work, side)
    rate = top / bottom
    loads = (lifted_left, lifted_right)
    _creep_pass(work, POLACH, rate, q, friction, shear_modulus, loads, False)
    rate = _balanced_rate(work, rate, q, friction, shear_modulus)
    _creep_pass(work, contacts.law, rate, q, friction, shear_modulus, loads, True)
    rate += _close_pitch_balance(work)
    total_y = 0.0
    total_m = 0.0
    total_roll = 0.0
    for side in range(2):
        sigma = 1.0 - 2.0 * side
        arm = work[side, ARM]
        normal = work[side, _NORMAL]
        force_y = -sigma * normal * work[side, SIN_ANGLE] + work[side, _LATERAL] * work[side, COS_ANGLE]
        lead = psi * work[side, LEAD_RATE]
        total_y += force_y
        total_m += -sigma * arm * work[side, _FX] + lead * force_y
        # roll moment about the wheelset centre of the rail's force at the contact (z up),
        # the contact ``r - sigma l phi`` below the centre in the track plane
        depth = work[side, RADIUS] - sigma * arm * work[side, ROLL]
        total_roll += sigma * arm * (load_left if side == 0 else load_right) + depth * force_y
        out[_OUT_LATERAL[side]] = force_y
        out[_OUT_NORMAL[side]] = normal
        out[_OUT_FX[side]] = work[side, _FX]
        # on the rail: the table's coordinate (the wheelset on the deflected rail) and the
        # contact's move along the axle from the centred wheelset's contact
        out[_OUT_U[side]] = work[side, _U] + sigma * (arm - contacts.centred_arm[j, side])
        out[_OUT_ANGLE[side]] = work[side, ANGLE]
        out[_OUT_LOAD[side]] = load_left if side == 0 else load_right
        _energy(work, side, rate, q, out)
        out[_OUT_WHEEL_U[side]] = _along_axle(sigma, arm, work[side, RADIUS], work[side, ROLL]) - contacts.centred_arm[j, side]
    out[_OUT_Y] = total_y - contacts.wall[j] * extra
    out[_OUT_M] = total_m
    out[_OUT_ROLL] = total_roll
    out[_OUT_BEYOND] = extra


@kernel
def _energy(work, side, rate, q, out):
    """The creepages of contact ``side`` at the balanced rotation ``rate``, its lateral
    creep force ``T`` (in the contact plane), the frictional power per unit rolling
    distance ``Tgamma = |Fx xi + T eta + Mz phi|`` [N] (the spin moment ``Mz`` of the table
    law; FASTSIM and Polach give none, so their share ``Mz phi`` is left out;
    ``docs/wear.md``) and the Hertz patch's area
    per ``N^(2/3)``, ``pi a b`` of the tables' semi-axes of 1 N [m^2 / N^(2/3)] (the area
    is that times ``N^(2/3)`` of the final normal force: the power is left to NumPy) into
    ``out``."""
    xi, eta, phi = _creepages(work, side, rate, q)
    fx, fy = work[side, _FX], work[side, _LATERAL]
    out[_OUT_XI[side]] = xi
    out[_OUT_ETA[side]] = eta
    out[_OUT_PHI[side]] = phi
    out[_OUT_CREEP_Y[side]] = fy
    out[_OUT_TGAMMA[side]] = abs(fx * xi + fy * eta + work[side, _MZ] * phi)
    out[_OUT_AREA[side]] = math.pi * work[side, SEMI_A] * work[side, SEMI_B]
    out[_OUT_SEMI_B[side]] = work[side, SEMI_B]


@kernel
def _along_axle(sigma, arm, radius, roll):
    """The contact's lateral place on the wheel, along the axle from the wheelset centre
    [m]: the track-plane arm turned back by the roll, ``arm cos(roll) - sigma r sin(roll)``
    (to fourth order in the roll, below 2e-9 relative at the tables' 15 mrad).  Less the
    centred contact's (no roll there) it is the position on the wheel profile, positive
    toward the field side."""
    square = roll * roll
    return arm * (1.0 - 0.5 * square) - sigma * radius * roll * (1.0 - square / 6.0)


@kernel
def _creepages(work, side, rate, q):
    """``(xi, eta, phi)`` of contact ``side`` for the wheel rotation ``rate = omega / v``
    (``eta`` of the work array, independent of the rotation)."""
    sigma = 1.0 - 2.0 * side
    xi = 1.0 - rate * work[side, RADIUS] - sigma * work[side, ARM] * q
    phi = -sigma * rate * work[side, SIN_AXLE] + q * work[side, COS_ANGLE]
    return xi, work[side, _ETA], phi


@kernel
def _creep_pass(work, law, rate, q, friction, shear_modulus, loads, final):
    """Creep forces of both contacts by ``law`` into ``work``, then the normal forces
    from the wheel loads: ``N cos(delta) + sigma T sin(delta) = Q``.  T is nearly
    proportional to N (exactly so in full slip): with ``kappa = T / N`` this gives N; on
    the ``final`` pass the forces are scaled with it, before it the ellipse."""
    for side in range(2):
        xi, eta, phi = _creepages(work, side, rate, q)
        scale = work[side, _SCALE]
        args = (work[side, _NORMAL], friction, work[side, SEMI_A] * scale, work[side, SEMI_B] * scale, shear_modulus,
                work[side, C11], work[side, C22], work[side, C23], xi, eta, phi)
        moment = 0.0
        if law == FASTSIM:
            fx, fy = fastsim(*args)
        elif law == TABLE:
            fx, fy, moment = tabulated_with_moment(*args)
        else:
            fx, fy, work[side, _F11] = polach_with_slope(*args)  # the tangent, for the pitch balance
        work[side, _FX] = fx
        work[side, _LATERAL] = fy
        work[side, _MZ] = moment
        sigma = 1.0 - 2.0 * side
        old = work[side, _NORMAL]
        new = loads[side] / max(work[side, COS_ANGLE] + sigma * fy / old * work[side, SIN_ANGLE], 0.05)
        work[side, _NORMAL] = new
        if final:
            work[side, _FX] *= new / old
            work[side, _LATERAL] *= new / old
            work[side, _MZ] *= new / old
        else:
            work[side, _SCALE] = new ** (1.0 / 3.0)


@kernel
def _balanced_rate(work, rate, q, friction, shear_modulus):
    """The wheel rotation ``omega / v`` that balances the pitch moment of the contacts,
    ``sum(r Fx + m T) = 0`` (``m`` of :func:`_lateral_pitch_arm`): Newton's method from
    ``rate``, the first step with the forces and tangent stiffnesses of the Polach pass
    in ``work``, the next (at least one, at most ``_NEWTON - 1``, until a step is below
    ``_EXIT``) with Polach's longitudinal force (:func:`express.rail.creep_law.
    polach_longitudinal`) at the corrected normal forces, the lateral forces T of the pass
    held.  (Stopping after a small first step, taken on the first pass's normal forces,
    left the rotation unconverged and moved the Manchester car's nonlinear critical speed
    by 0.3 km/h.)"""
    residual, slope = _pitch_moment(work)
    for iteration in range(_NEWTON):
        if not slope > 0.0:
            break
        step = residual / slope
        rate -= step
        if iteration > 0 and abs(step) < _EXIT:  # a step on the corrected normal forces, converged
            break
        residual = 0.0
        slope = 0.0
        for side in range(2):
            xi, eta, phi = _creepages(work, side, rate, q)
            scale = work[side, _SCALE]
            semi_a = work[side, SEMI_A] * scale
            spun = eta + phi * semi_a
            fx, k = polach_longitudinal(work[side, _NORMAL], friction, semi_a, work[side, SEMI_B] * scale,
                                        shear_modulus, work[side, C11], work[side, C22], xi, eta,
                                        spun if abs(spun) > abs(eta) else eta)
            r = work[side, RADIUS]
            residual += r * fx + work[side, _LATERAL] * work[side, _PITCH_ARM]
            slope += k * r * r
            work[side, _F11] = k
    return rate


@kernel
def _close_pitch_balance(work):
    """The last Newton step of the pitch balance applied to the final forces linearly:
    the chosen law's forces at the corrected normal forces leave a residual pitch moment
    (another law than the balance's, another N); the rotation's change
    ``-residual / sum(k r^2)`` moves each wheel's ``Fx`` by ``k r`` times it (``k`` the
    tangent stiffnesses of the balance); returns that change of ``omega / v`` (0 without
    a slope)."""
    residual, slope = _pitch_moment(work)
    change = 0.0
    if slope > 0.0:
        change = -residual / slope
        for side in range(2):
            work[side, _FX] += work[side, _F11] * work[side, RADIUS] * change
    return change


@kernel
def _pitch_moment(work):
    """The contacts' pitch moment about the axle,
    ``sum(r Fx + m T)``, and its slope in the rotation ``omega / v``, ``sum(k r^2)``, from
    the forces and tangent stiffnesses ``k`` in ``work``."""
    residual = 0.0
    slope = 0.0
    for side in range(2):
        r = work[side, RADIUS]
        residual += r * work[side, _FX] + work[side, _LATERAL] * work[side, _PITCH_ARM]
        slope += work[side, _F11] * r * r
    return residual, slope


@kernel
def _lateral_pitch_arm(sigma, psi, r, work, side):
    """Moment about the axle of a unit lateral creep force at the contact of a wheelset
    yawed by ``psi`` (``docs/contact.md``): the force acts ahead of the wheel's lowest
    point, ``x_w = lead + psi sigma arm``, and along the contact plane, inclined by the
    axle angle (whose sine is tabulated with ``cos(psi)``).  The normal force passes
    through the axle and has none.  ``work[side]`` holds the contact's fields."""
    ahead = psi * (work[side, LEAD_RATE] + sigma * work[side, ARM])
    sin_axle = work[side, SIN_AXLE]
    return sigma * ahead * sin_axle + psi * r * math.sqrt(max(1.0 - sin_axle * sin_axle, 0.0))


def patch_area(unit_area, normal):
    """Hertz patch area [m^2] from the kernel's ``unit_area`` [m^2 / N^(2/3)] and the
    normal force ``normal`` [N] (arrays broadcast; a lifted wheel's N <= 0 gives 0)."""
    return np.asarray(unit_area, dtype=float) * np.maximum(np.asarray(normal, dtype=float), 0.0) ** (2.0 / 3.0)


def quasi_static_forces(contact: WheelsetContact, y: float, psi: float = 0.0, y_dot: float = 0.0,
                        psi_dot: float = 0.0, rho: float = 0.0, speed: float = 1.0, law: CreepLaw = "polach",
                        loads: tuple[float, float] | None = None) -> dict[str, float]:
    """:func:`profile_wheelset_forces` of one state, by name (:data:`OUTPUTS`); SI units; ``law``
    ``"polach"``, ``"fastsim"`` or ``"table"``; ``loads`` the wheel loads (left, right) [N], the static
    ``contact.wheel_load`` by default."""
    left, right = (contact.wheel_load, contact.wheel_load) if loads is None else loads
    out = np.zeros(len(OUTPUTS))
    profile_wheelset_forces(contact_set([contact], law), 0, float(left), float(right), float(y), float(psi), float(y_dot),
                    float(psi_dot), float(rho), float(speed), np.zeros((2, len(WORK_FIELDS))), out)
    return dict(zip(OUTPUTS, out.tolist(), strict=True))
