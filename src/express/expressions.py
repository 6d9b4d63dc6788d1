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

Examples
--------
>>> parse_expression("2*a - 0.3")
2*a - 3/10
>>> parse_expression("__import__('os')")
Traceback (most recent call last):
...
express.expressions.ExpressionError: column 12: unexpected character "'"
"""

from __future__ import annotations

import math
import re
from fractions import Fraction

import sympy as sp

__all__ = ["ExpressionError", "parse_expression", "parse_number", "is_valid_name"]

_TOKEN = re.compile(
    r"\s*(?:(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
    r"|(?P<op>\*\*|[-+*/^()]))"
)
_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
_MAX_LENGTH = 1000
_MAX_TERMS = 200


class ExpressionError(ValueError):
    """An expression that does not follow the grammar; the message says where."""


def is_valid_name(name: str) -> bool:
    """Whether ``name`` can be a parameter name (letter first, then letters, digits, ``_``)."""
    return bool(_NAME.match(name))


def parse_number(text: str) -> sp.Rational:
    """Parse a decimal literal exactly (``"0.3"`` -> ``3/10``, ``"1e5"`` -> ``100000``).

    Raises
    ------
    ExpressionError
        For an exponent beyond the range of a double (``1e400``).
    """
    mantissa, _, exponent = text.lower().partition("e")
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
            op = self.take()[1]
            operand = self.unary()
            return -operand if op == "-" else operand
        return self.power()

    def power(self) -> sp.Expr:
        base = self.atom()
        if self.at_op("^", "**"):
            column = self.take()[2]
            exponent = self.unary()
            if not (exponent.is_Integer and abs(int(exponent)) <= 64):
                raise ExpressionError(
                    f"column {column}: the exponent must be an integer constant"
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
            value = self.expression()
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
    if len(text) > _MAX_LENGTH:
        raise ExpressionError(f"expression longer than {_MAX_LENGTH} characters")
    if not text.strip():
        raise ExpressionError("empty value")
    parser = _Parser(text)
    value = parser.expression()
    leftover = parser.peek()
    if leftover is not None:
        raise ExpressionError(f'column {leftover[2]}: unexpected "{leftover[1]}"')
    if _expanded_terms(value) > _MAX_TERMS:
        raise ExpressionError(f"the expression expands to more than {_MAX_TERMS} terms")
    return value


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
