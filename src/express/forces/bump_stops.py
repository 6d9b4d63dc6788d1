"""Clearance elements (bump stops): a force element of the time domain.

A clearance element's deflection ``delta = g . q + h . u`` is linear; it pushes back
only beyond its gap ``e0``::

    e = delta - e0   (delta >  e0)      F = k e + k3 e^3
    e = delta + e0   (delta < -e0)      (F has the sign of e)
    e = 0            otherwise

and adds the generalized force ``-F g`` to the equations of motion.  The linear
analyses leave these elements out (the generator says so in one warning); their
linearisation inside the gap is zero.

:class:`BumpStopElement` is the element (:class:`express.forces.element.ForceElement`):
it reads the coordinates of the deflections, acts along ``g``, has no internal state,
its compiled law is :class:`BumpStopLaw`, and it reports ``stop_<element>`` [N; N m for a
rotational one], the force of each stop (zero inside its gap).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import NamedTuple

import numpy as np
from numba import types
from numba.extending import overload

from express.assembly.equations import EquationsOfMotion
from express.base.kernels import kernel
from express.forces.element import ForceElement, sparse_rows
from express.forces.law import force_law
from express.model.parameters import expression_value

__all__ = ["BumpStopElement", "BumpStopLaw", "Clearances", "bump_stop_forces", "bump_stops_of", "clearance_force",
           "clearances_of"]


@dataclass(frozen=True)
class Clearances:
    """Every clearance element of a vehicle, evaluated.

    Attributes
    ----------
    names : tuple of str
        Element ids, length ``nb``.
    gradient : numpy.ndarray, shape (nb, n)
        ``g`` of each deflection over the coordinates ``q``.
    inputs : numpy.ndarray, shape (nb, m)
        ``h`` of each deflection over the inputs ``u``.
    gap, stiffness, progressive : numpy.ndarray, shape (nb,)
        ``e0`` [m or rad], ``k`` [N/m or N m/rad], ``k3`` [N/m^3 or N m/rad^3].
    """

    names: tuple[str, ...]
    gradient: np.ndarray
    inputs: np.ndarray
    gap: np.ndarray
    stiffness: np.ndarray
    progressive: np.ndarray

    @property
    def count(self) -> int:
        return len(self.names)


def _number(expression, values: dict[str, float]) -> float:
    try:
        return expression_value(expression, values)
    except KeyError as error:
        raise ValueError(f"no value for {error.args[0]}") from None


def clearances_of(equations: EquationsOfMotion, values: dict[str, float], dofs: tuple[str, ...] | None = None) -> Clearances:
    """The clearance elements of ``equations`` at parameter ``values`` (SI), their
    deflections over the coordinates ``dofs`` (default: the equations'; a numerical
    vehicle may have fewer: a series element without damping leaves its stroke out).

    Raises
    ------
    ValueError
        Naming a parameter without a value, a negative gap, or a deflection on a
        coordinate that ``dofs`` leaves out.
    """
    dofs = equations.dofs if dofs is None else dofs
    column = {dof: i for i, dof in enumerate(dofs)}
    n, m = len(dofs), len(equations.inputs)
    terms = equations.clearances
    gradient = np.zeros((len(terms), n))
    inputs = np.zeros((len(terms), m))
    gap, stiffness, progressive = (np.zeros(len(terms)) for _ in range(3))
    for b, term in enumerate(terms):
        for dof, value in term.gradient.items():
            number = _number(value, values)
            if dof in column:
                gradient[b, column[dof]] = number
            elif number != 0.0:
                raise ValueError(f"clearance element {term.element}: its deflection moves {dof}, which the vehicle "
                                 "leaves out")
        for name, value in term.inputs.items():
            inputs[b, equations.inputs.index(name)] = _number(value, values)
        gap[b] = _number(term.gap, values)
        stiffness[b] = _number(term.stiffness, values)
        progressive[b] = _number(term.progressive, values)
        if not gap[b] >= 0:
            raise ValueError(f"clearance element {term.element}: gap must be >= 0, got {gap[b]:g}")
    return Clearances(tuple(t.element for t in terms), gradient, inputs, gap, stiffness, progressive)


def clearance_force(delta: np.ndarray, gap: np.ndarray, stiffness: np.ndarray, progressive: np.ndarray) -> np.ndarray:
    """Force ``F`` [N or N m] of clearance elements at deflections ``delta`` (module
    docstring); arrays broadcast.

    Examples
    --------
    >>> clearance_force(np.array([0.005, 0.03, -0.03]), 0.01, 1e6, 0.0)
    array([     0.,  20000., -20000.])
    """
    penetration = np.where(delta > gap, delta - gap, np.where(delta < -gap, delta + gap, 0.0))
    return stiffness * penetration + progressive * penetration**3


class BumpStopLaw(NamedTuple):
    """Bump stops for the compiled march: the deflection of stop ``s`` is
    ``offset[k, s] + sum coefficient[s, :] x[places[s, :]]`` (its few nonzero terms, at
    ``places[s, :]`` of the state); ``gap`` [m], ``stiffness`` [N/m], ``progressive``
    [N/m^3] (rotational: rad, N m/rad, N m/rad^3); forces into ``z[first:]``."""

    first: int
    places: np.ndarray
    coefficient: np.ndarray
    offset: np.ndarray
    gap: np.ndarray
    stiffness: np.ndarray
    progressive: np.ndarray


@kernel
def bump_stop_forces(x, k, stops, z):
    """Bump-stop forces ``-F`` of :class:`BumpStopLaw` into ``z[stops.first:]``."""
    first = stops.first
    for s in range(stops.gap.size):
        delta = stops.offset[k, s]
        for i in range(stops.places.shape[1]):
            delta += stops.coefficient[s, i] * x[stops.places[s, i]]
        e = 0.0
        if delta > stops.gap[s]:
            e = delta - stops.gap[s]
        elif delta < -stops.gap[s]:
            e = delta + stops.gap[s]
        z[first + s] = -(stops.stiffness[s] * e + stops.progressive[s] * e * e * e)


@overload(force_law)
def _bump_stop_law(x, k, law, z, record, commit):
    if isinstance(law, types.BaseNamedTuple) and law.instance_class is BumpStopLaw:
        return lambda x, k, law, z, record, commit: bump_stop_forces(x, k, law, z)
    return None


class BumpStopElement(ForceElement):
    """The bump stops of a vehicle along a run (module docstring).

    Parameters
    ----------
    data : Clearances
        The stops at the vehicle's values (:func:`clearances_of`).
    force : numpy.ndarray, shape (N, n)
        How a generalized force on the coordinates enters the state equation
        (``FirstOrderForm.force``).
    u : numpy.ndarray, shape (steps + 1, m)
        The inputs at every step (the deflections' input part is ``h . u``).
    """

    kind = "bump stops"

    def __init__(self, data: Clearances, force: np.ndarray, u: np.ndarray):
        self.data, self.force, self.u = data, force, u
        size, n = force.shape
        self.rows = np.zeros((data.count, size))
        self.rows[:, :n] = data.gradient
        self.offset = np.ascontiguousarray(u @ data.inputs.T, dtype=float)

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"stop_{name}" for name in self.data.names)

    @property
    def reads(self) -> np.ndarray:
        return np.flatnonzero(np.any(self.rows != 0, axis=0))

    def directions(self) -> np.ndarray:
        n = self.data.gradient.shape[1]
        columns = [self.force[:, :n] @ row[:n] for row in self.rows]
        return np.column_stack(columns) if columns else np.zeros((self.force.shape[0], 0))

    def law(self, first: int) -> BumpStopLaw:
        index, coefficient = sparse_rows(self.rows)
        d = self.data
        return BumpStopLaw(first, index, coefficient, self.offset,
                           *(np.ascontiguousarray(a, dtype=float) for a in (d.gap, d.stiffness, d.progressive)))

    def deflections(self, x: np.ndarray, k: int) -> np.ndarray:
        """The deflections of the stops at state ``x`` and step ``k``."""
        return self.data.gradient @ x[: self.data.gradient.shape[1]] + self.data.inputs @ self.u[k]

    def _force(self, delta: np.ndarray) -> np.ndarray:
        d = self.data
        return -clearance_force(delta, d.gap, d.stiffness, d.progressive)

    def forces(self, x: np.ndarray, k: int) -> np.ndarray:
        return self._force(self.deflections(x, k))

    def slopes(self, x: np.ndarray, k: int, forces: np.ndarray) -> np.ndarray:
        """A stop's force depends on its deflection only: a forward difference of it."""
        step = 1e-8
        delta = self.deflections(x, k)
        rate = (self._force(delta + step) - self._force(delta)) / step
        return rate[:, None] * self.rows

    def outputs(self, states: np.ndarray, history: np.ndarray) -> dict[str, np.ndarray]:
        forces = -self._force(states @ self.rows.T + self.offset[: states.shape[0]])  # (steps + 1, n_stops)
        return {name: forces[:, s] for s, name in enumerate(self.names)}

    def output_units(self) -> dict[str, str]:
        return dict.fromkeys(self.names, "N")


def bump_stops_of(vehicle, u: np.ndarray) -> BumpStopElement | None:
    """The bump stops of ``vehicle`` (a :class:`~express.numeric.statespace.VehicleModel`)
    along the inputs ``u`` (steps + 1, m), or None when it has none."""
    data = clearances_of(vehicle.equations, vehicle.values, vehicle.dofs)
    if data.count == 0:
        return None
    return BumpStopElement(data, vehicle.form.force, u)
