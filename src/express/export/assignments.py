"""What the code exporters (:mod:`.matlab`, :mod:`.python_module`) share: the
assignments of a matrix's non-zero entries into a zero matrix, and the printing of each
distinct entry once.

One walk over a matrix's sparse storage gives every non-zero entry, row-major, and marks
each entry below the diagonal that equals its mirror above it, so that the exporter
copies that entry instead of printing it again (a mass, damping or stiffness matrix is
symmetric).  The cost follows the number of non-zero entries, not the matrix size.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sympy as sp

__all__ = ["Assignment", "EntryCode", "matrix_assignments"]


@dataclass(frozen=True)
class Assignment:
    """One non-zero entry of a matrix to write.

    Attributes
    ----------
    row, column : int
        0-based position.
    entry : sympy.Expr or None
        The entry, or ``None`` when it lies below the diagonal and equals the entry at
        ``(column, row)``, already written: the exporter copies that one.
    """

    row: int
    column: int
    entry: sp.Expr | None


def matrix_assignments(mat: sp.MatrixBase) -> list[Assignment]:
    """Every non-zero entry of ``mat`` as an :class:`Assignment`, sorted by row, then column.

    Examples
    --------
    >>> a, b = sp.symbols("a b")
    >>> [(x.row, x.column, x.entry) for x in matrix_assignments(sp.Matrix([[a, b], [b, 0]]))]
    [(0, 0, a), (0, 1, b), (1, 0, None)]
    """
    entries = {key: value for key, value in mat.todok().items() if value != 0}
    found = []
    for i, j in sorted(entries):
        value = entries[(i, j)]
        mirrored = j < i and entries.get((j, i)) == value
        found.append(Assignment(i, j, None if mirrored else value))
    return found


class EntryCode:
    """``expr -> code text`` through ``printer`` with the parameters renamed, each
    distinct entry printed once (a train repeats its cars' entries).

    Parameters
    ----------
    printer : sympy.printing.codeprinter.CodePrinter
        The language's printer (kept as :attr:`printer`: the Python exporter reads the
        modules it used).
    rename : dict of sympy.Symbol to sympy.Symbol
        Parameters written under a local name (``xreplace`` before printing).
    language : str
        Ends the message of an entry the printer cannot write (``"in MATLAB"``).
    """

    def __init__(self, printer: Any, rename: dict[sp.Symbol, sp.Symbol], language: str) -> None:
        self.printer = printer
        self.rename = rename
        self.language = language
        self.cache: dict[sp.Expr, str] = {}

    def __call__(self, expr: sp.Expr) -> str:
        """The code of ``expr``.

        Raises
        ------
        ValueError
            When the printer cannot write ``expr`` in its language.
        """
        text = self.cache.get(expr)
        if text is None:
            try:
                text = self.printer.doprint(expr.xreplace(self.rename) if self.rename else expr)
            except NotImplementedError as exc:
                raise ValueError(f"cannot write {sp.sstr(expr)!r} {self.language}: {exc}") from exc
            self.cache[expr] = text
        return text
