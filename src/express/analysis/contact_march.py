"""Time march with the wheel/rail contact from profile tables (issue 12, item 5).

When a model's conicity comes from profiles (:mod:`express.rail.profile_contact`), the
simulation replaces the dead-band flange spring and the creep saturation by the contact
forces of :func:`express.rail.contact_forces.profile_wheelset_forces`: normal forces from the
geometry, Hertz ellipses, creep forces by FASTSIM (or Polach), elastic rails.  As for the
other nonlinear forces, the linear part of the motion stays in the exactly discretised
``A`` (:mod:`express.analysis.integrator`), and the difference between the contact forces
and the linear wheel/rail terms of the model (:func:`express.rail.wheelrail.
wheelset_terms`, evaluated at the run's speed) is fed back on each wheelset's lateral and
yaw coordinates::

    z_y   = Y(y - yR, psi, y', psi', rho) - Y_lin,   Y_lin = -(K_yy y + K_ypsi psi + C_yy y' + C_ypsi psi') + P_yR yR + P_rho rho
    z_psi = M(...) - M_lin                            (likewise)

so that a small motion runs exactly as the linear model, which is the contact's
linearisation at the node's amplitude (``tests/test_contact_tables.py``).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import sympy as sp
from numba import njit, types
from numba.extending import overload

from express.analysis.curving.outputs import WheelRailOutputs
from express.analysis.integrator import (
    WheelsetCoordinates,
    bump_stop_arrays,
    wheel_rail_feedback,
    wheelset_coordinates,
)
from express.analysis.track_inputs import track_inputs
from express.base.caches import IdentityCache
from express.base.diagnostics import ArgumentError
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
from express.rail.options import CreepLaw
from express.rail.profile_contact import contact_terms, profile_nodes
from express.rail.vertical_contact import vertical_contacts
from express.rail.wheelrail import irregularity_input, wheelset_terms

__all__ = [
    "LINEAR_TERMS", "ContactFeedback", "WheelLoadModel", "contact_arrays", "contact_force_history", "contact_rhs",
    "contact_wheel_outputs", "dynamic_wheel_loads", "linear_coefficients", "linear_wheel_rail", "march_contact", "roll_coordinates",
    "static_wheel_loads", "wheel_loads_at", "wheel_loads_history",
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


def contact_arrays(contacts: list[WheelsetContact], law: CreepLaw = "fastsim") -> ContactSet:
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
    """

    static: np.ndarray
    offset: np.ndarray
    places: np.ndarray
    gain: np.ndarray


def static_wheel_loads(static: np.ndarray, steps: int) -> WheelLoadModel:
    """A :class:`WheelLoadModel` of the static loads only (``steps + 1`` instants)."""
    count = static.size
    return WheelLoadModel(np.ascontiguousarray(static, dtype=float), np.zeros((steps + 1, count, 2)),
                          np.zeros(0, dtype=np.int64), np.zeros((1, 0, count, 2)))


def dynamic_wheel_loads(vehicle, inputs, static: np.ndarray) -> WheelLoadModel | None:
    """The loads of the model's own vertical contact springs
    (:func:`express.rail.vertical_contact.vertical_contacts`) along ``inputs`` (a
    :class:`~express.analysis.track_inputs.TrackInputs`); ``None`` unless every wheel
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
    places = np.flatnonzero(np.any(rows != 0, axis=(0, 1)))
    gain = -(stiffness[:, :, None] * rows[:, :, places]).transpose(2, 0, 1)[None]
    offset = -stiffness[None] * np.einsum("jsm,km->kjs", drive, inputs.u)
    return WheelLoadModel(np.ascontiguousarray(static, dtype=float), np.ascontiguousarray(offset),
                          places.astype(np.int64), np.ascontiguousarray(gain))


@njit(cache=True)
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


@njit(cache=True)
def _loads_history(loads, states, out):
    for k in range(states.shape[0]):
        for j in range(out.shape[1]):
            out[k, j, 0], out[k, j, 1] = wheel_loads_at(loads, states[k], k, j)


def wheel_loads_history(loads: WheelLoadModel, states: np.ndarray) -> np.ndarray:
    """:func:`wheel_loads_at` of every instant of ``states`` (shape (N, >= n)), shape
    (N, n_wheelsets, 2), left then right [N]."""
    out = np.zeros((states.shape[0], loads.static.size, 2))
    _loads_history(loads, np.ascontiguousarray(states, dtype=float), out)
    return out


class ContactFeedback(NamedTuple):
    """The contact from profile tables of every wheelset, for
    :func:`express.analysis.integrator.heun_march`: the contact forces less the model's
    linear wheel/rail terms (the module docstring).

    Attributes
    ----------
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
    """

    wheelsets: WheelsetCoordinates
    contacts: ContactSet
    linear: np.ndarray
    loads: WheelLoadModel
    roll: np.ndarray
    arm: np.ndarray


@njit(cache=True)
def linear_wheel_rail(c, y, psi, y_dot, psi_dot, y_rail, rho):
    """The model's linear lateral force [N] and yaw moment [N m] on a wheelset with the
    coefficients ``c`` (a row of :func:`linear_coefficients`)."""
    state = (y, psi, y_dot, psi_dot, y_rail, rho)
    sign = (-1.0, -1.0, -1.0, -1.0, 1.0, 1.0)
    lateral = 0.0
    yaw = 0.0
    for i in range(6):
        lateral += sign[i] * c[_LATERAL_ROW[i]] * state[i]
        yaw += sign[i] * c[_YAW_ROW[i]] * state[i]
    return lateral, yaw


@njit(cache=True)
def contact_feedback(x, k, feedback, z, record):
    """Contact forces (:func:`express.rail.contact_forces.profile_wheelset_forces`) less the
    linear terms of every wheelset into ``z``; the forces into ``record`` (n_wheelsets,
    len(OUTPUTS))."""
    w = feedback.wheelsets
    count = w.iy.size
    work = np.empty((2, len(WORK_FIELDS)))
    for j in range(count):
        out = record[j]
        y, psi, y_dot, psi_dot = x[w.iy[j]], x[w.ipsi[j]], x[w.ivy[j]], x[w.ivpsi[j]]
        y_rail, rho = w.y_rail[k, j], w.rho[k, j]
        left, right = wheel_loads_at(feedback.loads, x, k, j)
        profile_wheelset_forces(feedback.contacts, j, left, right, y - y_rail, psi, y_dot, psi_dot, rho, w.speed, work, out)
        lateral, yaw = linear_wheel_rail(feedback.linear[j], y, psi, y_dot, psi_dot, y_rail, rho)
        z[j] = out[_OUT_Y] - lateral
        z[count + j] = out[_OUT_M] - yaw
        if feedback.roll.size > 0:
            # the contact's roll moment less that of the model's vertical springs, which
            # carry the load changes at +-arm: b (Q_L - Q_R)
            z[2 * count + j] = out[_OUT_ROLL] - feedback.arm[j] * (left - right)


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


@overload(wheel_rail_feedback)
def _contact_law(x, k, feedback, z, record):
    if isinstance(feedback, types.BaseNamedTuple) and feedback.instance_class is ContactFeedback:
        return lambda x, k, feedback, z, record: contact_feedback(x, k, feedback, z, record)
    return None


def march_contact(linear, x0, wheel_rail: dict, contact: ContactSet, coefficients: np.ndarray, *,
                  loads: WheelLoadModel | None = None, roll: tuple[np.ndarray, np.ndarray] = NO_ROLL, progress=None):
    """March with the contact feedback (``linear`` the linear part of the step and the
    other arguments as :func:`express.analysis.integrator.march`; ``contact`` from
    :func:`contact_arrays`, ``coefficients`` from :func:`linear_coefficients`, ``loads``
    the wheel loads, the static ones by default); returns the states, shape (steps + 1, N),
    and the contact forces of each state (:func:`contact_force_history`)."""
    steps = linear.steps
    loads = static_wheel_loads(contact.wheel_load, steps) if loads is None else loads
    feedback = ContactFeedback(wheelset_coordinates(wheel_rail, x0.size), contact, np.ascontiguousarray(coefficients),
                               loads, *roll)
    history = np.zeros((steps + 1, len(wheel_rail["iy"]), len(OUTPUTS)))
    states = linear.run(x0, feedback, bump_stop_arrays(wheel_rail, x0.size, steps), history, progress)
    return states, history


@njit(cache=True)
def _history(y, psi, y_dot, psi_dot, y_rail, rho, speed, contacts, loads, result):
    work = np.zeros((2, len(WORK_FIELDS)))
    for k in range(y.shape[0]):
        for j in range(y.shape[1]):
            profile_wheelset_forces(contacts, j, loads[k, j, 0], loads[k, j, 1], y[k, j] - y_rail[k, j], psi[k, j],
                            y_dot[k, j], psi_dot[k, j], rho[k, j], speed, work, result[k, j])


def contact_force_history(q, q_dot, iy, ipsi, y_rail, rho, speed, contact: ContactSet,
                          loads: np.ndarray | None = None) -> np.ndarray:
    """:data:`~express.rail.contact_forces.OUTPUTS` of every wheelset at every step,
    shape (steps, n_wheelsets, len(OUTPUTS)); ``loads`` the wheel loads (left, right) [N],
    shape (steps, n_wheelsets, 2), the static ones by default."""
    y, psi = np.ascontiguousarray(q[:, iy]), np.ascontiguousarray(q[:, ipsi])
    y_dot, psi_dot = np.ascontiguousarray(q_dot[:, iy]), np.ascontiguousarray(q_dot[:, ipsi])
    if loads is None:
        loads = np.broadcast_to(contact.wheel_load[None, :, None], (q.shape[0], len(iy), 2))
    result = np.zeros((q.shape[0], len(iy), len(OUTPUTS)))
    _history(y, psi, y_dot, psi_dot, np.ascontiguousarray(y_rail), np.ascontiguousarray(rho), float(speed), contact,
             np.ascontiguousarray(loads, dtype=float), result)
    return result


def contact_wheel_outputs(vehicle, history: np.ndarray, q: np.ndarray, loads: str) -> WheelRailOutputs:
    """The per-wheel record (:class:`~express.analysis.curving.outputs.WheelRailOutputs`)
    of a march from its contact forces ``history`` (:func:`march_contact`): each wheel's
    Q, Y, Fx, contact position and angle as the contact used them; the angle of attack is
    each wheelset's yaw ``q[:, psi]``; ``loads`` says where Q came from."""
    column = {name: k for k, name in enumerate(OUTPUTS)}

    def pair(name: str) -> np.ndarray:
        return history[:, :, [column[f"{name}_left"], column[f"{name}_right"]]]

    return WheelRailOutputs(
        vertical_load=pair("Q"), lateral_force=pair("Y"), longitudinal_force=pair("Fx"), contact_position=pair("u"),
        contact_angle=pair("angle"), angle_of_attack=q[:, [w.psi for w in vehicle.wheelsets]],
        static_load=np.array([w.wheel_load for w in vehicle.wheelsets], dtype=float), loads=loads)


def contact_rhs(vehicle, track, contacts: list[WheelsetContact], *, speed: float | None = None, start: float = 0.0,
                law: CreepLaw = "fastsim"):
    """The contact simulation's equations as ``f(t, x)`` for reference integrations
    (``scipy.integrate.solve_ivp``); bump stops are not included, the wheel loads are
    the static ones (the march adds the load transfer of
    :func:`express.analysis.curving.measure.estimated_wheel_loads`)."""
    v = float(vehicle.speed if speed is None else speed)
    a, b, bd = vehicle.state_matrix(v), vehicle.input_matrix(v), vehicle.input_rate_matrix(v)
    n = vehicle.n
    ws = vehicle.wheelsets
    columns = [vehicle.form.force[:, w.y] for w in ws] + [vehicle.form.force[:, w.psi] for w in ws]
    selector = np.column_stack(columns)
    arrays = contact_arrays(contacts, law)
    linear = linear_coefficients(vehicle, v)
    iy = np.array([w.y for w in ws])
    ipsi = np.array([w.psi for w in ws])

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        inputs = track_inputs(vehicle, track, np.array([start + v * t]), v)
        q_dot = vehicle.form.velocities(x, inputs.u[0], inputs.u_rate[0])
        history = contact_force_history(x[None, :n], q_dot[None, :], iy, ipsi, inputs.y_rail, inputs.rho_wheelsets,
                                        v, arrays)[0]
        terms = np.array([linear_wheel_rail(linear[j], x[iy[j]], x[ipsi[j]], q_dot[iy[j]], q_dot[ipsi[j]],
                                            inputs.y_rail[0, j], inputs.rho_wheelsets[0, j]) for j in range(len(iy))])
        z = np.concatenate([history[:, _OUT_Y] - terms[:, 0], history[:, _OUT_M] - terms[:, 1]])
        return a @ x + b @ inputs.u[0] + bd @ inputs.u_rate[0] + selector @ z

    return rhs

