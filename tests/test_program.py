"""Straight-line programs (express.numeric.program): the same values as the expressions,
the expressions back, and data that is not a program refused."""

from __future__ import annotations

import json
import math

import pytest
import sympy as sp

from express.numeric.program import ExpressionProgram, ProgramError, UnsupportedExpressionError

a, b, c, v = sp.symbols("a b c v")
EXPRESSIONS = [
    a + b,
    2 * (a + b) ** 2 - sp.Rational(3, 10) * c,
    (a * b + c) / v,
    -a * b**3 / (c * v**2),
    sp.sqrt(a) * b,
    a ** sp.Rational(3, 2),
    sp.Integer(7),
    sp.Float(0.1) * a,  # taken as the exact fraction of the double 0.1
    sp.Add(*(sp.Symbol(f"k{i}") * a for i in range(150))),  # longer than one generated line
]
NAMES = ["a", "b", "c", "v", *(f"k{i}" for i in range(150))]
VALUES = {"a": 1.7, "b": -0.3, "c": 2.5, "v": 30.0, **{f"k{i}": 1.0 + i / 7 for i in range(150)}}


@pytest.fixture(scope="module")
def program():
    return ExpressionProgram.from_expressions(EXPRESSIONS, NAMES)


def test_values_agree_with_exact_evaluation(program):
    """Each value within 4 ulp-sized steps of the exact value of the expression
    (achieved: at most 2e-16 relative; the program rounds like any float code)."""
    got = program.function()(*(VALUES[name] for name in NAMES))
    for expression, value in zip(EXPRESSIONS, got, strict=True):
        exact = float(sp.N(expression.subs({sp.Symbol(k): sp.Float(x, 30) for k, x in VALUES.items()}), 30))
        assert math.isclose(value, exact, rel_tol=1e-15, abs_tol=1e-300), expression


def test_expressions_come_back(program):
    back = ExpressionProgram.from_data(json.loads(json.dumps(program.to_data()))).expressions()
    expected = [e.xreplace({f: sp.Rational(f) for f in e.atoms(sp.Float)}) for e in EXPRESSIONS]
    assert back == expected


def test_data_round_trip_gives_the_same_bits(program):
    again = ExpressionProgram.from_data(json.loads(json.dumps(program.to_data())))
    arguments = [VALUES[name] for name in NAMES]
    assert program.function()(*arguments) == again.function()(*arguments)


def test_shared_subexpressions_are_computed_once():
    program = ExpressionProgram.from_expressions([(a + b) * c, (a + b) * v], ["a", "b", "c", "v"])
    adds = [op for op in program.operations if op[0] == "add"]
    assert len(adds) == 1


def test_division_by_zero_raises_as_python_does():
    function = ExpressionProgram.from_expressions([a / b], ["a", "b"]).function()
    with pytest.raises(ZeroDivisionError):
        function(1.0, 0.0)


@pytest.mark.parametrize(
    "expression", [sp.sin(a), sp.Abs(a), a**b, sp.Symbol("unknown")], ids=["sin", "Abs", "symbolic power", "unknown"]
)
def test_what_a_program_cannot_hold_is_refused(expression):
    with pytest.raises(UnsupportedExpressionError):
        ExpressionProgram.from_expressions([expression], ["a", "b"])


GOOD = {"parameters": ["a"], "operations": [["num", 1, 2], ["mul", 0, 1]], "outputs": [2]}


@pytest.mark.parametrize(
    ("change", "what"),
    [
        ({"operations": [["exec", 0]]}, "unknown operation"),
        ({"operations": [["num", 1, 0]]}, "zero denominator"),
        ({"operations": [["num", 10**400, 1]]}, "beyond a double"),
        ({"operations": [["add", 5]]}, "register not yet defined"),
        ({"operations": [["add", 0.5]]}, "not an integer"),
        ({"operations": [["add", True]]}, "a boolean is not a register"),
        ({"operations": [["pow", 0, 1]]}, "pow without its denominator"),
        ({"operations": [["pow", 0, 10000, 1]]}, "huge exponent"),
        ({"operations": [["add"]]}, "empty sum"),
        ({"outputs": [9]}, "output not defined"),
        ({"parameters": ["__import__('os')"]}, "bad name"),
        ({"parameters": "a"}, "names not a list"),
        ({"extra": 1}, "foreign key"),
    ],
)
def test_bad_program_data_is_refused(change, what):
    data = {**GOOD, **change}
    with pytest.raises(ProgramError):
        ExpressionProgram.from_data(data)


def test_good_program_data_is_accepted():
    assert ExpressionProgram.from_data(GOOD).function()(3.0) == [1.5]
