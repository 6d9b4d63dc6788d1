"""Exact derivatives of eigenvalues and of the critical speed with respect to parameters.

The eigenvalues of the state matrix ``A(v)`` are those of the quadratic eigenproblem
``Q(lambda) q = (lambda^2 M + lambda C(v) + K) q = 0`` (also with first-order
coordinates, whose rows of ``M`` are zero). For a simple eigenvalue with right and
left null vectors ``q``, ``u`` of ``Q(lambda)`` (``q`` the displacement part of the state
eigenvector, ``u`` from the singular value decomposition of ``Q(lambda)``)::

    d lambda / dp = - u^H (lambda^2 dM/dp + lambda dC/dp + dK/dp) q / (u^H (2 lambda M + C) q)

the derivative ``y^H (dA/dp) x / (y^H x)`` of the state form written for the matrices
that are differentiated. The derivatives ``dM/dq``, ``dC/dq``, ``dK/dq`` of every
parameter symbol ``q`` are compiled once per model and evaluated per point from the
parameter values, and a parameter acts directly and through the parameters derived from
it by the chain rule ``dA/dp = sum_q (dA/dq) (dq/dp)`` forward through the live graph
(:mod:`express.analysis.study.derivatives`: exact for derived expressions, a central
difference of the one derivation function for the creep coefficients; no eigenvalue is
ever differenced). All eigenvalues of a sweep share one evaluation of the derivatives.

At the critical speed the crossing eigenvalue satisfies ``Re lambda(v*, p) = threshold``;
the implicit function theorem gives::

    dv*/dp = - (d Re lambda / dp) / (d Re lambda / dv)

with ``dQ/dv = -lambda C1 / v^2`` (the creep damping ``C = C0 + C1 / v``). The derivatives are of the exact crossing
(:class:`~express.analysis.study.critical.HopfPoint`), not of the bisection midpoint that
``express critical-speed`` prints.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import sympy as sp

from express.analysis.study.critical import CriticalOptions, StateBlocks, fast_critical_speed
from express.analysis.study.derivatives import graph_rates, matrix_derivatives
from express.base.data import DataRecord
from express.base.diagnostics import ArgumentError, NoCriticalSpeedError
from express.numeric.statespace import VehicleModel

__all__ = [
    "CriticalSpeedSensitivity",
    "ParameterSensitivity",
    "chosen_parameters",
    "critical_speed_sensitivity",
    "eigenvalue_derivatives",
    "parameter_rates",
    "physical_constants",
    "sensitivity_parameters",
]


@dataclass(frozen=True)
class ParameterSensitivity:
    """Derivative of an output with respect to one parameter.

    Attributes
    ----------
    name : str
    value : float
        The parameter's value (SI).
    derivative : float
        d output / d parameter (SI units of both).
    elasticity : float
        ``(value / output) * derivative`` [-]: the relative change of the output per
        relative change of the parameter (0 for a parameter whose value is 0).
    """

    name: str
    value: float
    derivative: float
    elasticity: float


@dataclass(frozen=True, repr=False)
class CriticalSpeedSensitivity(DataRecord):
    """Result of :func:`critical_speed_sensitivity`.

    Attributes
    ----------
    critical_speed : float
        The exact crossing ``v*`` [m/s].
    frequency : float
        Frequency of the crossing mode [Hz].
    sensitivities : tuple of ParameterSensitivity
        One per parameter, in the order asked for.
    """

    critical_speed: float
    frequency: float
    sensitivities: tuple[ParameterSensitivity, ...]

    def to_xarray(self):
        """The sensitivities as an :class:`xarray.Dataset` over ``parameter``
        (:func:`express.analysis.result_data.sensitivity_dataset`)."""
        from express.analysis.result_data import sensitivity_dataset

        return sensitivity_dataset(self)

    def _summary(self) -> list[str]:
        top = ", ".join(f"{s.name} {s.elasticity:+.3g}" for s in self.ranked()[:4])
        return [f"critical speed {self.critical_speed:.3f} m/s ({self.critical_speed * 3.6:.1f} km/h), "
                f"{self.frequency:.3f} Hz; {len(self.sensitivities)} parameters",
                f"largest elasticities: {top}"[:160]]

    def ranked(self) -> list[ParameterSensitivity]:
        """Largest absolute elasticity first (ties by name)."""
        return sorted(self.sensitivities, key=lambda s: (-abs(s.elasticity), s.name))

    def as_dict(self) -> dict:
        """``{"critical_speed": v*, "sensitivities": {name: dv*/dp}, ...}`` (SI)."""
        return {
            "critical_speed": self.critical_speed,
            "frequency_hz": self.frequency,
            "sensitivities": {s.name: s.derivative for s in self.sensitivities},
            "elasticities": {s.name: s.elasticity for s in self.sensitivities},
        }


def _speed_name(vehicle: VehicleModel) -> str | None:
    model = vehicle.model
    if model is None or model.rail is None or not isinstance(model.rail.speed, sp.Symbol):
        return None
    return model.rail.speed.name


def sensitivity_parameters(vehicle: VehicleModel) -> list[str]:
    """The parameters a sensitivity can be taken with respect to: every primary (given)
    parameter of the model except the speed, sorted by name."""
    model = vehicle.model
    if model is None:
        return list(vehicle.equations.parameters)
    speed = _speed_name(vehicle)
    return sorted(name for name, p in model.parameters.items()
                  if name != speed and getattr(p, "expression", None) is None and not getattr(p, "derived_by", None))


def chosen_parameters(vehicle: VehicleModel, parameters: Sequence[str] | None) -> list[str]:
    """The parameters to differentiate: ``parameters`` (duplicates dropped, order kept) or
    every :func:`sensitivity_parameters` for None.

    Parameters
    ----------
    vehicle : VehicleModel
    parameters : sequence of str or None
        Names of given parameters.

    Raises
    ------
    ArgumentError
        A string instead of a sequence, or names that are not given parameters (each
        with a suggestion).
    """
    known = sensitivity_parameters(vehicle)
    if isinstance(parameters, str):
        raise ArgumentError(f"parameters must be a sequence of names, got the string {parameters!r}")
    names = list(dict.fromkeys(known if parameters is None else parameters))
    unknown = [name for name in names if name not in known]
    if unknown:
        from express.base.names import did_you_mean

        raise ArgumentError("; ".join(f"{name}: not a given parameter of the model (nor the speed)"
                                      f"{did_you_mean(name, known)}" for name in unknown))
    return names


#: Arguments of a parameter derivation that are material constants, not design values.
MATERIAL_ARGUMENTS = ("youngs_modulus", "poisson")


def physical_constants(vehicle: VehicleModel) -> list[str]:
    """The given parameters that are physical constants rather than design values: the
    gravity acceleration (``[gravity]``, ``[rail] gravity``) and the material constants
    of a derivation (Young's modulus and Poisson's ratio of Kalker's creep law), sorted.

    Examples
    --------
    >>> from express.numeric.statespace import load_vehicle
    >>> physical_constants(load_vehicle("examples/manchester.toml"))
    ['Emod', 'g', 'nu']
    """
    model = vehicle.model
    if model is None:
        return []
    expressions = [model.gravity] if model.gravity is not None else []
    if model.rail is not None:
        expressions.append(model.rail.gravity)
    for derivation in model.derivations:
        expressions += [expression for argument, expression, _ in derivation.inputs if argument in MATERIAL_ARGUMENTS]
    given = set(sensitivity_parameters(vehicle))
    names = {symbol.name for e in expressions if isinstance(e, sp.Expr) for symbol in e.free_symbols}
    return sorted(names & given)


def _rates(vehicle: VehicleModel, names: Sequence[str]) -> dict[str, np.ndarray]:
    if vehicle.model is None:
        return {name: np.eye(len(names))[k] for k, name in enumerate(names)}
    return graph_rates(vehicle.model, vehicle.equations).rates(vehicle.values, names)


def parameter_rates(vehicle: VehicleModel, name: str) -> dict[str, float]:
    """``dq/dp`` of every parameter ``q`` that depends on ``p = name`` (``p`` itself: 1),
    forward through the live parameter graph (:class:`~.derivatives.GraphRates`)."""
    return {q: float(rate[0]) for q, rate in _rates(vehicle, [name]).items()}


def _left_null_vector(pencil: np.ndarray) -> np.ndarray:
    """``u`` with ``u^H Q = 0`` for a singular ``Q`` (its smallest singular value)."""
    left, _singular, _right = np.linalg.svd(pencil)
    return left[:, -1]


def _pencil_derivatives(vehicle: VehicleModel, speed: float, eigenvalues, state_vectors,
                        names: Sequence[str]) -> tuple[np.ndarray, np.ndarray]:
    """``d lambda_k / dp`` for every name, shape (len(names), E), and ``d lambda_k / dv``,
    shape (E,), of the eigenpairs ``(eigenvalues[k], state_vectors[:, k])`` of ``A(speed)``
    (module docstring)."""
    if vehicle.inactive:  # the exact derivatives are of the full equations
        raise ArgumentError(f"no sensitivities at a series element's limit (zero or infinite damping, zero "
                         f"stiffness: {', '.join(vehicle.inactive)} removed); move the parameter off the limit")
    n = vehicle.n
    lam = np.atleast_1d(np.asarray(eigenvalues, dtype=complex))
    right = np.asarray(state_vectors, dtype=complex).reshape(-1, lam.size)[:n]
    damping = vehicle.damping(speed)
    left = np.column_stack([_left_null_vector(x**2 * vehicle.mass + x * damping + vehicle.stiffness) for x in lam])
    scale = np.einsum("ik,ik->k", left.conj(), (2 * vehicle.mass @ right) * lam + damping @ right)
    values = dict(vehicle.values)
    speed_name = _speed_name(vehicle)
    if speed_name is not None:
        values[speed_name] = float(speed)
    derivatives = matrix_derivatives(vehicle.equations)
    per_symbol = derivatives.contract(derivatives(values), lam, left, right)  # (symbols, E)
    rates = _rates(vehicle, names)
    jacobian = np.array([rates.get(q, np.zeros(len(names))) for q in derivatives.parameters]).reshape(-1, len(names))
    result = -(jacobian.T @ per_symbol + _equivalent_terms(vehicle, names, lam, left, right)) / scale
    speed_rate = -np.einsum("ik,ik->k", left.conj(), (-vehicle.damping_creep / speed**2) @ right) * lam / scale
    return result, speed_rate


def _equivalent_terms(vehicle: VehicleModel, names: Sequence[str], lam: np.ndarray, left: np.ndarray,
                      right: np.ndarray) -> np.ndarray:
    """``u^H (lambda dDC/dp + dDK/dp) x``, shape (len(names), E), of the equivalent
    elements of a vehicle linearised by ``--linearisation equivalent``
    (:class:`~express.forces.linearisation.LinearisedVehicle`): the change ``DK``, ``DC``
    from the tangents follows the describing functions, not the symbols, so it is
    differenced (central, step ``1e-4`` of the value: truncation ~1e-8 relative, against
    rounding ~1e-12 / 1e-4); zero for any other vehicle."""
    terms = np.zeros((len(names), lam.size), dtype=complex)
    if getattr(vehicle, "tangent_vehicle", None) is None:
        return terms
    for i, name in enumerate(names):
        value = float(vehicle.values[name])
        step = 1e-4 * (abs(value) or 1.0)
        ends = []
        for x in (value + step, value - step):
            seen = vehicle.with_values({name: x})
            base = getattr(seen, "tangent_vehicle", None) or seen
            ends.append((seen.stiffness - base.stiffness, seen.damping_base - base.damping_base))
        dk, dc = ((a - b) / (2 * step) for a, b in zip(ends[0], ends[1], strict=True))
        terms[i] = np.einsum("ik,ik->k", left.conj(), dk @ right + (dc @ right) * lam)
    return terms


def eigenvalue_derivatives(
    vehicle: VehicleModel, speed: float, parameters: list[str] | None = None
) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """Eigenvalues of ``A(v)`` and their exact derivatives with respect to parameters.

    Parameters
    ----------
    vehicle : VehicleModel
    speed : float
        [m/s].
    parameters : list of str, optional
        Default :func:`sensitivity_parameters`.

    Returns
    -------
    eigenvalues : numpy.ndarray, complex, shape (2n,)
        Sorted by descending real part (ties by descending imaginary part).
    derivatives : dict of str to numpy.ndarray, complex, shape (2n,)
        ``d lambda_k / dp`` [1/s per SI unit of p], in the order of ``eigenvalues``.
    """
    names = parameters if parameters is not None else sensitivity_parameters(vehicle)
    values, right = scipy.linalg.eig(vehicle.state_matrix(float(speed)))
    order = np.lexsort((-values.imag, -values.real))
    rates, _ = _pencil_derivatives(vehicle, float(speed), values[order], right[:, order], names)
    return values[order], {name: rates[k] for k, name in enumerate(names)}


def critical_speed_sensitivity(
    vehicle: VehicleModel, parameters: list[str] | None = None, options: CriticalOptions | None = None
) -> CriticalSpeedSensitivity:
    """Critical speed and its exact derivatives (implicit function theorem).

    Parameters
    ----------
    vehicle : VehicleModel
    parameters : list of str, optional
        Default :func:`sensitivity_parameters`.
    options : CriticalOptions, optional
        Search options (the tolerance is ignored: the exact crossing is used).

    Returns
    -------
    CriticalSpeedSensitivity

    Raises
    ------
    NoCriticalSpeedError
        When the vehicle has no crossing in the range (stable throughout, already
        unstable at ``v_min``, or a crossing Newton's method could not locate).
    """
    options = options or CriticalOptions()
    names = parameters if parameters is not None else sensitivity_parameters(vehicle)
    unknown = [name for name in names if vehicle.model is not None and name not in vehicle.model.parameters]
    if unknown:
        raise ArgumentError(f"unknown parameter{'s' if len(unknown) > 1 else ''}: {', '.join(unknown)}")
    blocks = StateBlocks(vehicle)
    result = fast_critical_speed(blocks, options)
    crossing = result.crossing
    if crossing is None:
        if result.unstable_at_min:
            raise NoCriticalSpeedError(f"already unstable at the lowest speed {options.v_min:g} m/s: no crossing to differentiate")
        if not result.found:
            raise NoCriticalSpeedError(f"stable up to {options.v_max:g} m/s: no critical speed to differentiate")
        raise NoCriticalSpeedError("the crossing could not be located exactly (not a simple oscillatory mode)")
    rates, rate_v = _pencil_derivatives(vehicle, crossing.speed, crossing.eigenvalue, crossing.vector, names)
    records = []
    for k, name in enumerate(names):
        value = float(vehicle.values[name]) if name in vehicle.values else float("nan")
        derivative = -rates[k, 0].real / rate_v[0].real + 0.0  # no "-0"
        elasticity = value / crossing.speed * derivative if value != 0 and math.isfinite(value) else 0.0
        records.append(ParameterSensitivity(name, value, float(derivative), float(elasticity)))
    return CriticalSpeedSensitivity(crossing.speed, crossing.frequency, tuple(records))
