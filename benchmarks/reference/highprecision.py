"""The reference computations at high precision (mpmath), from the exact symbolic matrices.

EXPRESS generates ``M``, ``C(v)``, ``K``, ``P(v)``, ``Pd`` as exact SymPy expressions of the
parameters (pins eliminated). Here they are evaluated with mpmath at ``dps`` significant
decimal digits, the parameter values being taken as the exact decimals listed in the
reference files, and every reference quantity is computed at that precision:

- eigenvalues: :func:`mpmath.eig` of the state matrix ``[[0, I], [-M^-1 K, -M^-1 C(v)]]``,
  i.e. the roots of ``det(lambda^2 M + lambda C(v) + K) = 0``;
- linear critical speed: the speed where the real part of the crossing eigenvalue is zero,
  by a secant iteration on the speed with a Newton refinement of the eigenpair of the
  quadratic eigenproblem at each speed (started from the library's double-precision result);
- frequency responses: ``(-w^2 M + i w C(v) + K) X = (P(v) + i w Pd) U`` by mpmath's LU.

Nothing here uses the library's numerical path (``express.numeric``); only the symbolic
equations and the model's data (stations, output points) come from EXPRESS.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import mpmath
import numpy as np
import sympy as sp

from express.assembly.mass_blocks import coupled_groups

#: Matrices of the second-order equations, in the order of the files.
MATRICES = ("M", "K", "C0", "C1", "P0", "P2", "Pd")


@dataclass(frozen=True)
class ExactVehicle:
    """A vehicle's exact equations, lambdified for mpmath.

    Attributes
    ----------
    dofs, inputs : tuple of str
    symbols : tuple of str
        Argument names of :attr:`functions`, in order (the speed among them when it is one).
    functions : dict of str to callable
        ``M``, ``C``, ``K`` and, when there are inputs, ``P``, ``Pd``: mpmath matrices of the
        arguments.
    speed : str or None
        Name of the speed parameter (``v``), None for a model without rail data.
    stations : dict of str to sympy.Expr
        Longitudinal position [m] of each wheelset body (rail vehicles).
    irregularity : tuple of str
        The lateral alignment inputs, one per wheelset, in the order of ``stations``.
    outputs : dict of str to dict of str to sympy.Expr
        Output points: the coefficient of each DOF in their lateral displacement.
    """

    dofs: tuple[str, ...]
    inputs: tuple[str, ...]
    symbols: tuple[str, ...]
    functions: dict
    speed: str | None
    stations: dict
    irregularity: tuple[str, ...]
    outputs: dict


def exact_vehicle(vehicle) -> ExactVehicle:
    """The exact equations of a :class:`express.numeric.statespace.VehicleModel`."""
    equations = vehicle.equations
    symbols = tuple(equations.parameters)
    arguments = [sp.Symbol(name) for name in symbols]
    by_name = {s.name: s for m in equations.matrices.values() for s in m.free_symbols}
    arguments = [by_name.get(name, symbol) for name, symbol in zip(symbols, arguments, strict=True)]
    functions = {
        name: sp.lambdify(arguments, sp.Matrix(matrix), modules="mpmath")
        for name, matrix in equations.matrices.items() if name in ("M", "C", "K", "P", "Pd")
    }
    model = vehicle.model
    speed = speed_name(vehicle)
    stations, irregularity, outputs = {}, (), {}
    if vehicle.layout is not None and vehicle.wheelsets and model is not None and model.rail is not None:
        stations = {w.name: sp.sympify(model.body(w.name).position[0]) for w in vehicle.wheelsets}
        irregularity = tuple(vehicle.layout.irregularity)
        outputs = {point.name: _lateral_row(model, vehicle.dofs, point) for point in model.rail.outputs}
    return ExactVehicle(equations.dofs, equations.inputs, symbols, functions, speed, stations, irregularity, outputs)


def speed_name(vehicle) -> str | None:
    """The name of the speed parameter of a rail vehicle (``v``), None without rail data."""
    rail = vehicle.model.rail if vehicle.model is not None else None
    if rail is None or not vehicle.wheelsets or not isinstance(rail.speed, sp.Symbol):
        return None
    return rail.speed.name


def _lateral_row(model, dofs: Sequence[str], point) -> dict:
    """``u_y = y + rz lx - rx lz`` of a point on a body (as
    :func:`express.numeric.statespace.point_lateral_row`), as exact coefficients."""
    body = model.body(point.body)
    lx, lz = sp.sympify(point.offset[0]), sp.sympify(point.offset[2])
    row = {}
    for dof, coefficient in (("y", sp.S.One), ("rz", lx), ("rx", -lz)):
        name = f"{body.id}.{dof}"
        if dof in body.dofs and name in dofs:
            row[name] = row.get(name, sp.S.Zero) + coefficient
    return row


def _mp(value) -> mpmath.mpf:
    """An mpf at the current precision: a decimal text or a float read as its shortest
    decimal (``repr``), an mpf kept as it is."""
    if isinstance(value, mpmath.mpf):
        return value
    return mpmath.mpf(value if isinstance(value, str) else repr(float(value)))


def evaluate(exact: ExactVehicle, values: Mapping[str, str], speed=None) -> dict[str, mpmath.matrix]:
    """``M``, ``C``, ``K`` (and ``P``, ``Pd``) at ``values`` (decimal texts) and ``speed``
    [m/s], as mpmath matrices at the current precision."""
    arguments = [_mp(speed) if name == exact.speed else _mp(values[name]) for name in exact.symbols]
    return {name: mpmath.matrix(function(*arguments)) for name, function in exact.functions.items()}


def speed_split(exact: ExactVehicle, values: Mapping[str, str]) -> dict[str, mpmath.matrix]:
    """``M, K, C0, C1, P0, P2, Pd`` with ``C(v) = C0 + C1 / v`` and ``P(v) = P0 + P2 v^2``.

    Found from the matrices at ``v = 1`` and ``v = 2`` and checked at ``v = 3`` (the
    speed enters the exact equations only that way).
    """
    one, two = evaluate(exact, values, 1), evaluate(exact, values, 2)
    split = {"M": one["M"], "K": one["K"], "C0": 2 * two["C"] - one["C"], "C1": 2 * (one["C"] - two["C"])}
    if "P" in one:
        split |= {"P0": (4 * one["P"] - two["P"]) / 3, "P2": (two["P"] - one["P"]) / 3, "Pd": one["Pd"]}
    if exact.speed is not None:
        three = evaluate(exact, values, 3)
        _check_same(three["C"], split["C0"] + split["C1"] / 3, "C(v) = C0 + C1/v")
        if "P" in one:
            _check_same(three["P"], split["P0"] + 9 * split["P2"], "P(v) = P0 + P2 v^2")
    return split


def _check_same(a: mpmath.matrix, b: mpmath.matrix, what: str) -> None:
    scale = max(mpmath.mnorm(a, 1), mpmath.mpf(1))
    if mpmath.mnorm(a - b, 1) > scale * mpmath.mpf(10) ** (10 - mpmath.mp.dps):
        raise ValueError(f"the speed does not enter as {what}")


def damping(split: Mapping[str, mpmath.matrix], speed) -> mpmath.matrix:
    """``C(v)`` [N s/m ...]."""
    return split["C0"] + split["C1"] / _mp(speed) if "C1" in split else split["C0"]


def forcing(split: Mapping[str, mpmath.matrix], speed) -> mpmath.matrix:
    """``P(v)``."""
    return split["P0"] + split["P2"] * _mp(speed) ** 2


def state_matrix(mass: mpmath.matrix, damping_: mpmath.matrix, stiffness: mpmath.matrix) -> mpmath.matrix:
    """``[[0, I], [-M^-1 K, -M^-1 C]]``, shape (2n, 2n)."""
    n = mass.rows
    inverse = mpmath.inverse(mass)
    lower_k, lower_c = -(inverse * stiffness), -(inverse * damping_)
    a = mpmath.zeros(2 * n, 2 * n)
    for i in range(n):
        a[i, n + i] = 1
        for j in range(n):
            a[n + i, j] = lower_k[i, j]
            a[n + i, n + j] = lower_c[i, j]
    return a


def coupled_blocks(*matrices: mpmath.matrix) -> list[list[int]]:
    """The DOFs in groups that no matrix couples (connected components of the pattern of
    non-zero entries, :func:`express.assembly.mass_blocks.coupled_groups`), each sorted,
    in the order of their first DOF: the eigenvalues of the whole are those of the groups
    together (exact, it is only a permutation)."""
    n = matrices[0].rows
    pattern = np.zeros((n, n), dtype=bool)
    for matrix in matrices:
        pattern |= np.array([[matrix[i, j] != 0 for j in range(n)] for i in range(n)])
    return [group.tolist() for group in coupled_groups(pattern)]


def _part(matrix: mpmath.matrix, index: list[int]) -> mpmath.matrix:
    return mpmath.matrix([[matrix[i, j] for j in index] for i in index])


def eigenvalues(mass, damping_, stiffness) -> list:
    """Every eigenvalue [1/s] (mpc), roots of ``det(lambda^2 M + lambda C + K)``: the
    eigenvalues of the state matrix of each group of :func:`coupled_blocks`."""
    values = []
    for index in coupled_blocks(mass, damping_, stiffness):
        a = state_matrix(_part(mass, index), _part(damping_, index), _part(stiffness, index))
        values += mpmath.eig(a, left=False, right=False)
    return values


def refine_eigenpair(mass, damping_, stiffness, value, vector, *, iterations: int = 30):
    """Newton on ``(lambda^2 M + lambda C + K) x = 0`` with the largest component of ``x``
    held at 1; returns ``(lambda, x)`` converged to the working precision.

    Raises
    ------
    ArithmeticError
        When it does not converge (a start too far from a simple eigenvalue).
    """
    n = mass.rows
    x = mpmath.matrix([mpmath.mpc(complex(c)) for c in vector])
    k = max(range(n), key=lambda i: abs(x[i]))
    x = x / x[k]
    lam = mpmath.mpc(complex(value))
    tolerance = mpmath.mpf(10) ** (8 - mpmath.mp.dps)
    for _ in range(iterations):
        q = lam**2 * mass + lam * damping_ + stiffness
        residual = q * x
        jacobian = q.copy()
        derivative = (2 * lam * mass + damping_) * x
        for i in range(n):
            jacobian[i, k] = derivative[i]
        step = mpmath.lu_solve(jacobian, -residual)
        lam += step[k]
        for i in range(n):
            if i != k:
                x[i] += step[i]
        if abs(step[k]) <= tolerance * abs(lam):
            return lam, x
    raise ArithmeticError(f"the eigenpair near {complex(value)} did not converge")


def critical_speed(split, start_speed: float, start_value: complex, start_vector, *, iterations: int = 40):
    """Speed [m/s] where the real part of the eigenvalue followed from ``start_value``
    (at ``start_speed``) is zero, and the eigenvalue there (secant on the speed).

    Returns
    -------
    (mpf, mpc, int)
        The speed, the eigenvalue (real part zero to the working precision) and the
        number of speeds evaluated.
    """
    mass, stiffness = split["M"], split["K"]
    lam, x = refine_eigenpair(mass, damping(split, start_speed), stiffness, start_value, start_vector)
    v0, g0 = _mp(start_speed), lam.real
    v1 = v0 * (1 + mpmath.mpf("1e-7"))
    tolerance = mpmath.mpf(10) ** (10 - mpmath.mp.dps)
    for count in range(2, iterations):
        lam, x = refine_eigenpair(mass, damping(split, v1), stiffness, lam, x)
        g1 = lam.real
        if g1 == g0:
            raise ArithmeticError("the secant on the speed stalled")
        v2 = v1 - g1 * (v1 - v0) / (g1 - g0)
        v0, g0, v1 = v1, g1, v2
        if abs(v1 - v0) <= tolerance * abs(v1):
            lam, x = refine_eigenpair(mass, damping(split, v1), stiffness, lam, x)
            return v1, lam, count + 1
    raise ArithmeticError("the critical speed did not converge")


def station_values(exact: ExactVehicle, values: Mapping[str, str]) -> list:
    """Position [m] of each wheelset, in the order of :attr:`ExactVehicle.stations`."""
    return [_expression(expression, values) for expression in exact.stations.values()]


def _expression(expression, values: Mapping[str, str]):
    expression = sp.sympify(expression)
    names = sorted(s.name for s in expression.free_symbols)
    function = sp.lambdify([sp.Symbol(n) for n in names], expression.subs(
        {s: sp.Symbol(s.name) for s in expression.free_symbols}), modules="mpmath")
    return mpmath.mpf(function(*[_mp(values[n]) for n in names]))


def track_response(exact, split, values, speed, frequencies) -> dict[str, list]:
    """Complex amplitudes of every DOF and output point per metre of lateral alignment
    ``yR_n = Im(exp(i w (t - t_n)))``, ``t_n = (x_lead - x_n) / v``, at each frequency [Hz]:
    ``{name: [X at f for f in frequencies]}``."""
    v = _mp(speed)
    stations = station_values(exact, values)
    lead = max(stations)
    columns = [exact.inputs.index(name) for name in exact.irregularity]
    mass, stiffness, c, p = split["M"], split["K"], damping(split, v), forcing(split, v)
    rows = {name: {dof: _expression(e, values) for dof, e in row.items()} for name, row in exact.outputs.items()}
    result: dict[str, list] = {name: [] for name in (*exact.dofs, *exact.outputs)}
    for f in frequencies:
        w = 2 * mpmath.pi * _mp(f)
        units = [mpmath.expj(-w * (lead - x) / v) for x in stations]
        rhs = mpmath.matrix(mass.rows, 1)
        for column, u in zip(columns, units, strict=True):
            for i in range(mass.rows):
                rhs[i] += (p[i, column] + 1j * w * split["Pd"][i, column]) * u
        x = mpmath.lu_solve(-(w**2) * mass + 1j * w * c + stiffness, rhs)
        for i, dof in enumerate(exact.dofs):
            result[dof].append(x[i])
        for name, row in rows.items():
            result[name].append(mpmath.fsum(coefficient * x[exact.dofs.index(dof)] for dof, coefficient in row.items()))
    return result


def ground_response(exact, split, frequencies) -> dict[tuple[str, str], list]:
    """``H`` of every DOF per unit sinusoid of every input (a model without rail data):
    ``(-w^2 M + i w C + K) H = P + i w Pd``; ``{(dof, input): [H at f ...]}``."""
    result: dict[tuple[str, str], list] = {(d, u): [] for d in exact.dofs for u in exact.inputs}
    for f in frequencies:
        w = 2 * mpmath.pi * _mp(f)
        z = -(w**2) * split["M"] + 1j * w * split["C0"] + split["K"]
        for j, name in enumerate(exact.inputs):
            rhs = mpmath.matrix([split["P0"][i, j] + 1j * w * split["Pd"][i, j] for i in range(z.rows)])
            h = mpmath.lu_solve(z, rhs)
            for i, dof in enumerate(exact.dofs):
                result[dof, name].append(h[i])
    return result


def start_eigenpair(vehicle, speed: float) -> tuple[complex, np.ndarray]:
    """The least stable eigenvalue of the library's double-precision ``A(v)`` and the
    ``q`` part of its eigenvector: the start of :func:`critical_speed`."""
    values, vectors = np.linalg.eig(vehicle.state_matrix(float(speed)))
    k = int(np.argmax(values.real + 1e-12 * np.sign(values.imag)))  # the member with Im >= 0
    return complex(values[k]), vectors[: vehicle.n, k]
