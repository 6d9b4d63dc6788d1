"""Straight-line programs: parameter expressions as plain data, compiled to one function.

An :class:`ExpressionProgram` is what the numerical side of EXPRESS needs of a list of
symbolic entries (the distinct non-zero entries of M, C, K, P, Pd): their common
subexpressions (:func:`sympy.cse`) written as numbered operations on *registers*::

    registers 0 .. P-1     the parameters, in the order of ``parameters``
    each operation         one more register: ("num", p, q) = the exact constant p/q,
                           ("add", a, b, ...), ("mul", a, b, ...),
                           ("pow", base, p, q) = base ** (p/q)
    outputs                the register of each expression

The program is data (integers and names, :meth:`to_data` / :meth:`from_data`, checked
strictly when read back), so it can be stored in the derivation cache
(:mod:`express.io.cache`) and read back without SymPy work and without evaluating
anything from the file: :meth:`function` writes the Python source itself, from the
checked integers, the way :func:`sympy.lambdify` does from expressions (``r5 = r0*r3``),
and :meth:`expressions` rebuilds the SymPy expressions with ``Add``/``Mul``/``Pow``.
Every path (no cache, a cold cache, a warm cache) evaluates through the same program,
so their numbers agree bit for bit.

Examples
--------
>>> import sympy as sp
>>> a, b = sp.symbols("a b")
>>> program = ExpressionProgram.from_expressions([a + b, 2 * (a + b) ** 2], ["a", "b"])
>>> program.function()(1.0, 0.5)
[1.5, 4.5]
>>> ExpressionProgram.from_data(program.to_data()).expressions()
[a + b, 2*(a + b)**2]
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # imported where used: reading and running a program needs no SymPy
    import sympy as sp

__all__ = ["ExpressionProgram", "ProgramError", "UnsupportedExpressionError", "checked_list", "checked_strings"]

#: Operations of a program: name -> number of integers after it (None: one or more).
OPERATIONS: dict[str, int | None] = {"num": 2, "add": None, "mul": None, "pow": 3}

#: Largest exponent numerator and denominator a program holds (``x**4096``, ``x**(1/64)``).
MAX_EXPONENT = (4096, 64)

#: Terms of one generated line: longer sums and products are continued on the next
#: line, left to right (the same rounding), which keeps Python's compiler out of deep
#: recursion.
_LINE_TERMS = 64


class UnsupportedExpressionError(ValueError):
    """An expression beyond ``+ * **`` of parameters and rationals (a function such as ``sin``)."""


class ProgramError(ValueError):
    """Program data that is not a valid program (a damaged or foreign cache entry)."""


@dataclass(frozen=True)
class ExpressionProgram:
    """Expressions of named parameters as a straight-line program (module docstring).

    Attributes
    ----------
    parameters : tuple of str
        Names of the arguments, in order (registers ``0 .. P-1``).
    operations : tuple of tuple
        ``(name, *integers)``, each defining the next register: ``("num", p, q)``,
        ``("add", *registers)``, ``("mul", *registers)``, ``("pow", base, p, q)``.
    outputs : tuple of int
        The register of every expression.
    """

    parameters: tuple[str, ...]
    operations: tuple[tuple[Any, ...], ...]
    outputs: tuple[int, ...]

    @classmethod
    def from_expressions(cls, expressions: Sequence[sp.Expr], parameters: Sequence[str]) -> ExpressionProgram:
        """The program of ``expressions`` (shared subexpressions once, :func:`sympy.cse`).

        Floats are taken as the exact fractions of their binary values.

        Raises
        ------
        UnsupportedExpressionError
            For a function (``sin``, ``Abs``), a symbol not in ``parameters``, a
            constant beyond the range of a double.
        """
        import sympy as sp

        exact = [_exact(sp.sympify(expression)) for expression in expressions]
        replacements, reduced = sp.cse(exact, symbols=sp.numbered_symbols("_cse")) if exact else ([], [])
        builder = _Builder(tuple(parameters))
        for symbol, value in replacements:
            builder.named[symbol] = builder.register(value)
        outputs = tuple(builder.register(value) for value in reduced)
        return cls(builder.parameters, tuple(builder.operations), outputs)

    def to_data(self) -> dict[str, Any]:
        """The program as JSON-ready data (lists of integers and names)."""
        return {
            "parameters": list(self.parameters),
            "operations": [list(operation) for operation in self.operations],
            "outputs": list(self.outputs),
        }

    @classmethod
    def from_data(cls, data: Any) -> ExpressionProgram:
        """The program of :meth:`to_data`'s data, checked strictly.

        Raises
        ------
        ProgramError
            For anything but a valid program: an unknown operation, a register not yet
            defined, a non-integer, a zero denominator, a constant beyond the range of a
            double, a bad parameter name.
        """
        from express.base.names import is_valid_name

        if not isinstance(data, dict) or set(data) != {"parameters", "operations", "outputs"}:
            raise ProgramError("not a program")
        parameters = data["parameters"]
        if not isinstance(parameters, list) or not all(isinstance(n, str) and is_valid_name(n) for n in parameters):
            raise ProgramError("bad parameter names")
        defined = len(parameters)
        operations = []
        for item in checked_list(data["operations"]):
            operations.append(_checked_operation(item, defined))
            defined += 1
        outputs = checked_list(data["outputs"])
        if not all(_is_int(x) and 0 <= x < defined for x in outputs):
            raise ProgramError("bad output register")
        return cls(tuple(parameters), tuple(operations), tuple(outputs))

    @property
    def size(self) -> int:
        """Number of expressions."""
        return len(self.outputs)

    def function(self) -> Callable[..., list[float]]:
        """A Python function of the parameters (floats, positional) that returns the list of
        the expressions' values; it raises ``ZeroDivisionError`` or ``OverflowError`` as
        Python's float arithmetic does.

        The source is written here from the program's checked integers (register
        numbers, exponents, constants printed as float literals), never taken from data.
        """
        namespace: dict[str, Any] = {"math": math}
        exec(compile("\n".join(self._source_lines()), "<express program>", "exec"), namespace)  # source written here from checked integers
        return namespace["_program"]

    def _source_lines(self) -> list[str]:
        names = [f"r{i}" for i in range(len(self.parameters))]
        lines = [f"def _program({', '.join(names)}):"]
        for name, *operands in self.operations:
            target = f"r{len(names)}"
            if name == "num":
                names.append(_literal(operands[0], operands[1]))
                continue
            if name == "pow":
                lines.append(f"    {target} = {_power(names[operands[0]], operands[1], operands[2])}")
            else:
                symbol = " + " if name == "add" else "*"
                terms = [names[i] for i in operands]
                lines.append(f"    {target} = {symbol.join(terms[:_LINE_TERMS])}")
                for start in range(_LINE_TERMS, len(terms), _LINE_TERMS):
                    lines.append(f"    {target} = {symbol.join([target, *terms[start:start + _LINE_TERMS]])}")
            names.append(target)
        lines.append("    return [" + ", ".join(names[i] for i in self.outputs) + "]")
        return lines

    def expressions(self) -> list[sp.Expr]:
        import sympy as sp

        """The SymPy expressions (shared subexpressions substituted back)."""
        values: list[sp.Expr] = [sp.Symbol(name) for name in self.parameters]
        for name, *operands in self.operations:
            if name == "num":
                values.append(sp.Rational(operands[0], operands[1]))
            elif name == "add":
                values.append(sp.Add(*(values[i] for i in operands)))
            elif name == "mul":
                values.append(sp.Mul(*(values[i] for i in operands)))
            else:
                values.append(sp.Pow(values[operands[0]], sp.Rational(operands[1], operands[2])))
        return [values[i] for i in self.outputs]


class _Builder:
    """Registers of a program under construction (expression -> register, memoized)."""

    def __init__(self, parameters: tuple[str, ...]):
        self.parameters = parameters
        self.index = {name: i for i, name in enumerate(parameters)}
        self.operations: list[tuple[Any, ...]] = []
        self.named: dict[sp.Symbol, int] = {}  # the symbols of sympy.cse
        self.memo: dict[sp.Expr, int] = {}

    def register(self, expression: sp.Expr) -> int:
        """The register holding ``expression`` (its operations appended as needed)."""
        found = self.memo.get(expression)
        if found is None:
            found = self._new(expression)
            self.memo[expression] = found
        return found

    def _new(self, expression: sp.Expr) -> int:
        if expression.is_Symbol:
            if expression in self.named:
                return self.named[expression]
            if expression.name not in self.index:
                raise UnsupportedExpressionError(f"{expression.name} is not a parameter")
            return self.index[expression.name]
        if expression.is_Rational:
            _check_constant(int(expression.p), int(expression.q), UnsupportedExpressionError)
            return self._append(("num", int(expression.p), int(expression.q)))
        if expression.is_Add or expression.is_Mul:
            operands = [self.register(argument) for argument in expression.args]
            return self._append(("add" if expression.is_Add else "mul", *operands))
        if expression.is_Pow and expression.exp.is_Rational:
            exponent = expression.exp
            if abs(exponent.p) > MAX_EXPONENT[0] or exponent.q > MAX_EXPONENT[1]:
                raise UnsupportedExpressionError(f"exponent {exponent} beyond {MAX_EXPONENT}")
            return self._append(("pow", self.register(expression.base), int(exponent.p), int(exponent.q)))
        raise UnsupportedExpressionError(f"cannot compile {type(expression).__name__} ({expression})")

    def _append(self, operation: tuple[Any, ...]) -> int:
        self.operations.append(operation)
        return len(self.parameters) + len(self.operations) - 1


def _exact(expression: sp.Expr) -> sp.Expr:
    """Floats as exact fractions (a printed float would be rounded to 15 digits)."""
    import sympy as sp

    floats = expression.atoms(sp.Float)
    return expression.xreplace({f: sp.Rational(f) for f in floats}) if floats else expression


def _is_int(value: Any) -> bool:
    return type(value) is int



def _check_constant(p: int, q: int, error: type[ValueError]) -> None:
    """A constant must be a finite double: ``p/q`` within about 1.8e308."""
    if q <= 0:
        raise error("a constant with a zero or negative denominator")
    if p and not abs(Fraction(p, q)) <= Fraction(1.7976931348623157e308):
        raise error("a constant beyond the range of a double")


def _checked_operation(item: Any, defined: int) -> tuple[Any, ...]:
    if not isinstance(item, list) or not item or item[0] not in OPERATIONS:
        raise ProgramError("unknown operation")
    name, operands = item[0], item[1:]
    expected = OPERATIONS[name]
    if not all(_is_int(x) for x in operands) or (len(operands) != expected if expected else not operands):
        raise ProgramError(f"bad {name} operation")
    if name == "num":
        _check_constant(operands[0], operands[1], ProgramError)
    elif name == "pow":
        if not (0 <= operands[0] < defined and 0 < operands[2] <= MAX_EXPONENT[1] and abs(operands[1]) <= MAX_EXPONENT[0]):
            raise ProgramError("bad pow operation")
    elif not all(0 <= x < defined for x in operands):
        raise ProgramError(f"bad {name} operation")
    return (name, *operands)


def _literal(p: int, q: int) -> str:
    """The float literal of ``p/q`` (rounded once, as ``p/q`` in Python)."""
    text = repr(p / q)
    return f"({text})" if text.startswith("-") else text


def _power(base: str, p: int, q: int) -> str:
    if q == 1:
        return f"{base}**{p}" if p >= 0 else f"{base}**({p})"
    if (p, q) == (1, 2):
        return f"math.sqrt({base})"
    return f"{base}**({_literal(p, q)})"


def checked_list(value: Any) -> list:
    """``value`` if it is a list (cache data read back), else :class:`ProgramError`."""
    if not isinstance(value, list):
        raise ProgramError("expected a list")
    return value


def checked_strings(value: Any) -> list[str]:
    """``value`` if it is a list of texts (cache data read back), else :class:`ProgramError`."""
    if not (isinstance(value, list) and all(isinstance(item, str) for item in value)):
        raise ProgramError("expected a list of texts")
    return value
