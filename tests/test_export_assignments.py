"""The assignments shared by the MATLAB and Python exporters (:mod:`express.export.assignments`)."""

from __future__ import annotations

import pytest
import sympy as sp
from sympy.printing.numpy import NumPyPrinter

from express.export.assignments import EntryCode, matrix_assignments

a, b, c = sp.symbols("a b c")


def _triples(mat):
    return [(x.row, x.column, x.entry) for x in matrix_assignments(mat)]


@pytest.mark.parametrize(
    "mat, expected",
    [
        (sp.Matrix([[a, b], [b, c]]), [(0, 0, a), (0, 1, b), (1, 0, None), (1, 1, c)]),
        (sp.Matrix([[a, b], [-b, c]]), [(0, 0, a), (0, 1, b), (1, 0, -b), (1, 1, c)]),  # not a mirror
        (sp.Matrix([[0, 0], [b, 0]]), [(1, 0, b)]),  # the mirror (0, 1) is zero: written
        (sp.ImmutableSparseMatrix(3, 3, {(2, 0): a, (0, 2): a, (1, 1): 0}), [(0, 2, a), (2, 0, None)]),
        (sp.zeros(3, 2), []),
        (sp.Matrix([[a, b, c]]), [(0, 0, a), (0, 1, b), (0, 2, c)]),  # rectangular (an input matrix)
    ],
)
def test_non_zero_entries_row_major_with_mirrors(mat, expected):
    assert _triples(mat) == expected


def test_dense_and_sparse_storage_give_the_same_assignments():
    dense = sp.Matrix(4, 4, lambda i, j: a * (i + 1) + b * (j + 1) if (i + j) % 3 == 0 else 0)
    assert matrix_assignments(dense) == matrix_assignments(sp.ImmutableSparseMatrix(dense))


def test_each_distinct_entry_is_printed_once_and_renamed():
    printer = NumPyPrinter({"strict": True, "fully_qualified_modules": True})
    code = EntryCode(printer, {a: sp.Symbol("a_")}, "with numpy")
    calls = []
    original = printer.doprint
    printer.doprint = lambda expr: calls.append(expr) or original(expr)
    assert code(a * b) == code(a * b) == "a_*b"
    assert len(calls) == 1


def test_an_entry_the_language_cannot_write_names_the_language():
    code = EntryCode(NumPyPrinter({"strict": True}), {}, "with numpy")
    with pytest.raises(ValueError, match=r"cannot write 'f\(a\)' with numpy"):
        code(sp.Function("f")(a))
