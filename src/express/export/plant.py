"""The vehicle's standard state space at one speed (``z' = A z + B u``, ``y = C z + D u``),
the input rates removed exactly (:mod:`express.export.linear_system` says how); the one
definition that the exports and the control plant
(:mod:`express.export.track_system`) build on."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from express.base.data import DataRecord, columns_frame, variable, xarray
from express.base.diagnostics import ArgumentError
from express.numeric.statespace import VehicleModel

__all__ = ["LinearSystem", "check_speed", "linear_system"]


@dataclass(frozen=True, repr=False)
class LinearSystem(DataRecord):
    """A standard state space ``z' = A z + B u``, ``y = C z + D u`` with names.

    Attributes
    ----------
    A, B, C, D : numpy.ndarray
        Shapes (s, s), (s, m), (p, s), (p, m): (2n, 2n), (2n, m), (2n, 2n), (2n, m) for
        every DOF and rate out and every model input in.
    states, inputs, outputs : tuple of str
        Names: outputs are the DOFs then their rates (``W1.y``, ..., ``W1.y_dot``);
        the states carry the same names (the state equals the output when ``u = 0``).
    speed : float
        Speed the matrices were evaluated at [m/s].

    As data: :meth:`to_xarray` holds the four matrices over ``state`` / ``from_state`` /
    ``input`` / ``output`` (units mixed, SI: each entry's is that of its row over its
    column's); :meth:`to_pandas` is one table of the nonzero entries (matrix, row,
    column, value).
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    outputs: tuple[str, ...]
    speed: float

    def to_xarray(self) -> Any:
        """``A``, ``B``, ``C``, ``D`` as an :class:`xarray.Dataset` with labelled dimensions."""
        mixed = "SI (row unit / column unit)"
        data = {"A": variable(self.A, ("state", "from_state"), mixed, "state matrix"),
                "B": variable(self.B, ("state", "input"), mixed, "input matrix"),
                "C": variable(self.C, ("output", "from_state"), mixed, "output matrix"),
                "D": variable(self.D, ("output", "input"), mixed, "feedthrough matrix"),
                "speed": variable(self.speed, (), "m/s", "speed")}
        coords = {"state": list(self.states), "from_state": list(self.states), "input": list(self.inputs),
                  "output": list(self.outputs)}
        return xarray().Dataset(data, coords=coords)

    def to_pandas(self) -> Any:
        """The nonzero entries of the four matrices, one row each: ``matrix``, ``row``,
        ``column`` (names) and ``value`` (SI)."""
        columns: dict[str, list] = {"matrix": [], "row": [], "column": [], "value": []}
        for name, matrix, rows, cols in (("A", self.A, self.states, self.states), ("B", self.B, self.states, self.inputs),
                                         ("C", self.C, self.outputs, self.states), ("D", self.D, self.outputs, self.inputs)):
            for i, j in zip(*np.nonzero(matrix), strict=True):
                columns["matrix"].append(name)
                columns["row"].append(rows[i])
                columns["column"].append(cols[j])
                columns["value"].append(float(matrix[i, j]))
        return columns_frame(columns, {"value": "SI"})

    def _summary(self) -> list[str]:
        return [f"{len(self.states)} states, {len(self.inputs)} inputs, {len(self.outputs)} outputs "
                f"at {self.speed:.3f} m/s ({self.speed * 3.6:.1f} km/h)"]


def linear_system(vehicle: VehicleModel, speed: float) -> LinearSystem:
    """The vehicle's linear model at ``speed`` [m/s; or a quantity] with the input rates removed.

    Raises
    ------
    ArgumentError
        If ``speed`` is not a positive finite speed (a ``ValueError``).
    """
    speed = check_speed(speed)
    a = vehicle.state_matrix(speed)
    b = vehicle.input_matrix(speed)
    bd = vehicle.input_rate_matrix(speed)
    # state [q; q_D'] (express.assembly.first_order): series elements' strokes have no rate state
    names = tuple(vehicle.dofs) + tuple(f"{vehicle.dofs[i]}_dot" for i in vehicle.form.massive)
    return LinearSystem(
        A=a,
        B=b + a @ bd,
        C=np.eye(a.shape[0]),
        D=bd.copy(),
        states=names,
        inputs=tuple(vehicle.inputs),
        outputs=names,
        speed=float(speed),
    )


def check_speed(speed: Any) -> float:
    """``speed`` in SI [m/s]: a number (SI) or a quantity (``"95 km/h"``, pint).

    Raises
    ------
    ArgumentError
        Not a positive finite speed (an :class:`InputError`, a ``ValueError``).
    """
    from express.base.arguments import si_argument

    value = float(speed) if isinstance(speed, (int, float, np.floating)) else si_argument(speed, "speed", "speed")
    if not (math.isfinite(value) and value > 0):
        raise ArgumentError(f"speed {speed!r}: must be a positive number of m/s")
    return value
