"""Tests of the restricted expression grammar (``express.base.expressions``).

Model-file values are numbers or arithmetic on parameter names.  They must be parsed
into *exact* SymPy expressions (``0.3`` is ``3/10``, never a float) and must never be
evaluated as code: anything outside the grammar is refused with the column where the
problem is.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from express.base.expressions import ExpressionError, is_valid_name, parse_expression, parse_number

SRC = Path(__file__).resolve().parents[1] / "src"
a, b, c = sp.symbols("a b c")


def column_of(error: ExpressionError) -> int | None:
    """The column number quoted in an error message, if any."""
    match = re.search(r"column (\d+)", str(error))
    return int(match.group(1)) if match else None


# --------------------------------------------------------------------------- numbers


@pytest.mark.parametrize(
    "text, expected",
    [
        ("0.3", sp.Rational(3, 10)),
        ("1e5", sp.Integer(100000)),
        ("1E5", sp.Integer(100000)),
        ("2.5E-3", sp.Rational(1, 400)),
        ("2.5e+3", sp.Integer(2500)),
        (".5", sp.Rational(1, 2)),
        ("1.", sp.Integer(1)),
        ("0", sp.Integer(0)),
        ("007", sp.Integer(7)),
        ("0.1", sp.Rational(1, 10)),
        ("123456789.123456789", sp.Rational(123456789123456789, 10**9)),
        ("-0.3", sp.Rational(-3, 10)),
        ("1e-20", sp.Rational(1, 10**20)),
    ],
)
def test_numbers_are_exact(text, expected):
    """Decimal literals become exact rationals: no binary floating point anywhere
    (0.1 + 0.2 must be exactly 3/10 in a generated matrix)."""
    value = parse_expression(text)
    assert value == expected
    assert not value.has(sp.Float)
    assert value.is_Rational


def test_decimal_sum_is_exact():
    """``0.1 + 0.2`` is exactly ``3/10`` (it would not be with floats)."""
    assert parse_expression("0.1 + 0.2") == sp.Rational(3, 10)


@pytest.mark.parametrize("text", ["0.3", "1e5", "2.5E-3", "17", ".25"])
def test_parse_number_matches_fraction(text):
    """``parse_number`` agrees with Python's exact ``Fraction`` parsing."""
    value = Fraction(text)
    assert parse_number(text) == sp.Rational(value.numerator, value.denominator)


# --------------------------------------------------------------------------- names


@pytest.mark.parametrize("name", ["lLU", "kLL", "J1", "a_1", "x", "Gamma", "kinf", "B2x"])
def test_names_become_symbols(name):
    """A parameter name is a plain SymPy symbol of the same (case-sensitive) name."""
    value = parse_expression(name)
    assert value == sp.Symbol(name)
    assert isinstance(value, sp.Symbol)


def test_names_are_case_sensitive():
    """``kLU`` and ``klu`` are different parameters."""
    assert parse_expression("kLU - klu") == sp.Symbol("kLU") - sp.Symbol("klu")
    assert parse_expression("kLU - klu") != 0


@pytest.mark.parametrize(
    "name, valid",
    [("a", True), ("lLU", True), ("k_1", True), ("_a", False), ("1a", False), ("a.b", False),
     ("", False), ("a b", False), ("é", False)],
)
def test_is_valid_name(name, valid):
    """Parameter names: a letter first, then letters, digits and ``_``."""
    assert is_valid_name(name) is valid


# --------------------------------------------------------------------------- structure


@pytest.mark.parametrize(
    "text, expected",
    [
        ("a + b*c", a + b * c),
        ("a*b + c", a * b + c),
        ("(a + b)*c", (a + b) * c),
        ("a - b - c", a - b - c),
        ("a - (b - c)", a - b + c),
        ("a/b/c", a / (b * c)),
        ("a/b*c", a * c / b),
        ("a/(b*c)", a / (b * c)),
        ("2*a - 0.3", 2 * a - sp.Rational(3, 10)),
        ("kLU/2", sp.Symbol("kLU") / 2),
        ("-b", -b),
        ("--a", a),
        ("+a", a),
        ("-(-a)", a),
        ("a*-b", -a * b),
        ("a - -b", a + b),
        ("-a^2", -(a**2)),
        ("-2^2", sp.Integer(-4)),
        ("(-2)^2", sp.Integer(4)),
        ("a^2", a**2),
        ("a**2", a**2),
        ("a ^ 2", a**2),
        ("a^-2", a**-2),
        ("a**-1", 1 / a),
        ("a^(2)", a**2),
        ("a^(-3)", a**-3),
        ("2^3^2", sp.Integer(512)),
        ("2*a^2", 2 * a**2),
        ("(a*b)^2", a**2 * b**2),
        ("a^2*b", a**2 * b),
        ("a^0", sp.Integer(1)),
        ("l^2", sp.Symbol("l") ** 2),
        ("  a\t+ b  ", a + b),
        ("((a))", a),
    ],
)
def test_precedence_and_associativity(text, expected):
    """Usual precedence: ``^``/``**`` over unary minus over ``* /`` over ``+ -``;
    ``-`` and ``/`` associate to the left, ``^`` to the right (as Python's ``**``)."""
    assert sp.simplify(parse_expression(text) - expected) == 0


# A reference evaluator for random expression trees: the text is built from the tree
# with full parentheses where needed, so the parser must agree with the tree.


def _tree():
    leaves = st.one_of(
        st.integers(0, 30).map(lambda n: (str(n), sp.Integer(n))),
        st.sampled_from(["a", "b", "c", "kLU", "lLL"]).map(lambda s: (s, sp.Symbol(s))),
        st.sampled_from(["0.5", "2.5", "0.25", "1e1"]).map(lambda s: (s, sp.Rational(Fraction(s)))),
    )

    def combine(children):
        def binary(op):
            def build(pair):
                (lt, lv), (rt, rv) = pair
                if op == "/" and rv == 0:
                    rv, rt = sp.Integer(1), "1"
                value = {"+": lv + rv, "-": lv - rv, "*": lv * rv, "/": lv / rv}[op]
                return f"({lt} {op} {rt})", value

            return st.tuples(children, children).map(build)

        unary = children.map(lambda t: (f"-({t[0]})", -t[1]))
        power = st.tuples(children, st.integers(-3, 3)).filter(lambda p: p[0][1] != 0 or p[1] >= 0).map(
            lambda p: (f"({p[0][0]})^{p[1]}" if p[1] >= 0 else f"({p[0][0]})^({p[1]})", p[0][1] ** p[1])
        )
        return st.one_of(binary("+"), binary("-"), binary("*"), binary("/"), unary, power)

    return st.recursive(leaves, combine, max_leaves=8)


@settings(max_examples=200, deadline=None)
@given(_tree())
def test_random_parenthesised_expressions_parse_to_their_value(pair):
    """Property: any fully parenthesised expression of numbers and names parses to
    exactly the value of the tree it was printed from."""
    text, value = pair
    assert sp.simplify(parse_expression(text) - value) == 0


@settings(max_examples=200, deadline=None)
@given(st.text(max_size=40))
def test_random_text_parses_or_is_refused(text):
    """Property: arbitrary text either parses to a SymPy expression without floats or
    raises ExpressionError -- never any other exception."""
    try:
        value = parse_expression(text)
    except ExpressionError:
        return
    assert isinstance(value, sp.Expr)
    assert not value.has(sp.Float)


@settings(max_examples=200, deadline=None)
@given(st.text(alphabet="ab12.e+-*/^() _'\"\t;:[]{}=", max_size=30))
def test_random_operator_soup_parses_or_is_refused(text):
    """Property: strings made of the grammar's own characters (plus a few others) parse
    or raise ExpressionError, nothing else."""
    try:
        parse_expression(text)
    except ExpressionError:
        pass


# --------------------------------------------------------------------------- refusals


@pytest.mark.parametrize(
    "text, columns, fragment",
    [
        ("__import__('os').system('ls')", {1, 11, 12}, ""),
        ("a(b)", {1, 2}, "function"),
        ("sin(a)", {1, 4}, ""),
        ("a;b", {2}, ";"),
        ("lambda: 0", {7}, ":"),
        ("a.b", {2}, "."),
        ("1/0", {2, 3}, "zero"),
        ("a/(b - b)", {2, 3}, "zero"),
        ("0^-1", {2, 3}, "zero"),
        ("a^b", {2, 3}, "integer"),
        ("a^0.5", {2, 3}, "integer"),
        ("a^(1/2)", {2, 3}, "integer"),
        ("a b", {3}, ""),
        ("1 2", {3}, ""),
        ("(a + b", {7}, ")"),
        ("a + b)", {6}, ")"),
        ("a +", {4}, ""),
        ("* a", {1}, ""),
        ("()", {2}, ""),
        ("_a", {1}, ""),
        ("0x10", {2}, ""),
        ("a = 1", {3}, "="),
        ("a @ b", {3}, "@"),
        ("é", {1}, ""),
        ("a, b", {2}, ","),
        ("[a]", {1}, "["),
        ("'a'", {1}, "'"),
    ],
)
def test_refusals_name_the_column(text, columns, fragment):
    """Text outside the grammar raises ExpressionError whose message gives the column
    of the offending character or token (1-based)."""
    with pytest.raises(ExpressionError) as info:
        parse_expression(text)
    assert column_of(info.value) in columns, str(info.value)
    assert fragment in str(info.value)


@pytest.mark.parametrize("text", ["", "   ", "\t"])
def test_empty_values_are_refused(text):
    """An empty value is an error, not zero."""
    with pytest.raises(ExpressionError, match="empty"):
        parse_expression(text)


def test_over_long_expression_is_refused():
    """A value longer than the limit is refused before parsing (no pathological input)."""
    text = "a+" * 600 + "a"
    with pytest.raises(ExpressionError, match="longer"):
        parse_expression(text)


def test_long_but_reasonable_expression_is_accepted():
    """A 201-character sum of names still parses."""
    text = "+".join(["a"] * 101)
    assert parse_expression(text) == 101 * a


@pytest.mark.parametrize("value", [None, 3, 0.3, b"a", ["a"]])
def test_non_text_is_refused(value):
    """Only strings are parsed; anything else is an ExpressionError, not a TypeError."""
    with pytest.raises(ExpressionError):
        parse_expression(value)


def test_code_is_never_executed(monkeypatch):
    """Parsing hostile text must not call anything: ``os.system`` is never reached."""
    calls = []
    monkeypatch.setattr(os, "system", lambda *args: calls.append(args) or 0)
    for text in ["__import__('os').system('ls')", "os.system('ls')", "exec('1')", "eval('1')"]:
        with pytest.raises(ExpressionError):
            parse_expression(text)
    assert calls == []


# --------------------------------------------------------------------------- resource use


def _parse_in_subprocess(text: str, timeout: float = 10.0) -> str:
    """Parse ``text`` in a child process; return 'ok' or 'refused', fail on a hang."""
    code = (
        "import sys\n"
        "from express.base.expressions import parse_expression, ExpressionError\n"
        "try:\n"
        "    parse_expression(sys.argv[1])\n"
        "    print('ok')\n"
        "except ExpressionError:\n"
        "    print('refused')\n"
    )
    env = dict(os.environ, PYTHONPATH=str(SRC))
    try:
        done = subprocess.run(
            [sys.executable, "-c", code, text], capture_output=True, text=True, timeout=timeout, env=env
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"parse_expression({text!r}) did not finish within {timeout} s")
    assert done.returncode == 0, done.stderr
    return done.stdout.strip()


@pytest.mark.slow
@pytest.mark.parametrize(
    "text",
    [
        "1e100000000",  # 12 characters, a 100-million-digit integer
        "((((((2^64)^64)^64)^64)^64)^64)",  # 2^(64^6): a 6.9e10-bit integer
    ],
)
def test_short_inputs_cannot_exhaust_resources(text):
    """The grammar exists so that a model file cannot make the program misbehave; a
    short value must be parsed or refused promptly, not tie up the CPU and memory
    building a gigantic exact integer."""
    assert _parse_in_subprocess(text) in ("ok", "refused")
