"""A model's derivation and its matrices as numbers.

This module owns the step from a model to the numbers of its vehicle: the derivation
(the equations and their compiled evaluator, from the derivation cache or derived and
stored there, ``docs/cache.md``), the matrices evaluated at parameter values with the
speed kept apart, and the series dampers an infinite damping locks. The vehicle record
built from them is :class:`express.numeric.statespace.VehicleModel`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from express.assembly.equations import STROKE, Matrices
from express.base.diagnostics import ArgumentError, ModelError, Problem
from express.numeric.compiled import CompiledMatrices, compile_matrices
from express.numeric.model_numbers import RailNumbers

if TYPE_CHECKING:  # the symbolic side (and SymPy) is imported where used: a warm load needs none of it
    from express.assembly.equations import EquationsOfMotion
    from express.model.records import Model

__all__ = ["evaluate_matrices", "locked_dampers", "matrices_at", "vehicle_derivation"]


def evaluate_matrices(equations: EquationsOfMotion, values: Mapping[str, float]) -> Matrices[np.ndarray]:
    """Every matrix of ``equations`` as float arrays at ``values`` (compiled once for
    this call; keep a :func:`express.numeric.compiled.compile_matrices` to evaluate often).

    Raises
    ------
    ArgumentError
        Naming the parameters that have no value, or for entries that are not finite.
    """
    compiled = compile_matrices(equations)
    return compiled(compiled.vector(values))


def vehicle_derivation(model: Model, with_rail: bool, key: str | None = None) -> tuple:
    """The derivation of ``model``: read from the derivation cache under ``key`` when
    there is an entry, else derived (entries expanded, not factored:
    :func:`express.assembly.generator.generate`) and stored under ``key``.

    Parameters
    ----------
    model : Model
        The model (its values are not used: the derivation is symbolic).
    with_rail : bool
        Include the wheel/rail and curve terms when the model has rail data.
    key : str, optional
        The derivation-cache key (:func:`express.io.cache.entry_key`); none: derived,
        not stored.

    Returns
    -------
    tuple
        ``(equations, evaluator, speed name, with_rail, layout, rail numbers)``: the
        :class:`~express.assembly.equations.EquationsOfMotion`, their
        :class:`~express.numeric.compiled.CompiledMatrices`, the speed parameter's name
        (or None), ``with_rail``, the :class:`~express.rail.layout.RailLayout` and the
        :class:`~express.numeric.model_numbers.RailNumbers` (both None without rail
        inputs): what :func:`express.numeric.statespace.vehicle_model` evaluates at
        the model's values.
    """
    import sympy as sp

    from express.io.cache import entry_damaged, read_entry, write_entry
    from express.numeric.derived import read_vehicle_entry, vehicle_entry
    from express.numeric.program import ProgramError, UnsupportedExpressionError
    from express.rail.build import generate_vehicle, rail_layout

    speed_name = None
    if with_rail and model.rail is not None and isinstance(model.rail.speed, sp.Symbol):
        speed_name = model.rail.speed.name
    cached = None
    payload = read_entry(key) if key else None
    if payload is not None:
        try:
            cached = read_vehicle_entry(payload, model)
            if cached.compiled.speed != (speed_name if speed_name in cached.compiled.parameters else None):
                raise ProgramError("another speed")
        except ProgramError:
            entry_damaged(key or "")
            cached = None
    if cached is not None:
        equations, evaluator = cached.equations, cached.compiled
    else:
        equations = generate_vehicle(model, with_rail=with_rail, readable=False).equations
        evaluator = compile_matrices(equations, speed_name)
    layout, rail_numbers = None, None
    if with_rail and model.rail is not None and equations.inputs:
        layout = rail_layout(model)
        rail_numbers = RailNumbers(model, equations, layout, cached.rail_numbers if cached else None)
    if key and cached is None:
        try:
            entry = vehicle_entry(equations, evaluator, rail_numbers.compiled if rail_numbers else None)
        except UnsupportedExpressionError:  # an entry with a function: derived every time
            entry = None
        if entry is not None:
            write_entry(key, entry)
    return equations, evaluator, speed_name, with_rail, layout, rail_numbers


def _speed_split(compiled: CompiledMatrices, values: Mapping[str, float]) -> tuple[Matrices[np.ndarray], np.ndarray, np.ndarray]:
    """``(matrices with C0 and P0, C1, P2)`` at ``values`` (the speed's value unused)."""
    vector = compiled.vector({**values, compiled.speed: 0.0} if compiled.speed else values)
    split = compiled.speed_split(vector)
    return split.matrices, split.damping_creep, split.forcing_speed2


def matrices_at(evaluator: CompiledMatrices, values: Mapping[str, float], locked: list[int], source: str) -> tuple:
    """The matrices at ``values``, the locked dampers' ``C`` infinite.

    Parameters
    ----------
    evaluator : CompiledMatrices
        The compiled matrices of the equations.
    values : mapping of str to float
        Parameter values (SI); the speed's value is not used.
    locked : list of int
        Indices of the strokes whose damping is infinite (:func:`locked_dampers`).
    source : str
        The model's file, for the error.

    Returns
    -------
    tuple
        ``(matrices with C0 and P0, C1, P2)``: the :class:`~express.assembly.equations.Matrices`
        at zero speed, the creep damping ``C1`` [N s] and the speed-squared forcing
        ``P2`` of ``C(v) = C0 + C1 / v`` and ``P(v) = P0 + P2 v**2``.

    Raises
    ------
    ModelError
        For values the matrices cannot be evaluated at (missing, not finite).
    """
    try:
        base, c1, p2 = _speed_split(evaluator, values)
    except ArgumentError as error:
        raise ModelError([Problem(source, None, "parameters", str(error))]) from None
    for i in locked:
        base["C"][i, i] = np.inf
    return base, c1, p2


def locked_dampers(model: Model, equations: EquationsOfMotion, values: dict[str, float]) -> tuple[dict[str, float], list[int]]:
    """Values with every infinite damping replaced by 1 for the evaluation, and the
    strokes of the series elements whose damping has such a parameter (locked by it) (their ``C`` entry is
    set back to inf for :func:`express.assembly.first_order.series_limits`).

    Parameters
    ----------
    model : Model
        The model whose series elements are looked at.
    equations : EquationsOfMotion
        Its equations (the strokes' indices are theirs).
    values : dict of str to float
        Parameter values (SI), ``inf`` for a locked damper.

    Returns
    -------
    tuple
        ``(values, locked)``: the values with each ``inf`` replaced by 1, and the indices
        of the locked strokes in ``equations.dofs``.
    """
    infinite = [name for name, value in values.items() if value == np.inf]
    if not infinite:
        return values, []
    locked = []
    for element in model.elements:
        name = f"{element.id}.{STROKE}"
        symbols: set = getattr(element.damping, "free_symbols", set())
        if element.series and name in equations.dofs and {s.name for s in symbols} & set(infinite):
            locked.append(equations.dofs.index(name))
    return {**values, **dict.fromkeys(infinite, 1.0)}, locked
