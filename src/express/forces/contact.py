"""The wheel/rail contact from profile tables as a force element, with the vertical
wheel loads that press it (issue 12, item 5).

When a model's conicity comes from profiles (:mod:`express.rail.profile_contact`), the
dead-band flange spring and the creep saturation give way to the contact forces of
:func:`express.rail.contact_forces.profile_wheelset_forces`: normal forces from the
geometry, Hertz ellipses, creep forces by FASTSIM (or Polach, or the tables of the exact theory), elastic rails.  The linear
part of the motion stays in ``A``; the difference between the contact forces and the
linear wheel/rail terms of the model (:func:`express.rail.wheelrail.wheelset_terms`,
evaluated at the run's speed) is fed back on each wheelset's lateral and yaw
coordinates (and its roll, on a model whose wheels stand on vertical springs)::

    z_y   = Y(y - yR, psi, y', psi', rho) - Y_lin,   Y_lin = -(K_yy y + K_ypsi psi + C_yy y' + C_ypsi psi') + P_yR yR + P_rho rho
    z_psi = M(...) - M_lin                            (likewise)

so that a small motion runs exactly as the linear model, which is the contact's
linearisation at the node's amplitude (``tests/test_contact_tables.py``).

The element (:class:`ContactElement`) reads each wheelset's lateral and yaw coordinates,
their rates and the coordinates its wheel loads depend on (:class:`WheelLoadModel`), has
no internal state, its compiled law is :class:`ContactFeedback`, its linearisation is by
differences, and it records the contact forces of every wheel
(:data:`~express.rail.contact_forces.OUTPUTS`) at every step.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import sympy as sp
from numba import njit, types
from numba.extending import overload

from express.base.caches import IdentityCache
from express.base.diagnostics import ArgumentError
from express.base.kernels import kernel
from express.forces.element import ForceElement
from express.forces.law import force_law
from express.forces.wheelsets import WheelsetCoordinates, wheel_rail_slopes
from express.model.parameters import expression_value
from express.rail.contact_forces import (
    LAWS,
    OUTPUTS,
    WORK_FIELDS,
    ContactSet,
    WheelsetContact,
    contact_set,
    profile_wheelset_forces,
)
from express.rail.curve import station_of
from express.rail.options import DEFAULT_CREEP_LAW, CreepLaw
from express.rail.profile_contact import contact_terms, profile_nodes
from express.rail.vertical_contact import vertical_contacts
from express.rail.wheel_rise import contact_rise
from express.rail.wheelrail import irregularity_input, wheelset_terms

__all__ = [
    "LINEAR_TERMS", "NO_ROLL", "ContactElement", "ContactFeedback", "WheelLoadModel", "contact_arrays",
    "contact_feedback", "dynamic_wheel_loads", "linear_coefficients", "linear_wheel_rail", "pressed_loads",
    "roll_coordinates", "static_wheel_loads", "unpressed", "wheel_loads_at", "wheel_loads_history",
]

#: The model's linear wheel/rail terms of a wheelset, in the order of the columns of
#: :func:`linear_coefficients`: (row, column, matrix) with ``y`` the lateral and ``psi``
#: the yaw coordinate, ``yR`` the rail irregularity and ``rho`` the curvature input.
LINEAR_TERMS = (
    ("y", "y", "K"), ("y", "psi", "K"), ("y", "y", "C"), ("y", "psi", "C"), ("y", "yR", "P"), ("y", "rho", "P"),
    ("psi", "y", "K"), ("psi", "psi", "K"), ("psi", "y", "C"), ("psi", "psi", "C"), ("psi", "yR", "P"),
    ("psi", "rho", "P"),
)
#: Columns of the lateral row (then of the yaw row) of :data:`LINEAR_TERMS`: K_y, K_psi, C_y, C_psi, P_yR, P_rho.
_LATERAL_ROW = tuple(i for i, term in enumerate(LINEAR_TERMS) if term[0] == "y")
_YAW_ROW = tuple(i for i, term in enumerate(LINEAR_TERMS) if term[0] == "psi")


def _linear_terms(model) -> list[list[tuple[int, object]]]:
    """``(slot, expression)`` of every wheelset's linear wheel/rail terms (cached by model)."""
    return _TERMS.get_or_make((model,), lambda: _build_linear_terms(model))


def _build_linear_terms(model) -> list[list[tuple[int, object]]]:
    rail = model.rail
    nodes = profile_nodes(model)
    by_body = station_of(model)
    terms_of = []
    for wheelset in rail.wheelsets:
        node = nodes.get(wheelset.body)
        curvature = by_body[wheelset.body].curvature_input
        stiffness, damping, forces = wheelset_terms(wheelset, rail.speed, curvature,
                                                    contact_terms(node) if node is not None else None)
        name = {"y": f"{wheelset.body}.y", "psi": f"{wheelset.body}.rz", "yR": irregularity_input(wheelset),
                "rho": curvature}
        slot = {(name[row], name[column], kind): i for i, (row, column, kind) in enumerate(LINEAR_TERMS)}
        terms_of.append([(slot[(row, column, kind)], value)
                         for kind, terms in (("K", stiffness), ("C", damping), ("P", forces))
                         for row, column, value in terms if (row, column, kind) in slot])
    return terms_of


_TERMS: IdentityCache[list[list[tuple[int, object]]]] = IdentityCache(16)
#: Coefficients already evaluated, by model and values.
_COEFFICIENTS: IdentityCache[np.ndarray] = IdentityCache(64)


def linear_coefficients(vehicle, speed: float) -> np.ndarray:
    """The model's linear wheel/rail terms of every wheelset at ``speed`` [m/s], shape
    (n_wheelsets, len(LINEAR_TERMS)): :data:`LINEAR_TERMS` (``K`` on (y, psi), ``C`` on
    (y', psi'), ``P`` on (yR, rho), lateral row then yaw row; the module docstring); kept
    for the same model and numbers."""
    model = vehicle.model
    rail = model.rail
    if not isinstance(rail.speed, sp.Symbol):
        raise ArgumentError("the contact simulation needs the model's speed as a parameter (rail.speed = \"v\")")
    values = {**vehicle.values, rail.speed.name: float(speed)}
    held = _COEFFICIENTS.get_or_make((model,), lambda: _coefficients(model, values), tuple(sorted(values.items())))
    return held.copy()


def _coefficients(model, values: dict[str, float]) -> np.ndarray:
    terms_of = _linear_terms(model)
    out = np.zeros((len(terms_of), len(LINEAR_TERMS)))
    for j, terms in enumerate(terms_of):
        for index, value in terms:
            out[j, index] += expression_value(value, values)
    return out


def contact_arrays(contacts: list[WheelsetContact], law: CreepLaw = DEFAULT_CREEP_LAW) -> ContactSet:
    """The tables and rail maps of the wheelsets stacked for the compiled march
    (:func:`express.rail.contact_forces.contact_set`, cached for the same contacts)."""
    if law not in LAWS:
        raise ArgumentError(f"creep law {law!r}: use one of {', '.join(LAWS)}")
    held = tuple(item for c in contacts for item in (c.tables, c.rail_map))
    numbers = tuple((c.wheel_load, c.friction, c.rail_stiffness) for c in contacts)
    made: list[ContactSet] = []

    def make() -> ContactSet:
        made.append(contact_set(contacts, law))
        return made[0]

    arrays = _ARRAYS.get_or_make(held, make, numbers)
    return arrays if made else arrays._replace(law=LAWS[law])


_ARRAYS: IdentityCache[ContactSet] = IdentityCache(16)


class WheelLoadModel(NamedTuple):
    """Vertical wheel loads during the march, linear in the state::

        Q[side] = Q0 + offset[k, j, side] + sum_i gain[k', i, j, side] x[places[i]]

    (``k' = k``, or 0 when ``gain`` holds one instant: constant gains).  Two sources
    (``docs/contact.md``): the model's own vertical contact springs
    (:func:`dynamic_wheel_loads`, ``Q = Q0 - k_z deflection``), or the quasi-static load
    transfer of :mod:`express.rail.load_transfer` for a lateral-only model
    (:func:`express.analysis.curving.measure.estimated_wheel_loads`: the normal load of
    cant and centrifugal force, the roll moment of the cant deficiency and of each body's
    lateral displacement).

    Attributes
    ----------
    static : numpy.ndarray, shape (n_wheelsets,)
        Q0 [N].
    offset : numpy.ndarray, shape (steps + 1, n_wheelsets, 2)
        [N], left then right.
    places : numpy.ndarray of int, shape (n_places,)
        State coordinates the loads depend on.
    gain : numpy.ndarray, shape (steps + 1 or 1, n_places, n_wheelsets, 2)
        [N per unit].
    stiffness : numpy.ndarray, shape (n_wheelsets, 2)
        The vertical contact springs under the wheels [N/m], which the wheel's rise on
        its rail presses (:func:`pressed_loads`); zero for loads that do not come from
        them.
    roll : numpy.ndarray of int, shape (n_wheelsets,)
        Each wheelset's roll coordinate in the state (-1: none).
    arm : numpy.ndarray, shape (n_wheelsets,)
        Lateral distance of its vertical springs from its centre [m].
    """

    static: np.ndarray
    offset: np.ndarray
    places: np.ndarray
    gain: np.ndarray
    stiffness: np.ndarray
    roll: np.ndarray
    arm: np.ndarray


def static_wheel_loads(static: np.ndarray, steps: int) -> WheelLoadModel:
    """A :class:`WheelLoadModel` of the static loads only (``steps + 1`` instants)."""
    count = static.size
    return WheelLoadModel(np.ascontiguousarray(static, dtype=float), np.zeros((steps + 1, count, 2)),
                          np.zeros(0, dtype=np.int64), np.zeros((1, 0, count, 2)), *unpressed(count))


def unpressed(count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The last fields of a :class:`WheelLoadModel` of ``count`` wheelsets whose loads do
    not come from vertical contact springs."""
    return np.zeros((count, 2)), np.full(count, -1, dtype=np.int64), np.zeros(count)


def dynamic_wheel_loads(vehicle, inputs, static: np.ndarray) -> WheelLoadModel | None:
    """The loads of the model's own vertical contact springs
    (:func:`express.rail.vertical_contact.vertical_contacts`) along ``inputs`` (a
    :class:`~express.analysis.time.track_inputs.TrackInputs`); ``None`` unless every wheel
    has one."""
    if vehicle.model is None:
        return None
    springs = vertical_contacts(vehicle.model, vehicle.values, [w.name for w in vehicle.wheelsets], vehicle.dofs,
                                vehicle.inputs)
    every = [spring for pair in springs for spring in pair if spring is not None]
    if len(every) != 2 * len(springs):
        return None
    count, dofs = len(springs), len(vehicle.dofs)
    rows = np.array([spring.dofs for spring in every]).reshape(count, 2, dofs)
    drive = np.array([spring.inputs for spring in every]).reshape(count, 2, -1)
    stiffness = np.array([spring.stiffness for spring in every]).reshape(count, 2)
    damping = np.array([spring.damping for spring in every]).reshape(count, 2)
    places = np.flatnonzero(np.any(rows != 0, axis=(0, 1)))
    gain = -(stiffness[:, :, None] * rows[:, :, places]).transpose(2, 0, 1)[None]
    offset = -stiffness[None] * np.einsum("jsm,km->kjs", drive, inputs.u)
    if np.any(damping != 0):
        # the dampers under the wheels carry load too: -c_z times the deflection's rate,
        # from the coordinates' velocities in the state and the inputs' rates
        velocity = {int(i): vehicle.n + j for j, i in enumerate(vehicle.form.massive)}
        if not all(int(i) in velocity for i in places):
            raise ArgumentError("a damped vertical contact element moves a coordinate without mass")
        gain = np.concatenate([gain, -(damping[:, :, None] * rows[:, :, places]).transpose(2, 0, 1)[None]], axis=1)
        places = np.concatenate([places, [velocity[int(i)] for i in places]])
        offset = offset - damping[None] * np.einsum("jsm,km->kjs", drive, inputs.u_rate)
    if inputs.rail is not None:  # the cross level at the contact springs
        offset = offset + inputs.rail.load_changes()
    roll = np.array([vehicle.dof_index(f"{w.name}.rx") if f"{w.name}.rx" in vehicle.dofs else -1
                     for w in vehicle.wheelsets], dtype=np.int64)
    arm = np.array([spring.arm for spring in every], dtype=float).reshape(count, 2).mean(axis=1)
    return WheelLoadModel(np.ascontiguousarray(static, dtype=float), np.ascontiguousarray(offset),
                          places.astype(np.int64), np.ascontiguousarray(gain), np.ascontiguousarray(stiffness, dtype=float),
                          roll, arm)


@kernel
def wheel_loads_at(loads, x, k, j):
    """``(Q_left, Q_right)`` [N] of wheelset ``j`` at step ``k`` and state ``x``
    (:class:`WheelLoadModel`)."""
    row = k if loads.gain.shape[0] > 1 else 0
    left = loads.static[j] + loads.offset[k, j, 0]
    right = loads.static[j] + loads.offset[k, j, 1]
    for i in range(loads.places.size):
        value = x[loads.places[i]]
        left += loads.gain[row, i, j, 0] * value
        right += loads.gain[row, i, j, 1] * value
    return left, right


@kernel
def pressed_loads(loads, contacts, x, j, y, psi, geometry):
    """``(left, right)`` [N]: what the wheels of wheelset ``j`` (at displacement ``y`` [m]
    from the track, yaw ``psi`` [rad], state ``x``) add to the loads of their vertical
    contact springs by sitting on their rails: ``k (rise + sigma (b - lever) phi)``, the
    wheel's rise on its rail and the difference between the springs' lever ``b`` and the
    load's own (:func:`express.rail.wheel_rise.contact_rise`) under the roll
    ``phi``; zero without such springs.  ``geometry`` is scratch space of shape (2, 2)."""
    if loads.stiffness[j, 0] == 0.0 and loads.stiffness[j, 1] == 0.0:
        return 0.0, 0.0
    contact_rise(contacts, j, y, psi, geometry)
    phi = x[loads.roll[j]] if loads.roll[j] >= 0 else 0.0
    arm = loads.arm[j]
    left = loads.stiffness[j, 0] * (geometry[0, 0] + (arm - geometry[0, 1]) * phi)
    right = loads.stiffness[j, 1] * (geometry[1, 0] - (arm - geometry[1, 1]) * phi)
    return left, right


@njit(cache=True)
def _loads_history(loads, states, contacts, y, psi, out):
    geometry = np.empty((2, 2))
    for k in range(states.shape[0]):
        for j in range(out.shape[1]):
            left, right = wheel_loads_at(loads, states[k], k, j)
            press_left, press_right = pressed_loads(loads, contacts, states[k], j, y[k, j], psi[k, j], geometry)
            out[k, j, 0], out[k, j, 1] = left + press_left, right + press_right


def wheel_loads_history(loads: WheelLoadModel, states: np.ndarray, contacts: ContactSet, y: np.ndarray,
                        psi: np.ndarray) -> np.ndarray:
    """The wheel loads (:func:`wheel_loads_at` and :func:`pressed_loads`) of every instant
    of ``states`` (shape (N, >= n)) with the wheelsets at ``y`` [m] from the track and yaw
    ``psi`` [rad] (N, n_wheelsets), shape (N, n_wheelsets, 2), left then right [N]."""
    out = np.zeros((states.shape[0], loads.static.size, 2))
    _loads_history(loads, np.ascontiguousarray(states, dtype=float), contacts, np.ascontiguousarray(y, dtype=float),
                   np.ascontiguousarray(psi, dtype=float), out)
    return out


class ContactFeedback(NamedTuple):
    """The contact from profile tables of every wheelset, compiled: the contact forces
    less the model's linear wheel/rail terms (the module docstring).

    Attributes
    ----------
    first : int
        The law's place in ``z``.
    wheelsets : WheelsetCoordinates
    contacts : ContactSet
    linear : numpy.ndarray, shape (n_wheelsets, len(LINEAR_TERMS))
        :func:`linear_coefficients`.
    loads : WheelLoadModel
        The vertical wheel loads.
    roll : numpy.ndarray of int, shape (n_wheelsets,) or (0,)
        The wheelsets' roll coordinates in the state when the contact's roll moment is
        fed back (a model whose wheels stand on vertical springs, :func:`roll_coordinates`);
        empty otherwise.
    arm : numpy.ndarray, shape like ``roll``
        Lateral distance of each wheelset's vertical springs from its centre [m].
    lift : numpy.ndarray of int, shape like ``roll`` or (0,)
        The wheelsets' vertical coordinates, on which the wheels' rise on their rails
        presses the vertical springs (:func:`pressed_loads`); empty without them.
    work : numpy.ndarray, shape (2, len(WORK_FIELDS))
        Scratch space of the wheelset kernel.
    geometry : numpy.ndarray, shape (2, 2)
        Scratch space of :func:`pressed_loads`.
    """

    first: int
    wheelsets: WheelsetCoordinates
    contacts: ContactSet
    linear: np.ndarray
    loads: WheelLoadModel
    roll: np.ndarray
    arm: np.ndarray
    lift: np.ndarray
    work: np.ndarray
    geometry: np.ndarray


@kernel
def linear_wheel_rail(c, j, y, psi, y_dot, psi_dot, y_rail, rho):
    """The model's linear lateral force [N] and yaw moment [N m] on a wheelset with the
    coefficients ``c[j]`` (row ``j`` of :func:`linear_coefficients`)."""
    state = (y, psi, y_dot, psi_dot, y_rail, rho)
    sign = (-1.0, -1.0, -1.0, -1.0, 1.0, 1.0)
    lateral = 0.0
    yaw = 0.0
    for i in range(6):
        lateral += sign[i] * c[j, _LATERAL_ROW[i]] * state[i]
        yaw += sign[i] * c[j, _YAW_ROW[i]] * state[i]
    return lateral, yaw


@kernel
def contact_feedback(x, k, feedback, z, record):
    """Contact forces (:func:`express.rail.contact_forces.profile_wheelset_forces`) less the
    linear terms of every wheelset into ``z``; the forces into ``record`` (n_wheelsets,
    len(OUTPUTS))."""
    w = feedback.wheelsets
    count = w.iy.size
    first = feedback.first
    work, geometry = feedback.work, feedback.geometry
    for j in range(count):
        out = record[j]
        y, psi, y_dot, psi_dot = x[w.iy[j]], x[w.ipsi[j]], x[w.ivy[j]], x[w.ivpsi[j]]
        y_rail, rho = w.y_rail[k, j], w.rho[k, j]
        left, right = wheel_loads_at(feedback.loads, x, k, j)
        press_left, press_right = pressed_loads(feedback.loads, feedback.contacts, x, j, y - y_rail, psi, geometry)
        profile_wheelset_forces(feedback.contacts, j, left + press_left, right + press_right, y - y_rail, psi, y_dot,
                                psi_dot, rho, w.speed, work, out)
        lateral, yaw = linear_wheel_rail(feedback.linear, j, y, psi, y_dot, psi_dot, y_rail, rho)
        z[first + j] = out[_OUT_Y] - lateral
        z[first + count + j] = out[_OUT_M] - yaw
        if feedback.roll.size > 0:
            # the contact's roll moment less that of the model's vertical springs, which
            # carry the load changes at +-arm: b (Q_L - Q_R)
            z[first + 2 * count + j] = out[_OUT_ROLL] - feedback.arm[j] * (left - right)
        if feedback.lift.size > 0:
            # the rails hold the wheels up by the rise too (the springs of A do not see it)
            z[first + 3 * count + j] = press_left + press_right


_OUT_Y, _OUT_M, _OUT_ROLL = OUTPUTS.index("Y"), OUTPUTS.index("M"), OUTPUTS.index("Mx")
NO_ROLL = (np.zeros(0, dtype=np.int64), np.zeros(0))


def roll_coordinates(vehicle) -> tuple[np.ndarray, np.ndarray]:
    """The wheelsets' roll coordinates (``<wheelset>.rx``) and the lateral arm of their
    vertical contact springs [m], for feeding the contact's roll moment back; empty
    arrays unless every wheel stands on a vertical spring and every wheelset rolls."""
    if vehicle.model is None or any(f"{w.name}.rx" not in vehicle.dofs for w in vehicle.wheelsets):
        return NO_ROLL
    springs = vertical_contacts(vehicle.model, vehicle.values, [w.name for w in vehicle.wheelsets], vehicle.dofs,
                                vehicle.inputs)
    if any(spring is None for pair in springs for spring in pair):
        return NO_ROLL
    arms = [0.5 * sum(spring.arm for spring in pair if spring is not None) for pair in springs]
    return (np.array([vehicle.dof_index(f"{w.name}.rx") for w in vehicle.wheelsets], dtype=np.int64),
            np.array(arms, dtype=float))


@overload(force_law)
def _contact_law(x, k, law, z, record, commit):
    if isinstance(law, types.BaseNamedTuple) and law.instance_class is ContactFeedback:
        return lambda x, k, law, z, record, commit: contact_feedback(x, k, law, z, record)
    return None


class ContactElement(ForceElement):
    """The contact from profile tables of a vehicle along a run (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        Its wheelsets and state form.
    coordinates : WheelsetCoordinates
        Where the wheelsets are and the track under them.
    contacts : ContactSet
        The stacked tables (:func:`contact_arrays`).
    linear : numpy.ndarray, shape (n_wheelsets, len(LINEAR_TERMS))
        The model's linear wheel/rail terms at the run's speed (:func:`linear_coefficients`).
    loads : WheelLoadModel
        The vertical wheel loads along the run.
    roll : (numpy.ndarray, numpy.ndarray)
        The roll coordinates and arms (:func:`roll_coordinates`), or :data:`NO_ROLL`.
    """

    kind = "contact tables"

    def __init__(self, vehicle, coordinates: WheelsetCoordinates, contacts: ContactSet, linear: np.ndarray,
                 loads: WheelLoadModel, roll: tuple[np.ndarray, np.ndarray] = NO_ROLL):
        self.wheelsets, self.force = vehicle.wheelsets, vehicle.form.force
        self.coordinates, self.contacts, self.loads, self.roll = coordinates, contacts, loads, roll
        self.linear = np.ascontiguousarray(linear)
        # with the roll coordinates (3-D wheelsets on vertical springs) the loads, and so
        # the forces, depend on each wheelset's vertical and roll coordinates too
        self.extra = tuple(np.array([vehicle.dof_index(f"{w.name}.{c}") for w in vehicle.wheelsets])
                           for c in ("z", "rx") if roll[0].size)
        # damped contact springs: the loads follow those coordinates' velocities too
        velocity = {int(i): vehicle.n + j for j, i in enumerate(vehicle.form.massive)}
        self.extra += tuple(rates for rates in (np.array([velocity.get(int(i), -1) for i in column])
                                                for column in self.extra) if np.isin(rates, loads.places).all())
        vertical = [f"{w.name}.z" for w in vehicle.wheelsets]
        self.lift = (np.array([vehicle.dof_index(name) for name in vertical], dtype=np.int64)
                     if roll[0].size and all(name in vehicle.dofs for name in vertical) else np.zeros(0, dtype=np.int64))

    @property
    def names(self) -> tuple[str, ...]:
        axes = ("y", "rz") + (("rx",) if self.roll[0].size else ()) + (("z",) if self.lift.size else ())
        return tuple(f"{w.name}.{axis} wheel/rail" for axis in axes for w in self.wheelsets)

    @property
    def reads(self) -> np.ndarray:
        c = self.coordinates
        return np.unique(np.concatenate([c.iy, c.ipsi, c.ivy, c.ivpsi, self.loads.places, *self.extra]))

    def directions(self) -> np.ndarray:
        columns = [self.force[:, w.y] for w in self.wheelsets] + [self.force[:, w.psi] for w in self.wheelsets]
        columns += [self.force[:, int(i)] for i in self.roll[0]]
        columns += [self.force[:, int(i)] for i in self.lift]
        return np.column_stack(columns)

    def law(self, first: int) -> ContactFeedback:
        return ContactFeedback(first, self.coordinates, self.contacts, self.linear, self.loads, *self.roll, self.lift,
                               np.zeros((2, len(WORK_FIELDS))), np.zeros((2, 2)))

    def record_shape(self) -> tuple[int, ...]:
        return (len(self.wheelsets), len(OUTPUTS))

    def forces(self, x: np.ndarray, k: int) -> np.ndarray:
        """The compiled law itself at one state (the march's forces, bit for bit)."""
        z = np.zeros(self.width)
        contact_feedback(np.ascontiguousarray(x, dtype=float), k, self.law(0), z, np.zeros(self.record_shape()))
        return z

    def slopes(self, x: np.ndarray, k: int, forces: np.ndarray) -> np.ndarray:
        return wheel_rail_slopes(self.forces, x, k, forces, self.coordinates, self.extra)
