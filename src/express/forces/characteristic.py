"""Nonlinear characteristics: force against deflection or against velocity, piecewise
linear (issue 31, item 2), a force element of the time domain.

An element with a characteristic (:mod:`express.model.characteristics`) carries
``F(r)``, ``r`` its deflection ``delta = g . q + h . u`` or its rate
``delta' = g . q' + h . u'`` (``q'`` from the state, :attr:`StateForm.velocity`, the
inputs' part included), ``F`` linear between the breakpoints and beyond the ends with the
end segments' slopes.  The linear analyses see its tangent at the static state, ``kt =
dF/dr`` at ``r = 0``, in ``K`` or ``C`` (with its symbol); ``F(0)`` is the preload that
the static state balances.  So the element feeds back the difference from the tangent,

    z = kt r - (F(r) - F(0))      along g

and a run that never leaves the segment through ``r = 0`` is the linear run exactly.

The element reads the coordinates (and velocities) of each ``r``, acts along ``g``, has
no internal state, its compiled law is :class:`CharacteristicLaw`, its linearisation is
``dz/dr = kt - F'(r)`` and it reports ``force_<element>`` (``F`` [N; N m rotational]).
The feedback of a change of slope ``kt - F'`` is explicit in the march: the step must
resolve ``w = sqrt(|kt - F'| g M^-1 g)`` (deflection) or the rate ``|ct - F'| g M^-1 g``
(velocity), :meth:`CharacteristicElement.resolved_step`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import types
from numba.extending import overload

from express.base.kernels import kernel
from express.forces.element import ForceElement, sparse_rows
from express.forces.law import force_law
from express.model.parameters import expression_value

__all__ = ["RESOLVED", "RESOLVED_RATE", "CharacteristicElement", "CharacteristicLaw", "characteristic_elements_of",
           "table_force"]

#: ``w dt`` of the largest stiffness change a step may meet and still resolve it (a
#: bilinear spring's oscillation across its knee: 3.1e-4 of its amplitude at 0.02,
#: 1.4e-3 at 0.05, 8e-3 at 0.2; tests/test_forces_characteristic.py).
RESOLVED = 0.02
#: ``dt |dc| g M^-1 g`` of the largest damping change a step may meet (the blow-off
#: damper's energy per cycle: 1.2e-5 at 0.5, 9e-5 at 1, 8e-4 at 3).
RESOLVED_RATE = 0.5


class CharacteristicLaw(NamedTuple):
    """Characteristics for the compiled march: ``r = offset[k, e] + sum coefficient[e, :]
    x[places[e, :]]``, breakpoints ``xs[e, :counts[e]]``, ``fs[e, :counts[e]]``, the tangent
    ``tangent[e]`` and ``F(0)`` ``zero[e]``; forces into ``z[first:]``."""

    first: int
    places: np.ndarray
    coefficient: np.ndarray
    offset: np.ndarray
    xs: np.ndarray
    fs: np.ndarray
    counts: np.ndarray
    tangent: np.ndarray
    zero: np.ndarray


@kernel
def _segment(xs, row, count, r):
    """The segment ``i`` of table ``row`` (``xs[row, i] <= r < xs[row, i + 1]``, the end
    ones beyond the ends)."""
    low, high = 0, count - 2
    while low < high:  # bisection over the segments' starts
        middle = (low + high + 1) // 2
        if xs[row, middle] <= r:
            low = middle
        else:
            high = middle - 1
    return low


@kernel
def table_force(xs, fs, row, count, r):
    """``(F(r), F'(r))`` of the piecewise-linear table ``row`` of ``xs``, ``fs`` (shape
    (n, breakpoints), its first ``count`` used; module docstring).  The tables are indexed
    in place: a row view handed to a compiled call costs more than the look-up."""
    i = _segment(xs, row, count, r)
    slope = (fs[row, i + 1] - fs[row, i]) / (xs[row, i + 1] - xs[row, i])
    return fs[row, i] + slope * (r - xs[row, i]), slope


@kernel
def characteristic_forces(x, k, law, z):
    """``z = kt r - (F(r) - F(0))`` of every element into ``z[law.first:]``."""
    for e in range(law.tangent.size):
        r = law.offset[k, e]
        for i in range(law.places.shape[1]):
            r += law.coefficient[e, i] * x[law.places[e, i]]
        force, _ = table_force(law.xs, law.fs, e, law.counts[e], r)
        z[law.first + e] = law.tangent[e] * r - (force - law.zero[e])


@overload(force_law)
def _characteristic_law(x, k, law, z, record, commit):
    if isinstance(law, types.BaseNamedTuple) and law.instance_class is CharacteristicLaw:
        return lambda x, k, law, z, record, commit: characteristic_forces(x, k, law, z)
    return None


class CharacteristicElement(ForceElement):
    """The characteristic elements of a vehicle along a run (module docstring).

    Parameters
    ----------
    names : tuple of str
        The elements' ids.
    rows : numpy.ndarray, shape (n_e, N)
        ``r`` of each element over the state (its deflection, or its rate).
    offset : numpy.ndarray, shape (steps + 1, n_e)
        The inputs' part of each ``r`` at every step.
    gradient : numpy.ndarray, shape (n_e, n)
        ``g`` of each deflection over the coordinates (where the force acts).
    xs, fs : numpy.ndarray, shape (n_e, P)
        The breakpoints [m or m/s; N], padded beyond ``count``.
    count : numpy.ndarray of int, shape (n_e,)
    tangent : numpy.ndarray, shape (n_e,)
        ``kt`` [N/m or N s/m].
    velocity, rotational : tuple of bool
        Each element's ``r`` is a rate / it acts on a rotation.
    force : numpy.ndarray, shape (N, n)
        How a generalized force enters the state equation (``StateForm.force``).
    mass_inverse : numpy.ndarray, shape (n, n)
        ``M_DD^-1`` (``StateForm.mass_inverse``), for the resolved step.
    """

    kind = "characteristic"

    def __init__(self, names: tuple[str, ...], rows: np.ndarray, offset: np.ndarray, gradient: np.ndarray,
                 xs: np.ndarray, fs: np.ndarray, count: np.ndarray, tangent: np.ndarray, velocity: tuple[bool, ...],
                 rotational: tuple[bool, ...], force: np.ndarray, mass_inverse: np.ndarray):
        self.ids, self.rows, self.offset, self.gradient = names, rows, np.ascontiguousarray(offset, dtype=float), gradient
        self.xs, self.fs, self.count = np.ascontiguousarray(xs, float), np.ascontiguousarray(fs, float), count
        self.tangent, self.velocity, self.rotational = np.ascontiguousarray(tangent, float), velocity, rotational
        self.force, self.mass_inverse = force, mass_inverse
        self.zero = np.array([table_force(self.xs, self.fs, e, int(count[e]), 0.0)[0] for e in range(len(names))])

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(f"characteristic_{name}" for name in self.ids)

    @property
    def reads(self) -> np.ndarray:
        return np.flatnonzero(np.any(self.rows != 0, axis=0))

    def directions(self) -> np.ndarray:
        return np.column_stack([self.force @ row for row in self.gradient])

    def law(self, first: int) -> CharacteristicLaw:
        places, coefficient = sparse_rows(self.rows)
        return CharacteristicLaw(first, places, coefficient, self.offset, self.xs, self.fs,
                                 np.ascontiguousarray(self.count, dtype=np.int64), self.tangent, self.zero)

    def values(self, x: np.ndarray, k: int) -> np.ndarray:
        """``r`` of every element at state ``x`` and step ``k``."""
        return self.rows @ x + self.offset[k]

    def _table(self, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        pairs = [table_force(self.xs, self.fs, e, int(self.count[e]), float(r[e])) for e in range(r.size)]
        return np.array([p[0] for p in pairs]), np.array([p[1] for p in pairs])

    def forces(self, x: np.ndarray, k: int) -> np.ndarray:
        r = self.values(x, k)
        return self.tangent * r - (self._table(r)[0] - self.zero)

    def slopes(self, x: np.ndarray, k: int, forces: np.ndarray) -> np.ndarray:
        """``(kt - F'(r)) dr/dx``."""
        return (self.tangent - self._table(self.values(x, k))[1])[:, None] * self.rows

    def resolved_step(self, mass: np.ndarray) -> float | None:
        """The step that resolves the largest change of slope of every element against its
        tangent (module docstring): :data:`RESOLVED` of ``1/w`` for a spring,
        :data:`RESOLVED_RATE` of ``1/rate`` for a damper."""
        compliance = np.maximum(np.einsum("ei,ij,ej->e", self.gradient, self.mass_inverse, self.gradient), 0.0)
        steps = []
        for e in range(len(self.ids)):
            count = int(self.count[e])
            slopes = np.diff(self.fs[e, :count]) / np.diff(self.xs[e, :count])
            change = float(np.max(np.abs(slopes - self.tangent[e]))) * compliance[e]
            if change > 0:
                steps.append(RESOLVED_RATE / change if self.velocity[e] else RESOLVED / np.sqrt(change))
        return min(steps) if steps else None

    def outputs(self, states: np.ndarray, history: np.ndarray) -> dict[str, np.ndarray]:
        r = states @ self.rows.T + self.offset[: states.shape[0]]
        found = {}
        for e, name in enumerate(self.ids):
            count = int(self.count[e])
            found[f"force_{name}"] = np.interp(r[:, e], self.xs[e, :count], self.fs[e, :count])
            for end, (a, b) in ((r[:, e] < self.xs[e, 0], (0, 1)), (r[:, e] > self.xs[e, count - 1], (count - 2, count - 1))):
                slope = (self.fs[e, b] - self.fs[e, a]) / (self.xs[e, b] - self.xs[e, a])
                found[f"force_{name}"][end] = self.fs[e, a] + slope * (r[end, e] - self.xs[e, a])
        return found

    def output_units(self) -> dict[str, str]:
        return {f"force_{name}": "N*m" if rotational else "N" for name, rotational in zip(self.ids, self.rotational, strict=True)}


def characteristic_elements_of(vehicle, u: np.ndarray, u_rate: np.ndarray) -> CharacteristicElement | None:
    """The characteristic elements of ``vehicle`` (a :class:`~express.numeric.statespace.VehicleModel`)
    along the inputs ``u`` and their rates ``u_rate`` (steps + 1, m), or None when it has none."""
    equations = vehicle.equations
    terms = [t for t in equations.element_terms if t.kind == "characteristic"]
    if not terms:
        return None
    form = vehicle.form
    column = {dof: i for i, dof in enumerate(vehicle.dofs)}
    n, m, size = len(vehicle.dofs), len(equations.inputs), form.size
    values = vehicle.values
    gradient, inputs = np.zeros((len(terms), n)), np.zeros((len(terms), m))
    for e, term in enumerate(terms):
        for dof, value in term.gradient.items():
            if dof in column:
                gradient[e, column[dof]] = expression_value(value, values)
        for name, value in term.inputs.items():
            inputs[e, equations.inputs.index(name)] = expression_value(value, values)
    velocity = tuple(expression_value(t.values["velocity"], values) == 1 for t in terms)
    rows, offset = np.zeros((len(terms), size)), np.zeros((u.shape[0], len(terms)))
    for e in range(len(terms)):
        if velocity[e]:  # delta' = g q' + h u', q' = V x + Vu u + Vr u'
            rows[e] = gradient[e] @ form.velocity
            offset[:, e] = u @ (gradient[e] @ form.velocity_input) + u_rate @ (gradient[e] @ form.velocity_rate + inputs[e])
        else:
            rows[e, :n] = gradient[e]
            offset[:, e] = u @ inputs[e]
    counts = np.array([sum(1 for key in t.values if key.startswith("x")) for t in terms], dtype=np.int64)
    xs, fs = np.zeros((len(terms), int(counts.max()))), np.zeros((len(terms), int(counts.max())))
    for e, term in enumerate(terms):
        for i in range(int(counts[e])):
            xs[e, i] = expression_value(term.values[f"x{i}"], values)
            fs[e, i] = expression_value(term.values[f"f{i}"], values)
        xs[e, counts[e]:] = xs[e, counts[e] - 1]  # padding, never read
        fs[e, counts[e]:] = fs[e, counts[e] - 1]
    tangent = np.array([expression_value(t.values["tangent"], values) for t in terms])
    kinds = {el.id: el.rotational for el in vehicle.model.elements} if vehicle.model is not None else {}
    return CharacteristicElement(tuple(t.element for t in terms), rows, offset, gradient, xs, fs, counts, tangent,
                                 velocity, tuple(kinds.get(t.element, False) for t in terms), form.force,
                                 form.mass_inverse)
