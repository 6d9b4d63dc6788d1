"""Numerical matrices of a set of equations, compiled once per model.

The symbolic M, C, K, P, Pd (and any further matrix) are turned into one generated
NumPy-free Python function of the parameter vector: the non-zero entries are
collected, identical entries evaluated once (the cars of a train share theirs), and
the common subexpressions of what remains shared (:func:`sympy.cse`, as a
straight-line program, :class:`express.numeric.program.ExpressionProgram`).  A call costs a few microseconds per distinct entry and a
scatter into zero arrays, whatever the number of cars; no ``subs`` or ``xreplace``
is ever used per point.

The speed ``v`` is kept apart: the entries that contain it have their own function,
evaluated at three speeds to separate ``C = C0 + C1 / v`` and ``P = P0 + P2 v**2``
(checked at the third speed), which is how :class:`express.numeric.statespace.VehicleModel`
gets ``A(v) = A0 + A1 / v`` exactly.

The eigenvalues of ``A(v)`` are then found block by block (:class:`EigenBlocks`): an
entry that is zero in both ``A0`` and ``A1`` is zero at every speed; the strongly
connected components of the graph ``i -> j`` of the other entries ``A[i, j]``, taken in
a topological order of the graph of components, permute ``A(v)`` into block
upper-triangular form at every speed (an edge between two components only runs one
way), and the eigenvalues of a block-triangular matrix are those of its diagonal
blocks.  Exact (no tolerance: the zeros are the floats' own, the structural zeros of
the exact symbolic model, e.g. vertical and lateral motions nothing couples), it costs
``sum(size^3)`` instead of ``N^3``; the order of the blocks does not change the set of
eigenvalues, so none is needed.  A matrix with one component (the forced-steering car:
its levers couple everything) is solved whole, with the same stacked
:func:`numpy.linalg.eigvals` call on the same array as before; the conventional car
splits into 34 + 6 states, the Manchester 3-D car (``examples/manchester.toml``) into
42 + 20 (``docs/benchmarks.md``).

Examples
--------
>>> from express.io import load_model
>>> from express.rail.build import generate_vehicle
>>> equations = generate_vehicle(load_model("examples/conventional.toml")).equations
>>> compiled = compile_matrices(equations, speed="v")
>>> split = compiled.speed_split(compiled.vector(equations.values))
>>> split.matrices["M"].shape, split.damping_creep.shape
((20, 20), (20, 20))
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from express.assembly.equations import EquationsOfMotion, Matrices
from express.base.diagnostics import ArgumentError
from express.numeric.program import ExpressionProgram, UnsupportedExpressionError

if TYPE_CHECKING:  # imported where used: matrices read from the derivation cache need no SymPy
    import sympy as sp

__all__ = ["CompiledMatrices", "EigenBlocks", "SpeedSplit", "compile_matrices", "diagonal_blocks", "strong_components"]

#: The three speeds [m/s] at which the speed-dependent entries are evaluated.
SPLIT_SPEEDS = (1.0, 2.0, 3.0)


@dataclass(frozen=True)
class SpeedSplit:
    """Matrices with the speed kept apart.

    Attributes
    ----------
    matrices : Matrices of numpy.ndarray
        Every matrix, with ``C`` the speed-independent part ``C0`` and ``P`` the part
        ``P0`` (the others do not depend on the speed).
    damping_creep : numpy.ndarray, shape (n, n)
        ``C1`` in ``C(v) = C0 + C1 / v``.
    forcing_speed2 : numpy.ndarray, shape (n, m)
        ``P2`` in ``P(v) = P0 + P2 v**2``.
    """

    matrices: Matrices[np.ndarray]
    damping_creep: np.ndarray
    forcing_speed2: np.ndarray

    def __post_init__(self) -> None:
        object.__setattr__(self, "matrices", Matrices.of(self.matrices))


class _Entries:
    """Distinct non-zero entries compiled into one function of the parameters (through
    an :class:`~express.numeric.program.ExpressionProgram`, the form the derivation
    cache stores)."""

    def __init__(self, expressions: Sequence[sp.Expr], symbols: Sequence[sp.Symbol]):
        self.size = len(expressions)
        self.program: ExpressionProgram | None = None
        try:
            self.program = ExpressionProgram.from_expressions(expressions, [symbol.name for symbol in symbols])
        except UnsupportedExpressionError:  # a function (sin, Abs): compiled by SymPy, not cacheable
            import sympy as sp

            exact = [e.xreplace({f: sp.Rational(f) for f in e.atoms(sp.Float)}) for e in expressions]
            self.function = sp.lambdify(list(symbols), exact, modules="math", cse=True)
            return
        self.function = self.program.function() if self.size else None

    @classmethod
    def from_program(cls, program: ExpressionProgram) -> _Entries:
        """Entries computed by ``program`` (read back from the cache: no SymPy work)."""
        entries = cls.__new__(cls)
        entries.program = program
        entries.size = program.size
        entries.function = program.function() if program.size else None
        return entries

    def __call__(self, arguments: Sequence[float]) -> np.ndarray:
        if self.function is None:
            return np.zeros(0)
        try:
            values = self.function(*arguments)
        except (ZeroDivisionError, OverflowError) as error:
            raise ArgumentError(f"a value is not finite at these parameter values ({error})") from None
        return np.array(values, dtype=float).reshape(self.size)


class CompiledMatrices:
    """Every matrix of ``equations`` as compiled functions of the parameter vector.

    Build with :func:`compile_matrices`.

    Attributes
    ----------
    parameters : tuple of str
        Names of the parameters, in the order of the vector :meth:`vector` builds
        (the equations' parameters, the speed included).
    speed : str or None
        The parameter kept apart as the speed, when it appears in the matrices.
    shapes : dict of str to tuple of int
        Shape of every matrix.
    """

    def __init__(self, equations: EquationsOfMotion, speed: str | None = None):
        self.parameters = tuple(equations.parameters)
        self.speed = speed if speed in self.parameters else None
        self.shapes = {key: tuple(matrix.shape) for key, matrix in equations.matrices.items()}
        import sympy as sp

        symbols = [sp.Symbol(name) for name in self.parameters]
        speed_symbol = sp.Symbol(self.speed) if self.speed else None
        distinct: dict[sp.Expr, tuple[bool, int]] = {}  # expression -> (with speed, index)
        lists: tuple[list[sp.Expr], list[sp.Expr]] = ([], [])
        self._scatter: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = {}
        for key, matrix in equations.matrices.items():
            places: tuple[list[int], list[int]] = ([], [])
            sources: tuple[list[int], list[int]] = ([], [])
            for (i, j), expression in sorted(matrix.todok().items()):
                if expression == 0:
                    continue
                if expression not in distinct:
                    with_speed = speed_symbol is not None and speed_symbol in expression.free_symbols
                    distinct[expression] = (with_speed, len(lists[with_speed]))
                    lists[with_speed].append(expression)
                with_speed, index = distinct[expression]
                places[with_speed].append(i * self.shapes[key][1] + j)
                sources[with_speed].append(index)
            self._scatter[key] = tuple(np.array(x, dtype=np.intp) for x in (*places, *sources))  # type: ignore[assignment]
        self._constant = _Entries(lists[False], symbols)
        self._speed_dependent = _Entries(lists[True], symbols)
        self._speed_position = self.parameters.index(self.speed) if self.speed else -1

    @classmethod
    def from_programs(
        cls,
        parameters: Sequence[str],
        speed: str | None,
        shapes: Mapping[str, tuple[int, int]],
        scatter: Mapping[str, tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]],
        constant: ExpressionProgram,
        speed_dependent: ExpressionProgram,
    ) -> CompiledMatrices:
        """The compiled matrices of :meth:`programs`' parts (read back from the derivation
        cache, :mod:`express.numeric.derived`: no SymPy work)."""
        compiled = cls.__new__(cls)
        compiled.parameters = tuple(parameters)
        compiled.speed = speed
        compiled.shapes = dict(shapes)
        compiled._scatter = dict(scatter)
        compiled._constant = _Entries.from_program(constant)
        compiled._speed_dependent = _Entries.from_program(speed_dependent)
        compiled._speed_position = compiled.parameters.index(speed) if speed else -1
        return compiled

    def programs(self) -> tuple[ExpressionProgram, ExpressionProgram, dict[str, tuple[np.ndarray, ...]]]:
        """``(constant entries, speed-dependent entries, scatter)``: the program of the
        distinct entries without and with the speed, and per matrix the flat places and
        the entry indices of each (``places0, places1, sources0, sources1``).

        Raises
        ------
        UnsupportedExpressionError
            When an entry has a function (compiled by SymPy instead; nothing to store).
        """
        if self._constant.program is None or self._speed_dependent.program is None:
            raise UnsupportedExpressionError("an entry has a function: no program")
        return self._constant.program, self._speed_dependent.program, dict(self._scatter)

    @property
    def distinct_entries(self) -> int:
        """Number of distinct non-zero entries compiled (over every matrix)."""
        return self._constant.size + self._speed_dependent.size

    def vector(self, values: Mapping[str, float]) -> np.ndarray:
        """The parameter vector of ``values`` (SI floats by name), shape (len(parameters),).

        Raises
        ------
        ArgumentError
            Naming the parameters that have no value.
        """
        missing = [name for name in self.parameters if name not in values]
        if missing:
            raise ArgumentError(f"no value for parameter{'s' if len(missing) > 1 else ''} {', '.join(missing)}")
        return np.array([float(values[name]) for name in self.parameters], dtype=float)

    def _assemble(self, constant: np.ndarray, speed_dependent: np.ndarray) -> dict[str, np.ndarray]:
        result = {}
        for key, (places0, places1, sources0, sources1) in self._scatter.items():
            flat = np.zeros(self.shapes[key][0] * self.shapes[key][1])
            flat[places0] = constant[sources0]
            flat[places1] = speed_dependent[sources1]
            result[key] = flat.reshape(self.shapes[key])
        return result

    def __call__(self, parameters: Sequence[float] | np.ndarray) -> Matrices[np.ndarray]:
        """Every matrix at the parameter vector ``parameters`` (the speed included).

        Raises
        ------
        ArgumentError
            When an entry is not finite there (a division by zero).
        """
        arguments = [float(x) for x in parameters]
        return Matrices.of(self._check_finite(self._assemble(self._constant(arguments), self._speed_dependent(arguments))))

    def sparse(self, parameters: Sequence[float] | np.ndarray) -> dict[str, Any]:
        """Every matrix at ``parameters`` as a ``scipy.sparse.csr_array``: memory and time
        follow the non-zeros, for models too big for dense arrays (a 1000-car train has
        24 000 DOFs: a dense M alone would take 4.6 GB).

        Raises
        ------
        ArgumentError
            When an entry is not finite there (a division by zero).
        """
        from scipy.sparse import csr_array

        arguments = [float(x) for x in parameters]
        constant, speed_dependent = self._constant(arguments), self._speed_dependent(arguments)
        if not (np.all(np.isfinite(constant)) and np.all(np.isfinite(speed_dependent))):
            raise ArgumentError("the matrices are not finite at these parameter values (division by zero or overflow)")
        result = {}
        for key, (places0, places1, sources0, sources1) in self._scatter.items():
            rows, columns = self.shapes[key]
            places = np.concatenate([places0, places1])
            values = np.concatenate([constant[sources0], speed_dependent[sources1]])
            result[key] = csr_array((values, (places // columns, places % columns)), shape=(rows, columns))
        return result

    def speed_split(self, parameters: Sequence[float] | np.ndarray) -> SpeedSplit:
        """The matrices with ``C = C0 + C1 / v`` and ``P = P0 + P2 v**2`` separated.

        The speed's own value in ``parameters`` is ignored.

        Raises
        ------
        ArgumentError
            When the speed enters the matrices otherwise (checked at a third speed), or
            an entry is not finite.
        """
        arguments = [float(x) for x in parameters]
        constant = self._constant(arguments)
        if self.speed is None or self._speed_dependent.size == 0:
            matrices = self._check_finite(self._assemble(constant, np.zeros(self._speed_dependent.size)))
            return SpeedSplit(Matrices.of(matrices), self._zeros("C"), self._zeros("P"))
        at = []
        for speed in SPLIT_SPEEDS:
            arguments[self._speed_position] = speed
            at.append(self._speed_dependent(arguments))
        return self._split(constant, at)

    def _split(self, constant: np.ndarray, at: list[np.ndarray]) -> SpeedSplit:
        """Separate the speed on the entry vectors (no dense work beyond one assembly)."""
        one, two, three = at
        v1, v2, v3 = SPLIT_SPEEDS
        for values in (constant, *at):
            if not np.all(np.isfinite(values)):
                raise ArgumentError("the matrices are not finite at these parameter values (division by zero or overflow)")
        base_values: dict[str, np.ndarray] = {}
        extra: dict[str, np.ndarray] = {}
        scale = 1.0
        for key in ("C", "P"):  # the check's scale: the largest entry of C(3) and P(3)
            if key in self._scatter:
                _, _, sources0, sources1 = self._scatter[key]
                scale = max(scale, _largest(constant[sources0]), _largest(three[sources1]))
        wrong = False
        for key, (_, _, sources0, sources1) in self._scatter.items():
            s1, s2, s3 = one[sources1], two[sources1], three[sources1]
            if key == "C":  # C(v) = C0 + C1 / v at v1, v2; checked at v3
                creep = (s1 - s2) / (1.0 / v1 - 1.0 / v2)
                base_values[key], extra[key] = s1 - creep / v1, creep
                wrong |= _largest(base_values[key] + creep / v3 - s3) > 1e-9 * scale
            elif key == "P":  # P(v) = P0 + P2 v^2
                speed2 = (s2 - s1) / (v2**2 - v1**2)
                base_values[key], extra[key] = s1 - speed2 * v1**2, speed2
                wrong |= _largest(base_values[key] + speed2 * v3**2 - s3) > 1e-9 * scale
            else:
                base_values[key] = s1
                size = max(_largest(constant[sources0]), _largest(s1))
                wrong |= _largest(s1 - s2) > (0.0 if key == "M" else 1e-9 * max(1.0, size))
        if wrong:
            raise ArgumentError(f"the speed {self.speed!r} enters the matrices other than as C0 + C1/v and P0 + P2 v^2")
        matrices = {}
        for key, (places0, places1, sources0, _) in self._scatter.items():
            flat = np.zeros(self.shapes[key][0] * self.shapes[key][1])
            flat[places0] = constant[sources0]
            flat[places1] = base_values[key]
            matrices[key] = flat.reshape(self.shapes[key])
        return SpeedSplit(Matrices.of(matrices), self._speed_part("C", extra), self._speed_part("P", extra))

    def _speed_part(self, key: str, extra: dict[str, np.ndarray]) -> np.ndarray:
        result = self._zeros(key)
        if key in extra:
            result.reshape(-1)[self._scatter[key][1]] = extra[key]
        return result

    def _zeros(self, key: str) -> np.ndarray:
        n = self.shapes["M"][0]
        if key == "P":
            return np.zeros(self.shapes.get("P", (n, 0)))
        return np.zeros((n, n))

    @staticmethod
    def _check_finite(matrices: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        for key, array in matrices.items():
            if not np.all(np.isfinite(array)):
                raise ArgumentError(f"matrix {key} is not finite at these parameter values (division by zero or overflow)")
        return matrices


def compile_matrices(equations: EquationsOfMotion, speed: str | None = None) -> CompiledMatrices:
    """Compile every matrix of ``equations`` (see the module docstring).

    Parameters
    ----------
    equations : EquationsOfMotion
    speed : str, optional
        Name of the speed parameter to keep apart (ignored when the matrices do not
        contain it).
    """
    return CompiledMatrices(equations, speed)


def _largest(values: np.ndarray) -> float:
    """Largest absolute value (0 for none)."""
    return float(np.abs(values).max(initial=0.0))


class CompiledExpressions:
    """A list of scalar parameter expressions compiled into one function (shared
    subexpressions computed once), evaluated from values by name.

    Examples
    --------
    >>> import sympy as sp
    >>> a, b = sp.symbols("a b")
    >>> compiled = CompiledExpressions([a + b, (a + b) * 2, sp.Integer(3)])
    >>> compiled({"a": 1.0, "b": 0.5}).tolist()
    [1.5, 3.0, 3.0]
    """

    def __init__(self, expressions: Sequence[sp.Expr]):
        import sympy as sp

        expressions = [sp.sympify(e) for e in expressions]
        self.size = len(expressions)
        self.names = tuple(sorted({s.name for e in expressions for s in e.free_symbols}))
        self._entries = _Entries(expressions, [sp.Symbol(name) for name in self.names])

    @property
    def program(self) -> ExpressionProgram:
        """The program that computes the expressions (the derivation cache stores it).

        Raises
        ------
        UnsupportedExpressionError
            When an expression has a function (compiled by SymPy instead).
        """
        if self._entries.program is None:
            raise UnsupportedExpressionError("an expression has a function: no program")
        return self._entries.program

    @classmethod
    def from_program(cls, program: ExpressionProgram) -> CompiledExpressions:
        """The compiled expressions of ``program`` (read back: no SymPy work)."""
        compiled = cls.__new__(cls)
        compiled.size = program.size
        compiled.names = program.parameters
        compiled._entries = _Entries.from_program(program)
        return compiled

    def __call__(self, values: Mapping[str, float]) -> np.ndarray:
        """Values of the expressions, shape (size,).

        Raises
        ------
        KeyError
            Naming the first parameter without a value.
        ArgumentError
            When a value is not finite (division by zero, overflow).
        """
        result = self._entries([float(values[name]) for name in self.names])
        if not np.all(np.isfinite(result)):
            raise ArgumentError("an expression is not finite at these parameter values")
        return result


# ------------------------------------------------------------------ eigenvalues by diagonal blocks

#: Bytes of one stacked eigvals call: big stacks of big matrices only fill the caches.
_STACK_BYTES = 1 << 20


def diagonal_blocks(*matrices: np.ndarray) -> tuple[np.ndarray, ...]:
    """The states of each diagonal block of the common sparsity pattern of ``matrices``.

    Parameters
    ----------
    *matrices : numpy.ndarray, shape (N, N)
        ``A0``, ``A1``: every entry non-zero in any of them is an edge.

    Returns
    -------
    tuple of numpy.ndarray of int
        The states (sorted) of each strongly connected component, largest first (ties:
        by first state).  One block ``arange(N)`` when nothing splits.
    """
    size = matrices[0].shape[0]
    pattern = np.zeros((size, size), dtype=bool)
    for matrix in matrices:
        pattern |= matrix != 0
    np.fill_diagonal(pattern, False)
    labels = strong_components([np.flatnonzero(row).tolist() for row in pattern])
    count = max(labels, default=0) + 1
    if count == 1:
        return (np.arange(size),)
    label_array = np.array(labels)
    blocks = [np.flatnonzero(label_array == label) for label in range(count)]
    blocks.sort(key=lambda block: (-block.size, int(block[0])))
    return tuple(blocks)


def strong_components(successors: Sequence[Sequence[int]]) -> list[int]:
    """The strongly connected component of every node of a directed graph (Tarjan's
    algorithm, iterative; linear in nodes and edges: a few milliseconds for a train's
    state matrix, without importing ``scipy.sparse.csgraph``, about 0.1 s of start-up).

    Parameters
    ----------
    successors : sequence of sequence of int
        ``successors[i]``: the nodes ``j`` of the edges ``i -> j``.

    Returns
    -------
    list of int
        Component label of each node, ``0 .. count - 1``, in the order the components
        are completed (a reverse topological order of the graph of components).

    Examples
    --------
    >>> strong_components([[1], [0, 2], [], [2]])
    [1, 1, 0, 2]
    """
    size = len(successors)
    index = [-1] * size
    low = [0] * size
    on_stack = [False] * size
    labels = [-1] * size
    stack: list[int] = []
    counter = count = 0
    for root in range(size):
        if index[root] >= 0:
            continue
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack[root] = True
        work = [(root, 0)]
        while work:
            node, position = work[-1]
            following = successors[node]
            if position < len(following):
                work[-1] = (node, position + 1)
                other = following[position]
                if index[other] < 0:
                    index[other] = low[other] = counter
                    counter += 1
                    stack.append(other)
                    on_stack[other] = True
                    work.append((other, 0))
                elif on_stack[other]:
                    low[node] = min(low[node], index[other])
                continue
            work.pop()
            if work:
                parent = work[-1][0]
                low[parent] = min(low[parent], low[node])
            if low[node] == index[node]:
                while True:
                    other = stack.pop()
                    on_stack[other] = False
                    labels[other] = count
                    if other == node:
                        break
                count += 1
    return labels


class EigenBlocks:
    """``A(v) = A0 + A1 / v`` split into its diagonal blocks once; eigenvalues at many speeds.

    Parameters
    ----------
    a0, a1 : numpy.ndarray, shape (N, N)
        The speed-independent part and the part divided by the speed [1/s].

    Examples
    --------
    >>> a0 = np.array([[1.0, 2.0, 0.0], [0.0, 3.0, 0.0], [5.0, 0.0, 4.0]])
    >>> blocks = EigenBlocks(a0, np.zeros((3, 3)))
    >>> [b.tolist() for b in blocks.blocks]
    [[0], [1], [2]]
    >>> np.sort(blocks.eigenvalues(np.array([1.0])).real)
    array([[1., 3., 4.]])
    """

    def __init__(self, a0: np.ndarray, a1: np.ndarray) -> None:
        self.size = a0.shape[0]
        self.blocks = diagonal_blocks(a0, a1)
        if len(self.blocks) == 1:
            self.pieces = [(a0, a1)]
        else:
            self.pieces = [(a0[np.ix_(block, block)], a1[np.ix_(block, block)]) for block in self.blocks]

    def eigenvalues(self, speeds: np.ndarray) -> np.ndarray:
        """Every eigenvalue [1/s] at each of ``speeds`` [m/s] (shape (S,)), shape (S, N).

        Row ``i`` holds the eigenvalues at ``speeds[i]``, block after block, each block's
        in LAPACK's order (sort them for any other order).
        """
        out = np.empty((speeds.size, self.size), dtype=complex)
        column = 0
        for b0, b1 in self.pieces:
            width = b0.shape[0]
            target = out[:, column : column + width]
            if width == 1:
                target[:, 0] = b0[0, 0] + b1[0, 0] / speeds
            else:
                chunk = max(1, min(256, _STACK_BYTES // (8 * width * width)))
                for start in range(0, speeds.size, chunk):
                    part = speeds[start : start + chunk]
                    target[start : start + part.size] = np.linalg.eigvals(b0[None] + b1[None] / part[:, None, None])
            column += width
        return out
