"""JSON export: the machine-readable contract, and the matrix checks every exporter shares.

This module owns

* :func:`to_json`, the JSON document described in ``conventions.md`` (the contract that
  outside tools read);
* :func:`matrix_items`, the canonical order of the matrices of an
  :class:`~express.equations.EquationsOfMotion` and the check of their shapes, used by
  every exporter so that all formats list the same matrices in the same order;
* :func:`parameter_symbols`, the check that every symbol in the matrices is a declared
  parameter.

The document is, key by key and in this order::

    dofs, eliminated, parameters, M, C, K,
    inputs, P, Pd          (only when the model has inputs)
    <further matrices>     (sorted by name)
    values, units          (always present, possibly empty)

Matrix entries are strings in SymPy syntax (``sympy.sstr``), row-major, rows and columns
ordered as ``dofs`` (columns of ``P``/``Pd`` as ``inputs``). A reader gets an entry back
with ``sympy.parse_expr(text, local_dict={name: sympy.Symbol(name) for name in
parameters})``; the ``local_dict`` matters for names SymPy would otherwise read as its own
objects (``E``, ``I``, ``S``, ``N``, ``gamma``, ``beta`` ...).
"""

from __future__ import annotations

import json
import math
from typing import Any

import sympy as sp

from express.equations import MATRIX_ORDER, EquationsOfMotion
from express.units import UnitError, format_quantity

__all__ = ["matrix_items", "parameter_symbols", "shown_value", "to_json"]

_SQUARE = ("M", "C", "K")
_INPUT_MATRICES = ("P", "Pd")


def matrix_items(eom: EquationsOfMotion) -> list[tuple[str, sp.ImmutableMatrix]]:
    """Return the matrices of a record in export order, after checking their shapes.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record to export.

    Returns
    -------
    list of (str, sympy.ImmutableMatrix)
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
    mats = {key: sp.ImmutableMatrix(value) for key, value in eom.matrices.items()}
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
        for sym in mat.free_symbols:
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


def _rows(mat: sp.ImmutableMatrix) -> list[list[str]]:
    return [[sp.sstr(mat[i, j]) for j in range(mat.cols)] for i in range(mat.rows)]


def to_json(eom: EquationsOfMotion) -> str:
    """Serialise equations of motion to the JSON contract of ``conventions.md``.

    Parameters
    ----------
    eom : EquationsOfMotion
        The record to export.

    Returns
    -------
    str
        A JSON document (``indent=2``, keys in the fixed order described in the module
        docstring, trailing newline). The same record always gives the same bytes.

    Raises
    ------
    ValueError
        If the matrices are inconsistent (see :func:`matrix_items`) or a value is not
        finite.
    """
    items = matrix_items(eom)
    parameter_symbols(eom, items)
    doc: dict[str, Any] = {
        "dofs": list(eom.dofs),
        "eliminated": list(eom.eliminated),
        "parameters": list(eom.parameters),
    }
    for key, mat in items:
        if key not in _SQUARE and eom.inputs and "inputs" not in doc:
            doc["inputs"] = list(eom.inputs)
        doc[key] = _rows(mat)
    if eom.inputs and "inputs" not in doc:
        doc["inputs"] = list(eom.inputs)
    doc["values"] = {name: _number(name, eom.values[name]) for name in sorted(eom.values)}
    doc["units"] = {name: str(eom.units[name]) for name in sorted(eom.units)}
    return json.dumps(doc, indent=2, ensure_ascii=False, allow_nan=False) + "\n"
