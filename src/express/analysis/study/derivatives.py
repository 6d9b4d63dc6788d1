"""Derivatives of a model's matrices and of its parameter graph, compiled once per model.

**Matrices.** Every non-zero entry of ``M``, ``C`` and ``K`` is differentiated (SymPy)
with respect to every parameter symbol it holds, once, when :class:`MatrixDerivatives`
is built; the derivatives are compiled into one function of the parameters
(:class:`express.numeric.compiled.CompiledExpressions`: common subexpressions shared, constants
exact), as :mod:`express.numeric.compiled` compiles the matrices themselves. An evaluation is one
call of that function (a few microseconds per entry) giving the numbers of every
``dM/dq``, ``dC/dq``, ``dK/dq`` (``C`` at the speed in the values); the contraction
``u^H (lambda^2 dM/dq + lambda dC/dq + dK/dq) x`` that an eigenvalue derivative needs
is a gather and a segmented sum over these numbers, for every ``q`` and every
eigenvalue at once. No symbolic work happens per evaluation.

**Parameter graph.** A parameter acts on the matrices directly and through the
parameters derived from it (the live graph of :mod:`express.model.parameters`). The rates
``dq/dp`` follow by the chain rule forward through the graph in its evaluation order
(:class:`GraphRates`): the partial derivatives of every derived expression
(``P0 = (mc + 2*mt + 4*mw)*g/8``) and of every argument of a derivation node are
compiled once, like the matrices, and evaluated per point; the rates of a
derivation's outputs (``[rail.creep]``: f1, f2 from the wheel load, radii and elastic
constants through the Hertz ellipse and Kalker's table, a function without a closed
form) are the central differences of that one function with respect to each argument
that moves (relative step :data:`DERIVED_STEP`), combined with the arguments' rates.
No eigenvalue is ever differenced.

Both are cached per set of equations (and per shape of the graph: a derived parameter
given a value at a point becomes a given one), so that every point of a study and every
eigenvalue of a sweep reuse them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import sympy as sp

from express.base.caches import IdentityCache
from express.base.diagnostics import ArgumentError
from express.model.parameters import derivation_function, evaluation_order
from express.model.records import Derivation
from express.numeric.compiled import CompiledExpressions

__all__ = ["DERIVED_STEP", "GraphRates", "MatrixDerivatives", "graph_rates", "matrix_derivatives"]

#: Relative step of the central difference of a derivation function (absolute for an
#: argument whose value is 0).
DERIVED_STEP = 1e-4

#: Matrices differentiated, in the order of the contraction's coefficients
#: ``lambda^2``, ``lambda``, ``1``.
KEYS = ("M", "C", "K")


def _compiled(expressions: Sequence[sp.Expr]) -> CompiledExpressions:
    return CompiledExpressions(list(expressions))


def _evaluate(compiled: CompiledExpressions, values: Mapping[str, float], what: str) -> np.ndarray:
    try:
        return compiled(values)
    except ValueError:
        raise ArgumentError(f"{what} is not finite at these parameter values") from None


class MatrixDerivatives:
    """``dM/dq``, ``dC/dq``, ``dK/dq`` of every parameter symbol ``q`` of a set of
    equations, compiled once (module docstring).

    Parameters
    ----------
    equations : EquationsOfMotion

    Attributes
    ----------
    parameters : tuple of str
        The symbols with a non-zero derivative, sorted; the rows of :meth:`contract`.
    size : int
        Number of non-zero derivative entries (all matrices and symbols).
    """

    def __init__(self, equations) -> None:
        self.equations = equations
        self.n = len(equations.dofs)
        slots: list[tuple[str, int, int, int, sp.Expr]] = []  # (symbol, matrix, i, j, derivative)
        for k, key in enumerate(KEYS):
            for (i, j), entry in sorted(equations.matrices[key].todok().items()):
                entry = sp.sympify(entry)
                for symbol in entry.free_symbols:
                    derivative = sp.diff(entry, symbol)
                    if derivative != 0:
                        slots.append((symbol.name, k, i, j, derivative))
        slots.sort(key=lambda slot: (slot[0], slot[1], slot[2], slot[3]))
        self.parameters = tuple(sorted({slot[0] for slot in slots}))
        position = {name: k for k, name in enumerate(self.parameters)}
        self.size = len(slots)
        self._symbol = np.array([position[s[0]] for s in slots], dtype=np.intp)
        self._matrix = np.array([s[1] for s in slots], dtype=np.intp)
        self._rows = np.array([s[2] for s in slots], dtype=np.intp)
        self._columns = np.array([s[3] for s in slots], dtype=np.intp)
        self._starts = np.searchsorted(self._symbol, np.arange(len(self.parameters)))
        self._function = _compiled([s[4] for s in slots])

    def __call__(self, values: Mapping[str, float]) -> np.ndarray:
        """The numbers of every derivative entry at ``values`` (SI by name; the speed
        parameter gives the speed of ``C``), shape (size,).

        Raises
        ------
        ArgumentError
            When a derivative is not finite there.
        """
        if self.size == 0:
            return np.zeros(0)
        return _evaluate(self._function, values, "a derivative of the matrices")

    def matrices(self, values: Mapping[str, float]) -> dict[str, dict[str, np.ndarray]]:
        """``{q: {"M": dM/dq, "C": dC/dq, "K": dK/dq}}`` at ``values``, dense, each shape
        (n, n) (for inspection; :meth:`contract` does not build them)."""
        numbers = self(values)
        result = {name: {key: np.zeros((self.n, self.n)) for key in KEYS} for name in self.parameters}
        for s in range(self.size):
            result[self.parameters[self._symbol[s]]][KEYS[self._matrix[s]]][self._rows[s], self._columns[s]] = numbers[s]
        return result

    def contract(self, numbers: np.ndarray, eigenvalues: np.ndarray, left: np.ndarray, right: np.ndarray) -> np.ndarray:
        """``u_k^H (lambda_k^2 dM/dq + lambda_k dC/dq + dK/dq) x_k`` for every symbol ``q``
        and eigenvalue ``k``.

        Parameters
        ----------
        numbers : numpy.ndarray, shape (size,)
            From :meth:`__call__`.
        eigenvalues : numpy.ndarray, complex, shape (E,)
        left, right : numpy.ndarray, complex, shape (n, E)
            The left and right null vectors ``u_k``, ``x_k`` of ``Q(lambda_k)``.

        Returns
        -------
        numpy.ndarray, complex, shape (len(parameters), E)
        """
        eigenvalues = np.asarray(eigenvalues, dtype=complex)
        if self.size == 0:
            return np.zeros((0, eigenvalues.size), dtype=complex)
        coefficients = np.stack([eigenvalues**2, eigenvalues, np.ones_like(eigenvalues)])  # (3, E)
        terms = left.conj()[self._rows] * right[self._columns] * coefficients[self._matrix] * numbers[:, None]
        return np.add.reduceat(terms, self._starts, axis=0)


class GraphRates:
    """The chain rule through a model's parameter graph, compiled once (module docstring).

    Parameters
    ----------
    model : Model
    """

    def __init__(self, model) -> None:
        self.model = model
        expressions: list[sp.Expr] = []
        self._steps: list[tuple] = []

        def add(expression) -> tuple[tuple[str, ...], int]:
            """Compile the partials of ``expression`` (and, for an argument, its value)."""
            expression = sp.sympify(expression)
            sources = tuple(sorted(s.name for s in expression.free_symbols))
            start = len(expressions)
            expressions.extend(sp.diff(expression, sp.Symbol(name)) for name in sources)
            return sources, start

        for node in evaluation_order(model):
            if isinstance(node, Derivation):
                arguments = []
                for argument, expression, _ in node.inputs:
                    sources, start = add(expression)
                    expressions.append(sp.sympify(expression))  # the argument's value, after its partials
                    arguments.append((argument, sources, start))
                outputs = tuple((key, name) for key, name, _ in node.outputs
                                if name in model.parameters and model.parameters[name].derived_by == node.item)
                self._steps.append(("derivation", node, tuple(arguments), outputs))
            elif node.expression is not None:
                sources, start = add(node.expression)
                self._steps.append(("expression", node.name, sources, start))
        self._partials = _compiled(expressions)

    def rates(self, values: Mapping[str, float], names: Sequence[str]) -> dict[str, np.ndarray]:
        """``dq/dp`` of every parameter ``q`` that depends on the parameters ``p`` in
        ``names`` (their own rates: unit vectors), each shape (len(names),).

        Parameters
        ----------
        values : mapping of str to float
            The model's values (SI).
        names : sequence of str

        Raises
        ------
        ArgumentError
            When a partial derivative is not finite there, or a derivation function
            refuses its perturbed arguments.
        """
        seeds = {name: np.eye(len(names))[k] for k, name in enumerate(names)}
        rates: dict[str, np.ndarray] = dict(seeds)
        if not self._steps:
            return rates
        partials = _evaluate(self._partials, values, "a derivative of the parameter graph")
        zero = np.zeros(len(names))
        for step in self._steps:
            if step[0] == "expression":
                _, target, sources, start = step
                rate = _combine(partials, start, sources, rates, zero)
                updates = {target: rate}
            else:
                updates = self._derivation(step, partials, rates, zero)
            for target, rate in updates.items():
                total = rate + seeds[target] if target in seeds else rate
                if np.any(total):
                    rates[target] = total
        return rates

    def _derivation(self, step: tuple, partials: np.ndarray, rates, zero: np.ndarray) -> dict[str, np.ndarray]:
        """Rates of a derivation's outputs: central differences of its function with
        respect to each argument that moves, times the argument's rate."""
        _, node, arguments, outputs = step
        value = {argument: float(partials[start + len(sources)]) for argument, sources, start in arguments}
        function = derivation_function(node.kind)
        settings = dict(node.settings)
        result = {name: zero.copy() for _, name in outputs}
        for argument, sources, start in arguments:
            moving = _combine(partials, start, sources, rates, zero)
            if not np.any(moving):
                continue
            step_size = DERIVED_STEP * abs(value[argument]) or DERIVED_STEP
            plus = function(**{**value, argument: value[argument] + step_size}, **settings)
            minus = function(**{**value, argument: value[argument] - step_size}, **settings)
            for key, name in outputs:
                result[name] = result[name] + (plus[key] - minus[key]) / (2.0 * step_size) * moving
        return result


def _combine(partials: np.ndarray, start: int, sources: tuple[str, ...], rates, zero: np.ndarray) -> np.ndarray:
    """``sum_s (d expression / d s) (ds/dp)`` over the expression's sources."""
    total = zero
    for k, source in enumerate(sources):
        rate = rates.get(source)
        if rate is not None:
            total = total + partials[start + k] * rate
    return total


#: Models (sets of equations) kept compiled.
_KEEP = 4
_MATRICES: IdentityCache[MatrixDerivatives] = IdentityCache(_KEEP)
_GRAPHS: IdentityCache[GraphRates] = IdentityCache(_KEEP)


def matrix_derivatives(equations) -> MatrixDerivatives:
    """The compiled derivatives of ``equations``' matrices (cached per set of equations)."""
    return _MATRICES.get_or_make((equations,), lambda: MatrixDerivatives(equations))


def graph_rates(model, equations) -> GraphRates:
    """The compiled chain rule of ``model``'s parameter graph (cached per set of
    equations and shape of the graph: which parameters are derived, and how)."""
    derived = [(name, p) for name, p in model.parameters.items() if p.expression is not None or p.derived_by]
    shape = tuple((name, p.derived_by) for name, p in derived)
    return _GRAPHS.get_or_make((equations, *(p.expression for _, p in derived)), lambda: GraphRates(model), shape)
