"""JSON export: the machine-readable contract, and the matrix checks every exporter shares.

This module owns

* :func:`to_json`, the JSON document described in ``docs/conventions.md`` (the contract
  that outside tools read), and :func:`dense_rows`, which gives the dense rows of a
  matrix from either form of the contract;
* :func:`matrix_items`, the canonical order of the matrices of an
  :class:`~express.assembly.equations.EquationsOfMotion` and the check of their shapes, used by
  every exporter so that all formats list the same matrices in the same order;
* :func:`matrix_entries`, the non-zero entries of a matrix in row-major order, read
  from its sparse storage: every exporter walks these, so that its cost follows the
  non-zero entries and not ``n**2``;
* :func:`parameter_symbols`, the check that every symbol in the matrices is a declared
  parameter.

The document (version 2), key by key and in this order::

    format, version        ("express-equations", 2)
    dofs, eliminated, parameters, M, C, K,
    inputs, P, Pd          (only when the model has inputs)
    <further matrices>     (sorted by name)
    values, units          (always present, possibly empty)
    given, derivation      (always present, possibly empty)

A matrix is ``{"shape": [rows, cols], "entries": [[i, j, "text"], ...]}``: its non-zero
entries only, 0-based row and column, row-major, one entry per line; rows and columns
are ordered as ``dofs`` (columns of ``P``/``Pd`` as ``inputs``). Entry texts are in
SymPy syntax (``sympy.sstr``). A reader gets an entry back with ``sympy.parse_expr(text,
local_dict={name: sympy.Symbol(name) for name in parameters})``; the ``local_dict``
matters for names SymPy would otherwise read as its own objects (``E``, ``I``, ``S``,
``N``, ``gamma``, ``beta`` ...). ``derivation`` lists how the derived parameters follow
from the ``given`` ones (:mod:`express.export.derivation`).

Version 1 (no ``format``/``version`` keys, no ``given``/``derivation``) wrote every
matrix densely, as a list of rows of strings; :func:`dense_rows` reads both.
"""

from __future__ import annotations

import json
import math
from typing import Any

import sympy as sp
from sympy.matrices.immutable import ImmutableRepMatrix

from express.assembly.equations import MATRIX_ORDER, EquationsOfMotion
from express.base.units import UnitError, format_quantity
from express.export.derivation import derivation_json, derivation_plan

__all__ = [
    "FORMAT",
    "VERSION",
    "dense_rows",
    "matrix_entries",
    "matrix_items",
    "parameter_symbols",
    "shown_value",
    "to_json",
]

#: Value of the ``format`` key of the document.
FORMAT = "express-equations"
#: Version of the document written by :func:`to_json` (1: dense rows; 2: sparse entries,
#: ``given`` and ``derivation``).
VERSION = 2

_SQUARE = ("M", "C", "K")
#: Keys of the document that are not matrices.
_DOCUMENT_KEYS = ("format", "version", "dofs", "eliminated", "parameters", "inputs", "values",
                  "units", "given", "derivation")
_INPUT_MATRICES = ("P", "Pd")


def matrix_items(eom: EquationsOfMotion) -> list[tuple[str, sp.ImmutableMatrix]]:
    """Return the matrices of a record in export order, after checking their shapes.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record to export.

    Returns
    -------
    list of (str, sympy.ImmutableMatrix or sympy.ImmutableSparseMatrix)
        ``M, C, K``, then ``P, Pd`` when the model has inputs, then any further matrices
        sorted by name. ``P``/``Pd`` with zero columns are dropped when there are no
        inputs.

    Raises
    ------
    ValueError
        If ``M``, ``C`` or ``K`` is missing or not ``n x n`` (``n = len(dofs)``), if
        ``P``/``Pd`` is not ``n x len(inputs)``, or if a further matrix's name is not a
        non-empty string.
    """
    n = len(eom.dofs)
    m = len(eom.inputs)
    mats = {
        key: value if isinstance(value, ImmutableRepMatrix) else sp.ImmutableMatrix(value)
        for key, value in eom.matrices.items()
    }
    items: list[tuple[str, sp.ImmutableMatrix]] = []
    for key in _SQUARE:
        if key not in mats:
            raise ValueError(f"model {eom.name!r}: matrix {key} is missing")
        if mats[key].shape != (n, n):
            raise ValueError(
                f"model {eom.name!r}: matrix {key} has shape {mats[key].shape}, "
                f"expected ({n}, {n}) for {n} DOFs"
            )
        items.append((key, mats[key]))
    for key in _INPUT_MATRICES:
        if key not in mats:
            continue
        if mats[key].shape != (n, m):
            raise ValueError(
                f"model {eom.name!r}: matrix {key} has shape {mats[key].shape}, "
                f"expected ({n}, {m}) for {n} DOFs and {m} inputs"
            )
        if m:
            items.append((key, mats[key]))
    extra = [key for key in mats if key not in MATRIX_ORDER]
    for key in extra:
        if not isinstance(key, str) or not key:
            raise ValueError(f"model {eom.name!r}: invalid matrix name {key!r}")
    for key in sorted(extra):
        items.append((key, mats[key]))
    return items


def matrix_entries(mat: sp.MatrixBase) -> list[tuple[int, int, sp.Expr]]:
    """The non-zero entries of a matrix, row-major, from its sparse storage.

    Parameters
    ----------
    mat : sympy.MatrixBase
        A SymPy matrix (dense or sparse; SymPy keeps both as dictionaries of keys).

    Returns
    -------
    list of (int, int, sympy.Expr)
        ``(row, column, entry)`` of every entry that is not structurally zero, sorted by
        row, then column (0-based). The cost follows the number of non-zero entries.
    """
    return sorted(
        ((i, j, value) for (i, j), value in mat.todok().items() if value != 0),
        key=lambda entry: (entry[0], entry[1]),
    )


def parameter_symbols(
    eom: EquationsOfMotion, items: list[tuple[str, sp.ImmutableMatrix]] | None = None
) -> dict[str, list[sp.Symbol]]:
    """Map each parameter name to the symbols of that name found in the matrices.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record.
    items : list of (str, sympy.ImmutableMatrix), optional
        The output of :func:`matrix_items` when already computed.

    Returns
    -------
    dict of str to list of sympy.Symbol
        For every name of ``eom.parameters`` (in that order), the symbols carrying it
        (usually one; several only if the same name was created with different
        assumptions), sorted by ``sympy.default_sort_key``.

    Raises
    ------
    ValueError
        If a matrix contains a symbol whose name is not a declared parameter.
    """
    if items is None:
        items = matrix_items(eom)
    found: dict[str, set[sp.Symbol]] = {}
    for _, mat in items:
        for value in mat.todok().values():
            for sym in value.free_symbols:
                found.setdefault(sym.name, set()).add(sym)
    unknown = sorted(set(found) - set(eom.parameters))
    if unknown:
        raise ValueError(
            f"model {eom.name!r}: symbols {', '.join(unknown)} appear in the matrices "
            "but are not listed in parameters"
        )
    return {
        name: sorted(found.get(name, ()), key=sp.default_sort_key) for name in eom.parameters
    }


def shown_value(eom: EquationsOfMotion, name: str) -> str | None:
    """A parameter's value as the headers of every export show it: in the unit the
    model file used (``"15 kN*s/m"``), never an SI number beside another unit.

    None when the parameter has no value; a bare SI number when it has no unit (or
    one that cannot be read, then marked ``SI``).
    """
    if name not in eom.values:
        return None
    value = float(eom.values[name])
    unit = str(eom.units.get(name, "")).strip()
    if not math.isfinite(value):
        return str(value)
    if not unit:
        return repr(value)
    try:
        return format_quantity(value, unit)
    except UnitError:
        return f"{value!r} SI"


def _number(name: str, value: Any) -> float:
    number = float(value)
    if not math.isfinite(number):
        raise ValueError(f"value of {name!r} is {number!r}; JSON has no non-finite numbers")
    return number


def _matrix(mat: sp.MatrixBase, cache: dict[sp.Expr, str]) -> dict[str, Any]:
    entries = []
    for i, j, value in matrix_entries(mat):
        text = cache.get(value)
        if text is None:  # repeated entries (cars of a train) are printed once
            text = cache[value] = sp.sstr(value)
        entries.append([i, j, text])
    return {"shape": [mat.rows, mat.cols], "entries": entries}


def dense_rows(matrix: Any) -> list[list[str]]:
    """The rows of a matrix of the JSON document, whatever its version.

    Parameters
    ----------
    matrix : list of list of str, or dict
        ``doc["K"]`` of a document: dense rows (version 1) or
        ``{"shape": [rows, cols], "entries": [[i, j, text], ...]}`` (version 2).

    Returns
    -------
    list of list of str
        ``rows x cols`` entry texts, ``"0"`` where the document has no entry.

    Raises
    ------
    ValueError
        If ``matrix`` is neither form, or an entry is outside the shape.
    """
    if isinstance(matrix, list):
        return [list(row) for row in matrix]
    try:
        rows, cols = (int(k) for k in matrix["shape"])
        entries = matrix["entries"]
    except (KeyError, TypeError, ValueError):
        raise ValueError("a matrix is a list of rows (version 1) or has 'shape' and 'entries'") from None
    dense = [["0"] * cols for _ in range(rows)]
    for i, j, text in entries:
        if not (0 <= i < rows and 0 <= j < cols):
            raise ValueError(f"entry ({i}, {j}) is outside the shape {rows} x {cols}")
        dense[i][j] = str(text)
    return dense


def _lines(key: str, value: Any, matrix: bool) -> list[str]:
    """``"key": value`` of the top-level object, indented as ``json.dumps(indent=2)``
    would, except that each entry of a matrix stays on one line."""
    head = f"  {json.dumps(key, ensure_ascii=False)}: "
    if matrix:
        shape = json.dumps(value["shape"])
        if not value["entries"]:
            return [head + "{", f'    "shape": {shape},', '    "entries": []', "  }"]
        entries = [
            "      " + json.dumps(entry, ensure_ascii=False, allow_nan=False) for entry in value["entries"]
        ]
        return [head + "{", f'    "shape": {shape},', '    "entries": [',
                ",\n".join(entries), "    ]", "  }"]
    text = json.dumps(value, indent=2, ensure_ascii=False, allow_nan=False)
    return [head + text.replace("\n", "\n  ")]


def to_json(eom: EquationsOfMotion) -> str:
    """Serialise equations of motion to the JSON contract of ``docs/conventions.md``.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record to export.

    Returns
    -------
    str
        A JSON document (version :data:`VERSION`; keys in the fixed order of the module
        docstring; two-space indent, each matrix entry on one line; trailing newline).
        The same record always gives the same bytes; the cost follows the number of
        non-zero entries.

    Raises
    ------
    ValueError
        If the matrices are inconsistent (see :func:`matrix_items`), a value is not
        finite, or a derivation cannot be written (see
        :func:`~express.export.derivation.derivation_plan`).
    """
    items = matrix_items(eom)
    parameter_symbols(eom, items)
    clash = sorted({key for key, _ in items} & set(_DOCUMENT_KEYS))
    if clash:
        raise ValueError(f"model {eom.name!r}: matrix name {clash[0]!r} is a key of the JSON document")
    plan = derivation_plan(eom)
    doc: dict[str, Any] = {
        "format": FORMAT,
        "version": VERSION,
        "dofs": list(eom.dofs),
        "eliminated": list(eom.eliminated),
        "parameters": list(eom.parameters),
    }
    cache: dict[sp.Expr, str] = {}
    for key, mat in items:
        if key not in _SQUARE and eom.inputs and "inputs" not in doc:
            doc["inputs"] = list(eom.inputs)
        doc[key] = _matrix(mat, cache)
    if eom.inputs and "inputs" not in doc:
        doc["inputs"] = list(eom.inputs)
    doc["values"] = {name: _number(name, eom.values[name]) for name in sorted(eom.values)}
    doc["units"] = {name: str(eom.units[name]) for name in sorted(eom.units)}
    doc["given"] = list(plan.given)
    doc["derivation"] = derivation_json(plan)
    matrices = {key for key, _ in items}
    body = ",\n".join("\n".join(_lines(key, value, key in matrices)) for key, value in doc.items())
    return "{\n" + body + "\n}\n"
