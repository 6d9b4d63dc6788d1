"""How the linear analyses see the nonlinear force elements, chosen (issue 31, item 6).

The symbolic matrices hold every nonlinear suspension element at its **tangent at the
static state**: a friction element stuck (its pre-slip spring ``k`` in ``K``), a
characteristic its slope at zero deflection (in ``K``) or velocity (in ``C``).  That is
the default.  The other two choices replace, element by element, that tangent by an
equivalent linear spring and damper along the element's own deflection
``delta = g . q + h . u``::

    K += (k_eq - k_t) g g^T,   P -= (k_eq - k_t) g h^T
    C += (c_eq - c_t) g g^T,   Pd -= (c_eq - c_t) g h^T

- **equivalent** — the describing function at a stated harmonic motion of every element,
  amplitude ``X`` (``angle`` for rotational elements) at frequency ``f``: a friction
  element ``k_eq = a(X)``, ``c_eq = b(X) / (2 pi f)``; a spring characteristic
  ``k_eq = a(X)``; a damper characteristic ``c_eq = a(2 pi f X)`` in velocity;
- **statistical** — Gaussian at each element's own rms deflection ``s`` and rate ``s'``
  (:attr:`Linearisation.levels`, found by the ride's iteration to its fixed point,
  :mod:`express.analysis.ride.statistical`): a friction element Caughey's Rayleigh average
  ``<a>(s)``, ``c_eq = <b>(s) / w_e`` at the deflection's mean frequency ``w_e = s'/s``
  (Rice's, the narrow-band assumption Caughey's method rests on); a characteristic
  ``E[F']`` at ``s`` (spring) or ``s'`` (damper).

The closed forms are :mod:`express.forces.describing`.  A friction limit that follows a
load is taken at its static load (``mu |N0|``).  Bump stops and the wheel/rail contact
keep their own linearisations (a bump stop open at the static state; the contact's
equivalent conicity).  :func:`linearised` gives a :class:`LinearisedVehicle`, which every
linear analysis takes as it takes any vehicle, and which re-linearises itself after
:meth:`~LinearisedVehicle.with_values`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from typing import Any, NamedTuple

import numpy as np

from express.forces.describing import jenkin_describing, jenkin_statistical, table_describing, table_statistical
from express.forces.linearisation_choice import KINDS, Linearisation
from express.model.parameters import expression_value
from express.numeric.statespace import VehicleModel

__all__ = ["KINDS", "ElementLinearisation", "ElementRow", "Linearisation", "LinearisedVehicle", "element_linearisations",
           "linearised", "nonlinear_rows"]

class ElementRow(NamedTuple):
    """A nonlinear suspension element as the linearisations read it: its deflection
    ``gradient . q + inputs . u`` (shapes (n,), (m,)), ``kind`` ``"friction"`` or
    ``"characteristic"``, whether it is ``rotational`` and (a characteristic) acts on the
    ``velocity``; ``tangent`` the slope the matrices hold; a friction element's
    ``limit`` [N; N m] (at the static load); a characteristic's breakpoints ``xs``, ``fs``."""

    element: str
    kind: str
    gradient: np.ndarray
    inputs: np.ndarray
    rotational: bool
    velocity: bool
    tangent: float
    limit: float
    xs: np.ndarray
    fs: np.ndarray


@dataclass(frozen=True)
class ElementLinearisation:
    """How one element is seen: ``stiffness`` ``k_eq`` [N/m; N m/rad] and ``damping``
    ``c_eq`` [N s/m; N m s/rad] of its equivalent branch, in place of its ``tangent`` in
    ``matrix`` (``"K"`` or ``"C"``); at deflection ``level`` and ``rate`` (amplitudes, or
    rms for ``statistical``; nan at the tangent)."""

    element: str
    kind: str
    matrix: str
    tangent: float
    stiffness: float
    damping: float
    level: float = math.nan
    rate: float = math.nan

    def describe(self) -> str:
        """One line: the element's equivalent values."""
        unit = ("N m/rad", "N m s/rad") if self.kind.endswith("(rotational)") else ("N/m", "N s/m")
        held = f"{'k' if self.matrix == 'K' else 'c'} {self.tangent:.6g} {unit[0] if self.matrix == 'K' else unit[1]}"
        return (f"{self.element}: tangent {held} in {self.matrix}; k_eq {self.stiffness:.6g} {unit[0]}, "
                f"c_eq {self.damping:.6g} {unit[1]}")


def nonlinear_rows(vehicle: VehicleModel) -> tuple[ElementRow, ...]:
    """The friction elements and characteristics of ``vehicle`` as :class:`ElementRow`."""
    equations = vehicle.equations
    terms = [t for t in equations.element_terms if t.kind in ("friction", "characteristic")]
    column = {dof: i for i, dof in enumerate(vehicle.dofs)}
    values = vehicle.values
    rotational = {e.id: e.rotational for e in vehicle.model.elements} if vehicle.model is not None else {}
    rows = []
    for term in terms:
        g, h = np.zeros(len(vehicle.dofs)), np.zeros(len(equations.inputs))
        for dof, value in term.gradient.items():
            if dof in column:
                g[column[dof]] = expression_value(value, values)
        for name, value in term.inputs.items():
            h[equations.inputs.index(name)] = expression_value(value, values)
        number = {key: expression_value(value, values) for key, value in term.values.items()}
        if term.kind == "friction":
            limit = number["friction"] * abs(number["load_static"]) if "load_static" in number else number["friction"]
            rows.append(ElementRow(term.element, "friction", g, h, rotational.get(term.element, False), False,
                                   number["stiffness"], limit, np.zeros(0), np.zeros(0)))
        else:
            count = sum(1 for key in number if key.startswith("x"))
            xs = np.array([number[f"x{i}"] for i in range(count)])
            fs = np.array([number[f"f{i}"] for i in range(count)])
            rows.append(ElementRow(term.element, "characteristic", g, h, rotational.get(term.element, False),
                                   number["velocity"] == 1, number["tangent"], math.nan, xs, fs))
    return tuple(rows)


def _seen(row: ElementRow, spec: Linearisation) -> ElementLinearisation:
    matrix = "C" if row.velocity else "K"
    kind = row.kind + (" (rotational)" if row.rotational else "")
    if spec.kind == "tangent" or (spec.kind == "statistical" and row.element not in spec.levels):
        return ElementLinearisation(row.element, kind, matrix, row.tangent,
                                    0.0 if row.velocity else row.tangent, row.tangent if row.velocity else 0.0)
    if spec.kind == "equivalent":
        level = spec.angle if row.rotational else spec.amplitude
        w = 2.0 * math.pi * spec.frequency
        rate = w * level
    else:
        level, rate = (abs(float(x)) for x in spec.levels[row.element])
        w = rate / level if level > 0.0 else math.inf
    if row.kind == "friction":
        a, b = (jenkin_describing if spec.kind == "equivalent" else jenkin_statistical)(row.tangent, row.limit, level)
        return ElementLinearisation(row.element, kind, matrix, row.tangent, a, b / w if b and w > 0.0 else 0.0, level, rate)
    law = table_describing if spec.kind == "equivalent" else table_statistical
    if row.velocity:
        return ElementLinearisation(row.element, kind, matrix, row.tangent, 0.0, law(row.xs, row.fs, rate), level, rate)
    return ElementLinearisation(row.element, kind, matrix, row.tangent, law(row.xs, row.fs, level), 0.0, level, rate)


def element_linearisations(vehicle: VehicleModel, spec: Linearisation) -> tuple[ElementLinearisation, ...]:
    """How ``spec`` sees each nonlinear suspension element of ``vehicle``."""
    return tuple(_seen(row, spec) for row in nonlinear_rows(vehicle))


@dataclass(frozen=True)
class LinearisedVehicle(VehicleModel):
    """A :class:`~express.numeric.statespace.VehicleModel` whose nonlinear elements are
    seen as :attr:`linearisation` says (module docstring); :attr:`elements` their values,
    :attr:`tangent_vehicle` the vehicle at its tangents."""

    linearisation: Linearisation = field(default_factory=Linearisation)
    elements: tuple[ElementLinearisation, ...] = ()
    tangent_vehicle: Any = field(default=None, repr=False, compare=False)

    def with_values(self, changes: Mapping[str, float | str]) -> VehicleModel:
        """The same linearisation of the vehicle with some values changed (re-linearised:
        the limits and slopes follow)."""
        return linearised(self.tangent_vehicle.with_values(changes), self.linearisation)

    def with_model(self, model: Any) -> VehicleModel:
        return linearised(self.tangent_vehicle.with_model(model), self.linearisation)


def linearised(vehicle: VehicleModel, spec: Linearisation | None) -> VehicleModel:
    """``vehicle`` with its nonlinear elements seen as ``spec`` says; itself for the
    tangent (or no elements).

    Parameters
    ----------
    vehicle : VehicleModel
        A linearised vehicle is taken from its tangent vehicle again.
    spec : Linearisation or None
        None or ``tangent``: the symbolic matrices' own tangent.

    Returns
    -------
    VehicleModel
        A :class:`LinearisedVehicle` when any element is replaced; every linear
        analysis takes it as any vehicle, and :meth:`~LinearisedVehicle.with_values`
        re-linearises it.

    Examples
    --------
    >>> from express import Linearisation, linearised, load_vehicle
    >>> wagon = load_vehicle("examples/y25-wagon.toml")  # doctest: +SKIP
    >>> seen = linearised(wagon, Linearisation("equivalent", amplitude="2 mm"))  # doctest: +SKIP
    """
    base = vehicle.tangent_vehicle if isinstance(vehicle, LinearisedVehicle) else vehicle
    if spec is None or spec.kind == "tangent":
        return base
    rows = nonlinear_rows(base)
    if not rows:
        return base
    seen = tuple(_seen(row, spec) for row in rows)
    stiffness, damping = base.stiffness.copy(), base.damping_base.copy()
    forcing, rate = base.forcing_base.copy(), base.forcing_rate_matrix.copy()
    for row, found in zip(rows, seen, strict=True):
        dk = found.stiffness - (0.0 if row.velocity else row.tangent)
        dc = found.damping - (row.tangent if row.velocity else 0.0)
        g, h = row.gradient, row.inputs
        stiffness += dk * np.outer(g, g)
        forcing -= dk * np.outer(g, h)
        damping += dc * np.outer(g, g)
        rate -= dc * np.outer(g, h)
    kept = {f.name: getattr(base, f.name) for f in fields(VehicleModel) if f.init}
    kept.update(stiffness=stiffness, damping_base=damping, forcing_base=forcing, forcing_rate_matrix=rate)
    return LinearisedVehicle(**kept, linearisation=spec, elements=seen, tangent_vehicle=base)
