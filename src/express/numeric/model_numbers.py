"""Numbers of a model's records at parameter values: the rail numbers of a vehicle
(speed, wheelset data, station positions: :class:`RailNumbers`, compiled once) and
the lateral displacement of a point (:func:`point_lateral_row`).

An error names the item (file and line) and the missing name or the division by zero.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from express.base.diagnostics import ModelError, Problem
from express.numeric.compiled import CompiledExpressions

if TYPE_CHECKING:
    from express.assembly.equations import EquationsOfMotion
    from express.model.records import Model
    from express.rail.layout import RailLayout

__all__ = ["RailNumbers", "WheelsetData", "missing_problems", "model_numbers", "point_lateral_row"]


@dataclass(frozen=True)
class WheelsetData:
    """Numerical wheel/rail data of one wheelset.

    ``y`` and ``psi`` are the indices of its lateral and yaw DOFs in ``q``;
    ``station`` its position along the vehicle [m] (x of its body).
    """

    name: str
    y: int
    psi: int
    station: float
    f1: float
    f2: float
    conicity: float
    r0: float
    b: float
    flange_clearance: float
    rail_stiffness: float
    friction: float
    wheel_load: float



class RailNumbers:
    """The speed, the wheelsets' data and the station positions of a model, compiled
    once into one function of the parameter values (the layout does not depend on them)."""

    KEYS = ("f1", "f2", "conicity", "r0", "b", "flange_clearance", "rail_stiffness", "friction", "wheel_load")

    def __init__(
        self, model: Model, equations: EquationsOfMotion, layout: RailLayout, compiled: CompiledExpressions | None = None
    ):
        rail = model.rail
        assert rail is not None
        # (expression, item, what) of every number, for the compiled function and the errors
        self.uses = [(rail.speed, "rail", "speed")]
        self.wheelsets = []
        for wheelset in rail.wheelsets:
            name = wheelset.body
            self.wheelsets.append((name, equations.dofs.index(f"{name}.y"), equations.dofs.index(f"{name}.rz")))
            self.uses.append((model.body(name).position[0], f"body {name}", "position"))
            self.uses += [(getattr(wheelset, key), f"wheelset {name}", key) for key in self.KEYS]
        self.uses += [(station.position, "station", "position") for station in layout.stations]
        if compiled is None or compiled.size != len(self.uses):  # compiled: read from the derivation cache
            compiled = CompiledExpressions([expression for expression, _, _ in self.uses])
        self.compiled = compiled

    @classmethod
    def of_wheelsets(cls, wheelsets: tuple[tuple[str, int, int], ...], compiled: CompiledExpressions) -> RailNumbers:
        """The numbers of a vehicle read from the cache: ``(name, y, psi)`` of every
        wheelset and the compiled numbers, no model (evaluated at the values it was
        stored with, which gave numbers before)."""
        numbers = cls.__new__(cls)
        numbers.uses, numbers.wheelsets, numbers.compiled = [], list(wheelsets), compiled
        return numbers

    def __call__(self, model: Model | None, values: Mapping[str, float]) -> tuple[float, tuple[WheelsetData, ...], np.ndarray]:
        """``(speed, wheelsets, station positions)`` at ``values``; a ModelError naming
        the item (file and line) and the missing name or the division by zero."""
        try:
            numbers = self.compiled(values).tolist()
        except (KeyError, ValueError):  # evaluated one by one for the precise error
            if model is None:
                raise
            numeric = model_numbers(model, values)
            numbers = [numeric(expression, item, what) for expression, item, what in self.uses]
        per = 1 + len(self.KEYS)
        wheelsets = tuple(
            WheelsetData(name, y, psi, numbers[1 + k * per], *numbers[2 + k * per : 1 + (k + 1) * per])
            for k, (name, y, psi) in enumerate(self.wheelsets)
        )
        return numbers[0], wheelsets, np.array(numbers[1 + len(wheelsets) * per :], dtype=float)


def missing_problems(model: Model, names: list[str]) -> list[Problem]:
    plural = "s" if len(names) > 1 else ""
    return [Problem(model.source, None, "parameters", f"no value for parameter{plural} {', '.join(names)}")]


def model_numbers(model: Model, values: Mapping[str, float]):
    """``numeric(expression, item, what)``: the float value of a use of parameters,
    or a ModelError naming the item (with its file and line) and the missing name."""

    from express.model.parameters import expression_value, undefined_name_problems

    def evaluate(expression, item: str = "", what: str = "") -> float:
        try:
            return expression_value(expression, values)
        except KeyError as error:
            name = error.args[0]
            raise ModelError(undefined_name_problems(model, [name]) or missing_problems(model, [name])) from None
        except ValueError as error:
            raise ModelError([Problem(model.source, None, f"{item} {what}".strip(), str(error))]) from None

    return evaluate


def point_lateral_row(model: Model, dofs: EquationsOfMotion | tuple[str, ...], body_id: str, offset) -> np.ndarray:
    """Row vector giving the lateral displacement of a point on a body from ``q``.

    ``u_y = y + rz lx - rx lz`` in the body's track frame (shape (n,)); ``dofs`` are the
    coordinates (a vehicle's :attr:`VehicleModel.dofs`, or equations for theirs).
    """
    if not isinstance(dofs, tuple):  # the equations
        dofs = dofs.dofs
    numeric = model_numbers(model, model.values())
    body = model.body(body_id)
    lx = numeric(offset[0], f"body {body_id}", "offset")
    lz = numeric(offset[2], f"body {body_id}", "offset")
    row = np.zeros(len(dofs))
    for dof, coefficient in (("y", 1.0), ("rz", lx), ("rx", -lz)):
        name = f"{body.id}.{dof}"
        if dof in body.dofs and name in dofs:
            row[dofs.index(name)] += coefficient
    return row
