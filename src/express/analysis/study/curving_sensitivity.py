"""Sensitivities of steady curving: derivatives of the steady-curving outputs with respect
to every parameter, by the implicit function theorem on the steady state's equations.

The steady state ``x`` in a constant curve solves (:mod:`express.analysis.curving.steady`)::

    r(x, p) = A(p) x + B(p) u + S(p) z(x, p) = 0

(``u`` the curvature and cant, ``z`` the nonlinear wheel/rail forces and the bump stops).
At the solution the velocities are zero and ``r = T F`` with ``T`` the state form's
force matrix (:attr:`~express.assembly.first_order.StateForm.force`: ``M^-1`` on the
coordinates with mass) and ``F`` the generalized forces::

    F(x, p) = -K(p) q + P(p, v) u + D z(x, p)

so that, since ``F = 0`` there, ``dr/dp = T dF/dp`` and the implicit function theorem gives::

    dx/dp = -(dr/dx)^-1 T (-(dK/dp) q + (dP/dp) u + d(D z)/dp)

- ``(dK/dp) q`` and ``(dP/dp) u`` are **exact**: the symbolic entries of ``K`` and ``P``
  differentiated once per model (compiled, :class:`LinearDerivatives`), chained through
  the parameter graph (:func:`express.analysis.study.derivatives.graph_rates`: exact for
  derived expressions, a central difference of the one derivation function for the creep
  coefficients and the profiles' equivalent conicity);
- ``d(D z)/dp`` at the fixed state, the wheel/rail forces of the contact model (dead-band
  flange and creep saturation, or the profiles' contact tables) and the bump stops, which
  are numerical functions, is a **central difference** (relative step
  :data:`CONTACT_STEP`) of those forces alone, the state held; the parameters for which
  it is not zero are listed (:attr:`SteadyCurvingSensitivity.differenced`);
- ``dr/dx = A + S dz/dx``: ``A`` exact, ``dz/dx`` central differences in the state
  (step :data:`STATE_STEP`).

The outputs (the leading wheelset's angle of attack, the largest Y/Q of any wheel, the
largest ``|ΣY|`` of any wheelset: the study outputs ``steady_aoa``, ``steady_YQ``,
``steady_SY``, :mod:`express.analysis.study.outputs`) are explicit functions of the state
and the parameters; each is differentiated along the exact tangent ``(dx/dp, 1)`` by a
central difference (relative step :data:`CONTACT_STEP`): no steady state is solved again.

**Nonsmooth outputs.** The largest Y/Q and ``|ΣY|`` are maxima over the wheels: the
derivative given is that of the wheel (wheelset) that is largest at the point, and the
margin to the next one is reported (:attr:`SteadyCurvingSensitivity.notes`); where two
are equal the maximum has a kink and only one-sided derivatives exist.  The dead-band
flange force and the contact tables' two-point contact are piecewise: the derivative is
that of the regime the steady state is in (the wheels in flange contact are named); a
parameter change that moves a wheel across the flange clearance changes the regime.
``docs/studies.md`` ("Sensitivities of steady curving") gives the checks against
central differences of the whole steady-curving solve.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import sympy as sp

from express.analysis.curving.steady import SteadyCurve, SteadyCurving, SteadyCurvingSolver
from express.analysis.study.derivatives import graph_rates
from express.base.caches import IdentityCache
from express.base.data import DataRecord, variable, xarray
from express.base.diagnostics import ArgumentError
from express.numeric.compiled import CompiledExpressions
from express.numeric.statespace import VehicleModel
from express.rail.options import DEFAULT_CREEP_LAW

__all__ = [
    "CONTACT_STEP",
    "OUTPUTS",
    "STATE_STEP",
    "LinearDerivatives",
    "SteadyCurvingSensitivity",
    "linear_derivatives",
    "steady_curving_sensitivity",
]

#: The outputs differentiated, with their SI units (the study outputs of the same names).
OUTPUTS = {"steady_aoa": "rad", "steady_YQ": "", "steady_SY": "N"}
#: Relative step of a parameter in the central differences of the contact forces at the
#: fixed state and of the outputs along the tangent (absolute for a parameter of value 0):
#: 1e-5 gives 6e-4 errors on the S1002 car (the tables re-derived from the profiles carry
#: noise), 1e-4 1e-5.
CONTACT_STEP = 1e-4
#: Step of the central differences of the nonlinear forces in the state ``dz/dx``
#: [m, rad, m/s, rad/s]: small against the spacing of the contact tables' points (a step
#: of 1e-6 gives 6 % errors on the S1002 car, 1e-7 2e-5, 1e-8 and 3e-9 the same 1e-5,
#: the reference's own accuracy; the dead-band model is the same from 1e-7 to 1e-8).
STATE_STEP = 1e-8


class LinearDerivatives:
    """``dK/dq`` and ``dP/dq`` of every parameter symbol ``q`` of a set of equations,
    differentiated once and compiled into one function (as
    :class:`~express.analysis.study.derivatives.MatrixDerivatives` does for M, C, K).

    Parameters
    ----------
    equations : EquationsOfMotion

    Attributes
    ----------
    parameters : tuple of str
        The symbols with a non-zero derivative, sorted.
    size : int
        Number of non-zero derivative entries.
    """

    def __init__(self, equations) -> None:
        slots: list[tuple[str, int, int, int, sp.Expr]] = []  # (symbol, 0 = K / 1 = P, i, j, derivative)
        for kind, key in enumerate(("K", "P")):
            matrix = equations.matrices.get(key)
            if matrix is None:
                continue
            for (i, j), entry in sorted(matrix.todok().items()):
                entry = sp.sympify(entry)
                for symbol in entry.free_symbols:
                    derivative = sp.diff(entry, symbol)
                    if derivative != 0:
                        slots.append((symbol.name, kind, i, j, derivative))
        slots.sort(key=lambda slot: slot[:4])
        self.parameters = tuple(sorted({slot[0] for slot in slots}))
        position = {name: k for k, name in enumerate(self.parameters)}
        self.size = len(slots)
        self.n = len(equations.dofs)
        self.symbol = np.array([position[s[0]] for s in slots], dtype=np.intp)
        self.kind = np.array([s[1] for s in slots], dtype=np.intp)
        self.rows = np.array([s[2] for s in slots], dtype=np.intp)
        self.columns = np.array([s[3] for s in slots], dtype=np.intp)
        self.function = CompiledExpressions([s[4] for s in slots]) if slots else None

    def force_rates(self, values: Mapping[str, float], q: np.ndarray, u: np.ndarray) -> np.ndarray:
        """``-(dK/dq) q + (dP/dq) u`` for every symbol ``q`` of :attr:`parameters`, shape
        (len(parameters), n) [N or N m per SI unit of the symbol].

        Parameters
        ----------
        values : mapping of str to float
            The parameter values (SI), the speed parameter at the speed of ``P(v)``.
        q : numpy.ndarray, shape (n,)
            Coordinates [m, rad].
        u : numpy.ndarray, shape (m,)
            Inputs.

        Raises
        ------
        ArgumentError
            When a derivative is not finite there.
        """
        result = np.zeros((len(self.parameters), self.n))
        if self.function is None:
            return result
        try:
            numbers = self.function(values)
        except ValueError:
            raise ArgumentError("a derivative of K or P is not finite at these parameter values") from None
        stiffness = self.kind == 0
        factor = np.empty(self.size)
        factor[stiffness] = -q[self.columns[stiffness]]
        factor[~stiffness] = u[self.columns[~stiffness]]
        np.add.at(result, (self.symbol, self.rows), numbers * factor)
        return result


_LINEAR: IdentityCache[LinearDerivatives] = IdentityCache(4)


def linear_derivatives(equations) -> LinearDerivatives:
    """The compiled derivatives of ``equations``' K and P (cached per set of equations)."""
    return _LINEAR.get_or_make((equations,), lambda: LinearDerivatives(equations))


@dataclass(frozen=True, repr=False)
class SteadyCurvingSensitivity(DataRecord):
    """Result of :func:`steady_curving_sensitivity`.

    Attributes
    ----------
    steady : SteadyCurving
        The steady state differentiated.
    values : dict of str to float
        ``steady_aoa`` [rad], ``steady_YQ`` [-], ``steady_SY`` [N] at the point.
    parameters : tuple of str
    parameter_values : numpy.ndarray, shape (P,)
        [SI].
    derivatives : numpy.ndarray, shape (P, 3)
        d output / d parameter, the outputs in the order of :data:`OUTPUTS` [output's SI
        unit per parameter's SI unit].
    state_derivatives : numpy.ndarray, shape (P, N)
        ``dx/dp`` of the steady state.
    differenced : tuple of str
        The parameters whose contact (or bump-stop) forces at the fixed state move with
        them: that term of ``dr/dp`` is a central difference (module docstring); the
        others' derivatives come from the symbolic K and P alone.
    notes : tuple of str
        Where the outputs are nonsmooth: the wheel (wheelset) whose maximum is
        differentiated and its margin to the next, the wheels in flange contact.
    """

    steady: SteadyCurving
    values: dict[str, float]
    parameters: tuple[str, ...]
    parameter_values: np.ndarray
    derivatives: np.ndarray
    state_derivatives: np.ndarray
    differenced: tuple[str, ...]
    notes: tuple[str, ...]

    @property
    def elasticities(self) -> np.ndarray:
        """``(p / output) d output / dp`` [-], shape (P, 3) (0 where the parameter or the
        output is 0)."""
        outputs = np.array([self.values[name] for name in OUTPUTS])
        with np.errstate(divide="ignore", invalid="ignore"):
            result = self.parameter_values[:, None] / outputs[None, :] * self.derivatives
        return np.where(np.isfinite(result) & (self.parameter_values[:, None] != 0), result, 0.0) + 0.0

    def derivative(self, output: str, parameter: str) -> float:
        """d ``output`` / d ``parameter`` (SI)."""
        return float(self.derivatives[self.parameters.index(parameter), list(OUTPUTS).index(output)])

    def as_dict(self) -> dict:
        """``{"values", "units", "sensitivities": {parameter: {output: d}}, "elasticities",
        "differenced", "notes", ...}`` (SI)."""
        names = list(OUTPUTS)
        elasticities = self.elasticities
        curve = self.steady.curve
        return {
            "radius": curve.radius, "cant": curve.cant, "direction": curve.direction, "speed": self.steady.speed,
            "unbalanced_acceleration": self.steady.unbalanced_acceleration, "contact": self.steady.contact,
            "values": dict(self.values), "units": dict(OUTPUTS),
            "sensitivities": {p: {o: float(self.derivatives[i, k]) for k, o in enumerate(names)}
                              for i, p in enumerate(self.parameters)},
            "elasticities": {p: {o: float(elasticities[i, k]) for k, o in enumerate(names)}
                             for i, p in enumerate(self.parameters)},
            "differenced": list(self.differenced), "notes": list(self.notes),
        }

    def to_xarray(self):
        """The derivatives as an :class:`xarray.Dataset` over ``parameter``: ``value``
        (SI), ``d_<output>`` and ``elasticity_<output>`` for each output, the outputs as
        scalars."""
        xr = xarray()
        data = {"value": variable(self.parameter_values, "parameter", "SI", "parameter value")}
        elasticities = self.elasticities
        for k, (name, unit) in enumerate(OUTPUTS.items()):
            data[f"d_{name}"] = variable(self.derivatives[:, k], "parameter", f"{unit or '1'} per SI unit of the parameter",
                                         f"derivative of {name}")
            data[f"elasticity_{name}"] = variable(elasticities[:, k], "parameter", "1", f"elasticity of {name}")
            data[name] = variable(self.values[name], (), unit or "1", name)
        dataset = xr.Dataset(data, coords={"parameter": list(self.parameters)})
        dataset.attrs.update({"radius_m": self.steady.curve.radius, "cant_m": self.steady.curve.cant,
                              "speed_m_s": self.steady.speed, "contact": self.steady.contact,
                              "differenced": ", ".join(self.differenced), "notes": "; ".join(self.notes)})
        return dataset

    def _summary(self) -> list[str]:
        curve = self.steady.curve
        order = np.argsort(-np.abs(self.elasticities[:, 0]), kind="stable")[:3]
        top = ", ".join(f"{self.parameters[i]} {self.elasticities[i, 0]:+.3g}" for i in order)
        return [f"R {curve.radius:g} m, cant {curve.cant:g} m, {self.steady.speed:.3f} m/s, {self.steady.contact}: "
                f"aoa {self.values['steady_aoa'] * 1e3:.4g} mrad, Y/Q {self.values['steady_YQ']:.4g}, "
                f"|SY| {self.values['steady_SY'] / 1e3:.4g} kN; {len(self.parameters)} parameters",
                f"largest aoa elasticities: {top}"[:160]]


def _speed_name(vehicle: VehicleModel) -> str | None:
    model = vehicle.model
    if model is None or model.rail is None or not isinstance(model.rail.speed, sp.Symbol):
        return None
    return model.rail.speed.name


def _generalised(vehicle: VehicleModel, state_forces: np.ndarray) -> np.ndarray:
    """``f`` from ``T f`` (``T`` the state form's force matrix): the generalized forces on
    the coordinates, from ``M_DD`` and ``C`` (module docstring of
    :mod:`express.assembly.first_order`)."""
    form = vehicle.form
    n, massive, first = form.n, form.massive, form.first_order
    f = np.zeros(n)
    if first.size:
        rate = state_forces[first]  # Z f_F
        f[first] = vehicle.damping_base[np.ix_(first, first)] @ rate
        f[massive] = vehicle.mass[np.ix_(massive, massive)] @ state_forces[n:] + \
            vehicle.damping_base[np.ix_(massive, first)] @ rate
    else:
        f[massive] = vehicle.mass[np.ix_(massive, massive)] @ state_forces[n:]
    return f


def _force_slopes(forces, x: np.ndarray, width: int) -> np.ndarray:
    """``dz/dx`` by central differences (step :data:`STATE_STEP`), shape (width, N)."""
    slopes = np.zeros((width, x.size))
    if not width:
        return slopes
    for j in range(x.size):
        up, down = x.copy(), x.copy()
        up[j] += STATE_STEP
        down[j] -= STATE_STEP
        slopes[:, j] = (forces.forces(up, 0) - forces.forces(down, 0)) / (2.0 * STATE_STEP)
    return slopes


def _outputs(solver: SteadyCurvingSolver, x: np.ndarray, inputs) -> tuple[float, np.ndarray, np.ndarray]:
    """The leading wheelset's angle of attack, every wheel's Y/Q (flattened) and every
    wheelset's ΣY at state ``x`` (as :meth:`SteadyCurvingSolver.solve` measures them)."""
    from express.analysis.curving.measure import wheel_rail_outputs

    vehicle = solver.vehicle
    q = x[: vehicle.n]
    q_dot = vehicle.form.velocities(x[None, :], inputs.u, inputs.u_rate)
    w = wheel_rail_outputs(vehicle, q[None, :], q_dot, inputs, solver.speed, contact=solver.tables)
    return float(w.angle_of_attack[0, 0]), np.ravel(w.y_over_q[0]), np.asarray(w.track_shift_force[0], dtype=float)


def _margin(values: np.ndarray, index: int) -> float:
    others = np.delete(values, index)
    return float(values[index] - np.max(others)) if others.size else math.inf


def steady_curving_sensitivity(
    vehicle: VehicleModel, curve: SteadyCurve, *, speed: float | str | None = None,
    parameters: Sequence[str] | None = None, contact: str | None = None, creep_law: str = DEFAULT_CREEP_LAW,
    flange: bool = True, saturation: bool = True,
) -> SteadyCurvingSensitivity:
    """The steady state in ``curve`` and the derivatives of its outputs with respect to
    every parameter (module docstring).

    Parameters
    ----------
    vehicle : VehicleModel
        With rail data.
    curve : SteadyCurve
    speed : float or quantity, optional
        [m/s] (a number is SI, ``"95 km/h"`` a quantity); the model's speed by default.
    parameters : sequence of str, optional
        Default every given parameter but the speed
        (:func:`express.analysis.study.sensitivity.sensitivity_parameters`).
    contact, creep_law, flange, saturation
        As :class:`~express.analysis.curving.steady.SteadyCurvingSolver`.

    Returns
    -------
    SteadyCurvingSensitivity

    Raises
    ------
    ArgumentError
        An unknown parameter, a vehicle with a series element at its limit or linearised
        for the linear analyses.
    CurveError
        A curve the vehicle cannot run, or without a steady state.
    """
    import scipy.linalg

    from express.base.arguments import si_argument

    names = _checked(vehicle, curve, parameters)
    v = float(vehicle.speed if speed is None else si_argument(speed, "speed", "speed"))
    options = {"contact": contact, "creep_law": creep_law, "flange": flange, "saturation": saturation}
    solver = SteadyCurvingSolver(vehicle, v, **options)  # type: ignore[arg-type]
    steady = solver.solve(curve)
    inputs = solver.inputs(curve)
    x = steady.state
    forces = solver.force_set(inputs)
    width = solver.selector.shape[1]
    factors = scipy.linalg.lu_factor(solver.a + solver.selector @ _force_slopes(forces, x, width))
    exact = _symbolic_rates(vehicle, names, v, x[: vehicle.n], inputs.u[0])

    aoa, yq, sy = _outputs(solver, x, inputs)
    yq_at, sy_at = int(np.argmax(yq)), int(np.argmax(np.abs(sy)))
    sign = 1.0 if sy[sy_at] >= 0 else -1.0
    derivatives = np.zeros((len(names), len(OUTPUTS)))
    state_rates = np.zeros((len(names), x.size))
    differenced = []
    for i, name in enumerate(names):
        value = float(vehicle.values[name])
        h = CONTACT_STEP * abs(value) or CONTACT_STEP
        ends = []
        for delta in (h, -h):
            moved = vehicle.with_values({name: value + delta})
            moved_solver = SteadyCurvingSolver(moved, v, **options)  # type: ignore[arg-type]
            moved_inputs = moved_solver.inputs(curve)
            z = moved_solver.force_set(moved_inputs).forces(x, 0) if width else np.zeros(0)
            ends.append((moved_solver, moved_inputs, _generalised(moved, moved_solver.selector @ z)))
        contact_rate = (ends[0][2] - ends[1][2]) / (2.0 * h)
        if np.any(contact_rate != 0.0):
            differenced.append(name)
        dx = state_rates[i] = -scipy.linalg.lu_solve(factors, vehicle.form.force @ (exact[i] + contact_rate))
        (aoa_p, yq_p, sy_p), (aoa_m, yq_m, sy_m) = (_outputs(s, x + delta * dx, inp)
                                                    for (s, inp, _), delta in zip(ends, (h, -h), strict=True))
        derivatives[i] = np.array([(aoa_p - aoa_m) / (2.0 * h), (yq_p[yq_at] - yq_m[yq_at]) / (2.0 * h),
                                   sign * (sy_p[sy_at] - sy_m[sy_at]) / (2.0 * h)]) + 0.0  # no "-0"
    return SteadyCurvingSensitivity(steady, {"steady_aoa": aoa, "steady_YQ": float(yq[yq_at]),
                                             "steady_SY": float(abs(sy[sy_at]))}, tuple(names),
                                    np.array([float(vehicle.values[name]) for name in names]), derivatives,
                                    state_rates, tuple(differenced), _notes(steady, yq, yq_at, sy, sy_at))


def _checked(vehicle: VehicleModel, curve, parameters: Sequence[str] | None) -> list[str]:
    """The parameters to differentiate, the vehicle and curve checked."""
    from express.analysis.study.sensitivity import chosen_parameters

    if not isinstance(curve, SteadyCurve):
        raise ArgumentError(f"curve must be a SteadyCurve (e.g. SteadyCurve(radius=600.0, cant=0.15)), got "
                            f"{type(curve).__name__}")
    if vehicle.inactive:
        raise ArgumentError(f"no sensitivities at a series element's limit ({', '.join(vehicle.inactive)} removed); "
                            "move the parameter off the limit")
    if getattr(vehicle, "tangent_vehicle", None) is not None:
        raise ArgumentError("steady curving runs the nonlinear elements themselves: give the tangent vehicle, not one "
                            "linearised for the linear analyses")
    return chosen_parameters(vehicle, parameters)


def _symbolic_rates(vehicle: VehicleModel, names: Sequence[str], speed: float, q: np.ndarray,
                    u: np.ndarray) -> np.ndarray:
    """``-(dK/dp) q + (dP/dp) u`` of every parameter in ``names``, shape (P, n): the
    symbolic derivatives chained through the parameter graph."""
    values = dict(vehicle.values)
    speed_name = _speed_name(vehicle)
    if speed_name is not None:
        values[speed_name] = speed
    linear = linear_derivatives(vehicle.equations)
    per_symbol = linear.force_rates(values, q, u)  # (symbols, n)
    if vehicle.model is not None:
        rates = graph_rates(vehicle.model, vehicle.equations).rates(vehicle.values, names)
    else:
        rates = {name: np.eye(len(names))[k] for k, name in enumerate(names)}
    chain = np.array([rates.get(s, np.zeros(len(names))) for s in linear.parameters]).reshape(-1, len(names))
    return chain.T @ per_symbol


def _notes(steady: SteadyCurving, yq: np.ndarray, yq_at: int, sy: np.ndarray, sy_at: int) -> tuple[str, ...]:
    """Where the outputs are nonsmooth (module docstring)."""
    notes = [f"steady_YQ is the Y/Q of wheelset {yq_at // 2 + 1} {'left' if yq_at % 2 == 0 else 'right'}, "
             f"{_margin(yq, yq_at):.3g} above the next wheel",
             f"steady_SY is |SY| of wheelset {sy_at + 1} of {len(sy)}, {_margin(np.abs(sy), sy_at):.4g} N above the next"]
    flanging = np.argwhere(steady.wheel_rail.flange_contact[0])
    if flanging.size:
        notes.append("flange contact at " + ", ".join(f"wheelset {j + 1} {'left' if k == 0 else 'right'}"
                                                      for j, k in flanging)
                     + ": the derivatives are those of this contact regime (the flange force is piecewise)")
    return tuple(notes)
