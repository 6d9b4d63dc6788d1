"""Parameter expressions of model files: a small, restricted grammar.

Values in a model file are numbers or arithmetic on parameter names (``lLU``, ``-b``,
``2*a``, ``kLU/2``, ``l^2``).  They are *parsed* here into exact SymPy expressions,
never evaluated as code: a decimal such as ``0.3`` becomes ``Rational(3, 10)``.

Grammar::

    expr   := term (("+" | "-") term)*
    term   := unary (("*" | "/") unary)*
    unary  := ("+" | "-") unary | power
    power  := atom (("^" | "**") unary)?      # exponent: an integer constant
    atom   := NUMBER | NAME | "(" expr ")"

The work is bounded before it is done (:mod:`express.base.limits`): an expression has at
most 1 000 characters (``EXPRESS_MAX_EXPRESSION`` raises it), nests parentheses,
signs and powers at most 100 levels deep, raises to integer powers ``|n| <= 64``,
expands to at most 200 terms, and every exact constant in it lies within the range
of a double (about 1.8e308): ``mc*(2^63)^64`` is refused at once instead of making
SymPy work for minutes with a 1 200-digit number.

Examples
--------
>>> parse_expression("2*a - 0.3")
2*a - 3/10
>>> parse_expression("__import__('os')")
Traceback (most recent call last):
...
express.base.expressions.ExpressionError: column 12: unexpected character "'"
"""

from __future__ import annotations

import math
import re
import sys
from collections.abc import Mapping
from fractions import Fraction

import sympy as sp

from express.base.limits import MAX_EXPONENT, MAX_NESTING, limit
from express.base.names import is_valid_name

__all__ = ["ExpressionError", "expression_value", "is_valid_name", "parse_expression", "parse_number"]

_TOKEN = re.compile(
    r"\s*(?:(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>\*\*|[-+*/^()]))"
)
_MAX_TERMS = 200
#: Largest finite double, exactly, and its bit length (constants must stay below it).
_DOUBLE_MAX = Fraction(sys.float_info.max)
_DOUBLE_MIN = Fraction(5e-324)  # the smallest positive (subnormal) double


class ExpressionError(ValueError):
    """An expression that does not follow the grammar; the message says where."""


def parse_number(text: str) -> sp.Rational:
    """Parse a decimal literal exactly (``"0.3"`` -> ``3/10``, ``"1e5"`` -> ``100000``).

    Raises
    ------
    ExpressionError
        For an exponent beyond the range of a double (``1e400``).
    """
    _, _, exponent = text.lower().partition("e")
    if exponent and abs(int(exponent)) > 308:
        raise ExpressionError(f'number "{text}" is out of range (exponent beyond 308)')
    value = Fraction(text)
    return sp.Rational(value.numerator, value.denominator)


def _tokenize(text: str) -> list[tuple[str, str, int]]:
    tokens = []
    position = 0
    stripped_end = len(text.rstrip())
    while position < stripped_end:
        match = _TOKEN.match(text, position)
        if match is None or match.end() == position:
            column = position + len(text[position:]) - len(text[position:].lstrip()) + 1
            raise ExpressionError(f'column {column}: unexpected character "{text[column - 1]}"')
        kind = match.lastgroup
        assert kind is not None
        tokens.append((kind, match.group(kind), match.start(kind) + 1))
        position = match.end()
    return tokens


class _Parser:
    def __init__(self, text: str):
        self.tokens = _tokenize(text)
        self.index = 0
        self.end_column = len(text.rstrip()) + 1
        self.depth = 0

    def nest(self, column: int) -> None:
        """One level deeper (a parenthesis, a sign or an exponent), refused beyond
        :data:`~express.base.limits.MAX_NESTING` before Python's own recursion limit."""
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise ExpressionError(
                f"column {column}: nested more than {MAX_NESTING} levels deep (parentheses, signs, powers)"
            )

    def peek(self) -> tuple[str, str, int] | None:
        return self.tokens[self.index] if self.index < len(self.tokens) else None

    def take(self) -> tuple[str, str, int]:
        token = self.peek()
        if token is None:
            raise ExpressionError(f"column {self.end_column}: expression ends too early")
        self.index += 1
        return token

    def at_op(self, *ops: str) -> bool:
        token = self.peek()
        return token is not None and token[0] == "op" and token[1] in ops

    def expression(self) -> sp.Expr:
        value = self.term()
        while self.at_op("+", "-"):
            op = self.take()[1]
            right = self.term()
            value = value + right if op == "+" else value - right
        return value

    def term(self) -> sp.Expr:
        value = self.unary()
        while self.at_op("*", "/"):
            op, _, column = self.take()[1], None, self.tokens[self.index - 1][2]
            right = self.unary()
            if op == "*":
                value = value * right
            else:
                if right == 0:
                    raise ExpressionError(f"column {column}: division by zero")
                value = value / right
        return value

    def unary(self) -> sp.Expr:
        if self.at_op("+", "-"):
            _, op, column = self.take()
            self.nest(column)
            operand = self.unary()
            self.depth -= 1
            return -operand if op == "-" else operand
        return self.power()

    def power(self) -> sp.Expr:
        base = self.atom()
        if self.at_op("^", "**"):
            column = self.take()[2]
            self.nest(column)
            exponent = self.unary()
            self.depth -= 1
            if not (exponent.is_Integer and abs(int(exponent)) <= MAX_EXPONENT):
                raise ExpressionError(
                    f"column {column}: the exponent must be an integer constant, at most {MAX_EXPONENT} in size"
                )
            if base == 0 and exponent < 0:
                raise ExpressionError(f"column {column}: division by zero")
            if base.is_Rational and base != 0:
                size = max(abs(base.p), abs(base.q)).bit_length() * abs(int(exponent))
                if size > 4096:
                    raise ExpressionError(f"column {column}: number too large")
            return base**exponent
        return base

    def atom(self) -> sp.Expr:
        kind, text, column = self.take()
        if kind == "number":
            return parse_number(text)
        if kind == "name":
            if text.startswith("_"):
                raise ExpressionError(f'column {column}: "{text}" is not a parameter name')
            if self.at_op("("):
                raise ExpressionError(
                    f'column {column}: "{text}(" looks like a function call; '
                    "only + - * / ^ and parentheses are allowed"
                )
            return sp.Symbol(text)
        if text == "(":
            self.nest(column)
            value = self.expression()
            self.depth -= 1
            closing = self.peek()
            if closing is None or closing[1] != ")":
                where = closing[2] if closing else self.end_column
                raise ExpressionError(f'column {where}: expected ")"')
            self.take()
            return value
        raise ExpressionError(f'column {column}: unexpected "{text}"')


def parse_expression(text: str) -> sp.Expr:
    """Parse a model-file value into an exact SymPy expression.

    Parameters
    ----------
    text : str
        A number or an arithmetic expression of parameter names.

    Returns
    -------
    sympy.Expr
        Exact expression; decimals become rationals.

    Raises
    ------
    ExpressionError
        If the text does not follow the grammar (the message gives the column).
    """
    if not isinstance(text, str):
        raise ExpressionError(f"expected text, got {type(text).__name__}")
    longest = limit("expression")
    if len(text) > longest:
        raise ExpressionError(
            f"expression of {len(text)} characters, longer than the limit of {longest} "
            "(raise it with the environment variable EXPRESS_MAX_EXPRESSION)"
        )
    if not text.strip():
        raise ExpressionError("empty value")
    parser = _Parser(text)
    value = parser.expression()
    leftover = parser.peek()
    if leftover is not None:
        raise ExpressionError(f'column {leftover[2]}: unexpected "{leftover[1]}"')
    if _expanded_terms(value) > _MAX_TERMS:
        raise ExpressionError(f"the expression expands to more than {_MAX_TERMS} terms")
    for constant in value.atoms(sp.Rational):
        _check_constant(constant)
    return value


def _check_constant(constant: sp.Rational) -> None:
    """Refuse an exact constant outside the range of a double (``2^4032``, ``1e-400``):
    no physical value needs one, and SymPy's work with it grows with its digits."""
    p, q = abs(int(constant.p)), int(constant.q)
    if p == 0:
        return
    exponent = (p.bit_length() - q.bit_length()) * math.log10(2)  # within 0.31 of log10(p/q)
    if abs(exponent) < 300 and max(p.bit_length(), q.bit_length()) > 1100:  # some 330 digits
        raise ExpressionError(f"a constant with {len(str(p)) + len(str(q))} digits is beyond the precision of a double")
    if abs(exponent) > 330 or not _DOUBLE_MIN <= Fraction(p, q) <= _DOUBLE_MAX:
        raise ExpressionError(
            f"a constant of about 1e{exponent:+.0f} is beyond the range of a double (5e-324 to 1.8e308)"
        )


def _expanded_terms(expression: sp.Expr) -> int:
    """An upper bound of the number of terms of ``expression`` once expanded."""
    if expression.is_Add:
        return sum(_expanded_terms(arg) for arg in expression.args)
    if expression.is_Mul:
        total = 1
        for arg in expression.args:
            total *= _expanded_terms(arg)
            if total > _MAX_TERMS:
                return total
        return total
    if expression.is_Pow and expression.exp.is_Integer:
        terms = _expanded_terms(expression.base)
        power = abs(int(expression.exp))
        if terms > 1:
            return math.comb(power + terms - 1, terms - 1)
        return 1
    return 1


def expression_value(expression, values: Mapping[str, float]) -> float:
    """Value of a parameter expression at ``values`` (SI floats by name).

    The one numerical evaluator of parameter expressions: a walk over the parsed
    expression with float arithmetic (no code is generated or evaluated).

    Raises
    ------
    KeyError
        Naming a parameter that has no value.
    ValueError
        If the result is not a finite number (division by zero, overflow).

    Examples
    --------
    >>> expression_value(parse_expression("(mc + 2*mt)*g/8"), {"mc": 30000.0, "mt": 2600.0, "g": 9.81})
    43164.0
    """
    try:
        result = _float(expression, values)
    except (ZeroDivisionError, OverflowError):
        result = math.inf
    if not math.isfinite(result):
        raise ValueError(f"{sp.sstr(expression)} does not give a finite number (division by zero or overflow)")
    return result


def _float(expression, values: Mapping[str, float]) -> float:
    if isinstance(expression, (int, float)):
        return float(expression)
    if expression.is_Symbol:
        return float(values[expression.name])
    if expression.is_Number:
        return float(expression)
    if expression.is_Add:
        return sum((_float(term, values) for term in expression.args), 0.0)
    if expression.is_Mul:
        product = 1.0
        for factor in expression.args:
            product *= _float(factor, values)
        return product
    if expression.is_Pow:
        base = _float(expression.base, values)
        exponent = expression.exp
        if exponent.is_Integer:
            return float(base ** int(exponent))
        return float(base ** _float(exponent, values))
    raise ValueError(f"cannot evaluate {sp.sstr(expression)}")
