"""Friction elements: Coulomb friction with a pre-slip spring, a force element of the time
domain (issue 31, item 1).

A friction element is a spring ``k`` (its ``stiffness``, the pre-slip stiffness) in series
with a slider that slips when the spring's force reaches the friction limit ``L``
(``friction = mu N`` in the model file, constant).  The slider's position ``s`` is the
element's internal state; with the deflection ``delta = g . q + h . u``::

    F = k (delta - s),   |F| <= L;   s moves only while |F| = L  (then F = L sign(delta'))

which is the exact rate-independent law (elastic–perfectly plastic): stick and slip
without smoothing.  In the march it is the *return mapping* at every kept state: the
trial force ``k (delta - s)`` beyond ``+-L`` moves the slider to ``delta -+ L/k``.  The
predictor's trial state updates nothing (:func:`express.forces.law.force_law`'s
``commit``).  Sources: the series spring–slider (Jenkin) element as used for friction
dampers in rail vehicles (e.g. the Lenoir link) in Iwnicki (ed.), *Handbook of Railway
Vehicle Dynamics*, 2nd ed., ch. on suspension components; its hysteresis loop is the
parallelogram of the elastoplastic element, area ``4 L (X - L/k)`` per cycle of amplitude
``X > L/k`` (tested).

How the linear analyses see it: **stuck** — the pre-slip spring alone, in ``K`` (and any
``damping`` of the element in ``C``, in parallel with the friction branch) — which is the
tangent at the static state.  The force element therefore feeds back the difference from
the stuck spring, ``z = -F + k delta = k s`` along ``g``; a run in which nothing slips is
exactly the linear run.

The element reads the coordinates of each deflection, acts along ``g``, has one internal
state per element (its slider), its compiled law is :class:`FrictionLaw`, its
linearisation is ``dz/d(delta) = 0`` stuck and ``k`` slipping, and it reports
``friction_<element>`` (the force ``F`` [N; N m rotational]) and ``slip_<element>`` (the
slider's position ``s`` [m; rad]).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.extending import overload

from express.forces.element import ForceElement, sparse_rows
from express.forces.law import force_law
from express.model.parameters import expression_value

__all__ = ["RESOLVED", "FrictionElement", "FrictionLaw", "friction_elements_of", "return_mapping"]

#: ``w dt`` of the pre-slip frequency a step may reach and still resolve the slip phase.
RESOLVED = 0.02


class FrictionLaw(NamedTuple):
    """Friction elements for the compiled march: deflection ``offset[k, f] + sum
    coefficient[f, :] x[places[f, :]]``, pre-slip ``stiffness`` [N/m], ``limit`` [N]
    (rotational: N m/rad, N m), the committed slider positions ``slider`` [m] (changed in
    place when committing); forces into ``z[first:]``."""

    first: int
    places: np.ndarray
    coefficient: np.ndarray
    offset: np.ndarray
    stiffness: np.ndarray
    limit: np.ndarray
    slider: np.ndarray


@njit(cache=True)
def return_mapping(delta, slider, stiffness, limit):
    """The slider's position after the deflection ``delta`` from ``slider`` (stick, or slip
    to the friction limit)."""
    force = stiffness * (delta - slider)
    if force > limit:
        return delta - limit / stiffness
    if force < -limit:
        return delta + limit / stiffness
    return slider


@njit(cache=True)
def _replay(delta, slider, stiffness, limit, out):
    """The committed slider positions at every kept state (the march's return mappings
    again, in the same order): ``out[k, f]``."""
    for k in range(delta.shape[0]):
        for f in range(delta.shape[1]):
            slider[f] = return_mapping(delta[k, f], slider[f], stiffness[f], limit[f])
            out[k, f] = slider[f]


@njit(cache=True)
def friction_forces(x, k, law, z, commit):
    """``z = k s`` of every friction element (the module docstring) into ``z[law.first:]``."""
    for f in range(law.limit.size):
        delta = law.offset[k, f]
        for i in range(law.places.shape[1]):
            delta += law.coefficient[f, i] * x[law.places[f, i]]
        slider = return_mapping(delta, law.slider[f], law.stiffness[f], law.limit[f])
        if commit:
            law.slider[f] = slider
        z[law.first + f] = law.stiffness[f] * slider


@overload(force_law)
def _friction_law(x, k, law, z, record, commit):
    if isinstance(law, types.BaseNamedTuple) and law.instance_class is FrictionLaw:
        return lambda x, k, law, z, record, commit: friction_forces(x, k, law, z, commit)
    return None


class FrictionElement(ForceElement):
    """The friction elements of a vehicle along a run (module docstring).

    Parameters
    ----------
    names : tuple of str
        The elements' ids.
    gradient : numpy.ndarray, shape (n_f, n)
        ``g`` of each deflection over the coordinates.
    input_gradient : numpy.ndarray, shape (n_f, m)
        ``h`` of each deflection over the inputs.
    stiffness, limit : numpy.ndarray, shape (n_f,)
        Pre-slip stiffness [N/m; N m/rad] and friction limit [N; N m].
    force : numpy.ndarray, shape (N, n)
        How a generalized force enters the state equation (``FirstOrderForm.force``).
    u : numpy.ndarray, shape (steps + 1, m)
        The inputs at every step.
    rotational : tuple of bool
        Whether each element acts on a rotation (its outputs' units).
    """

    kind = "friction"

    def __init__(self, names: tuple[str, ...], gradient: np.ndarray, input_gradient: np.ndarray,
                 stiffness: np.ndarray, limit: np.ndarray, force: np.ndarray, u: np.ndarray,
                 rotational: tuple[bool, ...]):
        self.ids, self.gradient, self.input_gradient, self.rotational = names, gradient, input_gradient, rotational
        self.stiffness, self.limit, self.force, self.u = stiffness, limit, force, u
        self.rows = np.zeros((len(names), force.shape[0]))
        self.rows[:, : gradient.shape[1]] = gradient
        self.offset = np.ascontiguousarray(u @ input_gradient.T, dtype=float)
        #: The slider positions the NumPy forces start from (the steady solver's state).
        self.slider = np.zeros(len(names))
        self.states = len(names)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"friction_{name}" for name in self.ids)

    @property
    def reads(self) -> np.ndarray:
        return np.flatnonzero(np.any(self.rows != 0, axis=0))

    def directions(self) -> np.ndarray:
        n = self.gradient.shape[1]
        return np.column_stack([self.force[:, :n] @ row for row in self.gradient])

    def law(self, first: int) -> FrictionLaw:
        index, coefficient = sparse_rows(self.rows)
        return FrictionLaw(first, index, coefficient, self.offset, np.ascontiguousarray(self.stiffness, dtype=float),
                           np.ascontiguousarray(self.limit, dtype=float), self.slider.copy())

    def deflections(self, x: np.ndarray, k: int) -> np.ndarray:
        """The deflections at state ``x`` and step ``k``."""
        return self.gradient @ x[: self.gradient.shape[1]] + self.input_gradient @ self.u[k]

    def _sliders(self, delta: np.ndarray) -> np.ndarray:
        return np.array([return_mapping(d, s, k, lim) for d, s, k, lim
                         in zip(delta, self.slider, self.stiffness, self.limit, strict=True)])

    def forces(self, x: np.ndarray, k: int) -> np.ndarray:
        return self.stiffness * self._sliders(self.deflections(x, k))

    def slopes(self, x: np.ndarray, k: int, forces: np.ndarray) -> np.ndarray:
        """Stuck: 0; slipping (the slider follows the deflection): ``k g``."""
        delta = self.deflections(x, k)
        slipping = np.abs(self.stiffness * (delta - self.slider)) > self.limit
        return np.where(slipping, self.stiffness, 0.0)[:, None] * self.rows

    def resolved_step(self, mass: np.ndarray) -> float | None:
        """While slipping the element feeds its pre-slip stiffness back explicitly: the step
        must resolve ``w = sqrt(ks g M^-1 g)``; :data:`RESOLVED` of a period of it (the free
        decay's error is 1.5e-4 of 4 F/k at w dt = 0.012, 4.5e-3 at 0.05)."""
        inverse = np.linalg.solve(mass, self.gradient.T)  # M^-1 g^T, (n, n_f)
        compliance = np.einsum("fi,if->f", self.gradient, inverse)
        omega = np.sqrt(self.stiffness * np.maximum(compliance, 0.0))
        largest = float(np.max(omega)) if omega.size else 0.0
        return RESOLVED / largest if largest > 0 else None

    def history_of(self, states: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The sliders and forces at every kept state, the march's return mapping replayed:
        ``(slider, force)``, each shape (steps + 1, n_f)."""
        delta = np.ascontiguousarray(states @ self.rows.T + self.offset[: states.shape[0]])
        sliders = np.zeros_like(delta)
        _replay(delta, self.slider.copy(), np.ascontiguousarray(self.stiffness, dtype=float),
                np.ascontiguousarray(self.limit, dtype=float), sliders)
        return sliders, self.stiffness * (delta - sliders)

    def outputs(self, states: np.ndarray, history: np.ndarray) -> dict[str, np.ndarray]:
        sliders, forces = self.history_of(states)
        found = {}
        for f, name in enumerate(self.ids):
            found[f"friction_{name}"] = forces[:, f]
            found[f"slip_{name}"] = sliders[:, f]
        return found

    def output_units(self) -> dict[str, str]:
        units = {}
        for name, rotational in zip(self.ids, self.rotational, strict=True):
            units[f"friction_{name}"] = "N*m" if rotational else "N"
            units[f"slip_{name}"] = "rad" if rotational else "m"
        return units


def friction_elements_of(vehicle, u: np.ndarray) -> FrictionElement | None:
    """The friction elements of ``vehicle`` (a :class:`~express.numeric.statespace.VehicleModel`)
    along the inputs ``u`` (steps + 1, m), or None when it has none."""
    equations = vehicle.equations
    terms = [t for t in equations.element_terms if t.kind == "friction"]
    if not terms:
        return None
    column = {dof: i for i, dof in enumerate(vehicle.dofs)}  # a stroke left out by the vehicle: no column
    n, m = len(vehicle.dofs), len(equations.inputs)
    gradient, inputs = np.zeros((len(terms), n)), np.zeros((len(terms), m))
    values = vehicle.values
    for f, term in enumerate(terms):
        for dof, value in term.gradient.items():
            if dof in column:
                gradient[f, column[dof]] = expression_value(value, values)
        for name, value in term.inputs.items():
            inputs[f, equations.inputs.index(name)] = expression_value(value, values)
    stiffness = np.array([expression_value(t.values["stiffness"], values) for t in terms])
    limit = np.array([expression_value(t.values["friction"], values) for t in terms])
    kinds = {e.id: e.rotational for e in vehicle.model.elements} if vehicle.model is not None else {}
    return FrictionElement(tuple(t.element for t in terms), gradient, inputs, stiffness, limit, vehicle.form.force, u,
                           tuple(kinds.get(t.element, False) for t in terms))
