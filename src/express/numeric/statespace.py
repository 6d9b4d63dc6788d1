"""Numerical state space ``x' = A(v) x + B(v) u + Bd u'`` (paper eqs. 14-16).

The symbolic matrices are evaluated once at the model's parameter values, keeping
the speed ``v`` apart: ``C = C0 + C1 / v`` (creep damping) and ``P = P0 + P2 v**2``
(cant deficiency), so that ``A(v)`` and ``B(v)`` at a new speed cost a few array
operations.  ``M`` is inverted numerically (never symbolically) and refused with a
clear error when it is singular.

Examples
--------
>>> from express.io import load_model
>>> vehicle = vehicle_model(load_model("examples/forced-steering.toml"))
>>> vehicle.state_matrix(30.0).shape, vehicle.input_matrix(30.0).shape
((48, 48), (48, 22))
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from express.assembly.equations import STROKE
from express.assembly.first_order import FirstOrderError, IndefiniteMassError, StateForm, series_limits, state_form
from express.base.diagnostics import ArgumentError, ModelError, Problem
from express.base.names import did_you_mean
from express.base.threads import limited_blas
from express.base.units import KMH
from express.numeric.compiled import CompiledMatrices, EigenBlocks
from express.numeric.derivation import locked_dampers, matrices_at, vehicle_derivation
from express.numeric.facts import VehicleFacts, facts_of
from express.numeric.model_numbers import RailNumbers, WheelsetData, missing_problems, point_lateral_row
from express.numeric.warm import (
    VehicleOrigin,
    WarmVehicle,
    find_warm,
    read_warm_vehicle,
    reemit,
    warm_entry,
    write_warm_entry,
)
from express.rail.layout import RailLayout

if TYPE_CHECKING:  # the symbolic side (and SymPy) is imported where used: a warm load needs none of it
    from express.assembly.equations import EquationsOfMotion
    from express.model.records import Model

__all__ = [
    "Evaluation",
    "SingularMassError",
    "VehicleModel",
    "WheelsetData",
    "load_vehicle",
    "point_lateral_row",
    "vehicle_model",
]


class SingularMassError(ModelError):
    """M cannot be inverted (a DOF without mass or inertia)."""


@dataclass(frozen=True)
class Evaluation:
    """How a :class:`VehicleModel` was evaluated, kept for :meth:`VehicleModel.with_values`.

    Attributes
    ----------
    evaluator : CompiledMatrices
        The matrices compiled once for the model.
    speed_name : str or None
        The speed parameter kept apart (``rail.speed``), when the model has one.
    rail_numbers : RailNumbers or None
        The wheelsets' numbers at given values, when the model has rail data.
    """

    evaluator: CompiledMatrices
    speed_name: str | None = None
    rail_numbers: Any = None


@dataclass(frozen=True)
class VehicleModel:
    """A model's numerical equations of motion, with the speed kept apart.

    Attributes
    ----------
    origin : VehicleOrigin
        The symbolic equations and model it was evaluated from (built on first use
        for a vehicle read from the derivation cache): :attr:`equations`, :attr:`model`.
    values : dict of str to float
        Parameter values used (SI).
    speed : float
        The model's own speed ``v`` [m/s] (nan when it has none).
    mass, stiffness : numpy.ndarray
        The vehicle's M and K, shape (n, n).
    damping_base, damping_creep : numpy.ndarray
        Damping ``C(v) = damping_base + damping_creep / v`` (creep damping falls with
        speed), shape (n, n); see :meth:`damping`.
    forcing_base, forcing_speed2 : numpy.ndarray
        Forcing ``P(v) = forcing_base + forcing_speed2 v**2`` (cant deficiency),
        shape (n, m); see :meth:`forcing`.
    forcing_rate_matrix : numpy.ndarray
        ``Pd``, multiplying the input rates ``u'``, shape (n, m); see :meth:`forcing_rate`.
    layout : RailLayout or None
        Meaning of the rail inputs.
    wheelsets : tuple of WheelsetData
    station_positions : numpy.ndarray
        x position of every station of ``layout`` [m], shape (len(layout.stations),).
    inactive : tuple of str
        Strokes of series elements at a limit, removed from the coordinates.
    evaluation : Evaluation or None
        How it was evaluated (set by :func:`vehicle_model` and :func:`load_vehicle`).
    form : StateForm
        The state-space form ``x = [q; q_D']`` (derived from the matrices).
    mass_inverse : numpy.ndarray
        ``M^-1`` of the coordinates with mass (derived).
    """

    origin: VehicleOrigin = field(repr=False, compare=False)
    values: dict[str, float]
    speed: float
    mass: np.ndarray
    stiffness: np.ndarray
    damping_base: np.ndarray
    damping_creep: np.ndarray
    forcing_base: np.ndarray
    forcing_speed2: np.ndarray
    forcing_rate_matrix: np.ndarray
    layout: RailLayout | None = None
    wheelsets: tuple[WheelsetData, ...] = ()
    station_positions: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: strokes of series elements at a limit, removed from the coordinates
    #: (:func:`express.assembly.first_order.series_limits`)
    inactive: tuple[str, ...] = ()
    evaluation: Evaluation | None = field(default=None, repr=False, compare=False)
    form: StateForm = field(init=False, repr=False, compare=False)
    mass_inverse: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        # x = [q; q_D'] (express.assembly.first_order): [q; q'] unless series elements add
        # first-order coordinates (damper strokes)
        form = _state_form(self)
        object.__setattr__(self, "form", form)
        object.__setattr__(self, "mass_inverse", form.mass_inverse)

    @property
    def equations(self) -> EquationsOfMotion:
        """The symbolic equations it was evaluated from."""
        return self.origin.equations

    @property
    def model(self) -> Model:
        """The model it was evaluated from (needed by :meth:`with_values`)."""
        return self.origin.model

    @property
    def name(self) -> str:
        """The model's name."""
        return self.origin.name

    @cached_property
    def facts(self) -> VehicleFacts:
        """What the analyses read of the model, as numbers (:mod:`express.numeric.facts`)."""
        return self.origin.facts if self.origin.facts is not None else facts_of(self.model, self.values)

    @property
    def dofs(self) -> tuple[str, ...]:
        """The coordinates: the equations' DOFs without the :attr:`inactive` strokes."""
        if not self.inactive:
            return self.origin.dofs
        return tuple(dof for dof in self.origin.dofs if dof not in self.inactive)

    @property
    def inputs(self) -> tuple[str, ...]:
        return self.origin.inputs

    @property
    def n(self) -> int:
        """Number of DOFs."""
        return len(self.dofs)

    def dof_index(self, name: str) -> int:
        """Index of a DOF by name (``ValueError`` naming the DOFs if unknown)."""
        try:
            return self.dofs.index(name)
        except ValueError:
            raise ArgumentError(f"unknown DOF {name!r}{did_you_mean(name, self.dofs)} (DOFs: {', '.join(self.dofs)})") from None

    def damping(self, v: float) -> np.ndarray:
        """The vehicle's damping matrix ``C(v)`` at speed ``v`` [m/s], shape (n, n)."""
        return self.damping_base + self.damping_creep / v

    def forcing(self, v: float) -> np.ndarray:
        """The vehicle's input matrix ``P(v)`` at speed ``v`` [m/s], shape (n, m)."""
        return self.forcing_base + self.forcing_speed2 * v**2

    def forcing_rate(self, v: float) -> np.ndarray:
        """The matrix ``Pd`` of the input rates ``u'`` at speed ``v`` [m/s], shape (n, m).

        Independent of the speed in the paper's models; takes it like the others."""
        return self.forcing_rate_matrix

    def state_matrix(self, v: float) -> np.ndarray:
        """State-space ``A(v)`` at speed ``v`` [m/s], shape (N, N), state ``[q; q']``
        (N = 2n; with series elements ``[q; q_D']``, N = n + n_D: their strokes are
        first-order coordinates, :mod:`express.assembly.first_order`)."""
        return self.form.state_matrix(v)

    def input_matrix(self, v: float) -> np.ndarray:
        """State-space ``B(v)`` of the inputs ``u`` at speed ``v`` [m/s], shape (N, m)."""
        return self.form.input_matrix(v)

    def input_rate_matrix(self, v: float) -> np.ndarray:
        """State-space ``Bd`` of the input rates ``u'`` at speed ``v`` [m/s], shape (N, m)."""
        return self.form.bd.copy()

    @limited_blas
    def with_values(self, changes: Mapping[str, float | str]) -> VehicleModel:
        """The same vehicle with some parameter values changed, re-evaluated
        numerically from the compiled matrices (about a millisecond; no regeneration).

        Every derived parameter follows (:func:`express.model.parameters.with_values`): a
        new mass changes the wheel load, the creep coefficients and all they feed.

        Parameters
        ----------
        changes : mapping of str to float or str
            Floats in SI, or texts with a unit as on the command line (``"60 t"``).

        Examples
        --------
        >>> from express.io import load_model
        >>> vehicle = vehicle_model(load_model("examples/conventional.toml"))
        >>> vehicle.with_values({"Gamma": 0.2}).wheelsets[0].conicity
        0.2
        """
        if self.origin.cached:  # read from the cache: through the symbolic model
            return self.origin.twin().with_values(changes)
        if self.evaluation is None:
            raise ArgumentError("this VehicleModel has no model to re-evaluate")
        from express.model.parameters import with_values

        return self.with_model(with_values(self.model, changes))

    def with_model(self, model: Model) -> VehicleModel:
        """The same equations at the (evaluated) values of ``model``, a model of the same
        equations (another wheel profile in its ``"profiles"`` node: the wear prediction)."""
        if self.origin.cached:
            return self.origin.twin().with_model(model)
        assert self.evaluation is not None
        return _evaluate_vehicle(model, self.equations, self.evaluation.evaluator, self.evaluation.speed_name,
                                 self.layout is not None, self.layout, self.evaluation.rail_numbers)

    def __repr__(self) -> str:
        speed = f", v = {self.speed / KMH:.6g} km/h" if self.speed == self.speed else ""
        return (
            f"<VehicleModel {self.name!r}: {self.n} DOFs, {len(self.inputs)} inputs, "
            f"{len(self.wheelsets)} wheelsets{speed}>"
        )

    @cached_property
    def eigen_blocks(self) -> EigenBlocks:
        """``A(v)`` split once into the diagonal blocks that carry its eigenvalues
        (:class:`express.numeric.compiled.EigenBlocks`: exact; one block when nothing splits)."""
        return EigenBlocks(self.form.a0, self.form.a1)

    @limited_blas
    def eigenvalues(self, v: float) -> np.ndarray:
        """Eigenvalues of ``A(v)`` [1/s], complex, shape (N,), block after block
        (:attr:`eigen_blocks`; the same set as :func:`numpy.linalg.eigvals` of
        :meth:`state_matrix`, in another order)."""
        return self.eigen_blocks.eigenvalues(np.array([float(v)]))[0]


def _state_form(vehicle: VehicleModel) -> StateForm:
    if not vehicle.dofs:  # an empty file, or bodies without DOFs
        source = vehicle.origin.source
        raise ModelError([Problem(source, None, "model", "no DOFs: no body has a DOF, there is nothing to analyse")])
    # only a series element's damper stroke may be massless (a first-order coordinate);
    # a body DOF without mass (mc = 0) would silently become one (issue 17)
    diagonal = np.diag(vehicle.mass)
    massless = [dof for dof, m in zip(vehicle.dofs, diagonal, strict=True)
                if not m > 0 and not dof.endswith(f".{STROKE}")]
    if massless:
        source = vehicle.origin.source
        plural = len(massless) > 1
        raise SingularMassError([Problem(
            source, None, "mass matrix",
            f"M cannot be inverted: DOF{'s' if plural else ''} {', '.join(massless)} ha{'ve' if plural else 's'} "
            "zero (or negative) mass or inertia; give it a mass or remove the DOF",
        )])
    try:
        return state_form(
            vehicle.mass, vehicle.damping_base, vehicle.damping_creep, vehicle.stiffness,
            vehicle.forcing_base, vehicle.forcing_speed2, vehicle.forcing_rate_matrix,
        )
    except FirstOrderError as error:
        if isinstance(error, IndefiniteMassError):
            _invert_mass(vehicle.mass, vehicle.dofs, vehicle.origin.source)
        source = vehicle.origin.source
        dofs = ", ".join(vehicle.dofs[i] for i in error.bad)
        raise SingularMassError(
            [Problem(source, None, "mass matrix", f"M cannot be inverted: {error} ({dofs}); give it a mass or a damper")]
        ) from None


def _invert_mass(mass: np.ndarray, dofs: tuple[str, ...], source: str) -> np.ndarray:
    try:
        np.linalg.cholesky(mass)
    except np.linalg.LinAlgError:
        diagonal = np.diag(mass)
        bad = [dofs[i] for i in range(len(diagonal)) if not diagonal[i] > 0]
        what = (
            f"DOF{'s' if len(bad) > 1 else ''} {', '.join(bad)} ha{'ve' if len(bad) > 1 else 's'} "
            "zero (or negative) mass or inertia"
            if bad
            else "M is not positive definite"
        )
        raise SingularMassError(
            [Problem(source, None, "mass matrix", f"M cannot be inverted: {what}; give it a mass or remove the DOF")]
        ) from None
    return np.linalg.inv(mass)


@limited_blas
def vehicle_model(model: Model, *, with_rail: bool = True) -> VehicleModel:
    """Generate and evaluate a model's equations at its parameter values.

    Parameters
    ----------
    model : Model
        A model with values for every parameter (``--set`` applied already).
    with_rail : bool
        Include the wheel/rail and curve terms when the model has rail data.

    Returns
    -------
    VehicleModel

    Raises
    ------
    ModelError
        For missing parameter values or a singular mass matrix.
    """
    derivation = vehicle_derivation(model, with_rail)
    return _evaluate_vehicle(model, *derivation)


def _evaluate_vehicle(
    model, equations, evaluator, speed_name, with_rail=True, layout=None, rail_numbers_of=None
) -> VehicleModel:
    """The numerical vehicle at ``model``'s values (``layout``: the rail layout, which
    does not depend on the values, when known already)."""
    from express.model.parameters import undefined_name_problems

    values = model.values()
    missing = [name for name in equations.parameters if name not in values]
    if missing:
        raise ModelError(undefined_name_problems(model, missing) or missing_problems(model, missing))
    finite, locked = locked_dampers(model, equations, values)
    matrices = matrices_at(evaluator, finite, locked, model.source)
    wheelsets: tuple[WheelsetData, ...] = ()
    stations = np.zeros(0)
    speed = float("nan")
    rail_numbers = None
    if with_rail and model.rail is not None and equations.inputs:
        from express.rail.build import rail_layout

        layout = layout or rail_layout(model)
        rail_numbers = rail_numbers_of or RailNumbers(model, equations, layout)
        speed, wheelsets, stations = rail_numbers(model, values)
    else:
        layout = None
    origin = VehicleOrigin(model.name, model.source, equations.dofs, equations.inputs, equations=equations, model=model)
    return _assembled(origin, values, matrices, (speed, wheelsets, stations, layout),
                      Evaluation(evaluator, speed_name, rail_numbers))


def _assembled(origin: VehicleOrigin, values: dict[str, float], matrices: tuple, rail: tuple,
               evaluation: Evaluation) -> VehicleModel:
    """The vehicle of evaluated ``matrices`` (:func:`express.numeric.derivation.matrices_at`)
    and ``rail`` numbers ``(speed, wheelsets, station positions, layout)``, series
    elements at a limit removed."""
    base, c1, p2 = matrices
    speed, wheelsets, stations, layout = rail
    n, m = len(origin.dofs), len(origin.inputs)
    limits = series_limits(
        origin.dofs, base["M"], base["C"], c1, base["K"], base.get("P", np.zeros((n, m))), p2,
        base.get("Pd", np.zeros((n, m))), STROKE,
    )
    mass, damping, creep, stiffness, forcing, forcing2, forcing_rate = limits.matrices
    return VehicleModel(
        origin=origin,
        values=values,
        speed=speed,
        mass=mass,
        stiffness=stiffness,
        damping_base=damping,
        damping_creep=creep,
        forcing_base=forcing,
        forcing_speed2=forcing2,
        forcing_rate_matrix=forcing_rate,
        inactive=limits.removed,
        layout=layout,
        wheelsets=wheelsets,
        station_positions=stations,
        evaluation=evaluation,
    )


def _warm_vehicle(warm: WarmVehicle, source: str, twin: Callable[[], VehicleModel]) -> VehicleModel:
    """The vehicle of a warm entry (:mod:`express.numeric.warm`): the same numbers as
    :func:`_evaluate_vehicle` at the file's values, from the same programs."""
    matrices = matrices_at(warm.compiled, warm.values, [], source)
    speed, stations, rail_numbers = float("nan"), np.zeros(0), None
    wheelsets: tuple[WheelsetData, ...] = ()
    if warm.layout is not None and warm.rail_numbers is not None:
        rail_numbers = RailNumbers.of_wheelsets(warm.wheelsets, warm.rail_numbers)
        speed, wheelsets, stations = rail_numbers(None, warm.values)
    origin = VehicleOrigin(warm.name, source, warm.dofs, warm.inputs, twin=twin,
                           facts=replace(warm.facts, source=source))
    return _assembled(origin, dict(warm.values), matrices, (speed, wheelsets, stations, warm.layout),
                      Evaluation(warm.compiled, warm.speed_name, rail_numbers))


#: Derived vehicles by derivation-cache key (the bytes of every file read, the options):
#: derivation takes about a second, re-evaluation with other values about a
#: millisecond, so repeated in-process calls (scripts, tests, studies) reuse it.
_GENERATED: dict[str, VehicleModel] = {}
_GENERATED_CACHE_SIZE = 4


def load_vehicle(
    path: str | Path, overrides: Mapping[str, float | str] | None = None, *, with_rail: bool = True
) -> VehicleModel:
    """Read a model file once and return its numerical vehicle with ``overrides`` applied.

    The derivation (equations and compiled functions) comes from the derivation cache
    when the same files were derived before (:mod:`express.io.cache`,
    ``docs/cache.md``), and is reused within the process; the overrides are applied
    after it.

    Parameters
    ----------
    path : str or Path
        Model file (classic ``.exp`` or modern ``.toml``).
    overrides : mapping of str to float or str, optional
        Parameter values: floats in SI, or texts as on the command line, checked
        against the parameter's dimension (``"100 km/h"``, ``"4 MN/m"``; a bare
        number is SI except for a speed, which is km/h). Derived parameters follow.
    with_rail : bool
        Include the wheel/rail and curve terms when the model has rail data.

    Raises
    ------
    ModelError
        For a bad file, an unknown parameter name (with the closest one) or a bad
        value (every problem at once).

    Examples
    --------
    >>> vehicle = load_vehicle("examples/conventional.toml", {"Gamma": 0.2})
    >>> vehicle.wheelsets[0].conicity
    0.2
    """
    found = find_warm(path, with_rail)  # no symbolic work, no SymPy (express.numeric.warm)
    base = _GENERATED.get(found.vehicle_key) if found is not None else None
    if base is None and found is not None:
        warm = read_warm_vehicle(found)
        if warm is not None:
            key = found.vehicle_key
            base = _remember(key, _warm_vehicle(warm, str(path), lambda: _symbolic_twin(path, with_rail, key)))
    if base is not None and found is not None and reemit(found, str(path)):
        return base.with_values(overrides) if overrides else base
    from express.io.cache import entry_key
    from express.model.parameters import override_values, with_values

    model, reads, caught = _read_model(path)
    values = override_values(model, overrides or {})
    key = entry_key("vehicle", reads, {"with_rail": with_rail})
    base = _GENERATED.get(key)
    if base is None:
        derivation = vehicle_derivation(model, with_rail, key)
        try:
            base = _evaluate_vehicle(model, *derivation)
        except ModelError:
            if not values:
                raise
            # e.g. a singular M at the file's values that the overrides cure
            return _evaluate_vehicle(with_values(model, values), *derivation)
        _remember(key, base)  # and the warm entry, new or replacing a stale or damaged one:
        write_warm_entry(path, with_rail, key, _warm_data(base, model, reads, caught))
    return base.with_values(values) if values else base


def _remember(key: str, vehicle: VehicleModel) -> VehicleModel:
    if len(_GENERATED) >= _GENERATED_CACHE_SIZE:
        _GENERATED.pop(next(iter(_GENERATED)))
    _GENERATED[key] = vehicle
    return vehicle


def _read_model(path: str | Path, repeat_warnings: bool = True) -> tuple[Model, list[tuple[str, str]], list]:
    """The model of ``path``, the files its reading read (:mod:`express.base.reads`) and
    the warnings it gave (given again here unless ``repeat_warnings`` is false: a warm
    load gave them already)."""
    import warnings

    from express.base.reads import recorded_reads
    from express.io import load_model

    with recorded_reads() as reads, warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = load_model(Path(path))
    if repeat_warnings:
        for warning in caught:
            warnings.warn_explicit(warning.message, warning.category, warning.filename, warning.lineno,
                                   source=warning.source)
    return model, reads, caught


def _symbolic_twin(path: str | Path, with_rail: bool, key: str) -> VehicleModel:
    """The vehicle of ``path`` through its symbolic model (the derivation from the cache):
    what a warm vehicle builds when something asks for its model or equations.

    Raises
    ------
    ArgumentError
        When the files the vehicle was loaded from changed since (``key`` is no longer
        theirs): the symbolic side would be another vehicle's.
    """
    from express.io.cache import entry_key

    model, reads, _ = _read_model(path, repeat_warnings=False)
    if entry_key("vehicle", reads, {"with_rail": with_rail}) != key:
        raise ArgumentError(f"{path}: the model (or a file it reads) changed since this vehicle was loaded; "
                            "load it again (express.load_vehicle)")
    derivation = vehicle_derivation(model, with_rail, key)
    return _evaluate_vehicle(model, *derivation)


def _warm_data(vehicle: VehicleModel, model: Model, reads: list[tuple[str, str]], caught: list) -> dict[str, Any] | None:
    """The warm entry of a vehicle evaluated from its symbolic model (:func:`express.numeric.warm.warm_entry`)."""
    from express.model.parameter_ranges import parameter_bounds

    evaluation = vehicle.evaluation
    if evaluation is None:
        return None
    rail_numbers = evaluation.rail_numbers
    return warm_entry(
        vehicle.name, reads, vehicle.values, evaluation.speed_name,
        [tuple(item) for item in rail_numbers.wheelsets] if rail_numbers is not None else [],
        vehicle.layout, vehicle.station_positions.tolist(), vehicle.facts, caught, parameter_bounds(model),
    )
