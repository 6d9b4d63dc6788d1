"""Exact derivatives of eigenvalues and of the critical speed with respect to parameters.

The eigenvalues of the state matrix ``A(v)`` are those of the quadratic eigenproblem
``Q(lambda) q = (lambda^2 M + lambda C(v) + K) q = 0`` (also with first-order
coordinates, whose rows of ``M`` are zero). For a simple eigenvalue with right and
left null vectors ``q``, ``u`` of ``Q(lambda)`` (``q`` the displacement part of the state
eigenvector, ``u`` from the singular value decomposition of ``Q(lambda)``)::

    d lambda / dp = - u^H (lambda^2 dM/dp + lambda dC/dp + dK/dp) q / (u^H (2 lambda M + C) q)

the derivative ``y^H (dA/dp) x / (y^H x)`` of the state form written for the matrices
that are differentiated: every entry of ``M``, ``C`` and ``K`` is differentiated (SymPy)
with respect to every parameter symbol it holds, once per set of equations.
A parameter enters the matrices directly or through
the parameters derived from it (the live graph of :mod:`express.parameters`): the chain
rule ``dA/dp = sum_q (dA/dq) (dq/dp)`` takes ``dq/dp`` forward through the graph in its
evaluation order, **exactly** for a derived parameter given by an expression (its
SymPy derivative), and for the outputs of a derivation function without a closed form
(``[rail.creep]``: the creep coefficients from the wheel load, radii and elastic
constants through the Hertz ellipse and Kalker's table) as a central difference of that
one function along the direction its arguments move (relative step ``1e-4`` of the
argument that moves most). No eigenvalue is ever differenced.

At the critical speed the crossing eigenvalue satisfies ``Re lambda(v*, p) = threshold``;
the implicit function theorem gives::

    dv*/dp = - (d Re lambda / dp) / (d Re lambda / dv)

with ``dQ/dv = -lambda C1 / v^2`` (the creep damping ``C = C0 + C1 / v``). The derivatives are of the exact crossing
(:class:`~express.analysis.study.critical.HopfPoint`), not of the bisection midpoint that
``express critical-speed`` prints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import sympy as sp

from ...statespace import VehicleModel
from .critical import CriticalOptions, StateBlocks, fast_critical_speed

__all__ = [
    "CriticalSpeedSensitivity",
    "MatrixDerivatives",
    "ParameterSensitivity",
    "critical_speed_sensitivity",
    "eigenvalue_derivatives",
    "parameter_rates",
    "sensitivity_parameters",
]

#: Relative step of the central difference of a derivation function.
DERIVED_STEP = 1e-4


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


@dataclass(frozen=True)
class CriticalSpeedSensitivity:
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


class MatrixDerivatives:
    """Numerical ``dM/dq``, ``dC/dq``, ``dK/dq`` for every parameter symbol ``q`` of a
    set of equations, from their symbolic entries differentiated once (SymPy) and
    compiled into one function.

    Parameters
    ----------
    equations : EquationsOfMotion
    """

    def __init__(self, equations):
        self.equations = equations
        self.n = len(equations.dofs)
        symbols = [sp.Symbol(name) for name in equations.parameters]
        self.slots: list[tuple[str, str, int, int]] = []  # (parameter, matrix, i, j)
        expressions = []
        for key in ("M", "C", "K"):
            for (i, j), entry in equations.matrices[key].todok().items():
                entry = sp.sympify(entry)
                for symbol in sorted(entry.free_symbols, key=lambda s: s.name):
                    derivative = sp.diff(entry, symbol)
                    if derivative != 0:
                        self.slots.append((symbol.name, key, i, j))
                        expressions.append(derivative)
        self.parameters = tuple(sorted({slot[0] for slot in self.slots}))
        self._function = sp.lambdify(symbols, expressions, modules="math") if expressions else None

    def __call__(self, values: dict[str, float]) -> dict[str, dict[str, np.ndarray]]:
        """``{q: {"M": dM/dq, "C": dC/dq, "K": dK/dq}}`` at ``values`` (SI; the speed
        parameter gives the speed of ``C``), each shape (n, n)."""
        result: dict[str, dict[str, np.ndarray]] = {}
        if self._function is None:
            return result
        numbers = self._function(*[float(values[name]) for name in self.equations.parameters])
        for (name, key, i, j), number in zip(self.slots, numbers, strict=True):
            blocks = result.setdefault(name, {k: np.zeros((self.n, self.n)) for k in ("M", "C", "K")})
            blocks[key][i, j] = number
        return result


_DERIVATIVES: dict[int, MatrixDerivatives] = {}


def _matrix_derivatives(equations) -> MatrixDerivatives:
    cached = _DERIVATIVES.get(id(equations))
    if cached is None or cached.equations is not equations:
        if len(_DERIVATIVES) >= 4:
            _DERIVATIVES.pop(next(iter(_DERIVATIVES)))
        cached = _DERIVATIVES[id(equations)] = MatrixDerivatives(equations)
    return cached


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


def _number(expression, values: dict[str, float]) -> float:
    from ...parameters import expression_value

    try:
        return expression_value(expression, values)
    except ValueError:  # a function the float walk does not know: let SymPy evaluate it
        return float(sp.sympify(expression).xreplace({sp.Symbol(k): v for k, v in values.items()}))


def _expression_rate(expression, values: dict[str, float], rates: dict[str, float]) -> float:
    """``d expression / dp`` from the rates of its symbols (exact: SymPy derivative)."""
    expression = sp.sympify(expression)
    total = 0.0
    for symbol in expression.free_symbols:
        rate = rates.get(symbol.name, 0.0)
        if rate:
            total += _number(sp.diff(expression, symbol), values) * rate
    return total


def _derivation_rates(node, values: dict[str, float], rates: dict[str, float]) -> dict[str, float]:
    """Rates of a derivation's outputs: central difference of its function along the
    direction in which its arguments move."""
    from ... import parameters as graph

    arguments = {name: _number(expression, values) for name, expression, _ in node.inputs}
    direction = {name: _expression_rate(expression, values, rates) for name, expression, _ in node.inputs}
    moving = {name: d for name, d in direction.items() if d}
    if not moving:
        return {}
    step = DERIVED_STEP * min(abs(arguments[name]) / abs(d) if arguments[name] else 1.0 / abs(d)
                              for name, d in moving.items())
    function = graph._function(node.kind)  # the node's registered function (rail layer)
    plus = function(**{k: a + step * direction[k] for k, a in arguments.items()})
    minus = function(**{k: a - step * direction[k] for k, a in arguments.items()})
    return {name: (plus[key] - minus[key]) / (2.0 * step) for key, name, _ in node.outputs}


def parameter_rates(vehicle: VehicleModel, name: str) -> dict[str, float]:
    """``dq/dp`` of every parameter ``q`` that depends on ``p = name`` (``p`` itself: 1),
    forward through the live parameter graph (module docstring)."""
    from ...model import Derivation
    from ...parameters import evaluation_order

    model = vehicle.model
    rates = {name: 1.0}
    if model is None:
        return rates
    values = dict(vehicle.values)
    for node in evaluation_order(model):
        if isinstance(node, Derivation):
            for target, rate in _derivation_rates(node, values, rates).items():
                parameter = model.parameters.get(target)
                if rate and parameter is not None and parameter.derived_by == node.item:
                    rates[target] = rate
        elif node.expression is not None:
            rate = _expression_rate(node.expression, values, rates)
            if rate:
                rates[node.name] = rate
    return rates


def _left_null_vector(pencil: np.ndarray) -> np.ndarray:
    """``u`` with ``u^H Q = 0`` for a singular ``Q`` (its smallest singular value)."""
    left, _singular, _right = np.linalg.svd(pencil)
    return left[:, -1]


def _pencil_derivatives(vehicle, speed, eigenvalue, state_vector, names):
    """``d lambda / dp`` for every name in ``names``, and ``d lambda / dv`` (module docstring)."""
    n = vehicle.n
    values = dict(vehicle.values)
    speed_name = _speed_name(vehicle)
    if speed_name is not None:
        values[speed_name] = float(speed)
    lam = complex(eigenvalue)
    damping = vehicle.damping(speed)
    q = np.asarray(state_vector)[:n]
    u = _left_null_vector(lam**2 * vehicle.mass + lam * damping + vehicle.stiffness)
    scale = u.conj() @ ((2 * lam * vehicle.mass + damping) @ q)
    per_symbol = {}
    for symbol, d in _matrix_derivatives(vehicle.equations)(values).items():
        per_symbol[symbol] = -(u.conj() @ ((lam**2 * d["M"] + lam * d["C"] + d["K"]) @ q)) / scale
    result = {}
    for name in names:
        total = 0.0 + 0.0j
        for q_name, rate in parameter_rates(vehicle, name).items():
            if q_name in per_symbol:
                total += rate * per_symbol[q_name]
        result[name] = complex(total)
    speed_rate = -(u.conj() @ ((lam * -vehicle.damping_creep / speed**2) @ q)) / scale
    return result, complex(speed_rate)


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
    result = {name: np.zeros(values.size, dtype=complex) for name in names}
    for position, k in enumerate(order):
        rates, _ = _pencil_derivatives(vehicle, speed, values[k], right[:, k], names)
        for name in names:
            result[name][position] = rates[name]
    return values[order], result


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
    ValueError
        When the vehicle has no crossing in the range (stable throughout, already
        unstable at ``v_min``, or a crossing Newton's method could not locate).
    """
    options = options or CriticalOptions()
    names = parameters if parameters is not None else sensitivity_parameters(vehicle)
    unknown = [name for name in names if vehicle.model is not None and name not in vehicle.model.parameters]
    if unknown:
        raise ValueError(f"unknown parameter{'s' if len(unknown) > 1 else ''}: {', '.join(unknown)}")
    blocks = StateBlocks(vehicle)
    result = fast_critical_speed(blocks, options)
    crossing = result.crossing
    if crossing is None:
        if result.unstable_at_min:
            raise ValueError(f"already unstable at the lowest speed {options.v_min:g} m/s: no crossing to differentiate")
        if result.speed is None:
            raise ValueError(f"stable up to {options.v_max:g} m/s: no critical speed to differentiate")
        raise ValueError("the crossing could not be located exactly (not a simple oscillatory mode)")
    rates, rate_v = _pencil_derivatives(vehicle, crossing.speed, crossing.eigenvalue, crossing.vector, names)
    records = []
    for name in names:
        value = float(vehicle.values[name]) if name in vehicle.values else float("nan")
        derivative = -rates[name].real / rate_v.real + 0.0  # no "-0"
        elasticity = value / crossing.speed * derivative if value != 0 and math.isfinite(value) else 0.0
        records.append(ParameterSensitivity(name, value, float(derivative), float(elasticity)))
    return CriticalSpeedSensitivity(crossing.speed, crossing.frequency, tuple(records))
